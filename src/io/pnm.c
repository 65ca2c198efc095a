/* pnm.c - binary PGM/PPM (P5, P6) and PFM ("Pf", "PF") in and out. */
#include <string.h>
#include "image_codec.h"

#define FAIL(st_, what_, off_) return ls_image_fail_(diag, (st_), (what_), (int64_t)(off_))

static int is_space(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Skips whitespace and '#' comments (to the end of their line). */
static size_t skip_space(const unsigned char *d, size_t n, size_t pos)
{
    while (pos < n) {
        if (is_space(d[pos])) {
            pos++;
        } else if (d[pos] == '#') {
            while (pos < n && d[pos] != '\n' && d[pos] != '\r') pos++;
        } else {
            break;
        }
    }
    return pos;
}

/* An unsigned decimal header field; values above 2^32 - 1 saturate. Returns
 * 0 when no digit is there. */
static int parse_uint(const unsigned char *d, size_t n, size_t *pos, uint32_t *value)
{
    size_t p = skip_space(d, n, *pos);
    uint64_t v = 0;
    size_t start = p;
    while (p < n && d[p] >= '0' && d[p] <= '9') {
        v = v * 10u + (uint64_t)(d[p] - '0');
        if (v > 0xffffffffu) v = 0x100000000u;
        p++;
    }
    if (p == start) {
        *pos = p;
        return 0;
    }
    *value = v > 0xffffffffu ? 0xffffffffu : (uint32_t)v;
    *pos = p;
    return 1;
}

/* The PFM scale: [+-] digits [. digits] [(e|E) [+-] digits]; only its sign
 * is used (negative: little-endian samples). */
static int parse_scale(const unsigned char *d, size_t n, size_t *pos, uint32_t *negative)
{
    size_t p = skip_space(d, n, *pos), digits = 0;
    *negative = 0;
    if (p < n && (d[p] == '+' || d[p] == '-')) *negative = d[p++] == '-';
    while (p < n && d[p] >= '0' && d[p] <= '9') p++, digits++;
    if (p < n && d[p] == '.') {
        p++;
        while (p < n && d[p] >= '0' && d[p] <= '9') p++, digits++;
    }
    if (digits == 0) {
        *pos = p;
        return 0;
    }
    if (p < n && (d[p] == 'e' || d[p] == 'E')) {
        size_t e = 0;
        p++;
        if (p < n && (d[p] == '+' || d[p] == '-')) p++;
        while (p < n && d[p] >= '0' && d[p] <= '9') p++, e++;
        if (e == 0) {
            *pos = p;
            return 0;
        }
    }
    *pos = p;
    return 1;
}

static ls_status check_size(uint32_t w, uint32_t h, size_t at, ls_diag *diag)
{
    size_t bytes;
    ls_status st;
    if (w == 0 || h == 0) FAIL(LS_ERR_PARSE, "PNM/PFM zero width or height", at);
    st = ls_image_bytes(w, h, &bytes);
    if (st != LS_OK) FAIL(st, "PNM/PFM image too large for this library", at);
    return LS_OK;
}

ls_status ls_pnm_info_(const unsigned char *d, size_t n, ls_image_info *info, ls_diag *diag)
{
    size_t pos = 2, at, need;
    uint32_t w = 0, h = 0, maxval = 0, channels, sample_bytes, pfm = d[1] == 'F' || d[1] == 'f';
    ls_status st;
    if (d[1] == '1' || d[1] == '2' || d[1] == '3' || d[1] == '4')
        FAIL(LS_ERR_UNSUPPORTED, "ASCII or bitmap PNM (P1 to P4) not supported", 0);
    if (d[1] == '7') FAIL(LS_ERR_UNSUPPORTED, "PAM (P7) not supported", 0);
    channels = (d[1] == '5' || d[1] == 'f') ? 1u : 3u;
    if (n < 3u || !is_space(d[2])) FAIL(LS_ERR_PARSE, "PNM/PFM magic not followed by whitespace", 2);
    at = skip_space(d, n, pos);
    if (!parse_uint(d, n, &pos, &w)) FAIL(LS_ERR_PARSE, "PNM/PFM width missing", pos);
    if (!parse_uint(d, n, &pos, &h)) FAIL(LS_ERR_PARSE, "PNM/PFM height missing", pos);
    st = check_size(w, h, at, diag);
    if (st != LS_OK) return st;
    if (pfm) {
        uint32_t negative;
        if (!parse_scale(d, n, &pos, &negative)) FAIL(LS_ERR_PARSE, "PFM scale missing or malformed", pos);
        info->format.type = LS_IMAGE_PFM;
        info->format.bits = 32;
        info->format.big_endian = !negative;
        sample_bytes = 4;
    } else {
        at = skip_space(d, n, pos);
        if (!parse_uint(d, n, &pos, &maxval)) FAIL(LS_ERR_PARSE, "PNM maxval missing", pos);
        if (maxval == 0 || maxval > 65535u) FAIL(LS_ERR_PARSE, "PNM maxval outside 1..65535", at);
        info->format.type = LS_IMAGE_PNM;
        info->format.bits = maxval < 256u ? 8u : 16u;
        sample_bytes = maxval < 256u ? 1u : 2u;
    }
    if (pos >= n || !is_space(d[pos])) FAIL(LS_ERR_PARSE, "PNM/PFM header not ended by one whitespace", pos);
    pos++;
    need = (size_t)w * h * channels * sample_bytes; /* below 2^28 * 12, checked by ls_image_bytes */
    if (n - pos < need) FAIL(LS_ERR_PARSE, "PNM/PFM pixel data truncated", n);
    if (n - pos > need) FAIL(LS_ERR_PARSE, "bytes after the PNM/PFM pixel data", pos + need);
    info->format.channels = channels;
    info->width = w;
    info->height = h;
    info->maxval = maxval;
    (void)ls_image_bytes(w, h, &info->image_bytes);
    info->scratch_bytes = 0;
    info->arena_bytes = info->image_bytes;
    return LS_OK;
}

ls_status ls_pnm_decode_(const unsigned char *d, size_t n, const ls_image_info *info, ls_image *image,
                         ls_diag *diag)
{
    uint32_t c = info->format.channels, w = info->width, h = info->height, x, y, k;
    uint32_t sb = info->format.type == LS_IMAGE_PFM ? 4u : (info->format.bits / 8u);
    /* the header was validated: the samples are the last `need` bytes */
    size_t need = (size_t)w * h * c * sb;
    const unsigned char *p = d + (n - need);
    for (y = 0; y < h; y++) {
        /* PFM stores the bottom row first */
        uint32_t iy = info->format.type == LS_IMAGE_PFM ? h - 1u - y : y;
        float *out = image->pixels + 4u * (size_t)iy * w;
        for (x = 0; x < w; x++, out += 4) {
            float v[3] = {0.0f, 0.0f, 0.0f};
            for (k = 0; k < c && k < 3u; k++, p += sb) { /* c <= 3: the header's check, spelled for the compiler */
                if (info->format.type == LS_IMAGE_PFM) {
                    uint32_t u = info->format.big_endian
                                     ? ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3]
                                     : ((uint32_t)p[3] << 24) | ((uint32_t)p[2] << 16) | ((uint32_t)p[1] << 8) | p[0];
                    memcpy(&v[k], &u, sizeof u);
                } else {
                    uint32_t q = sb == 1u ? p[0] : ((uint32_t)p[0] << 8) | p[1];
                    if (q > info->maxval) {
                        ls_image_fail_(diag, LS_ERR_PARSE, "PNM sample above maxval", (int64_t)(p - d));
                        if (diag != NULL) {
                            diag->has_index = 1;
                            diag->index = (uint64_t)y * w + x;
                        }
                        return LS_ERR_PARSE;
                    }
                    v[k] = ls_image_unorm_to_float_(q, info->maxval);
                }
            }
            if (c == 1u) {
                out[0] = out[1] = out[2] = v[0];
            } else {
                out[0] = v[0];
                out[1] = v[1];
                out[2] = v[2];
            }
            out[3] = 1.0f;
        }
    }
    return LS_OK;
}

