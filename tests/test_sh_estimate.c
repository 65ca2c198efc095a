/* test_sh_estimate.c - SH lighting and albedo estimated from images
 * (shade.h: ls_sh_basis, ls_sh_accumulate, ls_sh_solve, ls_albedo_accumulate,
 * ls_albedo_solve) and the fit that estimates them (fit.h:
 * LS_FIT_LIGHT_ESTIMATE, LS_FIT_ALBEDO_VERTEX, config.grad_limit). A mesh
 * rendered by ls_shade with known coefficients (and known vertex colours)
 * gives them back from its own images; the fit recovers the lighting of its
 * targets and runs the same bits twice; a per-vertex albedo fits painted
 * targets better than a uniform one; a limited gradient stays within its
 * bound; the errors. */
#include "test.h"
#include <stdlib.h>
#include "fit_targets.h"
#include "geo_test.h"

#define BUF_BYTES (32u << 20)
#define EST_VIEWS 6u
#define EST_RES 48u

static unsigned char *buf;

/* 27 distinct coefficients: a bright constant term and every other term in
 * turn, different per channel. */
static void known_sh(ls_real sh[27])
{
    uint32_t c, k;
    for (c = 0; c < 3; c++) {
        sh[9 * c] = (ls_real)(1.6 - 0.2 * c);
        for (k = 1; k < 9; k++) sh[9 * c + k] = (ls_real)(0.37 * sin(1.3 * k + 2.1 * c));
    }
}

static void basis_matches_sh_eval(void)
{
    ls_real sh[27], n[3], b[9], rgb[3];
    double max_err = 0;
    int trial, c, k;
    for (trial = 0; trial < 100; trial++) {
        for (k = 0; k < 27; k++) sh[k] = (ls_real)(1.7 * cos(trial * 0.9 + k * 1.1));
        for (k = 0; k < 3; k++) n[k] = (ls_real)(1.2 * sin(trial * 0.61 + k * 2.3));
        ls_shade_sh_eval(sh, n, rgb);
        ls_sh_basis(n, b);
        for (c = 0; c < 3; c++) {
            double e = 0;
            for (k = 0; k < 9; k++) e += (double)sh[9 * c + k] * (double)b[k];
            max_err = fmax(max_err, fabs(e - (double)rgb[c]));
        }
    }
    CHECK_MSG(max_err < TEST_EPS(64), "max error %.3g", max_err);
}

/* An ellipsoid (level 3, y x 0.7) from EST_VIEWS Fibonacci directions, S
 * samples per pixel side, shaded with `sh` (painted: with fit_test_paint's
 * vertex colours, given to the estimate as well); the estimate from those
 * images must give sh back. Half the views' targets get a pixel of garbage
 * colour with alpha 0.5, which the estimate must leave out. painted: the
 * albedo estimated under sh (albedo_err: the largest relative error of a
 * seen vertex's albedo times its channel's pooled ratio against its
 * colour, then the mean; seen: the vertices with samples, the others must keep their
 * value). */
