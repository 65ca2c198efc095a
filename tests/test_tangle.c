/* tests/test_tangle.c - tangling metrics: known intersecting and
 * non-intersecting triangle configurations, the BVH count against all pairs,
 * a sphere folded through itself, the same report split over workers, inverted faces after flipping known faces,
 * angle and quality percentiles (equilateral mesh: 60 degrees, quality 1;
 * a known mix against a sort done here), errors, arena sweep. */
#include "test.h"
#include "sweep.h"
#include "geo_test.h"
#include <largesteps/tangle.h>

static int meet(const double *a, const double *b)
{
    ls_real p[18];
    int i;
    for (i = 0; i < 9; i++) {
        p[i] = (ls_real)a[i];
        p[9 + i] = (ls_real)b[i];
    }
    return ls_triangles_meet(p, p + 3, p + 6, p + 9, p + 12, p + 15);
}

static void known_pairs(void)
{
    /* two triangles crossing through each other's interior */
    static const double t1[] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
    static const double x1[] = {0.5, 0.5, -1, 0.5, 0.5, 1, 1.5, -1, 0};
    /* parallel, 1 apart */
    static const double p1[] = {0, 0, 1, 2, 0, 1, 0, 2, 1};
    /* coplanar overlapping, coplanar disjoint, coplanar contained */
    static const double c1[] = {1, 1, 0, 3, 1, 0, 1, 3, 0};
    static const double c2[] = {3, 3, 0, 5, 3, 0, 3, 5, 0};
    static const double c3[] = {0.2, 0.2, 0, 0.5, 0.2, 0, 0.2, 0.5, 0};
    /* touching at one point (a vertex on the other's face), and near miss */
    static const double v1[] = {0.5, 0.5, 0, 1, 1, 2, 0, 1, 2};
    static const double v2[] = {0.5, 0.5, 1e-3, 1, 1, 2, 0, 1, 2};
    /* above the plane but beside the triangle, piercing the plane outside */
    static const double o1[] = {3, 3, -1, 3, 3, 1, 4, 3, 0};
    CHECK_EQ(meet(t1, x1), 1);
    CHECK_EQ(meet(x1, t1), 1);
    CHECK_EQ(meet(t1, p1), 0);
    CHECK_EQ(meet(t1, c1), 1);
    CHECK_EQ(meet(t1, c2), 0);
    CHECK_EQ(meet(t1, c3), 1);
    CHECK_EQ(meet(c3, t1), 1);
    CHECK_EQ(meet(t1, v1), 1);
    CHECK_EQ(meet(t1, v2), 0);
    CHECK_EQ(meet(t1, o1), 0);
}

/* Mesh-level rules: shared edge and shared vertex are not intersections;
 * a fan folded through itself at a shared vertex is; disjoint crossing is. */
/* Nearly coplanar faces of a flat region (two faces of a remeshed elephant,
 * double coordinates): apart, they must not meet, though their plane tests
 * are rounding noise; overlapping in the plane, they must. */
static void nearly_coplanar_pairs(void)
{
    static const double f[3][3] = {{0.045384521337851105, -0.038277236608747725, -0.039855256832367847},
                                   {0.040603747947953857, -0.032471157748914507, -0.030846403811952292},
                                   {0.051768512203888312, -0.031294815316244902, -0.032671908780173252}};
    static const double g[3][3] = {{0.023528977443394397, -0.028201023705782348, -0.020141152923666666},
                                   {0.035532299477315815, -0.026841565629575657, -0.021980207471861656},
                                   {0.028274851047976696, -0.033782707912771853, -0.028846922923567282}};
    ls_real a[3][3], b[3][3], c[3][3];
    int i, k;
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) {
            a[i][k] = (ls_real)f[i][k];
            b[i][k] = (ls_real)g[i][k];
        }
    CHECK(!ls_triangles_meet(a[0], a[1], a[2], b[0], b[1], b[2]));
    CHECK(!ls_triangles_meet(b[0], b[1], b[2], a[0], a[1], a[2]));
    /* a copy of f shifted by a third of an edge within its own plane overlaps it */
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) c[i][k] = a[i][k] + (a[1][k] - a[0][k]) / 3 + (a[2][k] - a[0][k]) / 5;
    CHECK(ls_triangles_meet(a[0], a[1], a[2], c[0], c[1], c[2]));
}

