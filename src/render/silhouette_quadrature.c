/* silhouette_quadrature.c - the integral along a visible sub-piece: spans, the SH quadratic form, adaptive quadrature */
#include "silhouette_internal.h"

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
 * on the same triangle (pixel boundaries, ls_sil_run_pass's joins). */
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
void ls_sil_sh_quad_init(sctx *sc)
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

/* For the symmetric 4 x 4 M stored as ls_sil_sh_quad_init's m, entry i at M[gs i]
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
 * pc->own: per channel's M_c (ls_sil_sh_quad_init), the form of H(u) = H0 + u dH
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
void ls_sil_integrate(const sctx *sc, sedge *ed, ls_real lo, ls_real hi, uint32_t beh, size_t p)
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
