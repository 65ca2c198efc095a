/* test_grid_solve.c - the transform solver of M = s I + w L on a grid:
 * against a dense solve of a Laplacian written out here (small grids, wrap
 * and Neumann, non-powers of two, lambda 0 / 1e-8 / 1 / 10 / 1e8, alpha
 * forms), against the sparse LDL^T and CG (larger grids), the stencil
 * product, set_weight, error cases and the arena sweep. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include "dense.h"

static int emulated;

static uint64_t rs = 0x243F6A8885A308D3ull;
static double urand(void)
{
    return test_rng_unit(&rs);
}

static unsigned char *new_buf(size_t bytes, ls_arena *a)
{
    unsigned char *b = (unsigned char *)malloc(bytes + LS_ARENA_ALIGN);
    if (b != NULL) ls_arena_init(a, b, bytes);
    return b;
}

/* The dense M = s I + w L of a W x H grid, L from the definition: x
 * neighbours (x +- 1) inside the row, or modulo W when wrap and W >= 3;
 * y neighbours inside the column. */
static void dense_system(uint32_t W, uint32_t H, int wrap, double s, double w, double *m)
{
    uint32_t n = W * H, x, y;
    memset(m, 0, (size_t)n * n * sizeof(double));
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            uint32_t i = y * W + x, nb[4], c = 0, q;
            if (x > 0) nb[c++] = i - 1;
            else if (wrap && W >= 3) nb[c++] = i + W - 1;
            if (x + 1 < W) nb[c++] = i + 1;
            else if (wrap && W >= 3) nb[c++] = i + 1 - W;
            if (y > 0) nb[c++] = i - W;
            if (y + 1 < H) nb[c++] = i + W;
            m[(size_t)i * n + i] = s + w * (double)c;
            for (q = 0; q < c; q++) m[(size_t)i * n + nb[q]] = -w;
        }
}

static double rel_err(const ls_real *x, const double *ref, size_t n)
{
    double e = 0, s = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        e += ((double)x[i] - ref[i]) * ((double)x[i] - ref[i]);
        s += ref[i] * ref[i];
    }
    return s > 0 ? sqrt(e / s) : sqrt(e);
}

static double rel_err_r(const ls_real *x, const ls_real *ref, size_t n)
{
    double e = 0, s = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        e += ((double)x[i] - (double)ref[i]) * ((double)x[i] - (double)ref[i]);
        s += (double)ref[i] * (double)ref[i];
    }
    return s > 0 ? sqrt(e / s) : sqrt(e);
}

/* kappa(M) <= (s + 8 w) / s (Gershgorin). */
static double kappa(double s, double w) { return (s + 8 * w) / s; }

