/* silhouette.c - exact box-filter silhouette derivatives (largesteps/silhouette.h). */
#include <largesteps/silhouette.h>
#include "render_internal.h"
#include <largesteps/sort.h>
#include <largesteps/math.h>
#include <float.h>
#include <math.h>
#include <string.h>

#if LS_REAL_IS_FLOAT
#define R_SQRT sqrtf
#define R_MIN_NORMAL FLT_MIN
#define R_MAX FLT_MAX
#else
#define R_SQRT sqrt
#define R_MIN_NORMAL DBL_MIN
#define R_MAX DBL_MAX
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
    ls_diag_clear(diag);
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

#define SIL_TILE_LOG2 1u                        /* candidate bins: tiles of at least 2 x 2 pixels (choose_tiles) */
#define SIL_MARGIN ((ls_real)1 / (ls_real)64)  /* pixels by which bin and candidate boxes grow */
/* Inlined where called, so that a copy sees a constant corner count and
 * its loops unroll (GCC wants the pragma; clang unrolls them unasked); not
 * where code size counts (LS_FAST_PATHS off: -Os, the MCU), which keeps one copy. */
#if (defined(__GNUC__) || defined(__clang__)) && LS_FAST_PATHS
#define SIL_INLINE __attribute__((always_inline)) inline
#define SIL_SPECIALIZE 1
#else
#define SIL_INLINE inline
#define SIL_SPECIALIZE 0
#endif
/* Cache hints (a fast path, off with LS_FAST_PATHS, as on the MCU, which has
 * no data cache): the work per silhouette edge is thousands of instructions,
 * more than the processor looks ahead, so the scattered loads of the next
 * edges (their vertices, forward sample, pixels; candidates' vertices) are
 * started by hand (fetch_edge, fetch_walk). A hint changes no result. */
#if (defined(__GNUC__) || defined(__clang__)) && LS_FAST_PATHS
#define SIL_FETCH 1
#define SIL_PREFETCH(p) __builtin_prefetch(p)
#else
#define SIL_FETCH 0
#define SIL_PREFETCH(p) ((void)(p))
#endif
#define SIL_AHEAD 8u /* edges_pass: fetch_edge this many edges ahead, fetch_walk half as many */
#if defined(__GNUC__) && !defined(__clang__) && LS_FAST_PATHS
#define SIL_UNROLL _Pragma("GCC unroll 4")
#else
#define SIL_UNROLL
#endif
#define SIL_LOOSE ((ls_real)1 / (ls_real)16384) /* px^2: a view bound c0v above it widens intervals (cand_interval) */
#define SIL_DEPTH_CAP 4                         /* adaptive quadrature: at most 2^4 parts per sub-piece */
/* run_pass's gather tests a box against the run's in one packed comparison
 * where SSE is there (x86; a fast path: the scalar test gives the same hits) */
#if LS_FAST_PATHS && (defined(__SSE__) || defined(_M_X64))
#include <xmmintrin.h>
#define SIL_SSE 1
#else
#define SIL_SSE 0
#endif
/* SSE2 (x86-64, a fast path): fbox_tiles converts a box's four coordinates
 * in one, and run_pass tests a hit's corners against the end vertices in one */
#if LS_FAST_PATHS && (defined(__SSE2__) || defined(_M_X64))
#include <emmintrin.h>
#define SIL_SSE2 1
/* corner_tiles' (x, y) pairs of ls_real in the low lanes */
#if LS_REAL_IS_FLOAT
typedef __m128 sil_v2;
#define V2_LOAD(p) _mm_loadl_pi(_mm_setzero_ps(), (const __m64 *)(const void *)(p))
#define V2_SET(x, y) _mm_setr_ps(x, y, 1.0f, 1.0f) /* 1: no 0 / 0 in a division's unused lanes */
#define V2_MIN _mm_min_ps
#define V2_MAX _mm_max_ps
#define V2_ADD _mm_add_ps
#define V2_SUB _mm_sub_ps
#define V2_MUL _mm_mul_ps
#define V2_DIV _mm_div_ps
#define V2_XOR _mm_xor_ps
#define V2_LE(a, b) _mm_movemask_ps(_mm_cmple_ps(a, b))
#define V2_GE(a, b) _mm_movemask_ps(_mm_cmpge_ps(a, b))
#define V2_FLOAT(v) (v)
#define V2_SWAP(v) _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 2, 0, 1))
#define V2_LO(v) _mm_cvtss_f32(v)
#define V2_HI(v) _mm_cvtss_f32(_mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 2, 0, 1)))
#define V2_STORE(p, v) _mm_storel_pi((__m64 *)(void *)(p), v)
#else
typedef __m128d sil_v2;
#define V2_LOAD(p) _mm_loadu_pd(p)
#define V2_SET(x, y) _mm_setr_pd(x, y)
#define V2_MIN _mm_min_pd
#define V2_MAX _mm_max_pd
#define V2_ADD _mm_add_pd
#define V2_SUB _mm_sub_pd
#define V2_MUL _mm_mul_pd
#define V2_DIV _mm_div_pd
#define V2_XOR _mm_xor_pd
#define V2_LE(a, b) _mm_movemask_pd(_mm_cmple_pd(a, b))
#define V2_GE(a, b) _mm_movemask_pd(_mm_cmpge_pd(a, b))
#define V2_FLOAT(v) _mm_cvtpd_ps(v)
#define V2_SWAP(v) _mm_shuffle_pd(v, v, 1)
#define V2_LO(v) _mm_cvtsd_f64(v)
#define V2_HI(v) _mm_cvtsd_f64(_mm_unpackhi_pd(v, v))
#define V2_STORE(p, v) _mm_storeu_pd(p, v)
#endif
#else
#define SIL_SSE2 0
#endif

struct spiece;

typedef struct sctx {
    const ls_vis *vis;
    const uint32_t *indices;
    const ls_real *normals;
    const ls_shade_opts *o;
    const ls_real *m;
    const ls_real *gimg;
    const ls_real *win;  /* [2 V] window position of the vertices in front of the near plane, or NULL */
    const unsigned char *vfront; /* [V] 1 for those vertices (Z + W >= 0, W > 0), or NULL */
    const ls_real *zv;   /* [V] NDC depth Z / W of those vertices (walks, window_hold, segment ends) */
    uint32_t behind;     /* vertices behind the near plane (Z + W < 0) */
    const size_t *offs;  /* [tiles + 1] bin starts */
    const uint32_t *ent; /* bin entries: triangle indices, increasing within a bin */
    float *tbox;         /* [4 T] box of each triangle (tri_fbox; x0 > x1: not binned) */
    /* the current piece's candidates, at most one per bin entry of a tile: */
    uint32_t *cid;       /* [slots] triangle of each candidate */
    ls_real *chi;        /* [slots] end of its interval */
    ls_real *clo;        /* [slots] starts of the intervals, sorted along with cord */
    uint32_t *cord;      /* [slots] the candidates in order of their starts */
    uint32_t *cact;      /* [slots] the active ones */
    ls_real *split;      /* [4 slots + 2] split parameters of the current piece */
    uint32_t triangle_count, tiles_x, tiles_y, flat;
    uint32_t tl;         /* tiles of 2^tl x 2^tl pixels (choose_tiles) */
    float tside_inv;     /* 2^-tl (tile_of) */
    const signed char *sign; /* [T] orientation of each triangle (tri_sign), or NULL */
    const uint32_t *twin; /* the edge table's twins (walks across edges), or NULL */
    int allfront;        /* 1: every vertex is in front (vfront) */
    int cull;            /* +1 / -1: triangles of that orientation (hdet sign) are never seen; 0: keep all */
    ls_real width, height, qtol, boost;
    ls_real *gp;         /* [3 V] the gradient being added to */
    struct spiece *piece; /* the sub-piece being integrated: scratch, not integrate's frame (the MCU's stack) */
    ls_real wk;          /* 3 max(|x| + |y|) + width + height over the window positions (tri_sign_front) */
    int shq;             /* 1: SH shading as a quadratic form (sh_quad_init), else ls_shade_point */
    uint32_t *wend;      /* [V] 1 + a walk face that held the vertex's window point, in front of it, or 0 (walk_reach);
                          * beside shq, where the MCU's 32-bit build had padding (the job stack) */
    ls_real shm[30];     /* per channel, the 10 entries of M_c / pi (shade.h), upper triangle by rows */
} sctx;

/* One silhouette segment being integrated: window a + t e, t in [0, 1]. */
typedef struct sedge {
    uint32_t ft, fu; /* the segment's face and its twin (or LS_EDGE_NONE) */
    uint32_t va, vb; /* the vertices at a and at a + e (LS_EDGE_NONE: an end cut at the near plane) */
    ls_real a[2], e[2];
    ls_real ka, kb;  /* integral of (1 - t) g.df and of t g.df over the visible parts */
    ls_real eabs;    /* |e0| + |e1| */
    ls_real ext;     /* |a0| + |a1| + |e0| + |e1|: the magnitude of the segment's points */
    ls_real tau;     /* margin x max(|e0|, |e1|): the side tests' margin (units of |e| x pixels) */
    ls_real tauv, c0v; /* cand_interval's tau and c0 for every polygon of window corners (sc->wk bounds them) */
    int cloc;        /* 1: c0v too loose (float): cand_interval bounds each polygon's own */
    ls_real za, zb;  /* NDC depth at a and at a + e */
    ls_real tbeg, tend, tinv; /* the segment's part in the image, 1 / its length */
    int fok;         /* 1: the own face's span over [tbeg, tend] is made (span_own: spiece.own) */
    uint32_t wnext;  /* the half-edge the walk that reached wtb goes on across when the cap stopped it, else LS_EDGE_NONE */
    ls_real wta, wtb; /* the segment's walks proved it hidden on [wta, wtb] (none: wta > wtb) */
} sedge;

/* An end of a segment: clip(v) + s (clip(w) - clip(v)) (clipped = 0: vertex v). */
typedef struct endp {
    uint32_t v, w, clipped;
    ls_real s;
    ls_real c[4];
} endp;

/* |x| by clearing the sign bit, with no branch (the margins and bounds take
 * many; -0 and +0 are the same to them). Not LS_RFABS: that is an out-of-line
 * call, and in these loops it made the armadillo's pass 10-15 % slower. On
 * the host (LS_FAST_PATHS) the compiler's built-in, which clears the bit in
 * the vector register: GCC moved the integer form out to a general register
 * and back, 0.7M more instructions a view (armadillo 512^2). */
static ls_real r_abs(ls_real x)
{
#if (defined(__GNUC__) || defined(__clang__)) && LS_FAST_PATHS
#if LS_REAL_IS_FLOAT
    return __builtin_fabsf(x);
#else
    return __builtin_fabs(x);
#endif
#else
#if LS_REAL_IS_FLOAT
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    u &= 0x7fffffffu;
#else
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    u &= 0x7fffffffffffffffull;
#endif
    memcpy(&x, &u, sizeof x);
    return x;
#endif
}

/* The point of triangle f on the ray through window (xw, yw): barycentrics
 * b and NDC depth; returns 0 when the triangle is edge-on there or the point
 * is behind the eye. */
static int tri_point(const sctx *sc, const uint32_t *f, ls_real xw, ls_real yw, ls_real b[3], ls_real *depth)
{
    ls_real px = (ls_real)2 * xw / sc->width - (ls_real)1, py = (ls_real)1 - (ls_real)2 * yw / sc->height;
    ls_real u[3], v[3], cz = (ls_real)0, cw = (ls_real)0;
    int k;
    if (ls_clip_barycentric(sc->vis->clip, f, px, py, u, v, b) == (ls_real)0) return 0;
    SIL_UNROLL
    for (k = 0; k < 3; k++) {
        const ls_real *cl = sc->vis->clip + 4 * (size_t)f[k];
        cz += b[k] * cl[2];
        cw += b[k] * cl[3];
    }
    if (!(cw > (ls_real)0)) return 0;
    *depth = cz / cw;
    return 1;
}

/* Window position of a vertex from its clip coordinates. */
static void window_of(const sctx *sc, const ls_real *cl, ls_real w[2])
{
    w[0] = (cl[0] / cl[3] + (ls_real)1) * sc->width * (ls_real)0.5;
    w[1] = ((ls_real)1 - cl[1] / cl[3]) * sc->height * (ls_real)0.5;
}

/* Endpoint of an edge clipped at the near plane Z + W = 0: the point
 * p + s (q - p), s = dp / (dp - dq), written to out. */
static void near_point(const ls_real *p, const ls_real *q, ls_real s, ls_real out[4])
{
    int r;
    for (r = 0; r < 4; r++) out[r] = p[r] + s * (q[r] - p[r]);
}

/* tri_poly of a triangle with a corner behind the eye or the near plane
 * (or without sc->win): out of line, the inlined path takes the rest. */
LS_NOINLINE static int tri_poly_cut(const sctx *sc, const uint32_t *f, ls_real x[4], ls_real y[4])
{
    const ls_real *c[3];
    ls_real d[3], w[2], q[4];
    int k, n = 0, front = 0;
    for (k = 0; k < 3; k++) {
        c[k] = sc->vis->clip + 4 * (size_t)f[k];
        d[k] = c[k][2] + c[k][3];
        if (d[k] >= (ls_real)0) {
            if (!(c[k][3] > (ls_real)0)) return 0;
            front++;
        }
    }
    if (front == 0) return 0;
    for (k = 0; k < 3; k++) {
        int k1 = (k + 1) % 3;
        if (d[k] >= (ls_real)0) {
            if (sc->win != NULL) {
                x[n] = sc->win[2 * (size_t)f[k]];
                y[n] = sc->win[2 * (size_t)f[k] + 1];
            } else {
                window_of(sc, c[k], w);
                x[n] = w[0];
                y[n] = w[1];
            }
            n++;
        }
        if ((d[k] >= (ls_real)0) != (d[k1] >= (ls_real)0)) {
            if (d[k] < (ls_real)0)
                near_point(c[k], c[k1], d[k] / (d[k] - d[k1]), q);
            else
                near_point(c[k1], c[k], d[k1] / (d[k1] - d[k]), q);
            if (!(q[3] > (ls_real)0)) return 0;
            window_of(sc, q, w);
            x[n] = w[0];
            y[n] = w[1];
            n++;
        }
    }
    return n;
}

/* The window polygon of triangle f clipped at the near plane (3 or 4
 * corners, 0 when nothing is in front); each clipped corner is computed
 * from the behind vertex, as the segment ends are. */
/* tri_poly for a triangle every corner of which is in front (tri_front):
 * its window corners. */
static inline void tri_win(const sctx *sc, const uint32_t *f, ls_real x[4], ls_real y[4])
{
    int k;
    SIL_UNROLL
    for (k = 0; k < 3; k++) {
        x[k] = sc->win[2 * (size_t)f[k]];
        y[k] = sc->win[2 * (size_t)f[k] + 1];
    }
}

static inline int tri_poly(const sctx *sc, const uint32_t *f, ls_real x[4], ls_real y[4])
{
    if (sc->vfront == NULL || (sc->vfront[f[0]] & sc->vfront[f[1]] & sc->vfront[f[2]]) == 0)
        return tri_poly_cut(sc, f, x, y);
    tri_win(sc, f, x, y);
    return 3;
}

/* Whether every corner of triangle f is in front of the eye (the pass's
 * sc->vfront is never NULL); allfront: sc->allfront, in a local of the
 * caller (a store through a uint32_t pointer may change an int). */
static inline int tri_front(const sctx *sc, int allfront, const uint32_t *f)
{
    return allfront || (sc->vfront[f[0]] & sc->vfront[f[1]] & sc->vfront[f[2]]) != 0;
}

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

