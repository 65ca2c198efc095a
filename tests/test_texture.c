/* tests/test_texture.c - textures: the bilinear lookup and its adjoint
 * against an independent tent-weight formula and central differences, and
 * textured shading (forward and backward to texels, UVs, positions and
 * vertex colours) against an independent float64 forward.
 *
 * The reference lookup sums tent weights max(0, 1 - |x - i|) max(0, 1 - |y - j|)
 * over every texel after clamping the continuous coordinate (or wrapping it,
 * with the tents of the periodic copies), not the library's four taps. The
 * reference render keeps the triangle id of every sample fixed (from
 * ls_raster at the base configuration) and recomputes the rest in double:
 * screen-affine barycentrics of the projected vertices made
 * perspective-correct with 1/W, interpolated UVs, the tent lookup, SH or
 * Lambert shading with uniform-weight vertex normals, vertex colours, and the
 * box mean of the samples. Probe: L = sum_p sum_c w_pc I_pc, random w. */
#include "test.h"
#include <stdlib.h>
#include <largesteps/texture.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/camera.h>
#include <largesteps/render_backward.h>
#include <largesteps/silhouette.h>

#define TEST_PI 3.14159265358979323846
#define MAXV 8
#define MAXT 8
#define IMG 18
#define SS 2
#define TW 7
#define TH 5

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static double rnd(void) /* uniform in [0, 1) */
{
    return test_rng_unit(&rng_state);
}

static double tol(void) { return sizeof(ls_real) == 4 ? 2e-3 : 1e-6; }

/* ---- the reference lookup ---- */

static double tent(double d)
{
    d = fabs(d);
    return d < 1 ? 1 - d : 0;
}

/* T(u, v) of a texture given in double, by tent weights over all texels. */
static void ref_sample(const double *tex, uint32_t w, uint32_t h, int repeat, double u, double v, double rgb[3])
{
    double x = u * w - 0.5, y = v * h - 0.5;
    uint32_t i, j;
    int c;
    if (y < 0) y = 0;
    if (y > h - 1.0) y = h - 1.0;
    if (repeat) {
        double ur = u - floor(u);
        x = ur * w - 0.5;
        if (x < 0) x += w; /* now in [0, w) */
    } else {
        if (x < 0) x = 0;
        if (x > w - 1.0) x = w - 1.0;
    }
    rgb[0] = rgb[1] = rgb[2] = 0;
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            double wx = repeat ? tent(x - i) + tent(x - i - w) + tent(x - i + w) : tent(x - i);
            double wt = wx * tent(y - j);
            if (wt == 0) continue;
            for (c = 0; c < 3; c++) rgb[c] += wt * tex[3 * (j * w + i) + (uint32_t)c];
        }
}

/* 1 when the lookup at (u, v) is at least `margin` (in texels) away from a
 * kink of the bilinear interpolant (texel-centre lines, clamp borders). */
static int away_from_kinks(uint32_t w, uint32_t h, int repeat, double u, double v, double margin)
{
    double x = (repeat ? u - floor(u) : u) * w - 0.5, y = v * h - 0.5;
    double fx = x - floor(x), fy = y - floor(y);
    return fx > margin && fx < 1 - margin && fy > margin && fy < 1 - margin;
}

static void fill_texture(ls_real *t, double *td, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        t[i] = (ls_real)(0.1 + 0.9 * rnd());
        td[i] = (double)t[i];
    }
}

