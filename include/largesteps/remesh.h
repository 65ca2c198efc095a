/* largesteps/remesh.h - isotropic remeshing (Botsch & Kobbelt 2004) in fixed
 * memory, as Large Steps uses it between optimization phases.
 *
 * Each iteration, on a half-edge copy of the mesh (largesteps/halfedge.h):
 *   1. split every edge longer than 4/3 h at its midpoint (passes until none
 *      is, at most 10);
 *   2. collapse every edge shorter than 4/5 h when the link condition holds
 *      (ls_he_collapse_ok), no edge of the merged vertex becomes longer than
 *      4/3 h, no remaining face normal turns by more than 60 degrees or
 *      becomes degenerate, and no remaining face around the merged vertex
 *      meets a face around its other corners (by ls_tangle_pair's rules).
 *      Two interior ends merge at the midpoint (the end with fewer edges is
 *      removed first); a boundary or kept (sharp, see sharp_angle) vertex is
 *      removed only into one of its kind, and an end of that kind keeps its
 *      position (at most 10 passes);
 *   3. flip interior edges when that lowers the sum of squared deviations of
 *      the four vertices' valences from 6 (4 on the boundary), neither new
 *      face normal turns by more than 60 degrees from either old one, and
 *      neither new face meets a face around its corners (at most 10 passes);
 *   4. tangential relaxation: each interior vertex moves to the mean of its
 *      neighbours, minus the component along its area-weighted normal
 *      (all vertices from the same old positions);
 *   5. projection of every interior vertex to the closest point of the input
 *      surface (a BVH of the input, largesteps/bvh.h, built once) among the
 *      input faces whose normals point the way the vertex's does (within
 *      the plain closest distance plus h; else the vertex stays): the
 *      nearest point of a part thinner than h is often on its other side,
 *      and moving there folds the mesh through the part. A move longer than
 *      h/32 is skipped when the vertex's faces would meet faces around
 *      their corners.
 * The local checks of 2, 3 and 5 are what keeps the remesh from adding
 * self-intersections (the armadillo at h = 2x its mean edge got 3
 * intersecting pairs without them); they look at the faces around the
 * corners only, so two sheets farther apart in the mesh than that can
 * still be pushed through each other (none in the tests). A vertex with
 * more than 64 faces is not moved by a checked operation.
 * Kept vertices (input vertices sharper than params.sharp_angle) are neither
 * relaxed nor projected: without them the tips and rims that are sharper than
 * the target resolution get rounded off (the bunny's ear rims move by 0.8 h).
 * Boundary vertices stay on the boundary and are not moved (split vertices of
 * boundary edges lie on the edge). Edges are visited in index order, so the
 * result is the same on every platform. The output is a compact indexed mesh:
 * manifold, consistently oriented, with the input's genus, components and
 * boundary loops; a face of exactly zero area in the result is an error.
 *
 * Large Steps' rule for the target: h = 1/2 of the current mean edge length
 * (ls_remesh_mean_edge), 5 iterations, projection on.
 *
 * Memory. The remesher works within a vertex capacity fixed up front
 * (ls_remesh_capacity); ls_remesh_bytes_bound gives the bytes for it, and
 * ls_remesh reports the bytes it really used. If a run needs more vertices
 * than the capacity (possible only for extreme inputs, e.g. long needle
 * triangles far below the target length's scale) it fails with LS_ERR_NOMEM
 * and leaves everything as it was: pass a larger vertex_cap.
 */
#ifndef LARGESTEPS_REMESH_H
#define LARGESTEPS_REMESH_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_REMESH_ITERATIONS 5u /* the reference's count */
#define LS_REMESH_SHARP_ANGLE 90 /* degrees; see ls_remesh_params.sharp_angle */

typedef struct ls_remesh_params {
    ls_real h;           /* target edge length, finite and > 0 */
    uint32_t iterations; /* >= 1; LS_REMESH_ITERATIONS by default */
    uint32_t project;    /* 1 (default): project onto the input surface; 0: no projection */
    uint32_t vertex_cap; /* 0 (default): ls_remesh_capacity's answer; else the capacity to use */
    ls_real sharp_angle; /* degrees: an interior input vertex with two incident faces whose normals
                            differ by more than this is kept in place (never moved or removed);
                            >= 180 keeps none (the reference's behaviour). LS_REMESH_SHARP_ANGLE by default */
} ls_remesh_params;

