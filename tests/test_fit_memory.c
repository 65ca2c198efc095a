/* tests/test_fit_memory.c - the whole job's memory (fit.h: ls_fit_job_bytes,
 * ls_fit_init_job): a fit with two remeshes runs start to end in an arena
 * of exactly the query's bytes (and gives the same bits as the fit in a
 * large arena), one byte less fails at init, a remesh beyond the capacity
 * (vertices, faces, factor fill) is a named error that changes nothing, and
 * bad capacities are refused up front. A sphere fitted to an ellipsoid seen
 * from 3 views at 24 x 24. */
#include "test.h"
#include "geo_test.h"
#include "sweep.h"
#include <stdlib.h>
#include "fit_targets.h"

#define RES 24u
#define NV 3u
#define BUF_BYTES (32u << 20)
#define ITERS 30u

static unsigned char *buf;
static ls_real mvps[NV][16];
static ls_real *targets[NV];
static ls_real sh[27];
static LS_ARENA_BUFFER(mesh_buf, 64 << 10);
static ls_mesh init;

/* Targets: an ellipsoid (level 3), SH shading, S = 4; the initial mesh: a
 * sphere of level 2 (162 vertices). */
static void make_problem(void)
{
    ls_arena arena;
    uint32_t i;
    fit_test_targets(3, NV, RES, buf, BUF_BYTES, mvps, targets, sh);
    REQUIRE(ls_arena_init(&arena, mesh_buf.bytes, sizeof mesh_buf.bytes) == LS_OK);
    REQUIRE(ls_icosphere(2, &arena, &init) == LS_OK);
    for (i = 0; i < 3u * init.vertex_count; i++) init.positions[i] *= (ls_real)0.6;
}

/* 1: the runs below hold a checkpoint and check self-intersections. */
static uint32_t guard_on;
/* 1: the runs below estimate the lighting and a per-vertex albedo. */
static uint32_t albedo_on;
/* 1: the runs below pull the vertices into the masks (config.mask_pull). */
static uint32_t mask_on;

static void config(ls_fit_config *c, uint32_t method, uint32_t solver)
{
    ls_fit_config_default(c);
    c->guard = guard_on;
    c->method = method;
    c->solver = solver;
    c->width = c->height = RES;
    c->shading.mode = LS_SHADE_SH;
    c->shading.sh = sh;
    c->optim.lr = (ls_real)0.05;
    if (mask_on) c->mask_pull = (ls_real)1e-3;
    if (albedo_on) {
        c->shading.sh = NULL;
        c->light = LS_FIT_LIGHT_ESTIMATE;
        c->albedo = LS_FIT_ALBEDO_VERTEX;
    }
    if (method != LS_FIT_LARGE_STEPS) {
        (void)ls_optim_config_default(LS_OPTIM_ADAM, &c->optim);
        c->optim.lr = (ls_real)0.01;
        c->reg_weight = 1;
    }
}

static ls_fit_views views(void)
{
    ls_fit_views v;
    v.count = NV;
    v.mvp = &mvps[0][0];
    v.targets = (const ls_real *const *)targets;
    return v;
}

/* Room for two remeshes of the sphere (162 -> ~600 -> ~2400 vertices);
 * room_vertices above LS_FIT_AUTO_ORDER_VERTICES sizes the job for the
 * other ordering. */
static uint32_t room_vertices = 6000;
static ls_fit_capacity roomy(void)
{
    ls_fit_capacity cap;
    cap.max_vertices = room_vertices;
    cap.max_faces = 2u * room_vertices - 4u; /* a sphere: F = 2 V - 4 */
    cap.max_factor_nnz = room_vertices * 64u;
    return cap;
}

/* ITERS iterations with remeshes before iterations 10 and 20 (job: in its
 * reservation; else in `arena`, as ls_fit_init leaves it). Returns 0 on
 * success, the positions in pos (malloc'd). */
