#!/bin/sh
# tests/bench/run_fan.sh - the distance and tangle metrics on overlapping
# boxes (the cases where a box-pruned search slows down): `largesteps metrics` on a planar triangle
# fan against itself (N vertices: a centre and N - 1 rim points on a circle)
# and on one vertex with F degenerate faces, at growing sizes; for the fans
# also the number of triangles whose axis-aligned box holds a query within
# the rounding slack (what a search pruned by those boxes alone evaluates)
# and the query time with the oriented boxes and without
# (tests/bench/fan_bound.c). Writes $BUILD/bench/fan.md and prints it.
# Environment: BUILD (default build), FAN_SIZES (default "5000 20000
# 100000"), DEGEN_SIZES (default "10000 100000 1000000").
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
make -s BUILD="$BUILD" all
${CC:-cc} -O2 -std=c99 -Iinclude -I"$BUILD/include" -Iport/posix tests/bench/fan_bound.c "$BUILD/liblargesteps-posix.a" \
    "$BUILD/liblargesteps.a" -lm -o "$OUT/fan_bound"
fan() { # N -> OBJ on stdout
    awk -v n="$1" 'BEGIN { m = n - 1; print "v 0 0 0"; pi = atan2(0, -1)
        for (i = 0; i < m; i++) printf "v %.17g %.17g 0\n", cos(2 * pi * i / m), sin(2 * pi * i / m)
        for (i = 0; i < m - 1; i++) printf "f 1 %d %d\n", i + 2, i + 3; printf "f 1 %d 2\n", m + 1 }'
}
ms() { sed -n 's/^time: distances \([0-9.]*\) ms, tangle \([0-9.]*\) ms.*/\1 \2/p' "$1"; }
{
    echo "# Metrics on overlapping boxes"
    echo
    echo "\`largesteps metrics A A\` wall time (ms) split as the program prints it; one thread; $(date -u +%Y-%m-%d)."
    echo "Command: sh tests/bench/run_fan.sh"
    echo
    echo "| input | faces | distances (ms) | tangle (ms) | axis-aligned boxes holding a query | us per query | us per query, axis-aligned boxes alone |"
    echo "|---|---|---|---|---|---|---|"
    for n in ${FAN_SIZES:-5000 20000 100000}; do
        fan "$n" > "$OUT/fan_$n.obj"
        "$BUILD/largesteps" metrics "$OUT/fan_$n.obj" "$OUT/fan_$n.obj" > "$OUT/fan_$n.txt"
        "$OUT/fan_bound" "$OUT/fan_$n.obj" 5000 > "$OUT/fan_$n.bound"
        set -- $(ms "$OUT/fan_$n.txt")
        echo "| fan, $n vertices | $((n - 1)) | $1 | $2 | $(sed -n 's/^boxes_within_slack_per_query //p' "$OUT/fan_$n.bound") | $(sed -n 's/^us_per_query //p' "$OUT/fan_$n.bound") | $(sed -n 's/^us_per_query_axis_aligned //p' "$OUT/fan_$n.bound") |"
    done
    for f in ${DEGEN_SIZES:-10000 100000 1000000}; do
        awk -v f="$f" 'BEGIN { print "v 0 0 0"; for (i = 0; i < f; i++) print "f 1 1 1" }' > "$OUT/degen_$f.obj"
        "$BUILD/largesteps" metrics "$OUT/degen_$f.obj" "$OUT/degen_$f.obj" > "$OUT/degen_$f.txt"
        set -- $(ms "$OUT/degen_$f.txt")
        echo "| one vertex, degenerate faces | $f | $1 | $2 | - | - | - |"
    done
} > "$OUT/fan.md"
cat "$OUT/fan.md"
