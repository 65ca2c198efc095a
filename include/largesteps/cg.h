/* largesteps/cg.h - Jacobi-preconditioned conjugate gradient for symmetric
 * positive definite sparse matrices, k right-hand sides at once.
 *
 * The memory-bounded alternative to the LDL^T factor (ldlt.h) for systems
 * whose factor does not fit: it needs the matrix (O(nnz)) and 3 n k + n reals
 * of scratch, nothing else. The matrix is an ls_csc read through its upper
 * triangle (ls_csc_matvec_sym); right-hand sides and solutions are n x k
 * row-major ("interleaved", entry (i, c) at x[i * k + c]), k <= LS_CG_MAX_K.
 * Every column runs its own CG (its own alpha, beta and stopping test) inside
 * one loop that shares the matrix products; a column stops when its residual
 * norm ||b_c - M x_c||_2 (the recurrence's) falls to tol * ||b_c||_2, and
 * stays as it is while the others go on. All sums are in index order: the
 * same bits on every target.
 *
 * Compared with the reference (largesteps-pytorch ConjugateGradientSolver:
 * unpreconditioned, one column at a time, absolute tolerance 1e-5, no cap)
 * this one is preconditioned with diag(M), relative, and capped.
 */
#ifndef LARGESTEPS_CG_H
#define LARGESTEPS_CG_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/sparse.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The most right-hand sides one call takes. */
#define LS_CG_MAX_K 4u

/* The controls (set by the caller) and the statistics (set by the solve) of
 * one ls_cg_solve. */
typedef struct ls_cg_info {
    /* in */
    uint32_t max_iter;                /* iteration cap per column (0: x is only checked) */
    ls_real tol;                      /* relative residual target, e.g. 1e-12 (double), 1e-6 (float) */
    /* out */
    uint32_t iterations[LS_CG_MAX_K]; /* CG iterations done per column */
    ls_real residual[LS_CG_MAX_K];    /* final ||b_c - M x_c|| / ||b_c|| (recomputed, not the
                                         recurrence's); 0 for a zero column */
    uint32_t converged;               /* number of columns that met tol */
    uint32_t max_iterations;          /* the largest of iterations[] */
} ls_cg_info;

/* ls_cg_bytes: exact scratch bytes of ls_cg_solve for n rows and k columns:
 * (3 n k + n) reals. O(1). Errors: LS_ERR_INVALID (NULL, k = 0 or >
 * LS_CG_MAX_K), LS_ERR_TOO_LARGE. */
ls_status ls_cg_bytes(uint32_t n, uint32_t k, size_t *bytes);

/* ls_cg_solve: solves M x = b for the k columns of b, starting from the x
 * given (warm start: pass the previous solution; zeros for a cold start),
 * with info->max_iter and info->tol; the other fields of *info are outputs.
 * Per iteration one product with M (2 nnz(upper) k multiply-adds) and 10 n k
 * flops. Stops per column at the relative tolerance or after max_iter
 * iterations; a column with b_c = 0 gets x_c = 0 at once. Not converging
 * within the cap is not an error: the call returns LS_OK and *info says how
 * far each column got. Memory: ls_cg_bytes scratch from the arena,
 * released. Errors: LS_ERR_INVALID (NULL, not square, k = 0 or >
 * LS_CG_MAX_K, tol < 0 or NaN), LS_ERR_NONFINITE (b or x holds a NaN or
 * infinity: x unchanged; or the iteration produced one), LS_ERR_NOT_SPD (a
 * diagonal entry <= 0, or p^T M p <= 0: M is not positive definite; x then
 * holds the last iterate), LS_ERR_NOMEM (x unchanged). */
ls_status ls_cg_solve(const ls_csc *m, uint32_t k, const ls_real *b, ls_real *x, ls_arena *arena, ls_cg_info *info);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_CG_H */