/* floor(c) clamped to [0, n - 1] (0 for NaN); n < 2^24. */
static uint32_t cell_of(ls_real c, uint32_t n)
{
    if (!(c >= (ls_real)1)) return 0;
    if (c >= (ls_real)n) return n - 1u;
    return (uint32_t)c; /* in [1, n): the cast truncates, as floor */
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
static void box_pass(const sctx *sc, size_t count[2], int *over)
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

/* The areas a of triangle f (ls_clip_barycentric's, b = a / sum a) along
 * a sub-piece [lo, hi] of the segment: affine in window position, so
 * a(t) = a0 + (t - lo) inv da from their values at the two ends (one point
 * when lo = hi). ad[k] = (a0_k, da_k): quad_side loads them as pairs. */
typedef struct aspan {
    const uint32_t *f;
    ls_real lo, inv, ad[3][2];
} aspan;

/* One sub-piece being integrated: the spans of the segment's face and of
 * the surface behind (beh = triangle + 1, 0: the background of pixel p). */
typedef struct spiece {
    aspan in, bh;
    aspan own;       /* the segment's own face over [tbeg, tend] (span_own) */
    /* on the fast path (own_form), per channel c, H^T M_c H of own along it
     * is oc[3c] + u oc[3c + 1] + u^2 oc[3c + 2] (u = (t - tbeg) tinv); osw:
     * S, sum a_k W_k at tbeg and their changes to tend */
    ls_real oc[9], osw[4];
    int oset;        /* 1: oc, osw, osure, orho, oinv are the segment's */
    int osure;       /* quad_sure over the segment; then orho, oinv: |dS| / min |S|, 1 / min |S| there */
    ls_real orho, oinv;
    uint32_t beh;
    size_t p;
    /* the SH fast path (sc->shq): per side (0 inside, 1 behind), g.E along the
     * sub-piece is (c0 + s c1 + s^2 c2) / S(s)^2 with S = s0 + s ds the sum
     * of the areas, and the sign of sum a_k W_k = w0 + s dw tells the eye's side;
     * q = (c0, c2, s0, ds, w0, dw, c1, 0), the pairs as quad_side makes them */
    ls_real q[2][8];
    ls_real G[20];   /* quad_piece's form, each entry twice (quad_side's pairs): here, not in a frame (the MCU's stack) */
    size_t gkey;     /* 1 + the pixel G is for, 0: none (zeroed once a view) */
    uint32_t bkey;   /* beh of span_init's last span, 0: none */
    ls_real bt, ba[3]; /* its hi and the areas there */
    ls_real gbg;     /* g . background (beh = 0) */
    int sure;        /* 1: quad_eval's tests pass at every s in [0, 1] (quad_sure), so are skipped */
    ls_real xerr;    /* if sure, quad_bound's bound on the 3-point rule's error over (hi - lo) / 400 */
} spiece;

/* The areas of triangle f at the segment's point t (ls_clip_areas: no
 * divisions for barycentrics, which are not used). */
static void span_areas(const sctx *sc, const sedge *ed, const uint32_t *f, ls_real t, ls_real a[3])
{
    ls_real px = (ls_real)2 * (ed->a[0] + t * ed->e[0]) / sc->width - (ls_real)1;
    ls_real py = (ls_real)1 - (ls_real)2 * (ed->a[1] + t * ed->e[1]) / sc->height;
    ls_real u[3], v[3];
    ls_clip_areas(sc->vis->clip, f, px, py, u, v, a);
}

/* The span of the surface behind (pc->beh) on [lo, hi], with the own
 * face's inv (pc->in: 1 / (hi - lo), or 0 when lo = hi). The areas at hi
 * are kept for the next sub-piece of the segment: about half start there
 * on the same triangle (pixel boundaries, run_pass's joins). */
static void span_init(const sctx *sc, const sedge *ed, spiece *pc, ls_real lo, ls_real hi)
{
    ls_real al[3], ah[3];
    aspan *sp = &pc->bh;
    int k;
    sp->f = sc->indices + 3 * (size_t)(pc->beh - 1u);
    sp->lo = lo;
    sp->inv = pc->in.inv;
    if (pc->bkey == pc->beh && pc->bt == lo)
        for (k = 0; k < 3; k++) al[k] = pc->ba[k];
    else
        span_areas(sc, ed, sp->f, lo, al);
    if (hi > lo)
        span_areas(sc, ed, sp->f, hi, ah);
    else
        for (k = 0; k < 3; k++) ah[k] = al[k];
    pc->bkey = pc->beh;
    pc->bt = hi;
    SIL_UNROLL
    for (k = 0; k < 3; k++) {
        pc->ba[k] = ah[k];
        sp->ad[k][0] = al[k];
        sp->ad[k][1] = ah[k] - al[k];
    }
}

/* span_init for the segment's own face (pc->in): its areas along the
 * segment's part in the image, from their values at its ends (pc->own,
 * made at the first sub-piece), affine there.
 * On its own edge they stay within [0, their sum], so the interpolation
 * loses nothing to magnitudes. The fast path reads no areas (quad_piece). */
static void span_own(const sctx *sc, sedge *ed, spiece *pc, ls_real lo, ls_real hi)
{
    aspan *sp = &pc->in;
    ls_real(*od)[2] = pc->own.ad;
    ls_real s0, ds;
    int k;
    if (!ed->fok) { /* the segment's first sub-piece */
        ls_real al[3], ah[3];
        aspan *ow = &pc->own;
        ow->f = sc->indices + 3 * (size_t)ed->ft;
        span_areas(sc, ed, ow->f, ed->tbeg, al);
        span_areas(sc, ed, ow->f, ed->tend, ah);
        for (k = 0; k < 3; k++) {
            ow->ad[k][0] = al[k];
            ow->ad[k][1] = ah[k] - al[k];
        }
        pc->oset = 0; /* own_form's coefficients are another segment's */
        pc->bkey = 0; /* and span_init's areas */
        ed->fok = 1;
    }
    sp->f = pc->own.f;
    sp->lo = lo;
    sp->inv = hi > lo ? (ls_real)1 / (hi - lo) : (ls_real)0;
    if (sc->shq && !sc->flat) return;
    s0 = (lo - ed->tbeg) * ed->tinv;
    ds = (hi - lo) * ed->tinv;
    SIL_UNROLL
    for (k = 0; k < 3; k++) {
        sp->ad[k][0] = od[k][0] + s0 * od[k][1];
        sp->ad[k][1] = ds * od[k][1];
    }
}

/* The barycentrics b of a span's triangle at t; 0 when it is edge-on there
 * or the point is behind the eye (as tri_point). */
static int span_bary(const sctx *sc, const aspan *sp, ls_real t, ls_real b[3])
{
    ls_real s = (t - sp->lo) * sp->inv, a[3], sum, cw = (ls_real)0;
    int k;
    SIL_UNROLL
    for (k = 0; k < 3; k++) a[k] = sp->ad[k][0] + s * sp->ad[k][1];
    sum = (a[0] + a[1]) + a[2];
    if (!(sum != (ls_real)0) || sum - sum != (ls_real)0) return 0;
    sum = (ls_real)1 / sum;
    SIL_UNROLL
    for (k = 0; k < 3; k++) {
        b[k] = a[k] * sum;
        cw += b[k] * sc->vis->clip[4 * (size_t)sp->f[k] + 3];
    }
    return cw > (ls_real)0;
}

/* g . (f_inside - f_behind) at parameter t of the segment for sub-piece pc. */
static ls_real point_term(const sctx *sc, const spiece *pc, ls_real t)
{
    ls_real b[3], rgb_in[3], rgb_bh[3], a_bh = (ls_real)0;
    const ls_real *g = sc->gimg + 4 * pc->p;
    if (!span_bary(sc, &pc->in, t, b)) return (ls_real)0;
    ls_shade_point(sc->o, pc->in.f, sc->normals, b, rgb_in);
    if (pc->beh != 0) {
        if (!span_bary(sc, &pc->bh, t, b)) return (ls_real)0;
        ls_shade_point(sc->o, pc->bh.f, sc->normals, b, rgb_bh);
        a_bh = (ls_real)1;
    } else {
        const ls_real *bg = sc->o->background_image != NULL ? sc->o->background_image + 3 * pc->p : sc->o->background;
        rgb_bh[0] = bg[0];
        rgb_bh[1] = bg[1];
        rgb_bh[2] = bg[2];
    }
    return ((g[0] * (rgb_in[0] - rgb_bh[0]) + g[1] * (rgb_in[1] - rgb_bh[1])) + g[2] * (rgb_in[2] - rgb_bh[2])) +
           g[3] * ((ls_real)1 - a_bh);
}

/* SH irradiance without renormalisation is a quadratic form of the
 * homogeneous interpolated normal, E_c = n_h^T M_c n_h / pi (shade.h), and
 * n_h = H / S with H = sum_k a_k (n_k, 1) and S = sum_k a_k affine along a
 * sub-piece (the areas are): so g . E = H^T G H / S^2 with G = sum_c g_c
 * M_c / pi, a quadratic in s over S^2, set up once per sub-piece and side
 * where ls_shade_point costs two SH evaluations per point. */
static void sh_quad_init(sctx *sc)
{
    const ls_real c1 = (ls_real)LS_SH_C1, c2 = (ls_real)LS_SH_C2, c3 = (ls_real)LS_SH_C3;
    const ls_real c4 = (ls_real)LS_SH_C4, c5 = (ls_real)LS_SH_C5, ip = (ls_real)0.31830988618379067154;
    const ls_shade_opts *o = sc->o;
    int c;
    sc->shq = o->mode == LS_SHADE_SH && !o->renormalize && o->vertex_colors == NULL && o->texture == NULL;
    if (!sc->shq) return;
    for (c = 0; c < 3; c++) {
        const ls_real *L = o->sh + 9 * (size_t)c;
        ls_real *m = sc->shm + 10 * (size_t)c;
        m[0] = c1 * L[8] * ip;  /* xx */
        m[1] = c1 * L[4] * ip;  /* xy */
        m[2] = c1 * L[7] * ip;  /* xz */
        m[3] = c2 * L[3] * ip;  /* x1 */
        m[4] = -c1 * L[8] * ip; /* yy */
        m[5] = c1 * L[5] * ip;  /* yz */
        m[6] = c2 * L[1] * ip;  /* y1 */
        m[7] = c3 * L[6] * ip;  /* zz */
        m[8] = c2 * L[2] * ip;  /* z1 */
        m[9] = (c4 * L[0] - c5 * L[6]) * ip; /* 11 */
    }
}

/* For the symmetric 4 x 4 M stored as sh_quad_init's m, entry i at M[gs i]
 * (gs = 2: each entry twice), and H = H0 + u dH in side_h's pairs h:
 * H^T M H = c[0] + u c[1] + u^2 c[2], through K = M H0, M dH (pairs as h). */
static SIL_INLINE void quad_coef(const ls_real *M, size_t gs, const ls_real h[8], ls_real c[3])
{
    static const unsigned char ix[16] = {0, 1, 2, 3, 1, 4, 5, 6, 2, 5, 7, 8, 3, 6, 8, 9}; /* M's entry (r, i) */
    ls_real k[8];
    int j, r;
    SIL_UNROLL
    for (r = 0; r < 4; r++) {
        const unsigned char *x = ix + 4 * (size_t)r;
        SIL_UNROLL
        for (j = 0; j < 2; j++)
            k[2 * r + j] = (M[gs * x[0]] * h[j] + M[gs * x[1]] * h[2 + j]) + (M[gs * x[2]] * h[4 + j] + M[gs * x[3]] * h[6 + j]);
    }
    c[0] = (h[0] * k[0] + h[2] * k[2]) + (h[4] * k[4] + h[6] * k[6]);
    c[1] = (ls_real)2 * ((h[0] * k[1] + h[2] * k[3]) + (h[4] * k[5] + h[6] * k[7]));
    c[2] = (h[1] * k[1] + h[3] * k[3]) + (h[5] * k[5] + h[7] * k[7]);
}

/* H = sum_k a_k (n_k, 1) of span sp at lo and its change, h[2 r + j]: H's
 * entry r (j = 0 at lo, 1 the change), and the same for sum a_k W_k, hw[j].
 * Side by side, which the compiler does in pairs (SLP). */
static SIL_INLINE void side_h(const sctx *sc, const aspan *sp, ls_real h[8], ls_real hw[2])
{
    const ls_real(*a)[2] = sp->ad;
    ls_real w[3];
    const ls_real *n0 = sc->normals + 3 * (size_t)sp->f[0], *n1 = sc->normals + 3 * (size_t)sp->f[1];
    const ls_real *n2 = sc->normals + 3 * (size_t)sp->f[2];
    int j, k, r;
    SIL_UNROLL
    for (k = 0; k < 3; k++) w[k] = sc->vis->clip[4 * (size_t)sp->f[k] + 3];
    SIL_UNROLL
    for (j = 0; j < 2; j++) {
        h[6 + j] = (a[0][j] + a[1][j]) + a[2][j];
        SIL_UNROLL
        for (r = 0; r < 3; r++) h[2 * r + j] = (a[0][j] * n0[r] + a[1][j] * n1[r]) + a[2][j] * n2[r];
        hw[j] = (((ls_real)0 + a[0][j] * w[0]) + a[1][j] * w[1]) + a[2][j] * w[2];
    }
}

/* The coefficients q (spiece.q) of one side's span for the form G; q is
 * stored last, after the loads. */
static void quad_side(const sctx *sc, const aspan *sp, const ls_real *restrict G, ls_real *restrict q)
{
    ls_real h[8], v[8], c[3];
    int k;
    side_h(sc, sp, h, v + 4);
    quad_coef(G, 2, h, c);
    v[0] = c[0];
    v[1] = c[2];
    v[2] = h[6];
    v[3] = h[7];
    v[6] = c[1];
    v[7] = (ls_real)0;
    SIL_UNROLL
    for (k = 0; k < 8; k++) q[k] = v[k];
}

/* For a side whose S and sum a_k W_k are sw[0] + s sw[1], sw[2] + s sw[3]
 * (q + 2): min |S| over s in [0, 1] if quad_eval's tests pass all over it,
 * else 0. Both are affine, so they keep their signs there when both ends
 * have them by far more than the rounding of their evaluation. */
static ls_real quad_sure(const ls_real sw[4])
{
    ls_real r = (ls_real)8 * LS_REAL_EPSILON, ms = r * (r_abs(sw[0]) + r_abs(sw[1]));
    ls_real mw = r * (r_abs(sw[2]) + r_abs(sw[3])), sg, s0, s1, w0, w1, smin;
    if (!((ms + mw) - (ms + mw) == (ls_real)0)) return (ls_real)0; /* both finite, and then so are S and w */
    /* S0 > ms and ... or S0 < -ms and ...: the same with all made positive */
    sg = sw[0] > (ls_real)0 ? (ls_real)1 : (ls_real)-1;
    s0 = sg * sw[0];
    s1 = sg * (sw[0] + sw[1]);
    w0 = sg * sw[2];
    w1 = sg * (sw[2] + sw[3]);
    smin = s0 < s1 ? s0 : s1;
    return ((smin > ms) & ((w0 < w1 ? w0 : w1) > mw)) ? smin : (ls_real)0;
}

/* A bound on the 3-point rule's error for a side q over [0, 1] on
 * quad_sure's path, over (hi - lo) / 400 (integrate), given
 * rho >= |dS| / min |S| and inv >= 1 / min |S|: the integrand is
 * omega N / S^2 (N = c0 + c1 s + c2 s^2, omega = 1 - t or t), and with
 * rho <= 1/16 Leibniz's rule bounds its 6th derivative in s by
 * 4635 rho^3 (|c2| + rho |c1| + rho^2 |c0|) / min S^2; the rule's error is
 * (hi - lo) / 2016000 times that (4635 / 2016000 < 1 / 400). */
static ls_real quad_bound(const ls_real q[8], ls_real rho, ls_real inv)
{
    if (!(rho <= (ls_real)0.0625)) return LS_REAL_MAX;
    return rho * rho * rho * (r_abs(q[1]) + rho * (r_abs(q[6]) + rho * r_abs(q[0]))) * (inv * inv);
}

/* The own face's coefficients along the segment (spiece.oc, osw) from
 * pc->own: per channel's M_c (sh_quad_init), the form of H(u) = H0 + u dH
 * through K = M_c H0, M_c dH (pairs, as side_h's). Once a segment, where
 * quad_side took two spans and a form per sub-piece. Not inlined: its frame
 * stays off integrate's (the MCU's stack). */
LS_NOINLINE static void own_form(const sctx *sc, spiece *pc)
{
    ls_real h[8], hw[2];
    int c;
    side_h(sc, &pc->own, h, hw);
    for (c = 0; c < 3; c++) quad_coef(sc->shm + 10 * (size_t)c, 1, h, pc->oc + 3 * (size_t)c);
    pc->osw[0] = h[6];
    pc->osw[1] = h[7];
    pc->osw[2] = hw[0];
    pc->osw[3] = hw[1];
    /* quad_sure over the segment holds on each sub-piece: their coefficients
     * (quad_piece) round by far less than its margins */
    pc->oinv = quad_sure(pc->osw);
    pc->osure = pc->oinv > (ls_real)0;
    if (pc->osure) pc->oinv = (ls_real)1 / pc->oinv;
    pc->orho = r_abs(h[7]) * pc->oinv;
    pc->oset = 1;
}

/* Sets up the fast path's coefficients of sub-piece [lo, hi] (spans made):
 * the own face's from own_form's at u = u0 + s du, the surface behind's
 * through quad_side and the pixel's form G. */
static void quad_piece(const sctx *sc, const sedge *ed, spiece *pc, ls_real lo, ls_real hi)
{
    const ls_real *g = sc->gimg + 4 * pc->p, *oc = pc->oc, *sw = pc->osw, *shm = sc->shm;
    ls_real g0 = g[0], g1 = g[1], g2 = g[2], *q = pc->q[0], *G = pc->G;
    ls_real u0 = (lo - ed->tbeg) * ed->tinv, du = (hi - lo) * ed->tinv, k0, k1, k2;
    if (!pc->oset) own_form(sc, pc); /* the segment's first sub-piece */
    k0 = (g0 * oc[0] + g1 * oc[3]) + g2 * oc[6];
    k1 = (g0 * oc[1] + g1 * oc[4]) + g2 * oc[7];
    k2 = (g0 * oc[2] + g1 * oc[5]) + g2 * oc[8];
    q[0] = k0 + u0 * (k1 + u0 * k2);
    q[1] = du * du * k2;
    q[2] = sw[0] + u0 * sw[1];
    q[3] = du * sw[1];
    q[4] = sw[2] + u0 * sw[3];
    q[5] = du * sw[3];
    q[6] = du * (k1 + (u0 + u0) * k2);
    q[7] = (ls_real)0;
    pc->sure = pc->osure;
    pc->xerr = pc->sure ? quad_bound(q, du * pc->orho, pc->oinv) : (ls_real)0;
    if (pc->beh != 0) {
        if (pc->gkey != pc->p + 1u) { /* a pixel's sub-pieces come in a row (a quarter follow one of theirs) */
            int j;
            pc->gkey = pc->p + 1u;
            SIL_UNROLL
            for (j = 0; j < 10; j++) G[2 * (size_t)j] = G[2 * (size_t)j + 1] = (g0 * shm[j] + g1 * shm[10 + j]) + g2 * shm[20 + j];
        }
        quad_side(sc, &pc->bh, G, pc->q[1]);
        if (pc->sure) {
            ls_real sm = quad_sure(pc->q[1] + 2);
            pc->sure = sm > (ls_real)0;
            if (pc->sure) pc->xerr += quad_bound(pc->q[1], r_abs(pc->q[1][3]) / sm, (ls_real)1 / sm);
        }
    } else {
        const ls_real *bg = sc->o->background_image != NULL ? sc->o->background_image + 3 * pc->p : sc->o->background;
        pc->gbg = (g0 * bg[0] + g1 * bg[1]) + g2 * bg[2];
    }
}

/* g . E of one side at s; 0 (as span_bary's failure) when the areas sum to
 * zero or overflow, or the point is behind the eye. */
static int quad_eval(const ls_real q[8], ls_real s, ls_real *val)
{
    ls_real S = q[2] + s * q[3], w = q[4] + s * q[5];
    if (!(S != (ls_real)0) || S - S != (ls_real)0) return 0;
    if (!(S > (ls_real)0 ? w > (ls_real)0 : w < (ls_real)0)) return 0;
    *val = (q[0] + s * (q[6] + s * q[1])) / (S * S);
    return 1;
}

/* point_term through the fast path; sure = pc->sure and bh = (pc->beh != 0),
 * constants in integrate's copies (SIL_INLINE). */
static SIL_INLINE ls_real quad_term_n(const sctx *sc, const spiece *pc, ls_real t, int sure, int bh)
{
    ls_real s = (t - pc->in.lo) * pc->in.inv, vin, vbh;
    const ls_real *g = sc->gimg + 4 * pc->p;
    if (sure) {
        const ls_real *a = pc->q[0], *b = pc->q[1];
        ls_real Sa = a[2] + s * a[3], Sb;
        vin = (a[0] + s * (a[6] + s * a[1])) / (Sa * Sa);
        if (!bh) return (vin - pc->gbg) + g[3];
        Sb = b[2] + s * b[3];
        return vin - (b[0] + s * (b[6] + s * b[1])) / (Sb * Sb);
    }
    if (!quad_eval(pc->q[0], s, &vin)) return (ls_real)0;
    if (!bh) return (vin - pc->gbg) + g[3];
    if (!quad_eval(pc->q[1], s, &vbh)) return (ls_real)0;
    return vin - vbh;
}

static ls_real quad_term(const sctx *sc, const spiece *pc, ls_real t)
{
    return quad_term_n(sc, pc, t, pc->sure, pc->beh != 0);
}

/* f[k] = half x the integrand at t[k] for k0 <= k < k1; sure: integrate's
 * (1, 2: quad_term_n's sure path without, with a surface behind). */
static SIL_INLINE void quad_nodes(const sctx *sc, const spiece *pc, int sure, const ls_real *t, ls_real half, int k0,
                                  int k1, ls_real *f)
{
    int k;
#if SIL_SPECIALIZE
    /* the usual cases with their tests out of the loop */
    if (sure == 1) {
        SIL_UNROLL
        for (k = k0; k < k1; k++) f[k] = quad_term_n(sc, pc, t[k], 1, 0) * half;
        return;
    }
    if (sure == 2) {
        SIL_UNROLL
        for (k = k0; k < k1; k++) f[k] = quad_term_n(sc, pc, t[k], 1, 1) * half;
        return;
    }
#else
    (void)sure;
#endif
    SIL_UNROLL
    for (k = k0; k < k1; k++) f[k] = (sc->shq ? quad_term(sc, pc, t[k]) : point_term(sc, pc, t[k])) * half;
}

/* Integrates (1 - t) g.df and t g.df over [lo, hi] into ed->ka, ed->kb
 * (the surface behind: beh, pixel p): one point when df is constant (mask
 * mode), else Gauss-Legendre with 3 points: once when quad_bound's bound
 * puts its error within qtol, else on the interval halved (depth first, at
 * most SIL_DEPTH_CAP times) until the 2-point rule agrees with it to qtol
 * (the difference bounds the 2-point rule's error; the 3-point rule's is
 * far below: 5 evaluations where 5 and 3 points took 7). */
static void integrate(const sctx *sc, sedge *ed, ls_real lo, ls_real hi, uint32_t beh, size_t p)
{
    static const ls_real x2 = (ls_real)0.57735026918962576451, x3 = (ls_real)0.77459666924148337704;
    static const ls_real w3a = (ls_real)0.55555555555555555556, w3b = (ls_real)0.88888888888888888889;
    /* pending intervals, depth first: their depths increase up the stack
     * but for the two halves just pushed, so it holds at most CAP + 1 */
    ls_real slo[SIL_DEPTH_CAP + 1], shi[SIL_DEPTH_CAP + 1], gabs;
    unsigned char sd[SIL_DEPTH_CAP + 1];
    int n = 1, sure = 0;
    const ls_real *g = sc->gimg + 4 * p;
    spiece *pc = sc->piece;
    /* zeroed once a view (ls_silhouette_backward): the parts a path leaves unused keep
     * an earlier sub-piece's values, which no path reads (each sets what it reads) */
    pc->beh = beh;
    pc->p = p;
    if (sc->flat) {
        ls_real mid = (lo + hi) * (ls_real)0.5, term, len = hi - lo, mb = len * (hi + lo) * (ls_real)0.5;
        span_own(sc, ed, pc, mid, mid);
        if (beh != 0) span_init(sc, ed, pc, mid, mid);
        term = point_term(sc, pc, mid);
        ed->ka += term * (len - mb);
        ed->kb += term * mb;
        return;
    }
    span_own(sc, ed, pc, lo, hi);
    if (beh != 0) span_init(sc, ed, pc, lo, hi);
    if (sc->shq) {
        quad_piece(sc, ed, pc, lo, hi);
        if (pc->sure) sure = 1 + (beh != 0);
    }
    gabs = ((r_abs(g[0]) + r_abs(g[1])) + r_abs(g[2])) + r_abs(g[3]);
    slo[0] = lo;
    shi[0] = hi;
    /* the bound shows the 3-point rule within qtol: no 2-point check, no halving */
    sd[0] = (unsigned char)(sure && pc->xerr <= (ls_real)200 * sc->qtol * gabs ? SIL_DEPTH_CAP : 0);
    while (n > 0) {
        ls_real l, h, mid, half, f[5], t[5], a3, b3;
        int d;
        n--;
        l = slo[n];
        h = shi[n];
        d = sd[n];
        mid = (l + h) * (ls_real)0.5;
        half = (h - l) * (ls_real)0.5;
        t[0] = mid;
        t[1] = mid - half * x3;
        t[2] = mid + half * x3;
        quad_nodes(sc, pc, sure, t, half, 0, 3, f);
        a3 = (w3b * ((ls_real)1 - t[0]) * f[0] + w3a * ((ls_real)1 - t[1]) * f[1]) + w3a * ((ls_real)1 - t[2]) * f[2];
        b3 = (w3b * t[0] * f[0] + w3a * t[1] * f[1]) + w3a * t[2] * f[2];
        if (d < SIL_DEPTH_CAP) {
            ls_real a2, b2, err;
            t[3] = mid - half * x2;
            t[4] = mid + half * x2;
            quad_nodes(sc, pc, sure, t, half, 3, 5, f);
            a2 = ((ls_real)1 - t[3]) * f[3] + ((ls_real)1 - t[4]) * f[4];
            b2 = t[3] * f[3] + t[4] * f[4];
            err = r_abs(a3 - a2) + r_abs(b3 - b2);
            if (!(err <= sc->qtol * ((r_abs(a3) + r_abs(b3)) + (h - l) * gabs))) {
                slo[n] = mid; /* the upper half waits: the lower half is done first */
                shi[n] = h;
                sd[n] = (unsigned char)(d + 1);
                slo[n + 1] = l;
                shi[n + 1] = mid;
                sd[n + 1] = (unsigned char)(d + 1);
                n += 2;
                continue;
            }
        }
        ed->ka += a3;
        ed->kb += b3;
    }
}

/* Whether window point (xw, yw) passes the quick test of a convex polygon
 * (x, y, n corners): not strictly outside one edge while strictly inside
 * another (either orientation; a point on the boundary passes). */
static SIL_INLINE int poly_holds_n(const ls_real *x, const ls_real *y, int n, ls_real xw, ls_real yw)
{
    int q, pos = 0, neg = 0;
    if (n > 4) return 0; /* never (tri_poly): tells the unrolled loop */
    SIL_UNROLL
    for (q = 0; q < n; q++) {
        int q1 = q + 1 == n ? 0 : q + 1;
        ls_real cr = (x[q1] - x[q]) * (yw - y[q]) - (y[q1] - y[q]) * (xw - x[q]);
        pos |= cr > (ls_real)0;
        neg |= cr < (ls_real)0;
        if (pos && neg) return 0;
    }
    return 1;
}

/* poly_holds_n, with a copy for triangles (SIL_INLINE). */
static int poly_holds(const ls_real *x, const ls_real *y, int n, ls_real xw, ls_real yw)
{
#if SIL_SPECIALIZE
    if (n == 3) return poly_holds_n(x, y, 3, xw, yw);
#endif
    return poly_holds_n(x, y, n, xw, yw);
}

/* Whether triangle f, every corner in front of the eye (window corners x,
 * y), holds window point (xw, yw), and its NDC depth there: the edge
 * functions c_q of the point (the quick test's cross products) are its
 * barycentrics up to their sum, all of one sign inside (0 on an edge), and
 * NDC depth is affine in window position on the triangle's plane, so it is
 * the corners' weighted by the functions of their opposite edges. One test
 * where the quick test and the clip barycentrics (tri_point) took two that
 * could disagree within rounding of an edge (they did ~390 times a view of
 * the armadillo at 512^2, at midpoints of sub-pieces one ulp long), with
 * no divisions but one; 0 when it does not hold the point or is edge-on. */
static int window_hold(const sctx *sc, const uint32_t *f, const ls_real *x, const ls_real *y, ls_real xw, ls_real yw,
                       ls_real *depth)
{
    ls_real c[3], sum;
    int q, pos = 0, neg = 0;
    SIL_UNROLL
    for (q = 0; q < 3; q++) {
        int q1 = q == 2 ? 0 : q + 1;
        c[q] = (x[q1] - x[q]) * (yw - y[q]) - (y[q1] - y[q]) * (xw - x[q]);
        pos |= c[q] > (ls_real)0;
        neg |= c[q] < (ls_real)0;
    }
    if (pos && neg) return 0;
    sum = (c[0] + c[1]) + c[2];
    if (sum == (ls_real)0) return 0;
    *depth = ((c[0] * sc->zv[f[2]] + c[1] * sc->zv[f[0]]) + c[2] * sc->zv[f[1]]) / sum;
    return 1;
}

/* Whether the segment's point at t is seen (1) and, if so, the surface
 * behind it: *beh = triangle + 1, or 0 for the background. The candidates
 * are the piece's active ones (sc->cact[0..*nact)): those whose interval
 * holds t are tested exactly (window_hold for a triangle in front of the
 * eye; else the quick polygon test, then the clip barycentrics and depth),
 * those whose interval ended before t are dropped from the list
 * (the parameters tested increase; run_pass adds them as their intervals
 * begin). The answer does not depend on the
 * order of the list (ties of the surface behind keep the smaller triangle),
 * so an occluder found is moved to the front, where the next point tests it
 * first. */
static int visibility(const sctx *sc, const sedge *ed, ls_real t, uint32_t *nact, uint32_t *beh)
{
    ls_real b[3], zc, tol, best = (ls_real)0;
    ls_real xw = ed->a[0] + t * ed->e[0], yw = ed->a[1] + t * ed->e[1];
    /* the segment's depth: NDC depth is affine in window position on a plane, so along a line
     * (as walk_front's); every point of the segment is in front of the eye (W > 0 at both ends) */
    ls_real ze = ed->za + t * (ed->zb - ed->za);
    uint32_t i = 0, best_id = 0;
    const int allfront = sc->allfront;
    if (ze > (ls_real)1) return 0; /* beyond the far plane: not drawn */
    tol = (ls_real)64 * LS_REAL_EPSILON * ((ls_real)1 + r_abs(ze));
    while (i < *nact) {
        uint32_t k = sc->cact[i], id = sc->cid[k];
        const uint32_t *f;
        if (sc->chi[k] < t) { /* its interval is behind: never needed again */
            sc->cact[i] = sc->cact[--*nact];
            continue;
        }
        i++;
        f = sc->indices + 3 * (size_t)id;
        /* each path its own corners: the front one's never reach memory */
        if (tri_front(sc, allfront, f)) { /* tri_poly's corners from sc->win */
            ls_real x[4], y[4];
            tri_win(sc, f, x, y);
            if (!window_hold(sc, f, x, y, xw, yw, &zc)) continue;
        } else {
            ls_real x[4], y[4];
            int n = tri_poly_cut(sc, f, x, y);
            if (!poly_holds(x, y, n, xw, yw)) continue;
            if (!tri_point(sc, f, xw, yw, b, &zc)) continue;
            if (b[0] < (ls_real)0 || b[1] < (ls_real)0 || b[2] < (ls_real)0) continue;
        }
        if (zc < (ls_real)-1 || zc > (ls_real)1) continue; /* clipped away */
        if (zc < ze - tol) {                                /* hidden */
            sc->cact[i - 1u] = sc->cact[0];
            sc->cact[0] = k;
            return 0;
        }
        if (zc > ze + tol && (best_id == 0 || zc < best || (zc == best && id + 1u < best_id))) {
            best = zc;
            best_id = id + 1u;
        }
    }
    *beh = best_id;
    return 1;
}

static void swap_keyed(ls_real *key, uint32_t *pay, uint32_t i, uint32_t j)
{
    ls_real tk = key[i];
    key[i] = key[j];
    key[j] = tk;
    if (pay != NULL) {
        uint32_t tp = pay[i];
        pay[i] = pay[j];
        pay[j] = tp;
    }
}

/* Sift-down of a max-heap key[0..end) from r. */
static void sift_keyed(ls_real *key, uint32_t *pay, uint32_t r, uint32_t end)
{
    for (;;) {
        uint32_t c = 2u * r + 1u;
        if (c >= end) return;
        if (c + 1u < end && key[c + 1u] > key[c]) c++;
        if (!(key[c] > key[r])) return;
        swap_keyed(key, pay, r, c);
        r = c;
    }
}

/* Sorts key[0..n) increasingly, moving pay (when not NULL) along:
 * insertion for a few, else heap sort (no recursion, no memory). Equal keys
 * are indistinguishable to the callers, so stability does not matter. */
static void sort_keyed(ls_real *key, uint32_t *pay, uint32_t n)
{
    uint32_t i;
    if (n <= 16u) {
        for (i = 1; i < n; i++) {
            uint32_t j;
            for (j = i; j > 0 && key[j - 1u] > key[j]; j--) swap_keyed(key, pay, j - 1u, j);
        }
        return;
    }
    for (i = n / 2u; i > 0; i--) sift_keyed(key, pay, i - 1u, n);
    for (i = n - 1u; i > 0; i--) {
        swap_keyed(key, pay, 0, i);
        sift_keyed(key, pay, 0, i);
    }
}

/* Sorts the split parameters key[0..n) increasingly: insertion by shifts
 * (no swaps) for up to 64 (nearly all: a run has 3.6 on average), else
 * sort_keyed. Equal parameters have the same bits (they are above t0 >= 0),
 * so any order of the ties is the same array. */
static void sort_splits(ls_real *key, uint32_t n)
{
    uint32_t i;
    if (n > 64u) {
        sort_keyed(key, NULL, n);
        return;
    }
    for (i = 1; i < n; i++) {
        ls_real v = key[i];
        uint32_t j = i;
        for (; j > 0 && key[j - 1u] > v; j--) key[j] = key[j - 1u];
        key[j] = v;
    }
}

/* Candidate polygon (x, y, n) against the run [t0, t1] of the segment:
 * appends to sp (at *ns) the parameters in (t0, t1) where its edges cross
 * the segment, and returns in [*lo, *hi] the parameters where the quick
 * polygon test of visibility can pass (0: nowhere in the run).
 *
 * The side of each corner, s_q = e x (corner - a), first tells which edges
 * can meet the segment's line: an edge whose two corners are on the same
 * side by more than tau (the margin times |e|, plus 64 eps times the
 * magnitudes of the terms, far above their rounding) has its crossing
 * parameter u outside [0, 1] by more than rounding, so it adds no split,
 * and a polygon with every corner so is skipped: no point of the segment
 * passes its quick test. The crossings of the other edges are computed as
 * before (the same expressions, so the same bits). The quick test at a(t)
 * computes cr_q = num_q - t den_q per edge q; the intervals where every
 * cr_q >= -eta_q (or every cr_q <= eta_q), eta_q again far above rounding,
 * hold every parameter where the test passes, and leaving out the edges
 * that do not meet the line only widens them: the intervals decide which
 * candidates are tested, never the outcome. Inlined (SIL_INLINE): run_pass
 * calls it with 3 corners in front (nearly all) and with any polygon. */
static SIL_INLINE int cand_interval(const sedge *ed, const ls_real *x, const ls_real *y, int n, int front,
                                    ls_real t0, ls_real t1, ls_real *sp, uint32_t *ns, ls_real *lo, ls_real *hi)
{
    /* [l0, h0]: every cr >= -eta (one orientation), [l1, h1]: every cr <= eta (the other);
     * scalars, not arrays indexed by the sign of den (they lived in memory) */
    ls_real l0, l1, h0, h1, sd[4], mc = (ls_real)0, tau = ed->tauv, c0 = ed->c0v;
    int q, ok0 = 1, ok1 = 1, up[4], dn[4], allup = 1, alldn = 1;
    if (n > 4) return 0; /* never (tri_poly): tells the unrolled loops */
    if (!front || ed->cloc) {
        /* corners cut at the near plane (sc->wk does not bound them), or
         * the view's bound too loose (float: hundreds of px^2, every
         * interval the whole run): the margins from the corners' offsets
         * to a, mc. The sides sd_q round below 2 eps mc eabs, the crossings'
         * cr_q = num_q - t den_q below 8 eps mc (mc + eabs), and the quick
         * test at a point a + t e adds the point's rounding (ext); only the
         * intervals change, never which candidate holds a point */
        SIL_UNROLL
        for (q = 0; q < n; q++) {
            ls_real v = r_abs(x[q] - ed->a[0]) + r_abs(y[q] - ed->a[1]);
            if (v > mc) mc = v;
        }
        tau = ed->tau + (ls_real)64 * LS_REAL_EPSILON * (mc + ed->ext) * ed->eabs;
        c0 = (ls_real)16 * LS_REAL_EPSILON * mc * (mc + ed->ext) + (ls_real)64 * R_MIN_NORMAL;
    }
    SIL_UNROLL
    for (q = 0; q < n; q++) {
        /* the corner relative to a: recomputed (the same bits) by the edges that need it,
         * not kept across the loops (they spilled) */
        ls_real rx = x[q] - ed->a[0], ry = y[q] - ed->a[1];
        sd[q] = ed->e[0] * ry - ed->e[1] * rx;
        /* without branches: which side a corner lies on is no pattern */
        up[q] = sd[q] > tau;
        dn[q] = sd[q] < -tau;
        allup &= up[q];
        alldn &= dn[q];
    }
    if (allup | alldn) return 0;
    l0 = l1 = t0;
    h0 = h1 = t1;
    SIL_UNROLL
    for (q = 0; q < n; q++) {
        int q1 = q + 1 == n ? 0 : q + 1;
        ls_real dx, dy, den, num, eta, r, blo, bhi, rx, ry;
        if ((up[q] & up[q1]) | (dn[q] & dn[q1])) continue; /* both corners on one side */
        rx = x[q] - ed->a[0];
        ry = y[q] - ed->a[1];
        dx = x[q1] - x[q];
        dy = y[q1] - y[q];
        den = ed->e[0] * dy - ed->e[1] * dx;
        num = rx * dy - ry * dx;
        eta = c0 + SIL_MARGIN * (r_abs(dx) > r_abs(dy) ? r_abs(dx) : r_abs(dy));
        if (den == (ls_real)0) { /* parallel: cr = num all along */
            if (num < -eta) ok0 = 0;
            if (num > eta) ok1 = 0;
            continue;
        }
        /* cr = num - t den is -eta at blo and eta at bhi when den > 0 (the reverse when den < 0);
         * the crossing tt = num / den lies between them */
        r = (ls_real)1 / den;
        blo = (num - eta) * r;
        bhi = (num + eta) * r;
        if (den < (ls_real)0) {
            ls_real w = blo;
            blo = bhi;
            bhi = w;
        }
        if (bhi > t0 && blo < t1) {
            ls_real tt = num / den;
            if (tt > t0 && tt < t1) {
                ls_real uu = (rx * ed->e[1] - ry * ed->e[0]) / den;
                if (uu >= (ls_real)0 && uu <= (ls_real)1) sp[(*ns)++] = tt;
            }
        }
        /* cr >= -eta: t <= bhi when den > 0, t >= blo when den < 0; cr <= eta: the reverse
         * (comparisons written so that a NaN bound leaves the interval as it was) */
        if (den > (ls_real)0) {
            if (bhi < h0) h0 = bhi;
            if (blo > l1) l1 = blo;
        } else {
            if (bhi < h1) h1 = bhi;
            if (blo > l0) l0 = blo;
        }
    }
    ok0 = ok0 && l0 <= h0;
    ok1 = ok1 && l1 <= h1;
    if (!ok0 && !ok1) return 0;
    *lo = ok0 ? l0 : l1;
    *hi = ok0 ? h0 : h1;
    if (ok0 && ok1) {
        if (l1 < *lo) *lo = l1;
        if (h1 > *hi) *hi = h1;
    }
    return 1;
}

/* Whether triangle o can stand in front of the segment in a walk: not its
 * faces, every corner in front of the eye, binned (not culled, inside the
 * image). */
static SIL_INLINE int walk_face(const sctx *sc, const sedge *ed, uint32_t o)
{
    const uint32_t *f = sc->indices + 3 * (size_t)o;
    if (o >= sc->triangle_count || o == ed->ft || o == ed->fu) return 0;
    if ((sc->vfront[f[0]] & sc->vfront[f[1]] & sc->vfront[f[2]]) == 0) return 0;
    return !(sc->tbox[4 * (size_t)o] > sc->tbox[4 * (size_t)o + 2]);
}

/* Whether walk face o, whose edge sides (walk_sides) at t are cs = num - t den
 * and whose corners have NDC depths z, is in front of the segment at t by
 * a margin: NDC depth is affine in window position, so the face's is the
 * corners' weighted by the sides of the opposite edges (a convex
 * combination inside), the segment's the interpolation of its ends'; the
 * face's is inside the clip range and below the segment's by four times
 * visibility()'s tolerance. */
static SIL_INLINE int walk_front(const sedge *ed, const ls_real cs[3], const ls_real z[3], ls_real t)
{
    ls_real c[3], sum, zc, ze = ed->za + t * (ed->zb - ed->za), tol, zt = (ls_real)256 * LS_REAL_EPSILON;
    int q;
    SIL_UNROLL
    for (q = 0; q < 3; q++) {
        c[q] = cs[q] > (ls_real)0 ? cs[q] : (ls_real)0;
    }
    sum = (c[0] + c[1]) + c[2];
    if (!(sum > (ls_real)0)) return 0;
    zc = ((c[0] * z[2] + c[1] * z[0]) + c[2] * z[1]) / sum;
    tol = (ls_real)256 * LS_REAL_EPSILON * ((ls_real)1 + r_abs(ze)); /* four times visibility()'s (exact: powers of 2) */
    return zc > (ls_real)-1 + zt && zc < (ls_real)1 - zt && zc < ze - tol;
}

#define SIL_WALK_CAP 24 /* triangles a walk crosses before it gives up */
#define SIL_LOCATE_CAP 6 /* and walk_locate (farther from the sample, it seldom gets anywhere) */
#define SIL_WALK_MARGIN ((ls_real)1 / (ls_real)4096) /* pixels: a walk's points are this far inside */

/* Whether the segment is hidden between ts and tg (either order) behind a
 * chain of triangles that share edges, starting at o, which holds the point
 * at ts. In each triangle, c_q(t) = s (num_q - t den_q) (s its orientation)
 * measures the side of edge q, affine along the segment: the walk leaves
 * through the edge whose c_q reaches 0 first, into the face across it, and
 * every other c_q is at least a margin (far above rounding) at both ends of
 * each triangle's stretch, so that stretch lies inside the triangle; the
 * depth difference is affine too, checked at both ends. The chain covers
 * the stretch with closed triangles: points on a shared edge count as hidden
 * (the per-sub-piece test may find an ulp-wide crack there). */
/* The sides of the segment's points to the edges of triangle o (a walk
 * face): c_q(t) = num_q - t den_q, positive inside, and the margin m_q
 * (c0 as cand_interval's, far above rounding) they must exceed to count as inside; 0 when the
 * triangle is degenerate on screen. */
static SIL_INLINE int walk_sides(const sctx *sc, const sedge *ed, uint32_t o, ls_real num[3], ls_real den[3], ls_real m[3])
{
    const uint32_t *f = sc->indices + 3 * (size_t)o;
    ls_real x[3], y[3], rx[3], ry[3], sg, mc = (ls_real)0, c0;
    uint32_t q;
    SIL_UNROLL
    for (q = 0; q < 3u; q++) {
        ls_real v;
        x[q] = sc->win[2 * (size_t)f[q]];
        y[q] = sc->win[2 * (size_t)f[q] + 1];
        rx[q] = x[q] - ed->a[0];
        ry[q] = y[q] - ed->a[1];
        v = r_abs(rx[q]) + r_abs(ry[q]);
        if (v > mc) mc = v;
    }
    sg = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    sg = sg > (ls_real)0 ? (ls_real)1 : (sg < (ls_real)0 ? (ls_real)-1 : (ls_real)0);
    if (sg == (ls_real)0) return 0;
    /* the rounding of c_q = num_q - t den_q (t in [0, 1]) from the corners'
     * offsets to a (mc bounds |x - a0| + |y - a1|, so |dx|, |dy| <= 2 mc):
     * below 4 eps (2 mc^2 + 2 mc eabs); not from the corners' magnitudes,
     * which in float put the margin pixels inside and no walk got through */
    c0 = (ls_real)16 * LS_REAL_EPSILON * mc * (mc + ed->eabs) + (ls_real)64 * R_MIN_NORMAL;
    SIL_UNROLL
    for (q = 0; q < 3u; q++) {
        uint32_t q1 = q == 2u ? 0u : q + 1u;
        ls_real dx = x[q1] - x[q], dy = y[q1] - y[q];
        num[q] = sg * (rx[q] * dy - ry[q] * dx);
        den[q] = sg * (ed->e[0] * dy - ed->e[1] * dx);
        m[q] = c0 + SIL_WALK_MARGIN * (r_abs(dx) > r_abs(dy) ? r_abs(dx) : r_abs(dy));
    }
    return 1;
}

/* The walk face holding the segment's point at t by the margins, found by
 * walking from o across the edge the point is farthest outside of
 * (normalized by the margins); LS_EDGE_NONE when the walk fails. Its
 * walk_sides are left in w (num, den, m), for walk_reach's first step. */
static uint32_t walk_locate(const sctx *sc, const sedge *ed, uint32_t o, ls_real t, ls_real w[9])
{
    ls_real *num = w, *den = w + 3, *m = w + 6;
    uint32_t step;
    for (step = 0; step < SIL_LOCATE_CAP; step++) {
        ls_real worst = (ls_real)0, c[3];
        uint32_t q, qw = 3u, tw;
        if (!walk_face(sc, ed, o) || !walk_sides(sc, ed, o, num, den, m)) return LS_EDGE_NONE;
        SIL_UNROLL
        for (q = 0; q < 3u; q++) c[q] = num[q] - t * den[q];
        /* inside by the margins (most tries): no division */
        if (c[0] >= m[0] && c[1] >= m[1] && c[2] >= m[2]) return o;
        SIL_UNROLL
        for (q = 0; q < 3u; q++) {
            if (!(c[q] >= m[q])) {
                ls_real r = c[q] / m[q];
                if (qw == 3u || r < worst) {
                    worst = r;
                    qw = q;
                }
            }
        }
        if (!(worst <= (ls_real)0)) return LS_EDGE_NONE; /* inside, but too near an edge (or NaN) */
        tw = sc->twin[3 * (size_t)o + qw];
        if (tw == LS_EDGE_NONE) return LS_EDGE_NONE;
        o = tw / 3u;
    }
    return LS_EDGE_NONE;
}

/* The walk of walk_hidden (above) from o, which holds the point at ts by
 * the margins of its edges but `in` (its entry edge, 3: none), towards tg:
 * returns the parameter up to which the segment is proven hidden (ts when
 * nothing is). Stopped by SIL_WALK_CAP, it leaves in *next the half-edge
 * to go on across (3 face + edge), else LS_EDGE_NONE.
 * first: o's walk_sides from walk_locate, or NULL; checked: 1 when an
 * earlier walk_reach from o with first found o in front of the segment at
 * ts (walk_front, its first step), which this one then does not test again.
 * Reaching tg at an end vertex of the segment (t = 0 at va, 1 at vb), it
 * records the face there in sc->wend, for the next segment through it. */
static ls_real walk_reach(const sctx *sc, const sedge *ed, uint32_t o, uint32_t in, ls_real ts, ls_real tg,
                          const ls_real *first, int checked, uint32_t *next)
{
    int up = tg > ts; /* the direction of the walk along t */
    uint32_t step;
    *next = LS_EDGE_NONE;
    for (step = 0; step < SIL_WALK_CAP; step++) {
        ls_real own[9], z[3], cs[3], cx[3], tx = tg;
        const ls_real *num = own, *den = own + 3, *m = own + 6;
        uint32_t q, qx = 3u, tw;
        if (step == 0 && first != NULL) {
            num = first;
            den = first + 3;
            m = first + 6;
        } else if (!walk_face(sc, ed, o) || !walk_sides(sc, ed, o, own, own + 3, own + 6)) {
            return ts;
        }
        SIL_UNROLL
        for (q = 0; q < 3u; q++) {
            cs[q] = num[q] - ts * den[q];
            if (q != in && cs[q] < m[q]) return ts; /* ts not inside by the margin */
            /* c_q falls along the walk: it leaves through q where c_q = 0 */
            if (q != in && (up ? den[q] > (ls_real)0 : den[q] < (ls_real)0)) {
                ls_real tq = num[q] / den[q];
                if (up ? tq < tx : tq > tx) {
                    tx = tq;
                    qx = q;
                }
            }
        }
        SIL_UNROLL
        for (q = 0; q < 3u; q++) {
            cx[q] = num[q] - tx * den[q];
            if (q != qx && cx[q] < m[q]) return ts; /* tx not inside (a corner, or tg) */
        }
        SIL_UNROLL
        for (q = 0; q < 3u; q++) z[q] = sc->zv[sc->indices[3 * (size_t)o + q]];
        if ((!checked && !walk_front(ed, cs, z, ts)) || !walk_front(ed, cx, z, tx)) return ts;
        if (qx == 3u) { /* tg reached: a walk of the next segment through an end vertex there starts from o */
            uint32_t v = tg == (ls_real)0 ? ed->va : (tg == (ls_real)1 ? ed->vb : LS_EDGE_NONE);
            if (v != LS_EDGE_NONE) sc->wend[v] = o + 1u;
            return tx;
        }
        tw = sc->twin[3 * (size_t)o + qx];
        if (tw == LS_EDGE_NONE) return tx;
        o = tw / 3u;
        in = tw % 3u;
        ts = tx;
        checked = 0;
    }
    *next = 3u * o + in; /* the last crossing's twin */
    return ts;
}

/* A run of the segment through one bin tile: its pieces, one per pixel,
 * [t[i], t[i + 1]] in pixel pix[i]. */
#define SIL_RUN_CAP 8
typedef struct srun {
    ls_real t[SIL_RUN_CAP + 1];
    size_t pix[SIL_RUN_CAP];
    size_t tile;
    int n;
} srun;

/* The forward's sample under window point (x, y) (walk_start, the hints). */
static SIL_INLINE size_t sample_under(const ls_vis *vis, ls_real x, ls_real y)
{
    ls_real ss = (ls_real)vis->ss;
    return (size_t)cell_of(y * ss, vis->sh) * vis->sw + cell_of(x * ss, vis->sw);
}

/* The walk face holding the segment's point at t by the margins (its
 * walk_sides in w), located from the triangle the forward drew at the
 * sample under the point at tq; LS_EDGE_NONE when that sample shows none
 * in front of the segment or the walk fails. */
static uint32_t walk_start(const sctx *sc, const sedge *ed, ls_real tq, ls_real t, ls_real w[9])
{
    const ls_vis *vis = sc->vis;
    size_t s = sample_under(vis, ed->a[0] + tq * ed->e[0], ed->a[1] + tq * ed->e[1]);
    uint32_t id = vis->tri[s];
    if (id == 0 || id - 1u == ed->ft || id - 1u == ed->fu) return LS_EDGE_NONE;
    /* the surface drawn there behind the segment's depth: no walk in front starts there */
    if (vis->depth[s] > ed->za + tq * (ed->zb - ed->za)) return LS_EDGE_NONE;
    return walk_locate(sc, ed, id - 1u, t, w);
}

/* Whether the segment's part in the image, [tbeg, tend], is hidden: a
 * quick proof that skips a segment whose every sub-piece the candidate
 * sweep would find hidden (most silhouette segments: two thirds of the
 * armadillo's); 0 leaves it to the runs. A walk starts from the face that
 * an earlier segment's walk found holding an end vertex of both (wend),
 * when the part has that end: one walk towards the other end, with no
 * sample and no walk_locate; else, or for what that one leaves, from the
 * triangle the forward drew at the sample under the middle of what is
 * left (walk_locate finds the face holding it from there), back towards
 * tbeg and on towards tend, each way going on once across a farther
 * surface. What it proves is kept as [wta, wtb] (the two walks' proofs
 * joined when they meet), which spares the runs and pixels inside it
 * (run_hidden). New walks from the runs found too few hidden ones to pay
 * (44.11M -> 42.96M instructions a view of the armadillo without them). */
LS_NOINLINE static int walk_segment(const sctx *sc, sedge *ed)
{
    ls_real t0 = ed->tbeg, t1 = ed->tend, tm, r[2], w[9], u[9];
    const ls_real *first = NULL;
    uint32_t id = LS_EDGE_NONE, nx = LS_EDGE_NONE, k, pass;
    if (sc->twin == NULL) return 0;
    for (pass = 0; pass < 2u; pass++) {
        if (pass == 0u) { /* the cached start: at va (t = 0), else at vb (t = 1) */
            tm = (ls_real)0;
            if (ed->va != LS_EDGE_NONE && t0 == tm && sc->wend[ed->va] != 0) {
                id = sc->wend[ed->va] - 1u;
            } else if (ed->vb != LS_EDGE_NONE && t1 == (ls_real)1 && sc->wend[ed->vb] != 0) {
                tm = (ls_real)1;
                id = sc->wend[ed->vb] - 1u;
            }
        } else {
            /* the middle of what the cached walk left */
            tm = (ed->wta <= t0 ? (ed->wtb > t0 ? ed->wtb : t0) + t1 : t0 + (ed->wta < t1 ? ed->wta : t1)) * (ls_real)0.5;
            id = walk_start(sc, ed, tm, tm, w);
            first = w;
        }
        if (id == LS_EDGE_NONE) continue;
        for (k = 0; k < 2u; k++) { /* back to t0, then on to t1 */
            ls_real tg = k ? t1 : t0, tq;
            uint32_t o;
            /* the walk back passed its first step's walk_front at tm unless it returned tm */
            r[k] = tm == tg ? tg : walk_reach(sc, ed, id, 3u, tm, tg, first, k && r[0] != tm, &nx);
            /* stopped short (but by the cap forwards: run_hidden goes on with that one), a walk
             * goes on once from whatever surface the sample 1.5 samples (along the major axis)
             * beyond shows: it most often stops at the contour of the surface it crossed, behind
             * which a farther one hides the segment */
            if (r[k] == tm || r[k] == tg || (k && nx != LS_EDGE_NONE)) continue;
            tq = (ls_real)1.5 / ((ls_real)sc->vis->ss * (r_abs(ed->e[0]) > r_abs(ed->e[1]) ? r_abs(ed->e[0]) : r_abs(ed->e[1])));
            tq = k ? r[1] + tq : r[0] - tq;
            if (k ? tq > tg : tq < tg) tq = tg;
            o = walk_start(sc, ed, tq, r[k], u);
            if (o != LS_EDGE_NONE) r[k] = walk_reach(sc, ed, o, 3u, r[k], tg, u, 0, &nx);
        }
        if (!(r[1] > r[0])) continue;
        if (!(r[1] >= ed->wta && r[0] <= ed->wtb)) { /* apart from the proof kept (or none): this one */
            ed->wta = r[0];
            ed->wtb = r[0];
        }
        if (r[0] < ed->wta) ed->wta = r[0];
        if (r[1] > ed->wtb) {
            ed->wtb = r[1];
            ed->wnext = nx;
        }
        if (ed->wta <= t0 && t1 <= ed->wtb) return 1;
    }
    return 0;
}

/* Whether the whole run lies in what the segment's walk proved hidden
 * (walk_segment), a walk stopped by the cap going on from where it stopped
 * when the run starts inside; else the run loses the pixels at either end
 * that lie inside it: run_pass sweeps each pixel as it would alone. */
LS_NOINLINE static int run_hidden(const sctx *sc, sedge *ed, srun *run)
{
    uint32_t nx;
    int j = 0, n = run->n;
    if (run->t[0] >= ed->wta && run->t[n] > ed->wtb && ed->wnext != LS_EDGE_NONE && ed->wtb >= run->t[0]) {
        ed->wtb = walk_reach(sc, ed, ed->wnext / 3u, ed->wnext % 3u, ed->wtb, ed->tend, NULL, 0, &nx);
        ed->wnext = nx;
    }
    while (j < n && run->t[j] >= ed->wta && run->t[j + 1] <= ed->wtb) j++; /* the first pixels */
    while (n > j && run->t[n - 1] >= ed->wta && run->t[n] <= ed->wtb) n--; /* the last ones */
    if (j > 0) {
        int k;
        for (k = j; k < n; k++) {
            run->t[k - j] = run->t[k];
            run->pix[k - j] = run->pix[k];
        }
        run->t[n - j] = run->t[n];
    }
    run->n = n - j;
    return run->n == 0;
}

/* Whether triangle g, every corner in front of the eye, with corner k at
 * the segment's end at a (dir 1) or at a + e (dir -1), holds no other point
 * of the segment: a triangle lies in the cone of its corner's two edges,
 * so it holds none when the segment's direction from that end, d, is
 * outside that cone by more than rounding (the cross products against
 * the two edges beyond 8 eps times the sums of their products' magnitudes,
 * above their rounding errors; the cone itself not degenerate). Most
 * faces around a silhouette edge's ends are such (measured: 44 % of the
 * faces whose box meets a run's on the fit's end mesh share a vertex
 * with the segment's face), and cost no candidate test. */
static int wedge_misses(const sctx *sc, const sedge *ed, const uint32_t *g, uint32_t k, ls_real dir)
{
    const ls_real *w = sc->win, *pa = w + 2 * (size_t)g[k];
    const ls_real *pp = w + 2 * (size_t)g[k == 2u ? 0u : k + 1u], *pq = w + 2 * (size_t)g[k == 0u ? 2u : k - 1u];
    ls_real px = pp[0] - pa[0], py = pp[1] - pa[1], qx = pq[0] - pa[0], qy = pq[1] - pa[1];
    ls_real dx = dir * ed->e[0], dy = dir * ed->e[1], e8 = (ls_real)8 * LS_REAL_EPSILON;
    ls_real o = px * qy - py * qx, bo = e8 * (r_abs(px * qy) + r_abs(py * qx)) + (ls_real)64 * R_MIN_NORMAL;
    ls_real c1, b1, c2, b2, sg;
    if (!(o > bo) && !(o < -bo)) return 0;
    sg = o > bo ? (ls_real)1 : (ls_real)-1; /* the cone's side: c < -b (o > 0) as -c < -b (o < 0) */
    c1 = px * dy - py * dx;
    b1 = e8 * (r_abs(px * dy) + r_abs(py * dx)) + (ls_real)64 * R_MIN_NORMAL;
    if (sg * c1 < -b1) return 1;
    c2 = dx * qy - dy * qx;
    b2 = e8 * (r_abs(dx * qy) + r_abs(dy * qx)) + (ls_real)64 * R_MIN_NORMAL;
    return sg * c2 < -b2;
}

/* Whether triangle id shares an end vertex with the segment and misses
 * the rest of it (wedge_misses); 0 leaves it to the candidate tests. Out
 * of line: inlined, its frame went into run_pass's, on the deepest chain
 * of the MCU's 4 KiB job stack (the Cortex-M4 double fit measured 4140
 * bytes). */
LS_NOINLINE static int end_face_misses(const sctx *sc, const sedge *ed, const uint32_t *g)
{
    uint32_t k;
    for (k = 0; k < 3u; k++) {
        if (g[k] != ed->va && g[k] != ed->vb) continue;
        if (!sc->allfront && (sc->vfront[g[0]] & sc->vfront[g[1]] & sc->vfront[g[2]]) == 0) return 0;
        return wedge_misses(sc, ed, g, k, g[k] == ed->va ? (ls_real)1 : (ls_real)-1);
    }
    return 0;
}

/* Whether every corner of triangle f, all in front of the eye, lies on one
 * side of the segment's line by cand_interval's margin for such corners
 * (tauv; not when cloc): its first test, which then rejects the triangle. */
static SIL_INLINE uint32_t one_side(const sctx *sc, const sedge *ed, const uint32_t *f)
{
    uint32_t q, up = 1, dn = 1;
    SIL_UNROLL
    for (q = 0; q < 3u; q++) {
        const ls_real *p = sc->win + 2 * (size_t)f[q];
        /* cand_interval's expression, so the same bits */
        ls_real rx = p[0] - ed->a[0], ry = p[1] - ed->a[1], sd = ed->e[0] * ry - ed->e[1] * rx;
        up &= (uint32_t)(sd > ed->tauv);
        dn &= (uint32_t)(sd < -ed->tauv);
    }
    return up | dn;
}

/* The pieces of a run: the candidates of the tile's bin whose box meets
 * the run's box, the parameters where their polygon edges cross the
 * segment (visibility and the surface behind are constant between two of
 * them, and between two pixel boundaries), each sub-piece integrated on its
 * own with its pixel's weights; the candidates are swept along the run by
 * their intervals. A candidate of the run that is no candidate of a piece
 * (its box misses the piece's box) neither crosses nor holds the piece, so
 * every piece gets the sub-pieces and the answers it would get alone. */
static void run_pass(const sctx *sc, sedge *ed, const srun *run)
{
    size_t k;
    ls_real *sp = sc->split, t0 = run->t[0], t1 = run->t[run->n];
    ls_real xa = ed->a[0] + t0 * ed->e[0], xb = ed->a[0] + t1 * ed->e[0];
    ls_real ya = ed->a[1] + t0 * ed->e[1], yb = ed->a[1] + t1 * ed->e[1];
    uint32_t ncand = 0, ns = 0, nact = 0, next = 0, i = 0, nhit = 0, nkeep = 0, nend = 0, va = ed->va, vb = ed->vb;
    const int allfront = sc->allfront;
    float fx0, fx1, fy0, fy1;
    int j;
    /* the pixels' image gradient, read by the quadrature after the candidate search */
    for (j = 0; SIL_FETCH && j < run->n; j++) SIL_PREFETCH(sc->gimg + 4 * run->pix[j]);
    /* the run's box, grown by the margin */
    fx0 = (float)((xa < xb ? xa : xb) - SIL_MARGIN);
    fx1 = (float)((xa < xb ? xb : xa) + SIL_MARGIN);
    fy0 = (float)((ya < yb ? ya : yb) - SIL_MARGIN);
    fy1 = (float)((ya < yb ? yb : ya) + SIL_MARGIN);
    /* the bin's triangles whose box meets the run's, gathered into cact
     * (free until the sweep; a bin holds at most one entry per binned
     * triangle, so it fits) without a branch per entry: about a third
     * meet it, in no predictable order */
    {
        const uint32_t *ent = sc->ent;
        const float *tbox = sc->tbox;
        uint32_t *out = sc->cact;
        size_t kb = sc->offs[run->tile], ke = sc->offs[run->tile + 1u], nh = 0;
#if SIL_SSE
        /* (x0, y0, -x1, -y1) <= (fx1, fy1, -fx0, -fy0) in every lane: the boxes
         * are finite (box_fbox), so the negated misses below are these */
        const __m128 lim = _mm_setr_ps(fx1, fy1, -fx0, -fy0), flip = _mm_setr_ps(0.0f, 0.0f, -0.0f, -0.0f);
#endif
        SIL_UNROLL
        for (k = kb; k < ke; k++) {
            uint32_t id = ent[k];
            const float *bx = tbox + 4 * (size_t)id;
#if SIL_SSE
            /* all four lanes: mask 15, and (15 + 1) >> 4 is the only 1 */
            size_t hit = ((size_t)_mm_movemask_ps(_mm_cmple_ps(_mm_xor_ps(_mm_loadu_ps(bx), flip), lim)) + 1u) >> 4;
#else
            /* the hit as a product of the four negated misses: one add, no 1 - miss */
            size_t hit = (size_t)((!(bx[2] < fx0)) & (!(bx[0] > fx1))) & (size_t)((!(bx[3] < fy0)) & (!(bx[1] > fy1)));
#endif
            out[nh] = id;
            nh += hit;
        }
        nhit = (uint32_t)nh;
    }
#if SIL_SSE2
    /* va and vb in every lane; the corners' vector has a 0 in its last lane, masked off */
    const __m128i eva = _mm_set1_epi32((int)va), evb = _mm_set1_epi32((int)vb);
#endif
    /* the hits sorted without a branch per hit (which have an end vertex,
     * or every corner on one side, follows no pattern): own faces dropped,
     * faces with an end vertex listed in cord (free until the candidates
     * are recorded) for the wedge test, the others kept in cact unless
     * one_side rejects them; the candidates are the same in any order */
    for (k = 0; k < nhit; k++) {
        uint32_t id = sc->cact[k], end, skip;
        const uint32_t *f = sc->indices + 3 * (size_t)id;
#if SIL_SSE2
        __m128i fv = _mm_unpacklo_epi64(_mm_loadl_epi64((const __m128i *)(const void *)f), _mm_cvtsi32_si128((int)f[2]));
        end = _mm_movemask_ps(_mm_castsi128_ps(_mm_or_si128(_mm_cmpeq_epi32(fv, eva), _mm_cmpeq_epi32(fv, evb)))) & 7 ? 1u : 0u;
#else
        end = ((f[0] == va) | (f[0] == vb)) | ((f[1] == va) | (f[1] == vb)) | ((f[2] == va) | (f[2] == vb));
#endif
        skip = (uint32_t)((id == ed->ft) | (id == ed->fu)); /* own face */
        sc->cord[nend] = id;
        nend += (skip ^ 1u) & end;
        skip |= end;
        /* (where code size counts, cand_interval alone rejects them) */
        if (SIL_SPECIALIZE && !ed->cloc && tri_front(sc, allfront, f)) skip |= one_side(sc, ed, f);
        sc->cact[nkeep] = id;
        nkeep += skip ^ 1u;
    }
    for (k = 0; k < nend + nkeep; k++) {
        uint32_t id = k < nend ? sc->cord[k] : sc->cact[k - nend];
        const uint32_t *f = sc->indices + 3 * (size_t)id;
        ls_real lo, hi;
        int in, front;
        /* (about a third of the hits have an end vertex; 87 % of those miss) */
        if (k < nend && end_face_misses(sc, ed, f)) continue;
        front = tri_front(sc, allfront, f);
        if (SIL_SPECIALIZE && front) {
            /* corners of its own, which never reach memory, and the triangle copy */
            ls_real x[4], y[4];
            tri_win(sc, f, x, y);
            in = cand_interval(ed, x, y, 3, 1, t0, t1, sp, &ns, &lo, &hi);
        } else { /* one call where code size counts */
            ls_real x[4], y[4];
            int n = 3;
            if (front)
                tri_win(sc, f, x, y);
            else
                n = tri_poly_cut(sc, f, x, y);
            in = n >= 3 && cand_interval(ed, x, y, n, front, t0, t1, sp, &ns, &lo, &hi);
        }
        if (!in) continue;
        if (SIL_FETCH) { /* a candidate may be the surface behind: the quadrature reads its corners */
            int q;
            for (q = 0; q < 3; q++) {
                SIL_PREFETCH(sc->vis->clip + 4 * (size_t)f[q]);
                if (sc->normals != NULL) SIL_PREFETCH(sc->normals + 3 * (size_t)f[q]);
            }
        }
        /* cord[ncand]: ncand <= k, so an end face not read yet is not overwritten */
        sc->cid[ncand] = id;
        sc->chi[ncand] = hi;
        sc->clo[ncand] = lo;
        sc->cord[ncand] = ncand;
        ncand++;
    }
    sort_splits(sp, ns);
    /* the candidates activated in order of their starts, even a few: with
     * all active from the start, half the visibility tests skipped one not
     * begun yet (2-2.6 % slower on the armadillo at 512^2, paired) */
    sort_keyed(sc->clo, sc->cord, ncand);
    for (j = 0; j < run->n; j++) {
        ls_real a = run->t[j], b = run->t[j + 1], plo = a, phi = a;
        uint32_t pbeh = 0;
        int pend = 0; /* [plo, phi] seen with the surface pbeh behind, not integrated yet */
        while (i < ns && !(sp[i] > a)) i++; /* crossings at or before the piece's start */
        for (;;) {
            uint32_t beh = 0;
            ls_real lo = a, hi = i < ns && sp[i] < b ? sp[i++] : b;
            a = hi;
            if (hi > lo) {
                ls_real mid = (lo + hi) * (ls_real)0.5;
                while (next < ncand && !(sc->clo[next] > mid)) sc->cact[nact++] = sc->cord[next++];
                if (visibility(sc, ed, mid, &nact, &beh)) {
                    /* a split whose crossing changed neither side (an edge farther than the surface
                     * behind, or of an occluder elsewhere) joins the two sub-pieces: one integrand */
                    if (pend && (beh != pbeh || phi != lo)) integrate(sc, ed, plo, phi, pbeh, run->pix[j]);
                    if (!pend || beh != pbeh || phi != lo) plo = lo;
                    phi = hi;
                    pbeh = beh;
                    pend = 1;
                } else if (pend) {
                    integrate(sc, ed, plo, phi, pbeh, run->pix[j]);
                    pend = 0;
                }
            }
            if (!(hi < b)) break;
        }
        if (pend) integrate(sc, ed, plo, phi, pbeh, run->pix[j]);
    }
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
 * k = first, first + step, ... (count of them) at t = (k - a) / e; next:
 * the parameter of line k (t_end when none is left), kept from one step
 * to the next (one division per crossing). */
typedef struct lines {
    ls_real k, step, a, e, next;
    int32_t left;
} lines;

static void lines_next(lines *l, ls_real t_end)
{
    l->next = l->left > 0 ? (l->k - l->a) / l->e : t_end;
}

static void lines_init(lines *l, ls_real a, ls_real e, ls_real t0, ls_real t1)
{
    ls_real s = a + t0 * e, f = a + t1 * e, lo = s < f ? s : f, hi = s < f ? f : s, first, last;
    l->a = a;
    l->e = e;
    l->left = 0;
    if (lo > (ls_real)-1073741824 && hi < (ls_real)1073741824) {
        /* the part in the image (clip_rect), ends within rounding of it:
         * floor(lo) and ceil(hi) by truncation, without ls_floor's calls */
        int32_t fl = (int32_t)lo, ce = (int32_t)hi;
        fl -= (int32_t)((ls_real)fl > lo);
        ce += (int32_t)((ls_real)ce < hi);
        first = (ls_real)fl + (ls_real)1;
        last = (ls_real)ce - (ls_real)1;
    } else {
        first = LS_RFLOOR(lo) + (ls_real)1;
        last = -LS_RFLOOR(-hi) - (ls_real)1;
    }
    if (e != (ls_real)0 && !(last < first)) {
        l->left = LS_RTO_I32(last - first) + 1;
        l->step = e > (ls_real)0 ? (ls_real)1 : (ls_real)-1;
        l->k = e > (ls_real)0 ? first : last;
    }
    lines_next(l, t1);
}

/* Past line k: on to the next. */
static void lines_step(lines *l, ls_real t_end)
{
    l->left--;
    l->k += l->step;
    lines_next(l, t_end);
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

/* Sends the gradient g (clip space) of segment end ep to the vertices: a
 * vertex directly; a point p + s (q - p) clipped at the near plane, with
 * s = dp / (dp - dq), d = Z + W, through (1 - s), s and s itself. */
static void end_to_positions(const sctx *sc, const endp *ep, const ls_real g[4], ls_real *gp)
{
    const ls_real *p = sc->vis->clip + 4 * (size_t)ep->v, *q = sc->vis->clip + 4 * (size_t)ep->w;
    ls_real dp = p[2] + p[3], dq = q[2] + q[3], den = dp - dq, gs, ds_dp, ds_dq, a[4], b[4], s = ep->s;
    int r;
    if (!ep->clipped) {
        clip_to_positions(sc, ep->v, g, gp);
        return;
    }
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
    clip_to_positions(sc, ep->v, a, gp);
    clip_to_positions(sc, ep->w, b, gp);
}

/* End of edge v -> w: the vertex, or (v behind the near plane) the point
 * where the edge crosses it. */
static void end_make(const sctx *sc, uint32_t v, uint32_t w, endp *ep)
{
    const ls_real *p = sc->vis->clip + 4 * (size_t)v, *q = sc->vis->clip + 4 * (size_t)w;
    ls_real dp = p[2] + p[3], dq = q[2] + q[3];
    ep->v = v;
    ep->w = w;
    ep->clipped = dp < (ls_real)0;
    ep->s = (ls_real)0;
    if (ep->clipped) {
        ep->s = dp / (dp - dq);
        near_point(p, q, ep->s, ep->c);
    } else {
        int r;
        for (r = 0; r < 4; r++) ep->c[r] = p[r];
    }
}

/* Window position w and NDC depth *z of segment end ep: a vertex's from
 * the pass's arrays (the same bits, no divisions), a cut end's computed. */
static inline void end_window(const sctx *sc, const endp *ep, ls_real w[2], ls_real *z)
{
    if (ep->clipped) {
        window_of(sc, ep->c, w);
        *z = ep->c[2] / ep->c[3];
        return;
    }
    w[0] = sc->win[2 * (size_t)ep->v];
    w[1] = sc->win[2 * (size_t)ep->v + 1];
    *z = sc->zv[ep->v];
}

/* One silhouette segment A -> B of face ft (twin fu), its ends those of
 * the edges v[0] -> v[1] and v[2] -> v[3] (end_make); C: a point of the
 * face off the segment's line (clip space), which tells the covered side. */
static void segment_pass(const sctx *sc, uint32_t ft, uint32_t fu, const uint32_t v[4], const ls_real *C)
{
    endp ends[2];
    const endp *ea = ends, *eb = ends + 1;
    sedge ed;
    ls_real b[2], nrm[2], t0 = (ls_real)0, t1 = (ls_real)1, tcur, side, g[4];
    lines lx, ly;
    srun run;
    uint32_t px, py;
    size_t tile;
    end_make(sc, v[0], v[1], &ends[0]);
    end_make(sc, v[2], v[3], &ends[1]);
    if (!(ea->c[3] > (ls_real)0) || !(eb->c[3] > (ls_real)0)) return;
    ed.ft = ft;
    ed.fu = fu;
    ed.va = ea->clipped ? LS_EDGE_NONE : ea->v;
    ed.vb = eb->clipped ? LS_EDGE_NONE : eb->v;
    ed.wta = R_MAX;
    ed.wtb = (ls_real)0;
    ed.wnext = LS_EDGE_NONE;
    ed.ka = (ls_real)0;
    ed.kb = (ls_real)0;
    end_window(sc, ea, ed.a, &ed.za);
    end_window(sc, eb, b, &ed.zb);
    ed.e[0] = b[0] - ed.a[0];
    ed.e[1] = b[1] - ed.a[1];
    ed.eabs = r_abs(ed.e[0]) + r_abs(ed.e[1]);
    ed.ext = (r_abs(ed.a[0]) + r_abs(ed.a[1])) + ed.eabs;
    ed.tau = SIL_MARGIN * (r_abs(ed.e[0]) > r_abs(ed.e[1]) ? r_abs(ed.e[0]) : r_abs(ed.e[1]));
    if (!clip_rect(sc, ed.a, ed.e, &t0, &t1)) return;
    ed.tbeg = t0;
    ed.tend = t1;
    ed.tinv = (ls_real)1 / (t1 - t0);
    ed.fok = 0;
    /* a walk over the whole segment first, before its pixels are walked:
     * the gradient of a hidden one is 0 */
    if (walk_segment(sc, &ed)) return;
    /* sc->wk (above every window corner's |x| + |y|) for cand_interval's mc (the runs' candidates) */
    ed.tauv = ed.tau + (ls_real)64 * LS_REAL_EPSILON * (sc->wk + ed.ext) * ed.eabs;
    ed.c0v = (ls_real)128 * LS_REAL_EPSILON * sc->wk * (sc->wk + ed.ext);
    ed.cloc = !(ed.c0v <= SIL_LOOSE); /* and NaN */
    /* normal scaled by |e|, pointing away from the face's side: window y
     * runs down, so the window-space side is minus the homogeneous one */
    side = -hdet(ea->c, eb->c, C);
    if (side == (ls_real)0 || side - side != (ls_real)0) return;
    nrm[0] = ed.e[1];
    nrm[1] = -ed.e[0];
    /* (e1, -e0) . (c - a) = -(e x (c - a)): it points towards the face when side < 0 */
    if (side < (ls_real)0) {
        nrm[0] = -nrm[0];
        nrm[1] = -nrm[1];
    }
    run.n = 0;
    lines_init(&lx, ed.a[0], ed.e[0], t0, t1);
    lines_init(&ly, ed.a[1], ed.e[1], t0, t1);
    tcur = t0;
    while (tcur < t1) {
        ls_real tx = lx.next, ty = ly.next, tn = t1, mid;
        if (tx < tn) tn = tx;
        if (ty < tn) tn = ty;
        if (tx <= tn && lx.left > 0) lines_step(&lx, t1);
        if (ty <= tn && ly.left > 0) lines_step(&ly, t1);
        if (tn <= tcur) continue; /* a crossing at (or before) the current point */
        mid = (tcur + tn) * (ls_real)0.5;
        px = cell_of(ed.a[0] + mid * ed.e[0], sc->vis->width);
        py = cell_of(ed.a[1] + mid * ed.e[1], sc->vis->height);
        tile = (size_t)(py >> sc->tl) * sc->tiles_x + (px >> sc->tl);
        if (run.n > 0 && (tile != run.tile || run.n == SIL_RUN_CAP)) {
            if (!run_hidden(sc, &ed, &run)) run_pass(sc, &ed, &run);
            run.n = 0;
        }
        if (run.n == 0) {
            run.tile = tile;
            run.t[0] = tcur;
        }
        run.pix[run.n] = (size_t)py * sc->vis->width + px;
        run.t[++run.n] = tn;
        tcur = tn;
    }
    if (run.n > 0 && !run_hidden(sc, &ed, &run)) run_pass(sc, &ed, &run);
    ed.ka *= sc->boost;
    ed.kb *= sc->boost;
    window_to_clip(sc, ea->c, nrm[0] * ed.ka, nrm[1] * ed.ka, g);
    end_to_positions(sc, ea, g, sc->gp);
    window_to_clip(sc, eb->c, nrm[0] * ed.kb, nrm[1] * ed.kb, g);
    end_to_positions(sc, eb, g, sc->gp);
}

/* Triangle t cut by the near plane: the cut (between the two points where
 * its edges cross the plane) bounds what is drawn of it. */
LS_NOINLINE static void cut_pass(const sctx *sc, uint32_t t)
{
    const uint32_t *f = sc->indices + 3 * (size_t)t;
    ls_real d[3];
    uint32_t ends[4];
    int k, n = 0, front = 0;
    for (k = 0; k < 3; k++) {
        const ls_real *c = sc->vis->clip + 4 * (size_t)f[k];
        d[k] = c[2] + c[3];
        if (d[k] >= (ls_real)0 && (front == 0 || d[k] > d[front - 1])) front = k + 1;
    }
    if (front == 0 || (d[0] >= (ls_real)0 && d[1] >= (ls_real)0 && d[2] >= (ls_real)0)) return;
    for (k = 0; k < 3; k++) {
        uint32_t v = f[k], w = f[(k + 1) % 3];
        if ((d[k] >= (ls_real)0) == (d[(k + 1) % 3] >= (ls_real)0) || n == 4) continue;
        ends[n++] = d[k] < (ls_real)0 ? v : w; /* from the vertex behind */
        ends[n++] = d[k] < (ls_real)0 ? w : v;
    }
    if (n == 4) segment_pass(sc, t, LS_EDGE_NONE, ends, sc->vis->clip + 4 * (size_t)f[front - 1]);
}

/* The vertex of half-edge h's face that is not on h (its corner (h + 2) % 3):
 * for a twin, the far corner the fold and valley tests read. */
static SIL_INLINE uint32_t far_vertex(const uint32_t *indices, uint32_t h)
{
    uint32_t k = h % 3u;
    return indices[3 * (size_t)(h / 3u) + (k == 0u ? 2u : k - 1u)];
}

/* Whether interior edge h (twin tw) is a silhouette: its two faces lie on
 * the same side of its screen line (one front-, one back-facing). Certain
 * orientations (tri_sign) decide at once: the face across the edge has the
 * opposite cyclic order of its vertices, so the two determinants of the
 * edge test have the signs of sign[ft] and -sign[fu]. */
static int folds(const sctx *sc, uint32_t h, uint32_t tw)
{
    uint32_t ft = h / 3u, fu = tw / 3u;
    int s1 = sc->sign[ft], s2 = sc->sign[fu]; /* NOLINT(bugprone-signed-char-misuse,cert-str34-c): small integers (-2..2), not characters */
    const uint32_t *f;
    const ls_real *c;
    ls_real sc_, sd_;
    if ((s1 == 2 || s1 == -2) && (s2 == 2 || s2 == -2)) return s1 == -s2;
    f = sc->indices + 3 * (size_t)ft;
    c = sc->vis->clip;
    sc_ = hdet(c + 4 * (size_t)f[h % 3u], c + 4 * (size_t)f[(h % 3u + 1u) % 3u], c + 4 * (size_t)far_vertex(sc->indices, h));
    sd_ = hdet(c + 4 * (size_t)f[h % 3u], c + 4 * (size_t)f[(h % 3u + 1u) % 3u], c + 4 * (size_t)far_vertex(sc->indices, tw));
    return (sc_ > (ls_real)0 && sd_ > (ls_real)0) || (sc_ < (ls_real)0 && sd_ < (ls_real)0);
}

/* ls_valley_edge (render_internal.h). Out of line: its locals stay out of
 * edges_pass's frame (the deep chain's, the MCU's job stack). */
LS_NOINLINE int ls_valley_edge(const ls_real *clip, const uint32_t *indices, uint32_t h, uint32_t tw, int cull)
{
    const uint32_t *f = indices + 3 * (size_t)(h / 3u), *g = indices + 3 * (size_t)(tw / 3u);
    uint32_t k = h % 3u, i, j;
    const ls_real *p = clip + 4 * (size_t)f[k], *o[3];
    ls_real m[3][3], u[3][3], e[3][3], det, pu, pe, bound, w = p[3];
    o[0] = clip + 4 * (size_t)f[k == 2u ? 0u : k + 1u];
    o[1] = clip + 4 * (size_t)f[k == 0u ? 2u : k - 1u];
    o[2] = clip + 4 * (size_t)far_vertex(indices, tw);
    /* the faces wound the same way (the twin runs back along the edge): the
     * edge table pairs the faces of an edge whatever their order */
    if (cull == 0 || !(w > (ls_real)0) || g[tw % 3u] != f[k == 2u ? 0u : k + 1u]) return 0;
    SIL_UNROLL
    for (i = 0; i < 3u; i++) {
        const ls_real *oi = o[i];
        SIL_UNROLL
        for (j = 0; j < 3u; j++) m[i][j] = w * oi[j] - oi[3] * p[j];
    }
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])) +
          m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if (!(cull < 0 ? det < (ls_real)0 : det > (ls_real)0)) return 0; /* a ridge (most), or no cull */
    SIL_UNROLL
    for (i = 0; i < 3u; i++) {
        SIL_UNROLL
        for (j = 0; j < 3u; j++) {
            u[i][j] = r_abs(m[i][j]);
            e[i][j] = u[i][j] + (ls_real)2 * LS_REAL_EPSILON * (r_abs(w * o[i][j]) + r_abs(o[i][3] * p[j])); /* and its rounding */
        }
    }
    /* permanents: of |m|, and of |m| grown by the rows' rounding; their
     * difference bounds what that rounding does to det */
    pu = (u[0][0] * (u[1][1] * u[2][2] + u[1][2] * u[2][1]) + u[0][1] * (u[1][0] * u[2][2] + u[1][2] * u[2][0])) +
         u[0][2] * (u[1][0] * u[2][1] + u[1][1] * u[2][0]);
    pe = (e[0][0] * (e[1][1] * e[2][2] + e[1][2] * e[2][1]) + e[0][1] * (e[1][0] * e[2][2] + e[1][2] * e[2][0])) +
         e[0][2] * (e[1][0] * e[2][1] + e[1][1] * e[2][0]);
    bound = (pe - pu) + (ls_real)16 * LS_REAL_EPSILON * pe + (ls_real)64 * R_MIN_NORMAL;
    /* the 4 x 4 determinant's sign is -det's */
    return r_abs(det) > bound;
}

