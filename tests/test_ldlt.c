/* test_ldlt.c - the sparse LDL^T against a dense LDL^T written here, normwise
 * backward errors on mesh systems M = I + lambda L, error cases, arena sweeps. */
#include "test.h"
#include "sweep.h"
#include "bench/meshgen.h"

typedef long double ld;

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint32_t rnd(void)
{
    return (uint32_t)test_rng_bits(&rng_state);
}
static double urand(void) /* [-1, 1) */
{
    return (double)rnd() / 2097152.0 / 1024.0 * 2.0 - 1.0;
}

static unsigned char *buf;
#define BUF_BYTES ((size_t)96 << 20)

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

/* ---- dense reference: LDL^T in long double, then solve ------------------ */
static void dense_from_csc(const ls_csc *a, ld *d)
{
    uint32_t n = a->ncols, j, p;
    memset(d, 0, sizeof(ld) * n * n);
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1]; p++) {
            uint32_t i = a->rowidx[p];
            if (i > j) continue;
            d[i * n + j] = a->values[p];
            d[j * n + i] = a->values[p];
        }
}

static int dense_ldlt_solve(uint32_t n, const ld *a, const ld *b, ld *x)
{
    ld *l = (ld *)calloc((size_t)n * n, sizeof(ld)), *dd = (ld *)calloc(n, sizeof(ld));
    uint32_t i, j, k;
    int ok = 1;
    for (j = 0; j < n; j++) {
        ld s = a[j * n + j];
        for (k = 0; k < j; k++) s -= l[j * n + k] * l[j * n + k] * dd[k];
        dd[j] = s;
        if (!(s > 0)) ok = 0;
        for (i = j + 1; i < n; i++) {
            ld t = a[i * n + j];
            for (k = 0; k < j; k++) t -= l[i * n + k] * l[j * n + k] * dd[k];
            l[i * n + j] = t / s;
        }
    }
    for (i = 0; i < n; i++) {
        ld t = b[i];
        for (k = 0; k < i; k++) t -= l[i * n + k] * x[k];
        x[i] = t;
    }
    for (i = 0; i < n; i++) x[i] /= dd[i];
    for (i = n; i > 0; i--) {
        ld t = x[i - 1];
        for (k = i; k < n; k++) t -= l[k * n + (i - 1)] * x[k];
        x[i - 1] = t;
    }
    free(l);
    free(dd);
    return ok;
}

/* factor + solve with our library; k = 1 */
static int sparse_solve(const ls_csc *a, uint32_t method, ls_real *x, uint32_t refine_steps, const ls_real *b)
{
    ls_arena arena;
    ls_ldlt f;
    if (ls_arena_init(&arena, buf, BUF_BYTES) != LS_OK) return 0;
    if (ls_ldlt_analyze(a, method, NULL, &arena, &f, NULL) != LS_OK) return 0;
    if (ls_ldlt_factor(&f, a, &arena, NULL) != LS_OK) return 0;
    if (ls_ldlt_solve(&f, 1, x, &arena) != LS_OK) return 0;
    if (refine_steps > 0 && ls_ldlt_refine(&f, a, 1, b, x, refine_steps, &arena) != LS_OK) return 0;
    return 1;
}

/* Random SPD with eigenvalues from 1 to 1/kappa (geometric), eigenvectors
 * from three random Householder reflections; stored with both triangles. */
static void random_spd(uint32_t n, double kappa, ls_arena *arena, ls_csc *out)
{
    double *q = (double *)calloc((size_t)n * n, sizeof(double)), *v = (double *)malloc(n * sizeof(double));
    double *a = (double *)calloc((size_t)n * n, sizeof(double));
    uint32_t *r = (uint32_t *)malloc((size_t)n * n * sizeof(uint32_t)), *c = (uint32_t *)malloc((size_t)n * n * sizeof(uint32_t));
    ls_real *val = (ls_real *)malloc((size_t)n * n * sizeof(ls_real));
    uint32_t i, j, k, h;
    for (i = 0; i < n; i++) q[i * n + i] = 1;
    for (h = 0; h < 3; h++) { /* q = q (I - 2 v v^T / v^T v) */
        double vv = 0;
        for (i = 0; i < n; i++) { v[i] = urand(); vv += v[i] * v[i]; }
        for (i = 0; i < n; i++) {
            double s = 0;
            for (k = 0; k < n; k++) s += q[i * n + k] * v[k];
            for (k = 0; k < n; k++) q[i * n + k] -= 2 * s * v[k] / vv;
        }
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            double s = 0;
            for (k = 0; k < n; k++) s += q[i * n + k] * q[j * n + k] * pow(kappa, -(double)k / (double)(n - 1));
            a[i * n + j] = s;
        }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) { /* symmetrize exactly: use the upper value */
            uint32_t lo = i < j ? i : j, hi = i < j ? j : i;
            r[i * n + j] = i;
            c[i * n + j] = j;
            val[i * n + j] = (ls_real)a[lo * n + hi];
        }
    (void)ls_csc_from_triplets(&(ls_triplets){n, n, (size_t)n * n, r, c, val}, arena, out, NULL);
    free(q); free(v); free(a); free(r); free(c); free(val);
}

