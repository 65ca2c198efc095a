/* test_param.c - the parameterization: round trips on the bunny within
 * kappa * epsilon, the adjoint identity, p-th power steps against repeated
 * dense solves, weight changes, lambda extremes per precision, CG warm
 * starts, arena sweeps. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include "../port/posix/ls_posix.h"
#include "dense.h"

static LS_ARENA_BUFFER(buf_, 8 << 20);
#define BUF buf_.bytes
static LS_ARENA_BUFFER(scr_, 2 << 20);

static uint64_t rs = 0x13198A2E03707344ull;
static double urand(void)
{
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}

static ls_mesh bunny;
static int emulated; /* LS_TEST_EMULATED=1 under QEMU: fewer cases */
static ls_arena bunny_arena;
static int bunny_ok;

static void load_bunny(void)
{
    unsigned char *data = NULL;
    size_t n = 0;
    ls_arena_init(&bunny_arena, BUF, sizeof BUF);
    bunny_ok = ls_posix_read_file("fixtures/meshes/bunny.obj", &data, &n) == LS_OK &&
               ls_mesh_read(data, n, LS_MESH_FORMAT_AUTO, &bunny_arena, &bunny, NULL) == LS_OK;
    free(data);
}

/* The bunny's uniform Laplacian and `count` vectors of 3 n reals from a,
 * the first holding the vertex positions; 0 on failure. */
static int bunny_setup(ls_arena *a, ls_csc *L, ls_real **v, int count)
{
    size_t nk = 3u * (size_t)bunny.vertex_count;
    int i;
    if (!bunny_ok || ls_laplacian_uniform(&bunny, LS_LAP_UPPER, a, L, NULL) != LS_OK) return 0;
    for (i = 0; i < count; i++) {
        v[i] = (ls_real *)ls_arena_alloc(a, nk, sizeof(ls_real));
        if (v[i] == NULL) return 0;
    }
    memcpy(v[0], bunny.positions, nk * sizeof(ls_real));
    return 1;
}

static ls_param_config config(uint32_t solver, uint32_t form, double w)
{
    ls_param_config c;
    memset(&c, 0, sizeof c);
    c.solver = solver;
    c.form = form;
    c.weight = (ls_real)w;
    c.k = 3;
    c.order = LS_ORDER_AUTO;
    c.cg_max_iter = 5000;
    c.cg_tol = LS_REAL_IS_FLOAT ? (ls_real)1e-6 : (ls_real)1e-13;
    return c;
}

static double rel_diff(const ls_real *a, const ls_real *b, size_t n)
{
    double e = 0, s = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        e += ((double)a[i] - (double)b[i]) * ((double)a[i] - (double)b[i]);
        s += (double)b[i] * (double)b[i];
    }
    return sqrt(e / s);
}

/* kappa(M) <= (1 + lambda * 2 max_i L_ii) / 1 for the uniform Laplacian (Gershgorin) */
static double kappa_bound(const ls_csc *L, double lambda)
{
    uint32_t j;
    double dmax = 0;
    for (j = 0; j < L->ncols; j++)
        if ((double)L->values[L->colptr[j + 1] - 1] > dmax) dmax = (double)L->values[L->colptr[j + 1] - 1];
    return 1 + lambda * 2 * dmax;
}

