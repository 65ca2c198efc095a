/* cmd_experiment.c - `largesteps experiment NAME [options] -o DIR`: the
 * paper's experiments as Markdown tables (DIR/NAME.md, also printed).
 *
 *   lambda-sweep  the alpha form, alpha in {0, .25, .5, .75, .95, .98, .99,
 *                 .999} (lambda = alpha / (1 - alpha)) at the paper's step
 *                 (--step, in the target's units, as its step_size 1e-3) and
 *                 one iteration count, L1 (the paper ran 4300 steps;
 *                 M = (1 - alpha)(I + lambda L), so a step of u moves x
 *                 1 / (1 - alpha) times farther than in the lambda form: the
 *                 effective rate grows with alpha), with the mean of dL/du
 *                 kept (the paper's) and/or projected out (--mean); then
 *                 the lambda form with the learning rate chosen per lambda
 *                 from a grid (best H).
 *   compare       naive, Laplacian-regularized, bilaplacian-regularized and
 *                 large steps, each tuned on a grid around the paper's values,
 *                 at equal iterations and at equal time (the large-steps
 *                 run's time); one contact sheet of all methods.
 *   silhouettes   silhouettes only (mask shading), lambda = 99, L2: large
 *                 steps against Laplacian regularization of weights 1, 400,
 *                 10000 (the paper's failure case for regularization).
 *   views         1, 2, 4, 9, 16, 25, 49 views.
 *
 * H is the symmetric vertex-sampled Hausdorff distance (igl::hausdorff, as
 * the paper's lambda-sweep figure reports it, not doubled); the dense
 * columns are over area-uniform face samples; "rel" divides by the target's
 * bounding-box diagonal. Learning rates are in units of the target's
 * bounding-sphere radius (as in largesteps fit). The default sizes are small so that each experiment
 * runs in minutes on one core; --iters, --res, --views, --level scale them.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <math.h>
#include "ls_posix.h"
#include "commands.h"
#include "fit_job.h"
#include "args.h"

typedef struct exp_args {
    const char *name, *target, *out;
    uint32_t iters, res, views, level, init_smooth;
    uint32_t remesh_count, remesh_at[LS_JOB_MAX_REMESH]; /* compare: every run's remesh schedule */
    uint32_t forms;   /* lambda-sweep: 1 the alpha form, 2 the lambda form, 3 both */
    uint32_t means;   /* lambda-sweep, alpha form: 1 mean kept, 2 projected, 3 both */
    double step;      /* lambda-sweep, alpha form: the learning rate in the target's units */
    double cap;       /* compare: a baseline run stops at cap x the large-steps run's time */
    double init_edge; /* > 0: the initial mesh is the target remeshed and smoothed (fit_job.h) */
} exp_args;

typedef struct exp_result {
    double h, h_rel, dense_h_rel, mean_rel, rms_rel, ms, ms_per_it, loss;
    uint32_t pairs, vertices, iterations;
    int ok;
} exp_result;

static int usage(FILE *f)
{
    fprintf(f, "usage: largesteps experiment lambda-sweep|compare|silhouettes|views [TARGET] [options] -o DIR\n"
               "       largesteps experiment tradeoffs [TARGET] [options] -o DIR   (--help for its options)\n"
               "       largesteps experiment texture [options] -o DIR   (texture reconstruction; --help)\n"
               "  TARGET      a mesh (OBJ, PLY, OFF) or a scene (default: the embedded bunny)\n"
               "  -o DIR      output directory (required): NAME.md, compare.png for compare, lambda-sweep.png\n"
               "              for lambda-sweep (a contact sheet of the results)\n"
               "  --iters N   iterations per run (1..1000000; default 400)\n"
               "  --res R     render size R x R (8..4096; default 64)\n"
               "  --views N   views (1..1024; default 16; the views experiment sets its own)\n"
               "  --level K   initial icosphere level (0..7; default 3)\n"
               "  --init-coarse E, --init-smooth N   initial mesh: the target remeshed to edge E x its\n"
               "              bounding-box diagonal (0 < E <= 1; default: the icosphere), N Taubin steps\n"
               "              (0..10000; default 10); for targets of genus > 0\n"
               "  --form F    lambda-sweep: alpha | lambda | both (default both)\n"
               "  --step X    lambda-sweep, alpha form: the learning rate in the target's units, as the\n"
               "              paper's step_size (0 < X <= 10; default 1e-3, the paper's)\n"
               "  --mean M    lambda-sweep, alpha form: keep (the paper's) | project (the mean of dL/du\n"
               "              taken out, the translation alone moves the mesh as a whole) | both (default)\n"
               "  --remesh I,J  compare: remesh every run before these iterations (default none, as the\n"
               "              paper's comparison figure)\n"
               "  --cap F     compare: each baseline run stops at F x the tuned large-steps run's time\n"
               "              (1..1000; default 3; a tangled mesh can cost 10x per iteration)\n" LS_ARGS_GLOBAL_HELP);
    return f == stderr ? 2 : 0;
}

