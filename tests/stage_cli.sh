#!/bin/sh
# stage_cli.sh - the command-line program end to end (a stage of `make test`):
# `largesteps fit` on the embedded bunny (a shortened version of the default fit's
# acceptance run: 200 iterations at 96 x 96, 16 views, two remeshes; the
# metrics it writes must show a close, untangled reconstruction; with 12
# views at 64-128 px the result's tangling moves with the last bits of the
# trajectory: 0 to 38 pairs in a sample of runs, none with 15 or 16 views
# at 96 px), on a mesh
# file and on a text scene; every output file present and complete; bad
# options, unreadable and malformed inputs give the documented exit status
# and message and leave no file behind; `largesteps experiment` writes its
# table; the outputs people look at (complete log.csv rows, the plot's log
# axes, ticks and remesh markers, an opaque labelled contact sheet, an ETA
# that counts the remeshes). Native gcc double build only.
jobs=${JOBS:-2}
build=build/cli
out=$build/out
pass=0 fail=0
mkdir -p build/logs "$build"
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
check() { # name, command...
    name=$1
    shift
    if "$@" > "$build/$name.log" 2>&1; then ok "$name"; else bad "$name"; tail -n 5 "$build/$name.log"; fi
}
if ! make --no-print-directory -j"$jobs" BUILD="$build" CC=gcc REAL=double all > build/logs/cli-build.log 2>&1; then
    tail -n 20 build/logs/cli-build.log
    bad "cli_build"
    echo "cli: $pass passed, $fail failed"
    exit 1
fi
ls=$build/largesteps
rm -rf "$out"
mkdir -p "$out"

# A JSON number field (first occurrence) from a metrics.json.
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1" | head -n 1; }
# awk comparison: less A B
less() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 < b + 0) }'; }

# 1. the embedded bunny, shortened acceptance run
if "$ls" fit --iters 200 --res 96 --views 16 --remesh 60,140 --settle 0 --quiet -o "$out/bunny" > "$build/fit_bunny.log" 2>&1; then
    ok "fit_embedded_bunny_runs"
    for f in result.obj log.csv convergence.svg contact.png metrics.json; do
        if [ -s "$out/bunny/$f" ]; then ok "fit_writes_$f"; else bad "fit_writes_$f"; fi
    done
    if ls -a "$out/bunny" | grep -q '\.tmp$'; then bad "fit_leaves_no_temporary_file"; else ok "fit_leaves_no_temporary_file"; fi
    m=$out/bunny/metrics.json
    rms=$(field "$m" rms_rel)
    h=$(field "$m" vertex_hausdorff_rel)
    pairs=$(field "$m" intersecting_pairs)
    its=$(field "$m" iterations)
    echo "     bunny 96x96, 16 views, 200 iterations: H/diag $h, RMS/diag $rms, self-intersecting pairs $pairs"
    if less "$rms" 0.025 && less "$h" 0.25; then ok "fit_bunny_close (RMS/diag $rms < 0.025, H/diag $h < 0.25)"; else bad "fit_bunny_close (RMS/diag $rms, H/diag $h)"; fi
    if [ "$pairs" = 0 ]; then ok "fit_bunny_untangled"; else bad "fit_bunny_untangled ($pairs pairs)"; fi
    if [ "$its" = 200 ] && [ "$(wc -l < "$out/bunny/log.csv")" = 202 ]; then ok "fit_log_has_every_iteration"; else bad "fit_log_has_every_iteration"; fi
    # the log's last row is the final mesh's distance: the metrics' dense Hausdorff (and its image loss)
    last_h=$(tail -n 1 "$out/bunny/log.csv" | awk -F, '$1 == 200 && $2 != "" { print $4 }')
    dense_h=$(field "$m" hausdorff_rel)
    if [ -n "$last_h" ] && awk -v a="$last_h" -v b="$dense_h" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-5 * b) }'; then
        ok "fit_log_tracks_hausdorff ($last_h = metrics $dense_h)"; else bad "fit_log_tracks_hausdorff ('$last_h' vs $dense_h)"; fi
    tracked=$(awk -F, 'NR > 1 && $4 != "" { n++ } END { print n + 0 }' "$out/bunny/log.csv")
    if [ "$tracked" = 9 ]; then ok "fit_log_distance_every_25_iterations"; else bad "fit_log_distance_every_25_iterations ($tracked rows)"; fi
    if grep -q '^v ' "$out/bunny/result.obj" && grep -q '^f ' "$out/bunny/result.obj"; then ok "fit_result_obj"; else bad "fit_result_obj"; fi
    if grep -q '</svg>' "$out/bunny/convergence.svg"; then ok "fit_svg_complete"; else bad "fit_svg_complete"; fi
    if grep -q 'time per iteration' "$build/fit_bunny.log" && grep -q 'H vertices' "$build/fit_bunny.log"; then
        ok "fit_prints_stage_times_and_metrics"; else bad "fit_prints_stage_times_and_metrics"; fi
else
    bad "fit_embedded_bunny_runs"
    tail -n 5 "$build/fit_bunny.log"
fi

# (Both without the default's settling phase, --settle 0: the bounds below
# were measured on this schedule; the settle is measured on the suite, where
# it lowers the bunny's H, docs/fit-suite.md, but at 200 iterations it takes
# steps the shortened run needs.)
# 1b. the spread of that run: a fit's Hausdorff maximum follows the last bits
# of its trajectory (a collapsed ear in one run, 1-3 % in its neighbours), so
# the same run with the learning rate moved in the 7th digit, k x 1e-6 for
# k = -4..4: their median must be close and none far off. Measured over 30
# such runs each before and after a change that moved the gradient's last
# bits: about 60 % end below 5 %, 23 % above 10 %, none above
# 21.3 %, with the same spread both times; the median of 9 stays below 10 %
# but for a few percent of such bit changes (the median of 3 below 5 %, as
# this test was, failed a third of them)
hs=$(field "$out/bunny/metrics.json" vertex_hausdorff_rel)
for k in -4 -3 -2 -1 1 2 3 4; do
    lr=$(awk -v k=$k 'BEGIN { printf "%.8f", 0.01 * (1 + k * 1e-6) }')
    if "$ls" fit --iters 200 --res 96 --views 16 --remesh 60,140 --settle 0 --lr $lr --track 0 --quiet -o "$out/bunny_$lr" \
        > "$build/fit_bunny_$lr.log" 2>&1; then
        hs="$hs $(field "$out/bunny_$lr/metrics.json" vertex_hausdorff_rel)"
    else
        hs="$hs 1"
    fi
done
med=$(echo $hs | tr ' ' '\n' | sort -g | sed -n 5p)
max=$(echo $hs | tr ' ' '\n' | sort -g | sed -n 9p)
echo "     bunny 96x96, 200 iterations, lr 0.01 x (1 + k 1e-6), k = 0, -4..4: H/diag $hs"
if [ -n "$med" ] && less "$med" 0.10 && less "$max" 0.30; then ok "fit_bunny_spread (median H/diag $med < 0.10, max $max < 0.30)"
else bad "fit_bunny_spread (H/diag $hs)"; fi

