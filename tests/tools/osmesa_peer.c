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
 * "osmesa: N passed, M failed".
 *
 *   osmesa_peer MESH.obj RES VIEWS --bench REPEATS
 *
 * benchmarks instead (run with LP_NUM_THREADS=0: llvmpipe rasterizes on the
 * calling thread): per view, the best of REPEATS of (a) visibility only:
 * OpenGL draws triangle ids in flat colour with depth test, largesteps runs
 * ls_raster; (b) SH-shaded: OpenGL draws the indexed mesh with a GLSL
 * fragment shader that evaluates the 9-coefficient SH irradiance
 * n_h^T M_c n_h / pi on the interpolated (not renormalised) vertex normal,
 * largesteps runs ls_raster + ls_shade(LS_SHADE_SH), both at one sample per
 * pixel. Neither reads pixels back. Times are process CPU time (robust on a
 * shared machine), summed over the views; one line
 * per mode: "bench MODE RES TRIANGLES VIEWS gl_ms ls_ms bytes_per_view"
 * (bytes: the visibility buffer, the raster scratch of the largest view and,
 * for SH, the RGBA output). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/glext.h>
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

/* Process CPU time: the benchmark's clock. Both renderers run on this
 * thread (LP_NUM_THREADS=0), so CPU time measures their work alone, also on
 * a machine shared with other jobs. */
static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
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

/* Both cameras of one view: the eye at 1.6 bounding-box diagonals from the
 * centre c in direction dir, 40 degrees vertical fov, planes at 0.1 and 4
 * diagonals. OpenGL: gluPerspective + gluLookAt, depth test, no lighting,
 * dithering or culling. largesteps: ls_camera_look_at + ls_camera_perspective
 * into M. Returns 0 when the ls_camera_* calls fail. */
static int view_setup(const double c[3], double diag, const ls_real *dir, uint32_t res, ls_real M[16])
{
    const double fovy_deg = 40.0, dist = 1.6 * diag, znear = 0.1 * diag, zfar = 4.0 * diag;
    double eye[3];
    ls_real le[3], lc[3], up[3] = {0, 1, 0}, V[16], P[16];
    int k;
    for (k = 0; k < 3; k++) {
        eye[k] = c[k] + dist * (double)dir[k];
        le[k] = (ls_real)eye[k];
        lc[k] = (ls_real)c[k];
    }
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
    if (ls_camera_look_at(le, lc, up, V) != LS_OK ||
        ls_camera_perspective((ls_real)(fovy_deg * 3.14159265358979323846 / 180.0), LS_FOV_Y, 1, (ls_real)znear,
                              (ls_real)zfar, P) != LS_OK)
        return 0;
    ls_mat4_mul(P, V, M);
    return 1;
}

/* The SH coefficients of the benchmark (9 per channel, ls_shade.h order). */
static const double bench_sh[27] = {0.79, 0.39, -0.34, -0.29, -0.11, -0.26, -0.16, 0.56, 0.21,
                                    0.44, 0.35, -0.18, -0.06, -0.05, -0.22, -0.09, 0.21, -0.05,
                                    0.54, 0.60, -0.27, 0.01, -0.12, -0.47, -0.15, 0.14, -0.30};

static const char *vs_src =
    "#version 120\n"
    "varying vec3 n;\n"
    "void main() { n = gl_Normal; gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex; }\n";
static const char *fs_src =
    "#version 120\n"
    "uniform mat4 M[3];\n"
    "varying vec3 n;\n"
    "void main() {\n"
    "  vec4 h = vec4(n, 1.0);\n"
    "  gl_FragColor = vec4(dot(h, M[0] * h), dot(h, M[1] * h), dot(h, M[2] * h), 1.0) * 0.31830988618379067;\n"
    "}\n";

static GLuint compile_program(void)
{
    GLuint vs = glCreateShader(GL_VERTEX_SHADER), fs = glCreateShader(GL_FRAGMENT_SHADER), prog;
    GLint ok = 0;
    char log[1024];
    glShaderSource(vs, 1, &vs_src, NULL);
    glCompileShader(vs);
    glShaderSource(fs, 1, &fs_src, NULL);
    glCompileShader(fs);
    prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        fprintf(stderr, "GLSL link failed: %s\n", log);
        return 0;
    }
    return prog;
}

