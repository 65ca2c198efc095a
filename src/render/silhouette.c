/* silhouette.c - exact box-filter silhouette derivatives (largesteps/silhouette.h): the entry, its passes over the contour edges and their segments */
#include "silhouette_internal.h"

/* Endpoint of an edge clipped at the near plane Z + W = 0: the point
 * p + s (q - p), s = dp / (dp - dq), written to out. */
static void near_point(const ls_real *p, const ls_real *q, ls_real s, ls_real out[4])
{
    int r;
    for (r = 0; r < 4; r++) out[r] = p[r] + s * (q[r] - p[r]);
}

/* tri_poly of a triangle with a corner behind the eye or the near plane
 * (or without sc->win): out of line, the inlined path takes the rest. */
LS_NOINLINE int ls_sil_tri_poly_cut(const sctx *sc, const uint32_t *f, ls_real x[4], ls_real y[4])
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
void ls_sil_window_to_clip(const sctx *sc, const ls_real *cl, ls_real gx, ls_real gy, ls_real g[4])
{
    g[0] = gx * sc->width / ((ls_real)2 * cl[3]);
    g[1] = -(gy * sc->height / ((ls_real)2 * cl[3]));
    g[2] = (ls_real)0;
    g[3] = -(g[0] * cl[0] + g[1] * cl[1]) / cl[3];
}

/* Adds clip-space gradient g of vertex v into the positions (through mvp). */
void ls_sil_clip_to_positions(const sctx *sc, uint32_t v, const ls_real g[4], ls_real *gp)
{
    ls_real *d = gp + 3 * (size_t)v;
    int c;
    for (c = 0; c < 3; c++) d[c] += ((sc->m[c] * g[0] + sc->m[4 + c] * g[1]) + sc->m[8 + c] * g[2]) + sc->m[12 + c] * g[3];
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
        ls_sil_clip_to_positions(sc, ep->v, g, gp);
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
    ls_sil_clip_to_positions(sc, ep->v, a, gp);
    ls_sil_clip_to_positions(sc, ep->w, b, gp);
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
    if (ls_sil_walk_segment(sc, &ed)) return;
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
            if (!ls_sil_run_hidden(sc, &ed, &run)) ls_sil_run_pass(sc, &ed, &run);
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
    if (run.n > 0 && !ls_sil_run_hidden(sc, &ed, &run)) ls_sil_run_pass(sc, &ed, &run);
    ed.ka *= sc->boost;
    ed.kb *= sc->boost;
    ls_sil_window_to_clip(sc, ea->c, nrm[0] * ed.ka, nrm[1] * ed.ka, g);
    end_to_positions(sc, ea, g, sc->gp);
    ls_sil_window_to_clip(sc, eb->c, nrm[0] * ed.kb, nrm[1] * ed.kb, g);
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
    if (vis == NULL) return ls_invalid_arg(diag, "view->vis is NULL");
    if (table == NULL) return ls_invalid_arg(diag, "view->table is NULL");
    if (opts == NULL) return ls_invalid_arg(diag, "view->opts is NULL");
    if (vis->tri == NULL || vis->clip == NULL || table->magic != EDGE_TABLE_MAGIC) return LS_ERR_STATE;
    if (table->triangle_count != counts[0] || table->vertex_count != counts[1])
        return ls_invalid_arg(diag, "view->table: triangle_count and vertex_count allowed = the view's");
    return ls_shade_check_args(vis, counts, indices, normals, opts, diag);
}

void ls_sil_sctx_init(sctx *sc, const ls_vis *vis, const uint32_t *indices, uint32_t triangle_count)
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

static ls_status silhouette_scratch_bytes_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
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
    ls_sil_sctx_init(&sc, vis, indices, triangle_count);
    ls_sil_choose_tiles(&sc, ls_sil_choose_cull(&sc, table, NULL));
    ls_sil_box_pass(&sc, count, &over);
    if (over) return LS_ERR_TOO_LARGE;
    return scratch_size(vis->vertex_count, (size_t)sc.tiles_x * sc.tiles_y, triangle_count, count[0],
                        slot_count(count[1], count[0]), bytes);
}

ls_status ls_silhouette_scratch_bytes(const ls_view *view, size_t *bytes)
{
    if (view == NULL) return LS_ERR_INVALID;
    return silhouette_scratch_bytes_impl(view->vis, view->table, view->indices, view->triangle_count, bytes);
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
 * are in the caches (docs/fast-paths.md has what this order pays). The keys go to ord, which holds 2 cap of them (ls_sil_setup_pass's free
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

static ls_status silhouette_backward_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
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
    if (mvp == NULL) return ls_invalid_arg(diag, "view->mvp is NULL");
    if (grad_image == NULL) return ls_invalid_arg(diag, "grad_image is NULL");
    if (grad_positions == NULL) return ls_invalid_arg(diag, "grad_positions is NULL");
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    counts[0] = triangle_count;
    counts[1] = vertex_count;
    st = check_args(vis, table, indices, normals, opts, counts, diag);
    if (st != LS_OK) return st;
    ls_sil_sctx_init(&sc, vis, indices, triangle_count);
    sc.normals = normals;
    sc.o = opts;
    sc.m = mvp;
    sc.gimg = grad_image;
    sc.flat = opts->mode == LS_SHADE_MASK;
    sc.boost = boost;
    sc.gp = grad_positions;
    ls_sil_sh_quad_init(&sc);
#if LS_REAL_IS_FLOAT
    sc.qtol = 1e-4f;
#else
    sc.qtol = 1e-9;
#endif
    mark = ls_arena_save(arena);
    st = ls_sil_setup_pass(&sc, table, vertex_count, &bits, &ord, arena);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    edges_pass(&sc, table, bits, ord, triangle_count / 4u);
    for (t = 0; sc.behind > 0 && t < triangle_count; t++) cut_pass(&sc, t);
    ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_silhouette_backward(const ls_view *view, const ls_real *grad_image, ls_real *grad_positions,
                                 ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return silhouette_backward_impl(view->vis, view->table, view->indices, view->triangle_count, view->normals,
                                  view->vertex_count, view->opts, view->mvp, view->boost, grad_image, grad_positions,
                                  arena, diag);
}
