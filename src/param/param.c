/* param.c - the large-steps parameterization over an LDL^T factor or CG. */
#include <largesteps/param.h>
#include <largesteps/math.h>
#include <string.h>

#define LS_PARAM_MAX_WORKERS 4096u

/* 1 when the LDL^T's solves are split over workers (a plan is built). */
static int splits(const ls_param_config *cfg)
{
    return cfg->workers > 1u && cfg->k == 3u;
}

static void set_diag(ls_diag *diag, ls_status st, const char *what)
{
    (void)ls_diag_set(diag, st, what, LS_DIAG_NO_INDEX);
}

/* The solver a configuration asks for: AUTO is the transform solver on a
 * grid and the LDL^T on a mesh; UINT32_MAX when out of range. */
static uint32_t solver_of(const ls_param_config *cfg, int grid)
{
    if (cfg->solver == LS_PARAM_AUTO) return grid ? LS_PARAM_GRID : LS_PARAM_LDLT;
    if (cfg->solver == LS_PARAM_GRID && !grid) return UINT32_MAX;
    if (cfg->solver > LS_PARAM_GRID) return UINT32_MAX;
    return cfg->solver;
}

/* NULL when cfg is in range, else what is wrong: the field and its allowed
 * range (*value: the offending value). */
static const char *config_error(const ls_param_config *cfg, int grid, ls_real *value)
{
    uint32_t solver = solver_of(cfg, grid);
    if (solver == UINT32_MAX) {
        *value = (ls_real)cfg->solver;
        return grid ? "cfg->solver: allowed LS_PARAM_LDLT, LS_PARAM_CG, LS_PARAM_AUTO or LS_PARAM_GRID"
                    : "cfg->solver: allowed LS_PARAM_LDLT, LS_PARAM_CG or LS_PARAM_AUTO (LS_PARAM_GRID is for "
                      "grids)";
    }
    if (cfg->k == 0 || cfg->k > LS_CG_MAX_K) {
        *value = (ls_real)cfg->k;
        return "cfg->k: the vectors' columns, allowed 1 .. LS_CG_MAX_K (4); 3 for x, y, z";
    }
    if (cfg->form != LS_SYSTEM_LAMBDA && cfg->form != LS_SYSTEM_ALPHA) {
        *value = (ls_real)cfg->form;
        return "cfg->form: allowed LS_SYSTEM_LAMBDA or LS_SYSTEM_ALPHA";
    }
    *value = cfg->weight;
    if (cfg->form == LS_SYSTEM_LAMBDA && !(LS_RISFINITE(cfg->weight) && cfg->weight >= (ls_real)0))
        return "cfg->weight: lambda must be finite and >= 0 (the paper: 19)";
    if (cfg->form == LS_SYSTEM_ALPHA && !(cfg->weight >= (ls_real)0 && cfg->weight < (ls_real)1))
        return "cfg->weight: alpha must be in [0, 1) (the paper: 0.95)";
    if (cfg->workers > LS_PARAM_MAX_WORKERS) {
        *value = (ls_real)cfg->workers;
        return "cfg->workers: allowed 0 .. 4096 (0 and 1: the solves on the calling thread)";
    }
    if (solver == LS_PARAM_CG && cfg->cg_max_iter == 0) {
        *value = (ls_real)0;
        return "cfg->cg_max_iter: 0 with the CG solver would not solve; allowed >= 1 (e.g. 1000)";
    }
    if (solver == LS_PARAM_CG && !(cfg->cg_tol >= (ls_real)0)) {
        *value = cfg->cg_tol;
        return "cfg->cg_tol: the CG's relative tolerance, allowed >= 0 (e.g. 1e-6)";
    }
    return NULL;
}

static int config_valid(const ls_param_config *cfg, int grid)
{
    ls_real v;
    return config_error(cfg, grid, &v) == NULL;
}

static int config_ok(const ls_csc *lap, const ls_param_config *cfg)
{
    if (lap == NULL || cfg == NULL || lap->colptr == NULL || lap->nrows != lap->ncols) return 0;
    return config_valid(cfg, 0);
}

