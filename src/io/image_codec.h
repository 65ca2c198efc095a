/* image_codec.h - private declarations shared by the image codecs (image.c,
 * png.c, pnm.c, inflate.c, deflate.c). Not installed; not part of the API. */
#ifndef LS_IMAGE_CODEC_H
#define LS_IMAGE_CODEC_H

#include <string.h>
#include <largesteps/image.h>
#include <largesteps/inflate.h>
#include <largesteps/checksum.h>

/* One run of the inflate core. Input: a segment [pos, end) of `file`; with
 * png_idat set, when a segment ends the reader continues with the data of the
 * next chunk if it is an IDAT chunk (PNG splits its zlib stream so). Output:
 * dst[0..cap), `produced` bytes of it. */
typedef struct ls_inflate_input {
    const unsigned char *file; /* the whole input: diag offsets are relative to it */
    size_t file_bytes;
    size_t pos;                /* next byte to read */
    size_t end;                /* end of the current segment */
    uint32_t png_idat;
    uint32_t zlib;             /* 1: a zlib stream (header, Adler-32); 0: raw deflate */
    unsigned char *dst;
    size_t cap;
    size_t produced;
} ls_inflate_input;

/* Bytes of the inflate state (Huffman tables), before arena rounding. */
size_t ls_inflate_state_bytes_(void);

/* Runs the decoder over `in`, with `state` pointing at
 * ls_inflate_state_bytes_() bytes. Returns LS_ERR_TOO_LARGE when the output
 * would pass cap. Fills diag. */
ls_status ls_inflate_run_(ls_inflate_input *in, void *state, ls_diag *diag);

/* Fills diag (when not NULL) and returns status. offset < 0: no offset. */
ls_status ls_image_fail_(ls_diag *diag, ls_status status, const char *what, int64_t offset);

/* A staging buffer in front of the caller's write callback. */
typedef struct ls_image_sink {
    ls_write_fn write;
    void *user;
    unsigned char *buf;
    size_t len;
    size_t cap;
    ls_status status; /* LS_ERR_IO once the callback failed */
} ls_image_sink;

#define LS_IMAGE_STAGING 4096u

void ls_image_sink_put_(ls_image_sink *sink, const void *data, size_t bytes);
void ls_image_sink_flush_(ls_image_sink *sink);

/* The deflate encoder (deflate.c): raw deflate (RFC 1951), no zlib
 * wrapper. Compressed bytes go to out(ctx, bytes, n) in pieces of at most
 * 1024 bytes. The state is ls_deflate_state_bytes_() caller-owned bytes
 * (8-byte aligned); level 1..9 as zlib's levels. */
typedef void (*ls_deflate_out_fn)(void *ctx, const unsigned char *bytes, size_t n);
size_t ls_deflate_state_bytes_(void);
void ls_deflate_begin_(void *state, uint32_t level, ls_deflate_out_fn out, void *ctx);
void ls_deflate_put_(void *state, const unsigned char *data, size_t n);
void ls_deflate_end_(void *state);
/* An upper bound of the deflate stream's bytes for n input bytes
 * (LS_ERR_TOO_LARGE when it overflows size_t). */
ls_status ls_deflate_bound_(size_t n, size_t *bytes);

/* Per-format parts, called by image.c after it has checked its arguments. */
ls_status ls_png_info_(const unsigned char *data, size_t bytes, ls_image_info *info, ls_diag *diag);
ls_status ls_png_decode_(const unsigned char *data, size_t bytes, const ls_image_info *info,
                         ls_image *image, ls_arena *arena, ls_diag *diag);
ls_status ls_png_encoded_size_(uint32_t width, uint32_t height, const ls_image_format *format,
                               size_t *file_bytes);
/* Scratch bytes of ls_png_encode_ beyond the sink's staging buffer (0 for
 * stored blocks). */
size_t ls_png_encode_scratch_(const ls_image_format *format);
void ls_png_encode_(const ls_image *image, const ls_image_format *format, ls_image_sink *sink, void *scratch);

ls_status ls_pnm_info_(const unsigned char *data, size_t bytes, ls_image_info *info, ls_diag *diag);
ls_status ls_pnm_decode_(const unsigned char *data, size_t bytes, const ls_image_info *info,
                         ls_image *image, ls_diag *diag);
ls_status ls_pnm_encoded_size_(uint32_t width, uint32_t height, const ls_image_format *format,
                               size_t *file_bytes);
void ls_pnm_encode_(const ls_image *image, const ls_image_format *format, ls_image_sink *sink);

/* Sample conversion shared by the decoders: q / maxval rounded to float. */
float ls_image_unorm_to_float_(uint32_t q, uint32_t maxval);

/* The conversion rule of image.h, inlined into the encoders:
 * round_half_to_even(clamp(v, 0, 1) * m) for m <= 65535, NaN -> 0. After the
 * clamp t = v * m lies in [0, 65535]; adding 2^23 moves it where floats are
 * spaced 1 apart, so the sum is t rounded to an integer, half to even (the
 * library requires round-to-nearest-even: ls_selftest), and its low mantissa
 * bits are that integer. No float-to-integer cast at all. */
static inline uint32_t ls_image_unorm_(float v, float m)
{
    float t;
    uint32_t bits;
    if (!(v > 0.0f)) v = 0.0f; /* negative, zero and NaN */
    if (v > 1.0f) v = 1.0f;
    t = v * m + 8388608.0f;
    memcpy(&bits, &t, sizeof bits);
    return bits - 0x4B000000u;
}

/* Deflate's length and distance codes and the code-length order (RFC 1951
 * 3.2.5, 3.2.7), shared by inflate.c and deflate.c. */
extern const uint16_t ls_deflate_len_base[29];
extern const uint8_t ls_deflate_len_extra[29];
extern const uint16_t ls_deflate_dist_base[30];
extern const uint8_t ls_deflate_dist_extra[30];
extern const uint8_t ls_deflate_cl_order[19];

#endif /* LS_IMAGE_CODEC_H */
