/* ls_posix.h - the POSIX platform layer: clock and whole-file I/O for the
 * command-line program and the tests. This is the only place that touches the
 * operating system; the library itself (src/) never does. */
#ifndef LS_POSIX_H
#define LS_POSIX_H

#include <largesteps.h>

/* Monotonic clock in nanoseconds, usable as an ls_clock_fn (user is ignored). */
uint64_t ls_posix_clock_ns(void *user);

/* Reads a whole file into a malloc'd buffer (*data, *bytes; free with free()).
 * LS_ERR_IO when it cannot be opened or read, LS_ERR_TOO_LARGE past SIZE_MAX. */
ls_status ls_posix_read_file(const char *path, unsigned char **data, size_t *bytes);

/* A write callback target: appends to a FILE * passed as `user`; returns 0 on
 * success, non-zero on a write error. */
int32_t ls_posix_write_file(void *user, const void *data, size_t bytes);

#endif /* LS_POSIX_H */
