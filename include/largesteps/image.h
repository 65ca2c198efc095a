/* largesteps/image.h - RGBA float images; PNG, PPM/PGM and PFM in and out.
 *
 * An ls_image is width x height pixels of four floats each, R, G, B, A, in
 * rows from the TOP of the picture to the bottom, each row from left to right:
 * the value of channel c of pixel (x, y) is pixels[4 * ((size_t)y * width + x) + c],
 * y = 0 being the top row (PFM files store rows bottom-up: the codec flips them).
 * Pixel values are what the file holds, scaled to [0, 1] for integer formats:
 * no gamma or colour-space conversion is ever applied.
 *
 * Integer conversion (the one rule every encoder and ls_image_to_unorm use):
 *     q = round_half_to_even(clamp(v, 0, 1) * M),  M = 255 or 65535,
 * computed in float (the product v * M is rounded to float first), NaN -> 0,
 * +inf -> M, -inf -> 0. It uses no libm call and no float-to-integer cast
 * (clamped, t = v * M + 2^23 has the integer in its low mantissa bits, which
 * is exact under the round-to-nearest-even mode ls_selftest checks), so it
 * gives the same bits on every target. Decoding maps q to
 * q / M rounded to the nearest float (bit depths below 8 likewise with
 * M = 2^bits - 1), so decode followed by encode at the same depth gives back
 * the file's integers exactly.
 *
 * Encoding writes through a caller's ls_write_fn (largesteps/stream.h).
 * LS_IMAGE_PNG is compressed: each row takes the PNG filter (None, Sub, Up,
 * Average, Paeth) with the smallest sum of byte magnitudes, then deflate
 * (LZ77 over a 32 KiB window with zlib's level-6 parameters, each block the
 * smallest of stored, fixed and dynamic Huffman), from about 282 KiB of
 * arena scratch; LS_IMAGE_PNG_STORED writes stored (uncompressed) deflate
 * blocks with no compressor and no filter (for small targets: 4 KiB of
 * scratch, a file size known in advance). Either way the bytes depend only
 * on the pixels and the format. Decoding reads from memory
 * in two phases: ls_image_decode_info parses and checks the header (and, for
 * PNG, every chunk and CRC) and states the exact arena bytes; ls_image_decode
 * then decodes. PNG decoding has a full inflate (stored, fixed and dynamic
 * Huffman blocks), all colour types and bit depths (1, 2, 4, 8, 16), palettes,
 * tRNS transparency and Adam7 interlacing.
 *
 * Malformed input is an error with a precise ls_diag (what, and the byte
 * offset where it was found, or the row in diag->index for errors in the
 * decompressed data), never a crash: every loop is bounded by the input size
 * and nothing is read outside it.
 */
#ifndef LARGESTEPS_IMAGE_H
#define LARGESTEPS_IMAGE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/stream.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Size limits of this library (files beyond them give LS_ERR_TOO_LARGE). */
#define LS_IMAGE_MAX_SIDE   (1u << 20)  /* width and height, each */
#define LS_IMAGE_MAX_PIXELS (1u << 28)  /* width * height */

typedef struct ls_image {
    uint32_t width;  /* pixels per row, >= 1 */
    uint32_t height; /* rows, >= 1 */
    float *pixels;   /* 4 * width * height floats: RGBA, top row first */
} ls_image;

/* File formats (ls_image_format.type). */
#define LS_IMAGE_PNG 1u /* PNG (written deflate-compressed) */
#define LS_IMAGE_PNM 2u /* binary PGM (P5, 1 channel) and PPM (P6, 3 channels) */
#define LS_IMAGE_PFM 3u /* Portable Float Map: "Pf" (1 channel) or "PF" (3 channels) */
#define LS_IMAGE_PNG_STORED 4u /* encoding only: PNG with stored (uncompressed) deflate blocks */

