/* test_order.c - the approximate minimum degree ordering: validity, fill
 * against the natural order and against CHOLMOD's AMD (figures from the issue),
 * arena sweep. */
#include "test.h"
#include "sweep.h"
#include "bench/meshgen.h"

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static uint32_t rnd(void)
{
    return (uint32_t)test_rng_bits(&rng_state);
}

static unsigned char *buf;
#define BUF_BYTES ((size_t)64 << 20)

/* CSC of a triplet list given in double values. */
static int build(const mtrip *t, ls_arena *arena, ls_csc *a)
{
    ls_real *v = (ls_real *)malloc((t->count + 1) * sizeof(ls_real));
    size_t i;
    ls_status st;
    for (i = 0; i < t->count; i++) v[i] = (ls_real)t->v[i];
    st = ls_csc_from_triplets(&(ls_triplets){t->n, t->n, t->count, t->r, t->c, v}, arena, a, NULL);
    free(v);
    return st == LS_OK;
}

/* nnz of L below the diagonal for an ordering method */
static uint32_t fill_of(const ls_csc *a, uint32_t method)
{
    ls_arena arena;
    ls_ldlt f;
    if (ls_arena_init(&arena, buf, BUF_BYTES) != LS_OK) return 0;
    if (ls_ldlt_analyze(a, method, NULL, &arena, &f, NULL) != LS_OK) return 0;
    return f.l_nnz;
}

static int order_valid(const ls_csc *a)
{
    ls_arena arena;
    uint32_t *perm = (uint32_t *)malloc((a->ncols + 1) * sizeof(uint32_t));
    unsigned char *mark = (unsigned char *)malloc(a->ncols + 1);
    int ok;
    if (ls_arena_init(&arena, buf, BUF_BYTES) != LS_OK) return 0;
    ok = ls_order_amd(a, &arena, perm, NULL) == LS_OK && ls_order_is_perm(a->ncols, perm, mark) &&
         arena.bottom == 0 && arena.top == 0;
    free(perm);
    free(mark);
    return ok;
}

static void order_small_graphs(void)
{
    ls_arena arena;
    ls_csc a;
    uint32_t r[64], c[64], i, n;
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
    /* empty 0 x 0, 1 x 1, diagonal only */
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){0, 0, 0, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK(order_valid(&a));
    r[0] = c[0] = 0;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){1, 1, 1, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK(order_valid(&a));
    for (i = 0; i < 9; i++) r[i] = c[i] = i;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){9, 9, 9, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK(order_valid(&a));
    /* path 0-1-...-9: minimum degree has no fill */
    for (n = 0, i = 0; i + 1 < 10; i++) { r[n] = i; c[n++] = i + 1; }
    for (i = 0; i < 10; i++) { r[n] = i; c[n++] = i; }
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){10, 10, n, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK(order_valid(&a));
    CHECK_EQ(fill_of(&a, LS_ORDER_AMD), 9);
    /* star with centre 0: natural order fills completely, AMD not at all */
    for (n = 0, i = 1; i < 12; i++) { r[n] = 0; c[n++] = i; }
    for (i = 0; i < 12; i++) { r[n] = i; c[n++] = i; }
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){12, 12, n, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK(order_valid(&a));
    CHECK_EQ(fill_of(&a, LS_ORDER_AMD), 11);
    CHECK_EQ(fill_of(&a, LS_ORDER_NATURAL), 11 * 12 / 2);
    /* two components, lower-triangle entries only (no graph: all isolated) */
    for (n = 0, i = 0; i + 1 < 8; i++) { r[n] = i + 1; c[n++] = i; }
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){8, 8, n, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK(order_valid(&a));
}

static void order_random_graphs(void)
{
    int trial;
    for (trial = 0; trial < 40; trial++) {
        ls_arena arena;
        ls_csc a;
        uint32_t n = 1 + rnd() % 120, m = rnd() % (4 * n + 1), i;
        uint32_t *r = (uint32_t *)malloc((m + n) * sizeof(uint32_t)), *c = (uint32_t *)malloc((m + n) * sizeof(uint32_t));
        for (i = 0; i < m; i++) {
            r[i] = rnd() % n;
            c[i] = rnd() % n;
        }
        for (i = 0; i < n; i++) r[m + i] = c[m + i] = i;
        REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
        REQUIRE(ls_csc_from_triplets(&(ls_triplets){n, n, m + n, r, c, NULL}, &arena, &a, NULL) == LS_OK);
        CHECK_MSG(order_valid(&a), "trial %d n %u", trial, n);
        /* minimum degree should not lose badly to the natural order */
        CHECK_MSG(fill_of(&a, LS_ORDER_AMD) <= fill_of(&a, LS_ORDER_NATURAL) + n, "trial %d", trial);
        free(r);
        free(c);
    }
}

