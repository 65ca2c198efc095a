/* tests/fit_targets.h - the fit tests' small problem (test_fit_knobs.c,
 * test_fit_memory.c): an ellipsoid (icosphere of `level`, y scaled by 0.7)
 * with SH shading (coefficients written to sh), seen from nv Fibonacci
 * directions at distance 3.2 (45.8 degree horizontal fov), res x res with
 * S = 4. The view transforms go to mvps, the target images (malloc'ed,
 * RGBA) to targets. work: scratch of work_bytes. Static: include once.
 * fit_test_targets_painted: the same with a per-vertex albedo that varies
 * over the surface (fit_test_paint: bands with a phase per channel). */
#ifndef LS_TEST_FIT_TARGETS_H
#define LS_TEST_FIT_TARGETS_H

#define FIT_TARGETS_MAX_VIEWS 16u

/* The painted albedo at point p (channel c): 0.25 .. 0.95. */
static ls_real fit_test_paint(const ls_real *p, uint32_t c)
{
    return (ls_real)(0.6 + 0.35 * sin(6.283185307179586 * (0.6 * (double)p[1] + 0.25 * (double)p[0]) + 2.0943951023931953 * c));
}

static void fit_test_targets_painted(uint32_t level, uint32_t nv, uint32_t res, unsigned char *work, size_t work_bytes,
                                     ls_real (*mvps)[16], ls_real **targets, ls_real sh[27], int painted)
{
    ls_arena arena;
    ls_mesh m;
    ls_vis vis;
    ls_real dirs[3 * FIT_TARGETS_MAX_VIEWS], proj[16], view[16], *normals;
    const ls_real center[3] = {0, 0, 0};
    ls_shade_opts o;
    uint32_t v, i;
    REQUIRE(nv <= FIT_TARGETS_MAX_VIEWS);
    REQUIRE(ls_arena_init(&arena, work, work_bytes) == LS_OK);
    REQUIRE(ls_icosphere(level, &arena, &m) == LS_OK);
    for (i = 0; i < m.vertex_count; i++) m.positions[3 * i + 1] *= (ls_real)0.7;
    normals = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
    REQUIRE(normals != NULL);
    REQUIRE(ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, normals, NULL) == LS_OK);
    REQUIRE(ls_camera_fibonacci_dirs(nv, dirs) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1, (ls_real)10, proj) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &arena, res, res, 4, m.vertex_count) == LS_OK);
    memset(sh, 0, 27 * sizeof(ls_real));
    for (i = 0; i < 3; i++) sh[9 * i] = (ls_real)1.5, sh[9 * i + 1] = (ls_real)0.8, sh[9 * i + 3] = (ls_real)-0.3;
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh;
    if (painted) {
        ls_real *colors = (ls_real *)ls_arena_alloc(&arena, 3u * m.vertex_count, sizeof(ls_real));
        REQUIRE(colors != NULL);
        for (i = 0; i < 3u * m.vertex_count; i++) colors[i] = fit_test_paint(m.positions + 3u * (i / 3u), i % 3u);
        o.vertex_colors = colors;
    }
    for (v = 0; v < nv; v++) {
        REQUIRE(ls_camera_orbit(center, (ls_real)3.2, dirs + 3 * v, view) == LS_OK);
        ls_mat4_mul(proj, view, mvps[v]);
        targets[v] = (ls_real *)malloc(4u * res * res * sizeof(ls_real));
        REQUIRE(targets[v] != NULL);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = mvps[v]}, &arena,
                NULL) == LS_OK);
        REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                .vertex_count = m.vertex_count, .normals = normals, .opts = &o}, targets[v], NULL) == LS_OK);
    }
}

static void fit_test_targets(uint32_t level, uint32_t nv, uint32_t res, unsigned char *work, size_t work_bytes,
                             ls_real (*mvps)[16], ls_real **targets, ls_real sh[27])
{
    fit_test_targets_painted(level, nv, res, work, work_bytes, mvps, targets, sh, 0);
}

#endif /* LS_TEST_FIT_TARGETS_H */
