/* test_mcu.c - the MCU-profile workload: what a Cortex-M4 part with 256 KiB
 * of RAM and an 8 KiB stack must be able to run.
 *
 * Each job in the table below runs the library on a fixed static arena of
 * MCU_ARENA_BYTES and must (1) succeed and check its own results, (2) fit the
 * arena (its peak is printed), and (3) on the Cortex-M4 port, stay within
 * MCU_JOB_STACK bytes of stack, measured by painting the stack before the job
 * (port/cortex-m4/ls_m4.h). `make m4` runs it in the MCU profile (mcu.ld);
 * every other target runs it as an ordinary test program, where the stack is
 * not measured. Later issues add jobs: an LDL^T solve on a small icosphere,
 * then a tiny fit, then a tiny fit with a remesh inside its job's
 * reservation (ls_fit_job_bytes). A job gets the arena initialised and empty; it reports
 * failures with CHECK/REQUIRE like any test.
 */
#include "test.h"
#if defined(LS_PORT_CORTEX_M4)
#include "ls_m4.h"
#endif

/* The deterministic math module (largesteps/math.h), present when its
 * type-generic macros are. */
#if defined(LS_RSIN)
#define MCU_MATH 1
#else
#define MCU_MATH 0
#endif

/* RAM budget: 256 KiB = 8 KiB stack + this arena + newlib's data and stdio
 * buffers (about 4 KiB) + the program's own static data. 224 KiB holds the
 * LDL^T of a 642-vertex icosphere in float (peak 222 KiB). The MCU builds sum
 * in float (SUMS=real); a host's float build sums in double, whose work
 * vectors take 10 KiB more. */
#if LS_REAL_IS_FLOAT && LS_SUMS_DOUBLE
#define MCU_ARENA_BYTES (240u * 1024u)
#else
#define MCU_ARENA_BYTES (224u * 1024u)
#endif
/* Stack budget of one job (the library's rule: a public function's worst
 * call chain is at most 4096 bytes), leaving room for main and printf. */
#define MCU_JOB_STACK 4096u

/* The bits of the MCU LDL^T job's solution (test_hash_reals), the same on
 * every target: printed by the job, fixed here. */
#define MCU_LDLT_HASH_FLOAT 0x369e68262d0c2094ull      /* float sums (SUMS=real) */
#define MCU_LDLT_HASH_FLOAT_DSUMS 0xdf9f87bf9f602542ull /* double sums (SUMS=double) */
#define MCU_LDLT_HASH_DOUBLE 0x3f59875378ab6e20ull

static LS_ARENA_BUFFER(mcu_buffer, MCU_ARENA_BYTES);

static void job_selftest(ls_arena *arena)
{
    (void)arena;
    CHECK_STATUS(ls_selftest(sizeof(ls_real)), LS_OK);
}

/* Fill the whole arena with 1 KiB objects and 512-byte scratch blocks from
 * both ends, then roll back: the arena must hand out exactly its capacity. */
static void job_arena_fill(ls_arena *arena)
{
    ls_arena_mark mark = ls_arena_save(arena);
    size_t objects = 0, scratch = 0;
    unsigned char *p;
    for (;;) {
        p = (unsigned char *)ls_arena_alloc(arena, 1024, 1);
        if (p == NULL) break;
        p[0] = (unsigned char)objects;
        p[1023] = (unsigned char)objects;
        objects++;
        p = (unsigned char *)ls_arena_scratch(arena, 512, 1);
        if (p == NULL) break;
        p[0] = 1;
        scratch++;
    }
    CHECK_EQ(objects * 1024 + scratch * 512 + 1024 > arena->capacity, 1);
    CHECK_EQ(arena->need > arena->capacity, 1);
    CHECK(ls_arena_available(arena) < 1024);
    ls_arena_restore(arena, mark);
    CHECK_EQ(ls_arena_used(arena), 0);
    CHECK_EQ(arena->peak, objects * 1024 + scratch * 512);
}

#if MCU_MATH
/* The elementary functions of the build's ls_real: identities that hold to
 * a few ulps, over a sweep (also measures the math functions' stack). */