static void estimate_from_renders(uint32_t ss, const ls_real sh[27], int painted, ls_real est[27], uint32_t *pixels,
                                  double *albedo_err, uint32_t *seen)
{
    ls_arena arena;
    ls_mesh m;
    ls_vis vis;
    ls_real dirs[3 * EST_VIEWS], proj[16], view[16], mvp[16], *normals, *img;
    const ls_real center[3] = {0, 0, 0};
    ls_shade_opts o;
    ls_sh_normal ne;
    ls_view vw;
    ls_real *colors = NULL, *num = NULL, *albedo = NULL;
    uint32_t v, i;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_icosphere(3, &arena, &m) == LS_OK);
    for (i = 0; i < m.vertex_count; i++) m.positions[3 * i + 1] *= (ls_real)0.7;
    normals = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
    img = (ls_real *)ls_arena_alloc(&arena, 4u * EST_RES * EST_RES, sizeof(ls_real));
    REQUIRE(img != NULL);
    REQUIRE(ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, normals, NULL) == LS_OK);
    REQUIRE(ls_camera_fibonacci_dirs(EST_VIEWS, dirs) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1, (ls_real)10, proj) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &arena, EST_RES, EST_RES, ss, m.vertex_count) == LS_OK);
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh;
    if (painted) {
        colors = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
        num = (ls_real *)ls_arena_alloc(&arena, 6u * m.vertex_count, sizeof(ls_real));
        albedo = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
        REQUIRE(albedo != NULL);
        for (i = 0; i < 3u * m.vertex_count; i++) {
            colors[i] = fit_test_paint(m.positions + 3u * (i / 3u), i % 3u);
            albedo[i] = (ls_real)7; /* kept where no sample falls */
        }
        memset(num, 0, 6u * m.vertex_count * sizeof(ls_real));
        o.vertex_colors = colors;
    }
    memset(&vw, 0, sizeof vw);
    vw.vis = &vis;
    vw.positions = m.positions;
    vw.indices = m.triangles;
    vw.triangle_count = m.face_count;
    vw.vertex_count = m.vertex_count;
    vw.normals = normals;
    vw.opts = &o;
    ls_sh_normal_clear(&ne);
    for (v = 0; v < EST_VIEWS; v++) {
        REQUIRE(ls_camera_orbit(center, (ls_real)3.2, dirs + 3 * v, view) == LS_OK);
        ls_mat4_mul(proj, view, mvp);
        vw.mvp = mvp;
        REQUIRE(ls_raster(&vis, &vw, &arena, NULL) == LS_OK);
        REQUIRE(ls_shade(&vw, img, NULL) == LS_OK);
        if (v % 2u == 0u) { /* the centre pixel (covered): a partial mask, a wrong colour */
            ls_real *px = img + 4u * (EST_RES / 2u * EST_RES + EST_RES / 2u);
            CHECK(px[3] == (ls_real)1);
            px[0] = px[1] = px[2] = (ls_real)50;
            px[3] = (ls_real)0.5;
        }
        REQUIRE(ls_sh_accumulate(&ne, &vw, img, NULL) == LS_OK);
        if (painted) REQUIRE(ls_albedo_accumulate(&vw, img, num, num + 3u * m.vertex_count, NULL) == LS_OK);
    }
    *pixels = ne.pixels;
    CHECK_EQ(ne.per_channel, (uint32_t)(painted != 0));
    REQUIRE(ls_sh_solve(&ne, est, NULL) == LS_OK);
    if (painted) {
        const ls_real *den = num + 3u * m.vertex_count;
        double sn[3] = {0, 0, 0}, sd[3] = {0, 0, 0}, err = 0, sum = 0;
        uint32_t c, n_seen = 0;
        REQUIRE(ls_albedo_solve(num, den, m.vertex_count, albedo, NULL) == LS_OK);
        for (i = 0; i < 3u * m.vertex_count; i++)
            if (den[i] > 0) sn[i % 3u] += (double)num[i], sd[i % 3u] += (double)den[i];
        for (v = 0; v < m.vertex_count; v++) {
            if (!(den[3u * v] > 0)) {
                CHECK(albedo[3u * v] == (ls_real)7 && albedo[3u * v + 1u] == (ls_real)7);
                continue;
            }
            n_seen++;
            for (c = 0; c < 3; c++) {
                const double e = fabs((double)albedo[3u * v + c] * sn[c] / sd[c] - (double)colors[3u * v + c]) /
                                 (double)colors[3u * v + c];
                err = fmax(err, e);
                sum += e;
            }
        }
        albedo_err[0] = err;
        albedo_err[1] = n_seen > 0 ? sum / (3.0 * n_seen) : 1.0;
        *seen = n_seen;
    }
}

