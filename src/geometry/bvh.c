/* bvh.c - a bounding-volume hierarchy over triangles: deterministic median
 * build without recursion, closest-point and box-overlap queries with a
 * fixed stack. See largesteps/bvh.h. */
#include <largesteps/bvh.h>
#include <largesteps/math.h>
#include <string.h>

#define NONE 0xffffffffu
#define STACK_CAP (LS_BVH_MAX_DEPTH + 2u)

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index, int has_index)
{
    (void)ls_diag_set(diag, st, what, has_index ? index : LS_DIAG_NO_INDEX);
}

/* Number of nodes of the tree over n triangles: every node of more than
 * LS_BVH_LEAF triangles splits into floor(n/2) and ceil(n/2). The sizes of one
 * level take at most two adjacent values, so a level is (size, count) twice. */
static uint64_t node_count_of(uint32_t n, uint32_t *depth)
{
    uint64_t total = 0, cnt[2];
    uint32_t s = n, levels = 0, k;
    cnt[0] = 1;
    cnt[1] = 0;
    while (cnt[0] + cnt[1] > 0) {
        uint64_t next[2];
        uint32_t base = s / 2u;
        total += cnt[0] + cnt[1];
        levels++;
        next[0] = next[1] = 0;
        for (k = 0; k < 2u; k++) {
            uint32_t x = s + k, h1 = x / 2u;
            if (cnt[k] == 0 || x <= LS_BVH_LEAF) continue;
            next[h1 - base] += cnt[k];
            next[(x - h1) - base] += cnt[k];
        }
        s = base;
        cnt[0] = next[0];
        cnt[1] = next[1];
    }
    if (depth != NULL) *depth = levels;
    return total;
}

/* One build work item: the triangles order[start .. start+count), and the
 * node whose `first` field must receive this item's node index (NONE for the
 * root and for first children, which follow their parent). */
typedef struct work_item {
    uint32_t start;
    uint32_t count;
    uint32_t parent;
    uint32_t level;
} work_item;

static void build_size(ls_size *s, uint32_t face_count, uint32_t nodes, int scratch)
{
    ls_size_add(s, nodes, sizeof(ls_bvh_node));
    ls_size_add(s, face_count, sizeof(uint32_t));
    if (!scratch) return;
    ls_size_add(s, (size_t)face_count * 3u, sizeof(ls_real)); /* centroids (scratch) */
    ls_size_add(s, STACK_CAP, sizeof(work_item));             /* work list (scratch) */
}

static ls_status bvh_size(uint32_t face_count, size_t *bytes, int scratch)
{
    ls_size s;
    uint64_t nodes;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (face_count == 0) return LS_ERR_INVALID;
    nodes = node_count_of(face_count, NULL);
    if (nodes > (uint64_t)UINT32_MAX) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    build_size(&s, face_count, (uint32_t)nodes, scratch);
    return ls_size_get(&s, bytes);
}

uint32_t ls_bvh_node_count(uint32_t face_count)
{
    uint64_t nodes;
    if (face_count == 0) return 0;
    nodes = node_count_of(face_count, NULL);
    return nodes > (uint64_t)UINT32_MAX ? 0u : (uint32_t)nodes;
}

ls_status ls_bvh_bytes(uint32_t face_count, size_t *bytes)
{
    return bvh_size(face_count, bytes, 1);
}

ls_status ls_bvh_tree_bytes(uint32_t face_count, size_t *bytes)
{
    return bvh_size(face_count, bytes, 0);
}

/* a < b in the order (centroid coordinate, triangle index). */
static int cent_less(const ls_real *cent, uint32_t axis, uint32_t a, uint32_t b)
{
    ls_real ka = cent[3u * a + axis], kb = cent[3u * b + axis];
    if (ka < kb) return 1;
    if (kb < ka) return 0;
    return a < b;
}

/* Rearranges idx[0..n) so that idx[k] is the element of rank k in the
 * (centroid, index) order, smaller ones before it and larger ones after it.
 * Iterative quickselect with a median-of-three pivot: a fixed sequence of
 * operations on a total order, hence the same result everywhere. */
