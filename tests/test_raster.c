/* test_raster.c - the visibility rasterizer against independent float64
 * computations: coverage with the top-left rule, perspective-correct
 * barycentrics and depth; watertightness on grids and on the bunny (every
 * sample covered exactly once, counted triangle by triangle); near-plane
 * clipping; degenerate and huge triangles; sizing queries and arena sweeps. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <largesteps/raster.h>

#define TEST_PI 3.14159265358979323846

/* ---- helpers (test side, float64) ------------------------------------- */

/* Under QEMU (LS_TEST_EMULATED=1, set by the Makefile for cross targets) the
 * heaviest checks run on fewer views and trials, to stay within the cross
 * tier's time budget; every check still runs. */
static int emulated(void)
{
    const char *e = getenv("LS_TEST_EMULATED");
    return e != NULL && e[0] == '1';
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double urand(void) /* [0, 1) */
{
    return test_rng_unit(&rng_state);
}

typedef struct tmesh {
    double *v;
    uint32_t *f;
    uint32_t nv, nf;
} tmesh;

/* A tiny OBJ reader (v and f lines only, 1-based indices, triangles). */
static int load_obj(const char *path, tmesh *m)
{
    FILE *fp = fopen(path, "r");
    char line[512];
    uint32_t cv = 0, cf = 0;
    memset(m, 0, sizeof *m);
    if (fp == NULL) return 0;
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') cv++;
        if (line[0] == 'f' && line[1] == ' ') cf++;
    }
    m->v = (double *)malloc(3 * (size_t)cv * sizeof(double));
    m->f = (uint32_t *)malloc(3 * (size_t)cf * sizeof(uint32_t));
    rewind(fp);
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') {
            double *p = m->v + 3 * (size_t)m->nv++;
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) m->nv--;
        } else if (line[0] == 'f' && line[1] == ' ') {
            unsigned a, b, c;
            if (sscanf(line + 2, "%u %u %u", &a, &b, &c) == 3) {
                uint32_t *q = m->f + 3 * (size_t)m->nf++;
                q[0] = a - 1;
                q[1] = b - 1;
                q[2] = c - 1;
            }
        }
    }
    fclose(fp);
    return m->nv == cv && m->nf == cf && cv > 0;
}

static void free_mesh(tmesh *m)
{
    free(m->v);
    free(m->f);
}

static ls_real *to_real(const double *v, size_t n)
{
    ls_real *r = (ls_real *)malloc(n * sizeof(ls_real) + 1);
    size_t i;
    for (i = 0; i < n; i++) r[i] = (ls_real)v[i];
    return r;
}

static void mat_mul(const double a[16], const double b[16], double o[16])
{
    int r, c, k;
    for (r = 0; r < 4; r++)
        for (c = 0; c < 4; c++) {
            double s = 0;
            for (k = 0; k < 4; k++) s += a[4 * r + k] * b[4 * k + c];
            o[4 * r + c] = s;
        }
}

/* gluPerspective-style (vertical fov), OpenGL clip space. */
static void persp(double fovy, double aspect, double n, double f, double p[16])
{
    double t = 1.0 / tan(fovy / 2);
    memset(p, 0, 16 * sizeof(double));
    p[0] = t / aspect;
    p[5] = t;
    p[10] = -(f + n) / (f - n);
    p[11] = -2 * f * n / (f - n);
    p[14] = -1;
}

static void look(const double eye[3], const double at[3], double v[16])
{
    double f[3], s[3], u[3], n;
    int i;
    for (i = 0; i < 3; i++) f[i] = at[i] - eye[i];
    n = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (i = 0; i < 3; i++) f[i] /= n;
    /* s = f x (0,1,0) */
    s[0] = -f[2];
    s[1] = 0;
    s[2] = f[0];
    n = sqrt(s[0] * s[0] + s[2] * s[2]);
    s[0] /= n;
    s[2] /= n;
    u[0] = s[1] * f[2] - s[2] * f[1];
    u[1] = s[2] * f[0] - s[0] * f[2];
    u[2] = s[0] * f[1] - s[1] * f[0];
    memset(v, 0, 16 * sizeof(double));
    for (i = 0; i < 3; i++) {
        v[i] = s[i];
        v[4 + i] = u[i];
        v[8 + i] = -f[i];
    }
    v[3] = -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
    v[7] = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
    v[11] = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
    v[15] = 1;
}

