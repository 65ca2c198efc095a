/* tests/test_remesh.c - isotropic remeshing: edge-length targets, topology
 * (genus, components, boundary loops), closedness and manifoldness, volume
 * and Hausdorff distance to the input (vertex-sampled, both ways, through
 * ls_bvh_closest), angle percentiles, open meshes, tangled inputs, arena
 * bounds, determinism. Statistics are computed here in double, independently
 * of the library's own sums. */
#include <stdlib.h>
#include "test.h"
#include "sweep.h"
#include "bench/meshgen.h"
#include "geo_test.h"

typedef struct heap_mesh {
    ls_mesh m;
    unsigned char *buf;
} heap_mesh;

/* A mesh in its own malloc'd arena. */
static int load_mesh(const char *path, heap_mesh *hm)
{
    unsigned char *d = NULL;
    size_t n = 0, need = 0;
    ls_mesh_file_info info;
    ls_arena a;
    memset(hm, 0, sizeof *hm);
    if (!geo_read_file(path, &d, &n)) return 0;
    if (ls_mesh_read_info(d, n, LS_MESH_FORMAT_AUTO, &info, NULL) != LS_OK ||
        ls_mesh_read_bytes(&info, &need) != LS_OK) {
        free(d);
        return 0;
    }
    hm->buf = (unsigned char *)malloc(need + 8u);
    ls_arena_init(&a, hm->buf, need);
    if (ls_mesh_read(d, n, info.format, &a, &hm->m, NULL) != LS_OK) {
        free(d);
        return 0;
    }
    free(d);
    return 1;
}

static void from_tmesh(const tmesh *t, heap_mesh *hm)
{
    uint32_t i;
    ls_arena a;
    size_t need = 0;
    ls_mesh_bytes(t->nv, t->nf, &need);
    hm->buf = (unsigned char *)malloc(need + 8u);
    ls_arena_init(&a, hm->buf, need);
    ls_mesh_alloc(&hm->m, t->nv, t->nf, &a);
    for (i = 0; i < 3u * t->nv; i++) hm->m.positions[i] = (ls_real)t->pos[i];
    for (i = 0; i < 3u * t->nf; i++) hm->m.triangles[i] = t->tri[i];
}

static void free_mesh(heap_mesh *hm)
{
    free(hm->buf);
    memset(hm, 0, sizeof *hm);
}

static ls_mesh_report validate(const ls_mesh *m)
{
    ls_mesh_report r;
    size_t need = 0;
    unsigned char *buf;
    ls_arena a;
    memset(&r, 0, sizeof r);
    ls_mesh_validate_bytes(m, &need);
    buf = (unsigned char *)malloc(need + 8u);
    ls_arena_init(&a, buf, need);
    ls_mesh_validate(m, &a, &r);
    free(buf);
    return r;
}

/* ---- independent statistics ------------------------------------------------ */

static double vdist(const ls_real *a, const ls_real *b)
{
    double x = (double)a[0] - (double)b[0], y = (double)a[1] - (double)b[1], z = (double)a[2] - (double)b[2];
    return sqrt(x * x + y * y + z * z);
}

static double mean_edge_ref(const ls_mesh *m)
{
    double s = 0;
    uint32_t f, j;
    for (f = 0; f < m->face_count; f++)
        for (j = 0; j < 3; j++)
            s += vdist(m->positions + 3u * m->triangles[3u * f + j], m->positions + 3u * m->triangles[3u * f + (j + 1) % 3]);
    return s / (3.0 * m->face_count);
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y ? 1 : 0;
}

typedef struct edge_stats {
    double mean, min, max, in_range; /* in_range: fraction in [4/5 h, 4/3 h] */
    double a_min, a1, a5, a50;       /* corner angles, degrees */
} edge_stats;

static edge_stats stats_of(const ls_mesh *m, double h)
{
    edge_stats s;
    size_t n = 3u * (size_t)m->face_count, k = 0, inside = 0;
    double *ang = (double *)malloc(n * sizeof(double) + 8u), sum = 0;
    uint32_t f, j;
    s.min = 1e300;
    s.max = 0;
    for (f = 0; f < m->face_count; f++) {
        for (j = 0; j < 3; j++) {
            const ls_real *a = m->positions + 3u * m->triangles[3u * f + j];
            const ls_real *b = m->positions + 3u * m->triangles[3u * f + (j + 1) % 3];
            const ls_real *c = m->positions + 3u * m->triangles[3u * f + (j + 2) % 3];
            double l = vdist(a, b), lc = vdist(a, c), u = 0, d;
            int q;
            for (q = 0; q < 3; q++) u += ((double)b[q] - a[q]) * ((double)c[q] - a[q]);
            d = u / (l * lc);
            ang[k++] = acos(d > 1 ? 1 : d < -1 ? -1 : d) * 180.0 / 3.14159265358979323846;
            sum += l;
            if (l < s.min) s.min = l;
            if (l > s.max) s.max = l;
            if (l >= 0.8 * h && l <= 4.0 / 3.0 * h) inside++;
        }
    }
    qsort(ang, n, sizeof(double), cmp_d);
    s.mean = sum / (double)n;
    s.in_range = (double)inside / (double)n;
    s.a_min = ang[0];
    s.a1 = ang[n / 100];
    s.a5 = ang[n / 20];
    s.a50 = ang[n / 2];
    free(ang);
    return s;
}

