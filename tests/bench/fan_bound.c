/* tests/bench/fan_bound.c - the closest-point work on overlapping boxes.
 *
 *   fan_bound MESH [QUERIES]
 *
 * For QUERIES points inside MESH's faces (10 per face on a stride of faces;
 * not on corners, where a fan's centre ties with every face): the
 * brute-force count of triangles whose axis-aligned bounding box, grown by
 * the query's rounding slack, contains the query (every exact search that
 * prunes with axis-aligned boxes alone must evaluate each of them, whatever
 * its traversal order: on a triangle fan the count grows with the number of
 * faces), and the time of ls_bvh_closest per query with the tree's oriented
 * boxes (ls_bvh_build_frames) and without. Output: "key value" lines. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <math.h>
#include <largesteps.h>
#include "ls_posix.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int main(int argc, char **argv)
{
    ls_mesh m;
    ls_arena a;
    ls_bvh b, plain;
    ls_diag d;
    size_t need = (size_t)1 << 30;
    void *buf = malloc(need);
    uint32_t f, k, q = 0, want = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : 20000u, stride;
    unsigned long long contain = 0;
    double t = 0, t_plain = 0, t0;
    if (argc < 2 || buf == NULL || ls_arena_init(&a, buf, need) != LS_OK) return 2;
    if (ls_posix_load_mesh(argv[1], &a, &m, &d) != LS_OK || ls_bvh_build(&m, &a, &b, &d) != LS_OK) return 1;
    plain = b;
    if (ls_bvh_build_frames(&b, &a, &d) != LS_OK) return 1;
    stride = m.face_count / (want / 10u + 1u) + 1u;
    for (f = 0; f < m.face_count && q < want; f += stride) {
        for (k = 0; k < 10u; k++, q++) {
            const uint32_t *tri = m.triangles + 3u * (size_t)f;
            double u = (double)(k + 1u) * 0.618034 - (double)(int)((double)(k + 1u) * 0.618034);
            double v = (double)(k + 1u) * 0.41421 - (double)(int)((double)(k + 1u) * 0.41421);
            ls_real p[3], lim = 0;
            ls_bvh_hit h;
            uint32_t j, g;
            if (u + v > 1) u = 1 - u, v = 1 - v;
            for (j = 0; j < 3u; j++) {
                const ls_real *P = m.positions;
                p[j] = P[3u * tri[0] + j] + (ls_real)u * (P[3u * tri[1] + j] - P[3u * tri[0] + j]) +
                       (ls_real)v * (P[3u * tri[2] + j] - P[3u * tri[0] + j]);
            }
            t0 = now_ms();
            (void)ls_bvh_closest(&b, p, LS_REAL_MAX, &h);
            t += now_ms() - t0;
            if (q < 200u) { /* without the oriented boxes: slow on fans, a few queries */
                t0 = now_ms();
                (void)ls_bvh_closest(&plain, p, LS_REAL_MAX, &h);
                t_plain += now_ms() - t0;
            }
            /* the rounding slack of ls_bvh_closest: 256 eps x the largest coordinate */
            for (j = 0; j < 3u; j++) {
                ls_real x = b.nodes[0].hi[j] > -b.nodes[0].lo[j] ? b.nodes[0].hi[j] : -b.nodes[0].lo[j];
                if (x > lim) lim = x;
            }
            lim = (ls_real)256 * LS_REAL_EPSILON * lim + (ls_real)sqrt((double)h.dist2);
            for (g = 0; g < m.face_count; g++) {
                const uint32_t *s = m.triangles + 3u * (size_t)g;
                int in = 1;
                for (j = 0; j < 3u && in; j++) {
                    ls_real lo = m.positions[3u * s[0] + j], hi = lo, x;
                    uint32_t c;
                    for (c = 1; c < 3u; c++) {
                        x = m.positions[3u * s[c] + j];
                        if (x < lo) lo = x;
                        if (x > hi) hi = x;
                    }
                    if (p[j] < lo - lim || p[j] > hi + lim) in = 0;
                }
                contain += (unsigned long long)in;
            }
        }
    }
    printf("faces %u\nqueries %u\nboxes_within_slack_per_query %.1f\nus_per_query %.2f\nus_per_query_axis_aligned %.2f\n",
           (unsigned)m.face_count, (unsigned)q, (double)contain / (double)q, 1e3 * t / (double)q,
           1e3 * t_plain / (double)(q < 200u ? q : 200u));
    free(buf);
    return 0;
}
