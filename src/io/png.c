/* png.c - PNG encoding (deflate-compressed with adaptive row filters, or
 * stored deflate blocks) and decoding (all colour types and bit depths,
 * palettes, tRNS, the five filters, Adam7). */
#include <string.h>
#include "image_codec.h"

static const unsigned char png_signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

/* Adam7 passes: first column and row, column and row steps. */
static const uint8_t adam7_x0[7] = {0, 4, 0, 2, 0, 1, 0};
static const uint8_t adam7_y0[7] = {0, 0, 4, 0, 2, 0, 1};
static const uint8_t adam7_dx[7] = {8, 8, 4, 4, 2, 2, 1};
static const uint8_t adam7_dy[7] = {8, 8, 8, 4, 4, 2, 2};

/* Decoding tables: the palette as RGBA floats (256 entries), then q / maxval
 * for every sample value q of depths up to 8 bits. */
#define TABLE_FLOATS ((size_t)(256 * 4 + 256))

/* What a scan of the chunks found. */
typedef struct png_scan {
    uint32_t width, height, bits, color, interlace;
    uint32_t channels;   /* samples per pixel */
    size_t plte;         /* offset of the PLTE data, 0 if none */
    uint32_t plte_n;     /* palette entries */
    size_t trns;         /* offset of the tRNS data, 0 if none */
    uint32_t trns_len;
    size_t idat;         /* offset of the first IDAT chunk (its length field) */
    size_t raw_bytes;    /* filtered rows, all passes */
} png_scan;

/* A chunk type as its big-endian 32-bit value (no memcmp: the library calls
 * only memcpy, memset and memmove). */
#define CHUNK(a, b, c, d) (((uint32_t)(a) << 24) | ((uint32_t)(b) << 16) | ((uint32_t)(c) << 8) | (uint32_t)(d))
#define IHDR CHUNK('I', 'H', 'D', 'R')
#define PLTE CHUNK('P', 'L', 'T', 'E')
#define TRNS CHUNK('t', 'R', 'N', 'S')
#define IDAT CHUNK('I', 'D', 'A', 'T')
#define IEND CHUNK('I', 'E', 'N', 'D')

