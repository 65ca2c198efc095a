/* camera.c - view and projection matrices, view sets on a sphere.
 * Conventions are in include/largesteps/camera.h. */
#include <largesteps/camera.h>
#include <largesteps/status.h>
#include <largesteps/math.h>
#include "../base/diag_internal.h"
#include <string.h>
#include <math.h>

#if LS_REAL_IS_FLOAT
#define R_SIN ls_sinf
#define R_COS ls_cosf
#define R_SQRT sqrtf
#else
#define R_SIN ls_sin
#define R_COS ls_cos
#define R_SQRT sqrt
#endif

#define R_PI ((ls_real)3.14159265358979323846)

static int finite_r(ls_real x)
{
    return x - x == x - x; /* false for NaN and +-inf */
}

static int finite3(const ls_real *v)
{
    return finite_r(v[0]) && finite_r(v[1]) && finite_r(v[2]);
}

void ls_mat4_identity(ls_real out[16])
{
    int i;
    for (i = 0; i < 16; i++) out[i] = (ls_real)0;
    out[0] = out[5] = out[10] = out[15] = (ls_real)1;
}

void ls_mat4_mul(const ls_real a[16], const ls_real b[16], ls_real out[16])
{
    ls_real t[16];
    size_t r, c;
    for (r = 0; r < 4; r++) {
        for (c = 0; c < 4; c++) {
            /* fixed order: ((a0 b0 + a1 b1) + a2 b2) + a3 b3 */
            ls_real s = a[4 * r] * b[c];
            s += a[4 * r + 1] * b[4 + c];
            s += a[4 * r + 2] * b[8 + c];
            s += a[4 * r + 3] * b[12 + c];
            t[4 * r + c] = s;
        }
    }
    memcpy(out, t, sizeof t);
}

void ls_mat4_apply(const ls_real m[16], const ls_real p[3], ls_real out[4])
{
    size_t r;
    ls_real t[4];
    for (r = 0; r < 4; r++) {
        ls_real s = m[4 * r] * p[0];
        s += m[4 * r + 1] * p[1];
        s += m[4 * r + 2] * p[2];
        s += m[4 * r + 3];
        t[r] = s;
    }
    memcpy(out, t, sizeof t);
}

