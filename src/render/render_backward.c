/* render_backward.c - backward of the interior shading (largesteps/render_backward.h). */
#include <largesteps/render_backward.h>
#include "render_internal.h"
#include <math.h>

#if LS_REAL_IS_FLOAT
#define R_SQRT sqrtf
#else
#define R_SQRT sqrt
#endif

#define R_INV_PI ((ls_real)0.31830988618379067154)
#define MAX_SS 4 /* samples per pixel side: ls_vis_init takes 1, 2 or 4 */

/* Inlined into the fast path's sample loop (LS_FAST_PATHS); one copy where
 * code size counts. Inlining changes no bits. */
#if (defined(__GNUC__) || defined(__clang__)) && LS_FAST_PATHS
#define BWD_INLINE __attribute__((always_inline)) inline
#else
#define BWD_INLINE inline
#endif

/* Everything one sample's backward needs (render_internal.h). */
typedef ls_shade_bctx bctx;

/* The SH gradient's constants, formed once per call: per channel c the
 * symmetric 3 x 3 matrix of dE_c/dn = 2 (M_c n_h)_xyz (its five distinct
 * entries xx = c1 L8, xy = c1 L4, xz = c1 L7, yz = c1 L5, zz = c3 L6; yy is
 * -xx) and its constant part (c2 L3, c2 L1, c2 L2), each times 2 / pi, stored
 * entry-major: k[3 j + c] is entry j of channel c. */
static void sh_grad_consts(const ls_real *sh, ls_real k[24])
{
    const ls_real c1 = (ls_real)LS_SH_C1, c2 = (ls_real)LS_SH_C2, c3 = (ls_real)LS_SH_C3;
    const ls_real s = (ls_real)2 * R_INV_PI;
    int c;
    for (c = 0; c < 3; c++) {
        const ls_real *L = sh + 9 * (size_t)c;
        k[c] = s * (c1 * L[8]);
        k[3 + c] = s * (c1 * L[4]);
        k[6 + c] = s * (c1 * L[7]);
        k[9 + c] = s * (c1 * L[5]);
        k[12 + c] = s * (c3 * L[6]);
        k[15 + c] = s * (c2 * L[3]);
        k[18 + c] = s * (c2 * L[1]);
        k[21 + c] = s * (c2 * L[2]);
    }
}

/* dL/dn of the SH irradiance, sum_c g_c dE_c/dn / pi (k: sh_grad_consts):
 * the channels' matrices are summed with the weights g first, then one
 * matrix-vector product. */
static BWD_INLINE void sh_grad(const ls_real *k, const ls_real n[3], const ls_real g[3], ls_real dn[3])
{
    const ls_real g0 = g[0], g1 = g[1], g2 = g[2], x = n[0], y = n[1], z = n[2];
    const ls_real xx = (g0 * k[0] + g1 * k[1]) + g2 * k[2], xy = (g0 * k[3] + g1 * k[4]) + g2 * k[5];
    const ls_real xz = (g0 * k[6] + g1 * k[7]) + g2 * k[8], yz = (g0 * k[9] + g1 * k[10]) + g2 * k[11];
    const ls_real zz = (g0 * k[12] + g1 * k[13]) + g2 * k[14];
    const ls_real hx = (g0 * k[15] + g1 * k[16]) + g2 * k[17], hy = (g0 * k[18] + g1 * k[19]) + g2 * k[20];
    const ls_real hz = (g0 * k[21] + g1 * k[22]) + g2 * k[23];
    dn[0] = ((xx * x + xy * y) + xz * z) + hx;
    dn[1] = ((xy * x - xx * y) + yz * z) + hy;
    dn[2] = ((xz * x + yz * y) + zz * z) + hz;
}

#if LS_FAST_PATHS
/* shading_backward for plain SH shading (bc->sh_plain: unit albedo, no
 * renormalization): the same arithmetic without the general path's
 * per-sample branches and copies (g x 1 is g). */
