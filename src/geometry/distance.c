/* distance.c - mesh-to-mesh distances over vertex and area-uniform face
 * samples (see largesteps/distance.h). */
#include <largesteps/distance.h>
#include <largesteps/math.h>
#include <string.h>
#include "../base/parallel.h"

/* R2 sequence increments, round(2^32 / g) and round(2^32 / g^2) for the
 * plastic number g = 1.3247179572447460...; the sequence starts at 1/2. */
#define R2_A1 3242174889u
#define R2_A2 2447445414u
#define R2_START 2147483648u
#define RAD_TO_DEG ((ls_real)57.295779513082320876798)

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index, int has_index)
{
    (void)ls_diag_set(diag, st, what, has_index ? index : LS_DIAG_NO_INDEX);
}

/* Neumaier-compensated sum. */
typedef struct csum {
    ls_real s;
    ls_real c;
} csum;

static void csum_add(csum *a, ls_real x)
{
    ls_real t = a->s + x;
    if (LS_RFABS(a->s) >= LS_RFABS(x)) a->c += (a->s - t) + x;
    else a->c += (x - t) + a->s;
    a->s = t;
}

static ls_real csum_get(const csum *a)
{
    return a->s + a->c;
}

typedef struct acc {
    csum sum;
    csum sum2;
    ls_real max;
    uint32_t count;
    uint32_t argmax;
} acc;

static void acc_init(acc *a)
{
    memset(a, 0, sizeof *a);
    a->argmax = UINT32_MAX;
}

static void acc_add(acc *a, ls_real x, uint32_t id)
{
    csum_add(&a->sum, x);
    csum_add(&a->sum2, x * x);
    if (a->count == 0 || x > a->max) {
        a->max = x;
        a->argmax = id;
    }
    a->count++;
}

static void acc_get(const acc *a, ls_dist_stats *s)
{
    s->count = a->count;
    s->argmax = a->argmax;
    s->max = a->max;
    s->mean = 0;
    s->rms = 0;
    if (a->count > 0) {
        ls_real m2 = csum_get(&a->sum2) / (ls_real)a->count;
        s->mean = csum_get(&a->sum) / (ls_real)a->count;
        s->rms = m2 > 0 ? LS_RSQRT(m2) : (ls_real)0;
    }
}

