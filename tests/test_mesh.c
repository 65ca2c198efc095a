/* test_mesh.c - stable sort, mesh validation (against brute-force counts),
 * welding, edges, adjacency, normals, bounds, spatial reordering, and arena
 * sweeps. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <largesteps/sort.h>
#include <largesteps/mesh.h>
#include <largesteps/mesh_io.h>
#include "../port/posix/ls_posix.h"

static uint64_t rng = 0x1234567887654321ull;
static uint32_t rnd32(void)
{
    return (uint32_t)(test_rng_next(&rng) >> 16);
}

static LS_ARENA_BUFFER(big, 32u << 20);
static ls_arena arena_g;
static ls_arena *fresh_arena(void)
{
    ls_arena_init(&arena_g, big.bytes, sizeof big.bytes);
    return &arena_g;
}

/* --- sort ------------------------------------------------------------------ */

static void sort_is_stable_and_sorted(void)
{
    static const size_t sizes[] = {0, 1, 2, 3, 15, 16, 17, 31, 33, 100, 1000, 4097, 100000};
    size_t si;
    for (si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        size_t n = sizes[si], i;
        uint32_t *k32 = malloc((n + 1) * sizeof *k32), *idx = malloc((n + 1) * sizeof *idx), *tmp = malloc((n + 1) * sizeof *tmp);
        uint64_t *k64 = malloc((n + 1) * sizeof *k64);
        uint32_t *count = calloc(64, sizeof *count);
        int bad = 0;
        uint32_t mod = si % 2 ? 7u : 1000003u;
        for (i = 0; i < n; i++) {
            k32[i] = rnd32() % mod;
            k64[i] = ((uint64_t)(rnd32() % 5u) << 40) | (rnd32() % mod);
        }
        for (i = 0; i < n; i++) idx[i] = (uint32_t)i;
        CHECK_STATUS(ls_sort_u32(k32, idx, n, tmp), LS_OK);
        for (i = 1; i < n; i++) {
            if (k32[idx[i - 1]] > k32[idx[i]] || (k32[idx[i - 1]] == k32[idx[i]] && idx[i - 1] > idx[i])) bad++;
        }
        /* a permutation: every index once */
        for (i = 0; i < n; i++) tmp[i] = 0;
        for (i = 0; i < n; i++) tmp[idx[i]]++;
        for (i = 0; i < n; i++) bad += tmp[i] != 1;
        for (i = 0; i < n; i++) idx[i] = (uint32_t)(n - 1 - i); /* reversed input order: stability keeps it */
        CHECK_STATUS(ls_sort_u64(k64, idx, n, tmp), LS_OK);
        for (i = 1; i < n; i++) {
            if (k64[idx[i - 1]] > k64[idx[i]] || (k64[idx[i - 1]] == k64[idx[i]] && idx[i - 1] < idx[i])) bad++;
        }
        CHECK_MSG(bad == 0, "n = %lu: %d order violations", (unsigned long)n, bad);
        free(k32);
        free(idx);
        free(tmp);
        free(k64);
        free(count);
    }
    {
        size_t b = 0;
        CHECK_STATUS(ls_sort_scratch_bytes(10, &b), LS_OK);
        CHECK_EQ(b, 40);
        CHECK_STATUS(ls_sort_scratch_bytes(SIZE_MAX / 2, &b), LS_ERR_TOO_LARGE);
        CHECK_STATUS(ls_sort_u32(NULL, NULL, 1, NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_sort_u32(NULL, NULL, 0, NULL), LS_OK);
    }
}

/* --- small meshes ---------------------------------------------------------------- */

typedef struct small_mesh {
    ls_real p[3 * 64];
    uint32_t t[3 * 128];
    ls_mesh m;
} small_mesh;

static void sm_init(small_mesh *s, const double *p, uint32_t nv, const uint32_t *t, uint32_t nf)
{
    uint32_t i;
    for (i = 0; i < 3 * nv; i++) s->p[i] = (ls_real)p[i];
    for (i = 0; i < 3 * nf; i++) s->t[i] = t[i];
    s->m.positions = s->p;
    s->m.triangles = s->t;
    s->m.vertex_count = nv;
    s->m.face_count = nf;
}

static const double tet_p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const uint32_t tet_t[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

static ls_mesh_report validate(const ls_mesh *m)
{
    ls_mesh_report r;
    memset(&r, 0xEE, sizeof r);
    CHECK_STATUS(ls_mesh_validate(m, fresh_arena(), &r), LS_OK);
    return r;
}

static void validate_closed_shapes(void)
{
    small_mesh s;
    ls_mesh_report r;
    ls_diag d;
    sm_init(&s, tet_p, 4, tet_t, 4);
    r = validate(&s.m);
    CHECK_EQ(r.edge_count, 6);
    CHECK_EQ(r.boundary_edges, 0);
    CHECK_EQ(r.components, 1);
    CHECK_EQ(r.euler, 2);
    CHECK_EQ(r.has_genus, 1);
    CHECK_EQ(r.genus, 0);
    CHECK_EQ(r.first_boundary_edge[0], LS_MESH_NONE);
    CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_ALL, &d), LS_OK);
    /* two tetrahedra: two components */
    {
        double p2[24];
        uint32_t t2[24], i;
        for (i = 0; i < 12; i++) p2[i] = tet_p[i], p2[12 + i] = tet_p[i] + 5;
        for (i = 0; i < 12; i++) t2[i] = tet_t[i], t2[12 + i] = tet_t[i] + 4;
        sm_init(&s, p2, 8, t2, 8);
        r = validate(&s.m);
        CHECK_EQ(r.components, 2);
        CHECK_EQ(r.euler, 4);
        CHECK_EQ(r.genus, 0);
    }
    /* a torus from a 4 x 5 grid: genus 1 */
    {
        double p3[3 * 20];
        uint32_t t3[3 * 40], i, j, f = 0;
        for (i = 0; i < 4; i++)
            for (j = 0; j < 5; j++) {
                double a = 6.283185307179586 * i / 4, b = 6.283185307179586 * j / 5;
                p3[3 * (i * 5 + j)] = (3 + cos(b)) * cos(a);
                p3[3 * (i * 5 + j) + 1] = (3 + cos(b)) * sin(a);
                p3[3 * (i * 5 + j) + 2] = sin(b);
            }
        for (i = 0; i < 4; i++)
            for (j = 0; j < 5; j++) {
                uint32_t a = i * 5 + j, b = ((i + 1) % 4) * 5 + j, c = ((i + 1) % 4) * 5 + (j + 1) % 5, e = i * 5 + (j + 1) % 5;
                t3[3 * f] = a, t3[3 * f + 1] = b, t3[3 * f + 2] = c, f++;
                t3[3 * f] = a, t3[3 * f + 1] = c, t3[3 * f + 2] = e, f++;
            }
        sm_init(&s, p3, 20, t3, 40);
        r = validate(&s.m);
        CHECK_EQ(r.edge_count, 60);
        CHECK_EQ(r.euler, 0);
        CHECK_EQ(r.has_genus, 1);
        CHECK_EQ(r.genus, 1);
        CHECK_EQ(r.orientation_conflicts, 0);
    }
}

