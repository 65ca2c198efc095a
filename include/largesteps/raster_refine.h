/* largesteps/raster_refine.h - adaptive supersampling of silhouette pixels:
 * forward and interior gradient over the same A x A sub-samples.
 *
 * Why. ls_shade (largesteps/shade.h) point-samples every pixel with S x S
 * samples, while ls_silhouette_backward (largesteps/silhouette.h) is the
 * exact derivative of the box-filtered image. In a pixel crossed by a
 * silhouette the two describe different images (the point-sampled value is
 * piecewise constant in the vertices, the box value moves with them), so
 * finite differences cannot check the gradient there and the optimizer sees
 * another image than the one it differentiates. This module re-evaluates
 * exactly those pixels with A x A sub-samples, so the forward tends to the
 * box value (error O(1/A) per pixel for straight edges), and takes the
 * interior shading gradient of those pixels over the same sub-samples, with
 * the same weights 1/A^2.
 *
 * Which pixels ("edge pixels"). Every pixel crossed by a silhouette
 * segment, walked in window space: the segments are those of
 * ls_silhouette_backward (from the edge table: an edge without a twin, or an
 * edge whose two faces' third vertices lie on the same side of it in the
 * homogeneous (X, Y, W) test, i.e. one face front- and one back-facing;
 * plus, for every triangle cut by the near plane, the cut). Each segment is
 * clipped at the near plane in clip space (an end with W <= 0 after that
 * drops the segment), clipped to the image grown by one pixel, and walked
 * cell by cell (a 2D DDA over the integer x and y lines); every pixel the
 * walk visits is an edge pixel. The choice is geometric, not based on the
 * samples: a silhouette that passes between the samples of a pixel, a
 * sub-pixel triangle that hits no sample and a thin sliver are all found,
 * and interior mesh edges (where the triangle id changes but the shading is
 * continuous) are not refined. Limits:
 *  - hidden silhouette segments (behind the surface) are walked too: their
 *    pixels are refined although they show a smooth surface (conservative:
 *    more work, same image up to the sampling of a smooth function);
 *  - discontinuities that are not silhouette edges are not found:
 *    interpenetrating triangles (intersection curves) and a texture's own
 *    edges, as in ls_silhouette_backward;
 *  - a walk in floating point may miss a pixel the segment only grazes
 *    (within rounding of a pixel side or corner), where the area at stake
 *    is of the order of that rounding;
 *  - a sub-pixel triangle that hits none of the A x A sub-samples is still
 *    missing from the forward (its coverage, at most its area, is the error
 *    that remains; the silhouette gradient sees it).
 *
 * Sub-samples. In an edge pixel (x, y), sub-sample (i, j), i, j in [0, A),
 * sits at window (x + (i + 0.5) / A, y + (j + 0.5) / A), NDC
 * px = (2 (x A + i) + 1) / (width A) - 1, py = 1 - (2 (y A + j) + 1) / (height A).
 * Its visible triangle is found with the exact (unsnapped) geometry: for
 * every triangle of the pixel's bin, the 2D homogeneous edge functions a of
 * the clip coordinates vis->clip at (px, py) (ls_clip_barycentric's
 * arithmetic); the point is covered when every a_k has the sign of sum(a)
 * (zero included), the surface point is in front (sum(a W) of that sign) and
 * its NDC depth sum(a Z) / sum(a W) is in [-1, 1]; smaller depth wins, on
 * equal depth the smaller index (the rasterizer's rule). No clipping is
 * needed: the homogeneous test handles triangles across the near plane.
 * For a closed mesh seen from outside (no boundary edge, no clipped
 * triangle, fewer than 1/64 of the covered samples of vis showing the
 * minority orientation: ls_silhouette_backward's test) the back faces are
 * left out of the bins: they are never the nearest surface.
 * The sub-sample is shaded with ls_shade's per-sample model at the
 * barycentrics ls_clip_barycentric gives there - the same function the
 * shading backward differentiates - or takes the background; the pixel is
 * the mean of its A^2 values (summed in row-major order), alpha the covered
 * fraction. Pixels that are not edge pixels keep ls_shade's value, bit for
 * bit, and their gradient is ls_shade_backward's over the S x S samples.
 *
 * Off. A <= S (0 and 1 included) turns the mode off: ls_refine_shade does
 * nothing and takes no memory, ls_refine_shade_backward is exactly
 * ls_shade_backward_grads; the scratch queries answer 0.
 *
 * Memory (scratch, from the top of the arena, released on return): one byte
 * per pixel (the edge-pixel map), 4 floats per triangle (its window box),
 * one size_t per LS_REFINE_TILE^2-pixel tile plus one and a uint32 per
 * (triangle, tile) pair of the bins (count pass, prefix sum, fill; each
 * tile's list in triangle order), and LS_REFINE_TILE^2 A^2 (uint32 +
 * ls_real) of sub-sample buffers (one tile's edge pixels) plus 2
 * LS_REFINE_TILE A ls_real (their NDC columns and rows). ls_refine_scratch_bytes gives the exact figure for a rasterized
 * view (O(samples + triangles), no memory), ls_refine_scratch_bytes_bound a
 * worst case. With S = 1 the bins' tiles are the rasterizer's (16 x 16), so
 * the bound is the rasterizer's bound plus W H bytes, 16 bytes per triangle
 * and the sub-sample buffers.
 *
 * Cost: O(samples) (the orientation count) + O(triangles) (boxes, bins,
 * edge classification) + O(silhouette length in pixels) (the walks) + per
 * tile holding edge pixels, its bin once, and for each candidate the
 * sub-samples inside its box of the edge pixels it meets; one shading per
 * sub-sample.
 *
 * Order: tiles in image order; in a tile, candidates in triangle order,
 * each against the edge pixels its box meets, then the edge pixels in image
 * order, sub-samples row-major; the backward adds the unrefined pixels first
 * (image order), then the edge pixels tile by tile: the same bits on every
 * run and platform.
 */
