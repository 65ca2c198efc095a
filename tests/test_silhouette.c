/* tests/test_silhouette.c - silhouette derivatives against central finite
 * differences of an independent float64 exact-coverage forward.
 *
 * The reference renders convex layers exactly: for each pixel square P the
 * part of (layer n P) by Sutherland-Hodgman clipping, minus the part it
 * shares with nearer layers (scenes have no triple overlaps). Flat colours:
 * area x colour; per-vertex colours (perspective-correct): the integral of
 * the colour over those polygons (fans of triangles, Duffy-mapped 8 x 8
 * Gauss points after one split into four). Plus the background on the rest;
 * alpha = covered area. Closed convex meshes in mask mode are one layer: the
 * convex hull of the projected vertices. With flat colours the interior term
 * is zero, so the finite differences of L = sum w I measure the silhouette
 * term alone; with varying colours the interior term is removed by also
 * differencing with the polygons held at the base positions.
 *
 * Scenes: orthographic (1e-6 relative, every scene) and perspective (smooth
 * weights; pooled: at least 95 % of configurations within 1e-3 in double,
 * every value finite; the distribution is printed): overlaps whose edges
 * cross inside pixels, perspective colours, near-plane cuts inside the
 * image, sub-pixel triangles, icospheres (ls_icosphere levels 1 and 2).
 * Also: translation and scaling invariants (a triangle; a fan of 150 thin
 * triangles, ~150 candidates per piece at its centre), boost and determinism, the
 * scratch query and arena sweep, the pair mode against FD of its own
 * forward, and the pair mode's error against the exact gradient (printed). */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/camera.h>
#include <largesteps/silhouette.h>
#include <largesteps/primitive.h>
#include <largesteps/math.h>
#include <largesteps/mesh_io.h>
#include "../port/posix/ls_posix.h"
#include "mesh_view.h"

#define IMG 12
#define MAXV 170
#define MAXT 330
#define MAXP 64

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static double rnd(void)
{
    return test_rng_unit(&rng_state);
}

typedef struct scene {
    uint32_t nv, nt, mask; /* mask: one colour (1), the mesh's convex hull is the layer */
    double p[3 * MAXV];
    uint32_t f[3 * MAXT];
    double mvp[16];
    double col[3 * MAXT]; /* flat colour per triangle (COLOR mode) */
    uint32_t vary;        /* 1: per-vertex colours vcol, perspective-correct (COLOR mode) */
    double vcol[3 * MAXV];
    double bg[3];
    double w[4 * IMG * IMG];
} scene;

/* ---- exact coverage ---- */

#include "box_ref.h"

static void to_window(const scene *sc, const double *q, double *x, double *y, double *z)
{
    ref_to_window(sc->mvp, IMG, q, x, y, z);
}

static double tri_window(const scene *sc, uint32_t t, poly *out, int *near_inside)
{
    return ref_tri_window(sc->mvp, IMG, sc->p, sc->f, t, out, near_inside);
}

/* Positions the shading of the reference uses (NULL: the scene's): with
 * the geometry of the polygons held, the finite differences of the loss
 * give the interior term alone. */
static const double *shade_pos;

/* Window corners and 1/w of triangle t (shading positions). */
static void ref_corners(const scene *sc, uint32_t t, double wx[3], double wy[3], double iw[3])
{
    const double *P = shade_pos != NULL ? shade_pos : sc->p;
    int k, r;
    for (k = 0; k < 3; k++) {
        const double *q = P + 3 * sc->f[3 * t + k];
        double cc[4];
        for (r = 0; r < 4; r++) cc[r] = sc->mvp[4 * r] * q[0] + sc->mvp[4 * r + 1] * q[1] + sc->mvp[4 * r + 2] * q[2] + sc->mvp[4 * r + 3];
        wx[k] = (cc[0] / cc[3] + 1) * 0.5 * IMG;
        wy[k] = (1 - cc[1] / cc[3]) * 0.5 * IMG;
        iw[k] = 1 / cc[3];
    }
}

/* Colour of triangle t at window point (x, y): screen-space barycentrics of
 * the projected corners, made perspective-correct with 1/w. */
static void ref_colour(const scene *sc, uint32_t t, const double *wx, const double *wy, const double *iw, double x,
                       double y, double rgb[3])
{
    double l[3], den, s = 0;
    int k, c;
    den = (wx[1] - wx[0]) * (wy[2] - wy[0]) - (wx[2] - wx[0]) * (wy[1] - wy[0]);
    l[1] = ((x - wx[0]) * (wy[2] - wy[0]) - (wx[2] - wx[0]) * (y - wy[0])) / den;
    l[2] = ((wx[1] - wx[0]) * (y - wy[0]) - (x - wx[0]) * (wy[1] - wy[0])) / den;
    l[0] = 1 - l[1] - l[2];
    for (k = 0; k < 3; k++) {
        l[k] *= iw[k];
        s += l[k];
    }
    for (c = 0; c < 3; c++) {
        rgb[c] = 0;
        for (k = 0; k < 3; k++) rgb[c] += l[k] / s * sc->vcol[3 * sc->f[3 * t + k] + c];
    }
}

/* Integral of triangle t's colour over the triangle (x0 y0, x1 y1, x2 y2),
 * mapped from the square (Duffy) with 8 x 8 Gauss points, after `levels`
 * splits into four (midpoints). */
static int ref_levels = 1;
static void ref_tri(const scene *sc, uint32_t t, const double *x, const double *y, double rgb[3])
{
    static const double gx[8] = {0.019855071751231856, 0.10166676129318664, 0.2372337950418355, 0.4082826787521751,
                                 0.5917173212478249, 0.7627662049581645, 0.8983332387068134, 0.9801449282487681};
    static const double gw[8] = {0.05061426814518813, 0.11119051722668724, 0.15685332293894364, 0.18134189168918100,
                                 0.18134189168918100, 0.15685332293894364, 0.11119051722668724, 0.05061426814518813};
    int i, j, c, n = 1 << ref_levels, a, b;
    double cwx[3], cwy[3], ciw[3];
    ref_corners(sc, t, cwx, cwy, ciw);
    /* split into n^2 similar sub-triangles on the barycentric lattice */
    for (a = 0; a < n; a++)
        for (b = 0; a + b < n; b++) {
            int up;
            for (up = 0; up < 2; up++) {
                double px[3], py[3], l[3][2], det;
                int k;
                if (up == 1 && a + b + 1 >= n) break;
                if (up == 0) {
                    l[0][0] = a; l[0][1] = b; l[1][0] = a + 1; l[1][1] = b; l[2][0] = a; l[2][1] = b + 1;
                } else {
                    l[0][0] = a + 1; l[0][1] = b; l[1][0] = a + 1; l[1][1] = b + 1; l[2][0] = a; l[2][1] = b + 1;
                }
                for (k = 0; k < 3; k++) {
                    double u = l[k][0] / n, v = l[k][1] / n;
                    px[k] = x[0] + u * (x[1] - x[0]) + v * (x[2] - x[0]);
                    py[k] = y[0] + u * (y[1] - y[0]) + v * (y[2] - y[0]);
                }
                det = fabs((px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]));
                for (i = 0; i < 8; i++)
                    for (j = 0; j < 8; j++) {
                        double u = gx[i], v = gx[j], col[3];
                        double qx = px[0] + u * (px[1] - px[0]) + u * v * (px[2] - px[1]);
                        double qy = py[0] + u * (py[1] - py[0]) + u * v * (py[2] - py[1]);
                        ref_colour(sc, t, cwx, cwy, ciw, qx, qy, col);
                        for (c = 0; c < 3; c++) rgb[c] += gw[i] * gw[j] * u * det * col[c];
                    }
            }
        }
}

/* Integral of triangle t's colour over convex polygon a (rgb), by a fan. */
static void ref_integrate(const scene *sc, uint32_t t, const poly *a, double rgb[3])
{
    int k;
    rgb[0] = rgb[1] = rgb[2] = 0;
    for (k = 1; k + 1 < a->n; k++) {
        double x[3] = {a->x[0], a->x[k], a->x[k + 1]}, y[3] = {a->y[0], a->y[k], a->y[k + 1]};
        ref_tri(sc, t, x, y, rgb);
    }
}

static double ref_loss(const scene *sc)
{
    poly layer[16], pix, a, b;
    double col[16][3], depth[16], L = 0;
    int nl = 0, i, j, c;
    uint32_t px, py;
    if (sc->mask) {
        static double x[MAXV], y[MAXV];
        double z;
        for (i = 0; i < (int)sc->nv; i++) to_window(sc, sc->p + 3 * i, &x[i], &y[i], &z);
        hull(x, y, (int)sc->nv, &layer[0]);
        col[0][0] = col[0][1] = col[0][2] = 1;
        nl = 1;
    } else {
        for (i = 0; i < (int)sc->nt; i++) {
            depth[i] = tri_window(sc, (uint32_t)i, &layer[i], NULL);
            for (c = 0; c < 3; c++) col[i][c] = sc->col[3 * i + c];
        }
        nl = (int)sc->nt;
    }
    for (py = 0; py < IMG; py++)
        for (px = 0; px < IMG; px++) {
            double rgb[3] = {0, 0, 0}, cover = 0, f[3];
            const double *w = sc->w + 4 * (py * IMG + px);
            pix.n = 4;
            pix.x[0] = px;     pix.y[0] = py;
            pix.x[1] = px + 1; pix.y[1] = py;
            pix.x[2] = px + 1; pix.y[2] = py + 1;
            pix.x[3] = px;     pix.y[3] = py + 1;
            for (i = 0; i < nl; i++) {
                double vis;
                intersect(&pix, &layer[i], &a);
                if (a.n < 3) continue;
                vis = area(&a);
                if (sc->vary) {
                    ref_integrate(sc, (uint32_t)i, &a, f);
                    for (c = 0; c < 3; c++) rgb[c] += f[c];
                } else {
                    for (c = 0; c < 3; c++) rgb[c] += vis * col[i][c];
                }
                for (j = 0; j < nl; j++)
                    if (j != i && depth[j] < depth[i] && !sc->mask) {
                        double o;
                        intersect(&a, &layer[j], &b);
                        if (b.n < 3) continue;
                        o = area(&b);
                        vis -= o;
                        if (sc->vary) {
                            ref_integrate(sc, (uint32_t)i, &b, f);
                            for (c = 0; c < 3; c++) rgb[c] -= f[c];
                        } else {
                            for (c = 0; c < 3; c++) rgb[c] -= o * col[i][c];
                        }
                    }
                cover += vis;
            }
            for (c = 0; c < 3; c++) L += w[c] * (rgb[c] + (1 - cover) * sc->bg[c]);
            L += w[3] * cover;
        }
    return L;
}

