/* test_camera.c - view and projection matrices against independent float64
 * formulas (libm), the documented window conventions (checked through the
 * rasterizer), and the view sets on the sphere. */
#include "test.h"
#include <stdlib.h>
#include <largesteps/camera.h>
#include <largesteps/raster.h>

#define TEST_PI 3.14159265358979323846

static void apply4(const ls_real m[16], const double p[3], double o[4])
{
    int r;
    for (r = 0; r < 4; r++)
        o[r] = (double)m[4 * r] * p[0] + (double)m[4 * r + 1] * p[1] + (double)m[4 * r + 2] * p[2] +
               (double)m[4 * r + 3];
}

static double tol(double scale)
{
    return TEST_EPS(16) * (1 + fabs(scale));
}

static void look_at_maps_eye_target_and_up(void)
{
    ls_real eye[3] = {(ls_real)1.5, (ls_real)-2, (ls_real)3}, at[3] = {(ls_real)-0.5, (ls_real)1, (ls_real)0.25};
    ls_real up[3] = {(ls_real)0.1, (ls_real)1, (ls_real)0.2}, v[16];
    double e[3], t[3], o[4], d, f[3], rot[9];
    int i, j;
    for (i = 0; i < 3; i++) {
        e[i] = (double)eye[i];
        t[i] = (double)at[i];
        f[i] = t[i] - e[i];
    }
    d = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    REQUIRE(ls_camera_look_at(eye, at, up, v) == LS_OK);
    apply4(v, e, o);
    CHECK_NEAR(o[0], 0, tol(4));
    CHECK_NEAR(o[1], 0, tol(4));
    CHECK_NEAR(o[2], 0, tol(4));
    CHECK_NEAR(o[3], 1, 0);
    apply4(v, t, o); /* the target lies on the -z axis at distance d */
    CHECK_NEAR(o[0], 0, tol(4));
    CHECK_NEAR(o[1], 0, tol(4));
    CHECK_NEAR(o[2], -d, tol(d));
    /* the rotation part is orthonormal with determinant +1 (right-handed) */
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) rot[3 * i + j] = (double)v[4 * i + j];
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            double s = rot[3 * i] * rot[3 * j] + rot[3 * i + 1] * rot[3 * j + 1] + rot[3 * i + 2] * rot[3 * j + 2];
            CHECK_NEAR(s, i == j ? 1.0 : 0.0, tol(1));
        }
    CHECK_NEAR(rot[0] * (rot[4] * rot[8] - rot[5] * rot[7]) - rot[1] * (rot[3] * rot[8] - rot[5] * rot[6]) +
                   rot[2] * (rot[3] * rot[7] - rot[4] * rot[6]),
               1, tol(1));
    /* up maps into the upper half of the image plane: view y of up > 0, view x of up = 0 */
    {
        double u[3] = {(double)up[0], (double)up[1], (double)up[2]};
        double vy = rot[3] * u[0] + rot[4] * u[1] + rot[5] * u[2];
        double vx = rot[0] * u[0] + rot[1] * u[1] + rot[2] * u[2];
        CHECK(vy > 0);
        CHECK_NEAR(vx, 0, tol(1));
    }
    /* degenerate and non-finite input */
    CHECK_STATUS(ls_camera_look_at(eye, eye, up, v), LS_ERR_INVALID);
    {
        ls_real par[3];
        for (i = 0; i < 3; i++) par[i] = at[i] - eye[i];
        CHECK_STATUS(ls_camera_look_at(eye, at, par, v), LS_ERR_INVALID);
        par[1] = (ls_real)NAN;
        CHECK_STATUS(ls_camera_look_at(eye, at, par, v), LS_ERR_NONFINITE);
    }
}

