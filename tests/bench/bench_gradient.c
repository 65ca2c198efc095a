/* tests/bench/bench_gradient.c - per-view cost of differentiable rendering:
 * forward (raster + SH shade), loss, shading backward (+ vertex normals),
 * silhouette pass, on the bunny (fixtures/meshes/bunny.obj) and the
 * armadillo (fixtures/meshes/armadillo.obj.gz, decompressed at bench time), at
 * 128^2 and 512^2, perspective. Times are process CPU time, the minimum over
 * repetitions (the machine is shared). Prints a table and writes it to
 * $BENCH_OUT (default build/bench/gradient.md).
 *
 *   make build/bench/bench_gradient && build/bench/bench_gradient
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

typedef struct row {
    const char *mesh;
    uint32_t res, tris, sil_edges;
    double fwd, loss, bwd, sil_exact, sil_mask, pair;
} row;


static int bench_mesh(const char *name, const char *path, const char *alt, row *rows, int *nrows)
{
    unsigned char *data = NULL, *buf;
    size_t bytes = 0, cap = (size_t)768 << 20;
    ls_arena arena;
    ls_mesh m;
    ls_edge_table et;
    ls_real c[3], r = 0, view[16], mvp[16];
    ls_real *nrm, *img, *tgt, *gimg, *gp, *gn, *pimg, *gin;
    uint32_t i, ri;
    static const uint32_t res[2] = {128, 512};
    if (ls_posix_read_data(path, &data, &bytes) != LS_OK && (alt == NULL || ls_posix_read_data(alt, &data, &bytes) != LS_OK)) {
        printf("bench_gradient: cannot read %s\n", path);
        return 0;
    }
    buf = (unsigned char *)malloc(cap);
    if (buf == NULL || ls_arena_init(&arena, buf, cap) != LS_OK) return 0;
    if (ls_mesh_read(data, bytes, LS_MESH_FORMAT_AUTO, &arena, &m, NULL) != LS_OK) return 0;
    free(data);
    mv_frame(&m, c, &r);
    mv_camera(c, r, view, mvp);
    if (ls_edge_table_build(&et, m.triangles, m.face_count, m.vertex_count, &arena, NULL) != LS_OK) return 0;
    nrm = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    gp = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    gn = (ls_real *)ls_arena_alloc(&arena, 3 * (size_t)m.vertex_count, sizeof(ls_real));
    for (ri = 0; ri < 2; ri++) {
        uint32_t W = res[ri], rep, reps = W <= 128 ? 20 : 5, sm;
        size_t npx = (size_t)W * W;
        ls_arena_mark mark = ls_arena_save(&arena);
        ls_vis vis;
        ls_shade_opts o;
        row *rw = &rows[(*nrows)++];
        ls_real loss = 0;
        double t0;
        img = (ls_real *)ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
        tgt = (ls_real *)ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
        gimg = (ls_real *)ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
        pimg = (ls_real *)ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
        gin = (ls_real *)ls_arena_alloc(&arena, 4 * npx, sizeof(ls_real));
        if (gin == NULL || gimg == NULL || ls_vis_init(&vis, &arena, W, W, 1, m.vertex_count) != LS_OK) return 0;
        for (i = 0; i < 4 * npx; i++) tgt[i] = (ls_real)(i % 4 == 3 ? 1 : 0.3);
        ls_shade_opts_init(&o);
        o.mode = LS_SHADE_SH;
        o.sh = mv_sh;
        memset(rw, 0, sizeof *rw);
        rw->mesh = name;
        rw->res = W;
        rw->tris = m.face_count;
        rw->fwd = rw->loss = rw->bwd = rw->sil_exact = rw->sil_mask = rw->pair = 1e300;
        memset(gin, 0, sizeof(ls_real) * 4 * npx);
        for (rep = 0; rep < reps; rep++) {
            const ls_real *rp[1], *tp[1];
            ls_real *gpp[1];
            double t;
            t0 = now_ms();
            if (ls_shade_vertex_normals(m.positions, m.vertex_count, m.triangles, m.face_count, nrm, NULL) != LS_OK ||
                ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles,
                        .triangle_count = m.face_count, .vertex_count = m.vertex_count, .mvp = mvp}, &arena,
                        NULL) != LS_OK ||
                ls_shade(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                        .vertex_count = m.vertex_count, .normals = nrm, .opts = &o}, img, NULL) != LS_OK)
                return 0;
            t = now_ms() - t0;
            rw->fwd = t < rw->fwd ? t : rw->fwd;
            rp[0] = img;
            tp[0] = tgt;
            gpp[0] = gimg;
            t0 = now_ms();
            if (ls_loss_views(&(ls_loss_shape){LS_LOSS_L1, W, W, 1}, rp, tp, gpp, &loss, NULL) != LS_OK) return 0;
            t = now_ms() - t0;
            rw->loss = t < rw->loss ? t : rw->loss;
            memset(gp, 0, sizeof(ls_real) * 3 * m.vertex_count);
            memset(gn, 0, sizeof(ls_real) * 3 * m.vertex_count);
            t0 = now_ms();
            if (ls_shade_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                    .vertex_count = m.vertex_count, .normals = nrm, .opts = &o, .mvp = mvp}, gimg, gp, gn, NULL,
                    NULL) != LS_OK ||
                ls_vertex_normals_backward(m.positions, m.vertex_count, m.triangles, m.face_count, gn, gp, &arena,
                                           NULL) != LS_OK)
                return 0;
            t = now_ms() - t0;
            rw->bwd = t < rw->bwd ? t : rw->bwd;
            for (sm = 0; sm < 2; sm++) { /* exact silhouette pass: SH, then mask */
                double *best = sm == 0 ? &rw->sil_exact : &rw->sil_mask;
                o.mode = sm == 0 ? LS_SHADE_SH : LS_SHADE_MASK;
                t0 = now_ms();
                if (ls_silhouette_backward(&(ls_view){.vis = &vis, .indices = m.triangles,
                        .triangle_count = m.face_count, .vertex_count = m.vertex_count, .normals = nrm, .opts = &o,
                        .mvp = mvp, .table = &et, .boost = 1}, gimg, gp, &arena, NULL) != LS_OK)
                    return 0;
                t = now_ms() - t0;
                *best = t < *best ? t : *best;
            }
            o.mode = LS_SHADE_SH;
            t0 = now_ms(); /* pair mode: blend forward + its backward */
            if (ls_pair_forward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                    .table = &et}, img, pimg, NULL) != LS_OK ||
                ls_pair_backward(&(ls_view){.vis = &vis, .indices = m.triangles, .triangle_count = m.face_count,
                        .mvp = mvp, .table = &et, .boost = 1}, img, gimg, gin, gp, NULL) != LS_OK)
                return 0;
            t = now_ms() - t0;
            rw->pair = t < rw->pair ? t : rw->pair;
        }
        /* silhouette edges of this view (front/back pairs and boundaries) */
        for (i = 0; i < 3 * m.face_count; i++) {
            uint32_t tw = et.twin[i];
            if (tw == LS_EDGE_NONE) {
                rw->sil_edges++;
                continue;
            }
            if (tw < i) continue;
            {
                const uint32_t *f = m.triangles + 3 * (size_t)(i / 3), *g = m.triangles + 3 * (size_t)(tw / 3);
                const ls_real *A = vis.clip + 4 * (size_t)f[i % 3], *B = vis.clip + 4 * (size_t)f[(i % 3 + 1) % 3];
                const ls_real *C = vis.clip + 4 * (size_t)f[(i % 3 + 2) % 3], *D = vis.clip + 4 * (size_t)g[(tw % 3 + 2) % 3];
                double dc = A[0] * (B[1] * C[3] - B[3] * C[1]) - A[1] * (B[0] * C[3] - B[3] * C[0]) + A[3] * (B[0] * C[1] - B[1] * C[0]);
                double dd = A[0] * (B[1] * D[3] - B[3] * D[1]) - A[1] * (B[0] * D[3] - B[3] * D[0]) + A[3] * (B[0] * D[1] - B[1] * D[0]);
                if ((dc > 0 && dd > 0) || (dc < 0 && dd < 0)) rw->sil_edges++;
            }
        }
        ls_arena_restore(&arena, mark);
    }
    free(buf);
    return 1;
}

