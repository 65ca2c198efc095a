/* tests/test_loss.c - L1 / L2 image losses against a float64 reference and
 * central finite differences of it. */
#include "test.h"
#include <stdlib.h>

#define W 7
#define H 5
#define V 3
#define NV (4 * W * H)

static uint64_t rng_state = 88172645463325252ull;
static double rnd(void) /* uniform in [0, 1) */
{
    return test_rng_unit(&rng_state);
}

static ls_real img[V][NV], ref[V][NV], grad[V][NV], grad2[V][NV];

/* The reference: the plain mean over the whole V x H x W x 4 tensor, in double. */
static double ref_loss(unsigned kind, const double *x, const double *r, size_t n)
{
    double s = 0.0;
    size_t i;
    for (i = 0; i < n; i++) {
        double d = x[i] - r[i];
        s += kind == LS_LOSS_L1 ? fabs(d) : d * d;
    }
    return s / (double)n;
}

static void fill(int with_ties)
{
    int v, i;
    for (v = 0; v < V; v++)
        for (i = 0; i < NV; i++) {
            ref[v][i] = (ls_real)rnd();
            img[v][i] = (ls_real)rnd();
            if (with_ties && i % 7 == 0) img[v][i] = ref[v][i]; /* sign(0) = 0 */
        }
}

static void check_kind(unsigned kind)
{
    static double x[V * NV], r[V * NV];
    const ls_real *pi[V], *pr[V];
    ls_real *pg[V];
    ls_real loss = 0;
    double want, h, maxrel = 0.0;
    int v, i, n_checked = 0;
    fill(1);
    for (v = 0; v < V; v++) {
        pi[v] = img[v];
        pr[v] = ref[v];
        pg[v] = grad[v];
        for (i = 0; i < NV; i++) {
            x[v * NV + i] = (double)img[v][i];
            r[v * NV + i] = (double)ref[v][i];
        }
    }
    CHECK_STATUS(ls_loss_views(&(ls_loss_shape){kind, W, H, V}, pi, pr, pg, &loss, NULL), LS_OK);
    want = ref_loss(kind, x, r, (size_t)V * NV);
    CHECK_NEAR(loss, want, TEST_EPS(8) * want);
    /* Central differences of the reference, per component. */
    for (v = 0; v < V; v++)
        for (i = 0; i < NV; i++) {
            double d = x[v * NV + i] - r[v * NV + i], fd, save = x[v * NV + i], g = (double)grad[v][i], err;
            if (d == 0.0) {
                CHECK_MSG(g == 0.0, "sign(0) must give 0 (view %d value %d: %g)", v, i, g);
                continue;
            }
            h = fabs(d) < 1e-3 ? fabs(d) * 0.25 : 1e-4; /* stay on one side of the kink */
            x[v * NV + i] = save + h;
            fd = ref_loss(kind, x, r, (size_t)V * NV);
            x[v * NV + i] = save - h;
            fd -= ref_loss(kind, x, r, (size_t)V * NV);
            x[v * NV + i] = save;
            fd /= 2.0 * h;
            err = fabs(fd - g) / (fabs(fd) + 1e-12);
            if (err > maxrel) maxrel = err;
            n_checked++;
        }
    printf("     %s: %d components, max relative error vs FD %.3g (abs floor 1e-12)\n",
           kind == LS_LOSS_L1 ? "L1" : "L2", n_checked, maxrel);
    CHECK(n_checked > V * NV / 2);
    CHECK_MSG(maxrel <= 1e-6 || (sizeof(ls_real) == 4 && maxrel <= 1e-5), "max relative FD error %g", maxrel);
}

static void loss_l1_matches_reference_and_fd(void) { check_kind(LS_LOSS_L1); }
static void loss_l2_matches_reference_and_fd(void) { check_kind(LS_LOSS_L2); }

