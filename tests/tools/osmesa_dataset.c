/* osmesa_dataset.c - a camera dataset rendered by another renderer: Mesa's
 * software OpenGL (OSMesa), so that `largesteps fit DIR/transforms.json` can
 * be tried on images it did not make. A test and benchmark tool
 * (tests/bench/run_dataset.sh).
 *
 *   osmesa_dataset MESH CAMERAS.json OUTDIR [painted]
 *
 * MESH: OBJ, PLY or OFF (gzip too). CAMERAS.json: a camera dataset
 * (transforms.json, scene.h) with its w and h; its cameras (poses, field of
 * view, principal point, clip planes) are loaded into OpenGL as they are
 * (ls_scene_projection and the view matrix, transposed for OpenGL's column
 * order). Shading: OpenGL's fixed-function Gouraud lighting, one directional
 * light from the upper front right (world direction 0.4, 0.8, 0.45) with
 * diffuse 0.85 and ambient 0.15, a grey-beige material, area-weighted vertex
 * normals computed here, one sample per pixel; the background is transparent
 * (alpha 0) and alpha is 1 on the object. The lighting is not recorded:
 * OUTDIR/transforms.json is the cameras' dataset without any largesteps_*
 * lighting member, so the fit treats it as unknown. `painted`: the material's
 * colour varies over the surface (per-vertex colours, bands along the
 * bounding box's height and depth with a phase per channel, 0.25 to 1 of
 * the material), an object whose albedo is not uniform. Writes OUTDIR/view_NNN.png
 * (8-bit RGBA) and OUTDIR/transforms.json. */
#define _POSIX_C_SOURCE 200809L
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <largesteps.h>
#include "ls_posix.h"

static int die(const char *what, const char *detail)
{
    fprintf(stderr, "osmesa_dataset: %s%s%s\n", what, detail != NULL ? ": " : "", detail != NULL ? detail : "");
    return 1;
}

/* Area-weighted vertex normals (unnormalised: GL_NORMALIZE scales them). */
static void vertex_normals(const ls_mesh *m, double *n)
{
    uint32_t f, k;
    memset(n, 0, 3 * (size_t)m->vertex_count * sizeof(double));
    for (f = 0; f < m->face_count; f++) {
        const uint32_t *t = m->triangles + 3 * (size_t)f;
        double a[3], b[3], c[3];
        for (k = 0; k < 3; k++) {
            a[k] = (double)m->positions[3 * t[1] + k] - (double)m->positions[3 * t[0] + k];
            b[k] = (double)m->positions[3 * t[2] + k] - (double)m->positions[3 * t[0] + k];
        }
        c[0] = a[1] * b[2] - a[2] * b[1];
        c[1] = a[2] * b[0] - a[0] * b[2];
        c[2] = a[0] * b[1] - a[1] * b[0];
        for (k = 0; k < 3; k++) {
            n[3 * t[0] + k] += c[k];
            n[3 * t[1] + k] += c[k];
            n[3 * t[2] + k] += c[k];
        }
    }
}

/* OpenGL's column-major copy of a row-major 4 x 4 matrix. */
static void to_gl(const ls_real *m, GLdouble *g)
{
    int i, k;
    for (i = 0; i < 4; i++)
        for (k = 0; k < 4; k++) g[4 * k + i] = (GLdouble)m[4 * i + k];
}

/* The camera-to-world matrix (rows) of a rigid world-to-view matrix. */
static void camera_to_world(const ls_real *v, double *c)
{
    int i, k;
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 3; k++) c[4 * i + k] = (double)v[4 * k + i];
        c[4 * i + 3] = -((double)v[i] * (double)v[3] + (double)v[4 + i] * (double)v[7] + (double)v[8 + i] * (double)v[11]);
    }
    c[12] = c[13] = c[14] = 0;
    c[15] = 1;
}

