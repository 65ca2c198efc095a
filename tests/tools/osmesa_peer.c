/* osmesa_peer.c - renders a mesh with Mesa's software OpenGL (OSMesa) and with
 * largesteps' rasterizer from the same cameras and compares them: silhouette
 * IoU, triangle ids and depth per pixel. A test-only tool (tests/stage_osmesa.sh).
 *
 *   osmesa_peer MESH.obj RES VIEWS [--bench REPEATS]
 *
 * OpenGL side: gluLookAt + gluPerspective (vertical fov), fixed-function
 * pipeline, one glDrawArrays over unrolled float vertex arrays (Mesa gets the
 * positions rounded to float; largesteps the doubles or floats of ls_real),
 * flat colour = triangle index + 1 in 24 bits, depth test GL_LESS,
 * no culling; glReadPixels (bottom row first, flipped here). largesteps side:
 * ls_camera_look_at + ls_camera_perspective(LS_FOV_Y) + ls_raster at S = 1.
 * The cameras sit on a Fibonacci sphere (ls_camera_fibonacci_dirs) around the
 * bounding-box centre at 1.6 times the bounding-box diagonal.
 *
 * Prints one "ok   NAME" / "FAIL NAME" line per check and per view, then
 * "osmesa: N passed, M failed". With --bench, also prints timings of both
 * renderers (best of REPEATS, one thread). */
#include <GL/osmesa.h>
#include <GL/glu.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <largesteps.h>

static int passed, failed;

static void report(int ok, const char *name, const char *detail)
{
    if (ok) passed++;
    else failed++;
    printf("%s %s  %s\n", ok ? "ok  " : "FAIL", name, detail);
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int load_obj(const char *path, double **v, uint32_t **f, uint32_t *nv, uint32_t *nf)
{
    FILE *fp = fopen(path, "r");
    char line[512];
    uint32_t cv = 0, cf = 0;
    if (fp == NULL) return 0;
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') cv++;
        if (line[0] == 'f' && line[1] == ' ') cf++;
    }
    *v = (double *)malloc(3 * (size_t)cv * sizeof(double));
    *f = (uint32_t *)malloc(3 * (size_t)cf * sizeof(uint32_t));
    *nv = *nf = 0;
    rewind(fp);
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') {
            double *p = *v + 3 * (size_t)*nv;
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) == 3) (*nv)++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            unsigned a, b, c;
            if (sscanf(line + 2, "%u %u %u", &a, &b, &c) == 3) {
                uint32_t *q = *f + 3 * (size_t)*nf;
                q[0] = a - 1;
                q[1] = b - 1;
                q[2] = c - 1;
                (*nf)++;
            }
        }
    }
    fclose(fp);
    return *nv == cv && *nf == cf && cv > 0;
}

