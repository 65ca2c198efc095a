#!/bin/sh
# stage_cli_io.sh - the program's files and limits (a stage of `make test`):
# every case runs the program as a hostile user would and asserts the exit
# status, the exact message and what is left on disk. Inputs: missing,
# directory, unreadable, endless (/dev/zero), larger than the limit, gzip
# bombs and lying trailers, limits in scene files. Outputs: stdout on a full
# device, symlink / FIFO / directory / device paths, a read-only directory,
# a full disk (a 16k tmpfs when root can mount one; an injected write failure,
# LS_POSIX_FAIL_WRITE=N, for the output sets), SIGINT
# and SIGTERM during the work. Numbers: every option refuses what is not a
# whole number or finite number in its range; --help of every command.
# Native gcc double build only; LS_BIN=path runs the cases against another
# build (every case fails on the program before this stage was added).
jobs=${JOBS:-2}
build=build/cli
out=$build/io
pass=0 fail=0
mkdir -p build/logs "$build"
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
if ! make --no-print-directory -j"$jobs" BUILD="$build" CC=gcc REAL=double all > build/logs/cli-io-build.log 2>&1; then
    tail -n 20 build/logs/cli-io-build.log
    bad "cli_io_build"
    echo "cli_io: $pass passed, $fail failed"
    exit 1
fi
ls=${LS_BIN:-$(pwd)/$build/largesteps} # LS_BIN: run the cases against another build (e.g. an older one)
rm -rf "$out"
mkdir -p "$out"
mesh=fixtures/meshes/bunny.obj

# expect NAME STATUS MESSAGE command...: the exit status and one stderr line
# exactly MESSAGE (no pattern: the whole line). expect_pattern: the line
# matching an extended REGEX instead (for messages naming whichever file the
# system refused first).
expect_line() { # grep mode (-F or -E), then expect's arguments
    mode=$1 name=$2 want=$3 msg=$4
    shift 4
    "$@" > "$out/$name.out" 2> "$out/$name.err"
    got=$?
    if [ "$got" = "$want" ] && grep -q -x "$mode" -e "$msg" "$out/$name.err"; then ok "$name"
    else bad "$name (status $got, wanted $want; wanted the line ($mode): $msg)"; head -n 3 "$out/$name.err"; fi
}
expect() { expect_line -F "$@"; }
expect_pattern() { expect_line -E "$@"; }
# time-capped: fails if the command does not end within SECONDS
capped() { secs=$1; shift; timeout "$secs" "$@"; }

# ---- inputs ----------------------------------------------------------------
expect read_missing 1 "largesteps: cannot read $out/missing.obj: No such file or directory" "$ls" info "$out/missing.obj"
expect read_directory 1 "largesteps: cannot read $out: Is a directory" "$ls" info "$out"
expect fit_missing_reason 1 "largesteps: cannot read $out/missing.obj: No such file or directory" \
    "$ls" fit "$out/missing.obj" --iters 1 -o "$out/fit_missing"
if [ "$(id -u)" != 0 ]; then
    cp "$mesh" "$out/secret.obj" && chmod 000 "$out/secret.obj"
    expect read_permission 1 "largesteps: cannot read $out/secret.obj: Permission denied" "$ls" info "$out/secret.obj"
fi
expect read_endless_dev_zero 1 "largesteps: cannot read /dev/zero: larger than the input limit of 256 MB (--max-input-mb N raises it)" \
    capped 20 "$ls" info /dev/zero
awk 'BEGIN { for (i = 0; i < 60000; i++) printf "v %d 0.000000000 0.000000000\n", i }' > "$out/big.obj" # 1.7 MB
expect read_limit_option 1 "largesteps: cannot read $out/big.obj: larger than the input limit of 1 MB (--max-input-mb N raises it)" \
    "$ls" --max-input-mb 1 metrics "$mesh" "$out/big.obj"
expect read_limit_option_after 1 "largesteps: cannot read $out/big.obj: larger than the input limit of 1 MB (--max-input-mb N raises it)" \
    "$ls" info "$out/big.obj" --max-input-mb 1
# gzip: the decompressed size counts (the armadillo: 0.7 MB compressed, 1.6 MB of text)
expect read_limit_gzip 1 "largesteps: cannot read fixtures/meshes/armadillo.obj.gz: larger than the input limit of 1 MB (--max-input-mb N raises it)" \
    "$ls" info fixtures/meshes/armadillo.obj.gz --max-input-mb 1
expect read_limit_bad_value 2 "largesteps info: --max-input-mb: '0' is not a whole number in [1, 1048576]" \
    "$ls" info "$mesh" --max-input-mb 0