static void apply(const double m[16], const double p[3], double o[4])
{
    int r;
    for (r = 0; r < 4; r++) o[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
}

/* Homogeneous 2D edge functions (nvdiffrast's formula) at NDC point (fx, fy):
 * returns the perspective-correct barycentrics b and the ray's clip point
 * weights; 0 when the sum of the a's is zero. */
static int ref_bary(double c[3][4], double fx, double fy, double b[3])
{
    double p[3][2], a[3], s;
    int k;
    for (k = 0; k < 3; k++) {
        p[k][0] = c[k][0] - fx * c[k][3];
        p[k][1] = c[k][1] - fy * c[k][3];
    }
    a[0] = p[1][0] * p[2][1] - p[1][1] * p[2][0];
    a[1] = p[2][0] * p[0][1] - p[2][1] * p[0][0];
    a[2] = p[0][0] * p[1][1] - p[0][1] * p[1][0];
    s = a[0] + a[1] + a[2];
    if (s == 0) return 0;
    for (k = 0; k < 3; k++) b[k] = a[k] / s;
    return 1;
}

static ls_arena big_arena(size_t bytes, void **mem)
{
    ls_arena a;
    *mem = malloc(bytes + 8);
    /* defined contents: the sweeps hash vis buffers before the first raster
     * call writes them (valgrind would flag the hash of fresh malloc memory) */
    if (*mem != NULL) memset(*mem, 0, bytes + 8);
    ls_arena_init(&a, *mem, bytes);
    return a;
}

/* ---- exactness: single triangles on the fixed-point grid --------------- */

/* Independent coverage of a sample by a screen triangle with integer
 * vertices (1/256 samples), top-left rule stated as: a sample on an edge
 * belongs to the triangle when the edge's inward normal points right, or
 * straight down. */
static int ref_covers(const long long x[3], const long long y[3], long long px, long long py)
{
    long long area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    int k;
    if (area == 0) return 0;
    for (k = 0; k < 3; k++) {
        long long ax = x[(k + 1) % 3], ay = y[(k + 1) % 3], bx = x[(k + 2) % 3], by = y[(k + 2) % 3];
        /* signed side of p relative to a->b, positive towards the interior */
        long long e = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
        long long nx = -(by - ay), ny = bx - ax; /* gradient of e */
        if (area < 0) {
            e = -e;
            nx = -nx;
            ny = -ny;
        }
        if (e < 0) return 0;
        if (e == 0 && !(nx > 0 || (nx == 0 && ny > 0))) return 0;
    }
    return 1;
}

static void single_triangles_match_float64(void)
{
    const uint32_t w = 32, h = 16, ss = 1, sw = 32, sh = 16;
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 22, &mem);
    int trial;
    long long covered = 0, on_edge = 0, wrong_cov = 0;
    double max_b = 0, max_d = 0;
    ls_real mvp[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, (ls_real)0.5, (ls_real)-0.4, 0, 0, 1, 0};
    REQUIRE(ls_vis_init(&vis, &a, w, h, ss, 3) == LS_OK);
    for (trial = 0; trial < (emulated() ? 150 : 400); trial++) {
        double clip[3][4];
        ls_real pos[9];
        uint32_t idx[3] = {0, 1, 2};
        long long qx[3], qy[3];
        int k, i, j;
        /* vertices on the half-sample lattice (many samples exactly on edges)
         * or on the 1/256 lattice, inside and slightly outside the image */
        int coarse = trial % 2 == 0;
        for (k = 0; k < 3; k++) {
            double wv = ldexp(1.0, (int)(urand() * 4) - 1); /* 0.5 .. 4: exact scaling */
            double zn = floor((urand() * 1.8 - 0.9) * 1024) / 1024;
            if (coarse) {
                /* at sample centres of a small window: edges through centres */
                qx[k] = ((long long)floor(urand() * 9) + (trial / 2) % 20) * 256 + 128;
                qy[k] = ((long long)floor(urand() * 7) + (trial / 2) % 8) * 256 + 128;
            } else {
                qx[k] = (long long)floor(urand() * (sw + 4) * 256) - 512;
                qy[k] = (long long)floor(urand() * (sh + 4) * 256) - 512;
            }
            clip[k][3] = wv;
            clip[k][0] = ((double)qx[k] / 256.0 / (sw / 2.0) - 1.0) * wv;
            clip[k][1] = (1.0 - (double)qy[k] / 256.0 / (sh / 2.0)) * wv;
            clip[k][2] = 0.5 * wv - 0.4; /* the matrix below: Z = 0.5 W - 0.4 */
            pos[3 * k] = (ls_real)clip[k][0];
            pos[3 * k + 1] = (ls_real)clip[k][1];
            pos[3 * k + 2] = (ls_real)wv;
            clip[k][0] = (double)pos[3 * k];
            clip[k][1] = (double)pos[3 * k + 1];
            clip[k][2] = (double)((ls_real)0.5 * pos[3 * k + 2] + (ls_real)-0.4);
            (void)zn;
        }
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
                .mvp = mvp}, &a, NULL) == LS_OK);
        {
            /* the lattice vertices must snap to exactly qx, qy (double build);
             * in float builds compare against what was snapped */
            for (k = 0; k < 3; k++) {
                if (!LS_REAL_IS_FLOAT) {
                    CHECK_EQ(vis.snap[2 * k], qx[k]);
                    CHECK_EQ(vis.snap[2 * k + 1], qy[k]);
                }
                qx[k] = vis.snap[2 * k];
                qy[k] = vis.snap[2 * k + 1];
            }
        }
        for (j = 0; j < (int)sh; j++)
            for (i = 0; i < (int)sw; i++) {
                size_t s = (size_t)j * sw + (size_t)i;
                long long px = i * 256 + 128, py = j * 256 + 128;
                int want = ref_covers(qx, qy, px, py);
                double b[3], zr = 0, wr = 0; /* set where covered; gcc -O1 cannot tell */
                if (want) {
                    double fx = 2.0 * (i + 0.5) / sw - 1.0, fy = 1.0 - 2.0 * (j + 0.5) / sh;
                    ref_bary(clip, fx, fy, b);
                    wr = b[0] * clip[0][3] + b[1] * clip[1][3] + b[2] * clip[2][3];
                    zr = (b[0] * clip[0][2] + b[1] * clip[1][2] + b[2] * clip[2][2]) / wr;
                    if (zr > 1) want = 0; /* beyond the far plane */
                }
                if ((vis.tri[s] != 0) != want) wrong_cov++;
                if (!want || vis.tri[s] == 0) continue;
                covered++;
                {
                    int k2;
                    for (k2 = 0; k2 < 3; k2++) {
                        long long ax = qx[(k2 + 1) % 3], ay = qy[(k2 + 1) % 3];
                        long long bx = qx[(k2 + 2) % 3], by = qy[(k2 + 2) % 3];
                        if ((bx - ax) * (py - ay) - (by - ay) * (px - ax) == 0) {
                            on_edge++;
                            break;
                        }
                    }
                }
                if (fabs((double)vis.bary[2 * s] - b[0]) > max_b) max_b = fabs((double)vis.bary[2 * s] - b[0]);
                if (fabs((double)vis.bary[2 * s + 1] - b[1]) > max_b)
                    max_b = fabs((double)vis.bary[2 * s + 1] - b[1]);
                if (fabs((double)vis.depth[s] - zr) > max_d) max_d = fabs((double)vis.depth[s] - zr);
            }
    }
    printf("     single triangles: %lld covered samples (%lld exactly on an edge), %lld coverage "
           "mismatches, max |db| %.3g, max |dz| %.3g\n",
           covered, on_edge, wrong_cov, max_b, max_d);
    CHECK_EQ(wrong_cov, 0);
    CHECK(covered > (emulated() ? 3000 : 10000));
    CHECK(on_edge > (emulated() ? 60 : 200));
    CHECK(max_b <= (LS_REAL_IS_FLOAT ? 2e-3 : 1e-11));
    CHECK(max_d <= (LS_REAL_IS_FLOAT ? 2e-3 : 1e-11));
    free(mem);
}

