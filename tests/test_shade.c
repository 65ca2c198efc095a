/* test_shade.c - shading against independent float64 computations: SH
 * irradiance as n_h^T M n_h, SH projection of band-limited environments
 * whose irradiance is known in closed form, Lambert, vertex colours,
 * background, alpha = coverage and the box resolve of supersamples. */
#include "test.h"
#include <stdlib.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/camera.h>
#include <largesteps/image.h>

#define TEST_PI 3.14159265358979323846

/* E(n) = n_h^T M n_h / pi, M built as in the header (the matrix form, not
 * the library's expanded polynomial). */
static double ref_sh(const double L[9], const double n[3])
{
    const double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    double M[4][4], nh[4] = {n[0], n[1], n[2], 1}, e = 0;
    int r, c;
    M[0][0] = c1 * L[8];  M[0][1] = c1 * L[4];  M[0][2] = c1 * L[7]; M[0][3] = c2 * L[3];
    M[1][0] = c1 * L[4];  M[1][1] = -c1 * L[8]; M[1][2] = c1 * L[5]; M[1][3] = c2 * L[1];
    M[2][0] = c1 * L[7];  M[2][1] = c1 * L[5];  M[2][2] = c3 * L[6]; M[2][3] = c2 * L[2];
    M[3][0] = c2 * L[3];  M[3][1] = c2 * L[1];  M[3][2] = c2 * L[2]; M[3][3] = c4 * L[0] - c5 * L[6];
    for (r = 0; r < 4; r++)
        for (c = 0; c < 4; c++) e += nh[r] * M[r][c] * nh[c];
    return e / TEST_PI;
}

static void sh_eval_matches_matrix_form(void)
{
    ls_real sh[27], n[3], rgb[3];
    double L[9];
    int trial, c, k;
    double max_err = 0;
    for (trial = 0; trial < 200; trial++) {
        for (k = 0; k < 27; k++) sh[k] = (ls_real)(sin(trial * 3.1 + k * 1.7) * 2);
        for (k = 0; k < 3; k++) n[k] = (ls_real)cos(trial * 0.77 + k * 2.1) * (ls_real)1.3;
        ls_shade_sh_eval(sh, n, rgb);
        for (c = 0; c < 3; c++) {
            double nd[3] = {(double)n[0], (double)n[1], (double)n[2]};
            for (k = 0; k < 9; k++) L[k] = (double)sh[9 * c + k];
            max_err = fmax(max_err, fabs((double)rgb[c] - ref_sh(L, nd)));
        }
    }
    CHECK_MSG(max_err < TEST_EPS(64) * 10, "max error %.3g", max_err);
}

/* An environment that is a polynomial of degree <= 2 in the direction has
 * an exactly known irradiance: for L = 1 + a.d, E/pi = 1 + (2/3) a.n; for
 * L = (a.d)^2 (unit a), E/pi = 1/3 + (1/6) (3 (a.n)^2 - 1) / 2. */
static void sh_projection_gives_known_irradiance(void)
{
    enum { W = 256, H = 128 };
    ls_real *env = (ls_real *)malloc(3 * W * H * sizeof(ls_real)), sh[27], rgb[3], n[3];
    double a[3] = {0.3, -0.5, 0.81}, na = sqrt(0.09 + 0.25 + 0.6561), max_err = 0;
    int i, j, trial;
    for (i = 0; i < 3; i++) a[i] /= na;
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            double t = TEST_PI * (j + 0.5) / H, p = 2 * TEST_PI * (i + 0.5) / W;
            double d[3] = {sin(t) * cos(p), cos(t), sin(t) * sin(p)};
            double ad = a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
            ls_real *px = env + 3 * (j * W + i);
            px[0] = (ls_real)(1 + ad); /* red: linear */
            px[1] = (ls_real)(ad * ad); /* green: quadratic */
            px[2] = (ls_real)1;         /* blue: constant */
        }
    REQUIRE(ls_sh_from_equirect(env, W, H, sh) == LS_OK);
    for (trial = 0; trial < 50; trial++) {
        double nd[3], an;
        nd[0] = cos(trial * 1.3) * sin(trial * 0.7 + 0.2);
        nd[1] = cos(trial * 0.7 + 0.2);
        nd[2] = sin(trial * 1.3) * sin(trial * 0.7 + 0.2);
        for (i = 0; i < 3; i++) n[i] = (ls_real)nd[i];
        an = a[0] * nd[0] + a[1] * nd[1] + a[2] * nd[2];
        ls_shade_sh_eval(sh, n, rgb);
        max_err = fmax(max_err, fabs((double)rgb[0] - (1 + 2.0 / 3.0 * an)));
        max_err = fmax(max_err, fabs((double)rgb[1] - (1.0 / 3.0 + (3 * an * an - 1) / 12.0)));
        max_err = fmax(max_err, fabs((double)rgb[2] - 1));
    }
    /* the constants have 6 digits; the quadrature is a midpoint rule */
    CHECK_MSG(max_err < 2e-4, "max irradiance error %.3g", max_err);
    CHECK_STATUS(ls_sh_from_equirect(env, 0, H, sh), LS_ERR_INVALID);
    free(env);
}

