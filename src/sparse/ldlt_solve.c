/* ldlt_solve.c - solves with an LDL^T factor for k interleaved right-hand
 * sides (n x k row-major), and iterative refinement. The permuted right-hand
 * sides are worked on as ls_acc (double unless SUMS=real, ldlt.h): each
 * entry of L is widened once per use, every sum rounds once at the end. */
#include <largesteps/ldlt.h>
#include <string.h>
#include "ldlt_internal.h"

static int all_finite(const ls_real *x, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++) {
        ls_real d = x[i] - x[i];
        if (!(d == 0)) return 0;
    }
    return 1;
}

/* Columns are processed in chunks of up to CHUNK consecutive columns that form
 * a chain in the elimination tree with nested patterns (column c's rows are
 * c+1 followed by column c+1's rows): then the rows below the chunk (R) are
 * shared, and each w_i of R is loaded and stored once per chunk instead of
 * once per column. The forward pass performs exactly the operations of the
 * column-by-column algorithm in the same order (same bits); the backward pass
 * subtracts the R terms of a chunk before its in-chunk terms (a fixed order).
 * Every k uses the same order per right-hand side, so k = 3 equals three
 * k = 1 solves bit for bit. */
#define CHUNK 4u

/* 1 when column c+1 continues column c's chain (c + 1 < n). */
static inline int chained(const uint32_t *lp, const uint32_t *li, uint32_t c)
{
    uint32_t cnt = lp[c + 1u] - lp[c];
    return cnt > 0 && li[lp[c]] == c + 1u && cnt == lp[c + 2u] - lp[c + 1u] + 1u;
}

/* R rows of a chunk of width 1, 2 or 4 (written out so that the chunk's values
 * stay in registers): forward subtracts the chunk's final values from each w_i
 * in column order; backward subtracts l_ic w_i from each column's accumulator
 * in row order. */
static void fwd_rows1(uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *wc, ls_acc *w)
{
    uint32_t t;
    const ls_real *p0 = pc[0];
    const ls_acc v00 = wc[0], v01 = wc[1], v02 = wc[2];
    for (t = 0; t < r; t++) {
        ls_acc *wi = w + 3u * (size_t)ri[t];
        ls_acc x0 = wi[0], x1 = wi[1], x2 = wi[2];
        x0 -= (ls_acc)p0[t] * v00;
        x1 -= (ls_acc)p0[t] * v01;
        x2 -= (ls_acc)p0[t] * v02;
        wi[0] = x0;
        wi[1] = x1;
        wi[2] = x2;
    }
}

static void fwd_rows2(uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *wc, ls_acc *w)
{
    uint32_t t;
    const ls_real *p0 = pc[0];
    const ls_acc v00 = wc[0], v01 = wc[1], v02 = wc[2];
    const ls_real *p1 = pc[1];
    const ls_acc v10 = wc[3], v11 = wc[4], v12 = wc[5];
    for (t = 0; t < r; t++) {
        ls_acc *wi = w + 3u * (size_t)ri[t];
        ls_acc x0 = wi[0], x1 = wi[1], x2 = wi[2];
        x0 -= (ls_acc)p0[t] * v00;
        x1 -= (ls_acc)p0[t] * v01;
        x2 -= (ls_acc)p0[t] * v02;
        x0 -= (ls_acc)p1[t] * v10;
        x1 -= (ls_acc)p1[t] * v11;
        x2 -= (ls_acc)p1[t] * v12;
        wi[0] = x0;
        wi[1] = x1;
        wi[2] = x2;
    }
}