static void select_kth(uint32_t *idx, uint32_t n, uint32_t k, const ls_real *cent, uint32_t axis)
{
    uint32_t lo = 0, hi = n - 1u;
    while (hi > lo) {
        uint32_t mid = lo + (hi - lo) / 2u, i, j, t, pivot;
        /* median of three into idx[mid], then to idx[hi] */
        if (cent_less(cent, axis, idx[mid], idx[lo])) { t = idx[mid]; idx[mid] = idx[lo]; idx[lo] = t; }
        if (cent_less(cent, axis, idx[hi], idx[lo])) { t = idx[hi]; idx[hi] = idx[lo]; idx[lo] = t; }
        if (cent_less(cent, axis, idx[hi], idx[mid])) { t = idx[hi]; idx[hi] = idx[mid]; idx[mid] = t; }
        t = idx[mid]; idx[mid] = idx[hi]; idx[hi] = t;
        pivot = idx[hi];
        j = lo;
        for (i = lo; i < hi; i++) {
            if (cent_less(cent, axis, idx[i], pivot)) {
                t = idx[i]; idx[i] = idx[j]; idx[j] = t;
                j++;
            }
        }
        t = idx[j]; idx[j] = idx[hi]; idx[hi] = t;
        if (j == k) return;
        if (k < j) hi = j - 1u;
        else lo = j + 1u;
    }
}

static void box_of(const ls_bvh *bvh, uint32_t start, uint32_t count, ls_bvh_node *node)
{
    uint32_t i, c, a;
    for (a = 0; a < 3u; a++) {
        node->lo[a] = bvh->positions[3u * (size_t)bvh->triangles[3u * (size_t)bvh->order[start]] + a];
        node->hi[a] = node->lo[a];
    }
    for (i = start; i < start + count; i++) {
        for (c = 0; c < 3u; c++) {
            const ls_real *v = bvh->positions + 3u * (size_t)bvh->triangles[3u * (size_t)bvh->order[i] + c];
            for (a = 0; a < 3u; a++) {
                if (v[a] < node->lo[a]) node->lo[a] = v[a];
                if (v[a] > node->hi[a]) node->hi[a] = v[a];
            }
        }
    }
}

/* The axis of largest extent of the centroids order[start .. start+count)
 * (ties: the lower axis). */
static uint32_t split_axis(const ls_bvh *bvh, const ls_real *cent, uint32_t start, uint32_t count)
{
    ls_real lo[3], hi[3], best;
    uint32_t i, a, axis = 0;
    for (a = 0; a < 3u; a++) lo[a] = hi[a] = cent[3u * (size_t)bvh->order[start] + a];
    for (i = start + 1u; i < start + count; i++) {
        const ls_real *c = cent + 3u * (size_t)bvh->order[i];
        for (a = 0; a < 3u; a++) {
            if (c[a] < lo[a]) lo[a] = c[a];
            if (c[a] > hi[a]) hi[a] = c[a];
        }
    }
    best = hi[0] - lo[0];
    for (a = 1; a < 3u; a++) {
        if (hi[a] - lo[a] > best) {
            best = hi[a] - lo[a];
            axis = a;
        }
    }
    return axis;
}

ls_status ls_bvh_check_mesh(const ls_mesh *mesh, ls_diag *diag)
{
    ls_diag_clear(diag);
    uint32_t f, v;
    if (mesh == NULL || (mesh->face_count > 0 && mesh->triangles == NULL) ||
        (mesh->vertex_count > 0 && mesh->positions == NULL)) {
        diag_set(diag, LS_ERR_INVALID,
                 mesh == NULL                                           ? "mesh is NULL"
                 : (mesh->face_count > 0 && mesh->triangles == NULL) ? "mesh->triangles is NULL with face_count > 0"
                                                                     : "mesh->positions is NULL with vertex_count > 0",
                 0, 0);
        return LS_ERR_INVALID;
    }
    if (mesh->face_count > (UINT32_MAX - 1u) / 3u) {
        diag_set(diag, LS_ERR_TOO_LARGE, "too many faces", 0, 0);
        return LS_ERR_TOO_LARGE;
    }
    for (f = 0; f < 3u * mesh->face_count; f++) {
        if (mesh->triangles[f] >= mesh->vertex_count) {
            diag_set(diag, LS_ERR_MESH, "face index out of range", f / 3u, 1);
            return LS_ERR_MESH;
        }
    }
    for (v = 0; v < mesh->vertex_count; v++) {
        const ls_real *p = mesh->positions + 3u * (size_t)v;
        if (!LS_RISFINITE(p[0]) || !LS_RISFINITE(p[1]) || !LS_RISFINITE(p[2])) {
            diag_set(diag, LS_ERR_NONFINITE, "vertex coordinate not finite", v, 1);
            return LS_ERR_NONFINITE;
        }
    }
    return LS_OK;
}

