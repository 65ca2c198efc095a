/* silhouette_walk.c - walks across the mesh that prove parts of a segment hidden without a candidate search */
#include "silhouette_internal.h"

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
 * ls_sil_visibility()'s tolerance. */
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
    tol = (ls_real)256 * LS_REAL_EPSILON * ((ls_real)1 + r_abs(ze)); /* four times ls_sil_visibility()'s (exact: powers of 2) */
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
 * (ls_sil_run_hidden). New walks from the runs found too few hidden ones to
 * pay for themselves (docs/silhouette-history.md). */
LS_NOINLINE int ls_sil_walk_segment(const sctx *sc, sedge *ed)
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
            /* stopped short (but by the cap forwards: ls_sil_run_hidden goes on with that one), a walk
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
 * (ls_sil_walk_segment), a walk stopped by the cap going on from where it stopped
 * when the run starts inside; else the run loses the pixels at either end
 * that lie inside it: ls_sil_run_pass sweeps each pixel as it would alone. */
LS_NOINLINE int ls_sil_run_hidden(const sctx *sc, sedge *ed, srun *run)
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
 * above their rounding errors; the cone itself not degenerate). Many
 * faces near a silhouette edge's ends share a vertex with the segment's
 * face, and then cost no candidate test. */
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
 * of line: inlined, its frame went into ls_sil_run_pass's, on the deepest chain
 * of the MCU's 4 KiB job stack (the Cortex-M4 double fit measured 4140
 * bytes). */
LS_NOINLINE int ls_sil_end_face_misses(const sctx *sc, const sedge *ed, const uint32_t *g)
{
    uint32_t k;
    for (k = 0; k < 3u; k++) {
        if (g[k] != ed->va && g[k] != ed->vb) continue;
        if (!sc->allfront && (sc->vfront[g[0]] & sc->vfront[g[1]] & sc->vfront[g[2]]) == 0) return 0;
        return wedge_misses(sc, ed, g, k, g[k] == ed->va ? (ls_real)1 : (ls_real)-1);
    }
    return 0;
}
