/* visual_hull.c - the visual hull of masked views by marching tetrahedra. */
#include <largesteps/visual_hull.h>
#include <largesteps/camera.h>
#include <largesteps/math.h>
#include "../base/diag_internal.h"

#define HULL_NONE 0xffffffffu
#define HULL_EDGE_MARGIN ((ls_real)0.02) /* a vertex stays this far (of its edge) from a grid point */

/* The six tetrahedra of a cell: corners 0, a, a | b, 7 for each order (a, b,
 * c) of the axis bits (x 1, y 2, z 4). Every edge joins a corner to one whose
 * bits hold its own, so an edge is (its lower corner, the bits it adds). */
static const unsigned char kuhn[6][4] = {
    {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7},
};

typedef struct hull_grid {
    uint32_t n[3];     /* points per axis, the padding's included */
    ls_real origin[3]; /* the position of point (0, 0, 0) */
    ls_real cell;      /* the cells' side */
    ls_real *f;        /* the field at every point, x fastest */
    uint32_t *layer;   /* two z layers of 7 edge vertices per point */
} hull_grid;

/* The vertices and faces of the whole surface, before the kept component. */
typedef struct hull_surface {
    ls_real *positions;
    uint32_t *faces;
    uint32_t vertices, face_count;
} hull_surface;

void ls_hull_params_default(ls_hull_params *params, const ls_real lo[3], const ls_real hi[3])
{
    uint32_t c;
    if (params == NULL) return;
    for (c = 0; c < 3; c++) {
        params->lo[c] = lo != NULL ? lo[c] : (ls_real)-1;
        params->hi[c] = hi != NULL ? hi[c] : (ls_real)1;
    }
    params->resolution = 128;
    params->threshold = (ls_real)0.5;
}

static ls_status check_args(const ls_hull_views *views, const ls_hull_params *params, const ls_arena *arena,
                            ls_diag *diag)
{
    uint32_t v, c;
    if (views == NULL || params == NULL || arena == NULL) return ls_invalid_arg(diag, "views, params and arena must not be NULL");
    if (views->count < 1u || views->count > 65535u) return ls_invalid_arg(diag, "views->count must be 1..65535");
    if (views->width < 1u || views->width > 65535u || views->height < 1u || views->height > 65535u)
        return ls_invalid_arg(diag, "views->width and views->height must be 1..65535");
    if (views->images == NULL || views->mvps == NULL) return ls_invalid_arg(diag, "views->images and views->mvps must not be NULL");
    for (v = 0; v < views->count; v++)
        if (views->images[v] == NULL) return ls_invalid_arg(diag, "views->images holds a NULL image");
    for (v = 0; v < 16u * views->count; v++)
        if (!LS_RISFINITE(views->mvps[v])) return ls_diag_set(diag, LS_ERR_NONFINITE, "views->mvps: a value is not finite", v);
    if (params->resolution < 2u || params->resolution > 1024u) return ls_invalid_arg(diag, "params->resolution must be 2..1024");
    if (!(params->threshold > 0 && params->threshold < 1)) return ls_invalid_arg(diag, "params->threshold must be in (0, 1)");
    for (c = 0; c < 3; c++) {
        if (!LS_RISFINITE(params->lo[c]) || !LS_RISFINITE(params->hi[c]) || !LS_RISFINITE(params->hi[c] - params->lo[c]))
            return ls_diag_set(diag, LS_ERR_NONFINITE, "params->lo or params->hi: a value is not finite", c);
        if (!(params->lo[c] < params->hi[c])) return ls_invalid_arg(diag, "params->lo must be below params->hi on every axis");
    }
    return LS_OK;
}

/* The grid's shape: cells of the longest side / resolution, one more point
 * than cells on each axis, and one padding point at both ends. */
static ls_status grid_shape(const ls_hull_params *params, hull_grid *g, size_t *points)
{
    ls_real longest = 0;
    uint32_t c;
    *points = 0;
    g->n[0] = g->n[1] = g->n[2] = 0;
    for (c = 0; c < 3; c++)
        if (params->hi[c] - params->lo[c] > longest) longest = params->hi[c] - params->lo[c];
    g->cell = longest / (ls_real)params->resolution;
    if (!(g->cell > 0)) return LS_ERR_INVALID;
    *points = 1;
    for (c = 0; c < 3; c++) {
        ls_real cells = LS_RCEIL((params->hi[c] - params->lo[c]) / g->cell);
        uint32_t k = cells < 1 ? 1u : cells > (ls_real)params->resolution ? params->resolution : LS_RTO_U32(cells);
        g->n[c] = k + 3u;
        g->origin[c] = params->lo[c] - g->cell;
        *points *= g->n[c];
    }
    return *points > 0x7fffffffu ? LS_ERR_TOO_LARGE : LS_OK;
}

