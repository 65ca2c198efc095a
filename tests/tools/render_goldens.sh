#!/bin/sh
# render_goldens.sh - (re)writes the golden renders of `largesteps render` listed in
# fixtures/render/goldens.txt: for each set NAME, the contact sheet as
# fixtures/render/NAME__contact.png and the first view as NAME__view_000.png,
# re-encoded losslessly by oiiotool (zlib-compressed PNG, same integers; our own
# encoder writes stored deflate blocks). Goldens are never regenerated to make a
# failing test pass without a written reason in fixtures/render/README.md.
#   sh tests/tools/render_goldens.sh [BUILD_DIR]   (default build/gcc-double)
set -e
B=${1:-build/gcc-double}
make --no-print-directory BUILD=$B CC=gcc CXX=g++ REAL=double all >/dev/null
T=build/render-goldens
rm -rf $T
mkdir -p $T
grep -v '^#' fixtures/render/goldens.txt | while read -r name mesh args; do
    [ -n "$name" ] || continue
    # shellcheck disable=SC2086
    $B/largesteps render "$mesh" $args -o $T/$name >$T/$name.log
    for f in contact view_000; do
        oiiotool --nosoftwareattrib --iconfig oiio:UnassociatedAlpha 1 $T/$name/$f.png -o fixtures/render/${name}__$f.png
        idiff -fail 0 -warn 0 $T/$name/$f.png fixtures/render/${name}__$f.png >/dev/null
        echo "wrote fixtures/render/${name}__$f.png"
    done
done