static int run(ls_fit *fit, ls_arena *arena, int job, ls_real **pos)
{
    ls_mesh out;
    ls_diag d;
    uint32_t it;
    ls_status st;
    for (it = 0; it < ITERS; it++) {
        if (it == 10 || it == 20) {
            st = ls_fit_remesh(fit, job ? NULL : arena, (ls_real)0.5, (ls_real)0.8, NULL, &d);
            if (st != LS_OK) {
                printf("     remesh before %u: %s %s\n", (unsigned)it, ls_status_name(st), d.what);
                return 1;
            }
        }
        if (guard_on && it % 5 == 0) { /* the guard's calls use the reserve only */
            ls_tangle_report t;
            st = ls_fit_tangle(fit, &t, &d);
            if (st == LS_OK) st = ls_fit_save(fit);
            if (st != LS_OK || t.intersecting_pairs != 0) {
                printf("     guard before %u: %s, %u pairs\n", (unsigned)it, ls_status_name(st), (unsigned)t.intersecting_pairs);
                return 1;
            }
        }
        if (guard_on && it == 17 && ls_fit_rollback(fit) != LS_OK) return 1; /* back to 15 */
        st = ls_fit_step(fit, NULL, &d);
        if (st != LS_OK) {
            printf("     step %u: %s %s\n", (unsigned)it, ls_status_name(st), d.what);
            return 1;
        }
    }
    *pos = (ls_real *)malloc(3u * (size_t)fit->vertex_count * sizeof(ls_real));
    return *pos == NULL || ls_fit_mesh(fit, *pos, &out) != LS_OK;
}

/* The job in exactly its bytes, peak included, with nothing taken from the
 * caller's arena after init; the same bits as ls_fit_init in a large arena
 * (the remesher's capacity does not change its result). */
static void job_runs_in_exactly_its_bytes(uint32_t method, uint32_t solver)
{
    ls_fit_config c;
    ls_fit_views v = views();
    ls_fit_capacity cap = roomy();
    ls_arena scratch, arena;
    ls_fit fit;
    ls_diag d;
    size_t job = 0, first = 0;
    unsigned char *mem;
    ls_real *a = NULL, *b = NULL;
    uint32_t n;
    config(&c, method, solver);
    REQUIRE(ls_arena_init(&scratch, buf, BUF_BYTES) == LS_OK);
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &job, &d), LS_OK);
    CHECK_STATUS(ls_fit_bytes(&c, &v, &init, &scratch, &first, &d), LS_OK);
    CHECK_EQ(ls_arena_used(&scratch), 0);
    mem = (unsigned char *)malloc(job);
    REQUIRE(mem != NULL && job % LS_ARENA_ALIGN == 0);
    REQUIRE(ls_arena_init(&arena, mem, job) == LS_OK);
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d), LS_OK);
    CHECK_EQ(arena.bottom, job); /* one reservation, nothing left over */
    CHECK_EQ(arena.top, 0);
    CHECK_EQ(ls_arena_available(&arena), 0);
    CHECK(fit.job_fit_bytes >= first);
    CHECK_EQ(run(&fit, &arena, 1, &a), 0);
    CHECK_EQ(fit.remeshes, 2);
    CHECK_EQ(arena.peak, job);
    CHECK_EQ(arena.bottom, job);
    CHECK_EQ(arena.top, 0);
    CHECK(fit.job.peak <= fit.job.capacity);
    CHECK(fit.block.capacity <= fit.job_fit_bytes);
    printf("     method %u solver %u: job %lu bytes (ls_fit_bytes of the initial %u vertices: %lu); fit part %lu, at the "
           "end %lu for %u vertices; work part peak %lu of %lu\n",
           (unsigned)method, (unsigned)solver, (unsigned long)job, (unsigned)init.vertex_count, (unsigned long)first,
           (unsigned long)fit.job_fit_bytes, (unsigned long)fit.block.capacity, (unsigned)fit.vertex_count,
           (unsigned long)(fit.job.peak - fit.job_fit_bytes), (unsigned long)(job - fit.job_fit_bytes));
    n = fit.vertex_count;
    /* the same fit with ls_fit_init in a large arena */
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, &d) == LS_OK);
    CHECK_EQ(run(&fit, &arena, 0, &b), 0);
    CHECK_EQ(fit.vertex_count, n);
    CHECK(a != NULL && b != NULL && fit.vertex_count == n && memcmp(a, b, 3u * (size_t)n * sizeof(ls_real)) == 0);
    free(a);
    free(b);
    free(mem);
}

static void job_large_steps(void) { job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_LDLT); }
/* The checkpoint and the self-intersection check (config.guard) inside the
 * job's bytes, with either solver. */
static void job_with_guard(void)
{
    guard_on = 1;
    job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_CG);
    guard_on = 0;
}
/* The per-vertex albedo and its sums inside the job's bytes, through the
 * remeshes (each estimates it again) and a roll-back. */