/* Names the invalid argument of an init call in *diag; returns LS_ERR_INVALID. */
static ls_status invalid(ls_diag *diag, const char *what, const ls_param_config *cfg, int grid)
{
    ls_real v = (ls_real)0;
    const char *bad = cfg != NULL ? config_error(cfg, grid, &v) : NULL;
    if (what == NULL && bad != NULL) {
        (void)ls_diag_set(diag, LS_ERR_INVALID, bad, LS_DIAG_NO_INDEX);
        if (diag != NULL) {
            diag->has_value = 1;
            diag->value = v;
        }
        return LS_ERR_INVALID;
    }
    (void)ls_diag_set(diag, LS_ERR_INVALID, what != NULL ? what : "cfg is NULL", LS_DIAG_NO_INDEX);
    return LS_ERR_INVALID;
}

void ls_param_config_default(ls_param_config *cfg)
{
    if (cfg == NULL) return;
    memset(cfg, 0, sizeof *cfg);
    cfg->solver = LS_PARAM_LDLT;
    cfg->form = LS_SYSTEM_LAMBDA;
    cfg->weight = (ls_real)19;
    cfg->k = 3;
    cfg->order = LS_ORDER_AUTO;
    cfg->cg_max_iter = 1000;
    cfg->cg_tol = (ls_real)1e-6;
}

/* The ordering actually used: AUTO and ND need coordinates. */
static int needs_coords(uint32_t order)
{
    return order == LS_ORDER_AUTO || order == LS_ORDER_ND;
}

static uint32_t order_method(const ls_param_config *cfg, const ls_real *xyz)
{
    if (xyz == NULL && needs_coords(cfg->order)) return LS_ORDER_AMD;
    return cfg->order;
}

/* The allocations made before the analysis: M's values, the step's
 * buffers, the CG warm starts and the solver scratch block (added to *s). */
static ls_status front_bytes(uint32_t n, size_t nnz, const ls_param_config *cfg, ls_size *s, size_t *work)
{
    size_t nk = (size_t)n * cfg->k, wb = 0;
    ls_status st;
    ls_size_add(s, nnz, sizeof(ls_real));
    if (solver_of(cfg, 0) == LS_PARAM_CG) {
        ls_size_add(s, 2u * nk, sizeof(ls_real)); /* tmp: two buffers */
        ls_size_add(s, nk, sizeof(ls_real));      /* warm_fwd */
        ls_size_add(s, nk, sizeof(ls_real));      /* warm_adj */
        st = ls_cg_bytes(n, cfg->k, &wb);
    } else {
        ls_size_add(s, nk, sizeof(ls_real));
        st = ls_ldlt_solve_bytes_n(n, cfg->k, &wb);
        wb = LS_ARENA_ROUND(wb);
    }
    if (st != LS_OK) return st;
    ls_size_add(s, wb, 1);
    *work = wb;
    return LS_OK;
}

/* Where the ordering's coordinates come from: the caller's vertex positions
 * (a mesh, may be NULL) or, for a width x height grid (width > 0), the
 * texel centres (x, y, 0), made in scratch for the analysis only. */
typedef struct coord_src {
    const ls_real *xyz;
    uint32_t width, height;
} coord_src;

static uint32_t coords_method(const ls_param_config *cfg, const coord_src *c)
{
    return c->width != 0 ? cfg->order : order_method(cfg, c->xyz);
}

/* 1 when the analysis gets coordinates. */
static int has_coords(const coord_src *c, uint32_t method)
{
    return c->xyz != NULL || (c->width != 0 && needs_coords(method));
}

/* The grid's texel coordinates, 3 n reals from the arena's top. */
static ls_real *grid_coords(const coord_src *c, ls_arena *arena)
{
    size_t n = (size_t)c->width * c->height, i;
    ls_real *xyz = (ls_real *)ls_arena_scratch(arena, 3u * n, sizeof(ls_real));
    if (xyz == NULL) return NULL;
    for (i = 0; i < n; i++) {
        size_t row = i / c->width; /* exact integer row */
        xyz[3u * i] = (ls_real)(i % c->width);
        xyz[3u * i + 1u] = (ls_real)row;
        xyz[3u * i + 2u] = (ls_real)0;
    }
    return xyz;
}

