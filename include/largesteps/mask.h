/* largesteps/mask.h - distances in the mask of an RGBA image (its alpha
 * channel): how far each pixel is from the object or from the background,
 * and how thick the object is in the image.
 *
 * A fit grows its mesh into the targets' masks by their silhouettes; an
 * object only a pixel or two thick in every view (a blade seen at 128 x 128)
 * leaves the silhouette gradients nothing to grow into, and the fit shrinks
 * onto a stub of it. ls_mask_inscribed_radius measures that: the radius in
 * pixels of the largest disc inside the mask.
 *
 * Method: the exact Euclidean distance transform of Felzenszwalb and
 * Huttenlocher (the lower envelope of parabolas), columns then rows, O(w h).
 * Distances are between pixel centres. Deterministic: the same bits on every
 * platform.
 */
#ifndef LARGESTEPS_MASK_H
#define LARGESTEPS_MASK_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ls_mask_distance_bytes: the arena bytes ls_mask_distance and
 * ls_mask_inscribed_radius take (one line's work; ls_mask_inscribed_radius
 * also a field of width x height reals), for any image of at most this size.
 * Errors: LS_ERR_INVALID (NULL, a side 0 or above 65535). */
ls_status ls_mask_distance_bytes(uint32_t width, uint32_t height, size_t *line_bytes, size_t *field_bytes);

/* ls_mask_distance: dist[y width + x] = the distance in pixels from pixel
 * (x, y) to the nearest pixel whose alpha is above `threshold` (to_background
 * 0: 0 on the object, growing outside it) or at most `threshold`
 * (to_background 1: 0 on the background, growing inside the object). Pixels
 * beyond the image are not counted; with no pixel of the kind sought every
 * distance is 1e10. rgba: [4 width height], rows top first. Scratch from
 * `arena` (the line bytes above), released on return. Errors: LS_ERR_INVALID
 * (NULL, sizes as above, threshold not finite), LS_ERR_NOMEM. */
ls_status ls_mask_distance(const ls_real *rgba, uint32_t width, uint32_t height, ls_real threshold,
                           uint32_t to_background, ls_real *dist, ls_arena *arena, ls_diag *diag);

/* ls_mask_inscribed_radius: *radius = the largest distance from a pixel
 * with alpha above 0.5 to the nearest one not above (pixels beyond the image
 * count as background): the radius of the largest disc inside the object, in
 * pixels; 0 when no pixel is inside. 1 for an object one pixel thick, 3.0 in
 * the median view for the blade above. Memory: both sizes of ls_mask_distance_bytes from `arena`,
 * released on return. Errors: as ls_mask_distance. */
ls_status ls_mask_inscribed_radius(const ls_real *rgba, uint32_t width, uint32_t height, ls_arena *arena,
                                   ls_real *radius, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif
