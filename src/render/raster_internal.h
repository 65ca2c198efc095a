/* raster_internal.h - the rasterizer's shared state (private to src/render):
 * the transformed vertices, clipped polygons, snapped triangles and their
 * sample boxes, and the fixed-point edge tests that raster_triangle.c (a
 * triangle's set-up) and raster.c (the passes and the drawing) both use.
 * Design and conventions: include/largesteps/raster.h. */
#ifndef LS_RASTER_INTERNAL_H
#define LS_RASTER_INTERNAL_H
#include <largesteps/raster.h>
#include "render_internal.h"
#include <string.h>

#define VIS_MAGIC 0x56495342u /* "VISB" */
#define SUB_ONE 256           /* one sample in fixed point */
#define SUB_HALF 128
#define FIX_LIMIT 8388608.0f  /* 2^23: clamp of snapped coordinates (|x| < guard + max dim) */
#define MAX_POLY 8            /* a triangle clipped by 5 planes has at most 8 vertices */
#define NPLANES 5
#define FLAG_OUT_MASK 0x1Fu   /* bits 0..4: outside plane k */
#define FLAG_BAD_W 0x20u      /* W <= 0 although no plane rejects it */

/* The transformed vertices, as arrays (scratch, one block of VERT_BYTES per
 * vertex; the on-the-fly count pass of the queries holds three): the count
 * pass reads only snap and flags, and clip, snap and flags go to the vis
 * whole. */
typedef struct vbuf {
    ls_real *clip;   /* clip coordinates, 4 per vertex */
    ls_real *zi;     /* Z/W and 1/W (valid when flags == 0) */
    int32_t *snap;   /* snapped window position, 1/256 samples (valid when flags == 0) */
    uint32_t *flags; /* planes the vertex is outside of */
} vbuf;
#define VERT_BYTES (6 * sizeof(ls_real) + 3 * sizeof(int32_t))

/* A polygon vertex during clipping: clip coordinates and the barycentric
 * weights (b0, b1) of the original triangle's first two vertices. */
typedef struct pvert {
    ls_real c[4];
    ls_real b[2];
} pvert;

typedef struct clipbuf {
    pvert a[MAX_POLY];
    pvert b[MAX_POLY];
} clipbuf;

/* One screen triangle ready to draw, positively oriented. */
typedef struct stri {
    int32_t x[3], y[3];
    ls_real zw[3], iw[3];
    ls_real b[3][2]; /* weights of the original triangle's vertices 0 and 1 */
    int64_t area;    /* twice the area, > 0 */
} stri;

/* Per-call constants. */
typedef struct rctx {
    const ls_real *m;
    ls_real sw_half, sh_half; /* sample grid size / 2 */
    ls_real gx, gy;           /* guard-band planes: |X| <= gx W, |Y| <= gy W */
    uint32_t sw, sh, tiles_x, tiles_y;
} rctx;

/* Clamped round-to-nearest of a real to int32 (NaN -> 0). */
static inline int32_t snap_round(ls_real v)
{
    ls_real f = v * (ls_real)SUB_ONE;
    int32_t t;
    if (!(f > -(ls_real)FIX_LIMIT)) f = -(ls_real)FIX_LIMIT; /* also NaN */
    if (f > (ls_real)FIX_LIMIT) f = (ls_real)FIX_LIMIT;
    f += (ls_real)0.5;
    t = (int32_t)f; /* truncation toward zero, |f| <= 2^23 + 1 */
    if ((ls_real)t > f) t -= 1; /* floor */
    return t;
}

typedef struct sbox {
    int64_t x0, y0, x1, y1; /* inclusive sample range */
} sbox;

/* Twice the signed area of the snapped triangle (x, y). */
static inline int64_t snap_area2(const int32_t x[3], const int32_t y[3])
{
    return ((int64_t)x[1] - x[0]) * ((int64_t)y[2] - y[0]) - ((int64_t)y[1] - y[0]) * ((int64_t)x[2] - x[0]);
}

/* floor(v / 256) for |v| < 2^30 (snapped coordinates are within 2^23 + 1);
 * shifts only non-negative values (>> of negative ones is
 * implementation-defined). */
static inline int64_t floor_div_sub(int64_t v)
{
    return ((v + ((int64_t)1 << 30)) >> LS_RASTER_SUBPIXEL_BITS) - ((int64_t)1 << (30 - LS_RASTER_SUBPIXEL_BITS));
}

