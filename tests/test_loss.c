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
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
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
    CHECK_STATUS(ls_loss_views(kind, W, H, V, pi, pr, pg, &loss, NULL), LS_OK);
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
        CHECK_STATUS(ls_loss_views(kind, W, H, V, pi, pr, pg, &a, NULL), LS_OK);
        CHECK_STATUS(ls_loss_begin(&acc, kind, W, H, V), LS_OK);
        CHECK_STATUS(ls_loss_finish(&acc, &c), LS_ERR_STATE);
        for (v = 0; v < V; v++) CHECK_STATUS(ls_loss_view(&acc, img[v], ref[v], grad2[v], NULL), LS_OK);
        CHECK_STATUS(ls_loss_view(&acc, img[0], ref[0], NULL, NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_loss_finish(&acc, &b), LS_OK);
        CHECK(memcmp(&a, &b, sizeof a) == 0);
        CHECK(memcmp(grad, grad2, sizeof grad) == 0);
        CHECK_STATUS(ls_loss_views(kind, W, H, V, pi, pr, NULL, &c, NULL), LS_OK);
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
    CHECK_STATUS(ls_loss_views(LS_LOSS_L1, 2, 2, 1, px, pr, pg, &loss, &diag), LS_ERR_NONFINITE);
    CHECK_EQ(diag.index, 9);
    CHECK_EQ(diag.offset, 0);
    CHECK(strcmp(diag.what, "non-finite target value") == 0);
    for (i = 0; i < 16; i++) CHECK(g[i] == (ls_real)-7);
    r[9] = 0;
    CHECK_STATUS(ls_loss_views(LS_LOSS_L1, 2, 2, 1, px, pr, pg, &loss, &diag), LS_OK);
    CHECK_NEAR(loss, 120.0 / 16.0, 0.0);
    CHECK(g[0] == 0);
    CHECK(g[1] == (ls_real)1 / (ls_real)16);
}

int main(void)
{
    TEST_INIT("test_loss");
    TEST_RUN(loss_l1_matches_reference_and_fd);
    TEST_RUN(loss_l2_matches_reference_and_fd);
    TEST_RUN(loss_fixed_order);
    TEST_RUN(loss_compensated);
    TEST_RUN(loss_errors);
    return TEST_END();
}
