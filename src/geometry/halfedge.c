/* halfedge.c - half-edge triangle mesh with fixed capacity: build from an
 * indexed mesh, split, collapse, flip, compaction. No recursion; every walk
 * is bounded by the number of half-edges. */
#include <largesteps/halfedge.h>
#include <largesteps/sort.h>
#include <string.h>

#define NONE LS_HE_NONE
#define MAX_EDGES 0x7ffffffeu /* 2 * edges + 1 must stay below NONE */

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index, int has_index)
{
    (void)ls_diag_set(diag, st, what, has_index ? index : LS_DIAG_NO_INDEX);
}

static uint32_t he_origin(const ls_hemesh *he, uint32_t h) { return he->hto[h ^ 1u]; }

/* The bound of every walk: the number of half-edge slots. */
static uint32_t walk_cap(const ls_hemesh *he) { return 2u * he->edge_count + 1u; }

ls_status ls_he_capacity(uint32_t vertex_cap, int64_t euler, uint32_t *edge_cap, uint32_t *face_cap)
{
    int64_t e, f;
    if (edge_cap == NULL || face_cap == NULL) return LS_ERR_INVALID;
    *edge_cap = 0;
    *face_cap = 0;
    if (euler > (int64_t)0x100000000LL || euler < -(int64_t)0x100000000LL) return LS_ERR_TOO_LARGE;
    e = 3 * (int64_t)vertex_cap - 3 * euler;
    f = 2 * (int64_t)vertex_cap - 2 * euler;
    if (e < 1) e = 1;
    if (f < 1) f = 1;
    if (e > (int64_t)MAX_EDGES || f > (int64_t)(NONE - 1u)) return LS_ERR_TOO_LARGE;
    *edge_cap = (uint32_t)e;
    *face_cap = (uint32_t)f;
    return LS_OK;
}

static ls_status he_object_size(uint32_t vertex_cap, int64_t euler, ls_size *s, uint32_t *ecap, uint32_t *fcap)
{
    ls_status st = ls_he_capacity(vertex_cap, euler, ecap, fcap);
    if (st != LS_OK) return st;
    ls_size_add(s, (size_t)vertex_cap, 3u * sizeof(ls_real));
    ls_size_add(s, (size_t)vertex_cap, sizeof(uint32_t));
    ls_size_add(s, 2u * (size_t)*ecap, sizeof(uint32_t)); /* hto */
    ls_size_add(s, 2u * (size_t)*ecap, sizeof(uint32_t)); /* hnext */
    ls_size_add(s, 2u * (size_t)*ecap, sizeof(uint32_t)); /* hprev */
    ls_size_add(s, 2u * (size_t)*ecap, sizeof(uint32_t)); /* hface */
    ls_size_add(s, (size_t)*fcap, sizeof(uint32_t));
    return LS_OK;
}

ls_status ls_he_bytes(uint32_t vertex_cap, int64_t euler, size_t *bytes)
{
    ls_size s;
    uint32_t ecap, fcap;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    ls_size_init(&s);
    st = he_object_size(vertex_cap, euler, &s, &ecap, &fcap);
    if (st != LS_OK) return st;
    return ls_size_get(&s, bytes);
}

/* Scratch of the pairing step: keys, order, half-edge ids, sort scratch. */
static void pair_scratch(uint32_t face_count, ls_size *s)
{
    size_t n = 3u * (size_t)face_count;
    ls_size_add(s, n, sizeof(uint64_t));
    ls_size_add(s, n, sizeof(uint32_t));
    ls_size_add(s, n, sizeof(uint32_t));
    ls_size_add(s, n, sizeof(uint32_t));
}

