#!/bin/sh
# stage_images.sh - the image codecs against OpenImageIO (Debian openimageio-tools).
#   read_*   we decode what oiiotool writes (zlib-compressed PNG 8/16-bit grey,
#            grey+alpha, RGB, RGBA; PGM/PPM 8/16-bit) and the Python-zlib fixtures of
#            fixtures/images (palette, 1/2/4-bit, Adam7, tRNS): size, channels, type
#            and every pixel equal `oiiotool --dumpdata` (integers, unassociated alpha).
#   write_*  oiiotool reads what we write with identical pixels: PNG and PGM/PPM give
#            the same `oiiotool --dumpdata` as the source; PFM (little- and big-endian)
#            gives exactly the floats q / M (printed %.9f) of the source's integers.
#   idiff_*  `idiff -fail 0` passes between a source and our re-encoding of it
#            (a few per format: each OpenImageIO start-up costs about 1 s).
#   golden_* golden renders (fixtures/render) against fresh ones with
#            `idiff -fail 0 -warn 0` (zero tolerance): the strips of
#            tests/test_shade.c (golden_renders, written by the test with
#            LS_GOLDEN_OUT=DIR) and the `largesteps render` sets listed in
#            fixtures/render/goldens.txt (contact sheet and first view of each);
#            plus a control that a one-step (1/65535) change fails idiff.
#   deflate_* the program's compressed PNGs decode (Python's zlib, oiiotool and
#            our inflate) to the pixels of their stored re-encoding, within
#            1.3 x the size of zlib -6 of the same rows.
# oiiotool and idiff take ~1 s to start, so files are generated and dumped in
# batches. Prints ok/FAIL lines and "images: N passed, M failed".
pass=0 fail=0
ok()  { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; if [ -n "$2" ]; then printf '%s\n' "$2" | head -n 8 | sed 's/^/     /'; fi; }
finish() { echo "images: $pass passed, $fail failed"; [ "$fail" = 0 ]; exit $?; }

for tool in oiiotool idiff; do
    command -v $tool >/dev/null 2>&1 || { bad "tool_$tool ($tool is missing: apt-get install openimageio-tools)"; finish; }
done
# IMAGES_BUILD=dir IMAGES_NO_MAKE=1: use a library built elsewhere (development)
B=${IMAGES_BUILD:-build/gcc-double}
[ -n "$IMAGES_NO_MAKE" ] || make --no-print-directory BUILD=$B CC=gcc CXX=g++ REAL=double all >$B.stage-images.log 2>&1 ||
    { bad "build_$B" "$(tail -n 5 $B.stage-images.log)"; finish; }
D=build/stage-images
rm -rf $D
mkdir -p $D/src $D/out $D/dump
T=$D/imgtool
if cc -std=c99 -O2 -Wall -Wextra -Werror -Iinclude -I$B/include -Iport/posix tests/tools/imgtool.c \
    $B/liblargesteps-posix.a $B/liblargesteps.a -lm -o $T 2>$D/imgtool.err; then
    ok "build_imgtool"
else
    bad "build_imgtool" "$(cat $D/imgtool.err)"
    finish
fi

