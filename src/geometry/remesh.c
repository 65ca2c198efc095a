/* remesh.c - isotropic remeshing (Botsch & Kobbelt 2004) on the half-edge
 * mesh, with projection onto the input through its BVH. */
#include <largesteps/remesh.h>
#include <largesteps/halfedge.h>
#include <largesteps/bvh.h>
#include <largesteps/tangle.h>
#include <largesteps/math.h>
#include <string.h>

#define NONE LS_HE_NONE

/* Keeps the frames of the phases apart (the per-function stack limit). */
#if defined(__GNUC__) || defined(__clang__)
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE
#endif
#define MAX_PASSES 10u
#define MAX_VERTEX_CAP 0x7fffffffu
#define RING_FACES 64u   /* a vertex with more faces than this is not moved by a checked operation */
#define CHECKED_MOVE 32u /* projection moves longer than h / CHECKED_MOVE are checked for intersections */

static void diag_set(ls_diag *diag, ls_status st, const char *what)
{
    (void)ls_diag_set(diag, st, what, LS_DIAG_NO_INDEX);
}

static void sub3(const ls_real *a, const ls_real *b, ls_real *out)
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

static void cross3(const ls_real *a, const ls_real *b, ls_real *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static ls_real dot3(const ls_real *a, const ls_real *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static ls_real dist2(const ls_real *a, const ls_real *b)
{
    ls_real d[3];
    sub3(a, b, d);
    return dot3(d, d);
}

/* Unnormalised normal (twice the area vector) of triangle (a, b, c). */
static void tri_normal(const ls_real *a, const ls_real *b, const ls_real *c, ls_real *n)
{
    ls_real u[3], v[3];
    sub3(b, a, u);
    sub3(c, a, v);
    cross3(u, v, n);
}

/* 1 when the angle between n0 and n1 is at most 60 degrees and n1 is not
 * degenerate (its squared length above eps * scale). */
static int normals_close(const ls_real *n0, const ls_real *n1, ls_real scale)
{
    ls_real d = dot3(n0, n1), l0 = dot3(n0, n0), l1 = dot3(n1, n1);
    if (!(l1 > LS_REAL_EPSILON * scale)) return 0;
    return d > 0 && d * d >= (ls_real)0.25 * l0 * l1;
}

/* Kahan summation. */
typedef struct ksum {
    ls_real s, c;
} ksum;

static void ksum_add(ksum *k, ls_real x)
{
    ls_real y = x - k->c, t = k->s + y;
    k->c = (t - k->s) - y;
    k->s = t;
}

void ls_remesh_params_default(ls_remesh_params *params, ls_real h)
{
    if (params == NULL) return;
    params->h = h;
    params->iterations = LS_REMESH_ITERATIONS;
    params->project = 1;
    params->vertex_cap = 0;
    params->sharp_angle = LS_REMESH_SHARP_ANGLE;
}

static int face_usable(const ls_mesh *mesh, uint32_t f)
{
    const uint32_t *t = mesh->triangles + 3u * (size_t)f;
    return t[0] < mesh->vertex_count && t[1] < mesh->vertex_count && t[2] < mesh->vertex_count;
}

ls_status ls_remesh_mean_edge(const ls_mesh *mesh, ls_real *mean)
{
    ksum k = {0, 0};
    uint32_t f, j, n = 0;
    if (mesh == NULL || mean == NULL || (mesh->face_count > 0 && (mesh->triangles == NULL || mesh->positions == NULL)))
        return LS_ERR_INVALID;
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *t = mesh->triangles + 3u * (size_t)f;
        if (!face_usable(mesh, f)) continue;
        for (j = 0; j < 3u; j++)
            ksum_add(&k, LS_RSQRT(dist2(mesh->positions + 3u * (size_t)t[j], mesh->positions + 3u * (size_t)t[(j + 1u) % 3u])));
        n++;
    }
    if (n == 0) return LS_ERR_MESH;
    *mean = k.s / ((ls_real)3 * (ls_real)n);
    return LS_OK;
}

static ls_real mesh_area(const ls_mesh *mesh)
{
    ksum k = {0, 0};
    uint32_t f;
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *t = mesh->triangles + 3u * (size_t)f;
        ls_real n[3];
        if (!face_usable(mesh, f)) continue;
        tri_normal(mesh->positions + 3u * (size_t)t[0], mesh->positions + 3u * (size_t)t[1],
                   mesh->positions + 3u * (size_t)t[2], n);
        ksum_add(&k, LS_RSQRT(dot3(n, n)) / 2);
    }
    return k.s;
}

/* ceil(x) as uint32_t, or UINT32_MAX when x is out of range or NaN. */
static uint32_t ceil_u32(ls_real x)
{
    if (!(x >= 0) || !(x < (ls_real)2147483648.0)) return UINT32_MAX;
    return LS_RTO_U32(LS_RCEIL(x));
}

