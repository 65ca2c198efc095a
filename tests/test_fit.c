/* tests/test_fit.c - the reconstruction loop on a small synthetic problem: a
 * sphere fitted to an ellipsoid seen from 6 views at 32 x 32. Asserts that
 * the loss and the geometric error fall (measured here, independently of the
 * loop), determinism, named errors for bad configurations and non-finite
 * targets, and the exact memory query. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>

#define RES 32u
#define NV 6u
#define BUF_BYTES (32u << 20)

static unsigned char *buf;
static ls_real mvps[NV][16];
static ls_real *targets[NV];
static const ls_real axes[3] = {(ls_real)1.0, (ls_real)0.65, (ls_real)0.8};

/* A few SH bands: light from above-front. */
static void sh_light(ls_real sh[27])
{
    int c;
    memset(sh, 0, 27 * sizeof(ls_real));
    for (c = 0; c < 3; c++) {
        sh[9 * c + 0] = (ls_real)1.6;
        sh[9 * c + 1] = (ls_real)0.9;  /* y */
        sh[9 * c + 2] = (ls_real)0.5;  /* z */
        sh[9 * c + 3] = (ls_real)-0.3; /* x */
    }
}

static ls_real sh_coeffs[27];

static void config_for(ls_fit_config *c, uint32_t method)
{
    ls_fit_config_default(c);
    c->method = method;
    c->width = c->height = RES;
    c->shading.mode = LS_SHADE_SH;
    c->shading.sh = sh_coeffs;
    /* learning rates in units of the initial sphere's radius 0.6 (fit.h):
     * steps of 0.05 and 5e-3 scene units */
    c->optim.lr = (ls_real)(0.05 / 0.6);
    if (method != LS_FIT_LARGE_STEPS) {
        (void)ls_optim_config_default(LS_OPTIM_ADAM, &c->optim);
        c->optim.lr = (ls_real)(5e-3 / 0.6);
        c->reg_weight = (ls_real)1;
    }
}

/* Target renders of the ellipsoid (icosphere level 3 scaled), S = 4. */
static void make_targets(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_vis vis;
    ls_real dirs[3 * NV], proj[16], view[16], *normals;
    const ls_real center[3] = {0, 0, 0};
    ls_shade_opts o;
    uint32_t v, i;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_icosphere(3, &arena, &m) == LS_OK);
    for (i = 0; i < m.vertex_count; i++)
        for (v = 0; v < 3; v++) m.positions[3 * i + v] *= axes[v];
    normals = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
    REQUIRE(normals != NULL);
    REQUIRE(ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, normals, NULL) == LS_OK);
    REQUIRE(ls_camera_fibonacci_dirs(NV, dirs) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1, (ls_real)10, proj) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &arena, RES, RES, 4, m.vertex_count) == LS_OK);
    sh_light(sh_coeffs);
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh_coeffs;
    for (v = 0; v < NV; v++) {
        REQUIRE(ls_camera_orbit(center, (ls_real)3.2, dirs + 3 * v, view) == LS_OK);
        ls_mat4_mul(proj, view, mvps[v]);
        targets[v] = (ls_real *)malloc(4u * RES * RES * sizeof(ls_real));
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = mvps[v]}, &arena,
                NULL) == LS_OK);
        REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                .vertex_count = m.vertex_count, .normals = normals, .opts = &o}, targets[v], NULL) == LS_OK);
    }
}

/* Mean and max over the vertices of | |p / axes| - 1 |: 0 on the ellipsoid. */
static void shape_error(const ls_mesh *m, double *mean, double *max)
{
    uint32_t i;
    *mean = *max = 0.0;
    for (i = 0; i < m->vertex_count; i++) {
        double r2 = 0.0, e;
        int k;
        for (k = 0; k < 3; k++) {
            double q = (double)m->positions[3 * i + k] / (double)axes[k];
            r2 += q * q;
        }
        e = fabs(sqrt(r2) - 1.0);
        *mean += e / m->vertex_count;
        if (e > *max) *max = e;
    }
}

static void initial_sphere(ls_arena *arena, ls_mesh *m, ls_real radius)
{
    uint32_t i;
    if (ls_icosphere(2, arena, m) != LS_OK) return;
    for (i = 0; i < 3u * m->vertex_count; i++) m->positions[i] *= radius;
}