/* choose_cull's count of a sample showing id into cnt: covered, showing
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
 * tested; the armadillo at 512^2 spent 0.05 ms a view on every 4th).
 * sign: per-triangle orientations (tri_sign), or NULL (the sizing query:
 * slower, no memory). Returns the covered samples estimated from those
 * rows, for choose_tiles (counted alone, lim = 0, when nothing can be
 * culled). */
static uint64_t choose_cull(sctx *sc, const ls_edge_table *table, const signed char *sign)
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

/* Candidate slots of a view: a piece's candidates come from one tile's bin,
 * at most one entry per binned triangle (at least one slot). */
static size_t slot_count(size_t binned, size_t entries)
{
    size_t n = binned < entries ? binned : entries;
    return n > 0 ? n : 1u;
}

/* Everything the pass needs, in the order it takes it: window positions
 * and depths, bin starts, orientations, vertex flags, triangle boxes, the
 * triangles binned, edge marks, bin entries, the candidate
 * slots and the split parameters (4 per slot and the piece's ends). */
static ls_status scratch_size(uint32_t vertex_count, size_t tiles, uint32_t triangle_count, size_t entries,
                              size_t slots, size_t *bytes)
{
    ls_size s;
    if (tiles > SIZE_MAX - 2u || slots > (SIZE_MAX - 2u) / 4u) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)vertex_count, 2 * sizeof(ls_real));
    ls_size_add(&s, (size_t)vertex_count, sizeof(ls_real));
    ls_size_add(&s, tiles + 2u, sizeof(size_t)); /* bin starts and bin_pass's extra cursor */
    ls_size_add(&s, (size_t)triangle_count + 1u, 1); /* orientations and next_edge's sentinel */
    ls_size_add(&s, (size_t)vertex_count, 1);
    ls_size_add(&s, (size_t)triangle_count, 4 * sizeof(float));
    ls_size_add(&s, (size_t)triangle_count, sizeof(uint32_t));
    ls_size_add(&s, 3 * (size_t)triangle_count / 64u + 1u, sizeof(uint64_t)); /* edge marks (next_edge) */
    ls_size_add(&s, entries, sizeof(uint32_t));
    ls_size_add(&s, slots, sizeof(uint32_t)); /* cid */
    ls_size_add(&s, slots, sizeof(ls_real));  /* chi */
    ls_size_add(&s, slots, sizeof(ls_real));  /* clo */
    ls_size_add(&s, slots, sizeof(uint32_t)); /* cord */
    ls_size_add(&s, slots, sizeof(uint32_t)); /* cact */
    ls_size_add(&s, 4u * slots + 2u, sizeof(ls_real));
    ls_size_add(&s, 1, sizeof(spiece));
    ls_size_add(&s, (size_t)vertex_count, sizeof(uint32_t)); /* wend */
    return ls_size_get(&s, bytes);
}