ls_status ls_remesh_capacity(const ls_mesh *mesh, const ls_mesh_report *report, ls_real h, uint32_t *vertex_cap)
{
    ls_real area, mean = 0;
    uint32_t interior, boundary;
    uint64_t cap;
    if (mesh == NULL || report == NULL || vertex_cap == NULL || !(h > 0) || !LS_RISFINITE(h) ||
        (mesh->face_count > 0 && (mesh->triangles == NULL || mesh->positions == NULL)))
        return LS_ERR_INVALID;
    *vertex_cap = 0;
    area = mesh_area(mesh);
    if (ls_remesh_mean_edge(mesh, &mean) != LS_OK) mean = 0;
    interior = ceil_u32((ls_real)3 * (area / h) / h);
    boundary = ceil_u32((ls_real)2 * mean / h);
    if (interior == UINT32_MAX || boundary == UINT32_MAX) return LS_ERR_TOO_LARGE;
    cap = (uint64_t)mesh->vertex_count + interior + (uint64_t)report->boundary_edges * boundary + 16u;
    if (cap > MAX_VERTEX_CAP) return LS_ERR_TOO_LARGE;
    *vertex_cap = (uint32_t)cap;
    return LS_OK;
}

/* The sizes of the phases of ls_remesh, mirroring its allocations. */
typedef struct rm_sizes {
    size_t validate; /* validation scratch (first, released) */
    size_t he;       /* block for the half-edge build */
    size_t bvh;      /* block for the BVH build (0 without projection) */
    uint32_t vcap, ecap, fcap;
} rm_sizes;

static ls_status rm_sizes_get(const ls_mesh *mesh, const ls_mesh_report *report, const ls_remesh_params *p,
                              rm_sizes *z)
{
    ls_status st;
    memset(z, 0, sizeof *z);
    if (p->vertex_cap != 0) {
        z->vcap = p->vertex_cap;
    } else {
        st = ls_remesh_capacity(mesh, report, p->h, &z->vcap);
        if (st != LS_OK) return st;
    }
    if (z->vcap < mesh->vertex_count) return LS_ERR_INVALID;
    st = ls_he_capacity(z->vcap, report->euler, &z->ecap, &z->fcap);
    if (st != LS_OK) return st;
    st = ls_mesh_validate_bytes(mesh, &z->validate);
    if (st != LS_OK) return st;
    st = ls_he_build_bytes(mesh, z->vcap, report->euler, &z->he);
    if (st != LS_OK) return st;
    if (p->project) {
        st = ls_bvh_bytes(mesh->face_count, &z->bvh);
        if (st != LS_OK) return st;
    }
    return LS_OK;
}

/* The total: max(validation, blocks + work arrays + max(compaction, output),
 * output + its reordering). */
static ls_status rm_total(const rm_sizes *z, size_t *bytes)
{
    ls_size s, tail, out, first, last;
    size_t ob, rb;
    ls_status st;
    ls_size_init(&s);
    ls_size_add(&s, z->he, 1u);
    if (z->bvh > 0) ls_size_add(&s, z->bvh, 1u);
    ls_size_add(&s, (size_t)z->vcap, 3u * sizeof(ls_real)); /* normals */
    ls_size_add(&s, (size_t)z->vcap, 3u * sizeof(ls_real)); /* new positions */
    ls_size_add(&s, (size_t)z->vcap, sizeof(uint32_t));     /* valences */
    ls_size_add(&s, (size_t)z->vcap, 1u);                   /* locked flags */
    ls_size_init(&tail);
    ls_size_add(&tail, (size_t)z->vcap, sizeof(uint32_t)); /* compaction maps */
    ls_size_add(&tail, (size_t)z->ecap, sizeof(uint32_t));
    ls_size_add(&tail, (size_t)z->fcap, sizeof(uint32_t));
    st = ls_mesh_bytes(z->vcap, z->fcap, &ob);
    if (st != LS_OK) return st;
    ls_size_init(&out);
    out.bytes = ob;
    ls_size_max(&tail, &out);
    ls_size_add_size(&s, &tail);
    ls_size_init(&first);
    first.bytes = z->validate;
    ls_size_max(&s, &first);
    st = ls_mesh_reorder_bytes(z->vcap, z->fcap, &rb);
    if (st != LS_OK) return st;
    ls_size_init(&last);
    ls_size_add(&last, ob, 1u);
    ls_size_add(&last, rb, 1u);
    ls_size_max(&s, &last);
    return ls_size_get(&s, bytes);
}

ls_status ls_remesh_bytes_bound(const ls_mesh *mesh, const ls_mesh_report *report, const ls_remesh_params *params,
                                size_t *bytes)
{
    rm_sizes z;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (mesh == NULL || report == NULL || params == NULL || !(params->h > 0) || !LS_RISFINITE(params->h))
        return LS_ERR_INVALID;
    st = rm_sizes_get(mesh, report, params, &z);
    if (st != LS_OK) return st;
    return rm_total(&z, bytes);
}

/* ---- the iteration ------------------------------------------------------- */

typedef struct rm_ctx {
    ls_hemesh *he;
    const ls_bvh *bvh; /* NULL: no projection */
    ls_real h, hi2, lo2;
    ls_real *normals;
    ls_real *newpos;
    uint32_t *valence;
    unsigned char *locked; /* 1: a sharp vertex of the input, neither moved nor removed */
    ls_remesh_info *info;
} rm_ctx;

