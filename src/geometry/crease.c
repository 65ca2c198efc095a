/* crease.c - a mesh's vertices split along its creases (ls_mesh_split_creases),
 * so that vertex normals shade a CAD part's creases sharp and its curved
 * faces smooth, and its creases counted (ls_mesh_count_creases). */
#include <largesteps/mesh.h>
#include <largesteps/sort.h>
#include "../base/diag_internal.h"
#include "mesh_internal.h"
#include <string.h>
#include <math.h>

#if LS_REAL_IS_FLOAT
#define REAL_SQRT sqrtf
#else
#define REAL_SQRT sqrt
#endif

ls_status ls_mesh_split_creases_bytes(uint32_t vertex_count, uint32_t face_count, size_t *bytes)
{
    ls_size s;
    size_t h = 3u * (size_t)face_count, mesh_bytes;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (face_count > MAX_VALIDATE_FACES || vertex_count > UINT32_MAX - 3u * face_count) return LS_ERR_TOO_LARGE;
    st = ls_mesh_bytes(vertex_count + 3u * face_count, face_count, &mesh_bytes);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    ls_size_add(&s, mesh_bytes, 1);
    ls_size_add(&s, h, sizeof(uint64_t)); /* edge keys */
    ls_size_add(&s, h, sizeof(uint32_t)); /* half-edges in key order */
    ls_size_add(&s, h, sizeof(uint32_t)); /* sort scratch, then each corner's vertex */
    ls_size_add(&s, h, sizeof(uint32_t)); /* corner groups (union-find) */
    ls_size_add(&s, vertex_count, sizeof(uint32_t)); /* vertices given to a group */
    return ls_size_get(&s, bytes);
}

/* Whether faces f and g meet at less than the crease angle: their normals'
 * cosine at least crease_cos (a degenerate face joins its neighbours). */
