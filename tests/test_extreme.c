/* tests/test_extreme.c - extremes of the inputs: mesh scales
 * 1e-6 and 1e6, lambda = 0, 1e-8, 1e8 and alpha = 0.999999 through a fit,
 * a camera inside the mesh, every vertex behind the camera, a mesh collapsed
 * to a point, a single triangle, 10^6 triangles inside one pixel, NaN and
 * infinity appearing in a target or a gradient during a fit (a named error
 * with the iteration and the fit byte for byte as before), and the fit's
 * exact scale invariance: a scene scaled by 2^k, k = -20 ... 20, gives
 * 2^k times the k = 0 result, bit for bit. Each case asserts finite results
 * and the exact outcome (a result or a named error). */
#include "test.h"
#include <stdlib.h>
#include <time.h>

#define RES 16u
#define NV 3u
#define BUF_BYTES (48u << 20)

static unsigned char *buf;
static ls_real sh[27];

static void sh_light(void)
{
    int c;
    memset(sh, 0, sizeof sh);
    for (c = 0; c < 3; c++) {
        sh[9 * c + 0] = (ls_real)1.6;
        sh[9 * c + 1] = (ls_real)0.9;
        sh[9 * c + 2] = (ls_real)0.5;
        sh[9 * c + 3] = (ls_real)-0.3;
    }
}

static int all_finite(const ls_real *v, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        if (!isfinite((double)v[i])) return 0;
    return 1;
}

static double max_abs(const ls_real *v, size_t n)
{
    double m = 0.0;
    size_t i;
    for (i = 0; i < n; i++)
        if (fabs((double)v[i]) > m) m = fabs((double)v[i]);
    return m;
}

/* nv views of a scene of scale s: cameras on a sphere of radius 3.2 s about
 * the origin, near 0.1 s, far 10 s. */
static void cameras(ls_real s, uint32_t nv, ls_real *mvp)
{
    ls_real dirs[3 * 8], proj[16], view[16];
    const ls_real center[3] = {0, 0, 0};
    uint32_t v;
    REQUIRE(nv <= 8);
    REQUIRE(ls_camera_fibonacci_dirs(nv, dirs) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1 * s, (ls_real)10 * s, proj) == LS_OK);
    for (v = 0; v < nv; v++) {
        REQUIRE(ls_camera_orbit(center, (ls_real)3.2 * s, dirs + 3 * v, view) == LS_OK);
        ls_mat4_mul(proj, view, mvp + 16 * v);
    }
}

static void shading(ls_shade_opts *o)
{
    ls_shade_opts_init(o);
    o->mode = LS_SHADE_SH;
    o->sh = sh;
}

/* An icosphere of `level` with axes (a0, a1, a2) times s. */
static ls_status ellipsoid(uint32_t level, ls_real s, const ls_real axes[3], ls_arena *arena, ls_mesh *m)
{
    uint32_t i, k;
    ls_status st = ls_icosphere(level, arena, m);
    if (st != LS_OK) return st;
    for (i = 0; i < m->vertex_count; i++)
        for (k = 0; k < 3; k++) m->positions[3 * i + k] *= axes[k] * s;
    return LS_OK;
}

/* One view: raster (S = ss), normals, shade into img; then, when grad is
 * given, the whole backward of L = sum(w . img) with a fixed weight image w:
 * shading, silhouettes (boost 1) and the normals, into grad [3 n]. */
typedef struct view_out {
    uint32_t covered;   /* pixels with alpha > 0 */
    uint32_t clipped;   /* triangles clipped at the near plane */
} view_out;

static ls_status render_view(const ls_mesh *m, const ls_real mvp[16], uint32_t res, uint32_t ss, ls_real *img,
                             ls_real *grad, view_out *vo, ls_arena *arena)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_shade_opts o;
    ls_vis vis;
    ls_edge_table table;
    ls_real *normals, *gimg, *gnorm;
    const uint32_t n = m->vertex_count;
    uint32_t i;
    ls_status st;
    shading(&o);
    normals = (ls_real *)ls_arena_alloc(arena, 3u * n, sizeof(ls_real));
    gimg = (ls_real *)ls_arena_alloc(arena, 4u * res * res, sizeof(ls_real));
    gnorm = (ls_real *)ls_arena_alloc(arena, 3u * n, sizeof(ls_real));
    if (gnorm == NULL) return LS_ERR_NOMEM;
    st = ls_shade_vertex_normals(m->positions, n, m->triangles, m->face_count, normals, NULL);
    if (st == LS_OK) st = ls_vis_init(&vis, arena, res, res, ss, n);
    if (st == LS_OK) st = ls_raster(&vis, &(ls_view){.positions = m->positions, .indices = m->triangles,
            .triangle_count = m->face_count, .vertex_count = n, .mvp = mvp}, arena, NULL);
    if (st == LS_OK) st = ls_shade(&(ls_view){.vis = &vis, .indices = m->triangles, .triangle_count = m->face_count,
            .vertex_count = n, .normals = normals, .opts = &o}, img, NULL);
    if (st == LS_OK && vo != NULL) {
        vo->covered = 0;
        for (i = 0; i < res * res; i++) vo->covered += img[4 * i + 3] > 0;
        vo->clipped = vis.clipped_triangles;
    }
    if (st == LS_OK && grad != NULL) {
        for (i = 0; i < 4u * res * res; i++) gimg[i] = (ls_real)(1 + (int)(i % 7u)) / (ls_real)7;
        memset(grad, 0, 3u * n * sizeof(ls_real));
        memset(gnorm, 0, 3u * n * sizeof(ls_real));
        st = ls_shade_backward(&(ls_view){.vis = &vis, .indices = m->triangles, .triangle_count = m->face_count,
                .vertex_count = n, .normals = normals, .opts = &o, .mvp = mvp}, gimg, grad, gnorm, NULL, NULL);
        if (st == LS_OK) st = ls_edge_table_build(&table, m->triangles, m->face_count, n, arena, NULL);
        if (st == LS_OK)
            st = ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = m->triangles,
                    .triangle_count = m->face_count, .vertex_count = n, .normals = normals, .opts = &o, .mvp = mvp,
                    .table = &table, .boost = 1}, gimg, grad, arena, NULL);
        if (st == LS_OK) st = ls_vertex_normals_backward(m->positions, n, m->triangles, m->face_count, gnorm, grad, arena, NULL);
    }
    ls_arena_restore(arena, mark);
    return st;
}

