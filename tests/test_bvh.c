/* tests/test_bvh.c - the triangle BVH: structure, closest points against
 * brute force (identical face, distance and point), degenerate triangles,
 * box-overlap iteration against brute force, errors, arena sweep. */
#include "test.h"
#include "sweep.h"
#include "geo_test.h"

static const double cube_p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                  1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};

/* Checks the tree's invariants: every face once in `order`, leaves of 1..LEAF
 * triangles, a node's box holds its triangles, children follow the layout. */
static void check_structure(const ls_mesh *m, const ls_bvh *b)
{
    uint32_t *seen = (uint32_t *)calloc(m->face_count, sizeof(uint32_t));
    uint32_t i, k, leaves = 0, covered = 0;
    REQUIRE(seen != NULL);
    CHECK(b->node_count <= 2 * m->face_count - 1);
    CHECK(b->depth <= LS_BVH_MAX_DEPTH);
    for (i = 0; i < m->face_count; i++) {
        CHECK(b->order[i] < m->face_count);
        if (b->order[i] < m->face_count) seen[b->order[i]]++;
    }
    for (i = 0; i < m->face_count; i++) CHECK_EQ(seen[i], 1);
    for (i = 0; i < b->node_count; i++) {
        const ls_bvh_node *n = &b->nodes[i];
        if (n->count > 0) {
            CHECK(n->count <= LS_BVH_LEAF);
            leaves++;
            covered += n->count;
            for (k = n->first; k < n->first + n->count; k++) {
                const uint32_t *t = m->triangles + 3 * b->order[k];
                int c, a;
                for (c = 0; c < 3; c++)
                    for (a = 0; a < 3; a++) {
                        ls_real x = m->positions[3 * t[c] + a];
                        CHECK(x >= n->lo[a] && x <= n->hi[a]);
                    }
            }
        } else {
            int a;
            REQUIRE(i + 1 < b->node_count && n->first > i + 1 && n->first < b->node_count);
            for (a = 0; a < 3; a++) {
                CHECK(b->nodes[i + 1].lo[a] >= n->lo[a] && b->nodes[i + 1].hi[a] <= n->hi[a]);
                CHECK(b->nodes[n->first].lo[a] >= n->lo[a] && b->nodes[n->first].hi[a] <= n->hi[a]);
            }
        }
    }
    CHECK_EQ(covered, m->face_count);
    CHECK_EQ(b->node_count, 2 * leaves - 1);
    free(seen);
}

/* Compares BVH and brute force on `count` points around the mesh (box
 * enlarged by `grow` of its size; some points snapped onto vertices, edges and
 * faces, where ties are likely). Returns the agreements. */