/* ---- the library side ---- */

static unsigned char *arena_buf;
#define ARENA_BYTES (4u << 20)

static int lib_grad(const scene *sc, ls_real boost, ls_real *gp)
{
    ls_arena arena;
    ls_vis vis;
    ls_edge_table et;
    ls_shade_opts o;
    ls_real pos[3 * MAXV], mvp[16], colors[3 * MAXV], gimg[4 * IMG * IMG];
    uint32_t i, k;
    if (ls_arena_init(&arena, arena_buf, ARENA_BYTES) != LS_OK) return 0;
    for (i = 0; i < 3 * sc->nv; i++) pos[i] = (ls_real)sc->p[i];
    for (i = 0; i < 16; i++) mvp[i] = (ls_real)sc->mvp[i];
    ls_shade_opts_init(&o);
    o.mode = sc->mask ? LS_SHADE_MASK : LS_SHADE_COLOR;
    for (i = 0; i < 3; i++) o.background[i] = (ls_real)sc->bg[i];
    for (i = 0; i < sc->nt; i++)
        for (k = 0; k < 3; k++) { /* flat: every vertex of the triangle has its colour */
            colors[3 * sc->f[3 * i + k]] = (ls_real)sc->col[3 * i];
            colors[3 * sc->f[3 * i + k] + 1] = (ls_real)sc->col[3 * i + 1];
            colors[3 * sc->f[3 * i + k] + 2] = (ls_real)sc->col[3 * i + 2];
        }
    if (sc->vary)
        for (i = 0; i < 3 * sc->nv; i++) colors[i] = (ls_real)sc->vcol[i];
    o.vertex_colors = sc->mask ? NULL : colors;
    for (i = 0; i < 4 * IMG * IMG; i++) gimg[i] = (ls_real)sc->w[i];
    for (i = 0; i < 3 * sc->nv; i++) gp[i] = 0;
    if (ls_vis_init(&vis, &arena, IMG, IMG, 1, MAXV) != LS_OK) return 0;
    if (ls_raster(&vis, &(ls_view){.positions = pos, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
            .mvp = mvp}, &arena, NULL) != LS_OK) return 0;
    if (ls_edge_table_build(&et, sc->f, sc->nt, sc->nv, &arena, NULL) != LS_OK) return 0;
    return ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt,
            .vertex_count = sc->nv, .opts = &o, .mvp = mvp, .table = &et, .boost = boost}, gimg, gp, &arena,
            NULL) == LS_OK;
}

typedef struct fdstats {
    int n;
    double max_rel, floor;
} fdstats;

static double tol(void);
static int fd_quiet;
static double fd_one(scene *sc, uint32_t i, double h, int interior)
{
    static double sp[3 * MAXV];
    double save = sc->p[i], lp, lm, d1, d2, *q = sc->p;
    if (interior) { /* polygons held at the base positions, shading moved */
        memcpy(sp, sc->p, sizeof(double) * 3 * sc->nv);
        shade_pos = sp;
        q = sp;
    }
    q[i] = save + h;
    lp = ref_loss(sc);
    q[i] = save - h;
    lm = ref_loss(sc);
    d1 = (lp - lm) / (2 * h);
    q[i] = save + 2 * h;
    lp = ref_loss(sc);
    q[i] = save - 2 * h;
    lm = ref_loss(sc);
    d2 = (lp - lm) / (4 * h);
    q[i] = save;
    shade_pos = NULL;
    /* central differences at h and 2h, Richardson-extrapolated: the
     * coverage is rational in the positions, so the h^2 term is real */
    return (4 * d1 - d2) / 3;
}

/* Analytic silhouette gradient vs central differences of the reference
 * (minus the interior term when the colours vary). */
static fdstats fd_compare(scene *sc, double h)
{
    ls_real gp[3 * MAXV];
    double fd[3 * MAXV], maxfd = 0;
    static int on_hull[MAXV];
    fdstats st = {0, 0, 0};
    uint32_t i;
    if (!lib_grad(sc, (ls_real)1, gp)) {
        st.max_rel = 1e300;
        return st;
    }
    if (sc->mask) { /* the hull's vertices: the others have zero derivative */
        static double hx[MAXV], hy[MAXV];
        poly hp;
        double z;
        int k;
        for (i = 0; i < sc->nv; i++) to_window(sc, sc->p + 3 * i, &hx[i], &hy[i], &z);
        hull(hx, hy, (int)sc->nv, &hp);
        for (i = 0; i < sc->nv; i++) {
            on_hull[i] = 0;
            for (k = 0; k < hp.n; k++) on_hull[i] |= hp.x[k] == hx[i] && hp.y[k] == hy[i];
        }
    }
    for (i = 0; i < 3 * sc->nv; i++) {
        if (sc->mask && !on_hull[i / 3]) {
            fd[i] = 0;
            continue;
        }
        fd[i] = fd_one(sc, i, h, 0);
        if (sc->vary) fd[i] -= fd_one(sc, i, h, 1);
        if (fabs(fd[i]) > maxfd) maxfd = fabs(fd[i]);
    }
    st.floor = 1e-4 * maxfd; /* FD round-off is ~1e-10 x max here */
    for (i = 0; i < 3 * sc->nv; i++) {
        double e = fabs((double)gp[i] - fd[i]) / fmax(fabs(fd[i]), st.floor);
        if (!isfinite((double)gp[i])) e = 1e300;
        if (e > tol() && !fd_quiet)
            printf("     component %u: analytic %.12g, FD %.12g, max |FD| %.3g\n", i, (double)gp[i], fd[i], maxfd);
        if (e > st.max_rel) st.max_rel = e;
        st.n++;
    }
    return st;
}

static void camera_ortho(scene *sc) { ref_camera_ortho(sc->mvp); }

static void camera_persp(scene *sc) { ref_camera_persp(sc->mvp); }

static void random_weights(scene *sc)
{
    int i;
    for (i = 0; i < 4 * IMG * IMG; i++) sc->w[i] = (double)(ls_real)(2 * rnd() - 1);
    for (i = 0; i < 3; i++) sc->bg[i] = (double)(ls_real)(0.1 + 0.2 * i);
}

/* A point in the view plane through the origin, in [-r, r]^2 of the camera's (right, up). */
static void view_point(double r, double depth_off, double *q)
{
    /* eye direction of camera_ortho is about (0.2, 0.3, 3): near enough to +z for these scenes */
    q[0] = r * (2 * rnd() - 1);
    q[1] = r * (2 * rnd() - 1);
    q[2] = depth_off;
}

static double tol(void) { return sizeof(ls_real) == 4 ? 1e-3 : 1e-6; }

static void run_trials(const char *name, void (*make)(scene *), int trials)
{
    static scene sc;
    double worst = 0;
    int t, n = 0, bad = 0;
    for (t = 0; t < trials; t++) {
        fdstats st;
        make(&sc);
        random_weights(&sc);
        st = fd_compare(&sc, getenv("FDH") ? atof(getenv("FDH")) : 3e-5);
        n += st.n;
        if (st.max_rel > worst) worst = st.max_rel;
        if (!(st.max_rel <= tol())) bad++;
    }
    printf("     %-34s %2d scenes, %3d components, max relative error %.3g (abs floor 1e-4 x max), %d over %.0e\n",
           name, trials, n, worst, bad, tol());
    CHECK_MSG(bad == 0, "%s: %d of %d scenes over tolerance (worst %.3g)", name, bad, trials, worst);
}

/* Smooth weights: one cosine wave per channel over the image. */
static void smooth_weights(scene *sc)
{
    int c, x, y;
    for (c = 0; c < 4; c++) {
        double a = 2 * rnd() - 1, b = 2 * rnd() - 1, ph = 6.283185307179586 * rnd();
        for (y = 0; y < IMG; y++)
            for (x = 0; x < IMG; x++)
                sc->w[4 * (y * IMG + x) + c] = (double)(ls_real)cos(6.283185307179586 * (a * (x + 0.5) + b * (y + 0.5)) / IMG + ph);
    }
    for (c = 0; c < 3; c++) sc->bg[c] = (double)(ls_real)(0.1 + 0.2 * c);
}

/* Random configurations with smooth weights: the distribution of the
 * per-scene worst relative error, pooled over the perspective families in
 * dist_total / dist_within; every value must be finite. */
