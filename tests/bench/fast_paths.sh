#!/bin/sh
# fast_paths.sh - what each of the silhouette pass's fast paths pays (a part of
# `make bench`): the pass with all of them (A) against the pass with one given
# up (B, -DLS_SIL_OFF=bit, src/render/silhouette_internal.h), and against the
# plain path (-DLS_FAST_PATHS=0), timed in one process by
# tests/tools/ab_silhouette.sh on the armadillo at RES (default 512) over REPS
# (default 40) paired repetitions. B/A above 1 is what the fast path saves.
# Each pair must give the same bits. Then the armadillo's gradient hash from
# bench_silhouette (512^2, 16 views) is compared with fixtures/bench-hash.txt.
# Table: $BUILD/bench/fast-paths.md.
set -e
BUILD=${BUILD:-build}
reps=${REPS:-40}
res=${RES:-512}
mkdir -p "$BUILD/bench"
table=$BUILD/bench/fast-paths.md
cc=${CC:-cc}
{
    echo "# The silhouette pass's fast paths ($(date -u +%Y-%m-%d), $($cc --version | head -n 1))"
    echo
    echo "Armadillo, ${res}², one view per repetition, $reps paired repetitions: B/A is the pass's time"
    echo "without the fast path over its time with all of them (paired median and quartiles)."
    echo
    echo "| fast path given up | B/A paired median | quartiles | same bits |"
    echo "|---|---|---|---|"
} > "$table"
status=0
for row in "1 specialized copies (always_inline, constant corner counts)" "2 cache hints (prefetch)" \
           "4 unrolling (GCC unroll 4)" "8 SSE box test" "16 SSE2 tiles and corner tests" \
           "plain all of them (LS_FAST_PATHS=0)"; do
    bit=${row%% *} what=${row#* }
    if [ "$bit" = plain ]; then flags=-DLS_FAST_PATHS=0; else flags=-DLS_SIL_OFF=$bit; fi
    line=$(AB_FLAGS_B=$flags sh tests/tools/ab_silhouette.sh src/render src/render "" "$reps" "$res" | tr '\n' ' ')
    med=$(printf '%s\n' "$line" | sed -n 's/.*paired median \([0-9.]*\).*/\1/p')
    q=$(printf '%s\n' "$line" | sed -n 's/.*(quartiles \([0-9.]*\) \([0-9.]*\)).*/\1-\2/p')
    same=no
    case $line in *"the same bits"*) same=yes ;; *) status=1 ;; esac
    echo "| $what | $med | $q | $same |" >> "$table"
    echo "$what: B/A $med ($q), same bits: $same"
done
make --no-print-directory REAL="${REAL:-double}" BUILD="$BUILD" "$BUILD/bench/bench_silhouette" > /dev/null
mesh=build/ab/armadillo.obj
got=$("$BUILD/bench/bench_silhouette" "$mesh" "$mesh" 512 16 1 | sed -n 's/.*gradient hash \([0-9a-f]*\) (\([a-z]*\)).*/\2 \1/p')
want=$(grep -v '^#' fixtures/bench-hash.txt | awk -v r="${got%% *}" '$1 == "armadillo-512-16" && $2 == r {print $2 " " $3}')
if [ -n "$got" ] && [ "$got" = "$want" ]; then
    echo "armadillo gradient hash: $got (fixtures/bench-hash.txt)"
else
    echo "FAIL armadillo gradient hash: got '$got', want '$want' (fixtures/bench-hash.txt)"
    status=1
fi
cat "$table"
exit $status