# 2. a mesh file and a text scene (cameras, SH lighting, mesh target)
check fit_mesh_file "$ls" fit fixtures/meshes/elephant.obj --init-sphere --iters 10 --res 32 --views 4 --level 2 --remesh none --quiet -o "$out/elephant"
mkdir -p "$out/scene"
cp fixtures/meshes/bunny.obj "$out/scene/"
cat > "$out/scene/scene.txt" <<'EOF'
largesteps-scene 1
resolution 40 30
fov 40
clip 1 100
views fibonacci 5 25 0 4.8 0
lighting sh 1.7 0.5 0.3 -0.2 0 0 0 0 0  1.7 0.5 0.3 -0.2 0 0 0 0 0  1.6 0.5 0.3 -0.2 0 0 0 0 0
background 0.1 0.1 0.2
target mesh bunny.obj
initial icosphere 2
EOF
check fit_text_scene "$ls" fit "$out/scene/scene.txt" --iters 10 --remesh 5 --quiet -o "$out/scene/result"
if grep -q '"vertices"' "$out/scene/result/metrics.json" 2>/dev/null; then ok "fit_scene_metrics"; else bad "fit_scene_metrics"; fi

# 2b. diagnostics instead of a silent run: a start that a view with the object
# in its target does not see (it could never move it there), and a gradient
# of zeros (everything outside the views) stop before any output is written
awk '/^v / { $2 = $2 + 100 } { print }' fixtures/meshes/bunny.obj > "$out/scene/far.obj"
sed -e 's/^initial icosphere 2$/initial mesh far.obj/' "$out/scene/scene.txt" > "$out/scene/unseen.txt"
sed -e 's/^target mesh bunny.obj$/target mesh far.obj/' "$out/scene/unseen.txt" > "$out/scene/still.txt"
rm -rf "$out/scene/unseen" "$out/scene/still"
"$ls" fit "$out/scene/unseen.txt" --iters 10 --quiet -o "$out/scene/unseen" > "$build/fit_unseen.log" 2>&1
got=$?
if [ "$got" = 1 ] && grep -q "frame 0 (counting from 0) does not see the initial mesh, while its target shows the object" \
        "$build/fit_unseen.log" && [ ! -e "$out/scene/unseen" ]; then ok "fit_view_without_the_start_refused"
else bad "fit_view_without_the_start_refused (status $got)"; cat "$build/fit_unseen.log"; fi
"$ls" fit "$out/scene/still.txt" --iters 100 --quiet -o "$out/scene/still" > "$build/fit_still.log" 2>&1
got=$?
if [ "$got" = 1 ] && grep -q "the gradient has been zero for 20 iterations (iteration 19, " "$build/fit_still.log" &&
        [ ! -e "$out/scene/still" ]; then ok "fit_zero_gradient_stops"
else bad "fit_zero_gradient_stops (status $got)"; cat "$build/fit_still.log"; fi


# 2c. the start for a target a sphere cannot reach: two unit cubes (two
# components) start from themselves; a fin (two faces on the same three
# vertices, turning opposite ways: the edge they share with the cube has four
# faces) is dropped before the remesh, which refuses non-manifold edges; two
# cubes through each other outgrow the remesher's capacity bound and are
# remeshed again with four times the room (without it they fell back to the
# icosphere); with a third face on an edge instead, or two needles far thinner
# than the start's edge (their splits outgrow even that), the icosphere with a
# warning that says why; a result that self-intersects where the target does
# says so
cube() { awk -v dx="$1" 'BEGIN { for (i = 0; i < 8; i++) printf "v %g %g %g\n", (i % 2) + dx, int(i / 2) % 2, int(i / 4) }'; }
cube_faces() {
    awk -v o="$1" 'BEGIN { split("1 3 4 2|5 6 8 7|1 2 6 5|3 7 8 4|1 5 7 3|2 4 8 6", q, "|")
        for (k = 1; k <= 6; k++) { n = split(q[k], v, " "); printf "f"; for (j = 1; j <= n; j++) printf " %d", v[j] + o; printf "\n" } }'
}
{ cube 0; cube 3; echo "v 0.5 -1 0"; cube_faces 0; cube_faces 8; echo "f 1 2 17"; echo "f 2 1 17"; } > "$out/cubes_fin.obj"
{ cube 0; cube 3; echo "v 0.5 -1 0"; cube_faces 0; cube_faces 8; echo "f 1 2 17"; } > "$out/cubes_nonmanifold.obj"
{ cube 0; cube 0.5; cube_faces 0; cube_faces 8; } > "$out/cubes_through.obj"
prism() { awk -v dy="$1" 'BEGIN { printf "v 0 %g 0\nv 0 %g 0.001\nv 0 %g 0\nv 1 %g 0\nv 1 %g 0.001\nv 1 %g 0\n", dy, dy + 0.0005, dy + 0.001, dy, dy + 0.0005, dy + 0.001 }'; }
prism_faces() {
    awk -v o="$1" 'BEGIN { split("1 3 2|4 5 6|1 4 6 3|1 2 5 4|2 3 6 5", q, "|")
        for (k = 1; k <= 5; k++) { n = split(q[k], v, " "); printf "f"; for (j = 1; j <= n; j++) printf " %d", v[j] + o; printf "\n" } }'
}
{ prism 0; prism 0.5; prism_faces 0; prism_faces 6; } > "$out/needles.obj"
expect() { # name, status, pattern, command...
    name=$1 want=$2 pattern=$3
    shift 3
    "$@" > "$build/$name.log" 2>&1
    got=$?
    if [ "$got" = "$want" ] && grep -q -e "$pattern" "$build/$name.log"; then ok "$name"; else bad "$name (status $got, wanted $want)"; cat "$build/$name.log"; fi
}
small="--iters 5 --res 32 --views 4 --remesh none --quiet"
# shellcheck disable=SC2086 # $small: a list of options
expect fit_components_start_from_the_target 0 "the target has 2 components, which a sphere cannot reach: starting from the target remeshed" \
    "$ls" fit "$out/cubes_fin.obj" $small -o "$out/cubes_fin"
# a start from the target itself has its detail: the default schedule (200, 500) does not remesh it,
# --remesh still does
"$ls" fit "$out/cubes_fin.obj" --init-coarse 0.1 --iters 201 --res 32 --views 4 --quiet -o "$out/cubes_sched" \
    > "$build/fit_target_start_not_remeshed.log" 2>&1
"$ls" fit "$out/cubes_fin.obj" --init-coarse 0.1 --iters 201 --res 32 --views 4 --remesh 200 --quiet \
    -o "$out/cubes_sched_asked" > "$build/fit_target_start_remeshed_when_asked.log" 2>&1
for t in not_remeshed:0 remeshed_when_asked:1; do
    if grep -q "^set-up .* ms; ${t#*:} remeshes" "$build/fit_target_start_${t%%:*}.log"; then ok "fit_target_start_${t%%:*}"
    else bad "fit_target_start_${t%%:*} (wanted ${t#*:} remeshes)"; cat "$build/fit_target_start_${t%%:*}.log"; fi
done
# shellcheck disable=SC2086
expect fit_nonmanifold_target_falls_back 0 "could not make a start of it (non-manifold edge (three or more faces); index = its first vertex): starting from the icosphere" \
    "$ls" fit "$out/cubes_nonmanifold.obj" $small -o "$out/cubes_nonmanifold"
# shellcheck disable=SC2086
expect fit_remesh_failure_falls_back 0 "could not make a start of it (remesh vertex capacity exceeded): starting from the icosphere" \
    "$ls" fit "$out/needles.obj" $small -o "$out/needles"
# shellcheck disable=SC2086
expect fit_remesh_retried_with_more_room 3 "starting from the target remeshed to 0.012 of its diagonal" \
    "$ls" fit "$out/cubes_through.obj" $small -o "$out/cubes_through"