static void validate_finds_each_problem(void)
{
    small_mesh s;
    ls_mesh_report r;
    ls_diag d;
    /* open square: 4 boundary edges in one loop */
    {
        static const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 9, 9, 9};
        static const uint32_t t[] = {0, 1, 2, 0, 2, 3};
        sm_init(&s, p, 5, t, 2);
        r = validate(&s.m);
        CHECK_EQ(r.boundary_edges, 4);
        CHECK_EQ(r.boundary_loops, 1);
        CHECK_EQ(r.first_boundary_edge[0], 0);
        CHECK_EQ(r.first_boundary_edge[1], 1);
        CHECK_EQ(r.unreferenced_vertices, 1);
        CHECK_EQ(r.first_unreferenced_vertex, 4);
        CHECK_EQ(r.genus, 0);
        CHECK_EQ(r.has_genus, 1);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_MANIFOLD, &d), LS_OK);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_CLOSED, &d), LS_ERR_MESH);
        CHECK(strstr(d.what, "boundary") != NULL);
    }
    /* bow tie: two triangles sharing only vertex 0 */
    {
        static const double p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0};
        static const uint32_t t[] = {0, 1, 2, 0, 3, 4};
        sm_init(&s, p, 5, t, 2);
        r = validate(&s.m);
        CHECK_EQ(r.nonmanifold_vertices, 1);
        CHECK_EQ(r.first_nonmanifold_vertex, 0);
        CHECK_EQ(r.nonmanifold_edges, 0);
        CHECK_EQ(r.has_genus, 0);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_MANIFOLD, &d), LS_ERR_MESH);
        CHECK_EQ(d.index, 0);
    }
    /* three faces on edge (0,1); a flipped face; a duplicate; a degenerate; a bad index;
       a NaN vertex; a zero-area face */
    {
        static const double p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 2, 0, 0, 0, 0, 0};
        static const uint32_t t[] = {0, 1, 2, 1, 0, 3, 0, 1, 4, /* fin */
                                     2, 1, 0,                   /* duplicate of face 0, opposite orientation */
                                     0, 0, 1,                   /* degenerate */
                                     0, 1, 9,                   /* index out of range */
                                     0, 1, 5};                  /* collinear: zero area (finite) */
        sm_init(&s, p, 7, t, 7);
        s.p[3 * 6] = (ls_real)NAN;
        r = validate(&s.m);
        CHECK_EQ(r.nonmanifold_edges, 1);
        CHECK_EQ(r.first_nonmanifold_edge[0], 0);
        CHECK_EQ(r.first_nonmanifold_edge[1], 1);
        CHECK_EQ(r.duplicate_faces, 1);
        CHECK_EQ(r.first_duplicate_face, 3);
        CHECK_EQ(r.degenerate_faces, 1);
        CHECK_EQ(r.first_degenerate_face, 4);
        CHECK_EQ(r.bad_index_faces, 1);
        CHECK_EQ(r.first_bad_index_face, 5);
        CHECK_EQ(r.zero_area_faces, 1);
        CHECK_EQ(r.first_zero_area_face, 6);
        CHECK_EQ(r.nonfinite_vertices, 1);
        CHECK_EQ(r.first_nonfinite_vertex, 6);
        CHECK_EQ(r.unreferenced_vertices, 1);
        CHECK_EQ(r.usable_faces, 5);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_INDICES, &d), LS_ERR_MESH);
        CHECK_EQ(d.index, 5);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_FINITE, &d), LS_ERR_NONFINITE);
        CHECK_EQ(d.index, 6);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_NONDEGENERATE, &d), LS_ERR_MESH);
        CHECK_EQ(d.index, 4);
    }
    /* tetrahedron with one face flipped: orientation conflicts on its 3 edges */
    {
        static const uint32_t t[] = {0, 1, 2, 0, 1, 3, 0, 3, 2, 1, 2, 3};
        sm_init(&s, tet_p, 4, t, 4);
        r = validate(&s.m);
        CHECK_EQ(r.orientation_conflicts, 3);
        CHECK_EQ(r.has_genus, 0);
    }
    /* empty mesh */
    {
        ls_mesh e = {NULL, NULL, 0, 0};
        r = validate(&e);
        CHECK_EQ(r.components, 0);
        CHECK_EQ(r.edge_count, 0);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_NONEMPTY, &d), LS_ERR_MESH);
        CHECK_STATUS(ls_mesh_validate(NULL, fresh_arena(), &r), LS_ERR_INVALID);
    }
}

/* Brute force on random small soups: unique edges, boundary, non-manifold
 * edges, components (by repeated relaxation), unreferenced vertices. */
static void validate_matches_brute_force(void)
{
    int iter, bad = 0;
    for (iter = 0; iter < 300; iter++) {
        small_mesh s;
        uint32_t nv = 3 + rnd32() % 20, nf = 1 + rnd32() % 40, f, g, v, k;
        uint32_t eu[3 * 128][2], ec[3 * 128], ne = 0, bnd = 0, nme = 0, comp[64], comps = 0, unref = 0, degen = 0, dup = 0;
        ls_mesh_report r;
        int changed;
        for (v = 0; v < 3 * nv; v++) s.p[v] = (ls_real)(rnd32() % 7);
        for (f = 0; f < 3 * nf; f++) s.t[f] = rnd32() % nv;
        s.m.positions = s.p, s.m.triangles = s.t, s.m.vertex_count = nv, s.m.face_count = nf;
        for (v = 0; v < nv; v++) comp[v] = v;
        for (f = 0; f < nf; f++) {
            const uint32_t *t = s.t + 3 * f;
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
                degen++;
                continue;
            }
            for (g = 0; g < f; g++) {
                const uint32_t *u = s.t + 3 * g;
                int same = 1;
                if (u[0] == u[1] || u[1] == u[2] || u[0] == u[2]) continue;
                for (k = 0; k < 3; k++) same &= (t[k] == u[0] || t[k] == u[1] || t[k] == u[2]);
                if (same) {
                    dup++;
                    break;
                }
            }
            for (k = 0; k < 3; k++) {
                uint32_t a = t[k], b = t[(k + 1) % 3], lo = a < b ? a : b, hi = a < b ? b : a, e;
                for (e = 0; e < ne && !(eu[e][0] == lo && eu[e][1] == hi); e++) {
                }
                if (e == ne) eu[ne][0] = lo, eu[ne][1] = hi, ec[ne++] = 0;
                ec[e]++;
            }
        }
        for (k = 0; k < ne; k++) bnd += ec[k] == 1, nme += ec[k] > 2;
        do {
            changed = 0;
            for (k = 0; k < ne; k++) {
                uint32_t a = eu[k][0], b = eu[k][1], m = comp[a] < comp[b] ? comp[a] : comp[b];
                if (comp[a] != m || comp[b] != m) comp[a] = comp[b] = m, changed = 1;
            }
        } while (changed);
        for (v = 0; v < nv; v++) {
            int used = 0;
            for (k = 0; k < ne; k++) used |= eu[k][0] == v || eu[k][1] == v;
            if (!used) unref++;
            else if (comp[v] == v) comps++;
        }
        r = validate(&s.m);
        if (r.edge_count != ne || r.boundary_edges != bnd || r.nonmanifold_edges != nme || r.components != comps ||
            r.unreferenced_vertices != unref || r.degenerate_faces != degen || r.duplicate_faces != dup ||
            r.usable_faces != nf - degen) {
            if (bad++ < 3)
                CHECK_MSG(0, "iter %d: E %u/%u bnd %u/%u nme %u/%u comp %u/%u unref %u/%u degen %u/%u dup %u/%u", iter, r.edge_count, ne,
                          r.boundary_edges, bnd, r.nonmanifold_edges, nme, r.components, comps, r.unreferenced_vertices, unref,
                          r.degenerate_faces, degen, r.duplicate_faces, dup);
        }
    }
    CHECK_EQ(bad, 0);
}

