/* largesteps/raster.h - deterministic tile rasterizer: the visibility buffer.
 *
 * Given clip-space transform M (largesteps/camera.h conventions: row-major,
 * column vectors, OpenGL clip space), vertex positions and triangles, the
 * rasterizer finds for every sample the nearest triangle and the
 * perspective-correct barycentrics and depth of the point seen there.
 *
 * Samples. With supersampling factor S (1, 2 or 4) every pixel holds an
 * ordered S x S grid of samples: the sample grid is (width S) x (height S),
 * row-major, top row first; sample (i, j) sits at ((i + 0.5) / S, (j + 0.5) / S)
 * in pixel units, so for S = 1 at pixel centres. Pixel (x, y) owns samples
 * i in [x S, x S + S), j in [y S, y S + S). Buffers are indexed by sample:
 * s = j (width S) + i.
 *
 * Pipeline (per call; every step in a fixed order, integer where it decides):
 *  - each vertex is transformed once: X = M (p, 1) (kept in vis->clip);
 *  - triangles crossing the near plane Z = -W, or with a vertex outside the
 *    guard band (LS_RASTER_GUARD samples beyond the image on each side), are
 *    clipped in homogeneous space; each edge is clipped in a canonical
 *    direction (from the lexicographically smaller endpoint) so that an edge
 *    shared by two triangles yields the same points for both;
 *  - window coordinates (in samples) are snapped to fixed point with
 *    LS_RASTER_SUBPIXEL_BITS fractional bits; edge functions are exact int64;
 *  - both orientations are drawn (no culling); a triangle whose snapped area
 *    is zero covers nothing;
 *  - top-left fill rule (rows going down): a sample exactly on an edge belongs
 *    to the triangle for which that edge is a top edge (horizontal, interior
 *    below) or a left edge (interior to its right). Triangles sharing an edge
 *    therefore cover every sample on it exactly once (watertight);
 *  - binning in LS_RASTER_TILE x LS_RASTER_TILE sample tiles, two passes over
 *    the triangles (count, prefix sum, fill): each tile lists its triangles in
 *    input order, and the bin memory is known before anything is drawn. An
 *    unclipped triangle whose sample box holds at most 12 samples (most of a
 *    fine mesh's) is not binned: it is drawn directly once that memory is
 *    taken (the depth test below makes the order irrelevant);
 *  - depth test on the pair (depth, triangle index): the smaller depth wins and
 *    on equal depth the smaller index wins, so the result does not depend on
 *    drawing order. Samples with depth > 1 (beyond the far plane) are dropped.
 *
 * Outputs per sample (ls_vis): tri = triangle index + 1 (0 = empty);
 * bary = (b0, b1), the perspective-correct barycentric weights of the
 * triangle's first and second vertex (b2 = 1 - b0 - b1), each in [0, 1];
 * depth = Z/W (NDC, -1 near .. 1 far; 1 where empty). Barycentrics are those
 * of the snapped screen triangle (exact integer edge functions at the sample),
 * made perspective-correct with the vertices' 1/W: b_k = (e_k / W_k) / sum(e / W).
 *
 * Limits: width S and height S at most LS_RASTER_MAX_DIM; up to 2^32 - 2
 * triangles.
 */
#ifndef LARGESTEPS_RASTER_H
#define LARGESTEPS_RASTER_H

#include <largesteps/core.h>
#include <largesteps/arena.h>
#include <largesteps/status.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_RASTER_TILE 16u          /* tile side in samples (power of two) */
#define LS_RASTER_TILE_LOG2 4u
#define LS_RASTER_SUBPIXEL_BITS 8u  /* fixed point: 1/256 sample */
#define LS_RASTER_MAX_DIM 8192u     /* max samples per row and per column */
#define LS_RASTER_GUARD 16384u      /* guard band beyond each image side, in samples */

/* The visibility buffer of one view, and per-vertex data of the last
 * rasterization (for interpolation and silhouette derivatives). */
typedef struct ls_vis {
    uint32_t width, height;  /* pixels */
    uint32_t ss;             /* S: samples per pixel side (1, 2, 4) */
    uint32_t sw, sh;         /* sample grid: width S, height S */
    uint32_t vertex_capacity;/* max vertices, fixed at init */
    uint32_t vertex_count;   /* vertices of the last call */
    uint32_t triangle_count; /* triangles of the last call */
    uint32_t *tri;           /* [sw sh] triangle index + 1, 0 = empty */
    ls_real *bary;           /* [2 sw sh] (b0, b1) per sample */
    ls_real *depth;          /* [sw sh] NDC depth Z/W; 1 where empty */
    ls_real *clip;           /* [4 vertex_capacity] clip coordinates (X, Y, Z, W) */
    int32_t *snap;           /* [2 vertex_capacity] window position in 1/256 samples
                                (valid for vertices with Z >= -W inside the guard band) */
    uint32_t *vflags;        /* [vertex_capacity] non-zero: the vertex is behind the near plane
                                or outside the guard band (bit k: outside plane k), so it was
                                clipped and snap is not used for it */
    uint8_t *tile_dirty;     /* [tiles] 1 when a tile may hold drawn samples; clean tiles with
                                nothing to draw are not cleared again (a pure speed-up) */
    size_t bin_entries;      /* tile-list entries of the last call */
    size_t scratch_bytes;    /* scratch bytes the last call took (peak above the object) */
    uint32_t clipped_triangles; /* triangles of the last call that needed clipping */
    uint32_t magic;          /* set by ls_vis_init */
} ls_vis;

