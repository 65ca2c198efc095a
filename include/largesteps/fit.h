/* largesteps/fit.h - the reconstruction loop: a mesh fitted to target images
 * of several views by gradient descent, with the large-steps
 * parameterization or one of the baselines the paper compares against.
 *
 * Per iteration (ls_fit_step), as the reference's scripts/main.py:
 *   x = M^{-1} u                      (large steps; the baselines keep x)
 *   for every view, in order:         raster, vertex normals, shade, loss
 *                                     gradient, shading backward,
 *                                     silhouette backward (times `boost`)
 *   dL/dx += normals backward         (through the vertex normals)
 *   baselines: + w d/dx of mean(x . L x) or mean((L x)^2)
 *   dL/du = M^{-1} dL/dx              (large steps)
 *   optimizer step on u (or x), and on the global translation block when
 *   use_translation is set (its own UniformAdam scale, as the reference's
 *   separate `tr` tensor).
 * The loss is the mean over views, pixels and RGBA channels (loss.h).
 *
 * Methods: LS_FIT_LARGE_STEPS (the paper's; UniformAdam by default),
 * LS_FIT_NAIVE (the optimizer on x), LS_FIT_LAPLACIAN and
 * LS_FIT_BILAPLACIAN (the optimizer on x with the reference's regularizers
 * mean(x . L x) and mean((L x)^2) over the 3n values, weight reg_weight, L the
 * uniform Laplacian).
 *
 * Memory: the object lives in one block of the caller's arena whose size
 * ls_fit_bytes gives exactly for an initial mesh (the factor of M depends on
 * the connectivity, so the query runs the symbolic analysis in scratch). The
 * iteration allocates nothing: everything it needs is in the block.
 * For a whole job with remeshes, ls_fit_job_bytes and ls_fit_init_job
 * reserve once, from a capacity, everything the fit and its remeshes will
 * ever take (below); nothing is allocated from the caller's arena after.
 *
 * Errors during an iteration name what failed: a NaN or infinity in a
 * target, a rendered image, the loss, a gradient or an updated parameter
 * gives LS_ERR_NONFINITE with diag->index = the iteration and diag->what
 * naming the stage. A failed step writes nothing half-done: x, u, params,
 * the optimizer's state, the solver's state (CG warm starts), iteration,
 * loss, reg_loss and timing are byte for byte as before the call; only the
 * working arrays (grad, gx, xr, normals, gnormals, image, gimage, vis) hold
 * whatever the step left in them.
 *
 * Scale: the fit works in a normalized frame. At init it measures the
 * initial mesh: R = half the largest side of its bounding box and S = the
 * largest power of two <= R (R = S = 1 for a mesh collapsed to a point).
 * Inside, positions are the caller's divided by S and the views' transforms
 * have their translation column divided by S (the same normalized device
 * coordinates, bit for bit); the learning rate is in units of R (the
 * optimizer moves by lr R / S in the frame). Everything else is measured in
 * the frame: Adam's eps (on gradients of frame coordinates), the
 * regularizers, the remeshing target (a fraction of the mean edge), the
 * remesher's, BVH's and rasterizer's tolerances. Because S is a power of
 * two, scaling the scene (initial mesh and the views' camera positions, near
 * and far planes; target images unchanged) by 2^k leaves every bit inside
 * the fit unchanged and scales ls_fit_mesh's result by exactly 2^k, as long
 * as no coordinate overflows or becomes subnormal (tests/test_extreme.c:
 * k = -20 ... 20). x, u, params (with the translation), reg_loss and the
 * optimizer's state are in the frame; ls_fit_mesh returns caller units.
 * ls_fit_remesh keeps the first fit's frame (S and R).
 *
 * Extremes (tests/test_extreme.c): lambda = 0 and 1e-8 fit as usual;
 * lambda = 1e8 fits in double and is LS_ERR_NOT_SPD at init in float
 * (param.h). In the alpha form M = (1 - alpha) I + alpha L moves the mean of
 * x by lr / (1 - alpha) per unit step of u: alpha = 0.999999 stays finite
 * but runs away (|x| ~ 5e4 after 4 steps at lr 0.05) unless lr is scaled by
 * 1 - alpha. A mesh collapsed to a point or behind every camera draws
 * nothing and gets zero gradients; a camera inside the mesh sees its inside.
 *
 * Determinism: views, pixels, edges and vertices are visited in a fixed
 * order; the same inputs give the same bits on every target.
 */
