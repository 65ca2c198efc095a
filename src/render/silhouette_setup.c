/* silhouette_setup.c - the per-view set-up: orientations, culling, tiles, the contour marks, boxes and bins */
#include "silhouette_internal.h"

static ls_real hdet(const ls_real *a, const ls_real *b, const ls_real *c);

/* Orientation of triangle f: the sign of the homogeneous determinant of its
 * clip coordinates (X, Y, W), doubled (+-2) when it is certain: the value
 * exceeds 8 eps times the permanent of the absolute entries (plus a few
 * smallest normals for underflow), more than twice the rounding error of
 * hdet with the rows in any order, so every such evaluation, as the edge
 * test's with rotated rows, has the same sign. */
static int tri_sign(const sctx *sc, const uint32_t *f)
{
    const ls_real *c = sc->vis->clip, *a = c + 4 * (size_t)f[0], *b = c + 4 * (size_t)f[1], *e = c + 4 * (size_t)f[2];
    ls_real d = hdet(a, b, e), perm, bound;
    int s = d > (ls_real)0 ? 1 : (d < (ls_real)0 ? -1 : 0);
    perm = (r_abs(a[0]) * (r_abs(b[1] * e[3]) + r_abs(b[3] * e[1])) +
            r_abs(a[1]) * (r_abs(b[0] * e[3]) + r_abs(b[3] * e[0]))) +
           r_abs(a[3]) * (r_abs(b[0] * e[1]) + r_abs(b[1] * e[0]));
    bound = (ls_real)8 * LS_REAL_EPSILON * perm + (ls_real)64 * R_MIN_NORMAL;
    return r_abs(d) > bound ? 2 * s : s;
}

/* tri_sign of a triangle with every corner in front of the eye (W > 0),
 * from its window corners: hdet = W0 W1 W2 det(NDC), and window y runs
 * down, so the window cross product has the opposite sign. It is certain
 * (+-2, the exact sign, as tri_sign's certain values are) when it exceeds
 * a bound on its error: window_of's coordinates are off by at most
 * eps (3 |x| + width) each (sc->wk bounds 3 |x| + width + height over the
 * front vertices), the differences and products add theirs; 16 eps covers
 * them with room. Otherwise tri_sign decides. Most triangles' cross
 * products exceed wkb, which bounds every triangle's bound, so the
 * answer is the same without computing theirs. */
static SIL_INLINE int tri_sign_front(const sctx *sc, const uint32_t *f, ls_real wkb)
{
    const ls_real *p0 = sc->win + 2 * (size_t)f[0], *p1 = sc->win + 2 * (size_t)f[1], *p2 = sc->win + 2 * (size_t)f[2];
    ls_real d1[2], d2[2], t1, t2, cr, k = sc->wk, bound;
    int fast;
#if SIL_SSE2
    /* the (dx, dy) pairs and both products in one each */
    sil_v2 a = V2_LOAD(p0), e1 = V2_SUB(V2_LOAD(p1), a), e2 = V2_SUB(V2_LOAD(p2), a), pr = V2_MUL(e1, V2_SWAP(e2));
    t1 = V2_LO(pr);
    t2 = V2_HI(pr);
#else
    int j;
    for (j = 0; j < 2; j++) { /* the (dx, dy) pairs */
        d1[j] = p1[j] - p0[j];
        d2[j] = p2[j] - p0[j];
    }
    t1 = d1[0] * d2[1];
    t2 = d1[1] * d2[0];
#endif
    cr = t1 - t2;
    fast = 2 * ((cr < -wkb) - (cr > wkb)); /* no branch on the orientation: it has no pattern */
    if (fast != 0) return fast;
#if SIL_SSE2
    V2_STORE(d1, e1);
    V2_STORE(d2, e2);
#endif
    bound = (ls_real)16 * LS_REAL_EPSILON *
                ((k * (((r_abs(d1[0]) + r_abs(d1[1])) + (r_abs(d2[0]) + r_abs(d2[1]))) + LS_REAL_EPSILON * k) +
                  r_abs(t1)) +
                 r_abs(t2)) +
            (ls_real)64 * R_MIN_NORMAL;
    if (cr > bound) return -2;
    if (cr < -bound) return 2;
    return tri_sign(sc, f);
}

/* Window box (x0, y0, x1, y1) of the window corners p0, p1, p2: the min
 * and max of p0 and p1 on two comparisons (SSE2's minsd and maxsd; on one,
 * gcc swaps them with a branch, which mispredicts); p0 - p0 keeps NaN as
 * one comparison had it (a NaN or infinite p0 made the max not finite),
 * else adds +0 (a max of -0 becomes +0: box_fbox does not tell them apart);
 * finite: the corners are known finite, and that is not needed. */
