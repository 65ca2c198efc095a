/* tests/test_silhouette.c - silhouette derivatives against central finite
 * differences of an independent float64 exact-coverage forward.
 *
 * The reference renders flat-coloured convex layers exactly: for each pixel
 * square P the area of (layer n P) by Sutherland-Hodgman clipping, minus the
 * area it shares with nearer layers (scenes have no triple overlaps), times
 * the layer colour, plus the background on the rest; alpha = covered area.
 * Closed convex meshes in mask mode are one layer: the convex hull of the
 * projected vertices. With flat colours the interior term is zero, so the
 * finite differences of L = sum w I measure the silhouette term alone. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/camera.h>
#include <largesteps/silhouette.h>

#define IMG 12
#define MAXV 12
#define MAXT 8
#define MAXP 24

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct scene {
    uint32_t nv, nt, mask; /* mask: one colour (1), the mesh's convex hull is the layer */
    double p[3 * MAXV];
    uint32_t f[3 * MAXT];
    double mvp[16];
    double col[3 * MAXT]; /* flat colour per triangle (COLOR mode) */
    double bg[3];
    double w[4 * IMG * IMG];
} scene;

/* ---- exact coverage ---- */

typedef struct poly {
    int n;
    double x[MAXP], y[MAXP];
} poly;

/* Keeps the part of `in` where (q - p) x (pt - p) * sign >= 0. */
static void clip_half(const poly *in, double px, double py, double qx, double qy, poly *out)
{
    int i;
    out->n = 0;
    for (i = 0; i < in->n; i++) {
        int j = (i + 1) % in->n;
        double si = (qx - px) * (in->y[i] - py) - (qy - py) * (in->x[i] - px);
        double sj = (qx - px) * (in->y[j] - py) - (qy - py) * (in->x[j] - px);
        if (si >= 0 && out->n < MAXP) {
            out->x[out->n] = in->x[i];
            out->y[out->n++] = in->y[i];
        }
        if ((si >= 0) != (sj >= 0) && out->n < MAXP) {
            double t = si / (si - sj);
            out->x[out->n] = in->x[i] + t * (in->x[j] - in->x[i]);
            out->y[out->n++] = in->y[i] + t * (in->y[j] - in->y[i]);
        }
    }
}

static double area(const poly *p)
{
    double a = 0;
    int i;
    for (i = 0; i < p->n; i++) {
        int j = (i + 1) % p->n;
        a += p->x[i] * p->y[j] - p->x[j] * p->y[i];
    }
    return 0.5 * a;
}

/* a n b for convex polygons, b counter-clockwise (positive area). */
static void intersect(const poly *a, const poly *b, poly *out)
{
    poly tmp = *a;
    int i;
    for (i = 0; i < b->n; i++) {
        int j = (i + 1) % b->n;
        clip_half(&tmp, b->x[i], b->y[i], b->x[j], b->y[j], out);
        tmp = *out;
    }
    *out = tmp;
}

static void make_ccw(poly *p)
{
    if (area(p) < 0) {
        int i;
        for (i = 0; i < p->n / 2; i++) {
            double tx = p->x[i], ty = p->y[i];
            p->x[i] = p->x[p->n - 1 - i];
            p->y[i] = p->y[p->n - 1 - i];
            p->x[p->n - 1 - i] = tx;
            p->y[p->n - 1 - i] = ty;
        }
    }
}

/* Window coordinates (pixels, y down) and NDC depth of world point q. */
static void to_window(const scene *sc, const double *q, double *x, double *y, double *z)
{
    double c[4];
    int r;
    for (r = 0; r < 4; r++) c[r] = sc->mvp[4 * r] * q[0] + sc->mvp[4 * r + 1] * q[1] + sc->mvp[4 * r + 2] * q[2] + sc->mvp[4 * r + 3];
    *x = (c[0] / c[3] + 1) * 0.5 * IMG;
    *y = (1 - c[1] / c[3]) * 0.5 * IMG;
    *z = c[2] / c[3];
}

/* Convex hull (gift wrapping) of n points, counter-clockwise in (x, y). */
static void hull(const double *x, const double *y, int n, poly *out)
{
    int start = 0, cur, i;
    out->n = 0;
    for (i = 1; i < n; i++)
        if (x[i] < x[start] || (x[i] == x[start] && y[i] < y[start])) start = i;
    cur = start;
    do {
        int next = (cur + 1) % n;
        out->x[out->n] = x[cur];
        out->y[out->n++] = y[cur];
        for (i = 0; i < n; i++) {
            double cr = (x[next] - x[cur]) * (y[i] - y[cur]) - (y[next] - y[cur]) * (x[i] - x[cur]);
            if (cr < 0) next = i;
        }
        cur = next;
    } while (cur != start && out->n < n);
    make_ccw(out);
}