static void small_grids_match_dense(void)
{
    static const uint32_t sizes[][2] = {{1, 1}, {1, 7}, {7, 1}, {2, 2}, {2, 5}, {3, 4}, {5, 3},
                                        {4, 4}, {6, 5}, {13, 9}, {8, 16}, {9, 1}, {16, 3}, {1, 12}};
    static const double weights[][2] = {{0, 0}, {0, 1e-8}, {0, 1}, {0, 10}, {0, 1e8}, {1, 0.5}, {1, 0.99}};
    size_t si, wi, i;
    int wrap;
    ls_arena a;
    unsigned char *buf = new_buf(1u << 20, &a);
    double *m = (double *)malloc(208u * 208u * sizeof(double)), *ref = (double *)malloc(208u * 3u * sizeof(double));
    ls_real *b = (ls_real *)malloc(208u * 3u * sizeof(ls_real)), *x = (ls_real *)malloc(208u * 3u * sizeof(ls_real));
    double worst[2] = {0, 0};
    REQUIRE(buf && m && ref && b && x);
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (wrap = 0; wrap < 2; wrap++)
            for (wi = 0; wi < sizeof weights / sizeof weights[0]; wi++) {
                uint32_t W = sizes[si][0], H = sizes[si][1], n = W * H, k = 1 + (uint32_t)((si + wi) % 3);
                uint32_t form = weights[wi][0] != 0 ? LS_SYSTEM_ALPHA : LS_SYSTEM_LAMBDA;
                ls_real wt = (ls_real)weights[wi][1];
                double s = form == LS_SYSTEM_ALPHA ? 1 - (double)wt : 1, w = (double)wt, err, tol;
                ls_arena_mark mk = ls_arena_save(&a);
                ls_grid_solver g;
                REQUIRE(ls_grid_solver_init(&g, W, H, (uint32_t)wrap, k, &a) == LS_OK);
                REQUIRE(ls_grid_solver_set_weight(&g, form, wt, NULL) == LS_OK);
                for (i = 0; i < (size_t)n * k; i++) {
                    b[i] = (ls_real)(urand() - 0.5);
                    ref[i] = (double)b[i];
                }
                dense_system(W, H, wrap, s, w, m);
                REQUIRE(dense_solve(m, (int)n, ref, (int)k));
                CHECK_STATUS(ls_grid_solver_solve(&g, b, x), LS_OK);
                err = rel_err(x, ref, (size_t)n * k);
                /* the dense elimination itself errs by ~kappa eps (double) */
                tol = (LS_REAL_IS_FLOAT ? 2e-6 : 1e-14) * (1 + log2((double)n + 1)) + kappa(s, w) * 4e-16;
                CHECK_MSG(err <= tol, "%ux%u wrap %d form %u w %g k %u: error %.3g > %.3g", W, H, wrap, form, w, k, err,
                          tol);
                if (w <= 10 && err > worst[LS_REAL_IS_FLOAT ? 1 : 0]) worst[LS_REAL_IS_FLOAT ? 1 : 0] = err;
                /* in place gives the same bits */
                {
                    ls_real *y = (ls_real *)malloc((size_t)n * k * sizeof(ls_real));
                    REQUIRE(y != NULL);
                    memcpy(y, b, (size_t)n * k * sizeof(ls_real));
                    CHECK_STATUS(ls_grid_solver_solve(&g, y, y), LS_OK);
                    CHECK(memcmp(y, x, (size_t)n * k * sizeof(ls_real)) == 0);
                    /* the stencil product against the dense matrix */
                    dense_system(W, H, wrap, s, w, m);
                    CHECK_STATUS(ls_grid_solver_apply(&g, b, y), LS_OK);
                    for (i = 0; i < n; i++) {
                        uint32_t c, q;
                        for (c = 0; c < k; c++) {
                            double acc = 0, mag = 0;
                            for (q = 0; q < n; q++) {
                                acc += m[(size_t)i * n + q] * (double)b[q * k + c];
                                mag += fabs(m[(size_t)i * n + q] * (double)b[q * k + c]);
                            }
                            CHECK_NEAR(y[i * k + c], acc, 8 * (double)LS_REAL_EPSILON * mag + 1e-300);
                        }
                    }
                    free(y);
                }
                if (w == 0) CHECK(memcmp(x, b, (size_t)n * k * sizeof(ls_real)) == 0);
                ls_arena_restore(&a, mk);
            }
    printf("     dense grids up to 13x9, weights <= 10: worst relative error %.3g\n", worst[LS_REAL_IS_FLOAT ? 1 : 0]);
    free(m), free(ref), free(b), free(x), free(buf);
}

/* ls_laplacian_grid_wrap (full storage) against the definition, entry by
 * entry; sorted rows; upper storage = its upper triangle. */
