/* image.c - RGBA float image buffers, integer conversion, and the format
 * dispatch of encoding and decoding (the formats are in png.c and pnm.c). */
#include <string.h>
#include "image_codec.h"

ls_status ls_image_fail_(ls_diag *diag, ls_status status, const char *what, int64_t offset)
{
    if (diag != NULL) {
        ls_diag_clear(diag);
        diag->status = status;
        diag->what = what;
        if (offset >= 0) {
            diag->has_offset = 1;
            diag->offset = (uint64_t)offset;
        }
    }
    return status;
}

ls_status ls_image_bytes(uint32_t width, uint32_t height, size_t *bytes)
{
    ls_size size;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (width == 0 || height == 0) return LS_ERR_INVALID;
    if (width > LS_IMAGE_MAX_SIDE || height > LS_IMAGE_MAX_SIDE ||
        (uint64_t)width * height > LS_IMAGE_MAX_PIXELS)
        return LS_ERR_TOO_LARGE;
    ls_size_init(&size);
    ls_size_add(&size, (size_t)width * height, 4u * sizeof(float));
    return ls_size_get(&size, bytes);
}

ls_status ls_image_create(ls_image *image, uint32_t width, uint32_t height, ls_arena *arena)
{
    size_t bytes;
    float *p;
    ls_status st;
    if (image == NULL || arena == NULL) return LS_ERR_INVALID;
    st = ls_image_bytes(width, height, &bytes);
    if (st != LS_OK) return st;
    p = (float *)ls_arena_alloc_zero(arena, (size_t)width * height, 4u * sizeof(float));
    if (p == NULL) return LS_ERR_NOMEM;
    image->width = width;
    image->height = height;
    image->pixels = p;
    return LS_OK;
}

uint8_t ls_unorm8(float v)
{
    return (uint8_t)ls_image_unorm_(v, 255.0f);
}

uint16_t ls_unorm16(float v)
{
    return (uint16_t)ls_image_unorm_(v, 65535.0f);
}

float ls_image_unorm_to_float_(uint32_t q, uint32_t maxval)
{
    return (float)q / (float)maxval;
}

static int layout_ok(const ls_image *image, uint32_t channels, uint32_t bits, const void *p,
                     size_t bytes)
{
    size_t need;
    if (image == NULL || p == NULL || image->pixels == NULL || image->width == 0 || image->height == 0)
        return 0;
    if (channels < 1u || channels > 4u || (bits != 8u && bits != 16u)) return 0;
    if (ls_size_mul((size_t)image->width * channels, image->height, &need) != LS_OK) return 0;
    if (ls_size_mul(need, bits / 8u, &need) != LS_OK) return 0;
    return bytes >= need;
}

/* Which RGBA channel the k-th stored sample comes from. */
static uint32_t source_channel(uint32_t channels, uint32_t k)
{
    if (channels == 2u) return k == 0 ? 0u : 3u;
    return k;
}

ls_status ls_image_to_unorm(const ls_image *image, uint32_t channels, uint32_t bits, void *out,
                            size_t out_bytes)
{
    size_t n, i;
    uint32_t k;
    if (!layout_ok(image, channels, bits, out, out_bytes)) return LS_ERR_INVALID;
    n = (size_t)image->width * image->height;
    for (i = 0; i < n; i++) {
        const float *px = image->pixels + 4u * i;
        for (k = 0; k < channels; k++) {
            float v = px[source_channel(channels, k)];
            if (bits == 8u)
                ((uint8_t *)out)[i * channels + k] = ls_unorm8(v);
            else
                ((uint16_t *)out)[i * channels + k] = ls_unorm16(v);
        }
    }
    return LS_OK;
}

