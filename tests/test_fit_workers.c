/* tests/test_fit_workers.c - the fit's views shared by the caller's workers
 * (fit.h: config.workers, config.parallel): 1, 2, 3 and 4 workers give the
 * same bits (positions, losses, estimated lighting and albedo), with the
 * tasks run in orders and on worker numbers that change from call to call,
 * through the batch's chunks, remeshes, a roll-back, the masks' pull, the
 * pair silhouettes and the adaptive supersampling; the memory for W workers is exact (the
 * job runs in exactly ls_fit_job_bytes) and grows with W by the per-worker
 * cost. A sphere fitted to an ellipsoid seen from 7 views at 24 x 24. */
#include "test.h"
#include <stdlib.h>
#include "fit_targets.h"

#define RES 24u
#define NV 7u
#define BUF_BYTES (48u << 20)
#define ITERS 24u

static unsigned char *buf;
static ls_real mvps[NV][16];
static ls_real *targets[NV];
static ls_real sh[27];

/* A parallel-for on this thread that does what threads may: tasks in an
 * order that changes with every call (a rotation, every other call
 * reversed) on worker numbers that rotate too. */
typedef struct scrambler {
    uint32_t workers, calls;
} scrambler;

static void scrambled_for(void *ctx, uint32_t count, ls_task_fn task, void *arg)
{
    scrambler *s = (scrambler *)ctx;
    const uint32_t shift = s->calls % count, flip = s->calls % 2u;
    uint32_t k;
    for (k = 0; k < count; k++) {
        const uint32_t i = flip ? count - 1u - (k + shift) % count : (k + shift) % count;
        task(arg, i, (k + s->calls) % s->workers);
    }
    s->calls++;
}

typedef struct run_out {
    uint64_t hash;      /* positions, losses, lighting, albedo */
    uint32_t vertices;
    uint32_t pulled;    /* steps whose masks' pull had a value */
    size_t job_bytes;
} run_out;

enum { CASE_PLAIN, CASE_ESTIMATE, CASE_PAIR, CASE_REFINE, CASE_COUNT };

static void configure(ls_fit_config *c, int which, scrambler *s, uint32_t workers)
{
    ls_fit_config_default(c);
    c->width = c->height = RES;
    c->shading.mode = LS_SHADE_SH;
    c->shading.sh = sh;
    c->optim.lr = (ls_real)0.05;
    c->guard = 1;
    c->view_batch = 5; /* 5 of the 7 views: chunks of every size */
    c->mask_pull = (ls_real)0.01; /* its value and gradient summed over blocks of vertices */
    if (which == CASE_ESTIMATE) {
        c->shading.sh = NULL;
        c->light = LS_FIT_LIGHT_ESTIMATE;
        c->albedo = LS_FIT_ALBEDO_VERTEX;
    } else if (which == CASE_PAIR) {
        c->silhouette = LS_FIT_SILHOUETTE_PAIR;
    } else if (which == CASE_REFINE) {
        c->ss = 1;
        c->aa = 2;
    }
    c->workers = workers;
    s->workers = workers;
    s->calls = 0;
    c->parallel.run = workers > 1u ? scrambled_for : NULL;
    c->parallel.ctx = s;
}

/* ITERS steps in a job of exactly its bytes: a remesh before 8 and 16, a
 * save at 10 and a roll-back at 13. */