struct ls_shade_opts;
struct ls_edge_table;

/* One view of a mesh, as the passes after ls_raster see it: the visibility
 * buffer, the mesh's arrays, the shading and the matrix, set once and handed
 * to every call of the view (ls_raster, ls_shade, ls_shade_backward,
 * ls_silhouette_backward, ls_pair_*, ls_refine_*). A call reads only the
 * fields its comment names; the others may be left zero. The struct holds
 * pointers only: the arrays stay the caller's. */
typedef struct ls_view {
    const ls_vis *vis;           /* the view rasterized from these arrays (not read by ls_raster) */
    const ls_real *positions;    /* [3 vertex_count] xyz (ls_raster) */
    const uint32_t *indices;     /* [3 triangle_count] vertex indices */
    uint32_t triangle_count;
    uint32_t vertex_count;
    const ls_real *normals;      /* [3 vertex_count] vertex normals, for the shading modes that use them */
    const struct ls_shade_opts *opts; /* the shading (largesteps/shade.h) */
    const ls_real *mvp;          /* [16] the matrix (ls_raster, the backward passes) */
    const struct ls_edge_table *table; /* the mesh's edge table (largesteps/silhouette.h): silhouette,
                                         * pair mode and refinement */
    ls_real boost;               /* factor of the silhouette gradient (1: as derived; the fit's
                                  * config.boost): ls_silhouette_backward, ls_pair_backward */
} ls_view;

/* ls_vis_bytes: exact bytes ls_vis_init takes for a width x height image with
 * S x S samples per pixel and up to max_vertices vertices. Errors:
 * LS_ERR_INVALID (NULL bytes, zero size, S not 1/2/4, sample grid beyond
 * LS_RASTER_MAX_DIM), LS_ERR_TOO_LARGE on size_t overflow. O(1). */
ls_status ls_vis_bytes(uint32_t width, uint32_t height, uint32_t ss, uint32_t max_vertices,
                       size_t *bytes);

/* ls_vis_init: allocates the buffers of *vis from the bottom of the arena
 * (ls_vis_bytes of them) and clears them to empty. Errors as ls_vis_bytes,
 * and LS_ERR_NOMEM (the arena is unchanged). O(width height S^2). */
ls_status ls_vis_init(ls_vis *vis, ls_arena *arena, uint32_t width, uint32_t height, uint32_t ss,
                      uint32_t max_vertices);

/* ls_raster_scratch_bytes_bound: a worst case for the scratch ls_raster takes
 * with these sizes: every triangle listed in every tile. Usually far more than
 * needed; ls_raster_scratch_bytes gives the exact figure for given geometry.
 * Errors: LS_ERR_INVALID (as ls_vis_bytes), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_raster_scratch_bytes_bound(uint32_t width, uint32_t height, uint32_t ss,
                                        uint32_t vertex_count, uint32_t triangle_count,
                                        size_t *bytes);

/* ls_raster_scratch_bytes: the exact scratch ls_raster will take for this
 * geometry and view (it runs the binning count pass, transforming vertices on
 * the fly). Arguments as ls_raster. Errors as ls_raster except LS_ERR_NOMEM.
 * O(vertices + triangles + tile entries); no memory. */
ls_status ls_raster_scratch_bytes(const ls_vis *vis, const ls_view *view, size_t *bytes);

/* ls_raster: rasterizes the triangles of view (indices, triangle_count:
 * 3 uint32 vertex indices each) of its vertices (positions, vertex_count:
 * 3 ls_real each, xyz) transformed by view->mvp into *vis,
 * overwriting its previous content. Scratch (64 bytes per vertex in double
 * builds, 8 per triangle, one size_t per tile, 4 per tile-list entry, ~1 KiB
 * of clipping buffers) comes from the top of the arena and is released before
 * return; its size is ls_raster_scratch_bytes, recorded in vis->scratch_bytes.
 * Errors (vis and the arena then unchanged): LS_ERR_STATE (vis not
 * initialised), LS_ERR_INVALID (NULL arrays, vertex_count above the capacity),
 * LS_ERR_MESH (an index >= vertex_count; diag->index is the triangle),
 * LS_ERR_NONFINITE (a non-finite matrix entry or clip coordinate; diag->index
 * is the vertex), LS_ERR_TOO_LARGE (bin entries beyond size_t), LS_ERR_NOMEM.
 * O(vertices + triangles + tile entries + covered samples). */
ls_status ls_raster(ls_vis *vis, const ls_view *view, ls_arena *arena, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_RASTER_H */
