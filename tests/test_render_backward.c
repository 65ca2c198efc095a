/* tests/test_render_backward.c - the interior-shading backward against
 * central finite differences of an independent float64 forward.
 *
 * The reference forward keeps the triangle id of every sample fixed (taken
 * from ls_raster at the unperturbed positions: no gradient flows through the
 * discrete id) and recomputes everything else in double from the positions:
 * clip coordinates, screen-space affine barycentrics of the projected
 * vertices made perspective-correct with 1/W (a different formula from the
 * library's 2D homogeneous one), uniform-weight vertex normals, the SH matrix
 * form n_h^T M n_h, Lambert, vertex colours, and the box mean of the samples.
 * The probe is L = sum_p sum_c w_pc I_pc with random weights (alpha too: it
 * must get no interior gradient). */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/camera.h>
#include <largesteps/render_backward.h>

#define TEST_PI 3.14159265358979323846
#define MAXV 16
#define MAXT 16
#define IMG 20
#define SS 2

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double rnd(void) /* uniform in [0, 1) */
{
    return test_rng_unit(&rng_state);
}

typedef struct scene {
    uint32_t nv, nt;
    double p[3 * MAXV];
    uint32_t f[3 * MAXT];
    double mvp[16];
    double col[3 * MAXV];
    ls_shade_opts opts; /* mode and parameters (pointers into the statics below) */
    uint32_t tri[IMG * SS * IMG * SS]; /* fixed ids of the base configuration */
    double w[4 * IMG * IMG];
    uint32_t clipped; /* triangles the rasterizer clipped */
} scene;

static ls_real sh_coef[27];
static ls_light lights[2];
static ls_real colors_r[3 * MAXV];

/* ---- the independent float64 forward ---- */

