/* tests/test_fit_knobs.c - the fit's speed/accuracy knobs: the
 * preconditioner's power p, the silhouette modes (exact, pair, none) and the
 * CG tolerance. One plain-SGD step is checked against a dense computation of
 * x - lr M^-p g with M = I + lambda L built here from the triangles; the
 * pair mode's loss against the blended images composed here; the modes'
 * memory and configuration errors. */
#include "test.h"
#include "dense.h"
#include <stdlib.h>
#include "fit_targets.h"

#define RES 24u
#define NV 3u
#define BUF_BYTES (16u << 20)

static unsigned char *buf;
static ls_real mvps[NV][16];
static ls_real *targets[NV];
static ls_real sh[27];

/* Targets: an ellipsoid (level 2), SH shading, S = 4 (fit_targets.h). */
static void make_targets(void) { fit_test_targets(2, NV, RES, buf, BUF_BYTES, mvps, targets, sh); }

static void config(ls_fit_config *c)
{
    ls_fit_config_default(c);
    c->width = c->height = RES;
    c->shading.mode = LS_SHADE_SH;
    c->shading.sh = sh;
    c->use_translation = 0;
    c->weight = (ls_real)4;
}

static void views_of(ls_fit_views *v)
{
    v->count = NV;
    v->mvp = &mvps[0][0];
    v->targets = (const ls_real *const *)targets;
}

/* A level-1 sphere of radius 0.8 in `arena`. */
static void sphere(ls_arena *arena, ls_mesh *m)
{
    uint32_t i;
    REQUIRE(ls_icosphere(1, arena, m) == LS_OK);
    for (i = 0; i < 3u * m->vertex_count; i++) m->positions[i] *= (ls_real)0.8;
}

/* Dense M = I + lambda (D - A), uniform weights, from the triangles. */
static double *dense_m(const ls_mesh *m, double lambda)
{
    uint32_t n = m->vertex_count, f, k;
    double *a = (double *)calloc((size_t)n * n, sizeof(double));
    int *adj = (int *)calloc((size_t)n * n, sizeof(int));
    if (a == NULL || adj == NULL) {
        free(a);
        free(adj);
        return NULL;
    }
    for (f = 0; f < m->face_count; f++)
        for (k = 0; k < 3; k++) {
            uint32_t i = m->triangles[3 * f + k], j = m->triangles[3 * f + (k + 1) % 3];
            adj[(size_t)i * n + j] = adj[(size_t)j * n + i] = 1;
        }
    for (f = 0; f < n; f++) {
        double deg = 0;
        for (k = 0; k < n; k++)
            if (adj[(size_t)f * n + k]) a[(size_t)f * n + k] = -lambda, deg += 1;
        a[(size_t)f * n + f] = 1 + lambda * deg;
    }
    free(adj);
    return a;
}

/* One SGD step (no momentum) from the sphere; checks x1 = x0 - lr R M^-p g
 * with g = dL/dx of that iteration in the fit's frame (fit.gx), R the fit's
 * length unit, and M dense. */
static void one_step_power(uint32_t power)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views v;
    ls_fit fit;
    ls_mesh init, out;
    ls_real *pos;
    double *m, *mcopy, *rhs, err = 0, scale = 0;
    const double lr = 1.0;
    uint32_t n, i, s;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    sphere(&arena, &init);
    n = init.vertex_count;
    config(&c);
    c.power = power;
    REQUIRE(ls_optim_config_default(LS_OPTIM_SGD, &c.optim) == LS_OK);
    c.optim.lr = (ls_real)lr;
    c.optim.beta1 = 0;
    views_of(&v);
    REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, NULL) == LS_OK);
    REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
    pos = (ls_real *)malloc(3u * n * sizeof(ls_real));
    rhs = (double *)malloc(3u * n * sizeof(double));
    REQUIRE(pos != NULL && rhs != NULL);
    REQUIRE(ls_fit_mesh(&fit, pos, &out) == LS_OK);
    m = dense_m(&init, (double)c.weight);
    REQUIRE(m != NULL);
    mcopy = (double *)malloc((size_t)n * n * sizeof(double));
    REQUIRE(mcopy != NULL);
    for (i = 0; i < 3u * n; i++) rhs[i] = (double)fit.gx[i];
    for (s = 0; s < (power == 1u ? 1u : 2u); s++) {
        memcpy(mcopy, m, (size_t)n * n * sizeof(double));
        REQUIRE(dense_solve(mcopy, (int)n, rhs, 3));
    }
    /* in the fit's frame (fit.h): x_f = x / S, g_f = S dL/dx (fit.gx), the
     * step lr R / S: back in caller units x1 = x0 - lr R M^-p g_f */
    for (i = 0; i < 3u * n; i++) {
        double step = lr * (double)fit.radius * rhs[i];
        double want = (double)init.positions[i] - step;
        double d = fabs((double)pos[i] - want);
        if (d > err) err = d;
        if (fabs(step) > scale) scale = fabs(step);
    }
    printf("     p = %u: step size %.3g, |x1 - (x0 - lr M^-%u g)| = %.3g\n", (unsigned)power, scale, (unsigned)power, err);
    CHECK(scale > 1e-6);
    CHECK(err <= 1e-9 * scale + TEST_EPS(32));
    free(m);
    free(mcopy);
    free(rhs);
    free(pos);
}