static void fwd_rows4(uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *wc, ls_acc *w)
{
    uint32_t t;
    const ls_real *p0 = pc[0];
    const ls_acc v00 = wc[0], v01 = wc[1], v02 = wc[2];
    const ls_real *p1 = pc[1];
    const ls_acc v10 = wc[3], v11 = wc[4], v12 = wc[5];
    const ls_real *p2 = pc[2];
    const ls_acc v20 = wc[6], v21 = wc[7], v22 = wc[8];
    const ls_real *p3 = pc[3];
    const ls_acc v30 = wc[9], v31 = wc[10], v32 = wc[11];
    for (t = 0; t < r; t++) {
        ls_acc *wi = w + 3u * (size_t)ri[t];
        ls_acc x0 = wi[0], x1 = wi[1], x2 = wi[2];
        x0 -= (ls_acc)p0[t] * v00;
        x1 -= (ls_acc)p0[t] * v01;
        x2 -= (ls_acc)p0[t] * v02;
        x0 -= (ls_acc)p1[t] * v10;
        x1 -= (ls_acc)p1[t] * v11;
        x2 -= (ls_acc)p1[t] * v12;
        x0 -= (ls_acc)p2[t] * v20;
        x1 -= (ls_acc)p2[t] * v21;
        x2 -= (ls_acc)p2[t] * v22;
        x0 -= (ls_acc)p3[t] * v30;
        x1 -= (ls_acc)p3[t] * v31;
        x2 -= (ls_acc)p3[t] * v32;
        wi[0] = x0;
        wi[1] = x1;
        wi[2] = x2;
    }
}

static void back_rows1(uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *w, ls_acc *acc)
{
    uint32_t t;
    const ls_real *p0 = pc[0];
    ls_acc a00 = acc[0], a01 = acc[1], a02 = acc[2];
    for (t = 0; t < r; t++) {
        const ls_acc *wi = w + 3u * (size_t)ri[t];
        const ls_acc x0 = wi[0], x1 = wi[1], x2 = wi[2];
        a00 -= (ls_acc)p0[t] * x0;
        a01 -= (ls_acc)p0[t] * x1;
        a02 -= (ls_acc)p0[t] * x2;
    }
    acc[0] = a00;
    acc[1] = a01;
    acc[2] = a02;
}

static void back_rows2(uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *w, ls_acc *acc)
{
    uint32_t t;
    const ls_real *p0 = pc[0];
    ls_acc a00 = acc[0], a01 = acc[1], a02 = acc[2];
    const ls_real *p1 = pc[1];
    ls_acc a10 = acc[3], a11 = acc[4], a12 = acc[5];
    for (t = 0; t < r; t++) {
        const ls_acc *wi = w + 3u * (size_t)ri[t];
        const ls_acc x0 = wi[0], x1 = wi[1], x2 = wi[2];
        a00 -= (ls_acc)p0[t] * x0;
        a01 -= (ls_acc)p0[t] * x1;
        a02 -= (ls_acc)p0[t] * x2;
        a10 -= (ls_acc)p1[t] * x0;
        a11 -= (ls_acc)p1[t] * x1;
        a12 -= (ls_acc)p1[t] * x2;
    }
    acc[0] = a00;
    acc[1] = a01;
    acc[2] = a02;
    acc[3] = a10;
    acc[4] = a11;
    acc[5] = a12;
}

static void back_rows4(uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *w, ls_acc *acc)
{
    uint32_t t;
    const ls_real *p0 = pc[0];
    ls_acc a00 = acc[0], a01 = acc[1], a02 = acc[2];
    const ls_real *p1 = pc[1];
    ls_acc a10 = acc[3], a11 = acc[4], a12 = acc[5];
    const ls_real *p2 = pc[2];
    ls_acc a20 = acc[6], a21 = acc[7], a22 = acc[8];
    const ls_real *p3 = pc[3];
    ls_acc a30 = acc[9], a31 = acc[10], a32 = acc[11];
    for (t = 0; t < r; t++) {
        const ls_acc *wi = w + 3u * (size_t)ri[t];
        const ls_acc x0 = wi[0], x1 = wi[1], x2 = wi[2];
        a00 -= (ls_acc)p0[t] * x0;
        a01 -= (ls_acc)p0[t] * x1;
        a02 -= (ls_acc)p0[t] * x2;
        a10 -= (ls_acc)p1[t] * x0;
        a11 -= (ls_acc)p1[t] * x1;
        a12 -= (ls_acc)p1[t] * x2;
        a20 -= (ls_acc)p2[t] * x0;
        a21 -= (ls_acc)p2[t] * x1;
        a22 -= (ls_acc)p2[t] * x2;
        a30 -= (ls_acc)p3[t] * x0;
        a31 -= (ls_acc)p3[t] * x1;
        a32 -= (ls_acc)p3[t] * x2;
    }
    acc[0] = a00;
    acc[1] = a01;
    acc[2] = a02;
    acc[3] = a10;
    acc[4] = a11;
    acc[5] = a12;
    acc[6] = a20;
    acc[7] = a21;
    acc[8] = a22;
    acc[9] = a30;
    acc[10] = a31;
    acc[11] = a32;
}

