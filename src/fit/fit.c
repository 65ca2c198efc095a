/* fit.c - the reconstruction loop: configuration, sizing, set-up and the
 * iteration (include/largesteps/fit.h) */
#include "fit_internal.h"
#include <stddef.h>

/* The fit's frame (fit.h): R = half the largest side of the mesh's bounding
 * box, S = the largest power of two <= R (1 when R = 0). Both scale exactly
 * with the mesh by any power of two: the bounds, the halving and the
 * doubling/halving loop are exact. */
void ls_fit_impl_measure_frame(const ls_mesh *m, ls_real *scale, ls_real *radius)
{
    ls_real lo[3], hi[3], r = (ls_real)0, s = (ls_real)1;
    if (ls_mesh_bounds(m, lo, hi) == LS_OK) {
        uint32_t k;
        for (k = 0; k < 3; k++) {
            ls_real h = (ls_real)0.5 * hi[k] - (ls_real)0.5 * lo[k];
            if (h > r) r = h;
        }
    }
    if (!(r > (ls_real)0) || !finite_r(r)) {
        *scale = *radius = (ls_real)1;
        return;
    }
    while (s > r) s *= (ls_real)0.5;
    while ((ls_real)2 * s <= r) s *= (ls_real)2;
    *scale = s;
    *radius = r;
}

/* out[16 count] (optional) = the views' transforms in the frame of unit
 * `scale`: the translation column divided by it, so that M (S x, 1) =
 * S (M' (x, 1)) and the normalized device coordinates are the same bits. */
static ls_status frame_views(const ls_fit_views *v, ls_real scale, ls_real *out, ls_diag *diag)
{
    uint32_t i, j;
    for (i = 0; i < v->count; i++)
        for (j = 0; j < 16u; j++) {
            ls_real a = v->mvp[16u * (size_t)i + j];
            if ((j & 3u) == 3u) a /= scale;
            if (!finite_r(a)) {
                diag_set(diag, LS_ERR_NONFINITE, "view transform: not finite in the fit's frame", i);
                return LS_ERR_NONFINITE;
            }
            if (out != NULL) out[16u * (size_t)i + j] = a;
        }
    return LS_OK;
}

/* out[3 n] = positions / scale; LS_ERR_NONFINITE when one is not finite. */
static ls_status frame_positions(const ls_mesh *m, ls_real scale, ls_real *out, ls_diag *diag)
{
    size_t i;
    for (i = 0; i < 3u * (size_t)m->vertex_count; i++) {
        out[i] = m->positions[i] / scale;
        if (!finite_r(out[i])) {
            diag_set(diag, LS_ERR_NONFINITE, "initial mesh: a coordinate not finite in the fit's frame", i / 3u);
            return LS_ERR_NONFINITE;
        }
    }
    return LS_OK;
}

void ls_fit_config_default(ls_fit_config *c)
{
    if (c == NULL) return;
    memset(c, 0, sizeof *c);
    c->method = LS_FIT_LARGE_STEPS;
    c->form = LS_SYSTEM_LAMBDA;
    c->weight = (ls_real)19;
    c->solver = LS_PARAM_LDLT;
    (void)ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &c->optim);
    c->optim.lr = (ls_real)1e-2;
    c->use_translation = 1;
    c->loss = LS_LOSS_L1;
    c->boost = (ls_real)3;
    c->width = 128;
    c->height = 128;
    c->ss = 1;
    ls_shade_opts_init(&c->shading);
}

/* NULL when the arguments are in range, else the argument or field that is
 * not, with its allowed range. */