/* The samples [*r0, *r1] (inclusive, clamped to [0, n - 1]) whose centres
 * lie within the snapped coordinates c[0..2]; 0 when there is none. */
static inline int sample_range(const int32_t c[3], uint32_t n, int64_t *r0, int64_t *r1)
{
    int32_t lo = c[0], hi = c[0];
    if (c[1] < lo) lo = c[1];
    if (c[1] > hi) hi = c[1];
    if (c[2] < lo) lo = c[2];
    if (c[2] > hi) hi = c[2];
    *r0 = floor_div_sub((int64_t)lo - SUB_HALF + SUB_ONE - 1);
    *r1 = floor_div_sub((int64_t)hi - SUB_HALF);
    if (*r0 < 0) *r0 = 0;
    if (*r1 > (int64_t)n - 1) *r1 = (int64_t)n - 1;
    return *r0 <= *r1;
}

/* Sample range whose centres may be covered by the snapped triangle (x, y)
 * (in any vertex order), clamped to the grid; returns 0 when empty (b is
 * then partly set: the y range is not computed when the x range is empty). */
static inline int snap_box(uint32_t sw, uint32_t sh, const int32_t x[3], const int32_t y[3], sbox *b)
{
    return sample_range(x, sw, &b->x0, &b->x1) && sample_range(y, sh, &b->y0, &b->y1);
}

/* The weights of an unclipped triangle's vertices 0 and 1 at its screen
 * triangle's vertices: as given, and with vertices 1 and 2 swapped. */
static const ls_real unit_b[2][3][2] = {{{1, 0}, {0, 1}, {0, 0}}, {{1, 0}, {0, 0}, {0, 1}}};

/* Loads the snapped vertices (x, y) of unclipped triangle v (in vb). */
static inline void snap_load(const int32_t *snap, const size_t v[3], int32_t x[3], int32_t y[3])
{
    /* unrolled by hand: gcc -O2 keeps small loops over arrays in memory */
    x[0] = snap[2 * v[0]];
    y[0] = snap[2 * v[0] + 1];
    x[1] = snap[2 * v[1]];
    y[1] = snap[2 * v[1] + 1];
    x[2] = snap[2 * v[2]];
    y[2] = snap[2 * v[2] + 1];
}

/* snap_load, returning twice the triangle's signed area. */
static inline int64_t unclipped_load(const int32_t *snap, const size_t v[3], int32_t x[3], int32_t y[3])
{
    snap_load(snap, v, x, y);
    return snap_area2(x, y);
}

/* Swaps vertices 1 and 2 of (x, y) when its twice-area a is negative: the
 * orientation make_stri gives it. */
static inline void orient(int32_t x[3], int32_t y[3], int64_t a)
{
    if (a < 0) {
        int32_t tx = x[1], ty = y[1];
        x[1] = x[2];
        y[1] = y[2];
        x[2] = tx;
        y[2] = ty;
    }
}

/* Edge function of a positively oriented screen triangle from vertex a to
 * vertex b: its value at the first sample of a box, biased by the top-left
 * rule (inside <=> all three >= 0), and its decrease per sample along x (dx)
 * and increase per sample along y (dy). */
typedef struct edgef {
    int64_t e, dx, dy, bias;
} edgef;

static inline void edge_init(edgef *g, const int32_t x[3], const int32_t y[3], int a, int b, int64_t px0, int64_t py0)
{
    int64_t dx = (int64_t)x[b] - x[a], dy = (int64_t)y[b] - y[a];
    g->bias = (dy < 0 || (dy == 0 && dx > 0)) ? 0 : -1; /* top-left rule */
    g->e = dx * (py0 - y[a]) - dy * (px0 - x[a]) + g->bias;
    g->dx = dy * SUB_ONE;
    g->dy = dx * SUB_ONE;
}

/* The three edges at sample (i, j); edge k is opposite vertex k (from
 * vertex k+1 to vertex k+2). */
static inline void edges_init(edgef g[3], const int32_t x[3], const int32_t y[3], int64_t i, int64_t j)
{
    const int64_t px0 = i * SUB_ONE + SUB_HALF, py0 = j * SUB_ONE + SUB_HALF;
    edge_init(&g[0], x, y, 1, 2, px0, py0);
    edge_init(&g[1], x, y, 2, 0, px0, py0);
    edge_init(&g[2], x, y, 0, 1, px0, py0);
}