expect fit_says_the_target_self_intersects 3 "The target itself self-intersects (52 face pairs)" \
    "$ls" fit "$out/cubes_through.obj" --init-coarse 0.2 --init-smooth 0 --iters 0 --res 32 --views 4 --quiet -o "$out/cubes_through_coarse"
# --init-coarse E: a start that self-intersects is remeshed again at 1.1 and 1.21 E, and the program says so
# (the automatic start too: fit_remesh_retried_with_more_room's log)
if grep -q "^the start self-intersects ([0-9]* face pairs) remeshed to 0.2, 0.22 and 0.242 of the diagonal alike" \
    "$build/fit_says_the_target_self_intersects.log"; then ok "fit_says_its_start_self_intersects"
else bad "fit_says_its_start_self_intersects"; cat "$build/fit_says_the_target_self_intersects.log"; fi
if grep -q "^the start self-intersects ([0-9]* face pairs) remeshed to 0.012, 0.0132 and 0.01452 of the diagonal alike" \
    "$build/fit_remesh_retried_with_more_room.log"; then ok "fit_says_its_automatic_start_self_intersects"
else bad "fit_says_its_automatic_start_self_intersects"; cat "$build/fit_remesh_retried_with_more_room.log"; fi
# a remesh the guard refuses (its result would self-intersect more than the mesh) is said as
# refused, not as done, and counted in the summary
expect fit_says_a_remesh_was_refused 3 "remesh before iteration 5 refused: its result would self-intersect more than the mesh; the fit goes on with its 7626 vertices" \
    "$ls" fit "$out/cubes_through.obj" --init-coarse 0.02 --iters 10 --res 32 --views 4 --remesh 5 --guard 5 -o "$out/cubes_refused"
if grep -q "^set-up .* ms; 0 remeshes, 1 refused (the mesh kept as it was);" "$build/fit_says_a_remesh_was_refused.log"; then
    ok "fit_counts_the_refused_remeshes"
else bad "fit_counts_the_refused_remeshes"; grep "^set-up" "$build/fit_says_a_remesh_was_refused.log"; fi

# 3. errors: exit status 2 for usage, 1 for bad input, a message, no output
expect fit_unknown_option 2 "unknown option" "$ls" fit --frobnicate -o "$out/x"
expect fit_bad_value 2 "--views: '0' is not a whole number in \[1, 1024\]" "$ls" fit --views 0 -o "$out/x"
expect fit_needs_output 2 "-o DIR" "$ls" fit --iters 3
expect fit_bad_alpha 2 "--alpha: '1' is not a number in \[0, 1)" "$ls" fit --alpha 1 --iters 1 --res 16 --views 1 -o "$out/x"
expect fit_missing_target 1 "nothing.obj" "$ls" fit "$out/nothing.obj" -o "$out/x"
# alpha 0.999 from the 642-vertex icosphere (smallest Laplacian eigenvalue 0.0675, computed apart by
# inverse iteration): the translation moves 1 + 999 x 0.0675 = 68 times as far as the smoothest shape, a warning;
# the default (1 + 19 x 0.0675 = 2.3) and alpha 0.98 from the 2562-vertex start (1 + 49 x 0.0170 = 1.8) have none
expect fit_mean_ratio_warning 0 "moves 68 times as far per step as its smoothest shape (its smallest Laplacian eigenvalue is 0.0675)" \
    "$ls" fit --alpha 0.999 --iters 0 --res 16 --views 1 --quiet -o "$out/meanwarn"
if "$ls" fit --iters 0 --res 16 --views 1 --quiet -o "$out/meanwarn0" 2>&1 | grep -q "smoothest shape" ||
    "$ls" fit --alpha 0.98 --level 4 --iters 0 --res 16 --views 1 --quiet -o "$out/meanwarn4" 2>&1 | grep -q "smoothest shape"; then
    bad "fit_mean_ratio_no_warning"; else ok "fit_mean_ratio_no_warning (alpha 0.95 from level 3, alpha 0.98 from level 4)"; fi
expect fit_mean_ratio_warning_098 0 "moves 4.3 times as far" "$ls" fit --alpha 0.98 --iters 0 --res 16 --views 1 --quiet -o "$out/meanwarn98"
printf 'v 0 0 0\nv 1 0 0\nf 1 2 7\n' > "$out/broken.obj"
expect fit_malformed_mesh 1 "broken.obj" "$ls" fit "$out/broken.obj" -o "$out/x"
printf 'largesteps-scene 1\nresolution 32 32\ncamera 0 0 3 0 0 0\nlighting sun\ntarget mesh bunny.obj\n' > "$out/scene/bad.txt"
expect fit_malformed_scene 1 "bad.txt:4:10" "$ls" fit "$out/scene/bad.txt" -o "$out/x"
if [ -e "$out/x" ] && [ -n "$(ls -A "$out/x")" ]; then bad "fit_failures_write_nothing"; else ok "fit_failures_write_nothing"; fi

# a gzip-compressed mesh is read (the armadillo fixture, remeshed coarse); a corrupt one is refused
check remesh_gzip_mesh "$ls" remesh fixtures/meshes/armadillo.obj.gz --factor 2 --iters 1 -o "$out/armadillo_coarse.obj"
if [ "$(grep -c '^f ' "$out/armadillo_coarse.obj" 2>/dev/null)" -gt 5000 ]; then ok "remesh_gzip_mesh_written"; else bad "remesh_gzip_mesh_written"; fi
{ head -c 200000 fixtures/meshes/armadillo.obj.gz; printf 'x'; tail -c +200002 fixtures/meshes/armadillo.obj.gz; } > "$out/corrupt.obj.gz"
expect remesh_corrupt_gzip 1 "corrupt.obj.gz" "$ls" remesh "$out/corrupt.obj.gz" -o "$out/corrupt_out.obj"
if [ -e "$out/corrupt_out.obj" ]; then bad "remesh_corrupt_gzip_writes_nothing"; else ok "remesh_corrupt_gzip_writes_nothing"; fi

# 4. an experiment table
check experiment_silhouettes "$ls" experiment silhouettes --iters 8 --res 24 --views 3 --level 1 -o "$out/exp"
if grep -q '^| large steps, lambda 99 |' "$out/exp/silhouettes.md" 2>/dev/null; then ok "experiment_table_written"; else bad "experiment_table_written"; fi

# the lambda sweep (tiny): the alpha form with the mean of dL/du kept and projected, each alpha against the paper's H
check experiment_lambda_sweep "$ls" experiment lambda-sweep --form alpha --mean both --iters 4 --res 24 --views 2 --level 1 -o "$out/sweep"
# (16 rows; the projected table's distances differ from the kept one's: the option reaches the fit)
sweep_rows() { grep '^| alpha' "$out/sweep/lambda-sweep.md" | sed -n "$1" | cut -d'|' -f3-7; }
if [ "$(grep -c '^| alpha .* | 0\.[0-9.-]* |$' "$out/sweep/lambda-sweep.md" 2>/dev/null)" = 16 ] &&
    grep -q 'step 0.001 in the target' "$out/sweep/lambda-sweep.md" && grep -q 'projected out' "$out/sweep/lambda-sweep.md" &&
    [ "$(sweep_rows 1,8p)" != "$(sweep_rows 9,16p)" ] && [ -s "$out/sweep/lambda-sweep.png" ]; then
    ok "experiment_lambda_sweep_both_means"; else bad "experiment_lambda_sweep_both_means"; fi
expect experiment_sweep_bad_mean 2 "--mean: 'foo' is not keep, project or both" "$ls" experiment lambda-sweep --mean foo -o "$out/x"
expect experiment_sweep_bad_step 2 "--step: '0' is not a number in (0, 10\]" "$ls" experiment lambda-sweep --step 0 -o "$out/x"

