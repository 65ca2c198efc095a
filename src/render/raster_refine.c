/* raster_refine.c - adaptive supersampling of silhouette pixels, forward and
 * interior backward (largesteps/raster_refine.h). */
#include <largesteps/raster_refine.h>
#include "render_internal.h"
#include <string.h>

#define BIG ((ls_real)1e30)
#define BOX_MARGIN 0.015625f /* 1/64 pixel: float boxes stay conservative */

/* Per-call state shared by the passes. */
typedef struct rf {
    const ls_vis *vis;
    const uint32_t *indices;
    uint32_t triangle_count, aa, tiles_x, tiles_y;
    uint8_t *mark;      /* [W H] 1: edge pixel */
    float *box;         /* [4 T] window box x0, y0, x1, y1 (x0 > x1: empty) */
    size_t *offs;       /* [tiles + 1] */
    uint32_t *list;     /* [entries] */
    uint32_t *sid;      /* [TILE^2 A^2] visible triangle + 1 per sub-sample of the current tile's pixels */
    ls_real *sdepth;    /* [TILE^2 A^2] */
    ls_real *scol, *srow; /* [TILE A] NDC of the current tile's sub-sample columns, rows */
    uint32_t x0, y0, x1, y1; /* the current tile's pixels (inclusive) */
    int cull;           /* 1 or -1: leave out triangles of that homogeneous orientation (closed mesh) */
    uint32_t pixels, segments;
} rf;

static int off_mode(uint32_t aa, uint32_t ss)
{
    return aa <= ss;
}

/* floor of a value in [-2^30, 2^30] to int32 (callers clamp first). */
static int32_t ifloor(ls_real v)
{
    int32_t t = (int32_t)v; /* toward zero */
    if ((ls_real)t > v) t -= 1;
    return t;
}

/* ---- triangle boxes and bins ---- */

/* The window box of triangle f (pixels), the near-plane-clipped polygon's
 * extent, widened and clamped to the image grown by one pixel; the whole
 * image when a clipped point is not in front (W <= 0). Returns 0 when empty. */
static int tri_box(const ls_vis *vis, const uint32_t *f, float out[4])
{
    ls_real poly[4][4], lo[2] = {BIG, BIG}, hi[2] = {-BIG, -BIG};
    const ls_real W = (ls_real)vis->width, H = (ls_real)vis->height;
    int n = 0, k, r;
    for (k = 0; k < 3; k++) {
        const ls_real *p = vis->clip + 4 * (size_t)f[k], *q = vis->clip + 4 * (size_t)f[(k + 1) % 3];
        ls_real dp = p[2] + p[3], dq = q[2] + q[3];
        if (dp >= (ls_real)0) {
            for (r = 0; r < 4; r++) poly[n][r] = p[r];
            n++;
        }
        if ((dp >= (ls_real)0) != (dq >= (ls_real)0)) {
            ls_real s = dp / (dp - dq);
            for (r = 0; r < 4; r++) poly[n][r] = p[r] + s * (q[r] - p[r]);
            n++;
        }
    }
    if (n < 3) return 0;
    for (k = 0; k < n; k++) {
        ls_real x, y;
        if (!(poly[k][3] > (ls_real)0)) {
            lo[0] = lo[1] = -BIG;
            hi[0] = hi[1] = BIG;
            break;
        }
        x = (poly[k][0] / poly[k][3] + (ls_real)1) * W * (ls_real)0.5;
        y = ((ls_real)1 - poly[k][1] / poly[k][3]) * H * (ls_real)0.5;
        if (x < lo[0]) lo[0] = x;
        if (x > hi[0]) hi[0] = x;
        if (y < lo[1]) lo[1] = y;
        if (y > hi[1]) hi[1] = y;
    }
    if (!(hi[0] >= (ls_real)0 && hi[1] >= (ls_real)0 && lo[0] <= W && lo[1] <= H)) return 0; /* NaN too */
    if (lo[0] < (ls_real)-1) lo[0] = (ls_real)-1;
    if (lo[1] < (ls_real)-1) lo[1] = (ls_real)-1;
    if (hi[0] > W + (ls_real)1) hi[0] = W + (ls_real)1;
    if (hi[1] > H + (ls_real)1) hi[1] = H + (ls_real)1;
    out[0] = (float)lo[0] - BOX_MARGIN;
    out[1] = (float)lo[1] - BOX_MARGIN;
    out[2] = (float)hi[0] + BOX_MARGIN;
    out[3] = (float)hi[1] + BOX_MARGIN;
    return 1;
}

/* Pixel and tile ranges of a box (clamped to the image). */
static void box_pixels(const ls_vis *vis, const float b[4], int32_t r[4])
{
    r[0] = ifloor((ls_real)b[0]);
    r[1] = ifloor((ls_real)b[1]);
    r[2] = ifloor((ls_real)b[2]);
    r[3] = ifloor((ls_real)b[3]);
    if (r[0] < 0) r[0] = 0;
    if (r[1] < 0) r[1] = 0;
    if (r[2] > (int32_t)vis->width - 1) r[2] = (int32_t)vis->width - 1;
    if (r[3] > (int32_t)vis->height - 1) r[3] = (int32_t)vis->height - 1;
}

