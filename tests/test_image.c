/* test_image.c - images: checksums, integer conversion, PNG/PNM/PFM round
 * trips, Python-zlib fixtures (every colour type, bit depth, filter, Adam7,
 * fixed and dynamic Huffman), a hand-built dynamic-Huffman stream, malformed
 * inputs, and arena sweeps of decoding, encoding and inflate. */
#include <stdlib.h>
#include "test.h"
#include "sweep.h"

static LS_ARENA_BUFFER(work, 4u << 20);
static unsigned char outbuf[1u << 20];

/* --- helpers -------------------------------------------------------------- */

/* Reads a whole file into a malloc'd buffer (tests run from the repository root). */
static ls_status read_file(const char *path, unsigned char **data, size_t *bytes)
{
    FILE *f = fopen(path, "rb");
    long len;
    *data = NULL;
    *bytes = 0;
    if (f == NULL) return LS_ERR_IO;
    if (fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return LS_ERR_IO;
    }
    *data = (unsigned char *)malloc((size_t)len + 1);
    if (*data == NULL || fread(*data, 1, (size_t)len, f) != (size_t)len) {
        free(*data);
        *data = NULL;
        fclose(f);
        return LS_ERR_IO;
    }
    fclose(f);
    *bytes = (size_t)len;
    return LS_OK;
}

static uint64_t rng_state = 12345u;
static uint32_t rng(void) /* 24 random bits */
{
    return (uint32_t)(test_rng_bits(&rng_state) >> 29);
}

static void be32w(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static uint32_t be32r(const unsigned char *p)
{
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
}

/* Bitwise CRC-32: the definition, independent of the library's table. */
static uint32_t crc_slow(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        c ^= p[i];
        for (k = 0; k < 8; k++) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
    }
    return c ^ 0xffffffffu;
}

/* Recomputes the CRC of the chunk starting at `at`. */
static void fix_crc(unsigned char *png, size_t at)
{
    uint32_t len = be32r(png + at);
    be32w(png + at + 8 + len, crc_slow(png + at + 4, len + 4));
}

/* Offset of the first chunk of a type, or 0. */
static size_t find_chunk(const unsigned char *png, size_t n, const char *type)
{
    size_t pos = 8;
    while (pos + 12 <= n) {
        uint32_t len = be32r(png + pos);
        if (memcmp(png + pos + 4, type, 4) == 0) return pos;
        pos += 12 + len;
    }
    return 0;
}

static ls_arena fresh_arena(void)
{
    ls_arena a;
    ls_arena_init(&a, work.bytes, sizeof work.bytes);
    return a;
}

static ls_status decode(const unsigned char *data, size_t n, ls_image *img, ls_diag *d)
{
    static ls_arena a;
    a = fresh_arena();
    return ls_image_decode(data, n, img, &a, d);
}

/* Encodes into outbuf; returns the length (0 on failure). */
static size_t encode(const ls_image *img, uint32_t type, uint32_t ch, uint32_t bits, uint32_t be)
{
    ls_image_format f;
    ls_membuf m;
    ls_arena a = fresh_arena();
    f.type = type;
    f.channels = ch;
    f.bits = bits;
    f.big_endian = be;
    m.data = outbuf;
    m.capacity = sizeof outbuf;
    m.size = 0;
    m.overflow = 0;
    if (ls_image_encode(img, &f, ls_membuf_write, &m, &a) != LS_OK) return 0;
    return m.size;
}

/* --- checksums ------------------------------------------------------------ */

static void checksum_known_values(void)
{
    static unsigned char big[100000];
    size_t i;
    uint32_t a = 1, b = 0;
    CHECK_EQ(ls_crc32(0, "123456789", 9), 0xCBF43926u);
    CHECK_EQ(ls_crc32(0, "", 0), 0);
    CHECK_EQ(ls_crc32(0, NULL, 0), 0);
    CHECK_EQ(ls_crc32(0, "The quick brown fox jumps over the lazy dog", 43), 0x414FA339u);
    CHECK_EQ(ls_crc32(0, "IEND", 4), 0xAE426082u);
    CHECK_EQ(ls_adler32(1, "Wikipedia", 9), 0x11E60398u);
    CHECK_EQ(ls_adler32(1, NULL, 0), 1);
    for (i = 0; i < sizeof big; i++) big[i] = (unsigned char)(i % 7u == 0 ? 255u : rng());
    CHECK_EQ(ls_crc32(0, big, sizeof big), crc_slow(big, sizeof big));
    CHECK_EQ(ls_crc32(ls_crc32(0, big, 333), big + 333, sizeof big - 333), ls_crc32(0, big, sizeof big));
    for (i = 0; i < sizeof big; i++) {
        a = (a + big[i]) % 65521u;
        b = (b + a) % 65521u;
    }
    CHECK_EQ(ls_adler32(1, big, sizeof big), (b << 16) | a);
    CHECK_EQ(ls_adler32(ls_adler32(1, big, 7777), big + 7777, sizeof big - 7777), (b << 16) | a);
    memset(big, 255, sizeof big); /* the worst case for the deferred modulo */
    a = 1;
    b = 0;
    for (i = 0; i < sizeof big; i++) {
        a = (a + 255u) % 65521u;
        b = (b + a) % 65521u;
    }
    CHECK_EQ(ls_adler32(1, big, sizeof big), (b << 16) | a);
}

/* --- conversion ----------------------------------------------------------- */

/* Reference: rint() rounds half to even in the default rounding mode. */
static uint32_t ref_unorm(float v, float m)
{
    float t;
    if (!(v > 0.0f)) return 0;
    if (v > 1.0f) v = 1.0f;
    t = v * m;
    return (uint32_t)rint((double)t);
}

static void unorm_rounding_rule(void)
{
    uint32_t bits, k, bad8 = 0, bad16 = 0;
    float nan_v = (float)NAN;
    CHECK_EQ(ls_unorm8(0.0f), 0);
    CHECK_EQ(ls_unorm8(1.0f), 255);
    CHECK_EQ(ls_unorm8(-3.0f), 0);
    CHECK_EQ(ls_unorm8(7.0f), 255);
    CHECK_EQ(ls_unorm8(nan_v), 0);
    CHECK_EQ(ls_unorm8((float)INFINITY), 255);
    CHECK_EQ(ls_unorm8(-(float)INFINITY), 0);
    CHECK_EQ(ls_unorm8(0.5f), 128);        /* 127.5 -> even */
    CHECK_EQ(ls_unorm16(0.5f), 32768);     /* 32767.5 -> even */
    CHECK_EQ(ls_unorm8(2.5f / 255.0f) == 2 || ls_unorm8(2.5f / 255.0f) == 3, 1);
    CHECK_EQ(ls_unorm16(nan_v), 0);
    CHECK_EQ(ls_unorm16(1.0f), 65535);
    /* every value k / M maps back to k */
    for (k = 0; k < 65536u; k++) {
        if (k < 256u && ls_unorm8((float)k / 255.0f) != k) bad8++;
        if (ls_unorm16((float)k / 65535.0f) != k) bad16++;
    }
    CHECK_EQ(bad8, 0);
    CHECK_EQ(bad16, 0);
    /* a sample of every float in [0, 1] against the rint() reference */
    bad8 = bad16 = 0;
    for (bits = 0; bits <= 0x3f800000u; bits += 997u) {
        float v;
        memcpy(&v, &bits, 4);
        if (ls_unorm8(v) != ref_unorm(v, 255.0f)) bad8++;
        if (ls_unorm16(v) != ref_unorm(v, 65535.0f)) bad16++;
    }
    /* and the floats right around every half-way point of the 8-bit scale */
    for (k = 0; k < 255u; k++) {
        float v = (float)(((double)k + 0.5) / 255.0);
        int j;
        for (j = 0; j < 40; j++) v = nextafterf(v, 0.0f);
        for (j = 0; j < 80; j++, v = nextafterf(v, 2.0f))
            if (ls_unorm8(v) != ref_unorm(v, 255.0f)) bad8++;
    }
    CHECK_EQ(bad8, 0);
    CHECK_EQ(bad16, 0);
}

