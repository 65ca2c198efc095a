#!/bin/sh
# budget.sh - `make test`: runs tests/matrix.sh, passing its output through,
# then prints every stage's time ("[name] ... in N s") beside its budget in
# tests/tools/budgets.txt, and the total beside its "total" line: notes, not
# tests (a slow machine is not a failure of the code). Last, the matrix's
# "N passed, M failed"; exits non-zero on any failure.
budgets=tests/tools/budgets.txt
mkdir -p build/logs
out=build/logs/matrix.out
start=$(date +%s)
# The matrix's own last line (the total) is held back and re-counted below.
{ sh tests/matrix.sh; echo "matrix-exit $?"; } 2>&1 | tee "$out" | grep --line-buffered -Ev '^([0-9]+ passed, [0-9]+ failed|matrix-exit [0-9]+)$'
secs=$(( $(date +%s) - start ))
budget() { # stage -> seconds
    b=$(awk -v s="$1" '$1 == s {print $2}' "$budgets")
    [ -n "$b" ] || b=$(awk '$1 == "default" {print $2}' "$budgets")
    echo "$b"
}
pass=0 fail=0
# shellcheck disable=SC2013 # one word per stage: "name=seconds"
for line in $(sed -n 's/^\[\([A-Za-z_0-9.-]*\)\] [0-9]* passed, [0-9]* failed in \([0-9]*\) s$/\1=\2/p' "$out"); do
    stage=${line%=*} t=${line#*=}
    b=$(budget "$stage")
    if [ "$t" -le "$b" ]; then echo "time $stage $t s (budget $b s)"
    else echo "time $stage $t s: OVER its budget of $b s (a note: the machine's speed is not a test result)"; fi
done
b=$(budget total)
if [ "$secs" -le "$b" ]; then echo "time total $secs s (budget $b s)"
else echo "time total $secs s: OVER its budget of $b s (a note: the machine's speed is not a test result)"; fi
mp=$(sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed$/\1/p' "$out" | tail -n 1)
mf=$(sed -n 's/^\([0-9]*\) passed, \([0-9]*\) failed$/\2/p' "$out" | tail -n 1)
rc=$(sed -n 's/^matrix-exit \([0-9]*\)$/\1/p' "$out")
if [ -z "$mp" ] || [ -z "$rc" ]; then mp=${mp:-0}; mf=$(( ${mf:-0} + 1 )); rc=1; echo "FAIL the matrix did not finish"; fi
echo "$((mp + pass)) passed, $((mf + fail)) failed"
[ "$rc" = 0 ] && [ "$fail" = 0 ]