/* A short large-steps fit: `iters` steps, a remesh before step remesh_at
 * (none if >= iters), the result (caller units) into *out (malloc'd). */
static ls_status run_fit(const ls_fit_config *c, const ls_fit_views *views, const ls_mesh *init, uint32_t iters,
                         uint32_t remesh_at, ls_arena *arena, ls_real **out, uint32_t *out_n, ls_diag *d)
{
    ls_fit fit;
    ls_mesh res;
    uint32_t it;
    ls_status st = ls_fit_init(&fit, c, views, init, arena, d);
    *out = NULL;
    for (it = 0; st == LS_OK && it < iters; it++) {
        if (it == remesh_at) st = ls_fit_remesh(&fit, arena, (ls_real)0.5, (ls_real)0.8, NULL, d);
        if (st == LS_OK) st = ls_fit_step(&fit, NULL, d);
    }
    if (st != LS_OK) return st;
    *out = (ls_real *)malloc(3u * fit.vertex_count * sizeof(ls_real));
    if (*out == NULL) return LS_ERR_NOMEM;
    *out_n = fit.vertex_count;
    return ls_fit_mesh(&fit, *out, &res);
}

static void fit_config(ls_fit_config *c)
{
    ls_fit_config_default(c);
    c->width = c->height = RES;
    c->shading.mode = LS_SHADE_SH;
    c->shading.sh = sh;
    c->optim.lr = (ls_real)0.05;
}

/* Targets: an ellipsoid of scale 1 rendered from cameras(1) at S = 2. */
static ls_real *targets[NV];
static ls_real mvp1[16 * NV];
static const ls_real target_axes[3] = {(ls_real)1.0, (ls_real)0.65, (ls_real)0.8};

static void make_targets(void)
{
    ls_arena arena;
    ls_mesh m;
    uint32_t v;
    sh_light();
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ellipsoid(2, 1, target_axes, &arena, &m) == LS_OK);
    cameras(1, NV, mvp1);
    for (v = 0; v < NV; v++) {
        targets[v] = (ls_real *)malloc(4u * RES * RES * sizeof(ls_real));
        REQUIRE(targets[v] != NULL);
        REQUIRE(render_view(&m, mvp1 + 16 * v, RES, 2, targets[v], NULL, NULL, &arena) == LS_OK);
    }
}

static const ls_real unit_axes[3] = {1, 1, 1};

/* Mesh scales 1e-6 and 1e6: render, gradients, the parameterization's
 * solve and a short fit are finite and agree with scale 1 (coverage exactly,
 * gradients x s and the fit / s to a relative tolerance: 1e-6 and 1e6 are
 * not powers of two, so bits may differ). */
