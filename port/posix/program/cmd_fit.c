/* cmd_fit.c - `largesteps fit [TARGET] [options] -o DIR`: the reconstruction.
 *
 * The target is a mesh (OBJ, PLY, OFF) rendered by our renderer from N views
 * on a Fibonacci sphere framing it, with S = 4 supersampling (so the fit does
 * not see exactly its own forward model) and SH lighting; without TARGET the
 * bunny compiled into the program is used. The initial mesh is an icosphere
 * fitted to the target's bounding sphere. Every file in DIR is written whole
 * (a temporary name, then renamed): result.obj, log.csv (iteration, loss,
 * time, and the dense distances to the target every --track iterations; a
 * last row for the final mesh with its image loss), convergence.svg (loss
 * and Hausdorff distance against iteration and time: log y axes with a tick
 * at each power of ten, the scheduled remeshes as dashed lines), contact.png (target,
 * initial and final render of every view, one row each, each tile labelled
 * with its row and view, over a grey checkerboard so that masks show).
 *
 * A scene file (.txt: the text format of scene.h; .xml: the Mitsuba subset;
 * .json: a camera dataset, transforms.json, whose RGBA images are the target)
 * gives the cameras, the resolution, the lighting (SH coefficients, or an
 * environment map in PFM projected to SH and scaled), the background and the
 * target: a mesh rendered as above, or one image per camera (PNG or PFM, the
 * scene's resolution). Paths in a scene are relative to its directory. The
 * initial mesh is the scene's (a file, or an icosphere of the given level on
 * the target mesh's bounding sphere; with image targets, the unit sphere).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <unistd.h>
#include <errno.h>
#include "ls_posix.h"
#include "commands.h"
#include "fit_job.h"
#include "report.h"
#include "args.h"


typedef struct fit_args {
    const char *target, *out;
    uint32_t views, res, level, target_ss, target_normals, quiet, track, init_smooth, init_sphere, init_hull, threads;
    uint32_t remesh_given;      /* --remesh was given (else the default for the start) */
    uint32_t res_given;         /* --res was given (else a thin mesh target raises the size) */
    uint32_t grad_limit_given;  /* --grad-limit was given (else the default for the lighting) */
    uint32_t boost_given;       /* --boost was given (else the default for the shading) */
    uint32_t target_normals_given; /* --target-normals was given (a mesh target's option) */
    uint32_t remesh_h_given;    /* --remesh-h was given (else the default for the start) */
    uint32_t perturb;           /* --perturb K: the learning rate x (1 + K 1e-6) */
    ls_real lr;               /* --lr: 0 when not given (the default for the start) */
    ls_real init_edge;        /* --init-coarse: 0 for the icosphere */
    double target_crease_deg; /* --target-normals DEGREES */
    ls_job_schedule sched;
    ls_fit_capacity cap;      /* --max-*: 0 means ls_job_capacity's default */
    ls_fit_config cfg;
} fit_args;

static int usage(FILE *f)
{
    fprintf(f,
            "usage: largesteps fit [TARGET.obj|.ply|.off] [options] -o DIR\n"
            "  without TARGET: the bunny compiled into the program\n"
            "  --views N          views on a Fibonacci sphere (1..1024; default 32)\n"
            "  --batch B          views rendered per iteration, spread over the --views pool (0 = all;\n"
            "                     default 16; all when the pool has no more)\n"
            "  --res R            render size R x R (8..4096; default 128, and for a mesh target thinner\n"
            "                     than 6 pixels there the size that makes it 6 thick, at most 512)\n"
            "  --iters N          iterations (0..1000000; default 800)\n"
            "  --alpha A          M = (1 - A) I + A Laplacian, 0 <= A < 1 (default 0.95, the paper's form)\n"
            "  --lambda L         M = I + L Laplacian instead (lambda = alpha / (1 - alpha); 0 <= L <= 1e12;\n"
            "                     not with --alpha)\n"
            "  --lr X             learning rate, in units of the initial mesh's radius (the target's\n"
            "                     bounding-sphere radius for the default icosphere; default 0.01, and\n"
            "                     0.003 after a start from the target itself not smoothed)\n"
            "  --method M         large (default) | naive | laplacian | bilaplacian\n"
            "  --reg W            regularizer weight of the laplacian/bilaplacian baselines (0..1e12; default 1)\n"
            "  --optimizer O      uniform (default for large) | adam (default otherwise) | sgd\n"
            "  --solver S         ldlt (default) | cg\n"
            "  --cg-tol T         relative residual tolerance of cg (0 < T <= 1; default 1e-6)\n"
            "  --power P          2 (default: the optimizer on u = M x) | 1 (the optimizer on x, gradient M^-1 g)\n"
            "  --silhouette S     exact (default) | pair (nvdiffrast-style, S = 1) | none\n"
            "  --ss S             supersampling of the fit's renders: 1 (default), 2 or 4\n"
            "  --aa-adaptive A    A x A sub-samples in silhouette pixels (forward and shading gradient;\n"
            "                     2..32, off when A <= S; default 0 = off)\n"
            "  --loss L           l1 (default) | l2\n");
    fprintf(f,
            "  --boost B          silhouette gradient multiplier (0..1e6; default 1.5, 3 with\n"
            "                     estimated lighting or --shading mask)\n"
            "  --boost-final B    the multiplier from the last scheduled remesh on, the finest stage\n"
            "                     (0..1e6; default 1 with the default --boost where the shading is\n"
            "                     given, else --boost's value)\n"
            "  --mask-pull W      pull vertices that project outside a target's mask back into it,\n"
            "                     along the mask's distance field, weight W (0..1e12; default 3e-5;\n"
            "                     0: off, the paper's)\n"
            "  --grad-limit K     scale a gradient block down to K x the optimizer's scale of the last\n"
            "                     step when an element exceeds it (0..1e6; default 10, 3 with estimated\n"
            "                     lighting; 0: off, the paper's): one sample of a sliver seen edge-on\n"
            "                     can otherwise freeze the fit\n"
            "  --settle F         the last F of the iterations run at a lower learning rate (0..1;\n"
            "                     default 0.125; 0: off)\n"
            "  --settle-lr X      that rate's factor (0 < X <= 1; default 0.5)\n"
            "  --guard N          every N iterations (default 25) check the mesh for self-intersections;\n"
            "                     new ones roll the fit back to the last check, remesh it and lower lr;\n"
            "                     from the 3rd roll-back in a row to the start, each halves N (down to\n"
            "                     5) until 4 clean checks\n"
            "  --guard-lr F       the learning rate's factor at a roll-back (0 < F <= 1; default 0.7)\n"
            "  --guard-remesh F   a roll-back remeshes to F x the mean edge (0..1000; default 1; 0: no remesh)\n"
            "  --no-guard         no checks (the paper's loop)\n"
            "  --perturb K        learning rate x (1 + K 1e-6): a robustness check, is the result stable\n"
            "                     under a change in the 6th digit? (default 0)\n"
            "  --shading S        sh (default; a camera dataset that does not record its lighting has it\n"
            "                     estimated with the geometry) | mask (the alpha masks alone)\n"
            "  --albedo A         with estimated lighting: uniform (default: one colour) | vertex (an RGB\n"
            "                     albedo per vertex, estimated with the lighting: objects whose colour varies)\n"
            "  --remesh I,J,...   remesh before these iterations (h = half the mean edge, lr x 0.8;\n"
            "                     default 200,500, none after a start from the target itself; 'none'\n"
            "                     for no remeshing)\n"
            "  --remesh-h F       remesh to F x the mean edge (0 < F <= 1; default 0.5, and 0.62 after a\n"
            "                     start from the target itself: --init-coarse and the automatic start)\n"
            );
    fprintf(f,
            "  --remesh-lr F      learning rate x F at each remesh (0 < F <= 1; default 0.8)\n"
            "  --mean M           keep (default: the paper's) | project: the mean of dL/du taken out, the\n"
            "                     translation alone moves the mesh as a whole\n"
            "  --max-vertices N   the job's capacity (memory is reserved once for it, ls_fit_job_bytes):\n"
            "                     vertices of any mesh and of the remesher (default (V0 + 64) 4^remeshes x 2)\n"
            "  --max-faces N      faces of any mesh (default: the most N vertices allow)\n"
            "  --max-factor-nnz N entries of the LDL^T factor (default 6 log2(N) per vertex); a remesh\n"
            "                     beyond the capacity stops the run with the field to raise\n"
            "  --level K          subdivision level of the initial icosphere (default 3)\n"
            "  --init-coarse E    initial mesh: the target remeshed to edge E x its bounding-box diagonal\n"
            "                     (keeps the target's genus; e.g. 0.05); default: the icosphere, but a\n"
            "                     target of genus > 0 or of several components starts this way by itself\n"
            "                     (--init-coarse 0.012)\n"
            "  --init-smooth N    Taubin smoothing steps of the start from --init-coarse or --init-hull\n"
            "                     (default 0)\n"
            "  --init-sphere      start from the icosphere whatever the target's genus and components\n"
            "  --init-hull N      initial mesh: the visual hull of the target images on a grid of N cells\n"
            "                     across (2..1024; e.g. 128), remeshed to 0.02 of its diagonal (--init-coarse\n"
            "                     E sets it)\n"
            "  --target-ss S      supersampling of the target renders: 1, 2 or 4 (default 4)\n"
            "  --target-normals N how a mesh target's renders are shaded: auto (default: vertex normals\n"
            "                     averaged over their faces, but a target made of flat pieces, a CAD part,\n"
            "                     split at its creases sharper than 60 degrees, and flat when the fit starts\n"
            "                     from the target itself not smoothed) | smooth (never split) |\n"
            "                     flat (each face its own normal) | DEGREES (0..180: split at the edges\n"
            "                     whose faces meet at more than this angle)\n"
            "  --track N          measure the distances to the target every N iterations for log.csv and\n"
            "                     convergence.svg (default 25; 0: only at the end; not counted in the times)\n"
            "  --no-translation   do not optimize a global translation\n"
            "  --quiet            no progress line\n"
            "  --threads N        threads that share each iteration's views (1..1024; default: the\n"
            "                     processors online); every count gives the same bits\n"
            "  -o DIR             output directory (created if missing)\n"
            LS_ARGS_GLOBAL_HELP
            "exit status: 0 done, 1 failed, 2 bad arguments, 3 done but the result self-intersects (its\n"
            "  files are written, metrics.json has \"self_intersecting\": true)\n");
    return f == stderr ? 2 : 0;
}

