/* fit_views.c - one iteration's views: each rendered, shaded and
 * differentiated by one of the caller's workers into a slot of its own, and
 * the slots added to the totals in view order (fit.h's parallelism) */
#include "fit_internal.h"
#include "../base/parallel.h"
#include <stddef.h>

/* LS_FIT_LIGHT_ESTIMATE before its first estimate: the iteration's views
 * rasterized once more to make it (view: set up by ls_fit_impl_views_pass, the vertex
 * normals computed). A step that fails restores sh_valid (fit_step_call). */
static ls_status first_estimate(ls_fit *fit, ls_view *view, uint32_t batch, ls_diag *diag)
{
    uint32_t k;
    ls_status st = LS_OK;
    if (fit->sh_valid) return LS_OK;
    ls_sh_normal_clear(&fit->sh_sums);
    for (k = 0; k < batch && st == LS_OK; k++) {
        const uint32_t v = ls_fit_view_of(&fit->config, fit->views.count, fit->iteration, k);
        view->mvp = fit->mvp + 16u * (size_t)v;
        st = ls_raster(&fit->vis, view, &fit->block, diag);
        if (st == LS_OK) st = ls_sh_accumulate(&fit->sh_sums, view, fit->views.targets[v], diag);
    }
    if (st != LS_OK) return st;
    if (ls_sh_solve(&fit->sh_sums, fit->sh, NULL) == LS_OK) fit->sh_valid = 1;
    return LS_OK;
}

/* LS_FIT_ALBEDO_VERTEX on a new mesh (albedo_due, the albedo all 1): the
 * iteration's views rasterized once more to estimate it under the lighting
 * in use. A step that fails sets it back to 1 (fit_step_call). */
static ls_status first_albedo(ls_fit *fit, ls_view *view, uint32_t batch, ls_diag *diag)
{
    const size_t nn = 3u * (size_t)fit->vertex_count;
    uint32_t k;
    ls_status st = LS_OK;
    if (!fit->albedo_due || !fit->sh_valid) return LS_OK;
    memset(fit->albedo_sums, 0, 2u * nn * sizeof(ls_real));
    for (k = 0; k < batch && st == LS_OK; k++) {
        const uint32_t v = ls_fit_view_of(&fit->config, fit->views.count, fit->iteration, k);
        view->mvp = fit->mvp + 16u * (size_t)v;
        st = ls_raster(&fit->vis, view, &fit->block, diag);
        if (st == LS_OK)
            st = ls_albedo_accumulate(view, fit->views.targets[v], fit->albedo_sums, fit->albedo_sums + nn, diag);
    }
    if (st != LS_OK) return st;
    (void)ls_albedo_solve(fit->albedo_sums, fit->albedo_sums + nn, fit->vertex_count, fit->albedo, NULL);
    fit->albedo_due = 0;
    return LS_OK;
}

/* The view first + index of the batch, by the caller's worker: rendered,
 * shaded and differentiated into slot `index` (its gradients from zero). */