static void perspective_matches_opengl(void)
{
    ls_real p[16];
    double fov = 0.9, n = 0.25, f = 40, aspect = 1.5, o[4], th = tan(fov / 2), q[3];
    /* vertical fov: the top of the frustum at depth d maps to NDC y = 1 */
    REQUIRE(ls_camera_perspective((ls_real)fov, LS_FOV_Y, (ls_real)aspect, (ls_real)n, (ls_real)f, p) == LS_OK);
    q[0] = th * aspect * 3;
    q[1] = th * 3;
    q[2] = -3;
    apply4(p, q, o);
    CHECK_NEAR(o[3], 3, 0);
    CHECK_NEAR(o[0] / o[3], 1, TEST_EPS(64));
    CHECK_NEAR(o[1] / o[3], 1, TEST_EPS(64));
    q[0] = 0;
    q[1] = 0;
    q[2] = -n;
    apply4(p, q, o);
    CHECK_NEAR(o[2] / o[3], -1, TEST_EPS(64));
    q[2] = -f;
    apply4(p, q, o);
    CHECK_NEAR(o[2] / o[3], 1, TEST_EPS(256));
    /* horizontal fov: the right edge at depth d maps to NDC x = 1 */
    REQUIRE(ls_camera_perspective((ls_real)fov, LS_FOV_X, (ls_real)aspect, (ls_real)n, (ls_real)f, p) == LS_OK);
    q[0] = th * 2;
    q[1] = th * 2 / aspect;
    q[2] = -2;
    apply4(p, q, o);
    CHECK_NEAR(o[0] / o[3], 1, TEST_EPS(64));
    CHECK_NEAR(o[1] / o[3], 1, TEST_EPS(64));
    /* the library's tan(fov/2) agrees with libm's */
    CHECK_NEAR((double)p[0], 1 / th, TEST_EPS(8) / th);
    CHECK_STATUS(ls_camera_perspective(0, LS_FOV_Y, 1, 1, 2, p), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_perspective((ls_real)3.2, LS_FOV_Y, 1, 1, 2, p), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_perspective(1, 2u, 1, 1, 2, p), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_perspective(1, LS_FOV_X, 1, 2, 1, p), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_perspective(1, LS_FOV_X, 0, 1, 2, p), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_perspective(1, LS_FOV_X, (ls_real)INFINITY, 1, 2, p), LS_ERR_NONFINITE);
    /* overflow: 2 far near beyond the largest ls_real (the fuzzer's find), p unchanged */
    {
        ls_real before[16];
        memcpy(before, p, sizeof before);
        CHECK_STATUS(ls_camera_perspective(1, LS_FOV_X, 1, 4, LS_REAL_MAX / 2, p), LS_ERR_TOO_LARGE);
        CHECK_STATUS(ls_camera_perspective(1, LS_FOV_X, LS_REAL_MAX, 1, 2, p), LS_ERR_TOO_LARGE);
        CHECK(memcmp(before, p, sizeof before) == 0);
    }
}

static void orthographic_matches_glortho(void)
{
    ls_real p[16];
    double o[4], q[3] = {-2, 5, -1};
    REQUIRE(ls_camera_orthographic(-2, 6, -3, 5, 1, 11, p) == LS_OK);
    apply4(p, q, o);
    CHECK_NEAR(o[0], -1, TEST_EPS(8));
    CHECK_NEAR(o[1], 1, TEST_EPS(8));
    CHECK_NEAR(o[2], -1, TEST_EPS(8));
    CHECK_NEAR(o[3], 1, 0);
    q[0] = 6;
    q[1] = -3;
    q[2] = -11;
    apply4(p, q, o);
    CHECK_NEAR(o[0], 1, TEST_EPS(8));
    CHECK_NEAR(o[1], -1, TEST_EPS(8));
    CHECK_NEAR(o[2], 1, TEST_EPS(8));
    CHECK_STATUS(ls_camera_orthographic(1, 1, 0, 1, 0, 1, p), LS_ERR_INVALID);
}

