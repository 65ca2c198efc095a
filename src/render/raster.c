/* raster.c - deterministic tile rasterizer producing the visibility buffer:
 * sizing, the count pass, the tiles and the drawing of triangles into samples.
 * Design and conventions: include/largesteps/raster.h. */
#include "raster_internal.h"

static int finite_r(ls_real x)
{
    return x - x == x - x;
}

static ls_status check_dims(uint32_t width, uint32_t height, uint32_t ss)
{
    if (width == 0 || height == 0 || (ss != 1 && ss != 2 && ss != 4)) return LS_ERR_INVALID;
    if (width > LS_RASTER_MAX_DIM / ss || height > LS_RASTER_MAX_DIM / ss) return LS_ERR_INVALID;
    return LS_OK;
}

ls_status ls_check_triangle_indices(const uint32_t *indices, uint32_t triangle_count, uint32_t vertex_count,
                                    ls_diag *diag)
{
    size_t i = 0, j, n = 3 * (size_t)triangle_count;
    uint32_t t, all = 0xffffffffu;
    /* whether any index may be out of range first, without a branch per
     * index, in blocks of a fixed count, which compilers vectorize at -O2:
     * with vertex_count <= 2^31, an index is below it exactly when its top
     * bit is clear and (index - vertex_count) mod 2^32 has it set, so every
     * index is in range when the and of ~index & (index - vertex_count)
     * over all has it set (an index out of range always clears it; with
     * more vertices an index in range may too: the loop below decides) */
    for (; i + 64u <= n; i += 64u) {
        uint32_t b = 0xffffffffu;
        for (j = 0; j < 64u; j++) b &= ~indices[i + j] & (indices[i + j] - vertex_count);
        all &= b;
    }
    for (; i < n; i++) all &= ~indices[i] & (indices[i] - vertex_count);
    for (t = 0; (all >> 31) == 0 && t < triangle_count; t++) { /* the first triangle out of range */
        const uint32_t *f = indices + 3 * (size_t)t;
        if (f[0] >= vertex_count || f[1] >= vertex_count || f[2] >= vertex_count)
            return ls_diag_set(diag, LS_ERR_MESH, "triangle vertex index out of range", t);
    }
    return LS_OK;
}

ls_real ls_clip_barycentric(const ls_real *clip, const uint32_t *f, ls_real px, ls_real py, ls_real u[3],
                            ls_real v[3], ls_real b[3])
{
    ls_real a[3], sum;
    int k;
    ls_clip_areas(clip, f, px, py, u, v, a);
    sum = (a[0] + a[1]) + a[2];
    if (!(sum != (ls_real)0) || sum - sum != (ls_real)0) return (ls_real)0;
    for (k = 0; k < 3; k++) b[k] = a[k] / sum;
    return sum;
}

static ls_status validate(const ls_real mvp[16], const ls_real *positions, uint32_t vertex_count,
                          const uint32_t *indices, uint32_t triangle_count, ls_diag *diag)
{
    int i;
    if (mvp == NULL) return ls_invalid_arg(diag, "view->mvp is NULL");
    if (vertex_count > 0 && positions == NULL)
        return ls_invalid_arg(diag, "view->positions is NULL with vertex_count > 0");
    if (triangle_count > 0 && indices == NULL)
        return ls_invalid_arg(diag, "view->indices is NULL with triangle_count > 0");
    if (triangle_count > UINT32_MAX - 1u) return LS_ERR_TOO_LARGE;
    for (i = 0; i < 16; i++) {
        if (!finite_r(mvp[i])) {
            if (diag != NULL) {
                diag->status = LS_ERR_NONFINITE;
                diag->has_value = 1;
                diag->value = mvp[i];
                diag->what = "non-finite entry in the clip transform";
            }
            return LS_ERR_NONFINITE;
        }
    }
    return ls_check_triangle_indices(indices, triangle_count, vertex_count, diag);
}

static ls_status nonfinite_vertex(uint32_t i, ls_diag *diag)
{
    if (diag != NULL) {
        diag->status = LS_ERR_NONFINITE;
        diag->has_index = 1;
        diag->index = i;
        diag->what = "vertex with non-finite clip coordinates";
    }
    return LS_ERR_NONFINITE;
}

/* Scratch layout of ls_raster, shared by the queries. */
static void scratch_size(ls_size *s, uint32_t vertex_count, uint32_t triangle_count, size_t tiles, size_t entries)
{
    ls_size_add(s, vertex_count, VERT_BYTES);
    ls_size_add(s, tiles + 1, sizeof(size_t));
    ls_size_add(s, 1, sizeof(clipbuf));
    ls_size_add(s, triangle_count, 4 * sizeof(uint16_t));
    ls_size_add(s, entries, sizeof(uint32_t));
}