static ls_status analyze(ls_ldlt *f, const ls_csc *a, uint32_t method, const ls_real *xyz, ls_arena *arena,
                         ls_diag *diag)
{
    if (xyz != NULL) return ls_ldlt_analyze_mesh(a, method, xyz, arena, f, diag);
    return ls_ldlt_analyze(a, method, NULL, arena, f, diag);
}

/* The analysis with coordinates from c: grid coordinates live in the top of
 * the arena during the analysis only. */
static ls_status analyze_from(ls_ldlt *f, const ls_csc *a, const ls_param_config *cfg, const coord_src *c,
                              ls_arena *arena, ls_diag *diag)
{
    uint32_t method = coords_method(cfg, c);
    ls_arena_mark mark = ls_arena_save(arena);
    const ls_real *xyz = c->xyz;
    ls_status st;
    if (c->width != 0 && needs_coords(method)) {
        xyz = grid_coords(c, arena);
        if (xyz == NULL) {
            set_diag(diag, LS_ERR_NOMEM, "arena too small for the grid's ordering coordinates");
            return LS_ERR_NOMEM;
        }
    }
    st = analyze(f, a, method, xyz, arena, diag);
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    return st;
}

/* The LDL^T's part of the bytes after the analysis: max(the analysis' peak,
 * its object + the numeric factor + the split's plan and its build). */
static ls_status factor_tail(uint32_t n, const ls_param_config *cfg, size_t object, size_t factor,
                             const ls_size *peak, ls_size *tail)
{
    size_t split_object = 0, split_peak = 0;
    if (splits(cfg)) {
        ls_status st = ls_ldlt_split_bytes_n(n, cfg->workers, &split_object, &split_peak);
        if (st != LS_OK) return st;
    }
    ls_size_init(tail);
    ls_size_add(tail, object, 1);
    ls_size_add(tail, factor, 1);
    if (splits(cfg)) ls_size_add(tail, 1, sizeof(ls_param_split));
    ls_size_add(tail, split_peak, 1);
    ls_size_max(tail, peak);
    return LS_OK;
}

/* The LDL^T's part of the bytes: max(coordinates + the analysis' peak, its
 * object + the numeric factor), measured by an analysis in scratch. */
static ls_status ldlt_tail(const ls_csc *lap, const ls_param_config *cfg, const coord_src *c, ls_arena *scratch,
                           ls_size *tail, uint32_t *l_nnz)
{
    ls_arena_mark mark;
    ls_ldlt f;
    ls_size peak;
    size_t ab = 0, fb = 0, obj;
    uint32_t method = coords_method(cfg, c);
    ls_status st;
    if (scratch == NULL) return LS_ERR_INVALID;
    st = has_coords(c, method) ? ls_ldlt_analyze_mesh_bytes(lap, method, &ab) : ls_ldlt_analyze_bytes(lap, method, &ab);
    if (st != LS_OK) return st;
    ls_size_init(&peak);
    if (c->xyz == NULL && has_coords(c, method)) ls_size_add(&peak, 3u * (size_t)c->width * c->height, sizeof(ls_real));
    ls_size_add(&peak, ab, 1);
    mark = ls_arena_save(scratch);
    st = analyze_from(&f, lap, cfg, c, scratch, NULL);
    if (st != LS_OK) return st;
    obj = scratch->bottom - mark.bottom;
    *l_nnz = f.l_nnz;
    st = ls_ldlt_bytes(&f, &fb);
    ls_arena_restore(scratch, mark);
    if (st != LS_OK) return st;
    return factor_tail(lap->ncols, cfg, obj, fb, &peak, tail);
}