#ifndef LARGESTEPS_RASTER_REFINE_H
#define LARGESTEPS_RASTER_REFINE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/render_backward.h>
#include <largesteps/silhouette.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_REFINE_MAX 32u      /* largest A */
#define LS_REFINE_TILE 16u     /* bin tile side in pixels (power of two) */
#define LS_REFINE_TILE_LOG2 4u

/* What a refined call did (optional output). */
typedef struct ls_refine_info {
    uint32_t pixels;      /* edge pixels evaluated with A x A sub-samples */
    uint32_t segments;    /* silhouette segments walked */
    size_t bin_entries;   /* (triangle, tile) pairs of the bins */
    size_t scratch_bytes; /* scratch taken (0 when off) */
} ls_refine_info;

/* ls_refine_scratch_bytes_bound: a worst case of the scratch of
 * ls_refine_shade / ls_refine_shade_backward for any geometry of this size
 * (every triangle in every tile); 0 (LS_OK, nothing else checked) when aa is
 * off for ss. Errors:
 * LS_ERR_INVALID (NULL, zero size, aa above LS_REFINE_MAX, width or height
 * above LS_RASTER_MAX_DIM), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_refine_scratch_bytes_bound(uint32_t width, uint32_t height, uint32_t ss, uint32_t triangle_count,
                                        uint32_t aa, size_t *bytes);

/* ls_refine_scratch_bytes: the exact scratch of ls_refine_shade /
 * ls_refine_shade_backward for the view (view->vis rasterized with its
 * indices and triangle_count, view->table of the same mesh); 0 when off. Errors: LS_ERR_INVALID
 * (NULL, counts differing from the rasterized ones, a table of another mesh,
 * aa above LS_REFINE_MAX), LS_ERR_STATE (vis not rasterized, table not
 * built), LS_ERR_MESH (an index out of range), LS_ERR_TOO_LARGE.
 * O(samples + triangles); no memory. */
ls_status ls_refine_scratch_bytes(const ls_view *view, uint32_t aa, size_t *bytes);

/* ls_refine_shade: overwrites the edge pixels of image [4 width height]
 * (ls_shade's output for the same view) with their A x A value (file
 * comment). view->table: ls_edge_table_build of the same triangles. info
 * (optional) receives the counts. Errors (image, arena and info then
 * unchanged): LS_ERR_INVALID (NULL arrays, counts differing from the
 * rasterized ones, a table of another mesh, aa above LS_REFINE_MAX, as
 * ls_shade), LS_ERR_STATE (vis not rasterized, table not built),
 * LS_ERR_MESH, LS_ERR_NOMEM. Cost: file comment. */
ls_status ls_refine_shade(const ls_view *view, uint32_t aa, ls_real *image, ls_arena *arena, ls_refine_info *info,
                          ls_diag *diag);

/* ls_refine_shade_backward: the interior shading gradient of the refined
 * image: ls_shade_backward_grads over the S x S samples of every pixel that
 * is not an edge pixel, and over the A x A sub-samples (weight 1/A^2 each,
 * the same visible triangles as ls_refine_shade) of the edge pixels.
 * Gradients are ADDED to *grads (as ls_shade_backward_grads). The silhouette
 * term is ls_silhouette_backward's, unchanged. Errors as ls_refine_shade
 * plus those of ls_shade_backward_grads; nothing is written on error.
 * Cost: that of ls_refine_shade plus the per-sample backward. */
ls_status ls_refine_shade_backward(const ls_view *view, uint32_t aa, const ls_real *grad_image,
                                   const ls_shade_grads *grads, ls_arena *arena, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_RASTER_REFINE_H */
