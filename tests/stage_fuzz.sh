#!/bin/sh
# stage_fuzz.sh - the libFuzzer targets of tests/fuzz/ (`make fuzz-replay`,
# a stage of `make test`; `make fuzz` runs it with FUZZ_TIME=60).
#   build_fuzz       the targets build (clang, -fsanitize=fuzzer,address,
#                    undefined,float-cast-overflow, -fno-sanitize-recover=all)
#   replay_NAME      every file of tests/fuzz/corpus/NAME/ (the seeds and the
#                    regress-* inputs of crashes found before) runs cleanly
#   fuzz_NAME        FUZZ_TIME seconds (default 10) of fuzzing from that
#                    corpus: no crash, leak, hang (-timeout=10) or invariant
#                    failure; new inputs go to build/fuzz/work/NAME/ and a
#                    crashing input to build/fuzz/crash-NAME-*
# clang's fuzzer runtime (Debian libclang-rt-14-dev) is required: without it
# the stage fails (CI installs it), it never passes by skipping.
# Prints ok/FAIL lines and "fuzz: N passed, M failed".
self=$(cd "$(dirname "$0")" && pwd)/$(basename "$0")
# shellcheck source=tests/tools/reports.sh
. "$(dirname "$self")/tools/reports.sh"
cd "$(dirname "$0")/.." || exit 1
FUZZ_TIME=${FUZZ_TIME:-10}
FUZZ_BUILD=${FUZZ_BUILD:-build/fuzz}
FUZZ_CC=${FUZZ_CC:-clang}
TARGETS="obj ply off png ppm pfm scene mitsuba transforms"
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | tail -n 12 | sed 's/^/     /'; fi; }
finish() { echo "fuzz: $pass passed, $fail failed"; [ "$fail" = 0 ]; exit $?; }

# One target: its replay and its fuzzing, report lines into FUZZ_BUILD/report-T.txt.
one() {
    t=$1
    bin=$FUZZ_BUILD/fuzz_$t
    corpus=tests/fuzz/corpus/$t
    dict=
    [ -f "tests/fuzz/dict/$t.dict" ] && dict="-dict=tests/fuzz/dict/$t.dict"
    log=$FUZZ_BUILD/replay-$t.log
    # Each file on its own (libFuzzer runs the named files and stops).
    # shellcheck disable=SC2046
    if [ -n "$(ls "$corpus" 2>/dev/null)" ] && "$bin" $(find "$corpus" -type f | sort) > "$log" 2>&1; then
        ok "replay_$t ($(find "$corpus" -type f | wc -l | tr -d ' ') inputs)"
    else
        bad "replay_$t" "$(grep -E 'invariant|ERROR|SUMMARY|runtime error|Running' "$log" | tail -n 6)"
    fi
    work=$FUZZ_BUILD/work/$t
    mkdir -p "$work"
    log=$FUZZ_BUILD/fuzz-$t.log
    # shellcheck disable=SC2086
    if "$bin" -max_total_time="$FUZZ_TIME" -timeout=10 -max_len=8192 -print_final_stats=1 $dict \
        -artifact_prefix="$FUZZ_BUILD/crash-$t-" "$work" "$corpus" > "$log" 2>&1; then
        runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
        cov=$(grep -E '^#[0-9]+' "$log" | tail -n 1 | sed -n 's/.*\(cov: [0-9]*\) \(ft: [0-9]*\).*/\1 \2/p')
        ok "fuzz_$t (${FUZZ_TIME} s, $runs runs, $cov)"
    else
        bad "fuzz_$t (input: $(find "$FUZZ_BUILD" -maxdepth 1 -name "crash-$t-*" | head -n 1))" \
            "$(grep -E 'invariant|ERROR|SUMMARY|runtime error|Test unit' "$log" | tail -n 8)"
    fi
}
if [ "$1" = --one ]; then
    one "$2" > "$FUZZ_BUILD/report-$2.txt" 2>&1
    exit 0
fi
mkdir -p "$FUZZ_BUILD"
if ! command -v "$FUZZ_CC" >/dev/null 2>&1; then
    bad "tool_clang ($FUZZ_CC is missing: apt-get install clang libclang-rt-14-dev)"
    finish
fi
# The fuzzer runtime: a one-line program must link with -fsanitize=fuzzer.
printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n);\nint LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { (void)d; (void)n; return 0; }\n' \
    > "$FUZZ_BUILD/probe.c"
if ! "$FUZZ_CC" -fsanitize=fuzzer "$FUZZ_BUILD/probe.c" -o "$FUZZ_BUILD/probe" > "$FUZZ_BUILD/probe.log" 2>&1; then
    bad "tool_libfuzzer (clang's fuzzer runtime is missing: apt-get install libclang-rt-14-dev)" "$(cat "$FUZZ_BUILD/probe.log")"
    finish
fi
if make --no-print-directory -j"${JOBS:-2}" FUZZ_BUILD="$FUZZ_BUILD" FUZZ_CC="$FUZZ_CC" fuzz-build > "$FUZZ_BUILD/build.log" 2>&1; then
    ok "build_fuzz"
else
    bad "build_fuzz" "$(cat "$FUZZ_BUILD/build.log")"
    finish
fi

# JOBS (default 2) targets at once; each one's lines in the list's order.
# shellcheck disable=SC2086 # $TARGETS is a list
reports_run "$self" "$FUZZ_BUILD/report-" .txt "" $TARGETS
finish