static const ls_real *pos(const ls_hemesh *he, uint32_t v) { return he->positions + 3u * (size_t)v; }

static ls_status split_pass(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t pass, e, m;
    for (pass = 0; pass < MAX_PASSES; pass++) {
        uint32_t n = 0, count = he->edge_count; /* edges made in this pass wait for the next */
        for (e = 0; e < count; e++) {
            uint32_t a = he->hto[2u * (size_t)e + 1u], b = he->hto[2u * (size_t)e];
            ls_real mid[3];
            ls_status st;
            if (b == NONE || dist2(pos(he, a), pos(he, b)) <= c->hi2) continue;
            mid[0] = (pos(he, a)[0] + pos(he, b)[0]) / 2;
            mid[1] = (pos(he, a)[1] + pos(he, b)[1]) / 2;
            mid[2] = (pos(he, a)[2] + pos(he, b)[2]) / 2;
            st = ls_he_split(he, e, mid, &m);
            if (st != LS_OK) return st;
            c->locked[m] = 0;
            n++;
        }
        c->info->splits += n;
        if (he->live_vertices > c->info->max_vertices) c->info->max_vertices = he->live_vertices;
        if (n == 0) break;
    }
    return LS_OK;
}

/* 1 when triangles fa and fb (vertex slots) intersect by ls_tangle_pair's
 * rules (shared slots are shared corners), with slot `moved` at p (NONE:
 * every vertex where it is). */
static NOINLINE int pair_meets(const ls_hemesh *he, const uint32_t *fa, const uint32_t *fb, uint32_t moved, const ls_real *p)
{
    ls_real lp[18];
    uint32_t ids[6] = {0, 0, 0, 0, 0, 0}, lt[6], n = 0, i;
    ls_mesh m;
    for (i = 0; i < 6u; i++) {
        uint32_t v = i < 3u ? fa[i] : fb[i - 3u], j = 0;
        while (j < n && ids[j] != v) j++;
        if (j == n) {
            const ls_real *src = v == moved && p != NULL ? p : pos(he, v);
            memcpy(lp + 3u * (size_t)n, src, 3u * sizeof(ls_real));
            ids[n++] = v;
        }
        lt[i] = j;
    }
    m.positions = lp;
    m.triangles = lt;
    m.vertex_count = n;
    m.face_count = 2;
    return ls_tangle_pair(&m, 0, 1);
}

/* 1 when triangle t (vertex slots, slot `moved` at p) intersects a face
 * around one of its corners other than `moved` that the operation on x and
 * y keeps: for a collapse (both = 0) one with neither x nor y, for a flip
 * (both = 1) one without both. The local guard of
 * collapses and flips: a move that folds the surface through its
 * neighbourhood is rejected. A corner with more than a bounded number of
 * faces counts as a hit (rejected, conservatively). */
static int tri_hits_ring(const ls_hemesh *he, const uint32_t *t, uint32_t moved, const ls_real *p, uint32_t x,
                         uint32_t y, int both)
{
    uint32_t j;
    for (j = 0; j < 3u; j++) {
        uint32_t start = he->vout[t[j]], k = start, guard = RING_FACES;
        if (t[j] == moved) continue;
        do {
            if (he->hface[k] != NONE) {
                uint32_t g[3];
                g[0] = t[j];
                g[1] = he->hto[k];
                g[2] = he->hto[he->hnext[k]];
                int hx = g[0] == x || g[1] == x || g[2] == x, hy = g[0] == y || g[1] == y || g[2] == y;
                if ((both ? !(hx && hy) : !hx && !hy) && pair_meets(he, t, g, moved, p)) return 1;
            }
            k = he->hnext[k ^ 1u];
        } while (k != start && --guard > 0);
        if (guard == 0) return 1;
    }
    return 0;
}

/* The faces around a and b after collapsing a into b with b at p (those
 * that survive: without both ends) against their neighbourhoods. */
static int collapse_clear(const ls_hemesh *he, uint32_t a, uint32_t b, const ls_real *p)
{
    uint32_t side;
    for (side = 0; side < (a == b ? 1u : 2u); side++) {
        uint32_t v = side == 0 ? a : b, start = he->vout[v], k = start, guard = RING_FACES;
        do {
            if (he->hface[k] != NONE) {
                uint32_t t[3];
                t[0] = b;
                t[1] = he->hto[k];
                t[2] = he->hto[he->hnext[k]];
                if (t[1] != a && t[1] != b && t[2] != a && t[2] != b && tri_hits_ring(he, t, b, p, a, b, 0)) return 0;
            }
            k = he->hnext[k ^ 1u];
        } while (k != start && --guard > 0);
        if (guard == 0) return 0;
    }
    return 1;
}

/* Checks the faces and edges around vertex v (an end of the collapsing edge
 * a-b) when v moves to p: no edge to a neighbour other than a, b longer than
 * 4/3 h, no face that keeps its area (one without both a and b) turning by
 * more than 60 degrees or becoming degenerate. */
