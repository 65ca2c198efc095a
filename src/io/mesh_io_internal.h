/* mesh_io_internal.h - what the mesh readers share (private to src/io): the
 * text cursor, the sink the readers fill, number parsing and error reports
 * with positions. mesh_io.c: OBJ, OFF, the dispatch and the writers;
 * mesh_ply.c: PLY (ASCII and binary). Formats: include/largesteps/mesh_io.h. */
#ifndef LS_MESH_IO_INTERNAL_H
#define LS_MESH_IO_INTERNAL_H
#include <largesteps/mesh_io.h>
#include <largesteps/number.h>
#include <string.h>

#define U32_LIMIT 0xffffffffu
#define COORD_NONFINITE "vertex coordinate is NaN or infinite"

/* --- text cursor ------------------------------------------------------- */

typedef struct text {
    const char *s;
    size_t n;
    size_t pos;
    size_t line_start;
    uint32_t line;
    uint32_t hash_comments; /* '#' ends the useful part of a line */
} text;

/* Output of the second pass (NULL pointers in the first). */
typedef struct sink {
    ls_real *p;
    uint32_t *t;
    uint64_t nv; /* vertices so far */
    uint64_t nt; /* triangles so far */
    uint64_t np; /* polygons so far */
} sink;

/* ---- what each file offers the others ---- */

/* mesh_ply.c */
ls_status ls_mio_read_ply(const char *s, size_t n, sink *k, ls_diag *diag);
uint32_t ls_mio_ply_is_binary(const void *data, size_t bytes);

/* mesh_io.c */
int ls_mio_is_eol(char c);
void ls_mio_text_init(text *t, const char *s, size_t n, size_t start, uint32_t hash_comments);
void ls_mio_skip_spaces(text *t);
void ls_mio_next_line(text *t);
size_t ls_mio_token(text *t, const char **tok);
ls_status ls_mio_text_error(ls_diag *diag, const text *t, size_t at, ls_status st, const char *what);
ls_status ls_mio_offset_error(ls_diag *diag, size_t at, ls_status st, const char *what);
int ls_mio_parse_uint(const char *tok, size_t len, uint64_t limit, uint64_t *out);
int ls_mio_parse_int(const char *tok, size_t len, uint64_t limit, int64_t *out);
int ls_mio_coord_finite(ls_real v);
int ls_mio_add_tri(sink *k, uint32_t a, uint32_t b, uint32_t c);

#endif
