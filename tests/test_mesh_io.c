/* test_mesh_io.c - OBJ / PLY / OFF readers and writers: fixtures compared
 * with an independent reading (strtod/strtof + sscanf), crafted variants of
 * every format feature, malformed inputs with their named errors and
 * places, assimp's odd files, exact write/read round trips, truncation and
 * byte-flip fuzzing, and the arena sweep of the reader.
 *
 *   build/tests/test_mesh_io --bench FILE [repeats]   parse throughput in MB/s
 */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <time.h>
#include <largesteps/mesh.h>
#include <largesteps/mesh_io.h>
#include <largesteps/number.h>
#include "../port/posix/ls_posix.h"

static LS_ARENA_BUFFER(big, 16u << 20);
static ls_arena arena_g;
static ls_arena *fresh_arena(void)
{
    ls_arena_init(&arena_g, big.bytes, sizeof big.bytes);
    return &arena_g;
}

static ls_status read_mem(const void *d, size_t n, uint32_t fmt, ls_mesh *m, ls_diag *diag)
{
    ls_diag_clear(diag);
    return ls_mesh_read(d, n, fmt, fresh_arena(), m, diag);
}

static ls_status read_str(const char *s, uint32_t fmt, ls_mesh *m, ls_diag *diag)
{
    return read_mem(s, strlen(s), fmt, m, diag);
}