static ls_status check_args(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                            const ls_real *normals, const ls_shade_opts *opts, const uint32_t counts[2], ls_diag *diag)
{
    if (vis == NULL || table == NULL || opts == NULL) return LS_ERR_INVALID;
    if (vis->tri == NULL || vis->clip == NULL || table->magic != EDGE_TABLE_MAGIC) return LS_ERR_STATE;
    if (table->triangle_count != counts[0] || table->vertex_count != counts[1]) return LS_ERR_INVALID;
    return ls_shade_check_args(vis, counts, indices, normals, opts, diag);
}

/* The bins' tile side, 2^tl pixels: 2, 4 or 8 by the covered pixels per
 * triangle (cov: choose_cull's estimate of the covered samples): small
 * triangles want small tiles (fewer candidates per run), large ones large
 * tiles (fewer entries per triangle, fewer and longer runs). The
 * thresholds, 1/8 and 1/2 covered pixel per triangle, are the measured
 * crossovers on the armadillo at 128^2 to 512^2 and the bunny at 64^2 and
 * 128^2 (the choice changes no bit, only which triangles are tested).
 * 2 x 2 is the smallest, so sizes counted with 2 x 2 tiles (the bounds
 * below) hold for every choice. */
static void choose_tiles(sctx *sc, uint64_t cov)
{
    const ls_vis *vis = sc->vis;
    uint64_t ts = (uint64_t)sc->triangle_count * vis->ss * vis->ss;
    /* ts: triangles x samples per pixel */
    sc->tl = 8u * cov < ts ? SIL_TILE_LOG2 : (2u * cov < ts ? SIL_TILE_LOG2 + 1u : SIL_TILE_LOG2 + 2u);
    sc->tiles_x = (vis->width + (1u << sc->tl) - 1u) >> sc->tl;
    sc->tiles_y = (vis->height + (1u << sc->tl) - 1u) >> sc->tl;
    sc->tside_inv = 1.0f / (float)(1u << sc->tl);
}