static void mesh_rules(void)
{
    static const double p[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 2, 2, 0, /* 0..3: a flat quad */
                               -1, -1, 0, -2, 0, 0,                 /* 4, 5: touch at vertex 0 only */
                               0.5, 0.5, -1, 0.5, 0.5, 1, 1.5, -1, 0, /* 6..8: crossing triangle */
                               1, 0.2, 0.5, 0.2, 1, 0.5 /* 9, 10: through face 0 from vertex 0 */};
    static const uint32_t t[] = {0, 1, 2, /* 0 */
                                 1, 3, 2, /* 1: shares edge 1-2 with 0 */
                                 0, 4, 5, /* 2: shares vertex 0 with 0 */
                                 6, 7, 8, /* 3: crosses 0 */
                                 0, 9, 10 /* 4: shares vertex 0, lies above face 0: no contact */};
    ls_arena a;
    ls_mesh m;
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(geo_mesh(&a, &m, p, 11, t, 5));
    CHECK_EQ(ls_tangle_pair(&m, 0, 1), 0);
    CHECK_EQ(ls_tangle_pair(&m, 0, 2), 0);
    CHECK_EQ(ls_tangle_pair(&m, 0, 3), 1);
    CHECK_EQ(ls_tangle_pair(&m, 3, 0), 1);
    CHECK_EQ(ls_tangle_pair(&m, 0, 4), 0);
    CHECK_EQ(ls_tangle_pair(&m, 0, 0), 0);
    /* entirely below face 0's plane but for vertex 0: contact at the shared vertex only */
    m.positions[3 * 9 + 2] = (ls_real)-0.5;
    m.positions[3 * 10 + 2] = (ls_real)-0.5;
    CHECK_EQ(ls_tangle_pair(&m, 0, 4), 0);
    /* fold face 4 through face 0: its far edge crosses z = 0 at (0.6, 0.6, 0) */
    m.positions[3 * 10 + 2] = (ls_real)0.5;
    CHECK_EQ(ls_tangle_pair(&m, 0, 4), 1);
    CHECK_EQ(ls_tangle_pair(&m, 4, 0), 1);
    /* a coplanar fan face overlapping face 0 from their shared vertex */
    m.positions[3 * 9 + 2] = 0;
    m.positions[3 * 10 + 2] = 0;
    CHECK_EQ(ls_tangle_pair(&m, 0, 4), 1);
    /* coplanar, shared vertex, no overlap (face 2) */
    CHECK_EQ(ls_tangle_pair(&m, 4, 2), 0);
    free(a.base);
}

/* All pairs with ls_tangle_pair against the BVH count. */
static void all_pairs(const ls_mesh *m, uint32_t *pairs, uint32_t *faces, uint32_t first[2])
{
    uint32_t f, g, *hit = (uint32_t *)calloc(m->face_count, sizeof(uint32_t));
    *pairs = *faces = 0;
    first[0] = first[1] = LS_MESH_NONE;
    for (f = 0; f < m->face_count; f++)
        for (g = f + 1; g < m->face_count; g++)
            if (ls_tangle_pair(m, f, g)) {
                if (*pairs == 0) {
                    first[0] = f;
                    first[1] = g;
                }
                (*pairs)++;
                hit[f] = hit[g] = 1;
            }
    for (f = 0; f < m->face_count; f++) *faces += hit[f];
    free(hit);
}