static BWD_INLINE void sh_plain_backward(const bctx *bc, const uint32_t *f, const ls_real b[3], const ls_real g[3],
                              ls_real gb[3])
{
    const ls_real *N0 = bc->normals + 3 * (size_t)f[0], *N1 = bc->normals + 3 * (size_t)f[1];
    const ls_real *N2 = bc->normals + 3 * (size_t)f[2];
    ls_real n[3], dn[3];
    n[0] = b[0] * N0[0] + b[1] * N1[0] + b[2] * N2[0];
    n[1] = b[0] * N0[1] + b[1] * N1[1] + b[2] * N2[1];
    n[2] = b[0] * N0[2] + b[1] * N1[2] + b[2] * N2[2];
    sh_grad(bc->shk, n, g, dn);
    gb[0] = N0[0] * dn[0] + N0[1] * dn[1] + N0[2] * dn[2];
    gb[1] = N1[0] * dn[0] + N1[1] * dn[1] + N1[2] * dn[2];
    gb[2] = N2[0] * dn[0] + N2[1] * dn[1] + N2[2] * dn[2];
    if (bc->gn != NULL) {
        ls_real *d0 = bc->gn + 3 * (size_t)f[0], *d1 = bc->gn + 3 * (size_t)f[1], *d2 = bc->gn + 3 * (size_t)f[2];
        ls_real b0 = b[0], b1 = b[1], b2 = b[2], e0 = dn[0], e1 = dn[1], e2 = dn[2];
        d0[0] += b0 * e0;
        d0[1] += b0 * e1;
        d0[2] += b0 * e2;
        d1[0] += b1 * e0;
        d1[1] += b1 * e1;
        d1[2] += b1 * e2;
        d2[0] += b2 * e0;
        d2[1] += b2 * e1;
        d2[2] += b2 * e2;
    }
}

#endif

/* dL/db of one covered sample of triangle f with barycentrics b, given
 * g = dL/d(sample rgb); adds to the normal and colour gradients. */