static void fit_power_one_and_two(void)
{
    one_step_power(1);
    one_step_power(2);
}

/* dL/dx of the first iteration with configuration c, into g [3 n]. */
static void first_gradient(const ls_fit_config *c, ls_real *g, ls_real *loss)
{
    ls_arena arena;
    ls_fit_views v;
    ls_fit fit;
    ls_mesh init;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    sphere(&arena, &init);
    views_of(&v);
    REQUIRE(ls_fit_init(&fit, c, &v, &init, &arena, NULL) == LS_OK);
    REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
    memcpy(g, fit.gx, 3u * init.vertex_count * sizeof(ls_real));
    *loss = fit.loss;
}

/* The first iteration's loss of the initial sphere composed here, outside
 * the fit: raster (S = 1), vertex normals, SH shade, then the pair blend
 * (pair) or the A x A refinement of silhouette pixels (aa > 1), and the
 * mean L1 over views, pixels and RGBA against the targets, into *loss. */
static void composed_loss(int pair, uint32_t aa, double *loss)
{
    ls_arena arena;
    ls_mesh init;
    ls_vis vis;
    ls_edge_table tab;
    ls_shade_opts o;
    ls_real *normals, *img, *blend;
    double sum = 0;
    uint32_t v, p;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    sphere(&arena, &init);
    normals = (ls_real *)ls_arena_alloc(&arena, 3u * init.vertex_count, sizeof(ls_real));
    img = (ls_real *)ls_arena_alloc(&arena, 4u * RES * RES, sizeof(ls_real));
    blend = (ls_real *)ls_arena_alloc(&arena, 4u * RES * RES, sizeof(ls_real));
    REQUIRE(normals != NULL && img != NULL && blend != NULL);
    REQUIRE(ls_shade_vertex_normals(init.positions, init.vertex_count, init.triangles, init.face_count, normals,
                                    NULL) == LS_OK);
    REQUIRE(ls_vis_init(&vis, &arena, RES, RES, 1, init.vertex_count) == LS_OK);
    REQUIRE(ls_edge_table_build(&tab, init.triangles, init.face_count, init.vertex_count, &arena, NULL) == LS_OK);
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh;
    for (v = 0; v < NV; v++) {
        const ls_real *out = img;
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = init.positions, .indices = init.triangles,
                .triangle_count = init.face_count, .vertex_count = init.vertex_count, .mvp = mvps[v]}, &arena,
                NULL) == LS_OK);
        REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = init.triangles, .triangle_count = init.face_count,
                .vertex_count = init.vertex_count, .normals = normals, .opts = &o}, img, NULL) == LS_OK);
        if (pair) {
            REQUIRE(ls_pair_forward(&(ls_view){.vis = &vis, .indices = init.triangles,
                    .triangle_count = init.face_count, .table = &tab}, img, blend, NULL) == LS_OK);
            out = blend;
        } else if (aa > 1) {
            REQUIRE(ls_refine_shade(&(ls_view){.vis = &vis, .indices = init.triangles,
                    .triangle_count = init.face_count, .vertex_count = init.vertex_count, .normals = normals,
                    .opts = &o, .table = &tab}, aa, img, &arena, NULL, NULL) == LS_OK);
        }
        for (p = 0; p < 4u * RES * RES; p++) sum += fabs((double)out[p] - (double)targets[v][p]);
    }
    *loss = sum / (double)(4u * RES * RES * NV);
}

/* The modes: none = exact with boost 0 (bit for bit); the silhouette term is
 * not zero; pair: the loss is that of the blended images composed here. */