/* Subtracts the final values wc of m = 1, 2 or 4 chained columns (pc:
 * their entries in rows ri[0 .. r)) from those rows of w, columns in order. */
void ls_ldlt_fwd_rows3(uint32_t m, uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *wc,
                       ls_acc *w)
{
    if (m == 1) fwd_rows1(r, ri, pc, wc, w);
    else if (m == 2) fwd_rows2(r, ri, pc, wc, w);
    else fwd_rows4(r, ri, pc, wc, w);
}

/* The width of the chunk of chained columns that starts at s, at most up
 * to hi: 1, 2 or 4. */
uint32_t ls_ldlt_fwd_chunk_width(const ls_ldlt *f, uint32_t s, uint32_t hi)
{
    uint32_t e;
    for (e = s + 1u; e < hi && e - s < CHUNK && chained(f->lp, f->li, e - 1u); e++) {
    }
    return e - s == 3u ? 2u : e - s; /* widths 1, 2, 4 */
}

/* forward (L) and diagonal (1/D), chunked, k = 3, over columns [lo, hi):
 * rows >= limit are not updated and a column with such rows is not scaled
 * (ls_ldlt_fwd3_range in ldlt_internal.h; the whole solve: 0, n, n) */
void ls_ldlt_fwd3_range(const ls_ldlt *f, ls_acc *w, uint32_t lo, uint32_t hi, uint32_t limit)
{
    uint32_t s = lo, c, c2;
    const uint32_t *lp = f->lp, *li = f->li;
    const ls_real *lx = f->lx, *dinv = f->dinv;
    while (s < hi) {
        const ls_real *pc[CHUNK];
        const uint32_t m = ls_ldlt_fwd_chunk_width(f, s, hi), e = s + m;
        uint32_t r;
        const uint32_t *ri;
        for (c = s; c < e; c++) {
            const ls_real *lc = lx + lp[c];
            pc[c - s] = lc + (e - 1u - c);
            for (c2 = c + 1u; c2 < e; c2++) {
                const ls_acc l = (ls_acc)lc[c2 - c - 1u];
                w[3u * (size_t)c2] -= l * w[3u * (size_t)c];
                w[3u * (size_t)c2 + 1u] -= l * w[3u * (size_t)c + 1u];
                w[3u * (size_t)c2 + 2u] -= l * w[3u * (size_t)c + 2u];
            }
        }
        r = lp[e] - lp[e - 1u];
        ri = li + lp[e - 1u];
        while (r > 0 && ri[r - 1u] >= limit) r--; /* rows ascend: the held ones are a suffix */
        ls_ldlt_fwd_rows3(m, r, ri, pc, w + 3u * (size_t)s, w);
        if (r == lp[e] - lp[e - 1u]) { /* no held rows in the chunk's columns (they share e-1's) */
            for (c = s; c < e; c++) {
                const ls_acc di = (ls_acc)dinv[c];
                w[3u * (size_t)c] *= di;
                w[3u * (size_t)c + 1u] *= di;
                w[3u * (size_t)c + 2u] *= di;
            }
        }
        s = e;
    }
}

/* The start of the backward chunk that ends at e (> lo), no lower than lo. */
uint32_t ls_ldlt_back_chunk_start(const ls_ldlt *f, uint32_t lo, uint32_t e)
{
    uint32_t s;
    for (s = e - 1u; s > lo && e - s < CHUNK && chained(f->lp, f->li, s - 1u); s--) {
    }
    if (e - s == 3u) s++; /* widths 1, 2, 4 */
    return s;
}

