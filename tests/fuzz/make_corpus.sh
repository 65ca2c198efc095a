#!/bin/sh
# make_corpus.sh - (re)writes the seed corpora tests/fuzz/corpus/NAME/ from
# fixtures/, Debian's assimp-testmodels (/usr/share/assimp/models: small OBJ,
# PLY and OFF files) and hand-made inputs. Each seed starts with the
# harness's selector byte (fuzz_common.h: 0x00 = an arena of the sizing
# answer, 0xC0 = three quarters of it); fuzz_png seeds also have the mode
# byte (fuzz_png.c). Regression inputs (crashes found) live in
# corpus/NAME/regress-*, and inputs kept from the long offline runs
# (`fuzz_NAME -merge=1` of their corpora: each adds coverage) in
# corpus/NAME/found-*; both are kept. Needs python3 (zlib, struct).
set -e
cd "$(dirname "$0")/../.."
C=tests/fuzz/corpus
A=/usr/share/assimp/models
for t in obj ply off png ppm pfm scene mitsuba; do
    mkdir -p $C/$t
    find $C/$t -type f ! -name 'regress-*' ! -name 'found-*' -delete
done
python3 - "$C" "$A" <<'PY'
import os, sys, struct, zlib, glob
C, A = sys.argv[1], sys.argv[2]
def put(t, name, data, sel=(0,)):
    for s in sel:
        with open(os.path.join(C, t, '%s-%02x' % (name, s)), 'wb') as f:
            f.write(bytes([s]) + data)
def small(paths, limit=16384):
    for p in sorted(set(paths)):
        if os.path.isfile(p) and os.path.getsize(p) <= limit:
            yield p, open(p, 'rb').read()
# --- meshes ---
for ext, t in (('obj', 'obj'), ('ply', 'ply'), ('off', 'off')):
    paths = glob.glob('fixtures/meshes/assimp/*/*.' + ext) + glob.glob(A + '/*/*.' + ext) + \
            glob.glob(A + '/*/*.' + ext.upper())
    for p, d in small(paths):
        put(t, os.path.basename(os.path.dirname(p)) + '_' + os.path.basename(p).replace('.', '_'), d, (0, 0xc0))
put('obj', 'hand_negative_polygon', b'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4/1/1 -3//2 -2 -1\n'
    b'vt 0 0\nvn 0 0 1\ng x\nf 1 2 3\r\nv 1e-300 -2.5E+3 .5\n# end')
put('obj', 'hand_bom_cr', b'\xef\xbb\xbfv 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r')
tri = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
faces = [(0, 1, 2), (0, 1, 3), (1, 2, 3)]
for fmt, e in (('binary_little_endian', '<'), ('binary_big_endian', '>')):
    h = ('ply\nformat %s 1.0\ncomment hand-made\nelement vertex 4\nproperty float x\nproperty double y\n'
         'property int16 z\nproperty uchar red\nelement face 3\nproperty list uchar int vertex_indices\n'
         'element edge 1\nproperty int a\nend_header\n' % fmt).encode()
    body = b''.join(struct.pack(e + 'fdhB', x, y, z, 7) for x, y, z in tri)
    body += b''.join(struct.pack(e + 'B3i', 3, *f) for f in faces) + struct.pack(e + 'i', 5)
    put('ply', 'hand_' + fmt, h + body)
put('ply', 'hand_ascii_quad', b'ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty float32 x\r\nproperty float32 y\r\n'
    b'property float32 z\r\nelement face 1\r\nproperty list uint8 uint32 vertex_index\r\nend_header\r\n'
    b'0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n')
put('off', 'hand_coff_counts_next_line', b'COFF\n# comment\n4 2 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n'
    b'0 0 1 1 0 0 1\n3 0 1 2 255 0 0\n4 0 1 2 3\n')
put('off', 'hand_off_one_line', b'OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n')
# --- images ---
def chunk(ty, data):
    return struct.pack('>I', len(data)) + ty + data + struct.pack('>I', zlib.crc32(ty + data) & 0xffffffff)
def png(w, h, ctype, depth, rows, extra=b''):
    ihdr = struct.pack('>IIBBBBB', w, h, depth, ctype, 0, 0, 0)
    return b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', ihdr) + extra + chunk(b'IDAT', zlib.compress(rows, 9)) + chunk(b'IEND', b'')
for p, d in small(glob.glob('fixtures/images/*.png'), 4096):
    put('png', os.path.basename(p).replace('.', '_'), b'\x00' + d, (0,))
    put('png', os.path.basename(p).replace('.', '_') + '_fixcrc', b'\x01' + d, (0xc0,))
put('png', 'hand_palette_trns', b'\x01' + png(3, 2, 3, 8, bytes([0, 0, 1, 2, 1, 2, 1, 0]),
    chunk(b'PLTE', bytes(range(9))) + chunk(b'tRNS', b'\x00\x80')))