/* The option being parsed, for the messages of ls_arg_u32 / ls_arg_real. */
static const char *cur_opt = "";

static int parse_u32(const char *s, uint32_t lo, uint32_t hi, uint32_t *out)
{
    return ls_arg_u32("fit", cur_opt, s, lo, hi, out);
}

/* A finite number in the range; open_ends: LS_ARG_LO_OPEN, LS_ARG_HI_OPEN. */
static int parse_range(const char *s, double lo, double hi, int open_ends, ls_real *out)
{
    double v;
    if (!ls_arg_real("fit", cur_opt, s, lo, hi, open_ends, &v)) return 0;
    *out = (ls_real)v;
    return 1;
}

static int ss3(const char *o)
{
    fprintf(stderr, "largesteps fit: %s: '3' is not 1, 2 or 4\n", o);
    return 0;
}

/* Options whose parser printed its own message (a number and its range). */
static int ranged(const char *o)
{
    static const char *const names[] = {"--views", "--batch", "--res", "--iters", "--level", "--init-coarse", "--init-smooth", "--init-hull",
                                        "--target-ss", "--ss", "--aa-adaptive", "--track", "--max-vertices",
                                        "--max-faces", "--max-factor-nnz", "--power", "--cg-tol", "--remesh-h",
                                        "--remesh-lr", "--lambda", "--alpha", "--lr", "--guard-lr", "--guard-remesh",
                                        "--guard", "--settle", "--settle-lr", "--perturb", "--reg", "--boost", "--boost-final",
                                        "--grad-limit", "--mask-pull", "--threads"};
    size_t k;
    for (k = 0; k < sizeof names / sizeof names[0]; k++)
        if (strcmp(o, names[k]) == 0) return 1;
    return 0;
}