# a gzip bomb: 300 MB of zeros in 1.3 MB; the trailer says 300 MB: refused before inflating
head -c 300000000 /dev/zero | gzip -1 > "$out/bomb.gz"
expect read_gzip_bomb 1 "largesteps: cannot read $out/bomb.gz: larger than the input limit of 256 MB (--max-input-mb N raises it)" \
    capped 20 "$ls" info "$out/bomb.gz"
# the same stream with a trailer that lies (ISIZE 1000): inflating stops at 1000 bytes
python3 - "$out" <<'PY'
import gzip, struct, sys
d = open(sys.argv[1] + "/bomb.gz", "rb").read()
open(sys.argv[1] + "/lie.gz", "wb").write(d[:-4] + struct.pack("<I", 1000))
s = gzip.compress(b"v 0 0 0\n")
open(sys.argv[1] + "/bigisize.gz", "wb").write(s[:-4] + struct.pack("<I", 200 << 20))
PY
expect read_gzip_lying_trailer 1 "largesteps: cannot read $out/lie.gz: corrupt gzip data: it decompresses to more than its trailer's length" \
    capped 20 "$ls" info "$out/lie.gz"
expect read_gzip_big_isize 1 "largesteps: cannot read $out/bigisize.gz: corrupt gzip data: its length does not match the trailer" \
    capped 20 "$ls" info "$out/bigisize.gz"
# a scene naming an endless file: the limit holds for the files a scene names
mkdir -p "$out/scene"
printf 'largesteps-scene 1\nresolution 16 16\nviews fibonacci 2 25 0 4.8 0\ntarget mesh /dev/zero\ninitial icosphere 1\n' > "$out/scene/zero.txt"
expect read_scene_target_dev_zero 1 "largesteps: cannot read /dev/zero: larger than the input limit of 256 MB (--max-input-mb N raises it)" \
    capped 30 "$ls" fit "$out/scene/zero.txt" --iters 1 --quiet -o "$out/scene/out"

# a Mitsuba scene naming an endless file (filename="/dev/urandom" for its environment map)
cat > "$out/scene/urandom.xml" <<'XML'
<?xml version="1.0"?>
<scene version="2.0.0">
  <sensor type="perspective">
    <float name="fov" value="45"/>
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>
  <emitter type="envmap"><string name="filename" value="/dev/urandom"/></emitter>
  <shape type="obj" id="mesh-target"><string name="filename" value="/dev/zero"/></shape>
</scene>
XML
expect read_mitsuba_filename_dev_urandom 1 "largesteps: cannot read /dev/urandom: larger than the input limit of 1 MB (--max-input-mb N raises it)" \
    capped 30 "$ls" --max-input-mb 1 fit "$out/scene/urandom.xml" --iters 1 --quiet -o "$out/scene/out"

# ---- standard output ---------------------------------------------------------
if [ -w /dev/full ]; then
    expect stdout_full_metrics_json 1 "largesteps: writing to standard output failed: No space left on device" \
        sh -c "\"$ls\" metrics $mesh $mesh --samples 100 --json > /dev/full"
    expect stdout_full_info 1 "largesteps: writing to standard output failed: No space left on device" sh -c "\"$ls\" info > /dev/full"
    expect stdout_full_version 1 "largesteps: writing to standard output failed: No space left on device" sh -c "\"$ls\" version > /dev/full"
fi


# ---- JSON ----------------------------------------------------------------------
# vertices at +-1e300: the distances overflow; the JSON stays valid (null, and why)
printf 'v -1e300 -1e300 0\nv 1e300 -1e300 0\nv 0 1e300 0\nv 0 0 1e300\nf 1 2 3\nf 1 2 4\n' > "$out/huge.obj"
"$ls" metrics "$out/huge.obj" "$out/huge.obj" --samples 10 --json > "$out/huge.json" 2> "$out/huge.err"
st=$?
if [ $st = 0 ] && python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if d["diag_b"] is None and d["not_finite"]["diag_b"] == "inf" else 1)' "$out/huge.json"; then
    ok "metrics_json_valid_with_non_finite_values"; else bad "metrics_json_valid_with_non_finite_values (status $st)"; head -c 300 "$out/huge.json"; fi