static void shading_backward(const bctx *bc, const uint32_t *f, const ls_real b[3], const ls_real g[3],
                             ls_real gb[3])
{
    const ls_shade_opts *o = bc->o;
    ls_real alb[3], dalb[3], ds[3], s[3], vc[3], tx[3], uv[2];
    int c, k;
#if LS_FAST_PATHS
    if (bc->sh_plain) {
        sh_plain_backward(bc, f, b, g, gb);
        return;
    }
#endif
    gb[0] = gb[1] = gb[2] = (ls_real)0;
    if (o->mode == LS_SHADE_MASK) return;
    for (c = 0; c < 3; c++) alb[c] = vc[c] = (ls_real)1;
    if (o->vertex_colors != NULL)
        for (c = 0; c < 3; c++)
            alb[c] = vc[c] = b[0] * o->vertex_colors[3 * (size_t)f[0] + (size_t)c] +
                             b[1] * o->vertex_colors[3 * (size_t)f[1] + (size_t)c] +
                             b[2] * o->vertex_colors[3 * (size_t)f[2] + (size_t)c];
    if (o->texture != NULL) { /* albedo = vertex colour x texture, as ls_shade_point */
        ls_shade_uv(o->uvs, f, b, uv);
        ls_texture_sample(o->texture, uv[0], uv[1], tx);
        for (c = 0; c < 3; c++) alb[c] *= tx[c];
    }
    if (o->mode == LS_SHADE_COLOR) {
        for (c = 0; c < 3; c++) dalb[c] = g[c];
    } else {
        ls_real n[3], nn[3], dnn[3], l = (ls_real)0;
        const ls_real *N[3];
        int renorm = 0;
        for (k = 0; k < 3; k++) N[k] = bc->normals + 3 * (size_t)f[k];
        for (c = 0; c < 3; c++) n[c] = b[0] * N[0][c] + b[1] * N[1][c] + b[2] * N[2][c];
        nn[0] = n[0];
        nn[1] = n[1];
        nn[2] = n[2];
        if (o->renormalize) {
            ls_real l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if (l2 > (ls_real)0) {
                l = R_SQRT(l2);
                for (c = 0; c < 3; c++) nn[c] = n[c] / l;
                renorm = 1;
            }
        }
        if (o->mode == LS_SHADE_SH) {
            /* the irradiance s only scales the albedo's gradient */
            if (o->vertex_colors != NULL || o->texture != NULL)
                ls_shade_sh_eval(o->sh, nn, s);
            else
                s[0] = s[1] = s[2] = (ls_real)0;
            for (c = 0; c < 3; c++) ds[c] = g[c] * alb[c];
            sh_grad(bc->shk, nn, ds, dnn);
        } else { /* Lambert */
            uint32_t li;
            for (c = 0; c < 3; c++) {
                s[c] = o->ambient[c];
                ds[c] = g[c] * alb[c];
            }
            dnn[0] = dnn[1] = dnn[2] = (ls_real)0;
            for (li = 0; li < o->light_count; li++) {
                const ls_light *lt = &o->lights[li];
                ls_real d = nn[0] * lt->dir[0] + nn[1] * lt->dir[1] + nn[2] * lt->dir[2];
                if (d > (ls_real)0) {
                    ls_real w = ds[0] * lt->rgb[0] + ds[1] * lt->rgb[1] + ds[2] * lt->rgb[2];
                    for (c = 0; c < 3; c++) {
                        s[c] += d * lt->rgb[c];
                        dnn[c] += w * lt->dir[c];
                    }
                }
            }
        }
        for (c = 0; c < 3; c++) dalb[c] = g[c] * s[c];
        if (renorm) {
            ls_real d = nn[0] * dnn[0] + nn[1] * dnn[1] + nn[2] * dnn[2];
            for (c = 0; c < 3; c++) dnn[c] = (dnn[c] - nn[c] * d) / l;
        }
        for (k = 0; k < 3; k++) {
            gb[k] = N[k][0] * dnn[0] + N[k][1] * dnn[1] + N[k][2] * dnn[2];
            if (bc->gn != NULL)
                for (c = 0; c < 3; c++) bc->gn[3 * (size_t)f[k] + (size_t)c] += b[k] * dnn[c];
        }
    }
    if (o->texture != NULL) {
        ls_real dt[3], duv[2];
        for (c = 0; c < 3; c++) dt[c] = dalb[c] * vc[c]; /* dL/d(texture colour) */
        ls_texture_sample_backward(o->texture, uv[0], uv[1], dt, bc->gt, duv);
        for (k = 0; k < 3; k++) {
            const ls_real *a = o->uvs + 2 * (size_t)f[k];
            gb[k] += a[0] * duv[0] + a[1] * duv[1];
            if (bc->guv != NULL) {
                bc->guv[2 * (size_t)f[k]] += b[k] * duv[0];
                bc->guv[2 * (size_t)f[k] + 1] += b[k] * duv[1];
            }
        }
        for (c = 0; c < 3; c++) dalb[c] *= tx[c]; /* dL/d(vertex colour) */
    }
    if (o->vertex_colors != NULL) {
        for (k = 0; k < 3; k++) {
            const ls_real *col = o->vertex_colors + 3 * (size_t)f[k];
            gb[k] += col[0] * dalb[0] + col[1] * dalb[1] + col[2] * dalb[2];
            if (bc->gc != NULL)
                for (c = 0; c < 3; c++) bc->gc[3 * (size_t)f[k] + (size_t)c] += b[k] * dalb[c];
        }
    }
}

/* The barycentrics b of the NDC point (px, py) in triangle f: those of
 * ls_clip_barycentric (u_k = x_k - px w_k, v_k = y_k - py w_k, a = u x v,
 * b = a / sum a) through one reciprocal *inv of the sum, which also scales
 * dL/da. 0 when the triangle is edge-on there or the sum or its reciprocal
 * is not finite (no gradient), else 1. */