ls_status ls_bvh_build(const ls_mesh *mesh, ls_arena *arena, ls_bvh *bvh, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_bvh t;
    ls_real *cent;
    work_item *stack;
    uint32_t f, sp, nodes, depth, next;
    ls_status st;
    if (mesh == NULL || arena == NULL || bvh == NULL || mesh->face_count == 0 || mesh->triangles == NULL ||
        mesh->positions == NULL) {
        diag_set(diag, LS_ERR_INVALID,
                 mesh == NULL              ? "mesh is NULL"
                 : arena == NULL           ? "arena is NULL"
                 : bvh == NULL             ? "bvh is NULL"
                 : mesh->face_count == 0   ? "mesh->face_count: 0; at least one face"
                 : mesh->triangles == NULL ? "mesh->triangles is NULL"
                                           : "mesh->positions is NULL",
                 0, 0);
        return LS_ERR_INVALID;
    }
    st = ls_bvh_check_mesh(mesh, diag);
    if (st != LS_OK) return st;
    nodes = (uint32_t)node_count_of(mesh->face_count, &depth);
    mark = ls_arena_save(arena);
    t.positions = mesh->positions;
    t.triangles = mesh->triangles;
    t.vertex_count = mesh->vertex_count;
    t.face_count = mesh->face_count;
    t.node_count = nodes;
    t.depth = depth;
    t.nodes = (ls_bvh_node *)ls_arena_alloc(arena, nodes, sizeof(ls_bvh_node));
    t.order = (uint32_t *)ls_arena_alloc(arena, mesh->face_count, sizeof(uint32_t));
    t.frames = NULL;
    t.frame_used = NULL;
    cent = (ls_real *)ls_arena_scratch(arena, (size_t)mesh->face_count * 3u, sizeof(ls_real));
    stack = (work_item *)ls_arena_scratch(arena, STACK_CAP, sizeof(work_item));
    if (t.nodes == NULL || t.order == NULL || cent == NULL || stack == NULL) {
        ls_arena_restore(arena, mark);
        diag_set(diag, LS_ERR_NOMEM, "arena too small for the BVH", 0, 0);
        return LS_ERR_NOMEM;
    }
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *tri = mesh->triangles + 3u * (size_t)f;
        uint32_t a;
        t.order[f] = f;
        for (a = 0; a < 3u; a++) {
            /* sum, not mean: the order is what matters */
            cent[3u * f + a] = (mesh->positions[3u * tri[0] + a] + mesh->positions[3u * tri[1] + a]) +
                               mesh->positions[3u * tri[2] + a];
        }
    }
    /* Depth-first, first child first: a node's first child is the next node. */
    sp = 0;
    stack[sp].start = 0;
    stack[sp].count = mesh->face_count;
    stack[sp].parent = NONE;
    stack[sp].level = 1;
    sp++;
    next = 0;
    while (sp > 0) {
        work_item w = stack[--sp];
        ls_bvh_node *node = &t.nodes[next];
        if (w.parent != NONE) t.nodes[w.parent].first = next;
        if (w.count <= LS_BVH_LEAF) {
            box_of(&t, w.start, w.count, node);
            node->first = w.start;
            node->count = w.count;
        } else {
            uint32_t half = w.count / 2u;
            uint32_t axis = split_axis(&t, cent, w.start, w.count);
            select_kth(t.order + w.start, w.count, half, cent, axis);
            node->first = NONE;
            node->count = 0;
            /* second child (filled in later), then the first on top */
            stack[sp].start = w.start + half;
            stack[sp].count = w.count - half;
            stack[sp].parent = next;
            stack[sp].level = w.level + 1u;
            sp++;
            stack[sp].start = w.start;
            stack[sp].count = half;
            stack[sp].parent = NONE;
            stack[sp].level = w.level + 1u;
            sp++;
        }
        next++;
    }
    /* An inner node's box is the union of its children's (they follow it):
     * one pass from the last node up, O(F) where boxing each node's corners
     * took O(F log F); min and max are exact, so the boxes are the same. */
    for (f = nodes; f-- > 0;) {
        ls_bvh_node *node = &t.nodes[f];
        if (node->count == 0) {
            const ls_bvh_node *c1 = &t.nodes[f + 1u], *c2 = &t.nodes[node->first];
            uint32_t a;
            for (a = 0; a < 3u; a++) {
                node->lo[a] = c1->lo[a] < c2->lo[a] ? c1->lo[a] : c2->lo[a];
                node->hi[a] = c1->hi[a] > c2->hi[a] ? c1->hi[a] : c2->hi[a];
            }
        }
    }
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    *bvh = t;
    return LS_OK;
}