/* One run from the problem's initial mesh, measured against its target;
 * render (optional): the result's views (S = 1), rendered before the run's
 * memory is released. */
static exp_result run_one(const ls_job_problem *p, const ls_fit_config *cfg, uint32_t iters, double budget_ms,
                          const uint32_t *remesh, uint32_t nremesh, ls_arena *arena, ls_real **render)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_job_run r;
    ls_distance_report d;
    ls_tangle_report t;
    ls_fit_config c = *cfg;
    exp_result e;
    memset(&e, 0, sizeof e);
    /* learning rates are in units of the initial mesh's radius (fit.h): the
     * icosphere on the target's bounding sphere, as largesteps fit */
    ls_job_schedule s;
    uint32_t k;
    ls_job_schedule_default(&s);
    s.guard_every = 0; /* the paper's plain loop: these runs reproduce its experiments */
    s.settle = 0;
    s.iterations = iters;
    s.time_budget_ms = budget_ms;
    s.remesh_count = nremesh < LS_JOB_MAX_REMESH ? nremesh : LS_JOB_MAX_REMESH;
    for (k = 0; k < s.remesh_count; k++) s.remesh_at[k] = remesh[k];
    if (ls_job_fit(p, &c, &s, 0, 0, NULL, arena, &r) && ls_job_metrics(p, &r.result, arena, &d, &t)) {
        e.ok = 1;
        e.h = (double)d.vertex_hausdorff;
        e.h_rel = (double)d.vertex_hausdorff_rel;
        e.dense_h_rel = (double)d.hausdorff_rel;
        e.mean_rel = (double)d.mean_rel;
        e.rms_rel = (double)d.rms_rel;
        e.ms = r.total_ms;
        e.iterations = r.iterations;
        e.ms_per_it = r.iterations > 0 ? r.total_ms / r.iterations : 0;
        e.loss = r.iterations > 0 ? (double)r.loss[r.iterations - 1] : 0;
        e.pairs = t.intersecting_pairs;
        e.vertices = r.result.vertex_count;
        if (render != NULL) {
            ls_diag rd;
            ls_diag_clear(&rd);
            e.ok = ls_job_render(p, &r.result, 1, render, arena, &rd) == LS_OK;
        }
    }
    ls_arena_restore(arena, mark);
    return e;
}

/* One table row; extra (NULL: none) is one more cell. */
static void row_end(FILE *f, const char *label, const exp_result *e, const char *extra)
{
    if (!e->ok)
        fprintf(f, "| %s | failed |%s", label, " | | | | | | |");
    else
        fprintf(f, "| %s | %.4f | %.4f | %.4f | %.4f | %.4f | %u | %u | %.0f (%.1f ms/it) |", label, e->h, e->h_rel,
                e->dense_h_rel, e->mean_rel, e->rms_rel, (unsigned)e->pairs, (unsigned)e->vertices, e->ms,
                e->ms_per_it);
    if (extra != NULL) fprintf(f, " %s |", extra);
    fprintf(f, "\n");
}

static void row(FILE *f, const char *label, const exp_result *e)
{
    row_end(f, label, e, NULL);
}

