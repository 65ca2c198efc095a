/* largesteps/distance.h - distances between two triangle meshes: Hausdorff,
 * mean and RMS, over vertex samples and over dense area-uniform face samples,
 * plus the normal angle error at the closest points.
 *
 * For a sample point p of mesh A, d(p, B) is the distance to the closest
 * point of B's surface (ls_bvh_closest, exact brute-force result). Two kinds
 * of samples are used, in each direction:
 *   - vertices: every vertex of the sampled mesh (unreferenced ones included).
 *     The symmetric maximum over vertices is what libigl's `igl::hausdorff`
 *     returns (it is symmetric and vertex-sampled), i.e. the "H" of the Large
 *     Steps paper's lambda-sweep figure (its comparison figure plots twice it).
 *     A lower bound of the surface Hausdorff distance.
 *   - face samples: `samples` points spread over the sampled mesh's faces in
 *     proportion to their areas: face f gets round(N C_f) - round(N C_{f-1})
 *     points (C_f the cumulative area fraction up to f, so the counts add up
 *     to N exactly), placed at the 2-D additive-recurrence (R2, plastic
 *     number) point of their global sample index, folded into the triangle:
 *     area-uniform, low-discrepancy, deterministic (32-bit integer
 *     arithmetic), no random generator. Zero-area faces get no samples.
 * Means and RMS are over the samples of one kind in one direction (face
 * samples: area-weighted by construction), accumulated with compensated
 * (Neumaier) sums in sample order. The symmetric mean and RMS average the two
 * directions (mean: (m_ab + m_ba) / 2; RMS: sqrt((r_ab^2 + r_ba^2) / 2)) over
 * the face samples, or over the vertices when there are no face samples.
 * Relative values divide by the diagonal of B's (the target's) bounding box.
 *
 * Normal angle error: at every face sample of A, the angle in degrees between
 * A's face normal there and the normal of B's closest triangle (0 when
 * parallel, 180 when opposite); samples whose closest triangle of B is
 * degenerate are not counted.
 */
#ifndef LARGESTEPS_DISTANCE_H
#define LARGESTEPS_DISTANCE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>
#include <largesteps/bvh.h>
#include <largesteps/parallel.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Statistics of one set of samples (distances, or angles in degrees). */
typedef struct ls_dist_stats {
    ls_real max;     /* largest value (0 without samples) */
    ls_real mean;    /* mean value */
    ls_real rms;     /* sqrt(mean of squares) */
    uint32_t count;  /* number of samples */
    uint32_t argmax; /* the first sample with the largest value: a vertex index, or a
                        face-sample index (UINT32_MAX without samples) */
} ls_dist_stats;

/* One direction: the samples of a mesh against a target surface. */
typedef struct ls_dist_one_way {
    ls_dist_stats vertex; /* every vertex of the sampled mesh */
    ls_dist_stats face;   /* the area-uniform face samples */
    ls_dist_stats normal; /* normal angle error at the face samples, degrees */
} ls_dist_one_way;

/* Both directions and the symmetric summary. */
typedef struct ls_distance_report {
    ls_dist_one_way ab;        /* samples of A against B */
    ls_dist_one_way ba;        /* samples of B against A */
    ls_real vertex_hausdorff;  /* max(ab.vertex.max, ba.vertex.max): igl::hausdorff */
    ls_real hausdorff;         /* max over every sample, both ways (vertices and faces) */
    ls_real mean;              /* (ab.face.mean + ba.face.mean) / 2 (a direction without face
                                  samples contributes its vertex mean instead) */
    ls_real rms;               /* sqrt((ab.face.rms^2 + ba.face.rms^2) / 2) (same rule) */
    ls_real diag;              /* diagonal of B's bounding box */
    ls_real vertex_hausdorff_rel; /* the four above divided by diag (0 when diag is 0) */
    ls_real hausdorff_rel;
    ls_real mean_rel;
    ls_real rms_rel;
} ls_distance_report;

