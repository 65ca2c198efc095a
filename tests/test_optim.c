/* tests/test_optim.c - UniformAdam, Adam and SGD with momentum against their
 * reference formulas written out here independently, in double, step by step
 * on fixed gradient sequences (large-steps-pytorch's AdamUniform, PyTorch's
 * Adam and SGD). Tolerance: 1e-14 relative in the double build, 1e-6 in float. */
#include "test.h"
#include "sweep.h"

#define NU 30 /* a 10 x 3 block (u) */
#define NT 3  /* a translation block */
#define N (NU + NT)
#define STEPS 12

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double rnd(void) /* uniform in [-1, 1) */
{
    return test_rng_range(&rng_state, -1.0, 1.0);
}

/* Gradient sequence: mixed magnitudes (a spike, tiny values, a zero step) as
 * silhouette and shading gradients are; rounded to ls_real so that the
 * library and the reference see the same inputs. */
static ls_real grads[STEPS][N];
static ls_real start[N];

static void make_inputs(void)
{
    int t, i;
    for (i = 0; i < N; i++) start[i] = (ls_real)(rnd() * 2.0);
    for (t = 0; t < STEPS; t++)
        for (i = 0; i < N; i++) {
            double g = rnd();
            if (i == 7) g *= 1000.0;          /* a silhouette spike */
            if (i % 5 == 3) g *= 1e-4;        /* small shading gradients */
            if (i >= NU) g *= 50.0;           /* the translation block is on another scale */
            if (t == 4) g = 0.0;              /* a step without gradient */
            grads[t][i] = (ls_real)g;
        }
}

static double tolerance(void)
{
    return LS_REAL_IS_FLOAT ? 1e-6 : 1e-14;
}

/* The references, in double. */
typedef struct ref_state {
    double p[N], m1[N], m2[N];
} ref_state;

static void ref_uniform_adam(ref_state *s, int t, const ls_real *g, double lr, double b1, double b2, double eps)
{
    int i, blk;
    const int first[2] = {0, NU}, size[2] = {NU, NT};
    for (i = 0; i < N; i++) {
        double gi = (double)g[i];
        s->m1[i] = b1 * s->m1[i] + (1.0 - b1) * gi;
        s->m2[i] = b2 * s->m2[i] + (1.0 - b2) * gi * gi;
    }
    for (blk = 0; blk < 2; blk++) {
        double mx = 0.0;
        for (i = first[blk]; i < first[blk] + size[blk]; i++) {
            double v = sqrt(s->m2[i] / (1.0 - pow(b2, t)));
            if (v > mx) mx = v;
        }
        for (i = first[blk]; i < first[blk] + size[blk]; i++)
            s->p[i] -= lr * (s->m1[i] / (1.0 - pow(b1, t))) / (eps + mx);
    }
}

static void ref_adam(ref_state *s, int t, const ls_real *g, double lr, double b1, double b2, double eps)
{
    int i;
    for (i = 0; i < N; i++) {
        double gi = (double)g[i], m1hat, m2hat;
        s->m1[i] = b1 * s->m1[i] + (1.0 - b1) * gi;
        s->m2[i] = b2 * s->m2[i] + (1.0 - b2) * gi * gi;
        m1hat = s->m1[i] / (1.0 - pow(b1, t));
        m2hat = s->m2[i] / (1.0 - pow(b2, t));
        s->p[i] -= lr * m1hat / (sqrt(m2hat) + eps);
    }
}

static void ref_sgd(ref_state *s, int t, const ls_real *g, double lr, double momentum)
{
    int i;
    for (i = 0; i < N; i++) {
        s->m1[i] = t == 1 ? (double)g[i] : momentum * s->m1[i] + (double)g[i];
        s->p[i] -= lr * s->m1[i];
    }
}

static LS_ARENA_BUFFER(work, 4096);

