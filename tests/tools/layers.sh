#!/bin/sh
# layers.sh [ROOT] - the library's layering: src/ has one folder per layer,
# listed lowest first by the Makefile's LAYERS line. A source file or private
# header may include only headers of its own layer or a lower one, and so may
# a public header (include/largesteps/X.h belongs to the layer of src/*/X.c).
# Prints one line per upward include and exits 1 if there is any.
root=${1:-.}
layers=$(sed -n 's/^LAYERS *:= *//p' "$root/Makefile")
[ -n "$layers" ] || { echo "layers.sh: no LAYERS line in $root/Makefile" >&2; exit 2; }
rank=0 map=
for l in $layers; do
    for f in "$root/src/$l"/*.c "$root/src/$l"/*.h; do
        [ -e "$f" ] || continue
        n=$(basename "$f"); map="$map ${n%.*}=$rank:$l"
    done
    rank=$((rank + 1))
done
# Every file that includes: src/<layer>/*.[ch] and the public headers.
files=$(ls "$root"/src/*/*.[ch] "$root"/include/largesteps/*.h)
# shellcheck disable=SC2086 # $files is a list of paths without spaces
awk -v map="$map" -v root="$root/" '
BEGIN {
    n = split(map, kv, " ")
    for (i = 1; i <= n; i++) { split(kv[i], a, "="); split(a[2], b, ":"); rk[a[1]] = b[1] + 0; ly[a[1]] = b[2] }
    bad = 0
}
FNR == 1 {
    name = FILENAME; sub(/.*\//, "", name); sub(/\.[ch]$/, "", name)
    where = FILENAME; sub("^" root, "", where)
    if (!(name in rk) && name != "config") { print where ": belongs to no layer (no src/<layer>/" name ".c)"; bad = 1 }
}
/^[ \t]*#[ \t]*include/ {
    inc = $0
    if (inc ~ /<largesteps\//) { sub(/.*<largesteps\//, "", inc); sub(/\.h>.*/, "", inc) }
    else if (inc ~ /"[a-z_0-9]+\.h"/) { sub(/[^"]*"/, "", inc); sub(/\.h".*/, "", inc) }
    else next
    if (inc == "config" || !(name in rk)) next
    if (!(inc in rk)) { print where ": includes " inc ".h, which belongs to no layer"; bad = 1; next }
    if (rk[inc] > rk[name]) {
        print where " (layer " ly[name] ") includes " inc ".h of the higher layer " ly[inc]
        bad = 1
    }
}
END { exit bad }' $files
