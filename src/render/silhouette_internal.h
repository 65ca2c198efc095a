/* silhouette_internal.h - the silhouette pass's shared state: what its
 * stages (silhouette_*.c) pass each other, the helpers they share, and every
 * fast-path switch of the pass (SIL_SPECIALIZE, SIL_FETCH, SIL_UNROLL,
 * SIL_SSE, SIL_SSE2), all on LS_FAST_PATHS (render_internal.h). Private to
 * src/render; the public API is largesteps/silhouette.h. */
#ifndef LS_SILHOUETTE_INTERNAL_H
#define LS_SILHOUETTE_INTERNAL_H
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

/* ---- the silhouette pass ---- */

/* The pass's fast paths, each on LS_FAST_PATHS (off at -Os and on the MCU)
 * and each given up alone by a bit of LS_SIL_OFF (1 specialization, 2 cache
 * hints, 4 unrolling, 8 SSE, 16 SSE2: how docs/fast-paths.md measures what
 * each pays). None changes a result: the plain path gives the same bits. */
#ifndef LS_SIL_OFF
#define LS_SIL_OFF 0
#endif
#define SIL_ON(bit) (LS_FAST_PATHS && !(LS_SIL_OFF & (bit)))

#define SIL_TILE_LOG2 1u                        /* candidate bins: tiles of at least 2 x 2 pixels (ls_sil_choose_tiles) */
#define SIL_MARGIN ((ls_real)1 / (ls_real)64)  /* pixels by which bin and candidate boxes grow */
/* Inlined where called, so that a copy sees a constant corner count and
 * its loops unroll (GCC wants the pragma; clang unrolls them unasked); not
 * where code size counts (LS_FAST_PATHS off: -Os, the MCU), which keeps one copy. */
#if (defined(__GNUC__) || defined(__clang__)) && SIL_ON(1)
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
#if (defined(__GNUC__) || defined(__clang__)) && SIL_ON(2)
#define SIL_FETCH 1
#define SIL_PREFETCH(p) __builtin_prefetch(p)
#else
#define SIL_FETCH 0
#define SIL_PREFETCH(p) ((void)(p))
#endif
#define SIL_AHEAD 8u /* edges_pass: fetch_edge this many edges ahead, fetch_walk half as many */
#if defined(__GNUC__) && !defined(__clang__) && SIL_ON(4)
#define SIL_UNROLL _Pragma("GCC unroll 4")
#else
#define SIL_UNROLL
#endif
#define SIL_LOOSE ((ls_real)1 / (ls_real)16384) /* px^2: a view bound c0v above it widens intervals (cand_interval) */
#define SIL_DEPTH_CAP 4                         /* adaptive quadrature: at most 2^4 parts per sub-piece */
/* ls_sil_run_pass's gather tests a box against the run's in one packed comparison
 * where SSE is there (x86; a fast path: the scalar test gives the same hits) */
#if SIL_ON(8) && (defined(__SSE__) || defined(_M_X64))
#include <xmmintrin.h>
#define SIL_SSE 1
#else
#define SIL_SSE 0
#endif
/* SSE2 (x86-64, a fast path): fbox_tiles converts a box's four coordinates
 * in one, and ls_sil_run_pass tests a hit's corners against the end vertices in one */
#if SIL_ON(16) && (defined(__SSE2__) || defined(_M_X64))
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
    uint32_t tl;         /* tiles of 2^tl x 2^tl pixels (ls_sil_choose_tiles) */
    float tside_inv;     /* 2^-tl (tile_of) */
    const signed char *sign; /* [T] orientation of each triangle (tri_sign), or NULL */
    const uint32_t *twin; /* the edge table's twins (walks across edges), or NULL */
    int allfront;        /* 1: every vertex is in front (vfront) */
    int cull;            /* +1 / -1: triangles of that orientation (hdet sign) are never seen; 0: keep all */
    ls_real width, height, qtol, boost;
    ls_real *gp;         /* [3 V] the gradient being added to */
    struct spiece *piece; /* the sub-piece being integrated: scratch, not integrate's frame (the MCU's stack) */
    ls_real wk;          /* 3 max(|x| + |y|) + width + height over the window positions (tri_sign_front) */
    int shq;             /* 1: SH shading as a quadratic form (ls_sil_sh_quad_init), else ls_shade_point */
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

/* A run of the segment through one bin tile: its pieces, one per pixel,
 * [t[i], t[i + 1]] in pixel pix[i]. */
#define SIL_RUN_CAP 8
typedef struct srun {
    ls_real t[SIL_RUN_CAP + 1];
    size_t pix[SIL_RUN_CAP];
    size_t tile;
    int n;
} srun;

/* |x| by clearing the sign bit, with no branch (the margins and bounds take
 * many; -0 and +0 are the same to them). Not LS_RFABS: that is an out-of-line
 * call in these loops (docs/fast-paths.md). */
static inline ls_real r_abs(ls_real x)
{
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
}

/* The point of triangle f on the ray through window (xw, yw): barycentrics
 * b and NDC depth; returns 0 when the triangle is edge-on there or the point
 * is behind the eye. */