/* Adds the bytes of build() for the sparse solvers to *s. */
static ls_status sparse_bytes(const ls_csc *lap, const ls_param_config *cfg, const coord_src *c, ls_arena *scratch,
                              ls_size *s, uint32_t *l_nnz)
{
    size_t work = 0;
    ls_status st = front_bytes(lap->ncols, ls_csc_nnz(lap), cfg, s, &work);
    if (st != LS_OK) return st;
    if (solver_of(cfg, 0) == LS_PARAM_LDLT) {
        ls_size tail;
        st = ldlt_tail(lap, cfg, c, scratch, &tail, l_nnz);
        if (st != LS_OK) return st;
        ls_size_add_size(s, &tail);
    }
    return LS_OK;
}

ls_status ls_param_bytes_fill(const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz, ls_arena *scratch,
                              size_t *bytes, uint32_t *factor_nnz)
{
    coord_src c;
    ls_size s;
    uint32_t l_nnz = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (!config_ok(lap, cfg)) return LS_ERR_INVALID;
    c.xyz = xyz;
    c.width = c.height = 0;
    ls_size_init(&s);
    st = sparse_bytes(lap, cfg, &c, scratch, &s, &l_nnz);
    if (st != LS_OK) return st;
    if (factor_nnz != NULL) *factor_nnz = l_nnz;
    return ls_size_get(&s, bytes);
}

ls_status ls_param_bytes(const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz, ls_arena *scratch,
                         size_t *bytes)
{
    return ls_param_bytes_fill(lap, cfg, xyz, scratch, bytes, NULL);
}

ls_status ls_param_bytes_bound(uint32_t n, uint32_t nnz, uint32_t factor_nnz, const ls_param_config *cfg,
                               int with_coords, size_t *bytes)
{
    ls_size s;
    size_t work = 0, ab = 0, object = 0, factor = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (cfg == NULL || !config_valid(cfg, 0)) return LS_ERR_INVALID;
    ls_size_init(&s);
    st = front_bytes(n, nnz, cfg, &s, &work);
    if (st == LS_OK && solver_of(cfg, 0) == LS_PARAM_LDLT) {
        /* as ldlt_tail: max(the analysis' peak, its object + the factor); the
         * upper triangle has at most every stored entry */
        ls_size tail, peak;
        uint32_t method = with_coords ? cfg->order : order_method(cfg, NULL);
        st = ls_ldlt_bytes_bound(n, nnz, nnz, factor_nnz, method, &ab, &object, &factor);
        ls_size_init(&peak);
        ls_size_add(&peak, ab, 1);
        if (st == LS_OK) st = factor_tail(n, cfg, object, factor, &peak, &tail);
        if (st == LS_OK) ls_size_add_size(&s, &tail);
    }
    if (st != LS_OK) return st;
    return ls_size_get(&s, bytes);
}

/* Builds the sparse solvers' part of *q (q->solver resolved, the other
 * fields of q zero) from the arena's bottom; the caller restores the arena
 * on failure. */
