/* tests/test_distance.c - mesh distances: against brute force (every point
 * against every triangle), symmetry, zero for identical meshes, concentric
 * spheres against bounds derived from the tessellation, parallel planes,
 * sample placement, errors, arena sweep. */
#include "test.h"
#include "sweep.h"
#include "geo_test.h"
#include <largesteps/distance.h>

/* Brute-force statistics of one direction, summed in double. */
typedef struct bf_stats {
    double max, mean, rms;
    uint32_t count, argmax;
} bf_stats;

static void bf_add(bf_stats *s, double x, uint32_t id, double *sum, double *sum2)
{
    if (s->count == 0 || x > s->max) {
        s->max = x;
        s->argmax = id;
    }
    s->count++;
    *sum += x;
    *sum2 += x * x;
}

static void bf_one_way(const ls_mesh *src, const ls_mesh *dst, uint32_t samples, bf_stats *vert, bf_stats *face)
{
    double s = 0, s2 = 0;
    uint32_t v, k;
    memset(vert, 0, sizeof *vert);
    memset(face, 0, sizeof *face);
    for (v = 0; v < src->vertex_count; v++) {
        ls_bvh_hit h;
        geo_brute_closest(dst, src->positions + 3 * v, &h);
        bf_add(vert, sqrt((double)h.dist2), v, &s, &s2);
    }
    vert->mean = s / vert->count;
    vert->rms = sqrt(s2 / vert->count);
    s = s2 = 0;
    for (k = 0; k < samples; k++) {
        ls_bvh_hit h;
        ls_real p[3];
        uint32_t f;
        if (ls_distance_sample_point(src, samples, k, &f, p) != LS_OK) return;
        geo_brute_closest(dst, p, &h);
        bf_add(face, sqrt((double)h.dist2), k, &s, &s2);
    }
    if (face->count) {
        face->mean = s / face->count;
        face->rms = sqrt(s2 / face->count);
    }
}

/* A sphere with every vertex pushed radially by a deterministic bump. */
static int bumpy_sphere(ls_arena *a, ls_mesh *m, double amp, uint64_t seed)
{
    const double c[3] = {0, 0, 0};
    geo_rng g;
    uint32_t i;
    if (!geo_sphere(a, m, 1.0, c, 10, 14)) return 0;
    g.s = test_rng_seed(seed);
    for (i = 0; i < m->vertex_count; i++) {
        double f = 1 + amp * (2 * geo_rand(&g) - 1);
        m->positions[3 * i] = (ls_real)((double)m->positions[3 * i] * f);
        m->positions[3 * i + 1] = (ls_real)((double)m->positions[3 * i + 1] * f);
        m->positions[3 * i + 2] = (ls_real)((double)m->positions[3 * i + 2] * f);
    }
    return 1;
}

static void compare_stats(const ls_dist_stats *s, const bf_stats *b)
{
    double tol = TEST_EPS(64) * (1 + b->max);
    CHECK_EQ(s->count, b->count);
    CHECK_EQ(s->argmax, b->argmax);
    CHECK((double)s->max == (double)(ls_real)b->max || fabs((double)s->max - b->max) <= TEST_EPS(2) * b->max);
    CHECK_NEAR(s->mean, b->mean, tol);
    CHECK_NEAR(s->rms, b->rms, tol);
}

static void matches_brute_force(void)
{
    ls_arena a;
    ls_mesh ma, mb;
    ls_bvh ta, tb;
    ls_dist_one_way ab, ba;
    bf_stats v, f;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    REQUIRE(bumpy_sphere(&a, &ma, 0.05, 1));
    REQUIRE(bumpy_sphere(&a, &mb, 0.08, 2));
    /* B: a different tessellation as well */
    REQUIRE(ls_bvh_build(&ma, &a, &ta, NULL) == LS_OK);
    REQUIRE(ls_bvh_build(&mb, &a, &tb, NULL) == LS_OK);
    const uint32_t na = geo_scaled(1500), nb = geo_scaled(900);
    CHECK_STATUS(ls_distance_one_way(&ma, &tb, na, &ab, NULL), LS_OK);
    CHECK_STATUS(ls_distance_one_way(&mb, &ta, nb, &ba, NULL), LS_OK);
    bf_one_way(&ma, &mb, na, &v, &f);
    compare_stats(&ab.vertex, &v);
    compare_stats(&ab.face, &f);
    CHECK_EQ(ab.face.count, na);
    bf_one_way(&mb, &ma, nb, &v, &f);
    compare_stats(&ba.vertex, &v);
    compare_stats(&ba.face, &f);
    CHECK(ab.vertex.max > 0.01);
    free(a.base);
}