static void extreme_mesh_scales(void)
{
    static const double scales[2] = {1e-6, 1e6};
    ls_arena arena;
    ls_mesh m1, ms;
    ls_real mvp[16 * NV], img1[4 * RES * RES], imgs[4 * RES * RES], *g1, *gs, *f1 = NULL, *fs = NULL;
    ls_fit_config c;
    ls_fit_views views;
    ls_diag d;
    uint32_t n1 = 0, ns = 0, i, si;
    view_out o1, os;
    const double tol = LS_REAL_IS_FLOAT ? 2e-3 : 1e-6;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ellipsoid(2, (ls_real)0.6, unit_axes, &arena, &m1) == LS_OK);
    g1 = (ls_real *)ls_arena_alloc(&arena, 3u * m1.vertex_count, sizeof(ls_real));
    gs = (ls_real *)ls_arena_alloc(&arena, 3u * m1.vertex_count, sizeof(ls_real));
    REQUIRE(gs != NULL);
    REQUIRE(render_view(&m1, mvp1, RES, 1, img1, g1, &o1, &arena) == LS_OK);
    fit_config(&c);
    views.count = NV;
    views.targets = (const ls_real *const *)targets;
    views.mvp = mvp1;
    REQUIRE(ls_fit_init != NULL);
    CHECK_STATUS(run_fit(&c, &views, &m1, 5, 99, &arena, &f1, &n1, &d), LS_OK);
    REQUIRE(f1 != NULL);
    for (si = 0; si < 2; si++) {
        const ls_real s = (ls_real)scales[si];
        double gmax = 0.0, gerr = 0.0, ferr = 0.0, rt = 0.0;
        ls_param_config pc;
        ls_param p;
        ls_csc lap;
        ls_real *u, *x;
        ls_arena_mark mark = ls_arena_save(&arena);
        REQUIRE(ellipsoid(2, (ls_real)0.6 * s, unit_axes, &arena, &ms) == LS_OK);
        cameras(s, NV, mvp);
        REQUIRE(render_view(&ms, mvp, RES, 1, imgs, gs, &os, &arena) == LS_OK);
        CHECK(all_finite(imgs, 4u * RES * RES));
        CHECK(all_finite(gs, 3u * ms.vertex_count));
        CHECK_EQ(os.covered, o1.covered);
        for (i = 0; i < 3u * ms.vertex_count; i++) {
            double a = (double)g1[i], b = (double)gs[i] * scales[si];
            if (fabs(a) > gmax) gmax = fabs(a);
            if (fabs(a - b) > gerr) gerr = fabs(a - b);
        }
        CHECK(gmax > 0.0);
        CHECK_MSG(gerr <= 1e-3 * gmax, "scale %g: gradient x s differs by %.3g (max %.3g)", scales[si], gerr, gmax);
        /* the parameterization: u = M x and back */
        REQUIRE(ls_laplacian_uniform(&ms, LS_LAP_UPPER, &arena, &lap, NULL) == LS_OK);
        memset(&pc, 0, sizeof pc);
        pc.solver = LS_PARAM_LDLT;
        pc.form = LS_SYSTEM_LAMBDA;
        pc.weight = 19;
        pc.k = 3;
        pc.order = LS_ORDER_AMD;
        REQUIRE(ls_param_init(&p, &lap, &pc, ms.positions, &arena, NULL) == LS_OK);
        u = (ls_real *)ls_arena_alloc(&arena, 3u * ms.vertex_count, sizeof(ls_real));
        x = (ls_real *)ls_arena_alloc(&arena, 3u * ms.vertex_count, sizeof(ls_real));
        REQUIRE(x != NULL);
        CHECK_STATUS(ls_param_to_differential(&p, ms.positions, u), LS_OK);
        CHECK_STATUS(ls_param_from_differential(&p, u, x), LS_OK);
        for (i = 0; i < 3u * ms.vertex_count; i++)
            if (fabs((double)x[i] - (double)ms.positions[i]) > rt) rt = fabs((double)x[i] - (double)ms.positions[i]);
        CHECK_MSG(rt <= 1e3 * TEST_EPS(1) * 0.6 * scales[si], "scale %g: round trip error %.3g", scales[si], rt);
        /* a short fit, lr in units of the mesh's radius */
        views.mvp = mvp;
        CHECK_STATUS(run_fit(&c, &views, &ms, 5, 99, &arena, &fs, &ns, &d), LS_OK);
        REQUIRE(fs != NULL);
        CHECK_EQ(ns, n1);
        CHECK(all_finite(fs, 3u * ns));
        for (i = 0; i < 3u * ns; i++) {
            double e = fabs((double)fs[i] / scales[si] - (double)f1[i]);
            if (e > ferr) ferr = e;
        }
        printf("     scale %g: %u covered pixels, gradient x s error %.2g (max %.2g), solve round trip %.2g, "
               "5-step fit / s differs by %.2g\n",
               scales[si], (unsigned)os.covered, gerr, gmax, rt, ferr);
        CHECK(ferr <= tol * 0.6);
        free(fs);
        fs = NULL;
        ls_arena_restore(&arena, mark);
    }
    free(f1);
}

/* lambda = 0, 1e-8, 1e8 and alpha = 0.999999 through a fit with a remesh
 * (the parameterization alone is in tests/test_param.c): 0, 1e-8 and 1e8
 * fit (float: 1e8 is refused, LS_ERR_NOT_SPD at init: the identity term
 * rounds away, param.h, with the arena unchanged); alpha = 0.999999 gives a
 * finite result that has run away (fit.h), in both precisions. */
static void extreme_lambda_fit(void)
{
    static const struct {
        uint32_t form;
        double w;
        int float_ok;
    } cases[4] = {{LS_SYSTEM_LAMBDA, 0.0, 1}, {LS_SYSTEM_LAMBDA, 1e-8, 1}, {LS_SYSTEM_LAMBDA, 1e8, 0},
                  {LS_SYSTEM_ALPHA, 0.999999, 1}};
    ls_arena arena;
    ls_mesh m;
    ls_fit_config c;
    ls_fit_views views;
    ls_diag d;
    ls_real *out = NULL;
    uint32_t i, n = 0;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ellipsoid(2, (ls_real)0.6, unit_axes, &arena, &m) == LS_OK);
    views.count = NV;
    views.mvp = mvp1;
    views.targets = (const ls_real *const *)targets;
    for (i = 0; i < 4; i++) {
        const int ok = !LS_REAL_IS_FLOAT || cases[i].float_ok;
        size_t used = ls_arena_used(&arena);
        ls_status st;
        fit_config(&c);
        c.form = cases[i].form;
        c.weight = (ls_real)cases[i].w;
        st = run_fit(&c, &views, &m, 4, 2, &arena, &out, &n, &d);
        printf("     %s %g: %s%s%s\n", c.form == LS_SYSTEM_ALPHA ? "alpha" : "lambda", cases[i].w, ls_status_name(st),
               st != LS_OK ? " - " : "", st != LS_OK ? d.what != NULL ? d.what : "" : "");
        CHECK_STATUS(st, ok ? LS_OK : LS_ERR_NOT_SPD);
        if (ok) {
            REQUIRE(out != NULL);
            CHECK(all_finite(out, 3u * n));
            printf("     max |vertex| %.3g\n", max_abs(out, 3u * n));
            /* the alpha form's M = (1 - alpha) I + alpha L moves the mean of x
             * by lr / (1 - alpha) per unit step of u: finite, but far off */
            if (c.form == LS_SYSTEM_LAMBDA) CHECK(max_abs(out, 3u * n) < 2.0);
        } else {
            CHECK_EQ(ls_arena_used(&arena), used);
        }
        free(out);
        out = NULL;
        ls_arena_init(&arena, buf, BUF_BYTES);
        REQUIRE(ellipsoid(2, (ls_real)0.6, unit_axes, &arena, &m) == LS_OK);
    }
}