# the compare experiment (tiny): four methods at equal iterations and at equal time, and its contact sheet
check experiment_compare "$ls" experiment compare --iters 6 --res 24 --views 2 --level 1 -o "$out/cmp"
if [ "$(grep -c -e '^| naive' -e '^| Laplacian' -e '^| bilaplacian' -e '^| large steps' "$out/cmp/compare.md" 2>/dev/null)" = 8 ] &&
    [ -s "$out/cmp/compare.png" ]; then ok "experiment_compare_rows_and_sheet"; else bad "experiment_compare_rows_and_sheet"; fi

# an initial mesh of the target's genus: the elephant (genus 3) remeshed coarse, no iteration
# --threads: the target renders and the views of each iteration shared by a pool of threads; any
# count gives the same bits
rm -rf "$out/thr1" "$out/thr3"
if "$ls" fit --threads 1 --iters 60 --remesh 20,40 --res 32 --views 7 --batch 5 --quiet -o "$out/thr1" > /dev/null 2>&1 &&
        "$ls" fit --threads 3 --iters 60 --remesh 20,40 --res 32 --views 7 --batch 5 --quiet -o "$out/thr3" > /dev/null 2>&1 &&
        cmp -s "$out/thr1/result.obj" "$out/thr3/result.obj" && cmp -s "$out/thr1/contact.png" "$out/thr3/contact.png" &&
        [ "$(cut -d, -f1,2 "$out/thr1/log.csv")" = "$(cut -d, -f1,2 "$out/thr3/log.csv")" ]; then
    ok "fit_threads_same_bits (1 and 3 threads: result.obj, the losses and the contact sheet identical)"
else bad "fit_threads_same_bits"; fi
expect fit_threads_bad_value 2 "--threads: '0' is not a whole number in \[1, 1024\]" "$ls" fit --threads 0 -o "$out/x"
check fit_init_coarse "$ls" fit fixtures/meshes/elephant.obj --init-coarse 0.03 --iters 0 --res 24 --views 1 --quiet -o "$out/coarse"
if "$ls" info "$out/coarse/result.obj" 2>/dev/null | grep -q '^genus  *3$' && [ "$(field "$out/coarse/metrics.json" intersecting_pairs)" = 0 ]; then
    ok "fit_init_coarse_keeps_genus_3_untangled"; else bad "fit_init_coarse_keeps_genus_3_untangled"; fi
expect fit_init_coarse_bad 2 "--init-coarse: '0' is not a number in (0, 1\]" "$ls" fit --init-coarse 0 -o "$out/x"
# the visual hull start of the bunny from 16 views at 64 x 64 is within 8 % of the diagonal (4.5 %; the sphere: 36 %)
check fit_init_hull "$ls" fit --init-hull 64 --iters 0 --res 64 --views 16 --quiet -o "$out/hull"
if awk -v h="$(field "$out/hull/metrics.json" hausdorff_rel)" 'BEGIN { exit !(h > 0 && h < 0.08) }' &&
    [ "$(field "$out/hull/metrics.json" intersecting_pairs)" = 0 ]; then
    ok "fit_init_hull_close_untangled"; else bad "fit_init_hull_close_untangled"; fi
expect fit_init_hull_bad 2 "--init-hull: '1' is not a whole number in \[2, 1024\]" "$ls" fit --init-hull 1 -o "$out/x"

# 5. the trade study's tables and plot (tiny)
check experiment_tradeoffs "$ls" experiment tradeoffs --iters 8 --res 24 --views 2 --level 1 --knobs silhouette,power -o "$out/trade"
if [ "$(grep -c '^| bunny | ' "$out/trade/tradeoffs.md" 2>/dev/null)" = 7 ] && grep -q '</svg>' "$out/trade/tradeoffs.svg" 2>/dev/null &&
    [ "$(wc -l < "$out/trade/tradeoffs.tsv")" = 6 ]; then ok "experiment_tradeoffs_tables_plot_rows"; else bad "experiment_tradeoffs_tables_plot_rows"; fi

# 6. the texture experiment (tiny; its runs are timed, so only the outputs are checked)
check experiment_texture "$ls" experiment texture --side 32 --res 24 --res-hi 48 --views 2 --tune 0.1 --time 0.2 -o "$out/tex"
if grep -q '^| large steps' "$out/tex/texture.md" 2>/dev/null && [ -s "$out/tex/texture.png" ]; then
    ok "experiment_texture_table_and_figure"; else bad "experiment_texture_table_and_figure"; fi
# at equal iterations every method ran the large-steps run's count (the 5th column), named in the heading
eq_iters=$(sed -n 's/^## equal iterations (\([0-9]*\) each.*/\1/p' "$out/tex/texture.md" 2>/dev/null)
if [ -n "$eq_iters" ] && [ "$(sed -n '/^## equal iterations/,$p' "$out/tex/texture.md" | grep '^| [nrl]' | cut -d'|' -f6 | tr -d ' ' | sort -u)" = "$eq_iters" ] &&
    [ "$(sed -n '/^## equal iterations/,$p' "$out/tex/texture.md" | grep -c '^| [nrl]')" = 3 ]; then
    ok "experiment_texture_equal_iterations ($eq_iters each)"; else bad "experiment_texture_equal_iterations"; fi
# the tuning grid from the command line: large steps only, 2 lambdas x 1 rate = 2 tuning rows and 2 final rows
# (equal time, equal iterations)
check experiment_texture_grid "$ls" experiment texture --side 32 --res 24 --res-hi 48 --views 2 --tune 0.1 --time 0.2 --fit-ss 1 \
    --methods ls --lambda-ls 4,16 --lr-ls 0.3 -o "$out/texgrid"
if [ "$(grep -c '^| large steps' "$out/texgrid/texture.md" 2>/dev/null)" = 4 ] && ! grep -q '^| naive' "$out/texgrid/texture.md"; then
    ok "experiment_texture_grid_rows"; else bad "experiment_texture_grid_rows"; fi
check experiment_texture_ls_adam "$ls" experiment texture --side 32 --res 24 --res-hi 48 --views 2 --tune 0.1 --time 0.2 --fit-ss 1 \
    --methods ls --ls-optimizer adam --lambda-ls 4 --lr-ls 0.3 -o "$out/texadam"
if [ "$(grep -c '^| large steps (Adam on u' "$out/texadam/texture.md" 2>/dev/null)" = 3 ]; then
    ok "experiment_texture_ls_adam_rows"; else bad "experiment_texture_ls_adam_rows"; fi
expect experiment_texture_bad_method 2 "usage" "$ls" experiment texture --methods ls,foo -o "$out/x"
expect experiment_texture_bad_grid 2 "usage" "$ls" experiment texture --lr-ls 0.1,0 -o "$out/x"

# 7. outputs people look at (log.csv, convergence.svg, contact.png, the ETA)
# A short fit with two remeshes and distances every 10 iterations: every row
# of log.csv has its loss and time (the last row, the final mesh, too); the
# plot's axes are logarithmic (ticks at powers of ten, minor ticks; iterations
# counted from 1), and each panel marks both remeshes; the contact sheet is opaque (RGB)
# (the checkerboard under the tiles).
check outputs_fit "$ls" fit --iters 40 --res 32 --views 3 --remesh 10,25 --track 10 --quiet -o "$out/outputs"
csv=$out/outputs/log.csv
if [ -s "$csv" ] && awk -F, 'NR > 1 && ($2 !~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/ || $3 !~ /^[0-9.]+$/) { bad = 1 } END { exit bad + 0 }' "$csv" &&
    [ "$(tail -n 1 "$csv" | cut -d, -f1)" = 40 ] && [ -n "$(tail -n 1 "$csv" | cut -d, -f4)" ]; then
    ok "outputs_csv_rows_complete (last: $(tail -n 1 "$csv"))"
