/* fit_job.h - what `largesteps fit` and `largesteps experiment` share: a
 * fitting problem (target, views, target images, lighting, initial mesh)
 * loaded from a mesh, a scene or the embedded bunny, and runs of the fit loop
 * on it with a remesh schedule, measured. Errors are reported on stderr;
 * functions return 1 on success, 0 on failure. */
#ifndef LS_FIT_JOB_H
#define LS_FIT_JOB_H

#include <stdio.h>
#include <largesteps.h>

#define LS_JOB_MAX_REMESH 32u
/* A fit whose gradient is exactly zero this many iterations in a row stops
 * with a message (nothing would ever move). */
#define LS_JOB_STILL_LIMIT 20u

/* How a mesh target's renders are shaded (ls_job_options.target_normals). */
#define LS_JOB_NORMALS_SMOOTH 0u
#define LS_JOB_NORMALS_FLAT 1u
#define LS_JOB_NORMALS_CREASES 2u
#define LS_JOB_NORMALS_AUTO 3u /* creases at LS_JOB_CREASE_DEG when the target is made of flat pieces */

/* --target-normals auto: a mesh target at least LS_JOB_FLAT_SHARE of whose
 * edges (of those with two faces) join faces less than LS_JOB_COPLANAR_DEG
 * apart is made of flat pieces, a CAD part, and its renders are split at its
 * creases sharper than LS_JOB_CREASE_DEG. The share is 26-79 % on 15 CAD
 * parts of CGAL's data (the fandisk 78 %, the rotor 66 %; a 16th, 16 %, has
 * almost no edge sharper than 60 degrees) and 2-21 % on 25 organic shapes
 * and scans (23 of CGAL's, the bunny 3 %, Suzanne 3 %, the triceratops 21 %). */
#define LS_JOB_FLAT_SHARE 0.25
#define LS_JOB_COPLANAR_DEG 0.5
#define LS_JOB_CREASE_DEG 60.0

typedef struct ls_job_options {
    const char *target;     /* mesh or scene path; NULL: the embedded bunny */
    uint32_t views;         /* views on a Fibonacci sphere (mesh targets) */
    uint32_t width, height; /* render size (mesh targets) */
    uint32_t target_ss;     /* supersampling of the target renders */
    uint32_t target_normals; /* mesh targets: LS_JOB_NORMALS_SMOOTH, _FLAT (each face's own normal,
                                ls_mesh_unweld), _CREASES (split where faces meet at more than
                                target_crease_deg, ls_mesh_split_creases) or _AUTO (ls_job_shown_mesh) */
    double target_crease_deg;
    uint32_t shading;       /* LS_SHADE_SH or LS_SHADE_MASK (mesh targets) */
    uint32_t level;         /* initial icosphere level */
    double init_edge;       /* > 0 (mesh targets): the initial mesh is the target remeshed to this
                               edge length (x its bounding-box diagonal) and smoothed by init_smooth
                               Taubin steps, of the target's genus; 0: the icosphere */
    uint32_t init_smooth;
    uint32_t init_auto;     /* 1 (mesh targets, init_edge 0): a target of genus > 0 or of several
                               components starts from the target remeshed coarse
                               (LS_JOB_AUTO_EDGE), as init_edge would, where the remesher takes it */
    uint32_t init_hull;     /* > 0: the initial mesh is the targets' visual hull on a grid of this
                               many cells across (ls_visual_hull), remeshed to init_edge (0:
                               LS_JOB_HULL_EDGE) and smoothed by init_smooth Taubin steps */
    uint32_t auto_res;      /* 1 (mesh targets): the size is raised for a target thinner than
                               LS_JOB_MIN_THICKNESS pixels at width x height (--res not given) */
    ls_parallel parallel;   /* the workers of the target renders and the metrics (none: run 0) */
    uint32_t workers;
} ls_job_options;

/* largesteps fit's config.grad_limit (fit.h). The interior shading
 * gradient has rare outliers: one sample of a triangle seen almost edge-on
 * divides by its tiny screen area. One such iteration gave a vertex
 * gradient 10^6 times the others; UniformAdam's one maximum took it into its
 * second moments and every later step was that much shorter: a fandisk fit
 * stood still from iteration 763 on, 1.6 % RMS instead of 0.37 %. Limited
 * to 10 x the block's scale (the usual ratio is 1.5-2) the spike passes as
 * a large step: on the fit suite the runs without a spike keep their bits and
 * the worst of three runs went 6.9 -> 2.0 % (armadillo), 4.6 -> 3.6 %
 * (fandisk), 1.24 -> 0.73 % (bunny). 3 limits more iterations: better on
 * the camel, worse on the hand (3.0 -> 3.7 %). */