/* View-by-view and all-at-once give the same bits, run after run. */
static void loss_fixed_order(void)
{
    const ls_real *pi[V], *pr[V];
    ls_real *pg[V];
    ls_real a = 0, b = 0, c = 0;
    ls_loss_acc acc;
    int v;
    unsigned kind;
    fill(0);
    for (kind = 0; kind < 2; kind++) {
        for (v = 0; v < V; v++) {
            pi[v] = img[v];
            pr[v] = ref[v];
            pg[v] = grad[v];
        }
        CHECK_STATUS(ls_loss_views(&(ls_loss_shape){kind, W, H, V}, pi, pr, pg, &a, NULL), LS_OK);
        CHECK_STATUS(ls_loss_begin(&acc, kind, W, H, V), LS_OK);
        CHECK_STATUS(ls_loss_finish(&acc, &c), LS_ERR_STATE);
        for (v = 0; v < V; v++) CHECK_STATUS(ls_loss_view(&acc, img[v], ref[v], grad2[v], NULL), LS_OK);
        CHECK_STATUS(ls_loss_view(&acc, img[0], ref[0], NULL, NULL), LS_ERR_INVALID);
        {
            ls_diag dg;
            CHECK_STATUS(ls_loss_view(&acc, img[0], ref[0], NULL, &dg), LS_ERR_INVALID);
            CHECK(strstr(dg.what, "acc->view_count") != NULL);
            CHECK_STATUS(ls_loss_view(&acc, NULL, ref[0], NULL, &dg), LS_ERR_INVALID);
            CHECK(strcmp(dg.what, "rendered is NULL") == 0);
            CHECK_STATUS(ls_loss_views(&(ls_loss_shape){kind, W, H, 0}, pi, pr, pg, &a, &dg), LS_ERR_INVALID);
            CHECK(strstr(dg.what, "shape->view_count") != NULL);
            CHECK_STATUS(ls_loss_views(&(ls_loss_shape){7u, W, H, V}, pi, pr, pg, &a, &dg), LS_ERR_INVALID);
            CHECK(strstr(dg.what, "shape->kind") != NULL);
        }
        CHECK_STATUS(ls_loss_finish(&acc, &b), LS_OK);
        CHECK(memcmp(&a, &b, sizeof a) == 0);
        CHECK(memcmp(grad, grad2, sizeof grad) == 0);
        CHECK_STATUS(ls_loss_views(&(ls_loss_shape){kind, W, H, V}, pi, pr, NULL, &c, NULL), LS_OK);
        CHECK(memcmp(&a, &c, sizeof a) == 0);
    }
}

/* Compensated sums: a view of many equal small terms plus one large one sums
 * exactly where a plain ls_real sum would drift. */
static void loss_compensated(void)
{
    static ls_real x[4 * 64 * 64], r[4 * 64 * 64];
    ls_real loss = 0;
    ls_loss_acc acc;
    size_t i;
    for (i = 0; i < 4 * 64 * 64; i++) {
        r[i] = 0;
        x[i] = (ls_real)0.1;
    }
    x[0] = (ls_real)1e6;
    CHECK_STATUS(ls_loss_begin(&acc, LS_LOSS_L1, 64, 64, 1), LS_OK);
    CHECK_STATUS(ls_loss_view(&acc, x, r, NULL, NULL), LS_OK);
    CHECK_STATUS(ls_loss_finish(&acc, &loss), LS_OK);
    /* exact: (1e6 + 16383 * 0.1) / 16384, up to the rounding of 0.1 itself */
    CHECK_NEAR(loss, (1e6 + 16383.0 * (double)(ls_real)0.1) / 16384.0, TEST_EPS(4) * 62.0);
}

