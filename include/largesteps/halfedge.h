/* largesteps/halfedge.h - a half-edge triangle mesh with a fixed capacity, for
 * local edits (edge split, collapse, flip) in arena memory.
 *
 * Layout. Half-edges come in pairs: edge e owns half-edges 2e and 2e + 1, so
 * the opposite ("twin") of half-edge h is h ^ 1. Half-edge 2e of an edge
 * built from a mesh points from the smaller to the larger vertex index. Each
 * half-edge stores the vertex it points to (hto), the next and previous
 * half-edge of its face or boundary loop (hnext, hprev) and its face (hface,
 * LS_HE_NONE for a boundary half-edge). The origin of h is hto[h ^ 1]. Faces
 * are triangles whose half-edges run counter-clockwise seen from outside (the
 * ls_mesh convention); boundary half-edges run the other way round each hole
 * and are linked into loops by hnext/hprev. Each vertex stores one outgoing
 * half-edge (vout), a boundary one whenever the vertex is on the boundary;
 * each face stores one of its half-edges (fedge).
 *
 * The outgoing half-edges of v, in order: h = vout[v], then h = hnext[h ^ 1],
 * until h is vout[v] again. Every walk in this module is bounded by the number
 * of half-edges, so a corrupted structure gives an error, never a hang.
 *
 * Dead elements. Split adds elements, collapse kills some: a dead vertex has
 * vout = LS_HE_NONE (so has an unreferenced vertex of the input), a dead edge
 * hto[2e] = LS_HE_NONE, a dead face fedge = LS_HE_NONE. The *_count fields
 * count slots (live and dead), the live_* fields the live elements.
 * ls_he_compact removes the dead slots in place; ls_he_to_mesh writes the
 * live elements as an indexed ls_mesh.
 *
 * Capacity. A mesh is built for at most vertex_cap vertices. The edge and face
 * capacities follow from the Euler characteristic chi = V - E + F of the
 * input, which the local operators preserve: a manifold triangle mesh with V
 * vertices (all referenced) and B boundary edges has E = 3V - 3chi - B and
 * F = 2V - 2chi - B edges and faces, so edge_cap = 3 vertex_cap - 3chi and
 * face_cap = 2 vertex_cap - 2chi hold any mesh of the same topology with at
 * most vertex_cap live vertices (see ls_he_capacity).
 */
#ifndef LARGESTEPS_HALFEDGE_H
#define LARGESTEPS_HALFEDGE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_HE_NONE 0xffffffffu /* no element: boundary face, dead slot */

typedef struct ls_hemesh {
    ls_real *positions;      /* vertex_cap * 3 */
    uint32_t *vout;          /* vertex_cap: an outgoing half-edge (a boundary one if any), NONE = dead */
    uint32_t *hto;           /* 2 * edge_cap: the vertex a half-edge points to; NONE = dead edge */
    uint32_t *hnext;         /* 2 * edge_cap: next half-edge of the face or boundary loop */
    uint32_t *hprev;         /* 2 * edge_cap: previous half-edge */
    uint32_t *hface;         /* 2 * edge_cap: the face on the left; NONE on the boundary */
    uint32_t *fedge;         /* face_cap: one half-edge of the face; NONE = dead */
    uint32_t vertex_count;   /* slots in use (live and dead) */
    uint32_t edge_count;
    uint32_t face_count;
    uint32_t vertex_cap;     /* slots available */
    uint32_t edge_cap;
    uint32_t face_cap;
    uint32_t live_vertices;  /* live elements */
    uint32_t live_edges;
    uint32_t live_faces;
} ls_hemesh;

/* ls_he_capacity: the edge and face capacities of a half-edge mesh with
 * vertex_cap vertices and Euler characteristic `euler` (from
 * ls_mesh_validate's report): 3 vertex_cap - 3 euler and 2 vertex_cap -
 * 2 euler (at least 1 each). O(1); no memory. Errors: LS_ERR_INVALID (NULL),
 * LS_ERR_TOO_LARGE (more than 2^31 - 2 edges or 2^32 - 2 faces). */
ls_status ls_he_capacity(uint32_t vertex_cap, int64_t euler, uint32_t *edge_cap, uint32_t *face_cap);

/* ls_he_bytes: the arena bytes of the mesh object itself (its arrays) for
 * vertex_cap vertices and Euler characteristic `euler` (exact). O(1).
 * Errors: LS_ERR_INVALID, LS_ERR_TOO_LARGE. */
ls_status ls_he_bytes(uint32_t vertex_cap, int64_t euler, size_t *bytes);

/* ls_he_build_bytes: the bytes ls_he_build takes for `mesh` (exact): the
 * larger of the validation scratch and the object of ls_he_bytes plus the
 * pairing scratch (about 16 bytes per face corner). O(1). Errors:
 * LS_ERR_INVALID, LS_ERR_TOO_LARGE. */
ls_status ls_he_build_bytes(const ls_mesh *mesh, uint32_t vertex_cap, int64_t euler, size_t *bytes);

