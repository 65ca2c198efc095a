/* tests/bench/bench_distance.c - the distance-metric benchmark: BVH build
 * time and bytes, closest-point query throughput, brute force on a subsample
 * (speed ratio and agreement), ls_mesh_distance (vertex-only and dense) and
 * ls_tangle times for a mesh against a perturbed copy of itself.
 *
 *   bench_distance MESH [OTHER_MESH ...] --out DIR [--repeat R] [--queries N]
 *
 * The first mesh is the main one (armadillo): its perturbed copy (every
 * vertex moved by a pseudo-random vector of up to 0.5 % of the bounding-box
 * diagonal per coordinate) is written to DIR/perturbed.obj, the query points
 * (face samples of the mesh moved by up to 1 % of the diagonal per
 * coordinate) to DIR/queries.txt and our answers (face, squared distance) to
 * DIR/ours.txt, for the CGAL peer (peer_cgal_distance.cpp). Times are CPU time, the
 * minimum of R runs. Output: one "key value" line per figure. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <largesteps.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint64_t lcg_state = 0x9e3779b97f4a7c15ull;
static double urand(void) /* [0, 1) */
{
    lcg_state = lcg_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(lcg_state >> 11) * (1.0 / 9007199254740992.0);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n + 16);
    if (p == NULL) {
        fprintf(stderr, "bench_distance: out of memory\n");
        exit(1);
    }
    return p;
}

static int load(const char *path, ls_mesh *m)
{
    FILE *f = fopen(path, "rb");
    unsigned char *data;
    long n;
    size_t bytes;
    ls_mesh_file_info info;
    ls_arena a;
    void *buf;
    if (f == NULL) return 0;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    data = (unsigned char *)xmalloc((size_t)n);
    if (fread(data, 1, (size_t)n, f) != (size_t)n) {
        fclose(f);
        return 0;
    }
    fclose(f);
    if (ls_mesh_read_info(data, (size_t)n, LS_MESH_FORMAT_AUTO, &info, NULL) != LS_OK) return 0;
    if (ls_mesh_read_bytes(&info, &bytes) != LS_OK) return 0;
    buf = xmalloc(bytes);
    ls_arena_init(&a, buf, bytes);
    if (ls_mesh_read(data, (size_t)n, info.format, &a, m, NULL) != LS_OK) return 0;
    free(data);
    return 1;
}

static const char *base_name(const char *p)
{
    const char *s = strrchr(p, '/');
    return s != NULL ? s + 1 : p;
}

static double diag_of(const ls_mesh *m)
{
    ls_real lo[3], hi[3];
    double s = 0;
    int k;
    ls_mesh_bounds(m, lo, hi);
    for (k = 0; k < 3; k++) s += ((double)hi[k] - (double)lo[k]) * ((double)hi[k] - (double)lo[k]);
    return sqrt(s);
}

/* BVH build: minimum time of `repeat` runs, bytes. */
static void bench_build(const char *name, const ls_mesh *m, int repeat)
{
    size_t bytes, tree;
    double best = 1e300;
    int r;
    void *buf;
    ls_bvh b;
    ls_bvh_bytes(m->face_count, &bytes);
    ls_bvh_tree_bytes(m->face_count, &tree);
    buf = xmalloc(bytes);
    for (r = 0; r < repeat; r++) {
        ls_arena a;
        double t0, t1;
        ls_arena_init(&a, buf, bytes);
        t0 = now_ms();
        if (ls_bvh_build(m, &a, &b, NULL) != LS_OK) {
            fprintf(stderr, "bench_distance: build failed\n");
            exit(1);
        }
        t1 = now_ms();
        if (t1 - t0 < best) best = t1 - t0;
    }
    printf("build %s faces %u nodes %u depth %u ms %.3f bytes %lu tree_bytes %lu\n", name, (unsigned)m->face_count,
           (unsigned)b.node_count, (unsigned)b.depth, best, (unsigned long)bytes, (unsigned long)tree);
    free(buf);
}

