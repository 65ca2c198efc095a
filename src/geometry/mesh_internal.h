/* mesh_internal.h - what mesh.c offers crease.c (private to src/geometry):
 * the argument checks, the half-edges keyed by edge, face cross products,
 * union-find and the corner of a face at a vertex. */
#ifndef LS_MESH_INTERNAL_H
#define LS_MESH_INTERNAL_H
#include <largesteps/mesh.h>

/* Faces above this make corner ids reach bit 31 (used as a mark). */
#define MAX_VALIDATE_FACES 0x2AAAAAAAu

/* What is wrong with the mesh argument, or NULL when it is usable. */
const char *ls_mesh_impl_problem(const ls_mesh *mesh);

/* The first face with an index out of range, or LS_MESH_NONE. */
uint32_t ls_mesh_impl_first_bad_face(const ls_mesh *mesh);

/* Fills keys[h] = (min << 32 | max) of each half-edge h = 3 f + k of the
 * usable faces (indices in range, three distinct) and lists those
 * half-edges in idx; returns how many. */
size_t ls_mesh_impl_half_edges(const ls_mesh *mesh, uint64_t *keys, uint32_t *idx);

/* The cross product (b - a) x (c - a) of face t's corners a, b, c. */
void ls_mesh_impl_face_cross(const ls_real *p, const uint32_t *t, ls_real n[3]);

/* Union-find with path halving (iterative). */
static inline uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static inline void uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    /* the smaller root wins: the result does not depend on the call order's details */
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
}

/* The corner (3f + k) of usable face f at vertex v. */
static inline uint32_t corner_of(const uint32_t *t, uint32_t f, uint32_t v)
{
    size_t c = 3 * (size_t)f;
    if (t[c] == v) return (uint32_t)c;
    if (t[c + 1] == v) return (uint32_t)(c + 1);
    return (uint32_t)(c + 2);
}

#endif /* LS_MESH_INTERNAL_H */