/* Twice the area of face f, in double. */
static double area2_of(const ls_mesh *m, uint32_t f)
{
    const uint32_t *t = m->triangles + 3 * f;
    double u[3], w[3], n[3];
    int j;
    for (j = 0; j < 3; j++) {
        u[j] = (double)m->positions[3 * t[1] + j] - (double)m->positions[3 * t[0] + j];
        w[j] = (double)m->positions[3 * t[2] + j] - (double)m->positions[3 * t[0] + j];
    }
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Face counts follow the areas: |n_f - N area_f / area| < 1 for every face,
 * they add up to N, and every sample lies in its face. */
static void samples_follow_area(void)
{
    ls_arena a;
    ls_mesh m;
    const uint32_t N = geo_emulated() ? 400 : 2000;
    uint32_t *cnt, k, f;
    double total = 0;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    REQUIRE(bumpy_sphere(&a, &m, 0.2, 3));
    cnt = (uint32_t *)calloc(m.face_count, sizeof(uint32_t));
    REQUIRE(cnt != NULL);
    for (f = 0; f < m.face_count; f++) total += area2_of(&m, f);
    for (k = 0; k < N; k++) {
        ls_real p[3], q[3], b[3], d2;
        const uint32_t *t;
        REQUIRE(ls_distance_sample_point(&m, N, k, &f, p) == LS_OK);
        REQUIRE(f < m.face_count);
        cnt[f]++;
        t = m.triangles + 3 * f;
        ls_closest_point_triangle(p, m.positions + 3 * t[0], m.positions + 3 * t[1], m.positions + 3 * t[2], q, b, &d2);
        CHECK(d2 <= TEST_EPS(64));
    }
    {
        uint32_t sum = 0, bad = 0;
        double cum = 0;
        for (f = 0; f < m.face_count; f++) {
            double area = area2_of(&m, f);
            cum += area;
            sum += cnt[f];
            /* the running count is the rounded running share */
            if (fabs((double)sum - N * cum / total) > 0.5 + 1e-3) bad++;
            if (fabs((double)cnt[f] - N * area / total) >= 1 + 1e-3) bad++;
        }
        CHECK_EQ(sum, N);
        CHECK_EQ(bad, 0);
    }
    free(cnt);
    free(a.base);
}

static void symmetric_and_zero_for_identical(void)
{
    ls_arena a;
    ls_mesh ma, mb;
    ls_distance_report r1, r2, r0;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    REQUIRE(bumpy_sphere(&a, &ma, 0.05, 4));
    REQUIRE(bumpy_sphere(&a, &mb, 0.05, 5));
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 800, 700, &a, &r1, NULL), LS_OK);
    CHECK_STATUS(ls_mesh_distance(&mb, &ma, 700, 800, &a, &r2, NULL), LS_OK);
    CHECK(memcmp(&r1.ab, &r2.ba, sizeof r1.ab) == 0);
    CHECK(memcmp(&r1.ba, &r2.ab, sizeof r1.ab) == 0);
    CHECK(r1.vertex_hausdorff == r2.vertex_hausdorff);
    CHECK(r1.hausdorff == r2.hausdorff);
    CHECK(r1.mean == r2.mean);
    CHECK(r1.rms == r2.rms);
    CHECK(r1.hausdorff >= r1.vertex_hausdorff);
    CHECK(r1.hausdorff >= r1.ab.face.max && r1.hausdorff >= r1.ba.face.max);
    CHECK(r1.rms >= r1.mean);
    /* the symmetric values, written out */
    CHECK_NEAR(r1.mean, ((double)r1.ab.face.mean + (double)r1.ba.face.mean) / 2, TEST_EPS(4));
    CHECK_NEAR(r1.rms,
               sqrt(((double)r1.ab.face.rms * (double)r1.ab.face.rms + (double)r1.ba.face.rms * (double)r1.ba.face.rms) / 2),
               TEST_EPS(4));
    CHECK(r1.ab.face.rms != r1.ba.face.rms);
    CHECK_NEAR(r1.rms_rel, (double)r1.rms / (double)r1.diag, TEST_EPS(4));
    CHECK_NEAR(r1.mean_rel, (double)r1.mean / (double)r1.diag, TEST_EPS(4));
    CHECK_NEAR(r1.vertex_hausdorff_rel, (double)r1.vertex_hausdorff / (double)r1.diag, TEST_EPS(4));
    CHECK_NEAR(r1.hausdorff_rel, (double)r1.hausdorff / (double)r1.diag, TEST_EPS(4));
    /* the arena is empty again */
    CHECK_EQ(ls_arena_used(&a), (size_t)(a.bottom));
    CHECK_STATUS(ls_mesh_distance(&ma, &ma, 800, 800, &a, &r0, NULL), LS_OK);
    CHECK(r0.vertex_hausdorff == 0);
    CHECK(r0.hausdorff <= TEST_EPS(16));
    CHECK(r0.mean <= TEST_EPS(16));
    CHECK_MSG(r0.ab.normal.mean <= 0.5, "normal mean %g max %g", (double)r0.ab.normal.mean, (double)r0.ab.normal.max);
    CHECK_EQ(r0.ab.normal.count, 800);
    free(a.base);
}