static void estimate_recovers_known_lighting(void)
{
    ls_real sh[27], est[27];
    uint32_t ss, k, pixels;
    known_sh(sh);
    for (ss = 1; ss <= 2; ss++) {
        double max_err = 0;
        estimate_from_renders(ss, sh, 0, est, &pixels, NULL, NULL);
        /* about a third of each 48 x 48 view is the ellipsoid's interior */
        CHECK_MSG(pixels > EST_VIEWS * 400u && pixels < EST_VIEWS * EST_RES * EST_RES / 2u, "pixels %u",
                  (unsigned)pixels);
        for (k = 0; k < 27; k++) max_err = fmax(max_err, fabs((double)est[k] - (double)sh[k]));
        /* the ridge (1e-6 of the mean diagonal) is the error's floor in double */
        CHECK_MSG(max_err < (LS_REAL_IS_FLOAT ? 2e-2 : 1e-4), "S = %u: max coefficient error %.3g", (unsigned)ss,
                  max_err);
    }
    /* a uniform albedo scales the coefficients it is estimated with */
    for (k = 0; k < 27; k++) sh[k] *= (ls_real)0.5;
    estimate_from_renders(1, sh, 0, est, &pixels, NULL, NULL);
    for (k = 0; k < 27; k++) CHECK_NEAR(est[k], sh[k], LS_REAL_IS_FLOAT ? 1e-2 : 1e-4);
}

/* Painted: the lighting with the colours known gives sh back (one matrix
 * per channel), and the albedo under sh gives the colours back, up to the
 * lumped estimate's smoothing over a vertex's ring (a uniform guess is off
 * by up to 58 %). */
static void estimate_with_vertex_albedo(void)
{
    ls_real sh[27], est[27];
    uint32_t k, pixels, seen = 0;
    double max_err = 0, albedo_err[2] = {1, 1};
    known_sh(sh);
    estimate_from_renders(2, sh, 1, est, &pixels, albedo_err, &seen);
    for (k = 0; k < 27; k++) max_err = fmax(max_err, fabs((double)est[k] - (double)sh[k]));
    CHECK_MSG(max_err < (LS_REAL_IS_FLOAT ? 2e-2 : 1e-4), "max coefficient error %.3g", max_err);
    CHECK_MSG(seen > 500u, "%u of 642 vertices seen", (unsigned)seen);
    CHECK_MSG(albedo_err[0] < 0.15 && albedo_err[1] < 0.03, "relative albedo error: largest %.3g, mean %.3g over %u "
              "vertices", albedo_err[0], albedo_err[1], (unsigned)seen);
}

/* A uniform albedo comes back as 1 everywhere, its colour in the pooled
 * ratio; the errors leave the albedo as it was. */