static int real_bits_equal(ls_real a, ls_real b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* --- fixtures against an independent reading --------------------------------- */

static void obj_fixtures_match_strtod(void)
{
    static const char *files[] = {"fixtures/meshes/bunny.obj", "fixtures/meshes/elephant.obj"};
    int fi;
    for (fi = 0; fi < 2; fi++) {
        unsigned char *d = NULL;
        size_t n = 0;
        ls_mesh m;
        ls_diag diag;
        ls_mesh_file_info info;
        uint32_t nv = 0, nf = 0, bad = 0;
        char *text, *line;
        REQUIRE(ls_posix_read_file(files[fi], &d, &n) == LS_OK);
        CHECK_STATUS(ls_mesh_read_info(d, n, LS_MESH_FORMAT_AUTO, &info, &diag), LS_OK);
        CHECK_EQ(info.format, LS_MESH_FORMAT_OBJ);
        CHECK_STATUS(read_mem(d, n, LS_MESH_FORMAT_AUTO, &m, &diag), LS_OK);
        CHECK_EQ(m.vertex_count, info.vertex_count);
        CHECK_EQ(m.face_count, info.face_count);
        text = malloc(n + 1);
        memcpy(text, d, n);
        text[n] = 0;
        for (line = strtok(text, "\n"); line != NULL; line = strtok(NULL, "\n")) {
            if (line[0] == 'v' && line[1] == ' ') {
                char *e = line + 2;
                int k;
                for (k = 0; k < 3; k++) {
#if LS_REAL_IS_FLOAT
                    ls_real ref = strtof(e, &e);
#else
                    ls_real ref = strtod(e, &e);
#endif
                    if (nv < m.vertex_count && !real_bits_equal(ref, m.positions[3 * nv + k])) bad++;
                }
                nv++;
            } else if (line[0] == 'f' && line[1] == ' ') {
                unsigned a, b, c;
                if (sscanf(line + 2, "%u %u %u", &a, &b, &c) != 3) bad++;
                if (nf < m.face_count &&
                    (m.triangles[3 * nf] != a - 1 || m.triangles[3 * nf + 1] != b - 1 || m.triangles[3 * nf + 2] != c - 1))
                    bad++;
                nf++;
            }
        }
        CHECK_EQ(nv, m.vertex_count);
        CHECK_EQ(nf, m.face_count);
        CHECK_EQ(bad, 0);
        free(text);
        free(d);
    }
}

/* --- OBJ features ------------------------------------------------------------- */

static void obj_features(void)
{
    ls_mesh m;
    ls_diag d;
    /* i, i/t, i/t/n, i//n, negative, a quad and a pentagon fan, skipped statements,
       CRLF, tabs, BOM, comments, no final newline, extra vertex values */
    const char *s = "\xef\xbb\xbf# comment\r\n"
                    "mtllib x.mtl\r\n"
                    "o thing\r\n"
                    "v 0 0 0 1\r\n"
                    "v\t1 0 0 0.5 0.5 0.5\r\n"
                    "v 1 1 0\n"
                    "vt 0 0\n"
                    "vn 0 0 1\n"
                    "v 0 1 0\r"
                    "v 2e0 .5 -0.0\n"
                    "g grp\n"
                    "usemtl m\n"
                    "s off\n"
                    "f 1 2 3\n"
                    "f 1/1 3/1 4/1\n"
                    "f 1/1/1 2/1/1 5/1/1\n"
                    "f 1//1 2//1 3//1 4//1\n"
                    "f -5 -4 -3 -2 -1  # trailing comment\n"
                    "l 1 2\n"
                    "p 3\n"
                    "f 5 4 3";
    static const uint32_t want[] = {0, 1, 2, 0, 2, 3, 0, 1, 4, 0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3, 0, 3, 4};
    size_t i;
    CHECK_STATUS(read_str(s, LS_MESH_FORMAT_AUTO, &m, &d), LS_OK);
    REQUIRE(m.vertex_count == 5 && m.face_count == 9);
    for (i = 0; i < 24; i++) CHECK_EQ(m.triangles[i], want[i]);
    CHECK_EQ(m.triangles[24], 4);
    CHECK_EQ(m.triangles[25], 3);
    CHECK_EQ(m.triangles[26], 2);
    CHECK(m.positions[3] == 1 && m.positions[12] == 2 && m.positions[13] == (ls_real)0.5 && m.positions[14] == 0 && signbit(m.positions[14]));
    /* forward references are allowed */
    CHECK_STATUS(read_str("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", LS_MESH_FORMAT_OBJ, &m, &d), LS_OK);
    CHECK_EQ(m.face_count, 1);
    {
        ls_mesh_file_info info;
        CHECK_STATUS(ls_mesh_read_info(s, strlen(s), LS_MESH_FORMAT_AUTO, &info, &d), LS_OK);
        CHECK_EQ(info.polygon_count, 6);
        CHECK_EQ(info.face_count, 9);
    }
}

/* --- malformed inputs ----------------------------------------------------------- */

typedef struct bad_case {
    const char *text;
    uint32_t format;
    ls_status status;
    const char *what; /* substring of diag.what */
    uint32_t line;    /* 0: not checked */
    uint32_t column;  /* 0: not checked */
} bad_case;

static void malformed_text_inputs(void)
{
    static const bad_case cases[] = {
        {"", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "empty file", 0, 0},
        {"  \n\r\n\t", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "empty file", 0, 0},
        {"v 1 2 3\nv 1 2\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "fewer than 3 coordinates", 2, 6},
        {"v 1 2 3.1+e2\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "invalid number", 1, 7},
        {"v 1 2 0x10\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "invalid number", 1, 7},
        {"v 1 2 1,5\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "invalid number", 1, 7},
        {"v 1 2 1e999\n", LS_MESH_FORMAT_OBJ, LS_ERR_TOO_LARGE, "too large", 1, 7},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "face index 0", 4, 7},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "out of range", 4, 7},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "before the first vertex", 4, 7},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "out of range", 4, 7},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "invalid face index", 4, 7},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2/1/1/1 3\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "invalid face index", 4, 5},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "fewer than 3 vertices", 3, 1},
        {"v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n\r\nf\r\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "fewer than 3 vertices", 5, 1},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", LS_MESH_FORMAT_OBJ, LS_ERR_MESH, "no triangles", 0, 0},
        {"v 0 0 0\nv 1 \x00 0\n", LS_MESH_FORMAT_OBJ, LS_ERR_PARSE, "NUL byte", 0, 0},
        {"OFF\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "before its counts", 0, 0},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "counts larger than the file", 0, 0},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "out of range", 6, 7},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -2\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "invalid face index", 6, 7},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "fewer indices than its count", 6, 8},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "fewer than 3 vertices", 6, 1},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "fewer than 3 coordinates", 5, 4},
        {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n\n\n\n\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "ends before all its faces", 0, 0},
        {"OFF\nx 1 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "invalid OFF vertex count", 2, 1},
        {"4OFF\n3 1 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_UNSUPPORTED, "4D", 1, 1},
        {"OFF BINARY\n", LS_MESH_FORMAT_AUTO, LS_ERR_UNSUPPORTED, "binary OFF", 1, 5},
        {"XOFF\n3 1 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "unknown OFF keyword", 1, 1},
        {"OFF\n99999999999999999999999 1 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "larger than the file", 2, 1},
        {"3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", LS_MESH_FORMAT_OBJ, LS_ERR_MESH, "no triangles", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "without x, y and z", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "out of range", 13, 7},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "out of range", 13, 7},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "ends early", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "fewer than 3 vertices", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "out of range for its type", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 x\n3 0 1 2\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "invalid number", 12, 5},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "count type must be an integer", 8, 1},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "integer type", 8, 1},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int colors\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "without vertex_indices", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float32 x\nproperty float y\nproperty quad z\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "unknown PLY property type", 6, 1},
        {"ply\nformat ascii 2.0\n", LS_MESH_FORMAT_AUTO, LS_ERR_UNSUPPORTED, "version", 2, 1},
        {"ply\nformat text 1.0\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "unknown PLY format", 2, 1},
        {"ply\nformat ascii 1.0\nCreated by Blender\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "unknown PLY header line", 3, 1},
        {"ply\nformat ascii 1.0\nelement vertex 3\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "without end_header", 0, 0},
        {"ply\nproperty float x\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "before any element", 2, 1},
        {"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "larger than the file", 3, 1},
        {"ply\nformat ascii 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "larger than the file", 0, 0},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "declared twice", 5, 1},
        {"ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "declared twice", 4, 1},
        {"ply\nend_header\n", LS_MESH_FORMAT_AUTO, LS_ERR_PARSE, "without a format", 2, 1},
        {"plyx\n", LS_MESH_FORMAT_PLY, LS_ERR_PARSE, "magic", 1, 1},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n", LS_MESH_FORMAT_AUTO, LS_ERR_MESH, "no triangles", 0, 0},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case *c = &cases[i];
        ls_mesh m;
        ls_diag d;
        ls_status st;
        size_t len = strlen(c->text);
        if (strstr(c->what, "NUL") != NULL) len = 17;
        memset(&m, 0x3C, sizeof m);
        st = read_mem(c->text, len, c->format, &m, &d);
        CHECK_MSG(st == c->status, "case %lu: status %s, wanted %s (%s)", (unsigned long)i, ls_status_name(st), ls_status_name(c->status), d.what);
        CHECK_MSG(d.what != NULL && strstr(d.what, c->what) != NULL, "case %lu: what '%s', wanted '%s'", (unsigned long)i, d.what ? d.what : "(null)", c->what);
        CHECK_MSG(d.status == st, "case %lu: diag status %d", (unsigned long)i, (int)d.status);
        if (c->line != 0) CHECK_MSG(d.has_line && d.line == c->line, "case %lu: line %u, wanted %u", (unsigned long)i, d.line, c->line);
        if (c->column != 0) CHECK_MSG(d.column == c->column, "case %lu: column %u, wanted %u", (unsigned long)i, d.column, c->column);
        CHECK_MSG(d.has_offset || d.has_line, "case %lu: no place in the diag", (unsigned long)i);
        CHECK_EQ(arena_g.bottom + arena_g.top, 0);
        CHECK_EQ(((unsigned char *)&m)[0], 0x3C);
    }
    /* UTF-16 with and without byte-order mark */
    {
        static const unsigned char le[] = {0xff, 0xfe, 'v', 0, ' ', 0, '1', 0};
        static const unsigned char nobom[] = {'v', 0, ' ', 0, '1', 0};
        ls_mesh m;
        ls_diag d;
        CHECK_STATUS(read_mem(le, sizeof le, LS_MESH_FORMAT_AUTO, &m, &d), LS_ERR_UNSUPPORTED);
        CHECK(strstr(d.what, "UTF-16") != NULL);
        CHECK_STATUS(read_mem(le, sizeof le, LS_MESH_FORMAT_PLY, &m, &d), LS_ERR_UNSUPPORTED);
        CHECK_STATUS(read_mem(nobom, sizeof nobom, LS_MESH_FORMAT_AUTO, &m, &d), LS_ERR_PARSE);
        CHECK(strstr(d.what, "NUL") != NULL && d.offset == 1);
        CHECK_STATUS(read_mem(NULL, 5, LS_MESH_FORMAT_AUTO, &m, &d), LS_ERR_INVALID);
        CHECK(strstr(d.what, "data is NULL") != NULL);
        CHECK_STATUS(read_mem("v", 1, 9, &m, &d), LS_ERR_INVALID);
        CHECK(strstr(d.what, "format") != NULL);
        CHECK_STATUS(ls_mesh_read("v", 1, LS_MESH_FORMAT_AUTO, NULL, &m, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "arena is NULL") == 0);
        CHECK_STATUS(ls_mesh_read_info("v", 1, LS_MESH_FORMAT_AUTO, NULL, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "info is NULL") == 0);
    }
}

/* --- assimp-testmodels -------------------------------------------------------- */

typedef struct file_case {
    const char *path;
    ls_status status;
    const char *what; /* for errors */
    uint32_t nv, nf;  /* for successes */
    uint32_t line;
} file_case;

static void assimp_files(void)
{
    static const file_case cases[] = {
        {"invalid/empty.obj", LS_ERR_PARSE, "empty file", 0, 0, 0},
        {"invalid/empty.ply", LS_ERR_PARSE, "empty file", 0, 0, 0},
        {"invalid/empty.off", LS_ERR_PARSE, "empty file", 0, 0, 0},
        {"invalid/malformed.obj", LS_ERR_PARSE, "face index 0", 0, 0, 28},
        {"invalid/malformed2.obj", LS_ERR_PARSE, "fewer than 3 vertices", 0, 0, 23},
        {"invalid/OutOfMemory.off", LS_ERR_PARSE, "counts larger than the file", 0, 0, 2},
        {"OBJ/box_UTF16BE.obj", LS_ERR_UNSUPPORTED, "UTF-16", 0, 0, 0},
        {"OBJ/number_formats.obj", LS_ERR_PARSE, "invalid number", 0, 0, 11},
        {"OBJ/testpoints.obj", LS_ERR_MESH, "no triangles", 0, 0, 0},
        {"OBJ/testline.obj", LS_ERR_MESH, "no triangles", 0, 0, 0},
        {"OBJ/point_cloud.obj", LS_ERR_MESH, "no triangles", 0, 0, 0},
        {"PLY/points.ply", LS_ERR_MESH, "no triangles", 0, 0, 0},
        {"PLY/issue623.ply", LS_ERR_PARSE, "", 0, 0, 0},
        {"OFF/invalid.off", LS_ERR_PARSE, "fewer than 3 vertices", 0, 0, 6},
        {"OBJ/box.obj", LS_OK, NULL, 8, 12, 0},
        {"OBJ/box_longline.obj", LS_OK, NULL, 8, 944, 0},
        {"OBJ/box_without_lineending.obj", LS_OK, NULL, 8, 12, 0},
        {"OBJ/multiple_spaces.obj", LS_OK, NULL, 4, 1, 0},
        {"OBJ/regr_3429812.obj", LS_OK, NULL, 4, 4, 0},
        {"OBJ/testmixed.obj", LS_OK, NULL, 8, 12, 0},
        {"OBJ/concave_polygon.obj", LS_OK, NULL, 64, 64, 0},
        {"OBJ/cube_usemtl.obj", LS_OK, NULL, 8, 12, 0},
        {"PLY/cube.ply", LS_OK, NULL, 8, 12, 0},
        {"PLY/cube_binary.ply", LS_OK, NULL, 8, 12, 0},
        {"PLY/float-color.ply", LS_OK, NULL, 3, 1, 0},
        {"PLY/cube_uv.ply", LS_OK, NULL, 24, 12, 0},
        {"OFF/Cube.off", LS_OK, NULL, 8, 12, 0},
    };
    size_t i;
    ls_mesh cube_ascii, cube_bin;
    memset(&cube_ascii, 0, sizeof cube_ascii);
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const file_case *c = &cases[i];
        char path[256];
        unsigned char *d = NULL;
        size_t n = 0;
        ls_mesh m;
        ls_diag diag;
        ls_status st;
        snprintf(path, sizeof path, "fixtures/meshes/assimp/%s", c->path);
        REQUIRE(ls_posix_read_file(path, &d, &n) == LS_OK);
        st = read_mem(d, n, LS_MESH_FORMAT_AUTO, &m, &diag);
        CHECK_MSG(st == c->status, "%s: %s (%s), wanted %s", c->path, ls_status_name(st), diag.what, ls_status_name(c->status));
        if (c->status != LS_OK) {
            CHECK_MSG(strstr(diag.what, c->what) != NULL, "%s: '%s'", c->path, diag.what);
            if (c->line) CHECK_MSG(diag.line == c->line, "%s: line %u, wanted %u", c->path, diag.line, c->line);
        } else if (st == LS_OK) {
            CHECK_MSG(m.vertex_count == c->nv && m.face_count == c->nf, "%s: %u V %u F", c->path, m.vertex_count, m.face_count);
            if (strcmp(c->path, "PLY/cube.ply") == 0) {
                static ls_real p[24];
                static uint32_t t[36];
                memcpy(p, m.positions, sizeof p);
                memcpy(t, m.triangles, sizeof t);
                cube_ascii.positions = p, cube_ascii.triangles = t;
            }
            if (strcmp(c->path, "PLY/cube_binary.ply") == 0 && cube_ascii.positions != NULL) {
                cube_bin = m;
                CHECK(memcmp(cube_bin.positions, cube_ascii.positions, 24 * sizeof(ls_real)) == 0);
                CHECK(memcmp(cube_bin.triangles, cube_ascii.triangles, 36 * sizeof(uint32_t)) == 0);
            }
        }
        free(d);
    }
}

/* --- PLY with every scalar type, both byte orders, skipped parts ----------------- */

static const char *const type_names[8] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
static const size_t type_sizes[8] = {1, 1, 2, 2, 4, 4, 4, 8};

/* Appends value v as type ti in byte order be (1 big endian) or as ascii text. */
static size_t put_value(unsigned char *o, int ti, double v, int fmt)
{
    unsigned char b[8];
    size_t sz = type_sizes[ti], i;
    if (fmt == 0) return (size_t)sprintf((char *)o, "%.17g ", v);
    if (ti == 6) {
        float f = (float)v;
        uint32_t u;
        memcpy(&u, &f, 4);
        for (i = 0; i < 4; i++) b[i] = (unsigned char)(u >> (8 * i));
    } else if (ti == 7) {
        uint64_t u;
        memcpy(&u, &v, 8);
        for (i = 0; i < 8; i++) b[i] = (unsigned char)(u >> (8 * i));
    } else {
        int64_t x = (int64_t)v;
        for (i = 0; i < sz; i++) b[i] = (unsigned char)((uint64_t)x >> (8 * i));
    }
    for (i = 0; i < sz; i++) o[i] = fmt == 2 ? b[sz - 1 - i] : b[i];
    return sz;
}

static void ply_every_type_and_byte_order(void)
{
    static const char *fmts[3] = {"ascii", "binary_little_endian", "binary_big_endian"};
    static const double pos[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-2, 3, 100}};
    int fmt, ct, it, ci, bad = 0;
    unsigned char *buf = malloc(8192);
    for (fmt = 0; fmt < 3; fmt++)
        for (ci = 0; ci < 8; ci++) /* coordinate type */
            for (ct = 0; ct < 6; ct++) /* list count type */
                for (it = 0; it < 6; it++) { /* index type */
                    size_t n;
                    int v, k;
                    ls_mesh m;
                    ls_diag d;
                    ls_status st;
                    n = (size_t)sprintf((char *)buf,
                                        "ply\r\nformat %s 1.0\r\ncomment every type  \r\nobj_info x\r\n"
                                        "element vertex 4\r\nproperty uchar red\r\nproperty %s x\r\nproperty %s y\r\n"
                                        "property list uchar short junk\r\nproperty %s z\r\nproperty float nx\r\n"
                                        "element edge 1\r\nproperty int v1\r\nproperty int v2\r\n"
                                        "element face 2\r\nproperty list %s %s %s\r\nproperty list uchar float texcoord\r\n"
                                        "end_header\r\n",
                                        fmts[fmt], type_names[ci], type_names[ci], type_names[ci], type_names[ct], type_names[it],
                                        (ct + it) % 2 ? "vertex_indices" : "vertex_index");
                    for (v = 0; v < 4; v++) {
                        double p[3];
                        for (k = 0; k < 3; k++) p[k] = (ci == 1 || ci == 3 || ci == 5) ? fabs(pos[v][k]) : pos[v][k];
                        n += put_value(buf + n, 1, 200, fmt);
                        n += put_value(buf + n, ci, p[0], fmt);
                        n += put_value(buf + n, ci, p[1], fmt);
                        n += put_value(buf + n, 1, 2, fmt);
                        n += put_value(buf + n, 2, -7, fmt);
                        n += put_value(buf + n, 2, 7, fmt);
                        n += put_value(buf + n, ci, p[2], fmt);
                        n += put_value(buf + n, 6, 0.25, fmt);
                        if (fmt == 0) buf[n++] = '\n';
                    }
                    n += put_value(buf + n, 4, 0, fmt);
                    n += put_value(buf + n, 4, 1, fmt);
                    if (fmt == 0) buf[n++] = '\n';
                    /* a triangle and a quad */
                    n += put_value(buf + n, ct, 3, fmt);
                    n += put_value(buf + n, it, 0, fmt);
                    n += put_value(buf + n, it, 1, fmt);
                    n += put_value(buf + n, it, 2, fmt);
                    n += put_value(buf + n, 1, 0, fmt);
                    if (fmt == 0) buf[n++] = '\n';
                    n += put_value(buf + n, ct, 4, fmt);
                    n += put_value(buf + n, it, 0, fmt);
                    n += put_value(buf + n, it, 1, fmt);
                    n += put_value(buf + n, it, 3, fmt);
                    n += put_value(buf + n, it, 2, fmt);
                    n += put_value(buf + n, 1, 1, fmt);
                    n += put_value(buf + n, 6, 0.5, fmt);
                    st = read_mem(buf, n, LS_MESH_FORMAT_AUTO, &m, &d);
                    if (st != LS_OK || m.vertex_count != 4 || m.face_count != 3) {
                        if (bad++ < 3) CHECK_MSG(0, "%s coord %s count %s index %s: %s (%s at %llu)", fmts[fmt], type_names[ci], type_names[ct], type_names[it],
                                                 ls_status_name(st), d.what, (unsigned long long)d.offset);
                        continue;
                    }
                    for (v = 0; v < 4; v++)
                        for (k = 0; k < 3; k++) {
                            double want = (ci == 1 || ci == 3 || ci == 5) ? fabs(pos[v][k]) : pos[v][k];
                            if (m.positions[3 * v + k] != (ls_real)want && bad++ < 3) CHECK_MSG(0, "%s %s: position %d.%d", fmts[fmt], type_names[ci], v, k);
                        }
                    {
                        static const uint32_t want[9] = {0, 1, 2, 0, 1, 3, 0, 3, 2};
                        if (memcmp(m.triangles, want, sizeof want) != 0 && bad++ < 3) CHECK_MSG(0, "%s: triangles", fmts[fmt]);
                    }
                    /* every truncation of a binary body fails cleanly */
                    if (fmt != 0 && ci == 7 && ct == 0 && it == 4) {
                        size_t cut, body = (size_t)(strstr((char *)buf, "end_header\r\n") - (char *)buf) + 12;
                        for (cut = body; cut < n; cut++) {
                            st = read_mem(buf, cut, LS_MESH_FORMAT_AUTO, &m, &d);
                            if ((st != LS_ERR_PARSE || d.has_offset == 0 || d.offset > cut) && bad++ < 3)
                                CHECK_MSG(0, "cut at %lu: %s %s", (unsigned long)cut, ls_status_name(st), d.what);
                        }
                        st = read_mem(buf, n - 1, LS_MESH_FORMAT_AUTO, &m, &d);
                        CHECK(st == LS_ERR_PARSE && strstr(d.what, "truncated") != NULL && d.offset == n - 4);
                    }
                }
    CHECK_EQ(bad, 0);
    free(buf);
}

/* Binary PLY doubles read into ls_real: the nearest value, ties to even
 * (compared with the compiler's conversion). */
static void ply_double_coordinates_round_correctly(void)
{
    enum { NV = 3000 };
    static unsigned char buf[200 + NV * 24 + 13];
    static double vals[3 * NV];
    uint64_t r = 0x2545F4914F6CDD1Dull;
    size_t n, i;
    ls_mesh m;
    ls_diag d;
    int bad = 0;
    n = (size_t)sprintf((char *)buf, "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\n"
                                     "property double y\nproperty double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
                        NV);
    for (i = 0; i < 3 * NV; i++) {
        uint64_t b;
        r ^= r << 13, r ^= r >> 7, r ^= r << 17;
        b = r;
        /* exponents around the float range and its subnormals, below 2^127 (beyond
         * float's range is LS_ERR_TOO_LARGE in the float build, checked below); ties too */
        b = (b & 0x800fffffffffffffull) | ((uint64_t)(1023 - 160 + (int)((r >> 20) % 287)) << 52);
        if (i % 7 == 0) b &= ~(uint64_t)0x0fffffff, b |= 0x10000000; /* exactly halfway between floats */
        if (i % 11 == 0) b &= 0x800fffffffffffffull;                  /* double subnormals */
        memcpy(&vals[i], &b, 8);
        n += put_value(buf + n, 7, vals[i], 1);
    }
    buf[n++] = 3;
    for (i = 0; i < 3; i++) n += put_value(buf + n, 4, (double)i, 1);
    CHECK_STATUS(read_mem(buf, n, LS_MESH_FORMAT_AUTO, &m, &d), LS_OK);
    for (i = 0; i < 3 * NV && m.vertex_count == NV; i++) {
        volatile double v = vals[i];
        ls_real want = (ls_real)v;
        if (!real_bits_equal(want, m.positions[i]) && bad++ < 3) CHECK_MSG(0, "value %.17g read as %.9g", vals[i], (double)m.positions[i]);
    }
    CHECK_EQ(bad, 0);
    /* one double beyond float's range: too large in the float build, kept in double */
    vals[0] = ldexp(1.0, 128);
    (void)put_value(buf + (n - 13 - 24 * NV), 7, vals[0], 1);
    CHECK_STATUS(read_mem(buf, n, LS_MESH_FORMAT_AUTO, &m, &d), LS_REAL_IS_FLOAT ? LS_ERR_TOO_LARGE : LS_OK);
}

static void off_variants(void)
{
    ls_mesh m;
    ls_diag d;
    /* comments before the keyword, counts on the keyword line, colours, blank lines, CR-only */
    CHECK_STATUS(read_str("# made by hand\n\nCOFF 4 2 0 # counts here\n"
                          "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n\n# a comment\n1 1 0 0 0 255 255\n0 1 0 1 1 1 1\n"
                          "3 0 1 2 .7 .7 .7\n3 0 2 3",
                          LS_MESH_FORMAT_AUTO, &m, &d),
                 LS_OK);
    CHECK(m.vertex_count == 4 && m.face_count == 2 && m.triangles[5] == 3 && m.positions[6] == 1);
    CHECK_STATUS(read_str("NOFF\r4 1\r0 0 0 0 0 1\r1 0 0 0 0 1\r1 1 0 0 0 1\r0 1 0 0 0 1\r4 0 1 2 3\r", LS_MESH_FORMAT_AUTO, &m, &d), LS_OK);
    CHECK(m.vertex_count == 4 && m.face_count == 2 && m.triangles[3] == 0 && m.triangles[4] == 2 && m.triangles[5] == 3);
    CHECK_STATUS(read_str("3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", LS_MESH_FORMAT_OFF, &m, &d), LS_OK);
    CHECK_EQ(m.face_count, 1);
    CHECK_STATUS(read_str("OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", LS_MESH_FORMAT_AUTO, &m, &d), LS_OK);
    CHECK_EQ(ls_mesh_format_guess("ply\r\n", 5), LS_MESH_FORMAT_PLY);
    CHECK_EQ(ls_mesh_format_guess("# c\nSTOFF\n", 10), LS_MESH_FORMAT_OFF);
    CHECK_EQ(ls_mesh_format_guess("v 1 2 3\n", 8), LS_MESH_FORMAT_OBJ);
}

/* --- writers ------------------------------------------------------------------ */

static int32_t fail_after(void *user, const void *data, size_t bytes)
{
    size_t *left = (size_t *)user;
    (void)data;
    if (bytes > *left) return 1;
    *left -= bytes;
    return 0;
}

static void write_then_read_gives_identical_bits(void)
{
    ls_mesh m, back;
    ls_diag d;
    unsigned char *file = NULL, *out = malloc(4u << 20);
    size_t n = 0, i;
    ls_membuf mb;
    ls_arena *a = fresh_arena();
    ls_real *p;
    REQUIRE(ls_posix_read_file("fixtures/meshes/bunny.obj", &file, &n) == LS_OK);
    REQUIRE(ls_mesh_read(file, n, LS_MESH_FORMAT_AUTO, a, &m, &d) == LS_OK);
    /* make the positions hard: random finite bit patterns, subnormals, -0, huge */
    p = m.positions;
    for (i = 0; i < 3 * (size_t)m.vertex_count; i++) {
        uint64_t r = (uint64_t)i * 0x9E3779B97F4A7C15ull;
        r ^= r >> 29;
        r *= 0xBF58476D1CE4E5B9ull;
        r ^= r >> 32;
        if (i % 5 == 0) {
#if LS_REAL_IS_FLOAT
            uint32_t b = (uint32_t)r;
            if ((b & 0x7f800000u) == 0x7f800000u) b &= 0xbfffffffu;
            memcpy(&p[i], &b, sizeof b);
#else
            if ((r & 0x7ff0000000000000ull) == 0x7ff0000000000000ull) r &= 0xbfffffffffffffffull;
            memcpy(&p[i], &r, sizeof r);
#endif
        }
    }
    p[0] = -(ls_real)0;
    p[1] = LS_REAL_MAX;
    p[2] = -LS_REAL_MAX;
    for (i = 0; i < 2; i++) {
        ls_status st;
        mb.data = out;
        mb.capacity = 4u << 20;
        mb.size = 0;
        mb.overflow = 0;
        st = i == 0 ? ls_mesh_write_obj(&m, ls_membuf_write, &mb) : ls_mesh_write_ply(&m, ls_membuf_write, &mb);
        CHECK_STATUS(st, LS_OK);
        st = ls_mesh_read(out, mb.size, LS_MESH_FORMAT_AUTO, a, &back, &d);
        CHECK_MSG(st == LS_OK, "%s: %s %s line %u", i ? "ply" : "obj", ls_status_name(st), d.what, d.line);
        if (st != LS_OK) continue;
        CHECK_EQ(back.vertex_count, m.vertex_count);
        CHECK_EQ(back.face_count, m.face_count);
        CHECK(memcmp(back.positions, m.positions, 3 * sizeof(ls_real) * m.vertex_count) == 0);
        CHECK(memcmp(back.triangles, m.triangles, 3 * sizeof(uint32_t) * m.face_count) == 0);
        if (i == 0) CHECK(memcmp(out, "v -0 ", 5) == 0);
        if (i == 1) CHECK(memcmp(out, "ply\nformat binary_little_endian 1.0\n", 36) == 0);
        /* a callback that fails at every point: LS_ERR_IO, never a crash */
        {
            size_t cut;
            int badio = 0;
            for (cut = 0; cut < mb.size; cut += mb.size / 37 + 1) {
                size_t left = cut;
                st = i == 0 ? ls_mesh_write_obj(&m, fail_after, &left) : ls_mesh_write_ply(&m, fail_after, &left);
                badio += st != LS_ERR_IO;
            }
            CHECK_EQ(badio, 0);
        }
    }
    /* an index out of range: nothing written */
    m.triangles[4] = m.vertex_count;
    mb.size = 0;
    CHECK_STATUS(ls_mesh_write_obj(&m, ls_membuf_write, &mb), LS_ERR_MESH);
    CHECK_STATUS(ls_mesh_write_ply(&m, ls_membuf_write, &mb), LS_ERR_MESH);
    CHECK_EQ(mb.size, 0);
    CHECK_STATUS(ls_mesh_write_obj(&m, NULL, &mb), LS_ERR_INVALID);
    free(out);
    free(file);
}

/* --- fuzzing --------------------------------------------------------------------- */

static void prefixes_and_byte_flips_never_crash(void)
{
    static const char *files[] = {"fixtures/meshes/assimp/PLY/cube.ply", "fixtures/meshes/assimp/PLY/cube_binary.ply",
                                  "fixtures/meshes/assimp/OBJ/box.obj", "fixtures/meshes/assimp/OFF/Cube.off"};
    static const char flips[] = {'\0', '\n', '\r', ' ', '-', '9', '/', '#', 'e', '.', '\xff'};
    uint64_t r = 88172645463325252ull;
    int fi, ok = 0, err = 0, other = 0;
    for (fi = 0; fi < 4; fi++) {
        unsigned char *d = NULL, *c;
        size_t n = 0, cut;
        int k;
        REQUIRE(ls_posix_read_file(files[fi], &d, &n) == LS_OK);
        c = malloc(n);
        for (cut = 0; cut <= n; cut++) {
            ls_mesh m;
            ls_diag dg;
            ls_status st;
            memcpy(c, d, cut);
            st = read_mem(c, cut, LS_MESH_FORMAT_AUTO, &m, &dg);
            if (st == LS_OK) ok++;
            else if (st == LS_ERR_PARSE || st == LS_ERR_MESH || st == LS_ERR_UNSUPPORTED || st == LS_ERR_TOO_LARGE ||
                     st == LS_ERR_NONFINITE) err++;
            else other++;
        }
        for (k = 0; k < 3000; k++) {
            ls_mesh m;
            ls_diag dg;
            ls_status st;
            memcpy(c, d, n);
            r ^= r << 13, r ^= r >> 7, r ^= r << 17;
            c[r % n] = (unsigned char)flips[(r >> 32) % sizeof flips];
            r ^= r << 13, r ^= r >> 7, r ^= r << 17;
            if (k % 2) c[r % n] = (unsigned char)(r >> 40);
            st = read_mem(c, n, LS_MESH_FORMAT_AUTO, &m, &dg);
            if (st == LS_OK) {
                /* whatever was accepted is a consistent mesh */
                uint32_t t;
                for (t = 0; t < 3 * m.face_count; t++) other += m.triangles[t] >= m.vertex_count;
                ok++;
            } else if (st == LS_ERR_PARSE || st == LS_ERR_MESH || st == LS_ERR_UNSUPPORTED || st == LS_ERR_TOO_LARGE ||
                     st == LS_ERR_NONFINITE) {
                err++;
                other += dg.what == NULL || dg.what[0] == 0;
            } else {
                other++;
            }
        }
        free(c);
        free(d);
    }
    CHECK_EQ(other, 0);
    CHECK(ok > 100 && err > 100);
}

/* NaN and infinite coordinates are rejected (found by tests/fuzz/fuzz_ply), in
 * text and binary files, with the place named. */
static void nonfinite_coordinates_rejected(void)
{
    static const char *const texts[] = {"v nan 0 0\nv 0 1 0\nv 1 0 0\nf 1 2 3\n",
                                        "v 0 0 0\nv 0 -INF 0\nv 1 0 0\nf 1 2 3\n",
                                        "OFF\n3 1 0\n0 0 0\n0 1 infinity\n1 0 0\n3 0 1 2\n",
                                        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                        "0 0 0\n0 1 0\n1 0 -nan\n3 0 1 2\n"};
    static const unsigned char ply_le[] = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                          "property float y\nproperty float z\nelement face 1\n"
                                          "property list uchar int vertex_indices\nend_header\n";
    static const uint32_t lines[] = {1, 2, 4, 12};
    unsigned char bin[sizeof ply_le - 1 + 36 + 13];
    size_t i, h = sizeof ply_le - 1;
    ls_mesh m;
    ls_diag dg;
    for (i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        CHECK_STATUS(read_str(texts[i], LS_MESH_FORMAT_AUTO, &m, &dg), LS_ERR_NONFINITE);
        CHECK_MSG(dg.has_line && dg.line == lines[i] && dg.what != NULL && strstr(dg.what, "NaN") != NULL, "text %d: line %u what %s",
                  (int)i, (unsigned)dg.line, dg.what);
    }
    memcpy(bin, ply_le, h);
    memset(bin + h, 0, sizeof bin - h);
    bin[h + 4 * 4 + 2] = 0x80, bin[h + 4 * 4 + 3] = 0x7f; /* vertex 1's y = +inf (0x7f800000) */
    bin[h + 36] = 3, bin[h + 36 + 5] = 1, bin[h + 36 + 9] = 2;
    CHECK_STATUS(read_mem(bin, sizeof bin, LS_MESH_FORMAT_AUTO, &m, &dg), LS_ERR_NONFINITE);
    CHECK(dg.has_offset && dg.offset == h + 16);
}

/* --- sweep ------------------------------------------------------------------------ */

typedef struct read_ctx {
    const unsigned char *data;
    size_t n;
    ls_mesh m;
} read_ctx;

static ls_status read_run(void *ctx, ls_arena *a)
{
    read_ctx *c = (read_ctx *)ctx;
    return ls_mesh_read(c->data, c->n, LS_MESH_FORMAT_AUTO, a, &c->m, NULL);
}

static uint64_t read_hash(void *ctx)
{
    read_ctx *c = (read_ctx *)ctx;
    return test_hash(&c->m, sizeof c->m, test_hash(c->data, c->n, TEST_HASH_SEED));
}

static void read_reset(void *ctx)
{
    read_ctx *c = (read_ctx *)ctx;
    memset(&c->m, 0, sizeof c->m);
}

static void reader_arena_sweep(void)
{
    static const char *files[] = {"fixtures/meshes/bunny.obj", "fixtures/meshes/assimp/PLY/cube_binary.ply", "fixtures/meshes/assimp/OFF/Cube.off"};
    int fi;
    for (fi = 0; fi < 3; fi++) {
        read_ctx c;
        sweep_job job;
        ls_mesh_file_info info;
        unsigned char *d = NULL;
        size_t n = 0, bytes = 0, want = 0;
        REQUIRE(ls_posix_read_file(files[fi], &d, &n) == LS_OK);
        CHECK_STATUS(ls_mesh_read_info(d, n, LS_MESH_FORMAT_AUTO, &info, NULL), LS_OK);
        CHECK_STATUS(ls_mesh_read_bytes(&info, &bytes), LS_OK);
        CHECK_STATUS(ls_mesh_bytes(info.vertex_count, info.face_count, &want), LS_OK);
        CHECK_EQ(bytes, want);
        CHECK_EQ(info.binary, fi == 1);
        memset(&c, 0, sizeof c);
        c.data = d;
        c.n = n;
        memset(&job, 0, sizeof job);
        job.name = files[fi];
        job.run = read_run;
        job.state_hash = read_hash;
        job.reset = read_reset;
        job.ctx = &c;
        job.answer = bytes;
        job.exact = 1;
        CHECK_EQ(sweep_arena(&job), 0);
        free(d);
    }
}

static int bench(const char *path, int repeats)
{
    unsigned char *d = NULL;
    size_t n = 0;
    static LS_ARENA_BUFFER(work, 64u << 20);
    ls_arena a;
    ls_mesh m;
    ls_diag dg;
    int i;
    double best = 1e30, best_cpu = 1e30;
    if (ls_posix_read_file(path, &d, &n) != LS_OK) {
        printf("cannot read %s\n", path);
        return 1;
    }
    for (i = 0; i < repeats; i++) {
        uint64_t t0, t1;
        clock_t c0, c1;
        ls_status st;
        ls_arena_init(&a, work.bytes, sizeof work.bytes);
        c0 = clock();
        t0 = ls_posix_clock_ns(NULL);
        st = ls_mesh_read(d, n, LS_MESH_FORMAT_AUTO, &a, &m, &dg);
        t1 = ls_posix_clock_ns(NULL);
        c1 = clock();
        if ((double)(c1 - c0) / CLOCKS_PER_SEC < best_cpu) best_cpu = (double)(c1 - c0) / CLOCKS_PER_SEC;
        if (st != LS_OK) {
            printf("%s: %s %s\n", path, ls_status_name(st), dg.what);
            return 1;
        }
        if ((double)(t1 - t0) < best) best = (double)(t1 - t0);
    }
    printf("%s: %lu bytes, %u vertices, %u triangles, best of %d: %.2f ms wall, %.1f MB/s; %.2f ms cpu, %.1f MB/s "
           "(both passes, ls_real = %s)\n",
           path, (unsigned long)n, m.vertex_count, m.face_count, repeats, best / 1e6, (double)n / (best / 1e9) / 1e6,
           best_cpu * 1e3, best_cpu > 0 ? (double)n / best_cpu / 1e6 : 0.0, LS_REAL_NAME);
    free(d);
    return 0;
}

int main(int argc, char **argv)
{
    TEST_INIT("test_mesh_io");
    if (argc > 2 && strcmp(argv[1], "--bench") == 0) return bench(argv[2], argc > 3 ? atoi(argv[3]) : 10);
    TEST_RUN(obj_fixtures_match_strtod);
    TEST_RUN(obj_features);
    TEST_RUN(malformed_text_inputs);
    TEST_RUN(nonfinite_coordinates_rejected);
    TEST_RUN(assimp_files);
    TEST_RUN(ply_every_type_and_byte_order);
    TEST_RUN(ply_double_coordinates_round_correctly);
    TEST_RUN(off_variants);
    TEST_RUN(write_then_read_gives_identical_bits);
    TEST_RUN(prefixes_and_byte_flips_never_crash);
    TEST_RUN(reader_arena_sweep);
    return TEST_END();
}