static double fwd_error(uint32_t n, const ls_real *x, const ld *xr)
{
    ld e = 0, m = 0;
    uint32_t i;
    for (i = 0; i < n; i++) {
        ld d = (ld)x[i] - xr[i];
        if (d < 0) d = -d;
        if (d > e) e = d;
        if ((xr[i] < 0 ? -xr[i] : xr[i]) > m) m = xr[i] < 0 ? -xr[i] : xr[i];
    }
    return (double)(e / m);
}

/* forward error of our solve against the dense LDL^T, for matrix a */
static void check_forward(const ls_csc *a, double kappa, const char *what)
{
    uint32_t n = a->ncols, i;
    ld *d = (ld *)malloc(sizeof(ld) * n * n), *bl = (ld *)malloc(sizeof(ld) * n), *xr = (ld *)malloc(sizeof(ld) * n);
    ls_real *b = (ls_real *)malloc(sizeof(ls_real) * n), *x = (ls_real *)malloc(sizeof(ls_real) * n);
    double e0, e1, tol = 2.0 * n * kappa * (double)LS_REAL_EPSILON;
    dense_from_csc(a, d);
    for (i = 0; i < n; i++) {
        b[i] = (ls_real)urand();
        bl[i] = b[i];
    }
    CHECK(dense_ldlt_solve(n, d, bl, xr));
    memcpy(x, b, sizeof(ls_real) * n);
    CHECK(sparse_solve(a, LS_ORDER_AMD, x, 0, b));
    e0 = fwd_error(n, x, xr);
    memcpy(x, b, sizeof(ls_real) * n);
    CHECK(sparse_solve(a, LS_ORDER_AMD, x, 2, b));
    e1 = fwd_error(n, x, xr);
    printf("     %-28s n %3u kappa %8.1e: forward error %.2e, refined %.2e (kappa eps %.1e)\n", what, n, kappa, e0, e1,
           kappa * (double)LS_REAL_EPSILON);
    CHECK_MSG(e0 <= tol, "%s: forward error %.3g > %.3g", what, e0, tol);
    CHECK_MSG(e1 <= tol, "%s: refined forward error %.3g > %.3g", what, e1, tol);
    free(d); free(bl); free(xr); free(b); free(x);
}

static void ldlt_random_spd_vs_dense(void)
{
    static const double kd[] = {1e1, 1e4, 1e8, 1e12}, kf[] = {1e1, 1e3, 1e5};
    const double *ks = sizeof(ls_real) == 8 ? kd : kf;
    size_t nk = sizeof(ls_real) == 8 ? 4 : 3, i;
    for (i = 0; i < nk; i++) {
        ls_arena arena;
        ls_csc a;
        REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
        random_spd(60 + 20 * (uint32_t)i, ks[i], &arena, &a);
        check_forward(&a, ks[i], "random SPD");
    }
}

static void ldlt_mesh_laplacians_vs_dense(void)
{
    static const double lambdas[] = {0.1, 19, 1e3};
    size_t i;
    for (i = 0; i < 3; i++) {
        tmesh m[2];
        int k;
        m[0] = icosphere(2);
        m[1] = gridmesh(12, 12);
        for (k = 0; k < 2; k++) {
            mtrip t = laplacian_system(&m[k], lambdas[i], k);
            ls_arena arena;
            ls_csc a;
            char what[64];
            REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
            REQUIRE(build(&t, &arena, &a));
            sprintf(what, "%s lambda %g", k == 0 ? "icosphere" : "grid", lambdas[i]);
            /* kappa <= 1 + 2 lambda max degree (Gershgorin; lambda_min >= 1) */
            check_forward(&a, 1 + 2 * lambdas[i] * (k == 0 ? 6 : 6), what);
            mtrip_free(&t);
            tmesh_free(&m[k]);
        }
    }
}

/* normwise backward error ||Mx - b|| / (||M|| ||x|| + ||b||), infinity norms,
 * in long double over the stored (rounded) matrix; k right-hand sides. */
static double backward_error(const ls_csc *a, uint32_t k, const ls_real *x, const ls_real *b)
{
    uint32_t n = a->ncols, j, p, c;
    ld *r = (ld *)calloc((size_t)n * k, sizeof(ld)), *rowsum = (ld *)calloc(n, sizeof(ld));
    ld rn = 0, an = 0, xn = 0, bn = 0;
    size_t i;
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1]; p++) {
            uint32_t ii = a->rowidx[p];
            ld v = a->values[p];
            if (ii > j) continue;
            for (c = 0; c < k; c++) r[(size_t)ii * k + c] += v * (ld)x[(size_t)j * k + c];
            rowsum[ii] += v < 0 ? -v : v;
            if (ii != j) {
                for (c = 0; c < k; c++) r[(size_t)j * k + c] += v * (ld)x[(size_t)ii * k + c];
                rowsum[j] += v < 0 ? -v : v;
            }
        }
    for (i = 0; i < (size_t)n * k; i++) {
        ld d = r[i] - (ld)b[i];
        d = d < 0 ? -d : d;
        if (d > rn) rn = d;
        if ((x[i] < 0 ? -(ld)x[i] : (ld)x[i]) > xn) xn = x[i] < 0 ? -(ld)x[i] : (ld)x[i];
        if ((b[i] < 0 ? -(ld)b[i] : (ld)b[i]) > bn) bn = b[i] < 0 ? -(ld)b[i] : (ld)b[i];
    }
    for (j = 0; j < n; j++)
        if (rowsum[j] > an) an = rowsum[j];
    free(r);
    free(rowsum);
    return (double)(rn / (an * xn + bn));
}