static int ring_ok(const rm_ctx *c, uint32_t v, uint32_t a, uint32_t b, const ls_real *p)
{
    const ls_hemesh *he = c->he;
    uint32_t x = he->vout[v], start = x, guard = 2u * he->edge_count + 1u;
    const ls_real *pv = pos(he, v);
    do {
        uint32_t w = he->hto[x];
        if (w != a && w != b) {
            if (dist2(pos(he, w), p) > c->hi2) return 0;
            if (he->hface[x] != NONE) {
                uint32_t w2 = he->hto[he->hnext[x]];
                if (w2 != a && w2 != b) {
                    ls_real n0[3], n1[3], scale;
                    tri_normal(pv, pos(he, w), pos(he, w2), n0);
                    tri_normal(p, pos(he, w), pos(he, w2), n1);
                    scale = dist2(pos(he, w), p) * dist2(pos(he, w2), p);
                    if (!normals_close(n0, n1, scale)) return 0;
                }
            }
        }
        x = he->hnext[x ^ 1u];
    } while (x != start && --guard > 0);
    return 1;
}

/* Collapses h (its origin a into its target b) if allowed: b moves to the
 * midpoint when both ends are interior, else stays. */
static int try_collapse(rm_ctx *c, uint32_t h)
{
    ls_hemesh *he = c->he;
    uint32_t a = he->hto[h ^ 1u], b = he->hto[h];
    ls_real p[3];
    int mid = !ls_he_is_boundary(he, a) && !ls_he_is_boundary(he, b) && !c->locked[b];
    const ls_real *pa = pos(he, a), *pb = pos(he, b);
    if (mid) {
        p[0] = (pa[0] + pb[0]) / 2;
        p[1] = (pa[1] + pb[1]) / 2;
        p[2] = (pa[2] + pb[2]) / 2;
    } else {
        p[0] = pb[0];
        p[1] = pb[1];
        p[2] = pb[2];
    }
    if (!ls_he_collapse_ok(he, h) || !ring_ok(c, a, a, b, p)) return 0;
    if (mid && !ring_ok(c, b, a, b, p)) return 0;
    if (!collapse_clear(he, a, b, p)) return 0;
    if (ls_he_collapse(he, h) != LS_OK) return 0;
    he->positions[3u * (size_t)b] = p[0];
    he->positions[3u * (size_t)b + 1u] = p[1];
    he->positions[3u * (size_t)b + 2u] = p[2];
    return 1;
}

static void collapse_pass(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t pass, e;
    for (pass = 0; pass < MAX_PASSES; pass++) {
        uint32_t n = 0;
        for (e = 0; e < he->edge_count; e++) {
            uint32_t h = 2u * e, a = he->hto[h + 1u], b = he->hto[h], first, second;
            int ba, bb, ok_a, ok_b;
            if (b == NONE || dist2(pos(he, a), pos(he, b)) >= c->lo2) continue;
            ba = ls_he_is_boundary(he, a);
            bb = ls_he_is_boundary(he, b);
            /* a may be removed into b: a boundary vertex only into a boundary
             * vertex, a locked one only into a locked one */
            ok_a = (!ba || bb) && (!c->locked[a] || c->locked[b]);
            ok_b = (!bb || ba) && (!c->locked[b] || c->locked[a]);
            if (!ok_a && !ok_b) continue;
            /* remove the vertex with fewer edges (a on ties) */
            if (ok_a && ok_b && ls_he_valence(he, a) > ls_he_valence(he, b)) {
                first = h + 1u;
                second = h;
            } else {
                first = ok_a ? h : h + 1u;
                second = ok_a && ok_b ? h + 1u : NONE;
            }
            if ((first == h ? ok_a : ok_b) && try_collapse(c, first)) {
                n++;
                continue;
            }
            if (second != NONE && try_collapse(c, second)) n++;
        }
        c->info->collapses += n;
        if (n == 0) break;
    }
}

static int target_valence(const ls_hemesh *he, uint32_t v) { return ls_he_is_boundary(he, v) ? 4 : 6; }

static int sq(int x) { return x * x; }

/* The new faces (d, c, a) and (c, d, b) against the old (a, b, c), (b, a, d). */
static int flip_geom_ok(const ls_hemesh *he, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    ls_real o0[3], o1[3], n0[3], n1[3], s0, s1;
    tri_normal(pos(he, a), pos(he, b), pos(he, c), o0);
    tri_normal(pos(he, b), pos(he, a), pos(he, d), o1);
    tri_normal(pos(he, d), pos(he, c), pos(he, a), n0);
    tri_normal(pos(he, c), pos(he, d), pos(he, b), n1);
    s0 = dist2(pos(he, c), pos(he, d)) * dist2(pos(he, a), pos(he, d));
    s1 = dist2(pos(he, c), pos(he, d)) * dist2(pos(he, b), pos(he, d));
    return normals_close(o0, n0, s0) && normals_close(o1, n0, s0) && normals_close(o0, n1, s1) &&
           normals_close(o1, n1, s1);
}

/* The new faces (d, c, a) and (c, d, b) against the faces around their
 * corners (other than the two they replace). */
static int flip_clear(const ls_hemesh *he, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    uint32_t t0[3], t1[3];
    t0[0] = d;
    t0[1] = c;
    t0[2] = a;
    t1[0] = c;
    t1[1] = d;
    t1[2] = b;
    return !tri_hits_ring(he, t0, NONE, NULL, a, b, 1) && !tri_hits_ring(he, t1, NONE, NULL, a, b, 1);
}

