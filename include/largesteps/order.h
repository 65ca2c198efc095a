/* largesteps/order.h - fill-reducing orderings for sparse symmetric matrices.
 *
 * An ordering is a permutation perm of 0..n-1, new index -> old index: the
 * factorization eliminates old variable perm[0] first. Only the pattern of a
 * matrix is read: its strictly upper entries (row < col) stand for the
 * symmetric graph (a matrix storing both triangles gives the same graph).
 *
 * ls_order_amd is an approximate minimum degree ordering written for this
 * library after Amestoy, Davis and Duff (SIAM J. Matrix Anal. Appl. 17(4),
 * 1996): quotient graph with elements, approximate external degrees,
 * supervariables detected by hashing, mass elimination, element absorption
 * and aggressive absorption. Iterative (no recursion); all workspace comes from
 * the top of the arena and is released on return.
 */
#ifndef LARGESTEPS_ORDER_H
#define LARGESTEPS_ORDER_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/sparse.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Ordering methods for the solver (uint32_t, not an enum: see DESIGN.md). */
#define LS_ORDER_NATURAL 0u /* identity permutation */
#define LS_ORDER_AMD     1u /* approximate minimum degree */
#define LS_ORDER_GIVEN   2u /* the caller supplies perm */
#define LS_ORDER_ND      3u /* geometric nested dissection (needs vertex coordinates) */
#define LS_ORDER_AUTO    4u /* AMD or ND, whichever predicts the smaller nnz(L) */

/* ls_order_bytes: the exact scratch bytes ls_order_amd takes for a square
 * matrix with n columns and nnz stored entries (a function of n and nnz
 * only). O(1). Errors: LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE. */
ls_status ls_order_bytes(uint32_t n, uint32_t nnz, size_t *bytes);

/* ls_order_amd: writes an approximate minimum degree ordering of the graph of
 * the square matrix a into perm (n entries, new -> old). Deterministic (ties
 * broken by index order). Time about O(nnz(L)) in practice (no proven bound);
 * scratch ls_order_bytes(n, nnz), all released on return, nothing kept.
 * Errors: LS_ERR_INVALID (NULL, not square, a row index out of range),
 * LS_ERR_TOO_LARGE (n >= 2^30), LS_ERR_NOMEM (arena unchanged). */
ls_status ls_order_amd(const ls_csc *a, ls_arena *arena, uint32_t *perm, ls_diag *diag);

/* ls_order_nd_bytes: exact scratch bytes of ls_order_nd_geom for n columns and
 * nnz stored entries. O(1). Errors: LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE. */
ls_status ls_order_nd_bytes(uint32_t n, uint32_t nnz, size_t *bytes);

/* ls_order_nd_geom: geometric nested dissection for a matrix whose variables
 * are mesh vertices with coordinates xyz (n x 3, row-major). Each vertex set
 * is cut at the median of its projection on one of 10 directions (its
 * principal direction by power iteration on the covariance, the 3 axes, the 6
 * face diagonals; for sets of at most 100 vertices the first 4), keeping the
 * direction whose smaller boundary is smallest; that boundary is the
 * separator, then refined on the graph (greedy vertex moves that shrink it or
 * keep its size while improving balance, parts kept within 3/4). Sets of at
 * most 16 vertices are leaves. The final order is a constrained minimum
 * degree on the whole graph: all leaf vertices first, then each separator
 * after the separators inside it, minimum degree within each set (as
 * CHOLMOD's NESDIS does with CAMD). nnz(L) is within 1.6 % of CHOLMOD with
 * METIS on icospheres of 2.5k-164k vertices and 0.3 % on a 400 x 400 grid
 * (tests/bench/run_ldlt.sh), 20-36 % below minimum degree's. Deterministic;
 * about O(n log n + nnz log n) plus the minimum degree; scratch
 * ls_order_nd_bytes, released; no recursion. Errors: LS_ERR_INVALID,
 * LS_ERR_NONFINITE (a coordinate; diag index = vertex), LS_ERR_TOO_LARGE,
 * LS_ERR_NOMEM (arena unchanged). */
ls_status ls_order_nd_geom(const ls_csc *a, const ls_real *xyz, ls_arena *arena, uint32_t *perm, ls_diag *diag);

/* ls_order_is_perm: 1 when perm holds each of 0..n-1 exactly once, else 0.
 * O(n); `mark` is caller workspace of n bytes (not read on input). */
int ls_order_is_perm(uint32_t n, const uint32_t *perm, unsigned char *mark);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_ORDER_H */