static void image_create_and_limits(void)
{
    ls_arena a = fresh_arena();
    ls_image img;
    size_t bytes;
    CHECK_STATUS(ls_image_bytes(0, 5, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_image_bytes(5, 0, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_image_bytes(LS_IMAGE_MAX_SIDE + 1u, 1, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_image_bytes(1u << 15, 1u << 15, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_image_bytes(3, 5, &bytes), LS_OK);
    CHECK_EQ(bytes, 240);
    CHECK_STATUS(ls_image_create(&img, 3, 5, &a), LS_OK);
    CHECK_EQ(ls_arena_used(&a), 240);
    CHECK(img.pixels[0] == 0.0f && img.pixels[59] == 0.0f);
}

static void unorm_pack_and_unpack(void)
{
    ls_arena a = fresh_arena();
    ls_image img;
    uint8_t in8[4 * 6], out8[4 * 6];
    uint16_t in16[4 * 6], out16[4 * 6];
    uint32_t ch, i;
    REQUIRE(ls_image_create(&img, 3, 2, &a) == LS_OK);
    for (ch = 1; ch <= 4; ch++) {
        for (i = 0; i < 6 * ch; i++) {
            in8[i] = (uint8_t)rng();
            in16[i] = (uint16_t)rng();
        }
        CHECK_STATUS(ls_image_from_unorm(&img, ch, 8, in8, 6 * ch), LS_OK);
        if (ch == 1) CHECK(img.pixels[1] == img.pixels[0] && img.pixels[2] == img.pixels[0] && img.pixels[3] == 1.0f);
        CHECK_STATUS(ls_image_to_unorm(&img, ch, 8, out8, 6 * ch), LS_OK);
        CHECK(memcmp(in8, out8, 6 * ch) == 0);
        CHECK_STATUS(ls_image_from_unorm(&img, ch, 16, in16, 12 * ch), LS_OK);
        CHECK_STATUS(ls_image_to_unorm(&img, ch, 16, out16, 12 * ch), LS_OK);
        CHECK(memcmp(in16, out16, 12 * ch) == 0);
        CHECK_STATUS(ls_image_to_unorm(&img, ch, 16, out16, 12 * ch - 1), LS_ERR_INVALID);
    }
    CHECK(img.pixels[4] == (float)in16[4] / 65535.0f);
    CHECK_STATUS(ls_image_to_unorm(&img, 5, 8, out8, sizeof out8), LS_ERR_INVALID);
    CHECK_STATUS(ls_image_to_unorm(&img, 3, 12, out8, sizeof out8), LS_ERR_INVALID);
}

/* --- round trips ---------------------------------------------------------- */

/* A w x h image of integer-valued samples q / M (alpha varies too). */
static void fill_pattern(ls_image *img, float m)
{
    size_t i, n = (size_t)img->width * img->height * 4;
    for (i = 0; i < n; i++) {
        uint32_t q = (uint32_t)((i * 2654435761u + (i >> 3) * 40503u) % ((uint32_t)m + 1u));
        if (i % 97u == 0) q = 0;
        if (i % 89u == 0) q = (uint32_t)m;
        img->pixels[i] = (float)q / m;
    }
}

static void check_decoded(const ls_image *src, const ls_image *dec, uint32_t ch, const char *what)
{
    size_t i, n = (size_t)src->width * src->height, bad = 0;
    if (dec->width != src->width || dec->height != src->height) {
        CHECK_MSG(0, "%s: size %ux%u vs %ux%u", what, dec->width, dec->height, src->width, src->height);
        return;
    }
    for (i = 0; i < n; i++) {
        const float *s = src->pixels + 4 * i, *d = dec->pixels + 4 * i;
        float want[4];
        if (ch <= 2) {
            want[0] = want[1] = want[2] = s[0];
        } else {
            want[0] = s[0];
            want[1] = s[1];
            want[2] = s[2];
        }
        want[3] = (ch == 2 || ch == 4) ? s[3] : 1.0f;
        if (memcmp(want, d, sizeof want) != 0) bad++;
    }
    CHECK_MSG(bad == 0, "%s: %lu pixels differ", what, (unsigned long)bad);
}

static void round_trip_every_format(void)
{
    static const uint32_t sizes[][2] = {{1, 1}, {7, 5}, {300, 120}};
    ls_arena a0 = fresh_arena();
    uint32_t s, ch, bits, be;
    char what[96];
    (void)a0;
    for (s = 0; s < 3; s++) {
        static LS_ARENA_BUFFER(src_mem, 600000);
        ls_arena sa;
        ls_image src, dec;
        ls_diag d;
        size_t n, want;
        ls_image_format f;
        ls_arena_init(&sa, src_mem.bytes, sizeof src_mem.bytes);
        REQUIRE(ls_image_create(&src, sizes[s][0], sizes[s][1], &sa) == LS_OK);
        for (bits = 8; bits <= 16; bits += 8) {
            fill_pattern(&src, bits == 8 ? 255.0f : 65535.0f);
            for (ch = 1; ch <= 4; ch++) {
                f.type = LS_IMAGE_PNG;
                f.channels = ch;
                f.bits = bits;
                f.big_endian = 0;
                n = encode(&src, LS_IMAGE_PNG, ch, bits, 0);
                /* compressed: the size query is a bound */
                CHECK(ls_image_encoded_size(src.width, src.height, &f, &want) == LS_OK && n > 0 && n <= want);
                sprintf(what, "png %ux%u ch%u %u-bit", src.width, src.height, ch, bits);
                CHECK_MSG(decode(outbuf, n, &dec, &d) == LS_OK, "%s: %s", what, d.what);
                check_decoded(&src, &dec, ch, what);
                f.type = LS_IMAGE_PNG_STORED;
                n = encode(&src, LS_IMAGE_PNG_STORED, ch, bits, 0);
                CHECK(ls_image_encoded_size(src.width, src.height, &f, &want) == LS_OK && want == n);
                sprintf(what, "stored png %ux%u ch%u %u-bit", src.width, src.height, ch, bits);
                CHECK_MSG(decode(outbuf, n, &dec, &d) == LS_OK, "%s: %s", what, d.what);
                check_decoded(&src, &dec, ch, what);
                if (ch == 1 || ch == 3) {
                    f.type = LS_IMAGE_PNM;
                    n = encode(&src, LS_IMAGE_PNM, ch, bits, 0);
                    CHECK(ls_image_encoded_size(src.width, src.height, &f, &want) == LS_OK && want == n);
                    sprintf(what, "pnm %ux%u ch%u %u-bit", src.width, src.height, ch, bits);
                    CHECK_MSG(decode(outbuf, n, &dec, &d) == LS_OK, "%s: %s", what, d.what);
                    check_decoded(&src, &dec, ch, what);
                }
            }
        }
        /* PFM keeps every float bit pattern, including NaN payloads and -0 */
        {
            size_t i, np = (size_t)src.width * src.height * 4;
            for (i = 0; i < np; i++) {
                uint32_t u = rng() * 2654435761u ^ rng();
                memcpy(&src.pixels[i], &u, 4);
            }
        }
        for (ch = 1; ch <= 3; ch += 2) {
            for (be = 0; be <= 1; be++) {
                size_t i, bad = 0;
                f.type = LS_IMAGE_PFM;
                f.channels = ch;
                f.bits = 32;
                f.big_endian = be;
                n = encode(&src, LS_IMAGE_PFM, ch, 32, be);
                CHECK(ls_image_encoded_size(src.width, src.height, &f, &want) == LS_OK && want == n);
                CHECK(memcmp(outbuf, ch == 1 ? "Pf\n" : "PF\n", 3) == 0);
                REQUIRE(decode(outbuf, n, &dec, &d) == LS_OK);
                for (i = 0; i < (size_t)src.width * src.height; i++) {
                    uint32_t k;
                    for (k = 0; k < 3; k++)
                        if (memcmp(&dec.pixels[4 * i + k], &src.pixels[4 * i + (ch == 1 ? 0 : k)], 4) != 0) bad++;
                    if (dec.pixels[4 * i + 3] != 1.0f) bad++;
                }
                CHECK_MSG(bad == 0, "pfm ch%u be%u: %lu samples differ", ch, be, (unsigned long)bad);
            }
        }
    }
}

/* Python's zlib.compress(level 0) of a 1x1 grey PNG with value 0x80: our
 * stored encoder writes the same bytes. */
static void png_bytes_match_reference(void)
{
    static const unsigned char want[70] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
        0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0x3a, 0x7e, 0x9b,
        0x55, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78, 0x01, 0x01, 0x02, 0x00, 0xfd, 0xff,
        0x00, 0x80, 0x00, 0x82, 0x00, 0x81, 0xc3, 0x6e, 0x25, 0xe0, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45,
        0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    ls_arena a = fresh_arena();
    ls_image img;
    size_t n;
    REQUIRE(ls_image_create(&img, 1, 1, &a) == LS_OK);
    img.pixels[0] = 128.0f / 255.0f;
    n = encode(&img, LS_IMAGE_PNG_STORED, 1, 8, 0);
    CHECK_EQ(n, 70);
    CHECK(memcmp(outbuf, want, 70) == 0);
    n = encode(&img, LS_IMAGE_PNM, 1, 8, 0);
    CHECK(n == 12 && memcmp(outbuf, "P5\n1 1\n255\n\x80", 12) == 0);
    n = encode(&img, LS_IMAGE_PNM, 3, 16, 0);
    CHECK(n == 19 && memcmp(outbuf, "P6\n1 1\n65535\n\x80\x80\0\0\0\0", 19) == 0);
    img.pixels[0] = 1.5f;
    n = encode(&img, LS_IMAGE_PFM, 1, 32, 0);
    CHECK(n == 16 && memcmp(outbuf, "Pf\n1 1\n-1.0\n\x00\x00\xc0\x3f", 16) == 0);
    n = encode(&img, LS_IMAGE_PFM, 1, 32, 1);
    CHECK(n == 15 && memcmp(outbuf, "Pf\n1 1\n1.0\n\x3f\xc0\x00\x00", 15) == 0);
}

static void large_png_spans_blocks_and_chunks(void)
{
    static LS_ARENA_BUFFER(src_mem, 1200000);
    ls_arena sa;
    ls_image src, dec;
    ls_diag d;
    size_t n, pos = 8, idats = 0;
    ls_arena_init(&sa, src_mem.bytes, sizeof src_mem.bytes);
    REQUIRE(ls_image_create(&src, 250, 240, &sa) == LS_OK); /* 480 KB of raw RGBA16 */
    fill_pattern(&src, 65535.0f);
    n = encode(&src, LS_IMAGE_PNG_STORED, 4, 16, 0);
    REQUIRE(n > 480000);
    while (pos + 12 <= n) {
        if (memcmp(outbuf + pos + 4, "IDAT", 4) == 0) {
            idats++;
            CHECK(be32r(outbuf + pos) <= 65536u);
        }
        pos += 12 + be32r(outbuf + pos);
    }
    CHECK(idats >= 8);
    CHECK_EQ(pos, n);
    REQUIRE(decode(outbuf, n, &dec, &d) == LS_OK);
    check_decoded(&src, &dec, 4, "large rgba16");
}


/* --- the compressor --------------------------------------------------------- */

/* A render-like picture (what the program writes): a shaded disc on a
 * transparent background, samples quantised to q / m. */
static void fill_render(ls_image *img, float m)
{
    uint32_t x, y, k;
    float cx = 0.5f * (float)img->width, cy = 0.45f * (float)img->height;
    float r = 0.38f * (float)(img->width < img->height ? img->width : img->height);
    for (y = 0; y < img->height; y++)
        for (x = 0; x < img->width; x++) {
            float *p = img->pixels + 4 * ((size_t)y * img->width + x);
            float dx = ((float)x + 0.5f - cx) / r, dy = ((float)y + 0.5f - cy) / r, r2 = dx * dx + dy * dy;
            if (r2 < 1.0f) {
                float nz = sqrtf(1.0f - r2), l = 0.15f + 0.85f * (0.3f * -dx + 0.5f * -dy + 0.81f * nz);
                if (l < 0.05f) l = 0.05f;
                p[0] = 0.9f * l;
                p[1] = 0.75f * l;
                p[2] = 0.6f * l;
                p[3] = 1.0f;
            } else {
                p[0] = p[1] = p[2] = p[3] = 0.0f;
            }
            for (k = 0; k < 4; k++) p[k] = (float)(m > 255.0f ? ls_unorm16(p[k]) : ls_unorm8(p[k])) / m;
        }
}

static void fill_noise(ls_image *img, float m)
{
    size_t i, n = (size_t)img->width * img->height * 4;
    uint32_t x = 2463534242u;
    for (i = 0; i < n; i++) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        img->pixels[i] = (float)((x >> 7) % ((uint32_t)m + 1u)) / m;
    }
}

/* Every pattern, shape, channel count and depth: the file decodes (our
 * inflate) to the pixels, and its size is within ls_image_encoded_size. */
static void png_deflate_round_trips(void)
{
    static const uint32_t sizes[][2] = {{1, 1}, {2, 3}, {300, 2}, {257, 9}, {513, 3}, {1, 300}, {64, 48}};
    static LS_ARENA_BUFFER(src_mem, 600000);
    uint32_t s, pat, ch, bits;
    char what[96];
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (pat = 0; pat < 4; pat++)
            for (bits = 8; bits <= 16; bits += 8)
                for (ch = 1; ch <= 4; ch++) {
                    ls_arena sa;
                    ls_image src, dec;
                    ls_image_format f = {LS_IMAGE_PNG, 0, 0, 0};
                    ls_diag d;
                    size_t n, want = 0, k;
                    float m = bits == 8 ? 255.0f : 65535.0f;
                    ls_arena_init(&sa, src_mem.bytes, sizeof src_mem.bytes);
                    REQUIRE(ls_image_create(&src, sizes[s][0], sizes[s][1], &sa) == LS_OK);
                    if (pat == 0) fill_pattern(&src, m);
                    else if (pat == 1) fill_noise(&src, m);
                    else if (pat == 2) fill_render(&src, m);
                    else
                        for (k = 0; k < 4u * src.width * src.height; k++) src.pixels[k] = 0.25f;
                    if (pat == 3) fill_pattern(&src, 1.0f); /* 0 and 1 only: long runs */
                    f.channels = ch;
                    f.bits = bits;
                    n = encode(&src, LS_IMAGE_PNG, ch, bits, 0);
                    CHECK(ls_image_encoded_size(src.width, src.height, &f, &want) == LS_OK);
                    sprintf(what, "deflate %ux%u pattern %u ch%u %u-bit", src.width, src.height, pat, ch, bits);
                    CHECK_MSG(n > 0 && n <= want, "%s: %lu bytes, bound %lu", what, (unsigned long)n, (unsigned long)want);
                    CHECK_MSG(decode(outbuf, n, &dec, &d) == LS_OK, "%s: %s", what, d.what);
                    check_decoded(&src, &dec, ch, what);
                }
}

/* Beyond one window and one block: window slides, blocks ended by a full
 * symbol buffer and by a slide, stored fallback for noise, IDAT chunks of
 * 16 KiB; the same bytes from a second run (no state kept between calls). */
static void png_deflate_large_images(void)
{
    static const uint32_t dims[][3] = {{400, 300, 0}, {300, 200, 1}, {400, 300, 2}};
    size_t i;
    unsigned char *mem = (unsigned char *)malloc(6u << 20);
    REQUIRE(mem != NULL);
    for (i = 0; i < 3; i++) {
        ls_arena sa;
        ls_image src, dec;
        ls_diag d;
        size_t n, n2, pos = 8, idats = 0, want = 0, last = 0;
        uint64_t h;
        ls_image_format f = {LS_IMAGE_PNG, 4, 8, 0};
        ls_arena_init(&sa, mem, 6u << 20);
        REQUIRE(ls_image_create(&src, dims[i][0], dims[i][1], &sa) == LS_OK);
        if (dims[i][2] == 0) fill_render(&src, 255.0f);
        else if (dims[i][2] == 1) fill_noise(&src, 255.0f);
        else fill_pattern(&src, 255.0f);
        n = encode(&src, LS_IMAGE_PNG, 4, 8, 0);
        REQUIRE(n > 0);
        CHECK(ls_image_encoded_size(src.width, src.height, &f, &want) == LS_OK && n <= want);
        while (pos + 12 <= n) {
            if (memcmp(outbuf + pos + 4, "IDAT", 4) == 0) {
                CHECK(idats == 0 || last == 16384u); /* every IDAT but the last is full */
                last = be32r(outbuf + pos);
                CHECK(last > 0 && last <= 16384u);
                idats++;
            }
            pos += 12 + be32r(outbuf + pos);
        }
        CHECK_EQ(pos, n);
        CHECK(idats >= 1);
        h = test_hash(outbuf, n, TEST_HASH_SEED);
        REQUIRE(decode(outbuf, n, &dec, &d) == LS_OK);
        check_decoded(&src, &dec, 4, "large deflate");
        n2 = encode(&src, LS_IMAGE_PNG, 4, 8, 0);
        CHECK(n2 == n && test_hash(outbuf, n, TEST_HASH_SEED) == h);
        if (dims[i][2] == 0) CHECK(n < 480300u / 10u); /* raw: 480300 bytes */
        if (dims[i][2] == 1) CHECK(n > 240200u);       /* noise: stored blocks */
        if (dims[i][2] == 2) CHECK(n < 480300u / 4u);
    }
    free(mem);
}

/* The size against zlib: the render-like 128 x 128 RGBA8 picture. zlib -6 of
 * its unfiltered rows (Python: zlib.compress(rows, 6), rows = a filter byte 0
 * and the 512 samples of each row) is ZLIB6 bytes; the file must be within
 * 1.3 x that plus the PNG chunks (57 bytes), and far below the stored file. */
#define ZLIB6_RENDER128 10152u
static void png_deflate_size_against_zlib(void)
{
    ls_arena a = fresh_arena();
    ls_image img;
    size_t n, stored;
    REQUIRE(ls_image_create(&img, 128, 128, &a) == LS_OK);
    fill_render(&img, 255.0f);
    stored = encode(&img, LS_IMAGE_PNG_STORED, 4, 8, 0);
    n = encode(&img, LS_IMAGE_PNG, 4, 8, 0);
    CHECK_EQ(stored, 65749);
    CHECK_MSG(n > 0 && (double)n <= 1.3 * ZLIB6_RENDER128 + 57.0, "%lu bytes, zlib -6 %u", (unsigned long)n,
              (unsigned)ZLIB6_RENDER128);
    printf("     png 128x128 render-like RGBA8: stored %lu bytes, compressed %lu, zlib -6 of the rows %u\n",
           (unsigned long)stored, (unsigned long)n, (unsigned)ZLIB6_RENDER128);
}


/* The compressed bytes are a function of the pixels only: the same hash on
 * every target (tests/digest.c hashes stored PNG: the compressor's state does
 * not fit the MCU profile). */
static void png_deflate_bytes_are_pinned(void)
{
    static const struct { uint32_t w, h, pattern, ch, bits; uint64_t hash; size_t n; } cases[] = {
        {128, 128, 0, 4, 8, 0xcc45813ef3b1cbeaull, 6934},
        {64, 48, 1, 3, 16, 0x74ac049e73d003d3ull, 4379},
        {300, 200, 2, 4, 8, 0xe3e7c887f6c9288eull, 240506}};
    unsigned char *mem = (unsigned char *)malloc(2u << 20);
    size_t i;
    REQUIRE(mem != NULL);
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ls_arena sa;
        ls_image img;
        size_t n;
        uint64_t h;
        float m = cases[i].bits == 8 ? 255.0f : 65535.0f;
        ls_arena_init(&sa, mem, 2u << 20);
        REQUIRE(ls_image_create(&img, cases[i].w, cases[i].h, &sa) == LS_OK);
        if (cases[i].pattern == 0) fill_render(&img, m);
        else if (cases[i].pattern == 1) fill_pattern(&img, m);
        else fill_noise(&img, m);
        n = encode(&img, LS_IMAGE_PNG, cases[i].ch, cases[i].bits, 0);
        h = test_hash(outbuf, n, TEST_HASH_SEED);
        CHECK_MSG(h == cases[i].hash && n == cases[i].n, "case %lu: %016llx, %lu bytes", (unsigned long)i,
                  (unsigned long long)h, (unsigned long)n);
    }
    free(mem);
}

/* --- fixtures from Python's zlib ------------------------------------------ */

static uint32_t fixture_p(uint32_t x, uint32_t y, uint32_t c, uint32_t bits)
{
    return (2473u * x + 4027u * y + 8191u * c + 97u * x * y + 5u) % (1u << bits);
}

/* Decodes one fixture and compares every pixel with the formula. Returns 1
 * when the file exists. */
static int check_fixture(const char *path, uint32_t w, uint32_t h, uint32_t color, uint32_t bits, uint32_t il,
                         uint32_t trns)
{
    unsigned char *data;
    size_t n, x, y, bad = 0;
    ls_image img;
    ls_image_info info;
    ls_diag d;
    uint32_t maxv = (1u << bits) - 1u, npal = bits == 8 ? 200u : (1u << bits);
    if (read_file(path, &data, &n) != LS_OK) return 0;
    CHECK_MSG(ls_image_decode_info(data, n, &info, &d) == LS_OK, "%s: %s", path, d.what);
    CHECK(info.width == w && info.height == h && info.format.bits == bits && info.interlaced == il &&
          info.palette == (color == 3) && info.transparency == trns);
    if (decode(data, n, &img, &d) != LS_OK) {
        CHECK_MSG(0, "%s: %s at %lu", path, d.what, (unsigned long)d.offset);
        free(data);
        return 1;
    }
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            const float *px = img.pixels + 4 * (y * w + x);
            float want[4];
            uint32_t k, q[4];
            for (k = 0; k < 4; k++) q[k] = fixture_p((uint32_t)x, (uint32_t)y, k, bits);
            if (color == 3) {
                uint32_t i = q[0] % npal;
                want[0] = (float)((37u * i) % 256u) / 255.0f;
                want[1] = (float)((91u * i) % 256u) / 255.0f;
                want[2] = (float)((151u * i) % 256u) / 255.0f;
                want[3] = (trns && i <= npal / 2) ? (float)((53u * i) % 256u) / 255.0f : 1.0f;
            } else if (color == 0 || color == 4) {
                want[0] = want[1] = want[2] = (float)q[0] / (float)maxv;
                want[3] = color == 4 ? (float)q[1] / (float)maxv
                                     : (trns && q[0] == fixture_p(1, 0, 0, bits)) ? 0.0f : 1.0f;
            } else {
                for (k = 0; k < 3; k++) want[k] = (float)q[k] / (float)maxv;
                want[3] = color == 6 ? (float)q[3] / (float)maxv
                          : (trns && q[0] == fixture_p(1, 0, 0, bits) && q[1] == fixture_p(1, 0, 1, bits) &&
                             q[2] == fixture_p(1, 0, 2, bits)) ? 0.0f : 1.0f;
            }
            if (memcmp(want, px, sizeof want) != 0) bad++;
        }
    CHECK_MSG(bad == 0, "%s: %lu pixels differ", path, (unsigned long)bad);
    free(data);
    return 1;
}

static void python_fixtures_decode_exactly(void)
{
    static const uint32_t chans[7] = {1, 0, 3, 1, 2, 0, 4};
    static const char *zs[3] = {"dyn", "fix", "split"};
    static const uint32_t tiny[6][4] = {{1, 1, 3, 1}, {1, 1, 6, 16}, {2, 3, 0, 2}, {3, 2, 2, 8}, {5, 1, 4, 8}, {1, 9, 0, 16}};
    uint32_t color, bits, il, trns, zi, files = 0, i;
    char path[128];
    for (color = 0; color <= 6; color++) {
        if (chans[color] == 0) continue;
        for (bits = 1; bits <= 16; bits *= 2)
            for (il = 0; il <= 1; il++)
                for (trns = 0; trns <= 1; trns++)
                    for (zi = 0; zi < 3; zi++) {
                        sprintf(path, "fixtures/images/c%u_b%u_i%u_t%u_%s.png", color, bits, il, trns, zs[zi]);
                        files += (uint32_t)check_fixture(path, 61, 43, color, bits, il, trns);
                    }
    }
    for (i = 0; i < 6; i++) {
        sprintf(path, "fixtures/images/tiny_%ux%u_c%u_b%u_i1.png", tiny[i][0], tiny[i][1], tiny[i][2], tiny[i][3]);
        files += (uint32_t)check_fixture(path, tiny[i][0], tiny[i][1], tiny[i][2], tiny[i][3], 1, 0);
    }
    CHECK_EQ(files, 44);
}

/* --- a hand-built dynamic Huffman stream ----------------------------------- */

typedef struct bitw {
    unsigned char b[256];
    size_t n;      /* bits written */
} bitw;

static void put_bits(bitw *w, uint32_t v, uint32_t n)
{
    uint32_t i;
    for (i = 0; i < n; i++, w->n++) {
        if (w->n % 8 == 0) w->b[w->n / 8] = 0;
        w->b[w->n / 8] |= (unsigned char)(((v >> i) & 1u) << (w->n % 8));
    }
}

/* Canonical codes of RFC 1951 3.2.2 from lengths. */
static void canon(const uint8_t *len, uint32_t n, uint32_t *code)
{
    uint32_t bl[16] = {0}, next[16], c = 0, i, b;
    for (i = 0; i < n; i++) bl[len[i]]++;
    bl[0] = 0;
    for (b = 1; b < 16; b++) {
        c = (c + bl[b - 1]) << 1;
        next[b] = c;
    }
    for (i = 0; i < n; i++)
        if (len[i]) code[i] = next[len[i]]++;
}

static void put_code(bitw *w, uint32_t code, uint32_t len)
{
    uint32_t i;
    for (i = 0; i < len; i++) put_bits(w, (code >> (len - 1 - i)) & 1u, 1);
}

/* Options to break the stream in chosen ways. */
typedef struct dyn_opts {
    uint32_t hlit_extra;    /* added to HLIT-257 (beyond 286 is an error) */
    int oversubscribe;      /* give 'c' length 1 */
    int no_eob;             /* give 256 length 0 */
    int repeat_first;       /* start the code lengths with code 16 */
    int incomplete;         /* give 'c' length 3: the literal/length code is incomplete */
    int bad_dist_code;      /* one distance code only, then the unused bit pattern */
} dyn_opts;

/* Raw deflate: one dynamic block producing "abcabcaaaaac". */
static size_t build_dynamic(const dyn_opts *o, unsigned char *out)
{
    static const uint8_t order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    bitw w;
    uint8_t lit[259] = {0}, dist[3] = {1, 0, 1}, cl[19] = {0};
    uint32_t litc[259], distc[3], clc[19], i;
    memset(&w, 0, sizeof w);
    lit['a'] = lit['b'] = lit['c'] = 2;
    lit[256] = 3;
    lit[258] = 3;
    if (o->oversubscribe) lit['c'] = 1;
    if (o->no_eob) lit[256] = 0;
    if (o->incomplete) lit['c'] = 3;
    if (o->bad_dist_code) dist[2] = 0;
    cl[18] = 2;
    cl[2] = 2;
    cl[0] = 2;
    cl[3] = 3;
    cl[1] = 3;
    if (o->repeat_first) cl[1] = cl[16] = 4;
    canon(lit, 259, litc);
    canon(dist, 3, distc);
    canon(cl, 19, clc);
    put_bits(&w, 1, 1);          /* BFINAL */
    put_bits(&w, 2, 2);          /* dynamic */
    put_bits(&w, 2 + o->hlit_extra, 5); /* HLIT = 259 */
    put_bits(&w, 2, 5);          /* HDIST = 3 */
    put_bits(&w, 14, 4);         /* HCLEN = 18 */
    for (i = 0; i < 18; i++) put_bits(&w, cl[order[i]], 3);
    if (o->repeat_first) {
        put_code(&w, clc[16], 4);
        put_bits(&w, 0, 2);
    }
    /* lengths: 97 zeros, 2 2 2 (or 2 2 1), 156 zeros, 3 (or 0), 0, 3 | 1 0 1 */
    put_code(&w, clc[18], 2);
    put_bits(&w, 97 - 11, 7);
    put_code(&w, clc[2], 2);
    put_code(&w, clc[2], 2);
    if (o->oversubscribe) put_code(&w, clc[1], cl[1]);
    else if (o->incomplete) put_code(&w, clc[3], 3);
    else put_code(&w, clc[2], 2);
    put_code(&w, clc[18], 2);
    put_bits(&w, 138 - 11, 7);
    put_code(&w, clc[18], 2);
    put_bits(&w, 18 - 11, 7);
    if (o->no_eob) put_code(&w, clc[0], 2); else put_code(&w, clc[3], 3);
    put_code(&w, clc[0], 2);
    put_code(&w, clc[3], 3);
    put_code(&w, clc[1], cl[1]);
    put_code(&w, clc[0], 2);
    if (o->bad_dist_code) put_code(&w, clc[0], 2); else put_code(&w, clc[1], cl[1]);
    if (o->bad_dist_code) {
        put_code(&w, litc['a'], 2);
        put_code(&w, litc[258], 3);
        put_bits(&w, 1, 1); /* no distance code starts with 1 */
    } else if (!o->oversubscribe && !o->no_eob && !o->incomplete) {
        put_code(&w, litc['a'], 2);
        put_code(&w, litc['b'], 2);
        put_code(&w, litc['c'], 2);
        put_code(&w, litc[258], 3); /* length 4 */
        put_code(&w, distc[2], 1);  /* distance symbol 2: 3 */
        put_code(&w, litc[258], 3);
        put_code(&w, distc[0], 1);  /* distance 1 */
        put_code(&w, litc['c'], 2);
        put_code(&w, litc[256], 3);
    }
    memcpy(out, w.b, (w.n + 7) / 8);
    return (w.n + 7) / 8;
}

static void inflate_handcrafted_dynamic_block(void)
{
    unsigned char stream[256], zs[300], out[64];
    size_t n, got;
    dyn_opts o;
    ls_arena a = fresh_arena();
    ls_diag d;
    uint32_t ad;
    memset(&o, 0, sizeof o);
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_OK);
    CHECK(got == 12 && memcmp(out, "abcabcaaaaac", 12) == 0);
    CHECK_EQ(ls_arena_used(&a), 0);
    /* the output buffer one byte short */
    CHECK_STATUS(ls_inflate(stream, n, out, 11, &got, &a, &d), LS_ERR_TOO_LARGE);
    /* argument errors name the argument */
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, NULL, &a, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "out_bytes is NULL") == 0);
    CHECK_STATUS(ls_zlib_decompress(NULL, n, out, sizeof out, &got, &a, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "src is NULL") != NULL);
    {
        ls_image_info info;
        ls_image img;
        CHECK_STATUS(ls_image_decode_info(stream, n, NULL, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "info is NULL") == 0);
        CHECK_STATUS(ls_image_decode_info(NULL, n, &info, &d), LS_ERR_INVALID);
        CHECK(strstr(d.what, "data is NULL") != NULL);
        CHECK_STATUS(ls_image_decode(stream, n, &img, NULL, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "arena is NULL") == 0);
    }
    /* the same in a zlib wrapper */
    zs[0] = 0x78;
    zs[1] = 0x9c;
    memcpy(zs + 2, stream, n);
    ad = ls_adler32(1, "abcabcaaaaac", 12);
    be32w(zs + 2 + n, ad);
    CHECK_STATUS(ls_zlib_decompress(zs, n + 6, out, sizeof out, &got, &a, &d), LS_OK);
    CHECK(got == 12 && memcmp(out, "abcabcaaaaac", 12) == 0);
    zs[n + 5] ^= 1;
    CHECK_STATUS(ls_zlib_decompress(zs, n + 6, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strcmp(d.what, "zlib Adler-32 mismatch") == 0);
    zs[n + 5] ^= 1;
    CHECK_STATUS(ls_zlib_decompress(zs, n + 7, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strcmp(d.what, "bytes after the end of the deflate stream") == 0);
    /* every truncation fails cleanly */
    {
        size_t k, bad = 0;
        for (k = 0; k < n + 6; k++)
            if (ls_zlib_decompress(zs, k, out, sizeof out, &got, &a, &d) != LS_ERR_PARSE) bad++;
        CHECK_EQ(bad, 0);
    }
}

static void inflate_rejects_malformed_streams(void)
{
    unsigned char stream[256], out[64];
    size_t n, got;
    dyn_opts o;
    ls_arena a = fresh_arena();
    ls_diag d;
    memset(&o, 0, sizeof o);
    o.oversubscribe = 1;
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strstr(d.what, "oversubscribed") != NULL);
    memset(&o, 0, sizeof o);
    o.incomplete = 1;
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strstr(d.what, "literal/length code lengths incomplete") != NULL);
    memset(&o, 0, sizeof o);
    o.bad_dist_code = 1;
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strcmp(d.what, "deflate: invalid distance code") == 0);
    memset(&o, 0, sizeof o);
    o.no_eob = 1;
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strstr(d.what, "no end-of-block code") != NULL);
    memset(&o, 0, sizeof o);
    o.hlit_extra = 28; /* HLIT = 287 */
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strstr(d.what, "more than 286") != NULL);
    CHECK(d.has_offset && d.offset <= 3);
    memset(&o, 0, sizeof o);
    o.repeat_first = 1;
    n = build_dynamic(&o, stream);
    CHECK_STATUS(ls_inflate(stream, n, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    CHECK(strstr(d.what, "repeat code 16 with no previous length") != NULL);
    /* hand-made fixed and stored blocks */
    {
        /* fixed block: literal 'A' (0x41: code 0x30+0x41 = 0x71, 8 bits) then length 3
           (symbol 257: 7-bit code 0000001) distance code 1 (5 bits, = 2): too far */
        bitw w;
        memset(&w, 0, sizeof w);
        put_bits(&w, 1, 1);
        put_bits(&w, 1, 2);
        put_code(&w, 0x30 + 'A', 8);
        put_code(&w, 1, 7);
        put_code(&w, 1, 5);
        put_code(&w, 0, 7);
        CHECK_STATUS(ls_inflate(w.b, (w.n + 7) / 8, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strcmp(d.what, "deflate: distance too far back") == 0);
        /* the same with distance code 0 (= 1): "AAAA" */
        memset(&w, 0, sizeof w);
        put_bits(&w, 1, 1);
        put_bits(&w, 1, 2);
        put_code(&w, 0x30 + 'A', 8);
        put_code(&w, 1, 7);
        put_code(&w, 0, 5);
        put_code(&w, 0, 7);
        CHECK_STATUS(ls_inflate(w.b, (w.n + 7) / 8, out, sizeof out, &got, &a, &d), LS_OK);
        CHECK(got == 4 && memcmp(out, "AAAA", 4) == 0);
        /* length symbol 286 (8-bit code 11000110) */
        memset(&w, 0, sizeof w);
        put_bits(&w, 1, 1);
        put_bits(&w, 1, 2);
        put_code(&w, 0xc0 + 6, 8);
        CHECK_STATUS(ls_inflate(w.b, (w.n + 7) / 8, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strstr(d.what, "286 or 287") != NULL);
        /* distance symbol 30 */
        memset(&w, 0, sizeof w);
        put_bits(&w, 1, 1);
        put_bits(&w, 1, 2);
        put_code(&w, 0x30 + 'A', 8);
        put_code(&w, 1, 7);
        put_code(&w, 30, 5);
        put_code(&w, 0, 7);
        CHECK_STATUS(ls_inflate(w.b, (w.n + 7) / 8, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strstr(d.what, "30 or 31") != NULL);
        /* block type 3 */
        memset(&w, 0, sizeof w);
        put_bits(&w, 7, 3);
        CHECK_STATUS(ls_inflate(w.b, 1, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strcmp(d.what, "deflate: invalid block type 3") == 0);
    }
    {
        unsigned char st[10] = {0x01, 0x03, 0x00, 0xfc, 0xff, 'x', 'y', 'z'};
        CHECK_STATUS(ls_inflate(st, 8, out, sizeof out, &got, &a, &d), LS_OK);
        CHECK(got == 3 && memcmp(out, "xyz", 3) == 0);
        st[3] = 0xfd;
        CHECK_STATUS(ls_inflate(st, 8, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strstr(d.what, "complement") != NULL);
        st[3] = 0xfc;
        CHECK_STATUS(ls_inflate(st, 7, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strcmp(d.what, "deflate stream truncated") == 0);
        CHECK_STATUS(ls_inflate(st, 0, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
    }
    {
        unsigned char zh[8] = {0x78, 0x9d, 0x03, 0x00}; /* FCHECK wrong */
        CHECK_STATUS(ls_zlib_decompress(zh, 8, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        CHECK(strstr(d.what, "check bits") != NULL);
        zh[0] = 0x77; /* CM 7 */
        CHECK_STATUS(ls_zlib_decompress(zh, 8, out, sizeof out, &got, &a, &d), LS_ERR_PARSE);
        zh[0] = 0x78;
        zh[1] = 0xbb; /* FDICT set, (0x78bb % 31 == 0) */
        CHECK_EQ((0x78 * 256 + 0xbb) % 31, 0);
        CHECK_STATUS(ls_zlib_decompress(zh, 8, out, sizeof out, &got, &a, &d), LS_ERR_UNSUPPORTED);
    }
    CHECK_EQ(ls_arena_used(&a), 0);
}

/* --- malformed images ------------------------------------------------------ */

static size_t small_png(uint32_t ch, uint32_t bits)
{
    static LS_ARENA_BUFFER(m, 4096);
    ls_arena a;
    ls_image img;
    ls_arena_init(&a, m.bytes, sizeof m.bytes);
    ls_image_create(&img, 5, 4, &a);
    fill_pattern(&img, 255.0f);
    return encode(&img, LS_IMAGE_PNG_STORED, ch, bits, 0); /* the tests below edit its stored data */
}

static void expect_png_error(unsigned char *png, size_t n, ls_status want, const char *what)
{
    ls_image img = {0, 0, NULL};
    ls_diag d;
    ls_status st = decode(png, n, &img, &d);
    CHECK_MSG(st == want, "%s: got %s (%s), wanted %s", what, ls_status_name(st), st != LS_OK ? d.what : "",
              ls_status_name(want));
    CHECK_MSG(st == LS_OK || strstr(d.what, what) != NULL, "wanted '%s', got '%s'", what, d.what);
    CHECK(img.pixels == NULL);
}

static void png_malformed_inputs(void)
{
    unsigned char png[2048];
    size_t n = small_png(3, 8), idat, ihdr, k;
    ls_diag d;
    ls_image img;
    REQUIRE(n > 60 && n < sizeof png);
    memcpy(png, outbuf, n);
    ihdr = 8;
    idat = find_chunk(png, n, "IDAT");
    REQUIRE(idat != 0);
    /* bad CRC: the offset is that of the CRC field */
    png[idat + 8 + 10] ^= 0x10;
    CHECK_STATUS(decode(png, n, &img, &d), LS_ERR_PARSE);
    CHECK(strcmp(d.what, "PNG CRC mismatch") == 0);
    CHECK(d.has_offset && d.offset == idat + 8 + be32r(png + idat));
    /* same corruption with the CRC fixed: the Adler-32 catches it, at the
       end of the zlib stream inside the IDAT chunk */
    fix_crc(png, idat);
    CHECK_STATUS(decode(png, n, &img, &d), LS_ERR_PARSE);
    CHECK(strcmp(d.what, "zlib Adler-32 mismatch") == 0);
    CHECK(d.has_offset && d.offset > idat + 8 && d.offset <= idat + 8 + be32r(png + idat));
    memcpy(png, outbuf, n);
    /* every truncation */
    {
        size_t bad = 0;
        for (k = 0; k < n; k++)
            if (decode(png, k, &img, &d) != LS_ERR_PARSE) bad++;
        CHECK_EQ(bad, 0);
    }
    /* trailing garbage */
    png[n] = 0;
    expect_png_error(png, n + 1, LS_ERR_PARSE, "bytes after PNG IEND");
    /* huge and zero dimensions */
    be32w(png + ihdr + 8, 0x7fffffffu);
    be32w(png + ihdr + 12, 0x7fffffffu);
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_TOO_LARGE, "too large");
    be32w(png + ihdr + 8, 0x80000000u);
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "above 2^31 - 1");
    be32w(png + ihdr + 8, 0);
    be32w(png + ihdr + 12, 4);
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "zero width");
    /* a larger declared size than the data: the zlib stream ends early */
    be32w(png + ihdr + 8, 6);
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "ends early");
    /* a smaller one: too much data */
    be32w(png + ihdr + 8, 4);
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "more data than the image");
    memcpy(png, outbuf, n);
    /* bad bit depth, colour type, interlace */
    png[ihdr + 16] = 3;
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "invalid bit depth");
    png[ihdr + 16] = 8;
    png[ihdr + 17] = 5;
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "invalid colour type");
    png[ihdr + 17] = 2;
    png[ihdr + 20] = 2;
    fix_crc(png, ihdr);
    expect_png_error(png, n, LS_ERR_PARSE, "interlace");
    memcpy(png, outbuf, n);
    /* filter type 5 in the first row: rewrite the stored data and both checksums */
    {
        unsigned char *z = png + idat + 8;
        size_t zlen = be32r(png + idat);
        z[2 + 5] = 5;
        be32w(z + zlen - 4, ls_adler32(1, z + 7, zlen - 11));
        fix_crc(png, idat);
        expect_png_error(png, n, LS_ERR_PARSE, "filter type above 4");
        CHECK_STATUS(decode(png, n, &img, &d), LS_ERR_PARSE);
        CHECK(d.has_index && d.index == 0 && d.has_value && d.value == 5);
    }
    memcpy(png, outbuf, n);
    /* unknown critical chunk and ancillary chunk */
    {
        unsigned char q[2100];
        size_t at = idat;
        memcpy(q, png, at);
        be32w(q + at, 1);
        memcpy(q + at + 4, "ZZZZ", 4);
        q[at + 8] = 1;
        fix_crc(q, at);
        memcpy(q + at + 13, png + at, n - at);
        expect_png_error(q, n + 13, LS_ERR_UNSUPPORTED, "unknown critical chunk");
        memcpy(q + at + 4, "zzZz", 4);
        fix_crc(q, at);
        CHECK_STATUS(decode(q, n + 13, &img, &d), LS_OK);
        /* an ancillary chunk between two IDAT chunks */
        {
            unsigned char anc[13];
            memcpy(anc, q + at, 13);
            memcpy(q, png, n - 12);
            memcpy(q + n - 12, anc, 13);
        }
        memcpy(q + n + 1, png + idat, 12); /* an empty-data IDAT copy: fix its length */
        be32w(q + n + 1, 0);
        memcpy(q + n + 5, "IDAT", 4);
        fix_crc(q, n + 1);
        memcpy(q + n + 13, png + n - 12, 12);
        expect_png_error(q, n + 25, LS_ERR_PARSE, "not consecutive");
    }
    /* missing IEND, missing IDAT, chunk length beyond the file */
    expect_png_error(png, n - 12, LS_ERR_PARSE, "without IEND");
    {
        unsigned char q[64];
        memcpy(q, png, 33);
        memcpy(q + 33, png + n - 12, 12);
        expect_png_error(q, 45, LS_ERR_PARSE, "no IDAT");
        memcpy(q, png, 45);
        be32w(q + 33, 0x7fffff00u);
        expect_png_error(q, 45, LS_ERR_PARSE, "truncated");
        q[0] = 'X';
        expect_png_error(q, 45, LS_ERR_PARSE, "unknown image signature");
    }
    expect_png_error(png, 0, LS_ERR_PARSE, "unknown image signature");
}

static void png_palette_errors(void)
{
    unsigned char *data, png[4096];
    size_t n, plte, trns, idat;
    ls_image img;
    ls_diag d;
    REQUIRE(read_file("fixtures/images/c3_b8_i0_t1_dyn.png", &data, &n) == LS_OK);
    REQUIRE(n < sizeof png);
    memcpy(png, data, n);
    free(data);
    plte = find_chunk(png, n, "PLTE");
    trns = find_chunk(png, n, "tRNS");
    idat = find_chunk(png, n, "IDAT");
    REQUIRE(plte && trns && idat);
    /* shrink the palette to 100 entries: indices 100..199 are out of range
       (the tRNS chunk, 101 entries, must shrink too) */
    {
        unsigned char q[4096];
        size_t m;
        memcpy(q, png, plte);
        be32w(q + plte, 300);
        memcpy(q + plte + 4, png + plte + 4, 304);
        fix_crc(q, plte);
        m = plte + 312;
        be32w(q + m, 100);
        memcpy(q + m + 4, png + trns + 4, 104);
        fix_crc(q, m);
        m += 112;
        memcpy(q + m, png + trns + 12 + 101, n - trns - 12 - 101);
        m += n - trns - 12 - 101;
        expect_png_error(q, m, LS_ERR_PARSE, "palette index out of range");
        CHECK_STATUS(decode(q, m, &img, &d), LS_ERR_PARSE);
        CHECK(d.has_index);
        /* tRNS longer than the palette */
        be32w(q + plte + 312, 101);
        memcpy(q + plte + 312 + 4, png + trns + 4, 105);
        fix_crc(q, plte + 312);
        memcpy(q + plte + 312 + 113, png + trns + 12 + 101, n - trns - 12 - 101);
        expect_png_error(q, m + 1, LS_ERR_PARSE, "tRNS length");
    }
    /* no PLTE at all */
    {
        unsigned char q[4096];
        size_t len = be32r(png + plte) + 12;
        memcpy(q, png, plte);
        memcpy(q + plte, png + plte + len, n - plte - len);
        expect_png_error(q, n - len, LS_ERR_PARSE, "tRNS before PLTE");
    }
}

static void pnm_and_pfm_headers(void)
{
    ls_image img;
    ls_diag d;
    ls_image_info info;
    static const char ok1[] = "P5\n# comment\n 2 # w\n1\n# maxval next\n 1000\n\x03\xe8\x01\xf4";
    static const char ok2[] = "P6 1 1 7\n\x07\x00\x03";
    static const char pf[] = "Pf\n1 2\n-2.5e+0\n\x00\x00\x80\x3f\x00\x00\x00\xc0";
    CHECK_STATUS(decode((const unsigned char *)ok1, sizeof ok1 - 1, &img, &d), LS_OK);
    CHECK(img.width == 2 && img.height == 1 && img.pixels[0] == 1.0f && img.pixels[4] == 500.0f / 1000.0f);
    CHECK_STATUS(ls_image_decode_info(ok1, sizeof ok1 - 1, &info, &d), LS_OK);
    CHECK(info.maxval == 1000 && info.format.bits == 16 && info.format.channels == 1 && info.arena_bytes == 32);
    CHECK_STATUS(decode((const unsigned char *)ok2, sizeof ok2 - 1, &img, &d), LS_OK);
    CHECK(img.pixels[0] == 1.0f && img.pixels[1] == 0.0f && img.pixels[2] == 3.0f / 7.0f && img.pixels[3] == 1.0f);
    CHECK_STATUS(decode((const unsigned char *)pf, sizeof pf - 1, &img, &d), LS_OK);
    CHECK(img.pixels[0] == -2.0f && img.pixels[4] == 1.0f); /* bottom row first */
    {
        struct { const char *s; ls_status st; const char *what; } bad[] = {
            {"P5\n2 1\n255\n\x01", LS_ERR_PARSE, "truncated"},
            {"P5\n2 1\n255\n\x01\x02\x03", LS_ERR_PARSE, "bytes after"},
            {"P5\n0 1\n255\n", LS_ERR_PARSE, "zero width"},
            {"P5\n99999999999 1\n255\n", LS_ERR_TOO_LARGE, "too large"},
            {"P5\n2000000 2000000\n255\n", LS_ERR_TOO_LARGE, "too large"},
            {"P5\n1 1\n70000\n\x01\x02", LS_ERR_PARSE, "maxval"},
            {"P5\n1 1\n0\n\x01", LS_ERR_PARSE, "maxval"},
            {"P5\n1 1\n10\n\x0b", LS_ERR_PARSE, "above maxval"},
            {"P5\n1 1\n255", LS_ERR_PARSE, "one whitespace"},
            {"P5\n1 x\n255\n\x01", LS_ERR_PARSE, "height missing"},
            {"P5", LS_ERR_PARSE, "whitespace"},
            {"P3\n1 1\n255\n1 2 3\n", LS_ERR_UNSUPPORTED, "ASCII"},
            {"P7\nWIDTH 1\n", LS_ERR_UNSUPPORTED, "PAM"},
            {"PF\n1 1\nabc\n", LS_ERR_PARSE, "scale"},
            {"PF\n1 1\n1e\n", LS_ERR_PARSE, "scale"},
            {"PF\n1 1\n-1.0\n\x01\x02\x03\x04", LS_ERR_PARSE, "truncated"},
            {"GIF89a", LS_ERR_PARSE, "signature"},
        };
        size_t i;
        for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
            size_t len = strlen(bad[i].s);
            ls_status st;
            st = decode((const unsigned char *)bad[i].s, len, &img, &d);
            CHECK_MSG(st == bad[i].st && strstr(d.what, bad[i].what) != NULL, "case %lu: %s (%s), wanted %s",
                      (unsigned long)i, ls_status_name(st), d.what, bad[i].what);
        }
    }
}

/* Random corruption with fixed-up CRCs reaches the inflater: nothing crashes
 * or hangs, every answer is OK or a named error. */
static void png_mutations_never_crash(void)
{
    static const char *files[] = {"fixtures/images/c2_b8_i1_t0_dyn.png", "fixtures/images/c0_b8_i0_t1_fix.png",
                                  "fixtures/images/c3_b4_i1_t1_split.png", "fixtures/images/c6_b16_i0_t0_fix.png"};
    size_t f, it, errors = 0, oks = 0, unnamed = 0;
    for (f = 0; f < 4; f++) {
        unsigned char *data, *q;
        size_t n;
        REQUIRE(read_file(files[f], &data, &n) == LS_OK);
        q = (unsigned char *)malloc(n);
        for (it = 0; it < 300; it++) {
            size_t idat, at, len, k, flips = 1 + rng() % 3;
            ls_image img;
            ls_diag d;
            ls_status st;
            memcpy(q, data, n);
            idat = find_chunk(q, n, "IDAT");
            len = be32r(q + idat);
            for (k = 0; k < flips; k++) {
                at = idat + 8 + rng() % len;
                q[at] ^= (unsigned char)(1u << (rng() % 8));
            }
            fix_crc(q, idat);
            st = decode(q, n, &img, &d);
            if (st == LS_OK) oks++;
            else {
                errors++;
                if (d.what == NULL || d.what[0] == 0 || (st != LS_ERR_PARSE && st != LS_ERR_UNSUPPORTED)) unnamed++;
            }
        }
        free(q);
        free(data);
    }
    CHECK_EQ(unnamed, 0);
    CHECK(errors > 1000);
    (void)oks;
}

/* Random corruption anywhere (IHDR, PLTE, tRNS, IDAT, lengths), with every
 * CRC that still fits recomputed so the semantic checks are reached; and
 * random bytes in PNM/PFM headers. */
static void whole_file_mutations_never_crash(void)
{
    static const char *files[] = {"fixtures/images/c3_b2_i0_t0_fix.png", "fixtures/images/c0_b16_i1_t1_dyn.png",
                                  "fixtures/images/tiny_3x2_c2_b8_i1.png", "fixtures/images/c3_b8_i0_t1_dyn.png"};
    size_t f, it, unnamed = 0, errors = 0;
    for (f = 0; f < 4; f++) {
        unsigned char *data, *q;
        size_t n;
        REQUIRE(read_file(files[f], &data, &n) == LS_OK);
        q = (unsigned char *)malloc(n);
        for (it = 0; it < 400; it++) {
            size_t k, flips = 1 + rng() % 4, pos = 8;
            ls_image img;
            ls_diag d;
            ls_status st;
            memcpy(q, data, n);
            for (k = 0; k < flips; k++) q[8 + rng() % (n - 8)] ^= (unsigned char)(1u << (rng() % 8));
            while (pos + 12 <= n) {
                uint32_t len = be32r(q + pos);
                if (len > n - pos - 12) break;
                if (rng() % 8 != 0) fix_crc(q, pos); /* sometimes leave a bad CRC */
                pos += 12 + len;
            }
            st = decode(q, n, &img, &d);
            if (st != LS_OK) {
                errors++;
                if (d.what == NULL || d.what[0] == 0 ||
                    (st != LS_ERR_PARSE && st != LS_ERR_UNSUPPORTED && st != LS_ERR_TOO_LARGE && st != LS_ERR_NOMEM))
                    unnamed++;
            }
        }
        free(q);
        free(data);
    }
    CHECK_EQ(unnamed, 0);
    CHECK(errors > 800);
    {
        static const char base[] = "P6\n# c\n3 2\n255\nabcdefghijklmnopqr";
        char q[sizeof base];
        for (it = 0; it < 3000; it++) {
            ls_image img;
            ls_diag d;
            ls_status st;
            memcpy(q, base, sizeof base);
            q[rng() % 16] = (char)(rng() % 3 == 0 ? "0123456789 #\nPF"[rng() % 15] : (char)rng());
            if (it % 2) q[1] = 'F';
            st = decode((const unsigned char *)q, sizeof base - 1 - (it % 5), &img, &d);
            if (st != LS_OK && (d.what == NULL || d.what[0] == 0)) unnamed++;
        }
        CHECK_EQ(unnamed, 0);
    }
}

/* --- arena sweeps ---------------------------------------------------------- */

typedef struct decode_job {
    const unsigned char *data;
    size_t n;
    ls_image img;
} decode_job;

static ls_status run_decode(void *ctx, ls_arena *a)
{
    decode_job *j = (decode_job *)ctx;
    return ls_image_decode(j->data, j->n, &j->img, a, NULL);
}

static uint64_t hash_decode(void *ctx)
{
    decode_job *j = (decode_job *)ctx;
    return test_hash(&j->img, sizeof j->img, test_hash(j->data, j->n, TEST_HASH_SEED));
}

static void reset_decode(void *ctx)
{
    decode_job *j = (decode_job *)ctx;
    memset(&j->img, 0, sizeof j->img);
}

static void sweep_decoders(void)
{
    static const char *files[] = {"fixtures/images/c3_b4_i1_t1_split.png", "fixtures/images/c6_b16_i0_t0_fix.png",
                                  "fixtures/images/c0_b1_i0_t0_dyn.png", "fixtures/images/tiny_1x1_c3_b1_i1.png"};
    size_t f;
    for (f = 0; f < 4; f++) {
        decode_job j;
        sweep_job s;
        ls_image_info info;
        unsigned char *data;
        size_t n;
        REQUIRE(read_file(files[f], &data, &n) == LS_OK);
        REQUIRE(ls_image_decode_info(data, n, &info, NULL) == LS_OK);
        CHECK_EQ(info.arena_bytes, info.image_bytes + info.scratch_bytes);
        memset(&j, 0, sizeof j);
        j.data = data;
        j.n = n;
        s.name = files[f];
        s.run = run_decode;
        s.state_hash = hash_decode;
        s.reset = reset_decode;
        s.ctx = &j;
        s.answer = info.arena_bytes;
        s.exact = 1;
        s.quiet = 0;
        CHECK_EQ(sweep_arena(&s), 0);
        free(data);
    }
    {
        static const char pnm[] = "P6\n3 2\n255\nabcdefghijklmnopqr";
        decode_job j;
        sweep_job s;
        ls_image_info info;
        REQUIRE(ls_image_decode_info(pnm, sizeof pnm - 1, &info, NULL) == LS_OK);
        memset(&j, 0, sizeof j);
        j.data = (const unsigned char *)pnm;
        j.n = sizeof pnm - 1;
        s.name = "pnm";
        s.run = run_decode;
        s.state_hash = hash_decode;
        s.reset = reset_decode;
        s.ctx = &j;
        s.answer = info.arena_bytes;
        s.exact = 1;
        s.quiet = 0;
        CHECK_EQ(sweep_arena(&s), 0);
    }
}

typedef struct encode_job {
    ls_image img;
    ls_image_format f;
    ls_membuf m;
} encode_job;

static ls_status run_encode(void *ctx, ls_arena *a)
{
    encode_job *j = (encode_job *)ctx;
    return ls_image_encode(&j->img, &j->f, ls_membuf_write, &j->m, a);
}

static uint64_t hash_encode(void *ctx)
{
    encode_job *j = (encode_job *)ctx;
    return test_hash(&j->m.size, sizeof j->m.size, test_hash(j->img.pixels, 16u * j->img.width * j->img.height, TEST_HASH_SEED));
}

static void reset_encode(void *ctx)
{
    ((encode_job *)ctx)->m.size = 0;
}

static void sweep_encoders(void)
{
    static LS_ARENA_BUFFER(m, 4096);
    ls_arena a;
    encode_job j;
    sweep_job s;
    uint32_t t;
    ls_arena_init(&a, m.bytes, sizeof m.bytes);
    REQUIRE(ls_image_create(&j.img, 9, 7, &a) == LS_OK);
    fill_pattern(&j.img, 255.0f);
    for (t = 1; t <= 4; t++) { /* PNG, PNM, PFM, PNG_STORED */
        j.f.type = t;
        j.f.channels = 3;
        j.f.bits = t == 3 ? 32 : 16;
        j.f.big_endian = 0;
        j.m.data = outbuf;
        j.m.capacity = sizeof outbuf;
        j.m.size = 0;
        j.m.overflow = 0;
        REQUIRE(ls_image_encode_bytes(9, 7, &j.f, &s.answer) == LS_OK);
        s.name = "encode";
        s.run = run_encode;
        s.state_hash = hash_encode;
        s.reset = reset_encode;
        s.ctx = &j;
        s.exact = 1;
        s.quiet = 0;
        CHECK_EQ(sweep_arena(&s), 0);
    }
    /* a failing callback: LS_ERR_IO, arena restored */
    {
        ls_arena b = fresh_arena();
        ls_membuf small;
        small.data = outbuf;
        small.capacity = 100;
        small.size = 0;
        small.overflow = 0;
        j.f.type = LS_IMAGE_PNG_STORED;
        j.f.bits = 8;
        CHECK_STATUS(ls_image_encode(&j.img, &j.f, ls_membuf_write, &small, &b), LS_ERR_IO);
        CHECK_EQ(ls_arena_used(&b), 0);
        CHECK_EQ(small.overflow, 1);
        j.f.type = LS_IMAGE_PNG;
        small.capacity = 40;
        small.size = 0;
        small.overflow = 0;
        CHECK_STATUS(ls_image_encode(&j.img, &j.f, ls_membuf_write, &small, &b), LS_ERR_IO);
        CHECK_EQ(ls_arena_used(&b), 0);
        CHECK_EQ(small.overflow, 1);
        j.f.channels = 2;
        j.f.type = LS_IMAGE_PNM;
        CHECK_STATUS(ls_image_encode(&j.img, &j.f, ls_membuf_write, &small, &b), LS_ERR_INVALID);
    }
}

typedef struct inflate_job {
    const unsigned char *src;
    size_t n;
    unsigned char out[64];
} inflate_job;

static ls_status run_inflate(void *ctx, ls_arena *a)
{
    inflate_job *j = (inflate_job *)ctx;
    size_t got;
    return ls_inflate(j->src, j->n, j->out, sizeof j->out, &got, a, NULL);
}

static uint64_t hash_inflate(void *ctx)
{
    inflate_job *j = (inflate_job *)ctx;
    return test_hash(j->src, j->n, TEST_HASH_SEED);
}

static void sweep_inflate(void)
{
    unsigned char stream[256];
    dyn_opts o;
    inflate_job j;
    sweep_job s;
    memset(&o, 0, sizeof o);
    j.n = build_dynamic(&o, stream);
    j.src = stream;
    REQUIRE(ls_inflate_bytes(&s.answer) == LS_OK);
    s.name = "inflate";
    s.run = run_inflate;
    s.state_hash = hash_inflate;
    s.reset = NULL;
    s.ctx = &j;
    s.exact = 1;
    s.quiet = 0;
    CHECK_EQ(sweep_arena(&s), 0);
}

int main(void)
{
    TEST_INIT("test_image");
    TEST_RUN(checksum_known_values);
    TEST_RUN(unorm_rounding_rule);
    TEST_RUN(image_create_and_limits);
    TEST_RUN(unorm_pack_and_unpack);
    TEST_RUN(round_trip_every_format);
    TEST_RUN(png_bytes_match_reference);
    TEST_RUN(large_png_spans_blocks_and_chunks);
    TEST_RUN(png_deflate_round_trips);
    TEST_RUN(png_deflate_large_images);
    TEST_RUN(png_deflate_size_against_zlib);
    TEST_RUN(png_deflate_bytes_are_pinned);
    TEST_RUN(python_fixtures_decode_exactly);
    TEST_RUN(inflate_handcrafted_dynamic_block);
    TEST_RUN(inflate_rejects_malformed_streams);
    TEST_RUN(png_malformed_inputs);
    TEST_RUN(png_palette_errors);
    TEST_RUN(pnm_and_pfm_headers);
    TEST_RUN(png_mutations_never_crash);
    TEST_RUN(whole_file_mutations_never_crash);
    TEST_RUN(sweep_decoders);
    TEST_RUN(sweep_encoders);
    TEST_RUN(sweep_inflate);
    return TEST_END();
}
