/* test_sparse.c - CSC matrices against dense references. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>

static uint64_t rng_state = 88172645463325252ull;
static uint32_t rnd(void)
{
    return (uint32_t)test_rng_bits(&rng_state);
}

#define NT 400
#define NR 17
#define NC 13

static uint32_t tr[NT], tc[NT];
static ls_real tv[NT];

static void make_triplets(void)
{
    int t;
    for (t = 0; t < NT; t++) {
        tr[t] = rnd() % NR;
        tc[t] = rnd() % NC;
        tv[t] = (ls_real)((int)(rnd() % 2001) - 1000) / (ls_real)64; /* exact in float */
    }
}

/* dense reference, summing in input order */
static void dense_ref(double *d)
{
    int t;
    memset(d, 0, sizeof(double) * NR * NC);
    for (t = 0; t < NT; t++) d[tr[t] * NC + tc[t]] += (double)tv[t];
}

static void csc_to_dense(const ls_csc *m, double *d)
{
    uint32_t j, p;
    memset(d, 0, sizeof(double) * m->nrows * m->ncols);
    for (j = 0; j < m->ncols; j++)
        for (p = m->colptr[j]; p < m->colptr[j + 1]; p++) d[m->rowidx[p] * m->ncols + j] += (double)m->values[p];
}

static LS_ARENA_BUFFER(big_buffer, 1 << 20);
#define big big_buffer.bytes

static void sparse_from_triplets_matches_dense(void)
{
    ls_arena arena;
    ls_csc m;
    double d[NR * NC], e[NR * NC];
    uint32_t j, p;
    int i;
    make_triplets();
    REQUIRE(ls_arena_init(&arena, big, sizeof big) == LS_OK);
    CHECK_STATUS(ls_csc_from_triplets(&(ls_triplets){NR, NC, NT, tr, tc, tv}, &arena, &m, NULL), LS_OK);
    csc_to_dense(&m, e);
    dense_ref(d);
    for (i = 0; i < NR * NC; i++) CHECK(d[i] == e[i]); /* multiples of 1/64: exact */
    /* rows strictly ascending in each column (duplicates summed) */
    for (j = 0; j < m.ncols; j++)
        for (p = m.colptr[j] + 1; p < m.colptr[j + 1]; p++) CHECK(m.rowidx[p - 1] < m.rowidx[p]);
    CHECK(ls_csc_nnz(&m) <= NR * NC);
    CHECK(ls_arena_used(&arena) > 0 && arena.top == 0);
}

static void sparse_from_triplets_errors(void)
{
    ls_arena arena;
    ls_csc m;
    ls_diag dg;
    uint32_t r[3] = {0, 5, 1}, c[3] = {0, 1, 1};
    REQUIRE(ls_arena_init(&arena, big, sizeof big) == LS_OK);
    CHECK_STATUS(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, r, c, NULL}, &arena, &m, &dg), LS_ERR_INVALID);
    CHECK(dg.has_index && dg.index == 1);
    CHECK(strstr(dg.what, "t->rows") != NULL);
    CHECK(ls_arena_used(&arena) == 0);
    CHECK_STATUS(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, NULL, c, NULL}, &arena, &m, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, NULL, c, NULL}, &arena, &m, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "t->rows") != NULL);
    CHECK_STATUS(ls_csc_from_triplets(NULL, &arena, &m, &dg), LS_ERR_INVALID);
    CHECK(strcmp(dg.what, "t is NULL") == 0);
    CHECK_STATUS(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, r, c, NULL}, NULL, &m, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "arena") != NULL);
    /* empty matrix */
    CHECK_STATUS(ls_csc_from_triplets(&(ls_triplets){0, 0, 0, NULL, NULL, NULL}, &arena, &m, NULL), LS_OK);
    CHECK_EQ(ls_csc_nnz(&m), 0);
}

/* sweep job: triplets */
typedef struct trip_job {
    ls_csc out;
} trip_job;

static ls_status trip_run(void *ctx, ls_arena *arena)
{
    trip_job *j = (trip_job *)ctx;
    return ls_csc_from_triplets(&(ls_triplets){NR, NC, NT, tr, tc, tv}, arena, &j->out, NULL);
}
static uint64_t trip_hash(void *ctx)
{
    trip_job *j = (trip_job *)ctx;
    uint64_t h = test_hash(tr, sizeof tr, TEST_HASH_SEED);
    h = test_hash(tv, sizeof tv, h);
    return test_hash(&j->out, sizeof j->out, h);
}
static void trip_reset(void *ctx)
{
    memset(ctx, 0, sizeof(trip_job));
}