int main(int argc, char **argv)
{
    const char *out = "build/bench", *paths[8];
    int npaths = 0, repeat = 3, i, r;
    uint32_t nq = 100000, k, v;
    ls_mesh A, B;
    char fname[1024];
    FILE *f;
    double d, t0, t1, best;
    ls_real *q;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out = argv[++i];
        else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = atoi(argv[++i]);
        else if (strcmp(argv[i], "--queries") == 0 && i + 1 < argc) nq = (uint32_t)atol(argv[++i]);
        else if (npaths < 8) paths[npaths++] = argv[i];
    }
    if (npaths == 0 || repeat < 1) {
        fprintf(stderr, "usage: bench_distance MESH [MESH ...] --out DIR [--repeat R] [--queries N]\n");
        return 2;
    }
    for (i = 0; i < npaths; i++) {
        ls_mesh m;
        if (!load(paths[i], &m)) {
            fprintf(stderr, "bench_distance: cannot read %s\n", paths[i]);
            return 1;
        }
        bench_build(base_name(paths[i]), &m, repeat);
        if (i == 0) A = m;
    }
    /* the perturbed copy */
    d = diag_of(&A);
    B = A;
    B.positions = (ls_real *)xmalloc(3 * sizeof(ls_real) * A.vertex_count);
    for (v = 0; v < 3 * A.vertex_count; v++) B.positions[v] = (ls_real)((double)A.positions[v] + 0.001 * d * (2 * urand() - 1));
    snprintf(fname, sizeof fname, "%s/perturbed.obj", out);
    f = fopen(fname, "wb");
    if (f == NULL) return 1;
    for (v = 0; v < A.vertex_count; v++)
        fprintf(f, "v %.17g %.17g %.17g\n", (double)B.positions[3 * v], (double)B.positions[3 * v + 1],
                (double)B.positions[3 * v + 2]);
    for (k = 0; k < A.face_count; k++)
        fprintf(f, "f %u %u %u\n", A.triangles[3 * k] + 1, A.triangles[3 * k + 1] + 1, A.triangles[3 * k + 2] + 1);
    fclose(f);
    /* query points: face samples of A, moved */
    q = (ls_real *)xmalloc(3 * sizeof(ls_real) * nq);
    for (k = 0; k < nq; k++) {
        uint32_t fc = (uint32_t)(urand() * A.face_count) % A.face_count;
        double u = urand(), w = urand();
        int c;
        if (u + w > 1) {
            u = 1 - u;
            w = 1 - w;
        }
        for (c = 0; c < 3; c++) {
            double a0 = (double)A.positions[3 * A.triangles[3 * fc] + c], a1 = (double)A.positions[3 * A.triangles[3 * fc + 1] + c],
                   a2 = (double)A.positions[3 * A.triangles[3 * fc + 2] + c];
            q[3 * k + c] = (ls_real)(a0 + u * (a1 - a0) + w * (a2 - a0) + 0.01 * d * (2 * urand() - 1));
        }
    }
    snprintf(fname, sizeof fname, "%s/queries.txt", out);
    f = fopen(fname, "wb");
    if (f == NULL) return 1;
    fprintf(f, "%u\n", (unsigned)nq);
    for (k = 0; k < nq; k++) fprintf(f, "%.17g %.17g %.17g\n", (double)q[3 * k], (double)q[3 * k + 1], (double)q[3 * k + 2]);
    fclose(f);
    {
        /* closest-point throughput on A's tree, and brute force on the first 1000 */
        size_t bytes;
        void *buf;
        ls_arena a;
        ls_bvh b;
        double sum = 0, bf_ms, bvh_ms_sub;
        uint32_t agree = 0, nb = nq < 1000 ? nq : 1000;
        ls_bvh_bytes(A.face_count, &bytes);
        buf = xmalloc(bytes);
        ls_arena_init(&a, buf, bytes);
        ls_bvh_build(&A, &a, &b, NULL);
        best = 1e300;
        for (r = 0; r < repeat; r++) {
            sum = 0;
            t0 = now_ms();
            for (k = 0; k < nq; k++) {
                ls_bvh_hit h;
                ls_bvh_closest(&b, q + 3 * k, LS_REAL_MAX, &h);
                sum += sqrt((double)h.dist2);
            }
            t1 = now_ms();
            if (t1 - t0 < best) best = t1 - t0;
        }
        printf("queries %s n %u ms %.3f per_s %.0f sum_dist %.12g\n", base_name(paths[0]), (unsigned)nq, best,
               nq / (best * 1e-3), sum);
        /* our answers, for the peer's agreement count */
        snprintf(fname, sizeof fname, "%s/ours.txt", out);
        f = fopen(fname, "wb");
        if (f == NULL) return 1;
        for (k = 0; k < nq; k++) {
            ls_bvh_hit h;
            ls_bvh_closest(&b, q + 3 * k, LS_REAL_MAX, &h);
            fprintf(f, "%u %.17g\n", (unsigned)h.face, (double)h.dist2);
        }
        fclose(f);
        t0 = now_ms();
        for (k = 0; k < nb; k++) {
            ls_bvh_hit h;
            ls_bvh_closest(&b, q + 3 * k, LS_REAL_MAX, &h);
        }
        bvh_ms_sub = now_ms() - t0;
        t0 = now_ms();
        for (k = 0; k < nb; k++) {
            ls_bvh_hit h, g;
            uint32_t fc;
            g.face = UINT32_MAX;
            g.dist2 = 0;
            for (fc = 0; fc < A.face_count; fc++) {
                const uint32_t *t = A.triangles + 3 * fc;
                ls_real pt[3], ba[3], d2;
                ls_closest_point_triangle(q + 3 * k, A.positions + 3 * t[0], A.positions + 3 * t[1], A.positions + 3 * t[2],
                                          pt, ba, &d2);
                if (g.face == UINT32_MAX || d2 < g.dist2) {
                    g.face = fc;
                    g.dist2 = d2;
                }
            }
            ls_bvh_closest(&b, q + 3 * k, LS_REAL_MAX, &h);
            agree += h.face == g.face && h.dist2 == g.dist2;
        }
        bf_ms = now_ms() - t0;
        printf("brute %s n %u agree %u brute_ms_per_query %.4f bvh_ms_per_query %.6f ratio %.0f\n", base_name(paths[0]),
               (unsigned)nb, (unsigned)agree, bf_ms / nb, best / nq, (bf_ms / nb) / (best / nq));
        (void)bvh_ms_sub;
        free(buf);
    }
    {
        /* metrics: vertex-only and dense, A against its perturbed copy */
        size_t bytes;
        void *buf;
        ls_arena a;
        ls_distance_report rep;
        ls_tangle_report tr;
        uint32_t s = ls_distance_default_samples(&A);
        ls_mesh_distance_bytes(A.face_count, B.face_count, &bytes);
        buf = xmalloc(bytes);
        for (i = 0; i < 2; i++) {
            uint32_t ns = i == 0 ? 0 : s;
            best = 1e300;
            for (r = 0; r < repeat; r++) {
                ls_arena_init(&a, buf, bytes);
                t0 = now_ms();
                if (ls_mesh_distance(&A, &B, ns, ns, &a, &rep, NULL) != LS_OK) return 1;
                t1 = now_ms();
                if (t1 - t0 < best) best = t1 - t0;
            }
            printf("metric %s samples %u ms %.3f bytes %lu H_vertex %.9g H %.9g mean %.9g rms %.9g diag %.9g "
                   "normal_mean_deg %.4g\n",
                   i == 0 ? "vertex" : "dense", (unsigned)ns, best, (unsigned long)bytes, (double)rep.vertex_hausdorff,
                   (double)rep.hausdorff, (double)rep.mean, (double)rep.rms, (double)rep.diag,
                   (double)rep.ab.normal.mean);
        }
        free(buf);
        ls_tangle_bytes(B.face_count, &bytes);
        buf = xmalloc(bytes);
        best = 1e300;
        for (r = 0; r < repeat; r++) {
            ls_arena_init(&a, buf, bytes);
            t0 = now_ms();
            if (ls_tangle(&B, &A, &a, &tr, NULL) != LS_OK) return 1;
            t1 = now_ms();
            if (t1 - t0 < best) best = t1 - t0;
        }
        printf("tangle perturbed ms %.3f bytes %lu pairs %u faces %u inverted %u angle_p1 %.3f angle_p50 %.3f "
               "quality_p1 %.4f\n",
               best, (unsigned long)bytes, (unsigned)tr.intersecting_pairs, (unsigned)tr.intersecting_faces,
               (unsigned)tr.inverted_faces, (double)tr.angle_p1, (double)tr.angle_p50, (double)tr.quality_p1);
        free(buf);
    }
    return 0;
}
