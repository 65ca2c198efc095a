#!/bin/sh
# tests/bench/run_workers.sh - the fit's time per iteration against the mesh's
# vertices, the resolution and the threads that share the views
# (`largesteps fit --threads N`): the embedded bunny's targets, an icosphere
# of level 3, 4 and 5 (642, 2562, 10242 vertices) held at its size (no
# remeshing), 32 views with 16 an iteration, ITERS iterations; for each, the
# time per iteration with 1 thread and with THREADS, their ratio, and whether
# the two results are the same bytes. Then the whole default fit, 1 thread
# against THREADS, PAIRS times in turn, and the median of the pairs' speed-ups.
# Writes $BUILD/bench/workers.md and prints it.
# Environment: BUILD (build), ITERS (60), THREADS (2), PAIRS (5), LEVELS
# ("3 4 5"), RESOLUTIONS ("128 256").
set -e
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
ITERS=${ITERS:-60}
THREADS=${THREADS:-2}
PAIRS=${PAIRS:-5}
OUT=$BUILD/bench/workers
mkdir -p "$OUT"
make -s BUILD="$BUILD" all
per_it() { sed -n 's/^time per iteration \([0-9.]*\) ms.*/\1/p' "$1"; }
{
    echo "# Threads"
    echo
    echo "Time per iteration of \`largesteps fit\` (the embedded bunny's 32 views, 16 an iteration; an icosphere held at"
    echo "its level, no remeshing; $ITERS iterations) with 1 thread and with $THREADS, on $(nproc) processors."
    echo "Same: the two runs' result.obj and losses identical. Measured $(date -u +%Y-%m-%d)."
    echo "Command: \`sh tests/bench/run_workers.sh\`"
    echo
    echo "| vertices | resolution | 1 thread ms | $THREADS threads ms | speed-up | same bits |"
    echo "|---:|---:|---:|---:|---:|---|"
    for res in ${RESOLUTIONS:-128 256}; do
        for level in ${LEVELS:-3 4 5}; do
            for t in 1 "$THREADS"; do
                "$BUILD/largesteps" fit --level "$level" --res "$res" --iters "$ITERS" --remesh none --no-guard \
                    --track 0 --threads "$t" --quiet -o "$OUT/l$level-r$res-t$t" > "$OUT/l$level-r$res-t$t.log" 2>&1 || true
            done
            a=$(per_it "$OUT/l$level-r$res-t1.log")
            b=$(per_it "$OUT/l$level-r$res-t$THREADS.log")
            same=no
            if cmp -s "$OUT/l$level-r$res-t1/result.obj" "$OUT/l$level-r$res-t$THREADS/result.obj" &&
                [ "$(cut -d, -f1,2 "$OUT/l$level-r$res-t1/log.csv")" = "$(cut -d, -f1,2 "$OUT/l$level-r$res-t$THREADS/log.csv")" ]; then
                same=yes
            fi
            v=$(sed -n 's/.*initial mesh: \([0-9]*\) vertices.*/\1/p' "$OUT/l$level-r$res-t1.log")
            awk -v v="$v" -v r="$res" -v a="$a" -v b="$b" -v s="$same" \
                'BEGIN { printf "| %s | %s² | %.2f | %.2f | %.2f | %s |\n", v, r, a, b, (b > 0 ? a / b : 0), s }'
        done
    done
    echo
    echo "The whole default fit (\`largesteps fit\`: 800 iterations, remeshes, self-intersection checks, the"
    echo "target's renders, the final metrics and the contact sheet), $PAIRS pairs of runs, 1 thread then"
    echo "$THREADS, in turn (a pair's two runs see about the same machine); wall seconds and each pair's ratio:"
    echo
    echo "| pair | 1 thread s | $THREADS threads s | speed-up |"
    echo "|---:|---:|---:|---:|"
    : > "$OUT/pairs.txt"
    k=1
    while [ "$k" -le "$PAIRS" ]; do
        for t in 1 "$THREADS"; do
            s0=$(date +%s.%N)
            "$BUILD/largesteps" fit --threads "$t" --track 0 --quiet -o "$OUT/default-t$t" > "$OUT/default-t$t.log" 2>&1 || true
            s1=$(date +%s.%N)
            eval "wall_$t=\$(awk -v a=\"\$s0\" -v b=\"\$s1\" 'BEGIN { printf \"%.2f\", b - a }')"
        done
        eval "w1=\$wall_1; wt=\$wall_$THREADS"
        awk -v k="$k" -v a="$w1" -v b="$wt" 'BEGIN { printf "| %d | %.2f | %.2f | %.3f |\n", k, a, b, (b > 0 ? a / b : 0) }'
        awk -v a="$w1" -v b="$wt" 'BEGIN { printf "%.4f\n", (b > 0 ? a / b : 0) }' >> "$OUT/pairs.txt"
        k=$((k + 1))
    done
    same=no
    cmp -s "$OUT/default-t1/result.obj" "$OUT/default-t$THREADS/result.obj" &&
        cmp -s "$OUT/default-t1/contact.png" "$OUT/default-t$THREADS/contact.png" && same=yes
    echo
    sort -n "$OUT/pairs.txt" | awk -v s="$same" '{ r[NR] = $1 } END {
        m = NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2
        printf "median speed-up %.2f (min %.2f, max %.2f); result.obj and contact.png the same bytes: %s\n", m, r[1], r[NR], s }'
} > "$OUT.md"
cat "$OUT.md"
