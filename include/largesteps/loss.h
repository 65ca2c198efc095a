/* largesteps/loss.h - image losses (L1, L2) over RGBA views, with gradients.
 *
 * The loss of a set of V views of width x height pixels is the mean over
 * views, pixels and the four RGBA channels, as the reference driver computes
 * it (large-steps-pytorch scripts/main.py: mean |I - R| or mean (I - R)^2 over
 * the whole V x H x W x 4 tensor):
 *     L1 = (1 / N) sum |I - R|,   L2 = (1 / N) sum (I - R)^2,   N = 4 V W H.
 * Gradients with respect to the rendered values I:
 *     dL1/dI = sign(I - R) / N  (sign(0) = 0),   dL2/dI = 2 (I - R) / N.
 *
 * Images are ls_real RGBA, 4 values per pixel, rows top first (the layout of
 * ls_shade's output and of ls_image). A reference loaded as an ls_image
 * (float) is converted by the caller (value by value) to ls_real.
 *
 * Accumulation is in a fixed order: within a view, blocks of 8 pixels in
 * memory order (the last one shorter); in a block, one plain sum per RGBA
 * channel, the four combined as (R + G) + (B + A); the block sums in a
 * compensated (Neumaier) sum in ls_real; then the per-view sums in view
 * order (compensated), then one division by N. The result is therefore the same bits on every platform
 * and independent of how the views are passed (all at once with
 * ls_loss_views, or view by view with ls_loss_view followed by
 * ls_loss_finish). No memory is used.
 *
 * Accuracy: every summed term is non-negative, so each rounding is relative
 * to the true sum, and the loss's relative error against the exact mean of
 * the given values is at most 20 u (u = LS_REAL_EPSILON / 2: 1.2e-6 in the
 * float build, 2.2e-15 in double): u for a term |d| (3 u for d^2), 9 u for a
 * block (7 + 2 additions), 2 u for each of the two compensated sums, u for
 * the division, and second-order terms below u while a view has fewer than
 * 1 / (16 u) blocks (2^23 pixels in float). tests/test_loss.c checks the
 * bound against a double-double reference on large images with values in
 * [0, 1], over 2^-30..2^30, equal and spiky.
 *
 * Finite inputs whose loss exceeds the range of ls_real give a loss of +inf
 * (LS_OK; the gradient is written as for any finite input).
 */
#ifndef LARGESTEPS_LOSS_H
#define LARGESTEPS_LOSS_H

#include <largesteps/core.h>
#include <largesteps/status.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_LOSS_L1 0u /* mean absolute difference (the default of the paper's figures) */
#define LS_LOSS_L2 1u /* mean squared difference */

/* A running total over views, in view order (compensated sum). */
typedef struct ls_loss_acc {
    uint32_t kind;       /* LS_LOSS_L1 or LS_LOSS_L2 */
    uint32_t width, height, view_count; /* the normalisation N = 4 V W H */
    uint32_t views_done; /* views added so far */
    ls_real sum;         /* sum of the per-view sums */
    ls_real comp;        /* compensation term of that sum */
} ls_loss_acc;

/* ls_loss_begin: starts a total for view_count views of width x height.
 * Errors: LS_ERR_INVALID (NULL, unknown kind, a zero size). O(1). */
ls_status ls_loss_begin(ls_loss_acc *acc, uint32_t kind, uint32_t width, uint32_t height,
                        uint32_t view_count);

/* ls_loss_view: adds one view: rendered and target are [4 width height]
 * RGBA. grad (may be NULL; may alias neither input) receives dL/drendered of
 * the final mean loss (already divided by N). Errors: LS_ERR_INVALID (NULL,
 * more views than announced), LS_ERR_NONFINITE (a non-finite rendered or
 * target value; diag->index is the first such value's index in the view,
 * *acc and grad unchanged). O(width height): two passes, the sum (a
 * non-finite input makes it non-finite; only then are the values scanned one
 * by one) and then the gradient (its cost: docs/rendering.md). No
 * memory. diag may be NULL. */
ls_status ls_loss_view(ls_loss_acc *acc, const ls_real *rendered, const ls_real *target, ls_real *grad,
                       ls_diag *diag);

/* ls_loss_merge: adds to acc the one view that `part` holds (begun with the
 * same kind, size and view count, then one ls_loss_view): the same bits as
 * that ls_loss_view on acc itself, so views taken apart (in parallel) and
 * merged in view order give the loss of the serial order. Errors:
 * LS_ERR_INVALID (NULL, a different shape, part not holding exactly one
 * view, acc already full). O(1). */
ls_status ls_loss_merge(ls_loss_acc *acc, const ls_loss_acc *part);

/* ls_loss_finish: the mean loss (sum / N) into *loss. LS_ERR_STATE when
 * fewer views were added than announced; LS_ERR_INVALID for NULL. O(1). */
ls_status ls_loss_finish(const ls_loss_acc *acc, ls_real *loss);

/* The views ls_loss_views takes at once: the loss and their size. */
typedef struct ls_loss_shape {
    uint32_t kind;       /* LS_LOSS_L1 or LS_LOSS_L2 */
    uint32_t width, height, view_count;
} ls_loss_shape;

/* ls_loss_views: all views of shape at once: rendered[v], target[v] are views
 * [4 width height]; grad (NULL, or an array whose entries may each be NULL)
 * receives the gradients. Same bits as ls_loss_begin / ls_loss_view /
 * ls_loss_finish in view order. Errors as those (diag->index is the value's
 * index within view diag->offset). O(V width height); no memory. */
ls_status ls_loss_views(const ls_loss_shape *shape, const ls_real *const *rendered, const ls_real *const *target,
                        ls_real *const *grad, ls_real *loss, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_LOSS_H */
