/* largesteps.h - umbrella header: includes every public header of the library.
 *
 * largesteps is a C99 library for inverse rendering of triangle meshes
 * ("Large Steps in Inverse Rendering of Geometry", Nicolet, Jacobson, Jakob
 * 2021). All memory comes from a caller-provided arena (largesteps/arena.h),
 * every failure is a returned ls_status (largesteps/status.h), and results are
 * the same bits on every compiler and architecture (largesteps/math.h).
 */
#ifndef LARGESTEPS_H
#define LARGESTEPS_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/monitor.h>
#include <largesteps/parallel.h>
#include <largesteps/math.h>
#include <largesteps/sparse.h>
#include <largesteps/order.h>
#include <largesteps/ldlt.h>
#include <largesteps/stream.h>
#include <largesteps/checksum.h>
#include <largesteps/inflate.h>
#include <largesteps/image.h>
#include <largesteps/contact.h>
#include <largesteps/camera.h>
#include <largesteps/raster.h>
#include <largesteps/texture.h>
#include <largesteps/shade.h>
#include <largesteps/loss.h>
#include <largesteps/render_backward.h>
#include <largesteps/silhouette.h>
#include <largesteps/raster_refine.h>
#include <largesteps/number.h>
#include <largesteps/sort.h>
#include <largesteps/mesh.h>
#include <largesteps/mesh_io.h>
#include <largesteps/bvh.h>
#include <largesteps/optim.h>
#include <largesteps/primitive.h>
#include <largesteps/scene.h>
#include <largesteps/fit.h>
#include <largesteps/laplacian.h>
#include <largesteps/cg.h>
#include <largesteps/grid_solve.h>
#include <largesteps/param.h>
#include <largesteps/toy1d.h>
#include <largesteps/distance.h>
#include <largesteps/tangle.h>
#include <largesteps/halfedge.h>
#include <largesteps/remesh.h>
#include <largesteps/visual_hull.h>
#include <largesteps/mask.h>

#endif /* LARGESTEPS_H */
