/* render_gradient.c - one view rendered, and the gradient of an image loss
 * with respect to the vertex positions: the interior term (shading through
 * the barycentrics and the vertex normals) plus the exact silhouette term.
 * The mesh is a sphere; the target is the same view of an ellipsoid. A small
 * step against the gradient lowers the loss.
 */
#include <stdio.h>
#include <math.h>
#include <string.h>
#include <largesteps.h>

#define RES 64u
#define SS 4u

static LS_ARENA_BUFFER(work, 8 << 20);
static ls_real target[4 * RES * RES], image[4 * RES * RES], gimage[4 * RES * RES];

/* Renders the view's positions into out (RGBA); its normals are computed first. */
static ls_status render(ls_vis *vis, const ls_view *view, ls_real *normals, ls_arena *a, ls_real *out)
{
    ls_status st = ls_shade_vertex_normals(view->positions, view->vertex_count, view->indices, view->triangle_count,
                                           normals, NULL);
    if (st == LS_OK) st = ls_raster(vis, view, a, NULL);
    if (st == LS_OK) st = ls_shade(view, out, NULL);
    return st;
}

/* The mean squared difference to the target and its gradient image. */
static ls_status image_loss(const ls_real *img, ls_real *grad, ls_real *loss)
{
    ls_loss_acc acc;
    ls_status st = ls_loss_begin(&acc, LS_LOSS_L2, RES, RES, 1);
    if (st == LS_OK) st = ls_loss_view(&acc, img, target, grad, NULL);
    if (st == LS_OK) st = ls_loss_finish(&acc, loss);
    return st;
}

int main(void)
{
    ls_arena a;
    ls_mesh m;
    ls_vis vis;
    ls_edge_table edges;
    ls_shade_opts o;
    ls_view sphere, ellipsoid; /* the same view of two meshes */
    ls_diag d;
    ls_real proj[16], view[16], mvp[16], sh[27] = {0}, loss = 0, loss2 = 0, norm = 0;
    ls_real *ell, *normals, *gnormals, *gpos, *moved;
    const ls_real center[3] = {0, 0, 0}, dir[3] = {(ls_real)0.3, (ls_real)0.4, 1};
    uint32_t i, n3;
    ls_status st = ls_arena_init(&a, work.bytes, sizeof work.bytes);
    if (st == LS_OK) st = ls_icosphere(3, &a, &m);
    if (st != LS_OK) return 1;
    n3 = 3u * m.vertex_count;
    ell = ls_arena_alloc(&a, n3, sizeof(ls_real));
    normals = ls_arena_alloc(&a, n3, sizeof(ls_real));
    gnormals = ls_arena_alloc_zero(&a, n3, sizeof(ls_real));
    gpos = ls_arena_alloc_zero(&a, n3, sizeof(ls_real));
    moved = ls_arena_alloc(&a, n3, sizeof(ls_real));
    if (moved == NULL) return 1;
    for (i = 0; i < n3; i++) ell[i] = m.positions[i] * (i % 3 == 1 ? (ls_real)0.7 : (ls_real)1.1);

    /* The camera, the lighting (a few SH bands, light from above), the buffers. */
    ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1, 10, proj);
    ls_camera_orbit(center, (ls_real)3.2, dir, view);
    ls_mat4_mul(proj, view, mvp);
    for (i = 0; i < 3; i++) sh[9 * i] = (ls_real)1.5, sh[9 * i + 1] = (ls_real)0.8;
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = sh;
    st = ls_vis_init(&vis, &a, RES, RES, SS, m.vertex_count);
    if (st == LS_OK) st = ls_edge_table_build(&edges, m.triangles, m.face_count, m.vertex_count, &a, &d);

    /* One view: everything the render, shading and gradient calls read. */
    memset(&sphere, 0, sizeof sphere);
    sphere.vis = &vis;
    sphere.positions = m.positions;
    sphere.indices = m.triangles;
    sphere.triangle_count = m.face_count;
    sphere.vertex_count = m.vertex_count;
    sphere.normals = normals;
    sphere.opts = &o;
    sphere.mvp = mvp;
    sphere.table = &edges;
    sphere.boost = 1; /* the exact silhouette gradient */
    ellipsoid = sphere;
    ellipsoid.positions = ell;

    /* Forward: the target, then the sphere and the loss. */
    if (st == LS_OK) st = render(&vis, &ellipsoid, normals, &a, target);
    if (st == LS_OK) st = render(&vis, &sphere, normals, &a, image);
    if (st == LS_OK) st = image_loss(image, gimage, &loss);

    /* Backward: interior shading, the normals' chain, then the silhouette. */
    if (st == LS_OK) st = ls_shade_backward(&sphere, gimage, gpos, gnormals, NULL, &d);
    if (st == LS_OK)
        st = ls_vertex_normals_backward(m.positions, m.vertex_count, m.triangles, m.face_count, gnormals, gpos, &a, &d);
    if (st == LS_OK) st = ls_silhouette_backward(&sphere, gimage, gpos, &a, &d);
    if (st != LS_OK) {
        printf("%s (%s)\n", ls_status_str(st), d.what);
        return 1;
    }
    for (i = 0; i < n3; i++) norm += gpos[i] * gpos[i];
    norm = (ls_real)sqrt((double)norm);
    printf("%u x %u, %u x %u samples per pixel: loss %.6e, |dL/dx| %.6e\n", RES, RES, SS, SS, (double)loss,
           (double)norm);

    /* A step of 0.02 against the gradient's direction lowers the loss. */
    for (i = 0; i < n3; i++) moved[i] = m.positions[i] - (ls_real)0.02 * gpos[i] / norm;
    sphere.positions = moved;
    st = render(&vis, &sphere, normals, &a, image);
    if (st == LS_OK) st = image_loss(image, NULL, &loss2);
    if (st != LS_OK) return 1;
    printf("after a step of 0.02 along -dL/dx: loss %.6e (%s)\n", (double)loss2, loss2 < loss ? "lower" : "NOT lower");
    return loss2 < loss ? 0 : 1;
}
