/* fit.c - the reconstruction loop (see include/largesteps/fit.h). */
#include <string.h>
#include <largesteps/fit.h>
#include <largesteps/laplacian.h>
#include <largesteps/loss.h>
#include <largesteps/render_backward.h>
#include <largesteps/remesh.h>

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index)
{
    if (diag == NULL) return;
    ls_diag_clear(diag);
    diag->status = st;
    diag->what = what;
    diag->has_index = 1;
    diag->index = index;
}

static int finite_r(ls_real x) { return x - x == x - x; }

/* LS_ERR_INVALID naming the argument that is wrong (diag may be NULL). */
static ls_status invalid_arg(ls_diag *diag, const char *what)
{
    return ls_diag_set(diag, LS_ERR_INVALID, what, LS_DIAG_NO_INDEX);
}

/* The fit's frame (fit.h): R = half the largest side of the mesh's bounding
 * box, S = the largest power of two <= R (1 when R = 0). Both scale exactly
 * with the mesh by any power of two: the bounds, the halving and the
 * doubling/halving loop are exact. */
static void measure_frame(const ls_mesh *m, ls_real *scale, ls_real *radius)
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
    if (c->mean_mode == LS_FIT_MEAN_PROJECT && !c->use_translation)
        return "config->mean_mode: LS_FIT_MEAN_PROJECT needs use_translation = 1";
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

static void param_config(const ls_fit_config *c, ls_param_config *pc)
{
    memset(pc, 0, sizeof *pc);
    pc->solver = c->solver;
    pc->form = c->form;
    pc->weight = c->weight;
    pc->k = 3;
    pc->order = LS_ORDER_AMD;
    pc->cg_max_iter = 1000;
    pc->cg_tol = c->cg_tol > (ls_real)0 ? c->cg_tol : (ls_real)1e-6;
}

/* p = 1: the optimizer moves x itself, its gradient preconditioned once. */
static int optimizes_u(const ls_fit_config *c)
{
    return c->method == LS_FIT_LARGE_STEPS && c->power != 1u;
}

static int pair_mode(const ls_fit_config *c)
{
    return c->silhouette == LS_FIT_SILHOUETTE_PAIR;
}

/* The block's layout, mirrored by ls_fit_bytes and ls_fit_init: the arrays,
 * the Laplacian (with its build scratch), M and its solver, the optimizer,
 * the edge table, the visibility buffer, then the scratch of one iteration. */
typedef struct fit_sizes {
    size_t arrays, lap, param, optim, edges, vis, iteration;
} fit_sizes;

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
    if (pair_mode(c)) {
        ls_size_add(&s, px, sizeof(ls_real)); /* pair_image */
        ls_size_add(&s, px, sizeof(ls_real)); /* pair_gimage */
    }
    ls_size_add(&s, 16u * (size_t)views, sizeof(ls_real)); /* mvp */
    if (c->guard) ls_size_add(&s, 3u * (3u * (size_t)n + 3u) + 3u * (size_t)n, sizeof(ls_real)); /* saved */
    return ls_size_get(&s, bytes);
}

/* The silhouette pass bins every triangle into the 2 x 2 pixel tiles its
 * screen box meets; for a framed mesh the (triangle, tile) pairs stay far
 * below the worst case (every triangle in every tile). The fit reserves
 * LS_FIT_BIN_PER_TRIANGLE pairs per triangle plus LS_FIT_BIN_PER_TILE per
 * tile; a view that needs more fails its step with LS_ERR_NOMEM. */
#define LS_FIT_BIN_PER_TRIANGLE 8u
#define LS_FIT_BIN_PER_TILE 16u

/* The scratch of one iteration: the step's own arrays (the solved positions,
 * a copy of the CG warm starts) for the whole step, then the larger of the
 * views' pass (raster, silhouettes, normals backward, the regularizer) and
 * the optimizer's snapshot (parameters and both moments), which follow one
 * another. */