static const char *config_error(const ls_fit_config *c, const ls_fit_views *v, const ls_mesh *m)
{
    uint32_t i;
    if (c == NULL || v == NULL || m == NULL) return "config, views or initial is NULL";
    if (m->positions == NULL || m->triangles == NULL) return "initial: positions or triangles is NULL";
    if (c->method > LS_FIT_BILAPLACIAN)
        return "config->method: allowed LS_FIT_LARGE_STEPS, LS_FIT_NAIVE, LS_FIT_LAPLACIAN or LS_FIT_BILAPLACIAN";
    if (c->loss > LS_LOSS_L2) return "config->loss: allowed LS_LOSS_L1 or LS_LOSS_L2";
    if (c->width == 0 || c->height == 0) return "config->width, height: the render size, allowed >= 1 (e.g. 128)";
    if (v->count == 0) return "views->count: allowed >= 1";
    if (v->mvp == NULL || v->targets == NULL) return "views->mvp or views->targets is NULL";
    for (i = 0; i < v->count; i++)
        if (v->targets[i] == NULL) return "views->targets[i]: a target image is NULL";
    if (c->form != LS_SYSTEM_LAMBDA && c->form != LS_SYSTEM_ALPHA)
        return "config->form: allowed LS_SYSTEM_LAMBDA or LS_SYSTEM_ALPHA";
    if (!finite_r(c->weight) || c->weight < (ls_real)0)
        return "config->weight: lambda finite and >= 0, or alpha in [0, 1) (the paper: lambda 19)";
    if (c->form == LS_SYSTEM_ALPHA && !(c->weight < (ls_real)1)) return "config->weight: alpha allowed in [0, 1)";
    if (c->solver != LS_PARAM_LDLT && c->solver != LS_PARAM_CG && c->solver != LS_PARAM_AUTO)
        return "config->solver: allowed LS_PARAM_LDLT, LS_PARAM_CG or LS_PARAM_AUTO";
    if (!finite_r(c->boost)) return "config->boost: the silhouette gradient's multiplier, allowed finite (the paper: 3)";
    if (!finite_r(c->reg_weight) || c->reg_weight < (ls_real)0) return "config->reg_weight: allowed finite and >= 0";
    if (c->shading.vertex_colors != NULL) return "config->shading.vertex_colors: must be NULL in a fit";
    if (c->shading.mode > LS_SHADE_LAMBERT)
        return "config->shading.mode: allowed LS_SHADE_MASK, LS_SHADE_SH or LS_SHADE_LAMBERT";
    if (c->silhouette > LS_FIT_SILHOUETTE_NONE)
        return "config->silhouette: allowed LS_FIT_SILHOUETTE_EXACT, LS_FIT_SILHOUETTE_PAIR or LS_FIT_SILHOUETTE_NONE";
    if (c->silhouette == LS_FIT_SILHOUETTE_PAIR && c->ss != 1)
        return "config->ss: the pair silhouette mode needs ss = 1";
    if (c->power > 2u) return "config->power: allowed 0 (= 2), 1 or 2";
    if (!finite_r(c->cg_tol) || c->cg_tol < (ls_real)0) return "config->cg_tol: allowed finite and >= 0 (0 means 1e-6)";
    if (c->aa > LS_REFINE_MAX) return "config->aa: allowed 0 .. LS_REFINE_MAX";
    if (c->silhouette == LS_FIT_SILHOUETTE_PAIR && c->aa > c->ss)
        return "config->aa: the pair silhouette mode allows aa <= ss only";
    if (c->guard > 1u) return "config->guard: allowed 0 or 1";
    if (c->mean_mode > LS_FIT_MEAN_PROJECT) return "config->mean_mode: allowed LS_FIT_MEAN_KEEP or LS_FIT_MEAN_PROJECT";
    if (!finite_r(c->mask_pull) || c->mask_pull < (ls_real)0)
        return "config->mask_pull: allowed finite and >= 0 (0: off)";
    if (c->mean_mode == LS_FIT_MEAN_PROJECT && !c->use_translation)
        return "config->mean_mode: LS_FIT_MEAN_PROJECT needs use_translation = 1";
    if (c->view_batch > v->count) return "config->view_batch: allowed 0 (all views) .. views->count";
    if (!finite_r(c->grad_limit) || c->grad_limit < (ls_real)0)
        return "config->grad_limit: allowed finite and >= 0 (0: off; e.g. 3)";
    if (c->light > LS_FIT_LIGHT_ESTIMATE) return "config->light: allowed LS_FIT_LIGHT_GIVEN or LS_FIT_LIGHT_ESTIMATE";
    if (c->light == LS_FIT_LIGHT_ESTIMATE && c->shading.mode != LS_SHADE_SH)
        return "config->light: LS_FIT_LIGHT_ESTIMATE estimates SH lighting: it needs shading.mode LS_SHADE_SH";
    if (c->albedo > LS_FIT_ALBEDO_VERTEX) return "config->albedo: allowed LS_FIT_ALBEDO_UNIFORM or LS_FIT_ALBEDO_VERTEX";
    if (c->albedo == LS_FIT_ALBEDO_VERTEX && c->light != LS_FIT_LIGHT_ESTIMATE)
        return "config->albedo: LS_FIT_ALBEDO_VERTEX is estimated with the lighting: it needs light = "
               "LS_FIT_LIGHT_ESTIMATE";
    if (c->workers > LS_FIT_MAX_WORKERS) return "config->workers: allowed 0 .. LS_FIT_MAX_WORKERS (0 and 1: one)";
    if (m->vertex_count == 0 || m->face_count == 0) return "initial: the mesh has no vertex or no face";
    if (m->vertex_count > (UINT32_MAX - 3u) / 3u) return "initial: more than (2^32 - 4) / 3 vertices";
    return NULL;
}

static ls_status check_config(const ls_fit_config *c, const ls_fit_views *v, const ls_mesh *m, ls_diag *diag)
{
    const char *bad = config_error(c, v, m);
    if (bad != NULL) {
        (void)ls_diag_set(diag, LS_ERR_INVALID, bad, LS_DIAG_NO_INDEX);
        return LS_ERR_INVALID;
    }
    return ls_optim_config_check(&c->optim, diag);
}

void ls_fit_impl_param_config(const ls_fit_config *c, uint32_t n, ls_param_config *pc)
{
    memset(pc, 0, sizeof *pc);
    pc->solver = c->solver;
    pc->form = c->form;
    pc->weight = c->weight;
    pc->k = 3;
    /* AMD's fill grows faster than n log n on large regular meshes (nnz(L)
     * 5.0x from 41k to 164k sphere vertices, nested dissection's 4.7x): from
     * LS_FIT_AUTO_ORDER_VERTICES on, the smaller of the two */
    pc->order = n >= LS_FIT_AUTO_ORDER_VERTICES ? LS_ORDER_AUTO : LS_ORDER_AMD;
    pc->cg_max_iter = 1000;
    pc->cg_tol = c->cg_tol > (ls_real)0 ? c->cg_tol : (ls_real)1e-6;
    /* the solves split over the workers too (the same bits: ls_ldlt_split) */
    pc->workers = fit_workers(c) > 1u ? fit_workers(c) : 0u;
    pc->parallel = &c->parallel;
}

/* p = 1: the optimizer moves x itself, its gradient preconditioned once. */
int ls_fit_impl_optimizes_u(const ls_fit_config *c)
{
    return c->method == LS_FIT_LARGE_STEPS && c->power != 1u;
}

/* The silhouette pass bins every triangle into the 2 x 2 pixel tiles its
 * screen box meets; for a framed mesh the (triangle, tile) pairs stay far
 * below the worst case (every triangle in every tile). The fit reserves
 * LS_FIT_BIN_PER_TRIANGLE pairs per triangle plus LS_FIT_BIN_PER_TILE per
 * tile; a view that needs more fails its step with LS_ERR_NOMEM. */
#define LS_FIT_BIN_PER_TRIANGLE 8u
#define LS_FIT_BIN_PER_TILE 16u

/* The scratch of one view's pass: the raster, the silhouettes' bins or the
 * adaptive refinement, whichever is largest (each released before the next). */
static ls_status view_scratch_bytes(const ls_fit_config *c, uint32_t n, uint32_t f, size_t *bytes)
{
    size_t a = 0, b = 0;
    ls_status st = ls_raster_scratch_bytes_bound(c->width, c->height, c->ss, n, f, &a);
    if (st == LS_OK)
        st = ls_silhouette_scratch_bytes_bins(c->width, c->height, n, f, LS_FIT_BIN_PER_TRIANGLE, LS_FIT_BIN_PER_TILE, &b);
    if (st == LS_OK && b > a) a = b;
    if (st == LS_OK) st = ls_refine_scratch_bytes_bound(c->width, c->height, c->ss, f, c->aa, &b); /* 0 when off */
    if (st == LS_OK && b > a) a = b;
    *bytes = a;
    return st;
}