/* Two concentric UV spheres, radii 1 and 1.1, same tessellation. Every
 * vertex lies on its sphere, so each tessellated surface lies between radius
 * r c and r, where c = min over faces of (distance of the face plane to the
 * centre) / r. Hence every distance, both ways, lies in
 * [1.1 c - 1, 1.1 - c]; vertex distances A->B are at most 0.1 (B has a vertex
 * on the same ray). */
static void concentric_spheres(void)
{
    ls_arena a;
    ls_mesh ma, mb;
    ls_distance_report r;
    const double ctr[3] = {0, 0, 0};
    double c = 1, lo, hi;
    uint32_t f;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_sphere(&a, &ma, 1.0, ctr, 24, 48));
    REQUIRE(geo_sphere(&a, &mb, 1.1, ctr, 24, 48));
    for (f = 0; f < ma.face_count; f++) {
        const uint32_t *t = ma.triangles + 3 * f;
        const ls_real *p0 = ma.positions + 3 * t[0], *p1 = ma.positions + 3 * t[1], *p2 = ma.positions + 3 * t[2];
        double u[3], w[3], n[3], len, d;
        int j;
        for (j = 0; j < 3; j++) {
            u[j] = (double)p1[j] - (double)p0[j];
            w[j] = (double)p2[j] - (double)p0[j];
        }
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        d = fabs(n[0] * (double)p0[0] + n[1] * (double)p0[1] + n[2] * (double)p0[2]) / len;
        if (d < c) c = d;
    }
    lo = 1.1 * c - 1 - TEST_EPS(64);
    hi = 1.1 - c + TEST_EPS(64);
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, geo_scaled(20000), geo_scaled(20000), &a, &r, NULL), LS_OK);
    printf("     concentric r=1, 1.1 (c = %.6f): H_vertex %.6f H %.6f mean %.6f rms %.6f, bounds [%.6f, %.6f]\n", c,
           (double)r.vertex_hausdorff, (double)r.hausdorff, (double)r.mean, (double)r.rms, lo, hi);
    CHECK(lo > 0.09 && hi < 0.11);
    CHECK((double)r.ab.vertex.max <= 0.1 + TEST_EPS(64));
    CHECK((double)r.ab.vertex.max >= lo);
    CHECK((double)r.hausdorff >= lo && (double)r.hausdorff <= hi);
    CHECK((double)r.mean >= lo && (double)r.mean <= hi);
    CHECK((double)r.rms >= lo && (double)r.rms <= hi);
    CHECK((double)r.ab.face.max <= hi && (double)r.ba.face.max <= hi);
    CHECK((double)r.ab.vertex.mean >= lo && (double)r.ba.vertex.mean >= lo);
    /* normals: the nearest face is parallel, or a neighbour at most two face
     * angular radii away */
    CHECK((double)r.ab.normal.max <= 4 * acos(c) * 180 / 3.14159265358979 + 1e-3);
    CHECK(r.ab.normal.mean < 1.0);
    CHECK_NEAR(r.diag, 2.2 * sqrt(3.0), 1e-5);
    free(a.base);
}

