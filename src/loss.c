/* loss.c - L1 / L2 image losses over RGBA views (largesteps/loss.h). */
#include <largesteps/loss.h>

/* Neumaier's compensated addition of x to (*s, *c); fixed order, no FMA.
 * Every sum here adds non-negative values (|d|, d^2 and sums of those), so
 * the larger magnitude is the larger value: max and min, no branch. */
static void comp_add(ls_real *s, ls_real *c, ls_real x)
{
    ls_real t = *s + x;
    ls_real hi = x > *s ? x : *s; /* maxsd and minsd, where SSE2 has them */
    ls_real lo = x < *s ? x : *s;
    *c += (hi - t) + lo;
    *s = t;
}

/* 1 when every value of a[0..n) and b[0..n) is finite (n a multiple of 4):
 * x - x is +0 for a finite x and NaN otherwise, and a NaN stays in a sum;
 * four independent sums, no early exit. */
static int all_finite(const ls_real *a, const ls_real *b, size_t n)
{
    ls_real z0 = (ls_real)0, z1 = (ls_real)0, z2 = (ls_real)0, z3 = (ls_real)0;
    size_t i;
    for (i = 0; i < n; i += 4) {
        z0 += (a[i] - a[i]) + (b[i] - b[i]);
        z1 += (a[i + 1] - a[i + 1]) + (b[i + 1] - b[i + 1]);
        z2 += (a[i + 2] - a[i + 2]) + (b[i + 2] - b[i + 2]);
        z3 += (a[i + 3] - a[i + 3]) + (b[i + 3] - b[i + 3]);
    }
    return ((z0 + z1) + (z2 + z3)) == (ls_real)0;
}

/* One channel's value of the L1 loss: |d| into its sum, sign(d) / N into g. */
static void l1_value(ls_real r, ls_real t, ls_real inv, ls_real *s, ls_real *c, ls_real *g)
{
    ls_real d = r - t;
    int sg = (d > (ls_real)0) - (d < (ls_real)0);
    comp_add(s, c, d * (ls_real)sg); /* |d| */
    *g = inv * (ls_real)sg;          /* +-inv or +0 */
}

/* The same for L2: d^2, and 2 d / N ((d + d) / n is d when d is 0). */
static void l2_value(ls_real r, ls_real t, ls_real n, ls_real *s, ls_real *c, ls_real *g)
{
    ls_real d = r - t;
    comp_add(s, c, d * d);
    *g = d == (ls_real)0 ? d : (d + d) / n;
}

static int finite_real(ls_real x)
{
    return x - x == (ls_real)0; /* false for NaN and +-inf */
}

static ls_real norm_count(const ls_loss_acc *acc)
{
    return (ls_real)4 * (ls_real)acc->view_count * (ls_real)acc->width * (ls_real)acc->height;
}

ls_status ls_loss_begin(ls_loss_acc *acc, uint32_t kind, uint32_t width, uint32_t height,
                        uint32_t view_count)
{
    if (acc == NULL || (kind != LS_LOSS_L1 && kind != LS_LOSS_L2) || width == 0 || height == 0 ||
        view_count == 0)
        return LS_ERR_INVALID;
    acc->kind = kind;
    acc->width = width;
    acc->height = height;
    acc->view_count = view_count;
    acc->views_done = 0;
    acc->sum = (ls_real)0;
    acc->comp = (ls_real)0;
    return LS_OK;
}

