#!/bin/sh
# m4_size.sh [--update] - code size per module of the Cortex-M4 float build
# (-Os -ffunction-sections -fdata-sections, linked with --gc-sections, every
# public ls_ function kept), checked against fixtures/size-cortex-m4.txt:
# a module over its limit, or without one, fails. --update rewrites the
# limits (measured + 10%, rounded up to 64 bytes): commit them with the change.
# Prints the table, "ok/FAIL size_<module>" lines and "size: N passed, M failed".
build=build/size-cortex-m4
thresholds=fixtures/size-cortex-m4.txt
mkdir -p "$build"
if ! make --no-print-directory -j"${JOBS:-2}" TARGET=cortex-m4 REAL=float BUILD="$build" \
        OPT="-Os -ffp-contract=off -fno-fast-math" lib > "$build/make.log" 2>&1; then
    cat "$build/make.log"
    echo "FAIL size_build (the Cortex-M4 -Os build failed)"
    echo "size: 0 passed, 1 failed"
    exit 1
fi
objs=$(ls "$build"/obj/src/*.o)
# Keep every public function (the whole API) and let --gc-sections drop the rest.
# shellcheck disable=SC2086
keep=$(arm-none-eabi-nm -g --defined-only $objs | awk 'NF == 3 {print "-Wl,--undefined=" $3}' | sort -u)
# shellcheck disable=SC2086
if ! arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -nostartfiles --specs=nosys.specs \
        -Wl,--gc-sections -Wl,-e,ls_version -Wl,-Map="$build/lib.map" $keep $objs -lm -o "$build/lib.elf" \
        > "$build/link.log" 2>&1; then
    cat "$build/link.log"
    echo "FAIL size_link (linking the Cortex-M4 size build failed)"
    echo "size: 0 passed, 1 failed"
    exit 1
fi
python3 tests/tools/m4_size.py "$build/lib.map" "$thresholds" "$build/obj/src/" "$@"