static void sctx_init(sctx *sc, const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count)
{
    memset(sc, 0, sizeof *sc);
    sc->vis = vis;
    sc->indices = indices;
    sc->triangle_count = triangle_count;
    sc->width = (ls_real)vis->width;
    sc->height = (ls_real)vis->height;
    sc->tl = SIL_TILE_LOG2;
    sc->tiles_x = (vis->width + (1u << SIL_TILE_LOG2) - 1u) >> SIL_TILE_LOG2;
    sc->tiles_y = (vis->height + (1u << SIL_TILE_LOG2) - 1u) >> SIL_TILE_LOG2;
    sc->tside_inv = 1.0f / (float)(1u << SIL_TILE_LOG2);
}

ls_status ls_silhouette_scratch_bytes(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                      uint32_t triangle_count, size_t *bytes)
{
    sctx sc;
    size_t count[2] = {0, 0};
    int over = 0;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (vis == NULL || table == NULL || (triangle_count > 0 && indices == NULL)) return LS_ERR_INVALID;
    if (vis->tri == NULL || vis->clip == NULL || table->magic != EDGE_TABLE_MAGIC) return LS_ERR_STATE;
    if (vis->triangle_count != triangle_count || table->triangle_count != triangle_count) return LS_ERR_INVALID;
    if (ls_check_triangle_indices(indices, triangle_count, vis->vertex_count, NULL) != LS_OK) return LS_ERR_MESH;
    sctx_init(&sc, vis, indices, triangle_count);
    choose_tiles(&sc, choose_cull(&sc, table, NULL));
    box_pass(&sc, count, &over);
    if (over) return LS_ERR_TOO_LARGE;
    return scratch_size(vis->vertex_count, (size_t)sc.tiles_x * sc.tiles_y, triangle_count, count[0],
                        slot_count(count[1], count[0]), bytes);
}

