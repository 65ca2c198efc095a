/* fit_internal.h - what the fit's files share (private to src/fit): the
 * sizing records, error helpers, and the functions one file offers the
 * others. fit.c: configuration, sizing, set-up and the iteration;
 * fit_views.c: the iteration's views on the caller's workers;
 * fit_remesh.c: checkpoints, self-intersection checks and remeshing (also
 * inside a job's memory); fit_job.c: a whole job's memory, planned up front. */
#ifndef LS_FIT_INTERNAL_H
#define LS_FIT_INTERNAL_H
#include <string.h>
#include <largesteps/fit.h>
#include <largesteps/laplacian.h>
#include <largesteps/loss.h>
#include <largesteps/render_backward.h>
#include <largesteps/remesh.h>
#include "../base/diag_internal.h"

static inline void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index)
{
    if (diag == NULL) return;
    ls_diag_clear(diag);
    diag->status = st;
    diag->what = what;
    diag->has_index = 1;
    diag->index = index;
}

static inline int finite_r(ls_real x) { return x - x == x - x; }

static inline uint64_t fit_now(const ls_monitor *m) { return (m != NULL && m->clock != NULL) ? m->clock(m->user) : 0u; }

static inline int fit_pair_mode(const ls_fit_config *c) { return c->silhouette == LS_FIT_SILHOUETTE_PAIR; }

/* The views an iteration renders: config.view_batch of the pool's count, or all of them. */
static inline uint32_t fit_batch(const ls_fit_config *c, uint32_t count)
{
    return c->view_batch > 0u && c->view_batch < count ? c->view_batch : count;
}

/* The block's layout, mirrored by ls_fit_bytes and ls_fit_init: the arrays,
 * the Laplacian (with its build scratch), M and its solver, the optimizer,
 * the edge table, the visibility buffer, then the scratch of one iteration. */
typedef struct fit_sizes {
    size_t arrays, lap, param, optim, edges, vis, iteration;
} fit_sizes;

/* A worker's buffers (config.workers; fit.h's parallelism). Worker 0 uses
 * the fit's own (vis, image, gimage, pair images, the block's top as
 * scratch); the others, these. */
struct ls_fit_worker {
    ls_vis vis;
    ls_real *image, *gimage, *pair_image, *pair_gimage;
    ls_arena scratch; /* raster, silhouette and refinement scratch of one view */
    ls_view view;     /* the view this worker renders (every worker, the first too) */
};

/* One view's results until they are added to the totals in view order. */
struct ls_fit_slot {
    ls_real *gx, *gn;     /* [3 n] dL/d(rendered positions), dL/d(vertex normals), from zero */
    ls_real *albedo_sums; /* [6 n] LS_FIT_ALBEDO_VERTEX: the albedo's num, den (else NULL) */
    ls_loss_acc acc;      /* the view's loss (one view) */
    ls_sh_normal ne;      /* LS_FIT_LIGHT_ESTIMATE: the view's lighting sums */
    uint64_t render_ns, shade_backward_ns, silhouette_ns;
    ls_status st;
    ls_diag diag;
};

/* The mask pull's blocks of vertices (fit_mask_pull.c): a fixed count, so
 * its value is the same sum for every worker count. */
#define LS_FIT_MASK_PARTS 32u

/* One iteration's views pass (fit_views.c): what its tasks share, in the
 * fit's memory rather than on the stack under the tasks' deep chains. */
struct ls_fit_pass {
    ls_fit *fit;
    const ls_monitor *monitor;
    ls_view base;    /* what every view shares: positions, indices, normals, shading, edges */
    ls_loss_acc acc; /* the batch's loss, the slots merged in view order */
    uint32_t first;  /* the chunk's first view in the batch */
    uint32_t batch, sums, shaded, albedo;
    uint32_t count, parts; /* the chunk's views; the sum's and the normals' parts */
    ls_real mask_scale, mask_sums[LS_FIT_MASK_PARTS]; /* config.mask_pull: its scale, each block's value */
    /* W > 1 (fit_normals.c), else NULL: each vertex's corners (3 t + k) in
     * face order, [vf_start[v], vf_start[v + 1]); the sums of its faces'
     * normals; per face, its terms (3 normal, or 9 gradient reals) and
     * whether it has any */
    uint32_t *vf_start, *vf_corner;
    ls_real *nsum, *face_buf;
    unsigned char *face_ok;
};