static SIL_INLINE void corner_box(const ls_real *p0, const ls_real *p1, const ls_real *p2, ls_real box[4], int finite)
{
    int k;
    for (k = 0; k < 2; k++) {
        ls_real lo = p0[k] < p1[k] ? p0[k] : p1[k], hi = p0[k] > p1[k] ? p0[k] : p1[k];
        if (!finite) hi += p0[k] - p0[k];
        box[k] = p2[k] < lo ? p2[k] : lo;
        box[k + 2] = p2[k] > hi ? p2[k] : hi;
    }
}

/* Window box (x0, y0, x1, y1) of triangle f's visible polygon; 0 when it
 * has none. */
static int tri_box(const sctx *sc, const uint32_t *f, ls_real box[4])
{
    if (sc->vfront != NULL && (sc->vfront[f[0]] & sc->vfront[f[1]] & sc->vfront[f[2]]) != 0) {
        /* every corner in front (most triangles): the box of the window corners */
        corner_box(sc->win + 2 * (size_t)f[0], sc->win + 2 * (size_t)f[1], sc->win + 2 * (size_t)f[2], box, 0);
    } else {
        ls_real x[4], y[4];
        int k, n = tri_poly(sc, f, x, y);
        if (n < 3) return 0;
        box[0] = box[2] = x[0];
        box[1] = box[3] = y[0];
        for (k = 1; k < n; k++) {
            if (x[k] < box[0]) box[0] = x[k];
            if (x[k] > box[2]) box[2] = x[k];
            if (y[k] < box[1]) box[1] = y[k];
            if (y[k] > box[3]) box[3] = y[k];
        }
    }
    return 1;
}

/* What the bins' boxes and tiles depend on, in a local copy (the
 * stores of boxes, bins and lists cannot change it, so it stays in
 * registers): grid_init. */
typedef struct sgrid {
    ls_real xm, ym;       /* width, height + margin: a box's x0, y0 at most these meets the image */
    ls_real xl, yl;       /* width, height + 1: the clamps of x1, y1 */
#if SIL_SSE2
    __m128 inv4, last4;   /* inv and (lx, ly, lx, ly) in each lane (fbox_tiles) */
    sil_v2 m2, l2;        /* (xm, ym), (xl, yl) (corner_tiles) */
#endif
    float inv;            /* sc->tside_inv */
    uint32_t tx;          /* sc->tiles_x */
    uint32_t lx, ly;      /* the last tile of a row and of a column */
} sgrid;

static void grid_init(const sctx *sc, sgrid *g)
{
    g->xm = sc->width + SIL_MARGIN;
    g->ym = sc->height + SIL_MARGIN;
    g->xl = sc->width + (ls_real)1;
    g->yl = sc->height + (ls_real)1;
    g->inv = sc->tside_inv;
    g->tx = sc->tiles_x;
    g->lx = sc->tiles_x - 1u;
    g->ly = sc->tiles_y - 1u;
#if SIL_SSE2
    g->inv4 = _mm_set1_ps(g->inv);
    g->last4 = _mm_setr_ps((float)g->lx, (float)g->ly, (float)g->lx, (float)g->ly);
    g->m2 = V2_SET(g->xm, g->ym);
    g->l2 = V2_SET(g->xl, g->yl);
#endif
}

/* The box for the bins of a window box of tri_box: clamped to the image
 * and a pixel around it, grown by the margin, in float (rounding at these
 * magnitudes is far below the margin); 0 (fb untouched) when the box is
 * not finite or lies outside the image. finite: the box is known finite
 * (box_keep's), so only the image is tested. */
static SIL_INLINE int box_fbox(const sgrid *g, const ls_real box[4], float fb[4], int finite)
{
    if (finite) {
        if (!(box[0] <= g->xm && box[2] >= -SIL_MARGIN && box[1] <= g->ym && box[3] >= -SIL_MARGIN)) return 0;
    } else if (!(box[0] >= -R_MAX && box[0] <= g->xm && box[2] >= -SIL_MARGIN && box[2] <= R_MAX &&
                 box[1] >= -R_MAX && box[1] <= g->ym && box[3] >= -SIL_MARGIN && box[3] <= R_MAX)) {
        /* finite and meeting the image, each bound on its own range (NaN fails
         * every comparison): x0 in [-max, width + margin], x1 in [-margin, max] */
        return 0;
    }
    /* the box meets the image: x0, y0 <= size + margin and x1, y1 >= -margin;
     * the clamps as max and min (no NaN here; a bound equal to -1 or to
     * the limit is the same value either way) */
    fb[0] = (float)((box[0] > (ls_real)-1 ? box[0] : (ls_real)-1) - SIL_MARGIN);
    fb[1] = (float)((box[1] > (ls_real)-1 ? box[1] : (ls_real)-1) - SIL_MARGIN);
    fb[2] = (float)((box[2] < g->xl ? box[2] : g->xl) + SIL_MARGIN);
    fb[3] = (float)((box[3] < g->yl ? box[3] : g->yl) + SIL_MARGIN);
    return 1;
}

