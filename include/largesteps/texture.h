/* largesteps/texture.h - RGB textures: bilinear lookup and its adjoint.
 *
 * A texture is width x height texels of 3 ls_real (RGB), stored like an
 * image: rows top first, texel (i, j) (column i, row j) at 3 (j width + i).
 * Texture coordinates (u, v): u grows to the right, v grows DOWNWARDS, (0, 0)
 * is the top-left corner of the top-left texel and (1, 1) the bottom-right
 * corner of the bottom-right one; texel centres sit at ((i + 0.5) / width,
 * (j + 0.5) / height). (OBJ and OpenGL put v = 0 at the bottom: pass
 * 1 - v_obj.) The texture does not own its texels: they are the caller's
 * array (for instance the parameter vector of a fit), and ls_texture_bytes
 * sizes it for an arena.
 *
 * Lookup (bilinear): with x = u width - 1/2, y = v height - 1/2,
 * i0 = floor(x), j0 = floor(y), fx = x - i0, fy = y - j0,
 *     T(u, v) = (1-fx)(1-fy) t[i0, j0] + fx (1-fy) t[i1, j0]
 *             + (1-fx) fy t[i0, j1] + fx fy t[i1, j1],    i1 = i0 + 1, j1 = j0 + 1,
 * (evaluated as a = t[i0,j0] + fx (t[i1,j0] - t[i0,j0]), b likewise on row j1,
 * T = a + fy (b - a): a constant texture returns its value exactly),
 * where rows are clamped to [0, height - 1] (clamp-to-edge in v) and columns
 * either clamped too (LS_TEXTURE_CLAMP) or taken modulo width
 * (LS_TEXTURE_REPEAT, after u is reduced to [0, 1) by u - floor(u): what a
 * UV sphere's longitude needs). The adjoint scatters a colour gradient g to
 * the four texels with the same weights, in the fixed order (i0, j0),
 * (i1, j0), (i0, j1), (i1, j1), and gives
 *     dT/du = width  ((1-fy)(t[i1, j0] - t[i0, j0]) + fy (t[i1, j1] - t[i0, j1])),
 *     dT/dv = height ((1-fx)(t[i0, j1] - t[i0, j0]) + fx (t[i1, j1] - t[i1, j0])),
 * the derivative of T inside a texel cell (T is continuous and piecewise
 * bilinear: at a cell boundary this is the one-sided derivative from the
 * cell of (i0, j0); where a tap is clamped both taps are the same texel and
 * the derivative is 0, as it is for the clamped lookup).
 *
 * A non-finite coordinate gives a non-finite colour (never an out-of-range
 * read: indices are clamped before use). Plain arithmetic in a fixed order:
 * the same bits on every platform for the same ls_real.
 */
#ifndef LARGESTEPS_TEXTURE_H
#define LARGESTEPS_TEXTURE_H

#include <largesteps/core.h>
#include <largesteps/status.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_TEXTURE_CLAMP 0u  /* u clamped to the edge texels */
#define LS_TEXTURE_REPEAT 1u /* u wraps around (period 1) */

typedef struct ls_texture {
    uint32_t width, height; /* texels, each >= 1 */
    uint32_t wrap_u;        /* LS_TEXTURE_CLAMP or LS_TEXTURE_REPEAT (v always clamps) */
    const ls_real *texels;  /* [3 width height] RGB, rows top first (the caller's array) */
} ls_texture;

/* ls_texture_bytes: the bytes of the texel array of a width x height
 * texture (3 ls_real per texel), for a caller who takes it from an arena.
 * Errors: LS_ERR_INVALID (NULL bytes, zero side), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_texture_bytes(uint32_t width, uint32_t height, size_t *bytes);

/* ls_texture_init: fills *tex with the given size, wrap mode and texel
 * array (not copied). Errors: LS_ERR_INVALID (NULL tex or texels, zero side,
 * unknown wrap mode, width height 3 beyond size_t); *tex is then unchanged.
 * O(1); no memory. */
ls_status ls_texture_init(ls_texture *tex, uint32_t width, uint32_t height, uint32_t wrap_u,
                          const ls_real *texels);

/* ls_texture_check: LS_OK when *tex is usable by the lookups (non-NULL
 * texels, non-zero sides, a known wrap mode), else LS_ERR_INVALID. O(1). */
ls_status ls_texture_check(const ls_texture *tex);

/* ls_texture_sample: the bilinear lookup T(u, v) into rgb[3] (formula
 * above). tex must pass ls_texture_check. O(1); no memory. */
void ls_texture_sample(const ls_texture *tex, ls_real u, ls_real v, ls_real rgb[3]);

/* ls_texture_sample_backward: the adjoint of ls_texture_sample at (u, v) for
 * the colour gradient g[3] = dL/dT: ADDS w_k g to the four texels of
 * grad_texels [3 width height] (same layout as the texels; NULL: not wanted)
 * and writes duv[2] = (g . dT/du, g . dT/dv) (NULL: not wanted). O(1); no
 * memory. */
void ls_texture_sample_backward(const ls_texture *tex, ls_real u, ls_real v, const ls_real g[3],
                                ls_real *grad_texels, ls_real duv[2]);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_TEXTURE_H */