/* ---- watertightness ---------------------------------------------------- */

/* Renders each triangle alone and adds its coverage to cnt[] (and its signed
 * coverage, by screen orientation, to sgn[]). */
static void per_triangle_coverage(ls_vis *vis, ls_arena *a, const ls_real *mvp, const ls_real *pos, uint32_t nv,
                                  const uint32_t *f, uint32_t nf, int *cnt, int *sgn)
{
    (void)nv;
    size_t n = (size_t)vis->sw * vis->sh, s;
    uint32_t t;
    for (t = 0; t < nf; t++) {
        double c[3][4], area;
        int k, i, orient;
        ls_real p3[9];
        static const uint32_t one[3] = {0, 1, 2};
        ls_status st;
        /* the triangle's own three vertices: the same inputs give the same bits */
        for (k = 0; k < 3; k++)
            for (i = 0; i < 3; i++) p3[3 * k + i] = pos[3 * (size_t)f[3 * (size_t)t + (size_t)k] + (size_t)i];
        st = ls_raster(vis, &(ls_view){.positions = p3, .indices = one, .triangle_count = 1, .vertex_count = 3,
                .mvp = mvp}, a, NULL);
        if (st != LS_OK) {
            CHECK_STATUS(st, LS_OK);
            return;
        }
        for (k = 0; k < 3; k++)
            for (i = 0; i < 4; i++) c[k][i] = (double)vis->clip[4 * k + i];
        /* orientation in window space (y down) */
        area = (c[1][0] / c[1][3] - c[0][0] / c[0][3]) * (-c[2][1] / c[2][3] + c[0][1] / c[0][3]) -
               (-c[1][1] / c[1][3] + c[0][1] / c[0][3]) * (c[2][0] / c[2][3] - c[0][0] / c[0][3]);
        orient = area > 0 ? 1 : -1;
        /* only tiles the call may have drawn in (tile_dirty) can hold its
         * samples: scanning them alone keeps big meshes affordable (the
         * full scan below, on small scenes, checks that this is safe) */
        {
            size_t tx, ty, tiles_x = (vis->sw + LS_RASTER_TILE - 1) / LS_RASTER_TILE;
            size_t tiles_y = (vis->sh + LS_RASTER_TILE - 1) / LS_RASTER_TILE;
            for (ty = 0; ty < tiles_y; ty++)
                for (tx = 0; tx < tiles_x; tx++) {
                    size_t x, y;
                    if (!vis->tile_dirty[ty * tiles_x + tx] && n > 4096) continue;
                    for (y = ty * LS_RASTER_TILE; y < (ty + 1) * LS_RASTER_TILE && y < vis->sh; y++)
                        for (x = tx * LS_RASTER_TILE; x < (tx + 1) * LS_RASTER_TILE && x < vis->sw; x++) {
                            s = y * vis->sw + x;
                            if (vis->tri[s]) {
                                cnt[s]++;
                                sgn[s] += orient;
                            }
                        }
                }
        }
    }
}

static void grid_of_triangles_is_watertight(void)
{
    /* a jittered grid of quads extending beyond the image, each split along a
     * random diagonal, random vertex order and depth; perspective W varies */
    enum { G = 14 };
    const uint32_t w = 48, h = 40;
    double pts[(G + 1) * (G + 1)][3];
    ls_real pos[(G + 1) * (G + 1) * 3];
    uint32_t f[G * G * 6];
    ls_real mvp[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, (ls_real)-1.002, (ls_real)-0.2002, 0, 0, -1, 0};
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 23, &mem);
    int *cnt, *sgn, trial;
    long long checked = 0, holes = 0, doubles = 0;
    uint32_t ss;
    for (ss = 1; ss <= 4; ss *= 2) {
        size_t n;
        REQUIRE(ls_vis_init(&vis, &a, w, h, ss, (G + 1) * (G + 1)) == LS_OK);
        n = (size_t)vis.sw * vis.sh;
        cnt = (int *)calloc(n, sizeof(int));
        sgn = (int *)calloc(n, sizeof(int));
        for (trial = 0; trial < (emulated() ? 1 : ss == 1 ? 8 : 2); trial++) {
            int i, j, nf = 0;
            double ox = urand() * 0.1, oy = urand() * 0.1;
            size_t s;
            for (j = 0; j <= G; j++)
                for (i = 0; i <= G; i++) {
                    double x = -1.2 + 2.4 * i / G + ox, y = -1.2 + 2.4 * j / G + oy;
                    double wv = 1.0 + 3.0 * urand();
                    if (i > 0 && i < G) x += (urand() - 0.5) * 0.08;
                    if (j > 0 && j < G) y += (urand() - 0.5) * 0.08;
                    /* a few vertices exactly on sample centres (edge cases) */
                    if (urand() < 0.3) {
                        x = (2.0 * (floor((x + 1) / 2 * vis.sw) + 0.5)) / vis.sw - 1;
                        y = 1 - (2.0 * (floor((1 - y) / 2 * vis.sh) + 0.5)) / vis.sh;
                        wv = 1;
                    }
                    pts[j * (G + 1) + i][0] = x * wv;
                    pts[j * (G + 1) + i][1] = y * wv;
                    pts[j * (G + 1) + i][2] = -wv;
                }
            for (i = 0; i < (G + 1) * (G + 1) * 3; i++) pos[i] = (ls_real)pts[i / 3][i % 3];
            for (j = 0; j < G; j++)
                for (i = 0; i < G; i++) {
                    uint32_t q[4], tri[2][3];
                    int t, r;
                    q[0] = (uint32_t)(j * (G + 1) + i);
                    q[1] = q[0] + 1;
                    q[2] = q[0] + G + 2;
                    q[3] = q[0] + G + 1;
                    if (urand() < 0.5) {
                        tri[0][0] = q[0]; tri[0][1] = q[1]; tri[0][2] = q[2];
                        tri[1][0] = q[0]; tri[1][1] = q[2]; tri[1][2] = q[3];
                    } else {
                        tri[0][0] = q[0]; tri[0][1] = q[1]; tri[0][2] = q[3];
                        tri[1][0] = q[1]; tri[1][1] = q[2]; tri[1][2] = q[3];
                    }
                    for (t = 0; t < 2; t++) {
                        int rot = (int)(urand() * 3), flip = urand() < 0.5;
                        for (r = 0; r < 3; r++) f[3 * nf + r] = tri[t][(r + rot) % 3];
                        if (flip) {
                            uint32_t tmp = f[3 * nf + 1];
                            f[3 * nf + 1] = f[3 * nf + 2];
                            f[3 * nf + 2] = tmp;
                        }
                        nf++;
                    }
                }
            memset(cnt, 0, n * sizeof(int));
            memset(sgn, 0, n * sizeof(int));
            per_triangle_coverage(&vis, &a, mvp, pos, (G + 1) * (G + 1), f, (uint32_t)nf, cnt, sgn);
            for (s = 0; s < n; s++) {
                checked++;
                if (cnt[s] == 0) holes++;
                if (cnt[s] > 1) doubles++;
            }
            /* and the full render covers everything */
            REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = f, .triangle_count = (uint32_t)nf,
                    .vertex_count = (G + 1) * (G + 1), .mvp = mvp}, &a, NULL) == LS_OK);
            for (s = 0; s < n; s++)
                if (vis.tri[s] == 0) holes++;
        }
        free(cnt);
        free(sgn);
        ls_arena_init(&a, mem, 1 << 23);
    }
    printf("     grid: %lld samples checked, %lld holes, %lld double hits\n", checked, holes, doubles);
    CHECK_EQ(holes, 0);
    CHECK_EQ(doubles, 0);
    free(mem);
}

