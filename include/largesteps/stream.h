/* largesteps/stream.h - the caller's output callback, shared by every writer.
 *
 * Encoders (images, meshes) never touch files: they hand their output, in
 * order, to a write callback the caller supplies. A callback that returns
 * non-zero stops the writer, which returns LS_ERR_IO (the bytes already
 * delivered stay delivered: a writer cannot take them back).
 *
 * ls_membuf is a ready-made sink that appends to a fixed caller buffer, for
 * firmware and tests that want the output in memory.
 */
#ifndef LARGESTEPS_STREAM_H
#define LARGESTEPS_STREAM_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Writes `bytes` bytes at `data` (bytes > 0); returns 0 on success, anything
 * else on failure (the writer then returns LS_ERR_IO). `user` is the pointer
 * the caller gave the writer alongside the callback. */
typedef int32_t (*ls_write_fn)(void *user, const void *data, size_t bytes);

/* A fixed memory sink: ls_membuf_write appends to data[size..capacity). */
typedef struct ls_membuf {
    unsigned char *data; /* the caller's buffer (may be NULL when capacity is 0) */
    size_t capacity;     /* its length in bytes */
    size_t size;         /* bytes written so far; set to 0 before the first write */
    uint32_t overflow;   /* set to 1 when a write did not fit (nothing of it is kept) */
} ls_membuf;

/* ls_membuf_write: an ls_write_fn whose `user` is an ls_membuf *. Appends the
 * bytes when they fit and returns 0; otherwise sets overflow, keeps the buffer
 * as it was and returns 1 (so the writer fails with LS_ERR_IO). A NULL user
 * fails. O(bytes); no memory. */
int32_t ls_membuf_write(void *user, const void *data, size_t bytes);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_STREAM_H */