static int dist_total, dist_within;
static void run_dist(const char *name, void (*make)(scene *), int trials)
{
    static scene sc;
    static const double edges[4] = {1e-8, 1e-6, 1e-4, 1e-3};
    double worst = 0, lim = sizeof(ls_real) == 4 ? 1e-2 : 1e-3;
    int t, n = 0, hist[5] = {0, 0, 0, 0, 0}, within = 0, nonfinite = 0, k;
    fd_quiet = getenv("FDV") == NULL;
    for (t = 0; t < trials; t++) {
        fdstats st;
        make(&sc);
        smooth_weights(&sc);
        st = fd_compare(&sc, 3e-5);
        n += st.n;
        if (st.max_rel >= 1e300) nonfinite++;
        if (st.max_rel > worst) worst = st.max_rel;
        for (k = 0; k < 4 && st.max_rel > edges[k]; k++) {
        }
        hist[k]++;
        within += st.max_rel <= lim;
    }
    fd_quiet = 0;
    dist_total += trials;
    dist_within += within;
    printf("     %-34s %2d scenes, %4d components: worst per scene <=1e-8 %d, <=1e-6 %d, <=1e-4 %d, <=1e-3 %d, "
           ">1e-3 %d (max %.3g)\n", name, trials, n, hist[0], hist[1], hist[2], hist[3], hist[4], worst);
    CHECK_MSG(nonfinite == 0, "%s: %d scenes with a non-finite gradient", name, nonfinite);
}

static void make_single(scene *sc)
{
    int k;
    memset(sc, 0, sizeof *sc);
    camera_ortho(sc);
    sc->nv = 3;
    sc->nt = 1;
    for (k = 0; k < 3; k++) view_point(0.8, 0.1 * (rnd() - 0.5), sc->p + 3 * k);
    sc->f[0] = 0; sc->f[1] = 1; sc->f[2] = 2;
    for (k = 0; k < 3; k++) sc->col[k] = (double)(ls_real)rnd();
}

/* An empty orthographic scene with one big triangle at depth -0.5 (its
 * corners jittered): vertices 0-2 of the layered scenes. */
static void big_back_triangle(scene *sc)
{
    int k;
    memset(sc, 0, sizeof *sc);
    camera_ortho(sc);
    sc->p[0] = -0.85; sc->p[1] = -0.8; sc->p[2] = -0.5;
    sc->p[3] = 0.85;  sc->p[4] = -0.75; sc->p[5] = -0.5;
    sc->p[6] = 0.05;  sc->p[7] = 0.85; sc->p[8] = -0.5;
    for (k = 0; k < 9; k++) sc->p[k] += 0.05 * (rnd() - 0.5);
}

/* A small triangle well inside a big one, in front of it. */
static void make_layers(scene *sc)
{
    int k;
    double cx, cy;
    big_back_triangle(sc);
    sc->nv = 6;
    sc->nt = 2;
    cx = 0.1 * (rnd() - 0.5);
    cy = -0.2 + 0.1 * (rnd() - 0.5);
    for (k = 0; k < 3; k++) {
        double a = 2.0943951 * k + rnd() * 0.5;
        sc->p[9 + 3 * k] = cx + 0.3 * cos(a);
        sc->p[10 + 3 * k] = cy + 0.3 * sin(a);
        sc->p[11 + 3 * k] = 0.3;
    }
    for (k = 0; k < 6; k++) sc->f[k] = (uint32_t)k;
    for (k = 0; k < 6; k++) sc->col[k] = (double)(ls_real)rnd();
}

/* A big triangle and a patch of four triangles sharing a centre vertex
 * (a fan, consistently wound: its inner edges are no silhouettes), centred
 * on one of the big triangle's edges, in front of it (patch_z 0.3) or
 * behind it (-0.8): in front, the runs of that edge inside the patch are
 * proven hidden by walks across the patch's inner edges and the runs it
 * covers in part are not; behind, no walk may hide anything. */
static double patch_z;
static void make_patch(scene *sc)
{
    int k;
    double cx, cy, a0 = 6.283185307179586 * rnd();
    big_back_triangle(sc);
    sc->nv = 8;
    sc->nt = 5;
    k = (int)(3 * rnd()) % 3; /* the edge the patch sits on */
    cx = 0.5 * (sc->p[3 * k] + sc->p[3 * ((k + 1) % 3)]) + 0.1 * (rnd() - 0.5);
    cy = 0.5 * (sc->p[3 * k + 1] + sc->p[3 * ((k + 1) % 3) + 1]) + 0.1 * (rnd() - 0.5);
    sc->p[9] = cx;
    sc->p[10] = cy;
    sc->p[11] = patch_z;
    for (k = 0; k < 4; k++) {
        double a = a0 + 1.5707963267948966 * k + 0.4 * (rnd() - 0.5), r = 0.45 + 0.15 * rnd();
        sc->p[12 + 3 * k] = cx + r * cos(a);
        sc->p[13 + 3 * k] = cy + r * sin(a);
        sc->p[14 + 3 * k] = patch_z;
    }
    sc->f[0] = 0; sc->f[1] = 1; sc->f[2] = 2;
    for (k = 0; k < 4; k++) {
        sc->f[3 + 3 * k] = 3;
        sc->f[4 + 3 * k] = (uint32_t)(4 + k);
        sc->f[5 + 3 * k] = (uint32_t)(4 + (k + 1) % 4);
    }
    for (k = 0; k < 6; k++) sc->col[k] = (double)(ls_real)rnd(); /* the patch: one colour (its inner edges are no edges of the image) */
    for (k = 6; k < 15; k++) sc->col[k] = sc->col[k - 3];
}