/* ls_texture_sample against the tent formula, both wrap modes, several sizes. */
static void sample_matches_reference(void)
{
    static const uint32_t sizes[5][2] = {{1, 1}, {2, 3}, {5, 4}, {7, 7}, {1, 6}};
    static ls_real t[3 * 49];
    static double td[3 * 49];
    unsigned s;
    int repeat, k;
    double maxerr = 0;
    for (s = 0; s < 5; s++)
        for (repeat = 0; repeat < 2; repeat++) {
            ls_texture tex;
            uint32_t w = sizes[s][0], h = sizes[s][1];
            fill_texture(t, td, 3 * (size_t)w * h);
            REQUIRE(ls_texture_init(&tex, w, h, repeat ? LS_TEXTURE_REPEAT : LS_TEXTURE_CLAMP, t) == LS_OK);
            for (k = 0; k < 200; k++) {
                double u = 2.4 * rnd() - 0.7, v = 2.4 * rnd() - 0.7, ref[3];
                ls_real rgb[3];
                int c;
                u = (double)(ls_real)u;
                v = (double)(ls_real)v;
                ls_texture_sample(&tex, (ls_real)u, (ls_real)v, rgb);
                ref_sample(td, w, h, repeat, u, v, ref);
                for (c = 0; c < 3; c++) {
                    double e = fabs((double)rgb[c] - ref[c]);
                    if (e > maxerr) maxerr = e;
                }
            }
        }
    printf("     lookup vs tent formula: max abs error %.3g\n", maxerr);
    CHECK_MSG(maxerr <= (sizeof(ls_real) == 4 ? 1e-5 : 1e-13), "lookup error %.3g", maxerr);
    /* a texel centre returns that texel exactly; out-of-range and NaN do not read outside */
    {
        ls_texture tex;
        ls_real rgb[3];
        fill_texture(t, td, 3 * 35);
        REQUIRE(ls_texture_init(&tex, 7, 5, LS_TEXTURE_CLAMP, t) == LS_OK);
        ls_texture_sample(&tex, (ls_real)(3.5 / 7), (ls_real)(2.5 / 5), rgb);
        CHECK(rgb[0] == t[3 * (2 * 7 + 3)] && rgb[1] == t[3 * (2 * 7 + 3) + 1] && rgb[2] == t[3 * (2 * 7 + 3) + 2]);
        ls_texture_sample(&tex, (ls_real)1e30, (ls_real)-1e30, rgb);
        CHECK(rgb[0] == t[3 * 6] && rgb[2] == t[3 * 6 + 2]);
        tex.wrap_u = LS_TEXTURE_REPEAT;
        ls_texture_sample(&tex, (ls_real)-1e30, (ls_real)0.5, rgb);
        CHECK(rgb[0] == rgb[0]);
        ls_texture_sample(&tex, (ls_real)NAN, (ls_real)NAN, rgb); /* no crash; value unspecified */
    }
}

/* The adjoint: texel weights against the tent formula (the lookup is linear
 * in the texels), dT/duv against central differences away from kinks. */
static void sample_backward_matches(void)
{
    static ls_real t[3 * TW * TH], gt[3 * TW * TH];
    static double td[3 * TW * TH], unit[3 * TW * TH];
    int repeat, k;
    double max_w = 0, max_d = 0;
    for (repeat = 0; repeat < 2; repeat++) {
        ls_texture tex;
        fill_texture(t, td, 3 * TW * TH);
        REQUIRE(ls_texture_init(&tex, TW, TH, repeat ? LS_TEXTURE_REPEAT : LS_TEXTURE_CLAMP, t) == LS_OK);
        for (k = 0; k < 60; k++) {
            double u = (double)(ls_real)(1.6 * rnd() - 0.3), v = (double)(ls_real)(1.4 * rnd() - 0.2);
            ls_real g[3], duv[2];
            double gd[3], dref[2] = {0, 0}, h = 1e-6, rp[3], rm[3];
            uint32_t i;
            int c, a;
            for (c = 0; c < 3; c++) gd[c] = (double)(g[c] = (ls_real)(2 * rnd() - 1));
            memset(gt, 0, sizeof gt);
            ls_texture_sample_backward(&tex, (ls_real)u, (ls_real)v, g, gt, duv);
            for (i = 0; i < 3 * TW * TH; i++) { /* dL/dt_i = g . T(unit texel i) */
                double ref[3], e;
                memset(unit, 0, sizeof unit);
                unit[i] = 1;
                ref_sample(unit, TW, TH, repeat, u, v, ref);
                e = fabs((double)gt[i] - gd[i % 3] * ref[i % 3]);
                if (e > max_w) max_w = e;
            }
            if (!away_from_kinks(TW, TH, repeat, u, v, 1e-3)) continue;
            for (a = 0; a < 2; a++) {
                double uu = u + (a == 0 ? h : 0), vv = v + (a == 1 ? h : 0);
                ref_sample(td, TW, TH, repeat, uu, vv, rp);
                uu = u - (a == 0 ? h : 0);
                vv = v - (a == 1 ? h : 0);
                ref_sample(td, TW, TH, repeat, uu, vv, rm);
                for (c = 0; c < 3; c++) dref[a] += gd[c] * (rp[c] - rm[c]) / (2 * h);
            }
            for (a = 0; a < 2; a++) {
                double e = fabs((double)duv[a] - dref[a]) / fmax(fabs(dref[a]), 1e-3);
                if (e > max_d) max_d = e;
            }
            /* duv alone, texels alone (the NULL outputs) */
            {
                ls_real duv2[2];
                ls_texture_sample_backward(&tex, (ls_real)u, (ls_real)v, g, NULL, duv2);
                CHECK(duv2[0] == duv[0] && duv2[1] == duv[1]);
                ls_texture_sample_backward(&tex, (ls_real)u, (ls_real)v, g, NULL, NULL);
            }
        }
    }
    printf("     adjoint: texel weights max abs error %.3g, dT/duv max rel error %.3g\n", max_w, max_d);
    CHECK_MSG(max_w <= (sizeof(ls_real) == 4 ? 1e-6 : 1e-14), "texel weights %.3g", max_w);
    CHECK_MSG(max_d <= tol(), "dT/duv %.3g", max_d);
    /* clamped region: zero derivative */
    {
        ls_texture tex;
        ls_real g[3] = {1, 1, 1}, duv[2];
        REQUIRE(ls_texture_init(&tex, TW, TH, LS_TEXTURE_CLAMP, t) == LS_OK);
        ls_texture_sample_backward(&tex, (ls_real)-0.2, (ls_real)1.3, g, NULL, duv);
        CHECK(duv[0] == 0 && duv[1] == 0);
    }
}