/* Scene: two triangles forming a quad in front of the camera, orthographic
 * (identity clip transform), normals and colours varying per vertex. */
static const ls_real quad_pos[12] = {-0.6f, -0.5f, 0, 0.7f, -0.4f, 0, 0.5f, 0.6f, 0, -0.5f, 0.4f, 0};
static const uint32_t quad_idx[6] = {0, 1, 2, 0, 2, 3};

static void shade_matches_interpolated_reference(void)
{
    static LS_ARENA_BUFFER(mem, 1 << 20);
    ls_arena a;
    ls_vis vis;
    ls_real mvp[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    ls_real normals[12] = {0, 0, 1, (ls_real)0.6, 0, (ls_real)0.8, 0, (ls_real)0.6, (ls_real)0.8,
                           (ls_real)-0.48, (ls_real)-0.6, (ls_real)0.64};
    ls_real colors[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, (ls_real)0.5, (ls_real)0.5, (ls_real)0.5};
    ls_real sh[27], out[4 * 20 * 16];
    ls_diag dg;
    ls_light lights[2] = {{{0, 0, 1}, {1, (ls_real)0.5, (ls_real)0.25}},
                          {{(ls_real)0.6, 0, (ls_real)0.8}, {(ls_real)0.2, (ls_real)0.2, (ls_real)0.2}}};
    ls_shade_opts o;
    uint32_t mode, renorm;
    int k;
    double max_err = 0;
    long long covered = 0;
    for (k = 0; k < 27; k++) sh[k] = (ls_real)(0.3 + 0.1 * sin(k * 0.9));
    REQUIRE(ls_arena_init(&a, mem.bytes, sizeof mem.bytes) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &a, 20, 16, 1, 4) == LS_OK);
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = quad_pos, .indices = quad_idx, .triangle_count = 2,
            .vertex_count = 4, .mvp = mvp}, &a, NULL) == LS_OK);
    for (mode = 0; mode <= LS_SHADE_COLOR; mode++)
        for (renorm = 0; renorm < 2; renorm++) {
            size_t p;
            ls_shade_opts_init(&o);
            o.mode = mode;
            o.renormalize = renorm;
            o.sh = sh;
            o.lights = lights;
            o.light_count = 2;
            o.ambient[0] = (ls_real)0.05;
            o.vertex_colors = (mode == LS_SHADE_COLOR || renorm) ? colors : NULL;
            o.background[0] = (ls_real)0.1;
            o.background[1] = (ls_real)0.2;
            o.background[2] = (ls_real)0.3;
            REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = quad_idx, .triangle_count = 2, .vertex_count = 4,
                    .normals = normals, .opts = &o}, out, NULL) == LS_OK);
            for (p = 0; p < 20 * 16; p++) {
                double want[3], b[3], n[3], alb[3] = {1, 1, 1};
                const uint32_t *f;
                int c, q;
                if (vis.tri[p] == 0) {
                    CHECK(out[4 * p] == o.background[0] && out[4 * p + 2] == o.background[2] && out[4 * p + 3] == 0);
                    continue;
                }
                covered++;
                f = quad_idx + 3 * (vis.tri[p] - 1);
                b[0] = (double)vis.bary[2 * p];
                b[1] = (double)vis.bary[2 * p + 1];
                b[2] = 1 - b[0] - b[1];
                for (c = 0; c < 3; c++) {
                    n[c] = 0;
                    for (q = 0; q < 3; q++) n[c] += b[q] * (double)normals[3 * f[q] + (uint32_t)c];
                    if (o.vertex_colors) {
                        alb[c] = 0;
                        for (q = 0; q < 3; q++) alb[c] += b[q] * (double)colors[3 * f[q] + (uint32_t)c];
                    }
                }
                if (renorm) {
                    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                    for (c = 0; c < 3; c++) n[c] /= l;
                }
                for (c = 0; c < 3; c++) {
                    if (mode == LS_SHADE_MASK) want[c] = 1;
                    else if (mode == LS_SHADE_COLOR) want[c] = alb[c];
                    else if (mode == LS_SHADE_SH) {
                        double L[9];
                        for (q = 0; q < 9; q++) L[q] = (double)sh[9 * c + q];
                        want[c] = alb[c] * ref_sh(L, n);
                    } else {
                        double s = (double)o.ambient[c];
                        for (q = 0; q < 2; q++) {
                            double d = n[0] * (double)lights[q].dir[0] + n[1] * (double)lights[q].dir[1] +
                                       n[2] * (double)lights[q].dir[2];
                            if (d > 0) s += d * (double)lights[q].rgb[c];
                        }
                        want[c] = alb[c] * s;
                    }
                    max_err = fmax(max_err, fabs((double)out[4 * p + (size_t)c] - want[c]));
                }
                CHECK(out[4 * p + 3] == 1);
            }
        }
    CHECK(covered > 300);
    CHECK_MSG(max_err < TEST_EPS(64) * 10, "max error %.3g", max_err);
    /* argument errors */
    o.mode = 7;
    CHECK_STATUS(ls_shade(&(ls_view){.vis = &vis, .indices = quad_idx, .triangle_count = 2, .vertex_count = 4,
            .normals = normals, .opts = &o}, out, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "view->opts->mode") != NULL);
    o.mode = LS_SHADE_SH;
    o.sh = NULL;
    CHECK_STATUS(ls_shade(&(ls_view){.vis = &vis, .indices = quad_idx, .triangle_count = 2, .vertex_count = 4,
            .normals = normals, .opts = &o}, out, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "view->opts->sh") != NULL);
    o.mode = LS_SHADE_MASK;
    CHECK_STATUS(ls_shade(&(ls_view){.vis = &vis, .indices = quad_idx, .triangle_count = 2, .vertex_count = 3,
            .normals = normals, .opts = &o}, out, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "view->vertex_count") != NULL);
    CHECK_STATUS(ls_shade(&(ls_view){.vis = &vis, .indices = quad_idx, .triangle_count = 2, .vertex_count = 4,
            .normals = normals, .opts = &o}, NULL, &dg), LS_ERR_INVALID);
    CHECK(strcmp(dg.what, "out is NULL") == 0);
    CHECK_STATUS(ls_shade_vertex_normals(NULL, 4, quad_idx, 2, out, &dg), LS_ERR_INVALID);
    CHECK(strstr(dg.what, "positions") != NULL);
}