/* Largest distance from a vertex of `from` to the surface of `to`. */
static double one_sided(const ls_mesh *from, const ls_mesh *to)
{
    size_t need = 0;
    unsigned char *buf;
    ls_arena a;
    ls_bvh bvh;
    double worst = -1;
    uint32_t v;
    ls_bvh_bytes(to->face_count, &need);
    buf = (unsigned char *)malloc(need + 8u);
    ls_arena_init(&a, buf, need);
    if (ls_bvh_build(to, &a, &bvh, NULL) == LS_OK) {
        worst = 0;
        for (v = 0; v < from->vertex_count; v++) {
            ls_bvh_hit hit;
            if (ls_bvh_closest(&bvh, from->positions + 3u * v, LS_REAL_MAX, &hit) != LS_OK) {
                worst = 1e300;
                break;
            }
            if (sqrt((double)hit.dist2) > worst) worst = sqrt((double)hit.dist2);
        }
    }
    free(buf);
    return worst;
}

/* Segment pq against triangle abc, in double: 1 when the segment crosses
 * the triangle's plane strictly inside or on the triangle (coplanar
 * configurations are not counted). */
static int seg_tri(const ls_real *p, const ls_real *q, const ls_real *a, const ls_real *b, const ls_real *c)
{
    double ab[3], ac[3], n[3], dp = 0, dq = 0, x[3], t;
    const ls_real *tri[3];
    int k, e;
    tri[0] = a;
    tri[1] = b;
    tri[2] = c;
    for (k = 0; k < 3; k++) {
        ab[k] = (double)b[k] - a[k];
        ac[k] = (double)c[k] - a[k];
    }
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    for (k = 0; k < 3; k++) {
        dp += ((double)p[k] - a[k]) * n[k];
        dq += ((double)q[k] - a[k]) * n[k];
    }
    if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || dp == dq) return 0;
    t = dp / (dp - dq);
    for (k = 0; k < 3; k++) x[k] = (double)p[k] + t * ((double)q[k] - p[k]);
    for (e = 0; e < 3; e++) {
        const ls_real *u = tri[e], *v = tri[(e + 1) % 3];
        double uv[3], ux[3], cr[3];
        for (k = 0; k < 3; k++) {
            uv[k] = (double)v[k] - u[k];
            ux[k] = x[k] - u[k];
        }
        cr[0] = uv[1] * ux[2] - uv[2] * ux[1];
        cr[1] = uv[2] * ux[0] - uv[0] * ux[2];
        cr[2] = uv[0] * ux[1] - uv[1] * ux[0];
        if (cr[0] * n[0] + cr[1] * n[1] + cr[2] * n[2] < 0) return 0;
    }
    return 1;
}

/* Self-intersecting face pairs, checked here independently of src/geometry/tangle.c:
 * candidate pairs from the BVH's box-overlap iterator, then edge-triangle
 * crossings in double. Pairs sharing an edge are skipped; pairs sharing one
 * vertex are tested with the edges opposite it. */
static long self_intersections(const ls_mesh *m)
{
    size_t need = 0;
    unsigned char *buf;
    ls_arena a;
    ls_bvh bvh;
    long n = 0;
    uint32_t f, g;
    if (ls_bvh_bytes(m->face_count, &need) != LS_OK) return -1;
    buf = (unsigned char *)malloc(need + 8u);
    ls_arena_init(&a, buf, need);
    if (ls_bvh_build(m, &a, &bvh, NULL) != LS_OK) {
        free(buf);
        return -1;
    }
    for (f = 0; f < m->face_count; f++) {
        const uint32_t *tf = m->triangles + 3u * f;
        ls_real lo[3], hi[3];
        ls_bvh_overlap it;
        int k;
        for (k = 0; k < 3; k++) {
            const ls_real *p0 = m->positions + 3u * tf[0], *p1 = m->positions + 3u * tf[1], *p2 = m->positions + 3u * tf[2];
            lo[k] = p0[k] < p1[k] ? (p0[k] < p2[k] ? p0[k] : p2[k]) : (p1[k] < p2[k] ? p1[k] : p2[k]);
            hi[k] = p0[k] > p1[k] ? (p0[k] > p2[k] ? p0[k] : p2[k]) : (p1[k] > p2[k] ? p1[k] : p2[k]);
        }
        if (ls_bvh_overlap_begin(&bvh, lo, hi, &it) != LS_OK) {
            n = -1;
            break;
        }
        while (ls_bvh_overlap_next(&it, &g)) {
            const uint32_t *tg = m->triangles + 3u * g;
            int shared = 0, i, j, hit = 0, sf = -1, sg = -1;
            if (g <= f) continue;
            for (i = 0; i < 3; i++)
                for (j = 0; j < 3; j++)
                    if (tf[i] == tg[j]) {
                        shared++;
                        sf = i;
                        sg = j;
                    }
            if (shared >= 2) continue;
            for (i = 0; i < 3 && !hit; i++) {
                if (shared == 1 && i != (sf + 1) % 3) continue; /* only the edge opposite the shared corner */
                hit = seg_tri(m->positions + 3u * tf[i], m->positions + 3u * tf[(i + 1) % 3], m->positions + 3u * tg[0],
                              m->positions + 3u * tg[1], m->positions + 3u * tg[2]);
            }
            for (i = 0; i < 3 && !hit; i++) {
                if (shared == 1 && i != (sg + 1) % 3) continue;
                hit = seg_tri(m->positions + 3u * tg[i], m->positions + 3u * tg[(i + 1) % 3], m->positions + 3u * tf[0],
                              m->positions + 3u * tf[1], m->positions + 3u * tf[2]);
            }
            n += hit;
        }
    }
    free(buf);
    return n;
}

