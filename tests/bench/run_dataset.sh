#!/bin/sh
# tests/bench/run_dataset.sh - fitting images another renderer made: for each
# mesh, `largesteps render --placement hemisphere` places 24 cameras over the
# upper half and a little below (their dataset only: the images are thrown
# away), Mesa's OpenGL renders the mesh through those cameras with a Lambert
# light and ambient term that the dataset does not record
# (tests/tools/osmesa_dataset.c), then `largesteps fit DIR/transforms.json`
# with its defaults fits the images alone (unknown lighting: estimated with the geometry)
# and `largesteps metrics` measures the result against the mesh, which the
# fit never saw (every fit on one thread: --threads 1, the times are one core's). Then a painted object (its colour varying: the uniform albedo
# against --albedo vertex) and the round trip through the program's own renders
# against the mesh-target fit. Writes $BUILD/bench/dataset.md and prints it. Environment:
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
# The mesh NAME: the shared copy, else the fixture's; nothing when neither is there.
mesh_of() { for m in "$SHARED/$1.obj" "fixtures/meshes/$1.obj"; do [ -r "$m" ] && echo "$m" && return; done; }
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
        mesh=$(mesh_of "$name")
        if [ -z "$mesh" ]; then echo "| $name | not found | | | | |"; continue; fi
        d=$OUT/$name
        rm -rf "$d"
        "$BUILD/largesteps" render "$mesh" --placement hemisphere --views "$VIEWS" --res "$RES" --shading mask \
            -o "$d/cameras" > "$d.render.log" 2>&1
        "$OUT/osmesa_dataset" "$mesh" "$d/cameras/transforms.json" "$d/images" > "$d.mesa.log" 2>&1
        t0=$(date +%s.%N)
        "$BUILD/largesteps" fit "$d/images/transforms.json" --threads 1 --quiet -o "$d/fit" > "$d.fit.log" 2>&1 || true
        t1=$(date +%s.%N)
        "$BUILD/largesteps" metrics "$d/fit/result.obj" "$mesh" --json > "$d.metrics.json" 2>&1 || true
        h=$(field "$d.metrics.json" hausdorff_rel)
        rms=$(field "$d.metrics.json" rms_rel)
        pairs=$(field "$d/fit/metrics.json" intersecting_pairs)
        verts=$(field "$d/fit/metrics.json" vertices)
        echo "| $name | $(awk -v x="${h:-0}" 'BEGIN { printf "%.2f", 100 * x }') | $(awk -v x="${rms:-0}" 'BEGIN { printf "%.3f", 100 * x }') | ${pairs:--} | ${verts:--} | $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') |"
    done
    echo
    echo "## A painted object: per-vertex albedo"
    echo
    echo "The same cameras, Mesa's renders with the material's colour varying over the surface (\`osmesa_dataset ... painted\`:"
    echo "bands with a phase per channel, 0.25 to 1 of the material), fitted with the uniform albedo (default) and with"
    echo "\`--albedo vertex\`."
    echo
    echo "| mesh | uniform: H % | RMS % | pairs | time s | vertex albedo: H % | RMS % | pairs | time s |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
    for name in ${DATASET_MESHES:-bunny armadillo nefertiti}; do
        mesh=$(mesh_of "$name")
        [ -n "$mesh" ] || continue
        d=$OUT/$name.painted
        rm -rf "$d"
        "$OUT/osmesa_dataset" "$mesh" "$OUT/$name/cameras/transforms.json" "$d/images" painted > "$d.mesa.log" 2>&1
        row="| $name"
        for albedo in uniform vertex; do
            t0=$(date +%s.%N)
            "$BUILD/largesteps" fit "$d/images/transforms.json" --albedo $albedo --threads 1 --quiet -o "$d/$albedo" > "$d.$albedo.log" 2>&1 || true
            t1=$(date +%s.%N)
            "$BUILD/largesteps" metrics "$d/$albedo/result.obj" "$mesh" --json > "$d.$albedo.json" 2>&1 || true
            row="$row | $(awk -v h="$(field "$d.$albedo.json" hausdorff_rel)" -v r="$(field "$d.$albedo.json" rms_rel)" \
                -v p="$(field "$d/$albedo/metrics.json" intersecting_pairs)" -v a="$t0" -v b="$t1" \
                'BEGIN { printf "%.2f | %.3f | %s | %.1f", 100 * h, 100 * r, (p == "" ? "-" : p), b - a }')"
        done
        echo "$row |"
    done
    echo
    echo "## The round trip: the program's own renders"
    echo
    echo "\`largesteps render MESH --views 32 --res $RES --ss 4\` (the fit's default cameras: 32 on a Fibonacci sphere; SH"
    echo "lighting, recorded in the dataset) fitted by \`largesteps fit DIR/transforms.json\`, against the mesh-target fit"
    echo "\`largesteps fit MESH\` (the same cameras, rendered in memory at S = 4). Ratio: the dataset's H over the mesh's."
    echo
    echo "| mesh | dataset H % | RMS % | pairs | mesh-target H % | RMS % | pairs | H ratio |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|"
    for name in ${DATASET_MESHES:-bunny armadillo nefertiti}; do
        mesh=$(mesh_of "$name")
        [ -n "$mesh" ] || continue
        d=$OUT/$name.own
        rm -rf "$d"
        "$BUILD/largesteps" render "$mesh" --views 32 --res "$RES" --ss 4 -o "$d/images" > "$d.render.log" 2>&1
        "$BUILD/largesteps" fit "$d/images/transforms.json" --threads 1 --quiet -o "$d/fit" > "$d.fit.log" 2>&1 || true
        "$BUILD/largesteps" metrics "$d/fit/result.obj" "$mesh" --json > "$d.metrics.json" 2>&1 || true
        "$BUILD/largesteps" fit "$mesh" --res "$RES" --threads 1 --quiet -o "$d/mesh" > "$d.mesh.log" 2>&1 || true
        h=$(field "$d.metrics.json" hausdorff_rel)
        rms=$(field "$d.metrics.json" rms_rel)
        pairs=$(field "$d/fit/metrics.json" intersecting_pairs)
        mh=$(field "$d/mesh/metrics.json" hausdorff_rel)
        mrms=$(field "$d/mesh/metrics.json" rms_rel)
        mpairs=$(field "$d/mesh/metrics.json" intersecting_pairs)
        awk -v n="$name" -v h="${h:-0}" -v r="${rms:-0}" -v p="${pairs:--}" -v mh="${mh:-0}" -v mr="${mrms:-0}" -v mp="${mpairs:--}" \
            'BEGIN { printf "| %s | %.2f | %.3f | %s | %.2f | %.3f | %s | %.2f |\n", n, 100 * h, 100 * r, p, 100 * mh, 100 * mr, mp, (mh > 0 ? h / mh : 0) }'
    done
} > "$OUT.md"
cat "$OUT.md"