static void ref_normals(const scene *sc, const double *p, double *nrm)
{
    uint32_t t, v;
    int k;
    for (v = 0; v < 3 * sc->nv; v++) nrm[v] = 0;
    for (t = 0; t < sc->nt; t++) {
        const double *a = p + 3 * sc->f[3 * t], *b = p + 3 * sc->f[3 * t + 1], *c = p + 3 * sc->f[3 * t + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (l == 0) continue;
        for (k = 0; k < 3; k++) {
            nrm[3 * sc->f[3 * t] + k] += n[k] / l;
            nrm[3 * sc->f[3 * t + 1] + k] += n[k] / l;
            nrm[3 * sc->f[3 * t + 2] + k] += n[k] / l;
        }
    }
    for (v = 0; v < sc->nv; v++) {
        double l = sqrt(nrm[3 * v] * nrm[3 * v] + nrm[3 * v + 1] * nrm[3 * v + 1] + nrm[3 * v + 2] * nrm[3 * v + 2]);
        for (k = 0; k < 3; k++) nrm[3 * v + k] = l > 0 ? nrm[3 * v + k] / l : 0;
    }
}

static double ref_sh(const ls_real *shc, const double n[3])
{
    const double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    double L[9], M[4][4], nh[4] = {n[0], n[1], n[2], 1}, e = 0;
    int r, c;
    for (r = 0; r < 9; r++) L[r] = (double)shc[r];
    M[0][0] = c1 * L[8];  M[0][1] = c1 * L[4];  M[0][2] = c1 * L[7]; M[0][3] = c2 * L[3];
    M[1][0] = c1 * L[4];  M[1][1] = -c1 * L[8]; M[1][2] = c1 * L[5]; M[1][3] = c2 * L[1];
    M[2][0] = c1 * L[7];  M[2][1] = c1 * L[5];  M[2][2] = c3 * L[6]; M[2][3] = c2 * L[2];
    M[3][0] = c2 * L[3];  M[3][1] = c2 * L[1];  M[3][2] = c2 * L[2]; M[3][3] = c4 * L[0] - c5 * L[6];
    for (r = 0; r < 4; r++)
        for (c = 0; c < 4; c++) e += nh[r] * M[r][c] * nh[c];
    return e / TEST_PI;
}

/* L = sum w I over RGB of the box-resolved image, ids fixed. */
static double ref_loss(const scene *sc, const double *p, const double *col)
{
    double clip[4 * MAXV], nrm[3 * MAXV], L = 0;
    const ls_shade_opts *o = &sc->opts;
    uint32_t v, sx, sy;
    int r, c, k;
    for (v = 0; v < sc->nv; v++)
        for (r = 0; r < 4; r++)
            clip[4 * v + r] = sc->mvp[4 * r] * p[3 * v] + sc->mvp[4 * r + 1] * p[3 * v + 1] +
                              sc->mvp[4 * r + 2] * p[3 * v + 2] + sc->mvp[4 * r + 3];
    ref_normals(sc, p, nrm);
    for (sy = 0; sy < IMG * SS; sy++)
        for (sx = 0; sx < IMG * SS; sx++) {
            uint32_t id = sc->tri[sy * IMG * SS + sx], pix = (sy / SS) * IMG + sx / SS;
            double px = (2.0 * sx + 1) / (IMG * SS) - 1, py = 1 - (2.0 * sy + 1) / (IMG * SS);
            double X[3], Y[3], lam[3], b[3], sum = 0, rgb[3], alb[3] = {1, 1, 1};
            const uint32_t *f;
            if (id == 0) continue; /* background: constant */
            f = sc->f + 3 * (id - 1);
            for (k = 0; k < 3; k++) {
                X[k] = clip[4 * f[k]] / clip[4 * f[k] + 3];
                Y[k] = clip[4 * f[k] + 1] / clip[4 * f[k] + 3];
            }
            for (k = 0; k < 3; k++) {
                int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
                lam[k] = (X[k1] - px) * (Y[k2] - py) - (X[k2] - px) * (Y[k1] - py);
                b[k] = lam[k] / clip[4 * f[k] + 3];
                sum += b[k];
            }
            for (k = 0; k < 3; k++) b[k] /= sum;
            if (o->vertex_colors != NULL)
                for (c = 0; c < 3; c++) alb[c] = b[0] * col[3 * f[0] + c] + b[1] * col[3 * f[1] + c] + b[2] * col[3 * f[2] + c];
            if (o->mode == LS_SHADE_COLOR) {
                for (c = 0; c < 3; c++) rgb[c] = alb[c];
            } else {
                double n[3];
                for (c = 0; c < 3; c++) n[c] = b[0] * nrm[3 * f[0] + c] + b[1] * nrm[3 * f[1] + c] + b[2] * nrm[3 * f[2] + c];
                if (o->renormalize) {
                    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                    for (c = 0; c < 3; c++) n[c] /= l;
                }
                if (o->mode == LS_SHADE_SH) {
                    for (c = 0; c < 3; c++) rgb[c] = ref_sh(o->sh + 9 * c, n);
                } else {
                    uint32_t l;
                    for (c = 0; c < 3; c++) rgb[c] = (double)o->ambient[c];
                    for (l = 0; l < o->light_count; l++) {
                        double d = n[0] * (double)o->lights[l].dir[0] + n[1] * (double)o->lights[l].dir[1] +
                                   n[2] * (double)o->lights[l].dir[2];
                        if (d > 0)
                            for (c = 0; c < 3; c++) rgb[c] += d * (double)o->lights[l].rgb[c];
                    }
                }
                for (c = 0; c < 3; c++) rgb[c] *= alb[c];
            }
            for (c = 0; c < 3; c++) L += sc->w[4 * pix + c] * rgb[c] / (SS * SS);
        }
    return L;
}

/* ---- scenes ---- */

static void set_camera(scene *sc, double dist, double nearp)
{
    ls_real view[16], proj[16], mvp[16], eye[3], tgt[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    int k;
    eye[0] = (ls_real)(0.3 * dist);
    eye[1] = (ls_real)(0.4 * dist);
    eye[2] = (ls_real)(0.866 * dist);
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_perspective((ls_real)0.9, LS_FOV_Y, (ls_real)1, (ls_real)nearp, (ls_real)50, proj);
    ls_mat4_mul(proj, view, mvp);
    for (k = 0; k < 16; k++) sc->mvp[k] = (double)mvp[k];
}

/* A perturbed octahedron: closed, shared vertex normals. */
static void scene_octahedron(scene *sc)
{
    static const int oct_f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    static const double oct_p[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    uint32_t v, t;
    int k;
    memset(sc, 0, sizeof *sc);
    sc->nv = 6;
    sc->nt = 8;
    for (v = 0; v < 6; v++)
        for (k = 0; k < 3; k++) sc->p[3 * v + k] = oct_p[v][k] * (1 + 0.15 * (rnd() - 0.5)) + 0.1 * (rnd() - 0.5);
    for (t = 0; t < 8; t++)
        for (k = 0; k < 3; k++) sc->f[3 * t + k] = (uint32_t)oct_f[t][k];
    set_camera(sc, 3.2, 0.5);
}

/* Two triangles sharing an edge, one vertex behind the camera (near clipping). */
static void scene_near(scene *sc)
{
    memset(sc, 0, sizeof *sc);
    set_camera(sc, 3.0, 1.0);
    sc->nv = 4;
    sc->nt = 2;
    /* eye at about (0.9, 1.2, 2.6): vertex 3 lies behind it */
    sc->p[0] = -0.8; sc->p[1] = -0.6; sc->p[2] = 0.1;
    sc->p[3] = 0.7;  sc->p[4] = -0.5; sc->p[5] = -0.2;
    sc->p[6] = 0.1;  sc->p[7] = 0.7;  sc->p[8] = 0.0;
    sc->p[9] = 1.3;  sc->p[10] = 1.8; sc->p[11] = 4.0;
    sc->f[0] = 0; sc->f[1] = 1; sc->f[2] = 2;
    sc->f[3] = 1; sc->f[4] = 3; sc->f[5] = 2;
}

static void setup_shading(scene *sc, uint32_t mode, int renorm, int with_colors)
{
    int k;
    uint32_t v;
    ls_shade_opts_init(&sc->opts);
    sc->opts.mode = mode;
    sc->opts.renormalize = (uint32_t)renorm;
    for (k = 0; k < 27; k++) sh_coef[k] = (ls_real)(0.8 * (rnd() - 0.3));
    sc->opts.sh = sh_coef;
    lights[0].dir[0] = (ls_real)0.48; lights[0].dir[1] = (ls_real)0.6; lights[0].dir[2] = (ls_real)0.64;
    lights[1].dir[0] = (ls_real)-0.6; lights[1].dir[1] = (ls_real)0.0; lights[1].dir[2] = (ls_real)0.8;
    for (k = 0; k < 3; k++) {
        lights[0].rgb[k] = (ls_real)(0.5 + 0.2 * k);
        lights[1].rgb[k] = (ls_real)(0.9 - 0.3 * k);
        sc->opts.ambient[k] = (ls_real)0.1;
        sc->opts.background[k] = (ls_real)0.25;
    }
    sc->opts.lights = lights;
    sc->opts.light_count = 2;
    for (v = 0; v < sc->nv; v++)
        for (k = 0; k < 3; k++) {
            sc->col[3 * v + k] = (double)(ls_real)(0.2 + 0.7 * rnd());
            colors_r[3 * v + k] = (ls_real)sc->col[3 * v + k];
        }
    sc->opts.vertex_colors = with_colors || mode == LS_SHADE_COLOR ? colors_r : NULL;
}

static unsigned char *arena_buf;
#define ARENA_BYTES (4u << 20)

/* Runs the library forward (ids) and backward; returns 0 on failure. */
static int lib_backward(scene *sc, ls_real *gp, ls_real *gcol, ls_real *image_out)
{
    ls_arena arena;
    ls_vis vis;
    ls_real pos[3 * MAXV], mvp[16], nrm[3 * MAXV], gn[3 * MAXV], gimg[4 * IMG * IMG];
    static ls_real img[4 * IMG * IMG];
    uint32_t i;
    if (ls_arena_init(&arena, arena_buf, ARENA_BYTES) != LS_OK) return 0;
    for (i = 0; i < 3 * sc->nv; i++) pos[i] = (ls_real)sc->p[i];
    for (i = 0; i < 16; i++) mvp[i] = (ls_real)sc->mvp[i];
    if (ls_vis_init(&vis, &arena, IMG, IMG, SS, MAXV) != LS_OK) return 0;
    if (ls_raster(&vis, &(ls_view){.positions = pos, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
            .mvp = mvp}, &arena, NULL) != LS_OK) return 0;
    memcpy(sc->tri, vis.tri, sizeof sc->tri);
    sc->clipped = vis.clipped_triangles;
    if (ls_shade_vertex_normals(pos, sc->nv, sc->f, sc->nt, nrm, NULL) != LS_OK) return 0;
    if (ls_shade(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
            .normals = nrm, .opts = &sc->opts}, img, NULL) != LS_OK) return 0;
    if (image_out != NULL) memcpy(image_out, img, sizeof img);
    for (i = 0; i < 4 * IMG * IMG; i++) gimg[i] = (ls_real)sc->w[i];
    for (i = 0; i < 3 * sc->nv; i++) gp[i] = gn[i] = gcol[i] = 0;
    if (ls_shade_backward(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
            .normals = nrm, .opts = &sc->opts, .mvp = mvp}, gimg, gp, gn, gcol, NULL) != LS_OK)
        return 0;
    if (ls_vertex_normals_backward(pos, sc->nv, sc->f, sc->nt, gn, gp, &arena, NULL) != LS_OK) return 0;
    return 1;
}

typedef struct fdstats {
    int n;
    double max_rel, floor;
} fdstats;

/* Compares every position (and colour) component with central differences. */
static fdstats fd_compare(scene *sc, const char *name)
{
    ls_real gp[3 * MAXV], gcol[3 * MAXV];
    double fd[3 * MAXV], fdc[3 * MAXV], maxfd = 0, maxfdc = 0, h = 1e-6;
    fdstats st = {0, 0, 0};
    uint32_t i, covered = 0;
    int ok = lib_backward(sc, gp, gcol, NULL);
    CHECK_MSG(ok, "%s: library forward/backward failed", name);
    if (!ok) return st;
    for (i = 0; i < (uint32_t)(IMG * SS * IMG * SS); i++) covered += sc->tri[i] != 0;
    CHECK_MSG(covered > 200, "%s: only %u covered samples", name, covered);
    if (strncmp(name, "near", 4) == 0) CHECK_MSG(sc->clipped > 0, "%s: nothing was clipped", name);
    for (i = 0; i < 3 * sc->nv; i++) {
        double save = sc->p[i], lp, lm;
        sc->p[i] = save + h;
        lp = ref_loss(sc, sc->p, sc->col);
        sc->p[i] = save - h;
        lm = ref_loss(sc, sc->p, sc->col);
        sc->p[i] = save;
        fd[i] = (lp - lm) / (2 * h);
        if (fabs(fd[i]) > maxfd) maxfd = fabs(fd[i]);
        if (sc->opts.vertex_colors != NULL) {
            save = sc->col[i];
            sc->col[i] = save + h;
            lp = ref_loss(sc, sc->p, sc->col);
            sc->col[i] = save - h;
            lm = ref_loss(sc, sc->p, sc->col);
            sc->col[i] = save;
            fdc[i] = (lp - lm) / (2 * h);
            if (fabs(fdc[i]) > maxfdc) maxfdc = fabs(fdc[i]);
        }
    }
    /* absolute floor: a fraction of the largest component */
    st.floor = (sizeof(ls_real) == 4 ? 1e-4 : 1e-7) * maxfd;
    for (i = 0; i < 3 * sc->nv; i++) {
        double e = fabs((double)gp[i] - fd[i]) / fmax(fabs(fd[i]), st.floor);
        CHECK_MSG(isfinite((double)gp[i]), "%s: non-finite gradient %u", name, i);
        if (e > st.max_rel) st.max_rel = e;
        st.n++;
        if (sc->opts.vertex_colors != NULL) {
            e = fabs((double)gcol[i] - fdc[i]) / fmax(fabs(fdc[i]), 1e-7 * maxfdc);
            if (e > st.max_rel) st.max_rel = e;
            st.n++;
        }
    }
    printf("     %-28s %3d components, max relative error %.3g (abs floor %.3g, max |dL/dp| %.3g)\n", name, st.n,
           st.max_rel, st.floor, maxfd);
    return st;
}

static double tol(void) { return sizeof(ls_real) == 4 ? 1e-3 : 1e-6; }

static void run_modes(void (*make)(scene *), const char *scene_name)
{
    static scene sc;
    static const struct { uint32_t mode; int renorm, colors; const char *name; } modes[] = {
        {LS_SHADE_SH, 0, 0, "SH"},
        {LS_SHADE_SH, 1, 0, "SH renormalised"},
        {LS_SHADE_SH, 0, 1, "SH + vertex colours"},
        {LS_SHADE_LAMBERT, 0, 0, "Lambert"},
        {LS_SHADE_LAMBERT, 1, 1, "Lambert renorm + colours"},
        {LS_SHADE_COLOR, 0, 1, "vertex colours"},
    };
    unsigned m;
    uint32_t i;
    char name[64];
    for (m = 0; m < sizeof modes / sizeof modes[0]; m++) {
        fdstats st;
        make(&sc);
        setup_shading(&sc, modes[m].mode, modes[m].renorm, modes[m].colors);
        for (i = 0; i < 4 * IMG * IMG; i++) sc.w[i] = (double)(ls_real)(2 * rnd() - 1);
        snprintf(name, sizeof name, "%s/%s", scene_name, modes[m].name);
        st = fd_compare(&sc, name);
        CHECK_MSG(st.n > 0 && st.max_rel <= tol(), "%s: max relative error %.3g > %.3g", name, st.max_rel, tol());
    }
}

static void backward_octahedron_fd(void) { run_modes(scene_octahedron, "octahedron"); }
static void backward_near_clip_fd(void) { run_modes(scene_near, "near-clipped"); }

/* The same inputs give the same bits; the mask mode and alpha give nothing. */
static void backward_deterministic(void)
{
    static scene sc;
    ls_real g1[3 * MAXV], g2[3 * MAXV], c1[3 * MAXV], c2[3 * MAXV];
    uint32_t i;
    scene_octahedron(&sc);
    setup_shading(&sc, LS_SHADE_SH, 1, 1);
    for (i = 0; i < 4 * IMG * IMG; i++) sc.w[i] = rnd() - 0.5;
    REQUIRE(lib_backward(&sc, g1, c1, NULL));
    REQUIRE(lib_backward(&sc, g2, c2, NULL));
    CHECK(memcmp(g1, g2, 3 * sc.nv * sizeof g1[0]) == 0);
    CHECK(memcmp(c1, c2, 3 * sc.nv * sizeof c1[0]) == 0);
    /* only alpha weights: no interior gradient */
    for (i = 0; i < 4 * IMG * IMG; i++)
        if (i % 4 != 3) sc.w[i] = 0;
    REQUIRE(lib_backward(&sc, g1, c1, NULL));
    for (i = 0; i < 3 * sc.nv; i++) CHECK(g1[i] == 0 && c1[i] == 0);
    setup_shading(&sc, LS_SHADE_MASK, 0, 0);
    for (i = 0; i < 4 * IMG * IMG; i++) sc.w[i] = 1;
    REQUIRE(lib_backward(&sc, g1, c1, NULL));
    for (i = 0; i < 3 * sc.nv; i++) CHECK(g1[i] == 0);
}

/* ls_vertex_normals_backward alone: FD of sum G . N(p) for random G, and the arena sweep. */
typedef struct vn_ctx {
    ls_real pos[3 * MAXV], gn[3 * MAXV], gp[3 * MAXV];
    uint32_t f[3 * MAXT], nv, nt;
} vn_ctx;

static ls_status vn_run(void *ctx, ls_arena *arena)
{
    vn_ctx *c = (vn_ctx *)ctx;
    return ls_vertex_normals_backward(c->pos, c->nv, c->f, c->nt, c->gn, c->gp, arena, NULL);
}
static uint64_t vn_hash(void *ctx)
{
    vn_ctx *c = (vn_ctx *)ctx;
    return test_hash(c, sizeof *c, 1469598103934665603ull);
}
static void vn_reset(void *ctx)
{
    vn_ctx *c = (vn_ctx *)ctx;
    memset(c->gp, 0, sizeof c->gp);
}

static void vertex_normals_backward_fd_and_sweep(void)
{
    static scene sc;
    static vn_ctx c;
    double nrm[3 * MAXV], maxrel = 0, maxfd = 0, fd[3 * MAXV], h = 1e-6;
    uint32_t i;
    size_t bytes = 0;
    ls_diag diag;
    sweep_job job;
    scene_octahedron(&sc);
    c.nv = sc.nv;
    c.nt = sc.nt;
    memcpy(c.f, sc.f, sizeof c.f);
    for (i = 0; i < 3 * sc.nv; i++) {
        c.pos[i] = (ls_real)sc.p[i];
        sc.p[i] = (double)c.pos[i];
        c.gn[i] = (ls_real)(rnd() - 0.5);
        c.gp[i] = 0;
    }
    for (i = 0; i < 3 * sc.nv; i++) {
        double save = sc.p[i], s = 0;
        uint32_t j;
        sc.p[i] = save + h;
        ref_normals(&sc, sc.p, nrm);
        for (j = 0; j < 3 * sc.nv; j++) s += (double)c.gn[j] * nrm[j];
        sc.p[i] = save - h;
        ref_normals(&sc, sc.p, nrm);
        for (j = 0; j < 3 * sc.nv; j++) s -= (double)c.gn[j] * nrm[j];
        sc.p[i] = save;
        fd[i] = s / (2 * h);
        if (fabs(fd[i]) > maxfd) maxfd = fabs(fd[i]);
    }
    CHECK_STATUS(ls_vertex_normals_backward_bytes(c.nv, &bytes), LS_OK);
    job.name = "vertex_normals_backward";
    job.run = vn_run;
    job.state_hash = vn_hash;
    job.reset = vn_reset;
    job.ctx = &c;
    job.answer = bytes;
    job.exact = 1;
    job.quiet = 0;
    CHECK_EQ(sweep_arena(&job), 0);
    {
        ls_arena arena;
        REQUIRE(ls_arena_init(&arena, arena_buf, ARENA_BYTES) == LS_OK);
        CHECK_STATUS(vn_run(&c, &arena), LS_OK);
        for (i = 0; i < 3 * sc.nv; i++) {
            double e = fabs((double)c.gp[i] - fd[i]) / fmax(fabs(fd[i]), 1e-7 * maxfd);
            if (e > maxrel) maxrel = e;
        }
        printf("     vertex normals: %u components, max relative error %.3g (abs floor %.3g)\n", 3 * sc.nv, maxrel,
               1e-7 * maxfd);
        CHECK_MSG(maxrel <= (sizeof(ls_real) == 4 ? 1e-3 : 1e-6), "max relative error %.3g", maxrel);
        c.f[4] = 99;
        CHECK_STATUS(ls_vertex_normals_backward(c.pos, c.nv, c.f, c.nt, c.gn, c.gp, &arena, &diag), LS_ERR_MESH);
        CHECK_EQ(diag.index, 1);
        CHECK_STATUS(ls_vertex_normals_backward(c.pos, c.nv, c.f, c.nt, c.gn, c.gp, NULL, NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_vertex_normals_backward(c.pos, c.nv, c.f, c.nt, c.gn, c.gp, NULL, &diag), LS_ERR_INVALID);
        CHECK(strcmp(diag.what, "arena is NULL") == 0);
        CHECK_EQ(arena.bottom + arena.top, 0);
    }
}

int main(void)
{
    TEST_INIT("test_render_backward");
    arena_buf = (unsigned char *)malloc(ARENA_BYTES);
    if (arena_buf == NULL) return 1;
    TEST_RUN(vertex_normals_backward_fd_and_sweep);
    TEST_RUN(backward_octahedron_fd);
    TEST_RUN(backward_near_clip_fd);
    TEST_RUN(backward_deterministic);
    free(arena_buf);
    return TEST_END();
}