# ---- overlapping boxes -----------------------------------------------------------
# A triangle fan (a centre and 99,999 rim points: a sample lies in the
# axis-aligned boxes of a share of all faces) and one vertex with 10^6
# degenerate faces: `metrics` of each against itself ends within the cap
# (about 4 s and 2.5 s on a 2-core VM; the fan took about 30 minutes before
# the oriented boxes) with every distance 0 up to the rounding of the slivers.
awk 'BEGIN { n = 100000; m = n - 1; print "v 0 0 0"; pi = atan2(0, -1)
    for (i = 0; i < m; i++) printf "v %.17g %.17g 0\n", cos(2 * pi * i / m), sin(2 * pi * i / m)
    for (i = 0; i < m - 1; i++) printf "f 1 %d %d\n", i + 2, i + 3; printf "f 1 %d 2\n", m + 1 }' > "$out/fan.obj"
awk 'BEGIN { print "v 0 0 0"; for (i = 0; i < 1000000; i++) print "f 1 1 1" }' > "$out/degenerate.obj"
for case in fan degenerate; do
    capped 60 "$ls" metrics "$out/$case.obj" "$out/$case.obj" --json > "$out/$case.json" 2> "$out/$case.err"
    st=$?
    if [ $st = 0 ] && python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if d["hausdorff_rel"] < 1e-7 and d["vertex_hausdorff"] == 0 else 1)' "$out/$case.json"; then
        ok "metrics_overlapping_boxes_$case"; else bad "metrics_overlapping_boxes_$case (status $st: 124 is the 60 s cap)"; head -c 300 "$out/$case.json"; fi
done
rm -f "$out/fan.obj" "$out/degenerate.obj"

# ---- numbers and options --------------------------------------------------------
expect num_views_wraps 2 "largesteps fit: --views: '-18446744073709551615' is not a whole number in [1, 1024]" "$ls" fit --views -18446744073709551615 -o "$out/x"
expect num_iters_suffix 2 "largesteps experiment: --iters: '5abc' is not a whole number in [1, 1000000]" "$ls" experiment views --iters 5abc -o "$out/x"
expect num_res_fraction 2 "largesteps experiment: --res: '8.9' is not a whole number in [8, 4096]" "$ls" experiment views --res 8.9 -o "$out/x"
expect num_remesh_iters_fraction 2 "largesteps remesh: --iters: '1.5' is not a whole number in [1, 1000]" "$ls" remesh "$mesh" --iters 1.5 -o "$out/x.obj"
expect num_texture_res_overflow 2 "largesteps experiment texture: --res: '4294967304' is not a whole number in [8, 1024]" "$ls" experiment texture --res 4294967304 -o "$out/x"
expect num_texture_time_nan 2 "largesteps experiment texture: --time: 'nan' is not a number in (0, 1000000]" "$ls" experiment texture --time nan -o "$out/x"
expect num_boost_huge_negative 2 "largesteps fit: --boost: '-1e308' is not a number in [0, 1000000]" "$ls" fit --boost -1e308 -o "$out/x"
expect num_grad_limit_negative 2 "largesteps fit: --grad-limit: '-0.5' is not a number in [0, 1000000]" "$ls" fit --grad-limit -0.5 -o "$out/x"
expect num_mask_pull_nan 2 "largesteps fit: --mask-pull: 'nan' is not a number in [0, 1e+12]" "$ls" fit --mask-pull nan -o "$out/x"
expect num_lambda_negative 2 "largesteps fit: --lambda: '-1' is not a number in [0, 1e+12]" "$ls" fit --lambda -1 -o "$out/x"
expect num_lr_zero 2 "largesteps fit: --lr: '0' is not a number in (0, 1000000]" "$ls" fit --lr 0 -o "$out/x"
expect num_samples_sign 2 "largesteps metrics: --samples: '+5' is not a whole number in [0, 4294967295]" "$ls" metrics "$mesh" "$mesh" --samples +5
expect num_tradeoffs_level 2 "largesteps experiment tradeoffs: --level: '8' is not a whole number in [0, 7]" "$ls" experiment tradeoffs --level 8 -o "$out/x"
expect num_toy1d_iters 2 "largesteps toy1d: --iters: '0x10' is not a whole number in [1, 100000]" "$ls" toy1d --iters 0x10 -o "$out/x"
expect num_render_fov 2 "largesteps render: --fov: 'inf' is not a number in (0, 180)" "$ls" render "$mesh" --fov inf -o "$out/x"
expect opt_lambda_alpha_conflict 2 "largesteps fit: --lambda and --alpha conflict (two forms of the same weight: give one)" "$ls" fit --lambda 19 --alpha 0.95 -o "$out/x"
expect opt_remesh_h_factor_conflict 2 "largesteps remesh: --h and --factor conflict (give one: an edge length or a factor)" "$ls" remesh "$mesh" --h 0.1 --factor 0.5 -o "$out/x.obj"
printf 'largesteps-scene 1\nresolution 16 16\nviews fibonacci 2 25 0 4.8 0\nbackground nan 0 0\ntarget mesh bunny.obj\n' > "$out/scene/nan.txt"
expect scene_background_nan 1 "largesteps: $out/scene/nan.txt:4:1: background: expected R G B (finite numbers)" "$ls" fit "$out/scene/nan.txt" -o "$out/x"
for c in fit render remesh metrics info toy1d experiment "experiment tradeoffs" "experiment texture" version; do
    # shellcheck disable=SC2086 # the command may be two words
    if "$ls" $c --help > "$out/help.out" 2>&1 && grep -q '^usage: largesteps' "$out/help.out"; then ok "help_exits_0: $c"; else bad "help_exits_0: $c"; fi
