/* largesteps/laplacian.h - mesh and grid Laplacians, the large-steps system
 * matrix M, and the Laplacian regularization baselines.
 *
 * Every Laplacian here is L = D - W: W holds the edge weights (w_ij > 0 for
 * an edge), D = diag(sum_j w_ij); rows sum to zero, L is symmetric positive
 * semi-definite. Matrices are ls_csc (sparse.h) with sorted rows and every
 * diagonal entry stored (also for unreferenced vertices, where it is 0), in
 * one of two storages:
 *   LS_LAP_UPPER  the upper triangle (row <= col) with the diagonal: what the
 *                 LDL^T and ls_csc_matvec_sym read; E + n entries;
 *   LS_LAP_FULL   both triangles; 2E + n entries (ls_csc_matvec works too).
 *
 * Weights (the reference implementation, largesteps/geometry.py):
 *   uniform     w_ij = 1 per unique edge: L = D - A, D the vertex degree;
 *   cotangent   w_ij = cot(alpha_ij) + cot(beta_ij), the angles opposite the
 *               edge in its (one or two) faces: the reference's UNHALVED
 *               convention (LS_COT_REFERENCE); LS_COT_HALF gives the usual
 *               (cot alpha + cot beta) / 2. Lambda values do not transfer
 *               between the two (a factor 2).
 *
 * The system matrix of the parameterization (paper eq. and compute_matrix):
 *   LS_SYSTEM_LAMBDA  M = I + lambda L, lambda >= 0;
 *   LS_SYSTEM_ALPHA   M = (1 - alpha) I + alpha L, 0 <= alpha < 1;
 * the two are equal up to scale: M_alpha = (1 - alpha)(I + lambda L) with
 * lambda = alpha / (1 - alpha) (alpha 0.95 <-> lambda 19, 0.99 <-> 99).
 * M keeps L's storage and shares L's pattern arrays (colptr, rowidx); it owns
 * only its values, so a new weight rewrites them in place
 * (ls_laplacian_system_update) and an LDL^T of M can be refactored
 * numerically (ls_ldlt_refactor) on the same symbolic analysis.
 *
 * Large weights: when the identity term rounds away against the Laplacian
 * diagonal (fl(s + w d) == fl(w d) for some vertex of degree d > 0, s = 1 or
 * 1 - alpha), the computed M is the singular w L and no solver can recover
 * the constant component of the solution. The system builders detect exactly
 * that case and return LS_ERR_NOT_SPD (diag: the vertex and the weight),
 * leaving M unchanged. That is lambda * degree >~ 2^25 in float and 2^54 in
 * double: for the uniform Laplacian of a triangle mesh (degrees 3 to 12) from
 * lambda ~ 3e6 to 1e7 in float and ~ 1.5e15 in double; so lambda = 1e8 is an
 * error in float and fine in double. Below that, the LDL^T
 * decides (it may still report LS_ERR_NOT_SPD for a pivot lost to rounding);
 * nothing non-finite is ever returned silently.
 */
#ifndef LARGESTEPS_LAPLACIAN_H
#define LARGESTEPS_LAPLACIAN_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/sparse.h>
#include <largesteps/mesh.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Storage of the built matrices. */
#define LS_LAP_UPPER 0u /* upper triangle with the diagonal */
#define LS_LAP_FULL  1u /* both triangles */

/* Cotangent conventions. */
#define LS_COT_REFERENCE 0u /* w_ij = cot alpha + cot beta (largesteps-pytorch) */
#define LS_COT_HALF      1u /* w_ij = (cot alpha + cot beta) / 2 */

/* Forms of the system matrix. */
#define LS_SYSTEM_LAMBDA 0u /* M = I + lambda L */
#define LS_SYSTEM_ALPHA  1u /* M = (1 - alpha) I + alpha L */

/* The reference's lower bound on a face's squared area (Heron's product
 * s(s-a)(s-b)(s-c) is clamped to at least this): a face below it counts as
 * clamped, its area is taken as sqrt(1e-12) = 1e-6. */
#define LS_COT_MIN_AREA2 ((ls_real)1e-12)