/* W (at least 1) and the slots: one per view when alone, else
 * LS_FIT_SLOTS_PER_WORKER per worker so that a slow view does not hold the
 * others back, and never more than an iteration's views. */
static inline uint32_t fit_workers(const ls_fit_config *c) { return c->workers > 1u ? c->workers : 1u; }
/* LS_FIT_LIGHT_ESTIMATE: whether the step about to run (or running:
 * fit->iteration is counted up after the solve) makes a new estimate. */
static inline int fit_light_iteration(const ls_fit *fit)
{
    return fit->iteration % LS_FIT_LIGHT_EVERY == LS_FIT_LIGHT_EVERY - 1u;
}
static inline uint32_t fit_slots(const ls_fit_config *c, uint32_t views)
{
    const uint32_t batch = fit_batch(c, views) > 0u ? fit_batch(c, views) : 1u;
    const uint32_t slots = fit_workers(c) > 1u ? LS_FIT_SLOTS_PER_WORKER * fit_workers(c) : 1u;
    return slots < batch ? slots : batch;
}

/* The counts a job's capacity bounds (ls_fit_capacity, plus the edges). */
typedef struct fit_counts {
    uint32_t vertices, faces, edges, factor_nnz;
} fit_counts;

/* ---- what each file offers the others ---- */

/* fit_job.c */
ls_status ls_fit_impl_over(ls_diag *diag, const char *what, uint64_t count, uint32_t cap);
ls_status ls_fit_impl_within(const fit_counts *have, const fit_counts *lim, int remesh, ls_diag *diag);

/* fit_views.c: renders every view of the iteration's batch and accumulates
 * the loss and dL/d(rendered positions) into fit->gx (fit->xr set). */
ls_status ls_fit_impl_views_pass(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag);

/* fit_normals.c: the vertex normals of fit->xr into fit->normals, and
 * their backward (fit->gnormals added into fit->gx), on the workers when
 * W > 1; ls_fit_impl_incidence rebuilds the vertex-to-corner lists after
 * the triangles change. */
void ls_fit_impl_incidence(const ls_fit *fit);
ls_status ls_fit_impl_normals(ls_fit *fit, ls_diag *diag);
ls_status ls_fit_impl_normals_backward(ls_fit *fit, ls_diag *diag);

/* fit.c */
void ls_fit_impl_measure_frame(const ls_mesh *m, ls_real *scale, ls_real *radius);
void ls_fit_impl_param_config(const ls_fit_config *c, uint32_t n, ls_param_config *pc);
int ls_fit_impl_optimizes_u(const ls_fit_config *c);
ls_status ls_fit_impl_iteration_scratch(const ls_fit_config *c, uint32_t n, uint32_t f, const ls_csc *lap, size_t *bytes);
ls_status ls_fit_impl_total(const fit_sizes *z, size_t *bytes);
ls_status ls_fit_impl_base_sizes(const ls_fit_config *c, uint32_t views, uint32_t n, uint32_t f, uint32_t edges, fit_sizes *z);
ls_status ls_fit_impl_fit_bytes_frame(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                                 ls_real scale, ls_arena *scratch, size_t *bytes, fit_counts *counts, ls_diag *diag);
ls_status ls_fit_impl_fit_init_frame(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views,
                                const ls_mesh *initial, ls_real scale, ls_real radius, const fit_counts *lim,
                                ls_arena *arena, ls_diag *diag);
/* A fit made again on a new mesh of the same job (remeshing): the
 * schedule's state (iteration, remeshes, timing, capacity, job) kept, the
 * learning rate times lr_factor. */
ls_status ls_fit_impl_rebuild(ls_fit *fit, ls_real lr_factor, const ls_mesh *mesh, ls_arena *arena, ls_diag *diag);
ls_status ls_fit_impl_init_args_ok(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                              ls_diag *diag);

/* fit_mask_pull.c: config.mask_pull. The arrays' counts (0 when off), the
 * distance fields from the targets (at set-up), and the term of an
 * iteration (its value added to reg_loss, its gradient to gx). */
void ls_fit_impl_mask_sizes(const ls_fit_config *c, uint32_t views, size_t *reals, size_t *indices);
void ls_fit_impl_mask_init(ls_fit *fit);
void ls_fit_impl_mask_pull(ls_fit *fit);

#endif
