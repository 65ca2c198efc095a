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
 *  1. Silhouette edges: from the edge table (built once per mesh by
 *     ls_edge_table_build: every half-edge's twin), an edge is a silhouette
 *     when it has no twin (a boundary, or a non-manifold edge) or when the
 *     third vertices of its two faces project onto the same side of it (one
 *     face front-, the other back-facing; orientation-independent test).
 *  2. The edge is clipped to the image rectangle and walked pixel by pixel
 *     (the parameters where it crosses integer x and y lines, merged in
 *     order; each piece's pixel is that of its midpoint).
 *  3. Each piece is integrated with 3-point Gauss-Legendre quadrature
 *     (exact when df (1 - t) is a polynomial of degree <= 5 in t: exact for
 *     flat and screen-affine colours; perspective-correct shading is
 *     rational along the edge, so this is an approximation there). At each
 *     point the triangles seen by the 3 x 3 samples around it (other than
 *     the edge's faces) are candidates: one that contains the point and is
 *     nearer (NDC depth) hides the point (no contribution); the nearest
 *     farther one is the surface behind; none: the background.
 *  4. g_P = dL/dI_P (RGBA) dotted with df; the sums over the pieces go to a
 *     and b (times the multiplier `boost`), then through the window ->
 *     clip -> positions chain: x = (X/W + 1) width / 2, y = (1 - Y/W) height / 2.
 * Half-edges are visited in index order and each edge's pieces in order along
 * it: the gradient is the same bits on every run and platform.
 *
 * Near plane: an edge with an endpoint behind Z = -W is clipped there in
 * clip space (p + s (q - p), s = (Z_p + W_p) / ((Z_p + W_p) - (Z_q + W_q)));
 * the clipped point's gradient goes to both vertices, through (1 - s), s
 * and through s itself (that last term is zero in exact arithmetic: the
 * clipped point moves along its own edge line). The side tests use the
 * homogeneous determinant det(X, Y, W) of the edge's endpoints and the third
 * vertex, valid wherever the third vertex is. Edges are not clipped at the
 * guard band (their window coordinates are computed in floating point).
 *
 * Limits of this first version (next steps of issue 9):
 *  - visibility is resolved with the sample grid (occluders that hit no
 *    sample of the 3 x 3 neighbourhood are missed), and an occluder whose
 *    silhouette crosses the edge inside a pixel is resolved only at the
 *    quadrature points (TODO: find the crossing - intersect the edge with
 *    the candidate occluder's edges - and split the piece there);
 *  - when the near plane cuts a triangle inside the view, the cut is an
 *    image discontinuity that is no mesh edge: not handled (TODO: treat the
 *    clipped polygon's near-plane side as an extra silhouette segment);
 *  - 3-point Gauss-Legendre per pixel piece only; perspective-correct
 *    shading makes df rational along the edge (TODO: adaptive quadrature,
 *    and an FD test with SH shading under perspective);
 *  - the pair (nvdiffrast-style) mode, forward consistency in edge pixels
 *    (adaptive supersampling / exact coverage in ls_shade), the gradient
 *    digests and the benchmark are not written.
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

/* ls_silhouette_backward: ADDS the silhouette part of dL/dpositions of one
 * view into grad_positions [3 vertex_count] (see the file comment). vis,
 * indices, normals, opts and mvp as given to ls_raster / ls_shade; table
 * from ls_edge_table_build on the same indices; grad_image [4 width height]
 * dL/dI (RGBA); boost multiplies the result (nvdiffrast's
 * pos_gradient_boost; 1 = the exact derivative). Errors: LS_ERR_INVALID (NULL
 * arrays, sizes differing from the rasterized ones, a table of another
 * mesh), LS_ERR_STATE (vis not rasterized, table not built), LS_ERR_MESH (an
 * index out of range; diag->index is the face). Nothing is written on error.
 * Cost O(triangles + pixels crossed by silhouette edges); no memory. */
ls_status ls_silhouette_backward(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                 uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                 const ls_shade_opts *opts, const ls_real mvp[16], ls_real boost,
                                 const ls_real *grad_image, ls_real *grad_positions, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_SILHOUETTE_H */
