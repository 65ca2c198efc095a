/* shade.c - forward shading of a visibility buffer (see largesteps/shade.h). */
#include <largesteps/shade.h>
#include "render_internal.h"
#include <largesteps/math.h>
#include <string.h>
#include <math.h>

#if LS_REAL_IS_FLOAT
#define R_SQRT sqrtf
#define R_SIN ls_sinf
#define R_COS ls_cosf
#define R_ATAN2 ls_atan2f
#else
#define R_SQRT sqrt
#define R_SIN ls_sin
#define R_COS ls_cos
#define R_ATAN2 ls_atan2
#endif

#define R_PI ((ls_real)3.14159265358979323846)
#define R_INV_PI ((ls_real)0.31830988618379067154)

void ls_shade_opts_init(ls_shade_opts *opts)
{
    if (opts == NULL) return;
    memset(opts, 0, sizeof *opts);
    opts->mode = LS_SHADE_MASK;
    opts->sh = NULL;
    opts->lights = NULL;
    opts->vertex_colors = NULL;
    opts->background_image = NULL;
    opts->texture = NULL;
    opts->uvs = NULL;
}

ls_status ls_shade_image_bytes(uint32_t width, uint32_t height, size_t *bytes)
{
    return ls_grid_values_bytes(width, height, 4, bytes);
}

/* n / |n| and 1, or 0 with n as it was when |n|^2 is not positive (zero
 * or NaN). */
static int normalize_nonzero(ls_real n[3])
{
    ls_real l2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    ls_real l;
    if (!(l2 > (ls_real)0)) return 0;
    l = R_SQRT(l2);
    n[0] /= l;
    n[1] /= l;
    n[2] /= l;
    return 1;
}

void ls_shade_uv(const ls_real *uvs, const uint32_t *f, const ls_real b[3], ls_real uv[2])
{
    const ls_real *a0 = uvs + 2 * (size_t)f[0], *a1 = uvs + 2 * (size_t)f[1], *a2 = uvs + 2 * (size_t)f[2];
    uv[0] = b[0] * a0[0] + b[1] * a1[0] + b[2] * a2[0];
    uv[1] = b[0] * a0[1] + b[1] * a1[1] + b[2] * a2[1];
}

void ls_shade_point(const ls_shade_opts *o, const uint32_t *f, const ls_real *normals, const ls_real b[3],
                    ls_real rgb[3])
{
    const ls_real b0 = b[0], b1 = b[1], b2 = b[2];
    ls_real n[3], alb[3];
    int c;
    if (o->mode == LS_SHADE_MASK) {
        rgb[0] = rgb[1] = rgb[2] = (ls_real)1;
        return;
    }
    if (o->vertex_colors != NULL) {
        const ls_real *c0 = o->vertex_colors + 3 * (size_t)f[0], *c1 = o->vertex_colors + 3 * (size_t)f[1];
        const ls_real *c2 = o->vertex_colors + 3 * (size_t)f[2];
        for (c = 0; c < 3; c++) alb[c] = b0 * c0[c] + b1 * c1[c] + b2 * c2[c];
    } else {
        alb[0] = alb[1] = alb[2] = (ls_real)1;
    }
    if (o->texture != NULL) {
        ls_real uv[2], t[3];
        ls_shade_uv(o->uvs, f, b, uv);
        ls_texture_sample(o->texture, uv[0], uv[1], t);
        for (c = 0; c < 3; c++) alb[c] *= t[c];
    }
    if (o->mode == LS_SHADE_COLOR) {
        rgb[0] = alb[0];
        rgb[1] = alb[1];
        rgb[2] = alb[2];
        return;
    }
    {
        const ls_real *n0 = normals + 3 * (size_t)f[0], *n1 = normals + 3 * (size_t)f[1];
        const ls_real *n2 = normals + 3 * (size_t)f[2];
        for (c = 0; c < 3; c++) n[c] = b0 * n0[c] + b1 * n1[c] + b2 * n2[c];
    }
    if (o->renormalize) (void)normalize_nonzero(n);
    if (o->mode == LS_SHADE_SH) {
        ls_shade_sh_eval(o->sh, n, rgb);
    } else { /* Lambert */
        uint32_t l;
        rgb[0] = o->ambient[0];
        rgb[1] = o->ambient[1];
        rgb[2] = o->ambient[2];
        for (l = 0; l < o->light_count; l++) {
            const ls_light *li = &o->lights[l];
            ls_real d = n[0] * li->dir[0] + n[1] * li->dir[1] + n[2] * li->dir[2];
            if (d > (ls_real)0)
                for (c = 0; c < 3; c++) rgb[c] += d * li->rgb[c];
        }
    }
    for (c = 0; c < 3; c++) rgb[c] *= alb[c];
}