static ls_status array_sizes(const ls_fit_config *c, uint32_t views, uint32_t n, uint32_t f, size_t *bytes)
{
    ls_size s;
    size_t px = (size_t)c->width * c->height * 4u;
    ls_size_init(&s);
    ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));  /* x */
    ls_size_add(&s, 3u * (size_t)f, sizeof(uint32_t)); /* triangles */
    ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));  /* u */
    ls_size_add(&s, 3u * (size_t)n + 3u, sizeof(ls_real)); /* params */
    ls_size_add(&s, 3u * (size_t)n + 3u, sizeof(ls_real)); /* grad */
    ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));  /* gx */
    ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));  /* xr */
    ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));  /* normals */
    ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));  /* gnormals */
    ls_size_add(&s, px, sizeof(ls_real));              /* image */
    ls_size_add(&s, px, sizeof(ls_real));              /* gimage */
    if (fit_pair_mode(c)) {
        ls_size_add(&s, px, sizeof(ls_real)); /* pair_image */
        ls_size_add(&s, px, sizeof(ls_real)); /* pair_gimage */
    }
    ls_size_add(&s, 16u * (size_t)views, sizeof(ls_real)); /* mvp */
    {
        size_t mr, mi;
        ls_fit_impl_mask_sizes(c, views, &mr, &mi);
        if (mr > 0) {
            ls_size_add(&s, mr, sizeof(ls_real));   /* mask_dist */
            ls_size_add(&s, mi, sizeof(uint32_t)); /* mask_index */
        }
    }
    if (c->guard) ls_size_add(&s, 3u * (3u * (size_t)n + 3u) + 3u * (size_t)n, sizeof(ls_real)); /* saved */
    if (c->albedo == LS_FIT_ALBEDO_VERTEX) {
        ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real)); /* albedo */
        ls_size_add(&s, 6u * (size_t)n, sizeof(ls_real)); /* albedo_sums */
    }
    ls_size_add(&s, 1, sizeof(struct ls_fit_pass));                /* pass */
    ls_size_add(&s, fit_workers(c), sizeof(struct ls_fit_worker)); /* workers */
    ls_size_add(&s, fit_slots(c, views), sizeof(struct ls_fit_slot));  /* slots */
    if (fit_workers(c) > 1u) { /* the normals' incidence and terms (fit_normals.c) */
        ls_size_add(&s, (size_t)n + 1u, sizeof(uint32_t));
        ls_size_add(&s, 3u * (size_t)f, sizeof(uint32_t));
        ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));
        ls_size_add(&s, 9u * (size_t)f, sizeof(ls_real));
        ls_size_add(&s, f, 1);
    }
    {
        uint32_t k;
        size_t scratch = 0;
        ls_status st = view_scratch_bytes(c, n, f, &scratch);
        if (st != LS_OK) return st;
        for (k = 0; k < fit_slots(c, views); k++) {
            ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real)); /* gx */
            ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real)); /* gn */
            if (c->albedo == LS_FIT_ALBEDO_VERTEX) ls_size_add(&s, 6u * (size_t)n, sizeof(ls_real));
        }
        for (k = 1; k < fit_workers(c); k++) { /* worker 0 has the fit's */
            ls_size_add(&s, px, sizeof(ls_real)); /* image */
            ls_size_add(&s, px, sizeof(ls_real)); /* gimage */
            if (fit_pair_mode(c)) {
                ls_size_add(&s, px, sizeof(ls_real));
                ls_size_add(&s, px, sizeof(ls_real));
            }
            ls_size_add(&s, scratch, 1); /* its scratch */
        }
    }
    return ls_size_get(&s, bytes);
}

/* The scratch of one iteration: the step's own arrays (the solved positions,
 * a copy of the CG warm starts) for the whole step, then the larger of the
 * views' pass (raster, silhouettes, normals backward, the regularizer) and
 * the optimizer's snapshot (parameters and both moments), which follow one
 * another. */
ls_status ls_fit_impl_iteration_scratch(const ls_fit_config *c, uint32_t n, uint32_t f, const ls_csc *lap, size_t *bytes)
{
    size_t a = 0, b = 0, e = 0;
    ls_size s, pass, snap;
    ls_status st = view_scratch_bytes(c, n, f, &a);
    if (st == LS_OK) st = ls_vertex_normals_backward_bytes(n, &b);
    if (st == LS_OK && c->method == LS_FIT_LAPLACIAN) st = ls_laplacian_energy_bytes(lap, 3, 0, 1, &e);
    if (st == LS_OK && c->method == LS_FIT_BILAPLACIAN) st = ls_laplacian_energy_bytes(lap, 3, 1, 1, &e);
    if (st != LS_OK) return st;
    if (b > a) a = b;
    if (e > a) a = e;
    ls_size_init(&s);
    if (c->method == LS_FIT_LARGE_STEPS) {
        ls_size_add(&s, 3u * (size_t)n, sizeof(ls_real));                                /* solved x */
        if (c->solver == LS_PARAM_CG) ls_size_add(&s, 6u * (size_t)n, sizeof(ls_real)); /* warm starts */
    }
    ls_size_init(&pass);
    ls_size_add(&pass, a, 1);
    ls_size_init(&snap);
    ls_size_add(&snap, 3u * (size_t)n + 3u, sizeof(ls_real)); /* params */
    ls_size_add(&snap, 3u * (size_t)n + 3u, sizeof(ls_real)); /* m1 */
    ls_size_add(&snap, 3u * (size_t)n + 3u, sizeof(ls_real)); /* m2 */
    ls_size_max(&pass, &snap);
    ls_size_add_size(&s, &pass);
    if (c->guard) { /* ls_fit_tangle: the positions, then the solve's warm start (CG) or the check */
        ls_size check, warm;
        ls_status st2 = ls_tangle_parallel_bytes(f, fit_workers(c), &e);
        if (st2 != LS_OK) return st2;
        ls_size_init(&check);
        ls_size_add(&check, 3u * (size_t)n, sizeof(ls_real));
        ls_size_init(&warm);
        ls_size_add(&warm, e, 1);
        if (c->solver == LS_PARAM_CG) {
            ls_size cgw;
            ls_size_init(&cgw);
            ls_size_add(&cgw, 3u * (size_t)n, sizeof(ls_real));
            ls_size_max(&warm, &cgw);
        }
        ls_size_add_size(&check, &warm);
        ls_size_max(&s, &check);
    }
    return ls_size_get(&s, bytes);
}