static void header(FILE *f)
{
    fprintf(f, "| run | H | H rel | dense H rel | mean rel | RMS rel | self-intersections | vertices | time ms |\n");
    fprintf(f, "|---|---|---|---|---|---|---|---|---|\n");
}

static void config(ls_fit_config *c, uint32_t method, ls_real lr)
{
    ls_fit_config_default(c);
    c->method = method;
    if (method != LS_FIT_LARGE_STEPS) (void)ls_optim_config_default(LS_OPTIM_ADAM, &c->optim);
    c->optim.lr = lr;
}

/* Renders of every view of a result (S = 1), for the contact sheet. */
typedef struct view_set {
    ls_real **v;
    size_t bytes; /* of one view */
} view_set;

static int views_alloc(const ls_job_problem *p, ls_arena *arena, view_set *s)
{
    uint32_t k;
    s->bytes = 4u * (size_t)p->width * p->height * sizeof(ls_real);
    s->v = (ls_real **)ls_arena_alloc(arena, p->views, sizeof(ls_real *));
    for (k = 0; s->v != NULL && k < p->views; k++) {
        s->v[k] = (ls_real *)ls_arena_alloc(arena, s->bytes / sizeof(ls_real), sizeof(ls_real));
        if (s->v[k] == NULL) s->v = NULL;
    }
    return s->v != NULL;
}

/* DIR/NAME: a contact sheet, a row per mesh, a column for each of the
 * first `cols` views. */
static void write_sheet(const ls_job_problem *p, const exp_args *a, const char *name, const view_set *rows,
                        uint32_t nrows, uint32_t cols, ls_arena *arena)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_image_format png = {LS_IMAGE_PNG, 4, 8, 0};
    ls_contact sheet;
    uint32_t r, v;
    ls_status st;
    if (cols > p->views) cols = p->views;
    st = ls_contact_init(&sheet, arena, nrows * cols, p->width, p->height, cols, 1, NULL);
    for (r = 0; r < nrows && st == LS_OK; r++)
        for (v = 0; v < cols && st == LS_OK; v++) st = ls_contact_put_rgba(&sheet, r * cols + v, rows[r].v[v]);
    if ((st != LS_OK || !ls_posix_write_image_in(a->out, name, &sheet.image, &png, arena, &st)) && st != LS_OK)
        fprintf(stderr, "largesteps experiment: cannot encode %s/%s: %s\n", a->out, name, ls_status_str(st)); /* a file error: reported by the writer */
    ls_arena_restore(arena, mark);
}

/* R, the unit of the fit's learning rate (fit.h): half the largest side of
 * the initial mesh's bounding box (1 for a mesh collapsed to a point). */
static double initial_radius(const ls_mesh *m)
{
    ls_real lo[3], hi[3];
    double r = 0;
    int k;
    if (ls_mesh_bounds(m, lo, hi) != LS_OK) return 1;
    for (k = 0; k < 3; k++)
        if ((double)(hi[k] - lo[k]) / 2 > r) r = (double)(hi[k] - lo[k]) / 2;
    return r > 0 ? r : 1;
}

/* The alpha form at the paper's fixed step, with the mean of dL/du kept
 * and/or projected out. */