static uint32_t compare_brute(const ls_mesh *m, const ls_bvh *b, uint32_t count, double grow, uint64_t seed)
{
    ls_real lo[3], hi[3];
    geo_rng g;
    uint32_t i, agree = 0;
    g.s = test_rng_seed(seed);
    ls_mesh_bounds(m, lo, hi);
    for (i = 0; i < count; i++) {
        ls_real p[3];
        ls_bvh_hit h1, h2;
        int a;
        uint32_t kind = i % 4;
        if (kind == 0 || kind == 3) {
            for (a = 0; a < 3; a++) {
                double ext = (double)(hi[a] - lo[a]);
                p[a] = (ls_real)((double)lo[a] - grow * ext + (1 + 2 * grow) * ext * geo_rand(&g));
            }
        } else {
            /* on the surface: a vertex, or a point of a face */
            uint32_t f = (uint32_t)(geo_rand(&g) * m->face_count) % m->face_count;
            const uint32_t *t = m->triangles + 3 * f;
            double u = geo_rand(&g), v = geo_rand(&g);
            if (kind == 1) { u = 0; v = 0; }
            if (u + v > 1) { u = 1 - u; v = 1 - v; }
            for (a = 0; a < 3; a++)
                p[a] = (ls_real)((1 - u - v) * (double)m->positions[3 * t[0] + a] + u * (double)m->positions[3 * t[1] + a] +
                                 v * (double)m->positions[3 * t[2] + a]);
        }
        /* a guess changes nothing: none, a random face, the answer's face */
        if (i % 3 == 0) CHECK_STATUS(ls_bvh_closest(b, p, (ls_real)INFINITY, &h1), LS_OK);
        else if (i % 3 == 1)
            CHECK_STATUS(ls_bvh_closest_near(b, p, (ls_real)INFINITY, (uint32_t)(geo_rand(&g) * m->face_count), &h1),
                         LS_OK);
        geo_brute_closest(m, p, &h2);
        if (i % 3 == 2) CHECK_STATUS(ls_bvh_closest_near(b, p, (ls_real)INFINITY, h2.face, &h1), LS_OK);
        if (h1.face == h2.face && h1.dist2 == h2.dist2 && memcmp(h1.point, h2.point, sizeof h1.point) == 0 &&
            memcmp(h1.bary, h2.bary, sizeof h1.bary) == 0)
            agree++;
        else
            CHECK_MSG(0, "point %u: bvh face %u d2 %.17g, brute face %u d2 %.17g", i, h1.face, (double)h1.dist2, h2.face,
                      (double)h2.dist2);
        /* a bounded search below the answer finds nothing; just above finds it */
        if (h2.dist2 > 0) {
            CHECK_STATUS(ls_bvh_closest(b, p, h2.dist2, &h1), LS_OK);
            CHECK_EQ(h1.face, UINT32_MAX);
        }
        CHECK_STATUS(ls_bvh_closest(b, p, h2.dist2 * (ls_real)1.5 + (ls_real)1e-30, &h1), LS_OK);
        CHECK_EQ(h1.face, h2.face);
        /* a guess at the answer, in a search bounded at its distance: the
         * bound is strict, so nothing is found */
        if (h2.dist2 > 0) {
            CHECK_STATUS(ls_bvh_closest_near(b, p, h2.dist2, h2.face, &h1), LS_OK);
            CHECK_EQ(h1.face, UINT32_MAX);
        }
    }
    return agree;
}

/* Checks the oriented boxes: orthonormal rows, and every corner of a node
 * inside its box, its projections computed in long double (the ranges must
 * hold the exact values, not only the rounded ones). */
static void check_frames(const ls_mesh *m, const ls_bvh *b)
{
    uint32_t i, k, c, a, j, bad = 0, rows = 0;
    REQUIRE(b->frames != NULL && b->frame_used != NULL);
    for (i = 0; i < b->node_count; i++) {
        const ls_bvh_frame *fr = &b->frames[i];
        uint32_t first = i, last = i;
        if (!(fr->lo[0] <= fr->hi[0])) {
            CHECK_EQ(b->frame_used[i / 32] >> (i % 32) & 1u, 0);
            continue;
        }
        for (a = 0; a < 3; a++)
            for (j = 0; j < 3; j++) {
                long double d = 0;
                for (c = 0; c < 3; c++) d += (long double)fr->axis[a][c] * (long double)fr->axis[j][c];
                if (fabsl(d - (a == j ? 1.0L : 0.0L)) > 16.0L * LS_REAL_EPSILON) rows++;
            }
        while (b->nodes[first].count == 0) first++;
        while (b->nodes[last].count == 0) last = b->nodes[last].first;
        for (k = b->nodes[first].first; k < b->nodes[last].first + b->nodes[last].count; k++) {
            const uint32_t *t = m->triangles + 3 * b->order[k];
            for (c = 0; c < 3; c++)
                for (a = 0; a < 3; a++) {
                    long double x = 0;
                    for (j = 0; j < 3; j++) x += (long double)fr->axis[a][j] * (long double)m->positions[3 * t[c] + j];
                    if (x < (long double)fr->lo[a] || x > (long double)fr->hi[a]) bad++;
                }
        }
    }
    CHECK_EQ(rows, 0);
    CHECK_EQ(bad, 0);
}

/* A fan of n - 1 triangles around a centre, with rim points on a circle of
 * radius r; `lift` raises the centre (0: planar; else a cone); then rotated by
 * the angles (ax, ay) and moved by `off`, so that no triangle lies along an
 * axis. */
