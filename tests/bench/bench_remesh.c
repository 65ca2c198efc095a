/* tests/bench/bench_remesh.c - remeshing benchmark: ls_remesh on a mesh file
 * at h = FACTOR x mean edge length (Large Steps: 0.5), 5 iterations; time is
 * the minimum of REPEAT runs (CPU clock of the process). Prints one line, in
 * the same columns as tests/peers/cgal_remesh.cpp:
 *   ours <mesh> <V_in> <V_out> <F_out> <ms> <mean/h> <in_range> <amin> <a1> <a5> <a50> <haus/h> <bytes_used> <bound>
 * Edge statistics are over the 3 edges of every face; in_range is the
 * fraction in [4/5 h, 4/3 h]; angles in degrees; haus is the vertex-sampled
 * Hausdorff distance to the input, both directions (as libigl's hausdorff).
 * usage: bench_remesh MESH FACTOR [REPEAT] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <largesteps.h>
#include "../../port/posix/ls_posix.h"

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y ? 1 : 0;
}

static double one_sided(const ls_mesh *from, const ls_mesh *to)
{
    size_t need = 0;
    unsigned char *buf;
    ls_arena a;
    ls_bvh bvh;
    double worst = 0;
    uint32_t v;
    ls_bvh_bytes(to->face_count, &need);
    buf = (unsigned char *)malloc(need + 8);
    ls_arena_init(&a, buf, need);
    if (ls_bvh_build(to, &a, &bvh, NULL) != LS_OK) worst = -1;
    for (v = 0; worst >= 0 && v < from->vertex_count; v++) {
        ls_bvh_hit hit;
        if (ls_bvh_closest(&bvh, from->positions + 3u * v, LS_REAL_MAX, &hit) == LS_OK && sqrt((double)hit.dist2) > worst)
            worst = sqrt((double)hit.dist2);
    }
    free(buf);
    return worst;
}

static double cpu_ms(void) { return 1000.0 * (double)clock() / (double)CLOCKS_PER_SEC; }

int main(int argc, char **argv)
{
    unsigned char *data = NULL, *mbuf, *vbuf, *work;
    size_t bytes = 0, need = 0, vneed = 0, bound = 0, n, k, inside = 0;
    ls_mesh_file_info info;
    ls_mesh in, out;
    ls_mesh_report rep;
    ls_remesh_params p;
    ls_remesh_info ri;
    ls_arena a, va, wa;
    ls_real mean = 0;
    double factor, h, best = 1e300, sum = 0, *ang, haus;
    int repeat, r;
    uint32_t f, j;
    const char *name;
    if (argc < 3) {
        fprintf(stderr, "usage: bench_remesh MESH FACTOR [REPEAT]\n");
        return 2;
    }
    factor = atof(argv[2]);
    repeat = argc > 3 ? atoi(argv[3]) : 3;
    if (ls_posix_read_file(argv[1], &data, &bytes) != LS_OK || ls_mesh_read_info(data, bytes, 0, &info, NULL) != LS_OK ||
        ls_mesh_read_bytes(&info, &need) != LS_OK) {
        fprintf(stderr, "bench_remesh: cannot read %s\n", argv[1]);
        return 1;
    }
    mbuf = (unsigned char *)malloc(need + 8);
    ls_arena_init(&a, mbuf, need);
    if (ls_mesh_read(data, bytes, info.format, &a, &in, NULL) != LS_OK) return 1;
    ls_mesh_validate_bytes(&in, &vneed);
    vbuf = (unsigned char *)malloc(vneed + 8);
    ls_arena_init(&va, vbuf, vneed);
    if (ls_mesh_validate(&in, &va, &rep) != LS_OK || ls_remesh_mean_edge(&in, &mean) != LS_OK) return 1;
    h = factor * (double)mean;
    ls_remesh_params_default(&p, (ls_real)h);
    if (ls_remesh_bytes_bound(&in, &rep, &p, &bound) != LS_OK) return 1;
    work = (unsigned char *)malloc(bound + 8);
    for (r = 0; r < repeat; r++) {
        double t0;
        ls_status st;
        ls_arena_init(&wa, work, bound);
        t0 = cpu_ms();
        st = ls_remesh(&in, &p, &wa, &out, &ri, NULL);
        t0 = cpu_ms() - t0;
        if (st != LS_OK) {
            fprintf(stderr, "bench_remesh: %s: %s\n", argv[1], ls_status_name(st));
            return 1;
        }
        if (t0 < best) best = t0;
    }
    n = 3u * (size_t)out.face_count;
    ang = (double *)malloc(n * sizeof(double));
    for (f = 0, k = 0; f < out.face_count; f++)
        for (j = 0; j < 3; j++) {
            const ls_real *pa = out.positions + 3u * out.triangles[3u * f + j];
            const ls_real *pb = out.positions + 3u * out.triangles[3u * f + (j + 1) % 3];
            const ls_real *pc = out.positions + 3u * out.triangles[3u * f + (j + 2) % 3];
            double u[3], w[3], lu, lw, d;
            int q;
            for (q = 0; q < 3; q++) {
                u[q] = (double)pb[q] - (double)pa[q];
                w[q] = (double)pc[q] - (double)pa[q];
            }
            lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            lw = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            d = (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / (lu * lw);
            ang[k++] = acos(d > 1 ? 1 : d < -1 ? -1 : d) * 180.0 / 3.14159265358979323846;
            sum += lu;
            if (lu >= 0.8 * h && lu <= 4.0 / 3.0 * h) inside++;
        }
    qsort(ang, n, sizeof(double), cmp_d);
    haus = one_sided(&out, &in);
    if (one_sided(&in, &out) > haus) haus = one_sided(&in, &out);
    name = strrchr(argv[1], '/') != NULL ? strrchr(argv[1], '/') + 1 : argv[1];
    printf("ours %s %u %u %u %.3f %.4f %.4f %.2f %.2f %.2f %.2f %.4f %lu %lu\n", name, (unsigned)in.vertex_count,
           (unsigned)out.vertex_count, (unsigned)out.face_count, best, sum / (double)n / h, (double)inside / (double)n,
           ang[0], ang[n / 100], ang[n / 20], ang[n / 2], haus / h, (unsigned long)ri.bytes_used, (unsigned long)bound);
    free(ang);
    free(work);
    free(vbuf);
    free(mbuf);
    free(data);
    return 0;
}