static int load_bunny(tmesh *m)
{
    return load_obj("fixtures/meshes/bunny.obj", m) || load_obj("../shared/meshes/bunny.obj", m);
}

/* mvp for a mesh seen from direction (dx, dy, dz) at distance dist from its
 * bounding-box centre, 45 degrees vertical fov, near and far planes zn, zf. */
static void mesh_mvp(const tmesh *m, const double dir[3], double dist, double aspect, double zn, double zf,
                     ls_real out[16])
{
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30}, c[3], eye[3], v[16], p[16], mvp[16];
    uint32_t i;
    int k;
    for (i = 0; i < m->nv; i++)
        for (k = 0; k < 3; k++) {
            if (m->v[3 * i + k] < lo[k]) lo[k] = m->v[3 * i + k];
            if (m->v[3 * i + k] > hi[k]) hi[k] = m->v[3 * i + k];
        }
    for (k = 0; k < 3; k++) c[k] = (lo[k] + hi[k]) / 2;
    eye[0] = c[0] + dist * dir[0];
    eye[1] = c[1] + dist * dir[1];
    eye[2] = c[2] + dist * dir[2];
    look(eye, c, v);
    persp(45.0 * TEST_PI / 180.0, aspect, zn, zf, p);
    mat_mul(p, v, mvp);
    for (k = 0; k < 16; k++) out[k] = (ls_real)mvp[k];
}

/* mvp for the bunny seen from direction (dx, dy, dz) at distance dist. */
static void bunny_mvp(const tmesh *m, double dx, double dy, double dz, double dist, double aspect, ls_real out[16])
{
    const double dir[3] = {dx, dy, dz};
    mesh_mvp(m, dir, dist, aspect, 0.5, 100.0, out);
}

/* Watertightness on a closed mesh: every triangle rendered alone, its
 * coverage counted per sample with the sign of its screen orientation. On a
 * closed mesh every ray enters as often as it leaves, so the signed count of
 * every sample is 0, and its total count is even: a crack or a double hit on
 * a shared edge or vertex breaks this. Also: the full render covers exactly
 * the samples some triangle covers. Camera directions and distances are
 * random (distance 1.2 bounding-box diagonals with a jitter of 1e-3), so
 * samples fall on edges at many sub-pixel offsets. */
static void closed_mesh_is_watertight(const char *name, const tmesh *m, int views, uint32_t w, uint32_t h,
                                      long long min_inside)
{
    ls_real *pos, mvp[16];
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 24, &mem);
    int *cnt, *sgn, view;
    size_t n, s;
    long long checked = 0, inside = 0, holes = 0, doubles = 0, parity = 0, vis_mismatch = 0;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, diag;
    uint32_t i;
    int k;
    for (i = 0; i < m->nv; i++)
        for (k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->v[3 * i + k]);
            hi[k] = fmax(hi[k], m->v[3 * i + k]);
        }
    diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    pos = to_real(m->v, 3 * (size_t)m->nv);
    REQUIRE(ls_vis_init(&vis, &a, w, h, 1, m->nv) == LS_OK);
    n = (size_t)vis.sw * vis.sh;
    cnt = (int *)calloc(n, sizeof(int));
    sgn = (int *)calloc(n, sizeof(int));
    for (view = 0; view < views; view++) {
        double th = urand() * 2 * TEST_PI, y = urand() * 1.6 - 0.8, r = sqrt(1 - y * y);
        /* distance with a random sub-pixel-scale jitter */
        const double dir[3] = {r * cos(th), y, r * sin(th)};
        mesh_mvp(m, dir, diag * (1.2 + urand() * 0.001), (double)w / (double)h, 0.05 * diag, 4 * diag, mvp);
        memset(cnt, 0, n * sizeof(int));
        memset(sgn, 0, n * sizeof(int));
        per_triangle_coverage(&vis, &a, mvp, pos, m->nv, m->f, m->nf, cnt, sgn);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = m->f, .triangle_count = m->nf,
                .vertex_count = m->nv, .mvp = mvp}, &a, NULL) == LS_OK);
        for (s = 0; s < n; s++) {
            checked++;
            if (sgn[s] != 0) parity++;
            if (cnt[s] > 0) inside++;
            if ((cnt[s] > 0) != (vis.tri[s] != 0)) vis_mismatch++;
            if (cnt[s] % 2 != 0) {
                if (sgn[s] > 0) doubles++;
                else holes++;
            }
        }
    }
    printf("     %s (%u triangles): %lld samples checked (%lld inside the silhouette), %lld unbalanced "
           "(%lld odd-high, %lld odd-low), %lld visibility mismatches\n",
           name, (unsigned)m->nf, checked, inside, parity, doubles, holes, vis_mismatch);
    CHECK_EQ(parity, 0);
    CHECK_EQ(holes + doubles, 0);
    CHECK_EQ(vis_mismatch, 0);
    CHECK_MSG(inside > min_inside, "%lld samples inside, wanted > %lld", inside, min_inside);
    free(cnt);
    free(sgn);
    free(pos);
    free(mem);
}