/* ---- closest point ---------------------------------------------------- */

static ls_real dot3(const ls_real *a, const ls_real *b)
{
    return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
}

static void sub3(const ls_real *a, const ls_real *b, ls_real *out)
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

/* q = s + t e, the point at parameter t of a segment; bary gets (1-t, t) at
 * corners i and j. */
static void on_segment(const ls_real *s, const ls_real *e, ls_real t, uint32_t i, uint32_t j, ls_real *point,
                       ls_real *bary)
{
    uint32_t a;
    for (a = 0; a < 3u; a++) point[a] = s[a] + t * e[a];
    bary[0] = bary[1] = bary[2] = 0;
    bary[i] = (ls_real)1 - t;
    bary[j] += t;
}

/* Clamped ratio num / den in [0, 1] (0 when den <= 0). */
static ls_real ratio01(ls_real num, ls_real den)
{
    ls_real t;
    if (!(den > 0) || !(num > 0)) return 0;
    if (num >= den) return 1;
    t = num / den;
    return t > (ls_real)1 ? (ls_real)1 : t;
}

/* The closest point of the longest edge (a degenerate triangle). */
static void closest_degenerate(const ls_real *p, const ls_real *const *v, ls_real *point, ls_real *bary)
{
    ls_real e[3], d[3], len2[3], best;
    uint32_t k, i = 0;
    for (k = 0; k < 3u; k++) {
        sub3(v[(k + 1u) % 3u], v[k], e);
        len2[k] = dot3(e, e);
    }
    best = len2[0];
    for (k = 1; k < 3u; k++) {
        if (len2[k] > best) {
            best = len2[k];
            i = k;
        }
    }
    sub3(v[(i + 1u) % 3u], v[i], e);
    sub3(p, v[i], d);
    on_segment(v[i], e, ratio01(dot3(d, e), best), i, (i + 1u) % 3u, point, bary);
}

/* The closest point of triangle v[0..2] to p (at most six arguments: calls
 * with more push arguments on x86-64, which the stack checker counts as a
 * dynamic frame). */
