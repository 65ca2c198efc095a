/* largesteps/ldlt.h - sparse LDL^T factorization of symmetric positive
 * definite matrices and solves with k interleaved right-hand sides.
 *
 * P A P^T = L D L^T with L unit lower triangular, D diagonal (no square roots),
 * P a fill-reducing permutation. The matrix A is an ls_csc read through its
 * upper triangle (entries with row <= col; a matrix storing both triangles is
 * fine). Three phases, each with an exact sizing query:
 *
 *   ls_ldlt_analyze_bytes / ls_ldlt_analyze   ordering, elimination tree,
 *        column counts, postorder: the symbolic object (depends on the pattern)
 *   ls_ldlt_bytes / ls_ldlt_factor            the numeric factor; the bytes are
 *        known after analysis, before any numeric work
 *   ls_ldlt_refactor                          new values, same pattern: no memory
 *   ls_ldlt_solve_bytes / ls_ldlt_solve       X = A^{-1} B in place, B n x k
 *        row-major (entry (i, c) at x[i*k + c]); k = 3 is the fast path
 *   ls_ldlt_refine                            iterative refinement steps
 *   ls_ldlt_split_bytes_n / ls_ldlt_split_init / ls_ldlt_solve_split
 *        the k = 3 solve over the caller's workers, the same bits
 *
 * Algorithm: up-looking LDL^T (row k of L is a sparse triangular solve whose
 * pattern is the elimination-tree reach of column k of A). Every operation is
 * done in a fixed order: the same input gives the same bits everywhere.
 *
 * Pivots: a zero, negative or non-finite pivot (including NaN or infinity in
 * A) fails with LS_ERR_NOT_SPD; the ls_diag names the column in A's
 * numbering (index) and the pivot (value). A factor whose (re)factorization
 * failed is marked invalid: solves on it return LS_ERR_STATE until a
 * successful ls_ldlt_refactor.
 *
 * Tiny values: during the factorization, intermediate values and entries of
 * L whose magnitude is below LS_LDLT_FLUSH are replaced by zero (the pattern
 * is kept). Products of two kept values are then never subnormal, so the float
 * factorization does not slow down on CPUs that trap subnormals, without
 * touching the FPU's flush flags. This perturbs A by at most about
 * LS_LDLT_FLUSH times its row counts: negligible when A's diagonal is of
 * order 1 or larger (M = I + lambda L); scale A so if it is not.
 *
 * Very large lambda in M = I + lambda L: when lambda times the vertex degree
 * exceeds about 1/epsilon, 1 + lambda*deg rounds to lambda*deg and the
 * computed matrix is the singular lambda L; the last pivot of each connected
 * component is then rounding noise. Then ls_ldlt_factor either returns
 * LS_ERR_NOT_SPD naming that column (noise <= 0), or succeeds with a tiny
 * backward error but a meaningless constant component of the solution. The
 * solver does not know the structure of M; the caller (the parameterization)
 * should handle the constant mode or keep lambda below 1e6 (float) / 1e14
 * (double). See the README's backward-error table.
 */