/* What a remesh did. */
typedef struct ls_remesh_info {
    uint32_t splits;       /* operations done, summed over the iterations */
    uint32_t collapses;
    uint32_t flips;
    uint32_t vertex_cap;   /* the capacity used */
    uint32_t max_vertices; /* the most live vertices at any time (<= vertex_cap) */
    size_t bytes_used;     /* the arena's high-water mark during the call, above its use at entry */
} ls_remesh_info;

/* ls_remesh_params_default: h as given, LS_REMESH_ITERATIONS iterations,
 * projection on, capacity from the bound. O(1). NULL is ignored. */
void ls_remesh_params_default(ls_remesh_params *params, ls_real h);

/* ls_remesh_mean_edge: the mean edge length as the reference computes it:
 * the mean over the three edges of every face (an interior edge counts
 * twice; on a closed mesh this is the mean over edges). Faces with an index
 * out of range are skipped. Compensated sum in face order. O(F); no memory.
 * Errors: LS_ERR_INVALID (NULL), LS_ERR_MESH (no usable face). */
ls_status ls_remesh_mean_edge(const ls_mesh *mesh, ls_real *mean);

/* ls_remesh_capacity: the vertex capacity for remeshing `mesh` to target h:
 * V + ceil(3 A / h^2) + B ceil(2 m / h) + 16, where V is the input's vertex
 * count (the input must fit before any collapse), A its area, B its number of
 * boundary edges (report from ls_mesh_validate) and m its mean edge length.
 * Margin: a mesh of equilateral triangles of side h has 1.15 A / h^2
 * vertices, and splitting alone (edges in (2/3 h, 4/3 h]) leaves at most
 * about 2.6 A / h^2; the boundary term covers splitting boundary edges. O(F);
 * no memory. Errors: LS_ERR_INVALID (NULL, h not finite and > 0),
 * LS_ERR_TOO_LARGE (more than 2^31 vertices). */
ls_status ls_remesh_capacity(const ls_mesh *mesh, const ls_mesh_report *report, ls_real h, uint32_t *vertex_cap);

/* ls_remesh_bytes_bound: the arena bytes ls_remesh takes at most with these
 * parameters (capacity as params->vertex_cap or ls_remesh_capacity): the
 * half-edge mesh at capacity, the BVH of the input (if projecting), per-vertex
 * work arrays, and the output mesh at capacity. `report` is
 * ls_mesh_validate's report of `mesh`. With params->vertex_cap set, only
 * the mesh's counts and report->euler are read, and the bound grows with
 * both counts: it holds for every mesh with at most those counts and that
 * Euler characteristic (a job sized before its meshes exist, fit.h). O(F).
 * Errors: LS_ERR_INVALID, LS_ERR_TOO_LARGE. */
ls_status ls_remesh_bytes_bound(const ls_mesh *mesh, const ls_mesh_report *report, const ls_remesh_params *params,
                                size_t *bytes);

/* ls_remesh: remeshes `in` to target edge length params->h (see above) into
 * *out (positions and triangles from the arena's bottom; everything else is
 * scratch, released). The input must be a non-empty oriented 2-manifold
 * (boundaries allowed) with finite coordinates and no face that repeats a
 * vertex; unreferenced vertices are dropped. *info (may be NULL) receives the
 * counts. Cost about O(iterations (V log F)) for the output's V. Errors:
 * LS_ERR_INVALID (NULL, bad parameters, vertex_cap below the input's vertex
 * count), LS_ERR_MESH / LS_ERR_NONFINITE (input rejected; diag->what and
 * index say why, e.g. "non-manifold edge"; or "remesh produced a zero-area
 * face"), LS_ERR_TOO_LARGE, LS_ERR_NOMEM (arena below the bound, or the
 * capacity exceeded; diag->what says which). On failure the arena and *out
 * are unchanged. */
ls_status ls_remesh(const ls_mesh *in, const ls_remesh_params *params, ls_arena *arena, ls_mesh *out,
                    ls_remesh_info *info, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_REMESH_H */
