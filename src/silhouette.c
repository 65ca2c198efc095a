/* silhouette.c - exact box-filter silhouette derivatives (largesteps/silhouette.h). */
#include <largesteps/silhouette.h>
#include "render_internal.h"
#include <largesteps/sort.h>
#include <largesteps/math.h>
#include <math.h>

#if LS_REAL_IS_FLOAT
#define R_SQRT sqrtf
#else
#define R_SQRT sqrt
#endif

#define EDGE_TABLE_MAGIC 0x45544231u /* "ETB1" */

static ls_status face_error(ls_diag *diag, uint32_t t, const char *what)
{
    if (diag != NULL) {
        ls_diag_clear(diag);
        diag->status = LS_ERR_MESH;
        diag->has_index = 1;
        diag->index = t;
        diag->what = what;
    }
    return LS_ERR_MESH;
}

static void table_size(ls_size *obj, ls_size *scratch, uint32_t triangle_count)
{
    size_t n = 3 * (size_t)triangle_count;
    ls_size_init(obj);
    ls_size_init(scratch);
    if (n == 0) return;
    ls_size_add(obj, n, sizeof(uint32_t));
    ls_size_add(scratch, n, sizeof(uint64_t)); /* keys */
    ls_size_add(scratch, n, sizeof(uint32_t)); /* sorted order */
    ls_size_add(scratch, n, sizeof(uint32_t)); /* sort scratch */
}

ls_status ls_edge_table_bytes(uint32_t triangle_count, size_t *bytes)
{
    ls_size obj, scratch;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if ((uint64_t)triangle_count * 3u >= (uint64_t)LS_EDGE_NONE) return LS_ERR_TOO_LARGE;
    table_size(&obj, &scratch, triangle_count);
    ls_size_add_size(&obj, &scratch);
    return ls_size_get(&obj, bytes);
}

ls_status ls_edge_table_build(ls_edge_table *table, const uint32_t *indices, uint32_t triangle_count,
                              uint32_t vertex_count, ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    uint32_t *twin = NULL, t, n, boundary = 0;
    if (table == NULL || arena == NULL || (triangle_count > 0 && indices == NULL)) return LS_ERR_INVALID;
    if ((uint64_t)triangle_count * 3u >= (uint64_t)LS_EDGE_NONE) return LS_ERR_TOO_LARGE;
    for (t = 0; t < triangle_count; t++) {
        const uint32_t *f = indices + 3 * (size_t)t;
        if (f[0] >= vertex_count || f[1] >= vertex_count || f[2] >= vertex_count)
            return face_error(diag, t, "triangle vertex index out of range");
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
            return face_error(diag, t, "triangle with a repeated vertex");
    }
    n = 3u * triangle_count;
    mark = ls_arena_save(arena);
    if (n > 0) {
        uint32_t *order, *sscr, i;
        uint64_t *keys;
        twin = (uint32_t *)ls_arena_alloc(arena, n, sizeof(uint32_t));
        keys = twin ? (uint64_t *)ls_arena_scratch(arena, n, sizeof(uint64_t)) : NULL;
        order = keys ? (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t)) : NULL;
        sscr = order ? (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t)) : NULL;
        if (sscr == NULL) {
            ls_arena_restore(arena, mark);
            return LS_ERR_NOMEM;
        }
        for (i = 0; i < n; i++) {
            uint32_t a = indices[i], b = indices[i - i % 3u + (i % 3u + 1u) % 3u];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            keys[i] = ((uint64_t)lo << 32) | hi;
            order[i] = i;
        }
        if (ls_sort_u64(keys, order, n, sscr) != LS_OK) {
            ls_arena_restore(arena, mark);
            return LS_ERR_INVALID;
        }
        i = 0;
        while (i < n) {
            uint32_t j = i + 1u;
            while (j < n && keys[order[j]] == keys[order[i]]) j++;
            if (j - i == 2u) {
                twin[order[i]] = order[i + 1u];
                twin[order[i + 1u]] = order[i];
            } else {
                uint32_t k;
                for (k = i; k < j; k++) twin[order[k]] = LS_EDGE_NONE;
                boundary += j - i;
            }
            i = j;
        }
        /* release the scratch, keep the twins */
        {
            ls_arena_mark keep = mark;
            keep.bottom = arena->bottom;
            ls_arena_restore(arena, keep);
        }
    }
    table->triangle_count = triangle_count;
    table->vertex_count = vertex_count;
    table->twin = twin;
    table->boundary_edges = boundary;
    table->magic = EDGE_TABLE_MAGIC;
    return LS_OK;
}

