/* largesteps/shade.h - forward shading of a visibility buffer into an RGBA image.
 *
 * Input: an ls_vis filled by ls_raster (largesteps/raster.h), the same
 * triangles, and per-vertex attributes (normals, optionally colours). Every
 * sample is shaded on its own, then each pixel is the box average (mean) of its
 * S x S samples: colour = mean over samples of (surface colour where covered,
 * background colour elsewhere); alpha = coverage = covered samples / S^2.
 * Output: ls_real RGBA, width x height pixels, rows top first (the layout of
 * ls_image in largesteps/image.h): pixel (x, y) channel c at 4 (y width + x) + c.
 *
 * Shading modes (ls_shade_opts.mode); each pays only for what it uses:
 *  - LS_SHADE_MASK: white (1, 1, 1) where covered (the silhouette).
 *  - LS_SHADE_SH: diffuse irradiance from 9 spherical-harmonics coefficients
 *    per channel (Ramamoorthi & Hanrahan 2001, as the reference renderer):
 *    E_c(n) = n_h^T M_c n_h with n_h = (n, 1) and
 *        M = [ c1 L22   c1 L2-2  c1 L21  c2 L11 ]
 *            [ c1 L2-2 -c1 L22   c1 L2-1 c2 L1-1 ]
 *            [ c1 L21   c1 L2-1  c3 L20  c2 L10 ]
 *            [ c2 L11   c2 L1-1  c2 L10  c4 L00 - c5 L20 ]
 *    c1..c5 = 0.429043, 0.511664, 0.743125, 0.886227, 0.247708; colour
 *    = albedo E_c / pi. Coefficients sh[9 c + k], k in the order L00, L1-1,
 *    L10, L11, L2-2, L2-1, L20, L21, L22 (real SH basis on (x, y, z):
 *    Y1-1 ~ y, Y10 ~ z, Y11 ~ x, Y2-2 ~ xy, Y2-1 ~ yz, Y20 ~ 3z^2 - 1,
 *    Y21 ~ xz, Y22 ~ x^2 - y^2).
 *  - LS_SHADE_LAMBERT: albedo sum_l max(0, n . d_l) rgb_l over directional
 *    lights (d_l: unit direction towards the light) plus an ambient term.
 *  - LS_SHADE_COLOR: the albedo (vertex colour and/or texture), unlit.
 * n is the barycentric interpolation of the vertex normals, NOT renormalised
 * (as the reference renderer) unless opts.renormalize is 1. albedo is the
 * interpolated vertex colour when opts.vertex_colors is given, else 1,
 * times the texture colour when opts.texture is given.
 *
 * Textures (largesteps/texture.h). With opts.texture and opts.uvs (one (u, v)
 * per VERTEX, [2 vertex_count]) the albedo is multiplied by the bilinear
 * lookup at uv = b0 uv_0 + b1 uv_1 + b2 uv_2, interpolated with the same
 * perspective-correct barycentrics as every other attribute. Lit: SH or
 * Lambert mode with a texture; unlit: LS_SHADE_COLOR with a texture (vertex
 * colours then optional, multiplying the texture). LS_SHADE_MASK ignores
 * the texture. UVs are per vertex: a seam (the longitude wrap of a UV
 * sphere, or any chart boundary) needs its vertices duplicated, one copy per
 * side; the rasterizer does not mind, but the silhouette module
 * (largesteps/silhouette.h) then sees the seam as an open boundary, which
 * matters only when positions are optimised. With opts.texture NULL nothing
 * of this runs (one pointer test per covered sample).
 *
 * Everything is plain arithmetic in a fixed order (no libm): the same bits on
 * every platform for the same ls_real.
 */
#ifndef LARGESTEPS_SHADE_H
#define LARGESTEPS_SHADE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/raster.h>
#include <largesteps/texture.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_SHADE_MASK 0u
#define LS_SHADE_SH 1u
#define LS_SHADE_LAMBERT 2u
#define LS_SHADE_COLOR 3u