static void sweep_alpha(FILE *f, const ls_job_problem *p, const exp_args *a, ls_arena *arena)
{
    static const double alphas[8] = {0, 0.25, 0.5, 0.75, 0.95, 0.98, 0.99, 0.999};
    static const char *paper[8] = {"0.78-0.91", "0.78-0.91", "0.78-0.91", "0.156-0.158", "0.156-0.158",
                                   "0.156-0.158", "0.156-0.158", "0.127"};
    const double radius = initial_radius(&p->initial), mu = ls_job_smallest_mode(&p->initial, arena);
    ls_arena_mark mark = ls_arena_save(arena);
    view_set rows[18]; /* target, initial, then each alpha's result with the mean kept, then projected */
    const uint32_t rows_used = 2u + (a->means & 1u ? 8u : 0u) + (a->means & 2u ? 8u : 0u);
    uint32_t nrows = 2, r;
    ls_fit_config c;
    char label[96], cell[64];
    uint32_t mean;
    int i, ok = 1;
    ls_diag d;
    ls_diag_clear(&d);
    for (r = 0; r < rows_used && ok; r++) ok = views_alloc(p, arena, &rows[r]);
    ok = ok && ls_job_render(p, &p->target, 1, rows[0].v, arena, &d) == LS_OK &&
         ls_job_render(p, &p->initial, 1, rows[1].v, arena, &d) == LS_OK;
    for (mean = 0; mean < 2; mean++) {
        if ((a->means & (1u << mean)) == 0) continue;
        fprintf(f, "## alpha form, step %g in the target's units (lr %.6g R, R = %.6g), %u iterations, L1, the mean "
                   "of dL/du %s\n\n",
                a->step, a->step / radius, radius, (unsigned)a->iters,
                mean == 0 ? "kept (the paper's)" : "projected out (the translation moves the mesh as a whole)");
        fprintf(f, "The initial mesh's smallest nonzero Laplacian eigenvalue mu_1 = %.6f: M^-1 amplifies the mean "
                   "(translation) mode (1 - alpha + alpha mu_1) / (1 - alpha) times as much as the smoothest shape "
                   "mode (the amplification column). Beside each run, H as the paper's figure gives it for the same "
                   "alpha (its range over the alphas of one regime).\n\n",
                mu);
        fprintf(f, "| run | H | H rel | dense H rel | mean rel | RMS rel | self-intersections | vertices | time ms | "
                   "amplification | paper's H (Suzanne) |\n");
        fprintf(f, "|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (i = 0; i < 8; i++) {
            exp_result e;
            config(&c, LS_FIT_LARGE_STEPS, (ls_real)(a->step / radius));
            c.form = LS_SYSTEM_ALPHA;
            c.weight = (ls_real)alphas[i];
            c.mean_mode = mean == 0 ? LS_FIT_MEAN_KEEP : LS_FIT_MEAN_PROJECT;
            e = run_one(p, &c, a->iters, 0, NULL, 0, arena, ok ? rows[nrows].v : NULL);
            if (ok && !e.ok) ok = 0;
            nrows++;
            snprintf(label, sizeof label, "alpha %g (lambda %.3g)", alphas[i], alphas[i] / (1 - alphas[i]));
            snprintf(cell, sizeof cell, "%.3g | %s", (1 - alphas[i] + alphas[i] * mu) / (1 - alphas[i]), paper[i]);
            row_end(f, label, &e, cell);
            fflush(f);
        }
        fprintf(f, "\n");
    }
    if (ok) {
        write_sheet(p, a, "lambda-sweep.png", rows, nrows, 4, arena);
        fprintf(f, "Contact sheet: lambda-sweep.png (rows: target, initial, then each alpha from 0 to 0.999%s; the "
                   "first %u views).\n\n",
                a->means == 3 ? ", the mean kept, then projected" : "", (unsigned)(p->views < 4 ? p->views : 4));
    }
    ls_arena_restore(arena, mark);
}

/* The lambda form, the learning rate tuned per lambda. */
static void sweep_lambda(FILE *f, const ls_job_problem *p, const exp_args *a, ls_arena *arena)
{
    static const double lambdas[6] = {0, 1, 3, 19, 99, 999};
    static const double lrs[6] = {3e-3, 1e-2, 3e-2, 1e-1, 3e-1, 1};
    ls_fit_config c;
    char label[64];
    int i, k;
    fprintf(f, "\n## lambda form, learning rate chosen per lambda from {3e-3, 1e-2, 3e-2, 0.1, 0.3, 1} (lowest H)\n\n");
    header(f);
    for (i = 0; i < 6; i++) {
        exp_result best;
        double best_lr = 0;
        memset(&best, 0, sizeof best);
        for (k = 0; k < 6; k++) {
            exp_result e;
            config(&c, LS_FIT_LARGE_STEPS, (ls_real)lrs[k]);
            c.weight = (ls_real)lambdas[i];
            e = run_one(p, &c, a->iters, 0, NULL, 0, arena, NULL);
            if (e.ok && (!best.ok || e.h < best.h)) best = e, best_lr = lrs[k];
        }
        snprintf(label, sizeof label, "lambda %g, lr %g", lambdas[i], best_lr);
        row(f, label, &best);
        fflush(f);
    }
}