static void closest_on_triangle(const ls_real *p, const ls_real *const *v, ls_real *point, ls_real *bary,
                                ls_real *dist2)
{
    ls_real ab[3], ac[3], ap[3], bp[3], cp[3], n[3], bc[3], d[3];
    ls_real d1, d2, d3, d4, d5, d6, va, vb, vc, n2, l1, l2, lim;
    const ls_real *a = v[0], *b = v[1], *c = v[2];
    uint32_t k;
    /* a query at a corner is answered exactly (distance 0, the lowest such
     * corner), whatever the triangle's shape */
    for (k = 0; k < 3u; k++) {
        if (p[0] == v[k][0] && p[1] == v[k][1] && p[2] == v[k][2]) {
            point[0] = p[0];
            point[1] = p[1];
            point[2] = p[2];
            bary[0] = bary[1] = bary[2] = 0;
            bary[k] = 1;
            *dist2 = 0;
            return;
        }
    }
    sub3(b, a, ab);
    sub3(c, a, ac);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    n2 = dot3(n, n);
    l1 = dot3(ab, ab);
    l2 = dot3(ac, ac);
    /* Degenerate: |ab x ac| <= 16 eps |ab| |ac| (angle below ~16 eps), which
     * also catches repeated corners and underflow. */
    lim = (ls_real)16 * LS_REAL_EPSILON;
    if (!(n2 > lim * lim * l1 * l2) || !(n2 > 0)) {
        closest_degenerate(p, v, point, bary);
        goto done;
    }
    sub3(p, a, ap);
    d1 = dot3(ab, ap);
    d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        on_segment(a, ab, 0, 0, 1, point, bary);
        goto done;
    }
    sub3(p, b, bp);
    d3 = dot3(ab, bp);
    d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        on_segment(a, ab, 1, 0, 1, point, bary);
        goto done;
    }
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        on_segment(a, ab, ratio01(d1, d1 - d3), 0, 1, point, bary);
        goto done;
    }
    sub3(p, c, cp);
    d5 = dot3(ab, cp);
    d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        on_segment(a, ac, 1, 0, 2, point, bary);
        goto done;
    }
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        on_segment(a, ac, ratio01(d2, d2 - d6), 0, 2, point, bary);
        goto done;
    }
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        sub3(c, b, bc);
        on_segment(b, bc, ratio01(d4 - d3, (d4 - d3) + (d5 - d6)), 1, 2, point, bary);
        goto done;
    }
    {
        ls_real den = (va + vb) + vc, s, t;
        if (!(den > 0)) {
            closest_degenerate(p, v, point, bary);
            goto done;
        }
        s = vb > 0 ? vb / den : (ls_real)0;
        t = vc > 0 ? vc / den : (ls_real)0;
        if (s + t > (ls_real)1) {
            s = s / (s + t);
            t = (ls_real)1 - s;
        }
        point[0] = a[0] + s * ab[0] + t * ac[0];
        point[1] = a[1] + s * ab[1] + t * ac[1];
        point[2] = a[2] + s * ab[2] + t * ac[2];
        bary[0] = ((ls_real)1 - s) - t;
        bary[1] = s;
        bary[2] = t;
    }
done:
    sub3(p, point, d);
    *dist2 = dot3(d, d);
}

void ls_closest_point_triangle(const ls_real p[3], const ls_real a[3], const ls_real b[3], const ls_real c[3],
                               ls_real point[3], ls_real bary[3], ls_real *dist2)
{
    const ls_real *v[3];
    v[0] = a;
    v[1] = b;
    v[2] = c;
    closest_on_triangle(p, v, point, bary, dist2);
}

/* Squared distance from p to a node's box. */
static ls_real box_dist2(const ls_bvh_node *node, const ls_real *p)
{
    ls_real s = 0;
    uint32_t a;
    for (a = 0; a < 3u; a++) {
        ls_real g = 0;
        if (p[a] < node->lo[a]) g = node->lo[a] - p[a];
        else if (p[a] > node->hi[a]) g = p[a] - node->hi[a];
        s += g * g;
    }
    return s;
}

/* Bound on the rounding error of a computed point-triangle distance, as a
 * distance: a few hundred ulps of the largest coordinate involved. Boxes
 * closer than the best distance plus this slack are searched, so that every
 * triangle whose computed distance could equal or beat the best is
 * evaluated: the result is the brute-force minimum (distance, then index). */
static ls_real slack_of(const ls_bvh *bvh, const ls_real *p)
{
    const ls_bvh_node *root = &bvh->nodes[0];
    ls_real m = 0;
    uint32_t a;
    for (a = 0; a < 3u; a++) {
        ls_real x = LS_RFABS(root->lo[a]);
        if (x > m) m = x;
        x = LS_RFABS(root->hi[a]);
        if (x > m) m = x;
        x = LS_RFABS(p[a]);
        if (x > m) m = x;
    }
    return (ls_real)256 * LS_REAL_EPSILON * m;
}

/* Squared distance from p to a node's oriented box, never above the true
 * squared distance to the node's triangles: each axis's gap is shortened by
 * `margin` (slack / 8, above the rounding of p's projection; the box's ranges
 * hold the exact projections) and the sum by 32 eps (above the frame's
 * departure from orthonormal). The caller uses it only for p within
 * LS_REAL_MAX / 4 on each axis, so that p's projections are finite, and for
 * nodes whose box is in use (finite and tight). */
