/* tests/test_visual_hull.c - the visual hull of three orthographic views of a
 * ball: the intersection of three cylinders (a Steinmetz solid), whose
 * surface and volume are known in closed form. Checks the surface's
 * position, a closed genus-0 manifold with outward faces, the speck dropped,
 * exact bytes, determinism and the errors. */
#include "test.h"
#include "geo_test.h"
#include <stdlib.h>
#include <string.h>

#define BUF_BYTES (64u << 20)
#define RES 96u      /* image side */
#define RADIUS 0.6   /* the ball */
static unsigned char *buf;
static ls_real *images[3];
static ls_real mvps[48];

/* View a looks along axis a: window x, y from the two other axes (X = p[(a+1)%3], Y = p[(a+2)%3]),
 * orthographic (W = 1) over [-1, 1]. */
static void make_views(int speck)
{
    uint32_t a, i, j;
    memset(mvps, 0, sizeof mvps);
    for (a = 0; a < 3u; a++) {
        ls_real *m = mvps + 16u * a;
        m[0 * 4 + (a + 1u) % 3u] = 1;
        m[1 * 4 + (a + 2u) % 3u] = 1;
        m[2 * 4 + a] = 1;
        m[15] = 1;
        for (j = 0; j < RES; j++)
            for (i = 0; i < RES; i++) {
                /* the pixel centre on the image plane: window -> (X, Y) */
                double x = (i + 0.5) / RES * 2.0 - 1.0, y = 1.0 - (j + 0.5) / RES * 2.0;
                int in = x * x + y * y <= RADIUS * RADIUS;
                /* a speck: a small ball at (0.85, 0.85, 0.85), seen by every view at (0.85, 0.85) */
                if (speck && (x - 0.85) * (x - 0.85) + (y - 0.85) * (y - 0.85) <= 0.05 * 0.05) in = 1;
                images[a][4u * (j * RES + i) + 0] = images[a][4u * (j * RES + i) + 1] = 0.5;
                images[a][4u * (j * RES + i) + 2] = 0.5;
                images[a][4u * (j * RES + i) + 3] = in ? 1 : 0;
            }
    }
}

static void setup(ls_hull_views *hv, ls_hull_params *hp, uint32_t resolution)
{
    static const ls_real lo[3] = {-0.95, -0.95, -0.95}, hi[3] = {0.95, 0.95, 0.95};
    hv->images = (const ls_real *const *)images;
    hv->mvps = mvps;
    hv->count = 3;
    hv->width = hv->height = RES;
    ls_hull_params_default(hp, lo, hi);
    hp->resolution = resolution;
}

/* Every vertex on the tricylinder's surface: the largest of its three
 * distances from the axes is the radius, within a cell and a pixel. */
static void tricylinder(void)
{
    static const uint32_t resolutions[2] = {40, 96};
    uint32_t r;
    make_views(0);
    for (r = 0; r < (geo_emulated() ? 1u : 2u); r++) { /* under QEMU the coarse grid alone */
        ls_arena arena;
        ls_hull_views hv;
        ls_hull_params hp;
        ls_mesh m;
        ls_mesh_report rep;
        ls_diag d;
        uint32_t v;
        double worst = 0, cell, vol, exact = 8.0 * (2.0 - sqrt(2.0)) * RADIUS * RADIUS * RADIUS;
        setup(&hv, &hp, resolutions[r]);
        cell = 1.9 / resolutions[r];
        REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
        REQUIRE(ls_visual_hull(&hv, &hp, &arena, &m, &d) == LS_OK);
        for (v = 0; v < m.vertex_count; v++) {
            const ls_real *p = m.positions + 3u * v;
            double x = p[0], y = p[1], z = p[2];
            double q = sqrt(x * x + y * y), s = sqrt(y * y + z * z), t = sqrt(x * x + z * z);
            double e = fabs((q > s ? (q > t ? q : t) : (s > t ? s : t)) - RADIUS);
            if (e > worst) worst = e;
        }
        vol = geo_signed_volume(&m);
        printf("  resolution %u: %u vertices, %u faces, surface within %.4f (cell %.4f, pixel %.4f), volume %.4f "
               "(exact %.4f)\n",
               (unsigned)resolutions[r], (unsigned)m.vertex_count, (unsigned)m.face_count, worst, cell, 2.0 / RES, vol,
               exact);
        CHECK(worst <= 0.5 * cell + 2.0 / RES);
        CHECK(fabs(vol - exact) <= (r == 0 ? 0.03 : 0.01) * exact); /* > 0: the faces point outward */
        REQUIRE(ls_mesh_validate(&m, &arena, &rep) == LS_OK);
        CHECK_EQ(rep.has_genus, 1u);
        CHECK_EQ(rep.genus, 0);
        CHECK_EQ(rep.components, 1u);
        CHECK_EQ(rep.boundary_edges, 0u);
        CHECK_EQ(rep.unreferenced_vertices, 0u);
        CHECK_EQ(rep.zero_area_faces, 0u);
    }
}