static ls_status build(ls_param *q, const ls_csc *lap, const ls_param_config *cfg, const coord_src *c,
                       ls_arena *arena, ls_diag *diag)
{
    ls_size s;
    size_t work = 0, nk;
    unsigned char *block;
    ls_status st;
    ls_size_init(&s);
    st = front_bytes(lap->ncols, ls_csc_nnz(lap), cfg, &s, &work);
    if (st != LS_OK) return st;
    q->lap = *lap;
    q->n = lap->ncols;
    q->k = cfg->k;
    q->form = cfg->form;
    q->weight = cfg->weight;
    q->cg.max_iter = cfg->cg_max_iter;
    q->cg.tol = cfg->cg_tol;
    nk = (size_t)q->n * q->k;
    st = ls_laplacian_system(lap, cfg->form, cfg->weight, arena, &q->m, diag);
    if (st != LS_OK) return st;
    q->identity = cfg->weight == (ls_real)0;
    q->tmp = (ls_real *)ls_arena_alloc(arena, q->solver == LS_PARAM_CG ? 2u * nk : nk, sizeof(ls_real));
    if (q->solver == LS_PARAM_CG) {
        q->warm_fwd = (ls_real *)ls_arena_alloc_zero(arena, nk, sizeof(ls_real));
        q->warm_adj = (ls_real *)ls_arena_alloc_zero(arena, nk, sizeof(ls_real));
        if (q->warm_fwd == NULL || q->warm_adj == NULL) goto nomem;
    }
    block = (unsigned char *)ls_arena_alloc(arena, work, 1);
    if (q->tmp == NULL || block == NULL) goto nomem;
    (void)ls_arena_init(&q->work, block, work);
    if (q->solver == LS_PARAM_LDLT) {
        st = analyze_from(&q->f, &q->m, cfg, c, arena, diag);
        if (st == LS_OK) st = ls_ldlt_factor(&q->f, &q->m, arena, diag);
        if (st == LS_OK && splits(cfg)) {
            q->split = (ls_param_split *)ls_arena_alloc(arena, 1, sizeof(ls_param_split));
            if (q->split == NULL) goto nomem;
            memset(&q->split->parallel, 0, sizeof q->split->parallel);
            if (cfg->parallel != NULL) q->split->parallel = *cfg->parallel;
            st = ls_ldlt_split_init(&q->split->plan, &q->f, cfg->workers, arena);
            if (st == LS_ERR_NOMEM) goto nomem;
        }
    }
    return st;
nomem:
    set_diag(diag, LS_ERR_NOMEM, "arena too small for the parameterization");
    return LS_ERR_NOMEM;
}

ls_status ls_param_init(ls_param *p, const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz,
                        ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    coord_src c;
    ls_param q;
    ls_status st;
    if (p == NULL || arena == NULL || cfg == NULL) return invalid(diag, "p, cfg or arena is NULL", cfg, 0);
    if (lap == NULL || lap->colptr == NULL || lap->nrows != lap->ncols)
        return invalid(diag, "lap: NULL or not a square matrix", cfg, 0);
    if (!config_valid(cfg, 0)) return invalid(diag, NULL, cfg, 0);
    memset(&q, 0, sizeof q);
    q.solver = solver_of(cfg, 0);
    c.xyz = xyz;
    c.width = c.height = 0;
    mark = ls_arena_save(arena);
    st = build(&q, lap, cfg, &c, arena, diag);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    *p = q;
    ls_diag_clear(diag);
    return LS_OK;
}

/* The Laplacian of ls_param_init_mesh. */
static ls_status mesh_laplacian(const ls_mesh *mesh, ls_arena *arena, ls_csc *lap, ls_diag *diag)
{
    return ls_laplacian_uniform(mesh, LS_LAP_UPPER, arena, lap, diag);
}

ls_status ls_param_mesh_bytes(const ls_mesh *mesh, const ls_param_config *cfg, ls_arena *scratch, size_t *bytes)
{
    ls_arena_mark mark;
    ls_size total, lap_peak;
    ls_csc lap;
    size_t old_peak, start, pb = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (mesh == NULL || scratch == NULL || cfg == NULL || !config_valid(cfg, 0)) return LS_ERR_INVALID;
    mark = ls_arena_save(scratch);
    old_peak = scratch->peak;
    start = ls_arena_used(scratch);
    scratch->peak = start;
    /* the Laplacian's build, measured: its peak, then its matrix below the rest */
    st = mesh_laplacian(mesh, scratch, &lap, NULL);
    if (st == LS_OK) {
        size_t lap_bytes = scratch->bottom - mark.bottom;
        ls_size_init(&lap_peak);
        ls_size_add(&lap_peak, scratch->peak - start, 1);
        st = ls_param_bytes(&lap, cfg, mesh->positions, scratch, &pb);
        ls_size_init(&total);
        ls_size_add(&total, lap_bytes, 1);
        ls_size_add(&total, pb, 1);
        ls_size_max(&total, &lap_peak);
        if (st == LS_OK) st = ls_size_get(&total, bytes);
    }
    ls_arena_restore(scratch, mark);
    if (scratch->peak < old_peak) scratch->peak = old_peak;
    return st;
}