/* alpha at window position (x, y), bilinear between pixel centres. */
static ls_real sample_alpha(const ls_real *img, uint32_t w, uint32_t h, ls_real x, ls_real y)
{
    uint32_t i0, j0, i1, j1;
    ls_real fx, fy, top, bottom;
    x -= (ls_real)0.5;
    y -= (ls_real)0.5;
    if (x < 0) x = 0;
    if (y < 0) y = 0;
    if (x > (ls_real)(w - 1u)) x = (ls_real)(w - 1u);
    if (y > (ls_real)(h - 1u)) y = (ls_real)(h - 1u);
    i0 = LS_RTO_U32(LS_RFLOOR(x));
    j0 = LS_RTO_U32(LS_RFLOOR(y));
    fx = x - (ls_real)i0;
    fy = y - (ls_real)j0;
    i1 = i0 + 1u < w ? i0 + 1u : i0;
    j1 = j0 + 1u < h ? j0 + 1u : j0;
    top = img[4u * ((size_t)j0 * w + i0) + 3u] * (1 - fx) + img[4u * ((size_t)j0 * w + i1) + 3u] * fx;
    bottom = img[4u * ((size_t)j1 * w + i0) + 3u] * (1 - fx) + img[4u * ((size_t)j1 * w + i1) + 3u] * fx;
    return top * (1 - fy) + bottom * fy;
}

/* min over the views that see p of (alpha - threshold); 1 - threshold when
 * none does. Leaves at the first view whose alpha is 0 or less. */
static ls_real field_at(const ls_hull_views *views, ls_real threshold, const ls_real p[3])
{
    ls_real f = 1 - threshold, clip[4];
    uint32_t v;
    for (v = 0; v < views->count; v++) {
        ls_real x, y, a;
        ls_mat4_apply(views->mvps + 16u * (size_t)v, p, clip);
        if (!(clip[3] > 0)) continue; /* behind the camera */
        x = (clip[0] / clip[3] + 1) * (ls_real)0.5 * (ls_real)views->width;
        y = (1 - clip[1] / clip[3]) * (ls_real)0.5 * (ls_real)views->height;
        if (!(x >= 0 && y >= 0 && x <= (ls_real)views->width && y <= (ls_real)views->height)) continue; /* off the image */
        a = sample_alpha(views->images[v], views->width, views->height, x, y);
        if (a - threshold < f) f = a - threshold;
        if (a <= 0) break;
    }
    return f;
}

static void carve(const ls_hull_views *views, const ls_hull_params *params, hull_grid *g)
{
    uint32_t i, j, k;
    size_t at = 0;
    for (k = 0; k < g->n[2]; k++)
        for (j = 0; j < g->n[1]; j++)
            for (i = 0; i < g->n[0]; i++, at++) {
                ls_real p[3];
                if (i == 0 || j == 0 || k == 0 || i + 1u == g->n[0] || j + 1u == g->n[1] || k + 1u == g->n[2]) {
                    g->f[at] = -1; /* the padding is outside */
                    continue;
                }
                p[0] = g->origin[0] + g->cell * (ls_real)i;
                p[1] = g->origin[1] + g->cell * (ls_real)j;
                p[2] = g->origin[2] + g->cell * (ls_real)k;
                g->f[at] = field_at(views, params->threshold, p);
            }
}

static size_t point_index(const hull_grid *g, uint32_t i, uint32_t j, uint32_t k)
{
    return ((size_t)k * g->n[1] + j) * g->n[0] + i;
}

/* The point of corner `bits` of cell (i, j, k). */
static size_t corner_index(const hull_grid *g, uint32_t i, uint32_t j, uint32_t k, unsigned bits)
{
    return point_index(g, i + (bits & 1u), j + ((bits >> 1) & 1u), k + ((bits >> 2) & 1u));
}