/* The factors of the SH irradiance that do not depend on the normal, per
 * channel: ls_shade_sh_eval forms them on each call, ls_shade's SH loop once
 * for all its pixels (the same bits). */
typedef struct sh_pre {
    ls_real k8[3], k6[3], k0[3];
} sh_pre;

static void sh_pre_init(sh_pre *p, const ls_real sh[27])
{
    const ls_real c1 = (ls_real)LS_SH_C1, c3 = (ls_real)LS_SH_C3, c4 = (ls_real)LS_SH_C4, c5 = (ls_real)LS_SH_C5;
    int c;
    for (c = 0; c < 3; c++) {
        const ls_real *L = sh + 9 * (size_t)c;
        p->k8[c] = c1 * L[8];
        p->k6[c] = c3 * L[6];
        p->k0[c] = c4 * L[0] - c5 * L[6];
    }
}

/* ls_shade_sh_eval with the factors of p (same operations, same order). */
static inline void sh_eval_pre(const sh_pre *p, const ls_real sh[27], const ls_real n[3], ls_real rgb[3])
{
    const ls_real c1 = (ls_real)LS_SH_C1, c2 = (ls_real)LS_SH_C2;
    ls_real x = n[0], y = n[1], z = n[2];
    int c;
    for (c = 0; c < 3; c++) {
        const ls_real *L = sh + 9 * (size_t)c;
        ls_real e = p->k8[c] * (x * x - y * y);
        e += p->k6[c] * z * z;
        e += p->k0[c];
        e += (ls_real)2 * c1 * (L[4] * x * y + L[7] * x * z + L[5] * y * z);
        e += (ls_real)2 * c2 * (L[3] * x + L[1] * y + L[2] * z);
        rgb[c] = e * R_INV_PI;
    }
}

void ls_shade_sh_eval(const ls_real sh[27], const ls_real n[3], ls_real rgb[3])
{
    sh_pre pre;
    sh_pre_init(&pre, sh);
    sh_eval_pre(&pre, sh, n, rgb);
}

#if LS_FAST_PATHS
/* ls_shade's common case (the fit's): SH, no vertex colours, texture or
 * background image, one sample per pixel. The operations of the general
 * loop and ls_shade_point, without their per-sample tests; their products by
 * the albedo 1 and by 1 / S^2 = 1 are left out (x * 1 is x for any value
 * arithmetic gives: no signalling NaN). */
LS_NOINLINE static void shade_sh1(const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count,
                                  const ls_real *normals, const ls_shade_opts *o, const ls_real bg_pixel[4], ls_real *out)
{
    const uint32_t *tri = vis->tri;
    const ls_real *bary = vis->bary, *sh = o->sh;
    const size_t count = (size_t)vis->width * vis->height;
    const int renormalize = o->renormalize != 0;
    sh_pre pre;
    size_t p;
    sh_pre_init(&pre, sh);
    for (p = 0; p < count; p++) {
        const uint32_t id = tri[p];
        ls_real *px = out + 4 * p;
        if (id == 0 || id > triangle_count) {
            memcpy(px, bg_pixel, 4 * sizeof *bg_pixel);
            continue;
        }
        {
            const uint32_t *f = indices + 3 * (size_t)(id - 1u);
            const ls_real *n0 = normals + 3 * (size_t)f[0], *n1 = normals + 3 * (size_t)f[1];
            const ls_real *n2 = normals + 3 * (size_t)f[2];
            const ls_real b0 = bary[2 * p], b1 = bary[2 * p + 1], b2 = (ls_real)1 - b0 - b1;
            ls_real n[3], rgb[3];
            n[0] = b0 * n0[0] + b1 * n1[0] + b2 * n2[0];
            n[1] = b0 * n0[1] + b1 * n1[1] + b2 * n2[1];
            n[2] = b0 * n0[2] + b1 * n1[2] + b2 * n2[2];
            if (renormalize) (void)normalize_nonzero(n);
            sh_eval_pre(&pre, sh, n, rgb);
            /* the general loop's sums from +0 (a -0 becomes +0) */
            px[0] = (ls_real)0 + rgb[0];
            px[1] = (ls_real)0 + rgb[1];
            px[2] = (ls_real)0 + rgb[2];
            px[3] = (ls_real)1;
        }
    }
}