#ifndef LARGESTEPS_FIT_H
#define LARGESTEPS_FIT_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/monitor.h>
#include <largesteps/mesh.h>
#include <largesteps/sparse.h>
#include <largesteps/raster.h>
#include <largesteps/shade.h>
#include <largesteps/silhouette.h>
#include <largesteps/raster_refine.h>
#include <largesteps/optim.h>
#include <largesteps/param.h>
#include <largesteps/remesh.h>
#include <largesteps/tangle.h>
#include <largesteps/parallel.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Methods. */
#define LS_FIT_LARGE_STEPS 0u
#define LS_FIT_NAIVE       1u
#define LS_FIT_LAPLACIAN   2u
#define LS_FIT_BILAPLACIAN 3u

/* Silhouette gradient modes (silhouette.h). */
#define LS_FIT_SILHOUETTE_EXACT 0u /* ls_silhouette_backward: exact for a box pixel filter */
#define LS_FIT_SILHOUETTE_PAIR  1u /* ls_pair_forward/backward: nvdiffrast-style blending of pixel pairs (S = 1) */
#define LS_FIT_SILHOUETTE_NONE  2u /* no silhouette term: interior shading gradients only */

/* The mean (rigid translation) mode of the large-steps gradient dL/du.
 * M^-1 amplifies it the most (1 / (1 - alpha), or 1 in the lambda form
 * against 1 + lambda mu for the other modes), so under UniformAdam's one
 * maximum it can take the whole step and the mesh jitters as a block. */
#define LS_FIT_MEAN_KEEP    0u /* the paper's: u moves the mean like any other mode */
#define LS_FIT_MEAN_PROJECT 1u /* its per-axis mean taken out of dL/du: the translation block
                                  (use_translation, required) alone moves the mesh as a whole */

/* The lighting (config.light). LS_FIT_LIGHT_ESTIMATE is for targets whose
 * lighting is not known: the 27 SH coefficients (shade.h; with a uniform
 * albedo, which scales each channel's 9, they are the albedo too) are
 * estimated from the targets on the current geometry, in closed form
 * (ls_sh_accumulate, ls_sh_solve: linear least squares over the pixels
 * covered in both the render and the target's mask), and the geometry is
 * fitted under them: the two alternate. The iterations i with
 * i mod LS_FIT_LIGHT_EVERY = LS_FIT_LIGHT_EVERY - 1 accumulate the sums while
 * they render (their batch of views and vertex normals; no second raster
 * pass) and solve them once their step has succeeded: the iterations after
 * shade with that estimate. The first iteration estimates from its own
 * views first, in a pass of rasters of its own. An estimate that cannot be
 * solved (no pixel in common) keeps the previous one (zeros at first). The
 * estimate is fit->sh; remeshes keep it and the checkpoint saves it.
 * LS_FIT_LIGHT_GIVEN costs nothing of this. */
#define LS_FIT_LIGHT_GIVEN    0u /* config.shading as given */
#define LS_FIT_LIGHT_ESTIMATE 1u /* SH estimated from the targets (shading.mode LS_SHADE_SH; shading.sh unused) */
/* The estimate's period in iterations: its sums cost about a sixth of an
 * iteration at 128 x 128 (the armadillo's dataset), a fit's lighting settles in
 * far fewer iterations than its geometry. */
#define LS_FIT_LIGHT_EVERY 8u