else bad "outputs_csv_rows_complete"; tail -n 2 "$csv"; fi
svg=$out/outputs/convergence.svg
if [ "$(grep -c 'class="remesh"' "$svg" 2>/dev/null)" = 8 ]; then ok "outputs_svg_remesh_markers (2 remeshes x 4 panels)"
else bad "outputs_svg_remesh_markers ($(grep -c 'class="remesh"' "$svg" 2>/dev/null) markers)"; fi
# every y and x tick label a power of ten, at least 2 per panel; minor ticks on both axes
decade_labels() { # class: every label a power of ten, at least 8
    sed -n "s/.*class=\"$1\".*>\([^<]*\)<\/text><\/g>\$/\1/p" "$svg" |
        awk '{ if ($1 <= 0) bad = 1; else { l = log($1) / log(10); d = l - sprintf("%.0f", l); if (d * d > 1e-12) bad = 1 } n++ }
             END { exit !(n >= 8 && !bad) }'
}
if decade_labels ytick && decade_labels xtick &&
    [ "$(grep -c 'class="yminor"' "$svg")" -ge 8 ] && [ "$(grep -c 'class="xminor"' "$svg")" -ge 8 ]; then
    ok "outputs_svg_log_axes_and_ticks ($(grep -c 'class="ytick"' "$svg") decade ticks)"
else bad "outputs_svg_log_axes_and_ticks"; fi
if python3 - "$out/outputs/contact.png" <<'PY'
import sys, struct, zlib
b = open(sys.argv[1], 'rb').read()
p, z, ihdr = 8, b'', None
while p < len(b):
    n = struct.unpack('>I', b[p:p + 4])[0]
    t, d = b[p + 4:p + 8], b[p + 8:p + 8 + n]
    if t == b'IHDR': ihdr = d
    if t == b'IDAT': z += d
    p += 12 + n
w, h, bits, ct = struct.unpack('>IIBB', ihdr[:10])
assert ct == 2 and bits == 8, 'colour type %d, %d bits: want RGB, 8 bits (no alpha)' % (ct, bits)
r, prev, rb = zlib.decompress(z), bytearray(3 * w), 3 * w
assert len(r) == h * (rb + 1)
colours = set()
for y in range(h):
    f, cur = r[y * (rb + 1)], bytearray(r[y * (rb + 1) + 1:(y + 1) * (rb + 1)])
    for i in range(rb):
        a = cur[i - 3] if i >= 3 else 0
        c = prev[i - 3] if i >= 3 else 0
        u = prev[i]
        q = a + u - c
        pr = [0, a, u, (a + u) >> 1, a if abs(q - a) <= abs(q - u) and abs(q - a) <= abs(q - c) else u if abs(q - u) <= abs(q - c) else c][f]
        cur[i] = (cur[i] + pr) & 255
    colours.update(bytes(cur[i:i + 3]) for i in range(0, rb, 3 * 7))
    prev = cur
assert len(colours) > 50, 'only %d colours: renders missing' % len(colours)
PY
then ok "outputs_contact_sheet_opaque (RGB, no alpha)"; else bad "outputs_contact_sheet_opaque"; fi
# The ETA counts the remeshes: ls_report_eta_ms (report.c) against hand-worked
# figures: 10 ms per iteration, remeshes before 200 and 500 of 800 at h = 1/2
# (growth guessed 2: 100 x 10 + 300 x 20 + 300 x 40 = 19000 ms, not the
# 7000 ms of the average alone); after the first remesh (500 ms) the
# iterations take 30 ms: growth measured 3, 290 x 30 + 500 x 3 + 300 x 90.
cat > "$build/eta_test.c" <<'C'
#include <stdio.h>
#include "report.h"
int main(void)
{
    static const uint32_t at[2] = {200, 500};
    ls_report_eta e;
    double a, b, c;
    ls_report_eta_init(&e, at, 2, 0.5);
    a = ls_report_eta_ms(&e, 100, 800, 1000.0);
    ls_report_eta_remesh(&e, 200, 2000.0, 2500.0);
    b = ls_report_eta_ms(&e, 210, 800, 2800.0);
    c = ls_report_eta_ms(&e, 800, 800, 30000.0);
    printf("%.3f %.3f %.3f\n", a, b, c);
    return !(a > 18999.999 && a < 19000.001 && b > 37199.999 && b < 37200.001 && c == 0.0);
}
C
if gcc -std=c99 -Iinclude -I"$build/include" -Iport/posix -Iport/posix/program "$build/eta_test.c" "$build/liblargesteps-posix.a" \
        "$build/liblargesteps.a" -lm -o "$build/eta_test" 2> "$build/eta_test.log" && "$build/eta_test" > "$build/eta_test.out"; then
    ok "outputs_eta_counts_remeshes ($(cat "$build/eta_test.out"))"
else bad "outputs_eta_counts_remeshes"; cat "$build/eta_test.log" "$build/eta_test.out" 2>/dev/null | head -n 5; fi

# Camera datasets: `render` writes DIR/transforms.json with its cameras and
# lighting; `fit DIR/transforms.json` fits the images alone (it never sees the
# mesh) about as well as the mesh-target fit with the same views; a dataset
# without its lighting has it estimated with the geometry, and says so
# (--shading mask: the alpha masks alone); a malformed dataset names the
# line, column and problem.
ds=$out/dataset
rm -rf "$ds" "$out/fit_ds" "$out/fit_mesh"
if "$ls" render fixtures/meshes/bunny.obj --views 8 --res 48 -o "$ds" > "$build/ds_render.log" 2>&1 &&
        grep -q '"largesteps_sh"' "$ds/transforms.json" && grep -q '"file_path": "view_007.png"' "$ds/transforms.json"; then
    ok "render_writes_dataset"
else bad "render_writes_dataset"; fi
if "$ls" fit "$ds/transforms.json" --iters 120 --remesh 40 -o "$out/fit_ds" > "$build/ds_fit.log" 2>&1 &&
        "$ls" fit fixtures/meshes/bunny.obj --views 8 --res 48 --iters 120 --remesh 40 -o "$out/fit_mesh" > "$build/ds_fit_mesh.log" 2>&1 &&
        "$ls" metrics "$out/fit_ds/result.obj" fixtures/meshes/bunny.obj --json > "$build/ds_m1.json" 2>&1 &&
        "$ls" metrics "$out/fit_mesh/result.obj" fixtures/meshes/bunny.obj --json > "$build/ds_m2.json" 2>&1; then
    h1=$(field "$build/ds_m1.json" hausdorff_rel)
    h2=$(field "$build/ds_m2.json" hausdorff_rel)
    if less "$h1" "$(awk -v h="$h2" 'BEGIN { print 1.2 * h + 0.005 }')"; then
        ok "fit_dataset_round_trip (H/diag $h1 from the images, $h2 from the mesh)"
    else bad "fit_dataset_round_trip (H/diag $h1 from the images, $h2 from the mesh)"; fi