static void fit_silhouette_modes(void)
{
    ls_fit_config c;
    ls_real g_exact[3 * 42], g_none[3 * 42], g_zero[3 * 42], g_pair[3 * 42], l_exact, l_none, l_zero, l_pair;
    double diff = 0, pair_diff = 0;
    uint32_t i;
    config(&c);
    first_gradient(&c, g_exact, &l_exact);
    c.silhouette = LS_FIT_SILHOUETTE_NONE;
    first_gradient(&c, g_none, &l_none);
    c.silhouette = LS_FIT_SILHOUETTE_EXACT;
    c.boost = 0;
    first_gradient(&c, g_zero, &l_zero);
    c.boost = 3;
    c.silhouette = LS_FIT_SILHOUETTE_PAIR;
    first_gradient(&c, g_pair, &l_pair);
    CHECK(memcmp(g_none, g_zero, sizeof g_none) == 0);
    CHECK(l_none == l_exact && l_zero == l_exact);
    for (i = 0; i < 3 * 42; i++) {
        diff += fabs((double)g_exact[i] - (double)g_none[i]);
        pair_diff += fabs((double)g_pair[i] - (double)g_none[i]);
    }
    printf("     |g_exact - g_none|_1 = %.4g, |g_pair - g_none|_1 = %.4g, loss point-sampled %.6f, pair-blended %.6f\n",
           diff, pair_diff, (double)l_exact, (double)l_pair);
    CHECK(diff > 1e-4);
    CHECK(pair_diff > 1e-4);
    {
        double sum = 0;
        composed_loss(1, 0, &sum); /* raster, normals, shade, blend, mean L1 */
        printf("     pair loss composed here %.9f, by the fit %.9f\n", sum, (double)l_pair);
        CHECK_NEAR((double)l_pair, sum, 1e-12 + TEST_EPS(16) * sum);
    }
}

/* CG at a tight tolerance reproduces the LDL^T fit; a loose one does not. */
static void fit_cg_tolerance(void)
{
    ls_fit_config c;
    ls_real *x[3];
    static const double tols[3] = {0, 1e-12, 1e-2};
    double d_tight = 0, d_loose = 0, scale = 0;
    uint32_t k, i, it;
    for (k = 0; k < 3; k++) {
        ls_arena arena;
        ls_fit_views v;
        ls_fit fit;
        ls_mesh init, out;
        config(&c);
        c.solver = k == 0 ? LS_PARAM_LDLT : LS_PARAM_CG;
        c.cg_tol = (ls_real)tols[k];
        if (sizeof(ls_real) == sizeof(float) && k == 1) c.cg_tol = (ls_real)1e-6;
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        sphere(&arena, &init);
        views_of(&v);
        REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, NULL) == LS_OK);
        for (it = 0; it < 3; it++) REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
        x[k] = (ls_real *)malloc(3u * init.vertex_count * sizeof(ls_real));
        REQUIRE(x[k] != NULL);
        REQUIRE(ls_fit_mesh(&fit, x[k], &out) == LS_OK);
    }
    for (i = 0; i < 3 * 42; i++) {
        d_tight = fmax(d_tight, fabs((double)x[1][i] - (double)x[0][i]));
        d_loose = fmax(d_loose, fabs((double)x[2][i] - (double)x[0][i]));
        scale = fmax(scale, fabs((double)x[0][i]));
    }
    printf("     3 iterations: max |x_CG - x_LDLT| tol tight %.3g, tol 1e-2 %.3g\n", d_tight, d_loose);
    CHECK(d_tight <= (sizeof(ls_real) == sizeof(float) ? 1e-4 : 1e-9) * scale);
    CHECK(d_loose > 10 * d_tight);
    for (k = 0; k < 3; k++) free(x[k]);
}

/* Bad knob values are named errors; the pair mode's two images cost memory
 * only in that mode. */
static void fit_knob_errors_and_memory(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views v;
    ls_fit fit;
    ls_mesh init;
    size_t exact_bytes = 0, pair_bytes = 0;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    sphere(&arena, &init);
    views_of(&v);
    config(&c);
    c.silhouette = 3;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
    config(&c);
    c.silhouette = LS_FIT_SILHOUETTE_PAIR;
    c.ss = 2;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
    config(&c);
    c.power = 3;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
    config(&c);
    c.cg_tol = (ls_real)-1;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
    config(&c);
    REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &exact_bytes, NULL) == LS_OK);
    c.silhouette = LS_FIT_SILHOUETTE_PAIR;
    REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &pair_bytes, NULL) == LS_OK);
    printf("     fit bytes: exact %lu, pair %lu\n", (unsigned long)exact_bytes, (unsigned long)pair_bytes);
    CHECK(pair_bytes >= exact_bytes + 2u * 4u * RES * RES * sizeof(ls_real) - 64u);
}