/* Ramamoorthi-Hanrahan M_c (column-major for GL; symmetric anyway). */
static void sh_matrices(float m[48])
{
    const double c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    int c;
    for (c = 0; c < 3; c++) {
        const double *L = bench_sh + 9 * c;
        double M[16] = {c1 * L[8], c1 * L[4], c1 * L[7], c2 * L[3],
                        c1 * L[4], -c1 * L[8], c1 * L[5], c2 * L[1],
                        c1 * L[7], c1 * L[5], c3 * L[6], c2 * L[2],
                        c2 * L[3], c2 * L[1], c2 * L[2], c4 * L[0] - c5 * L[6]};
        int i;
        for (i = 0; i < 16; i++) m[16 * c + i] = (float)M[i];
    }
}

static int bench_main(const double *v, const uint32_t *f, uint32_t nv, uint32_t nf, const ls_real *pos,
                      const float *tv, const unsigned char *tc, const ls_real *dirs, uint32_t res, uint32_t views,
                      int repeats, const double c[3], double diag)
{
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    unsigned char *rgba = (unsigned char *)malloc(4 * (size_t)res * res);
    size_t mem_bytes, vis_bytes, scratch_max = 0, rgba_bytes;
    void *mem;
    ls_arena arena;
    ls_vis vis;
    ls_real *nrm = (ls_real *)malloc(3 * (size_t)nv * sizeof(ls_real)), sh[27], *out;
    float *fv = (float *)malloc(3 * (size_t)nv * sizeof(float)), *fn = (float *)malloc(3 * (size_t)nv * sizeof(float));
    float shm[48];
    double t_gl[2] = {0, 0}, t_ls[2] = {0, 0};
    uint32_t view, i, mode;
    GLuint prog;
    ls_shade_opts o;
    if (ctx == NULL || !OSMesaMakeCurrent(ctx, rgba, GL_UNSIGNED_BYTE, (GLsizei)res, (GLsizei)res)) {
        fprintf(stderr, "cannot create an OSMesa context\n");
        return 1;
    }
    printf("     renderer: %s / %s\n", (const char *)glGetString(GL_RENDERER), (const char *)glGetString(GL_VERSION));
    if (ls_vis_bytes(res, res, 1, nv, &vis_bytes) != LS_OK || ls_shade_image_bytes(res, res, &rgba_bytes) != LS_OK)
        return 1;
    mem_bytes = vis_bytes + rgba_bytes + ((size_t)1 << 26);
    mem = malloc(mem_bytes + 8);
    ls_arena_init(&arena, mem, mem_bytes);
    if (ls_vis_init(&vis, &arena, res, res, 1, nv) != LS_OK) return 1;
    out = (ls_real *)ls_arena_alloc(&arena, rgba_bytes, 1);
    if (ls_shade_vertex_normals(pos, nv, f, nf, nrm, NULL) != LS_OK) return 1;
    for (i = 0; i < 27; i++) sh[i] = (ls_real)bench_sh[i];
    for (i = 0; i < 3 * nv; i++) {
        fv[i] = (float)v[i];
        fn[i] = (float)nrm[i];
    }
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh;
    prog = compile_program();
    if (prog == 0) return 1;
    sh_matrices(shm);
    for (view = 0; view < views; view++) {
        ls_real M[16];
        if (!view_setup(c, diag, dirs + 3 * view, res, M)) return 1;
        for (mode = 0; mode < 2; mode++) {
            double best_gl = 1e30, best_ls = 1e30;
            int rep;
            if (mode == 0) {
                glUseProgram(0);
                glShadeModel(GL_FLAT);
                glDisableClientState(GL_NORMAL_ARRAY);
                glEnableClientState(GL_VERTEX_ARRAY);
                glEnableClientState(GL_COLOR_ARRAY);
                glVertexPointer(3, GL_FLOAT, 0, tv);
                glColorPointer(3, GL_UNSIGNED_BYTE, 0, tc);
            } else {
                glUseProgram(prog);
                glUniformMatrix4fv(glGetUniformLocation(prog, "M"), 3, GL_FALSE, shm);
                glShadeModel(GL_SMOOTH);
                glDisableClientState(GL_COLOR_ARRAY);
                glEnableClientState(GL_VERTEX_ARRAY);
                glEnableClientState(GL_NORMAL_ARRAY);
                glVertexPointer(3, GL_FLOAT, 0, fv);
                glNormalPointer(GL_FLOAT, 0, fn);
            }
            for (rep = 0; rep < repeats + 1; rep++) { /* the first run warms up (shader compilation) */
                double t0 = cpu_s(), t;
                glClearColor(0, 0, 0, 0);
                glClearDepth(1.0);
                glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                if (mode == 0) glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(3 * nf));
                else glDrawElements(GL_TRIANGLES, (GLsizei)(3 * nf), GL_UNSIGNED_INT, f);
                glFinish();
                t = cpu_s() - t0;
                if (rep > 0 && t < best_gl) best_gl = t;
            }
            for (rep = 0; rep < repeats + 1; rep++) {
                double t0 = cpu_s(), t;
                if (ls_raster(&vis, &(ls_view){.positions = pos, .indices = f, .triangle_count = nf, .vertex_count = nv,
                        .mvp = M}, &arena, NULL) != LS_OK) return 1;
                if (mode == 1 && ls_shade(&(ls_view){.vis = &vis, .indices = f, .triangle_count = nf,
                        .vertex_count = nv, .normals = nrm, .opts = &o}, out, NULL) != LS_OK) return 1;
                t = cpu_s() - t0;
                if (rep > 0 && t < best_ls) best_ls = t;
            }
            if (vis.scratch_bytes > scratch_max) scratch_max = vis.scratch_bytes;
            t_gl[mode] += best_gl;
            t_ls[mode] += best_ls;
        }
    }
    for (mode = 0; mode < 2; mode++)
        printf("bench %s %u %u %u %.6f %.6f %lu\n", mode == 0 ? "vis" : "sh", res, nf, views, t_gl[mode] * 1e3,
               t_ls[mode] * 1e3, (unsigned long)(vis_bytes + scratch_max + (mode == 1 ? rgba_bytes : 0)));
    OSMesaDestroyContext(ctx);
    free(mem);
    free(rgba);
    free(nrm);
    free(fv);
    free(fn);
    return 0;
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
    if (repeats > 0) {
        int rc = bench_main(v, f, nv, nf, pos, tv, tc, dirs, res, views, repeats, c, diag);
        free(pos);
        free(dirs);
        free(tv);
        free(tc);
        free(v);
        free(f);
        return rc;
    }

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
        ls_real M[16];
        GLdouble gm[16];
        size_t p, n = (size_t)res * res, both = 0, either = 0, same_id = 0, edge_only = 1;
        double max_dz = 0;
        int cam_ok;
        /* --- OpenGL (and our matrices) --- */
        cam_ok = view_setup(c, diag, dirs + 3 * view, res, M);
        glShadeModel(GL_FLAT);
        /* unrolled vertex and colour arrays (colour = triangle index + 1 on
         * all three corners), drawn with one glDrawArrays: Mesa's fast path */
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, tv);
        glColorPointer(3, GL_UNSIGNED_BYTE, 0, tc);
        glClearColor(0, 0, 0, 0);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawArrays(GL_TRIANGLES, 0, (GLsizei)(3 * nf));
        glFinish();
        glReadPixels(0, 0, (GLsizei)res, (GLsizei)res, GL_DEPTH_COMPONENT, GL_FLOAT, gdepth);
        /* --- largesteps --- */
        if (!cam_ok) {
            report(0, "camera", "ls_camera_* failed");
            continue;
        }
        /* the two projection matrices agree (GL stores column-major) */
        {
            double max_m = 0, eye_mag = fabs(c[0]) + fabs(c[1]) + fabs(c[2]) + 1.6 * diag * 1.7320508;
            GLdouble mv[16], pr[16];
            glGetDoublev(GL_MODELVIEW_MATRIX, mv);
            glGetDoublev(GL_PROJECTION_MATRIX, pr);
            for (i = 0; i < 4; i++)
                for (k = 0; k < 4; k++) {
                    double s = 0, scale = 0;
                    int j;
                    for (j = 0; j < 4; j++) {
                        s += pr[j * 4 + i] * mv[k * 4 + j];
                        /* the size of the terms, and for the translation column
                         * of the terms -R eye that Mesa rounds to float (large
                         * and cancelling for a mesh far from the origin, such
                         * as the armadillo) */
                        scale += fabs(pr[j * 4 + i]) * (fabs(mv[k * 4 + j]) + (k == 3 && j < 3 ? eye_mag : 0));
                    }
                    gm[i * 4 + k] = s;
                    max_m = fmax(max_m, fabs(s - (double)M[i * 4 + k]) / (1 + scale));
                }
            snprintf(name, sizeof name, "view%u_matrix_matches_glu", view);
            snprintf(detail, sizeof detail, "max difference relative to the terms %.3g", max_m);
            report(max_m < 1e-5, name, detail);
        }
        {
            ls_status st = ls_raster(&vis, &(ls_view){.positions = pos, .indices = f, .triangle_count = nf,
                    .vertex_count = nv, .mvp = M}, &arena, NULL);
            if (st != LS_OK) {
                report(0, "ls_raster", ls_status_name(st));
                continue;
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
