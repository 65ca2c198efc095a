#!/bin/sh
# stage_flags.sh - the same bits under the build flags users choose (a stage of
# `make test`): the library and the digest program built with gcc and clang at
# -O0, -Os (the plain paths: LS_FAST_PATHS is 0 when optimizing for size, as
# on the MCU; also at -O2 with -DLS_FAST_PATHS=0, with the gradient tests), -O3 and -O2 -march=x86-64-v3 (AVX2 and FMA: the vectorizers'
# fused multiply-adds), in double and float, and for aarch64 at -O3 under QEMU; each
# digest must be exactly the committed fixture. The check is first shown a
# build that changes bits: the functions marked LS_NO_VECTORIZE (complex
# products, which GCC fuses into vfmaddsub under -march=x86-64-v3 despite
# -ffp-contract=off) built with the vectorizer on, whose digest must differ.
jobs=${JOBS:-2}
pass=0 fail=0
mkdir -p build/logs build/flags
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | sed 's/^/     /'; fi; }
# row NAME CC REAL OPT [make variables...]: builds BUILD/tests/digest, echoes BUILD
build_row() {
    name=$1 cc=$2 real=$3 opt=$4
    shift 4
    dir=build/flags/$name
    if make --no-print-directory -j"$jobs" BUILD="$dir" CC="$cc" REAL="$real" OPT="$opt" "$@" "$dir/tests/digest" \
            > "build/logs/flags-$name.log" 2>&1; then
        return 0
    fi
    return 1
}
host_has() { grep -qw "$1" /proc/cpuinfo 2>/dev/null; }
v3=1
for f in avx2 fma bmi2; do host_has "$f" || v3=0; done

# The planted failure: first, so that a check that cannot fail does not pass.
if [ "$v3" = 1 ]; then
    if ! build_row probe-v3 gcc double "-O2 -march=x86-64-v3" ARCHFLAGS=-DLS_TEST_VECTORIZE_ALL; then
        bad "flags_probe (build failed: build/logs/flags-probe-v3.log)"
    elif sh tests/tools/digest_check.sh build/flags/probe-v3/tests/digest fixtures/digest-double.txt > /dev/null 2>&1; then
        bad "flags_probe (the grid solver built with GCC's vectorizer under -march=x86-64-v3 gives the fixture's digest: the check cannot see fused multiply-adds)"
    else
        ok "flags_probe (the vectorized complex products under -march=x86-64-v3 change the digest, as they must)"
    fi
fi
for cc in gcc clang; do
    for real in double float; do
        for opt in "-O0" "-Os" "-O3" "-O2 -march=x86-64-v3"; do
            tag=$(echo "$opt" | tr -d ' ' | tr '=' '-')
            name=$cc-$real$tag
            # the plain paths once: -Os with gcc in double (the Cortex-M4 stage runs them in float)
            if [ "$opt" = "-Os" ] && { [ "$cc" = clang ] || [ "$real" = float ]; }; then continue; fi
            if [ "$opt" = "-O2 -march=x86-64-v3" ] && [ "$v3" = 0 ]; then
                echo "     $name: not run, this CPU lacks AVX2/FMA/BMI2"
                continue
            fi
            if ! build_row "$name" "$cc" "$real" "$opt"; then
                bad "flags_$name (build failed)" "$(grep -E 'error|Error' "build/logs/flags-$name.log" | head -n 5)"
            elif out=$(sh tests/tools/digest_check.sh "build/flags/$name/tests/digest" "fixtures/digest-$real.txt"); then
                ok "flags_$name (the fixture's digest)"
            else
                bad "flags_$name" "$(printf '%s\n' "$out" | grep -E 'want|got|exited' | head -n 12)"
            fi
        done
    done
done
# The plain paths at the default level: LS_FAST_PATHS=0 leaves out every fast
# path (SSE2, specialized copies, prefetches, the shading backward's SH
# loop); the gradient tests and the digest must pass and match as they do
# with them.
name=gcc-double-O2-plain
plain_tests="test_silhouette test_render_backward test_raster_refine test_shade"
if ! build_row "$name" gcc double "-O2" ARCHFLAGS=-DLS_FAST_PATHS=0 \
        $(for t in $plain_tests; do printf ' build/flags/%s/tests/%s' "$name" "$t"; done); then
    bad "flags_$name (build failed)" "$(grep -E 'error|Error' "build/logs/flags-$name.log" | head -n 5)"
else
    if out=$(sh tests/tools/digest_check.sh "build/flags/$name/tests/digest" fixtures/digest-double.txt); then
        ok "flags_$name (the fixture's digest without the fast paths)"
    else
        bad "flags_$name" "$(printf '%s\n' "$out" | grep -E 'want|got|exited' | head -n 12)"
    fi
    for t in $plain_tests; do
        if out=$("build/flags/$name/tests/$t" 2>&1); then
            ok "flags_${name}_$t ($(printf '%s\n' "$out" | tail -n 1))"
        else
            bad "flags_${name}_$t" "$(printf '%s\n' "$out" | grep -E '^FAIL' | head -n 8)"
        fi
    done
fi
# aarch64 at -O3 under QEMU
for real in double float; do
    name=aarch64-$real-O3
    if ! build_row "$name" aarch64-linux-gnu-gcc "$real" "-O3" TARGET=aarch64; then
        bad "flags_$name (build failed)" "$(grep -E 'error|Error' "build/logs/flags-$name.log" | head -n 5)"
    elif out=$(sh tests/tools/digest_check.sh "build/flags/$name/tests/digest" "fixtures/digest-$real.txt" \
                 "env LS_TEST_EMULATED=1 qemu-aarch64 -L /usr/aarch64-linux-gnu"); then
        ok "flags_$name (the fixture's digest under qemu-aarch64)"
    else
        bad "flags_$name" "$(printf '%s\n' "$out" | grep -E 'want|got|exited' | head -n 12)"
    fi
done
echo "flags: $pass passed, $fail failed"
[ "$fail" = 0 ]
