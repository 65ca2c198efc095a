/* tangle.c - self-intersections, inverted faces, triangle shape statistics
 * (see largesteps/tangle.h). */
#include <largesteps/tangle.h>
#include <largesteps/bvh.h>
#include <largesteps/math.h>
#include <largesteps/sort.h>
#include <string.h>
#include "../base/parallel.h"

#define RAD_TO_DEG ((ls_real)57.295779513082320876798)

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index, int has_index)
{
    (void)ls_diag_set(diag, st, what, has_index ? index : LS_DIAG_NO_INDEX);
}

static void sub3(const ls_real *a, const ls_real *b, ls_real *o)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static void cross3(const ls_real *u, const ls_real *v, ls_real *n)
{
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

static ls_real dot3(const ls_real *a, const ls_real *b)
{
    return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
}

/* Sign of the volume [d, a - p, b - p]. */
static int vol_sign(const ls_real *d, const ls_real *p, const ls_real *a, const ls_real *b)
{
    ls_real u[3], v[3], n[3], x;
    sub3(a, p, u);
    sub3(b, p, v);
    cross3(u, v, n);
    x = dot3(d, n);
    return (x > 0) - (x < 0);
}

static int orient2(const ls_real *a, const ls_real *b, const ls_real *c)
{
    ls_real x = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    return (x > 0) - (x < 0);
}

static int between(ls_real a, ls_real b, ls_real x)
{
    return a <= b ? (a <= x && x <= b) : (b <= x && x <= a);
}

/* Closed 2-D segments pq and ab meet. */
static int seg_seg2(const ls_real *p, const ls_real *q, const ls_real *a, const ls_real *b)
{
    int o1 = orient2(p, q, a), o2 = orient2(p, q, b), o3 = orient2(a, b, p), o4 = orient2(a, b, q);
    if (o1 * o2 < 0 && o3 * o4 < 0) return 1;
    if (o1 == 0 && between(p[0], q[0], a[0]) && between(p[1], q[1], a[1])) return 1;
    if (o2 == 0 && between(p[0], q[0], b[0]) && between(p[1], q[1], b[1])) return 1;
    if (o3 == 0 && between(a[0], b[0], p[0]) && between(a[1], b[1], p[1])) return 1;
    if (o4 == 0 && between(a[0], b[0], q[0]) && between(a[1], b[1], q[1])) return 1;
    return 0;
}

static int in_tri2(const ls_real *t0, const ls_real *t1, const ls_real *t2, const ls_real *p)
{
    int s0 = orient2(t0, t1, p), s1 = orient2(t1, t2, p), s2 = orient2(t2, t0, p);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

/* Coplanar case: drop the axis of the normal's largest component. */
static int seg_tri_coplanar(const ls_real *p, const ls_real *q, const ls_real *const *t, const ls_real *n)
{
    ls_real P[2], Q[2], T[3][2];
    uint32_t ax = 0, i, k, j;
    ls_real m = LS_RFABS(n[0]);
    if (LS_RFABS(n[1]) > m) {
        m = LS_RFABS(n[1]);
        ax = 1;
    }
    if (LS_RFABS(n[2]) > m) ax = 2;
    for (k = 0, j = 0; k < 3u; k++) {
        if (k == ax) continue;
        P[j] = p[k];
        Q[j] = q[k];
        for (i = 0; i < 3u; i++) T[i][j] = t[i][k];
        j++;
    }
    if (in_tri2(T[0], T[1], T[2], P) || in_tri2(T[0], T[1], T[2], Q)) return 1;
    for (i = 0; i < 3u; i++)
        if (seg_seg2(P, Q, T[i], T[(i + 1u) % 3u])) return 1;
    return 0;
}

/* Sum of absolute components (a cheap norm for rounding tolerances). */
static ls_real norm1(const ls_real *a)
{
    return LS_RFABS(a[0]) + LS_RFABS(a[1]) + LS_RFABS(a[2]);
}

/* The closed segment pq meets the closed triangle t (0 for a degenerate t).
 * A point whose signed distance to t's plane is below the rounding error of
 * computing it (64 epsilon times the magnitudes involved) counts as on the
 * plane: nearly coplanar pairs are then decided in the plane, not by the
 * sign of rounding noise (which made far-apart faces of a flat region look
 * intersecting). */
static int seg_tri(const ls_real *p, const ls_real *q, const ls_real *const *t)
{
    const ls_real tol = (ls_real)64 * LS_REAL_EPSILON;
    ls_real u[3], v[3], n[3], wp[3], wq[3], d[3], dp, dq, nn;
    int s0, s1, s2, zp, zq;
    sub3(t[1], t[0], u);
    sub3(t[2], t[0], v);
    cross3(u, v, n);
    if (n[0] == 0 && n[1] == 0 && n[2] == 0) return 0;
    nn = norm1(n);
    sub3(p, t[0], wp);
    sub3(q, t[0], wq);
    dp = dot3(n, wp);
    dq = dot3(n, wq);
    zp = LS_RFABS(dp) <= tol * nn * norm1(wp);
    zq = LS_RFABS(dq) <= tol * nn * norm1(wq);
    if (!zp && !zq && ((dp > 0 && dq > 0) || (dp < 0 && dq < 0))) return 0;
    if (zp && zq) return seg_tri_coplanar(p, q, t, n);
    if (zp) return seg_tri_coplanar(p, p, t, n); /* only p touches the plane */
    if (zq) return seg_tri_coplanar(q, q, t, n);
    sub3(q, p, d);
    s0 = vol_sign(d, p, t[0], t[1]);
    s1 = vol_sign(d, p, t[1], t[2]);
    s2 = vol_sign(d, p, t[2], t[0]);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

/* Closed axis-aligned boxes of two triangles overlap (exact comparisons). */
static int boxes_meet(const ls_real *const *a, const ls_real *const *b)
{
    uint32_t k;
    for (k = 0; k < 3u; k++) {
        ls_real alo = a[0][k], ahi = a[0][k], blo = b[0][k], bhi = b[0][k];
        uint32_t i;
        for (i = 1; i < 3u; i++) {
            if (a[i][k] < alo) alo = a[i][k];
            if (a[i][k] > ahi) ahi = a[i][k];
            if (b[i][k] < blo) blo = b[i][k];
            if (b[i][k] > bhi) bhi = b[i][k];
        }
        if (ahi < blo || bhi < alo) return 0;
    }
    return 1;
}

int ls_triangles_meet(const ls_real a0[3], const ls_real a1[3], const ls_real a2[3], const ls_real b0[3],
                      const ls_real b1[3], const ls_real b2[3])
{
    const ls_real *ta[3], *tb[3];
    uint32_t i;
    ta[0] = a0;
    ta[1] = a1;
    ta[2] = a2;
    tb[0] = b0;
    tb[1] = b1;
    tb[2] = b2;
    if (!boxes_meet(ta, tb)) return 0;
    for (i = 0; i < 3u; i++) {
        if (seg_tri(ta[i], ta[(i + 1u) % 3u], tb)) return 1;
        if (seg_tri(tb[i], tb[(i + 1u) % 3u], ta)) return 1;
    }
    return 0;
}

static int pair_test(const ls_mesh *m, uint32_t f, uint32_t g)
{
    const uint32_t *s = m->triangles + 3u * (size_t)f, *t = m->triangles + 3u * (size_t)g;
    const ls_real *ps[3], *pt[3];
    uint32_t i, j, shared = 0, si = 0, tj = 0;
    for (i = 0; i < 3u; i++) {
        for (j = 0; j < 3u; j++) {
            if (s[i] == t[j]) {
                shared++;
                si = i;
                tj = j;
            }
        }
    }
    if (shared >= 2u) return 0;
    for (i = 0; i < 3u; i++) {
        ps[i] = m->positions + 3u * (size_t)s[i];
        pt[i] = m->positions + 3u * (size_t)t[i];
    }
    if (shared == 0) return ls_triangles_meet(ps[0], ps[1], ps[2], pt[0], pt[1], pt[2]);
    /* one shared vertex: the opposite edges */
    return seg_tri(ps[(si + 1u) % 3u], ps[(si + 2u) % 3u], pt) || seg_tri(pt[(tj + 1u) % 3u], pt[(tj + 2u) % 3u], ps);
}

int ls_tangle_pair(const ls_mesh *mesh, uint32_t f, uint32_t g)
{
    uint32_t k;
    if (mesh == NULL || mesh->triangles == NULL || mesh->positions == NULL || f == g || f >= mesh->face_count ||
        g >= mesh->face_count)
        return 0;
    for (k = 0; k < 3u; k++)
        if (mesh->triangles[3u * (size_t)f + k] >= mesh->vertex_count ||
            mesh->triangles[3u * (size_t)g + k] >= mesh->vertex_count)
            return 0;
    return pair_test(mesh, f, g);
}

/* ---- sizing ----------------------------------------------------------- */

/* The intersection search's split: a part per worker (its pair count and
 * first pair, a bit per face), blocks of faces handed out TANGLE_BLOCKS per
 * worker so that a slow block does not hold the others back. */
#define TANGLE_BLOCKS 8u

typedef struct tangle_part {
    uint32_t pairs, first[2];
} tangle_part;

static ls_status tangle_size(uint32_t face_count, uint32_t workers, size_t *bytes)
{
    ls_size s, b, sortp;
    size_t bvh, tree, n3;
    ls_status st;
    if ((st = ls_bvh_bytes(face_count, &bvh)) != LS_OK) return st;
    if ((st = ls_bvh_tree_bytes(face_count, &tree)) != LS_OK) return st;
    n3 = (size_t)face_count * 3u;
    /* phase 1: the tree's build */
    ls_size_init(&s);
    ls_size_add(&s, bvh, 1);
    /* phase 2: tree + face flags + the nodes' common vertices */
    ls_size_init(&b);
    ls_size_add(&b, tree, 1);
    ls_size_add(&b, (size_t)workers * ((size_t)face_count / 32u + 1u), sizeof(uint32_t));
    ls_size_add(&b, workers, sizeof(tangle_part));
    ls_size_add(&b, 3u * (size_t)ls_bvh_node_count(face_count), sizeof(uint32_t));
    ls_size_max(&s, &b);
    /* phase 3 (tree released): keys, index, sort scratch for 3F corners */
    ls_size_init(&sortp);
    ls_size_add(&sortp, n3, sizeof(uint64_t));
    ls_size_add(&sortp, n3, sizeof(uint32_t));
    ls_size_add(&sortp, n3, sizeof(uint32_t));
    ls_size_max(&s, &sortp);
    return ls_size_get(&s, bytes);
}

ls_status ls_tangle_parallel_bytes(uint32_t face_count, uint32_t workers, size_t *bytes)
{
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (face_count == 0 || workers == 0) return LS_ERR_INVALID;
    if (face_count > (UINT32_MAX - 1u) / 3u || workers > LS_TANGLE_MAX_WORKERS) return LS_ERR_TOO_LARGE;
    return tangle_size(face_count, workers, bytes);
}

ls_status ls_tangle_bytes(uint32_t face_count, size_t *bytes)
{
    return ls_tangle_parallel_bytes(face_count, 1u, bytes);
}

/* ---- shapes ----------------------------------------------------------- */

static uint64_t real_key(ls_real x)
{
#if LS_REAL_IS_FLOAT
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return (uint64_t)b;
#else
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
#endif
}

static ls_real key_real(uint64_t k)
{
    ls_real x;
#if LS_REAL_IS_FLOAT
    uint32_t b = (uint32_t)k;
    memcpy(&x, &b, sizeof b);
#else
    memcpy(&x, &k, sizeof k);
#endif
    return x;
}

/* Nearest-rank percentile p (1..100) of n sorted keys. */
static ls_real pct(const uint64_t *keys, const uint32_t *idx, uint32_t n, uint32_t p)
{
    uint64_t r = ((uint64_t)n * p + 99u) / 100u;
    if (r == 0) r = 1;
    return key_real(keys[idx[r - 1u]]);
}

/* Face f's edge vectors e[k] = v[k+1] - v[k]. */
static void face_edges(const ls_mesh *m, uint32_t f, ls_real e[3][3])
{
    const uint32_t *t = m->triangles + 3u * (size_t)f;
    uint32_t k;
    for (k = 0; k < 3u; k++) sub3(m->positions + 3u * (size_t)t[(k + 1u) % 3u], m->positions + 3u * (size_t)t[k], e[k]);
}

/* Face f's corner angles in degrees (corner k between e[k] and -e[k+2]). */
static void corner_angles(const ls_mesh *m, uint32_t f, ls_real ang[3])
{
    ls_real e[3][3];
    uint32_t k;
    face_edges(m, f, e);
    for (k = 0; k < 3u; k++) {
        ls_real u[3], c[3];
        const ls_real *a = e[k], *b = e[(k + 2u) % 3u];
        u[0] = -b[0];
        u[1] = -b[1];
        u[2] = -b[2];
        cross3(a, u, c);
        ang[k] = LS_RATAN2(LS_RSQRT(dot3(c, c)), dot3(a, u)) * RAD_TO_DEG;
    }
}

/* Face f's quality 2 r / R = 4 |n|^2 / (l0 l1 l2 (l0 + l1 + l2)), in [0, 1]. */
static ls_real face_quality(const ls_mesh *m, uint32_t f)
{
    ls_real e[3][3], n[3], len[3], den, n2, q;
    uint32_t k;
    face_edges(m, f, e);
    for (k = 0; k < 3u; k++) len[k] = LS_RSQRT(dot3(e[k], e[k]));
    cross3(e[0], e[1], n);
    n2 = dot3(n, n);
    den = (len[0] * len[1] * len[2]) * ((len[0] + len[1]) + len[2]);
    q = (den > 0 && n2 > 0) ? (ls_real)4 * n2 / den : (ls_real)0;
    if (!(q >= 0)) q = 0;
    return q > 1 ? (ls_real)1 : q;
}

static void shapes(const ls_mesh *m, uint64_t *keys, uint32_t *idx, uint32_t *scratch, ls_tangle_report *r)
{
    uint32_t f, k, n3 = 3u * m->face_count;
    ls_real qsum = 0, qc = 0;
    for (f = 0; f < m->face_count; f++) {
        ls_real ang[3];
        corner_angles(m, f, ang);
        for (k = 0; k < 3u; k++) keys[3u * f + k] = real_key(ang[k]);
    }
    for (k = 0; k < n3; k++) idx[k] = k;
    ls_sort_u64(keys, idx, n3, scratch);
    r->angle_min = key_real(keys[idx[0]]);
    r->angle_max = key_real(keys[idx[n3 - 1u]]);
    r->angle_p1 = pct(keys, idx, n3, 1);
    r->angle_p5 = pct(keys, idx, n3, 5);
    r->angle_p50 = pct(keys, idx, n3, 50);
    for (f = 0; f < m->face_count; f++) {
        const ls_real q = face_quality(m, f);
        ls_real t;
        keys[f] = real_key(q);
        idx[f] = f;
        /* compensated sum of the qualities */
        t = qsum + q;
        if (LS_RFABS(qsum) >= LS_RFABS(q)) qc += (qsum - t) + q;
        else qc += (q - t) + qsum;
        qsum = t;
    }
    ls_sort_u64(keys, idx, m->face_count, scratch);
    r->quality_min = key_real(keys[idx[0]]);
    r->quality_p1 = pct(keys, idx, m->face_count, 1);
    r->quality_p5 = pct(keys, idx, m->face_count, 5);
    r->quality_p50 = pct(keys, idx, m->face_count, 50);
    r->quality_mean = (qsum + qc) / (ls_real)m->face_count;
}

/* ---- the report ------------------------------------------------------- */

static void face_normal(const ls_mesh *m, uint32_t f, ls_real n[3])
{
    const uint32_t *t = m->triangles + 3u * (size_t)f;
    ls_real u[3], v[3];
    sub3(m->positions + 3u * (size_t)t[1], m->positions + 3u * (size_t)t[0], u);
    sub3(m->positions + 3u * (size_t)t[2], m->positions + 3u * (size_t)t[0], v);
    cross3(u, v, n);
}

static void orientation(const ls_mesh *m, const ls_mesh *ref, ls_tangle_report *r)
{
    uint32_t f;
    for (f = 0; f < m->face_count; f++) {
        ls_real n[3], nr[3];
        face_normal(m, f, n);
        if (n[0] == 0 && n[1] == 0 && n[2] == 0) r->degenerate_faces++;
        if (ref == NULL) continue;
        face_normal(ref, f, nr);
        if (dot3(n, nr) < 0) {
            if (r->inverted_faces == 0) r->first_inverted = f;
            r->inverted_faces++;
        }
    }
}

/* ---- self-intersections ------------------------------------------------ */

/* Two faces meet only where an edge of one meets the other (pair_test): an
 * edge (a, b) of f can meet only faces that hold neither a nor b (a shared
 * vertex leaves the opposite edges; two shared vertices, nothing). So the
 * search goes edge by edge and skips every subtree whose faces all hold a or
 * b: a fan's spokes, or a million faces on one vertex, are not paired with
 * the whole tree (a search by face boxes tests Theta(F^2) pairs there). Each
 * unordered pair is tested once, at the first of its edge-face contacts in a
 * fixed order. */

static int holds(const uint32_t *t, uint32_t v)
{
    return t[0] == v || t[1] == v || t[2] == v;
}

static void grow_box(const ls_real *p, ls_real *lo, ls_real *hi)
{
    uint32_t a;
    for (a = 0; a < 3u; a++) {
        if (p[a] < lo[a]) lo[a] = p[a];
        if (p[a] > hi[a]) hi[a] = p[a];
    }
}

static int boxes_overlap(const ls_real *alo, const ls_real *ahi, const ls_real *blo, const ls_real *bhi)
{
    uint32_t a;
    for (a = 0; a < 3u; a++)
        if (ahi[a] < blo[a] || bhi[a] < alo[a]) return 0;
    return 1;
}

/* The box of edge k of face x (its vertices k and k + 1), grown by `slack`:
 * seg_tri counts a point within its rounding tolerance of a triangle's plane
 * as on it, so the box must reach that far. */
static void edge_box(const ls_mesh *m, uint32_t x, uint32_t k, ls_real slack, ls_real lo[3], ls_real hi[3])
{
    const uint32_t *t = m->triangles + 3u * (size_t)x;
    const ls_real *p = m->positions + 3u * (size_t)t[k], *q = m->positions + 3u * (size_t)t[(k + 1u) % 3u];
    uint32_t a;
    for (a = 0; a < 3u; a++) lo[a] = hi[a] = p[a];
    grow_box(q, lo, hi);
    for (a = 0; a < 3u; a++) {
        lo[a] -= slack;
        hi[a] += slack;
    }
}

/* An edge (ends va, vb; box elo, ehi) can meet face y: y holds neither
 * end, and their boxes meet. */
static int edge_meets_box(const ls_mesh *m, uint32_t va, uint32_t vb, const ls_real *elo, const ls_real *ehi,
                          uint32_t y)
{
    const uint32_t *ty = m->triangles + 3u * (size_t)y;
    ls_real flo[3], fhi[3];
    uint32_t a;
    if (holds(ty, va) || holds(ty, vb)) return 0;
    for (a = 0; a < 3u; a++) flo[a] = fhi[a] = m->positions[3u * (size_t)ty[0] + a];
    grow_box(m->positions + 3u * (size_t)ty[1], flo, fhi);
    grow_box(m->positions + 3u * (size_t)ty[2], flo, fhi);
    return boxes_overlap(elo, ehi, flo, fhi);
}

/* Edge k of face x can meet face y (edge_meets_box). */
static int contact(const ls_mesh *m, uint32_t x, uint32_t k, uint32_t y, ls_real slack)
{
    const uint32_t *tx = m->triangles + 3u * (size_t)x;
    ls_real elo[3], ehi[3];
    edge_box(m, x, k, slack, elo, ehi);
    return edge_meets_box(m, tx[k], tx[(k + 1u) % 3u], elo, ehi, y);
}

/* Edge k of f is the pair {f, g}'s first contact: the lower face's edges
 * come first, then the higher's. */
static int first_contact(const ls_mesh *m, uint32_t f, uint32_t k, uint32_t g, ls_real slack)
{
    const uint32_t x[2] = {f < g ? f : g, f < g ? g : f};
    uint32_t s, j;
    for (s = 0; s < 2u; s++)
        for (j = 0; j < 3u; j++) {
            if (x[s] == f && j == k) return 1;
            if (contact(m, x[s], j, x[1u - s], slack)) return 0;
        }
    return 1;
}

/* The vertices every face of each node holds (up to 3 per node, LS_MESH_NONE
 * for the rest), children before parents (a child's index is above its
 * parent's). */
static void common_vertices(const ls_mesh *m, const ls_bvh *bvh, uint32_t *com)
{
    uint32_t i = bvh->node_count, j, k;
    while (i-- > 0u) {
        const ls_bvh_node *n = &bvh->nodes[i];
        uint32_t *c = com + 3u * (size_t)i;
        if (n->count > 0u) {
            const uint32_t *t = m->triangles + 3u * (size_t)bvh->order[n->first];
            for (k = 0; k < 3u; k++) c[k] = t[k];
            for (j = n->first + 1u; j < n->first + n->count; j++) {
                t = m->triangles + 3u * (size_t)bvh->order[j];
                for (k = 0; k < 3u; k++)
                    if (c[k] != LS_MESH_NONE && !holds(t, c[k])) c[k] = LS_MESH_NONE;
            }
        } else {
            const uint32_t *l = com + 3u * ((size_t)i + 1u), *r = com + 3u * (size_t)n->first;
            for (k = 0; k < 3u; k++) c[k] = l[k] != LS_MESH_NONE && holds(r, l[k]) ? l[k] : LS_MESH_NONE;
        }
    }
}

static void count_pair(uint32_t f, uint32_t g, uint32_t *flags, tangle_part *r)
{
    const uint32_t a = f < g ? f : g, b = f < g ? g : f;
    if (r->pairs == 0 || a < r->first[0] || (a == r->first[0] && b < r->first[1])) {
        r->first[0] = a;
        r->first[1] = b;
    }
    r->pairs++;
    flags[f / 32u] |= 1u << (f % 32u);
    flags[g / 32u] |= 1u << (g % 32u);
}

/* The search's shared arguments; a task is a block of faces. */
typedef struct tangle_job {
    const ls_mesh *m;
    const ls_bvh *bvh;
    const uint32_t *com;
    uint32_t *flags; /* [workers][words] */
    tangle_part *parts; /* [workers] */
    size_t words;
    ls_real slack;
    uint32_t blocks;
} tangle_job;

/* The pairs whose first contact is an edge of a face of [lo, hi): each pair
 * counted once, by the face of its first contact (first_contact). */
static void intersections(const tangle_job *j, uint32_t lo, uint32_t hi, uint32_t *flags, tangle_part *r)
{
    const ls_mesh *m = j->m;
    const ls_bvh *bvh = j->bvh;
    const ls_real slack = j->slack;
    uint32_t stack[LS_BVH_MAX_DEPTH + 2u];
    uint32_t f, k;
    for (f = lo; f < hi; f++) {
        const uint32_t *t = m->triangles + 3u * (size_t)f;
        for (k = 0; k < 3u; k++) {
            const uint32_t va = t[k], vb = t[(k + 1u) % 3u];
            ls_real elo[3], ehi[3];
            uint32_t sp = 1;
            edge_box(m, f, k, slack, elo, ehi);
            stack[0] = 0;
            while (sp > 0u) {
                const uint32_t i = stack[--sp];
                const ls_bvh_node *n = &bvh->nodes[i];
                const uint32_t *c = j->com + 3u * (size_t)i;
                uint32_t q;
                if (!boxes_overlap(n->lo, n->hi, elo, ehi) || holds(c, va) || holds(c, vb)) continue;
                if (n->count == 0u) {
                    if (sp + 2u > LS_BVH_MAX_DEPTH + 2u) return; /* not a tree of ls_bvh_build */
                    stack[sp++] = n->first;
                    stack[sp++] = i + 1u;
                    continue;
                }
                for (q = n->first; q < n->first + n->count; q++) {
                    const uint32_t g = bvh->order[q];
                    if (g == f || !edge_meets_box(m, va, vb, elo, ehi, g) || !first_contact(m, f, k, g, slack) ||
                        !pair_test(m, f, g))
                        continue;
                    count_pair(f, g, flags, r);
                }
            }
        }
    }
}

static void tangle_task(void *arg, uint32_t block, uint32_t worker)
{
    const tangle_job *j = (const tangle_job *)arg;
    const uint64_t fc = j->m->face_count;
    intersections(j, (uint32_t)(fc * block / j->blocks), (uint32_t)(fc * (block + 1u) / j->blocks),
                  j->flags + (size_t)worker * j->words, j->parts + worker);
}

/* The search over the workers, merged into r: counts added, the least first
 * pair, the face bits joined (the same report for any split). */
static void all_intersections(const ls_mesh *m, const ls_bvh *bvh, const uint32_t *com, uint32_t *flags,
                              tangle_part *parts, const ls_parallel *par, uint32_t workers, ls_tangle_report *r)
{
    const ls_bvh_node *root = &bvh->nodes[0];
    tangle_job job;
    ls_real big = 0;
    size_t w, i;
    uint32_t a;
    for (a = 0; a < 3u; a++) {
        if (LS_RFABS(root->lo[a]) > big) big = LS_RFABS(root->lo[a]);
        if (LS_RFABS(root->hi[a]) > big) big = LS_RFABS(root->hi[a]);
    }
    job.m = m;
    job.bvh = bvh;
    job.com = com;
    job.flags = flags;
    job.parts = parts;
    job.words = (size_t)m->face_count / 32u + 1u;
    /* above seg_tri's on-plane tolerance: 64 eps x a sum of at most 6 coordinates, over the
       cosine of the projection (>= 1/sqrt 3) */
    job.slack = (ls_real)2048 * LS_REAL_EPSILON * big;
    job.blocks = workers > 1u ? TANGLE_BLOCKS * workers : 1u;
    if (job.blocks > m->face_count) job.blocks = m->face_count;
    memset(flags, 0, (size_t)workers * job.words * sizeof(uint32_t));
    memset(parts, 0, (size_t)workers * sizeof(tangle_part));
    ls_parallel_run(par, workers, job.blocks, tangle_task, &job);
    for (w = 0; w < workers; w++) {
        const tangle_part *p = parts + w;
        if (p->pairs == 0u) continue;
        if (r->intersecting_pairs == 0u || p->first[0] < r->first_pair[0] ||
            (p->first[0] == r->first_pair[0] && p->first[1] < r->first_pair[1])) {
            r->first_pair[0] = p->first[0];
            r->first_pair[1] = p->first[1];
        }
        r->intersecting_pairs += p->pairs;
        if (w > 0u)
            for (i = 0; i < job.words; i++) flags[i] |= flags[w * job.words + i];
    }
    for (i = 0; i < job.words; i++) {
        uint32_t x = flags[i];
        while (x != 0) {
            x &= x - 1u;
            r->intersecting_faces++;
        }
    }
}

/* The report: the pairs, then (with `whole`) the shapes and the orientation.
 * Not inlined: the callgraph check names it as the caller of its tasks. */
LS_NOINLINE static ls_status tangle_report(const ls_mesh *mesh, const ls_mesh *reference, const ls_parallel *par,
                                           uint32_t workers, int whole, ls_arena *arena, ls_tangle_report *out,
                                           ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_tangle_report r;
    ls_bvh bvh;
    tangle_part *parts;
    uint32_t *flags, *com, *idx, *scratch, n3;
    uint64_t *keys;
    size_t bytes;
    ls_status st;
    if (mesh == NULL || arena == NULL || out == NULL || mesh->face_count == 0 || mesh->triangles == NULL ||
        mesh->positions == NULL ||
        (reference != NULL && (reference->face_count != mesh->face_count || reference->triangles == NULL ||
                               reference->positions == NULL))) {
        diag_set(diag, LS_ERR_INVALID,
                 mesh == NULL               ? "mesh is NULL"
                 : arena == NULL            ? "arena is NULL"
                 : out == NULL              ? "out is NULL"
                 : mesh->face_count == 0    ? "mesh->face_count: 0; at least one face"
                 : mesh->triangles == NULL  ? "mesh->triangles is NULL"
                 : mesh->positions == NULL  ? "mesh->positions is NULL"
                 : reference->face_count != mesh->face_count ? "reference->face_count: allowed = mesh->face_count"
                 : reference->triangles == NULL ? "reference->triangles is NULL"
                                                : "reference->positions is NULL",
                 0, 0);
        return LS_ERR_INVALID;
    }
    if (workers == 0u || workers > LS_TANGLE_MAX_WORKERS) {
        diag_set(diag, LS_ERR_INVALID, "workers: allowed 1 .. LS_TANGLE_MAX_WORKERS (1024)", 0, 0);
        return LS_ERR_INVALID;
    }
    st = ls_tangle_parallel_bytes(mesh->face_count, workers, &bytes);
    if (st == LS_OK) st = ls_bvh_check_mesh(mesh, diag);
    else diag_set(diag, st, "too many faces", 0, 0);
    if (st == LS_OK && reference != NULL) st = ls_bvh_check_mesh(reference, diag);
    if (st != LS_OK) return st;
    memset(&r, 0, sizeof r);
    r.face_count = mesh->face_count;
    r.first_pair[0] = r.first_pair[1] = LS_MESH_NONE;
    r.first_inverted = LS_MESH_NONE;
    r.has_reference = reference != NULL;
    mark = ls_arena_save(arena);
    st = ls_bvh_build(mesh, arena, &bvh, NULL);
    if (st != LS_OK) goto fail;
    flags = (uint32_t *)ls_arena_scratch(arena, (size_t)workers * (mesh->face_count / 32u + 1u), sizeof(uint32_t));
    parts = (tangle_part *)ls_arena_scratch(arena, workers, sizeof(tangle_part));
    com = (uint32_t *)ls_arena_scratch(arena, 3u * (size_t)bvh.node_count, sizeof(uint32_t));
    if (flags == NULL || parts == NULL || com == NULL) goto nomem;
    common_vertices(mesh, &bvh, com);
    all_intersections(mesh, &bvh, com, flags, parts, par, workers, &r);
    ls_arena_restore(arena, mark);
    if (!whole) {
        *out = r;
        return LS_OK;
    }
    n3 = 3u * mesh->face_count;
    keys = (uint64_t *)ls_arena_scratch(arena, n3, sizeof(uint64_t));
    idx = (uint32_t *)ls_arena_scratch(arena, n3, sizeof(uint32_t));
    scratch = (uint32_t *)ls_arena_scratch(arena, n3, sizeof(uint32_t));
    if (keys == NULL || idx == NULL || scratch == NULL) goto nomem;
    shapes(mesh, keys, idx, scratch, &r);
    orientation(mesh, reference, &r);
    ls_arena_restore(arena, mark);
    *out = r;
    return LS_OK;
nomem:
    st = LS_ERR_NOMEM;
fail:
    ls_arena_restore(arena, mark);
    diag_set(diag, st, "arena too small for the tangle metrics", 0, 0);
    return st;
}

ls_status ls_tangle_parallel(const ls_mesh *mesh, const ls_mesh *reference, const ls_parallel *par, uint32_t workers,
                             ls_arena *arena, ls_tangle_report *out, ls_diag *diag)
{
    return tangle_report(mesh, reference, par, workers, 1, arena, out, diag);
}

ls_status ls_tangle_pairs(const ls_mesh *mesh, const ls_parallel *par, uint32_t workers, ls_arena *arena,
                          ls_tangle_report *out, ls_diag *diag)
{
    return tangle_report(mesh, NULL, par, workers, 0, arena, out, diag);
}

ls_status ls_tangle(const ls_mesh *mesh, const ls_mesh *reference, ls_arena *arena, ls_tangle_report *out,
                    ls_diag *diag)
{
    return ls_tangle_parallel(mesh, reference, NULL, 1u, arena, out, diag);
}