static void bunny_round_trip_and_adjoint(void)
{
    static const double lambdas[] = {1, 19, 99, 1000};
    ls_arena a = bunny_arena;
    ls_csc L;
    ls_real *v[7], *x, *u, *y, *va, *vb, *ma, *mb;
    size_t nk = 3u * (size_t)bunny.vertex_count, i, li;
    uint32_t s;
    REQUIRE(bunny_setup(&a, &L, v, 7));
    x = v[0], u = v[1], y = v[2], va = v[3], vb = v[4], ma = v[5], mb = v[6];
    for (i = 0; i < nk; i++) {
        va[i] = (ls_real)(urand() - 0.5);
        vb[i] = (ls_real)(urand() - 0.5);
    }
    for (s = 0; s < 2; s++)
        for (li = 0; li < sizeof lambdas / sizeof lambdas[0]; li++) {
            ls_arena_mark mk = ls_arena_save(&a);
            if (emulated && li != 1) continue; /* lambda 19 only */
            ls_param p;
            ls_param_config c = config(s, LS_SYSTEM_LAMBDA, lambdas[li]);
            double kap = kappa_bound(&L, lambdas[li]), err, tol, ab = 0, ba = 0, na = 0, nb = 0;
            REQUIRE(ls_param_init(&p, &L, &c, bunny.positions, &a, NULL) == LS_OK);
            CHECK_STATUS(ls_param_to_differential(&p, x, u), LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, u, y), LS_OK);
            err = rel_diff(y, x, nk);
            /* LDL^T: a few units of kappa * eps; CG: its tolerance times kappa */
            tol = s == LS_PARAM_LDLT ? 4 * kap * (double)LS_REAL_EPSILON : kap * (double)c.cg_tol;
            printf("     %s lambda %-5g kappa <= %-7.0f round trip %.3g (tol %.3g)\n", s ? "cg  " : "ldlt", lambdas[li], kap,
                   err, tol);
            CHECK(err <= tol);
            /* <M^-1 a, b> = <a, M^-1 b> */
            CHECK_STATUS(ls_param_adjoint(&p, va, ma), LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, vb, mb), LS_OK);
            for (i = 0; i < nk; i++) {
                ab += (double)ma[i] * (double)vb[i];
                ba += (double)va[i] * (double)mb[i];
                na += (double)va[i] * (double)va[i];
                nb += (double)vb[i] * (double)vb[i];
            }
            CHECK_NEAR(ab, ba, (s == LS_PARAM_LDLT ? 4 * (double)LS_REAL_EPSILON : (double)c.cg_tol) * sqrt(na * nb) * 10);
            if (s == LS_PARAM_CG) { /* separate warm starts: each holds its last result */
                CHECK(memcmp(p.warm_fwd, mb, nk * sizeof(ls_real)) == 0);
                CHECK(memcmp(p.warm_adj, ma, nk * sizeof(ls_real)) == 0);
            }
            ls_arena_restore(&a, mk);
        }
}

/* an octahedron with one vertex pulled: 6 vertices, 8 faces */
static ls_real oct_pos[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1.4f, 0, 0, -1};
static uint32_t oct_tri[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

/* the elephant fixture, lambda 19, both solvers (native runs only) */
static void elephant_round_trip(void)
{
    unsigned char *data = NULL;
    size_t n = 0, nk;
    ls_arena a = bunny_arena;
    ls_mesh m;
    ls_csc L;
    ls_real *u, *y;
    uint32_t s;
    if (emulated) return;
    REQUIRE(ls_posix_read_file("fixtures/meshes/elephant.obj", &data, &n) == LS_OK);
    REQUIRE(ls_mesh_read(data, n, LS_MESH_FORMAT_AUTO, &a, &m, NULL) == LS_OK);
    free(data);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    nk = 3u * m.vertex_count;
    u = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    y = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    REQUIRE(u && y);
    for (s = 0; s < 2; s++) {
        ls_arena_mark mk = ls_arena_save(&a);
        ls_param p;
        ls_param_config c = config(s, LS_SYSTEM_LAMBDA, 19);
        double kap = kappa_bound(&L, 19), err, tol;
        REQUIRE(ls_param_init(&p, &L, &c, m.positions, &a, NULL) == LS_OK);
        CHECK_STATUS(ls_param_to_differential(&p, m.positions, u), LS_OK);
        CHECK_STATUS(ls_param_from_differential(&p, u, y), LS_OK);
        err = rel_diff(y, m.positions, nk);
        tol = s == LS_PARAM_LDLT ? 4 * kap * (double)LS_REAL_EPSILON : kap * (double)c.cg_tol;
        printf("     elephant (%u vertices) %s lambda 19: round trip %.3g (tol %.3g)\n", m.vertex_count, s ? "cg  " : "ldlt",
               err, tol);
        CHECK(err <= tol);
        ls_arena_restore(&a, mk);
    }
}

static void power_steps_match_repeated_dense_solves(void)
{
    ls_mesh m = {oct_pos, oct_tri, 6, 8};
    ls_arena a;
    ls_csc L;
    uint32_t power, s, cot;
    ls_arena_init(&a, scr_.bytes, sizeof scr_.bytes);
    for (cot = 0; cot < 2; cot++) {
        if (cot)
            REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_FULL, &a, &L, NULL, NULL) == LS_OK);
        else
            REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
        for (s = 0; s < 2; s++)
            for (power = 1; power <= 3; power++) {
                ls_arena_mark mk = ls_arena_save(&a);
                ls_param p;
                ls_param_config c = config(s, LS_SYSTEM_ALPHA, 0.9);
                ls_real x[18], g[18];
                double d[36], dm[36], want[18], eta = 0.3, err = 0, big = 0;
                uint32_t i, j, q;
                REQUIRE(ls_param_init(&p, &L, &c, NULL, &a, NULL) == LS_OK);
                /* dense M = 0.1 I + 0.9 L from L's entries */
                memset(d, 0, sizeof d);
                for (j = 0; j < 6; j++)
                    for (q = L.colptr[j]; q < L.colptr[j + 1]; q++) {
                        i = L.rowidx[q];
                        if (i > j) continue;
                        d[i * 6 + j] = d[j * 6 + i] = 0.9 * (double)L.values[q] + (i == j ? 0.1 : 0.0);
                    }
                for (i = 0; i < 18; i++) {
                    x[i] = (ls_real)(urand() - 0.5);
                    g[i] = (ls_real)(urand() - 0.5);
                    want[i] = (double)g[i];
                }
                for (q = 0; q < power; q++) {
                    memcpy(dm, d, sizeof d);
                    dense_solve(dm, 6, want, 3);
                }
                for (i = 0; i < 18; i++) want[i] = (double)x[i] - eta * want[i];
                CHECK_STATUS(ls_param_step(&p, x, g, (ls_real)eta, power), LS_OK);
                for (i = 0; i < 18; i++) {
                    err = fmax(err, fabs((double)x[i] - want[i]));
                    big = fmax(big, fabs(want[i]));
                }
                /* M^-p amplifies by up to 10^p (smallest eigenvalue 0.1): relative to the result */
                CHECK_MSG(err <= (LS_REAL_IS_FLOAT ? 1e-5 : 1e-13) * (1 + big), "cot %u solver %u power %u: error %g (max %g)",
                          cot, s, power, err, big);
                ls_arena_restore(&a, mk);
            }
    }
}

