/* mask_internal.h - the exact distance transform of mask.c, for the fit's
 * mask pull (fit_mask_pull.c), which keeps one field per view. */
#ifndef LS_MASK_INTERNAL_H
#define LS_MASK_INTERNAL_H

#include <largesteps/core.h>

/* A distance larger than any in an image (squared pixels). */
#define LS_MASK_FAR ((ls_real)1e20)

/* g [w h]: 0 at the pixels distances are taken to, LS_MASK_FAR elsewhere;
 * replaced by each pixel's Euclidean distance to the nearest of them.
 * line: 3 (max(w, h) + 1) reals, v: max(w, h) + 1 indices of work. */
void ls_mask_impl_transform(ls_real *g, uint32_t w, uint32_t h, ls_real *line, uint32_t *v);

#endif /* LS_MASK_INTERNAL_H */