ls_status ls_fit_impl_total(const fit_sizes *z, size_t *bytes)
{
    ls_size s;
    ls_size_init(&s);
    ls_size_add(&s, z->arrays, 1);
    ls_size_add(&s, z->lap, 1);
    ls_size_add(&s, z->param, 1);
    ls_size_add(&s, z->optim, 1);
    ls_size_add(&s, z->edges, 1);
    ls_size_add(&s, z->vis, 1);
    ls_size_add(&s, z->iteration, 1);
    return ls_size_get(&s, bytes);
}

/* Sizes of everything but the solver, for a mesh with `edges` unique edges. */
ls_status ls_fit_impl_base_sizes(const ls_fit_config *c, uint32_t views, uint32_t n, uint32_t f, uint32_t edges, fit_sizes *z)
{
    ls_status st;
    memset(z, 0, sizeof *z);
    st = array_sizes(c, views, n, f, &z->arrays);
    if (st == LS_OK) st = ls_laplacian_bytes(n, f, edges, LS_LAP_UPPER, &z->lap);
    if (st == LS_OK) st = ls_optim_bytes(3u * n + 3u, &z->optim);
    if (st == LS_OK) st = ls_edge_table_bytes(f, &z->edges);
    if (st == LS_OK) st = ls_vis_bytes(c->width, c->height, c->ss, n, &z->vis);
    if (st == LS_OK) { /* one visibility buffer per worker */
        ls_size v;
        uint32_t k;
        ls_size_init(&v);
        for (k = 0; k < fit_workers(c); k++) ls_size_add(&v, z->vis, 1);
        st = ls_size_get(&v, &z->vis);
    }
    return st;
}

/* ls_fit_bytes in the frame of unit `scale`: the ordering of the factor
 * sees the normalized coordinates, as ls_fit_init gives them. *counts
 * (optional) receives the mesh's counts and its factor's fill. */
ls_status ls_fit_impl_fit_bytes_frame(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                                 ls_real scale, ls_arena *scratch, size_t *bytes, fit_counts *counts, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_mesh_edges e;
    ls_param_config pc;
    ls_csc lap;
    fit_sizes z;
    ls_real *xyz;
    size_t peak, used, block;
    uint32_t l_nnz = 0;
    ls_status st;
    mark = ls_arena_save(scratch);
    peak = scratch->peak;
    used = ls_arena_used(scratch);
    ls_arena_reset_peak(scratch);
    st = frame_views(views, scale, NULL, diag);
    xyz = st == LS_OK ? (ls_real *)ls_arena_scratch(scratch, 3u * (size_t)initial->vertex_count, sizeof(ls_real)) : NULL;
    if (st == LS_OK && xyz == NULL) st = LS_ERR_NOMEM;
    if (st == LS_OK) st = frame_positions(initial, scale, xyz, diag);
    if (st == LS_OK) st = ls_mesh_edges_build(initial, scratch, &e, diag);
    if (st == LS_OK) st = ls_fit_impl_base_sizes(config, views->count, initial->vertex_count, initial->face_count, e.count, &z);
    if (st == LS_OK) st = ls_laplacian_uniform(initial, LS_LAP_UPPER, scratch, &lap, diag);
    if (st == LS_OK) st = ls_fit_impl_iteration_scratch(config, initial->vertex_count, initial->face_count, &lap, &z.iteration);
    if (st == LS_OK && config->method == LS_FIT_LARGE_STEPS) {
        ls_fit_impl_param_config(config, initial->vertex_count, &pc);
        st = ls_param_bytes_fill(&lap, &pc, xyz, scratch, &z.param, &l_nnz);
    }
    /* ls_fit_init runs this same measurement in its arena before taking the
     * block: the answer covers both */
    used = scratch->peak - used;
    ls_arena_restore(scratch, mark);
    if (peak > scratch->peak) scratch->peak = peak;
    if (st != LS_OK) return st;
    st = ls_fit_impl_total(&z, &block);
    if (st != LS_OK) return st;
    *bytes = block > used ? block : used;
    if (counts != NULL) {
        counts->vertices = initial->vertex_count;
        counts->faces = initial->face_count;
        counts->edges = e.count;
        counts->factor_nnz = l_nnz;
    }
    return LS_OK;
}

static ls_status fit_bytes_call(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial, ls_arena *scratch, size_t *bytes, ls_diag *diag)
{
    ls_real scale, radius;
    ls_status st;
    if (bytes == NULL || scratch == NULL) return ls_invalid_arg(diag, "bytes or scratch is NULL");
    st = check_config(config, views, initial, diag);
    if (st != LS_OK) return st;
    ls_fit_impl_measure_frame(initial, &scale, &radius);
    return ls_fit_impl_fit_bytes_frame(config, views, initial, scale, scratch, bytes, NULL, diag);
}