/* Triangle t clipped at the near plane Z + W >= 0 in clip space, projected
 * to the window, counter-clockwise; returns the mean NDC depth of its
 * corners. *near_inside (if not NULL) is set when a point made by the clip
 * lands inside the image (its discontinuity is not a mesh edge). */
static double tri_window(const scene *sc, uint32_t t, poly *out, int *near_inside)
{
    double c[3][4], zs = 0;
    int k, r, n = 0;
    for (k = 0; k < 3; k++) {
        const double *q = sc->p + 3 * sc->f[3 * t + k];
        for (r = 0; r < 4; r++) c[k][r] = sc->mvp[4 * r] * q[0] + sc->mvp[4 * r + 1] * q[1] + sc->mvp[4 * r + 2] * q[2] + sc->mvp[4 * r + 3];
    }
    if (near_inside) *near_inside = 0;
    for (k = 0; k < 3; k++) {
        const double *p0 = c[k], *p1 = c[(k + 1) % 3];
        double d0 = p0[2] + p0[3], d1 = p1[2] + p1[3];
        if (d0 >= 0) {
            out->x[n] = (p0[0] / p0[3] + 1) * 0.5 * IMG;
            out->y[n] = (1 - p0[1] / p0[3]) * 0.5 * IMG;
            zs += p0[2] / p0[3];
            n++;
        }
        if ((d0 >= 0) != (d1 >= 0)) {
            double s = d0 / (d0 - d1), q[4];
            for (r = 0; r < 4; r++) q[r] = p0[r] + s * (p1[r] - p0[r]);
            out->x[n] = (q[0] / q[3] + 1) * 0.5 * IMG;
            out->y[n] = (1 - q[1] / q[3]) * 0.5 * IMG;
            zs += q[2] / q[3];
            if (near_inside && out->x[n] > -1 && out->x[n] < IMG + 1 && out->y[n] > -1 && out->y[n] < IMG + 1)
                *near_inside = 1;
            n++;
        }
    }
    out->n = n;
    make_ccw(out);
    return n > 0 ? zs / n : 0;
}

static double ref_loss(const scene *sc)
{
    poly layer[MAXT], pix, a, b;
    double col[MAXT][3], depth[MAXT], L = 0;
    int nl = 0, i, j, c;
    uint32_t px, py;
    if (sc->mask) {
        double x[MAXV] = {0}, y[MAXV] = {0}, z;
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
            double rgb[3] = {0, 0, 0}, cover = 0;
            const double *w = sc->w + 4 * (py * IMG + px);
            pix.n = 4;
            pix.x[0] = px;     pix.y[0] = py;
            pix.x[1] = px + 1; pix.y[1] = py;
            pix.x[2] = px + 1; pix.y[2] = py + 1;
            pix.x[3] = px;     pix.y[3] = py + 1;
            for (i = 0; i < nl; i++) {
                double vis;
                intersect(&pix, &layer[i], &a);
                vis = area(&a);
                for (j = 0; j < nl; j++)
                    if (j != i && depth[j] < depth[i] && !sc->mask) {
                        intersect(&a, &layer[j], &b);
                        vis -= area(&b);
                    }
                cover += vis;
                for (c = 0; c < 3; c++) rgb[c] += vis * col[i][c];
            }
            for (c = 0; c < 3; c++) L += w[c] * (rgb[c] + (1 - cover) * sc->bg[c]);
            L += w[3] * cover;
        }
    return L;
}

/* ---- the library side ---- */

static unsigned char *arena_buf;
#define ARENA_BYTES (1u << 20)

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
    o.vertex_colors = sc->mask ? NULL : colors;
    for (i = 0; i < 4 * IMG * IMG; i++) gimg[i] = (ls_real)sc->w[i];
    for (i = 0; i < 3 * sc->nv; i++) gp[i] = 0;
    if (ls_vis_init(&vis, &arena, IMG, IMG, 1, MAXV) != LS_OK) return 0;
    if (ls_raster(&vis, &arena, mvp, pos, sc->nv, sc->f, sc->nt, NULL) != LS_OK) return 0;
    if (ls_edge_table_build(&et, sc->f, sc->nt, sc->nv, &arena, NULL) != LS_OK) return 0;
    return ls_silhouette_backward(&vis, &et, sc->f, sc->nt, NULL, sc->nv, &o, mvp, boost, gimg, gp, NULL) == LS_OK;
}