static void folded_sphere(void)
{
    ls_arena a;
    ls_mesh m;
    ls_tangle_report r;
    const double c[3] = {0, 0, 0};
    uint32_t pairs, faces, first[2];
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_sphere(&a, &m, 1.0, c, 12, 16));
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    CHECK_EQ(r.intersecting_pairs, 0);
    CHECK_EQ(r.intersecting_faces, 0);
    CHECK_EQ(r.first_pair[0], LS_MESH_NONE);
    CHECK_EQ(r.has_reference, 0);
    /* push the north pole through the south side (a little off the axis, to
     * stay clear of exact contacts): its fan crosses the far faces */
    m.positions[0] = (ls_real)0.0137;
    m.positions[1] = (ls_real)0.0071;
    m.positions[2] = (ls_real)-1.5;
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    all_pairs(&m, &pairs, &faces, first);
    printf("     folded sphere: %u intersecting pairs, %u faces (all pairs: %u, %u)\n", r.intersecting_pairs,
           r.intersecting_faces, pairs, faces);
    CHECK(pairs > 16);
    CHECK_EQ(r.intersecting_pairs, pairs);
    CHECK_EQ(r.intersecting_faces, faces);
    CHECK_EQ(r.first_pair[0], first[0]);
    CHECK_EQ(r.first_pair[1], first[1]);
    /* the bunny: no self-intersections by the BVH and by all pairs */
    REQUIRE(geo_read("fixtures/meshes/bunny.obj", &a, &m));
    CHECK_STATUS(ls_tangle(&m, &m, &a, &r, NULL), LS_OK);
    CHECK_EQ(r.inverted_faces, 0);
    CHECK_EQ(r.degenerate_faces, 0);
    printf("     bunny: %u intersecting pairs; angles min %.2f p1 %.2f p5 %.2f p50 %.2f max %.2f; quality min %.3f p1 %.3f p50 %.3f mean %.3f\n",
           r.intersecting_pairs, (double)r.angle_min, (double)r.angle_p1, (double)r.angle_p5, (double)r.angle_p50,
           (double)r.angle_max, (double)r.quality_min, (double)r.quality_p1, (double)r.quality_p50,
           (double)r.quality_mean);
    free(a.base);
}

/* A sphere with random vertex noise: BVH count = all-pairs count. */
static void noisy_sphere_matches_all_pairs(void)
{
    ls_arena a;
    ls_mesh m;
    ls_tangle_report r;
    geo_rng g;
    const double c[3] = {0, 0, 0};
    uint32_t pairs, faces, first[2], i;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_emulated() ? geo_sphere(&a, &m, 1.0, c, 14, 20) : geo_sphere(&a, &m, 1.0, c, 20, 30));
    g.s = test_rng_seed(21);
    for (i = 0; i < 3 * m.vertex_count; i++) m.positions[i] += (ls_real)(0.3 * (geo_rand(&g) - 0.5));
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    all_pairs(&m, &pairs, &faces, first);
    printf("     noisy sphere (%u faces): %u intersecting pairs, %u faces (all pairs: %u, %u)\n", m.face_count, r.intersecting_pairs,
           r.intersecting_faces, pairs, faces);
    CHECK(pairs > 10);
    CHECK_EQ(r.intersecting_pairs, pairs);
    CHECK_EQ(r.intersecting_faces, faces);
    CHECK_EQ(r.first_pair[0], first[0]);
    CHECK_EQ(r.first_pair[1], first[1]);
    free(a.base);
}

/* A parallel-for on this thread that does what threads may: tasks in
 * reverse order on worker numbers that rotate. */
static void reversed_for(void *ctx, uint32_t count, ls_task_fn task, void *arg)
{
    const uint32_t workers = *(const uint32_t *)ctx;
    uint32_t k;
    for (k = 0; k < count; k++) task(arg, count - 1u - k, (k * 7u + 3u) % workers);
}

/* ls_tangle_parallel: the report of ls_tangle, field by field, for 1 to 5
 * workers, each in exactly ls_tangle_parallel_bytes (one byte less fails);
 * workers 0 and above the limit refused. */