/* A camera at the centre of a closed mesh, looking out: every pixel sees
 * the inside (no culling), the render and the gradients are finite, and a
 * short fit seen from inside runs and stays finite. */
static void extreme_camera_inside(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_real proj[16], view[16], mvp[16], img[4 * RES * RES], *g, *out = NULL, *tg[1];
    const ls_real eye[3] = {0, 0, 0}, at[3] = {0, 0, -1}, up[3] = {0, 1, 0};
    ls_fit_config c;
    ls_fit_views views;
    ls_diag d;
    view_out vo;
    uint32_t n = 0;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ellipsoid(2, (ls_real)0.6, unit_axes, &arena, &m) == LS_OK);
    REQUIRE(ls_camera_look_at(eye, at, up, view) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)1.2, LS_FOV_X, 1, (ls_real)0.01, 10, proj) == LS_OK);
    ls_mat4_mul(proj, view, mvp);
    g = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
    REQUIRE(g != NULL);
    REQUIRE(render_view(&m, mvp, RES, 1, img, g, &vo, &arena) == LS_OK);
    printf("     camera inside: %u of %u pixels covered, %u triangles clipped, |grad| max %.3g\n", (unsigned)vo.covered,
           RES * RES, (unsigned)vo.clipped, max_abs(g, 3u * m.vertex_count));
    CHECK_EQ(vo.covered, RES * RES);
    CHECK(vo.clipped > 0);
    CHECK(all_finite(img, 4u * RES * RES));
    CHECK(all_finite(g, 3u * m.vertex_count));
    CHECK(max_abs(g, 3u * m.vertex_count) > 0.0);
    /* a fit from inside towards a render of the slightly larger sphere */
    tg[0] = (ls_real *)malloc(sizeof img);
    REQUIRE(tg[0] != NULL);
    {
        ls_arena_mark mk = ls_arena_save(&arena);
        ls_mesh big;
        REQUIRE(ellipsoid(2, (ls_real)0.7, target_axes, &arena, &big) == LS_OK);
        REQUIRE(render_view(&big, mvp, RES, 1, tg[0], NULL, NULL, &arena) == LS_OK);
        ls_arena_restore(&arena, mk);
    }
    fit_config(&c);
    views.count = 1;
    views.mvp = mvp;
    views.targets = (const ls_real *const *)tg;
    CHECK_STATUS(run_fit(&c, &views, &m, 5, 99, &arena, &out, &n, &d), LS_OK);
    CHECK(out != NULL && all_finite(out, 3u * n));
    free(out);
    free(tg[0]);
}

/* Every vertex behind the camera: nothing is drawn (the background, alpha
 * 0), every gradient is exactly zero, and a fit step is a no-op on the
 * vertices (zero gradients: UniformAdam's m1 stays 0). */
static void extreme_behind_camera(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_real img[4 * RES * RES], *g, *out = NULL;
    ls_fit_config c;
    ls_fit_views views;
    ls_diag d;
    view_out vo;
    uint32_t i, n = 0;
    ls_real dirs[3 * NV];
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ellipsoid(2, (ls_real)0.6, unit_axes, &arena, &m) == LS_OK);
    REQUIRE(ls_camera_fibonacci_dirs(NV, dirs) == LS_OK);
    /* view 0's eye is at 3.2 dir: put the sphere at 6.4 dir, behind it */
    for (i = 0; i < m.vertex_count; i++) {
        uint32_t k;
        for (k = 0; k < 3; k++) m.positions[3 * i + k] += (ls_real)6.4 * dirs[k];
    }
    g = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
    REQUIRE(g != NULL);
    REQUIRE(render_view(&m, mvp1, RES, 1, img, g, &vo, &arena) == LS_OK);
    CHECK_EQ(vo.covered, 0);
    CHECK(all_finite(img, 4u * RES * RES));
    CHECK(max_abs(img, 4u * RES * RES) == 0.0); /* black background, alpha 0 */
    CHECK(max_abs(g, 3u * m.vertex_count) == 0.0);
    fit_config(&c);
    c.use_translation = 0;
    views.count = 1;
    views.mvp = mvp1;
    views.targets = (const ls_real *const *)targets;
    CHECK_STATUS(run_fit(&c, &views, &m, 3, 99, &arena, &out, &n, &d), LS_OK);
    REQUIRE(out != NULL);
    /* x = M^-1 M x: the round trip's rounding only */
    for (i = 0; i < 3u * n; i++) CHECK_NEAR(out[i], m.positions[i], 1e3 * TEST_EPS(8));
    free(out);
}

/* A mesh collapsed to a point (at (0.3, -0.2, 0.1), then at the origin):
 * zero-area faces draw nothing and get no gradient; the fit's frame falls
 * back to unit scale; a fit runs and stays finite and bounded (the solve's
 * rounding opens the point by ~1e-17, whose silhouettes then pull it
 * towards the target). */
static void extreme_collapsed_mesh(void)
{
    static const ls_real where[2][3] = {{(ls_real)0.3, (ls_real)-0.2, (ls_real)0.1}, {0, 0, 0}};
    ls_arena arena;
    ls_mesh m;
    ls_real img[4 * RES * RES], *g, *out = NULL;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_diag d;
    view_out vo;
    uint32_t i, w, n = 0;
    for (w = 0; w < 2; w++) {
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(ls_icosphere(2, &arena, &m) == LS_OK);
        for (i = 0; i < 3u * m.vertex_count; i++) m.positions[i] = where[w][i % 3u];
        g = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
        REQUIRE(g != NULL);
        REQUIRE(render_view(&m, mvp1, RES, 1, img, g, &vo, &arena) == LS_OK);
        CHECK_EQ(vo.covered, 0);
        CHECK(all_finite(img, 4u * RES * RES));
        CHECK(max_abs(g, 3u * m.vertex_count) == 0.0);
        fit_config(&c);
        views.count = NV;
        views.mvp = mvp1;
        views.targets = (const ls_real *const *)targets;
        REQUIRE(ls_fit_init(&fit, &c, &views, &m, &arena, &d) == LS_OK);
        CHECK(fit.scale == 1 && fit.radius == 1);
        CHECK_STATUS(run_fit(&c, &views, &m, 3, 99, &arena, &out, &n, &d), LS_OK);
        REQUIRE(out != NULL);
        CHECK(all_finite(out, 3u * n));
        CHECK(max_abs(out, 3u * n) < 2.0);
        free(out);
        out = NULL;
    }
}

