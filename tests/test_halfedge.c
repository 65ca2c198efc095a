/* tests/test_halfedge.c - the half-edge mesh: build, split, collapse, flip,
 * compaction, checked after every operation by an independent consistency
 * checker (twins, next/prev cycles, faces, vertex fans, counts, Euler
 * characteristic) and by ls_mesh_validate on the indexed result. */
#include <stdlib.h>
#include "test.h"
#include "sweep.h"
#include "bench/meshgen.h"

/* ---- test meshes ------------------------------------------------------- */

typedef struct owned_mesh {
    ls_mesh m;
} owned_mesh;

static ls_mesh to_ls(const tmesh *t)
{
    ls_mesh m;
    uint32_t i;
    m.vertex_count = t->nv;
    m.face_count = t->nf;
    m.positions = (ls_real *)malloc((size_t)t->nv * 3u * sizeof(ls_real) + 8u);
    m.triangles = (uint32_t *)malloc((size_t)t->nf * 3u * sizeof(uint32_t) + 8u);
    for (i = 0; i < 3u * t->nv; i++) m.positions[i] = (ls_real)t->pos[i];
    for (i = 0; i < 3u * t->nf; i++) m.triangles[i] = t->tri[i];
    return m;
}

static void free_ls(ls_mesh *m)
{
    free(m->positions);
    free(m->triangles);
}

static ls_mesh make_ico(int level)
{
    tmesh t = icosphere(level);
    ls_mesh m = to_ls(&t);
    tmesh_free(&t);
    return m;
}

static ls_mesh make_grid(uint32_t w, uint32_t h)
{
    tmesh t = gridmesh(w, h);
    ls_mesh m = to_ls(&t);
    tmesh_free(&t);
    return m;
}

static unsigned char *g_buf;
static size_t g_buf_bytes;

static void arena_big(ls_arena *a, size_t bytes)
{
    if (g_buf_bytes < bytes) {
        free(g_buf);
        g_buf = (unsigned char *)malloc(bytes + 16u);
        g_buf_bytes = bytes;
    }
    ls_arena_init(a, g_buf, bytes);
}

/* ---- the independent checker -------------------------------------------
 * Returns the number of problems; prints the first few. Does not use the
 * module's walks: fans are counted by scanning every half-edge. */