/* backward (L^T), chunked from column hi - 1 down to lo, k = 3 */
void ls_ldlt_bwd3_range(const ls_ldlt *f, ls_acc *w, uint32_t lo, uint32_t hi)
{
    const uint32_t *lp = f->lp, *li = f->li;
    const ls_real *lx = f->lx;
    uint32_t e = hi;
    while (e > lo) {
        const uint32_t s = ls_ldlt_back_chunk_start(f, lo, e), m = e - s;
        const uint32_t r = lp[e] - lp[e - 1u];
        const uint32_t *ri = li + lp[e - 1u];
        const ls_real *pc[CHUNK];
        ls_acc acc[3u * CHUNK];
        uint32_t c;
        for (c = s; c < e; c++) pc[c - s] = lx + lp[c] + (e - 1u - c);
        memcpy(acc, w + 3u * (size_t)s, 3u * (size_t)m * sizeof(ls_acc));
        if (m == 1) back_rows1(r, ri, pc, w, acc);
        else if (m == 2) back_rows2(r, ri, pc, w, acc);
        else back_rows4(r, ri, pc, w, acc);
        for (c = e; c > s; c--) {
            const uint32_t cc = c - 1u;
            const ls_real *lc = lx + lp[cc];
            ls_acc *a = acc + 3u * (size_t)(cc - s);
            uint32_t c2;
            for (c2 = cc + 1u; c2 < e; c2++) {
                const ls_acc l = (ls_acc)lc[c2 - cc - 1u];
                a[0] -= l * w[3u * (size_t)c2];
                a[1] -= l * w[3u * (size_t)c2 + 1u];
                a[2] -= l * w[3u * (size_t)c2 + 2u];
            }
            w[3u * (size_t)cc] = a[0];
            w[3u * (size_t)cc + 1u] = a[1];
            w[3u * (size_t)cc + 2u] = a[2];
        }
        e = s;
    }
}

/* The same two passes for any k (the same operations per right-hand side). */
static void forwardk(const ls_ldlt *f, uint32_t k, ls_acc *w)
{
    uint32_t n = f->n, s = 0, e, c, c2, t, q;
    const uint32_t *lp = f->lp, *li = f->li;
    const ls_real *lx = f->lx, *dinv = f->dinv;
    while (s < n) {
        uint32_t m, r;
        const uint32_t *ri;
        for (e = s + 1u; e < n && e - s < CHUNK && chained(lp, li, e - 1u); e++) {
        }
        if (e - s == 3u) e--; /* widths 1, 2, 4 */
        m = e - s;
        for (c = s; c < e; c++) {
            const ls_real *lc = lx + lp[c];
            for (c2 = c + 1u; c2 < e; c2++) {
                const ls_acc l = (ls_acc)lc[c2 - c - 1u];
                for (q = 0; q < k; q++) w[(size_t)c2 * k + q] -= l * w[(size_t)c * k + q];
            }
        }
        r = lp[e] - lp[e - 1u];
        ri = li + lp[e - 1u];
        for (t = 0; t < r; t++) {
            ls_acc *wi = w + (size_t)ri[t] * k;
            for (c = 0; c < m; c++) {
                const ls_acc l = (ls_acc)lx[lp[s + c] + (e - 1u - (s + c)) + t];
                const ls_acc *wc = w + (size_t)(s + c) * k;
                for (q = 0; q < k; q++) wi[q] -= l * wc[q];
            }
        }
        for (c = s; c < e; c++)
            for (q = 0; q < k; q++) w[(size_t)c * k + q] *= (ls_acc)dinv[c];
        s = e;
    }
}

static void backwardk(const ls_ldlt *f, uint32_t k, ls_acc *w)
{
    uint32_t n = f->n, e = n, c, c2, t, q;
    const uint32_t *lp = f->lp, *li = f->li;
    const ls_real *lx = f->lx;
    while (e > 0) {
        const uint32_t s = ls_ldlt_back_chunk_start(f, 0, e), m = e - s;
        uint32_t r;
        const uint32_t *ri;
        r = lp[e] - lp[e - 1u];
        ri = li + lp[e - 1u];
        for (t = 0; t < r; t++) {
            const ls_acc *wi = w + (size_t)ri[t] * k;
            for (c = 0; c < m; c++) {
                const ls_acc l = (ls_acc)lx[lp[s + c] + (e - 1u - (s + c)) + t];
                ls_acc *wc = w + (size_t)(s + c) * k;
                for (q = 0; q < k; q++) wc[q] -= l * wi[q];
            }
        }
        for (c = e; c > s; c--) {
            const uint32_t cc = c - 1u;
            const ls_real *lc = lx + lp[cc];
            for (c2 = cc + 1u; c2 < e; c2++) {
                const ls_acc l = (ls_acc)lc[c2 - cc - 1u];
                for (q = 0; q < k; q++) w[(size_t)cc * k + q] -= l * w[(size_t)c2 * k + q];
            }
        }
        e = s;
    }
}

