/* tests/bench/bench_silhouette.c - cost of the exact silhouette pass on the
 * fit's workload: a mesh (the current state of a fit, or any mesh) seen from
 * the fit's cameras (N views on a Fibonacci sphere framing the target, 45
 * degrees, margin 1.1), SH shading, the L1 gradient against the target's
 * render (one sample per pixel). The target is TARGET scaled by 1.02 about
 * its box centre and shifted by 1/200 of its box diagonal along x (so that
 * with TARGET = MESH the loss gradient is not zero and the hash checks
 * bits). Prints, per run, the silhouette pass time
 * per view (process CPU time, the minimum over REPS repetitions of all
 * views), the forward time per view, the scratch bytes of the pass and a
 * hash of the bits of the summed gradient (to check that a faster pass gives
 * the same bits).
 *
 *   make build/bench/bench_silhouette
 *   build/bench/bench_silhouette MESH [TARGET [RES [VIEWS [REPS]]]]
 *
 * TARGET defaults to MESH; RES 128, VIEWS 16, REPS 5. With BENCH_DUMP=FILE
 * set, the summed gradient of the first repetition is written to FILE (raw
 * ls_real values), to measure how far two builds' gradients differ.
 */
#define _POSIX_C_SOURCE 200112L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>
#include <largesteps.h>
#include "ls_posix.h"
#include "mesh_view.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}


static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *c = (const unsigned char *)p;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= c[i];
        h *= 1099511628211ull;
    }
    return h;
}

static int render(ls_vis *vis, ls_arena *a, const ls_real *mvp, const ls_mesh *m, ls_real *nrm, const ls_shade_opts *o,
                  ls_real *img)
{
    return ls_shade_vertex_normals(m->positions, m->vertex_count, m->triangles, m->face_count, nrm, NULL) == LS_OK &&
           ls_raster(vis, &(ls_view){.positions = m->positions, .indices = m->triangles,
                   .triangle_count = m->face_count, .vertex_count = m->vertex_count, .mvp = mvp}, a, NULL) == LS_OK &&
           ls_shade(&(ls_view){.vis = vis, .indices = m->triangles, .triangle_count = m->face_count,
                   .vertex_count = m->vertex_count, .normals = nrm, .opts = o}, img, NULL) == LS_OK;
}

