#!/bin/sh
# tests/bench/run_dataset.sh - fitting images another renderer made: for each
# mesh, `largesteps render --placement hemisphere` places 24 cameras over the
# upper half and a little below (their dataset only: the images are thrown
# away), Mesa's OpenGL renders the mesh through those cameras with a Lambert
# light and ambient term that the dataset does not record
# (tests/tools/osmesa_dataset.c), then `largesteps fit DIR/transforms.json`
# with its defaults fits the images alone (unknown lighting: estimated with the geometry)
# and `largesteps metrics` measures the result against the mesh, which the
# fit never saw. Writes $BUILD/bench/dataset.md and prints it. Environment:
# BUILD (default build), SHARED (../shared/meshes), DATASET_MESHES (default
# "bunny armadillo nefertiti"), RES (128), VIEWS (24).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
SHARED=${SHARED:-../shared/meshes}
OUT=$BUILD/bench/dataset
RES=${RES:-128}
VIEWS=${VIEWS:-24}
mkdir -p "$OUT"
make -s BUILD="$BUILD" all
${CC:-cc} -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Iinclude -I"$BUILD/include" -Iport/posix tests/tools/osmesa_dataset.c \
    "$BUILD/liblargesteps-posix.a" "$BUILD/liblargesteps.a" -lOSMesa -lm -o "$OUT/osmesa_dataset"
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1" | head -n 1; }
{
    echo "# Fitting images another renderer made"
    echo
    echo "$VIEWS cameras over the upper hemisphere and a little below, ${RES}², rendered by Mesa (OSMesa, Lambert +"
    echo "ambient, transparent background; the lighting not recorded), fitted by \`largesteps fit DIR/transforms.json\`"
    echo "with its defaults (unknown lighting: estimated with the geometry), measured against the mesh the fit never saw."
    echo "Measured $(date -u +%Y-%m-%d). Command: \`sh tests/bench/run_dataset.sh\`"
    echo
    echo "| mesh | H % of diagonal | RMS % | self-intersecting pairs | vertices | time s |"
    echo "|---|---:|---:|---:|---:|---:|"
    for name in ${DATASET_MESHES:-bunny armadillo nefertiti}; do
        mesh=$SHARED/$name.obj
        [ -r "$mesh" ] || mesh=fixtures/meshes/$name.obj
        if [ ! -r "$mesh" ]; then echo "| $name | not found | | | | |"; continue; fi
        d=$OUT/$name
        rm -rf "$d"
        "$BUILD/largesteps" render "$mesh" --placement hemisphere --views "$VIEWS" --res "$RES" --shading mask \
            -o "$d/cameras" > "$d.render.log" 2>&1
        "$OUT/osmesa_dataset" "$mesh" "$d/cameras/transforms.json" "$d/images" > "$d.mesa.log" 2>&1
        t0=$(date +%s.%N)
        "$BUILD/largesteps" fit "$d/images/transforms.json" --quiet -o "$d/fit" > "$d.fit.log" 2>&1 || true
        t1=$(date +%s.%N)
        "$BUILD/largesteps" metrics "$d/fit/result.obj" "$mesh" --json > "$d.metrics.json" 2>&1 || true
        h=$(field "$d.metrics.json" hausdorff_rel)
        rms=$(field "$d.metrics.json" rms_rel)
        pairs=$(field "$d/fit/metrics.json" intersecting_pairs)
        verts=$(field "$d/fit/metrics.json" vertices)
        echo "| $name | $(awk -v x="${h:-0}" 'BEGIN { printf "%.2f", 100 * x }') | $(awk -v x="${rms:-0}" 'BEGIN { printf "%.3f", 100 * x }') | ${pairs:--} | ${verts:--} | $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') |"
    done
} > "$OUT.md"
cat "$OUT.md"