#define LS_JOB_GRAD_LIMIT 10.0
/* With estimated lighting, which shades with more contrast: without a limit
 * one iteration's outlier threw the translation of a fit of the bunny's Mesa
 * dataset 3 % of the diagonal away (one run of 18); limited to 3 x the
 * block's scale, the same run ends at 1.7 %. */
#define LS_JOB_GRAD_LIMIT_ESTIMATE 3.0

/* largesteps fit's config.boost (fit.h: the silhouette gradient's multiplier)
 * when the targets' shading is given (a mesh target, or a dataset that
 * records its lighting). UniformAdam scales every vertex's step by one
 * maximum, which the boosted silhouette terms set; a smaller boost leaves
 * the exact shading gradients more of each step (docs/fit-suite.md: 6 of 14
 * suite targets within every bound, 5 at the paper's 3). */
#define LS_JOB_BOOST 1.5
/* With estimated lighting or the masks alone, the paper's 3: estimated
 * shading gradients carry the estimate's error, and 1.5 lost on the Mesa
 * datasets (docs/fitting.md). */
#define LS_JOB_BOOST_ESTIMATE 3.0
/* The boost of the finest stage, from the last scheduled remesh on, when the
 * targets' shading is given: the silhouettes are in place by then, and a
 * lower boost leaves the shading more of each step for the detail
 * (docs/fit-suite.md: the mean of the eight sphere starts' medians of six
 * runs 2.56 -> 2.45 %). With estimated lighting it stays LS_JOB_BOOST_ESTIMATE. */
#define LS_JOB_BOOST_FINAL 1.0

/* largesteps fit's config.mask_pull (fit.h). On the fit suite (median of
 * three runs, H % of the diagonal) 3e-5 against none: camel 5.19 -> 4.78,
 * elk 3.44 -> 2.54, hand 2.97 -> 2.82, armadillo 1.93 -> 2.02; 1e-4 pulled
 * harder: camel 4.72 and elk 2.11 but the hand 3.63 and the femur 3.50
 * (2.87); 1e-2 and above outweigh the images (the camel 6.7 %, 1.4 % RMS). */
#define LS_JOB_MASK_PULL 3e-5

/* A start from the target itself (its genus or components ask for it, or
 * --init-coarse): the target remeshed to LS_JOB_AUTO_EDGE x its bounding-box
 * diagonal and not smoothed, with no scheduled remesh (its detail is there
 * from the start; --remesh I,J asks for them, to LS_JOB_COARSE_REMESH_H x the
 * mean edge). A remeshed start that self-intersects is made again at
 * LS_JOB_START_RETRY x the edge, LS_JOB_START_RETRIES times at most. On the
 * six such targets of docs/fit-suite.md (medians of six runs, H % of the
 * diagonal), against 0.02 smoothed by 10 Taubin steps and remeshed before 200
 * and 500: the elephant 0.88 -> 0.55, the elk 1.74 -> 1.58, the femur 3.64 ->
 * 2.06 (its tunnel, which no view sees into, is in the finer start), the knot
 * 0.37 -> 0.47, the rotor 3.90 -> 3.98, Suzanne 2.90 -> 2.50, in less time
 * and memory (the elephant 29 -> 22 s and 78 -> 34 MiB). */
#define LS_JOB_AUTO_EDGE 0.012
#define LS_JOB_START_RETRY 1.1
#define LS_JOB_START_RETRIES 2u
#define LS_JOB_COARSE_REMESH_H 0.62

/* --lr's default: from the icosphere, the visual hull and a smoothed start. */
#define LS_JOB_LR 0.01

/* The learning rate of a start from the target itself, not smoothed (--lr's
 * default there). Such a start is the target's own surface, near the answer, and
 * Adam's first step is full-sized whatever the gradient: at 0.01 the femur's
 * first step raised the loss 6-fold (0.0026 -> 0.015) and the fit never came
 * back to its start's H 1.49 % (ended at 2.1 %). On the six targets of
 * docs/fit-suite.md that start so (medians of three runs, H % of the
 * diagonal), 0.01 / 0.005 / 0.003 / 0.002 / 0.001: mean 1.92 / 1.86 / 1.74 /
 * 1.76 / 1.66, the femur 2.04 / 2.12 / 1.93 / 1.90 / 1.95; started at 0.03 of
 * the diagonal (one run each, four targets), 0.01 / 0.003 / 0.001: mean 1.92
 * / 1.73 / 2.01 not smoothed (0.001 moves too little to bring back what a
 * coarser start lacks), 2.25 / 2.58 (0.003) smoothed by 10 Taubin steps (a
 * smoothed start has lost detail the fit must bring back). */
