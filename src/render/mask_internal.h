/* mask_internal.h - the exact distance transform of mask.c, for the fit's
 * mask pull (fit_mask_pull.c), which keeps one field per view. */
#ifndef LS_MASK_INTERNAL_H
#define LS_MASK_INTERNAL_H

#include <largesteps/core.h>

/* A distance larger than any in an image (squared pixels). */
#define LS_MASK_FAR ((ls_real)1e20)

/* g [w h]: each pixel's Euclidean distance to the nearest pixel whose alpha
 * (rgba [4 w h]) is above threshold (to_background 0) or at most threshold
 * (to_background 1); LS_MASK_FAR's root where there is none. line: 3 (max(w, h)
 * + 1) reals, v: max(w, h) + 1 indices of work. */
void ls_mask_impl_distance(const ls_real *rgba, uint32_t w, uint32_t h, ls_real threshold, uint32_t to_background,
                           ls_real *g, ls_real *line, uint32_t *v);

#endif /* LS_MASK_INTERNAL_H */