static void albedo_solve_cases(void)
{
    ls_real num[6 * 3], albedo[3 * 3], before[3 * 3];
    ls_diag d;
    uint32_t i;
    for (i = 0; i < 9; i++) { /* den = s^2 w, num = den t: the colour t of channel i mod 3, whatever s and w */
        const ls_real s = (ls_real)(0.5 + 0.25 * i);
        num[9 + i] = s * s * (ls_real)(1 + i);
        num[i] = num[9 + i] * (ls_real)(0.2 + 0.1 * (i % 3u));
        albedo[i] = before[i] = (ls_real)3;
    }
    num[9 + 4] = 0; /* vertex 1, channel 1: no sample */
    CHECK_STATUS(ls_albedo_solve(num, num + 9, 3, albedo, NULL), LS_OK);
    for (i = 0; i < 9; i++) {
        if (i == 4) CHECK(albedo[i] == (ls_real)3); /* kept */
        else CHECK_NEAR(albedo[i], 1, 1e-6);
    }
    for (i = 0; i < 9; i++) num[9 + i] = 0;
    CHECK_STATUS(ls_albedo_solve(num, num + 9, 3, before, &d), LS_ERR_STATE);
    CHECK(d.what != NULL && strstr(d.what, "no sample") != NULL);
    for (i = 0; i < 9; i++) CHECK(before[i] == (ls_real)3);
    CHECK_STATUS(ls_albedo_solve(NULL, num, 3, albedo, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_albedo_solve(num, num + 9, 3, NULL, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_albedo_accumulate(NULL, num, num, num + 9, NULL), LS_ERR_INVALID);
}

static void estimate_errors(void)
{
    ls_sh_normal ne;
    ls_real sh[27], before[27], img[4 * 4 * 4];
    ls_vis vis;
    ls_view vw;
    ls_arena arena;
    ls_diag d;
    uint32_t k;
    for (k = 0; k < 27; k++) sh[k] = before[k] = (ls_real)k;
    ls_sh_normal_clear(&ne);
    CHECK_STATUS(ls_sh_solve(&ne, sh, &d), LS_ERR_STATE); /* no pixel */
    CHECK(d.what != NULL && strstr(d.what, "no pixel") != NULL);
    CHECK(memcmp(sh, before, sizeof sh) == 0);
    CHECK_STATUS(ls_sh_solve(NULL, sh, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_sh_solve(&ne, NULL, NULL), LS_ERR_INVALID);
    /* one pixel seen: a single normal cannot determine 9 coefficients, but the ridge gives the
       least-norm-like answer that reproduces it */
    {
        ls_real n[3] = {0, 0, 1}, b[9], rgb[3] = {(ls_real)0.3, (ls_real)0.5, (ls_real)0.7};
        uint32_t i, j, a = 0, c;
        ls_sh_basis(n, b);
        for (i = 0; i < 9; i++)
            for (j = i; j < 9; j++) ne.ata[a++] = b[i] * b[j];
        for (c = 0; c < 3; c++)
            for (j = 0; j < 9; j++) ne.atb[9 * c + j] = b[j] * rgb[c];
        ne.pixels = 1;
        CHECK_STATUS(ls_sh_solve(&ne, sh, NULL), LS_OK);
        for (c = 0; c < 3; c++) {
            double e = 0;
            for (j = 0; j < 9; j++) e += (double)sh[9 * c + j] * (double)b[j];
            CHECK_NEAR(e, rgb[c], 1e-3);
        }
        ne.atb[4] = (ls_real)NAN;
        for (k = 0; k < 27; k++) before[k] = sh[k];
        CHECK_STATUS(ls_sh_solve(&ne, sh, NULL), LS_ERR_NONFINITE);
        CHECK(memcmp(sh, before, sizeof sh) == 0);
    }
    ls_sh_normal_clear(&ne);
    memset(&vw, 0, sizeof vw);
    memset(img, 0, sizeof img);
    CHECK_STATUS(ls_sh_accumulate(NULL, &vw, img, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_sh_accumulate(&ne, NULL, img, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_sh_accumulate(&ne, &vw, NULL, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_sh_accumulate(&ne, &vw, img, NULL), LS_ERR_INVALID); /* no vis */
    memset(&vis, 0, sizeof vis);
    vw.vis = &vis;
    CHECK_STATUS(ls_sh_accumulate(&ne, &vw, img, &d), LS_ERR_STATE); /* not set up */
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &arena, 4, 4, 1, 3) == LS_OK);
    vw.vertex_count = 3;
    CHECK_STATUS(ls_sh_accumulate(&ne, &vw, img, &d), LS_ERR_INVALID); /* no normals */
    CHECK(d.what != NULL && strstr(d.what, "normals") != NULL);
    CHECK_EQ(ne.pixels, 0);
}

/* The fit estimating its lighting: the ellipsoid's targets (fit_targets.h)
 * from a sphere. */
#define FIT_RES 32u
#define FIT_VIEWS 6u
#define FIT_STEPS 200u

static ls_real fit_mvps[FIT_VIEWS][16];
static ls_real *fit_targets[FIT_VIEWS];
static ls_real fit_sh[27];

static void fit_config(ls_fit_config *c, uint32_t guard)
{
    ls_fit_config_default(c);
    c->width = c->height = FIT_RES;
    c->shading.mode = LS_SHADE_SH;
    c->shading.sh = NULL; /* the fit's own */
    c->light = LS_FIT_LIGHT_ESTIMATE;
    c->guard = guard;
}

/* A fit of config c from a level-2 sphere of radius 0.8 on the targets above. */
static ls_status fit_sphere(ls_fit *fit, const ls_fit_config *c, ls_arena *arena)
{
    ls_fit_views v;
    ls_mesh init;
    uint32_t i;
    v.count = FIT_VIEWS;
    v.mvp = &fit_mvps[0][0];
    v.targets = (const ls_real *const *)fit_targets;
    if (ls_icosphere(2, arena, &init) != LS_OK) return LS_ERR_NOMEM;
    for (i = 0; i < 3u * init.vertex_count; i++) init.positions[i] *= (ls_real)0.8;
    return ls_fit_init(fit, c, &v, &init, arena, NULL);
}

/* n steps of the fit from a level-2 sphere of radius 0.8 into *out (the
 * lighting and the loss of each step); returns the final mesh's hash. */
static uint64_t fit_run(uint32_t n, uint32_t albedo, ls_real sh_out[27], ls_real *losses, ls_arena *arena)
{
    ls_fit_config c;
    ls_fit fit;
    uint32_t i;
    ls_arena_mark mark = ls_arena_save(arena);
    uint64_t h;
    fit_config(&c, 0);
    c.albedo = albedo;
    if (fit_sphere(&fit, &c, arena) != LS_OK) return 0;
    CHECK_EQ(fit.sh_valid, 0);
    for (i = 0; i < n; i++) {
        if (ls_fit_step(&fit, NULL, NULL) != LS_OK) return 0;
        losses[i] = fit.loss;
    }
    CHECK_EQ(fit.sh_valid, 1);
    memcpy(sh_out, fit.sh, sizeof fit.sh);
    h = test_hash_reals(fit.x, 3u * (size_t)fit.vertex_count, TEST_HASH_SEED);
    ls_arena_restore(arena, mark);
    return h;
}

static void fit_estimates_the_lighting(void)
{
    ls_arena arena;
    ls_real sh1[27], sh2[27], loss1[FIT_STEPS], loss2[FIT_STEPS];
    uint64_t h1, h2;
    double err0 = 0, err = 0;
    uint32_t k;
    fit_test_targets(3, FIT_VIEWS, FIT_RES, buf, BUF_BYTES / 2u, fit_mvps, fit_targets, fit_sh);
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2u, BUF_BYTES / 2u) == LS_OK);
    h1 = fit_run(FIT_STEPS, LS_FIT_ALBEDO_UNIFORM, sh1, loss1, &arena);
    REQUIRE(h1 != 0);
    if (!geo_emulated()) { /* the same bits twice (under QEMU, where a fit is 50 times slower, once) */
        h2 = fit_run(FIT_STEPS, LS_FIT_ALBEDO_UNIFORM, sh2, loss2, &arena);
        CHECK(h1 == h2);
        CHECK(memcmp(sh1, sh2, sizeof sh1) == 0);
        CHECK(memcmp(loss1, loss2, sizeof loss1) == 0);
    }
    CHECK_MSG(loss1[FIT_STEPS - 1] < (ls_real)0.5 * loss1[0], "loss %g -> %g", (double)loss1[0],
              (double)loss1[FIT_STEPS - 1]);
    /* the targets' lighting: the constant term and the first band (the rest is 0) */
    for (k = 0; k < 27; k++) {
        err = fmax(err, fabs((double)sh1[k] - (double)fit_sh[k]));
        err0 = fmax(err0, fabs((double)fit_sh[k]));
    }
    CHECK_MSG(err < 0.05 * err0, "lighting error %.3g (coefficients up to %.3g)", err, err0);
    for (k = 0; k < FIT_VIEWS; k++) free(fit_targets[k]);
}

/* Painted targets (a per-vertex albedo): the fit with LS_FIT_ALBEDO_VERTEX
 * reproduces them better than with a uniform albedo, the same bits twice;
 * a remesh estimates the albedo again at the next step. */
static void fit_vertex_albedo(void)
{
    ls_arena arena;
    ls_real sh[27], loss_u[FIT_STEPS], loss_v[FIT_STEPS], loss_v2[FIT_STEPS];
    uint64_t hu, hv, hv2;
    uint32_t i;
    fit_test_targets_painted(3, FIT_VIEWS, FIT_RES, buf, BUF_BYTES / 2u, fit_mvps, fit_targets, fit_sh, 1);
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2u, BUF_BYTES / 2u) == LS_OK);
    hu = fit_run(FIT_STEPS, LS_FIT_ALBEDO_UNIFORM, sh, loss_u, &arena);
    hv = fit_run(FIT_STEPS, LS_FIT_ALBEDO_VERTEX, sh, loss_v, &arena);
    REQUIRE(hu != 0 && hv != 0);
    if (!geo_emulated()) { /* the same bits twice, natively */
        hv2 = fit_run(FIT_STEPS, LS_FIT_ALBEDO_VERTEX, sh, loss_v2, &arena);
        CHECK(hv == hv2 && memcmp(loss_v, loss_v2, sizeof loss_v) == 0);
    }
    printf("     final loss: vertex albedo %g, uniform %g\n", (double)loss_v[FIT_STEPS - 1], (double)loss_u[FIT_STEPS - 1]);
    CHECK_MSG(loss_v[FIT_STEPS - 1] < (ls_real)0.7 * loss_u[FIT_STEPS - 1], "final loss: vertex albedo %g, uniform %g",
              (double)loss_v[FIT_STEPS - 1], (double)loss_u[FIT_STEPS - 1]);
    {
        ls_fit_config c;
        ls_fit fit;
        double mean = 0;
        fit_config(&c, 0);
        c.albedo = LS_FIT_ALBEDO_VERTEX;
        REQUIRE(fit_sphere(&fit, &c, &arena) == LS_OK);
        for (i = 0; i < 16; i++) REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
        for (i = 0; i < 3u * fit.vertex_count; i++) mean += (double)fit.albedo[i];
        mean /= 3.0 * fit.vertex_count;
        CHECK_MSG(fabs(mean - 1) < 0.2, "mean albedo %g", mean); /* the scale in the lighting */
        REQUIRE(ls_fit_remesh(&fit, &arena, (ls_real)1, (ls_real)1, NULL, NULL) == LS_OK);
        CHECK_EQ(fit.albedo_due, 1);
        for (i = 0; i < 3u * fit.vertex_count; i++) REQUIRE(fit.albedo[i] == (ls_real)1);
        REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
        CHECK_EQ(fit.albedo_due, 0);
        mean = 0;
        for (i = 0; i < 3u * fit.vertex_count; i++) mean = fmax(mean, fabs((double)fit.albedo[i] - 1));
        CHECK_MSG(mean > 0.2, "after the remesh's first step the albedo varies by %g", mean);
    }
    for (i = 0; i < FIT_VIEWS; i++) free(fit_targets[i]);
}