static inline int tri_point(const sctx *sc, const uint32_t *f, ls_real xw, ls_real yw, ls_real b[3], ls_real *depth)
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
static inline void window_of(const sctx *sc, const ls_real *cl, ls_real w[2])
{
    w[0] = (cl[0] / cl[3] + (ls_real)1) * sc->width * (ls_real)0.5;
    w[1] = ((ls_real)1 - cl[1] / cl[3]) * sc->height * (ls_real)0.5;
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

/* Homogeneous orientation det[A; B; C] over (X, Y, W): for A and B in
 * front of the eye its sign says on which side of the screen line A B the
 * face through C lies near the edge, wherever C is (even behind the eye). */
static inline ls_real hdet(const ls_real *a, const ls_real *b, const ls_real *c)
{
    return (a[0] * (b[1] * c[3] - b[3] * c[1]) - a[1] * (b[0] * c[3] - b[3] * c[0])) +
           a[3] * (b[0] * c[1] - b[1] * c[0]);
}

/* silhouette.c: tri_poly of a triangle cut by the near plane (out of line). */
int ls_sil_tri_poly_cut(const sctx *sc, const uint32_t *f, ls_real x[4], ls_real y[4]);

static inline int tri_poly(const sctx *sc, const uint32_t *f, ls_real x[4], ls_real y[4])
{
    if (sc->vfront == NULL || (sc->vfront[f[0]] & sc->vfront[f[1]] & sc->vfront[f[2]]) == 0)
        return ls_sil_tri_poly_cut(sc, f, x, y);
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

/* floor(c) clamped to [0, n - 1] (0 for NaN); n < 2^24. */
static inline uint32_t cell_of(ls_real c, uint32_t n)
{
    if (!(c >= (ls_real)1)) return 0;
    if (c >= (ls_real)n) return n - 1u;
    return (uint32_t)c; /* in [1, n): the cast truncates, as floor */
}

/* The forward's sample under window point (x, y) (walk_start, the hints). */
static SIL_INLINE size_t sample_under(const ls_vis *vis, ls_real x, ls_real y)
{
    ls_real ss = (ls_real)vis->ss;
    return (size_t)cell_of(y * ss, vis->sh) * vis->sw + cell_of(x * ss, vis->sw);
}

/* The index of the lowest set bit of m != 0: a de Bruijn multiply (C99 has no builtin). */
static inline uint32_t low_bit(uint64_t m)
{
    static const unsigned char idx[64] = {0,  1,  48, 2,  57, 49, 28, 3,  61, 58, 50, 42, 38, 29, 17, 4,
                                          62, 55, 59, 36, 53, 51, 43, 22, 45, 39, 33, 30, 24, 18, 12, 5,
                                          63, 47, 56, 27, 60, 41, 37, 16, 54, 35, 52, 21, 44, 32, 23, 11,
                                          46, 26, 40, 15, 34, 20, 31, 10, 25, 14, 19, 9,  13, 8,  7,  6};
    return idx[((m & ((uint64_t)0 - m)) * 0x03f79d71b4cb0a89ull) >> 58];
}

/* Candidate slots of a view: a piece's candidates come from one tile's bin,
 * at most one entry per binned triangle (at least one slot). */
static inline size_t slot_count(size_t binned, size_t entries)
{
    size_t n = binned < entries ? binned : entries;
    return n > 0 ? n : 1u;
}

/* ---- the stages (each file's entry points, in the order the pass calls them) ---- */

/* silhouette_setup.c */
void ls_sil_box_pass(const sctx *sc, size_t count[2], int *over);
uint64_t ls_sil_choose_cull(sctx *sc, const ls_edge_table *table, const signed char *sign);
void ls_sil_choose_tiles(sctx *sc, uint64_t cov);
ls_status ls_sil_setup_pass(sctx *out, const ls_edge_table *table, uint32_t vertex_count,
                                        uint64_t **bitsp, uint64_t **ordp, ls_arena *arena);

/* silhouette_quadrature.c */
void ls_sil_sh_quad_init(sctx *sc);
void ls_sil_integrate(const sctx *sc, sedge *ed, ls_real lo, ls_real hi, uint32_t beh, size_t p);

/* silhouette_visibility.c */
int ls_sil_visibility(const sctx *sc, const sedge *ed, ls_real t, uint32_t *nact, uint32_t *beh);
void ls_sil_run_pass(const sctx *sc, sedge *ed, const srun *run);

/* silhouette_walk.c */
int ls_sil_walk_segment(const sctx *sc, sedge *ed);
int ls_sil_run_hidden(const sctx *sc, sedge *ed, srun *run);
int ls_sil_end_face_misses(const sctx *sc, const sedge *ed, const uint32_t *g);

/* silhouette.c */
void ls_sil_window_to_clip(const sctx *sc, const ls_real *cl, ls_real gx, ls_real gy, ls_real g[4]);
void ls_sil_clip_to_positions(const sctx *sc, uint32_t v, const ls_real g[4], ls_real *gp);
void ls_sil_sctx_init(sctx *sc, const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count);

#endif
