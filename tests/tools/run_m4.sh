#!/bin/sh
# run_m4.sh ELF - runs a program of the Cortex-M4 port on QEMU's mps2-an386
# board (semihosting) and exits with the program's exit status (124 on a
# timeout, 99 on a fault, 134 when QEMU stops on a lockup, e.g. after a stack
# overflow). The program's stdout and stderr pass through, except the port's
# report line "ls_m4: stack high-water ...", which is written to ELF.stack.
# LS_M4_TIMEOUT: seconds before the run is killed (default 120).
# LS_M4_ICOUNT=1: run with -icount shift=0 (one instruction per virtual
# nanosecond) so that ls_m4_instructions() counts instructions.
elf=$1
[ -f "$elf" ] || { echo "run_m4.sh: no such program: $elf" >&2; exit 2; }
icount=
[ "${LS_M4_ICOUNT:-0}" = 1 ] && icount="-icount shift=0"
# shellcheck disable=SC2086 # $icount is empty or two words on purpose
timeout "${LS_M4_TIMEOUT:-120}" qemu-system-arm -M mps2-an386 $icount -display none -monitor none -serial null \
    -semihosting-config enable=on,target=native -kernel "$elf" 2> "$elf.stderr" < /dev/null
rc=$?
grep '^ls_m4: stack high-water' "$elf.stderr" > "$elf.stack"
grep -v '^ls_m4: stack high-water' "$elf.stderr" >&2
exit $rc
