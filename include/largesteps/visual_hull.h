/* largesteps/visual_hull.h - the visual hull of an object seen in masked
 * views: the closed surface of the points that every view sees inside its
 * mask. A start for a fit that already has the target's limbs, ears and tails
 * apart, which a sphere has to grow and often webs together.
 *
 * Method. The box is split into cubic cells, one cell of padding around it.
 * At every grid point the field f = min over views of (alpha - threshold) is
 * taken, alpha sampled bilinearly at the point's projection (camera.h's
 * window convention, pixel centres at +0.5); a view the point projects behind
 * or off the image (by more than half a pixel) says nothing about it. The
 * padding's points are outside. The surface f = 0 is extracted by marching
 * tetrahedra on the Kuhn split of each cell into six tetrahedra along its
 * main diagonal (neighbouring cells split their common faces alike), one
 * vertex per crossed edge, linearly interpolated (kept 2 % of an edge away
 * from its ends so no face degenerates). The result is a closed, oriented
 * (outward normals) 2-manifold; only its component with the most faces is
 * kept (specks carved free by a mask's noise are dropped).
 *
 * Everything is deterministic: points in x-fastest order, views in index
 * order, vertices numbered as they are first met.
 */
#ifndef LARGESTEPS_VISUAL_HULL_H
#define LARGESTEPS_VISUAL_HULL_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The views carved from. */
typedef struct ls_hull_views {
    const ls_real *const *images; /* count RGBA images, width x height, rows top first (shade.h):
                                     the alpha channel is the mask */
    const ls_real *mvps;          /* count 4 x 4 model-view-projection matrices, 16 values each (camera.h) */
    uint32_t count;               /* views (1..65535) */
    uint32_t width, height;       /* pixels of every image (1..65535) */
} ls_hull_views;

typedef struct ls_hull_params {
    ls_real lo[3], hi[3]; /* the box that holds the object (lo < hi on every axis) */
    uint32_t resolution;  /* cells along the box's longest side (2..1024; default 128) */
    ls_real threshold;    /* a pixel is inside where its alpha is at least this (0 < t < 1; default 0.5) */
} ls_hull_params;

/* ls_hull_params_default: the box lo..hi, 128 cells, threshold 0.5. O(1). */
void ls_hull_params_default(ls_hull_params *params, const ls_real lo[3], const ls_real hi[3]);

/* ls_visual_hull_bytes: the exact arena bytes ls_visual_hull takes with these
 * views and parameters (the grid's field and two layers of edge vertices as
 * scratch, the kept component's mesh). It carves and counts in the arena's
 * free space, which must hold the field and the layers (else LS_ERR_NOMEM),
 * and restores the arena. Time as ls_visual_hull. Errors: as ls_visual_hull,
 * LS_ERR_MESH when no point is inside every view. */
ls_status ls_visual_hull_bytes(const ls_hull_views *views, const ls_hull_params *params, ls_arena *arena,
                               size_t *bytes, ls_diag *diag);

/* ls_visual_hull: the hull's surface into *out (positions and triangles from
 * the arena's bottom; the rest is scratch, released). Time O(P V) for the P
 * grid points and V views (a point leaves the views' loop at the first view
 * that sees it outside every mask), plus O(cells). Errors: LS_ERR_INVALID
 * (NULL, bad counts or parameters; diag names them), LS_ERR_NONFINITE (a
 * matrix or box value), LS_ERR_MESH (no point is inside every view: the masks
 * are empty, or the cameras do not look at the box), LS_ERR_TOO_LARGE (more
 * than 2^31 points, edges or faces), LS_ERR_NOMEM (arena and *out unchanged). */
ls_status ls_visual_hull(const ls_hull_views *views, const ls_hull_params *params, ls_arena *arena, ls_mesh *out,
                         ls_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_VISUAL_HULL_H */