static int check_he(const ls_hemesh *he, int64_t euler_expected, const char *where)
{
    uint32_t H = 2u * he->edge_count, h, v, f, lv = 0, le = 0, lf = 0;
    int bad = 0;
    uint32_t *outdeg, *bout, *seen;
#define BAD(...)                                            \
    do {                                                    \
        if (bad < 5) {                                      \
            printf("     %s: ", where);                     \
            printf(__VA_ARGS__);                            \
            printf("\n");                                   \
        }                                                   \
        bad++;                                              \
    } while (0)
    outdeg = (uint32_t *)calloc((size_t)he->vertex_count + 1u, sizeof(uint32_t));
    bout = (uint32_t *)calloc((size_t)he->vertex_count + 1u, sizeof(uint32_t));
    seen = (uint32_t *)calloc((size_t)H + 1u, sizeof(uint32_t));
    for (h = 0; h < H; h++) {
        uint32_t t = he->hto[h], n, p, o;
        if ((t == LS_HE_NONE) != (he->hto[h ^ 1u] == LS_HE_NONE)) BAD("half-edge %u: twin liveness differs", h);
        if (t == LS_HE_NONE) continue;
        if ((h & 1u) == 0) le++;
        if (t >= he->vertex_count || he->vout[t] == LS_HE_NONE) { BAD("half-edge %u points to dead vertex %u", h, t); continue; }
        o = he->hto[h ^ 1u];
        if (o == t) BAD("half-edge %u is a loop", h);
        n = he->hnext[h];
        p = he->hprev[h];
        if (n >= H || p >= H || he->hto[n] == LS_HE_NONE || he->hto[p] == LS_HE_NONE) { BAD("half-edge %u: bad next/prev", h); continue; }
        if (he->hprev[n] != h || he->hnext[p] != h) BAD("half-edge %u: next/prev not inverse", h);
        if (he->hto[n ^ 1u] != t) BAD("half-edge %u: next does not start at its end", h);
        if (he->hto[p] != o) BAD("half-edge %u: prev does not end at its start", h);
        if (he->hface[h] != he->hface[n]) BAD("half-edge %u: next in another face", h);
        if (he->hface[h] != LS_HE_NONE) {
            if (he->hface[h] >= he->face_count || he->fedge[he->hface[h]] == LS_HE_NONE) BAD("half-edge %u in a dead face", h);
            if (he->hnext[he->hnext[n]] != h) BAD("half-edge %u: face is not a triangle", h);
        } else {
            if (he->hface[h ^ 1u] == LS_HE_NONE) BAD("edge %u has no face", h >> 1);
            bout[o]++;
        }
        outdeg[o]++;
    }
    for (f = 0; f < he->face_count; f++) {
        uint32_t h0 = he->fedge[f];
        if (h0 == LS_HE_NONE) continue;
        lf++;
        if (h0 >= H || he->hface[h0] != f) BAD("face %u: fedge not in the face", f);
    }
    for (v = 0; v < he->vertex_count; v++) {
        uint32_t s = he->vout[v], x, n = 0;
        if (s == LS_HE_NONE) {
            if (outdeg[v] != 0) BAD("dead vertex %u has edges", v);
            continue;
        }
        lv++;
        if (s >= H || he->hto[s] == LS_HE_NONE || he->hto[s ^ 1u] != v) { BAD("vertex %u: vout not outgoing", v); continue; }
        if (bout[v] > 1u) BAD("vertex %u: %u boundary half-edges out (non-manifold)", v, bout[v]);
        if (bout[v] == 1u && he->hface[s] != LS_HE_NONE) BAD("vertex %u: vout is not its boundary half-edge", v);
        /* the fan from vout reaches every outgoing half-edge exactly once */
        x = s;
        do {
            if (x >= H || seen[x] == v + 1u || n > outdeg[v]) break;
            seen[x] = v + 1u;
            n++;
            x = he->hnext[x ^ 1u];
        } while (x != s);
        if (n != outdeg[v] || x != s) BAD("vertex %u: fan of %u half-edges, %u out", v, n, outdeg[v]);
    }
    if (lv != he->live_vertices || le != he->live_edges || lf != he->live_faces)
        BAD("live counts %u %u %u, stored %u %u %u", lv, le, lf, he->live_vertices, he->live_edges, he->live_faces);
    if ((int64_t)lv - (int64_t)le + (int64_t)lf != euler_expected)
        BAD("Euler characteristic %lld, expected %lld", (long long)lv - (long long)le + (long long)lf, (long long)euler_expected);
    free(outdeg);
    free(bout);
    free(seen);
#undef BAD
    return bad;
}

/* Validates in a buffer of its own (m may live in the shared one). */
static int64_t euler_of(const ls_mesh *m, ls_mesh_report *rep)
{
    ls_arena a;
    size_t need = 0;
    unsigned char *buf;
    int64_t chi = -9999;
    ls_mesh_validate_bytes(m, &need);
    buf = (unsigned char *)malloc(need + 16u);
    ls_arena_init(&a, buf, need);
    if (ls_mesh_validate(m, &a, rep) == LS_OK) chi = rep->euler;
    free(buf);
    return chi;
}

static uint64_t rng_state = 12345u;
static uint32_t rng24(void) /* 24 random bits */
{
    return (uint32_t)(test_rng_bits(&rng_state) >> 29);
}

/* ---- tests --------------------------------------------------------------- */