/* A single triangle, seen face on by an orthographic camera: its coverage
 * (S = 4) is its area in pixels to the sampling's resolution; the
 * silhouette gradient of L = sum(alpha) is d(area)/d(vertex) (the edge
 * opposite a vertex, rotated: |e| / 2 along its outward normal); a short
 * fit of the triangle is finite. */
static void extreme_single_triangle(void)
{
    ls_real pos[9] = {(ls_real)-0.5, (ls_real)-0.4, -1, (ls_real)0.55, (ls_real)-0.3, -1, (ls_real)-0.1, (ls_real)0.6, -1};
    uint32_t tri[3] = {0, 1, 2};
    ls_arena arena;
    ls_mesh m;
    ls_real proj[16], img[4 * 32 * 32], gimg[4 * 32 * 32], grad[9], gwant[9], *out = NULL, *tg[1];
    ls_shade_opts o;
    ls_vis vis;
    ls_edge_table table;
    ls_fit_config c;
    ls_fit_views views;
    ls_diag d;
    double cover = 0.0, area, px = 32.0 / 2.0; /* pixels per unit */
    uint32_t i, n = 0;
    m.positions = pos;
    m.triangles = tri;
    m.vertex_count = 3;
    m.face_count = 1;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_camera_orthographic(-1, 1, -1, 1, (ls_real)0.1, 10, proj) == LS_OK);
    ls_shade_opts_init(&o); /* mask */
    REQUIRE(ls_vis_init(&vis, &arena, 32, 32, 4, 3) == LS_OK);
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = tri, .triangle_count = 1, .vertex_count = 3,
            .mvp = proj}, &arena, NULL) == LS_OK);
    REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = tri, .triangle_count = 1, .vertex_count = 3, .opts = &o}, img,
            NULL) == LS_OK);
    for (i = 0; i < 32u * 32u; i++) cover += (double)img[4 * i + 3];
    area = 0.5 * fabs(((double)pos[3] - (double)pos[0]) * ((double)pos[7] - (double)pos[1]) -
                      ((double)pos[6] - (double)pos[0]) * ((double)pos[4] - (double)pos[1])) * px * px;
    printf("     single triangle: coverage %.4f px, area %.4f px\n", cover, area);
    CHECK_NEAR(cover, area, 0.02 * area);
    /* d sum(alpha) / d p_i: area gradient, orthographic so dx_pixel = px dx */
    for (i = 0; i < 4u * 32u * 32u; i++) gimg[i] = (ls_real)((i & 3u) == 3u);
    memset(grad, 0, sizeof grad);
    REQUIRE(ls_edge_table_build(&table, tri, 1, 3, &arena, NULL) == LS_OK);
    REQUIRE(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = tri, .triangle_count = 1, .vertex_count = 3,
            .opts = &o, .mvp = proj, .table = &table, .boost = 1}, gimg, grad, &arena, NULL) == LS_OK);
    for (i = 0; i < 3; i++) {
        const ls_real *a = pos + 3 * ((i + 1) % 3), *b = pos + 3 * ((i + 2) % 3);
        /* counter-clockwise: d area / d p_i = (a_y - b_y, b_x - a_x) / 2 */
        gwant[3 * i + 0] = (ls_real)(0.5 * ((double)a[1] - (double)b[1]) * px * px);
        gwant[3 * i + 1] = (ls_real)(0.5 * ((double)b[0] - (double)a[0]) * px * px);
        gwant[3 * i + 2] = 0;
    }
    for (i = 0; i < 9; i++) {
        CHECK(isfinite((double)grad[i]));
        if (i % 3 != 2) CHECK_NEAR(grad[i], gwant[i], 0.05 * max_abs(gwant, 9));
    }
    /* a short fit of the lone triangle towards a render of a larger one */
    tg[0] = (ls_real *)malloc(4u * RES * RES * sizeof(ls_real));
    REQUIRE(tg[0] != NULL);
    {
        ls_real big[9];
        ls_mesh mb = m;
        ls_vis v2;
        ls_arena_mark mk = ls_arena_save(&arena);
        for (i = 0; i < 9; i++) big[i] = i % 3 == 2 ? pos[i] : (ls_real)1.2 * pos[i];
        mb.positions = big;
        REQUIRE(ls_vis_init(&v2, &arena, RES, RES, 1, 3) == LS_OK);
        REQUIRE(ls_raster(&v2, &(ls_view){.positions = big, .indices = tri, .triangle_count = 1, .vertex_count = 3,
                .mvp = proj}, &arena, NULL) == LS_OK);
        REQUIRE(ls_shade(&(ls_view){.vis = &v2, .indices = tri, .triangle_count = 1, .vertex_count = 3, .opts = &o},
                tg[0], NULL) == LS_OK);
        ls_arena_restore(&arena, mk);
        (void)mb;
    }
    fit_config(&c);
    c.shading = o;
    views.count = 1;
    views.mvp = proj;
    views.targets = (const ls_real *const *)tg;
    CHECK_STATUS(run_fit(&c, &views, &m, 5, 99, &arena, &out, &n, &d), LS_OK);
    REQUIRE(out != NULL);
    CHECK_EQ(n, 3);
    CHECK(all_finite(out, 9));
    free(out);
    free(tg[0]);
}