/* A default face-sample count for a mesh: 10 per vertex, at least 1000
 * (the Metro/MeshLab habit is about one per vertex; this is denser). O(1). */
uint32_t ls_distance_default_samples(const ls_mesh *mesh);

/* ls_distance_one_way: the samples of `src` (its vertices and `samples`
 * face samples) against the surface of the tree `target` (built with
 * ls_bvh_build on the target mesh). O((V + N) log F) time; no memory.
 * Errors: LS_ERR_INVALID (NULL), LS_ERR_MESH (an index of src out of range;
 * diag->index = the face), LS_ERR_NONFINITE (a NaN or infinite coordinate
 * of src; diag->index = the vertex); *out is unchanged on failure. */
ls_status ls_distance_one_way(const ls_mesh *src, const ls_bvh *target, uint32_t samples, ls_dist_one_way *out,
                              ls_diag *diag);

/* ls_mesh_distance_bytes: the exact arena bytes of ls_mesh_distance for
 * meshes with these face counts (both trees). O(1). Errors: LS_ERR_INVALID
 * (NULL, a zero face count), LS_ERR_TOO_LARGE. */
ls_status ls_mesh_distance_bytes(uint32_t faces_a, uint32_t faces_b, size_t *bytes);

/* ls_mesh_distance_parallel_bytes: the exact arena bytes of
 * ls_mesh_distance_parallel with `workers` workers (1: ls_mesh_distance_bytes).
 * O(1). Errors: as ls_mesh_distance_bytes; workers 0: LS_ERR_INVALID. */
ls_status ls_mesh_distance_parallel_bytes(uint32_t faces_a, uint32_t faces_b, uint32_t workers, size_t *bytes);

/* ls_mesh_distance: both directions between meshes a and b (samples_a face
 * samples on a, samples_b on b; see ls_distance_default_samples) and the
 * symmetric summary. Builds the two trees in the arena and releases them
 * before returning (nothing stays allocated). O((V + N) log F). Errors:
 * LS_ERR_INVALID (NULL, a mesh without faces), LS_ERR_MESH, LS_ERR_NONFINITE
 * (diag says which mesh in `what` and the element in index), LS_ERR_NOMEM;
 * on failure the arena and *out are unchanged. */
ls_status ls_mesh_distance(const ls_mesh *a, const ls_mesh *b, uint32_t samples_a, uint32_t samples_b,
                           ls_arena *arena, ls_distance_report *out, ls_diag *diag);

/* ls_mesh_distance_parallel: ls_mesh_distance on the caller's parallel-for
 * (largesteps/parallel.h; par NULL, par->run NULL or workers 1: on this
 * thread): each direction in rounds of 4,096 points, the closest points
 * of a round in slices on the workers, their distances and angles added in
 * point order on this thread: the same report, bit for bit, for any worker
 * count. samples: samples_a and samples_b. Memory:
 * ls_mesh_distance_parallel_bytes (with workers > 1 the two trees and the
 * rounds' arrays, 80 KiB in double, are held together). Errors as
 * ls_mesh_distance; workers 0: LS_ERR_INVALID. */
ls_status ls_mesh_distance_parallel(const ls_mesh *a, const ls_mesh *b, const uint32_t samples[2], const ls_parallel *par,
                                    uint32_t workers, ls_arena *arena, ls_distance_report *out, ls_diag *diag);

/* ls_distance_sample_point: face sample number k (0 <= k < samples) of
 * `mesh` as ls_distance_one_way places it: its face (*face) and position.
 * O(F) (it walks the cumulative areas; for tests and tools). Errors:
 * LS_ERR_INVALID (NULL, k >= samples, zero total area), LS_ERR_MESH. */
ls_status ls_distance_sample_point(const ls_mesh *mesh, uint32_t samples, uint32_t k, uint32_t *face, ls_real point[3]);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_DISTANCE_H */
