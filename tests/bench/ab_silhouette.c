/* ab_silhouette.c - two builds of the silhouette pass timed in one process,
 * for changes too small for separate runs on a noisy machine. The builds
 * are linked as ls_silhouette_backward_A and _B (tests/tools/ab_silhouette.sh);
 * each repetition renders the armadillo's bench view (forward, L1 loss,
 * shading backward, as bench_gradient does, so the caches are as cold as
 * there) before each pass, A and B in alternating order.
 * Usage: ab_silhouette MESH [REPS [RES]]. Prints the minima, the medians and
 * the median of the per-repetition ratios B/A, and each build's minimum over
 * the forward's, and whether the two gradients have the same bits (exit 1
 * when they differ: a change meant to move no bit did). */
#define _POSIX_C_SOURCE 200112L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <largesteps.h>
#include "ls_posix.h"
#include "mesh_view.h"

/* both builds have the current signature of ls_silhouette_backward */
#define AB_SIGNATURE(name) ls_status name(const ls_view *, const ls_real *, ls_real *, ls_arena *, ls_diag *)
AB_SIGNATURE(ls_silhouette_backward_A);
AB_SIGNATURE(ls_silhouette_backward_B);
typedef AB_SIGNATURE((*ab_fn));

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    enum { MAX_REPS = 500 };
    static double ta[MAX_REPS], tb[MAX_REPS], ratio[MAX_REPS], tf[2 * MAX_REPS];
    const ab_fn pass[2] = {ls_silhouette_backward_A, ls_silhouette_backward_B};
    unsigned char *data = NULL, *buf;
    size_t bytes = 0, cap = (size_t)768 << 20, npx, i;
    uint32_t reps = argc > 2 ? (uint32_t)atoi(argv[2]) : 40, res = argc > 3 ? (uint32_t)atoi(argv[3]) : 512, r;
    ls_real c[3], radius = 0, view[16], mvp[16], loss = 0, *nrm, *img, *tgt, *gimg, *gp, *gn, *grad[2];
    ls_arena arena;
    ls_mesh m;
    ls_edge_table et;
    ls_vis vis;
    ls_shade_opts o;
    if (argc < 2 || reps < 1 || reps > MAX_REPS || res < 8) {
        fprintf(stderr, "usage: ab_silhouette MESH [REPS (1..%d) [RES]]\n", MAX_REPS);
        return 2;
    }
    npx = (size_t)res * res;
    buf = malloc(cap);
    if (buf == NULL || ls_posix_read_data(argv[1], &data, &bytes) != LS_OK) return 1;
    ls_arena_init(&arena, buf, cap);
    if (ls_mesh_read(data, bytes, LS_MESH_FORMAT_AUTO, &arena, &m, NULL) != LS_OK) return 1;
    mv_frame(&m, c, &radius);
    mv_camera(c, radius, view, mvp);
    nrm = ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    gp = ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    gn = ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    img = ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
    tgt = ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
    gimg = ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
    grad[0] = ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    grad[1] = ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    if (gimg == NULL || grad[1] == NULL || ls_edge_table_build(&et, m.triangles, m.face_count, m.vertex_count, &arena, NULL) != LS_OK ||
        ls_vis_init(&vis, &arena, res, res, 1, m.vertex_count) != LS_OK)
        return 1;
    for (i = 0; i < 4 * npx; i++) tgt[i] = (ls_real)(i % 4 == 3 ? 1 : 0.3);
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = mv_sh;
    for (r = 0; r < reps; r++) {
        double t[2];
        int k;
        for (k = 0; k < 2; k++) {
            int which = (r & 1u) ? 1 - k : k; /* A first on even repetitions, B first on odd ones */
            const ls_real *rp[1], *tp[1];
            ls_real *gpp[1];
            double t0 = now_ms();
            if (ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, nrm, NULL) != LS_OK ||
                ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                        .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = mvp}, &arena,
                        NULL) != LS_OK ||
                ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                        .vertex_count = m.vertex_count, .normals = nrm, .opts = &o}, img, NULL) != LS_OK)
                return 1;
            tf[2 * r + (uint32_t)k] = now_ms() - t0;
            rp[0] = img;
            tp[0] = tgt;
            gpp[0] = gimg;
            memset(gp, 0, sizeof(ls_real) * 3 * m.vertex_count);
            memset(gn, 0, sizeof(ls_real) * 3 * m.vertex_count);
            if (ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, res, res, 1}, rp, tp, gpp, &loss, NULL) != LS_OK ||
                ls_shade_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                        .vertex_count = m.vertex_count, .normals = nrm, .opts = &o, .mvp = mvp}, gimg, gp, gn, NULL,
                        NULL) != LS_OK ||
                ls_vertex_normals_backward(m.positions, m.vertex_count, m.triangles, m.face_count, gn, gp, &arena,
                                           NULL) != LS_OK)
                return 1;
            t0 = now_ms();
            if (pass[which](&(ls_view){.vis = &vis, .table = &et, .indices = m.triangles,
                    .triangle_count = m.face_count,
                                        .normals = nrm, .vertex_count = m.vertex_count, .opts = &o, .mvp = mvp, .boost = 1},
                            gimg, gp, &arena, NULL) != LS_OK)
                return 1;
            t[which] = now_ms() - t0;
            memcpy(grad[which], gp, sizeof(ls_real) * 3 * m.vertex_count);
        }
        ta[r] = t[0];
        tb[r] = t[1];
        ratio[r] = t[1] / t[0];
    }
    qsort(ta, reps, sizeof ta[0], cmp_double);
    qsort(tb, reps, sizeof tb[0], cmp_double);
    qsort(ratio, reps, sizeof ratio[0], cmp_double);
    qsort(tf, 2 * (size_t)reps, sizeof tf[0], cmp_double);
    printf("A min %.3f med %.3f ms | B min %.3f med %.3f ms | B/A: mins %.3f, paired median %.3f (quartiles %.3f %.3f)"
           " | forward min %.3f ms: A/fwd %.3f, B/fwd %.3f\n",
           ta[0], ta[reps / 2], tb[0], tb[reps / 2], tb[0] / ta[0], ratio[reps / 2], ratio[reps / 4],
           ratio[3 * reps / 4], tf[0], ta[0] / tf[0], tb[0] / tf[0]);
    if (memcmp(grad[0], grad[1], sizeof(ls_real) * 3 * m.vertex_count) != 0) {
        printf("gradients of A and B differ\n");
        return 1;
    }
    printf("gradients of A and B: the same bits\n");
    return 0;
}
