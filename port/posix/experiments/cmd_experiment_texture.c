/* cmd_experiment_texture.c - `largesteps experiment texture [options] -o DIR`:
 * texture reconstruction from renders (the paper's texture figure).
 *
 * Target: a photo-like image read from a PNG (default: the "softwaves"
 * wallpaper of Debian's desktop-base package,
 * /usr/share/desktop-base/softwaves-theme/grub/grub-16x9.png, 1920 x 1080,
 * GPL-2+, (c) 2014-2022 Juliette Taka Belin), its centre square cropped to
 * 1024 x 1024 (point-sampled from the crop when --image is smaller).
 * Scene: a textured quad (UVs over the whole texture, clamp) or, with
 * --scene sphere, a UV sphere (longitude seam duplicated, u repeats), seen
 * from --views training views plus 2 validation views (for tuning) and 4
 * held-out test views, --res x --res pixels (default 108), unlit.
 *
 * Renders. Target renders, and every render used for an error figure, use
 * 4 x 4 samples per pixel with a box resolve (the full-resolution texture
 * supersampled: the target is filtered to the pixel footprint). The fit
 * renders the same way by default (--fit-ss 4): a pixel of a 108^2 view
 * covers about 8 x 8 texels of the 1024^2 texture, and one bilinear lookup
 * per pixel (--fit-ss 1) would see 4 of them and could not reproduce a
 * box-filtered target (the data then conflict between views, and the
 * comparison measures how each method regularizes aliasing).
 * --targets fit renders the training targets with the fit's own sampling.
 *
 * Methods, each on the texels x (n x 3, n = side^2), starting from grey 0.5,
 * L = mean over training pixels and RGB of (I - I*)^2:
 *   naive        Adam on x;
 *   regularized  Adam on L + w tr(x^T Lg x), Lg the 4-neighbour grid Laplacian;
 *   large steps  u = (I + lambda Lg) x, UniformAdam on u (ls_param on Lg),
 *                applied to x directly (ls_param_adjoint2 gives M^-1 g and
 *                M^-2 g, ls_optim_step_mapped steps x = M^-1 u): one forward
 *                and two inverse grid transforms per iteration instead of
 *                the four of adjoint + from_differential.
 * Each is tuned on a small grid (learning rate; w or lambda) by the PSNR of
 * the 2 validation views after a short run, then run for the same time
 * (process CPU time of the iterations: the machine may be shared; the
 * large-steps setup, ls_param_grid_init with the grid's transform solver,
 * is timed and reported apart).
 * Errors: PSNR of the 4 held-out views (covered pixels), and PSNR of the
 * fitted texture against the target texture, both box-filtered to the
 * render's footprint (blocks of f x f texels, f the power of two nearest
 * side / (quad side in pixels in the front view)).
 *
 * Outputs: DIR/texture.md (the table, also printed) and DIR/texture.png
 * (target texture | target render | naive | regularized | large steps; each
 * texture shown box-filtered to the tile, the render magnified x2).
 * Default sizes keep the run under ~2 minutes (texture 256^2, 2 s tuning and
 * 12 s final runs); --full is the acceptance run (texture 1024^2).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <errno.h>
#include <unistd.h>
#include "ls_posix.h"
#include "args.h"

#define TX_CMD "experiment texture"
#include "commands.h"

#define TX_DEFAULT_IMAGE "/usr/share/desktop-base/softwaves-theme/grub/grub-16x9.png"
#define TX_SS_TARGET 4u
#define TX_VAL 2u
#define TX_TEST 4u
#define TX_MAX_VIEWS 64u
#define TX_RES_HI 512u /* default of --res-hi: the held-out views again at 512^2, detail the training resolution cannot show */

#define TX_GRID_MAX 8u
#define M_NAIVE 0
#define M_REG 1
#define M_LS 2

/* A tuning grid: up to TX_GRID_MAX values (n = 0: the method's default). */
typedef struct tx_grid {
    double v[TX_GRID_MAX];
    uint32_t n;
} tx_grid;

typedef struct tx_args {
    const char *out, *image, *scene;
    uint32_t res, res_hi, views, side, full, fit_ss, own_targets, ls_adam;
    double tune_s, run_s;
    uint32_t methods;                   /* bit m: run method m */
    tx_grid lr[3], weight[3];           /* per method; weight: w (regularized) or lambda (large steps) */
} tx_args;

/* Geometry, UVs and the views (vis buffers of the fit and the targets). */
typedef struct tx_problem {
    uint32_t nv, nt, wrap, side, res, ntrain, nviews;
    ls_real *pos, *uv, *nrm;
    uint32_t *idx;
    ls_real mvp[TX_MAX_VIEWS][16];
    ls_vis vis1[TX_MAX_VIEWS];  /* S = fit_ss, for the fit */
    ls_vis vis4;                /* S = 4, re-rasterized per evaluation view */
    uint32_t res_hi;            /* the held-out views again at res_hi^2 (S = 4) */
    ls_vis vis_hi;              /* S = 4 at res_hi, for the held-out views at high resolution */
    ls_real *targets_hi[TX_TEST]; /* RGBA, S = 4 renders of the true texture at res_hi */
    ls_real *targets[TX_MAX_VIEWS]; /* RGBA, S = 4 renders of the true texture */
    ls_real *truth;             /* the true texture, 1024^2 */
    uint32_t truth_side;
    uint32_t footprint;         /* box-filter block for the texture error */
    uint32_t ls_adam;           /* large steps with per-element Adam on u instead of UniformAdam */
    ls_shade_opts opts;
    ls_csc lap;                 /* the grid Laplacian of the fitted texture */
    ls_arena *arena;
} tx_problem;

/* The solver of the large-steps parameterization: the one place to change
 * it. AUTO: the grid's exact transform solver (grid_solve.h). */
static uint32_t tx_solver(uint32_t side)
{
    (void)side;
    return LS_PARAM_AUTO;
}

