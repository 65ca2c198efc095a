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

ls_status ls_posix_load_mesh(const char *path, ls_arena *arena, ls_mesh *mesh, ls_diag *diag)
{
    unsigned char *data = NULL;
    size_t bytes = 0;
    ls_status st = ls_posix_read_file(path, &data, &bytes);
    if (st == LS_OK) st = ls_mesh_read(data, bytes, LS_MESH_FORMAT_AUTO, arena, mesh, diag);
    free(data);
    return st;
}