/* Decimal digits of v into buf (at least 10 bytes); returns their count. */
static size_t put_uint(unsigned char *buf, uint32_t v)
{
    unsigned char tmp[10];
    size_t n = 0, i;
    do {
        tmp[n++] = (unsigned char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0);
    for (i = 0; i < n; i++) buf[i] = tmp[n - 1u - i];
    return n;
}

/* "P6\n<w> <h>\n65535\n", "PF\n<w> <h>\n-1.0\n", ... */
static size_t header(uint32_t w, uint32_t h, const ls_image_format *f, unsigned char *buf)
{
    size_t n = 0;
    buf[n++] = 'P';
    if (f->type == LS_IMAGE_PFM)
        buf[n++] = f->channels == 1u ? 'f' : 'F';
    else
        buf[n++] = f->channels == 1u ? '5' : '6';
    buf[n++] = '\n';
    n += put_uint(buf + n, w);
    buf[n++] = ' ';
    n += put_uint(buf + n, h);
    buf[n++] = '\n';
    if (f->type == LS_IMAGE_PFM) {
        if (!f->big_endian) buf[n++] = '-';
        buf[n++] = '1';
        buf[n++] = '.';
        buf[n++] = '0';
        buf[n++] = '\n';
    } else {
        n += put_uint(buf + n, f->bits == 8u ? 255u : 65535u);
        buf[n++] = '\n';
    }
    return n;
}

ls_status ls_pnm_encoded_size_(uint32_t width, uint32_t height, const ls_image_format *format,
                               size_t *file_bytes)
{
    unsigned char buf[48];
    size_t data;
    uint32_t sb = format->type == LS_IMAGE_PFM ? 4u : format->bits / 8u;
    if (ls_size_mul((size_t)width * height, (size_t)format->channels * sb, &data) != LS_OK ||
        ls_size_sum(data, header(width, height, format, buf), file_bytes) != LS_OK)
        return LS_ERR_TOO_LARGE;
    return LS_OK;
}

void ls_pnm_encode_(const ls_image *image, const ls_image_format *f, ls_image_sink *sink)
{
    unsigned char buf[512];
    size_t len = header(image->width, image->height, f, buf);
    uint32_t x, y, k, w = image->width, h = image->height;
    for (y = 0; y < h && sink->status == LS_OK; y++) {
        uint32_t iy = f->type == LS_IMAGE_PFM ? h - 1u - y : y;
        const float *px = image->pixels + 4u * (size_t)iy * w;
        for (x = 0; x < w; x++, px += 4) {
            for (k = 0; k < f->channels; k++) {
                if (f->type == LS_IMAGE_PFM) {
                    uint32_t u;
                    memcpy(&u, &px[k], sizeof u);
                    if (f->big_endian) {
                        buf[len] = (unsigned char)(u >> 24);
                        buf[len + 1] = (unsigned char)(u >> 16);
                        buf[len + 2] = (unsigned char)(u >> 8);
                        buf[len + 3] = (unsigned char)u;
                    } else {
                        buf[len] = (unsigned char)u;
                        buf[len + 1] = (unsigned char)(u >> 8);
                        buf[len + 2] = (unsigned char)(u >> 16);
                        buf[len + 3] = (unsigned char)(u >> 24);
                    }
                    len += 4;
                } else if (f->bits == 8u) {
                    buf[len++] = (unsigned char)ls_image_unorm_(px[k], 255.0f);
                } else {
                    uint32_t q = ls_image_unorm_(px[k], 65535.0f);
                    buf[len++] = (unsigned char)(q >> 8);
                    buf[len++] = (unsigned char)q;
                }
            }
            if (len > sizeof buf - 12u) {
                ls_image_sink_put_(sink, buf, len);
                len = 0;
            }
        }
    }
    if (len > 0) ls_image_sink_put_(sink, buf, len);
}
