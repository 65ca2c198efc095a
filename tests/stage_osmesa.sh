#!/bin/sh
# stage_osmesa.sh - the rasterizer against a real OpenGL (a stage of `make test`):
# Mesa's software OpenGL (OSMesa) renders the same meshes (bunny, elephant, and
# the armadillo from /work/shared/meshes when present) from the same cameras
# (gluLookAt + gluPerspective) as largesteps (ls_camera_* + ls_raster), at 512^2,
# 8 views on a Fibonacci sphere. Per view (tests/tools/osmesa_peer.c): the
# clip matrices agree with GLU's (within 1e-5 of the size of the terms: Mesa
# keeps matrices in float), the silhouettes have IoU >= 0.999 with
# differences only on silhouette pixels, the same triangle is seen on >= 99%
# of the pixels both cover, and depth agrees within 5e-5 (window units).
# Then a timing smoke test per resolution (one thread each: LP_NUM_THREADS=0;
# `make bench` runs the full benchmark, tests/tools/bench_render.sh).
# Packages: .ci/packages/raster.txt.
jobs=${JOBS:-2}
build=build/osmesa
pass=0 fail=0
mkdir -p build/logs "$build"
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
if ! make --no-print-directory -j"$jobs" BUILD="$build" CC=gcc REAL=double lib > build/logs/osmesa-build.log 2>&1; then
    tail -n 20 build/logs/osmesa-build.log
    bad "osmesa_build_library"
    echo "osmesa: $pass passed, $fail failed"
    exit 1
fi
if ! gcc -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Werror -Iinclude -I"$build/include" \
        tests/tools/osmesa_peer.c "$build/liblargesteps.a" -lOSMesa -lGLU -lm -o "$build/osmesa_peer" \
        > build/logs/osmesa-peer-build.log 2>&1; then
    cat build/logs/osmesa-peer-build.log
    bad "osmesa_build_peer (needs libosmesa6-dev and libglu1-mesa-dev)"
    echo "osmesa: $pass passed, $fail failed"
    exit 1
fi
export LP_NUM_THREADS=0
run() { # label, args...
    label=$1
    shift
    out=$("$build/osmesa_peer" "$@" 2>&1)
    printf '%s\n' "$out" | grep -v '^osmesa: ' | sed "s/^\(ok  \|FAIL\) /\1 ${label}_/"
    p=$(printf '%s\n' "$out" | sed -n 's/^osmesa: \([0-9]*\) passed, \([0-9]*\) failed$/\1/p')
    f=$(printf '%s\n' "$out" | sed -n 's/^osmesa: \([0-9]*\) passed, \([0-9]*\) failed$/\2/p')
    if [ -z "$p" ]; then
        bad "${label} (the peer crashed or printed no summary)"
        return
    fi
    pass=$((pass + p))
    fail=$((fail + f))
}
run bunny fixtures/meshes/bunny.obj 512 8
run elephant fixtures/meshes/elephant.obj 512 8
# the armadillo (52000 triangles) when the shared mesh directory is there
# (it is not copied into fixtures/: 1.6 MB)
armadillo=${ARMADILLO:-/work/shared/meshes/armadillo.obj}
if [ -f "$armadillo" ]; then run armadillo "$armadillo" 512 8
else echo "     armadillo: $armadillo not found, not compared"; fi
# timing smoke test (the full benchmark with the armadillo is `make bench`:
# tests/tools/bench_render.sh): both renderers, visibility and SH-shaded
for res in 128 512; do
    out=$("$build/osmesa_peer" fixtures/meshes/bunny.obj "$res" 2 --bench 3 2>&1)
    if printf '%s\n' "$out" | grep -q '^bench sh '; then
        pass=$((pass + 1))
        echo "ok   bench_bunny_$res"
        printf '%s\n' "$out" | awk '/^bench / { printf "     bench %s %s^2: Mesa %.3f ms, largesteps %.3f ms per view (ratio %.2f)\n", $2, $3, $6 / $5, $7 / $5, $6 / $7 }'
    else
        bad "bench_bunny_$res" ; printf '%s\n' "$out" | tail -n 5
    fi
done
echo "osmesa: $pass passed, $fail failed"
[ "$fail" = 0 ]