/* The adaptive supersampling knob (raster_refine.h): A <= S is off, bit for
 * bit (same loss, gradient, memory); A = 8 changes the loss and the gradient
 * (it sees the silhouette pixels' box values, closer to the S = 4 targets),
 * and the loss is that of the refined images composed here; A above the
 * maximum or with the pair mode is an error. */
static void fit_adaptive_supersampling(void)
{
    ls_fit_config c;
    ls_real g_off[3 * 42], g_one[3 * 42], g_aa[3 * 42], l_off, l_one, l_aa;
    size_t b_off = 0, b_aa = 0, b_one = 0;
    double diff = 0;
    uint32_t i;
    config(&c);
    first_gradient(&c, g_off, &l_off);
    c.aa = 1;
    first_gradient(&c, g_one, &l_one);
    c.aa = 8;
    first_gradient(&c, g_aa, &l_aa);
    CHECK(memcmp(g_off, g_one, sizeof g_off) == 0);
    CHECK(l_off == l_one);
    for (i = 0; i < 3 * 42; i++) diff += fabs((double)g_aa[i] - (double)g_off[i]);
    printf("     loss S = 1 %.6f, A = 8 %.6f; |g_A8 - g_off|_1 = %.4g\n", (double)l_off, (double)l_aa, diff);
    CHECK(l_aa < l_off);
    CHECK(diff > 1e-4);
    {
        double sum = 0;
        composed_loss(0, 8, &sum); /* the refined loss composed independently */
        printf("     refined loss composed here %.9f, by the fit %.9f\n", sum, (double)l_aa);
        CHECK_NEAR((double)l_aa, sum, 1e-12 + TEST_EPS(16) * sum);
    }
    {
        ls_arena arena;
        ls_fit_views v;
        ls_fit fit;
        ls_mesh init;
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        sphere(&arena, &init);
        views_of(&v);
        config(&c);
        REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &b_off, NULL) == LS_OK);
        c.aa = 1;
        REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &b_one, NULL) == LS_OK);
        c.aa = 8;
        REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &b_aa, NULL) == LS_OK);
        printf("     fit bytes: off %lu, A = 8 %lu\n", (unsigned long)b_off, (unsigned long)b_aa);
        CHECK_EQ(b_one, b_off);
        CHECK(b_aa >= b_off);
        c.aa = LS_REFINE_MAX + 1;
        CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
        c.aa = 4;
        c.silhouette = LS_FIT_SILHOUETTE_PAIR;
        CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
    }
}


/* The mask pull (config.mask_pull): from a sphere of radius 1.2 around the
 * 1 x 0.7 x 1 ellipsoid many vertices project outside the targets' masks.
 * Its value is recomputed here with a brute-force distance transform (the
 * nearest covered pixel centre by a search over all of them) and the same
 * bilinear sampling; its gradient (dL/dx with the pull minus without) is
 * checked against central differences of that independent value. */
static double pull_dist(const ls_real *t, uint32_t px, uint32_t py)
{
    double best = 1e300;
    uint32_t x, y;
    for (y = 0; y < RES; y++)
        for (x = 0; x < RES; x++)
            if (t[4u * (y * RES + x) + 3u] > 0) {
                double dx = (double)x - (double)px, dy = (double)y - (double)py, d = dx * dx + dy * dy;
                if (d < best) best = d;
            }
    return sqrt(best);
}

static double *pull_fields(void)
{
    double *g = (double *)malloc((size_t)NV * RES * RES * sizeof(double));
    uint32_t v, x, y;
    if (g == NULL) return NULL;
    for (v = 0; v < NV; v++)
        for (y = 0; y < RES; y++)
            for (x = 0; x < RES; x++) g[((size_t)v * RES + y) * RES + x] = pull_dist(targets[v], x, y);
    return g;
}