/* Runs `method` for STEPS steps and compares every parameter after every step. */
static void compare_method(uint32_t method, double lr, double b1, double b2, double eps)
{
    const uint32_t blocks[2] = {NU, NT};
    ls_optim_config cfg;
    ls_optim opt;
    ls_arena arena;
    ref_state ref;
    ls_real p[N];
    double worst = 0.0;
    int t, i;
    make_inputs();
    memset(&ref, 0, sizeof ref);
    for (i = 0; i < N; i++) {
        p[i] = start[i];
        ref.p[i] = (double)start[i];
    }
    REQUIRE(ls_optim_config_default(method, &cfg) == LS_OK);
    cfg.lr = (ls_real)lr;
    cfg.beta1 = (ls_real)b1;
    cfg.beta2 = (ls_real)b2;
    cfg.eps = (ls_real)eps;
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    REQUIRE(ls_optim_init(&opt, &cfg, N, 2, blocks, &arena) == LS_OK);
    for (t = 1; t <= STEPS; t++) {
        CHECK_STATUS(ls_optim_step(&opt, p, grads[t - 1], NULL), LS_OK);
        if (method == LS_OPTIM_UNIFORM_ADAM) ref_uniform_adam(&ref, t, grads[t - 1], lr, b1, b2, eps);
        if (method == LS_OPTIM_ADAM) ref_adam(&ref, t, grads[t - 1], lr, b1, b2, eps);
        if (method == LS_OPTIM_SGD) ref_sgd(&ref, t, grads[t - 1], lr, b1);
        for (i = 0; i < N; i++) {
            double err = fabs((double)p[i] - ref.p[i]) / (fabs(ref.p[i]) > 1.0 ? fabs(ref.p[i]) : 1.0);
            if (err > worst) worst = err;
        }
    }
    CHECK_EQ(opt.step, STEPS);
    CHECK_MSG(worst <= tolerance(), "method %u: worst relative error %.3g > %.3g", (unsigned)method, worst, tolerance());
    printf("     method %u: %d steps, worst relative error vs the double reference %.3g\n", (unsigned)method, STEPS,
           worst);
}

static void optim_uniform_adam_matches_reference(void)
{
    compare_method(LS_OPTIM_UNIFORM_ADAM, 0.1, 0.9, 0.999, 1e-8);
    compare_method(LS_OPTIM_UNIFORM_ADAM, 0.02, 0.5, 0.9, 1e-3); /* other betas and eps */
}

static void optim_adam_matches_reference(void)
{
    compare_method(LS_OPTIM_ADAM, 1e-2, 0.9, 0.999, 1e-8);
}

static void optim_sgd_matches_reference(void)
{
    compare_method(LS_OPTIM_SGD, 1e-3, 0.9, 0.0, 0.0);
    compare_method(LS_OPTIM_SGD, 1e-3, 0.0, 0.0, 0.0); /* plain gradient descent */
}

/* The first UniformAdam step is lr * g / (eps + max |g|) per block: the
 * largest gradient of each block moves its parameter by lr (up to eps), a
 * block's step does not depend on the other block's gradients, and scaling a
 * block's gradients leaves its step unchanged (the "uniform" property). */
