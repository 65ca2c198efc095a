#!/usr/bin/env python3
"""gen_image_fixtures.py - writes the PNG decoder fixtures in fixtures/images/.

Independent of the library: Python's own zlib compresses (dynamic Huffman by
default, fixed Huffman with Z_FIXED), and the filters, Adam7 and chunk layout
are written here from the PNG specification. Pixel values follow a formula
that tests/test_image.c recomputes:
    P(x, y, c) = (2473 x + 4027 y + 8191 c + 97 x y + 5) mod 2^bits
palette entry i = (37 i, 91 i, 151 i) mod 256, tRNS alpha of entry i = 53 i mod 256
(first n/2 + 1 entries), colour-key tRNS = the colour of pixel (1, 0).
Names: c<colour>_b<bits>_i<interlace>_t<trns>_<z>.png (61 x 43), z = dyn | fix |
split (split: dynamic, with the zlib stream cut into 7-byte IDAT chunks), and
tiny_<w>x<h>_c<colour>_b<bits>_i<interlace>.png (Adam7 passes left empty).
usage: gen_image_fixtures.py OUTDIR
"""
import struct
import sys
import zlib

W, H = 61, 43
CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def P(x, y, c, bits):
    return (2473 * x + 4027 * y + 8191 * c + 97 * x * y + 5) % (1 << bits)


def palette_size(bits):
    return min(1 << bits, 200) if bits == 8 else (1 << bits)


def sample(x, y, c, color, bits):
    if color == 3:
        return P(x, y, 0, bits) % palette_size(bits)
    return P(x, y, c, bits)


def pack_row(xs, y, color, bits):
    global W, H
    ch = CHANNELS[color]
    vals = [sample(x, y, c, color, bits) for x in xs for c in range(ch)]
    if bits == 16:
        return b''.join(struct.pack('>H', v) for v in vals)
    if bits == 8:
        return bytes(vals)
    out = bytearray()
    acc, n = 0, 0
    for v in vals:
        acc = (acc << bits) | v
        n += bits
        if n == 8:
            out.append(acc)
            acc, n = 0, 0
    if n:
        out.append(acc << (8 - n))
    return bytes(out)


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def filter_row(ftype, row, prev, bpp):
    out = bytearray()
    for i, v in enumerate(row):
        a = row[i - bpp] if i >= bpp else 0
        b = prev[i] if prev is not None else 0
        c = prev[i - bpp] if (prev is not None and i >= bpp) else 0
        pred = [0, a, b, (a + b) >> 1, paeth(a, b, c)][ftype]
        out.append((v - pred) & 255)
    return bytes([ftype]) + bytes(out)


def raw_data(color, bits, interlace):
    bpp = max(1, CHANNELS[color] * bits // 8)
    passes = [(0, 0, 1, 1)] if not interlace else [
        (0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]
    out = bytearray()
    for pi, (x0, y0, dx, dy) in enumerate(passes):
        xs = list(range(x0, W, dx))
        ys = list(range(y0, H, dy))
        if not xs or not ys:
            continue
        prev = None
        for r, y in enumerate(ys):
            row = pack_row(xs, y, color, bits)
            out += filter_row((pi + r) % 5, row, prev, bpp)
            prev = row
    return bytes(out)


def chunk(t, body):
    return struct.pack('>I', len(body)) + t + body + struct.pack('>I', zlib.crc32(t + body) & 0xffffffff)


def png(color, bits, interlace, trns, z):
    raw = raw_data(color, bits, interlace)
    if z == 'fix':
        co = zlib.compressobj(9, zlib.DEFLATED, 15, 9, zlib.Z_FIXED)
    else:
        co = zlib.compressobj(9, zlib.DEFLATED, 15, 9, zlib.Z_DEFAULT_STRATEGY)
    comp = co.compress(raw) + co.flush()
    btype = (comp[2] >> 1) & 3
    out = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', W, H, bits, color, 0, 0, interlace))
    if color == 3:
        n = palette_size(bits)
        out += chunk(b'PLTE', b''.join(bytes([(37 * i) % 256, (91 * i) % 256, (151 * i) % 256]) for i in range(n)))
        if trns:
            out += chunk(b'tRNS', bytes((53 * i) % 256 for i in range(n // 2 + 1)))
    elif trns:
        key = [P(1, 0, c, bits) for c in range(CHANNELS[color])]
        out += chunk(b'tRNS', b''.join(struct.pack('>H', k) for k in key))
    out += chunk(b'tEXt', b'Comment\x00fixture for tests/test_image.c')
    if z == 'split':
        for i in range(0, len(comp), 7):
            out += chunk(b'IDAT', comp[i:i + 7])
    else:
        out += chunk(b'IDAT', comp)
    out += chunk(b'IEND', b'')
    return out, btype


def main():
    outdir = sys.argv[1]
    cases = []
    for color, depths in ((0, (1, 2, 4, 8, 16)), (2, (8, 16)), (3, (1, 2, 4, 8)), (4, (8, 16)), (6, (8, 16))):
        for bits in depths:
            for interlace in (0, 1):
                cases.append((color, bits, interlace, 0, 'dyn'))
    cases += [(0, 8, 0, 1, 'fix'), (0, 16, 1, 1, 'dyn'), (2, 16, 0, 1, 'split'), (2, 8, 1, 1, 'fix'),
              (3, 8, 0, 1, 'dyn'), (3, 4, 1, 1, 'split'), (6, 16, 0, 0, 'fix'), (3, 2, 0, 0, 'fix')]
    for color, bits, interlace, trns, z in cases:
        data, btype = png(color, bits, interlace, trns, z)
        name = 'c%d_b%d_i%d_t%d_%s.png' % (color, bits, interlace, trns, z)
        with open('%s/%s' % (outdir, name), 'wb') as f:
            f.write(data)
        print(name, len(data), 'first block type', btype)
    global W, H
    for (w, h, color, bits) in ((1, 1, 3, 1), (1, 1, 6, 16), (2, 3, 0, 2), (3, 2, 2, 8), (5, 1, 4, 8), (1, 9, 0, 16)):
        W, H = w, h
        data, btype = png(color, bits, 1, 0, 'dyn')
        name = 'tiny_%dx%d_c%d_b%d_i1.png' % (w, h, color, bits)
        with open('%s/%s' % (outdir, name), 'wb') as f:
            f.write(data)
        print(name, len(data), 'first block type', btype)


main()
