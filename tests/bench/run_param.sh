#!/bin/sh
# tests/bench/run_param.sh - the parameterization's solvers: LDL^T factor vs
# Jacobi-preconditioned CG on M = I + lambda L (uniform Laplacian), lambda =
# 1, 19, 99, one thread, CPU time, minimum of REPEAT runs. Writes
# build/bench/param.md and prints it. No peer: both solvers are ours.
#
# Environment: BUILD (default build), PARAM_MESHES (default: the bunny
# fixture and ../shared/meshes/armadillo.obj, read at bench time), SHARED
# (default ../shared), PARAM_REPEAT (3), PARAM_TOL (CG relative tolerance,
# 1e-10).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
SHARED=${SHARED:-../shared}
MESHES=${PARAM_MESHES:-"fixtures/meshes/bunny.obj $SHARED/meshes/armadillo.obj"}
REPEAT=${PARAM_REPEAT:-3}
TOL=${PARAM_TOL:-1e-10}
make --no-print-directory -s BUILD="$BUILD" "$OUT/bench_param"
raw=$OUT/param.raw
: > "$raw"
for m in $MESHES; do
    [ -f "$m" ] || { echo "run_param: $m not found, skipped" >&2; continue; }
    "$OUT/bench_param" "$m" "$REPEAT" "$TOL" 1 19 99 >> "$raw"
done
{
    echo "# Parameterization solvers: LDL^T factor vs Jacobi-preconditioned CG, M = I + lambda L (uniform)"
    echo
    echo "CPU ms, one thread, minimum of $REPEAT runs. init = ls_param_init (LDL^T: automatic ordering +"
    echo "symbolic + numeric factor; CG: M and its buffers). solve = ls_param_from_differential of u = M x"
    echo "(x = the vertex positions, 3 columns); CG from a zero start. warm = CG after u changed by a 1e-3"
    echo "relative perturbation, from the previous solution (one optimizer step). rel. error: LDL^T round"
    echo "trip ||x' - x|| / ||x||; CG ||x_cg - x_ldlt|| / ||x_ldlt||. bytes = ls_param_bytes (the object;"
    echo "CG keeps M, two warm starts, the step's two buffers and its scratch; LDL^T the symbolic + numeric factor)."
    echo "Command: sh tests/bench/run_param.sh (make bench)"
    echo
    echo "| mesh | n | lambda | solver | init ms | solve ms | iterations | warm iterations | warm ms | rel. error | bytes |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
    cat "$raw"
} > "$OUT/param.md"
cat "$OUT/param.md"