static void lambda_zero_is_exact(void)
{
    ls_mesh m = {oct_pos, oct_tri, 6, 8};
    ls_arena a;
    ls_csc L;
    uint32_t s, f;
    ls_arena_init(&a, scr_.bytes, sizeof scr_.bytes);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    for (s = 0; s < 2; s++)
        for (f = 0; f < 2; f++) {
            ls_arena_mark mk = ls_arena_save(&a);
            ls_param p;
            ls_param_config c = config(s, f, 0);
            ls_real u[18], x[18], y[18];
            uint32_t i;
            for (i = 0; i < 18; i++) u[i] = (ls_real)((urand() - 0.5) * 1e3);
            u[4] = (ls_real)-0.0;
            u[5] = (ls_real)1e-300 * (ls_real)1e-10; /* 0 or a subnormal */
            REQUIRE(ls_param_init(&p, &L, &c, NULL, &a, NULL) == LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, u, x), LS_OK);
            CHECK(memcmp(x, u, sizeof u) == 0);
            CHECK_STATUS(ls_param_adjoint(&p, u, x), LS_OK);
            CHECK(memcmp(x, u, sizeof u) == 0);
            CHECK_STATUS(ls_param_to_differential(&p, u, y), LS_OK);
            CHECK(memcmp(y, u, sizeof u) == 0);
            /* and after set_weight back to 0 */
            CHECK_STATUS(ls_param_set_weight(&p, (ls_real)0.5, NULL), LS_OK);
            CHECK_STATUS(ls_param_set_weight(&p, (ls_real)0, NULL), LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, u, x), LS_OK);
            CHECK(memcmp(x, u, sizeof u) == 0);
            ls_arena_restore(&a, mk);
        }
}

/* lambda = 1e8 and alpha = 0.999999 on the bunny: a finite, accurate result or
 * the named error, as documented in param.h for each precision */
