#!/bin/sh
# readme_blocks.sh BUILD [FILE...] - every ```c block of the given Markdown
# files (default README.md) is a whole program: each is compiled against
# BUILD's library (BUILD/liblargesteps.a, BUILD/include) with the strict
# warning set, then run; a block that fails to compile or exits non-zero
# fails. Prints ok/FAIL lines and "readme_blocks: N passed, M failed".
B=${1:?usage: readme_blocks.sh BUILD [FILE...]}
shift
[ $# -gt 0 ] || set -- README.md
CC=${CC:-gcc}
FLAGS="-std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wconversion -Wstrict-prototypes -Wmissing-prototypes -Wvla -O2 -ffp-contract=off"
D=$B/readme-blocks
rm -rf "$D"
mkdir -p "$D"
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; [ -z "$2" ] || sed -n '1,12p' "$2" | sed 's/^/     /'; }
for md in "$@"; do
    base=$(basename "$md" .md)
    # block_<file>_<N>.c for the N-th ```c block (N from 1), with its first line number
    awk -v dir="$D" -v base="$base" '
        /^```c[ \t]*$/ { n++; out = sprintf("%s/%s_%d.c", dir, base, n); printf "" > out; inblock = 1
                         print n ":" NR > (dir "/" base ".lines"); next }
        /^```/ && inblock { inblock = 0; close(out); next }
        inblock { print > out }' "$md"
    [ -e "$D/$base.lines" ] || { bad "${base}_has_c_blocks (no \`\`\`c block in $md)"; continue; }
    while IFS=: read -r n line; do
        src=$D/${base}_$n.c
        name="${base}_block_${n}_line_$line"
        # shellcheck disable=SC2086
        if ! $CC $FLAGS -I include -I "$B/include" "$src" "$B/liblargesteps.a" -lm -o "$D/${base}_$n" 2> "$D/${base}_$n.err"; then
            bad "$name (does not compile)" "$D/${base}_$n.err"
        elif ! "$D/${base}_$n" > "$D/${base}_$n.out" 2>&1; then
            bad "$name (exits with an error)" "$D/${base}_$n.out"
        else
            ok "$name"
        fi
    done < "$D/$base.lines"
done
echo "readme_blocks: $pass passed, $fail failed"
[ "$fail" = 0 ]