/* The best (lowest H) of a grid of learning rates and weights for one
 * method; each run stops at budget_ms when > 0. best (optional) receives
 * the best run's renders (tmp: scratch renders of the same size). */
static exp_result tuned(const ls_job_problem *p, const exp_args *a, uint32_t method, uint32_t iters, double budget_ms,
                        ls_arena *arena, double *lr_out, double *w_out, const view_set *best_views, const view_set *tmp)
{
    static const double lrs_adam[3] = {3e-3, 1e-2, 3e-2};
    static const double lrs_large[3] = {1e-2, 3e-2, 1e-1};
    static const double weights[3] = {0.3, 3, 30};
    ls_fit_config c;
    exp_result best;
    uint32_t v;
    int i, k, nw = method == LS_FIT_LAPLACIAN || method == LS_FIT_BILAPLACIAN ? 3 : 1;
    memset(&best, 0, sizeof best);
    for (i = 0; i < 3; i++)
        for (k = 0; k < nw; k++) {
            exp_result e;
            double lr = method == LS_FIT_LARGE_STEPS ? lrs_large[i] : lrs_adam[i];
            config(&c, method, (ls_real)lr);
            c.reg_weight = (ls_real)weights[k];
            e = run_one(p, &c, iters, budget_ms, a->remesh_at, a->remesh_count, arena,
                        best_views != NULL ? tmp->v : NULL);
            if (e.ok && (!best.ok || e.h < best.h)) {
                best = e, *lr_out = lr, *w_out = nw > 1 ? weights[k] : 0;
                for (v = 0; best_views != NULL && v < p->views; v++) memcpy(best_views->v[v], tmp->v[v], tmp->bytes);
            }
        }
    return best;
}

static void method_label(char *label, size_t cap, const char *name, double lr, double w, const exp_result *e,
                         uint32_t iters)
{
    int n = w > 0 ? snprintf(label, cap, "%s, lr %g, weight %g", name, lr, w) : snprintf(label, cap, "%s, lr %g", name, lr);
    if (n > 0 && (size_t)n < cap && e->ok && e->iterations < iters)
        snprintf(label + n, cap - (size_t)n, ", %u iterations", (unsigned)e->iterations);
}

static void compare(FILE *f, const ls_job_problem *p, const exp_args *a, ls_arena *arena)
{
    static const uint32_t methods[4] = {LS_FIT_NAIVE, LS_FIT_LAPLACIAN, LS_FIT_BILAPLACIAN, LS_FIT_LARGE_STEPS};
    static const char *const names[4] = {"naive (Adam)", "Laplacian reg. (Adam)", "bilaplacian reg. (Adam)",
                                         "large steps (UniformAdam, lambda 19)"};
    ls_arena_mark mark = ls_arena_save(arena);
    exp_result large;
    double lr = 0, w = 0, large_lr = 0, cap_ms;
    view_set rows[6], tmp; /* target, initial, the four methods at equal time */
    char label[160];
    int m, ok = views_alloc(p, arena, &tmp);
    ls_diag d;
    ls_diag_clear(&d);
    for (m = 0; m < 6 && ok; m++) ok = views_alloc(p, arena, &rows[m]);
    ok = ok && ls_job_render(p, &p->target, 1, rows[0].v, arena, &d) == LS_OK &&
         ls_job_render(p, &p->initial, 1, rows[1].v, arena, &d) == LS_OK;
    large = tuned(p, a, LS_FIT_LARGE_STEPS, a->iters, 0, arena, &large_lr, &w, ok ? &rows[5] : NULL, &tmp);
    cap_ms = a->cap * large.ms;
    fprintf(f, "## equal iterations (%u), each method tuned on a grid of learning rates (and weights); a baseline run "
               "stops at %g x the large-steps run's time (%.0f ms)\n\n",
            (unsigned)a->iters, a->cap, cap_ms);
    header(f);
    for (m = 0; m < 4; m++) {
        exp_result e = m == 3 ? large : tuned(p, a, methods[m], a->iters, cap_ms, arena, &lr, &w, NULL, NULL);
        if (m == 3) lr = large_lr, w = 0;
        method_label(label, sizeof label, names[m], lr, w, &e, a->iters);
        row(f, label, &e);
        fflush(f);
    }
    fprintf(f, "\n## equal time (%.0f ms, the large-steps run's)\n\n", large.ms);
    header(f);
    for (m = 0; m < 3; m++) {
        exp_result e = tuned(p, a, methods[m], 1000000u, large.ms, arena, &lr, &w, ok ? &rows[2 + m] : NULL, &tmp);
        method_label(label, sizeof label, names[m], lr, w, &e, 1000000u);
        row(f, label, &e);
        fflush(f);
    }
    method_label(label, sizeof label, names[3], large_lr, 0, &large, a->iters);
    row(f, label, &large);
    if (ok) {
        write_sheet(p, a, "compare.png", rows, 6, p->views, arena);
        fprintf(f, "\nContact sheet: compare.png (rows: target, initial, naive, Laplacian, bilaplacian, large steps at "
                   "equal time; a column per view).\n");
    }
    ls_arena_restore(arena, mark);
}