/* --- real meshes --------------------------------------------------------------- */

static unsigned char *fixture(const char *path, size_t *n)
{
    unsigned char *d = NULL;
    if (ls_posix_read_file(path, &d, n) != LS_OK) return NULL;
    return d;
}

static int read_fixture(const char *path, ls_mesh *m, ls_arena *a)
{
    size_t n;
    unsigned char *d = fixture(path, &n);
    ls_status st;
    if (d == NULL) return 0;
    st = ls_mesh_read(d, n, LS_MESH_FORMAT_AUTO, a, m, NULL);
    free(d);
    return st == LS_OK;
}

static void fixtures_are_closed_with_known_genus(void)
{
    static const char *files[] = {"fixtures/meshes/bunny.obj", "fixtures/meshes/elephant.obj"};
    static const uint32_t nv[] = {1839, 2775}, nf[] = {3674, 5558};
    static const int32_t genus[] = {0, 3};
    int i;
    for (i = 0; i < 2; i++) {
        ls_mesh m;
        ls_mesh_report r;
        ls_arena *a = fresh_arena();
        REQUIRE(read_fixture(files[i], &m, a));
        CHECK_EQ(m.vertex_count, nv[i]);
        CHECK_EQ(m.face_count, nf[i]);
        CHECK_STATUS(ls_mesh_validate(&m, a, &r), LS_OK);
        CHECK_EQ(r.edge_count, 3 * nf[i] / 2);
        CHECK_EQ(r.boundary_edges + r.nonmanifold_edges + r.nonmanifold_vertices + r.orientation_conflicts, 0);
        CHECK_EQ(r.degenerate_faces + r.duplicate_faces + r.zero_area_faces + r.unreferenced_vertices, 0);
        CHECK_EQ(r.components, 1);
        CHECK_EQ(r.has_genus, 1);
        CHECK_EQ(r.genus, genus[i]);
        CHECK_STATUS(ls_mesh_require(&r, LS_MESH_REQ_ALL, NULL), LS_OK);
    }
}

/* --- sweeps ---------------------------------------------------------------- */

typedef struct validate_ctx {
    ls_mesh m;
    ls_mesh_report r;
} validate_ctx;

static ls_status validate_run(void *ctx, ls_arena *a)
{
    validate_ctx *c = (validate_ctx *)ctx;
    return ls_mesh_validate(&c->m, a, &c->r);
}

static uint64_t validate_hash(void *ctx)
{
    validate_ctx *c = (validate_ctx *)ctx;
    uint64_t h = test_hash(&c->r, sizeof c->r, TEST_HASH_SEED);
    h = test_hash(c->m.positions, 3 * sizeof(ls_real) * c->m.vertex_count, h);
    return test_hash(c->m.triangles, 3 * sizeof(uint32_t) * c->m.face_count, h);
}

typedef struct edges_ctx {
    ls_mesh m;
    ls_mesh_edges e;
    ls_mesh_adjacency adj;
    int which; /* 0 edges, 1 adjacency, 2 weld */
    ls_real *pcopy;
    uint32_t *tcopy;
} edges_ctx;

static ls_status edges_run(void *ctx, ls_arena *a)
{
    edges_ctx *c = (edges_ctx *)ctx;
    if (c->which == 0) return ls_mesh_edges_build(&c->m, a, &c->e, NULL);
    if (c->which == 1) return ls_mesh_adjacency_build(&c->e, c->m.vertex_count, a, &c->adj);
    return ls_mesh_weld(&c->m, a, NULL, NULL);
}

static uint64_t edges_hash(void *ctx)
{
    edges_ctx *c = (edges_ctx *)ctx;
    uint64_t h = test_hash(&c->m, sizeof c->m, TEST_HASH_SEED);
    h = test_hash(c->m.positions, 3 * sizeof(ls_real) * c->m.vertex_count, h);
    h = test_hash(c->m.triangles, 3 * sizeof(uint32_t) * c->m.face_count, h);
    if (c->which == 0) h = test_hash(&c->e, sizeof c->e, h);
    if (c->which == 1) h = test_hash(&c->adj, sizeof c->adj, h);
    return h;
}

static void edges_reset(void *ctx)
{
    edges_ctx *c = (edges_ctx *)ctx;
    if (c->which == 2) {
        /* undo the weld */
        c->m.vertex_count = 36;
        memcpy(c->m.positions, c->pcopy, 36 * 3 * sizeof(ls_real));
        memcpy(c->m.triangles, c->tcopy, 12 * 3 * sizeof(uint32_t));
    }
    memset(&c->e, 0, sizeof c->e);
    memset(&c->adj, 0, sizeof c->adj);
}

static void sweeps_validate_edges_adjacency(void)
{
    ls_mesh m;
    ls_mesh_report r;
    ls_arena *a = fresh_arena();
    validate_ctx vc;
    edges_ctx ec;
    sweep_job job;
    size_t bytes = 0;
    ls_mesh_edges e0;
    REQUIRE(read_fixture("fixtures/meshes/bunny.obj", &m, a));
    REQUIRE(ls_mesh_validate(&m, a, &r) == LS_OK);
    vc.m = m;
    memset(&vc.r, 0, sizeof vc.r);
    CHECK_STATUS(ls_mesh_validate_bytes(&m, &bytes), LS_OK);
    memset(&job, 0, sizeof job);
    job.name = "mesh_validate";
    job.run = validate_run;
    job.state_hash = validate_hash;
    job.ctx = &vc;
    job.answer = bytes;
    job.exact = 1;
    CHECK_EQ(sweep_arena(&job), 0);
    CHECK(memcmp(&vc.r, &r, sizeof r) == 0);

    memset(&ec, 0, sizeof ec);
    ec.m = m;
    CHECK_STATUS(ls_mesh_edges_bytes(m.face_count, r.edge_count, &bytes), LS_OK);
    job.name = "mesh_edges";
    job.run = edges_run;
    job.state_hash = edges_hash;
    job.reset = edges_reset;
    job.ctx = &ec;
    job.answer = bytes;
    CHECK_EQ(sweep_arena(&job), 0);
    /* keep a built edge list for the adjacency sweep (in the big arena) */
    CHECK_STATUS(ls_mesh_edges_build(&m, a, &e0, NULL), LS_OK);
    CHECK_EQ(e0.count, r.edge_count);
    ec.e = e0;
    ec.which = 1;
    CHECK_STATUS(ls_mesh_adjacency_bytes(m.vertex_count, e0.count, &bytes), LS_OK);
    job.name = "mesh_adjacency";
    job.answer = bytes;
    job.reset = NULL;
    CHECK_EQ(sweep_arena(&job), 0);
}

/* --- edges and adjacency against brute force ------------------------------------ */