/* symmetric test matrix: the uniform Laplacian of a 5 x 4 grid plus 2 I */
static void grid_matrix(ls_arena *arena, ls_csc *m, int full)
{
    uint32_t r[200], c[200];
    ls_real v[200];
    uint32_t n = 0, x, y, W = 5, H = 4;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            uint32_t i = y * W + x, deg = 0;
            if (x + 1 < W) { r[n] = i; c[n] = i + 1; v[n++] = -1; deg++; }
            if (y + 1 < H) { r[n] = i; c[n] = i + W; v[n++] = -1; deg++; }
            if (x > 0) { if (full) { r[n] = i; c[n] = i - 1; v[n++] = -1; } deg++; }
            if (y > 0) { if (full) { r[n] = i; c[n] = i - W; v[n++] = -1; } deg++; }
            r[n] = i; c[n] = i; v[n++] = (ls_real)(deg + 2);
        }
    (void)ls_csc_from_triplets(&(ls_triplets){W * H, W * H, n, r, c, v}, arena, m, NULL);
}

static void sparse_triangle_symperm_matvec(void)
{
    ls_arena arena;
    ls_csc a, up, lo, pa;
    uint32_t perm[20], i, j, c;
    double da[400], du[400], dl[400], dp[400];
    ls_real x[60], y[60], y2[60];
    size_t bytes, before;
    REQUIRE(ls_arena_init(&arena, big, sizeof big) == LS_OK);
    grid_matrix(&arena, &a, 1);
    REQUIRE(a.ncols == 20);
    csc_to_dense(&a, da);
    for (i = 0; i < 20; i++)
        for (j = 0; j < 20; j++) CHECK(da[i * 20 + j] == da[j * 20 + i]);
    before = ls_arena_used(&arena);
    REQUIRE(ls_csc_triangle_bytes(&a, 1, &bytes) == LS_OK);
    CHECK_STATUS(ls_csc_triangle(&a, 1, &arena, &up), LS_OK);
    CHECK_EQ(ls_arena_used(&arena) - before, bytes);
    CHECK_STATUS(ls_csc_triangle(&a, 0, &arena, &lo), LS_OK);
    csc_to_dense(&up, du);
    csc_to_dense(&lo, dl);
    for (i = 0; i < 20; i++)
        for (j = 0; j < 20; j++) {
            CHECK(du[i * 20 + j] == (i <= j ? da[i * 20 + j] : 0));
            CHECK(dl[i * 20 + j] == (i >= j ? da[i * 20 + j] : 0));
        }
    /* a permutation: reverse interleave */
    for (i = 0; i < 20; i++) perm[i] = (i * 7 + 3) % 20;
    before = ls_arena_used(&arena);
    REQUIRE(ls_csc_symperm_bytes(&up, &bytes) == LS_OK);
    ls_arena_reset_peak(&arena);
    CHECK_STATUS(ls_csc_symperm(&up, perm, &arena, &pa), LS_OK);
    CHECK_EQ(arena.peak - before, bytes);
    csc_to_dense(&pa, dp);
    for (i = 0; i < 20; i++)
        for (j = 0; j < 20; j++) CHECK(dp[i * 20 + j] == (i <= j ? da[perm[i] * 20 + perm[j]] : 0));
    for (j = 0; j < 20; j++)
        for (c = pa.colptr[j] + 1; c < pa.colptr[j + 1]; c++) CHECK(pa.rowidx[c - 1] < pa.rowidx[c]);
    perm[3] = perm[4];
    CHECK_STATUS(ls_csc_symperm(&up, perm, &arena, &pa), LS_ERR_INVALID);
    /* products: full, and symmetric from the upper triangle or from both */
    for (i = 0; i < 60; i++) x[i] = (ls_real)((int)(rnd() % 17) - 8);
    CHECK_STATUS(ls_csc_matvec(&a, 3, x, y), LS_OK);
    for (i = 0; i < 20; i++)
        for (c = 0; c < 3; c++) {
            double s = 0;
            for (j = 0; j < 20; j++) s += da[i * 20 + j] * (double)x[j * 3 + c];
            CHECK(s == (double)y[i * 3 + c]);
        }
    CHECK_STATUS(ls_csc_matvec_sym(&up, 3, x, y2), LS_OK);
    for (i = 0; i < 60; i++) CHECK(y[i] == y2[i]);
    CHECK_STATUS(ls_csc_matvec_sym(&a, 3, x, y2), LS_OK);
    for (i = 0; i < 60; i++) CHECK(y[i] == y2[i]);
    CHECK_STATUS(ls_csc_matvec(&a, 0, x, y), LS_ERR_INVALID);
}