/* The same count by src/geometry/tangle.c (ls_tangle), printed beside ours. */
static long tangle_count(const ls_mesh *m)
{
    size_t need = 0;
    unsigned char *buf;
    ls_arena a;
    ls_tangle_report t;
    long n = -1;
    if (ls_tangle_bytes(m->face_count, &need) != LS_OK) return -1;
    buf = (unsigned char *)malloc(need + 8u);
    ls_arena_init(&a, buf, need);
    if (ls_tangle(m, NULL, &a, &t, NULL) == LS_OK) n = (long)t.intersecting_pairs;
    free(buf);
    return n;
}

static double hausdorff_vertices(const ls_mesh *a, const ls_mesh *b)
{
    double x = one_sided(a, b), y = one_sided(b, a);
    return x > y ? x : y;
}

/* Runs ls_remesh in an arena of the bound; returns the status. */
typedef struct run_result {
    ls_status st;
    ls_mesh out;
    ls_remesh_info info;
    size_t bound;
    double ms;
    unsigned char *buf;
    ls_diag diag;
} run_result;

static run_result run_remesh(const ls_mesh *in, const ls_remesh_params *p)
{
    run_result r;
    ls_mesh_report rep = validate(in);
    ls_arena a;
    uint64_t t0;
    memset(&r, 0, sizeof r);
    r.st = ls_remesh_bytes_bound(in, &rep, p, &r.bound);
    if (r.st != LS_OK) return r;
    r.buf = (unsigned char *)malloc(r.bound + 8u);
    ls_arena_init(&a, r.buf, r.bound);
    t0 = ls_posix_clock_ns(NULL);
    r.st = ls_remesh(in, p, &a, &r.out, &r.info, &r.diag);
    r.ms = (double)(ls_posix_clock_ns(NULL) - t0) / 1e6;
    return r;
}

static int emulated(void) { return geo_emulated(); }

/* 1 in the sanitizer build (ASan makes the armadillo's remeshes ~10x slower). */
#if defined(__SANITIZE_ADDRESS__)
#define RM_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RM_SANITIZED 1
#endif
#endif
#ifndef RM_SANITIZED
#define RM_SANITIZED 0
#endif

/* ---- tests ----------------------------------------------------------------- */

static void mean_edge_helper(void)
{
    ls_real pos[12] = {0, 0, 0, 3, 0, 0, 0, 4, 0, 0, 0, 1};
    uint32_t tri[6] = {0, 1, 2, 0, 1, 7}; /* the second face is out of range: skipped */
    ls_mesh m;
    ls_real mean = 0;
    m.positions = pos;
    m.triangles = tri;
    m.vertex_count = 4;
    m.face_count = 2;
    CHECK_STATUS(ls_remesh_mean_edge(&m, &mean), LS_OK);
    CHECK_NEAR(mean, 4.0, TEST_EPS(8)); /* (3 + 5 + 4) / 3 */
    m.face_count = 0;
    CHECK_STATUS(ls_remesh_mean_edge(&m, &mean), LS_ERR_MESH);
    {
        heap_mesh b;
        REQUIRE(load_mesh("fixtures/meshes/bunny.obj", &b));
        CHECK_STATUS(ls_remesh_mean_edge(&b.m, &mean), LS_OK);
        CHECK_NEAR(mean, mean_edge_ref(&b.m), 1e-5 * mean_edge_ref(&b.m));
        free_mesh(&b);
    }
}

