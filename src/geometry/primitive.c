/* primitive.c - icosphere and planar grid meshes. */
#include <largesteps/primitive.h>
#include <largesteps/math.h>

/* The regular icosahedron: vertices (0 or +-1, +-phi) in cyclic order of the
 * axes, faces counter-clockwise seen from outside. */
static const signed char ico_vertex[12][3] = {
    {-1, 2, 0}, {1, 2, 0}, {-1, -2, 0}, {1, -2, 0}, {0, -1, 2}, {0, 1, 2},
    {0, -1, -2}, {0, 1, -2}, {2, 0, -1}, {2, 0, 1}, {-2, 0, -1}, {-2, 0, 1},
}; /* 2 stands for phi */
static const unsigned char ico_face[20][3] = {
    {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1},
};

ls_status ls_icosphere_counts(uint32_t level, uint32_t *vertices, uint32_t *faces, uint32_t *edges)
{
    uint64_t p;
    if (vertices == NULL || faces == NULL || edges == NULL) return LS_ERR_INVALID;
    if (level > LS_ICOSPHERE_MAX_LEVEL) return LS_ERR_TOO_LARGE;
    p = (uint64_t)1 << (2u * level);
    *vertices = (uint32_t)(10u * p + 2u);
    *faces = (uint32_t)(20u * p);
    *edges = (uint32_t)(30u * p);
    return LS_OK;
}

ls_status ls_icosphere_bytes(uint32_t level, size_t *bytes)
{
    uint32_t v, f, e, fp = 0, ep = 0, vp;
    size_t mesh_bytes, edge_bytes = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    st = ls_icosphere_counts(level, &v, &f, &e);
    if (st == LS_OK) st = ls_mesh_bytes(v, f, &mesh_bytes);
    if (st == LS_OK && level > 0) st = ls_icosphere_counts(level - 1u, &vp, &fp, &ep);
    if (st == LS_OK && level > 0) st = ls_mesh_edges_bytes(fp, ep, &edge_bytes);
    if (st != LS_OK) return st;
    return ls_size_sum(mesh_bytes, edge_bytes, bytes);
}

