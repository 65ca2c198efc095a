/* test_cg.c - Jacobi-preconditioned CG against dense solves and the LDL^T,
 * the iteration cap, warm starts, per-column independence, errors, sweeps. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include "../port/posix/ls_posix.h"
#include "dense.h"

static LS_ARENA_BUFFER(buf_, 4 << 20);
#define BUF buf_.bytes

static uint64_t rs = 0x243F6A8885A308D3ull;
static double urand(void)
{
    return test_rng_unit(&rs);
}

/* a bumpy triangulated nx x ny grid */
static ls_real gpos[3 * 400];
static uint32_t gtri[6 * 400];
static ls_mesh grid_mesh(uint32_t nx, uint32_t ny)
{
    ls_mesh m;
    uint32_t x, y, f = 0;
    for (y = 0; y < ny; y++)
        for (x = 0; x < nx; x++) {
            uint32_t v = y * nx + x;
            gpos[3 * v] = (ls_real)x;
            gpos[3 * v + 1] = (ls_real)y;
            gpos[3 * v + 2] = (ls_real)(0.3 * sin(0.7 * x + 1.3 * y));
        }
    for (y = 0; y + 1 < ny; y++)
        for (x = 0; x + 1 < nx; x++) {
            uint32_t v = y * nx + x;
            gtri[3 * f] = v; gtri[3 * f + 1] = v + 1; gtri[3 * f + 2] = v + nx + 1; f++;
            gtri[3 * f] = v; gtri[3 * f + 1] = v + nx + 1; gtri[3 * f + 2] = v + nx; f++;
        }
    m.positions = gpos;
    m.triangles = gtri;
    m.vertex_count = nx * ny;
    m.face_count = f;
    return m;
}

static void to_dense_sym(const ls_csc *m, double *d)
{
    uint32_t j, p, n = m->ncols;
    memset(d, 0, sizeof(double) * n * n);
    for (j = 0; j < n; j++)
        for (p = m->colptr[j]; p < m->colptr[j + 1]; p++) {
            uint32_t i = m->rowidx[p];
            if (i > j) continue;
            d[i * n + j] = d[j * n + i] = (double)m->values[p];
        }
}

static const ls_real cg_tol = LS_REAL_IS_FLOAT ? (ls_real)1e-6 : (ls_real)1e-12;

static void cg_matches_dense_solve(void)
{
    ls_arena a;
    ls_mesh m = grid_mesh(10, 8);
    ls_csc L, M;
    ls_cg_info info;
    static double d[80 * 80], b[240];
    ls_real rb[240], x[240];
    double lam[3] = {1, 19, 99};
    int li, i;
    ls_arena_init(&a, BUF, sizeof BUF);
    REQUIRE(ls_laplacian_cot(&m, LS_COT_REFERENCE, LS_LAP_UPPER, &a, &L, NULL, NULL) == LS_OK);
    for (li = 0; li < 3; li++) {
        double err = 0, nrm = 0;
        REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)lam[li], &a, &M, NULL) == LS_OK);
        for (i = 0; i < 240; i++) {
            rb[i] = (ls_real)(urand() - 0.5);
            b[i] = (double)rb[i];
            x[i] = 0;
        }
        to_dense_sym(&M, d);
        REQUIRE(dense_solve(d, 80, b, 3));
        info.max_iter = 1000;
        info.tol = cg_tol;
        CHECK_STATUS(ls_cg_solve(&M, 3, rb, x, &a, &info), LS_OK);
        CHECK_EQ(info.converged, 3);
        for (i = 0; i < 240; i++) {
            err += ((double)x[i] - b[i]) * ((double)x[i] - b[i]);
            nrm += b[i] * b[i];
        }
        /* forward error <= kappa * tol; kappa(M) <= 1 + lambda * 2 max row sum of |L| (~ 1 + 8 lambda here) */
        printf("     lambda %g: iterations %u %u %u, residual %.2g, forward error %.3g\n", lam[li], info.iterations[0],
               info.iterations[1], info.iterations[2], (double)info.residual[0], sqrt(err / nrm));
        CHECK(sqrt(err / nrm) <= (1 + 16 * lam[li]) * (double)cg_tol);
        /* the recomputed residual: the tolerance, or the rounding floor kappa * eps */
        for (i = 0; i < 3; i++) CHECK((double)info.residual[i] <= 2 * (double)cg_tol + 4 * (1 + 16 * lam[li]) * TEST_EPS(1));
    }
}