ls_status ls_param_init_mesh(ls_param *p, const ls_mesh *mesh, const ls_param_config *cfg, ls_arena *arena,
                             ls_diag *diag)
{
    ls_arena_mark mark;
    ls_csc lap;
    ls_param q;
    ls_status st;
    if (p == NULL || mesh == NULL || arena == NULL || cfg == NULL)
        return invalid(diag, "p, mesh, cfg or arena is NULL", cfg, 0);
    if (!config_valid(cfg, 0)) return invalid(diag, NULL, cfg, 0);
    mark = ls_arena_save(arena);
    st = mesh_laplacian(mesh, arena, &lap, diag);
    if (st == LS_ERR_NOMEM) set_diag(diag, LS_ERR_NOMEM, "arena too small for the parameterization's Laplacian");
    if (st == LS_OK) st = ls_param_init(&q, &lap, cfg, mesh->positions, arena, diag);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    *p = q;
    return LS_OK;
}

/* ---- texture grids ------------------------------------------------------ */

static int grid_ok(const ls_grid_shape *shape, const ls_param_config *cfg)
{
    return shape != NULL && cfg != NULL && shape->width != 0 && shape->height != 0 && config_valid(cfg, 1);
}

/* The sparse solvers on the grid: the bytes of the owned Laplacian and of
 * build(), whose analysis runs in scratch. */
static ls_status grid_sparse_bytes(const ls_grid_shape *shape, const ls_param_config *cfg, ls_arena *scratch,
                                   ls_size *s)
{
    ls_arena_mark mark;
    ls_csc lap;
    coord_src c;
    size_t b = 0;
    uint32_t l_nnz = 0;
    ls_status st = ls_laplacian_grid_wrap_bytes(shape->width, shape->height, shape->wrap_u, LS_LAP_UPPER, &b);
    if (st != LS_OK) return st;
    if (scratch == NULL) return LS_ERR_INVALID;
    ls_size_add(s, b, 1);
    mark = ls_arena_save(scratch);
    st = ls_laplacian_grid_wrap(shape->width, shape->height, shape->wrap_u, LS_LAP_UPPER, scratch, &lap);
    c.xyz = NULL;
    c.width = shape->width;
    c.height = shape->height;
    if (st == LS_OK) st = sparse_bytes(&lap, cfg, &c, scratch, s, &l_nnz);
    ls_arena_restore(scratch, mark);
    return st;
}

ls_status ls_param_grid_bytes(const ls_grid_shape *shape, const ls_param_config *cfg, ls_arena *scratch,
                              size_t *bytes)
{
    ls_size s;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (!grid_ok(shape, cfg)) return LS_ERR_INVALID;
    ls_size_init(&s);
    if (solver_of(cfg, 1) == LS_PARAM_GRID) {
        size_t b = 0;
        st = ls_grid_solver_bytes(shape->width, shape->height, shape->wrap_u, cfg->k, &b);
        if (st != LS_OK) return st;
        ls_size_add(&s, b, 1);
        ls_size_add(&s, (size_t)shape->width * shape->height * cfg->k, sizeof(ls_real)); /* tmp */
    } else {
        st = grid_sparse_bytes(shape, cfg, scratch, &s);
        if (st != LS_OK) return st;
    }
    return ls_size_get(&s, bytes);
}

/* The transform solver's part of *q: its tables, the weight and the step's
 * buffer. */
static ls_status grid_build(ls_param *q, const ls_grid_shape *shape, const ls_param_config *cfg, ls_arena *arena,
                            ls_diag *diag)
{
    ls_status st = ls_grid_solver_init(&q->gs, shape->width, shape->height, shape->wrap_u, cfg->k, arena);
    if (st == LS_OK) st = ls_grid_solver_set_weight(&q->gs, cfg->form, cfg->weight, diag);
    if (st != LS_OK) return st;
    q->n = shape->width * shape->height;
    q->k = cfg->k;
    q->form = cfg->form;
    q->weight = cfg->weight;
    q->identity = cfg->weight == (ls_real)0;
    q->tmp = (ls_real *)ls_arena_alloc(arena, (size_t)q->n * q->k, sizeof(ls_real));
    return q->tmp != NULL ? LS_OK : LS_ERR_NOMEM;
}