/* Runs `iters` iterations; returns the final mesh positions (malloc'd). */
static ls_real *run_fit(uint32_t method, uint32_t iters, ls_real *first_loss, ls_real *last_loss, double err[2])
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh init, out;
    ls_diag d;
    ls_real *pos;
    uint32_t it;
    ls_status st;
    if (ls_arena_init(&arena, buf, BUF_BYTES) != LS_OK) return NULL;
    initial_sphere(&arena, &init, (ls_real)0.6);
    config_for(&c, method);
    views.count = NV;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    st = ls_fit_init(&fit, &c, &views, &init, &arena, &d);
    if (st != LS_OK) {
        printf("     init: %s %s\n", ls_status_name(st), d.what);
        return NULL;
    }
    for (it = 0; it < iters; it++) {
        st = ls_fit_step(&fit, NULL, &d);
        if (st != LS_OK) {
            printf("     step %u: %s %s\n", (unsigned)it, ls_status_name(st), d.what);
            return NULL;
        }
        if (it == 0) *first_loss = fit.loss;
    }
    *last_loss = fit.loss;
    pos = (ls_real *)malloc(3u * fit.vertex_count * sizeof(ls_real));
    if (pos == NULL || ls_fit_mesh(&fit, pos, &out) != LS_OK) return NULL;
    shape_error(&out, &err[0], &err[1]);
    return pos;
}

static double large_steps_error = 1e30;

static void fit_large_steps_converges(void)
{
    ls_real l0 = 0, l1 = 0, l2 = 0, l3 = 0;
    double e[2], e2[2], e0[2];
    ls_real *a, *b;
    ls_arena arena;
    ls_mesh init;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    shape_error(&init, &e0[0], &e0[1]);
    a = run_fit(LS_FIT_LARGE_STEPS, 80, &l0, &l1, e);
    REQUIRE(a != NULL);
    printf("     large steps (lr 0.05 scene units), 80 iterations: loss %.4g -> %.4g, shape error mean %.4f max %.4f (initial %.4f / %.4f)\n",
           (double)l0, (double)l1, e[0], e[1], e0[0], e0[1]);
    CHECK(l1 < (ls_real)0.25 * l0);
    CHECK(e[0] < 0.1 * e0[0]);
    large_steps_error = e[0];
    /* the same bits again */
    b = run_fit(LS_FIT_LARGE_STEPS, 80, &l2, &l3, e2);
    REQUIRE(b != NULL);
    CHECK(l2 == l0 && l3 == l1);
    CHECK(memcmp(a, b, 3u * 162u * sizeof(ls_real)) == 0);
    free(a);
    free(b);
}

static void fit_baselines_run(void)
{
    static const uint32_t methods[3] = {LS_FIT_NAIVE, LS_FIT_LAPLACIAN, LS_FIT_BILAPLACIAN};
    int i;
    for (i = 0; i < 3; i++) {
        ls_real l0 = 0, l1 = 0;
        double e[2];
        ls_real *p = run_fit(methods[i], 80, &l0, &l1, e);
        REQUIRE(p != NULL);
        printf("     method %u, 80 iterations: loss %.4g -> %.4g, shape error mean %.4f max %.4f\n", (unsigned)methods[i],
               (double)l0, (double)l1, e[0], e[1]);
        CHECK(l1 < l0);
        /* the method's claim at equal iterations, each baseline with Adam at
         * its own step size: large steps' shape error is smaller */
        CHECK(e[0] > 1.5 * large_steps_error);
        free(p);
    }
}