static int fan_mesh(ls_arena *a, ls_mesh *m, uint32_t n, double r, double lift, double ax, double ay, double off)
{
    double *p = (double *)malloc(3 * sizeof(double) * n);
    uint32_t *t = (uint32_t *)malloc(3 * sizeof(uint32_t) * (n - 1)), i;
    int ok;
    if (p == NULL || t == NULL) {
        free(p);
        free(t);
        return 0;
    }
    for (i = 0; i < n; i++) {
        double th = 6.283185307179586 * (double)(i == 0 ? 0 : i - 1) / (double)(n - 1);
        double x = i == 0 ? 0 : r * cos(th), y = i == 0 ? 0 : r * sin(th), z = i == 0 ? lift : 0, y2, z2;
        y2 = y * cos(ax) - z * sin(ax); /* about x, then about y */
        z2 = y * sin(ax) + z * cos(ax);
        p[3 * i + 0] = x * cos(ay) + z2 * sin(ay) + off;
        p[3 * i + 1] = y2 + off;
        p[3 * i + 2] = -x * sin(ay) + z2 * cos(ay) + off;
    }
    for (i = 0; i + 1 < n; i++) {
        t[3 * i] = 0;
        t[3 * i + 1] = 1 + i;
        t[3 * i + 2] = 1 + (i + 1) % (n - 1);
    }
    ok = geo_mesh(a, m, p, n, t, n - 1);
    free(p);
    free(t);
    return ok;
}

/* With oriented boxes the answers are the same, bit for bit, on every mesh:
 * cube, sphere, degenerate faces, fans planar and conical at several
 * scales and offsets; near the largest finite coordinates the boxes still
 * hold their corners. */
static void frames_match_brute_force(void)
{
    static const double degen_p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0.5, 0.5, 1, 1, 1, 0};
    static const uint32_t degen_t[] = {0, 1, 2, 1, 5, 2, 0, 4, 1, 0, 1, 3, 2, 2, 4, 5, 5, 5, 0, 1, 2};
    const double ctr[3] = {0.25, -0.5, 2};
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    ls_arena_mark mk;
    int i;
    REQUIRE(geo_arena(&a, 1 << 24) != NULL);
    mk = ls_arena_save(&a);
    for (i = 0; i < 9; i++) {
        uint32_t n = geo_scaled(500);
        size_t bytes, before;
        ls_arena_restore(&a, mk);
        if (i == 0) REQUIRE(geo_mesh(&a, &m, cube_p, 8, cube_t, 12));
        else if (i == 1) REQUIRE(geo_sphere(&a, &m, 1.5, ctr, 12, 16));
        else if (i == 2) REQUIRE(geo_mesh(&a, &m, degen_p, 6, degen_t, 7));
        else if (i == 3) REQUIRE(fan_mesh(&a, &m, 1000, 1, 0, 0, 0, 0));
        else if (i == 4) REQUIRE(fan_mesh(&a, &m, 1000, 1, 0, 0.7, 0.3, 0));
        else if (i == 5) REQUIRE(fan_mesh(&a, &m, 777, 2, 0.05, 1.1, -0.4, 0.5));
        else if (i == 6) REQUIRE(fan_mesh(&a, &m, 600, 1e-3, 0, 0.2, 0.9, 1e3));
        else if (i == 7) REQUIRE(fan_mesh(&a, &m, 300, 1e-3 * sqrt((double)LS_REAL_MAX), 1e-4 * sqrt((double)LS_REAL_MAX),
                                          0.5, 0.5, 0));
        else REQUIRE(fan_mesh(&a, &m, 300, 0.45 * (double)LS_REAL_MAX, 0, 0.5, 0.5, 0));
        CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
        CHECK_STATUS(ls_bvh_frames_bytes(m.face_count, &bytes), LS_OK);
        before = ls_arena_used(&a);
        a.peak = before;
        CHECK_STATUS(ls_bvh_build_frames(&b, &a, NULL), LS_OK);
        CHECK_EQ(a.peak - before, bytes);
        check_structure(&m, &b);
        check_frames(&m, &b);
        if (i == 8) continue; /* the boxes hold (checked above); every squared distance would overflow */
        CHECK_EQ(compare_brute(&m, &b, n, i == 7 ? 0.5 : 0.2, 40 + (uint64_t)i), n);
    }
    free(a.base);
}