ls_status ls_he_build_bytes(const ls_mesh *mesh, uint32_t vertex_cap, int64_t euler, size_t *bytes)
{
    ls_size s, val;
    uint32_t ecap, fcap;
    size_t vb;
    ls_status st;
    if (bytes == NULL || mesh == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (vertex_cap == 0) vertex_cap = mesh->vertex_count;
    if (mesh->face_count > (NONE - 1u) / 3u) return LS_ERR_TOO_LARGE;
    st = ls_mesh_validate_bytes(mesh, &vb);
    if (st != LS_OK) return st;
    /* validation first (scratch, released), then the object and the pairing scratch */
    ls_size_init(&s);
    st = he_object_size(vertex_cap, euler, &s, &ecap, &fcap);
    if (st != LS_OK) return st;
    pair_scratch(mesh->face_count, &s);
    ls_size_init(&val);
    val.bytes = vb;
    ls_size_max(&s, &val);
    return ls_size_get(&s, bytes);
}

/* Sets vout[v] to a boundary outgoing half-edge when v has one (starting
 * from the current vout[v], which must be a live outgoing half-edge). */
static void adjust_outgoing(ls_hemesh *he, uint32_t v)
{
    uint32_t h = he->vout[v], start = h, guard = walk_cap(he);
    if (h == NONE) return;
    do {
        if (he->hface[h] == NONE) {
            he->vout[v] = h;
            return;
        }
        h = he->hnext[h ^ 1u];
    } while (h != start && h < 2u * he->edge_count && --guard > 0);
}

static ls_status build_pairs(const ls_mesh *mesh, ls_hemesh *he, ls_arena *arena, ls_diag *diag)
{
    const uint32_t *t = mesh->triangles;
    size_t n = 3u * (size_t)mesh->face_count, k, g;
    uint64_t *keys = (uint64_t *)ls_arena_scratch(arena, n, sizeof(uint64_t));
    uint32_t *idx = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    uint32_t *hid = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    uint32_t *tmp = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    uint32_t e = 0, f, j, v, h;
    if (keys == NULL || idx == NULL || hid == NULL || tmp == NULL) return LS_ERR_NOMEM;
    for (k = 0; k < n; k++) {
        uint32_t a = t[k], b = t[k - k % 3u + (k % 3u + 1u) % 3u];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        keys[k] = ((uint64_t)lo << 32) | hi;
        idx[k] = (uint32_t)k;
    }
    ls_sort_u64(keys, idx, n, tmp);
    for (k = 0; k < n; k = g) {
        uint64_t key = keys[idx[k]];
        uint32_t lo = (uint32_t)(key >> 32), hi = (uint32_t)key;
        int used[2] = {0, 0};
        for (g = k; g < n && keys[idx[g]] == key; g++) {
            uint32_t c = idx[g], side = t[c] == lo ? 0u : 1u;
            if (g - k >= 2u) {
                diag_set(diag, LS_ERR_MESH, "non-manifold edge", (uint64_t)(c / 3u), 1);
                return LS_ERR_MESH;
            }
            if (used[side]) {
                diag_set(diag, LS_ERR_MESH, "inconsistent face orientation", (uint64_t)(c / 3u), 1);
                return LS_ERR_MESH;
            }
            used[side] = 1;
            hid[c] = 2u * e + side;
        }
        he->hto[2u * (size_t)e] = hi;
        he->hto[2u * (size_t)e + 1u] = lo;
        e++;
    }
    he->edge_count = e;
    he->live_edges = e;
    for (h = 0; h < 2u * e; h++) {
        he->hface[h] = NONE;
        he->hnext[h] = NONE;
        he->hprev[h] = NONE;
    }
    for (f = 0; f < mesh->face_count; f++) {
        for (j = 0; j < 3u; j++) {
            h = hid[3u * (size_t)f + j];
            he->hface[h] = f;
            he->hnext[h] = hid[3u * (size_t)f + (j + 1u) % 3u];
            he->hprev[h] = hid[3u * (size_t)f + (j + 2u) % 3u];
        }
        he->fedge[f] = hid[3u * (size_t)f];
    }
    for (v = 0; v < mesh->vertex_count; v++) he->vout[v] = NONE;
    /* boundary half-edges first: each vertex has at most one outgoing */
    for (h = 0; h < 2u * e; h++) {
        if (he->hface[h] != NONE) continue;
        v = he_origin(he, h);
        if (he->vout[v] != NONE) {
            diag_set(diag, LS_ERR_MESH, "non-manifold vertex", (uint64_t)v, 1);
            return LS_ERR_MESH;
        }
        he->vout[v] = h;
    }
    for (h = 0; h < 2u * e; h++) {
        v = he_origin(he, h);
        if (he->vout[v] == NONE) he->vout[v] = h;
    }
    for (h = 0; h < 2u * e; h++) {
        uint32_t nx;
        if (he->hface[h] != NONE) continue;
        nx = he->vout[he->hto[h]];
        he->hnext[h] = nx;
        he->hprev[nx] = h;
    }
    he->live_vertices = 0;
    for (v = 0; v < mesh->vertex_count; v++) he->live_vertices += he->vout[v] != NONE ? 1u : 0u;
    return LS_OK;
}

ls_status ls_he_build(const ls_mesh *mesh, uint32_t vertex_cap, ls_arena *arena, ls_hemesh *he,
                      ls_mesh_report *report, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_mesh_report rep;
    ls_arena_mark mark;
    ls_hemesh m;
    ls_status st;
    if (mesh == NULL || arena == NULL || he == NULL || (mesh->vertex_count > 0 && mesh->positions == NULL) ||
        (mesh->face_count > 0 && mesh->triangles == NULL)) {
        diag_set(diag, LS_ERR_INVALID,
                 mesh == NULL    ? "mesh is NULL"
                 : arena == NULL ? "arena is NULL"
                 : he == NULL    ? "he is NULL"
                 : mesh->positions == NULL && mesh->vertex_count > 0 ? "mesh->positions is NULL with vertex_count > 0"
                                                                    : "mesh->triangles is NULL with face_count > 0",
                 0, 0);
        return LS_ERR_INVALID;
    }
    if (vertex_cap == 0) vertex_cap = mesh->vertex_count;
    if (vertex_cap < mesh->vertex_count) {
        diag_set(diag, LS_ERR_INVALID, "vertex_cap: allowed 0 or >= mesh->vertex_count", (uint64_t)vertex_cap, 1);
        return LS_ERR_INVALID;
    }
    if (mesh->face_count > (NONE - 1u) / 3u) {
        diag_set(diag, LS_ERR_TOO_LARGE, "too many faces", (uint64_t)mesh->face_count, 1);
        return LS_ERR_TOO_LARGE;
    }
    st = ls_mesh_validate(mesh, arena, &rep);
    if (st != LS_OK) {
        diag_set(diag, st, st == LS_ERR_NOMEM ? "arena too small" : "mesh cannot be validated", 0, 0);
        return st;
    }
    if (report != NULL) *report = rep;
    st = ls_mesh_require(&rep, LS_MESH_REQ_INDICES | LS_MESH_REQ_FINITE | LS_MESH_REQ_NONEMPTY | LS_MESH_REQ_MANIFOLD,
                         diag);
    if (st != LS_OK) return st;
    if (rep.degenerate_faces > 0) {
        diag_set(diag, LS_ERR_MESH, "face with a repeated vertex", (uint64_t)rep.first_degenerate_face, 1);
        return LS_ERR_MESH;
    }
    memset(&m, 0, sizeof m);
    st = ls_he_capacity(vertex_cap, rep.euler, &m.edge_cap, &m.face_cap);
    if (st != LS_OK || m.edge_cap < rep.edge_count || m.face_cap < mesh->face_count) {
        diag_set(diag, LS_ERR_TOO_LARGE, "capacity out of range", 0, 0);
        return LS_ERR_TOO_LARGE;
    }
    m.vertex_cap = vertex_cap;
    mark = ls_arena_save(arena);
    m.positions = (ls_real *)ls_arena_alloc(arena, (size_t)vertex_cap, 3u * sizeof(ls_real));
    m.vout = (uint32_t *)ls_arena_alloc(arena, (size_t)vertex_cap, sizeof(uint32_t));
    m.hto = (uint32_t *)ls_arena_alloc(arena, 2u * (size_t)m.edge_cap, sizeof(uint32_t));
    m.hnext = (uint32_t *)ls_arena_alloc(arena, 2u * (size_t)m.edge_cap, sizeof(uint32_t));
    m.hprev = (uint32_t *)ls_arena_alloc(arena, 2u * (size_t)m.edge_cap, sizeof(uint32_t));
    m.hface = (uint32_t *)ls_arena_alloc(arena, 2u * (size_t)m.edge_cap, sizeof(uint32_t));
    m.fedge = (uint32_t *)ls_arena_alloc(arena, (size_t)m.face_cap, sizeof(uint32_t));
    if (m.positions == NULL || m.vout == NULL || m.hto == NULL || m.hnext == NULL || m.hprev == NULL ||
        m.hface == NULL || m.fedge == NULL) {
        ls_arena_restore(arena, mark);
        diag_set(diag, LS_ERR_NOMEM, "arena too small", 0, 0);
        return LS_ERR_NOMEM;
    }
    if (mesh->vertex_count > 0)
        memcpy(m.positions, mesh->positions, (size_t)mesh->vertex_count * 3u * sizeof(ls_real));
    m.vertex_count = mesh->vertex_count;
    m.face_count = mesh->face_count;
    m.live_faces = mesh->face_count;
    {
        ls_arena_mark scratch = ls_arena_save(arena);
        st = build_pairs(mesh, &m, arena, diag);
        ls_arena_restore(arena, scratch);
    }
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        if (st == LS_ERR_NOMEM) diag_set(diag, LS_ERR_NOMEM, "arena too small", 0, 0);
        return st;
    }
    *he = m;
    return LS_OK;
}