/* ---- the silhouette pass ---- */

typedef struct sctx {
    const ls_vis *vis;
    const uint32_t *indices;
    const ls_real *normals;
    const ls_shade_opts *o;
    const ls_real *m;
    const ls_real *gimg;
    uint32_t triangle_count;
    ls_real width, height;
} sctx;

/* The point of triangle f on the ray through window (xw, yw): barycentrics
 * b and NDC depth; returns 0 when the triangle is edge-on there or the point
 * is behind the eye. */
static int tri_point(const sctx *sc, const uint32_t *f, ls_real xw, ls_real yw, ls_real b[3], ls_real *depth)
{
    ls_real px = (ls_real)2 * xw / sc->width - (ls_real)1, py = (ls_real)1 - (ls_real)2 * yw / sc->height;
    ls_real u[3], v[3], cz = (ls_real)0, cw = (ls_real)0;
    int k;
    if (ls_clip_barycentric(sc->vis->clip, f, px, py, u, v, b) == (ls_real)0) return 0;
    for (k = 0; k < 3; k++) {
        const ls_real *cl = sc->vis->clip + 4 * (size_t)f[k];
        cz += b[k] * cl[2];
        cw += b[k] * cl[3];
    }
    if (!(cw > (ls_real)0)) return 0;
    *depth = cz / cw;
    return 1;
}

/* The surface colour of triangle f at barycentrics b (as ls_shade). */
static ls_real r_abs(ls_real x) { return x < (ls_real)0 ? -x : x; }

/* g_P . (f_inside - f_behind) at window point (xw, yw) on the edge of face
 * `ft` (twin face `fu`, or LS_EDGE_NONE) in pixel p; 0 when hidden. */