static void loss_errors(void)
{
    ls_loss_acc acc;
    ls_diag diag;
    ls_real x[4 * 2 * 2], r[4 * 2 * 2], g[4 * 2 * 2], loss = 0;
    const ls_real *px[1], *pr[1];
    ls_real *pg[1];
    volatile ls_real zero = 0;
    int i;
    for (i = 0; i < 16; i++) {
        x[i] = (ls_real)i;
        r[i] = 0;
        g[i] = (ls_real)-7;
    }
    CHECK_STATUS(ls_loss_begin(NULL, LS_LOSS_L1, 2, 2, 1), LS_ERR_INVALID);
    CHECK_STATUS(ls_loss_begin(&acc, 2u, 2, 2, 1), LS_ERR_INVALID);
    CHECK_STATUS(ls_loss_begin(&acc, LS_LOSS_L1, 0, 2, 1), LS_ERR_INVALID);
    CHECK_STATUS(ls_loss_begin(&acc, LS_LOSS_L1, 2, 2, 0), LS_ERR_INVALID);
    CHECK_STATUS(ls_loss_begin(&acc, LS_LOSS_L2, 2, 2, 1), LS_OK);
    x[5] = zero / zero;
    CHECK_STATUS(ls_loss_view(&acc, x, r, g, &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.index, 5);
    CHECK(strcmp(diag.what, "non-finite rendered value") == 0);
    CHECK_EQ(acc.views_done, 0);
    for (i = 0; i < 16; i++) CHECK(g[i] == (ls_real)-7);
    x[5] = 5;
    r[9] = (ls_real)1 / zero;
    px[0] = x;
    pr[0] = r;
    pg[0] = g;
    CHECK_STATUS(ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, 2, 2, 1}, px, pr, pg, &loss, &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.index, 9);
    CHECK_EQ(diag.offset, 0);
    CHECK(strcmp(diag.what, "non-finite target value") == 0);
    for (i = 0; i < 16; i++) CHECK(g[i] == (ls_real)-7);
    r[9] = 0;
    CHECK_STATUS(ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, 2, 2, 1}, px, pr, pg, &loss, &diag), LS_OK);
    CHECK_NEAR(loss, 120.0 / 16.0, 0.0);
    CHECK(g[0] == 0);
    CHECK(g[1] == (ls_real)1 / (ls_real)16);
}

/* ---- Accuracy of the blocked sums (loss.h: relative error <= 20 u) ---- */

#define AW 150 /* 150 x 100: 1875 blocks per view, rows not block-aligned */
#define AH 100
#define AV 3
#define AN (4 * AW * AH)
static ls_real big_r[AV][AN], big_t[AV][AN];

/* The exact sum a + b as hi + lo (Knuth's TwoSum). */
static void two_sum(double a, double b, double *hi, double *lo)
{
    double s = a + b, bb = s - a;
    *hi = s;
    *lo = (a - (s - bb)) + (b - bb);
}

/* The exact product a * a as hi + lo (Dekker, no FMA). */
static void two_square(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a, ah = c - (c - a), al = a - ah;
    *hi = a * a;
    *lo = ((ah * ah - *hi) + 2.0 * ah * al) + al * al;
}

/* The reference loss: every term exact as a double-double, summed in
 * double-double (relative error of order 2^-100 before the last rounding),
 * then one rounding to double and one division: within 2^-52 relative. */
static double ref_loss_dd(unsigned kind, uint32_t w, uint32_t h, uint32_t nv, const ls_real *r, const ls_real *t,
                          size_t stride)
{
    double sh = 0.0, sl = 0.0;
    size_t n = (size_t)4 * w * h, i;
    uint32_t v;
    for (v = 0; v < nv; v++)
        for (i = 0; i < n; i++) {
            double dh, dl, p[3], e;
            int k;
            two_sum((double)r[v * stride + i], -(double)t[v * stride + i], &dh, &dl);
            if (kind == LS_LOSS_L1) {
                if (dh < 0.0) {
                    dh = -dh;
                    dl = -dl;
                }
                p[0] = dh;
                p[1] = dl;
                p[2] = 0.0;
            } else {
                two_square(dh, &p[0], &p[1]);
                p[2] = 2.0 * dh * dl + dl * dl;
            }
            for (k = 0; k < 3; k++) {
                two_sum(sh, p[k], &sh, &e);
                sl += e;
            }
        }
    return (sh + sl) / ((double)n * (double)nv);
}

typedef enum { FILL_UNIT, FILL_WIDE, FILL_EQUAL, FILL_SPIKES } fill_kind;

static double wide_value(void) /* +-[0.5, 1) 2^e, e in [-30, 30] (float: [-20, 20]) */
{
    int e = (int)(rnd() * (sizeof(ls_real) == 4 ? 41.0 : 61.0)) - (sizeof(ls_real) == 4 ? 20 : 30);
    double m = 0.5 + 0.5 * rnd();
    return ldexp(rnd() < 0.5 ? -m : m, e);
}