/* Remesh a closed fixture to factor x mean edge and check everything. */
static void remesh_closed(const char *path, double factor)
{
    heap_mesh in;
    ls_mesh_report ri, ro;
    ls_remesh_params p;
    run_result r;
    edge_stats s;
    ls_real mean = 0;
    double h, vol_in, vol_out, haus;
    REQUIRE(load_mesh(path, &in));
    ri = validate(&in.m);
    REQUIRE(ls_remesh_mean_edge(&in.m, &mean) == LS_OK);
    h = factor * (double)mean;
    ls_remesh_params_default(&p, (ls_real)h);
    r = run_remesh(&in.m, &p);
    CHECK_MSG(r.st == LS_OK, "%s: %s (%s)", path, ls_status_name(r.st), r.diag.what ? r.diag.what : "");
    if (r.st != LS_OK) {
        free(r.buf);
        free_mesh(&in);
        return;
    }
    ro = validate(&r.out);
    CHECK_EQ(ro.boundary_edges, 0);
    CHECK_EQ(ro.nonmanifold_edges + ro.nonmanifold_vertices + ro.orientation_conflicts, 0);
    CHECK_EQ(ro.degenerate_faces + ro.zero_area_faces + ro.duplicate_faces + ro.unreferenced_vertices, 0);
    CHECK_EQ(ro.has_genus, 1);
    CHECK_EQ(ro.genus, ri.genus);
    CHECK_EQ(ro.components, ri.components);
    s = stats_of(&r.out, h);
    CHECK_MSG(fabs(s.mean / h - 1) <= 0.10, "mean edge %.4g h", s.mean / h);
    CHECK_MSG(s.in_range >= 0.90, "%.3f of edges in [4/5 h, 4/3 h]", s.in_range);
    CHECK(r.info.bytes_used <= r.bound);
    CHECK(r.info.max_vertices <= r.info.vertex_cap);
    {
        long si = self_intersections(&in.m), so = self_intersections(&r.out);
        CHECK_MSG(si >= 0 && so >= 0 && so <= si, "self-intersecting pairs %ld in the input, %ld after", si, so);
        printf("     self-intersecting pairs: input %ld, output %ld (ls_tangle: %ld, %ld)\n", si, so, tangle_count(&in.m),
               tangle_count(&r.out));
    }
    vol_in = geo_signed_volume(&in.m);
    vol_out = geo_signed_volume(&r.out);
    haus = hausdorff_vertices(&in.m, &r.out);
    if (factor <= 0.5) {
        CHECK_MSG(fabs(vol_out / vol_in - 1) < 0.01, "volume change %.4f %%", 100 * (vol_out / vol_in - 1));
        CHECK_MSG(haus < 0.5 * h, "Hausdorff %.4g = %.3f h", haus, haus / h);
    }
    printf("     %s h=%.3g x mean: V %u -> %u, F %u; edge mean %.3f h [%.3f, %.3f] h, %.1f %% in range; "
           "angles min %.1f, 1%% %.1f, 5%% %.1f, median %.1f; volume %+.3f %%; Hausdorff %.3f h; "
           "%.1f ms; bytes %lu used / %lu bound; %u splits %u collapses %u flips\n",
           path, factor, in.m.vertex_count, r.out.vertex_count, r.out.face_count, s.mean / h, s.min / h, s.max / h,
           100 * s.in_range, s.a_min, s.a1, s.a5, s.a50, 100 * (vol_out / vol_in - 1), haus / h, r.ms,
           (unsigned long)r.info.bytes_used, (unsigned long)r.bound, r.info.splits, r.info.collapses, r.info.flips);
    free(r.buf);
    free_mesh(&in);
}

static void bunny_half(void)
{
    if (emulated()) return; /* ~0.1 s natively, seconds under QEMU; the digest pins the bits on every target */
    remesh_closed("fixtures/meshes/bunny.obj", 0.5);
}
static void bunny_double(void) { remesh_closed("fixtures/meshes/bunny.obj", 2.0); }
static void elephant_half(void)
{
    if (emulated()) return; /* as bunny_half */
    remesh_closed("fixtures/meshes/elephant.obj", 0.5);
}
static void elephant_double(void) { remesh_closed("fixtures/meshes/elephant.obj", 2.0); }
/* The armadillo (26002 V, 52000 F; gzip fixture, see fixtures/meshes/README.md)
 * only in the native optimized builds: its remesh to h = 1/2 mean edge takes
 * ~5 s natively (88k vertices), so under ASan or QEMU it would pass the time
 * limit of a test program. */
static int armadillo_skipped(void)
{
    if (!emulated() && !RM_SANITIZED) return 0;
    printf("     armadillo: not run (%s)\n", emulated() ? "emulated target" : "sanitizer build");
    return 1;
}
static void armadillo_half(void)
{
    if (!armadillo_skipped()) remesh_closed("fixtures/meshes/armadillo.obj.gz", 0.5);
}
static void armadillo_double(void)
{
    if (!armadillo_skipped()) remesh_closed("fixtures/meshes/armadillo.obj.gz", 2.0);
}

/* The gzip fixture decompresses (with ls_inflate, CRC-32 and length checked:
 * ls_posix_read_data) to the mesh the README documents; a corrupted copy is
 * refused. */
static void gzip_fixture(void)
{
    unsigned char *d = NULL, *g = NULL;
    size_t n = 0, gn = 0, start = 0, len = 0;
    uint32_t crc = 0, isize = 0;
    heap_mesh m;
    REQUIRE(geo_read_file("fixtures/meshes/armadillo.obj.gz", &d, &n));
    CHECK_EQ(n, 1675109u); /* the size of ../shared/meshes/armadillo.obj */
    CHECK(n > 20 && memcmp(d, "# from Debian libcgal-demo", 26) == 0);
    free(d);
    REQUIRE(load_mesh("fixtures/meshes/armadillo.obj.gz", &m));
    CHECK_EQ(m.m.vertex_count, 26002u);
    CHECK_EQ(m.m.face_count, 52000u);
    free_mesh(&m);
    /* a flipped bit in the deflate data or in the trailer's CRC is an error */
    REQUIRE(ls_posix_read_file("fixtures/meshes/armadillo.obj.gz", &g, &gn) == LS_OK);
    REQUIRE(ls_posix_gzip_member(g, gn, &start, &len, &crc, &isize));
    CHECK_EQ(start, 10u); /* gzip -n: no name field */
    CHECK_EQ(isize, 1675109u);
    CHECK_EQ(ls_posix_gzip_member(g, 17, &start, &len, &crc, &isize), 0);
    g[0] ^= 1u;
    CHECK_EQ(ls_posix_gzip_member(g, gn, &start, &len, &crc, &isize), 0);
    g[0] ^= 1u;
    {
        unsigned char *o = NULL;
        size_t on = 0;
        CHECK_STATUS(ls_posix_gunzip(g, gn, &o, &on), LS_OK);
        CHECK_EQ(on, 1675109u);
        free(o);
        o = NULL;
        g[gn - 6] ^= 1u; /* the trailer's CRC-32 */
        CHECK_STATUS(ls_posix_gunzip(g, gn, &o, &on), LS_ERR_PARSE);
        CHECK(o == NULL);
        g[gn - 6] ^= 1u;
        g[gn / 2] ^= 0x10u; /* the deflate data */
        CHECK(ls_posix_gunzip(g, gn, &o, &on) != LS_OK);
        CHECK(o == NULL);
        g[gn / 2] ^= 0x10u;
    }
    free(g);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y ? 1 : 0;
}