/* The workers' and the slots' arrays (array_sizes' order). */
static int take_parallel(ls_fit *fit, uint32_t n, uint32_t f)
{
    const ls_fit_config *c = &fit->config;
    ls_arena *a = &fit->block;
    const size_t px = (size_t)c->width * c->height * 4u;
    const uint32_t slots = fit_slots(c, fit->views.count);
    size_t scratch = 0;
    uint32_t k;
    fit->pass = (struct ls_fit_pass *)ls_arena_alloc(a, 1, sizeof(struct ls_fit_pass));
    fit->workers = (struct ls_fit_worker *)ls_arena_alloc(a, fit_workers(c), sizeof(struct ls_fit_worker));
    fit->slots = (struct ls_fit_slot *)ls_arena_alloc(a, slots, sizeof(struct ls_fit_slot));
    if (fit->pass == NULL || fit->workers == NULL || fit->slots == NULL || view_scratch_bytes(c, n, f, &scratch) != LS_OK) return 0;
    memset(fit->pass, 0, sizeof *fit->pass);
    if (fit_workers(c) > 1u) {
        struct ls_fit_pass *p = fit->pass;
        p->vf_start = (uint32_t *)ls_arena_alloc(a, (size_t)n + 1u, sizeof(uint32_t));
        p->vf_corner = (uint32_t *)ls_arena_alloc(a, 3u * (size_t)f, sizeof(uint32_t));
        p->nsum = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
        p->face_buf = (ls_real *)ls_arena_alloc(a, 9u * (size_t)f, sizeof(ls_real));
        p->face_ok = (unsigned char *)ls_arena_alloc(a, f, 1);
        if (p->face_ok == NULL) return 0;
    }
    memset(fit->workers, 0, fit_workers(c) * sizeof(struct ls_fit_worker));
    memset(fit->slots, 0, slots * sizeof(struct ls_fit_slot));
    fit->slot_count = slots;
    for (k = 0; k < slots; k++) {
        struct ls_fit_slot *sl = fit->slots + k;
        sl->gx = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
        sl->gn = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
        if (c->albedo == LS_FIT_ALBEDO_VERTEX) sl->albedo_sums = (ls_real *)ls_arena_alloc(a, 6u * (size_t)n, sizeof(ls_real));
        if (sl->gn == NULL || (c->albedo == LS_FIT_ALBEDO_VERTEX && sl->albedo_sums == NULL)) return 0;
    }
    for (k = 1; k < fit_workers(c); k++) {
        struct ls_fit_worker *w = fit->workers + k;
        void *mem;
        w->image = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        w->gimage = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        if (fit_pair_mode(c)) {
            w->pair_image = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
            w->pair_gimage = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        }
        mem = ls_arena_alloc(a, scratch, 1);
        if (w->gimage == NULL || (fit_pair_mode(c) && w->pair_gimage == NULL) || (scratch > 0 && mem == NULL) ||
            ls_arena_init(&w->scratch, mem, scratch) != LS_OK)
            return 0;
    }
    return 1;
}

/* Allocations from the block, in the layout's order. */
static int take_arrays(ls_fit *fit, uint32_t n, uint32_t f)
{
    ls_arena *a = &fit->block;
    size_t px = (size_t)fit->config.width * fit->config.height * 4u;
    fit->x = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
    fit->triangles = (uint32_t *)ls_arena_alloc(a, 3u * (size_t)f, sizeof(uint32_t));
    fit->u = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
    fit->params = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n + 3u, sizeof(ls_real));
    fit->grad = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n + 3u, sizeof(ls_real));
    fit->gx = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
    fit->xr = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
    fit->normals = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
    fit->gnormals = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
    fit->image = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
    fit->gimage = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
    if (fit_pair_mode(&fit->config)) {
        fit->pair_image = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        fit->pair_gimage = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        if (fit->pair_gimage == NULL) return 0;
    }
    fit->mvp = (ls_real *)ls_arena_alloc(a, 16u * (size_t)fit->views.count, sizeof(ls_real));
    fit->mask_dist = NULL;
    fit->mask_index = NULL;
    {
        size_t mr, mi;
        ls_fit_impl_mask_sizes(&fit->config, fit->views.count, &mr, &mi);
        if (mr > 0) {
            fit->mask_dist = (ls_real *)ls_arena_alloc(a, mr, sizeof(ls_real));
            fit->mask_index = (uint32_t *)ls_arena_alloc(a, mi, sizeof(uint32_t));
            if (fit->mask_index == NULL) return 0;
        }
    }
    if (fit->config.guard) {
        fit->saved = (ls_real *)ls_arena_alloc(a, 3u * (3u * (size_t)n + 3u) + 3u * (size_t)n, sizeof(ls_real));
        if (fit->saved == NULL) return 0;
    }
    if (fit->config.albedo == LS_FIT_ALBEDO_VERTEX) {
        size_t i;
        fit->albedo = (ls_real *)ls_arena_alloc(a, 3u * (size_t)n, sizeof(ls_real));
        fit->albedo_sums = (ls_real *)ls_arena_alloc(a, 6u * (size_t)n, sizeof(ls_real));
        if (fit->albedo_sums == NULL) return 0;
        for (i = 0; i < 3u * (size_t)n; i++) fit->albedo[i] = (ls_real)1;
    }
    return fit->mvp != NULL && take_parallel(fit, n, f);
}

/* ls_fit_init in a given frame (ls_fit_remesh keeps the first fit's); lim
 * (optional): a job's capacity, checked before anything is taken. */
