/* file.c - whole-file reading and writing, a FILE*-backed write callback,
 * directories. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>
#include "ls_posix.h"

ls_status ls_posix_read_file(const char *path, unsigned char **data, size_t *bytes)
{
    FILE *f;
    unsigned char *buf = NULL;
    size_t len = 0, cap = 0;
    ls_status status = LS_OK;
    if (path == NULL || data == NULL || bytes == NULL) return LS_ERR_INVALID;
    *data = NULL;
    *bytes = 0;
    f = fopen(path, "rb");
    if (f == NULL) return LS_ERR_IO;
    for (;;) {
        size_t got;
        if (len == cap) {
            size_t ncap = cap == 0 ? 65536 : cap * 2;
            unsigned char *nbuf = ncap > cap ? (unsigned char *)realloc(buf, ncap) : NULL;
            if (nbuf == NULL) {
                status = LS_ERR_TOO_LARGE;
                break;
            }
            buf = nbuf;
            cap = ncap;
        }
        got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            if (ferror(f)) status = LS_ERR_IO;
            break;
        }
    }
    fclose(f);
    if (status != LS_OK) {
        free(buf);
        return status;
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

int ls_posix_write_whole(const char *path, int (*body)(FILE *f, void *ctx), void *ctx)
{
    char tmp[4096];
    FILE *f;
    int ok;
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp) return 0;
    f = fopen(tmp, "wb");
    if (f == NULL) return 0;
    ok = body(f, ctx) && fflush(f) == 0 && !ferror(f);
    if (fclose(f) != 0) ok = 0;
    if (ok && rename(tmp, path) != 0) ok = 0;
    if (!ok) remove(tmp);
    return ok;
}

int ls_posix_write_whole_in(const char *dir, const char *name, int (*body)(FILE *f, void *ctx), void *ctx)
{
    char path[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, name) >= sizeof path) return 0;
    return ls_posix_write_whole(path, body, ctx);
}

typedef struct image_file {
    const ls_image *img;
    const ls_image_format *fmt;
    ls_arena *arena;
    ls_status st;
} image_file;

static int image_body(FILE *f, void *ctx)
{
    image_file *c = (image_file *)ctx;
    ls_arena_mark mark = ls_arena_save(c->arena);
    c->st = ls_image_encode(c->img, c->fmt, ls_posix_write_file, f, c->arena);
    ls_arena_restore(c->arena, mark);
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
    size_t start = 0, len = 0, got = 0, wbytes = 0;
    uint32_t crc = 0, isize = 0;
    ls_arena a;
    ls_status st;
    if (g == NULL || data == NULL || bytes == NULL) return LS_ERR_INVALID;
    *data = NULL;
    *bytes = 0;
    if (!ls_posix_gzip_member(g, n, &start, &len, &crc, &isize)) return LS_ERR_PARSE;
    st = ls_inflate_bytes(&wbytes);
    if (st != LS_OK) return st;
    out = (unsigned char *)malloc((size_t)isize + 1u);
    work = (unsigned char *)malloc(wbytes + LS_ARENA_ALIGN);
    if (out == NULL || work == NULL) {
        free(out);
        free(work);
        return LS_ERR_TOO_LARGE;
    }
    st = ls_arena_init(&a, work, wbytes + LS_ARENA_ALIGN);
    if (st == LS_OK) st = ls_inflate(g + start, len, out, (size_t)isize, &got, &a, NULL);
    /* the trailer's length and CRC-32 must match what came out */
    if (st == LS_OK && (got != (size_t)isize || ls_crc32(0, out, got) != crc)) st = LS_ERR_PARSE;
    free(work);
    if (st != LS_OK) {
        free(out);
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
    if (st == LS_OK) st = ls_mesh_read(data, bytes, LS_MESH_FORMAT_AUTO, arena, mesh, diag);
    free(data);
    return st;
}
