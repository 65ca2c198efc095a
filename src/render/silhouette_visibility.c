/* silhouette_visibility.c - candidates and visibility: which surface is in front of and behind a segment's point */
#include "silhouette_internal.h"

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
 * (the parameters tested increase; ls_sil_run_pass adds them as their intervals
 * begin). The answer does not depend on the
 * order of the list (ties of the surface behind keep the smaller triangle),
 * so an occluder found is moved to the front, where the next point tests it
 * first. */
int ls_sil_visibility(const sctx *sc, const sedge *ed, ls_real t, uint32_t *nact, uint32_t *beh)
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
            int n = ls_sil_tri_poly_cut(sc, f, x, y);
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
 * candidates are tested, never the outcome. Inlined (SIL_INLINE): ls_sil_run_pass
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
void ls_sil_run_pass(const sctx *sc, sedge *ed, const srun *run)
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
        /* a hit that shares an end vertex mostly misses: the cheap test first */
        if (k < nend && ls_sil_end_face_misses(sc, ed, f)) continue;
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
                n = ls_sil_tri_poly_cut(sc, f, x, y);
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
     * all active from the start, half the visibility tests skip one not
     * begun yet */
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
                if (ls_sil_visibility(sc, ed, mid, &nact, &beh)) {
                    /* a split whose crossing changed neither side (an edge farther than the surface
                     * behind, or of an occluder elsewhere) joins the two sub-pieces: one integrand */
                    if (pend && (beh != pbeh || phi != lo)) ls_sil_integrate(sc, ed, plo, phi, pbeh, run->pix[j]);
                    if (!pend || beh != pbeh || phi != lo) plo = lo;
                    phi = hi;
                    pbeh = beh;
                    pend = 1;
                } else if (pend) {
                    ls_sil_integrate(sc, ed, plo, phi, pbeh, run->pix[j]);
                    pend = 0;
                }
            }
            if (!(hi < b)) break;
        }
        if (pend) ls_sil_integrate(sc, ed, plo, phi, pbeh, run->pix[j]);
    }
}