static void flip_pass(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t pass, e, v;
    for (v = 0; v < he->vertex_count; v++) c->valence[v] = ls_he_valence(he, v);
    for (pass = 0; pass < MAX_PASSES; pass++) {
        uint32_t n = 0;
        for (e = 0; e < he->edge_count; e++) {
            uint32_t h = 2u * e, a, b, cc, d;
            int ta, tb, tc, td, va, vb, vc, vd, before, after;
            if (he->hto[h] == NONE || he->hface[h] == NONE || he->hface[h + 1u] == NONE) continue;
            a = he->hto[h + 1u];
            b = he->hto[h];
            cc = he->hto[he->hnext[h]];
            d = he->hto[he->hnext[h + 1u]];
            ta = target_valence(he, a);
            tb = target_valence(he, b);
            tc = target_valence(he, cc);
            td = target_valence(he, d);
            va = (int)c->valence[a];
            vb = (int)c->valence[b];
            vc = (int)c->valence[cc];
            vd = (int)c->valence[d];
            before = sq(va - ta) + sq(vb - tb) + sq(vc - tc) + sq(vd - td);
            after = sq(va - 1 - ta) + sq(vb - 1 - tb) + sq(vc + 1 - tc) + sq(vd + 1 - td);
            if (after >= before || !ls_he_flip_ok(he, e) || !flip_geom_ok(he, a, b, cc, d) || !flip_clear(he, a, b, cc, d))
                continue;
            if (ls_he_flip(he, e) != LS_OK) continue;
            c->valence[a]--;
            c->valence[b]--;
            c->valence[cc]++;
            c->valence[d]++;
            n++;
        }
        c->info->flips += n;
        if (n == 0) break;
    }
}

/* A live face's corners in its winding order; 0 for a removed face. */
static int face_corners(const ls_hemesh *he, uint32_t f, uint32_t t[3])
{
    uint32_t h = he->fedge[f];
    if (h == NONE) return 0;
    t[0] = he->hto[h ^ 1u];
    t[1] = he->hto[h];
    t[2] = he->hto[he->hnext[h]];
    return 1;
}

/* Area-weighted vertex normals, accumulated in face order. */
static void vertex_normals(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t v, f, j;
    for (v = 0; v < 3u * he->vertex_count; v++) c->normals[v] = 0;
    for (f = 0; f < he->face_count; f++) {
        uint32_t t[3];
        ls_real n[3];
        if (!face_corners(he, f, t)) continue;
        tri_normal(pos(he, t[0]), pos(he, t[1]), pos(he, t[2]), n);
        for (j = 0; j < 3u; j++) {
            c->normals[3u * (size_t)t[j]] += n[0];
            c->normals[3u * (size_t)t[j] + 1u] += n[1];
            c->normals[3u * (size_t)t[j] + 2u] += n[2];
        }
    }
}

/* The centroid of a ring that is not star-shaped from it (slivers split
 * along their length) lies outside the ring, and moving there folds a face
 * over its neighbours; two neighbours moving at once can fold one too. So
 * every face is checked with the moves applied: a face that faced the way
 * its corners' normals (summed) do must still face that way and not become
 * degenerate, else its corners stay where they are, until no face fails
 * (each round only keeps more vertices in place). A face already turned
 * against its corners (a spike through the surface) may turn back. Where no
 * move folds, the moves are unchanged. */
static void keep_unfolded(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t v, f, k, changed = 1, rounds = 0;
    for (v = 0; v < he->vertex_count; v++) {
        uint32_t x = he->vout[v];
        if (x == NONE || he->hface[x] == NONE || c->locked[v])
            for (k = 0; k < 3u; k++) c->newpos[3u * (size_t)v + k] = pos(he, v)[k];
    }
    while (changed && rounds++ < he->vertex_count + 1u) {
        changed = 0;
        for (f = 0; f < he->face_count; f++) {
            uint32_t t[3], j;
            const ls_real *q[3];
            ls_real n0[3], n1[3], r[3];
            int moved = 0;
            if (!face_corners(he, f, t)) continue;
            for (j = 0; j < 3u; j++) {
                q[j] = c->newpos + 3u * (size_t)t[j];
                moved |= q[j][0] != pos(he, t[j])[0] || q[j][1] != pos(he, t[j])[1] || q[j][2] != pos(he, t[j])[2];
            }
            if (!moved) continue;
            tri_normal(pos(he, t[0]), pos(he, t[1]), pos(he, t[2]), n0);
            tri_normal(q[0], q[1], q[2], n1);
            for (k = 0; k < 3u; k++)
                r[k] = (c->normals[3u * (size_t)t[0] + k] + c->normals[3u * (size_t)t[1] + k]) +
                       c->normals[3u * (size_t)t[2] + k];
            if (!(dot3(n0, r) > 0) || (dot3(n1, r) > 0 && dot3(n1, n1) > LS_REAL_EPSILON * dist2(q[0], q[1]) * dist2(q[0], q[2])))
                continue;
            for (j = 0; j < 3u; j++)
                for (k = 0; k < 3u; k++) c->newpos[3u * (size_t)t[j] + k] = pos(he, t[j])[k];
            changed = 1;
        }
    }
}

