/* test_laplacian.c - Laplacians against hand-computed entries and an
 * independent angle formula, the system matrix, the regularizers (against
 * dense products), and arena sweeps. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include "../port/posix/ls_posix.h"

static LS_ARENA_BUFFER(buf_, 1 << 20);
#define BUF buf_.bytes

static ls_arena fresh(void)
{
    ls_arena a;
    ls_arena_init(&a, BUF, sizeof BUF);
    return a;
}

/* dense n x n from a CSC (both triangles filled from an upper one) */
static void to_dense(const ls_csc *m, int upper, double *d)
{
    uint32_t j, p, n = m->ncols;
    memset(d, 0, sizeof(double) * n * n);
    for (j = 0; j < n; j++)
        for (p = m->colptr[j]; p < m->colptr[j + 1]; p++) {
            uint32_t i = m->rowidx[p];
            d[i * n + j] = (double)m->values[p];
            if (upper) d[j * n + i] = (double)m->values[p];
        }
}

static ls_real tet_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static uint32_t tet_tri[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

/* hexagon fan of unit equilateral triangles: centre 0, ring 1..6 */
static ls_real hex_pos[21];
static uint32_t hex_tri[18];
static void make_hex(ls_mesh *m)
{
    int k;
    hex_pos[0] = hex_pos[1] = hex_pos[2] = 0;
    for (k = 0; k < 6; k++) {
        double a = (double)k * 3.14159265358979323846 / 3.0;
        hex_pos[3 * (k + 1)] = (ls_real)cos(a);
        hex_pos[3 * (k + 1) + 1] = (ls_real)sin(a);
        hex_pos[3 * (k + 1) + 2] = 0;
        hex_tri[3 * k] = 0;
        hex_tri[3 * k + 1] = (uint32_t)(k + 1);
        hex_tri[3 * k + 2] = (uint32_t)((k + 1) % 6 + 1);
    }
    m->positions = hex_pos;
    m->triangles = hex_tri;
    m->vertex_count = 7;
    m->face_count = 6;
}

static void tetra_uniform_and_cot_by_hand(void)
{
    ls_mesh m = {tet_pos, tet_tri, 4, 4};
    ls_arena a = fresh();
    ls_csc L;
    double d[16], r3 = 1.0 / sqrt(3.0);
    uint32_t clamped = 99, i, j, conv;
    CHECK_STATUS(ls_laplacian_uniform(&m, LS_LAP_FULL, &a, &L, NULL), LS_OK);
    to_dense(&L, 0, d);
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) CHECK_NEAR(d[i * 4 + j], i == j ? 3.0 : -1.0, 0);
    CHECK_EQ(ls_csc_nnz(&L), 16);
    for (conv = 0; conv < 2; conv++) {
        double s = conv == LS_COT_HALF ? 0.5 : 1.0;
        CHECK_STATUS(ls_laplacian_cot(&m, conv, LS_LAP_UPPER, &a, &L, &clamped, NULL), LS_OK);
        CHECK_EQ(clamped, 0);
        CHECK_EQ(ls_csc_nnz(&L), 10);
        to_dense(&L, 1, d);
        /* edges at the right-angled corner 0: two 45-degree opposite angles, cot 1 each;
         * edges of the equilateral face: cot 60 = 1/sqrt 3 once (the other face's angle is 90) */
        CHECK_NEAR(d[0 * 4 + 1], -2.0 * s, TEST_EPS(8));
        CHECK_NEAR(d[0 * 4 + 3], -2.0 * s, TEST_EPS(8));
        CHECK_NEAR(d[1 * 4 + 2], -r3 * s, TEST_EPS(8));
        CHECK_NEAR(d[2 * 4 + 3], -r3 * s, TEST_EPS(8));
        CHECK_NEAR(d[0], 6.0 * s, TEST_EPS(16));
        CHECK_NEAR(d[1 * 4 + 1], (2.0 + 2.0 * r3) * s, TEST_EPS(16));
        CHECK_NEAR(d[3 * 4 + 3], (2.0 + 2.0 * r3) * s, TEST_EPS(16));
    }
}