static void edges_and_adjacency_are_sorted_and_complete(void)
{
    ls_mesh m;
    ls_mesh_report r;
    ls_mesh_edges e;
    ls_mesh_adjacency adj;
    ls_arena *a = fresh_arena();
    uint32_t i, f, k, bad = 0;
    ls_diag d;
    REQUIRE(read_fixture("fixtures/meshes/elephant.obj", &m, a));
    REQUIRE(ls_mesh_validate(&m, a, &r) == LS_OK);
    CHECK_STATUS(ls_mesh_edges_build(&m, a, &e, NULL), LS_OK);
    CHECK_EQ(e.count, r.edge_count);
    for (i = 0; i < e.count; i++) {
        if (e.v[2 * i] >= e.v[2 * i + 1]) bad++;
        if (i > 0 && (e.v[2 * i - 2] > e.v[2 * i] || (e.v[2 * i - 2] == e.v[2 * i] && e.v[2 * i - 1] >= e.v[2 * i + 1]))) bad++;
    }
    CHECK_EQ(bad, 0);
    CHECK_STATUS(ls_mesh_adjacency_build(&e, m.vertex_count, a, &adj), LS_OK);
    CHECK_EQ(adj.offsets[0], 0);
    CHECK_EQ(adj.offsets[m.vertex_count], 2 * e.count);
    /* every face edge is in both rows, rows strictly increasing */
    for (f = 0; f < m.face_count; f++) {
        for (k = 0; k < 3; k++) {
            uint32_t a0 = m.triangles[3 * f + k], b0 = m.triangles[3 * f + (k + 1) % 3], j, found = 0;
            for (j = adj.offsets[a0]; j < adj.offsets[a0 + 1]; j++) found += adj.neighbors[j] == b0;
            for (j = adj.offsets[b0]; j < adj.offsets[b0 + 1]; j++) found += adj.neighbors[j] == a0;
            if (found != 2) bad++;
        }
    }
    for (i = 0; i < m.vertex_count; i++) {
        uint32_t j;
        for (j = adj.offsets[i] + 1; j < adj.offsets[i + 1]; j++) bad += adj.neighbors[j - 1] >= adj.neighbors[j];
    }
    CHECK_EQ(bad, 0);
    /* bad index */
    m.triangles[7] = m.vertex_count;
    CHECK_STATUS(ls_mesh_edges_build(&m, a, &e, &d), LS_ERR_MESH);
    CHECK_EQ(d.index, 2);
    CHECK_STATUS(ls_mesh_face_normals(&m, NULL, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "out is NULL") != NULL);
    CHECK_STATUS(ls_mesh_edges_build(NULL, a, &e, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "mesh is NULL") == 0);
    CHECK_STATUS(ls_mesh_edges_build(&m, a, NULL, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "edges is NULL") == 0);
    CHECK_STATUS(ls_mesh_require(NULL, LS_MESH_REQ_ALL, &d), LS_ERR_INVALID);
    CHECK(strcmp(d.what, "r is NULL") == 0);
}

/* --- welding ----------------------------------------------------------------------- */