done
if grep -q -e '--max-input-mb' "$out/help.out" || "$ls" fit --help | grep -q -e '--max-input-mb'; then ok "help_lists_global_options"; else bad "help_lists_global_options"; fi
if [ ! -e "$out/x" ]; then ok "refused_options_write_nothing"; else bad "refused_options_write_nothing"; fi

# ---- output paths, checked before any work -------------------------------------
expect out_unknown_extension 2 "largesteps remesh: -o: '$out/out.stl' has an unknown extension (.obj or .ply)" "$ls" remesh "$mesh" -o "$out/out.stl"
: > "$out/regular"
expect out_dir_is_a_file 2 "largesteps: -o $out/regular: it exists and is not a directory" capped 5 "$ls" fit --iters 1000 -o "$out/regular"
cp "$mesh" "$out/precious.obj"
ln -sf precious.obj "$out/link.obj"
expect out_symlink_refused 2 "largesteps: cannot write $out/link.obj: it is a symbolic link; only regular files are replaced" \
    "$ls" remesh "$mesh" --iters 1 -o "$out/link.obj"
if [ -L "$out/link.obj" ] && cmp -s "$mesh" "$out/precious.obj"; then ok "out_symlink_untouched"; else bad "out_symlink_untouched"; fi
mkfifo "$out/fifo.obj"
expect out_fifo_refused 2 "largesteps: cannot write $out/fifo.obj: it is a FIFO; only regular files are replaced" \
    capped 10 "$ls" remesh "$mesh" --iters 1 -o "$out/fifo.obj"
mkdir -p "$out/dir.obj"
expect out_directory_refused 2 "largesteps: cannot write $out/dir.obj: it is a directory; only regular files are replaced" \
    "$ls" remesh "$mesh" --iters 1 -o "$out/dir.obj"
# a device node (made in our own directory: /dev itself is never touched)
if [ "$(id -u)" = 0 ] && mknod "$out/full.ply" c 1 7 2> /dev/null; then
    expect out_device_refused 2 "largesteps: cannot write $out/full.ply: it is a character device; only regular files are replaced" \
        "$ls" remesh "$mesh" --iters 1 -o "$out/full.ply"
    if [ -c "$out/full.ply" ]; then ok "out_device_untouched"; else bad "out_device_untouched"; fi
fi
expect out_missing_directory 2 "largesteps: cannot write $out/no/such/x.obj: No such file or directory" "$ls" remesh "$mesh" -o "$out/no/such/x.obj"

# ---- read-only directory and full disk ------------------------------------------
mnt=$out/mnt
mkdir -p "$mnt/ro" "$mnt/full"
if [ "$(id -u)" = 0 ] && mount -t tmpfs -o ro,size=64k tmpfs "$mnt/ro" 2> /dev/null; then
    expect out_read_only_fs 2 "largesteps: cannot write $mnt/ro/x.obj: Read-only file system" "$ls" remesh "$mesh" --iters 1 -o "$mnt/ro/x.obj"
    umount "$mnt/ro"
elif [ "$(id -u)" != 0 ]; then
    chmod 555 "$mnt/ro"
    expect out_read_only_dir 2 "largesteps: cannot write $mnt/ro/x.obj: Permission denied" "$ls" remesh "$mesh" --iters 1 -o "$mnt/ro/x.obj"
    chmod 755 "$mnt/ro"
