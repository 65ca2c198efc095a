#!/bin/sh
# hygiene.sh BUILD CC CXX SAN CC_IS_GCC - rules checked on the built library objects:
#   undefined symbols on an allowlist (no heap, stdio, qsort, exit, ...);
#   no writable .data/.bss (no global state);
#   every external symbol starts with ls_;
#   no recursion and a stack budget (gcc call graph);
#   every public header compiles alone, as C99 and as C++.
# Each check is first run on tests/tools/probe_bad.c, which breaks every rule:
# a check that does not fail there is itself reported as a failure.
build=$1 cc=$2 cxx=$3 san=$4 is_gcc=$5
NM=${NM:-nm}
SIZE=${SIZE:-size}
STACK_BUDGET=${STACK_BUDGET:-4096}
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | sed 's/^/     /'; fi; }

# libc functions the library may call, and the compiler's runtime helpers
# (64-bit division on 32-bit targets, soft-float on Cortex-M, ...).
ALLOW='^(memcpy|memset|memmove|sqrt|sqrtf|_GLOBAL_OFFSET_TABLE_|__stack_chk_fail|__stack_chk_guard|__aeabi_[a-z0-9_]+|__(u?(div|mod)[dst]i3|u?divmod[dst]i4|ashl[dst]i3|ashr[dst]i3|lshr[dst]i3|mul[dst]i3|(clz|ctz|popcount|parity|ffs)[dst]i2|bswap[sd]i2|(add|sub|mul|div|neg)[sdt]f3|extend[sdt]f[sdt]f2|trunc[dt]f[sd]f2|fix(uns)?[sdt]f[sdt]i|float(un)?[sdt]i[sdt]f|(eq|ne|lt|le|gt|ge|un|cmp)[sdt]f2))$'

# Undefined in some object and defined in none: what the library needs from outside.
undefined_bad() {
    $NM -g --defined-only -A "$@" 2>/dev/null | awk '{print $NF}' | sort -u > "$probe_dir/defined.txt"
    $NM -u -A "$@" 2>/dev/null | awk '{print $NF}' | sort -u | grep -vxF -f "$probe_dir/defined.txt" | grep -Ev "$ALLOW"
}
writable_bad() {
    for o in "$@"; do
        $SIZE -A "$o" | awk -v o="$o" '$1 ~ /^\.(data|bss|tdata|tbss)($|\.)/ && $1 !~ /^\.data\.rel\.ro/ && $2 > 0 {print o ": " $1 " " $2 " bytes"}'
        $NM -A "$o" | awk '$(NF-1) == "C" {print $0 " (common symbol)"}'
    done
}
prefix_bad() { $NM -g --defined-only -A "$@" | awk '{print $NF}' | grep -v '^ls_'; }

