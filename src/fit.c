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

static ls_status check_config(const ls_fit_config *c, const ls_fit_views *v, const ls_mesh *m)
{
    uint32_t i;
    if (c == NULL || v == NULL || m == NULL || m->positions == NULL || m->triangles == NULL) return LS_ERR_INVALID;
    if (c->method > LS_FIT_BILAPLACIAN || c->loss > LS_LOSS_L2 || c->width == 0 || c->height == 0) return LS_ERR_INVALID;
    if (v->count == 0 || v->mvp == NULL || v->targets == NULL) return LS_ERR_INVALID;
    for (i = 0; i < v->count; i++)
        if (v->targets[i] == NULL) return LS_ERR_INVALID;
    if (c->form != LS_SYSTEM_LAMBDA && c->form != LS_SYSTEM_ALPHA) return LS_ERR_INVALID;
    if (!finite_r(c->weight) || c->weight < (ls_real)0) return LS_ERR_INVALID;
    if (c->form == LS_SYSTEM_ALPHA && !(c->weight < (ls_real)1)) return LS_ERR_INVALID;
    if (c->solver != LS_PARAM_LDLT && c->solver != LS_PARAM_CG && c->solver != LS_PARAM_AUTO) return LS_ERR_INVALID;
    if (!finite_r(c->boost) || !finite_r(c->reg_weight) || c->reg_weight < (ls_real)0) return LS_ERR_INVALID;
    if (c->shading.vertex_colors != NULL || c->shading.mode > LS_SHADE_LAMBERT) return LS_ERR_INVALID;
    if (c->silhouette > LS_FIT_SILHOUETTE_NONE || (c->silhouette == LS_FIT_SILHOUETTE_PAIR && c->ss != 1)) return LS_ERR_INVALID;
    if (c->power > 2u || !finite_r(c->cg_tol) || c->cg_tol < (ls_real)0) return LS_ERR_INVALID;
    if (m->vertex_count == 0 || m->face_count == 0 || m->vertex_count > (UINT32_MAX - 3u) / 3u) return LS_ERR_INVALID;
    return LS_OK;
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

static ls_status array_sizes(const ls_fit_config *c, uint32_t n, uint32_t f, size_t *bytes)
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
    return ls_size_get(&s, bytes);
}

/* The silhouette pass bins every triangle into the 2 x 2 pixel tiles its
 * screen box meets; for a framed mesh the (triangle, tile) pairs stay far
 * below the worst case (every triangle in every tile). The fit reserves
 * LS_FIT_BIN_PER_TRIANGLE pairs per triangle plus LS_FIT_BIN_PER_TILE per
 * tile; a view that needs more fails its step with LS_ERR_NOMEM. */
#define LS_FIT_BIN_PER_TRIANGLE 8u
#define LS_FIT_BIN_PER_TILE 16u

