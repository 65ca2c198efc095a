/* largesteps/param.h - the large-steps parameterization: differential
 * coordinates u = M x with M = I + lambda L (or (1 - alpha) I + alpha L),
 * their inverse, the adjoint, and preconditioned gradient steps, on a mesh
 * (ls_param_init) or on a texture grid (ls_param_grid_init).
 *
 * An ls_param holds a Laplacian L (borrowed: its arrays must outlive the
 * object), the system matrix M (its own values, L's pattern), the weight and
 * one of two solvers, chosen at init:
 *   LS_PARAM_LDLT  a sparse LDL^T factor of M (ldlt.h), ordered with
 *                  LS_ORDER_AUTO (AMD or geometric nested dissection) when
 *                  vertex coordinates are given, else cfg->order;
 *   LS_PARAM_CG    Jacobi-preconditioned CG (cg.h): memory O(nnz(M)), with
 *                  separate warm starts for the forward solve and the
 *                  adjoint solve (as the reference keeps them), each
 *                  starting from the previous solution of its kind.
 *   LS_PARAM_GRID  texture grids only: the exact transform solver of
 *                  grid_solve.h (cosine / Fourier transforms, O(n log n) per
 *                  solve, O(W + H) memory besides the vectors; any finite
 *                  lambda, no LS_ERR_NOT_SPD);
 *   LS_PARAM_AUTO  LS_PARAM_GRID on a grid, LS_PARAM_LDLT on a mesh.
 * On a grid (ls_param_grid_init) the object builds and owns the grid
 * Laplacian (ls_laplacian_grid_wrap, upper storage) for LDLT and CG, whose
 * ordering gets the texel centres (x, y, 0) as coordinates; the transform
 * solver needs no matrix (M x by the 5-point stencil).
 * Vectors are n x k interleaved (k = 3 for x, y, z or RGB; 1 for the 1D toy).
 *
 *   to_differential     u = M x
 *   from_differential   x = M^{-1} u
 *   adjoint             dloss/du = M^{-1} dloss/dx (M is symmetric)
 *   step                x <- x - eta M^{-p} g, p = 1, 2, ... (the paper's
 *                       direct preconditioned descent)
 *   set_weight          a new lambda/alpha: M's values rewritten and the
 *                       factor refactored numerically (no memory, the
 *                       symbolic analysis is kept)
 *
 * Extremes. A weight of 0 makes M = I and every solve and product a copy:
 * x = u bit for bit (also -0 and the payload of every value). Large weights
 * follow laplacian.h: when the identity term rounds away (uniform mesh
 * Laplacian: lambda >~ 3e6 in float, >~ 1.5e15 in double) init and
 * set_weight return LS_ERR_NOT_SPD; below that, the LDL^T may still return
 * LS_ERR_NOT_SPD for a pivot lost to rounding. Measured on the bunny
 * (tests/test_param.c): lambda = 1e8 is LS_ERR_NOT_SPD in float (at init or
 * set_weight) and solves in double (round-trip error ~1e-8); alpha =
 * 0.999999 (lambda ~ 1e6) solves in double (~3e-11) and gives a finite but
 * inaccurate result in float (round-trip error ~7e-2: kappa * eps > 1; keep
 * lambda <= ~1e4 in float for accuracy). No call returns NaN: solves check
 * their inputs and results (LS_ERR_NONFINITE).
 */
#ifndef LARGESTEPS_PARAM_H
#define LARGESTEPS_PARAM_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/sparse.h>
#include <largesteps/ldlt.h>
#include <largesteps/cg.h>
#include <largesteps/laplacian.h>
#include <largesteps/grid_solve.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Solvers. */
#define LS_PARAM_LDLT 0u
#define LS_PARAM_CG   1u
#define LS_PARAM_AUTO 2u /* grid: LS_PARAM_GRID; mesh: LS_PARAM_LDLT */
#define LS_PARAM_GRID 3u /* texture grids: the transform solver (grid_solve.h) */