/* The half-edges (a, b) of faces whose reverse (b, a) belongs to no face,
 * as pairs in *out (malloc'd); returns their count. */
static uint32_t boundary_halfedges(const ls_mesh *m, uint32_t **out)
{
    size_t n = 3u * (size_t)m->face_count, k;
    uint64_t *keys = (uint64_t *)malloc(n * sizeof(uint64_t) + 8u);
    uint32_t count = 0, f, j;
    *out = (uint32_t *)malloc(2u * n * sizeof(uint32_t) + 8u);
    for (f = 0; f < m->face_count; f++)
        for (j = 0; j < 3; j++)
            keys[3u * f + j] = ((uint64_t)m->triangles[3u * f + j] << 32) | m->triangles[3u * f + (j + 1) % 3];
    qsort(keys, n, sizeof(uint64_t), cmp_u64);
    for (k = 0; k < n; k++) {
        uint64_t rev = (keys[k] << 32) | (keys[k] >> 32);
        if (bsearch(&rev, keys, n, sizeof(uint64_t), cmp_u64) == NULL) {
            (*out)[2u * count] = (uint32_t)(keys[k] >> 32);
            (*out)[2u * count + 1u] = (uint32_t)keys[k];
            count++;
        }
    }
    free(keys);
    return count;
}

/* A sphere with a cap cut off: one boundary loop, kept; boundary vertices of
 * the result lie on the input's boundary edges. */
static void open_mesh_keeps_boundary(void)
{
    tmesh t = icosphere(emulated() ? 2 : 3); /* smaller under QEMU */
    heap_mesh in;
    ls_mesh_report ri, ro;
    ls_remesh_params p;
    run_result r;
    uint32_t f, nf = 0;
    double h, worst = 0;
    for (f = 0; f < t.nf; f++) {
        int j, cut = 1;
        for (j = 0; j < 3; j++) cut &= t.pos[3u * t.tri[3u * f + j] + 2] > 0.5 * sqrt(t.pos[3u * t.tri[3u * f + j]] * t.pos[3u * t.tri[3u * f + j]] + t.pos[3u * t.tri[3u * f + j] + 1] * t.pos[3u * t.tri[3u * f + j] + 1] + t.pos[3u * t.tri[3u * f + j] + 2] * t.pos[3u * t.tri[3u * f + j] + 2]);
        if (!cut) {
            memmove(t.tri + 3u * nf, t.tri + 3u * f, 3u * sizeof(uint32_t));
            nf++;
        }
    }
    REQUIRE(nf < t.nf);
    t.nf = nf;
    from_tmesh(&t, &in);
    tmesh_free(&t);
    ri = validate(&in.m);
    REQUIRE(ri.boundary_loops == 1);
    h = 0.5 * mean_edge_ref(&in.m);
    ls_remesh_params_default(&p, (ls_real)h);
    r = run_remesh(&in.m, &p);
    REQUIRE(r.st == LS_OK);
    ro = validate(&r.out);
    CHECK_EQ(ro.boundary_loops, 1);
    CHECK_EQ(ro.components, 1);
    CHECK_EQ(ro.genus, ri.genus);
    CHECK_EQ(ro.nonmanifold_edges + ro.nonmanifold_vertices + ro.orientation_conflicts, 0);
    CHECK_EQ(ro.degenerate_faces + ro.zero_area_faces + ro.unreferenced_vertices, 0);
    CHECK(ro.boundary_edges >= ri.boundary_edges); /* boundary edges are split, never merged below the input's */
    /* every vertex on a boundary edge of the output lies on a boundary edge of the input */
    {
        uint32_t *bi = NULL, *bo = NULL, nbi = boundary_halfedges(&in.m, &bi), nbo = boundary_halfedges(&r.out, &bo), e, g, k;
        CHECK_EQ(nbi, ri.boundary_edges);
        CHECK_EQ(nbo, ro.boundary_edges);
        for (e = 0; e < nbo; e++) {
            for (k = 0; k < 2; k++) {
                const ls_real *pv = r.out.positions + 3u * bo[2 * e + k];
                double best = 1e300;
                for (g = 0; g < nbi; g++) {
                    const ls_real *pa = in.m.positions + 3u * bi[2 * g], *pb = in.m.positions + 3u * bi[2 * g + 1];
                    double ab[3], ap[3], t2 = 0, l2 = 0, d2 = 0;
                    int q;
                    for (q = 0; q < 3; q++) {
                        ab[q] = (double)pb[q] - pa[q];
                        ap[q] = (double)pv[q] - pa[q];
                        t2 += ab[q] * ap[q];
                        l2 += ab[q] * ab[q];
                    }
                    t2 = t2 / l2;
                    if (t2 < 0) t2 = 0;
                    if (t2 > 1) t2 = 1;
                    for (q = 0; q < 3; q++) d2 += (ap[q] - t2 * ab[q]) * (ap[q] - t2 * ab[q]);
                    if (d2 < best) best = d2;
                }
                if (best > worst) worst = best;
            }
        }
        free(bi);
        free(bo);
    }
    CHECK_MSG(sqrt(worst) < 1e3 * TEST_EPS(1), "boundary vertex %.3g off the input boundary", sqrt(worst));
    printf("     open sphere: V %u -> %u, boundary edges %u -> %u\n", in.m.vertex_count, r.out.vertex_count,
           ri.boundary_edges, ro.boundary_edges);
    free(r.buf);
    free_mesh(&in);
}