/* Ramamoorthi-Hanrahan constants. */
#define LS_SH_C1 0.429043
#define LS_SH_C2 0.511664
#define LS_SH_C3 0.743125
#define LS_SH_C4 0.886227
#define LS_SH_C5 0.247708

typedef struct ls_light {
    ls_real dir[3]; /* unit direction from the surface towards the light (world) */
    ls_real rgb[3]; /* radiance scale per channel */
} ls_light;

typedef struct ls_shade_opts {
    uint32_t mode;                /* LS_SHADE_* */
    uint32_t renormalize;         /* 1: normalise the interpolated normal */
    const ls_real *sh;            /* [27] SH coefficients, 9 per channel (LS_SHADE_SH) */
    const ls_light *lights;       /* [light_count] (LS_SHADE_LAMBERT) */
    uint32_t light_count;
    ls_real ambient[3];           /* added to the Lambert sum (LS_SHADE_LAMBERT) */
    const ls_real *vertex_colors; /* [3 vertex_count] RGB albedo, or NULL (LS_SHADE_COLOR needs it or a texture) */
    ls_real background[3];        /* RGB where no surface is seen */
    const ls_real *background_image; /* optional [3 width height] RGB per pixel, rows top first;
                                        replaces background when not NULL */
    const ls_texture *texture;    /* optional albedo texture (NULL: none) */
    const ls_real *uvs;           /* [2 vertex_count] (u, v) per vertex (required with texture) */
} ls_shade_opts;

/* ls_shade_opts_init: mode LS_SHADE_MASK, no renormalisation, no lights or
 * colours, no texture, black background, ambient 0. O(1). */
void ls_shade_opts_init(ls_shade_opts *opts);

/* ls_shade_image_bytes: the bytes of the RGBA output of a width x height
 * view (4 ls_real per pixel), for a caller who takes it from an arena.
 * Errors: LS_ERR_INVALID (zero side, NULL), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_shade_image_bytes(uint32_t width, uint32_t height, size_t *bytes);

/* ls_shade: shades view->vis (from ls_raster with view->indices) into out
 * [4 width height] RGBA. Reads vis, indices, triangle_count, vertex_count,
 * opts and normals ([3 vertex_count] vertex normals, unused by
 * LS_SHADE_MASK and LS_SHADE_COLOR, may then be NULL). Errors: LS_ERR_STATE
 * (vis not rasterized), LS_ERR_INVALID (NULL arrays a mode needs, unknown
 * mode, vertex_count differing from the rasterized one, a texture without
 * uvs or failing ls_texture_check), LS_ERR_MESH (an
 * index out of range; diag->index is the triangle). O(samples); no memory. */
ls_status ls_shade(const ls_view *view, ls_real *out, ls_diag *diag);

/* ls_shade_sh_eval: E_c(n) / pi for the three channels at normal n (as
 * given, not normalised) into rgb. O(1). */
void ls_shade_sh_eval(const ls_real sh[27], const ls_real n[3], ls_real rgb[3]);

/* ls_shade_vertex_normals: unit vertex normals into out[3 vertex_count]: the
 * normalised sum of the unit normals of the incident faces (uniform weights,
 * what the reference renderer's weights amount to; research notes 4.3). A
 * vertex with no non-degenerate face gets (0, 0, 0). Errors: LS_ERR_INVALID
 * (NULL arrays), LS_ERR_MESH (index out of range; diag->index is the face).
 * O(vertices + faces); no memory. (A stand-in for the mesh module's normals.) */
ls_status ls_shade_vertex_normals(const ls_real *positions, uint32_t vertex_count, const uint32_t *indices,
                                  uint32_t triangle_count, ls_real *out, ls_diag *diag);

/* ls_sh_from_equirect: projects an equirectangular environment map (RGB,
 * width x height, rows top first, 3 ls_real per pixel) onto the 9 SH
 * coefficients per channel (order as above) into sh[27]. Pixel (i, j) looks
 * in direction (sin t cos p, cos t, sin t sin p) with polar angle
 * t = pi (j + 0.5) / height from +y (up) and azimuth p = 2 pi (i + 0.5) / width;
 * each pixel weighs its solid angle (2 pi / width)(pi / height) sin t.
 * Sums run in a fixed order. Errors: LS_ERR_INVALID (NULL, zero size).
 * O(width height); no memory. */