ls_status ls_image_from_unorm(ls_image *image, uint32_t channels, uint32_t bits, const void *in,
                              size_t in_bytes)
{
    size_t n, i;
    uint32_t maxval = bits == 8u ? 255u : 65535u;
    if (!layout_ok(image, channels, bits, in, in_bytes)) return LS_ERR_INVALID;
    n = (size_t)image->width * image->height;
    for (i = 0; i < n; i++) {
        float *px = image->pixels + 4u * i;
        uint32_t s[4] = {0, 0, 0, 0}, k;
        for (k = 0; k < channels; k++)
            s[k] = bits == 8u ? ((const uint8_t *)in)[i * channels + k]
                              : ((const uint16_t *)in)[i * channels + k];
        if (channels <= 2u) {
            px[0] = px[1] = px[2] = ls_image_unorm_to_float_(s[0], maxval);
            px[3] = channels == 2u ? ls_image_unorm_to_float_(s[1], maxval) : 1.0f;
        } else {
            for (k = 0; k < 3u; k++) px[k] = ls_image_unorm_to_float_(s[k], maxval);
            px[3] = channels == 4u ? ls_image_unorm_to_float_(s[3], maxval) : 1.0f;
        }
    }
    return LS_OK;
}

/* --- encoding ------------------------------------------------------------ */

static int format_writable(const ls_image_format *f)
{
    if (f == NULL) return 0;
    switch (f->type) {
    case LS_IMAGE_PNG:
    case LS_IMAGE_PNG_STORED:
        return f->channels >= 1u && f->channels <= 4u && (f->bits == 8u || f->bits == 16u);
    case LS_IMAGE_PNM:
        return (f->channels == 1u || f->channels == 3u) && (f->bits == 8u || f->bits == 16u);
    case LS_IMAGE_PFM:
        return (f->channels == 1u || f->channels == 3u) && f->bits == 32u && f->big_endian <= 1u;
    default:
        return 0;
    }
}

void ls_image_sink_flush_(ls_image_sink *sink)
{
    if (sink->len > 0 && sink->status == LS_OK && sink->write(sink->user, sink->buf, sink->len) != 0)
        sink->status = LS_ERR_IO;
    sink->len = 0;
}

void ls_image_sink_put_(ls_image_sink *sink, const void *data, size_t bytes)
{
    const unsigned char *p = (const unsigned char *)data;
    while (bytes > 0 && sink->status == LS_OK) {
        size_t n = sink->cap - sink->len;
        if (n > bytes) n = bytes;
        memcpy(sink->buf + sink->len, p, n);
        sink->len += n;
        p += n;
        bytes -= n;
        if (sink->len == sink->cap) ls_image_sink_flush_(sink);
    }
}

ls_status ls_image_encode_bytes(uint32_t width, uint32_t height, const ls_image_format *format,
                                size_t *arena_bytes)
{
    size_t image;
    ls_status st;
    if (arena_bytes == NULL) return LS_ERR_INVALID;
    *arena_bytes = 0;
    if (!format_writable(format)) return LS_ERR_INVALID;
    st = ls_image_bytes(width, height, &image);
    if (st != LS_OK) return st;
    *arena_bytes = LS_ARENA_ROUND(LS_IMAGE_STAGING) + LS_ARENA_ROUND(ls_png_encode_scratch_(format));
    return LS_OK;
}

ls_status ls_image_encoded_size(uint32_t width, uint32_t height, const ls_image_format *format,
                                size_t *file_bytes)
{
    size_t image;
    ls_status st;
    if (file_bytes == NULL) return LS_ERR_INVALID;
    *file_bytes = 0;
    if (!format_writable(format)) return LS_ERR_INVALID;
    st = ls_image_bytes(width, height, &image);
    if (st != LS_OK) return st;
    if (format->type == LS_IMAGE_PNG || format->type == LS_IMAGE_PNG_STORED)
        return ls_png_encoded_size_(width, height, format, file_bytes);
    return ls_pnm_encoded_size_(width, height, format, file_bytes);
}

