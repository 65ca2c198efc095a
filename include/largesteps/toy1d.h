/* largesteps/toy1d.h - the paper's 1D toy: why large steps keep a "mesh"
 * from tangling where plain gradient descent does not.
 *
 * A 1D "mesh" of LS_TOY1D_N = 32 points starts at the linear progression
 * x_i = -1 + 2 i / 31 in [-1, 1]; the target is the progression in
 * [-0.5, 0.5]. Only "silhouette" gradients exist: the loss is
 * (x_0 - t_0)^2 / 2 + (x_31 - t_31)^2 / 2, so the two end points receive the
 * gradient of their distance to the target ends and every other point zero.
 * Methods (fixed step sizes, chosen so that no method overshoots: eta times
 * the end point's diagonal entry of the step's matrix stays below 1):
 *   naive            x <- x - 0.5 g
 *   laplacian reg.   x <- x - 0.5 (g + 2 w L x), w = 0.05 (loss + w x^T L x)
 *   large steps      x <- x - eta (I + lambda L)^{-p} g with L the path
 *                    graph Laplacian (ls_laplacian_grid(32, 1)), p = 1, 2,
 *                    lambda = 1, 19, 99, eta = 1.5 (p = 1) and 2 (p = 2)
 * The step of the large-steps methods goes through ls_param_step (LDL^T).
 * What it shows (asserted by tests/test_toy1d.c against a dense solve written
 * there): naive descent inverts elements (some x_{i+1} < x_i) at iteration 1;
 * large steps never invert for p = 2 with lambda >= 19 and for p = 1 with
 * lambda = 99, but do for lambda = 1 (and p = 1, lambda = 19); their end points
 * converge to the targets; the interior points stop where the diffused
 * profile leaves them, short of the target.
 */
#ifndef LARGESTEPS_TOY1D_H
#define LARGESTEPS_TOY1D_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_TOY1D_N 32u
#define LS_TOY1D_METHODS 8u

/* Kinds of method. */
#define LS_TOY1D_NAIVE 0u
#define LS_TOY1D_REG   1u
#define LS_TOY1D_LARGE 2u

typedef struct ls_toy1d_method {
    const char *name;  /* e.g. "large-p2-l19" */
    uint32_t kind;     /* LS_TOY1D_* */
    uint32_t power;    /* p (large steps), else 0 */
    ls_real lambda;    /* lambda (large steps) or the regularization weight w */
    ls_real step;      /* eta */
} ls_toy1d_method;

/* ls_toy1d_method_get: the description of method `index` (0 ..
 * LS_TOY1D_METHODS - 1): 0 naive, 1 laplacian-regularized, 2-4 large steps
 * p = 1 with lambda 1, 19, 99, 5-7 p = 2 with lambda 1, 19, 99. O(1).
 * Errors: LS_ERR_INVALID (NULL, index out of range). */
ls_status ls_toy1d_method_get(uint32_t index, ls_toy1d_method *out);

/* ls_toy1d_points: the start positions and the targets (LS_TOY1D_N each;
 * either may be NULL). O(N). */
void ls_toy1d_points(ls_real *start, ls_real *target);

/* ls_toy1d_bytes: exact arena bytes of ls_toy1d_run(method): the grid
 * Laplacian, the parameterization (ls_param_bytes, whose LDL^T analysis runs
 * in `scratch`, which needs a few KiB) and two vectors; all released by the
 * run. Errors: LS_ERR_INVALID, LS_ERR_NOMEM (scratch too small). */
ls_status ls_toy1d_bytes(uint32_t method, ls_arena *scratch, size_t *bytes);

/* ls_toy1d_run: runs `iters` iterations of method `index` from the start
 * positions and writes the trajectory: traj[it * LS_TOY1D_N + i] = x_i after
 * `it` iterations, it = 0 .. iters ((iters + 1) * LS_TOY1D_N reals). Cost
 * O(iters N p). Memory: ls_toy1d_bytes, all released before return.
 * Deterministic. Errors: LS_ERR_INVALID, LS_ERR_NOMEM (traj unchanged), and
 * the solver's (not expected). */
ls_status ls_toy1d_run(uint32_t index, uint32_t iters, ls_real *traj, ls_arena *arena);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_TOY1D_H */
