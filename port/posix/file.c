/* file.c - whole-file reading and writing, a FILE*-backed write callback,
 * directories. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <stdint.h>
#include <sys/stat.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>
#include "ls_posix.h"

/* The input limit (ls_posix_set_input_limit) and the reason of the last
 * read failure (ls_posix_read_error). */
static size_t input_limit = (size_t)LS_POSIX_INPUT_LIMIT_MB << 20;
static char read_error[256];

void ls_posix_set_input_limit(size_t bytes)
{
    input_limit = bytes;
}

size_t ls_posix_input_limit(void)
{
    return input_limit;
}

const char *ls_posix_read_error(void)
{
    return read_error[0] != 0 ? read_error : "read failed";
}

static ls_status read_fail(ls_status st, int err)
{
    if (st == LS_ERR_TOO_LARGE)
        snprintf(read_error, sizeof read_error,
                 "larger than the input limit of %llu MB (--max-input-mb N raises it)",
                 (unsigned long long)(input_limit >> 20));
    else if (st == LS_ERR_NOMEM)
        snprintf(read_error, sizeof read_error, "out of memory while reading");
    else
        snprintf(read_error, sizeof read_error, "%s", strerror(err));
    return st;
}

ls_status ls_posix_read_file(const char *path, unsigned char **data, size_t *bytes)
{
    FILE *f;
    struct stat sb;
    unsigned char *buf = NULL;
    size_t len = 0, cap = 0, limit = input_limit;
    ls_status status = LS_OK;
    int err = 0;
    if (path == NULL || data == NULL || bytes == NULL) return LS_ERR_INVALID;
    *data = NULL;
    *bytes = 0;
    read_error[0] = 0;
    f = fopen(path, "rb");
    if (f == NULL) return read_fail(LS_ERR_IO, errno);
    if (fstat(fileno(f), &sb) == 0) {
        if (S_ISDIR(sb.st_mode)) {
            fclose(f);
            return read_fail(LS_ERR_IO, EISDIR);
        }
        /* a regular file larger than the limit is refused before reading */
        if (S_ISREG(sb.st_mode) && (uintmax_t)sb.st_size > (uintmax_t)limit) {
            fclose(f);
            return read_fail(LS_ERR_TOO_LARGE, 0);
        }
    }
    /* the buffer doubles up to the limit plus one byte (to tell "exactly
     * the limit" from "more"), never beyond */
    for (;;) {
        size_t got;
        if (len == cap) {
            size_t ncap = cap == 0 ? 65536 : cap > SIZE_MAX / 2u ? SIZE_MAX : cap * 2u;
            unsigned char *nbuf;
            if (limit < SIZE_MAX && ncap > limit + 1u) ncap = limit + 1u;
            nbuf = ncap > cap ? (unsigned char *)realloc(buf, ncap) : NULL;
            if (nbuf == NULL) {
                status = ncap > cap ? LS_ERR_NOMEM : LS_ERR_TOO_LARGE;
                break;
            }
            buf = nbuf;
            cap = ncap;
        }
        got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (len > limit) {
            status = LS_ERR_TOO_LARGE;
            break;
        }
        if (got == 0) {
            if (ferror(f)) {
                status = LS_ERR_IO;
                err = errno;
            }
            break;
        }
    }
    fclose(f);
    if (status != LS_OK) {
        free(buf);
        return read_fail(status, err != 0 ? err : EIO);
    }
    *data = buf;
    *bytes = len;
    return LS_OK;
}

int32_t ls_posix_write_file(void *user, const void *data, size_t bytes)
{
    FILE *f = (FILE *)user;
    if (f == NULL) return 1;
    return fwrite(data, 1, bytes, f) == bytes ? 0 : 1;
}

int ls_posix_mkdir_p(const char *path)
{
    char buf[4096];
    size_t i, n = strlen(path);
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, path, n + 1);
    for (i = 1; i <= n; i++) {
        if (buf[i] != '/' && buf[i] != '\0') continue;
        buf[i] = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST) return -1;
        buf[i] = i < n ? '/' : '\0';
    }
    return 0;
}

/* ---- outputs ---------------------------------------------------------- */