static void order_mesh_fill(void)
{
    /* nnz(L) including the diagonal, compared with CHOLMOD's AMD on the same
     * icosphere (84.8k at 2562 vertices) and with natural order. */
    struct { int level; double cholmod; } cases[] = {{4, 84.8e3}};
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        tmesh m = icosphere(cases[k].level);
        mtrip t = laplacian_system(&m, 19.0, 0);
        ls_arena arena;
        ls_csc a;
        double amd, nat;
        REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        CHECK(order_valid(&a));
        amd = (double)fill_of(&a, LS_ORDER_AMD) + m.nv;
        nat = (double)fill_of(&a, LS_ORDER_NATURAL) + m.nv;
        printf("     icosphere %u: nnz(L) amd %.0f (CHOLMOD AMD %.0f, ratio %.3f), natural %.0f\n", m.nv, amd,
               cases[k].cholmod, amd / cases[k].cholmod, nat);
        CHECK(amd <= 1.05 * cases[k].cholmod);
        CHECK(amd * 2 < nat);
        mtrip_free(&t);
        tmesh_free(&m);
    }
    {
        tmesh m = gridmesh(40, 40);
        mtrip t = laplacian_system(&m, 1.0, 1);
        ls_arena arena;
        ls_csc a;
        uint32_t amd, nat;
        REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        CHECK(order_valid(&a));
        amd = fill_of(&a, LS_ORDER_AMD);
        nat = fill_of(&a, LS_ORDER_NATURAL);
        printf("     grid 40x40: nnz(L) strictly lower amd %u, natural %u\n", amd, nat);
        CHECK(amd * 2 < nat);
        mtrip_free(&t);
        tmesh_free(&m);
    }
}

typedef struct ord_job {
    const ls_csc *a;
    uint32_t *perm;
    uint32_t n;
} ord_job;
static ls_status ord_run(void *ctx, ls_arena *arena)
{
    ord_job *j = (ord_job *)ctx;
    return ls_order_amd(j->a, arena, j->perm, NULL);
}
static uint64_t ord_hash(void *ctx)
{
    ord_job *j = (ord_job *)ctx;
    uint64_t h = test_hash(j->a->rowidx, 4 * (size_t)ls_csc_nnz(j->a), TEST_HASH_SEED);
    return test_hash(j->perm, 4 * (size_t)j->n, h);
}
static void ord_reset(void *ctx)
{
    ord_job *j = (ord_job *)ctx;
    memset(j->perm, 0, 4 * (size_t)j->n);
}

static void order_arena_sweep(void)
{
    tmesh m = icosphere(2);
    mtrip t = laplacian_system(&m, 1.0, 0);
    ls_arena arena;
    ls_csc a;
    ord_job oj;
    sweep_job sj;
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
    REQUIRE(build(&t, &arena, &a));
    oj.a = &a;
    oj.n = a.ncols;
    oj.perm = (uint32_t *)calloc(a.ncols, sizeof(uint32_t));
    memset(&sj, 0, sizeof sj);
    sj.name = "order_amd";
    sj.run = ord_run;
    sj.state_hash = ord_hash;
    sj.reset = ord_reset;
    sj.ctx = &oj;
    sj.exact = 1;
    REQUIRE(ls_order_bytes(a.ncols, ls_csc_nnz(&a), &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    free(oj.perm);
    mtrip_free(&t);
    tmesh_free(&m);
}

static void order_errors(void)
{
    ls_arena arena;
    ls_csc a;
    uint32_t r[2] = {0, 1}, c[2] = {0, 1}, perm[3];
    ls_diag dg;
    size_t bytes;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){3, 2, 2, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    CHECK_STATUS(ls_order_amd(&a, &arena, perm, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "not square") != NULL);
    CHECK_STATUS(ls_order_amd(NULL, &arena, perm, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_order_amd(NULL, &arena, perm, &dg), LS_ERR_INVALID);
    CHECK(strcmp(dg.what, "a is NULL") == 0);
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){2, 2, 2, r, c, NULL}, &arena, &a, NULL) == LS_OK);
    a.rowidx[1] = 7;
    CHECK_STATUS(ls_order_amd(&a, &arena, perm, &dg), LS_ERR_INVALID);
    CHECK(dg.has_index && dg.index == 1);
    CHECK(strstr(dg.what, "a->rowidx") != NULL);
    CHECK_STATUS(ls_order_nd_geom(&a, NULL, &arena, perm, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "xyz") != NULL);
    CHECK_STATUS(ls_order_bytes(1u << 30, 10, &bytes), LS_ERR_TOO_LARGE);
    perm[0] = 1; perm[1] = 1; perm[2] = 0;
    {
        unsigned char mark[3];
        CHECK(!ls_order_is_perm(3, perm, mark));
        perm[1] = 2;
        CHECK(ls_order_is_perm(3, perm, mark));
    }
}

static ls_real *coords(const tmesh *m)
{
    ls_real *x = (ls_real *)malloc(3 * sizeof(ls_real) * (m->nv + 1));
    size_t i;
    for (i = 0; i < 3 * (size_t)m->nv; i++) x[i] = (ls_real)m->pos[i];
    return x;
}