/* A planar disk given as one polygon triangulated from a corner: slivers
 * down to 3.6 degrees' spread. Splitting them along their length leaves
 * vertices whose ring is not star-shaped from its centroid; the tangential
 * relaxation must not fold faces over each other there (before, it left 162
 * self-intersecting pairs on the 100-gon, 1,106 on the 1000-gon). Every face
 * of the result faces +z; no pair intersects. */
static void polygon_fan_stays_flat(void)
{
    uint32_t sizes[2] = {100, 1000}, s;
    for (s = 0; s < (emulated() ? 1u : 2u); s++) {
        uint32_t n = sizes[s], i, folded = 0;
        size_t need = 0;
        heap_mesh in;
        ls_arena a;
        ls_remesh_params p;
        run_result r;
        ls_mesh_bytes(n, n - 2u, &need);
        in.buf = (unsigned char *)malloc(need + 8u);
        REQUIRE(in.buf != NULL);
        ls_arena_init(&a, in.buf, need);
        REQUIRE(ls_mesh_alloc(&in.m, n, n - 2u, &a) == LS_OK);
        for (i = 0; i < n; i++) {
            in.m.positions[3u * i] = (ls_real)cos(6.283185307179586 * i / n);
            in.m.positions[3u * i + 1u] = (ls_real)sin(6.283185307179586 * i / n);
            in.m.positions[3u * i + 2u] = 0;
        }
        for (i = 0; i + 2u < n; i++) {
            in.m.triangles[3u * i] = 0;
            in.m.triangles[3u * i + 1u] = i + 1u;
            in.m.triangles[3u * i + 2u] = i + 2u;
        }
        ls_remesh_params_default(&p, (ls_real)(0.5 * mean_edge_ref(&in.m)));
        r = run_remesh(&in.m, &p);
        if (r.st != LS_OK && sizeof(ls_real) < 8 && n == 1000) {
            /* in float the thinnest slivers of the 1000-gon keep no area: a named error, not a fold */
            CHECK_STATUS(r.st, LS_ERR_MESH);
            printf("     %u-gon (float): LS_ERR_MESH, a zero-area face\n", n);
            free(r.buf);
            free_mesh(&in);
            continue;
        }
        REQUIRE(r.st == LS_OK);
        for (i = 0; i < r.out.face_count; i++) {
            const ls_real *q0 = r.out.positions + 3u * r.out.triangles[3u * i],
                          *q1 = r.out.positions + 3u * r.out.triangles[3u * i + 1u],
                          *q2 = r.out.positions + 3u * r.out.triangles[3u * i + 2u];
            double nz = ((double)q1[0] - q0[0]) * ((double)q2[1] - q0[1]) - ((double)q1[1] - q0[1]) * ((double)q2[0] - q0[0]);
            folded += !(nz > 0);
        }
        printf("     %u-gon: %u faces, %u not facing +z, %ld self-intersecting pairs\n", n, r.out.face_count, folded,
               tangle_count(&r.out));
        CHECK_EQ(folded, 0);
        CHECK_EQ(tangle_count(&r.out), 0);
        free(r.buf);
        free_mesh(&in);
    }
}

/* A sphere whose vertices are pushed around until faces fold over: the
 * result is valid or a named error, never a crash or a hang. */
/* Remeshes a tangled mesh to factor x its mean edge: a valid manifold
 * result with the input's genus and components, or a named error; the input
 * is never changed. */
static void remesh_tangled(const heap_mesh *in, double factor, double label)
{
    ls_remesh_params p;
    run_result r;
    ls_mesh_report ri = validate(&in->m), ro;
    uint64_t before = test_hash_reals(in->m.positions, 3u * in->m.vertex_count, TEST_HASH_SEED);
    ls_remesh_params_default(&p, (ls_real)(factor * mean_edge_ref(&in->m)));
    r = run_remesh(&in->m, &p);
    CHECK(before == test_hash_reals(in->m.positions, 3u * in->m.vertex_count, TEST_HASH_SEED));
    if (r.st == LS_OK) {
        ro = validate(&r.out);
        CHECK_EQ(ro.nonmanifold_edges + ro.nonmanifold_vertices + ro.orientation_conflicts, 0);
        CHECK_EQ(ro.degenerate_faces + ro.zero_area_faces + ro.unreferenced_vertices, 0);
        CHECK_EQ(ro.boundary_edges, 0);
        CHECK_EQ(ro.genus, ri.genus);
        CHECK_EQ(ro.components, ri.components);
        printf("     tangled %.1f, h %.1f x mean: ok, V %u -> %u\n", label, factor, in->m.vertex_count, r.out.vertex_count);
    } else {
        CHECK(r.st == LS_ERR_MESH || r.st == LS_ERR_NOMEM);
        CHECK(r.diag.what != NULL && r.diag.what[0] != 0);
        printf("     tangled %.1f, h %.1f x mean: %s (%s)\n", label, factor, ls_status_name(r.st),
               r.diag.what ? r.diag.what : "");
    }
    free(r.buf);
}

