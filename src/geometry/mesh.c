/* mesh.c - indexed triangle meshes: validation, welding, edges, adjacency,
 * normals and bounds (crease.c: splitting at creases). */
#include <largesteps/mesh.h>
#include <largesteps/sort.h>
#include <largesteps/math.h>
#include "../base/diag_internal.h"
#include "mesh_internal.h"
#include <string.h>
#include <math.h>

#if LS_REAL_IS_FLOAT
#define REAL_SQRT sqrtf
#define REAL_ATAN2 ls_atan2f
#else
#define REAL_SQRT sqrt
#define REAL_ATAN2 ls_atan2
#endif

#define MARK 0x80000000u

static void set_diag(ls_diag *diag, ls_status st, const char *what, uint64_t index)
{
    (void)ls_diag_set(diag, st, what, index);
}

static int finite3(const ls_real *p)
{
    return p[0] - p[0] == 0 && p[1] - p[1] == 0 && p[2] - p[2] == 0;
}

ls_status ls_mesh_bytes(uint32_t vertex_count, uint32_t face_count, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)vertex_count * 3u, sizeof(ls_real));
    ls_size_add(&s, (size_t)face_count, 3u * sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

ls_status ls_mesh_alloc(ls_mesh *mesh, uint32_t vertex_count, uint32_t face_count, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_real *p;
    uint32_t *t;
    if (mesh == NULL || arena == NULL) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    p = (ls_real *)ls_arena_alloc(arena, (size_t)vertex_count * 3u, sizeof(ls_real));
    t = p == NULL ? NULL : (uint32_t *)ls_arena_alloc(arena, (size_t)face_count, 3u * sizeof(uint32_t));
    if (t == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    mesh->positions = p;
    mesh->triangles = t;
    mesh->vertex_count = vertex_count;
    mesh->face_count = face_count;
    return LS_OK;
}

/* What is wrong with the mesh argument, or NULL when it is usable. */
const char *ls_mesh_impl_problem(const ls_mesh *mesh)
{
    if (mesh == NULL) return "mesh is NULL";
    if (mesh->vertex_count > 0 && mesh->positions == NULL) return "mesh->positions is NULL with vertex_count > 0";
    if (mesh->face_count > 0 && mesh->triangles == NULL) return "mesh->triangles is NULL with face_count > 0";
    return NULL;
}

static ls_status check_mesh(const ls_mesh *mesh)
{
    return ls_mesh_impl_problem(mesh) == NULL ? LS_OK : LS_ERR_INVALID;
}

/* The first face with an index out of range, or LS_MESH_NONE. */
uint32_t ls_mesh_impl_first_bad_face(const ls_mesh *mesh)
{
    uint32_t f;
    const uint32_t *t = mesh->triangles;
    for (f = 0; f < mesh->face_count; f++) {
        if (t[3 * (size_t)f] >= mesh->vertex_count || t[3 * (size_t)f + 1] >= mesh->vertex_count ||
            t[3 * (size_t)f + 2] >= mesh->vertex_count)
            return f;
    }
    return LS_MESH_NONE;
}

static int usable(const uint32_t *t, uint32_t nv)
{
    return t[0] < nv && t[1] < nv && t[2] < nv && t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
}

/* Fills keys[h] = (min << 32 | max) of each half-edge of the usable faces and
 * lists those half-edges in idx; returns how many. */
size_t ls_mesh_impl_half_edges(const ls_mesh *mesh, uint64_t *keys, uint32_t *idx)
{
    const uint32_t *t = mesh->triangles;
    uint32_t f, k;
    size_t n = 0;
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *tf = t + 3 * (size_t)f;
        if (!usable(tf, mesh->vertex_count)) continue;
        for (k = 0; k < 3; k++) {
            uint32_t a = tf[k], b = tf[k == 2 ? 0 : k + 1];
            uint32_t h = 3u * f + k;
            keys[h] = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
            idx[n++] = h;
        }
    }
    return n;
}

ls_status ls_mesh_validate_bytes(const ls_mesh *mesh, size_t *bytes)
{
    ls_size s;
    size_t h;
    if (bytes == NULL || mesh == NULL) return LS_ERR_INVALID;
    if (mesh->face_count > MAX_VALIDATE_FACES) return LS_ERR_TOO_LARGE;
    h = 3u * (size_t)mesh->face_count;
    ls_size_init(&s);
    ls_size_add(&s, h, sizeof(uint64_t));
    ls_size_add(&s, h, sizeof(uint32_t));
    ls_size_add(&s, h, sizeof(uint32_t));
    ls_size_add(&s, h, sizeof(uint32_t));
    ls_size_add(&s, mesh->vertex_count, sizeof(uint32_t));
    ls_size_add(&s, mesh->vertex_count, sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

static void note_first(uint32_t *count, uint32_t *first, uint32_t index)
{
    (*count)++;
    if (index < *first) *first = index;
}

static void note_edge(uint32_t *count, uint32_t first[2], uint64_t key)
{
    if (*count == 0) {
        first[0] = (uint32_t)(key >> 32);
        first[1] = (uint32_t)key;
    }
    (*count)++;
}

/* Sorted (lo, mid, hi) of a face. */
static void sorted3(const uint32_t *t, uint32_t s[3])
{
    uint32_t a = t[0], b = t[1], c = t[2], x;
    if (a > b) x = a, a = b, b = x;
    if (b > c) x = b, b = c, c = x;
    if (a > b) x = a, a = b, b = x;
    s[0] = a;
    s[1] = b;
    s[2] = c;
}

static void report_init(ls_mesh_report *r, const ls_mesh *mesh)
{
    memset(r, 0, sizeof *r);
    r->vertex_count = mesh->vertex_count;
    r->face_count = mesh->face_count;
    r->first_nonfinite_vertex = LS_MESH_NONE;
    r->first_bad_index_face = LS_MESH_NONE;
    r->first_degenerate_face = LS_MESH_NONE;
    r->first_zero_area_face = LS_MESH_NONE;
    r->first_duplicate_face = LS_MESH_NONE;
    r->first_unreferenced_vertex = LS_MESH_NONE;
    r->first_boundary_edge[0] = r->first_boundary_edge[1] = LS_MESH_NONE;
    r->first_nonmanifold_edge[0] = r->first_nonmanifold_edge[1] = LS_MESH_NONE;
    r->first_orientation_conflict[0] = r->first_orientation_conflict[1] = LS_MESH_NONE;
    r->first_nonmanifold_vertex = LS_MESH_NONE;
}

/* Per-face checks: indices, degeneracy, zero area. */
static void validate_faces(const ls_mesh *mesh, ls_mesh_report *r)
{
    uint32_t f, v;
    const uint32_t nv = mesh->vertex_count;
    const ls_real *p = mesh->positions;
    for (v = 0; v < nv; v++) {
        if (!finite3(p + 3 * (size_t)v)) note_first(&r->nonfinite_vertices, &r->first_nonfinite_vertex, v);
    }
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *t = mesh->triangles + 3 * (size_t)f;
        const ls_real *a, *b, *c;
        ls_real u[3], w[3];
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) {
            note_first(&r->bad_index_faces, &r->first_bad_index_face, f);
            continue;
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            note_first(&r->degenerate_faces, &r->first_degenerate_face, f);
            continue;
        }
        r->usable_faces++;
        a = p + 3 * (size_t)t[0];
        b = p + 3 * (size_t)t[1];
        c = p + 3 * (size_t)t[2];
        if (!finite3(a) || !finite3(b) || !finite3(c)) continue;
        u[0] = b[0] - a[0], u[1] = b[1] - a[1], u[2] = b[2] - a[2];
        w[0] = c[0] - a[0], w[1] = c[1] - a[1], w[2] = c[2] - a[2];
        if (u[1] * w[2] - u[2] * w[1] == 0 && u[2] * w[0] - u[0] * w[2] == 0 && u[0] * w[1] - u[1] * w[0] == 0)
            note_first(&r->zero_area_faces, &r->first_zero_area_face, f);
    }
}

/* Duplicate faces: usable faces sorted by their sorted index triple. */
static void validate_duplicates(const ls_mesh *mesh, ls_mesh_report *r, uint32_t *keys, uint32_t *idx, uint32_t *tmp)
{
    uint32_t f, pass, n = 0, i;
    for (f = 0; f < mesh->face_count; f++) {
        if (usable(mesh->triangles + 3 * (size_t)f, mesh->vertex_count)) idx[n++] = f;
    }
    for (pass = 0; pass < 3; pass++) {
        for (i = 0; i < n; i++) {
            uint32_t s[3];
            sorted3(mesh->triangles + 3 * (size_t)idx[i], s);
            keys[idx[i]] = s[2 - pass];
        }
        (void)ls_sort_u32(keys, idx, n, tmp);
    }
    for (i = 1; i < n; i++) {
        uint32_t s[3], q[3];
        sorted3(mesh->triangles + 3 * (size_t)idx[i - 1], q);
        sorted3(mesh->triangles + 3 * (size_t)idx[i], s);
        if (s[0] == q[0] && s[1] == q[1] && s[2] == q[2])
            note_first(&r->duplicate_faces, &r->first_duplicate_face, idx[i]);
    }
}

ls_status ls_mesh_validate(const ls_mesh *mesh, ls_arena *arena, ls_mesh_report *report)
{
    ls_mesh_report r;
    ls_arena_mark mark;
    uint64_t *ekey;
    uint32_t *idx, *tmp, *cpar, *vpar, *vflag, v, f, k;
    size_t h, nh, i, j;
    const uint32_t *t;
    uint32_t nv;
    ls_status st = check_mesh(mesh);
    if (st != LS_OK || arena == NULL || report == NULL) return LS_ERR_INVALID;
    if (mesh->face_count > MAX_VALIDATE_FACES) return LS_ERR_TOO_LARGE;
    nv = mesh->vertex_count;
    t = mesh->triangles;
    h = 3u * (size_t)mesh->face_count;
    mark = ls_arena_save(arena);
    ekey = (uint64_t *)ls_arena_scratch(arena, h, sizeof(uint64_t));
    idx = ekey == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    tmp = idx == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    cpar = tmp == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    vpar = cpar == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nv, sizeof(uint32_t));
    vflag = vpar == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nv, sizeof(uint32_t));
    if (vflag == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    report_init(&r, mesh);
    validate_faces(mesh, &r);

    nh = ls_mesh_impl_half_edges(mesh, ekey, idx);
    (void)ls_sort_u64(ekey, idx, nh, tmp);
    for (i = 0; i < h; i++) cpar[i] = (uint32_t)i;
    for (v = 0; v < nv; v++) vpar[v] = v;
    for (i = 0; i < nh; i = j) {
        uint64_t key = ekey[idx[i]];
        uint32_t lo = (uint32_t)(key >> 32), hi = (uint32_t)key;
        for (j = i + 1; j < nh && ekey[idx[j]] == key; j++) {
        }
        r.edge_count++;
        uf_union(vpar, lo, hi);
        if (j - i == 1) {
            note_edge(&r.boundary_edges, r.first_boundary_edge, key);
        } else if (j - i == 2) {
            uint32_t f1 = idx[i] / 3u, f2 = idx[i + 1] / 3u;
            if (t[idx[i]] == t[idx[i + 1]]) note_edge(&r.orientation_conflicts, r.first_orientation_conflict, key);
            uf_union(cpar, corner_of(t, f1, lo), corner_of(t, f2, lo));
            uf_union(cpar, corner_of(t, f1, hi), corner_of(t, f2, hi));
        } else {
            note_edge(&r.nonmanifold_edges, r.first_nonmanifold_edge, key);
        }
    }
    /* fans around each vertex: its corners should share one root */
    for (v = 0; v < nv; v++) vflag[v] = LS_MESH_NONE;
    for (f = 0; f < mesh->face_count; f++) {
        if (!usable(t + 3 * (size_t)f, nv)) continue;
        for (k = 0; k < 3; k++) {
            uint32_t c = 3u * f + k, root = uf_find(cpar, c);
            v = t[c];
            if (vflag[v] == LS_MESH_NONE) {
                vflag[v] = root;
            } else if ((vflag[v] & MARK) == 0 && vflag[v] != root) {
                vflag[v] |= MARK;
                note_first(&r.nonmanifold_vertices, &r.first_nonmanifold_vertex, v);
            }
        }
    }
    for (v = 0; v < nv; v++) {
        if (vflag[v] == LS_MESH_NONE) {
            note_first(&r.unreferenced_vertices, &r.first_unreferenced_vertex, v);
            vflag[v] = 0;
        } else {
            vflag[v] = 1;
            if (uf_find(vpar, v) == v) r.components++;
        }
    }
    r.used_vertices = nv - r.unreferenced_vertices;
    /* boundary loops: components of the boundary edges */
    for (v = 0; v < nv; v++) vpar[v] = v;
    for (i = 0; i < nh; i = j) {
        uint64_t key = ekey[idx[i]];
        for (j = i + 1; j < nh && ekey[idx[j]] == key; j++) {
        }
        if (j - i == 1) {
            uint32_t lo = (uint32_t)(key >> 32), hi = (uint32_t)key;
            uf_union(vpar, lo, hi);
            vflag[lo] |= 2u;
            vflag[hi] |= 2u;
        }
    }
    for (v = 0; v < nv; v++) {
        if ((vflag[v] & 2u) != 0 && uf_find(vpar, v) == v) r.boundary_loops++;
    }
    validate_duplicates(mesh, &r, (uint32_t *)ekey, idx, tmp);
    r.euler = (int64_t)r.used_vertices - (int64_t)r.edge_count + (int64_t)r.usable_faces;
    if (r.usable_faces > 0 && r.nonmanifold_edges == 0 && r.nonmanifold_vertices == 0 && r.orientation_conflicts == 0) {
        int64_t g2 = 2 * (int64_t)r.components - r.euler - (int64_t)r.boundary_loops;
        if (g2 >= 0 && g2 % 2 == 0 && g2 / 2 <= INT32_MAX) {
            r.has_genus = 1;
            r.genus = (int32_t)(g2 / 2);
        }
    }
    ls_arena_restore(arena, mark);
    *report = r;
    return LS_OK;
}

