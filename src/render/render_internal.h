/* render_internal.h - pieces shared by the rasterizer, shading, shading
 * backward and silhouette modules (not part of the public API). */
#ifndef LS_RENDER_INTERNAL_H
#define LS_RENDER_INTERNAL_H

/* The same-bits fast paths that duplicate a general path for the fit's
 * common case (plain SH shading at one sample per pixel): left out where code
 * size counts more than speed (-Os: the Cortex-M4 build), where the general
 * path gives the same bits. -DLS_FAST_PATHS=0 builds the plain paths at any
 * level (make test runs them: tests/stage_flags.sh). */
#ifndef LS_FAST_PATHS
#if defined(__OPTIMIZE_SIZE__)
#define LS_FAST_PATHS 0
#else
#define LS_FAST_PATHS 1
#endif
#endif

#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/render_backward.h>
#include "../base/diag_internal.h"

/* ls_check_triangle_indices: LS_OK when every index of the triangle_count
 * triangles is below vertex_count, else LS_ERR_MESH with diag naming the
 * first bad triangle. O(T). (raster.c) */
ls_status ls_check_triangle_indices(const uint32_t *indices, uint32_t triangle_count, uint32_t vertex_count,
                                    ls_diag *diag);

/* ls_clip_barycentric: perspective-correct barycentrics b of the NDC point
 * (px, py) in triangle f from the clip coordinates (4 per vertex): with
 * u_k = x_k - px w_k and v_k = y_k - py w_k, a = u x v and b = a / sum(a).
 * Fills u, v (for derivatives) and returns sum(a), or 0 when the triangle is
 * edge-on there or the sum is not finite (b is then unset). O(1). (raster.c) */
ls_real ls_clip_barycentric(const ls_real *clip, const uint32_t *f, ls_real px, ls_real py, ls_real u[3],
                            ls_real v[3], ls_real b[3]);

/* ls_clip_barycentric's first part: u, v and the areas a = u x v (b = a /
 * sum(a)), for callers that need no b (the silhouette pass's spans). */
static inline void ls_clip_areas(const ls_real *clip, const uint32_t *f, ls_real px, ls_real py, ls_real u[3],
                                 ls_real v[3], ls_real a[3])
{
    /* unrolled by hand: gcc -O2 keeps small loops over arrays in memory */
    const ls_real *c0 = clip + 4 * (size_t)f[0], *c1 = clip + 4 * (size_t)f[1], *c2 = clip + 4 * (size_t)f[2];
    u[0] = c0[0] - px * c0[3];
    v[0] = c0[1] - py * c0[3];
    u[1] = c1[0] - px * c1[3];
    v[1] = c1[1] - py * c1[3];
    u[2] = c2[0] - px * c2[3];
    v[2] = c2[1] - py * c2[3];
    a[0] = u[1] * v[2] - u[2] * v[1];
    a[1] = u[2] * v[0] - u[0] * v[2];
    a[2] = u[0] * v[1] - u[1] * v[0];
}

/* ls_valley_edge: whether the edge of half-edge h (twin tw: a silhouette,
 * its faces on one side of its screen line) is a valley of the surface,
 * which no eye outside a closed mesh sees. cull: the orientation (sign of
 * the homogeneous determinant of (X, Y, W)) of the faces a closed mesh
 * seen from outside never shows, as ls_silhouette_backward and the refine
 * pass choose it (no boundary edge, nothing across the near plane, the
 * other orientation at most 1/64 of the covered samples); 0: none, and
 * the answer is 0. With the two faces wound alike (the twin runs back
 * along the edge), the ray to a point of a valley comes through the solid
 * (the side of the back face's plane away from the eye, which in a valley
 * lies inside), so it entered the solid through a front face strictly
 * before the point. The test: the sign of the 4 x 4 determinant of the
 * clip coordinates of the edge's ends p, q and the faces' other corners
 * r, d (the corners' orientation in space times det(mvp): convexity does
 * not depend on the view) against the visible orientation -cull. With p's
 * row taken from the others scaled by its W (w_p q - w_q p, ..., W = 0
 * exactly), it is -w_p times the 3 x 3 determinant of their (X, Y, Z):
 * differences at the mesh's scale, where the 4 x 4 one cancels at the
 * scene's (in float it certified none of the armadillo's valleys). 1 only
 * when beyond a bound on the rows' rounding (each component within 2 eps
 * of its products' sum) and the determinant's. O(1). (silhouette.c) */
int ls_valley_edge(const ls_real *clip, const uint32_t *indices, uint32_t h, uint32_t tw, int cull);

/* ls_shade_point: the colour of triangle f at barycentrics b under opts (as
 * ls_shade computes each covered sample). O(lights). (shade.c) */
void ls_shade_point(const ls_shade_opts *opts, const uint32_t *f, const ls_real *normals, const ls_real b[3],
                    ls_real rgb[3]);

/* ls_face_cross: c = (p1 - p0) x (p2 - p0) of face f, its edges into e1,
 * e2; returns |c|^2. O(1). (shade.c) */
ls_real ls_face_cross(const ls_real *positions, const uint32_t *f, ls_real e1[3], ls_real e2[3], ls_real c[3]);

/* ls_vertex_normal_sums: m[3 vertex_count] = per vertex, the sum of the unit
 * normals of its faces, added in face order (degenerate faces skipped): the
 * vectors ls_shade_vertex_normals normalizes. Indices checked by the caller.
 * O(V + T). (shade.c) */
