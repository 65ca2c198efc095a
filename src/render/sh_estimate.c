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

/* The pixel's row r[9] (the mean basis over its S x S samples), or 0 when
 * a sample is not covered. */
static int pixel_row(const ls_vis *vis, size_t s0, const uint32_t *indices, uint32_t triangle_count,
                     const ls_real *normals, int renormalize, ls_real r[9])
{
    const uint32_t ss = vis->ss;
    uint32_t i, j, k;
    for (k = 0; k < 9; k++) r[k] = (ls_real)0;
    for (j = 0; j < ss; j++)
        for (i = 0; i < ss; i++) {
            const size_t s = s0 + (size_t)j * vis->sw + i;
            const uint32_t id = vis->tri[s];
            ls_real n[3], b[9];
            if (id == 0 || id > triangle_count) return 0;
            sample_normal(vis, s, indices + 3 * (size_t)(id - 1u), normals, renormalize, n);
            ls_sh_basis(n, b);
            for (k = 0; k < 9; k++) r[k] += b[k];
        }
    if (ss > 1) {
        const ls_real inv_n = (ls_real)1 / (ls_real)(ss * ss);
        for (k = 0; k < 9; k++) r[k] *= inv_n;
    }
    return 1;
}

ls_status ls_sh_accumulate(ls_sh_normal *ne, const ls_view *view, const ls_real *target, ls_diag *diag)
{
    const ls_vis *vis;
    uint32_t x, y;
    int renormalize;
    ls_diag_clear(diag);
    if (ne == NULL || view == NULL || target == NULL) return ls_invalid_arg(diag, "ne, view or target is NULL");
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
    {
        ls_status st = ls_check_triangle_indices(view->indices, view->triangle_count, view->vertex_count, diag);
        if (st != LS_OK) return st;
    }
    renormalize = view->opts != NULL && view->opts->renormalize != 0;
    for (y = 0; y < vis->height; y++) {
        size_t s0 = (size_t)y * vis->ss * vis->sw, p = (size_t)y * vis->width;
        for (x = 0; x < vis->width; x++, s0 += vis->ss, p++) {
            const ls_real *t = target + 4 * p;
            ls_real r[9];
            uint32_t i, j, a = 0;
            if (!(t[3] >= (ls_real)LS_SH_TARGET_ALPHA)) continue;
            if (!pixel_row(vis, s0, view->indices, view->triangle_count, view->normals, renormalize, r)) continue;
            for (i = 0; i < 9; i++)
                for (j = i; j < 9; j++) ne->ata[a++] += r[i] * r[j];
            for (i = 0; i < 3; i++)
                for (j = 0; j < 9; j++) ne->atb[9 * i + j] += r[j] * t[i];
            ne->pixels++;
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

ls_status ls_sh_solve(const ls_sh_normal *ne, ls_real sh[27], ls_diag *diag)
{
    ls_real l[36], d[9], out[27], ridge = (ls_real)0;
    uint32_t i, j, k, c;
    ls_diag_clear(diag);
    if (ne == NULL || sh == NULL) return ls_invalid_arg(diag, "ne or sh is NULL");
    if (ne->pixels == 0) {
        (void)ls_diag_set(diag, LS_ERR_STATE,
                          "lighting estimate: no pixel is covered by both the render and the target's mask",
                          LS_DIAG_NO_INDEX);
        return LS_ERR_STATE;
    }
    for (i = 0; i < 9; i++) ridge += ne->ata[packed(i, i)];
    ridge = ridge * ((ls_real)LS_SH_RIDGE / (ls_real)9);
    /* A + r I = L D L^T, L unit lower triangular (its strict part packed by rows) */
    for (j = 0; j < 9; j++) {
        ls_real dj = ne->ata[packed(j, j)] + ridge;
        for (k = 0; k < j; k++) dj -= l[lower(j, k)] * l[lower(j, k)] * d[k];
        if (!(dj > (ls_real)0.5 * ridge) || dj - dj != dj - dj) {
            (void)ls_diag_set(diag, LS_ERR_NOT_SPD,
                              "lighting estimate: the pixels' normals do not determine the 9 coefficients "
                              "(too few pixels, or non-finite sums)", j);
            return LS_ERR_NOT_SPD;
        }
        d[j] = dj;
        for (i = j + 1; i < 9; i++) {
            ls_real a = ne->ata[packed(j, i)];
            for (k = 0; k < j; k++) a -= l[lower(i, k)] * l[lower(j, k)] * d[k];
            l[lower(i, j)] = a / dj;
        }
    }
    for (c = 0; c < 3; c++) {
        ls_real *x = out + 9 * (size_t)c;
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