/* sweep jobs for triangle and symperm */
typedef struct tri_job {
    const ls_csc *a;
    const uint32_t *perm;
    ls_csc out;
} tri_job;
static ls_status tri_run(void *ctx, ls_arena *arena)
{
    tri_job *j = (tri_job *)ctx;
    return j->perm ? ls_csc_symperm(j->a, j->perm, arena, &j->out) : ls_csc_triangle(j->a, 1, arena, &j->out);
}
static uint64_t tri_hash(void *ctx)
{
    tri_job *j = (tri_job *)ctx;
    uint64_t h = test_hash(j->a->values, sizeof(ls_real) * ls_csc_nnz(j->a), TEST_HASH_SEED);
    return test_hash(&j->out, sizeof j->out, h);
}
static void tri_reset(void *ctx)
{
    tri_job *j = (tri_job *)ctx;
    memset(&j->out, 0, sizeof j->out);
}

static void sparse_arena_sweeps(void)
{
    trip_job tj;
    tri_job rj;
    sweep_job sj;
    ls_arena arena;
    ls_csc a;
    uint32_t perm[20], i;
    make_triplets();
    memset(&tj, 0, sizeof tj);
    memset(&sj, 0, sizeof sj);
    sj.name = "csc_from_triplets";
    sj.run = trip_run;
    sj.state_hash = trip_hash;
    sj.reset = trip_reset;
    sj.ctx = &tj;
    sj.exact = 1;
    REQUIRE(ls_csc_from_triplets_bytes(NR, NC, NT, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);

    REQUIRE(ls_arena_init(&arena, big, sizeof big) == LS_OK);
    grid_matrix(&arena, &a, 0);
    for (i = 0; i < 20; i++) perm[i] = 19 - i;
    memset(&rj, 0, sizeof rj);
    rj.a = &a;
    sj.name = "csc_triangle";
    sj.run = tri_run;
    sj.state_hash = tri_hash;
    sj.reset = tri_reset;
    sj.ctx = &rj;
    REQUIRE(ls_csc_triangle_bytes(&a, 1, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    rj.perm = perm;
    sj.name = "csc_symperm";
    REQUIRE(ls_csc_symperm_bytes(&a, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
}

static void sparse_deterministic_order(void)
{
    /* the same triplets in another order give the same matrix, and duplicate
     * sums follow input order (checked with values where order matters) */
    ls_arena arena;
    ls_csc m1, m2;
    uint32_t r[3] = {1, 1, 1}, c[3] = {2, 2, 2};
    ls_real v[3];
    v[0] = (ls_real)1;
    v[1] = (ls_real)LS_REAL_EPSILON / (ls_real)2;
    v[2] = (ls_real)LS_REAL_EPSILON / (ls_real)2;
    REQUIRE(ls_arena_init(&arena, big, sizeof big) == LS_OK);
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, r, c, v}, &arena, &m1, NULL) == LS_OK);
    CHECK(m1.values[0] == (ls_real)1); /* (1 + e/2) + e/2: each sum ties to even, 1 */
    v[0] = v[1];
    v[2] = (ls_real)1;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, r, c, v}, &arena, &m2, NULL) == LS_OK);
    CHECK(m2.values[0] > (ls_real)1); /* (e/2 + e/2) + 1 = 1 + e exactly */
    CHECK_EQ(ls_csc_nnz(&m1), 1);
}

int main(void)
{
    TEST_INIT("test_sparse");
    TEST_RUN(sparse_from_triplets_matches_dense);
    TEST_RUN(sparse_from_triplets_errors);
    TEST_RUN(sparse_triangle_symperm_matvec);
    TEST_RUN(sparse_arena_sweeps);
    TEST_RUN(sparse_deterministic_order);
    return TEST_END();
}