#endif

ls_status ls_shade_check_args(const ls_vis *vis, const uint32_t counts[2], const uint32_t *indices,
                              const ls_real *normals, const ls_shade_opts *opts, ls_diag *diag)
{
    const uint32_t triangle_count = counts[0], vertex_count = counts[1];
    if (vis == NULL) return ls_invalid_arg(diag, "view->vis is NULL");
    if (opts == NULL) return ls_invalid_arg(diag, "view->opts is NULL");
    if (vis->tri == NULL) return LS_ERR_STATE;
    if (vis->triangle_count != triangle_count)
        return ls_invalid_arg(diag, "view->triangle_count: allowed = view->vis->triangle_count");
    if (vis->vertex_count != vertex_count)
        return ls_invalid_arg(diag, "view->vertex_count: allowed = view->vis->vertex_count");
    if (opts->mode > LS_SHADE_COLOR)
        return ls_invalid_arg(diag, "view->opts->mode: allowed LS_SHADE_MASK .. LS_SHADE_COLOR");
    if (triangle_count > 0 && indices == NULL)
        return ls_invalid_arg(diag, "view->indices is NULL with triangle_count > 0");
    if ((opts->mode == LS_SHADE_SH || opts->mode == LS_SHADE_LAMBERT) && normals == NULL)
        return ls_invalid_arg(diag, "view->normals is NULL; needed by LS_SHADE_SH and LS_SHADE_LAMBERT");
    if (opts->mode == LS_SHADE_SH && opts->sh == NULL)
        return ls_invalid_arg(diag, "view->opts->sh is NULL; needed by LS_SHADE_SH");
    if (opts->mode == LS_SHADE_LAMBERT && opts->light_count > 0 && opts->lights == NULL)
        return ls_invalid_arg(diag, "view->opts->lights is NULL with light_count > 0");
    if (opts->mode == LS_SHADE_COLOR && opts->vertex_colors == NULL && opts->texture == NULL)
        return ls_invalid_arg(diag, "view->opts: LS_SHADE_COLOR needs vertex_colors or texture");
    if (opts->texture != NULL && opts->uvs == NULL)
        return ls_invalid_arg(diag, "view->opts->uvs is NULL; needed with a texture");
    if (opts->texture != NULL && ls_texture_check(opts->texture) != LS_OK)
        return ls_invalid_arg(diag, "view->opts->texture: texels NULL, wrap_u unknown or size out of range");
    return ls_check_triangle_indices(indices, triangle_count, vertex_count, diag);
}