static void texture_args(void)
{
    ls_texture tex;
    ls_real t[3] = {1, 1, 1};
    size_t bytes;
    CHECK(ls_texture_init(&tex, 0, 1, LS_TEXTURE_CLAMP, t) == LS_ERR_INVALID);
    CHECK(ls_texture_init(&tex, 1, 1, 7u, t) == LS_ERR_INVALID);
    CHECK(ls_texture_init(&tex, 1, 1, LS_TEXTURE_CLAMP, NULL) == LS_ERR_INVALID);
    CHECK(ls_texture_init(NULL, 1, 1, LS_TEXTURE_CLAMP, t) == LS_ERR_INVALID);
    CHECK(ls_texture_init(&tex, 1, 1, LS_TEXTURE_REPEAT, t) == LS_OK && ls_texture_check(&tex) == LS_OK);
    CHECK(ls_texture_check(NULL) == LS_ERR_INVALID);
    CHECK(ls_texture_bytes(4, 3, &bytes) == LS_OK && bytes >= 36 * sizeof(ls_real));
    CHECK(ls_texture_bytes(0, 3, &bytes) == LS_ERR_INVALID);
    CHECK(ls_texture_bytes(1, 1, NULL) == LS_ERR_INVALID);
    CHECK(ls_texture_bytes(0xFFFFFFFFu, 0xFFFFFFFFu, &bytes) == LS_ERR_TOO_LARGE || sizeof(size_t) > 8);
}

/* ---- textured scenes ---- */

typedef struct scene {
    uint32_t nv, nt, repeat;
    double p[3 * MAXV], uv[2 * MAXV], col[3 * MAXV], tex[3 * TW * TH];
    uint32_t f[3 * MAXT];
    double mvp[16];
    ls_shade_opts opts;
    uint32_t tri[IMG * SS * IMG * SS];
    double w[4 * IMG * IMG];
} scene;

static ls_real sh_coef[27], colors_r[3 * MAXV], uvs_r[2 * MAXV], tex_r[3 * TW * TH];
static ls_light lights[2];
static ls_texture texture;

static void ref_normals(const scene *sc, const double *p, double *nrm)
{
    uint32_t t, v;
    int k, q;
    for (v = 0; v < 3 * sc->nv; v++) nrm[v] = 0;
    for (t = 0; t < sc->nt; t++) {
        const uint32_t *f = sc->f + 3 * t;
        double a[3], b[3], n[3], l;
        for (k = 0; k < 3; k++) {
            a[k] = p[3 * f[1] + (uint32_t)k] - p[3 * f[0] + (uint32_t)k];
            b[k] = p[3 * f[2] + (uint32_t)k] - p[3 * f[0] + (uint32_t)k];
        }
        n[0] = a[1] * b[2] - a[2] * b[1];
        n[1] = a[2] * b[0] - a[0] * b[2];
        n[2] = a[0] * b[1] - a[1] * b[0];
        l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (l == 0) continue;
        for (q = 0; q < 3; q++)
            for (k = 0; k < 3; k++) nrm[3 * f[q] + (uint32_t)k] += n[k] / l;
    }
    for (v = 0; v < sc->nv; v++) {
        double *n = nrm + 3 * v, l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (k = 0; k < 3; k++) n[k] = l > 0 ? n[k] / l : 0;
    }
}

/* SH irradiance / pi by the explicit polynomial in the basis functions. */
static double ref_sh(const ls_real *L, const double n[3])
{
    const double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    double x = n[0], y = n[1], z = n[2];
    double e = c1 * (double)L[8] * (x * x - y * y) + c3 * (double)L[6] * z * z + c4 * (double)L[0] -
               c5 * (double)L[6] + 2 * c1 * ((double)L[4] * x * y + (double)L[7] * x * z + (double)L[5] * y * z) +
               2 * c2 * ((double)L[3] * x + (double)L[1] * y + (double)L[2] * z);
    return e / TEST_PI;
}

