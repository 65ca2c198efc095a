/* sh_estimate.c - SH lighting estimated from images: the least-squares
 * normal equations of a rasterized view against its target, and their
 * solution (see largesteps/shade.h). */
#include <largesteps/shade.h>
#include "render_internal.h"
#include <largesteps/math.h>
#include <string.h>

#define R_INV_PI ((ls_real)0.31830988618379067154)

void ls_sh_basis(const ls_real n[3], ls_real b[9])
{
    const ls_real c1 = (ls_real)LS_SH_C1, c2 = (ls_real)LS_SH_C2, c3 = (ls_real)LS_SH_C3;
    const ls_real c4 = (ls_real)LS_SH_C4, c5 = (ls_real)LS_SH_C5;
    const ls_real x = n[0], y = n[1], z = n[2];
    const ls_real k1 = (ls_real)2 * c1 * R_INV_PI, k2 = (ls_real)2 * c2 * R_INV_PI;
    b[0] = c4 * R_INV_PI;
    b[1] = k2 * y;
    b[2] = k2 * z;
    b[3] = k2 * x;
    b[4] = k1 * (x * y);
    b[5] = k1 * (y * z);
    b[6] = (c3 * (z * z) - c5) * R_INV_PI;
    b[7] = k1 * (x * z);
    b[8] = c1 * (x * x - y * y) * R_INV_PI;
}

void ls_sh_normal_clear(ls_sh_normal *ne)
{
    if (ne == NULL) return;
    memset(ne, 0, sizeof *ne);
}

/* The interpolated normal of sample s (as ls_shade forms it). */
static void sample_normal(const ls_vis *vis, size_t s, const uint32_t *f, const ls_real *normals, int renormalize,
                          ls_real n[3])
{
    const ls_real b0 = vis->bary[2 * s], b1 = vis->bary[2 * s + 1], b2 = (ls_real)1 - b0 - b1;
    const ls_real *n0 = normals + 3 * (size_t)f[0], *n1 = normals + 3 * (size_t)f[1];
    const ls_real *n2 = normals + 3 * (size_t)f[2];
    int k;
    for (k = 0; k < 3; k++) n[k] = b0 * n0[k] + b1 * n1[k] + b2 * n2[k];
    if (renormalize) {
        ls_real l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (l2 > (ls_real)0) {
            ls_real l = LS_RSQRT(l2);
            n[0] /= l;
            n[1] /= l;
            n[2] /= l;
        }
    }
}

/* The pixel's rows: r[9] the mean basis over its S x S samples, and with
 * colours (vertex colours, else NULL) rc[27] the means of colour_c b per
 * channel; 0 when a sample is not covered. */
static int pixel_row(const ls_vis *vis, size_t s0, const uint32_t *indices, uint32_t triangle_count,
                     const ls_real *normals, int renormalize, const ls_real *colors, ls_real r[9], ls_real rc[27])
{
    const uint32_t ss = vis->ss;
    uint32_t i, j, k, c;
    for (k = 0; k < 9; k++) r[k] = (ls_real)0;
    if (colors != NULL)
        for (k = 0; k < 27; k++) rc[k] = (ls_real)0;
    for (j = 0; j < ss; j++)
        for (i = 0; i < ss; i++) {
            const size_t s = s0 + (size_t)j * vis->sw + i;
            const uint32_t id = vis->tri[s];
            const uint32_t *f;
            ls_real n[3], b[9];
            if (id == 0 || id > triangle_count) return 0;
            f = indices + 3 * (size_t)(id - 1u);
            sample_normal(vis, s, f, normals, renormalize, n);
            ls_sh_basis(n, b);
            for (k = 0; k < 9; k++) r[k] += b[k];
            if (colors != NULL) {
                const ls_real b0 = vis->bary[2 * s], b1 = vis->bary[2 * s + 1], b2 = (ls_real)1 - b0 - b1;
                for (c = 0; c < 3; c++) {
                    const ls_real a = b0 * colors[3 * (size_t)f[0] + c] + b1 * colors[3 * (size_t)f[1] + c] +
                                      b2 * colors[3 * (size_t)f[2] + c];
                    for (k = 0; k < 9; k++) rc[9 * c + k] += a * b[k];
                }
            }
        }
    if (ss > 1) {
        const ls_real inv_n = (ls_real)1 / (ls_real)(ss * ss);
        for (k = 0; k < 9; k++) r[k] *= inv_n;
        if (colors != NULL)
            for (k = 0; k < 27; k++) rc[k] *= inv_n;
    }
    return 1;
}