put('png', 'hand_filters', b'\x01' + png(4, 5, 2, 8, b''.join(bytes([f]) + bytes((f * 37 + i) & 255 for i in range(12)) for f in range(5))))
data = bytes((i * i) & 255 for i in range(3000)) + b'abcabcabc' * 50
for lvl in (0, 1, 9):
    z = zlib.compress(data, lvl)
    put('png', 'zlib_level%d' % lvl, b'\x02' + struct.pack('>H', (len(data) + 3) // 4) + z)
    co = zlib.compressobj(lvl, zlib.DEFLATED, -15)
    r = co.compress(data) + co.flush()
    put('png', 'raw_level%d' % lvl, b'\x03' + struct.pack('>H', (len(data) + 3) // 4) + r)
co = zlib.compressobj(9, zlib.DEFLATED, -15, 9, zlib.Z_FIXED)
put('png', 'raw_fixed', b'\x03' + struct.pack('>H', 1000) + co.compress(data) + co.flush())
put('ppm', 'p6_8bit', b'P6\n# c\n3 2\n255\n' + bytes(range(18)))
put('ppm', 'p5_16bit', b'P5 2 2 65535 ' + struct.pack('>4H', 0, 1, 65535, 30000), (0, 0xc0))
put('ppm', 'p5_maxval7', b'P5\n4\n1\n7\n' + bytes([0, 3, 7, 5]))
put('ppm', 'p6_16bit_maxval1000', b'P6\n1 2\n1000\n' + struct.pack('>6H', 0, 1, 999, 1000, 5, 6))
put('pfm', 'pf_le', b'PF\n2 1\n-1.0\n' + struct.pack('<6f', 0, 1, 0.5, -2, 1e30, 3.5), (0, 0xc0))
put('pfm', 'pf_be', b'PF\n1 2\n1.0\n' + struct.pack('>6f', 0, 1, 0.5, 2, 4, 8))
put('pfm', 'pfgrey_le_scale', b'Pf 3 1 -0.5\n' + struct.pack('<3f', 1, 2, 3))
# --- scenes ---
scene = (b'# a test scene\nlargesteps-scene 1\nresolution 320 240\nfov 60 y\nclip 0.5 50\ncamera 0 0 5  0 0 0\n'
         b'image "views/front view.png"\nfov 30\nviews fibonacci 4 2.5 1 2 3   # around (1, 2, 3)\nviews rings 2 3 4\n'
         b'lighting sh 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27\n'
         b'background 0.25 0.5 1\r\ntarget mesh "meshes/the bunny.obj"\ninitial icosphere 2\n')
put('scene', 'full', scene, (0, 0xc0))
put('scene', 'envmap_images', b'largesteps-scene 1\nresolution 16 8\ncamera 1 2 3 0 0 0 0 0 1\nimage a.png\n'
    b'camera -1 2 3 0 0 0\nimage b.pfm\nlighting envmap sky.pfm 2\ntarget images\ninitial mesh "m.ply"\n')
put('scene', 'mask_rings', b'largesteps-scene 1\nresolution 64 64\nviews rings 3 5 2.5 0 0 1\nlighting mask\ntarget mesh t.obj\n')
mitsuba = (b'<?xml version="1.0"?>\n<!-- the reference\'s layout -->\n<scene version="2.0.0">\n'
    b'  <default name="resx" value="200"/>\n  <default name="resy" value="100"/>\n  <sensor type="perspective">\n'
    b'    <float name="fov" value="45"/>\n    <float name="near_clip" value="0.1"/>\n    <float name="far_clip" value="100"/>\n'
    b'    <transform name="to_world">\n      <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/>\n    </transform>\n'
    b'    <film type="hdrfilm"><integer name="width" value="$resx"/><integer name="height" value="$resy"/></film>\n'
    b'  </sensor>\n  <sensor type="perspective">\n    <float name="fov" value="30"/>\n    <string name="fov_axis" value="y"/>\n'
    b'    <transform name="to_world">\n      <rotate y="1" angle="90"/>\n      <translate value="0 0 5"/>\n'
    b'      <scale value="2"/>\n      <rotate value="1, 1, 0" angle="10"/>\n'
    b'      <matrix value="1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1"/>\n    </transform>\n'
    b'    <film type="hdrfilm"><integer name="width" value="$resx"/><integer name="height" value="$resy"/></film>\n'
    b'  </sensor>\n  <emitter type="envmap"><string name="filename" value="sky.pfm"/><float name="scale" value="2.5"/></emitter>\n'
    b'  <shape type="ply" id="mesh-source"><string name="filename" value="source.ply"/></shape>\n'
    b'  <shape type="ply" id="mesh-target"><string name="filename" value="target.ply"/><bsdf type="diffuse"/></shape>\n'
    b'</scene>\n')
put('mitsuba', 'reference_layout', mitsuba, (0, 0xc0))
put('mitsuba', 'minimal', b'<scene><sensor type="perspective"><float name="fov" value="40"/></sensor></scene>')
PY
du -sh "$C"; for t in "$C"/*; do echo "$(basename "$t"): $(find "$t" -type f | wc -l) files"; done