/* Temporary files in flight, removed by the signal handler: a fixed table
 * (no allocation in the handler; a slot is published by setting its flag
 * after its name is complete). */
#define TEMP_SLOTS 4200
static char temp_name[TEMP_SLOTS][4096];
static volatile sig_atomic_t temp_live[TEMP_SLOTS];
static char write_error[4200];
static unsigned long files_started;

const char *ls_posix_write_error(void)
{
    return write_error[0] != 0 ? write_error : "write failed";
}

static void on_signal(int sig)
{
    int k;
    for (k = 0; k < TEMP_SLOTS; k++)
        if (temp_live[k]) (void)unlink(temp_name[k]);
    signal(sig, SIG_DFL);
    raise(sig);
}

void ls_posix_cleanup_on_signals(void)
{
    static const int sigs[3] = {SIGINT, SIGTERM, SIGHUP};
    struct sigaction sa, was;
    int k;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (k = 0; k < 3; k++) {
        /* a signal ignored by the caller (nohup, a background job) stays ignored */
        if (sigaction(sigs[k], NULL, &was) == 0 && was.sa_handler == SIG_IGN) continue;
        (void)sigaction(sigs[k], &sa, NULL);
    }
}

static int temp_claim(void)
{
    int k;
    for (k = 0; k < TEMP_SLOTS; k++)
        if (!temp_live[k]) return k;
    return -1;
}

static void temp_drop(int k, int remove_file)
{
    if (k < 0) return;
    if (remove_file) (void)unlink(temp_name[k]);
    temp_live[k] = 0;
}

static void set_write_error(const char *path, int err, const char *why)
{
    snprintf(write_error, sizeof write_error, "cannot write %s: %s", path, why != NULL ? why : strerror(err));
}

/* What a path that must not be replaced is, or NULL for a regular file. */
static const char *not_regular(mode_t m)
{
    return S_ISLNK(m)  ? "a symbolic link"
         : S_ISDIR(m)  ? "a directory"
         : S_ISFIFO(m) ? "a FIFO"
         : S_ISCHR(m)  ? "a character device"
         : S_ISBLK(m)  ? "a block device"
         : S_ISSOCK(m) ? "a socket"
         : S_ISREG(m)  ? NULL : "not a regular file";
}

/* The directory part of path into dir ("." when none). */
static int dir_of(const char *path, char *dir, size_t cap)
{
    const char *slash = strrchr(path, '/');
    size_t n = slash == NULL ? 0 : slash == path ? 1 : (size_t)(slash - path);
    if (n + 2 > cap) return 0;
    if (n == 0) {
        dir[0] = '.';
        dir[1] = 0;
    } else {
        memcpy(dir, path, n);
        dir[n] = 0;
    }
    return 1;
}

int ls_posix_check_output(const char *path)
{
    struct stat sb;
    char dir[4096];
    const char *what;
    if (path == NULL || path[0] == 0) {
        fprintf(stderr, "largesteps: an empty output path\n");
        return 0;
    }
    if (lstat(path, &sb) == 0 && (what = not_regular(sb.st_mode)) != NULL) {
        fprintf(stderr, "largesteps: cannot write %s: it is %s; only regular files are replaced\n", path, what);
        return 0;
    }
    if (!dir_of(path, dir, sizeof dir) || stat(dir, &sb) != 0) {
        fprintf(stderr, "largesteps: cannot write %s: %s\n", path, strerror(errno != 0 ? errno : ENAMETOOLONG));
        return 0;
    }
    if (!S_ISDIR(sb.st_mode)) {
        fprintf(stderr, "largesteps: cannot write %s: %s\n", path, strerror(ENOTDIR));
        return 0;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        fprintf(stderr, "largesteps: cannot write %s: %s\n", path, strerror(errno));
        return 0;
    }
    return 1;
}

