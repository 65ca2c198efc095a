/* tests/bench/peer_fftw_grid.c - the texture grid's solve, ours
 * (ls_grid_solver_solve: our own FFT, cosine transforms by Makhoul's
 * reordering) against FFTW's DCT-II / DCT-III of the same grid (FFTW_MEASURE
 * plans, the 3 interleaved channels in one plan), in one run on one thread.
 *
 * M = I + lambda L, L the 4-neighbour grid Laplacian with Neumann ends: the
 * DCT-II diagonalizes it (eigenvalues 4 sin^2(pi j / 2W) + 4 sin^2(pi k / 2H)),
 * so FFTW's solve is REDFT10, a division, REDFT01 and the 1 / (4 W H) of the
 * unnormalized pair. Both solve the same right-hand side; the table gives
 * their relative difference (a wrong transform or scale shows there).
 *
 * usage: peer_fftw_grid REPEAT LAMBDA SIZE...
 * prints per size: | grid | ours ms | FFTW ms | ours / FFTW | difference |
 * (CPU time, the minimum of REPEAT solves each, alternated). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <fftw3.h>
#include <largesteps.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int main(int argc, char **argv)
{
    int repeat, si;
    double lambda;
    if (argc < 4 || sizeof(ls_real) != sizeof(double)) {
        fprintf(stderr, "usage: peer_fftw_grid REPEAT LAMBDA SIZE... (a double build)\n");
        return 2;
    }
    repeat = atoi(argv[1]);
    lambda = atof(argv[2]);
    for (si = 3; si < argc; si++) {
        const int side = atoi(argv[si]), k = 3;
        const size_t n = (size_t)side * (size_t)side, nk = n * (size_t)k;
        double *b = (double *)malloc(nk * sizeof(double)), *ours = (double *)malloc(nk * sizeof(double));
        double *peer = fftw_alloc_real(nk), *scale = (double *)malloc(n * sizeof(double));
        double best_ours = 1e300, best_peer = 1e300, e = 0, s = 0;
        const int dims[2] = {side, side};
        const fftw_r2r_kind fwd[2] = {FFTW_REDFT10, FFTW_REDFT10}, inv[2] = {FFTW_REDFT01, FFTW_REDFT01};
        fftw_plan pf, pi;
        ls_grid_solver g;
        ls_arena arena;
        size_t bytes = 0, i;
        void *mem;
        int rep, x, y;
        if (b == NULL || ours == NULL || peer == NULL || scale == NULL) return 1;
        if (ls_grid_solver_bytes((uint32_t)side, (uint32_t)side, 0, (uint32_t)k, &bytes) != LS_OK) return 1;
        mem = malloc(bytes);
        if (mem == NULL || ls_arena_init(&arena, mem, bytes) != LS_OK) return 1;
        if (ls_grid_solver_init(&g, (uint32_t)side, (uint32_t)side, 0, (uint32_t)k, &arena) != LS_OK ||
            ls_grid_solver_set_weight(&g, LS_SYSTEM_LAMBDA, (ls_real)lambda, NULL) != LS_OK)
            return 1;
        /* the same three channels, in place, one plan for all of them */
        pf = fftw_plan_many_r2r(2, dims, k, peer, NULL, k, 1, peer, NULL, k, 1, fwd, FFTW_MEASURE);
        pi = fftw_plan_many_r2r(2, dims, k, peer, NULL, k, 1, peer, NULL, k, 1, inv, FFTW_MEASURE);
        if (pf == NULL || pi == NULL) return 1;
        for (y = 0; y < side; y++)
            for (x = 0; x < side; x++) {
                const double sx = sin(3.14159265358979323846 * x / (2.0 * side));
                const double sy = sin(3.14159265358979323846 * y / (2.0 * side));
                scale[(size_t)y * side + x] = 1.0 / ((1.0 + lambda * 4.0 * (sx * sx + sy * sy)) * 4.0 * side * side);
            }
        for (i = 0; i < nk; i++) b[i] = 0.5 + 0.3 * sin(0.001 * (double)i) + 0.05 * sin(12.9898 * (double)i);
        for (rep = 0; rep < repeat; rep++) {
            double t0, t1;
            size_t j;
            memcpy(ours, b, nk * sizeof(double));
            t0 = now_ms();
            if (ls_grid_solver_solve(&g, (const ls_real *)ours, (ls_real *)ours) != LS_OK) return 1;
            t1 = now_ms();
            if (t1 - t0 < best_ours) best_ours = t1 - t0;
            memcpy(peer, b, nk * sizeof(double));
            t0 = now_ms();
            fftw_execute(pf);
            for (j = 0; j < n; j++) {
                peer[3 * j] *= scale[j];
                peer[3 * j + 1] *= scale[j];
                peer[3 * j + 2] *= scale[j];
            }
            fftw_execute(pi);
            t1 = now_ms();
            if (t1 - t0 < best_peer) best_peer = t1 - t0;
        }
        for (i = 0; i < nk; i++) {
            e += (ours[i] - peer[i]) * (ours[i] - peer[i]);
            s += peer[i] * peer[i];
        }
        printf("| %dx%d | %.1f | %.1f | %.2f | %.1e |\n", side, side, best_ours, best_peer, best_ours / best_peer,
               sqrt(e / s));
        fflush(stdout);
        fftw_destroy_plan(pf);
        fftw_destroy_plan(pi);
        fftw_free(peer);
        free(b), free(ours), free(scale), free(mem);
    }
    fftw_cleanup();
    return 0;
}