/* A gx x gy grid of 2 gx gy triangles mapped into [0.02, 0.2]^2 at z = -1:
 * inside pixel (4, 3) of an orthographic [-1, 1]^2 view at 8 x 8 (0.25
 * units per pixel). */
static void grid_in_a_pixel(uint32_t gx, uint32_t gy, ls_arena *arena, ls_mesh *m)
{
    size_t i;
    REQUIRE(ls_grid_mesh(gx, gy, arena, m) == LS_OK);
    for (i = 0; i < m->vertex_count; i++) {
        m->positions[3 * i] = (ls_real)0.02 + (ls_real)0.18 * m->positions[3 * i];
        m->positions[3 * i + 1] = (ls_real)0.02 + (ls_real)0.18 * m->positions[3 * i + 1];
        m->positions[3 * i + 2] = -1;
    }
}

/* 10^6 triangles (a 708 x 707 grid) inside one pixel of an 8 x 8 view:
 * the raster's scratch from its exact sizing query (8 bytes less:
 * LS_ERR_NOMEM), exactly one covered pixel, finite shading gradients (zero
 * inside), bounded time; the silhouette pass's scratch query at 10^6, and
 * the pass itself on 10^4 triangles in the pixel (its cost grows as the
 * silhouette pieces times the candidates of their tile: ~130 s at 10^6,
 * left to the silhouette's speed work). */
static void extreme_million_triangles_in_a_pixel(void)
{
    const uint32_t res = 8;
    const char *emu = getenv("LS_TEST_EMULATED");
    const int emulated = emu != NULL && strcmp(emu, "1") == 0;
    ls_arena arena, sa;
    ls_mesh m;
    ls_real proj[16], img[4 * 8 * 8], gimg[4 * 8 * 8], *grad;
    ls_shade_opts o;
    ls_vis vis;
    ls_edge_table table;
    size_t raster_bytes, sil_bytes, sil_bound, mesh_bytes, vis_bytes, table_bytes, total, i;
    unsigned char *s1, *mem;
    uint32_t covered = 0, pass;
    clock_t t0;
    double secs[2];
    REQUIRE(ls_camera_orthographic(-1, 1, -1, 1, (ls_real)0.1, 10, proj) == LS_OK);
    ls_shade_opts_init(&o);
    for (i = 0; i < 4u * res * res; i++) gimg[i] = (ls_real)((i & 3u) == 3u);
    for (pass = 0; pass < 2; pass++) {
        /* under emulation (tests/tools/cross_skip.txt) 10^5 triangles */
        const uint32_t gx = pass == 0 ? emulated ? 224 : 708 : 71, gy = pass == 0 ? emulated ? 224 : 707 : 71;
        /* the mesh, the buffers and the edge table from their sizing queries */
        REQUIRE(ls_grid_mesh_bytes(gx, gy, &mesh_bytes) == LS_OK);
        REQUIRE(ls_vis_bytes(res, res, 1, (gx + 1u) * (gy + 1u), &vis_bytes) == LS_OK);
        REQUIRE(ls_edge_table_bytes(2u * gx * gy, &table_bytes) == LS_OK);
        total = LS_ARENA_ROUND(mesh_bytes) + LS_ARENA_ROUND(vis_bytes) + LS_ARENA_ROUND(table_bytes);
        mem = (unsigned char *)malloc(total);
        REQUIRE(mem != NULL);
        REQUIRE(ls_arena_init(&arena, mem, total) == LS_OK);
        grid_in_a_pixel(gx, gy, &arena, &m);
        CHECK(pass == 1 || emulated || m.face_count >= 1000000u);
        REQUIRE(ls_vis_init(&vis, &arena, res, res, 1, m.vertex_count) == LS_OK);
        REQUIRE(ls_edge_table_build(&table, m.triangles, m.face_count, m.vertex_count, &arena, NULL) == LS_OK);
        grad = (ls_real *)calloc(3u * (size_t)m.vertex_count, sizeof(ls_real));
        REQUIRE(grad != NULL);
        t0 = clock();
        REQUIRE(ls_raster_scratch_bytes(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = proj}, &raster_bytes) == LS_OK);
        s1 = (unsigned char *)malloc(raster_bytes);
        REQUIRE(s1 != NULL);
        REQUIRE(ls_arena_init(&sa, s1, raster_bytes - 8u) == LS_OK);
        CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = proj}, &sa, NULL),
                     LS_ERR_NOMEM);
        REQUIRE(ls_arena_init(&sa, s1, raster_bytes) == LS_OK);
        CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = proj}, &sa, NULL), LS_OK);
        CHECK_EQ(vis.scratch_bytes, raster_bytes);
        free(s1);
        REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                .vertex_count = m.vertex_count, .opts = &o}, img, NULL) == LS_OK);
        for (i = 0, covered = 0; i < res * res; i++) covered += img[4 * i + 3] > 0;
        CHECK_EQ(covered, 1);
        CHECK(img[4 * (3 * res + 4) + 3] == 1);
        CHECK_STATUS(ls_shade_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                .vertex_count = m.vertex_count, .opts = &o, .mvp = proj}, gimg, grad, NULL, NULL, NULL),
                     LS_OK);
        CHECK(all_finite(grad, 3u * (size_t)m.vertex_count));
        REQUIRE(ls_silhouette_scratch_bytes(&(ls_view){.vis = &vis, .indices = m.triangles,
                .triangle_count = m.face_count, .table = &table}, &sil_bytes) == LS_OK);
        REQUIRE(ls_silhouette_scratch_bytes_bound(res, res, m.vertex_count, m.face_count, &sil_bound) == LS_OK);
        CHECK(sil_bytes <= sil_bound);
        if (pass == 1) { /* the silhouettes in the exact scratch */
            s1 = (unsigned char *)malloc(sil_bytes);
            REQUIRE(s1 != NULL);
            REQUIRE(ls_arena_init(&sa, s1, sil_bytes) == LS_OK);
            CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = m.triangles,
                    .triangle_count = m.face_count, .vertex_count = m.vertex_count, .opts = &o, .mvp = proj,
                    .table = &table, .boost = 1}, gimg, grad, &sa, NULL),
                         LS_OK);
            free(s1);
            CHECK(all_finite(grad, 3u * (size_t)m.vertex_count));
            CHECK(max_abs(grad, 3u * (size_t)m.vertex_count) > 0.0);
        }
        secs[pass] = (double)(clock() - t0) / CLOCKS_PER_SEC;
        printf("     %u triangles in one pixel: mesh + buffers %lu bytes, raster scratch %lu bytes, silhouette scratch "
               "%lu bytes, %s, |grad| max %.3g, %.2f s\n",
               (unsigned)m.face_count, (unsigned long)total, (unsigned long)raster_bytes, (unsigned long)sil_bytes,
               pass == 0 ? "raster + shade + shading backward" : "raster + shade + both backwards",
               max_abs(grad, 3u * (size_t)m.vertex_count), secs[pass]);
        free(grad);
        free(mem);
    }
    if (!emulated) {
        CHECK(secs[0] < 5.0);
        CHECK(secs[1] < 2.0);
    }
}