/* The albedo with estimated lighting (config.albedo). LS_FIT_ALBEDO_UNIFORM:
 * one colour, carried by the 27 coefficients. LS_FIT_ALBEDO_VERTEX: an RGB
 * albedo per vertex (fit->albedo, mean 1 per channel, the scale in the
 * lighting), for objects whose colour varies; the estimate's iterations
 * also add the albedo's sums (ls_albedo_accumulate, under the lighting in
 * use) and, once the step has succeeded, solve both: the lighting given the
 * albedo, the albedo given the lighting (ls_albedo_solve). The albedo
 * starts at 1; a remesh starts it at 1 again (its vertices are new) and the
 * next iteration estimates it; a roll-back keeps it. The renders, the
 * shading gradient and the silhouettes then take the general (vertex
 * colour) paths: slower than the uniform albedo's. */
#define LS_FIT_ALBEDO_UNIFORM 0u
#define LS_FIT_ALBEDO_VERTEX  1u

/* Parallelism the caller provides (largesteps/parallel.h). An iteration's
 * views are independent until their gradients are summed: with
 * config.workers = W > 1 and config.parallel.run set, the views of a batch
 * are taken LS_FIT_SLOTS_PER_WORKER W at a time (all at once when the batch
 * is no larger: one wait for the slowest view per iteration), each rendered,
 * shaded and differentiated (raster, shading, loss, shading backward,
 * silhouettes, the lighting's sums) by one of the caller's workers into a
 * slot of its own, and the slots are then added to the totals in view order
 * (their vertex ranges split over the workers). Each view's gradient starts from zero, so
 * the sum's order is the views' whatever W and whatever worker ran which
 * view: the same bits for every worker count, and with no parallel-for at
 * all (the slots then run one after another on the calling thread). The
 * self-intersection checks (ls_fit_tangle, the guard's check of a remesh)
 * split their faces over the same workers.
 *
 * The monitor's clock (if any) is read from the workers; its report
 * callback is called from the calling thread only. Memory: every worker
 * beyond the first holds a visibility buffer, the images and a raster
 * scratch; every slot (min(LS_FIT_SLOTS_PER_WORKER W, the batch)) a
 * view's gradient (6 n reals, 12 n with LS_FIT_ALBEDO_VERTEX); ls_fit_bytes
 * and ls_fit_job_bytes include them for the configured W. */
#define LS_FIT_SLOTS_PER_WORKER 8u
#define LS_FIT_MAX_WORKERS 1024u

/* The factor's ordering (LS_FIT_LARGE_STEPS with the LDL^T): AMD below
 * LS_FIT_AUTO_ORDER_VERTICES vertices, LS_ORDER_AUTO (AMD or nested
 * dissection, the smaller predicted fill) from there on, where AMD's fill
 * grows faster than n log n on regular meshes. A job sizes for its
 * capacity's ordering. */
#define LS_FIT_AUTO_ORDER_VERTICES 16384u

