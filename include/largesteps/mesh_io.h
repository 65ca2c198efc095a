/* largesteps/mesh_io.h - OBJ, PLY and OFF meshes from memory; OBJ and binary
 * PLY through a write callback.
 *
 * Readers take the whole file as a memory buffer and make two passes over
 * it: the first checks everything and counts vertices and triangles (no
 * memory), the second fills a mesh of exactly that size from the arena. So
 * ls_mesh_read_info + ls_mesh_read_bytes tell the bytes up front, a file that
 * is malformed anywhere is rejected before any memory is taken, and header
 * counts are never trusted for allocation (they are checked against the
 * bytes that are really there). Every error names its cause in diag->what
 * and its place: line and column for text, byte offset for binary data.
 *
 * What is read (only positions and triangles are kept):
 *   OBJ  "v x y z [w ...]" and "f" with i, i/t, i/t/n or i//n tokens (1-based;
 *        negative = relative to the vertices so far); polygons are
 *        fan-triangulated (a concave polygon can give overlapping
 *        triangles); every other statement (vt, vn, g, o, s, l, p, usemtl,
 *        mtllib, #, ...) is skipped. Forward references are allowed; a
 *        backslash line continuation is not supported (LS_ERR_PARSE).
 *   PLY  ascii, binary_little_endian, binary_big_endian 1.0; every scalar
 *        type and its alias (char/int8 ... double/float64); vertex x, y, z of
 *        any scalar type; face list "vertex_indices" or "vertex_index" of an
 *        integer type; other elements and properties are skipped. Header
 *        lines other than format/comment/obj_info/element/property/end_header
 *        are rejected (LS_ERR_PARSE "unknown PLY header line").
 *   OFF  OFF, COFF, NOFF, CNOFF, STOFF and the like (counts on the keyword
 *        line or the next; vertex colours and extra values ignored; per-face
 *        colours after the indices ignored; 0-based indices; # comments).
 *        4OFF, nOFF and binary OFF give LS_ERR_UNSUPPORTED.
 * Text may use LF, CRLF or CR line ends and may lack a final line end; a
 * UTF-8 byte-order mark is skipped; UTF-16 gives LS_ERR_UNSUPPORTED. Numbers
 * follow largesteps/number.h (locale-free, correctly rounded to ls_real).
 *
 * Errors of the readers: LS_ERR_PARSE (malformed; what/line/column or
 * offset say where: "empty file", "invalid number", "face index 0",
 * "face index out of range", "face with fewer than 3 vertices", "truncated
 * binary body", "element count larger than the file", ...),
 * LS_ERR_UNSUPPORTED (UTF-16, 4D OFF, binary OFF, ...), LS_ERR_TOO_LARGE
 * (more than 2^32 - 1 vertices or triangles), LS_ERR_MESH (the file has no
 * triangles, e.g. a point cloud), LS_ERR_NONFINITE (a vertex coordinate
 * that is NaN or infinite: "nan", "inf", or such a binary value; a finite
 * number beyond ls_real's range, in text or as a binary double in the float
 * build, is LS_ERR_TOO_LARGE), LS_ERR_NOMEM, LS_ERR_INVALID.
 */
#ifndef LARGESTEPS_MESH_IO_H
#define LARGESTEPS_MESH_IO_H

#include <largesteps/core.h>
#include <largesteps/arena.h>
#include <largesteps/status.h>
#include <largesteps/mesh.h>
#include <largesteps/stream.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_MESH_FORMAT_AUTO 0u /* PLY if the file starts with "ply", OFF if its keyword ends in "OFF", else OBJ */
#define LS_MESH_FORMAT_OBJ 1u
#define LS_MESH_FORMAT_PLY 2u
#define LS_MESH_FORMAT_OFF 3u

/* What the first pass found. */
typedef struct ls_mesh_file_info {
    uint32_t format;        /* LS_MESH_FORMAT_OBJ, _PLY or _OFF (never AUTO) */
    uint32_t vertex_count;
    uint32_t face_count;    /* triangles, after fan triangulation */
    uint32_t polygon_count; /* faces as written in the file */
    uint32_t binary;        /* 1 for binary PLY */
} ls_mesh_file_info;

/* ls_mesh_format_guess: the format of data[0..bytes) by its first bytes
 * (see LS_MESH_FORMAT_AUTO). O(first line). */
uint32_t ls_mesh_format_guess(const void *data, size_t bytes);

/* ls_mesh_read_info: the first pass: checks the whole file and counts. No
 * memory; O(bytes). Errors as listed above (not LS_ERR_NOMEM). */
ls_status ls_mesh_read_info(const void *data, size_t bytes, uint32_t format, ls_mesh_file_info *info, ls_diag *diag);

/* ls_mesh_read_bytes: the arena bytes ls_mesh_read takes for this file
 * (exact: the mesh's two arrays, no scratch). O(1). */
ls_status ls_mesh_read_bytes(const ls_mesh_file_info *info, size_t *bytes);

/* ls_mesh_read: both passes; on success *mesh holds positions and triangles
 * allocated from the bottom of the arena. On failure the arena and *mesh are
 * unchanged. O(bytes). Errors as listed above. */
ls_status ls_mesh_read(const void *data, size_t bytes, uint32_t format, ls_arena *arena, ls_mesh *mesh,
                       ls_diag *diag);

/* ls_mesh_write_obj: "v x y z" lines (17 significant digits for double, 9
 * for float: reading the file back gives the same bits) and "f a b c" lines
 * (1-based), LF line ends, through write(user, ...) in chunks of at most 512
 * bytes. O(V + F); no memory (about 700 bytes of stack). Errors:
 * LS_ERR_INVALID, LS_ERR_MESH (an index out of range: nothing is written),
 * LS_ERR_IO (the callback failed; bytes already written stay written). */
ls_status ls_mesh_write_obj(const ls_mesh *mesh, ls_write_fn write, void *user);

/* ls_mesh_write_ply: binary_little_endian PLY (on every host): vertex x, y,
 * z as float (float build) or double, faces as "list uchar uint
 * vertex_indices"; exact. Otherwise as ls_mesh_write_obj. */
ls_status ls_mesh_write_ply(const ls_mesh *mesh, ls_write_fn write, void *user);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_MESH_IO_H */