static void optim_uniform_adam_blocks_are_independent(void)
{
    const uint32_t blocks[2] = {NU, NT};
    ls_optim_config cfg;
    ls_optim opt;
    ls_arena arena;
    ls_real p1[N], p2[N], g[N];
    double mx = 0.0;
    int i, imax = 0;
    make_inputs();
    REQUIRE(ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &cfg) == LS_OK);
    for (i = 0; i < N; i++) {
        p1[i] = p2[i] = 0;
        g[i] = grads[0][i];
        if (i < NU && fabs((double)g[i]) > mx) {
            mx = fabs((double)g[i]);
            imax = i;
        }
    }
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    REQUIRE(ls_optim_init(&opt, &cfg, N, 2, blocks, &arena) == LS_OK);
    REQUIRE(ls_optim_step(&opt, p1, g, NULL) == LS_OK);
    CHECK_NEAR(fabs((double)p1[imax]), 0.1, 0.1 * TEST_EPS(8) + 1e-8);
    CHECK_NEAR((double)opt.last_scale[0], mx, mx * TEST_EPS(4));
    /* translation gradients x 1024 (exact in binary): block 0 bit-identical, block 1 too */
    for (i = NU; i < N; i++) g[i] = g[i] * (ls_real)1024;
    REQUIRE(ls_optim_reset(&opt, 2, blocks) == LS_OK);
    REQUIRE(ls_optim_step(&opt, p2, g, NULL) == LS_OK);
    CHECK(memcmp(p1, p2, NU * sizeof(ls_real)) == 0);
    for (i = NU; i < N; i++) CHECK_NEAR(p2[i], p1[i], 1e-7);
    /* one block over everything: the translation spike now dominates the scale */
    {
        const uint32_t one = N;
        ls_real p3[N];
        memset(p3, 0, sizeof p3);
        REQUIRE(ls_optim_reset(&opt, 1, &one) == LS_OK);
        REQUIRE(ls_optim_step(&opt, p3, g, NULL) == LS_OK);
        CHECK(fabs((double)p3[imax]) < 0.1 * 0.5);
    }
}

/* A NaN or infinite gradient is rejected with the element named, and nothing changes. */
static void optim_nonfinite_gradient_changes_nothing(void)
{
    const uint32_t blocks[2] = {NU, NT};
    const uint32_t methods[3] = {LS_OPTIM_UNIFORM_ADAM, LS_OPTIM_ADAM, LS_OPTIM_SGD};
    ls_optim_config cfg;
    ls_optim opt;
    ls_arena arena;
    ls_diag diag;
    ls_real p[N], g[N];
    uint64_t h_before, h_after;
    int m, i, k;
    make_inputs();
    for (m = 0; m < 3; m++)
        for (k = 0; k < 3; k++) {
            REQUIRE(ls_optim_config_default(methods[m], &cfg) == LS_OK);
            REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
            REQUIRE(ls_optim_init(&opt, &cfg, N, 2, blocks, &arena) == LS_OK);
            for (i = 0; i < N; i++) p[i] = start[i];
            REQUIRE(ls_optim_step(&opt, p, grads[0], NULL) == LS_OK);
            for (i = 0; i < N; i++) g[i] = grads[1][i];
            g[13 + k] = k == 0 ? (ls_real)NAN : k == 1 ? (ls_real)INFINITY : -(ls_real)INFINITY;
            h_before = test_hash_reals(p, N, test_hash_reals(opt.m1, N, test_hash_reals(opt.m2, N, TEST_HASH_SEED)));
            CHECK_STATUS(ls_optim_step(&opt, p, g, &diag), LS_ERR_NONFINITE);
            h_after = test_hash_reals(p, N, test_hash_reals(opt.m1, N, test_hash_reals(opt.m2, N, TEST_HASH_SEED)));
            CHECK(h_before == h_after);
            CHECK_EQ(opt.step, 1);
            CHECK_EQ(diag.index, 13 + k);
            CHECK(diag.has_index == 1 && diag.what != NULL && diag.what[0] != '\0');
        }
}