/* The checks shared by the two accumulations (nothing is added on error). */
static ls_status check_view(const ls_view *view, const ls_real *target, ls_diag *diag)
{
    const ls_vis *vis;
    if (view == NULL || target == NULL) return ls_invalid_arg(diag, "view or target is NULL");
    vis = view->vis;
    if (vis == NULL) return ls_invalid_arg(diag, "view->vis is NULL");
    if (vis->tri == NULL) return LS_ERR_STATE;
    if (view->normals == NULL) return ls_invalid_arg(diag, "view->normals is NULL; the estimate needs vertex normals");
    if (vis->triangle_count != view->triangle_count)
        return ls_invalid_arg(diag, "view->triangle_count: allowed = view->vis->triangle_count");
    if (vis->vertex_count != view->vertex_count)
        return ls_invalid_arg(diag, "view->vertex_count: allowed = view->vis->vertex_count");
    if (view->triangle_count > 0 && view->indices == NULL)
        return ls_invalid_arg(diag, "view->indices is NULL with triangle_count > 0");
    return ls_check_triangle_indices(view->indices, view->triangle_count, view->vertex_count, diag);
}

ls_status ls_sh_accumulate(ls_sh_normal *ne, const ls_view *view, const ls_real *target, ls_diag *diag)
{
    const ls_vis *vis;
    const ls_real *colors;
    uint32_t x, y;
    int renormalize;
    ls_status st;
    ls_diag_clear(diag);
    if (ne == NULL) return ls_invalid_arg(diag, "ne is NULL");
    st = check_view(view, target, diag);
    if (st != LS_OK) return st;
    vis = view->vis;
    renormalize = view->opts != NULL && view->opts->renormalize != 0;
    colors = view->opts != NULL ? view->opts->vertex_colors : NULL;
    if (ne->pixels > 0 && (ne->per_channel != 0) != (colors != NULL))
        return ls_invalid_arg(diag, "view->opts->vertex_colors: the sums hold views with and without vertex colours; "
                                    "clear them (ls_sh_normal_clear) between the two");
    if (colors != NULL) ne->per_channel = 1;
    for (y = 0; y < vis->height; y++) {
        size_t s0 = (size_t)y * vis->ss * vis->sw, p = (size_t)y * vis->width;
        for (x = 0; x < vis->width; x++, s0 += vis->ss, p++) {
            const ls_real *t = target + 4 * p;
            ls_real r[9], rc[27];
            uint32_t i, j, a = 0;
            if (!(t[3] >= (ls_real)LS_SH_TARGET_ALPHA)) continue;
            if (!pixel_row(vis, s0, view->indices, view->triangle_count, view->normals, renormalize, colors, r, rc))
                continue;
            if (colors == NULL) {
                for (i = 0; i < 9; i++)
                    for (j = i; j < 9; j++) ne->ata[a++] += r[i] * r[j];
                for (i = 0; i < 3; i++)
                    for (j = 0; j < 9; j++) ne->atb[9 * i + j] += r[j] * t[i];
            } else {
                uint32_t c;
                for (c = 0; c < 3; c++) {
                    const ls_real *q = rc + 9 * (size_t)c;
                    ls_real *m = ne->ata_rgb + 45 * (size_t)c;
                    a = 0;
                    for (i = 0; i < 9; i++)
                        for (j = i; j < 9; j++) m[a++] += q[i] * q[j];
                    for (j = 0; j < 9; j++) ne->atb[9 * c + j] += q[j] * t[c];
                }
            }
            ne->pixels++;
        }
    }
    return LS_OK;
}