typedef struct ls_fit_config {
    uint32_t method;          /* LS_FIT_* */
    uint32_t form;            /* LS_SYSTEM_LAMBDA (M = I + lambda L) or LS_SYSTEM_ALPHA */
    ls_real weight;           /* lambda or alpha (large steps) */
    uint32_t solver;          /* LS_PARAM_LDLT, LS_PARAM_CG or LS_PARAM_AUTO (= LDL^T on a mesh) */
    ls_optim_config optim;    /* optimizer of u (large steps) or x (baselines); lr in units of R (above) */
    uint32_t use_translation; /* 1: optimize a global translation too */
    ls_real reg_weight;       /* LS_FIT_LAPLACIAN / LS_FIT_BILAPLACIAN */
    uint32_t loss;            /* LS_LOSS_L1 or LS_LOSS_L2 */
    ls_real boost;            /* silhouette gradient multiplier (the paper uses 3); read at every
                                 step, so a caller may change fit->config.boost between steps
                                 (largesteps fit lowers it for the finest stage) */
    uint32_t width, height;   /* render size */
    uint32_t ss;              /* samples per pixel side of the fit's renders (1, 2, 4) */
    ls_shade_opts shading;    /* mode, SH, lights, background (vertex_colors must be NULL) */
    uint32_t silhouette;      /* LS_FIT_SILHOUETTE_* */
    uint32_t power;           /* large steps: the gradient's preconditioner M^-p. 2 (0 means 2): the
                               * method, the optimizer on u = M x (a step in u is one M^-1 in x, its
                               * gradient another); 1: the optimizer on x with gradient M^-1 dL/dx */
    ls_real cg_tol;           /* LS_PARAM_CG: relative residual tolerance (0 means 1e-6) */
    uint32_t aa;              /* adaptive supersampling of silhouette pixels (raster_refine.h): A x A
                               * sub-samples there, forward and interior gradient; A <= ss (0 default)
                               * is off; at most LS_REFINE_MAX; not with the pair mode */
    uint32_t mean_mode;       /* large steps: LS_FIT_MEAN_* */
    uint32_t guard;           /* 1: the fit holds a checkpoint (ls_fit_save, ls_fit_rollback) and the
                               * memory of its self-intersection check (ls_fit_tangle); 0: neither */
    uint32_t view_batch;      /* views rendered per iteration: 0 (or views.count) all of them; B < count:
                               * B views of the pool, iteration i taking the views (i B + k) s mod count,
                               * k < B, s the stride coprime to count nearest count (3 - sqrt 5) / 2
                               * (ls_fit_view_of), so that a batch spreads over the pool and every
                               * view comes back every count / B iterations. More views at the
                               * cost of fewer: coverage without the time. The loss is the batch's. */
    uint32_t light;           /* LS_FIT_LIGHT_GIVEN or LS_FIT_LIGHT_ESTIMATE (above) */
    ls_real grad_limit;       /* UniformAdam: K > 0 scales a block's gradient (u or x, the translation)
                               * down, direction kept, when its largest element exceeds K times the
                               * block's scale of the last step (optim.h's last_scale, the largest
                               * running RMS): one outlier iteration cannot inflate the second moments
                               * and stall or throw the block for hundreds of steps; 0 (default): off.
                               * The interior shading gradient has such outliers: a sample of a
                               * triangle seen almost edge-on divides by its tiny screen area
                               * (render_backward.h). `largesteps fit` uses 3 with estimated lighting,
                               * whose shading varies more with the normal than its default SH */
    ls_real mask_pull;        /* w > 0 pulls every vertex that projects outside a target's mask in a
                               * view of the batch back into it: w / (B n) times the sum of
                               * max(0, d - 1)^2, d its distance in pixels to the nearest covered
                               * pixel (an exact distance transform of each target's alpha > 0,
                               * bilinear), added to reg_loss and to dL/dx. The silhouette
                               * gradient moves only a render's outline; a part covering pixels
                               * the target leaves empty inside it (the web between two legs grown
                               * from one sphere) recedes from its border alone. 0 (default): off */
    uint32_t albedo;          /* LS_FIT_ALBEDO_UNIFORM (default) or LS_FIT_ALBEDO_VERTEX (with
                               * LS_FIT_LIGHT_ESTIMATE; above) */
    uint32_t workers;         /* W: the caller's workers the memory is sized for (0 or 1: one;
                               * at most LS_FIT_MAX_WORKERS); results do not depend on it (above) */
    ls_parallel parallel;     /* the caller's parallel-for (run NULL: none) */
} ls_fit_config;

/* The views: view_count clip transforms (16 reals each, projection x view,
 * camera.h) and target images [4 width height] RGBA each (borrowed: they
 * must outlive the fit). */
typedef struct ls_fit_views {
    uint32_t count;
    const ls_real *mvp;
    const ls_real *const *targets;
} ls_fit_views;

/* Clock time of each stage, summed over the iterations (with a monitor
 * clock; zeros without). */
typedef struct ls_fit_timing {
    uint64_t render_ns;         /* raster, normals, shade, loss */
    uint64_t shade_backward_ns; /* interior shading gradient and normals backward */
    uint64_t silhouette_ns;     /* silhouette gradient */
    uint64_t solve_ns;          /* x = M^-1 u and the adjoint */
    uint64_t optimizer_ns;      /* the optimizer step */
} ls_fit_timing;

