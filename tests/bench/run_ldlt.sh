#!/bin/sh
# tests/bench/run_ldlt.sh - the solver benchmark: our LDL^T against CHOLMOD on
# M = I + lambda L (uniform Laplacian, lambda = 19), one thread, CPU time,
# minimum of REPEAT runs. Writes build/bench/ldlt.md and prints it.
#
# Bench-only dependencies (CI does not run benchmarks): Debian (CHOLMOD, Eigen)
#   apt-get install --no-install-recommends libsuitesparse-dev libeigen3-dev
# CHOLMOD runs with Debian's reference BLAS (libblas3) and OMP_NUM_THREADS=1.
#
# Environment: BUILD (default build), LDLT_MESHES (default below; add ico:8
# and grid:800x800 for the 655k / 640k cases, minutes each), LDLT_REPEAT (3),
# LDLT_LAMBDA (19).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
LAMBDA=${LDLT_LAMBDA:-19}
REPEAT=${LDLT_REPEAT:-3}
MESHES=${LDLT_MESHES:-"obj:../shared/meshes/bunny.obj ico:4 ico:5 ico:6 ico:7 grid:400x400"}
make --no-print-directory -s BUILD="$BUILD" "$OUT/bench_ldlt"
PEER=1
if [ -f /usr/include/suitesparse/cholmod.h ]; then
    make --no-print-directory -s BUILD="$BUILD" "$OUT/peer_cholmod"
else
    echo "run_ldlt: CHOLMOD missing (apt-get install libsuitesparse-dev): peers skipped" >&2
    PEER=0
fi
EIGEN=1
if [ -f /usr/include/eigen3/Eigen/SparseCholesky ]; then
    make --no-print-directory -s BUILD="$BUILD" "$OUT/peer_eigen"
else
    echo "run_ldlt: Eigen missing (apt-get install libeigen3-dev): Eigen peer skipped" >&2
    EIGEN=0
fi
export OMP_NUM_THREADS=1
raw=$OUT/ldlt.raw
: > "$raw"
for m in $MESHES; do
    case $m in obj:*) [ -f "${m#obj:}" ] || { echo "run_ldlt: ${m#obj:} not found, skipped" >&2; continue; } ;; esac
    "$OUT/bench_ldlt" "$m" "$LAMBDA" "$REPEAT" amd >> "$raw"
    "$OUT/bench_ldlt" "$m" "$LAMBDA" "$REPEAT" auto >> "$raw"
    if [ $PEER = 1 ]; then
        for mode in amd metis super-amd; do
            "$OUT/peer_cholmod" "$m" "$LAMBDA" "$REPEAT" "$mode" >> "$raw"
        done
    fi
    if [ $EIGEN = 1 ]; then
        "$OUT/peer_eigen" "$m" "$LAMBDA" "$REPEAT" >> "$raw"
    fi
done
{
    echo "# LDL^T benchmark: M = I + $LAMBDA L (uniform Laplacian), one thread"
    echo
    echo "CPU ms, minimum of $REPEAT runs (solve: of $((REPEAT * 5))). analyze = ordering + etree + column counts"
    echo "+ postorder; factor = numeric factorization (refactor of an analyzed pattern); solve3 = one solve"
    echo "with 3 right-hand sides (x, y, z). nnz(L) includes the diagonal. bytes: ours = symbolic object +"
    echo "numeric factor kept in the arena; CHOLMOD = its peak memory_usage. ours-amd: our AMD; ours-auto:"
    echo "our AMD or our geometric nested dissection (=nd), whichever predicts the smaller nnz(L) (its analyze"
    echo "time includes both orderings). Ratios: ours-amd / CHOLMOD simplicial AMD, ours-auto / CHOLMOD"
    echo "simplicial METIS. CHOLMOD supernodal AMD uses Debian's reference BLAS. Eigen: SimplicialLDLT with"
    echo "its AMDOrdering (analyze = analyzePattern, solve3 = solve of an n x 3 matrix, column by column;"
    echo "bytes = 12 nnz(L) + 12 n, computed, not measured)."
    echo "Command: sh tests/bench/run_ldlt.sh"
    echo
    echo "| mesh | n | solver | nnz(L) | analyze | factor | solve3 | bytes | B/nnz(L) | resid |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    awk '{ o = ($1 ~ /^ours/); printf "| %s | %s | %s | %.0f | %.2f | %.2f | %.3f | %.0f | %.1f | %s |\n", $2, $3, (o ? "**" $1 "**" : ($1 == "eigen" ? "Eigen SimplicialLDLT AMD" : "CHOLMOD " $1)), $4, $5, $6, $7, $8, $8/$4, (o ? $10 : $9) }' "$raw"
    echo
    echo "| mesh | n | nnz(L) amd/AMD | analyze amd/AMD | factor amd/AMD | solve3 amd/AMD | auto picks | nnz(L) auto/METIS | analyze auto/METIS | factor auto/METIS | solve3 auto/METIS | factor auto/AMD | factor amd/Eigen | solve3 amd/Eigen |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    awk '$1=="ours-amd" { n[$2]=$3; on[$2]=$4; oa[$2]=$5; of[$2]=$6; os[$2]=$7; order[++k]=$2 }
         $1 ~ /^ours-auto/ { pick[$2]=substr($1, 11); un[$2]=$4; ua[$2]=$5; uf[$2]=$6; us[$2]=$7 }
         $1=="amd"  { an[$2]=$4; aa[$2]=$5; af[$2]=$6; as[$2]=$7 }
         $1=="metis"{ mn[$2]=$4; ma[$2]=$5; mf[$2]=$6; ms[$2]=$7 }
         $1=="eigen"{ ef[$2]=$6; es[$2]=$7 }
         END { for (i = 1; i <= k; i++) { m = order[i]; if (!(m in an)) continue;
               efr = (m in ef) ? sprintf("%.2f", of[m]/ef[m]) : "-"; esr = (m in es) ? sprintf("%.2f", os[m]/es[m]) : "-";
               printf "| %s | %s | %.3f | %.2f | %.2f | %.2f | %s | %.3f | %.2f | %.2f | %.2f | %.2f | %s | %s |\n", m, n[m], on[m]/an[m], oa[m]/aa[m], of[m]/af[m], os[m]/as[m], pick[m], un[m]/mn[m], ua[m]/ma[m], uf[m]/mf[m], us[m]/ms[m], uf[m]/af[m], efr, esr } }' "$raw"
} > "$OUT/ldlt.md"
cat "$OUT/ldlt.md"