uint32_t ls_he_valence(const ls_hemesh *he, uint32_t v)
{
    uint32_t h, start, n = 0, guard;
    if (he == NULL || v >= he->vertex_count || he->vout[v] == NONE) return 0;
    guard = walk_cap(he);
    h = start = he->vout[v];
    do {
        if (h >= 2u * he->edge_count || n >= guard) return 0;
        n++;
        h = he->hnext[h ^ 1u];
    } while (h != start);
    return n;
}

int ls_he_is_boundary(const ls_hemesh *he, uint32_t v)
{
    if (he == NULL || v >= he->vertex_count || he->vout[v] == NONE) return 0;
    return he->hface[he->vout[v]] == NONE;
}

static int edge_live(const ls_hemesh *he, uint32_t e)
{
    return e < he->edge_count && he->hto[2u * (size_t)e] != NONE;
}

static void link(ls_hemesh *he, uint32_t a, uint32_t b)
{
    he->hnext[a] = b;
    he->hprev[b] = a;
}

/* Sets the face of three half-edges forming a cycle a -> b -> c. */
static void make_face(ls_hemesh *he, uint32_t f, uint32_t a, uint32_t b, uint32_t c)
{
    link(he, a, b);
    link(he, b, c);
    link(he, c, a);
    he->hface[a] = f;
    he->hface[b] = f;
    he->hface[c] = f;
    he->fedge[f] = a;
}