ls_status ls_ldlt_solve_bytes_n(uint32_t n, uint32_t k, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (k == 0) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)n * k, sizeof(ls_acc));
    if ((size_t)n * k / k != n) return LS_ERR_TOO_LARGE;
    return ls_size_get(&s, bytes);
}

ls_status ls_ldlt_solve_bytes(const ls_ldlt *f, uint32_t k, size_t *bytes)
{
    if (bytes != NULL) *bytes = 0;
    if (f == NULL) return LS_ERR_INVALID;
    return ls_ldlt_solve_bytes_n(f->n, k, bytes);
}

/* The k = 3 solve's gather (P b into w) and scatter (w into P^T x) over
 * rows [lo, hi): 1 when every value moved is finite (x - x is 0 for a
 * finite x and NaN otherwise, and a sum of zeros and NaNs is NaN iff one
 * is, in any order). */
int ls_ldlt_gather3(const ls_ldlt *f, const ls_real *x, ls_acc *w, uint32_t lo, uint32_t hi)
{
    uint32_t i;
    ls_real chk0 = 0, chk1 = 0, chk2 = 0;
    for (i = lo; i < hi; i++) {
        const ls_real *src = x + 3u * (size_t)f->perm[i];
        ls_acc *dst = w + 3u * (size_t)i;
        const ls_real v0 = src[0], v1 = src[1], v2 = src[2];
        dst[0] = (ls_acc)v0;
        dst[1] = (ls_acc)v1;
        dst[2] = (ls_acc)v2;
        chk0 += v0 - v0;
        chk1 += v1 - v1;
        chk2 += v2 - v2;
    }
    return chk0 + chk1 + chk2 == 0;
}

int ls_ldlt_scatter3(const ls_ldlt *f, const ls_acc *w, ls_real *x, uint32_t lo, uint32_t hi)
{
    uint32_t i;
    ls_real chk0 = 0, chk1 = 0, chk2 = 0;
    for (i = lo; i < hi; i++) {
        ls_real *dst = x + 3u * (size_t)f->perm[i];
        const ls_acc *src = w + 3u * (size_t)i;
        const ls_real v0 = (ls_real)src[0], v1 = (ls_real)src[1], v2 = (ls_real)src[2];
        dst[0] = v0;
        dst[1] = v1;
        dst[2] = v2;
        chk0 += v0 - v0;
        chk1 += v1 - v1;
        chk2 += v2 - v2;
    }
    return chk0 + chk1 + chk2 == 0;
}

/* The k = 3 solve: the whole passes, or the plan's split over the caller's
 * workers (ldlt_split.c: the same bits). */
static ls_status solve3(const ls_ldlt *f, const ls_ldlt_split *sp, const ls_parallel *par, ls_real *x, ls_acc *w)
{
    if (sp != NULL) return ls_ldlt_split_solve3(f, sp, par, x, w);
    if (!ls_ldlt_gather3(f, x, w, 0, f->n)) return LS_ERR_NONFINITE;
    ls_ldlt_fwd3_range(f, w, 0, f->n, f->n);
    ls_ldlt_bwd3_range(f, w, 0, f->n);
    return ls_ldlt_scatter3(f, w, x, 0, f->n) ? LS_OK : LS_ERR_NONFINITE;
}

/* Scratch for a solve, or the status to return without one. */
static ls_acc *solve_scratch(const ls_ldlt *f, uint32_t k, const ls_real *x, ls_arena *arena, ls_status *st)
{
    size_t bytes;
    ls_acc *w;
    *st = LS_ERR_INVALID;
    if (f == NULL || k == 0 || arena == NULL || (x == NULL && f->n > 0)) return NULL;
    *st = LS_ERR_STATE;
    if (f->state != LS_LDLT_VALID) return NULL;
    *st = LS_ERR_TOO_LARGE;
    if (ls_ldlt_solve_bytes(f, k, &bytes) != LS_OK) return NULL;
    w = (ls_acc *)ls_arena_scratch(arena, (size_t)f->n * k, sizeof(ls_acc));
    *st = w != NULL ? LS_OK : all_finite(x, (size_t)f->n * k) ? LS_ERR_NOMEM : LS_ERR_NONFINITE;
    return w;
}

