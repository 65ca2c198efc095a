/* largesteps/grid_solve.h - the exact fast solver of M x = b for the grid
 * Laplacian of a W x H texture, by diagonalizing M with transforms.
 *
 * M = s I + w L (laplacian.h: LS_SYSTEM_LAMBDA s = 1, w = lambda;
 * LS_SYSTEM_ALPHA s = 1 - alpha, w = alpha) with L the 4-neighbour grid
 * Laplacian of ls_laplacian_grid_wrap (vertex (x, y) at index y W + x):
 *   wrap = 0  Neumann ends in both directions: L = Lx (+) Ly with the path
 *             Laplacians of W and H points, diagonalized by the cosine
 *             transform (DCT-II forward, its exact inverse back): eigenvalues
 *             2 - 2 cos(pi k / N) = 4 sin^2(pi k / 2N);
 *   wrap = 1  x wraps around (a UV sphere's texture: (0, y) and (W - 1, y)
 *             are neighbours; effective from W = 3): a real Fourier transform
 *             in x (eigenvalues 4 sin^2(pi k / W)), the cosine transform in y.
 * x = T^-1 diag(1 / (s + w (mu_x + mu_y))) T b, exact up to rounding: no
 * iteration, no tolerance, and the constant mode is solved exactly at any
 * weight (unlike the sparse solvers, a huge lambda is no error).
 *
 * Transforms: our own complex FFT, iterative radix 2 (stages fused in
 * pairs), for any length N: a
 * power of two directly, other lengths by Bluestein's chirp z-transform on a
 * power of two >= 2N - 1; cosine transforms by Makhoul's reordering through
 * one FFT of length N; two lines of one channel share one complex FFT.
 * Twiddles come from ls_sin/ls_cos (math.h): the same bits on every target.
 * Vectors are n x k interleaved (k channels, n = W H, entry (i, c) at
 * v[i k + c]); every channel is transformed on its own, in a fixed order.
 *
 * Cost of a solve: O(n k log n): per channel, a forward and an inverse
 * complex FFT of length W (or its Bluestein length) per 2 rows and of length
 * H per 2 columns. Measured figures: tests/bench/run_grid.sh (make bench,
 * build/bench/grid.md).
 * Memory: O(W + H k) (twiddle, chirp and eigenvalue tables, line buffers,
 * a block of 8 columns); the solve works in place in the caller's vector and
 * needs no arena.
 *
 * Accuracy (tests/test_grid_solve.c, grids up to 100 x 60, lambda <= 10 or
 * alpha 0.95): relative difference to the sparse LDL^T and to CG <= 1.4e-14
 * in double; in float <= 8e-7 against a double dense solve (<= 3.5e-6 to the
 * float LDL^T, whose own error is larger).
 */
#ifndef LARGESTEPS_GRID_SOLVE_H
#define LARGESTEPS_GRID_SOLVE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The largest grid side (the Bluestein length 2^k >= 2N - 1 must fit in
 * uint32_t with room). */
#define LS_GRID_MAX_SIDE (1u << 28)

/* A texture grid: width x height texels, texel (x, y) at index y width + x;
 * wrap_u nonzero when x wraps around (effective from width = 3). */
typedef struct ls_grid_shape {
    uint32_t width;
    uint32_t height;
    uint32_t wrap_u;
} ls_grid_shape;

/* One direction's transform tables. Arrays of complex numbers hold (re, im)
 * pairs of ls_real. */
typedef struct ls_grid_fft {
    uint32_t n;      /* points in this direction */
    uint32_t p;      /* FFT length: n if a power of two, else the Bluestein length */
    uint32_t dct;    /* 1: cosine transform (Neumann); 0: real Fourier transform (wrap) */
    uint32_t pad_;
    ls_real *tw;     /* p/2 complex: e^{-2 pi i j / p} */
    ls_real *chirp;  /* Bluestein: n complex e^{-i pi j^2 / n}; NULL if p == n */
    ls_real *filt;   /* Bluestein: p complex, the FFT of the conjugate chirp over p; NULL if p == n */
    ls_real *post;   /* cosine: n complex e^{-i pi k / 2n}; NULL for Fourier */
    ls_real *mu;     /* n: the 1-D Laplacian's eigenvalue of each transform output */
} ls_grid_fft;