static void cg_matches_ldlt_on_the_bunny_and_warm_start_helps(void)
{
    ls_arena a;
    unsigned char *data = NULL;
    size_t n = 0, i, nk;
    ls_mesh m;
    ls_csc L, M;
    ls_ldlt f;
    ls_cg_info cold, warm;
    ls_real *b, *x, *y;
    double err = 0, nrm = 0;
    ls_arena_init(&a, BUF, sizeof BUF);
    REQUIRE(ls_posix_read_file("fixtures/meshes/bunny.obj", &data, &n) == LS_OK);
    REQUIRE(ls_mesh_read(data, n, LS_MESH_FORMAT_AUTO, &a, &m, NULL) == LS_OK);
    free(data);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)19, &a, &M, NULL) == LS_OK);
    REQUIRE(ls_ldlt_analyze_mesh(&M, LS_ORDER_AUTO, m.positions, &a, &f, NULL) == LS_OK);
    REQUIRE(ls_ldlt_factor(&f, &M, &a, NULL) == LS_OK);
    nk = 3u * m.vertex_count;
    b = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    x = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    y = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    REQUIRE(b && x && y);
    memcpy(b, m.positions, nk * sizeof(ls_real));
    memcpy(y, b, nk * sizeof(ls_real));
    REQUIRE(ls_ldlt_solve(&f, 3, y, &a) == LS_OK);
    memset(x, 0, nk * sizeof(ls_real));
    cold.max_iter = warm.max_iter = 2000;
    cold.tol = warm.tol = cg_tol;
    CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &cold), LS_OK);
    for (i = 0; i < nk; i++) {
        err += ((double)x[i] - (double)y[i]) * ((double)x[i] - (double)y[i]);
        nrm += (double)y[i] * (double)y[i];
    }
    printf("     bunny lambda 19: CG %u iterations, relative difference to the LDL^T %.3g\n", cold.max_iterations,
           sqrt(err / nrm));
    CHECK(sqrt(err / nrm) <= 500 * (double)cg_tol);
    /* a small change of b: the previous solution as the start needs fewer iterations */
    for (i = 0; i < nk; i++) b[i] += (ls_real)(1e-3 * (urand() - 0.5));
    CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &warm), LS_OK);
    printf("     warm start after a 1e-3 perturbation: %u iterations (cold %u)\n", warm.max_iterations, cold.max_iterations);
    CHECK(warm.max_iterations < cold.max_iterations);
    CHECK_EQ(warm.converged, 3);
}

static void cap_columns_and_determinism(void)
{
    ls_arena a;
    ls_mesh m = grid_mesh(12, 12);
    ls_csc L, M;
    ls_cg_info info, i1;
    ls_real b[432], x[432], xs[144], bs[144];
    int i, c, same = 1;
    ls_arena_init(&a, BUF, sizeof BUF);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)19, &a, &M, NULL) == LS_OK);
    for (i = 0; i < 432; i++) {
        b[i] = (i % 3 == 1) ? (ls_real)0 : (ls_real)(urand() - 0.5);
        x[i] = (i % 3 == 1) ? (ls_real)5 : (ls_real)0;
    }
    info.max_iter = 3;
    info.tol = cg_tol;
    CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &info), LS_OK);
    CHECK_EQ(info.iterations[0], 3);
    CHECK_EQ(info.iterations[1], 0); /* b = 0: x = 0 at once */
    CHECK_EQ(info.iterations[2], 3);
    CHECK_EQ(info.converged, 1);
    CHECK(info.residual[0] > cg_tol);
    for (i = 0; i < 144; i++) CHECK(x[3 * i + 1] == 0);
    /* 3 columns at once = each column alone, bit for bit */
    info.max_iter = i1.max_iter = 500;
    i1.tol = cg_tol;
    for (i = 0; i < 432; i++) x[i] = 0;
    CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &info), LS_OK);
    for (c = 0; c < 3; c++) {
        for (i = 0; i < 144; i++) {
            bs[i] = b[3 * i + c];
            xs[i] = 0;
        }
        CHECK_STATUS(ls_cg_solve(&M, 1, bs, xs, &a, &i1), LS_OK);
        CHECK_EQ(i1.iterations[0], info.iterations[c]);
        for (i = 0; i < 144; i++) same &= memcmp(&xs[i], &x[3 * i + c], sizeof(ls_real)) == 0;
    }
    CHECK(same);
}