static int parse_args(int argc, char **argv, fit_args *a)
{
    int i, optimizer_set = 0;
    uint32_t optimizer = LS_OPTIM_UNIFORM_ADAM;
    int lambda_set = 0, alpha_set = 0;
    memset(a, 0, sizeof *a);
    a->views = 32;
    a->res = 128;
    ls_job_schedule_default(&a->sched);
    a->level = 3;
    a->target_ss = 4;
    a->target_normals = LS_JOB_NORMALS_AUTO;
    a->track = 25;
    ls_fit_config_default(&a->cfg);
    a->cfg.form = LS_SYSTEM_ALPHA;
    a->cfg.weight = (ls_real)0.95;
    a->cfg.reg_weight = 1;
    a->cfg.shading.mode = LS_SHADE_SH;
    a->cfg.view_batch = 16; /* 16 of the 32 views each iteration: twice the coverage for the same time */
    a->cfg.mask_pull = (ls_real)LS_JOB_MASK_PULL;
    for (i = 1; i < argc; i++) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0) return usage(stdout), -1;
        if (strcmp(o, "--no-translation") == 0) {
            a->cfg.use_translation = 0;
            continue;
        }
        if (strcmp(o, "--no-guard") == 0) {
            a->sched.guard_every = 0;
            continue;
        }
        if (strcmp(o, "--init-sphere") == 0) {
            a->init_sphere = 1;
            continue;
        }
        if (strcmp(o, "--quiet") == 0) {
            a->quiet = 1;
            continue;
        }
        if (o[0] != '-') {
            if (a->target != NULL) return fprintf(stderr, "largesteps fit: more than one target\n"), 0;
            a->target = o;
            continue;
        }
        if (v == NULL) return fprintf(stderr, "largesteps fit: %s needs a value\n", o), 0;
        i++;
        cur_opt = o;
        if (strcmp(o, "-o") == 0) a->out = v;
        else if (strcmp(o, "--views") == 0) ok = parse_u32(v, 1, 1024, &a->views);
        else if (strcmp(o, "--threads") == 0) ok = parse_u32(v, 1, LS_FIT_MAX_WORKERS, &a->threads);
        else if (strcmp(o, "--batch") == 0) ok = parse_u32(v, 0, 1024, &a->cfg.view_batch);
        else if (strcmp(o, "--res") == 0) ok = parse_u32(v, 8, 4096, &a->res), a->res_given = 1;
        else if (strcmp(o, "--iters") == 0) ok = parse_u32(v, 0, 1000000, &a->sched.iterations);
        else if (strcmp(o, "--level") == 0) ok = parse_u32(v, 0, 7, &a->level);
        else if (strcmp(o, "--init-coarse") == 0) ok = parse_range(v, 0, 1, LS_ARG_LO_OPEN, &a->init_edge);
        else if (strcmp(o, "--init-smooth") == 0) ok = parse_u32(v, 0, 10000, &a->init_smooth);
        else if (strcmp(o, "--init-hull") == 0) ok = parse_u32(v, 2, 1024, &a->init_hull);
        else if (strcmp(o, "--target-ss") == 0) ok = parse_u32(v, 1, 4, &a->target_ss) && (a->target_ss != 3 || ss3(o));
        else if (strcmp(o, "--ss") == 0) ok = parse_u32(v, 1, 4, &a->cfg.ss) && (a->cfg.ss != 3 || ss3(o));
        else if (strcmp(o, "--aa-adaptive") == 0) ok = parse_u32(v, 0, LS_REFINE_MAX, &a->cfg.aa);
        else if (strcmp(o, "--track") == 0) ok = parse_u32(v, 0, 1000000, &a->track);
        else if (strcmp(o, "--max-vertices") == 0) ok = parse_u32(v, 1, UINT32_MAX, &a->cap.max_vertices);
        else if (strcmp(o, "--max-faces") == 0) ok = parse_u32(v, 1, UINT32_MAX, &a->cap.max_faces);
        else if (strcmp(o, "--max-factor-nnz") == 0) ok = parse_u32(v, 1, UINT32_MAX, &a->cap.max_factor_nnz);
        else if (strcmp(o, "--power") == 0) ok = parse_u32(v, 1, 2, &a->cfg.power);
        else if (strcmp(o, "--cg-tol") == 0) ok = parse_range(v, 0, 1, LS_ARG_LO_OPEN, &a->cfg.cg_tol);
        else if (strcmp(o, "--silhouette") == 0) {
            a->cfg.silhouette = strcmp(v, "exact") == 0  ? LS_FIT_SILHOUETTE_EXACT
                              : strcmp(v, "pair") == 0 ? LS_FIT_SILHOUETTE_PAIR
                              : strcmp(v, "none") == 0 ? LS_FIT_SILHOUETTE_NONE : 99u;
            ok = a->cfg.silhouette != 99u;
        }
        else if (strcmp(o, "--remesh") == 0)
            ok = ls_job_parse_remesh(v, a->sched.remesh_at, &a->sched.remesh_count), a->remesh_given = 1;
        else if (strcmp(o, "--remesh-h") == 0)
            ok = parse_range(v, 0, 1, LS_ARG_LO_OPEN, &a->sched.remesh_h), a->remesh_h_given = 1;
        else if (strcmp(o, "--remesh-lr") == 0) ok = parse_range(v, 0, 1, LS_ARG_LO_OPEN, &a->sched.remesh_lr);
        else if (strcmp(o, "--mean") == 0) {
            a->cfg.mean_mode = strcmp(v, "keep") == 0 ? LS_FIT_MEAN_KEEP : strcmp(v, "project") == 0 ? LS_FIT_MEAN_PROJECT : 99u;
            ok = a->cfg.mean_mode != 99u;
        }
        else if (strcmp(o, "--lambda") == 0) ok = parse_range(v, 0, 1e12, LS_ARG_CLOSED, &a->cfg.weight), a->cfg.form = LS_SYSTEM_LAMBDA, lambda_set = 1;
        else if (strcmp(o, "--alpha") == 0) ok = parse_range(v, 0, 1, LS_ARG_HI_OPEN, &a->cfg.weight), a->cfg.form = LS_SYSTEM_ALPHA, alpha_set = 1;
        else if (strcmp(o, "--lr") == 0) ok = parse_range(v, 0, 1e6, LS_ARG_LO_OPEN, &a->lr);
        else if (strcmp(o, "--settle") == 0) ok = parse_range(v, 0, 1, LS_ARG_CLOSED, &a->sched.settle);
        else if (strcmp(o, "--settle-lr") == 0) ok = parse_range(v, 0, 1, LS_ARG_LO_OPEN, &a->sched.settle_lr);
        else if (strcmp(o, "--guard-lr") == 0) ok = parse_range(v, 0, 1, LS_ARG_LO_OPEN, &a->sched.guard_lr);
        else if (strcmp(o, "--guard-remesh") == 0) ok = parse_range(v, 0, 1000, LS_ARG_CLOSED, &a->sched.guard_remesh);
        else if (strcmp(o, "--guard") == 0) ok = parse_u32(v, 0, 1000000, &a->sched.guard_every);
        else if (strcmp(o, "--perturb") == 0) ok = parse_u32(v, 0, 1000, &a->perturb);
        else if (strcmp(o, "--reg") == 0) ok = parse_range(v, 0, 1e12, LS_ARG_CLOSED, &a->cfg.reg_weight);
        else if (strcmp(o, "--boost") == 0) ok = parse_range(v, 0, 1e6, LS_ARG_CLOSED, &a->cfg.boost), a->boost_given = 1;
        else if (strcmp(o, "--boost-final") == 0)
            ok = parse_range(v, 0, 1e6, LS_ARG_CLOSED, &a->sched.boost_final);
        else if (strcmp(o, "--mask-pull") == 0) ok = parse_range(v, 0, 1e12, LS_ARG_CLOSED, &a->cfg.mask_pull);
        else if (strcmp(o, "--grad-limit") == 0)
            ok = parse_range(v, 0, 1e6, LS_ARG_CLOSED, &a->cfg.grad_limit), a->grad_limit_given = 1;
        else if (strcmp(o, "--method") == 0) {
            a->cfg.method = strcmp(v, "large") == 0 ? LS_FIT_LARGE_STEPS : strcmp(v, "naive") == 0 ? LS_FIT_NAIVE
                          : strcmp(v, "laplacian") == 0 ? LS_FIT_LAPLACIAN : strcmp(v, "bilaplacian") == 0 ? LS_FIT_BILAPLACIAN : 99u;
            ok = a->cfg.method != 99u;
        } else if (strcmp(o, "--optimizer") == 0) {
            optimizer = strcmp(v, "uniform") == 0 ? LS_OPTIM_UNIFORM_ADAM : strcmp(v, "adam") == 0 ? LS_OPTIM_ADAM
                      : strcmp(v, "sgd") == 0 ? LS_OPTIM_SGD : 99u;
            ok = optimizer != 99u;
            optimizer_set = 1;
        } else if (strcmp(o, "--solver") == 0) {
            a->cfg.solver = strcmp(v, "ldlt") == 0 ? LS_PARAM_LDLT : strcmp(v, "cg") == 0 ? LS_PARAM_CG : 99u;
            ok = a->cfg.solver != 99u;
        } else if (strcmp(o, "--loss") == 0) {
            a->cfg.loss = strcmp(v, "l1") == 0 ? LS_LOSS_L1 : strcmp(v, "l2") == 0 ? LS_LOSS_L2 : 99u;
            ok = a->cfg.loss != 99u;
        } else if (strcmp(o, "--albedo") == 0) {
            a->cfg.albedo = strcmp(v, "uniform") == 0 ? LS_FIT_ALBEDO_UNIFORM
                          : strcmp(v, "vertex") == 0  ? LS_FIT_ALBEDO_VERTEX
                                                      : 99u;
            ok = a->cfg.albedo != 99u;
        } else if (strcmp(o, "--shading") == 0) {
            a->cfg.shading.mode = strcmp(v, "sh") == 0 ? LS_SHADE_SH : strcmp(v, "mask") == 0 ? LS_SHADE_MASK : 99u;
            ok = a->cfg.shading.mode != 99u;
        } else if (strcmp(o, "--target-normals") == 0) {
            a->target_normals_given = 1;
            if (!ls_job_parse_normals(v, &a->target_normals, &a->target_crease_deg))
                return fprintf(stderr, "largesteps fit: --target-normals: '%s' is not auto, smooth, flat or an angle in "
                                       "degrees between 0 and 180\n", v), 0;
        } else {
            return fprintf(stderr, "largesteps fit: unknown option %s (see --help)\n", o), 0;
        }
        if (!ok && !ranged(o)) fprintf(stderr, "largesteps fit: %s: bad value '%s' (see --help for the choices)\n", o, v);
        if (!ok) return 0;
    }
    if (lambda_set && alpha_set)
        return fprintf(stderr, "largesteps fit: --lambda and --alpha conflict (two forms of the same weight: give one)\n"), 0;
    if (a->out == NULL) return fprintf(stderr, "largesteps fit: -o DIR is required\n"), 0;
    if (!optimizer_set && a->cfg.method != LS_FIT_LARGE_STEPS) optimizer = LS_OPTIM_ADAM;
    (void)ls_optim_config_default(optimizer, &a->cfg.optim);
    a->cfg.width = a->cfg.height = a->res;
    return 1;
}