static ls_status iteration_scratch(const ls_fit_config *c, uint32_t n, uint32_t f, const ls_csc *lap, size_t *bytes)
{
    size_t a = 0, b = 0, e = 0, sil = 0;
    ls_status st = ls_raster_scratch_bytes_bound(c->width, c->height, c->ss, n, f, &a);
    if (st == LS_OK)
        st = ls_silhouette_scratch_bytes_bins(c->width, c->height, n, f, LS_FIT_BIN_PER_TRIANGLE, LS_FIT_BIN_PER_TILE, &sil);
    if (st == LS_OK && sil > a) a = sil;
    if (st == LS_OK) st = ls_vertex_normals_backward_bytes(n, &b);
    if (st == LS_OK && c->method == LS_FIT_LAPLACIAN) st = ls_laplacian_energy_bytes(lap, 3, 0, 1, &e);
    if (st == LS_OK && c->method == LS_FIT_BILAPLACIAN) st = ls_laplacian_energy_bytes(lap, 3, 1, 1, &e);
    if (st != LS_OK) return st;
    *bytes = a > b ? a : b;
    if (e > *bytes) *bytes = e;
    return LS_OK;
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
static ls_status base_sizes(const ls_fit_config *c, const ls_mesh *m, uint32_t edges, fit_sizes *z)
{
    ls_status st;
    uint32_t n = m->vertex_count, f = m->face_count;
    memset(z, 0, sizeof *z);
    st = array_sizes(c, n, f, &z->arrays);
    if (st == LS_OK) st = ls_laplacian_bytes(n, f, edges, LS_LAP_UPPER, &z->lap);
    if (st == LS_OK) st = ls_optim_bytes(3u * n + 3u, &z->optim);
    if (st == LS_OK) st = ls_edge_table_bytes(f, &z->edges);
    if (st == LS_OK) st = ls_vis_bytes(c->width, c->height, c->ss, n, &z->vis);
    return st;
}

ls_status ls_fit_bytes(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                       ls_arena *scratch, size_t *bytes, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_mesh_edges e;
    ls_param_config pc;
    ls_csc lap;
    fit_sizes z;
    size_t peak, used, block;
    ls_status st;
    if (bytes == NULL || scratch == NULL) return LS_ERR_INVALID;
    st = check_config(config, views, initial);
    if (st != LS_OK) return st;
    mark = ls_arena_save(scratch);
    peak = scratch->peak;
    used = ls_arena_used(scratch);
    ls_arena_reset_peak(scratch);
    st = ls_mesh_edges_build(initial, scratch, &e, diag);
    if (st == LS_OK) st = base_sizes(config, initial, e.count, &z);
    if (st == LS_OK) st = ls_laplacian_uniform(initial, LS_LAP_UPPER, scratch, &lap, diag);
    if (st == LS_OK) st = iteration_scratch(config, initial->vertex_count, initial->face_count, &lap, &z.iteration);
    if (st == LS_OK && config->method == LS_FIT_LARGE_STEPS) {
        param_config(config, &pc);
        st = ls_param_bytes(&lap, &pc, initial->positions, scratch, &z.param);
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
    return LS_OK;
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
    return fit->gimage != NULL;
}

ls_status ls_fit_init(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                      ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_param_config pc;
    size_t bytes, reserve;
    void *mem;
    uint32_t n, nf, i;
    ls_status st;
    if (fit == NULL || arena == NULL) return LS_ERR_INVALID;
    memset(fit, 0, sizeof *fit);
    st = check_config(config, views, initial);
    if (st != LS_OK) return st;
    for (i = 0; i < 3u * initial->vertex_count; i++)
        if (!finite_r(initial->positions[i])) {
            diag_set(diag, LS_ERR_NONFINITE, "initial mesh: non-finite coordinate", i / 3u);
            return LS_ERR_NONFINITE;
        }
    mark = ls_arena_save(arena);
    /* the block: measured with the arena's free top as scratch */
    st = ls_fit_bytes(config, views, initial, arena, &bytes, diag);
    if (st != LS_OK) return st;
    mem = ls_arena_alloc(arena, bytes, 1);
    if (mem == NULL) return LS_ERR_NOMEM;
    fit->config = *config;
    fit->views = *views;
    n = initial->vertex_count;
    nf = initial->face_count;
    fit->vertex_count = n;
    fit->face_count = nf;
    st = ls_arena_init(&fit->block, mem, bytes);
    if (st == LS_OK && !take_arrays(fit, n, nf)) st = LS_ERR_NOMEM;
    if (st == LS_OK) {
        memcpy(fit->x, initial->positions, 3u * (size_t)n * sizeof(ls_real));
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
        st = ls_optim_init(&fit->optim, &config->optim, 3u * n + 3u, config->use_translation ? 2u : 1u, blocks, &fit->block);
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
    uint32_t v;
    uint64_t t0;
    ls_status st;
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
        const ls_real *mvp = fit->views.mvp + 16u * (size_t)v;
        uint64_t t1, t2, t3;
        st = ls_monitor_report(monitor, "fit.view", v, fit->views.count);
        if (st == LS_OK) st = ls_raster(&fit->vis, &fit->block, mvp, fit->xr, n, fit->triangles, nf, diag);
        if (st == LS_OK) st = ls_shade(&fit->vis, fit->triangles, nf, fit->normals, n, &c->shading, fit->image, diag);
        if (st == LS_OK && pair_mode(c)) {
            /* the loss sees the blended image; its gradient goes back through
             * the blending to the positions and to the shaded image */
            st = ls_pair_forward(&fit->vis, &fit->edges, fit->triangles, nf, fit->image, fit->pair_image, diag);
            if (st == LS_OK) st = ls_loss_view(&acc, fit->pair_image, fit->views.targets[v], fit->pair_gimage, diag);
        } else if (st == LS_OK) {
            st = ls_loss_view(&acc, fit->image, fit->views.targets[v], fit->gimage, diag);
        }
        t1 = now(monitor);
        fit->timing.render_ns += t1 - t0;
        if (st == LS_OK && pair_mode(c)) {
            memset(fit->gimage, 0, (size_t)c->width * c->height * 4u * sizeof(ls_real));
            st = ls_pair_backward(&fit->vis, &fit->edges, fit->triangles, nf, mvp, c->boost, fit->image,
                                  fit->pair_gimage, fit->gimage, fit->gx, diag);
        }
        t2 = now(monitor);
        fit->timing.silhouette_ns += t2 - t1;
        if (st == LS_OK)
            st = ls_shade_backward(&fit->vis, fit->triangles, nf, fit->normals, n, &c->shading, mvp, fit->gimage,
                                   fit->gx, shaded ? fit->gnormals : NULL, NULL, diag);
        t1 = now(monitor);
        fit->timing.shade_backward_ns += t1 - t2;
        if (st == LS_OK && c->silhouette == LS_FIT_SILHOUETTE_EXACT)
            st = ls_silhouette_backward(&fit->vis, &fit->edges, fit->triangles, nf, fit->normals, n, &c->shading, mvp,
                                        c->boost, fit->gimage, fit->gx, &fit->block, diag);
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

ls_status ls_fit_step(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag)
{
    const ls_fit_config *c;
    uint32_t n, i, k;
    ls_real tr[3];
    uint64_t t0;
    size_t bad;
    ls_status st = LS_OK;
    if (fit == NULL || fit->x == NULL) return LS_ERR_INVALID;
    c = &fit->config;
    n = fit->vertex_count;
    t0 = now(monitor);
    if (optimizes_u(c)) st = ls_param_from_differential(&fit->param, fit->params, fit->x);
    fit->timing.solve_ns += now(monitor) - t0;
    if (st != LS_OK) {
        if (diag != NULL && st == LS_ERR_NONFINITE) diag_set(diag, st, "solve: non-finite differential coordinates", fit->iteration);
        return st;
    }
    for (k = 0; k < 3; k++) tr[k] = c->use_translation ? fit->params[3u * n + k] : (ls_real)0;
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++) fit->xr[3u * i + k] = fit->x[3u * i + k] + tr[k];
    st = views_pass(fit, monitor, diag);
    if (st == LS_ERR_NONFINITE && diag != NULL) diag->index = fit->iteration, diag->has_index = 1;
    if (st != LS_OK) return st;
    bad = first_nonfinite(fit->gx, 3u * (size_t)n);
    if (bad < 3u * (size_t)n) {
        diag_set(diag, LS_ERR_NONFINITE, "non-finite gradient of the vertex positions", fit->iteration);
        return LS_ERR_NONFINITE;
    }
    fit->reg_loss = (ls_real)0;
    if (c->method == LS_FIT_LAPLACIAN || c->method == LS_FIT_BILAPLACIAN) {
        /* w mean(...) over the 3n values: value and gradient scaled by w / (3n) */
        const ls_real w = c->reg_weight / (ls_real)(3u * n);
        st = c->method == LS_FIT_LAPLACIAN ? ls_laplacian_energy(&fit->lap, 3, fit->x, w, &fit->reg_loss, fit->grad, &fit->block)
                                           : ls_laplacian_bilaplacian(&fit->lap, 3, fit->x, w, &fit->reg_loss, fit->grad, &fit->block);
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
    } else {
        memcpy(fit->grad, fit->gx, 3u * (size_t)n * sizeof(ls_real));
    }
    fit->timing.solve_ns += now(monitor) - t0;
    if (st != LS_OK) return st;
    t0 = now(monitor);
    st = ls_optim_step(&fit->optim, fit->params, fit->grad, diag);
    fit->timing.optimizer_ns += now(monitor) - t0;
    if (st != LS_OK) {
        if (st == LS_ERR_NONFINITE) diag_set(diag, st, "non-finite gradient of the optimized parameters", fit->iteration);
        return st;
    }
    if (!optimizes_u(c)) memcpy(fit->x, fit->params, 3u * (size_t)n * sizeof(ls_real));
    fit->iteration++;
    return LS_OK;
}

ls_status ls_fit_mesh(ls_fit *fit, ls_real *positions, ls_mesh *mesh)
{
    uint32_t i, k, n;
    if (fit == NULL || positions == NULL || mesh == NULL || fit->x == NULL) return LS_ERR_INVALID;
    n = fit->vertex_count;
    if (optimizes_u(&fit->config)) {
        ls_status st = ls_param_from_differential(&fit->param, fit->params, fit->x);
        if (st != LS_OK) return st;
    }
    for (i = 0; i < n; i++)
        for (k = 0; k < 3; k++)
            positions[3u * i + k] = fit->x[3u * i + k] + (fit->config.use_translation ? fit->params[3u * n + k] : (ls_real)0);
    mesh->positions = positions;
    mesh->triangles = fit->triangles;
    mesh->vertex_count = n;
    mesh->face_count = fit->face_count;
    return LS_OK;
}

ls_status ls_fit_remesh(ls_fit *fit, ls_arena *arena, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info,
                        ls_diag *diag)
{
    ls_arena_mark mark, keep;
    ls_fit_config cfg;
    ls_fit_views views;
    ls_fit_timing timing;
    ls_remesh_params params;
    ls_mesh cur, out, copy;
    ls_real *pos, mean;
    size_t start, new_bytes, copy_bytes;
    uint32_t iteration, remeshes;
    ls_status st;
    if (fit == NULL || arena == NULL || fit->x == NULL || !(h_factor > (ls_real)0) || !(h_factor <= (ls_real)1) ||
        !(lr_factor > (ls_real)0) || !finite_r(lr_factor))
        return LS_ERR_INVALID;
    start = (size_t)(fit->block.base - arena->base);
    if (fit->block.base < arena->base || start + LS_ARENA_ROUND(fit->block.capacity) != arena->bottom) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    pos = (ls_real *)ls_arena_scratch(arena, 3u * (size_t)fit->vertex_count, sizeof(ls_real));
    if (pos == NULL) return LS_ERR_NOMEM;
    st = ls_fit_mesh(fit, pos, &cur);
    if (st == LS_OK) st = ls_remesh_mean_edge(&cur, &mean);
    if (st == LS_OK) {
        ls_remesh_params_default(&params, h_factor * mean);
        st = ls_remesh(&cur, &params, arena, &out, info, diag);
    }
    cfg = fit->config;
    cfg.optim.lr = cfg.optim.lr * lr_factor;
    if (st == LS_OK) st = ls_fit_bytes(&cfg, &fit->views, &out, arena, &new_bytes, diag);
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
    views = fit->views;
    timing = fit->timing;
    iteration = fit->iteration;
    remeshes = fit->remeshes;
    keep.bottom = start;
    keep.top = arena->top;
    ls_arena_restore(arena, keep);
    st = ls_fit_init(fit, &cfg, &views, &copy, arena, diag);
    keep.bottom = arena->bottom;
    keep.top = mark.top;
    ls_arena_restore(arena, keep);
    if (st != LS_OK) return st;
    fit->timing = timing;
    fit->iteration = iteration;
    fit->remeshes = remeshes + 1u;
    return LS_OK;
}