static void build_closed_and_open(void)
{
    ls_mesh meshes[3];
    int k;
    meshes[0] = make_ico(0);
    meshes[1] = make_ico(2);
    meshes[2] = make_grid(6, 5);
    for (k = 0; k < 3; k++) {
        ls_mesh_report rep, rep2;
        ls_hemesh he;
        ls_arena a;
        size_t bytes;
        int64_t chi = euler_of(&meshes[k], &rep);
        REQUIRE(ls_he_build_bytes(&meshes[k], 0, chi, &bytes) == LS_OK);
        arena_big(&a, bytes);
        CHECK_STATUS(ls_he_build(&meshes[k], 0, &a, &he, &rep2, NULL), LS_OK);
        CHECK_EQ(he.live_vertices, meshes[k].vertex_count);
        CHECK_EQ(he.live_faces, meshes[k].face_count);
        CHECK_EQ(he.live_edges, rep.edge_count);
        CHECK_EQ(check_he(&he, chi, "build"), 0);
        CHECK_EQ(rep2.euler, chi);
        if (k == 2) {
            /* grid: boundary vertices are those on the border */
            uint32_t v, nb = 0;
            for (v = 0; v < he.vertex_count; v++) nb += (uint32_t)ls_he_is_boundary(&he, v);
            CHECK_EQ(nb, rep.boundary_edges);
            CHECK(ls_he_valence(&he, 0) == 2 || ls_he_valence(&he, 0) == 3); /* a grid corner */
        } else {
            CHECK_EQ(ls_he_valence(&he, 0), 5);
        }
    }
    for (k = 0; k < 3; k++) free_ls(&meshes[k]);
}