static void lambda_extremes(void)
{
    ls_arena a = bunny_arena;
    ls_csc L;
    ls_real *v[3], *x, *u, *y;
    size_t nk = 3u * (size_t)bunny.vertex_count, i;
    uint32_t s, e;
    REQUIRE(bunny_setup(&a, &L, v, 3));
    x = v[0], u = v[1], y = v[2];
    for (e = 0; e < 2; e++)
        for (s = 0; s < 2; s++) {
            ls_arena_mark mk = ls_arena_save(&a);
            ls_param p;
            ls_diag dg;
            ls_param_config c = e == 0 ? config(s, LS_SYSTEM_LAMBDA, 1e8) : config(s, LS_SYSTEM_ALPHA, 0.999999);
            ls_status st;
            int expect_error = e == 0 && LS_REAL_IS_FLOAT;
            if (emulated && s == LS_PARAM_CG) continue; /* thousands of CG iterations: native runs only */
            st = ls_param_init(&p, &L, &c, bunny.positions, &a, &dg);
            if (st == LS_OK) {
                int finite = 1;
                double r;
                ls_status s2;
                CHECK_STATUS(ls_param_to_differential(&p, x, u), LS_OK);
                s2 = ls_param_from_differential(&p, u, y);
                for (i = 0; i < nk; i++) finite &= isfinite((double)y[i]) != 0;
                r = rel_diff(y, x, nk);
                printf("     %s %s: init ok, solve %s, round trip %.3g%s\n", e ? "alpha 0.999999" : "lambda 1e8    ",
                       s ? "cg  " : "ldlt", ls_status_name(s2), r,
                       s == LS_PARAM_CG ? "" : "");
                if (s2 == LS_OK) CHECK(finite);
                if (s == LS_PARAM_LDLT) {
                    CHECK_STATUS(s2, LS_OK);
                    /* kappa ~ 1 + 2e8 * 24 in double; ~ 5e7 for alpha 0.999999 */
                    CHECK(r <= (LS_REAL_IS_FLOAT ? 0.5 : 1e-5));
                }
            } else {
                printf("     %s %s: %s (%s)\n", e ? "alpha 0.999999" : "lambda 1e8    ", s ? "cg  " : "ldlt",
                       ls_status_name(st), dg.what);
                CHECK_STATUS(st, LS_ERR_NOT_SPD);
            }
            CHECK(expect_error == (st != LS_OK));
            ls_arena_restore(&a, mk);
        }
}