ls_status ls_fit_impl_fit_init_frame(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views,
                                const ls_mesh *initial, ls_real scale, ls_real radius, const fit_counts *lim,
                                ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_param_config pc;
    ls_optim_config oc;
    size_t bytes, reserve;
    fit_counts have;
    void *mem;
    uint32_t n, nf;
    ls_status st;
    mark = ls_arena_save(arena);
    /* the block: measured with the arena's free top as scratch */
    st = ls_fit_impl_fit_bytes_frame(config, views, initial, scale, arena, &bytes, &have, diag);
    if (st == LS_OK && lim != NULL) st = ls_fit_impl_within(&have, lim, 0, diag);
    if (st != LS_OK) return st;
    mem = ls_arena_alloc(arena, bytes, 1);
    if (mem == NULL) return LS_ERR_NOMEM;
    fit->config = *config;
    fit->views = *views;
    fit->saved = NULL;
    fit->saved_valid = 0;
    fit->scale = scale;
    fit->radius = radius;
    n = initial->vertex_count;
    nf = initial->face_count;
    fit->vertex_count = n;
    fit->face_count = nf;
    st = ls_arena_init(&fit->block, mem, bytes);
    if (st == LS_OK && !take_arrays(fit, n, nf)) st = LS_ERR_NOMEM;
    if (st == LS_OK) st = frame_positions(initial, scale, fit->x, diag);
    if (st == LS_OK) st = frame_views(views, scale, fit->mvp, diag);
    if (st == LS_OK) ls_fit_impl_mask_init(fit);
    if (st == LS_OK) {
        memcpy(fit->triangles, initial->triangles, 3u * (size_t)nf * sizeof(uint32_t));
        ls_fit_impl_incidence(fit);
        st = ls_laplacian_uniform(initial, LS_LAP_UPPER, &fit->block, &fit->lap, diag);
    }
    if (st == LS_OK && config->method == LS_FIT_LARGE_STEPS) {
        ls_fit_impl_param_config(config, n, &pc);
        st = ls_param_init(&fit->param, &fit->lap, &pc, fit->x, &fit->block, diag);
        if (st == LS_OK) st = ls_param_to_differential(&fit->param, fit->x, fit->u);
    }
    if (st == LS_OK) {
        uint32_t blocks[2];
        blocks[0] = 3u * n;
        blocks[1] = 3u;
        /* the learning rate in units of R, inside a frame of unit S */
        oc = config->optim;
        oc.lr = oc.lr * (radius / scale);
        st = ls_optim_init(&fit->optim, &oc, 3u * n + 3u, config->use_translation ? 2u : 1u, blocks, &fit->block);
    }
    if (st == LS_OK) st = ls_edge_table_build(&fit->edges, fit->triangles, nf, n, &fit->block, diag);
    if (st == LS_OK) st = ls_vis_init(&fit->vis, &fit->block, config->width, config->height, config->ss, n);
    {
        uint32_t k;
        for (k = 1; st == LS_OK && k < fit_workers(config); k++)
            st = ls_vis_init(&fit->workers[k].vis, &fit->block, config->width, config->height, config->ss, n);
    }
    if (st == LS_OK) {
        /* what is left is the iteration's scratch: check it covers the reserve */
        st = ls_fit_impl_iteration_scratch(config, n, nf, &fit->lap, &reserve);
        if (st == LS_OK && ls_arena_available(&fit->block) < reserve) st = LS_ERR_NOMEM; /* not reached */
        fit->scratch_bytes = ls_arena_available(&fit->block);
    }
    if (st != LS_OK) {
        memset(fit, 0, sizeof *fit);
        ls_arena_restore(arena, mark);
        return st;
    }
    memcpy(fit->params, ls_fit_impl_optimizes_u(config) ? fit->u : fit->x, 3u * (size_t)n * sizeof(ls_real));
    fit->params[3u * (size_t)n] = fit->params[3u * (size_t)n + 1u] = fit->params[3u * (size_t)n + 2u] = (ls_real)0;
    return LS_OK;
}

/* The arguments of ls_fit_init and ls_fit_init_job. */
ls_status ls_fit_impl_init_args_ok(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                              ls_diag *diag)
{
    uint32_t i;
    ls_status st = check_config(config, views, initial, diag);
    if (st != LS_OK) return st;
    for (i = 0; i < 3u * initial->vertex_count; i++)
        if (!finite_r(initial->positions[i])) {
            diag_set(diag, LS_ERR_NONFINITE, "initial mesh: non-finite coordinate", i / 3u);
            return LS_ERR_NONFINITE;
        }
    return LS_OK;
}

static ls_status fit_init_call(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial, ls_arena *arena, ls_diag *diag)
{
    ls_real scale, radius;
    ls_status st;
    if (fit == NULL || arena == NULL) return ls_invalid_arg(diag, "fit or arena is NULL");
    memset(fit, 0, sizeof *fit);
    st = ls_fit_impl_init_args_ok(config, views, initial, diag);
    if (st != LS_OK) return st;
    ls_fit_impl_measure_frame(initial, &scale, &radius);
    return ls_fit_impl_fit_init_frame(fit, config, views, initial, scale, radius, NULL, arena, diag);
}

/* The first non-finite value of v[0..count), or count. */
static size_t first_nonfinite(const ls_real *v, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        if (!finite_r(v[i])) return i;
    return count;
}

static uint32_t gcd_u32(uint32_t a, uint32_t b)
{
    while (b != 0u) {
        uint32_t t = a % b;
        a = b;
        b = t;
    }
    return a;
}

/* The stride coprime to count (>= 2) nearest count (3 - sqrt 5) / 2, below
 * first: 0.381966011250105 with integers only. */
static uint32_t coprime_stride(uint32_t count)
{
    uint32_t s = (uint32_t)(((uint64_t)count * 381966011u + 500000000u) / 1000000000u), d;
    if (s == 0u) s = 1u;
    for (d = 0u; d < count; d++) {
        if (s > d && gcd_u32(s - d, count) == 1u) return s - d;
        if (s + d < count && gcd_u32(s + d, count) == 1u) return s + d;
    }
    return 1u; /* not reached: 1 is coprime to every count */
}

/* The batch's views (fit.h): the golden-ratio stride spreads consecutive
 * positions over the pool (a Fibonacci sphere's views are in height order). */
uint32_t ls_fit_view_of(const ls_fit_config *config, uint32_t count, uint32_t iteration, uint32_t k)
{
    const uint32_t batch = config != NULL ? config->view_batch : 0u;
    uint64_t pos;
    if (count == 0u) return 0u;
    if (batch == 0u || batch >= count) return k % count;
    pos = ((uint64_t)iteration * batch + k) % count;
    return (uint32_t)(pos * coprime_stride(count) % count);
}

/* The iteration up to the optimizer: positions xs (= M^-1 params for large
 * steps, the fit's x for the baselines), rendered at xs + translation, the
 * loss, dL/dx in fit->gx and the optimizer's gradient in fit->grad. Writes
 * only working arrays, the loss fields and the timing (the caller restores
 * those on failure). */
/* g [3 n] loses its per-axis mean (sums in vertex order). */
static void remove_mean(ls_real *g, uint32_t n)
{
    uint32_t i, k;
    for (k = 0; k < 3; k++) {
        ls_real s = (ls_real)0;
        for (i = 0; i < n; i++) s += g[3u * i + k];
        s /= (ls_real)n;
        for (i = 0; i < n; i++) g[3u * i + k] -= s;
    }
}

