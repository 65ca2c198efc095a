/* test_toy1d.c - the paper's 1D toy: the library's trajectories against an
 * independent simulation written here (dense path-graph Laplacian, dense
 * Gaussian elimination in double), and the paper's claims asserted on
 * both: naive descent inverts within a few iterations; large steps never
 * invert for p = 2, lambda >= 19 and p = 1, lambda = 99, and do for lambda = 1;
 * the end points converge; the interior points stop short of the target. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>

#define N 32
#define ITERS 200

/* The step sizes, written here independently of src/param/toy1d.c's table. */
static const struct {
    const char *name;
    int kind; /* 0 naive, 1 regularized, 2 large steps */
    int power;
    double lambda, step;
} expect[8] = {
    {"naive", 0, 0, 0, 0.5},           {"laplacian-reg", 1, 0, 0.05, 0.5}, {"large-p1-l1", 2, 1, 1, 1.5},
    {"large-p1-l19", 2, 1, 19, 4},     {"large-p1-l99", 2, 1, 99, 8},      {"large-p2-l1", 2, 2, 1, 2},
    {"large-p2-l19", 2, 2, 19, 8},     {"large-p2-l99", 2, 2, 99, 16},
};

static double ref[8][(ITERS + 1) * N];
static ls_real lib[8][(ITERS + 1) * N];
static double target[N];

/* x = A^{-1} b, dense Gaussian elimination without pivoting (A is SPD) */
static void dense_solve(const double *a_in, double *b)
{
    double a[N * N];
    int i, j, c;
    memcpy(a, a_in, sizeof a);
    for (c = 0; c < N; c++)
        for (i = c + 1; i < N; i++) {
            double f = a[i * N + c] / a[c * N + c];
            for (j = c; j < N; j++) a[i * N + j] -= f * a[c * N + j];
            b[i] -= f * b[c];
        }
    for (i = N - 1; i >= 0; i--) {
        double s = b[i];
        for (j = i + 1; j < N; j++) s -= a[i * N + j] * b[j];
        b[i] = s / a[i * N + i];
    }
}

static void simulate(int k, double *traj)
{
    double L[N * N], M[N * N], x[N], g[N];
    int i, j, it, q;
    memset(L, 0, sizeof L);
    for (i = 0; i + 1 < N; i++) {
        L[i * N + i] += 1;
        L[(i + 1) * N + i + 1] += 1;
        L[i * N + i + 1] = L[(i + 1) * N + i] = -1;
    }
    for (i = 0; i < N * N; i++) M[i] = expect[k].lambda * L[i] + (i % (N + 1) == 0 ? 1.0 : 0.0);
    for (i = 0; i < N; i++) {
        x[i] = -1.0 + 2.0 * i / (N - 1);
        target[i] = 0.5 * x[i];
    }
    memcpy(traj, x, sizeof x);
    for (it = 1; it <= ITERS; it++) {
        memset(g, 0, sizeof g);
        g[0] = x[0] - target[0];
        g[N - 1] = x[N - 1] - target[N - 1];
        if (expect[k].kind == 1)
            for (i = 0; i < N; i++)
                for (j = 0; j < N; j++) g[i] += 2 * expect[k].lambda * L[i * N + j] * x[j];
        if (expect[k].kind == 2)
            for (q = 0; q < expect[k].power; q++) dense_solve(M, g);
        for (i = 0; i < N; i++) x[i] -= expect[k].step * g[i];
        memcpy(traj + it * N, x, sizeof x);
    }
}

static int first_inversion_d(const double *traj)
{
    int it, i;
    for (it = 0; it <= ITERS; it++)
        for (i = 0; i + 1 < N; i++)
            if (traj[it * N + i + 1] < traj[it * N + i]) return it;
    return -1;
}

static int first_inversion_r(const ls_real *traj)
{
    int it, i;
    for (it = 0; it <= ITERS; it++)
        for (i = 0; i + 1 < N; i++)
            if (traj[it * N + i + 1] < traj[it * N + i]) return it;
    return -1;
}

/* max |a - b|, as a plain loop: aarch64-linux-gnu-gcc 12 crashes (internal
 * compiler error in vect_transform_reduction) vectorizing an fmax reduction
 * over float-to-double conversions here. */
static double max_abs_diff(const ls_real *a, const double *b, int n)
{
    double worst = 0;
    int i;
    for (i = 0; i < n; i++) {
        double e = fabs((double)a[i] - b[i]);
        if (e > worst || e != e) worst = e;
    }
    return worst;
}