ls_status ls_mesh_require(const ls_mesh_report *r, uint32_t flags, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (r == NULL) return ls_invalid_arg(diag, "r is NULL");
    if ((flags & LS_MESH_REQ_INDICES) && r->bad_index_faces > 0) {
        set_diag(diag, LS_ERR_MESH, "face index out of range", r->first_bad_index_face);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_FINITE) && r->nonfinite_vertices > 0) {
        set_diag(diag, LS_ERR_NONFINITE, "vertex with a NaN or infinite coordinate", r->first_nonfinite_vertex);
        return LS_ERR_NONFINITE;
    }
    if ((flags & LS_MESH_REQ_NONEMPTY) && r->usable_faces == 0) {
        set_diag(diag, LS_ERR_MESH, "no usable triangle", 0);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_NONDEGENERATE) && r->degenerate_faces > 0) {
        set_diag(diag, LS_ERR_MESH, "degenerate face (repeated vertex index)", r->first_degenerate_face);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_NONDEGENERATE) && r->zero_area_faces > 0) {
        set_diag(diag, LS_ERR_MESH, "zero-area face", r->first_zero_area_face);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_MANIFOLD) && r->nonmanifold_edges > 0) {
        set_diag(diag, LS_ERR_MESH, "non-manifold edge (three or more faces); index = its first vertex", r->first_nonmanifold_edge[0]);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_MANIFOLD) && r->nonmanifold_vertices > 0) {
        set_diag(diag, LS_ERR_MESH, "non-manifold vertex (faces form several fans)", r->first_nonmanifold_vertex);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_MANIFOLD) && r->orientation_conflicts > 0) {
        set_diag(diag, LS_ERR_MESH, "inconsistent orientation across an edge; index = its first vertex", r->first_orientation_conflict[0]);
        return LS_ERR_MESH;
    }
    if ((flags & LS_MESH_REQ_CLOSED) && r->boundary_edges > 0) {
        set_diag(diag, LS_ERR_MESH, "boundary edge (mesh not closed); index = its first vertex", r->first_boundary_edge[0]);
        return LS_ERR_MESH;
    }
    return LS_OK;
}