/* Position of the edge (a, b), a < b, in the sorted edge table. */
static uint32_t find_edge(const ls_mesh_edges *edges, uint32_t a, uint32_t b)
{
    uint32_t lo = 0, hi = edges->count;
    if (a > b) {
        uint32_t t = a;
        a = b;
        b = t;
    }
    while (hi - lo > 1u) {
        uint32_t mid = lo + (hi - lo) / 2u;
        uint32_t ma = edges->v[2u * (size_t)mid], mb = edges->v[2u * (size_t)mid + 1u];
        if (ma < a || (ma == a && mb <= b))
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static void set_unit(ls_real *p, ls_real x, ls_real y, ls_real z)
{
    ls_real r = LS_RSQRT(x * x + y * y + z * z);
    p[0] = x / r;
    p[1] = y / r;
    p[2] = z / r;
}

/* One subdivision in place: the level's faces (the first `faces` of the
 * array) become 4 * faces, and one vertex per edge is appended after the
 * `vertices` existing ones. Faces are expanded from the last one down so that
 * no unread face is overwritten (face f writes faces 4f..4f+3 >= f). */
static void subdivide(ls_mesh *m, uint32_t vertices, uint32_t faces, const ls_mesh_edges *edges)
{
    uint32_t e, f;
    for (e = 0; e < edges->count; e++) {
        const ls_real *a = m->positions + 3u * (size_t)edges->v[2u * (size_t)e];
        const ls_real *b = m->positions + 3u * (size_t)edges->v[2u * (size_t)e + 1u];
        set_unit(m->positions + 3u * ((size_t)vertices + e), a[0] + b[0], a[1] + b[1], a[2] + b[2]);
    }
    for (f = faces; f-- > 0;) {
        uint32_t *t = m->triangles + 3u * (size_t)f, *o = m->triangles + 12u * (size_t)f;
        uint32_t a = t[0], b = t[1], c = t[2];
        uint32_t ab = vertices + find_edge(edges, a, b), bc = vertices + find_edge(edges, b, c);
        uint32_t ca = vertices + find_edge(edges, c, a);
        o[0] = a, o[1] = ab, o[2] = ca;
        o[3] = b, o[4] = bc, o[5] = ab;
        o[6] = c, o[7] = ca, o[8] = bc;
        o[9] = ab, o[10] = bc, o[11] = ca;
    }
}

ls_status ls_icosphere(uint32_t level, ls_arena *arena, ls_mesh *mesh)
{
    const ls_real phi = ((ls_real)1 + LS_RSQRT((ls_real)5)) / (ls_real)2;
    ls_arena_mark mark;
    ls_mesh m;
    uint32_t v, f, e, l, i, k;
    ls_status st;
    if (arena == NULL || mesh == NULL) return LS_ERR_INVALID;
    st = ls_icosphere_counts(level, &v, &f, &e);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    st = ls_mesh_alloc(&m, v, f, arena);
    if (st != LS_OK) return st;
    for (i = 0; i < 12u; i++) {
        ls_real c[3];
        for (k = 0; k < 3u; k++)
            c[k] = ico_vertex[i][k] == 2 ? phi : ico_vertex[i][k] == -2 ? -phi : (ls_real)ico_vertex[i][k];
        set_unit(m.positions + 3u * (size_t)i, c[0], c[1], c[2]);
    }
    for (i = 0; i < 20u; i++)
        for (k = 0; k < 3u; k++) m.triangles[3u * (size_t)i + k] = ico_face[i][k];
    for (l = 0; l < level; l++) {
        ls_arena_mark level_mark = ls_arena_save(arena);
        ls_mesh cur = m;
        ls_mesh_edges edges;
        uint32_t vl, fl, el;
        (void)ls_icosphere_counts(l, &vl, &fl, &el);
        cur.vertex_count = vl;
        cur.face_count = fl;
        st = ls_mesh_edges_build(&cur, arena, &edges, NULL);
        if (st != LS_OK) {
            ls_arena_restore(arena, mark);
            return st;
        }
        subdivide(&m, vl, fl, &edges);
        ls_arena_restore(arena, level_mark);
    }
    *mesh = m;
    return LS_OK;
}

ls_status ls_grid_mesh_bytes(uint32_t nx, uint32_t ny, size_t *bytes)
{
    uint64_t v, f;
    if (bytes == NULL || nx == 0 || ny == 0) return LS_ERR_INVALID;
    v = ((uint64_t)nx + 1u) * ((uint64_t)ny + 1u);
    f = 2u * (uint64_t)nx * (uint64_t)ny;
    if (v > UINT32_MAX || f > UINT32_MAX) return LS_ERR_TOO_LARGE;
    return ls_mesh_bytes((uint32_t)v, (uint32_t)f, bytes);
}

ls_status ls_grid_mesh(uint32_t nx, uint32_t ny, ls_arena *arena, ls_mesh *mesh)
{
    ls_mesh m;
    size_t bytes;
    uint32_t i, j;
    ls_status st;
    if (arena == NULL || mesh == NULL) return LS_ERR_INVALID;
    st = ls_grid_mesh_bytes(nx, ny, &bytes);
    if (st != LS_OK) return st;
    st = ls_mesh_alloc(&m, (nx + 1u) * (ny + 1u), 2u * nx * ny, arena);
    if (st != LS_OK) return st;
    for (j = 0; j <= ny; j++)
        for (i = 0; i <= nx; i++) {
            ls_real *p = m.positions + 3u * ((size_t)j * (nx + 1u) + i);
            p[0] = (ls_real)i / (ls_real)nx;
            p[1] = (ls_real)j / (ls_real)ny;
            p[2] = (ls_real)0;
        }
    for (j = 0; j < ny; j++)
        for (i = 0; i < nx; i++) {
            uint32_t v00 = j * (nx + 1u) + i, v10 = v00 + 1u, v01 = v00 + nx + 1u, v11 = v01 + 1u;
            uint32_t *t = m.triangles + 6u * ((size_t)j * nx + i);
            t[0] = v00, t[1] = v10, t[2] = v11;
            t[3] = v00, t[4] = v11, t[5] = v01;
        }
    *mesh = m;
    return LS_OK;
}
