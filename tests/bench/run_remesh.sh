#!/bin/sh
# tests/bench/run_remesh.sh - the remeshing benchmark: ls_remesh against
# CGAL's isotropic remeshing (the peer, measured in the same run) at
# h = FACTOR x mean edge (0.5: the Large Steps rule), 5 iterations, one
# thread, CPU time, minimum of REPEAT runs. Writes build/bench/remesh.md and
# prints it.
#
# Bench-only dependency (CI does not run benchmarks): Debian
#   apt-get install --no-install-recommends libcgal-dev   (header-only; links gmp, mpfr)
#
# Environment: BUILD (default build), REMESH_MESHES (default below),
# REMESH_FACTORS (0.5), REMESH_REPEAT (3).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
REPEAT=${REMESH_REPEAT:-3}
FACTORS=${REMESH_FACTORS:-0.5}
MESHES=${REMESH_MESHES:-"fixtures/meshes/bunny.obj fixtures/meshes/elephant.obj ../shared/meshes/armadillo.obj"}
make --no-print-directory -s BUILD="$BUILD" "$OUT/bench_remesh"
PEER=1
if [ -f /usr/include/CGAL/Polygon_mesh_processing/remesh.h ]; then
    make --no-print-directory -s BUILD="$BUILD" "$OUT/cgal_remesh"
else
    echo "run_remesh: CGAL missing (apt-get install libcgal-dev): peer skipped" >&2
    PEER=0
fi
raw=$OUT/remesh.raw
: > "$raw"
for m in $MESHES; do
    [ -f "$m" ] || { echo "run_remesh: $m not found, skipped" >&2; continue; }
    for fac in $FACTORS; do
        printf '%s ' "$fac" >> "$raw"
        "$OUT/bench_remesh" "$m" "$fac" "$REPEAT" >> "$raw"
        if [ $PEER = 1 ]; then
            printf '%s ' "$fac" >> "$raw"
            "$OUT/cgal_remesh" "$m" "$fac" 5 "$REPEAT" >> "$raw"
        fi
    done
done
{
    echo "# Remeshing benchmark: isotropic remeshing, 5 iterations, h = factor x mean edge"
    echo
    echo "CPU ms (clock(), one thread), minimum of $REPEAT runs. Edge statistics over"
    echo "the 3 edges of every face: mean / h and the fraction in [4/5 h, 4/3 h]. Angles: corner angles in degrees"
    echo "(min, 1st and 5th percentile, median). Hausdorff: vertex-sampled, both directions (libigl's hausdorff), / h."
    echo "bytes: arena high-water mark of ls_remesh / its bound (ls_remesh_bytes_bound). CGAL:"
    echo "Polygon_mesh_processing::isotropic_remeshing (CGAL $(dpkg-query -W -f '${Version}' libcgal-dev 2>/dev/null || echo '?'))"
    echo "with default parameters (no feature protection; ours keeps input vertices sharper than 90 degrees)."
    echo "Command: sh tests/bench/run_remesh.sh"
    echo
    echo "| mesh | factor | remesher | V in | V out | F out | ms | mean/h | in range | min angle | 1 % | 5 % | median | Hausdorff/h | bytes used | bytes bound |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    awk '{ printf "| %s | %s | %s | %s | %s | %s | %.1f | %.3f | %.1f %% | %.1f | %.1f | %.1f | %.1f | %.3f | %s | %s |\n", $3, $1, ($2 == "ours" ? "**ours**" : "CGAL"), $4, $5, $6, $7, $8, 100 * $9, $10, $11, $12, $13, $14, ($2 == "ours" ? $15 : "-"), ($2 == "ours" ? $16 : "-") }' "$raw"
    echo
    echo "| mesh | factor | time ours/CGAL |"
    echo "|---|---|---|"
    awk '$2 == "ours" { t[$3 " " $1] = $7; k[++n] = $3 " " $1 } $2 == "cgal" { c[$3 " " $1] = $7 }
         END { for (i = 1; i <= n; i++) if (k[i] in c) { split(k[i], p, " "); printf "| %s | %s | %.3f |\n", p[1], p[2], t[k[i]] / c[k[i]] } }' "$raw"
} > "$OUT/remesh.md"
cat "$OUT/remesh.md"