/* --- welding ------------------------------------------------------------ */

ls_status ls_mesh_unweld_bytes(uint32_t face_count, size_t *bytes)
{
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (face_count > UINT32_MAX / 3u) return LS_ERR_TOO_LARGE;
    return ls_mesh_bytes(3u * face_count, face_count, bytes);
}

ls_status ls_mesh_unweld(const ls_mesh *in, ls_arena *arena, ls_mesh *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_mesh m;
    uint32_t bad, f, k;
    ls_status st;
    if (check_mesh(in) != LS_OK) return ls_invalid_arg(diag, ls_mesh_impl_problem(in));
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (out == NULL) return ls_invalid_arg(diag, "out is NULL");
    if (in->face_count > UINT32_MAX / 3u) return LS_ERR_TOO_LARGE;
    bad = ls_mesh_impl_first_bad_face(in);
    if (bad != LS_MESH_NONE) {
        set_diag(diag, LS_ERR_MESH, "face index out of range", bad);
        return LS_ERR_MESH;
    }
    st = ls_mesh_alloc(&m, 3u * in->face_count, in->face_count, arena);
    if (st != LS_OK) return st;
    for (f = 0; f < in->face_count; f++)
        for (k = 0; k < 3u; k++) {
            const size_t c = 3u * (size_t)f + k;
            memcpy(m.positions + 3u * c, in->positions + 3u * (size_t)in->triangles[c], 3u * sizeof(ls_real));
            m.triangles[c] = (uint32_t)c;
        }
    *out = m;
    return LS_OK;
}

