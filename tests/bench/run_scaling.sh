#!/bin/sh
# tests/bench/run_scaling.sh - the fit's time per iteration against the mesh's
# size: icospheres of level 4 to 7 (2562 to 163842 vertices) and the
# Nefertiti scan remeshed (--init-coarse 0.004: about 58k vertices), held at
# their size (no remeshing, no guard), at 256² and 512², 16 and 25 views (all
# of them every iteration), ITERS iterations. Per run: the stages of an
# iteration on one thread (render, shading backward, silhouettes, solves,
# optimizer), the set-up (Laplacian, ordering, factor), the time per
# iteration with THREADS threads and the speed-up; then, between consecutive
# sphere levels, each stage's growth exponent (log time ratio / log vertex
# ratio; n log n is about 1.1 here, n^1.5 is 1.5). Writes
# $BUILD/bench/scaling.md and prints it.
# Environment: BUILD (build), ITERS (5), THREADS (2), LEVELS ("4 5 6 7"),
# RESOLUTIONS ("256 512"), VIEWS ("16 25"), SCAN (../shared/meshes/nefertiti.obj;
# empty: none).
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
ITERS=${ITERS:-5}
THREADS=${THREADS:-2}
SCAN=${SCAN-../shared/meshes/nefertiti.obj}
[ -n "$SCAN" ] && [ ! -e "$SCAN" ] && SCAN=
OUT=$BUILD/bench/scaling
mkdir -p "$OUT"
make -s BUILD="$BUILD" all
# run NAME THREADS ARGS...: the stage line and the set-up of one run into $OUT/NAME-tT.log
run() {
    name=$1 t=$2
    shift 2
    "$BUILD/largesteps" fit "$@" --iters "$ITERS" --remesh none --no-guard --track 0 --threads "$t" --quiet \
        -o "$OUT/$name-t$t" > "$OUT/$name-t$t.log" 2>&1 || true
}
stages() { # log -> "total render shade_bw silhouettes solves optimizer setup vertices" (ms)
    awk '/^time per iteration/ { gsub(/[:,]/, ""); t = $4; r = $7; b = $10; s = $12; v = $14; o = $16 }
         /^set-up/ { u = $2 }
         /initial mesh:/ { for (i = 1; i <= NF; i++) if ($i == "mesh:") n = $(i + 1) }
         END { printf "%s %s %s %s %s %s %s %s\n", t, r, b, s, v, o, u, n }' "$1"
}
{
    echo "# Scaling"
    echo
    echo "Milliseconds per iteration of \`largesteps fit\` against the mesh's vertices (held at its size: no"
    echo "remeshing, no guard; every view each iteration; $ITERS iterations; the embedded bunny's targets, or"
    echo "the scan's own). Stages on 1 thread; the last columns with $THREADS threads, on $(nproc) processors."
    echo "Set-up: the Laplacian, the ordering and the factor, once per mesh. Measured $(date -u +%Y-%m-%d)."
    echo "Command: \`sh tests/bench/run_scaling.sh\`"
    echo
    echo "| mesh | vertices | res | views | render | shading bw | silhouettes | solves | optimizer | 1 thread | $THREADS threads | speed-up | set-up s |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for res in ${RESOLUTIONS:-256 512}; do
        for views in ${VIEWS:-16 25}; do
            meshes=""
            for level in ${LEVELS:-4 5 6 7}; do meshes="$meshes l$level"; done
            [ -n "$SCAN" ] && meshes="$meshes scan"
            for m in $meshes; do
                name=$m-r$res-v$views
                if [ "$m" = scan ]; then
                    set -- "$SCAN" --init-coarse 0.004
                else
                    set -- --level "${m#l}"
                fi
                run "$name" 1 "$@" --res "$res" --views "$views" --batch 0
                run "$name" "$THREADS" "$@" --res "$res" --views "$views" --batch 0
                a=$(stages "$OUT/$name-t1.log")
                b=$(stages "$OUT/$name-t$THREADS.log")
                echo "$m $res $views $a" >> "$OUT/rows.txt.$$"
                echo "$a" | awk -v m="$m" -v r="$res" -v w="$views" -v b="$b" '{
                    split(b, q, " ");
                    printf "| %s | %s | %s² | %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.1f | %.1f | %.2f | %.2f |\n",
                        (m == "scan" ? "Nefertiti scan" : "icosphere " substr(m, 2)), $8, r, w, $2, $3, $4, $5, $6,
                        $1, q[1], (q[1] > 0 ? $1 / q[1] : 0), $7 / 1000 }'
            done
        done
    done
    echo
    echo "Growth exponent of each stage between consecutive sphere levels (4x the vertices):"
    echo
    echo "| res | views | vertices | render | shading bw | silhouettes | solves | whole iteration | set-up |"
    echo "|---:|---:|---|---:|---:|---:|---:|---:|---:|"
    awk '$1 ~ /^l/ { key = $2 " " $3; if (key in prev) { split(prev[key], p, " ");
            k = log($11 / p[11]);
            printf "| %s² | %s | %d -> %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", $2, $3, p[11], $11,
                log($5 / p[5]) / k, log($6 / p[6]) / k, log($7 / p[7]) / k, log($8 / p[8]) / k, log($4 / p[4]) / k,
                log($10 / p[10]) / k }
          prev[key] = $0 }' "$OUT/rows.txt.$$"
    rm -f "$OUT/rows.txt.$$"
} > "$OUT.md"
cat "$OUT.md"