static void silhouettes(FILE *f, const ls_job_problem *p, const exp_args *a, ls_arena *arena)
{
    static const double weights[3] = {1, 400, 10000};
    ls_fit_config c;
    exp_result e;
    char label[64];
    int k;
    fprintf(f, "## silhouettes only (mask), L2, %u iterations\n\n", (unsigned)a->iters);
    header(f);
    config(&c, LS_FIT_LARGE_STEPS, (ls_real)5e-3);
    c.weight = 99;
    c.loss = LS_LOSS_L2;
    c.use_translation = 0;
    e = run_one(p, &c, a->iters, 0, NULL, 0, arena, NULL);
    row(f, "large steps, lambda 99", &e);
    for (k = 0; k < 3; k++) {
        config(&c, LS_FIT_LAPLACIAN, (ls_real)5e-3);
        c.reg_weight = (ls_real)weights[k];
        c.loss = LS_LOSS_L2;
        c.use_translation = 0;
        e = run_one(p, &c, a->iters, 0, NULL, 0, arena, NULL);
        snprintf(label, sizeof label, "Laplacian reg., weight %g", weights[k]);
        row(f, label, &e);
        fflush(f);
    }
}

typedef struct table_buf {
    const char *text;
    size_t bytes;
} table_buf;

static int write_table(FILE *f, void *ctx)
{
    const table_buf *t = (const table_buf *)ctx;
    return fwrite(t->text, 1, t->bytes, f) == t->bytes;
}

static int experiment_body(FILE *f, const exp_args *ap, ls_arena *arena_p);