static void wrap_laplacian_matches_definition(void)
{
    static const uint32_t sizes[][2] = {{1, 1}, {2, 3}, {3, 1}, {3, 4}, {7, 5}, {1, 6}};
    size_t si;
    ls_arena a;
    unsigned char *buf = new_buf(1u << 18, &a);
    double *m = (double *)malloc(35u * 35u * sizeof(double));
    REQUIRE(buf && m);
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        uint32_t W = sizes[si][0], H = sizes[si][1], n = W * H, j, q, wrap;
        for (wrap = 0; wrap < 2; wrap++) {
            ls_csc F, U;
            size_t bf = 0, bu = 0, used = ls_arena_used(&a);
            uint32_t seen = 0;
            REQUIRE(ls_laplacian_grid_wrap_bytes(W, H, wrap, LS_LAP_FULL, &bf) == LS_OK);
            REQUIRE(ls_laplacian_grid_wrap_bytes(W, H, wrap, LS_LAP_UPPER, &bu) == LS_OK);
            REQUIRE(ls_laplacian_grid_wrap(W, H, wrap, LS_LAP_FULL, &a, &F) == LS_OK);
            CHECK_EQ(ls_arena_used(&a) - used, bf);
            REQUIRE(ls_laplacian_grid_wrap(W, H, wrap, LS_LAP_UPPER, &a, &U) == LS_OK);
            CHECK_EQ(ls_arena_used(&a) - used, bf + bu);
            dense_system(W, H, (int)wrap, 0, 1, m);
            for (j = 0; j < n; j++)
                for (q = F.colptr[j]; q < F.colptr[j + 1]; q++) {
                    CHECK(q == F.colptr[j] || F.rowidx[q] > F.rowidx[q - 1]);
                    CHECK((double)F.values[q] == m[(size_t)F.rowidx[q] * n + j]);
                    seen++;
                }
            for (j = 0; j < n * n; j++) /* every nonzero of the definition and every diagonal entry is stored */
                if (m[j] != 0 || j % (n + 1) == 0) seen--;
            CHECK_EQ(seen, 0);
            for (j = 0, q = 0; j < n; j++) {
                uint32_t p;
                for (p = F.colptr[j]; p < F.colptr[j + 1]; p++)
                    if (F.rowidx[p] <= j) {
                        CHECK(U.rowidx[q] == F.rowidx[p] && U.values[q] == F.values[p]);
                        q++;
                    }
                CHECK_EQ(U.colptr[j + 1], q);
            }
            if (wrap == 0) { /* = ls_laplacian_grid */
                ls_csc G;
                REQUIRE(ls_laplacian_grid(W, H, LS_LAP_FULL, &a, &G) == LS_OK);
                CHECK(ls_csc_nnz(&G) == ls_csc_nnz(&F) && memcmp(G.rowidx, F.rowidx, ls_csc_nnz(&F) * 4u) == 0);
            }
        }
    }
    free(m), free(buf);
}

/* The same systems through the sparse Laplacian of laplacian.c (with its
 * wrap option): LDL^T and CG. */
static void larger_grids_match_ldlt_and_cg(void)
{
    static const uint32_t sizes[][2] = {{64, 64}, {100, 60}, {37, 50}, {128, 3}};
    size_t si;
    int wrap;
    ls_arena a;
    unsigned char *buf = new_buf(64u << 20, &a);
    REQUIRE(buf != NULL);
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (wrap = 0; wrap < 2; wrap++) {
            uint32_t W = sizes[si][0], H = sizes[si][1], n = W * H, k = 3, form = si == 2 ? LS_SYSTEM_ALPHA : LS_SYSTEM_LAMBDA;
            ls_real wt = form == LS_SYSTEM_ALPHA ? (ls_real)0.95 : (ls_real)10;
            size_t nk = (size_t)n * k, i;
            ls_arena_mark mk = ls_arena_save(&a);
            ls_grid_solver g;
            ls_csc L, M;
            ls_ldlt f;
            ls_cg_info info;
            ls_real *b, *x, *xl, *xc;
            double el, ec;
            if (emulated && si > 1) continue;
            REQUIRE(ls_grid_solver_init(&g, W, H, (uint32_t)wrap, k, &a) == LS_OK);
            REQUIRE(ls_grid_solver_set_weight(&g, form, wt, NULL) == LS_OK);
            REQUIRE(ls_laplacian_grid_wrap(W, H, (uint32_t)wrap, LS_LAP_UPPER, &a, &L) == LS_OK);
            REQUIRE(ls_laplacian_system(&L, form, wt, &a, &M, NULL) == LS_OK);
            b = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            x = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            xl = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            xc = (ls_real *)ls_arena_alloc_zero(&a, nk, sizeof(ls_real));
            REQUIRE(b && x && xl && xc);
            for (i = 0; i < nk; i++) b[i] = (ls_real)(urand() - 0.5 + (i % 3 == 0 ? 2.0 : 0.0));
            CHECK_STATUS(ls_grid_solver_solve(&g, b, x), LS_OK);
            REQUIRE(ls_ldlt_analyze(&M, LS_ORDER_AMD, NULL, &a, &f, NULL) == LS_OK);
            REQUIRE(ls_ldlt_factor(&f, &M, &a, NULL) == LS_OK);
            memcpy(xl, b, nk * sizeof(ls_real));
            REQUIRE(ls_ldlt_solve(&f, k, xl, &a) == LS_OK);
            memset(&info, 0, sizeof info);
            info.max_iter = 20000;
            info.tol = LS_REAL_IS_FLOAT ? (ls_real)1e-7 : (ls_real)1e-14;
            REQUIRE(ls_cg_solve(&M, k, b, xc, &a, &info) == LS_OK);
            el = rel_err_r(x, xl, nk);
            ec = rel_err_r(x, xc, nk);
            printf("     %3ux%-3u %s %s: vs LDL^T %.3g, vs CG %.3g (%u iterations)\n", W, H, wrap ? "wrap   " : "neumann",
                   form == LS_SYSTEM_ALPHA ? "alpha 0.95" : "lambda 10 ", el, ec, info.max_iterations);
            CHECK(el <= (LS_REAL_IS_FLOAT ? 2e-5 : 1e-12));
            CHECK(ec <= (LS_REAL_IS_FLOAT ? 5e-5 : 1e-11));
            ls_arena_restore(&a, mk);
        }
    free(buf);
}