/* A checkpoint holds the lighting: the steps after a roll-back repeat the
 * ones after the save bit for bit; a remesh keeps it. */
static void fit_checkpoint_and_remesh_keep_the_lighting(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit fit;
    ls_real sh_a[27], loss_a[4];
    uint32_t i;
    fit_test_targets(3, FIT_VIEWS, FIT_RES, buf, BUF_BYTES / 2u, fit_mvps, fit_targets, fit_sh);
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2u, BUF_BYTES / 2u) == LS_OK);
    fit_config(&c, 1);
    REQUIRE(fit_sphere(&fit, &c, &arena) == LS_OK);
    for (i = 0; i < 5; i++) REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
    REQUIRE(ls_fit_save(&fit) == LS_OK);
    for (i = 0; i < 4; i++) {
        REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
        loss_a[i] = fit.loss;
    }
    memcpy(sh_a, fit.sh, sizeof sh_a);
    REQUIRE(ls_fit_rollback(&fit) == LS_OK);
    for (i = 0; i < 4; i++) {
        REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
        CHECK(fit.loss == loss_a[i]);
    }
    CHECK(memcmp(sh_a, fit.sh, sizeof sh_a) == 0);
    REQUIRE(ls_fit_remesh(&fit, &arena, (ls_real)1, (ls_real)1, NULL, NULL) == LS_OK);
    CHECK_EQ(fit.sh_valid, 1);
    CHECK(memcmp(sh_a, fit.sh, sizeof sh_a) == 0);
    CHECK_STATUS(ls_fit_step(&fit, NULL, NULL), LS_OK);
    for (i = 0; i < FIT_VIEWS; i++) free(fit_targets[i]);
}