ls_status ls_sh_from_equirect(const ls_real *rgb, uint32_t width, uint32_t height, ls_real sh[27]);

/* ls_shade_env_background: the background of one view from an
 * equirectangular environment map (RGB, env_width x env_height, rows top
 * first, directions as in ls_sh_from_equirect), looked up (nearest texel) in
 * the world direction of the ray through each pixel centre, into
 * out[3 width height] (rows top first), to be passed as
 * opts.background_image. view and proj are the camera's world-to-view and
 * projection matrices (largesteps/camera.h); the ray through NDC (nx, ny)
 * joins the unprojected points at NDC depth -1 and 1. (The reference
 * renderer's map uses u = 0.75 - phi / 2 pi: convert its maps first.)
 * Errors: LS_ERR_INVALID (NULL, zero size, a singular projection),
 * LS_ERR_NONFINITE (non-finite matrix). O(width height); no memory. */
ls_status ls_shade_env_background(const ls_real *env, uint32_t env_width, uint32_t env_height,
                                  const ls_real view[16], const ls_real proj[16], uint32_t width,
                                  uint32_t height, ls_real *out);

/* Estimating SH lighting from images (a dataset that does not record its
 * lighting). The SH colour of a covered sample is linear in the 27
 * coefficients: colour_c = sum_k sh[9 c + k] b_k(n), with the basis of
 * ls_sh_basis. A uniform albedo scales each channel's 9 coefficients, so
 * the 27 coefficients are the lighting and the albedo together. Given a
 * rasterized view and its target image, ls_sh_accumulate adds the least-
 * squares normal equations of the pixels that the view covers entirely (all
 * S x S samples) and the target covers (alpha >= LS_SH_TARGET_ALPHA):
 * A^T A += r r^T and A^T t_c += r t_c, r the mean of b(n) over the pixel's
 * samples (the ls_shade box average), t the target's RGB. The matrix is the
 * same for the three channels. ls_sh_solve solves them: the coefficients
 * that best reproduce the targets' colours on the current geometry. */
#define LS_SH_TARGET_ALPHA 0.999

typedef struct ls_sh_normal {
    ls_real ata[45];      /* upper triangle of A^T A, rows in turn: (0,0) .. (0,8), (1,1) .. (8,8) */
    ls_real atb[27];      /* A^T t per channel: atb[9 c + k] */
    uint32_t pixels;      /* pixels accumulated */
    uint32_t per_channel; /* 1: views with vertex colours were added, the matrices below hold the sums */
    ls_real ata_rgb[135]; /* per channel (vertex colours): ata_rgb[45 c + ...], packed as ata */
} ls_sh_normal;

/* ls_sh_basis: b[9] with E_c(n) / pi = sum_k sh[9 c + k] b[k] (the
 * operations of ls_shade_sh_eval, factored): b0 = c4 / pi, b1 = 2 c2 y / pi,
 * b2 = 2 c2 z / pi, b3 = 2 c2 x / pi, b4 = 2 c1 x y / pi,
 * b5 = 2 c1 y z / pi, b6 = (c3 z^2 - c5) / pi, b7 = 2 c1 x z / pi,
 * b8 = c1 (x^2 - y^2) / pi. n as given (not normalised). O(1). */
void ls_sh_basis(const ls_real n[3], ls_real b[9]);

/* ls_sh_normal_clear: zero sums. NULL is ignored. O(1). */
void ls_sh_normal_clear(ls_sh_normal *ne);

