#!/bin/sh
# fit_suite.sh - `make bench-fit`: `largesteps fit` with default options on
# every target of tests/bench/fit_suite.txt (or SUITE_LIST), plus PERTURBED runs per target
# whose learning rate is moved in the 6th digit (--perturb 1..N), and one
# Markdown table: dense symmetric Hausdorff and RMS over the target's
# bounding-box diagonal, self-intersecting pairs, iterations, time, the job's
# reserved bytes and the process's peak memory, and the worst perturbed run.
#
#   sh tests/bench/fit_suite.sh [TARGET ...] [-- FIT OPTIONS]
#
# Environment: SUITE_LIST (tests/bench/fit_suite.txt; tests/bench/fit_suite_cad.txt
# lists CAD parts), BUILD (build), JOBS (2: runs at once), PERTURBED (5),
# SUITE_OUT ($BUILD/bench/fit_suite), SHARED (../shared/meshes), CGAL_DATA
# (/usr/share/doc/libcgal-dev/data.tar.gz, Debian's libcgal-demo).
# Targets whose file is not there are listed as skipped.
# Writes $SUITE_OUT.md and prints it.
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
JOBS=${JOBS:-2}
PERTURBED=${PERTURBED:-5}
OUT=${SUITE_OUT:-$BUILD/bench/fit_suite}
SHARED=${SHARED:-../shared/meshes}
CGAL_DATA=${CGAL_DATA:-/usr/share/doc/libcgal-dev/data.tar.gz}
SUITE_LIST=${SUITE_LIST:-tests/bench/fit_suite.txt}
export SUITE_LIST
args="$*"
only=
while [ $# -gt 0 ] && [ "$1" != -- ]; do only="$only $1"; shift; done
[ "$1" = -- ] && shift
extra="$*"
make -s BUILD="$BUILD" all
mkdir -p "$OUT/meshes"
# The CGAL meshes, unpacked once.
if [ -r "$CGAL_DATA" ] && [ ! -e "$OUT/meshes/.cgal" ]; then
    tar -xzf "$CGAL_DATA" -C "$OUT/meshes" --strip-components=2 data/meshes && touch "$OUT/meshes/.cgal"
fi
list=$OUT/runs.txt
: > "$list"
sed -e 's/#.*//' "$SUITE_LIST" | while read -r name where file what; do
    [ -n "$name" ] || continue
    if [ -n "$only" ] && ! echo " $only " | grep -q " $name "; then continue; fi
    case $where in
        fixture) path=fixtures/meshes/$file ;;
        shared) path=$SHARED/$file ;;
        cgal) path=$OUT/meshes/$file ;;
        *) echo "$SUITE_LIST: unknown place '$where' for $name" >&2; exit 2 ;;
    esac
    if [ ! -r "$path" ]; then echo "$name skipped $path"; continue; fi
    k=0
    while [ $k -le "$PERTURBED" ]; do echo "$name $k $path"; k=$((k + 1)); done
done >> "$list"
grep ' skipped ' "$list" | sed 's/^/not found: /' >&2 || true
# One run: OUT/NAME/K/ holds the program's files, its output, exit status and
# rusage (elapsed seconds, peak resident KiB). xargs appends "NAME K PATH".
grep -v ' skipped ' "$list" | xargs -P "$JOBS" -L 1 sh -c '
    out="$0/$3/$4"; mkdir -p "$out"
    # shellcheck disable=SC2086 # $2: extra fit options, a list
    /usr/bin/time -f "%e %M" -o "$out/rusage" "$1" fit "$5" --perturb "$4" --quiet --track 0 --threads 1 $2 -o "$out" \
        > "$out/stdout" 2>&1
    echo $? > "$out/rc"
' "$OUT" "$BUILD/largesteps" "$extra" || true
python3 tests/bench/fit_suite_table.py "$OUT" "$list" "sh tests/bench/fit_suite.sh $args" > "$OUT.md"
cat "$OUT.md"