/* Some pixel of an RGBA image has coverage (alpha above 0). */
static int covered(const ls_real *rgba, uint32_t width, uint32_t height)
{
    size_t i, n = (size_t)width * height;
    for (i = 0; i < n; i++)
        if (rgba[4u * i + 3u] > (ls_real)0) return 1;
    return 0;
}

typedef struct log_data {
    const ls_job_run *r;
    const ls_job_schedule *sched; /* the remeshes (markers in the plot) */
    double final_loss;            /* the final mesh's image loss */
} log_data;

/* The image loss of the final mesh: its renders (1 sample per pixel)
 * against the targets, with the fit's loss (NaN if it cannot be computed). */
static double final_loss(const ls_job_problem *p, uint32_t kind, ls_real *const *renders)
{
    ls_loss_acc acc;
    ls_real loss;
    uint32_t v;
    if (ls_loss_begin(&acc, kind, p->width, p->height, p->views) != LS_OK) return NAN;
    for (v = 0; v < p->views; v++)
        if (ls_loss_view(&acc, renders[v], p->targets[v], NULL, NULL) != LS_OK) return NAN;
    return ls_loss_finish(&acc, &loss) == LS_OK ? (double)loss : NAN;
}

/* One row per iteration (its loss, the elapsed time at its end), and the
 * distances of the mesh before it where they were measured; a last row for
 * the final mesh (where distances were measured): its image loss
 * (final_loss), the time at the end and its distances. */
static int write_log(FILE *f, void *ctx)
{
    const log_data *l = (const log_data *)ctx;
    const ls_job_run *r = l->r;
    uint32_t i, k = 0;
    fprintf(f, "iteration,loss,elapsed_ms,hausdorff_rel,rms_rel\n");
    for (i = 0; i <= r->iterations; i++) {
        if (i < r->iterations) fprintf(f, "%u,%.9g,%.3f,", (unsigned)i, (double)r->loss[i], r->ms[i]);
        else if (k < r->tracked)
            fprintf(f, "%u,%.9g,%.3f,", (unsigned)i, l->final_loss, r->iterations > 0 ? r->ms[i - 1] : 0.0);
        while (k < r->tracked && r->track_it[k] < i) k++;
        if (k < r->tracked && r->track_it[k] == i)
            fprintf(f, "%.6g,%.6g\n", (double)r->track_h_rel[k], (double)r->track_rms_rel[k]);
        else if (i < r->iterations)
            fprintf(f, ",\n");
    }
    return !ferror(f);
}

/* The decades [*lo, *hi] (powers of ten, at least one apart) around the
 * positive values of v[0..n) and e[0..ne). */
static void decades(const double *v, uint32_t n, const double *e, uint32_t ne, double *lo, double *hi)
{
    uint32_t i;
    *lo = 1e300;
    *hi = -1e300;
    for (i = 0; i < n + ne; i++) {
        double x = i < n ? v[i] : e[i - n];
        if (x > 0 && log10(x) < *lo) *lo = log10(x);
        if (x > 0 && log10(x) > *hi) *hi = log10(x);
    }
    if (!(*hi >= *lo)) *lo = 0, *hi = 1;
    *lo = floor(*lo);
    *hi = ceil(*hi);
    if (*hi - *lo < 1) *hi = *lo + 1;
}

/* One panel: y (log) against x (log, x > 0), a tick and a grid line at every
 * power of ten with minor ticks at 2..9 on both axes, and the remeshes
 * (marks, in x's units) as dashed lines. */