#define LS_JOB_COARSE_LR 0.003

/* The visual hull start's edge (x its bounding-box diagonal): at 0.03 a
 * camel's legs, remeshed, cross each other; at 0.02 they do not. */
#define LS_JOB_HULL_EDGE 0.02

/* The views and lighting of a mesh target, which `largesteps render` uses
 * too (a dataset it writes is the problem the mesh-target fit solves): a
 * horizontal field of view of LS_JOB_FOV_DEG degrees, the bounding sphere
 * filling the image with the margin LS_JOB_MARGIN (ls_camera_frame), and SH
 * lighting: a soft sky from above plus a key light from the front right. */
#define LS_JOB_FOV_DEG 45.0

/* How thick the object is in the targets: the median over the views of the
 * radius of the largest disc inside each mask (ls_mask_inscribed_radius), in
 * pixels. Below LS_JOB_MIN_THICKNESS the silhouettes leave the fit too little
 * to grow into: a blade 3.0 pixels thick at 128 x 128 fitted to 43 % of its
 * diagonal, at 256 x 256 (6.5 pixels) to 1.9-2.4 %; the 24 other targets of
 * the fit suite and its CAD parts are 12-42 pixels thick at 128 x 128. A mesh
 * target that thin is rendered, and fitted, at the size that makes it
 * LS_JOB_MIN_THICKNESS thick, rounded up to a multiple of
 * LS_JOB_AUTO_RES_STEP, at most LS_JOB_AUTO_RES_MAX; images that thin are
 * warned of. */
#define LS_JOB_MIN_THICKNESS 6.0
#define LS_JOB_AUTO_RES_STEP 64u
#define LS_JOB_AUTO_RES_MAX 512u
#define LS_JOB_MARGIN 1.1
extern const ls_real ls_job_default_sh[27];

typedef struct ls_job_problem {
    uint32_t views, width, height;
    ls_real *mvps;           /* 16 per view */
    ls_real **targets;       /* [4 W H] per view */
    ls_shade_opts shading;   /* lighting and background of targets and fit */
    ls_real sh[27];
    int have_mesh;           /* the target is a mesh (metrics need it) */
    ls_mesh target;
    ls_camera_framing framing;
    ls_mesh initial;         /* the initial mesh */
    const char *name;        /* for reports */
    int32_t target_genus;    /* mesh targets: the genus (-1: not an oriented 2-manifold) */
    uint32_t target_components;
    int auto_coarse;         /* 1: the coarse start was chosen for the target's genus or components;
                                -1: it was, but the remesher failed on the target (the icosphere) */
    const char *coarse_failure; /* auto_coarse -1: the remesher's reason (static text) */
    int from_target;         /* 1: the initial mesh is the target remeshed (--init-coarse or automatic) */
    int target_creased;      /* 1: --target-normals auto found the target made of flat pieces */
    int target_flat_start;   /* 1: --target-normals auto rendered the target flat, the fit starting from it */
    double target_flat_share; /* mesh targets: the share of its two-face edges between coplanar faces */
    double thickness;        /* the targets' median inscribed radius in pixels (LS_JOB_MIN_THICKNESS) */
    uint32_t res_asked;      /* the size asked for when a thin mesh target raised it (else 0) */
    double thickness_asked;  /* the thickness at that size */
    double start_edge_asked; /* a remeshed start's edge asked for, x the diagonal (--init-coarse, automatic, hull) */
    double start_edge;       /* the one it has (another when the first folded) */
    uint32_t start_tries;    /* the remeshes it took: 1, or more when one self-intersected */
    uint32_t start_pairs;    /* its self-intersecting face pairs (0 unless every edge tried had them) */
    uint32_t light;          /* LS_FIT_LIGHT_ESTIMATE: a dataset without its lighting, estimated by the
                                fit (sh then zeros until the fit's estimate is copied in) */
    ls_parallel parallel;    /* the renders' and the metrics' workers (ls_job_options') */
    uint32_t workers;
} ls_job_problem;

/* The problem's worker count for the library's parallel calls (at least 1). */
uint32_t ls_job_workers(const ls_job_problem *p);

