#!/bin/sh
# tests/bench/run_workers.sh - the fit's time per iteration against the mesh's
# vertices, the resolution and the threads that share the views
# (`largesteps fit --threads N`): the embedded bunny's targets, an icosphere
# of level 3, 4 and 5 (642, 2562, 10242 vertices) held at its size (no
# remeshing), 32 views with 16 an iteration, ITERS iterations; for each, the
# time per iteration with 1 thread and with THREADS, their ratio, and whether
# the two results are the same bytes. Then the whole default fit, PAIRS
# rounds of 1 thread, THREADS threads, and THREADS one-thread runs at once:
# the last is the machine's ceiling (processors that share a core, or slow
# down when all are busy, give less than THREADS times one), and the
# speed-up's median is printed with it and with their ratio, the efficiency.
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
    echo "target's renders, the final metrics and the contact sheet), $PAIRS rounds: 1 thread, then $THREADS threads,"
    echo "then $THREADS one-thread runs at once (the peer: what the machine gives $THREADS busy processors; its"
    echo "ceiling is $THREADS x the lone run's time over theirs, the most $THREADS threads could gain). Wall seconds;"
    echo "efficiency is the speed-up over the ceiling:"
    echo
    echo "| round | 1 thread s | $THREADS threads s | speed-up | $THREADS runs at once s | ceiling | efficiency |"
    echo "|---:|---:|---:|---:|---:|---:|---:|"
    : > "$OUT/pairs.txt"
    # wall seconds of `largesteps ARGS`, or with `peer` of THREADS one-thread
    # default fits started together (until the last ends)
    wall() {
        s0=$(date +%s.%N)
        if [ "$1" = peer ]; then
            j=1
            while [ "$j" -le "$THREADS" ]; do
                "$BUILD/largesteps" fit --threads 1 --track 0 --quiet -o "$OUT/peer-$j" > "$OUT/peer-$j.log" 2>&1 &
                j=$((j + 1))
            done
            wait
        else
            "$BUILD/largesteps" "$@" > "$OUT/run.log" 2>&1 || true
        fi
        awk -v a="$s0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }'
    }
    k=1
    while [ "$k" -le "$PAIRS" ]; do
        w1=$(wall fit --threads 1 --track 0 --quiet -o "$OUT/default-t1")
        wt=$(wall fit --threads "$THREADS" --track 0 --quiet -o "$OUT/default-t$THREADS")
        wp=$(wall peer)
        awk -v k="$k" -v a="$w1" -v b="$wt" -v p="$wp" -v n="$THREADS" -v f="$OUT/pairs.txt" 'BEGIN {
            s = b > 0 ? a / b : 0; c = p > 0 ? n * a / p : 0; e = c > 0 ? s / c : 0
            printf "| %d | %.2f | %.2f | %.3f | %.2f | %.3f | %.3f |\n", k, a, b, s, p, c, e
            printf "%.4f %.4f %.4f\n", s, c, e >> f }'
        k=$((k + 1))
    done
    same=no
    cmp -s "$OUT/default-t1/result.obj" "$OUT/default-t$THREADS/result.obj" &&
        cmp -s "$OUT/default-t1/contact.png" "$OUT/default-t$THREADS/contact.png" && same=yes
    echo
    # the median, least and most of column $1 of pairs.txt
    median() { cut -d' ' -f"$1" "$OUT/pairs.txt" | sort -n | awk '{ r[NR] = $1 } END {
        printf "%.2f (min %.2f, max %.2f)", NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2, r[1], r[NR] }'; }
    echo "median speed-up $(median 1); ceiling $(median 2); efficiency $(median 3)"
    echo "result.obj and contact.png the same bytes with 1 and $THREADS threads: $same"
} > "$OUT.md"
cat "$OUT.md"