/* Crossed edges and faces of the whole surface. */
static ls_status count_surface(const hull_grid *g, uint32_t *vertices, uint32_t *faces)
{
    uint64_t nv = 0, nf = 0;
    uint32_t i, j, k, t, c;
    unsigned d;
    for (k = 0; k + 1u < g->n[2]; k++)
        for (j = 0; j + 1u < g->n[1]; j++)
            for (i = 0; i + 1u < g->n[0]; i++) {
                unsigned inside = 0, b;
                for (b = 0; b < 8u; b++)
                    if (g->f[corner_index(g, i, j, k, b)] >= 0) inside |= 1u << b;
                /* the edges that leave corner 0 towards the cell's other seven corners: every
                   grid edge is counted once, from its lower end (the padding keeps the last
                   points outside, so no edge beyond the cells crosses) */
                for (d = 1; d < 8u; d++)
                    if (((inside >> d) & 1u) != (inside & 1u)) nv++;
                if (inside == 0 || inside == 0xffu) continue;
                for (t = 0; t < 6u; t++) {
                    unsigned in = 0;
                    for (c = 0; c < 4u; c++) in += (inside >> kuhn[t][c]) & 1u;
                    nf += in == 2u ? 2u : in == 1u || in == 3u ? 1u : 0u;
                }
            }
    if (nv > 0x7fffffffu || nf > 0x7fffffffu) return LS_ERR_TOO_LARGE;
    *vertices = (uint32_t)nv;
    *faces = (uint32_t)nf;
    return LS_OK;
}

/* The vertex on the edge from corner u to corner u | d of cell (i, j, k),
 * made when first met. */
static uint32_t edge_vertex(const hull_grid *g, uint32_t i, uint32_t j, uint32_t k, unsigned u, unsigned d,
                            hull_surface *s)
{
    uint32_t pi = i + (u & 1u), pj = j + ((u >> 1) & 1u), pk = k + ((u >> 2) & 1u);
    uint32_t *slot = g->layer + (size_t)(pk & 1u) * 7u * g->n[0] * g->n[1] + ((size_t)pj * g->n[0] + pi) * 7u + (d - 1u);
    if (*slot == HULL_NONE) {
        ls_real fa = g->f[point_index(g, pi, pj, pk)];
        ls_real fb = g->f[corner_index(g, i, j, k, u | d)];
        ls_real t = fa / (fa - fb), *p = s->positions + 3u * (size_t)s->vertices;
        if (t < HULL_EDGE_MARGIN) t = HULL_EDGE_MARGIN;
        if (t > 1 - HULL_EDGE_MARGIN) t = 1 - HULL_EDGE_MARGIN;
        p[0] = g->origin[0] + g->cell * ((ls_real)pi + t * (ls_real)(d & 1u));
        p[1] = g->origin[1] + g->cell * ((ls_real)pj + t * (ls_real)((d >> 1) & 1u));
        p[2] = g->origin[2] + g->cell * ((ls_real)pk + t * (ls_real)((d >> 2) & 1u));
        *slot = s->vertices++;
    }
    return *slot;
}

/* Twice the position of an edge's midpoint in the cell, in cell units. */
static void edge_mid2(unsigned a, unsigned b, int m[3])
{
    unsigned c;
    for (c = 0; c < 3u; c++) m[c] = (int)((a >> c) & 1u) + (int)((b >> c) & 1u);
}

/* One face on the edges (e[0], e[1]), (e[2], e[3]), (e[4], e[5]) (corner
 * bits), turned so that its normal points from the inside corners to the
 * outside ones. The test uses the edges' midpoints in exact integers (they
 * never degenerate); w: the outward direction, scaled. */
static void emit_face(const hull_grid *g, uint32_t i, uint32_t j, uint32_t k, const unsigned e[6], const int w[3],
                      hull_surface *s)
{
    int m[3][3], a[3], b[3], n[3];
    size_t q;
    uint32_t c, *f = s->faces + 3u * (size_t)s->face_count;
    for (q = 0; q < 3u; q++) edge_mid2(e[2u * q], e[2u * q + 1u], m[q]);
    for (c = 0; c < 3u; c++) {
        a[c] = m[1][c] - m[0][c];
        b[c] = m[2][c] - m[0][c];
    }
    n[0] = a[1] * b[2] - a[2] * b[1];
    n[1] = a[2] * b[0] - a[0] * b[2];
    n[2] = a[0] * b[1] - a[1] * b[0];
    for (q = 0; q < 3u; q++) {
        unsigned lo = e[2u * q] & e[2u * q + 1u], hi = e[2u * q] | e[2u * q + 1u];
        f[q] = edge_vertex(g, i, j, k, lo, hi ^ lo, s);
    }
    if (n[0] * w[0] + n[1] * w[1] + n[2] * w[2] < 0) {
        uint32_t t = f[1];
        f[1] = f[2];
        f[2] = t;
    }
    s->face_count++;
}

/* The faces of one tetrahedron (corner bits tet[0..3]), inside: the cell's
 * inside corners as bits. */