ls_status ls_loss_view(ls_loss_acc *acc, const ls_real *rendered, const ls_real *target, ls_real *grad,
                       ls_diag *diag)
{
    size_t i, count;
    ls_real s0, s1, s2, s3, c0, c1, c2, c3, n, dummy[4] = {0, 0, 0, 0};
    if (acc == NULL || rendered == NULL || target == NULL || acc->views_done >= acc->view_count ||
        (acc->kind != LS_LOSS_L1 && acc->kind != LS_LOSS_L2))
        return LS_ERR_INVALID;
    count = (size_t)4 * (size_t)acc->width * (size_t)acc->height;
    /* Check first, so that nothing is written on failure; on failure, the first bad value. */
    for (i = all_finite(rendered, target, count) ? count : 0; i < count; i++) {
        if (!finite_real(rendered[i]) || !finite_real(target[i])) {
            if (diag != NULL) {
                ls_diag_clear(diag);
                diag->status = LS_ERR_NONFINITE;
                diag->has_index = 1;
                diag->index = i;
                diag->has_value = 1;
                diag->value = finite_real(rendered[i]) ? target[i] : rendered[i];
                diag->what = finite_real(rendered[i]) ? "non-finite target value" : "non-finite rendered value";
            }
            return LS_ERR_NONFINITE;
        }
    }
    n = norm_count(acc);
    /* One compensated sum per RGBA channel (four independent chains, not one
     * long dependent one), combined in channel order. Adding +0 leaves a sum
     * as it is (neither part is ever -0 where it matters), so zero
     * differences need no branch, nor does the sign of d. Without grad, the
     * gradients go to a dummy (no branch in the loop). */
    s0 = s1 = s2 = s3 = c0 = c1 = c2 = c3 = (ls_real)0;
    if (acc->kind == LS_LOSS_L1) {
        ls_real inv = (ls_real)1 / n;
        for (i = 0; i < count; i += 4) {
            ls_real *g = grad != NULL ? grad + i : dummy;
            l1_value(rendered[i], target[i], inv, &s0, &c0, &g[0]);
            l1_value(rendered[i + 1], target[i + 1], inv, &s1, &c1, &g[1]);
            l1_value(rendered[i + 2], target[i + 2], inv, &s2, &c2, &g[2]);
            l1_value(rendered[i + 3], target[i + 3], inv, &s3, &c3, &g[3]);
        }
    } else {
        for (i = 0; i < count; i += 4) {
            ls_real *g = grad != NULL ? grad + i : dummy;
            l2_value(rendered[i], target[i], n, &s0, &c0, &g[0]);
            l2_value(rendered[i + 1], target[i + 1], n, &s1, &c1, &g[1]);
            l2_value(rendered[i + 2], target[i + 2], n, &s2, &c2, &g[2]);
            l2_value(rendered[i + 3], target[i + 3], n, &s3, &c3, &g[3]);
        }
    }
    comp_add(&s0, &c0, s1);
    comp_add(&s0, &c0, s2);
    comp_add(&s0, &c0, s3);
    c0 += (c1 + c2) + c3;
    comp_add(&acc->sum, &acc->comp, s0 + c0);
    acc->views_done++;
    return LS_OK;
}

ls_status ls_loss_finish(const ls_loss_acc *acc, ls_real *loss)
{
    if (acc == NULL || loss == NULL) return LS_ERR_INVALID;
    if (acc->views_done != acc->view_count) return LS_ERR_STATE;
    *loss = (acc->sum + acc->comp) / norm_count(acc);
    return LS_OK;
}

ls_status ls_loss_views(uint32_t kind, uint32_t width, uint32_t height, uint32_t view_count,
                        const ls_real *const *rendered, const ls_real *const *target,
                        ls_real *const *grad, ls_real *loss, ls_diag *diag)
{
    ls_loss_acc acc;
    uint32_t v;
    ls_status st;
    if (rendered == NULL || target == NULL || loss == NULL) return LS_ERR_INVALID;
    st = ls_loss_begin(&acc, kind, width, height, view_count);
    if (st != LS_OK) return st;
    /* Check every view before writing any gradient. */
    for (v = 0; v < view_count; v++) {
        if (rendered[v] == NULL || target[v] == NULL) return LS_ERR_INVALID;
    }
    for (v = 0; v < view_count; v++) {
        ls_loss_acc probe = acc;
        probe.views_done = 0;
        st = ls_loss_view(&probe, rendered[v], target[v], NULL, diag);
        if (st != LS_OK) {
            if (diag != NULL) {
                diag->has_offset = 1;
                diag->offset = v;
            }
            return st;
        }
    }
    for (v = 0; v < view_count; v++) {
        st = ls_loss_view(&acc, rendered[v], target[v], grad != NULL ? grad[v] : NULL, NULL);
        if (st != LS_OK) return st;
    }
    return ls_loss_finish(&acc, loss);
}
