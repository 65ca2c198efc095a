#!/usr/bin/env python3
"""api_params.py [HEADER...] - the public API's parameter counts: no function
declared in include/largesteps/*.h takes more than 8 parameters, and a call
of one view (its first parameters a view: `const ls_view *` or
`ls_vis *, const ls_view *`) takes at most 6. Prints the offenders, one a
line, and exits 1 when there is one (tests/hygiene.sh; it first shows the
check a planted 9-parameter declaration, which it must report)."""
import glob
import re
import sys

PROTO = re.compile(r'\b(?:ls_status|void|int|ls_real|size_t|uint32_t|uint64_t|const char \*|double)\s+\**'
                   r'(ls_[a-z0-9_]+)\s*\(([^;{]*?)\)\s*;')


def offenders(text, name):
    text = re.sub(r'/\*.*?\*/', '', text, flags=re.S)
    out = []
    for m in PROTO.finditer(text):
        args = [a.strip() for a in m.group(2).split(',')]
        n = 0 if args in (['void'], ['']) else len(args)
        view = any('ls_view *' in a for a in args[:2])
        if n > 8:
            out.append('%s: %s takes %d parameters (at most 8)' % (name, m.group(1), n))
        elif view and n > 6:
            out.append('%s: %s takes a view and %d parameters (at most 6)' % (name, m.group(1), n))
    return out


def main():
    headers = sys.argv[1:] or sorted(glob.glob('include/largesteps.h') + glob.glob('include/largesteps/*.h'))
    found = []
    for h in headers:
        with open(h, encoding='utf-8') as f:
            found += offenders(f.read(), h)
    for line in found:
        print(line)
    return 1 if found else 0


if __name__ == '__main__':
    sys.exit(main())