static void equilateral_fan_by_hand(void)
{
    ls_mesh m;
    ls_arena a = fresh();
    ls_csc L;
    double d[49], r3 = 1.0 / sqrt(3.0);
    uint32_t k;
    make_hex(&m);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    to_dense(&L, 1, d);
    CHECK_NEAR(d[0], 6, 0);
    for (k = 1; k <= 6; k++) {
        CHECK_NEAR(d[k * 7 + k], 3, 0);
        CHECK_NEAR(d[k], -1, 0);
        CHECK_NEAR(d[k * 7 + (k % 6 + 1)], -1, 0);
        CHECK_NEAR(d[k * 7 + ((k + 2) % 6 + 1)], 0, 0); /* opposite ring vertex: no edge */
    }
    REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_FULL, &a, &L, NULL, NULL) == LS_OK);
    to_dense(&L, 0, d);
    CHECK_NEAR(d[0], 12.0 * r3, TEST_EPS(64));
    for (k = 1; k <= 6; k++) {
        CHECK_NEAR(d[k], -2.0 * r3, TEST_EPS(16));                    /* interior edge: two 60-degree angles */
        CHECK_NEAR(d[k * 7 + (k % 6 + 1)], -r3, TEST_EPS(16));        /* boundary edge: one */
        CHECK_NEAR(d[k * 7 + k], 4.0 * r3, TEST_EPS(32));
    }
}

/* rows sum to zero, full storage symmetric, upper storage = the full's upper triangle, bit for bit */
static void row_sums_symmetry_and_storages_agree(void)
{
    ls_mesh m;
    ls_arena a = fresh();
    ls_csc U, F;
    static double du[49], df[49];
    uint32_t i, j, kind;
    make_hex(&m);
    hex_pos[3 * 2 + 2] = (ls_real)0.3; /* not flat: unequal weights */
    hex_pos[3 * 5] = (ls_real)-0.7;
    for (kind = 0; kind < 2; kind++) {
        if (kind == 0) {
            REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &U, NULL, NULL) == LS_OK);
            REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_FULL, &a, &F, NULL, NULL) == LS_OK);
        } else {
            REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &U, NULL) == LS_OK);
            REQUIRE(ls_laplacian_uniform(&m, LS_LAP_FULL, &a, &F, NULL) == LS_OK);
        }
        to_dense(&U, 1, du);
        to_dense(&F, 0, df);
        for (i = 0; i < 7; i++) {
            double s = 0, mag = 0;
            for (j = 0; j < 7; j++) {
                s += df[i * 7 + j];
                mag += fabs(df[i * 7 + j]);
                CHECK(df[i * 7 + j] == df[j * 7 + i]);
                CHECK(du[i * 7 + j] == df[i * 7 + j]);
            }
            CHECK_NEAR(s, 0, mag * TEST_EPS(8));
        }
    }
    make_hex(&m);
}

static uint64_t rs = 0x9E3779B97F4A7C15ull;
static double urand(void)
{
    return test_rng_unit(&rs);
}

/* one triangle: L_ij = -cot(angle at the third corner), the angle by atan2(|cross|, dot) */
static void cot_weights_match_angles_on_random_triangles(void)
{
    int t, worst_t = -1;
    double worst = 0;
    for (t = 0; t < 2000; t++) {
        ls_real pos[9];
        uint32_t tri[3] = {0, 1, 2}, c;
        ls_mesh m = {pos, tri, 3, 1};
        ls_arena a = fresh();
        ls_csc L;
        double d[9], cot_ref[3], area2;
        int k;
        for (k = 0; k < 9; k++) pos[k] = (ls_real)(urand() * 4.0 - 2.0);
        REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_FULL, &a, &L, &c, NULL) == LS_OK);
        to_dense(&L, 0, d);
        {
            double e1[3], e2[3], cr[3];
            for (k = 0; k < 3; k++) {
                e1[k] = (double)pos[3 + k] - (double)pos[k];
                e2[k] = (double)pos[6 + k] - (double)pos[k];
            }
            cr[0] = e1[1] * e2[2] - e1[2] * e2[1];
            cr[1] = e1[2] * e2[0] - e1[0] * e2[2];
            cr[2] = e1[0] * e2[1] - e1[1] * e2[0];
            area2 = 0.25 * (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        }
        if (area2 < 0.01) continue; /* keep the comparison well conditioned */
        for (k = 0; k < 3; k++) {
            /* angle at corner k between the edges to the other two corners */
            int a1 = (k + 1) % 3, a2 = (k + 2) % 3, q;
            double u[3], v[3], cr[3], dt = 0;
            for (q = 0; q < 3; q++) {
                u[q] = (double)pos[3 * a1 + q] - (double)pos[3 * k + q];
                v[q] = (double)pos[3 * a2 + q] - (double)pos[3 * k + q];
                dt += u[q] * v[q];
            }
            cr[0] = u[1] * v[2] - u[2] * v[1];
            cr[1] = u[2] * v[0] - u[0] * v[2];
            cr[2] = u[0] * v[1] - u[1] * v[0];
            cot_ref[k] = 1.0 / tan(atan2(sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), dt));
        }
        for (k = 0; k < 3; k++) {
            int i = (k + 1) % 3, j = (k + 2) % 3;
            double err = fabs(-d[i * 3 + j] - cot_ref[k]) / (1.0 + fabs(cot_ref[k]));
            if (err > worst) {
                worst = err;
                worst_t = t;
            }
        }
    }
    printf("     cot vs atan2 angles: worst error %.3g (relative to 1 + |cot|) at triangle %d\n", worst, worst_t);
    CHECK(worst < (LS_REAL_IS_FLOAT ? 2e-4 : 1e-11));
}