static void svg_panel(FILE *f, double px, double py, double pw, double ph, const char *title, const char *xlabel,
                      const double *x, const double *y, uint32_t n, const char *colour, const double *marks,
                      uint32_t nmarks)
{
    double xlo, xhi, lo, hi;
    int k, m;
    uint32_t i;
    decades(x, n, marks, nmarks, &xlo, &xhi);
    decades(y, n, NULL, 0, &lo, &hi);
#define LX(v_) ((v_) > 0 ? log10(v_) : xlo)
#define SX(v_) (px + pw * (LX(v_) - xlo) / (xhi - xlo))
#define SY(l_) (py + ph - ph * ((l_) - lo) / (hi - lo))
    fprintf(f, "<g class=\"panel\">\n<text x=\"%g\" y=\"%g\">%s</text>\n", px, py - 8, title);
    for (k = (int)lo; k <= (int)hi; k++) {
        fprintf(f, "<line class=\"grid\" x1=\"%g\" x2=\"%g\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", px, px + pw,
                SY(k), SY(k));
        fprintf(f, "<g class=\"ytick\"><line x1=\"%g\" x2=\"%g\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"black\"/>"
                   "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text></g>\n",
                px - 6, px, SY(k), SY(k), px - 8, SY(k) + 4, pow(10.0, k));
        for (m = 2; m <= 9 && k < (int)hi; m++)
            fprintf(f, "<line class=\"yminor\" x1=\"%g\" x2=\"%g\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"black\"/>\n", px - 3,
                    px, SY(k + log10((double)m)), SY(k + log10((double)m)));
    }
    for (k = (int)xlo; k <= (int)xhi; k++) {
        const double v = pow(10.0, k);
        fprintf(f, "<line class=\"grid\" x1=\"%.1f\" x2=\"%.1f\" y1=\"%g\" y2=\"%g\" stroke=\"#ddd\"/>\n", SX(v), SX(v),
                py, py + ph);
        fprintf(f, "<g class=\"xtick\"><line x1=\"%.1f\" x2=\"%.1f\" y1=\"%g\" y2=\"%g\" stroke=\"black\"/>"
                   "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text></g>\n",
                SX(v), SX(v), py + ph, py + ph + 5, SX(v), py + ph + 18, v);
        for (m = 2; m <= 9 && k < (int)xhi; m++)
            fprintf(f, "<line class=\"xminor\" x1=\"%.1f\" x2=\"%.1f\" y1=\"%g\" y2=\"%g\" stroke=\"black\"/>\n",
                    SX(m * v), SX(m * v), py + ph, py + ph + 3);
    }
    fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"end\">%s</text>\n", px + pw, py + ph + 34, xlabel);
    fprintf(f, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", px, py, pw, ph);
    for (i = 0; i < nmarks; i++)
        fprintf(f, "<g class=\"remesh\"><line x1=\"%.1f\" x2=\"%.1f\" y1=\"%g\" y2=\"%g\" stroke=\"#2a8a2a\" "
                   "stroke-dasharray=\"4 3\"/><text x=\"%.1f\" y=\"%g\" font-size=\"10\" fill=\"#2a8a2a\">remesh</text></g>\n",
                SX(marks[i]), SX(marks[i]), py, py + ph, SX(marks[i]) + 3, py + 11);
    fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", colour);
    for (i = 0; i < n; i++) fprintf(f, "%.1f,%.1f ", SX(x[i]), y[i] > 0 ? SY(log10(y[i])) : py + ph);
    fprintf(f, "\"/>\n</g>\n");
#undef LX
#undef SX
#undef SY
}

/* Loss and dense Hausdorff distance (log scales) against iteration and
 * time: four panels in one standalone SVG, the scheduled remeshes marked. */
static int write_svg(FILE *f, void *ctx)
{
    const log_data *l = (const log_data *)ctx;
    const ls_job_run *r = l->r;
    const double w = 900, h = 640;
    uint32_t n = r->iterations, t = r->tracked, i, nm = 0;
    double mit[LS_JOB_MAX_REMESH], mms[LS_JOB_MAX_REMESH];
    double *it = (double *)calloc(n + t + 1u, sizeof(double));
    double *loss = (double *)calloc(n + 1u, sizeof(double));
    double *hit = (double *)calloc(t + 1u, sizeof(double));
    double *hms = (double *)calloc(t + 1u, sizeof(double));
    double *hv = (double *)calloc(t + 1u, sizeof(double));
    int ok = it != NULL && loss != NULL && hit != NULL && hms != NULL && hv != NULL;
    for (i = 0; l->sched != NULL && i < l->sched->remesh_count && i < LS_JOB_MAX_REMESH; i++)
        if (l->sched->remesh_at[i] < n) { /* done: before iteration remesh_at */
            mit[nm] = (double)l->sched->remesh_at[i] + 1.0; /* the first iteration after it, counting from 1 */
            mms[nm++] = l->sched->remesh_at[i] > 0 ? r->ms[l->sched->remesh_at[i] - 1u] / 1000.0 : 0.0;
        }
    if (ok) {
        for (i = 0; i < n; i++) it[i] = (double)i + 1.0, loss[i] = (double)r->loss[i];
        for (i = 0; i < t; i++) hit[i] = (double)r->track_it[i] + 1.0, hms[i] = r->track_ms[i] / 1000.0, hv[i] = 100.0 * (double)r->track_h_rel[i];
        fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" font-family=\"sans-serif\" font-size=\"12\">\n", w, h);
        fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
        svg_panel(f, 70, 40, 360, 220, "image loss against iteration", "iteration (from 1)", it, loss, n, "#1f5fbf", mit, nm);
        for (i = 0; i < n; i++) it[i] = r->ms[i] / 1000.0;
        svg_panel(f, 510, 40, 360, 220, "image loss against time", "seconds", it, loss, n, "#1f5fbf", mms, nm);
        if (t > 0) {
            svg_panel(f, 70, 360, 360, 220, "dense Hausdorff / bbox diagonal, % (against iteration)", "iteration (from 1)", hit, hv,
                      t, "#bf3f1f", mit, nm);
            svg_panel(f, 510, 360, 360, 220, "dense Hausdorff / bbox diagonal, % (against time)", "seconds", hms, hv, t,
                      "#bf3f1f", mms, nm);
        } else {
            fprintf(f, "<text x=\"70\" y=\"390\">no distances: the target is not a mesh, or --track 0</text>\n");
        }
        fprintf(f, "</svg>\n");
    }
    free(it);
    free(loss);
    free(hit);
    free(hms);
    free(hv);
    return ok && !ferror(f);
}

static int write_obj(FILE *f, void *ctx)
{
    return ls_mesh_write_obj((const ls_mesh *)ctx, ls_posix_write_file, f) == LS_OK;
}

/* albedo.ply: the result with its estimated per-vertex albedo as float red,
 * green, blue (mean 1 per channel; estimated_sh in metrics.json holds the
 * scale). */
static int write_albedo_ply(FILE *f, void *ctx)
{
    const ls_job_run *r = (const ls_job_run *)ctx;
    const ls_mesh *m = &r->result;
    uint32_t i;
    fprintf(f, "ply\nformat ascii 1.0\ncomment largesteps fit --albedo vertex: the estimated albedo, mean 1 per "
               "channel\nelement vertex %u\nproperty float x\nproperty float y\nproperty float z\n"
               "property float red\nproperty float green\nproperty float blue\nelement face %u\n"
               "property list uchar int vertex_indices\nend_header\n",
            (unsigned)m->vertex_count, (unsigned)m->face_count);
    for (i = 0; i < m->vertex_count; i++)
        fprintf(f, "%.9g %.9g %.9g %.6g %.6g %.6g\n", (double)m->positions[3u * i], (double)m->positions[3u * i + 1u],
                (double)m->positions[3u * i + 2u], (double)r->albedo[3u * i], (double)r->albedo[3u * i + 1u],
                (double)r->albedo[3u * i + 2u]);
    for (i = 0; i < m->face_count; i++)
        fprintf(f, "3 %u %u %u\n", (unsigned)m->triangles[3u * i], (unsigned)m->triangles[3u * i + 1u],
                (unsigned)m->triangles[3u * i + 2u]);
    return !ferror(f);
}

