/* fit_remesh.c - the fit's checkpoints, self-intersection checks and remeshing,
 * also inside a job's memory (include/largesteps/fit.h) */
#include "fit_internal.h"

static ls_status remesh_in_job(ls_fit *fit, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info, ls_diag *diag);

/* The current mesh in the fit's frame: M^-1 u (large steps; the CG's warm
 * start and statistics are put back, from the block's scratch) or x, plus
 * the translation. */
static ls_status frame_mesh(ls_fit *fit, ls_real *positions)
{
    const uint32_t n = fit->vertex_count;
    if (ls_fit_impl_optimizes_u(&fit->config)) {
        const size_t nn = 3u * (size_t)n;
        const ls_cg_info cg = fit->param.cg;
        ls_arena_mark mark = ls_arena_save(&fit->block);
        ls_real *warm = NULL;
        ls_status st;
        if (fit->config.solver == LS_PARAM_CG) {
            warm = (ls_real *)ls_arena_scratch(&fit->block, nn, sizeof(ls_real));
            if (warm == NULL) return LS_ERR_NOMEM; /* not reached: the iteration's reserve */
            memcpy(warm, fit->param.warm_fwd, nn * sizeof(ls_real));
        }
        st = ls_param_from_differential(&fit->param, fit->params, positions);
        if (warm != NULL) {
            memcpy(fit->param.warm_fwd, warm, nn * sizeof(ls_real));
            fit->param.cg = cg;
        }
        ls_arena_restore(&fit->block, mark);
        if (st != LS_OK) return st;
    } else {
        memcpy(positions, fit->x, 3u * (size_t)n * sizeof(ls_real));
    }
    if (fit->config.use_translation) {
        uint32_t i, k;
        for (i = 0; i < n; i++)
            for (k = 0; k < 3; k++) positions[3u * i + k] += fit->params[3u * n + k];
    }
    return LS_OK;
}

/* The current mesh's self-intersections: all of ls_tangle's report, or
 * (whole 0) the pairs alone. */
static ls_status fit_tangle_call(ls_fit *fit, int whole, ls_tangle_report *out, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_real *pos;
    ls_mesh m;
    ls_status st;
    if (fit == NULL || out == NULL || fit->x == NULL) return ls_invalid_arg(diag, "fit or out is NULL, or fit not initialised");
    if (!fit->config.guard) return ls_invalid_arg(diag, "fit->config.guard: 0; ls_fit_tangle needs a fit made with guard = 1");
    mark = ls_arena_save(&fit->block);
    pos = (ls_real *)ls_arena_scratch(&fit->block, 3u * (size_t)fit->vertex_count, sizeof(ls_real));
    st = pos != NULL ? frame_mesh(fit, pos) : LS_ERR_NOMEM; /* not reached: the reserve */
    if (st == LS_OK) {
        const ls_parallel *par = &fit->config.parallel;
        const uint32_t w = fit_workers(&fit->config);
        m.positions = pos;
        m.triangles = fit->triangles;
        m.vertex_count = fit->vertex_count;
        m.face_count = fit->face_count;
        st = whole ? ls_tangle_parallel(&m, NULL, par, w, &fit->block, out, diag)
                   : ls_tangle_pairs(&m, par, w, &fit->block, out, diag);
    }
    ls_arena_restore(&fit->block, mark);
    return st;
}

/* The checkpoint's parts: params, m1, m2 (the optimizer's count each), x. */
static void saved_parts(const ls_fit *fit, ls_real **parts)
{
    const size_t count = fit->optim.count;
    parts[0] = fit->saved;
    parts[1] = parts[0] + count;
    parts[2] = parts[1] + count;
    parts[3] = parts[2] + count;
}