static void ref_shade(const scene *sc, const double *nrm, const uint32_t *f, const double b[3], const double *uv,
                      const double *col, const double *tex, double rgb[3])
{
    const ls_shade_opts *o = &sc->opts;
    double alb[3] = {1, 1, 1}, t[3], u = 0, v = 0;
    int c, k;
    if (o->vertex_colors != NULL)
        for (c = 0; c < 3; c++)
            alb[c] = b[0] * col[3 * f[0] + (uint32_t)c] + b[1] * col[3 * f[1] + (uint32_t)c] +
                     b[2] * col[3 * f[2] + (uint32_t)c];
    for (k = 0; k < 3; k++) {
        u += b[k] * uv[2 * f[k]];
        v += b[k] * uv[2 * f[k] + 1];
    }
    ref_sample(tex, TW, TH, (int)sc->repeat, u, v, t);
    for (c = 0; c < 3; c++) alb[c] *= t[c];
    if (o->mode == LS_SHADE_COLOR) {
        for (c = 0; c < 3; c++) rgb[c] = alb[c];
        return;
    }
    {
        double n[3];
        for (c = 0; c < 3; c++)
            n[c] = b[0] * nrm[3 * f[0] + (uint32_t)c] + b[1] * nrm[3 * f[1] + (uint32_t)c] +
                   b[2] * nrm[3 * f[2] + (uint32_t)c];
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
    }
    for (c = 0; c < 3; c++) rgb[c] *= alb[c];
}

/* The reference image (RGB per pixel, background excluded) or, with img NULL, L = sum w I. */
static double ref_render(const scene *sc, const double *p, const double *uv, const double *col, const double *tex,
                         double *img)
{
    double clip[4 * MAXV], nrm[3 * MAXV], L = 0;
    uint32_t v, sx, sy;
    int r, c, k;
    for (v = 0; v < sc->nv; v++)
        for (r = 0; r < 4; r++)
            clip[4 * v + (uint32_t)r] = sc->mvp[4 * r] * p[3 * v] + sc->mvp[4 * r + 1] * p[3 * v + 1] +
                                        sc->mvp[4 * r + 2] * p[3 * v + 2] + sc->mvp[4 * r + 3];
    ref_normals(sc, p, nrm);
    if (img != NULL) memset(img, 0, 3 * IMG * IMG * sizeof *img);
    for (sy = 0; sy < IMG * SS; sy++)
        for (sx = 0; sx < IMG * SS; sx++) {
            uint32_t id = sc->tri[sy * IMG * SS + sx], pix = (sy / SS) * IMG + sx / SS;
            double px = (2.0 * sx + 1) / (IMG * SS) - 1, py = 1 - (2.0 * sy + 1) / (IMG * SS);
            double X[3], Y[3], b[3], sum = 0, rgb[3];
            const uint32_t *f;
            if (id == 0) continue;
            f = sc->f + 3 * (id - 1);
            for (k = 0; k < 3; k++) {
                X[k] = clip[4 * f[k]] / clip[4 * f[k] + 3];
                Y[k] = clip[4 * f[k] + 1] / clip[4 * f[k] + 3];
            }
            for (k = 0; k < 3; k++) { /* screen-space area opposite vertex k, over W_k */
                int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
                b[k] = ((X[k1] - px) * (Y[k2] - py) - (X[k2] - px) * (Y[k1] - py)) / clip[4 * f[k] + 3];
                sum += b[k];
            }
            for (k = 0; k < 3; k++) b[k] /= sum;
            ref_shade(sc, nrm, f, b, uv, col, tex, rgb);
            for (c = 0; c < 3; c++) {
                if (img != NULL) img[3 * pix + (uint32_t)c] += rgb[c] / (SS * SS);
                L += sc->w[4 * pix + (uint32_t)c] * rgb[c] / (SS * SS);
            }
        }
    return L;
}

