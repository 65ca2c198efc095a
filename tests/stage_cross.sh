#!/bin/sh
# stage_cross.sh - the emulated tier (`make cross`; a stage of `make test`):
# for each target - aarch64, armhf, riscv64, s390x (big-endian) and i686
# (SSE2) - the library, every test program and the digest are cross-compiled
# with Debian's gcc, in double and in float, and run under qemu-user
# (`make check TARGET=t REAL=r`: tests, digest against fixtures/, hygiene).
# Every target is required: a missing compiler or QEMU is a failure.
# Each target's time (both builds) is printed beside CROSS_BUDGET seconds
# (default 240; 71-149 s wall measured on a 2-core machine loaded by other
# jobs): a slower target is noted, not failed.
# Logs: build/logs/cross-TARGET-REAL.log.
budget=${CROSS_BUDGET:-240}
targets=${CROSS_TARGETS:-"aarch64 armhf riscv64 s390x i686"}
jobs=${JOBS:-2}
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
mkdir -p build/logs
total_start=$(date +%s)
# CPU seconds (user + system) used by finished children so far: with the
# wall time it shows whether a slow target was slow or the machine was busy.
# (`times` must run in this shell, not in a $(...) subshell.)
cpu_file=build/logs/cross-times.txt
cpu() { awk 'NR == 2 {n = split($0, f, " "); s = 0; for (i = 1; i <= n; i++) {split(f[i], a, "m"); s += a[1] * 60 + a[2]} printf "%d", s}' "$cpu_file"; }
for t in $targets; do
    times > "$cpu_file"
    start=$(date +%s) cpu0=$(cpu)
    for r in double float; do
        log=build/logs/cross-$t-$r.log
        echo "== $t $r"
        if make --no-print-directory -j"$jobs" TARGET="$t" REAL="$r" check > "$log" 2>&1; then
            grep -E '^(ok|FAIL|     |[A-Za-z_0-9.-]+: [0-9]+ passed)' "$log"
            ok "cross_${t}_${r}"
        else
            # The test lines and summaries of what ran, then the error of what did not.
            grep -E '^(ok|FAIL|     |[A-Za-z_0-9.-]+: [0-9]+ passed)' "$log"
            grep -E 'error:|\*\*\*|not found|No such file' "$log" | head -n 15 | sed 's/^/     /'
            bad "cross_${t}_${r} (log: $log)"
        fi
    done
    secs=$(( $(date +%s) - start ))
    times > "$cpu_file"
    echo "     time $t: $secs s wall, $(( $(cpu) - cpu0 )) s CPU (double + float: build and run)"
    # a note, not a test: the machine's speed is not a result
    if [ "$secs" -le "$budget" ]; then echo "     $t: $secs s (budget $budget s)"; else echo "     $t: $secs s, OVER its budget of $budget s"; fi
done
echo "     time all targets: $(( $(date +%s) - total_start )) s"
echo "cross: $pass passed, $fail failed"
[ "$fail" = 0 ]