#if !SIL_SSE2
/* The tile of a box coordinate v of tri_fbox: cell_of(v / side, last + 1)
 * without its branches: tri_fbox clamps v to at least -1 - margin and a
 * side is at least 2, so v / side > -1 and the truncation toward zero is
 * that floor clamped. inv = 1 / side, a power of two: the product is the
 * quotient exactly (in float too, the box's own type: no conversion),
 * without a division's latency. */
static uint32_t tile_of(float v, float inv, uint32_t last)
{
    uint32_t i = (uint32_t)(int32_t)(v * inv);
    return i < last ? i : last;
}
#endif

/* The box of triangle t's visible polygon for the bins (box_fbox); 0 when
 * t is not binned (no box, or culled: sign 0 or of the culled orientation). */
static int tri_fbox(const sctx *sc, const sgrid *g, uint32_t t, float fb[4])
{
    const uint32_t *f = sc->indices + 3 * (size_t)t;
    ls_real box[4];
    if (sc->cull != 0 && sc->cull * (sc->sign != NULL ? sc->sign[t] : tri_sign(sc, f)) >= 0) return 0;
    return tri_box(sc, f, box) && box_fbox(g, box, fb, 0);
}

/* The tiles (x0, y0, x1, y1) a box of tri_fbox overlaps. */
static inline void fbox_tiles(const sgrid *g, const float fb[4], uint32_t r[4])
{
#if SIL_SSE2
    /* tile_of's in each lane, the clamp before the truncation: the last
     * tile (< 2^24) is a float exactly, and the truncation is monotone */
    _mm_storeu_si128((__m128i *)(void *)r, _mm_cvttps_epi32(_mm_min_ps(_mm_mul_ps(_mm_loadu_ps(fb), g->inv4), g->last4)));
#else
    r[0] = tile_of(fb[0], g->inv, g->lx);
    r[1] = tile_of(fb[1], g->inv, g->ly);
    r[2] = tile_of(fb[2], g->inv, g->lx);
    r[3] = tile_of(fb[3], g->inv, g->ly);
#endif
}

#if SIL_SSE2
/* corner_box, box_fbox (finite) and fbox_tiles of window corners p0, p1,
 * p2 in pairs: min and max are the comparisons' (a < b ? a : b), the
 * conversions round as the casts; 0 (fb untouched) when the box misses
 * the image. */
static SIL_INLINE int corner_tiles(const sgrid *g, const ls_real *p0, const ls_real *p1, const ls_real *p2, float fb[4],
                                   uint32_t r[4])
{
    sil_v2 a = V2_LOAD(p0), b = V2_LOAD(p1), c = V2_LOAD(p2), lo, hi;
    const sil_v2 mg = V2_SET(SIL_MARGIN, SIL_MARGIN);
    __m128 v;
    lo = V2_MIN(c, V2_MIN(a, b));
    hi = V2_MAX(c, V2_MAX(a, b));
    if ((V2_LE(lo, g->m2) & V2_GE(hi, V2_SET(-SIL_MARGIN, -SIL_MARGIN)) & 3) != 3) return 0;
    lo = V2_SUB(V2_MAX(lo, V2_SET((ls_real)-1, (ls_real)-1)), mg);
    hi = V2_ADD(V2_MIN(hi, g->l2), mg);
    v = _mm_movelh_ps(V2_FLOAT(lo), V2_FLOAT(hi));
    _mm_storeu_ps(fb, v);
    _mm_storeu_si128((__m128i *)(void *)r, _mm_cvttps_epi32(_mm_min_ps(_mm_mul_ps(v, g->inv4), g->last4)));
    return 1;
}
#endif

/* Adds the bin entries of the tiles r (fbox_tiles) of a binned triangle's
 * box to *count (*over set on overflow of size_t). */
static void tile_count(const uint32_t r[4], size_t *count, int *over)
{
    size_t add = (size_t)(r[2] - r[0] + 1u) * (size_t)(r[3] - r[1] + 1u);
    if (*count > SIZE_MAX - add) *over = 1;
    *count += add;
}

/* Adds the tiles r (fbox_tiles) of a binned triangle's box to the entries
 * of each tile, offs[tile + 2], for bin_pass. */