ls_status ls_albedo_accumulate(const ls_view *view, const ls_real *target, ls_real *num, ls_real *den, ls_diag *diag)
{
    const ls_vis *vis;
    uint32_t x, y;
    int renormalize;
    ls_status st;
    ls_diag_clear(diag);
    if (num == NULL || den == NULL) return ls_invalid_arg(diag, "num or den is NULL");
    if (view != NULL && (view->opts == NULL || view->opts->sh == NULL))
        return ls_invalid_arg(diag, "view->opts->sh is NULL; the albedo is estimated under known SH lighting");
    st = check_view(view, target, diag);
    if (st != LS_OK) return st;
    vis = view->vis;
    renormalize = view->opts->renormalize != 0;
    for (y = 0; y < vis->height; y++) {
        size_t s0 = (size_t)y * vis->ss * vis->sw, p = (size_t)y * vis->width;
        for (x = 0; x < vis->width; x++, s0 += vis->ss, p++) {
            const ls_real *t = target + 4 * p;
            uint32_t i, j, k, c, covered = 1;
            if (!(t[3] >= (ls_real)LS_SH_TARGET_ALPHA)) continue;
            for (j = 0; j < vis->ss && covered; j++)
                for (i = 0; i < vis->ss; i++) {
                    const uint32_t id = vis->tri[s0 + (size_t)j * vis->sw + i];
                    if (id == 0 || id > view->triangle_count) covered = 0;
                }
            if (!covered) continue;
            for (j = 0; j < vis->ss; j++)
                for (i = 0; i < vis->ss; i++) {
                    const size_t s = s0 + (size_t)j * vis->sw + i;
                    const uint32_t *f = view->indices + 3 * (size_t)(vis->tri[s] - 1u);
                    const ls_real b0 = vis->bary[2 * s], b1 = vis->bary[2 * s + 1];
                    const ls_real bw[3] = {b0, b1, (ls_real)1 - b0 - b1};
                    ls_real n[3], e[3];
                    sample_normal(vis, s, f, view->normals, renormalize, n);
                    ls_shade_sh_eval(view->opts->sh, n, e);
                    for (k = 0; k < 3; k++)
                        for (c = 0; c < 3; c++) {
                            num[3 * (size_t)f[k] + c] += bw[k] * e[c] * t[c];
                            den[3 * (size_t)f[k] + c] += bw[k] * e[c] * e[c];
                        }
                }
        }
    }
    return LS_OK;
}

ls_status ls_albedo_solve(const ls_real *num, const ls_real *den, uint32_t vertex_count, ls_real *albedo,
                          ls_diag *diag)
{
    ls_real sn[3] = {0, 0, 0}, sd[3] = {0, 0, 0};
    uint32_t v, c;
    ls_diag_clear(diag);
    if (num == NULL || den == NULL || albedo == NULL) return ls_invalid_arg(diag, "num, den or albedo is NULL");
    for (v = 0; v < vertex_count; v++)
        for (c = 0; c < 3; c++)
            if (den[3 * (size_t)v + c] > (ls_real)0) {
                sn[c] += num[3 * (size_t)v + c];
                sd[c] += den[3 * (size_t)v + c];
            }
    if (!(sd[0] > (ls_real)0 || sd[1] > (ls_real)0 || sd[2] > (ls_real)0)) {
        (void)ls_diag_set(diag, LS_ERR_STATE, "albedo estimate: no sample is covered by both the render and the "
                                              "target's mask", LS_DIAG_NO_INDEX);
        return LS_ERR_STATE;
    }
    for (c = 0; c < 3; c++) { /* the pooled ratio: the albedo's mean stays 1 */
        const ls_real mean = sd[c] > (ls_real)0 ? sn[c] / sd[c] : (ls_real)0;
        for (v = 0; v < vertex_count; v++) {
            const size_t i = 3 * (size_t)v + c;
            ls_real a;
            if (!(den[i] > (ls_real)0) || !(mean > (ls_real)0)) continue;
            a = num[i] / den[i] / mean;
            albedo[i] = a > (ls_real)0 ? a : (ls_real)0;
        }
    }
    return LS_OK;
}

