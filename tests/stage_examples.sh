#!/bin/sh
# stage_examples.sh - the programs of examples/ and the C blocks of the README,
# as a user builds them: compiled with gcc (and clang for double) and the
# strict warning set against the gcc double and float libraries, run, and
# each example's output compared with examples/NAME.expected (double) or
# examples/NAME.float.expected (float; NAME.expected when there is none).
# The library gives the same bits everywhere, so the outputs are exact.
# Then tests/tools/readme_blocks.sh: every ```c block of README.md compiled
# and run, in both precisions. Prints "examples: N passed, M failed".
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; [ -z "$2" ] || sed -n '1,20p' "$2" | sed 's/^/     /'; }
FLAGS="-std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wconversion -Wstrict-prototypes -Wmissing-prototypes -Wvla -O2 -ffp-contract=off"
for real in double float; do
    B=${EXAMPLES_BUILD_PREFIX:-build/gcc}-$real
    if ! make --no-print-directory -j2 BUILD="$B" CC=gcc CXX=g++ REAL=$real lib > "$B.stage-examples.log" 2>&1; then
        bad "build_$B" "$B.stage-examples.log"
        continue
    fi
    D=$B/examples
    mkdir -p "$D"
    compilers=gcc
    [ $real = double ] && command -v clang > /dev/null 2>&1 && compilers="gcc clang"
    for src in examples/*.c; do
        name=$(basename "$src" .c)
        want=examples/$name.expected
        [ $real = float ] && [ -e "examples/$name.float.expected" ] && want=examples/$name.float.expected
        for cc in $compilers; do
            exe=$D/$name-$cc
            # shellcheck disable=SC2086
            if ! $cc $FLAGS -Iinclude -I"$B/include" "$src" "$B/liblargesteps.a" -lm -o "$exe" 2> "$exe.err"; then
                bad "example_${name}_${cc}_$real (does not compile)" "$exe.err"
            elif ! "$exe" > "$exe.out" 2>&1; then
                bad "example_${name}_${cc}_$real (exits with an error)" "$exe.out"
            elif ! diff -u "$want" "$exe.out" > "$exe.diff" 2>&1; then
                bad "example_${name}_${cc}_$real (output differs from $want)" "$exe.diff"
            else
                ok "example_${name}_${cc}_$real"
            fi
        done
    done
    sh tests/tools/readme_blocks.sh "$B" README.md > "$D/readme.log" 2>&1
    sed -n 's/^\(ok  \|FAIL\) /\1 /p' "$D/readme.log" | sed "s/^\(ok  \|FAIL\) \([^ ]*\)/\1 \2_$real/"
    p=$(sed -n 's/^readme_blocks: \([0-9]*\) passed, \([0-9]*\) failed$/\1/p' "$D/readme.log")
    f=$(sed -n 's/^readme_blocks: \([0-9]*\) passed, \([0-9]*\) failed$/\2/p' "$D/readme.log")
    [ -n "$p" ] || { p=0; f=1; echo "FAIL readme_blocks_$real (no summary)"; }
    pass=$((pass + p)) fail=$((fail + f))
    grep -A12 '^FAIL' "$D/readme.log" | grep '^     ' || true
done
echo "examples: $pass passed, $fail failed"
[ "$fail" = 0 ]