static void degenerate_faces_are_clamped_and_counted(void)
{
    /* face 0 collinear (zero area), face 1 a needle of area 1e-9, face 2 fine,
     * face 3 repeats an index (skipped) */
    ls_real pos[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 0.5f, 2e-9f, 0};
    uint32_t tri[] = {0, 1, 2, 0, 1, 4, 0, 1, 3, 0, 0, 3};
    ls_mesh m = {pos, tri, 5, 4};
    ls_arena a = fresh();
    ls_csc L;
    uint32_t clamped = 0, p;
    int finite = 1;
    CHECK_STATUS(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &L, &clamped, NULL), LS_OK);
    CHECK_EQ(clamped, 2);
    for (p = 0; p < ls_csc_nnz(&L); p++) finite &= isfinite((double)L.values[p]) != 0;
    CHECK(finite);
    /* edge (0,1): opposite corner 2 in the collinear face: dot 2, area clamped
     * to 1e-6: cot 1e6; corner 4 of the needle: dot -0.25: cot -125000;
     * corner 3 of the good face: cot 1 */
    {
        double d[25];
        to_dense(&L, 1, d);
        CHECK_NEAR(d[0 * 5 + 1], -875001.0, 875001.0 * TEST_EPS(16));
    }
    {
        ls_real bad[15];
        ls_diag dg;
        memcpy(bad, pos, sizeof bad);
        bad[7] = (ls_real)NAN;
        m.positions = bad;
        CHECK_STATUS(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &L, NULL, &dg), LS_ERR_NONFINITE);
        CHECK_EQ(dg.index, 2);
    }
}

/* no faces (or only degenerate ones): every vertex keeps its zero diagonal entry */
static void isolated_vertices_keep_a_diagonal(void)
{
    uint32_t tri[] = {0, 0, 1};
    ls_mesh m = {tet_pos, tri, 4, 0};
    ls_arena a = fresh();
    ls_csc L, M;
    uint32_t j, f;
    for (f = 0; f < 2; f++) {
        m.face_count = f;
        REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &L, NULL, NULL) == LS_OK);
        CHECK_EQ(ls_csc_nnz(&L), 4);
        for (j = 0; j < 4; j++) CHECK(L.rowidx[j] == j && L.values[j] == 0);
        REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_ALPHA, (ls_real)0.5, &a, &M, NULL) == LS_OK);
        for (j = 0; j < 4; j++) CHECK(M.values[j] == (ls_real)0.5);
    }
    {
        uint32_t bad[] = {0, 1, 7};
        ls_diag dg;
        m.triangles = bad;
        m.face_count = 1;
        CHECK_STATUS(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, &dg), LS_ERR_MESH);
        CHECK_STATUS(ls_laplacian_uniform(&m, 5u, &a, &L, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "storage") != NULL);
        CHECK_STATUS(ls_laplacian_cot(&m, 9u, LS_LAP_UPPER, &a, &L, NULL, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "convention") != NULL);
        CHECK_STATUS(ls_laplacian_cot(NULL, LS_COT_HALF, LS_LAP_UPPER, &a, &L, NULL, &dg), LS_ERR_INVALID);
        CHECK(strcmp(dg.what, "mesh is NULL") == 0);
    }
}