static void parallel_same_report(void)
{
    ls_arena a, t;
    ls_mesh m;
    ls_tangle_report r1, rw;
    ls_parallel par;
    ls_diag d;
    geo_rng g;
    const double c[3] = {0, 0, 0};
    uint32_t i, w;
    size_t bytes;
    unsigned char *mem;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_sphere(&a, &m, 1.0, c, 14, 20));
    g.s = test_rng_seed(23);
    for (i = 0; i < 3 * m.vertex_count; i++) m.positions[i] += (ls_real)(0.3 * (geo_rand(&g) - 0.5));
    CHECK_STATUS(ls_tangle(&m, &m, &a, &r1, NULL), LS_OK);
    CHECK(r1.intersecting_pairs > 10);
    par.run = reversed_for;
    par.ctx = &w;
    for (w = 1; w <= 5; w++) {
        REQUIRE(ls_tangle_parallel_bytes(m.face_count, w, &bytes) == LS_OK);
        mem = (unsigned char *)malloc(bytes);
        REQUIRE(mem != NULL);
        REQUIRE(ls_arena_init(&t, mem, bytes - 1u) == LS_OK);
        CHECK_STATUS(ls_tangle_parallel(&m, &m, &par, w, &t, &rw, NULL), LS_ERR_NOMEM);
        REQUIRE(ls_arena_init(&t, mem, bytes) == LS_OK);
        memset(&rw, 0xab, sizeof rw);
        CHECK_STATUS(ls_tangle_parallel(&m, &m, &par, w, &t, &rw, NULL), LS_OK);
        CHECK_EQ(t.peak, bytes);
        CHECK_MSG(rw.intersecting_pairs == r1.intersecting_pairs && rw.intersecting_faces == r1.intersecting_faces &&
                      rw.first_pair[0] == r1.first_pair[0] && rw.first_pair[1] == r1.first_pair[1] &&
                      rw.inverted_faces == r1.inverted_faces && rw.degenerate_faces == r1.degenerate_faces &&
                      rw.angle_p50 == r1.angle_p50 && rw.quality_mean == r1.quality_mean,
                  "%u workers: %u pairs, %u faces, first (%u, %u); one: %u, %u, (%u, %u)", (unsigned)w,
                  rw.intersecting_pairs, rw.intersecting_faces, rw.first_pair[0], rw.first_pair[1],
                  r1.intersecting_pairs, r1.intersecting_faces, r1.first_pair[0], r1.first_pair[1]);
        /* the pairs alone: the same pair fields in the same memory, no statistics */
        memset(&rw, 0xab, sizeof rw);
        CHECK_STATUS(ls_tangle_pairs(&m, &par, w, &t, &rw, NULL), LS_OK);
        CHECK(t.peak <= bytes);
        CHECK_MSG(rw.intersecting_pairs == r1.intersecting_pairs && rw.intersecting_faces == r1.intersecting_faces &&
                      rw.first_pair[0] == r1.first_pair[0] && rw.first_pair[1] == r1.first_pair[1] &&
                      rw.face_count == r1.face_count && rw.inverted_faces == 0 && rw.has_reference == 0 &&
                      rw.first_inverted == LS_MESH_NONE && rw.angle_max == 0 && rw.quality_mean == 0,
                  "%u workers, pairs alone: %u pairs, %u faces", (unsigned)w, rw.intersecting_pairs,
                  rw.intersecting_faces);
        free(mem);
    }
    printf("     %u faces, %u intersecting pairs: the same report for 1 to 5 workers\n", m.face_count,
           r1.intersecting_pairs);
    CHECK_STATUS(ls_tangle_parallel(&m, NULL, &par, 0, &a, &rw, &d), LS_ERR_INVALID);
    CHECK(d.what != NULL && strstr(d.what, "workers") != NULL);
    CHECK_STATUS(ls_tangle_parallel(&m, NULL, &par, LS_TANGLE_MAX_WORKERS + 1u, &a, &rw, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_tangle_parallel_bytes(m.face_count, 0, &bytes), LS_ERR_INVALID);
    free(a.base);
}

/* A fan around vertex 0 with its rim scattered in a ball (every pair shares
 * the centre; they meet through the rim edges), random faces among the rim
 * vertices, and faces with repeated vertices: the edge-by-edge search that
 * skips subtrees holding an edge's end (a fan's spokes, a vertex's star)
 * counts what all pairs count. */