typedef struct ls_job_run {
    uint32_t iterations;     /* done */
    ls_real *loss;           /* per iteration (capacity iterations + 1) */
    double *ms;              /* elapsed at the end of each iteration */
    ls_mesh result;          /* final mesh (positions in the arena) */
    ls_fit_timing timing;
    uint32_t remeshes;
    double setup_ms, total_ms;
    size_t fit_bytes;        /* the fit's block at the start */
    size_t fit_bytes_end;    /* the fit's block at the end */
    size_t job_bytes;        /* with a capacity: ls_fit_job_bytes, the fit's whole arena (else 0) */
    size_t peak_used;        /* with a capacity: the most the fit held at once (its block, plus the
                                remesher's work during a remesh) */
    ls_fit_capacity capacity;/* with a capacity: the one used */
    uint32_t rollbacks;      /* guard: roll-backs to the last check */
    uint32_t remeshes_refused; /* guard: remeshes not done (their results self-intersected more than the mesh
                                  at both edge lengths tried, or exceeded the job's capacity) */
    uint32_t remesh_live_max;/* the most live vertices of the remesher, over the remeshes */
    uint32_t factor_nnz;     /* nnz(L) of the final fit's LDL^T factor (0 without) */
    uint32_t tracked;        /* distance samples taken (track_every > 0) */
    uint32_t *track_it;      /* iteration of each sample (the mesh before it) */
    double *track_ms;        /* elapsed fit time at that point */
    ls_real *track_h_rel;    /* dense symmetric Hausdorff / target diagonal */
    ls_real *track_rms_rel;  /* dense RMS / target diagonal */
    double track_total_ms;   /* time spent measuring (excluded from ms and total_ms) */
    ls_real sh[27];          /* the fit's estimated lighting (LS_FIT_LIGHT_ESTIMATE; else zeros) */
    ls_real *albedo;         /* [3 result.vertex_count] LS_FIT_ALBEDO_VERTEX: the estimated albedo (mean 1 per
                                channel, the scale in sh); else NULL */
} ls_job_run;

/* --target-normals / --normals: smooth, flat, auto or an angle in degrees in
 * (0, 180) into *normals (LS_JOB_NORMALS_*) and *crease_deg; 0 for anything
 * else (the caller says what is allowed). */
int ls_job_parse_normals(const char *v, uint32_t *normals, double *crease_deg);

/* The mesh a target's renders show for target_normals (LS_JOB_NORMALS_*):
 * the mesh itself, unwelded, or split at its creases (from the arena); for
 * _AUTO, *flat_share is the share of its two-face edges between coplanar
 * faces and *creased whether it was split for it. */
ls_status ls_job_shown_mesh(const ls_mesh *mesh, uint32_t normals, double crease_deg, ls_arena *arena, ls_mesh *shown,
                            int *creased, double *flat_share, ls_diag *d);

/* Loads the problem into the arena (everything stays allocated). */
int ls_job_load(ls_job_problem *p, const ls_job_options *o, ls_arena *arena);

/* Renders mesh m from every view with S = ss into rgba[v]. */
ls_status ls_job_render(const ls_job_problem *p, const ls_mesh *m, uint32_t ss, ls_real **rgba, ls_arena *arena,
                        ls_diag *d);


/* The run's schedule: iterations (stopping early once time_budget_ms > 0 is
 * exceeded) and the remeshes: before each listed iteration the mesh is
 * remeshed to remesh_h x its mean edge and the learning rate multiplied by
 * remesh_lr (ls_fit_remesh). */
typedef struct ls_job_schedule {
    uint32_t iterations;
    double time_budget_ms;
    uint32_t remesh_count, remesh_at[LS_JOB_MAX_REMESH];
    ls_real remesh_h, remesh_lr;
    uint32_t guard_every;    /* > 0: every guard_every iterations the mesh is checked for
                                self-intersections (ls_fit_tangle); more than at the last check
                                roll the fit back to it (ls_fit_rollback), remesh it to
                                guard_remesh x its mean edge (when > 0) and multiply the
                                learning rate by guard_lr */
    ls_real guard_lr;
    ls_real guard_remesh;    /* (roll-backs to the start, again and again, also shorten the interval:
                                LS_JOB_GUARD_SPIRAL) */
    ls_real settle;          /* the last settle x iterations (rounded down) run at settle_lr x the
                                learning rate: the steps' jitter dies down before the result is
                                taken (0: off) */
    ls_real settle_lr;
    ls_real boost_final;     /* >= 0: config.boost from the last scheduled remesh on (< 0, the
                                default: unchanged) */
} ls_job_schedule;

