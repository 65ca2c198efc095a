#!/bin/sh
# lint.sh - static analysis of the library: cppcheck, clang-tidy (bugprone,
# cert, clang-analyzer) and scan-build. Zero findings; any suppression is
# justified in place in the source (NOLINT(check): why / cppcheck-suppress).
# Each analyser is first shown a planted bug (tests/tools/lint_probe.c) and
# must report it, so a silent analyser does not pass. JOBS (default 2):
# the processes each analyser runs at once.
jobs=${JOBS:-2}
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | sed 's/^/     /'; fi; }
dir=build/lint
mkdir -p "$dir/include/largesteps"
printf '#ifndef LARGESTEPS_CONFIG_H\n#define LARGESTEPS_CONFIG_H\n#define LS_REAL_IS_FLOAT %s\n#endif\n' 0 > "$dir/include/largesteps/config.h"
INC="-Iinclude -I$dir/include"
SRC=$(ls src/*/*.c)
probe=tests/tools/lint_probe.c

need() { command -v "$1" >/dev/null 2>&1 || { bad "$2 ($1 is not installed: .ci/run installs it)"; return 1; }; }

# cppcheck
if need cppcheck lint_cppcheck; then
    CPPCHECK="cppcheck -j $jobs --std=c99 --enable=warning,portability,performance,style --inline-suppr --error-exitcode=1 -q --suppress=missingIncludeSystem --suppress=unusedFunction $INC"
    if $CPPCHECK $probe >/dev/null 2>&1; then
        bad "lint_cppcheck (does not report the planted bug in $probe)"
    elif out=$($CPPCHECK $SRC 2>&1) && [ -z "$out" ]; then
        ok "lint_cppcheck"
    else
        bad "lint_cppcheck" "$out"
    fi
fi

# clang-tidy
if need clang-tidy lint_clang_tidy; then
    CHECKS='-*,bugprone-*,cert-*,clang-analyzer-*,-bugprone-easily-swappable-parameters,-cert-err33-c'
    TIDY="clang-tidy -quiet --checks=$CHECKS --warnings-as-errors=*"
    if $TIDY $probe -- -std=c99 $INC >/dev/null 2>&1; then
        bad "lint_clang_tidy (does not report the planted bug in $probe)"
    elif out=$(printf '%s\n' $SRC | xargs -P "$jobs" -n 4 sh -c "$TIDY \"\$@\" -- -std=c99 $INC" sh 2>&1); then
        ok "lint_clang_tidy"
    else
        bad "lint_clang_tidy" "$(printf '%s\n' "$out" | grep -E 'warning|error' | head -n 40)"
    fi
fi

# scan-build (the clang static analyzer driving a real compile)
if need scan-build lint_scan_build; then
    if scan-build --status-bugs -o "$dir/scan-probe" clang -std=c99 $INC -c $probe -o "$dir/probe.o" >/dev/null 2>&1; then
        bad "lint_scan_build (does not report the planted bug in $probe)"
    else
        rm -rf "$dir/scan"
        if out=$(scan-build --use-cc=clang --status-bugs -o "$dir/scan" make --no-print-directory -j"$jobs" -B BUILD="$dir/scan-build" lib 2>&1); then
            ok "lint_scan_build"
        else
            bad "lint_scan_build" "$(printf '%s\n' "$out" | grep -E 'warning|bug' | head -n 40)"
        fi
    fi
fi

# Layering (tests/tools/layers.sh): first shown a copy of the tree with an
# upward include planted (the lowest layer including the fit), which it must report.
plant="$dir/layers-probe"
rm -rf "$plant" && mkdir -p "$plant" && cp -R Makefile src include "$plant/"
printf '#include <largesteps/fit.h>\n' >> "$plant/src/base/sort.c"
if sh tests/tools/layers.sh "$plant" >/dev/null 2>&1; then
    bad "lint_layers (does not report the upward include planted in $plant/src/base/sort.c)"
elif out=$(sh tests/tools/layers.sh . 2>&1); then
    ok "lint_layers (src/: $(sed -n 's/^LAYERS *:= *//p' Makefile), lowest first)"
else
    bad "lint_layers" "$out"
fi

echo "lint: $pass passed, $fail failed"
[ "$fail" = 0 ]
