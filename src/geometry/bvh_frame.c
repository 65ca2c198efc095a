/* bvh_frame.c - oriented boxes for the nodes of a BVH: each node's box along
 * the principal axes of its triangles' corners (see largesteps/bvh.h). Any
 * orthonormal frame gives a valid bound; the principal axes give a tight one,
 * which is what keeps closest-point queries logarithmic on fans and slivers. */
#include <largesteps/bvh.h>
#include <largesteps/math.h>
#include <string.h>

ls_status ls_bvh_frames_bytes(uint32_t face_count, size_t *bytes)
{
    ls_size s;
    uint32_t nodes;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (face_count == 0) return LS_ERR_INVALID;
    nodes = ls_bvh_node_count(face_count);
    if (nodes == 0) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, nodes, sizeof(ls_bvh_frame));
    ls_size_add(&s, nodes / 32u + 1u, sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

static void set_identity(ls_real r[3][3])
{
    uint32_t i, j;
    for (i = 0; i < 3u; i++)
        for (j = 0; j < 3u; j++) r[i][j] = i == j ? (ls_real)1 : (ls_real)0;
}

/* The eigenvectors of the symmetric matrix c as the rows of r: cyclic Jacobi
 * rotations until the off-diagonal part is under 1/1024 of the diagonal, at
 * most 4 sweeps. A box needs the axes to a degree or so, not to the last
 * bit: converging to eps took most of the frames' time. A matrix with
 * non-finite entries stops the sweeps; orthonormalize then checks r. */
static void principal_axes(ls_real c[3][3], ls_real r[3][3])
{
    static const uint32_t pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    uint32_t sweep, k, j;
    set_identity(r);
    for (sweep = 0; sweep < 4u; sweep++) {
        ls_real off = (LS_RFABS(c[0][1]) + LS_RFABS(c[0][2])) + LS_RFABS(c[1][2]);
        ls_real on = (LS_RFABS(c[0][0]) + LS_RFABS(c[1][1])) + LS_RFABS(c[2][2]);
        if (!(off * (ls_real)1024 > on)) break;
        for (k = 0; k < 3u; k++) {
            uint32_t p = pairs[k][0], q = pairs[k][1];
            ls_real theta, t, cs, sn;
            if (c[p][q] == 0) continue;
            /* the rotation that zeroes c[p][q]: t = tan of its angle, the
             * smaller root of t^2 + 2 theta t - 1 = 0 */
            theta = (c[q][q] - c[p][p]) / ((ls_real)2 * c[p][q]);
            t = (ls_real)1 / (LS_RFABS(theta) + LS_RSQRT(theta * theta + (ls_real)1));
            if (theta < 0) t = -t;
            cs = (ls_real)1 / LS_RSQRT(t * t + (ls_real)1);
            sn = t * cs;
            for (j = 0; j < 3u; j++) { /* c P */
                ls_real a = c[j][p], b = c[j][q];
                c[j][p] = cs * a - sn * b;
                c[j][q] = sn * a + cs * b;
            }
            for (j = 0; j < 3u; j++) { /* P^T c P */
                ls_real a = c[p][j], b = c[q][j];
                c[p][j] = cs * a - sn * b;
                c[q][j] = sn * a + cs * b;
            }
            for (j = 0; j < 3u; j++) { /* the eigenvectors V P, as rows */
                ls_real a = r[p][j], b = r[q][j];
                r[p][j] = cs * a - sn * b;
                r[q][j] = sn * a + cs * b;
            }
        }
    }
}

static ls_real dot3(const ls_real *a, const ls_real *b)
{
    return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
}

/* Scales v to unit length; 0 when its length is not a positive finite number. */
static int normalize(ls_real *v)
{
    ls_real n = LS_RSQRT(dot3(v, v));
    if (!(n > 0) || !LS_RISFINITE(n)) return 0;
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
    return 1;
}

/* Gram-Schmidt on rows 0 and 1, row 2 their cross product, so that the rows
 * are orthonormal to a few ulps whatever the rotations' rounding (the query's
 * bound counts on it); the identity when the rows are not usable. */
static void orthonormalize(ls_real r[3][3])
{
    int ok = normalize(r[0]);
    if (ok) {
        ls_real d = dot3(r[1], r[0]);
        uint32_t a;
        for (a = 0; a < 3u; a++) r[1][a] -= d * r[0][a];
        ok = normalize(r[1]);
    }
    if (ok) {
        r[2][0] = r[0][1] * r[1][2] - r[0][2] * r[1][1];
        r[2][1] = r[0][2] * r[1][0] - r[0][0] * r[1][2];
        r[2][2] = r[0][0] * r[1][1] - r[0][1] * r[1][0];
        ok = normalize(r[2]);
    }
    if (!ok) set_identity(r);
}

/* A node's corner moments about the origin o of the tree (its box's centre,
 * so that the differences stay small): count, sums and sums of products. */
typedef struct moments {
    ls_real n;
    ls_real s[3];
    ls_real s2[6]; /* xx xy xz yy yz zz */
} moments;

/* The build keeps each node's moments in its frame's place until the frame
 * is made (see ls_bvh_build_frames). */
typedef char moments_fit_in_a_frame[sizeof(moments) <= sizeof(ls_bvh_frame) ? 1 : -1];

static const ls_real *corner(const ls_bvh *bvh, uint32_t pos, uint32_t c)
{
    return bvh->positions + 3u * (size_t)bvh->triangles[3u * (size_t)bvh->order[pos] + c];
}

static void leaf_moments(const ls_bvh *bvh, const ls_bvh_node *node, const ls_real *o, moments *m)
{
    uint32_t i, k, a, b, j;
    memset(m, 0, sizeof *m);
    for (i = node->first; i < node->first + node->count; i++) {
        for (k = 0; k < 3u; k++) {
            const ls_real *v = corner(bvh, i, k);
            ls_real d[3];
            for (a = 0; a < 3u; a++) {
                d[a] = v[a] - o[a];
                m->s[a] += d[a];
            }
            for (a = 0, j = 0; a < 3u; a++)
                for (b = a; b < 3u; b++, j++) m->s2[j] += d[a] * d[b];
        }
    }
    m->n = (ls_real)3 * (ls_real)node->count;
}

static void add_moments(moments *m, const moments *x)
{
    uint32_t a;
    m->n += x->n;
    for (a = 0; a < 3u; a++) m->s[a] += x->s[a];
    for (a = 0; a < 6u; a++) m->s2[a] += x->s2[a];
}

/* The principal axes of the corners (rows of axis, orthonormal). */
static void axes_of(const moments *m, ls_real axis[3][3])
{
    ls_real c[3][3];
    uint32_t a, b, j;
    for (a = 0, j = 0; a < 3u; a++)
        for (b = a; b < 3u; b++, j++) c[a][b] = c[b][a] = m->s2[j] / m->n - (m->s[a] / m->n) * (m->s[b] / m->n);
    principal_axes(c, axis);
    orthonormalize(axis);
}

/* The range of u . x over the node's corners for a leaf, or over the boxes
 * of a child (the tighter of its axis-aligned box and its oriented box),
 * widened by `pad` so that it holds the exact values: pad covers the
 * rounding of the products and sums (and the oriented box's departure from
 * orthonormal), a few tens of eps of the tree's largest coordinate. */
static void leaf_range(const ls_bvh *bvh, const ls_bvh_node *node, const ls_real *u, ls_real *lo, ls_real *hi)
{
    uint32_t i, k;
    for (i = node->first; i < node->first + node->count; i++) {
        for (k = 0; k < 3u; k++) {
            ls_real t = dot3(u, corner(bvh, i, k));
            if ((i == node->first && k == 0) || t < *lo) *lo = t;
            if ((i == node->first && k == 0) || t > *hi) *hi = t;
        }
    }
}

static void child_range(const ls_bvh_node *node, const ls_bvh_frame *fr, const ls_real *u, ls_real *lo,
                        ls_real *hi)
{
    ls_real blo = 0, bhi = 0;
    uint32_t a;
    for (a = 0; a < 3u; a++) { /* the axis-aligned box: exact up to the rounding */
        ls_real x = node->lo[a] * u[a], y = node->hi[a] * u[a];
        blo += x < y ? x : y;
        bhi += x < y ? y : x;
    }
    if (fr->lo[0] <= fr->hi[0]) { /* the oriented box: x = sum_k (a_k . x) a_k */
        ls_real olo = 0, ohi = 0;
        for (a = 0; a < 3u; a++) {
            ls_real w = dot3(u, fr->axis[a]), x = fr->lo[a] * w, y = fr->hi[a] * w;
            olo += x < y ? x : y;
            ohi += x < y ? y : x;
        }
        if (olo > blo) blo = olo;
        if (ohi < bhi) bhi = ohi;
    }
    *lo = blo;
    *hi = bhi;
}

/* Surface area of a box with these sides (up to the factor 2). */
static ls_real box_area(const ls_real *e)
{
    return (e[0] * e[1] + e[1] * e[2]) + e[2] * e[0];
}

/* Whether the oriented box pays its test: a query point near the surface
 * falls in a box about in proportion to its surface area, and on most
 * meshes the two boxes differ little (there the second test only costs:
 * +50 % on a scan's queries), while on fans and slivers the oriented box is
 * a small part of the other. */
static int tight(const ls_bvh_node *node, const ls_bvh_frame *fr)
{
    ls_real e[3], f[3];
    uint32_t a;
    for (a = 0; a < 3u; a++) {
        e[a] = node->hi[a] - node->lo[a];
        f[a] = fr->hi[a] - fr->lo[a];
    }
    return box_area(f) < (ls_real)0.25 * box_area(e);
}

ls_status ls_bvh_build_frames(ls_bvh *bvh, ls_arena *arena, ls_diag *diag)
{
    ls_bvh_frame *frames;
    uint32_t *used;
    ls_arena_mark mark;
    const ls_bvh_node *root;
    ls_real o[3], big = 0, pad;
    uint32_t i, a;
    ls_diag_clear(diag);
    if (bvh == NULL || arena == NULL || bvh->nodes == NULL || bvh->order == NULL || bvh->node_count == 0) {
        (void)ls_diag_set(diag, LS_ERR_INVALID,
                          bvh == NULL     ? "bvh is NULL"
                          : arena == NULL ? "arena is NULL"
                                          : "bvh is not built (ls_bvh_build first)",
                          LS_DIAG_NO_INDEX);
        return LS_ERR_INVALID;
    }
    mark = ls_arena_save(arena);
    frames = (ls_bvh_frame *)ls_arena_alloc(arena, bvh->node_count, sizeof(ls_bvh_frame));
    used = (uint32_t *)ls_arena_alloc(arena, bvh->node_count / 32u + 1u, sizeof(uint32_t));
    if (frames == NULL || used == NULL) {
        ls_arena_restore(arena, mark);
        (void)ls_diag_set(diag, LS_ERR_NOMEM, "arena too small for the BVH's oriented boxes", LS_DIAG_NO_INDEX);
        return LS_ERR_NOMEM;
    }
    memset(used, 0, (bvh->node_count / 32u + 1u) * sizeof(uint32_t));
    root = &bvh->nodes[0];
    for (a = 0; a < 3u; a++) {
        o[a] = root->lo[a] * (ls_real)0.5 + root->hi[a] * (ls_real)0.5;
        if (LS_RFABS(root->lo[a]) > big) big = LS_RFABS(root->lo[a]);
        if (LS_RFABS(root->hi[a]) > big) big = LS_RFABS(root->hi[a]);
    }
    pad = (ls_real)128 * LS_REAL_EPSILON * big;
    /* Children have higher indices than their parent, so one pass from the
     * last node up gives every node its moments (a leaf's from its corners,
     * an inner node's as its children's sum), each kept in the node's own
     * frame slot; a second pass from the last node up replaces them by the
     * frame: the axes from the node's moments, the ranges from its corners
     * (a leaf) or from its children's finished boxes. O(F) in all. */
    for (i = bvh->node_count; i-- > 0;) {
        const ls_bvh_node *node = &bvh->nodes[i];
        moments m, x;
        if (node->count > 0) {
            leaf_moments(bvh, node, o, &m);
        } else {
            memcpy(&m, &frames[i + 1u], sizeof m);
            memcpy(&x, &frames[node->first], sizeof x);
            add_moments(&m, &x);
        }
        memcpy(&frames[i], &m, sizeof m);
    }
    for (i = bvh->node_count; i-- > 0;) {
        const ls_bvh_node *node = &bvh->nodes[i];
        ls_bvh_frame fr;
        moments m;
        int finite = 1;
        memcpy(&m, &frames[i], sizeof m);
        axes_of(&m, fr.axis);
        for (a = 0; a < 3u; a++) {
            if (node->count > 0) {
                leaf_range(bvh, node, fr.axis[a], &fr.lo[a], &fr.hi[a]);
            } else {
                uint32_t c2 = node->first;
                ls_real lo2, hi2;
                child_range(&bvh->nodes[i + 1u], &frames[i + 1u], fr.axis[a], &fr.lo[a], &fr.hi[a]);
                child_range(&bvh->nodes[c2], &frames[c2], fr.axis[a], &lo2, &hi2);
                if (lo2 < fr.lo[a]) fr.lo[a] = lo2;
                if (hi2 > fr.hi[a]) fr.hi[a] = hi2;
            }
            fr.lo[a] -= pad;
            fr.hi[a] += pad;
            finite &= LS_RISFINITE(fr.lo[a]) && LS_RISFINITE(fr.hi[a]);
        }
        if (!finite) { /* a projection overflowed: no oriented box, the query keeps the axis-aligned one */
            fr.lo[0] = LS_REAL_MAX;
            fr.hi[0] = -LS_REAL_MAX;
        }
        if (finite && tight(node, &fr)) used[i / 32u] |= (uint32_t)1 << (i % 32u);
        frames[i] = fr;
    }
    bvh->frames = frames;
    bvh->frame_used = used;
    return LS_OK;
}