/* set_weight: the same bits as a fresh init, no memory; errors keep the
 * previous weight; huge lambda is exact in the constant mode. */
static void set_weight_and_extremes(void)
{
    ls_arena a;
    unsigned char *buf = new_buf(1u << 20, &a);
    ls_grid_solver g, h;
    ls_real b[3 * 35], x1[3 * 35], x2[3 * 35];
    size_t used, i;
    ls_diag dg;
    double mean = 0, xm = 0;
    REQUIRE(buf != NULL);
    REQUIRE(ls_grid_solver_init(&g, 7, 5, 1, 3, &a) == LS_OK);
    REQUIRE(ls_grid_solver_init(&h, 7, 5, 1, 3, &a) == LS_OK);
    for (i = 0; i < 105; i++) b[i] = (ls_real)(urand() - 0.5);
    REQUIRE(ls_grid_solver_set_weight(&g, LS_SYSTEM_LAMBDA, (ls_real)3, NULL) == LS_OK);
    REQUIRE(ls_grid_solver_set_weight(&h, LS_SYSTEM_ALPHA, (ls_real)0.25, NULL) == LS_OK);
    used = ls_arena_used(&a);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_LAMBDA, (ls_real)3, NULL), LS_OK);
    CHECK_EQ(ls_arena_used(&a), used);
    CHECK_STATUS(ls_grid_solver_solve(&g, b, x1), LS_OK);
    CHECK_STATUS(ls_grid_solver_solve(&h, b, x2), LS_OK);
    CHECK(memcmp(x1, x2, sizeof x1) == 0);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_LAMBDA, (ls_real)-1, &dg), LS_ERR_INVALID);
    CHECK(dg.what != NULL && dg.has_value);
    CHECK(strstr(dg.what, "weight: lambda") != NULL);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_ALPHA, (ls_real)1, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "weight: alpha") != NULL);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, 7u, (ls_real)0.5, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "form") != NULL);
    CHECK_STATUS(ls_grid_solver_set_weight(NULL, LS_SYSTEM_LAMBDA, (ls_real)1, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "g: ") != NULL);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_LAMBDA, (ls_real)NAN, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_LAMBDA, (ls_real)INFINITY, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_ALPHA, (ls_real)1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_ALPHA, (ls_real)-0.1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_set_weight(&h, 7u, (ls_real)0.5, NULL), LS_ERR_INVALID);
    CHECK(h.weight == (ls_real)3 && h.form == LS_SYSTEM_LAMBDA);
    CHECK_STATUS(ls_grid_solver_solve(&h, b, x2), LS_OK);
    CHECK(memcmp(x1, x2, sizeof x1) == 0);
    /* lambda 1e30: M^-1 b -> the channel means (the constant mode is exact) */
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_LAMBDA, (ls_real)1e30, NULL), LS_OK);
    CHECK_STATUS(ls_grid_solver_solve(&h, b, x2), LS_OK);
    for (i = 0; i < 35; i++) {
        mean += (double)b[3 * i] / 35;
    }
    for (i = 0; i < 35; i++) xm = fmax(xm, fabs((double)x2[3 * i] - mean));
    CHECK(xm <= 1e-5 * (LS_REAL_IS_FLOAT ? 10 : 1e-9));
    /* alpha close to 1 */
    CHECK_STATUS(ls_grid_solver_set_weight(&h, LS_SYSTEM_ALPHA, (ls_real)0.999999, NULL), LS_OK);
    CHECK_STATUS(ls_grid_solver_solve(&h, b, x2), LS_OK);
    for (i = 0; i < 105; i++) CHECK(isfinite((double)x2[i]));
    free(buf);
}