static ls_real point_term(const sctx *sc, uint32_t ft, uint32_t fu, ls_real xw, ls_real yw, size_t p)
{
    const ls_vis *vis = sc->vis;
    ls_real b[3], ze, rgb_in[3], rgb_bh[3], a_bh, best = (ls_real)0, tol;
    const ls_real *g = sc->gimg + 4 * p;
    uint32_t seen[9], nseen = 0, best_id = 0;
    int32_t sx, sy, i, j;
    ls_real fx = LS_RFLOOR(xw * (ls_real)vis->ss), fy = LS_RFLOOR(yw * (ls_real)vis->ss);
    if (!tri_point(sc, sc->indices + 3 * (size_t)ft, xw, yw, b, &ze)) return (ls_real)0;
    ls_shade_point(sc->o, sc->indices + 3 * (size_t)ft, sc->normals, b, rgb_in);
    tol = (ls_real)64 * LS_REAL_EPSILON * ((ls_real)1 + r_abs(ze));
    sx = LS_RTO_I32(fx);
    sy = LS_RTO_I32(fy);
    for (j = sy - 1; j <= sy + 1; j++) {
        if (j < 0 || (uint32_t)j >= vis->sh) continue;
        for (i = sx - 1; i <= sx + 1; i++) {
            uint32_t id, q, dup = 0;
            ls_real bc[3], zc;
            if (i < 0 || (uint32_t)i >= vis->sw) continue;
            id = vis->tri[(size_t)j * vis->sw + (size_t)i];
            if (id == 0 || id > sc->triangle_count || id - 1u == ft || id - 1u == fu) continue;
            for (q = 0; q < nseen; q++) dup |= seen[q] == id;
            if (dup) continue;
            seen[nseen++] = id;
            if (!tri_point(sc, sc->indices + 3 * (size_t)(id - 1u), xw, yw, bc, &zc)) continue;
            if (bc[0] < (ls_real)0 || bc[1] < (ls_real)0 || bc[2] < (ls_real)0) continue;
            if (zc < ze - tol) return (ls_real)0; /* hidden */
            if (zc > ze + tol && (best_id == 0 || zc < best || (zc == best && id < best_id))) {
                best = zc;
                best_id = id;
            }
        }
    }
    if (best_id != 0) {
        if (!tri_point(sc, sc->indices + 3 * (size_t)(best_id - 1u), xw, yw, b, &ze)) return (ls_real)0;
        ls_shade_point(sc->o, sc->indices + 3 * (size_t)(best_id - 1u), sc->normals, b, rgb_bh);
        a_bh = (ls_real)1;
    } else {
        const ls_real *bg = sc->o->background_image != NULL ? sc->o->background_image + 3 * p : sc->o->background;
        rgb_bh[0] = bg[0];
        rgb_bh[1] = bg[1];
        rgb_bh[2] = bg[2];
        a_bh = (ls_real)0;
    }
    return ((g[0] * (rgb_in[0] - rgb_bh[0]) + g[1] * (rgb_in[1] - rgb_bh[1])) + g[2] * (rgb_in[2] - rgb_bh[2])) +
           g[3] * ((ls_real)1 - a_bh);
}

/* Window position of a vertex from its clip coordinates. */
static void window_of(const sctx *sc, const ls_real *cl, ls_real w[2])
{
    w[0] = (cl[0] / cl[3] + (ls_real)1) * sc->width * (ls_real)0.5;
    w[1] = ((ls_real)1 - cl[1] / cl[3]) * sc->height * (ls_real)0.5;
}

/* Liang-Barsky clip of a + t e, t in [*t0, *t1], to [0, width] x [0, height]. */
static int clip_rect(const sctx *sc, const ls_real a[2], const ls_real e[2], ls_real *t0, ls_real *t1)
{
    ls_real p[4], q[4];
    int k;
    p[0] = -e[0];
    q[0] = a[0];
    p[1] = e[0];
    q[1] = sc->width - a[0];
    p[2] = -e[1];
    q[2] = a[1];
    p[3] = e[1];
    q[3] = sc->height - a[1];
    for (k = 0; k < 4; k++) {
        if (p[k] == (ls_real)0) {
            if (q[k] < (ls_real)0) return 0;
        } else {
            ls_real r = q[k] / p[k];
            if (p[k] < (ls_real)0) {
                if (r > *t0) *t0 = r;
            } else if (r < *t1) {
                *t1 = r;
            }
        }
    }
    return *t0 < *t1;
}

/* Grid-line crossings of one coordinate along the edge: the lines
 * k = first, first + step, ... (count of them) at t = (k - a) / e. */
typedef struct lines {
    ls_real k, step, a, e;
    int32_t left;
} lines;

static void lines_init(lines *l, ls_real a, ls_real e, ls_real t0, ls_real t1)
{
    ls_real s = a + t0 * e, f = a + t1 * e, lo = s < f ? s : f, hi = s < f ? f : s;
    ls_real first = LS_RFLOOR(lo) + (ls_real)1, last = -LS_RFLOOR(-hi) - (ls_real)1;
    l->a = a;
    l->e = e;
    l->left = 0;
    if (e == (ls_real)0 || last < first) return;
    l->left = LS_RTO_I32(last - first) + 1;
    l->step = e > (ls_real)0 ? (ls_real)1 : (ls_real)-1;
    l->k = e > (ls_real)0 ? first : last;
}

