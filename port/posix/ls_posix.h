/* ls_posix.h - the POSIX platform layer: clock and whole-file I/O for the
 * command-line program and the tests. This is the only place that touches the
 * operating system; the library itself (src/) never does. */
#ifndef LS_POSIX_H
#define LS_POSIX_H

#include <stdio.h>
#include <largesteps.h>

/* Monotonic clock in nanoseconds, usable as an ls_clock_fn (user is ignored). */
uint64_t ls_posix_clock_ns(void *user);

/* A pool of threads for the fit's parallel-for (fit.h: config.parallel =
 * {ls_posix_pool_run, pool}, config.workers = the pool's workers): workers -
 * 1 threads plus the calling thread. create: NULL when the threads cannot all
 * be started (or workers is 0 or above LS_FIT_MAX_WORKERS); destroy joins
 * them (NULL is ignored). ls_posix_cores: the processors online (at least 1). */
typedef struct ls_posix_pool ls_posix_pool;
ls_posix_pool *ls_posix_pool_create(uint32_t workers);
void ls_posix_pool_destroy(ls_posix_pool *pool);
void ls_posix_pool_run(void *pool, uint32_t count, ls_task_fn task, void *arg);
uint32_t ls_posix_cores(void);

/* The program's working memory, malloc'd (free with free()): on a 64-bit
 * host the larger of 1 GiB and 3/4 of the machine's physical memory (its
 * pages are committed only as they are used), else 1 GiB; 1 GiB when the
 * larger cannot be had. *bytes: its size (0 and NULL when not even 1 GiB). */
void *ls_posix_work_memory(size_t *bytes);

/* The default limit on the size of a file the program reads (plain or after
 * gzip decompression), in MB (2^20 bytes): 256 MB of OBJ text is about 3
 * million triangles. */
#define LS_POSIX_INPUT_LIMIT_MB 256u

/* The input limit in bytes for every later read (ls_posix_read_file,
 * ls_posix_gunzip); SIZE_MAX for none. Not thread-safe: set it once, first. */
void ls_posix_set_input_limit(size_t bytes);
size_t ls_posix_input_limit(void);

/* Why the last failed read failed, for a message: the system's reason
 * ("No such file or directory", "Is a directory", "Permission denied"), the
 * input limit, or corrupt gzip data. A static string, valid until the next
 * read. */
const char *ls_posix_read_error(void);

/* Reads a whole file into a malloc'd buffer (*data, *bytes; free with free()).
 * LS_ERR_IO when it cannot be opened or read (a directory included),
 * LS_ERR_TOO_LARGE when it is larger than the input limit (checked while
 * reading: a device or pipe without end fails at the limit), LS_ERR_NOMEM. */
ls_status ls_posix_read_file(const char *path, unsigned char **data, size_t *bytes);

/* The deflate stream of a gzip member (RFC 1952) in g[0..n): its offset in
 * *start and length in *len, and the trailer's CRC-32 and ISIZE (the
 * uncompressed length mod 2^32). One member only; 0 when the header or the
 * framing is malformed or the method is not deflate. */
int ls_posix_gzip_member(const unsigned char *g, size_t n, size_t *start, size_t *len, uint32_t *crc,
                         uint32_t *isize);

/* Decompresses the gzip member g[0..n) into a malloc'd buffer with the
 * library's ls_inflate, its length and CRC-32 checked against the trailer:
 * LS_ERR_PARSE when malformed or corrupt, LS_ERR_TOO_LARGE when the output
 * is larger than the input limit, LS_ERR_NOMEM, ls_inflate's errors. The
 * trailer's ISIZE is only a hint: the buffer is at most the limit and at
 * most deflate's largest expansion of the compressed length. */
ls_status ls_posix_gunzip(const unsigned char *g, size_t n, unsigned char **data, size_t *bytes);

/* ls_posix_read_file, and a gzip file (told by its first two bytes, 1f 8b)
 * decompressed by ls_posix_gunzip. */