static void march_tet(const hull_grid *g, uint32_t i, uint32_t j, uint32_t k, const unsigned char tet[4],
                      unsigned inside, hull_surface *s)
{
    unsigned in[4], out[4], ni = 0, no = 0, c;
    size_t q;
    int w[3] = {0, 0, 0};
    for (c = 0; c < 4u; c++) {
        if ((inside >> tet[c]) & 1u)
            in[ni++] = tet[c];
        else
            out[no++] = tet[c];
    }
    if (ni == 0 || no == 0) return;
    for (c = 0; c < 3u; c++) {
        int si = 0, so = 0;
        for (q = 0; q < ni; q++) si += (int)((in[q] >> c) & 1u);
        for (q = 0; q < no; q++) so += (int)((out[q] >> c) & 1u);
        w[c] = so * (int)ni - si * (int)no;
    }
    if (ni == 1u || no == 1u) { /* one corner cut off */
        unsigned lone = ni == 1u ? in[0] : out[0];
        const unsigned *rest = ni == 1u ? out : in;
        unsigned e[6];
        for (q = 0; q < 3u; q++) {
            e[2u * q] = lone;
            e[2u * q + 1u] = rest[q];
        }
        emit_face(g, i, j, k, e, w, s);
    } else { /* a quad: the edges a-c, a-d, b-d, b-c around it */
        unsigned e1[6], e2[6];
        e1[0] = in[0], e1[1] = out[0], e1[2] = in[0], e1[3] = out[1], e1[4] = in[1], e1[5] = out[1];
        e2[0] = in[0], e2[1] = out[0], e2[2] = in[1], e2[3] = out[1], e2[4] = in[1], e2[5] = out[0];
        emit_face(g, i, j, k, e1, w, s);
        emit_face(g, i, j, k, e2, w, s);
    }
}

static void march(hull_grid *g, hull_surface *s)
{
    size_t layer = 7u * (size_t)g->n[0] * g->n[1], x;
    uint32_t i, j, k, t;
    for (x = 0; x < 2u * layer; x++) g->layer[x] = HULL_NONE;
    s->vertices = s->face_count = 0;
    for (k = 0; k + 1u < g->n[2]; k++) {
        uint32_t *next = g->layer + (size_t)((k + 1u) & 1u) * layer; /* z layer k + 1 replaces k - 1 */
        for (x = 0; x < layer; x++) next[x] = HULL_NONE;
        for (j = 0; j + 1u < g->n[1]; j++)
            for (i = 0; i + 1u < g->n[0]; i++) {
                unsigned inside = 0, b;
                for (b = 0; b < 8u; b++)
                    if (g->f[corner_index(g, i, j, k, b)] >= 0) inside |= 1u << b;
                if (inside == 0 || inside == 0xffu) continue;
                for (t = 0; t < 6u; t++) march_tet(g, i, j, k, kuhn[t], inside, s);
            }
    }
}

static uint32_t find_root(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]]; /* path halving */
        v = parent[v];
    }
    return v;
}

/* The component with the most faces (the first met among equals): its root.
 * parent: V scratch, count: V scratch. */
static uint32_t largest_component(const hull_surface *s, uint32_t *parent, uint32_t *count)
{
    uint32_t v, f, c, best = 0;
    for (v = 0; v < s->vertices; v++) parent[v] = v, count[v] = 0;
    for (f = 0; f < s->face_count; f++)
        for (c = 1; c < 3u; c++) {
            uint32_t a = find_root(parent, s->faces[3u * (size_t)f]), b = find_root(parent, s->faces[3u * (size_t)f + c]);
            if (a != b) parent[a < b ? b : a] = a < b ? a : b;
        }
    for (f = 0; f < s->face_count; f++) count[find_root(parent, s->faces[3u * (size_t)f])]++;
    for (v = 0; v < s->vertices; v++)
        if (count[v] > count[best]) best = v;
    return best;
}

/* Carves, marches and picks the kept component; its counts in *kv, *kf and,
 * with out != NULL, the mesh from the arena's bottom. Scratch from the top is
 * released. */