/* ls_laplacian_bytes: exact arena bytes of ls_laplacian_uniform and
 * ls_laplacian_cot for a mesh with these counts, edge_count being its number
 * of unique edges (ls_mesh_report.edge_count from ls_mesh_validate, or
 * ls_mesh_edges.count): the matrix (E + n or 2E + n entries) plus the peak
 * scratch of the edge extraction (about 48 bytes per face, released). O(1).
 * Errors: LS_ERR_INVALID (NULL, unknown storage), LS_ERR_TOO_LARGE. */
ls_status ls_laplacian_bytes(uint32_t vertex_count, uint32_t face_count, uint32_t edge_count, uint32_t storage,
                             size_t *bytes);

/* ls_laplacian_uniform: *out = the uniform (combinatorial) Laplacian D - A of
 * the mesh's usable faces (ls_mesh_edges_build: faces repeating an index are
 * skipped): -1 per unique edge, the vertex degree on the diagonal; values
 * are small integers, exact in both precisions. n = vertex_count.
 * O(F log F + V). Memory: ls_laplacian_bytes from the arena (the matrix
 * from the bottom, the rest scratch). Errors: LS_ERR_INVALID (NULL, unknown
 * storage), LS_ERR_MESH (a face index out of range; diag->index = face),
 * LS_ERR_TOO_LARGE, LS_ERR_NOMEM; on failure the arena and *out are as before. */
ls_status ls_laplacian_uniform(const ls_mesh *mesh, uint32_t storage, ls_arena *arena, ls_csc *out, ls_diag *diag);

/* ls_laplacian_cot: *out = the cotangent Laplacian of the mesh's usable
 * faces with the given convention (LS_COT_REFERENCE or LS_COT_HALF), same
 * pattern as ls_laplacian_uniform. Per face, with edge vectors from each
 * corner, cot = dot / |cross| where |cross| = 2 area, and area^2 =
 * |cross|^2 / 4 clamped to at least LS_COT_MIN_AREA2 as the reference clamps
 * Heron's product: a zero-area or needle face gives large but finite weights,
 * never Inf or NaN. Faces are accumulated in face order; the diagonal is the
 * sum of the row's final off-diagonal weights (row sums are zero up to the
 * rounding of that sum). *clamped (optional) receives the number of faces
 * whose squared area was clamped. Obtuse angles give negative weights (L is
 * then not an M-matrix, as in the reference). O(F log deg + F log F + V).
 * Memory: ls_laplacian_bytes. Errors: as ls_laplacian_uniform, plus
 * LS_ERR_INVALID for an unknown convention and LS_ERR_NONFINITE for a NaN or
 * infinite coordinate (diag->index = vertex). */
ls_status ls_laplacian_cot(const ls_mesh *mesh, uint32_t convention, uint32_t storage, ls_arena *arena,
                           ls_csc *out, uint32_t *clamped, ls_diag *diag);

/* ls_laplacian_grid_bytes: exact arena bytes of ls_laplacian_grid. O(1).
 * Errors: LS_ERR_INVALID (NULL, nx or ny = 0, unknown storage),
 * LS_ERR_TOO_LARGE (nx * ny >= 2^32 or the entries overflow). */
ls_status ls_laplacian_grid_bytes(uint32_t nx, uint32_t ny, uint32_t storage, size_t *bytes);

/* ls_laplacian_grid: *out = the uniform Laplacian of the 4-neighbour graph of
 * an nx x ny grid, vertex (x, y) at index y * nx + x: -1 per neighbour, the
 * number of neighbours (2 to 4) on the diagonal. ny = 1 gives the path graph
 * of nx points (degree 1 at the ends, 2 inside). O(nx ny); no scratch.
 * Errors: as ls_laplacian_grid_bytes, LS_ERR_NOMEM (arena, *out unchanged). */
ls_status ls_laplacian_grid(uint32_t nx, uint32_t ny, uint32_t storage, ls_arena *arena, ls_csc *out);

/* ls_laplacian_grid_wrap_bytes, ls_laplacian_grid_wrap: as ls_laplacian_grid
 * with, when wrap_x is nonzero, the two ends of every row joined: (0, y) and
 * (nx - 1, y) are neighbours (a texture that wraps around in u, a UV
 * sphere), so every vertex has 2 neighbours in x. The wrap takes effect from
 * nx = 3 on (for nx <= 2 the ends are the same vertex or already
 * neighbours: the result equals ls_laplacian_grid's). wrap_x = 0 gives
 * exactly ls_laplacian_grid. Cost, memory and errors as ls_laplacian_grid. */