/* The parts of a fit a failed step must leave as they were. */
static uint64_t fit_state_hash(const ls_fit *f)
{
    const uint32_t n = f->vertex_count;
    uint64_t h = TEST_HASH_SEED;
    h = test_hash_reals(f->x, 3u * n, h);
    h = test_hash_reals(f->u, 3u * n, h);
    h = test_hash_reals(f->params, 3u * n + 3u, h);
    h = test_hash_reals(f->optim.m1, f->optim.count, h);
    h = test_hash_reals(f->optim.m2, f->optim.count, h);
    h = test_hash_reals(f->optim.last_scale, LS_OPTIM_MAX_BLOCKS, h);
    h = test_hash(&f->optim.step, sizeof f->optim.step, h);
    h = test_hash(&f->iteration, sizeof f->iteration, h);
    h = test_hash(&f->loss, sizeof f->loss, h);
    h = test_hash(&f->reg_loss, sizeof f->reg_loss, h);
    h = test_hash(&f->timing, sizeof f->timing, h);
    h = test_hash(&f->config, sizeof f->config, h);
    if (f->config.solver == LS_PARAM_CG) {
        h = test_hash_reals(f->param.warm_fwd, 3u * n, h);
        h = test_hash_reals(f->param.warm_adj, 3u * n, h);
        h = test_hash(&f->param.cg, sizeof f->param.cg, h);
    }
    return h;
}

/* NaN or infinity appearing during a fit, at iteration 3: in a target, in a
 * gradient (the silhouette boost made huge), in a parameter (an SGD step
 * overflowing): LS_ERR_NONFINITE naming iteration 3, the fit's state and its
 * mesh byte for byte as before the step, and the fit goes on once the cause
 * is removed. LDL^T and CG. */
