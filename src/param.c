/* param.c - the large-steps parameterization over an LDL^T factor or CG. */
#include <largesteps/param.h>
#include <largesteps/math.h>
#include <string.h>

static void set_diag(ls_diag *diag, ls_status st, const char *what)
{
    (void)ls_diag_set(diag, st, what, LS_DIAG_NO_INDEX);
}

static int config_ok(const ls_csc *lap, const ls_param_config *cfg)
{
    if (lap == NULL || cfg == NULL || lap->colptr == NULL || lap->nrows != lap->ncols) return 0;
    if (cfg->solver != LS_PARAM_LDLT && cfg->solver != LS_PARAM_CG) return 0;
    if (cfg->k == 0 || cfg->k > LS_CG_MAX_K) return 0;
    if (cfg->solver == LS_PARAM_CG && !(cfg->cg_tol >= (ls_real)0)) return 0;
    return cfg->form == LS_SYSTEM_LAMBDA || cfg->form == LS_SYSTEM_ALPHA;
}

/* The ordering actually used: AUTO and ND need coordinates. */
static uint32_t order_method(const ls_param_config *cfg, const ls_real *xyz)
{
    if (xyz == NULL && (cfg->order == LS_ORDER_AUTO || cfg->order == LS_ORDER_ND)) return LS_ORDER_AMD;
    return cfg->order;
}

/* The allocations made before the analysis: M's values, the step's
 * buffers, the CG warm starts and the solver scratch block. */
static ls_status front_bytes(const ls_csc *lap, const ls_param_config *cfg, ls_size *s, size_t *work)
{
    size_t nk = (size_t)lap->ncols * cfg->k, wb = 0;
    ls_status st;
    ls_size_init(s);
    ls_size_add(s, ls_csc_nnz(lap), sizeof(ls_real));
    if (cfg->solver == LS_PARAM_CG) {
        ls_size_add(s, 2u * nk, sizeof(ls_real)); /* tmp: two buffers */
        ls_size_add(s, nk, sizeof(ls_real));      /* warm_fwd */
        ls_size_add(s, nk, sizeof(ls_real));      /* warm_adj */
        st = ls_cg_bytes(lap->ncols, cfg->k, &wb);
    } else {
        ls_size_add(s, nk, sizeof(ls_real));
        st = ls_size_mul(nk, sizeof(ls_real), &wb);
        wb = LS_ARENA_ROUND(wb);
    }
    if (st != LS_OK) return st;
    ls_size_add(s, wb, 1);
    *work = wb;
    return LS_OK;
}

static ls_status analyze(ls_ldlt *f, const ls_csc *a, uint32_t method, const ls_real *xyz, ls_arena *arena,
                         ls_diag *diag)
{
    if (xyz != NULL) return ls_ldlt_analyze_mesh(a, method, xyz, arena, f, diag);
    return ls_ldlt_analyze(a, method, NULL, arena, f, diag);
}

static ls_status analyze_bytes(const ls_csc *a, uint32_t method, const ls_real *xyz, size_t *bytes)
{
    if (xyz != NULL) return ls_ldlt_analyze_mesh_bytes(a, method, bytes);
    return ls_ldlt_analyze_bytes(a, method, bytes);
}

ls_status ls_param_bytes(const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz, ls_arena *scratch,
                         size_t *bytes)
{
    ls_size s, tail;
    size_t work = 0, ab = 0, fb = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (!config_ok(lap, cfg)) return LS_ERR_INVALID;
    st = front_bytes(lap, cfg, &s, &work);
    if (st != LS_OK) return st;
    if (cfg->solver == LS_PARAM_LDLT) {
        ls_arena_mark mark;
        ls_ldlt f;
        size_t obj;
        uint32_t method = order_method(cfg, xyz);
        if (scratch == NULL) return LS_ERR_INVALID;
        st = analyze_bytes(lap, method, xyz, &ab);
        if (st != LS_OK) return st;
        mark = ls_arena_save(scratch);
        st = analyze(&f, lap, method, xyz, scratch, NULL);
        if (st != LS_OK) return st;
        obj = scratch->bottom - mark.bottom;
        st = ls_ldlt_bytes(&f, &fb);
        ls_arena_restore(scratch, mark);
        if (st != LS_OK) return st;
        /* the analysis' peak, or its object plus the numeric factor */
        ls_size_init(&tail);
        ls_size_add(&tail, obj, 1);
        ls_size_add(&tail, fb, 1);
        if (ab > tail.bytes) tail.bytes = ab;
        ls_size_add_size(&s, &tail);
    }
    return ls_size_get(&s, bytes);
}