static void fill_big(fill_kind how)
{
    int v, i;
    for (v = 0; v < AV; v++)
        for (i = 0; i < AN; i++) {
            switch (how) {
            case FILL_UNIT:
                big_r[v][i] = (ls_real)rnd();
                big_t[v][i] = (ls_real)rnd();
                break;
            case FILL_WIDE:
                big_r[v][i] = (ls_real)wide_value();
                big_t[v][i] = (ls_real)wide_value();
                break;
            case FILL_EQUAL: /* the same term everywhere: plain sums drift the most */
                big_r[v][i] = (ls_real)0.1;
                big_t[v][i] = 0;
                break;
            case FILL_SPIKES: /* a large value among small ones in every block */
                big_r[v][i] = (ls_real)(i % 29 == 0 ? 1e4 * (1.0 + rnd()) : 1e-3 * rnd());
                big_t[v][i] = (ls_real)(1e-3 * rnd());
                break;
            }
        }
}

/* Relative error of the library's loss against ref_loss_dd in units of
 * u = LS_REAL_EPSILON / 2, for a w x h x nv set taken from big_r / big_t. */
static double loss_error_u(unsigned kind, uint32_t w, uint32_t h, uint32_t nv)
{
    const ls_real *pr[AV] = {NULL}, *pt[AV] = {NULL}; /* all set below; gcc -O1 cannot tell */
    ls_real loss = 0;
    double want;
    uint32_t v;
    for (v = 0; v < nv; v++) {
        pr[v] = big_r[v];
        pt[v] = big_t[v];
    }
    if (ls_loss_views(&(ls_loss_shape){kind, w, h, nv}, pr, pt, NULL, &loss, NULL) != LS_OK) return 1e30;
    want = ref_loss_dd(kind, w, h, nv, big_r[0], big_t[0], AN);
    return fabs((double)loss - want) / (want * 0.5 * (double)LS_REAL_EPSILON);
}

static void loss_accuracy_bound(void)
{
    static const char *names[] = {"[0,1]", "wide", "equal", "spikes"};
    /* loss.h: 20 u; the reference's own rounding (2^-52
     * relative, 2 u in the double build) is granted on top */
    const double bound_u = 20.0, ref_u = ldexp(1.0, -52) / (0.5 * (double)LS_REAL_EPSILON);
    int how;
    unsigned kind;
    for (how = FILL_UNIT; how <= FILL_SPIKES; how++) {
        fill_big((fill_kind)how);
        for (kind = 0; kind < 2; kind++) {
            /* 150 x 100 x 3 views; 37 x 29 (a 1-pixel last block); 1 x 1 */
            double e0 = loss_error_u(kind, AW, AH, AV), e1 = loss_error_u(kind, 37, 29, 1);
            double e2 = loss_error_u(kind, 1, 1, 1);
            printf("     %s %-6s: relative error %.2f u (150x100x3), %.2f u (37x29), %.2f u (1x1); bound %.0f u\n",
                   kind == LS_LOSS_L1 ? "L1" : "L2", names[how], e0, e1, e2, bound_u);
            CHECK_MSG(e0 <= bound_u + ref_u && e1 <= bound_u + ref_u && e2 <= bound_u + ref_u, "%s %s: %g %g %g u",
                      kind == LS_LOSS_L1 ? "L1" : "L2", names[how], e0, e1, e2);
        }
    }
}

/* ---- The gradient: the same bits as the per-value formulas ---- */

#if LS_REAL_IS_FLOAT
#define TL_REAL_MIN FLT_MIN
#else
#define TL_REAL_MIN DBL_MIN
#endif