static void ldlt_backward_error_table(void)
{
    static const double lambdas[] = {0, 1e-6, 1, 19, 1e3, 1e6, 1e8};
    const double limit = sizeof(ls_real) == 8 ? 1e-14 : 1e-6;
    int mi;
    printf("     | mesh | n | lambda | backward error | refined (2 steps) |\n");
    for (mi = 0; mi < 2; mi++) {
        tmesh m = mi == 0 ? icosphere(5) : gridmesh(100, 100);
        size_t li;
        for (li = 0; li < sizeof lambdas / sizeof lambdas[0]; li++) {
            mtrip t = laplacian_system(&m, lambdas[li], 0);
            ls_arena arena;
            ls_csc a;
            ls_ldlt f;
            ls_diag dg;
            ls_real *b = (ls_real *)malloc(sizeof(ls_real) * 3 * m.nv), *x = (ls_real *)malloc(sizeof(ls_real) * 3 * m.nv);
            double e0 = -1, e1 = -1;
            ls_status st;
            size_t i;
            REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
            REQUIRE(build(&t, &arena, &a));
            for (i = 0; i < 3 * (size_t)m.nv; i++) b[i] = (ls_real)urand();
            memcpy(x, b, sizeof(ls_real) * 3 * m.nv);
            REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
            st = ls_ldlt_factor(&f, &a, &arena, &dg);
            if (st == LS_OK) {
                CHECK_STATUS(ls_ldlt_solve(&f, 3, x, &arena), LS_OK);
                e0 = backward_error(&a, 3, x, b);
                CHECK_STATUS(ls_ldlt_refine(&f, &a, 3, b, x, 2, &arena), LS_OK);
                e1 = backward_error(&a, 3, x, b);
                printf("     | %s | %u | %g | %.3e | %.3e |\n", mi == 0 ? "icosphere" : "grid 100x100", m.nv,
                       lambdas[li], e0, e1);
                CHECK_MSG(e1 <= limit, "lambda %g: refined backward error %.3g", lambdas[li], e1);
                /* float sums (SUMS=real, for FPUs without double): about 2e-6 here */
                CHECK_MSG(e0 <= (sizeof(ls_acc) == 8 ? limit : 3e-6), "lambda %g: backward error %.3g", lambdas[li], e0);
            } else {
                printf("     | %s | %u | %g | %s at column %llu (pivot %.3g) | |\n", mi == 0 ? "icosphere" : "grid 100x100",
                       m.nv, lambdas[li], ls_status_name(st), (unsigned long long)dg.index, (double)dg.value);
                /* only allowed where the identity rounds away: float, lambda 1e8 */
                CHECK_MSG(st == LS_ERR_NOT_SPD && sizeof(ls_real) == 4 && lambdas[li] >= 1e7,
                          "lambda %g: %s", lambdas[li], ls_status_name(st));
            }
            free(b);
            free(x);
            mtrip_free(&t);
        }
        tmesh_free(&m);
    }
}

