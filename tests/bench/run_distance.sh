#!/bin/sh
# tests/bench/run_distance.sh - the distance-metric benchmark: BVH build time
# and bytes (armadillo, bunny), closest-point throughput and brute-force
# agreement, ls_mesh_distance (vertex-only and dense) and ls_tangle for the
# armadillo against a perturbed copy of itself; peer in the same run: CGAL's
# AABB tree on the same mesh and query points. Writes $BUILD/bench/distance.md
# and prints it.
#
# Bench-only dependency (CI does not run benchmarks): Debian libcgal-dev
# (header-only use). Without it the peer is skipped.
#
# Environment: BUILD (default build), DIST_MESH (default
# ../shared/meshes/armadillo.obj), DIST_REPEAT (3), DIST_QUERIES (100000),
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
MESH=${DIST_MESH:-../shared/meshes/armadillo.obj}
BUNNY=fixtures/meshes/bunny.obj
REPEAT=${DIST_REPEAT:-3}
QUERIES=${DIST_QUERIES:-100000}
if [ ! -f "$MESH" ]; then
    echo "run_distance: $MESH not found, skipped" >&2
    exit 0
fi
make --no-print-directory -s BUILD="$BUILD" "$OUT/bench_distance"
PEER=1
if [ -f /usr/include/CGAL/AABB_tree.h ]; then
    make --no-print-directory -s BUILD="$BUILD" "$OUT/peer_cgal_distance"
else
    echo "run_distance: CGAL missing (apt-get install libcgal-dev): peer skipped" >&2
    PEER=0
fi
raw=$OUT/distance.raw
# the armadillo against its own remesh (h = half the mean edge), with the command-line tools
make -s BUILD="$BUILD" all
"$BUILD/largesteps" remesh "$MESH" --factor 0.5 -o "$OUT/armadillo_remesh.obj" > "$OUT/remesh_for_metrics.txt"
"$BUILD/largesteps" metrics "$MESH" "$OUT/armadillo_remesh.obj" --json > "$OUT/metrics_vs_remesh.json"
"$OUT/bench_distance" "$MESH" "$BUNNY" --out "$OUT" --repeat "$REPEAT" --queries "$QUERIES" > "$raw"
if [ $PEER = 1 ]; then
    "$OUT/peer_cgal_distance" "$MESH" "$OUT" "$REPEAT" >> "$raw"
fi
{
    echo "# Distance metrics benchmark"
    echo
    echo "CPU ms, minimum of $REPEAT runs, one thread, ls_real = double (-O2). Mesh: $(basename "$MESH");"
    echo "perturbed copy: every coordinate moved by up to 0.1 % of the bounding-box diagonal (LCG);"
    echo "queries: $QUERIES face samples of the mesh moved by up to 1 % of the diagonal per coordinate."
    echo "Peer in the same run: CGAL AABB_tree (AABB_triangle_primitive, Simple_cartesian<double>,"
    echo "accelerate_distance_queries) on the same triangles and points; its memory is the growth of the"
    echo "process's peak RSS during the first build (measured, coarse). Command: sh tests/bench/run_distance.sh"
    echo
    echo "## BVH build"
    echo
    echo "| mesh | faces | nodes | depth | build ms | arena bytes (build) | tree bytes (kept) | B/face |"
    echo "|---|---|---|---|---|---|---|---|"
    awk '$1=="build" { printf "| %s | %s | %s | %s | %.2f | %s | %s | %.1f |\n", $2, $4, $6, $8, $10, $12, $14, $14/$4 }' "$raw"
    awk '$1=="cgal_build" { printf "| %s (CGAL AABB_tree + distance accel.) | %s | - | - | %.2f | %s (RSS growth) | - | %.1f |\n", "'"$(basename "$MESH")"'", $3, $5, $7, $7/$3 }' "$raw"
    echo
    echo "## Closest-point queries ($(basename "$MESH"))"
    echo
    echo "| implementation | queries | ms | queries/s | sum of distances |"
    echo "|---|---|---|---|---|"
    awk '$1=="queries" { printf "| **ours** (ls_bvh_closest) | %s | %.1f | %.0f | %s |\n", $4, $6, $8, $10 }' "$raw"
    awk '$1=="cgal_queries" { printf "| CGAL closest_point_and_primitive | %s | %.1f | %.0f | %s |\n", $3, $5, $7, $9 }' "$raw"
    awk '$1=="brute" { printf "| brute force (every triangle), first %s queries | %s | %.3f per query | %.0f | - |\n", $4, $4, $8, 1000/$8 }' "$raw"
    echo
    awk '$1=="brute" { printf "Brute force vs BVH on the first %s queries: %s identical (face and squared distance, bit for bit); BVH speed-up %sx.\n", $4, $6, $12 }' "$raw"
    awk '$1=="cgal_agreement" { printf "CGAL vs ours on all %s queries: squared distance within 1e-9 relative for %s (worst %s); same face for %s (a different face at an equal distance is a tie at a shared edge or vertex, where we return the lowest face index and CGAL any).\n", $3, $5, $9, $7 }' "$raw"
    echo
    echo "## Metrics, $(basename "$MESH") vs its perturbed copy"
    echo
    echo "| metric | face samples per mesh | ms | arena bytes | H_vertex | H | mean | RMS | diag(B) |"
    echo "|---|---|---|---|---|---|---|---|---|"
    awk '$1=="metric" { printf "| **ours** ls_mesh_distance, %s | %s | %.1f | %s | %s | %s | %s | %s | %s |\n", $2, $4, $6, $8, $10, $12, $14, $16, $18 }' "$raw"
    awk '$1=="cgal_metric" { printf "| CGAL, vertices (two trees + queries) | 0 | %.1f | - | %s | - | - | - | - |\n", $4, $6 }' "$raw"
    awk '$1=="tangle" { printf "| **ours** ls_tangle (perturbed copy, reference = original) | - | %.1f | %s | %s intersecting pairs (%s faces), %s inverted, angle p1 %s, p50 %s, quality p1 %s | | | | |\n", $4, $6, $8, $10, $12, $14, $16, $18 }' "$raw"
    echo
    echo "## Metrics, $(basename "$MESH") vs its remesh (h = half its mean edge length)"
    echo
    j=$OUT/metrics_vs_remesh.json
    v=$(sed -n 's/.*"b": {"path": "[^"]*", "vertices": \([0-9]*\).*/\1/p' "$j")
    t=$(sed -n 's/.*"time_ms": {"distance": \([0-9.]*\), "tangle": \([0-9.]*\)}.*/\1 ms distances, \2 ms tangling/p' "$j")
    b=$(sed -n 's/.*"arena_bytes": \([0-9]*\).*/\1/p' "$j")
    h=$(sed -n 's/.*"vertex_hausdorff_rel": \([0-9.e+-]*\).*/\1/p' "$j")
    r=$(sed -n 's/.*"rms_rel": \([0-9.e+-]*\).*/\1/p' "$j")
    echo "Remesh: $v vertices. \`largesteps metrics\` (dense, default samples, both ways, and ls_tangle of both): $t;"
    echo "arena $b bytes; H_vertex / diag $h, RMS / diag $r (wall time of one run, from its JSON)."
    echo
    echo "Both directions are included in every metric time (two BVH builds, then vertex and face samples"
    echo "of A against B and of B against A). H_vertex is libigl's igl::hausdorff (vertex-sampled, symmetric);"
    echo "mean and RMS are over the face samples (the vertex row: over the vertices), averaged over both directions."
} > "$OUT/distance.md"
cat "$OUT/distance.md"