/* What the method really remeshes: meshes from a fit's early iterations.
 * fixtures/meshes/tangled_naive_bunny_{a,b}.obj are the results of 40
 * iterations of the naive method (Adam on the vertices) from an icosphere of
 * level 3 towards the bunny (`largesteps fit --method naive --iters 40
 * --remesh none --level 3 --res 64 --views 8`, lr 0.02 and 0.05): 1387 and
 * 22532 self-intersecting face pairs. */
static void fit_tangled_fixtures(void)
{
    static const char *const files[2] = {"fixtures/meshes/tangled_naive_bunny_a.obj",
                                         "fixtures/meshes/tangled_naive_bunny_b.obj"};
    int i;
    for (i = 0; i < 2; i++) {
        heap_mesh in;
        long si;
        REQUIRE(load_mesh(files[i], &in));
        si = self_intersections(&in.m);
        printf("     %s: %u vertices, %ld self-intersecting pairs\n", files[i], in.m.vertex_count, si);
        CHECK(si > 0);
        remesh_tangled(&in, 0.5, (double)i);
        if (!emulated()) remesh_tangled(&in, 1.0, (double)i);
        free_mesh(&in);
    }
}

static void tangled_input(void)
{
    double amp;
    int trial = 0;
    for (amp = emulated() ? 0.8 : 0.2; amp <= 0.81; amp += 0.3) { /* one amplitude under QEMU */
        tmesh t = icosphere(2);
        heap_mesh in;
        uint64_t s = test_rng_seed((uint64_t)trial++);
        uint32_t i;
        double factor;
        for (i = 0; i < 3u * t.nv; i++) {
            t.pos[i] += amp * (test_rng_unit(&s) - 0.5);
        }
        from_tmesh(&t, &in);
        tmesh_free(&t);
        {
            /* the input is really tangled (and the checker can see it) */
            long si = self_intersections(&in.m);
            printf("     tangled amp %.1f: %ld self-intersecting pairs in the input\n", amp, si);
            if (amp > 0.5) CHECK(si > 0);
        }
        for (factor = 0.5; factor <= 2.0; factor *= 2) remesh_tangled(&in, factor, amp);
        free_mesh(&in);
    }
}