static void bunny_is_watertight(void)
{
    tmesh m;
    REQUIRE(load_bunny(&m));
    closed_mesh_is_watertight("bunny", &m, emulated() ? 1 : 4, 72, 64, emulated() ? 400 : 2000);
    free_mesh(&m);
}

static void elephant_is_watertight(void)
{
    tmesh m;
    REQUIRE(load_obj("fixtures/meshes/elephant.obj", &m) || load_obj("../shared/meshes/elephant.obj", &m));
    closed_mesh_is_watertight("elephant", &m, emulated() ? 1 : 3, 96, 80, emulated() ? 300 : 1500);
    free_mesh(&m);
}

/* The armadillo (52000 triangles, 1.6 MB) is not copied into fixtures/: it is
 * read from the shared mesh directory when present (native runs only). */
static void armadillo_is_watertight(void)
{
    tmesh m;
    if (emulated() || !(load_obj("/work/shared/meshes/armadillo.obj", &m) || load_obj("../shared/meshes/armadillo.obj", &m))) {
        printf("     armadillo: not run (%s)\n", emulated() ? "emulated target" : "mesh not found");
        return;
    }
    closed_mesh_is_watertight("armadillo", &m, 3, 160, 128, 5000);
    free_mesh(&m);
}

/* ---- clipping and degenerate input ------------------------------------- */

static int all_finite(const ls_vis *vis)
{
    size_t n = (size_t)vis->sw * vis->sh, s;
    for (s = 0; s < n; s++) {
        double b0 = (double)vis->bary[2 * s], b1 = (double)vis->bary[2 * s + 1], d = (double)vis->depth[s];
        if (!(b0 >= -1e-6 && b0 <= 1 + 1e-6 && b1 >= -1e-6 && b1 <= 1 + 1e-6 && b0 + b1 <= 1 + 1e-6)) return 0;
        if (!(d >= -1.0001 && d <= 1)) return 0;
    }
    return 1;
}

static void near_plane_crossing_matches_float64(void)
{
    /* random large triangles around the camera, some vertices behind it */
    const uint32_t w = 40, h = 30;
    double p[16];
    ls_real mvp[16];
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 22, &mem);
    int trial, k;
    long long checked = 0, mism = 0, covered = 0, clipped = 0;
    double max_b = 0;
    persp(60.0 * TEST_PI / 180.0, 4.0 / 3.0, 0.3, 50.0, p);
    for (k = 0; k < 16; k++) mvp[k] = (ls_real)p[k];
    REQUIRE(ls_vis_init(&vis, &a, w, h, 1, 3) == LS_OK);
    for (trial = 0; trial < (emulated() ? 80 : 300); trial++) {
        double v[3][3], c[3][4];
        ls_real pos[9];
        uint32_t idx[3] = {0, 1, 2};
        int i, j;
        for (k = 0; k < 3; k++) {
            v[k][0] = (urand() - 0.5) * 8;
            v[k][1] = (urand() - 0.5) * 6;
            v[k][2] = -urand() * 6 + 1.5; /* some behind the camera (z > 0) */
            pos[3 * k] = (ls_real)v[k][0];
            pos[3 * k + 1] = (ls_real)v[k][1];
            pos[3 * k + 2] = (ls_real)v[k][2];
            v[k][0] = (double)pos[3 * k];
            v[k][1] = (double)pos[3 * k + 1];
            v[k][2] = (double)pos[3 * k + 2];
            apply(p, v[k], c[k]);
        }
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
                .mvp = mvp}, &a, NULL) == LS_OK);
        clipped += vis.clipped_triangles;
        CHECK(all_finite(&vis));
        for (j = 0; j < (int)h; j++)
            for (i = 0; i < (int)w; i++) {
                double fx = 2.0 * (i + 0.5) / w - 1.0, fy = 1.0 - 2.0 * (j + 0.5) / h, b[3], wr, zr, mn;
                size_t s = (size_t)j * w + (size_t)i;
                int want;
                if (!ref_bary(c, fx, fy, b)) continue;
                wr = b[0] * c[0][3] + b[1] * c[1][3] + b[2] * c[2][3];
                zr = (b[0] * c[0][2] + b[1] * c[1][2] + b[2] * c[2][2]);
                mn = fmin(b[0], fmin(b[1], b[2]));
                want = mn >= 0 && wr > 0 && zr >= -wr && zr <= wr;
                /* skip samples within 1e-3 of an edge or of the near/far planes: snapping decides those */
                if (fabs(mn) < 1e-3 * (1 + fabs(b[0]) + fabs(b[1]) + fabs(b[2])) || fabs(zr + wr) < 1e-3 * wr ||
                    fabs(zr - wr) < 1e-3 * wr)
                    continue;
                checked++;
                if ((vis.tri[s] != 0) != want) mism++;
                if (want && vis.tri[s]) {
                    /* snapping moves each vertex by at most 1/512 sample in x and y:
                     * the barycentrics may move by about that times their screen
                     * gradient (one-sample central differences of the reference) */
                    double bx0[3], bx1[3], by0[3], by1[3], g, err;
                    int q;
                    covered++;
                    /* gradient per sample from central differences over 1/8 sample */
                    ref_bary(c, fx - 0.125 / w, fy, bx0);
                    ref_bary(c, fx + 0.125 / w, fy, bx1);
                    ref_bary(c, fx, fy - 0.125 / h, by0);
                    ref_bary(c, fx, fy + 0.125 / h, by1);
                    for (q = 0; q < 2; q++) {
                        g = (fabs(bx1[q] - bx0[q]) + fabs(by1[q] - by0[q])) * 4;
                        err = fabs((double)vis.bary[2 * s + (size_t)q] - b[q]);
                        if (err / (2.0 * g / 256.0 + (LS_REAL_IS_FLOAT ? 1e-5 : 1e-12)) > max_b)
                            max_b = err / (2.0 * g / 256.0 + (LS_REAL_IS_FLOAT ? 1e-5 : 1e-12));
                    }
                }
            }
    }
    printf("     near plane: %lld triangles clipped, %lld samples checked, %lld covered, %lld mismatches, "
           "max |db| / (snap bound) %.3g\n",
           clipped, checked, covered, mism, max_b);
    CHECK(clipped > (emulated() ? 10 : 50));
    CHECK(covered > (emulated() ? 1000 : 5000));
    CHECK_EQ(mism, 0);
    CHECK(max_b <= 1); /* within the snapping bound */
    free(mem);
}