static void job_with_vertex_albedo(void)
{
    guard_on = albedo_on = 1;
    job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    guard_on = albedo_on = 0;
}
/* The masks' distance fields inside the job's bytes, made again by every
 * remesh's rebuild. */
static void job_with_mask_pull(void)
{
    guard_on = mask_on = 1;
    job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    guard_on = mask_on = 0;
}
/* A capacity from LS_FIT_AUTO_ORDER_VERTICES on sizes the job for the
 * AUTO ordering (nested dissection's scratch too); the small meshes of the
 * run still take AMD, inside those bytes. */
static void job_sized_for_the_auto_ordering(void)
{
    room_vertices = LS_FIT_AUTO_ORDER_VERTICES + 1000u;
    job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    room_vertices = 6000;
}

/* A mesh of LS_FIT_AUTO_ORDER_VERTICES vertices or more (an icosphere of
 * 40962) is factored with the smaller of AMD and nested dissection's fill
 * (nested dissection's on a regular sphere), in exactly the job's bytes. */
static void large_mesh_takes_the_auto_ordering(void)
{
    ls_fit_config c;
    ls_fit_views v = views();
    ls_fit_capacity cap;
    ls_arena scratch, arena, mesh_arena;
    ls_mesh big;
    ls_fit fit;
    ls_diag d;
    size_t job = 0;
    unsigned char *mem, *mesh_mem;
    uint32_t i;
    if (geo_emulated()) {
        printf("     (skipped under emulation: a 40962-vertex factor)\n");
        return;
    }
    mesh_mem = (unsigned char *)malloc(16u << 20);
    REQUIRE(mesh_mem != NULL && ls_arena_init(&mesh_arena, mesh_mem, 16u << 20) == LS_OK);
    REQUIRE(ls_icosphere(6, &mesh_arena, &big) == LS_OK);
    REQUIRE(big.vertex_count >= LS_FIT_AUTO_ORDER_VERTICES);
    for (i = 0; i < 3u * big.vertex_count; i++) big.positions[i] *= (ls_real)0.6;
    config(&c, LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    cap.max_vertices = big.vertex_count;
    cap.max_faces = big.face_count;
    cap.max_factor_nnz = big.vertex_count * 64u;
    REQUIRE(ls_arena_init(&scratch, buf, BUF_BYTES) == LS_OK);
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &big, &cap, &scratch, &job, &d), LS_OK);
    mem = (unsigned char *)malloc(job);
    REQUIRE(mem != NULL && ls_arena_init(&arena, mem, job) == LS_OK);
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &big, &cap, &arena, &d), LS_OK);
    CHECK_EQ(fit.param.f.method, LS_ORDER_ND);
    CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_OK);
    CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_OK);
    CHECK_EQ(arena.peak, job);
    printf("     %u vertices: nnz(L) %u with nested dissection; job %lu bytes\n", (unsigned)big.vertex_count,
           (unsigned)fit.param.f.l_nnz, (unsigned long)job);
    free(mem);
    free(mesh_mem);
}

static void job_cg_and_baseline(void)
{
    job_runs_in_exactly_its_bytes(LS_FIT_LARGE_STEPS, LS_PARAM_CG);
    job_runs_in_exactly_its_bytes(LS_FIT_BILAPLACIAN, LS_PARAM_LDLT);
}

/* Every arena below the answer fails at init with LS_ERR_NOMEM and leaves
 * the arena as it was; the answer succeeds with the answer as its peak. */
typedef struct init_job {
    ls_fit fit;
    ls_fit_config c;
    ls_fit_views v;
    ls_fit_capacity cap;
} init_job;
static ls_status init_run(void *ctx, ls_arena *arena)
{
    init_job *j = (init_job *)ctx;
    return ls_fit_init_job(&j->fit, &j->c, &j->v, &init, &j->cap, arena, NULL);
}
static uint64_t init_hash(void *ctx)
{
    init_job *j = (init_job *)ctx;
    uint64_t h = test_hash_reals(init.positions, 3u * init.vertex_count, TEST_HASH_SEED);
    return j->fit.x == NULL ? h : h + 1u; /* a failure leaves the fit zeroed */
}