static void grid_laplacian_matches_neighbour_count(void)
{
    static const uint32_t sizes[][2] = {{1, 1}, {5, 1}, {1, 4}, {3, 4}, {6, 5}};
    size_t s;
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        uint32_t nx = sizes[s][0], ny = sizes[s][1], n = nx * ny, i, j, st;
        static double d[900];
        for (st = 0; st < 2; st++) {
            ls_arena a = fresh();
            ls_csc L;
            size_t bytes = 0;
            REQUIRE(ls_laplacian_grid_bytes(nx, ny, st, &bytes) == LS_OK);
            REQUIRE(ls_laplacian_grid(nx, ny, st, &a, &L) == LS_OK);
            CHECK_EQ(a.peak, bytes);
            to_dense(&L, st == LS_LAP_UPPER, d);
            for (i = 0; i < n; i++)
                for (j = 0; j < n; j++) {
                    uint32_t xi = i % nx, yi = i / nx, xj = j % nx, yj = j / nx;
                    int adj = (yi == yj && (xi + 1 == xj || xj + 1 == xi)) || (xi == xj && (yi + 1 == yj || yj + 1 == yi));
                    double want = adj ? -1.0 : 0.0;
                    if (i == j) want = (xi > 0) + (xi + 1 < nx) + (yi > 0) + (yi + 1 < ny);
                    CHECK_NEAR(d[i * n + j], want, 0);
                }
        }
    }
    {
        ls_arena a = fresh();
        ls_csc L;
        size_t b;
        CHECK_STATUS(ls_laplacian_grid(0, 3, LS_LAP_UPPER, &a, &L), LS_ERR_INVALID);
        CHECK_STATUS(ls_laplacian_grid_bytes(65536, 65536, LS_LAP_UPPER, &b), LS_ERR_TOO_LARGE);
    }
}

static void system_matrix_forms_and_update(void)
{
    ls_mesh m = {tet_pos, tet_tri, 4, 4};
    ls_arena a = fresh();
    ls_csc L, M;
    ls_real *vals;
    ls_diag dg;
    double dl[16], dm[16];
    uint32_t i;
    REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &L, NULL, NULL) == LS_OK);
    to_dense(&L, 1, dl);
    REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)19, &a, &M, NULL) == LS_OK);
    CHECK(M.colptr == L.colptr && M.rowidx == L.rowidx && M.values != L.values);
    to_dense(&M, 1, dm);
    for (i = 0; i < 16; i++) CHECK_NEAR(dm[i], (i % 5 == 0 ? 1.0 : 0.0) + 19.0 * dl[i], TEST_EPS(64));
    vals = M.values;
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_ALPHA, (ls_real)0.95, &M, NULL), LS_OK);
    CHECK(M.values == vals);
    to_dense(&M, 1, dm);
    for (i = 0; i < 16; i++) CHECK_NEAR(dm[i], (i % 5 == 0 ? 0.05 : 0.0) + 0.95 * dl[i], TEST_EPS(64));
    /* alpha = 0.95 is (1 - alpha)(I + 19 L) */
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_ALPHA, (ls_real)1, &M, &dg), LS_ERR_INVALID);
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_ALPHA, (ls_real)-0.1, &M, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "weight: alpha") != NULL);
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_LAMBDA, (ls_real)-1, &M, &dg), LS_ERR_INVALID);
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_LAMBDA, (ls_real)NAN, &M, &dg), LS_ERR_INVALID);
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_LAMBDA, (ls_real)INFINITY, &M, &dg), LS_ERR_INVALID);
    CHECK_STATUS(ls_laplacian_system_update(&L, 7u, (ls_real)1, &M, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "form") != NULL);
    CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_LAMBDA, (ls_real)1, NULL, &dg), LS_ERR_INVALID);
    CHECK(strcmp(dg.what, "m is NULL") == 0);
    CHECK_STATUS(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)1, NULL, &M, &dg), LS_ERR_INVALID);
    CHECK(strcmp(dg.what, "arena is NULL") == 0);
    to_dense(&M, 1, dl);
    for (i = 0; i < 16; i++) CHECK(dl[i] == dm[i]); /* unchanged by the failures */
    /* lambda = 1e8: the identity rounds away in float (degree-3 diagonal 6 * 1e8), not in double */
    {
        ls_status st = ls_laplacian_system_update(&L, LS_SYSTEM_LAMBDA, (ls_real)1e8, &M, &dg);
        CHECK_STATUS(st, LS_REAL_IS_FLOAT ? LS_ERR_NOT_SPD : LS_OK);
        if (st != LS_OK) CHECK(dg.has_value && dg.value == (ls_real)1e8);
        CHECK_STATUS(ls_laplacian_system_update(&L, LS_SYSTEM_LAMBDA, (ls_real)1e17, &M, &dg), LS_ERR_NOT_SPD);
    }
}

