/* texture.c - RGB textures: bilinear lookup and its adjoint (see largesteps/texture.h). */
#include <largesteps/texture.h>
#include "render_internal.h"
#include <largesteps/math.h>
#include <largesteps/arena.h>

/* The four taps of a lookup: texel offsets (in ls_real units) of (i0, j0),
 * (i1, j0), (i0, j1), (i1, j1) and the fractions fx, fy. */
typedef struct taps {
    size_t off[4];
    ls_real fx, fy;
} taps;

/* Clamped column/row pair (k0, k1) and fraction of coordinate x on n texels. */
static void axis_clamp(ls_real x, uint32_t n, uint32_t *k0, uint32_t *k1, ls_real *f)
{
    ls_real xf = LS_RFLOOR(x);
    int32_t i = LS_RTO_I32(xf); /* clamped conversion: NaN and huge values are safe */
    int64_t a = (int64_t)i, b = (int64_t)i + 1;
    *f = x - xf;
    if (a < 0) a = 0;
    if (b < 0) b = 0;
    if (a > (int64_t)n - 1) a = (int64_t)n - 1;
    if (b > (int64_t)n - 1) b = (int64_t)n - 1;
    *k0 = (uint32_t)a;
    *k1 = (uint32_t)b;
}

/* Wrapped column pair of u (period 1) on n texels. */
static void axis_repeat(ls_real u, uint32_t n, uint32_t *k0, uint32_t *k1, ls_real *f)
{
    ls_real ur = u - LS_RFLOOR(u); /* [0, 1] (1 only by rounding) */
    ls_real x = ur * (ls_real)n - (ls_real)0.5, xf = LS_RFLOOR(x);
    int32_t i = LS_RTO_I32(xf); /* in [-1, n] for finite u */
    int64_t a = (int64_t)i % (int64_t)n, b;
    if (a < 0) a += (int64_t)n;
    b = a + 1 >= (int64_t)n ? 0 : a + 1;
    *f = x - xf;
    *k0 = (uint32_t)a;
    *k1 = (uint32_t)b;
}

static void make_taps(const ls_texture *t, ls_real u, ls_real v, taps *tp)
{
    uint32_t i0, i1, j0, j1;
    if (t->wrap_u == LS_TEXTURE_REPEAT)
        axis_repeat(u, t->width, &i0, &i1, &tp->fx);
    else
        axis_clamp(u * (ls_real)t->width - (ls_real)0.5, t->width, &i0, &i1, &tp->fx);
    axis_clamp(v * (ls_real)t->height - (ls_real)0.5, t->height, &j0, &j1, &tp->fy);
    tp->off[0] = 3 * ((size_t)j0 * t->width + i0);
    tp->off[1] = 3 * ((size_t)j0 * t->width + i1);
    tp->off[2] = 3 * ((size_t)j1 * t->width + i0);
    tp->off[3] = 3 * ((size_t)j1 * t->width + i1);
}

ls_status ls_grid_values_bytes(uint32_t width, uint32_t height, uint32_t channels, size_t *bytes)
{
    ls_size s;
    size_t n;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (width == 0 || height == 0) return LS_ERR_INVALID;
    if (ls_size_mul(width, height, &n) != LS_OK) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, n, channels * sizeof(ls_real));
    return ls_size_get(&s, bytes);
}

ls_status ls_texture_bytes(uint32_t width, uint32_t height, size_t *bytes)
{
    return ls_grid_values_bytes(width, height, 3, bytes);
}

ls_status ls_texture_check(const ls_texture *tex)
{
    size_t bytes;
    if (tex == NULL || tex->texels == NULL) return LS_ERR_INVALID;
    if (tex->wrap_u != LS_TEXTURE_CLAMP && tex->wrap_u != LS_TEXTURE_REPEAT) return LS_ERR_INVALID;
    if (ls_texture_bytes(tex->width, tex->height, &bytes) != LS_OK) return LS_ERR_INVALID;
    return LS_OK;
}

ls_status ls_texture_init(ls_texture *tex, uint32_t width, uint32_t height, uint32_t wrap_u,
                          const ls_real *texels)
{
    ls_texture t;
    if (tex == NULL) return LS_ERR_INVALID;
    t.width = width;
    t.height = height;
    t.wrap_u = wrap_u;
    t.texels = texels;
    if (ls_texture_check(&t) != LS_OK) return LS_ERR_INVALID;
    *tex = t;
    return LS_OK;
}

void ls_texture_sample(const ls_texture *tex, ls_real u, ls_real v, ls_real rgb[3])
{
    taps tp;
    int c;
    make_taps(tex, u, v, &tp);
    /* as two lerps in x and one in y: a constant texture gives its value exactly */
    for (c = 0; c < 3; c++) {
        ls_real t00 = tex->texels[tp.off[0] + (size_t)c], t10 = tex->texels[tp.off[1] + (size_t)c];
        ls_real t01 = tex->texels[tp.off[2] + (size_t)c], t11 = tex->texels[tp.off[3] + (size_t)c];
        ls_real a = t00 + tp.fx * (t10 - t00), b = t01 + tp.fx * (t11 - t01);
        rgb[c] = a + tp.fy * (b - a);
    }
}

void ls_texture_sample_backward(const ls_texture *tex, ls_real u, ls_real v, const ls_real g[3],
                                ls_real *grad_texels, ls_real duv[2])
{
    taps tp;
    int c;
    make_taps(tex, u, v, &tp);
    if (grad_texels != NULL) {
        ls_real w[4];
        int k;
        w[0] = ((ls_real)1 - tp.fx) * ((ls_real)1 - tp.fy);
        w[1] = tp.fx * ((ls_real)1 - tp.fy);
        w[2] = ((ls_real)1 - tp.fx) * tp.fy;
        w[3] = tp.fx * tp.fy;
        for (k = 0; k < 4; k++)
            for (c = 0; c < 3; c++) grad_texels[tp.off[k] + (size_t)c] += w[k] * g[c];
    }
    if (duv != NULL) {
        const ls_real *t00 = tex->texels + tp.off[0], *t10 = tex->texels + tp.off[1];
        const ls_real *t01 = tex->texels + tp.off[2], *t11 = tex->texels + tp.off[3];
        ls_real du = (ls_real)0, dv = (ls_real)0;
        for (c = 0; c < 3; c++) {
            du += g[c] * (((ls_real)1 - tp.fy) * (t10[c] - t00[c]) + tp.fy * (t11[c] - t01[c]));
            dv += g[c] * (((ls_real)1 - tp.fx) * (t01[c] - t00[c]) + tp.fx * (t11[c] - t10[c]));
        }
        duv[0] = du * (ls_real)tex->width;
        duv[1] = dv * (ls_real)tex->height;
    }
}