int ls_posix_check_output_dir(const char *dir)
{
    char up[4096];
    struct stat sb;
    size_t n;
    if (dir == NULL || dir[0] == 0) {
        fprintf(stderr, "largesteps: an empty output directory\n");
        return 0;
    }
    if (stat(dir, &sb) == 0) {
        if (!S_ISDIR(sb.st_mode)) {
            fprintf(stderr, "largesteps: -o %s: it exists and is not a directory\n", dir);
            return 0;
        }
        if (access(dir, W_OK | X_OK) != 0) {
            fprintf(stderr, "largesteps: cannot write in %s: %s\n", dir, strerror(errno));
            return 0;
        }
        return 1;
    }
    if (errno != ENOENT) {
        fprintf(stderr, "largesteps: cannot write in %s: %s\n", dir, strerror(errno));
        return 0;
    }
    /* missing: the nearest existing ancestor must be a writable directory */
    n = strlen(dir);
    if (n >= sizeof up) return fprintf(stderr, "largesteps: -o %s: %s\n", dir, strerror(ENAMETOOLONG)), 0;
    memcpy(up, dir, n + 1);
    for (;;) {
        char *slash;
        while (n > 1 && up[n - 1] == '/') up[--n] = 0;
        slash = strrchr(up, '/');
        if (slash == NULL) {
            up[0] = '.';
            up[1] = 0;
        } else if (slash == up) {
            up[1] = 0;
        } else {
            *slash = 0;
        }
        n = strlen(up);
        if (stat(up, &sb) == 0) break;
        if (errno != ENOENT || (up[0] == '.' && up[1] == 0) || (up[0] == '/' && up[1] == 0)) {
            fprintf(stderr, "largesteps: cannot create %s: %s\n", dir, strerror(errno));
            return 0;
        }
    }
    if (!S_ISDIR(sb.st_mode)) {
        fprintf(stderr, "largesteps: cannot create %s: %s is not a directory\n", dir, up);
        return 0;
    }
    if (access(up, W_OK | X_OK) != 0) {
        fprintf(stderr, "largesteps: cannot create %s: %s\n", dir, strerror(errno));
        return 0;
    }
    return 1;
}

/* An injected failure for the tests (tests/stage_cli_io.sh): with
 * LS_POSIX_FAIL_WRITE=N in the environment, the N-th output file (1-based)
 * fails as on a full disk. */
static int injected_failure(void)
{
    const char *e = getenv("LS_POSIX_FAIL_WRITE");
    return e != NULL && strtoul(e, NULL, 10) == files_started;
}

/* Writes body into a new temporary file in dir (named .NAME.XXXXXX; its
 * slot in *slot), checked: fflush, ferror, fsync, fclose. 1 on success; 0
 * with the temporary removed and write_error set. */
static int write_temp(const char *dir, const char *name, const char *final_path, int (*body)(FILE *f, void *ctx),
                      void *ctx, int *slot)
{
    FILE *f;
    int fd, ok, err = 0, k = temp_claim();
    mode_t mask;
    *slot = -1;
    if (k < 0) {
        set_write_error(final_path, 0, "too many files at once");
        return 0;
    }
    if ((size_t)snprintf(temp_name[k], sizeof temp_name[k], "%s/.%s.XXXXXX", dir, name) >= sizeof temp_name[k]) {
        set_write_error(final_path, ENAMETOOLONG, NULL);
        return 0;
    }
    files_started++;
    {
        /* the file and its slot appear together for the signal handler */
        sigset_t all, old;
        sigfillset(&all);
        (void)sigprocmask(SIG_BLOCK, &all, &old);
        fd = mkstemp(temp_name[k]);
        err = errno;
        if (fd >= 0) temp_live[k] = 1;
        (void)sigprocmask(SIG_SETMASK, &old, NULL);
    }
    if (fd < 0) {
        set_write_error(final_path, err, NULL);
        return 0;
    }
    err = 0;
    mask = umask(0);
    umask(mask);
    (void)fchmod(fd, (mode_t)(0666 & ~mask));
    f = fdopen(fd, "wb");
    if (f == NULL) {
        err = errno;
        close(fd);
        temp_drop(k, 1);
        set_write_error(final_path, err, NULL);
        return 0;
    }
    errno = 0;
    ok = body(f, ctx) != 0;
    if (!ok) err = errno;
    if (ok && (fflush(f) != 0 || ferror(f))) ok = 0, err = errno;
    if (ok && injected_failure()) ok = 0, err = ENOSPC;
    if (ok && fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS) ok = 0, err = errno;
    if (fclose(f) != 0 && ok) ok = 0, err = errno;
    if (!ok) {
        temp_drop(k, 1);
        set_write_error(final_path, err, err != 0 ? NULL : "the data could not be produced");
        return 0;
    }
    *slot = k;
    return 1;
}