ls_status ls_vis_bytes(uint32_t width, uint32_t height, uint32_t ss, uint32_t max_vertices, size_t *bytes)
{
    ls_size s;
    size_t n;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    st = check_dims(width, height, ss);
    if (st != LS_OK) return st;
    n = (size_t)(width * ss) * (size_t)(height * ss); /* <= 2^26 */
    ls_size_init(&s);
    ls_size_add(&s, n, sizeof(uint32_t));
    ls_size_add(&s, n, 2 * sizeof(ls_real));
    ls_size_add(&s, n, sizeof(ls_real));
    ls_size_add(&s, max_vertices, 4 * sizeof(ls_real));
    ls_size_add(&s, max_vertices, 2 * sizeof(int32_t));
    ls_size_add(&s, max_vertices, sizeof(uint32_t));
    ls_size_add(&s, ((size_t)(width * ss + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2) *
                        ((size_t)(height * ss + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2),
                sizeof(uint8_t));
    return ls_size_get(&s, bytes);
}

static void vis_clear(ls_vis *vis)
{
    size_t n = (size_t)vis->sw * vis->sh, i;
    memset(vis->tri, 0, n * sizeof *vis->tri);
    for (i = 0; i < 2 * n; i++) vis->bary[i] = (ls_real)0;
    for (i = 0; i < n; i++) vis->depth[i] = (ls_real)1;
}

ls_status ls_vis_init(ls_vis *vis, ls_arena *arena, uint32_t width, uint32_t height, uint32_t ss,
                      uint32_t max_vertices)
{
    size_t bytes, n, tiles;
    ls_status st;
    ls_arena_mark mark;
    ls_vis v;
    if (vis == NULL || arena == NULL) return LS_ERR_INVALID;
    st = ls_vis_bytes(width, height, ss, max_vertices, &bytes);
    if (st != LS_OK) return st;
    memset(&v, 0, sizeof v);
    v.width = width;
    v.height = height;
    v.ss = ss;
    v.sw = width * ss;
    v.sh = height * ss;
    v.vertex_capacity = max_vertices;
    n = (size_t)v.sw * v.sh;
    mark = ls_arena_save(arena);
    v.tri = (uint32_t *)ls_arena_alloc(arena, n, sizeof(uint32_t));
    v.bary = v.tri ? (ls_real *)ls_arena_alloc(arena, n, 2 * sizeof(ls_real)) : NULL;
    v.depth = v.bary ? (ls_real *)ls_arena_alloc(arena, n, sizeof(ls_real)) : NULL;
    v.clip = v.depth ? (ls_real *)ls_arena_alloc(arena, max_vertices, 4 * sizeof(ls_real)) : NULL;
    v.snap = v.clip ? (int32_t *)ls_arena_alloc(arena, max_vertices, 2 * sizeof(int32_t)) : NULL;
    v.vflags = v.snap ? (uint32_t *)ls_arena_alloc(arena, max_vertices, sizeof(uint32_t)) : NULL;
    tiles = ((size_t)(v.sw + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2) *
            ((size_t)(v.sh + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2);
    v.tile_dirty = v.vflags ? (uint8_t *)ls_arena_alloc_zero(arena, tiles, sizeof(uint8_t)) : NULL;
    if (v.tile_dirty == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    vis_clear(&v);
    v.magic = VIS_MAGIC;
    *vis = v;
    return LS_OK;
}

ls_status ls_raster_scratch_bytes_bound(uint32_t width, uint32_t height, uint32_t ss, uint32_t vertex_count,
                                        uint32_t triangle_count, size_t *bytes)
{
    ls_size s;
    size_t tiles, entries;
    ls_status st;
    uint32_t tx, ty;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    st = check_dims(width, height, ss);
    if (st != LS_OK) return st;
    tx = (width * ss + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2;
    ty = (height * ss + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2;
    tiles = (size_t)tx * ty;
    st = ls_size_mul(tiles, triangle_count, &entries);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    scratch_size(&s, vertex_count, triangle_count, tiles, entries);
    return ls_size_get(&s, bytes);
}

/* Arguments of the count pass (few arguments: no stack-passed ones). */
typedef struct cpass {
    const vbuf *vb;           /* transformed vertices, or NULL: transform on the fly */
    const ls_real *positions;
    const uint32_t *indices;
    uint32_t triangle_count;
    uint32_t clipped;         /* out: triangles that needed clipping */
    size_t *counts;           /* out, optional: tile counts (added to) */
    uint16_t *rects;          /* out, optional: each triangle's sample range x0, y0, x1, y1
                                 (< LS_RASTER_MAX_DIM; x0 > x1 when it covers nothing;
                                 RECT_DIRECT set in x0 when it is drawn unbinned) */
    size_t entries;           /* out: total tile-list entries */
} cpass;

/* Count pass over the triangles: adds each triangle's tiles to counts and the
 * total to entries. */
LS_NOINLINE static ls_status count_pass(const rctx *cx, clipbuf *cb, cpass *cp)
{
    uint32_t t;
    size_t total = 0;
    /* set by ls_rast_transform_all for validated vertices; zeroed, as the analyzer
     * cannot tell (once a call, not once a triangle) */
    ls_real lclip[12] = {0}, lzi[6] = {0};
    int32_t lsnap[6] = {0};
    uint32_t lflags[3] = {0, 0, 0};
    vbuf local;
    const vbuf *vb;
    local.clip = lclip;
    local.zi = lzi;
    local.snap = lsnap;
    local.flags = lflags;
    vb = cp->vb != NULL ? cp->vb : &local;
    cp->clipped = 0;
    for (t = 0; t < cp->triangle_count; t++) {
        const uint32_t *f = cp->indices + 3 * (size_t)t;
        size_t v[3];
        sbox sb, tb;
        size_t n;
        int ok, direct;
        if (cp->vb != NULL) {
            v[0] = f[0];
            v[1] = f[1];
            v[2] = f[2];
        } else {
            (void)ls_rast_transform_all(cx, cp->positions, f, 3, &local); /* validated before */
            v[0] = 0;
            v[1] = 1;
            v[2] = 2;
        }
        direct = 0;
        if (vb->flags[v[0]] | vb->flags[v[1]] | vb->flags[v[2]]) {
            cp->clipped++;
            ok = ls_rast_clipped_box(cx, vb, v, cb, &sb);
        } else {
            ok = unclipped_box(cx, vb->snap, v, &sb);
            direct = ok && box_direct(&sb);
        }
        if (!ok) {
            if (cp->rects != NULL) { /* an empty range, every field set (valgrind) */
                cp->rects[4 * (size_t)t] = 1;
                cp->rects[4 * (size_t)t + 1] = 1;
                cp->rects[4 * (size_t)t + 2] = 0;
                cp->rects[4 * (size_t)t + 3] = 0;
            }
            continue;
        }
        if (cp->rects != NULL) {
            cp->rects[4 * (size_t)t] = (uint16_t)((uint32_t)sb.x0 | (direct ? RECT_DIRECT : 0u));
            cp->rects[4 * (size_t)t + 1] = (uint16_t)sb.y0;
            cp->rects[4 * (size_t)t + 2] = (uint16_t)sb.x1;
            cp->rects[4 * (size_t)t + 3] = (uint16_t)sb.y1;
        }
        if (direct) continue;
        tb.x0 = sb.x0 >> LS_RASTER_TILE_LOG2; /* non-negative after clamping */
        tb.y0 = sb.y0 >> LS_RASTER_TILE_LOG2;
        tb.x1 = sb.x1 >> LS_RASTER_TILE_LOG2;
        tb.y1 = sb.y1 >> LS_RASTER_TILE_LOG2;
        n = (size_t)(tb.x1 - tb.x0 + 1) * (size_t)(tb.y1 - tb.y0 + 1);
        if (total > SIZE_MAX - n) return LS_ERR_TOO_LARGE;
        total += n;
        if (cp->counts != NULL) {
            int64_t tx, ty;
            for (ty = tb.y0; ty <= tb.y1; ty++)
                for (tx = tb.x0; tx <= tb.x1; tx++) cp->counts[(size_t)ty * cx->tiles_x + (size_t)tx]++;
        }
    }
    cp->entries = total;
    return LS_OK;
}

/* The clip buffer (768 bytes in double) lives in this helper's frame rather
 * than in its caller's, so no frame passes the 1024-byte limit on s390x,
 * whose frames also carry a 160-byte register save area. */
LS_NOINLINE static ls_status count_pass_local(const rctx *cx, cpass *cp)
{
    clipbuf cb;
    return count_pass(cx, &cb, cp);
}

static ls_status raster_scratch_bytes_impl(const ls_vis *vis, const ls_real mvp[16], const ls_real *positions,
                                           uint32_t vertex_count, const uint32_t *indices, uint32_t triangle_count,
                                           size_t *bytes)
{
    rctx cx;
    ls_size s;
    cpass cp;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (vis == NULL || vis->magic != VIS_MAGIC) return LS_ERR_STATE;
    if (vertex_count > vis->vertex_capacity) return LS_ERR_INVALID;
    st = validate(mvp, positions, vertex_count, indices, triangle_count, NULL);
    if (st != LS_OK) return st;
    ls_rast_ctx_init(&cx, mvp, vis->sw, vis->sh);
    {
        ls_real c[4], zi[2];
        int32_t sn[2];
        uint32_t fl, i;
        vbuf one;
        one.clip = c;
        one.zi = zi;
        one.snap = sn;
        one.flags = &fl;
        for (i = 0; i < vertex_count; i++)
            if (ls_rast_transform_all(&cx, positions + 3 * (size_t)i, NULL, 1, &one) == 0) return LS_ERR_NONFINITE;
    }
    memset(&cp, 0, sizeof cp);
    cp.positions = positions;
    cp.indices = indices;
    cp.triangle_count = triangle_count;
    st = count_pass_local(&cx, &cp);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    scratch_size(&s, vertex_count, triangle_count, (size_t)cx.tiles_x * cx.tiles_y, cp.entries);
    return ls_size_get(&s, bytes);
}

ls_status ls_raster_scratch_bytes(const ls_vis *vis, const ls_view *view, size_t *bytes)
{
    if (view == NULL) return LS_ERR_INVALID;
    return raster_scratch_bytes_impl(vis, view->mvp, view->positions, view->vertex_count, view->indices, view->triangle_count, bytes);
}

/* The number of steps along a row before an edge value e, which changes by
 * -step per sample, becomes >= 0: 0 when it already is, INT64_MAX when it
 * never does (it does not grow along the row). */
static int64_t first_nonneg(int64_t e, int64_t step)
{
    uint64_t num, den;
    if (e >= 0) return 0;
    if (step >= 0) return INT64_MAX;
    num = (uint64_t)(-e) + (uint64_t)(-step) - 1u; /* ceil(-e / -step) */
    den = (uint64_t)(-step);
    if (num <= UINT32_MAX) return (int64_t)((uint32_t)num / (uint32_t)den); /* small triangles: a faster divide */
    return (int64_t)(num / den);
}

/* Rows at most this many samples wide find their first inside sample by
 * stepping rather than by first_nonneg's divisions (the same sample). */
#define NARROW_ROW 4

/* What drawing a screen triangle's samples takes besides its edge values. */
typedef struct dconst {
    ls_real z0, dz1, dz2, w0, w1, w2, c00, c10, c20, c01, c11, c21;
    uint32_t idp; /* id + 1 */
} dconst;

/* The constants of a screen triangle with the given depths zw, 1/W iw,
 * weights c, twice-area and id. */
static inline void dconst_init(dconst *k, const ls_real zw[3], const ls_real iw[3], const ls_real c[3][2], int64_t area,
                               uint32_t id)
{
    const ls_real inv_area = (ls_real)1 / (ls_real)area;
    /* depth = zw0 + e1 (zw1 - zw0) / area + e2 (zw2 - zw0) / area */
    k->z0 = zw[0];
    k->dz1 = (zw[1] - zw[0]) * inv_area;
    k->dz2 = (zw[2] - zw[0]) * inv_area;
    k->w0 = iw[0];
    k->w1 = iw[1];
    k->w2 = iw[2];
    k->c00 = c[0][0];
    k->c10 = c[1][0];
    k->c20 = c[2][0];
    k->c01 = c[0][1];
    k->c11 = c[1][1];
    k->c21 = c[2][1];
    k->idp = id + 1u;
}

/* Draws sample s, covered, whose exact edge functions (without the fill
 * rule's bias) are e0, e1, e2, when it is nearer than what the sample holds
 * or as near with an id not above its own. */
static inline void draw_sample(uint32_t *tri, ls_real *depth, ls_real *bary, size_t s, const dconst *k, int64_t e0,
                               int64_t e1, int64_t e2)
{
    const ls_real f1 = (ls_real)e1, f2 = (ls_real)e2, d = k->z0 + (f1 * k->dz1 + f2 * k->dz2);
    const ls_real cd = depth[s];
    /* an empty sample (id + 1 = 0) holds depth 1 and, as cur - 1 wraps to
     * UINT32_MAX, every id is below it: this is "d <= 1 and (empty, or
     * nearer, or as near with an id not above)", as a drawn sample's depth
     * is <= 1 (a NaN d fails either way) */
    if (d < cd || (d == cd && k->idp - 1u <= tri[s] - 1u)) {
        ls_real f0 = (ls_real)e0;
        ls_real q0 = f0 * k->w0, q1 = f1 * k->w1, q2 = f2 * k->w2;
        ls_real rq = (ls_real)1 / ((q0 + q1) + q2);
        tri[s] = k->idp;
        depth[s] = d;
        bary[2 * s] = (q0 * k->c00 + q1 * k->c10 + q2 * k->c20) * rq;
        bary[2 * s + 1] = (q0 * k->c01 + q1 * k->c11 + q2 * k->c21) * rq;
    }
}

/* Draws one screen triangle into the samples of box b (inclusive, inside
 * the grid and the triangle's own box). */
LS_NOINLINE static void draw_stri(ls_vis *vis, const stri *t, const sbox *b, uint32_t id)
{
    edgef g[3];
    dconst k;
    const int64_t last = b->x1 - b->x0;
    /* locals, so that the stores into the buffers cannot force reloads */
    uint32_t *tri = vis->tri;
    ls_real *depth = vis->depth, *bary = vis->bary;
    const size_t sw = vis->sw;
    dconst_init(&k, t->zw, t->iw, (const ls_real(*)[2])t->b, t->area, id);
    edges_init(g, t->x, t->y, b->x0, b->y0);
    {
        const int64_t sx0 = g[0].dx, sx1 = g[1].dx, sx2 = g[2].dx, b0 = g[0].bias, b1 = g[1].bias, b2 = g[2].bias;
        int64_t i, j, r0 = g[0].e, r1 = g[1].e, r2 = g[2].e;
        for (j = b->y0; j <= b->y1; j++, r0 += g[0].dy, r1 += g[1].dy, r2 += g[2].dy) {
            /* the first sample of the row where every edge is >= 0 (exact
             * integer arithmetic: the samples drawn are the same as testing
             * them all); past the row when there is none */
            int64_t e0 = r0, e1 = r1, e2 = r2, skip = 0;
            size_t s;
            if (last < NARROW_ROW) {
                while (skip <= last && (e0 | e1 | e2) < 0) {
                    skip++;
                    e0 -= sx0;
                    e1 -= sx1;
                    e2 -= sx2;
                }
            } else {
                int64_t k0 = first_nonneg(r0, sx0), k1 = first_nonneg(r1, sx1), k2 = first_nonneg(r2, sx2);
                skip = k0 > k1 ? k0 : k1;
                if (k2 > skip) skip = k2;
                if (skip > last) skip = last + 1;
                e0 -= skip * sx0;
                e1 -= skip * sx1;
                e2 -= skip * sx2;
            }
            s = (size_t)j * sw + (size_t)(b->x0 + skip);
            for (i = skip; i <= last; i++, s++, e0 -= sx0, e1 -= sx1, e2 -= sx2) {
                /* from `skip` on, the edges whose value grows along the row are
                 * all >= 0: the first negative value is on an edge that only
                 * decreases, so the rest of the row is outside too */
                if ((e0 | e1 | e2) < 0) break;
                draw_sample(tri, depth, bary, s, &k, e0 - b0, e1 - b1, e2 - b2);
            }
        }
    }
}

/* The drawing constants of unclipped triangle v (in vb) of signed twice-area
 * a (!= 0) and id, as positively oriented. */
static inline void unclipped_dconst(dconst *k, const vbuf *vb, const size_t v[3], int64_t a, uint32_t id)
{
    const size_t o1 = a > 0 ? v[1] : v[2], o2 = a > 0 ? v[2] : v[1];
    ls_real zw[3], iw[3];
    zw[0] = vb->zi[2 * v[0]];
    iw[0] = vb->zi[2 * v[0] + 1];
    zw[1] = vb->zi[2 * o1];
    iw[1] = vb->zi[2 * o1 + 1];
    zw[2] = vb->zi[2 * o2];
    iw[2] = vb->zi[2 * o2 + 1];
    dconst_init(k, zw, iw, unit_b[a < 0], a > 0 ? a : -a, id);
}

/* Tiles per row of the vis's sample grid. */
static inline size_t tiles_across(const ls_vis *vis)
{
    return ((size_t)vis->sw + LS_RASTER_TILE - 1u) >> LS_RASTER_TILE_LOG2;
}

/* Marks the tiles of box b (at most a tile wide and high: those of its
 * corners) dirty. */
static inline void mark_tiles(ls_vis *vis, const sbox *b)
{
    const size_t tiles_x = tiles_across(vis);
    const size_t r0 = (size_t)(b->y0 >> LS_RASTER_TILE_LOG2) * tiles_x;
    const size_t r1 = (size_t)(b->y1 >> LS_RASTER_TILE_LOG2) * tiles_x;
    const size_t c0 = (size_t)(b->x0 >> LS_RASTER_TILE_LOG2), c1 = (size_t)(b->x1 >> LS_RASTER_TILE_LOG2);
    uint8_t *d = vis->tile_dirty;
    d[r0 + c0] = 1;
    d[r0 + c1] = 1;
    d[r1 + c0] = 1;
    d[r1 + c1] = 1;
}

/* Draws the one sample of box b, covered by unclipped triangle v (in vb) of
 * signed twice-area a with edge values e. */
LS_NOINLINE static void draw_one(ls_vis *vis, const vbuf *vb, const size_t v[3], int64_t a, const sbox *b,
                                 const int64_t e[3], uint32_t id)
{
    dconst k;
    unclipped_dconst(&k, vb, v, a, id);
    draw_sample(vis->tri, vis->depth, vis->bary, (size_t)b->y0 * vis->sw + (size_t)b->x0, &k, e[0], e[1], e[2]);
    /* mark_tiles of a one-sample box: its one tile */
    vis->tile_dirty[(size_t)(b->y0 >> LS_RASTER_TILE_LOG2) * tiles_across(vis) + (size_t)(b->x0 >> LS_RASTER_TILE_LOG2)] = 1;
}

/* Draws unclipped triangle v (in vb) into the samples of box b (inclusive,
 * inside the grid and the triangle's own box) of at most DRAW_SMALL samples,
 * sample by sample. */
LS_NOINLINE static void draw_small(ls_vis *vis, const vbuf *vb, const size_t v[3], const sbox *b, uint32_t id)
{
    int32_t x[3], y[3];
    dconst k;
    int64_t e[3], area, a = unclipped_load(vb->snap, v, x, y);
    if (a == 0) return;
    orient(x, y, a);
    area = a > 0 ? a : -a;
    if (b->x0 == b->x1 && b->y0 == b->y1) { /* one sample: no loop set-up */
        if (sample_edges(x, y, area, b->x0, b->y0, e)) draw_one(vis, vb, v, a, b, e, id);
        return;
    }
    {
        /* sample_edges' values stepped along the box (exact integers: the
         * same values), and its test of them */
        const int64_t px0 = b->x0 * SUB_ONE + SUB_HALF, py0 = b->y0 * SUB_ONE + SUB_HALF;
        const int64_t ax1 = (int64_t)x[0] - x[2], ay1 = (int64_t)y[0] - y[2];
        const int64_t ax2 = (int64_t)x[1] - x[0], ay2 = (int64_t)y[1] - y[0];
        const int64_t sx1 = ay1 * SUB_ONE, sx2 = ay2 * SUB_ONE, sy1 = ax1 * SUB_ONE, sy2 = ax2 * SUB_ONE;
        const size_t sw = vis->sw;
        int64_t r1 = ax1 * (py0 - y[2]) - ay1 * (px0 - x[2]);
        int64_t r2 = ax2 * (py0 - y[0]) - ay2 * (px0 - x[0]);
        const int64_t w = b->x1 - b->x0 + 1, n = w * (b->y1 - b->y0 + 1), r10 = r1, r20 = r2;
        int64_t e1 = r1, e2 = r2, q, col = 0, row = 0, m = 0;
        /* the covered samples' row and column in the box; zeroed (24 bytes)
         * because the analyzer cannot tell that those read were written */
        unsigned char crow[DRAW_SMALL] = {0}, ccol[DRAW_SMALL] = {0};
        /* One pass over the box's samples in row order, without a branch per
         * sample (coverage of such small triangles has no pattern, and its
         * tests mispredicted): the covered ones are gathered (each sample is
         * written at slot m, which advances when it is covered; the
         * top-left rule's test, for a sample on an edge, is rare), then
         * drawn in the same order with their edge values formed again
         * (exact integers: the same values). */
        for (q = 0; q < n; q++) {
            const int64_t e0 = area - e1 - e2;
            int64_t in = (e0 | e1 | e2) >= 0, wrap;
            if (in & ((e0 == 0) | (e1 == 0) | (e2 == 0))) {
                e[0] = e0;
                e[1] = e1;
                e[2] = e2;
                in = on_edge_inside(x, y, e);
            }
            crow[m] = (unsigned char)row;
            ccol[m] = (unsigned char)col;
            m += in;
            /* the next sample: along the row, or the first of the next row */
            wrap = col + 1 == w;
            col = wrap ? 0 : col + 1;
            row = wrap ? row + 1 : row;
            r1 = wrap ? r1 + sy1 : r1;
            r2 = wrap ? r2 + sy2 : r2;
            e1 = wrap ? r1 : e1 - sx1;
            e2 = wrap ? r2 : e2 - sx2;
        }
        if (m == 0) return;
        mark_tiles(vis, b);
        unclipped_dconst(&k, vb, v, a, id);
        for (q = 0; q < m; q++) {
            const int64_t c1 = r10 + crow[q] * sy1 - ccol[q] * sx1, c2 = r20 + crow[q] * sy2 - ccol[q] * sx2;
            draw_sample(vis->tri, vis->depth, vis->bary, (size_t)(b->y0 + crow[q]) * sw + (size_t)(b->x0 + ccol[q]), &k,
                        area - c1 - c2, c1, c2);
        }
    }
}

/* Draws unclipped triangle v (in vb) into the samples of box b (inclusive,
 * inside the grid and the triangle's own box). */
LS_NOINLINE static void draw_unclipped(ls_vis *vis, const vbuf *vb, const size_t v[3], const sbox *b, uint32_t id)
{
    stri st;
    size_t o[3];
    int64_t a;
    if (box_direct(b)) {
        draw_small(vis, vb, v, b, id);
        return;
    }
    a = unclipped_load(vb->snap, v, st.x, st.y);
    if (a == 0) return;
    orient(st.x, st.y, a);
    o[0] = v[0];
    o[1] = a > 0 ? v[1] : v[2];
    o[2] = a > 0 ? v[2] : v[1];
    st.area = a > 0 ? a : -a;
    st.zw[0] = vb->zi[2 * o[0]];
    st.iw[0] = vb->zi[2 * o[0] + 1];
    st.zw[1] = vb->zi[2 * o[1]];
    st.iw[1] = vb->zi[2 * o[1] + 1];
    st.zw[2] = vb->zi[2 * o[2]];
    st.iw[2] = vb->zi[2 * o[2] + 1];
    memcpy(st.b, unit_b[a < 0], sizeof st.b);
    draw_stri(vis, &st, b, id);
}

/* b = b intersected with r; 0 when empty. */
static inline int box_clip(sbox *b, const sbox *r)
{
    if (b->x0 < r->x0) b->x0 = r->x0;
    if (b->y0 < r->y0) b->y0 = r->y0;
    if (b->x1 > r->x1) b->x1 = r->x1;
    if (b->y1 > r->y1) b->y1 = r->y1;
    return b->x0 <= b->x1 && b->y0 <= b->y1;
}

/* What every tile's drawing needs. */
typedef struct dpass {
    ls_vis *vis;
    const rctx *cx;
    const vbuf *vb;
    const uint32_t *indices;
    const uint16_t *rects; /* the count pass's sample ranges */
    clipbuf *cb;
} dpass;

/* Draws the screen triangles of triangle t, which needs clipping (v: its
 * vertices), into the samples of tile box r. */
LS_NOINLINE static void draw_clipped(const dpass *dp, uint32_t t, const size_t v[3], const sbox *r)
{
    int n = ls_rast_clipped_prepare(dp->cx, dp->vb, v, dp->cb), k;
    sbox b;
    stri st;
    for (k = 0; k < n; k++)
        if (ls_rast_clipped_sub(dp->cx, dp->cb, k, &st) && snap_box(dp->cx->sw, dp->cx->sh, st.x, st.y, &b) && box_clip(&b, r))
            draw_stri(dp->vis, &st, &b, t);
}

/* The samples (inclusive) of tile (tx, ty), clipped to the grid. */
static void tile_rect(const rctx *cx, uint32_t tx, uint32_t ty, sbox *r)
{
    r->x0 = (int64_t)tx << LS_RASTER_TILE_LOG2;
    r->y0 = (int64_t)ty << LS_RASTER_TILE_LOG2;
    r->x1 = r->x0 + LS_RASTER_TILE - 1;
    r->y1 = r->y0 + LS_RASTER_TILE - 1;
    if (r->x1 > (int64_t)cx->sw - 1) r->x1 = (int64_t)cx->sw - 1;
    if (r->y1 > (int64_t)cx->sh - 1) r->y1 = (int64_t)cx->sh - 1;
}

/* Clears the dirty tiles (a clean one is clear already) and marks them clean. */
LS_NOINLINE static void clear_tiles(ls_vis *vis, const rctx *cx)
{
    uint32_t tx, ty;
    for (ty = 0; ty < cx->tiles_y; ty++)
        for (tx = 0; tx < cx->tiles_x; tx++) {
            sbox r;
            int64_t j;
            if (!vis->tile_dirty[(size_t)ty * cx->tiles_x + tx]) continue;
            vis->tile_dirty[(size_t)ty * cx->tiles_x + tx] = 0;
            tile_rect(cx, tx, ty, &r);
            for (j = r.y0; j <= r.y1; j++) {
                size_t s0 = (size_t)j * vis->sw + (size_t)r.x0, n = (size_t)(r.x1 - r.x0 + 1), i;
                memset(vis->tri + s0, 0, n * sizeof *vis->tri);
                memset(vis->bary + 2 * s0, 0, 2 * n * sizeof *vis->bary); /* all-zero bits are +0 in IEEE 754 */
                for (i = 0; i < n; i++) vis->depth[s0 + i] = (ls_real)1;
            }
        }
}

/* Draws the triangles the count pass marked RECT_DIRECT; those of one sample
 * are tested here, without a call. */
LS_NOINLINE static void draw_direct(ls_vis *vis, const vbuf *vb, const uint32_t *indices, const uint16_t *rects,
                                    uint32_t triangle_count)
{
    uint32_t t;
    for (t = 0; t < triangle_count; t++) {
        const uint16_t *rc = rects + 4 * (size_t)t;
        const uint32_t *f = indices + 3 * (size_t)t;
        size_t v[3];
        sbox b;
        if (!(rc[0] & RECT_DIRECT)) continue;
        v[0] = f[0];
        v[1] = f[1];
        v[2] = f[2];
        b.x0 = rc[0] & ~RECT_DIRECT;
        b.y0 = rc[1];
        b.x1 = rc[2];
        b.y1 = rc[3];
        if (b.x0 == b.x1 && b.y0 == b.y1) {
            int32_t x[3], y[3];
            int64_t e[3], a = unclipped_load(vb->snap, v, x, y);
            orient(x, y, a);
            if (sample_edges(x, y, a > 0 ? a : -a, b.x0, b.y0, e)) draw_one(vis, vb, v, a, &b, e, t);
        } else {
            draw_small(vis, vb, v, &b, t);
        }
    }
}

LS_NOINLINE static void draw_tile(const dpass *dp, const uint32_t *list, size_t count, uint32_t tx, uint32_t ty)
{
    ls_vis *vis = dp->vis;
    const rctx *cx = dp->cx;
    const vbuf *vb = dp->vb;
    const uint32_t *indices = dp->indices;
    sbox r, b;
    size_t e;
    if (count == 0) return;
    tile_rect(cx, tx, ty, &r);
    vis->tile_dirty[(size_t)ty * cx->tiles_x + tx] = 1; /* clear_tiles cleared it */
    for (e = 0; e < count; e++) {
        uint32_t t = list[e];
        const uint32_t *f = indices + 3 * (size_t)t;
        const uint16_t *rc = dp->rects + 4 * (size_t)t;
        size_t v[3];
        v[0] = f[0];
        v[1] = f[1];
        v[2] = f[2];
        if (vb->flags[v[0]] | vb->flags[v[1]] | vb->flags[v[2]]) {
            draw_clipped(dp, t, v, &r);
            continue;
        }
        /* the triangle's own box, from the count pass */
        b.x0 = rc[0];
        b.y0 = rc[1];
        b.x1 = rc[2];
        b.y1 = rc[3];
        if (box_clip(&b, &r)) draw_unclipped(vis, vb, v, &b, t);
    }
}

static ls_status raster_impl(ls_vis *vis, ls_arena *arena, const ls_real mvp[16], const ls_real *positions,
                             uint32_t vertex_count, const uint32_t *indices, uint32_t triangle_count, ls_diag *diag)
{
    ls_diag_clear(diag);
    rctx cx;
    ls_arena_mark mark;
    vbuf vb;
    size_t *offs, tiles, entries, i, before;
    uint32_t *list, t, clipped;
    clipbuf *cb;
    uint16_t *rects;
    cpass cp;
    dpass dp;
    ls_status st;
    if (vis == NULL) return ls_invalid_arg(diag, "vis is NULL");
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (vis->magic != VIS_MAGIC) return LS_ERR_STATE;
    if (vertex_count > vis->vertex_capacity)
        return ls_invalid_arg(diag, "view->vertex_count: allowed <= vis->vertex_capacity");
    st = validate(mvp, positions, vertex_count, indices, triangle_count, diag);
    if (st != LS_OK) return st;
    ls_rast_ctx_init(&cx, mvp, vis->sw, vis->sh);
    tiles = (size_t)cx.tiles_x * cx.tiles_y;
    mark = ls_arena_save(arena);
    before = ls_arena_used(arena);
    vb.clip = (ls_real *)ls_arena_scratch(arena, vertex_count, VERT_BYTES);
    offs = vb.clip ? (size_t *)ls_arena_scratch(arena, tiles + 1, sizeof(size_t)) : NULL;
    cb = offs ? (clipbuf *)ls_arena_scratch(arena, 1, sizeof(clipbuf)) : NULL;
    rects = cb ? (uint16_t *)ls_arena_scratch(arena, triangle_count, 4 * sizeof(uint16_t)) : NULL;
    if (rects == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    vb.zi = vb.clip + 4 * (size_t)vertex_count;
    vb.snap = (int32_t *)(void *)(vb.zi + 2 * (size_t)vertex_count);
    vb.flags = (uint32_t *)(vb.snap + 2 * (size_t)vertex_count);
    t = ls_rast_transform_all(&cx, positions, NULL, vertex_count, &vb);
    if (t < vertex_count) {
        ls_arena_restore(arena, mark);
        return nonfinite_vertex(t, diag);
    }
    for (i = 0; i <= tiles; i++) offs[i] = 0;
    memset(&cp, 0, sizeof cp);
    cp.vb = &vb;
    cp.indices = indices;
    cp.triangle_count = triangle_count;
    cp.counts = offs + 1;
    cp.rects = rects;
    st = count_pass(&cx, cb, &cp);
    entries = cp.entries;
    clipped = cp.clipped;
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    list = (uint32_t *)ls_arena_scratch(arena, entries, sizeof(uint32_t));
    if (list == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    /* nothing fails from here on: vis may change */
    clear_tiles(vis, &cx);
    draw_direct(vis, &vb, indices, rects, triangle_count);
    /* prefix sum: offs[k + 1] = end of tile k's list */
    for (i = 0; i < tiles; i++) offs[i + 1] += offs[i];
    /* fill in reverse triangle order, moving each end down to its start, so
     * that every list ends up in increasing triangle order */
    for (t = triangle_count; t-- > 0;) {
        const uint16_t *rc = rects + 4 * (size_t)t;
        uint32_t tx, ty, tx0 = (uint32_t)rc[0] >> LS_RASTER_TILE_LOG2, tx1 = (uint32_t)rc[2] >> LS_RASTER_TILE_LOG2;
        if (rc[0] > rc[2]) continue; /* also when RECT_DIRECT is set */
        for (ty = (uint32_t)rc[1] >> LS_RASTER_TILE_LOG2; ty <= (uint32_t)rc[3] >> LS_RASTER_TILE_LOG2; ty++)
            for (tx = tx0; tx <= tx1; tx++) {
                size_t k = (size_t)ty * cx.tiles_x + tx + 1;
                list[--offs[k]] = t;
            }
    }
    /* now offs[k + 1] is the start of tile k; tile k ends at offs[k + 2] (or entries) */
    vis->scratch_bytes = ls_arena_used(arena) - before;
    dp.vis = vis;
    dp.cx = &cx;
    dp.vb = &vb;
    dp.indices = indices;
    dp.rects = rects;
    dp.cb = cb;
    for (t = 0; t < cx.tiles_y; t++) {
        uint32_t tx;
        for (tx = 0; tx < cx.tiles_x; tx++) {
            size_t k = (size_t)t * cx.tiles_x + tx;
            size_t start = offs[k + 1], end = k + 1 < tiles ? offs[k + 2] : entries;
            draw_tile(&dp, list + start, end - start, tx, t);
        }
    }
    if (vertex_count > 0) {
        memcpy(vis->clip, vb.clip, (size_t)vertex_count * 4 * sizeof(ls_real));
        memcpy(vis->snap, vb.snap, (size_t)vertex_count * 2 * sizeof(int32_t));
        memcpy(vis->vflags, vb.flags, (size_t)vertex_count * sizeof(uint32_t));
    }
    vis->vertex_count = vertex_count;
    vis->triangle_count = triangle_count;
    vis->bin_entries = entries;
    vis->clipped_triangles = clipped;
    ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_raster(ls_vis *vis, const ls_view *view, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return raster_impl(vis, arena, view->mvp, view->positions, view->vertex_count, view->indices, view->triangle_count, diag);
}