/* The index of (i, j), j < i, in the packed strict lower triangle. */
static uint32_t lower(uint32_t i, uint32_t j)
{
    return i * (i - 1u) / 2u + j;
}

/* The index of (i, j), i <= j, in the packed upper triangle. */
static uint32_t packed(uint32_t i, uint32_t j)
{
    return i * 9u - i * (i + 1u) / 2u + j;
}

/* ata (packed) + r I = L D L^T, r the ridge; 0 when not positive definite
 * (*bad: the failing row). */
static int factor9(const ls_real *ata, ls_real l[36], ls_real d[9], uint32_t *bad)
{
    ls_real ridge = (ls_real)0;
    uint32_t i, j, k;
    for (i = 0; i < 9; i++) ridge += ata[packed(i, i)];
    ridge = ridge * ((ls_real)LS_SH_RIDGE / (ls_real)9);
    /* L unit lower triangular, its strict part packed by rows */
    for (j = 0; j < 9; j++) {
        ls_real dj = ata[packed(j, j)] + ridge;
        for (k = 0; k < j; k++) dj -= l[lower(j, k)] * l[lower(j, k)] * d[k];
        if (!(dj > (ls_real)0.5 * ridge) || dj - dj != dj - dj) {
            *bad = j;
            return 0;
        }
        d[j] = dj;
        for (i = j + 1; i < 9; i++) {
            ls_real a = ata[packed(j, i)];
            for (k = 0; k < j; k++) a -= l[lower(i, k)] * l[lower(j, k)] * d[k];
            l[lower(i, j)] = a / dj;
        }
    }
    return 1;
}

ls_status ls_sh_solve(const ls_sh_normal *ne, ls_real sh[27], ls_diag *diag)
{
    ls_real l[36], d[9], out[27];
    uint32_t i, k, c, bad = 0;
    ls_diag_clear(diag);
    if (ne == NULL || sh == NULL) return ls_invalid_arg(diag, "ne or sh is NULL");
    if (ne->pixels == 0) {
        (void)ls_diag_set(diag, LS_ERR_STATE,
                          "lighting estimate: no pixel is covered by both the render and the target's mask",
                          LS_DIAG_NO_INDEX);
        return LS_ERR_STATE;
    }
    for (c = 0; c < 3; c++) {
        ls_real *x = out + 9 * (size_t)c;
        /* one matrix for the three channels, or each its own (vertex colours) */
        if ((c == 0 || ne->per_channel) && !factor9(ne->per_channel ? ne->ata_rgb + 45 * (size_t)c : ne->ata, l, d, &bad)) {
            (void)ls_diag_set(diag, LS_ERR_NOT_SPD,
                              "lighting estimate: the pixels' normals do not determine the 9 coefficients "
                              "(too few pixels, or non-finite sums)", bad);
            return LS_ERR_NOT_SPD;
        }
        for (i = 0; i < 9; i++) { /* L y = b */
            ls_real s = ne->atb[9 * c + i];
            for (k = 0; k < i; k++) s -= l[lower(i, k)] * x[k];
            x[i] = s;
        }
        for (i = 0; i < 9; i++) x[i] /= d[i];
        for (i = 9; i-- > 0;) { /* L^T x = y / d */
            ls_real s = x[i];
            for (k = i + 1; k < 9; k++) s -= l[lower(k, i)] * x[k];
            x[i] = s;
        }
    }
    for (k = 0; k < 27; k++)
        if (out[k] - out[k] != out[k] - out[k]) {
            (void)ls_diag_set(diag, LS_ERR_NONFINITE, "lighting estimate: a coefficient is not finite", k);
            return LS_ERR_NONFINITE;
        }
    memcpy(sh, out, sizeof out);
    return LS_OK;
}