static ls_status step_gradient(ls_fit *fit, ls_real *xs, const ls_monitor *monitor, ls_diag *diag)
{
    const ls_fit_config *c = &fit->config;
    const uint32_t n = fit->vertex_count;
    uint32_t i, k;
    ls_real tr[3];
    uint64_t t0;
    ls_status st = LS_OK;
    t0 = fit_now(monitor);
    if (ls_fit_impl_optimizes_u(c)) st = ls_param_from_differential(&fit->param, fit->params, xs);
    fit->timing.solve_ns += fit_now(monitor) - t0;
    if (st != LS_OK) {
        if (st == LS_ERR_NONFINITE) diag_set(diag, st, "solve: non-finite differential coordinates", fit->iteration);
        return st;
    }
    for (k = 0; k < 3; k++) tr[k] = c->use_translation ? fit->params[3u * n + k] : (ls_real)0;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) fit->xr[3u * i + k] = xs[3u * i + k] + tr[k];
    st = ls_fit_impl_views_pass(fit, monitor, diag);
    if (st == LS_ERR_NONFINITE && diag != NULL) diag->index = fit->iteration, diag->has_index = 1;
    if (st != LS_OK) return st;
    if (first_nonfinite(fit->gx, 3u * (size_t)n) < 3u * (size_t)n) {
        diag_set(diag, LS_ERR_NONFINITE, "non-finite gradient of the vertex positions", fit->iteration);
        return LS_ERR_NONFINITE;
    }
    if (!finite_r(fit->loss)) {
        diag_set(diag, LS_ERR_NONFINITE, "non-finite loss", fit->iteration);
        return LS_ERR_NONFINITE;
    }
    fit->reg_loss = (ls_real)0;
    if (c->method == LS_FIT_LAPLACIAN || c->method == LS_FIT_BILAPLACIAN) {
        /* w mean(...) over the 3n values: value and gradient scaled by w / (3n) */
        const ls_real w = c->reg_weight / (ls_real)(3u * n);
        st = c->method == LS_FIT_LAPLACIAN ? ls_laplacian_energy(&fit->lap, 3, xs, w, &fit->reg_loss, fit->grad, &fit->block)
                                           : ls_laplacian_bilaplacian(&fit->lap, 3, xs, w, &fit->reg_loss, fit->grad, &fit->block);
        if (st != LS_OK) return st;
        for (i = 0; i < 3u * n; i++) fit->gx[i] += fit->grad[i];
    }
    t0 = fit_now(monitor);
    ls_fit_impl_mask_pull(fit);
    fit->timing.render_ns += fit_now(monitor) - t0; /* a loss term: with the images' */
    /* the translation's gradient: the sum over the vertices, in order */
    for (k = 0; k < 3; k++) {
        ls_real s = (ls_real)0;
        for (i = 0; i < n; i++) s += fit->gx[3u * i + k];
        fit->grad[3u * n + k] = s;
    }
    t0 = fit_now(monitor);
    if (c->method == LS_FIT_LARGE_STEPS) {
        st = ls_param_adjoint(&fit->param, fit->gx, fit->grad);
        if (st == LS_OK && c->mean_mode == LS_FIT_MEAN_PROJECT) remove_mean(fit->grad, n);
    } else {
        memcpy(fit->grad, fit->gx, 3u * (size_t)n * sizeof(ls_real));
    }
    fit->timing.solve_ns += fit_now(monitor) - t0;
    if (st == LS_ERR_NONFINITE) diag_set(diag, st, "adjoint solve: non-finite gradient", fit->iteration);
    return st;
}

/* config.grad_limit: a block's gradient whose largest element exceeds K x
 * the block's last UniformAdam scale is scaled down to it, its direction
 * kept (none before the first step, or with another method). */
static void limit_gradient(ls_fit *fit)
{
    const ls_optim *o = &fit->optim;
    const ls_real k = fit->config.grad_limit;
    size_t at = 0, i;
    uint32_t b;
    if (!(k > (ls_real)0) || o->config.method != LS_OPTIM_UNIFORM_ADAM || o->step == 0u) return;
    for (b = 0; b < o->block_count; b++) {
        const ls_real bound = k * o->last_scale[b];
        ls_real mx = (ls_real)0;
        for (i = at; i < at + o->block_size[b]; i++) {
            const ls_real a = fit->grad[i] < (ls_real)0 ? -fit->grad[i] : fit->grad[i];
            if (a > mx) mx = a;
        }
        if (bound > (ls_real)0 && mx > bound) {
            const ls_real f = bound / mx;
            for (i = at; i < at + o->block_size[b]; i++) fit->grad[i] *= f;
        }
        at += o->block_size[b];
    }
}

/* The optimizer step, undone when a parameter overflows (its snapshot in
 * the block's scratch, released on return). */