static ls_status shade_impl(const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count, const ls_real *normals,
                            uint32_t vertex_count, const ls_shade_opts *opts, ls_real *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    uint32_t x, y, ss;
    ls_real inv_n, bg_pixel[4];
    uint32_t counts[2];
    ls_status st;
    if (out == NULL) return ls_invalid_arg(diag, "out is NULL");
    counts[0] = triangle_count;
    counts[1] = vertex_count;
    st = ls_shade_check_args(vis, counts, indices, normals, opts, diag);
    if (st != LS_OK) return st;
    ss = vis->ss;
    inv_n = (ls_real)1 / (ls_real)(ss * ss);
    /* a pixel that sees no surface: with a constant background, its value
     * computed once, by the same sums the loop below would do */
    {
        uint32_t k;
        bg_pixel[0] = bg_pixel[1] = bg_pixel[2] = (ls_real)0;
        for (k = 0; k < ss * ss; k++) {
            bg_pixel[0] += opts->background[0];
            bg_pixel[1] += opts->background[1];
            bg_pixel[2] += opts->background[2];
        }
        bg_pixel[0] *= inv_n;
        bg_pixel[1] *= inv_n;
        bg_pixel[2] *= inv_n;
        bg_pixel[3] = (ls_real)0 * inv_n;
    }
#if LS_FAST_PATHS
    if (ss == 1 && opts->mode == LS_SHADE_SH && opts->vertex_colors == NULL && opts->texture == NULL &&
        opts->background_image == NULL) {
        shade_sh1(vis, indices, triangle_count, normals, opts, bg_pixel, out);
        return LS_OK;
    }
#endif
    for (y = 0; y < vis->height; y++) {
        /* the pixel's first sample, stepped along (no index products per pixel) */
        size_t s0 = (size_t)y * ss * vis->sw, p = (size_t)y * vis->width;
        for (x = 0; x < vis->width; x++, s0 += ss, p++) {
            const ls_real *bg = opts->background_image != NULL ? opts->background_image + 3 * p : opts->background;
            ls_real acc[3] = {(ls_real)0, (ls_real)0, (ls_real)0};
            uint32_t covered = 0, i, j;
            if (opts->background_image == NULL && ls_pixel_empty(vis->tri + s0, ss, vis->sw, triangle_count)) {
                memcpy(out + 4 * p, bg_pixel, sizeof bg_pixel);
                continue;
            }
            /* samples of the pixel in row-major order: a fixed summation order */
            for (j = 0; j < ss; j++) {
                for (i = 0; i < ss; i++) {
                    size_t s = s0 + (size_t)j * vis->sw + i;
                    uint32_t id = vis->tri[s];
                    ls_real rgb[3];
                    if (id == 0 || id > triangle_count) {
                        rgb[0] = bg[0];
                        rgb[1] = bg[1];
                        rgb[2] = bg[2];
                    } else {
                        covered++;
                        ls_real b[3];
                        b[0] = vis->bary[2 * s];
                        b[1] = vis->bary[2 * s + 1];
                        b[2] = (ls_real)1 - b[0] - b[1];
                        ls_shade_point(opts, indices + 3 * (size_t)(id - 1u), normals, b, rgb);
                    }
                    acc[0] += rgb[0];
                    acc[1] += rgb[1];
                    acc[2] += rgb[2];
                }
            }
            out[4 * p] = acc[0] * inv_n;
            out[4 * p + 1] = acc[1] * inv_n;
            out[4 * p + 2] = acc[2] * inv_n;
            out[4 * p + 3] = (ls_real)covered * inv_n;
        }
    }
    return LS_OK;
}

ls_status ls_shade(const ls_view *view, ls_real *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return shade_impl(view->vis, view->indices, view->triangle_count, view->normals, view->vertex_count, view->opts, out, diag);
}

/* ls_face_cross, inlined into the sums below. */
static inline ls_real face_cross(const ls_real *positions, const uint32_t *f, ls_real e1[3], ls_real e2[3], ls_real c[3])
{
    const ls_real *p0 = positions + 3 * (size_t)f[0], *p1 = positions + 3 * (size_t)f[1];
    const ls_real *p2 = positions + 3 * (size_t)f[2];
    int k;
    for (k = 0; k < 3; k++) {
        e1[k] = p1[k] - p0[k];
        e2[k] = p2[k] - p0[k];
    }
    c[0] = e1[1] * e2[2] - e1[2] * e2[1];
    c[1] = e1[2] * e2[0] - e1[0] * e2[2];
    c[2] = e1[0] * e2[1] - e1[1] * e2[0];
    return c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
}

ls_real ls_face_cross(const ls_real *positions, const uint32_t *f, ls_real e1[3], ls_real e2[3], ls_real c[3])
{
    return face_cross(positions, f, e1, e2, c);
}

int ls_face_unit_normal(const ls_real *positions, const uint32_t *f, ls_real n[3])
{
    ls_real e1[3], e2[3], c[3], l2 = face_cross(positions, f, e1, e2, c), l;
    n[0] = n[1] = n[2] = (ls_real)0;
    if (!(l2 > (ls_real)0) || l2 - l2 != l2 - l2) return 0; /* degenerate or overflow */
    l = R_SQRT(l2);
    n[0] = c[0] / l;
    n[1] = c[1] / l;
    n[2] = c[2] / l;
    return 1;
}