static void run(int which, uint32_t workers, run_out *result)
{
    ls_fit_config c;
    ls_fit_views v;
    ls_fit_capacity cap;
    ls_arena scratch, arena, mesh_arena;
    ls_mesh init;
    ls_fit fit;
    ls_diag d;
    scrambler s;
    run_out out;
    unsigned char *mem;
    memset(result, 0, sizeof *result);
    uint32_t it, i;
    uint64_t h = TEST_HASH_SEED;
    memset(&out, 0, sizeof out);
    configure(&c, which, &s, workers);
    v.count = NV;
    v.mvp = &mvps[0][0];
    v.targets = (const ls_real *const *)targets;
    cap.max_vertices = 3000;
    cap.max_faces = 2u * 3000u - 4u;
    cap.max_factor_nnz = 3000u * 64u;
    REQUIRE(ls_arena_init(&mesh_arena, buf, 1u << 20) == LS_OK);
    REQUIRE(ls_icosphere(2, &mesh_arena, &init) == LS_OK);
    for (i = 0; i < 3u * init.vertex_count; i++) init.positions[i] *= (ls_real)0.85; /* beyond the ellipsoid in y: the masks pull */
    REQUIRE(ls_arena_init(&scratch, buf + (1u << 20), BUF_BYTES - (1u << 20)) == LS_OK);
    REQUIRE(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &out.job_bytes, &d) == LS_OK);
    mem = (unsigned char *)malloc(out.job_bytes);
    REQUIRE(mem != NULL);
    REQUIRE(ls_arena_init(&arena, mem, out.job_bytes) == LS_OK);
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d), LS_OK);
    for (it = 0; it < ITERS; it++) {
        if (it == 8 || it == 16) REQUIRE(ls_fit_remesh(&fit, NULL, (ls_real)0.6, (ls_real)0.9, NULL, &d) == LS_OK);
        if (it == 10) REQUIRE(ls_fit_save(&fit) == LS_OK);
        if (it == 13) REQUIRE(ls_fit_rollback(&fit) == LS_OK);
        if (ls_fit_step(&fit, NULL, &d) != LS_OK) {
            printf("     case %d, %u workers, step %u: %s\n", which, (unsigned)workers, (unsigned)it, d.what);
            free(mem);
            return;
        }
        h = test_hash_reals(&fit.loss, 1, h);
        h = test_hash_reals(&fit.reg_loss, 1, h);
        out.pulled += fit.reg_loss > (ls_real)0;
    }
    CHECK_EQ(arena.peak, out.job_bytes); /* exactly the job's bytes, and not one more */
    CHECK(fit.job.peak <= fit.job.capacity);
    h = test_hash_reals(fit.x, 3u * (size_t)fit.vertex_count, h);
    h = test_hash_reals(fit.params, 3u * (size_t)fit.vertex_count + 3u, h);
    h = test_hash_reals(fit.sh, 27, h);
    if (fit.albedo != NULL) h = test_hash_reals(fit.albedo, 3u * (size_t)fit.vertex_count, h);
    out.hash = h;
    out.vertices = fit.vertex_count;
    free(mem);
    *result = out;
}

static void same_bits_for_every_worker_count(void)
{
    int which;
    for (which = 0; which < CASE_COUNT; which++) {
        run_out one, many;
        uint32_t w;
        run(which, 1, &one);
        CHECK(one.hash != 0 && one.vertices > 162u); /* it ran and remeshed */
        CHECK(one.pulled > 0u);                      /* some vertices were outside the masks */
        for (w = 2; w <= 4; w++) {
            run(which, w, &many);
            CHECK_MSG(many.hash == one.hash && many.vertices == one.vertices,
                      "case %d: %u workers give other bits than one", which, (unsigned)w);
            CHECK(many.job_bytes > one.job_bytes); /* each worker has its buffers */
            if (w == 2)
                printf("     case %d: %u vertices at the end; job %lu bytes with 1 worker, %lu with 2\n", which,
                       (unsigned)one.vertices, (unsigned long)one.job_bytes, (unsigned long)many.job_bytes);
        }
    }
}

/* A bad worker count is refused; more workers than views is fine. */
static void worker_config(void)
{
    ls_fit_config c;
    ls_fit_views v;
    ls_fit fit;
    ls_mesh init;
    ls_arena arena;
    ls_diag d;
    scrambler s;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_icosphere(1, &arena, &init) == LS_OK);
    v.count = NV;
    v.mvp = &mvps[0][0];
    v.targets = (const ls_real *const *)targets;
    configure(&c, CASE_PLAIN, &s, LS_FIT_MAX_WORKERS + 1u);
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "config->workers") != NULL);
    configure(&c, CASE_PLAIN, &s, 9); /* 9 workers, 5 views a batch */
    CHECK_STATUS(ls_fit_init(&fit, &c, &v, &init, &arena, &d), LS_OK);
    CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_OK);
}

int main(void)
{
    uint32_t k;
    TEST_INIT("test_fit_workers");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    fit_test_targets(3, NV, RES, buf, BUF_BYTES, mvps, targets, sh);
    TEST_RUN(same_bits_for_every_worker_count);
    TEST_RUN(worker_config);
    for (k = 0; k < NV; k++) free(targets[k]);
    free(buf);
    return TEST_END();
}
