/* largesteps/silhouette.h - exact box-filter silhouette derivatives.
 *
 * The box-filtered image I_P = integral over pixel P of f (the colour of the
 * visible surface) changes with the vertices in two ways: the interior term
 * (largesteps/render_backward.h) and the motion of the discontinuities. For a
 * silhouette edge a -> b (window coordinates, pixels) with s(t) = a + t (b - a)
 * (Reynolds transport; research notes rasterizer.md 3.6 and 4.2):
 *     dI_P/da = N * integral over the visible part of the edge in P of (1 - t) df(t) dt,
 *     dI_P/db = N * integral of t df(t) dt,
 * where N is the edge's normal scaled by its length |b - a|, pointing away from
 * the side the edge's faces cover, and df = f_inside - f_behind per RGBA
 * channel (inside: the edge's face, alpha 1; behind: the nearest surface
 * farther than the edge at that point, or the background with alpha 0).
 *
 * Algorithm (ls_silhouette_backward), per view: silhouette segments from the
 * edge table (boundary edges, edges between a front- and a back-facing face,
 * near-plane cuts; valley edges of a closed mesh seen from outside left
 * out); candidate occluders binned by tile; each segment walked pixel by
 * pixel, every pixel piece split where a candidate's edges cross it, each
 * sub-piece's visibility decided exactly at its midpoint (a run proven hidden
 * by a walk over faces is skipped); the visible pieces integrated (exact
 * moments in mask mode, adaptive Gauss-Legendre otherwise), dotted with
 * dL/dI and chained to the vertices through window and clip coordinates.
 * Edges are visited in a fixed order: the gradient is the same bits on every
 * run and platform. The full description, the near-plane handling, the
 * accuracy measured against finite differences and the pair mode's error:
 * docs/silhouette.md.
 *
 * The pair mode (ls_pair_forward / ls_pair_backward below) is the cheap
 * alternative, selected per render by calling it instead of
 * ls_silhouette_backward. Forward consistency: ls_shade is point sampled;
 * largesteps/raster_refine.h re-evaluates the silhouette pixels with A x A
 * sub-samples so that the forward matches the box filter differentiated
 * here as A grows.
 *
 * Not handled: interpenetrating triangles (intersection curves are not
 * mesh edges); depth ties within 64 eps are neither hiding nor behind. The
 * fit sequences forward, loss and backward itself (fit.c); there is no
 * one-call view forward + backward for other callers.
 */
#ifndef LARGESTEPS_SILHOUETTE_H
#define LARGESTEPS_SILHOUETTE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_EDGE_NONE 0xFFFFFFFFu /* no twin: a boundary or non-manifold edge */

/* Half-edge 3 t + k of triangle t runs from its vertex k to vertex (k + 1) % 3. */
typedef struct ls_edge_table {
    uint32_t triangle_count;
    uint32_t vertex_count;
    uint32_t *twin;  /* [3 triangle_count] the half-edge on the other face, or LS_EDGE_NONE */
    uint32_t boundary_edges; /* half-edges without a twin */
    uint32_t magic;  /* set by ls_edge_table_build */
} ls_edge_table;

/* ls_edge_table_bytes: the exact arena bytes ls_edge_table_build takes at
 * peak: the twin array (3 uint32 per triangle, kept) plus the scratch of the
 * build (3 uint64 keys, 3 + 3 uint32 of sort indices and sort scratch per
 * triangle, released). Errors: LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_edge_table_bytes(uint32_t triangle_count, size_t *bytes);

/* ls_edge_table_build: pairs every half-edge with the half-edge of the other
 * face on the same (unordered) vertex pair, by a stable sort of the keys
 * (min vertex, max vertex). An edge on exactly two faces is paired; on one
 * (boundary) or more than two (non-manifold) faces it gets LS_EDGE_NONE and
 * counts as a silhouette in every view. The twin array comes from the bottom
 * of the arena. Errors: LS_ERR_INVALID (NULL), LS_ERR_MESH (an index >=
 * vertex_count or a face with a repeated vertex; diag->index is the face),
 * LS_ERR_TOO_LARGE (3 triangle_count beyond uint32), LS_ERR_NOMEM (arena and
 * *table unchanged). O(T log T). */
ls_status ls_edge_table_build(ls_edge_table *table, const uint32_t *indices, uint32_t triangle_count,
                              uint32_t vertex_count, ls_arena *arena, ls_diag *diag);

/* ls_silhouette_scratch_bytes: the exact scratch ls_silhouette_backward
 * takes for this view (reads view->vis, rasterized with view->indices and
 * triangle_count, and view->table of the same mesh): 2 ls_real and one byte per vertex (window positions, flags), one
 * byte and 4 floats per triangle (orientation, box), one size_t per tile
 * (of 2, 4 or 8 pixels, as chosen for the view) plus one, a uint32 per
 * (triangle, tile) pair of the candidate
 * bins, and per candidate slot (min(binned triangles, pairs), at least 1)
 * 3 uint32 and 6 ls_real (candidates of a run and its split parameters), plus
 * 2 ls_real; the pairs and binned triangles are counted here by the binning
 * pass, without memory. Errors: LS_ERR_INVALID (NULL, counts differing from
 * the rasterized ones), LS_ERR_STATE (vis not rasterized, table not built),
 * LS_ERR_MESH (an index out of range), LS_ERR_TOO_LARGE.
 * O(samples + triangles). */