typedef struct json_data {
    const ls_job_problem *p;
    const ls_job_run *r;
    const fit_args *a;
    const ls_distance_report *d;
    const ls_tangle_report *t;
} json_data;

static int write_json(FILE *f, void *ctx)
{
    const json_data *j = (const json_data *)ctx;
    const ls_fit_timing *t = &j->r->timing;
    double n = j->r->iterations > 0 ? (double)j->r->iterations : 1.0;
    fprintf(f, "{\n  \"target\": ");
    ls_report_json_string(f, j->p->name);
    fprintf(f, ",\n  \"iterations\": %u, \"remeshes\": %u, \"vertices\": %u, \"faces\": %u,\n",
            (unsigned)j->r->iterations, (unsigned)j->r->remeshes, (unsigned)j->r->result.vertex_count,
            (unsigned)j->r->result.face_count);
    fprintf(f, "  \"rollbacks\": %u, \"remeshes_refused\": %u,\n", (unsigned)j->r->rollbacks,
            (unsigned)j->r->remeshes_refused);
    fprintf(f, "  \"final_loss\": "); /* null when not finite (a diverged fit) */
    ls_report_json_number(f, j->r->iterations > 0 ? (double)j->r->loss[j->r->iterations - 1] : 0.0);
    fprintf(f, ",\n");
    fprintf(f, "  \"ms_per_iteration\": {\"total\": %.4f, \"render\": %.4f, \"shading_backward\": %.4f, "
               "\"silhouettes\": %.4f, \"solves\": %.4f, \"optimizer\": %.4f},\n",
            j->r->total_ms / n, (double)t->render_ns * 1e-6 / n, (double)t->shade_backward_ns * 1e-6 / n,
            (double)t->silhouette_ns * 1e-6 / n, (double)t->solve_ns * 1e-6 / n, (double)t->optimizer_ns * 1e-6 / n);
    if (j->p->light == LS_FIT_LIGHT_ESTIMATE) { /* the lighting the fit estimated (shade.h's order) */
        uint32_t k;
        fprintf(f, "  \"albedo\": \"%s\",\n", j->r->albedo != NULL ? "vertex" : "uniform");
        fprintf(f, "  \"estimated_sh\": [");
        for (k = 0; k < 27; k++) {
            ls_report_json_number(f, (double)j->r->sh[k]);
            fprintf(f, "%s", k + 1 < 27 ? ", " : "],\n");
        }
    }
    if (j->d != NULL) ls_report_json_distance(f, j->d);
    fprintf(f, "  \"self_intersecting\": %s,\n", j->t->intersecting_pairs > 0 ? "true" : "false");
    ls_report_json_tangle(f, "tangle", j->t, 1);
    fprintf(f, "  \"fit_bytes\": %llu, \"job_bytes\": %llu, \"peak_bytes\": %llu\n}\n",
            (unsigned long long)j->r->fit_bytes, (unsigned long long)j->r->job_bytes, (unsigned long long)j->r->peak_used);
    return !ferror(f);
}

/* The fit after its arguments, in the arena; the caller releases it on
 * every path. */