objs=$(ls "$build"/obj/src/*.o)
probe_dir="$build/hygiene-probe"
mkdir -p "$probe_dir"
if ! $cc -std=c99 -O2 -fcallgraph-info=su -c tests/tools/probe_bad.c -o "$probe_dir/probe_bad.o" 2>/dev/null; then
    $cc -std=c99 -O2 -c tests/tools/probe_bad.c -o "$probe_dir/probe_bad.o"
fi
probe="$probe_dir/probe_bad.o"

run_check() { # name, function
    name=$1 fn=$2
    if [ -z "$($fn "$probe")" ]; then bad "$name (the check does not catch tests/tools/probe_bad.c)"; return; fi
    out=$($fn $objs)
    if [ -z "$out" ]; then ok "$name"; else bad "$name" "$out"; fi
}

if [ "$san" = 1 ]; then
    echo "     (sanitizer build: object hygiene is checked in the plain builds)"
else
    run_check "hygiene_undefined_symbols_allowlisted" undefined_bad
    run_check "hygiene_no_writable_data" writable_bad
fi
run_check "hygiene_external_symbols_ls_prefixed" prefix_bad

if [ "$is_gcc" = 1 ] && [ "$san" != 1 ]; then
    # Recursion: from an -O0 compile, whose call graph keeps every call of the source.
    o0="$probe_dir/O0"
    mkdir -p "$o0"
    $cc -std=c99 -O0 -fcallgraph-info -c tests/tools/probe_bad.c -o "$o0/probe_bad.o"
    for src in src/*/*.c; do
        $cc -std=c99 -O0 -fcallgraph-info -Iinclude -I"$build/include" -c "$src" -o "$o0/lib_$(basename "$src" .c).o"
    done
    if python3 tests/tools/callgraph.py recursion "$o0/probe_bad.ci" >/dev/null 2>&1; then
        bad "callgraph_no_recursion (the check does not catch the recursion in tests/tools/probe_bad.c)"
    elif python3 tests/tools/callgraph.py recursion "$o0"/lib_*.ci > "$probe_dir/recursion.log"; then
        ok "$(sed -n 's/^ok   //p' "$probe_dir/recursion.log")"
    else
        bad "callgraph_no_recursion" "$(cat "$probe_dir/recursion.log")"
    fi
    # Every task src/ hands to ls_parallel_run is in the edges file (the
    # stack check follows only the calls it names).
    unlisted=""
    for t in $(grep -ho 'ls_parallel_run([^;]*' $(ls src/*/*.c) | sed 's/.*, *\([a-z_0-9]*\), *[^,]*$/\1/'); do
        grep -q "^[^ #]*: .*[ :]$t\b" tests/tools/task_edges.txt || unlisted="$unlisted $t"
    done
    if [ -z "$unlisted" ]; then ok "callgraph_tasks_listed"; else bad "callgraph_tasks_listed" "not in tests/tools/task_edges.txt:$unlisted"; fi
    # Stack: the -O2 frames of the real build, budget per public function
    # (first seen to fail with a budget no real function meets).
    if python3 tests/tools/callgraph.py stack 8 "$probe_dir/tiny.md" "$build"/obj/src/*.ci >/dev/null 2>&1; then
        bad "callgraph_stack_budget (the check passes an 8-byte budget)"
    elif python3 tests/tools/callgraph.py stack "$STACK_BUDGET" "$build/stack.md" --edges tests/tools/task_edges.txt "$build"/obj/src/*.ci > "$probe_dir/stack.log"; then
        ok "$(sed -n 's/^ok   //p' "$probe_dir/stack.log") -> $build/stack.md"
    else
        bad "callgraph_stack_budget" "$(cat "$probe_dir/stack.log")"
    fi
fi

# Public headers: each compiles alone as C99 and as C++ (extern "C", no C-only syntax).
herr=""
for h in include/largesteps.h include/largesteps/*.h; do
    inc=${h#include/}
    [ "$inc" = largesteps/config.h ] && continue
    if ! printf '#include <%s>\nint ls_header_probe_;\n' "$inc" | \
        $cc -x c -std=c99 -pedantic -Wall -Wextra -Werror -Wconversion -Wdouble-promotion \
            -Iinclude -I"$build/include" -fsyntax-only - 2>"$probe_dir/h.err"; then
        herr="$herr$(printf '\n%s (C): %s' "$h" "$(head -3 "$probe_dir/h.err")")"
    fi
    if ! printf '#include <%s>\nint ls_header_probe_;\n' "$inc" | \
        $cxx -x c++ -std=c++11 -pedantic -Wall -Wextra -Werror -Iinclude -I"$build/include" \
            -fsyntax-only - 2>"$probe_dir/h.err"; then
        herr="$herr$(printf '\n%s (C++): %s' "$h" "$(head -3 "$probe_dir/h.err")")"
    fi
done
if [ -z "$herr" ]; then ok "headers_compile_alone_as_c99_and_cpp"; else bad "headers_compile_alone_as_c99_and_cpp" "$herr"; fi

# The API's parameter counts (tests/tools/api_params.py), first shown a planted
# 9-parameter declaration that it must report.
plant=$build/api_params_probe.h
printf 'ls_status ls_probe(int a, int b, int c, int d, int e, int f, int g, int h, int i);\n' > "$plant"
if python3 tests/tools/api_params.py "$plant" > /dev/null 2>&1; then
    bad "api_parameter_counts (the check does not report the planted 9-parameter declaration)"
elif out=$(python3 tests/tools/api_params.py 2>&1); then
    ok "api_parameter_counts (no public function over 8 parameters, no view call over 6)"
else
    bad "api_parameter_counts" "$out"
fi

echo "hygiene: $pass passed, $fail failed"
[ "$fail" = 0 ]