static inline void tile_add(const sgrid *g, const uint32_t r[4], size_t *offs)
{
    uint32_t tx, ty;
    if ((r[2] - r[0]) <= 1u && (r[3] - r[1]) <= 1u) {
        /* at most 2 x 2 tiles (most triangles): the four counts without
         * loops, whose trip counts mispredict; an absent tile adds 0 to
         * one that is present */
        size_t nx = r[2] - r[0], ny = r[3] - r[1], b = (size_t)r[1] * g->tx + r[0] + 2u;
        size_t d = ny * g->tx;
        offs[b]++;
        offs[b + nx] += nx;
        offs[b + d] += ny;
        offs[b + d + nx] += nx & ny;
        return;
    }
    for (ty = r[1]; ty <= r[3]; ty++)
        for (tx = r[0]; tx <= r[2]; tx++) offs[(size_t)ty * g->tx + tx + 2u]++;
}

/* box_keep's loop; fast: every vertex is in front and every window
 * position finite (the corners' box, tested against the image only). */
static SIL_INLINE uint32_t box_list(const sctx *sc, uint32_t *list, uint32_t n, size_t *offs, int fast)
{
    const uint32_t *ind = sc->indices;
    const ls_real *win = sc->win;
    float *tbox = sc->tbox;
    const signed char *sign = sc->sign;
    const int cull = sc->cull;
    sgrid g;
    uint32_t i, *out = list, r[4];
    grid_init(sc, &g);
    for (i = 0; i < n; i++) {
        uint32_t t = list[i];
        const uint32_t *f = ind + 3 * (size_t)t;
        float *fb = tbox + 4 * (size_t)t;
        ls_real box[4];
        if (cull != 0 && cull * sign[t] >= 0) continue; /* NOLINT(bugprone-signed-char-misuse,cert-str34-c): -2..2 */
        if (fast) {
#if SIL_SSE2
            if (!corner_tiles(&g, win + 2 * (size_t)f[0], win + 2 * (size_t)f[1], win + 2 * (size_t)f[2], fb, r))
                continue;
#else
            corner_box(win + 2 * (size_t)f[0], win + 2 * (size_t)f[1], win + 2 * (size_t)f[2], box, 1);
            if (!box_fbox(&g, box, fb, 1)) continue;
            fbox_tiles(&g, fb, r);
#endif
        } else {
            if (!tri_box(sc, f, box) || !box_fbox(&g, box, fb, 0)) continue;
            fbox_tiles(&g, fb, r);
        }
        tile_add(&g, r, offs);
        *out++ = t;
    }
    return (uint32_t)(out - list);
}

/* Boxes the triangles of list[0..n) not culled into sc->tbox, counts
 * the entries of each tile into offs [tiles + 2] and makes offs[tile + 2]
 * the end of the entries of the tiles before (bin_pass's cursors), so
 * offs[tiles + 1] is the number of bin entries; keeps in list, in order,
 * the binned ones and returns their number (bin_pass's list). count:
 * the bin entries and binned triangles (*over set on overflow). tri_fbox,
 * without the per-triangle front test when every vertex is in front
 * (allfront) and finite (finite). */
LS_NOINLINE static uint32_t box_keep(const sctx *sc, uint32_t *list, uint32_t n, size_t *offs, size_t count[2],
                                     int *over, int finite)
{
    size_t tiles = (size_t)sc->tiles_x * sc->tiles_y, k, sum = 0;
    uint32_t m;
    int ov = 0;
    memset(offs, 0, (tiles + 2u) * sizeof(size_t));
#if SIL_SPECIALIZE
    if (sc->allfront && finite)
        m = box_list(sc, list, n, offs, 1);
    else
        m = box_list(sc, list, n, offs, 0);
#else
    m = box_list(sc, list, n, offs, sc->allfront && finite);
#endif
    /* each tile's count is at most the triangles; only the sum may overflow */
    for (k = 2; k <= tiles + 1u; k++) {
        sum += offs[k];
        ov |= sum < offs[k];
        offs[k] = sum;
    }
    *over = ov;
    count[0] = sum;
    count[1] = m;
    return m;
}

/* The sizing query's count of the bin entries and binned triangles of
 * every triangle into count[0], count[1] (*over set on overflow). */
void ls_sil_box_pass(const sctx *sc, size_t count[2], int *over)
{
    uint32_t t, r[4];
    float fb[4];
    sgrid g;
    grid_init(sc, &g);
    count[0] = 0;
    count[1] = 0;
    *over = 0;
    for (t = 0; t < sc->triangle_count; t++) {
        if (!tri_fbox(sc, &g, t, fb)) continue;
        fbox_tiles(&g, fb, r);
        tile_count(r, count, over);
        count[1]++;
    }
}

/* Bins the triangles of list[0..n) (in increasing order, each binned:
 * their boxes sc->tbox counted into offs [tiles + 2] by box_keep) into
 * the tiles their boxes overlap: offs becomes the bin starts (offs[tiles]
 * the total), ent the bins (triangles in index order in each). */
