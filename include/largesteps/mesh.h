/* largesteps/mesh.h - indexed triangle meshes: validation, welding, edges,
 * adjacency, normals, bounds.
 *
 * An ls_mesh is two plain arrays: vertex positions (x, y, z per vertex, in
 * ls_real) and triangles (three uint32_t vertex indices per face, 0-based,
 * counter-clockwise seen from outside). Nothing else is stored; derived data
 * (edges, adjacency, normals) is computed on request into caller memory or an
 * arena, with exact sizing queries.
 *
 * Terms used below. A face is "usable" when its three indices are below
 * vertex_count and pairwise distinct; only usable faces take part in the
 * topology (edges, manifoldness, components, Euler characteristic). A
 * "degenerate" face repeats an index; a "zero-area" face is usable but its
 * edge vectors' cross product is exactly zero. Every result is computed in a
 * fixed order with the library's own stable sort, so it is the same on every
 * platform.
 */
#ifndef LARGESTEPS_MESH_H
#define LARGESTEPS_MESH_H

#include <largesteps/core.h>
#include <largesteps/arena.h>
#include <largesteps/status.h>

#ifdef __cplusplus
extern "C" {
#endif

/* "No such element" in the first_* fields of ls_mesh_report. */
#define LS_MESH_NONE 0xffffffffu

typedef struct ls_mesh {
    ls_real *positions;    /* vertex_count * 3 values: x0 y0 z0 x1 y1 z1 ... */
    uint32_t *triangles;   /* face_count * 3 vertex indices */
    uint32_t vertex_count;
    uint32_t face_count;
} ls_mesh;

/* ls_mesh_bytes: the arena bytes ls_mesh_alloc takes for these counts
 * (exact). LS_ERR_TOO_LARGE on size_t overflow. O(1). */
ls_status ls_mesh_bytes(uint32_t vertex_count, uint32_t face_count, size_t *bytes);

/* ls_mesh_alloc: allocates uninitialised positions and triangles from the
 * bottom of the arena and sets the counts. LS_ERR_NOMEM when the arena is too
 * small (arena and *mesh unchanged), LS_ERR_INVALID for NULL pointers. O(1). */
ls_status ls_mesh_alloc(ls_mesh *mesh, uint32_t vertex_count, uint32_t face_count, ls_arena *arena);

/* What ls_mesh_validate found. Counts, and for each kind of problem the
 * first offending element (lowest index; LS_MESH_NONE if there is none).
 * Edges are named by their two vertex indices (smaller first). */
typedef struct ls_mesh_report {
    uint32_t vertex_count;
    uint32_t face_count;
    uint32_t nonfinite_vertices;        /* a NaN or infinite coordinate */
    uint32_t first_nonfinite_vertex;
    uint32_t bad_index_faces;           /* an index >= vertex_count */
    uint32_t first_bad_index_face;
    uint32_t degenerate_faces;          /* a repeated index */
    uint32_t first_degenerate_face;
    uint32_t zero_area_faces;           /* usable, finite, cross product exactly 0 */
    uint32_t first_zero_area_face;
    uint32_t duplicate_faces;           /* same vertex set as an earlier usable face */
    uint32_t first_duplicate_face;
    uint32_t unreferenced_vertices;     /* used by no usable face */
    uint32_t first_unreferenced_vertex;
    uint32_t edge_count;                /* unique undirected edges of usable faces */
    uint32_t boundary_edges;            /* used by one face */
    uint32_t first_boundary_edge[2];
    uint32_t nonmanifold_edges;         /* used by three or more faces */
    uint32_t first_nonmanifold_edge[2];
    uint32_t orientation_conflicts;     /* two faces traverse the edge the same way */
    uint32_t first_orientation_conflict[2];
    uint32_t nonmanifold_vertices;      /* incident faces form more than one fan */
    uint32_t first_nonmanifold_vertex;
    uint32_t components;                /* connected components of the usable faces */
    uint32_t boundary_loops;            /* connected components of the boundary edges */
    uint32_t used_vertices;             /* vertex_count - unreferenced_vertices */
    uint32_t usable_faces;
    int64_t euler;                      /* used_vertices - edge_count + usable_faces */
    uint32_t has_genus;                 /* 1 for an oriented 2-manifold (with boundary) */
    int32_t genus;                      /* (2 components - euler - boundary_loops) / 2, summed over components */
} ls_mesh_report;

/* ls_mesh_validate_bytes: the scratch bytes ls_mesh_validate needs (exact:
 * an arena with this many free bytes succeeds, fewer fail). LS_ERR_TOO_LARGE
 * when face_count > (2^32 - 1) / 3 or on size_t overflow. O(1). */
ls_status ls_mesh_validate_bytes(const ls_mesh *mesh, size_t *bytes);

/* ls_mesh_validate: fills *report (see ls_mesh_report) for any mesh, however
 * broken: it never fails on bad data, it reports it. Cost O(F log F + V);
 * memory: scratch only (released before return; about 64 bytes per face and
 * 8 per vertex). Errors: LS_ERR_INVALID (NULL pointers, or NULL arrays with
 * non-zero counts), LS_ERR_TOO_LARGE, LS_ERR_NOMEM (report unchanged). */
ls_status ls_mesh_validate(const ls_mesh *mesh, ls_arena *arena, ls_mesh_report *report);

/* Requirement flags for ls_mesh_require. */
#define LS_MESH_REQ_FINITE 0x01u        /* no NaN or infinite coordinates */
#define LS_MESH_REQ_INDICES 0x02u       /* every index < vertex_count */
#define LS_MESH_REQ_NONDEGENERATE 0x04u /* no repeated index, no zero-area face */
#define LS_MESH_REQ_MANIFOLD 0x08u      /* no non-manifold edge or vertex, consistent orientation */
#define LS_MESH_REQ_CLOSED 0x10u        /* no boundary edge */
#define LS_MESH_REQ_NONEMPTY 0x20u      /* at least one usable face */
#define LS_MESH_REQ_ALL 0x3fu

/* ls_mesh_require: LS_OK when the report meets every requirement in `flags`,
 * else LS_ERR_MESH (LS_ERR_NONFINITE for a NaN/inf coordinate) with the first
 * failing requirement named in diag->what and its element in diag->index.
 * O(1); no memory. */
ls_status ls_mesh_require(const ls_mesh_report *report, uint32_t flags, ls_diag *diag);

/* ls_mesh_weld: merges vertices with exactly equal positions (-0 equals +0;
 * a NaN coordinate never matches), in place. The vertex kept for a group is
 * its lowest index; kept vertices keep their relative order; triangles are
 * re-indexed (faces that become degenerate are kept: validate reports them).
 * remap (optional, vertex_count entries) receives each old vertex's new index;
 * *removed (optional) the number of vertices merged away. O(V log V + F);
 * scratch 20 bytes per vertex. Errors: LS_ERR_INVALID, LS_ERR_MESH (an index
 * out of range; the mesh is unchanged), LS_ERR_NOMEM (unchanged). */
ls_status ls_mesh_weld(ls_mesh *mesh, ls_arena *arena, uint32_t *remap, uint32_t *removed);

/* ls_mesh_weld_bytes: the scratch bytes ls_mesh_weld needs (exact). O(1). */
ls_status ls_mesh_weld_bytes(const ls_mesh *mesh, size_t *bytes);

/* ls_mesh_unweld: the mesh with every face on three vertices of its own
 * (face f's corners become vertices 3f, 3f + 1, 3f + 2, at the positions of
 * the corners), into *out (positions and triangles from the bottom of the
 * arena, ls_mesh_unweld_bytes). The surface is the same; the vertex normals
 * of the result (ls_mesh_vertex_normals, ls_shade_vertex_normals) are its
 * face normals, so renders of it are shaded flat, as a CAD part's faces are,
 * where those of `in` interpolate normals averaged over each vertex's faces.
 * O(F). Errors: LS_ERR_INVALID (NULL), LS_ERR_MESH (an index out of range,
 * diag->index = the face), LS_ERR_TOO_LARGE (3 F vertices do not fit a
 * uint32_t), LS_ERR_NOMEM; the arena and *out are unchanged on any error. */
ls_status ls_mesh_unweld(const ls_mesh *in, ls_arena *arena, ls_mesh *out, ls_diag *diag);

/* ls_mesh_unweld_bytes: the arena bytes ls_mesh_unweld takes for a mesh of
 * face_count faces (exact; ls_mesh_bytes(3 F, F)). O(1). */
ls_status ls_mesh_unweld_bytes(uint32_t face_count, size_t *bytes);

/* ls_mesh_split_creases: the mesh with its vertices split along its creases,
 * into *out (positions and triangles from the bottom of the arena): where
 * the two faces of an edge meet at an angle whose cosine is below crease_cos
 * (their normals more than acos(crease_cos) apart), each side of the edge
 * gets vertices of its own, as do the sides of a boundary edge, of an edge
 * with more than two faces, and of one whose faces disagree on orientation.
 * The vertex normals of the result then average each vertex's faces only
 * within one smooth sheet: renders show a CAD part's creases sharp and its
 * curved faces smooth. The surface is the same. Vertex v's first sheet (in
 * face order) keeps index v; the others are added after the input's vertices
 * in the order of their first corner, so a mesh without creases comes back
 * as it was. crease_cos = 1 splits every edge between faces that are not
 * coplanar; -1 splits none but the edges named above. O(F log F).
 * Errors: LS_ERR_INVALID (NULL, crease_cos outside [-1, 1]), LS_ERR_MESH (an
 * index out of range, diag->index = the face), LS_ERR_TOO_LARGE, LS_ERR_NOMEM;
 * the arena and *out are unchanged on any error. */
ls_status ls_mesh_split_creases(const ls_mesh *in, ls_real crease_cos, ls_arena *arena, ls_mesh *out, ls_diag *diag);

/* ls_mesh_split_creases_bytes: the arena bytes ls_mesh_split_creases needs
 * for a mesh of these counts: its scratch (20 bytes per face corner and 4 per
 * vertex) and its result at the most vertices it can have (V + 3 F); the
 * result it keeps takes 3 * sizeof(ls_real) bytes fewer per vertex that no
 * crease adds. O(1). */
ls_status ls_mesh_split_creases_bytes(uint32_t vertex_count, uint32_t face_count, size_t *bytes);

/* ls_mesh_count_creases: of the mesh's edges that have exactly two faces,
 * oriented alike (the edges ls_mesh_split_creases may keep whole), *edges;
 * of those, *creases have faces whose normals' cosine is below crease_cos.
 * With a small angle (crease_cos near 1) edges - creases counts the edges
 * between coplanar faces: most of a CAD part's edges, few of a scan's.
 * Scratch only (ls_mesh_count_creases_bytes); the arena is as it was after.
 * O(F log F). Errors as ls_mesh_split_creases's. */
ls_status ls_mesh_count_creases(const ls_mesh *in, ls_real crease_cos, ls_arena *arena, uint32_t *creases,
                                uint32_t *edges, ls_diag *diag);

/* ls_mesh_count_creases_bytes: the scratch ls_mesh_count_creases needs (exact:
 * 16 bytes per face corner). O(1). */
ls_status ls_mesh_count_creases_bytes(uint32_t face_count, size_t *bytes);

/* ls_mesh_reorder: puts the mesh in a spatially coherent order, in place:
 * faces sorted by the Morton code (10 bits per axis of the bounding box) of
 * their centroids, equal codes keeping their order, each face's corners as
 * they were (orientation kept); vertices in order of first use by the sorted
 * faces, unused ones last in their order. Loops over the faces then read
 * nearby vertices one after another (what it saves the renderer:
 * docs/remeshing-and-metrics.md). remap (optional, vertex_count
 * entries) receives each old vertex's new index. O(F log F + V); scratch
 * ls_mesh_reorder_bytes. Errors: LS_ERR_INVALID, LS_ERR_MESH (an index out of
 * range), LS_ERR_NOMEM; the mesh is unchanged on any error. */
ls_status ls_mesh_reorder(ls_mesh *mesh, ls_arena *arena, uint32_t *remap);

/* ls_mesh_reorder_bytes: the scratch bytes ls_mesh_reorder needs for these
 * counts (exact). O(1). */
ls_status ls_mesh_reorder_bytes(uint32_t vertex_count, uint32_t face_count, size_t *bytes);

/* Unique undirected edges, sorted by (smaller, larger) vertex index. */
typedef struct ls_mesh_edges {
    uint32_t *v;      /* count * 2 vertex indices, v[2i] < v[2i+1] */
    uint32_t count;
} ls_mesh_edges;

/* ls_mesh_edges_bytes: the bytes ls_mesh_edges_build takes for a mesh with
 * this many faces and unique edges (report.edge_count): the edge array plus
 * the scratch of the sort (exact). O(1). */
ls_status ls_mesh_edges_bytes(uint32_t face_count, uint32_t edge_count, size_t *bytes);

/* ls_mesh_edges_build: the unique edges of the usable faces (degenerate faces
 * are skipped), allocated from the bottom of the arena. O(F log F). Errors:
 * LS_ERR_MESH (an index out of range; diag->index is the face), LS_ERR_NOMEM,
 * LS_ERR_TOO_LARGE, LS_ERR_INVALID. */
ls_status ls_mesh_edges_build(const ls_mesh *mesh, ls_arena *arena, ls_mesh_edges *edges, ls_diag *diag);

/* Vertex adjacency in compressed sparse rows: the neighbours of vertex v are
 * neighbors[offsets[v] .. offsets[v+1]), in increasing order. */
typedef struct ls_mesh_adjacency {
    uint32_t *offsets;   /* vertex_count + 1 entries */
    uint32_t *neighbors; /* 2 * edge count entries */
    uint32_t vertex_count;
} ls_mesh_adjacency;

/* ls_mesh_adjacency_bytes: bytes for ls_mesh_adjacency_build (exact). O(1). */
ls_status ls_mesh_adjacency_bytes(uint32_t vertex_count, uint32_t edge_count, size_t *bytes);

/* ls_mesh_adjacency_build: the CSR adjacency of `edges` (from
 * ls_mesh_edges_build) over vertex_count vertices, allocated from the bottom
 * of the arena. O(V + E); no scratch. Errors: LS_ERR_INVALID (an edge index
 * >= vertex_count, NULL pointers), LS_ERR_NOMEM, LS_ERR_TOO_LARGE. */
ls_status ls_mesh_adjacency_build(const ls_mesh_edges *edges, uint32_t vertex_count, ls_arena *arena,
                                  ls_mesh_adjacency *adjacency);

/* ls_mesh_face_normals: the unit normal of each face (right-hand rule over
 * its vertex order) into out[3 * face_count]; (0, 0, 0) for zero-area and
 * degenerate faces, never NaN for finite positions. O(F); no memory. Errors:
 * LS_ERR_MESH (an index out of range; out unchanged, diag->index = face). */
ls_status ls_mesh_face_normals(const ls_mesh *mesh, ls_real *out, ls_diag *diag);

/* Weightings for ls_mesh_vertex_normals. */
#define LS_NORMALS_UNIFORM 0u /* sum of the unit normals of the incident faces */
#define LS_NORMALS_AREA 1u    /* sum of the face normals scaled by the face areas */
#define LS_NORMALS_ANGLE 2u   /* sum of the unit face normals scaled by the corner angles */

/* ls_mesh_vertex_normals: per-vertex unit normals into out[3 * vertex_count]:
 * the normalised weighted sum over the incident faces, accumulated in face
 * order; (0, 0, 0) where the sum is zero (unreferenced vertices, only
 * zero-area faces, cancelling normals): never NaN for finite positions.
 * O(F + V); no memory. Errors: LS_ERR_INVALID (unknown weighting, NULL),
 * LS_ERR_MESH (an index out of range; out unchanged, diag->index = face). */
ls_status ls_mesh_vertex_normals(const ls_mesh *mesh, uint32_t weighting, ls_real *out, ls_diag *diag);

/* ls_mesh_bounds: the axis-aligned bounding box of the finite vertices into
 * lo[3] and hi[3]. LS_ERR_MESH when there is no vertex with three finite
 * coordinates (lo, hi unchanged). O(V); no memory. */
ls_status ls_mesh_bounds(const ls_mesh *mesh, ls_real lo[3], ls_real hi[3]);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_MESH_H */
