#!/bin/sh
# stage_cross.sh - the emulated tier (`make cross`; a stage of `make test`):
# for each target - aarch64, armhf, riscv64, s390x (big-endian) and i686
# (SSE2) - the library, the test programs and the digest are cross-compiled
# with Debian's gcc, in double and in float, and run under qemu-user
# (`make check TARGET=t REAL=r`: tests, digest against fixtures/, hygiene).
# The digest, which pins the library's outputs bit for bit, runs in both
# precisions on every target; the test programs in one precision per target,
# each precision on a 32-bit and a 64-bit target (double: armhf, riscv64 and
# big-endian s390x; float: aarch64 and i686), the other precision with
# DIGEST_ONLY=1 (CROSS_FULL=1 runs them in both: twice the time).
# Every target is required: a missing compiler or QEMU is a failure.
# JOBS (default 2) targets run at once (QEMU runs one test at a time, so a
# target alone leaves the other core idle); each target's lines are printed
# when it ends, in the list's order. Each target's time (both builds) is
# printed beside CROSS_BUDGET seconds (default 400; about 310 s wall measured
# two at a time on a 2-core machine): a slower target is noted, not failed.
# Logs: build/logs/cross-TARGET-REAL.log, build/logs/cross-TARGET.out.
budget=${CROSS_BUDGET:-400}
targets=${CROSS_TARGETS:-"aarch64 armhf riscv64 s390x i686"}
mkdir -p build/logs
# shellcheck source=tests/tools/reports.sh
. "$(dirname "$0")/tools/reports.sh"
# One target, both precisions: its report lines into build/logs/cross-T.out.
if [ "$1" = --one ]; then
    t=$2
    {
        start=$(date +%s)
        case $t in aarch64 | i686) programs=float ;; *) programs=double ;; esac
        for r in double float; do
            log=build/logs/cross-$t-$r.log
            only=1 what="digest and hygiene; the test programs run in $programs"
            if [ "$r" = "$programs" ] || [ "${CROSS_FULL:-0}" = 1 ]; then only=0 what=""; fi
            echo "== $t $r"
            if make --no-print-directory -j1 TARGET="$t" REAL="$r" DIGEST_ONLY=$only check > "$log" 2>&1; then
                grep -E '^(ok|FAIL|     |[A-Za-z_0-9.-]+: [0-9]+ passed)' "$log"
                echo "ok   cross_${t}_${r}${what:+ ($what)}"
            else
                # The test lines and summaries of what ran, then the error of what did not.
                grep -E '^(ok|FAIL|     |[A-Za-z_0-9.-]+: [0-9]+ passed)' "$log"
                grep -E 'error:|\*\*\*|not found|No such file' "$log" | head -n 15 | sed 's/^/     /'
                echo "FAIL cross_${t}_${r} (log: $log)"
            fi
        done
        secs=$(( $(date +%s) - start ))
        # a note, not a test: the machine's speed is not a result
        if [ "$secs" -le "$budget" ]; then echo "     $t: $secs s wall, double + float (budget $budget s)"
        else echo "     $t: $secs s wall, double + float, OVER its budget of $budget s"; fi
    } > "build/logs/cross-$t.out" 2>&1
    exit 0
fi
total_start=$(date +%s)
pass=0 fail=0
# shellcheck disable=SC2086 # $targets is a list
reports_run "$0" build/logs/cross- .out cross_ $targets
echo "     time all targets: $(( $(date +%s) - total_start )) s"
echo "cross: $pass passed, $fail failed"
[ "$fail" = 0 ]
