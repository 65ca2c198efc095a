#!/bin/sh
# tests/bench/run_split.sh - the parameterization's solve split over two
# workers (ls_ldlt_split) against the same solve on one thread, in turn in
# the same run; both orderings. Writes build/bench/split.md and prints it.
#
# Environment: BUILD (default build), SHARED (default ../shared),
# SPLIT_MESHES (default: the elephant fixture, the bunny fixture, the
# armadillo and Nefertiti from $SHARED/meshes), SPLIT_WORKERS (2),
# SPLIT_ROUNDS (9).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
SHARED=${SHARED:-../shared}
MESHES=${SPLIT_MESHES:-"fixtures/meshes/bunny.obj fixtures/meshes/elephant.obj $SHARED/meshes/armadillo.obj $SHARED/meshes/nefertiti.obj"}
WORKERS=${SPLIT_WORKERS:-2}
ROUNDS=${SPLIT_ROUNDS:-9}
make --no-print-directory -s BUILD="$BUILD" "$OUT/bench_split"
raw=$OUT/split.raw
: > "$raw"
for m in $MESHES; do
    [ -f "$m" ] || { echo "run_split: $m not found, skipped" >&2; continue; }
    for order in amd nd; do
        "$OUT/bench_split" "$m" "$order" "$WORKERS" "$ROUNDS" >> "$raw"
    done
done
{
    echo "# The solve split over workers: x = M^{-1} u, M = I + 19 L, 3 columns"
    echo
    echo "Wall ms per solve, medians of $ROUNDS rounds of 20 solves, one thread and $WORKERS workers of the POSIX"
    echo "pool in turn; ratio = the median of the rounds' split / one. T %: the columns the calling thread"
    echo "runs, as a share of the tree's weight; most loaded %: the heaviest worker's pieces. Same bits: the"
    echo "split solve's result equals the one-thread solve's, byte for byte."
    echo "Command: sh tests/bench/run_split.sh (make bench)"
    echo
    echo "| mesh | n | ordering | nnz(L) | workers | T % | most loaded % | one ms | split ms | ratio | same bits |"
    echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|"
    cat "$raw"
} > "$OUT/split.md"
cat "$OUT/split.md"
