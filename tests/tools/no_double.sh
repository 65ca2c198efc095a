#!/bin/sh
# no_double.sh OBJDIR INCDIR - the float build for Cortex-M4 (a single-
# precision FPU: double arithmetic is software) must contain no double
# arithmetic. The objects in OBJDIR are linked with --gc-sections, keeping
# every public function except the explicitly double-precision API (functions
# whose prototype in include/largesteps/*.h, read with INCDIR's config.h, has
# a `double` parameter or result, e.g. ls_sin next to ls_sinf); the linked
# image must then contain none of the helpers of double arithmetic: the ARM
# EABI ones (__aeabi_dadd, __aeabi_dmul, __aeabi_dcmp*, __aeabi_d2f,
# __aeabi_d2iz, __aeabi_f2d, __aeabi_i2d, __aeabi_l2d, ...), libgcc's generic
# ones (__adddf3, __extendsfdf2, ...) or libm's double functions (sqrt, ...).
# On failure prints which library object pulled in which helper.
objdir=$1 incdir=$2
[ -d "$objdir" ] || { echo "no_double.sh: no object directory '$objdir'" >&2; exit 2; }
cc="arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16"
work=$objdir/../no-double
mkdir -p "$work"
objs=$(ls "$objdir"/*.o)
# The double-precision API, from gcc's own reading of the headers.
: > "$work/api.c"
for h in include/largesteps/*.h; do
    [ "$(basename "$h")" = config.h ] || echo "#include <largesteps/$(basename "$h")>" >> "$work/api.c"
done
: > "$work/api.txt"
if [ -s "$work/api.c" ] && [ -n "$incdir" ]; then
    $cc -std=c99 -Iinclude -I"$incdir" -fsyntax-only -aux-info "$work/api.txt" "$work/api.c" || exit 2
fi
grep 'largesteps/' "$work/api.txt" | grep -w double | sed -n 's/.* \([A-Za-z_0-9]*\) (.*/\1/p' | sort -u > "$work/double_api.txt"
# shellcheck disable=SC2086
arm-none-eabi-nm -g --defined-only $objs | awk 'NF == 3 {print $3}' | sort -u > "$work/public.txt"
keep=$(comm -23 "$work/public.txt" "$work/double_api.txt" | sed 's/^/-Wl,--undefined=/')
first=$(comm -23 "$work/public.txt" "$work/double_api.txt" | head -n 1)
# shellcheck disable=SC2086
if ! $cc -nostartfiles --specs=nosys.specs -Wl,--gc-sections -Wl,-e,"$first" -Wl,-Map="$work/link.map" \
        $keep $objs -lm -o "$work/float.elf" > "$work/link.log" 2>&1; then
    cat "$work/link.log"
    exit 2
fi
pattern='^(__aeabi_(d[a-z0-9]+|[a-z0-9]+2d)|__[a-z]+df[0-9]|__[a-z]+df[a-z]+[0-9]|sqrt|sin|cos|tan|atan2?|exp|log|log10|pow|floor|ceil|fabs|fmod|round|trunc)$'
bad=$(arm-none-eabi-nm --defined-only "$work/float.elf" | awk '{print $NF}' | grep -E "$pattern" | sort -u | tr '\n' ' ')
if [ -z "$bad" ]; then
    echo "$(wc -l < "$work/public.txt") public functions kept but $(wc -l < "$work/double_api.txt") of the double API: no double arithmetic"
    exit 0
fi
echo "double arithmetic linked in: $bad"
# Who calls them: the call graph of the linked code (after --gc-sections);
# a function is tainted when it calls a double helper or a tainted function
# (libgcc's float -> 64-bit integer conversions are done in double, for one).
# Printed: each tainted function outside the helpers and what it calls.
arm-none-eabi-objdump -d --no-show-raw-insn "$work/float.elf" | awk -v pat="$pattern" '
    /^[0-9a-f]+ <[^>]+>:$/ {fn = $2; gsub(/[<>:]/, "", fn); next}
    /\t(bl|blx|b|b\.w|b\.n)[ \t]+[0-9a-f]+ <[^>+]+>/ {
        t = $NF; gsub(/[<>]/, "", t)
        if (t != fn) { n++; from[n] = fn; to[n] = t }
    }
    END {
        for (i = 1; i <= n; i++) if (to[i] ~ pat) bad[to[i]] = 1
        do {
            changed = 0
            for (i = 1; i <= n; i++) if ((to[i] in bad) && !(from[i] in bad)) { bad[from[i]] = 1; changed = 1 }
        } while (changed)
        for (i = 1; i <= n; i++)
            if ((to[i] in bad) && from[i] !~ /^__/) print "  " from[i] " calls " to[i]
    }' | sort -u | head -n 40
exit 1