int main(int argc, char **argv)
{
    const GLfloat light_dir[4] = {0.4f, 0.8f, 0.45f, 0.0f}, diffuse[4] = {0.85f, 0.85f, 0.85f, 1.0f};
    const GLfloat ambient[4] = {0.15f, 0.15f, 0.15f, 1.0f}, material[4] = {0.8f, 0.74f, 0.66f, 1.0f};
    const GLfloat black[4] = {0, 0, 0, 1};
    unsigned char *text = NULL, *rgba;
    size_t bytes = 0, need = 0, arena_bytes = (size_t)1 << 28;
    ls_arena arena;
    ls_scene scene;
    ls_mesh mesh;
    ls_diag d;
    ls_status st;
    double *normals;
    OSMesaContext ctx;
    FILE *out;
    char path[4096];
    uint32_t v, w, h, x, y, f, k;
    void *mem;
    int painted = argc == 5 && strcmp(argv[4], "painted") == 0;
    double lo[3], hi[3];
    if (argc != 4 && !painted) {
        fprintf(stderr, "usage: osmesa_dataset MESH CAMERAS.json OUTDIR [painted]\n");
        return 2;
    }
    mem = malloc(arena_bytes);
    if (mem == NULL || ls_arena_init(&arena, mem, arena_bytes) != LS_OK) return die("out of memory", NULL);
    ls_diag_clear(&d);
    if (ls_posix_load_mesh(argv[1], &arena, &mesh, &d) != LS_OK) return die(argv[1], d.what);
    if (ls_posix_read_file(argv[2], &text, &bytes) != LS_OK) return die(argv[2], ls_posix_read_error());
    st = ls_scene_parse_transforms_bytes((const char *)text, bytes, &need, &d);
    if (st == LS_OK) st = ls_scene_parse_transforms((const char *)text, bytes, &arena, &scene, &d);
    free(text);
    if (st != LS_OK) return die(argv[2], d.what);
    if (scene.width == 0 || scene.height == 0) return die(argv[2], "the dataset gives no w and h");
    w = scene.width;
    h = scene.height;
    if (ls_posix_mkdir_p(argv[3]) != 0) return die("cannot create", argv[3]);
    normals = (double *)malloc(3 * (size_t)mesh.vertex_count * sizeof(double));
    rgba = (unsigned char *)malloc(4 * (size_t)w * h);
    if (normals == NULL || rgba == NULL) return die("out of memory", NULL);
    vertex_normals(&mesh, normals);
    ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    if (ctx == NULL || !OSMesaMakeCurrent(ctx, rgba, GL_UNSIGNED_BYTE, (GLsizei)w, (GLsizei)h))
        return die("cannot create an OSMesa context", NULL);
    glViewport(0, 0, (GLsizei)w, (GLsizei)h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DITHER);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glShadeModel(GL_SMOOTH);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, black);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
    glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
    glLightfv(GL_LIGHT0, GL_SPECULAR, black);
    glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE, material);
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, black);
    if (painted) {
        glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
        glEnable(GL_COLOR_MATERIAL);
    }
    for (k = 0; k < 3; k++) lo[k] = hi[k] = (double)mesh.positions[k];
    for (f = 0; f < mesh.vertex_count; f++)
        for (k = 0; k < 3; k++) {
            const double c = (double)mesh.positions[3 * (size_t)f + k];
            if (c < lo[k]) lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    out = NULL;
    snprintf(path, sizeof path, "%s/transforms.json", argv[3]);
    out = fopen(path, "w");
    if (out == NULL) return die("cannot write", path);
    {
        const ls_scene_camera *c = &scene.cameras[0];
        fprintf(out, "{\n  \"camera_angle_%s\": %.17g,\n  \"w\": %u,\n  \"h\": %u,\n", c->fov_axis == LS_FOV_Y ? "y" : "x",
                (double)c->fov, (unsigned)w, (unsigned)h);
        if (c->center[0] != 0 || c->center[1] != 0)
            fprintf(out, "  \"cx\": %.17g,\n  \"cy\": %.17g,\n", ((double)c->center[0] + 1.0) * w / 2.0,
                    (1.0 - (double)c->center[1]) * h / 2.0);
        fprintf(out, "  \"largesteps_clip\": [%.17g, %.17g],\n  \"frames\": [\n", (double)c->near_plane,
                (double)c->far_plane);
    }
    for (v = 0; v < scene.camera_count; v++) {
        ls_real proj[16];
        GLdouble g[16];
        ls_image img;
        ls_image_format png = {LS_IMAGE_PNG, 4, 8, 0};
        ls_arena_mark mark = ls_arena_save(&arena);
        double c2w[16];
        char name[64];
        if (ls_scene_projection(&scene, v, proj) != LS_OK) return die("camera", "ls_scene_projection failed");
        glMatrixMode(GL_PROJECTION);
        to_gl(proj, g);
        glLoadMatrixd(g);
        glMatrixMode(GL_MODELVIEW);
        to_gl(scene.cameras[v].view, g);
        glLoadMatrixd(g);
        glLightfv(GL_LIGHT0, GL_POSITION, light_dir); /* in world space: after the view */
        glClearColor(0, 0, 0, 0);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glBegin(GL_TRIANGLES);
        for (f = 0; f < mesh.face_count; f++)
            for (k = 0; k < 3; k++) {
                const uint32_t i = mesh.triangles[3 * (size_t)f + k];
                if (painted) {
                    const double ty = ((double)mesh.positions[3 * i + 1] - lo[1]) / (hi[1] - lo[1] + 1e-30);
                    const double tz = ((double)mesh.positions[3 * i + 2] - lo[2]) / (hi[2] - lo[2] + 1e-30);
                    double col[3];
                    int c;
                    for (c = 0; c < 3; c++)
                        col[c] = (double)material[c] *
                                 (0.625 + 0.375 * sin(6.283185307179586 * (2.0 * ty + 0.5 * tz) + 2.0943951023931953 * c));
                    glColor3d(col[0], col[1], col[2]);
                }
                glNormal3d(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
                glVertex3d((double)mesh.positions[3 * i], (double)mesh.positions[3 * i + 1],
                           (double)mesh.positions[3 * i + 2]);
            }
        glEnd();
        glFinish();
        if (ls_image_create(&img, w, h, &arena) != LS_OK) return die("out of memory", NULL);
        for (y = 0; y < h; y++) /* OpenGL's rows bottom first */
            for (x = 0; x < w; x++)
                for (k = 0; k < 4; k++)
                    img.pixels[4 * ((size_t)y * w + x) + k] = (float)rgba[4 * ((size_t)(h - 1 - y) * w + x) + k] / 255.0f;
        snprintf(name, sizeof name, "view_%03u.png", (unsigned)v);
        if (!ls_posix_write_image_in(argv[3], name, &img, &png, &arena, NULL)) return die("cannot write", name);
        ls_arena_restore(&arena, mark);
        camera_to_world(scene.cameras[v].view, c2w);
        fprintf(out, "    {\"file_path\": \"%s\", \"transform_matrix\": [", name);
        for (k = 0; k < 4; k++)
            fprintf(out, "%s[%.17g, %.17g, %.17g, %.17g]", k > 0 ? ", " : "", c2w[4 * k], c2w[4 * k + 1], c2w[4 * k + 2],
                    c2w[4 * k + 3]);
        fprintf(out, "]}%s\n", v + 1 < scene.camera_count ? "," : "");
    }
    fprintf(out, "  ]\n}\n");
    if (fclose(out) != 0) return die("cannot write", path);
    OSMesaDestroyContext(ctx);
    free(normals);
    free(rgba);
    free(mem);
    printf("%u views of %s at %u x %u by %s into %s\n", (unsigned)scene.camera_count, argv[1], (unsigned)w, (unsigned)h,
           (const char *)"OSMesa", argv[3]);
    return 0;
}
