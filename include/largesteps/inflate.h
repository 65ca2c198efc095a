/* largesteps/inflate.h - zlib (RFC 1950) and raw deflate (RFC 1951) decompression.
 *
 * Decompresses from one memory buffer into another whose size the caller
 * knows (PNG rows, fixtures). The decoder is iterative with a bounded stack;
 * its Huffman tables live in a fixed-size state taken from the arena's
 * scratch. Every malformed stream is an error with ls_diag->what naming it
 * and ls_diag->offset giving the byte of the input where it was found.
 */
#ifndef LARGESTEPS_INFLATE_H
#define LARGESTEPS_INFLATE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ls_inflate_bytes: the exact arena bytes ls_zlib_decompress and ls_inflate
 * take (the decoder state with its Huffman tables; a constant of the build,
 * about 7 KB). LS_ERR_INVALID for NULL. O(1). */
ls_status ls_inflate_bytes(size_t *arena_bytes);

/* ls_zlib_decompress: decompresses the zlib stream src[0..src_bytes) into
 * dst[0..dst_bytes), *out_bytes receiving the length produced. The stream
 * must end exactly at src_bytes and its Adler-32 must match. Errors:
 * LS_ERR_PARSE (bad header, invalid block type, invalid or incomplete Huffman
 * code lengths, invalid codes, distances before the start of the output,
 * stored lengths that do not match, truncation, Adler-32 mismatch, bytes
 * after the stream), LS_ERR_UNSUPPORTED (preset dictionary), LS_ERR_TOO_LARGE
 * (the output does not fit dst), LS_ERR_NOMEM, LS_ERR_INVALID. On failure
 * dst may hold partial output; the arena is restored. O(src + dst). */
ls_status ls_zlib_decompress(const void *src, size_t src_bytes, void *dst, size_t dst_bytes,
                             size_t *out_bytes, ls_arena *arena, ls_diag *diag);

/* ls_inflate: the same for a raw deflate stream (no zlib header or
 * checksum); bytes after the final block are an error. */
ls_status ls_inflate(const void *src, size_t src_bytes, void *dst, size_t dst_bytes,
                     size_t *out_bytes, ls_arena *arena, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_INFLATE_H */
