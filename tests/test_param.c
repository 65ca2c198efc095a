/* test_param.c - the parameterization: round trips on the bunny within
 * kappa * epsilon, the adjoint identity, p-th power steps against repeated
 * dense solves, weight changes, lambda extremes per precision, CG warm
 * starts, arena sweeps; on texture grids, the LDL^T, CG and transform
 * solvers against each other. */
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
    return test_rng_unit(&rs);
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

/* ---- texture grids ------------------------------------------------------ */

static ls_param_config grid_config(uint32_t solver, uint32_t form, double w, uint32_t k)
{
    ls_param_config c = config(solver, form, w);
    c.k = k;
    c.cg_tol = LS_REAL_IS_FLOAT ? (ls_real)1e-7 : (ls_real)1e-14;
    return c;
}

static const char *solver_name(uint32_t s)
{
    return s == LS_PARAM_LDLT ? "ldlt" : s == LS_PARAM_CG ? "cg  " : s == LS_PARAM_GRID ? "grid" : "auto";
}

/* Every solver on grids (Neumann and wrap, powers of two or not): round
 * trips, <M^-1 a, b> = <a, M^-1 b>, agreement between the solvers, the
 * 2nd-power step against two solves, set_weight. */
static void grid_solvers_agree(void)
{
    static const uint32_t shapes[][3] = {{13, 9, 0}, {16, 8, 1}, {1, 7, 0}, {30, 20, 1}, {5, 2, 1}};
    size_t si, i;
    ls_arena a;
    ls_arena_init(&a, BUF, sizeof BUF);
    for (si = 0; si < sizeof shapes / sizeof shapes[0]; si++) {
        ls_grid_shape sh;
        uint32_t n = shapes[si][0] * shapes[si][1], k = si == 2 ? 1u : 3u, s, form = si == 1 ? LS_SYSTEM_ALPHA : LS_SYSTEM_LAMBDA;
        double w = si == 1 ? 0.9 : 10;
        size_t nk = (size_t)n * k;
        ls_arena_mark mk = ls_arena_save(&a);
        ls_real *x = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real)), *u = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
        ls_real *y = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real)), *ma = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
        ls_real *mb = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real)), *vb = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
        ls_real *ref = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real)), *st2 = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
        REQUIRE(x && u && y && ma && mb && vb && ref && st2);
        sh.width = shapes[si][0];
        sh.height = shapes[si][1];
        sh.wrap_u = shapes[si][2];
        for (i = 0; i < nk; i++) {
            x[i] = (ls_real)(urand() - 0.5 + (double)(i % 3));
            vb[i] = (ls_real)(urand() - 0.5);
        }
        for (s = 0; s < 4; s++) {
            ls_arena_mark m2 = ls_arena_save(&a);
            ls_param p;
            ls_param_config c = grid_config(s, form, w, k);
            /* float CG stalls near its 1e-7 target: a looser bound for it */
            double err, ab = 0, ba = 0, na = 0, nb = 0, tol = LS_REAL_IS_FLOAT ? (s == LS_PARAM_CG ? 1e-4 : 2e-5) : 1e-12;
            size_t bytes = 0, before = a.bottom;
            ls_arena sc;
            ls_arena_init(&sc, scr_.bytes, sizeof scr_.bytes);
            REQUIRE(ls_param_grid_bytes(&sh, &c, &sc, &bytes) == LS_OK);
            REQUIRE(ls_param_grid_init(&p, &sh, &c, &a, NULL) == LS_OK);
            CHECK_EQ(p.solver, s == LS_PARAM_AUTO ? LS_PARAM_GRID : s);
            CHECK(a.bottom - before <= bytes);
            CHECK_STATUS(ls_param_to_differential(&p, x, u), LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, u, y), LS_OK);
            err = rel_diff(y, x, nk);
            CHECK_MSG(err <= tol, "%ux%u wrap %u %s: round trip %.3g", sh.width, sh.height, sh.wrap_u, solver_name(s), err);
            /* the adjoint is the transpose: <M^-1 a, b> = <a, M^-1 b> */
            CHECK_STATUS(ls_param_adjoint(&p, x, ma), LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, vb, mb), LS_OK);
            for (i = 0; i < nk; i++) {
                ab += (double)ma[i] * (double)vb[i];
                ba += (double)x[i] * (double)mb[i];
                na += (double)x[i] * (double)x[i];
                nb += (double)vb[i] * (double)vb[i];
            }
            CHECK_NEAR(ab, ba, tol * sqrt(na * nb));
            /* the solvers agree on M^-1 b */
            if (s == 0) memcpy(ref, mb, nk * sizeof(ls_real));
            err = rel_diff(mb, ref, nk);
            CHECK_MSG(err <= tol, "%ux%u %s vs ldlt: %.3g", sh.width, sh.height, solver_name(s), err);
            /* step with power 2 = two solves */
            memset(st2, 0, nk * sizeof(ls_real));
            CHECK_STATUS(ls_param_step(&p, st2, vb, (ls_real)-1, 2), LS_OK);
            CHECK_STATUS(ls_param_from_differential(&p, mb, y), LS_OK);
            err = rel_diff(st2, y, nk);
            CHECK_MSG(err <= tol, "%s step: %.3g", solver_name(s), err);
            /* set_weight to 2w equals a fresh init at 2w (the transform solver: the same bits) */
            if (s == LS_PARAM_GRID || s == LS_PARAM_LDLT) {
                ls_param q;
                ls_param_config c2 = grid_config(s, form, form == LS_SYSTEM_ALPHA ? 0.5 : 20, k);
                CHECK_STATUS(ls_param_set_weight(&p, c2.weight, NULL), LS_OK);
                REQUIRE(ls_param_grid_init(&q, &sh, &c2, &a, NULL) == LS_OK);
                CHECK_STATUS(ls_param_from_differential(&p, vb, mb), LS_OK);
                CHECK_STATUS(ls_param_from_differential(&q, vb, y), LS_OK);
                CHECK(memcmp(mb, y, nk * sizeof(ls_real)) == 0);
                CHECK_STATUS(ls_param_set_weight(&p, (ls_real)-1, NULL), LS_ERR_INVALID);
                CHECK(p.weight == c2.weight);
            }
            ls_arena_restore(&a, m2);
        }
        if (si == 3) printf("     %ux%u wrap, 3 channels, lambda 10: ldlt / cg / grid agree (tolerance %.0e)\n", sh.width,
                            sh.height, LS_REAL_IS_FLOAT ? 2e-5 : 1e-12);
        ls_arena_restore(&a, mk);
    }
}