ls_status ls_mesh_weld_bytes(const ls_mesh *mesh, size_t *bytes)
{
    ls_size s;
    if (mesh == NULL || bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, mesh->vertex_count, sizeof(uint64_t));
    ls_size_add(&s, mesh->vertex_count, sizeof(uint32_t));
    ls_size_add(&s, mesh->vertex_count, sizeof(uint32_t));
    ls_size_add(&s, mesh->vertex_count, sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

/* The bits of a coordinate as a sort key, with -0 mapped to +0. */
static uint64_t coord_key(ls_real x)
{
#if LS_REAL_IS_FLOAT
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    if ((b & 0x7fffffffu) == 0) b = 0;
    return b;
#else
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    if ((b & 0x7fffffffffffffffu) == 0) b = 0;
    return b;
#endif
}

ls_status ls_mesh_weld(ls_mesh *mesh, ls_arena *arena, uint32_t *remap, uint32_t *removed)
{
    ls_arena_mark mark;
    uint64_t *keys;
    uint32_t *idx, *tmp, *rep, nv, v, next = 0, i, axis;
    size_t c;
    ls_real *p;
    if (check_mesh(mesh) != LS_OK || arena == NULL) return LS_ERR_INVALID;
    if (ls_mesh_impl_first_bad_face(mesh) != LS_MESH_NONE) return LS_ERR_MESH;
    nv = mesh->vertex_count;
    p = mesh->positions;
    mark = ls_arena_save(arena);
    keys = (uint64_t *)ls_arena_scratch(arena, nv, sizeof(uint64_t));
    idx = keys == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nv, sizeof(uint32_t));
    tmp = idx == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nv, sizeof(uint32_t));
    rep = tmp == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nv, sizeof(uint32_t));
    if (rep == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    for (v = 0; v < nv; v++) idx[v] = v;
    for (axis = 3; axis-- > 0;) {
        for (v = 0; v < nv; v++) keys[v] = coord_key(p[3 * (size_t)v + axis]);
        (void)ls_sort_u64(keys, idx, nv, tmp);
    }
    /* runs of equal positions: the first (lowest index) represents them */
    for (i = 0; i < nv; i++) {
        const ls_real *a = p + 3 * (size_t)idx[i];
        const ls_real *b = i > 0 ? p + 3 * (size_t)idx[i - 1] : NULL;
        if (b != NULL && a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) {
            rep[idx[i]] = rep[idx[i - 1]];
        } else {
            rep[idx[i]] = idx[i];
        }
    }
    /* new indices in order of the kept vertices; rep becomes the new index */
    for (v = 0; v < nv; v++) {
        uint32_t r = rep[v];
        if (r == v) {
            if (next != v) memmove(p + 3 * (size_t)next, p + 3 * (size_t)v, 3 * sizeof(ls_real));
            rep[v] = next++;
        } else {
            rep[v] = rep[r];
        }
    }
    for (c = 0; c < 3 * (size_t)mesh->face_count; c++) mesh->triangles[c] = rep[mesh->triangles[c]];
    if (remap != NULL) memcpy(remap, rep, (size_t)nv * sizeof(uint32_t));
    if (removed != NULL) *removed = nv - next;
    mesh->vertex_count = next;
    ls_arena_restore(arena, mark);
    return LS_OK;
}