/* The most a job's meshes may hold (ls_fit_job_bytes). Every mesh the fit
 * holds (the initial one and each remesh result) must stay within it, and
 * the remesher works with max_vertices as its vertex capacity (it splits
 * before it collapses, so its live vertex count can briefly exceed its
 * result's). The factor's fill is a capacity of its own: nnz(L) depends on
 * the connectivity and the ordering, and no vertex count bounds it below
 * O(n^2). Measure it on a representative mesh (fit->param.f.l_nnz after
 * init or a remesh) and leave a margin: for the isotropic meshes of the
 * method it grows about as n log n (AMD: 16 per vertex on the 1.8k-vertex
 * bunny, 46 on a 10k icosphere, 72 on 164k). */
typedef struct ls_fit_capacity {
    uint32_t max_vertices;   /* > 0 */
    uint32_t max_faces;      /* > 0; the remesher's results have at most 2 max_vertices - 2 chi faces
                                (chi = the initial mesh's Euler characteristic; 2 for a sphere) */
    uint32_t max_factor_nnz; /* > 0 for large steps with the LDL^T: entries of L below its diagonal;
                                ignored (may be 0) otherwise */
} ls_fit_capacity;

typedef struct ls_fit {
    ls_fit_config config;
    ls_fit_views views;
    ls_arena block;           /* the object's memory */
    uint32_t vertex_count, face_count;
    ls_real *x;               /* [3 n] vertex positions (frame units, before translation) rendered by the
                                 last step (large steps: M^-1 u before its update) */
    uint32_t *triangles;      /* [3 f] */
    ls_real *u;               /* [3 n] differential coordinates (large steps) */
    ls_real *params;          /* [3 n + 3] what the optimizer moves: u or x, then the translation */
    ls_real *grad;            /* [3 n + 3] its gradient */
    ls_real *gx;              /* [3 n] dL/dx */
    ls_real *xr;              /* [3 n] rendered positions: x + translation */
    ls_real *normals;         /* [3 n] */
    ls_real *gnormals;        /* [3 n] */
    ls_real *image;           /* [4 W H] */
    ls_real *gimage;          /* [4 W H] */
    ls_real *pair_image;      /* [4 W H] LS_FIT_SILHOUETTE_PAIR: the blended image (else NULL) */
    ls_real *pair_gimage;     /* [4 W H] LS_FIT_SILHOUETTE_PAIR: dL/d(shaded image) (else NULL) */
    ls_csc lap;               /* uniform Laplacian (upper triangle) */
    ls_param param;           /* large steps: M and its solver */
    ls_optim optim;
    ls_edge_table edges;
    ls_vis vis;
    size_t scratch_bytes;     /* scratch reserved for one iteration */
    uint32_t iteration;       /* iterations done */
    ls_real scale;            /* S: the frame's unit, a power of two (caller units per frame unit) */
    ls_real radius;           /* R: half the initial mesh's largest bounding-box side (caller units); lr unit */
    ls_real *mvp;             /* [16 views] the views' transforms in the frame */
    ls_real loss;             /* image loss of the last iteration (before its step) */
    ls_real reg_loss;         /* regularizer value of the last iteration (baselines), plus the
                                 mask pull's (config.mask_pull) */
    ls_fit_timing timing;
    uint32_t remeshes;        /* remeshes done */
    ls_fit_capacity capacity; /* ls_fit_init_job: the job's capacity (zeros after ls_fit_init) */
    uint32_t max_edges;       /* ls_fit_init_job: the edges the capacity allows (max_vertices + max_faces - chi) */
    ls_arena job;             /* ls_fit_init_job: the reservation; its first job_fit_bytes hold the fit's
                                 block, the rest is the remesher's work (job.peak: its high-water mark) */
    size_t job_fit_bytes;
    struct ls_fit_pass *pass;      /* an iteration's views pass (private) */
    struct ls_fit_worker *workers; /* [config.workers] each worker's buffers (private) */
    struct ls_fit_slot *slots;     /* [slot_count] each view's results before they are summed (private) */
    uint32_t slot_count;
    ls_real *albedo;          /* [3 n] LS_FIT_ALBEDO_VERTEX: the albedo in use (else NULL) */
    ls_real *albedo_sums;     /* [6 n] LS_FIT_ALBEDO_VERTEX: the next estimate's num, den (working) */
    uint32_t albedo_due;      /* LS_FIT_ALBEDO_VERTEX: 1 when the next iteration estimates it (a new mesh) */
    ls_real *saved;           /* guard: the checkpoint [params | m1 | m2 | x] (else NULL) */
    uint32_t saved_valid;     /* guard: 1 when the checkpoint holds a state of this mesh */
    uint32_t saved_step;      /* guard: the optimizer's step count and the iteration saved */
    uint32_t saved_iteration;
    ls_real saved_last_scale[LS_OPTIM_MAX_BLOCKS];
    ls_real *mask_dist;       /* config.mask_pull: [views W H] each target's distance field in pixels,
                                 then a line's work (else NULL) */
    uint32_t *mask_index;     /* config.mask_pull: a line's work (else NULL) */
    /* LS_FIT_LIGHT_ESTIMATE; the last fields: a remesh's rebuild keeps them */
    ls_real sh[27];           /* the lighting in use (zeros before the first estimate) */
    uint32_t sh_valid;        /* 1 once an estimate has been made */
    ls_sh_normal sh_sums;     /* the sums of the next estimate (working) */
    ls_shade_opts lit;        /* config.shading with sh (working) */
    ls_real saved_sh[27];     /* guard: the checkpoint's lighting and its sh_valid */
    uint32_t saved_sh_valid;
} ls_fit;