/* Process CPU time: the machine may be shared, and the comparison is of work done. */
static double now_s(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return (double)ls_posix_clock_ns(NULL) * 1e-9;
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Parses a comma list of positive numbers into g; 0 when malformed. */
static int parse_grid(const char *v, tx_grid *g)
{
    g->n = 0;
    while (*v != '\0') {
        char *end;
        double d = 0;
        size_t n = ls_scan_number(v, strlen(v));
        end = (char *)(uintptr_t)(v + n);
        if (n == 0 || ls_parse_double(v, n, &d) != LS_OK) return 0;
        if (end == v || !(d > 0) || !(d < 1e300) || g->n == TX_GRID_MAX || (*end != ',' && *end != '\0')) return 0;
        g->v[g->n++] = d;
        v = *end == ',' ? end + 1 : end;
    }
    return g->n > 0;
}

/* Parses --methods: a comma list of naive, reg, ls into a bit set; 0 when malformed. */
static uint32_t parse_methods(const char *v)
{
    static const char *const names[3] = {"naive", "reg", "ls"};
    uint32_t bits = 0;
    while (*v != '\0') {
        size_t len = strcspn(v, ",");
        int m, found = 0;
        for (m = 0; m < 3; m++)
            if (strlen(names[m]) == len && strncmp(v, names[m], len) == 0) {
                bits |= 1u << m;
                found = 1;
            }
        if (!found) return 0;
        v += len;
        if (*v == ',') v++;
    }
    return bits;
}

/* Fills the grids the command line left empty with the defaults. */
static void default_grids(tx_args *a, uint32_t footprint)
{
    static const double lr_adam[3] = {0.1, 0.3, 1}, lr_ua[3] = {0.1, 0.3, 1};
    double fp2 = (double)footprint * footprint, w0 = 1e-6 * fp2 / ((double)a->side * a->side / 16384.0);
    int m, i;
    for (m = 0; m < 3; m++)
        if (a->lr[m].n == 0) {
            a->lr[m].n = 3;
            for (i = 0; i < 3; i++) a->lr[m].v[i] = m == M_LS ? lr_ua[i] : lr_adam[i];
        }
    if (a->weight[M_NAIVE].n == 0) {
        a->weight[M_NAIVE].n = 1;
        a->weight[M_NAIVE].v[0] = 0;
    }
    if (a->weight[M_REG].n == 0) {
        a->weight[M_REG].n = 3;
        for (i = 0; i < 3; i++) a->weight[M_REG].v[i] = w0 * (i == 0 ? 0.1 : i == 1 ? 1 : 10);
    }
    if (a->weight[M_LS].n == 0) {
        a->weight[M_LS].n = 3;
        for (i = 0; i < 3; i++) a->weight[M_LS].v[i] = fp2 * (i == 0 ? 1 : i == 1 ? 4 : 16);
    }
}

static int usage(FILE *f)
{
    fprintf(f, "usage: largesteps experiment texture [options] -o DIR\n"
               "  --image PNG   target image (default %s)\n"
               "  --scene S     quad (default) or sphere\n"
               "  --res R       render size R x R (default 108)\n"
               "  --res-hi R    the held-out views measured again at R x R (8..2048; default 512)\n"
               "  --views N     training views (default 8)\n"
               "  --fit-ss S    samples per pixel side of the fit's renders: 4 (default, as the targets), 2 or 1\n"
               "  --ls-optimizer O   uniform (default: UniformAdam, the method's) or adam (per-texel Adam on u)\n"
               "  --targets T   training targets: box (default: 4 x 4 samples, box resolve) or fit\n"
               "                (rendered like the fit's renders, --fit-ss); error renders are always box\n"
               "  --side N      fitted texture side (default 256; --full: 1024)\n"
               "  --tune S      seconds per tuning run (default 2)\n"
               "  --time S      seconds per final run (default 12)\n"
               "  --full        acceptance run: --side 1024 --tune 20 --time 90\n"
               "  --methods L   comma list of naive, reg, ls (default all three)\n"
               "  --lr-naive L, --lr-reg L, --lr-ls L    learning-rate grids (comma lists;\n"
               "                default 0.1,0.3,1 for all three)\n"
               "  --w-reg L, --lambda-ls L   weight grids (default: w = 1e-7, 1e-6, 1e-5 x f^2 / (side^2 / 128^2),\n"
               "                lambda = 1, 4, 16 x f^2; f the footprint below)\n",
            TX_DEFAULT_IMAGE);
    return f == stderr ? 2 : 0;
}

/* ---- scene ---- */

static int make_scene(tx_problem *p, const char *scene)
{
    ls_arena *a = p->arena;
    uint32_t i, j;
    if (strcmp(scene, "sphere") == 0) {
        const uint32_t nu = 48, nl = 24; /* longitude x latitude cells */
        p->nv = (nu + 1) * (nl + 1);
        p->nt = 2 * nu * nl;
        p->wrap = LS_TEXTURE_REPEAT;
    } else {
        p->nv = 4;
        p->nt = 2;
        p->wrap = LS_TEXTURE_CLAMP;
    }
    p->pos = (ls_real *)ls_arena_alloc(a, 3u * p->nv, sizeof(ls_real));
    p->nrm = (ls_real *)ls_arena_alloc(a, 3u * p->nv, sizeof(ls_real));
    p->uv = (ls_real *)ls_arena_alloc(a, 2u * p->nv, sizeof(ls_real));
    p->idx = (uint32_t *)ls_arena_alloc(a, 3u * p->nt, sizeof(uint32_t));
    if (p->pos == NULL || p->nrm == NULL || p->uv == NULL || p->idx == NULL) return 0;
    if (strcmp(scene, "sphere") == 0) {
        const uint32_t nu = 48, nl = 24;
        uint32_t t = 0;
        for (j = 0; j <= nl; j++)
            for (i = 0; i <= nu; i++) { /* column nu duplicates column 0 (the seam) */
                double th = 3.14159265358979323846 * j / nl, ph = 2 * 3.14159265358979323846 * i / nu;
                ls_real *q = p->pos + 3 * (j * (nu + 1) + i);
                q[0] = (ls_real)(sin(th) * sin(ph));
                q[1] = (ls_real)cos(th);
                q[2] = (ls_real)(sin(th) * cos(ph));
                p->uv[2 * (j * (nu + 1) + i)] = (ls_real)((double)i / nu);
                p->uv[2 * (j * (nu + 1) + i) + 1] = (ls_real)((double)j / nl);
            }
        for (j = 0; j < nl; j++)
            for (i = 0; i < nu; i++) {
                uint32_t a0 = j * (nu + 1) + i, a1 = a0 + 1, b0 = a0 + nu + 1, b1 = b0 + 1;
                p->idx[3 * t] = a0; p->idx[3 * t + 1] = b0; p->idx[3 * t + 2] = b1; t++;
                p->idx[3 * t] = a0; p->idx[3 * t + 1] = b1; p->idx[3 * t + 2] = a1; t++;
            }
    } else {
        static const float q[4][5] = {{-1, -1, 0, 0, 1}, {1, -1, 0, 1, 1}, {1, 1, 0, 1, 0}, {-1, 1, 0, 0, 0}};
        static const uint32_t f[6] = {0, 1, 2, 0, 2, 3};
        for (i = 0; i < 4; i++) {
            for (j = 0; j < 3; j++) p->pos[3 * i + j] = (ls_real)q[i][j];
            p->uv[2 * i] = (ls_real)q[i][3];
            p->uv[2 * i + 1] = (ls_real)q[i][4];
        }
        memcpy(p->idx, f, sizeof f);
    }
    return ls_shade_vertex_normals(p->pos, p->nv, p->idx, p->nt, p->nrm, NULL) == LS_OK;
}

/* View k of n: training views on a cone of 35 deg around +z (the quad's
 * normal), then validation and test views at other azimuths and 20 / 50 deg.
 * The sphere's views go all around. */
static void view_matrix(const tx_problem *p, int sphere, uint32_t k, ls_real mvp[16])
{
    ls_real view[16], proj[16], eye[3], tgt[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    double tilt, az, dist = sphere ? 3.2 : 2.9;
    uint32_t ntr = p->ntrain;
    if (k < ntr) {
        tilt = sphere ? 0.35 * ((k % 3) - 1.0) : 0.61;
        az = 2 * 3.14159265358979323846 * (k + 0.5) / ntr;
    } else {
        uint32_t e = k - ntr;
        tilt = sphere ? 0.5 * ((e % 2) ? 1 : -1) * 0.6 : (e % 2 ? 0.87 : 0.35);
        az = 2 * 3.14159265358979323846 * (e + 0.25) / (TX_VAL + TX_TEST) + 0.4;
    }
    if (sphere) {
        eye[0] = (ls_real)(dist * cos(tilt) * sin(az));
        eye[1] = (ls_real)(dist * sin(tilt));
        eye[2] = (ls_real)(dist * cos(tilt) * cos(az));
    } else {
        eye[0] = (ls_real)(dist * sin(tilt) * cos(az));
        eye[1] = (ls_real)(dist * sin(tilt) * sin(az));
        eye[2] = (ls_real)(dist * cos(tilt));
    }
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_perspective((ls_real)0.75, LS_FOV_Y, (ls_real)1, (ls_real)0.1, (ls_real)20, proj);
    ls_mat4_mul(proj, view, mvp);
}

/* ---- images ---- */

/* The target texture: the centre square of the image, point-sampled to side^2. */
static int load_truth(tx_problem *p, const char *path, uint32_t side)
{
    unsigned char *data = NULL;
    size_t bytes = 0;
    ls_image_info info;
    ls_image img;
    ls_arena_mark mark;
    uint32_t x, y, sq, x0, y0;
    ls_status st = ls_posix_read_file(path, &data, &bytes);
    if (st != LS_OK) return fprintf(stderr, "largesteps experiment texture: cannot read %s: %s (install desktop-base or pass --image)\n", path, ls_posix_read_error()), 0;
    st = ls_image_decode_info(data, bytes, &info, NULL);
    p->truth = (ls_real *)ls_arena_alloc(p->arena, 3u * side * side, sizeof(ls_real));
    mark = ls_arena_save(p->arena);
    if (st == LS_OK && p->truth != NULL) st = ls_image_decode(data, bytes, &img, p->arena, NULL);
    free(data);
    if (st != LS_OK || p->truth == NULL) return fprintf(stderr, "largesteps experiment texture: %s: %s\n", path, ls_status_str(st)), 0;
    sq = img.width < img.height ? img.width : img.height;
    x0 = (img.width - sq) / 2;
    y0 = (img.height - sq) / 2;
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++) {
            size_t sx = x0 + (size_t)x * sq / side, sy = y0 + (size_t)y * sq / side;
            const float *px = img.pixels + 4 * (sy * img.width + sx);
            int c;
            for (c = 0; c < 3; c++) p->truth[3 * ((size_t)y * side + x) + (size_t)c] = (ls_real)px[c];
        }
    ls_arena_restore(p->arena, mark);
    p->truth_side = side;
    return 1;
}

/* Box filter of a side^2 texture by blocks of f (side multiple of f) into out ((side/f)^2). */
static void box_down(const ls_real *t, uint32_t side, uint32_t f, double *out)
{
    uint32_t os = side / f, x, y, i, j;
    for (y = 0; y < os; y++)
        for (x = 0; x < os; x++) {
            double s[3] = {0, 0, 0};
            int c;
            for (j = 0; j < f; j++)
                for (i = 0; i < f; i++)
                    for (c = 0; c < 3; c++) s[c] += (double)t[3 * ((size_t)(y * f + j) * side + x * f + i) + (size_t)c];
            for (c = 0; c < 3; c++) out[3 * ((size_t)y * os + x) + (size_t)c] = s[c] / ((double)f * f);
        }
}

static double psnr(double mse) { return mse > 0 ? 10 * log10(1 / mse) : 99; }

/* Renders texels (side^2) from view k into rgba through vis (S = 4: vis4 or vis_hi). */
static int render_in(tx_problem *p, ls_vis *vis, const ls_real *texels, uint32_t side, uint32_t k, ls_real *rgba)
{
    ls_texture tex;
    ls_shade_opts o = p->opts;
    if (ls_texture_init(&tex, side, side, p->wrap, texels) != LS_OK) return 0;
    o.texture = &tex;
    if (ls_raster(vis, &(ls_view){.positions = p->pos, .indices = p->idx, .triangle_count = p->nt,
            .vertex_count = p->nv, .mvp = p->mvp[k]}, p->arena, NULL) != LS_OK) return 0;
    return ls_shade(&(ls_view){.vis = vis, .indices = p->idx, .triangle_count = p->nt, .vertex_count = p->nv,
            .normals = p->nrm, .opts = &o}, rgba, NULL) == LS_OK;
}

/* Renders texels (side^2) from view k with S = 4 at the training resolution into rgba. */
static int render4(tx_problem *p, const ls_real *texels, uint32_t side, uint32_t k, ls_real *rgba)
{
    return render_in(p, &p->vis4, texels, side, k, rgba);
}

/* Adds the squared error over the covered pixels of one render to *se, their values to *cnt. */
static void covered_error(const ls_real *img, const ls_real *target, size_t np, double *se, size_t *cnt)
{
    size_t i;
    for (i = 0; i < np; i++) {
        int c;
        if (!(target[4 * i + 3] > 0)) continue;
        for (c = 0; c < 3; c++) {
            double d = (double)img[4 * i + (size_t)c] - (double)target[4 * i + (size_t)c];
            *se += d * d;
        }
        *cnt += 3;
    }
}

/* PSNR over the covered pixels of views [k0, k1) of the S = 4 renders. */
static double views_psnr(tx_problem *p, const ls_real *texels, uint32_t side, uint32_t k0, uint32_t k1, ls_real *buf)
{
    double se = 0;
    size_t cnt = 0;
    uint32_t k;
    for (k = k0; k < k1; k++) {
        if (!render4(p, texels, side, k, buf)) return -1;
        covered_error(buf, p->targets[k], (size_t)p->res * p->res, &se, &cnt);
    }
    return cnt > 0 ? psnr(se / (double)cnt) : -1;
}

/* PSNR over the covered pixels of the held-out views at res_hi (buf: res_hi^2 RGBA). */
static double views_psnr_hi(tx_problem *p, const ls_real *texels, uint32_t side, ls_real *buf)
{
    double se = 0;
    size_t cnt = 0;
    uint32_t t;
    for (t = 0; t < TX_TEST; t++) {
        if (!render_in(p, &p->vis_hi, texels, side, p->ntrain + TX_VAL + t, buf)) return -1;
        covered_error(buf, p->targets_hi[t], (size_t)p->res_hi * p->res_hi, &se, &cnt);
    }
    return cnt > 0 ? psnr(se / (double)cnt) : -1;
}

/* PSNR of a side^2 texture against the truth, both box-filtered to blocks
 * of `block` texels of the fitted texture (1: texel by texel, the truth
 * box-filtered to the fitted side). */
static double texture_psnr(const tx_problem *p, const ls_real *texels, uint32_t side, uint32_t block)
{
    uint32_t fs = side / block > 0 ? block : side, ft = p->truth_side / (side / fs);
    uint32_t os = side / fs;
    double *a = (double *)malloc(sizeof(double) * 3 * os * os), *b = (double *)malloc(sizeof(double) * 3 * os * os);
    double se = 0;
    size_t i;
    if (a == NULL || b == NULL) {
        free(a);
        free(b);
        return -1;
    }
    box_down(texels, side, fs, a);
    box_down(p->truth, p->truth_side, ft, b);
    for (i = 0; i < 3u * (size_t)os * os; i++) se += (a[i] - b[i]) * (a[i] - b[i]);
    free(a);
    free(b);
    return psnr(se / (3.0 * os * os));
}

/* ---- the fit ---- */

static const char *const method_names[3] = {"naive (Adam)", "regularized (Adam + w tr(x^T L x))", "large steps (UniformAdam, I + lambda L)"};

/* The row label of method m (large steps names its optimizer). */
static const char *method_label(const tx_problem *p, int m)
{
    return m == M_LS && p->ls_adam ? "large steps (Adam on u, I + lambda L)" : method_names[m];
}

typedef struct tx_run {
    double lr, weight, seconds, setup, loss, val, test, test_hi, tex, tex_full;
    uint32_t iters;
    int ok;
} tx_run;

/* One run of method m for `seconds` (or, iters > 0, that many iterations)
 * from grey; the texels stay in x (side^2 x 3). Large steps uses par (built
 * by make_param, its setup timed there and reported apart). */
static tx_run fit(tx_problem *p, int m, double lr, double weight, double seconds, uint32_t iters, ls_real *x,
                  ls_real *buf, ls_param *par)
{
    ls_arena *a = p->arena;
    ls_arena_mark mark = ls_arena_save(a);
    uint32_t side = p->side, n = side * side, k;
    size_t np = (size_t)p->res * p->res, i;
    ls_real *g = (ls_real *)ls_arena_alloc(a, 3u * n, sizeof(ls_real));
    ls_real *gimg = (ls_real *)ls_arena_alloc(a, 4 * np, sizeof(ls_real));
    ls_real *gu2 = NULL, *greg = NULL;
    ls_optim opt;
    ls_optim_config oc;
    ls_texture tex;
    ls_shade_opts o = p->opts;
    ls_shade_grads gr;
    tx_run r;
    uint32_t bs[1];
    double t0;
    memset(&r, 0, sizeof r);
    r.lr = lr;
    r.weight = weight;
    memset(&gr, 0, sizeof gr);
    for (i = 0; i < 3u * (size_t)n; i++) x[i] = (ls_real)0.5;
    if (g == NULL || gimg == NULL || (m == M_LS && par == NULL)) goto done;
    ls_optim_config_default(m == M_LS && !p->ls_adam ? LS_OPTIM_UNIFORM_ADAM : LS_OPTIM_ADAM, &oc);
    oc.lr = (ls_real)lr;
    bs[0] = 3u * n;
    if (ls_optim_init(&opt, &oc, 3u * n, 1, bs, a) != LS_OK) goto done;
    t0 = now_s();
    if (m != M_NAIVE) { /* the regularizer's gradient, or dL/du */
        greg = (ls_real *)ls_arena_alloc(a, 3u * n, sizeof(ls_real));
        if (greg == NULL) goto done;
    }
    if (m == M_LS) { /* M^{-2} g: UniformAdam moves x = M^{-1} u directly (ls_optim_step_mapped); Adam: u itself */
        gu2 = (ls_real *)ls_arena_alloc(a, 3u * n, sizeof(ls_real));
        if (gu2 == NULL || (p->ls_adam && ls_param_to_differential(par, x, gu2) != LS_OK)) goto done;
    }
    if (ls_texture_init(&tex, side, side, p->wrap, x) != LS_OK) goto done;
    o.texture = &tex;
    gr.texels = g;
    for (;;) {
        double loss = 0, inv = 1.0 / (3.0 * (double)np * p->ntrain);
        for (i = 0; i < 3u * (size_t)n; i++) g[i] = 0;
        for (k = 0; k < p->ntrain; k++) {
            if (ls_shade(&(ls_view){.vis = &p->vis1[k], .indices = p->idx, .triangle_count = p->nt,
                    .vertex_count = p->nv, .normals = p->nrm, .opts = &o}, buf, NULL) != LS_OK) goto done;
            for (i = 0; i < 4 * np; i++) {
                double d = (double)buf[i] - (double)p->targets[k][i];
                if ((i & 3u) == 3u) {
                    gimg[i] = 0;
                    continue;
                }
                loss += d * d * inv;
                gimg[i] = (ls_real)(2 * d * inv);
            }
            if (ls_shade_backward_grads(&(ls_view){.vis = &p->vis1[k], .indices = p->idx, .triangle_count = p->nt,
                    .vertex_count = p->nv, .normals = p->nrm, .opts = &o, .mvp = p->mvp[k]}, gimg, &gr, NULL) !=
                LS_OK)
                goto done;
        }
        r.loss = loss;
        if (m == M_NAIVE) {
            if (ls_optim_step(&opt, x, g, NULL) != LS_OK) goto done;
        } else if (m == M_REG) {
            if (ls_laplacian_energy(&p->lap, 3, x, (ls_real)weight, NULL, greg, NULL) != LS_OK) goto done;
            for (i = 0; i < 3u * (size_t)n; i++) g[i] += greg[i];
            if (ls_optim_step(&opt, x, g, NULL) != LS_OK) goto done;
        } else if (p->ls_adam) { /* per-element Adam does not commute with M^{-1}: the u form */
            if (ls_param_adjoint(par, g, greg) != LS_OK || ls_optim_step(&opt, gu2, greg, NULL) != LS_OK ||
                ls_param_from_differential(par, gu2, x) != LS_OK)
                goto done;
        } else {
            if (ls_param_adjoint2(par, g, greg, gu2) != LS_OK || ls_optim_step_mapped(&opt, x, greg, gu2, NULL) != LS_OK)
                goto done;
        }
        r.iters++;
        r.seconds = now_s() - t0;
        if (iters > 0 ? r.iters >= iters : r.seconds >= seconds) break;
    }
    r.ok = 1;
done:
    ls_arena_restore(a, mark);
    return r;
}

/* The large-steps parameterization M = I + lambda L of the texels (from the
 * bottom of the arena: the caller restores). Returns its setup seconds, < 0 on failure. */
static double make_param(tx_problem *p, double lambda, ls_param *par)
{
    ls_param_config pc;
    double t0 = now_s();
    memset(&pc, 0, sizeof pc);
    pc.solver = tx_solver(p->side);
    pc.form = LS_SYSTEM_LAMBDA;
    pc.weight = (ls_real)lambda;
    pc.k = 3;
    pc.order = LS_ORDER_AMD;
    pc.cg_max_iter = 500;
    pc.cg_tol = (ls_real)1e-6;
    {
        ls_grid_shape shape;
        shape.width = shape.height = p->side;
        shape.wrap_u = p->wrap == LS_TEXTURE_REPEAT;
        if (ls_param_grid_init(par, &shape, &pc, p->arena, NULL) != LS_OK) return -1;
    }
    return now_s() - t0;
}

static void evaluate(tx_problem *p, tx_run *r, const ls_real *x, ls_real *buf, int test)
{
    uint32_t v0 = p->ntrain;
    r->val = views_psnr(p, x, p->side, v0, v0 + TX_VAL, buf);
    if (test) {
        r->test = views_psnr(p, x, p->side, v0 + TX_VAL, v0 + TX_VAL + TX_TEST, buf);
        r->test_hi = views_psnr_hi(p, x, p->side, buf);
        r->tex = texture_psnr(p, x, p->side, p->footprint);
        r->tex_full = texture_psnr(p, x, p->side, 1);
    }
}

/* ---- the figure ---- */

/* Box-filters a side^2 texture to tile^2 RGBA (each tile pixel the mean of its texel rectangle). */
static void texture_tile(const ls_real *t, uint32_t side, uint32_t tile, ls_real *rgba)
{
    uint32_t x, y, i, j;
    for (y = 0; y < tile; y++)
        for (x = 0; x < tile; x++) {
            uint32_t i0 = x * side / tile, i1 = (x + 1) * side / tile, j0 = y * side / tile, j1 = (y + 1) * side / tile;
            double s[3] = {0, 0, 0}, c = 0;
            int q;
            if (i1 <= i0) i1 = i0 + 1;
            if (j1 <= j0) j1 = j0 + 1;
            for (j = j0; j < j1; j++)
                for (i = i0; i < i1; i++) {
                    for (q = 0; q < 3; q++) s[q] += (double)t[3 * ((size_t)j * side + i) + (size_t)q];
                    c += 1;
                }
            for (q = 0; q < 3; q++) rgba[4 * ((size_t)y * tile + x) + (size_t)q] = (ls_real)(s[q] / c);
            rgba[4 * ((size_t)y * tile + x) + 3] = 1;
        }
}

static int write_figure(tx_problem *p, const char *dir, ls_real *const fitted[3], ls_real *buf)
{
    const uint32_t tile = 2 * p->res;
    ls_arena_mark mark = ls_arena_save(p->arena);
    ls_contact sheet;
    ls_real *rgba = (ls_real *)ls_arena_alloc(p->arena, 4u * tile * tile, sizeof(ls_real));
    ls_image_format png = {LS_IMAGE_PNG, 3, 8, 0};
    uint32_t x, y, m;
    int ok = 0;
    if (rgba == NULL || ls_contact_init(&sheet, p->arena, 5, tile, tile, 5, 2, NULL) != LS_OK) goto out;
    texture_tile(p->truth, p->truth_side, tile, rgba);
    if (ls_contact_put_rgba(&sheet, 0, rgba) != LS_OK) goto out;
    for (y = 0; y < tile; y++) /* a held-out target render, magnified x2 */
        for (x = 0; x < tile; x++)
            memcpy(rgba + 4 * ((size_t)y * tile + x), p->targets[p->ntrain + TX_VAL] + 4 * ((size_t)(y / 2) * p->res + x / 2),
                   4 * sizeof(ls_real));
    if (ls_contact_put_rgba(&sheet, 1, rgba) != LS_OK) goto out;
    for (m = 0; m < 3; m++) {
        texture_tile(fitted[m], p->side, tile, rgba);
        if (ls_contact_put_rgba(&sheet, 2 + m, rgba) != LS_OK) goto out;
    }
    (void)buf;
    ok = ls_posix_write_image_in(dir, "texture.png", &sheet.image, &png, p->arena, NULL);
out:
    ls_arena_restore(p->arena, mark);
    return ok;
}

/* ---- the command ---- */

static int setup(tx_problem *p, const tx_args *a)
{
    uint32_t k, maxcov = 0;
    size_t np = (size_t)a->res * a->res;
    int sphere = strcmp(a->scene, "sphere") == 0;
    p->side = a->side;
    p->ls_adam = a->ls_adam;
    p->res = a->res;
    p->res_hi = a->res_hi;
    p->ntrain = a->views;
    p->nviews = a->views + TX_VAL + TX_TEST;
    if (!make_scene(p, a->scene) || !load_truth(p, a->image, 1024)) return 0;
    if (ls_laplacian_grid(a->side, a->side, LS_LAP_UPPER, p->arena, &p->lap) != LS_OK) return 0;
    ls_shade_opts_init(&p->opts);
    p->opts.mode = LS_SHADE_COLOR;
    p->opts.uvs = p->uv;
    p->opts.background[0] = p->opts.background[1] = p->opts.background[2] = (ls_real)0.1;
    if (ls_vis_init(&p->vis4, p->arena, a->res, a->res, TX_SS_TARGET, p->nv) != LS_OK ||
        ls_vis_init(&p->vis_hi, p->arena, p->res_hi, p->res_hi, TX_SS_TARGET, p->nv) != LS_OK)
        return 0;
    for (k = 0; k < p->nviews; k++) {
        uint32_t cov = 0;
        size_t i;
        view_matrix(p, sphere, k, p->mvp[k]);
        if (ls_vis_init(&p->vis1[k], p->arena, a->res, a->res, a->fit_ss, p->nv) != LS_OK ||
            ls_raster(&p->vis1[k], &(ls_view){.positions = p->pos, .indices = p->idx, .triangle_count = p->nt,
                    .vertex_count = p->nv, .mvp = p->mvp[k]}, p->arena, NULL) != LS_OK)
            return 0;
        p->targets[k] = (ls_real *)ls_arena_alloc(p->arena, 4 * np, sizeof(ls_real));
        if (p->targets[k] == NULL) return 0;
        if (k < p->ntrain && a->own_targets) { /* training targets by the fit's own forward model */
            ls_texture tex;
            ls_shade_opts o = p->opts;
            if (ls_texture_init(&tex, p->truth_side, p->truth_side, p->wrap, p->truth) != LS_OK) return 0;
            o.texture = &tex;
            if (ls_shade(&(ls_view){.vis = &p->vis1[k], .indices = p->idx, .triangle_count = p->nt,
                    .vertex_count = p->nv, .normals = p->nrm, .opts = &o}, p->targets[k], NULL) != LS_OK) return 0;
        } else if (!render4(p, p->truth, p->truth_side, k, p->targets[k])) {
            return 0;
        }
        for (i = 0; i < np * a->fit_ss * a->fit_ss; i++) cov += p->vis1[k].tri[i] != 0;
        cov /= a->fit_ss * a->fit_ss;
        if (cov > maxcov) maxcov = cov;
    }
    for (k = 0; k < TX_TEST; k++) {
        p->targets_hi[k] = (ls_real *)ls_arena_alloc(p->arena, 4u * p->res_hi * p->res_hi, sizeof(ls_real));
        if (p->targets_hi[k] == NULL ||
            !render_in(p, &p->vis_hi, p->truth, p->truth_side, p->ntrain + TX_VAL + k, p->targets_hi[k]))
            return 0;
    }
    /* footprint: texels per pixel along the quad (sphere: along the equator's visible half) */
    {
        double px = sqrt((double)maxcov) * (sphere ? 3.14159265358979323846 : 1.0), f = a->side / (px > 1 ? px : 1);
        p->footprint = 1;
        while (p->footprint * 2 <= a->side && (double)p->footprint * 1.41421356 < f) p->footprint *= 2;
    }
    return 1;
}

int ls_cmd_experiment_texture(int argc, char **argv)
{
    static tx_problem p;
    tx_args a;
    ls_arena arena;
    unsigned char *work;
    size_t work_bytes;
    ls_real *fitted[3], *fitted_eq, *buf;
    tx_run best[3];
    FILE *f;
    char path[4096], tmp[4096];
    int i, m;
    memset(&a, 0, sizeof a);
    a.image = TX_DEFAULT_IMAGE;
    a.scene = "quad";
    a.res = 108;
    a.res_hi = TX_RES_HI;
    a.fit_ss = 4;
    a.own_targets = 0;
    a.views = 8;
    a.side = 0;
    a.tune_s = 2;
    a.run_s = 12;
    a.methods = 7u;
    for (i = 1; i < argc; i++) {
        const char *opt = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(opt, "--full") == 0) {
            a.full = 1;
            continue;
        }
        if (strcmp(opt, "-h") == 0 || strcmp(opt, "--help") == 0) return usage(stdout);
        if (v == NULL) return usage(stderr);
        i++;
        if (strcmp(opt, "-o") == 0) a.out = v;
        else if (strcmp(opt, "--image") == 0) a.image = v;
        else if (strcmp(opt, "--scene") == 0 && (strcmp(v, "quad") == 0 || strcmp(v, "sphere") == 0)) a.scene = v;
        else if (strcmp(opt, "--ls-optimizer") == 0 && (strcmp(v, "uniform") == 0 || strcmp(v, "adam") == 0)) a.ls_adam = strcmp(v, "adam") == 0;
        else if (strcmp(opt, "--targets") == 0 && (strcmp(v, "box") == 0 || strcmp(v, "fit") == 0)) a.own_targets = strcmp(v, "fit") == 0;
        else if (strcmp(opt, "--fit-ss") == 0) {
            if (!ls_arg_u32(TX_CMD, opt, v, 1, 4, &a.fit_ss)) return 2;
            if (a.fit_ss == 3) return fprintf(stderr, "largesteps " TX_CMD ": --fit-ss: '3' is not 1, 2 or 4\n"), 2;
        } else if (strcmp(opt, "--res") == 0) {
            if (!ls_arg_u32(TX_CMD, opt, v, 8, 1024, &a.res)) return 2;
        } else if (strcmp(opt, "--res-hi") == 0) {
            if (!ls_arg_u32(TX_CMD, opt, v, 8, 2048, &a.res_hi)) return 2;
        } else if (strcmp(opt, "--views") == 0) {
            if (!ls_arg_u32(TX_CMD, opt, v, 1, TX_MAX_VIEWS - TX_VAL - TX_TEST, &a.views)) return 2;
        } else if (strcmp(opt, "--side") == 0) {
            if (!ls_arg_u32(TX_CMD, opt, v, 4, 1024, &a.side)) return 2;
        } else if (strcmp(opt, "--tune") == 0) {
            if (!ls_arg_real(TX_CMD, opt, v, 0, 1e6, LS_ARG_LO_OPEN, &a.tune_s)) return 2;
        } else if (strcmp(opt, "--time") == 0) {
            if (!ls_arg_real(TX_CMD, opt, v, 0, 1e6, LS_ARG_LO_OPEN, &a.run_s)) return 2;
        }
        else if (strcmp(opt, "--methods") == 0 && (a.methods = parse_methods(v)) != 0) continue;
        else if (strcmp(opt, "--lr-naive") == 0 && parse_grid(v, &a.lr[M_NAIVE])) continue;
        else if (strcmp(opt, "--lr-reg") == 0 && parse_grid(v, &a.lr[M_REG])) continue;
        else if (strcmp(opt, "--lr-ls") == 0 && parse_grid(v, &a.lr[M_LS])) continue;
        else if (strcmp(opt, "--w-reg") == 0 && parse_grid(v, &a.weight[M_REG])) continue;
        else if (strcmp(opt, "--lambda-ls") == 0 && parse_grid(v, &a.weight[M_LS])) continue;
        else return usage(stderr);
    }
    if (a.out == NULL) return fprintf(stderr, "largesteps " TX_CMD ": -o DIR is required\n"), usage(stderr);
    if (!ls_posix_check_output_dir(a.out)) return 2;
    if (a.full) {
        if (a.side == 0) a.side = 1024;
        a.tune_s = a.tune_s == 2 ? 20 : a.tune_s;
        a.run_s = a.run_s == 12 ? 90 : a.run_s;
    }
    if (a.side == 0) a.side = 256;
    work_bytes = sizeof(size_t) > 4u ? (size_t)3 << 30 : (size_t)1 << 30; /* 1 GiB on 32-bit hosts */
    work = (unsigned char *)malloc(work_bytes);
    if (work == NULL || ls_arena_init(&arena, work, work_bytes) != LS_OK) return fprintf(stderr, "out of memory\n"), 1;
    p.arena = &arena;
    if (ls_posix_mkdir_p(a.out) != 0) return fprintf(stderr, "largesteps experiment texture: cannot create %s\n", a.out), 1;
    if (!setup(&p, &a)) return fprintf(stderr, "largesteps experiment texture: setup failed\n"), 1;
    /* one render: S = 4 samples of a view at the training resolution, or the RGBA of one at TX_RES_HI */
    buf = (ls_real *)ls_arena_alloc(&arena, 16u * a.res * a.res > 4u * a.res_hi * a.res_hi ? 16u * a.res * a.res
                                                                                       : 4u * a.res_hi * a.res_hi,
                                    sizeof(ls_real));
    for (m = 0; m < 3; m++) fitted[m] = (ls_real *)ls_arena_alloc(&arena, 3u * a.side * a.side, sizeof(ls_real));
    fitted_eq = (ls_real *)ls_arena_alloc(&arena, 3u * a.side * a.side, sizeof(ls_real));
    if (buf == NULL || fitted_eq == NULL || fitted[0] == NULL || fitted[1] == NULL || fitted[2] == NULL) return fprintf(stderr, "out of memory\n"), 1;
    for (m = 0; m < 3; m++) { /* grey: what the figure shows for a method not run */
        size_t q;
        for (q = 0; q < 3u * (size_t)a.side * a.side; q++) fitted[m][q] = (ls_real)0.5;
    }
    snprintf(path, sizeof path, "%s/texture.md", a.out);
    snprintf(tmp, sizeof tmp, "%s/.texture.md.tmp", a.out);
    f = fopen(tmp, "w");
    if (f == NULL) return fprintf(stderr, "largesteps experiment texture: cannot write %s\n", path), 1;
    fprintf(f, "# experiment texture: %s, target %s (centre square, 1024^2), fitted texture %u^2\n\n", a.scene, a.image,
            (unsigned)a.side);
    fprintf(f, "%u training, %u validation (tuning), %u held-out views at %u x %u; fit renders %u x %u samples/pixel, "
               "targets and error renders 4 x 4 samples/pixel (box); texture error on %u x %u texel blocks; "
               "large-steps solver %s.\n\n",
            (unsigned)a.views, TX_VAL, TX_TEST, (unsigned)a.res, (unsigned)a.res, (unsigned)a.fit_ss, (unsigned)a.fit_ss, (unsigned)p.footprint,
            (unsigned)p.footprint, tx_solver(a.side) == LS_PARAM_LDLT ? "LDL^T (AMD)" : tx_solver(a.side) == LS_PARAM_CG ? "CG" : "the grid's transform solver");
    if (a.ls_adam) fprintf(f, "Large steps runs per-texel Adam on u (--ls-optimizer adam), not the method's UniformAdam.\n\n");
    /* tuning grids: learning rate, and w (regularized) or lambda (large steps), scaled with the footprint */
    default_grids(&a, p.footprint);
    fprintf(f, "## tuning (%.0f s per run; validation-view PSNR in dB)\n\n| method | lr | w or lambda | iterations | train loss | validation PSNR |\n|---|---|---|---|---|---|\n",
            a.tune_s);
    for (m = 0; m < 3; m++) {
        uint32_t gi, gj;
        best[m].val = -1e30;
        best[m].ok = 0;
        if ((a.methods & (1u << m)) == 0) continue;
        for (gj = 0; gj < a.weight[m].n; gj++) {
            double w = a.weight[m].v[gj], setup = 0;
            ls_arena_mark pm = ls_arena_save(&arena);
            ls_param par;
            if (m == M_LS && (setup = make_param(&p, w, &par)) < 0) {
                fprintf(stderr, "largesteps experiment texture: the parameterization failed\n");
                continue;
            }
            for (gi = 0; gi < a.lr[m].n; gi++) {
                double lr = a.lr[m].v[gi];
                tx_run r = fit(&p, m, lr, w, a.tune_s, 0, fitted[m], buf, m == M_LS ? &par : NULL);
                if (!r.ok) {
                    fprintf(stderr, "largesteps experiment texture: %s lr %g failed\n", method_label(&p, m), lr);
                    continue;
                }
                r.setup = setup;
                evaluate(&p, &r, fitted[m], buf, 0);
                fprintf(f, "| %s | %g | %g | %u | %.3g | %.2f |\n", method_label(&p, m), lr, w, (unsigned)r.iters, r.loss, r.val);
                fflush(f);
                if (r.val > best[m].val) best[m] = r;
            }
            ls_arena_restore(&arena, pm);
        }
    }
    /* equal time, then equal iterations (the iterations of the large-steps
     * run, else of the slowest): the tuned settings from grey each time; the
     * figure shows the equal-time results */
    {
        uint32_t equal_iters = 0, pass;
        tx_run first[3];     /* the equal-time runs: one that ran equal_iters is the equal-iterations run too */
        double first_setup[3];
        memset(first, 0, sizeof first);
        for (pass = 0; pass < 2; pass++) {
            if (pass == 0)
                fprintf(f, "\n## equal time (%g s of iterations each), tuned settings\n\n", a.run_s);
            else
                fprintf(f, "\n## equal iterations (%u each: the large-steps run's at equal time, else the slowest's), tuned "
                           "settings\n\n",
                        (unsigned)equal_iters);
            fprintf(f, "| method | lr | w or lambda | setup (s) | iterations | seconds | train loss | held-out PSNR %u^2 "
                       "(dB) | held-out PSNR %u^2 (dB) | texture PSNR (dB) | texture PSNR, low-passed (dB) |\n"
                       "|---|---|---|---|---|---|---|---|---|---|---|\n",
                    (unsigned)a.res, (unsigned)a.res_hi);
            for (m = 2; m >= 0; m--) { /* large steps first: its iterations set the second pass */
                ls_arena_mark pm = ls_arena_save(&arena);
                ls_real *x = pass == 0 ? fitted[m] : fitted_eq;
                ls_param par;
                double setup = 0;
                tx_run r;
                if (!best[m].ok || (pass == 1 && equal_iters == 0)) continue;
                if (pass == 1 && first[m].ok && first[m].iters == equal_iters) {
                    r = first[m]; /* the same iterations from the same start: the same texels */
                    setup = first_setup[m];
                } else {
                    if (m == M_LS && (setup = make_param(&p, best[m].weight, &par)) < 0) continue;
                    r = fit(&p, m, best[m].lr, best[m].weight, pass == 0 ? a.run_s : 1e30, pass == 0 ? 0 : equal_iters,
                            x, buf, m == M_LS ? &par : NULL);
                    ls_arena_restore(&arena, pm);
                    if (!r.ok) continue;
                    evaluate(&p, &r, x, buf, 1);
                }
                if (pass == 0) first[m] = r, first_setup[m] = setup;
                if (pass == 0 && (m == M_LS || !best[M_LS].ok) && (equal_iters == 0 || r.iters < equal_iters))
                    equal_iters = r.iters;
                fprintf(f, "| %s | %g | %g | %.2f | %u | %.1f | %.3g | %.2f | %.2f | %.2f | %.2f |\n", method_label(&p, m),
                        r.lr, r.weight, setup, (unsigned)r.iters, r.seconds, r.loss, r.test, r.test_hi, r.tex_full,
                        r.tex);
                fflush(f);
            }
        }
    }
    {
        ls_real *grey = (ls_real *)ls_arena_alloc(&arena, 3u * a.side * a.side, sizeof(ls_real));
        size_t q;
        double tp;
        if (grey == NULL) return fprintf(stderr, "out of memory\n"), 1;
        for (q = 0; q < 3u * (size_t)a.side * a.side; q++) grey[q] = (ls_real)0.5;
        tp = views_psnr(&p, grey, a.side, p.ntrain + TX_VAL, p.nviews, buf);
        fprintf(f, "\n(The start, grey 0.5: held-out PSNR %.2f dB at %u^2, %.2f dB at %u^2; texture PSNR %.2f dB, "
                   "low-passed %.2f dB.)\n",
                tp, (unsigned)a.res, views_psnr_hi(&p, grey, a.side, buf), (unsigned)a.res_hi, texture_psnr(&p, grey, a.side, 1),
                texture_psnr(&p, grey, a.side, p.footprint));
    }
    if (!write_figure(&p, a.out, fitted, buf)) fprintf(stderr, "largesteps experiment texture: cannot write the figure\n");
    else fprintf(f, "\nFigure: %s/texture.png (target texture | held-out target render | naive | regularized | large steps).\n", a.out);
    {
        /* checked, then renamed; never a half-written or stale temporary */
        int bad = fflush(f) != 0 || ferror(f) || fsync(fileno(f)) != 0, err = errno;
        if (fclose(f) != 0 && !bad) bad = 1, err = errno;
        if (bad || rename(tmp, path) != 0) {
            if (!bad) err = errno;
            remove(tmp);
            free(work);
            return fprintf(stderr, "largesteps: cannot write %s: %s\n", path, strerror(err)), 1;
        }
    }
    (void)ls_posix_print_file_in(a.out, "texture.md");
    free(work);
    return 0;
}