static void extreme_nonfinite_during_fit(void)
{
    ls_arena arena;
    ls_mesh m, before_mesh, after_mesh;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_diag d;
    ls_real *tg[NV], *pb, *pa;
    uint32_t v, kind, solver;
    for (v = 0; v < NV; v++) {
        tg[v] = (ls_real *)malloc(4u * RES * RES * sizeof(ls_real));
        REQUIRE(tg[v] != NULL);
    }
    for (solver = 0; solver < 2; solver++)
        for (kind = 0; kind < 4; kind++) {
            static const char *const names[4] = {"NaN in a target", "inf in a target", "inf in a gradient",
                                                 "overflowing parameter"};
            uint64_t h;
            uint32_t it;
            ls_real saved = 0;
            REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
            REQUIRE(ellipsoid(2, (ls_real)0.6, unit_axes, &arena, &m) == LS_OK);
            for (v = 0; v < NV; v++) memcpy(tg[v], targets[v], 4u * RES * RES * sizeof(ls_real));
            fit_config(&c);
            c.solver = solver ? LS_PARAM_CG : LS_PARAM_LDLT;
            if (kind == 2) c.loss = LS_LOSS_L2;
            if (kind == 3) {
                (void)ls_optim_config_default(LS_OPTIM_SGD, &c.optim);
                c.optim.beta1 = 0;
                c.optim.lr = (ls_real)1e-3;
            }
            views.count = NV;
            views.mvp = mvp1;
            views.targets = (const ls_real *const *)tg;
            REQUIRE(ls_fit_init(&fit, &c, &views, &m, &arena, &d) == LS_OK);
            for (it = 0; it < 3; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
            pb = (ls_real *)malloc(3u * fit.vertex_count * sizeof(ls_real));
            pa = (ls_real *)malloc(3u * fit.vertex_count * sizeof(ls_real));
            REQUIRE(pb != NULL && pa != NULL);
            REQUIRE(ls_fit_mesh(&fit, pb, &before_mesh) == LS_OK);
            h = fit_state_hash(&fit);
            if (kind == 0) saved = tg[1][4 * (RES * 7 + 5) + 2], tg[1][4 * (RES * 7 + 5) + 2] = (ls_real)NAN;
            if (kind == 1) saved = tg[2][4 * (RES * 9 + 8)], tg[2][4 * (RES * 9 + 8)] = (ls_real)INFINITY;
            if (kind == 2) { /* finite inputs whose gradient overflows: huge targets under L2, a large boost */
                for (v = 0; v < 4u * RES * RES; v++) tg[0][v] = LS_REAL_MAX / 2;
                fit.config.boost = (ls_real)1e6;
            }
            if (kind == 3) { /* large silhouette gradients, a huge SGD step */
                saved = fit.optim.config.lr;
                fit.optim.config.lr = LS_REAL_MAX;
                fit.config.boost = (ls_real)1e6;
            }
            ls_diag_clear(&d);
            CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_ERR_NONFINITE);
            printf("     %s, %s: %s at iteration %llu: %s\n", solver ? "cg  " : "ldlt", names[kind],
                   ls_status_name(d.status), (unsigned long long)d.index, d.what != NULL ? d.what : "(null)");
            CHECK(d.has_index && d.index == 3);
            CHECK(d.what != NULL);
            if (kind == 2) CHECK(d.what != NULL && strstr(d.what, "gradient") != NULL);
            CHECK_EQ(fit.iteration, 3);
            if (kind == 3) fit.optim.config.lr = saved;
            fit.config.boost = c.boost; /* the hash covers the config */
            CHECK(fit_state_hash(&fit) == h);
            REQUIRE(ls_fit_mesh(&fit, pa, &after_mesh) == LS_OK);
            CHECK(memcmp(pa, pb, 3u * fit.vertex_count * sizeof(ls_real)) == 0);
            /* the cause removed, the fit goes on */
            if (kind == 0) tg[1][4 * (RES * 7 + 5) + 2] = saved;
            if (kind == 1) tg[2][4 * (RES * 9 + 8)] = saved;
            if (kind == 2) memcpy(tg[0], targets[0], 4u * RES * RES * sizeof(ls_real));
            CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_OK);
            CHECK_EQ(fit.iteration, 4);
            free(pb);
            free(pa);
        }
    for (v = 0; v < NV; v++) free(tg[v]);
}

/* Scale invariance (fit.h): the scene (initial mesh, cameras with their
 * near and far planes) scaled by 2^k, targets and configuration unchanged:
 * a fit of 3 steps, a remesh and 2 more steps gives exactly 2^k times the
 * k = 0 vertices, for every k in -20 ... 20 (under emulation k in -20, -7,
 * 3, 20). */
static void extreme_scale_invariance(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_fit_config c;
    ls_fit_views views;
    ls_diag d;
    ls_real mvp[16 * NV], *ref = NULL, *out = NULL;
    uint32_t nref = 0, n = 0, i;
    int k, bad = 0, first_bad = 99, runs = 0;
    const char *emu = getenv("LS_TEST_EMULATED");
    const int emulated = emu != NULL && strcmp(emu, "1") == 0;
    fit_config(&c);
    views.count = NV;
    views.mvp = mvp;
    views.targets = (const ls_real *const *)targets;
    for (k = 0; k >= -20; k = k == 20 ? -1 : k >= 0 ? k + 1 : k - 1) {
        ls_real s = 1;
        int j;
        if (emulated && k != 0 && k != -20 && k != -7 && k != 3 && k != 20) continue;
        for (j = 0; j < (k < 0 ? -k : k); j++) s *= k < 0 ? (ls_real)0.5 : (ls_real)2;
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(ellipsoid(1, (ls_real)0.6 * s, unit_axes, &arena, &m) == LS_OK);
        cameras(s, NV, mvp);
        /* the cameras scale exactly: the translation column by s */
        for (j = 0; j < (int)(16 * NV); j++) CHECK(mvp[j] == ((j & 3) == 3 ? s * mvp1[j] : mvp1[j]));
        CHECK_STATUS(run_fit(&c, &views, &m, 5, 3, &arena, &out, &n, &d), LS_OK);
        REQUIRE(out != NULL);
        if (k == 0) {
            ref = out;
            nref = n;
            CHECK(n > m.vertex_count); /* the remesh refined */
            CHECK(all_finite(ref, 3u * n));
            out = NULL;
            continue;
        }
        runs++;
        if (n != nref) {
            bad++;
        } else {
            for (i = 0; i < 3u * n; i++) out[i] /= s;
            if (memcmp(out, ref, 3u * n * sizeof(ls_real)) != 0) bad++, first_bad = k < first_bad ? k : first_bad;
        }
        free(out);
        out = NULL;
    }
    printf("     k = -20 .. 20: %d of %d scaled fits differ from 2^k x the k = 0 fit (%u vertices after the remesh)\n", bad,
           runs, (unsigned)nref);
    CHECK_EQ(runs, emulated ? 4 : 40);
    CHECK_MSG(bad == 0, "first differing k: %d", first_bad);
    free(ref);
}

int main(void)
{
    uint32_t v;
    TEST_INIT("test_extreme");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(make_targets);
    TEST_RUN(extreme_mesh_scales);
    TEST_RUN(extreme_lambda_fit);
    TEST_RUN(extreme_camera_inside);
    TEST_RUN(extreme_behind_camera);
    TEST_RUN(extreme_collapsed_mesh);
    TEST_RUN(extreme_single_triangle);
    TEST_RUN(extreme_million_triangles_in_a_pixel);
    TEST_RUN(extreme_nonfinite_during_fit);
    TEST_RUN(extreme_scale_invariance);
    for (v = 0; v < NV; v++) free(targets[v]);
    free(buf);
    return TEST_END();
}