static ls_real frame_dist2(const ls_bvh_frame *fr, const ls_real *p, ls_real margin)
{
    ls_real s = 0;
    uint32_t a;
    for (a = 0; a < 3u; a++) {
        ls_real t = (fr->axis[a][0] * p[0] + fr->axis[a][1] * p[1]) + fr->axis[a][2] * p[2], g = 0;
        if (t < fr->lo[a]) g = (fr->lo[a] - t) - margin;
        else if (t > fr->hi[a]) g = (t - fr->hi[a]) - margin;
        if (g > 0) s += g * g;
    }
    return s * ((ls_real)1 - (ls_real)32 * LS_REAL_EPSILON);
}

/* The larger of the two boxes' distances (the oriented one only when
 * margin >= 0, that is when the tree has frames and p is not huge, when the
 * axis-aligned one does not prune already, and when the node's box is in
 * use). */
static ls_real node_dist2(const ls_bvh *bvh, uint32_t i, const ls_real *p, ls_real margin, ls_real limit)
{
    ls_real d = box_dist2(&bvh->nodes[i], p);
    if (margin >= 0 && d <= limit && bvh->frames != NULL && bvh->frame_used != NULL &&
        (bvh->frame_used[i / 32u] >> (i % 32u) & 1u)) {
        ls_real o = frame_dist2(&bvh->frames[i], p, margin);
        if (o > d) d = o;
    }
    return d;
}

static ls_real prune_limit(ls_real best2, ls_real slack)
{
    ls_real r;
    if (!(best2 < LS_REAL_MAX)) return best2;
    r = LS_RSQRT(best2) + slack;
    return r * r;
}

/* Entries of the closest-point stack: a median-split tree over at most
 * 2^32 - 1 faces has at most 31 levels, and a depth-first search keeps at
 * most one entry per level plus one. */
#define QUERY_CAP 40u

/* The triangle f's closest point to p, as the search evaluates it. */
static void closest_on_face(const ls_bvh *bvh, uint32_t f, const ls_real *p, ls_bvh_hit *h)
{
    const uint32_t *tri = bvh->triangles + 3u * (size_t)f;
    const ls_real *v[3];
    v[0] = bvh->positions + 3u * (size_t)tri[0];
    v[1] = bvh->positions + 3u * (size_t)tri[1];
    v[2] = bvh->positions + 3u * (size_t)tri[2];
    closest_on_triangle(p, v, h->point, h->bary, &h->dist2);
    h->face = f;
}

ls_status ls_bvh_closest(const ls_bvh *bvh, const ls_real p[3], ls_real max_dist2, ls_bvh_hit *hit)
{
    return ls_bvh_closest_near(bvh, p, max_dist2, NONE, hit);
}