static void job_math(ls_arena *arena)
{
    int k;
    double worst_pyth = 0, worst_explog = 0;
    (void)arena;
    for (k = -2000; k <= 2000; k++) {
        ls_real x = (ls_real)k / (ls_real)64;
        ls_real s = LS_RSIN(x), c = LS_RCOS(x);
        ls_real e = LS_REXP(x / (ls_real)8), l = LS_RLOG(e);
        double pyth = fabs((double)(s * s + c * c) - 1.0);
        double explog = fabs((double)l - (double)(x / (ls_real)8));
        if (pyth > worst_pyth) worst_pyth = pyth;
        if (explog > worst_explog) worst_explog = explog;
    }
    CHECK_NEAR(worst_pyth, 0, TEST_EPS(4));
    CHECK_NEAR(worst_explog, 0, TEST_EPS(4) * 32);
}
#endif

/* The solver on the MCU: M = I + 19 L of an icosphere (642 vertices in float,
 * as the LDLT issue asks; 162 in double, whose factor would not fit), ordered
 * from the coordinates (AUTO), factored, 3 right-hand sides solved. The
 * residual is checked and the solution's bits must equal the host's: the
 * hash below is the one every target prints (also checked natively). */
static void job_ldlt(ls_arena *arena)
{
#if LS_REAL_IS_FLOAT
    const uint32_t level = 3;
    const uint64_t want = sizeof(ls_acc) == 8 ? MCU_LDLT_HASH_FLOAT_DSUMS : MCU_LDLT_HASH_FLOAT;
#else
    const uint32_t level = 2;
    const uint64_t want = MCU_LDLT_HASH_DOUBLE;
#endif
    ls_mesh m;
    ls_csc lap, a;
    ls_ldlt f;
    ls_real *x, *r;
    uint32_t i;
    double worst = 0, scale = 0;
    uint64_t h;
    REQUIRE(ls_icosphere(level, arena, &m) == LS_OK);
    REQUIRE(ls_laplacian_uniform(&m, LS_LAP_UPPER, arena, &lap, NULL) == LS_OK);
    REQUIRE(ls_laplacian_system(&lap, LS_SYSTEM_LAMBDA, (ls_real)19, arena, &a, NULL) == LS_OK);
    REQUIRE(ls_ldlt_analyze_mesh(&a, LS_ORDER_AUTO, m.positions, arena, &f, NULL) == LS_OK);
    REQUIRE(ls_ldlt_factor(&f, &a, arena, NULL) == LS_OK);
    x = (ls_real *)ls_arena_alloc(arena, 3u * m.vertex_count, sizeof(ls_real));
    REQUIRE(x != NULL);
    memcpy(x, m.positions, 3u * m.vertex_count * sizeof(ls_real));
    REQUIRE(ls_ldlt_solve(&f, 3, x, arena) == LS_OK);
    r = (ls_real *)ls_arena_alloc(arena, 3u * m.vertex_count, sizeof(ls_real)); /* where the solve's scratch was */
    REQUIRE(r != NULL);
    REQUIRE(ls_csc_matvec_sym(&a, 3, x, r) == LS_OK);
    for (i = 0; i < 3u * m.vertex_count; i++) {
        double e = fabs((double)r[i] - (double)m.positions[i]);
        if (e > worst) worst = e;
        if (fabs((double)x[i]) > scale) scale = fabs((double)x[i]);
    }
    CHECK_MSG(worst <= TEST_EPS(64) * 153.0 * scale, "residual %.3g", worst); /* |M| <= 1 + 19 * 2 * 6 */
    h = test_hash_reals(x, 3u * m.vertex_count, TEST_HASH_SEED);
    printf("     ldlt: %u vertices, nnz(L) %u (%s), residual %.2g, solution hash %016llx\n", (unsigned)m.vertex_count,
           (unsigned)f.l_nnz, f.method == LS_ORDER_ND ? "nd" : "amd", worst, (unsigned long long)h);
    CHECK_MSG(h == want, "solution hash %016llx differs from the host's %016llx", (unsigned long long)h,
              (unsigned long long)want);
}

/* A fit on the MCU: one view at 32 x 32 (float; 16 x 16 in double,
 * whose buffers are twice as large) of an ellipsoid, from an icosphere of
 * level 1 (level 0 in double), 10 iterations of large steps. The memory is
 * sized by ls_fit_bytes on the target itself, and the fit runs in what the
 * query said. */