/* A parallel-for on this thread that runs the tasks last first, on worker
 * numbers counted down. */
static void reversed_for(void *ctx, uint32_t count, ls_task_fn task, void *arg)
{
    const uint32_t workers = *(const uint32_t *)ctx;
    uint32_t k;
    for (k = 0; k < count; k++) task(arg, count - 1u - k, (workers - 1u - k % workers));
}

/* ls_mesh_distance_parallel: the report of ls_mesh_distance, every byte,
 * for 1 to 3 workers, in one round and in several; its memory is the
 * query's; workers 0 refused. */
static void parallel_same_report(void)
{
    ls_arena a;
    ls_mesh ma, mb;
    ls_distance_report r1, rw;
    ls_parallel par;
    ls_diag d;
    geo_rng g;
    const double ctr[3] = {0, 0, 0};
    uint32_t i, w, samples[2];
    size_t need0 = 0;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_sphere(&a, &ma, 1.0, ctr, 16, 30));
    REQUIRE(geo_sphere(&a, &mb, 1.1, ctr, 12, 20));
    g.s = test_rng_seed(31);
    for (i = 0; i < 3 * ma.vertex_count; i++) ma.positions[i] += (ls_real)(0.05 * (geo_rand(&g) - 0.5));
    memset(&r1, 0, sizeof r1);
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, geo_scaled(4000), geo_scaled(3000), &a, &r1, NULL), LS_OK);
    par.run = reversed_for;
    par.ctx = &w;
    samples[0] = geo_scaled(4000);
    samples[1] = geo_scaled(3000);
    for (w = 1; w <= 3; w++) {
        memset(&rw, 0, sizeof rw);
        CHECK_STATUS(ls_mesh_distance_parallel(&ma, &mb, samples, &par, w, &a, &rw, NULL),
                     LS_OK);
        CHECK_MSG(memcmp(&r1, &rw, sizeof r1) == 0, "%u workers: H %.17g rms %.17g; one: %.17g %.17g", (unsigned)w,
                  (double)rw.hausdorff, (double)rw.rms, (double)r1.hausdorff, (double)r1.rms);
    }
    printf("     H %.6f rms %.6f: the same report for 1 to 3 workers\n", (double)r1.hausdorff, (double)r1.rms);
    /* several rounds of 4,096 points each way, and the memory the query gives */
    samples[0] = 9000u;
    samples[1] = 4097u;
    memset(&r1, 0, sizeof r1);
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, samples[0], samples[1], &a, &r1, NULL), LS_OK);
    for (w = 2; w <= 3; w++) {
        size_t need = 0, before = ls_arena_used(&a);
        memset(&rw, 0, sizeof rw);
        CHECK_STATUS(ls_mesh_distance_parallel_bytes(ma.face_count, mb.face_count, w, &need), LS_OK);
        ls_arena_reset_peak(&a);
        CHECK_STATUS(ls_mesh_distance_parallel(&ma, &mb, samples, &par, w, &a, &rw, NULL), LS_OK);
        CHECK_MSG(a.peak - before == need, "%u workers: peak %lu, query %lu", (unsigned)w, (unsigned long)(a.peak - before),
                  (unsigned long)need);
        CHECK_MSG(memcmp(&r1, &rw, sizeof r1) == 0, "%u workers, 9,000 samples: H %.17g rms %.17g; one: %.17g %.17g",
                  (unsigned)w, (double)rw.hausdorff, (double)rw.rms, (double)r1.hausdorff, (double)r1.rms);
    }
    CHECK_STATUS(ls_mesh_distance_parallel_bytes(ma.face_count, mb.face_count, 0, &need0), LS_ERR_INVALID);
    CHECK_STATUS(ls_mesh_distance_parallel(&ma, &mb, samples, &par, 0, &a, &rw, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "workers") != NULL);
    free(a.base);
}