int main(void)
{
    row rows[8];
    int n = 0, i, ok = 1;
    const char *out = getenv("BENCH_OUT") ? getenv("BENCH_OUT") : "build/bench/gradient.md";
    FILE *f;
    char line[512];
    ok &= bench_mesh("bunny", "fixtures/meshes/bunny.obj", "/work/shared/meshes/bunny.obj", rows, &n);
    ok &= bench_mesh("armadillo", "fixtures/meshes/armadillo.obj.gz", "/work/shared/meshes/armadillo.obj", rows, &n);
    f = fopen(out, "w");
    snprintf(line, sizeof line,
             "| mesh | res | tris | sil. edges | forward ms | loss ms | shading bwd ms | silhouette SH ms | silhouette mask ms | pair fwd+bwd ms | bwd/fwd | sil/fwd |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    fputs(line, stdout);
    if (f) fputs(line, f);
    for (i = 0; i < n; i++) {
        const row *r = &rows[i];
        snprintf(line, sizeof line, "| %s | %u | %u | %u | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %.2f |\n", r->mesh,
                 r->res, r->tris, r->sil_edges, r->fwd, r->loss, r->bwd, r->sil_exact, r->sil_mask, r->pair, r->bwd / r->fwd,
                 r->sil_exact / r->fwd);
        fputs(line, stdout);
        if (f) fputs(line, f);
    }
    snprintf(line, sizeof line, "\nls_real = %s; CPU time, minimum of 20 (128^2) or 5 (512^2) runs; one view, S = 1; "
             "forward = vertex normals + raster + SH shade; bwd = shading + vertex-normal backward; "
             "sil = exact silhouette pass; pair = ls_pair_forward + ls_pair_backward (nvdiffrast-style). "
             "Accuracy: exact mode within 1e-3 of FD in 76/76 test configurations (most 1e-6); pair mode "
             "relative L2 error vs exact: see test_silhouette (median 0.38 smooth, 0.57 random weights).\n", LS_REAL_NAME);
    fputs(line, stdout);
    if (f) {
        fputs(line, f);
        fclose(f);
    }
    return ok ? 0 : 1;
}