ls_status ls_he_split(ls_hemesh *he, uint32_t e, const ls_real p[3], uint32_t *vertex)
{
    uint32_t h0, h1, b, f0, f1, m, g, need_e, need_f, g0, g1;
    if (he == NULL || p == NULL || !edge_live(he, e)) return LS_ERR_INVALID;
    h0 = 2u * e;
    h1 = h0 + 1u;
    b = he->hto[h0];
    f0 = he->hface[h0];
    f1 = he->hface[h1];
    need_e = 1u + (f0 != NONE ? 1u : 0u) + (f1 != NONE ? 1u : 0u);
    need_f = (f0 != NONE ? 1u : 0u) + (f1 != NONE ? 1u : 0u);
    if (he->vertex_count >= he->vertex_cap || he->edge_cap - he->edge_count < need_e ||
        he->face_cap - he->face_count < need_f)
        return LS_ERR_NOMEM;
    m = he->vertex_count++;
    he->live_vertices++;
    he->positions[3u * (size_t)m] = p[0];
    he->positions[3u * (size_t)m + 1u] = p[1];
    he->positions[3u * (size_t)m + 2u] = p[2];
    g = he->edge_count++;
    he->live_edges++;
    g0 = 2u * g;     /* m -> b */
    g1 = g0 + 1u;    /* b -> m */
    he->hto[g0] = b;
    he->hto[g1] = m;
    he->hto[h0] = m; /* h0: a -> m, h1: m -> a */
    if (f0 != NONE) {
        uint32_t hn = he->hnext[h0], hp = he->hprev[h0], c = he->hto[hn];
        uint32_t k = he->edge_count++, f2 = he->face_count++;
        he->live_edges++;
        he->live_faces++;
        he->hto[2u * (size_t)k] = c;      /* m -> c */
        he->hto[2u * (size_t)k + 1u] = m; /* c -> m */
        make_face(he, f0, h0, 2u * k, hp);
        make_face(he, f2, g0, hn, 2u * k + 1u);
    } else {
        uint32_t on = he->hnext[h0];
        he->hface[g0] = NONE;
        link(he, h0, g0);
        link(he, g0, on);
    }
    if (f1 != NONE) {
        uint32_t qn = he->hnext[h1], qp = he->hprev[h1], d = he->hto[qn];
        uint32_t l = he->edge_count++, f3 = he->face_count++;
        he->live_edges++;
        he->live_faces++;
        he->hto[2u * (size_t)l] = d;      /* m -> d */
        he->hto[2u * (size_t)l + 1u] = m; /* d -> m */
        make_face(he, f1, h1, qn, 2u * l + 1u);
        make_face(he, f3, g1, 2u * l, qp);
    } else {
        uint32_t pp = he->hprev[h1];
        he->hface[g1] = NONE;
        link(he, pp, g1);
        link(he, g1, h1);
    }
    /* a boundary half-edge out of m when there is one */
    he->vout[m] = (f0 != NONE && f1 == NONE) ? h1 : g0;
    if (he->vout[b] == h1) he->vout[b] = g1;
    if (vertex != NULL) *vertex = m;
    return LS_OK;
}