static BWD_INLINE int sample_bary(const ls_real *clip, const uint32_t *f, ls_real px, ls_real py, ls_real u[3],
                                  ls_real v[3], ls_real b[3], ls_real *inv)
{
    ls_real sum, r;
    ls_clip_areas(clip, f, px, py, u, v, b);
    sum = (b[0] + b[1]) + b[2];
    if (!(sum != (ls_real)0) || sum - sum != (ls_real)0) return 0;
    r = (ls_real)1 / sum;
    if (r - r != (ls_real)0) return 0; /* a sum too small for its reciprocal */
    b[0] *= r;
    b[1] *= r;
    b[2] *= r;
    *inv = r;
    return 1;
}

/* out = r - t w for the first three entries of the transform's rows r and
 * w: dL/d(clip x, y, w) of a vertex are gu, gv and -(px gu + py gv), which
 * the rows X, Y, W take to gu mx + gv my, mx = X - px W, my = Y - py W. */
static BWD_INLINE void sample_row(const ls_real *r, const ls_real *w, ls_real t, ls_real out[3])
{
    out[0] = r[0] - t * w[0];
    out[1] = r[1] - t * w[1];
    out[2] = r[2] - t * w[2];
}

/* dL/d(vertex positions) of one sample from gb = dL/db (sample_bary's u, v,
 * b, inv; sample_row's mx, my): dL/da = (gb - b . gb) / sum a, then through
 * a = u x v to the clip coordinates. */
static BWD_INLINE void sample_positions(ls_real *gp, const uint32_t *f, const ls_real u[3], const ls_real v[3],
                                        const ls_real b[3], const ls_real gb[3], ls_real inv, const ls_real mx[3],
                                        const ls_real my[3])
{
    const ls_real dot = (b[0] * gb[0] + b[1] * gb[1]) + b[2] * gb[2];
    const ls_real ga0 = (gb[0] - dot) * inv, ga1 = (gb[1] - dot) * inv, ga2 = (gb[2] - dot) * inv;
    /* gu_k = (v x ga)_k, gv_k = (ga x u)_k */
    const ls_real gu0 = v[1] * ga2 - v[2] * ga1, gv0 = ga1 * u[2] - ga2 * u[1];
    const ls_real gu1 = v[2] * ga0 - v[0] * ga2, gv1 = ga2 * u[0] - ga0 * u[2];
    const ls_real gu2 = v[0] * ga1 - v[1] * ga0, gv2 = ga0 * u[1] - ga1 * u[0];
    ls_real *d0 = gp + 3 * (size_t)f[0], *d1 = gp + 3 * (size_t)f[1], *d2 = gp + 3 * (size_t)f[2];
    const ls_real x0 = mx[0], x1 = mx[1], x2 = mx[2], y0 = my[0], y1 = my[1], y2 = my[2];
    d0[0] += x0 * gu0 + y0 * gv0;
    d0[1] += x1 * gu0 + y1 * gv0;
    d0[2] += x2 * gu0 + y2 * gv0;
    d1[0] += x0 * gu1 + y0 * gv1;
    d1[1] += x1 * gu1 + y1 * gv1;
    d1[2] += x2 * gu1 + y2 * gv1;
    d2[0] += x0 * gu2 + y0 * gv2;
    d2[1] += x1 * gu2 + y1 * gv2;
    d2[2] += x2 * gu2 + y2 * gv2;
}

/* One covered sample at NDC (px, py) of triangle f, g = dL/d(sample rgb). */
LS_NO_VECTORIZE static void sample_backward(const bctx *bc, const uint32_t *f, ls_real px, ls_real py, const ls_real g[3])
{
    ls_real u[3], v[3], b[3], gb[3], mx[3], my[3], inv;
    if (!sample_bary(bc->vis->clip, f, px, py, u, v, b, &inv)) return; /* no gradient */
    shading_backward(bc, f, b, g, gb);
    if (bc->gp == NULL) return;
    sample_row(bc->m, bc->m + 12, px, mx);
    sample_row(bc->m + 4, bc->m + 12, py, my);
    sample_positions(bc->gp, f, u, v, b, gb, inv, mx, my);
}

