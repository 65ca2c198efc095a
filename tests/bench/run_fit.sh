#!/bin/sh
# tests/bench/run_fit.sh - time per iteration of the reconstruction against
# the vertex count, with the stage breakdown: the embedded bunny as
# the target, 16 views at 128 x 128, large steps (lambda 19, LDL^T), no
# remeshing, from icospheres of level 3 to 6 (642 to 40962 vertices), 20
# iterations each (one thread). Writes $BUILD/bench/fit.md and prints it.
#
# Environment: BUILD (default build), FIT_ITERS (20), FIT_RES (128), FIT_VIEWS (16).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
ITERS=${FIT_ITERS:-20}
RES=${FIT_RES:-128}
VIEWS=${FIT_VIEWS:-16}
mkdir -p "$OUT"
make -s BUILD="$BUILD" all
{
    echo "# Reconstruction: time per iteration against vertex count"
    echo
    echo "Embedded bunny target, $VIEWS views at ${RES}x$RES, large steps (lambda 19, LDL^T), $ITERS iterations,"
    echo "no remeshing, one thread, wall time (ms per iteration, mean over the iterations)."
    echo "Command: sh tests/bench/run_fit.sh"
    echo
    echo "| vertices | total | render | shading backward | silhouettes | solves | optimizer | fit bytes |"
    echo "|---|---|---|---|---|---|---|---|"
    for level in 3 4 5 6; do
        "$BUILD/largesteps" fit --level $level --iters "$ITERS" --res "$RES" --views "$VIEWS" --remesh none \
            --alpha 0.95 --threads 1 --quiet -o "$OUT/fit_level$level" > "$OUT/fit_level$level.txt"
        j=$OUT/fit_level$level/metrics.json
        v=$(sed -n 's/.*"vertices": \([0-9]*\).*/\1/p' "$j" | head -n 1)
        b=$(sed -n 's/.*"fit_bytes": \([0-9]*\).*/\1/p' "$j")
        sed -n 's/.*"ms_per_iteration": {"total": \([0-9.]*\), "render": \([0-9.]*\), "shading_backward": \([0-9.]*\), "silhouettes": \([0-9.]*\), "solves": \([0-9.]*\), "optimizer": \([0-9.]*\)}.*/\1 \2 \3 \4 \5 \6/p' "$j" |
            awk -v v="$v" -v b="$b" '{ printf "| %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f | %s |\n", v, $1, $2, $3, $4, $5, $6, b }'
    done
} > "$OUT/fit.md"
cat "$OUT/fit.md"