# One oiiotool run writes every source: noise (few matches), gradients and
# checkers (long matches, dynamic Huffman blocks), at 8 and 16 bits.
set --
for bits in 8 16; do
    [ $bits = 8 ] && d=uint8 || d=uint16
    set -- "$@" \
        --pattern noise:type=uniform:min=0:max=1:seed=1 97x61 1 -d $d -o $D/src/noise_grey$bits.png \
        --pattern noise:type=uniform:min=0:max=1:seed=2 97x61 2 -d $d -o $D/src/noise_ga$bits.png \
        --pattern noise:type=uniform:min=0:max=1:seed=3 97x61 3 -d $d -o $D/src/noise_rgb$bits.png \
        --pattern noise:type=uniform:min=0:max=1:seed=4 97x61 4 -d $d -o $D/src/noise_rgba$bits.png \
        --pattern fill:topleft=0,0,0:topright=1,0,0.5:bottomleft=0,1,0.25:bottomright=1,1,1 301x203 3 -d $d -o $D/src/grad_rgb$bits.png \
        --pattern checker:width=7:height=5:color1=0.1,0.2,0.3,0.4:color2=0.9,0.8,0.7,1 157x129 4 -d $d -o $D/src/check_rgba$bits.png \
        --pattern fill:top=0:bottom=1 31x517 1 -d $d -o $D/src/grad_grey$bits.png \
        --pattern noise:type=uniform:min=0:max=1:seed=5 53x41 3 -d $d -o $D/src/noise_rgb$bits.ppm \
        --pattern noise:type=uniform:min=0:max=1:seed=6 53x41 1 -d $d -o $D/src/noise_grey$bits.pgm \
        --pattern fill:top=0,0.5,1:bottom=1,0.5,0 64x300 3 -d $d -o $D/src/grad_rgb$bits.ppm
done
if oiiotool --nosoftwareattrib "$@" >$D/gen.txt 2>&1; then ok "generate_sources_with_oiiotool"
else bad "generate_sources_with_oiiotool" "$(cat $D/gen.txt)"; finish; fi

# oiiotool --dumpdata of many files, split into one file per input under
# $D/dump (named after the path): a normalised header "W x H, C channel, TYPE",
# then the pixel lines without oiiotool's float echo in parentheses.
dump_all() {
    n=$#
    for f in "$@"; do set -- "$@" --iconfig oiio:UnassociatedAlpha 1 "$f"; done
    shift $n
    oiiotool --dumpdata "$@" 2>&1 | awk -v dir="$D/dump" '
        /^[^ ].* : +[0-9]+ x +[0-9]+,/ {
            if (out != "") close(out)
            f = $0; sub(/ +:.*/, "", f); gsub("/", "_", f); out = dir "/" f ".txt"
            h = $0; sub(/^.* : +/, "", h); gsub(/ +/, " ", h); sub(/ [a-z]+$/, "", h)
            print h > out; next }
        /^ +Pixel/ { sub(/ \([^()]*\)$/, ""); print > out; next }
        { print "unexpected: " $0 > (dir "/_unexpected.txt") }'
}
theirs() { echo "$D/dump/$(echo "$1" | tr / _).txt"; }

# OpenImageIO 2.4's PNM reader returns some 16-bit samples one too low (59241
# read as 59240), so 16-bit PGM/PPM files are dumped by this independent
# Python reader instead (binary P5/P6, maxval 255 or 65535).
pnm16_dump() { # file -> same layout as dump_all
    python3 - "$1" <<'PY'
import sys
d = open(sys.argv[1], 'rb').read()
tok, pos = [], 2
while len(tok) < 3:
    while d[pos:pos + 1].isspace(): pos += 1
    if d[pos:pos + 1] == b'#':
        while d[pos:pos + 1] not in (b'\n', b'\r'): pos += 1
        continue
    start = pos
    while not d[pos:pos + 1].isspace(): pos += 1
    tok.append(int(d[start:pos]))
w, h, maxval = tok
ch = 1 if d[:2] == b'P5' else 3
data = d[pos + 1:]
b = 2 if maxval > 255 else 1
print('%d x %d, %d channel, %s' % (w, h, ch, 'uint16' if b == 2 else 'uint8'))
for y in range(h):
    for x in range(w):
        vals = []
        for c in range(ch):
            i = ((y * w + x) * ch + c) * b
            vals.append(str(int.from_bytes(data[i:i + b], 'big')))
        print('    Pixel (%d, %d): %s' % (x, y, ' '.join(vals)))
PY
}