static void set_camera(scene *sc, double dist)
{
    ls_real view[16], proj[16], mvp[16], eye[3], tgt[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    int k;
    eye[0] = (ls_real)(0.35 * dist);
    eye[1] = (ls_real)(0.45 * dist);
    eye[2] = (ls_real)(0.82 * dist);
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_perspective((ls_real)0.9, LS_FOV_Y, (ls_real)1, (ls_real)0.3, (ls_real)50, proj);
    ls_mat4_mul(proj, view, mvp);
    for (k = 0; k < 16; k++) sc->mvp[k] = (double)mvp[k];
}

/* A tilted quad (two triangles), UVs over most of the texture (clamp). */
static void scene_quad(scene *sc)
{
    static const double q[4][3] = {{-1, -0.9, 0.1}, {1.1, -1, -0.1}, {1, 1, 0.2}, {-0.9, 1.05, 0}};
    static const double quv[4][2] = {{0.04, 0.95}, {0.97, 0.93}, {0.96, 0.05}, {0.03, 0.06}};
    uint32_t v;
    int k;
    memset(sc, 0, sizeof *sc);
    sc->nv = 4;
    sc->nt = 2;
    for (v = 0; v < 4; v++) {
        for (k = 0; k < 3; k++) sc->p[3 * v + (uint32_t)k] = q[v][k] + 0.05 * (rnd() - 0.5);
        for (k = 0; k < 2; k++) sc->uv[2 * v + (uint32_t)k] = (double)(ls_real)(quv[v][k] + 0.02 * (rnd() - 0.5));
    }
    sc->f[0] = 0; sc->f[1] = 1; sc->f[2] = 2;
    sc->f[3] = 0; sc->f[4] = 2; sc->f[5] = 3;
    set_camera(sc, 3.0);
}

/* An octahedron with UVs beyond [0, 1] in u (repeat). */
static void scene_octahedron(scene *sc)
{
    static const int of[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    static const double op[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    uint32_t v, t;
    int k;
    memset(sc, 0, sizeof *sc);
    sc->nv = 6;
    sc->nt = 8;
    sc->repeat = 1;
    for (v = 0; v < 6; v++) {
        for (k = 0; k < 3; k++) sc->p[3 * v + (uint32_t)k] = op[v][k] * (1 + 0.15 * (rnd() - 0.5)) + 0.1 * (rnd() - 0.5);
        sc->uv[2 * v] = (double)(ls_real)(1.8 * rnd() - 0.4);
        sc->uv[2 * v + 1] = (double)(ls_real)(0.1 + 0.8 * rnd());
    }
    for (t = 0; t < 8; t++)
        for (k = 0; k < 3; k++) sc->f[3 * t + (uint32_t)k] = (uint32_t)of[t][k];
    set_camera(sc, 2.7);
}

static void setup_shading(scene *sc, uint32_t mode, int renorm, int with_colors)
{
    uint32_t i;
    int k;
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
    for (i = 0; i < 3 * sc->nv; i++) colors_r[i] = (ls_real)(sc->col[i] = (double)(ls_real)(0.2 + 0.7 * rnd()));
    for (i = 0; i < 2 * sc->nv; i++) uvs_r[i] = (ls_real)sc->uv[i];
    fill_texture(tex_r, sc->tex, 3 * TW * TH);
    ls_texture_init(&texture, TW, TH, sc->repeat ? LS_TEXTURE_REPEAT : LS_TEXTURE_CLAMP, tex_r);
    sc->opts.vertex_colors = with_colors ? colors_r : NULL;
    sc->opts.texture = &texture;
    sc->opts.uvs = uvs_r;
    for (i = 0; i < 4 * IMG * IMG; i++) sc->w[i] = (double)(ls_real)(2 * rnd() - 1);
}

static unsigned char *arena_buf;
#define ARENA_BYTES (2u << 20)

typedef struct lib_out {
    ls_real img[4 * IMG * IMG];
    ls_real gp[3 * MAXV], gc[3 * MAXV], guv[2 * MAXV], gt[3 * TW * TH];
} lib_out;

/* The library forward (keeping the ids in sc->tri) and backward. */
static int lib_run(scene *sc, lib_out *out)
{
    ls_arena arena;
    ls_vis vis;
    ls_real pos[3 * MAXV], mvp[16], nrm[3 * MAXV], gn[3 * MAXV], gimg[4 * IMG * IMG];
    ls_shade_grads g;
    uint32_t i;
    if (ls_arena_init(&arena, arena_buf, ARENA_BYTES) != LS_OK) return 0;
    for (i = 0; i < 3 * sc->nv; i++) pos[i] = (ls_real)sc->p[i];
    for (i = 0; i < 16; i++) mvp[i] = (ls_real)sc->mvp[i];
    if (ls_vis_init(&vis, &arena, IMG, IMG, SS, MAXV) != LS_OK) return 0;
    if (ls_raster(&vis, &(ls_view){.positions = pos, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
            .mvp = mvp}, &arena, NULL) != LS_OK) return 0;
    memcpy(sc->tri, vis.tri, sizeof sc->tri);
    if (ls_shade_vertex_normals(pos, sc->nv, sc->f, sc->nt, nrm, NULL) != LS_OK) return 0;
    if (ls_shade(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
            .normals = nrm, .opts = &sc->opts}, out->img, NULL) != LS_OK) return 0;
    for (i = 0; i < 4 * IMG * IMG; i++) gimg[i] = (ls_real)sc->w[i];
    memset(out->gp, 0, sizeof out->gp);
    memset(out->gc, 0, sizeof out->gc);
    memset(out->guv, 0, sizeof out->guv);
    memset(out->gt, 0, sizeof out->gt);
    memset(gn, 0, sizeof gn);
    g.positions = out->gp;
    g.normals = gn;
    g.colors = out->gc;
    g.texels = out->gt;
    g.uvs = out->guv;
    if (ls_shade_backward_grads(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt,
            .vertex_count = sc->nv, .normals = nrm, .opts = &sc->opts, .mvp = mvp}, gimg, &g, NULL) != LS_OK) return 0;
    if (sc->opts.mode != LS_SHADE_COLOR &&
        ls_vertex_normals_backward(pos, sc->nv, sc->f, sc->nt, gn, out->gp, &arena, NULL) != LS_OK)
        return 0;
    return 1;
}

/* Max relative error of analytic a[0..n) against central differences of the
 * reference loss in the double array x (perturbed in place), with an absolute
 * floor of `floor_frac` times the largest difference. */
static double fd_check(scene *sc, double *x, const ls_real *a, uint32_t n, double h, double floor_frac,
                       double *maxfd_out)
{
    static double fd[3 * TW * TH];
    double maxfd = 0, maxrel = 0;
    uint32_t i;
    for (i = 0; i < n; i++) {
        double save = x[i], lp, lm;
        x[i] = save + h;
        lp = ref_render(sc, sc->p, sc->uv, sc->col, sc->tex, NULL);
        x[i] = save - h;
        lm = ref_render(sc, sc->p, sc->uv, sc->col, sc->tex, NULL);
        x[i] = save;
        fd[i] = (lp - lm) / (2 * h);
        if (fabs(fd[i]) > maxfd) maxfd = fabs(fd[i]);
    }
    for (i = 0; i < n; i++) {
        double e = fabs((double)a[i] - fd[i]) / fmax(fabs(fd[i]), floor_frac * maxfd);
        CHECK_MSG(isfinite((double)a[i]), "non-finite gradient %u", i);
        if (e > maxrel) maxrel = e;
    }
    *maxfd_out = maxfd;
    return maxrel;
}

/* Gradients to texels, UVs, vertex colours and positions against central
 * differences of the reference; the forward against the reference image. */
static void run_modes(void (*make)(scene *), const char *scene_name)
{
    static scene sc;
    static lib_out out;
    static double refimg[3 * IMG * IMG];
    static const struct { uint32_t mode; int renorm, colors; const char *name; } modes[] = {
        {LS_SHADE_COLOR, 0, 0, "unlit texture"},
        {LS_SHADE_COLOR, 0, 1, "unlit texture x colours"},
        {LS_SHADE_SH, 0, 0, "SH x texture"},
        {LS_SHADE_LAMBERT, 1, 1, "Lambert renorm x colours x texture"},
    };
    unsigned m;
    for (m = 0; m < sizeof modes / sizeof modes[0]; m++) {
        double et, euv, ep, ec = 0, mt, muv, mp, mc = 0, fwd = 0, fl = sizeof(ls_real) == 4 ? 1e-4 : 1e-7;
        uint32_t i, covered = 0;
        make(&sc);
        setup_shading(&sc, modes[m].mode, modes[m].renorm, modes[m].colors);
        REQUIRE(lib_run(&sc, &out));
        for (i = 0; i < (uint32_t)(IMG * SS * IMG * SS); i++) covered += sc.tri[i] != 0;
        CHECK_MSG(covered > 300, "%s: only %u covered samples", scene_name, covered);
        /* forward: the library's snapped barycentrics against exact ones */
        ref_render(&sc, sc.p, sc.uv, sc.col, sc.tex, refimg);
        for (i = 0; i < IMG * IMG; i++) {
            int c;
            double a = (double)out.img[4 * i + 3], bgw = 1 - a; /* background part of the pixel */
            for (c = 0; c < 3; c++) {
                double e = fabs((double)out.img[4 * i + (uint32_t)c] - refimg[3 * i + (uint32_t)c] -
                                bgw * (double)sc.opts.background[c]);
                if (e > fwd) fwd = e;
            }
        }
        /* the image is linear in the texels and in the vertex colours: a large step is exact */
        et = fd_check(&sc, sc.tex, out.gt, 3 * TW * TH, 0.25, fl, &mt);
        euv = fd_check(&sc, sc.uv, out.guv, 2 * sc.nv, 1e-6, fl, &muv);
        ep = fd_check(&sc, sc.p, out.gp, 3 * sc.nv, 1e-6, fl, &mp);
        if (modes[m].colors) ec = fd_check(&sc, sc.col, out.gc, 3 * sc.nv, 0.25, fl, &mc);
        printf("     %s/%-36s fwd %.2g | rel err texels %.2g uv %.2g pos %.2g col %.2g (max |g| %.2g %.2g %.2g %.2g)\n",
               scene_name, modes[m].name, fwd, et, euv, ep, ec, mt, muv, mp, mc);
        CHECK_MSG(fwd < 2e-2, "%s/%s: forward differs from the reference by %.3g", scene_name, modes[m].name, fwd);
        CHECK_MSG(mt > 0 && muv > 0 && mp > 0, "%s/%s: zero gradients", scene_name, modes[m].name);
        CHECK_MSG(et <= tol() && euv <= tol() && ep <= tol() && ec <= tol(), "%s/%s: gradient error", scene_name,
                  modes[m].name);
    }
}

static void textured_quad_fd(void) { run_modes(scene_quad, "quad"); }
static void textured_octahedron_repeat_fd(void) { run_modes(scene_octahedron, "octahedron"); }

/* A 1 x 1 white texture changes no bit of the image or of the position and
 * colour gradients; the textured path is deterministic; argument errors. */
static void white_texture_is_identity(void)
{
    static scene sc;
    static lib_out a, b;
    static ls_real white[3] = {1, 1, 1};
    ls_texture wt;
    uint32_t mode;
    for (mode = LS_SHADE_SH; mode <= LS_SHADE_COLOR; mode++) {
        scene_octahedron(&sc);
        setup_shading(&sc, mode, 1, 1);
        sc.opts.texture = NULL;
        REQUIRE(lib_run(&sc, &a));
        REQUIRE(ls_texture_init(&wt, 1, 1, LS_TEXTURE_REPEAT, white) == LS_OK);
        sc.opts.texture = &wt;
        REQUIRE(lib_run(&sc, &b));
        CHECK(memcmp(a.img, b.img, sizeof a.img) == 0);
        CHECK(memcmp(a.gp, b.gp, sizeof a.gp) == 0);
        CHECK(memcmp(a.gc, b.gc, sizeof a.gc) == 0);
    }
    setup_shading(&sc, LS_SHADE_SH, 0, 1);
    REQUIRE(lib_run(&sc, &a));
    REQUIRE(lib_run(&sc, &b));
    CHECK(memcmp(&a, &b, sizeof a) == 0);
    {
        ls_arena arena;
        ls_vis vis;
        ls_real pos[3 * MAXV], mvp[16], nrm[3 * MAXV];
        uint32_t i;
        REQUIRE(ls_arena_init(&arena, arena_buf, ARENA_BYTES) == LS_OK);
        for (i = 0; i < 3 * sc.nv; i++) pos[i] = (ls_real)sc.p[i];
        for (i = 0; i < 16; i++) mvp[i] = (ls_real)sc.mvp[i];
        REQUIRE(ls_vis_init(&vis, &arena, IMG, IMG, SS, MAXV) == LS_OK);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = sc.f, .triangle_count = sc.nt,
                .vertex_count = sc.nv, .mvp = mvp}, &arena, NULL) == LS_OK);
        REQUIRE(ls_shade_vertex_normals(pos, sc.nv, sc.f, sc.nt, nrm, NULL) == LS_OK);
        sc.opts.uvs = NULL;
        CHECK(ls_shade(&(ls_view){.vis = &vis, .indices = sc.f, .triangle_count = sc.nt, .vertex_count = sc.nv,
                .normals = nrm, .opts = &sc.opts}, a.img, NULL) == LS_ERR_INVALID);
        sc.opts.uvs = uvs_r;
        texture.wrap_u = 9;
        CHECK(ls_shade(&(ls_view){.vis = &vis, .indices = sc.f, .triangle_count = sc.nt, .vertex_count = sc.nv,
                .normals = nrm, .opts = &sc.opts}, a.img, NULL) == LS_ERR_INVALID);
        texture.wrap_u = LS_TEXTURE_CLAMP;
        sc.opts.mode = LS_SHADE_COLOR; /* unlit: a texture alone is enough */
        sc.opts.vertex_colors = NULL;
        CHECK(ls_shade(&(ls_view){.vis = &vis, .indices = sc.f, .triangle_count = sc.nt, .vertex_count = sc.nv,
                .normals = nrm, .opts = &sc.opts}, a.img, NULL) == LS_OK);
        CHECK(ls_shade_backward_grads(&(ls_view){.vis = &vis, .indices = sc.f, .triangle_count = sc.nt,
                .vertex_count = sc.nv, .normals = nrm, .opts = &sc.opts, .mvp = mvp}, a.img, NULL, NULL) ==
              LS_ERR_INVALID);
    }
}