ls_status ls_fit_save(ls_fit *fit)
{
    ls_real *p[4];
    size_t count;
    if (fit == NULL || fit->saved == NULL) return LS_ERR_INVALID;
    count = fit->optim.count;
    saved_parts(fit, p);
    memcpy(p[0], fit->params, count * sizeof(ls_real));
    memcpy(p[1], fit->optim.m1, count * sizeof(ls_real));
    memcpy(p[2], fit->optim.m2, count * sizeof(ls_real));
    memcpy(p[3], fit->x, 3u * (size_t)fit->vertex_count * sizeof(ls_real));
    memcpy(fit->saved_last_scale, fit->optim.last_scale, sizeof fit->saved_last_scale);
    fit->saved_step = fit->optim.step;
    fit->saved_iteration = fit->iteration;
    memcpy(fit->saved_sh, fit->sh, sizeof fit->saved_sh);
    fit->saved_sh_valid = fit->sh_valid;
    fit->saved_valid = 1;
    return LS_OK;
}

ls_status ls_fit_rollback(ls_fit *fit)
{
    ls_real *p[4];
    size_t count;
    if (fit == NULL || fit->saved == NULL || !fit->saved_valid) return LS_ERR_INVALID;
    count = fit->optim.count;
    saved_parts(fit, p);
    memcpy(fit->params, p[0], count * sizeof(ls_real));
    memcpy(fit->optim.m1, p[1], count * sizeof(ls_real));
    memcpy(fit->optim.m2, p[2], count * sizeof(ls_real));
    memcpy(fit->x, p[3], 3u * (size_t)fit->vertex_count * sizeof(ls_real));
    memcpy(fit->optim.last_scale, fit->saved_last_scale, sizeof fit->saved_last_scale);
    fit->optim.step = fit->saved_step;
    fit->iteration = fit->saved_iteration;
    memcpy(fit->sh, fit->saved_sh, sizeof fit->sh);
    fit->sh_valid = fit->saved_sh_valid;
    return LS_OK;
}

ls_status ls_fit_mesh(ls_fit *fit, ls_real *positions, ls_mesh *mesh)
{
    size_t i;
    ls_status st;
    if (fit == NULL || positions == NULL || mesh == NULL || fit->x == NULL) return LS_ERR_INVALID;
    st = frame_mesh(fit, positions);
    if (st != LS_OK) return st;
    for (i = 0; i < 3u * (size_t)fit->vertex_count; i++) positions[i] *= fit->scale;
    mesh->positions = positions;
    mesh->triangles = fit->triangles;
    mesh->vertex_count = fit->vertex_count;
    mesh->face_count = fit->face_count;
    return LS_OK;
}

/* The guard's check of a remesh: LS_ERR_MESH when `out` self-intersects
 * more than `cur` (scratch of `work` only). Its own frame: the remesher's
 * call chain does not carry the two reports. */
LS_NOINLINE static ls_status no_new_tangles(const ls_fit *fit, const ls_mesh *cur, const ls_mesh *out, ls_arena *work,
                                            ls_diag *diag)
{
    ls_tangle_report before, after;
    const ls_parallel *par = &fit->config.parallel;
    const uint32_t w = fit_workers(&fit->config);
    ls_status st = ls_tangle_pairs(cur, par, w, work, &before, diag);
    if (st == LS_OK) st = ls_tangle_pairs(out, par, w, work, &after, diag);
    if (st == LS_OK && after.intersecting_pairs > before.intersecting_pairs) {
        diag_set(diag, LS_ERR_MESH, "remesh: the result self-intersects more than the mesh (try another h)",
                 fit->iteration);
        if (diag != NULL) diag->value = (ls_real)after.intersecting_pairs, diag->has_value = 1;
        st = LS_ERR_MESH;
    }
    return st;
}

/* The current mesh remeshed to h_factor x its mean edge (ls_fit_remesh's
 * first half) into *out at the bottom of `work`, in caller units (the
 * frame's positions times S: exact), from positions in work's scratch;
 * vertex_cap as in ls_remesh_params (0: the remesher's estimate). The
 * caller restores `work`. */