static ls_real lines_next(const lines *l, ls_real t_end)
{
    return l->left > 0 ? (l->k - l->a) / l->e : t_end;
}

static uint32_t pixel_of(ls_real v, uint32_t n)
{
    ls_real f = LS_RFLOOR(v);
    int32_t i = LS_RTO_I32(f);
    if (i < 0) return 0;
    if ((uint32_t)i >= n) return n - 1u;
    return (uint32_t)i;
}

/* dL/d(X, Y, Z, W) of a clip-space point cl from window-space dL/d(x, y). */
static void window_to_clip(const sctx *sc, const ls_real *cl, ls_real gx, ls_real gy, ls_real g[4])
{
    g[0] = gx * sc->width / ((ls_real)2 * cl[3]);
    g[1] = -(gy * sc->height / ((ls_real)2 * cl[3]));
    g[2] = (ls_real)0;
    g[3] = -(g[0] * cl[0] + g[1] * cl[1]) / cl[3];
}

/* Adds clip-space gradient g of vertex v into the positions (through mvp). */
static void clip_to_positions(const sctx *sc, uint32_t v, const ls_real g[4], ls_real *gp)
{
    ls_real *d = gp + 3 * (size_t)v;
    int c;
    for (c = 0; c < 3; c++) d[c] += ((sc->m[c] * g[0] + sc->m[4 + c] * g[1]) + sc->m[8 + c] * g[2]) + sc->m[12 + c] * g[3];
}

/* Homogeneous orientation det[A; B; C] over (X, Y, W): for A and B in
 * front of the eye its sign says on which side of the screen line A B the
 * face through C lies near the edge, wherever C is (even behind the eye). */
static ls_real hdet(const ls_real *a, const ls_real *b, const ls_real *c)
{
    return (a[0] * (b[1] * c[3] - b[3] * c[1]) - a[1] * (b[0] * c[3] - b[3] * c[0])) +
           a[3] * (b[0] * c[1] - b[1] * c[0]);
}

/* Endpoint of an edge clipped at the near plane Z + W = 0: the point
 * p + s (q - p), s = dp / (dp - dq), written to out. */
static void near_point(const ls_real *p, const ls_real *q, ls_real s, ls_real out[4])
{
    int r;
    for (r = 0; r < 4; r++) out[r] = p[r] + s * (q[r] - p[r]);
}

/* Sends the gradient g (clip space) of the clipped endpoint p + s (q - p),
 * s = dp / (dp - dq) with d = Z + W, to the vertices vp and vq. */
static void clipped_to_positions(const sctx *sc, uint32_t vp, uint32_t vq, ls_real s, const ls_real g[4], ls_real *gp)
{
    const ls_real *p = sc->vis->clip + 4 * (size_t)vp, *q = sc->vis->clip + 4 * (size_t)vq;
    ls_real dp = p[2] + p[3], dq = q[2] + q[3], den = dp - dq, gs, ds_dp, ds_dq, a[4], b[4];
    int r;
    gs = (g[0] * (q[0] - p[0]) + g[1] * (q[1] - p[1])) + (g[2] * (q[2] - p[2]) + g[3] * (q[3] - p[3]));
    ds_dp = -dq / (den * den);
    ds_dq = dp / (den * den);
    for (r = 0; r < 4; r++) {
        a[r] = ((ls_real)1 - s) * g[r];
        b[r] = s * g[r];
    }
    a[2] += gs * ds_dp; /* d = Z + W */
    a[3] += gs * ds_dp;
    b[2] += gs * ds_dq;
    b[3] += gs * ds_dq;
    clip_to_positions(sc, vp, a, gp);
    clip_to_positions(sc, vq, b, gp);
}