static int fit_main(fit_args *ap, ls_arena *arena_p)
{
    fit_args a = *ap;
    ls_arena arena = *arena_p;
    ls_job_options o;
    ls_job_problem p;
    ls_job_run run;
    ls_distance_report dist;
    ls_tangle_report tangle;
    ls_diag d;
    ls_real **renders;
    uint32_t v;
    int have_metrics = 0, tty;
    ls_status st;
    memset(&o, 0, sizeof o);
    o.target = a.target;
    o.views = a.views;
    o.width = o.height = a.res;
    o.target_ss = a.target_ss;
    o.target_normals = a.target_normals;
    o.target_crease_deg = a.target_crease_deg;
    o.shading = a.cfg.shading.mode;
    o.level = a.level;
    o.init_edge = (double)a.init_edge;
    o.init_smooth = a.init_smooth;
    o.init_auto = !a.init_sphere;
    o.init_hull = a.init_hull;
    o.auto_res = !a.res_given;
    o.parallel = a.cfg.parallel; /* the target renders and the metrics on the fit's threads */
    o.workers = a.cfg.workers;
    if (!ls_job_load(&p, &o, &arena)) return 1;
    if (a.target_normals_given && !p.have_mesh) {
        fprintf(stderr, "largesteps fit: --target-normals shades the renders of a mesh target; %s's targets are "
                        "its images (leave the option out)\n", a.target);
        return 2;
    }
    if (a.cfg.view_batch >= p.views) a.cfg.view_batch = 0; /* as many as there are: all */
    if (!a.remesh_given && p.from_target) a.sched.remesh_count = 0; /* a start from the target has its detail */
    if (!a.remesh_h_given && p.from_target)
        a.sched.remesh_h = (ls_real)LS_JOB_COARSE_REMESH_H; /* and is refined less when --remesh asks */
    if (a.lr == 0) /* the target's own surface, not smoothed, is near the answer */
        a.lr = (ls_real)(p.from_target && a.init_smooth == 0 ? LS_JOB_COARSE_LR : LS_JOB_LR);
    /* in units of the initial mesh's radius (fit.h); --perturb moves it in the 6th digit */
    a.cfg.optim.lr = a.lr * ((ls_real)1 + (ls_real)a.perturb * (ls_real)1e-6);
    if (!a.grad_limit_given)
        a.cfg.grad_limit = (ls_real)(p.light == LS_FIT_LIGHT_ESTIMATE ? LS_JOB_GRAD_LIMIT_ESTIMATE : LS_JOB_GRAD_LIMIT);
    {
        const int shading_given = p.light != LS_FIT_LIGHT_ESTIMATE && p.shading.mode != LS_SHADE_MASK;
        if (!a.boost_given) a.cfg.boost = (ls_real)(shading_given ? LS_JOB_BOOST : LS_JOB_BOOST_ESTIMATE);
        if (a.sched.boost_final < 0) /* not given (the schedule's -1): --boost alone holds for the whole run */
            a.sched.boost_final = !a.boost_given && shading_given ? (ls_real)LS_JOB_BOOST_FINAL : a.cfg.boost;
    }
    if (a.cfg.albedo == LS_FIT_ALBEDO_VERTEX && p.light != LS_FIT_LIGHT_ESTIMATE) {
        fprintf(stderr, "largesteps fit: --albedo vertex is estimated with the lighting, from a camera dataset that "
                        "does not record its lighting (its transforms.json without largesteps_sh); this target's "
                        "shading is %s\n", p.shading.mode == LS_SHADE_MASK ? "the masks alone" : "given");
        return 2;
    }
    if (p.res_asked > 0)
        printf("the target is %.1f pixels thick at %u x %u (the median view's largest disc inside its mask), too thin "
               "for its silhouettes to grow a fit into: fitting at %u x %u, where it is %.1f (--res sets the size)\n",
               p.thickness_asked, (unsigned)p.res_asked, (unsigned)p.res_asked, (unsigned)p.width, (unsigned)p.height,
               p.thickness);
    if (p.thickness > 0 && p.thickness < LS_JOB_MIN_THICKNESS)
        fprintf(stderr, "largesteps fit: warning: the object is only %.1f pixels thick in the targets (the median "
                        "view's largest disc inside its mask); below %g the fit tends to shrink onto a part of it (%s)\n",
                p.thickness, LS_JOB_MIN_THICKNESS,
                p.have_mesh ? "a larger --res makes it thicker" : "images of higher resolution, or cropped closer to the "
                                                                 "object, make it thicker");
    if (p.target_creased)
        printf("the target is made of flat pieces (%.0f %% of its edges join coplanar faces): its renders show its "
               "creases sharper than %g degrees (--target-normals smooth shades it smooth)\n",
               100.0 * p.target_flat_share, LS_JOB_CREASE_DEG);
    if (p.have_mesh && (p.target_genus > 0 || p.target_components > 1)) {
        char what[64];
        if (p.target_genus > 0 && p.target_components > 1)
            snprintf(what, sizeof what, "genus %d and %u components", (int)p.target_genus, (unsigned)p.target_components);
        else if (p.target_genus > 0)
            snprintf(what, sizeof what, "genus %d", (int)p.target_genus);
        else
            snprintf(what, sizeof what, "%u components", (unsigned)p.target_components);
        if (p.auto_coarse > 0)
            printf("the target has %s, which a sphere cannot reach: starting from the target remeshed to %g of its "
                   "diagonal (--init-coarse E sets the edge; --init-sphere starts from the icosphere)\n",
                   what, p.start_edge);
        else if (p.auto_coarse < 0)
            fprintf(stderr, "largesteps fit: warning: the target has %s, which a sphere cannot reach, but the "
                            "remesher could not make a start of it (%s): starting from the icosphere all the same "
                            "(repair the mesh, or --init-hull 128 starts from the targets' visual hull)\n",
                    what, p.coarse_failure);
        else if (a.init_edge == 0 && a.init_hull == 0)
            fprintf(stderr, "largesteps fit: warning: the target has %s; the icosphere is one genus-0 surface and "
                            "cannot match it (--init-coarse %g starts from the target's own topology)\n",
                    what, LS_JOB_AUTO_EDGE);
    }
    if (p.target_flat_start)
        printf("the fit starts from the target itself: its renders show its faces flat, so that the fit stays on "
               "them (--target-normals smooth shades them smooth)\n");
    if (p.start_tries > 1 && p.start_pairs > 0) /* a remeshed start (coarse_initial): what became of its edge */
        printf("the start self-intersects (%u face pairs) remeshed to %g, %g and %g of the diagonal alike (a part "
               "thinner than the edge, or a target that self-intersects): remeshed to %g\n",
               (unsigned)p.start_pairs, p.start_edge_asked, p.start_edge_asked * LS_JOB_START_RETRY,
               p.start_edge_asked * LS_JOB_START_RETRY * LS_JOB_START_RETRY, p.start_edge);
    else if (p.start_tries > 1)
        printf("the start remeshed to %g of the diagonal self-intersected (a part thinner than the edge): remeshed "
               "to %g instead\n",
               p.start_edge_asked, p.start_edge);
    if (a.cfg.method == LS_FIT_LARGE_STEPS && a.cfg.mean_mode == LS_FIT_MEAN_KEEP) {
        /* M^-1 moves the mesh's translation 1 + lambda mu_1 times as far as its smoothest shape; far above
           that shape, UniformAdam's one scale turns the steps into translation jitter (docs/experiments.md) */
        const double w = (double)a.cfg.weight, lambda = a.cfg.form == LS_SYSTEM_ALPHA ? w / (1 - w) : w;
        const double mu = ls_job_smallest_mode(&p.initial, &arena), ratio = 1 + lambda * mu;
        if (ratio > LS_JOB_MEAN_RATIO_WARN)
            fprintf(stderr, "largesteps fit: warning: with lambda %g (alpha %g) the initial mesh's translation moves %.2g "
                            "times as far per step as its smoothest shape (its smallest Laplacian eigenvalue is %.3g); "
                            "from %g up the default fit was measured to jitter or leave the views at every learning "
                            "rate tried. A finer start (--level: each level divides the eigenvalue by about 4) or a "
                            "lower --alpha brings it below %g\n",
                    lambda, lambda / (1 + lambda), ratio, mu, (double)LS_JOB_MEAN_RATIO_WARN, (double)LS_JOB_MEAN_RATIO_WARN);
    }
    printf("target %s: %u vertices, %u faces; initial mesh: %u vertices; %u views at %u x %u (the object %.1f "
           "pixels thick)\n", p.name,
           p.have_mesh ? (unsigned)p.target.vertex_count : 0u, p.have_mesh ? (unsigned)p.target.face_count : 0u,
           (unsigned)p.initial.vertex_count, (unsigned)p.views, (unsigned)p.width, (unsigned)p.height, p.thickness);
    renders = (ls_real **)ls_arena_alloc(&arena, 2u * p.views, sizeof(ls_real *));
    for (v = 0; renders != NULL && v < 2u * p.views; v++) {
        renders[v] = (ls_real *)ls_arena_alloc(&arena, 4u * (size_t)p.width * p.height, sizeof(ls_real));
        if (renders[v] == NULL) renders = NULL;
    }
    if (renders == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL), 1;
    ls_diag_clear(&d);
    st = ls_job_render(&p, &p.initial, 1, renders, &arena, &d);
    if (st != LS_OK) return ls_job_fail("rendering the initial mesh", st, &d), 1;
    /* a view whose target shows the object but which does not see the start cannot move it */
    for (v = 0; v < p.views; v++)
        if (covered(p.targets[v], p.width, p.height) && !covered(renders[v], p.width, p.height)) {
            fprintf(stderr, "largesteps fit: frame %u (counting from 0) does not see the initial mesh, while its target "
                            "shows the object: "
                            "check that camera (a dataset's transform_matrix is camera-to-world, OpenGL: looking "
                            "down -z) or give an initial mesh where the cameras look\n", (unsigned)v);
            return 1;
        }
    tty = isatty(1);
    if (!ls_job_fit(&p, &a.cfg, &a.sched, a.quiet ? 0 : tty ? 2 : 1,
                    a.track > 0 ? a.track : a.sched.iterations + 1u, &a.cap, &arena, &run))
        return 1;
    {
        const ls_fit_timing *t = &run.timing;
        double n = run.iterations > 0 ? run.iterations : 1;
        printf("fit memory %.2f MiB reserved for the job (ls_fit_job_bytes: %lu bytes for %u vertices, %u faces, "
               "%u factor entries), %.2f MiB at start, %.2f at the end, %.2f at most in use; the remesher's most live "
               "vertices %u, factor entries at the end %u\n",
               (double)run.job_bytes / 1048576.0, (unsigned long)run.job_bytes, (unsigned)run.capacity.max_vertices,
               (unsigned)run.capacity.max_faces, (unsigned)run.capacity.max_factor_nnz,
               (double)run.fit_bytes / 1048576.0, (double)run.fit_bytes_end / 1048576.0,
               (double)run.peak_used / 1048576.0, (unsigned)run.remesh_live_max, (unsigned)run.factor_nnz);
        printf("set-up %.1f ms; %u remeshes", run.setup_ms, (unsigned)run.remeshes);
        if (run.remeshes_refused > 0) printf(", %u refused (the mesh kept as it was)", (unsigned)run.remeshes_refused);
        printf("; %u vertices at the end; distances measured %u times in %.0f ms (not counted below)\n",
               (unsigned)run.result.vertex_count, (unsigned)run.tracked, run.track_total_ms);
        printf("time per iteration %.2f ms: render %.2f, shading backward %.2f, silhouettes %.2f, solves %.2f, "
               "optimizer %.2f\n",
               run.total_ms / n, (double)t->render_ns * 1e-6 / n, (double)t->shade_backward_ns * 1e-6 / n,
               (double)t->silhouette_ns * 1e-6 / n, (double)t->solve_ns * 1e-6 / n, (double)t->optimizer_ns * 1e-6 / n);
    }
    if (p.light == LS_FIT_LIGHT_ESTIMATE) { /* the contact sheet's renders under the estimated lighting */
        memcpy(p.sh, run.sh, sizeof p.sh);
        st = ls_job_render(&p, &p.initial, 1, renders, &arena, &d);
        if (st != LS_OK) return ls_job_fail("rendering the initial mesh", st, &d), 1;
    }
    p.shading.vertex_colors = run.albedo; /* the result under its estimated albedo (NULL: uniform) */
    st = ls_job_render(&p, &run.result, 1, renders + p.views, &arena, &d);
    p.shading.vertex_colors = NULL;
    if (st != LS_OK) return ls_job_fail("rendering the result", st, &d), 1;
    if (p.have_mesh) {
        have_metrics = ls_job_metrics(&p, &run.result, &arena, &dist, &tangle);
        if (!have_metrics) return 1;
        ls_report_text_distance(stdout, &dist);
    } else {
        st = ls_tangle_parallel(&run.result, NULL, &p.parallel, ls_job_workers(&p), &arena, &tangle, &d);
        if (st != LS_OK) return ls_job_fail("checking the result for self-intersections", st, &d), 1;
    }
    ls_report_text_tangle(stdout, "result", &tangle);
    {
        log_data l;
        json_data j;
        ls_contact sheet;
        ls_posix_outset *set;
        l.r = &run;
        l.sched = &a.sched;
        l.final_loss = final_loss(&p, a.cfg.loss, renders + p.views);
        j.p = &p;
        j.r = &run;
        j.a = &a;
        j.d = have_metrics ? &dist : NULL;
        j.t = &tangle;
        if (ls_posix_mkdir_p(a.out) != 0) return fprintf(stderr, "largesteps fit: cannot create %s: %s\n", a.out, strerror(errno)), 1;
        const uint32_t shown = ls_report_sheet_views(p.views);
        st = ls_contact_init(&sheet, &arena, 3u * shown, p.width, p.height, shown, 1, NULL);
        for (v = 0; v < shown && st == LS_OK; v++) {
            const uint32_t w = ls_report_sheet_view(v, p.views);
            st = ls_contact_put_rgba(&sheet, v, p.targets[w]);
            if (st == LS_OK) st = ls_contact_put_rgba(&sheet, shown + v, renders[w]);
            if (st == LS_OK) st = ls_contact_put_rgba(&sheet, 2u * shown + v, renders[p.views + w]);
        }
        if (st == LS_OK) st = ls_report_fit_sheet(&sheet, p.views);
        if (st != LS_OK) return ls_job_fail("contact sheet", st, NULL), 1;
        ls_image_format png = {LS_IMAGE_PNG, 3, 8, 0}; /* the sheet is opaque: no alpha channel */
        /* the files appear together or not at all: an earlier run's set
         * stays whole when this one cannot be written */
        set = ls_posix_outset_begin(a.out);
        if (set == NULL) return fprintf(stderr, "largesteps fit: out of memory\n"), 1;
        (void)(ls_posix_outset_add(set, "result.obj", write_obj, &run.result) &&
               ls_posix_outset_add(set, "log.csv", write_log, &l) &&
               ls_posix_outset_add(set, "convergence.svg", write_svg, &l) &&
               ls_posix_outset_add_image(set, "contact.png", &sheet.image, &png, &arena, NULL) &&
               ls_posix_outset_add(set, "metrics.json", write_json, &j) &&
               (run.albedo == NULL || ls_posix_outset_add(set, "albedo.ply", write_albedo_ply, &run)));
        if (!ls_posix_outset_commit(set)) return 1;
    }
    printf("final loss %.6g after %u iterations; wrote %s/{result.obj,log.csv,convergence.svg,contact.png,metrics.json%s}\n",
           run.iterations > 0 ? (double)run.loss[run.iterations - 1] : 0.0, (unsigned)run.iterations, a.out,
           run.albedo != NULL ? ",albedo.ply" : "");
    if (tangle.intersecting_pairs > 0) { /* never a silent tangle: the last line and the exit status */
        ls_tangle_report own;
        fprintf(stderr, "largesteps fit: the result self-intersects (%u face pairs, faces %u and %u first); it is "
                        "written all the same. ",
                (unsigned)tangle.intersecting_pairs, (unsigned)tangle.first_pair[0], (unsigned)tangle.first_pair[1]);
        if (p.have_mesh && ls_tangle(&p.target, NULL, &arena, &own, &d) == LS_OK && own.intersecting_pairs > 0)
            fprintf(stderr, "The target itself self-intersects (%u face pairs), and a result that follows it can too "
                            "(exit status 3)\n", (unsigned)own.intersecting_pairs);
        else
            fprintf(stderr, "Try a smaller --lr, more --views or --guard %u (exit status 3)\n",
                    a.sched.guard_every > 0 ? a.sched.guard_every / 2u + 1u : 25u);
        return 3;
    }
    return 0;
}