/* The scratch for a view of this size whose bins hold `entries` entries. */
static ls_status scratch_for_entries(uint32_t width, uint32_t height, uint32_t vertex_count,
                                     uint32_t triangle_count, size_t entries, size_t *bytes)
{
    size_t tiles = (size_t)((width >> SIL_TILE_LOG2) + 1u) * (size_t)((height >> SIL_TILE_LOG2) + 1u);
    return scratch_size(vertex_count, tiles, triangle_count, entries, slot_count(triangle_count, entries), bytes);
}

ls_status ls_silhouette_scratch_bytes_bins(uint32_t width, uint32_t height, uint32_t vertex_count,
                                           uint32_t triangle_count, uint32_t per_triangle, uint32_t per_tile,
                                           size_t *bytes)
{
    uint64_t tiles, entries;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (width == 0 || height == 0) return LS_ERR_INVALID;
    tiles = (uint64_t)((width >> SIL_TILE_LOG2) + 1u) * (uint64_t)((height >> SIL_TILE_LOG2) + 1u);
    entries = (uint64_t)per_triangle * triangle_count + (uint64_t)per_tile * tiles;
    if (entries > (uint64_t)SIZE_MAX / 16u) return LS_ERR_TOO_LARGE;
    return scratch_for_entries(width, height, vertex_count, triangle_count, (size_t)entries, bytes);
}