/* The transform solver is exact at any lambda: 1e8 works in both precisions
 * (the sparse solvers give LS_ERR_NOT_SPD in float); weight 0 copies. */
static void grid_extremes_and_errors(void)
{
    ls_grid_shape sh = {24, 10, 1};
    ls_param p;
    ls_arena a;
    ls_param_config c = grid_config(LS_PARAM_GRID, LS_SYSTEM_LAMBDA, 1e8, 3);
    ls_real x[720], u[720], y[720];
    size_t i, bytes = 0, used0;
    volatile double mean = 0; /* not vectorized: gcc 12 for aarch64 (float build) ICEs on this reduction */
    volatile double dev = 0;
    ls_arena_init(&a, scr_.bytes, sizeof scr_.bytes);
    for (i = 0; i < 720; i++) x[i] = (ls_real)(urand() - 0.5);
    REQUIRE(ls_param_grid_init(&p, &sh, &c, &a, NULL) == LS_OK);
    CHECK_STATUS(ls_param_to_differential(&p, x, u), LS_OK);
    CHECK_STATUS(ls_param_from_differential(&p, u, y), LS_OK);
    /* the round trip is bounded by kappa eps (kappa <= 1 + 8e8): ~1e-7 in double, useless in float */
    printf("     grid lambda 1e8: round trip %.3g (kappa eps %.3g)\n", rel_diff(y, x, 720), 8e8 * (double)LS_REAL_EPSILON);
    CHECK(rel_diff(y, x, 720) <= 4 * (1 + 8e8) * (double)LS_REAL_EPSILON);
    /* M^-1 of random data at lambda 1e8: nearly the channel means */
    CHECK_STATUS(ls_param_from_differential(&p, x, y), LS_OK);
    for (i = 0; i < 240; i++) mean += (double)x[3 * i] / 240;
    for (i = 0; i < 240; i++) dev = fmax(dev, fabs((double)y[3 * i] - mean));
    CHECK(dev <= 1e-6);
    c.weight = 0;
    REQUIRE(ls_param_grid_init(&p, &sh, &c, &a, NULL) == LS_OK);
    x[4] = (ls_real)-0.0;
    CHECK_STATUS(ls_param_from_differential(&p, x, y), LS_OK);
    CHECK(memcmp(x, y, sizeof x) == 0);
    CHECK_STATUS(ls_param_to_differential(&p, x, y), LS_OK);
    CHECK(memcmp(x, y, sizeof x) == 0);
    /* errors */
    used0 = ls_arena_used(&a);
    x[7] = (ls_real)NAN;
    CHECK_STATUS(ls_param_from_differential(&p, x, y), LS_ERR_NONFINITE);
    sh.width = 0;
    CHECK_STATUS(ls_param_grid_init(&p, &sh, &c, &a, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_param_grid_bytes(&sh, &c, &a, &bytes), LS_ERR_INVALID);
    sh.width = 4;
    c.solver = 9;
    CHECK_STATUS(ls_param_grid_init(&p, &sh, &c, &a, NULL), LS_ERR_INVALID);
    c.solver = LS_PARAM_GRID;
    c.form = LS_SYSTEM_ALPHA;
    c.weight = 1;
    CHECK_STATUS(ls_param_grid_init(&p, &sh, &c, &a, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_param_grid_init(&p, NULL, &c, &a, NULL), LS_ERR_INVALID);
    CHECK_EQ(ls_arena_used(&a), used0);
    c.weight = (ls_real)0.5;
    c.solver = LS_PARAM_LDLT;
    CHECK_STATUS(ls_param_grid_bytes(&sh, &c, NULL, &bytes), LS_ERR_INVALID); /* LDLT needs scratch */
    /* GRID is for grids; AUTO on a mesh is the LDL^T */
    {
        ls_mesh m = {oct_pos, oct_tri, 6, 8};
        ls_csc L;
        ls_param q;
        ls_real v[18], w1[18], w2[18];
        ls_param_config cm = config(LS_PARAM_GRID, LS_SYSTEM_LAMBDA, 19);
        REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
        CHECK_STATUS(ls_param_init(&p, &L, &cm, NULL, &a, NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_param_bytes(&L, &cm, NULL, &a, &bytes), LS_ERR_INVALID);
        cm.solver = LS_PARAM_AUTO;
        REQUIRE(ls_param_init(&p, &L, &cm, oct_pos, &a, NULL) == LS_OK);
        CHECK_EQ(p.solver, LS_PARAM_LDLT);
        cm.solver = LS_PARAM_LDLT;
        REQUIRE(ls_param_init(&q, &L, &cm, oct_pos, &a, NULL) == LS_OK);
        for (i = 0; i < 18; i++) v[i] = (ls_real)(urand() - 0.5);
        CHECK_STATUS(ls_param_from_differential(&p, v, w1), LS_OK);
        CHECK_STATUS(ls_param_from_differential(&q, v, w2), LS_OK);
        CHECK(memcmp(w1, w2, sizeof w1) == 0);
    }
}

typedef struct grid_param_job {
    ls_grid_shape sh;
    ls_param_config cfg;
    ls_param p;
} grid_param_job;

static ls_status grid_param_run(void *ctx, ls_arena *a)
{
    grid_param_job *j = (grid_param_job *)ctx;
    return ls_param_grid_init(&j->p, &j->sh, &j->cfg, a, NULL);
}

static uint64_t grid_param_hash(void *ctx)
{
    grid_param_job *j = (grid_param_job *)ctx;
    return test_hash(&j->p, sizeof j->p, TEST_HASH_SEED);
}

static void grid_sweeps(void)
{
    uint32_t v;
    for (v = 0; v < 6; v++) {
        static grid_param_job j;
        sweep_job job;
        size_t bytes = 0;
        ls_arena s;
        ls_arena_init(&s, scr_.bytes, sizeof scr_.bytes);
        memset(&j, 0, sizeof j);
        j.sh.width = v == 4 ? 9u : 12u;
        j.sh.height = v == 5 ? 1u : 7u;
        j.sh.wrap_u = v & 1u;
        j.cfg = grid_config(v == 0 || v == 5 ? LS_PARAM_GRID : v == 1 ? LS_PARAM_AUTO : v == 2 ? LS_PARAM_CG : LS_PARAM_LDLT,
                            LS_SYSTEM_LAMBDA, 10, 3);
        if (v == 4) j.cfg.order = LS_ORDER_AMD;
        REQUIRE(ls_param_grid_bytes(&j.sh, &j.cfg, &s, &bytes) == LS_OK);
        CHECK_EQ(ls_arena_used(&s), 0);
        memset(&job, 0, sizeof job);
        job.name = "param_grid";
        job.run = grid_param_run;
        job.state_hash = grid_param_hash;
        job.ctx = &j;
        job.answer = bytes;
        job.exact = 1;
        CHECK_MSG(sweep_arena(&job) == 0, "variant %u", v);
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
    TEST_RUN(grid_solvers_agree);
    TEST_RUN(grid_extremes_and_errors);
    TEST_RUN(grid_sweeps);
    return TEST_END();
}