/* The oriented boxes make a fan's closest-point search logarithmic: of the
 * nodes whose axis-aligned box holds a point of the fan (every exact search
 * visits them), a fixed share of the tree, the ones whose oriented box holds
 * it too are a few per level. Counted in the test with its own evaluation
 * of the boxes (long double, no margin). */
static void frames_prune_fans(void)
{
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    uint32_t n = 16385, q, i, k, in_box = 0, in_both = 0, queries = 64;
    REQUIRE(geo_arena(&a, 1 << 25) != NULL);
    REQUIRE(fan_mesh(&a, &m, n, 1, 0, 0.7, 0.3, 0));
    REQUIRE(ls_bvh_build(&m, &a, &b, NULL) == LS_OK);
    REQUIRE(ls_bvh_build_frames(&b, &a, NULL) == LS_OK);
    for (q = 0; q < queries; q++) {
        /* the centroid of face f, at radius about 2/3 */
        uint32_t f = (uint32_t)(((uint64_t)q * 2654435761u) % m.face_count);
        ls_real p[3];
        for (k = 0; k < 3; k++)
            p[k] = (m.positions[3 * m.triangles[3 * f] + k] + m.positions[3 * m.triangles[3 * f + 1] + k] +
                    m.positions[3 * m.triangles[3 * f + 2] + k]) / 3;
        for (i = 0; i < b.node_count; i++) {
            const ls_bvh_node *nd = &b.nodes[i];
            const ls_bvh_frame *fr = &b.frames[i];
            int inside = 1;
            for (k = 0; k < 3; k++) inside &= p[k] >= nd->lo[k] && p[k] <= nd->hi[k];
            if (!inside) continue;
            in_box++;
            if (b.frame_used[i / 32] >> (i % 32) & 1u) {
                for (k = 0; k < 3; k++) {
                    long double t = (long double)fr->axis[k][0] * p[0] + (long double)fr->axis[k][1] * p[1] +
                                    (long double)fr->axis[k][2] * p[2];
                    inside &= t >= (long double)fr->lo[k] - 1e-9L && t <= (long double)fr->hi[k] + 1e-9L;
                }
            }
            in_both += (uint32_t)inside;
        }
    }
    printf("     fan of %u faces: per query %.1f nodes hold the point in their axis-aligned box, %.1f in both boxes\n",
              m.face_count, (double)in_box / queries, (double)in_both / queries);
    CHECK(in_box > 200 * queries);  /* the axis-aligned boxes alone: a share of the 8k nodes */
    CHECK(in_both < 100 * queries); /* both: a few per level (15 levels) */
    free(a.base);
}

static ls_status frames_run(void *ctx, ls_arena *a)
{
    return ls_bvh_build_frames((ls_bvh *)ctx, a, NULL);
}

static uint64_t frames_hash(void *ctx)
{
    return test_hash(ctx, sizeof(ls_bvh), TEST_HASH_SEED);
}