static void bin_pass(const sctx *sc, const uint32_t *list, uint32_t n, size_t *offs, uint32_t *ent)
{
    const float *tbox = sc->tbox;
    uint32_t i, tx, ty, r[4];
    sgrid g;
    grid_init(sc, &g);
    offs++; /* offs[tile + 1], the tile's start, is its cursor: it ends as its end, the next tile's start */
    for (i = 0; i < n; i++) {
        uint32_t t = list[i];
        fbox_tiles(&g, tbox + 4 * (size_t)t, r);
        if ((r[2] - r[0]) <= 1u && (r[3] - r[1]) <= 1u) {
            /* at most 2 x 2 tiles, as tile_add counted them, with no loops
             * (their trip counts mispredict) and no branch: an absent tile
             * is one of the tiles after it in this order (nx, ny = 0), so
             * its entry is written again there, and then kept */
            size_t nx = r[2] - r[0], ny = r[3] - r[1], b = (size_t)r[1] * g.tx + r[0];
            size_t d = ny * g.tx;
            ent[offs[b + d + nx]] = t;
            offs[b + d + nx] += nx & ny;
            ent[offs[b + d]] = t;
            offs[b + d] += ny;
            ent[offs[b + nx]] = t;
            offs[b + nx] += nx;
            ent[offs[b]++] = t;
            continue;
        }
        for (ty = r[1]; ty <= r[3]; ty++)
            for (tx = r[0]; tx <= r[2]; tx++) ent[offs[(size_t)ty * g.tx + tx]++] = t;
    }
}

/* ls_sil_choose_cull's count of a sample showing id into cnt: covered, showing
 * a positive and a negative orientation (sign, or tri_sign when NULL; only
 * for an id up to lim). Inlined, so the counts stay in registers
 * (increments of a counter in memory chain through it). */
static SIL_INLINE void cull_count(const sctx *sc, const signed char *sign, uint32_t lim, uint32_t id, uint64_t cnt[3])
{
    int sg;
    if (id == 0) return;
    cnt[0]++;
    if (id > lim) return;
    /* NOLINTNEXTLINE(bugprone-signed-char-misuse,cert-str34-c): -2..2 */
    sg = sign != NULL ? sign[id - 1u] : tri_sign(sc, sc->indices + 3 * (size_t)(id - 1u));
    cnt[1] += (uint64_t)(sg > 0);
    cnt[2] += (uint64_t)(sg < 0);
}

/* Orientation culling of the candidates: for a closed mesh (no boundary
 * edge) of which nothing crosses the near plane, seen from outside, the
 * triangles of one orientation (back faces) are never the nearest surface
 * of the exact geometry: they can neither hide an edge nor be the surface
 * behind one, and are left out of the bins. Seen from outside means: the
 * samples showing the other orientation are fewer than 1/64 of those
 * showing this one (the snapped forward shows a few back faces at the rim;
 * an eye inside the mesh sees almost only back faces), counted on every
 * 4th sample row, every 8th from 256 rows, every 16th from 512 (the
 * choice never changes what is integrated, only which triangles are
 * tested).
 * sign: per-triangle orientations (tri_sign), or NULL (the sizing query:
 * no memory for them). Returns the covered samples estimated from those
 * rows, for ls_sil_choose_tiles (counted alone, lim = 0, when nothing can be
 * culled). */
uint64_t ls_sil_choose_cull(sctx *sc, const ls_edge_table *table, const signed char *sign)
{
    const ls_vis *vis = sc->vis;
    const uint32_t *tri = vis->tri;
    uint64_t cnt[3] = {0, 0, 0}, q[2]; /* covered, positive, negative */
    uint32_t v, x, y, k, lim = sc->triangle_count, step = vis->sh < 256u ? 4u : (vis->sh < 512u ? 8u : 16u);
    sc->cull = 0;
    if (table->boundary_edges != 0 || sc->behind != 0) lim = 0;
    for (v = 0; sign == NULL && v < vis->vertex_count; v++) { /* with sign, sc->behind counted them */
        const ls_real *cl = vis->clip + 4 * (size_t)v;
        if (!(cl[2] + cl[3] >= (ls_real)0)) lim = 0;
    }
    for (y = 0; y < vis->sh; y += step) {
        const uint32_t *row = tri + (size_t)y * vis->sw;
        /* samples by fours, most of which show nothing: two 8-byte loads test them */
        for (x = 0; x + 4u <= vis->sw; x += 4u) {
            memcpy(q, row + x, sizeof q);
            if ((q[0] | q[1]) == 0) continue;
            SIL_UNROLL
            for (k = 0; k < 4u; k++) cull_count(sc, sign, lim, row[x + k], cnt);
        }
        for (; x < vis->sw; x++) cull_count(sc, sign, lim, row[x], cnt);
    }
    /* with lim = 0, both are 0: no culling */
    if (cnt[2] < cnt[1] / 64u) sc->cull = -1;
    if (cnt[1] < cnt[2] / 64u) sc->cull = 1;
    return cnt[0] * step;
}

