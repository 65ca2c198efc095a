/* file.c - whole-file reading and a FILE*-backed write callback. */
#include <stdio.h>
#include <stdlib.h>
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