ls_status ls_posix_read_data(const char *path, unsigned char **data, size_t *bytes);

/* A write callback target: appends to a FILE * passed as `user`; returns 0 on
 * success, non-zero on a write error. */
int32_t ls_posix_write_file(void *user, const void *data, size_t bytes);

/* Reads an OBJ, PLY or OFF file (format from its first bytes; gzip-compressed
 * too, ls_posix_read_data) into *mesh from the arena: LS_ERR_IO when
 * unreadable, LS_ERR_TOO_LARGE over the input limit, LS_ERR_PARSE for a
 * corrupt gzip file (diag->what: ls_posix_read_error()), else ls_mesh_read's
 * errors. */
ls_status ls_posix_load_mesh(const char *path, ls_arena *arena, ls_mesh *mesh, ls_diag *diag);

/* Creates a directory and its missing parents (like mkdir -p); 0 on success. */
int ls_posix_mkdir_p(const char *path);

/* Checks an output file path before any work: refused (a message on
 * stderr, 0) when it is a symbolic link, a directory, a FIFO, a device or a
 * socket (only regular files are replaced), or when its directory is missing
 * or not writable (the system's reason). 1 when it can be written. */
int ls_posix_check_output(const char *path);

/* The same for an output directory: an existing directory that is writable,
 * or a missing one whose nearest existing ancestor is a writable directory.
 * Refused when it exists and is not a directory. */
int ls_posix_check_output_dir(const char *dir);

/* Writes PATH whole or not at all: body(f, ctx) writes into a new temporary
 * file in PATH's directory (.NAME.XXXXXX; returning non-zero on success),
 * which is checked (fflush, ferror, fsync, fclose) and renamed to PATH. A
 * PATH that is a symbolic link, FIFO, device or directory is refused. On any
 * failure the temporary is removed, PATH is untouched, and one line
 * "largesteps: cannot write PATH: REASON" (the system's reason, e.g. "No
 * space left on device") goes to stderr. Returns 1 on success, 0 on
 * failure. */
int ls_posix_write_whole(const char *path, int (*body)(FILE *f, void *ctx), void *ctx);

/* The same for DIR/NAME. */
int ls_posix_write_whole_in(const char *dir, const char *name, int (*body)(FILE *f, void *ctx), void *ctx);

/* The last write failure ("cannot write PATH: REASON"). */
const char *ls_posix_write_error(void);

/* Removes the temporaries in flight on SIGINT, SIGTERM and SIGHUP, then
 * dies of the signal (main calls it once). A signal the caller ignores
 * (nohup, a background job's SIGINT) stays ignored. */
void ls_posix_cleanup_on_signals(void);

/* An output set: files that appear together or not at all. Each add writes
 * its file to a checked temporary in DIR (which must exist); commit renames
 * them all into place with the signals held, abort (or any failed add)
 * removes them and leaves every earlier file untouched. begin returns NULL
 * when out of memory; commit prints the failure ("largesteps: cannot write
 * PATH: REASON; no file of the set was written") and frees the set, as
 * abort does. At most 4096 files. */
typedef struct ls_posix_outset ls_posix_outset;
ls_posix_outset *ls_posix_outset_begin(const char *dir);
int ls_posix_outset_add(ls_posix_outset *s, const char *name, int (*body)(FILE *f, void *ctx), void *ctx);
int ls_posix_outset_add_image(ls_posix_outset *s, const char *name, const ls_image *img, const ls_image_format *fmt,
                              ls_arena *arena, ls_status *st);
int ls_posix_outset_commit(ls_posix_outset *s);
/* The size of the file the last ls_posix_outset_add_image or
 * ls_posix_write_image_in wrote (compressed PNG: known only once written). */
size_t ls_posix_last_image_bytes(void);
void ls_posix_outset_abort(ls_posix_outset *s);

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