static void regularizers_match_dense_products(void)
{
    ls_mesh m;
    ls_arena a = fresh();
    ls_csc L;
    ls_real x[21], g[21], gb[21], value = 0, bvalue = 0;
    double d[49], lx[21], llx[21], e = 0, b = 0;
    uint32_t i, j, c;
    make_hex(&m);
    REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &L, NULL, NULL) == LS_OK);
    to_dense(&L, 1, d);
    for (i = 0; i < 21; i++) x[i] = (ls_real)(urand() - 0.5);
    for (i = 0; i < 7; i++)
        for (c = 0; c < 3; c++) {
            lx[i * 3 + c] = 0;
            for (j = 0; j < 7; j++) lx[i * 3 + c] += d[i * 7 + j] * (double)x[j * 3 + c];
        }
    for (i = 0; i < 7; i++)
        for (c = 0; c < 3; c++) {
            llx[i * 3 + c] = 0;
            for (j = 0; j < 7; j++) llx[i * 3 + c] += d[i * 7 + j] * lx[j * 3 + c];
        }
    for (i = 0; i < 21; i++) {
        e += (double)x[i] * lx[i];
        b += lx[i] * lx[i];
    }
    CHECK_STATUS(ls_laplacian_energy(&L, 3, x, (ls_real)0.7, &value, g, NULL), LS_OK);
    CHECK_STATUS(ls_laplacian_bilaplacian(&L, 3, x, (ls_real)0.7, &bvalue, gb, &a), LS_OK);
    CHECK_NEAR(value, 0.7 * e, TEST_EPS(64) * 10);
    CHECK_NEAR(bvalue, 0.7 * b, TEST_EPS(64) * 100);
    for (i = 0; i < 21; i++) {
        CHECK_NEAR(g[i], 1.4 * lx[i], TEST_EPS(64) * 10);
        CHECK_NEAR(gb[i], 1.4 * llx[i], TEST_EPS(64) * 100);
    }
    /* value only: scratch from the arena */
    {
        ls_real v2 = 0;
        CHECK_STATUS(ls_laplacian_energy(&L, 3, x, (ls_real)0.7, &v2, NULL, &a), LS_OK);
        CHECK(v2 == value);
    }
}

/* ---- arena sweeps ------------------------------------------------------- */

typedef struct lap_job {
    ls_mesh mesh;
    uint32_t kind; /* 0 uniform, 1 cot, 2 grid, 3 system, 4 energy (value only), 5 bilaplacian */
    uint32_t storage;
    ls_csc out, lap;
    ls_real x[21], value;
} lap_job;

static ls_status lap_run(void *ctx, ls_arena *a)
{
    lap_job *j = (lap_job *)ctx;
    switch (j->kind) {
    case 0: return ls_laplacian_uniform(&j->mesh, j->storage, a, &j->out, NULL);
    case 1: return ls_laplacian_cot(&j->mesh, LS_COT_HALF, j->storage, a, &j->out, NULL, NULL);
    case 2: return ls_laplacian_grid(7, 3, j->storage, a, &j->out);
    case 3: return ls_laplacian_system(&j->lap, LS_SYSTEM_LAMBDA, (ls_real)2, a, &j->out, NULL);
    case 4: return ls_laplacian_energy(&j->lap, 3, j->x, (ls_real)1, &j->value, NULL, a);
    default: return ls_laplacian_bilaplacian(&j->lap, 3, j->x, (ls_real)1, &j->value, NULL, a);
    }
}