/* 1 when the edge from vertex a to vertex b of a positively oriented
 * screen triangle is a top or left one (samples on it are inside). */
static inline int top_left(const int32_t x[3], const int32_t y[3], int a, int b)
{
    int32_t dy = y[b] - y[a];
    return dy < 0 || (dy == 0 && x[b] > x[a]);
}

/* sample_edges' rare case, a sample on an edge (some e[k] == 0, none < 0):
 * 1 when it is inside. Out of line, so that the compiler does not hoist the
 * edge tests out of the sample loops (docs/fast-paths.md). */
LS_NOINLINE static int on_edge_inside(const int32_t x[3], const int32_t y[3], const int64_t e[3])
{
    return (e[0] != 0 || top_left(x, y, 1, 2)) && (e[1] != 0 || top_left(x, y, 2, 0)) &&
           (e[2] != 0 || top_left(x, y, 0, 1));
}

/* The exact edge values e of the positively oriented snapped triangle
 * (x, y) of twice-area a at the centre of sample (i, j), e[k] for the edge
 * from vertex k + 1 to vertex k + 2 (as edges_init, without the bias: their
 * sum is a); returns 1 when the sample is covered (all >= 0, a zero one only
 * on a top or left edge). */
static inline int sample_edges(const int32_t x[3], const int32_t y[3], int64_t a, int64_t i, int64_t j, int64_t e[3])
{
    const int64_t px = i * SUB_ONE + SUB_HALF, py = j * SUB_ONE + SUB_HALF;
    e[1] = ((int64_t)x[0] - x[2]) * (py - y[2]) - ((int64_t)y[0] - y[2]) * (px - x[2]);
    e[2] = ((int64_t)x[1] - x[0]) * (py - y[0]) - ((int64_t)y[1] - y[0]) * (px - x[0]);
    e[0] = a - e[1] - e[2];
    if ((e[0] | e[1] | e[2]) < 0) return 0;
    if (e[0] != 0 && e[1] != 0 && e[2] != 0) return 1;
    return on_edge_inside(x, y, e);
}

/* Boxes of at most this many samples are drawn sample by sample, larger
 * ones by rows (the fewest instructions: docs/fast-paths.md). */
#define DRAW_SMALL 12

#define RECT_DIRECT 0x8000u /* in a rect's x0 (samples are < LS_RASTER_MAX_DIM <= 2^15) */

/* Unclipped triangles of at most DRAW_SMALL samples (most of them at 128^2)
 * skip the bins and are drawn straight after the count pass: the depth test
 * does not depend on the drawing order, and binning them costs more than
 * drawing them. Their boxes are narrower than a tile (mark_tiles). */
static inline int box_direct(const sbox *b)
{
    return (b->x1 - b->x0 + 1) * (b->y1 - b->y0 + 1) <= DRAW_SMALL;
}

/* The sample range of an unclipped triangle v (in vb); 0 if empty. It is
 * its own screen triangle, whose box and area do not depend on the vertex
 * order: no screen triangle is built. */
static inline int unclipped_box(const rctx *cx, const int32_t *snap, const size_t v[3], sbox *u)
{
    int32_t x[3], y[3];
    /* the box first: a third of the fit's triangles at 10k vertices have
     * none, and their area is not needed */
    snap_load(snap, v, x, y);
    return snap_box(cx->sw, cx->sh, x, y, u) && snap_area2(x, y) != 0;
}

/* ---- what each file offers the others ---- */

/* raster_triangle.c */
void ls_rast_ctx_init(rctx *cx, const ls_real mvp[16], uint32_t sw, uint32_t sh);
uint32_t ls_rast_transform_all(const rctx *cx, const ls_real *positions, const uint32_t *idx,
                                                 uint32_t count, const vbuf *vb);
int ls_rast_clipped_prepare(const rctx *cx, const vbuf *vb, const size_t v[3], clipbuf *cb);
int ls_rast_clipped_sub(const rctx *cx, const clipbuf *cb, int k, stri *out);
int ls_rast_clipped_box(const rctx *cx, const vbuf *vb, const size_t v[3], clipbuf *cb, sbox *u);

#endif