static void box_resolve_and_coverage(void)
{
    static LS_ARENA_BUFFER(mem, 1 << 21);
    ls_arena a;
    ls_vis vis;
    ls_real mvp[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    ls_real colors[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, (ls_real)0.5, (ls_real)0.5, (ls_real)0.5};
    ls_real out[4 * 24 * 20], bgimg[3 * 24 * 20];
    ls_shade_opts o;
    uint32_t ss;
    size_t p;
    int partial = 0;
    for (p = 0; p < 3 * 24 * 20; p++) bgimg[p] = (ls_real)((p * 37 % 101) / 100.0);
    REQUIRE(ls_arena_init(&a, mem.bytes, sizeof mem.bytes) == LS_OK);
    for (ss = 1; ss <= 4; ss *= 2) {
        ls_arena_init(&a, mem.bytes, sizeof mem.bytes);
        REQUIRE(ls_vis_init(&vis, &a, 24, 20, ss, 4) == LS_OK);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = quad_pos, .indices = quad_idx, .triangle_count = 2,
                .vertex_count = 4, .mvp = mvp}, &a, NULL) == LS_OK);
        ls_shade_opts_init(&o);
        o.mode = LS_SHADE_COLOR;
        o.vertex_colors = colors;
        o.background_image = bgimg;
        REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = quad_idx, .triangle_count = 2, .vertex_count = 4,
                .opts = &o}, out, NULL) == LS_OK);
        for (p = 0; p < 24 * 20; p++) {
            size_t x = p % 24, y = p / 24;
            uint32_t i, j, cov = 0;
            double acc[3] = {0, 0, 0};
            int c;
            for (j = 0; j < ss; j++)
                for (i = 0; i < ss; i++) {
                    size_t s = (y * ss + j) * vis.sw + x * ss + i;
                    for (c = 0; c < 3; c++) {
                        if (vis.tri[s]) {
                            const uint32_t *f = quad_idx + 3 * (vis.tri[s] - 1);
                            double b0 = (double)vis.bary[2 * s], b1 = (double)vis.bary[2 * s + 1];
                            acc[c] += b0 * (double)colors[3 * f[0] + (uint32_t)c] + b1 * (double)colors[3 * f[1] + (uint32_t)c] +
                                      (1 - b0 - b1) * (double)colors[3 * f[2] + (uint32_t)c];
                        } else {
                            acc[c] += (double)bgimg[3 * p + (size_t)c];
                        }
                    }
                    cov += vis.tri[s] != 0;
                }
            CHECK_NEAR(out[4 * p + 3], (double)cov / (ss * ss), 0);
            if (cov > 0 && cov < ss * ss) partial++;
            for (c = 0; c < 3; c++) CHECK_NEAR(out[4 * p + (size_t)c], acc[c] / (ss * ss), TEST_EPS(32));
        }
    }
    CHECK(partial > 10); /* edge pixels with fractional alpha exist */
}