/* The speck is a second component of the hull: dropped. */
static void speck_dropped(void)
{
    ls_arena arena;
    ls_hull_views hv;
    ls_hull_params hp;
    ls_mesh m;
    ls_mesh_report rep;
    uint32_t v;
    double far = 0;
    make_views(1);
    setup(&hv, &hp, 48);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_visual_hull(&hv, &hp, &arena, &m, NULL) == LS_OK);
    for (v = 0; v < m.vertex_count; v++) {
        const ls_real *p = m.positions + 3u * v;
        double n = sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
        if (n > far) far = n;
    }
    CHECK(far < 0.9); /* the tricylinder's corners are at 0.6 sqrt(2) = 0.85 */
    REQUIRE(ls_mesh_validate(&m, &arena, &rep) == LS_OK);
    CHECK_EQ(rep.components, 1u);
    make_views(0);
}

/* ls_visual_hull_bytes is exact; one byte less is LS_ERR_NOMEM and leaves
 * the arena as it was; two runs give the same bits. */
static void exact_bytes_and_bits(void)
{
    ls_arena arena;
    ls_hull_views hv;
    ls_hull_params hp;
    ls_mesh m, m2;
    size_t bytes = 0, used;
    ls_status st;
    make_views(0);
    setup(&hv, &hp, 40);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    REQUIRE(ls_visual_hull_bytes(&hv, &hp, &arena, &bytes, NULL) == LS_OK);
    CHECK_EQ(ls_arena_used(&arena), 0u);
    REQUIRE(ls_arena_init(&arena, buf, bytes) == LS_OK);
    REQUIRE(ls_visual_hull(&hv, &hp, &arena, &m, NULL) == LS_OK);
    CHECK_EQ(arena.peak, bytes);
    used = ls_arena_used(&arena);
    {
        ls_arena small;
        ls_mesh none;
        unsigned char *other = buf + (BUF_BYTES / 2u);
        memset(&none, 0, sizeof none);
        REQUIRE(ls_arena_init(&small, other, bytes - LS_ARENA_ALIGN) == LS_OK);
        st = ls_visual_hull(&hv, &hp, &small, &none, NULL);
        CHECK_EQ(st, LS_ERR_NOMEM);
        CHECK_EQ(ls_arena_used(&small), 0u);
        CHECK(none.positions == NULL);
        REQUIRE(ls_arena_init(&small, other, BUF_BYTES / 2u) == LS_OK);
        REQUIRE(ls_visual_hull(&hv, &hp, &small, &m2, NULL) == LS_OK);
        CHECK_EQ(ls_arena_used(&small), used);
        CHECK_EQ(m2.vertex_count, m.vertex_count);
        CHECK_EQ(m2.face_count, m.face_count);
        CHECK(memcmp(m2.positions, m.positions, 3u * sizeof(ls_real) * m.vertex_count) == 0);
        CHECK(memcmp(m2.triangles, m.triangles, 3u * sizeof(uint32_t) * m.face_count) == 0);
    }
}

static void errors(void)
{
    ls_arena arena;
    ls_hull_views hv;
    ls_hull_params hp;
    ls_mesh m;
    ls_diag d;
    uint32_t i;
    make_views(0);
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    setup(&hv, &hp, 32);
    CHECK_EQ(ls_visual_hull(NULL, &hp, &arena, &m, &d), LS_ERR_INVALID);
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, NULL, &d), LS_ERR_INVALID);
    hp.resolution = 1;
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, &m, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "resolution") != NULL);
    setup(&hv, &hp, 32);
    hp.threshold = 1;
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, &m, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "threshold") != NULL);
    setup(&hv, &hp, 32);
    hp.hi[1] = hp.lo[1];
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, &m, &d), LS_ERR_INVALID);
    setup(&hv, &hp, 32);
    hv.count = 0;
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, &m, &d), LS_ERR_INVALID);
    setup(&hv, &hp, 32);
    mvps[5] = (ls_real)(1.0 / 0.0 * 0.0);
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, &m, &d), LS_ERR_NONFINITE);
    mvps[5] = 0;
    for (i = 0; i < RES * RES; i++) images[1][4u * i + 3u] = 0; /* one view sees nothing */
    CHECK_EQ(ls_visual_hull(&hv, &hp, &arena, &m, &d), LS_ERR_MESH);
    CHECK(strstr(d.what, "mask") != NULL);
    CHECK_EQ(ls_arena_used(&arena), 0u);
}

int main(void)
{
    uint32_t a;
    TEST_INIT("test_visual_hull");
    buf = (unsigned char *)malloc(BUF_BYTES);
    for (a = 0; a < 3u; a++) images[a] = (ls_real *)malloc(4u * RES * RES * sizeof(ls_real));
    if (buf == NULL || images[0] == NULL || images[1] == NULL || images[2] == NULL) return 1;
    TEST_RUN(tricylinder);
    TEST_RUN(speck_dropped);
    TEST_RUN(exact_bytes_and_bits);
    TEST_RUN(errors);
    for (a = 0; a < 3u; a++) free(images[a]);
    free(buf);
    return TEST_END();
}