#ifndef LARGESTEPS_LDLT_H
#define LARGESTEPS_LDLT_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/sparse.h>
#include <largesteps/order.h>
#include <largesteps/parallel.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The type of the sums of the factorization and the solves (the y and w
 * work vectors). The float build stores L and D in float but by default sums
 * in double (make SUMS=double, LS_SUMS_DOUBLE 1): sums of hundreds of products
 * then round once, and the unrefined backward error of a 3-RHS solve on a
 * 10k-vertex mesh is 2e-8..7e-8 instead of 1e-6..2e-6 with float sums. SUMS=real
 * (the Cortex-M4's default: no double FPU) sums in float. */
#if LS_SUMS_DOUBLE || !LS_REAL_IS_FLOAT
typedef double ls_acc;
#else
typedef float ls_acc;
#endif

#if LS_REAL_IS_FLOAT
#define LS_LDLT_FLUSH 1.0842021724855044e-19f /* 2^-63: squares stay normal in float */
#else
#define LS_LDLT_FLUSH 1.4916681462400413e-154 /* 2^-511: squares stay normal in double */
#endif

/* Factor states. */
#define LS_LDLT_ANALYZED 1u /* symbolic only: factor before solving */
#define LS_LDLT_VALID    2u /* a successful numeric factorization */
#define LS_LDLT_INVALID  3u /* the last (re)factorization failed: refactor needed */

typedef struct ls_ldlt {
    uint32_t n;
    uint32_t state;     /* LS_LDLT_* */
    uint32_t a_nnz;     /* stored entries of the analyzed matrix (checked by factor) */
    uint32_t c_nnz;     /* entries of A's upper triangle */
    uint32_t l_nnz;     /* entries of L below the diagonal */
    uint32_t method;    /* LS_ORDER_* used */
    uint32_t *perm;     /* n: new -> old */
    uint32_t *pinv;     /* n: old -> new */
    uint32_t *parent;   /* n: elimination tree, UINT32_MAX at roots */
    uint32_t *lp;       /* n + 1: column starts of L */
    uint32_t *cp;       /* n + 1: P A P^T upper pattern, column starts */
    uint32_t *ci;       /* c_nnz: its rows */
    uint32_t *csrc;     /* c_nnz: position of each entry's value in A */
    /* numeric part, allocated by the first ls_ldlt_factor (NULL before) */
    uint32_t *li;       /* l_nnz: rows of L */
    ls_real *lx;        /* l_nnz: values of L */
    ls_real *dinv;      /* n: 1 / D */
    ls_acc *y;          /* n: workspace */
    uint32_t *flag;     /* n: workspace */
    uint32_t *stack;    /* n: workspace */
    uint32_t *lnz;      /* n: workspace */
    uint64_t flops;     /* multiply-adds of one numeric factorization */
} ls_ldlt;

/* ls_ldlt_analyze_bytes: exact arena bytes of ls_ldlt_analyze(a, method):
 * the symbolic object plus the peak scratch (ordering). O(nnz(a)).
 * Errors: LS_ERR_INVALID (NULL, not square, unknown method, or LS_ORDER_ND /
 * LS_ORDER_AUTO, which need coordinates: ls_ldlt_analyze_mesh_bytes),
 * LS_ERR_TOO_LARGE. */
ls_status ls_ldlt_analyze_bytes(const ls_csc *a, uint32_t method, size_t *bytes);

/* ls_ldlt_analyze: symbolic analysis of the square matrix a: the ordering
 * (LS_ORDER_AMD, LS_ORDER_NATURAL, or LS_ORDER_GIVEN with perm = new -> old,
 * else perm is ignored and may be NULL), the permuted upper pattern, the
 * elimination tree, its postorder (the factor's columns are renumbered in it)
 * and the exact column counts of L (Gilbert-Ng-Peyton: time about
 * O(nnz(A)), not O(nnz(L)), plus the ordering's). The object keeps 20 bytes
 * per row plus 8 per entry of A's upper triangle (about 52 bytes per vertex of
 * a triangle mesh); the ordering's scratch is released. Memory:
 * ls_ldlt_analyze_bytes from the arena's bottom. Errors: LS_ERR_INVALID (NULL, not square, perm not a permutation,
 * index out of range), LS_ERR_TOO_LARGE (nnz(L) >= 2^32), LS_ERR_NOMEM; on
 * failure the arena and *f are unchanged. */
ls_status ls_ldlt_analyze(const ls_csc *a, uint32_t method, const uint32_t *perm, ls_arena *arena,
                          ls_ldlt *f, ls_diag *diag);

/* ls_ldlt_analyze_mesh_bytes: exact arena bytes of ls_ldlt_analyze_mesh(a,
 * method); method may be any LS_ORDER_* but LS_ORDER_GIVEN. O(nnz(a)). */
ls_status ls_ldlt_analyze_mesh_bytes(const ls_csc *a, uint32_t method, size_t *bytes);

/* ls_ldlt_analyze_mesh: ls_ldlt_analyze for a matrix whose variables are mesh
 * vertices with coordinates xyz (n x 3 row-major), which enables
 * LS_ORDER_ND (geometric nested dissection) and LS_ORDER_AUTO: both AMD and
 * ND are computed, their nnz(L) predicted from exact column counts, and the
 * smaller kept (f->method says which). AUTO costs about both orderings plus
 * two column counts. Errors: as ls_ldlt_analyze, plus LS_ERR_NONFINITE for a
 * non-finite coordinate. */
ls_status ls_ldlt_analyze_mesh(const ls_csc *a, uint32_t method, const ls_real *xyz, ls_arena *arena, ls_ldlt *f,
                               ls_diag *diag);

/* ls_ldlt_bytes: exact arena bytes the numeric factor will take (L, 1/D and
 * workspace: 12 bytes per entry of L in double, 8 in float, plus 12 + 2
 * sizeof(ls_real) per row), known from the analysis before any numeric work.
 * O(1). Errors: LS_ERR_INVALID (NULL or not analyzed), LS_ERR_TOO_LARGE. */
ls_status ls_ldlt_bytes(const ls_ldlt *f, size_t *bytes);

/* ls_ldlt_bytes_bound: the three sizes above for a matrix that does not
 * exist yet (a job sized up front): an n x n matrix with nnz stored entries,
 * c_nnz (<= nnz) of them in its upper triangle with the diagonal, analyzed
 * with `method`, whose L has l_nnz entries below the diagonal. *analyze =
 * ls_ldlt_analyze(_mesh)_bytes, *object = the symbolic object that
 * ls_ldlt_analyze keeps (its part of *analyze), *factor = ls_ldlt_bytes;
 * exact at those counts and never smaller for any larger count, so a
 * matrix within the counts fits. nnz(L) is not a function of n and nnz
 * (it depends on the pattern and the ordering): the caller bounds it. O(1).
 * Errors: LS_ERR_INVALID (NULL, unknown method, c_nnz > nnz),
 * LS_ERR_TOO_LARGE (all three then 0). */
ls_status ls_ldlt_bytes_bound(uint32_t n, uint32_t nnz, uint32_t c_nnz, uint32_t l_nnz, uint32_t method,
                              size_t *analyze, size_t *object, size_t *factor);

/* ls_ldlt_factor: numeric factorization of a (same pattern as analyzed: the
 * entry count is checked, the pattern itself is trusted). The first call takes
 * ls_ldlt_bytes(f) from the arena's bottom; later calls reuse that memory
 * (arena may then be NULL). Time sum over columns of |L(:,j)|^2 (up-looking).
 * Errors: LS_ERR_INVALID (NULL, pattern size differs, nothing analyzed),
 * LS_ERR_NOMEM (nothing changed), LS_ERR_NOT_SPD (diag: column in A's
 * numbering, pivot value; f is then marked LS_LDLT_INVALID and the arena is as
 * before the call). */
ls_status ls_ldlt_factor(ls_ldlt *f, const ls_csc *a, ls_arena *arena, ls_diag *diag);

/* ls_ldlt_refactor: numeric-only refactorization with new values of the same
 * pattern, reusing the memory of a previous ls_ldlt_factor (no arena). Same
 * cost and errors as ls_ldlt_factor; LS_ERR_STATE if never factored. */
ls_status ls_ldlt_refactor(ls_ldlt *f, const ls_csc *a, ls_diag *diag);

/* ls_ldlt_solve_bytes: exact scratch bytes of ls_ldlt_solve with k
 * right-hand sides (n * k reals). O(1). */
ls_status ls_ldlt_solve_bytes(const ls_ldlt *f, uint32_t k, size_t *bytes);

/* ls_ldlt_solve_bytes_n: the same for an n x n factor not built yet (a
 * caller sizing a job before the analysis). O(1). */
ls_status ls_ldlt_solve_bytes_n(uint32_t n, uint32_t k, size_t *bytes);

/* ls_ldlt_solve: x (n x k, row-major) holds B on entry and A^{-1} B on
 * return: permute, forward with L, scale by 1/D, backward with L^T,
 * permute back. Time 4 nnz(L) k + O(n k); scratch n k reals, released.
 * Errors: LS_ERR_INVALID (NULL, k = 0), LS_ERR_STATE (not validly
 * factored), LS_ERR_NONFINITE (B holds a NaN or infinity: x unchanged; or the
 * solution overflowed: x then holds it), LS_ERR_NOMEM (x unchanged). */
ls_status ls_ldlt_solve(const ls_ldlt *f, uint32_t k, ls_real *x, ls_arena *arena);

/* A plan that splits the k = 3 solve over W workers (parallel.h) by
 * subtrees of the elimination tree: the last columns [top, n) (T, at most
 * a third of the work, run by the calling thread) are cut off, and the
 * subtrees below them (the pieces) are dealt to the workers, largest
 * first; the pieces' updates of T's rows are applied by the workers too,
 * each to its own rows. Every sum keeps its order, so ls_ldlt_solve_split
 * gives the bits of ls_ldlt_solve(f, 3, ...) for every plan, worker count
 * and parallel-for. The plan depends on the factor's pattern only: it
 * stays valid across ls_ldlt_refactor. */
typedef struct ls_ldlt_split {
    uint32_t n, workers;   /* workers 1: the whole solve (one worker asked, or below the minimum work) */
    uint32_t top;          /* T = columns [top, n) */
    uint32_t top_start;    /* T's backward pass ends at this column (<= top) */
    uint32_t held_chunks;  /* chunks of 1, 2 or 4 chained piece columns with rows in T */
    uint32_t *data;        /* group (W + 1: worker g's pieces are sub[group[g] .. group[g+1])),
                            * rows (W + 1: held-update task g has rows [rows[g], rows[g+1])),
                            * sub (3 n: per piece its first column, root + 1, backward start),
                            * held (3 n: per held chunk its first column, width, first entry in T) */
} ls_ldlt_split;

/* What a plan does with the work (entries of L plus columns), for benchmarks
 * and tests: the tree's total, T's part, the most loaded worker's part, the
 * held updates' entries, and the number of pieces. */
typedef struct ls_ldlt_split_stats {
    uint64_t work, top_work, max_load, held_entries;
    uint32_t pieces;
} ls_ldlt_split_stats;

/* Below this weight (entries of L plus columns) a plan keeps the solve
 * whole on the calling thread (workers 1): the handing out costs more than
 * it saves (tests/bench/run_split.sh: 0.07 ms solves of a 1,839-vertex mesh). */
#define LS_LDLT_SPLIT_MIN_WORK 32768u

/* ls_ldlt_split_bytes_n: exact arena bytes of ls_ldlt_split_init for an
 * n x n factor and `workers` (1 .. 4096) workers: *object (kept: 24 n + 8 W
 * bytes, rounded) and *peak (object plus the build's scratch, released: 20
 * n + 12 W more). O(1). Errors: LS_ERR_INVALID, LS_ERR_TOO_LARGE. */
ls_status ls_ldlt_split_bytes_n(uint32_t n, uint32_t workers, size_t *object, size_t *peak);

/* ls_ldlt_split_init: the plan for factor f (factored at least once: the
 * pattern of L comes with the numeric factor) and `workers` workers.
 * O(nnz(L) + n log n). Errors: LS_ERR_INVALID (NULL, workers 0 or above 4096),
 * LS_ERR_STATE (not factored), LS_ERR_TOO_LARGE, LS_ERR_NOMEM (arena and *sp unchanged). */
ls_status ls_ldlt_split_init(ls_ldlt_split *sp, const ls_ldlt *f, uint32_t workers, ls_arena *arena);

/* ls_ldlt_split_get_stats: the plan's shares of the work (sp made for f). O(n).
 * Errors: LS_ERR_INVALID (NULL, sizes differ). */
ls_status ls_ldlt_split_get_stats(const ls_ldlt_split *sp, const ls_ldlt *f, ls_ldlt_split_stats *stats);

/* ls_ldlt_solve_split: ls_ldlt_solve(f, 3, x, arena) with its two passes'
 * pieces run as sp->workers tasks of par (NULL, or run NULL: on this
 * thread); sp NULL or of one worker: the whole solve. The gather, the scatter and
 * the held updates run on the workers too; T on the calling thread. Same
 * scratch and errors as
 * ls_ldlt_solve, plus LS_ERR_INVALID when sp is not of f's size. */
ls_status ls_ldlt_solve_split(const ls_ldlt *f, const ls_ldlt_split *sp, const ls_parallel *par, ls_real *x,
                              ls_arena *arena);

/* ls_ldlt_refine_bytes: exact scratch bytes of ls_ldlt_refine (2 n k reals). */
ls_status ls_ldlt_refine_bytes(const ls_ldlt *f, uint32_t k, size_t *bytes);

/* ls_ldlt_refine: `steps` rounds of iterative refinement of x (n x k, a
 * solution of A x = b from ls_ldlt_solve): r = b - A x in working precision,
 * x += A^{-1} r. Improves the backward error to a few epsilon (it cannot beat
 * the forward error bound kappa * epsilon). Time steps * (2 nnz(A) + 4
 * nnz(L)) k. Errors: as ls_ldlt_solve, plus LS_ERR_INVALID if a's size
 * differs from the factor's. */
ls_status ls_ldlt_refine(const ls_ldlt *f, const ls_csc *a, uint32_t k, const ls_real *b, ls_real *x,
                         uint32_t steps, ls_arena *arena);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_LDLT_H */