else bad "fit_dataset_round_trip"; tail -n 3 "$build/ds_fit.log"; fi
rm -rf "$ds.lambert" "$out/fit_ds_light" "$out/fit_ds_mask"
if "$ls" render fixtures/meshes/bunny.obj --views 8 --res 48 --shading lambert -o "$ds.lambert" > /dev/null 2>&1 &&
        "$ls" fit "$ds.lambert/transforms.json" --iters 40 --remesh 20 -o "$out/fit_ds_light" > "$build/ds_light.log" 2>&1 &&
        grep -q "does not record its lighting: estimating it (9 RGB spherical-harmonics coefficients; the albedo uniform, or per vertex with --albedo vertex)" \
            "$build/ds_light.log" &&
        [ -s "$out/fit_ds_light/result.obj" ]; then
    # the estimate in metrics.json: 27 numbers, a positive constant term in each channel
    l00=$(sed -n 's/.*"estimated_sh": \[\([^]]*\)\].*/\1/p' "$out/fit_ds_light/metrics.json" |
          awk -F', ' 'NF == 27 && $1 > 0 && $10 > 0 && $19 > 0 { print $1 " " $10 " " $19 }')
    if [ -n "$l00" ]; then ok "fit_dataset_unknown_lighting_estimated (L00 $l00)"
    else bad "fit_dataset_unknown_lighting_estimated"; grep estimated_sh "$out/fit_ds_light/metrics.json"; fi
else bad "fit_dataset_unknown_lighting_estimated"; tail -n 3 "$build/ds_light.log"; fi
# --albedo vertex: albedo.ply beside the result (its vertices, an RGB albedo of mean 1 per channel);
# refused where the lighting is not estimated, before any work
rm -rf "$out/fit_ds_albedo"
if "$ls" fit "$ds.lambert/transforms.json" --albedo vertex --iters 24 --remesh 12 -o "$out/fit_ds_albedo" > "$build/ds_albedo.log" 2>&1 &&
        grep -q '"albedo": "vertex"' "$out/fit_ds_albedo/metrics.json" &&
        python3 - "$out/fit_ds_albedo/albedo.ply" "$out/fit_ds_albedo/result.obj" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
end = lines.index("end_header")
nv = int([l for l in lines if l.startswith("element vertex")][0].split()[2])
rows = [list(map(float, l.split())) for l in lines[end + 1:end + 1 + nv]]
objv = [list(map(float, l.split()[1:4])) for l in open(sys.argv[2]) if l.startswith("v ")]
assert len(objv) == nv and all(abs(a - b) < 1e-5 * (1 + abs(b)) for r, o in zip(rows, objv) for a, b in zip(r[:3], o))
for c in range(3):
    col = [r[3 + c] for r in rows]
    assert min(col) >= 0 and 0.8 < sum(col) / nv < 1.25 and max(col) > min(col), (c, min(col), max(col))
PY
then ok "fit_dataset_vertex_albedo"
else bad "fit_dataset_vertex_albedo"; tail -n 3 "$build/ds_albedo.log"; fi
expect fit_vertex_albedo_needs_estimated_lighting 2 "--albedo vertex is estimated with the lighting" \
    "$ls" fit fixtures/meshes/bunny.obj --albedo vertex --iters 1 -o "$out/x"
expect fit_albedo_bad_value 2 "--albedo: bad value 'texture'" "$ls" fit --albedo texture -o "$out/x"
if "$ls" fit "$ds.lambert/transforms.json" --shading mask --iters 5 -o "$out/fit_ds_mask" > "$build/ds_mask.log" 2>&1 &&
        ! grep -q "estimating it" "$build/ds_mask.log" && ! grep -q estimated_sh "$out/fit_ds_mask/metrics.json"; then
    ok "fit_dataset_unknown_lighting_shading_mask_fits_masks"
else bad "fit_dataset_unknown_lighting_shading_mask_fits_masks"; tail -n 3 "$build/ds_mask.log"; fi
# the silhouette boost's default follows the shading: 1.5 where it is given
# (a mesh target), 3 where it is estimated; each default gives the bytes of
# its value and not those of the other
boost_fit() { # dir, target, options...
    d=$1 t=$2
    shift 2
    rm -rf "${out:?}/${d:?}"
    "$ls" fit "$t" --iters 8 --remesh none --res 32 --views 4 --threads 1 --quiet --track 0 "$@" -o "$out/$d" > /dev/null 2>&1
}
if boost_fit boost_mesh fixtures/meshes/bunny.obj && boost_fit boost_mesh15 fixtures/meshes/bunny.obj --boost 1.5 &&
        boost_fit boost_mesh3 fixtures/meshes/bunny.obj --boost 3 &&
        boost_fit boost_ds "$ds.lambert/transforms.json" && boost_fit boost_ds3 "$ds.lambert/transforms.json" --boost 3 &&
        boost_fit boost_ds15 "$ds.lambert/transforms.json" --boost 1.5 &&
        cmp -s "$out/boost_mesh/result.obj" "$out/boost_mesh15/result.obj" &&
        ! cmp -s "$out/boost_mesh/result.obj" "$out/boost_mesh3/result.obj" &&
        cmp -s "$out/boost_ds/result.obj" "$out/boost_ds3/result.obj" &&
        ! cmp -s "$out/boost_ds/result.obj" "$out/boost_ds15/result.obj"; then
    ok "fit_boost_default_follows_the_shading (1.5 given, 3 estimated)"
else bad "fit_boost_default_follows_the_shading"; fi
# the finest stage's boost: from the last scheduled remesh on, 1 by default where
# the shading is given; --boost alone holds for the whole run; with estimated
# lighting it stays 3; a remesh later than the last iteration changes nothing
if boost_fit final_mesh fixtures/meshes/bunny.obj --remesh 2,5 &&
        boost_fit final_mesh1 fixtures/meshes/bunny.obj --remesh 2,5 --boost-final 1 &&
        boost_fit final_mesh15 fixtures/meshes/bunny.obj --remesh 2,5 --boost 1.5 &&
        boost_fit final_mesh15b fixtures/meshes/bunny.obj --remesh 2,5 --boost-final 1.5 &&
        boost_fit final_late fixtures/meshes/bunny.obj --remesh 9 && boost_fit final_none fixtures/meshes/bunny.obj &&
        boost_fit final_ds "$ds.lambert/transforms.json" --remesh 2,5 &&
        boost_fit final_ds3 "$ds.lambert/transforms.json" --remesh 2,5 --boost-final 3 &&
        cmp -s "$out/final_mesh/result.obj" "$out/final_mesh1/result.obj" &&
        cmp -s "$out/final_mesh15/result.obj" "$out/final_mesh15b/result.obj" &&
        ! cmp -s "$out/final_mesh/result.obj" "$out/final_mesh15/result.obj" &&
        cmp -s "$out/final_late/result.obj" "$out/final_none/result.obj" &&
        cmp -s "$out/final_ds/result.obj" "$out/final_ds3/result.obj"; then
    ok "fit_boost_final (1 from the last remesh on, --boost alone for the whole run, 3 estimated)"
else bad "fit_boost_final"; fi
expect fit_boost_final_range 2 "--boost-final" "$ls" fit --boost-final -1 -o "$out/x"
# a start from the target itself, not smoothed, steps at lr 0.003 by default; a
# smoothed start at 0.01, as from the sphere; --lr overrides either
own=fixtures/meshes/elephant.obj
if boost_fit lr_own "$own" && boost_fit lr_own3 "$own" --lr 0.003 && boost_fit lr_own1 "$own" --lr 0.01 &&
        boost_fit lr_smooth "$own" --init-coarse 0.012 --init-smooth 2 &&
        boost_fit lr_smooth1 "$own" --init-coarse 0.012 --init-smooth 2 --lr 0.01 &&
        cmp -s "$out/lr_own/result.obj" "$out/lr_own3/result.obj" &&
        ! cmp -s "$out/lr_own/result.obj" "$out/lr_own1/result.obj" &&
        cmp -s "$out/lr_smooth/result.obj" "$out/lr_smooth1/result.obj"; then
    ok "fit_lr_follows_the_start (0.003 from the target itself, 0.01 smoothed)"