#if LS_FAST_PATHS
/* ls_shade_backward_pixels for plain SH shading (bc->sh_plain) at one
 * sample per pixel, the fit's case: sample_backward's arithmetic inlined
 * into the pixel loop, the row's my once per row. */
LS_NO_VECTORIZE LS_NOINLINE static void pixels_sh_plain(const bctx *bc, uint32_t triangle_count, const ls_real *grad_image,
                                        const uint8_t *skip)
{
    const ls_vis *vis = bc->vis;
    const ls_real *clip = vis->clip, *m = bc->m;
    const ls_real inv_sw = (ls_real)1 / (ls_real)vis->sw;
    ls_real *gp = bc->gp;
    uint32_t x, y;
    for (y = 0; y < vis->height; y++) {
        const uint32_t *row = vis->tri + (size_t)y * vis->sw;
        const ls_real py = (ls_real)1 - (ls_real)(2u * y + 1u) / (ls_real)vis->sh;
        ls_real my[3];
        sample_row(m + 4, m + 12, py, my);
        for (x = 0; x < vis->width; x++) {
            size_t p = (size_t)y * vis->width + x;
            uint32_t id = row[x];
            const uint32_t *f;
            ls_real g[3], px, u[3], v[3], b[3], gb[3], mx[3], inv;
            if (id == 0 || id > triangle_count || (skip != NULL && skip[p])) continue;
            g[0] = grad_image[4 * p];
            g[1] = grad_image[4 * p + 1];
            g[2] = grad_image[4 * p + 2];
            if (g[0] == (ls_real)0 && g[1] == (ls_real)0 && g[2] == (ls_real)0) continue;
            px = (ls_real)(2u * x + 1u) * inv_sw - (ls_real)1;
            f = bc->indices + 3 * (size_t)(id - 1u);
            if (!sample_bary(clip, f, px, py, u, v, b, &inv)) continue;
            sh_plain_backward(bc, f, b, g, gb);
            if (gp == NULL) continue;
            sample_row(m, m + 12, px, mx);
            sample_positions(gp, f, u, v, b, gb, inv, mx, my);
        }
    }
}
#endif

ls_status ls_shade_backward(const ls_view *view, const ls_real *grad_image, ls_real *grad_positions,
                            ls_real *grad_normals, ls_real *grad_colors, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_shade_grads g;
    g.positions = grad_positions;
    g.normals = grad_normals;
    g.colors = grad_colors;
    g.texels = NULL;
    g.uvs = NULL;
    return ls_shade_backward_grads(view, grad_image, &g, diag);
}

ls_status ls_shade_backward_begin(ls_shade_bctx *bc, const ls_vis *vis, const uint32_t *indices,
                                  uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                  const ls_shade_opts *opts, const ls_real mvp[16], const ls_real *grad_image,
                                  const ls_shade_grads *grads, ls_diag *diag)
{
    uint32_t counts[2];
    ls_status st;
    if (vis == NULL) return ls_invalid_arg(diag, "view->vis is NULL");
    if (opts == NULL) return ls_invalid_arg(diag, "view->opts is NULL");
    if (mvp == NULL) return ls_invalid_arg(diag, "view->mvp is NULL");
    if (grad_image == NULL) return ls_invalid_arg(diag, "grad_image is NULL");
    if (grads == NULL) return ls_invalid_arg(diag, "grads is NULL");
    if (vis->tri == NULL || vis->clip == NULL) return LS_ERR_STATE;
    counts[0] = triangle_count;
    counts[1] = vertex_count;
    st = ls_shade_check_args(vis, counts, indices, normals, opts, diag);
    if (st != LS_OK) return st;
    bc->vis = vis;
    bc->indices = indices;
    bc->normals = normals;
    bc->o = opts;
    bc->m = mvp;
    bc->gp = grads->positions;
    bc->gn = opts->mode == LS_SHADE_COLOR ? NULL : grads->normals;
    bc->gc = grads->colors;
    bc->gt = opts->texture != NULL ? grads->texels : NULL;
    bc->guv = opts->texture != NULL ? grads->uvs : NULL;
    bc->sh_plain = LS_FAST_PATHS && opts->mode == LS_SHADE_SH && opts->vertex_colors == NULL &&
                   opts->texture == NULL && !opts->renormalize;
    if (opts->mode == LS_SHADE_SH) sh_grad_consts(opts->sh, bc->shk);
    return LS_OK;
}

