/* largesteps/tangle.h - how tangled a triangle mesh is: self-intersecting
 * triangle pairs, faces inverted relative to a reference orientation, and the
 * distribution of triangle shapes (corner angles, radius ratio).
 *
 * Self-intersection. Two faces are tested when their boxes overlap (a BVH
 * over the mesh's own triangles, ls_bvh_overlap). The rule depends on the
 * vertex indices they share:
 *   - none: they intersect when their closed point sets meet (touching
 *     counts): some edge of one meets the other triangle, which covers
 *     crossing, containment and coplanar overlap;
 *   - one vertex v: they intersect when they meet anywhere but at v: the edge
 *     opposite v in either meets the other triangle (a fan folded through
 *     itself). Contact along two collinear edges through v is not counted;
 *   - two or three (neighbours across an edge, duplicates): never counted
 *     (a fold across an edge shows up as an inverted face instead).
 * Predicates are orientation signs in ls_real arithmetic (exact for the
 * small-integer and axis-aligned configurations in the tests; near-zero signs
 * may be misjudged). A degenerate (zero-normal) triangle is never crossed,
 * but its edges are tested against the other triangle.
 *
 * Shapes: corner angles atan2(|e1 x e2|, e1 . e2) in degrees over all 3F
 * corners, and the radius ratio q = 2 r / R = 16 A^2 / (a b c (a + b + c))
 * (1 for equilateral, 0 for degenerate). Percentiles are nearest-rank:
 * the value of rank ceil(p n / 100) in ascending order (p = 1, 5, 50).
 */
#ifndef LARGESTEPS_TANGLE_H
#define LARGESTEPS_TANGLE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>
#include <largesteps/parallel.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ls_tangle_report {
    uint32_t face_count;
    uint32_t intersecting_pairs;  /* face pairs that intersect (rules above) */
    uint32_t intersecting_faces;  /* faces in at least one such pair */
    uint32_t first_pair[2];       /* the first pair in (lower face, higher face) order; LS_MESH_NONE if none */
    uint32_t has_reference;       /* 1 when a reference was given */
    uint32_t inverted_faces;      /* normal . reference normal < 0 */
    uint32_t first_inverted;      /* lowest inverted face, LS_MESH_NONE if none */
    uint32_t degenerate_faces;    /* zero normal (in the mesh) */
    ls_real angle_min, angle_p1, angle_p5, angle_p50, angle_max; /* degrees */
    ls_real quality_min, quality_p1, quality_p5, quality_p50, quality_mean;
} ls_tangle_report;

/* ls_tangle_bytes: exact arena bytes of ls_tangle for a mesh of face_count
 * faces (its BVH, a bit per face, then the sort of 3F angles). O(1).
 * Errors: LS_ERR_INVALID (NULL, zero faces), LS_ERR_TOO_LARGE. */
ls_status ls_tangle_bytes(uint32_t face_count, size_t *bytes);

/* ls_tangle: fills *out for `mesh`. `reference` (optional, NULL to skip the
 * inverted count) gives the orientation each face should have: the same
 * number of faces, face f of the mesh compared with face f of the reference
 * (normally the initial mesh: same connectivity, other positions).
 * O(F log F + k) for k overlapping box pairs. Memory: scratch only (released
 * before returning). Errors: LS_ERR_INVALID (NULL, no faces, reference with
 * another face count), LS_ERR_MESH (index out of range; diag->index = face),
 * LS_ERR_NONFINITE (diag->index = vertex), LS_ERR_NOMEM; on failure the
 * arena and *out are unchanged. */
ls_status ls_tangle(const ls_mesh *mesh, const ls_mesh *reference, ls_arena *arena, ls_tangle_report *out,
                    ls_diag *diag);

/* ls_tangle_parallel: ls_tangle with the search for intersecting pairs split
 * into blocks of faces on the caller's parallel-for (largesteps/parallel.h;
 * par NULL, par->run NULL or workers 1: this thread), tasks numbered by
 * worker < workers. The report is the same for every worker count and
 * every order the tasks run in (counts added, the least first pair, the
 * faces' bits joined). ls_tangle_parallel_bytes: its exact arena bytes,
 * ls_tangle_bytes plus a bit per face and a count for each worker beyond
 * the first. Errors as ls_tangle and ls_tangle_bytes; workers 0:
 * LS_ERR_INVALID, above LS_TANGLE_MAX_WORKERS: LS_ERR_TOO_LARGE. */
#define LS_TANGLE_MAX_WORKERS 1024u
ls_status ls_tangle_parallel_bytes(uint32_t face_count, uint32_t workers, size_t *bytes);
ls_status ls_tangle_parallel(const ls_mesh *mesh, const ls_mesh *reference, const ls_parallel *par, uint32_t workers,
                             ls_arena *arena, ls_tangle_report *out, ls_diag *diag);

/* ls_tangle_pairs: ls_tangle_parallel's self-intersections alone
 * (intersecting_pairs, intersecting_faces, first_pair and face_count; the
 * rest 0, first_inverted LS_MESH_NONE): the check of a fit that needs no more, in about two
 * thirds of the time (no sorts of the angles and qualities). Memory: at
 * most ls_tangle_parallel_bytes. Errors as ls_tangle_parallel. */
ls_status ls_tangle_pairs(const ls_mesh *mesh, const ls_parallel *par, uint32_t workers, ls_arena *arena,
                          ls_tangle_report *out, ls_diag *diag);

/* ls_tangle_pair: 1 when faces f and g of `mesh` intersect by the rules
 * above, else 0 (also for f == g or an index out of range). O(1); no memory.
 * The brute-force check of ls_tangle's count (all pairs) uses it. */
int ls_tangle_pair(const ls_mesh *mesh, uint32_t f, uint32_t g);

/* ls_triangles_meet: 1 when the closed triangles (a0, a1, a2) and
 * (b0, b1, b2) have a common point, else 0 (no shared-vertex rule). O(1). */
int ls_triangles_meet(const ls_real a0[3], const ls_real a1[3], const ls_real a2[3], const ls_real b0[3],
                      const ls_real b1[3], const ls_real b2[3]);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_TANGLE_H */
