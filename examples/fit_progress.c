/* fit_progress.c - a whole reconstruction with ls_fit: a sphere fitted to six
 * views of an ellipsoid, memory sized up front, a progress callback that
 * reports and can cancel, one remesh halfway, and the result measured.
 * The callback here cancels once the user asks to stop (in a program, a
 * signal handler or a button sets the flag; here iteration 150 does): the
 * step in progress returns LS_ERR_CANCELLED and leaves the fit as it was.
 */
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <largesteps.h>

#define RES 32u
#define VIEWS 6u

static ls_real mvps[VIEWS][16], sh[27];
static ls_real *targets[VIEWS];
static const ls_real axes[3] = {(ls_real)1.0, (ls_real)0.65, (ls_real)0.8};

/* The progress callback: counts the views it is told about; non-zero cancels. */
typedef struct job {
    int stop_requested;
    unsigned long reports;
} job;

static int32_t on_progress(void *user, const ls_progress *p)
{
    job *j = (job *)user;
    (void)p; /* p->stage, p->done, p->total: what the fit is doing */
    j->reports++;
    return j->stop_requested ? 1 : 0;
}

/* Target images: the ellipsoid seen from VIEWS directions, SH lighting. */
static ls_status make_targets(ls_arena *a)
{
    ls_arena_mark mark = ls_arena_save(a);
    ls_real dirs[3 * VIEWS], proj[16], view[16], *normals;
    const ls_real center[3] = {0, 0, 0};
    ls_shade_opts o;
    ls_mesh m;
    ls_vis vis;
    ls_view target; /* one view of the ellipsoid; mvp set per view */
    uint32_t v, i;
    ls_status st = ls_icosphere(3, a, &m);
    for (i = 0; st == LS_OK && i < 3u * m.vertex_count; i++) m.positions[i] *= axes[i % 3];
    normals = st == LS_OK ? ls_arena_alloc(a, 3u * m.vertex_count, sizeof(ls_real)) : NULL;
    if (normals == NULL) return LS_ERR_NOMEM;
    st = ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, normals, NULL);
    if (st == LS_OK) st = ls_camera_fibonacci_dirs(VIEWS, dirs);
    if (st == LS_OK) st = ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1, 10, proj);
    if (st == LS_OK) st = ls_vis_init(&vis, a, RES, RES, 4, m.vertex_count);
    for (i = 0; i < 3; i++) sh[9 * i] = (ls_real)1.6, sh[9 * i + 1] = (ls_real)0.9, sh[9 * i + 3] = (ls_real)-0.3;
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh;
    memset(&target, 0, sizeof target);
    target.vis = &vis;
    target.positions = m.positions;
    target.indices = m.triangles;
    target.triangle_count = m.face_count;
    target.vertex_count = m.vertex_count;
    target.normals = normals;
    target.opts = &o;
    for (v = 0; v < VIEWS && st == LS_OK; v++) {
        targets[v] = malloc(4u * RES * RES * sizeof(ls_real));
        if (targets[v] == NULL) return LS_ERR_NOMEM;
        st = ls_camera_orbit(center, (ls_real)3.2, dirs + 3 * v, view);
        ls_mat4_mul(proj, view, mvps[v]);
        target.mvp = mvps[v];
        if (st == LS_OK) st = ls_raster(&vis, &target, a, NULL);
        if (st == LS_OK) st = ls_shade(&target, targets[v], NULL);
    }
    ls_arena_restore(a, mark); /* the targets are in malloc'ed memory */
    return st;
}

/* Mean distance of the vertices to the ellipsoid, in units of its radius. */
static double shape_error(const ls_mesh *m)
{
    double sum = 0;
    uint32_t i, k;
    for (i = 0; i < m->vertex_count; i++) {
        double r2 = 0;
        for (k = 0; k < 3; k++) {
            double q = (double)m->positions[3 * i + k] / (double)axes[k];
            r2 += q * q;
        }
        sum += fabs(sqrt(r2) - 1);
    }
    return sum / m->vertex_count;
}

int main(void)
{
    const size_t buffer_bytes = 64u << 20;
    void *buffer = malloc(buffer_bytes);
    ls_arena arena;
    ls_fit_config cfg;
    ls_fit_views views;
    ls_fit fit;
    ls_mesh start, result;
    ls_monitor monitor = {0};
    ls_diag d;
    job j = {0, 0};
    size_t bytes = 0;
    ls_real *positions;
    uint32_t i;
    ls_status st = buffer != NULL ? ls_arena_init(&arena, buffer, buffer_bytes) : LS_ERR_NOMEM;
    if (st == LS_OK) st = make_targets(&arena);
    if (st == LS_OK) st = ls_icosphere(2, &arena, &start); /* 162 vertices, radius 0.6 */
    for (i = 0; st == LS_OK && i < 3u * start.vertex_count; i++) start.positions[i] *= (ls_real)0.6;

    /* The paper's settings, at 32 x 32 with SH shading like the targets. */
    ls_fit_config_default(&cfg);
    cfg.width = cfg.height = RES;
    cfg.shading.mode = LS_SHADE_SH;
    cfg.shading.sh = sh;
    cfg.optim.lr = (ls_real)0.08;
    views.count = VIEWS;
    views.mvp = &mvps[0][0];
    views.targets = (const ls_real *const *)targets;
    if (st == LS_OK) st = ls_fit_bytes(&cfg, &views, &start, &arena, &bytes, &d);
    if (st == LS_OK) printf("the fit takes %zu bytes\n", bytes);
    if (st == LS_OK) st = ls_fit_init(&fit, &cfg, &views, &start, &arena, &d);

    monitor.progress = on_progress;
    monitor.user = &j;
    while (st == LS_OK) {
        if (fit.iteration == 150) j.stop_requested = 1; /* the user asks to stop */
        st = ls_fit_step(&fit, &monitor, &d);
        if (st == LS_OK && fit.iteration % 25 == 0) printf("iteration %3u: loss %.5e\n", fit.iteration, (double)fit.loss);
        if (st == LS_OK && fit.iteration == 100) {
            /* the method's remesh: half the mean edge, learning rate x 0.8 */
            st = ls_fit_remesh(&fit, &arena, (ls_real)0.5, (ls_real)0.8, NULL, &d);
            if (st == LS_OK) printf("remeshed: %u vertices\n", fit.vertex_count);
        }
    }
    if (st != LS_ERR_CANCELLED) {
        printf("stopped: %s (%s)\n", ls_status_str(st), d.what);
        return 1;
    }
    printf("cancelled during iteration %u after %lu progress reports; the fit keeps %u iterations done\n",
           fit.iteration + 1, j.reports, fit.iteration);
    positions = malloc(3u * fit.vertex_count * sizeof(ls_real));
    if (positions == NULL || ls_fit_mesh(&fit, positions, &result) != LS_OK) return 1;
    printf("mean distance to the ellipsoid: %.4f (the start: %.4f)\n", shape_error(&result), shape_error(&start));
    for (i = 0; i < VIEWS; i++) free(targets[i]);
    free(positions);
    free(buffer);
    return 0;
}