static void tetra(scene *sc)
{
    static const uint32_t tf[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
    int k, j;
    sc->nv = 4;
    sc->nt = 4;
    sc->mask = 1;
    for (k = 0; k < 4; k++) {
        double a = 2.0943951 * k + rnd() * 0.6;
        sc->p[3 * k] = k == 3 ? 0.2 * (rnd() - 0.5) : 0.75 * cos(a);
        sc->p[3 * k + 1] = k == 3 ? 0.2 * (rnd() - 0.5) : 0.75 * sin(a);
        sc->p[3 * k + 2] = k == 3 ? 0.7 : -0.3 + 0.1 * rnd();
        for (j = 0; j < 3; j++) sc->f[3 * k + j] = tf[k][j];
    }
    /* tilt it, so that the silhouette has four edges in some trials */
    for (k = 0; k < 4; k++) sc->p[3 * k] += 0.6 * (rnd() - 0.5) * sc->p[3 * k + 2];
}

/* A flat fan of 150 thin triangles around a vertex c (mask mode): the
 * pieces of the two boundary edges at c meet every triangle of the fan (more
 * candidates than the former fixed buffers held). The rim is a circular arc
 * in a plane, so its window image stays convex. */
static void make_fan(scene *sc)
{
    const uint32_t nt = 150;
    double cx = 0.1 * (rnd() - 0.5), cy = -0.3 + 0.1 * (rnd() - 0.5), a0 = 0.35 + 0.2 * rnd(), a1 = 2.6 + 0.2 * rnd();
    uint32_t k;
    memset(sc, 0, sizeof *sc);
    camera_ortho(sc);
    sc->mask = 1;
    sc->nv = nt + 2;
    sc->nt = nt;
    sc->p[0] = cx;
    sc->p[1] = cy;
    sc->p[2] = 0.1 * rnd();
    for (k = 0; k <= nt; k++) { /* the rim: a circular arc (convex), angles jittered inside */
        double a = a0 + (a1 - a0) * (k + 0.4 * (rnd() - 0.5) * (k > 0 && k < nt)) / nt, r = 0.6;
        sc->p[3 * (k + 1)] = cx + r * cos(a);
        sc->p[3 * (k + 1) + 1] = cy + r * sin(a);
        sc->p[3 * (k + 1) + 2] = sc->p[2];
    }
    for (k = 0; k < nt; k++) {
        sc->f[3 * k] = 0;
        sc->f[3 * k + 1] = k + 1;
        sc->f[3 * k + 2] = k + 2;
    }
}

static void make_tetra_ortho(scene *sc)
{
    memset(sc, 0, sizeof *sc);
    camera_ortho(sc);
    tetra(sc);
}

static void make_tetra_persp(scene *sc)
{
    memset(sc, 0, sizeof *sc);
    camera_persp(sc);
    tetra(sc);
}

static void make_single_persp(scene *sc)
{
    make_single(sc);
    camera_persp(sc);
}

/* A triangle with a vertex behind the eye: two of its edges are clipped at
 * the near plane (the gradient reaches the hidden vertex through the clip
 * parameter). The near-plane cut itself stays outside the image. */
static int near_found;
static void make_near(scene *sc)
{
    int tries, k, inside = 1;
    poly pl;
    for (tries = 0; tries < 200 && inside; tries++) {
        make_single(sc);
        camera_persp(sc);
        /* eye (0.4, 0.5, 2.6): put vertex 2 beside and behind it */
        sc->p[6] = 0.4 + (rnd() < 0.5 ? -1 : 1) * (0.6 + 0.6 * rnd());
        sc->p[7] = 0.5 + 0.6 * (rnd() - 0.5);
        sc->p[8] = 3.0 + 0.5 * rnd();
        tri_window(sc, 0, &pl, &inside);
        {
            double c3 = 0;
            for (k = 0; k < 4; k++) c3 += sc->mvp[8 + k] * (k < 3 ? sc->p[6 + k] : 1) + sc->mvp[12 + k] * (k < 3 ? sc->p[6 + k] : 1);
            if (c3 >= 0) inside = 1; /* vertex 2 must be behind the near plane */
        }
    }
    near_found = !inside;
}

/* Two triangles at different depths overlapping partly: the nearer one's
 * edges cross the farther one's inside pixels. */
static void make_overlap_persp(scene *sc)
{
    int k;
    memset(sc, 0, sizeof *sc);
    camera_persp(sc);
    sc->nv = 6;
    sc->nt = 2;
    for (k = 0; k < 3; k++) {
        double a = 2.0943951 * k + 0.7 * rnd();
        sc->p[3 * k] = -0.15 + 0.7 * cos(a);
        sc->p[3 * k + 1] = 0.7 * sin(a);
        sc->p[3 * k + 2] = -0.4 + 0.1 * rnd();
        a = 2.0943951 * k + 0.7 * rnd();
        sc->p[9 + 3 * k] = 0.25 + 0.5 * cos(a);
        sc->p[10 + 3 * k] = 0.1 + 0.5 * sin(a);
        sc->p[11 + 3 * k] = 0.4 + 0.1 * rnd();
    }
    for (k = 0; k < 6; k++) sc->f[k] = (uint32_t)k;
    for (k = 0; k < 6; k++) sc->col[k] = (double)(ls_real)rnd();
}

static void vary_colours(scene *sc)
{
    uint32_t i;
    sc->vary = 1;
    for (i = 0; i < 3 * sc->nv; i++) sc->vcol[i] = (double)(ls_real)rnd();
}

static void make_overlap_vary(scene *sc)
{
    make_overlap_persp(sc);
    vary_colours(sc);
}

static void make_single_vary(scene *sc)
{
    make_single(sc);
    camera_persp(sc);
    /* tilt the triangle in depth: perspective-correct colours vary rationally */
    sc->p[2] = -0.8;
    sc->p[5] = 0.6;
    vary_colours(sc);
}

/* A triangle whose third vertex is between the eye and the near plane: the
 * near-plane cut crosses the image. */
static void make_near_cut(scene *sc)
{
    int tries, inside = 0;
    poly pl;
    for (tries = 0; tries < 200 && !inside; tries++) {
        make_single(sc);
        camera_persp(sc);
        /* eye (0.4, 0.5, 2.6) looking at the origin; near plane 0.3 away */
        double lam = 0.92 + 0.04 * rnd();
        sc->p[6] = 0.4 * lam + 0.06 * (rnd() - 0.5);
        sc->p[7] = 0.5 * lam + 0.06 * (rnd() - 0.5);
        sc->p[8] = 2.6 * lam;
        tri_window(sc, 0, &pl, &inside);
    }
    vary_colours(sc);
}

/* A tiny triangle (well under a pixel) under perspective. */
static void make_subpixel(scene *sc)
{
    int k;
    double cx = 0.6 * (2 * rnd() - 1), cy = 0.6 * (2 * rnd() - 1);
    make_single(sc);
    camera_persp(sc);
    for (k = 0; k < 3; k++) {
        double a = 2.0943951 * k + rnd();
        sc->p[3 * k] = cx + 0.03 * cos(a);
        sc->p[3 * k + 1] = cy + 0.03 * sin(a);
        sc->p[3 * k + 2] = 0.05 * (rnd() - 0.5);
    }
}

/* Icosphere (ls_icosphere) scaled anisotropically (still convex), under
 * perspective, mask mode: the reference is the hull of the projection. */
static uint32_t ico_level;
static void make_icosphere(scene *sc)
{
    static unsigned char *buf;
    ls_arena arena;
    ls_mesh m;
    size_t bytes = 0;
    double s[3], o[3];
    uint32_t i;
    int k;
    memset(sc, 0, sizeof *sc);
    camera_persp(sc);
    if (ls_icosphere_bytes(ico_level, &bytes) != LS_OK) return;
    if (buf == NULL) buf = (unsigned char *)malloc(1u << 18);
    if (buf == NULL || bytes > (1u << 18) || ls_arena_init(&arena, buf, 1u << 18) != LS_OK) return;
    if (ls_icosphere(ico_level, &arena, &m) != LS_OK || m.vertex_count > MAXV || m.face_count > MAXT) return;
    for (k = 0; k < 3; k++) {
        s[k] = 0.45 + 0.3 * rnd();
        o[k] = 0.3 * (rnd() - 0.5);
    }
    sc->nv = m.vertex_count;
    sc->nt = m.face_count;
    sc->mask = 1;
    for (i = 0; i < m.vertex_count; i++)
        for (k = 0; k < 3; k++) sc->p[3 * i + k] = (double)(ls_real)(s[k] * (double)m.positions[3 * i + k] + o[k]);
    memcpy(sc->f, m.triangles, sizeof(uint32_t) * 3 * m.face_count);
}

/* Perspective scenes against the reference, smooth weights: at least 95 %
 * of the configurations (pooled) within 1e-3 relative (double). */
static void silhouette_perspective_distributions(void)
{
    int q = getenv("LS_TEST_EMULATED") != NULL ? 4 : 1; /* under QEMU: a quarter */
    double lim = sizeof(ls_real) == 4 ? 1e-2 : 1e-3;
    dist_total = dist_within = 0;
    run_dist("overlap, crossings in pixels", make_overlap_persp, 20 / q);
    run_dist("overlap, perspective colours", make_overlap_vary, 8 / q);
    run_dist("single, perspective colours", make_single_vary, 8 / q);
    run_dist("near-plane cut in the image", make_near_cut, 8 / q);
    run_dist("sub-pixel triangle", make_subpixel, 20 / q);
    ico_level = 1;
    run_dist("icosphere level 1 (mask)", make_icosphere, 8 / q);
    ico_level = 2;
    run_dist("icosphere level 2, sub-pixel faces", make_icosphere, q > 1 ? 1 : 4);
    printf("     pooled: %d of %d configurations within %.0e\n", dist_within, dist_total, lim);
    CHECK_MSG(dist_within * 100 >= 95 * dist_total, "%d of %d configurations within %.0e", dist_within, dist_total, lim);
}

static void silhouette_single_triangle_ortho(void) { run_trials("ortho single triangle", make_single, 20); }
static void silhouette_layers_ortho(void) { run_trials("ortho layered triangles", make_layers, 10); }
static void silhouette_tetra_ortho(void) { run_trials("ortho tetrahedron (mask)", make_tetra_ortho, 10); }
static void silhouette_patch_ortho(void)
{
    uint64_t keep = rng_state; /* the other tests' scenes stay as they were */
    patch_z = 0.3;
    run_trials("ortho patch over an edge", make_patch, 20);
    patch_z = -0.8;
    run_trials("ortho patch behind an edge", make_patch, 10);
    rng_state = keep;
}
static void silhouette_single_persp(void) { run_trials("perspective single triangle", make_single_persp, 10); }
/* The fan (mask, ortho): the pieces at its centre have ~150 candidates;
 * translating it leaves the summed image
 * unchanged and scaling it about a point gives d(sum R)/ds = 2 A (1 - bg),
 * A its window area by the shoelace formula. */
static void silhouette_many_candidates(void)
{
    static scene sc;
    static double x[MAXV], y[MAXV];
    ls_real gp[3 * MAXV];
    uint64_t rng_saved = rng_state; /* the other tests' scenes stay as they were */
    int i, trial;
    for (trial = 0; trial < 3; trial++) {
        double sx, sy, ds, ar, z;
        make_fan(&sc);
        for (i = 0; i < 3; i++) sc.bg[i] = 0.25;
        for (i = 0; i < 4 * IMG * IMG; i++) sc.w[i] = i % 4 == 0 ? 1 : 0; /* sum of the red channel */
        REQUIRE(lib_grad(&sc, (ls_real)1, gp));
        for (i = 0; i < (int)sc.nv; i++) to_window(&sc, sc.p + 3 * i, &x[i], &y[i], &z);
        sx = sy = ds = ar = 0;
        {
            double jx[2] = {sc.mvp[0] * 0.5 * IMG, -sc.mvp[4] * 0.5 * IMG}, jy[2] = {sc.mvp[1] * 0.5 * IMG, -sc.mvp[5] * 0.5 * IMG};
            double det = jx[0] * jy[1] - jy[0] * jx[1];
            double wx[2] = {jy[1] / det, -jx[1] / det}, wy[2] = {-jy[0] / det, jx[0] / det};
            for (i = 0; i < (int)sc.nv; i++) {
                double gx = (double)gp[3 * i] * wx[0] + (double)gp[3 * i + 1] * wx[1];
                double gy = (double)gp[3 * i] * wy[0] + (double)gp[3 * i + 1] * wy[1];
                sx += gx;
                sy += gy;
                ds += gx * (x[i] - x[0]) + gy * (y[i] - y[0]); /* scaling about the centre vertex */
            }
        }
        for (i = 0; i < (int)sc.nv; i++) { /* the polygon c, r_0 .. r_n */
            int j = i + 1 == (int)sc.nv ? 0 : i + 1;
            ar += 0.5 * (x[i] * y[j] - x[j] * y[i]);
        }
        ar = fabs(ar);
        printf("     fan of %u: translation %.3g %.3g; scaling %.12g vs 2 A (1 - bg) = %.12g\n", (unsigned)sc.nt, sx, sy, ds,
               2 * ar * 0.75);
        CHECK_NEAR(sx, 0, sizeof(ls_real) == 4 ? 1e-3 : 1e-9);
        CHECK_NEAR(sy, 0, sizeof(ls_real) == 4 ? 1e-3 : 1e-9);
        CHECK_NEAR(ds, 2 * ar * 0.75, (sizeof(ls_real) == 4 ? 1e-4 : 1e-10) * ar);
    }
    rng_state = rng_saved;
}
static void silhouette_tetra_persp(void) { run_trials("perspective tetrahedron (mask)", make_tetra_persp, 10); }
static void silhouette_near_clip(void)
{
    static scene sc;
    ls_real gp[3 * MAXV];
    double g2 = 0, gall = 0;
    int i;
    run_trials("perspective, near-clipped triangle", make_near, 10);
    make_near(&sc);
    REQUIRE(near_found);
    random_weights(&sc);
    REQUIRE(lib_grad(&sc, (ls_real)1, gp));
    for (i = 0; i < 9; i++) {
        gall += fabs((double)gp[i]);
        if (i >= 6) g2 += fabs((double)gp[i]);
    }
    /* the hidden vertex gets gradient through the clip parameter */
    CHECK_MSG(g2 > 1e-3 * gall, "hidden vertex gradient %.3g of %.3g", g2, gall);
}

/* Orthographic invariants: translating a flat shape in the image plane keeps
 * sum I; scaling it by s gives d(sum I)/ds = 2 area (c_fg - c_bg). */
static void silhouette_invariants(void)
{
    static scene sc;
    ls_real gp[3 * MAXV];
    double sx = 0, sy = 0, ds = 0, ar, cxw = 0, cyw = 0, x[3], y[3], z;
    int i, c;
    make_single(&sc);
    for (c = 0; c < 3; c++) sc.bg[c] = 0.25;
    for (i = 0; i < 4 * IMG * IMG; i++) sc.w[i] = i % 4 == 0 ? 1 : 0; /* sum of the red channel */
    sc.col[0] = 0.75;
    REQUIRE(lib_grad(&sc, (ls_real)1, gp));
    for (i = 0; i < 3; i++) {
        to_window(&sc, sc.p + 3 * i, &x[i], &y[i], &z);
        cxw += x[i] / 3;
        cyw += y[i] / 3;
    }
    /* window-space gradients from world ones: the ortho camera maps world
     * (x, y) affinely; use the directional derivative along the world
     * directions that move the window point by (1, 0) and (0, 1) */
    {
        /* columns of the 2x2 window Jacobian of the world (x, y) */
        double jx[2] = {sc.mvp[0] * 0.5 * IMG, -sc.mvp[4] * 0.5 * IMG}, jy[2] = {sc.mvp[1] * 0.5 * IMG, -sc.mvp[5] * 0.5 * IMG};
        double det = jx[0] * jy[1] - jy[0] * jx[1];
        /* world displacement (dx, dy) for a window displacement (1, 0) and (0, 1) */
        double wx[2] = {jy[1] / det, -jx[1] / det}, wy[2] = {-jy[0] / det, jx[0] / det};
        for (i = 0; i < 3; i++) {
            sx += (double)gp[3 * i] * wx[0] + (double)gp[3 * i + 1] * wx[1];
            sy += (double)gp[3 * i] * wy[0] + (double)gp[3 * i + 1] * wy[1];
            /* scaling about the window centroid: vertex moves by (x - cx, y - cy) */
            ds += ((double)gp[3 * i] * wx[0] + (double)gp[3 * i + 1] * wx[1]) * (x[i] - cxw) +
                  ((double)gp[3 * i] * wy[0] + (double)gp[3 * i + 1] * wy[1]) * (y[i] - cyw);
        }
    }
    ar = fabs(0.5 * ((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])));
    printf("     translation: d(sum R)/dx %.3g, d/dy %.3g; scaling: %.12g vs 2 A (c - bg) = %.12g\n", sx, sy, ds,
           2 * ar * 0.5);
    CHECK_NEAR(sx, 0, sizeof(ls_real) == 4 ? 1e-4 : 1e-10);
    CHECK_NEAR(sy, 0, sizeof(ls_real) == 4 ? 1e-4 : 1e-10);
    CHECK_NEAR(ds, 2 * ar * 0.5, (sizeof(ls_real) == 4 ? 1e-4 : 1e-10) * ar);
}