ls_status ls_silhouette_scratch_bytes_bound(uint32_t width, uint32_t height, uint32_t vertex_count,
                                            uint32_t triangle_count, size_t *bytes)
{
    uint64_t tiles;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (width == 0 || height == 0) return LS_ERR_INVALID;
    tiles = (uint64_t)((width >> SIL_TILE_LOG2) + 1u) * (uint64_t)((height >> SIL_TILE_LOG2) + 1u);
    if (tiles > (uint64_t)SIZE_MAX / 16u || (triangle_count > 0 && tiles > (uint64_t)SIZE_MAX / triangle_count))
        return LS_ERR_TOO_LARGE;
    return scratch_for_entries(width, height, vertex_count, triangle_count, (size_t)tiles * triangle_count, bytes);
}

/* The index of the lowest set bit of m != 0: a de Bruijn multiply (C99 has no builtin). */
static uint32_t low_bit(uint64_t m)
{
    static const unsigned char idx[64] = {0,  1,  48, 2,  57, 49, 28, 3,  61, 58, 50, 42, 38, 29, 17, 4,
                                          62, 55, 59, 36, 53, 51, 43, 22, 45, 39, 33, 30, 24, 18, 12, 5,
                                          63, 47, 56, 27, 60, 41, 37, 16, 54, 35, 52, 21, 44, 32, 23, 11,
                                          46, 26, 40, 15, 34, 20, 31, 10, 25, 14, 19, 9,  13, 8,  7,  6};
    return idx[((m & ((uint64_t)0 - m)) * 0x03f79d71b4cb0a89ull) >> 58];
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

/* Bit k of x at bit 2 k (x < 2^16): one coordinate of a Morton code. */
static uint32_t morton_spread(uint32_t x)
{
    x = (x | (x << 8)) & 0x00ff00ffu;
    x = (x | (x << 4)) & 0x0f0f0f0fu;
    x = (x | (x << 2)) & 0x33333333u;
    return (x | (x << 1)) & 0x55555555u;
}

/* A window coordinate's 4-pixel cell, clamped to [0, 2^16) (0 for NaN). */
static uint32_t morton_cell(ls_real c)
{
    c *= (ls_real)0.25;
    if (!(c >= (ls_real)1)) return 0;
    return c < (ls_real)65535 ? (uint32_t)c : 65535u;
}

/* Edge h from v0 to v1 as the integration order's key: the Morton code of
 * the 4 x 4-pixel cell of its window midpoint (0 for an end behind the
 * near plane, whose window position is 0), then h. Every key differs. */
static uint64_t edge_key(const sctx *sc, uint32_t h, uint32_t v0, uint32_t v1)
{
    const ls_real *a = sc->win + 2 * (size_t)v0, *b = sc->win + 2 * (size_t)v1;
    uint32_t m = morton_spread(morton_cell((a[0] + b[0]) * (ls_real)0.5)) |
                 (morton_spread(morton_cell((a[1] + b[1]) * (ls_real)0.5)) << 1);
    return ((uint64_t)m << 32) | h;
}

/* Sorts a[0..n) by their high 32 bits (the keys of edge_key, whose low
 * bits, the half-edges, are in increasing order on entry), through tmp[n]:
 * LSD radix sort by 7-bit digits, stable, as many passes as the largest
 * key has digits (2 for the cells of a 512^2 image); every entry differs,
 * so this is the one increasing order. Out of line: its counts stay off
 * the deep chain's frames (the MCU's stack). */
LS_NOINLINE static void sort_keys(uint64_t *a, uint64_t *tmp, uint32_t n)
{
    uint32_t cnt[128], i, b, shift, sum;
    uint64_t top = 0, *src = a, *dst = tmp, *sw;
    for (i = 0; i < n; i++) top |= a[i];
    for (shift = 32u; shift < 64u && (top >> shift) != 0; shift += 7u) {
        memset(cnt, 0, sizeof cnt);
        for (i = 0; i < n; i++) cnt[(src[i] >> shift) & 127u]++;
        for (b = 0, sum = 0; b < 128u; b++) {
            uint32_t c = cnt[b];
            cnt[b] = sum;
            sum += c;
        }
        for (i = 0; i < n; i++) dst[cnt[(src[i] >> shift) & 127u]++] = src[i];
        sw = src;
        src = dst;
        dst = sw;
    }
    if (src != a) memcpy(a, src, (size_t)n * sizeof *a);
}

/* Whether marked edge h (twin tw) is integrated: a boundary edge, or a
 * fold that is no valley (ls_valley_edge), with an end in front of the
 * near plane; its vertices from a to a + e in v0, v1. */
static SIL_INLINE int edge_live(const sctx *sc, uint32_t h, uint32_t tw, uint32_t *v0, uint32_t *v1)
{
    const ls_real *clip = sc->vis->clip;
    const uint32_t *f = sc->indices + 3 * (size_t)(h / 3u);
    uint32_t k = h % 3u;
    if (tw != LS_EDGE_NONE && (!folds(sc, h, tw) || ls_valley_edge(clip, sc->indices, h, tw, sc->cull))) return 0;
    *v0 = f[k];
    *v1 = f[k == 2u ? 0u : k + 1u];
    return clip[4 * (size_t)*v0 + 2] + clip[4 * (size_t)*v0 + 3] >= (ls_real)0 ||
           clip[4 * (size_t)*v1 + 2] + clip[4 * (size_t)*v1 + 3] >= (ls_real)0;
}

/* segment_pass of edge h (twin tw), from its face's corner k = h % 3 to the next. */
static SIL_INLINE void edge_segment(const sctx *sc, uint32_t h, uint32_t tw)
{
    uint32_t t = h / 3u, k = h % 3u, v[4];
    const uint32_t *f = sc->indices + 3 * (size_t)t;
    v[0] = v[3] = f[k];
    v[1] = v[2] = f[k == 2u ? 0u : k + 1u];
    segment_pass(sc, t, tw == LS_EDGE_NONE ? LS_EDGE_NONE : tw / 3u, v,
                 sc->vis->clip + 4 * (size_t)f[k == 0u ? 2u : k - 1u]);
}

/* Window midpoint m of edge h, at its face f's corner k = h % 3 (the hints). */
static SIL_INLINE void edge_mid(const sctx *sc, const uint32_t *f, uint32_t k, ls_real m[2])
{
    const ls_real *a = sc->win + 2 * (size_t)f[k], *b = sc->win + 2 * (size_t)f[k == 2u ? 0u : k + 1u];
    m[0] = (a[0] + b[0]) * (ls_real)0.5;
    m[1] = (a[1] + b[1]) * (ls_real)0.5;
}

/* Cache hints for edge h, SIL_AHEAD edges before segment_pass takes it:
 * its face's corners (clip, normals, depth, walk starts, gradient), the
 * forward's sample under its midpoint (walk_start) and that pixel's image
 * gradient. Inlined (SIL_INLINE): a call that only prefetches counts as
 * pure to GCC, which drops it. */
static SIL_INLINE void fetch_edge(const sctx *sc, uint32_t h)
{
    const uint32_t *f = sc->indices + 3 * (size_t)(h / 3u);
    const ls_vis *vis = sc->vis;
    uint32_t k = h % 3u, q;
    ls_real m[2];
    size_t sample;
    edge_mid(sc, f, k, m);
    sample = sample_under(vis, m[0], m[1]);
    SIL_PREFETCH(vis->tri + sample);
    SIL_PREFETCH(vis->depth + sample);
    SIL_PREFETCH(sc->gimg + 4 * ((size_t)cell_of(m[1], vis->height) * vis->width + cell_of(m[0], vis->width)));
    for (q = 0; q < 3u; q++) {
        SIL_PREFETCH(sc->vis->clip + 4 * (size_t)f[q]);
        if (sc->normals != NULL) SIL_PREFETCH(sc->normals + 3 * (size_t)f[q]);
    }
    for (q = 0; q < 2u; q++) {
        uint32_t v = f[(k + q) % 3u];
        SIL_PREFETCH(sc->gp + 3 * (size_t)v);
        SIL_PREFETCH(sc->zv + v);
        SIL_PREFETCH(sc->wend + v);
    }
}

/* Cache hints for the face the forward drew under edge h's midpoint (the
 * sample fetch_edge fetched): where its walk starts (walk_start). */
static SIL_INLINE void fetch_walk(const sctx *sc, uint32_t h)
{
    const uint32_t *f = sc->indices + 3 * (size_t)(h / 3u);
    ls_real m[2];
    uint32_t id;
    edge_mid(sc, f, h % 3u, m);
    id = sc->vis->tri[sample_under(sc->vis, m[0], m[1])];
    if (id == 0 || id > sc->triangle_count || sc->twin == NULL) return;
    SIL_PREFETCH(sc->indices + 3 * (size_t)(id - 1u));
    SIL_PREFETCH(sc->twin + 3 * (size_t)(id - 1u));
    SIL_PREFETCH(sc->tbox + 4 * (size_t)(id - 1u));
}

/* Cache hint for the row of marked edge h's twin face (fetch_fold reads it). */
static SIL_INLINE void fetch_twin(const sctx *sc, const ls_edge_table *table, uint32_t h)
{
    uint32_t tw = table->twin[h];
    if (tw != LS_EDGE_NONE) SIL_PREFETCH(sc->indices + 3 * (size_t)(tw / 3u));
}

/* Cache hints for marked edge h's fold and valley tests (edge_live) and
 * key: the corners of its faces (the twin's row fetched earlier). */
static SIL_INLINE void fetch_fold(const sctx *sc, const ls_edge_table *table, uint32_t h)
{
    const uint32_t *f = sc->indices + 3 * (size_t)(h / 3u);
    uint32_t tw = table->twin[h], q;
    for (q = 0; q < 3u; q++) {
        SIL_PREFETCH(sc->vis->clip + 4 * (size_t)f[q]);
        SIL_PREFETCH(sc->win + 2 * (size_t)f[q]);
    }
    if (tw != LS_EDGE_NONE) SIL_PREFETCH(sc->vis->clip + 4 * (size_t)far_vertex(sc->indices, tw));
}

/* Every silhouette edge (next_edge's marks, edge_live), integrated in the
 * order of edge_key (the summation order): nearby edges one after the
 * other share their tiles' bins, triangles, walks and pixels while these
 * are in the caches (3-5 % faster than half-edge order on the armadillo at
 * 512^2). The keys go to ord, which holds 2 cap of them (setup_pass's free
 * list: cap keys and sort_keys's copy); more edges than cap (a tangle)
 * are integrated in half-edge order: a choice made by the mesh and view
 * alone, the same on every target. Its own frame (the stack limit on every
 * target). */
LS_NOINLINE static void edges_pass(const sctx *sc, const ls_edge_table *table, const uint64_t *bits, uint64_t *ord,
                                   uint32_t cap)
{
    uint32_t w, n = 0, nm = 0, i, v0, v1;
    uint64_t b;
    /* where there are hints, the marked half-edges first, in order, into ord
     * when they fit (a few per cent of the edges): their tests then read
     * corners fetched ahead, as the edges' own work does (5,694 a view of
     * the armadillo at 512^2, each test reading four scattered rows) */
    for (w = 0; SIL_FETCH && w <= 3 * (size_t)sc->triangle_count / 64u; w++)
        for (b = bits[w]; b != 0; b &= b - 1u, nm++)
            if (nm < cap) ord[nm] = 64u * w + low_bit(b);
    if (SIL_FETCH && nm <= cap) { /* the live ones' keys, in place (n <= i) */
        for (i = 0; i < nm; i++) {
            uint32_t h = (uint32_t)ord[i], tw;
            if (i + 2u * SIL_AHEAD < nm) fetch_twin(sc, table, (uint32_t)ord[i + 2u * SIL_AHEAD]);
            if (i + SIL_AHEAD < nm) fetch_fold(sc, table, (uint32_t)ord[i + SIL_AHEAD]);
            tw = table->twin[h];
            if (edge_live(sc, h, tw, &v0, &v1)) ord[n++] = edge_key(sc, h, v0, v1);
        }
    } else {
        uint32_t pass;
        /* pass 0 lists the keys; pass 1 (only when they do not fit) integrates in half-edge order */
        for (pass = 0; pass < 2u; pass++) {
            for (w = 0; w <= 3 * (size_t)sc->triangle_count / 64u; w++) {
                for (b = bits[w]; b != 0; b &= b - 1u) {
                    uint32_t h = 64u * w + low_bit(b), tw = table->twin[h];
                    if (!edge_live(sc, h, tw, &v0, &v1)) continue;
                    if (pass == 1u) {
                        edge_segment(sc, h, tw);
                    } else {
                        if (n < cap) ord[n] = edge_key(sc, h, v0, v1);
                        n++;
                    }
                }
            }
            if (n <= cap) break;
        }
        if (n > cap) return;
    }
    sort_keys(ord, ord + cap, n);
    for (i = 0; i < n; i++) {
        uint32_t h = (uint32_t)ord[i];
        if (SIL_FETCH && i + SIL_AHEAD < n) fetch_edge(sc, (uint32_t)ord[i + SIL_AHEAD]);
        if (SIL_FETCH && i + SIL_AHEAD / 2u < n) fetch_walk(sc, (uint32_t)ord[i + SIL_AHEAD / 2u]);
        edge_segment(sc, h, table->twin[h]);
    }
}

/* setup_pass's orientations (tri_sign) of the triangles into sign, each
 * triangle's tbox entry unbinned (x0 > x1) until box_keep boxes it and,
 * on the guess that the culled faces are those certain of sign -2
 * (choose_cull's cull = -1: a closed mesh wound counterclockwise, seen
 * from outside), the others listed in keep, their number returned
 * (setup_pass lists them again when the guess fails). allfront:
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

/* The pass's per-view set-up, after sctx_init: window positions and
 * depths, orientations, culling, tiles, the contour marks (bits), boxes,
 * bins and the candidate slots, all in scratch. Out of line: its locals
 * stay out of the frame that the deep chain below edges_pass adds to (the
 * MCU's 4 KiB job stack). */
LS_NOINLINE static ls_status setup_pass(sctx *out, const ls_edge_table *table, uint32_t vertex_count,
                                        uint64_t **bitsp, uint64_t **ordp, ls_arena *arena)
{
    /* a copy of its own: the compiler keeps a local context's fields in
     * registers across the byte stores of the orientations, which may
     * alias anything reached through a pointer (0.3M instructions a view) */
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
    choose_tiles(sc, choose_cull(sc, table, sign));
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

ls_status ls_silhouette_backward(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                 uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                 const ls_shade_opts *opts, const ls_real mvp[16], ls_real boost,
                                 const ls_real *grad_image, ls_real *grad_positions, ls_arena *arena,
                                 ls_diag *diag)
{
    ls_diag_clear(diag);
    sctx sc;
    uint32_t t, counts[2];
    ls_arena_mark mark;
    uint64_t *bits = NULL, *ord = NULL;
    ls_status st;
    if (mvp == NULL || grad_image == NULL || grad_positions == NULL || arena == NULL) return LS_ERR_INVALID;
    counts[0] = triangle_count;
    counts[1] = vertex_count;
    st = check_args(vis, table, indices, normals, opts, counts, diag);
    if (st != LS_OK) return st;
    sctx_init(&sc, vis, indices, triangle_count);
    sc.normals = normals;
    sc.o = opts;
    sc.m = mvp;
    sc.gimg = grad_image;
    sc.flat = opts->mode == LS_SHADE_MASK;
    sc.boost = boost;
    sc.gp = grad_positions;
    sh_quad_init(&sc);
#if LS_REAL_IS_FLOAT
    sc.qtol = 1e-4f;
#else
    sc.qtol = 1e-9;
#endif
    mark = ls_arena_save(arena);
    st = setup_pass(&sc, table, vertex_count, &bits, &ord, arena);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    edges_pass(&sc, table, bits, ord, triangle_count / 4u);
    for (t = 0; sc.behind > 0 && t < triangle_count; t++) cut_pass(&sc, t);
    ls_arena_restore(arena, mark);
    return LS_OK;
}

/* ---- the pair mode (nvdiffrast-style antialiasing, deterministic) ---- */

typedef struct pctx {
    const ls_vis *vis;
    const ls_edge_table *table;
    const uint32_t *indices;
    uint32_t triangle_count;
} pctx;

/* One pair of neighbouring pixels p0 -> p1 (right or down) whose triangle
 * ids differ: the silhouette edge of the owner crossing the segment between
 * their centres, at c (pixel units from the owner's centre, towards the
 * neighbour when ds = 1). */
typedef struct pitem {
    size_t p0, p1, q;
    uint32_t va, vb;    /* the edge's vertices */
    ls_real x1, y1, x2, y2, c, ds, alpha; /* frame: owner's centre, x along the pair */
    int vertical, clamped;
} pitem;

static int pair_item(const pctx *pc, size_t p0, size_t p1, int vertical, pitem *it)
{
    const ls_vis *vis = pc->vis;
    uint32_t id0 = vis->tri[p0], id1 = vis->tri[p1], own, k, best = 3u;
    size_t po;
    ls_real x[3], y[3], cx, cy, bc = (ls_real)0, dc, hw = (ls_real)vis->width * (ls_real)0.5;
    ls_real hh = (ls_real)vis->height * (ls_real)0.5;
    const uint32_t *f;
    if (id0 == id1) return 0;
    if (id0 > pc->triangle_count || id1 > pc->triangle_count) return 0;
    if (id0 == 0 || (id1 != 0 && vis->depth[p1] < vis->depth[p0])) {
        own = id1 - 1u;
        po = p1;
        it->ds = (ls_real)-1;
    } else {
        own = id0 - 1u;
        po = p0;
        it->ds = (ls_real)1;
    }
    f = pc->indices + 3 * (size_t)own;
    {
        size_t row = po / vis->width; /* the pixel's row and column */
        cx = (ls_real)(po - row * vis->width) + (ls_real)0.5;
        cy = (ls_real)row + (ls_real)0.5;
    }
    for (k = 0; k < 3; k++) {
        const ls_real *cl = vis->clip + 4 * (size_t)f[k];
        ls_real wx, wy;
        if (!(cl[2] + cl[3] >= (ls_real)0) || !(cl[3] > (ls_real)0)) return 0; /* near-clipped: skipped */
        wx = (cl[0] / cl[3] + (ls_real)1) * hw - cx;
        wy = ((ls_real)1 - cl[1] / cl[3]) * hh - cy;
        x[k] = vertical ? wy : wx;
        y[k] = vertical ? wx : wy;
    }
    for (k = 0; k < 3; k++) { /* the crossing farthest towards the neighbour */
        uint32_t k1 = (k + 1u) % 3u;
        ls_real d = y[k1] - y[k], cc;
        if ((y[k] >= (ls_real)0) == (y[k1] >= (ls_real)0) || d == (ls_real)0) continue;
        cc = (x[k] * y[k1] - x[k1] * y[k]) / d;
        if (best == 3u || it->ds * cc > it->ds * bc) {
            best = k;
            bc = cc;
        }
    }
    if (best == 3u) return 0;
    {
        uint32_t k1 = (best + 1u) % 3u, h = 3u * own + best, tw = pc->table->twin[h];
        ls_real dx = x[k1] - x[best], dy = y[k1] - y[best];
        const ls_real *A = vis->clip + 4 * (size_t)f[best], *B = vis->clip + 4 * (size_t)f[k1];
        if (r_abs(dy) < r_abs(dx)) return 0; /* flatter than 45 degrees to the pair */
        if (tw != LS_EDGE_NONE) {             /* the neighbour face folds behind: a silhouette */
            const uint32_t *g = pc->indices + 3 * (size_t)(tw / 3u);
            ls_real sc_ = hdet(A, B, vis->clip + 4 * (size_t)f[(best + 2u) % 3u]);
            ls_real sd_ = hdet(A, B, vis->clip + 4 * (size_t)g[(tw % 3u + 2u) % 3u]);
            if (!((sc_ > (ls_real)0 && sd_ > (ls_real)0) || (sc_ < (ls_real)0 && sd_ < (ls_real)0))) return 0;
        }
        it->va = f[best];
        it->vb = f[k1];
        it->x1 = x[best];
        it->y1 = y[best];
        it->x2 = x[k1];
        it->y2 = y[k1];
    }
    dc = it->ds * bc;
    if (!(dc > (ls_real)-0.0625 && dc < (ls_real)1.0625)) return 0;
    it->clamped = dc < (ls_real)0 || dc > (ls_real)1;
    dc = dc < (ls_real)0 ? (ls_real)0 : (dc > (ls_real)1 ? (ls_real)1 : dc);
    it->c = bc;
    it->alpha = it->ds * ((ls_real)0.5 - dc);
    it->p0 = p0;
    it->p1 = p1;
    it->vertical = vertical;
    return 1;
}

/* The next blending pair from cursor *k (2 pixel + direction, image
 * order); 0 when there is none left. it->q is the pixel it modifies. */
static int pair_next(const pctx *pc, size_t *k, pitem *it)
{
    const ls_vis *vis = pc->vis;
    size_t n = 2 * (size_t)vis->width * vis->height;
    if (vis->width == 0) return 0;
    while (*k < n) {
        size_t p0 = *k >> 1, row = p0 / vis->width, col = p0 - row * vis->width;
        int dir = (int)(*k & 1u);
        (*k)++;
        if (dir == 0 ? col + 1u >= vis->width : row + 1u >= vis->height) continue;
        if (pair_item(pc, p0, dir == 0 ? p0 + 1u : p0 + vis->width, dir, it)) {
            it->q = it->alpha > (ls_real)0 ? it->p0 : it->p1;
            return 1;
        }
    }
    return 0;
}

static ls_status pair_check(pctx *pc, const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                            uint32_t triangle_count, ls_diag *diag)
{
    if (vis == NULL || table == NULL || (triangle_count > 0 && indices == NULL)) return LS_ERR_INVALID;
    if (vis->tri == NULL || vis->clip == NULL || table->magic != EDGE_TABLE_MAGIC) return LS_ERR_STATE;
    if (vis->ss != 1u || vis->triangle_count != triangle_count || table->triangle_count != triangle_count ||
        table->vertex_count != vis->vertex_count)
        return LS_ERR_INVALID;
    pc->vis = vis;
    pc->table = table;
    pc->indices = indices;
    pc->triangle_count = triangle_count;
    return ls_check_triangle_indices(indices, triangle_count, vis->vertex_count, diag);
}

ls_status ls_pair_forward(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                          uint32_t triangle_count, const ls_real *image_in, ls_real *image_out, ls_diag *diag)
{
    ls_diag_clear(diag);
    pctx pc;
    size_t n, p, k = 0;
    pitem it;
    ls_status st = pair_check(&pc, vis, table, indices, triangle_count, diag);
    if (st != LS_OK) return st;
    if (image_in == NULL || image_out == NULL || image_in == image_out) return LS_ERR_INVALID;
    n = 4 * (size_t)vis->width * vis->height;
    for (p = 0; p < n; p++) image_out[p] = image_in[p];
    while (pair_next(&pc, &k, &it)) {
        int c;
        for (c = 0; c < 4; c++)
            image_out[4 * it.q + (size_t)c] += it.alpha * (image_in[4 * it.p1 + (size_t)c] - image_in[4 * it.p0 + (size_t)c]);
    }
    return LS_OK;
}

ls_status ls_pair_backward(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                           uint32_t triangle_count, const ls_real mvp[16], ls_real boost, const ls_real *image_in,
                           const ls_real *grad_out, ls_real *grad_in, ls_real *grad_positions, ls_diag *diag)
{
    ls_diag_clear(diag);
    pctx pc;
    sctx sc;
    size_t k = 0;
    pitem it;
    ls_status st = pair_check(&pc, vis, table, indices, triangle_count, diag);
    if (st != LS_OK) return st;
    if (mvp == NULL || image_in == NULL || grad_out == NULL || grad_positions == NULL || grad_in == grad_out)
        return LS_ERR_INVALID;
    sctx_init(&sc, vis, indices, triangle_count);
    sc.m = mvp;
    if (grad_in != NULL) {
        size_t p, n = 4 * (size_t)vis->width * vis->height;
        for (p = 0; p < n; p++) grad_in[p] += grad_out[p];
    }
    while (pair_next(&pc, &k, &it)) {
        ls_real dd = (ls_real)0, gc, gx1, gy1, gx2, gy2, D, g4[4];
        int c;
        for (c = 0; c < 4; c++) {
            ls_real g = grad_out[4 * it.q + (size_t)c];
            dd += g * (image_in[4 * it.p1 + (size_t)c] - image_in[4 * it.p0 + (size_t)c]);
            if (grad_in != NULL) {
                grad_in[4 * it.p0 + (size_t)c] -= it.alpha * g;
                grad_in[4 * it.p1 + (size_t)c] += it.alpha * g;
            }
        }
        if (it.clamped) continue;
        /* alpha = ds / 2 - c: dL/dc = -dd; c = (x1 y2 - x2 y1) / (y2 - y1) */
        gc = -dd * boost;
        D = it.y2 - it.y1;
        gx1 = gc * it.y2 / D;
        gx2 = -(gc * it.y1 / D);
        gy1 = gc * (it.c - it.x2) / D;
        gy2 = gc * (it.x1 - it.c) / D;
        window_to_clip(&sc, vis->clip + 4 * (size_t)it.va, it.vertical ? gy1 : gx1, it.vertical ? gx1 : gy1, g4);
        clip_to_positions(&sc, it.va, g4, grad_positions);
        window_to_clip(&sc, vis->clip + 4 * (size_t)it.vb, it.vertical ? gy2 : gx2, it.vertical ? gx2 : gy2, g4);
        clip_to_positions(&sc, it.vb, g4, grad_positions);
    }
    return LS_OK;
}