static void degenerate_and_huge_triangles_are_safe(void)
{
    double p[16];
    ls_real mvp[16];
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 22, &mem);
    int k, trial;
    static const double cases[][9] = {
        {0, 0, -2, 0, 0, -2, 0, 0, -2},                     /* a point */
        {-1, -1, -2, 1, 1, -2, 0.5, 0.5, -2},               /* collinear */
        {0, 0, -2, 0.0001, 0, -2, 0, 0.0001, -2},           /* sub-pixel */
        {0, -1, -1, 0, 1, -1, 0, 0, -5},                    /* edge-on */
        {-1e6, -1e6, -3, 1e6, -1e6, -3, 0, 1e6, -3},        /* far beyond the guard band */
        {-1e15, -1e15, -3, 1e15, -1e15, -3, 0, 1e15, -3},   /* absurdly huge */
        {0, 0, 5, 1, 0, 5, 0, 1, 5},                        /* entirely behind */
        {0, 0, 0, 1, 0, 0, 0, 1, 0},                        /* at the eye (W = 0) */
        {-1, -1, 0, 1, -1, 0, 0, 1, -2},                    /* two vertices at W = 0 */
        {-5, -5, 1, 5, -5, 1, 0, 5, -3},                    /* crossing the eye plane */
        {-1e7, 0, -1e-7, 1e7, 0, -1e-7, 0, 1, -2},          /* grazing the eye */
    };
    persp(50.0 * TEST_PI / 180.0, 1.0, 0.1, 100.0, p);
    for (k = 0; k < 16; k++) mvp[k] = (ls_real)p[k];
    REQUIRE(ls_vis_init(&vis, &a, 64, 64, 2, 3) == LS_OK);
    for (trial = 0; trial < (int)(sizeof cases / sizeof cases[0]); trial++) {
        ls_real pos[9];
        uint32_t idx[3] = {0, 1, 2};
        size_t s, cov = 0;
        for (k = 0; k < 9; k++) pos[k] = (ls_real)cases[trial][k];
        CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1,
                .vertex_count = 3, .mvp = mvp}, &a, NULL), LS_OK);
        CHECK_MSG(all_finite(&vis), "case %d: non-finite or out-of-range output", trial);
        for (s = 0; s < (size_t)vis.sw * vis.sh; s++) cov += vis.tri[s] != 0;
        /* (1e15 in float: the clipped vertices are not representable to a sample) */
        if (trial == 4 || (trial == 5 && !LS_REAL_IS_FLOAT)) CHECK_MSG(cov == (size_t)vis.sw * vis.sh, "case %d: %lu covered", trial, (unsigned long)cov);
        if (trial <= 3 || trial == 6 || trial == 7) CHECK_MSG(cov == 0, "case %d: %lu covered", trial, (unsigned long)cov);
    }
    CHECK_EQ(a.top, 0);
    free(mem);
}

static void bad_input_is_rejected(void)
{
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 20, &mem);
    ls_real mvp[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    ls_real pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t idx[3] = {0, 1, 3};
    ls_diag d;
    ls_vis blank;
    size_t bytes;
    memset(&blank, 0, sizeof blank);
    CHECK_STATUS(ls_vis_init(&vis, &a, 0, 4, 1, 3), LS_ERR_INVALID);
    CHECK_STATUS(ls_vis_init(&vis, &a, 4, 4, 3, 3), LS_ERR_INVALID);
    CHECK_STATUS(ls_vis_init(&vis, &a, 4096, 4, 4, 3), LS_ERR_INVALID);
    CHECK_STATUS(ls_vis_bytes(2048, 2048, 4, 3, &bytes), LS_OK);
    REQUIRE(ls_vis_init(&vis, &a, 8, 8, 1, 3) == LS_OK);
    CHECK_STATUS(ls_raster(&blank, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
            .mvp = mvp}, &a, NULL), LS_ERR_STATE);
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 4,
            .mvp = mvp}, &a, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 4,
            .mvp = mvp}, &a, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "view->vertex_count") != NULL);
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = NULL, .triangle_count = 1, .vertex_count = 3,
            .mvp = mvp}, &a, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "view->indices") != NULL);
    CHECK_STATUS(ls_raster(&vis, NULL, &a, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "view is NULL") == 0);
    ls_diag_clear(&d);
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
            .mvp = mvp}, &a, &d), LS_ERR_MESH);
    CHECK(d.has_index && d.index == 0 && d.what != NULL);
    idx[2] = 2;
    pos[4] = (ls_real)NAN;
    ls_diag_clear(&d);
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
            .mvp = mvp}, &a, &d), LS_ERR_NONFINITE);
    CHECK(d.has_index && d.index == 1);
    pos[4] = 0;
    mvp[5] = (ls_real)INFINITY;
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = pos, .indices = idx, .triangle_count = 1, .vertex_count = 3,
            .mvp = mvp}, &a, NULL), LS_ERR_NONFINITE);
    CHECK_EQ(a.top, 0);
    free(mem);
}