/* boost scales; same bits run after run. */
static void silhouette_boost_and_determinism(void)
{
    static scene sc;
    ls_real g1[3 * MAXV], g2[3 * MAXV], g3[3 * MAXV];
    int i;
    make_layers(&sc);
    random_weights(&sc);
    REQUIRE(lib_grad(&sc, (ls_real)1, g1));
    REQUIRE(lib_grad(&sc, (ls_real)1, g2));
    REQUIRE(lib_grad(&sc, (ls_real)3, g3));
    CHECK(memcmp(g1, g2, 3 * sc.nv * sizeof g1[0]) == 0);
    for (i = 0; i < (int)(3 * sc.nv); i++) CHECK_NEAR(g3[i], 3 * (double)g1[i], 1e-5 * fabs((double)g1[i]) + 1e-12);
}

/* Edge table: twins, boundary counts, errors, the arena sweep. */
typedef struct et_ctx {
    uint32_t f[3 * MAXT], nt, nv;
    ls_edge_table et;
} et_ctx;

static ls_status et_run(void *ctx, ls_arena *arena)
{
    et_ctx *c = (et_ctx *)ctx;
    return ls_edge_table_build(&c->et, c->f, c->nt, c->nv, arena, NULL);
}
static uint64_t et_hash(void *ctx)
{
    et_ctx *c = (et_ctx *)ctx;
    return test_hash(c, sizeof *c, 1469598103934665603ull);
}
static void et_reset(void *ctx)
{
    et_ctx *c = (et_ctx *)ctx;
    memset(&c->et, 0, sizeof c->et);
}

static void edge_table_build(void)
{
    static et_ctx c;
    static scene sc;
    ls_arena arena;
    ls_diag diag;
    size_t bytes = 0;
    sweep_job job;
    uint32_t h;
    memset(&c, 0, sizeof c);
    memset(&sc, 0, sizeof sc);
    tetra(&sc);
    memcpy(c.f, sc.f, sizeof c.f);
    c.nt = 4;
    c.nv = 4;
    CHECK_STATUS(ls_edge_table_bytes(c.nt, &bytes), LS_OK);
    job.name = "edge_table";
    job.run = et_run;
    job.state_hash = et_hash;
    job.reset = et_reset;
    job.ctx = &c;
    job.answer = bytes;
    job.exact = 1;
    job.quiet = 0;
    CHECK_EQ(sweep_arena(&job), 0);
    REQUIRE(ls_arena_init(&arena, arena_buf, ARENA_BYTES) == LS_OK);
    REQUIRE(et_run(&c, &arena) == LS_OK);
    CHECK_EQ(c.et.boundary_edges, 0);
    CHECK_EQ(arena.top, 0);
    CHECK_EQ(arena.bottom, 3 * 4 * sizeof(uint32_t) <= 64 ? arena.bottom : 0);
    for (h = 0; h < 12; h++) {
        uint32_t t = c.et.twin[h];
        REQUIRE(t < 12);
        CHECK_EQ(c.et.twin[t], h);
        /* the same vertex pair, reversed (consistent orientation) */
        CHECK_EQ(c.f[h], c.f[t - t % 3 + (t % 3 + 1) % 3]);
        CHECK_EQ(c.f[t], c.f[h - h % 3 + (h % 3 + 1) % 3]);
    }
    c.nt = 1;
    REQUIRE(et_run(&c, &arena) == LS_OK);
    CHECK_EQ(c.et.boundary_edges, 3);
    c.f[1] = 9;
    CHECK_STATUS(ls_edge_table_build(&c.et, c.f, 1, 4, &arena, &diag), LS_ERR_MESH);
    CHECK_EQ(diag.index, 0);
    c.f[1] = c.f[0];
    CHECK_STATUS(ls_edge_table_build(&c.et, c.f, 1, 4, &arena, &diag), LS_ERR_MESH);
    CHECK(strcmp(diag.what, "triangle with a repeated vertex") == 0);
    CHECK_STATUS(ls_edge_table_build(NULL, c.f, 1, 4, &arena, &diag), LS_ERR_INVALID);
    CHECK(strcmp(diag.what, "table is NULL") == 0);
    CHECK_STATUS(ls_edge_table_build(&c.et, NULL, 1, 4, &arena, &diag), LS_ERR_INVALID);
    CHECK(strstr(diag.what, "indices") != NULL);
    CHECK_STATUS(ls_edge_table_bytes(0x55555555u, &bytes), LS_ERR_TOO_LARGE);
}

/* The silhouette pass's scratch: exact query, arena sweep (nothing written
 * on failure), the bound above the exact figure, argument errors. */
typedef struct sil_ctx {
    ls_vis vis;
    ls_edge_table et;
    ls_shade_opts o;
    const scene *sc;
    ls_real mvp[16], gimg[4 * IMG * IMG], gp[3 * MAXV], colors[3 * MAXV];
} sil_ctx;

static ls_status sil_run(void *ctx, ls_arena *arena)
{
    sil_ctx *c = (sil_ctx *)ctx;
    return ls_silhouette_backward(&(ls_view){.vis = &c->vis, .indices = c->sc->f, .triangle_count = c->sc->nt,
            .vertex_count = c->sc->nv, .opts = &c->o, .mvp = c->mvp, .table = &c->et, .boost = 1}, c->gimg, c->gp,
            arena, NULL);
}
static uint64_t sil_hash(void *ctx)
{
    sil_ctx *c = (sil_ctx *)ctx;
    return test_hash(c->gp, sizeof c->gp, 1469598103934665603ull);
}
static void sil_reset(void *ctx)
{
    sil_ctx *c = (sil_ctx *)ctx;
    memset(c->gp, 0, sizeof c->gp);
}