static void mat4_helpers(void)
{
    ls_real a[16], b[16], c[16], id[16], p[3] = {1, 2, 3}, o[4];
    int i;
    for (i = 0; i < 16; i++) {
        a[i] = (ls_real)(i % 5) - 2;
        b[i] = (ls_real)((i * 7) % 11) - 5;
    }
    ls_mat4_mul(a, b, c);
    for (i = 0; i < 16; i++) {
        int r = i / 4, k = i % 4, j;
        double s = 0;
        for (j = 0; j < 4; j++) s += (double)a[4 * r + j] * (double)b[4 * j + k];
        CHECK_NEAR(c[i], s, 0);
    }
    ls_mat4_identity(id);
    ls_mat4_mul(a, id, c);
    CHECK(memcmp(a, c, sizeof a) == 0);
    ls_mat4_mul(a, b, a); /* aliasing */
    ls_mat4_mul(id, a, c);
    CHECK(memcmp(a, c, sizeof a) == 0);
    ls_mat4_apply(b, p, o);
    for (i = 0; i < 4; i++)
        CHECK_NEAR(o[i], (double)b[4 * i] + 2 * (double)b[4 * i + 1] + 3 * (double)b[4 * i + 2] + (double)b[4 * i + 3], 0);
}

static void fibonacci_dirs_match_libm(void)
{
    uint32_t n = 257, i;
    ls_real *d = (ls_real *)malloc(3 * n * sizeof(ls_real));
    double sum[3] = {0, 0, 0}, mind = 10, ga = TEST_PI * (3 - sqrt(5.0)), max_len = 0, max_err = 0;
    REQUIRE(ls_camera_fibonacci_dirs(n, d) == LS_OK);
    for (i = 0; i < n; i++) {
        double y = 1 - (2.0 * i + 1) / n, r = sqrt(1 - y * y), az = fmod(i * ga, 2 * TEST_PI);
        double len = sqrt((double)d[3 * i] * d[3 * i] + (double)d[3 * i + 1] * d[3 * i + 1] +
                          (double)d[3 * i + 2] * d[3 * i + 2]);
        uint32_t j;
        /* the azimuth i * golden angle is reduced in ls_real: error grows with i */
        max_len = fmax(max_len, fabs(len - 1));
        max_err = fmax(max_err, fabs((double)d[3 * i] - r * cos(az)) / (1 + i));
        max_err = fmax(max_err, fabs((double)d[3 * i + 1] - y) / (1 + i));
        max_err = fmax(max_err, fabs((double)d[3 * i + 2] - r * sin(az)) / (1 + i));
        sum[0] += (double)d[3 * i];
        sum[1] += (double)d[3 * i + 1];
        sum[2] += (double)d[3 * i + 2];
        for (j = 0; j < i; j++) {
            double dx = (double)d[3 * i] - (double)d[3 * j], dy = (double)d[3 * i + 1] - (double)d[3 * j + 1],
                   dz = (double)d[3 * i + 2] - (double)d[3 * j + 2];
            double dd = sqrt(dx * dx + dy * dy + dz * dz);
            if (dd < mind) mind = dd;
        }
    }
    /* evenly spread: centroid near 0, no two directions closer than ~half the mean spacing */
    CHECK(fabs(sum[0]) / n < 0.02 && fabs(sum[1]) / n < TEST_EPS(8) && fabs(sum[2]) / n < 0.02);
    CHECK(mind > 0.5 * sqrt(4 * TEST_PI / n));
    CHECK_MSG(max_len <= TEST_EPS(8), "max |len - 1| %.3g", max_len);
    CHECK_MSG(max_err <= TEST_EPS(64), "max error / (i + 1) vs libm %.3g", max_err);
    CHECK_STATUS(ls_camera_fibonacci_dirs(0, NULL), LS_OK);
    CHECK_STATUS(ls_camera_fibonacci_dirs(3, NULL), LS_ERR_INVALID);
    free(d);
}