# --- we read what oiiotool (and Python's zlib) wrote -----------------------
dump_all $D/src/* fixtures/images/*.png
for f in $D/src/* fixtures/images/*.png; do
    name=read_$(basename "$f" | tr . _)
    case "$f" in fixtures/*) name=read_fixture_$(basename "$f" .png) ;; esac
    if ! $T dump "$f" > $D/ours.txt 2>$D/err.txt; then bad "$name" "$(cat $D/err.txt)"; continue; fi
    t=$(theirs "$f")
    case "$f" in *16.ppm | *16.pgm) pnm16_dump "$f" > $D/py.txt; t=$D/py.txt ;; esac
    if [ -s "$t" ] && cmp -s $D/ours.txt "$t"; then ok "$name"
    else bad "$name" "$(diff $D/ours.txt "$t" 2>&1 | head -n 6)"; fi
done

# --- oiiotool reads what we wrote ------------------------------------------
: > $D/writes.txt
for f in $D/src/* fixtures/images/c3_b4_i1_t1_split.png fixtures/images/c0_b2_i0_t0_dyn.png \
    fixtures/images/c2_b16_i1_t0_dyn.png fixtures/images/c0_b16_i1_t1_dyn.png; do
    base=$(basename "$f" | tr . _)
    t=$(theirs "$f")
    ch=$(sed -n '1s/.*, \([0-9]\) channel.*/\1/p' "$t")
    case "$(head -n 1 "$t")" in *uint16*) bits=16 ;; *) bits=8 ;; esac
    case "$f" in fixtures/*) set -- png ;; *) set -- png pnm pfm pfmbe ;; esac
    for kind in "$@"; do
        case $kind in
        png) out=$D/out/$base.png; args="png $ch $bits" ;;
        pnm) [ "$ch" = 1 ] || [ "$ch" = 3 ] || continue; out=$D/out/$base.pnm; args="pnm $ch $bits" ;;
        pfm) [ "$ch" = 1 ] || [ "$ch" = 3 ] || continue; out=$D/out/${base}_le.pfm; args="pfm $ch 32" ;;
        pfmbe) [ "$ch" = 1 ] || [ "$ch" = 3 ] || continue; out=$D/out/${base}_be.pfm; args="pfm $ch 32 be" ;;
        esac
        # shellcheck disable=SC2086
        if $T convert "$f" "$out" $args 2>$D/err.txt; then echo "$f $out" >> $D/writes.txt
        else bad "write_$(basename "$out" | tr . _)" "$(cat $D/err.txt)"; fi
    done
done
# shellcheck disable=SC2046
dump_all $(awk '{print $2}' $D/writes.txt)
while read -r src out; do
    name=write_$(basename "$out" | tr . _)
    case "$out" in
    *.pfm) $T dumpf "$src" | sed '1s/, uint[0-9]*$/, float/' > $D/want.txt ;;
    *16.ppm | *16.pgm) ;;
    *) cp "$(theirs "$src")" $D/want.txt ;;
    esac
    case "$src:$out" in *16.ppm:*.pnm | *16.pgm:*.pnm | *16.ppm:*.png | *16.pgm:*.png) pnm16_dump "$src" > $D/want.txt ;; esac
    got=$(theirs "$out")
    if [ "${out%.pnm}" != "$out" ] && grep -q uint16 "$got"; then pnm16_dump "$out" > $D/py.txt; got=$D/py.txt; fi
    if [ -s "$got" ] && cmp -s "$got" $D/want.txt; then ok "$name"
    else bad "$name" "$(diff "$got" $D/want.txt 2>&1 | head -n 6)"; fi
done < $D/writes.txt
[ -s $D/dump/_unexpected.txt ] && bad "oiiotool_dump_format" "$(head -n 5 $D/dump/_unexpected.txt)"

# --- idiff on a few pairs ---------------------------------------------------
for pair in "noise_rgba16.png noise_rgba16_png.png" "grad_rgb8.png grad_rgb8_png.png" \
    "noise_grey16.pgm noise_grey16_pgm.pnm" "grad_rgb8.ppm grad_rgb8_ppm.pnm" "noise_ga8.png noise_ga8_png.png"; do
    set -- $pair
    if idiff -fail 0 $D/src/$1 $D/out/$2 >$D/idiff.txt 2>&1; then ok "idiff_$(echo "$2" | tr . _)"
    else bad "idiff_$(echo "$2" | tr . _)" "$(cat $D/idiff.txt)"; fi
done
# PFM against the 8-bit source: OpenImageIO converts q to float as q * (1/255),
# which can differ from our q / 255 by one ulp, so the tolerance is 1e-6 (a
# fifteenth of a 16-bit step: a different integer would fail it).
if idiff -fail 1e-6 $D/src/noise_rgb8.png $D/out/noise_rgb8_png_be.pfm >$D/idiff.txt 2>&1; then
    ok "idiff_noise_rgb8_pfm_be_within_1e-6"
else
    bad "idiff_noise_rgb8_pfm_be_within_1e-6" "$(cat $D/idiff.txt)"
fi

# --- golden renders, zero tolerance -----------------------------------------
# (double builds: the float goldens are checked by test_shade in float builds)
R=$D/render
mkdir -p $R/shade
golden() { # name fresh golden
    if [ ! -f "$2" ]; then bad "golden_$1" "not rendered: $2"; return; fi
    if idiff -fail 0 -warn 0 "$2" "$3" >$D/idiff.txt 2>&1; then ok "golden_$1"
    else bad "golden_$1" "$(cat $D/idiff.txt)"; fi
}
if make --no-print-directory BUILD=$B CC=gcc CXX=g++ REAL=double $B/tests/test_shade >$D/test_shade_build.log 2>&1 &&
    LS_GOLDEN_OUT=$R/shade $B/tests/test_shade >$D/test_shade.log 2>&1; then
    ok "golden_test_shade_runs"
else
    bad "golden_test_shade_runs" "$(tail -n 5 $D/test_shade_build.log $D/test_shade.log)"
fi
for m in mask sh lambert; do
    golden "test_shade_bunny_${m}_double" $R/shade/bunny_${m}_double.png fixtures/render/bunny_${m}_double.png
done
grep -v '^#' fixtures/render/goldens.txt > $D/goldens.txt
while read -r name mesh args; do
    [ -n "$name" ] || continue
    # shellcheck disable=SC2086
    if $B/largesteps render "$mesh" $args -o $R/$name >$R/$name.log 2>&1; then ok "render_$name"
    else bad "render_$name" "$(tail -n 5 $R/$name.log)"; continue; fi
    for g in fixtures/render/${name}__*.png; do
        f=${g#fixtures/render/${name}__}
        golden "${name}_$(basename "$f" .png)" "$R/$name/$f" "$g"
    done
done < $D/goldens.txt
# control: every sample one 16-bit step brighter must fail at zero tolerance
if oiiotool --iconfig oiio:UnassociatedAlpha 1 fixtures/render/cli_bunny_sh__view_000.png --addc 0.0000152590219 \
        -d uint16 -o $R/plus_one_step.png >$D/control.txt 2>&1 &&
    ! idiff -fail 0 -warn 0 $R/plus_one_step.png fixtures/render/cli_bunny_sh__view_000.png >>$D/control.txt 2>&1; then
    ok "golden_control_one_step_fails"
else
    bad "golden_control_one_step_fails" "$(cat $D/control.txt)"
fi
# --- the PNG writer's compression (deflate) --------------------------------
# The program's outputs (two 128 x 128 views and their contact sheet, 8 and
# 16 bits): Python's zlib (an independent inflate) and our own decoder give
# the same rows as the stored re-encoding (imgtool convert ... pngstored),
# oiiotool reads the same pixels from both, and the file is within 1.3 x the
# size of zlib -6 of the unfiltered rows (plus 57 bytes of PNG chunks).
Z=$D/deflate
mkdir -p $Z
for bits in 8 16; do
    if $B/largesteps render fixtures/meshes/bunny.obj --views 2 --res 128 --bits $bits -o $Z/b$bits >$Z/b$bits.log 2>&1; then
        ok "deflate_render_${bits}bit"
    else bad "deflate_render_${bits}bit" "$(tail -n 5 $Z/b$bits.log)"; continue; fi
    for f in view_000 contact; do
        $T convert $Z/b$bits/$f.png $Z/b$bits/${f}_stored.png pngstored 4 $bits 2>$Z/err.txt ||
            bad "deflate_stored_copy_${f}_${bits}bit" "$(cat $Z/err.txt)"
    done
done
set --
for f in $Z/b*/view_000.png $Z/b*/contact.png $Z/b*/*_stored.png; do set -- "$@" "$f"; done
dump_all "$@"
for f in $Z/b*/view_000.png $Z/b*/contact.png; do
    name=$(echo "${f#$Z/}" | tr /. __)
    s=${f%.png}_stored.png
    if [ -s "$(theirs "$f")" ] && cmp -s "$(theirs "$f")" "$(theirs "$s")"; then ok "deflate_oiiotool_same_pixels_$name"
    else bad "deflate_oiiotool_same_pixels_$name"; fi
    if out=$(python3 - "$f" "$s" <<'PY'
import sys, struct, zlib
def rows(path):
    b = open(path, 'rb').read()
    p, z, ihdr = 8, b'', None
    while p < len(b):
        n = struct.unpack('>I', b[p:p + 4])[0]
        t, d = b[p + 4:p + 8], b[p + 8:p + 8 + n]
        assert zlib.crc32(t + d) & 0xffffffff == struct.unpack('>I', b[p + 8 + n:p + 12 + n])[0], 'CRC'
        if t == b'IHDR': ihdr = d
        if t == b'IDAT': z += d
        p += 12 + n
    w, h, bits, ct = struct.unpack('>IIBB', ihdr[:10])
    bpp = {0: 1, 2: 3, 4: 2, 6: 4}[ct] * bits // 8
    r, out, prev = zlib.decompress(z), [], bytearray(w * bpp)
    for y in range(h):
        f = r[y * (w * bpp + 1)]
        cur = bytearray(r[y * (w * bpp + 1) + 1:(y + 1) * (w * bpp + 1)])
        for i in range(len(cur)):
            a = cur[i - bpp] if i >= bpp else 0
            c = prev[i - bpp] if i >= bpp else 0
            u = prev[i]
            if f == 1: cur[i] = (cur[i] + a) & 255
            elif f == 2: cur[i] = (cur[i] + u) & 255
            elif f == 3: cur[i] = (cur[i] + ((a + u) >> 1)) & 255
            elif f == 4:
                q = a + u - c
                pa, pb, pc = abs(q - a), abs(q - u), abs(q - c)
                cur[i] = (cur[i] + (a if pa <= pb and pa <= pc else u if pb <= pc else c)) & 255
            else: assert f == 0, 'filter %d' % f
        out.append(bytes(cur))
        prev = cur
    return len(b), out
n, ours = rows(sys.argv[1])
ns, stored = rows(sys.argv[2])
assert ours == stored, 'pixels differ'
z6 = len(zlib.compress(b''.join(b'\0' + r for r in stored), 6))
print('%d bytes, stored %d, zlib -6 %d, ratio %.3f' % (n, ns, z6, n / (z6 + 57.0)))
assert n <= 1.3 * z6 + 57, 'above 1.3 x zlib -6'
PY
    ); then ok "deflate_python_zlib_same_pixels_and_size_$name ($out)"
    else bad "deflate_python_zlib_same_pixels_and_size_$name" "$out"; fi
    if $T dump "$f" > $Z/ours.txt 2>$Z/err.txt && $T dump "$s" > $Z/stored.txt && cmp -s $Z/ours.txt $Z/stored.txt; then
        ok "deflate_own_inflate_round_trip_$name"
    else bad "deflate_own_inflate_round_trip_$name" "$(cat $Z/err.txt)"; fi
done
finish