static void build_rejects_nonmanifold(void)
{
    ls_real pos[5 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    /* three faces on edge (0, 1) */
    uint32_t t3[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    /* two fans meeting at vertex 0 (bowtie) */
    ls_real pos2[5 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0};
    uint32_t tb[6] = {0, 1, 2, 0, 3, 4};
    /* inconsistent orientation */
    uint32_t to[6] = {0, 1, 2, 0, 1, 3};
    uint32_t tr[6] = {0, 1, 1, 0, 2, 3};
    ls_mesh m;
    ls_hemesh he;
    ls_arena a;
    ls_diag d;
    memset(&he, 0x5a, sizeof he);
    arena_big(&a, 1u << 16);
    m.positions = pos;
    m.vertex_count = 5;
    m.triangles = t3;
    m.face_count = 3;
    CHECK_STATUS(ls_he_build(&m, 0, &a, &he, NULL, &d), LS_ERR_MESH);
    CHECK_MSG(strstr(d.what, "non-manifold edge") != NULL, "what = %s", d.what);
    m.positions = pos2;
    m.triangles = tb;
    m.face_count = 2;
    CHECK_STATUS(ls_he_build(&m, 0, &a, &he, NULL, &d), LS_ERR_MESH);
    CHECK_MSG(strstr(d.what, "non-manifold vertex") != NULL, "what = %s", d.what);
    m.triangles = to;
    CHECK_STATUS(ls_he_build(&m, 0, &a, &he, NULL, &d), LS_ERR_MESH);
    CHECK_MSG(strstr(d.what, "orient") != NULL, "what = %s", d.what);
    m.triangles = tr;
    CHECK_STATUS(ls_he_build(&m, 0, &a, &he, NULL, &d), LS_ERR_MESH);
    CHECK_MSG(strstr(d.what, "repeated") != NULL, "what = %s", d.what);
    CHECK_EQ(a.bottom, 0);
    CHECK_EQ(a.top, 0);
    CHECK_STATUS(ls_he_build(&m, 2, &a, &he, NULL, &d), LS_ERR_INVALID);
    CHECK_MSG(strstr(d.what, "vertex_cap") != NULL, "what = %s", d.what);
    CHECK_STATUS(ls_he_build(&m, 0, &a, NULL, NULL, &d), LS_ERR_INVALID);
    CHECK_MSG(strcmp(d.what, "he is NULL") == 0, "what = %s", d.what);
}

/* Random operations: after each, the checker; at the end, the indexed mesh
 * keeps components, genus and boundary loops. */
static void random_ops(const ls_mesh *in, uint32_t extra, int steps, const char *name)
{
    ls_mesh_report rep, rep2;
    ls_hemesh he;
    ls_arena a;
    ls_mesh out;
    size_t bytes, cb;
    int64_t chi = euler_of(in, &rep);
    int s, splits = 0, collapses = 0, flips = 0, bad = 0, refused_flip = 0;
    uint32_t vcap = in->vertex_count + extra;
    REQUIRE(ls_he_build_bytes(in, vcap, chi, &bytes) == LS_OK);
    arena_big(&a, bytes + (size_t)vcap * 200u);
    REQUIRE(ls_he_build(in, vcap, &a, &he, NULL, NULL) == LS_OK);
    for (s = 0; s < steps && bad == 0; s++) {
        uint32_t op = rng24() % 3u, e = rng24() % he.edge_count;
        if (he.hto[2u * e] == LS_HE_NONE) continue;
        if (op == 0) {
            ls_real p[3];
            uint32_t a0 = he.hto[2u * e + 1u], b0 = he.hto[2u * e], k, nv;
            for (k = 0; k < 3; k++) p[k] = (he.positions[3u * a0 + k] + he.positions[3u * b0 + k]) / 2;
            if (ls_he_split(&he, e, p, &nv) == LS_OK) {
                splits++;
                CHECK_EQ(he.hto[2u * e], nv);
                CHECK_EQ(ls_he_is_boundary(&he, nv), he.hface[2u * e] == LS_HE_NONE || he.hface[2u * e + 1u] == LS_HE_NONE);
            }
        } else if (op == 1) {
            uint32_t h = 2u * e + (rng24() & 1u);
            int ok = ls_he_collapse_ok(&he, h);
            ls_status st = ls_he_collapse(&he, h);
            CHECK_EQ(st, ok ? LS_OK : LS_ERR_MESH);
            collapses += st == LS_OK;
        } else {
            int ok = ls_he_flip_ok(&he, e);
            ls_status st = ls_he_flip(&he, e);
            CHECK_EQ(st, ok ? LS_OK : LS_ERR_MESH);
            flips += st == LS_OK;
            refused_flip += !ok;
        }
        bad += check_he(&he, chi, name);
        if (s % 97 == 0 && bad == 0) {
            REQUIRE(ls_he_compact_bytes(&he, &cb) == LS_OK);
            REQUIRE(ls_he_compact(&he, &a) == LS_OK);
            CHECK_EQ(he.vertex_count, he.live_vertices);
            bad += check_he(&he, chi, "after compact");
        }
    }
    CHECK_EQ(bad, 0);
    CHECK(splits > 10 && collapses > 10 && flips > 10);
    CHECK_STATUS(ls_he_to_mesh(&he, &a, &out), he.vertex_count == he.live_vertices && he.edge_count == he.live_edges && he.face_count == he.live_faces ? LS_OK : LS_ERR_STATE);
    REQUIRE(ls_he_compact(&he, &a) == LS_OK);
    REQUIRE(check_he(&he, chi, "final compact") == 0);
    REQUIRE(ls_he_to_mesh(&he, &a, &out) == LS_OK);
    CHECK_EQ(out.vertex_count, he.live_vertices);
    CHECK_EQ(out.face_count, he.live_faces);
    euler_of(&out, &rep2);
    CHECK_EQ(rep2.nonmanifold_edges + rep2.nonmanifold_vertices + rep2.orientation_conflicts, 0);
    CHECK_EQ(rep2.degenerate_faces + rep2.unreferenced_vertices, 0);
    CHECK_EQ(rep2.components, rep.components);
    CHECK_EQ(rep2.boundary_loops, rep.boundary_loops);
    CHECK_EQ(rep2.genus, rep.genus);
    CHECK_EQ(rep2.euler, rep.euler);
    printf("     %s: %d splits, %d collapses, %d flips (%d refused); V %u -> %u\n", name, splits, collapses, flips,
           refused_flip, in->vertex_count, out.vertex_count);
}

static void operators_random_closed(void)
{
    ls_mesh m = make_ico(2);
    rng_state = test_rng_seed(7u);
    random_ops(&m, 400, 3000, "icosphere");
    free_ls(&m);
}

static void operators_random_open(void)
{
    ls_mesh m = make_grid(9, 7);
    rng_state = test_rng_seed(99u);
    random_ops(&m, 400, 3000, "grid");
    free_ls(&m);
}

/* Known results of single operations on small meshes. */
static void operators_exact(void)
{
    ls_mesh m = make_ico(0), out;
    ls_mesh_report rep;
    ls_hemesh he;
    ls_arena a;
    ls_real p[3] = {0, 0, 0};
    uint32_t e, nv, v0, v1, h;
    int64_t chi = euler_of(&m, &rep);
    uint64_t hash;
    arena_big(&a, 1u << 20);
    REQUIRE(ls_he_build(&m, 13, &a, &he, NULL, NULL) == LS_OK);
    CHECK_EQ(chi, 2);
    /* split: 13 vertices, 30 + 3 edges, 20 + 2 faces; new vertex valence 4 */
    REQUIRE(ls_he_split(&he, 0, p, &nv) == LS_OK);
    CHECK_EQ(nv, 12);
    CHECK_EQ(he.live_vertices, 13);
    CHECK_EQ(he.live_edges, 33);
    CHECK_EQ(he.live_faces, 22);
    CHECK_EQ(ls_he_valence(&he, nv), 4);
    CHECK_EQ(check_he(&he, 2, "split"), 0);
    /* full: the next split fails and changes nothing */
    hash = test_hash(he.hto, 2u * he.edge_count * 4u, TEST_HASH_SEED);
    CHECK_STATUS(ls_he_split(&he, 1, p, NULL), LS_ERR_NOMEM);
    CHECK(hash == test_hash(he.hto, 2u * he.edge_count * 4u, TEST_HASH_SEED));
    CHECK_EQ(he.live_vertices, 13);
    /* collapse the new vertex back: valence-4 vertex into a neighbour */
    h = he.vout[nv];
    v1 = he.hto[h];
    REQUIRE(ls_he_collapse_ok(&he, h));
    REQUIRE(ls_he_collapse(&he, h) == LS_OK);
    CHECK_EQ(he.live_vertices, 12);
    CHECK_EQ(he.live_edges, 30);
    CHECK_EQ(he.live_faces, 20);
    CHECK_EQ(check_he(&he, 2, "collapse"), 0);
    CHECK(ls_he_valence(&he, v1) >= 5);
    /* flip an edge of the icosahedron: the ends lose one edge, the corners gain one */
    REQUIRE(ls_he_compact(&he, &a) == LS_OK);
    e = 5;
    v0 = he.hto[2u * e + 1u];
    v1 = he.hto[2u * e];
    {
        uint32_t c = he.hto[he.hnext[2u * e]], d = he.hto[he.hnext[2u * e + 1u]];
        uint32_t vc = ls_he_valence(&he, c), vd = ls_he_valence(&he, d), va = ls_he_valence(&he, v0),
                 vb = ls_he_valence(&he, v1);
        REQUIRE(ls_he_flip_ok(&he, e));
        REQUIRE(ls_he_flip(&he, e) == LS_OK);
        CHECK_EQ(ls_he_valence(&he, c), vc + 1);
        CHECK_EQ(ls_he_valence(&he, d), vd + 1);
        CHECK_EQ(ls_he_valence(&he, v0), va - 1);
        CHECK_EQ(ls_he_valence(&he, v1), vb - 1);
        CHECK(he.hto[2u * e] == c || he.hto[2u * e] == d);
        /* flipping back is allowed and restores the valences */
        REQUIRE(ls_he_flip(&he, e) == LS_OK);
        CHECK_EQ(ls_he_valence(&he, v0), va);
        CHECK_EQ(check_he(&he, 2, "flip"), 0);
    }
    REQUIRE(ls_he_to_mesh(&he, &a, &out) == LS_OK);
    CHECK_EQ(out.vertex_count, 12);
    CHECK_EQ(out.face_count, 20);
    free_ls(&m);
}

/* Collapses that would change the topology are refused. */
static void collapse_refusals(void)
{
    /* tetrahedron: every collapse would leave two faces on three vertices */
    ls_real tp[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    uint32_t tt[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    /* a single triangle: its edges are all boundary */
    uint32_t t1[3] = {0, 1, 2};
    ls_mesh m;
    ls_hemesh he;
    ls_arena a;
    uint32_t h;
    arena_big(&a, 1u << 16);
    m.positions = tp;
    m.vertex_count = 4;
    m.triangles = tt;
    m.face_count = 4;
    REQUIRE(ls_he_build(&m, 0, &a, &he, NULL, NULL) == LS_OK);
    for (h = 0; h < 2u * he.edge_count; h++) {
        CHECK_EQ(ls_he_collapse_ok(&he, h), 0);
        CHECK_EQ(ls_he_flip_ok(&he, h >> 1), 0);
    }
    CHECK_STATUS(ls_he_collapse(&he, 0), LS_ERR_MESH);
    CHECK_EQ(check_he(&he, 2, "tetrahedron"), 0);
    m.triangles = t1;
    m.face_count = 1;
    m.vertex_count = 3;
    REQUIRE(ls_he_build(&m, 0, &a, &he, NULL, NULL) == LS_OK);
    for (h = 0; h < 2u * he.edge_count; h++) CHECK_EQ(ls_he_collapse_ok(&he, h), 0);
    CHECK_EQ(ls_he_flip_ok(&he, 0), 0);
    CHECK_STATUS(ls_he_split(&he, 0, tp, NULL), LS_ERR_NOMEM); /* capacity 3 */
    CHECK_STATUS(ls_he_collapse(&he, 99), LS_ERR_INVALID);
    CHECK_STATUS(ls_he_flip(&he, 99), LS_ERR_INVALID);
}

/* A corrupted structure: a one-ring walk that never comes back. Every
 * walk is bounded, so the calls return (valence 0 = "does not close"). */
static void corrupted_walks_end(void)
{
    ls_mesh m = make_ico(1);
    ls_hemesh he;
    ls_arena a;
    uint32_t v = 0, w, x, h;
    arena_big(&a, 1u << 20);
    REQUIRE(ls_he_build(&m, 0, &a, &he, NULL, NULL) == LS_OK);
    /* a vertex w not adjacent to v: its fan never reaches v's */
    for (w = 1; w < he.vertex_count; w++) {
        uint32_t k, adj = 0;
        for (k = 0; k < 2u * he.edge_count; k++)
            if (he.hto[k] == w && he.hto[k ^ 1u] == v) adj = 1;
        if (!adj) break;
    }
    REQUIRE(w < he.vertex_count);
    x = he.vout[v] ^ 1u;
    he.hnext[x] = he.vout[w]; /* v's walk jumps into w's fan and circles there */
    CHECK_EQ(ls_he_valence(&he, v), 0);
    for (h = 0; h < 2u * he.edge_count; h++) (void)ls_he_collapse_ok(&he, h);
    for (h = 0; h < he.edge_count; h++) (void)ls_he_flip_ok(&he, h);
    CHECK(check_he(&he, 2, "corrupted (expected)") > 0); /* the checker sees it */
    free_ls(&m);
}

/* ---- arena sweep of the build --------------------------------------------- */

typedef struct build_ctx {
    ls_mesh *mesh;
    ls_hemesh he;
    uint32_t vcap;
} build_ctx;

static ls_status build_run(void *ctx, ls_arena *arena)
{
    build_ctx *c = (build_ctx *)ctx;
    return ls_he_build(c->mesh, c->vcap, arena, &c->he, NULL, NULL);
}

static uint64_t build_hash(void *ctx)
{
    build_ctx *c = (build_ctx *)ctx;
    uint64_t h = test_hash(&c->he, sizeof c->he, TEST_HASH_SEED);
    h = test_hash_reals(c->mesh->positions, 3u * c->mesh->vertex_count, h);
    return test_hash(c->mesh->triangles, 3u * c->mesh->face_count * sizeof(uint32_t), h);
}

static void build_sweep(void)
{
    ls_mesh m = make_ico(1);
    ls_mesh_report rep;
    build_ctx c;
    sweep_job job;
    int64_t chi = euler_of(&m, &rep);
    memset(&c, 0, sizeof c);
    c.mesh = &m;
    c.vcap = 100;
    memset(&job, 0, sizeof job);
    job.name = "he_build";
    job.run = build_run;
    job.state_hash = build_hash;
    job.ctx = &c;
    job.exact = 1;
    REQUIRE(ls_he_build_bytes(&m, c.vcap, chi, &job.answer) == LS_OK);
    CHECK_EQ(sweep_arena(&job), 0);
    free_ls(&m);
}

int main(void)
{
    TEST_INIT("test_halfedge");
    TEST_RUN(build_closed_and_open);
    TEST_RUN(build_rejects_nonmanifold);
    TEST_RUN(operators_exact);
    TEST_RUN(collapse_refusals);
    TEST_RUN(operators_random_closed);
    TEST_RUN(operators_random_open);
    TEST_RUN(corrupted_walks_end);
    TEST_RUN(build_sweep);
    free(g_buf);
    return TEST_END();
}
