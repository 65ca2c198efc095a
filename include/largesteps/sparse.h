/* largesteps/sparse.h - compressed sparse column (CSC) matrices.
 *
 * An ls_csc holds an nrows x ncols matrix column by column: the entries of
 * column j are rowidx[colptr[j] .. colptr[j+1]-1] with values in the same
 * positions. Matrices built here have each column's rows strictly ascending
 * (no duplicates). Indices and counts are uint32_t: at most UINT32_MAX - 1
 * rows, columns and entries (larger gives LS_ERR_TOO_LARGE).
 *
 * Symmetric matrices are used by the solver through their upper triangle
 * (entries with row <= col); a matrix that stores both triangles works too,
 * its strictly lower entries are then ignored by the symmetric routines.
 *
 * Dense right-hand sides and products are n x k blocks stored row-major
 * ("interleaved"): entry (i, c) at x[i * k + c]; k = 3 holds x, y, z.
 */
#ifndef LARGESTEPS_SPARSE_H
#define LARGESTEPS_SPARSE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ls_csc {
    uint32_t nrows;
    uint32_t ncols;
    uint32_t capacity;  /* entries allocated in rowidx/values (>= nnz) */
    uint32_t *colptr;   /* ncols + 1 entries; colptr[ncols] = nnz */
    uint32_t *rowidx;   /* row of each entry */
    ls_real *values;    /* value of each entry */
} ls_csc;

/* ls_csc_nnz: the number of stored entries, colptr[ncols] (0 for NULL). O(1). */
uint32_t ls_csc_nnz(const ls_csc *a);

/* ls_csc_from_triplets_bytes: exact arena bytes of ls_csc_from_triplets for
 * these sizes (object plus scratch); depends only on the sizes. O(1).
 * Errors: LS_ERR_INVALID (NULL bytes), LS_ERR_TOO_LARGE. */
ls_status ls_csc_from_triplets_bytes(uint32_t nrows, uint32_t ncols, size_t count, size_t *bytes);

/* Entries of an nrows x ncols matrix as triplets (rows[t], cols[t], vals[t]),
 * t < count; vals may be NULL (pattern only: every value is 1). */
typedef struct ls_triplets {
    uint32_t nrows, ncols;
    size_t count;
    const uint32_t *rows, *cols;
    const ls_real *vals;
} ls_triplets;

/* ls_csc_from_triplets: builds *out from the `count` triplets of t (rows[t], cols[t],
 * vals[t]); duplicates are summed in input order, rows come out sorted in each
 * column. Deterministic: a stable two-pass bucket sort, O(nrows + ncols + count).
 * vals may be NULL (pattern only: every value is 1). The object holds
 * `count` entries of capacity. Errors: LS_ERR_INVALID (NULL arguments, an
 * index out of range: ls_diag index = the triplet), LS_ERR_TOO_LARGE,
 * LS_ERR_NOMEM (arena and *out unchanged). */
ls_status ls_csc_from_triplets(const ls_triplets *t, ls_arena *arena, ls_csc *out, ls_diag *diag);

/* ls_csc_triangle_bytes: exact bytes of ls_csc_triangle(a, upper). O(ncols)
 * plus a pass over the row indices. */
ls_status ls_csc_triangle_bytes(const ls_csc *a, int upper, size_t *bytes);

/* ls_csc_triangle: *out = the upper (upper != 0: row <= col) or lower
 * (row >= col) triangle of a, diagonal included. O(nnz). Errors:
 * LS_ERR_INVALID, LS_ERR_NOMEM (nothing changed). */
ls_status ls_csc_triangle(const ls_csc *a, int upper, ls_arena *arena, ls_csc *out);

/* ls_csc_symperm_bytes: exact bytes of ls_csc_symperm(a). O(ncols + nnz). */
ls_status ls_csc_symperm_bytes(const ls_csc *a, size_t *bytes);

/* ls_csc_symperm: for a square symmetric a given by its upper triangle and a
 * permutation perm (new index -> old index, n entries), *out = the upper
 * triangle of P A P^T, i.e. out(i, j) = a(perm[i], perm[j]), rows sorted in
 * each column. O(n + nnz); scratch 2n indices. Errors: LS_ERR_INVALID (not
 * square, NULL, perm not a permutation), LS_ERR_NOMEM (nothing changed). */
ls_status ls_csc_symperm(const ls_csc *a, const uint32_t *perm, ls_arena *arena, ls_csc *out);

/* ls_csc_matvec: y = A x for an n x k interleaved block x (ncols x k) giving y
 * (nrows x k). y must not overlap x. O(nnz * k), no memory. Errors:
 * LS_ERR_INVALID. */
ls_status ls_csc_matvec(const ls_csc *a, uint32_t k, const ls_real *x, ls_real *y);

/* ls_csc_matvec_sym: y = A x for a square symmetric A read from its upper
 * triangle (entries with row > col are ignored). O(nnz * k); no memory.
 * Errors: LS_ERR_INVALID (NULL, not square, k = 0). */
ls_status ls_csc_matvec_sym(const ls_csc *a, uint32_t k, const ls_real *x, ls_real *y);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_SPARSE_H */