typedef struct ls_param_config {
    uint32_t solver;     /* LS_PARAM_LDLT, _CG, _AUTO or (grids) _GRID */
    uint32_t form;       /* LS_SYSTEM_LAMBDA or LS_SYSTEM_ALPHA */
    ls_real weight;      /* lambda (>= 0) or alpha (in [0, 1)) */
    uint32_t k;          /* columns of the vectors, 1 .. LS_CG_MAX_K */
    uint32_t order;      /* LDL^T ordering without coordinates (LS_ORDER_AMD, _NATURAL) */
    uint32_t cg_max_iter;/* CG iteration cap per solve */
    ls_real cg_tol;      /* CG relative tolerance */
    uint32_t workers;    /* LDL^T, k = 3: > 1 splits its solves over the caller's workers
                          * (ls_ldlt_split: the same bits; 0 or 1: none; at most 4096) */
    const ls_parallel *parallel; /* their parallel-for (copied by the init; NULL: this thread) */
} ls_param_config;

/* The split of the LDL^T's solves (config.workers > 1). */
typedef struct ls_param_split {
    ls_ldlt_split plan;
    ls_parallel parallel;
} ls_param_split;

typedef struct ls_param {
    ls_csc lap;          /* the Laplacian (arrays borrowed; on a grid owned); unused by GRID */
    ls_csc m;            /* the system matrix: lap's pattern, own values */
    uint32_t n, k, solver, form; /* solver as resolved: LDLT, CG or GRID, never AUTO */
    ls_real weight;
    uint32_t identity;   /* 1 when weight = 0: M = I, solves are copies */
    ls_ldlt f;           /* LS_PARAM_LDLT: the factor */
    struct ls_param_split *split; /* LS_PARAM_LDLT with workers > 1: the solves' plan and
                          * parallel-for, in the object's memory (else NULL) */
    ls_cg_info cg;       /* LS_PARAM_CG: cap and tolerance, statistics of the last solve */
    ls_real *warm_fwd;   /* LS_PARAM_CG: n k, last from_differential result */
    ls_real *warm_adj;   /* LS_PARAM_CG: n k, last adjoint result */
    ls_real *tmp;        /* n k: the step's direction */
    ls_arena work;       /* the solvers' scratch, over a block the object owns */
    uint32_t grid;       /* 1: built by ls_param_grid_init */
    uint32_t width, height, wrap_u; /* the grid (wrap_u as effective) */
    ls_grid_solver gs;   /* LS_PARAM_GRID: the transform solver */
} ls_param;

/* ls_param_config_default: the paper's settings for a mesh: the LDL^T,
 * M = I + lambda L with lambda = 19, k = 3 (x, y, z), ordering LS_ORDER_AUTO
 * (AMD without coordinates), and for LS_PARAM_CG a cap of 1000 iterations
 * and a relative tolerance of 1e-6. Start from it and change what you need.
 * O(1). NULL is ignored. */
void ls_param_config_default(ls_param_config *cfg);

/* ls_param_mesh_bytes: the exact arena bytes of ls_param_init_mesh with
 * these arguments, the Laplacian included: an arena with this many free
 * bytes builds the object, one with fewer fails with LS_ERR_NOMEM and
 * leaves the arena and *p unchanged. The query builds the Laplacian and runs
 * the LDL^T's symbolic analysis in `scratch` (released before return): it
 * needs at most as many free bytes there as it answers, so the arena you
 * will build in serves. Cost: the Laplacian and one analysis. Errors:
 * LS_ERR_INVALID (NULL, a bad config), LS_ERR_MESH (a face index out of
 * range), LS_ERR_TOO_LARGE, LS_ERR_NOMEM (scratch too small). */
ls_status ls_param_mesh_bytes(const ls_mesh *mesh, const ls_param_config *cfg, ls_arena *scratch, size_t *bytes);

/* ls_param_init_mesh: the parameterization of a triangle mesh in one call,
 * as the reference's compute_matrix: builds the mesh's uniform Laplacian
 * (laplacian.h, upper storage; owned by the object, kept at the bottom of
 * the arena below it) and then ls_param_init with the mesh's positions as
 * the ordering's coordinates. Memory: ls_param_mesh_bytes. Errors: as
 * ls_laplacian_uniform and ls_param_init; on failure the arena and *p are
 * as before. */