/* The silhouette term shades both sides of an edge with the textured colour
 * (ls_shade_point): a white texture changes no bit of it, a constant texture
 * c matches vertex colours c (to rounding: the colours are interpolated),
 * and a darker texture gives another gradient. */
static void silhouette_sees_texture(void)
{
    static scene sc;
    static ls_real cols[3 * MAXV], gimg[4 * IMG * IMG];
    ls_real pos[3 * MAXV], mvp[16], g[4][3 * MAXV];
    ls_real white[3] = {1, 1, 1}, c[3] = {0.8f, 0.3f, 0.5f}, dark[3] = {0.1f, 0.1f, 0.1f};
    ls_texture ct[3];
    ls_arena arena;
    ls_vis vis;
    ls_edge_table et;
    uint32_t i;
    double maxd = 0, maxg = 0;
    int k;
    scene_octahedron(&sc);
    setup_shading(&sc, LS_SHADE_COLOR, 0, 0);
    for (i = 0; i < 3 * sc.nv; i++) cols[i] = c[i % 3];
    for (i = 0; i < 4 * IMG * IMG; i++) gimg[i] = (ls_real)sc.w[i];
    REQUIRE(ls_arena_init(&arena, arena_buf, ARENA_BYTES) == LS_OK);
    for (i = 0; i < 3 * sc.nv; i++) pos[i] = (ls_real)sc.p[i];
    for (i = 0; i < 16; i++) mvp[i] = (ls_real)sc.mvp[i];
    REQUIRE(ls_vis_init(&vis, &arena, IMG, IMG, SS, MAXV) == LS_OK);
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = sc.f, .triangle_count = sc.nt,
            .vertex_count = sc.nv, .mvp = mvp}, &arena, NULL) == LS_OK);
    REQUIRE(ls_edge_table_build(&et, sc.f, sc.nt, sc.nv, &arena, NULL) == LS_OK);
    REQUIRE(ls_texture_init(&ct[0], 1, 1, LS_TEXTURE_CLAMP, white) == LS_OK);
    REQUIRE(ls_texture_init(&ct[1], 1, 1, LS_TEXTURE_CLAMP, c) == LS_OK);
    REQUIRE(ls_texture_init(&ct[2], 1, 1, LS_TEXTURE_CLAMP, dark) == LS_OK);
    memset(g, 0, sizeof g);
    for (k = 0; k < 4; k++) { /* vertex colours c; + white texture; texture c alone; dark texture alone */
        sc.opts.vertex_colors = k < 2 ? cols : NULL;
        sc.opts.texture = k == 0 ? NULL : &ct[k - 1];
        REQUIRE(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = sc.f, .triangle_count = sc.nt,
                .vertex_count = sc.nv, .opts = &sc.opts, .mvp = mvp, .table = &et, .boost = 1}, gimg, g[k], &arena,
                NULL) == LS_OK);
    }
    CHECK(memcmp(g[0], g[1], sizeof g[0]) == 0);
    for (i = 0; i < 3 * sc.nv; i++) {
        double d = fabs((double)g[0][i] - (double)g[2][i]);
        if (d > maxd) maxd = d;
        if (fabs((double)g[0][i]) > maxg) maxg = fabs((double)g[0][i]);
    }
    CHECK_MSG(maxg > 0 && maxd <= (sizeof(ls_real) == 4 ? 1e-4 : 1e-12) * maxg, "texture c vs colours c: %.3g", maxd);
    CHECK(memcmp(g[0], g[3], sizeof g[0]) != 0);
}

int main(void)
{
    TEST_INIT("test_texture");
    arena_buf = (unsigned char *)malloc(ARENA_BYTES);
    if (arena_buf == NULL) return 1;
    TEST_RUN(texture_args);
    TEST_RUN(sample_matches_reference);
    TEST_RUN(sample_backward_matches);
    TEST_RUN(textured_quad_fd);
    TEST_RUN(textured_octahedron_repeat_fd);
    TEST_RUN(white_texture_is_identity);
    TEST_RUN(silhouette_sees_texture);
    free(arena_buf);
    return TEST_END();
}