/* ls_fit_config_default: the paper's large-steps settings: lambda = 19,
 * LDL^T, UniformAdam lr 1e-2, L1, boost 3, translation on, 128 x 128 with
 * S = 1, exact silhouettes, no adaptive supersampling (aa 0), p = 2, SH shading with the caller's coefficients to fill (mode
 * LS_SHADE_MASK until then), the lighting given (LS_FIT_LIGHT_GIVEN), no
 * gradient limit. O(1). NULL is ignored. */
void ls_fit_config_default(ls_fit_config *config);

/* ls_fit_bytes: exact arena bytes of ls_fit_init with these arguments (the
 * block, including the worst raster scratch of an iteration). Runs the
 * factor's symbolic analysis in `scratch` (large steps with LS_PARAM_LDLT;
 * may be NULL otherwise). Errors: as ls_fit_init, LS_ERR_NOMEM (scratch too
 * small). */
ls_status ls_fit_bytes(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                       ls_arena *scratch, size_t *bytes, ls_diag *diag);

/* ls_fit_init: a fit starting from `initial` (copied; closed or open
 * manifold triangle mesh with finite positions). Builds the Laplacian, M and
 * its factor, u = M x, the optimizer, the edge table and the visibility
 * buffer, all in the normalized frame (above). Errors: LS_ERR_INVALID (NULL,
 * a bad configuration: zero views or resolution, negative lambda, alpha
 * outside [0, 1), an unknown method, solver, loss, optimizer or silhouette
 * mode, the pair mode with S > 1 or with aa > S, aa above LS_REFINE_MAX, p outside {0, 1, 2}, a negative or
 * non-finite CG tolerance, vertex colours, LS_FIT_LIGHT_ESTIMATE without
 * LS_SHADE_SH, a negative or non-finite grad_limit), LS_ERR_MESH / LS_ERR_NONFINITE
 * (the initial mesh; also a coordinate or a view transform that overflows in
 * the frame: a mesh tiny against its distance from the origin),
 * LS_ERR_NOT_SPD (M: lambda too large for the precision, see param.h),
 * LS_ERR_NOMEM; on failure the arena
 * is unchanged and *fit is zeroed. */
ls_status ls_fit_init(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                      ls_arena *arena, ls_diag *diag);