int ls_cmd_experiment(int argc, char **argv)
{
    exp_args a;
    unsigned char *work;
    size_t work_bytes = (size_t)1 << 30, table_bytes = 0;
    ls_arena arena;
    char md[256], *table = NULL;
    FILE *f;
    int i, rc;
    memset(&a, 0, sizeof a);
    a.iters = 400;
    a.res = 64;
    a.views = 16;
    a.level = 3;
    a.init_smooth = 10;
    a.cap = 3;
    a.forms = 3;
    a.means = 3;
    a.step = 1e-3;
    if (argc < 2) return usage(stderr);
    if (strcmp(argv[1], "texture") == 0) return ls_cmd_experiment_texture(argc - 1, argv + 1);
    a.name = argv[1];
    if (strcmp(a.name, "tradeoffs") == 0) return ls_cmd_tradeoffs(argc - 1, argv + 1);
    for (i = 2; i < argc; i++) {
        const char *opt = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0) return usage(stdout);
        if (opt[0] != '-') {
            if (a.target != NULL) return fprintf(stderr, "largesteps experiment: more than one target ('%s')\n", opt), 2;
            a.target = opt;
            continue;
        }
        if (strcmp(opt, "-o") != 0 && strcmp(opt, "--iters") != 0 && strcmp(opt, "--res") != 0 &&
            strcmp(opt, "--views") != 0 && strcmp(opt, "--level") != 0 && strcmp(opt, "--init-smooth") != 0 &&
            strcmp(opt, "--init-coarse") != 0 && strcmp(opt, "--remesh") != 0 && strcmp(opt, "--form") != 0 &&
            strcmp(opt, "--cap") != 0 && strcmp(opt, "--step") != 0 && strcmp(opt, "--mean") != 0) {
            fprintf(stderr, "largesteps experiment: unknown option '%s'\n", opt);
            return usage(stderr);
        }
        if (v == NULL) return fprintf(stderr, "largesteps experiment: %s needs a value\n", opt), 2;
        i++;
        if (strcmp(opt, "-o") == 0) a.out = v;
        else if (strcmp(opt, "--iters") == 0) ok = ls_arg_u32("experiment", opt, v, 1, 1000000, &a.iters);
        else if (strcmp(opt, "--res") == 0) ok = ls_arg_u32("experiment", opt, v, 8, 4096, &a.res);
        else if (strcmp(opt, "--views") == 0) ok = ls_arg_u32("experiment", opt, v, 1, 1024, &a.views);
        else if (strcmp(opt, "--level") == 0) ok = ls_arg_u32("experiment", opt, v, 0, 7, &a.level);
        else if (strcmp(opt, "--init-smooth") == 0) ok = ls_arg_u32("experiment", opt, v, 0, 10000, &a.init_smooth);
        else if (strcmp(opt, "--init-coarse") == 0) ok = ls_arg_real("experiment", opt, v, 0, 1, LS_ARG_LO_OPEN, &a.init_edge);
        else if (strcmp(opt, "--cap") == 0) ok = ls_arg_real("experiment", opt, v, 1, 1000, LS_ARG_CLOSED, &a.cap);
        else if (strcmp(opt, "--step") == 0) ok = ls_arg_real("experiment", opt, v, 0, 10, LS_ARG_LO_OPEN, &a.step);
        else if (strcmp(opt, "--mean") == 0) {
            ok = strcmp(v, "keep") == 0 || strcmp(v, "project") == 0 || strcmp(v, "both") == 0;
            if (ok) a.means = strcmp(v, "keep") == 0 ? 1u : strcmp(v, "project") == 0 ? 2u : 3u;
            else fprintf(stderr, "largesteps experiment: --mean: '%s' is not keep, project or both\n", v);
        }
        else if (strcmp(opt, "--remesh") == 0) {
            ok = ls_job_parse_remesh(v, a.remesh_at, &a.remesh_count);
            if (!ok) fprintf(stderr, "largesteps experiment: --remesh: '%s' is not 'none' or increasing iterations I,J,... below 1000000\n", v);
        } else {
            ok = strcmp(v, "alpha") == 0 || strcmp(v, "lambda") == 0 || strcmp(v, "both") == 0;
            if (ok) a.forms = strcmp(v, "alpha") == 0 ? 1u : strcmp(v, "lambda") == 0 ? 2u : 3u;
            else fprintf(stderr, "largesteps experiment: --form: '%s' is not alpha, lambda or both\n", v);
        }
        if (!ok) return 2;
    }
    if (strcmp(a.name, "lambda-sweep") != 0 && strcmp(a.name, "compare") != 0 && strcmp(a.name, "silhouettes") != 0 &&
        strcmp(a.name, "views") != 0) {
        if (strcmp(a.name, "--help") == 0 || strcmp(a.name, "-h") == 0) return usage(stdout);
        fprintf(stderr, "largesteps experiment: unknown experiment '%s'\n", a.name);
        return usage(stderr);
    }
    if (a.out == NULL) return fprintf(stderr, "largesteps experiment: -o DIR is required\n"), usage(stderr);
    if (!ls_posix_check_output_dir(a.out)) return 2;
    work = (unsigned char *)malloc(work_bytes);
    if (work == NULL || ls_arena_init(&arena, work, work_bytes) != LS_OK) {
        free(work);
        return fprintf(stderr, "largesteps experiment: out of memory\n"), 1;
    }
    /* compare writes its contact sheet into DIR during the run */
    if (ls_posix_mkdir_p(a.out) != 0) {
        free(work);
        return fprintf(stderr, "largesteps experiment: cannot create %s: %s\n", a.out, strerror(errno)), 1;
    }
    /* the table is built in memory and written whole at the end (nothing is
     * left behind when a run fails or is interrupted) */
    f = open_memstream(&table, &table_bytes);
    if (f == NULL) {
        free(work);
        return fprintf(stderr, "largesteps experiment: out of memory\n"), 1;
    }
    rc = experiment_body(f, &a, &arena);
    if (fclose(f) != 0) rc = (fprintf(stderr, "largesteps experiment: out of memory\n"), 1);
    free(work);
    if (rc == 0) {
        table_buf tb;
        snprintf(md, sizeof md, "%s.md", a.name);
        tb.text = table;
        tb.bytes = table_bytes;
        if (!ls_posix_write_whole_in(a.out, md, write_table, &tb)) rc = 1;
        else if (fwrite(table, 1, table_bytes, stdout) != table_bytes) rc = 1;
    }
    free(table);
    return rc;
}