/* 1 when w is a neighbour of v (a walk over v's outgoing half-edges). */
static int adjacent(const ls_hemesh *he, uint32_t v, uint32_t w)
{
    uint32_t h = he->vout[v], start = h, guard = walk_cap(he);
    if (h == NONE) return 0;
    do {
        if (he->hto[h] == w) return 1;
        h = he->hnext[h ^ 1u];
    } while (h != start && h < 2u * he->edge_count && --guard > 0);
    return 0;
}

int ls_he_collapse_ok(const ls_hemesh *he, uint32_t h)
{
    uint32_t o, a, b, c = NONE, d = NONE, x, start, guard;
    if (he == NULL || h >= 2u * he->edge_count || he->hto[h] == NONE) return 0;
    o = h ^ 1u;
    a = he_origin(he, h);
    b = he->hto[h];
    if (a == b) return 0;
    if (he->hface[h] != NONE) {
        uint32_t hn = he->hnext[h], hp = he->hprev[h];
        c = he->hto[hn];
        if (he->hface[hn ^ 1u] == NONE && he->hface[hp ^ 1u] == NONE) return 0;
        if (!ls_he_is_boundary(he, c) && ls_he_valence(he, c) <= 3u) return 0;
    }
    if (he->hface[o] != NONE) {
        uint32_t on = he->hnext[o], op = he->hprev[o];
        d = he->hto[on];
        if (he->hface[on ^ 1u] == NONE && he->hface[op ^ 1u] == NONE) return 0;
        if (!ls_he_is_boundary(he, d) && ls_he_valence(he, d) <= 3u) return 0;
    }
    if (c != NONE && c == d) return 0;
    if (he->hface[h] != NONE && he->hface[o] != NONE && ls_he_is_boundary(he, a) && ls_he_is_boundary(he, b))
        return 0;
    /* link condition: common neighbours of a and b are only c and d */
    guard = walk_cap(he);
    x = start = he->vout[a];
    if (x == NONE) return 0;
    do {
        uint32_t w = he->hto[x];
        if (w != b && w != c && w != d && adjacent(he, b, w)) return 0;
        x = he->hnext[x ^ 1u];
        if (x >= 2u * he->edge_count || --guard == 0) return 0;
    } while (x != start);
    return 1;
}

/* Removes the two-half-edge loop x -> y -> x of face f: x takes the place of
 * y's twin, and the edge of y and the face die. */
static void remove_loop(ls_hemesh *he, uint32_t f, uint32_t x, uint32_t y)
{
    uint32_t t = y ^ 1u, tn = he->hnext[t], tp = he->hprev[t], tf = he->hface[t];
    uint32_t vb = he->hto[y], vc = he->hto[x]; /* x: vb -> vc, y: vc -> vb */
    link(he, x, tn);
    link(he, tp, x);
    he->hface[x] = tf;
    if (tf != NONE && he->fedge[tf] == t) he->fedge[tf] = x;
    if (he->vout[vb] == t) he->vout[vb] = x;
    if (he->vout[vc] == y) he->vout[vc] = x ^ 1u;
    he->fedge[f] = NONE;
    he->hto[y] = NONE;
    he->hto[t] = NONE;
    he->live_faces--;
    he->live_edges--;
}