/* One silhouette edge va -> vb of face ft (third vertex vc), twin face fu. */
static void edge_pass(const sctx *sc, uint32_t ft, uint32_t fu, uint32_t va, uint32_t vb, uint32_t vc, ls_real boost,
                      ls_real *gp)
{
    static const ls_real xi[3] = {(ls_real)-0.77459666924148337704, (ls_real)0, (ls_real)0.77459666924148337704};
    static const ls_real wq[3] = {(ls_real)0.55555555555555555556, (ls_real)0.88888888888888888889,
                                  (ls_real)0.55555555555555555556};
    const ls_real *A = sc->vis->clip + 4 * (size_t)va, *B = sc->vis->clip + 4 * (size_t)vb;
    const ls_real *C = sc->vis->clip + 4 * (size_t)vc;
    ls_real ca[4], cb[4], a[2], b[2], e[2], nrm[2], t0 = (ls_real)0, t1 = (ls_real)1, tcur, ka = (ls_real)0;
    ls_real kb = (ls_real)0, da = A[2] + A[3], db = B[2] + B[3], sa = (ls_real)0, sb = (ls_real)1, side, g[4];
    lines lx, ly;
    int r;
    if (da < (ls_real)0 && db < (ls_real)0) return; /* behind the near plane */
    if (da < (ls_real)0) {
        sa = da / (da - db);
        near_point(A, B, sa, ca);
    } else {
        for (r = 0; r < 4; r++) ca[r] = A[r];
    }
    if (db < (ls_real)0) {
        sb = db / (db - da);
        near_point(B, A, sb, cb);
    } else {
        for (r = 0; r < 4; r++) cb[r] = B[r];
    }
    if (!(ca[3] > (ls_real)0) || !(cb[3] > (ls_real)0)) return;
    window_of(sc, ca, a);
    window_of(sc, cb, b);
    e[0] = b[0] - a[0];
    e[1] = b[1] - a[1];
    /* normal scaled by |e|, pointing away from the face's side: window y
     * runs down, so the window-space side is minus the homogeneous one */
    side = -hdet(ca, cb, C);
    if (side == (ls_real)0 || side - side != (ls_real)0) return;
    nrm[0] = e[1];
    nrm[1] = -e[0];
    /* (e1, -e0) . (c - a) = -(e x (c - a)): it points towards the face when side < 0 */
    if (side < (ls_real)0) {
        nrm[0] = -nrm[0];
        nrm[1] = -nrm[1];
    }
    if (!clip_rect(sc, a, e, &t0, &t1)) return;
    lines_init(&lx, a[0], e[0], t0, t1);
    lines_init(&ly, a[1], e[1], t0, t1);
    tcur = t0;
    while (tcur < t1) {
        ls_real tx = lines_next(&lx, t1), ty = lines_next(&ly, t1), tn = t1, mid, half;
        uint32_t px, py;
        size_t p;
        int q;
        if (tx < tn) tn = tx;
        if (ty < tn) tn = ty;
        if (tx <= tn && lx.left > 0) {
            lx.left--;
            lx.k += lx.step;
        }
        if (ty <= tn && ly.left > 0) {
            ly.left--;
            ly.k += ly.step;
        }
        if (tn <= tcur) continue; /* a crossing at (or before) the current point */
        mid = (tcur + tn) * (ls_real)0.5;
        half = (tn - tcur) * (ls_real)0.5;
        px = pixel_of(a[0] + mid * e[0], sc->vis->width);
        py = pixel_of(a[1] + mid * e[1], sc->vis->height);
        p = (size_t)py * sc->vis->width + px;
        for (q = 0; q < 3; q++) {
            ls_real t = mid + half * xi[q];
            ls_real term = point_term(sc, ft, fu, a[0] + t * e[0], a[1] + t * e[1], p) * half * wq[q];
            ka += ((ls_real)1 - t) * term;
            kb += t * term;
        }
        tcur = tn;
    }
    ka *= boost;
    kb *= boost;
    window_to_clip(sc, ca, nrm[0] * ka, nrm[1] * ka, g);
    if (da < (ls_real)0)
        clipped_to_positions(sc, va, vb, sa, g, gp);
    else
        clip_to_positions(sc, va, g, gp);
    window_to_clip(sc, cb, nrm[0] * kb, nrm[1] * kb, g);
    if (db < (ls_real)0)
        clipped_to_positions(sc, vb, va, sb, g, gp);
    else
        clip_to_positions(sc, vb, g, gp);
}