static void cross3(const ls_real a[3], const ls_real b[3], ls_real out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static ls_real dot3(const ls_real a[3], const ls_real b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Normalises v in place; returns 0 when its length is zero or not finite. */
static int normalize3(ls_real v[3])
{
    ls_real n2 = dot3(v, v), n;
    if (!(n2 > (ls_real)0) || !finite_r(n2)) return 0;
    n = R_SQRT(n2);
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
    return 1;
}

ls_status ls_camera_look_at(const ls_real eye[3], const ls_real target[3], const ls_real up[3],
                            ls_real view[16])
{
    ls_real f[3], s[3], u[3], upn[3];
    if (eye == NULL || target == NULL || up == NULL || view == NULL) return LS_ERR_INVALID;
    if (!finite3(eye) || !finite3(target) || !finite3(up)) return LS_ERR_NONFINITE;
    f[0] = target[0] - eye[0];
    f[1] = target[1] - eye[1];
    f[2] = target[2] - eye[2];
    upn[0] = up[0];
    upn[1] = up[1];
    upn[2] = up[2];
    if (!normalize3(f) || !normalize3(upn)) return LS_ERR_INVALID;
    cross3(f, upn, s);
    /* up (anti)parallel to the view direction: no image orientation */
    if (!(dot3(s, s) > (ls_real)1e-12f)) return LS_ERR_INVALID;
    if (!normalize3(s)) return LS_ERR_INVALID;
    cross3(s, f, u);
    view[0] = s[0];
    view[1] = s[1];
    view[2] = s[2];
    view[3] = -dot3(s, eye);
    view[4] = u[0];
    view[5] = u[1];
    view[6] = u[2];
    view[7] = -dot3(u, eye);
    view[8] = -f[0];
    view[9] = -f[1];
    view[10] = -f[2];
    view[11] = dot3(f, eye);
    view[12] = view[13] = view[14] = (ls_real)0;
    view[15] = (ls_real)1;
    return LS_OK;
}

ls_status ls_camera_perspective(ls_real fov, uint32_t fov_axis, ls_real aspect, ls_real near_plane,
                                ls_real far_plane, ls_real proj[16])
{
    ls_real half, t, sx, sy, p10, p11;
    int i;
    if (proj == NULL || fov_axis > LS_FOV_Y) return LS_ERR_INVALID;
    if (!finite_r(fov) || !finite_r(aspect) || !finite_r(near_plane) || !finite_r(far_plane))
        return LS_ERR_NONFINITE;
    if (!(fov > (ls_real)0) || !(fov < R_PI) || !(aspect > (ls_real)0) || !(near_plane > (ls_real)0) ||
        !(far_plane > near_plane))
        return LS_ERR_INVALID;
    half = fov * (ls_real)0.5;
    t = R_SIN(half) / R_COS(half); /* tan(fov / 2) > 0 */
    if (!(t > (ls_real)0) || !finite_r(t)) return LS_ERR_INVALID;
    if (fov_axis == LS_FOV_X) {
        sx = (ls_real)1 / t;
        sy = sx * aspect;
    } else {
        sy = (ls_real)1 / t;
        sx = sy / aspect;
    }
    p10 = -(far_plane + near_plane) / (far_plane - near_plane);
    p11 = -((ls_real)2 * far_plane * near_plane) / (far_plane - near_plane);
    /* huge planes or a tiny fov overflow (proj is then left unchanged) */
    if (!finite_r(sx) || !finite_r(sy) || !finite_r(p10) || !finite_r(p11)) return LS_ERR_TOO_LARGE;
    for (i = 0; i < 16; i++) proj[i] = (ls_real)0;
    proj[0] = sx;
    proj[5] = sy;
    proj[10] = p10;
    proj[11] = p11;
    proj[14] = (ls_real)-1;
    return LS_OK;
}

ls_status ls_camera_orthographic(ls_real left, ls_real right, ls_real bottom, ls_real top,
                                 ls_real near_plane, ls_real far_plane, ls_real proj[16])
{
    int i;
    if (proj == NULL) return LS_ERR_INVALID;
    if (!finite_r(left) || !finite_r(right) || !finite_r(bottom) || !finite_r(top) ||
        !finite_r(near_plane) || !finite_r(far_plane))
        return LS_ERR_NONFINITE;
    if (left == right || bottom == top || near_plane == far_plane) return LS_ERR_INVALID;
    for (i = 0; i < 16; i++) proj[i] = (ls_real)0;
    proj[0] = (ls_real)2 / (right - left);
    proj[3] = -(right + left) / (right - left);
    proj[5] = (ls_real)2 / (top - bottom);
    proj[7] = -(top + bottom) / (top - bottom);
    proj[10] = (ls_real)-2 / (far_plane - near_plane);
    proj[11] = -(far_plane + near_plane) / (far_plane - near_plane);
    proj[15] = (ls_real)1;
    return LS_OK;
}

ls_status ls_camera_fibonacci_dirs(uint32_t n, ls_real *dirs)
{
    /* the golden angle as a fraction of a turn: (3 - sqrt 5) / 2 */
    const ls_real golden_turn = (ls_real)0.38196601125010515180;
    uint32_t i;
    if (n == 0) return LS_OK;
    if (dirs == NULL) return LS_ERR_INVALID;
    for (i = 0; i < n; i++) {
        ls_real y = (ls_real)1 - ((ls_real)2 * (ls_real)i + (ls_real)1) / (ls_real)n;
        ls_real r2 = (ls_real)1 - y * y, r, turn, az;
        uint32_t whole;
        r = r2 > (ls_real)0 ? R_SQRT(r2) : (ls_real)0;
        /* reduce the azimuth to [0, 1) turns before scaling by 2 pi so that
         * the argument of sin/cos stays small */
        turn = (ls_real)i * golden_turn;
        whole = (uint32_t)turn; /* 0 <= turn < 2^32 */
        turn -= (ls_real)whole;
        az = turn * (ls_real)2 * R_PI;
        dirs[3 * (size_t)i] = r * R_COS(az);
        dirs[3 * (size_t)i + 1] = y;
        dirs[3 * (size_t)i + 2] = r * R_SIN(az);
    }
    return LS_OK;
}

ls_status ls_camera_ring_dirs(uint32_t rings, uint32_t per_ring, ls_real *dirs)
{
    uint32_t k, j;
    if (rings == 0 || per_ring == 0) return LS_OK;
    if (per_ring > UINT32_MAX / rings) return LS_ERR_TOO_LARGE;
    if (dirs == NULL) return LS_ERR_INVALID;
    for (k = 0; k < rings; k++) {
        ls_real el = -R_PI * (ls_real)0.5 + R_PI * ((ls_real)k + (ls_real)1) / ((ls_real)rings + (ls_real)1);
        ls_real ce = R_COS(el), se = R_SIN(el);
        for (j = 0; j < per_ring; j++) {
            ls_real turn = ((ls_real)j + ((k & 1u) ? (ls_real)0.5 : (ls_real)0)) / (ls_real)per_ring;
            ls_real az = turn * (ls_real)2 * R_PI;
            size_t o = 3 * ((size_t)k * per_ring + j);
            dirs[o] = ce * R_COS(az);
            dirs[o + 1] = se;
            dirs[o + 2] = ce * R_SIN(az);
        }
    }
    return LS_OK;
}

ls_status ls_camera_orbit(const ls_real center[3], ls_real distance, const ls_real dir[3],
                          ls_real view[16])
{
    ls_real d[3], eye[3];
    ls_real up_y[3] = {(ls_real)0, (ls_real)1, (ls_real)0};
    ls_real up_z[3] = {(ls_real)0, (ls_real)0, (ls_real)1};
    if (center == NULL || dir == NULL || view == NULL) return LS_ERR_INVALID;
    if (!finite3(center) || !finite3(dir) || !finite_r(distance)) return LS_ERR_NONFINITE;
    if (!(distance > (ls_real)0)) return LS_ERR_INVALID;
    d[0] = dir[0];
    d[1] = dir[1];
    d[2] = dir[2];
    if (!normalize3(d)) return LS_ERR_INVALID;
    eye[0] = center[0] + distance * d[0];
    eye[1] = center[1] + distance * d[1];
    eye[2] = center[2] + distance * d[2];
    /* |d.y| > cos(0.8 deg): looking almost straight up or down */
    return ls_camera_look_at(eye, center, (d[1] > (ls_real)0.9999 || d[1] < (ls_real)-0.9999) ? up_z : up_y,
                             view);
}

static ls_status frame_nonfinite(uint32_t i, ls_diag *diag)
{
    return ls_diag_set(diag, LS_ERR_NONFINITE, "vertex with a non-finite coordinate", i);
}

ls_status ls_camera_frame(const ls_real *positions, uint32_t vertex_count, ls_real fov, uint32_t fov_axis,
                          ls_real aspect, ls_real margin, ls_camera_framing *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_real lo[3], hi[3], c[3], r2 = (ls_real)0, t, proj[16];
    ls_real r, dist, near_plane, far_plane;
    uint32_t i;
    int k;
    ls_status st;
    if (positions == NULL) return ls_invalid_arg(diag, "positions is NULL");
    if (out == NULL) return ls_invalid_arg(diag, "out is NULL");
    if (vertex_count == 0) return ls_invalid_arg(diag, "vertex_count: 0; at least one point");
    if (!finite_r(margin) || !finite_r(fov) || !finite_r(aspect)) return LS_ERR_NONFINITE;
    if (!(margin >= (ls_real)1)) return ls_invalid_arg(diag, "margin: allowed >= 1");
    /* a projection with a unit near plane gives the half-angle tangents */
    st = ls_camera_perspective(fov, fov_axis, aspect, (ls_real)1, (ls_real)2, proj);
    if (st == LS_ERR_INVALID) {
        return ls_invalid_arg(diag, fov_axis > LS_FOV_Y        ? "fov_axis: allowed LS_FOV_X or LS_FOV_Y"
                                    : !(aspect > (ls_real)0) ? "aspect: allowed > 0"
                                                             : "fov: allowed in (0, pi) radians");
    }
    if (st != LS_OK) return st;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = positions[k];
    for (i = 0; i < vertex_count; i++) {
        const ls_real *p = positions + 3 * (size_t)i;
        if (!finite3(p)) return frame_nonfinite(i, diag);
        for (k = 0; k < 3; k++) {
            if (p[k] < lo[k]) lo[k] = p[k];
            if (p[k] > hi[k]) hi[k] = p[k];
        }
    }
    for (k = 0; k < 3; k++) c[k] = lo[k] + (hi[k] - lo[k]) * (ls_real)0.5;
    for (i = 0; i < vertex_count; i++) {
        const ls_real *p = positions + 3 * (size_t)i;
        ls_real d[3], q;
        d[0] = p[0] - c[0];
        d[1] = p[1] - c[1];
        d[2] = p[2] - c[2];
        q = dot3(d, d);
        if (q > r2) r2 = q;
    }
    if (!(r2 > (ls_real)0) || !finite_r(r2))
        return ls_invalid_arg(diag, "positions: all points equal, or too far apart for ls_real");
    r = R_SQRT(r2);
    /* the smaller half-angle: the larger of proj[0] = 1 / tan(hx), proj[5] = 1 / tan(hy) */
    t = (ls_real)1 / (proj[0] > proj[5] ? proj[0] : proj[5]);
    dist = r * R_SQRT((ls_real)1 + t * t) / t * margin;
    near_plane = (dist - r) * (ls_real)0.5;
    far_plane = (dist + r) * (ls_real)2;
    if (!finite_r(dist) || !(near_plane > (ls_real)0))
        return ls_invalid_arg(diag, "margin or fov: the camera distance is not finite");
    st = ls_camera_perspective(fov, fov_axis, aspect, near_plane, far_plane, out->proj);
    if (st == LS_ERR_INVALID) return ls_invalid_arg(diag, "margin or fov: no valid projection at this distance");
    if (st != LS_OK) return st;
    for (k = 0; k < 3; k++) out->center[k] = c[k];
    out->radius = r;
    out->distance = dist;
    out->near_plane = near_plane;
    out->far_plane = far_plane;
    return LS_OK;
}

ls_status ls_camera_framed_view(const ls_camera_framing *fr, const ls_real dir[3], ls_real view[16],
                                ls_real mvp[16])
{
    ls_real v[16];
    ls_status st;
    if (fr == NULL || mvp == NULL) return LS_ERR_INVALID;
    st = ls_camera_orbit(fr->center, fr->distance, dir, v);
    if (st != LS_OK) return st;
    if (view != NULL) memcpy(view, v, sizeof v);
    ls_mat4_mul(fr->proj, v, mvp);
    return LS_OK;
}
