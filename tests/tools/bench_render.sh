#!/bin/sh
# bench_render.sh - the rasterizer's benchmark against Mesa's llvmpipe (`make bench`).
# Visibility-only and SH-shaded rendering of the bunny (fixtures/meshes/bunny.obj)
# and the armadillo (/work/shared/meshes/armadillo.obj, or $ARMADILLO) at 128^2,
# 512^2 and 2048^2, one sample per pixel, one thread on both sides
# (LP_NUM_THREADS=0: llvmpipe rasterizes on the calling thread). Both renderers
# run in the same process on the same cameras (tests/tools/osmesa_peer.c
# --bench: 4 views on a Fibonacci sphere, best of REPEATS per view in
# process CPU time, which the machine's other jobs do not inflate). Prints the table and writes it as Markdown to
# $BUILD/bench/render.md. ratio = Mesa's time / ours (> 1: ours is faster).
# Packages: .ci/packages/raster.txt. Variables: BUILD (default build), REAL
# (default double), VIEWS (4), REPEATS (10; 3 at 2048^2).
set -e
B=${BUILD:-build}
REAL=${REAL:-double}
VIEWS=${VIEWS:-4}
REPEATS=${REPEATS:-10}
ARMADILLO=${ARMADILLO:-/work/shared/meshes/armadillo.obj}
out=$B/bench
mkdir -p "$out"
make --no-print-directory BUILD="$B" REAL="$REAL" lib >"$out/render-build.log" 2>&1 || { tail -n 20 "$out/render-build.log"; exit 1; }
make --no-print-directory BUILD="$B" REAL="$REAL" "$out/osmesa_bench" >>"$out/render-build.log" 2>&1 || { tail -n 20 "$out/render-build.log"; exit 1; }
export LP_NUM_THREADS=0
: > "$out/render-raw.txt"
for mesh in fixtures/meshes/bunny.obj "$ARMADILLO"; do
    if [ ! -f "$mesh" ]; then echo "bench_render: $mesh is missing, skipped" >&2; continue; fi
    for res in 128 512 2048; do
        reps=$REPEATS
        [ "$res" = 2048 ] && reps=3
        "$out/osmesa_bench" "$mesh" "$res" "$VIEWS" --bench "$reps" | grep '^bench ' |
            sed "s|^bench |$(basename "$mesh" .obj) |" >> "$out/render-raw.txt"
    done
done
cpu=$(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -n 1)
mesa=$(LP_NUM_THREADS=0 "$out/osmesa_bench" fixtures/meshes/bunny.obj 16 1 --bench 1 | sed -n 's/^ *renderer: //p')
awk -v cpu="$cpu" -v mesa="$mesa" -v real="$REAL" -v views="$VIEWS" '
BEGIN {
    printf "# Rasterizer benchmark: largesteps vs Mesa llvmpipe, one thread\n\n"
    printf "CPU: %s. Mesa: %s (LP_NUM_THREADS=0). largesteps: ls_real = %s, gcc -O2.\n", cpu, mesa, real
    printf "Per view (mean of %d views on a Fibonacci sphere, each the best of its repeats in process CPU time), 1 sample per pixel.\n", views
    printf "vis = visibility only (ls_raster; GL: flat triangle ids + depth test); sh = ls_raster + ls_shade(SH)\n"
    printf "(GL: GLSL SH irradiance on interpolated normals). ratio = Mesa time / largesteps time (> 1: we are faster).\n"
    printf "bytes/view = visibility buffer + largest raster scratch (+ RGBA output for sh).\n\n"
    printf "| mesh | mode | res | triangles | Mesa ms | ours ms | ratio | ours Mtri/s | ours Msamples/s | bytes/view |\n"
    printf "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
}
{
    mesh = $1; mode = $2; res = $3; tris = $4; nv = $5; gl = $6 / nv; ls = $7 / nv; bytes = $8
    printf "| %s | %s | %d^2 | %d | %.3f | %.3f | %.2f | %.2f | %.1f | %d |\n", mesh, mode, res, tris, gl, ls, gl / ls,
        tris / (ls * 1e-3) * 1e-6, res * res / (ls * 1e-3) * 1e-6, bytes
}' "$out/render-raw.txt" > "$out/render.md"
cat "$out/render.md"
echo "wrote $out/render.md"
