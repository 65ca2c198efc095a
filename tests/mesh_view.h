/* tests/mesh_view.h - a mesh seen as the gradient tests and benchmarks see
 * it: the SH lighting they shade with, the mesh's bounding-box frame, the
 * perspective camera looking at it, and a triangle far outside the image
 * that opens a closed mesh (its boundary edges turn off the closed-mesh
 * shortcuts of the silhouette and refine passes, and change nothing else). */
#ifndef LS_TEST_MESH_VIEW_H
#define LS_TEST_MESH_VIEW_H

#include <string.h>
#include <largesteps.h>

/* SH coefficients, 9 per channel (R, G, B): a warm key light from above. */
static const ls_real mv_sh[27] = {
    (ls_real)0.8, (ls_real)0.1, (ls_real)0.3, (ls_real)-0.2, (ls_real)0.05, 0, (ls_real)-0.1, (ls_real)0.02, (ls_real)0.07,
    (ls_real)0.7, (ls_real)0.2, (ls_real)0.25, (ls_real)-0.1, 0, (ls_real)0.04, (ls_real)-0.08, (ls_real)0.01, (ls_real)0.05,
    (ls_real)0.6, (ls_real)0.15, (ls_real)0.35, (ls_real)-0.15, (ls_real)0.03, (ls_real)0.02, (ls_real)-0.12, 0, (ls_real)0.06};

/* Shading options: SH lighting mv_sh over a grey-green background (edges
 * over the background and over the surface behind both count). */
static inline void mv_shade_opts(ls_shade_opts *o)
{
    ls_shade_opts_init(o);
    o->mode = LS_SHADE_SH;
    o->sh = mv_sh;
    o->background[0] = (ls_real)0.3;
    o->background[1] = (ls_real)0.5;
    o->background[2] = (ls_real)0.2;
}

/* The centre c of the mesh's bounding box and its largest half-side r. */
static inline void mv_frame(const ls_mesh *m, ls_real c[3], ls_real *r)
{
    ls_real lo[3], hi[3];
    uint32_t v, k;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = m->positions[k];
    for (v = 0; v < m->vertex_count; v++)
        for (k = 0; k < 3; k++) {
            ls_real x = m->positions[3 * (size_t)v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    *r = 0;
    for (k = 0; k < 3; k++) {
        c[k] = (lo[k] + hi[k]) / 2;
        *r = (hi[k] - lo[k]) / 2 > *r ? (hi[k] - lo[k]) / 2 : *r;
    }
}

/* The view (view) and clip (mvp) matrices of a camera at c + (0.9, 0.6, 2.6) r
 * looking at c, y up, 0.8 rad vertical field of view, near 0.1 r, far 10 r. */
static inline void mv_camera(const ls_real c[3], ls_real r, ls_real view[16], ls_real mvp[16])
{
    ls_real eye[3], up[3] = {0, 1, 0}, proj[16];
    eye[0] = c[0] + (ls_real)0.9 * r;
    eye[1] = c[1] + (ls_real)0.6 * r;
    eye[2] = c[2] + (ls_real)2.6 * r;
    ls_camera_look_at(eye, c, up, view);
    ls_camera_perspective((ls_real)0.8, LS_FOV_Y, 1, (ls_real)0.1 * r, 10 * r, proj);
    ls_mat4_mul(proj, view, mvp);
}

/* Mesh m into pos [3 (V + 3)] and tri [3 (T + 1)] with one more triangle,
 * 40 r to the side of c at c's depth (in front of mv_camera's eye, far
 * outside its image). */
static inline void mv_open_far(const ls_mesh *m, const ls_real c[3], ls_real r, ls_real *pos, uint32_t *tri)
{
    uint32_t k, nv = m->vertex_count;
    memcpy(pos, m->positions, 3 * (size_t)nv * sizeof(ls_real));
    memcpy(tri, m->triangles, 3 * (size_t)m->face_count * sizeof(uint32_t));
    for (k = 0; k < 3; k++) {
        pos[3 * (size_t)(nv + k)] = c[0] - 40 * r + (ls_real)(k == 1) * r / 10;
        pos[3 * (size_t)(nv + k) + 1] = c[1] + (ls_real)(k == 2) * r / 10;
        pos[3 * (size_t)(nv + k) + 2] = c[2];
        tri[3 * (size_t)m->face_count + k] = nv + k;
    }
}

#endif