/* ls_bvh_frames_bytes is exact, and a short arena fails cleanly. */
static void frames_arena_sweep(void)
{
    ls_arena a;
    ls_mesh m;
    ls_bvh b, keep;
    sweep_job job;
    const double ctr[3] = {0, 0, 0};
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    REQUIRE(geo_sphere(&a, &m, 1.0, ctr, 10, 12));
    REQUIRE(ls_bvh_build(&m, &a, &b, NULL) == LS_OK);
    keep = b;
    memset(&job, 0, sizeof job);
    job.name = "bvh_build_frames sphere";
    job.run = frames_run;
    job.state_hash = frames_hash;
    job.ctx = &b;
    job.exact = 1;
    REQUIRE(ls_bvh_frames_bytes(m.face_count, &job.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&job), 0);
    b = keep;
    CHECK_STATUS(ls_bvh_build_frames(NULL, &a, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_build_frames(&b, NULL, NULL), LS_ERR_INVALID);
    memset(&keep, 0, sizeof keep);
    CHECK_STATUS(ls_bvh_build_frames(&keep, &a, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_frames_bytes(0, &job.answer), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_frames_bytes(1, NULL), LS_ERR_INVALID);
    free(a.base);
}

static void cube_matches_brute_force(void)
{
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(geo_mesh(&a, &m, cube_p, 8, cube_t, 12));
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
    check_structure(&m, &b);
    CHECK_EQ(compare_brute(&m, &b, geo_scaled(2000), 0.5, 1), geo_scaled(2000));
    {
        /* the centre is equidistant (0.5) from all 12 faces: face 0 wins */
        ls_real p[3] = {(ls_real)0.5, (ls_real)0.5, (ls_real)0.5};
        ls_bvh_hit h;
        CHECK_STATUS(ls_bvh_closest(&b, p, (ls_real)INFINITY, &h), LS_OK);
        CHECK_EQ(h.face, 0);
        CHECK(h.dist2 == (ls_real)0.25);
    }
    free(a.base);
}

static void sphere_and_bunny_match_brute_force(void)
{
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    const double c[3] = {0.1, -0.2, 0.3};
    uint32_t agree;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_sphere(&a, &m, 1.0, c, 12, 16));
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
    check_structure(&m, &b);
    CHECK_EQ(compare_brute(&m, &b, geo_scaled(3000), 0.3, 7), geo_scaled(3000));
    REQUIRE(geo_read("fixtures/meshes/bunny.obj", &a, &m));
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
    check_structure(&m, &b);
    agree = compare_brute(&m, &b, geo_scaled(1200), 0.2, 11);
    CHECK_EQ(agree, geo_scaled(1200));
    printf("     bunny: %u faces, %u nodes, depth %u, %u/%u queries identical to brute force\n", m.face_count,
           b.node_count, b.depth, agree, geo_scaled(1200));
    free(a.base);
}

/* Collinear and coincident corners: the answer is the closest point of the
 * longest edge, checked against a dense sampling of that segment. */
static void degenerate_triangles(void)
{
    ls_real a[3] = {0, 0, 0}, b3[3] = {1, 1, 0}, c[3] = {3, 3, 0}, p[3], q[3], bary[3], d2;
    geo_rng g;
    int i, k;
    g.s = test_rng_seed(5);
    for (i = 0; i < 200; i++) {
        double best = 1e300, qx;
        for (k = 0; k < 3; k++) p[k] = (ls_real)(6 * geo_rand(&g) - 1.5);
        ls_closest_point_triangle(p, a, b3, c, q, bary, &d2);
        /* exact: projection on the segment a-c, clamped */
        qx = ((double)p[0] + (double)p[1]) / 2;
        if (qx < 0) qx = 0;
        if (qx > 3) qx = 3;
        best = (qx - (double)p[0]) * (qx - (double)p[0]) + (qx - (double)p[1]) * (qx - (double)p[1]) +
               (double)p[2] * (double)p[2];
        CHECK_NEAR(d2, best, 1e-5 * (1 + best));
        CHECK_NEAR(q[0], qx, 1e-5);
        CHECK_NEAR(q[1], qx, 1e-5);
        CHECK_NEAR((double)bary[0] + (double)bary[1] + (double)bary[2], 1.0, TEST_EPS(4));
        CHECK(bary[0] >= 0 && bary[1] >= 0 && bary[2] >= 0);
        /* the barycentric coordinates reproduce the point */
        CHECK_NEAR((double)bary[0] * (double)a[0] + (double)bary[1] * (double)b3[0] + (double)bary[2] * (double)c[0],
                   (double)q[0], 1e-5);
    }
    /* all three corners equal */
    p[0] = 1;
    p[1] = 2;
    p[2] = 2;
    ls_closest_point_triangle(p, b3, b3, b3, q, bary, &d2);
    CHECK(q[0] == 1 && q[1] == 1 && q[2] == 0);
    CHECK_NEAR(d2, 5.0, TEST_EPS(8));
    /* two equal corners: a segment */
    ls_closest_point_triangle(p, a, c, a, q, bary, &d2);
    CHECK_NEAR(q[0], 1.5, TEST_EPS(8));
    CHECK_NEAR(d2, 0.25 + 0.25 + 4, TEST_EPS(16));
    CHECK(ls_isfinite((double)d2));
}

/* Non-degenerate triangles: the answer against a dense barycentric sampling
 * (never farther than the best sample, never much closer). */
static void closest_point_against_sampling(void)
{
    geo_rng g;
    int i, k, s, t;
    const int N = 60;
    g.s = test_rng_seed(99);
    for (i = 0; i < 120; i++) {
        ls_real v[3][3], p[3], q[3], bary[3], d2;
        double best = 1e300, h = 0;
        for (k = 0; k < 9; k++) v[k / 3][k % 3] = (ls_real)(2 * geo_rand(&g) - 1);
        for (k = 0; k < 3; k++) p[k] = (ls_real)(4 * geo_rand(&g) - 2);
        ls_closest_point_triangle(p, v[0], v[1], v[2], q, bary, &d2);
        for (s = 0; s <= N; s++)
            for (t = 0; s + t <= N; t++) {
                double u = (double)s / N, w = (double)t / N, d = 0, x;
                for (k = 0; k < 3; k++) {
                    x = (1 - u - w) * (double)v[0][k] + u * (double)v[1][k] + w * (double)v[2][k] - (double)p[k];
                    d += x * x;
                }
                if (d < best) best = d;
            }
        for (k = 0; k < 3; k++) {
            double e = (double)v[(k + 1) % 3][0] - (double)v[k][0], f = (double)v[(k + 1) % 3][1] - (double)v[k][1],
                   gg = (double)v[(k + 1) % 3][2] - (double)v[k][2];
            double l = sqrt(e * e + f * f + gg * gg);
            if (l > h) h = l;
        }
        /* sampling spacing <= h / N: the true distance is within h/N of the best sample's */
        CHECK((double)d2 <= best * (1 + 1e-5) + 1e-6);
        CHECK(sqrt((double)d2) >= sqrt(best) - h / N - 1e-6);
        CHECK(bary[0] >= 0 && bary[1] >= 0 && bary[2] >= 0);
        CHECK_NEAR((double)bary[0] + (double)bary[1] + (double)bary[2], 1.0, TEST_EPS(4));
    }
}

static void degenerate_mesh_matches_brute_force(void)
{
    /* a fan with a collinear face (3), a face with a repeated index (4), one
     * with all corners equal (5) and duplicated faces (6 = 0) */
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0.5, 0.5, 1, 1, 1, 0};
    static const uint32_t t[] = {0, 1, 2, 1, 5, 2, 0, 4, 1, 0, 1, 3, 2, 2, 4, 5, 5, 5, 0, 1, 2};
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    REQUIRE(geo_arena(&a, 1 << 16) != NULL);
    REQUIRE(geo_mesh(&a, &m, p, 6, t, 7));
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
    check_structure(&m, &b);
    CHECK_EQ(compare_brute(&m, &b, geo_scaled(2000), 0.5, 3), geo_scaled(2000));
    {
        /* face 6 duplicates face 0: the lower index wins */
        ls_real q[3] = {(ls_real)0.2, (ls_real)0.2, (ls_real)-1};
        ls_bvh_hit h;
        CHECK_STATUS(ls_bvh_closest(&b, q, (ls_real)INFINITY, &h), LS_OK);
        CHECK_EQ(h.face, 0);
        CHECK(h.dist2 == 1);
    }
    free(a.base);
}