fi
leftovers() { find "$1" -name '.*.??????' 2> /dev/null | head -n 1; }
if [ "$(id -u)" = 0 ] && mount -t tmpfs -o size=16k tmpfs "$mnt/full" 2> /dev/null; then
    printf 'an earlier table\n' > "$mnt/full/views.md"
    expect full_disk_experiment 1 "largesteps: cannot write $mnt/full/views.md: No space left on device" \
        sh -c "head -c 12000 /dev/zero > '$mnt/full/filler'; exec \"$ls\" experiment views --iters 2 --res 8 --level 0 -o '$mnt/full'"
    if [ "$(cat "$mnt/full/views.md")" = "an earlier table" ] && [ -z "$(leftovers "$mnt/full")" ]; then
        ok "full_disk_keeps_the_earlier_table"; else bad "full_disk_keeps_the_earlier_table"; ls -la "$mnt/full"; fi
    rm -f "$mnt/full/filler" "$mnt/full/views.md"
    # which file of the set meets the full disk first depends on the kernel's
    # tmpfs accounting; what matters is the message and that nothing is left
    expect_pattern full_disk_fit 1 "largesteps: cannot write $mnt/full/[a-z_]+\.(png|obj|ply|csv|json|svg|md): No space left on device; no file of the set was written" \
        "$ls" fit --iters 2 --res 64 --views 4 --level 1 --remesh none --quiet -o "$mnt/full"
    if [ -z "$(ls -A "$mnt/full")" ]; then ok "full_disk_fit_writes_nothing"; else bad "full_disk_fit_writes_nothing"; ls -la "$mnt/full"; fi
    umount "$mnt/full"
fi
# an earlier run's set stays whole when a later run cannot write (injected: the 4th file fails)
"$ls" fit --iters 3 --res 16 --views 2 --level 1 --remesh none --quiet -o "$out/sets" > /dev/null 2>&1
LS_POSIX_FAIL_WRITE=4 "$ls" fit --iters 6 --res 16 --views 2 --level 1 --remesh none --quiet -o "$out/sets" > /dev/null 2> "$out/sets.err"
st=$?
if [ $st = 1 ] && grep -q -x -F "largesteps: cannot write $out/sets/contact.png: No space left on device; no file of the set was written" "$out/sets.err" &&
    grep -q '"iterations": 3,' "$out/sets/metrics.json" && [ "$(ls -A "$out/sets" | wc -l)" = 5 ] && [ -z "$(leftovers "$out/sets")" ]; then
    ok "failed_fit_leaves_the_earlier_set_whole"; else bad "failed_fit_leaves_the_earlier_set_whole (status $st)"; cat "$out/sets.err"; ls -la "$out/sets"; fi
LS_POSIX_FAIL_WRITE=1 "$ls" remesh "$mesh" --iters 1 -o "$out/precious.obj" > /dev/null 2> "$out/remesh_fail.err"
st=$?
if [ $st = 1 ] && cmp -s "$mesh" "$out/precious.obj" && [ -z "$(leftovers "$out")" ]; then ok "failed_write_keeps_the_old_file"; else bad "failed_write_keeps_the_old_file (status $st)"; fi

# ---- signals: SIGINT and SIGTERM during work and during writes -------------------
# during the work: 0.05 s after the start (loading, rendering); during the writes: as soon as
# the first file (a temporary or a view) appears in the output directory. The
# directory must then hold no temporary and either no file or the whole set.
for sig in INT TERM; do
    for when in work writes; do
        d=$out/sig_${sig}_$when
        mkdir -p "$d"
        # (a background job starts with SIGINT ignored: restored to the default first)
        python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); os.execv(sys.argv[1], sys.argv[1:])' \
            "$ls" render "$mesh" --views 24 --res 512 --ss 1 -o "$d" > /dev/null 2>&1 &
        pid=$!
        if [ $when = work ]; then # once the wrapper has become the program (Linux: /proc)
            k=0
            while [ "$(cat "/proc/$pid/comm" 2> /dev/null)" != largesteps ] && [ $k -lt 300 ] && kill -0 "$pid" 2> /dev/null; do
                sleep 0.01; k=$((k + 1)); done
            sleep 0.05
        else
            k=0
            while [ -z "$(ls -A "$d")" ] && [ $k -lt 3000 ] && kill -0 "$pid" 2> /dev/null; do sleep 0.01; k=$((k + 1)); done
        fi
        kill -s "$sig" "$pid" 2> /dev/null
        wait "$pid"
        n=$(ls -A "$d" 2> /dev/null | wc -l)
        if [ -z "$(leftovers "$d")" ] && { [ "$n" = 0 ] || [ "$n" = 25 ]; }; then ok "signal_${sig}_during_${when}_leaves_no_temporary ($n files)"
        else bad "signal_${sig}_during_${when}_leaves_no_temporary"; ls -la "$d"; fi
    done
done

echo "cli_io: $pass passed, $fail failed"
[ "$fail" = 0 ]