/* The final path must be absent or a regular file. */
static int replaceable(const char *path)
{
    struct stat sb;
    const char *what;
    if (lstat(path, &sb) == 0 && (what = not_regular(sb.st_mode)) != NULL) {
        snprintf(write_error, sizeof write_error, "cannot write %s: it is %s; only regular files are replaced",
                 path, what);
        return 0;
    }
    return 1;
}

static void sync_dir(const char *dir)
{
    int fd = open(dir, O_RDONLY);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

int ls_posix_write_whole(const char *path, int (*body)(FILE *f, void *ctx), void *ctx)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    int k;
    write_error[0] = 0;
    if (!dir_of(path, dir, sizeof dir)) {
        set_write_error(path, ENAMETOOLONG, NULL);
        fprintf(stderr, "largesteps: %s\n", write_error);
        return 0;
    }
    if (!replaceable(path) || !write_temp(dir, slash != NULL ? slash + 1 : path, path, body, ctx, &k)) {
        fprintf(stderr, "largesteps: %s\n", write_error);
        return 0;
    }
    if (rename(temp_name[k], path) != 0) {
        set_write_error(path, errno, NULL);
        temp_drop(k, 1);
        fprintf(stderr, "largesteps: %s\n", write_error);
        return 0;
    }
    temp_drop(k, 0);
    sync_dir(dir);
    return 1;
}

int ls_posix_write_whole_in(const char *dir, const char *name, int (*body)(FILE *f, void *ctx), void *ctx)
{
    char path[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, name) >= sizeof path) return 0;
    return ls_posix_write_whole(path, body, ctx);
}

/* ---- output sets -------------------------------------------------------- */

#define SET_CAP 4096
struct ls_posix_outset {
    char dir[4096];
    int count, failed;
    int slot[SET_CAP];
    char *final[SET_CAP];
};

ls_posix_outset *ls_posix_outset_begin(const char *dir)
{
    ls_posix_outset *s;
    if (strlen(dir) >= sizeof s->dir) return NULL;
    s = (ls_posix_outset *)calloc(1, sizeof *s);
    if (s == NULL) return NULL;
    memcpy(s->dir, dir, strlen(dir) + 1);
    write_error[0] = 0;
    return s;
}

int ls_posix_outset_add(ls_posix_outset *s, const char *name, int (*body)(FILE *f, void *ctx), void *ctx)
{
    char path[4096];
    int k;
    if (s == NULL || s->failed) return 0;
    if ((size_t)snprintf(path, sizeof path, "%s/%s", s->dir, name) >= sizeof path || s->count >= SET_CAP) {
        set_write_error(path, ENAMETOOLONG, s->count >= SET_CAP ? "too many files at once" : NULL);
        s->failed = 1;
        return 0;
    }
    if (!replaceable(path) || !write_temp(s->dir, name, path, body, ctx, &k)) {
        s->failed = 1;
        return 0;
    }
    s->final[s->count] = (char *)malloc(strlen(path) + 1);
    if (s->final[s->count] == NULL) {
        temp_drop(k, 1);
        set_write_error(path, ENOMEM, NULL);
        s->failed = 1;
        return 0;
    }
    memcpy(s->final[s->count], path, strlen(path) + 1);
    s->slot[s->count++] = k;
    return 1;
}

static void outset_free(ls_posix_outset *s, int remove_temps)
{
    int i;
    for (i = 0; i < s->count; i++) {
        if (remove_temps) temp_drop(s->slot[i], 1);
        free(s->final[i]);
    }
    free(s);
}

void ls_posix_outset_abort(ls_posix_outset *s)
{
    if (s != NULL) outset_free(s, 1);
}