static void noisy_fan_matches_all_pairs(void)
{
    ls_arena a;
    ls_mesh m;
    ls_tangle_report r;
    geo_rng g;
    const uint32_t rim = 240, extra = 60, degenerate = 24;
    uint32_t pairs, faces, first[2], i, f = 0;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    m.vertex_count = rim + 1u;
    m.face_count = rim + extra + degenerate;
    m.positions = (ls_real *)ls_arena_alloc(&a, 3u * m.vertex_count, sizeof(ls_real));
    m.triangles = (uint32_t *)ls_arena_alloc(&a, 3u * m.face_count, sizeof(uint32_t));
    REQUIRE(m.positions != NULL && m.triangles != NULL);
    g.s = test_rng_seed(35);
    m.positions[0] = m.positions[1] = m.positions[2] = 0;
    for (i = 3; i < 3u * m.vertex_count; i++) m.positions[i] = (ls_real)(2.0 * geo_rand(&g) - 1.0);
    for (i = 0; i < rim; i++, f++) {
        m.triangles[3u * f] = 0;
        m.triangles[3u * f + 1u] = 1u + i;
        m.triangles[3u * f + 2u] = 1u + (i + 1u) % rim;
    }
    for (i = 0; i < extra; i++, f++) {
        uint32_t k;
        for (k = 0; k < 3u; k++) m.triangles[3u * f + k] = 1u + (uint32_t)(geo_rand(&g) * rim) % rim;
    }
    for (i = 0; i < degenerate; i++, f++) {
        const uint32_t v = 1u + (uint32_t)(geo_rand(&g) * rim) % rim;
        m.triangles[3u * f] = i % 3u == 0 ? 0u : v;
        m.triangles[3u * f + 1u] = i % 2u == 0 ? 0u : v;
        m.triangles[3u * f + 2u] = i % 4u == 0 ? 0u : 1u + (v % rim);
    }
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    all_pairs(&m, &pairs, &faces, first);
    printf("     noisy fan (%u faces): %u intersecting pairs, %u faces (all pairs: %u, %u)\n", m.face_count,
           r.intersecting_pairs, r.intersecting_faces, pairs, faces);
    CHECK(pairs > 1000);
    CHECK_EQ(r.intersecting_pairs, pairs);
    CHECK_EQ(r.intersecting_faces, faces);
    CHECK_EQ(r.first_pair[0], first[0]);
    CHECK_EQ(r.first_pair[1], first[1]);
    /* a flat fan: every pair touches at the centre, none crosses */
    for (i = 0; i < rim; i++) {
        const double t = 6.283185307179586 * i / rim;
        m.positions[3u * (1u + i)] = (ls_real)cos(t);
        m.positions[3u * (1u + i) + 1u] = (ls_real)sin(t);
        m.positions[3u * (1u + i) + 2u] = 0;
    }
    m.face_count = rim;
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    all_pairs(&m, &pairs, &faces, first);
    CHECK_EQ(pairs, 0);
    CHECK_EQ(r.intersecting_pairs, 0);
    free(a.base);
}

/* A triangle soup (no shared vertices): flipping faces 3, 7 and 11 by
 * swapping two of their vertices' positions inverts exactly those. */
static void inverted_faces(void)
{
    ls_arena a;
    ls_mesh m, ref;
    ls_tangle_report r;
    uint32_t f, k;
    const uint32_t n = 20;
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(ls_mesh_alloc(&ref, 3 * n, n, &a) == LS_OK);
    REQUIRE(ls_mesh_alloc(&m, 3 * n, n, &a) == LS_OK);
    for (f = 0; f < n; f++) {
        ls_real *p = ref.positions + 9 * f;
        p[0] = (ls_real)(3 * f);
        p[1] = 0;
        p[2] = (ls_real)(f % 3);
        p[3] = (ls_real)(3 * f + 1);
        p[4] = 0;
        p[5] = (ls_real)(f % 3);
        p[6] = (ls_real)(3 * f);
        p[7] = 1;
        p[8] = (ls_real)(f % 3 + 1);
        for (k = 0; k < 3; k++) ref.triangles[3 * f + k] = m.triangles[3 * f + k] = 3 * f + k;
    }
    memcpy(m.positions, ref.positions, 9 * n * sizeof(ls_real));
    for (f = 3; f < n; f += 4) {
        ls_real t[3];
        memcpy(t, m.positions + 9 * f + 3, sizeof t);
        memcpy(m.positions + 9 * f + 3, m.positions + 9 * f + 6, sizeof t);
        memcpy(m.positions + 9 * f + 6, t, sizeof t);
    }
    CHECK_STATUS(ls_tangle(&m, &ref, &a, &r, NULL), LS_OK);
    CHECK_EQ(r.has_reference, 1);
    CHECK_EQ(r.inverted_faces, 5);
    CHECK_EQ(r.first_inverted, 3);
    CHECK_EQ(r.intersecting_pairs, 0);
    CHECK_STATUS(ls_tangle(&ref, &ref, &a, &r, NULL), LS_OK);
    CHECK_EQ(r.inverted_faces, 0);
    CHECK_EQ(r.first_inverted, LS_MESH_NONE);
    /* a collapsed face is degenerate, not inverted */
    memcpy(m.positions + 3, m.positions, 3 * sizeof(ls_real));
    CHECK_STATUS(ls_tangle(&m, &ref, &a, &r, NULL), LS_OK);
    CHECK_EQ(r.degenerate_faces, 1);
    CHECK_EQ(r.inverted_faces, 5);
    free(a.base);
}