/* The sign of the homogeneous determinant det((X, Y, W) of a, b, c). */
static int hsign(const ls_real *a, const ls_real *b, const ls_real *c)
{
    ls_real d = a[0] * (b[1] * c[3] - b[3] * c[1]);
    d -= a[1] * (b[0] * c[3] - b[3] * c[0]);
    d += a[3] * (b[0] * c[1] - b[1] * c[0]);
    return d > (ls_real)0 ? 1 : (d < (ls_real)0 ? -1 : 0);
}

/* A closed mesh seen from outside never shows its back faces: with no
 * boundary edge, no clipped triangle and fewer than 1/64 of the covered
 * samples of vis showing the minority homogeneous orientation (the test of
 * ls_silhouette_backward), the orientation to leave out (1 or -1), else 0. */
static int cull_orientation(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                            uint32_t triangle_count)
{
    size_t n = (size_t)vis->sw * vis->sh, s, pos = 0, neg = 0;
    if (table->boundary_edges != 0 || vis->clipped_triangles != 0) return 0;
    for (s = 0; s < n; s++) {
        uint32_t id = vis->tri[s];
        const uint32_t *f;
        int o;
        if (id == 0 || id > triangle_count) continue;
        f = indices + 3 * (size_t)(id - 1u);
        o = hsign(vis->clip + 4 * (size_t)f[0], vis->clip + 4 * (size_t)f[1], vis->clip + 4 * (size_t)f[2]);
        if (o > 0) pos++;
        else if (o < 0) neg++;
    }
    if (neg * 64u < pos + neg && pos > 0) return -1;
    if (pos * 64u < pos + neg && neg > 0) return 1;
    return 0;
}

/* 1 when triangle f is left out (culled orientation). */
static int culled(const ls_vis *vis, const uint32_t *f, int cull)
{
    return cull != 0 &&
           hsign(vis->clip + 4 * (size_t)f[0], vis->clip + 4 * (size_t)f[1], vis->clip + 4 * (size_t)f[2]) == cull;
}

/* The bin entries of every triangle (count pass, no memory). */
static ls_status count_entries(const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count, int cull,
                                size_t *entries)
{
    size_t total = 0;
    uint32_t t;
    for (t = 0; t < triangle_count; t++) {
        float b[4];
        int32_t r[4];
        size_t n;
        if (culled(vis, indices + 3 * (size_t)t, cull) || !tri_box(vis, indices + 3 * (size_t)t, b)) continue;
        box_pixels(vis, b, r);
        if (r[0] > r[2] || r[1] > r[3]) continue;
        n = (size_t)((r[2] >> LS_REFINE_TILE_LOG2) - (r[0] >> LS_REFINE_TILE_LOG2) + 1) *
            (size_t)((r[3] >> LS_REFINE_TILE_LOG2) - (r[1] >> LS_REFINE_TILE_LOG2) + 1);
        if (total > SIZE_MAX - n) return LS_ERR_TOO_LARGE;
        total += n;
    }
    *entries = total;
    return LS_OK;
}

static void scratch_layout(ls_size *s, uint32_t width, uint32_t height, uint32_t triangle_count, uint32_t aa,
                           size_t tiles, size_t entries)
{
    ls_size_init(s);
    ls_size_add(s, (size_t)width * height, sizeof(uint8_t));
    ls_size_add(s, triangle_count, 4 * sizeof(float));
    ls_size_add(s, tiles + 1, sizeof(size_t));
    ls_size_add(s, entries, sizeof(uint32_t));
    ls_size_add(s, (size_t)aa * aa * LS_REFINE_TILE * LS_REFINE_TILE, sizeof(uint32_t));
    ls_size_add(s, (size_t)aa * aa * LS_REFINE_TILE * LS_REFINE_TILE, sizeof(ls_real));
    ls_size_add(s, (size_t)aa * LS_REFINE_TILE, sizeof(ls_real));
    ls_size_add(s, (size_t)aa * LS_REFINE_TILE, sizeof(ls_real));
}

static size_t tile_count(uint32_t width, uint32_t height)
{
    return (size_t)((width + LS_REFINE_TILE - 1u) >> LS_REFINE_TILE_LOG2) *
           (size_t)((height + LS_REFINE_TILE - 1u) >> LS_REFINE_TILE_LOG2);
}

ls_status ls_refine_scratch_bytes_bound(uint32_t width, uint32_t height, uint32_t ss, uint32_t triangle_count,
                                        uint32_t aa, size_t *bytes)
{
    ls_size s;
    size_t tiles, entries;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (off_mode(aa, ss)) return LS_OK; /* nothing to check: off costs nothing */
    if (width == 0 || height == 0 || width > LS_RASTER_MAX_DIM || height > LS_RASTER_MAX_DIM || aa > LS_REFINE_MAX)
        return LS_ERR_INVALID;
    tiles = tile_count(width, height);
    st = ls_size_mul(tiles, triangle_count, &entries);
    if (st != LS_OK) return st;
    scratch_layout(&s, width, height, triangle_count, aa, tiles, entries);
    return ls_size_get(&s, bytes);
}