static void rejects_bad_input(void)
{
    ls_real pos[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    uint32_t t3[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    ls_mesh m, out;
    ls_remesh_params p;
    ls_diag d;
    static LS_ARENA_BUFFER(buf, 1 << 16); /* aligned: ls_arena_init requires it */
    ls_arena a;
    memset(&out, 0x33, sizeof out);
    m.positions = pos;
    m.triangles = t3;
    m.vertex_count = 5;
    m.face_count = 3;
    REQUIRE(ls_arena_init(&a, buf.bytes, sizeof buf.bytes) == LS_OK);
    ls_remesh_params_default(&p, (ls_real)0.5);
    CHECK_STATUS(ls_remesh(&m, &p, &a, &out, NULL, &d), LS_ERR_MESH);
    CHECK_MSG(d.what != NULL && strstr(d.what, "non-manifold") != NULL, "what = %s", d.what);
    CHECK_EQ(a.bottom + a.top, 0);
    CHECK_EQ(out.vertex_count, 0x33333333u);
    p.h = 0;
    CHECK_STATUS(ls_remesh(&m, &p, &a, &out, NULL, &d), LS_ERR_INVALID);
    CHECK_MSG(strstr(d.what, "params->h") != NULL, "what = %s", d.what);
    p.h = (ls_real)0.5;
    p.iterations = 0;
    CHECK_STATUS(ls_remesh(&m, &p, &a, &out, NULL, &d), LS_ERR_INVALID);
    CHECK_MSG(strstr(d.what, "params->iterations") != NULL, "what = %s", d.what);
    pos[3] = (ls_real)NAN;
    m.face_count = 2;
    ls_remesh_params_default(&p, (ls_real)0.5);
    CHECK_STATUS(ls_remesh(&m, &p, &a, &out, NULL, &d), LS_ERR_NONFINITE);
}

/* A capacity too small for the refinement: LS_ERR_NOMEM, nothing changed. */
static void capacity_exceeded(void)
{
    tmesh t = icosphere(1);
    heap_mesh in;
    ls_remesh_params p;
    run_result r;
    ls_mesh_report rep;
    ls_arena a;
    ls_mesh out;
    unsigned char *buf;
    size_t bound;
    from_tmesh(&t, &in);
    tmesh_free(&t);
    rep = validate(&in.m);
    ls_remesh_params_default(&p, (ls_real)(0.25 * mean_edge_ref(&in.m)));
    p.vertex_cap = in.m.vertex_count + 20u;
    REQUIRE(ls_remesh_bytes_bound(&in.m, &rep, &p, &bound) == LS_OK);
    buf = (unsigned char *)malloc(bound + 8u);
    ls_arena_init(&a, buf, bound);
    memset(&out, 0, sizeof out);
    memset(&r, 0, sizeof r);
    r.st = ls_remesh(&in.m, &p, &a, &out, &r.info, &r.diag);
    CHECK_STATUS(r.st, LS_ERR_NOMEM);
    CHECK(r.diag.what != NULL && strstr(r.diag.what, "capacity") != NULL);
    CHECK_EQ(a.bottom + a.top, 0);
    CHECK(out.positions == NULL);
    p.vertex_cap = in.m.vertex_count - 1u;
    CHECK_STATUS(ls_remesh_bytes_bound(&in.m, &rep, &p, &bound), LS_ERR_INVALID);
    CHECK_STATUS(ls_remesh(&in.m, &p, &a, &out, NULL, NULL), LS_ERR_INVALID);
    {
        ls_diag d;
        CHECK_STATUS(ls_remesh(&in.m, &p, &a, &out, NULL, &d), LS_ERR_INVALID);
        CHECK_MSG(strstr(d.what, "params->vertex_cap") != NULL, "what = %s", d.what);
    }
    free(buf);
    free_mesh(&in);
}

/* The same input twice gives the same bits. */
static void deterministic(void)
{
    tmesh t = icosphere(2);
    heap_mesh in;
    ls_remesh_params p;
    run_result r1, r2;
    from_tmesh(&t, &in);
    tmesh_free(&t);
    ls_remesh_params_default(&p, (ls_real)(0.6 * mean_edge_ref(&in.m)));
    r1 = run_remesh(&in.m, &p);
    r2 = run_remesh(&in.m, &p);
    REQUIRE(r1.st == LS_OK && r2.st == LS_OK);
    CHECK_EQ(r1.out.vertex_count, r2.out.vertex_count);
    CHECK_EQ(r1.out.face_count, r2.out.face_count);
    CHECK(test_hash_reals(r1.out.positions, 3u * r1.out.vertex_count, TEST_HASH_SEED) ==
          test_hash_reals(r2.out.positions, 3u * r2.out.vertex_count, TEST_HASH_SEED));
    CHECK(test_hash(r1.out.triangles, 12u * r1.out.face_count, TEST_HASH_SEED) ==
          test_hash(r2.out.triangles, 12u * r2.out.face_count, TEST_HASH_SEED));
    CHECK_EQ(r1.info.bytes_used, r2.info.bytes_used);
    free(r1.buf);
    free(r2.buf);
    free_mesh(&in);
}

/* ---- arena sweep ---------------------------------------------------------------- */

typedef struct sweep_ctx {
    const ls_mesh *in;
    ls_remesh_params p;
    ls_mesh out;
} sweep_ctx;

static ls_status sweep_run(void *ctx, ls_arena *arena)
{
    sweep_ctx *c = (sweep_ctx *)ctx;
    return ls_remesh(c->in, &c->p, arena, &c->out, NULL, NULL);
}

static uint64_t sweep_hash(void *ctx)
{
    sweep_ctx *c = (sweep_ctx *)ctx;
    uint64_t h = test_hash(&c->out, sizeof c->out, TEST_HASH_SEED);
    h = test_hash_reals(c->in->positions, 3u * c->in->vertex_count, h);
    return test_hash(c->in->triangles, 12u * c->in->face_count, h);
}

static void arena_sweep(void)
{
    tmesh t = icosphere(1);
    heap_mesh in;
    sweep_ctx c;
    sweep_job job;
    ls_mesh_report rep;
    from_tmesh(&t, &in);
    tmesh_free(&t);
    rep = validate(&in.m);
    memset(&c, 0, sizeof c);
    c.in = &in.m;
    ls_remesh_params_default(&c.p, (ls_real)(0.5 * mean_edge_ref(&in.m)));
    c.p.iterations = 2;
    memset(&job, 0, sizeof job);
    job.name = "remesh";
    job.run = sweep_run;
    job.state_hash = sweep_hash;
    job.ctx = &c;
    job.exact = 0;
    REQUIRE(ls_remesh_bytes_bound(&in.m, &rep, &c.p, &job.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&job), 0);
    /* without projection too */
    c.p.project = 0;
    REQUIRE(ls_remesh_bytes_bound(&in.m, &rep, &c.p, &job.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&job), 0);
    free_mesh(&in);
}

int main(void)
{
    TEST_INIT("test_remesh");
    TEST_RUN(mean_edge_helper);
    TEST_RUN(rejects_bad_input);
    TEST_RUN(bunny_half);
    TEST_RUN(bunny_double);
    TEST_RUN(elephant_half);
    TEST_RUN(elephant_double);
    TEST_RUN(gzip_fixture);
    TEST_RUN(armadillo_half);
    TEST_RUN(armadillo_double);
    TEST_RUN(open_mesh_keeps_boundary);
    TEST_RUN(polygon_fan_stays_flat);
    TEST_RUN(tangled_input);
    TEST_RUN(fit_tangled_fixtures);
    TEST_RUN(capacity_exceeded);
    TEST_RUN(deterministic);
    TEST_RUN(arena_sweep);
    return TEST_END();
}
