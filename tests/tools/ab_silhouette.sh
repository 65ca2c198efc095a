#!/bin/sh
# ab_silhouette.sh OLD.c NEW.c [MESH [REPS [RES]]] - times two versions of
# src/render/silhouette.c against each other in one process (tests/bench/ab_silhouette.c):
# each is compiled as the library compiles it, its entry point renamed to
# ls_silhouette_backward_A (OLD) or _B (NEW) and every other symbol made
# local, then linked with the library of the current tree (make lib first).
# Example: git show HEAD~1:src/render/silhouette.c > /tmp/old.c &&
#          sh tests/tools/ab_silhouette.sh /tmp/old.c src/render/silhouette.c
set -e
[ $# -ge 2 ] || { echo "usage: $0 OLD.c NEW.c [MESH [REPS [RES]]]" >&2; exit 2; }
out=build/ab
mkdir -p "$out"
mesh=${3:-$out/armadillo.obj}
[ -n "$3" ] || gzip -dc fixtures/meshes/armadillo.obj.gz > "$mesh"
flags="-std=c99 -O2 -ffp-contract=off -fno-fast-math -Iinclude -Ibuild/include -Isrc/render"
for side in A B; do
    if [ "$side" = A ]; then src=$1; else src=$2; fi
    # shellcheck disable=SC2086 # $flags is a list of options
    ${CC:-cc} $flags -c "$src" -o "$out/$side.o"
    objcopy --redefine-sym ls_silhouette_backward=ls_silhouette_backward_$side \
        -G ls_silhouette_backward_$side "$out/$side.o" "$out/${side}_local.o"
done
${CC:-cc} -std=c99 -O2 -ffp-contract=off -Iinclude -Ibuild/include -Itests -Iport/posix tests/bench/ab_silhouette.c \
    "$out/A_local.o" "$out/B_local.o" build/liblargesteps-posix.a build/liblargesteps.a -lm -o "$out/ab_silhouette"
"$out/ab_silhouette" "$mesh" "${4:-40}" "${5:-512}"
