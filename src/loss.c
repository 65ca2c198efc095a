/* loss.c - L1 / L2 image losses over RGBA views (largesteps/loss.h). */
#include <largesteps/loss.h>

/* Neumaier's compensated addition of x to (*s, *c); fixed order, no FMA. */
static void comp_add(ls_real *s, ls_real *c, ls_real x)
{
    ls_real t = *s + x;
    ls_real as = *s < (ls_real)0 ? -*s : *s;
    ls_real ax = x < (ls_real)0 ? -x : x;
    if (as >= ax)
        *c += (*s - t) + x;
    else
        *c += (x - t) + *s;
    *s = t;
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
    ls_real s = (ls_real)0, c = (ls_real)0, n;
    if (acc == NULL || rendered == NULL || target == NULL || acc->views_done >= acc->view_count ||
        (acc->kind != LS_LOSS_L1 && acc->kind != LS_LOSS_L2))
        return LS_ERR_INVALID;
    count = (size_t)4 * (size_t)acc->width * (size_t)acc->height;
    /* Check first, so that nothing is written on failure: a pixel at a time
     * (x - x is +0 for a finite x, NaN otherwise), then the first bad value. */
    for (i = 0; i < count; i += 4) {
        const ls_real *r = rendered + i, *t = target + i;
        ls_real z = ((r[0] - r[0]) + (t[0] - t[0])) + ((r[1] - r[1]) + (t[1] - t[1]));
        z += ((r[2] - r[2]) + (t[2] - t[2])) + ((r[3] - r[3]) + (t[3] - t[3]));
        if (z != (ls_real)0) break;
    }
    for (; i < count; i++) {
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
    /* Adding +0 leaves (s, c) as they are (neither is ever -0): zero
     * differences are skipped, and branches on the sign of d, which would be
     * mispredicted, are avoided. */
    if (acc->kind == LS_LOSS_L1) {
        ls_real inv = (ls_real)1 / n;
        for (i = 0; i < count; i++) {
            ls_real d = rendered[i] - target[i];
            int sg = (d > (ls_real)0) - (d < (ls_real)0);
            if (sg != 0) comp_add(&s, &c, d * (ls_real)sg); /* |d| */
            if (grad != NULL) grad[i] = inv * (ls_real)sg;   /* +-inv or +0 */
        }
    } else {
        for (i = 0; i < count; i++) {
            ls_real d = rendered[i] - target[i], d2 = d * d;
            if (d2 != (ls_real)0) comp_add(&s, &c, d2);
            if (grad != NULL) grad[i] = d == (ls_real)0 ? d : (d + d) / n; /* (d + d) / n is d there */
        }
    }
    comp_add(&acc->sum, &acc->comp, s + c);
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
