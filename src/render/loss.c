/* loss.c - L1 / L2 image losses over RGBA views (largesteps/loss.h). */
#include <largesteps/loss.h>
#include "../base/diag_internal.h"

/* Pixels per block of the sum: four plain lane sums of at most this many
 * terms each, so that their rounding error (at most (LOSS_BLOCK + 1) u
 * relative, see loss.h) does not grow with the image; the blocks go into a
 * compensated sum. 8 keeps the bound at 20 u for about 1 instruction per
 * value of per-block work (the alternatives measured: docs/fast-paths.md). */
#define LOSS_BLOCK 8u

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

static int finite_real(ls_real x)
{
    return x - x == (ls_real)0; /* false for NaN and +-inf */
}

/* |d| as max(d, -d): one maxsd (vmax.f32) and no libm; a NaN stays a NaN
 * (d > -d is false, -NaN is returned), which is what makes the sum the
 * finiteness check. */
static ls_real abs_real(ls_real d)
{
    ls_real m = -d;
    return d > m ? d : m;
}

/* The plain sums of a block of `pixels` pixels: |r - t| (L1) or (r - t)^2
 * (L2) per RGBA channel (four independent chains, which SSE2 and NEON run
 * as two or one vector: the same operations in the same order per lane),
 * combined as (R + G) + (B + A). */
static ls_real block_sum(uint32_t kind, const ls_real *r, const ls_real *t, size_t pixels)
{
    ls_real a0 = (ls_real)0, a1 = (ls_real)0, a2 = (ls_real)0, a3 = (ls_real)0;
    size_t p;
    if (kind == LS_LOSS_L1) {
        for (p = 0; p < pixels; p++, r += 4, t += 4) {
            a0 += abs_real(r[0] - t[0]);
            a1 += abs_real(r[1] - t[1]);
            a2 += abs_real(r[2] - t[2]);
            a3 += abs_real(r[3] - t[3]);
        }
    } else {
        for (p = 0; p < pixels; p++, r += 4, t += 4) {
            ls_real d0 = r[0] - t[0], d1 = r[1] - t[1], d2 = r[2] - t[2], d3 = r[3] - t[3];
            a0 += d0 * d0;
            a1 += d1 * d1;
            a2 += d2 * d2;
            a3 += d3 * d3;
        }
    }
    return (a0 + a1) + (a2 + a3);
}

/* The view's sum over `pixels` pixels: the block sums of LOSS_BLOCK pixels
 * (the last one shorter) in memory order in a compensated sum. NaN when an
 * input is NaN, +-inf or NaN when an input is infinite; +inf or NaN also
 * when finite inputs overflow. Reads only. */
static ls_real view_sum(uint32_t kind, const ls_real *r, const ls_real *t, size_t pixels)
{
    ls_real s = (ls_real)0, c = (ls_real)0;
    size_t p, m;
    for (p = 0; p < pixels; p += m) {
        m = pixels - p < LOSS_BLOCK ? pixels - p : LOSS_BLOCK;
        comp_add(&s, &c, block_sum(kind, r + 4 * p, t + 4 * p, m));
    }
    return s + c;
}

/* Powers of two that scale the smallest subnormal |d| to at least 1:
 * 2^1074 for double, 2^149 for float, as two factors that are in range. */
#if LS_REAL_IS_FLOAT
#define LOSS_SCALE 37778931862957161709568.0f /* 2^75 */
#else
#define LOSS_SCALE 4.4989137945431964e+161 /* 2^537 */
#endif

/* The L1 gradient sign(d) / N of four values at a time, bit for bit as
 * +inv, -inv or +0, with multiplies and max/min only (no compare into an
 * integer, no branch, so that the compilers vectorize it).
 * (d * S) * (S * inv), S = LOSS_SCALE, is at least inv in magnitude for
 * every non-zero d (power-of-two scalings are exact until they overflow, and
 * rounding is monotonic) and is +-0 for d = +-0; the clamp to [-inv, inv]
 * leaves +-inv or +-0, and + 0 turns -0 into +0, as sign(0) = 0 gives. */