static void set_weight_matches_fresh_init(void)
{
    ls_arena a = bunny_arena;
    ls_csc L;
    ls_real *v[3], *u, *x1, *x2;
    size_t nk = 3u * (size_t)bunny.vertex_count;
    ls_param p, q;
    ls_param_config c = config(LS_PARAM_LDLT, LS_SYSTEM_LAMBDA, 1);
    ls_param_config c19 = config(LS_PARAM_LDLT, LS_SYSTEM_LAMBDA, 19);
    REQUIRE(bunny_setup(&a, &L, v, 3));
    u = v[0], x1 = v[1], x2 = v[2];
    REQUIRE(ls_param_init(&p, &L, &c, bunny.positions, &a, NULL) == LS_OK);
    REQUIRE(ls_param_init(&q, &L, &c19, bunny.positions, &a, NULL) == LS_OK);
    {
        size_t used = ls_arena_used(&a);
        CHECK_STATUS(ls_param_set_weight(&p, (ls_real)19, NULL), LS_OK);
        CHECK_EQ(ls_arena_used(&a), used);
    }
    CHECK_STATUS(ls_param_from_differential(&p, u, x1), LS_OK);
    CHECK_STATUS(ls_param_from_differential(&q, u, x2), LS_OK);
    CHECK(memcmp(x1, x2, nk * sizeof(ls_real)) == 0);
    /* a failing weight keeps the previous one and a valid factor */
    CHECK_STATUS(ls_param_set_weight(&p, (ls_real)-1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_param_set_weight(&p, (ls_real)1e300 * (ls_real)1e300, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_param_set_weight(&p, (ls_real)1e30, NULL), LS_ERR_NOT_SPD);
    CHECK(p.weight == (ls_real)19);
    CHECK_STATUS(ls_param_from_differential(&p, u, x1), LS_OK);
    CHECK(memcmp(x1, x2, nk * sizeof(ls_real)) == 0);
    /* NaN input: named error, output unchanged */
    {
        ls_real keep = x1[0];
        u[5] = (ls_real)NAN;
        CHECK_STATUS(ls_param_from_differential(&p, u, x1), LS_ERR_NONFINITE);
        CHECK(x1[0] == keep);
    }
}

/* ---- sizes and sweeps --------------------------------------------------- */

typedef struct param_job {
    ls_csc *lap;
    ls_param_config cfg;
    const ls_real *xyz;
    ls_param p;
} param_job;

static ls_status param_run(void *ctx, ls_arena *a)
{
    param_job *j = (param_job *)ctx;
    return ls_param_init(&j->p, j->lap, &j->cfg, j->xyz, a, NULL);
}

static uint64_t param_hash(void *ctx)
{
    param_job *j = (param_job *)ctx;
    return test_hash(&j->p, sizeof j->p, TEST_HASH_SEED);
}

static void sweeps_and_bunny_bytes(void)
{
    ls_mesh m = {oct_pos, oct_tri, 6, 8};
    ls_arena a, s;
    ls_csc L;
    static param_job j;
    uint32_t v;
    ls_arena_init(&a, scr_.bytes, sizeof scr_.bytes);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    for (v = 0; v < 4; v++) {
        sweep_job job;
        size_t bytes = 0;
        ls_arena_mark mk = ls_arena_save(&a);
        memset(&j, 0, sizeof j);
        j.lap = &L;
        j.cfg = config(v == 3 ? LS_PARAM_CG : LS_PARAM_LDLT, LS_SYSTEM_LAMBDA, v == 2 ? 0 : 19);
        j.xyz = v == 0 ? oct_pos : NULL;
        if (v == 1) j.cfg.order = LS_ORDER_AMD;
        REQUIRE(ls_param_bytes(j.lap, &j.cfg, j.xyz, &a, &bytes) == LS_OK);
        CHECK(ls_arena_save(&a).bottom == mk.bottom && ls_arena_save(&a).top == mk.top);
        memset(&job, 0, sizeof job);
        job.name = "param";
        job.run = param_run;
        job.state_hash = param_hash;
        job.ctx = &j;
        job.answer = bytes;
        job.exact = 1;
        CHECK_MSG(sweep_arena(&job) == 0, "variant %u", v);
    }
    /* the bunny: bytes of the objects */
    REQUIRE(bunny_ok);
    a = bunny_arena;
    ls_arena_init(&s, scr_.bytes, sizeof scr_.bytes);
    {
        ls_csc B;
        size_t lb = 0, pb[2] = {0, 0};
        ls_mesh_report rep;
        REQUIRE(ls_mesh_validate(&bunny, &a, &rep) == LS_OK);
        REQUIRE(ls_laplacian_bytes(bunny.vertex_count, bunny.face_count, rep.edge_count, LS_LAP_UPPER, &lb) == LS_OK);
        REQUIRE(ls_laplacian_uniform(&bunny, LS_LAP_UPPER, &a, &B, NULL) == LS_OK);
        for (v = 0; v < 2; v++) {
            ls_param_config c = config(v, LS_SYSTEM_LAMBDA, 19);
            ls_param p;
            size_t before = a.bottom;
            REQUIRE(ls_param_bytes(&B, &c, bunny.positions, &s, &pb[v]) == LS_OK);
            ls_arena_reset_peak(&a);
            REQUIRE(ls_param_init(&p, &B, &c, bunny.positions, &a, NULL) == LS_OK);
            CHECK_EQ(a.peak - ls_arena_used(&a) + (a.bottom - before), pb[v]);
            printf("     bunny (%u vertices) lambda 19, %s: param init peak %lu bytes, kept %lu bytes\n", bunny.vertex_count,
                   v ? "CG  " : "LDLT", (unsigned long)pb[v], (unsigned long)(a.bottom - before));
        }
        printf("     bunny uniform Laplacian (upper): build peak %lu bytes, matrix %lu bytes\n", (unsigned long)lb,
               (unsigned long)((bunny.vertex_count + 1u) * 4u + ls_csc_nnz(&B) * (4u + sizeof(ls_real))));
    }
}

int main(void)
{
    TEST_INIT("test_param");
    emulated = getenv("LS_TEST_EMULATED") != NULL && strcmp(getenv("LS_TEST_EMULATED"), "1") == 0;
    load_bunny();
    TEST_RUN(bunny_round_trip_and_adjoint);
    TEST_RUN(elephant_round_trip);
    TEST_RUN(power_steps_match_repeated_dense_solves);
    TEST_RUN(lambda_zero_is_exact);
    TEST_RUN(lambda_extremes);
    TEST_RUN(set_weight_matches_fresh_init);
    TEST_RUN(sweeps_and_bunny_bytes);
    return TEST_END();
}