static void silhouette_scratch_sweep(void)
{
    static scene sc;
    static sil_ctx c;
    ls_arena arena;
    sweep_job job;
    size_t bytes = 0, bound = 0;
    uint32_t i, k;
    ls_real gp2[3 * MAXV];
    memset(&c, 0, sizeof c);
    make_overlap_persp(&sc);
    random_weights(&sc);
    c.sc = &sc;
    for (i = 0; i < 16; i++) c.mvp[i] = (ls_real)sc.mvp[i];
    {
        ls_real pos[3 * MAXV];
        for (i = 0; i < 3 * sc.nv; i++) pos[i] = (ls_real)sc.p[i];
        REQUIRE(ls_arena_init(&arena, arena_buf, ARENA_BYTES) == LS_OK);
        REQUIRE(ls_vis_init(&c.vis, &arena, IMG, IMG, 1, MAXV) == LS_OK);
        REQUIRE(ls_raster(&c.vis, &(ls_view){.positions = pos, .indices = sc.f, .triangle_count = sc.nt,
                .vertex_count = sc.nv, .mvp = c.mvp}, &arena, NULL) == LS_OK);
        REQUIRE(ls_edge_table_build(&c.et, sc.f, sc.nt, sc.nv, &arena, NULL) == LS_OK);
    }
    ls_shade_opts_init(&c.o);
    c.o.mode = LS_SHADE_COLOR;
    for (i = 0; i < sc.nt; i++)
        for (k = 0; k < 3; k++) c.colors[3 * sc.f[3 * i + k] + k] = (ls_real)sc.col[3 * i + k];
    c.o.vertex_colors = c.colors;
    for (i = 0; i < 4 * IMG * IMG; i++) c.gimg[i] = (ls_real)sc.w[i];
    CHECK_STATUS(ls_silhouette_scratch_bytes(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt,
            .table = &c.et}, &bytes), LS_OK);
    CHECK_STATUS(ls_silhouette_scratch_bytes_bound(IMG, IMG, sc.nv, sc.nt, &bound), LS_OK);
    CHECK(bound >= bytes);
    job.name = "silhouette_backward";
    job.run = sil_run;
    job.state_hash = sil_hash;
    job.reset = sil_reset;
    job.ctx = &c;
    job.answer = bytes;
    job.exact = 1;
    job.quiet = 0;
    CHECK_EQ(sweep_arena(&job), 0);
    /* the same bits in a larger arena; nothing written on errors */
    {
        static LS_ARENA_BUFFER(big, 1u << 16);
        ls_arena a2;
        memset(c.gp, 0, sizeof c.gp);
        REQUIRE(ls_arena_init(&a2, big.bytes, sizeof big.bytes) == LS_OK);
        REQUIRE(sil_run(&c, &a2) == LS_OK);
        memcpy(gp2, c.gp, sizeof gp2);
        memset(c.gp, 0, sizeof c.gp);
        REQUIRE(ls_arena_init(&a2, big.bytes, bytes) == LS_OK);
        REQUIRE(sil_run(&c, &a2) == LS_OK);
        CHECK(memcmp(gp2, c.gp, sizeof gp2) == 0);
        CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt,
                .vertex_count = sc.nv, .opts = &c.o, .mvp = c.mvp, .table = &c.et, .boost = 1}, c.gimg, c.gp, NULL,
                NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt,
                .vertex_count = sc.nv + 1, .opts = &c.o, .mvp = c.mvp, .table = &c.et, .boost = 1}, c.gimg, c.gp, &a2,
                NULL), LS_ERR_INVALID);
        {
            ls_diag dg;
            CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt,
                    .vertex_count = sc.nv, .opts = &c.o, .mvp = c.mvp, .table = &c.et, .boost = 1}, c.gimg, c.gp, NULL,
                    &dg), LS_ERR_INVALID);
            CHECK(strcmp(dg.what, "arena is NULL") == 0);
            CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt,
                    .vertex_count = sc.nv + 1, .opts = &c.o, .mvp = c.mvp, .table = &c.et, .boost = 1}, c.gimg, c.gp,
                    &a2, &dg), LS_ERR_INVALID);
            CHECK(strstr(dg.what, "view->table") != NULL);
            CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt,
                    .vertex_count = sc.nv, .opts = &c.o, .table = &c.et, .boost = 1}, c.gimg, c.gp, &a2, &dg),
                    LS_ERR_INVALID);
            CHECK(strcmp(dg.what, "view->mvp is NULL") == 0);
            CHECK_STATUS(ls_pair_forward(NULL, c.gimg, c.gp, &dg), LS_ERR_INVALID);
            CHECK(strcmp(dg.what, "view is NULL") == 0);
            CHECK_STATUS(ls_pair_forward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt},
                    c.gimg, c.gp, &dg), LS_ERR_INVALID);
            CHECK(strcmp(dg.what, "view->table is NULL") == 0);
            CHECK_STATUS(ls_pair_backward(&(ls_view){.vis = &c.vis, .indices = sc.f, .triangle_count = sc.nt},
                    c.gimg, c.gimg, NULL, c.gp, &dg), LS_ERR_INVALID);
            CHECK(strcmp(dg.what, "view->table is NULL") == 0);
        }
        CHECK(memcmp(gp2, c.gp, sizeof gp2) == 0);
        CHECK_STATUS(ls_silhouette_scratch_bytes(&(ls_view){.indices = sc.f, .triangle_count = sc.nt, .table = &c.et},
                &bytes), LS_ERR_INVALID);
        CHECK_STATUS(ls_silhouette_scratch_bytes_bound(0, IMG, sc.nv, sc.nt, &bytes), LS_ERR_INVALID);
    }
}

/* The bunny fixture into a fresh arena (arena_buf), with the centre and
 * the largest half-side of its bounding box; 0 (after saying so) when the
 * fixture is missing. */
static int load_bunny(ls_arena *arena, ls_mesh *m, ls_real c[3], ls_real *r)
{
    unsigned char *data = NULL;
    size_t bytes = 0;
    int ok;
    if (ls_posix_read_file("fixtures/meshes/bunny.obj", &data, &bytes) != LS_OK) {
        printf("     (fixtures/meshes/bunny.obj not found: skipped)\n");
        return 0;
    }
    ok = ls_arena_init(arena, arena_buf, ARENA_BYTES) == LS_OK &&
         ls_mesh_read(data, bytes, LS_MESH_FORMAT_OBJ, arena, m, NULL) == LS_OK;
    free(data);
    CHECK(ok);
    if (!ok) return 0;
    mv_frame(m, c, r);
    return 1;
}

/* The bunny (closed, not convex: silhouette edges hidden behind its own
 * parts), orthographic, mask mode: translating it in the image plane keeps
 * the covered area (summed gradient ~ 0) and scaling it about a point gives
 * d(area)/ds = 2 area, the area measured with 4 x 4 samples per pixel. */
static void silhouette_bunny_invariants(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_vis vis;
    ls_edge_table et;
    ls_shade_opts o;
    size_t i;
    ls_real view[16], proj[16], mvp[16], eye[3], c[3] = {0, 0, 0}, up[3] = {0, 1, 0}, r = 0;
    static ls_real img[4 * 64 * 64], gimg[4 * 64 * 64];
    ls_real *gp;
    double tr[2] = {0, 0}, trabs = 0, ds = 0, area = 0;
    uint32_t v, k, W = 64;
    if (!load_bunny(&arena, &m, c, &r)) return;
    eye[0] = c[0] + (ls_real)0.5 * r;
    eye[1] = c[1] + (ls_real)0.3 * r;
    eye[2] = c[2] + 3 * r;
    ls_camera_look_at(eye, c, up, view);
    ls_camera_orthographic(-(ls_real)1.4 * r, (ls_real)1.4 * r, -(ls_real)1.4 * r, (ls_real)1.4 * r, r, 6 * r, proj);
    ls_mat4_mul(proj, view, mvp);
    gp = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    REQUIRE(gp != NULL);
    REQUIRE(ls_edge_table_build(&et, m.triangles, m.face_count, m.vertex_count, &arena, NULL) == LS_OK);
    CHECK_EQ(et.boundary_edges, 0);
    REQUIRE(ls_vis_init(&vis, &arena, W, W, 4, m.vertex_count) == LS_OK);
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles, .triangle_count = m.face_count,
            .vertex_count = m.vertex_count, .mvp = mvp}, &arena, NULL) == LS_OK);
    ls_shade_opts_init(&o);
    REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
            .vertex_count = m.vertex_count, .opts = &o}, img, NULL) == LS_OK);
    for (i = 0; i < 4 * (size_t)W * W; i++) {
        gimg[i] = (ls_real)(i % 4 == 3 ? 1 : 0); /* L = sum of alpha = covered area in pixels */
        if (i % 4 == 3) area += (double)img[i];
    }
    for (i = 0; i < 3 * (size_t)m.vertex_count; i++) gp[i] = 0;
    REQUIRE(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
            .vertex_count = m.vertex_count, .opts = &o, .mvp = mvp, .table = &et, .boost = 1}, gimg, gp, &arena,
            NULL) == LS_OK);
    for (v = 0; v < m.vertex_count; v++) {
        const ls_real *g = gp + 3 * (size_t)v, *q = m.positions + 3 * (size_t)v;
        /* world directions of the image's x and y: rows 0 and 1 of the view matrix */
        for (k = 0; k < 2; k++) {
            double d = (double)g[0] * view[4 * k] + (double)g[1] * view[4 * k + 1] + (double)g[2] * view[4 * k + 2];
            tr[k] += d;
        }
        trabs += fabs((double)g[0]) + fabs((double)g[1]) + fabs((double)g[2]);
        ds += (double)g[0] * (q[0] - c[0]) + (double)g[1] * (q[1] - c[1]) + (double)g[2] * (q[2] - c[2]);
    }
    printf("     bunny (%u faces, 64^2 ortho): translation %.3g %.3g (of sum |g| %.3g); scaling %.6g vs 2 x area %.6g "
           "(4x4 samples)\n", m.face_count, tr[0], tr[1], trabs, ds, 2 * area);
    CHECK(fabs(tr[0]) <= (sizeof(ls_real) == 4 ? 1e-4 : 1e-10) * trabs);
    CHECK(fabs(tr[1]) <= (sizeof(ls_real) == 4 ? 1e-4 : 1e-10) * trabs);
    CHECK(fabs(ds - 2 * area) <= 5e-3 * 2 * area);
}