int main(int argc, char **argv)
{
    size_t cap = (size_t)1 << 30, npx, maxscr = 0;
    unsigned char *buf;
    ls_arena arena;
    ls_mesh m, tg;
    ls_edge_table et;
    ls_camera_framing fr;
    ls_vis vis, tvis;
    ls_shade_opts o;
    ls_real *dirs, *mvps, *nrm, *tnrm, *img, **tgt, *gimg, *gp;
    uint32_t res = argc > 3 ? (uint32_t)atoi(argv[3]) : 128u, views = argc > 4 ? (uint32_t)atoi(argv[4]) : 16u;
    uint32_t reps = argc > 5 ? (uint32_t)atoi(argv[5]) : 5u, v, r;
    double sil = 1e300, fwd = 1e300;
    uint64_t hash = 1469598103934665603ull;
    ls_status st;
    if (argc < 2) {
        fprintf(stderr, "usage: %s MESH [TARGET [RES [VIEWS [REPS]]]]\n", argv[0]);
        return 2;
    }
    buf = (unsigned char *)malloc(cap);
    if (buf == NULL || ls_arena_init(&arena, buf, cap) != LS_OK) return 1;
    if (ls_posix_load_mesh(argv[1], &arena, &m, NULL) != LS_OK ||
        ls_posix_load_mesh(argc > 2 ? argv[2] : argv[1], &arena, &tg, NULL) != LS_OK) {
        fprintf(stderr, "cannot read the meshes\n");
        return 1;
    }
    { /* the target differs from the mesh: scaled 1.02 about its box centre, shifted along x */
        ls_real lo[3], hi[3], c[3], d2 = 0;
        uint32_t i, k;
        for (k = 0; k < 3; k++) lo[k] = hi[k] = tg.positions[k];
        for (i = 0; i < tg.vertex_count; i++)
            for (k = 0; k < 3; k++) {
                ls_real p = tg.positions[3 * (size_t)i + k];
                lo[k] = p < lo[k] ? p : lo[k];
                hi[k] = p > hi[k] ? p : hi[k];
            }
        for (k = 0; k < 3; k++) {
            c[k] = (lo[k] + hi[k]) / 2;
            d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
        }
        for (i = 0; i < tg.vertex_count; i++)
            for (k = 0; k < 3; k++) {
                ls_real *p = tg.positions + 3 * (size_t)i + k;
                *p = c[k] + (ls_real)1.02 * (*p - c[k]) + (k == 0 ? (ls_real)(sqrt((double)d2) / 200.0) : (ls_real)0);
            }
    }
    if (ls_camera_frame(tg.positions, tg.vertex_count, (ls_real)(45.0 * 3.14159265358979323846 / 180.0), LS_FOV_X, 1,
                        (ls_real)1.1, &fr, NULL) != LS_OK)
        return 1;
    npx = (size_t)res * res;
    dirs = (ls_real *)ls_arena_alloc(&arena, 3u * views, sizeof(ls_real));
    mvps = (ls_real *)ls_arena_alloc(&arena, 16u * views, sizeof(ls_real));
    tgt = (ls_real **)ls_arena_alloc(&arena, views, sizeof(ls_real *));
    nrm = (ls_real *)ls_arena_alloc(&arena, 3u * (size_t)m.vertex_count, sizeof(ls_real));
    gp = (ls_real *)ls_arena_alloc(&arena, 3u * (size_t)m.vertex_count, sizeof(ls_real));
    tnrm = (ls_real *)ls_arena_alloc(&arena, 3u * (size_t)tg.vertex_count, sizeof(ls_real));
    img = (ls_real *)ls_arena_alloc(&arena, 4u * npx, sizeof(ls_real));
    gimg = (ls_real *)ls_arena_alloc(&arena, 4u * npx * views, sizeof(ls_real));
    if (gimg == NULL || ls_vis_init(&vis, &arena, res, res, 1, m.vertex_count) != LS_OK ||
        ls_vis_init(&tvis, &arena, res, res, 1, tg.vertex_count) != LS_OK ||
        ls_edge_table_build(&et, m.triangles, m.face_count, m.vertex_count, &arena, NULL) != LS_OK)
        return 1;
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = mv_sh;
    (void)ls_camera_fibonacci_dirs(views, dirs);
    for (v = 0; v < views; v++) {
        (void)ls_camera_framed_view(&fr, dirs + 3u * v, NULL, mvps + 16u * v);
        tgt[v] = (ls_real *)ls_arena_alloc(&arena, 4u * npx, sizeof(ls_real));
        if (tgt[v] == NULL || !render(&tvis, &arena, mvps + 16u * v, &tg, tnrm, &o, tgt[v])) return 1;
    }
    for (r = 0; r < reps; r++) {
        double ts = 0, tf = 0;
        memset(gp, 0, 3u * (size_t)m.vertex_count * sizeof(ls_real));
        for (v = 0; v < views; v++) {
            const ls_real *rp[1], *tp[1];
            ls_real *gpp[1], loss;
            double t0 = now_ms();
            if (!render(&vis, &arena, mvps + 16u * v, &m, nrm, &o, img)) return 1;
            tf += now_ms() - t0;
            rp[0] = img;
            tp[0] = tgt[v];
            gpp[0] = gimg;
            if (ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, res, res, 1}, rp, tp, gpp, &loss, NULL) != LS_OK) return 1;
            if (r == 0) {
                size_t b = 0;
                if (ls_silhouette_scratch_bytes(&(ls_view){.vis = &vis, .indices = m.triangles,
                        .triangle_count = m.face_count, .table = &et}, &b) != LS_OK) return 1;
                if (b > maxscr) maxscr = b;
            }
            t0 = now_ms();
            st = ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                    .vertex_count = m.vertex_count, .normals = nrm, .opts = &o, .mvp = mvps + 16u * v, .table = &et,
                    .boost = 3}, gimg, gp, &arena, NULL);
            ts += now_ms() - t0;
            if (st != LS_OK) {
                fprintf(stderr, "silhouette: %s\n", ls_status_str(st));
                return 1;
            }
        }
        if (ts < sil) sil = ts;
        if (tf < fwd) fwd = tf;
        if (r == 0) hash = fnv(hash, gp, 3u * (size_t)m.vertex_count * sizeof(ls_real));
        if (r == 0 && getenv("BENCH_DUMP") != NULL) { /* the summed gradient's raw values, to compare two builds */
            FILE *df = fopen(getenv("BENCH_DUMP"), "wb");
            if (df == NULL || fwrite(gp, sizeof(ls_real), 3u * (size_t)m.vertex_count, df) != 3u * (size_t)m.vertex_count)
                fprintf(stderr, "bench_silhouette: cannot write %s\n", getenv("BENCH_DUMP"));
            if (df != NULL) fclose(df);
        }
    }
    printf("mesh %s: %u vertices, %u faces, %u views at %u^2: silhouette %.3f ms/view (%.2f ms/iteration), "
           "forward %.3f ms/view, ratio %.2f, scratch %zu bytes, gradient hash %016llx (%s)\n",
           argv[1], (unsigned)m.vertex_count, (unsigned)m.face_count, (unsigned)views, (unsigned)res, sil / views, sil,
           fwd / views, sil / fwd, maxscr, (unsigned long long)hash, LS_REAL_NAME);
    free(buf);
    return 0;
}