ls_status ls_image_encode(const ls_image *image, const ls_image_format *format, ls_write_fn write,
                          void *user, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_image_sink sink;
    size_t bytes, extra;
    void *scratch = NULL;
    if (image == NULL || image->pixels == NULL || write == NULL || arena == NULL ||
        !format_writable(format))
        return LS_ERR_INVALID;
    if (ls_image_bytes(image->width, image->height, &bytes) != LS_OK) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    sink.buf = (unsigned char *)ls_arena_scratch(arena, LS_IMAGE_STAGING, 1);
    extra = ls_png_encode_scratch_(format);
    if (sink.buf != NULL && extra > 0) scratch = ls_arena_scratch(arena, extra, 1);
    if (sink.buf == NULL || (extra > 0 && scratch == NULL)) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    sink.write = write;
    sink.user = user;
    sink.len = 0;
    sink.cap = LS_IMAGE_STAGING;
    sink.status = LS_OK;
    if (format->type == LS_IMAGE_PNG || format->type == LS_IMAGE_PNG_STORED)
        ls_png_encode_(image, format, &sink, scratch);
    else
        ls_pnm_encode_(image, format, &sink);
    ls_image_sink_flush_(&sink);
    ls_arena_restore(arena, mark);
    return sink.status;
}

/* --- decoding ------------------------------------------------------------ */

ls_status ls_image_decode_info(const void *data, size_t bytes, ls_image_info *info, ls_diag *diag)
{
    ls_diag_clear(diag);
    const unsigned char *p = (const unsigned char *)data;
    ls_status st;
    if (diag != NULL) ls_diag_clear(diag);
    if (info == NULL) return ls_image_fail_(diag, LS_ERR_INVALID, "info is NULL", -1);
    if (data == NULL && bytes > 0) return ls_image_fail_(diag, LS_ERR_INVALID, "data is NULL with bytes > 0", -1);
    memset(info, 0, sizeof *info);
    if (bytes >= 8u && p[0] == 0x89u && p[1] == 'P' && p[2] == 'N' && p[3] == 'G' && p[4] == '\r' &&
        p[5] == '\n' && p[6] == 0x1au && p[7] == '\n')
        st = ls_png_info_(p, bytes, info, diag);
    else if (bytes >= 2u && p[0] == 'P' && ((p[1] >= '1' && p[1] <= '7') || p[1] == 'F' || p[1] == 'f'))
        st = ls_pnm_info_(p, bytes, info, diag);
    else
        return ls_image_fail_(diag, LS_ERR_PARSE, "unknown image signature (not PNG, PNM or PFM)", 0);
    if (st != LS_OK) {
        memset(info, 0, sizeof *info);
        return st;
    }
    return LS_OK;
}

ls_status ls_image_decode(const void *data, size_t bytes, ls_image *image, ls_arena *arena,
                          ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_image_info info;
    ls_image out;
    ls_arena_mark mark;
    ls_status st;
    if (image == NULL) return ls_image_fail_(diag, LS_ERR_INVALID, "image is NULL", -1);
    if (arena == NULL) return ls_image_fail_(diag, LS_ERR_INVALID, "arena is NULL", -1);
    st = ls_image_decode_info(data, bytes, &info, diag);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    out.width = info.width;
    out.height = info.height;
    out.pixels = (float *)ls_arena_alloc(arena, (size_t)info.width * info.height, 4u * sizeof(float));
    if (out.pixels == NULL) return ls_image_fail_(diag, LS_ERR_NOMEM, "arena too small for the image", -1);
    if (info.format.type == LS_IMAGE_PNG)
        st = ls_png_decode_((const unsigned char *)data, bytes, &info, &out, arena, diag);
    else
        st = ls_pnm_decode_((const unsigned char *)data, bytes, &info, &out, diag);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    /* keep the image, release the scratch */
    {
        ls_arena_mark keep = ls_arena_save(arena);
        keep.top = mark.top;
        ls_arena_restore(arena, keep);
    }
    *image = out;
    return LS_OK;
}