/* A tiny fit from a static buffer sized on the target: by ls_fit_bytes,
 * or (whole_job) by ls_fit_job_bytes for a capacity that holds one remesh,
 * which then runs inside the reservation. */
static void fit_on_target(ls_arena *arena, int whole_job)
{
#if LS_REAL_IS_FLOAT
    const uint32_t res = whole_job ? 16 : 32, level = whole_job ? 0 : 1;
#else
    const uint32_t res = 16, level = 0;
#endif
    static const ls_real sh[27] = {(ls_real)1.6, (ls_real)0.8, (ls_real)0.4, 0, 0, 0, 0, 0, 0,
                                   (ls_real)1.6, (ls_real)0.8, (ls_real)0.4, 0, 0, 0, 0, 0, 0,
                                   (ls_real)1.6, (ls_real)0.8, (ls_real)0.4, 0, 0, 0, 0, 0, 0};
    const ls_real dir[3] = {(ls_real)0.3, (ls_real)0.4, 1};
    ls_mesh target, init;
    ls_camera_framing fr;
    static ls_fit_config c; /* as the fit: the caller's to place (it grows with the options) */
    ls_fit_views views;
    static ls_fit fit; /* not on the job's stack: the object is the caller's to place (about 1 KiB) */
    ls_vis vis;
    ls_real mvp[16], *img, *normals, first = 0;
    const ls_real *targets[1];
    ls_arena_mark mark;
    ls_fit_capacity cap;
    size_t bytes = 0, before;
    uint32_t i;
    cap.max_vertices = 96; /* a remesh to half the mean edge: about 4x the vertices */
    cap.max_faces = 2u * 96u - 4u;
    cap.max_factor_nnz = 96u * 16u;
    REQUIRE(ls_icosphere(2, arena, &target) == LS_OK);
    for (i = 0; i < target.vertex_count; i++) target.positions[3 * i] *= (ls_real)1.4;
    ls_fit_config_default(&c);
    c.width = c.height = res;
    c.shading.mode = LS_SHADE_SH;
    c.shading.sh = sh;
    c.optim.lr = (ls_real)0.02;
    REQUIRE(ls_camera_frame(target.positions, target.vertex_count, (ls_real)0.8, LS_FOV_X, 1, (ls_real)1.1, &fr, NULL) == LS_OK);
    REQUIRE(ls_camera_framed_view(&fr, dir, NULL, mvp) == LS_OK);
    img = (ls_real *)ls_arena_alloc(arena, 4u * res * res, sizeof(ls_real));
    REQUIRE(img != NULL);
    targets[0] = img;
    mark = ls_arena_save(arena);
    normals = (ls_real *)ls_arena_alloc(arena, 3u * target.vertex_count, sizeof(ls_real));
    REQUIRE(normals != NULL);
    REQUIRE(ls_shade_vertex_normals(target.positions, target.vertex_count, target.triangles, target.face_count, normals,
                                    NULL) == LS_OK);
    REQUIRE(ls_vis_init(&vis, arena, res, res, 1, target.vertex_count) == LS_OK);
    REQUIRE(ls_raster(&vis, &(ls_view){.positions = target.positions, .indices = target.triangles,
            .triangle_count = target.face_count, .vertex_count = target.vertex_count, .mvp = mvp}, arena,
            NULL) == LS_OK);
    REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = target.triangles, .triangle_count = target.face_count,
            .vertex_count = target.vertex_count, .normals = normals, .opts = &c.shading}, img, NULL) ==
            LS_OK);
    ls_arena_restore(arena, mark);
    REQUIRE(ls_icosphere(level, arena, &init) == LS_OK);
    views.count = 1;
    views.mvp = mvp;
    views.targets = targets;
    before = ls_arena_used(arena);
    if (whole_job) {
        REQUIRE(ls_fit_job_bytes(&c, &views, &init, &cap, arena, &bytes, NULL) == LS_OK);
        CHECK(bytes <= ls_arena_available(arena));
        REQUIRE(ls_fit_init_job(&fit, &c, &views, &init, &cap, arena, NULL) == LS_OK);
    } else {
        REQUIRE(ls_fit_bytes(&c, &views, &init, arena, &bytes, NULL) == LS_OK);
        CHECK(bytes <= ls_arena_available(arena));
        REQUIRE(ls_fit_init(&fit, &c, &views, &init, arena, NULL) == LS_OK);
    }
    CHECK_EQ(ls_arena_used(arena) - before, LS_ARENA_ROUND(bytes));
    for (i = 0; i < 10; i++) {
        if (whole_job && i == 5) REQUIRE(ls_fit_remesh(&fit, NULL, (ls_real)0.5, (ls_real)0.8, NULL, NULL) == LS_OK);
        REQUIRE(ls_fit_step(&fit, NULL, NULL) == LS_OK);
        if (i == 0) first = fit.loss;
        CHECK(fit.loss - fit.loss == 0);
    }
    CHECK_EQ(ls_arena_used(arena) - before, LS_ARENA_ROUND(bytes)); /* nothing more after init */
    printf("     fit%s: %ux%u, %u -> %u vertices, %s %lu, loss %.5g -> %.5g\n", whole_job ? " with a remesh" : "",
           (unsigned)res, (unsigned)res, (unsigned)init.vertex_count, (unsigned)fit.vertex_count,
           whole_job ? "ls_fit_job_bytes" : "ls_fit_bytes", (unsigned long)bytes, (double)first, (double)fit.loss);
}