static void job_one_byte_less_fails_at_init(void)
{
    static init_job j;
    ls_arena scratch, arena;
    sweep_job sj;
    ls_diag d;
    unsigned char *mem;
    config(&j.c, LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    j.v = views();
    j.cap = roomy();
    memset(&sj, 0, sizeof sj);
    sj.name = "fit_init_job";
    sj.run = init_run;
    sj.state_hash = init_hash;
    sj.ctx = &j;
    sj.exact = 1;
    REQUIRE(ls_arena_init(&scratch, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_fit_job_bytes(&j.c, &j.v, &init, &j.cap, &scratch, &sj.answer, NULL) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    /* one byte less, named */
    mem = (unsigned char *)malloc(sj.answer);
    REQUIRE(mem != NULL);
    REQUIRE(ls_arena_init(&arena, mem, sj.answer - 1u) == LS_OK);
    CHECK_STATUS(ls_fit_init_job(&j.fit, &j.c, &j.v, &init, &j.cap, &arena, &d), LS_ERR_NOMEM);
    CHECK(d.what != NULL && strstr(d.what, "ls_fit_job_bytes") != NULL);
    CHECK_EQ(arena.need, sj.answer);
    CHECK_EQ(arena.bottom, 0);
    CHECK_EQ(arena.top, 0);
    CHECK(j.fit.x == NULL);
    free(mem);
}

/* The fit's bytes (its part of the reservation) and struct, to compare. */
typedef struct snapshot {
    ls_fit fit;
    unsigned char *bytes;
} snapshot;

static void snap(const ls_fit *fit, snapshot *s)
{
    s->fit = *fit;
    s->bytes = (unsigned char *)malloc(fit->job_fit_bytes);
    if (s->bytes != NULL) memcpy(s->bytes, fit->job.base, fit->job_fit_bytes);
}

static int same(const ls_fit *fit, const snapshot *s)
{
    ls_fit a = *fit, b = s->fit;
    /* the reservation's work part moves its peak only */
    a.job.peak = b.job.peak = 0;
    return s->bytes != NULL && memcmp(&a, &b, sizeof a) == 0 &&
           memcmp(s->bytes, fit->job.base, fit->job_fit_bytes) == 0;
}

/* A remesh past one capacity field: the named error, nothing changed, and
 * the run goes on (a coarser remesh, when given, then fits). */
static void remesh_past(const char *field, ls_fit_capacity cap, ls_real coarser)
{
    ls_fit_config c;
    ls_fit_views v = views();
    ls_arena arena;
    ls_fit fit;
    ls_diag d;
    ls_mesh m;
    ls_real *pos;
    snapshot s;
    uint32_t it;
    ls_status st;
    config(&c, LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d) == LS_OK);
    for (it = 0; it < 5; it++) REQUIRE(ls_fit_step(&fit, NULL, &d) == LS_OK);
    /* the solver's workspace holds the sums of the last solve: the remesh
     * starts with x = M^-1 u, so the same solve first */
    pos = (ls_real *)malloc(3u * (size_t)fit.vertex_count * sizeof(ls_real));
    REQUIRE(pos != NULL && ls_fit_mesh(&fit, pos, &m) == LS_OK);
    free(pos);
    snap(&fit, &s);
    st = ls_fit_remesh(&fit, NULL, (ls_real)0.5, (ls_real)0.8, NULL, &d);
    CHECK_STATUS(st, LS_ERR_TOO_LARGE);
    printf("     %s: %s (needed %lu, capacity %.0f)\n", field, d.what, (unsigned long)d.index, (double)d.value);
    CHECK(d.what != NULL && strstr(d.what, field) != NULL && strstr(d.what, "remesh") == d.what);
    CHECK(d.has_index && d.has_value && (double)d.index > (double)d.value);
    CHECK(same(&fit, &s));
    CHECK_EQ(fit.job.bottom, fit.job_fit_bytes);
    CHECK_EQ(fit.job.top, 0);
    free(s.bytes);
    for (it = 0; it < 5; it++) CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_OK);
    CHECK_EQ(fit.iteration, 10);
    if (coarser > 0) {
        CHECK_STATUS(ls_fit_remesh(&fit, NULL, coarser, (ls_real)0.8, NULL, &d), LS_OK);
        CHECK_EQ(fit.remeshes, 1);
        CHECK(fit.vertex_count <= cap.max_vertices);
        CHECK_STATUS(ls_fit_step(&fit, NULL, &d), LS_OK);
    }
}

static void remesh_beyond_capacity(void)
{
    ls_fit_capacity cap = roomy();
    ls_fit fit;
    ls_fit_config c;
    ls_fit_views v = views();
    ls_arena arena;
    uint32_t fill;
    cap.max_vertices = 400; /* the remesh to half the edge needs ~600 */
    cap.max_faces = 2u * 400u - 4u;
    remesh_past("max_vertices", cap, (ls_real)1);
    cap = roomy();
    cap.max_faces = 400; /* vertices allow it, faces do not */
    remesh_past("max_faces", cap, (ls_real)0);
    /* the initial factor's fill exactly: the finer mesh fills more */
    config(&c, LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, NULL) == LS_OK);
    fill = fit.param.f.l_nnz;
    cap = roomy();
    cap.max_factor_nnz = fill;
    remesh_past("max_factor_nnz", cap, (ls_real)0);
}