/* Two parallel unit squares 0.25 apart: every distance is 0.25, both ways;
 * normal error 0 (same orientation) or 180 (flipped copy). */
static void parallel_squares(void)
{
    static const double p1[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const double p2[] = {0, 0, 0.25, 1, 0, 0.25, 1, 1, 0.25, 0, 1, 0.25};
    static const uint32_t t[] = {0, 1, 2, 0, 2, 3}, tf[] = {0, 2, 1, 0, 3, 2};
    ls_arena a;
    ls_mesh ma, mb;
    ls_distance_report r;
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(geo_mesh(&a, &ma, p1, 4, t, 2));
    REQUIRE(geo_mesh(&a, &mb, p2, 4, t, 2));
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 500, 500, &a, &r, NULL), LS_OK);
    CHECK(r.vertex_hausdorff == (ls_real)0.25);
    CHECK_NEAR(r.hausdorff, 0.25, TEST_EPS(8));
    CHECK_NEAR(r.mean, 0.25, TEST_EPS(8));
    CHECK_NEAR(r.rms, 0.25, TEST_EPS(8));
    CHECK_NEAR(r.ab.face.mean, 0.25, TEST_EPS(8));
    CHECK_NEAR(r.ab.normal.max, 0, 1e-6);
    CHECK_NEAR(r.diag, sqrt(2.0), TEST_EPS(4));
    memcpy(mb.triangles, tf, sizeof tf);
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 500, 500, &a, &r, NULL), LS_OK);
    CHECK_NEAR(r.ab.normal.mean, 180, 1e-4);
    CHECK_NEAR(r.ab.normal.max, 180, 1e-4);
    free(a.base);
}

static void errors(void)
{
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t t[] = {0, 1, 2}, bad[] = {0, 1, 5};
    ls_arena a;
    ls_mesh ma, mb;
    ls_distance_report r;
    ls_dist_one_way w;
    ls_diag d;
    size_t bytes;
    uint32_t f;
    ls_real q[3];
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(geo_mesh(&a, &ma, p, 3, t, 1));
    REQUIRE(geo_mesh(&a, &mb, p, 3, bad, 1));
    memset(&r, 0x5a, sizeof r);
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 10, 10, &a, &r, &d), LS_ERR_MESH);
    CHECK(strcmp(d.what, "mesh B: face index out of range") == 0);
    CHECK_EQ(d.index, 0);
    CHECK_EQ(ls_arena_used(&a), a.bottom);
    mb.triangles[2] = 2;
    mb.positions[3] = (ls_real)NAN;
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 10, 10, &a, &r, &d), LS_ERR_NONFINITE);
    CHECK_EQ(d.index, 1);
    CHECK_STATUS(ls_mesh_distance(&mb, &ma, 10, 10, &a, &r, &d), LS_ERR_NONFINITE);
    CHECK(strcmp(d.what, "mesh A: vertex coordinate not finite") == 0);
    mb.positions[3] = 1;
    CHECK_STATUS(ls_mesh_distance(NULL, &mb, 10, 10, &a, &r, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "a is NULL") == 0);
    mb.face_count = 0;
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 10, 10, &a, &r, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "b->face_count") != NULL);
    CHECK_STATUS(ls_distance_one_way(&ma, NULL, 10, &w, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "target is NULL") == 0);
    CHECK_STATUS(ls_mesh_distance_bytes(0, 1, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_distance_sample_point(&ma, 10, 10, &f, q), LS_ERR_INVALID);
    CHECK_EQ(ls_distance_default_samples(&ma), 1000);
    /* zero samples: only vertices */
    mb.face_count = 1;
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 0, 0, &a, &r, &d), LS_OK);
    CHECK_EQ(r.ab.face.count, 0);
    CHECK_EQ(r.ab.vertex.count, 3);
    /* without face samples the symmetric mean and RMS are the vertices' */
    /* B's vertex 0 lifted to z = 1: A's origin is 1/sqrt(3) from B's plane
     * x + y + z = 1 (foot (1/3, 1/3, 1/3) inside B), its other vertices lie on
     * B; B's lifted vertex is 1 from A, the others 0 */
    mb.positions[2] = 1;
    CHECK_STATUS(ls_mesh_distance(&ma, &mb, 0, 0, &a, &r, &d), LS_OK);
    CHECK_NEAR(r.ab.vertex.max, 1 / sqrt(3.0), TEST_EPS(8));
    CHECK_NEAR(r.ab.vertex.mean, 1 / (3 * sqrt(3.0)), TEST_EPS(8));
    CHECK_NEAR(r.ba.vertex.max, 1.0, TEST_EPS(8));
    CHECK_NEAR(r.mean, ((double)r.ab.vertex.mean + (double)r.ba.vertex.mean) / 2, TEST_EPS(8));
    CHECK_NEAR(r.ba.vertex.mean, 1.0 / 3, TEST_EPS(8));
    CHECK_NEAR(r.rms, sqrt(((double)r.ab.vertex.rms * (double)r.ab.vertex.rms + (double)r.ba.vertex.rms * (double)r.ba.vertex.rms) / 2),
               TEST_EPS(8));
    free(a.base);
}