static void view_task(void *arg, uint32_t index, uint32_t worker)
{
    const struct ls_fit_pass *j = (const struct ls_fit_pass *)arg;
    ls_fit *fit = j->fit;
    const ls_fit_config *c = &fit->config;
    struct ls_fit_slot *sl = fit->slots + index;
    struct ls_fit_worker *w = fit->workers + worker;
    const size_t nn = 3u * (size_t)fit->vertex_count;
    const uint32_t v = ls_fit_view_of(c, fit->views.count, fit->iteration, j->first + index);
    const ls_real *target = fit->views.targets[v];
    ls_real *image = worker == 0 ? fit->image : w->image, *gimage = worker == 0 ? fit->gimage : w->gimage;
    ls_real *pair_image = worker == 0 ? fit->pair_image : w->pair_image;
    ls_real *pair_gimage = worker == 0 ? fit->pair_gimage : w->pair_gimage;
    ls_arena *arena = worker == 0 ? &fit->block : &w->scratch;
    ls_vis *vis = worker == 0 ? &fit->vis : &w->vis;
    ls_diag *diag = &sl->diag;
    ls_view *view = &w->view; /* in the worker's memory, not on the stack: the deep chain below */
    uint64_t t0, t1, t2;
    ls_status st;
    *view = j->base;
    view->vis = vis;
    view->mvp = fit->mvp + 16u * (size_t)v;
    ls_diag_clear(diag);
    memset(sl->gx, 0, nn * sizeof(ls_real));
    if (j->shaded) memset(sl->gn, 0, nn * sizeof(ls_real));
    t0 = fit_now(j->monitor);
    st = ls_loss_begin(&sl->acc, c->loss, c->width, c->height, j->batch);
    if (st == LS_OK) st = ls_raster(vis, view, arena, diag);
    if (st == LS_OK && j->sums) {
        ls_sh_normal_clear(&sl->ne);
        st = ls_sh_accumulate(&sl->ne, view, target, diag);
        if (st == LS_OK && fit->albedo != NULL && fit->sh_valid) {
            memset(sl->albedo_sums, 0, 2u * nn * sizeof(ls_real));
            st = ls_albedo_accumulate(view, target, sl->albedo_sums, sl->albedo_sums + nn, diag);
        }
    }
    if (st == LS_OK) st = ls_shade(view, image, diag);
    if (st == LS_OK && c->aa > c->ss) st = ls_refine_shade(view, c->aa, image, arena, NULL, diag);
    if (st == LS_OK && fit_pair_mode(c)) {
        /* the loss sees the blended image; its gradient goes back through
         * the blending to the positions and to the shaded image */
        st = ls_pair_forward(view, image, pair_image, diag);
        if (st == LS_OK) st = ls_loss_view(&sl->acc, pair_image, target, pair_gimage, diag);
    } else if (st == LS_OK) {
        st = ls_loss_view(&sl->acc, image, target, gimage, diag);
    }
    t1 = fit_now(j->monitor);
    sl->render_ns = t1 - t0;
    if (st == LS_OK && fit_pair_mode(c)) {
        memset(gimage, 0, (size_t)c->width * c->height * 4u * sizeof(ls_real));
        st = ls_pair_backward(view, image, pair_gimage, gimage, sl->gx, diag);
    }
    t2 = fit_now(j->monitor);
    sl->silhouette_ns = t2 - t1;
    if (st == LS_OK && c->aa > c->ss) {
        ls_shade_grads sg;
        memset(&sg, 0, sizeof sg);
        sg.positions = sl->gx;
        sg.normals = j->shaded ? sl->gn : NULL;
        st = ls_refine_shade_backward(view, c->aa, gimage, &sg, arena, diag);
    } else if (st == LS_OK) {
        st = ls_shade_backward(view, gimage, sl->gx, j->shaded ? sl->gn : NULL, NULL, diag);
    }
    t1 = fit_now(j->monitor);
    sl->shade_backward_ns = t1 - t2;
    if (st == LS_OK && c->silhouette == LS_FIT_SILHOUETTE_EXACT)
        st = ls_silhouette_backward(view, gimage, sl->gx, arena, diag);
    sl->silhouette_ns += fit_now(j->monitor) - t1;
    sl->st = st;
}

/* The slots' gradients added to the totals over [lo, hi), slot after slot:
 * each element receives them in view order (any split: the same bits).
 * field: the slot's array, 0 gx, 1 gn, 2 albedo_sums. */
static void add_range(ls_real *to, size_t lo, size_t hi, const struct ls_fit_slot *slots, uint32_t count, uint32_t field)
{
    size_t i;
    uint32_t k;
    for (k = 0; k < count; k++) {
        const ls_real *from = field == 0u ? slots[k].gx : field == 1u ? slots[k].gn : slots[k].albedo_sums;
        for (i = lo; i < hi; i++) to[i] += from[i];
    }
}

static void sum_task(void *arg, uint32_t part, uint32_t worker)
{
    const struct ls_fit_pass *j = (const struct ls_fit_pass *)arg;
    ls_fit *fit = j->fit;
    const size_t nn = 3u * (size_t)fit->vertex_count;
    const size_t lo = nn * part / j->parts, hi = nn * (part + 1u) / j->parts;
    (void)worker;
    add_range(fit->gx, lo, hi, fit->slots, j->count, 0u);
    if (j->shaded) add_range(fit->gnormals, lo, hi, fit->slots, j->count, 1u);
    if (j->albedo) add_range(fit->albedo_sums, 2u * lo, 2u * hi, fit->slots, j->count, 2u);
}

/* Renders every view of the batch and accumulates the loss and dL/d(rendered
 * positions) into fit->gx: the views in chunks of the slots, each chunk's
 * views by the workers, then added in view order (fit.h). */
