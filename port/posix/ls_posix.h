/* ls_posix.h - the POSIX platform layer: clock and whole-file I/O for the
 * command-line program and the tests. This is the only place that touches the
 * operating system; the library itself (src/) never does. */
#ifndef LS_POSIX_H
#define LS_POSIX_H

#include <stdio.h>
#include <largesteps.h>

/* Monotonic clock in nanoseconds, usable as an ls_clock_fn (user is ignored). */
uint64_t ls_posix_clock_ns(void *user);

/* Reads a whole file into a malloc'd buffer (*data, *bytes; free with free()).
 * LS_ERR_IO when it cannot be opened or read, LS_ERR_TOO_LARGE past SIZE_MAX. */
ls_status ls_posix_read_file(const char *path, unsigned char **data, size_t *bytes);

/* The deflate stream of a gzip member (RFC 1952) in g[0..n): its offset in
 * *start and length in *len, and the trailer's CRC-32 and ISIZE (the
 * uncompressed length mod 2^32). One member only; 0 when the header or the
 * framing is malformed or the method is not deflate. */
int ls_posix_gzip_member(const unsigned char *g, size_t n, size_t *start, size_t *len, uint32_t *crc,
                         uint32_t *isize);

/* Decompresses the gzip member g[0..n) into a malloc'd buffer with the
 * library's ls_inflate, its length and CRC-32 checked against the trailer:
 * LS_ERR_PARSE when malformed or corrupt, LS_ERR_TOO_LARGE when the memory
 * is not there, ls_inflate's errors. */
ls_status ls_posix_gunzip(const unsigned char *g, size_t n, unsigned char **data, size_t *bytes);

/* ls_posix_read_file, and a gzip file (told by its first two bytes, 1f 8b)
 * decompressed by ls_posix_gunzip. */
ls_status ls_posix_read_data(const char *path, unsigned char **data, size_t *bytes);

/* A write callback target: appends to a FILE * passed as `user`; returns 0 on
 * success, non-zero on a write error. */
int32_t ls_posix_write_file(void *user, const void *data, size_t bytes);

/* Reads an OBJ, PLY or OFF file (format from its first bytes; gzip-compressed
 * too, ls_posix_read_data) into *mesh from the arena: LS_ERR_IO when
 * unreadable, LS_ERR_PARSE for a corrupt gzip file, else ls_mesh_read's
 * errors. */
ls_status ls_posix_load_mesh(const char *path, ls_arena *arena, ls_mesh *mesh, ls_diag *diag);

/* Creates a directory and its missing parents (like mkdir -p); 0 on success. */
int ls_posix_mkdir_p(const char *path);

/* Writes PATH whole or not at all: body(f, ctx) writes into PATH.tmp
 * (returning non-zero on success), which is then renamed to PATH; on any
 * failure the temporary file is removed and PATH is untouched. Returns 1 on
 * success, 0 on failure. */
int ls_posix_write_whole(const char *path, int (*body)(FILE *f, void *ctx), void *ctx);

/* The same for DIR/NAME. */
int ls_posix_write_whole_in(const char *dir, const char *name, int (*body)(FILE *f, void *ctx), void *ctx);

/* Encodes img as fmt (e.g. PNG) into DIR/NAME, whole or not at all (the
 * encoder's scratch from the arena, released). Returns 1 on success; 0 on
 * failure, with the encoder's status in *st (LS_OK when the file itself
 * failed; st may be NULL). */
int ls_posix_write_image_in(const char *dir, const char *name, const ls_image *img, const ls_image_format *fmt,
                            ls_arena *arena, ls_status *st);

/* Copies the file DIR/NAME to stdout (the experiments echo their tables);
 * 1 on success, 0 if it cannot be read. */
int ls_posix_print_file_in(const char *dir, const char *name);

#endif /* LS_POSIX_H */
