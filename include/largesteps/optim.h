/* largesteps/optim.h - first-order optimizers with one state layout:
 * UniformAdam (the large-steps method's optimizer), Adam and SGD with momentum.
 *
 * The parameters are a flat array of `count` reals split into consecutive
 * blocks (e.g. the n x 3 differential coordinates u, then a 3-vector global
 * translation). Every method keeps the same state: a step counter t and two
 * arrays m1, m2 of `capacity` reals. Each step, with gradient g (t starts at 1):
 *
 *   UniformAdam (the reference's AdamUniform, largesteps/optimize.py):
 *       m1 <- b1 m1 + (1 - b1) g          m2 <- b2 m2 + (1 - b2) g*g
 *       m1^ = m1 / (1 - b1^t)             m2^ = m2 / (1 - b2^t)
 *       p  <- p - lr * m1^ / (eps + max over the BLOCK of sqrt(m2^))
 *     One scalar per block: the infinity norm of sqrt(m2^) over every element of
 *     the block (all vertices and all three axes), so a translation block is
 *     normalized on its own, as the reference's separate parameter tensor is.
 *   Adam (as PyTorch's torch.optim.Adam, no weight decay):
 *       m1, m2 as above;  p <- p - (lr / (1 - b1^t)) * m1 / (sqrt(m2) / sqrt(1 - b2^t) + eps)
 *   SGD with momentum (PyTorch's torch.optim.SGD, dampening 0, not Nesterov;
 *     m2 is kept at zero):
 *       m1 <- g at t = 1, else b1 m1 + g;   p <- p - lr * m1
 *
 * b^t is computed with the library's pow (ls_pow / ls_powf: below 1 ulp, the
 * same bits everywhere). Every element is updated independently and the block
 * maxima are taken in index order, so results are bit-identical on every
 * target. sqrt is monotonic, so max(sqrt(m2^)) is computed as sqrt(max(m2^)).
 *
 * With eps = 0, an element (Adam) or a block (UniformAdam) whose denominator
 * is exactly zero does not move, instead of dividing by zero.
 *
 * A non-finite gradient (NaN, infinity) is rejected before anything changes:
 * the step returns LS_ERR_NONFINITE naming the element, and parameters and
 * state are as before the call - the fit loop reports the iteration.
 *
 * After remeshing the parameter count changes: ls_optim_reset starts the state
 * over (t = 0, moments zero) for new block sizes within the capacity; the
 * learning rate is the public field config.lr (the method multiplies it by 0.8
 * at every remesh).
 */
#ifndef LARGESTEPS_OPTIM_H
#define LARGESTEPS_OPTIM_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Methods. */
#define LS_OPTIM_UNIFORM_ADAM 1u
#define LS_OPTIM_ADAM         2u
#define LS_OPTIM_SGD          3u

/* At most this many parameter blocks. */
#define LS_OPTIM_MAX_BLOCKS 4u

typedef struct ls_optim_config {
    uint32_t method; /* LS_OPTIM_* */
    ls_real lr;      /* learning rate (> 0) */
    ls_real beta1;   /* first-moment decay; SGD: the momentum (0 = plain gradient descent) */
    ls_real beta2;   /* second-moment decay (Adam methods) */
    ls_real eps;     /* added to the denominator (Adam methods) */
} ls_optim_config;

typedef struct ls_optim {
    ls_optim_config config;
    uint32_t capacity;                       /* reals allocated in m1 and m2 */
    uint32_t count;                          /* parameters in use: the sum of the block sizes */
    uint32_t block_count;                    /* 1 .. LS_OPTIM_MAX_BLOCKS */
    uint32_t block_size[LS_OPTIM_MAX_BLOCKS]; /* reals per block, in order */
    uint32_t step;                           /* steps taken since init or reset (t) */
    ls_real *m1;                             /* first moments (SGD: momentum buffer) */
    ls_real *m2;                             /* second moments (zero for SGD) */
    ls_real last_scale[LS_OPTIM_MAX_BLOCKS]; /* UniformAdam: each block's max sqrt(m2^) of
                                                the last step (0 for the other methods) */
} ls_optim;