ls_status ls_param_init_mesh(ls_param *p, const ls_mesh *mesh, const ls_param_config *cfg, ls_arena *arena,
                             ls_diag *diag);

/* ls_param_bytes: exact arena bytes of ls_param_init with these arguments.
 * For the LDL^T the factor's size depends on the ordering, so the query runs
 * the symbolic analysis in `scratch` (it needs ls_ldlt_analyze_mesh_bytes /
 * ls_ldlt_analyze_bytes of free space there, released before return, and
 * costs one analysis); for CG scratch may be NULL. O(nnz) plus the analysis.
 * Errors: LS_ERR_INVALID (NULL, a bad config), LS_ERR_TOO_LARGE,
 * LS_ERR_NOMEM (scratch too small). */
ls_status ls_param_bytes(const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz, ls_arena *scratch,
                         size_t *bytes);

/* ls_param_bytes_fill: ls_param_bytes, and *factor_nnz (optional) = the
 * entries below the diagonal of the LDL^T factor that ls_param_init would
 * build (0 for CG), from the same analysis. Same cost, memory and errors. */
ls_status ls_param_bytes_fill(const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz, ls_arena *scratch,
                              size_t *bytes, uint32_t *factor_nnz);

/* ls_param_bytes_bound: the bytes of ls_param_init (mesh) for any Laplacian
 * of n columns with at most nnz stored entries whose LDL^T factor has at
 * most factor_nnz entries below the diagonal (ignored for CG);
 * with_coords: 1 when init will get vertex coordinates (the ordering
 * cfg->order then; else as ls_param_init without them). Exact for upper
 * storage at those counts, never smaller for smaller counts; for sizing a
 * job before its meshes exist (fit.h). O(1); no memory. Errors:
 * LS_ERR_INVALID (NULL, a bad config), LS_ERR_TOO_LARGE. */
ls_status ls_param_bytes_bound(uint32_t n, uint32_t nnz, uint32_t factor_nnz, const ls_param_config *cfg,
                               int with_coords, size_t *bytes);

/* ls_param_init: builds *p for the Laplacian lap (square, every diagonal
 * entry stored; upper or full storage) and cfg; xyz (n x 3, optional) are
 * the vertex coordinates for the ordering. Builds M, analyzes and factors it
 * (LDL^T) or prepares the CG (zero warm starts). Cost: the analysis and the
 * factorization (LDL^T) or O(nnz) (CG). Memory: ls_param_bytes from the
 * arena's bottom. Errors: LS_ERR_INVALID (NULL, cfg out of range: solver,
 * form, weight, k, and with CG cg_max_iter = 0 or a negative tol;
 * diag->what names the argument or field and its allowed range,
 * diag->value holds the value), LS_ERR_NOT_SPD (the weight is too large for
 * the precision, or a pivot failed), LS_ERR_NONFINITE, LS_ERR_NOMEM; on
 * failure the arena and *p are as before. On success *diag is cleared (as
 * by every init and set_weight call here). */
ls_status ls_param_init(ls_param *p, const ls_csc *lap, const ls_param_config *cfg, const ls_real *xyz,
                        ls_arena *arena, ls_diag *diag);

/* ls_param_grid_bytes: exact arena bytes of ls_param_grid_init with these
 * arguments. GRID: ls_grid_solver_bytes plus n k reals (the step's buffer),
 * scratch may be NULL. LDLT: the grid Laplacian, then as ls_param_bytes: the
 * query builds the Laplacian and the texel coordinates in `scratch` and runs
 * the symbolic analysis there (needs ls_laplacian_grid_wrap_bytes + 3 n
 * reals + ls_ldlt_analyze_mesh_bytes, released before return). CG: the
 * Laplacian and as ls_param_bytes (scratch holds the Laplacian for the
 * query). Errors: LS_ERR_INVALID (NULL, zero width or height, cfg out of
 * range), LS_ERR_TOO_LARGE, LS_ERR_NOMEM (scratch too small). */