static void vertex_normals_of_an_octahedron(void)
{
    /* closed, outward: each vertex normal is the vertex direction */
    ls_real pos[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    uint32_t f[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    ls_real n[18];
    int k;
    ls_diag d;
    REQUIRE(ls_shade_vertex_normals(pos, 6, f, 8, n, NULL) == LS_OK);
    for (k = 0; k < 18; k++) CHECK_NEAR(n[k], pos[k], TEST_EPS(8));
    f[5] = 9;
    ls_diag_clear(&d);
    CHECK_STATUS(ls_shade_vertex_normals(pos, 6, f, 8, n, &d), LS_ERR_MESH);
    CHECK(d.has_index && d.index == 1);
}


static void env_background_follows_the_rays(void)
{
    enum { EW = 64, EH = 32, W = 24, H = 18 };
    ls_real env[3 * EW * EH], out[3 * W * H], view[16], proj[16];
    ls_real eye[3] = {(ls_real)0.3, (ls_real)-0.2, (ls_real)0.5}, at[3] = {(ls_real)1.3, (ls_real)0.4, (ls_real)-0.7};
    ls_real up[3] = {0, 1, 0};
    int i, j, checked = 0, wrong = 0, trial;
    for (j = 0; j < EH; j++)
        for (i = 0; i < EW; i++) {
            env[3 * (j * EW + i)] = (ls_real)i;
            env[3 * (j * EW + i) + 1] = (ls_real)j;
            env[3 * (j * EW + i) + 2] = (ls_real)0.5;
        }
    for (trial = 0; trial < 2; trial++) {
        double fx = 1.1, aspect = (double)W / H, tx = tan(fx / 2), ty = tx / aspect, R[9];
        if (trial == 1) {
            at[0] = (ls_real)-2;
            at[1] = (ls_real)1.7;
        }
        REQUIRE(ls_camera_look_at(eye, at, up, view) == LS_OK);
        REQUIRE(ls_camera_perspective((ls_real)fx, LS_FOV_X, (ls_real)aspect, (ls_real)0.1, 50, proj) == LS_OK);
        REQUIRE(ls_shade_env_background(env, EW, EH, view, proj, W, H, out) == LS_OK);
        for (i = 0; i < 9; i++) R[i] = (double)view[4 * (i / 3) + i % 3];
        for (j = 0; j < H; j++)
            for (i = 0; i < W; i++) {
                /* view-space ray through the pixel centre, then world */
                double nx = 2.0 * (i + 0.5) / W - 1, ny = 1 - 2.0 * (j + 0.5) / H;
                double d[3] = {nx * tx, ny * ty, -1}, w[3], t, ph, u, v;
                int k;
                for (k = 0; k < 3; k++) w[k] = R[k] * d[0] + R[3 + k] * d[1] + R[6 + k] * d[2];
                t = atan2(sqrt(w[0] * w[0] + w[2] * w[2]), w[1]);
                ph = atan2(w[2], w[0]);
                if (ph < 0) ph += 2 * TEST_PI;
                u = ph / (2 * TEST_PI) * EW;
                v = t / TEST_PI * EH;
                if (fabs(u - floor(u + 0.5)) < 1e-6 || fabs(v - floor(v + 0.5)) < 1e-6) continue;
                checked++;
                if ((double)out[3 * (j * W + i)] != floor(u) || (double)out[3 * (j * W + i) + 1] != floor(v)) wrong++;
            }
    }
    CHECK(checked > 800);
    CHECK_EQ(wrong, 0);
    proj[15] = (ls_real)NAN;
    CHECK_STATUS(ls_shade_env_background(env, EW, EH, view, proj, W, H, out), LS_ERR_NONFINITE);
    memset(proj, 0, sizeof proj);
    CHECK_STATUS(ls_shade_env_background(env, EW, EH, view, proj, W, H, out), LS_ERR_INVALID);
}

/* ---- golden renders --------------------------------------------------------
 * The bunny from three views (ls_camera_fibonacci_dirs(3), ls_camera_orbit at
 * distance 25 around the bounding-box centre, 40 degree horizontal fov), 32x32
 * per view side by side, in three modes: silhouette mask with 4x4 samples,
 * SH irradiance (coefficients projected from a synthetic sky) with 2x2
 * samples, Lambert with two lights and position-derived vertex colours with
 * 1 sample. Compared at zero tolerance: the exact bits of the ls_real output
 * (a digest in fixtures/render/digests.txt, one per ls_real) and the 16-bit PNG
 * (fixtures/render/bunny_MODE_REAL.png, decoded and compared sample by sample).
 * LS_UPDATE_GOLDENS=1 rewrites them (see fixtures/render/README.md). */

static int load_obj_r(const char *path, ls_real **v, uint32_t **f, uint32_t *nv, uint32_t *nf)
{
    FILE *fp = fopen(path, "r");
    char line[512];
    uint32_t cv = 0, cf = 0;
    if (fp == NULL) return 0;
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') cv++;
        if (line[0] == 'f' && line[1] == ' ') cf++;
    }
    *v = (ls_real *)malloc(3 * (size_t)cv * sizeof(ls_real));
    *f = (uint32_t *)malloc(3 * (size_t)cf * sizeof(uint32_t));
    *nv = *nf = 0;
    rewind(fp);
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') {
            double a, b, c;
            if (sscanf(line + 2, "%lf %lf %lf", &a, &b, &c) == 3) {
                ls_real *p = *v + 3 * (size_t)*nv;
                p[0] = (ls_real)a;
                p[1] = (ls_real)b;
                p[2] = (ls_real)c;
                (*nv)++;
            }
        } else if (line[0] == 'f' && line[1] == ' ') {
            unsigned a, b, c;
            if (sscanf(line + 2, "%u %u %u", &a, &b, &c) == 3) {
                uint32_t *q = *f + 3 * (size_t)*nf;
                q[0] = a - 1;
                q[1] = b - 1;
                q[2] = c - 1;
                (*nf)++;
            }
        }
    }
    fclose(fp);
    return *nv == cv && *nf == cf && cv > 0;
}

