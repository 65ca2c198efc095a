/* largesteps/camera.h - view and projection matrices, and view sets on a sphere.
 *
 * Conventions (OpenGL's, as nvdiffrast and Mesa use them):
 *
 *   Matrices are ls_real[16], row-major, acting on column vectors:
 *   p' = M p with p'[r] = sum_c m[4 r + c] p[c]. So m[3], m[7], m[11] hold the
 *   translation and a point (x, y, z) is used as (x, y, z, 1).
 *
 *   View space is right-handed: the camera looks down -z, +y is up and +x is
 *   right on the image.
 *
 *   Clip space: (X, Y, Z, W) = P (view point). For a perspective P, W = -z_view
 *   (positive in front of the camera). Normalised device coordinates are
 *   (X/W, Y/W, Z/W) in [-1, 1]^3: Z/W = -1 on the near plane, +1 on the far plane.
 *   The rasterizer clips against the near plane Z >= -W in homogeneous space and
 *   discards samples with Z/W > 1.
 *
 *   Window: a W_px x H_px image, x to the right, rows top first (row 0 is the top
 *   row, as in image files): x_win = (X/W + 1) / 2 * W_px, y_win = (1 - Y/W) / 2 * H_px.
 *   Pixel (i, j) covers [i, i+1) x [j, j+1) and its centre is (i + 0.5, j + 0.5).
 *   (OpenGL's window origin is at the bottom: its row j is our row H_px - 1 - j.)
 *
 *   Field of view: the full angle in radians, given on the horizontal axis
 *   (LS_FOV_X, as the reference renderer's Mitsuba-style scenes do) or the vertical
 *   one (LS_FOV_Y, as gluPerspective). aspect = W_px / H_px.
 *
 * The reference renderer (large-steps-pytorch scripts/render.py) differs: its
 * projection puts W = +z_view (the camera looks down +z, Mitsuba's convention)
 * and mirrors x, and its background rows are flipped. To read its scenes, build
 * the Mitsuba camera-to-world transform, invert it and negate the view x and z
 * axes (a rotation by pi about y), then use these matrices.
 *
 * Every function here is deterministic on every platform: sines and cosines are
 * the library's own (largesteps/math.h), and the arithmetic order is fixed.
 * None needs memory.
 */
#ifndef LARGESTEPS_CAMERA_H
#define LARGESTEPS_CAMERA_H

#include <largesteps/core.h>
#include <largesteps/status.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_FOV_X 0u /* the field of view spans the image width */
#define LS_FOV_Y 1u /* the field of view spans the image height */

/* ls_mat4_mul: out = a b (apply b first, then a). out may alias a or b. O(64). */
void ls_mat4_mul(const ls_real a[16], const ls_real b[16], ls_real out[16]);

/* ls_mat4_identity: out = I. O(16). */
void ls_mat4_identity(ls_real out[16]);

/* ls_mat4_apply: out = M (p, 1): the homogeneous image of the point p (all four
 * components, no division). O(16). */
void ls_mat4_apply(const ls_real m[16], const ls_real p[3], ls_real out[4]);

/* ls_camera_look_at: the world-to-view matrix of a camera at `eye` looking at
 * `target` with `up` giving the image's up direction (it need not be
 * orthogonal to the view direction). Errors: LS_ERR_NONFINITE for non-finite
 * input, LS_ERR_INVALID when eye == target or up is parallel to the view
 * direction (view is then left unchanged). O(1), no memory. */
ls_status ls_camera_look_at(const ls_real eye[3], const ls_real target[3], const ls_real up[3],
                            ls_real view[16]);

/* ls_camera_perspective: the OpenGL perspective projection (see the file
 * comment) with full field of view `fov` radians on axis `fov_axis` (LS_FOV_X
 * or LS_FOV_Y), aspect = width / height, and clip planes 0 < near < far.
 * Errors: LS_ERR_INVALID for fov outside (0, pi), a bad axis, aspect <= 0 or
 * planes out of order; LS_ERR_NONFINITE for NaN/inf; LS_ERR_TOO_LARGE when an
 * entry would overflow (planes near the largest ls_real, or a fov so small
 * that 1 / tan(fov / 2) times the aspect does); proj is unchanged on error.
 * O(1), no memory. */
ls_status ls_camera_perspective(ls_real fov, uint32_t fov_axis, ls_real aspect, ls_real near_plane,
                                ls_real far_plane, ls_real proj[16]);