static void table_matches_and_trajectories_match_dense(void)
{
    static LS_ARENA_BUFFER(mem, 1 << 16);
    ls_arena a;
    int k, i;
    ls_real t0[N], tt[N];
    ls_arena_init(&a, mem.bytes, sizeof mem.bytes);
    ls_toy1d_points(t0, tt);
    for (i = 0; i < N; i++) {
        CHECK_NEAR(t0[i], -1.0 + 2.0 * i / 31.0, TEST_EPS(2));
        CHECK_NEAR(tt[i], -0.5 + 1.0 * i / 31.0, TEST_EPS(2));
    }
    for (k = 0; k < 8; k++) {
        ls_toy1d_method m;
        double worst = 0;
        REQUIRE(ls_toy1d_method_get((uint32_t)k, &m) == LS_OK);
        CHECK(strcmp(m.name, expect[k].name) == 0);
        CHECK_EQ(m.kind, expect[k].kind);
        CHECK_EQ(m.power, expect[k].power);
        CHECK((double)m.lambda == expect[k].lambda || fabs((double)m.lambda - expect[k].lambda) < 1e-8);
        CHECK((double)m.step == expect[k].step);
        simulate(k, ref[k]);
        CHECK_STATUS(ls_toy1d_run((uint32_t)k, ITERS, lib[k], &a), LS_OK);
        CHECK_EQ(ls_arena_used(&a), 0);
        worst = max_abs_diff(lib[k], ref[k], (ITERS + 1) * N);
        CHECK_MSG(worst <= (LS_REAL_IS_FLOAT ? 2e-5 : 1e-12), "%s: trajectory differs from the dense simulation by %g",
                  expect[k].name, worst);
    }
    {
        ls_toy1d_method m;
        CHECK_STATUS(ls_toy1d_method_get(8, &m), LS_ERR_INVALID);
    }
}

/* The claims, on the dense simulation and on the library's trajectories. */
static void claims_hold(void)
{
    int k, i;
    printf("     %-14s %9s %9s %12s %12s %12s\n", "method", "first inv", "(library)", "end error", "interior err", "min gap");
    for (k = 0; k < 8; k++) {
        const double *xe = ref[k] + ITERS * N, *xp = ref[k] + (ITERS - 1) * N;
        int fd = first_inversion_d(ref[k]), fr = first_inversion_r(lib[k]);
        const ls_real *le = lib[k] + ITERS * N;
        double end = fmax(fabs(xe[0] - target[0]), fabs(xe[N - 1] - target[N - 1])), interior = 0, moved = 0, gap = 1;
        double lend = fmax(fabs((double)le[0] - target[0]), fabs((double)le[N - 1] - target[N - 1]));
        int it;
        for (it = 0; it <= ITERS; it++) /* the smallest x[i+1] - x[i] over the run */
            for (i = 0; i + 1 < N; i++) gap = fmin(gap, ref[k][it * N + i + 1] - ref[k][it * N + i]);
        for (i = 1; i + 1 < N; i++) {
            interior = fmax(interior, fabs(xe[i] - target[i]));
            moved = fmax(moved, fabs(xe[i] - xp[i]));
        }
        printf("     %-14s %9d %9d %12.3g %12.6f %12.6f\n", expect[k].name, fd, fr, end, interior, gap);
        CHECK_EQ(fd, fr);
        if (expect[k].kind == 0) CHECK(fd >= 1 && fd <= 3);              /* naive: inverts within a few */
        if (expect[k].kind == 2 && (expect[k].power == 2 ? expect[k].lambda >= 19 : expect[k].lambda >= 99))
            CHECK_MSG(fd == -1, "%s inverted at %d", expect[k].name, fd); /* never inverts */
        if (expect[k].kind == 2 && (expect[k].lambda <= 1 || (expect[k].power == 1 && expect[k].lambda <= 19)))
            CHECK_MSG(fd >= 1, "%s never inverted", expect[k].name); /* small lambda: inverts */
        if (expect[k].kind != 1) {
            CHECK(end < 1e-9);                                            /* the end points converge */
            CHECK(lend < (LS_REAL_IS_FLOAT ? 1e-6 : 1e-9));
            CHECK(moved < 1e-9);                                          /* and everything has stopped */
            CHECK(interior > 0.04);                                       /* short of the target inside */
        }
    }
}

typedef struct toy_job {
    uint32_t method;
    ls_real traj[11 * N];
} toy_job;

static ls_status toy_run(void *ctx, ls_arena *a)
{
    toy_job *j = (toy_job *)ctx;
    return ls_toy1d_run(j->method, 10, j->traj, a);
}

static uint64_t toy_hash(void *ctx)
{
    toy_job *j = (toy_job *)ctx;
    return test_hash(j->traj, sizeof j->traj, TEST_HASH_SEED);
}

static void sweeps(void)
{
    static LS_ARENA_BUFFER(scr, 1 << 16);
    static toy_job j;
    ls_arena s;
    uint32_t k;
    ls_arena_init(&s, scr.bytes, sizeof scr.bytes);
    for (k = 0; k < 8; k++) {
        sweep_job job;
        size_t bytes = 0;
        REQUIRE(ls_toy1d_bytes(k, &s, &bytes) == LS_OK);
        CHECK_EQ(ls_arena_used(&s), 0);
        memset(&j, 0, sizeof j);
        j.method = k;
        memset(&job, 0, sizeof job);
        job.name = "toy1d";
        job.run = toy_run;
        job.state_hash = toy_hash;
        job.ctx = &j;
        job.answer = bytes;
        job.exact = 1;
        CHECK_MSG(sweep_arena(&job) == 0, "method %u", k);
    }
}

int main(void)
{
    TEST_INIT("test_toy1d");
    TEST_RUN(table_matches_and_trajectories_match_dense);
    TEST_RUN(claims_hold);
    TEST_RUN(sweeps);
    return TEST_END();
}
