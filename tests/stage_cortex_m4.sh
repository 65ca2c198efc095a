#!/bin/sh
# stage_cortex_m4.sh - the Cortex-M4 tier (`make m4`; a stage of `make test`)
# on QEMU's mps2-an386 board, port/cortex-m4:
#   - float, full-RAM profile: test_mcu, the digest (against fixtures/), hygiene;
#   - double, full-RAM profile: the same (double arithmetic in soft float);
#   - float, MCU profile (256 KiB RAM, 8 KiB stack): test_mcu and the digest;
#   - the float builds sum in float there (SUMS=real: no double FPU), so their
#     digests are checked against fixtures/digest-float-floatsums.txt, which
#     the host's SUMS=real float build must reproduce too (checked here);
#   - the float library contains no double arithmetic (no __aeabi_d* ...),
#     the check first shown a planted violation (tests/tools/double_probe.c);
#   - the stack high-water mark of each program, measured by painting, within
#     the profile's stack less 1 KiB;
#   - code size per module against its limit (`make size`).
# The stage's time is printed beside M4_BUDGET seconds (default 150: three M4
# builds and the host float-sums digest build); over it is noted, not failed.
budget=${M4_BUDGET:-150}
jobs=${JOBS:-2}
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | sed 's/^/     /'; fi; }
mkdir -p build/logs
stage_start=$(date +%s)
for v in "full float" "full double" "mcu float"; do
    # shellcheck disable=SC2086 # split "profile real" on purpose
    set -- $v
    profile=$1 real=$2
    build=build/cortex-m4-$profile-$real
    log=build/logs/cortex-m4-$profile-$real.log
    start=$(date +%s)
    rm -f "$build"/tests/*.stack
    echo "== cortex-m4 $profile $real"
    if make --no-print-directory -j"$jobs" TARGET=cortex-m4 PROFILE="$profile" REAL="$real" check > "$log" 2>&1; then
        grep -E '^(ok|FAIL|     |[A-Za-z_0-9.-]+: [0-9]+ passed)' "$log"
        ok "m4_${profile}_${real} ($(( $(date +%s) - start )) s)"
    else
        grep -E '^(ok|FAIL|     |[A-Za-z_0-9.-]+: [0-9]+ passed)' "$log"
        grep -E 'error:|\*\*\*|not found|No such file' "$log" | head -n 15 | sed 's/^/     /'
        bad "m4_${profile}_${real} (log: $log)"
    fi
    # Stack high-water marks reported by the port after main returned.
    for prog in test_mcu digest; do
        line=$(cat "$build/tests/$prog.stack" 2>/dev/null)
        used=$(printf '%s\n' "$line" | sed -n 's/^ls_m4: stack high-water \([0-9]*\) of \([0-9]*\) bytes.*/\1/p')
        size=$(printf '%s\n' "$line" | sed -n 's/^ls_m4: stack high-water \([0-9]*\) of \([0-9]*\) bytes.*/\2/p')
        if [ -z "$used" ]; then
            bad "m4_stack_${profile}_${real}_$prog (no stack report: the program did not return from main)"
        elif [ $((used + 1024)) -le "$size" ]; then
            ok "m4_stack_${profile}_${real}_$prog ($used of $size bytes, painted)"
        else
            bad "m4_stack_${profile}_${real}_$prog ($used of $size bytes: less than 1 KiB left)"
        fi
    done
done

# The host's float build with float sums: the same digest as the M4's.
log=build/logs/host-float-floatsums.log
out=""
if make --no-print-directory -j"$jobs" REAL=float SUMS=real BUILD=build/float-floatsums TARGET= \
        build/float-floatsums/tests/digest > "$log" 2>&1 &&
        out=$(sh tests/tools/digest_check.sh build/float-floatsums/tests/digest fixtures/digest-float-floatsums.txt); then
    ok "host_float_floatsums_digest (the M4's fixture, reproduced on the host)"
else
    bad "host_float_floatsums_digest (log: $log)" "$(printf '%s\n' "$out" | grep -v '^ok' | head -n 10)"
fi

# No double arithmetic in the float library (the double-precision API such as
# ls_sin aside): the check is first shown a planted violation.
probe_dir=build/cortex-m4-no-double-probe/obj
mkdir -p "$probe_dir"
lib_objs=build/cortex-m4-full-float/obj/src
if ! arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -O2 \
        -c tests/tools/double_probe.c -o "$probe_dir/double_probe.o" 2> build/logs/double_probe.err; then
    bad "m4_float_library_has_no_double_arithmetic (cannot compile the probe)" "$(cat build/logs/double_probe.err)"
elif sh tests/tools/no_double.sh "$probe_dir" "" > /dev/null 2>&1; then
    bad "m4_float_library_has_no_double_arithmetic (the check misses the double arithmetic in tests/tools/double_probe.c)"
elif ! ls "$lib_objs"/*.o > /dev/null 2>&1; then
    bad "m4_float_library_has_no_double_arithmetic (no objects: the float build failed)"
elif out=$(sh tests/tools/no_double.sh "$lib_objs" build/cortex-m4-full-float/include 2>&1); then
    ok "m4_float_library_has_no_double_arithmetic ($out)"
else
    bad "m4_float_library_has_no_double_arithmetic" "$out"
fi

# Code size per module (prints its own table, checks and summary line).
size_rc=0
sh tests/tools/m4_size.sh || size_rc=1

secs=$(( $(date +%s) - stage_start ))
# a note, not a test: the machine's speed is not a result
if [ "$secs" -le "$budget" ]; then echo "     m4: $secs s (budget $budget s)"; else echo "     m4: $secs s, OVER its budget of $budget s"; fi
echo "cortex_m4: $pass passed, $fail failed"
[ "$fail" = 0 ] && [ "$size_rc" = 0 ]