static ls_status check_vis(const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count, uint32_t aa,
                           ls_diag *diag)
{
    if (vis == NULL) return ls_invalid_arg(diag, "view->vis is NULL");
    if (aa > LS_REFINE_MAX) return ls_invalid_arg(diag, "aa: allowed 0 .. LS_REFINE_MAX");
    if (vis->tri == NULL || vis->clip == NULL) return LS_ERR_STATE;
    if (vis->triangle_count != triangle_count)
        return ls_invalid_arg(diag, "view->triangle_count: allowed = view->vis->triangle_count");
    if (triangle_count > 0 && indices == NULL)
        return ls_invalid_arg(diag, "view->indices is NULL with triangle_count > 0");
    return LS_OK;
}

static ls_status check_table(const ls_edge_table *table, uint32_t triangle_count, ls_diag *diag)
{
    if (table == NULL) return ls_invalid_arg(diag, "view->table is NULL");
    if (table->twin == NULL && triangle_count > 0) return LS_ERR_STATE;
    if (table->triangle_count != triangle_count)
        return ls_invalid_arg(diag, "view->table->triangle_count: allowed = view->triangle_count");
    return LS_OK;
}

static ls_status refine_scratch_bytes_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                           uint32_t triangle_count, uint32_t aa, size_t *bytes)
{
    ls_size s;
    size_t entries = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    st = check_vis(vis, indices, triangle_count, aa, NULL);
    if (st != LS_OK) return st;
    if (off_mode(aa, vis->ss)) return LS_OK;
    st = check_table(table, triangle_count, NULL);
    if (st == LS_OK) st = ls_check_triangle_indices(indices, triangle_count, vis->vertex_count, NULL);
    if (st == LS_OK) {
        int cull = cull_orientation(vis, table, indices, triangle_count);
        st = count_entries(vis, indices, triangle_count, cull, &entries);
    }
    if (st != LS_OK) return st;
    scratch_layout(&s, vis->width, vis->height, triangle_count, aa, tile_count(vis->width, vis->height), entries);
    return ls_size_get(&s, bytes);
}

ls_status ls_refine_scratch_bytes(const ls_view *view, uint32_t aa, size_t *bytes)
{
    if (view == NULL) return LS_ERR_INVALID;
    return refine_scratch_bytes_impl(view->vis, view->table, view->indices, view->triangle_count, aa, bytes);
}

/* Fills the boxes and the bins (offs[k] = start of tile k, offs[tiles] = end). */
static void build_bins(rf *c)
{
    const ls_vis *vis = c->vis;
    size_t tiles = (size_t)c->tiles_x * c->tiles_y, k;
    uint32_t t;
    for (k = 0; k <= tiles; k++) c->offs[k] = 0;
    for (t = 0; t < c->triangle_count; t++) {
        float *b = c->box + 4 * (size_t)t;
        int32_t r[4], tx, ty;
        if (culled(vis, c->indices + 3 * (size_t)t, c->cull) || !tri_box(vis, c->indices + 3 * (size_t)t, b)) {
            b[0] = b[1] = 1.0f;
            b[2] = b[3] = 0.0f;
            continue;
        }
        box_pixels(vis, b, r);
        if (r[0] > r[2] || r[1] > r[3]) {
            b[0] = b[1] = 1.0f;
            b[2] = b[3] = 0.0f;
            continue;
        }
        for (ty = r[1] >> LS_REFINE_TILE_LOG2; ty <= r[3] >> LS_REFINE_TILE_LOG2; ty++)
            for (tx = r[0] >> LS_REFINE_TILE_LOG2; tx <= r[2] >> LS_REFINE_TILE_LOG2; tx++)
                c->offs[(size_t)ty * c->tiles_x + (size_t)tx + 1]++;
    }
    for (k = 0; k < tiles; k++) c->offs[k + 1] += c->offs[k];
    /* fill in reverse order moving each tile's end down: lists in triangle order */
    for (t = c->triangle_count; t-- > 0;) {
        const float *b = c->box + 4 * (size_t)t;
        int32_t r[4], tx, ty;
        if (!(b[0] <= b[2])) continue;
        box_pixels(vis, b, r);
        if (r[0] > r[2] || r[1] > r[3]) continue;
        for (ty = r[1] >> LS_REFINE_TILE_LOG2; ty <= r[3] >> LS_REFINE_TILE_LOG2; ty++)
            for (tx = r[0] >> LS_REFINE_TILE_LOG2; tx <= r[2] >> LS_REFINE_TILE_LOG2; tx++) {
                size_t q = (size_t)ty * c->tiles_x + (size_t)tx + 1;
                c->list[--c->offs[q]] = t;
            }
    }
    /* now offs[q + 1] is the start of tile q; shift to offs[q] = start */
    for (k = 0; k < tiles; k++) c->offs[k] = c->offs[k + 1];
    /* offs[tiles] (the end of the last tile) is set by the caller */
}