static uint64_t lap_hash(void *ctx)
{
    lap_job *j = (lap_job *)ctx;
    uint64_t h = test_hash(&j->out, sizeof j->out, TEST_HASH_SEED);
    h = test_hash(&j->value, sizeof j->value, h);
    return test_hash(hex_pos, sizeof hex_pos, h);
}

static void sweeps(void)
{
    static lap_job j;
    ls_arena a = fresh();
    uint32_t kind, st;
    make_hex(&j.mesh);
    REQUIRE(ls_laplacian_uniform(&j.mesh, LS_LAP_UPPER, &a, &j.lap, NULL) == LS_OK);
    for (kind = 0; kind < 6; kind++)
        for (st = 0; st < 2; st++) {
            sweep_job job;
            size_t bytes = 0;
            j.kind = kind;
            j.storage = st;
            memset(&j.out, 0, sizeof j.out);
            if (kind <= 1) REQUIRE(ls_laplacian_bytes(7, 6, 12, st, &bytes) == LS_OK);
            if (kind == 2) REQUIRE(ls_laplacian_grid_bytes(7, 3, st, &bytes) == LS_OK);
            if (kind == 3) REQUIRE(ls_laplacian_system_bytes(&j.lap, &bytes) == LS_OK);
            if (kind >= 4) REQUIRE(ls_laplacian_energy_bytes(&j.lap, 3, kind == 5, 0, &bytes) == LS_OK);
            memset(&job, 0, sizeof job);
            job.name = "laplacian";
            job.run = lap_run;
            job.state_hash = lap_hash;
            job.ctx = &j;
            job.answer = bytes;
            job.exact = 1;
            CHECK_MSG(sweep_arena(&job) == 0, "sweep kind %u storage %u", kind, st);
        }
}

/* the bunny: the uniform Laplacian's degrees are the edge counts */
static void bunny_laplacians(void)
{
    unsigned char *data = NULL;
    size_t n = 0, bytes = 0;
    ls_arena a = fresh();
    ls_mesh m;
    ls_mesh_report rep;
    ls_csc U, C;
    uint32_t clamped = 0, j;
    double trace = 0;
    int finite = 1;
    REQUIRE(ls_posix_read_file("fixtures/meshes/bunny.obj", &data, &n) == LS_OK);
    REQUIRE(ls_mesh_read(data, n, LS_MESH_FORMAT_AUTO, &a, &m, NULL) == LS_OK);
    free(data);
    REQUIRE(ls_mesh_validate(&m, &a, &rep) == LS_OK);
    REQUIRE(ls_laplacian_bytes(m.vertex_count, m.face_count, rep.edge_count, LS_LAP_UPPER, &bytes) == LS_OK);
    {
        ls_arena_mark mk = ls_arena_save(&a);
        size_t used = ls_arena_used(&a);
        ls_arena_reset_peak(&a);
        REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &U, NULL) == LS_OK);
        CHECK_EQ(a.peak - used, bytes);
        (void)mk;
    }
    CHECK_EQ(ls_csc_nnz(&U), rep.edge_count + m.vertex_count);
    for (j = 0; j < m.vertex_count; j++) trace += (double)U.values[U.colptr[j + 1] - 1];
    CHECK_NEAR(trace, 2.0 * rep.edge_count, 0);
    REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &C, &clamped, NULL) == LS_OK);
    for (j = 0; j < ls_csc_nnz(&C); j++) finite &= isfinite((double)C.values[j]) != 0;
    CHECK(finite);
    printf("     bunny: %u vertices, %u edges, cot faces clamped %u\n", m.vertex_count, rep.edge_count, clamped);
}

int main(void)
{
    TEST_INIT("test_laplacian");
    TEST_RUN(tetra_uniform_and_cot_by_hand);
    TEST_RUN(equilateral_fan_by_hand);
    TEST_RUN(row_sums_symmetry_and_storages_agree);
    TEST_RUN(cot_weights_match_angles_on_random_triangles);
    TEST_RUN(degenerate_faces_are_clamped_and_counted);
    TEST_RUN(isolated_vertices_keep_a_diagonal);
    TEST_RUN(grid_laplacian_matches_neighbour_count);
    TEST_RUN(system_matrix_forms_and_update);
    TEST_RUN(regularizers_match_dense_products);
    TEST_RUN(sweeps);
    TEST_RUN(bunny_laplacians);
    return TEST_END();
}