/* ls_fit_job_bytes: the exact arena bytes of ls_fit_init_job with these
 * arguments: one reservation that holds the fit for any mesh within the
 * capacity (the largest block ls_fit_bytes can answer for such a mesh:
 * every array at max_vertices / max_faces / max_edges, the factor at
 * max_factor_nnz) and, above it, the work of ls_fit_remesh (the current
 * positions, the remesher at max_vertices with its BVH and output, and the
 * new fit's sizing). A bound for the fit, exact for the job: an arena of
 * this many free bytes runs ls_fit_init_job, every ls_fit_step and every
 * ls_fit_remesh whose result is within the capacity; one byte less fails at
 * init. Checks the initial mesh against the capacity: its counts, its edges
 * and its factor's fill (the symbolic analysis, in `scratch`, which needs
 * about ls_fit_bytes of free space; released). Cost O(F log F) plus one
 * analysis. The bound rests on two facts: every size in the fit grows with
 * the counts, and the remesher keeps the Euler characteristic chi of the
 * initial mesh (genus, components, boundary loops), so a mesh's edges are
 * V + F - chi <= max_edges. Errors: those of ls_fit_bytes, LS_ERR_INVALID
 * (NULL, a zero capacity field; max_factor_nnz = 0 with the LDL^T),
 * LS_ERR_TOO_LARGE (the initial mesh exceeds the capacity: diag->what names
 * the field, diag->index = the mesh's count, diag->value = the capacity; or
 * the bytes overflow size_t), LS_ERR_NOMEM (scratch too small). */
ls_status ls_fit_job_bytes(const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                           const ls_fit_capacity *capacity, ls_arena *scratch, size_t *bytes, ls_diag *diag);

/* ls_fit_init_job: ls_fit_init for a whole job: reserves ls_fit_job_bytes
 * at the bottom of `arena` in one allocation and builds the fit at its
 * start; ls_fit_remesh then works inside the reservation and never touches
 * `arena` again (the fit need not be the arena's last allocation, and the
 * arena may be NULL there). The validation of the initial mesh runs first
 * in the arena's free top (released). Errors: as ls_fit_job_bytes and
 * ls_fit_init (LS_ERR_NOMEM: less free space than the reservation,
 * arena->need set); on failure the arena is unchanged and *fit zeroed. */
ls_status ls_fit_init_job(ls_fit *fit, const ls_fit_config *config, const ls_fit_views *views, const ls_mesh *initial,
                          const ls_fit_capacity *capacity, ls_arena *arena, ls_diag *diag);

/* ls_fit_step: one iteration (above). monitor (optional) gives the stage
 * timing clock and may cancel (checked once per view). Memory: the block's
 * reserved scratch (the solved positions and, for the optimizer's undo, a
 * copy of the parameters and moments). Errors: LS_ERR_NONFINITE
 * (diag->index = iteration, what = the stage), LS_ERR_CANCELLED, and the
 * errors of the stages (LS_ERR_NOMEM: a view whose silhouette binning needs
 * more than the reserve); the fit is then as before the call (above). */
ls_status ls_fit_step(ls_fit *fit, const ls_monitor *monitor, ls_diag *diag);