else bad "fit_lr_follows_the_start"; fi
# a scheduled remesh beyond the job's capacity is said, and the fit goes on with its mesh
expect fit_remesh_beyond_capacity_goes_on 0 "a remesh before iteration 1 would exceed the job's capacity" \
    "$ls" fit --iters 3 --remesh 1 --max-vertices 700 --res 32 --views 4 --quiet --track 0 -o "$out/cap"
# render --cameras: a dataset's own cameras give its images again, byte for
# byte, and the same transforms.json (its numbers to 1e-12); a non-square dataset with an off-centre
# principal point gives images of its size and keeps the point; --cameras
# with --views is refused; the upper-hemisphere placement stays above y = -1/4
rm -rf "$ds.again" "$ds.wide" "$ds.hemi"
if "$ls" render fixtures/meshes/bunny.obj --cameras "$ds/transforms.json" --res 48 -o "$ds.again" > "$build/ds_again.log" 2>&1 &&
        cmp -s "$ds/view_005.png" "$ds.again/view_005.png" &&
        python3 - "$ds/transforms.json" "$ds.again/transforms.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
def same(x, y):  # numbers to 1e-12 (the poses are inverted twice), the rest equal
    if isinstance(x, (int, float)) and isinstance(y, (int, float)): return abs(x - y) <= 1e-12 * max(1.0, abs(x))
    if isinstance(x, list): return isinstance(y, list) and len(x) == len(y) and all(map(same, x, y))
    if isinstance(x, dict): return isinstance(y, dict) and x.keys() == y.keys() and all(same(x[k], y[k]) for k in x)
    return x == y
sys.exit(0 if same(a, b) else 1)
PY
    then
    ok "render_cameras_reproduces_the_dataset"
else bad "render_cameras_reproduces_the_dataset"; tail -n 3 "$build/ds_again.log"; fi
sed -n '/"largesteps_clip"/p' "$ds/transforms.json" > "$build/clip.txt"
{
    printf '{"fl_x": 60, "fl_y": 60, "cx": 36, "cy": 18.5, "w": 64, "h": 40,\n'
    cat "$build/clip.txt"
    printf '"frames": [{"file_path": "a", "transform_matrix": %s}]}\n' \
        "$(sed -n 's/.*"view_002.png", "transform_matrix": \(.*\)},*$/\1/p' "$ds/transforms.json")"
} > "$build/wide.json"
if "$ls" render fixtures/meshes/bunny.obj --cameras "$build/wide.json" -o "$ds.wide" > "$build/ds_wide.log" 2>&1 &&
        [ "$(od -An -tx1 -j16 -N8 "$ds.wide/view_000.png" | tr -d ' \n')" = 0000004000000028 ] &&
        grep -q '"cx": 36,' "$ds.wide/transforms.json" && grep -q '"cy": 18.5,' "$ds.wide/transforms.json"; then
    ok "render_cameras_non_square_off_centre (64 x 40, cx 36, cy 18.5)"
else bad "render_cameras_non_square_off_centre"; cat "$build/ds_wide.log"; fi
expect render_cameras_conflict 2 "--cameras gives the views: not with --views" \
    "$ls" render fixtures/meshes/bunny.obj --cameras "$ds/transforms.json" --views 3 -o "$out/x"
expect render_cameras_malformed 1 "bad_cameras.json:1:" \
    sh -c "printf '{\"frames\": [}' > '$build/bad_cameras.json'; exec '$ls' render fixtures/meshes/bunny.obj --cameras '$build/bad_cameras.json' -o '$out/x'"
if "$ls" render fixtures/meshes/bunny.obj --placement hemisphere --views 24 --res 16 -o "$ds.hemi" > /dev/null 2>&1 &&
        python3 - "$ds.hemi/transforms.json" fixtures/meshes/bunny.obj <<'PY'
import json, sys, math
f = json.load(open(sys.argv[1]))["frames"]
v = [[float(t) for t in l.split()[1:4]] for l in open(sys.argv[2]) if l.startswith("v ")]
c = [(min(p[k] for p in v) + max(p[k] for p in v)) / 2 for k in range(3)]  # the framing's centre
ys = []
for fr in f:
    d = [fr["transform_matrix"][k][3] - c[k] for k in range(3)]
    ys.append(d[1] / math.sqrt(sum(x * x for x in d)))  # the view direction's height
sys.exit(0 if len(f) == 24 and min(ys) >= -0.25 - 1e-9 and min(ys) < 0 and max(ys) > 0.95 else 1)
PY
then ok "render_hemisphere_placement (24 views)"; else bad "render_hemisphere_placement"; fi

printf '{"camera_angle_x": 0.7,\n "frames": [{"file_path": "a", "fl_x": 3}]}\n' > "$build/bad_transforms.json"
if "$ls" fit "$build/bad_transforms.json" -o "$out/fit_bad_ds" > "$build/ds_bad.log" 2>&1; then
    bad "fit_dataset_malformed (exit 0)"
elif grep -q 'bad_transforms.json:2:33: intrinsics per frame are not supported' "$build/ds_bad.log"; then
    ok "fit_dataset_malformed ($(head -n 1 "$build/ds_bad.log" | cut -c1-90)...)"
else bad "fit_dataset_malformed"; cat "$build/ds_bad.log"; fi

# --normals flat (render) and --target-normals flat (fit): each face shaded with its own
# normal. A cube seen by one view at 32 x 32 without supersampling: its fully covered
# pixels take one colour per visible face (at most 3) when flat, hundreds when smooth
# (the default, the same bytes); a dataset target has no mesh to shade and is refused.
cc -std=c99 -O2 -Iinclude -I"$build/include" -Iport/posix tests/tools/imgtool.c "$build/liblargesteps-posix.a" \
    "$build/liblargesteps.a" -lm -o "$build/imgtool" 2> "$build/imgtool.err" || cat "$build/imgtool.err"
colours() { "$build/imgtool" dump "$1" | awk '$NF == 255 { c[$(NF-3) " " $(NF-2) " " $(NF-1)]++ } END { n = 0; for (k in c) n++; print n }'; }
{ cube 0; cube_faces 0; } > "$out/cube.obj"
for n in flat smooth default 45 60 120 auto; do
    opt="--normals $n"; [ "$n" = default ] && opt=""
    # shellcheck disable=SC2086 # $opt: an option and its value, or nothing
    "$ls" render "$out/cube.obj" --views 1 --res 32 --ss 1 --bits 8 $opt -o "$out/cube_$n" > "$build/cube_$n.log" 2>&1
done
cf=$(colours "$out/cube_flat/view_000.png"); cs=$(colours "$out/cube_smooth/view_000.png")
if [ -n "$cf" ] && [ "$cf" -ge 1 ] && [ "$cf" -le 3 ] && [ -n "$cs" ] && [ "$cs" -gt 20 ] &&
        cmp -s "$out/cube_smooth/view_000.png" "$out/cube_default/view_000.png"; then
    ok "render_normals_flat ($cf colours flat, $cs smooth)"