/* ---- edge pixels ---- */

/* Marks the pixels the window segment (ax, ay) -> (bx, by) crosses (2D DDA). */
static void walk(rf *c, ls_real ax, ls_real ay, ls_real bx, ls_real by)
{
    const int32_t W = (int32_t)c->vis->width, H = (int32_t)c->vis->height;
    ls_real dx = bx - ax, dy = by - ay, tmx, tmy, tdx, tdy;
    int32_t ix = ifloor(ax), iy = ifloor(ay), ex = ifloor(bx), ey = ifloor(by), sx, sy;
    uint32_t n, k;
    sx = dx > (ls_real)0 ? 1 : -1;
    sy = dy > (ls_real)0 ? 1 : -1;
    n = (uint32_t)(ex > ix ? ex - ix : ix - ex) + (uint32_t)(ey > iy ? ey - iy : iy - ey);
    tmx = dx != (ls_real)0 ? ((ls_real)(ix + (sx > 0)) - ax) / dx : BIG;
    tmy = dy != (ls_real)0 ? ((ls_real)(iy + (sy > 0)) - ay) / dy : BIG;
    tdx = dx != (ls_real)0 ? (ls_real)sx / dx : BIG;
    tdy = dy != (ls_real)0 ? (ls_real)sy / dy : BIG;
    for (k = 0;; k++) {
        if (ix >= 0 && iy >= 0 && ix < W && iy < H) c->mark[(size_t)iy * (size_t)W + (size_t)ix] = 1;
        if (k == n) break;
        if (iy == ey || (ix != ex && tmx < tmy)) {
            ix += sx;
            tmx += tdx;
        } else {
            iy += sy;
            tmy += tdy;
        }
    }
}

/* Marks the pixels of the clip-space segment p -> q: near-plane clip
 * (unless near is 0: a cut, whose ends lie on the plane up to rounding),
 * window coordinates, clip to the image grown by one pixel, walk. */
static void mark_segment(rf *c, const ls_real *p0, const ls_real *q0, int near)
{
    const ls_real W = (ls_real)c->vis->width, H = (ls_real)c->vis->height;
    ls_real p[4], q[4], dp = p0[2] + p0[3], dq = q0[2] + q0[3], ax, ay, bx, by, t0 = 0, t1 = 1, d[2];
    ls_real lo[2], hi[2];
    int r;
    if (!near) dp = dq = (ls_real)0;
    if (dp < (ls_real)0 && dq < (ls_real)0) return;
    for (r = 0; r < 4; r++) {
        p[r] = p0[r];
        q[r] = q0[r];
    }
    if (dp < (ls_real)0) {
        ls_real s = dp / (dp - dq);
        for (r = 0; r < 4; r++) p[r] = p0[r] + s * (q0[r] - p0[r]);
    } else if (dq < (ls_real)0) {
        ls_real s = dq / (dq - dp);
        for (r = 0; r < 4; r++) q[r] = q0[r] + s * (p0[r] - q0[r]);
    }
    if (!(p[3] > (ls_real)0 && q[3] > (ls_real)0)) return;
    ax = (p[0] / p[3] + (ls_real)1) * W * (ls_real)0.5;
    ay = ((ls_real)1 - p[1] / p[3]) * H * (ls_real)0.5;
    bx = (q[0] / q[3] + (ls_real)1) * W * (ls_real)0.5;
    by = ((ls_real)1 - q[1] / q[3]) * H * (ls_real)0.5;
    if (ax - ax != (ls_real)0 || ay - ay != (ls_real)0 || bx - bx != (ls_real)0 || by - by != (ls_real)0) return;
    /* Liang-Barsky against [-1, W + 1] x [-1, H + 1] */
    d[0] = bx - ax;
    d[1] = by - ay;
    lo[0] = (ls_real)-1 - ax;
    lo[1] = (ls_real)-1 - ay;
    hi[0] = W + (ls_real)1 - ax;
    hi[1] = H + (ls_real)1 - ay;
    for (r = 0; r < 2; r++) {
        if (d[r] == (ls_real)0) {
            if (lo[r] > (ls_real)0 || hi[r] < (ls_real)0) return;
        } else {
            ls_real ta = lo[r] / d[r], tb = hi[r] / d[r];
            if (ta > tb) {
                ls_real tt = ta;
                ta = tb;
                tb = tt;
            }
            if (ta > t0) t0 = ta;
            if (tb < t1) t1 = tb;
        }
    }
    if (!(t0 <= t1)) return;
    c->segments++;
    walk(c, ax + t0 * d[0], ay + t0 * d[1], ax + t1 * d[0], ay + t1 * d[1]);
}