/* ls_camera_orthographic: the OpenGL orthographic projection (glOrtho) of the
 * view-space box [left, right] x [bottom, top] x [-near, -far]; W = 1.
 * Errors: LS_ERR_INVALID when left == right, bottom == top or near == far;
 * LS_ERR_NONFINITE for NaN/inf. O(1), no memory. */
ls_status ls_camera_orthographic(ls_real left, ls_real right, ls_real bottom, ls_real top,
                                 ls_real near_plane, ls_real far_plane, ls_real proj[16]);

/* ls_camera_fibonacci_dirs: n unit directions spread evenly on the sphere
 * (Fibonacci lattice): direction i has y = 1 - (2 i + 1) / n, azimuth
 * i * pi (3 - sqrt 5), x = r cos(azimuth), z = r sin(azimuth), r = sqrt(1 - y^2).
 * dirs receives 3 n values. Errors: LS_ERR_INVALID for NULL dirs with n > 0.
 * O(n), no memory. */
ls_status ls_camera_fibonacci_dirs(uint32_t n, ls_real *dirs);

/* ls_camera_ring_dirs: rings * per_ring unit directions on rings of constant
 * latitude: ring k (0 = lowest) at elevation -pi/2 + pi (k + 1) / (rings + 1),
 * direction j of a ring at azimuth 2 pi j / per_ring (+ pi / per_ring on odd
 * rings, so neighbouring rings interleave); x = cos(el) cos(az), y = sin(el),
 * z = cos(el) sin(az). Ring-major order. dirs receives 3 rings per_ring values.
 * Errors: LS_ERR_INVALID for NULL dirs with a non-empty set, LS_ERR_TOO_LARGE
 * when rings * per_ring overflows uint32_t. O(rings per_ring), no memory. */
ls_status ls_camera_ring_dirs(uint32_t rings, uint32_t per_ring, ls_real *dirs);

/* ls_camera_orbit: the world-to-view matrix of a camera at center + distance
 * dir looking at center, with world +y as up (world +z when dir is within
 * about 0.8 degrees of the y axis). dir need not be normalised. Errors as
 * ls_camera_look_at, plus LS_ERR_INVALID for distance <= 0 or a zero dir.
 * O(1), no memory. */
ls_status ls_camera_orbit(const ls_real center[3], ls_real distance, const ls_real dir[3],
                          ls_real view[16]);

/* A camera framing of a mesh for a view set: every camera at `distance` from
 * `center` sees the whole bounding sphere (center, radius) of the vertices. */
typedef struct ls_camera_framing {
    ls_real center[3];  /* centre of the vertices' bounding box */
    ls_real radius;     /* largest distance of a vertex from center (> 0) */
    ls_real distance;   /* camera distance from center */
    ls_real near_plane; /* (distance - radius) / 2 */
    ls_real far_plane;  /* 2 (distance + radius) */
    ls_real proj[16];   /* ls_camera_perspective(fov, fov_axis, aspect, near_plane, far_plane) */
} ls_camera_framing;

/* ls_camera_frame: frames vertex_count points (3 ls_real each) for cameras
 * of full field of view `fov` on axis `fov_axis` and aspect width / height:
 * the bounding sphere is the bounding-box centre and the largest distance of
 * a point from it; with t the tangent of the smaller half field of view (of
 * the two image axes), a sphere of radius r fills the cone exactly at
 * distance r sqrt(1 + t^2) / t, and the distance is that times `margin`
 * (>= 1: 1.05 leaves 5% of free border). Then the view of direction d is
 * ls_camera_orbit(center, distance, d) and its clip transform
 * proj * view. Deterministic (sqrt, fixed order). Errors: LS_ERR_INVALID
 * (NULL arguments, no points, all points equal, margin < 1, errors of
 * ls_camera_perspective), LS_ERR_NONFINITE (a non-finite coordinate or
 * argument; diag->index is the vertex). O(vertex_count); no memory. */
ls_status ls_camera_frame(const ls_real *positions, uint32_t vertex_count, ls_real fov, uint32_t fov_axis,
                          ls_real aspect, ls_real margin, ls_camera_framing *out, ls_diag *diag);

/* ls_camera_framed_view: the world-to-view matrix (may be NULL) and the clip
 * transform mvp = proj * view of the camera of framing fr looking at its
 * centre from direction dir (ls_camera_orbit). Errors as ls_camera_orbit.
 * O(1), no memory. */
ls_status ls_camera_framed_view(const ls_camera_framing *fr, const ls_real dir[3], ls_real view[16],
                                ls_real mvp[16]);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_CAMERA_H */