/* Twice the area vector of face f. */
static void tri_cross(const ls_real *pos, const uint32_t *tris, uint32_t f, ls_real n[3])
{
    const uint32_t *t = tris + 3u * (size_t)f;
    const ls_real *a = pos + 3u * (size_t)t[0];
    const ls_real *b = pos + 3u * (size_t)t[1];
    const ls_real *c = pos + 3u * (size_t)t[2];
    ls_real u[3], v[3];
    uint32_t k;
    for (k = 0; k < 3u; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

static void face_cross(const ls_mesh *m, uint32_t f, ls_real n[3])
{
    tri_cross(m->positions, m->triangles, f, n);
}

static ls_real norm3(const ls_real n[3])
{
    return LS_RSQRT((n[0] * n[0] + n[1] * n[1]) + n[2] * n[2]);
}

static ls_real total_area2(const ls_mesh *m)
{
    csum s;
    uint32_t f;
    s.s = s.c = 0;
    for (f = 0; f < m->face_count; f++) {
        ls_real n[3];
        face_cross(m, f, n);
        csum_add(&s, norm3(n));
    }
    return csum_get(&s);
}

/* Walks the faces handing out sample counts: after a call for face f,
 * *end is the number of samples in faces 0..f (round(N C_f), the last face
 * ending at N exactly). */
typedef struct sampler {
    csum cum;
    ls_real total;
    uint32_t n;
    uint32_t end;
} sampler;

static uint32_t sampler_next(sampler *s, ls_real area2, int last)
{
    uint32_t begin = s->end, e;
    ls_real x;
    csum_add(&s->cum, area2);
    if (last) {
        s->end = s->n;
        return s->n - begin;
    }
    x = (ls_real)s->n * (csum_get(&s->cum) / s->total);
    e = LS_RTO_U32(LS_RFLOOR(x + (ls_real)0.5));
    if (e < begin) e = begin;
    if (e > s->n) e = s->n;
    s->end = e;
    return e - begin;
}

/* Face sample k in face f: the R2 point of index k folded into the triangle. */
static void sample_in_face(const ls_mesh *m, uint32_t f, uint32_t k, ls_real p[3])
{
    const uint32_t *t = m->triangles + 3u * (size_t)f;
    const ls_real *a = m->positions + 3u * (size_t)t[0];
    const ls_real *b = m->positions + 3u * (size_t)t[1];
    const ls_real *c = m->positions + 3u * (size_t)t[2];
    uint32_t xu = R2_START + k * R2_A1, xv = R2_START + k * R2_A2, j;
    const ls_real scale = (ls_real)1 / (ls_real)16777216;
    ls_real u = (ls_real)(xu >> 8) * scale, v = (ls_real)(xv >> 8) * scale;
    if (u + v > (ls_real)1) {
        u = (ls_real)1 - u;
        v = (ls_real)1 - v;
    }
    for (j = 0; j < 3u; j++) p[j] = a[j] + u * (b[j] - a[j]) + v * (c[j] - a[j]);
}

/* ls_bvh_check_mesh, with the messages of one mesh role. */
static ls_status check_mesh(const ls_mesh *m, const char *bad_index, const char *bad_value, ls_diag *diag)
{
    ls_status st = ls_bvh_check_mesh(m, diag);
    if (diag != NULL && st == LS_ERR_MESH) diag->what = bad_index;
    if (diag != NULL && st == LS_ERR_NONFINITE) diag->what = bad_value;
    return st;
}

uint32_t ls_distance_default_samples(const ls_mesh *mesh)
{
    uint32_t v;
    if (mesh == NULL) return 1000u;
    v = mesh->vertex_count;
    if (v > UINT32_MAX / 10u) return UINT32_MAX;
    return v * 10u < 1000u ? 1000u : v * 10u;
}

/* Angle in degrees between two (unnormalised) normals; -1 when one is zero. */
static ls_real normal_angle(const ls_real n1[3], const ls_real n2[3])
{
    ls_real c[3], d;
    if ((n2[0] == 0 && n2[1] == 0 && n2[2] == 0) || (n1[0] == 0 && n1[1] == 0 && n1[2] == 0)) return -1;
    c[0] = n1[1] * n2[2] - n1[2] * n2[1];
    c[1] = n1[2] * n2[0] - n1[0] * n2[2];
    c[2] = n1[0] * n2[1] - n1[1] * n2[0];
    d = (n1[0] * n2[0] + n1[1] * n2[1]) + n1[2] * n2[2];
    return LS_RATAN2(norm3(c), d) * RAD_TO_DEG;
}

/* The closest point on target of vertex k of src (face UINT32_MAX) or of
 * face sample k in face `face`: its distance and, for a sample, the angle
 * between the two faces' normals (-1 when one is zero). *guess: the last
 * answer (consecutive points are close; the answer does not depend on it). */
static ls_status closest_of(const ls_mesh *src, const ls_bvh *target, uint32_t face, uint32_t k, uint32_t *guess,
                            ls_real *dist, ls_real *angle)
{
    ls_bvh_hit hit;
    ls_real p[3];
    const ls_real *q = p;
    ls_status st;
    if (face != UINT32_MAX) sample_in_face(src, face, k, p);
    else q = src->positions + 3u * (size_t)k;
    st = ls_bvh_closest_near(target, q, LS_REAL_MAX, *guess, &hit);
    if (st != LS_OK) return st;
    *guess = hit.face;
    *dist = LS_RSQRT(hit.dist2);
    if (face != UINT32_MAX) {
        ls_real n1[3], n2[3];
        face_cross(src, face, n1);
        tri_cross(target->positions, target->triangles, hit.face, n2);
        *angle = normal_angle(n1, n2);
    }
    return LS_OK;
}

static ls_status one_way(const ls_mesh *src, const ls_bvh *target, uint32_t samples, ls_dist_one_way *out)
{
    acc av, af, an;
    sampler sm;
    uint32_t v, f, k = 0, guess = UINT32_MAX;
    ls_real d, ang = -1;
    ls_status st;
    acc_init(&av);
    acc_init(&af);
    acc_init(&an);
    for (v = 0; v < src->vertex_count; v++) {
        st = closest_of(src, target, UINT32_MAX, v, &guess, &d, &ang);
        if (st != LS_OK) return st;
        acc_add(&av, d, v);
    }
    memset(&sm, 0, sizeof sm);
    sm.total = total_area2(src);
    sm.n = sm.total > 0 ? samples : 0u;
    for (f = 0; f < src->face_count && sm.n > 0; f++) {
        ls_real n1[3];
        uint32_t c;
        face_cross(src, f, n1);
        c = sampler_next(&sm, norm3(n1), f + 1u == src->face_count);
        for (; c > 0; c--, k++) {
            st = closest_of(src, target, f, k, &guess, &d, &ang);
            if (st != LS_OK) return st;
            acc_add(&af, d, k);
            if (ang >= 0) acc_add(&an, ang, k);
        }
    }
    acc_get(&av, &out->vertex);
    acc_get(&af, &out->face);
    acc_get(&an, &out->normal);
    return LS_OK;
}

ls_status ls_distance_one_way(const ls_mesh *src, const ls_bvh *target, uint32_t samples, ls_dist_one_way *out,
                              ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_dist_one_way r;
    ls_status st;
    if (src == NULL || target == NULL || out == NULL || target->nodes == NULL ||
        (src->face_count > 0 && src->triangles == NULL) || (src->vertex_count > 0 && src->positions == NULL)) {
        diag_set(diag, LS_ERR_INVALID,
                 src == NULL             ? "src is NULL"
                 : target == NULL        ? "target is NULL"
                 : out == NULL           ? "out is NULL"
                 : target->nodes == NULL ? "target->nodes is NULL (ls_bvh_build first)"
                 : src->positions == NULL && src->vertex_count > 0 ? "src->positions is NULL with vertex_count > 0"
                                                                  : "src->triangles is NULL with face_count > 0",
                 0, 0);
        return LS_ERR_INVALID;
    }
    st = check_mesh(src, "face index out of range", "vertex coordinate not finite", diag);
    if (st != LS_OK) return st;
    st = one_way(src, target, samples, &r);
    if (st != LS_OK) {
        diag_set(diag, st, "closest-point query failed", 0, 0);
        return st;
    }
    *out = r;
    return LS_OK;
}

/* The parallel path (ls_mesh_distance_parallel with workers > 1): each
 * direction in rounds of DIST_ROUND points. The calling thread hands out
 * the round's points (vertices, or face samples with their faces from the
 * area walk), the workers find their closest points in slices, each into
 * the point's own entry, and the calling thread adds the round's distances
 * and angles in point order: the operations and the order of one_way, so
 * the same bits (the closest point does not depend on the guess). */
#define DIST_ROUND 4096u
#define DIST_SLICES_PER_WORKER 4u

typedef struct dist_round {
    const ls_mesh *src;
    const ls_bvh *target;
    uint32_t first;      /* the round's first vertex or sample index */
    uint32_t count;      /* its points */
    uint32_t slices;
    int faces;           /* 0: vertices, 1: face samples (face[] holds their faces) */
    uint32_t *face;      /* DIST_ROUND */
    ls_real *dist;       /* DIST_ROUND */
    ls_real *angle;      /* DIST_ROUND: -1 when a normal is zero */
    ls_status st[32]; /* a status per slice: at most 32 slices */
} dist_round;

static ls_status dist_point(const dist_round *r, uint32_t i, uint32_t *guess)
{
    return closest_of(r->src, r->target, r->faces ? r->face[i] : UINT32_MAX, r->first + i, guess, &r->dist[i],
                      &r->angle[i]);
}

static void round_task(void *arg, uint32_t index, uint32_t worker)
{
    dist_round *r = (dist_round *)arg;
    const uint32_t lo = (uint32_t)((uint64_t)r->count * index / r->slices);
    const uint32_t hi = (uint32_t)((uint64_t)r->count * (index + 1u) / r->slices);
    uint32_t i, guess = UINT32_MAX;
    ls_status st = LS_OK;
    (void)worker;
    for (i = lo; i < hi && st == LS_OK; i++) st = dist_point(r, i, &guess);
    r->st[index] = st;
}

static ls_status run_round(dist_round *r, const ls_parallel *par, uint32_t workers)
{
    uint32_t k, most = (uint32_t)(sizeof r->st / sizeof r->st[0]);
    r->slices = workers * DIST_SLICES_PER_WORKER < most ? workers * DIST_SLICES_PER_WORKER : most;
    if (r->slices > r->count) r->slices = r->count;
    ls_parallel_run(par, workers, r->slices, round_task, r);
    for (k = 0; k < r->slices; k++)
        if (r->st[k] != LS_OK) return r->st[k];
    return LS_OK;
}

/* one_way on the workers; r's arrays from the caller. */
static ls_status one_way_rounds(dist_round *r, const ls_parallel *par, uint32_t workers, uint32_t samples,
                                ls_dist_one_way *out)
{
    const ls_mesh *src = r->src;
    acc av, af, an;
    sampler sm;
    uint32_t f = 0, left = 0, i; /* the walk: face f still has `left` samples to hand out */
    ls_status st;
    acc_init(&av);
    acc_init(&af);
    acc_init(&an);
    r->faces = 0;
    for (r->first = 0; r->first < src->vertex_count; r->first += r->count) {
        r->count = src->vertex_count - r->first < DIST_ROUND ? src->vertex_count - r->first : DIST_ROUND;
        st = run_round(r, par, workers);
        if (st != LS_OK) return st;
        for (i = 0; i < r->count; i++) acc_add(&av, r->dist[i], r->first + i);
    }
    memset(&sm, 0, sizeof sm);
    sm.total = total_area2(src);
    sm.n = sm.total > 0 ? samples : 0u;
    r->faces = 1;
    r->first = 0;
    while (sm.n > 0) {
        r->count = 0;
        while (r->count < DIST_ROUND) {
            if (left == 0) {
                ls_real n1[3];
                if (f == src->face_count) break;
                face_cross(src, f, n1);
                left = sampler_next(&sm, norm3(n1), f + 1u == src->face_count);
                f++;
                continue;
            }
            r->face[r->count++] = f - 1u;
            left--;
        }
        if (r->count == 0) break;
        st = run_round(r, par, workers);
        if (st != LS_OK) return st;
        for (i = 0; i < r->count; i++) {
            acc_add(&af, r->dist[i], r->first + i);
            if (r->angle[i] >= 0) acc_add(&an, r->angle[i], r->first + i);
        }
        r->first += r->count;
    }
    acc_get(&av, &out->vertex);
    acc_get(&af, &out->face);
    acc_get(&an, &out->normal);
    return LS_OK;
}

/* The staging arrays of the parallel path. */
static void round_sizes(ls_size *s)
{
    ls_size_add(s, DIST_ROUND, sizeof(uint32_t));
    ls_size_add(s, DIST_ROUND, sizeof(ls_real));
    ls_size_add(s, DIST_ROUND, sizeof(ls_real));
}

ls_status ls_mesh_distance_parallel_bytes(uint32_t faces_a, uint32_t faces_b, uint32_t workers, size_t *bytes)
{
    size_t whole = 0, ta, fa, tb, fb, held;
    ls_size s;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (workers == 0) return LS_ERR_INVALID;
    st = ls_mesh_distance_bytes(faces_a, faces_b, &whole);
    if (st != LS_OK || workers == 1u) {
        *bytes = whole;
        return st;
    }
    /* the two trees and their frames, then the rounds' arrays */
    if ((st = ls_bvh_tree_bytes(faces_a, &ta)) != LS_OK) return st;
    if ((st = ls_bvh_tree_bytes(faces_b, &tb)) != LS_OK) return st;
    if ((st = ls_bvh_frames_bytes(faces_a, &fa)) != LS_OK) return st;
    if ((st = ls_bvh_frames_bytes(faces_b, &fb)) != LS_OK) return st;
    ls_size_init(&s);
    ls_size_add(&s, ta, 1);
    ls_size_add(&s, tb, 1);
    ls_size_add(&s, fa, 1);
    ls_size_add(&s, fb, 1);
    round_sizes(&s);
    if ((st = ls_size_get(&s, &held)) != LS_OK) return st;
    *bytes = held > whole ? held : whole;
    return LS_OK;
}

ls_status ls_mesh_distance_bytes(uint32_t faces_a, uint32_t faces_b, size_t *bytes)
{
    size_t ta, tb, ba, bb, fa, fb, keep_b, a_peak, x;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if ((st = ls_bvh_bytes(faces_a, &ba)) != LS_OK) return st;
    if ((st = ls_bvh_bytes(faces_b, &bb)) != LS_OK) return st;
    if ((st = ls_bvh_tree_bytes(faces_a, &ta)) != LS_OK) return st;
    if ((st = ls_bvh_tree_bytes(faces_b, &tb)) != LS_OK) return st;
    if ((st = ls_bvh_frames_bytes(faces_a, &fa)) != LS_OK) return st;
    if ((st = ls_bvh_frames_bytes(faces_b, &fb)) != LS_OK) return st;
    /* B's tree and frames are built first and kept while A's are built (its
     * build's scratch, then its frames beside its tree) */
    if ((st = ls_size_sum(tb, fb, &keep_b)) != LS_OK) return st;
    if ((st = ls_size_sum(ta, fa, &a_peak)) != LS_OK) return st;
    if (ba > a_peak) a_peak = ba;
    if ((st = ls_size_sum(keep_b, a_peak, &x)) != LS_OK) return st;
    *bytes = x > bb ? x : bb;
    return LS_OK;
}

ls_status ls_mesh_distance(const ls_mesh *a, const ls_mesh *b, uint32_t samples_a, uint32_t samples_b,
                           ls_arena *arena, ls_distance_report *out, ls_diag *diag)
{
    const uint32_t samples[2] = {samples_a, samples_b};
    return ls_mesh_distance_parallel(a, b, samples, NULL, 1u, arena, out, diag);
}

ls_status ls_mesh_distance_parallel(const ls_mesh *a, const ls_mesh *b, const uint32_t samples[2], const ls_parallel *par,
                                    uint32_t workers, ls_arena *arena, ls_distance_report *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_bvh ta, tb;
    ls_distance_report r;
    ls_real lo[3], hi[3], d[3];
    ls_status st;
    uint32_t k;
    if (workers == 0u || samples == NULL) {
        diag_set(diag, LS_ERR_INVALID, workers == 0u ? "workers: 0; at least 1" : "samples is NULL", 0, 0);
        return LS_ERR_INVALID;
    }
    if (a == NULL || b == NULL || arena == NULL || out == NULL || a->face_count == 0 || b->face_count == 0 ||
        a->triangles == NULL || b->triangles == NULL || a->positions == NULL || b->positions == NULL) {
        diag_set(diag, LS_ERR_INVALID,
                 a == NULL               ? "a is NULL"
                 : b == NULL             ? "b is NULL"
                 : arena == NULL         ? "arena is NULL"
                 : out == NULL           ? "out is NULL"
                 : a->face_count == 0    ? "a->face_count: 0; at least one face"
                 : b->face_count == 0    ? "b->face_count: 0; at least one face"
                 : a->triangles == NULL  ? "a->triangles is NULL"
                 : b->triangles == NULL  ? "b->triangles is NULL"
                 : a->positions == NULL  ? "a->positions is NULL"
                                         : "b->positions is NULL",
                 0, 0);
        return LS_ERR_INVALID;
    }
    st = check_mesh(a, "mesh A: face index out of range", "mesh A: vertex coordinate not finite", diag);
    if (st == LS_OK) st = check_mesh(b, "mesh B: face index out of range", "mesh B: vertex coordinate not finite", diag);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    /* oriented boxes too: samples of a fan or of slivers lie in the
     * axis-aligned boxes of a fixed share of the faces */
    st = ls_bvh_build(b, arena, &tb, NULL);
    if (st == LS_OK) st = ls_bvh_build_frames(&tb, arena, NULL);
    if (st == LS_OK) st = ls_bvh_build(a, arena, &ta, NULL);
    if (st == LS_OK) st = ls_bvh_build_frames(&ta, arena, NULL);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        diag_set(diag, st, st == LS_ERR_NOMEM ? "arena too small for the two BVHs" : "BVH build failed", 0, 0);
        return st;
    }
    memset(&r, 0, sizeof r);
    if (workers > 1u && par != NULL && par->run != NULL) {
        dist_round rd;
        rd.face = (uint32_t *)ls_arena_alloc(arena, DIST_ROUND, sizeof(uint32_t));
        rd.dist = (ls_real *)ls_arena_alloc(arena, DIST_ROUND, sizeof(ls_real));
        rd.angle = (ls_real *)ls_arena_alloc(arena, DIST_ROUND, sizeof(ls_real));
        st = rd.face != NULL && rd.dist != NULL && rd.angle != NULL ? LS_OK : LS_ERR_NOMEM;
        if (st == LS_ERR_NOMEM) {
            ls_arena_restore(arena, mark);
            diag_set(diag, st, "arena too small for the two BVHs and the rounds' arrays", 0, 0);
            return st;
        }
        rd.src = a;
        rd.target = &tb;
        st = one_way_rounds(&rd, par, workers, samples[0], &r.ab);
        rd.src = b;
        rd.target = &ta;
        if (st == LS_OK) st = one_way_rounds(&rd, par, workers, samples[1], &r.ba);
    } else {
        st = one_way(a, &tb, samples[0], &r.ab);
        if (st == LS_OK) st = one_way(b, &ta, samples[1], &r.ba);
    }
    ls_arena_restore(arena, mark);
    if (st != LS_OK) {
        diag_set(diag, st, "closest-point query failed", 0, 0);
        return st;
    }
    r.vertex_hausdorff = r.ab.vertex.max > r.ba.vertex.max ? r.ab.vertex.max : r.ba.vertex.max;
    r.hausdorff = r.vertex_hausdorff;
    if (r.ab.face.max > r.hausdorff) r.hausdorff = r.ab.face.max;
    if (r.ba.face.max > r.hausdorff) r.hausdorff = r.ba.face.max;
    {
        /* face samples when there are any, else vertices */
        const ls_dist_stats *sa = r.ab.face.count > 0 ? &r.ab.face : &r.ab.vertex;
        const ls_dist_stats *sb = r.ba.face.count > 0 ? &r.ba.face : &r.ba.vertex;
        r.mean = (sa->mean + sb->mean) * (ls_real)0.5;
        r.rms = LS_RSQRT((sa->rms * sa->rms + sb->rms * sb->rms) * (ls_real)0.5);
    }
    ls_mesh_bounds(b, lo, hi);
    for (k = 0; k < 3u; k++) d[k] = hi[k] - lo[k];
    r.diag = norm3(d);
    if (r.diag > 0) {
        r.vertex_hausdorff_rel = r.vertex_hausdorff / r.diag;
        r.hausdorff_rel = r.hausdorff / r.diag;
        r.mean_rel = r.mean / r.diag;
        r.rms_rel = r.rms / r.diag;
    }
    *out = r;
    return LS_OK;
}

ls_status ls_distance_sample_point(const ls_mesh *mesh, uint32_t samples, uint32_t k, uint32_t *face, ls_real point[3])
{
    sampler sm;
    uint32_t f;
    if (mesh == NULL || face == NULL || point == NULL || k >= samples || mesh->triangles == NULL ||
        mesh->positions == NULL)
        return LS_ERR_INVALID;
    if (ls_bvh_check_mesh(mesh, NULL) != LS_OK) return LS_ERR_MESH;
    memset(&sm, 0, sizeof sm);
    sm.total = total_area2(mesh);
    sm.n = samples;
    if (!(sm.total > 0)) return LS_ERR_INVALID;
    for (f = 0; f < mesh->face_count; f++) {
        ls_real n[3];
        uint32_t begin = sm.end;
        face_cross(mesh, f, n);
        sampler_next(&sm, norm3(n), f + 1u == mesh->face_count);
        if (k < sm.end && k >= begin) {
            *face = f;
            sample_in_face(mesh, f, k, point);
            return LS_OK;
        }
    }
    return LS_ERR_INVALID;
}