/* w / (NV n) sum of max(0, d - 1)^2 over the views and the positions p. */
static double pull_value(const double *g, const double *p, uint32_t n, double w)
{
    double sum = 0;
    uint32_t v, i;
    for (v = 0; v < NV; v++)
        for (i = 0; i < n; i++) {
            const ls_real *m = mvps[v];
            double c[4], fx, fy, tx, ty, d;
            const double *f = g + (size_t)v * RES * RES;
            uint32_t r, ix, iy;
            for (r = 0; r < 4; r++)
                c[r] = (double)m[4 * r] * p[3 * i] + (double)m[4 * r + 1] * p[3 * i + 1] + (double)m[4 * r + 2] * p[3 * i + 2] +
                       (double)m[4 * r + 3];
            if (!(c[3] > 0)) continue;
            fx = (c[0] / c[3] + 1) * 0.5 * RES - 0.5;
            fy = (1 - c[1] / c[3]) * 0.5 * RES - 0.5;
            if (!(fx >= 0 && fy >= 0 && fx < RES - 1 && fy < RES - 1)) continue;
            ix = (uint32_t)fx, iy = (uint32_t)fy;
            tx = fx - ix, ty = fy - iy;
            d = (1 - ty) * ((1 - tx) * f[iy * RES + ix] + tx * f[iy * RES + ix + 1]) +
                ty * ((1 - tx) * f[(iy + 1) * RES + ix] + tx * f[(iy + 1) * RES + ix + 1]);
            if (d > 1) sum += (d - 1) * (d - 1);
        }
    return sum * w / ((double)NV * n);
}

static void fit_mask_pull(void)
{
    ls_arena arena;
    ls_fit_config c;
    ls_fit_views v;
    ls_fit fit;
    ls_mesh init;
    const double w = 0.5, h = 1e-6;
    double *g = pull_fields(), *p, value, worst = 0, largest = 0;
    ls_real *with, *without, reg;
    size_t bytes_off = 0, bytes_on = 0;
    uint32_t n, i, outside = 0;
    REQUIRE(g != NULL);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    sphere(&arena, &init);
    n = init.vertex_count;
    for (i = 0; i < 3u * n; i++) init.positions[i] *= (ls_real)1.5; /* radius 1.2 */
    views_of(&v);
    config(&c);
    with = (ls_real *)malloc(3u * n * sizeof(ls_real));
    without = (ls_real *)malloc(3u * n * sizeof(ls_real));
    p = (double *)malloc(3u * n * sizeof(double));
    REQUIRE(with != NULL && without != NULL && p != NULL);
    REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &bytes_off, NULL) == LS_OK);
    REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, NULL) == LS_OK);
    REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
    memcpy(without, fit.gx, 3u * n * sizeof(ls_real));
    CHECK(fit.reg_loss == 0);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    sphere(&arena, &init);
    for (i = 0; i < 3u * n; i++) init.positions[i] *= (ls_real)1.5;
    c.mask_pull = (ls_real)w;
    REQUIRE(ls_fit_bytes(&c, &v, &init, &arena, &bytes_on, NULL) == LS_OK);
    REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, NULL) == LS_OK);
    REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
    memcpy(with, fit.gx, 3u * n * sizeof(ls_real));
    reg = fit.reg_loss;
    for (i = 0; i < 3u * n; i++) p[i] = (double)init.positions[i];
    value = pull_value(g, p, n, w);
    for (i = 0; i < 3u * n; i++) {
        double keep = p[i], fd, got;
        p[i] = keep + h;
        fd = pull_value(g, p, n, w);
        p[i] = keep - h;
        fd = (fd - pull_value(g, p, n, w)) / (2 * h);
        p[i] = keep;
        got = (double)(with[i] - without[i]) / (double)fit.scale; /* gx is in the fit's frame: S dL/dx */
        if (fabs(fd - got) > worst) worst = fabs(fd - got);
        if (fabs(fd) > largest) largest = fabs(fd);
        outside += fd != 0;
    }
    printf("     mask pull: value %.6g (here %.6g), %u coordinates pulled, largest gradient %.3g, worst difference "
           "to central differences %.3g; bytes %lu -> %lu\n",
           (double)reg, value, (unsigned)outside, largest, worst, (unsigned long)bytes_off, (unsigned long)bytes_on);
    CHECK(value > 0 && outside > 20);
    CHECK(fabs((double)reg - value) <= 1e-9 * value + TEST_EPS(64));
    CHECK(worst <= 1e-5 * largest + TEST_EPS(1e6));
    CHECK(bytes_on >= bytes_off + (size_t)NV * RES * RES * sizeof(ls_real));
    c.mask_pull = (ls_real)-1;
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, NULL), LS_ERR_INVALID);
    free(g);
    free(p);
    free(with);
    free(without);
}

int main(void)
{
    uint32_t v;
    TEST_INIT("test_fit_knobs");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(make_targets);
    TEST_RUN(fit_power_one_and_two);
    TEST_RUN(fit_silhouette_modes);
    TEST_RUN(fit_cg_tolerance);
    TEST_RUN(fit_knob_errors_and_memory);
    TEST_RUN(fit_adaptive_supersampling);
    TEST_RUN(fit_mask_pull);
    for (v = 0; v < NV; v++) free(targets[v]);
    free(buf);
    return TEST_END();
}
