/* ldlt_internal.h (src/sparse) - the k = 3 solve's passes over column
 * ranges, shared by the whole solve (ldlt_solve.c) and the solve split over
 * subtrees of the elimination tree (ldlt_split.c). Each performs the same
 * operations in the same order as the whole solve does on those columns. */
#ifndef LS_SPARSE_LDLT_INTERNAL_H
#define LS_SPARSE_LDLT_INTERNAL_H

#include <largesteps/ldlt.h>

/* Forward with L and the scaling by 1/D over columns [lo, hi) of w (n x 3):
 * rows >= limit are held back (not updated), and a column that has such
 * rows is not scaled (its owner does both later, ls_ldlt_split's replay). */
void ls_ldlt_fwd3_range(const ls_ldlt *f, ls_acc *w, uint32_t lo, uint32_t hi, uint32_t limit);

/* The forward pass' chunk kernel: subtracts the values wc of m = 1, 2 or 4
 * chained columns (pc: their entries in rows ri[0 .. r)) from those rows
 * of w, the columns in order; and the width of the chunk that starts at
 * column s, not past hi. */
void ls_ldlt_fwd_rows3(uint32_t m, uint32_t r, const uint32_t *ri, const ls_real *const *pc, const ls_acc *wc,
                       ls_acc *w);
uint32_t ls_ldlt_fwd_chunk_width(const ls_ldlt *f, uint32_t s, uint32_t hi);

/* Backward with L^T from column hi - 1 down to lo, chunked as the whole
 * solve's pass would be when it reaches hi. */
void ls_ldlt_bwd3_range(const ls_ldlt *f, ls_acc *w, uint32_t lo, uint32_t hi);

/* The start of the backward pass' chunk that ends at e (> lo), >= lo. */
uint32_t ls_ldlt_back_chunk_start(const ls_ldlt *f, uint32_t lo, uint32_t e);

/* The gather of P b into w and the scatter of w into P^T x over rows
 * [lo, hi); 1 when every value moved is finite. */
int ls_ldlt_gather3(const ls_ldlt *f, const ls_real *x, ls_acc *w, uint32_t lo, uint32_t hi);
int ls_ldlt_scatter3(const ls_ldlt *f, const ls_acc *w, ls_real *x, uint32_t lo, uint32_t hi);

/* The split solve of x in place, w its scratch (n x 3): the gather, the
 * pieces' passes and the scatter on the workers, T and the replay on this
 * thread (ldlt_split.c). LS_ERR_NONFINITE as ls_ldlt_solve. */
ls_status ls_ldlt_split_solve3(const ls_ldlt *f, const ls_ldlt_split *sp, const ls_parallel *par, ls_real *x,
                               ls_acc *w);

#endif /* LS_SPARSE_LDLT_INTERNAL_H */
