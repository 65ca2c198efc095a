/* tests/bench/bench_loss.c - the image loss alone, as the fit calls it: V
 * views of RES x RES RGBA, ls_loss_begin / ls_loss_view (with gradient) /
 * ls_loss_finish, L1 and L2. Inputs: uniform values in [0, 1], with a
 * background (40 % of the pixels zero in both images, as outside the
 * silhouettes). Prints the minimum over REPEAT runs of the process CPU time
 * of one pass over the views, and ns per value.
 *
 *   make build/bench/bench_loss && build/bench/bench_loss [RES [VIEWS [REPEAT]]]
 */
#define _POSIX_C_SOURCE 200112L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <largesteps.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint64_t rng = 88172645463325252ull;
static double rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

int main(int argc, char **argv)
{
    uint32_t res = argc > 1 ? (uint32_t)atoi(argv[1]) : 128u, views = argc > 2 ? (uint32_t)atoi(argv[2]) : 16u;
    int repeat = argc > 3 ? atoi(argv[3]) : 200, k, rep;
    size_t n = (size_t)4 * res * res, i, p;
    ls_real *r = malloc(views * n * sizeof *r), *t = malloc(views * n * sizeof *t), *g = malloc(n * sizeof *g);
    ls_real loss = 0, sink = 0;
    if (r == NULL || t == NULL || g == NULL || res == 0 || views == 0) return 1;
    for (p = 0; p < views * n / 4; p++) {
        int bg = rnd() < 0.4;
        for (k = 0; k < 4; k++) {
            r[4 * p + (size_t)k] = bg ? (ls_real)0 : (ls_real)rnd();
            t[4 * p + (size_t)k] = bg ? (ls_real)0 : (ls_real)rnd();
        }
    }
    for (k = 0; k < 2; k++) {
        double best = 1e30;
        for (rep = 0; rep < repeat; rep++) {
            ls_loss_acc acc;
            uint32_t v;
            double t0 = now_ms(), dt;
            if (ls_loss_begin(&acc, (uint32_t)k, res, res, views) != LS_OK) return 1;
            for (v = 0; v < views; v++)
                if (ls_loss_view(&acc, r + v * n, t + v * n, g, NULL) != LS_OK) return 1;
            if (ls_loss_finish(&acc, &loss) != LS_OK) return 1;
            dt = now_ms() - t0;
            if (dt < best) best = dt;
            for (i = 0; i < n; i += 4099) sink += g[i];
        }
        printf("%s %ux%u x %u views (%s): %.3f ms per pass, %.2f ns per value (loss %.9g)\n", k == 0 ? "L1" : "L2",
               (unsigned)res, (unsigned)res, (unsigned)views, LS_REAL_NAME, best, best * 1e6 / (double)(views * n),
               (double)loss);
    }
    free(r);
    free(t);
    free(g);
    return sink == (ls_real)12345 ? 2 : 0;
}