ls_status ls_silhouette_backward(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                 uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                 const ls_shade_opts *opts, const ls_real mvp[16], ls_real boost,
                                 const ls_real *grad_image, ls_real *grad_positions, ls_diag *diag)
{
    sctx sc;
    uint32_t t, h;
    if (vis == NULL || table == NULL || opts == NULL || mvp == NULL || grad_image == NULL || grad_positions == NULL)
        return LS_ERR_INVALID;
    if (vis->tri == NULL || vis->clip == NULL || table->magic != EDGE_TABLE_MAGIC) return LS_ERR_STATE;
    if (vis->triangle_count != triangle_count || vis->vertex_count != vertex_count ||
        table->triangle_count != triangle_count || table->vertex_count != vertex_count)
        return LS_ERR_INVALID;
    if (opts->mode > LS_SHADE_COLOR || (triangle_count > 0 && indices == NULL)) return LS_ERR_INVALID;
    if ((opts->mode == LS_SHADE_SH || opts->mode == LS_SHADE_LAMBERT) && normals == NULL) return LS_ERR_INVALID;
    if (opts->mode == LS_SHADE_SH && opts->sh == NULL) return LS_ERR_INVALID;
    if (opts->mode == LS_SHADE_LAMBERT && opts->light_count > 0 && opts->lights == NULL) return LS_ERR_INVALID;
    if (opts->mode == LS_SHADE_COLOR && opts->vertex_colors == NULL) return LS_ERR_INVALID;
    for (t = 0; t < triangle_count; t++) {
        const uint32_t *f = indices + 3 * (size_t)t;
        if (f[0] >= vertex_count || f[1] >= vertex_count || f[2] >= vertex_count)
            return face_error(diag, t, "triangle vertex index out of range");
    }
    sc.vis = vis;
    sc.indices = indices;
    sc.normals = normals;
    sc.o = opts;
    sc.m = mvp;
    sc.gimg = grad_image;
    sc.triangle_count = triangle_count;
    sc.width = (ls_real)vis->width;
    sc.height = (ls_real)vis->height;
    for (h = 0; h < 3u * triangle_count; h++) {
        uint32_t ft = h / 3u, k = h % 3u, tw = table->twin[h], fu = LS_EDGE_NONE;
        const uint32_t *f = indices + 3 * (size_t)ft;
        uint32_t va = f[k], vb = f[(k + 1u) % 3u], vc = f[(k + 2u) % 3u];
        if (tw != LS_EDGE_NONE) {
            const uint32_t *g = indices + 3 * (size_t)(tw / 3u);
            uint32_t vd = g[(tw % 3u + 2u) % 3u];
            ls_real sc_, sd_;
            if (tw < h) continue; /* each edge once */
            /* c and d on the same side of the edge: one face front-, one back-facing */
            sc_ = hdet(vis->clip + 4 * (size_t)va, vis->clip + 4 * (size_t)vb, vis->clip + 4 * (size_t)vc);
            sd_ = hdet(vis->clip + 4 * (size_t)va, vis->clip + 4 * (size_t)vb, vis->clip + 4 * (size_t)vd);
            if (!((sc_ > (ls_real)0 && sd_ > (ls_real)0) || (sc_ < (ls_real)0 && sd_ < (ls_real)0))) continue;
            fu = tw / 3u;
        }
        edge_pass(&sc, ft, fu, va, vb, vc, boost, grad_positions);
    }
    return LS_OK;
}