/* Marks every pixel crossed by a silhouette segment (header). */
static void mark_edges(rf *c, const ls_edge_table *table)
{
    const ls_real *clip = c->vis->clip;
    uint32_t t, k;
    for (t = 0; t < c->triangle_count; t++) {
        const uint32_t *f = c->indices + 3 * (size_t)t;
        for (k = 0; k < 3; k++) {
            uint32_t h = 3u * t + k, tw = table->twin[h];
            const ls_real *a = clip + 4 * (size_t)f[k], *b = clip + 4 * (size_t)f[(k + 1u) % 3u];
            if (tw != LS_EDGE_NONE) {
                const uint32_t *g = c->indices + 3 * (size_t)(tw / 3u);
                int s1, s2;
                if (tw < h) continue; /* each shared edge once */
                s1 = hsign(a, b, clip + 4 * (size_t)f[(k + 2u) % 3u]);
                s2 = hsign(a, b, clip + 4 * (size_t)g[(tw % 3u + 2u) % 3u]);
                if (s1 * s2 < 0) continue; /* opposite sides: not a silhouette */
                if (ls_valley_edge(clip, c->indices, h, tw, c->cull)) continue; /* hidden: the surface there is smooth */
            }
            mark_segment(c, a, b, 1);
        }
    }
    /* near-plane cuts */
    for (t = 0; t < c->triangle_count; t++) {
        const uint32_t *f = c->indices + 3 * (size_t)t;
        ls_real pt[2][4];
        int n = 0, r;
        for (k = 0; k < 3; k++) {
            const ls_real *p = clip + 4 * (size_t)f[k], *q = clip + 4 * (size_t)f[(k + 1u) % 3u];
            ls_real dp = p[2] + p[3], dq = q[2] + q[3];
            if ((dp >= (ls_real)0) != (dq >= (ls_real)0) && n < 2) {
                ls_real s = dp / (dp - dq);
                for (r = 0; r < 4; r++) pt[n][r] = p[r] + s * (q[r] - p[r]);
                n++;
            }
        }
        if (n == 2) mark_segment(c, pt[0], pt[1], 0);
    }
}

/* ---- sub-sample visibility ---- */

/* Sub-sample range [i0, i1] of a box coordinate range [b0, b1] in pixel x0. */
static void sub_range(ls_real b0, ls_real b1, uint32_t x0, uint32_t aa, int32_t *i0, int32_t *i1)
{
    ls_real a = (b0 - (ls_real)x0) * (ls_real)aa - (ls_real)0.5, e = (b1 - (ls_real)x0) * (ls_real)aa - (ls_real)0.5;
    int32_t lo, hi;
    if (a < (ls_real)-1) a = (ls_real)-1;
    if (e > (ls_real)aa) e = (ls_real)aa;
    lo = ifloor(a);
    if ((ls_real)lo < a) lo++; /* ceil */
    hi = ifloor(e);
    if (lo < 0) lo = 0;
    if (hi > (int32_t)aa - 1) hi = (int32_t)aa - 1;
    *i0 = lo;
    *i1 = hi;
}

/* Sets up tile (tx, ty): its pixel range, the NDC coordinates of its
 * sub-sample columns and rows (the header's formula: the shading and the
 * backward use these values), and clears the sub-samples of its edge
 * pixels. Returns 0 when the tile holds no edge pixel. */
static int tile_begin(rf *c, uint32_t tx, uint32_t ty)
{
    const ls_vis *vis = c->vis;
    const uint32_t aa = c->aa, n = aa * aa;
    const ls_real sw = (ls_real)(vis->width * aa), sh = (ls_real)(vis->height * aa);
    uint32_t x, y, k, any = 0;
    c->x0 = tx << LS_REFINE_TILE_LOG2;
    c->y0 = ty << LS_REFINE_TILE_LOG2;
    c->x1 = c->x0 + LS_REFINE_TILE - 1u < vis->width - 1u ? c->x0 + LS_REFINE_TILE - 1u : vis->width - 1u;
    c->y1 = c->y0 + LS_REFINE_TILE - 1u < vis->height - 1u ? c->y0 + LS_REFINE_TILE - 1u : vis->height - 1u;
    for (y = c->y0; y <= c->y1; y++)
        for (x = c->x0; x <= c->x1; x++) {
            size_t q0 = ((size_t)(y - c->y0) * LS_REFINE_TILE + (x - c->x0)) * n;
            if (!c->mark[(size_t)y * vis->width + x]) continue;
            any = 1;
            for (k = 0; k < n; k++) {
                c->sid[q0 + k] = 0;
                c->sdepth[q0 + k] = (ls_real)1;
            }
        }
    if (!any) return 0;
    for (k = 0; k < LS_REFINE_TILE * aa; k++) {
        c->scol[k] = (ls_real)(2u * (c->x0 * aa + k) + 1u) / sw - (ls_real)1;
        c->srow[k] = (ls_real)1 - (ls_real)(2u * (c->y0 * aa + k) + 1u) / sh;
    }
    return 1;
}

/* Candidate t (clip corners c0, c1, c2, box b) against the sub-samples of
 * edge pixel (x, y) of the current tile inside its box. */