static void ldlt_no_subnormals_and_refactor(void)
{
    tmesh m = icosphere(5);
    mtrip t1 = laplacian_system(&m, 1.0, 0), t19 = laplacian_system(&m, 19.0, 0);
    ls_arena arena;
    ls_csc a1, a19;
    ls_ldlt f, g;
    uint32_t i, sub = 0, zero = 0;
    ls_real *lx;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(build(&t1, &arena, &a1));
    REQUIRE(build(&t19, &arena, &a19));
    REQUIRE(ls_ldlt_analyze(&a19, LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
    g = f;
    REQUIRE(ls_ldlt_factor(&f, &a19, &arena, NULL) == LS_OK);
    for (i = 0; i < f.l_nnz; i++) {
        ls_real v = f.lx[i] < 0 ? -f.lx[i] : f.lx[i];
        if (v == 0) zero++;
        else if (v < (sizeof(ls_real) == 4 ? (ls_real)FLT_MIN : (ls_real)DBL_MIN)) sub++;
    }
    printf("     lambda 19, n %u: nnz(L) %u, flushed to zero %u, subnormal %u\n", m.nv, f.l_nnz, zero, sub);
    CHECK_EQ(sub, 0);
    lx = (ls_real *)malloc(sizeof(ls_real) * f.l_nnz);
    memcpy(lx, f.lx, sizeof(ls_real) * f.l_nnz);
    /* a second factor at lambda 1, then refactor to 19: the same bits */
    REQUIRE(ls_ldlt_factor(&g, &a1, &arena, NULL) == LS_OK);
    CHECK(memcmp(g.lx, lx, sizeof(ls_real) * f.l_nnz) != 0);
    CHECK_STATUS(ls_ldlt_refactor(&g, &a19, NULL), LS_OK);
    CHECK(memcmp(g.lx, lx, sizeof(ls_real) * f.l_nnz) == 0);
    CHECK(memcmp(g.dinv, f.dinv, sizeof(ls_real) * f.n) == 0);
    free(lx);
    mtrip_free(&t1);
    mtrip_free(&t19);
    tmesh_free(&m);
}

static void ldlt_multi_rhs_and_digest(void)
{
    /* k = 3 interleaved equals three k = 1 solves bit for bit, and k = 2, 5 too */
    tmesh m = icosphere(3);
    mtrip t = laplacian_system(&m, 19.0, 1);
    ls_arena arena;
    ls_csc a;
    ls_ldlt f;
    uint32_t n = m.nv, i, c, k;
    ls_real *x3 = (ls_real *)malloc(sizeof(ls_real) * 5 * n), *x1 = (ls_real *)malloc(sizeof(ls_real) * n);
    ls_real *b = (ls_real *)malloc(sizeof(ls_real) * 5 * n);
    uint64_t h;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(build(&t, &arena, &a));
    REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
    REQUIRE(ls_ldlt_factor(&f, &a, &arena, NULL) == LS_OK);
    for (i = 0; i < 5 * n; i++) b[i] = (ls_real)((double)(i % 97) / 97.0 - 0.5);
    for (k = 1; k <= 5; k++) {
        memcpy(x3, b, sizeof(ls_real) * k * n);
        CHECK_STATUS(ls_ldlt_solve(&f, k, x3, &arena), LS_OK);
        for (c = 0; c < k; c++) {
            for (i = 0; i < n; i++) x1[i] = b[(size_t)i * k + c];
            CHECK_STATUS(ls_ldlt_solve(&f, 1, x1, &arena), LS_OK);
            for (i = 0; i < n; i++) CHECK(x1[i] == x3[(size_t)i * k + c]);
        }
    }
    memcpy(x3, b, sizeof(ls_real) * 3 * n);
    CHECK_STATUS(ls_ldlt_solve(&f, 3, x3, &arena), LS_OK);
    h = test_hash_reals(f.lx, f.l_nnz, TEST_HASH_SEED);
    h = test_hash_reals(f.dinv, n, h);
    h = test_hash_reals(x3, 3 * (size_t)n, h);
    printf("     digest (icosphere 642, lambda 19, factor + 3-RHS solve): %016llx\n", (unsigned long long)h);
    /* the same bits on every compiler and architecture (measured: gcc and clang, x86-64) */
    CHECK(h == (sizeof(ls_real) == 8 ? 0x6640e17f1302a6a3ull : sizeof(ls_acc) == 8 ? 0x52ecddb881dbff9bull : 0x46ec4bba2ee45146ull));
    free(x3);
    free(x1);
    free(b);
    mtrip_free(&t);
    tmesh_free(&m);
}

static void ldlt_errors(void)
{
    ls_arena arena;
    ls_csc a;
    ls_ldlt f;
    ls_diag dg;
    uint32_t r[8], c[8];
    ls_real v[8], x[4];
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    /* indefinite: diag(2, -1, 3) */
    r[0] = c[0] = 0; v[0] = 2;
    r[1] = c[1] = 1; v[1] = -1;
    r[2] = c[2] = 2; v[2] = 3;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){3, 3, 3, r, c, v}, &arena, &a, NULL) == LS_OK);
    REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_NATURAL, NULL, &arena, &f, NULL) == LS_OK);
    {
        size_t used = ls_arena_used(&arena);
        CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, &dg), LS_ERR_NOT_SPD);
        CHECK(dg.has_index && dg.index == 1 && dg.value == -1);
        CHECK(f.state == LS_LDLT_INVALID);
        CHECK_EQ(ls_arena_used(&arena), used);
    }
    x[0] = x[1] = x[2] = 1;
    CHECK_STATUS(ls_ldlt_solve(&f, 1, x, &arena), LS_ERR_STATE);
    /* singular [[1 1][1 1]] with a permutation: the pivot of old column 0 or 1 is 0 */
    r[0] = 0; c[0] = 0; v[0] = 1;
    r[1] = 0; c[1] = 1; v[1] = 1;
    r[2] = 1; c[2] = 1; v[2] = 1;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){2, 2, 3, r, c, v}, &arena, &a, NULL) == LS_OK);
    {
        uint32_t perm[2] = {1, 0};
        REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_GIVEN, perm, &arena, &f, NULL) == LS_OK);
    }
    CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, &dg), LS_ERR_NOT_SPD);
    CHECK(dg.index == 0 && dg.value == 0);
    /* NaN off the diagonal: the pivot after it is NaN, named */
    v[1] = (ls_real)NAN;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){2, 2, 3, r, c, v}, &arena, &a, NULL) == LS_OK);
    REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_NATURAL, NULL, &arena, &f, NULL) == LS_OK);
    CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, &dg), LS_ERR_NOT_SPD);
    CHECK(dg.index == 1 && dg.value != dg.value);
    CHECK(strstr(dg.what, "non-finite") != NULL);
    /* infinite diagonal */
    v[1] = 0;
    v[0] = (ls_real)INFINITY;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){2, 2, 3, r, c, v}, &arena, &a, NULL) == LS_OK);
    REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_NATURAL, NULL, &arena, &f, NULL) == LS_OK);
    CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, &dg), LS_ERR_NOT_SPD);
    CHECK(dg.index == 0);
    /* then a good refactor revalidates: factor once good, break it, repair */
    v[0] = 4;
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){2, 2, 3, r, c, v}, &arena, &a, NULL) == LS_OK);
    REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
    CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, NULL), LS_OK);
    a.values[0] = -4;
    CHECK_STATUS(ls_ldlt_refactor(&f, &a, &dg), LS_ERR_NOT_SPD);
    CHECK_STATUS(ls_ldlt_solve(&f, 1, x, &arena), LS_ERR_STATE);
    a.values[0] = 4;
    CHECK_STATUS(ls_ldlt_refactor(&f, &a, &dg), LS_OK);
    x[0] = 4; x[1] = 1; /* [[4 0][0 1]] x = (4, 1) */
    CHECK_STATUS(ls_ldlt_solve(&f, 1, x, &arena), LS_OK);
    CHECK(x[0] == 1 && x[1] == 1);
    /* non-finite right-hand side: error, x untouched */
    x[0] = (ls_real)NAN;
    x[1] = 2;
    CHECK_STATUS(ls_ldlt_solve(&f, 1, x, &arena), LS_ERR_NONFINITE);
    CHECK(x[1] == 2);
    {
        /* k = 3 (the fused gather/check path): an infinity anywhere is
         * reported, x is untouched and the arena is as before */
        ls_real x3[6];
        ls_arena_mark before = ls_arena_save(&arena);
        int pos;
        for (pos = 0; pos < 6; pos++) {
            int q;
            for (q = 0; q < 6; q++) x3[q] = (ls_real)(q + 1);
            x3[pos] = pos % 2 ? (ls_real)INFINITY : (ls_real)-INFINITY;
            CHECK_STATUS(ls_ldlt_solve(&f, 3, x3, &arena), LS_ERR_NONFINITE);
            CHECK(x3[(pos + 1) % 6] == (ls_real)((pos + 1) % 6 + 1));
            CHECK(arena.top == before.top && arena.bottom == before.bottom);
        }
        for (pos = 0; pos < 6; pos++) x3[pos] = (ls_real)(pos + 1);
        x3[0] = 4 * x3[0]; x3[1] = 4 * x3[1]; x3[2] = 4 * x3[2]; /* row 0 scaled by the pivot 4 */
        CHECK_STATUS(ls_ldlt_solve(&f, 3, x3, &arena), LS_OK);
        CHECK(x3[0] == 1 && x3[1] == 2 && x3[2] == 3 && x3[3] == 4 && x3[4] == 5 && x3[5] == 6);
    }
    /* a matrix whose pattern size differs from the analyzed one */
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){2, 2, 2, r, c, v}, &arena, &a, NULL) == LS_OK);
    CHECK_STATUS(ls_ldlt_refactor(&f, &a, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "a: ") != NULL);
    /* empty 0 x 0: trivially fine; n x n with no entries: zero pivot */
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){0, 0, 0, r, c, v}, &arena, &a, NULL) == LS_OK);
    CHECK_STATUS(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL), LS_OK);
    CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, NULL), LS_OK);
    CHECK_STATUS(ls_ldlt_solve(&f, 3, NULL, &arena), LS_OK);
    REQUIRE(ls_csc_from_triplets(&(ls_triplets){3, 3, 0, r, c, v}, &arena, &a, NULL) == LS_OK);
    CHECK_STATUS(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL), LS_OK);
    CHECK_STATUS(ls_ldlt_factor(&f, &a, &arena, &dg), LS_ERR_NOT_SPD);
    CHECK(dg.value == 0);
    /* bad arguments */
    CHECK_STATUS(ls_ldlt_analyze(NULL, LS_ORDER_AMD, NULL, &arena, &f, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_ldlt_analyze(&a, 7, NULL, &arena, &f, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "method") != NULL);
    CHECK_STATUS(ls_ldlt_analyze(&a, LS_ORDER_GIVEN, NULL, &arena, &f, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "perm is NULL") != NULL);
    CHECK_STATUS(ls_ldlt_analyze_mesh(&a, LS_ORDER_ND, NULL, &arena, &f, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "xyz") != NULL);
    CHECK_STATUS(ls_ldlt_factor(NULL, &a, &arena, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "f: ") != NULL);
    {
        uint32_t perm[3] = {0, 0, 1};
        CHECK_STATUS(ls_ldlt_analyze(&a, LS_ORDER_GIVEN, perm, &arena, &f, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "perm") != NULL);
    }
}

