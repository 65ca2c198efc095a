#!/bin/sh
# tests/bench/run_grid.sh - the parameterization on a texture grid: the
# transform solver (grid_solve.h) against the sparse LDL^T (automatic
# ordering) and CG, M = I + lambda L, 3 channels (RGB), one thread, CPU
# time. Writes build/bench/grid.md and prints it; then the transform solver
# against FFTW's DCT-II/III of the same grid (peer_fftw_grid, Debian
# libfftw3-dev, bench only; skipped with a note when it is missing).
#
# Environment: BUILD (default build), GRID_SIZES (default "256 512 1024"),
# GRID_LAMBDA (10), GRID_TOL (CG relative tolerance, 1e-10), GRID_WRAP (0:
# Neumann, 1: wrap in u), GRID_REPEAT (3; the LDL^T runs once above 512^2),
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=$BUILD/bench
mkdir -p "$OUT"
SIZES=${GRID_SIZES:-"256 512 1024"}
LAMBDA=${GRID_LAMBDA:-10}
TOL=${GRID_TOL:-1e-10}
WRAP=${GRID_WRAP:-0}
REPEAT=${GRID_REPEAT:-3}
make --no-print-directory -s BUILD="$BUILD" "$OUT/bench_grid"
raw=$OUT/grid.raw
ratios=$OUT/grid.ratios
# shellcheck disable=SC2086
"$OUT/bench_grid" "$REPEAT" "$LAMBDA" "$TOL" "$WRAP" $SIZES > "$raw" 2> "$ratios.all"
grep '^RATIO ' "$ratios.all" | sed 's/^RATIO //' > "$ratios" || true
grep -v '^RATIO ' "$ratios.all" >&2 || true
{
    echo "# Texture grid: transform solver vs sparse LDL^T vs CG, M = I + $LAMBDA L, 3 channels"
    echo
    echo "CPU ms, one thread, minimum of $REPEAT runs (LDL^T above 512^2: one run). Grid Laplacian: 4 neighbours,"
    echo "$( [ "$WRAP" = 1 ] && echo "wrap-around in u, Neumann in v" || echo "Neumann boundary") (ls_param_grid_init). init = ls_param_grid_init (transform: tables;"
    echo "LDL^T: Laplacian, M, LS_ORDER_AUTO ordering on the texel centres, symbolic + numeric factor; CG: Laplacian,"
    echo "M, buffers). solve = ls_param_from_differential of u = M x (x a smooth RGB texture plus noise); CG from zero"
    echo "to a $TOL relative residual. bytes = ls_param_grid_bytes: the object's arena peak (the caller's vectors"
    echo "not counted). vs transform = ||x_solver - x_transform|| / ||x_transform||; round trip = ||M^-1 M x - x|| / ||x||."
    echo "Command: sh tests/bench/run_grid.sh (make bench)"
    echo
    echo "| grid | solver | init ms | solve ms | CG iterations | bytes | vs transform | round trip |"
    echo "|---|---|---|---|---|---|---|---|"
    cat "$raw"
    echo
    echo "Ratios (the other solver / the transform solver; init against at least 0.01 ms). The last column is"
    echo "ls_grid_solver_bytes: the transform solver's tables and buffers without the parameterization's n k step buffer."
    echo
    echo "| grid | LDL^T init | LDL^T solve | LDL^T bytes | CG solve | CG bytes | transform solver alone, bytes |"
    echo "|---|---|---|---|---|---|---|"
    cat "$ratios"
    if [ -f /usr/include/fftw3.h ] && [ "$WRAP" = 0 ]; then
        make --no-print-directory -s BUILD="$BUILD" "$OUT/peer_fftw_grid"
        echo
        echo "The transform solver against FFTW (3.x, FFTW_MEASURE plans; REDFT10, the division by the eigenvalues,"
        echo "REDFT01 and the 1/(4WH) scale, the 3 interleaved channels in one plan), the same right-hand side,"
        echo "CPU ms of one solve, the minimum of $REPEAT alternated runs; difference = ||x_ours - x_FFTW|| / ||x_FFTW||."
        echo
        echo "| grid | ours ms | FFTW ms | ours / FFTW | difference |"
        echo "|---|---|---|---|---|"
        # shellcheck disable=SC2086
        "$OUT/peer_fftw_grid" "$REPEAT" "$LAMBDA" $SIZES
    else
        echo
        echo "FFTW peer skipped: apt-get install libfftw3-dev (and GRID_WRAP=0)."
    fi
} > "$OUT/grid.md"
rm -f "$ratios.all"
cat "$OUT/grid.md"
