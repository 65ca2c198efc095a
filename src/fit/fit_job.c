/* fit_job.c - a whole fit job: its memory planned up front from the
 * schedule's limits (include/largesteps/fit.h) */
#include "fit_internal.h"

/* --- a whole job within one reservation (fit.h: ls_fit_job_bytes) ------ */

/* LS_ERR_TOO_LARGE in *diag: `what` exceeded; index = the count, value =
 * the capacity. */
ls_status ls_fit_impl_over(ls_diag *diag, const char *what, uint64_t count, uint32_t cap)
{
    (void)ls_diag_set(diag, LS_ERR_TOO_LARGE, what, count);
    if (diag != NULL) {
        diag->has_value = 1;
        diag->value = (ls_real)cap;
    }
    return LS_ERR_TOO_LARGE;
}

/* LS_ERR_TOO_LARGE naming the first count of `have` above its limit. */
ls_status ls_fit_impl_within(const fit_counts *have, const fit_counts *lim, int remesh, ls_diag *diag)
{
    static const char *const what[2][4] = {
        {"initial mesh: more vertices than capacity.max_vertices", "initial mesh: more faces than capacity.max_faces",
         "initial mesh: more edges than the capacity allows (max_vertices + max_faces - Euler characteristic)",
         "initial mesh: more LDL^T factor entries than capacity.max_factor_nnz"},
        {"remesh: more vertices than capacity.max_vertices", "remesh: more faces than capacity.max_faces",
         "remesh: more edges than the capacity allows (max_vertices + max_faces - Euler characteristic)",
         "remesh: more LDL^T factor entries than capacity.max_factor_nnz"}};
    uint32_t h[4], l[4], k;
    h[0] = have->vertices, h[1] = have->faces, h[2] = have->edges, h[3] = have->factor_nnz;
    l[0] = lim->vertices, l[1] = lim->faces, l[2] = lim->edges, l[3] = lim->factor_nnz;
    for (k = 0; k < 4; k++)
        if (h[k] > l[k]) return ls_fit_impl_over(diag, what[remesh != 0][k], h[k], l[k]);
    return LS_OK;
}

/* The large-steps LDL^T: the fill has a capacity of its own. */
static int uses_factor(const ls_fit_config *c)
{
    return c->method == LS_FIT_LARGE_STEPS && (c->solver == LS_PARAM_LDLT || c->solver == LS_PARAM_AUTO);
}

/* The reservation for counts within lim and a mesh of Euler characteristic
 * euler: the fit's region (the largest block ls_fit_bytes can answer, and
 * the measurement that precedes it: positions, edges, Laplacian, the
 * factor's analysis) and above it the remesh work (the current positions,
 * then the larger of the remesher's bound at max_vertices and its output
 * with the new fit's measurement). Every term grows with every count. */
