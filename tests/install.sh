#!/bin/sh
# install.sh - `make install` of both variants into a scratch prefix, then a
# user's program built through pkg-config against each (as C and as C++), the
# README's link command as written, and the ABI guard: double headers with the float library must fail to link.
root=$(pwd)/build/install-test
prefix=$root/prefix
rm -rf "$root"
mkdir -p "$root"
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"

for real in double float; do
    if make --no-print-directory -j2 BUILD="$root/build-$real" REAL=$real PREFIX="$prefix" install > "$root/make-$real.log" 2>&1; then
        ok "install_$real"
    else
        bad "install_$real"; cat "$root/make-$real.log"
    fi
done

for pc in largesteps largesteps-float; do
    want=double
    [ "$pc" = largesteps-float ] && want=float
    # shellcheck disable=SC2046
    if cc -std=c99 -pedantic -Wall -Wextra -Werror tests/tools/install_probe.c $(pkg-config --cflags --libs --static $pc) \
          -o "$root/probe-$pc" 2> "$root/probe-$pc.err" && "$root/probe-$pc" > "$root/probe-$pc.out" &&
       [ "$(cat "$root/probe-$pc.out")" = "$want $want LS_OK" ]; then
        ok "pkgconfig_c_program_$pc"
    else
        bad "pkgconfig_c_program_$pc"; cat "$root/probe-$pc.err" "$root/probe-$pc.out" 2>/dev/null
    fi
    # shellcheck disable=SC2046
    if c++ -x c++ -std=c++11 -Wall -Wextra -Werror tests/tools/install_probe.c -x none $(pkg-config --cflags --libs --static $pc) \
          -o "$root/probe-cxx-$pc" 2> "$root/probe-cxx-$pc.err" && "$root/probe-cxx-$pc" > /dev/null; then
        ok "pkgconfig_cxx_program_$pc"
    else
        bad "pkgconfig_cxx_program_$pc"; cat "$root/probe-cxx-$pc.err"
    fi
done

# The README's command exactly as written (no --static: the library is
# static and its .pc lists -lm in Libs, so the plain line links), for both
# precisions; the program is the README's first example (examples/selftest.c).
for pc in largesteps largesteps-float; do
    want=examples/selftest.expected
    [ "$pc" = largesteps-float ] && want=examples/selftest.float.expected
    # shellcheck disable=SC2046
    if (cd "$root" && gcc "$OLDPWD/examples/selftest.c" $(pkg-config --cflags --libs $pc) -o "readme-$pc") \
          2> "$root/readme-$pc.err" && "$root/readme-$pc" > "$root/readme-$pc.out" &&
       cmp -s "$root/readme-$pc.out" "$want"; then
        ok "readme_pkgconfig_command_$pc"
    else
        bad "readme_pkgconfig_command_$pc"; cat "$root/readme-$pc.err" "$root/readme-$pc.out" 2>/dev/null
    fi
done

# The ABI guard: headers of one variant, library of the other.
for pair in "largesteps largesteps-float" "largesteps-float largesteps"; do
    set -- $pair
    # shellcheck disable=SC2046
    if cc -std=c99 tests/tools/install_probe.c $(pkg-config --cflags "$1") $(pkg-config --libs --static "$2") \
          -o "$root/mismatch" > "$root/mismatch.err" 2>&1; then
        bad "abi_guard_$1_headers_with_$2_library_fails_to_link"
    elif grep -q 'ls_arena_init_f' "$root/mismatch.err"; then
        ok "abi_guard_$1_headers_with_$2_library_fails_to_link"
    else
        bad "abi_guard_$1_headers_with_$2_library_fails_to_link (failed for another reason)"; cat "$root/mismatch.err"
    fi
done

echo "install: $pass passed, $fail failed"
[ "$fail" = 0 ]
