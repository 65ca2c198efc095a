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
 * Algorithm (ls_silhouette_backward), per view:
 *  1. Silhouette segments: from the edge table (built once per mesh by
 *     ls_edge_table_build: every half-edge's twin), an edge is a silhouette
 *     when it has no twin (a boundary, or a non-manifold edge) or when the
 *     third vertices of its two faces project onto the same side of it (one
 *     face front-, the other back-facing; orientation-independent test).
 *     Also, for every triangle cut by the near plane, the cut (the side of
 *     its clipped polygon on the plane) is a segment of that face with
 *     nothing behind it on the face's side. For a closed mesh seen from
 *     outside (as in 2.) the silhouette edges that are valleys of the
 *     surface (the back face's far corner on the eye's side of the front
 *     face's plane, the two faces wound alike) are left out: the ray to
 *     such an edge arrives through the solid, so a front face hides it
 *     (41 % of the armadillo's silhouette edges in the fit's views). Like
 *     the back-face culling, this assumes no inside-out fold: in a tangled
 *     mesh a valley can show.
 *  2. Candidate bins: every triangle's window polygon (clipped at the near
 *     plane) is binned by its box into square tiles (count, prefix sum,
 *     fill; triangles in index order) of 2, 4 or 8 pixels: 2 below 1/8
 *     covered pixel per triangle, 8 from 1/2 up (counted on every 4th sample
 *     row), so small triangles meet few candidates per run and large ones
 *     few tiles. For a closed mesh seen from outside
 *     (no boundary edge, nothing across the near plane, fewer than 1/64 of
 *     the covered samples showing the minority orientation) the back-facing
 *     orientation is left out: it is never the nearest surface.
 *  3. Each segment is clipped to the image and walked pixel by pixel (the
 *     parameters where it crosses integer x and y lines, merged in order);
 *     the pixels it crosses in one bin tile form a run. The candidates of
 *     a run are the triangles of the tile's bin whose box meets the run's
 *     box, less those whose corners all lie on one side of the segment's
 *     line (by a margin far above rounding), and less the faces that have
 *     an end vertex of the segment as a corner and whose cone at that
 *     corner misses the segment's direction (beyond rounding: a triangle
 *     lies in the cone of its corner's edges, so it holds no other point of
 *     the segment; on the fit's end mesh this halves the candidates).
 *     Every pixel piece is split
 *     where a candidate's polygon edges cross it, so between two splits the
 *     surface in front of the segment and the one behind it do not change.
 *     Each sub-piece's visibility is decided at its midpoint (exact
 *     homogeneous barycentrics and NDC depth of every candidate containing
 *     the point: a nearer one hides it, the nearest farther one is the
 *     surface behind, none: the background) - no occluder is missed for
 *     want of a sample. Only the candidates whose interval along the
 *     segment (where their polygon, grown by far more than rounding, meets
 *     it) holds the midpoint are tested, swept along the run (sorted by
 *     their starts when a run has many), the last occluder first: the cost
 *     of a sub-piece is its depth complexity, not its tile's bin size, and
 *     the intervals decide which candidates are tested, never the answer.
 *     Before that, a run is skipped when a walk proves it hidden: from the
 *     triangle the forward drew under the run's middle, across shared
 *     edges, through faces that contain the segment's points by a margin
 *     and lie in front of it by a margin (containment and NDC depth are
 *     affine along the segment, checked at each face's stretch ends); the
 *     walk goes on along the segment as far as it can, so the runs that
 *     follow inside what it proved cost nothing.
 *  4. Each visible sub-piece is integrated (consecutive ones of a pixel
 *     with the same surface behind as one: the split between them changed
 *     neither side): in mask mode df is constant (one evaluation, exact
 *     moments); otherwise (perspective-correct shading is rational along
 *     the edge) Gauss-Legendre with 3 points, the interval halved (depth
 *     first, at most 4 times) until the 2-point rule agrees with it to 1e-9
 *     (double) / 1e-4 (float) relative. The barycentric areas are affine
 *     along the segment (the face's own once per segment). SH shading
 *     without renormalisation, vertex colours or texture is a quadratic form
 *     of the homogeneous interpolated normal: g . E = (q0 + q1 s + q2 s^2) /
 *     S(s)^2 along a sub-piece, its coefficients set up once per sub-piece
 *     and side; other shading evaluates ls_shade_point per point.
 *  5. g_P = dL/dI_P (RGBA) dotted with df; the sums over the pieces go to a
 *     and b (times the multiplier `boost`), then through the window ->
 *     clip -> positions chain: x = (X/W + 1) width / 2, y = (1 - Y/W) height / 2.
 * Silhouette edges are integrated in the order of the Morton code of their
 * window midpoint's 4 x 4-pixel cell, then of their half-edge (nearby
 * edges share bins, triangles and pixels while these are cached; in
 * half-edge order when there are more than T / 2 of them), then the
 * near-plane cuts in triangle order, and each segment's pieces in order
 * along it: the gradient is the same bits on every run and platform.
 *
 * Near plane: an edge with an endpoint behind Z = -W is clipped there in
 * clip space (p + s (q - p), s = (Z_p + W_p) / ((Z_p + W_p) - (Z_q + W_q)));
 * the clipped point's gradient goes to both vertices, through (1 - s), s
 * and through s itself (that last term is zero in exact arithmetic: the
 * clipped point moves along its own edge line). The cut segments' ends are
 * such points. The side tests use the homogeneous determinant det(X, Y, W)
 * of the segment's ends and a point of the face, valid wherever that point
 * is. Segments are not clipped at the guard band (their window coordinates
 * are computed in floating point).
 *
 * Measured (tests/test_silhouette.c, 12 x 12 views, central differences of
 * an independent float64 exact-coverage reference, smooth weights, double):
 * single and layered triangles, ortho and perspective, closed tetrahedra,
 * icospheres (levels 1 and 2, sub-pixel faces), overlapping triangles whose
 * edges cross inside pixels, perspective-varying colours (silhouette term
 * isolated by holding the reference's polygons), near-plane cuts inside the
 * image, sub-pixel triangles: 76 of 76 configurations within 1e-3 relative,
 * most within 1e-6. Cost (tests/bench/bench_silhouette.c on the fit's
 * meshes, tests/bench/bench_gradient.c): see README.
 *
 * The pair mode (ls_pair_forward / ls_pair_backward below) is the cheap
 * alternative, selected per render by calling it instead of
 * ls_silhouette_backward: its backward is the derivative of its own blended
 * forward (FD: 4e-7 relative), but against the exact derivative of the box
 * image its position gradient is off by a relative L2 error of 0.38
 * (median, smooth weights; cosine 0.97) and 0.57 (random weights; cosine
 * 0.87) on single triangles at 12 x 12, and zero for triangles that hit no
 * pixel centre.
 *
 * Forward consistency: ls_shade is point sampled, so in pixels crossed by a
 * silhouette its image is not the box-filtered one this module
 * differentiates; largesteps/raster_refine.h re-evaluates exactly those
 * pixels with A x A sub-samples (forward and interior gradient), which
 * brings the two together as A grows (the fit's knob `aa`, off by default).
 *
 * The hot loops avoid branches whose outcome has no pattern (which half of
 * an edge comes first, which bin entries meet a run, a tile range of one or
 * two tiles): mispredictions were a quarter of the pass's time on the fit's
 * meshes (callgrind's branch simulation), and selects gave the same bits.
 *
 * Speed (README): the armadillo (52k faces) at 512^2 costs 0.43-0.49 x
 * the forward's time (30 runs of bench_gradient; target 0.5 x); a sixth of
 * it is O(triangles) (orientations, boxes, bins), the rest the visible
 * runs' candidate search, visibility and quadrature (about half), the
 * walks (an eighth), the marked edges' tests and the segments' own work;
 * what moved it last was memory (the edge order, cache hints ahead of each
 * edge and of each marked edge's tests), GCC's code for |x| and the
 * candidates' activation in order (36.4M instructions a view over the
 * fit's 16 cameras).
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