/* The bins' tile side, 2^tl pixels: 2, 4 or 8 by the covered pixels per
 * triangle (cov: ls_sil_choose_cull's estimate of the covered samples): small
 * triangles want small tiles (fewer candidates per run), large ones large
 * tiles (fewer entries per triangle, fewer and longer runs). The
 * thresholds, 1/8 and 1/2 covered pixel per triangle, are the measured
 * crossovers on the armadillo at 128^2 to 512^2 and the bunny at 64^2 and
 * 128^2 (the choice changes no bit, only which triangles are tested).
 * 2 x 2 is the smallest, so sizes counted with 2 x 2 tiles (the bounds
 * below) hold for every choice. */
void ls_sil_choose_tiles(sctx *sc, uint64_t cov)
{
    const ls_vis *vis = sc->vis;
    uint64_t ts = (uint64_t)sc->triangle_count * vis->ss * vis->ss;
    /* ts: triangles x samples per pixel */
    sc->tl = 8u * cov < ts ? SIL_TILE_LOG2 : (2u * cov < ts ? SIL_TILE_LOG2 + 1u : SIL_TILE_LOG2 + 2u);
    sc->tiles_x = (vis->width + (1u << sc->tl) - 1u) >> sc->tl;
    sc->tiles_y = (vis->height + (1u << sc->tl) - 1u) >> sc->tl;
    sc->tside_inv = 1.0f / (float)(1u << sc->tl);
}

/* next_edge's loop; open: the mesh has boundary edges (twins to clamp).
 * One branch per face, on whether any of its edges is a candidate: few
 * are (the contour's), so it is mostly not taken and the bits' updates
 * are skipped, with fewer mispredictions than a branch per edge. */
static SIL_INLINE void mark_faces(const sctx *sc, const uint32_t *list, uint32_t n, uint64_t *bits, int open)
{
    const signed char *sign = sc->sign;
    const uint32_t *twin = sc->twin;
    uint32_t i, k, tc = sc->triangle_count;
    for (i = 0; i < n; i++) {
        uint32_t h = 3u * list[i], tw[3], mk[3];
        int s = sign[list[i]] + 4; /* NOLINT(bugprone-signed-char-misuse,cert-str34-c): small integers (-2..2), not characters */
        SIL_UNROLL
        for (k = 0; k < 3u; k++) {
            uint32_t fu;
            tw[k] = twin[h + k];
            fu = tw[k] / 3u;
            if (open) fu = fu < tc ? fu : tc;
            mk[k] = (uint32_t)(((s + sign[fu]) & 7) != 0); /* NOLINT(bugprone-signed-char-misuse,cert-str34-c): the sum is not +-4 */
        }
        if ((mk[0] | mk[1] | mk[2]) == 0) continue;
        SIL_UNROLL
        for (k = 0; k < 3u; k++, h++) {
            uint32_t c = tw[k] < h ? tw[k] : h;
            bits[c >> 6] |= (uint64_t)mk[k] << (c & 63u);
        }
    }
}

/* Marks in bits [3 T / 64 + 1] the candidate silhouette edges, each at its
 * smaller half-edge (edges_pass takes them in that order): a boundary edge,
 * or an interior edge whose faces are not both certain of one orientation.
 * Only the faces of list[0..n) are visited: every candidate has one (the
 * faces whose sign is not that of certain culled ones; every face when
 * nothing is culled, as with boundary edges). A boundary twin's face is
 * clamped to the sentinel sign[tc] = 0, so its sum is never +-4 and it is
 * a candidate, as it must be. */
static void next_edge(const sctx *sc, const uint32_t *list, uint32_t n, uint64_t *bits, int open)
{
    memset(bits, 0, (3 * (size_t)sc->triangle_count / 64u + 1u) * sizeof(uint64_t));
#if SIL_SPECIALIZE
    if (open)
        mark_faces(sc, list, n, bits, 1);
    else
        mark_faces(sc, list, n, bits, 0);
#else
    mark_faces(sc, list, n, bits, open);
#endif
}

/* ls_sil_setup_pass's orientations (tri_sign) of the triangles into sign, each
 * triangle's tbox entry unbinned (x0 > x1) until box_keep boxes it and,
 * on the guess that the culled faces are those certain of sign -2
 * (ls_sil_choose_cull's cull = -1: a closed mesh wound counterclockwise, seen
 * from outside), the others listed in keep, their number returned
 * (ls_sil_setup_pass lists them again when the guess fails). allfront:
 * sc->allfront (no per-triangle front test). */