LS_NOINLINE static ls_status step_optimizer(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
{
    ls_optim *o = &fit->optim;
    const size_t count = o->count;
    ls_arena_mark mark = ls_arena_save(&fit->block);
    ls_real *p0 = (ls_real *)ls_arena_scratch(&fit->block, count, sizeof(ls_real));
    ls_real *m1 = (ls_real *)ls_arena_scratch(&fit->block, count, sizeof(ls_real));
    ls_real *m2 = (ls_real *)ls_arena_scratch(&fit->block, count, sizeof(ls_real));
    ls_real last[LS_OPTIM_MAX_BLOCKS];
    uint32_t t = o->step;
    uint64_t t0;
    ls_status st;
    if (m2 == NULL) { /* not reached: reserved by ls_fit_impl_iteration_scratch */
        ls_arena_restore(&fit->block, mark);
        return LS_ERR_NOMEM;
    }
    memcpy(p0, fit->params, count * sizeof(ls_real));
    memcpy(m1, o->m1, count * sizeof(ls_real));
    memcpy(m2, o->m2, count * sizeof(ls_real));
    memcpy(last, o->last_scale, sizeof last);
    t0 = fit_now(monitor);
    limit_gradient(fit);
    st = ls_optim_step(o, fit->params, fit->grad, diag);
    fit->timing.optimizer_ns += fit_now(monitor) - t0;
    if (st == LS_ERR_NONFINITE) diag_set(diag, st, "non-finite gradient of the optimized parameters", fit->iteration);
    if (st == LS_OK && first_nonfinite(fit->params, count) < count) {
        diag_set(diag, LS_ERR_NONFINITE, "optimizer step: a parameter overflowed", fit->iteration);
        memcpy(fit->params, p0, count * sizeof(ls_real));
        memcpy(o->m1, m1, count * sizeof(ls_real));
        memcpy(o->m2, m2, count * sizeof(ls_real));
        memcpy(o->last_scale, last, sizeof last);
        o->step = t;
        st = LS_ERR_NONFINITE;
    }
    ls_arena_restore(&fit->block, mark);
    return st;
}

static ls_status fit_step_call(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_fit_timing timing;
    ls_cg_info cg;
    ls_real loss, reg_loss, *xs, *warm = NULL;
    uint32_t sh_valid, albedo_due;
    size_t nn;
    ls_status st = LS_OK;
    if (fit == NULL || fit->x == NULL) return ls_invalid_arg(diag, "fit: NULL or not initialised (ls_fit_init)");
    nn = 3u * (size_t)fit->vertex_count;
    /* what a failure restores: the scalars here, the CG warm starts copied
     * to scratch; x is written only once the step has succeeded */
    timing = fit->timing;
    loss = fit->loss;
    reg_loss = fit->reg_loss;
    cg = fit->param.cg;
    sh_valid = fit->sh_valid; /* only the first estimate can change sh before the step succeeds */
    albedo_due = fit->albedo_due; /* and the albedo, from 1 */
    mark = ls_arena_save(&fit->block);
    xs = fit->x;
    if (ls_fit_impl_optimizes_u(&fit->config)) {
        xs = (ls_real *)ls_arena_scratch(&fit->block, nn, sizeof(ls_real));
        if (fit->config.solver == LS_PARAM_CG) {
            warm = (ls_real *)ls_arena_scratch(&fit->block, 2u * nn, sizeof(ls_real));
            if (warm != NULL) {
                memcpy(warm, fit->param.warm_fwd, nn * sizeof(ls_real));
                memcpy(warm + nn, fit->param.warm_adj, nn * sizeof(ls_real));
            }
        }
        if (xs == NULL || (fit->config.solver == LS_PARAM_CG && warm == NULL)) st = LS_ERR_NOMEM; /* not reached */
    }
    if (st == LS_OK) st = step_gradient(fit, xs, monitor, diag);
    if (st == LS_OK) st = step_optimizer(fit, monitor, diag);
    if (st == LS_OK) {
        if (ls_fit_impl_optimizes_u(&fit->config)) memcpy(fit->x, xs, nn * sizeof(ls_real));
        else memcpy(fit->x, fit->params, nn * sizeof(ls_real));
        /* the lighting of the geometry just rendered, for the next steps (kept when it cannot be solved) */
        if (fit->config.light == LS_FIT_LIGHT_ESTIMATE && fit_light_iteration(fit)) {
            /* each from sums taken under the other's previous value; the
             * albedo's mean stays 1, so the two cannot trade scale back and forth */
            const uint32_t had_light = fit->sh_valid;
            if (ls_sh_solve(&fit->sh_sums, fit->sh, NULL) == LS_OK) fit->sh_valid = 1;
            if (fit->albedo != NULL && had_light)
                (void)ls_albedo_solve(fit->albedo_sums, fit->albedo_sums + nn, fit->vertex_count, fit->albedo, NULL);
        }
        fit->iteration++;
    } else {
        if (!sh_valid && fit->sh_valid) { /* sh was zeros before its first estimate */
            memset(fit->sh, 0, sizeof fit->sh);
            fit->sh_valid = 0;
        }
        if (albedo_due && !fit->albedo_due) { /* the albedo was 1 before its estimate */
            size_t i;
            for (i = 0; i < nn; i++) fit->albedo[i] = (ls_real)1;
            fit->albedo_due = 1;
        }
        fit->timing = timing;
        fit->loss = loss;
        fit->reg_loss = reg_loss;
        fit->param.cg = cg;
        if (warm != NULL) {
            memcpy(fit->param.warm_fwd, warm, nn * sizeof(ls_real));
            memcpy(fit->param.warm_adj, warm + nn, nn * sizeof(ls_real));
        }
    }
    ls_arena_restore(&fit->block, mark);
    return st;
}

/* The public calls that take a diag clear it on success (fit.h). */

ls_status ls_fit_bytes(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                       ls_arena *scratch, size_t *bytes, ls_diag *diag)
{
    ls_status st = fit_bytes_call(config, views, initial, scratch, bytes, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

ls_status ls_fit_init(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                      ls_arena *arena, ls_diag *diag)
{
    ls_status st = fit_init_call(fit, config, views, initial, arena, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

ls_status ls_fit_step(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
{
    ls_status st = fit_step_call(fit, monitor, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

/* ls_fit_remesh's second half: *fit replaced by a fit on `mesh` (caller
 * units) with configuration cfg (not in *fit), built in `arena`, keeping
 * the frame, the views, the timing, the counts and the job's reservation. */
ls_status ls_fit_impl_rebuild(ls_fit *fit, ls_real lr_factor, const ls_mesh *mesh, ls_arena *arena, ls_diag *diag)
{
    ls_fit_config cfg = fit->config; /* here, not in the callers' frames: the deep chain below is the MCU's stack */
    const ls_fit_views views = fit->views;
    const ls_fit_timing timing = fit->timing;
    const ls_fit_capacity capacity = fit->capacity;
    const ls_arena job = fit->job;
    const size_t job_fit_bytes = fit->job_fit_bytes;
    const ls_real scale = fit->scale, radius = fit->radius;
    const uint32_t iteration = fit->iteration, remeshes = fit->remeshes, max_edges = fit->max_edges;
    ls_status st;
    cfg.optim.lr = cfg.optim.lr * lr_factor;
    memset(fit, 0, offsetof(ls_fit, sh)); /* the estimated lighting (the last fields) carries over */
    st = ls_fit_impl_fit_init_frame(fit, &cfg, &views, mesh, scale, radius, NULL, arena, diag);
    if (st != LS_OK) return st;
    fit->timing = timing;
    fit->iteration = iteration;
    fit->remeshes = remeshes + 1u;
    fit->albedo_due = fit->albedo != NULL; /* new vertices: estimated again at the next iteration */
    fit->capacity = capacity;
    fit->max_edges = max_edges;
    fit->job = job;
    fit->job_fit_bytes = job_fit_bytes;
    return LS_OK;
}