ls_status ls_param_init(ls_param *p, const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz,
                        ls_arena *arena, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_param q;
    ls_size s;
    size_t work = 0, nk;
    unsigned char *block;
    ls_status st;
    if (p == NULL || arena == NULL || !config_ok(lap, cfg)) {
        set_diag(diag, LS_ERR_INVALID, "NULL argument or configuration out of range");
        return LS_ERR_INVALID;
    }
    st = front_bytes(lap, cfg, &s, &work);
    if (st != LS_OK) return st;
    memset(&q, 0, sizeof q);
    q.lap = *lap;
    q.n = lap->ncols;
    q.k = cfg->k;
    q.solver = cfg->solver;
    q.form = cfg->form;
    q.weight = cfg->weight;
    q.cg.max_iter = cfg->cg_max_iter;
    q.cg.tol = cfg->cg_tol;
    nk = (size_t)q.n * q.k;
    mark = ls_arena_save(arena);
    st = ls_laplacian_system(lap, cfg->form, cfg->weight, arena, &q.m, diag);
    if (st != LS_OK) return st;
    q.identity = cfg->weight == (ls_real)0;
    q.tmp = (ls_real *)ls_arena_alloc(arena, cfg->solver == LS_PARAM_CG ? 2u * nk : nk, sizeof(ls_real));
    if (cfg->solver == LS_PARAM_CG) {
        q.warm_fwd = (ls_real *)ls_arena_alloc_zero(arena, nk, sizeof(ls_real));
        q.warm_adj = (ls_real *)ls_arena_alloc_zero(arena, nk, sizeof(ls_real));
        if (q.warm_fwd == NULL || q.warm_adj == NULL) goto nomem;
    }
    block = (unsigned char *)ls_arena_alloc(arena, work, 1);
    if (q.tmp == NULL || block == NULL) goto nomem;
    (void)ls_arena_init(&q.work, block, work);
    if (cfg->solver == LS_PARAM_LDLT) {
        st = analyze(&q.f, &q.m, order_method(cfg, xyz), xyz, arena, diag);
        if (st == LS_OK) st = ls_ldlt_factor(&q.f, &q.m, arena, diag);
        if (st != LS_OK) {
            ls_arena_restore(arena, mark);
            return st;
        }
    }
    *p = q;
    return LS_OK;
nomem:
    ls_arena_restore(arena, mark);
    set_diag(diag, LS_ERR_NOMEM, "arena too small for the parameterization");
    return LS_ERR_NOMEM;
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
    return ls_csc_matvec_sym(&p->m, p->k, x, u);
}

/* x = M^{-1} b; CG starts from and updates `warm` (n k). */
static ls_status solve(ls_param *p, const ls_real *b, ls_real *x, ls_real *warm)
{
    size_t nk = (size_t)p->n * p->k;
    ls_status st;
    if (!finite_all(b, nk)) return LS_ERR_NONFINITE;
    if (p->identity) {
        if (x != b) memmove(x, b, nk * sizeof(ls_real));
        return LS_OK;
    }
    if (p->solver == LS_PARAM_LDLT) {
        if (x != b) memmove(x, b, nk * sizeof(ls_real));
        return ls_ldlt_solve(&p->f, p->k, x, &p->work);
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
        if (p->solver == LS_PARAM_LDLT) {
            st = ls_ldlt_solve(&p->f, p->k, d, &p->work);
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
    if (p == NULL || p->m.values == NULL) return LS_ERR_INVALID;
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
    return LS_OK;
}
