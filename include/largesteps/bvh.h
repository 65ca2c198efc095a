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
 * closest point is the closest point of their longest edge. A triangle counts
 * as degenerate when |ab x ac| <= 16 eps |ab| |ac| (eps = LS_REAL_EPSILON).
 * The search prunes a box only when it is farther than the best distance plus
 * a rounding slack (256 eps times the largest coordinate of the tree's box and
 * the query), so its answer is exactly what a brute-force loop over every
 * triangle with ls_closest_point_triangle gives (smallest dist2, then lowest
 * index).
 *
 * Oriented boxes (ls_bvh_build_frames, optional): axis-aligned boxes overlap
 * badly when triangles are long, thin and not along an axis (a triangle fan:
 * a query inside the fan lies in the box of a fixed share of its triangles,
 * and every exact search evaluates them all). With frames, each node also has
 * a box along the principal axes of its corners, and a closest-point query
 * prunes with the larger of the two distances: about O(log F) per query on
 * such meshes too. The answer is the same, bit for bit.
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

/* A node's oriented box: the rows axis[k] are orthonormal up to a few ulps,
 * and the exact projection axis[k] . v of each of the node's corners v lies
 * in [lo[k], hi[k]] (the ranges are widened to cover their own rounding).
 * lo[0] > hi[0] marks a node without one (a projection overflowed). */
typedef struct ls_bvh_frame {
    ls_real axis[3][3];
    ls_real lo[3];
    ls_real hi[3];
} ls_bvh_frame;