typedef struct dist_ctx {
    ls_mesh a, b;
    ls_distance_report r;
} dist_ctx;

static ls_status dist_run(void *ctx, ls_arena *a)
{
    dist_ctx *c = (dist_ctx *)ctx;
    return ls_mesh_distance(&c->a, &c->b, 200, 150, a, &c->r, NULL);
}

static uint64_t dist_hash(void *ctx)
{
    dist_ctx *c = (dist_ctx *)ctx;
    uint64_t h = test_hash(&c->r, sizeof c->r, TEST_HASH_SEED);
    h = test_hash(c->a.positions, 3 * sizeof(ls_real) * c->a.vertex_count, h);
    return test_hash(c->b.positions, 3 * sizeof(ls_real) * c->b.vertex_count, h);
}

static void dist_reset(void *ctx)
{
    dist_ctx *c = (dist_ctx *)ctx;
    memset(&c->r, 0, sizeof c->r);
}

static void arena_sweep(void)
{
    ls_arena a;
    dist_ctx c;
    sweep_job job;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    REQUIRE(bumpy_sphere(&a, &c.a, 0.05, 8));
    REQUIRE(bumpy_sphere(&a, &c.b, 0.05, 9));
    c.b.face_count -= 10; /* different sizes */
    memset(&c.r, 0, sizeof c.r);
    memset(&job, 0, sizeof job);
    job.name = "mesh_distance";
    job.run = dist_run;
    job.state_hash = dist_hash;
    job.reset = dist_reset;
    job.ctx = &c;
    job.exact = 1;
    REQUIRE(ls_mesh_distance_bytes(c.a.face_count, c.b.face_count, &job.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&job), 0);
    /* and the other way round (A's tree larger than B's) */
    {
        ls_mesh t = c.a;
        c.a = c.b;
        c.b = t;
        REQUIRE(ls_mesh_distance_bytes(c.a.face_count, c.b.face_count, &job.answer) == LS_OK);
        CHECK_EQ(sweep_arena(&job), 0);
    }
    free(a.base);
}

int main(void)
{
    TEST_INIT("test_distance");
    TEST_RUN(matches_brute_force);
    TEST_RUN(samples_follow_area);
    TEST_RUN(symmetric_and_zero_for_identical);
    TEST_RUN(concentric_spheres);
    TEST_RUN(parallel_squares);
    TEST_RUN(parallel_same_report);
    TEST_RUN(errors);
    TEST_RUN(arena_sweep);
    return TEST_END();
}