void ls_vertex_normal_sums(const ls_real *positions, uint32_t vertex_count, const uint32_t *indices,
                           uint32_t triangle_count, ls_real *m)
{
    uint32_t t, v;
    for (v = 0; v < 3 * vertex_count; v++) m[v] = (ls_real)0;
    /* faces in input order: a fixed accumulation order per vertex */
    for (t = 0; t < triangle_count; t++) {
        const uint32_t *f = indices + 3 * (size_t)t;
        ls_real n[3];
        uint32_t k, q;
        if (!ls_face_unit_normal(positions, f, n)) continue;
        for (k = 0; k < 3u; k++)
            for (q = 0; q < 3u; q++) m[3 * (size_t)f[k] + q] += n[q];
    }
}

void ls_vertex_normal_unit(const ls_real m[3], ls_real n[3])
{
    n[0] = m[0];
    n[1] = m[1];
    n[2] = m[2];
    if (!normalize_nonzero(n)) n[0] = n[1] = n[2] = (ls_real)0;
}

ls_status ls_shade_vertex_normals(const ls_real *positions, uint32_t vertex_count, const uint32_t *indices,
                                  uint32_t triangle_count, ls_real *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    uint32_t v;
    if (vertex_count > 0 && positions == NULL) return ls_invalid_arg(diag, "positions is NULL with vertex_count > 0");
    if (vertex_count > 0 && out == NULL) return ls_invalid_arg(diag, "out is NULL with vertex_count > 0");
    if (triangle_count > 0 && indices == NULL) return ls_invalid_arg(diag, "indices is NULL with triangle_count > 0");
    if (ls_check_triangle_indices(indices, triangle_count, vertex_count, diag) != LS_OK) return LS_ERR_MESH;
    ls_vertex_normal_sums(positions, vertex_count, indices, triangle_count, out);
    for (v = 0; v < vertex_count; v++) ls_vertex_normal_unit(out + 3 * (size_t)v, out + 3 * (size_t)v);
    return LS_OK;
}

ls_status ls_sh_from_equirect(const ls_real *rgb, uint32_t width, uint32_t height, ls_real sh[27])
{
    uint32_t i, j;
    int k, c;
    ls_real acc[27];
    if (rgb == NULL || sh == NULL || width == 0 || height == 0) return LS_ERR_INVALID;
    for (k = 0; k < 27; k++) acc[k] = (ls_real)0;
    for (j = 0; j < height; j++) {
        ls_real th = R_PI * ((ls_real)j + (ls_real)0.5) / (ls_real)height;
        ls_real st = R_SIN(th), ct = R_COS(th);
        ls_real dw = ((ls_real)2 * R_PI / (ls_real)width) * (R_PI / (ls_real)height) * st;
        for (i = 0; i < width; i++) {
            ls_real ph = (ls_real)2 * R_PI * ((ls_real)i + (ls_real)0.5) / (ls_real)width;
            ls_real x = st * R_COS(ph), y = ct, z = st * R_SIN(ph), Y[9];
            const ls_real *px = rgb + 3 * ((size_t)j * width + i);
            Y[0] = (ls_real)0.282095;
            Y[1] = (ls_real)0.488603 * y;
            Y[2] = (ls_real)0.488603 * z;
            Y[3] = (ls_real)0.488603 * x;
            Y[4] = (ls_real)1.092548 * x * y;
            Y[5] = (ls_real)1.092548 * y * z;
            Y[6] = (ls_real)0.315392 * ((ls_real)3 * z * z - (ls_real)1);
            Y[7] = (ls_real)1.092548 * x * z;
            Y[8] = (ls_real)0.546274 * (x * x - y * y);
            for (c = 0; c < 3; c++)
                for (k = 0; k < 9; k++) acc[9 * c + k] += px[c] * Y[k] * dw;
        }
    }
    memcpy(sh, acc, sizeof acc);
    return LS_OK;
}

/* Inverse of a 4x4 matrix by Gauss-Jordan elimination with partial pivoting
 * (a fixed sequence of operations); returns 0 when it is singular. */
