/* tests/fuzz/fuzz_png.c - libFuzzer target: PNG decoding and inflate.
 *
 * Input: the selector byte (fuzz_common.h), a mode byte, then the payload.
 * Modes (the mode byte modulo 4):
 *   0  the payload is a PNG file, decoded as it is (fuzz_image.h);
 *   1  the same after the harness rewrote the CRC of every complete chunk,
 *      so that mutations of chunk data reach the decoder instead of failing
 *      the CRC check;
 *   2  the payload after two more bytes (the output buffer size / 4, big-
 *      endian) is a zlib stream for ls_zlib_decompress;
 *   3  likewise a raw deflate stream for ls_inflate.
 * Modes 2 and 3 are checked against zlib: when ours succeeds, zlib's inflate
 * must decode the same input to the same bytes, consuming all of it; the
 * arena is as before the call whatever the outcome, and an arena smaller
 * than ls_inflate_bytes gives LS_ERR_NOMEM.
 */
#include <zlib.h>
#include "fuzz_image.h"

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static void fix_crcs(unsigned char *d, size_t n)
{
    size_t pos = 8;
    while (pos + 12u <= n) {
        uint32_t len = ((uint32_t)d[pos] << 24) | ((uint32_t)d[pos + 1] << 16) | ((uint32_t)d[pos + 2] << 8) | d[pos + 3];
        if (len > n - pos - 12u) break;
        put_be32(d + pos + 8u + len, ls_crc32(0, d + pos + 4u, (size_t)len + 4u));
        pos += 12u + (size_t)len;
    }
}

/* zlib's verdict on the same stream; 1 when it decodes all of src[0..n) to
 * exactly out[0..out_n). */
static int zlib_agrees(const uint8_t *src, size_t n, int raw, const unsigned char *out, size_t out_n)
{
    z_stream z;
    unsigned char *buf = (unsigned char *)malloc(out_n + 1u);
    int rc, ok;
    FUZZ_ASSERT(buf != NULL);
    memset(&z, 0, sizeof z);
    FUZZ_ASSERT(inflateInit2(&z, raw ? -15 : 15) == Z_OK);
    z.next_in = (Bytef *)(uintptr_t)src;
    z.avail_in = (uInt)n;
    z.next_out = buf;
    z.avail_out = (uInt)(out_n + 1u);
    rc = inflate(&z, Z_FINISH);
    ok = rc == Z_STREAM_END && z.avail_in == 0 && z.total_out == out_n && memcmp(buf, out, out_n) == 0;
    inflateEnd(&z);
    free(buf);
    return ok;
}

static void fuzz_inflate(uint8_t selector, const uint8_t *data, size_t size, int raw)
{
    size_t need = 0, dst_bytes, out_bytes = 0;
    unsigned char *dst;
    fuzz_arena fa;
    ls_diag diag;
    ls_status st;
    if (size < 2) return;
    dst_bytes = (((size_t)data[0] << 8) | data[1]) * 4u;
    data += 2;
    size -= 2;
    FUZZ_ASSERT(ls_inflate_bytes(&need) == LS_OK && need > 0);
    fuzz_arena_open(&fa, selector, need);
    dst = (unsigned char *)malloc(dst_bytes > 0 ? dst_bytes : 1u);
    FUZZ_ASSERT(dst != NULL);
    ls_diag_clear(&diag);
    if (raw)
        st = ls_inflate(data, size, dst, dst_bytes, &out_bytes, &fa.arena, &diag);
    else
        st = ls_zlib_decompress(data, size, dst, dst_bytes, &out_bytes, &fa.arena, &diag);
    FUZZ_ASSERT(st >= LS_OK && st < LS_STATUS_COUNT);
    FUZZ_ASSERT(fa.arena.bottom == fa.mark.bottom && fa.arena.top == fa.mark.top);
    if (!fa.enough) FUZZ_ASSERT(st != LS_OK);
    if (fa.enough) FUZZ_ASSERT(st != LS_ERR_NOMEM);
    if (st == LS_OK) {
        FUZZ_ASSERT(out_bytes <= dst_bytes);
        FUZZ_ASSERT(fuzz_arena_peak(&fa) == need);
        FUZZ_ASSERT(zlib_agrees(data, size, raw, dst, out_bytes));
    } else if (st != LS_ERR_NOMEM) {
        FUZZ_ASSERT(diag.what != NULL && diag.what[0] != '\0' && diag.status == st);
    }
    free(dst);
    fuzz_arena_close(&fa);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t selector, mode;
    unsigned char *copy;
    if (size < 2) return 0;
    selector = data[0];
    mode = (uint8_t)(data[1] & 3u);
    data += 2;
    size -= 2;
    switch (mode) {
    case 0:
        fuzz_image_decode(selector, data, size);
        break;
    case 1:
        copy = (unsigned char *)malloc(size > 0 ? size : 1u);
        FUZZ_ASSERT(copy != NULL);
        if (size > 0) memcpy(copy, data, size);
        fix_crcs(copy, size);
        fuzz_image_decode(selector, copy, size);
        free(copy);
        break;
    default:
        fuzz_inflate(selector, data, size, mode == 3);
        break;
    }
    return 0;
}
