/* tests/test_primitive.c - icosphere and grid meshes: counts, geometry,
 * topology (validated by ls_mesh_validate), orientation, exact sizing. */
#include "test.h"
#include "geo_test.h"
#include "sweep.h"
#include <stdlib.h>

#define BUF_BYTES (8u << 20)
static unsigned char *buf;

static double edge_len(const ls_mesh *m, uint32_t a, uint32_t b)
{
    const ls_real *p = m->positions + 3u * a, *q = m->positions + 3u * b;
    double dx = (double)p[0] - q[0], dy = (double)p[1] - q[1], dz = (double)p[2] - q[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static void icosphere_geometry_and_topology(void)
{
    uint32_t level;
    double prev_volume = 0.0;
    for (level = 0; level <= 4; level++) {
        ls_arena arena;
        ls_mesh m;
        ls_mesh_report r;
        uint32_t v, f, e, i, k;
        double worst_radius = 0.0, lmin = 1e30, lmax = 0.0, vol;
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(ls_icosphere_counts(level, &v, &f, &e) == LS_OK);
        REQUIRE(ls_icosphere(level, &arena, &m) == LS_OK);
        CHECK_EQ(m.vertex_count, v);
        CHECK_EQ(m.face_count, f);
        CHECK_EQ(v, 10u * (1u << (2u * level)) + 2u);
        for (i = 0; i < v; i++) {
            const ls_real *p = m.positions + 3u * i;
            double r2 = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
            if (fabs(r2 - 1.0) > worst_radius) worst_radius = fabs(r2 - 1.0);
        }
        CHECK_MSG(worst_radius <= TEST_EPS(4), "level %u: radius off by %.3g", (unsigned)level, worst_radius);
        for (i = 0; i < f; i++)
            for (k = 0; k < 3; k++) {
                double l = edge_len(&m, m.triangles[3u * i + k], m.triangles[3u * i + (k + 1u) % 3u]);
                if (l < lmin) lmin = l;
                if (l > lmax) lmax = l;
            }
        /* subdividing the icosahedron keeps edges within a factor 1.2 of each other */
        CHECK_MSG(lmax / lmin < 1.2, "level %u: edge ratio %.4f", (unsigned)level, lmax / lmin);
        REQUIRE(ls_mesh_validate(&m, &arena, &r) == LS_OK);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_ALL, NULL), LS_OK);
        CHECK_EQ(r.edge_count, e);
        CHECK_EQ(r.components, 1);
        CHECK_EQ(r.has_genus, 1);
        CHECK_EQ(r.genus, 0);
        CHECK_EQ(r.duplicate_faces, 0);
        vol = geo_signed_volume(&m);
        /* outward, growing towards the ball's 4 pi / 3 */
        CHECK(vol > prev_volume && vol < 4.0 * 3.14159265358979 / 3.0);
        prev_volume = vol;
        printf("     level %u: %u vertices, %u faces, edge ratio %.4f, volume %.6f\n", (unsigned)level, (unsigned)v,
               (unsigned)f, lmax / lmin, vol);
    }
    CHECK(4.0 * 3.14159265358979 / 3.0 - prev_volume < 0.02);
}

/* The vertices of level l are a bit-exact prefix of those of level l + 1. */
static void icosphere_levels_nest(void)
{
    ls_arena arena;
    ls_mesh a, b;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_icosphere(2, &arena, &a) == LS_OK);
    REQUIRE(ls_icosphere(3, &arena, &b) == LS_OK);
    CHECK(memcmp(a.positions, b.positions, 3u * sizeof(ls_real) * a.vertex_count) == 0);
}

typedef struct ico_job {
    uint32_t level;
    int grid;
    ls_mesh m;
} ico_job;
static ls_status ico_run(void *ctx, ls_arena *arena)
{
    ico_job *j = (ico_job *)ctx;
    return j->grid ? ls_grid_mesh(5, 3, arena, &j->m) : ls_icosphere(j->level, arena, &j->m);
}
static uint64_t ico_hash(void *ctx)
{
    ico_job *j = (ico_job *)ctx;
    return test_hash(&j->m, sizeof j->m, TEST_HASH_SEED);
}
static void ico_reset(void *ctx)
{
    ico_job *j = (ico_job *)ctx;
    memset(&j->m, 0, sizeof j->m);
}