static void errors(void)
{
    ls_arena a;
    ls_mesh m = grid_mesh(4, 4);
    ls_csc L, M;
    ls_cg_info o;
    ls_real b[48], x[48], x0[48];
    int i;
    o.max_iter = 100;
    o.tol = cg_tol;
    ls_arena_init(&a, BUF, sizeof BUF);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)1, &a, &M, NULL) == LS_OK);
    for (i = 0; i < 48; i++) {
        b[i] = (ls_real)i;
        x[i] = x0[i] = (ls_real)0.5;
    }
    b[7] = (ls_real)NAN;
    CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &o), LS_ERR_NONFINITE);
    CHECK(memcmp(x, x0, sizeof x) == 0);
    b[7] = 1;
    CHECK_STATUS(ls_cg_solve(&M, 5, b, x, &a, &o), LS_ERR_INVALID);
    CHECK_STATUS(ls_cg_solve(&M, 0, b, x, &a, &o), LS_ERR_INVALID);
    /* diagonal lowered by 2.5: indefinite (p^T M p <= 0 shows); then a negative diagonal entry */
    REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)1, &a, &M, NULL) == LS_OK);
    {
        uint32_t j;
        for (j = 0; j < M.ncols; j++) M.values[M.colptr[j + 1] - 1] -= (ls_real)2.5; /* diag - 2.5 */
        CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &o), LS_ERR_NOT_SPD);
        M.values[M.colptr[1] - 1] = (ls_real)-1;
        CHECK_STATUS(ls_cg_solve(&M, 3, b, x, &a, &o), LS_ERR_NOT_SPD);
    }
}

typedef struct cg_job {
    ls_csc *m;
    ls_real b[48], x[48];
} cg_job;

static ls_status cg_run(void *ctx, ls_arena *a)
{
    cg_job *j = (cg_job *)ctx;
    ls_cg_info o;
    int i;
    o.max_iter = 100;
    o.tol = cg_tol;
    for (i = 0; i < 48; i++) j->x[i] = 0;
    return ls_cg_solve(j->m, 3, j->b, j->x, a, &o);
}

static uint64_t cg_hash(void *ctx)
{
    cg_job *j = (cg_job *)ctx;
    return test_hash(j->b, sizeof j->b, TEST_HASH_SEED);
}

static void sweep(void)
{
    static LS_ARENA_BUFFER(own, 1 << 16);
    ls_arena a;
    ls_mesh m = grid_mesh(4, 4);
    ls_csc L, M;
    cg_job j;
    sweep_job job;
    size_t bytes = 0;
    int i;
    ls_arena_init(&a, own.bytes, sizeof own.bytes);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) == LS_OK);
    REQUIRE(ls_laplacian_system(&L, LS_SYSTEM_LAMBDA, (ls_real)3, &a, &M, NULL) == LS_OK);
    for (i = 0; i < 48; i++) j.b[i] = (ls_real)(urand() - 0.5);
    j.m = &M;
    REQUIRE(ls_cg_bytes(16, 3, &bytes) == LS_OK);
    CHECK_EQ(bytes, (3 * 48 + 16) * sizeof(ls_real));
    memset(&job, 0, sizeof job);
    job.name = "cg";
    job.run = cg_run;
    job.state_hash = cg_hash;
    job.ctx = &j;
    job.answer = bytes;
    job.exact = 1;
    CHECK(sweep_arena(&job) == 0);
}

int main(void)
{
    TEST_INIT("test_cg");
    TEST_RUN(cg_matches_dense_solve);
    TEST_RUN(cg_matches_ldlt_on_the_bunny_and_warm_start_helps);
    TEST_RUN(cap_columns_and_determinism);
    TEST_RUN(errors);
    TEST_RUN(sweep);
    return TEST_END();
}