static void overlap_matches_brute_force(void)
{
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    geo_rng g;
    int i;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_read("fixtures/meshes/bunny.obj", &a, &m));
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
    g.s = test_rng_seed(17);
    for (i = 0; i < (int)geo_scaled(60); i++) {
        ls_real lo[3], hi[3], flo[3], fhi[3];
        ls_bvh_overlap it;
        uint32_t f, c, k, n_it = 0, n_bf = 0, *hits = (uint32_t *)calloc(m.face_count, sizeof(uint32_t));
        for (k = 0; k < 3; k++) {
            double x = -3 + 6 * geo_rand(&g), w = 0.6 * geo_rand(&g);
            lo[k] = (ls_real)x;
            hi[k] = (ls_real)(x + w);
        }
        CHECK_STATUS(ls_bvh_overlap_begin(&b, lo, hi, &it), LS_OK);
        while (ls_bvh_overlap_next(&it, &f)) {
            n_it++;
            hits[f]++;
        }
        for (f = 0; f < m.face_count; f++) {
            const uint32_t *t = m.triangles + 3 * f;
            int in = 1;
            for (k = 0; k < 3; k++) {
                flo[k] = fhi[k] = m.positions[3 * t[0] + k];
                for (c = 1; c < 3; c++) {
                    ls_real x = m.positions[3 * t[c] + k];
                    if (x < flo[k]) flo[k] = x;
                    if (x > fhi[k]) fhi[k] = x;
                }
                if (flo[k] > hi[k] || fhi[k] < lo[k]) in = 0;
            }
            /* every triangle whose box overlaps is reported, once */
            if (in) {
                n_bf++;
                CHECK_EQ(hits[f], 1);
            } else {
                CHECK(hits[f] <= 1);
            }
        }
        CHECK(n_it >= n_bf);
        free(hits);
    }
    free(a.base);
}

