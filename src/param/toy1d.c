/* toy1d.c - the paper's 1D toy: naive, regularized and large-steps descent on
 * 32 points with gradients at the two ends only. */
#include <largesteps/toy1d.h>
#include <largesteps/laplacian.h>
#include <largesteps/param.h>
#include <string.h>

static const ls_toy1d_method methods[LS_TOY1D_METHODS] = {
    {"naive", LS_TOY1D_NAIVE, 0u, (ls_real)0, (ls_real)0.5},
    {"laplacian-reg", LS_TOY1D_REG, 0u, (ls_real)0.05, (ls_real)0.5},
    {"large-p1-l1", LS_TOY1D_LARGE, 1u, (ls_real)1, (ls_real)1.5},
    {"large-p1-l19", LS_TOY1D_LARGE, 1u, (ls_real)19, (ls_real)4},
    {"large-p1-l99", LS_TOY1D_LARGE, 1u, (ls_real)99, (ls_real)8},
    {"large-p2-l1", LS_TOY1D_LARGE, 2u, (ls_real)1, (ls_real)2},
    {"large-p2-l19", LS_TOY1D_LARGE, 2u, (ls_real)19, (ls_real)8},
    {"large-p2-l99", LS_TOY1D_LARGE, 2u, (ls_real)99, (ls_real)16},
};

ls_status ls_toy1d_method_get(uint32_t index, ls_toy1d_method *out)
{
    if (out == NULL || index >= LS_TOY1D_METHODS) return LS_ERR_INVALID;
    *out = methods[index];
    return LS_OK;
}

void ls_toy1d_points(ls_real *start, ls_real *target)
{
    uint32_t i;
    for (i = 0; i < LS_TOY1D_N; i++) {
        ls_real s = (ls_real)(2u * i) / (ls_real)(LS_TOY1D_N - 1u) - (ls_real)1;
        if (start != NULL) start[i] = s;
        if (target != NULL) target[i] = s * (ls_real)0.5;
    }
}

static void config(const ls_toy1d_method *m, ls_param_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    cfg->solver = LS_PARAM_LDLT;
    cfg->form = LS_SYSTEM_LAMBDA;
    cfg->weight = m->lambda;
    cfg->k = 1;
    cfg->order = LS_ORDER_NATURAL;
}

ls_status ls_toy1d_bytes(uint32_t index, ls_arena *scratch, size_t *bytes)
{
    ls_size s;
    size_t b = 0;
    ls_status st;
    if (bytes == NULL || index >= LS_TOY1D_METHODS) return LS_ERR_INVALID;
    *bytes = 0;
    ls_size_init(&s);
    st = ls_laplacian_grid_bytes(LS_TOY1D_N, 1, LS_LAP_UPPER, &b);
    if (st != LS_OK) return st;
    ls_size_add(&s, b, 1);
    ls_size_add(&s, LS_TOY1D_N, sizeof(ls_real)); /* x */
    ls_size_add(&s, LS_TOY1D_N, sizeof(ls_real)); /* g */
    ls_size_add(&s, LS_TOY1D_N, sizeof(ls_real)); /* target */
    ls_size_add(&s, LS_TOY1D_N, sizeof(ls_real)); /* the regularizer's gradient */
    if (methods[index].kind == LS_TOY1D_LARGE) {
        ls_param_config cfg;
        ls_csc lap;
        ls_arena_mark mark;
        if (scratch == NULL) return LS_ERR_INVALID;
        config(&methods[index], &cfg);
        mark = ls_arena_save(scratch);
        st = ls_laplacian_grid(LS_TOY1D_N, 1, LS_LAP_UPPER, scratch, &lap);
        if (st == LS_OK) st = ls_param_bytes(&lap, &cfg, NULL, scratch, &b);
        ls_arena_restore(scratch, mark);
        if (st != LS_OK) return st;
        ls_size_add(&s, b, 1);
    }
    return ls_size_get(&s, bytes);
}

ls_status ls_toy1d_run(uint32_t index, uint32_t iters, ls_real *traj, ls_arena *arena)
{
    const ls_toy1d_method *m;
    ls_arena_mark mark;
    ls_csc lap;
    ls_param p;
    ls_param_config cfg;
    ls_real *x, *g, *target, *reg;
    uint32_t it, i, last = LS_TOY1D_N - 1u;
    ls_status st;
    if (traj == NULL || arena == NULL || index >= LS_TOY1D_METHODS) return LS_ERR_INVALID;
    m = &methods[index];
    mark = ls_arena_save(arena);
    st = ls_laplacian_grid(LS_TOY1D_N, 1, LS_LAP_UPPER, arena, &lap);
    if (st != LS_OK) return st;
    x = (ls_real *)ls_arena_alloc(arena, LS_TOY1D_N, sizeof(ls_real));
    g = (ls_real *)ls_arena_alloc(arena, LS_TOY1D_N, sizeof(ls_real));
    target = (ls_real *)ls_arena_alloc(arena, LS_TOY1D_N, sizeof(ls_real));
    reg = (ls_real *)ls_arena_alloc(arena, LS_TOY1D_N, sizeof(ls_real));
    if (x == NULL || g == NULL || target == NULL || reg == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    if (m->kind == LS_TOY1D_LARGE) {
        config(m, &cfg);
        st = ls_param_init(&p, &lap, &cfg, NULL, arena, NULL);
        if (st != LS_OK) {
            ls_arena_restore(arena, mark);
            return st;
        }
    }
    ls_toy1d_points(x, target);
    memcpy(traj, x, LS_TOY1D_N * sizeof(ls_real));
    for (it = 1; it <= iters && st == LS_OK; it++) {
        /* the loss' gradient: the end points only */
        for (i = 0; i < LS_TOY1D_N; i++) g[i] = (ls_real)0;
        g[0] = x[0] - target[0];
        g[last] = x[last] - target[last];
        if (m->kind == LS_TOY1D_LARGE) {
            st = ls_param_step(&p, x, g, m->step, m->power);
        } else {
            if (m->kind == LS_TOY1D_REG) {
                /* g + 2 w L x: the regularizer's gradient first, then the loss' */
                st = ls_laplacian_energy(&lap, 1, x, m->lambda, NULL, reg, NULL);
                for (i = 0; i < LS_TOY1D_N; i++) g[i] += reg[i];
            }
            for (i = 0; i < LS_TOY1D_N; i++) x[i] -= m->step * g[i];
        }
        memcpy(traj + (size_t)it * LS_TOY1D_N, x, LS_TOY1D_N * sizeof(ls_real));
    }
    ls_arena_restore(arena, mark);
    return st;
}