static void pixel_candidate(rf *c, uint32_t t, const float *b, const ls_real *const cc[3], uint32_t x, uint32_t y)
{
    const uint32_t aa = c->aa;
    const ls_real *c0 = cc[0], *c1 = cc[1], *c2 = cc[2];
    const size_t q0 = ((size_t)(y - c->y0) * LS_REFINE_TILE + (x - c->x0)) * aa * aa;
    const ls_real *scol = c->scol + (size_t)(x - c->x0) * aa, *srow = c->srow + (size_t)(y - c->y0) * aa;
    int32_t i0, i1, j0, j1, i, j;
    sub_range((ls_real)b[0], (ls_real)b[2], x, aa, &i0, &i1);
    sub_range((ls_real)b[1], (ls_real)b[3], y, aa, &j0, &j1);
    for (j = j0; j <= j1; j++) {
        ls_real py = srow[j];
        ls_real v0 = c0[1] - py * c0[3], v1 = c1[1] - py * c1[3], v2 = c2[1] - py * c2[3];
        for (i = i0; i <= i1; i++) {
            ls_real px = scol[i];
            /* ls_clip_barycentric's arithmetic */
            ls_real u0 = c0[0] - px * c0[3], u1 = c1[0] - px * c1[3], u2 = c2[0] - px * c2[3];
            ls_real a0 = u1 * v2 - u2 * v1, a1 = u2 * v0 - u0 * v2, a2 = u0 * v1 - u1 * v0;
            ls_real sum = (a0 + a1) + a2, zs, ws, d;
            size_t q = q0 + (size_t)j * aa + (size_t)i;
            if (sum > (ls_real)0) {
                if (a0 < (ls_real)0 || a1 < (ls_real)0 || a2 < (ls_real)0) continue;
            } else if (sum < (ls_real)0) {
                if (a0 > (ls_real)0 || a1 > (ls_real)0 || a2 > (ls_real)0) continue;
            } else {
                continue; /* edge-on, or NaN */
            }
            ws = (a0 * c0[3] + a1 * c1[3]) + a2 * c2[3];
            if (!(sum > (ls_real)0 ? ws > (ls_real)0 : ws < (ls_real)0)) continue; /* behind the eye */
            zs = (a0 * c0[2] + a1 * c1[2]) + a2 * c2[2];
            d = zs / ws;
            if (!(d >= (ls_real)-1 && d <= (ls_real)1)) continue;
            /* triangles come in increasing order: on equal depth the first stays */
            if (c->sid[q] == 0 || d < c->sdepth[q]) {
                c->sid[q] = t + 1u;
                c->sdepth[q] = d;
            }
        }
    }
}

/* The visible triangle (id + 1, 0 = none) and depth of every sub-sample of
 * the edge pixels of the current tile (tile_begin), into c->sid / c->sdepth:
 * the tile's candidates in triangle order, each against the edge pixels its
 * box meets. */
static void tile_visibility(rf *c, uint32_t tx, uint32_t ty)
{
    const ls_vis *vis = c->vis;
    const size_t tile = (size_t)ty * c->tiles_x + tx;
    size_t e;
    for (e = c->offs[tile]; e < c->offs[tile + 1]; e++) {
        uint32_t t = c->list[e], x, y;
        const float *b = c->box + 4 * (size_t)t;
        const uint32_t *f = c->indices + 3 * (size_t)t;
        const ls_real *cc[3];
        int32_t r[4];
        box_pixels(vis, b, r);
        if (r[0] < (int32_t)c->x0) r[0] = (int32_t)c->x0;
        if (r[1] < (int32_t)c->y0) r[1] = (int32_t)c->y0;
        if (r[2] > (int32_t)c->x1) r[2] = (int32_t)c->x1;
        if (r[3] > (int32_t)c->y1) r[3] = (int32_t)c->y1;
        cc[0] = vis->clip + 4 * (size_t)f[0];
        cc[1] = vis->clip + 4 * (size_t)f[1];
        cc[2] = vis->clip + 4 * (size_t)f[2];
        for (y = (uint32_t)r[1]; (int32_t)y <= r[3]; y++)
            for (x = (uint32_t)r[0]; (int32_t)x <= r[2]; x++)
                if (c->mark[(size_t)y * vis->width + x]) pixel_candidate(c, t, b, cc, x, y);
    }
}

/* The refined value of edge pixel (x, y) of the current tile into image:
 * the mean of its sub-samples' colours (row-major sums), alpha the covered
 * fraction. */