ls_status ls_he_collapse(ls_hemesh *he, uint32_t h)
{
    uint32_t o, a, b, hn, hp, on, op, fh, fo, x, start, guard, c = NONE, d = NONE;
    if (he == NULL || h >= 2u * he->edge_count || he->hto[h] == NONE) return LS_ERR_INVALID;
    if (!ls_he_collapse_ok(he, h)) return LS_ERR_MESH;
    o = h ^ 1u;
    a = he_origin(he, h);
    b = he->hto[h];
    hn = he->hnext[h];
    hp = he->hprev[h];
    on = he->hnext[o];
    op = he->hprev[o];
    fh = he->hface[h];
    fo = he->hface[o];
    if (fh != NONE) c = he->hto[hn];
    if (fo != NONE) d = he->hto[on];
    /* every half-edge into a now ends at b */
    guard = walk_cap(he);
    x = start = he->vout[a];
    do {
        he->hto[x ^ 1u] = b;
        x = he->hnext[x ^ 1u];
    } while (x != start && --guard > 0);
    /* unlink the edge */
    link(he, hp, hn);
    link(he, op, on);
    if (fh != NONE) he->fedge[fh] = hn;
    if (fo != NONE) he->fedge[fo] = on;
    he->vout[b] = hn;
    he->hto[h] = NONE;
    he->hto[o] = NONE;
    he->live_edges--;
    he->vout[a] = NONE;
    he->live_vertices--;
    if (fh != NONE) remove_loop(he, fh, hn, hp);
    if (fo != NONE) remove_loop(he, fo, on, op);
    /* hn (or on) is a live outgoing half-edge of b in every case */
    he->vout[b] = fh != NONE ? hn : (fo != NONE ? on : hn);
    adjust_outgoing(he, b);
    if (c != NONE) {
        he->vout[c] = hn ^ 1u;
        adjust_outgoing(he, c);
    }
    if (d != NONE) {
        he->vout[d] = on ^ 1u;
        adjust_outgoing(he, d);
    }
    return LS_OK;
}

int ls_he_flip_ok(const ls_hemesh *he, uint32_t e)
{
    uint32_t h, o, a, b, c, d;
    if (he == NULL || !edge_live(he, e)) return 0;
    h = 2u * e;
    o = h + 1u;
    if (he->hface[h] == NONE || he->hface[o] == NONE) return 0;
    a = he->hto[o];
    b = he->hto[h];
    c = he->hto[he->hnext[h]];
    d = he->hto[he->hnext[o]];
    if (c == d || c == a || c == b || d == a || d == b) return 0;
    if (adjacent(he, c, d)) return 0;
    if (ls_he_valence(he, a) < (ls_he_is_boundary(he, a) ? 3u : 4u)) return 0;
    if (ls_he_valence(he, b) < (ls_he_is_boundary(he, b) ? 3u : 4u)) return 0;
    return 1;
}

ls_status ls_he_flip(ls_hemesh *he, uint32_t e)
{
    uint32_t h, o, a, b, c, d, hn, hp, on, op, f0, f1;
    if (he == NULL || !edge_live(he, e)) return LS_ERR_INVALID;
    if (!ls_he_flip_ok(he, e)) return LS_ERR_MESH;
    h = 2u * e;
    o = h + 1u;
    hn = he->hnext[h]; /* b -> c */
    hp = he->hprev[h]; /* c -> a */
    on = he->hnext[o]; /* a -> d */
    op = he->hprev[o]; /* d -> b */
    a = he->hto[o];
    b = he->hto[h];
    c = he->hto[hn];
    d = he->hto[on];
    f0 = he->hface[h];
    f1 = he->hface[o];
    he->hto[h] = c; /* h: d -> c */
    he->hto[o] = d; /* o: c -> d */
    make_face(he, f0, h, hp, on);
    make_face(he, f1, o, op, hn);
    if (he->vout[a] == h) he->vout[a] = on;
    if (he->vout[b] == o) he->vout[b] = hn;
    return LS_OK;
}

