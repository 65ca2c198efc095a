#!/bin/sh
# stage_fit_suite.sh - the fit suite shortened (a stage of `make test`; the
# whole suite is `make bench-fit`): `largesteps fit` with its defaults on three
# small targets of the kinds the default must handle (the bunny's ears; the
# elephant, genus 3: its own start; the camel's thin legs, grown from the
# sphere; the cross, a CAD part, shown with its creases) at 64 x 64, 8 views,
# 300 iterations, remeshes before 100 and 200, three runs each with the
# learning rate moved in the 6th digit (--perturb); and the cactus, whose thin
# arms fold the sphere's first steps, once at 128 x 128 and 32 views.
# Asserted: every run ends without a self-intersecting face pair (exit status
# 0; 3 would say it tangled), and the median dense Hausdorff distance over the
# runs stays within the target's bound. The loop without the guard and from
# the sphere (--no-guard --init-sphere, the earlier default) fails both:
# 451 pairs on the camel, 55 and H 10.3 % on the elephant, 21 on the bunny;
# the cross rendered smooth (FIT_SUITE_EXTRA="--target-normals smooth", the
# earlier default) ends at H 4.53, 4.22 and 4.18 %, with its creases 0.91,
# 1.23 and 0.90 %.
# Runs are deterministic: the same bits on every machine and thread count (each
# run on one thread: JOBS runs share the cores). FIT_SUITE_EXTRA adds
# options to every run (FIT_SUITE_EXTRA="--no-guard --init-sphere" shows the
# failures above).
jobs=${JOBS:-2}
build=build/cli
out=$build/fit_suite
pass=0 fail=0
mkdir -p build/logs "$build"
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
if ! make --no-print-directory -j"$jobs" BUILD="$build" CC=gcc REAL=double all > build/logs/fit-suite-build.log 2>&1; then
    tail -n 20 build/logs/fit-suite-build.log
    bad "fit_suite_build"
    echo "fit_suite: $pass passed, $fail failed"
    exit 1
fi
rm -rf "$out"
mkdir -p "$out"
# name, file, bound on the median H / diagonal (%)
# The bunny at 64 x 64 from 8 views is bimodal (an ear grown or not): runs
# --perturb 0..6 gave H 2.4, 2.8, 3.3, 12.7, 6.6, 13.4, 1.8 % with each view's
# gradient added to the running total, 16.0, 5.8, 2.8, 10.7, 1.8, 3.5, 13.0 %
# with each view's gradient from zero (the order that lets threads share the
# views), so its bound is 7 %; the guard's pairs are what this stage tells apart.
targets="bunny:fixtures/meshes/bunny.obj:7 elephant:fixtures/meshes/elephant.obj:6 camel:fixtures/meshes/camel.off.gz:14
    cross:fixtures/meshes/cross.off:2.5"
for t in $targets; do
    name=${t%%:*} rest=${t#*:}
    for k in 0 1 2; do echo "$name ${rest%%:*} $k"; done
done | xargs -P "$jobs" -L 1 sh -c '
    # $2 name, $3 file, $4 run (xargs appends them)
    # shellcheck disable=SC2086 # FIT_SUITE_EXTRA: a list of options
    "$0" fit "$3" --res 64 --views 8 --iters 300 --remesh 100,200 --perturb "$4" --threads 1 --quiet --track 0 $FIT_SUITE_EXTRA \
        -o "$1/$2-$4" > "$1/$2-$4.log" 2>&1
    echo $? > "$1/$2-$4.rc"
' "$build/largesteps" "$out"
# A JSON number field (first occurrence) from a metrics.json.
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1" | head -n 1; }
for t in $targets; do
    name=${t%%:*} bound=${t##*:}
    hs= rcs=
    for k in 0 1 2; do
        rcs="$rcs $(cat "$out/$name-$k.rc" 2>/dev/null || echo missing)"
        h=$(field "$out/$name-$k/metrics.json" hausdorff_rel)
        hs="$hs $(awk -v h="${h:-1}" 'BEGIN { printf "%.2f", 100 * h }')"
    done
    if [ "$rcs" = " 0 0 0" ]; then ok "fit_suite_${name}_untangled (exit status 0 in all 3 runs)"
    else bad "fit_suite_${name}_untangled (exit statuses$rcs; 3: self-intersections, see $out/$name-*.log)"; fi
    med=$(printf '%s\n' $hs | sort -n | sed -n 2p)
    if awk -v m="$med" -v b="$bound" 'BEGIN { exit !(m + 0 <= b + 0) }'; then
        ok "fit_suite_${name}_close (median H/diag $med % <= $bound %; runs$hs)"
    else
        bad "fit_suite_${name}_close (median H/diag $med % > $bound %; runs$hs)"
    fi
done
# A scheduled remesh long after the last check (--guard 100): the guard checks
# the mesh before remeshing it, so a tangle since the check is rolled back
# instead of remeshed into the checkpoint. Remeshing first ended these runs
# with 4 pairs (the elephant, from the coarse start of that time: 0.03 of its
# diagonal, remeshes to half the mean edge) and 67 (the camel).
for t in "elephant:fixtures/meshes/elephant.obj:199,299:0:--init-coarse 0.03 --remesh-h 0.5" \
    "camel:fixtures/meshes/camel.off.gz:149,249:1:"; do
    name=${t%%:*} rest=${t#*:}
    file=${rest%%:*} rest=${rest#*:}
    at=${rest%%:*} rest=${rest#*:}
    # shellcheck disable=SC2086 # the start's options: a list
    "$build/largesteps" fit "$file" --res 64 --views 8 --iters 320 --guard 100 --remesh "$at" --perturb "${rest%%:*}" \
        ${rest#*:} --threads 1 --quiet --track 0 -o "$out/$name-late" > "$out/$name-late.log" 2>&1
    rc=$?
    if [ "$rc" = 0 ]; then ok "fit_suite_${name}_checked_before_remesh (exit status 0)"
    else bad "fit_suite_${name}_checked_before_remesh (exit status $rc; 3: self-intersections, see $out/$name-late.log)"; fi
done
# The cactus (thin arms, grown from the sphere) at the default 128 x 128 and 32 views, 300
# iterations: the sphere's first steps fold it, and each check that finds it folded rolls the fit
# back to its start. With a check every 25 iterations throughout (the guard before it shortened
# its interval at the third roll-back in a row to the start) this run rolled back 11 times and
# ended at H 11.0 % (RMS 3.19 %); now 4 times, 1.05 % (RMS 0.148 %).
"$build/largesteps" fit fixtures/meshes/cactus.off.gz --iters 300 --remesh 100,200 --threads 1 --quiet --track 0 \
    -o "$out/cactus" > "$out/cactus.log" 2>&1
rc=$?
h=$(field "$out/cactus/metrics.json" hausdorff_rel)
h=$(awk -v h="${h:-1}" 'BEGIN { printf "%.2f", 100 * h }')
if [ "$rc" = 0 ] && awk -v h="$h" 'BEGIN { exit !(h + 0 <= 3) }'; then
    ok "fit_suite_cactus_not_held_at_its_start (H/diag $h % <= 3 %, exit status 0)"
else bad "fit_suite_cactus_not_held_at_its_start (H/diag $h %, exit status $rc; see $out/cactus.log)"; fi
echo "fit_suite: $pass passed, $fail failed"
[ "$fail" = 0 ]