static void relax(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t v, k;
    vertex_normals(c);
    for (v = 0; v < he->vertex_count; v++) {
        uint32_t x = he->vout[v], start = x, guard = 2u * he->edge_count + 1u, cnt = 0;
        ls_real q[3] = {0, 0, 0}, d[3], *nv = c->normals + 3u * (size_t)v, l2, t;
        const ls_real *p = pos(he, v);
        if (x == NONE || he->hface[x] == NONE || c->locked[v]) continue; /* dead, boundary or locked */
        do {
            const ls_real *w = pos(he, he->hto[x]);
            q[0] += w[0];
            q[1] += w[1];
            q[2] += w[2];
            cnt++;
            x = he->hnext[x ^ 1u];
        } while (x != start && --guard > 0);
        for (k = 0; k < 3u; k++) d[k] = q[k] / (ls_real)cnt - p[k];
        l2 = dot3(nv, nv);
        t = l2 > 0 ? dot3(d, nv) / l2 : 0;
        for (k = 0; k < 3u; k++) c->newpos[3u * (size_t)v + k] = p[k] + (d[k] - t * nv[k]);
    }
    keep_unfolded(c);
    for (v = 0; v < he->vertex_count; v++) {
        uint32_t x = he->vout[v];
        if (x == NONE || he->hface[x] == NONE || c->locked[v]) continue;
        for (k = 0; k < 3u; k++) he->positions[3u * (size_t)v + k] = c->newpos[3u * (size_t)v + k];
    }
}

/* The unnormalised normal of face f of the BVH's mesh. */
static void input_normal(const ls_bvh *bvh, uint32_t f, ls_real *n)
{
    const uint32_t *t = bvh->triangles + 3u * (size_t)f;
    tri_normal(bvh->positions + 3u * (size_t)t[0], bvh->positions + 3u * (size_t)t[1],
               bvh->positions + 3u * (size_t)t[2], n);
}

/* The closest point to p of the input faces that face the same way as n
 * (positive dot product), searched within distance r: 1 and *hit, or 0 when
 * there is none. Ties go to the lowest face index. */
static int closest_facing(const ls_bvh *bvh, const ls_real *p, const ls_real *n, ls_real r, ls_bvh_hit *hit)
{
    ls_bvh_overlap it;
    ls_real lo[3], hi[3], r2 = r * r;
    uint32_t f, k;
    int found = 0;
    for (k = 0; k < 3u; k++) {
        lo[k] = p[k] - r;
        hi[k] = p[k] + r;
    }
    if (ls_bvh_overlap_begin(bvh, lo, hi, &it) != LS_OK) return 0;
    while (ls_bvh_overlap_next(&it, &f)) {
        const uint32_t *t = bvh->triangles + 3u * (size_t)f;
        ls_real nf[3], q[3], b[3], d2;
        input_normal(bvh, f, nf);
        if (!(dot3(nf, n) > 0)) continue;
        ls_closest_point_triangle(p, bvh->positions + 3u * (size_t)t[0], bvh->positions + 3u * (size_t)t[1],
                                  bvh->positions + 3u * (size_t)t[2], q, b, &d2);
        if (!(d2 <= r2) || (found && (d2 > hit->dist2 || (d2 == hit->dist2 && f > hit->face)))) continue;
        memcpy(hit->point, q, sizeof q);
        memcpy(hit->bary, b, sizeof b);
        hit->dist2 = d2;
        hit->face = f;
        found = 1;
    }
    return found;
}

/* Moves every interior, unlocked vertex to the closest point of the input
 * surface among the input faces that face the way the vertex's normal does.
 * The plain closest point is used when its face agrees; otherwise (a thin
 * part whose other side is nearer, e.g. a finger thinner than h) the
 * nearest agreeing face within that distance plus h, and the vertex stays
 * where it is when there is none: snapping to the far side of a thin part
 * would fold the mesh through it. A move longer than h / CHECKED_MOVE is
 * also skipped when the vertex's faces would then meet a face around their
 * other corners (collapse_clear). Shorter ones are not checked, for time:
 * checking every move doubles the armadillo's remesh; with h / 8 the bunny
 * at h = 1/2 mean edge still got 5 intersecting pairs from a projection
 * (removed by the next iteration), with h / 32 none. */
static NOINLINE ls_status project(rm_ctx *c)
{
    ls_hemesh *he = c->he;
    uint32_t v;
    vertex_normals(c);
    for (v = 0; v < he->vertex_count; v++) {
        uint32_t x = he->vout[v];
        const ls_real *nv = c->normals + 3u * (size_t)v;
        ls_bvh_hit hit;
        ls_real nf[3];
        ls_status st;
        if (x == NONE || he->hface[x] == NONE || c->locked[v]) continue;
        st = ls_bvh_closest(c->bvh, pos(he, v), LS_REAL_MAX, &hit);
        if (st != LS_OK) return st;
        if (hit.face == UINT32_MAX) continue;
        input_normal(c->bvh, hit.face, nf);
        if (!(dot3(nf, nv) > 0) && !closest_facing(c->bvh, pos(he, v), nv, LS_RSQRT(hit.dist2) + c->h, &hit)) continue;
        if (dist2(hit.point, pos(he, v)) > c->h * c->h / (ls_real)(CHECKED_MOVE * CHECKED_MOVE) &&
            !collapse_clear(he, v, v, hit.point))
            continue;
        he->positions[3u * (size_t)v] = hit.point[0];
        he->positions[3u * (size_t)v + 1u] = hit.point[1];
        he->positions[3u * (size_t)v + 2u] = hit.point[2];
    }
    return LS_OK;
}