ls_status ls_silhouette_scratch_bytes(const ls_view *view, size_t *bytes);

/* ls_silhouette_scratch_bytes_bound: a worst case of the above for any
 * geometry of this size (every triangle in every tile, one slot per
 * triangle): for sizing an arena up front; usually far more than the exact
 * figure. Errors: LS_ERR_INVALID (NULL, zero size), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_silhouette_scratch_bytes_bound(uint32_t width, uint32_t height, uint32_t vertex_count,
                                            uint32_t triangle_count, size_t *bytes);

/* ls_silhouette_scratch_bytes_bins: the scratch of a view of this size whose
 * candidate bins hold at most per_triangle (triangle, tile) pairs per
 * triangle plus per_tile per 2 x 2 pixel tile (counted with the smallest
 * tiles: a view binned with larger ones takes no more): for callers that
 * reserve memory for an expected binning (a triangle of a framed mesh
 * typically meets 1 to 4 tiles) rather than the worst case. Errors: as the
 * bound. O(1). */
ls_status ls_silhouette_scratch_bytes_bins(uint32_t width, uint32_t height, uint32_t vertex_count,
                                           uint32_t triangle_count, uint32_t per_triangle, uint32_t per_tile,
                                           size_t *bytes);

/* ls_silhouette_backward: ADDS the silhouette part of dL/dpositions of one
 * view into grad_positions [3 vertex_count] (see the file comment). view:
 * vis, indices, normals, opts and mvp as given to ls_raster / ls_shade;
 * table from ls_edge_table_build on the same indices; boost multiplies the
 * result (nvdiffrast's pos_gradient_boost; 1 = the exact derivative).
 * grad_image [4 width height] dL/dI (RGBA). Scratch from the top of the
 * arena (ls_silhouette_scratch_bytes), released on return. Errors:
 * LS_ERR_INVALID (NULL arrays, sizes differing from the rasterized ones, a
 * table of another mesh, unknown mode), LS_ERR_STATE (vis not rasterized,
 * table not built), LS_ERR_MESH (an index out of range; diag->index is the
 * face), LS_ERR_NOMEM, LS_ERR_TOO_LARGE. Nothing is written on error.
 * Cost O(triangles + bin entries + runs of silhouette segments x
 * the candidates of their runs, each sub-piece tested against the
 * candidates whose intervals hold it). */
ls_status ls_silhouette_backward(const ls_view *view, const ls_real *grad_image, ls_real *grad_positions,
                                 ls_arena *arena, ls_diag *diag);

/* The pair mode: nvdiffrast's antialiasing (research notes rasterizer.md
 * 1.3) re-implemented deterministically, a cheap approximation of the
 * silhouette term for comparison. Every pixel is paired with its right and
 * lower neighbour; where their triangle ids differ, the owner (the nearer
 * one, or the only one) looks for its silhouette edge crossing the segment
 * between the two pixel centres (at most 45 degrees from perpendicular,
 * crossing within 1/16 pixel of the segment) and the crossing c blends the
 * two point-sampled colours: alpha = ds (1/2 - c); out[p0] += alpha (in[p1] -
 * in[p0]) when alpha > 0, else out[p1] += the same. Pairs are visited in
 * image order (rows, then right before down): the same bits everywhere.
 * Needs S = 1 (else LS_ERR_INVALID); triangles with a vertex behind the
 * near plane are skipped.
 *
 * ls_pair_forward: image_out [4 width height] = image_in (ls_shade's
 * output) blended as above; reads view->vis, table, indices and
 * triangle_count. Errors: LS_ERR_INVALID (NULL, aliasing images,
 * S != 1, counts differing), LS_ERR_STATE (vis or table not built),
 * LS_ERR_MESH. O(pixels); no memory. */
ls_status ls_pair_forward(const ls_view *view, const ls_real *image_in, ls_real *image_out, ls_diag *diag);

/* ls_pair_backward: the backward of ls_pair_forward: from grad_out = dL/d
 * image_out, ADDS dL/dpositions (through the crossings, times view->boost, to the
 * two vertices of each blending edge; none for clamped crossings) into
 * grad_positions [3 vertex_count] and, when grad_in is not NULL, ADDS dL/d
 * image_in into grad_in [4 width height] (for ls_shade_backward). image_in
 * is the forward's input; view as for ls_pair_forward, with mvp and boost.
 * Errors as ls_pair_forward, plus LS_ERR_INVALID for NULL mvp, grad_out or
 * grad_positions. O(pixels); no memory. */
ls_status ls_pair_backward(const ls_view *view, const ls_real *image_in, const ls_real *grad_out, ls_real *grad_in,
                           ls_real *grad_positions, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_SILHOUETTE_H */