static uint32_t fill_of_perm(const ls_csc *a, const uint32_t *perm)
{
    ls_arena arena;
    ls_ldlt f;
    if (ls_arena_init(&arena, buf, BUF_BYTES / 2) != LS_OK) return 0;
    if (ls_ldlt_analyze(a, LS_ORDER_GIVEN, perm, &arena, &f, NULL) != LS_OK) return 0;
    return f.l_nnz;
}

static void order_nd_geometric(void)
{
    int k;
    for (k = 0; k < 3; k++) {
        tmesh m = k == 0 ? icosphere(5) : k == 1 ? gridmesh(60, 50) : icosphere(1);
        mtrip t = laplacian_system(&m, 1.0, 0);
        ls_real *x = coords(&m);
        ls_arena arena;
        ls_csc a;
        uint32_t *perm = (uint32_t *)malloc(4 * (size_t)m.nv);
        unsigned char *mark = (unsigned char *)malloc(m.nv);
        uint32_t nd, amd;
        size_t i;
        REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        CHECK_STATUS(ls_order_nd_geom(&a, x, &arena, perm, NULL), LS_OK);
        CHECK(ls_order_is_perm(m.nv, perm, mark));
        nd = fill_of_perm(&a, perm);
        amd = fill_of(&a, LS_ORDER_AMD);
        printf("     %s n %u: nnz(L) strictly lower nd %u, amd %u\n", k == 1 ? "grid" : "icosphere", m.nv, nd, amd);
        if (k == 0) CHECK(nd < amd); /* 10242-vertex sphere: 372.6k vs 472.3k (with diagonal) */
        /* the target: <= 1.05 x CHOLMOD-METIS's nnz(L) (369880 with the
         * diagonal, 359638 strictly lower; tests/bench/run_ldlt.sh): 1.008 */
        if (k == 0) CHECK_MSG(nd <= 377620u, "nd fill %u", nd);
        /* all vertices at one point: still a permutation */
        for (i = 0; i < 3 * (size_t)m.nv; i++) x[i] = (ls_real)1;
        CHECK_STATUS(ls_order_nd_geom(&a, x, &arena, perm, NULL), LS_OK);
        CHECK(ls_order_is_perm(m.nv, perm, mark));
        {
            ls_diag dg;
            x[3 * 5 + 1] = (ls_real)NAN;
            CHECK_STATUS(ls_order_nd_geom(&a, x, &arena, perm, &dg), LS_ERR_NONFINITE);
            CHECK(dg.has_index && dg.index == 5);
        }
        free(perm);
        free(mark);
        free(x);
        mtrip_free(&t);
        tmesh_free(&m);
    }
}

typedef struct nd_job {
    const ls_csc *a;
    const ls_real *xyz;
    uint32_t *perm;
    uint32_t n;
} nd_job;
static ls_status nd_run(void *ctx, ls_arena *arena)
{
    nd_job *j = (nd_job *)ctx;
    return ls_order_nd_geom(j->a, j->xyz, arena, j->perm, NULL);
}
static uint64_t nd_hash(void *ctx)
{
    nd_job *j = (nd_job *)ctx;
    uint64_t h = test_hash(j->xyz, 3 * sizeof(ls_real) * (size_t)j->n, TEST_HASH_SEED);
    return test_hash(j->perm, 4 * (size_t)j->n, h);
}
static void nd_reset(void *ctx)
{
    nd_job *j = (nd_job *)ctx;
    memset(j->perm, 0, 4 * (size_t)j->n);
}

static void order_nd_arena_sweep(void)
{
    tmesh m = icosphere(3);
    mtrip t = laplacian_system(&m, 1.0, 0);
    ls_real *x = coords(&m);
    ls_arena arena;
    ls_csc a;
    nd_job nj;
    sweep_job sj;
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
    REQUIRE(build(&t, &arena, &a));
    nj.a = &a;
    nj.xyz = x;
    nj.n = a.ncols;
    nj.perm = (uint32_t *)calloc(a.ncols, sizeof(uint32_t));
    memset(&sj, 0, sizeof sj);
    sj.name = "order_nd_geom";
    sj.run = nd_run;
    sj.state_hash = nd_hash;
    sj.reset = nd_reset;
    sj.ctx = &nj;
    sj.exact = 1;
    REQUIRE(ls_order_nd_bytes(a.ncols, ls_csc_nnz(&a), &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    free(nj.perm);
    free(x);
    mtrip_free(&t);
    tmesh_free(&m);
}

int main(void)
{
    TEST_INIT("test_order");
    buf = (unsigned char *)malloc(BUF_BYTES);
    TEST_RUN(order_small_graphs);
    TEST_RUN(order_random_graphs);
    TEST_RUN(order_mesh_fill);
    TEST_RUN(order_arena_sweep);
    TEST_RUN(order_errors);
    TEST_RUN(order_nd_geometric);
    TEST_RUN(order_nd_arena_sweep);
    free(buf);
    return TEST_END();
}