typedef struct ls_bvh {
    const ls_real *positions;  /* borrowed from the mesh */
    const uint32_t *triangles; /* borrowed from the mesh */
    uint32_t vertex_count;
    uint32_t face_count;
    uint32_t node_count;       /* nodes in use (<= 2 * face_count - 1) */
    uint32_t depth;            /* levels of the tree */
    ls_bvh_node *nodes;        /* node 0 is the root */
    uint32_t *order;           /* face_count triangle indices, grouped by leaf */
    ls_bvh_frame *frames;      /* NULL, or node_count oriented boxes (ls_bvh_build_frames) */
    uint32_t *frame_used;      /* with frames: bit i % 32 of word i / 32 set when closest-point queries
                                  test node i's oriented box (its surface is under a quarter of the
                                  axis-aligned box's); the others keep the axis-aligned box alone */
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

/* ls_bvh_tree_bytes: the part of ls_bvh_bytes that stays allocated after a
 * successful build (nodes and order, from the arena's bottom); the rest is the
 * build's scratch, released before it returns. O(1). Errors as ls_bvh_bytes. */
ls_status ls_bvh_tree_bytes(uint32_t face_count, size_t *bytes);

/* ls_bvh_node_count: the nodes ls_bvh_build makes for face_count faces
 * (the tree's shape depends on the count alone); 0 for no face or a count
 * whose tree would not fit in 32-bit indices. O(log F). */
uint32_t ls_bvh_node_count(uint32_t face_count);

/* ls_bvh_check_mesh: the input checks of ls_bvh_build (and of the distance
 * and tangle metrics): at most (2^32 - 2) / 3 faces, every index below
 * vertex_count, every coordinate finite. O(V + F); no memory. Errors:
 * LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE, LS_ERR_MESH (diag->index = the
 * first bad face), LS_ERR_NONFINITE (diag->index = the first bad vertex). */
ls_status ls_bvh_check_mesh(const ls_mesh *mesh, ls_diag *diag);

/* ls_bvh_build: builds the tree of every face of `mesh` (at least one face;
 * finite positions; indices in range). O(F log F) time. Memory: the nodes and
 * the order from the arena's bottom, scratch from the top. Errors:
 * LS_ERR_INVALID (NULL, no faces), LS_ERR_MESH (an index out of range;
 * diag->index = the face), LS_ERR_NONFINITE (a NaN or infinite coordinate;
 * diag->index = the vertex), LS_ERR_NOMEM (arena and *bvh unchanged). */
ls_status ls_bvh_build(const ls_mesh *mesh, ls_arena *arena, ls_bvh *bvh, ls_diag *diag);

/* ls_bvh_frames_bytes: exact arena bytes of ls_bvh_build_frames for a tree
 * of face_count triangles (all of it stays allocated). O(log F). Errors as
 * ls_bvh_bytes. */
ls_status ls_bvh_frames_bytes(uint32_t face_count, size_t *bytes);

/* ls_bvh_build_frames: gives every node of a built tree its oriented box
 * (bvh->frames), for closest-point queries on meshes whose axis-aligned boxes
 * overlap (see above): the principal axes of each node's corners, its ranges
 * from its corners (a leaf) or its children's boxes. Time O(F); memory from
 * the arena's bottom, no scratch. Overlap queries do not use the frames.
 * Errors: LS_ERR_INVALID (NULL, a tree not built), LS_ERR_NOMEM (arena and
 * *bvh unchanged). */
ls_status ls_bvh_build_frames(ls_bvh *bvh, ls_arena *arena, ls_diag *diag);

/* ls_bvh_closest: the closest point of the tree's surface to p. Only points
 * closer than sqrt(max_dist2) are searched (pass an infinite or huge value for
 * an unbounded search); when none is, hit->face is UINT32_MAX and the
 * other fields are unspecified. Time about O(log F) for points near the surface
 * (measured: docs/remeshing-and-metrics.md); no memory, about 750 bytes of stack. Errors: LS_ERR_INVALID (NULL, NaN
 * max_dist2), LS_ERR_NONFINITE (p not finite), LS_ERR_STATE (a tree deeper
 * than ls_bvh_build makes: not built by it). */
ls_status ls_bvh_closest(const ls_bvh *bvh, const ls_real p[3], ls_real max_dist2, ls_bvh_hit *hit);

/* ls_bvh_closest_near: ls_bvh_closest with a guess, a triangle likely to be
 * close (the answer of a nearby query, say; UINT32_MAX or any index >=
 * face_count for none). The guess is evaluated first, so the search prunes
 * from the start: on a sequence of nearby queries (samples of a surface in
 * order) it visits far fewer nodes. The answer is the same as
 * ls_bvh_closest's, bit for bit, whatever the guess. Errors as
 * ls_bvh_closest. */
ls_status ls_bvh_closest_near(const ls_bvh *bvh, const ls_real p[3], ls_real max_dist2, uint32_t guess,
                              ls_bvh_hit *hit);

/* Iterator over the triangles whose boxes overlap a query box (closed
 * intervals: touching boxes overlap), for triangle-pair tests such as
 * self-intersection counts. Triangles come leaf by leaf, in a fixed order
 * (depth first, first child first), each at most once. The state lives in the
 * struct (a fixed stack, about 300 bytes); no memory. */
typedef struct ls_bvh_overlap {
    const ls_bvh *bvh;
    ls_real lo[3];
    ls_real hi[3];
    uint32_t stack[LS_BVH_MAX_DEPTH + 2u];
    uint32_t sp;
    uint32_t pos; /* the current leaf's next position in bvh->order */
    uint32_t end;
} ls_bvh_overlap;

/* ls_bvh_overlap_begin: starts an iteration over the triangles of `bvh`
 * whose boxes overlap the box [lo, hi]. O(1). Errors: LS_ERR_INVALID
 * (NULL), LS_ERR_NONFINITE (a NaN bound; infinite bounds are allowed). */
ls_status ls_bvh_overlap_begin(const ls_bvh *bvh, const ls_real lo[3], const ls_real hi[3], ls_bvh_overlap *it);

/* ls_bvh_overlap_next: the next triangle in *face and 1, or 0 when the
 * iteration is over. Total cost O(log F + k) for k reported triangles on
 * well-shaped meshes; no memory. */
int ls_bvh_overlap_next(ls_bvh_overlap *it, uint32_t *face);

/* ls_closest_point_triangle: the closest point of triangle (a, b, c) to p,
 * with its barycentric coordinates (they sum to 1) and squared distance;
 * robust to degenerate triangles (see above). O(1). */
void ls_closest_point_triangle(const ls_real p[3], const ls_real a[3], const ls_real b[3], const ls_real c[3],
                               ls_real point[3], ls_real bary[3], ls_real *dist2);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_BVH_H */