static ls_status build(const ls_hull_views *views, const ls_hull_params *params, ls_arena *arena, ls_mesh *out,
                       uint32_t counts[4], ls_diag *diag)
{
    uint32_t *kv = counts + 2, *kf = counts + 3;
    ls_arena_mark mark = ls_arena_save(arena);
    hull_grid g;
    hull_surface s;
    uint32_t *parent, *count, root, v, f, c;
    size_t points;
    ls_status st = check_args(views, params, arena, diag);
    if (st != LS_OK) return st;
    st = grid_shape(params, &g, &points);
    if (st != LS_OK) return ls_diag_set(diag, st, "the grid has more than 2^31 points: lower params->resolution", LS_DIAG_NO_INDEX);
    g.f = (ls_real *)ls_arena_scratch(arena, points, sizeof(ls_real));
    g.layer = (uint32_t *)ls_arena_scratch(arena, 14u * (size_t)g.n[0] * g.n[1], sizeof(uint32_t));
    if (g.layer == NULL) goto nomem;
    carve(views, params, &g);
    st = count_surface(&g, &v, &f);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return ls_diag_set(diag, st, "the hull has more than 2^31 vertices or faces: lower params->resolution", LS_DIAG_NO_INDEX);
    }
    if (f == 0) {
        ls_arena_restore(arena, mark);
        return ls_diag_set(diag, LS_ERR_MESH,
                           "no point is inside every view's mask: check the masks (alpha) and that the cameras look at the box",
                           LS_DIAG_NO_INDEX);
    }
    counts[0] = v;
    counts[1] = f;
    s.positions = (ls_real *)ls_arena_scratch(arena, 3u * (size_t)v, sizeof(ls_real));
    s.faces = (uint32_t *)ls_arena_scratch(arena, 3u * (size_t)f, sizeof(uint32_t));
    parent = (uint32_t *)ls_arena_scratch(arena, v, sizeof(uint32_t));
    count = (uint32_t *)ls_arena_scratch(arena, v, sizeof(uint32_t));
    if (count == NULL) goto nomem;
    march(&g, &s);
    root = largest_component(&s, parent, count);
    *kf = count[root];
    *kv = 0;
    for (v = 0; v < s.vertices; v++) /* count: the kept vertices' new numbers */
        count[v] = find_root(parent, v) == root ? (*kv)++ : HULL_NONE;
    if (out != NULL) {
        ls_mesh m;
        st = ls_mesh_alloc(&m, *kv, *kf, arena);
        if (st != LS_OK) goto nomem;
        for (v = 0; v < s.vertices; v++)
            if (count[v] != HULL_NONE)
                for (c = 0; c < 3u; c++) m.positions[3u * (size_t)count[v] + c] = s.positions[3u * (size_t)v + c];
        for (f = 0, root = 0; f < s.face_count; f++)
            if (count[s.faces[3u * (size_t)f]] != HULL_NONE) {
                for (c = 0; c < 3u; c++) m.triangles[3u * (size_t)root + c] = count[s.faces[3u * (size_t)f + c]];
                root++;
            }
        mark.bottom = arena->bottom; /* the mesh stays, the scratch goes */
        ls_arena_restore(arena, mark);
        *out = m;
        return LS_OK;
    }
    ls_arena_restore(arena, mark);
    return LS_OK;
nomem:
    ls_arena_restore(arena, mark);
    return ls_diag_set(diag, LS_ERR_NOMEM, "the arena is too small for the visual hull (ls_visual_hull_bytes)", LS_DIAG_NO_INDEX);
}

ls_status ls_visual_hull_bytes(const ls_hull_views *views, const ls_hull_params *params, ls_arena *arena,
                               size_t *bytes, ls_diag *diag)
{
    uint32_t counts[4];
    hull_grid g;
    size_t points, mesh;
    ls_size total;
    ls_status st;
    if (bytes == NULL) return ls_invalid_arg(diag, "bytes must not be NULL");
    st = build(views, params, arena, NULL, counts, diag);
    if (st != LS_OK) return st;
    (void)grid_shape(params, &g, &points);
    ls_size_init(&total); /* as build allocates */
    ls_size_add(&total, points, sizeof(ls_real));
    ls_size_add(&total, 14u * (size_t)g.n[0] * g.n[1], sizeof(uint32_t));
    ls_size_add(&total, 3u * (size_t)counts[0], sizeof(ls_real));
    ls_size_add(&total, 3u * (size_t)counts[1], sizeof(uint32_t));
    ls_size_add(&total, counts[0], sizeof(uint32_t));
    ls_size_add(&total, counts[0], sizeof(uint32_t));
    st = ls_mesh_bytes(counts[2], counts[3], &mesh);
    if (st == LS_OK) ls_size_add(&total, mesh, 1);
    if (st != LS_OK || total.overflow) return ls_diag_set(diag, LS_ERR_TOO_LARGE, "the hull's bytes overflow size_t", LS_DIAG_NO_INDEX);
    *bytes = total.bytes;
    return LS_OK;
}

ls_status ls_visual_hull(const ls_hull_views *views, const ls_hull_params *params, ls_arena *arena, ls_mesh *out,
                         ls_diag *diag)
{
    uint32_t counts[4];
    if (out == NULL) return ls_invalid_arg(diag, "out must not be NULL");
    return build(views, params, arena, out, counts, diag);
}