/* How an image is (to be) stored. Channels: 1 grey (the R channel when
 * encoding), 2 grey + alpha (R and A), 3 RGB, 4 RGBA. Allowed combinations
 * for encoding: PNG and PNG_STORED 1-4 channels at 8 or 16 bits; PNM 1 or 3 channels at 8
 * or 16 bits (16-bit samples big-endian, maxval 65535); PFM 1 or 3 channels,
 * bits = 32, big_endian 0 (scale -1.0) or 1 (scale 1.0). */
typedef struct ls_image_format {
    uint32_t type;       /* LS_IMAGE_PNG, LS_IMAGE_PNM or LS_IMAGE_PFM */
    uint32_t channels;   /* samples per pixel in the file (indexed PNG: 1) */
    uint32_t bits;       /* bits per sample: 1, 2, 4, 8, 16 (PNG), 8/16 (PNM), 32 (PFM) */
    uint32_t big_endian; /* PFM only: 1 when the samples are big-endian */
} ls_image_format;

/* What ls_image_decode_info found in a file's header. */
typedef struct ls_image_info {
    ls_image_format format; /* as stored in the file */
    uint32_t width;
    uint32_t height;
    uint32_t palette;       /* PNG colour type 3: samples are palette indices */
    uint32_t transparency;  /* PNG tRNS chunk present (becomes alpha) */
    uint32_t interlaced;    /* PNG Adam7 */
    uint32_t maxval;        /* PNM maxval (1..65535), else 2^bits - 1 (PFM: 0) */
    size_t image_bytes;     /* the ls_image pixels: ls_image_bytes(width, height) */
    size_t scratch_bytes;   /* decoding scratch (PNG: filtered rows and inflate state) */
    size_t arena_bytes;     /* exact arena bytes ls_image_decode takes (peak) */
} ls_image_info;

/* ls_image_bytes: the exact arena bytes of an image's pixels,
 * 16 * width * height rounded to LS_ARENA_ALIGN. LS_ERR_INVALID for a zero
 * side or NULL bytes, LS_ERR_TOO_LARGE past LS_IMAGE_MAX_SIDE /
 * LS_IMAGE_MAX_PIXELS or when size_t overflows. O(1). */
ls_status ls_image_bytes(uint32_t width, uint32_t height, size_t *bytes);

/* ls_image_create: allocates a width x height image from the bottom of the
 * arena, every value 0 (transparent black). Memory: ls_image_bytes(). Errors
 * as ls_image_bytes, LS_ERR_NOMEM (arena and *image unchanged). O(pixels). */
ls_status ls_image_create(ls_image *image, uint32_t width, uint32_t height, ls_arena *arena);

/* ls_unorm8 / ls_unorm16: one value by the conversion rule above:
 * round_half_to_even(clamp(v, 0, 1) * 255 or 65535), NaN -> 0. O(1). */
uint8_t ls_unorm8(float v);
uint16_t ls_unorm16(float v);

/* ls_image_to_unorm: packs the image into integers, row by row from the top:
 * `channels` samples per pixel (1: R, 2: R A, 3: R G B, 4: R G B A), `bits` 8
 * (uint8_t samples) or 16 (uint16_t samples, native byte order), by the
 * conversion rule. out must hold width * height * channels samples
 * (out_bytes says how many bytes it has). LS_ERR_INVALID for bad arguments or
 * a short buffer. O(pixels); no memory. */
ls_status ls_image_to_unorm(const ls_image *image, uint32_t channels, uint32_t bits,
                            void *out, size_t out_bytes);

/* ls_image_from_unorm: the inverse: fills the image from integers laid out as
 * above (grey is copied to R, G and B; without alpha A = 1), each q becoming
 * q / (2^bits - 1) rounded to float. LS_ERR_INVALID for bad arguments or a
 * short buffer. O(pixels); no memory. */
ls_status ls_image_from_unorm(ls_image *image, uint32_t channels, uint32_t bits,
                              const void *in, size_t in_bytes);