/* Compacts the mesh and the locked flags alike (live vertices keep their order). */
static ls_status compact(rm_ctx *c, ls_arena *arena)
{
    ls_hemesh *he = c->he;
    uint32_t v, n = 0;
    /* if the compaction fails, the whole remesh fails: the flags may go first */
    for (v = 0; v < he->vertex_count; v++)
        if (he->vout[v] != NONE) c->locked[n++] = c->locked[v];
    return ls_he_compact(he, arena);
}

/* Marks the sharp vertices: two incident faces whose unit normals' dot
 * product is below cos_limit. */
static void mark_sharp(rm_ctx *c, ls_real cos_limit)
{
    ls_hemesh *he = c->he;
    uint32_t v;
    for (v = 0; v < he->vertex_count; v++) {
        uint32_t x = he->vout[v], start = x, guard = 2u * he->edge_count + 1u;
        c->locked[v] = 0;
        if (x == NONE || he->hface[x] == NONE || !(cos_limit >= -1)) continue;
        do {
            uint32_t y = he->hnext[x ^ 1u], guard2 = 2u * he->edge_count + 1u;
            ls_real n0[3], l0;
            tri_normal(pos(he, v), pos(he, he->hto[x]), pos(he, he->hto[he->hnext[x]]), n0);
            l0 = LS_RSQRT(dot3(n0, n0));
            while (y != start && --guard2 > 0 && !c->locked[v]) {
                ls_real n1[3], l1;
                tri_normal(pos(he, v), pos(he, he->hto[y]), pos(he, he->hto[he->hnext[y]]), n1);
                l1 = LS_RSQRT(dot3(n1, n1));
                if (l0 > 0 && l1 > 0 && dot3(n0, n1) < cos_limit * l0 * l1) c->locked[v] = 1;
                y = he->hnext[y ^ 1u];
            }
            x = he->hnext[x ^ 1u];
        } while (x != start && --guard > 0 && !c->locked[v]);
    }
}

/* A sub-arena over a scratch block of `bytes` from the top of `arena`. */
static int sub_arena(ls_arena *arena, size_t bytes, ls_arena *sub)
{
    void *block = ls_arena_scratch(arena, bytes, 1u);
    if (block == NULL) return 0;
    return ls_arena_init(sub, block, bytes) == LS_OK;
}

static NOINLINE ls_status rm_run(rm_ctx *c, const ls_remesh_params *p, ls_arena *arena, ls_diag *diag)
{
    uint32_t it;
    for (it = 0; it < p->iterations; it++) {
        ls_status st = split_pass(c);
        if (st != LS_OK) {
            diag_set(diag, st, st == LS_ERR_NOMEM ? "remesh vertex capacity exceeded" : "split failed");
            return st;
        }
        collapse_pass(c);
        st = compact(c, arena);
        if (st != LS_OK) {
            diag_set(diag, st, "arena too small");
            return st;
        }
        flip_pass(c);
        relax(c);
        if (c->bvh != NULL) {
            st = project(c);
            if (st != LS_OK) {
                diag_set(diag, st, "projection failed (non-finite position)");
                return st;
            }
        }
    }
    return LS_OK;
}

static int zero_area_face(const ls_mesh *m)
{
    uint32_t f;
    for (f = 0; f < m->face_count; f++) {
        const uint32_t *t = m->triangles + 3u * (size_t)f;
        ls_real n[3];
        tri_normal(m->positions + 3u * (size_t)t[0], m->positions + 3u * (size_t)t[1],
                   m->positions + 3u * (size_t)t[2], n);
        if (n[0] == 0 && n[1] == 0 && n[2] == 0) return 1;
    }
    return 0;
}

/* Validation (scratch, released) and the sizes of the run; its own frame
 * keeps the report off ls_remesh's stack. */
static ls_status rm_prepare(const ls_mesh *in, const ls_remesh_params *params, ls_arena *arena, rm_sizes *z,
                            ls_diag *diag)
{
    ls_mesh_report rep;
    ls_status st = ls_mesh_validate(in, arena, &rep);
    if (st != LS_OK) {
        diag_set(diag, st, st == LS_ERR_NOMEM ? "arena too small" : "mesh cannot be validated");
        return st;
    }
    st = ls_mesh_require(&rep, LS_MESH_REQ_INDICES | LS_MESH_REQ_FINITE | LS_MESH_REQ_NONEMPTY, diag);
    if (st != LS_OK) return st;
    st = rm_sizes_get(in, &rep, params, z);
    if (st != LS_OK)
        diag_set(diag, st,
                 st != LS_ERR_INVALID       ? "mesh too large"
                 : params->vertex_cap != 0u ? "params->vertex_cap: allowed 0 or >= in->vertex_count"
                                            : "params->vertex_cap: 0 sizes below in->vertex_count for this h; pass one");
    return st;
}