/* ---- arena sweeps ------------------------------------------------------- */
typedef struct ld_job {
    const ls_csc *a;
    const ls_real *xyz;
    ls_ldlt f, base;
    ls_real *x, *b;
    int phase; /* 0 analyze, 1 factor, 2 solve, 3 refine, 4 analyze auto */
} ld_job;

static ls_status ld_run(void *ctx, ls_arena *arena)
{
    ld_job *j = (ld_job *)ctx;
    switch (j->phase) {
    case 0: return ls_ldlt_analyze(j->a, LS_ORDER_AMD, NULL, arena, &j->f, NULL);
    case 1: return ls_ldlt_factor(&j->f, j->a, arena, NULL);
    case 2: return ls_ldlt_solve(&j->f, 3, j->x, arena);
    case 4: return ls_ldlt_analyze_mesh(j->a, LS_ORDER_AUTO, j->xyz, arena, &j->f, NULL);
    default: return ls_ldlt_refine(&j->f, j->a, 3, j->b, j->x, 1, arena);
    }
}
static uint64_t ld_hash(void *ctx)
{
    ld_job *j = (ld_job *)ctx;
    uint64_t h = test_hash(j->a->values, sizeof(ls_real) * ls_csc_nnz(j->a), TEST_HASH_SEED);
    h = test_hash(&j->f, sizeof j->f, h);
    return test_hash(j->x, sizeof(ls_real) * 3 * j->a->ncols, h);
}
static void ld_reset(void *ctx)
{
    ld_job *j = (ld_job *)ctx;
    j->f = j->base;
    memcpy(j->x, j->b, sizeof(ls_real) * 3 * j->a->ncols);
}