else bad "render_normals_flat ($cf colours flat, $cs smooth)"; fi
# --normals DEGREES splits the cube's 90-degree edges below 90 and none above
c45=$(colours "$out/cube_45/view_000.png")
if [ -n "$c45" ] && [ "$c45" -ge 1 ] && [ "$c45" -le 3 ] && cmp -s "$out/cube_smooth/view_000.png" "$out/cube_120/view_000.png" &&
        cmp -s "$out/cube_auto/view_000.png" "$out/cube_60/view_000.png"; then
    ok "render_normals_creases ($c45 colours at 45 degrees; 120 degrees the same bytes as smooth; auto as 60)"
else bad "render_normals_creases ($c45 colours at 45 degrees)"; fi
expect render_normals_bad_value 2 "--normals: 'bumpy' is not smooth, auto, flat or an angle" "$ls" render "$out/cube.obj" --normals bumpy -o "$out/x"
for n in flat smooth 45 60 120 default; do
    opt="--target-normals $n"; [ "$n" = default ] && opt=""
    # shellcheck disable=SC2086 # $opt: an option and its value, or nothing
    "$ls" fit "$out/cube.obj" $opt --iters 0 --res 32 --views 4 --quiet -o "$out/cube_fit_$n" > "$build/cube_fit_$n.log" 2>&1
done
if [ -s "$out/cube_fit_flat/contact.png" ] && [ -s "$out/cube_fit_smooth/contact.png" ] &&
        ! cmp -s "$out/cube_fit_flat/contact.png" "$out/cube_fit_smooth/contact.png" &&
        ! cmp -s "$out/cube_fit_45/contact.png" "$out/cube_fit_smooth/contact.png" &&
        cmp -s "$out/cube_fit_120/contact.png" "$out/cube_fit_smooth/contact.png"; then
    ok "fit_target_normals_change_the_targets (flat and 45 degrees differ from smooth, 120 does not)"
else bad "fit_target_normals_change_the_targets"; tail -n 3 "$build/cube_fit_flat.log" "$build/cube_fit_45.log"; fi
# The default (auto) splits a target made of flat pieces at 60 degrees and says so (a third of
# the cube's edges join coplanar faces), and leaves a smooth one as it is (the bunny: 3 %).
"$ls" fit --target-normals smooth --iters 0 --res 32 --views 4 --quiet -o "$out/bunny_fit_smooth" > "$build/bunny_fit_smooth.log" 2>&1
"$ls" fit --iters 0 --res 32 --views 4 --quiet -o "$out/bunny_fit_default" > "$build/bunny_fit_default.log" 2>&1
if cmp -s "$out/cube_fit_default/contact.png" "$out/cube_fit_60/contact.png" &&
        grep -q "the target is made of flat pieces (33 % of its edges join coplanar faces)" "$build/cube_fit_default.log" &&
        [ -s "$out/bunny_fit_default/contact.png" ] && cmp -s "$out/bunny_fit_default/contact.png" "$out/bunny_fit_smooth/contact.png" &&
        ! grep -q "flat pieces" "$build/bunny_fit_default.log"; then
    ok "fit_target_normals_auto (the cube split at 60 degrees, the bunny smooth)"
else bad "fit_target_normals_auto"; cat "$build/cube_fit_default.log"; fi
# A fit that starts from the target itself (the elephant, genus 3: the automatic start) renders it
# flat by default and says so; with a smoothed start (--init-smooth) or from the sphere, smooth as
# before (the same bytes as --target-normals smooth).
for n in default:'' flat:'--target-normals flat' smooth:'--target-normals smooth' smoothed:'--init-smooth 2' \
    smoothed_smooth:'--init-smooth 2 --target-normals smooth' sphere:'--init-sphere' \
    sphere_smooth:'--init-sphere --target-normals smooth'; do
    # shellcheck disable=SC2086 # ${n#*:}: options and their values, or nothing
    "$ls" fit fixtures/meshes/elephant.obj ${n#*:} --iters 0 --res 24 --views 2 --quiet -o "$out/el_fit_${n%%:*}" \
        > "$build/el_fit_${n%%:*}.log" 2>&1
done
if [ -s "$out/el_fit_default/contact.png" ] && [ -s "$out/el_fit_smooth/contact.png" ] &&
        cmp -s "$out/el_fit_default/contact.png" "$out/el_fit_flat/contact.png" &&
        ! cmp -s "$out/el_fit_default/contact.png" "$out/el_fit_smooth/contact.png" &&
        grep -q "the fit starts from the target itself: its renders show its faces flat" "$build/el_fit_default.log" &&
        [ -s "$out/el_fit_smoothed/contact.png" ] && [ -s "$out/el_fit_sphere/contact.png" ] &&
        cmp -s "$out/el_fit_smoothed/contact.png" "$out/el_fit_smoothed_smooth/contact.png" &&
        cmp -s "$out/el_fit_sphere/contact.png" "$out/el_fit_sphere_smooth/contact.png" &&
        ! grep -q "renders show its faces flat" "$build/el_fit_smoothed.log" "$build/el_fit_sphere.log"; then
    ok "fit_target_flat_from_its_own_start (flat from itself; smoothed or from the sphere, smooth)"
else bad "fit_target_flat_from_its_own_start"; cat "$build/el_fit_default.log"; fi
expect fit_target_normals_bad_value 2 "--target-normals" "$ls" fit "$out/cube.obj" --target-normals 180 -o "$out/x"
expect fit_target_normals_needs_a_mesh 2 "--target-normals shades the renders of a mesh target" \
    "$ls" fit "$ds/transforms.json" --target-normals flat --iters 0 -o "$out/x"

# A target only a few pixels thick at the asked size (a bar 1 x 0.03 x 0.03: 2.8 pixels in the
# median of 8 views at 128 x 128) is fitted at the size that makes it 6 thick, rounded up to a
# multiple of 64; with --res given, the size stays and a warning names the fix; the bunny (6.4
# pixels at 32 x 32) says nothing of it.
awk 'BEGIN { for (i = 0; i < 8; i++) printf "v %g %g %g\n", (i % 2), (int(i / 2) % 2) * 0.03, int(i / 4) * 0.03 }' > "$out/bar.obj"
cube_faces 0 >> "$out/bar.obj"
"$ls" fit "$out/bar.obj" --iters 0 --views 8 --quiet -o "$out/bar_fit" > "$build/bar_fit.log" 2>&1
"$ls" fit "$out/bar.obj" --iters 0 --views 8 --res 200 --quiet -o "$out/bar_fit_200" > "$build/bar_fit_200.log" 2>&1
if grep -q "the target is 2.8 pixels thick at 128 x 128 .*: fitting at 320 x 320, where it is 6.0" "$build/bar_fit.log" &&
        grep -q "8 views at 320 x 320" "$build/bar_fit.log" && ! grep -q "warning" "$build/bar_fit.log" &&
        grep -q "warning: the object is only 4.0 pixels thick .*a larger --res makes it thicker" "$build/bar_fit_200.log" &&
        grep -q "8 views at 200 x 200" "$build/bar_fit_200.log" && grep -q "(the object 6.4 pixels thick)" "$build/bunny_fit_default.log" && ! grep -q "too thin\|warning" "$build/bunny_fit_default.log"; then
    ok "fit_thin_target_rendered_larger (2.8 pixels at 128: 320 x 320; --res 200 kept, with a warning)"
else bad "fit_thin_target_rendered_larger"; cat "$build/bar_fit.log" "$build/bar_fit_200.log"; fi

echo "cli: $pass passed, $fail failed"
[ "$fail" = 0 ]