ls_status ls_bvh_closest_near(const ls_bvh *bvh, const ls_real p[3], ls_real max_dist2, uint32_t guess,
                              ls_bvh_hit *hit)
{
    uint32_t stack[QUERY_CAP];
    ls_real near[QUERY_CAP]; /* each entry's box distance */
    uint32_t sp = 0, best_face = NONE, done = NONE;
    ls_real best2 = max_dist2, limit, slack, margin = -1;
    if (bvh == NULL || p == NULL || hit == NULL || bvh->nodes == NULL || LS_RISNAN(max_dist2))
        return LS_ERR_INVALID;
    if (!LS_RISFINITE(p[0]) || !LS_RISFINITE(p[1]) || !LS_RISFINITE(p[2])) return LS_ERR_NONFINITE;
    hit->face = NONE;
    if (guess < bvh->face_count) { /* evaluated first: the search starts with its distance */
        done = guess;
        ls_bvh_hit h;
        closest_on_face(bvh, guess, p, &h);
        if (h.dist2 < best2) {
            *hit = h;
            best2 = h.dist2;
            best_face = guess;
        }
    }
    slack = slack_of(bvh, p);
    limit = prune_limit(best2, slack);
    if (bvh->frames != NULL && bvh->frame_used != NULL && LS_RFABS(p[0]) < LS_REAL_MAX / 4 && LS_RFABS(p[1]) < LS_REAL_MAX / 4 &&
        LS_RFABS(p[2]) < LS_REAL_MAX / 4)
        margin = slack / 8;
    stack[0] = 0;
    near[0] = node_dist2(bvh, 0, p, margin, limit);
    sp = 1;
    while (sp > 0) {
        const ls_bvh_node *node;
        sp--;
        if (near[sp] > limit) continue;
        node = &bvh->nodes[stack[sp]];
        if (node->count > 0) {
            uint32_t i;
            for (i = node->first; i < node->first + node->count; i++) {
                uint32_t f = bvh->order[i];
                ls_bvh_hit h;
                ls_real d2;
                if (f == done) continue; /* the guess, already evaluated */
                closest_on_face(bvh, f, p, &h);
                d2 = h.dist2;
                if (best_face == NONE ? d2 < best2 : (d2 < best2 || (d2 == best2 && f < best_face))) {
                    best2 = d2;
                    best_face = f;
                    memcpy(hit->point, h.point, sizeof h.point);
                    memcpy(hit->bary, h.bary, sizeof h.bary);
                    limit = prune_limit(best2, slack);
                }
            }
        } else {
            uint32_t c1 = stack[sp] + 1u, c2 = node->first;
            ls_real d1 = node_dist2(bvh, c1, p, margin, limit), d2 = node_dist2(bvh, c2, p, margin, limit);
            if (sp + 2u > QUERY_CAP) return LS_ERR_STATE; /* not a tree built by ls_bvh_build */
            /* the nearer child on top; children beyond the limit are not pushed */
            if (d1 > d2) {
                uint32_t tc = c1;
                ls_real td = d1;
                c1 = c2;
                d1 = d2;
                c2 = tc;
                d2 = td;
            }
            if (d2 <= limit) {
                stack[sp] = c2;
                near[sp++] = d2;
            }
            if (d1 <= limit) {
                stack[sp] = c1;
                near[sp++] = d1;
            }
        }
    }
    hit->face = best_face;
    hit->dist2 = best2;
    return LS_OK;
}

/* ---- box overlap ------------------------------------------------------ */

static int box_overlaps(const ls_bvh_node *node, const ls_real *lo, const ls_real *hi)
{
    uint32_t a;
    for (a = 0; a < 3u; a++)
        if (node->lo[a] > hi[a] || node->hi[a] < lo[a]) return 0;
    return 1;
}

ls_status ls_bvh_overlap_begin(const ls_bvh *bvh, const ls_real lo[3], const ls_real hi[3], ls_bvh_overlap *it)
{
    uint32_t a;
    if (bvh == NULL || lo == NULL || hi == NULL || it == NULL || bvh->nodes == NULL) return LS_ERR_INVALID;
    for (a = 0; a < 3u; a++) {
        if (LS_RISNAN(lo[a]) || LS_RISNAN(hi[a])) return LS_ERR_NONFINITE;
        it->lo[a] = lo[a];
        it->hi[a] = hi[a];
    }
    it->bvh = bvh;
    it->sp = 1;
    it->stack[0] = 0;
    it->pos = 0;
    it->end = 0;
    return LS_OK;
}

int ls_bvh_overlap_next(ls_bvh_overlap *it, uint32_t *face)
{
    const ls_bvh *bvh;
    if (it == NULL || face == NULL || it->bvh == NULL) return 0;
    bvh = it->bvh;
    for (;;) {
        const ls_bvh_node *node;
        if (it->pos < it->end) {
            *face = bvh->order[it->pos++];
            return 1;
        }
        if (it->sp == 0) return 0;
        node = &bvh->nodes[it->stack[--it->sp]];
        if (!box_overlaps(node, it->lo, it->hi)) continue;
        if (node->count > 0) {
            it->pos = node->first;
            it->end = node->first + node->count;
        } else {
            if (it->sp + 2u > LS_BVH_MAX_DEPTH + 2u) return 0;
            it->stack[it->sp++] = node->first;
            it->stack[it->sp++] = (uint32_t)(node - bvh->nodes) + 1u;
        }
    }
}