void ls_vertex_normal_sums(const ls_real *positions, uint32_t vertex_count, const uint32_t *indices,
                           uint32_t triangle_count, ls_real *m);

/* ls_face_unit_normal: n = face f's unit normal, the term ls_vertex_normal_sums
 * adds at each of its corners; returns 0 (n zero) for a degenerate or
 * overflowing face, which adds nothing. O(1). (shade.c) */
int ls_face_unit_normal(const ls_real *positions, const uint32_t *f, ls_real n[3]);

/* ls_vertex_normal_unit: n = m / |m| (zero for m = 0), ls_shade_vertex_normals'
 * normal from a vertex's sum m (n may be m). O(1). (shade.c) */
void ls_vertex_normal_unit(const ls_real m[3], ls_real n[3]);

/* ls_vertex_normal_sum_grad: in place, a vertex's sum m becomes dL/dm given
 * g = dL/d(its unit normal). O(1). (render_backward.c) */
void ls_vertex_normal_sum_grad(ls_real m[3], const ls_real g[3]);

/* ls_face_normal_backward: face f's terms of ls_vertex_normals_backward
 * from gm [3 V] = dL/dm: g[0..2] subtracted at corner 0, g[3..5] added at
 * corner 1, g[6..8] at corner 2; returns 0 for a face that adds nothing
 * (degenerate or overflowing). O(1). (render_backward.c) */
int ls_face_normal_backward(const ls_real *positions, const uint32_t *f, const ls_real *gm, ls_real g[9]);

/* ls_shade_uv: the texture coordinates uv[2] of triangle f at barycentrics b
 * from the per-vertex uvs [2 vertex_count]. O(1). (shade.c) */
void ls_shade_uv(const ls_real *uvs, const uint32_t *f, const ls_real b[3], ls_real uv[2]);

/* ls_shade_check_args: the argument checks shared by ls_shade and
 * ls_shade_backward (the visibility buffer and its counts, the mode's
 * required arrays and the triangle indices). O(T). Five arguments: a
 * seventh would be passed on the stack, which the call-graph check counts as
 * a dynamic frame. (shade.c) */
ls_status ls_shade_check_args(const ls_vis *vis, const uint32_t counts[2], const uint32_t *indices,
                              const ls_real *normals, const ls_shade_opts *opts, ls_diag *diag);

/* ls_grid_values_bytes: the bytes of width x height x channels ls_real
 * values (an image or a texture): LS_ERR_INVALID for a zero side or NULL,
 * LS_ERR_TOO_LARGE on overflow. O(1). (texture.c) */
ls_status ls_grid_values_bytes(uint32_t width, uint32_t height, uint32_t channels, size_t *bytes);

/* The shading backward's per-call state (render_backward.c), shared with the
 * adaptive refinement (raster_refine.c), which runs the same per-sample
 * backward over its own sub-samples. */
typedef struct ls_shade_bctx {
    const ls_vis *vis;
    const uint32_t *indices;
    const ls_real *normals;
    const ls_shade_opts *o;
    const ls_real *m; /* mvp */
    ls_real *gp, *gn, *gc, *gt, *guv;
    int sh_plain;      /* SH, no colours, no texture, no renormalization: sh_plain_backward's path */
    ls_real shk[24];   /* SH gradient matrices and constants x 2 / pi, entry-major (sh_grad_consts) */
} ls_shade_bctx;

/* ls_shade_backward_begin: the argument checks of ls_shade_backward_grads
 * and the state *bc of the call (nothing written elsewhere). O(T).
 * (render_backward.c) */
ls_status ls_shade_backward_begin(ls_shade_bctx *bc, const ls_vis *vis, const uint32_t *indices,
                                  uint32_t triangle_count, const ls_real *normals, uint32_t vertex_count,
                                  const ls_shade_opts *opts, const ls_real mvp[16], const ls_real *grad_image,
                                  const ls_shade_grads *grads, ls_diag *diag);

/* ls_shade_backward_pixels: the interior backward of every pixel over its
 * S x S samples, in image order, except the pixels p with skip[p] != 0
 * (skip may be NULL). Not for LS_SHADE_MASK. O(samples). (render_backward.c) */
void ls_shade_backward_pixels(const ls_shade_bctx *bc, uint32_t triangle_count, const ls_real *grad_image,
                              const uint8_t *skip);

/* ls_shade_backward_sample: the backward of one covered sample of triangle
 * f at NDC (px, py), g = dL/d(sample rgb): barycentrics from
 * ls_clip_barycentric on vis->clip (nothing when edge-on). O(lights).
 * (render_backward.c) */
void ls_shade_backward_sample(const ls_shade_bctx *bc, const uint32_t *f, ls_real px, ls_real py, const ls_real g[3]);

/* 1 when no sample of the pixel whose first sample is t0 sees a triangle
 * (ids 0 or beyond the count). */
static inline int ls_pixel_empty(const uint32_t *t0, uint32_t ss, size_t sw, uint32_t triangle_count)
{
    uint32_t i, j;
    if (ss == 1) return t0[0] == 0 || t0[0] > triangle_count; /* the fit's case, without the loops */
    for (j = 0; j < ss; j++, t0 += sw)
        for (i = 0; i < ss; i++)
            if (t0[i] != 0 && t0[i] <= triangle_count) return 0;
    return 1;
}

#endif /* LS_RENDER_INTERNAL_H */