int ls_posix_outset_commit(ls_posix_outset *s)
{
    sigset_t all, old;
    int i, ok = 1;
    if (s == NULL) return 0;
    if (s->failed) {
        fprintf(stderr, "largesteps: %s; no file of the set was written\n", ls_posix_write_error());
        outset_free(s, 1);
        return 0;
    }
    /* every member is complete on disk: the renames, with the signals held
     * so that an interrupt does not split the set */
    sigfillset(&all);
    (void)sigprocmask(SIG_BLOCK, &all, &old);
    for (i = 0; i < s->count && ok; i++) {
        if (rename(temp_name[s->slot[i]], s->final[i]) != 0) {
            set_write_error(s->final[i], errno, NULL);
            ok = 0;
        } else {
            temp_drop(s->slot[i], 0);
            s->slot[i] = -1;
        }
    }
    for (; i < s->count; i++) temp_drop(s->slot[i], 1);
    (void)sigprocmask(SIG_SETMASK, &old, NULL);
    sync_dir(s->dir);
    if (!ok) fprintf(stderr, "largesteps: %s\n", ls_posix_write_error());
    for (i = 0; i < s->count; i++) free(s->final[i]);
    free(s);
    return ok;
}

typedef struct image_file {
    const ls_image *img;
    const ls_image_format *fmt;
    ls_arena *arena;
    ls_status st;
} image_file;

/* The bytes of the last image image_body wrote (the program is one thread). */
static size_t last_image_bytes;

size_t ls_posix_last_image_bytes(void) { return last_image_bytes; }

static int image_body(FILE *f, void *ctx)
{
    image_file *c = (image_file *)ctx;
    ls_arena_mark mark = ls_arena_save(c->arena);
    long end;
    c->st = ls_image_encode(c->img, c->fmt, ls_posix_write_file, f, c->arena);
    ls_arena_restore(c->arena, mark);
    end = c->st == LS_OK ? ftell(f) : -1;
    last_image_bytes = end > 0 ? (size_t)end : 0;
    return c->st == LS_OK;
}

int ls_posix_write_image_in(const char *dir, const char *name, const ls_image *img, const ls_image_format *fmt,
                            ls_arena *arena, ls_status *st)
{
    image_file c;
    int ok;
    c.img = img;
    c.fmt = fmt;
    c.arena = arena;
    c.st = LS_OK;
    ok = ls_posix_write_whole_in(dir, name, image_body, &c);
    if (st != NULL) *st = c.st;
    return ok;
}

int ls_posix_outset_add_image(ls_posix_outset *s, const char *name, const ls_image *img, const ls_image_format *fmt,
                              ls_arena *arena, ls_status *st)
{
    image_file c;
    int ok;
    c.img = img;
    c.fmt = fmt;
    c.arena = arena;
    c.st = LS_OK;
    ok = ls_posix_outset_add(s, name, image_body, &c);
    if (st != NULL) *st = c.st;
    return ok;
}

int ls_posix_print_file_in(const char *dir, const char *name)
{
    char path[4096];
    unsigned char *text = NULL;
    size_t bytes = 0;
    int ok;
    if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, name) >= sizeof path) return 0;
    ok = ls_posix_read_file(path, &text, &bytes) == LS_OK && fwrite(text, 1, bytes, stdout) == bytes;
    free(text);
    return ok;
}

int ls_posix_gzip_member(const unsigned char *g, size_t n, size_t *start, size_t *len, uint32_t *crc,
                         uint32_t *isize)
{
    size_t at = 10;
    unsigned flg;
    if (n < 18 || g[0] != 0x1f || g[1] != 0x8b || g[2] != 8) return 0;
    flg = g[3];
    if (flg & 0xe0u) return 0; /* reserved bits */
    if (flg & 4u) {            /* FEXTRA: a 2-byte length, then that many bytes */
        if (at + 2 > n) return 0;
        at += 2 + ((size_t)g[at] | (size_t)g[at + 1] << 8);
    }
    if (flg & 8u) { /* FNAME, zero-terminated */
        while (at < n && g[at] != 0) at++;
        at++;
    }
    if (flg & 16u) { /* FCOMMENT, zero-terminated */
        while (at < n && g[at] != 0) at++;
        at++;
    }
    if (flg & 2u) at += 2; /* FHCRC */
    if (at > n || n - at < 8) return 0;
    *start = at;
    *len = n - 8 - at;
    *crc = (uint32_t)g[n - 8] | (uint32_t)g[n - 7] << 8 | (uint32_t)g[n - 6] << 16 | (uint32_t)g[n - 5] << 24;
    *isize = (uint32_t)g[n - 4] | (uint32_t)g[n - 3] << 8 | (uint32_t)g[n - 2] << 16 | (uint32_t)g[n - 1] << 24;
    return 1;
}