/* --- spatial order --------------------------------------------------------- */

ls_status ls_mesh_reorder_bytes(uint32_t vertex_count, uint32_t face_count, size_t *bytes)
{
    ls_size s, perm, tris;
    if (bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, face_count, sizeof(uint32_t)); /* keys (30-bit Morton codes) */
    ls_size_add(&s, face_count, sizeof(uint32_t)); /* order */
    ls_size_add(&s, face_count, sizeof(uint32_t)); /* the sort's scratch */
    ls_size_add(&s, vertex_count, sizeof(uint32_t)); /* new vertex indices */
    /* one buffer for the old positions, then the old triangles */
    ls_size_init(&perm);
    ls_size_add(&perm, vertex_count, 3 * sizeof(ls_real));
    ls_size_init(&tris);
    ls_size_add(&tris, face_count, 3 * sizeof(uint32_t));
    ls_size_max(&perm, &tris);
    ls_size_add_size(&s, &perm);
    return ls_size_get(&s, bytes);
}

/* The 10 low bits of x spread to every third bit (Morton interleaving). */
static uint32_t spread10(uint32_t x)
{
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

/* (v - lo) * inv as a cell 0..1023 (NaN and below: 0). */
static uint32_t cell10(ls_real v, ls_real lo, ls_real inv)
{
    ls_real t = (v - lo) * inv;
    if (!(t > 0)) return 0;
    return t >= (ls_real)1023 ? 1023u : (uint32_t)t;
}

ls_status ls_mesh_reorder(ls_mesh *mesh, ls_arena *arena, uint32_t *remap)
{
    ls_arena_mark mark;
    ls_real lo[3], hi[3], inv[3];
    uint32_t *keys, *order, *tmp, *vmap, nv, nf, f, v, next = 0;
    size_t nbuf, c;
    void *buf;
    int k;
    if (check_mesh(mesh) != LS_OK || arena == NULL) return LS_ERR_INVALID;
    if (ls_mesh_impl_first_bad_face(mesh) != LS_MESH_NONE) return LS_ERR_MESH;
    nv = mesh->vertex_count;
    nf = mesh->face_count;
    if (nf == 0) { /* every vertex unused: the order stays */
        for (v = 0; remap != NULL && v < nv; v++) remap[v] = v;
        return LS_OK;
    }
    nbuf = 3 * (size_t)nv * sizeof(ls_real) > 3 * (size_t)nf * sizeof(uint32_t) ? 3 * (size_t)nv * sizeof(ls_real)
                                                                                : 3 * (size_t)nf * sizeof(uint32_t);
    mark = ls_arena_save(arena);
    keys = (uint32_t *)ls_arena_scratch(arena, nf, sizeof(uint32_t));
    order = keys == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nf, sizeof(uint32_t));
    tmp = order == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nf, sizeof(uint32_t));
    vmap = tmp == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, nv, sizeof(uint32_t));
    buf = vmap == NULL ? NULL : ls_arena_scratch(arena, nbuf, 1);
    if (buf == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    /* centroids are summed, not divided: cells over 3 x the box */
    if (ls_mesh_bounds(mesh, lo, hi) != LS_OK) lo[0] = lo[1] = lo[2] = hi[0] = hi[1] = hi[2] = 0;
    for (k = 0; k < 3; k++) {
        ls_real ext = (ls_real)3 * (hi[k] - lo[k]);
        inv[k] = ext > 0 ? (ls_real)1024 / ext : (ls_real)0;
        lo[k] *= (ls_real)3;
    }
    for (f = 0; f < nf; f++) {
        const uint32_t *t = mesh->triangles + 3 * (size_t)f;
        uint32_t code = 0;
        for (k = 0; k < 3; k++) {
            ls_real sum = (mesh->positions[3 * (size_t)t[0] + (size_t)k] + mesh->positions[3 * (size_t)t[1] + (size_t)k]) +
                          mesh->positions[3 * (size_t)t[2] + (size_t)k];
            code |= spread10(cell10(sum, lo[k], inv[k])) << k;
        }
        keys[f] = code;
        order[f] = f;
    }
    (void)ls_sort_u32(keys, order, nf, tmp); /* stable: equal codes keep their order */
    /* vertices by first use, the unused ones after them in their order */
    for (v = 0; v < nv; v++) vmap[v] = LS_MESH_NONE;
    for (f = 0; f < nf; f++)
        for (k = 0; k < 3; k++) {
            uint32_t *m = &vmap[mesh->triangles[3 * (size_t)order[f] + (size_t)k]];
            if (*m == LS_MESH_NONE) *m = next++;
        }
    for (v = 0; v < nv; v++)
        if (vmap[v] == LS_MESH_NONE) vmap[v] = next++;
    memcpy(buf, mesh->positions, 3 * (size_t)nv * sizeof(ls_real));
    for (v = 0; v < nv; v++) memcpy(mesh->positions + 3 * (size_t)vmap[v], (const ls_real *)buf + 3 * (size_t)v,
                                    3 * sizeof(ls_real));
    memcpy(buf, mesh->triangles, 3 * (size_t)nf * sizeof(uint32_t));
    for (f = 0; f < nf; f++)
        for (c = 0; c < 3; c++)
            mesh->triangles[3 * (size_t)f + c] = vmap[((const uint32_t *)buf)[3 * (size_t)order[f] + c]];
    if (remap != NULL) memcpy(remap, vmap, (size_t)nv * sizeof(uint32_t));
    ls_arena_restore(arena, mark);
    return LS_OK;
}