/* An equilateral triangulated grid: every angle 60 degrees, quality 1. */
static void equilateral_mesh(void)
{
    ls_arena a;
    ls_mesh m;
    ls_tangle_report r;
    const uint32_t W = 9, H = 7;
    uint32_t i, j, f = 0;
    REQUIRE(geo_arena(&a, 1 << 18) != NULL);
    REQUIRE(ls_mesh_alloc(&m, W * H, 2 * (W - 1) * (H - 1), &a) == LS_OK);
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            ls_real *p = m.positions + 3 * (j * W + i);
            p[0] = (ls_real)((double)i + 0.5 * (double)j);
            p[1] = (ls_real)(sqrt(3.0) / 2 * (double)j);
            p[2] = 0;
        }
    for (j = 0; j + 1 < H; j++)
        for (i = 0; i + 1 < W; i++) {
            uint32_t v = j * W + i;
            m.triangles[3 * f] = v;
            m.triangles[3 * f + 1] = v + 1;
            m.triangles[3 * f + 2] = v + W;
            f++;
            m.triangles[3 * f] = v + 1;
            m.triangles[3 * f + 1] = v + W + 1;
            m.triangles[3 * f + 2] = v + W;
            f++;
        }
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    CHECK_NEAR(r.angle_min, 60, 1e-3);
    CHECK_NEAR(r.angle_p1, 60, 1e-3);
    CHECK_NEAR(r.angle_p5, 60, 1e-3);
    CHECK_NEAR(r.angle_p50, 60, 1e-3);
    CHECK_NEAR(r.angle_max, 60, 1e-3);
    CHECK_NEAR(r.quality_min, 1, 1e-5);
    CHECK_NEAR(r.quality_mean, 1, 1e-5);
    CHECK_EQ(r.intersecting_pairs, 0);
    CHECK_EQ(r.degenerate_faces, 0);
    free(a.base);
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* Percentiles of a random mesh against libm angles sorted with qsort. */
static void percentiles_against_sort(void)
{
    ls_arena a;
    ls_mesh m;
    ls_tangle_report r;
    geo_rng g;
    enum { NF = 499 }; /* 1497 corners: p n / 100 is not an integer */
    uint32_t i, n3;
    double *ang, *q, qmean = 0;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    REQUIRE(ls_mesh_alloc(&m, 3 * NF, NF, &a) == LS_OK);
    g.s = test_rng_seed(77);
    for (i = 0; i < 9 * NF; i++) m.positions[i] = (ls_real)(10 * geo_rand(&g));
    for (i = 0; i < 3 * NF; i++) m.triangles[i] = i;
    n3 = 3 * NF;
    ang = (double *)malloc(n3 * sizeof(double));
    q = (double *)malloc(NF * sizeof(double));
    for (i = 0; i < NF; i++) {
        double e[3][3], l[3], n[3], A2;
        int k, j;
        for (k = 0; k < 3; k++) {
            for (j = 0; j < 3; j++)
                e[k][j] = (double)m.positions[9 * i + 3 * ((k + 1) % 3) + j] - (double)m.positions[9 * i + 3 * k + j];
            l[k] = sqrt(e[k][0] * e[k][0] + e[k][1] * e[k][1] + e[k][2] * e[k][2]);
        }
        for (k = 0; k < 3; k++) {
            const double *u = e[k], *w = e[(k + 2) % 3];
            double d = -(u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / (l[k] * l[(k + 2) % 3]);
            ang[3 * i + k] = acos(d) * 180 / 3.14159265358979323846;
        }
        n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
        n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
        n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
        A2 = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 4;
        q[i] = 16 * A2 / (l[0] * l[1] * l[2] * (l[0] + l[1] + l[2]));
        qmean += q[i] / NF;
    }
    qsort(ang, n3, sizeof(double), cmp_double);
    qsort(q, NF, sizeof(double), cmp_double);
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, NULL), LS_OK);
    /* nearest rank: ceil(p n / 100), written out: 1497 corners -> ranks 15, 75, 749 */
    CHECK_NEAR(r.angle_min, ang[0], 1e-3);
    CHECK_NEAR(r.angle_p1, ang[14], 1e-3);
    CHECK_NEAR(r.angle_p5, ang[74], 1e-3);
    CHECK_NEAR(r.angle_p50, ang[748], 1e-3);
    CHECK_NEAR(r.angle_max, ang[n3 - 1], 1e-3);
    CHECK_NEAR(r.quality_min, q[0], 1e-4);
    /* 499 faces -> ranks 5, 25, 250 */
    CHECK_NEAR(r.quality_p1, q[4], 1e-4);
    CHECK_NEAR(r.quality_p5, q[24], 1e-4);
    CHECK_NEAR(r.quality_p50, q[249], 1e-4);
    CHECK_NEAR(r.quality_mean, qmean, 1e-4);
    free(ang);
    free(q);
    free(a.base);
}