static ls_real l1_grad(ls_real r, ls_real t, ls_real k, ls_real inv, ls_real ninv)
{
    ls_real x = ((r - t) * LOSS_SCALE) * k;
    x = x < inv ? x : inv;
    x = x > ninv ? x : ninv;
    return x + (ls_real)0;
}

/* The gradients, after the sum has shown every input finite: L1 as above,
 * L2 2 d / N as (d + d) / n (+-0 for d = +-0, as before). Four values a
 * step, so that the compilers' vectorizers need no remainder loop. */
static void view_grad(uint32_t kind, const ls_real *r, const ls_real *t, ls_real n, ls_real *g, size_t count)
{
    size_t i;
    if (kind == LS_LOSS_L1) {
        const ls_real inv = (ls_real)1 / n, ninv = -inv, k = LOSS_SCALE * inv;
        for (i = 0; i < count; i += 4) {
            /* all four before any store: g may alias nothing, but the
             * compilers cannot know that without restrict */
            ls_real g0 = l1_grad(r[i], t[i], k, inv, ninv), g1 = l1_grad(r[i + 1], t[i + 1], k, inv, ninv);
            ls_real g2 = l1_grad(r[i + 2], t[i + 2], k, inv, ninv), g3 = l1_grad(r[i + 3], t[i + 3], k, inv, ninv);
            g[i] = g0;
            g[i + 1] = g1;
            g[i + 2] = g2;
            g[i + 3] = g3;
        }
    } else {
        for (i = 0; i < count; i += 4) {
            ls_real d0 = r[i] - t[i], d1 = r[i + 1] - t[i + 1], d2 = r[i + 2] - t[i + 2], d3 = r[i + 3] - t[i + 3];
            g[i] = (d0 + d0) / n;
            g[i + 1] = (d1 + d1) / n;
            g[i + 2] = (d2 + d2) / n;
            g[i + 3] = (d3 + d3) / n;
        }
    }
}

/* The first non-finite value of either input (count when there is none:
 * then a non-finite sum is an overflow of finite inputs). */
static size_t first_nonfinite(const ls_real *r, const ls_real *t, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        if (!finite_real(r[i]) || !finite_real(t[i])) break;
    return i;
}

static ls_real norm_count(const ls_loss_acc *acc)
{
    return (ls_real)4 * (ls_real)acc->view_count * (ls_real)acc->width * (ls_real)acc->height;
}

static size_t value_count(const ls_loss_acc *acc)
{
    return (size_t)4 * (size_t)acc->width * (size_t)acc->height;
}

/* One view's sum into *sum, or LS_ERR_NONFINITE with diag as loss.h says.
 * Writes nothing else. Finite inputs whose sum overflows give +inf. */
static ls_status checked_sum(const ls_loss_acc *acc, const ls_real *r, const ls_real *t, ls_real *sum,
                             ls_diag *diag)
{
    size_t count = value_count(acc);
    ls_real s = view_sum(acc->kind, r, t, count / 4);
    if (!finite_real(s)) {
        /* rare: the exact scan finds the first bad value */
        size_t i = first_nonfinite(r, t, count);
        if (i < count) {
            if (diag != NULL) {
                ls_diag_clear(diag);
                diag->status = LS_ERR_NONFINITE;
                diag->has_index = 1;
                diag->index = i;
                diag->has_value = 1;
                diag->value = finite_real(r[i]) ? t[i] : r[i];
                diag->what = finite_real(r[i]) ? "non-finite target value" : "non-finite rendered value";
            }
            return LS_ERR_NONFINITE;
        }
        s = LS_REAL_MAX * (ls_real)2; /* +inf: finite inputs, a sum beyond the range */
    }
    *sum = s;
    return LS_OK;
}

/* Adds a view's sum to the running total; an infinite total stays +inf
 * (its compensation, inf - inf, would be NaN). */
static void add_view(ls_loss_acc *acc, ls_real s)
{
    comp_add(&acc->sum, &acc->comp, s);
    if (!finite_real(acc->sum)) acc->comp = (ls_real)0;
    acc->views_done++;
}