static void primitive_arena_sweeps(void)
{
    ico_job job;
    sweep_job sj;
    uint32_t level;
    memset(&sj, 0, sizeof sj);
    memset(&job, 0, sizeof job);
    sj.run = ico_run;
    sj.state_hash = ico_hash;
    sj.reset = ico_reset;
    sj.ctx = &job;
    sj.exact = 1;
    for (level = 0; level <= 3; level++) {
        job.level = level;
        sj.name = "icosphere";
        REQUIRE(ls_icosphere_bytes(level, &sj.answer) == LS_OK);
        CHECK_EQ(sweep_arena(&sj), 0);
    }
    job.grid = 1;
    sj.name = "grid_mesh";
    REQUIRE(ls_grid_mesh_bytes(5, 3, &sj.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
}

static void grid_mesh_layout(void)
{
    ls_arena arena;
    ls_mesh m;
    ls_mesh_report r;
    ls_real n[3 * 24];
    uint32_t i;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_grid_mesh(4, 3, &arena, &m) == LS_OK);
    CHECK_EQ(m.vertex_count, 20);
    CHECK_EQ(m.face_count, 24);
    /* vertex (i, j) = j (nx + 1) + i at (i / nx, j / ny, 0) */
    CHECK(m.positions[3 * 7] == (ls_real)0.5 && m.positions[3 * 7 + 1] == (ls_real)1 / (ls_real)3);
    CHECK(m.positions[3 * 19] == 1 && m.positions[3 * 19 + 1] == 1 && m.positions[3 * 19 + 2] == 0);
    REQUIRE(ls_mesh_validate(&m, &arena, &r) == LS_OK);
    CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_ALL & ~LS_MESH_REQ_CLOSED, NULL), LS_OK);
    CHECK_EQ(r.boundary_edges, 2 * (4 + 3));
    CHECK_EQ(r.boundary_loops, 1);
    CHECK_EQ(r.genus, 0);
    REQUIRE(ls_mesh_face_normals(&m, n, NULL) == LS_OK);
    for (i = 0; i < 24; i++) CHECK_NEAR(n[3 * i + 2], 1.0, TEST_EPS(4));
}

static void primitive_errors(void)
{
    ls_arena arena;
    ls_mesh m;
    size_t bytes;
    uint32_t v, f, e;
    REQUIRE(ls_arena_init(&arena, buf, 64) == LS_OK);
    CHECK_STATUS(ls_icosphere_counts(LS_ICOSPHERE_MAX_LEVEL + 1u, &v, &f, &e), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_icosphere_counts(LS_ICOSPHERE_MAX_LEVEL, &v, &f, &e), LS_OK);
    CHECK_EQ(f, 20ull << 26);
    CHECK_STATUS(ls_icosphere_bytes(14, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_icosphere_bytes(13, &bytes), sizeof(size_t) < 8 ? LS_ERR_TOO_LARGE : LS_OK);
    CHECK_STATUS(ls_icosphere(2, &arena, &m), LS_ERR_NOMEM);
    CHECK_EQ(ls_arena_used(&arena), 0);
    CHECK_STATUS(ls_icosphere(2, NULL, &m), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_mesh_bytes(0, 3, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_grid_mesh_bytes(70000, 70000, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_grid_mesh(3, 0, &arena, &m), LS_ERR_INVALID);
}

int main(void)
{
    TEST_INIT("test_primitive");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(icosphere_geometry_and_topology);
    TEST_RUN(icosphere_levels_nest);
    TEST_RUN(primitive_arena_sweeps);
    TEST_RUN(grid_mesh_layout);
    TEST_RUN(primitive_errors);
    free(buf);
    return TEST_END();
}