static int experiment_body(FILE *f, const exp_args *ap, ls_arena *arena_p)
{
    exp_args a = *ap;
    ls_arena arena = *arena_p;
    ls_job_options o;
    ls_job_problem p;
    int i;
    memset(&o, 0, sizeof o);
    o.target = a.target;
    o.views = a.views;
    o.width = o.height = a.res;
    o.target_ss = 4;
    o.shading = strcmp(a.name, "silhouettes") == 0 ? LS_SHADE_MASK : LS_SHADE_SH;
    o.level = a.level;
    o.init_edge = a.init_edge;
    o.init_smooth = a.init_smooth;
    fprintf(f, "# experiment %s: %s, %u x %u, ", a.name, a.target != NULL ? a.target : "embedded bunny", (unsigned)a.res,
            (unsigned)a.res);
    if (a.init_edge > 0)
        fprintf(f, "initial mesh the target remeshed to %g x its bounding-box diagonal and %u Taubin steps", a.init_edge,
                (unsigned)a.init_smooth);
    else
        fprintf(f, "initial icosphere level %u", (unsigned)a.level);
    for (i = 0; i < (int)a.remesh_count; i++)
        fprintf(f, i == 0 ? ", remeshing before iterations %u" : ", %u", (unsigned)a.remesh_at[i]);
    fprintf(f, "\n\n");
    if (strcmp(a.name, "views") == 0) {
        static const uint32_t counts[7] = {1, 2, 4, 9, 16, 25, 49};
        ls_fit_config c;
        int k;
        fprintf(f, "## large steps, lambda 19, lr 1e-2, %u iterations\n\n", (unsigned)a.iters);
        header(f);
        for (k = 0; k < 7; k++) {
            ls_arena_mark mark = ls_arena_save(&arena);
            exp_result e;
            char label[32];
            o.views = counts[k];
            if (!ls_job_load(&p, &o, &arena)) return 1;
            config(&c, LS_FIT_LARGE_STEPS, (ls_real)1e-2);
            e = run_one(&p, &c, a.iters, 0, NULL, 0, &arena, NULL);
            snprintf(label, sizeof label, "%u views", (unsigned)counts[k]);
            row(f, label, &e);
            fflush(f);
            ls_arena_restore(&arena, mark);
        }
    } else {
        if (!ls_job_load(&p, &o, &arena)) return 1;
        if (strcmp(a.name, "lambda-sweep") == 0 && (a.forms & 1u) != 0) sweep_alpha(f, &p, &a, &arena);
        if (strcmp(a.name, "lambda-sweep") == 0 && (a.forms & 2u) != 0) sweep_lambda(f, &p, &a, &arena);
        if (strcmp(a.name, "compare") == 0) compare(f, &p, &a, &arena);
        if (strcmp(a.name, "silhouettes") == 0) silhouettes(f, &p, &a, &arena);
    }
    if (ferror(f)) return fprintf(stderr, "largesteps experiment: out of memory for the table\n"), 1;
    return 0;
}