static void ldlt_arena_sweeps(void)
{
    tmesh m = icosphere(2);
    mtrip t = laplacian_system(&m, 19.0, 0);
    ls_arena arena, big;
    ls_csc a;
    ld_job j;
    sweep_job sj;
    uint32_t i;
    unsigned char *fbuf = (unsigned char *)malloc((size_t)16 << 20);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(build(&t, &arena, &a));
    memset(&j, 0, sizeof j);
    j.a = &a;
    j.x = (ls_real *)malloc(sizeof(ls_real) * 3 * a.ncols);
    j.b = (ls_real *)malloc(sizeof(ls_real) * 3 * a.ncols);
    for (i = 0; i < 3 * a.ncols; i++) j.b[i] = j.x[i] = (ls_real)(i % 7) - (ls_real)3;
    memset(&sj, 0, sizeof sj);
    sj.run = ld_run;
    sj.state_hash = ld_hash;
    sj.reset = ld_reset;
    sj.ctx = &j;
    sj.exact = 1;
    /* analyze */
    sj.name = "ldlt_analyze";
    j.phase = 0;
    REQUIRE(ls_ldlt_analyze_bytes(&a, LS_ORDER_AMD, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    /* factor: on top of an analysis living in another arena */
    REQUIRE(ls_arena_init(&big, fbuf, (size_t)16 << 20) == LS_OK);
    REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &big, &j.base, NULL) == LS_OK);
    j.f = j.base;
    j.phase = 1;
    sj.name = "ldlt_factor";
    REQUIRE(ls_ldlt_bytes(&j.f, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    /* solve and refine: scratch only */
    REQUIRE(ls_ldlt_factor(&j.base, &a, &big, NULL) == LS_OK);
    j.f = j.base;
    j.phase = 2;
    sj.name = "ldlt_solve";
    REQUIRE(ls_ldlt_solve_bytes(&j.f, 3, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    j.phase = 3;
    sj.name = "ldlt_refine";
    REQUIRE(ls_ldlt_refine_bytes(&j.f, 3, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    /* automatic ordering choice (needs coordinates) */
    {
        ls_real *xyz = (ls_real *)malloc(sizeof(ls_real) * 3 * m.nv);
        for (i = 0; i < 3 * m.nv; i++) xyz[i] = (ls_real)m.pos[i];
        j.xyz = xyz;
        j.phase = 4;
        memset(&j.base, 0, sizeof j.base);
        j.f = j.base;
        sj.name = "ldlt_analyze_mesh_auto";
        REQUIRE(ls_ldlt_analyze_mesh_bytes(&a, LS_ORDER_AUTO, &sj.answer) == LS_OK);
        CHECK_EQ(sweep_arena(&sj), 0);
        free(xyz);
    }
    free(j.x);
    free(j.b);
    free(fbuf);
    mtrip_free(&t);
    tmesh_free(&m);
}

static void ldlt_auto_ordering(void)
{
    int k;
    for (k = 0; k < 2; k++) {
        tmesh m = k == 0 ? icosphere(5) : gridmesh(60, 50);
        mtrip t = laplacian_system(&m, 19.0, 0);
        ls_real *xyz = (ls_real *)malloc(sizeof(ls_real) * 3 * m.nv);
        ls_real *b = (ls_real *)malloc(sizeof(ls_real) * 3 * m.nv), *x = (ls_real *)malloc(sizeof(ls_real) * 3 * m.nv);
        ls_arena arena;
        ls_csc a;
        ls_ldlt f, g;
        size_t i;
        double e;
        for (i = 0; i < 3 * (size_t)m.nv; i++) {
            xyz[i] = (ls_real)m.pos[i];
            b[i] = x[i] = (ls_real)urand();
        }
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        CHECK_STATUS(ls_ldlt_analyze(&a, LS_ORDER_ND, NULL, &arena, &f, NULL), LS_ERR_INVALID);
        REQUIRE(ls_ldlt_analyze_mesh(&a, LS_ORDER_AUTO, xyz, &arena, &f, NULL) == LS_OK);
        REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &g, NULL) == LS_OK);
        printf("     %s n %u: auto picks %s, nnz(L) %u (amd %u)\n", k == 0 ? "icosphere" : "grid 60x50", m.nv,
               f.method == LS_ORDER_ND ? "nd" : "amd", f.l_nnz, g.l_nnz);
        CHECK(f.l_nnz <= g.l_nnz);
        if (k == 0) CHECK(f.method == LS_ORDER_ND);
        REQUIRE(ls_ldlt_factor(&f, &a, &arena, NULL) == LS_OK);
        CHECK_STATUS(ls_ldlt_solve(&f, 3, x, &arena), LS_OK);
        CHECK_STATUS(ls_ldlt_refine(&f, &a, 3, b, x, 2, &arena), LS_OK);
        e = backward_error(&a, 3, x, b);
        CHECK_MSG(e <= (sizeof(ls_real) == 8 ? 1e-14 : 1e-6), "backward error %.3g", e);
        free(xyz);
        free(b);
        free(x);
        mtrip_free(&t);
        tmesh_free(&m);
    }
}

/* A parallel-for on this thread that runs the tasks in an order that
 * changes with every call (a rotation, every other call reversed). */
static void scrambled_for(void *ctx, uint32_t count, ls_task_fn task, void *arg)
{
    uint32_t *calls = (uint32_t *)ctx, k;
    const uint32_t shift = *calls % count, flip = *calls % 2u;
    for (k = 0; k < count; k++) task(arg, flip ? count - 1u - (k + shift) % count : (k + shift) % count, 0);
    (*calls)++;
}

/* The solve split over 1 .. 16 workers gives the whole solve's bits, on
 * one tree (AMD, nested dissection) and on a forest (two components); its
 * memory is what the query says; T stays within a sixteenth of the work. */
static void ldlt_split_same_bits(void)
{
    static const uint32_t workers[] = {1, 2, 3, 4, 7, 16};
    int k;
    for (k = 0; k < 4; k++) {
        tmesh m = k == 0 ? icosphere(4) : k == 1 ? icosphere(5) : gridmesh(60, 50);
        mtrip t = laplacian_system(&m, 19.0, 0);
        uint32_t n = m.nv, w, calls = 0;
        ls_real *xyz = (ls_real *)malloc(sizeof(ls_real) * 3 * n);
        ls_real *b = (ls_real *)malloc(sizeof(ls_real) * 3 * n), *x = (ls_real *)malloc(sizeof(ls_real) * 3 * n);
        ls_parallel par;
        ls_arena arena;
        ls_csc a;
        ls_ldlt f;
        size_t i;
        par.run = scrambled_for;
        par.ctx = &calls;
        if (k == 3) { /* cut the grid into two components: drop the couplings across row 25 */
            size_t j, kept = 0;
            for (j = 0; j < t.count; j++) {
                if (t.r[j] != t.c[j] && (t.r[j] < 25u * 60u) != (t.c[j] < 25u * 60u)) continue;
                t.r[kept] = t.r[j];
                t.c[kept] = t.c[j];
                t.v[kept] = t.v[j];
                kept++;
            }
            t.count = kept;
        }
        for (i = 0; i < 3 * (size_t)n; i++) {
            xyz[i] = (ls_real)m.pos[i];
            b[i] = (ls_real)urand();
        }
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        if (k == 1) REQUIRE(ls_ldlt_analyze_mesh(&a, LS_ORDER_ND, xyz, &arena, &f, NULL) == LS_OK);
        else REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
        REQUIRE(ls_ldlt_factor(&f, &a, &arena, NULL) == LS_OK);
        memcpy(x, b, sizeof(ls_real) * 3 * n);
        REQUIRE(ls_ldlt_solve(&f, 3, x, &arena) == LS_OK);
        for (w = 0; w < sizeof workers / sizeof workers[0]; w++) {
            ls_arena_mark mark = ls_arena_save(&arena);
            ls_ldlt_split sp;
            ls_ldlt_split_stats st;
            size_t object = 0, peak = 0, before = ls_arena_used(&arena);
            ls_real *y = (ls_real *)malloc(sizeof(ls_real) * 3 * n);
            int same = 1, pass;
            REQUIRE(ls_ldlt_split_bytes_n(n, workers[w], &object, &peak) == LS_OK);
            ls_arena_reset_peak(&arena);
            CHECK_STATUS(ls_ldlt_split_init(&sp, &f, workers[w], &arena), LS_OK);
            CHECK(ls_arena_used(&arena) - before == object);
            CHECK(arena.peak - before == peak);
            REQUIRE(ls_ldlt_split_get_stats(&sp, &f, &st) == LS_OK);
            CHECK(st.top_work * 3u <= st.work);
            CHECK(st.work >= LS_LDLT_SPLIT_MIN_WORK && sp.workers == workers[w]); /* the split runs */
            for (pass = 0; pass < 2; pass++) { /* twice: the scrambler's order changes */
                memcpy(y, b, sizeof(ls_real) * 3 * n);
                CHECK_STATUS(ls_ldlt_solve_split(&f, &sp, pass == 0 ? &par : NULL, y, &arena), LS_OK);
                for (i = 0; i < 3 * (size_t)n; i++) same &= memcmp(&x[i], &y[i], sizeof(ls_real)) == 0;
            }
            CHECK_MSG(same, "case %d, %u workers: the split solve differs from the whole one", k, workers[w]);
            if (workers[w] == 2u || workers[w] == 4u)
                printf("     %s n %u, %u workers: %u pieces, T %.1f %% of the work, the most loaded worker %.1f %%, "
                       "held entries %.1f %%\n",
                       k == 0 ? "icosphere amd" : k == 1 ? "icosphere nd" : k == 2 ? "grid amd" : "two grids amd", n,
                       workers[w], st.pieces, 100.0 * (double)st.top_work / (double)st.work,
                       100.0 * (double)st.max_load / (double)st.work, 100.0 * (double)st.held_entries / (double)st.work);
            if (workers[w] == 2u) CHECK(st.pieces >= 2u && st.max_load * 10u <= st.work * 6u);
            free(y);
            ls_arena_restore(&arena, mark);
        }
        {
            ls_ldlt_split sp;
            ls_ldlt g = f;

            CHECK_STATUS(ls_ldlt_split_init(&sp, &f, 0, &arena), LS_ERR_INVALID);
            CHECK_STATUS(ls_ldlt_split_init(&sp, &f, 4097, &arena), LS_ERR_INVALID);
            g.state = LS_LDLT_ANALYZED;
            CHECK_STATUS(ls_ldlt_split_init(&sp, &g, 2, &arena), LS_ERR_STATE);
            REQUIRE(ls_ldlt_split_init(&sp, &f, 2, &arena) == LS_OK);
            sp.n = n - 1u;
            CHECK_STATUS(ls_ldlt_solve_split(&f, &sp, &par, x, &arena), LS_ERR_INVALID);
        }
        free(xyz);
        free(b);
        free(x);
        mtrip_free(&t);
        tmesh_free(&m);
    }
}

/* The plan on the trees at the extremes: a small factor, a chain (a path, natural order:
 * nothing to split) and a star (an arrow matrix: 20,000 leaves under one
 * root): the same bits, and the build stays linear (the test's time). */
static void ldlt_split_chain_and_star(void)
{
    { /* a factor below the minimum work: the plan keeps the solve whole */
        tmesh m = icosphere(2);
        mtrip t = laplacian_system(&m, 19.0, 0);
        ls_arena arena;
        ls_ldlt_split sp;
        ls_csc a;
        ls_ldlt f;
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        REQUIRE(ls_ldlt_analyze(&a, LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
        REQUIRE(ls_ldlt_factor(&f, &a, &arena, NULL) == LS_OK);
        CHECK_STATUS(ls_ldlt_split_init(&sp, &f, 2, &arena), LS_OK);
        CHECK(f.l_nnz + f.n < LS_LDLT_SPLIT_MIN_WORK && sp.workers == 1u);
        mtrip_free(&t);
        tmesh_free(&m);
    }
    int k;
    for (k = 0; k < 2; k++) {
        const uint32_t n = 20001;
        mtrip t;
        uint32_t i, calls = 0;
        ls_real *b = (ls_real *)malloc(sizeof(ls_real) * 3 * n), *x = (ls_real *)malloc(sizeof(ls_real) * 3 * n);
        ls_parallel par;
        ls_arena arena;
        ls_ldlt_split sp;
        ls_ldlt_split_stats st;
        ls_csc a;
        ls_ldlt f;
        int same = 1;
        t.n = n;
        t.count = 0;
        t.r = (uint32_t *)malloc(sizeof(uint32_t) * 2 * n);
        t.c = (uint32_t *)malloc(sizeof(uint32_t) * 2 * n);
        t.v = (double *)malloc(sizeof(double) * 2 * n);
        for (i = 0; i < n; i++) { /* the diagonal, then one coupling per row below the first */
            t.r[t.count] = t.c[t.count] = i;
            t.v[t.count++] = k == 1 && i == 0 ? (double)n : 3.0;
            if (i == 0) continue;
            t.r[t.count] = k == 0 ? i - 1u : 0u; /* upper triangle: row <= col */
            t.c[t.count] = i;
            t.v[t.count++] = -1.0;
        }
        for (i = 0; i < 3 * n; i++) b[i] = (ls_real)urand();
        par.run = scrambled_for;
        par.ctx = &calls;
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(build(&t, &arena, &a));
        REQUIRE(ls_ldlt_analyze(&a, k == 0 ? LS_ORDER_NATURAL : LS_ORDER_AMD, NULL, &arena, &f, NULL) == LS_OK);
        REQUIRE(ls_ldlt_factor(&f, &a, &arena, NULL) == LS_OK);
        memcpy(x, b, sizeof(ls_real) * 3 * n);
        REQUIRE(ls_ldlt_solve(&f, 3, x, &arena) == LS_OK);
        CHECK_STATUS(ls_ldlt_split_init(&sp, &f, 1024, &arena), LS_OK);
        REQUIRE(ls_ldlt_split_get_stats(&sp, &f, &st) == LS_OK);
        printf("     %s n %u, 1024 workers: %u pieces, T %.1f %% of the work\n", k == 0 ? "chain" : "star", n,
               st.pieces, 100.0 * (double)st.top_work / (double)st.work);
        CHECK(st.work >= LS_LDLT_SPLIT_MIN_WORK);
        if (k == 1) CHECK(st.pieces >= n - 2u); /* the leaves (AMD may keep one with the root) */
        CHECK_STATUS(ls_ldlt_solve_split(&f, &sp, &par, b, &arena), LS_OK);
        for (i = 0; i < 3 * n; i++) same &= memcmp(&x[i], &b[i], sizeof(ls_real)) == 0;
        CHECK_MSG(same, "%s: the split solve differs from the whole one", k == 0 ? "chain" : "star");
        free(b);
        free(x);
        mtrip_free(&t);
    }
}

int main(void)
{
    TEST_INIT("test_ldlt");
    buf = (unsigned char *)malloc(BUF_BYTES);
    TEST_RUN(ldlt_random_spd_vs_dense);
    TEST_RUN(ldlt_mesh_laplacians_vs_dense);
    TEST_RUN(ldlt_backward_error_table);
    TEST_RUN(ldlt_no_subnormals_and_refactor);
    TEST_RUN(ldlt_multi_rhs_and_digest);
    TEST_RUN(ldlt_errors);
    TEST_RUN(ldlt_arena_sweeps);
    TEST_RUN(ldlt_auto_ordering);
    TEST_RUN(ldlt_split_same_bits);
    TEST_RUN(ldlt_split_chain_and_star);
    free(buf);
    return TEST_END();
}