static void weld_merges_exact_duplicates_only(void)
{
    /* a cube split per face corner: 36 vertices, 8 positions */
    static ls_real p[36 * 3], pcopy[36 * 3];
    static uint32_t t[36], tcopy[36];
    static const int cube[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    ls_mesh m;
    ls_mesh_report r;
    uint32_t remap[36], removed = 0, i, k;
    edges_ctx ec;
    sweep_job job;
    size_t bytes;
    for (i = 0; i < 12; i++)
        for (k = 0; k < 3; k++) {
            int c = cube[i][k];
            p[3 * (3 * i + k)] = (ls_real)((c == 1 || c == 2 || c == 5 || c == 6) ? 1 : 0);
            p[3 * (3 * i + k) + 1] = (ls_real)((c == 2 || c == 3 || c == 6 || c == 7) ? 1 : 0);
            p[3 * (3 * i + k) + 2] = (ls_real)(c >= 4 ? 1 : 0);
            t[3 * i + k] = 3 * i + k;
        }
    p[3 * 1 + 2] = -p[3 * 1 + 2]; /* vertex 1 is cube corner 2, z = 0: -0 must equal +0 */
    m.positions = p, m.triangles = t, m.vertex_count = 36, m.face_count = 12;
    memcpy(pcopy, p, sizeof p);
    memcpy(tcopy, t, sizeof t);
    r = validate(&m);
    CHECK_EQ(r.components, 12);
    CHECK_STATUS(ls_mesh_weld(&m, fresh_arena(), remap, &removed), LS_OK);
    CHECK_EQ(m.vertex_count, 8);
    CHECK_EQ(removed, 28);
    CHECK_EQ(remap[0], 0);
    for (i = 0; i < 36; i++) {
        /* kept vertices in order of first appearance, and positions preserved */
        CHECK(p[3 * remap[i]] == pcopy[3 * i] && p[3 * remap[i] + 1] == pcopy[3 * i + 1] && p[3 * remap[i] + 2] == pcopy[3 * i + 2]);
    }
    r = validate(&m);
    CHECK_EQ(r.components, 1);
    CHECK_EQ(r.has_genus, 1);
    CHECK_EQ(r.genus, 0);
    CHECK_EQ(r.boundary_edges, 0);
    /* NaN positions never merge */
    memcpy(p, pcopy, sizeof p);
    memcpy(t, tcopy, sizeof t);
    m.vertex_count = 36;
    for (i = 0; i < 36; i++) p[3 * i] = (ls_real)NAN;
    CHECK_STATUS(ls_mesh_weld(&m, fresh_arena(), NULL, &removed), LS_OK);
    CHECK_EQ(removed, 0);
    CHECK_EQ(m.vertex_count, 36);
    /* sweep */
    memcpy(p, pcopy, sizeof p);
    memcpy(t, tcopy, sizeof t);
    m.vertex_count = 36;
    memset(&ec, 0, sizeof ec);
    ec.m = m;
    ec.which = 2;
    ec.pcopy = pcopy;
    ec.tcopy = tcopy;
    CHECK_STATUS(ls_mesh_weld_bytes(&m, &bytes), LS_OK);
    memset(&job, 0, sizeof job);
    job.name = "mesh_weld";
    job.run = edges_run;
    job.state_hash = edges_hash;
    job.reset = edges_reset;
    job.ctx = &ec;
    job.answer = bytes;
    job.exact = 1;
    CHECK_EQ(sweep_arena(&job), 0);
    /* a bad index: nothing changes */
    t[4] = 99;
    m.vertex_count = 36;
    CHECK_STATUS(ls_mesh_weld(&m, fresh_arena(), NULL, NULL), LS_ERR_MESH);
    CHECK_EQ(m.vertex_count, 36);
}

/* --- unwelding --------------------------------------------------------------------- */

static void unweld_gives_each_face_its_vertices(void)
{
    static unsigned char mem[4096];
    small_mesh s;
    ls_mesh u;
    ls_arena a;
    ls_diag d;
    ls_real vn[3 * 12];
    size_t bytes = 0;
    uint32_t f, k, i, removed = 0;
    sm_init(&s, tet_p, 4, tet_t, 4);
    CHECK_STATUS(ls_mesh_unweld_bytes(4, &bytes), LS_OK);
    CHECK_EQ(bytes, 12 * 3 * sizeof(ls_real) + 4 * 3 * sizeof(uint32_t));
    /* exactly the bytes it says: one fewer fails and leaves the arena as it was */
    CHECK_STATUS(ls_arena_init(&a, mem, bytes), LS_OK);
    CHECK_STATUS(ls_mesh_unweld(&s.m, &a, &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 12);
    CHECK_EQ(u.face_count, 4);
    CHECK_STATUS(ls_arena_init(&a, mem, bytes - 1), LS_OK);
    CHECK_STATUS(ls_mesh_unweld(&s.m, &a, &u, NULL), LS_ERR_NOMEM);
    CHECK_EQ(a.bottom, 0);
    CHECK_STATUS(ls_mesh_unweld(&s.m, fresh_arena(), &u, NULL), LS_OK);
    for (f = 0; f < 4; f++)
        for (k = 0; k < 3; k++) {
            CHECK_EQ(u.triangles[3 * f + k], 3 * f + k);
            for (i = 0; i < 3; i++) CHECK(u.positions[3 * (3 * f + k) + i] == (ls_real)tet_p[3 * tet_t[3 * f + k] + i]);
        }
    /* every vertex normal of the result is its face's normal, by an independent double cross product */
    CHECK_STATUS(ls_mesh_vertex_normals(&u, LS_NORMALS_UNIFORM, vn, NULL), LS_OK);
    for (f = 0; f < 4; f++) {
        const double *a0 = tet_p + 3 * tet_t[3 * f], *b = tet_p + 3 * tet_t[3 * f + 1], *c = tet_p + 3 * tet_t[3 * f + 2];
        double e1[3], e2[3], x[3], len;
        for (i = 0; i < 3; i++) e1[i] = b[i] - a0[i], e2[i] = c[i] - a0[i];
        x[0] = e1[1] * e2[2] - e1[2] * e2[1], x[1] = e1[2] * e2[0] - e1[0] * e2[2], x[2] = e1[0] * e2[1] - e1[1] * e2[0];
        len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        for (k = 0; k < 3; k++)
            for (i = 0; i < 3; i++) CHECK_NEAR(vn[3 * (3 * f + k) + i], x[i] / len, TEST_EPS(4));
    }
    /* welding it back gives the four vertices again */
    CHECK_STATUS(ls_mesh_weld(&u, fresh_arena(), NULL, &removed), LS_OK);
    CHECK_EQ(u.vertex_count, 4);
    CHECK_EQ(removed, 8);
    /* an index out of range is named */
    s.t[7] = 9;
    ls_diag_clear(&d);
    CHECK_STATUS(ls_mesh_unweld(&s.m, fresh_arena(), &u, &d), LS_ERR_MESH);
    CHECK_EQ(d.index, 2);
    CHECK_STATUS(ls_mesh_unweld(NULL, fresh_arena(), &u, NULL), LS_ERR_INVALID);
}

/* --- splitting at creases ----------------------------------------------------------- */

/* The result's vertex normals against each face's own normal (independent
 * double cross products): 1 when every corner of every face whose vertex
 * normal should be its face's (all of them, for a mesh split at every crease)
 * matches, and each corner sits where the input's corner was. */
static int split_shows_face_normals(const small_mesh *s, const ls_mesh *u)
{
    ls_real vn[3 * 64];
    uint32_t f, k, i;
    if (ls_mesh_vertex_normals(u, LS_NORMALS_UNIFORM, vn, NULL) != LS_OK) return 0;
    for (f = 0; f < s->m.face_count; f++) {
        const ls_real *a0 = s->p + 3 * s->t[3 * f], *b = s->p + 3 * s->t[3 * f + 1], *c = s->p + 3 * s->t[3 * f + 2];
        double e1[3], e2[3], x[3], len;
        for (i = 0; i < 3; i++) e1[i] = (double)b[i] - (double)a0[i], e2[i] = (double)c[i] - (double)a0[i];
        x[0] = e1[1] * e2[2] - e1[2] * e2[1], x[1] = e1[2] * e2[0] - e1[0] * e2[2], x[2] = e1[0] * e2[1] - e1[1] * e2[0];
        len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        for (k = 0; k < 3; k++)
            for (i = 0; i < 3; i++) {
                const uint32_t v = u->triangles[3 * f + k];
                if (fabs((double)vn[3 * v + i] - x[i] / len) > 1e-5) return 0;
                if (u->positions[3 * v + i] != s->p[3 * s->t[3 * f + k] + i]) return 0;
            }
    }
    return 1;
}

static void creases_split_and_counted(void)
{
    static const double cube_p[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    static const uint32_t cube_t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                      1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
    /* two triangles on the edge 0-1, their normals 30 degrees apart; open */
    static const double hinge_p[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -0.8660254037844386, 0.5};
    static const uint32_t hinge_t[] = {0, 1, 2, 1, 0, 3};
    static unsigned char mem[8192];
    const ls_real cos45 = (ls_real)0.70710678118654752, cos100 = (ls_real)-0.17364817766693035;
    small_mesh s;
    ls_mesh u;
    ls_arena a;
    ls_diag d;
    size_t bytes = 0, mesh_bytes = 0;
    uint32_t i;

    uint32_t creases = 0, edges = 0;

    /* a cube at 45 degrees: each corner on its three sides, 24 vertices shaded flat */
    sm_init(&s, cube_p, 8, cube_t, 12);
    /* its 18 edges: the 12 of the cube, and 6 diagonals between coplanar faces */
    CHECK_STATUS(ls_mesh_count_creases(&s.m, cos45, fresh_arena(), &creases, &edges, NULL), LS_OK);
    CHECK_EQ(edges, 18);
    CHECK_EQ(creases, 12);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, cos45, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 24);
    CHECK_EQ(u.face_count, 12);
    CHECK(split_shows_face_normals(&s, &u));
    /* at 180 degrees nothing splits: the same mesh, index for index */
    CHECK_STATUS(ls_mesh_split_creases(&s.m, -1, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 8);
    for (i = 0; i < 36; i++) CHECK_EQ(u.triangles[i], cube_t[i]);
    for (i = 0; i < 24; i++) CHECK(u.positions[i] == s.p[i]);

    /* the tetrahedron: its three faces at the origin meet at 90 degrees, the
     * slanted face meets them at 125.3; at 100 the origin stays one vertex,
     * each other corner splits in two (the slanted face's sheet is new) */
    sm_init(&s, tet_p, 4, tet_t, 4);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, cos100, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 7);
    CHECK_STATUS(ls_mesh_count_creases(&s.m, cos100, fresh_arena(), &creases, &edges, NULL), LS_OK);
    CHECK_EQ(edges, 6);
    CHECK_EQ(creases, 3);
    for (i = 0; i < 9; i++) CHECK_EQ(u.triangles[i], tet_t[i]); /* the first sheets keep their indices */
    CHECK(u.triangles[9] >= 4 && u.triangles[10] >= 4 && u.triangles[11] >= 4);
    CHECK(!split_shows_face_normals(&s, &u)); /* the axis faces share averaged normals */
    CHECK(u.triangles[9] != u.triangles[10] && u.triangles[10] != u.triangles[11]);
    /* at 45 degrees every edge is a crease: 12 vertices, flat as ls_mesh_unweld shows it */
    CHECK_STATUS(ls_mesh_split_creases(&s.m, cos45, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 12);
    CHECK(split_shows_face_normals(&s, &u));

    /* the hinge: 30 degrees apart; joined at 45, split at 25; its boundary edges split nothing */
    sm_init(&s, hinge_p, 4, hinge_t, 2);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, cos45, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 4);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, (ls_real)0.90630778703665, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 6);
    CHECK(split_shows_face_normals(&s, &u));
    CHECK_STATUS(ls_mesh_count_creases(&s.m, (ls_real)0.90630778703665, fresh_arena(), &creases, &edges, NULL), LS_OK);
    CHECK_EQ(edges, 1); /* the four boundary edges are not counted */
    CHECK_EQ(creases, 1);
    /* faces that disagree on orientation do not share their vertices */
    s.t[3] = 0, s.t[4] = 1;
    CHECK_STATUS(ls_mesh_split_creases(&s.m, -1, fresh_arena(), &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 6);

    /* the bytes it says are enough for the most vertices a split can make;
     * without room for the result it fails and leaves the arena as it was */
    sm_init(&s, tet_p, 4, tet_t, 4);
    CHECK_STATUS(ls_mesh_split_creases_bytes(4, 4, &bytes), LS_OK);
    CHECK_STATUS(ls_mesh_bytes(16, 4, &mesh_bytes), LS_OK);
    CHECK(bytes > mesh_bytes && bytes <= sizeof mem);
    CHECK_STATUS(ls_arena_init(&a, mem, bytes), LS_OK);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, cos45, &a, &u, NULL), LS_OK);
    CHECK_EQ(u.vertex_count, 12);
    CHECK_STATUS(ls_arena_init(&a, mem, bytes - mesh_bytes), LS_OK);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, cos45, &a, &u, NULL), LS_ERR_NOMEM);
    CHECK_EQ(a.bottom, 0);
    CHECK_EQ(a.top, 0);
    CHECK_STATUS(ls_mesh_split_creases_bytes(UINT32_MAX, 1, &bytes), LS_ERR_TOO_LARGE);
    /* counting takes exactly its scratch, and gives it back */
    CHECK_STATUS(ls_mesh_count_creases_bytes(4, &bytes), LS_OK);
    CHECK_STATUS(ls_arena_init(&a, mem, bytes), LS_OK);
    CHECK_STATUS(ls_mesh_count_creases(&s.m, cos45, &a, &creases, &edges, NULL), LS_OK);
    CHECK_EQ(creases, 6);
    CHECK_EQ(a.bottom + a.top, 0);
    CHECK_STATUS(ls_arena_init(&a, mem, bytes - 1), LS_OK);
    CHECK_STATUS(ls_mesh_count_creases(&s.m, cos45, &a, &creases, &edges, NULL), LS_ERR_NOMEM);
    CHECK_EQ(a.bottom + a.top, 0);

    /* bad arguments and an index out of range are named */
    CHECK_STATUS(ls_mesh_split_creases(&s.m, (ls_real)1.5, fresh_arena(), &u, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_mesh_split_creases(NULL, 0, fresh_arena(), &u, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_mesh_count_creases(&s.m, 0, fresh_arena(), NULL, &edges, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_mesh_count_creases(&s.m, 0, NULL, &creases, &edges, NULL), LS_ERR_INVALID);
    s.t[7] = 9;
    ls_diag_clear(&d);
    CHECK_STATUS(ls_mesh_split_creases(&s.m, 0, fresh_arena(), &u, &d), LS_ERR_MESH);
    CHECK_EQ(d.index, 2);
}

/* --- normals ------------------------------------------------------------------------ */

static void face_and_vertex_normals(void)
{
    small_mesh s;
    ls_real fn[3 * 8], vn[3 * 8];
    uint32_t w, i;
    ls_diag d;
    sm_init(&s, tet_p, 4, tet_t, 4);
    CHECK_STATUS(ls_mesh_face_normals(&s.m, fn, NULL), LS_OK);
    /* face 0 (0,2,1) lies in z = 0 facing -z; face 3 (1,2,3) faces (1,1,1)/sqrt3 */
    CHECK_NEAR(fn[0], 0, 0);
    CHECK_NEAR(fn[1], 0, 0);
    CHECK_NEAR(fn[2], -1, 0);
    CHECK_NEAR(fn[9], 1 / sqrt(3.0), TEST_EPS(4));
    CHECK_NEAR(fn[10], 1 / sqrt(3.0), TEST_EPS(4));
    /* vertex 0 of the tetrahedron: uniform = (-1,-1,-1)/sqrt3; vertex 1 differs by weighting */
    for (w = 0; w < 3; w++) {
        CHECK_STATUS(ls_mesh_vertex_normals(&s.m, w, vn, NULL), LS_OK);
        CHECK_NEAR(vn[0], -1 / sqrt(3.0), TEST_EPS(8));
        CHECK_NEAR(vn[2], -1 / sqrt(3.0), TEST_EPS(8));
    }
    /* an independent double computation of all three weightings on vertex 1 */
    {
        double acc[3][3] = {{0}}, f;
        uint32_t k;
        for (f = 0; f < 4; f++) {
            const uint32_t *t = tet_t + 3 * (int)f;
            for (k = 0; k < 3; k++) {
                const double *a, *b, *c;
                double u[3], v[3], x[3], len, ang;
                if (t[k] != 1) continue;
                a = tet_p + 3 * t[k], b = tet_p + 3 * t[(k + 1) % 3], c = tet_p + 3 * t[(k + 2) % 3];
                for (i = 0; i < 3; i++) u[i] = b[i] - a[i], v[i] = c[i] - a[i];
                x[0] = u[1] * v[2] - u[2] * v[1], x[1] = u[2] * v[0] - u[0] * v[2], x[2] = u[0] * v[1] - u[1] * v[0];
                len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
                ang = atan2(len, u[0] * v[0] + u[1] * v[1] + u[2] * v[2]);
                for (i = 0; i < 3; i++) acc[0][i] += x[i] / len, acc[1][i] += x[i], acc[2][i] += ang * x[i] / len;
            }
        }
        for (w = 0; w < 3; w++) {
            double len = sqrt(acc[w][0] * acc[w][0] + acc[w][1] * acc[w][1] + acc[w][2] * acc[w][2]);
            CHECK_STATUS(ls_mesh_vertex_normals(&s.m, w, vn, NULL), LS_OK);
            for (i = 0; i < 3; i++) CHECK_NEAR(vn[3 + i], acc[w][i] / len, TEST_EPS(16));
        }
        CHECK(fabs(acc[0][0] / sqrt(acc[0][0] * acc[0][0] + acc[0][1] * acc[0][1] + acc[0][2] * acc[0][2]) -
                   acc[2][0] / sqrt(acc[2][0] * acc[2][0] + acc[2][1] * acc[2][1] + acc[2][2] * acc[2][2])) > 1e-3);
    }
    /* zero-area faces and unreferenced vertices: zeros, never NaN */
    {
        static const double p[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 5, 5, 5};
        static const uint32_t t[] = {0, 1, 2, 0, 0, 1};
        sm_init(&s, p, 4, t, 2);
        CHECK_STATUS(ls_mesh_face_normals(&s.m, fn, NULL), LS_OK);
        for (i = 0; i < 6; i++) CHECK(fn[i] == 0);
        for (w = 0; w < 3; w++) {
            CHECK_STATUS(ls_mesh_vertex_normals(&s.m, w, vn, NULL), LS_OK);
            for (i = 0; i < 12; i++) CHECK(vn[i] == 0);
        }
        /* tiny and huge faces normalise without underflow or overflow */
        s.p[3] = (ls_real)1e-30, s.p[7] = (ls_real)1e-30;
        s.p[6] = 0;
        CHECK_STATUS(ls_mesh_face_normals(&s.m, fn, NULL), LS_OK);
        CHECK_NEAR(fn[2], 1, TEST_EPS(2));
        s.p[3] = (ls_real)1e30, s.p[7] = (ls_real)1e30;
        CHECK_STATUS(ls_mesh_face_normals(&s.m, fn, NULL), LS_OK);
        CHECK_NEAR(fn[2], 1, TEST_EPS(2));
        CHECK_STATUS(ls_mesh_vertex_normals(&s.m, 3, vn, NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_mesh_vertex_normals(&s.m, 3, vn, &d), LS_ERR_INVALID);
        CHECK(strstr(d.what, "weighting") != NULL);
        s.t[5] = 4;
        memset(vn, 0x5A, sizeof vn);
        CHECK_STATUS(ls_mesh_vertex_normals(&s.m, 0, vn, &d), LS_ERR_MESH);
        CHECK_EQ(d.index, 1);
        CHECK_EQ(((unsigned char *)vn)[0], 0x5A);
    }
}

static void bunny_vertex_normals_point_outward(void)
{
    ls_mesh m;
    ls_arena *a = fresh_arena();
    ls_real *vn, lo[3], hi[3];
    uint32_t v, w, out_count;
    double c[3], meanlen;
    REQUIRE(read_fixture("fixtures/meshes/bunny.obj", &m, a));
    vn = malloc(3 * sizeof(ls_real) * m.vertex_count);
    CHECK_STATUS(ls_mesh_bounds(&m, lo, hi), LS_OK);
    CHECK_NEAR(sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2])), 15.757, 1e-3);
    for (v = 0; v < 3; v++) c[v] = 0.5 * (lo[v] + hi[v]);
    for (w = 0; w < 3; w++) {
        CHECK_STATUS(ls_mesh_vertex_normals(&m, w, vn, NULL), LS_OK);
        out_count = 0;
        meanlen = 0;
        for (v = 0; v < m.vertex_count; v++) {
            const ls_real *p = m.positions + 3 * v, *n = vn + 3 * v;
            out_count += (p[0] - c[0]) * n[0] + (p[1] - c[1]) * n[1] + (p[2] - c[2]) * n[2] > 0;
            meanlen += sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        }
        CHECK_MSG(out_count > m.vertex_count * 8 / 10, "weighting %u: %u of %u normals point away from the centre", w, out_count, m.vertex_count);
        CHECK_NEAR(meanlen / m.vertex_count, 1, TEST_EPS(8));
    }
    free(vn);
    {
        ls_mesh e = {NULL, NULL, 0, 0};
        CHECK_STATUS(ls_mesh_bounds(&e, lo, hi), LS_ERR_MESH);
    }
}