static ls_status job_sizes(const ls_fit_config *c, uint32_t views, const fit_counts *lim, int64_t euler,
                           size_t *region, size_t *bytes)
{
    const uint32_t n = lim->vertices, f = lim->faces;
    ls_param_config pc;
    ls_remesh_params rp;
    ls_mesh_report rep;
    ls_mesh shape;
    ls_csc lap;
    ls_size measure, fit, work, after, rm;
    fit_sizes z;
    size_t block = 0, eb = 0, rb = 0, ob = 0, analyze = 0, object = 0, factor = 0;
    ls_status st;
    if ((uint64_t)n + lim->edges > UINT32_MAX) return LS_ERR_TOO_LARGE;
    st = ls_fit_impl_base_sizes(c, views, n, f, lim->edges, &z);
    /* the regularizer's scratch depends on the Laplacian's size only */
    memset(&lap, 0, sizeof lap);
    lap.nrows = lap.ncols = n;
    if (st == LS_OK) st = ls_fit_impl_iteration_scratch(c, n, f, &lap, &z.iteration);
    if (st == LS_OK && c->method == LS_FIT_LARGE_STEPS) {
        ls_fit_impl_param_config(c, n, &pc); /* the capacity's: the ordering of its largest mesh */
        st = ls_param_bytes_bound(n, n + lim->edges, lim->factor_nnz, &pc, 1, &z.param);
        /* the measurement runs the analysis only: no factor */
        if (st == LS_OK && uses_factor(c))
            st = ls_ldlt_bytes_bound(n, n + lim->edges, n + lim->edges, 0, pc.order, &analyze, &object, &factor);
    }
    if (st == LS_OK) st = ls_fit_impl_total(&z, &block);
    if (st == LS_OK) st = ls_mesh_edges_bytes(f, lim->edges, &eb);
    if (st != LS_OK) return st;
    ls_size_init(&measure);
    ls_size_add(&measure, 3u * (size_t)n, sizeof(ls_real));
    ls_size_add(&measure, eb, 1);
    ls_size_add(&measure, z.lap, 1);
    ls_size_add(&measure, analyze, 1);
    ls_size_init(&fit);
    ls_size_add(&fit, block, 1);
    ls_size_max(&fit, &measure);
    /* the remesher's bound reads the counts and the Euler characteristic only */
    memset(&shape, 0, sizeof shape);
    shape.vertex_count = n;
    shape.face_count = f;
    memset(&rep, 0, sizeof rep);
    rep.euler = euler;
    ls_remesh_params_default(&rp, (ls_real)1);
    rp.vertex_cap = n;
    st = ls_remesh_bytes_bound(&shape, &rep, &rp, &rb);
    if (st == LS_OK) st = ls_mesh_bytes(n, f, &ob);
    if (st == LS_OK) st = ls_size_get(&fit, region);
    if (st != LS_OK) return st;
    ls_size_init(&rm);
    ls_size_add(&rm, rb, 1);
    ls_size_init(&after);
    ls_size_add(&after, ob, 1);
    if (c->guard) { /* the result's self-intersection check (the larger mesh's) or the measurement */
        ls_size check;
        size_t tb = 0;
        st = ls_tangle_parallel_bytes(f, fit_workers(c), &tb);
        if (st != LS_OK) return st;
        ls_size_init(&check);
        ls_size_add(&check, tb, 1);
        ls_size_max(&check, &measure);
        ls_size_add_size(&after, &check);
    } else {
        ls_size_add_size(&after, &measure);
    }
    ls_size_max(&rm, &after);
    ls_size_init(&work);
    ls_size_add(&work, 3u * (size_t)n, sizeof(ls_real));
    ls_size_add_size(&work, &rm);
    ls_size_add_size(&fit, &work);
    return ls_size_get(&fit, bytes);
}

/* A job's limits and sizes: the capacity checked, the initial mesh's
 * counts against it, its edges and Euler characteristic from a validation
 * in scratch (released). */
static ls_status job_plan(const ls_fit_config *c, const ls_fit_views *views, const ls_mesh *initial,
                          const ls_fit_capacity *cap, ls_arena *scratch, fit_counts *lim, size_t *region,
                          size_t *bytes, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_mesh_report rep;
    fit_counts have;
    int64_t e;
    ls_status st;
    memset(lim, 0, sizeof *lim);
    if (cap == NULL || cap->max_vertices == 0 || cap->max_faces == 0 || (uses_factor(c) && cap->max_factor_nnz == 0)) {
        (void)ls_diag_set(diag, LS_ERR_INVALID,
                          "capacity: max_vertices and max_faces must be > 0, and max_factor_nnz with the LDL^T",
                          LS_DIAG_NO_INDEX);
        return LS_ERR_INVALID;
    }
    lim->vertices = cap->max_vertices;
    lim->faces = cap->max_faces;
    lim->edges = lim->factor_nnz = UINT32_MAX;
    have.vertices = initial->vertex_count;
    have.faces = initial->face_count;
    have.edges = have.factor_nnz = 0;
    st = ls_fit_impl_within(&have, lim, 0, diag);
    if (st != LS_OK) return st;
    mark = ls_arena_save(scratch);
    st = ls_mesh_validate(initial, scratch, &rep);
    ls_arena_restore(scratch, mark);
    if (st != LS_OK) {
        (void)ls_diag_set(diag, st, st == LS_ERR_NOMEM ? "arena too small to validate the initial mesh"
                                                       : "initial mesh: cannot be validated", LS_DIAG_NO_INDEX);
        return st;
    }
    /* every mesh of the job has the initial one's Euler characteristic
     * (the remesher keeps genus, components and boundary loops), so E =
     * V + F - chi */
    e = (int64_t)cap->max_vertices + (int64_t)cap->max_faces - rep.euler;
    lim->edges = e < 0 ? 0u : e > (int64_t)UINT32_MAX ? UINT32_MAX : (uint32_t)e;
    lim->factor_nnz = cap->max_factor_nnz;
    have.edges = rep.edge_count;
    st = ls_fit_impl_within(&have, lim, 0, diag);
    if (st == LS_OK) st = job_sizes(c, views->count, lim, rep.euler, region, bytes);
    return st;
}

