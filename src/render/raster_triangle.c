/* raster_triangle.c - a triangle's set-up for the rasterizer: the vertex
 * transform, clipping against the view volume, snapping to fixed point */
#include "raster_internal.h"

void ls_rast_ctx_init(rctx *cx, const ls_real mvp[16], uint32_t sw, uint32_t sh)
{
    cx->m = mvp;
    cx->sw = sw;
    cx->sh = sh;
    cx->sw_half = (ls_real)sw * (ls_real)0.5;
    cx->sh_half = (ls_real)sh * (ls_real)0.5;
    /* x_s in [-G, sw + G]  <=>  X/W in [-(1 + 2G/sw), 1 + 2G/sw] */
    cx->gx = (ls_real)1 + (ls_real)(2u * LS_RASTER_GUARD) / (ls_real)sw;
    cx->gy = (ls_real)1 + (ls_real)(2u * LS_RASTER_GUARD) / (ls_real)sh;
    cx->tiles_x = (sw + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2;
    cx->tiles_y = (sh + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2;
}

/* Signed distance-like value of c to clip plane k (inside when >= 0):
 * 0 near (Z >= -W), 1 left, 2 right, 3 top, 4 bottom of the guard band. */
static inline ls_real plane_dist(const rctx *cx, const ls_real c[4], int k)
{
    switch (k) {
    case 0: return c[2] + c[3];
    case 1: return c[0] + cx->gx * c[3];
    case 2: return cx->gx * c[3] - c[0];
    case 3: return cx->gy * c[3] - c[1];
    default: return c[1] + cx->gy * c[3];
    }
}

static inline void snap_xyzw(ls_real sw_half, ls_real sh_half, ls_real c0, ls_real c1, ls_real c2, ls_real c3,
                             int32_t *x, int32_t *y, ls_real *zw, ls_real *iw)
{
    const ls_real inv = (ls_real)1 / c3;
    *x = snap_round((c0 * inv + (ls_real)1) * sw_half);
    *y = snap_round(((ls_real)1 - c1 * inv) * sh_half);
    *zw = c2 * inv;
    *iw = inv;
}

static void snap_point(const rctx *cx, const ls_real c[4], int32_t *x, int32_t *y, ls_real *zw, ls_real *iw)
{
    snap_xyzw(cx->sw_half, cx->sh_half, c[0], c[1], c[2], c[3], x, y, zw, iw);
}

/* Row r of the transform times (x, y, z, 1), summed left to right. */
static inline ls_real mrow(const ls_real r[4], ls_real x, ls_real y, ls_real z)
{
    ls_real s = r[0] * x;
    s += r[1] * y;
    s += r[2] * z;
    return s + r[3];
}

/* gcc's basic-block vectorizer pairs the matrix rows with more shuffles than
 * it saves (docs/fast-paths.md). */
#if defined(__GNUC__) && !defined(__clang__)
#define NO_SLP __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define NO_SLP
#endif

/* Transforms vertices idx[i] (i when idx is NULL) of positions into entries
 * i of vb, i in [0, count); returns the first i whose clip coordinates are
 * not finite, or count. Each vertex in locals, stored once at the end
 * (stores through vb could alias the transform and the positions: values
 * kept in memory are reloaded). */
NO_SLP LS_NOINLINE uint32_t ls_rast_transform_all(const rctx *cx, const ls_real *positions, const uint32_t *idx,
                                                 uint32_t count, const vbuf *vb)
{
    const ls_real *m = cx->m;
    const ls_real gx = cx->gx, gy = cx->gy, sw_half = cx->sw_half, sh_half = cx->sh_half;
    ls_real *const clip = vb->clip, *const zi = vb->zi;
    int32_t *const snap = vb->snap;
    uint32_t *const vflags = vb->flags;
    uint32_t i;
    for (i = 0; i < count; i++) {
        const ls_real *p = positions + 3 * (size_t)(idx != NULL ? idx[i] : i);
        const ls_real px = p[0], py = p[1], pz = p[2];
        const ls_real c0 = mrow(m, px, py, pz), c1 = mrow(m + 4, px, py, pz);
        const ls_real c2 = mrow(m + 8, px, py, pz), c3 = mrow(m + 12, px, py, pz);
        ls_real *c = clip + 4 * (size_t)i;
        uint32_t flags;
        /* one test for the four: a sum of x - x is +0 when all are finite, NaN otherwise */
        if (!((c0 - c0) + (c1 - c1) + (c2 - c2) + (c3 - c3) == (ls_real)0)) break;
        {
            /* the common case first, one test: the least of the five plane
             * values (plane_dist's, from locals: cx's fields would be
             * reloaded after each store; finite or infinite, never NaN, for
             * finite c) is >= 0 */
            const ls_real gxw = gx * c3, gyw = gy * c3;
            const ls_real d0 = c2 + c3, d1 = c0 + gxw, d2 = gxw - c0, d3 = gyw - c1, d4 = c1 + gyw;
            ls_real lo = d0 < d1 ? d0 : d1;
            lo = lo < d2 ? lo : d2;
            lo = lo < d3 ? lo : d3;
            lo = lo < d4 ? lo : d4;
            if (lo >= (ls_real)0)
                flags = c3 > (ls_real)0 ? 0u : FLAG_BAD_W;
            else
                flags = (uint32_t)(d0 < (ls_real)0) | (uint32_t)(d1 < (ls_real)0) << 1 |
                        (uint32_t)(d2 < (ls_real)0) << 2 | (uint32_t)(d3 < (ls_real)0) << 3 |
                        (uint32_t)(d4 < (ls_real)0) << 4;
        }
        c[0] = c0;
        c[1] = c1;
        c[2] = c2;
        c[3] = c3;
        vflags[i] = flags;
        if (flags == 0) {
            snap_xyzw(sw_half, sh_half, c0, c1, c2, c3, &snap[2 * (size_t)i], &snap[2 * (size_t)i + 1], &zi[2 * (size_t)i],
                      &zi[2 * (size_t)i + 1]);
        } else {
            snap[2 * (size_t)i] = snap[2 * (size_t)i + 1] = 0;
            zi[2 * (size_t)i] = zi[2 * (size_t)i + 1] = (ls_real)0;
        }
    }
    return i;
}

/* 1 when a is lexicographically smaller than b (canonical edge direction). */
static int lex_less(const ls_real a[4], const ls_real b[4])
{
    int i;
    for (i = 0; i < 4; i++) {
        if (a[i] < b[i]) return 1;
        if (a[i] > b[i]) return 0;
    }
    return 0;
}

/* Intersection of edge (p, q) with plane k, computed from the canonical
 * endpoint so that both triangles sharing the edge get the same point. */
static void clip_edge(const rctx *cx, const pvert *p, const pvert *q, int k, pvert *out)
{
    const pvert *a = p, *b = q;
    ls_real da, db, t;
    int i;
    if (lex_less(q->c, p->c)) {
        a = q;
        b = p;
    }
    da = plane_dist(cx, a->c, k);
    db = plane_dist(cx, b->c, k);
    t = da / (da - db);
    for (i = 0; i < 4; i++) out->c[i] = a->c[i] + t * (b->c[i] - a->c[i]);
    for (i = 0; i < 2; i++) out->b[i] = a->b[i] + t * (b->b[i] - a->b[i]);
}

/* Clips the triangle (v0, v1, v2) against the planes in `planes`; the polygon
 * ends up in cb->a. Returns its vertex count (0 when nothing is left). */
LS_NOINLINE static int clip_polygon(const rctx *cx, const ls_real *const v[3], uint32_t planes, clipbuf *cb)
{
    int n = 3, k, i;
    pvert *src = cb->a, *dst = cb->b, *tmp;
    for (i = 0; i < 3; i++) {
        memcpy(src[i].c, v[i], sizeof src[i].c);
        src[i].b[0] = i == 0 ? (ls_real)1 : (ls_real)0;
        src[i].b[1] = i == 1 ? (ls_real)1 : (ls_real)0;
    }
    for (k = 0; k < NPLANES; k++) {
        int m = 0;
        if (!(planes & (1u << k))) continue;
        for (i = 0; i < n; i++) {
            const pvert *p = &src[i], *q = &src[i + 1 < n ? i + 1 : 0];
            int pin = plane_dist(cx, p->c, k) >= (ls_real)0;
            int qin = plane_dist(cx, q->c, k) >= (ls_real)0;
            if (pin && m < MAX_POLY) dst[m++] = *p;
            if (pin != qin && m < MAX_POLY) clip_edge(cx, p, q, k, &dst[m++]);
        }
        n = m;
        tmp = src;
        src = dst;
        dst = tmp;
        if (n < 3) return 0;
    }
    if (src != cb->a) memcpy(cb->a, src, (size_t)n * sizeof *src);
    return n;
}

/* Builds a positively oriented screen triangle from three snapped points;
 * returns 0 when its snapped area is zero. */
static int make_stri(stri *t)
{
    int64_t a = snap_area2(t->x, t->y);
    if (a == 0) return 0;
    if (a < 0) { /* swap vertices 1 and 2 */
        int32_t ti;
        ls_real tr;
        int i;
        ti = t->x[1]; t->x[1] = t->x[2]; t->x[2] = ti;
        ti = t->y[1]; t->y[1] = t->y[2]; t->y[2] = ti;
        tr = t->zw[1]; t->zw[1] = t->zw[2]; t->zw[2] = tr;
        tr = t->iw[1]; t->iw[1] = t->iw[2]; t->iw[2] = tr;
        for (i = 0; i < 2; i++) {
            tr = t->b[1][i]; t->b[1][i] = t->b[2][i]; t->b[2][i] = tr;
        }
        a = -a;
    }
    t->area = a;
    return 1;
}

/* Prepares a triangle that needs clipping (v: its vertices in vb, some flag
 * set): returns how many screen triangles it gives (a fan over the clipped
 * polygon, which is left in cb->a; 0 = nothing to draw). ls_rast_clipped_sub builds
 * them one at a time, so that only one screen triangle lives on the stack. */
int ls_rast_clipped_prepare(const rctx *cx, const vbuf *vb, const size_t v[3], clipbuf *cb)
{
    const uint32_t *fl = vb->flags;
    uint32_t any = fl[v[0]] | fl[v[1]] | fl[v[2]], all = fl[v[0]] & fl[v[1]] & fl[v[2]];
    const ls_real *c[3];
    int n, i;
    if (all & FLAG_OUT_MASK) return 0; /* entirely outside one plane */
    for (i = 0; i < 3; i++) c[i] = vb->clip + 4 * v[i];
    n = clip_polygon(cx, c, any & FLAG_OUT_MASK, cb);
    for (i = 0; i < n; i++)
        if (!(cb->a[i].c[3] > (ls_real)0)) return 0; /* not a proper projection */
    return n >= 3 ? n - 2 : 0;
}

/* Screen triangle k of a clipped triangle; returns 0 when its snapped area is 0. */
int ls_rast_clipped_sub(const rctx *cx, const clipbuf *cb, int k, stri *out)
{
    const pvert *p[3];
    int i;
    p[0] = &cb->a[0];
    p[1] = &cb->a[k + 1];
    p[2] = &cb->a[k + 2];
    for (i = 0; i < 3; i++) {
        snap_point(cx, p[i]->c, &out->x[i], &out->y[i], &out->zw[i], &out->iw[i]);
        out->b[i][0] = p[i]->b[0];
        out->b[i][1] = p[i]->b[1];
    }
    return make_stri(out);
}

/* The sample range of a triangle that needs clipping (union of its screen
 * triangles' boxes); 0 if empty. */
LS_NOINLINE int ls_rast_clipped_box(const rctx *cx, const vbuf *vb, const size_t v[3], clipbuf *cb, sbox *u)
{
    int n = ls_rast_clipped_prepare(cx, vb, v, cb), k, any = 0;
    sbox b;
    stri st;
    for (k = 0; k < n; k++) {
        if (!ls_rast_clipped_sub(cx, cb, k, &st) || !snap_box(cx->sw, cx->sh, st.x, st.y, &b)) continue;
        if (!any) {
            *u = b;
            any = 1;
        } else {
            if (b.x0 < u->x0) u->x0 = b.x0;
            if (b.y0 < u->y0) u->y0 = b.y0;
            if (b.x1 > u->x1) u->x1 = b.x1;
            if (b.y1 > u->y1) u->y1 = b.y1;
        }
    }
    return any;
}