void ls_shade_backward_sample(const ls_shade_bctx *bc, const uint32_t *f, ls_real px, ls_real py, const ls_real g[3])
{
    sample_backward(bc, f, px, py, g);
}

void ls_shade_backward_pixels(const ls_shade_bctx *bc, uint32_t triangle_count, const ls_real *grad_image,
                              const uint8_t *skip)
{
    const ls_vis *vis = bc->vis;
    uint32_t x, y, ss = vis->ss;
    ls_real inv_n = (ls_real)1 / (ls_real)(ss * ss);
    const ls_real inv_sw = (ls_real)1 / (ls_real)vis->sw; /* NDC x of column sx: (2 sx + 1) / sw - 1 */
    if (ss > MAX_SS) return; /* not a vis of ls_vis_init */
#if LS_FAST_PATHS
    if (ss == 1 && bc->sh_plain) {
        pixels_sh_plain(bc, triangle_count, grad_image, skip);
        return;
    }
#endif
    for (y = 0; y < vis->height; y++) {
        ls_real pys[MAX_SS]; /* the NDC y of the row's samples, once per row */
        uint32_t j;
        for (j = 0; j < ss; j++) pys[j] = (ls_real)1 - (ls_real)(2u * (y * ss + j) + 1u) / (ls_real)vis->sh;
        for (x = 0; x < vis->width; x++) {
            size_t p = (size_t)y * vis->width + x;
            ls_real g[3];
            uint32_t i;
            if (skip != NULL && skip[p]) continue;
            if (ls_pixel_empty(vis->tri + (size_t)y * ss * vis->sw + (size_t)x * ss, ss, vis->sw, triangle_count))
                continue; /* no sample to take a gradient: cheaper to test before it is read */
            g[0] = grad_image[4 * p] * inv_n;
            g[1] = grad_image[4 * p + 1] * inv_n;
            g[2] = grad_image[4 * p + 2] * inv_n;
            if (g[0] == (ls_real)0 && g[1] == (ls_real)0 && g[2] == (ls_real)0) continue;
            for (j = 0; j < ss; j++) {
                uint32_t sy = y * ss + j;
                ls_real py = pys[j];
                for (i = 0; i < ss; i++) {
                    uint32_t sx = x * ss + i;
                    size_t s = (size_t)sy * vis->sw + sx;
                    uint32_t id = vis->tri[s];
                    ls_real px;
                    if (id == 0 || id > triangle_count) continue;
                    px = (ls_real)(2u * sx + 1u) * inv_sw - (ls_real)1;
                    sample_backward(bc, bc->indices + 3 * (size_t)(id - 1u), px, py, g);
                }
            }
        }
    }
}

static ls_status shade_backward_grads_impl(const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count,
                                           const ls_real *normals, uint32_t vertex_count, const ls_shade_opts *opts,
                                           const ls_real mvp[16], const ls_real *grad_image, const ls_shade_grads *grads,
                                           ls_diag *diag)
{
    ls_diag_clear(diag);
    bctx bc;
    ls_status st = ls_shade_backward_begin(&bc, vis, indices, triangle_count, normals, vertex_count, opts, mvp,
                                           grad_image, grads, diag);
    if (st != LS_OK) return st;
    if (opts->mode == LS_SHADE_MASK) return LS_OK; /* nothing depends on positions inside */
    ls_shade_backward_pixels(&bc, triangle_count, grad_image, NULL);
    return LS_OK;
}

ls_status ls_shade_backward_grads(const ls_view *view, const ls_real *grad_image, const ls_shade_grads *grads,
                                  ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return shade_backward_grads_impl(view->vis, view->indices, view->triangle_count, view->normals, view->vertex_count, view->opts,
                                   view->mvp, grad_image, grads, diag);
}