static void ring_dirs_match_libm(void)
{
    uint32_t rings = 3, per = 5, k, j;
    ls_real d[3 * 15];
    double max_err = 0;
    REQUIRE(ls_camera_ring_dirs(rings, per, d) == LS_OK);
    for (k = 0; k < rings; k++)
        for (j = 0; j < per; j++) {
            double el = -TEST_PI / 2 + TEST_PI * (k + 1) / (rings + 1);
            double az = 2 * TEST_PI * (j + ((k & 1) ? 0.5 : 0.0)) / per;
            const ls_real *q = d + 3 * (k * per + j);
            max_err = fmax(max_err, fabs((double)q[0] - cos(el) * cos(az)));
            max_err = fmax(max_err, fabs((double)q[1] - sin(el)));
            max_err = fmax(max_err, fabs((double)q[2] - cos(el) * sin(az)));
        }
    CHECK_MSG(max_err <= TEST_EPS(16), "max error vs libm %.3g", max_err);
    CHECK_STATUS(ls_camera_ring_dirs(70000, 70000, d), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_camera_ring_dirs(2, 2, NULL), LS_ERR_INVALID);
}

static void orbit_looks_at_the_center(void)
{
    ls_real c[3] = {1, 2, 3}, dir[3] = {(ls_real)0.3, (ls_real)0.4, (ls_real)-0.2}, v[16];
    ls_real up_dir[3] = {0, 1, 0};
    double o[4], q[3] = {1, 2, 3}, n = sqrt(0.09 + 0.16 + 0.04);
    REQUIRE(ls_camera_orbit(c, 7, dir, v) == LS_OK);
    apply4(v, q, o);
    CHECK_NEAR(o[0], 0, tol(8));
    CHECK_NEAR(o[1], 0, tol(8));
    CHECK_NEAR(o[2], -7, tol(8));
    q[0] = 1 + 7 * 0.3 / n;
    q[1] = 2 + 7 * 0.4 / n;
    q[2] = 3 - 7 * 0.2 / n;
    apply4(v, q, o);
    CHECK_NEAR(o[2], 0, tol(8) * 4);
    /* straight above: still a valid camera */
    CHECK_STATUS(ls_camera_orbit(c, 7, up_dir, v), LS_OK);
    CHECK_STATUS(ls_camera_orbit(c, 0, dir, v), LS_ERR_INVALID);
}

/* The documented window conventions, through the rasterizer: a small
 * triangle around a world point lands on the pixel the formulas in camera.h
 * give (top row first). */
static void window_conventions_hold_in_the_rasterizer(void)
{
    static LS_ARENA_BUFFER(mem, 1 << 20);
    ls_arena a;
    ls_vis vis;
    ls_real view[16], proj[16], mvp[16];
    ls_real eye[3] = {0, 0, 5}, at[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    int trial;
    REQUIRE(ls_arena_init(&a, mem.bytes, sizeof mem.bytes) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &a, 40, 30, 1, 3) == LS_OK);
    REQUIRE(ls_camera_look_at(eye, at, up, view) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)1.0, LS_FOV_X, (ls_real)(40.0 / 30.0), 1, 20, proj) == LS_OK);
    ls_mat4_mul(proj, view, mvp);
    for (trial = 0; trial < 20; trial++) {
        double wx = -1.5 + 0.15 * trial, wy = 1.0 - 0.1 * trial, o[4], q[3], xw, yw;
        ls_real pos[9];
        uint32_t idx[3] = {0, 1, 2};
        size_t s, hit = 0, where = 0;
        q[0] = wx;
        q[1] = wy;
        q[2] = 0;
        apply4(mvp, q, o);
        xw = (o[0] / o[3] + 1) / 2 * 40;
        yw = (1 - o[1] / o[3]) / 2 * 30;
        /* a tiny triangle (0.02 world units) around the point */
        pos[0] = (ls_real)(wx - 0.01);
        pos[1] = (ls_real)(wy - 0.01);
        pos[2] = 0;
        pos[3] = (ls_real)(wx + 0.01);
        pos[4] = (ls_real)(wy - 0.01);
        pos[5] = 0;
        pos[6] = (ls_real)wx;
        pos[7] = (ls_real)(wy + 0.02);
        pos[8] = 0;
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
                .mvp = mvp}, &a, NULL) == LS_OK);
        for (s = 0; s < 40 * 30; s++)
            if (vis.tri[s]) {
                hit++;
                where = s;
            }
        if (fabs(xw - floor(xw) - 0.5) < 0.1 && fabs(yw - floor(yw) - 0.5) < 0.1) {
            /* the point is within 0.1 px of a pixel centre: that pixel is covered */
            CHECK_EQ(hit, 1);
            CHECK_EQ(where, (size_t)floor(yw) * 40 + (size_t)floor(xw));
        } else if (hit) {
            CHECK(fabs((double)(where % 40) + 0.5 - xw) < 0.6 && fabs((double)(where / 40) + 0.5 - yw) < 0.6);
        }
    }
    /* upper-left world point lands in the upper-left image quadrant */
    {
        ls_real pos[9] = {-2, 1, 0, (ls_real)-1.5, 1, 0, -2, (ls_real)1.5, 0};
        uint32_t idx[3] = {0, 1, 2};
        size_t s, n = 0;
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
                .mvp = mvp}, &a, NULL) == LS_OK);
        for (s = 0; s < 40 * 30; s++)
            if (vis.tri[s]) {
                n++;
                CHECK(s % 40 < 20 && s / 40 < 15);
            }
        CHECK(n > 0);
    }
}

