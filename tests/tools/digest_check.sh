#!/bin/sh
# digest_check.sh DIGEST FIXTURE [RUNNER] - runs the digest program (through
# RUNNER, e.g. qemu) and compares its stdout with the committed fixture, byte
# for byte. Prints "ok   digest_<real>" or "FAIL digest_<real>" with the lines
# that differ, then "digest: N passed, M failed". The program's own output is
# kept in DIGEST.out.
prog=$1 fixture=$2 runner=$3
name=digest_$(basename "$fixture" .txt | sed 's/^digest-//')
out="$prog.out"
if [ ! -f "$fixture" ]; then
    echo "FAIL $name"
    echo "     no fixture $fixture: run \`make digest-update\` and commit it"
    echo "digest: 0 passed, 1 failed"
    exit 1
fi
# shellcheck disable=SC2086
if $runner "$prog" > "$out" 2> "$out.err"; then rc=0; else rc=$?; fi
if [ "$rc" = 0 ] && cmp -s "$fixture" "$out"; then
    echo "ok   $name ($(grep -vc '^#' "$out") lines match $fixture)"
    echo "digest: 1 passed, 0 failed"
    exit 0
fi
echo "FAIL $name"
[ "$rc" = 0 ] || echo "     the program exited with status $rc: $(head -c 300 "$out.err")"
diff "$fixture" "$out" | grep '^[<>]' | head -n 40 | sed -e 's/^</     want/' -e 's/^>/     got /'
echo "digest: 0 passed, 1 failed"
exit 1