typedef struct ls_grid_solver {
    uint32_t width, height; /* W, H */
    uint32_t wrap;          /* 1 if x wraps around (W >= 3 and asked for) */
    uint32_t k;             /* channels */
    uint32_t form;          /* LS_SYSTEM_LAMBDA or LS_SYSTEM_ALPHA */
    uint32_t identity;      /* 1 when weight = 0: solves are copies */
    ls_real weight;         /* lambda or alpha */
    ls_real shift;          /* s: 1 or 1 - alpha */
    ls_grid_fft fx, fy;     /* the x and y transforms */
    ls_real *line;          /* max(W, H) complex: two lines being transformed */
    ls_real *work;          /* Bluestein: the larger p complex; NULL if none */
    ls_real *block;         /* H x block_w x k: a block of columns being transformed */
    uint32_t block_w;       /* columns per block: min(W, 8) */
    uint32_t pad_;
} ls_grid_solver;

/* ls_grid_solver_bytes: exact arena bytes of ls_grid_solver_init with these
 * arguments: twiddles, Bluestein chirp and filter, cosine post-twiddles,
 * eigenvalues, line buffers and a block of min(W, 8) columns of k channels,
 * O(W + H k). O(1).
 * Errors: LS_ERR_INVALID (NULL, width or height 0 or above
 * LS_GRID_MAX_SIDE, k = 0), LS_ERR_TOO_LARGE (W H k >= 2^32 or the bytes
 * overflow). */
ls_status ls_grid_solver_bytes(uint32_t width, uint32_t height, uint32_t wrap, uint32_t k, size_t *bytes);

/* ls_grid_solver_init: builds *g for a width x height grid (wrap: x wraps
 * around, see above), k channels, weight 0 (M = I) of LS_SYSTEM_LAMBDA form:
 * call ls_grid_solver_set_weight next. Cost O((W + H) log(W + H)) (tables,
 * the Bluestein filters' FFTs). Memory: ls_grid_solver_bytes from the
 * arena's bottom, no scratch. Errors: as ls_grid_solver_bytes,
 * LS_ERR_INVALID for a NULL g or arena, LS_ERR_NOMEM; on failure the arena
 * and *g are as before. */
ls_status ls_grid_solver_init(ls_grid_solver *g, uint32_t width, uint32_t height, uint32_t wrap, uint32_t k,
                              ls_arena *arena);

/* ls_grid_solver_set_weight: M = s I + w L for `form` (LS_SYSTEM_LAMBDA:
 * lambda finite >= 0; LS_SYSTEM_ALPHA: alpha in [0, 1)). No memory, O(1)
 * (the eigenvalue tables do not depend on the weight). Errors:
 * LS_ERR_INVALID (NULL, unknown form, weight out of range or NaN; diag says
 * which); on failure *g is unchanged. */
ls_status ls_grid_solver_set_weight(ls_grid_solver *g, uint32_t form, ls_real weight, ls_diag *diag);

/* ls_grid_solver_solve: x = M^{-1} b (n x k; x may equal b: in place). A
 * weight of 0 copies b bit for bit. Cost O(n k log n); no arena (the
 * object's line buffers: one solver object serves one solve at a time).
 * Errors: LS_ERR_INVALID (NULL), LS_ERR_NONFINITE (b holds a NaN or
 * infinity: x unchanged; or the result overflowed, |b| near LS_REAL_MAX /
 * n: x is then set to zero). */
ls_status ls_grid_solver_solve(ls_grid_solver *g, const ls_real *b, ls_real *x);

/* ls_grid_solver_solve2: x1 = M^{-1} b and x2 = M^{-2} b for the price of
 * one forward and two inverse transforms (two solves take two of each).
 * x1 may equal b; x2 must overlap neither. x1 is bit for bit what
 * ls_grid_solver_solve gives; x2 agrees with two solves to rounding.
 * Errors: as ls_grid_solver_solve (both outputs), LS_ERR_INVALID also for
 * x2 equal to x1 or b (a partial overlap is not detected). */
ls_status ls_grid_solver_solve2(ls_grid_solver *g, const ls_real *b, ls_real *x1, ls_real *x2);

/* ls_grid_solver_apply: y = M x by the 5-point stencil (n x k; y must not
 * overlap x), the neighbours summed in the order -y, -x, +x, +y. O(n k); no
 * memory. Errors: LS_ERR_INVALID (NULL). */
ls_status ls_grid_solver_apply(const ls_grid_solver *g, const ls_real *x, ls_real *y);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_GRID_SOLVE_H */