static uint32_t be32(const unsigned char *p)
{
    return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
}

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static int is_letter(unsigned char c)
{
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

static uint32_t color_channels(uint32_t color)
{
    switch (color) {
    case 0: return 1;
    case 2: return 3;
    case 3: return 1;
    case 4: return 2;
    case 6: return 4;
    default: return 0;
    }
}

static int depth_ok(uint32_t color, uint32_t bits)
{
    switch (color) {
    case 0: return bits == 1 || bits == 2 || bits == 4 || bits == 8 || bits == 16;
    case 3: return bits == 1 || bits == 2 || bits == 4 || bits == 8;
    case 2: case 4: case 6: return bits == 8 || bits == 16;
    default: return 0;
    }
}

/* Bytes of one filtered row of w pixels (filter byte not included). */
static size_t row_bytes(uint32_t w, uint32_t channels, uint32_t bits)
{
    return ((size_t)w * channels * bits + 7u) / 8u;
}

static uint32_t pass_size(uint32_t n, uint32_t start, uint32_t step)
{
    return n > start ? (n - start + step - 1u) / step : 0u;
}

#define FAIL(st_, what_, off_) return ls_image_fail_(diag, (st_), (what_), (int64_t)(off_))

static ls_status parse_ihdr(const unsigned char *d, size_t at, png_scan *s, ls_diag *diag)
{
    size_t total = 0, image;
    uint32_t pass;
    ls_status st;
    s->width = be32(d);
    s->height = be32(d + 4);
    s->bits = d[8];
    s->color = d[9];
    s->interlace = d[12];
    if (s->width == 0 || s->height == 0) FAIL(LS_ERR_PARSE, "PNG zero width or height", at);
    if (s->width > 0x7fffffffu || s->height > 0x7fffffffu)
        FAIL(LS_ERR_PARSE, "PNG width or height above 2^31 - 1", at);
    s->channels = color_channels(s->color);
    if (s->channels == 0) FAIL(LS_ERR_PARSE, "PNG invalid colour type", at + 9u);
    if (!depth_ok(s->color, s->bits)) FAIL(LS_ERR_PARSE, "PNG invalid bit depth for its colour type", at + 8u);
    if (d[10] != 0) FAIL(LS_ERR_PARSE, "PNG unknown compression method", at + 10u);
    if (d[11] != 0) FAIL(LS_ERR_PARSE, "PNG unknown filter method", at + 11u);
    if (s->interlace > 1u) FAIL(LS_ERR_PARSE, "PNG unknown interlace method", at + 12u);
    st = ls_image_bytes(s->width, s->height, &image);
    if (st != LS_OK) FAIL(st, "PNG image too large for this library", at);
    for (pass = 0; pass < (s->interlace ? 7u : 1u); pass++) {
        uint32_t pw = s->interlace ? pass_size(s->width, adam7_x0[pass], adam7_dx[pass]) : s->width;
        uint32_t ph = s->interlace ? pass_size(s->height, adam7_y0[pass], adam7_dy[pass]) : s->height;
        size_t rows;
        if (pw == 0 || ph == 0) continue;
        if (ls_size_mul(1u + row_bytes(pw, s->channels, s->bits), ph, &rows) != LS_OK ||
            ls_size_sum(total, rows, &total) != LS_OK)
            FAIL(LS_ERR_TOO_LARGE, "PNG image too large for this library", at);
    }
    s->raw_bytes = total;
    return LS_OK;
}

/* Walks every chunk: structure, CRCs, IHDR, PLTE, tRNS, IDAT order, IEND. */
static ls_status png_scan_chunks(const unsigned char *data, size_t bytes, png_scan *s, int check_crc,
                                 ls_diag *diag)
{
    size_t pos = 8;
    int seen_ihdr = 0, idat_state = 0; /* 0 none yet, 1 in the run, 2 after it */
    memset(s, 0, sizeof *s);
    for (;;) {
        uint32_t len, tv;
        const unsigned char *type, *body;
        if (bytes - pos < 12u) {
            if (bytes == pos) FAIL(LS_ERR_PARSE, "PNG file ends without IEND", pos);
            FAIL(LS_ERR_PARSE, "PNG chunk header truncated", pos);
        }
        len = be32(data + pos);
        type = data + pos + 4;
        body = data + pos + 8;
        if (len > 0x7fffffffu) FAIL(LS_ERR_PARSE, "PNG chunk length above 2^31 - 1", pos);
        if (len > bytes - pos - 12u) FAIL(LS_ERR_PARSE, "PNG chunk truncated", pos);
        if (!is_letter(type[0]) || !is_letter(type[1]) || !is_letter(type[2]) || !is_letter(type[3]))
            FAIL(LS_ERR_PARSE, "PNG chunk type is not four letters", pos + 4u);
        if (check_crc && ls_crc32(0, type, (size_t)len + 4u) != be32(body + len))
            FAIL(LS_ERR_PARSE, "PNG CRC mismatch", pos + 8u + len);
        tv = be32(type);
        if (!seen_ihdr && tv != IHDR) FAIL(LS_ERR_PARSE, "PNG does not start with IHDR", pos);
        if (idat_state == 1 && tv != IDAT) idat_state = 2;
        if (tv == IHDR) {
            ls_status st;
            if (seen_ihdr) FAIL(LS_ERR_PARSE, "PNG has two IHDR chunks", pos);
            if (len != 13u) FAIL(LS_ERR_PARSE, "PNG IHDR length is not 13", pos);
            st = parse_ihdr(body, pos + 8u, s, diag);
            if (st != LS_OK) return st;
            seen_ihdr = 1;
        } else if (tv == PLTE) {
            if (idat_state != 0) FAIL(LS_ERR_PARSE, "PNG PLTE after IDAT", pos);
            if (s->plte != 0) FAIL(LS_ERR_PARSE, "PNG has two PLTE chunks", pos);
            if (s->trns != 0) FAIL(LS_ERR_PARSE, "PNG PLTE after tRNS", pos);
            if (s->color == 0 || s->color == 4) FAIL(LS_ERR_PARSE, "PNG PLTE in a greyscale image", pos);
            if (len == 0 || len > 768u || len % 3u != 0)
                FAIL(LS_ERR_PARSE, "PNG PLTE length is not 3 to 768 and a multiple of 3", pos);
            s->plte = pos + 8u;
            s->plte_n = len / 3u;
        } else if (tv == TRNS) {
            if (idat_state != 0) FAIL(LS_ERR_PARSE, "PNG tRNS after IDAT", pos);
            if (s->trns != 0) FAIL(LS_ERR_PARSE, "PNG has two tRNS chunks", pos);
            if (s->color == 4 || s->color == 6) FAIL(LS_ERR_PARSE, "PNG tRNS in an image with alpha", pos);
            if (s->color == 3 && s->plte == 0) FAIL(LS_ERR_PARSE, "PNG tRNS before PLTE", pos);
            if ((s->color == 0 && len != 2u) || (s->color == 2 && len != 6u) ||
                (s->color == 3 && len > s->plte_n))
                FAIL(LS_ERR_PARSE, "PNG tRNS length does not fit the colour type", pos);
            s->trns = pos + 8u;
            s->trns_len = len;
        } else if (tv == IDAT) {
            if (idat_state == 2) FAIL(LS_ERR_PARSE, "PNG IDAT chunks are not consecutive", pos);
            if (idat_state == 0) {
                if (s->color == 3 && s->plte == 0) FAIL(LS_ERR_PARSE, "PNG indexed image without PLTE", pos);
                s->idat = pos;
            }
            idat_state = 1;
        } else if (tv == IEND) {
            if (len != 0) FAIL(LS_ERR_PARSE, "PNG IEND is not empty", pos);
            if (idat_state == 0) FAIL(LS_ERR_PARSE, "PNG has no IDAT chunk", pos);
            pos += 12u;
            if (pos != bytes) FAIL(LS_ERR_PARSE, "bytes after PNG IEND", pos);
            return LS_OK;
        } else if ((type[0] & 0x20u) == 0) {
            FAIL(LS_ERR_UNSUPPORTED, "PNG unknown critical chunk", pos + 4u);
        }
        pos += 12u + (size_t)len;
    }
}

static void scan_sizes(const png_scan *s, size_t *scratch)
{
    ls_size size;
    ls_size_init(&size);
    ls_size_add(&size, s->raw_bytes, 1);
    ls_size_add(&size, ls_inflate_state_bytes_(), 1);
    ls_size_add(&size, TABLE_FLOATS, sizeof(float));
    (void)ls_size_get(&size, scratch);
}

ls_status ls_png_info_(const unsigned char *data, size_t bytes, ls_image_info *info, ls_diag *diag)
{
    png_scan s;
    ls_status st = png_scan_chunks(data, bytes, &s, 1, diag);
    size_t image;
    if (st != LS_OK) return st;
    info->format.type = LS_IMAGE_PNG;
    info->format.channels = s.channels;
    info->format.bits = s.bits;
    info->width = s.width;
    info->height = s.height;
    info->palette = s.color == 3u;
    info->transparency = s.trns != 0;
    info->interlaced = s.interlace;
    info->maxval = (1u << s.bits) - 1u;
    (void)ls_image_bytes(s.width, s.height, &image);
    info->image_bytes = image;
    scan_sizes(&s, &info->scratch_bytes);
    if (ls_size_sum(image, info->scratch_bytes, &info->arena_bytes) != LS_OK)
        FAIL(LS_ERR_TOO_LARGE, "PNG image too large for this library", 16);
    return LS_OK;
}

static uint32_t paeth(uint32_t a, uint32_t b, uint32_t c)
{
    int32_t p = (int32_t)a + (int32_t)b - (int32_t)c;
    int32_t pa = p > (int32_t)a ? p - (int32_t)a : (int32_t)a - p;
    int32_t pb = p > (int32_t)b ? p - (int32_t)b : (int32_t)b - p;
    int32_t pc = p > (int32_t)c ? p - (int32_t)c : (int32_t)c - p;
    if (pa <= pb && pa <= pc) return a;
    return pb <= pc ? b : c;
}

/* Undoes the filter of one row in place; prev is the unfiltered row above
 * (NULL for the first row of a pass). Returns 0 for an unknown filter type. */
static int unfilter(unsigned char *row, const unsigned char *prev, size_t n, uint32_t filter, size_t bpp)
{
    size_t i;
    switch (filter) {
    case 0:
        return 1;
    case 1:
        for (i = bpp; i < n; i++) row[i] = (unsigned char)(row[i] + row[i - bpp]);
        return 1;
    case 2:
        if (prev != NULL)
            for (i = 0; i < n; i++) row[i] = (unsigned char)(row[i] + prev[i]);
        return 1;
    case 3:
        for (i = 0; i < n; i++) {
            uint32_t left = i >= bpp ? row[i - bpp] : 0u, up = prev != NULL ? prev[i] : 0u;
            row[i] = (unsigned char)(row[i] + ((left + up) >> 1));
        }
        return 1;
    case 4:
        for (i = 0; i < n; i++) {
            uint32_t left = i >= bpp ? row[i - bpp] : 0u, up = prev != NULL ? prev[i] : 0u;
            uint32_t ul = (i >= bpp && prev != NULL) ? prev[i - bpp] : 0u;
            row[i] = (unsigned char)(row[i] + paeth(left, up, ul));
        }
        return 1;
    default:
        return 0;
    }
}

static uint32_t sample_at(const unsigned char *row, size_t k, uint32_t bits)
{
    if (bits == 8u) return row[k];
    if (bits == 16u) return ((uint32_t)row[2u * k] << 8) | row[2u * k + 1u];
    {
        size_t bit = k * bits;
        uint32_t shift = 8u - bits - (uint32_t)(bit & 7u);
        return ((uint32_t)row[bit >> 3] >> shift) & ((1u << bits) - 1u);
    }
}

typedef struct png_expand {
    const png_scan *s;
    const float *pal;  /* RGBA floats, 256 entries */
    const float *lut;  /* q / maxval for q <= 255 (depths up to 8) */
    float m;           /* maxval as a float (16-bit samples are divided) */
    uint32_t key[3];   /* tRNS colour key (grey or RGB) */
    uint32_t has_key;
} png_expand;

static float unit(const png_expand *e, uint32_t q)
{
    return e->s->bits <= 8u ? e->lut[q] : (float)q / e->m;
}

/* Converts one unfiltered row of pw pixels to floats at out, out_step floats
 * apart. Returns the x of a palette index out of range, or -1. */
static int64_t expand_row(const png_expand *e, const unsigned char *row, uint32_t pw, float *out,
                          size_t out_step)
{
    const png_scan *s = e->s;
    uint32_t x;
    if (s->color == 3u) {
        for (x = 0; x < pw; x++, out += out_step) {
            uint32_t idx = sample_at(row, x, s->bits);
            if (idx >= s->plte_n) return (int64_t)x;
            memcpy(out, e->pal + (size_t)idx * 4u, 4u * sizeof(float));
        }
    } else if (s->channels <= 2u) {
        for (x = 0; x < pw; x++, out += out_step) {
            size_t k = (size_t)x * s->channels;
            uint32_t g = sample_at(row, k, s->bits);
            out[0] = out[1] = out[2] = unit(e, g);
            if (s->channels == 2u)
                out[3] = unit(e, sample_at(row, k + 1u, s->bits));
            else
                out[3] = (e->has_key && g == e->key[0]) ? 0.0f : 1.0f;
        }
    } else if (s->bits == 8u) {
        const unsigned char *p = row;
        for (x = 0; x < pw; x++, out += out_step, p += s->channels) {
            out[0] = e->lut[p[0]];
            out[1] = e->lut[p[1]];
            out[2] = e->lut[p[2]];
            if (s->channels == 4u)
                out[3] = e->lut[p[3]];
            else
                out[3] = (e->has_key && p[0] == e->key[0] && p[1] == e->key[1] && p[2] == e->key[2]) ? 0.0f : 1.0f;
        }
    } else {
        for (x = 0; x < pw; x++, out += out_step) {
            size_t k = (size_t)x * s->channels;
            uint32_t r = sample_at(row, k, 16), g = sample_at(row, k + 1u, 16), b = sample_at(row, k + 2u, 16);
            out[0] = (float)r / 65535.0f;
            out[1] = (float)g / 65535.0f;
            out[2] = (float)b / 65535.0f;
            if (s->channels == 4u)
                out[3] = (float)sample_at(row, k + 3u, 16) / 65535.0f;
            else
                out[3] = (e->has_key && r == e->key[0] && g == e->key[1] && b == e->key[2]) ? 0.0f : 1.0f;
        }
    }
    return -1;
}

static void build_tables(const png_scan *s, const unsigned char *data, float *tables, png_expand *e)
{
    float *pal = tables, *lut = tables + (size_t)256 * 4u;
    uint32_t i, maxval = (1u << s->bits) - 1u;
    for (i = 0; i < 256u; i++) lut[i] = i <= maxval ? ls_image_unorm_to_float_(i, maxval) : 0.0f;
    for (i = 0; i < 256u * 4u; i++) pal[i] = 1.0f;
    for (i = 0; i < s->plte_n; i++) {
        const unsigned char *rgb = data + s->plte + (size_t)i * 3u;
        float *q = pal + (size_t)i * 4u;
        q[0] = (float)rgb[0] / 255.0f;
        q[1] = (float)rgb[1] / 255.0f;
        q[2] = (float)rgb[2] / 255.0f;
    }
    e->pal = pal;
    e->lut = lut;
    e->m = (float)maxval;
    e->has_key = 0;
    if (s->trns != 0) {
        const unsigned char *t = data + s->trns;
        if (s->color == 3u) {
            for (i = 0; i < s->trns_len; i++) pal[(size_t)i * 4u + 3u] = (float)t[i] / 255.0f;
        } else {
            uint32_t n = s->color == 0u ? 1u : 3u, k;
            e->has_key = 1;
            for (k = 0; k < n; k++) e->key[k] = ((uint32_t)t[(size_t)k * 2u] << 8) | t[(size_t)k * 2u + 1u];
        }
    }
}

ls_status ls_png_decode_(const unsigned char *data, size_t bytes, const ls_image_info *info,
                         ls_image *image, ls_arena *arena, ls_diag *diag)
{
    png_scan s;
    png_expand e;
    ls_inflate_input in;
    unsigned char *raw;
    float *tables;
    void *state;
    size_t at = 0;
    uint32_t pass;
    /* ls_image_decode_info has just checked the CRCs of this buffer */
    ls_status st = png_scan_chunks(data, bytes, &s, 0, diag);
    (void)info;
    if (st != LS_OK) return st;
    raw = (unsigned char *)ls_arena_scratch(arena, s.raw_bytes, 1);
    state = raw != NULL ? ls_arena_scratch(arena, ls_inflate_state_bytes_(), 1) : NULL;
    tables = state != NULL ? (float *)ls_arena_scratch(arena, TABLE_FLOATS, sizeof(float)) : NULL;
    if (tables == NULL) return ls_image_fail_(diag, LS_ERR_NOMEM, "arena too small for PNG decoding", -1);
    in.file = data;
    in.file_bytes = bytes;
    in.pos = s.idat + 8u;
    in.end = in.pos + be32(data + s.idat);
    in.png_idat = 1;
    in.zlib = 1;
    in.dst = raw;
    in.cap = s.raw_bytes;
    in.produced = 0;
    st = ls_inflate_run_(&in, state, diag);
    if (st == LS_ERR_TOO_LARGE) {
        if (diag != NULL) {
            diag->status = LS_ERR_PARSE;
            diag->what = "PNG zlib stream holds more data than the image";
        }
        return LS_ERR_PARSE;
    }
    if (st != LS_OK) return st;
    if (in.produced != s.raw_bytes)
        return ls_image_fail_(diag, LS_ERR_PARSE, "PNG image data ends early", (int64_t)s.idat);
    e.s = &s;
    build_tables(&s, data, tables, &e);
    for (pass = 0; pass < (s.interlace ? 7u : 1u); pass++) {
        uint32_t x0 = s.interlace ? adam7_x0[pass] : 0u, y0 = s.interlace ? adam7_y0[pass] : 0u;
        uint32_t dx = s.interlace ? adam7_dx[pass] : 1u, dy = s.interlace ? adam7_dy[pass] : 1u;
        uint32_t pw = pass_size(s.width, x0, dx), ph = pass_size(s.height, y0, dy), r;
        size_t n = row_bytes(pw, s.channels, s.bits);
        size_t bpp = (s.channels * s.bits + 7u) / 8u;
        const unsigned char *prev = NULL;
        if (pw == 0 || ph == 0) continue;
        for (r = 0; r < ph; r++) {
            unsigned char *row = raw + at + 1u;
            uint32_t y = y0 + r * dy;
            int64_t badx;
            if (!unfilter(row, prev, n, raw[at], bpp)) {
                ls_image_fail_(diag, LS_ERR_PARSE, "PNG filter type above 4", -1);
                if (diag != NULL) {
                    diag->has_index = 1;
                    diag->index = y;
                    diag->has_value = 1;
                    diag->value = (ls_real)raw[at];
                }
                return LS_ERR_PARSE;
            }
            badx = expand_row(&e, row, pw, image->pixels + ((size_t)y * s.width + x0) * 4u, (size_t)dx * 4u);
            if (badx >= 0) {
                ls_image_fail_(diag, LS_ERR_PARSE, "PNG palette index out of range", -1);
                if (diag != NULL) {
                    diag->has_index = 1;
                    diag->index = (uint64_t)y * s.width + x0 + (uint64_t)badx * dx;
                }
                return LS_ERR_PARSE;
            }
            prev = row;
            at += 1u + n;
        }
    }
    return LS_OK;
}

/* --- encoding ------------------------------------------------------------ */

#define IDAT_MAX 65536u
#define STORED_MAX 65535u
#define IDAT_BUF 16384u /* compressed: IDAT chunks of this many bytes, the last one shorter */
#define SEG_PX 256u     /* pixels converted at a time while filtering */
#define PNG_LEVEL 6u    /* the compressor's effort (zlib's default level) */

/* Sizes of an encoded PNG: image bytes, zlib stream, IDAT chunks. */
typedef struct png_layout {
    size_t raw;
    size_t zlib;
    size_t chunks;
} png_layout;

static ls_status encoded_parts(uint32_t width, uint32_t height, const ls_image_format *f, png_layout *l)
{
    size_t blocks, t;
    if (ls_size_mul(1u + row_bytes(width, f->channels, f->bits), height, &l->raw) != LS_OK)
        return LS_ERR_TOO_LARGE;
    blocks = l->raw / STORED_MAX + (l->raw % STORED_MAX != 0);
    if (blocks == 0) blocks = 1;
    if (ls_size_mul(blocks, 5u, &t) != LS_OK || ls_size_sum(t, l->raw, &t) != LS_OK ||
        ls_size_sum(t, 6u, &l->zlib) != LS_OK)
        return LS_ERR_TOO_LARGE;
    l->chunks = l->zlib / IDAT_MAX + (l->zlib % IDAT_MAX != 0);
    return LS_OK;
}

ls_status ls_png_encoded_size_(uint32_t width, uint32_t height, const ls_image_format *format,
                               size_t *file_bytes)
{
    png_layout l;
    size_t t;
    if (encoded_parts(width, height, format, &l) != LS_OK) return LS_ERR_TOO_LARGE;
    if (format->type == LS_IMAGE_PNG) { /* the compressor's bound, zlib header and Adler-32 */
        if (ls_deflate_bound_(l.raw, &l.zlib) != LS_OK || ls_size_sum(l.zlib, 6u, &l.zlib) != LS_OK)
            return LS_ERR_TOO_LARGE;
        l.chunks = l.zlib / IDAT_BUF + (l.zlib % IDAT_BUF != 0);
    }
    if (ls_size_mul(l.chunks, 12u, &t) != LS_OK || ls_size_sum(t, l.zlib, &t) != LS_OK ||
        ls_size_sum(t, 8u + 25u + 12u, file_bytes) != LS_OK)
        return LS_ERR_TOO_LARGE;
    return LS_OK;
}

typedef struct png_writer {
    ls_image_sink *sink;
    uint32_t crc;        /* of the open IDAT chunk */
    size_t chunk_left;   /* bytes left in the open IDAT chunk */
    size_t zlib_left;    /* zlib bytes not yet written */
    size_t block_left;   /* raw bytes left in the open stored block */
    size_t raw_left;     /* raw bytes not yet written */
    uint32_t adler;
    uint32_t open;       /* an IDAT chunk is open */
} png_writer;

/* Stored blocks (LS_IMAGE_PNG_STORED): no row filter, the file's layout
 * known from the image size alone. */
static void write_chunk(ls_image_sink *sink, const char *type, const unsigned char *body, uint32_t len)
{
    unsigned char b[4];
    uint32_t crc = ls_crc32(ls_crc32(0, type, 4), body, len);
    put_be32(b, len);
    ls_image_sink_put_(sink, b, 4);
    ls_image_sink_put_(sink, type, 4);
    ls_image_sink_put_(sink, body, len);
    put_be32(b, crc);
    ls_image_sink_put_(sink, b, 4);
}

static void close_idat(png_writer *w)
{
    unsigned char b[4];
    if (!w->open) return;
    put_be32(b, w->crc);
    ls_image_sink_put_(w->sink, b, 4);
    w->open = 0;
}

/* zlib-stream bytes into IDAT chunks of at most IDAT_MAX bytes. */
static void zlib_put(png_writer *w, const unsigned char *p, size_t n)
{
    while (n > 0) {
        size_t m;
        if (w->chunk_left == 0) {
            unsigned char b[8];
            close_idat(w);
            w->chunk_left = w->zlib_left < IDAT_MAX ? w->zlib_left : IDAT_MAX;
            put_be32(b, (uint32_t)w->chunk_left);
            b[4] = 'I';
            b[5] = 'D';
            b[6] = 'A';
            b[7] = 'T';
            ls_image_sink_put_(w->sink, b, 8);
            w->crc = ls_crc32(0, "IDAT", 4);
            w->open = 1;
        }
        m = n < w->chunk_left ? n : w->chunk_left;
        w->crc = ls_crc32(w->crc, p, m);
        ls_image_sink_put_(w->sink, p, m);
        w->chunk_left -= m;
        w->zlib_left -= m;
        p += m;
        n -= m;
    }
}

/* Image bytes into stored blocks of at most STORED_MAX bytes. */
static void raw_put(png_writer *w, const unsigned char *p, size_t n)
{
    w->adler = ls_adler32(w->adler, p, n);
    while (n > 0) {
        size_t m;
        if (w->block_left == 0) {
            unsigned char h[5];
            size_t len = w->raw_left < STORED_MAX ? w->raw_left : STORED_MAX;
            h[0] = w->raw_left <= STORED_MAX ? 1u : 0u; /* BFINAL when this block is the last; BTYPE 00 */
            h[1] = (unsigned char)len;
            h[2] = (unsigned char)(len >> 8);
            h[3] = (unsigned char)~len;
            h[4] = (unsigned char)(~len >> 8);
            zlib_put(w, h, 5);
            w->block_left = len;
        }
        m = n < w->block_left ? n : w->block_left;
        zlib_put(w, p, m);
        w->block_left -= m;
        w->raw_left -= m;
        p += m;
        n -= m;
    }
}

/* The signature and the IHDR chunk (both writers). */
static void write_header(const ls_image *image, const ls_image_format *f, ls_image_sink *sink)
{
    static const uint8_t color_of[5] = {0, 0, 4, 2, 6};
    unsigned char ihdr[13];
    ls_image_sink_put_(sink, png_signature, 8);
    put_be32(ihdr, image->width);
    put_be32(ihdr + 4, image->height);
    ihdr[8] = (unsigned char)f->bits;
    ihdr[9] = color_of[f->channels];
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    write_chunk(sink, "IHDR", ihdr, 13);
}

static void encode_stored(const ls_image *image, const ls_image_format *f, ls_image_sink *sink)
{
    unsigned char buf[512], zhead[2] = {0x78, 0x01};
    png_writer w;
    png_layout l;
    size_t len = 0;
    uint32_t x, y, k, bytes_per = f->bits / 8u;
    (void)encoded_parts(image->width, image->height, f, &l);
    write_header(image, f, sink);
    w.sink = sink;
    w.crc = 0;
    w.chunk_left = 0;
    w.zlib_left = l.zlib;
    w.block_left = 0;
    w.raw_left = l.raw;
    w.adler = 1;
    w.open = 0;
    zlib_put(&w, zhead, 2);
    for (y = 0; y < image->height && sink->status == LS_OK; y++) {
        const float *px = image->pixels + 4u * (size_t)y * image->width;
        buf[len++] = 0; /* filter type None */
        for (x = 0; x < image->width; x++, px += 4) {
            for (k = 0; k < f->channels; k++) {
                float v = px[f->channels == 2u && k == 1u ? 3u : k];
                if (bytes_per == 1u) {
                    buf[len++] = (unsigned char)ls_image_unorm_(v, 255.0f);
                } else {
                    uint32_t q = ls_image_unorm_(v, 65535.0f);
                    buf[len++] = (unsigned char)(q >> 8);
                    buf[len++] = (unsigned char)q;
                }
            }
            if (len > sizeof buf - 8u) {
                raw_put(&w, buf, len);
                len = 0;
            }
        }
        if (len > 0) {
            raw_put(&w, buf, len);
            len = 0;
        }
    }
    {
        unsigned char b[4];
        put_be32(b, w.adler);
        zlib_put(&w, b, 4);
    }
    close_idat(&w);
    write_chunk(sink, "IEND", NULL, 0);
}

/* Compressed (LS_IMAGE_PNG): each row gets the filter whose bytes have the
 * smallest sum of magnitudes (as signed bytes), the heuristic of libpng; the
 * rows go through the deflate encoder into IDAT chunks of IDAT_BUF bytes. */
typedef struct png_scratch {
    unsigned char idat[IDAT_BUF];
    unsigned char cur[(SEG_PX + 1u) * 8u]; /* the pixel on the left, then SEG_PX pixels */
    unsigned char up[(SEG_PX + 1u) * 8u];  /* the same of the row above */
    unsigned char filtered[SEG_PX * 8u];
} png_scratch;

#define DEFLATE_AT LS_ARENA_ROUND(sizeof(png_scratch))

size_t ls_png_encode_scratch_(const ls_image_format *format)
{
    return format->type == LS_IMAGE_PNG ? DEFLATE_AT + LS_ARENA_ROUND(ls_deflate_state_bytes_()) : 0u;
}

typedef struct png_idat {
    ls_image_sink *sink;
    unsigned char *buf;
    size_t n;
} png_idat;

static void idat_flush(png_idat *z)
{
    if (z->n > 0) write_chunk(z->sink, "IDAT", z->buf, (uint32_t)z->n);
    z->n = 0;
}

static void idat_put(void *ctx, const unsigned char *p, size_t n)
{
    png_idat *z = (png_idat *)ctx;
    while (n > 0) {
        size_t m = IDAT_BUF - z->n;
        if (m > n) m = n;
        memcpy(z->buf + z->n, p, m);
        z->n += m;
        p += m;
        n -= m;
        if (z->n == IDAT_BUF) idat_flush(z);
    }
}

/* The file's bytes of pixels [x0 - 1, x0 + n) of row y at dst (zeros for
 * the pixel left of the row); bpp bytes per pixel. */
static void load_pixels(const ls_image *image, const ls_image_format *f, uint32_t y, uint32_t x0, uint32_t n,
                        unsigned char *dst)
{
    const float *px;
    uint32_t x, k, bytes_per = f->bits / 8u;
    if (x0 == 0) {
        memset(dst, 0, (size_t)f->channels * bytes_per);
        dst += (size_t)f->channels * bytes_per;
        x0 = 1;
        n--;
    }
    px = image->pixels + 4u * ((size_t)y * image->width + x0 - 1u);
    for (x = 0; x <= n; x++, px += 4) {
        for (k = 0; k < f->channels; k++) {
            float v = px[f->channels == 2u && k == 1u ? 3u : k];
            if (bytes_per == 1u) {
                *dst++ = (unsigned char)ls_image_unorm_(v, 255.0f);
            } else {
                uint32_t q = ls_image_unorm_(v, 65535.0f);
                *dst++ = (unsigned char)(q >> 8);
                *dst++ = (unsigned char)q;
            }
        }
    }
}

/* Loads the segment [x0, x0 + n) of row y and of the row above. */
static void load_segment(const ls_image *image, const ls_image_format *f, uint32_t y, uint32_t x0, uint32_t n,
                         png_scratch *ps, size_t bpp)
{
    load_pixels(image, f, y, x0, n, ps->cur);
    if (y > 0)
        load_pixels(image, f, y - 1u, x0, n, ps->up);
    else
        memset(ps->up, 0, (size_t)(n + 1u) * bpp);
}

/* Filter type t of byte i of the segment (cur and up start one pixel left). */
static unsigned char filter_byte(const png_scratch *ps, size_t i, size_t bpp, uint32_t t)
{
    uint32_t x = ps->cur[i + bpp], a = ps->cur[i], b = ps->up[i + bpp], c = ps->up[i];
    switch (t) {
    case 0: return (unsigned char)x;
    case 1: return (unsigned char)(x - a);
    case 2: return (unsigned char)(x - b);
    case 3: return (unsigned char)(x - ((a + b) >> 1));
    default: return (unsigned char)(x - paeth(a, b, c));
    }
}

static void encode_deflate(const ls_image *image, const ls_image_format *f, ls_image_sink *sink, void *scratch)
{
    static const unsigned char zhead[2] = {0x78, 0x9c}; /* 32 KiB window, default level */
    png_scratch *ps = (png_scratch *)scratch;
    void *state = (unsigned char *)scratch + DEFLATE_AT;
    unsigned char b[4];
    png_idat z;
    uint32_t y, adler = 1;
    size_t bpp = (size_t)f->channels * (f->bits / 8u);
    write_header(image, f, sink);
    z.sink = sink;
    z.buf = ps->idat;
    z.n = 0;
    idat_put(&z, zhead, 2);
    ls_deflate_begin_(state, PNG_LEVEL, idat_put, &z);
    for (y = 0; y < image->height && sink->status == LS_OK; y++) {
        uint32_t cost[5] = {0, 0, 0, 0, 0}, x0, t, best = 0;
        unsigned char ft;
        for (x0 = 0; x0 < image->width; x0 += SEG_PX) {
            uint32_t n = image->width - x0 < SEG_PX ? image->width - x0 : SEG_PX;
            size_t i;
            load_segment(image, f, y, x0, n, ps, bpp);
            for (i = 0; i < (size_t)n * bpp; i++)
                for (t = 0; t < 5u; t++) {
                    uint32_t v = filter_byte(ps, i, bpp, t);
                    cost[t] += v < 128u ? v : 256u - v;
                }
        }
        for (t = 1; t < 5u; t++)
            if (cost[t] < cost[best]) best = t;
        ft = (unsigned char)best;
        adler = ls_adler32(adler, &ft, 1);
        ls_deflate_put_(state, &ft, 1);
        for (x0 = 0; x0 < image->width; x0 += SEG_PX) {
            uint32_t n = image->width - x0 < SEG_PX ? image->width - x0 : SEG_PX;
            size_t i;
            load_segment(image, f, y, x0, n, ps, bpp);
            for (i = 0; i < (size_t)n * bpp; i++) ps->filtered[i] = filter_byte(ps, i, bpp, best);
            adler = ls_adler32(adler, ps->filtered, (size_t)n * bpp);
            ls_deflate_put_(state, ps->filtered, (size_t)n * bpp);
        }
    }
    ls_deflate_end_(state);
    put_be32(b, adler);
    idat_put(&z, b, 4);
    idat_flush(&z);
    write_chunk(sink, "IEND", NULL, 0);
}

void ls_png_encode_(const ls_image *image, const ls_image_format *f, ls_image_sink *sink, void *scratch)
{
    if (f->type == LS_IMAGE_PNG)
        encode_deflate(image, f, sink, scratch);
    else
        encode_stored(image, f, sink);
}
