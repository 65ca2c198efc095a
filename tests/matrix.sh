#!/bin/sh
# matrix.sh - `make test`: every native build variant, static analysis and the
# install checks. Prints each stage's results and time, then one last line
# "N passed, M failed" (summed over every "name: N passed, M failed" line the
# stages print); exits non-zero on any failure. A stage that fails without
# reporting a failed test (a build error, a crash) counts as one failure.
JOBS=${JOBS:-2}
total_pass=0 total_fail=0
mkdir -p build/logs

stage() { # name, command...
    name=$1
    shift
    start=$(date +%s)
    log="build/logs/stage-$name.log"
    if "$@" > "$log" 2>&1; then rc=0; else rc=1; fi
    p=$(awk '/^[A-Za-z_0-9.-]+: [0-9]+ passed, [0-9]+ failed/ {s += $2} END {print s + 0}' "$log")
    f=$(awk '/^[A-Za-z_0-9.-]+: [0-9]+ passed, [0-9]+ failed/ {s += $4} END {print s + 0}' "$log")
    if [ "$rc" != 0 ] && [ "$f" = 0 ]; then
        f=1
        tail -n 30 "$log" | sed 's/^/  | /'
        echo "  stage $name failed before its tests reported (log: $log)"
    fi
    grep -E '^(FAIL|     )' "$log" | head -n 60 | sed 's/^/  /'
    echo "[$name] $p passed, $f failed in $(( $(date +%s) - start )) s"
    total_pass=$((total_pass + p))
    total_fail=$((total_fail + f))
}

variant() { # build dir, make variables...
    dir=$1
    shift
    make --no-print-directory -j"$JOBS" BUILD="$dir" "$@" all >/dev/null 2>"$dir.err" || { cat "$dir.err"; return 1; }
    make --no-print-directory -j"$JOBS" BUILD="$dir" "$@" check
}

stage gcc-double   variant build/gcc-double   CC=gcc   CXX=g++     REAL=double
stage gcc-float    variant build/gcc-float    CC=gcc   CXX=g++     REAL=float
# clang double is also the build with status messages compiled out (names only).
stage clang-double variant build/clang-double CC=clang CXX=clang++ REAL=double ARCHFLAGS=-DLS_NO_STATUS_STRINGS
stage asan-ubsan   variant build/asan-ubsan   CC=clang CXX=clang++ REAL=double SAN=1
stage install      sh tests/install.sh
stage lint         sh tests/lint.sh
# Stages that need more than the native compilers (OpenImageIO, QEMU, ...):
# each tests/stage_NAME.sh prints "NAME: N passed, M failed" like the others.
for script in tests/stage_*.sh; do
    [ -e "$script" ] || continue
    name=$(basename "$script" .sh)
    stage "${name#stage_}" sh "$script"
done

echo "$total_pass passed, $total_fail failed"
[ "$total_fail" = 0 ]