typedef struct fdstats {
    int n;
    double max_rel, floor;
} fdstats;

static double tol(void);
static fdstats fd_compare(scene *sc, double h)
{
    ls_real gp[3 * MAXV];
    double fd[3 * MAXV], maxfd = 0;
    fdstats st = {0, 0, 0};
    uint32_t i;
    if (!lib_grad(sc, (ls_real)1, gp)) {
        st.max_rel = 1e300;
        return st;
    }
    for (i = 0; i < 3 * sc->nv; i++) {
        /* central differences at h and 2h, Richardson-extrapolated: the
         * coverage is rational in the positions, so the h^2 term is real */
        double save = sc->p[i], lp, lm, d1, d2;
        sc->p[i] = save + h;
        lp = ref_loss(sc);
        sc->p[i] = save - h;
        lm = ref_loss(sc);
        d1 = (lp - lm) / (2 * h);
        sc->p[i] = save + 2 * h;
        lp = ref_loss(sc);
        sc->p[i] = save - 2 * h;
        lm = ref_loss(sc);
        d2 = (lp - lm) / (4 * h);
        sc->p[i] = save;
        fd[i] = (4 * d1 - d2) / 3;
        if (fabs(fd[i]) > maxfd) maxfd = fabs(fd[i]);
    }
    st.floor = 1e-4 * maxfd; /* FD round-off is ~1e-10 x max here */
    for (i = 0; i < 3 * sc->nv; i++) {
        double e = fabs((double)gp[i] - fd[i]) / fmax(fabs(fd[i]), st.floor);
        if (!isfinite((double)gp[i])) e = 1e300;
        if (e > tol()) printf("     component %u: analytic %.12g, FD %.12g, max |FD| %.3g\n", i, (double)gp[i], fd[i], maxfd);
        if (e > st.max_rel) st.max_rel = e;
        st.n++;
    }
    return st;
}

static void camera_ortho(scene *sc)
{
    ls_real view[16], proj[16], mvp[16], eye[3] = {(ls_real)0.2, (ls_real)0.3, 3}, tgt[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    int k;
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_orthographic(-1, 1, -1, 1, (ls_real)0.1, 10, proj);
    ls_mat4_mul(proj, view, mvp);
    for (k = 0; k < 16; k++) sc->mvp[k] = (double)mvp[k];
}

static void camera_persp(scene *sc)
{
    ls_real view[16], proj[16], mvp[16], eye[3] = {(ls_real)0.4, (ls_real)0.5, (ls_real)2.6}, tgt[3] = {0, 0, 0};
    ls_real up[3] = {0, 1, 0};
    int k;
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_perspective((ls_real)0.9, LS_FOV_Y, 1, (ls_real)0.3, 20, proj);
    ls_mat4_mul(proj, view, mvp);
    for (k = 0; k < 16; k++) sc->mvp[k] = (double)mvp[k];
}

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

/* A small triangle well inside a big one, in front of it. */
static void make_layers(scene *sc)
{
    int k;
    double cx, cy;
    memset(sc, 0, sizeof *sc);
    camera_ortho(sc);
    sc->nv = 6;
    sc->nt = 2;
    sc->p[0] = -0.85; sc->p[1] = -0.8; sc->p[2] = -0.5;
    sc->p[3] = 0.85;  sc->p[4] = -0.75; sc->p[5] = -0.5;
    sc->p[6] = 0.05;  sc->p[7] = 0.85; sc->p[8] = -0.5;
    for (k = 0; k < 9; k++) sc->p[k] += 0.05 * (rnd() - 0.5);
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

static void silhouette_single_triangle_ortho(void) { run_trials("ortho single triangle", make_single, 20); }
static void silhouette_layers_ortho(void) { run_trials("ortho layered triangles", make_layers, 10); }
static void silhouette_tetra_ortho(void) { run_trials("ortho tetrahedron (mask)", make_tetra_ortho, 10); }
static void silhouette_single_persp(void) { run_trials("perspective single triangle", make_single_persp, 10); }
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
    CHECK_STATUS(ls_edge_table_bytes(0x55555555u, &bytes), LS_ERR_TOO_LARGE);
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
    TEST_RUN(silhouette_single_persp);
    TEST_RUN(silhouette_tetra_persp);
    TEST_RUN(silhouette_near_clip);
    TEST_RUN(silhouette_invariants);
    TEST_RUN(silhouette_boost_and_determinism);
    free(arena_buf);
    return TEST_END();
}
