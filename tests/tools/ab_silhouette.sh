#!/bin/sh
# ab_silhouette.sh OLD NEW [MESH [REPS [RES]]] - times two versions of the
# silhouette pass against each other in one process (tests/bench/ab_silhouette.c).
# OLD and NEW are folders holding the pass's sources (silhouette*.c and
# silhouette_internal.h, as in src/render); AB_FLAGS_A and AB_FLAGS_B add
# compiler flags to one side (for example -DLS_SIL_OFF=16: docs/fast-paths.md).
# Each side is compiled as the library compiles it, its objects joined into
# one, its entry point renamed to ls_silhouette_backward_A (OLD) or _B (NEW)
# and every other symbol made local, then linked with the library of the
# current tree (make lib first).
# Example: mkdir -p /tmp/old && git archive HEAD~1 src/render | tar -x -C /tmp/old &&
#          sh tests/tools/ab_silhouette.sh /tmp/old/src/render src/render
set -e
[ $# -ge 2 ] || { echo "usage: $0 OLD_DIR NEW_DIR [MESH [REPS [RES]]]" >&2; exit 2; }
out=build/ab
mkdir -p "$out"
mesh=${3:-$out/armadillo.obj}
[ -n "$3" ] || gzip -dc fixtures/meshes/armadillo.obj.gz > "$mesh"
flags="-std=c99 -O2 -ffp-contract=off -fno-fast-math -Iinclude -Ibuild/include"
for side in A B; do
    if [ "$side" = A ]; then dir=$1 extra=$AB_FLAGS_A; else dir=$2 extra=$AB_FLAGS_B; fi
    rm -f "$out/$side"-*.o
    for src in "$dir"/silhouette*.c; do
        # shellcheck disable=SC2086 # $flags and $extra are lists of options
        ${CC:-cc} $flags $extra -I"$dir" -Isrc/render -c "$src" -o "$out/$side-$(basename "$src" .c).o"
    done
    ld -r -o "$out/$side.o" "$out/$side"-*.o
    objcopy --redefine-sym ls_silhouette_backward=ls_silhouette_backward_$side \
        -G ls_silhouette_backward_$side "$out/$side.o" "$out/${side}_local.o"
done
${CC:-cc} -std=c99 -O2 -ffp-contract=off -Iinclude -Ibuild/include -Itests -Iport/posix tests/bench/ab_silhouette.c \
    "$out/A_local.o" "$out/B_local.o" build/liblargesteps-posix.a build/liblargesteps.a -lm -o "$out/ab_silhouette"
"$out/ab_silhouette" "$mesh" "${4:-40}" "${5:-512}"