ls_status ls_laplacian_grid_wrap_bytes(uint32_t nx, uint32_t ny, uint32_t wrap_x, uint32_t storage, size_t *bytes);
ls_status ls_laplacian_grid_wrap(uint32_t nx, uint32_t ny, uint32_t wrap_x, uint32_t storage, ls_arena *arena,
                                 ls_csc *out);

/* ls_laplacian_system_bytes: exact arena bytes of ls_laplacian_system: the
 * values of M, nnz(L) reals (the pattern is shared with L). O(1). Errors:
 * LS_ERR_INVALID, LS_ERR_TOO_LARGE. */
ls_status ls_laplacian_system_bytes(const ls_csc *lap, size_t *bytes);

/* ls_laplacian_system: *m = the system matrix of `form` with `weight`
 * (lambda or alpha, see above) for the square Laplacian lap, which must store
 * every diagonal entry: m->colptr and m->rowidx point at lap's arrays (keep
 * them alive), m->values are new: M_jj = s + w L_jj with s = 1 (lambda) or
 * 1 - alpha (computed once, in ls_real), M_ij = w L_ij off the diagonal.
 * O(nnz). Errors: LS_ERR_INVALID (NULL, not square, unknown form, lambda < 0
 * or not finite, alpha outside [0, 1), a column without its diagonal entry:
 * diag->index = column), LS_ERR_NOT_SPD (the identity term rounds away, see
 * the top of this file: diag->index = vertex, value = weight), LS_ERR_NOMEM;
 * on failure the arena and *m are as before. */
ls_status ls_laplacian_system(const ls_csc *lap, uint32_t form, ls_real weight, ls_arena *arena, ls_csc *m,
                              ls_diag *diag);

/* ls_laplacian_system_update: rewrites the values of a matrix m made by
 * ls_laplacian_system(lap, ...) for a new form and weight, in place (no
 * memory); the pattern is unchanged, so an LDL^T of m can be refactored with
 * ls_ldlt_refactor. O(nnz). Errors: as ls_laplacian_system (LS_ERR_INVALID
 * also when m does not share lap's pattern); on failure m is unchanged. */
ls_status ls_laplacian_system_update(const ls_csc *lap, uint32_t form, ls_real weight, ls_csc *m, ls_diag *diag);

/* ls_laplacian_energy: the Laplacian regularizer of the fit loop's baseline,
 * value = w x^T L x summed over the k columns of x (n x k interleaved, L
 * symmetric read through its upper triangle), and its gradient grad =
 * 2 w L x (n x k, must not overlap x). value or grad may be NULL (not
 * computed; grad is needed for the value and is then taken from scratch).
 * The reference's "laplacian" regularizer is mean(x . L x) = value / (n k)
 * with w = 1. O(nnz k). Memory: n k reals of scratch from the arena when
 * grad is NULL (ls_laplacian_energy_bytes), else none (arena may be NULL).
 * Errors: LS_ERR_INVALID (NULL, not square, k = 0), LS_ERR_NOMEM. */
ls_status ls_laplacian_energy(const ls_csc *lap, uint32_t k, const ls_real *x, ls_real w, ls_real *value,
                              ls_real *grad, ls_arena *arena);

/* ls_laplacian_energy_bytes: exact scratch bytes of ls_laplacian_energy and
 * ls_laplacian_bilaplacian with these arguments (has_grad = grad != NULL).
 * O(1). */
ls_status ls_laplacian_energy_bytes(const ls_csc *lap, uint32_t k, int bilaplacian, int has_grad, size_t *bytes);

/* ls_laplacian_bilaplacian: the bilaplacian regularizer value = w ||L x||^2
 * (Frobenius over the k columns) and its gradient grad = 2 w L (L x) (L
 * symmetric). The reference's mean((L v)^2) is value / (n k) with w = 1.
 * O(2 nnz k). value or grad may be NULL. Memory: n k reals of scratch
 * (L x) from the arena, released (ls_laplacian_energy_bytes). Errors: as
 * ls_laplacian_energy. */
ls_status ls_laplacian_bilaplacian(const ls_csc *lap, uint32_t k, const ls_real *x, ls_real w, ls_real *value,
                                   ls_real *grad, ls_arena *arena);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_LAPLACIAN_H */