/* --- spatial order ----------------------------------------------------------- */

typedef struct reorder_ctx {
    ls_mesh m;
    ls_real *p0;
    uint32_t *t0;
} reorder_ctx;

static ls_status reorder_run(void *ctx, ls_arena *a)
{
    return ls_mesh_reorder(&((reorder_ctx *)ctx)->m, a, NULL);
}

static uint64_t reorder_hash(void *ctx)
{
    reorder_ctx *c = (reorder_ctx *)ctx;
    uint64_t h = test_hash(c->m.positions, 3 * sizeof(ls_real) * c->m.vertex_count, TEST_HASH_SEED);
    return test_hash(c->m.triangles, 3 * sizeof(uint32_t) * c->m.face_count, h);
}

static void reorder_reset(void *ctx)
{
    reorder_ctx *c = (reorder_ctx *)ctx;
    memcpy(c->m.positions, c->p0, 3 * sizeof(ls_real) * c->m.vertex_count);
    memcpy(c->m.triangles, c->t0, 3 * sizeof(uint32_t) * c->m.face_count);
}

/* Mean over faces of (largest - smallest vertex index): how far apart a
 * face's vertices are in memory. */
static double index_spread(const ls_mesh *m)
{
    double s = 0;
    uint32_t f;
    for (f = 0; f < m->face_count; f++) {
        const uint32_t *t = m->triangles + 3 * f;
        uint32_t lo = t[0] < t[1] ? t[0] : t[1], hi = t[0] < t[1] ? t[1] : t[0];
        lo = t[2] < lo ? t[2] : lo;
        hi = t[2] > hi ? t[2] : hi;
        s += hi - lo;
    }
    return s / m->face_count;
}