static ls_status remesh_current(ls_fit *fit, ls_arena *work, ls_real h_factor, uint32_t vertex_cap, ls_mesh *out,
                                ls_remesh_info *info, ls_diag *diag)
{
    ls_remesh_params params;
    ls_mesh cur;
    ls_real mean, *pos;
    size_t i;
    ls_status st;
    pos = (ls_real *)ls_arena_scratch(work, 3u * (size_t)fit->vertex_count, sizeof(ls_real));
    if (pos == NULL) return LS_ERR_NOMEM;
    /* remeshed in the fit's frame, so that the result does not depend on
     * the scene's scale */
    st = frame_mesh(fit, pos);
    cur.positions = pos;
    cur.triangles = fit->triangles;
    cur.vertex_count = fit->vertex_count;
    cur.face_count = fit->face_count;
    if (st == LS_OK) st = ls_remesh_mean_edge(&cur, &mean);
    if (st == LS_OK) {
        ls_remesh_params_default(&params, h_factor * mean);
        params.vertex_cap = vertex_cap;
        st = ls_remesh(&cur, &params, work, out, info, diag);
    }
    if (st == LS_OK && fit->config.guard) st = no_new_tangles(fit, &cur, out, work, diag);
    if (st != LS_OK) return st;
    /* the new fit's initial mesh in the caller's units (exact: S is a power of two) */
    for (i = 0; i < 3u * (size_t)out->vertex_count; i++) out->positions[i] *= fit->scale;
    return LS_OK;
}


static ls_status fit_remesh_call(ls_fit *fit, ls_arena *arena, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info, ls_diag *diag)
{
    ls_arena_mark mark, keep;
    ls_mesh out, copy;
    size_t start, new_bytes, copy_bytes;
    ls_status st;
    if (fit == NULL || fit->x == NULL) return ls_invalid_arg(diag, "fit: NULL or not initialised (ls_fit_init)");
    if (!(h_factor > (ls_real)0) || !(h_factor <= (ls_real)2))
        return ls_invalid_arg(diag, "h_factor: the target edge over the mean edge, allowed (0, 2] (the method: 0.5)");
    if (!(lr_factor > (ls_real)0) || !finite_r(lr_factor) || !finite_r(fit->config.optim.lr * lr_factor))
        return ls_invalid_arg(diag, "lr_factor: allowed finite and > 0 (the method: 0.8)");
    if (fit->job.base != NULL) return remesh_in_job(fit, h_factor, lr_factor, info, diag);
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL (a fit from ls_fit_init remeshes in its arena)");
    start = (size_t)(fit->block.base - arena->base);
    if (fit->block.base < arena->base || start + LS_ARENA_ROUND(fit->block.capacity) != arena->bottom)
        return ls_invalid_arg(diag, "arena: the fit must be the last allocation at its bottom");
    mark = ls_arena_save(arena);
    st = remesh_current(fit, arena, h_factor, 0, &out, info, diag);
    /* the sizes do not depend on the learning rate */
    if (st == LS_OK) st = ls_fit_impl_fit_bytes_frame(&fit->config, &fit->views, &out, fit->scale, arena, &new_bytes, NULL, diag);
    if (st == LS_OK) st = ls_mesh_bytes(out.vertex_count, out.face_count, &copy_bytes);
    if (st == LS_OK) {
        /* after the swap: [start, start + new fit) at the bottom, the copy of the
         * remeshed mesh at the top, with the caller's top use above it */
        size_t during = arena->bottom + copy_bytes + mark.top; /* the copy while the output still exists */
        size_t need = start + new_bytes + copy_bytes + mark.top;
        if (during > need) need = during;
        if (need > arena->capacity || need < start) {
            arena->need = need;
            diag_set(diag, LS_ERR_NOMEM, "arena too small for the remeshed fit", fit->iteration);
            st = LS_ERR_NOMEM;
        }
    }
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    /* the point of no return: copy the new mesh to the top, release the old
     * fit and the remesher's output, build the new fit in their place */
    keep.bottom = arena->bottom;
    keep.top = mark.top;
    ls_arena_restore(arena, keep);
    copy.vertex_count = out.vertex_count;
    copy.face_count = out.face_count;
    {
        ls_real *cp = (ls_real *)ls_arena_scratch(arena, 3u * (size_t)out.vertex_count, sizeof(ls_real));
        uint32_t *ct = (uint32_t *)ls_arena_scratch(arena, 3u * (size_t)out.face_count, sizeof(uint32_t));
        memcpy(cp, out.positions, 3u * (size_t)out.vertex_count * sizeof(ls_real));
        memcpy(ct, out.triangles, 3u * (size_t)out.face_count * sizeof(uint32_t));
        copy.positions = cp;
        copy.triangles = ct;
    }
    keep.bottom = start;
    keep.top = arena->top;
    ls_arena_restore(arena, keep);
    st = ls_fit_impl_rebuild(fit, lr_factor, &copy, arena, diag);
    keep.bottom = arena->bottom;
    keep.top = mark.top;
    ls_arena_restore(arena, keep);
    return st;
}