static ls_status iteration_scratch(const ls_fit_config *c, uint32_t n, uint32_t f, const ls_csc *lap, size_t *bytes)
{
    size_t a = 0, b = 0, e = 0, sil = 0;
    ls_size s, pass, snap;
    ls_status st = ls_raster_scratch_bytes_bound(c->width, c->height, c->ss, n, f, &a);
    if (st == LS_OK)
        st = ls_silhouette_scratch_bytes_bins(c->width, c->height, n, f, LS_FIT_BIN_PER_TRIANGLE, LS_FIT_BIN_PER_TILE, &sil);
    if (st == LS_OK && sil > a) a = sil;
    if (st == LS_OK) st = ls_refine_scratch_bytes_bound(c->width, c->height, c->ss, f, c->aa, &sil); /* 0 when off */
    if (st == LS_OK && sil > a) a = sil;
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
        ls_status st2 = ls_tangle_bytes(f, &e);
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

static ls_status total(const fit_sizes *z, size_t *bytes)
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
static ls_status base_sizes(const ls_fit_config *c, uint32_t views, uint32_t n, uint32_t f, uint32_t edges, fit_sizes *z)
{
    ls_status st;
    memset(z, 0, sizeof *z);
    st = array_sizes(c, views, n, f, &z->arrays);
    if (st == LS_OK) st = ls_laplacian_bytes(n, f, edges, LS_LAP_UPPER, &z->lap);
    if (st == LS_OK) st = ls_optim_bytes(3u * n + 3u, &z->optim);
    if (st == LS_OK) st = ls_edge_table_bytes(f, &z->edges);
    if (st == LS_OK) st = ls_vis_bytes(c->width, c->height, c->ss, n, &z->vis);
    return st;
}

/* The counts a job's capacity bounds (ls_fit_capacity, plus the edges). */
typedef struct fit_counts {
    uint32_t vertices, faces, edges, factor_nnz;
} fit_counts;

/* ls_fit_bytes in the frame of unit `scale`: the ordering of the factor
 * sees the normalized coordinates, as ls_fit_init gives them. *counts
 * (optional) receives the mesh's counts and its factor's fill. */
static ls_status fit_bytes_frame(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
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
    if (st == LS_OK) st = base_sizes(config, views->count, initial->vertex_count, initial->face_count, e.count, &z);
    if (st == LS_OK) st = ls_laplacian_uniform(initial, LS_LAP_UPPER, scratch, &lap, diag);
    if (st == LS_OK) st = iteration_scratch(config, initial->vertex_count, initial->face_count, &lap, &z.iteration);
    if (st == LS_OK && config->method == LS_FIT_LARGE_STEPS) {
        param_config(config, &pc);
        st = ls_param_bytes_fill(&lap, &pc, xyz, scratch, &z.param, &l_nnz);
    }
    /* ls_fit_init runs this same measurement in its arena before taking the
     * block: the answer covers both */
    used = scratch->peak - used;
    ls_arena_restore(scratch, mark);
    if (peak > scratch->peak) scratch->peak = peak;
    if (st != LS_OK) return st;
    st = total(&z, &block);
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
    if (bytes == NULL || scratch == NULL) return invalid_arg(diag, "bytes or scratch is NULL");
    st = check_config(config, views, initial, diag);
    if (st != LS_OK) return st;
    measure_frame(initial, &scale, &radius);
    return fit_bytes_frame(config, views, initial, scale, scratch, bytes, NULL, diag);
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
    if (pair_mode(&fit->config)) {
        fit->pair_image = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        fit->pair_gimage = (ls_real *)ls_arena_alloc(a, px, sizeof(ls_real));
        if (fit->pair_gimage == NULL) return 0;
    }
    fit->mvp = (ls_real *)ls_arena_alloc(a, 16u * (size_t)fit->views.count, sizeof(ls_real));
    if (fit->config.guard) {
        fit->saved = (ls_real *)ls_arena_alloc(a, 3u * (3u * (size_t)n + 3u) + 3u * (size_t)n, sizeof(ls_real));
        if (fit->saved == NULL) return 0;
    }
    return fit->mvp != NULL;
}

static ls_status within(const fit_counts *have, const fit_counts *lim, int remesh, ls_diag *diag);

/* ls_fit_init in a given frame (ls_fit_remesh keeps the first fit's); lim
 * (optional): a job's capacity, checked before anything is taken. */
static ls_status fit_init_frame(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views,
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
    st = fit_bytes_frame(config, views, initial, scale, arena, &bytes, &have, diag);
    if (st == LS_OK && lim != NULL) st = within(&have, lim, 0, diag);
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
    if (st == LS_OK) {
        memcpy(fit->triangles, initial->triangles, 3u * (size_t)nf * sizeof(uint32_t));
        st = ls_laplacian_uniform(initial, LS_LAP_UPPER, &fit->block, &fit->lap, diag);
    }
    if (st == LS_OK && config->method == LS_FIT_LARGE_STEPS) {
        param_config(config, &pc);
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
    if (st == LS_OK) {
        /* what is left is the iteration's scratch: check it covers the reserve */
        st = iteration_scratch(config, n, nf, &fit->lap, &reserve);
        if (st == LS_OK && ls_arena_available(&fit->block) < reserve) st = LS_ERR_NOMEM; /* not reached */
        fit->scratch_bytes = ls_arena_available(&fit->block);
    }
    if (st != LS_OK) {
        memset(fit, 0, sizeof *fit);
        ls_arena_restore(arena, mark);
        return st;
    }
    memcpy(fit->params, optimizes_u(config) ? fit->u : fit->x, 3u * (size_t)n * sizeof(ls_real));
    fit->params[3u * (size_t)n] = fit->params[3u * (size_t)n + 1u] = fit->params[3u * (size_t)n + 2u] = (ls_real)0;
    return LS_OK;
}

/* The arguments of ls_fit_init and ls_fit_init_job. */
static ls_status init_args_ok(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
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
    if (fit == NULL || arena == NULL) return invalid_arg(diag, "fit or arena is NULL");
    memset(fit, 0, sizeof *fit);
    st = init_args_ok(config, views, initial, diag);
    if (st != LS_OK) return st;
    measure_frame(initial, &scale, &radius);
    return fit_init_frame(fit, config, views, initial, scale, radius, NULL, arena, diag);
}

static uint64_t now(const ls_monitor *m)
{
    return (m != NULL && m->clock != NULL) ? m->clock(m->user) : 0u;
}

/* The first non-finite value of v[0..count), or count. */
static size_t first_nonfinite(const ls_real *v, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        if (!finite_r(v[i])) return i;
    return count;
}

/* Renders every view and accumulates the loss and dL/d(rendered positions)
 * into fit->gx. */
static ls_status views_pass(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
{
    const ls_fit_config *c = &fit->config;
    const uint32_t n = fit->vertex_count, nf = fit->face_count;
    const int shaded = c->shading.mode == LS_SHADE_SH || c->shading.mode == LS_SHADE_LAMBERT;
    ls_loss_acc acc;
    ls_view view;
    uint32_t v;
    uint64_t t0;
    ls_status st;
    memset(&view, 0, sizeof view);
    view.vis = &fit->vis;
    view.positions = fit->xr;
    view.indices = fit->triangles;
    view.triangle_count = nf;
    view.vertex_count = n;
    view.normals = fit->normals;
    view.opts = &c->shading;
    view.table = &fit->edges;
    view.boost = c->boost;
    memset(fit->gx, 0, 3u * (size_t)n * sizeof(ls_real));
    memset(fit->gnormals, 0, 3u * (size_t)n * sizeof(ls_real));
    t0 = now(monitor);
    if (shaded) {
        st = ls_shade_vertex_normals(fit->xr, n, fit->triangles, nf, fit->normals, diag);
        if (st != LS_OK) return st;
    }
    st = ls_loss_begin(&acc, c->loss, c->width, c->height, fit->views.count);
    if (st != LS_OK) return st;
    for (v = 0; v < fit->views.count; v++) {
        uint64_t t1, t2, t3;
        view.mvp = fit->mvp + 16u * (size_t)v;
        st = ls_monitor_report(monitor, "fit.view", v, fit->views.count);
        if (st == LS_OK) st = ls_raster(&fit->vis, &view, &fit->block, diag);
        if (st == LS_OK) st = ls_shade(&view, fit->image, diag);
        if (st == LS_OK && c->aa > c->ss) st = ls_refine_shade(&view, c->aa, fit->image, &fit->block, NULL, diag);
        if (st == LS_OK && pair_mode(c)) {
            /* the loss sees the blended image; its gradient goes back through
             * the blending to the positions and to the shaded image */
            st = ls_pair_forward(&view, fit->image, fit->pair_image, diag);
            if (st == LS_OK) st = ls_loss_view(&acc, fit->pair_image, fit->views.targets[v], fit->pair_gimage, diag);
        } else if (st == LS_OK) {
            st = ls_loss_view(&acc, fit->image, fit->views.targets[v], fit->gimage, diag);
        }
        t1 = now(monitor);
        fit->timing.render_ns += t1 - t0;
        if (st == LS_OK && pair_mode(c)) {
            memset(fit->gimage, 0, (size_t)c->width * c->height * 4u * sizeof(ls_real));
            st = ls_pair_backward(&view, fit->image, fit->pair_gimage, fit->gimage, fit->gx, diag);
        }
        t2 = now(monitor);
        fit->timing.silhouette_ns += t2 - t1;
        if (st == LS_OK && c->aa > c->ss) {
            ls_shade_grads sg;
            memset(&sg, 0, sizeof sg);
            sg.positions = fit->gx;
            sg.normals = shaded ? fit->gnormals : NULL;
            st = ls_refine_shade_backward(&view, c->aa, fit->gimage, &sg, &fit->block, diag);
        } else if (st == LS_OK) {
            st = ls_shade_backward(&view, fit->gimage, fit->gx, shaded ? fit->gnormals : NULL, NULL, diag);
        }
        t1 = now(monitor);
        fit->timing.shade_backward_ns += t1 - t2;
        if (st == LS_OK && c->silhouette == LS_FIT_SILHOUETTE_EXACT)
            st = ls_silhouette_backward(&view, fit->gimage, fit->gx, &fit->block, diag);
        t3 = now(monitor);
        fit->timing.silhouette_ns += t3 - t1;
        t0 = t3;
        if (st != LS_OK) return st;
    }
    if (shaded) {
        st = ls_vertex_normals_backward(fit->xr, n, fit->triangles, nf, fit->gnormals, fit->gx, &fit->block, diag);
        fit->timing.shade_backward_ns += now(monitor) - t0;
        if (st != LS_OK) return st;
    }
    return ls_loss_finish(&acc, &fit->loss);
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
    t0 = now(monitor);
    if (optimizes_u(c)) st = ls_param_from_differential(&fit->param, fit->params, xs);
    fit->timing.solve_ns += now(monitor) - t0;
    if (st != LS_OK) {
        if (st == LS_ERR_NONFINITE) diag_set(diag, st, "solve: non-finite differential coordinates", fit->iteration);
        return st;
    }
    for (k = 0; k < 3; k++) tr[k] = c->use_translation ? fit->params[3u * n + k] : (ls_real)0;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) fit->xr[3u * i + k] = xs[3u * i + k] + tr[k];
    st = views_pass(fit, monitor, diag);
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
    /* the translation's gradient: the sum over the vertices, in order */
    for (k = 0; k < 3; k++) {
        ls_real s = (ls_real)0;
        for (i = 0; i < n; i++) s += fit->gx[3u * i + k];
        fit->grad[3u * n + k] = s;
    }
    t0 = now(monitor);
    if (c->method == LS_FIT_LARGE_STEPS) {
        st = ls_param_adjoint(&fit->param, fit->gx, fit->grad);
        if (st == LS_OK && c->mean_mode == LS_FIT_MEAN_PROJECT) remove_mean(fit->grad, n);
    } else {
        memcpy(fit->grad, fit->gx, 3u * (size_t)n * sizeof(ls_real));
    }
    fit->timing.solve_ns += now(monitor) - t0;
    if (st == LS_ERR_NONFINITE) diag_set(diag, st, "adjoint solve: non-finite gradient", fit->iteration);
    return st;
}

/* The optimizer step, undone when a parameter overflows (its snapshot in
 * the block's scratch, released on return). */
static ls_status step_optimizer(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
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
    if (m2 == NULL) { /* not reached: reserved by iteration_scratch */
        ls_arena_restore(&fit->block, mark);
        return LS_ERR_NOMEM;
    }
    memcpy(p0, fit->params, count * sizeof(ls_real));
    memcpy(m1, o->m1, count * sizeof(ls_real));
    memcpy(m2, o->m2, count * sizeof(ls_real));
    memcpy(last, o->last_scale, sizeof last);
    t0 = now(monitor);
    st = ls_optim_step(o, fit->params, fit->grad, diag);
    fit->timing.optimizer_ns += now(monitor) - t0;
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
    size_t nn;
    ls_status st = LS_OK;
    if (fit == NULL || fit->x == NULL) return invalid_arg(diag, "fit: NULL or not initialised (ls_fit_init)");
    nn = 3u * (size_t)fit->vertex_count;
    /* what a failure restores: the scalars here, the CG warm starts copied
     * to scratch; x is written only once the step has succeeded */
    timing = fit->timing;
    loss = fit->loss;
    reg_loss = fit->reg_loss;
    cg = fit->param.cg;
    mark = ls_arena_save(&fit->block);
    xs = fit->x;
    if (optimizes_u(&fit->config)) {
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
        if (optimizes_u(&fit->config)) memcpy(fit->x, xs, nn * sizeof(ls_real));
        else memcpy(fit->x, fit->params, nn * sizeof(ls_real));
        fit->iteration++;
    } else {
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

/* The current mesh in the fit's frame: M^-1 u (large steps; the CG's warm
 * start and statistics are put back, from the block's scratch) or x, plus
 * the translation. */
static ls_status frame_mesh(ls_fit *fit, ls_real *positions)
{
    const uint32_t n = fit->vertex_count;
    if (optimizes_u(&fit->config)) {
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

static ls_status fit_tangle_call(ls_fit *fit, ls_tangle_report *out, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_real *pos;
    ls_mesh m;
    ls_status st;
    if (fit == NULL || out == NULL || fit->x == NULL) return invalid_arg(diag, "fit or out is NULL, or fit not initialised");
    if (!fit->config.guard) return invalid_arg(diag, "fit->config.guard: 0; ls_fit_tangle needs a fit made with guard = 1");
    mark = ls_arena_save(&fit->block);
    pos = (ls_real *)ls_arena_scratch(&fit->block, 3u * (size_t)fit->vertex_count, sizeof(ls_real));
    st = pos != NULL ? frame_mesh(fit, pos) : LS_ERR_NOMEM; /* not reached: the reserve */
    if (st == LS_OK) {
        m.positions = pos;
        m.triangles = fit->triangles;
        m.vertex_count = fit->vertex_count;
        m.face_count = fit->face_count;
        st = ls_tangle(&m, NULL, &fit->block, out, diag);
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
    ls_status st = ls_tangle(cur, NULL, work, &before, diag);
    if (st == LS_OK) st = ls_tangle(out, NULL, work, &after, diag);
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

/* ls_fit_remesh's second half: *fit replaced by a fit on `mesh` (caller
 * units) with configuration cfg (not in *fit), built in `arena`, keeping
 * the frame, the views, the timing, the counts and the job's reservation. */
static ls_status rebuild(ls_fit *fit, const ls_fit_config *cfg, const ls_mesh *mesh, ls_arena *arena, ls_diag *diag)
{
    const ls_fit_views views = fit->views;
    const ls_fit_timing timing = fit->timing;
    const ls_fit_capacity capacity = fit->capacity;
    const ls_arena job = fit->job;
    const size_t job_fit_bytes = fit->job_fit_bytes;
    const ls_real scale = fit->scale, radius = fit->radius;
    const uint32_t iteration = fit->iteration, remeshes = fit->remeshes, max_edges = fit->max_edges;
    ls_status st;
    memset(fit, 0, sizeof *fit);
    st = fit_init_frame(fit, cfg, &views, mesh, scale, radius, NULL, arena, diag);
    if (st != LS_OK) return st;
    fit->timing = timing;
    fit->iteration = iteration;
    fit->remeshes = remeshes + 1u;
    fit->capacity = capacity;
    fit->max_edges = max_edges;
    fit->job = job;
    fit->job_fit_bytes = job_fit_bytes;
    return LS_OK;
}

static ls_status remesh_in_job(ls_fit *fit, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info, ls_diag *diag);

static ls_status fit_remesh_call(ls_fit *fit, ls_arena *arena, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info, ls_diag *diag)
{
    ls_arena_mark mark, keep;
    ls_fit_config cfg;
    ls_mesh out, copy;
    size_t start, new_bytes, copy_bytes;
    ls_status st;
    if (fit == NULL || fit->x == NULL) return invalid_arg(diag, "fit: NULL or not initialised (ls_fit_init)");
    if (!(h_factor > (ls_real)0) || !(h_factor <= (ls_real)2))
        return invalid_arg(diag, "h_factor: the target edge over the mean edge, allowed (0, 2] (the method: 0.5)");
    if (!(lr_factor > (ls_real)0) || !finite_r(lr_factor))
        return invalid_arg(diag, "lr_factor: allowed finite and > 0 (the method: 0.8)");
    if (fit->job.base != NULL) return remesh_in_job(fit, h_factor, lr_factor, info, diag);
    if (arena == NULL) return invalid_arg(diag, "arena is NULL (a fit from ls_fit_init remeshes in its arena)");
    start = (size_t)(fit->block.base - arena->base);
    if (fit->block.base < arena->base || start + LS_ARENA_ROUND(fit->block.capacity) != arena->bottom)
        return invalid_arg(diag, "arena: the fit must be the last allocation at its bottom");
    mark = ls_arena_save(arena);
    st = remesh_current(fit, arena, h_factor, 0, &out, info, diag);
    cfg = fit->config;
    cfg.optim.lr = cfg.optim.lr * lr_factor;
    if (st == LS_OK) st = fit_bytes_frame(&cfg, &fit->views, &out, fit->scale, arena, &new_bytes, NULL, diag);
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
    st = rebuild(fit, &cfg, &copy, arena, diag);
    keep.bottom = arena->bottom;
    keep.top = mark.top;
    ls_arena_restore(arena, keep);
    return st;
}

/* --- a whole job within one reservation (fit.h: ls_fit_job_bytes) ------ */

/* LS_ERR_TOO_LARGE in *diag: `what` exceeded; index = the count, value =
 * the capacity. */
static ls_status over(ls_diag *diag, const char *what, uint64_t count, uint32_t cap)
{
    (void)ls_diag_set(diag, LS_ERR_TOO_LARGE, what, count);
    if (diag != NULL) {
        diag->has_value = 1;
        diag->value = (ls_real)cap;
    }
    return LS_ERR_TOO_LARGE;
}

/* LS_ERR_TOO_LARGE naming the first count of `have` above its limit. */
static ls_status within(const fit_counts *have, const fit_counts *lim, int remesh, ls_diag *diag)
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
        if (h[k] > l[k]) return over(diag, what[remesh != 0][k], h[k], l[k]);
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
    st = base_sizes(c, views, n, f, lim->edges, &z);
    /* the regularizer's scratch depends on the Laplacian's size only */
    memset(&lap, 0, sizeof lap);
    lap.nrows = lap.ncols = n;
    if (st == LS_OK) st = iteration_scratch(c, n, f, &lap, &z.iteration);
    if (st == LS_OK && c->method == LS_FIT_LARGE_STEPS) {
        param_config(c, &pc);
        st = ls_param_bytes_bound(n, n + lim->edges, lim->factor_nnz, &pc, 1, &z.param);
        /* the measurement runs the analysis only: no factor */
        if (st == LS_OK && uses_factor(c))
            st = ls_ldlt_bytes_bound(n, n + lim->edges, n + lim->edges, 0, pc.order, &analyze, &object, &factor);
    }
    if (st == LS_OK) st = total(&z, &block);
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
        st = ls_tangle_bytes(f, &tb);
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
    st = within(&have, lim, 0, diag);
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
    st = within(&have, lim, 0, diag);
    if (st == LS_OK) st = job_sizes(c, views->count, lim, rep.euler, region, bytes);
    return st;
}

static ls_status fit_job_bytes_call(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial, const ls_fit_capacity *capacity, ls_arena *scratch, size_t *bytes, ls_diag *diag)
{
    fit_counts lim, have;
    ls_real scale, radius;
    size_t region = 0, job = 0, fit_bytes = 0;
    ls_status st;
    if (bytes == NULL || scratch == NULL) return invalid_arg(diag, "bytes or scratch is NULL");
    *bytes = 0;
    st = init_args_ok(config, views, initial, diag);
    if (st == LS_OK) st = job_plan(config, views, initial, capacity, scratch, &lim, &region, &job, diag);
    if (st != LS_OK) return st;
    /* the initial mesh's fill, from the analysis that init will run */
    measure_frame(initial, &scale, &radius);
    st = fit_bytes_frame(config, views, initial, scale, scratch, &fit_bytes, &have, diag);
    if (st == LS_OK) st = within(&have, &lim, 0, diag);
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
    if (fit == NULL || arena == NULL) return invalid_arg(diag, "fit or arena is NULL");
    memset(fit, 0, sizeof *fit);
    st = init_args_ok(config, views, initial, diag);
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
    measure_frame(initial, &scale, &radius);
    st = ls_arena_init(&region, mem, region_bytes);
    if (st == LS_OK) st = fit_init_frame(fit, config, views, initial, scale, radius, &lim, &region, diag);
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

/* ls_fit_remesh inside the job's reservation: the remesher and the new
 * fit's measurement in the work part, every count checked against the
 * capacity before the old fit is touched, then the new fit built in the
 * fit's part from the output still in the work part (no copy needed). */
static ls_status remesh_in_job(ls_fit *fit, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info, ls_diag *diag)
{
    ls_arena_mark mark = ls_arena_save(&fit->job);
    ls_arena region;
    ls_fit_config cfg;
    fit_counts lim, have;
    ls_mesh out;
    size_t new_bytes = 0;
    ls_status st;
    lim.vertices = fit->capacity.max_vertices;
    lim.faces = fit->capacity.max_faces;
    lim.edges = fit->max_edges;
    lim.factor_nnz = fit->capacity.max_factor_nnz;
    st = remesh_current(fit, &fit->job, h_factor, lim.vertices, &out, info, diag);
    /* the work part holds the remesher's bound at max_vertices: running
     * out of it is running out of vertex capacity */
    if (st == LS_ERR_NOMEM) st = over(diag, "remesh: more vertices than capacity.max_vertices", (uint64_t)lim.vertices + 1u, lim.vertices);
    if (st == LS_OK) {
        have.vertices = out.vertex_count;
        have.faces = out.face_count;
        have.edges = have.factor_nnz = 0;
        st = within(&have, &lim, 1, diag);
    }
    cfg = fit->config;
    cfg.optim.lr = cfg.optim.lr * lr_factor;
    if (st == LS_OK) st = fit_bytes_frame(&cfg, &fit->views, &out, fit->scale, &fit->job, &new_bytes, &have, diag);
    if (st == LS_OK) st = within(&have, &lim, 1, diag);
    if (st == LS_OK && new_bytes > fit->job_fit_bytes) /* not reached: the bound covers the counts */
        st = over(diag, "remesh: the new fit exceeds the job's reservation", new_bytes, (uint32_t)0);
    if (st != LS_OK) {
        ls_arena_restore(&fit->job, mark);
        return st;
    }
    /* the point of no return */
    st = ls_arena_init(&region, fit->job.base, fit->job_fit_bytes);
    if (st == LS_OK) st = rebuild(fit, &cfg, &out, &region, diag);
    ls_arena_restore(&fit->job, mark);
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

ls_status ls_fit_tangle(ls_fit *fit, ls_tangle_report *out, ls_diag *diag)
{
    ls_status st = fit_tangle_call(fit, out, diag);
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
