/* tests/bench/bench_grid.c - the parameterization on a texture grid: the
 * transform solver (grid_solve.h) against the sparse LDL^T and CG, for
 * M = I + lambda L (4-neighbour grid Laplacian), 3 channels, one thread,
 * CPU time, minimum of REPEAT runs (1 run for the LDL^T above 512^2).
 *
 * usage: bench_grid REPEAT LAMBDA CG_TOL WRAP SIZE...
 * prints one markdown row per (size, solver):
 *   | grid | solver | init ms | solve ms | CG iterations | bytes | vs transform | round trip |
 * then (on stderr, lines starting "RATIO ") one row of ratios per size
 * (LDL^T / transform, CG / transform; init ratio against at least 0.01 ms)
 * and the transform solver's own bytes (ls_grid_solver_bytes: tables and
 * buffers, without the parameterization's n k step buffer):
 *   | grid | LDL^T init | LDL^T solve | LDL^T bytes | CG solve | CG bytes | transform tables bytes |
 * init = ls_param_grid_init (transform: twiddle and eigenvalue tables; LDL^T:
 * grid Laplacian, M, ordering LS_ORDER_AUTO (AMD or nested dissection on the
 * texel centres, whichever predicts less fill), symbolic and numeric factor;
 * CG: the Laplacian, M and buffers). solve = ls_param_from_differential of
 * u = M x for a smooth texture x plus noise, CG from a zero start to CG_TOL
 * relative residual. bytes = ls_param_grid_bytes (the object's arena bytes,
 * the peak of init; the vectors x, u are the caller's and not counted).
 * vs transform = ||x_solver - x_grid|| / ||x_grid||; round trip =
 * ||M^-1 (M x) - x|| / ||x||. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <largesteps.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static double rel(const ls_real *a, const ls_real *b, size_t n)
{
    double e = 0, s = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        e += ((double)a[i] - (double)b[i]) * ((double)a[i] - (double)b[i]);
        s += (double)b[i] * (double)b[i];
    }
    return sqrt(e / s);
}

static const char *solver_name(uint32_t s)
{
    return s == LS_PARAM_GRID ? "transform" : s == LS_PARAM_LDLT ? "LDL^T" : "CG";
}

typedef struct result {
    double init, solve, err, trip;
    size_t bytes;
    uint32_t iters;
} result;

int main(int argc, char **argv)
{
    size_t arena_bytes = (size_t)6 << 30, scratch_bytes = (size_t)2 << 30;
    void *mem = malloc(arena_bytes), *smem = malloc(scratch_bytes);
    int repeat, si;
    double lambda, tol;
    uint32_t wrap;
    if (argc < 6 || mem == NULL || smem == NULL) {
        fprintf(stderr, "usage: bench_grid REPEAT LAMBDA CG_TOL WRAP SIZE...\n");
        return 2;
    }
    repeat = atoi(argv[1]);
    lambda = atof(argv[2]);
    tol = atof(argv[3]);
    wrap = (uint32_t)atoi(argv[4]);
    for (si = 5; si < argc; si++) {
        uint32_t side = (uint32_t)atoi(argv[si]), s, order[3] = {LS_PARAM_GRID, LS_PARAM_LDLT, LS_PARAM_CG};
        size_t n = (size_t)side * side, nk = 3 * n, i;
        ls_grid_shape sh;
        result res[3];
        ls_real *x = (ls_real *)malloc(nk * sizeof(ls_real)), *u = (ls_real *)malloc(nk * sizeof(ls_real));
        ls_real *y = (ls_real *)malloc(nk * sizeof(ls_real)), *xg = (ls_real *)malloc(nk * sizeof(ls_real));
        if (x == NULL || u == NULL || y == NULL || xg == NULL) return 1;
        sh.width = sh.height = side;
        sh.wrap_u = wrap;
        for (i = 0; i < n; i++) {
            double px = (double)(i % side) / side, py = (double)(i / side) / side;
            uint32_t c;
            for (c = 0; c < 3; c++)
                x[3 * i + c] = (ls_real)(0.5 + 0.3 * sin(6.283 * (c + 1) * px) * cos(6.283 * 2 * py) +
                                         0.05 * sin(12.9898 * (double)i + 78.233 * c));
        }
        for (s = 0; s < 3; s++) {
            uint32_t solver = order[s];
            ls_param_config c;
            result *r = &res[s];
            ls_arena a, sc;
            int rep, reps = solver == LS_PARAM_LDLT && side > 512 ? 1 : repeat;
            memset(&c, 0, sizeof c);
            memset(r, 0, sizeof *r);
            c.solver = solver;
            c.form = LS_SYSTEM_LAMBDA;
            c.weight = (ls_real)lambda;
            c.k = 3;
            c.order = LS_ORDER_AUTO;
            c.cg_max_iter = 100000;
            c.cg_tol = (ls_real)tol;
            if (ls_arena_init(&sc, smem, scratch_bytes) != LS_OK) return 1;
            if (ls_param_grid_bytes(&sh, &c, &sc, &r->bytes) != LS_OK) {
                fprintf(stderr, "bench_grid: bytes failed (%s %u)\n", solver_name(solver), side);
                return 1;
            }
            r->init = r->solve = 1e300;
            for (rep = 0; rep < reps; rep++) {
                ls_param p;
                double t0, t1;
                ls_status st;
                if (ls_arena_init(&a, mem, arena_bytes) != LS_OK) return 1;
                t0 = now_ms();
                st = ls_param_grid_init(&p, &sh, &c, &a, NULL);
                t1 = now_ms();
                if (st != LS_OK) {
                    fprintf(stderr, "bench_grid: init %s %u: %s\n", solver_name(solver), side, ls_status_name(st));
                    return 1;
                }
                if (t1 - t0 < r->init) r->init = t1 - t0;
                if (ls_param_to_differential(&p, x, u) != LS_OK) return 1;
                t0 = now_ms();
                st = ls_param_from_differential(&p, u, y);
                t1 = now_ms();
                if (st != LS_OK) return 1;
                if (t1 - t0 < r->solve) r->solve = t1 - t0;
                r->iters = p.cg.max_iterations;
            }
            if (solver == LS_PARAM_GRID) memcpy(xg, y, nk * sizeof(ls_real));
            r->err = rel(y, xg, nk);
            r->trip = rel(y, x, nk);
            if (solver == LS_PARAM_CG)
                printf("| %ux%u | CG tol %g | %.1f | %.1f | %u | %lu | %.2e | %.2e |\n", side, side, tol, r->init, r->solve,
                       r->iters, (unsigned long)r->bytes, r->err, r->trip);
            else
                printf("| %ux%u | %s | %.1f | %.1f | - | %lu | %.2e | %.2e |\n", side, side, solver_name(solver), r->init,
                       r->solve, (unsigned long)r->bytes, r->err, r->trip);
            fflush(stdout);
        }
        {
            size_t tables = 0;
            if (ls_grid_solver_bytes(side, side, wrap, 3, &tables) != LS_OK) return 1;
            fprintf(stderr, "RATIO | %ux%u | %.0f | %.2f | %.1f | %.2f | %.2f | %lu |\n", side, side,
                    res[1].init / (res[0].init > 0.01 ? res[0].init : 0.01), res[1].solve / res[0].solve,
                    (double)res[1].bytes / (double)res[0].bytes, res[2].solve / res[0].solve,
                    (double)res[2].bytes / (double)res[0].bytes, (unsigned long)tables);
        }
        free(x), free(u), free(y), free(xg);
    }
    free(mem), free(smem);
    return 0;
}
