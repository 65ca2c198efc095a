/* largesteps/render_backward.h - backward of the interior shading: from
 * dL/d(image) to vertex positions, normals and colours.
 *
 * What is differentiated. ls_shade (largesteps/shade.h) makes every pixel the
 * mean of its S x S samples; a covered sample's colour is a function of the
 * perspective-correct barycentrics b of the point seen there, of the vertex
 * normals and of the vertex colours. This module gives the derivative of that
 * image with respect to the vertex data, holding the discrete visibility (the
 * triangle id of every sample) fixed: the silhouette part of the derivative
 * (where ids change) is largesteps/silhouette.h's.
 *
 * Barycentrics are those of the exact (unsnapped) geometry, from the clip
 * coordinates vis->clip (X_k, Y_k, W_k) of the triangle's vertices and the
 * sample's NDC position (px, py): with u_k = X_k - px W_k, v_k = Y_k - py W_k,
 * the point of the triangle on the sample's ray has b = (u x v) / sum(u x v)
 * (the 2D homogeneous edge functions; they depend on positions both through
 * the edges and through the ray's W). The chain, per covered sample:
 *     dL/db from the shading model (SH: dE_c/dn = 2 (M_c n_h)_xyz / pi;
 *     Lambert: sum over lit lights of d_l rgb_l; vertex colours: the colours;
 *     optional renormalisation: (I - n n^T) / |n|),
 *     dL/da = (dL/db - (b . dL/db)) / sum(a),   a = u x v,
 *     dL/du = v x dL/da,   dL/dv = dL/da x u,
 *     dL/dX_k = dL/du_k,  dL/dY_k = dL/dv_k,  dL/dW_k = -px dL/du_k - py dL/dv_k,
 *     dL/dp_k += M[0..3][0..2]^T dL/d(X, Y, Z, W)_k   (Z does not enter b),
 * and dL/dN_k += b_k dL/dn, dL/dcolour_k += b_k dL/dalbedo.
 * This is the derivative of the image of the exact geometry; the forward's
 * barycentrics come from positions snapped to 1/256 sample, so the two
 * differ at that level. The visibility term is largesteps/silhouette.h's.
 *
 * Order: samples in image order (rows top first, then samples of a pixel in
 * row-major order), each adding into the three vertices of its triangle in
 * the order 0, 1, 2: the sums are the same bits on every run and platform.
 * Gradients are ADDED to the caller's arrays (zero them first), so views can
 * be accumulated one after the other in a fixed order.
 */
#ifndef LARGESTEPS_RENDER_BACKWARD_H
#define LARGESTEPS_RENDER_BACKWARD_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ls_shade_backward: adds the interior-shading gradient of one view.
 * view as ls_shade was given it, with mvp, the matrix ls_raster was given (the clip
 * coordinates in vis->clip are used for the barycentrics, mvp for the chain
 * to positions). grad_image: [4 width height] dL/d(shaded RGBA) (alpha gets
 * no interior gradient). Outputs, each [3 vertex_count] and each optional
 * (NULL = not wanted): grad_positions, grad_normals (dL/d of the `normals`
 * input; feed it to ls_vertex_normals_backward when the normals come from
 * ls_shade_vertex_normals), grad_colors (dL/d opts->vertex_colors).
 * (Texel and UV gradients: ls_shade_backward_grads.)
 * Errors: as ls_shade (LS_ERR_STATE, LS_ERR_INVALID, LS_ERR_MESH), plus
 * LS_ERR_INVALID for NULL mvp or grad_image. Nothing is written on error.
 * O(samples); no memory. */
ls_status ls_shade_backward(const ls_view *view, const ls_real *grad_image, ls_real *grad_positions,
                            ls_real *grad_normals, ls_real *grad_colors, ls_diag *diag);

/* The outputs of ls_shade_backward_grads; each optional (NULL = not wanted),
 * each ADDED to. */
typedef struct ls_shade_grads {
    ls_real *positions; /* [3 vertex_count] */
    ls_real *normals;   /* [3 vertex_count] dL/d of the `normals` input */
    ls_real *colors;    /* [3 vertex_count] dL/d opts->vertex_colors */
    ls_real *texels;    /* [3 width height] dL/d opts->texture->texels (with a texture) */
    ls_real *uvs;       /* [2 vertex_count] dL/d opts->uvs (with a texture) */
} ls_shade_grads;

/* ls_shade_backward_grads: ls_shade_backward with the outputs in *grads,
 * including those of a texture (largesteps/texture.h): with opts->texture, the
 * albedo factor T(uv) at uv = sum_k b_k uv_k gets g_T = dL/dalbedo x vertex
 * colour; its adjoint scatters g_T to the four bilinear texels (in the
 * lookup's fixed order, samples in image order) and gives
 * dL/duv = g_T . dT/duv, so dL/db_k += uv_k . dL/duv (the texture's spatial
 * derivative, chained to positions like every other attribute) and
 * dL/duv_k += b_k dL/duv. The texture's derivative is that of the bilinear
 * cell the point falls in (one-sided on a texel-cell boundary). Errors as
 * ls_shade_backward, plus LS_ERR_INVALID for NULL grads. O(samples); no
 * memory. */
ls_status ls_shade_backward_grads(const ls_view *view, const ls_real *grad_image, const ls_shade_grads *grads,
                                  ls_diag *diag);

/* ls_vertex_normals_backward_bytes: the exact arena bytes
 * ls_vertex_normals_backward takes (3 ls_real per vertex of scratch).
 * Errors: LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE. O(1). */
ls_status ls_vertex_normals_backward_bytes(uint32_t vertex_count, size_t *bytes);

/* ls_vertex_normals_backward: the backward of ls_shade_vertex_normals:
 * given grad_normals = dL/dN [3 vertex_count], ADDS dL/dpositions into
 * grad_positions [3 vertex_count], through N_v = m_v / |m_v|,
 * m_v = sum of the unit normals n_f = c_f / |c_f| of the faces around v,
 * c_f = (p1 - p0) x (p2 - p0): dL/dm = (I - N N^T) dL/dN / |m|,
 * dL/dc = (I - n n^T) dL/dn / |c|, dL/dp1 += e2 x dL/dc, dL/dp2 += dL/dc x e1,
 * dL/dp0 -= both. Faces and vertices the forward skipped (zero area, zero
 * normal sum) get no gradient. Faces are visited in input order. Scratch from
 * the top of the arena (ls_vertex_normals_backward_bytes), released on
 * return. Errors: LS_ERR_INVALID (NULL), LS_ERR_MESH (index out of range;
 * diag->index is the face), LS_ERR_NOMEM (nothing written).
 * O(vertices + faces). */
ls_status ls_vertex_normals_backward(const ls_real *positions, uint32_t vertex_count, const uint32_t *indices,
                                     uint32_t triangle_count, const ls_real *grad_normals,
                                     ls_real *grad_positions, ls_arena *arena, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_RENDER_BACKWARD_H */