/* reset gives exactly the trajectory of a fresh optimizer. */
static void optim_reset_restarts_the_trajectory(void)
{
    const uint32_t blocks[2] = {NU, NT}, small[1] = {9};
    ls_optim_config cfg;
    ls_optim a, b;
    ls_arena arena;
    ls_real pa[N], pb[N];
    int t, i;
    make_inputs();
    REQUIRE(ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &cfg) == LS_OK);
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    REQUIRE(ls_optim_init(&a, &cfg, N, 1, small, &arena) == LS_OK);
    REQUIRE(ls_optim_init(&b, &cfg, N, 2, blocks, &arena) == LS_OK);
    for (i = 0; i < N; i++) pa[i] = pb[i] = start[i];
    for (t = 0; t < 3; t++) REQUIRE(ls_optim_step(&a, pa, grads[t + 5], NULL) == LS_OK); /* 9 used */
    for (i = 0; i < N; i++) pa[i] = start[i];
    REQUIRE(ls_optim_reset(&a, 2, blocks) == LS_OK);
    CHECK_EQ(a.step, 0);
    CHECK_EQ(a.count, N);
    for (t = 0; t < STEPS; t++) {
        REQUIRE(ls_optim_step(&a, pa, grads[t], NULL) == LS_OK);
        REQUIRE(ls_optim_step(&b, pb, grads[t], NULL) == LS_OK);
    }
    CHECK(memcmp(pa, pb, sizeof pa) == 0);
}

/* eps = 0 with zero gradients: no 0/0. */
static void optim_zero_gradient_with_zero_eps(void)
{
    const uint32_t one = 4;
    const uint32_t methods[2] = {LS_OPTIM_UNIFORM_ADAM, LS_OPTIM_ADAM};
    ls_optim_config cfg;
    ls_optim opt;
    ls_arena arena;
    ls_real p[4] = {1, 2, 3, 4}, g[4] = {0, 0, 0, 0};
    int m;
    for (m = 0; m < 2; m++) {
        REQUIRE(ls_optim_config_default(methods[m], &cfg) == LS_OK);
        cfg.eps = 0;
        REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
        REQUIRE(ls_optim_init(&opt, &cfg, 4, 1, &one, &arena) == LS_OK);
        CHECK_STATUS(ls_optim_step(&opt, p, g, NULL), LS_OK);
        CHECK(p[0] == 1 && p[1] == 2 && p[2] == 3 && p[3] == 4);
    }
}

static void optim_rejects_bad_configurations(void)
{
    const uint32_t blocks[5] = {1, 1, 1, 1, 1}, zero[2] = {3, 0}, big[2] = {3, 8};
    ls_optim_config cfg, good;
    ls_optim opt;
    ls_arena arena;
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    CHECK_STATUS(ls_optim_config_default(99u, &cfg), LS_ERR_INVALID);
    CHECK_STATUS(ls_optim_config_default(LS_OPTIM_SGD, NULL), LS_ERR_INVALID);
    REQUIRE(ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &good) == LS_OK);
    CHECK_NEAR(good.lr, 0.1, 1e-7);
    CHECK_NEAR(good.beta1, 0.9, 1e-7);
    CHECK_NEAR(good.beta2, 0.999, 1e-7);
    CHECK_NEAR(good.eps, 1e-8, 1e-15);
    cfg = good, cfg.lr = 0;
    CHECK_STATUS(ls_optim_init(&opt, &cfg, 4, 1, blocks, &arena), LS_ERR_INVALID);
    cfg = good, cfg.lr = (ls_real)NAN;
    CHECK_STATUS(ls_optim_init(&opt, &cfg, 4, 1, blocks, &arena), LS_ERR_INVALID);
    cfg = good, cfg.beta1 = 1;
    CHECK_STATUS(ls_optim_init(&opt, &cfg, 4, 1, blocks, &arena), LS_ERR_INVALID);
    cfg = good, cfg.beta2 = -(ls_real)0.5;
    CHECK_STATUS(ls_optim_init(&opt, &cfg, 4, 1, blocks, &arena), LS_ERR_INVALID);
    cfg = good, cfg.eps = -1;
    CHECK_STATUS(ls_optim_init(&opt, &cfg, 4, 1, blocks, &arena), LS_ERR_INVALID);
    cfg = good, cfg.method = 0;
    CHECK_STATUS(ls_optim_init(&opt, &cfg, 4, 1, blocks, &arena), LS_ERR_INVALID);
    CHECK_STATUS(ls_optim_init(&opt, &good, 8, 5, blocks, &arena), LS_ERR_INVALID);  /* too many blocks */
    CHECK_STATUS(ls_optim_init(&opt, &good, 8, 0, blocks, &arena), LS_ERR_INVALID);
    CHECK_STATUS(ls_optim_init(&opt, &good, 8, 2, zero, &arena), LS_ERR_INVALID);    /* empty block */
    CHECK_STATUS(ls_optim_init(&opt, &good, 8, 2, big, &arena), LS_ERR_INVALID);     /* 11 > 8 */
    CHECK_EQ(ls_arena_used(&arena), 0);
    CHECK_STATUS(ls_optim_init(&opt, &good, 11, 2, big, &arena), LS_OK);
    CHECK_STATUS(ls_optim_reset(&opt, 2, zero), LS_ERR_INVALID);
    CHECK_STATUS(ls_optim_step(&opt, NULL, NULL, NULL), LS_ERR_INVALID);
    {
        ls_real p[11] = {0}, g[11] = {0};
        ls_diag dg;
        CHECK_STATUS(ls_optim_step(&opt, NULL, g, &dg), LS_ERR_INVALID);
        CHECK(strcmp(dg.what, "params is NULL") == 0);
        CHECK_STATUS(ls_optim_step_mapped(&opt, p, g, NULL, &dg), LS_ERR_INVALID);
        CHECK(strcmp(dg.what, "mapped is NULL") == 0);
    }
    CHECK_EQ(opt.count, 11);
}

