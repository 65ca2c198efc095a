/* largesteps/bvh.h - a bounding-volume hierarchy over the triangles of a mesh,
 * for closest-point queries (remeshing's projection, distance metrics) and
 * triangle-pair overlap queries (self-intersection counts).
 *
 * Build: top-down, no recursion (an explicit work list), splitting each node's
 * triangles at the median of their centroids along the longest axis of the
 * centroid box; the median is found with a deterministic selection whose ties
 * are broken by triangle index, so the tree is the same on every platform.
 * Leaves hold at most LS_BVH_LEAF triangles; the depth is at most
 * LS_BVH_MAX_DEPTH, so traversals use a fixed stack on the C stack.
 *
 * Queries: a closest-point query returns the nearest point of the surface,
 * the triangle it lies on and its barycentric coordinates; among equally
 * distant triangles the lowest index wins, whatever the traversal order.
 * Degenerate triangles (repeated or collinear corners) are handled: their
 * closest point is the closest point of their longest edge.
 *
 * The tree borrows the mesh: it keeps pointers to positions and triangles,
 * which must stay alive and unchanged while the tree is used.
 */
#ifndef LARGESTEPS_BVH_H
#define LARGESTEPS_BVH_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_BVH_LEAF 4u       /* at most this many triangles per leaf */
#define LS_BVH_MAX_DEPTH 64u /* bound on the depth (median splits give about log2(F / LEAF)) */

typedef struct ls_bvh_node {
    ls_real lo[3];  /* box of the node's triangles */
    ls_real hi[3];
    uint32_t first; /* leaf: first position in `order`; inner node: index of the second child
                       (the first child is the next node) */
    uint32_t count; /* leaf: number of triangles (>= 1); inner node: 0 */
} ls_bvh_node;

typedef struct ls_bvh {
    const ls_real *positions;  /* borrowed from the mesh */
    const uint32_t *triangles; /* borrowed from the mesh */
    uint32_t vertex_count;
    uint32_t face_count;
    uint32_t node_count;       /* nodes in use (<= 2 * face_count - 1) */
    uint32_t depth;            /* levels of the tree */
    ls_bvh_node *nodes;        /* node 0 is the root */
    uint32_t *order;           /* face_count triangle indices, grouped by leaf */
} ls_bvh;

/* The closest point of the surface to a query point. */
typedef struct ls_bvh_hit {
    ls_real point[3]; /* the closest point */
    ls_real dist2;    /* squared distance to it */
    ls_real bary[3];  /* its barycentric coordinates in triangle `face` */
    uint32_t face;    /* the triangle (the lowest index among equally close ones) */
} ls_bvh_hit;

/* ls_bvh_bytes: exact arena bytes of ls_bvh_build for a mesh with face_count
 * triangles (the tree plus the build's scratch). O(1). Errors:
 * LS_ERR_INVALID (NULL bytes), LS_ERR_TOO_LARGE. */
ls_status ls_bvh_bytes(uint32_t face_count, size_t *bytes);

/* ls_bvh_build: builds the tree of every face of `mesh` (at least one face;
 * finite positions; indices in range). O(F log F) time. Memory: the nodes and
 * the order from the arena's bottom, scratch from the top. Errors:
 * LS_ERR_INVALID (NULL, no faces), LS_ERR_MESH (an index out of range;
 * diag->index = the face), LS_ERR_NONFINITE (a NaN or infinite coordinate;
 * diag->index = the vertex), LS_ERR_NOMEM (arena and *bvh unchanged). */
ls_status ls_bvh_build(const ls_mesh *mesh, ls_arena *arena, ls_bvh *bvh, ls_diag *diag);

/* ls_bvh_closest: the closest point of the tree's surface to p. Only points
 * closer than sqrt(max_dist2) are searched (pass an infinite or huge value for
 * an unbounded search); when none is, hit->face is UINT32_MAX and the
 * other fields are unspecified. Time about O(log F) for points near the surface; no memory.
 * Errors: LS_ERR_INVALID (NULL), LS_ERR_NONFINITE (p not finite). */
ls_status ls_bvh_closest(const ls_bvh *bvh, const ls_real p[3], ls_real max_dist2, ls_bvh_hit *hit);

/* ls_closest_point_triangle: the closest point of triangle (a, b, c) to p,
 * with its barycentric coordinates (they sum to 1) and squared distance;
 * robust to degenerate triangles (see above). O(1). */
void ls_closest_point_triangle(const ls_real p[3], const ls_real a[3], const ls_real b[3], const ls_real c[3],
                               ls_real point[3], ls_real bary[3], ls_real *dist2);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_BVH_H */