static void errors(void)
{
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t t[] = {0, 1, 2}, bad[] = {0, 1, 3};
    ls_arena a;
    ls_mesh m, m2;
    ls_tangle_report r;
    ls_diag d;
    size_t bytes;
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(geo_mesh(&a, &m, p, 3, bad, 1));
    REQUIRE(geo_mesh(&a, &m2, p, 3, t, 1));
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, &d), LS_ERR_MESH);
    CHECK_EQ(d.index, 0);
    CHECK_EQ(ls_tangle_pair(&m, 0, 0), 0);
    m.triangles[2] = 2;
    m.positions[5] = (ls_real)INFINITY;
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, &d), LS_ERR_NONFINITE);
    CHECK_EQ(d.index, 1);
    CHECK_STATUS(ls_tangle(&m2, &m, &a, &r, &d), LS_ERR_NONFINITE);
    m.positions[5] = 0;
    m.face_count = 0;
    CHECK_STATUS(ls_tangle(&m2, &m, &a, &r, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "reference->face_count") != NULL);
    CHECK_STATUS(ls_tangle(&m, NULL, &a, &r, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "mesh->face_count") != NULL);
    CHECK_STATUS(ls_tangle(NULL, NULL, &a, &r, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "mesh is NULL") == 0);
    CHECK_STATUS(ls_tangle_bytes(0, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_tangle_bytes(UINT32_MAX, &bytes), LS_ERR_TOO_LARGE);
    CHECK_EQ(ls_arena_used(&a), a.bottom);
    free(a.base);
}

typedef struct tangle_ctx {
    ls_mesh m;
    ls_tangle_report r;
} tangle_ctx;

static ls_status tangle_run(void *ctx, ls_arena *a)
{
    tangle_ctx *c = (tangle_ctx *)ctx;
    return ls_tangle(&c->m, &c->m, a, &c->r, NULL);
}

static uint64_t tangle_hash(void *ctx)
{
    tangle_ctx *c = (tangle_ctx *)ctx;
    uint64_t h = test_hash(&c->r, sizeof c->r, TEST_HASH_SEED);
    return test_hash(c->m.positions, 3 * sizeof(ls_real) * c->m.vertex_count, h);
}

static void tangle_reset(void *ctx)
{
    tangle_ctx *c = (tangle_ctx *)ctx;
    memset(&c->r, 0, sizeof c->r);
}

static void arena_sweep(void)
{
    ls_arena a;
    tangle_ctx c;
    sweep_job job;
    const double ctr[3] = {0, 0, 0};
    int i;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    for (i = 0; i < 2; i++) {
        REQUIRE(geo_sphere(&a, &c.m, 1.0, ctr, i == 0 ? 3 : 10, i == 0 ? 4 : 12));
        c.m.positions[2] = (ls_real)-1.5; /* folded */
        memset(&c.r, 0, sizeof c.r);
        memset(&job, 0, sizeof job);
        job.name = i == 0 ? "tangle small" : "tangle sphere";
        job.run = tangle_run;
        job.state_hash = tangle_hash;
        job.reset = tangle_reset;
        job.ctx = &c;
        job.exact = 1;
        REQUIRE(ls_tangle_bytes(c.m.face_count, &job.answer) == LS_OK);
        CHECK_EQ(sweep_arena(&job), 0);
    }
    free(a.base);
}

int main(void)
{
    TEST_INIT("test_tangle");
    TEST_RUN(known_pairs);
    TEST_RUN(nearly_coplanar_pairs);
    TEST_RUN(mesh_rules);
    TEST_RUN(folded_sphere);
    TEST_RUN(noisy_sphere_matches_all_pairs);
    TEST_RUN(noisy_fan_matches_all_pairs);
    TEST_RUN(parallel_same_report);
    TEST_RUN(inverted_faces);
    TEST_RUN(equilateral_mesh);
    TEST_RUN(percentiles_against_sort);
    TEST_RUN(errors);
    TEST_RUN(arena_sweep);
    return TEST_END();
}