static void loss_gradient_bits(void)
{
    static ls_real x[4 * 5 * 3], r[4 * 5 * 3], g1[4 * 5 * 3], g2[4 * 5 * 3];
    const ls_real tiny = TL_REAL_MIN * LS_REAL_EPSILON; /* the smallest subnormal */
    const ls_real special[][2] = {
        {0, 0}, {-0.0, 0}, {0, -0.0}, {-0.0, -0.0}, {tiny, 0}, {0, tiny}, {-tiny, 0}, {tiny, tiny}, {2 * tiny, tiny},
        {TL_REAL_MIN, 0}, {1, 1}, {1, (ls_real)0.5}, {(ls_real)0.5, 1}, {LS_REAL_MAX, LS_REAL_MAX},
        {LS_REAL_MAX, -LS_REAL_MAX}, {-LS_REAL_MAX, LS_REAL_MAX}, {LS_REAL_MAX, 0}, {1, 1 + LS_REAL_EPSILON},
    };
    const uint32_t nspecial = (uint32_t)(sizeof special / sizeof special[0]);
    ls_loss_acc acc;
    uint32_t i, views;
    unsigned kind;
    for (views = 1; views <= 7; views += 3)
        for (kind = 0; kind < 2; kind++) {
            ls_real n = (ls_real)4 * (ls_real)views * (ls_real)5 * (ls_real)3, inv = (ls_real)1 / n;
            for (i = 0; i < 60; i++) {
                if (i < nspecial) {
                    x[i] = special[i][0];
                    r[i] = special[i][1];
                } else {
                    x[i] = (ls_real)wide_value();
                    r[i] = i % 5 == 0 ? x[i] : (ls_real)wide_value();
                }
            }
            CHECK_STATUS(ls_loss_begin(&acc, kind, 5, 3, views), LS_OK);
            CHECK_STATUS(ls_loss_view(&acc, x, r, g1, NULL), LS_OK);
            for (i = 0; i < 60; i++) {
                ls_real d = x[i] - r[i];
                g2[i] = kind == LS_LOSS_L1 ? inv * (ls_real)((d > 0) - (d < 0)) : d == 0 ? d : (d + d) / n;
            }
            for (i = 0; i < 60; i++)
                CHECK_MSG(memcmp(&g1[i], &g2[i], sizeof g1[i]) == 0, "%s views %u value %u (%g - %g): %a, want %a",
                          kind == LS_LOSS_L1 ? "L1" : "L2", (unsigned)views, (unsigned)i, (double)x[i], (double)r[i],
                          (double)g1[i], (double)g2[i]);
        }
}

/* ---- Errors: the first bad value, nothing written; overflow ---- */

static void loss_nonfinite_first_and_untouched(void)
{
    static ls_real x[3][4 * 40 * 10], r[3][4 * 40 * 10], g[3][4 * 40 * 10];
    const ls_real *px[3], *pr[3];
    ls_real *pg[3], loss = 0;
    volatile ls_real zero = 0;
    const ls_real inf = (ls_real)1 / zero, nan = zero / zero;
    ls_loss_acc acc, before;
    ls_diag diag;
    uint64_t hg;
    int v, i;
    for (v = 0; v < 3; v++) {
        for (i = 0; i < 4 * 40 * 10; i++) {
            x[v][i] = (ls_real)rnd();
            r[v][i] = (ls_real)rnd();
            g[v][i] = (ls_real)-7;
        }
        px[v] = x[v];
        pr[v] = r[v];
        pg[v] = g[v];
    }
    hg = test_hash(g, sizeof g, 1);
    /* a view whose earlier views were added: acc must not move */
    CHECK_STATUS(ls_loss_begin(&acc, LS_LOSS_L1, 40, 10, 3), LS_OK);
    CHECK_STATUS(ls_loss_view(&acc, x[0], r[0], NULL, NULL), LS_OK);
    before = acc;
    /* target +inf at 300 comes before rendered NaN at 700 (later block) */
    x[1][700] = nan;
    r[1][300] = inf;
    CHECK_STATUS(ls_loss_view(&acc, x[1], r[1], g[1], &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.index, 300);
    CHECK(diag.value == inf);
    CHECK(strcmp(diag.what, "non-finite target value") == 0);
    CHECK(memcmp(&acc, &before, sizeof acc) == 0);
    CHECK(test_hash(g, sizeof g, 1) == hg);
    /* +inf - +inf: both infinite at the same index; the rendered one is named */
    r[1][300] = (ls_real)0.5;
    x[1][700] = (ls_real)0.5;
    x[1][1599] = inf;
    r[1][1599] = inf;
    CHECK_STATUS(ls_loss_view(&acc, x[1], r[1], g[1], &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.index, 1599);
    CHECK(strcmp(diag.what, "non-finite rendered value") == 0);
    /* -inf rendered against a finite target, L2 */
    x[1][1599] = -inf;
    r[1][1599] = 0;
    CHECK_STATUS(ls_loss_begin(&acc, LS_LOSS_L2, 40, 10, 3), LS_OK);
    CHECK_STATUS(ls_loss_view(&acc, x[1], r[1], g[1], &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.index, 1599);
    CHECK(diag.value == -inf);
    CHECK_EQ(acc.views_done, 0);
    CHECK(test_hash(g, sizeof g, 1) == hg);
    /* all views at once: a NaN in the last view writes no gradient anywhere */
    x[1][1599] = 0;
    x[2][4] = nan;
    CHECK_STATUS(ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, 40, 10, 3}, px, pr, pg, &loss, &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.offset, 2);
    CHECK_EQ(diag.index, 4);
    CHECK(test_hash(g, sizeof g, 1) == hg);
    x[2][4] = 0;
    CHECK_STATUS(ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, 40, 10, 3}, px, pr, pg, &loss, &diag), LS_OK);
    CHECK(test_hash(g, sizeof g, 1) != hg);
}