ls_status ls_ldlt_solve_split(const ls_ldlt *f, const ls_ldlt_split *sp, const ls_parallel *par, ls_real *x,
                              ls_arena *arena)
{
    ls_arena_mark mark;
    ls_acc *w;
    ls_status st;
    if (sp != NULL && (f == NULL || sp->n != f->n)) return LS_ERR_INVALID;
    if (arena == NULL) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    w = solve_scratch(f, 3u, x, arena, &st);
    if (w == NULL) return st;
    st = solve3(f, sp != NULL && sp->workers > 1u ? sp : NULL, par, x, w);
    ls_arena_restore(arena, mark);
    return st;
}

ls_status ls_ldlt_solve(const ls_ldlt *f, uint32_t k, ls_real *x, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_acc *w;
    uint32_t i, c, n;
    ls_status st;
    if (k == 3) return ls_ldlt_solve_split(f, NULL, NULL, x, arena);
    if (arena == NULL) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    w = solve_scratch(f, k, x, arena, &st);
    if (w == NULL) return st;
    n = f->n;
    if (!all_finite(x, (size_t)n * k)) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NONFINITE;
    }
    for (i = 0; i < n; i++) {
        const ls_real *src = x + (size_t)f->perm[i] * k;
        for (c = 0; c < k; c++) w[(size_t)i * k + c] = (ls_acc)src[c];
    }
    forwardk(f, k, w);
    backwardk(f, k, w);
    for (i = 0; i < n; i++) {
        ls_real *dst = x + (size_t)f->perm[i] * k;
        for (c = 0; c < k; c++) dst[c] = (ls_real)w[(size_t)i * k + c];
    }
    ls_arena_restore(arena, mark);
    return all_finite(x, (size_t)n * k) ? LS_OK : LS_ERR_NONFINITE;
}

ls_status ls_ldlt_refine_bytes(const ls_ldlt *f, uint32_t k, size_t *bytes)
{
    ls_size s;
    ls_status st = ls_ldlt_solve_bytes(f, k, bytes);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)f->n * k, sizeof(ls_real)); /* the residual */
    ls_size_add(&s, *bytes, 1u);                        /* the solve's */
    return ls_size_get(&s, bytes);
}

ls_status ls_ldlt_refine(const ls_ldlt *f, const ls_csc *a, uint32_t k, const ls_real *b, ls_real *x,
                         uint32_t steps, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_real *r;
    size_t i, count, bytes;
    uint32_t s;
    ls_status st = LS_OK;
    if (f == NULL || a == NULL || k == 0 || arena == NULL || ((b == NULL || x == NULL) && f->n > 0) ||
        a->ncols != f->n || a->nrows != f->n)
        return LS_ERR_INVALID;
    if (f->state != LS_LDLT_VALID) return LS_ERR_STATE;
    if (ls_ldlt_refine_bytes(f, k, &bytes) != LS_OK) return LS_ERR_TOO_LARGE;
    count = (size_t)f->n * k;
    if (!all_finite(b, count) || !all_finite(x, count)) return LS_ERR_NONFINITE;
    mark = ls_arena_save(arena);
    r = (ls_real *)ls_arena_scratch(arena, count, sizeof(ls_real));
    if (r == NULL) return LS_ERR_NOMEM;
    for (s = 0; s < steps; s++) {
        st = ls_csc_matvec_sym(a, k, x, r);
        if (st != LS_OK) break;
        for (i = 0; i < count; i++) r[i] = b[i] - r[i];
        st = ls_ldlt_solve(f, k, r, arena);
        if (st != LS_OK) break;
        for (i = 0; i < count; i++) x[i] += r[i];
    }
    ls_arena_restore(arena, mark);
    if (st != LS_OK) return st;
    return all_finite(x, count) ? LS_OK : LS_ERR_NONFINITE;
}