/* The SH fast path (SH without renormalisation, vertex colours or texture:
 * the shading as a quadratic form set up once per sub-piece) against the
 * general path (ls_shade_point at every quadrature point), selected by unit
 * vertex colours, which change nothing but the path: the bunny in
 * perspective at 64^2, a grey background (edges over the background and
 * over the surface behind), weights varying per pixel and channel. The
 * two differ by the quadrature tolerance and rounding only. */
static void silhouette_sh_fast_path(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_vis vis;
    ls_edge_table et;
    ls_shade_opts o;
    size_t i;
    ls_real view[16], mvp[16], c[3], r = 0;
    static ls_real gimg[4 * 64 * 64];
    ls_real *gp[2], *nrm, *ones;
    double d2 = 0, n2 = 0;
    uint32_t W = 64, pass;
    if (!load_bunny(&arena, &m, c, &r)) return;
    mv_camera(c, r, view, mvp);
    nrm = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    ones = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    gp[0] = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    gp[1] = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    REQUIRE(gp[1] != NULL);
    REQUIRE(ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, nrm, NULL) == LS_OK);
    REQUIRE(ls_edge_table_build(&et, m.triangles, m.face_count, m.vertex_count, &arena, NULL) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &arena, W, W, 1, m.vertex_count) == LS_OK);
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles, .triangle_count = m.face_count,
            .vertex_count = m.vertex_count, .mvp = mvp}, &arena, NULL) == LS_OK);
    for (i = 0; i < 3 * (size_t)m.vertex_count; i++) ones[i] = 1;
    for (i = 0; i < 4 * (size_t)W * W; i++) gimg[i] = (ls_real)(0.25 + 0.5 * (double)((i * 7919u) % 101u) / 101.0 - (i % 4 == 1 ? 0.6 : 0));
    for (pass = 0; pass < 2; pass++) {
        mv_shade_opts(&o);
        o.vertex_colors = pass == 0 ? NULL : ones; /* pass 1: the general path */
        for (i = 0; i < 3 * (size_t)m.vertex_count; i++) gp[pass][i] = 0;
        REQUIRE(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                .vertex_count = m.vertex_count, .normals = nrm, .opts = &o, .mvp = mvp, .table = &et, .boost = 1}, gimg,
                gp[pass], &arena, NULL) == LS_OK);
    }
    for (i = 0; i < 3 * (size_t)m.vertex_count; i++) {
        d2 += ((double)gp[0][i] - (double)gp[1][i]) * ((double)gp[0][i] - (double)gp[1][i]);
        n2 += (double)gp[1][i] * (double)gp[1][i];
    }
    printf("     bunny (%u faces, 64^2 perspective, SH): fast path vs ls_shade_point: relative L2 %.3g (|g| %.3g)\n",
           m.face_count, sqrt(d2 / n2), sqrt(n2));
    CHECK(n2 > 0);
    CHECK(sqrt(d2) <= (sizeof(ls_real) == 4 ? 1e-4 : 1e-9) * sqrt(n2));
}

/* Valleys: on a closed mesh seen from outside the pass skips the
 * silhouette edges that are valleys of the surface (the back face's far
 * corner lies on the eye's side of the front face's plane), which no eye
 * outside can see. The bunny in perspective at 128^2 (SH, a grey
 * background, weights varying per pixel and channel) twice: as it is, and
 * with one small triangle added far outside the image, whose boundary
 * edges turn the closed-mesh shortcuts off (every silhouette edge swept,
 * back faces kept as candidates) and change nothing else; and a third
 * time wound the other way (the normals kept), which culls the other
 * orientation. The gradients of the bunny's vertices agree to rounding,
 * and the valleys
 * (counted here in world space, from the eye and the faces' normals) are a
 * good part of the silhouette edges, so the shortcut is exercised. */
static void silhouette_valleys_hidden(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_shade_opts o;
    size_t i;
    ls_real view[16], mvp[16], eye[3], c[3], r = 0;
    static ls_real gimg[4 * 128 * 128];
    ls_real *gp[3], *nrm, *pos;
    uint32_t *tri, *flip, W = 128, pass, h, contour = 0, valleys = 0, nv, nf;
    double vol = 0, dmax = 0, gmax = 0, fmax = 0;
    if (!load_bunny(&arena, &m, c, &r)) return;
    mv_camera(c, r, view, mvp);
    eye[0] = c[0] + (ls_real)0.9 * r; /* mv_camera's */
    eye[1] = c[1] + (ls_real)0.6 * r;
    eye[2] = c[2] + (ls_real)2.6 * r;
    nv = m.vertex_count + 3u;
    nf = m.face_count + 1u;
    pos = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)nv, sizeof(ls_real));
    tri = (uint32_t *)ls_arena_alloc(&arena, 3 * (size_t)nf, sizeof(uint32_t));
    nrm = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)nv, sizeof(ls_real));
    gp[0] = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)nv, sizeof(ls_real));
    gp[1] = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)nv, sizeof(ls_real));
    gp[2] = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)nv, sizeof(ls_real));
    flip = (uint32_t *)ls_arena_alloc(&arena, 3 * (size_t)m.face_count, sizeof(uint32_t));
    REQUIRE(flip != NULL);
    mv_open_far(&m, c, r, pos, tri);
    for (i = 0; i < 4 * (size_t)W * W; i++) gimg[i] = (ls_real)(0.25 + 0.5 * (double)((i * 7919u) % 101u) / 101.0 - (i % 4 == 1 ? 0.6 : 0));
    for (i = 0; i < m.face_count; i++) {
        flip[3 * i] = tri[3 * i];
        flip[3 * i + 1] = tri[3 * i + 2];
        flip[3 * i + 2] = tri[3 * i + 1];
    }
    for (pass = 0; pass < 3; pass++) {
        ls_arena_mark mk = ls_arena_save(&arena);
        uint32_t n = pass == 1 ? nv : m.vertex_count, f = pass == 1 ? nf : m.face_count;
        const uint32_t *fc = pass == 2 ? flip : tri;
        ls_edge_table et;
        ls_vis vis;
        REQUIRE(ls_shade_vertex_normals(pos, n, tri, f, nrm, NULL) == LS_OK);
        REQUIRE(ls_edge_table_build(&et, fc, f, n, &arena, NULL) == LS_OK);
        CHECK_EQ(et.boundary_edges, pass == 1 ? 3u : 0u);
        REQUIRE(ls_vis_init(&vis, &arena, W, W, 1, n) == LS_OK);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = fc, .triangle_count = f, .vertex_count = n,
                .mvp = mvp}, &arena, NULL) == LS_OK);
        mv_shade_opts(&o);
        for (i = 0; i < 3 * (size_t)nv; i++) gp[pass][i] = 0;
        REQUIRE(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = fc, .triangle_count = f, .vertex_count = n,
                .normals = nrm, .opts = &o, .mvp = mvp, .table = &et, .boost = 1}, gimg, gp[pass], &arena,
                NULL) == LS_OK);
        if (pass == 0) { /* the valleys among the silhouette edges, in world space */
            for (h = 0; h < 3u * m.face_count; h++) {
                uint32_t tw = et.twin[h], k, a, b, cc, d;
                double n0[3], n1[3], e1[3], e2[3], side, f0 = 0, f1 = 0;
                if (tw == LS_EDGE_NONE || tw < h) continue;
                a = tri[h];
                b = tri[h % 3u == 2u ? h - 2u : h + 1u];
                cc = tri[h % 3u == 0u ? h + 2u : h - 1u];
                d = tri[tw % 3u == 0u ? tw + 2u : tw - 1u];
                for (k = 0; k < 3; k++) {
                    e1[k] = (double)pos[3 * b + k] - (double)pos[3 * a + k];
                    e2[k] = (double)pos[3 * cc + k] - (double)pos[3 * a + k];
                }
                n0[0] = e1[1] * e2[2] - e1[2] * e2[1];
                n0[1] = e1[2] * e2[0] - e1[0] * e2[2];
                n0[2] = e1[0] * e2[1] - e1[1] * e2[0];
                for (k = 0; k < 3; k++) e2[k] = (double)pos[3 * d + k] - (double)pos[3 * b + k];
                for (k = 0; k < 3; k++) e1[k] = (double)pos[3 * a + k] - (double)pos[3 * b + k];
                n1[0] = e1[1] * e2[2] - e1[2] * e2[1]; /* face (b, a, d) */
                n1[1] = e1[2] * e2[0] - e1[0] * e2[2];
                n1[2] = e1[0] * e2[1] - e1[1] * e2[0];
                side = 0;
                for (k = 0; k < 3; k++) {
                    f0 += n0[k] * ((double)eye[k] - (double)pos[3 * a + k]);
                    f1 += n1[k] * ((double)eye[k] - (double)pos[3 * a + k]);
                    side += n0[k] * ((double)pos[3 * d + k] - (double)pos[3 * a + k]);
                }
                if ((f0 > 0) == (f1 > 0)) continue;
                contour++;
                valleys += side > 0; /* d above the face's outward plane (the bunny is wound outward, below) */
            }
            for (i = 0; i < m.face_count; i++) { /* signed volume: positive when wound outward */
                const ls_real *p0 = pos + 3 * (size_t)tri[3 * i], *p1 = pos + 3 * (size_t)tri[3 * i + 1], *p2 = pos + 3 * (size_t)tri[3 * i + 2];
                vol += (double)p0[0] * ((double)p1[1] * p2[2] - (double)p1[2] * p2[1]) -
                       (double)p0[1] * ((double)p1[0] * p2[2] - (double)p1[2] * p2[0]) +
                       (double)p0[2] * ((double)p1[0] * p2[1] - (double)p1[1] * p2[0]);
            }
        }
        ls_arena_restore(&arena, mk);
    }
    for (i = 0; i < 3 * (size_t)m.vertex_count; i++) {
        double d = fabs((double)gp[0][i] - (double)gp[1][i]), e = fabs((double)gp[2][i] - (double)gp[1][i]);
        dmax = d > dmax ? d : dmax;
        fmax = e > fmax ? e : fmax;
        gmax = fabs((double)gp[1][i]) > gmax ? fabs((double)gp[1][i]) : gmax;
    }
    printf("     bunny (%u faces, 128^2 perspective, SH): %u silhouette edges, %u valleys; against opened, max difference: "
           "closed %.3g, wound the other way %.3g, of max |g| %.3g\n", m.face_count, contour, valleys, dmax, fmax, gmax);
    CHECK(vol > 0);
    CHECK(valleys * 10u >= contour && contour > 100u);
    CHECK(gmax > 0);
    CHECK(dmax <= (sizeof(ls_real) == 4 ? 1e-4 : 1e-9) * gmax);
    CHECK(fmax <= (sizeof(ls_real) == 4 ? 1e-4 : 1e-9) * gmax);
}

