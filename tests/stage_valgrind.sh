#!/bin/sh
# stage_valgrind.sh - a representative subset of the unit tests (gcc, double,
# -O2 -g) under `valgrind --error-exitcode=1 --leak-check=full` (memcheck:
# invalid reads and writes, uninitialised values deciding a branch, leaks),
# `make valgrind`, a stage of `make test`. The tests run with
# LS_TEST_EMULATED=1 (valgrind is an emulator: the programs shrink their own
# loops), about 2 minutes in all on a 2-core machine. The subset: every
# reader of untrusted bytes (mesh_io, image, scene), the arena, the sparse
# kernels, the Laplacian, CG, meshes and half-edges, rasterization, shading,
# the backward pass, and the out-of-memory sweeps of test_oom (LDLT, remesh,
# silhouette and a short fit at their allocation points). test_ldlt, test_fit,
# test_remesh, test_silhouette and test_number are left to ASan (each takes
# several minutes under valgrind).
# Prints ok/FAIL lines and "valgrind: N passed, M failed".
cd "$(dirname "$0")/.." || exit 1
B=${VALGRIND_BUILD:-build/valgrind}
TESTS="arena sparse scene laplacian shade render_backward cg mesh halfedge raster mesh_io image oom"
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | tail -n 20 | sed 's/^/     /'; fi; }
finish() { echo "valgrind: $pass passed, $fail failed"; [ "$fail" = 0 ]; exit $?; }

command -v valgrind >/dev/null 2>&1 || { bad "tool_valgrind (valgrind is missing: apt-get install valgrind)"; finish; }
mkdir -p "$B"
bins=
for t in $TESTS; do bins="$bins $B/tests/test_$t"; done
# shellcheck disable=SC2086
if make --no-print-directory -j"${JOBS:-2}" BUILD="$B" CC=gcc CXX=g++ REAL=double ARCHFLAGS=-g TARGET= $bins \
    > "$B.stage-valgrind.log" 2>&1; then
    ok "build_valgrind"
else
    bad "build_valgrind" "$(tail -n 20 "$B.stage-valgrind.log")"
    finish
fi
for t in $TESTS; do
    log=$B/valgrind-$t.log
    start=$(date +%s)
    if LS_TEST_EMULATED=1 valgrind -q --error-exitcode=1 --leak-check=full \
        "$B/tests/test_$t" > "$log" 2>&1; then
        ok "valgrind_test_$t ($(( $(date +%s) - start )) s)"
    else
        bad "valgrind_test_$t" "$(grep -E '^==[0-9]+==|^FAIL' "$log" | head -n 20)"
    fi
done
finish