/* ls_optim_config_default: the reference's defaults for a method:
 * UniformAdam lr 0.1, betas (0.9, 0.999), eps 1e-8 (large-steps-pytorch);
 * Adam lr 1e-3, betas (0.9, 0.999), eps 1e-8 (PyTorch); SGD lr 1e-2, momentum
 * 0.9. Errors: LS_ERR_INVALID (NULL or unknown method: *config unchanged). O(1). */
ls_status ls_optim_config_default(uint32_t method, ls_optim_config *config);

/* ls_optim_config_check: LS_OK when *config is in range for ls_optim_init,
 * else LS_ERR_INVALID with diag->what naming the field and its allowed
 * range and diag->value the value (ls_optim_init has no diag: call this to
 * learn why it refused). On success *diag is cleared. O(1). */
ls_status ls_optim_config_check(const ls_optim_config *config, ls_diag *diag);

/* ls_optim_bytes: exact arena bytes of ls_optim_init with this capacity
 * (2 * capacity reals). O(1). Errors: LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE. */
ls_status ls_optim_bytes(uint32_t capacity, size_t *bytes);

/* ls_optim_init: an optimizer for up to `capacity` parameters, with the state
 * reset for `block_count` blocks of the given sizes (see ls_optim_reset).
 * Memory: ls_optim_bytes(capacity) from the arena's bottom. Errors:
 * LS_ERR_INVALID (NULL, unknown method, lr <= 0 or not finite, beta1 outside
 * [0, 1), beta2 outside [0, 1) for the Adam methods, eps < 0 or not finite,
 * block_count 0 or above LS_OPTIM_MAX_BLOCKS, a block of size 0, the sizes'
 * sum above capacity), LS_ERR_NOMEM, LS_ERR_TOO_LARGE; on failure the arena
 * and *opt are unchanged. O(capacity). */
ls_status ls_optim_init(ls_optim *opt, const ls_optim_config *config, uint32_t capacity, uint32_t block_count,
                        const uint32_t *block_sizes, ls_arena *arena);

/* ls_optim_reset: starts over (t = 0, moments zero) with new block sizes,
 * keeping the memory and the configuration. O(count). Errors: LS_ERR_INVALID
 * (as ls_optim_init; *opt unchanged). */
ls_status ls_optim_reset(ls_optim *opt, uint32_t block_count, const uint32_t *block_sizes);

/* ls_optim_step: one step: params (opt->count reals, in block order) move
 * against grad (same layout) as the method above says. O(count); no memory.
 * Errors: LS_ERR_INVALID (NULL, opt not initialised; diag->what says which),
 * LS_ERR_NONFINITE (a NaN or infinite gradient; diag->index = its element,
 * diag->value = it; nothing changed). On success *diag is cleared. A
 * parameter that overflows to infinity is not detected here. */
ls_status ls_optim_step(ls_optim *opt, ls_real *params, const ls_real *grad, ls_diag *diag);

/* ls_optim_step_mapped: the step of ls_optim_step on parameters u, applied
 * to params = A u for a fixed linear map A (large steps: A = M^{-1}, so the
 * optimizer moves x without solving for it). grad is the gradient with
 * respect to u (it drives m2 and so the block maxima) and mapped = A grad
 * (it drives m1, which then holds A m1). Because UniformAdam's normalization
 * is one scalar per block and SGD's momentum is linear, params move exactly
 * as A u would, up to rounding; per-element Adam does not commute with A and
 * is refused. The state must only ever be stepped one way. Cost as
 * ls_optim_step. Errors: LS_ERR_INVALID (as ls_optim_step; also Adam, a NULL
 * mapped), LS_ERR_NONFINITE (in grad or mapped; nothing changed). */
ls_status ls_optim_step_mapped(ls_optim *opt, ls_real *params, const ls_real *grad, const ls_real *mapped,
                               ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_OPTIM_H */