/* ---- supersampling, determinism, sizing -------------------------------- */

static void supersampling_equals_finer_grid(void)
{
    tmesh m;
    ls_real *pos, mvp[16];
    ls_vis v2, v1;
    void *mem;
    ls_arena a = big_arena(1 << 24, &mem);
    REQUIRE(load_bunny(&m));
    pos = to_real(m.v, 3 * (size_t)m.nv);
    bunny_mvp(&m, 0.3, 0.4, 0.866, 21.0, 1.0, mvp);
    REQUIRE(ls_vis_init(&v2, &a, 40, 40, 2, m.nv) == LS_OK);
    REQUIRE(ls_vis_init(&v1, &a, 80, 80, 1, m.nv) == LS_OK);
    REQUIRE(ls_raster(&v2, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf, .vertex_count = m.nv,
            .mvp = mvp}, &a, NULL) == LS_OK);
    REQUIRE(ls_raster(&v1, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf, .vertex_count = m.nv,
            .mvp = mvp}, &a, NULL) == LS_OK);
    CHECK(memcmp(v1.tri, v2.tri, 80 * 80 * sizeof(uint32_t)) == 0);
    CHECK(memcmp(v1.depth, v2.depth, 80 * 80 * sizeof(ls_real)) == 0);
    CHECK(memcmp(v1.bary, v2.bary, 2 * 80 * 80 * sizeof(ls_real)) == 0);
    /* deterministic: a second run gives the same bits */
    {
        uint64_t h1 = test_hash(v1.tri, 80 * 80 * 4, TEST_HASH_SEED), h2;
        h1 = test_hash(v1.bary, 2 * 80 * 80 * sizeof(ls_real), h1);
        REQUIRE(ls_raster(&v1, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf,
                .vertex_count = m.nv, .mvp = mvp}, &a, NULL) == LS_OK);
        h2 = test_hash(v1.tri, 80 * 80 * 4, TEST_HASH_SEED);
        h2 = test_hash(v1.bary, 2 * 80 * 80 * sizeof(ls_real), h2);
        CHECK(h1 == h2);
    }
    free(pos);
    free_mesh(&m);
    free(mem);
}

static void visible_surface_is_the_nearest(void)
{
    /* the full render picks, per sample, the covering triangle with the
     * smallest (depth, index), checked against per-triangle renders */
    tmesh m;
    ls_real *pos, mvp[16];
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 24, &mem);
    ls_real *best;
    uint32_t *best_id, t;
    size_t n, s;
    long long wrong = 0;
    REQUIRE(load_bunny(&m));
    pos = to_real(m.v, 3 * (size_t)m.nv);
    bunny_mvp(&m, -0.5, 0.2, 0.84, 20.0, 1.0, mvp);
    REQUIRE(ls_vis_init(&vis, &a, emulated() ? 24 : 48, emulated() ? 24 : 48, 1, m.nv) == LS_OK);
    n = (size_t)vis.sw * vis.sh;
    best = (ls_real *)malloc(n * sizeof(ls_real));
    best_id = (uint32_t *)calloc(n, sizeof(uint32_t));
    for (t = 0; t < m.nf; t++) {
        ls_real p3[9];
        static const uint32_t one[3] = {0, 1, 2};
        int k;
        for (k = 0; k < 9; k++) p3[k] = pos[3 * (size_t)m.f[3 * (size_t)t + (size_t)(k / 3)] + (size_t)(k % 3)];
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = p3, .indices = one, .triangle_count = 1, .vertex_count = 3,
                .mvp = mvp}, &a, NULL) == LS_OK);
        for (s = 0; s < n; s++)
            if (vis.tri[s] && (best_id[s] == 0 || vis.depth[s] < best[s])) {
                best[s] = vis.depth[s];
                best_id[s] = t + 1;
            }
    }
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf, .vertex_count = m.nv,
            .mvp = mvp}, &a, NULL) == LS_OK);
    for (s = 0; s < n; s++)
        if (vis.tri[s] != best_id[s] || (best_id[s] && vis.depth[s] != best[s])) wrong++;
    CHECK_EQ(wrong, 0);
    free(best);
    free(best_id);
    free(pos);
    free_mesh(&m);
    free(mem);
}

typedef struct raster_job {
    ls_vis *vis;
    const ls_real *mvp, *pos;
    const uint32_t *f;
    uint32_t nv, nf;
} raster_job;

static ls_status run_raster(void *ctx, ls_arena *arena)
{
    raster_job *j = (raster_job *)ctx;
    return ls_raster(j->vis, &(ls_view){.positions = j->pos, .indices = j->f, .triangle_count = j->nf,
            .vertex_count = j->nv, .mvp = j->mvp}, arena, NULL);
}

static uint64_t hash_raster(void *ctx)
{
    raster_job *j = (raster_job *)ctx;
    size_t n = (size_t)j->vis->sw * j->vis->sh;
    uint64_t h = test_hash(j->vis->tri, n * 4, TEST_HASH_SEED);
    h = test_hash(j->vis->bary, 2 * n * sizeof(ls_real), h);
    h = test_hash(j->vis->depth, n * sizeof(ls_real), h);
    h = test_hash(j->vis->clip, 4 * (size_t)j->nv * sizeof(ls_real), h);
    h = test_hash(j->pos, 3 * (size_t)j->nv * sizeof(ls_real), h);
    return test_hash(j->f, 3 * (size_t)j->nf * sizeof(uint32_t), h);
}

typedef struct vis_job {
    ls_vis vis;
    uint32_t w, h, ss, nv;
} vis_job;