typedef struct init_job {
    ls_optim opt;
    ls_optim_config cfg;
} init_job;
static ls_status init_run(void *ctx, ls_arena *arena)
{
    init_job *j = (init_job *)ctx;
    const uint32_t blocks[2] = {300, 3};
    return ls_optim_init(&j->opt, &j->cfg, 400, 2, blocks, arena);
}
static uint64_t init_hash(void *ctx)
{
    init_job *j = (init_job *)ctx;
    return test_hash(&j->opt, sizeof j->opt, TEST_HASH_SEED);
}
static void init_reset(void *ctx)
{
    init_job *j = (init_job *)ctx;
    memset(&j->opt, 0, sizeof j->opt);
}

static void optim_arena_sweep(void)
{
    init_job job;
    sweep_job sj;
    size_t bytes = 0;
    memset(&job, 0, sizeof job);
    memset(&sj, 0, sizeof sj);
    REQUIRE(ls_optim_config_default(LS_OPTIM_ADAM, &job.cfg) == LS_OK);
    sj.name = "optim_init";
    sj.run = init_run;
    sj.state_hash = init_hash;
    sj.reset = init_reset;
    sj.ctx = &job;
    sj.exact = 1;
    REQUIRE(ls_optim_bytes(400, &sj.answer) == LS_OK);
    CHECK_EQ(sj.answer, LS_ARENA_ROUND(400 * sizeof(ls_real)) * 2);
    CHECK_EQ(sweep_arena(&sj), 0);
    CHECK_STATUS(ls_optim_bytes(1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_optim_bytes(UINT32_MAX, &bytes), sizeof(size_t) < 8 ? LS_ERR_TOO_LARGE : LS_OK);
}

int main(void)
{
    TEST_INIT("test_optim");
    TEST_RUN(optim_uniform_adam_matches_reference);
    TEST_RUN(optim_adam_matches_reference);
    TEST_RUN(optim_sgd_matches_reference);
    TEST_RUN(optim_uniform_adam_blocks_are_independent);
    TEST_RUN(optim_nonfinite_gradient_changes_nothing);
    TEST_RUN(optim_reset_restarts_the_trajectory);
    TEST_RUN(optim_zero_gradient_with_zero_eps);
    TEST_RUN(optim_rejects_bad_configurations);
    TEST_RUN(optim_arena_sweep);
    return TEST_END();
}