ls_status ls_fit_impl_views_pass(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
{
    const ls_fit_config *c = &fit->config;
    const uint32_t n = fit->vertex_count, nf = fit->face_count;
    const int shaded = c->shading.mode == LS_SHADE_SH || c->shading.mode == LS_SHADE_LAMBERT;
    const int estimate = c->light == LS_FIT_LIGHT_ESTIMATE;
    const int sums = estimate && fit_light_iteration(fit);
    struct ls_fit_pass *pass = fit->pass; /* the pass's state, off the stack: the tasks' deep chains */
    ls_view *view = &pass->base;
    ls_loss_acc *acc = &pass->acc;
    uint32_t k, batch;
    uint64_t t0;
    ls_status st;
    memset(view, 0, sizeof *view);
    view->vis = &fit->vis;
    view->positions = fit->xr;
    view->indices = fit->triangles;
    view->triangle_count = nf;
    view->vertex_count = n;
    view->normals = fit->normals;
    view->opts = &c->shading;
    if (estimate) { /* the fit's own coefficients (and albedo) */
        fit->lit = c->shading;
        fit->lit.sh = fit->sh;
        fit->lit.vertex_colors = fit->albedo; /* NULL: uniform */
        view->opts = &fit->lit;
    }
    view->table = &fit->edges;
    view->boost = c->boost;
    memset(fit->gx, 0, 3u * (size_t)n * sizeof(ls_real));
    memset(fit->gnormals, 0, 3u * (size_t)n * sizeof(ls_real));
    t0 = fit_now(monitor);
    if (shaded) {
        st = ls_fit_impl_normals(fit, diag);
        if (st != LS_OK) return st;
    }
    batch = fit_batch(c, fit->views.count);
    if (estimate) {
        st = first_estimate(fit, view, batch, diag);
        if (st == LS_OK && fit->albedo != NULL) st = first_albedo(fit, view, batch, diag);
        if (st != LS_OK) return st;
    }
    if (sums) ls_sh_normal_clear(&fit->sh_sums);
    if (sums && fit->albedo != NULL) memset(fit->albedo_sums, 0, 6u * (size_t)n * sizeof(ls_real));
    st = ls_loss_begin(acc, c->loss, c->width, c->height, batch);
    if (st != LS_OK) return st;
    fit->timing.render_ns += fit_now(monitor) - t0;
    pass->fit = fit;
    pass->monitor = monitor;
    pass->batch = batch;
    pass->sums = (uint32_t)sums;
    pass->shaded = (uint32_t)shaded;
    pass->parts = fit_workers(c);
    for (k = 0; k < batch; k += fit->slot_count) {
        const uint32_t count = batch - k < fit->slot_count ? batch - k : fit->slot_count;
        uint32_t i;
        st = ls_monitor_report(monitor, "fit.view", k, batch);
        if (st != LS_OK) return st;
        pass->first = k;
        ls_parallel_run(&c->parallel, fit_workers(c), count, view_task, pass);
        for (i = 0; i < count; i++) { /* the first failure in view order */
            const struct ls_fit_slot *sl = fit->slots + i;
            if (sl->st != LS_OK) {
                if (diag != NULL) *diag = sl->diag;
                return sl->st;
            }
        }
        t0 = fit_now(monitor);
        for (i = 0; i < count; i++) {
            const struct ls_fit_slot *sl = fit->slots + i;
            uint32_t q;
            st = ls_loss_merge(acc, &sl->acc);
            if (st != LS_OK) return st;
            fit->timing.render_ns += sl->render_ns;
            fit->timing.shade_backward_ns += sl->shade_backward_ns;
            fit->timing.silhouette_ns += sl->silhouette_ns;
            if (!sums) continue;
            for (q = 0; q < 45u; q++) fit->sh_sums.ata[q] += sl->ne.ata[q];
            for (q = 0; q < 135u; q++) fit->sh_sums.ata_rgb[q] += sl->ne.ata_rgb[q];
            for (q = 0; q < 27u; q++) fit->sh_sums.atb[q] += sl->ne.atb[q];
            fit->sh_sums.pixels += sl->ne.pixels;
            fit->sh_sums.per_channel |= sl->ne.per_channel;
        }
        pass->count = count;
        pass->albedo = (uint32_t)(sums && fit->albedo != NULL && fit->sh_valid);
        ls_parallel_run(&c->parallel, fit_workers(c), pass->parts, sum_task, pass);
        fit->timing.shade_backward_ns += fit_now(monitor) - t0;
    }
    if (shaded) {
        t0 = fit_now(monitor);
        st = ls_fit_impl_normals_backward(fit, diag);
        fit->timing.shade_backward_ns += fit_now(monitor) - t0;
        if (st != LS_OK) return st;
    }
    return ls_loss_finish(acc, &fit->loss);
}

