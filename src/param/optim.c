/* optim.c - UniformAdam, Adam and SGD with momentum on one state layout.
 * The formulas and their sources are in include/largesteps/optim.h. */
#include <string.h>
#include <largesteps/optim.h>
#include <largesteps/math.h>

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint32_t index, ls_real value)
{
    if (ls_diag_set(diag, st, what, index) != LS_OK && diag != NULL) {
        diag->has_value = 1;
        diag->value = value;
    }
}

static int is_finite(ls_real x)
{
    return x - x == x - x; /* false for NaN and infinities */
}

/* A decay rate must lie in [0, 1). */
static int valid_beta(ls_real b)
{
    return is_finite(b) && b >= (ls_real)0 && b < (ls_real)1;
}

/* NULL when c is in range, else the field and its allowed range (*value:
 * the offending value). */
static const char *config_error(const ls_optim_config *c, ls_real *value)
{
    *value = (ls_real)c->method;
    if (c->method != LS_OPTIM_UNIFORM_ADAM && c->method != LS_OPTIM_ADAM && c->method != LS_OPTIM_SGD)
        return "config->method: allowed LS_OPTIM_UNIFORM_ADAM, LS_OPTIM_ADAM or LS_OPTIM_SGD";
    *value = c->lr;
    if (!is_finite(c->lr) || c->lr <= (ls_real)0) return "config->lr: the learning rate, allowed finite and > 0";
    *value = c->beta1;
    if (!valid_beta(c->beta1)) return "config->beta1: allowed [0, 1) (the reference: 0.9)";
    if (c->method == LS_OPTIM_SGD) return NULL;
    *value = c->beta2;
    if (!valid_beta(c->beta2)) return "config->beta2: allowed [0, 1) (the reference: 0.999)";
    *value = c->eps;
    if (!is_finite(c->eps) || c->eps < (ls_real)0) return "config->eps: allowed finite and >= 0 (the reference: 1e-8)";
    return NULL;
}

static int valid_config(const ls_optim_config *c)
{
    ls_real v;
    return config_error(c, &v) == NULL;
}

ls_status ls_optim_config_check(const ls_optim_config *config, ls_diag *diag)
{
    ls_real v = (ls_real)0;
    const char *bad;
    if (config == NULL) {
        (void)ls_diag_set(diag, LS_ERR_INVALID, "config is NULL", LS_DIAG_NO_INDEX);
        return LS_ERR_INVALID;
    }
    bad = config_error(config, &v);
    if (bad != NULL) {
        (void)ls_diag_set(diag, LS_ERR_INVALID, bad, LS_DIAG_NO_INDEX);
        if (diag != NULL) {
            diag->has_value = 1;
            diag->value = v;
        }
        return LS_ERR_INVALID;
    }
    ls_diag_clear(diag);
    return LS_OK;
}

/* The sum of the block sizes, or 0 when the blocks are invalid for capacity. */
static uint32_t blocks_total(uint32_t capacity, uint32_t block_count, const uint32_t *block_sizes)
{
    uint32_t b, total = 0;
    if (block_sizes == NULL || block_count == 0 || block_count > LS_OPTIM_MAX_BLOCKS) return 0;
    for (b = 0; b < block_count; b++) {
        if (block_sizes[b] == 0 || block_sizes[b] > capacity - total) return 0;
        total += block_sizes[b];
    }
    return total;
}

static void set_blocks(ls_optim *opt, uint32_t count, uint32_t block_count, const uint32_t *block_sizes)
{
    uint32_t b;
    opt->count = count;
    opt->block_count = block_count;
    for (b = 0; b < LS_OPTIM_MAX_BLOCKS; b++) {
        opt->block_size[b] = b < block_count ? block_sizes[b] : 0u;
        opt->last_scale[b] = (ls_real)0;
    }
    opt->step = 0;
    memset(opt->m1, 0, (size_t)opt->capacity * sizeof(ls_real));
    memset(opt->m2, 0, (size_t)opt->capacity * sizeof(ls_real));
}