static void fit_rejects_bad_input(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh init;
    ls_diag d;
    ls_real *saved, nan_target[4 * RES * RES];
    const ls_real *bad_targets[NV];
    uint32_t v;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    views.count = NV;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    config_for(&c, LS_FIT_LARGE_STEPS);
    c.weight = -1;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    config_for(&c, LS_FIT_LARGE_STEPS);
    c.form = LS_SYSTEM_ALPHA;
    c.weight = 1;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    config_for(&c, LS_FIT_LARGE_STEPS);
    c.width = 0;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    config_for(&c, LS_FIT_LARGE_STEPS);
    c.method = 9;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    config_for(&c, LS_FIT_LARGE_STEPS);
    views.count = 0;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    views.count = NV;
    CHECK_EQ(ls_arena_used(&arena) > 0, 1); /* the initial mesh only */
    /* a NaN in a target: named with the iteration, nothing changed */
    memcpy(nan_target, targets[3], sizeof nan_target);
    nan_target[4 * (RES * 5 + 7) + 1] = (ls_real)NAN;
    for (v = 0; v < NV; v++) bad_targets[v] = v == 3 ? nan_target : targets[v];
    views.targets = bad_targets;
    REQUIRE(ls_fit_init(&fit, &c, &views, &init, &arena, &d) == LS_OK);
    saved = (ls_real *)malloc((3u * fit.vertex_count + 3u) * sizeof(ls_real));
    REQUIRE(saved != NULL);
    memcpy(saved, fit.params, (3u * fit.vertex_count + 3u) * sizeof(ls_real));
    CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_ERR_NONFINITE);
    CHECK_EQ(fit.iteration, 0);
    CHECK(memcmp(saved, fit.params, (3u * fit.vertex_count + 3u) * sizeof(ls_real)) == 0);
    free(saved);
}

/* Remeshing inside the loop: more vertices, the learning rate times 0.8, the
 * loss still falling; too small an arena changes nothing; not last in the
 * arena is refused. */