/* ls_image_encode_bytes: the exact arena bytes ls_image_encode takes for a
 * width x height image in `format` (a fixed staging buffer, plus for
 * LS_IMAGE_PNG the compressor's fixed state, taken as scratch and released
 * on return; the same for every image size). LS_ERR_INVALID for a format it cannot write, errors
 * of ls_image_bytes for the size. O(1). */
ls_status ls_image_encode_bytes(uint32_t width, uint32_t height, const ls_image_format *format,
                                size_t *arena_bytes);

/* ls_image_encoded_size: the length in bytes of the file ls_image_encode
 * writes for a width x height image in `format`: exact for
 * LS_IMAGE_PNG_STORED (signature, IHDR, IDAT chunks of at most 65536 bytes
 * holding a zlib stream of stored blocks of at most 65535 bytes, IEND), PNM
 * and PFM (header and samples); for LS_IMAGE_PNG an upper bound that holds
 * for any pixels (a few bytes per 16 KiB above the stored size: the
 * compressor falls back to stored blocks), so a buffer of that size always
 * holds the file. LS_ERR_TOO_LARGE when it overflows size_t. O(1). */
ls_status ls_image_encoded_size(uint32_t width, uint32_t height, const ls_image_format *format,
                                size_t *file_bytes);

/* ls_image_encode: writes `image` in `format` through write(user, ...), in
 * pieces of at most 4096 bytes (the staging buffer, from the arena's scratch).
 * The output depends only on the pixels and the format. Errors: LS_ERR_INVALID
 * (NULL arguments, an unwritable format), LS_ERR_NOMEM (nothing written),
 * LS_ERR_IO when the callback fails (the bytes before stay written). The
 * arena is as before the call on return. O(pixels). */
ls_status ls_image_encode(const ls_image *image, const ls_image_format *format,
                          ls_write_fn write, void *user, ls_arena *arena);

/* ls_image_decode_info: recognises the format (PNG signature, "P5"/"P6",
 * "PF"/"Pf"), parses its header and fills *info, including the exact arena
 * bytes decoding will take. For PNG it walks every chunk and checks its CRC,
 * IHDR, PLTE and tRNS, that the IDAT chunks are consecutive and that nothing
 * follows IEND; PNM and PFM files must be exactly header + samples long.
 * Errors (diag->what names each, diag->offset says where): LS_ERR_PARSE for
 * malformed input (unknown signature, truncated data, bad CRC, zero width or
 * height, trailing bytes, ...), LS_ERR_TOO_LARGE past the size limits,
 * LS_ERR_UNSUPPORTED for valid features not handled (ASCII or bitmap PNM,
 * PAM, unknown critical PNG chunks), LS_ERR_INVALID for NULL arguments.
 * O(file bytes); no memory. diag may be NULL. */
ls_status ls_image_decode_info(const void *data, size_t bytes, ls_image_info *info, ls_diag *diag);

/* ls_image_decode: decodes a PNG, PNM or PFM file held in memory into a new
 * RGBA image allocated from the arena (grey is copied to R, G and B; missing
 * alpha is 1; PNG tRNS gives alpha 0 to the matching colour or palette
 * entries). Takes exactly info.arena_bytes at peak (the image from the
 * bottom, scratch from the top, released on return). On any failure the arena
 * and *image are unchanged. Errors: those of ls_image_decode_info, plus
 * LS_ERR_PARSE for corrupt compressed data (invalid Huffman codes or code
 * lengths, distances too far back, bad stored-block lengths, truncated or
 * overlong zlib streams, Adler-32 mismatch, filter types above 4 (diag->index
 * = row, diag->value = the type), palette indices out of range (diag->index
 * = pixel), PNM samples above maxval), LS_ERR_UNSUPPORTED for a zlib preset
 * dictionary, and LS_ERR_NOMEM. O(file bytes + pixels). */
ls_status ls_image_decode(const void *data, size_t bytes, ls_image *image, ls_arena *arena,
                          ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_IMAGE_H */