/* --- edges and adjacency ------------------------------------------------- */

ls_status ls_mesh_edges_bytes(uint32_t face_count, uint32_t edge_count, size_t *bytes)
{
    ls_size s;
    size_t h = 3u * (size_t)face_count;
    if (bytes == NULL) return LS_ERR_INVALID;
    if (face_count > MAX_VALIDATE_FACES) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, h, sizeof(uint64_t));
    ls_size_add(&s, h, sizeof(uint32_t));
    ls_size_add(&s, h, sizeof(uint32_t));
    ls_size_add(&s, (size_t)edge_count, 2u * sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

ls_status ls_mesh_edges_build(const ls_mesh *mesh, ls_arena *arena, ls_mesh_edges *edges, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    uint64_t *keys;
    uint32_t *idx, *tmp, *out, bad, count = 0;
    size_t h, nh, i;
    if (check_mesh(mesh) != LS_OK) return ls_invalid_arg(diag, ls_mesh_impl_problem(mesh));
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (edges == NULL) return ls_invalid_arg(diag, "edges is NULL");
    if (mesh->face_count > MAX_VALIDATE_FACES) return LS_ERR_TOO_LARGE;
    bad = ls_mesh_impl_first_bad_face(mesh);
    if (bad != LS_MESH_NONE) {
        set_diag(diag, LS_ERR_MESH, "face index out of range", bad);
        return LS_ERR_MESH;
    }
    h = 3u * (size_t)mesh->face_count;
    mark = ls_arena_save(arena);
    keys = (uint64_t *)ls_arena_scratch(arena, h, sizeof(uint64_t));
    idx = keys == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    tmp = idx == NULL ? NULL : (uint32_t *)ls_arena_scratch(arena, h, sizeof(uint32_t));
    if (tmp == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    nh = ls_mesh_impl_half_edges(mesh, keys, idx);
    (void)ls_sort_u64(keys, idx, nh, tmp);
    for (i = 0; i < nh; i++) {
        if (i == 0 || keys[idx[i]] != keys[idx[i - 1]]) count++;
    }
    out = (uint32_t *)ls_arena_alloc(arena, (size_t)count, 2u * sizeof(uint32_t));
    if (out == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    count = 0;
    for (i = 0; i < nh; i++) {
        uint64_t key = keys[idx[i]];
        if (i > 0 && key == keys[idx[i - 1]]) continue;
        out[2 * (size_t)count] = (uint32_t)(key >> 32);
        out[2 * (size_t)count + 1] = (uint32_t)key;
        count++;
    }
    /* release the scratch, keep the edges */
    {
        ls_arena_mark keep;
        keep.bottom = arena->bottom;
        keep.top = mark.top;
        ls_arena_restore(arena, keep);
    }
    edges->v = out;
    edges->count = count;
    return LS_OK;
}

ls_status ls_mesh_adjacency_bytes(uint32_t vertex_count, uint32_t edge_count, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)vertex_count + 1u, sizeof(uint32_t));
    ls_size_add(&s, (size_t)edge_count, 2u * sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

ls_status ls_mesh_adjacency_build(const ls_mesh_edges *edges, uint32_t vertex_count, ls_arena *arena,
                                  ls_mesh_adjacency *adjacency)
{
    ls_arena_mark mark;
    uint32_t *off, *nb, v;
    size_t e, m;
    if (edges == NULL || arena == NULL || adjacency == NULL || (edges->count > 0 && edges->v == NULL))
        return LS_ERR_INVALID;
    m = 2u * (size_t)edges->count;
    for (e = 0; e < m; e++) {
        if (edges->v[e] >= vertex_count) return LS_ERR_INVALID;
    }
    mark = ls_arena_save(arena);
    off = (uint32_t *)ls_arena_alloc(arena, (size_t)vertex_count + 1u, sizeof(uint32_t));
    nb = off == NULL ? NULL : (uint32_t *)ls_arena_alloc(arena, (size_t)edges->count, 2u * sizeof(uint32_t));
    if (nb == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    memset(off, 0, ((size_t)vertex_count + 1u) * sizeof(uint32_t));
    for (e = 0; e < m; e++) off[edges->v[e] + 1u]++;
    for (v = 0; v < vertex_count; v++) off[v + 1u] += off[v];
    /* off[v] is the fill cursor of v; edges sorted by (a, b) fill each row in increasing order */
    for (e = 0; e < edges->count; e++) {
        uint32_t a = edges->v[2 * e], b = edges->v[2 * e + 1];
        nb[off[a]++] = b;
        nb[off[b]++] = a;
    }
    for (v = vertex_count; v > 0; v--) off[v] = off[v - 1];
    off[0] = 0;
    adjacency->offsets = off;
    adjacency->neighbors = nb;
    adjacency->vertex_count = vertex_count;
    return LS_OK;
}

/* --- normals and bounds --------------------------------------------------- */

static ls_real real_abs(ls_real x)
{
    return x < 0 ? -x : x;
}

/* Normalises v in place (scaled first, so no overflow or underflow); a zero
 * or non-finite vector becomes (0, 0, 0). Returns the length before. */
static ls_real normalize3(ls_real v[3])
{
    ls_real m = real_abs(v[0]), len;
    if (real_abs(v[1]) > m) m = real_abs(v[1]);
    if (real_abs(v[2]) > m) m = real_abs(v[2]);
    if (!(m > 0) || m - m != 0) {
        v[0] = v[1] = v[2] = 0;
        return 0;
    }
    v[0] /= m, v[1] /= m, v[2] /= m;
    len = REAL_SQRT(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= len, v[1] /= len, v[2] /= len;
    return len * m;
}

void ls_mesh_impl_face_cross(const ls_real *p, const uint32_t *t, ls_real n[3])
{
    const ls_real *a = p + 3 * (size_t)t[0], *b = p + 3 * (size_t)t[1], *c = p + 3 * (size_t)t[2];
    ls_real u0 = b[0] - a[0], u1 = b[1] - a[1], u2 = b[2] - a[2];
    ls_real w0 = c[0] - a[0], w1 = c[1] - a[1], w2 = c[2] - a[2];
    n[0] = u1 * w2 - u2 * w1;
    n[1] = u2 * w0 - u0 * w2;
    n[2] = u0 * w1 - u1 * w0;
}

/* Scales v to a largest component of magnitude 1 (0 for a zero or
 * non-finite vector); returns 0 in that case. */
static int scale_unit_max(ls_real v[3])
{
    ls_real m = real_abs(v[0]);
    if (real_abs(v[1]) > m) m = real_abs(v[1]);
    if (real_abs(v[2]) > m) m = real_abs(v[2]);
    if (!(m > 0) || m - m != 0) return 0;
    v[0] /= m, v[1] /= m, v[2] /= m;
    return 1;
}

/* The unit normal of a face, computed from edge vectors scaled first so that
 * tiny and huge triangles neither underflow nor overflow; (0, 0, 0) for
 * zero-area or non-finite faces. Returns 1 when non-zero. */
static int face_unit_normal(const ls_real *p, const uint32_t *t, ls_real n[3])
{
    const ls_real *a = p + 3 * (size_t)t[0], *b = p + 3 * (size_t)t[1], *c = p + 3 * (size_t)t[2];
    ls_real u[3], w[3];
    u[0] = b[0] - a[0], u[1] = b[1] - a[1], u[2] = b[2] - a[2];
    w[0] = c[0] - a[0], w[1] = c[1] - a[1], w[2] = c[2] - a[2];
    n[0] = n[1] = n[2] = 0;
    if (!scale_unit_max(u) || !scale_unit_max(w)) return 0;
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    return normalize3(n) != 0;
}

ls_status ls_mesh_face_normals(const ls_mesh *mesh, ls_real *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    uint32_t f, bad;
    if (check_mesh(mesh) != LS_OK) return ls_invalid_arg(diag, ls_mesh_impl_problem(mesh));
    if (out == NULL && mesh->face_count > 0) return ls_invalid_arg(diag, "out is NULL with face_count > 0");
    bad = ls_mesh_impl_first_bad_face(mesh);
    if (bad != LS_MESH_NONE) {
        set_diag(diag, LS_ERR_MESH, "face index out of range", bad);
        return LS_ERR_MESH;
    }
    for (f = 0; f < mesh->face_count; f++) {
        (void)face_unit_normal(mesh->positions, mesh->triangles + 3 * (size_t)f, out + 3 * (size_t)f);
    }
    return LS_OK;
}

/* The angle at p[0] between p[1] - p[0] and p[2] - p[0]. */
static ls_real corner_angle(const ls_real *a, const ls_real *b, const ls_real *c)
{
    ls_real u[3], w[3], x[3], d;
    u[0] = b[0] - a[0], u[1] = b[1] - a[1], u[2] = b[2] - a[2];
    w[0] = c[0] - a[0], w[1] = c[1] - a[1], w[2] = c[2] - a[2];
    (void)scale_unit_max(u);
    (void)scale_unit_max(w);
    x[0] = u[1] * w[2] - u[2] * w[1];
    x[1] = u[2] * w[0] - u[0] * w[2];
    x[2] = u[0] * w[1] - u[1] * w[0];
    d = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
    return REAL_ATAN2(REAL_SQRT(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), d);
}

ls_status ls_mesh_vertex_normals(const ls_mesh *mesh, uint32_t weighting, ls_real *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    uint32_t f, v, k, bad;
    const ls_real *p;
    if (check_mesh(mesh) != LS_OK) return ls_invalid_arg(diag, ls_mesh_impl_problem(mesh));
    if (out == NULL && mesh->vertex_count > 0) return ls_invalid_arg(diag, "out is NULL with vertex_count > 0");
    if (weighting > LS_NORMALS_ANGLE) return ls_invalid_arg(diag, "weighting: allowed LS_NORMALS_UNIFORM .. LS_NORMALS_ANGLE");
    bad = ls_mesh_impl_first_bad_face(mesh);
    if (bad != LS_MESH_NONE) {
        set_diag(diag, LS_ERR_MESH, "face index out of range", bad);
        return LS_ERR_MESH;
    }
    p = mesh->positions;
    if (mesh->vertex_count > 0) memset(out, 0, 3 * (size_t)mesh->vertex_count * sizeof(ls_real));
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *t = mesh->triangles + 3 * (size_t)f;
        ls_real n[3], unit[3];
        if (!face_unit_normal(p, t, unit)) continue;
        ls_mesh_impl_face_cross(p, t, n);
        for (k = 0; k < 3; k++) {
            ls_real *o = out + 3 * (size_t)t[k];
            if (weighting == LS_NORMALS_AREA) {
                o[0] += n[0], o[1] += n[1], o[2] += n[2];
            } else if (weighting == LS_NORMALS_ANGLE) {
                ls_real a = corner_angle(p + 3 * (size_t)t[k], p + 3 * (size_t)t[(k + 1) % 3], p + 3 * (size_t)t[(k + 2) % 3]);
                o[0] += a * unit[0], o[1] += a * unit[1], o[2] += a * unit[2];
            } else {
                o[0] += unit[0], o[1] += unit[1], o[2] += unit[2];
            }
        }
    }
    for (v = 0; v < mesh->vertex_count; v++) (void)normalize3(out + 3 * (size_t)v);
    return LS_OK;
}

ls_status ls_mesh_bounds(const ls_mesh *mesh, ls_real lo[3], ls_real hi[3])
{
    uint32_t v, k, any = 0;
    ls_real l[3] = {0, 0, 0}, h[3] = {0, 0, 0};
    if (check_mesh(mesh) != LS_OK || lo == NULL || hi == NULL) return LS_ERR_INVALID;
    for (v = 0; v < mesh->vertex_count; v++) {
        const ls_real *q = mesh->positions + 3 * (size_t)v;
        if (!finite3(q)) continue;
        for (k = 0; k < 3; k++) {
            if (!any || q[k] < l[k]) l[k] = q[k];
            if (!any || q[k] > h[k]) h[k] = q[k];
        }
        any = 1;
    }
    if (!any) return LS_ERR_MESH;
    for (k = 0; k < 3; k++) lo[k] = l[k], hi[k] = h[k];
    return LS_OK;
}