/* Mean distance between consecutive faces' centroids over the box diagonal. */
static double centroid_walk(const ls_mesh *m)
{
    double s = 0, prev[3] = {0, 0, 0}, d2 = 0;
    ls_real lo[3], hi[3];
    uint32_t f;
    int k;
    (void)ls_mesh_bounds(m, lo, hi);
    for (k = 0; k < 3; k++) d2 += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
    for (f = 0; f < m->face_count; f++) {
        double c[3], e = 0;
        for (k = 0; k < 3; k++) {
            c[k] = ((double)m->positions[3 * m->triangles[3 * f] + k] + m->positions[3 * m->triangles[3 * f + 1] + k] +
                    m->positions[3 * m->triangles[3 * f + 2] + k]) / 3;
            e += (c[k] - prev[k]) * (c[k] - prev[k]);
            prev[k] = c[k];
        }
        if (f > 0) s += sqrt(e);
    }
    return s / (m->face_count - 1) / sqrt(d2);
}

/* The bunny in a shuffled order (faces and vertices), reordered: the same
 * faces (corners in their order) over the same points, vertices numbered by
 * first use, and near each other in memory and along the face order; the
 * same bits twice; errors and the arena sweep leave the mesh unchanged. */
static void reorder_is_a_spatial_permutation(void)
{
    ls_mesh m, s;
    ls_arena *a = fresh_arena();
    uint32_t *perm, *remap, *seen, nv, nf, i, v, f, next = 0;
    uint64_t *ka, *kb;
    reorder_ctx rc;
    sweep_job job;
    size_t bytes = 0;
    double spread0, spread1, walk0, walk1;
    REQUIRE(read_fixture("fixtures/meshes/bunny.obj", &m, a));
    nv = m.vertex_count;
    nf = m.face_count;
    perm = malloc(sizeof(uint32_t) * nv);
    remap = malloc(sizeof(uint32_t) * nv);
    seen = calloc(nv, sizeof(uint32_t));
    ka = malloc(sizeof(uint64_t) * nf);
    kb = malloc(sizeof(uint64_t) * nf);
    REQUIRE(ls_mesh_alloc(&s, nv, nf, a) == LS_OK);
    /* shuffle: vertex v moves to perm[v]; faces in a random order */
    for (v = 0; v < nv; v++) perm[v] = v;
    for (v = nv - 1; v > 0; v--) {
        uint32_t j = rnd32() % (v + 1), t = perm[v];
        perm[v] = perm[j];
        perm[j] = t;
    }
    for (v = 0; v < nv; v++) memcpy(s.positions + 3 * perm[v], m.positions + 3 * v, 3 * sizeof(ls_real));
    for (f = 0; f < nf; f++)
        for (i = 0; i < 3; i++) s.triangles[3 * f + i] = perm[m.triangles[3 * f + i]];
    for (f = nf - 1; f > 0; f--) {
        uint32_t j = rnd32() % (f + 1), t[3];
        memcpy(t, s.triangles + 3 * f, sizeof t);
        memcpy(s.triangles + 3 * f, s.triangles + 3 * j, sizeof t);
        memcpy(s.triangles + 3 * j, t, sizeof t);
    }
    m = s; /* the shuffled mesh is the input from here on */
    REQUIRE(ls_mesh_alloc(&s, nv, nf, a) == LS_OK);
    memcpy(s.positions, m.positions, 3 * sizeof(ls_real) * nv);
    memcpy(s.triangles, m.triangles, 3 * sizeof(uint32_t) * nf);
    spread0 = index_spread(&s);
    walk0 = centroid_walk(&s);
    CHECK_STATUS(ls_mesh_reorder(&s, a, remap), LS_OK);
    spread1 = index_spread(&s);
    walk1 = centroid_walk(&s);
    printf("     bunny shuffled -> reordered: vertex index spread per face %.0f -> %.1f (of %u), "
           "centroid step %.4f -> %.4f of the diagonal\n", spread0, spread1, nv, walk0, walk1);
    CHECK(spread1 < spread0 / 8);
    CHECK(walk1 < walk0 / 10);
    /* the same points, moved by remap; a permutation */
    for (v = 0; v < nv; v++) {
        REQUIRE(remap[v] < nv);
        seen[remap[v]]++;
        CHECK(memcmp(s.positions + 3 * remap[v], m.positions + 3 * v, 3 * sizeof(ls_real)) == 0);
    }
    for (v = 0; v < nv; v++) CHECK_EQ(seen[v], 1);
    /* the same faces, each with its corners in order */
    for (f = 0; f < nf; f++) {
        const uint32_t *t = m.triangles + 3 * f, *u = s.triangles + 3 * f;
        ka[f] = ((uint64_t)remap[t[0]] * nv + remap[t[1]]) * nv + remap[t[2]];
        kb[f] = ((uint64_t)u[0] * nv + u[1]) * nv + u[2];
    }
    {
        uint32_t *ia = malloc(sizeof(uint32_t) * nf), *ib = malloc(sizeof(uint32_t) * nf), *tmp = malloc(sizeof(uint32_t) * nf);
        for (f = 0; f < nf; f++) ia[f] = ib[f] = f;
        CHECK_STATUS(ls_sort_u64(ka, ia, nf, tmp), LS_OK);
        CHECK_STATUS(ls_sort_u64(kb, ib, nf, tmp), LS_OK);
        for (f = 0; f < nf; f++) CHECK(ka[ia[f]] == kb[ib[f]]);
        free(ia);
        free(ib);
        free(tmp);
    }
    /* vertices numbered by first use */
    for (f = 0; f < 3 * nf; f++)
        if (s.triangles[f] == next) next++;
        else CHECK(s.triangles[f] < next);
    CHECK_EQ(next, nv);
    /* the same bits again, and from the reordered mesh nothing moves */
    {
        ls_mesh t;
        REQUIRE(ls_mesh_alloc(&t, nv, nf, a) == LS_OK);
        memcpy(t.positions, s.positions, 3 * sizeof(ls_real) * nv);
        memcpy(t.triangles, s.triangles, 3 * sizeof(uint32_t) * nf);
        CHECK_STATUS(ls_mesh_reorder(&t, a, NULL), LS_OK);
        CHECK(memcmp(t.positions, s.positions, 3 * sizeof(ls_real) * nv) == 0);
        CHECK(memcmp(t.triangles, s.triangles, 3 * sizeof(uint32_t) * nf) == 0);
        /* an index out of range: refused, nothing written */
        t.triangles[3 * 17 + 1] = nv;
        CHECK_STATUS(ls_mesh_reorder(&t, a, NULL), LS_ERR_MESH);
        CHECK_EQ(t.triangles[3 * 17 + 1], nv);
        CHECK(memcmp(t.positions, s.positions, 3 * sizeof(ls_real) * nv) == 0);
        CHECK_STATUS(ls_mesh_reorder(NULL, a, NULL), LS_ERR_INVALID);
        CHECK_STATUS(ls_mesh_reorder(&t, NULL, NULL), LS_ERR_INVALID);
    }
    /* the sizing query is exact; a smaller arena changes nothing */
    rc.m = m;
    rc.p0 = malloc(3 * sizeof(ls_real) * nv);
    rc.t0 = malloc(3 * sizeof(uint32_t) * nf);
    memcpy(rc.p0, m.positions, 3 * sizeof(ls_real) * nv);
    memcpy(rc.t0, m.triangles, 3 * sizeof(uint32_t) * nf);
    CHECK_STATUS(ls_mesh_reorder_bytes(nv, nf, &bytes), LS_OK);
    memset(&job, 0, sizeof job);
    job.name = "mesh_reorder";
    job.run = reorder_run;
    job.state_hash = reorder_hash;
    job.reset = reorder_reset;
    job.ctx = &rc;
    job.answer = bytes;
    job.exact = 1;
    CHECK_EQ(sweep_arena(&job), 0);
    free(rc.p0);
    free(rc.t0);
    free(perm);
    free(remap);
    free(seen);
    free(ka);
    free(kb);
}