static SIL_INLINE uint32_t sign_pass(const sctx *sc, signed char *sign, uint32_t *keep, ls_real wkb, int allfront)
{
    const uint32_t *indices = sc->indices;
    const unsigned char *vfront = sc->vfront;
    float *fb = sc->tbox;
    uint32_t t, n = 0, tc = sc->triangle_count;
    for (t = 0; t < tc; t++, fb += 4) {
        const uint32_t *f = indices + 3 * (size_t)t;
        int s = allfront || (vfront[f[0]] & vfront[f[1]] & vfront[f[2]]) != 0 ? tri_sign_front(sc, f, wkb)
                                                                                : tri_sign(sc, f);
        sign[t] = (signed char)s;
        fb[0] = 1.0f;
        fb[2] = 0.0f;
        keep[n] = t;
        n += (uint32_t)(s != -2);
    }
    return n;
}

/* The pass's per-view set-up, after ls_sil_sctx_init: window positions and
 * depths, orientations, culling, tiles, the contour marks (bits), boxes,
 * bins and the candidate slots, all in scratch. Out of line: its locals
 * stay out of the frame that the deep chain below edges_pass adds to (the
 * MCU's 4 KiB job stack). */
LS_NOINLINE ls_status ls_sil_setup_pass(sctx *out, const ls_edge_table *table, uint32_t vertex_count,
                                        uint64_t **bitsp, uint64_t **ordp, ls_arena *arena)
{
    /* a copy of its own: the compiler keeps a local context's fields in
     * registers across the byte stores of the orientations, which may
     * alias anything reached through a pointer */
    sctx own = *out, *sc = &own;
    const ls_vis *vis = sc->vis;
    const ls_real *cl = vis->clip;
    uint32_t t, h, triangle_count = sc->triangle_count, *keep, nkeep = 0, nfront = 0, behind = 0;
    ls_real wk = (ls_real)0, msum = (ls_real)0;
    int cull;
    size_t count[2] = {0, 0}, slots;
    int over = 0;
    signed char *sign;
    unsigned char *vfront;
    ls_real *win, *zv, wkb;
    size_t *offs;
    uint32_t *ent;
    uint64_t *bits;
#if SIL_SSE2
    const sil_v2 flip = V2_SET((ls_real)0, -(ls_real)0), one = V2_SET((ls_real)1, (ls_real)1),
                 wh = V2_SET(sc->width, sc->height), half = V2_SET((ls_real)0.5, (ls_real)0.5);
#endif
    win = (ls_real *)ls_arena_scratch(arena, 2 * (size_t)vertex_count, sizeof(ls_real));
    zv = win ? (ls_real *)ls_arena_scratch(arena, (size_t)vertex_count, sizeof(ls_real)) : NULL;
    sign = zv ? (signed char *)ls_arena_scratch(arena, (size_t)triangle_count + 1u, 1) : NULL;
    vfront = sign ? (unsigned char *)ls_arena_scratch(arena, (size_t)vertex_count, 1) : NULL;
    sc->tbox = vfront ? (float *)ls_arena_scratch(arena, (size_t)triangle_count, 4 * sizeof(float)) : NULL;
    keep = sc->tbox ? (uint32_t *)ls_arena_scratch(arena, (size_t)triangle_count, sizeof(uint32_t)) : NULL;
    bits = keep ? (uint64_t *)ls_arena_scratch(arena, 3 * (size_t)triangle_count / 64u + 1u, sizeof(uint64_t)) : NULL;
    if (bits == NULL) return LS_ERR_NOMEM;
    for (h = 0; h < vertex_count; h++, cl += 4) { /* behind, wk and msum in registers, not through sc */
        ls_real w = cl[3];
        int near = cl[2] + w >= (ls_real)0, fr = near & (w > (ls_real)0);
        vfront[h] = (unsigned char)fr;
        behind += (uint32_t)!near;
        nfront += (uint32_t)fr;
        if (fr) {
            ls_real p[2], m;
#if SIL_SSE2
            /* window_of in pairs: (x / w + 1, -(y / w) + 1) x (width, height) x 0.5 */
            V2_STORE(p, V2_MUL(V2_MUL(V2_ADD(V2_XOR(V2_DIV(V2_LOAD(cl), V2_SET(w, w)), flip), one), wh), half));
#else
            window_of(sc, cl, p);
#endif
            win[2 * (size_t)h] = p[0];
            win[2 * (size_t)h + 1] = p[1];
            zv[h] = cl[2] / w;
            m = r_abs(p[0]) + r_abs(p[1]);
            msum += m; /* finite only when every m is */
            if (m > wk) wk = m; /* inf: no bound is finite; NaN: its triangles' cross products are NaN */
        } else {
            win[2 * (size_t)h] = (ls_real)0;
            win[2 * (size_t)h + 1] = (ls_real)0;
            zv[h] = (ls_real)0;
        }
    }
    sc->behind = behind;
    sc->wk = ((ls_real)3 * wk + sc->width) + sc->height;
    sc->allfront = nfront == vertex_count;
    /* with M = max(|x| + |y|) <= wk / 3, each |d| sum is at most 4 M and |t1|, |t2| at most 4 M^2:
     * tri_sign_front's bound is below 16 eps (20 wk^2 / 9 + eps wk) + 64 min, far below this */
    wkb = (ls_real)64 * LS_REAL_EPSILON * sc->wk * (sc->wk + (ls_real)1) + (ls_real)128 * R_MIN_NORMAL;
    sc->win = win;
    sc->zv = zv;
    sc->vfront = vfront;
#if SIL_SPECIALIZE
    if (sc->allfront)
        nkeep = sign_pass(sc, sign, keep, wkb, 1);
    else
        nkeep = sign_pass(sc, sign, keep, wkb, 0);
#else
    nkeep = sign_pass(sc, sign, keep, wkb, sc->allfront);
#endif
    sign[triangle_count] = 0; /* next_edge's sentinel for boundary twins */
    sc->sign = sign;
    sc->twin = table->twin;
    ls_sil_choose_tiles(sc, ls_sil_choose_cull(sc, table, sign));
    offs = (size_t *)ls_arena_scratch(arena, (size_t)sc->tiles_x * sc->tiles_y + 2u, sizeof(size_t)); /* by the tiles */
    if (offs == NULL) return LS_ERR_NOMEM;
    /* the faces not certain of the culled orientation (all when nothing is
     * culled), listed without a branch (orientations have no pattern):
     * next_edge's faces, and box_keep's after its cull test (false only for
     * the few uncertain ones); sign_pass listed them when its guess holds */
    cull = sc->cull;
    if (cull != -1) {
        nkeep = 0;
        for (t = 0; t < triangle_count; t++) {
            keep[nkeep] = t;
            nkeep += (uint32_t)(sign[t] != 2 * cull + 3 * (cull == 0)); /* NOLINT(bugprone-signed-char-misuse,cert-str34-c): -2..2 */
        }
    }
    next_edge(sc, keep, nkeep, bits, table->boundary_edges != 0);
    nkeep = box_keep(sc, keep, nkeep, offs, count, &over, msum <= R_MAX);
    slots = slot_count(count[1], count[0]);
    if (over || slots > (SIZE_MAX - 2u) / 4u) return LS_ERR_TOO_LARGE;
    ent = (uint32_t *)ls_arena_scratch(arena, count[0], sizeof(uint32_t));
    sc->cid = ent ? (uint32_t *)ls_arena_scratch(arena, slots, sizeof(uint32_t)) : NULL;
    sc->chi = sc->cid ? (ls_real *)ls_arena_scratch(arena, slots, sizeof(ls_real)) : NULL;
    sc->clo = sc->chi ? (ls_real *)ls_arena_scratch(arena, slots, sizeof(ls_real)) : NULL;
    sc->cord = sc->clo ? (uint32_t *)ls_arena_scratch(arena, slots, sizeof(uint32_t)) : NULL;
    sc->cact = sc->cord ? (uint32_t *)ls_arena_scratch(arena, slots, sizeof(uint32_t)) : NULL;
    sc->split = sc->cact ? (ls_real *)ls_arena_scratch(arena, 4u * slots + 2u, sizeof(ls_real)) : NULL;
    sc->piece = sc->split ? (spiece *)ls_arena_scratch(arena, 1, sizeof(spiece)) : NULL;
    sc->wend = sc->piece ? (uint32_t *)ls_arena_scratch(arena, (size_t)vertex_count, sizeof(uint32_t)) : NULL;
    if (sc->wend == NULL) return LS_ERR_NOMEM;
    memset(sc->piece, 0, sizeof *sc->piece); /* once: integrate sets, per sub-piece, what it reads */
    memset(sc->wend, 0, (size_t)vertex_count * sizeof(uint32_t)); /* no walk has reached a vertex yet */
    bin_pass(sc, keep, nkeep, offs, ent);
    sc->offs = offs;
    sc->ent = ent;
    *bitsp = bits;
    *ordp = (uint64_t *)(void *)keep; /* free from here on: edges_pass's order (2 (T / 4) entries; 8-byte aligned) */
    *out = own;
    return LS_OK;
}