/* ls_fit_remesh inside the job's reservation: the remesher and the new
 * fit's measurement in the work part, every count checked against the
 * capacity before the old fit is touched, then the new fit built in the
 * fit's part from the output still in the work part (no copy needed). */
static ls_status remesh_in_job(ls_fit *fit, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info, ls_diag *diag)
{
    ls_arena_mark mark = ls_arena_save(&fit->job);
    ls_arena region;
    fit_counts lim, have;
    ls_mesh out;
    size_t new_bytes = 0;
    ls_status st;
    memset(&out, 0, sizeof out);
    lim.vertices = fit->capacity.max_vertices;
    lim.faces = fit->capacity.max_faces;
    lim.edges = fit->max_edges;
    lim.factor_nnz = fit->capacity.max_factor_nnz;
    st = remesh_current(fit, &fit->job, h_factor, lim.vertices, &out, info, diag);
    /* the work part holds the remesher's bound at max_vertices: running
     * out of it is running out of vertex capacity */
    if (st == LS_ERR_NOMEM) st = ls_fit_impl_over(diag, "remesh: more vertices than capacity.max_vertices", (uint64_t)lim.vertices + 1u, lim.vertices);
    if (st == LS_OK) {
        have.vertices = out.vertex_count;
        have.faces = out.face_count;
        have.edges = have.factor_nnz = 0;
        st = ls_fit_impl_within(&have, &lim, 1, diag);
    }
    /* the sizes do not depend on the learning rate */
    if (st == LS_OK) st = ls_fit_impl_fit_bytes_frame(&fit->config, &fit->views, &out, fit->scale, &fit->job, &new_bytes, &have, diag);
    if (st == LS_OK) st = ls_fit_impl_within(&have, &lim, 1, diag);
    if (st == LS_OK && new_bytes > fit->job_fit_bytes) /* not reached: the bound covers the counts */
        st = ls_fit_impl_over(diag, "remesh: the new fit exceeds the job's reservation", new_bytes, (uint32_t)0);
    if (st != LS_OK) {
        ls_arena_restore(&fit->job, mark);
        return st;
    }
    /* the point of no return */
    st = ls_arena_init(&region, fit->job.base, fit->job_fit_bytes);
    if (st == LS_OK) st = ls_fit_impl_rebuild(fit, lr_factor, &out, &region, diag);
    ls_arena_restore(&fit->job, mark);
    return st;
}

ls_status ls_fit_tangle(ls_fit *fit, ls_tangle_report *out, ls_diag *diag)
{
    ls_status st = fit_tangle_call(fit, 1, out, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

ls_status ls_fit_tangle_pairs(ls_fit *fit, ls_tangle_report *out, ls_diag *diag)
{
    ls_status st = fit_tangle_call(fit, 0, out, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

ls_status ls_fit_remesh(ls_fit *fit, ls_arena *arena, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info,
                        ls_diag *diag)
{
    ls_status st = fit_remesh_call(fit, arena, h_factor, lr_factor, info, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}
