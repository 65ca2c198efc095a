/* tests/bench/bench_refine.c - cost and accuracy of the adaptive
 * supersampling of silhouette pixels (largesteps/raster_refine.h).
 *
 * A mesh seen from N views on a Fibonacci sphere (45 degrees, margin 1.1),
 * SH shading, S = 1. Per A in {off, 4, 8, 16}: the forward per view (raster
 * + shade + refine; process CPU time, the minimum over REPS repetitions of
 * all views), the refine pass alone, its interior backward (refined) against
 * ls_shade_backward, the edge pixels per view, the exact scratch; and the
 * error of the image in the edge pixels (max over pixels and RGBA channels,
 * and the mean of the per-pixel max) against the image refined with
 * A = LS_REFINE_MAX (32), the stand-in for the box value (itself within
 * 1/32 of it per straight edge). Writes a Markdown table to stdout.
 *
 *   make build/bench/bench_refine
 *   build/bench/bench_refine MESH [RES [VIEWS [REPS]]]
 */
#define _POSIX_C_SOURCE 200112L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <largesteps.h>
#include "ls_posix.h"
#include "mesh_view.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}


int main(int argc, char **argv)
{
    static const uint32_t aas[4] = {0, 4, 8, 16};
    size_t cap = (size_t)1 << 30, npx, p;
    unsigned char *buf;
    ls_arena arena;
    ls_mesh m;
    ls_edge_table et;
    ls_camera_framing fr;
    ls_vis vis;
    ls_shade_opts o;
    ls_shade_grads g;
    ls_real *dirs, *mvps, *nrm, *img, *ref, *gimg, *gp, *gn;
    uint32_t res = argc > 2 ? (uint32_t)atoi(argv[2]) : 128u, views = argc > 3 ? (uint32_t)atoi(argv[3]) : 8u;
    uint32_t reps = argc > 4 ? (uint32_t)atoi(argv[4]) : 3u, v, r, a;
    if (argc < 2) {
        fprintf(stderr, "usage: %s MESH [RES [VIEWS [REPS]]]\n", argv[0]);
        return 2;
    }
    buf = (unsigned char *)malloc(cap);
    if (buf == NULL || ls_arena_init(&arena, buf, cap) != LS_OK) return 1;
    if (ls_posix_load_mesh(argv[1], &arena, &m, NULL) != LS_OK) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    if (ls_camera_frame(m.positions, m.vertex_count, (ls_real)(45.0 * 3.14159265358979323846 / 180.0), LS_FOV_X, 1,
                        (ls_real)1.1, &fr, NULL) != LS_OK)
        return 1;
    npx = (size_t)res * res;
    dirs = (ls_real *)ls_arena_alloc(&arena, 3u * views, sizeof(ls_real));
    mvps = (ls_real *)ls_arena_alloc(&arena, 16u * views, sizeof(ls_real));
    nrm = (ls_real *)ls_arena_alloc(&arena, 3u * (size_t)m.vertex_count, sizeof(ls_real));
    gp = (ls_real *)ls_arena_alloc(&arena, 3u * (size_t)m.vertex_count, sizeof(ls_real));
    gn = (ls_real *)ls_arena_alloc(&arena, 3u * (size_t)m.vertex_count, sizeof(ls_real));
    img = (ls_real *)ls_arena_alloc(&arena, 4u * npx, sizeof(ls_real));
    ref = (ls_real *)ls_arena_alloc(&arena, 4u * npx, sizeof(ls_real));
    gimg = (ls_real *)ls_arena_alloc(&arena, 4u * npx, sizeof(ls_real));
    if (gimg == NULL || ls_vis_init(&vis, &arena, res, res, 1, m.vertex_count) != LS_OK ||
        ls_edge_table_build(&et, m.triangles, m.face_count, m.vertex_count, &arena, NULL) != LS_OK)
        return 1;
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = mv_sh;
    o.background[0] = o.background[1] = o.background[2] = (ls_real)0.2;
    (void)ls_camera_fibonacci_dirs(views, dirs);
    for (v = 0; v < views; v++) (void)ls_camera_framed_view(&fr, dirs + 3u * v, NULL, mvps + 16u * v);
    for (p = 0; p < 4u * npx; p++) gimg[p] = (ls_real)((p * 2654435761u) % 1000u) * (ls_real)1e-3 - (ls_real)0.5;
    if (ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, nrm, NULL) != LS_OK) return 1;
    printf("mesh %s: %u vertices, %u faces, %u views at %u^2, S = 1, SH shading (%s)\n\n", argv[1],
           (unsigned)m.vertex_count, (unsigned)m.face_count, (unsigned)views, (unsigned)res, LS_REAL_NAME);
    printf("| A | forward ms/view | refine ms/view | shading backward ms/view | edge pixels/view | scratch bytes | "
           "max error | mean error |\n|---|---|---|---|---|---|---|---|\n");
    for (a = 0; a < 4; a++) {
        double tf = 1e300, tr = 1e300, tb = 1e300, emax = 0, esum = 0;
        size_t scr = 0, edge = 0, nerr = 0;
        for (r = 0; r < reps; r++) {
            double f = 0, rf = 0, b = 0;
            for (v = 0; v < views; v++) {
                ls_refine_info info;
                double t0 = now_ms(), t1;
                if (ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                        .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = mvps + 16u * v}, &arena,
                        NULL) != LS_OK ||
                    ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                            .vertex_count = m.vertex_count, .normals = nrm, .opts = &o}, img, NULL) != LS_OK)
                    return 1;
                t1 = now_ms();
                if (ls_refine_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                        .vertex_count = m.vertex_count, .normals = nrm, .opts = &o, .table = &et}, aas[a], img, &arena,
                        &info, NULL) != LS_OK)
                    return 1;
                rf += now_ms() - t1;
                f += now_ms() - t0;
                memset(&g, 0, sizeof g);
                g.positions = gp;
                g.normals = gn;
                t0 = now_ms();
                if (ls_refine_shade_backward(&(ls_view){.vis = &vis, .indices = m.triangles,
                        .triangle_count = m.face_count, .vertex_count = m.vertex_count, .normals = nrm, .opts = &o,
                        .mvp = mvps + 16u * v, .table = &et}, aas[a], gimg, &g, &arena, NULL) != LS_OK)
                    return 1;
                b += now_ms() - t0;
                if (r == 0) {
                    size_t bytes = 0;
                    if (ls_refine_scratch_bytes(&(ls_view){.vis = &vis, .indices = m.triangles,
                            .triangle_count = m.face_count, .table = &et}, aas[a], &bytes) != LS_OK) return 1;
                    if (bytes > scr) scr = bytes;
                    edge += info.pixels;
                    /* the error in the edge pixels of A = 32 */
                    {
                        static unsigned char *mk;
                        size_t q;
                        if (mk == NULL) mk = (unsigned char *)malloc(npx);
                        memcpy(ref, img, 4u * npx * sizeof(ls_real));
                        for (q = 0; q < npx; q++) ref[4 * q + 3] = (ls_real)-7;
                        if (ls_refine_shade(&(ls_view){.vis = &vis, .indices = m.triangles,
                                .triangle_count = m.face_count, .vertex_count = m.vertex_count, .normals = nrm,
                                .opts = &o, .table = &et}, LS_REFINE_MAX, ref, &arena, NULL, NULL) != LS_OK)
                            return 1;
                        if (ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                                .vertex_count = m.vertex_count, .normals = nrm, .opts = &o}, img, NULL) != LS_OK ||
                            ls_refine_shade(&(ls_view){.vis = &vis, .indices = m.triangles,
                                    .triangle_count = m.face_count, .vertex_count = m.vertex_count, .normals = nrm,
                                    .opts = &o, .table = &et}, aas[a], img, &arena, NULL, NULL) != LS_OK)
                            return 1;
                        for (q = 0; q < npx; q++) {
                            double e = 0;
                            int c;
                            if (ref[4 * q + 3] == (ls_real)-7) continue; /* not an edge pixel */
                            for (c = 0; c < 4; c++) {
                                double d = (double)img[4 * q + c] - (double)ref[4 * q + c];
                                if (d < 0) d = -d;
                                if (d > e) e = d;
                            }
                            if (e > emax) emax = e;
                            esum += e;
                            nerr++;
                        }
                    }
                }
            }
            if (f < tf) tf = f;
            if (rf < tr) tr = rf;
            if (b < tb) tb = b;
        }
        printf("| %s%u | %.3f | %.3f | %.3f | %.0f | %zu | %.4f | %.5f |\n", aas[a] == 0 ? "off " : "", (unsigned)aas[a],
               tf / views, tr / views, tb / views, (double)edge / views, scr, emax, nerr ? esum / (double)nerr : 0.0);
    }
    free(buf);
    return 0;
}