static ls_status fit_job_bytes_call(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial, const ls_fit_capacity *capacity, ls_arena *scratch, size_t *bytes, ls_diag *diag)
{
    fit_counts lim, have;
    ls_real scale, radius;
    size_t region = 0, job = 0, fit_bytes = 0;
    ls_status st;
    if (bytes == NULL || scratch == NULL) return ls_invalid_arg(diag, "bytes or scratch is NULL");
    *bytes = 0;
    st = ls_fit_impl_init_args_ok(config, views, initial, diag);
    if (st == LS_OK) st = job_plan(config, views, initial, capacity, scratch, &lim, &region, &job, diag);
    if (st != LS_OK) return st;
    /* the initial mesh's fill, from the analysis that init will run */
    ls_fit_impl_measure_frame(initial, &scale, &radius);
    st = ls_fit_impl_fit_bytes_frame(config, views, initial, scale, scratch, &fit_bytes, &have, diag);
    if (st == LS_OK) st = ls_fit_impl_within(&have, &lim, 0, diag);
    if (st == LS_OK) *bytes = job;
    return st;
}

static ls_status fit_init_job_call(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial, const ls_fit_capacity *capacity, ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_arena region;
    fit_counts lim;
    ls_real scale, radius;
    size_t region_bytes = 0, bytes = 0;
    void *mem;
    ls_status st;
    if (fit == NULL || arena == NULL) return ls_invalid_arg(diag, "fit or arena is NULL");
    memset(fit, 0, sizeof *fit);
    st = ls_fit_impl_init_args_ok(config, views, initial, diag);
    if (st == LS_OK) st = job_plan(config, views, initial, capacity, arena, &lim, &region_bytes, &bytes, diag);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    mem = ls_arena_alloc(arena, bytes, 1);
    if (mem == NULL) {
        (void)ls_diag_set(diag, LS_ERR_NOMEM, "arena too small for the job (ls_fit_job_bytes; arena->need)",
                          LS_DIAG_NO_INDEX);
        return LS_ERR_NOMEM;
    }
    /* the fit at the start of the reservation, the remesh work above it */
    ls_fit_impl_measure_frame(initial, &scale, &radius);
    st = ls_arena_init(&region, mem, region_bytes);
    if (st == LS_OK) st = ls_fit_impl_fit_init_frame(fit, config, views, initial, scale, radius, &lim, &region, diag);
    if (st == LS_OK) st = ls_arena_init(&fit->job, mem, bytes);
    if (st == LS_OK && ls_arena_alloc(&fit->job, region_bytes, 1) == NULL) st = LS_ERR_NOMEM; /* not reached */
    if (st != LS_OK) {
        memset(fit, 0, sizeof *fit);
        ls_arena_restore(arena, mark);
        return st;
    }
    fit->capacity = *capacity;
    fit->max_edges = lim.edges;
    fit->job_fit_bytes = region_bytes;
    return LS_OK;
}

ls_status ls_fit_job_bytes(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                           const ls_fit_capacity *capacity, ls_arena *scratch, size_t *bytes, ls_diag *diag)
{
    ls_status st = fit_job_bytes_call(config, views, initial, capacity, scratch, bytes, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

ls_status ls_fit_init_job(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                          const ls_fit_capacity *capacity, ls_arena *arena, ls_diag *diag)
{
    ls_status st = fit_init_job_call(fit, config, views, initial, capacity, arena, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}