static void job_fit(ls_arena *arena) { fit_on_target(arena, 0); }
static void job_fit_whole(ls_arena *arena) { fit_on_target(arena, 1); }

typedef struct mcu_job {
    const char *name;
    void (*run)(ls_arena *arena);
} mcu_job;

static const mcu_job jobs[] = {
    {"mcu_selftest", job_selftest},
    {"mcu_arena_fill", job_arena_fill},
#if MCU_MATH
    {"mcu_math", job_math},
#endif
    {"mcu_ldlt", job_ldlt},
    {"mcu_fit", job_fit},
    {"mcu_fit_job", job_fit_whole},
};

static void run_job(const mcu_job *job)
{
    ls_arena arena;
#if defined(LS_PORT_CORTEX_M4)
    size_t stack = 0;
    uintptr_t mark;
#endif
    test_g.current = job->name;
    test_g.failures_in_test = 0;
    if (ls_arena_init(&arena, mcu_buffer.bytes, sizeof mcu_buffer.bytes) != LS_OK) {
        TEST_FAILMSG_("ls_arena_init failed");
    } else {
#if defined(LS_PORT_CORTEX_M4)
        mark = ls_m4_stack_paint();
        job->run(&arena);
        stack = ls_m4_stack_used_since(mark);
        CHECK_MSG(stack <= MCU_JOB_STACK, "stack %lu bytes > budget %u", (unsigned long)stack, MCU_JOB_STACK);
#else
        job->run(&arena);
#endif
        CHECK(arena.peak <= MCU_ARENA_BYTES);
    }
    if (test_g.failures_in_test == 0) {
        test_g.passed++;
#if defined(LS_PORT_CORTEX_M4)
        printf("ok   %s (arena peak %lu bytes, stack %lu bytes)\n", job->name,
               (unsigned long)arena.peak, (unsigned long)stack);
#else
        printf("ok   %s (arena peak %lu bytes)\n", job->name, (unsigned long)arena.peak);
#endif
    } else {
        test_g.failed++;
    }
    fflush(stdout);
}

#if defined(LS_PORT_CORTEX_M4)
/* The whole program, printf included, within the profile's stack. */
static void whole_program_stack_fits(void)
{
    size_t used = ls_m4_stack_high_water(), size = ls_m4_stack_size();
    printf("     stack high-water so far %lu of %lu bytes, RAM %lu bytes\n", (unsigned long)used,
           (unsigned long)size, (unsigned long)ls_m4_ram_size());
    CHECK(used + 1024 <= size);
}
#endif

int main(void)
{
    size_t i;
    TEST_INIT("test_mcu");
    for (i = 0; i < sizeof jobs / sizeof jobs[0]; i++) run_job(&jobs[i]);
#if defined(LS_PORT_CORTEX_M4)
    TEST_RUN(whole_program_stack_fits);
#endif
    return TEST_END();
}