ls_status ls_he_compact_bytes(const ls_hemesh *he, size_t *bytes)
{
    ls_size s;
    if (he == NULL || bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)he->vertex_count, sizeof(uint32_t));
    ls_size_add(&s, (size_t)he->edge_count, sizeof(uint32_t));
    ls_size_add(&s, (size_t)he->face_count, sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

static uint32_t map_h(const uint32_t *emap, uint32_t h)
{
    return h == NONE ? NONE : 2u * emap[h >> 1] + (h & 1u);
}

ls_status ls_he_compact(ls_hemesh *he, ls_arena *arena)
{
    ls_arena_mark mark;
    uint32_t *vmap, *emap, *fmap, i, n;
    if (he == NULL || arena == NULL) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    vmap = (uint32_t *)ls_arena_scratch(arena, (size_t)he->vertex_count, sizeof(uint32_t));
    emap = (uint32_t *)ls_arena_scratch(arena, (size_t)he->edge_count, sizeof(uint32_t));
    fmap = (uint32_t *)ls_arena_scratch(arena, (size_t)he->face_count, sizeof(uint32_t));
    if (vmap == NULL || emap == NULL || fmap == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    for (i = 0, n = 0; i < he->vertex_count; i++) vmap[i] = he->vout[i] != NONE ? n++ : NONE;
    for (i = 0, n = 0; i < he->edge_count; i++) emap[i] = he->hto[2u * (size_t)i] != NONE ? n++ : NONE;
    for (i = 0, n = 0; i < he->face_count; i++) fmap[i] = he->fedge[i] != NONE ? n++ : NONE;
    for (i = 0; i < he->vertex_count; i++) {
        uint32_t j = vmap[i];
        if (j == NONE) continue;
        he->positions[3u * (size_t)j] = he->positions[3u * (size_t)i];
        he->positions[3u * (size_t)j + 1u] = he->positions[3u * (size_t)i + 1u];
        he->positions[3u * (size_t)j + 2u] = he->positions[3u * (size_t)i + 2u];
        he->vout[j] = map_h(emap, he->vout[i]);
    }
    for (i = 0; i < he->edge_count; i++) {
        uint32_t j = emap[i], s;
        if (j == NONE) continue;
        for (s = 0; s < 2u; s++) {
            uint32_t from = 2u * i + s, to = 2u * j + s, f = he->hface[from];
            he->hto[to] = vmap[he->hto[from]];
            he->hnext[to] = map_h(emap, he->hnext[from]);
            he->hprev[to] = map_h(emap, he->hprev[from]);
            he->hface[to] = f == NONE ? NONE : fmap[f];
        }
    }
    for (i = 0; i < he->face_count; i++) {
        uint32_t j = fmap[i];
        if (j != NONE) he->fedge[j] = map_h(emap, he->fedge[i]);
    }
    he->vertex_count = he->live_vertices;
    he->edge_count = he->live_edges;
    he->face_count = he->live_faces;
    ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_he_to_mesh(const ls_hemesh *he, ls_arena *arena, ls_mesh *mesh)
{
    ls_mesh m;
    ls_status st;
    uint32_t f, v;
    if (he == NULL || arena == NULL || mesh == NULL) return LS_ERR_INVALID;
    if (he->vertex_count != he->live_vertices || he->edge_count != he->live_edges ||
        he->face_count != he->live_faces)
        return LS_ERR_STATE;
    for (f = 0; f < he->face_count; f++) {
        uint32_t h = he->fedge[f], h1, h2;
        if (h >= 2u * he->edge_count) return LS_ERR_STATE;
        h1 = he->hnext[h];
        if (h1 >= 2u * he->edge_count) return LS_ERR_STATE;
        h2 = he->hnext[h1];
        if (h2 >= 2u * he->edge_count || he->hnext[h2] != h || he->hface[h] != f || he->hface[h1] != f ||
            he->hface[h2] != f)
            return LS_ERR_STATE;
    }
    st = ls_mesh_alloc(&m, he->vertex_count, he->face_count, arena);
    if (st != LS_OK) return st;
    for (v = 0; v < he->vertex_count; v++) {
        m.positions[3u * (size_t)v] = he->positions[3u * (size_t)v];
        m.positions[3u * (size_t)v + 1u] = he->positions[3u * (size_t)v + 1u];
        m.positions[3u * (size_t)v + 2u] = he->positions[3u * (size_t)v + 2u];
    }
    for (f = 0; f < he->face_count; f++) {
        uint32_t h = he->fedge[f], h1 = he->hnext[h];
        m.triangles[3u * (size_t)f] = he_origin(he, h);
        m.triangles[3u * (size_t)f + 1u] = he->hto[h];
        m.triangles[3u * (size_t)f + 2u] = he->hto[h1];
    }
    *mesh = m;
    return LS_OK;
}