static ls_status run_vis(void *ctx, ls_arena *arena)
{
    vis_job *j = (vis_job *)ctx;
    return ls_vis_init(&j->vis, arena, j->w, j->h, j->ss, j->nv);
}

static uint64_t hash_vis(void *ctx)
{
    return test_hash(&((vis_job *)ctx)->vis, sizeof(ls_vis), TEST_HASH_SEED);
}

static void sizing_queries_and_arena_sweeps(void)
{
    tmesh m;
    ls_real *pos, mvp[16];
    ls_vis vis;
    void *mem;
    ls_arena a = big_arena(1 << 24, &mem);
    size_t exact, bound, vb;
    raster_job rj;
    vis_job vj;
    sweep_job sj;
    uint32_t ss;
    REQUIRE(load_bunny(&m));
    pos = to_real(m.v, 3 * (size_t)m.nv);
    bunny_mvp(&m, 0.1, 0.2, 0.97, 20.0, 1.0, mvp);
    /* vis buffers: exact */
    for (ss = 1; ss <= 4; ss *= 2) {
        memset(&vj, 0, sizeof vj);
        vj.w = 13;
        vj.h = 7;
        vj.ss = ss;
        vj.nv = 5;
        REQUIRE(ls_vis_bytes(13, 7, ss, 5, &vb) == LS_OK);
        memset(&sj, 0, sizeof sj);
        sj.name = "vis_init";
        sj.run = run_vis;
        sj.state_hash = hash_vis;
        sj.ctx = &vj;
        sj.answer = vb;
        sj.exact = 1;
        CHECK_EQ(sweep_arena(&sj), 0);
    }
    /* raster scratch: exact query for this geometry, bound above it */
    REQUIRE(ls_vis_init(&vis, &a, 64, 48, 2, m.nv) == LS_OK);
    REQUIRE(ls_raster_scratch_bytes(&vis, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf,
            .vertex_count = m.nv, .mvp = mvp}, &exact) == LS_OK);
    REQUIRE(ls_raster_scratch_bytes_bound(64, 48, 2, m.nv, m.nf, &bound) == LS_OK);
    CHECK(bound >= exact);
    rj.vis = &vis;
    rj.mvp = mvp;
    rj.pos = pos;
    rj.f = m.f;
    rj.nv = m.nv;
    rj.nf = m.nf;
    memset(&sj, 0, sizeof sj);
    sj.name = "raster";
    sj.run = run_raster;
    sj.state_hash = hash_raster;
    sj.ctx = &rj;
    sj.answer = exact;
    sj.exact = 1;
    CHECK_EQ(sweep_arena(&sj), 0);
    CHECK_EQ(vis.scratch_bytes, exact);
    /* a clipped scene too (camera inside the bunny's bounding box) */
    bunny_mvp(&m, 0.1, 0.2, 0.97, 2.0, 1.0, mvp);
    REQUIRE(ls_raster_scratch_bytes(&vis, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf,
            .vertex_count = m.nv, .mvp = mvp}, &exact) == LS_OK);
    sj.answer = exact;
    CHECK_EQ(sweep_arena(&sj), 0);
    CHECK(vis.clipped_triangles > 0);
    /* overflow of the bound */
    CHECK_STATUS(ls_raster_scratch_bytes_bound(2048, 2048, 4, 10, UINT32_MAX - 2, &bound),
                 sizeof(size_t) < 8 ? LS_ERR_TOO_LARGE : LS_OK);
    free(pos);
    free_mesh(&m);
    free(mem);
}

static void bytes_per_view_report(void)
{
    tmesh m;
    ls_real *pos, mvp[16];
    uint32_t res[2] = {128, 512};
    int r;
    void *mem;
    ls_arena a = big_arena((size_t)1 << 26, &mem);
    REQUIRE(load_bunny(&m));
    pos = to_real(m.v, 3 * (size_t)m.nv);
    bunny_mvp(&m, 0.3, 0.3, 0.905, 25.0, 1.0, mvp);
    for (r = 0; r < 2; r++) {
        ls_vis vis;
        size_t vb, sb, bound;
        REQUIRE(ls_vis_bytes(res[r], res[r], 1, m.nv, &vb) == LS_OK);
        ls_arena_init(&a, mem, (size_t)1 << 26);
        REQUIRE(ls_vis_init(&vis, &a, res[r], res[r], 1, m.nv) == LS_OK);
        REQUIRE(ls_raster_scratch_bytes(&vis, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf,
                .vertex_count = m.nv, .mvp = mvp}, &sb) == LS_OK);
        REQUIRE(ls_raster_scratch_bytes_bound(res[r], res[r], 1, m.nv, m.nf, &bound) == LS_OK);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = pos, .indices = m.f, .triangle_count = m.nf,
                .vertex_count = m.nv, .mvp = mvp}, &a, NULL) == LS_OK);
        printf("     bunny %u^2 S=1: vis %lu bytes, raster scratch %lu bytes (%lu bin entries; bound %lu)\n",
               res[r], (unsigned long)vb, (unsigned long)sb, (unsigned long)vis.bin_entries,
               (unsigned long)bound);
        CHECK_EQ(vis.scratch_bytes, sb);
    }
    free(pos);
    free_mesh(&m);
    free(mem);
}

int main(void)
{
    TEST_INIT("test_raster");
    TEST_RUN(single_triangles_match_float64);
    TEST_RUN(grid_of_triangles_is_watertight);
    TEST_RUN(bunny_is_watertight);
    TEST_RUN(elephant_is_watertight);
    TEST_RUN(armadillo_is_watertight);
    TEST_RUN(near_plane_crossing_matches_float64);
    TEST_RUN(degenerate_and_huge_triangles_are_safe);
    TEST_RUN(bad_input_is_rejected);
    TEST_RUN(supersampling_equals_finer_grid);
    TEST_RUN(visible_surface_is_the_nearest);
    TEST_RUN(sizing_queries_and_arena_sweeps);
    TEST_RUN(bytes_per_view_report);
    return TEST_END();
}