ls_status ls_param_grid_init(ls_param *p, const ls_grid_shape *shape, const ls_param_config *cfg, ls_arena *arena,
                             ls_diag *diag)
{
    ls_arena_mark mark;
    ls_param q;
    ls_status st;
    if (p == NULL || arena == NULL || cfg == NULL) return invalid(diag, "p, cfg or arena is NULL", cfg, 1);
    if (shape == NULL || shape->width == 0 || shape->height == 0)
        return invalid(diag, "shape: NULL, or a width or height of 0 (allowed >= 1)", cfg, 1);
    if (!config_valid(cfg, 1)) return invalid(diag, NULL, cfg, 1);
    memset(&q, 0, sizeof q);
    q.solver = solver_of(cfg, 1);
    q.grid = 1;
    q.width = shape->width;
    q.height = shape->height;
    q.wrap_u = shape->wrap_u != 0 && shape->width >= 3u;
    mark = ls_arena_save(arena);
    if (q.solver == LS_PARAM_GRID) {
        st = grid_build(&q, shape, cfg, arena, diag);
    } else {
        ls_csc lap;
        coord_src c;
        c.xyz = NULL;
        c.width = shape->width;
        c.height = shape->height;
        st = ls_laplacian_grid_wrap(shape->width, shape->height, shape->wrap_u, LS_LAP_UPPER, arena, &lap);
        if (st == LS_OK) st = build(&q, &lap, cfg, &c, arena, diag);
    }
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        if (st == LS_ERR_NOMEM) set_diag(diag, LS_ERR_NOMEM, "arena too small for the parameterization");
        return st;
    }
    *p = q;
    ls_diag_clear(diag);
    return LS_OK;
}

static int finite_all(const ls_real *v, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        if (!LS_RISFINITE(v[i])) return 0;
    return 1;
}

ls_status ls_param_to_differential(const ls_param *p, const ls_real *x, ls_real *u)
{
    if (p == NULL || x == NULL || u == NULL) return LS_ERR_INVALID;
    if (p->identity) {
        if (u != x) memmove(u, x, (size_t)p->n * p->k * sizeof(ls_real));
        return LS_OK;
    }
    if (p->solver == LS_PARAM_GRID) return ls_grid_solver_apply(&p->gs, x, u);
    return ls_csc_matvec_sym(&p->m, p->k, x, u);
}

/* x = M^{-1} x with the factor, split over the workers when planned. */
static ls_status ldlt_solve(ls_param *p, ls_real *x)
{
    if (p->split != NULL) return ls_ldlt_solve_split(&p->f, &p->split->plan, &p->split->parallel, x, &p->work);
    return ls_ldlt_solve(&p->f, p->k, x, &p->work);
}

/* x = M^{-1} b; CG starts from and updates `warm` (n k). */
static ls_status solve(ls_param *p, const ls_real *b, ls_real *x, ls_real *warm)
{
    size_t nk = (size_t)p->n * p->k;
    ls_status st;
    if (p->solver == LS_PARAM_GRID) return ls_grid_solver_solve(&p->gs, b, x); /* it checks b itself */
    if (!finite_all(b, nk)) return LS_ERR_NONFINITE;
    if (p->identity) {
        if (x != b) memmove(x, b, nk * sizeof(ls_real));
        return LS_OK;
    }
    if (p->solver == LS_PARAM_LDLT) {
        if (x != b) memmove(x, b, nk * sizeof(ls_real));
        return ldlt_solve(p, x);
    }
    st = ls_cg_solve(&p->m, p->k, b, warm, &p->work, &p->cg);
    if (st != LS_OK) {
        memset(warm, 0, nk * sizeof(ls_real)); /* no poisoned warm start */
        return st;
    }
    memmove(x, warm, nk * sizeof(ls_real));
    return LS_OK;
}