static void fit_remesh_in_the_loop(void)
{
    ls_arena arena, small;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh init;
    ls_diag d;
    ls_remesh_info info;
    ls_real lr, loss_before;
    uint32_t it, n_before;
    uint64_t h;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    config_for(&c, LS_FIT_LARGE_STEPS);
    views.count = NV;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    REQUIRE(ls_fit_init(&fit, &c, &views, &init, &arena, &d) == LS_OK);
    for (it = 0; it < 30; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    loss_before = fit.loss;
    n_before = fit.vertex_count;
    lr = fit.config.optim.lr;
    /* an arena with room for the old fit only: LS_ERR_NOMEM, nothing changed */
    {
        size_t used = ls_arena_used(&arena);
        REQUIRE(ls_arena_init(&small, buf, used + 4096) == LS_OK);
        small.bottom = arena.bottom; /* the same objects, a smaller capacity */
        h = test_hash_reals(fit.params, 3u * fit.vertex_count + 3u, TEST_HASH_SEED);
        CHECK_STATUS(ls_fit_remesh(&fit, &small, (ls_real)0.5, (ls_real)0.8, &info, &d), LS_ERR_NOMEM);
        CHECK(small.need > small.capacity);
        CHECK_EQ(small.bottom, arena.bottom);
        CHECK_EQ(small.top, 0);
        CHECK(h == test_hash_reals(fit.params, 3u * fit.vertex_count + 3u, TEST_HASH_SEED));
        CHECK_EQ(fit.vertex_count, n_before);
    }
    CHECK_STATUS(ls_fit_remesh(&fit, &arena, (ls_real)0.5, (ls_real)0.8, &info, &d), LS_OK);
    printf("     remesh after 30 iterations: %u -> %u vertices (%u splits, %u collapses, %u flips), lr %.4g -> %.4g\n",
           (unsigned)n_before, (unsigned)fit.vertex_count, (unsigned)info.splits, (unsigned)info.collapses,
           (unsigned)info.flips, (double)lr, (double)fit.config.optim.lr);
    CHECK(fit.vertex_count > 2u * n_before);
    CHECK_NEAR(fit.config.optim.lr, lr * 0.8, 1e-7);
    CHECK_EQ(fit.iteration, 30);
    CHECK_EQ(fit.remeshes, 1);
    for (it = 0; it < 30; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    printf("     loss %.4g before the remesh, %.4g 30 iterations after\n", (double)loss_before, (double)fit.loss);
    CHECK(fit.loss < loss_before);
    /* the fit must be the arena's last object */
    CHECK(ls_arena_alloc(&arena, 8, 1) != NULL);
    CHECK_STATUS(ls_fit_remesh(&fit, &arena, (ls_real)0.5, (ls_real)0.8, &info, &d), LS_ERR_INVALID);
}

/* The guard (config.guard): a rollback puts back what the steps after the
 * save changed, so the same steps then give the same bits; ls_fit_tangle
 * counts what ls_tangle counts on ls_fit_mesh's result (a mesh with a
 * vertex pushed through the far side), in the fit's own memory. */
static void fit_guard_rolls_back_and_counts(void)
{
    ls_arena arena, other;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh init, cur;
    ls_diag d;
    ls_tangle_report mine, ref;
    ls_remesh_info info;
    ls_real *pos;
    uint64_t at_save, after;
    uint32_t it, k;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES / 2) == LS_OK);
    REQUIRE(ls_arena_init(&other, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    for (k = 0; k < 3; k++) init.positions[k] *= (ls_real)-1.6; /* vertex 0 through the far side */
    config_for(&c, LS_FIT_LARGE_STEPS);
    views.count = NV;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    REQUIRE(ls_fit_init(&fit, &c, &views, &init, &arena, &d) == LS_OK);
    CHECK_STATUS(ls_fit_tangle(&fit, &mine, &d), LS_ERR_INVALID); /* no guard */
    CHECK_STATUS(ls_fit_save(&fit), LS_ERR_INVALID);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES / 2) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    for (k = 0; k < 3; k++) init.positions[k] *= (ls_real)-1.6;
    c.guard = 2;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    c.guard = 1;
    REQUIRE(ls_fit_init(&fit, &c, &views, &init, &arena, &d) == LS_OK);
    CHECK_STATUS(ls_fit_rollback(&fit), LS_ERR_INVALID); /* nothing saved */
    for (it = 0; it < 3; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    /* the count, against ls_tangle on the current mesh in other memory */
    CHECK_STATUS(ls_fit_tangle(&fit, &mine, &d), LS_OK);
    pos = (ls_real *)ls_arena_alloc(&other, 3u * fit.vertex_count, sizeof(ls_real));
    REQUIRE(pos != NULL && ls_fit_mesh(&fit, pos, &cur) == LS_OK);
    REQUIRE(ls_tangle(&cur, NULL, &other, &ref, &d) == LS_OK);
    printf("     ls_fit_tangle %u pairs (%u faces), ls_tangle %u (%u)\n", (unsigned)mine.intersecting_pairs,
           (unsigned)mine.intersecting_faces, (unsigned)ref.intersecting_pairs, (unsigned)ref.intersecting_faces);
    CHECK(ref.intersecting_pairs > 0);
    CHECK_EQ(mine.intersecting_pairs, ref.intersecting_pairs);
    CHECK_EQ(mine.intersecting_faces, ref.intersecting_faces);
    {   /* the pairs alone: the same pair fields, no statistics */
        ls_tangle_report pairs;
        memset(&pairs, 0xab, sizeof pairs);
        CHECK_STATUS(ls_fit_tangle_pairs(&fit, &pairs, &d), LS_OK);
        CHECK_EQ(pairs.intersecting_pairs, ref.intersecting_pairs);
        CHECK_EQ(pairs.intersecting_faces, ref.intersecting_faces);
        CHECK(pairs.first_pair[0] == ref.first_pair[0] && pairs.first_pair[1] == ref.first_pair[1]);
        CHECK(pairs.angle_p50 == 0 && pairs.quality_mean == 0 && mine.angle_p50 > 0);
    }
    /* save, 5 steps, rollback: the saved state; 5 steps again: the same bits */
    REQUIRE(ls_fit_save(&fit) == LS_OK);
    at_save = test_hash_reals(fit.params, 3u * fit.vertex_count + 3u, TEST_HASH_SEED) ^
              test_hash_reals(fit.optim.m2, 3u * fit.vertex_count + 3u, TEST_HASH_SEED + 1u) ^
              test_hash_reals(fit.x, 3u * fit.vertex_count, TEST_HASH_SEED + 2u);
    for (it = 0; it < 5; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    after = test_hash_reals(fit.params, 3u * fit.vertex_count + 3u, TEST_HASH_SEED);
    CHECK_STATUS(ls_fit_rollback(&fit), LS_OK);
    CHECK_EQ(fit.iteration, 3);
    CHECK_EQ(fit.optim.step, 3);
    CHECK(at_save == (test_hash_reals(fit.params, 3u * fit.vertex_count + 3u, TEST_HASH_SEED) ^
                      test_hash_reals(fit.optim.m2, 3u * fit.vertex_count + 3u, TEST_HASH_SEED + 1u) ^
                      test_hash_reals(fit.x, 3u * fit.vertex_count, TEST_HASH_SEED + 2u)));
    for (it = 0; it < 5; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    CHECK(after == test_hash_reals(fit.params, 3u * fit.vertex_count + 3u, TEST_HASH_SEED));
    /* a remesh empties the checkpoint */
    REQUIRE(ls_fit_remesh(&fit, &arena, (ls_real)0.5, (ls_real)0.8, &info, &d) == LS_OK);
    CHECK_STATUS(ls_fit_rollback(&fit), LS_ERR_INVALID);
}

/* With the guard, a remesh whose result self-intersects more than the mesh
 * is refused and changes nothing; without it the same remesh is taken. The
 * case: a sphere flattened to a pancake 0.002 thick (level 2, x widened by
 * 1 + y^2), remeshed at half its mean edge, which pushes its two sides
 * through each other at the rim: the refused result's count (diag->value) is
 * ls_tangle's on ls_remesh's own result. */
static void fit_guard_refuses_a_tangling_remesh(void)
{
    ls_arena arena, other;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh init, cur, out;
    ls_diag d;
    ls_remesh_params rp;
    ls_tangle_report t;
    ls_real *pos, mean;
    uint64_t h;
    uint32_t i, n, g;
    for (g = 1; g <= 2; g++) { /* guard on, then off */
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES / 2) == LS_OK);
        REQUIRE(ls_arena_init(&other, buf + BUF_BYTES / 2, BUF_BYTES / 2) == LS_OK);
        REQUIRE(ls_icosphere(2, &arena, &init) == LS_OK);
        for (i = 0; i < init.vertex_count; i++) {
            ls_real y = init.positions[3u * i + 1u];
            init.positions[3u * i + 2u] *= (ls_real)0.002;
            init.positions[3u * i] *= (ls_real)1 + y * y;
        }
        config_for(&c, LS_FIT_LARGE_STEPS);
        c.guard = g == 1;
        views.count = NV;
        views.mvp = &mvps[0][0];
        views.targets = (const ls_real *const *)targets;
        REQUIRE(ls_fit_init(&fit, &c, &views, &init, &arena, &d) == LS_OK);
        n = fit.vertex_count;
        h = test_hash_reals(fit.params, 3u * n + 3u, TEST_HASH_SEED);
        if (g == 2) {
            CHECK_STATUS(ls_fit_remesh(&fit, &arena, (ls_real)0.5, (ls_real)1, NULL, &d), LS_OK);
            continue;
        }
        /* the remesher's own result, counted here */
        pos = (ls_real *)ls_arena_alloc(&other, 3u * n, sizeof(ls_real));
        REQUIRE(pos != NULL && ls_fit_mesh(&fit, pos, &cur) == LS_OK);
        REQUIRE(ls_remesh_mean_edge(&cur, &mean) == LS_OK);
        ls_remesh_params_default(&rp, (ls_real)0.5 * mean);
        REQUIRE(ls_remesh(&cur, &rp, &other, &out, NULL, &d) == LS_OK);
        REQUIRE(ls_tangle(&out, NULL, &other, &t, &d) == LS_OK);
        CHECK_STATUS(ls_fit_remesh(&fit, &arena, (ls_real)0.5, (ls_real)1, NULL, &d), LS_ERR_MESH);
        printf("     pancake remeshed at half its mean edge: %u self-intersecting pairs (ls_tangle: %u): refused\n",
               (unsigned)d.value, (unsigned)t.intersecting_pairs);
        CHECK(t.intersecting_pairs > 0);
        CHECK(d.has_value && (uint32_t)d.value == t.intersecting_pairs);
        CHECK_EQ(fit.vertex_count, n);
        CHECK(h == test_hash_reals(fit.params, 3u * n + 3u, TEST_HASH_SEED));
        CHECK_EQ(fit.remeshes, 0);
        REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK); /* the fit goes on */
    }
}

/* LS_FIT_MEAN_PROJECT: the step of u has no mean on any axis (the
 * translation block moves the mesh as a whole); it needs that block. */
static void fit_mean_mode_projects(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh init;
    ls_diag d;
    ls_real *before;
    double mean[3] = {0, 0, 0}, scale = 0;
    uint32_t i, k, n;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    for (i = 0; i < init.vertex_count; i++) init.positions[3u * i] += (ls_real)0.2; /* off centre: a mean gradient */
    config_for(&c, LS_FIT_LARGE_STEPS);
    views.count = NV;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    c.mean_mode = LS_FIT_MEAN_PROJECT;
    c.use_translation = 0;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    c.use_translation = 1;
    c.mean_mode = 2;
    CHECK_STATUS(ls_fit_init(&fit, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    c.mean_mode = LS_FIT_MEAN_PROJECT;
    REQUIRE(ls_fit_init(&fit, &c, &views, &init, &arena, &d) == LS_OK);
    n = fit.vertex_count;
    before = (ls_real *)malloc(3u * n * sizeof(ls_real));
    REQUIRE(before != NULL);
    memcpy(before, fit.params, 3u * n * sizeof(ls_real));
    REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) {
            double du = (double)fit.params[3u * i + k] - (double)before[3u * i + k];
            mean[k] += du / n;
            if (fabs(du) > scale) scale = fabs(du);
        }
    printf("     largest |du| %.3g; mean du %.3g %.3g %.3g; translation step %.3g %.3g %.3g\n", scale, mean[0], mean[1],
           mean[2], (double)fit.params[3u * n], (double)fit.params[3u * n + 1u], (double)fit.params[3u * n + 2u]);
    CHECK(scale > 0);
    for (k = 0; k < 3; k++) CHECK(fabs(mean[k]) <= 1e-4 * scale);
    CHECK(fabs((double)fit.params[3u * n]) > 0); /* the translation moved instead */
    free(before);
}

/* view_batch: every pool position maps to a view once per pass over the
 * pool; a batch's step is bit for bit the step of a fit given just those
 * views; a batch of the whole pool is the fit without a batch. */
static void fit_view_batch(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views views, sub;
    ls_fit fa, fb;
    ls_mesh init;
    ls_diag d;
    ls_real sub_mvp[2][16];
    const ls_real *sub_targets[2];
    uint32_t count, batch, pos, k, seen[64], bad = 0;
    memset(&c, 0, sizeof c);
    for (count = 1; count <= 64; count++)
        for (batch = 0; batch <= count; batch++) {
            c.view_batch = batch;
            memset(seen, 0, sizeof seen);
            for (pos = 0; pos < count; pos++) {
                uint32_t b = batch == 0 || batch == count ? count : batch;
                uint32_t v = ls_fit_view_of(&c, count, pos / b, pos % b);
                if (v >= count || seen[v]++) bad++;
            }
        }
    CHECK(bad == 0);
    c.view_batch = 3;
    CHECK(ls_fit_view_of(&c, 0, 5, 1) == 0);
    c.view_batch = 0;
    CHECK(ls_fit_view_of(&c, 7, 5, 4) == 4);
    /* consecutive views of a batch are apart: the stride of 16 is 5 or 7 */
    c.view_batch = 4;
    k = ls_fit_view_of(&c, 16, 0, 1);
    printf("     stride for 16 views: %u\n", (unsigned)k);
    CHECK(k == 5 || k == 7);

    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    initial_sphere(&arena, &init, (ls_real)0.6);
    config_for(&c, LS_FIT_LARGE_STEPS);
    views.count = NV;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    c.view_batch = NV + 1u;
    CHECK_STATUS(ls_fit_init(&fa, &c, &views, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "view_batch") != NULL);
    c.view_batch = 2;
    REQUIRE(ls_fit_init(&fa, &c, &views, &init, &arena, &d) == LS_OK);
    for (k = 0; k < 2; k++) {
        uint32_t v = ls_fit_view_of(&c, NV, 0, k);
        memcpy(sub_mvp[k], mvps[v], sizeof sub_mvp[k]);
        sub_targets[k] = targets[v];
    }
    sub.count = 2;
    sub.mvp = &sub_mvp[0][0];
    sub.targets = sub_targets;
    c.view_batch = 0;
    REQUIRE(ls_fit_init(&fb, &c, &sub, &init, &arena, &d) == LS_OK);
    REQUIRE(ls_fit_step(&fa, NULL, &d) == LS_OK);
    REQUIRE(ls_fit_step(&fb, NULL, &d) == LS_OK);
    printf("     batch of 2 of %u views: loss %.9g, the same 2 views alone %.9g\n", NV, (double)fa.loss, (double)fb.loss);
    CHECK(fa.loss == fb.loss);
    CHECK(memcmp(fa.params, fb.params, (3u * fa.vertex_count + 3u) * sizeof(ls_real)) == 0);
    /* the whole pool as a batch: the fit without one, bit for bit */
    c.view_batch = NV;
    REQUIRE(ls_fit_init(&fa, &c, &views, &init, &arena, &d) == LS_OK);
    c.view_batch = 0;
    REQUIRE(ls_fit_init(&fb, &c, &views, &init, &arena, &d) == LS_OK);
    for (k = 0; k < 2; k++) {
        REQUIRE(ls_fit_step(&fa, NULL, &d) == LS_OK);
        REQUIRE(ls_fit_step(&fb, NULL, &d) == LS_OK);
    }
    CHECK(fa.loss == fb.loss);
    CHECK(memcmp(fa.params, fb.params, (3u * fa.vertex_count + 3u) * sizeof(ls_real)) == 0);
}

typedef struct fit_job {
    ls_fit fit;
    ls_fit_config c;
    ls_fit_views views;
    ls_mesh init;
} fit_job;
static ls_status fit_run(void *ctx, ls_arena *arena)
{
    fit_job *j = (fit_job *)ctx;
    return ls_fit_init(&j->fit, &j->c, &j->views, &j->init, arena, NULL);
}
static uint64_t fit_hash(void *ctx)
{
    fit_job *j = (fit_job *)ctx;
    return test_hash_reals(j->init.positions, 3u * j->init.vertex_count, TEST_HASH_SEED);
}

static void fit_memory_query_is_exact(void)
{
    static LS_ARENA_BUFFER(mesh_buf, 64 << 10);
    static fit_job job;
    ls_arena marena, scratch;
    sweep_job sj;
    uint32_t method;
    static const uint32_t variants[3] = {LS_FIT_LARGE_STEPS, LS_FIT_LAPLACIAN, 3u}; /* 3: large steps, guard */
    uint32_t k;
    for (k = 0; k < 3; k++) {
        method = variants[k];
        REQUIRE(ls_arena_init(&marena, mesh_buf.bytes, sizeof mesh_buf.bytes) == LS_OK);
        initial_sphere(&marena, &job.init, (ls_real)0.6);
        config_for(&job.c, method == 3u ? LS_FIT_LARGE_STEPS : method);
        job.c.guard = method == 3u;
        job.c.width = job.c.height = 16;
        job.views.count = NV;
        job.views.mvp = &mvps[0][0];
        job.views.targets = (const ls_real *const *)targets;
        memset(&sj, 0, sizeof sj);
        sj.name = method == LS_FIT_LARGE_STEPS ? "fit_init (large steps)"
                : method == 3u                  ? "fit_init (large steps, guard)" : "fit_init (laplacian)";
        sj.run = fit_run;
        sj.state_hash = fit_hash;
        sj.ctx = &job;
        sj.exact = 1;
        REQUIRE(ls_arena_init(&scratch, buf, BUF_BYTES) == LS_OK);
        REQUIRE(ls_fit_bytes(&job.c, &job.views, &job.init, &scratch, &sj.answer, NULL) == LS_OK);
        CHECK_EQ(ls_arena_used(&scratch), 0);
        printf("     %s: %lu bytes for %u vertices at 16 x 16\n", sj.name, (unsigned long)sj.answer,
               (unsigned)job.init.vertex_count);
        CHECK_EQ(sweep_arena(&sj), 0);
    }
}

int main(void)
{
    uint32_t v;
    TEST_INIT("test_fit");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(make_targets);
    TEST_RUN(fit_large_steps_converges);
    TEST_RUN(fit_baselines_run);
    TEST_RUN(fit_rejects_bad_input);
    TEST_RUN(fit_remesh_in_the_loop);
    TEST_RUN(fit_guard_rolls_back_and_counts);
    TEST_RUN(fit_guard_refuses_a_tangling_remesh);
    TEST_RUN(fit_mean_mode_projects);
    TEST_RUN(fit_view_batch);
    TEST_RUN(fit_memory_query_is_exact);
    for (v = 0; v < NV; v++) free(targets[v]);
    free(buf);
    return TEST_END();
}