/* Finite inputs whose loss exceeds the range: LS_OK, loss +inf (not NaN,
 * also after more views), the gradient as for any finite input. */
static void loss_overflow_is_inf(void)
{
    static ls_real x[4 * 8 * 8], r[4 * 8 * 8], g[4 * 8 * 8];
    const ls_real big = LS_REAL_MAX * (ls_real)0.75;
    ls_real loss = 0, inv = (ls_real)1 / (ls_real)(4 * 8 * 8 * 2);
    ls_loss_acc acc;
    unsigned kind;
    int i;
    for (kind = 0; kind < 2; kind++) {
        /* one difference that overflows (L1: MAX - -MAX), then every term large */
        for (i = 0; i < 4 * 8 * 8; i++) {
            x[i] = (ls_real)0.25;
            r[i] = 0;
        }
        x[9] = LS_REAL_MAX;
        r[9] = -LS_REAL_MAX;
        CHECK_STATUS(ls_loss_begin(&acc, kind, 8, 8, 2), LS_OK);
        CHECK_STATUS(ls_loss_view(&acc, x, r, g, NULL), LS_OK);
        if (kind == LS_LOSS_L1) {
            CHECK(g[9] == inv);
            CHECK(g[10] == inv);
        }
        for (i = 0; i < 4 * 8 * 8; i++) x[i] = big;
        CHECK_STATUS(ls_loss_view(&acc, x, r, g, NULL), LS_OK);
        CHECK_STATUS(ls_loss_finish(&acc, &loss), LS_OK);
        CHECK_MSG(loss > LS_REAL_MAX, "%s: loss %g, want +inf", kind == LS_LOSS_L1 ? "L1" : "L2", (double)loss);
        /* the sum alone overflows, in a single view */
        CHECK_STATUS(ls_loss_begin(&acc, kind, 8, 8, 1), LS_OK);
        CHECK_STATUS(ls_loss_view(&acc, x, r, g, NULL), LS_OK);
        CHECK_STATUS(ls_loss_finish(&acc, &loss), LS_OK);
        CHECK(loss > LS_REAL_MAX);
    }
}

int main(void)
{
    TEST_INIT("test_loss");
    TEST_RUN(loss_l1_matches_reference_and_fd);
    TEST_RUN(loss_l2_matches_reference_and_fd);
    TEST_RUN(loss_fixed_order);
    TEST_RUN(loss_compensated);
    TEST_RUN(loss_errors);
    TEST_RUN(loss_accuracy_bound);
    TEST_RUN(loss_gradient_bits);
    TEST_RUN(loss_nonfinite_first_and_untouched);
    TEST_RUN(loss_overflow_is_inf);
    return TEST_END();
}