/* config.grad_limit: a block's gradient is scaled down to K x its last
 * scale when it exceeds it (here K = 0.5: every step after the first), and a
 * limit no gradient reaches gives the same bits as none. */
static void fit_grad_limit(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit fit;
    ls_real x_off[3 * 200];
    uint32_t i, b, run, n_off = 0;
    fit_test_targets(3, FIT_VIEWS, FIT_RES, buf, BUF_BYTES / 2u, fit_mvps, fit_targets, fit_sh);
    for (run = 0; run < 3; run++) {
        REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2u, BUF_BYTES / 2u) == LS_OK);
        fit_config(&c, 0);
        c.grad_limit = run == 0 ? (ls_real)0 : run == 1 ? (ls_real)1e30 : (ls_real)0.5;
        REQUIRE(fit_sphere(&fit, &c, &arena) == LS_OK);
        REQUIRE(3u * fit.vertex_count <= 3u * 200u);
        for (i = 0; i < 12; i++) {
            ls_real scale[LS_OPTIM_MAX_BLOCKS];
            size_t at = 0, j;
            memcpy(scale, fit.optim.last_scale, sizeof scale);
            REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
            if (run != 2 || i == 0) continue;
            for (b = 0; b < fit.optim.block_count; b++) { /* fit.grad: what the optimizer was given */
                double mx = 0;
                for (j = at; j < at + fit.optim.block_size[b]; j++) mx = fmax(mx, fabs((double)fit.grad[j]));
                CHECK_MSG(mx <= 0.5 * (double)scale[b] * (1 + 1e-6), "step %u block %u: %g > %g", (unsigned)i,
                          (unsigned)b, mx, 0.5 * (double)scale[b]);
                at += fit.optim.block_size[b];
            }
        }
        if (run == 0) {
            n_off = fit.vertex_count;
            memcpy(x_off, fit.x, 3u * n_off * sizeof(ls_real));
        } else if (run == 1) {
            CHECK(fit.vertex_count == n_off && memcmp(x_off, fit.x, 3u * n_off * sizeof(ls_real)) == 0);
        } else {
            CHECK(memcmp(x_off, fit.x, 3u * n_off * sizeof(ls_real)) != 0); /* the limit changed the steps */
        }
    }
    for (i = 0; i < FIT_VIEWS; i++) free(fit_targets[i]);
}