/* ls_sh_accumulate: adds the pixels of one view (above) to *ne. Reads
 * view->vis (rasterized), indices, triangle_count, vertex_count, normals
 * and opts->renormalize and opts->vertex_colors (opts may be NULL: no
 * renormalisation, no colours); target: [4 width height] RGBA of the
 * view's size. With vertex colours (a per-vertex albedo) a channel's row
 * is the pixel's mean of albedo_c b(n) over its samples, so each channel
 * has its own matrix (ne->per_channel, ata_rgb); the coefficients are then
 * the lighting alone. Pixels are added in image order, a pixel's samples in
 * row order: the same bits for the same inputs and the same order of
 * calls. Errors: LS_ERR_INVALID (NULL arrays, counts differing from the
 * rasterized ones, views with and without vertex colours in one sum),
 * LS_ERR_STATE (vis not set up), LS_ERR_MESH (an index out of range); *ne
 * is then unchanged. O(samples); no memory. */
ls_status ls_sh_accumulate(ls_sh_normal *ne, const ls_view *view, const ls_real *target, ls_diag *diag);

/* ls_sh_solve: the least-squares coefficients of the sums into sh[27]:
 * (A^T A + r I) L_c = A^T t_c per channel, r = LS_SH_RIDGE x the mean of
 * A^T A's diagonal (a tie-break for directions the pixels barely see), by
 * an LDL^T factorisation in a fixed order. Errors: LS_ERR_INVALID (NULL),
 * LS_ERR_STATE (no pixel accumulated), LS_ERR_NOT_SPD (the pixels' normals
 * do not determine the coefficients: too few or all alike), sh then
 * unchanged. O(1). */
#define LS_SH_RIDGE 1e-6
ls_status ls_sh_solve(const ls_sh_normal *ne, ls_real sh[27], ls_diag *diag);

/* Estimating a per-vertex albedo under known SH lighting. A covered
 * sample's colour is albedo_c E_c(n) / pi with albedo_c = sum_j b_j a_jc
 * over its triangle's corners j (barycentrics b_j). ls_albedo_accumulate
 * adds, for every sample of a pixel that the view covers entirely and the
 * target covers (alpha >= LS_SH_TARGET_ALPHA), num[3 v + c] += b_j s_c t_c
 * and den[3 v + c] += b_j s_c^2 for each corner v, s_c = E_c(n) / pi under
 * view->opts->sh, t the target pixel's RGB. These are the least-squares
 * normal equations of the albedo with A^T A lumped to its row sums (the
 * barycentrics sum to 1): a_vc = num / den is a weighted mean of t_c / s_c
 * over the samples the vertex touches, exact for a uniform albedo.
 * ls_albedo_solve sets a_vc = num / den where den > 0 (else a_vc is kept),
 * clamped at 0, then divides each channel by its pooled ratio
 * sum num / sum den: the albedo's mean stays 1, and the lighting (estimated
 * with the albedo, ls_sh_accumulate) carries the scale. (A prior that pulls
 * a vertex with few samples towards the mean, 0.05 of the mean den, was
 * tried: the painted bunny's fit was no better, 1.36 % H against 1.40 %,
 * RMS 0.219 % against 0.188 %, and a known albedo came back worse.) */

/* ls_albedo_accumulate: adds one view (above) to num, den [3 vertex_count]
 * (the caller clears them). Reads view->vis (rasterized), indices,
 * triangle_count, vertex_count, normals, opts->sh and opts->renormalize.
 * Samples in image order: the same bits for the same inputs and calls.
 * Errors: LS_ERR_INVALID (NULL arrays, opts->sh NULL, counts differing from
 * the rasterized ones), LS_ERR_STATE (vis not set up), LS_ERR_MESH (an
 * index out of range; nothing added). O(samples); no memory. */
ls_status ls_albedo_accumulate(const ls_view *view, const ls_real *target, ls_real *num, ls_real *den, ls_diag *diag);

/* ls_albedo_solve: albedo [3 vertex_count] from the sums (above). Errors:
 * LS_ERR_INVALID (NULL), LS_ERR_STATE (no sample accumulated: den all 0;
 * albedo unchanged). O(vertex_count); no memory. */
ls_status ls_albedo_solve(const ls_real *num, const ls_real *den, uint32_t vertex_count, ls_real *albedo,
                          ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_SHADE_H */