ls_status ls_param_from_differential(ls_param *p, const ls_real *u, ls_real *x)
{
    if (p == NULL || u == NULL || x == NULL) return LS_ERR_INVALID;
    return solve(p, u, x, p->warm_fwd);
}

ls_status ls_param_adjoint(ls_param *p, const ls_real *gx, ls_real *gu)
{
    if (p == NULL || gx == NULL || gu == NULL) return LS_ERR_INVALID;
    return solve(p, gx, gu, p->warm_adj);
}

ls_status ls_param_adjoint2(ls_param *p, const ls_real *gx, ls_real *gu, ls_real *gu2)
{
    ls_status st;
    if (p == NULL || gx == NULL || gu == NULL || gu2 == NULL || gu2 == gu || gu2 == gx) return LS_ERR_INVALID;
    if (p->solver == LS_PARAM_GRID && !p->identity) return ls_grid_solver_solve2(&p->gs, gx, gu, gu2);
    st = solve(p, gx, gu, p->warm_adj);
    if (st != LS_OK) return st;
    /* the second solve cold (the adjoint's warm start stays its own): 0 + M^{-1} gu */
    memset(gu2, 0, (size_t)p->n * p->k * sizeof(ls_real));
    return ls_param_step(p, gu2, gu, (ls_real)-1, 1u);
}

ls_status ls_param_step(ls_param *p, ls_real *x, const ls_real *g, ls_real eta, uint32_t power)
{
    size_t nk, i;
    ls_real *d;
    uint32_t r;
    if (p == NULL || x == NULL || g == NULL || power == 0 || !LS_RISFINITE(eta)) return LS_ERR_INVALID;
    nk = (size_t)p->n * p->k;
    if (!finite_all(g, nk)) return LS_ERR_NONFINITE;
    d = p->tmp;
    if (p->identity) {
        for (i = 0; i < nk; i++) x[i] -= eta * g[i];
        return LS_OK;
    }
    memcpy(d, g, nk * sizeof(ls_real));
    for (r = 0; r < power; r++) {
        ls_status st;
        if (p->solver == LS_PARAM_GRID) {
            st = ls_grid_solver_solve(&p->gs, d, d);
        } else if (p->solver == LS_PARAM_LDLT) {
            st = ldlt_solve(p, d);
        } else {
            ls_real *next = d == p->tmp ? p->tmp + nk : p->tmp;
            memset(next, 0, nk * sizeof(ls_real));
            st = ls_cg_solve(&p->m, p->k, d, next, &p->work, &p->cg);
            d = next;
        }
        if (st != LS_OK) return st;
    }
    for (i = 0; i < nk; i++) x[i] -= eta * d[i];
    return LS_OK;
}

ls_status ls_param_set_weight(ls_param *p, ls_real weight, ls_diag *diag)
{
    ls_status st;
    if (p == NULL) return invalid(diag, "p is NULL", NULL, 0);
    if (p->solver == LS_PARAM_GRID) {
        st = ls_grid_solver_set_weight(&p->gs, p->form, weight, diag);
        if (st != LS_OK) return st;
        p->weight = weight;
        p->identity = weight == (ls_real)0;
        ls_diag_clear(diag);
        return LS_OK;
    }
    if (p->m.values == NULL) return invalid(diag, "p: not initialised (ls_param_init)", NULL, 0);
    st = ls_laplacian_system_update(&p->lap, p->form, weight, &p->m, diag);
    if (st != LS_OK) return st;
    if (p->solver == LS_PARAM_LDLT) {
        st = ls_ldlt_refactor(&p->f, &p->m, diag);
        if (st != LS_OK) {
            /* back to the previous weight, which factored before */
            (void)ls_laplacian_system_update(&p->lap, p->form, p->weight, &p->m, NULL);
            (void)ls_ldlt_refactor(&p->f, &p->m, NULL);
            return st;
        }
    }
    p->weight = weight;
    p->identity = weight == (ls_real)0;
    ls_diag_clear(diag);
    return LS_OK;
}
