#!/usr/bin/env python3
"""callgraph.py - no recursion and a stack budget, from gcc's -fcallgraph-info=su.

Reads every .ci file (one per translation unit of the library), merges them
into one call graph, and (MODE "recursion", on an -O0 build whose graph still
has every call the source makes; at -O2 gcc turns tail recursion into loops)
  * fails if the graph has a cycle (direct or indirect recursion);
(MODE "stack", on the real -O2 build)
  * computes, for every public function (ls_*), the worst-case stack depth of
    any call chain it starts: its own frame plus the deepest callee chain.
    Calls through function pointers are the caller's callbacks (progress,
    I/O) and are not counted: their stack is the caller's business. The
    library's own calls through a pointer (the tasks it hands to the caller's
    parallel-for, run on the calling thread too) are named in an edges file
    (--edges FILE: lines "caller: callee ...", a static function named
    "path:name" as gcc names it) and counted; a name there that
    is not in the graph, or a caller without an indirect call, fails.
  * fails if any public function exceeds the budget, or if a frame is dynamic
    (alloca/VLA) and therefore unbounded;
  * writes the table of every public function's worst case to OUT (Markdown).
Prints "callgraph: N passed, M failed" like the test programs.
usage: callgraph.py recursion [--edges FILE] file.ci...
       callgraph.py stack BUDGET OUT.md [--edges FILE] file.ci...
"""
import re
import sys

mode = sys.argv[1]
if mode == 'stack':
    budget = int(sys.argv[2])
    out_path = sys.argv[3]
    files = sys.argv[4:]
else:
    files = sys.argv[2:]
extra = {}  # caller -> callees through a pointer (--edges)
if files[:1] == ['--edges']:
    with open(files[1]) as f:
        for line in f:
            line = line.split('#', 1)[0].strip()
            if line:
                caller, callees = line.split(': ', 1)  # a static caller is path:name
                extra.setdefault(caller.strip(), set()).update(callees.split())
    files = files[2:]

frames = {}   # function -> (bytes, kind)
edges = {}    # function -> set of callees
node_re = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
edge_re = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
for path in files:
    with open(path) as f:
        for line in f:
            m = node_re.search(line)
            if m:
                title, label = m.group(1), m.group(2)
                s = re.search(r'\\n(\d+) bytes \((\w+)', label)
                if s:
                    prev = frames.get(title, (0, 'static'))
                    frames[title] = (max(prev[0], int(s.group(1))), s.group(2))
                edges.setdefault(title, set())
                continue
            m = edge_re.search(line)
            if m:
                edges.setdefault(m.group(1), set()).add(m.group(2))

passed = failed = 0
problems = []
stale = []
for caller, callees in sorted(extra.items()):
    if caller not in edges or '__indirect_call' not in edges[caller]:
        stale.append('%s (no indirect call in the graph)' % caller)
        continue
    for c in sorted(callees):
        if c not in edges:
            stale.append('%s -> %s (no such function in the graph)' % (caller, c))
        else:
            edges[caller].add(c)
if stale:
    for s_ in stale:
        print('     edges file: ' + s_)
    print('FAIL callgraph: the edges file names what the graph does not have')
    print('callgraph: 0 passed, 1 failed')
    sys.exit(1)

# Cycle detection and longest path with an explicit stack (Tarjan would do;
# a three-colour DFS is enough to find one cycle and report it).
WHITE, GREY, BLACK = 0, 1, 2
colour = {n: WHITE for n in edges}
depth = {}
cycles = []
for root in sorted(edges):
    if colour[root] != WHITE:
        continue
    stack = [(root, iter(sorted(edges[root])))]
    colour[root] = GREY
    while stack:
        node, it = stack[-1]
        nxt = next(it, None)
        if nxt is None:
            own = frames.get(node, (0, 'static'))[0]
            deepest = 0
            for c in edges[node]:
                if c == '__indirect_call':
                    continue
                deepest = max(deepest, depth.get(c, 0))
            depth[node] = own + deepest
            colour[node] = BLACK
            stack.pop()
            continue
        if nxt not in colour:
            colour[nxt] = BLACK
            depth[nxt] = frames.get(nxt, (0, 'static'))[0]
            continue
        if colour[nxt] == GREY:
            chain = [n for n, _ in stack]
            cycles.append(chain[chain.index(nxt):] + [nxt])
            continue
        if colour[nxt] == WHITE:
            colour[nxt] = GREY
            stack.append((nxt, iter(sorted(edges[nxt]))))

if mode == 'recursion':
    for c in cycles:
        print('     recursion: ' + ' -> '.join(c))
    print('%s   callgraph_no_recursion: %d functions' % ('ok' if not cycles else 'FAIL', len(edges)))
    print('callgraph: %d passed, %d failed' % (0 if cycles else 1, 1 if cycles else 0))
    sys.exit(1 if cycles else 0)

dynamic = sorted(n for n, (b, k) in frames.items() if k != 'static' and n.startswith('ls_'))
dynamic += sorted(n for n, (b, k) in frames.items() if k not in ('static',) and not n.startswith('ls_'))
if dynamic:
    failed += 1
    problems.append('dynamic stack frames (alloca/VLA): ' + ', '.join(dynamic))
else:
    passed += 1

public = sorted(n for n in frames if n.startswith('ls_'))
over = [(n, depth.get(n, 0)) for n in public if depth.get(n, 0) > budget]
if over:
    failed += 1
    for n, d in over:
        problems.append('stack budget: %s needs %d bytes > %d' % (n, d, budget))
else:
    passed += 1

with open(out_path, 'w') as f:
    f.write('# Worst-case stack use per public function\n\n')
    f.write('gcc -O2 on the build machine, callbacks excluded; budget %d bytes.\n\n' % budget)
    f.write('| function | own frame | worst chain |\n|---|---:|---:|\n')
    for n in public:
        f.write('| %s | %d | %d |\n' % (n, frames[n][0], depth.get(n, 0)))

worst = max([depth.get(n, 0) for n in public] or [0])
for p in problems:
    print('     ' + p)
print('%s   callgraph_stack_budget: %d public functions, worst chain %d bytes (budget %d)'
      % ('ok' if not problems else 'FAIL', len(public), worst, budget))
print('callgraph: %d passed, %d failed' % (passed, failed))
sys.exit(1 if failed else 0)