static int smooth_across(const ls_mesh *m, uint32_t f, uint32_t g, ls_real crease_cos)
{
    ls_real a[3], b[3], dot, len;
    ls_mesh_impl_face_cross(m->positions, m->triangles + 3u * (size_t)f, a);
    ls_mesh_impl_face_cross(m->positions, m->triangles + 3u * (size_t)g, b);
    dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    len = REAL_SQRT(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * REAL_SQRT(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    return !(dot < crease_cos * len);
}

/* The arguments of the crease functions checked, then the usable faces'
 * half-edges from the top of the arena, sorted by edge (keys, idx; tmp is
 * free for the caller after). On an error the arena is as it was. */
static ls_status sorted_half_edges(const ls_mesh *in, ls_real crease_cos, ls_arena *arena, ls_diag *diag,
                                   uint64_t **keys, uint32_t **idx, uint32_t **tmp, size_t *nh)
{
    const size_t h = 3u * (size_t)(in == NULL ? 0 : in->face_count);
    ls_arena_mark mark;
    uint32_t bad;
    if (ls_mesh_impl_problem(in) != NULL) return ls_invalid_arg(diag, ls_mesh_impl_problem(in));
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (!(crease_cos >= -1 && crease_cos <= 1)) return ls_invalid_arg(diag, "crease_cos is not in [-1, 1]");
    if (in->face_count > MAX_VALIDATE_FACES || in->vertex_count > UINT32_MAX - 3u * in->face_count)
        return LS_ERR_TOO_LARGE;
    bad = ls_mesh_impl_first_bad_face(in);
    if (bad != LS_MESH_NONE) {
        (void)ls_diag_set(diag, LS_ERR_MESH, "face index out of range", bad);
        return LS_ERR_MESH;
    }
    mark = ls_arena_save(arena);
    *keys = (uint64_t *)ls_arena_scratch(arena, h, sizeof(uint64_t));
    *idx = *keys == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    *tmp = *idx == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    if (*tmp == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    *nh = ls_mesh_impl_half_edges(in, *keys, *idx);
    (void)ls_sort_u64(*keys, *idx, *nh, *tmp);
    return LS_OK;
}

/* The next edge from sorted half-edge *i on that has exactly two faces, of
 * opposite directions along it (their first vertices differ): its faces f
 * and g and its key; 0 when none is left. */
static int next_face_pair(const ls_mesh *m, const uint64_t *keys, const uint32_t *idx, size_t nh, size_t *i,
                          uint32_t *f, uint32_t *g, uint64_t *key)
{
    while (*i < nh) {
        const size_t k = *i;
        size_t j = k + 1;
        while (j < nh && keys[idx[j]] == keys[idx[k]]) j++;
        *i = j;
        if (j - k == 2 && m->triangles[idx[k]] != m->triangles[idx[k + 1]]) {
            *f = idx[k] / 3u, *g = idx[k + 1] / 3u, *key = keys[idx[k]];
            return 1;
        }
    }
    return 0;
}

ls_status ls_mesh_count_creases_bytes(uint32_t face_count, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (face_count > MAX_VALIDATE_FACES) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, 3u * (size_t)face_count, sizeof(uint64_t));
    ls_size_add(&s, 3u * (size_t)face_count, sizeof(uint32_t));
    ls_size_add(&s, 3u * (size_t)face_count, sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

ls_status ls_mesh_count_creases(const ls_mesh *in, ls_real crease_cos, ls_arena *arena, uint32_t *creases,
                                uint32_t *edges, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    uint64_t *keys, key;
    uint32_t *idx, *tmp, f, g, nc = 0, ne = 0;
    size_t nh, i = 0;
    ls_status st;
    if (creases == NULL || edges == NULL) return ls_invalid_arg(diag, "creases or edges is NULL");
    mark = arena == NULL ? (ls_arena_mark){0, 0} : ls_arena_save(arena);
    st = sorted_half_edges(in, crease_cos, arena, diag, &keys, &idx, &tmp, &nh);
    if (st != LS_OK) return st;
    while (next_face_pair(in, keys, idx, nh, &i, &f, &g, &key)) {
        ne++;
        if (!smooth_across(in, f, g, crease_cos)) nc++;
    }
    ls_arena_restore(arena, mark);
    *creases = nc;
    *edges = ne;
    return LS_OK;
}

ls_status ls_mesh_split_creases(const ls_mesh *in, ls_real crease_cos, ls_arena *arena, ls_mesh *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    uint64_t *keys, key;
    uint32_t *idx, *tmp, *group, *given, next, c, f, g;
    size_t h, nh, i = 0;
    ls_mesh m;
    ls_status st;
    if (out == NULL) return ls_invalid_arg(diag, "out is NULL");
    mark = arena == NULL ? (ls_arena_mark){0, 0} : ls_arena_save(arena);
    st = sorted_half_edges(in, crease_cos, arena, diag, &keys, &idx, &tmp, &nh);
    if (st != LS_OK) return st;
    h = 3u * (size_t)in->face_count;
    group = (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    given = group == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, in->vertex_count, sizeof(uint32_t));
    if (given == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    /* The corners of a vertex stay one vertex where the two faces of an
     * edge through it meet at less than the crease angle. An edge with one
     * face or more than two, or whose faces disagree on orientation, splits. */
    for (c = 0; c < (uint32_t)h; c++) group[c] = c;
    while (next_face_pair(in, keys, idx, nh, &i, &f, &g, &key)) {
        const uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
        if (smooth_across(in, f, g, crease_cos)) {
            uf_union(group, corner_of(in->triangles, f, a), corner_of(in->triangles, g, a));
            uf_union(group, corner_of(in->triangles, f, b), corner_of(in->triangles, g, b));
        }
    }
    /* A vertex's first group keeps its index; each further group is a new
     * vertex after the input's, in the order of its first corner. */
    memset(given, 0, (size_t)in->vertex_count * sizeof(uint32_t));
    next = in->vertex_count;
    for (c = 0; c < (uint32_t)h; c++) {
        const uint32_t r = uf_find(group, c), v = in->triangles[c];
        if (r != c) {
            tmp[c] = tmp[r];
        } else if (!given[v]) {
            given[v] = 1;
            tmp[c] = v;
        } else {
            tmp[c] = next++;
        }
    }
    st = ls_mesh_alloc(&m, next, in->face_count, arena);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    memcpy(m.positions, in->positions, 3u * (size_t)in->vertex_count * sizeof(ls_real));
    for (c = 0; c < (uint32_t)h; c++) {
        m.triangles[c] = tmp[c];
        if (tmp[c] >= in->vertex_count)
            memcpy(m.positions + 3u * (size_t)tmp[c], in->positions + 3u * (size_t)in->triangles[c], 3u * sizeof(ls_real));
    }
    {   /* release the scratch, keep the mesh */
        ls_arena_mark keep;
        keep.bottom = arena->bottom;
        keep.top = mark.top;
        ls_arena_restore(arena, keep);
    }
    *out = m;
    return LS_OK;
}