/* ls_fit_remesh: the method's remeshing step: the current mesh (x plus the
 * translation) is remeshed to h = h_factor x its mean edge length (the
 * method: 1/2; ls_remesh_mean_edge, LS_REMESH_ITERATIONS iterations,
 * projection onto the current surface), then the fit is rebuilt on it: the
 * Laplacian, M and its factor, u = M x, the optimizer reset, the translation
 * folded into x, and the learning rate multiplied by lr_factor (the method:
 * 0.8). The iteration count and timing carry on. The fit must be the last
 * allocation at the bottom of `arena` (as ls_fit_init leaves it); the new
 * fit replaces it at the same place. Before anything is released the call
 * checks that the arena can hold the remesher's work and the new fit, so a
 * failure for lack of memory (LS_ERR_NOMEM, arena->need set) or a rejected
 * mesh leaves the fit and the arena as they were. *info (optional) receives
 * the remesher's counts. Errors: LS_ERR_INVALID (NULL, factors not in
 * (0, 2] / (0, inf), the fit not last in the arena), the remesher's, and
 * those of ls_fit_init; only an error of the final rebuild (not expected once
 * the checks passed) leaves the fit zeroed.
 * A fit from ls_fit_init_job remeshes inside its reservation (`arena` is
 * not used and may be NULL), with the capacity's max_vertices as the
 * remesher's vertex capacity. A result beyond the capacity is refused, not
 * coarsened (h is the method's; a larger h_factor is the caller's choice):
 * LS_ERR_TOO_LARGE, diag->what naming the capacity field ("remesh: more
 * vertices than capacity.max_vertices", "... faces ...", "... edges ...",
 * "... factor entries than capacity.max_factor_nnz"), diag->index = the
 * count the result needed (for vertices: max_vertices + 1, the remesher
 * stops there), diag->value = the capacity. The fit is then as before,
 * byte for byte (its struct and its part of the reservation; only the
 * solver's workspace holds the sums of the remesh's x = M^-1 u, as after
 * ls_fit_mesh), and the run can go on. */
/* With config.guard, a remeshed mesh with more self-intersecting face pairs
 * than the current one (ls_tangle, both counted) is refused: LS_ERR_MESH,
 * diag->value = its pairs, the fit as before; another h may do. */
ls_status ls_fit_remesh(ls_fit *fit, ls_arena *arena, ls_real h_factor, ls_real lr_factor, ls_remesh_info *info,
                        ls_diag *diag);

/* ls_fit_tangle: the self-intersections of the current mesh (x = M^-1 u
 * plus the translation; ls_tangle without a reference) into *out. Needs
 * config.guard (its memory is the block's reserved scratch: nothing is
 * allocated). The fit is not changed (as ls_fit_mesh). O(F log F + k).
 * Errors: LS_ERR_INVALID (NULL, no guard), the solve's. */
ls_status ls_fit_tangle(ls_fit *fit, ls_tangle_report *out, ls_diag *diag);

/* ls_fit_tangle_pairs: ls_fit_tangle's self-intersections alone
 * (ls_tangle_pairs: the pair fields, the shape statistics left 0), for a
 * check at intervals such as the program's guard. As ls_fit_tangle
 * otherwise. */
ls_status ls_fit_tangle_pairs(ls_fit *fit, ls_tangle_report *out, ls_diag *diag);

/* ls_fit_save: the checkpoint takes what ls_fit_step changes: x, the
 * parameters (u or x, and the translation), the optimizer's moments and step
 * count, the iteration count and the estimated lighting (sh, sh_valid).
 * ls_fit_rollback puts them back, so the steps after it repeat the ones
 * after the save bit for bit (the learning
 * rate, config.optim.lr of fit->optim, is the caller's to change). A remesh
 * empties the checkpoint. Needs config.guard. O(n). Errors: LS_ERR_INVALID
 * (NULL, no guard; rollback: no checkpoint since init or the last remesh). */
ls_status ls_fit_save(ls_fit *fit);
ls_status ls_fit_rollback(ls_fit *fit);

/* ls_fit_view_of: the view index rendered k-th (k < the batch) at iteration
 * `iteration` of a fit with this configuration and views.count = count
 * (config.view_batch, above); k itself when the batch is all views. O(log
 * count) (the stride's gcd). count 0 gives 0. */
uint32_t ls_fit_view_of(const ls_fit_config *config, uint32_t count, uint32_t iteration, uint32_t k);

/* ls_fit_mesh: the current mesh: x = M^{-1} u (large steps; one solve) plus
 * the translation, times S (caller units), written into positions
 * [3 vertex_count]; the triangles point into the fit. The fit is not
 * changed (with LS_PARAM_CG the forward solve's warm start is put back, so
 * the result is the same before and after any number of calls). O(n) plus
 * the solve. Errors: LS_ERR_INVALID, the solve's. */
ls_status ls_fit_mesh(ls_fit *fit, ls_real *positions, ls_mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_FIT_H */