int ls_cmd_fit(int argc, char **argv)
{
    fit_args a;
    unsigned char *work;
    size_t work_bytes = 0;
    ls_arena arena;
    ls_posix_pool *pool = NULL;
    int rc, r = parse_args(argc, argv, &a);
    if (r <= 0) return r < 0 ? 0 : 2;
    if (!ls_posix_check_output_dir(a.out)) return 2; /* before any work */
    work = (unsigned char *)ls_posix_work_memory(&work_bytes);
    if (work == NULL || ls_arena_init(&arena, work, work_bytes) != LS_OK) {
        free(work);
        return fprintf(stderr, "largesteps fit: out of memory\n"), 1;
    }
    if (a.threads == 0) a.threads = ls_posix_cores();
    if (a.threads > 1u) { /* the views of each iteration shared by a pool of threads */
        pool = ls_posix_pool_create(a.threads);
        if (pool == NULL) {
            free(work);
            return fprintf(stderr, "largesteps fit: cannot start %u threads (--threads 1 runs on this one)\n",
                           (unsigned)a.threads), 1;
        }
        a.cfg.workers = a.threads;
        a.cfg.parallel.run = ls_posix_pool_run;
        a.cfg.parallel.ctx = pool;
    }
    rc = fit_main(&a, &arena);
    ls_posix_pool_destroy(pool);
    free(work); /* on every path, failures included */
    return rc;
}
