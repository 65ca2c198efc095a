#!/bin/sh
# run_refine.sh - the adaptive supersampling of silhouette pixels
# (tests/bench/bench_refine.c, `make bench`): the bunny
# (fixtures/meshes/bunny.obj) and the armadillo (/work/shared/meshes/armadillo.obj,
# or $ARMADILLO) at 128^2 and 512^2, A = off, 4, 8, 16: forward, refine pass and
# shading backward per view, edge pixels, exact scratch, and the error in the
# edge pixels against A = 32. Writes Markdown to $BUILD/bench/refine.md.
# Variables: BUILD (default build), VIEWS (8), REPEATS (3).
set -e
B=${BUILD:-build}
VIEWS=${VIEWS:-8}
REPEATS=${REPEATS:-3}
ARMADILLO=${ARMADILLO:-/work/shared/meshes/armadillo.obj}
out=$B/bench
mkdir -p "$out"
make --no-print-directory BUILD="$B" "$B/bench/bench_refine" >"$out/refine-build.log" 2>&1 || { tail -n 20 "$out/refine-build.log"; exit 1; }
{
    printf '# Adaptive supersampling of silhouette pixels (raster_refine.h)\n\n'
    printf 'CPU: %s. Times: process CPU time per view, best of %s repetitions of %s views.\n' \
        "$(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -n 1)" "$REPEATS" "$VIEWS"
    printf 'forward = raster + shade + refine; errors: max over RGBA of |I - I_32| in the edge pixels (I_32: A = 32).\n\n'
    for mesh in fixtures/meshes/bunny.obj "$ARMADILLO"; do
        if [ ! -f "$mesh" ]; then echo "run_refine: $mesh is missing, skipped" >&2; continue; fi
        for res in 128 512; do
            "$B/bench/bench_refine" "$mesh" "$res" "$VIEWS" "$REPEATS"
            printf '\n'
        done
    done
} | tee "$out/refine.md"