static int acc_ok(const ls_loss_acc *acc)
{
    return acc->views_done < acc->view_count && (acc->kind == LS_LOSS_L1 || acc->kind == LS_LOSS_L2);
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
    ls_diag_clear(diag);
    ls_real s = (ls_real)0;
    ls_status st;
    if (acc == NULL) return ls_invalid_arg(diag, "acc is NULL");
    if (rendered == NULL) return ls_invalid_arg(diag, "rendered is NULL");
    if (target == NULL) return ls_invalid_arg(diag, "target is NULL");
    if (!acc_ok(acc)) return ls_invalid_arg(diag, "acc: not begun, or all acc->view_count views already added");
    /* the sum first (it reads only): nothing is written on failure */
    st = checked_sum(acc, rendered, target, &s, diag);
    if (st != LS_OK) return st;
    if (grad != NULL) view_grad(acc->kind, rendered, target, norm_count(acc), grad, value_count(acc));
    add_view(acc, s);
    return LS_OK;
}

ls_status ls_loss_merge(ls_loss_acc *acc, const ls_loss_acc *part)
{
    if (acc == NULL || part == NULL || !acc_ok(acc) || part->views_done != 1u || part->kind != acc->kind ||
        part->width != acc->width || part->height != acc->height || part->view_count != acc->view_count)
        return LS_ERR_INVALID;
    add_view(acc, part->sum); /* one view from zero: its sum exactly, no compensation */
    return LS_OK;
}

ls_status ls_loss_finish(const ls_loss_acc *acc, ls_real *loss)
{
    if (acc == NULL || loss == NULL) return LS_ERR_INVALID;
    if (acc->views_done != acc->view_count) return LS_ERR_STATE;
    *loss = (acc->sum + acc->comp) / norm_count(acc);
    return LS_OK;
}

ls_status ls_loss_views(const ls_loss_shape *shape, const ls_real *const *rendered, const ls_real *const *target,
                        ls_real *const *grad, ls_real *loss, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_loss_acc acc;
    uint32_t v, view_count;
    ls_status st;
    if (shape == NULL) return ls_invalid_arg(diag, "shape is NULL");
    if (rendered == NULL) return ls_invalid_arg(diag, "rendered is NULL");
    if (target == NULL) return ls_invalid_arg(diag, "target is NULL");
    if (loss == NULL) return ls_invalid_arg(diag, "loss is NULL");
    view_count = shape->view_count;
    st = ls_loss_begin(&acc, shape->kind, shape->width, shape->height, view_count);
    if (st == LS_ERR_INVALID) {
        int kind_ok = shape->kind == LS_LOSS_L1 || shape->kind == LS_LOSS_L2;
        return ls_invalid_arg(diag, !kind_ok          ? "shape->kind: allowed LS_LOSS_L1 or LS_LOSS_L2"
                                    : view_count == 0 ? "shape->view_count: 0; at least one view"
                                                      : "shape->width, shape->height: allowed >= 1");
    }
    if (st != LS_OK) return st;
    /* Check every view before writing any gradient. */
    for (v = 0; v < view_count; v++) {
        if (rendered[v] == NULL || target[v] == NULL) {
            (void)ls_invalid_arg(diag, "rendered[v] or target[v] is NULL (v: diag->offset)");
            if (diag != NULL) {
                diag->has_offset = 1;
                diag->offset = v;
            }
            return LS_ERR_INVALID;
        }
    }
    /* The sums (the same bits as view by view), then the gradients. */
    for (v = 0; v < view_count; v++) {
        ls_real s = (ls_real)0;
        st = checked_sum(&acc, rendered[v], target[v], &s, diag);
        if (st != LS_OK) {
            if (diag != NULL) {
                diag->has_offset = 1;
                diag->offset = v;
            }
            return st;
        }
        add_view(&acc, s);
    }
    if (grad != NULL)
        for (v = 0; v < view_count; v++)
            if (grad[v] != NULL) view_grad(shape->kind, rendered[v], target[v], norm_count(&acc), grad[v], value_count(&acc));
    return ls_loss_finish(&acc, loss);
}