void ls_vertex_normal_sum_grad(ls_real m[3], const ls_real g[3])
{
    ls_real l2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
    if (l2 > (ls_real)0) {
        ls_real l = R_SQRT(l2), n[3], d;
        int k;
        for (k = 0; k < 3; k++) n[k] = m[k] / l;
        d = n[0] * g[0] + n[1] * g[1] + n[2] * g[2];
        for (k = 0; k < 3; k++) m[k] = (g[k] - n[k] * d) / l;
    } else {
        m[0] = m[1] = m[2] = (ls_real)0;
    }
}

int ls_face_normal_backward(const ls_real *positions, const uint32_t *f, const ls_real *gm, ls_real g[9])
{
    ls_real e1[3], e2[3], c[3], l2 = ls_face_cross(positions, f, e1, e2, c), l, n[3], gn[3], gc[3], d;
    int k;
    if (!(l2 > (ls_real)0) || l2 - l2 != l2 - l2) return 0;
    l = R_SQRT(l2);
    for (k = 0; k < 3; k++) {
        n[k] = c[k] / l;
        gn[k] = (gm[3 * (size_t)f[0] + (size_t)k] + gm[3 * (size_t)f[1] + (size_t)k]) + gm[3 * (size_t)f[2] + (size_t)k];
    }
    d = n[0] * gn[0] + n[1] * gn[1] + n[2] * gn[2];
    for (k = 0; k < 3; k++) gc[k] = (gn[k] - n[k] * d) / l;
    for (k = 0; k < 3; k++) {
        int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        ls_real g1 = e2[k1] * gc[k2] - e2[k2] * gc[k1]; /* (e2 x gc)_k */
        ls_real g2 = gc[k1] * e1[k2] - gc[k2] * e1[k1]; /* (gc x e1)_k */
        g[3 + k] = g1;
        g[6 + k] = g2;
        g[k] = g1 + g2;
    }
    return 1;
}

ls_status ls_vertex_normals_backward_bytes(uint32_t vertex_count, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    ls_size_init(&s);
    ls_size_add(&s, vertex_count, 3 * sizeof(ls_real));
    return ls_size_get(&s, bytes);
}

ls_status ls_vertex_normals_backward(const ls_real *positions, uint32_t vertex_count, const uint32_t *indices,
                                     uint32_t triangle_count, const ls_real *grad_normals,
                                     ls_real *grad_positions, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_real *m;
    uint32_t t, v;
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (vertex_count > 0 && (positions == NULL || grad_normals == NULL || grad_positions == NULL))
        return ls_invalid_arg(diag, "positions, grad_normals or grad_positions is NULL with vertex_count > 0");
    if (triangle_count > 0 && indices == NULL) return ls_invalid_arg(diag, "indices is NULL with triangle_count > 0");
    if (ls_check_triangle_indices(indices, triangle_count, vertex_count, diag) != LS_OK) return LS_ERR_MESH;
    if (vertex_count == 0) return LS_OK;
    mark = ls_arena_save(arena);
    m = (ls_real *)ls_arena_scratch(arena, vertex_count, 3 * sizeof(ls_real));
    if (m == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    ls_vertex_normal_sums(positions, vertex_count, indices, triangle_count, m); /* the forward's sums m_v */
    for (v = 0; v < vertex_count; v++) ls_vertex_normal_sum_grad(m + 3 * (size_t)v, grad_normals + 3 * (size_t)v);
    for (t = 0; t < triangle_count; t++) {
        const uint32_t *f = indices + 3 * (size_t)t;
        ls_real g[9];
        int k;
        if (!ls_face_normal_backward(positions, f, m, g)) continue;
        for (k = 0; k < 3; k++) {
            grad_positions[3 * (size_t)f[1] + (size_t)k] += g[3 + k];
            grad_positions[3 * (size_t)f[2] + (size_t)k] += g[6 + k];
            grad_positions[3 * (size_t)f[0] + (size_t)k] -= g[k];
        }
    }
    ls_arena_restore(arena, mark);
    return LS_OK;
}