static void fit_light_config_errors(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views v;
    ls_fit fit;
    ls_mesh init;
    ls_diag d;
    ls_real *t[1];
    ls_real mvp[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    static ls_real img[4 * 8 * 8], sh_given[27];
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_icosphere(1, &arena, &init) == LS_OK);
    t[0] = img;
    v.count = 1;
    v.mvp = mvp;
    v.targets = (const ls_real *const *)t;
    fit_config(&c, 0);
    c.width = c.height = 8;
    c.shading.mode = LS_SHADE_MASK;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "config->light") != NULL);
    c.shading.mode = LS_SHADE_SH;
    c.light = 2;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "config->light") != NULL);
    c.light = LS_FIT_LIGHT_ESTIMATE;
    c.grad_limit = (ls_real)-1;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "config->grad_limit") != NULL);
    c.grad_limit = (ls_real)3;
    c.albedo = 2;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "config->albedo") != NULL);
    c.albedo = LS_FIT_ALBEDO_VERTEX;
    c.light = LS_FIT_LIGHT_GIVEN;
    c.shading.sh = sh_given;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "LS_FIT_LIGHT_ESTIMATE") != NULL);
    c.light = LS_FIT_LIGHT_ESTIMATE;
    c.shading.sh = NULL;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_OK);
}

int main(void)
{
    TEST_INIT("test_sh_estimate");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(basis_matches_sh_eval);
    TEST_RUN(estimate_recovers_known_lighting);
    TEST_RUN(estimate_errors);
    TEST_RUN(estimate_with_vertex_albedo);
    TEST_RUN(albedo_solve_cases);
    TEST_RUN(fit_estimates_the_lighting);
    TEST_RUN(fit_checkpoint_and_remesh_keep_the_lighting);
    TEST_RUN(fit_vertex_albedo);
    TEST_RUN(fit_grad_limit);
    TEST_RUN(fit_light_config_errors);
    free(buf);
    return TEST_END();
}