/* ls_he_build: the half-edge mesh of `mesh`, with room for vertex_cap
 * vertices (0: exactly the input's vertex count). The mesh is validated
 * first (ls_mesh_validate); it must have at least one face, finite
 * coordinates, indices in range, no face that repeats a vertex, and be an
 * oriented 2-manifold (boundaries allowed). Unreferenced vertices become dead
 * slots. If `report` is not NULL it receives the validation report (also on
 * an LS_ERR_MESH failure). O(F log F). Memory: the object from the arena's
 * bottom, scratch from the top (released). Errors: LS_ERR_INVALID (NULL,
 * vertex_cap below the input's vertex count), LS_ERR_MESH (diag->what names
 * the violated requirement: "non-manifold edge", "non-manifold vertex",
 * "inconsistent face orientation", "face with a repeated vertex", ...;
 * diag->index the element), LS_ERR_NONFINITE, LS_ERR_TOO_LARGE, LS_ERR_NOMEM
 * (the arena and *he unchanged). */
ls_status ls_he_build(const ls_mesh *mesh, uint32_t vertex_cap, ls_arena *arena, ls_hemesh *he,
                      ls_mesh_report *report, ls_diag *diag);

/* ls_he_valence: the number of edges at live vertex v (0 for a dead or
 * out-of-range vertex, or when the walk around v does not close). O(valence). */
uint32_t ls_he_valence(const ls_hemesh *he, uint32_t v);

/* ls_he_is_boundary: 1 when live vertex v lies on a boundary, else 0. O(1). */
int ls_he_is_boundary(const ls_hemesh *he, uint32_t v);

/* ls_he_split: splits live edge e at a new vertex placed at p (normally the
 * midpoint): the edge becomes two, and each of its (one or two) faces
 * becomes two by an edge from the new vertex to the opposite corner. Adds 1
 * vertex, 2 or 3 edges and 1 or 2 faces; orientation is kept. Half-edge 2e
 * keeps its origin and now ends at the new vertex, whose index goes to
 * *vertex (may be NULL). O(1). Errors: LS_ERR_INVALID (NULL, dead or
 * out-of-range edge), LS_ERR_NOMEM (a capacity is full; the mesh is
 * unchanged). */
ls_status ls_he_split(ls_hemesh *he, uint32_t e, const ls_real p[3], uint32_t *vertex);

/* ls_he_collapse_ok: 1 when collapsing half-edge h (its origin merged into
 * its target) keeps the mesh a manifold of the same topology: the link
 * condition (the one-rings of the two ends share only the corners opposite
 * the edge, which are distinct), no face whose two other edges are both on
 * the boundary, no interior edge between two boundary vertices, and no
 * opposite corner left with fewer than three edges. Else 0 (also for a dead
 * or out-of-range h). O(valence(a) * valence(b)); no memory. */
int ls_he_collapse_ok(const ls_hemesh *he, uint32_t h);

/* ls_he_collapse: removes the origin of half-edge h; its edges now end at
 * the target of h (whose position is not changed), and the one or two faces
 * of the edge disappear with one edge each. Kills 1 vertex, 2 or 3 edges and
 * 1 or 2 faces (their slots stay dead until ls_he_compact). O(valence).
 * Errors: LS_ERR_INVALID (NULL, dead or out-of-range h), LS_ERR_MESH (the
 * collapse is not allowed, see ls_he_collapse_ok; the mesh is unchanged). */
ls_status ls_he_collapse(ls_hemesh *he, uint32_t h);

/* ls_he_flip_ok: 1 when interior edge e can be flipped: both faces live,
 * the two opposite corners distinct and not yet joined by an edge, and both
 * ends keep at least three edges. Else 0. O(valence). */
int ls_he_flip_ok(const ls_hemesh *he, uint32_t e);

/* ls_he_flip: replaces edge e (a, b), shared by faces (a, b, c) and
 * (b, a, d), by the edge (c, d): the faces become (d, c, a) and (c, d, b).
 * O(1). Errors: LS_ERR_INVALID (NULL, dead or out-of-range e), LS_ERR_MESH
 * (not allowed, see ls_he_flip_ok; unchanged). */
ls_status ls_he_flip(ls_hemesh *he, uint32_t e);

/* ls_he_compact_bytes: the scratch ls_he_compact needs for this mesh
 * (exact: one uint32_t per vertex, edge and face slot). O(1). */
ls_status ls_he_compact_bytes(const ls_hemesh *he, size_t *bytes);

/* ls_he_compact: removes the dead slots in place: live elements keep their
 * relative order and move to the front, every reference is renumbered, and
 * the *_count fields become the live counts. Capacities are unchanged.
 * O(V + E + F). Memory: scratch only (released). Errors: LS_ERR_INVALID,
 * LS_ERR_NOMEM (the mesh is unchanged). */
ls_status ls_he_compact(ls_hemesh *he, ls_arena *arena);

/* ls_he_to_mesh: the live vertices and faces as an indexed mesh (vertices
 * and faces in slot order; each face starts at the origin of its fedge),
 * allocated from the arena's bottom. The half-edge mesh must have no dead
 * slot (call ls_he_compact first). O(V + F). Errors: LS_ERR_INVALID,
 * LS_ERR_STATE (dead slots or a broken face cycle), LS_ERR_NOMEM (the arena
 * and *mesh unchanged). */
ls_status ls_he_to_mesh(const ls_hemesh *he, ls_arena *arena, ls_mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_HALFEDGE_H */