static void errors(void)
{
    ls_arena a;
    unsigned char *buf = new_buf(1u << 16, &a);
    ls_grid_solver g;
    size_t bytes = 0;
    ls_real b[12], x[12];
    int i;
    REQUIRE(buf != NULL);
    CHECK_STATUS(ls_grid_solver_bytes(0, 3, 0, 1, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_bytes(3, 0, 0, 1, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_bytes(3, 3, 0, 0, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_bytes(3, 3, 0, 1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_bytes(LS_GRID_MAX_SIDE + 1u, 1, 0, 1, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_bytes(65536, 65536, 0, 1, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_grid_solver_bytes(40000, 40000, 1, 3, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_grid_solver_init(NULL, 3, 3, 0, 1, &a), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_init(&g, 3, 3, 0, 1, NULL), LS_ERR_INVALID);
    CHECK_EQ(ls_arena_used(&a), 0);
    REQUIRE(ls_grid_solver_init(&g, 2, 2, 0, 3, &a) == LS_OK);
    REQUIRE(ls_grid_solver_set_weight(&g, LS_SYSTEM_LAMBDA, (ls_real)2, NULL) == LS_OK);
    CHECK_STATUS(ls_grid_solver_set_weight(NULL, LS_SYSTEM_LAMBDA, (ls_real)2, NULL), LS_ERR_INVALID);
    for (i = 0; i < 12; i++) b[i] = (ls_real)i, x[i] = (ls_real)7;
    CHECK_STATUS(ls_grid_solver_solve(NULL, b, x), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_solve(&g, NULL, x), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_solver_apply(&g, b, NULL), LS_ERR_INVALID);
    b[5] = (ls_real)NAN;
    CHECK_STATUS(ls_grid_solver_solve(&g, b, x), LS_ERR_NONFINITE);
    for (i = 0; i < 12; i++) CHECK(x[i] == (ls_real)7);
    b[5] = (ls_real)INFINITY;
    CHECK_STATUS(ls_grid_solver_solve(&g, b, b), LS_ERR_NONFINITE);
    CHECK(isinf((double)b[5]));
    /* finite but huge: the transform overflows: zeros and the named error, never NaN */
    for (i = 0; i < 12; i++) b[i] = (i & 1) ? LS_REAL_MAX : -LS_REAL_MAX;
    CHECK_STATUS(ls_grid_solver_solve(&g, b, x), LS_ERR_NONFINITE);
    for (i = 0; i < 12; i++) CHECK(x[i] == (ls_real)0);
    free(buf);
}

/* ---- the arena sweep ------------------------------------------------------ */

typedef struct grid_job {
    uint32_t w, h, wrap, k;
    ls_grid_solver g;
} grid_job;

static ls_status grid_run(void *ctx, ls_arena *a)
{
    grid_job *j = (grid_job *)ctx;
    return ls_grid_solver_init(&j->g, j->w, j->h, j->wrap, j->k, a);
}

static uint64_t grid_hash(void *ctx)
{
    grid_job *j = (grid_job *)ctx;
    return test_hash(&j->g, sizeof j->g, TEST_HASH_SEED);
}

static void sweeps(void)
{
    static const uint32_t cases[][4] = {{1, 1, 0, 1}, {8, 4, 0, 3}, {7, 5, 1, 3}, {13, 9, 0, 2}, {16, 9, 1, 1},
                                        {2, 3, 1, 1}, {100, 60, 1, 3}};
    size_t c;
    for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        static grid_job j;
        sweep_job job;
        size_t bytes = 0;
        memset(&j, 0, sizeof j);
        j.w = cases[c][0], j.h = cases[c][1], j.wrap = cases[c][2], j.k = cases[c][3];
        REQUIRE(ls_grid_solver_bytes(j.w, j.h, j.wrap, j.k, &bytes) == LS_OK);
        memset(&job, 0, sizeof job);
        job.name = "grid_solver";
        job.run = grid_run;
        job.state_hash = grid_hash;
        job.ctx = &j;
        job.answer = bytes;
        job.exact = 1;
        CHECK_MSG(sweep_arena(&job) == 0, "case %lu", (unsigned long)c);
    }
    {
        size_t b256 = 0, b1024 = 0, b1000 = 0;
        REQUIRE(ls_grid_solver_bytes(256, 256, 0, 3, &b256) == LS_OK);
        REQUIRE(ls_grid_solver_bytes(1024, 1024, 1, 3, &b1024) == LS_OK);
        REQUIRE(ls_grid_solver_bytes(1000, 1000, 0, 3, &b1000) == LS_OK);
        printf("     solver bytes: 256^2 %lu, 1024^2 wrap %lu, 1000^2 (Bluestein) %lu\n", (unsigned long)b256,
               (unsigned long)b1024, (unsigned long)b1000);
        CHECK(b1024 < 400000u); /* O(W + H k): tables and an 8-column block */
    }
}

/* solve2: x1 is the lone solve's bits, x2 two solves to rounding; and the
 * large-steps iteration moved to x (ls_param_adjoint2 + ls_optim_step_mapped)
 * follows the u form (adjoint, step on u, x = M^{-1} u) on the transform
 * solver and on LDL^T, for UniformAdam and SGD with momentum; Adam is refused. */
static void mapped_steps_follow_u_form(void)
{
    const uint32_t W = 24, H = 17, n = W * H, k = 3, steps = 25;
    const size_t nk = (size_t)n * k;
    static const uint32_t methods[2] = {LS_OPTIM_UNIFORM_ADAM, LS_OPTIM_SGD};
    static const uint32_t solvers[2] = {LS_PARAM_GRID, LS_PARAM_LDLT};
    ls_arena a;
    unsigned char *buf = new_buf(16u << 20, &a);
    ls_real *b, *x1, *x2, *y, *wts, *tgt;
    size_t i;
    uint32_t mi, si, wrap, t;
    REQUIRE(buf != NULL);
    b = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    x1 = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    x2 = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    y = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    wts = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    tgt = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    REQUIRE(b && x1 && x2 && y && wts && tgt);
    for (i = 0; i < nk; i++) {
        b[i] = (ls_real)(urand() - 0.5);
        wts[i] = (ls_real)(urand() < 0.2 ? urand() * 4.0 : 0.0); /* sparse data, like bilinear taps */
        tgt[i] = (ls_real)urand();
    }
    for (wrap = 0; wrap < 2; wrap++) {
        ls_arena_mark mk = ls_arena_save(&a);
        ls_grid_solver g;
        REQUIRE(ls_grid_solver_init(&g, W, H, wrap, k, &a) == LS_OK);
        REQUIRE(ls_grid_solver_set_weight(&g, LS_SYSTEM_LAMBDA, (ls_real)30, NULL) == LS_OK);
        CHECK_STATUS(ls_grid_solver_solve2(&g, b, x1, x2), LS_OK);
        CHECK_STATUS(ls_grid_solver_solve(&g, b, y), LS_OK);
        CHECK(memcmp(x1, y, nk * sizeof(ls_real)) == 0);
        CHECK_STATUS(ls_grid_solver_solve(&g, y, y), LS_OK);
        printf("     solve2 %s: M^-2 b vs two solves %.3g\n", wrap ? "wrap   " : "neumann", rel_err_r(x2, y, nk));
        CHECK(rel_err_r(x2, y, nk) <= (LS_REAL_IS_FLOAT ? 1e-5 : 1e-13));
        CHECK_STATUS(ls_grid_solver_solve2(&g, b, x1, x1), LS_ERR_INVALID);
        CHECK_STATUS(ls_grid_solver_solve2(&g, b, x1, (ls_real *)b), LS_ERR_INVALID);
        b[5] = (ls_real)LS_REAL_MAX * (ls_real)4;
        CHECK_STATUS(ls_grid_solver_solve2(&g, b, x1, x2), LS_ERR_NONFINITE);
        b[5] = (ls_real)0.25;
        ls_arena_restore(&a, mk);
    }
    for (si = 0; si < 2; si++)
        for (mi = 0; mi < 2; mi++) {
            ls_arena_mark mk = ls_arena_save(&a);
            ls_param par;
            ls_param_config pc;
            ls_grid_shape shape;
            ls_optim_config oc;
            ls_optim ou, ox;
            ls_real *u, *xu, *xx, *gx, *gu, *gu2;
            uint32_t bs[1];
            double e;
            memset(&pc, 0, sizeof pc);
            pc.solver = solvers[si];
            pc.form = LS_SYSTEM_LAMBDA;
            pc.weight = (ls_real)30;
            pc.k = k;
            pc.order = LS_ORDER_AMD;
            shape.width = W;
            shape.height = H;
            shape.wrap_u = 0;
            REQUIRE(ls_param_grid_init(&par, &shape, &pc, &a, NULL) == LS_OK);
            REQUIRE(ls_optim_config_default(methods[mi], &oc) == LS_OK);
            oc.lr = (ls_real)0.05;
            bs[0] = (uint32_t)nk;
            REQUIRE(ls_optim_init(&ou, &oc, (uint32_t)nk, 1, bs, &a) == LS_OK);
            REQUIRE(ls_optim_init(&ox, &oc, (uint32_t)nk, 1, bs, &a) == LS_OK);
            u = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            xu = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            xx = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            gx = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            gu = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            gu2 = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
            REQUIRE(u && xu && xx && gx && gu && gu2);
            for (i = 0; i < nk; i++) xu[i] = xx[i] = (ls_real)0.5;
            REQUIRE(ls_param_to_differential(&par, xu, u) == LS_OK);
            for (t = 0; t < steps; t++) {
                /* loss sum wts (x - tgt)^2 / 2 at each form's own x */
                for (i = 0; i < nk; i++) gx[i] = wts[i] * (xu[i] - tgt[i]);
                REQUIRE(ls_param_adjoint(&par, gx, gu) == LS_OK);
                REQUIRE(ls_optim_step(&ou, u, gu, NULL) == LS_OK);
                REQUIRE(ls_param_from_differential(&par, u, xu) == LS_OK);
                for (i = 0; i < nk; i++) gx[i] = wts[i] * (xx[i] - tgt[i]);
                REQUIRE(ls_param_adjoint2(&par, gx, gu, gu2) == LS_OK);
                REQUIRE(ls_optim_step_mapped(&ox, xx, gu, gu2, NULL) == LS_OK);
            }
            e = rel_err_r(xx, xu, nk);
            printf("     %s, %s: x after %u mapped steps vs the u form %.3g\n", si == 0 ? "grid  " : "LDL^T ",
                   mi == 0 ? "UniformAdam" : "SGD        ", (unsigned)steps, e);
            CHECK(e <= (LS_REAL_IS_FLOAT ? 1e-4 : 1e-11));
            CHECK(rel_err_r(xx, tgt, nk) > 1e-3); /* it moved, but not onto the data */
            CHECK_STATUS(ls_param_adjoint2(&par, gx, gu, gu), LS_ERR_INVALID);
            oc.lr = (ls_real)0.05;
            {
                ls_optim oa;
                ls_optim_config ac;
                REQUIRE(ls_optim_config_default(LS_OPTIM_ADAM, &ac) == LS_OK);
                REQUIRE(ls_optim_init(&oa, &ac, (uint32_t)nk, 1, bs, &a) == LS_OK);
                CHECK_STATUS(ls_optim_step_mapped(&oa, xx, gu, gu2, NULL), LS_ERR_INVALID);
            }
            gu[7] = gu[7] / (ls_real)0;
            memcpy(y, xx, nk * sizeof(ls_real));
            CHECK_STATUS(ls_optim_step_mapped(&ox, xx, gu, gu2, NULL), LS_ERR_NONFINITE);
            CHECK(memcmp(y, xx, nk * sizeof(ls_real)) == 0);
            ls_arena_restore(&a, mk);
        }
    free(buf);
}

int main(void)
{
    TEST_INIT("test_grid_solve");
    emulated = getenv("LS_TEST_EMULATED") != NULL && strcmp(getenv("LS_TEST_EMULATED"), "1") == 0;
    TEST_RUN(wrap_laplacian_matches_definition);
    TEST_RUN(small_grids_match_dense);
    TEST_RUN(larger_grids_match_ldlt_and_cg);
    TEST_RUN(set_weight_and_extremes);
    TEST_RUN(errors);
    TEST_RUN(sweeps);
    TEST_RUN(mapped_steps_follow_u_form);
    return TEST_END();
}