ls_status ls_optim_config_default(uint32_t method, ls_optim_config *config)
{
    if (config == NULL) return LS_ERR_INVALID;
    switch (method) {
    case LS_OPTIM_UNIFORM_ADAM:
        config->lr = (ls_real)0.1;
        break;
    case LS_OPTIM_ADAM:
        config->lr = (ls_real)1e-3;
        break;
    case LS_OPTIM_SGD:
        config->lr = (ls_real)1e-2;
        break;
    default:
        return LS_ERR_INVALID;
    }
    config->method = method;
    config->beta1 = (ls_real)0.9;
    config->beta2 = method == LS_OPTIM_SGD ? (ls_real)0 : (ls_real)0.999;
    config->eps = method == LS_OPTIM_SGD ? (ls_real)0 : (ls_real)1e-8;
    return LS_OK;
}

ls_status ls_optim_bytes(uint32_t capacity, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, capacity, sizeof(ls_real));
    ls_size_add(&s, capacity, sizeof(ls_real));
    return ls_size_get(&s, bytes);
}

ls_status ls_optim_init(ls_optim *opt, const ls_optim_config *config, uint32_t capacity, uint32_t block_count,
                        const uint32_t *block_sizes, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_real *m1, *m2;
    size_t bytes;
    uint32_t total;
    ls_status st;
    if (opt == NULL || config == NULL || arena == NULL || !valid_config(config)) return LS_ERR_INVALID;
    total = blocks_total(capacity, block_count, block_sizes);
    if (total == 0) return LS_ERR_INVALID;
    st = ls_optim_bytes(capacity, &bytes);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    m1 = (ls_real *)ls_arena_alloc(arena, capacity, sizeof(ls_real));
    m2 = (ls_real *)ls_arena_alloc(arena, capacity, sizeof(ls_real));
    if (m1 == NULL || m2 == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    opt->config = *config;
    opt->capacity = capacity;
    opt->m1 = m1;
    opt->m2 = m2;
    set_blocks(opt, total, block_count, block_sizes);
    return LS_OK;
}

ls_status ls_optim_reset(ls_optim *opt, uint32_t block_count, const uint32_t *block_sizes)
{
    uint32_t total;
    if (opt == NULL || opt->m1 == NULL || opt->m2 == NULL) return LS_ERR_INVALID;
    total = blocks_total(opt->capacity, block_count, block_sizes);
    if (total == 0) return LS_ERR_INVALID;
    set_blocks(opt, total, block_count, block_sizes);
    return LS_OK;
}

/* Both moments of Adam and UniformAdam, element by element: m1 from g1,
 * m2 from g2 (the same array for a plain step). */
static void update_moments(ls_optim *opt, const ls_real *g1, const ls_real *g2)
{
    const ls_real b1 = opt->config.beta1, b2 = opt->config.beta2;
    const ls_real a1 = (ls_real)1 - b1, a2 = (ls_real)1 - b2;
    uint32_t i;
    for (i = 0; i < opt->count; i++) {
        const ls_real g = g2[i];
        opt->m1[i] = b1 * opt->m1[i] + a1 * g1[i];
        opt->m2[i] = b2 * opt->m2[i] + a2 * (g * g);
    }
}

/* UniformAdam on the block [first, first + size). */
static ls_real uniform_adam_block(const ls_optim *opt, ls_real *params, uint32_t first, uint32_t size,
                                  ls_real bc1, ls_real bc2)
{
    const ls_real lr = opt->config.lr;
    ls_real m2max = (ls_real)0, scale, denom;
    uint32_t i;
    for (i = first; i < first + size; i++) {
        const ls_real m2hat = opt->m2[i] / bc2;
        if (m2hat > m2max) m2max = m2hat;
    }
    scale = LS_RSQRT(m2max);
    denom = opt->config.eps + scale;
    if (denom == (ls_real)0) return scale; /* eps = 0 and every m2 zero: no step (not 0/0) */
    for (i = first; i < first + size; i++) {
        const ls_real m1hat = opt->m1[i] / bc1;
        params[i] = params[i] - lr * (m1hat / denom);
    }
    return scale;
}

static void adam(const ls_optim *opt, ls_real *params, ls_real bc1, ls_real bc2)
{
    const ls_real step_size = opt->config.lr / bc1, bc2_sqrt = LS_RSQRT(bc2), eps = opt->config.eps;
    uint32_t i;
    for (i = 0; i < opt->count; i++) {
        const ls_real denom = LS_RSQRT(opt->m2[i]) / bc2_sqrt + eps;
        if (denom == (ls_real)0) continue; /* eps = 0 and m2 zero: no step (not 0/0) */
        params[i] = params[i] - step_size * (opt->m1[i] / denom);
    }
}

static void sgd(ls_optim *opt, ls_real *params, const ls_real *grad)
{
    const ls_real momentum = opt->config.beta1, lr = opt->config.lr;
    uint32_t i;
    for (i = 0; i < opt->count; i++) {
        opt->m1[i] = opt->step == 1 ? grad[i] : momentum * opt->m1[i] + grad[i];
        params[i] = params[i] - lr * opt->m1[i];
    }
}

/* 1 when every gradient is finite, else the diagnosis of the first that is not. */
static int grad_finite(const ls_optim *opt, const ls_real *grad, ls_diag *diag)
{
    uint32_t i;
    for (i = 0; i < opt->count; i++) {
        if (!is_finite(grad[i])) {
            diag_set(diag, LS_ERR_NONFINITE, "non-finite gradient", i, grad[i]);
            return 0;
        }
    }
    return 1;
}

/* The step with m1 driven by g1 and m2 by g2 (g1 = g2: ls_optim_step). */
static ls_status step(ls_optim *opt, ls_real *params, const ls_real *g1, const ls_real *g2, ls_diag *diag)
{
    ls_real bc1, bc2, t;
    uint32_t b, first;
    if (!grad_finite(opt, g1, diag) || (g2 != g1 && !grad_finite(opt, g2, diag))) return LS_ERR_NONFINITE;
    if (opt->step < UINT32_MAX) opt->step++;
    if (opt->config.method == LS_OPTIM_SGD) {
        sgd(opt, params, g1);
        return LS_OK;
    }
    update_moments(opt, g1, g2);
    t = (ls_real)opt->step;
    bc1 = (ls_real)1 - LS_RPOW(opt->config.beta1, t);
    bc2 = (ls_real)1 - LS_RPOW(opt->config.beta2, t);
    if (opt->config.method == LS_OPTIM_ADAM) {
        adam(opt, params, bc1, bc2);
        return LS_OK;
    }
    for (b = 0, first = 0; b < opt->block_count; b++) {
        opt->last_scale[b] = uniform_adam_block(opt, params, first, opt->block_size[b], bc1, bc2);
        first += opt->block_size[b];
    }
    return LS_OK;
}

/* The arguments of a step: LS_OK, or LS_ERR_INVALID naming the first that is wrong. */
static ls_status step_args(const ls_optim *opt, const ls_real *params, const ls_real *grad, int mapped_ok,
                           ls_diag *diag)
{
    const char *what = NULL;
    if (opt == NULL) what = "opt is NULL";
    else if (params == NULL) what = "params is NULL";
    else if (grad == NULL) what = "grad is NULL";
    else if (!mapped_ok) what = "mapped is NULL";
    else if (opt->m1 == NULL || opt->count == 0) what = "opt: not initialised (ls_optim_init)";
    else if (!valid_config(&opt->config)) return ls_optim_config_check(&opt->config, diag);
    if (what == NULL) return LS_OK;
    (void)ls_diag_set(diag, LS_ERR_INVALID, what, LS_DIAG_NO_INDEX);
    return LS_ERR_INVALID;
}

ls_status ls_optim_step(ls_optim *opt, ls_real *params, const ls_real *grad, ls_diag *diag)
{
    ls_status st = step_args(opt, params, grad, 1, diag);
    if (st == LS_OK) st = step(opt, params, grad, grad, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}

ls_status ls_optim_step_mapped(ls_optim *opt, ls_real *params, const ls_real *grad, const ls_real *mapped,
                               ls_diag *diag)
{
    ls_status st = step_args(opt, params, grad, mapped != NULL, diag);
    if (st == LS_OK && opt->config.method == LS_OPTIM_ADAM) {
        (void)ls_diag_set(diag, LS_ERR_INVALID,
                          "opt->config.method: LS_OPTIM_ADAM does not commute with the map; allowed "
                          "LS_OPTIM_UNIFORM_ADAM or LS_OPTIM_SGD",
                          LS_DIAG_NO_INDEX);
        return LS_ERR_INVALID;
    }
    if (st == LS_OK) st = step(opt, params, mapped, grad, diag);
    if (st == LS_OK) ls_diag_clear(diag);
    return st;
}