ls_status ls_posix_gunzip(const unsigned char *g, size_t n, unsigned char **data, size_t *bytes)
{
    unsigned char *out, *work;
    size_t start = 0, len = 0, got = 0, wbytes = 0, cap;
    uint32_t crc = 0, isize = 0;
    const char *why;
    ls_arena a;
    ls_status st;
    if (g == NULL || data == NULL || bytes == NULL) return LS_ERR_INVALID;
    *data = NULL;
    *bytes = 0;
    if (!ls_posix_gzip_member(g, n, &start, &len, &crc, &isize)) {
        snprintf(read_error, sizeof read_error, "not a valid gzip file (bad header or framing)");
        return LS_ERR_PARSE;
    }
    /* ISIZE is the length mod 2^32: when it is over the limit, so is the
     * length. Otherwise it is only a hint: the buffer is never larger than
     * deflate's largest expansion of the stream (1032:1) nor the limit, and
     * a longer output fails ls_inflate (it does not fit) */
    if ((uintmax_t)isize > (uintmax_t)input_limit) return read_fail(LS_ERR_TOO_LARGE, 0);
    cap = (size_t)isize;
    if (len < SIZE_MAX / 1032u && cap > len * 1032u + 64u) cap = len * 1032u + 64u;
    st = ls_inflate_bytes(&wbytes);
    if (st != LS_OK) return st;
    out = (unsigned char *)malloc(cap + 1u);
    work = (unsigned char *)malloc(wbytes + LS_ARENA_ALIGN);
    if (out == NULL || work == NULL) {
        free(out);
        free(work);
        return read_fail(LS_ERR_NOMEM, 0);
    }
    st = ls_arena_init(&a, work, wbytes + LS_ARENA_ALIGN);
    if (st == LS_OK) st = ls_inflate(g + start, len, out, cap, &got, &a, NULL);
    why = st == LS_ERR_TOO_LARGE ? "it decompresses to more than its trailer's length"
        : st != LS_OK            ? "not a valid deflate stream"
        : got != (size_t)isize   ? "its length does not match the trailer"
        : ls_crc32(0, out, got) != crc ? "its CRC-32 does not match the trailer" : NULL;
    if (why != NULL && st != LS_ERR_NOMEM) st = LS_ERR_PARSE;
    free(work);
    if (st != LS_OK) {
        free(out);
        snprintf(read_error, sizeof read_error, "corrupt gzip data: %s", why);
        return st;
    }
    *data = out;
    *bytes = got;
    return LS_OK;
}

ls_status ls_posix_read_data(const char *path, unsigned char **data, size_t *bytes)
{
    unsigned char *raw = NULL;
    size_t n = 0;
    ls_status st = ls_posix_read_file(path, &raw, &n);
    if (st != LS_OK || n < 2 || raw[0] != 0x1f || raw[1] != 0x8b) {
        *data = raw;
        *bytes = n;
        return st;
    }
    st = ls_posix_gunzip(raw, n, data, bytes);
    free(raw);
    return st;
}

ls_status ls_posix_load_mesh(const char *path, ls_arena *arena, ls_mesh *mesh, ls_diag *diag)
{
    unsigned char *data = NULL;
    size_t bytes = 0;
    ls_status st = ls_posix_read_data(path, &data, &bytes);
    if (st != LS_OK) {
        if (diag != NULL) {
            ls_diag_clear(diag);
            diag->status = st;
            diag->what = ls_posix_read_error();
        }
        return st;
    }
    st = ls_mesh_read(data, bytes, LS_MESH_FORMAT_AUTO, arena, mesh, diag);
    free(data);
    return st;
}