static int invert4(const ls_real m[16], ls_real inv[16])
{
    ls_real a[4][8];
    int r, c, k;
    for (r = 0; r < 4; r++)
        for (c = 0; c < 8; c++) a[r][c] = c < 4 ? m[4 * r + c] : (c - 4 == r ? (ls_real)1 : (ls_real)0);
    for (c = 0; c < 4; c++) {
        int piv = c;
        ls_real best = a[c][c] < (ls_real)0 ? -a[c][c] : a[c][c];
        for (r = c + 1; r < 4; r++) {
            ls_real v = a[r][c] < (ls_real)0 ? -a[r][c] : a[r][c];
            if (v > best) {
                best = v;
                piv = r;
            }
        }
        if (!(best > (ls_real)0)) return 0;
        if (piv != c)
            for (k = 0; k < 8; k++) {
                ls_real t = a[c][k];
                a[c][k] = a[piv][k];
                a[piv][k] = t;
            }
        for (k = 7; k >= c; k--) a[c][k] /= a[c][c];
        for (r = 0; r < 4; r++) {
            ls_real f;
            if (r == c) continue;
            f = a[r][c];
            for (k = c; k < 8; k++) a[r][k] -= f * a[c][k];
        }
    }
    for (r = 0; r < 4; r++)
        for (c = 0; c < 4; c++) inv[4 * r + c] = a[r][c + 4];
    return 1;
}

/* Clamped index floor(u * n) for u in [0, 1] (NaN -> 0). */
static uint32_t texel(ls_real u, uint32_t n)
{
    ls_real v = u * (ls_real)n;
    uint32_t i;
    if (!(v > (ls_real)0)) return 0;
    if (v >= (ls_real)n) return n - 1u;
    i = (uint32_t)v; /* 0 <= v < n <= 2^32 - 1 */
    return i < n ? i : n - 1u;
}

ls_status ls_shade_env_background(const ls_real *env, uint32_t env_width, uint32_t env_height,
                                  const ls_real view[16], const ls_real proj[16], uint32_t width,
                                  uint32_t height, ls_real *out)
{
    ls_real ip[16];
    uint32_t x, y;
    int k;
    if (env == NULL || view == NULL || proj == NULL || out == NULL || env_width == 0 || env_height == 0 ||
        width == 0 || height == 0)
        return LS_ERR_INVALID;
    for (k = 0; k < 16; k++)
        if (view[k] - view[k] != view[k] - view[k] || proj[k] - proj[k] != proj[k] - proj[k])
            return LS_ERR_NONFINITE;
    if (!invert4(proj, ip)) return LS_ERR_INVALID;
    for (y = 0; y < height; y++) {
        ls_real ny = (ls_real)1 - (ls_real)2 * ((ls_real)y + (ls_real)0.5) / (ls_real)height;
        for (x = 0; x < width; x++) {
            ls_real nx = (ls_real)2 * ((ls_real)x + (ls_real)0.5) / (ls_real)width - (ls_real)1;
            ls_real p[2][3], d[3], w[3], l2, t, ph;
            const ls_real *px;
            int e;
            size_t i;
            for (e = 0; e < 2; e++) { /* unproject NDC depth -1 and +1 */
                ls_real nz = e == 0 ? (ls_real)-1 : (ls_real)1, h[4];
                for (i = 0; i < 4; i++) h[i] = ip[4 * i] * nx + ip[4 * i + 1] * ny + ip[4 * i + 2] * nz + ip[4 * i + 3];
                for (i = 0; i < 3; i++) p[e][i] = h[i] / h[3];
            }
            for (i = 0; i < 3; i++) d[i] = p[1][i] - p[0][i];
            /* view to world: the transpose of the view rotation */
            for (i = 0; i < 3; i++) w[i] = view[i] * d[0] + view[4 + i] * d[1] + view[8 + i] * d[2];
            l2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
            t = R_ATAN2(R_SQRT(w[0] * w[0] + w[2] * w[2]), w[1]); /* polar angle from +y */
            ph = R_ATAN2(w[2], w[0]);
            if (ph < (ls_real)0) ph += (ls_real)2 * R_PI;
            if (!(l2 > (ls_real)0)) t = ph = (ls_real)0;
            px = env + 3 * ((size_t)texel(t / R_PI, env_height) * env_width +
                            texel(ph / ((ls_real)2 * R_PI), env_width));
            out[3 * ((size_t)y * width + x)] = px[0];
            out[3 * ((size_t)y * width + x) + 1] = px[1];
            out[3 * ((size_t)y * width + x) + 2] = px[2];
        }
    }
    return LS_OK;
}