static void shade_pixel(const rf *c, const ls_shade_opts *opts, const ls_real *normals, uint32_t x, uint32_t y,
                        ls_real *image)
{
    const ls_vis *vis = c->vis;
    const uint32_t aa = c->aa;
    const size_t p = (size_t)y * vis->width + x;
    const size_t q0 = ((size_t)(y - c->y0) * LS_REFINE_TILE + (x - c->x0)) * aa * aa;
    const ls_real *scol = c->scol + (size_t)(x - c->x0) * aa, *srow = c->srow + (size_t)(y - c->y0) * aa;
    const ls_real *bg = opts->background_image != NULL ? opts->background_image + 3 * p : opts->background;
    const ls_real inv_n = (ls_real)1 / (ls_real)(aa * aa);
    ls_real acc[3] = {(ls_real)0, (ls_real)0, (ls_real)0};
    uint32_t covered = 0, i, j;
    for (j = 0; j < aa; j++)
        for (i = 0; i < aa; i++) {
            uint32_t id = c->sid[q0 + (size_t)j * aa + i];
            ls_real rgb[3];
            if (id == 0) {
                rgb[0] = bg[0];
                rgb[1] = bg[1];
                rgb[2] = bg[2];
            } else {
                const uint32_t *f = c->indices + 3 * (size_t)(id - 1u);
                ls_real u[3], v[3], b[3];
                (void)ls_clip_barycentric(vis->clip, f, scol[i], srow[j], u, v, b); /* sum != 0: tested */
                ls_shade_point(opts, f, normals, b, rgb);
                covered++;
            }
            acc[0] += rgb[0];
            acc[1] += rgb[1];
            acc[2] += rgb[2];
        }
    image[4 * p] = acc[0] * inv_n;
    image[4 * p + 1] = acc[1] * inv_n;
    image[4 * p + 2] = acc[2] * inv_n;
    image[4 * p + 3] = (ls_real)covered * inv_n;
}

/* The interior backward of edge pixel (x, y) of the current tile over its
 * covered sub-samples (row-major), each with weight 1/A^2. */
static void backward_pixel(const rf *c, const ls_shade_bctx *bc, const ls_real *grad_image, uint32_t x, uint32_t y)
{
    const uint32_t aa = c->aa;
    const size_t p = (size_t)y * c->vis->width + x;
    const size_t q0 = ((size_t)(y - c->y0) * LS_REFINE_TILE + (x - c->x0)) * aa * aa;
    const ls_real *scol = c->scol + (size_t)(x - c->x0) * aa, *srow = c->srow + (size_t)(y - c->y0) * aa;
    const ls_real inv_n = (ls_real)1 / (ls_real)(aa * aa);
    ls_real g[3];
    uint32_t i, j;
    g[0] = grad_image[4 * p] * inv_n;
    g[1] = grad_image[4 * p + 1] * inv_n;
    g[2] = grad_image[4 * p + 2] * inv_n;
    if (g[0] == (ls_real)0 && g[1] == (ls_real)0 && g[2] == (ls_real)0) return;
    for (j = 0; j < aa; j++)
        for (i = 0; i < aa; i++) {
            uint32_t id = c->sid[q0 + (size_t)j * aa + i];
            if (id != 0) ls_shade_backward_sample(bc, c->indices + 3 * (size_t)(id - 1u), scol[i], srow[j], g);
        }
}

/* What the forward and the backward do in one marked pixel. */
typedef struct pixel_job {
    const ls_shade_opts *opts;
    const ls_real *normals;
    ls_real *image;          /* forward: the image refined; NULL: backward */
    const ls_shade_bctx *bc; /* backward */
    const ls_real *grad_image;
} pixel_job;

/* Every marked pixel, tile by tile (the tile's sub-sample visibility first). */
static void each_marked_pixel(rf *c, const pixel_job *job)
{
    uint32_t tx, ty, x, y;
    for (ty = 0; ty < c->tiles_y; ty++)
        for (tx = 0; tx < c->tiles_x; tx++) {
            if (!tile_begin(c, tx, ty)) continue;
            tile_visibility(c, tx, ty);
            for (y = c->y0; y <= c->y1; y++)
                for (x = c->x0; x <= c->x1; x++) {
                    if (!c->mark[(size_t)y * c->vis->width + x]) continue;
                    if (job->image != NULL)
                        shade_pixel(c, job->opts, job->normals, x, y, job->image);
                    else
                        backward_pixel(c, job->bc, job->grad_image, x, y);
                }
        }
}

/* ---- the calls ---- */