ls_status ls_param_grid_bytes(const ls_grid_shape *shape, const ls_param_config *cfg, ls_arena *scratch,
                              size_t *bytes);

/* ls_param_grid_init: builds *p for a texture grid (shape: width x height
 * texels, wrap_u for a texture that wraps around in u) and cfg, after which
 * every ls_param_* call below works as on a mesh. GRID (or AUTO): the
 * transform solver, O((W + H) log) to build, any finite lambda (alpha <
 * 1). LDLT / CG: the grid Laplacian built and owned, then as ls_param_init
 * (the LDL^T ordered with cfg->order, which may be LS_ORDER_AUTO or _ND:
 * the texel centres are the coordinates). Memory: ls_param_grid_bytes from
 * the arena's bottom (coordinates in scratch during the analysis). Errors:
 * as ls_param_init (LS_ERR_INVALID also for a zero width or height);
 * on failure the arena and *p are as before. */
ls_status ls_param_grid_init(ls_param *p, const ls_grid_shape *shape, const ls_param_config *cfg, ls_arena *arena,
                             ls_diag *diag);

/* ls_param_to_differential: u = M x (n x k; u must not overlap x). O(nnz k)
 * (GRID: the 5-point stencil, O(n k)); no memory. Errors: LS_ERR_INVALID. */
ls_status ls_param_to_differential(const ls_param *p, const ls_real *x, ls_real *u);

/* ls_param_from_differential: x = M^{-1} u (n x k; x may equal u). LDL^T:
 * 4 nnz(L) k + O(n k); GRID: O(n k log n) (ls_grid_solver_solve); CG: warm-started from the previous result, statistics
 * in p->cg. No arena (the object's own scratch). Errors:
 * LS_ERR_INVALID, LS_ERR_NONFINITE (u holds a NaN or infinity: x unchanged),
 * LS_ERR_STATE (the factor is invalid), LS_ERR_NOT_SPD (CG breakdown). */
ls_status ls_param_from_differential(ls_param *p, const ls_real *u, ls_real *x);

/* ls_param_adjoint: gu = M^{-1} gx, the gradient with respect to u of a loss
 * whose gradient with respect to x = M^{-1} u is gx (M symmetric). Same
 * solve and errors as ls_param_from_differential; CG keeps its own warm
 * start for it. */
ls_status ls_param_adjoint(ls_param *p, const ls_real *gx, ls_real *gu);

/* ls_param_adjoint2: gu = M^{-1} gx (as ls_param_adjoint) and gu2 = M^{-2} gx
 * = M^{-1} gu, for ls_optim_step_mapped (a step on u applied to x = M^{-1} u
 * directly: the large-steps iteration without from_differential). GRID: one
 * forward and two inverse transforms (ls_grid_solver_solve2) instead of the
 * two solves, i.e. four transforms, of adjoint + from_differential; LDL^T and
 * CG: two solves (the second cold). gu2 must be neither gx nor gu. Errors: as
 * ls_param_adjoint. */
ls_status ls_param_adjoint2(ls_param *p, const ls_real *gx, ls_real *gu, ls_real *gu2);

/* ls_param_step: x <- x - eta M^{-power} g (power >= 1), by `power`
 * successive solves of g's copy (warm starts are not used or changed: CG
 * starts from zero). Cost power solves. Errors: LS_ERR_INVALID (power = 0,
 * NULL, eta not finite), as ls_param_from_differential; on failure x is
 * unchanged. */
ls_status ls_param_step(ls_param *p, ls_real *x, const ls_real *g, ls_real eta, uint32_t power);

/* ls_param_set_weight: a new weight of the same form: M's values are
 * rewritten and the factor refactored (ls_ldlt_refactor, no memory); CG
 * keeps its warm starts; GRID: O(1) (ls_grid_solver_set_weight). O(nnz) plus
 * one numeric factorization. Errors: as
 * ls_laplacian_system_update and ls_ldlt_refactor; on any failure the object
 * keeps its previous weight and a valid factor (it is refactored again). */
ls_status ls_param_set_weight(ls_param *p, ls_real weight, ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_PARAM_H */