int main(int argc, char **argv)
{
    double *v, lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, c[3], diag;
    uint32_t *f, nv, nf, res, views, i, k, view;
    int repeats = 0;
    ls_real *pos, *dirs;
    unsigned char *rgba, *tc;
    float *gdepth, *tv;
    OSMesaContext ctx;
    ls_arena arena;
    void *mem;
    size_t mem_bytes = (size_t)1 << 28;
    ls_vis vis;
    double fovy_deg = 40.0, t_gl_best = 1e30, t_ls_best = 1e30;
    char name[128], detail[256];
    if (argc < 4) {
        fprintf(stderr, "usage: %s MESH.obj RES VIEWS [--bench REPEATS]\n", argv[0]);
        return 2;
    }
    res = (uint32_t)atoi(argv[2]);
    views = (uint32_t)atoi(argv[3]);
    if (argc >= 6 && strcmp(argv[4], "--bench") == 0) repeats = atoi(argv[5]);
    if (!load_obj(argv[1], &v, &f, &nv, &nf)) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    for (i = 0; i < nv; i++)
        for (k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], v[3 * i + k]);
            hi[k] = fmax(hi[k], v[3 * i + k]);
        }
    for (k = 0; k < 3; k++) c[k] = (lo[k] + hi[k]) / 2;
    diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
    pos = (ls_real *)malloc(3 * (size_t)nv * sizeof(ls_real));
    for (i = 0; i < 3 * nv; i++) pos[i] = (ls_real)v[i];
    tv = (float *)malloc(9 * (size_t)nf * sizeof(float));
    tc = (unsigned char *)malloc(9 * (size_t)nf);
    for (i = 0; i < nf; i++) {
        uint32_t id = i + 1, q;
        for (k = 0; k < 3; k++)
            for (q = 0; q < 3; q++) tv[9 * i + 3 * k + q] = (float)v[3 * f[3 * i + k] + q];
        for (k = 0; k < 3; k++) {
            tc[9 * i + 3 * k] = (unsigned char)(id & 255u);
            tc[9 * i + 3 * k + 1] = (unsigned char)((id >> 8) & 255u);
            tc[9 * i + 3 * k + 2] = (unsigned char)((id >> 16) & 255u);
        }
    }
    dirs = (ls_real *)malloc(3 * (size_t)views * sizeof(ls_real));
    if (ls_camera_fibonacci_dirs(views, dirs) != LS_OK) return 2;

    ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    rgba = (unsigned char *)malloc(4 * (size_t)res * res);
    gdepth = (float *)malloc(sizeof(float) * (size_t)res * res);
    if (ctx == NULL || !OSMesaMakeCurrent(ctx, rgba, GL_UNSIGNED_BYTE, (GLsizei)res, (GLsizei)res)) {
        report(0, "osmesa_context", "cannot create an OSMesa context");
        printf("osmesa: %d passed, %d failed\n", passed, failed);
        return 1;
    }
    printf("     renderer: %s / %s\n", (const char *)glGetString(GL_RENDERER), (const char *)glGetString(GL_VERSION));
    mem = malloc(mem_bytes + 8);
    ls_arena_init(&arena, mem, mem_bytes);
    if (ls_vis_init(&vis, &arena, res, res, 1, nv) != LS_OK) return 2;

    for (view = 0; view < views; view++) {
        double eye[3], dist = 1.6 * diag, znear = 0.1 * diag, zfar = 4.0 * diag;
        ls_real le[3], lc[3], up[3] = {0, 1, 0}, V[16], P[16], M[16];
        GLdouble gm[16];
        size_t p, n = (size_t)res * res, both = 0, either = 0, same_id = 0, edge_only = 1;
        double max_dz = 0, t0;
        int rep;
        for (k = 0; k < 3; k++) {
            eye[k] = c[k] + dist * (double)dirs[3 * view + k];
            le[k] = (ls_real)eye[k];
            lc[k] = (ls_real)c[k];
        }
        /* --- OpenGL --- */
        glViewport(0, 0, (GLsizei)res, (GLsizei)res);
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        gluPerspective(fovy_deg, 1.0, znear, zfar);
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        gluLookAt(eye[0], eye[1], eye[2], c[0], c[1], c[2], 0, 1, 0);
        glDisable(GL_LIGHTING);
        glDisable(GL_DITHER);
        glDisable(GL_CULL_FACE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glShadeModel(GL_FLAT);
        /* unrolled vertex and colour arrays (colour = triangle index + 1 on
         * all three corners), drawn with one glDrawArrays: Mesa's fast path */
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, tv);
        glColorPointer(3, GL_UNSIGNED_BYTE, 0, tc);
        for (rep = 0; rep < (repeats > 0 ? repeats : 1); rep++) {
            t0 = now_s();
            glClearColor(0, 0, 0, 0);
            glClearDepth(1.0);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(3 * nf));
            glFinish();
            t_gl_best = fmin(t_gl_best, now_s() - t0);
        }
        glReadPixels(0, 0, (GLsizei)res, (GLsizei)res, GL_DEPTH_COMPONENT, GL_FLOAT, gdepth);
        /* --- largesteps --- */
        if (ls_camera_look_at(le, lc, up, V) != LS_OK ||
            ls_camera_perspective((ls_real)(fovy_deg * 3.14159265358979323846 / 180.0), LS_FOV_Y, 1,
                                  (ls_real)znear, (ls_real)zfar, P) != LS_OK) {
            report(0, "camera", "ls_camera_* failed");
            continue;
        }
        ls_mat4_mul(P, V, M);
        /* the two projection matrices agree (GL stores column-major) */
        {
            double max_m = 0;
            GLdouble mv[16], pr[16];
            glGetDoublev(GL_MODELVIEW_MATRIX, mv);
            glGetDoublev(GL_PROJECTION_MATRIX, pr);
            for (i = 0; i < 4; i++)
                for (k = 0; k < 4; k++) {
                    double s = 0;
                    int j;
                    for (j = 0; j < 4; j++) s += pr[j * 4 + i] * mv[k * 4 + j];
                    gm[i * 4 + k] = s;
                    max_m = fmax(max_m, fabs(s - (double)M[i * 4 + k]) / (1 + fabs(s)));
                }
            snprintf(name, sizeof name, "view%u_matrix_matches_glu", view);
            snprintf(detail, sizeof detail, "max relative difference %.3g", max_m);
            report(max_m < 1e-5, name, detail); /* Mesa keeps its matrices in float */
        }
        for (rep = 0; rep < (repeats > 0 ? repeats : 1); rep++) {
            ls_status st;
            t0 = now_s();
            st = ls_raster(&vis, &arena, M, pos, nv, f, nf, NULL);
            t_ls_best = fmin(t_ls_best, now_s() - t0);
            if (st != LS_OK) {
                report(0, "ls_raster", ls_status_name(st));
                break;
            }
        }
        /* --- compare: GL row r (bottom first) is our row res - 1 - r --- */
        for (p = 0; p < n; p++) {
            size_t x = p % res, yg = p / res, q = (res - 1 - yg) * res + x;
            uint32_t gid = (uint32_t)rgba[4 * p] | ((uint32_t)rgba[4 * p + 1] << 8) | ((uint32_t)rgba[4 * p + 2] << 16);
            uint32_t lid = vis.tri[q];
            if (gid && lid) both++;
            if (gid || lid) either++;
            if (gid != 0 && gid == lid) {
                double dz = fabs((double)gdepth[p] - ((double)vis.depth[q] + 1) / 2);
                same_id++;
                max_dz = fmax(max_dz, dz);
            }
            if ((gid != 0) != (lid != 0)) {
                /* a silhouette difference must sit on the silhouette: a
                 * 4-neighbour of ours differs in coverage */
                size_t yq = res - 1 - yg;
                int nb = 0;
                if (x > 0 && (vis.tri[q - 1] != 0) != (lid != 0)) nb = 1;
                if (x + 1 < res && (vis.tri[q + 1] != 0) != (lid != 0)) nb = 1;
                if (yq > 0 && (vis.tri[q - res] != 0) != (lid != 0)) nb = 1;
                if (yq + 1 < res && (vis.tri[q + res] != 0) != (lid != 0)) nb = 1;
                if (!nb) edge_only = 0;
            }
        }
        {
            double iou = either ? (double)both / (double)either : 1;
            snprintf(name, sizeof name, "view%u_silhouette_iou", view);
            snprintf(detail, sizeof detail, "IoU %.6f (%lu covered by both, %lu by either), differences only on edges: %s",
                     iou, (unsigned long)both, (unsigned long)either, edge_only ? "yes" : "no");
            report(iou >= 0.999 && edge_only && both > n / 50, name, detail);
            snprintf(name, sizeof name, "view%u_ids_and_depth", view);
            snprintf(detail, sizeof detail, "same triangle on %.4f of common pixels, max |depth diff| %.3g (window units)",
                     both ? (double)same_id / (double)both : 0.0, max_dz);
            report(both && (double)same_id / (double)both > 0.99 && max_dz < 5e-5, name, detail);
        }
        (void)gm;
    }
    if (repeats > 0) {
        printf("     bench %ux%u, %u triangles, best of %d: OSMesa %.3f ms, largesteps %.3f ms (ratio %.2f), "
               "largesteps %.1f Mtri/s, %.1f Msamples/s\n",
               res, res, nf, repeats, t_gl_best * 1e3, t_ls_best * 1e3, t_gl_best / t_ls_best,
               nf / t_ls_best * 1e-6, (double)res * res / t_ls_best * 1e-6);
    }
    OSMesaDestroyContext(ctx);
    printf("osmesa: %d passed, %d failed\n", passed, failed);
    free(mem);
    free(rgba);
    free(gdepth);
    free(pos);
    free(dirs);
    free(tv);
    free(tc);
    free(v);
    free(f);
    return failed ? 1 : 0;
}