static void errors(void)
{
    static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t t[] = {0, 1, 2}, bad[] = {0, 1, 3};
    ls_arena a;
    ls_mesh m;
    ls_bvh b;
    ls_bvh_hit h;
    ls_diag d;
    ls_real q[3] = {0, 0, 0};
    size_t bytes;
    REQUIRE(geo_arena(&a, 1 << 12) != NULL);
    REQUIRE(geo_mesh(&a, &m, p, 3, bad, 1));
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, &d), LS_ERR_MESH);
    CHECK_EQ(d.index, 0);
    memcpy(m.triangles, t, sizeof t);
    m.positions[4] = (ls_real)NAN;
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, &d), LS_ERR_NONFINITE);
    CHECK_EQ(d.index, 1);
    m.positions[4] = 0;
    m.face_count = 0;
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "mesh->face_count") != NULL);
    m.face_count = 1;
    CHECK_STATUS(ls_bvh_build(NULL, &a, &b, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "mesh is NULL") == 0);
    CHECK_STATUS(ls_bvh_build(&m, NULL, &b, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "arena is NULL") == 0);
    CHECK_STATUS(ls_bvh_check_mesh(NULL, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "mesh is NULL") == 0);
    CHECK_STATUS(ls_bvh_build(&m, &a, &b, &d), LS_OK);
    q[1] = (ls_real)INFINITY;
    CHECK_STATUS(ls_bvh_closest(&b, q, 1, &h), LS_ERR_NONFINITE);
    q[1] = 0;
    CHECK_STATUS(ls_bvh_closest(&b, q, (ls_real)NAN, &h), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_closest(NULL, q, 1, &h), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_closest(&b, q, -1, &h), LS_OK);
    CHECK_EQ(h.face, UINT32_MAX);
    CHECK_STATUS(ls_bvh_bytes(0, &bytes), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_bytes(1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_bvh_bytes(UINT32_MAX, &bytes), sizeof(size_t) < 8 ? LS_ERR_TOO_LARGE : LS_OK);
    free(a.base);
}

/* The node count of the bytes query matches the tree for every size 1..300. */
static void node_counts(void)
{
    ls_arena a;
    ls_mesh m;
    uint32_t n, i;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    for (n = 1; n <= (geo_emulated() ? 60u : 300u); n++) {
        ls_bvh b;
        size_t bytes, before;
        ls_arena_mark mk = ls_arena_save(&a);
        REQUIRE(ls_mesh_alloc(&m, n + 2, n, &a) == LS_OK);
        for (i = 0; i < n + 2; i++) {
            m.positions[3 * i] = (ls_real)i;
            m.positions[3 * i + 1] = (ls_real)(i % 7);
            m.positions[3 * i + 2] = (ls_real)(i % 3);
        }
        for (i = 0; i < n; i++) {
            m.triangles[3 * i] = i;
            m.triangles[3 * i + 1] = i + 1;
            m.triangles[3 * i + 2] = i + 2;
        }
        REQUIRE(ls_bvh_bytes(n, &bytes) == LS_OK);
        ls_arena_reset_peak(&a);
        before = ls_arena_used(&a);
        CHECK_STATUS(ls_bvh_build(&m, &a, &b, NULL), LS_OK);
        CHECK_EQ(a.peak - before, bytes);
        check_structure(&m, &b);
        ls_arena_restore(&a, mk);
    }
    free(a.base);
}