/* Framing: centre, radius and distance against float64 formulas (libm tan and
 * sin of the half angles), and every point of a cloud projects inside the
 * image from many directions; with margin 1 a point on the bounding sphere's
 * silhouette reaches the image border on the narrower axis. */
static void framing_fits_the_bounding_sphere(void)
{
    enum { NP = 200 };
    ls_real pts[3 * NP], dirs[3 * 40];
    ls_camera_framing fr;
    ls_diag dg;
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30}, c[3], r = 0;
    uint64_t seed = test_rng_seed(7u);
    uint32_t i, v, axis;
    int k;
    for (i = 0; i < 3 * NP; i++) {
        pts[i] = (ls_real)(test_rng_unit(&seed) * (i % 3 == 1 ? 6.0 : 2.0) + (i % 3 == 2 ? -4.0 : 1.0));
    }
    for (i = 0; i < NP; i++)
        for (k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], (double)pts[3 * i + k]);
            hi[k] = fmax(hi[k], (double)pts[3 * i + k]);
        }
    for (k = 0; k < 3; k++) c[k] = (lo[k] + hi[k]) / 2;
    for (i = 0; i < NP; i++) {
        double d0 = (double)pts[3 * i] - c[0], d1 = (double)pts[3 * i + 1] - c[1], d2 = (double)pts[3 * i + 2] - c[2];
        r = fmax(r, sqrt(d0 * d0 + d1 * d1 + d2 * d2));
    }
    REQUIRE(ls_camera_fibonacci_dirs(40, dirs) == LS_OK);
    for (axis = 0; axis < 2; axis++) {
        const double fov = 0.7, aspect = 1.6;
        double hx = axis == LS_FOV_X ? fov / 2 : atan(tan(fov / 2) * aspect);
        double hy = axis == LS_FOV_Y ? fov / 2 : atan(tan(fov / 2) / aspect);
        double h = fmin(hx, hy), want = r / sin(h) * 1.25, worst = 0;
        REQUIRE(ls_camera_frame(pts, NP, (ls_real)fov, axis, (ls_real)aspect, (ls_real)1.25, &fr, NULL) == LS_OK);
        for (k = 0; k < 3; k++) CHECK_NEAR((double)fr.center[k], c[k], tol(8));
        CHECK_NEAR((double)fr.radius, r, tol(8) * 4);
        CHECK_NEAR((double)fr.distance, want, tol(want) * 8);
        CHECK_NEAR((double)fr.near_plane, (want - r) / 2, tol(want) * 8);
        CHECK_NEAR((double)fr.far_plane, (want + r) * 2, tol(want) * 16);
        for (v = 0; v < 40; v++) {
            ls_real mvp[16], view[16];
            double o[4], q[3];
            REQUIRE(ls_camera_framed_view(&fr, dirs + 3 * v, view, mvp) == LS_OK);
            for (i = 0; i < NP; i++) {
                for (k = 0; k < 3; k++) q[k] = (double)pts[3 * i + k];
                apply4(mvp, q, o);
                CHECK(o[3] > (double)fr.near_plane && o[3] < (double)fr.far_plane);
                worst = fmax(worst, fmax(fabs(o[0] / o[3]), fabs(o[1] / o[3])));
            }
        }
        /* inside, and not absurdly small (the cloud is a box, not a sphere) */
        CHECK_MSG(worst < 1 / 1.25 + 1e-5 && worst > 0.3, "axis %u: max |ndc| %.6f", axis, worst);
        /* margin 1: the sphere's silhouette touches the border on the narrower axis */
        REQUIRE(ls_camera_frame(pts, NP, (ls_real)fov, axis, (ls_real)aspect, 1, &fr, NULL) == LS_OK);
        {
            /* a point on the sphere, on the silhouette cone in the image's narrower direction */
            ls_real mvp[16], view[16], d[3] = {0, 0, 1};
            double dist = (double)fr.distance, rr = (double)fr.radius, o[4], q[3], tx, ty;
            REQUIRE(ls_camera_framed_view(&fr, d, view, mvp) == LS_OK);
            /* view looks down -z from +z: a point at height y = rr cos(h) (x = 0), z at the tangent */
            tx = rr * rr / dist; /* distance from the centre towards the eye of the tangent circle */
            ty = sqrt(rr * rr - tx * tx);
            q[0] = c[0] + (hx < hy ? ty : 0);
            q[1] = c[1] + (hx < hy ? 0 : ty);
            q[2] = c[2] + tx;
            apply4(mvp, q, o);
            CHECK_NEAR(fmax(fabs(o[0] / o[3]), fabs(o[1] / o[3])), 1.0, 1e-5);
        }
    }
    /* errors */
    CHECK_STATUS(ls_camera_frame(pts, 0, 1, LS_FOV_X, 1, 1, &fr, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_frame(pts, NP, 1, LS_FOV_X, 1, (ls_real)0.5, &fr, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_camera_frame(pts, 1, 1, LS_FOV_X, 1, 1, &fr, NULL), LS_ERR_INVALID); /* one point */
    CHECK_STATUS(ls_camera_frame(pts, NP, 4, LS_FOV_X, 1, 1, &fr, NULL), LS_ERR_INVALID);
    {
        CHECK_STATUS(ls_camera_frame(pts, 0, 1, LS_FOV_X, 1, 1, &fr, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "vertex_count") != NULL);
        CHECK_STATUS(ls_camera_frame(pts, NP, 1, LS_FOV_X, 1, (ls_real)0.5, &fr, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "margin") != NULL);
        CHECK_STATUS(ls_camera_frame(pts, 1, 1, LS_FOV_X, 1, 1, &fr, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "positions") != NULL);
        CHECK_STATUS(ls_camera_frame(pts, NP, 4, LS_FOV_X, 1, 1, &fr, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "fov") != NULL);
        CHECK_STATUS(ls_camera_frame(pts, NP, 1, 5u, 1, 1, &fr, &dg), LS_ERR_INVALID);
        CHECK(strstr(dg.what, "fov_axis") != NULL);
    }
    pts[3 * 17 + 1] = (ls_real)INFINITY;
    ls_diag_clear(&dg);
    CHECK_STATUS(ls_camera_frame(pts, NP, 1, LS_FOV_X, 1, 1, &fr, &dg), LS_ERR_NONFINITE);
    CHECK(dg.has_index && dg.index == 17);
    CHECK_STATUS(ls_camera_framed_view(NULL, dirs, NULL, dirs), LS_ERR_INVALID);
}

int main(void)
{
    TEST_INIT("test_camera");
    TEST_RUN(look_at_maps_eye_target_and_up);
    TEST_RUN(perspective_matches_opengl);
    TEST_RUN(orthographic_matches_glortho);
    TEST_RUN(mat4_helpers);
    TEST_RUN(fibonacci_dirs_match_libm);
    TEST_RUN(ring_dirs_match_libm);
    TEST_RUN(orbit_looks_at_the_center);
    TEST_RUN(window_conventions_hold_in_the_rasterizer);
    TEST_RUN(framing_fits_the_bounding_sphere);
    return TEST_END();
}