/* Takes the scratch, builds the bins and the edge-pixel map. */
static ls_status refine_begin(rf *c, const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                              uint32_t triangle_count, uint32_t aa, ls_arena *arena)
{
    size_t entries = 0, tiles, p, np;
    int cull = cull_orientation(vis, table, indices, triangle_count);
    ls_status st = count_entries(vis, indices, triangle_count, cull, &entries);
    if (st != LS_OK) return st;
    memset(c, 0, sizeof *c);
    c->cull = cull;
    c->vis = vis;
    c->indices = indices;
    c->triangle_count = triangle_count;
    c->aa = aa;
    c->tiles_x = (vis->width + LS_REFINE_TILE - 1u) >> LS_REFINE_TILE_LOG2;
    c->tiles_y = (vis->height + LS_REFINE_TILE - 1u) >> LS_REFINE_TILE_LOG2;
    tiles = (size_t)c->tiles_x * c->tiles_y;
    np = (size_t)vis->width * vis->height;
    c->mark = (uint8_t *)ls_arena_scratch(arena, np, sizeof(uint8_t));
    c->box = c->mark ? (float *)ls_arena_scratch(arena, triangle_count, 4 * sizeof(float)) : NULL;
    c->offs = c->box ? (size_t *)ls_arena_scratch(arena, tiles + 1, sizeof(size_t)) : NULL;
    c->list = c->offs ? (uint32_t *)ls_arena_scratch(arena, entries, sizeof(uint32_t)) : NULL;
    c->sid = c->list ? (uint32_t *)ls_arena_scratch(arena, (size_t)aa * aa * LS_REFINE_TILE * LS_REFINE_TILE,
                                                    sizeof(uint32_t)) : NULL;
    c->sdepth = c->sid ? (ls_real *)ls_arena_scratch(arena, (size_t)aa * aa * LS_REFINE_TILE * LS_REFINE_TILE,
                                                     sizeof(ls_real)) : NULL;
    c->scol = c->sdepth ? (ls_real *)ls_arena_scratch(arena, (size_t)aa * LS_REFINE_TILE, sizeof(ls_real)) : NULL;
    c->srow = c->scol ? (ls_real *)ls_arena_scratch(arena, (size_t)aa * LS_REFINE_TILE, sizeof(ls_real)) : NULL;
    if (c->srow == NULL) return LS_ERR_NOMEM;
    build_bins(c);
    c->offs[tiles] = entries;
    memset(c->mark, 0, np);
    mark_edges(c, table);
    for (p = 0; p < np; p++) c->pixels += c->mark[p];
    return LS_OK;
}

static ls_status refine_shade_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                   uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                   const ls_shade_opts *opts, uint32_t aa, ls_real *image, ls_arena *arena,
                                   ls_refine_info *info, ls_diag *diag)
{
    ls_diag_clear(diag);
    rf c;
    ls_arena_mark mark;
    pixel_job job;
    size_t before;
    uint32_t counts[2];
    ls_status st;
    if (image == NULL) return ls_invalid_arg(diag, "image is NULL");
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    st = check_vis(vis, indices, triangle_count, aa, diag);
    if (st != LS_OK) return st;
    counts[0] = triangle_count;
    counts[1] = vertex_count;
    st = ls_shade_check_args(vis, counts, indices, normals, opts, diag);
    if (st != LS_OK) return st;
    if (off_mode(aa, vis->ss)) {
        if (info != NULL) memset(info, 0, sizeof *info);
        return LS_OK;
    }
    st = check_table(table, triangle_count, diag);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    before = ls_arena_used(arena);
    st = refine_begin(&c, vis, table, indices, triangle_count, aa, arena);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    job.opts = opts;
    job.normals = normals;
    job.image = image;
    job.bc = NULL;
    job.grad_image = NULL;
    each_marked_pixel(&c, &job);
    if (info != NULL) {
        info->pixels = c.pixels;
        info->segments = c.segments;
        info->bin_entries = c.offs[(size_t)c.tiles_x * c.tiles_y];
        info->scratch_bytes = ls_arena_used(arena) - before;
    }
    ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_refine_shade(const ls_view *view, uint32_t aa, ls_real *image, ls_arena *arena, ls_refine_info *info,
                          ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return refine_shade_impl(view->vis, view->table, view->indices, view->triangle_count, view->normals, view->vertex_count,
                           view->opts, aa, image, arena, info, diag);
}

static ls_status refine_shade_backward_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                            uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                            const ls_shade_opts *opts, uint32_t aa, const ls_real mvp[16],
                                            const ls_real *grad_image, const ls_shade_grads *grads, ls_arena *arena,
                                            ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_shade_bctx bc;
    rf c;
    ls_arena_mark mark;
    pixel_job job;
    ls_status st;
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    st = check_vis(vis, indices, triangle_count, aa, diag);
    if (st != LS_OK) return st;
    st = ls_shade_backward_begin(&bc, vis, indices, triangle_count, normals, vertex_count, opts, mvp, grad_image,
                                 grads, diag);
    if (st != LS_OK) return st;
    if (off_mode(aa, vis->ss)) {
        if (opts->mode == LS_SHADE_MASK) return LS_OK;
        ls_shade_backward_pixels(&bc, triangle_count, grad_image, NULL);
        return LS_OK;
    }
    st = check_table(table, triangle_count, diag);
    if (st != LS_OK) return st;
    if (opts->mode == LS_SHADE_MASK) return LS_OK; /* nothing depends on positions inside */
    mark = ls_arena_save(arena);
    st = refine_begin(&c, vis, table, indices, triangle_count, aa, arena);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    ls_shade_backward_pixels(&bc, triangle_count, grad_image, c.mark);
    job.opts = opts;
    job.normals = normals;
    job.image = NULL;
    job.bc = &bc;
    job.grad_image = grad_image;
    each_marked_pixel(&c, &job);
    ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_refine_shade_backward(const ls_view *view, uint32_t aa, const ls_real *grad_image,
                                   const ls_shade_grads *grads, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return refine_shade_backward_impl(view->vis, view->table, view->indices, view->triangle_count, view->normals,
                                    view->vertex_count, view->opts, aa, view->mvp, grad_image, grads, arena, diag);
}
