/* largesteps/primitive.h - meshes generated from a few parameters: the
 * icosphere (the method's initial mesh, and the tests' sphere) and a planar
 * grid (an open mesh with a boundary).
 *
 * Both are deterministic: the same bits on every target (vertices are
 * normalised with the correctly rounded sqrt, nothing else is transcendental).
 */
#ifndef LARGESTEPS_PRIMITIVE_H
#define LARGESTEPS_PRIMITIVE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/mesh.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Subdivision levels above this overflow the 32-bit face count. */
#define LS_ICOSPHERE_MAX_LEVEL 13u

/* ls_icosphere_counts: vertices (10 * 4^level + 2), faces (20 * 4^level)
 * and edges (30 * 4^level) of ls_icosphere(level). Errors: LS_ERR_INVALID
 * (NULL), LS_ERR_TOO_LARGE (level above LS_ICOSPHERE_MAX_LEVEL). O(1). */
ls_status ls_icosphere_counts(uint32_t level, uint32_t *vertices, uint32_t *faces, uint32_t *edges);

/* ls_icosphere_bytes: exact arena bytes of ls_icosphere(level): the mesh plus
 * the peak scratch of the subdivision (the edge table of the level before
 * the last). O(1). Errors: as ls_icosphere_counts, LS_ERR_TOO_LARGE on size_t
 * overflow. */
ls_status ls_icosphere_bytes(uint32_t level, size_t *bytes);

/* ls_icosphere: the unit sphere as a regular icosahedron whose triangles are
 * split into four `level` times, every new vertex (an edge midpoint) pushed
 * out to the sphere. Faces are oriented counter-clockwise seen from outside
 * (outward normals); vertices 0..11 are the icosahedron's, and the vertices
 * of level l are a prefix of those of level l + 1. Time O(F log F) (the edge
 * table is sorted at each level). Memory: the mesh from the arena's bottom,
 * scratch released. Errors: LS_ERR_INVALID (NULL), LS_ERR_TOO_LARGE,
 * LS_ERR_NOMEM (arena and *mesh unchanged). */
ls_status ls_icosphere(uint32_t level, ls_arena *arena, ls_mesh *mesh);

/* ls_grid_mesh_bytes: exact arena bytes of ls_grid_mesh(nx, ny). O(1).
 * Errors: LS_ERR_INVALID (NULL, nx or ny zero), LS_ERR_TOO_LARGE. */
ls_status ls_grid_mesh_bytes(uint32_t nx, uint32_t ny, size_t *bytes);

/* ls_grid_mesh: the unit square [0, 1] x [0, 1] in the plane z = 0 as nx x ny
 * cells of two triangles each (the diagonal from the cell's lower-left to its
 * upper-right corner), normals +z. Vertex (i, j) is number j (nx + 1) + i at
 * (i / nx, j / ny, 0). O(nx ny). Errors: as ls_grid_mesh_bytes, LS_ERR_NOMEM
 * (arena and *mesh unchanged). */
ls_status ls_grid_mesh(uint32_t nx, uint32_t ny, ls_arena *arena, ls_mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_PRIMITIVE_H */