/* The guard's interval while the fit cannot leave its start: from the
 * LS_JOB_GUARD_SPIRAL-th roll-back in a row to the start on, each one halves
 * it, down to LS_JOB_GUARD_MIN iterations; LS_JOB_GUARD_CLEAN clean checks in
 * a row double it back. A sphere collapsing onto thin parts folds within a
 * few steps, and with a check every 25 iterations the cactus went back to
 * its start 30 times. A fit that does not keep returning to its start keeps
 * guard_every (halving at every roll-back to the start made the blade's and
 * a beam's first roll-backs finer too, and lost them: 2.1 -> 30 % and 0.7 ->
 * 7.1 %). */
#define LS_JOB_GUARD_MIN 5u
#define LS_JOB_GUARD_CLEAN 4u
#define LS_JOB_GUARD_SPIRAL 3u

/* The program's default schedule: 800 iterations, remeshes before 200 and
 * 500 at the method's h = 1/2 the mean edge and lr x 0.8. */
void ls_job_schedule_default(ls_job_schedule *s);

/* The capacity of a job on schedule s from p->initial (fit.h), each field
 * of `given` that is not 0 kept: vertices (V + 64) (1 / remesh_h^2)^remeshes
 * x 2 (a remesh to h x the mean edge multiplies the vertices by about
 * 1 / h^2: 3.5x measured on the bunny at h = 1/2; the remesher splits before
 * it collapses), faces the most a
 * mesh of that many vertices with the initial mesh's Euler characteristic
 * has, and 6 log2(N) factor entries per vertex (AMD's fill per vertex: 16
 * on the 1.8k-vertex bunny, 46 on a 10k icosphere, 93 at 655k). Validates
 * the initial mesh in arena's scratch. */
int ls_job_capacity(const ls_job_problem *p, const ls_job_schedule *s, const ls_fit_capacity *given, ls_arena *arena,
                    ls_fit_capacity *cap);

/* Runs the fit from p->initial on schedule s;
 * progress: 0 none, 1 lines, 2 a line updated in place. With track_every > 0
 * and a target mesh, the dense distances to the target are measured every
 * track_every iterations and at the end (their time is not counted in the
 * run's times). capacity NULL: the fit in `arena` as ls_fit_init sizes it;
 * else (fields 0: ls_job_capacity's) the whole job in one block of
 * ls_fit_job_bytes from `arena` (ls_fit_init_job). The run's arrays and
 * result are left in the arena (roll back with a mark to reuse it). */
int ls_job_fit(const ls_job_problem *p, const ls_fit_config *cfg, const ls_job_schedule *s, int progress,
               uint32_t track_every, const ls_fit_capacity *capacity, ls_arena *arena, ls_job_run *r);

/* Distances (both ways, vertex and dense samples) and tangling of a result
 * against the problem's target mesh. */
int ls_job_metrics(const ls_job_problem *p, const ls_mesh *result, ls_arena *arena, ls_distance_report *dist,
                   ls_tangle_report *tangle);

/* Parses a remesh schedule: "none", or increasing iterations "I,J,..."
 * (at most LS_JOB_MAX_REMESH, each below 10^6) into at[0..*count). 1 on
 * success; 0 (and *count unspecified) when malformed. */
int ls_job_parse_remesh(const char *text, uint32_t *at, uint32_t *count);

/* mu_1, the smallest nonzero eigenvalue of the mesh's uniform Laplacian (0
 * when it cannot be computed: fewer than 4 vertices, no memory). With the
 * large-steps weight lambda (alpha form: alpha / (1 - alpha)), M^-1 moves
 * the mesh's mean (its translation) 1 + lambda mu_1 times as far per unit
 * step as its smoothest shape mode. Inverse iteration on I + 1000 L with the
 * constant taken out, at most 100 solves (in `arena`, released). */
double ls_job_smallest_mode(const ls_mesh *m, ls_arena *arena);

/* largesteps fit warns when 1 + lambda mu_1 of its start exceeds this: from
 * the 642-vertex icosphere, alpha 0.98 (4.3) and 0.99 (7.7) failed on the
 * bunny and the dino at every learning rate tried (0.002 to 0.01) and 0.999
 * (68) left the views, where 0.95 (2.3) and 0.9 (1.6) fit
 * (docs/experiments.md). */
#define LS_JOB_MEAN_RATIO_WARN 4

/* Wall clock in milliseconds. */
double ls_job_now_ms(void);

/* Prints "largesteps: WHAT: status: detail" to stderr; returns 0. */
int ls_job_fail(const char *what, ls_status st, const ls_diag *d);

#endif /* LS_FIT_JOB_H */