ls_status ls_remesh(const ls_mesh *in, const ls_remesh_params *params, ls_arena *arena, ls_mesh *out,
                    ls_remesh_info *info, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_arena sub; /* the builds' own arenas over scratch blocks; the objects outlive it */
    ls_remesh_info inf;
    ls_hemesh he;
    ls_bvh bvh;
    ls_mesh res;
    rm_sizes z;
    rm_ctx c;
    size_t entry_used, old_peak;
    ls_status st;
    if (in == NULL || params == NULL || arena == NULL || out == NULL || !(params->h > 0) ||
        !LS_RISFINITE(params->h) || params->iterations == 0 || params->project > 1u ||
        !(params->sharp_angle >= 0)) {
        diag_set(diag, LS_ERR_INVALID,
                 in == NULL                     ? "in is NULL"
                 : params == NULL               ? "params is NULL"
                 : arena == NULL                ? "arena is NULL"
                 : out == NULL                  ? "out is NULL"
                 : !(params->h > 0) || !LS_RISFINITE(params->h) ? "params->h: allowed finite and > 0"
                 : params->iterations == 0      ? "params->iterations: allowed >= 1"
                 : params->project > 1u         ? "params->project: allowed 0 or 1"
                                                : "params->sharp_angle: allowed >= 0 degrees");
        return LS_ERR_INVALID;
    }
    mark = ls_arena_save(arena);
    entry_used = ls_arena_used(arena);
    old_peak = arena->peak;
    ls_arena_reset_peak(arena);
    memset(&inf, 0, sizeof inf);
    st = rm_prepare(in, params, arena, &z, diag);
    if (st != LS_OK) goto fail;
    inf.vertex_cap = z.vcap;
    if (!sub_arena(arena, z.he, &sub)) {
        st = LS_ERR_NOMEM;
        diag_set(diag, st, "arena too small");
        goto fail;
    }
    st = ls_he_build(in, z.vcap, &sub, &he, NULL, diag);
    if (st != LS_OK) goto fail;
    memset(&c, 0, sizeof c);
    if (params->project) {
        if (!sub_arena(arena, z.bvh, &sub)) {
            st = LS_ERR_NOMEM;
            diag_set(diag, st, "arena too small");
            goto fail;
        }
        st = ls_bvh_build(in, &sub, &bvh, diag);
        if (st != LS_OK) goto fail;
        c.bvh = &bvh;
    }
    c.he = &he;
    c.h = params->h;
    c.hi2 = params->h * params->h * (ls_real)16 / (ls_real)9;
    c.lo2 = params->h * params->h * (ls_real)16 / (ls_real)25;
    c.info = &inf;
    inf.max_vertices = he.live_vertices;
    c.normals = (ls_real *)ls_arena_scratch(arena, (size_t)z.vcap, 3u * sizeof(ls_real));
    c.newpos = (ls_real *)ls_arena_scratch(arena, (size_t)z.vcap, 3u * sizeof(ls_real));
    c.valence = (uint32_t *)ls_arena_scratch(arena, (size_t)z.vcap, sizeof(uint32_t));
    c.locked = (unsigned char *)ls_arena_scratch(arena, (size_t)z.vcap, 1u);
    if (c.normals == NULL || c.newpos == NULL || c.valence == NULL || c.locked == NULL) {
        st = LS_ERR_NOMEM;
        diag_set(diag, st, "arena too small");
        goto fail;
    }
    if (params->sharp_angle < 180) mark_sharp(&c, LS_RCOS(params->sharp_angle * ((ls_real)3.14159265358979323846 / 180)));
    else mark_sharp(&c, (ls_real)-2);
    st = rm_run(&c, params, arena, diag);
    if (st != LS_OK) goto fail;
    st = compact(&c, arena);
    if (st == LS_OK) st = ls_he_to_mesh(&he, arena, &res);
    if (st != LS_OK) {
        diag_set(diag, st, st == LS_ERR_NOMEM ? "arena too small" : "half-edge mesh corrupted");
        goto fail;
    }
    if (zero_area_face(&res)) {
        st = LS_ERR_MESH;
        diag_set(diag, st, "remesh produced a zero-area face");
        goto fail;
    }
    {
        /* keep the output at the bottom, release every scratch block */
        ls_arena_mark keep;
        keep.bottom = arena->bottom;
        keep.top = mark.top;
        ls_arena_restore(arena, keep);
    }
    /* the output in spatial order: the renderer's passes read it in order */
    st = ls_mesh_reorder(&res, arena, NULL);
    if (st != LS_OK) {
        diag_set(diag, st, "arena too small");
        goto fail;
    }
    inf.bytes_used = arena->peak - entry_used;
    if (arena->peak < old_peak) arena->peak = old_peak;
    *out = res;
    if (info != NULL) *info = inf;
    return LS_OK;
fail:
    ls_arena_restore(arena, mark);
    if (arena->peak < old_peak) arena->peak = old_peak;
    return st;
}