static void sizes_and_alloc(void)
{
    size_t b = 0;
    ls_mesh m;
    ls_arena a;
    static LS_ARENA_BUFFER(small, 256);
    CHECK_STATUS(ls_mesh_bytes(3, 1, &b), LS_OK);
    CHECK_EQ(b, LS_ARENA_ROUND(9 * sizeof(ls_real)) + 16);
    CHECK_STATUS(ls_mesh_bytes(0xffffffffu, 0xffffffffu, &b), sizeof(size_t) == 4 ? LS_ERR_TOO_LARGE : LS_OK);
    ls_arena_init(&a, small.bytes, sizeof small.bytes);
    CHECK_STATUS(ls_mesh_alloc(&m, 100, 100, &a), LS_ERR_NOMEM);
    CHECK_EQ(a.bottom, 0);
    CHECK_STATUS(ls_mesh_alloc(&m, 3, 1, &a), LS_OK);
    CHECK_EQ(m.vertex_count, 3);
    m.face_count = 0x7fffffffu;
    CHECK_STATUS(ls_mesh_validate_bytes(&m, &b), LS_ERR_TOO_LARGE);
}

int main(void)
{
    TEST_INIT("test_mesh");
    TEST_RUN(sort_is_stable_and_sorted);
    TEST_RUN(sizes_and_alloc);
    TEST_RUN(validate_closed_shapes);
    TEST_RUN(validate_finds_each_problem);
    TEST_RUN(validate_matches_brute_force);
    TEST_RUN(fixtures_are_closed_with_known_genus);
    TEST_RUN(sweeps_validate_edges_adjacency);
    TEST_RUN(edges_and_adjacency_are_sorted_and_complete);
    TEST_RUN(weld_merges_exact_duplicates_only);
    TEST_RUN(unweld_gives_each_face_its_vertices);
    TEST_RUN(creases_split_and_counted);
    TEST_RUN(face_and_vertex_normals);
    TEST_RUN(bunny_vertex_normals_point_outward);
    TEST_RUN(reorder_is_a_spatial_permutation);
    return TEST_END();
}