typedef struct build_ctx {
    ls_mesh m;
    ls_bvh b;
} build_ctx;

static ls_status build_run(void *ctx, ls_arena *a)
{
    build_ctx *c = (build_ctx *)ctx;
    return ls_bvh_build(&c->m, a, &c->b, NULL);
}

static uint64_t build_hash(void *ctx)
{
    build_ctx *c = (build_ctx *)ctx;
    uint64_t h = test_hash(&c->b, sizeof c->b, TEST_HASH_SEED);
    h = test_hash(c->m.positions, 3 * sizeof(ls_real) * c->m.vertex_count, h);
    return test_hash(c->m.triangles, 3 * sizeof(uint32_t) * c->m.face_count, h);
}

static void build_reset(void *ctx)
{
    build_ctx *c = (build_ctx *)ctx;
    memset(&c->b, 0, sizeof c->b);
}

static void arena_sweep(void)
{
    ls_arena a;
    build_ctx c;
    sweep_job job;
    const double ctr[3] = {0, 0, 0};
    int i;
    REQUIRE(geo_arena(&a, 1 << 20) != NULL);
    for (i = 0; i < 2; i++) {
        if (i == 0) REQUIRE(geo_mesh(&a, &c.m, cube_p, 8, cube_t, 12));
        else REQUIRE(geo_sphere(&a, &c.m, 1.0, ctr, 10, 12));
        memset(&c.b, 0, sizeof c.b);
        memset(&job, 0, sizeof job);
        job.name = i == 0 ? "bvh_build cube" : "bvh_build sphere";
        job.run = build_run;
        job.state_hash = build_hash;
        job.reset = build_reset;
        job.ctx = &c;
        job.exact = 1;
        REQUIRE(ls_bvh_bytes(c.m.face_count, &job.answer) == LS_OK);
        CHECK_EQ(sweep_arena(&job), 0);
    }
    free(a.base);
}

/* The same input gives the same tree bytes (nodes and order). */
static void deterministic(void)
{
    ls_arena a;
    ls_mesh m;
    ls_bvh b1, b2;
    REQUIRE(geo_arena(&a, 1 << 22) != NULL);
    REQUIRE(geo_read("fixtures/meshes/bunny.obj", &a, &m));
    REQUIRE(ls_bvh_build(&m, &a, &b1, NULL) == LS_OK);
    REQUIRE(ls_bvh_build(&m, &a, &b2, NULL) == LS_OK);
    CHECK_EQ(b1.node_count, b2.node_count);
    CHECK(memcmp(b1.nodes, b2.nodes, b1.node_count * sizeof(ls_bvh_node)) == 0);
    CHECK(memcmp(b1.order, b2.order, m.face_count * sizeof(uint32_t)) == 0);
    CHECK_EQ(test_hash(b1.order, m.face_count * sizeof(uint32_t), TEST_HASH_SEED) != 0, 1);
    free(a.base);
}

int main(void)
{
    TEST_INIT("test_bvh");
    TEST_RUN(cube_matches_brute_force);
    TEST_RUN(sphere_and_bunny_match_brute_force);
    TEST_RUN(degenerate_triangles);
    TEST_RUN(closest_point_against_sampling);
    TEST_RUN(degenerate_mesh_matches_brute_force);
    TEST_RUN(overlap_matches_brute_force);
    TEST_RUN(errors);
    TEST_RUN(node_counts);
    TEST_RUN(arena_sweep);
    TEST_RUN(deterministic);
    TEST_RUN(frames_match_brute_force);
    TEST_RUN(frames_prune_fans);
    TEST_RUN(frames_arena_sweep);
    return TEST_END();
}