/* ---- the pair mode ---- */

/* Pair-mode loss sum w . pair(shade(raster(p))) in mask mode, and (if gp)
 * its position gradient from ls_pair_backward. */
static double pair_loss(const scene *sc, const double *pos_d, ls_real *gp, ls_real *g_exact)
{
    ls_arena arena;
    ls_vis vis;
    ls_edge_table et;
    ls_shade_opts o;
    static ls_real img[4 * IMG * IMG], out[4 * IMG * IMG], gimg[4 * IMG * IMG];
    ls_real pos[3 * MAXV], mvp[16];
    double L = 0;
    uint32_t i;
    if (ls_arena_init(&arena, arena_buf, ARENA_BYTES) != LS_OK) return 0;
    for (i = 0; i < 3 * sc->nv; i++) pos[i] = (ls_real)pos_d[i];
    for (i = 0; i < 16; i++) mvp[i] = (ls_real)sc->mvp[i];
    ls_shade_opts_init(&o);
    for (i = 0; i < 3; i++) o.background[i] = (ls_real)sc->bg[i];
    if (ls_vis_init(&vis, &arena, IMG, IMG, 1, MAXV) != LS_OK ||
        ls_raster(&vis, &(ls_view){.positions = pos, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
                .mvp = mvp}, &arena, NULL) != LS_OK ||
        ls_edge_table_build(&et, sc->f, sc->nt, sc->nv, &arena, NULL) != LS_OK ||
        ls_shade(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt, .vertex_count = sc->nv,
                .opts = &o}, img, NULL) != LS_OK ||
        ls_pair_forward(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt, .table = &et}, img, out,
                NULL) != LS_OK)
        return 0;
    for (i = 0; i < 4 * IMG * IMG; i++) {
        L += sc->w[i] * (double)out[i];
        gimg[i] = (ls_real)sc->w[i];
    }
    if (gp != NULL) {
        for (i = 0; i < 3 * sc->nv; i++) gp[i] = 0;
        CHECK_STATUS(ls_pair_backward(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt, .mvp = mvp,
                .table = &et, .boost = 1}, img, gimg, NULL, gp, NULL), LS_OK);
    }
    if (g_exact != NULL) {
        for (i = 0; i < 3 * sc->nv; i++) g_exact[i] = 0;
        CHECK_STATUS(ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = sc->f, .triangle_count = sc->nt,
                .vertex_count = sc->nv, .opts = &o, .mvp = mvp, .table = &et, .boost = 1}, gimg, g_exact, &arena, NULL),
                LS_OK);
    }
    return L;
}

static void make_single_mask(scene *sc)
{
    int k;
    make_single(sc);
    if (rnd() < 0.5) camera_persp(sc);
    for (k = 0; k < 3; k++) sc->bg[k] = 0;
}

/* The pair mode's backward is the derivative of its own forward (central
 * differences of the library's pair forward, steps too small to move a
 * sample across an edge), and is deterministic. */
static void pair_backward_matches_its_forward(void)
{
    static scene sc;
    static double pd[3 * MAXV];
    ls_real gp[3 * MAXV], gp2[3 * MAXV];
    double worst = 0, h = sizeof(ls_real) == 4 ? 1e-4 : 1e-7;
    int t, i, checked = 0, n = getenv("LS_TEST_EMULATED") != NULL ? 3 : 10;
    for (t = 0; t < n; t++) {
        double maxg = 0;
        make_single_mask(&sc);
        random_weights(&sc);
        for (i = 0; i < 3; i++) sc.bg[i] = 0;
        pair_loss(&sc, sc.p, gp, NULL);
        pair_loss(&sc, sc.p, gp2, NULL);
        CHECK(memcmp(gp, gp2, sizeof(ls_real) * 3 * sc.nv) == 0);
        for (i = 0; i < (int)(3 * sc.nv); i++) maxg = fmax(maxg, fabs((double)gp[i]));
        for (i = 0; i < (int)(3 * sc.nv); i++) {
            double lp, lm, fd, e;
            memcpy(pd, sc.p, sizeof(double) * 3 * sc.nv);
            pd[i] += h;
            lp = pair_loss(&sc, pd, NULL, NULL);
            pd[i] -= 2 * h;
            lm = pair_loss(&sc, pd, NULL, NULL);
            fd = (lp - lm) / (2 * h);
            e = fabs(fd - (double)gp[i]) / fmax(fabs(fd), 1e-3 * maxg + 1e-12);
            worst = fmax(worst, e);
            checked++;
        }
    }
    printf("     pair mode vs FD of its own forward: %d components, max relative error %.3g%s\n", checked, worst,
           sizeof(ls_real) == 4 ? " (float: FD of a float forward, not checked)" : "");
    if (sizeof(ls_real) == 8) CHECK(worst < 1e-4);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The pair mode's error against the exact gradient (the accuracy column of
 * the trade table): a triangle of colour 1 on background 0, mask mode,
 * relative L2 error and cosine of the position gradient, per scene. */
static void pair_error_against_exact(void)
{
    static scene sc;
    ls_real gp[3 * MAXV], ge[3 * MAXV];
    double rel[2][40], cosv[2][40];
    int t, w, i, n = getenv("LS_TEST_EMULATED") != NULL ? 10 : 40;
    for (w = 0; w < 2; w++) {
        for (t = 0; t < n; t++) {
            double num = 0, den = 0, dot = 0, np = 0;
            make_single_mask(&sc);
            if (w == 0)
                random_weights(&sc);
            else
                smooth_weights(&sc);
            for (i = 0; i < 3; i++) sc.bg[i] = 0;
            pair_loss(&sc, sc.p, gp, ge);
            for (i = 0; i < (int)(3 * sc.nv); i++) {
                double a = (double)gp[i], b = (double)ge[i];
                num += (a - b) * (a - b);
                den += b * b;
                dot += a * b;
                np += a * a;
            }
            rel[w][t] = sqrt(num / fmax(den, 1e-300));
            cosv[w][t] = dot / fmax(sqrt(np * den), 1e-300);
        }
        qsort(rel[w], (size_t)n, sizeof(double), cmp_double);
        qsort(cosv[w], (size_t)n, sizeof(double), cmp_double);
        printf("     pair mode vs exact, %s weights, %d scenes: relative L2 error median %.3f, p90 %.3f; cosine median %.3f, "
               "p10 %.3f\n", w == 0 ? "random" : "smooth", n, rel[w][n / 2], rel[w][(9 * n) / 10], cosv[w][n / 2],
               cosv[w][n / 10]);
    }
    /* an approximation, not the derivative: well off per component, about right in direction */
    CHECK(rel[1][n / 2] > 1e-3);
    CHECK(cosv[1][n / 2] > 0.5);
}

int main(void)
{
    TEST_INIT("test_silhouette");
    arena_buf = (unsigned char *)malloc(ARENA_BYTES);
    if (arena_buf == NULL) return 1;
    TEST_RUN(edge_table_build);
    TEST_RUN(silhouette_single_triangle_ortho);
    TEST_RUN(silhouette_layers_ortho);
    TEST_RUN(silhouette_tetra_ortho);
    TEST_RUN(silhouette_patch_ortho);
    TEST_RUN(silhouette_single_persp);
    TEST_RUN(silhouette_tetra_persp);
    TEST_RUN(silhouette_many_candidates);
    TEST_RUN(silhouette_near_clip);
    TEST_RUN(silhouette_invariants);
    TEST_RUN(silhouette_perspective_distributions);
    TEST_RUN(silhouette_boost_and_determinism);
    TEST_RUN(silhouette_scratch_sweep);
    TEST_RUN(silhouette_bunny_invariants);
    TEST_RUN(silhouette_sh_fast_path);
    TEST_RUN(silhouette_valleys_hidden);
    TEST_RUN(pair_backward_matches_its_forward);
    TEST_RUN(pair_error_against_exact);
    free(arena_buf);
    return TEST_END();
}