static unsigned char *read_all(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    unsigned char *d;
    long len;
    if (fp == NULL) return NULL;
    fseek(fp, 0, SEEK_END);
    len = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    d = (unsigned char *)malloc((size_t)len + 1);
    *n = fread(d, 1, (size_t)len, fp);
    fclose(fp);
    return d;
}

static int32_t write_file_cb(void *user, const void *data, size_t bytes)
{
    return fwrite(data, 1, bytes, (FILE *)user) == bytes ? 0 : 1;
}

#define GV 32u /* pixels per view side */
#define GN 3u  /* views */

static void golden_renders(void)
{
    static const char *names[3] = {"mask", "sh", "lambert"};
    static const uint32_t sss[3] = {4, 2, 1};
    const char *real = LS_REAL_IS_FLOAT ? "float" : "double";
    int update = getenv("LS_UPDATE_GOLDENS") != NULL && getenv("LS_UPDATE_GOLDENS")[0] == '1';
    const char *fresh_dir = getenv("LS_GOLDEN_OUT");
    ls_real *pos = NULL, *nrm, *col, dirs[3 * GN], lo[3], hi[3], center[3], proj[16], sky[3 * 32 * 16], sh[27];
    uint32_t *f = NULL, nv, nf, i, m, view;
    size_t mem_bytes = (size_t)1 << 24;
    void *mem = malloc(mem_bytes);
    ls_arena a;
    ls_light lights[2] = {{{(ls_real)0.6, (ls_real)0.64, (ls_real)0.48}, {1, (ls_real)0.9, (ls_real)0.8}},
                          {{(ls_real)-0.8, 0, (ls_real)-0.6}, {(ls_real)0.2, (ls_real)0.25, (ls_real)0.4}}};
    FILE *digests_out = NULL;
    char *digests = NULL;
    size_t digests_len = 0;
    REQUIRE(load_obj_r("fixtures/meshes/bunny.obj", &pos, &f, &nv, &nf) ||
            load_obj_r("../shared/meshes/bunny.obj", &pos, &f, &nv, &nf));
    nrm = (ls_real *)malloc(3 * (size_t)nv * sizeof(ls_real));
    col = (ls_real *)malloc(3 * (size_t)nv * sizeof(ls_real));
    REQUIRE(ls_shade_vertex_normals(pos, nv, f, nf, nrm, NULL) == LS_OK);
    for (i = 0; i < 3; i++) lo[i] = hi[i] = pos[i];
    for (i = 0; i < 3 * nv; i++) {
        if (pos[i] < lo[i % 3]) lo[i % 3] = pos[i];
        if (pos[i] > hi[i % 3]) hi[i % 3] = pos[i];
    }
    for (i = 0; i < 3; i++) center[i] = (lo[i] + hi[i]) * (ls_real)0.5;
    for (i = 0; i < 3 * nv; i++) col[i] = (ls_real)0.25 + (ls_real)0.75 * (pos[i] - lo[i % 3]) / (hi[i % 3] - lo[i % 3]);
    /* a sky: bright above, warm horizon, dark ground (arithmetic only) */
    for (i = 0; i < 32 * 16; i++) {
        ls_real t = (ls_real)(i / 32) / (ls_real)15; /* 0 top .. 1 bottom */
        sky[3 * i] = t < (ls_real)0.5 ? (ls_real)0.6 + t : (ls_real)0.3;
        sky[3 * i + 1] = t < (ls_real)0.5 ? (ls_real)0.7 + (ls_real)0.2 * t : (ls_real)0.25;
        sky[3 * i + 2] = t < (ls_real)0.5 ? (ls_real)1 - (ls_real)0.6 * t : (ls_real)0.2 + (ls_real)0.01 * (ls_real)(i % 32);
    }
    REQUIRE(ls_sh_from_equirect(sky, 32, 16, sh) == LS_OK);
    REQUIRE(ls_camera_fibonacci_dirs(GN, dirs) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.6981317007977318, LS_FOV_X, 1, 1, 100, proj) == LS_OK);
    if (update) {
        digests_out = fopen("fixtures/render/digests.txt.new", "w");
        REQUIRE(digests_out != NULL);
    } else {
        char *d = (char *)read_all("fixtures/render/digests.txt", &digests_len);
        REQUIRE(d != NULL);
        digests = (char *)realloc(d, digests_len + 1);
        digests[digests_len] = 0;
    }
    for (m = 0; m < 3; m++) {
        ls_image strip;
        uint64_t h = TEST_HASH_SEED;
        ls_shade_opts o;
        char path[128], want[128];
        ls_real out[4 * GV * GV];
        REQUIRE(ls_arena_init(&a, mem, mem_bytes) == LS_OK);
        REQUIRE(ls_image_create(&strip, GN * GV, GV, &a) == LS_OK);
        for (view = 0; view < GN; view++) {
            ls_vis vis;
            ls_real v[16], mvp[16];
            ls_arena_mark mk = ls_arena_save(&a);
            uint32_t x, y;
            REQUIRE(ls_camera_orbit(center, 25, dirs + 3 * view, v) == LS_OK);
            ls_mat4_mul(proj, v, mvp);
            REQUIRE(ls_vis_init(&vis, &a, GV, GV, sss[m], nv) == LS_OK);
            REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = f, .triangle_count = nf, .vertex_count = nv,
                    .mvp = mvp}, &a, NULL) == LS_OK);
            ls_shade_opts_init(&o);
            o.mode = m == 0 ? LS_SHADE_MASK : m == 1 ? LS_SHADE_SH : LS_SHADE_LAMBERT;
            o.sh = sh;
            o.lights = lights;
            o.light_count = 2;
            o.ambient[0] = o.ambient[1] = o.ambient[2] = (ls_real)0.05;
            o.vertex_colors = m == 2 ? col : NULL;
            o.background[0] = (ls_real)0.1;
            o.background[1] = (ls_real)0.1;
            o.background[2] = (ls_real)0.15;
            REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = f, .triangle_count = nf, .vertex_count = nv,
                    .normals = nrm, .opts = &o}, out, NULL) == LS_OK);
            h = test_hash_reals(out, sizeof out / sizeof out[0], h);
            for (y = 0; y < GV; y++)
                for (x = 0; x < GV; x++)
                    for (i = 0; i < 4; i++)
                        strip.pixels[4 * ((size_t)y * GN * GV + view * GV + x) + i] = (float)out[4 * (y * GV + x) + i];
            ls_arena_restore(&a, mk);
        }
        snprintf(want, sizeof want, "%s %s %016llx", names[m], real, (unsigned long long)h);
        snprintf(path, sizeof path, "fixtures/render/bunny_%s_%s.png", names[m], real);
        if (fresh_dir != NULL) {
            /* LS_GOLDEN_OUT=DIR: also write this run's strip (tests/stage_images.sh
             * compares it with the golden using OpenImageIO's idiff) */
            char fresh[512];
            ls_image_format fmt = {LS_IMAGE_PNG, 4, 16, 0};
            FILE *fp;
            snprintf(fresh, sizeof fresh, "%s/bunny_%s_%s.png", fresh_dir, names[m], real);
            fp = fopen(fresh, "wb");
            CHECK_MSG(fp != NULL, "cannot write %s", fresh);
            if (fp != NULL) {
                CHECK_STATUS(ls_image_encode(&strip, &fmt, write_file_cb, fp, &a), LS_OK);
                CHECK(fclose(fp) == 0);
            }
        }
        if (update) {
            ls_image_format fmt = {LS_IMAGE_PNG, 4, 16, 0};
            FILE *fp = fopen(path, "wb");
            REQUIRE(fp != NULL);
            CHECK_STATUS(ls_image_encode(&strip, &fmt, write_file_cb, fp, &a), LS_OK);
            fclose(fp);
            fprintf(digests_out, "%s\n", want);
            printf("     wrote %s (%s)\n", path, want);
        } else {
            size_t n = 0, k, bad = 0;
            unsigned char *file = read_all(path, &n);
            ls_image gold;
            uint16_t *q1 = (uint16_t *)malloc(GN * GV * GV * 4 * 2), *q2 = (uint16_t *)malloc(GN * GV * GV * 4 * 2);
            CHECK_MSG(strstr(digests, want) != NULL, "render digest differs: %s not in fixtures/render/digests.txt", want);
            CHECK_MSG(file != NULL, "missing golden %s", path);
            if (file != NULL) {
                CHECK_STATUS(ls_image_decode(file, n, &gold, &a, NULL), LS_OK);
                CHECK(gold.width == strip.width && gold.height == strip.height);
                if (gold.width == strip.width && gold.height == strip.height) {
                    ls_image_to_unorm(&strip, 4, 16, q1, GN * GV * GV * 4 * 2);
                    ls_image_to_unorm(&gold, 4, 16, q2, GN * GV * GV * 4 * 2);
                    for (k = 0; k < GN * GV * GV * 4; k++) bad += q1[k] != q2[k];
                    CHECK_MSG(bad == 0, "%s: %lu of %u samples differ", path, (unsigned long)bad, GN * GV * GV * 4);
                }
                free(file);
            }
            free(q1);
            free(q2);
        }
    }
    if (digests_out) fclose(digests_out);
    free(digests);
    free(pos);
    free(f);
    free(nrm);
    free(col);
    free(mem);
}

int main(void)
{
    TEST_INIT("test_shade");
    TEST_RUN(sh_eval_matches_matrix_form);
    TEST_RUN(sh_projection_gives_known_irradiance);
    TEST_RUN(shade_matches_interpolated_reference);
    TEST_RUN(box_resolve_and_coverage);
    TEST_RUN(vertex_normals_of_an_octahedron);
    TEST_RUN(env_background_follows_the_rays);
    TEST_RUN(golden_renders);
    return TEST_END();
}