static void bad_capacities(void)
{
    ls_fit_config c;
    ls_fit_views v = views();
    ls_fit_capacity cap;
    ls_arena scratch, arena;
    ls_fit fit;
    ls_diag d;
    size_t bytes = 1;
    uint32_t fill;
    config(&c, LS_FIT_LARGE_STEPS, LS_PARAM_LDLT);
    REQUIRE(ls_arena_init(&scratch, buf, BUF_BYTES / 2u) == LS_OK);
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2u, BUF_BYTES / 2u) == LS_OK);
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, NULL, &scratch, &bytes, &d), LS_ERR_INVALID);
    CHECK_EQ(bytes, 0);
    cap = roomy();
    cap.max_vertices = 0;
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "max_vertices") != NULL);
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d), LS_ERR_INVALID);
    cap = roomy();
    cap.max_faces = 0;
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_ERR_INVALID);
    cap = roomy();
    cap.max_factor_nnz = 0; /* needed by the LDL^T only */
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "max_factor_nnz") != NULL);
    c.solver = LS_PARAM_CG;
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_OK);
    c.solver = LS_PARAM_LDLT;
    /* below the initial mesh: named, with the count and the capacity */
    cap = roomy();
    cap.max_vertices = init.vertex_count - 1u;
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_ERR_TOO_LARGE);
    CHECK(strstr(d.what, "initial mesh: more vertices than capacity.max_vertices") != NULL);
    CHECK(d.index == init.vertex_count && d.value == (ls_real)(init.vertex_count - 1u));
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d), LS_ERR_TOO_LARGE);
    CHECK_EQ(arena.bottom, 0);
    CHECK_EQ(arena.top, 0);
    cap = roomy();
    cap.max_faces = init.face_count - 1u;
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_ERR_TOO_LARGE);
    CHECK(strstr(d.what, "max_faces") != NULL);
    REQUIRE(ls_fit_init(&fit, &c, &v, &init, &arena, NULL) == LS_OK);
    fill = fit.param.f.l_nnz;
    REQUIRE(ls_arena_init(&arena, buf + BUF_BYTES / 2u, BUF_BYTES / 2u) == LS_OK);
    cap = roomy();
    cap.max_factor_nnz = fill - 1u;
    CHECK_STATUS(ls_fit_job_bytes(&c, &v, &init, &cap, &scratch, &bytes, &d), LS_ERR_TOO_LARGE);
    CHECK(strstr(d.what, "initial mesh: more LDL^T factor entries than capacity.max_factor_nnz") != NULL);
    CHECK(d.index == fill);
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d), LS_ERR_TOO_LARGE);
    CHECK(strstr(d.what, "max_factor_nnz") != NULL);
    CHECK_EQ(arena.bottom, 0);
    CHECK_EQ(arena.top, 0);
    CHECK(fit.x == NULL);
    cap.max_factor_nnz = fill;
    CHECK_STATUS(ls_fit_init_job(&fit, &c, &v, &init, &cap, &arena, &d), LS_OK);
    CHECK_EQ(ls_arena_used(&scratch), 0);
}

int main(void)
{
    uint32_t v;
    TEST_INIT("test_fit_memory");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(make_problem);
    TEST_RUN(job_large_steps);
    TEST_RUN(job_cg_and_baseline);
    TEST_RUN(job_with_guard);
    TEST_RUN(job_with_vertex_albedo);
    TEST_RUN(job_with_mask_pull);
    TEST_RUN(job_sized_for_the_auto_ordering);
    TEST_RUN(large_mesh_takes_the_auto_ordering);
    TEST_RUN(job_one_byte_less_fails_at_init);
    TEST_RUN(remesh_beyond_capacity);
    TEST_RUN(bad_capacities);
    for (v = 0; v < NV; v++) free(targets[v]);
    free(buf);
    return TEST_END();
}
