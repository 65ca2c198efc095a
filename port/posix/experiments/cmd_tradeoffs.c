/* cmd_tradeoffs.c - `largesteps experiment tradeoffs [TARGET] -o DIR`: speed
 * against accuracy. Runs the reconstruction from one default configuration
 * (that of `largesteps fit`) and from variants that change one knob each,
 * and records per run: time per iteration by stage, total time, the arena's
 * peak, the final dense Hausdorff distance and RMS, self-intersections and,
 * where it applies (silhouette mode, supersampling), the error of the first
 * iteration's gradient against a reference (exact silhouettes at S = 4).
 *
 * Writes DIR/tradeoffs.md (a table per knob, ratios to the default run),
 * DIR/tradeoffs.svg (error against time for every run, the Pareto front
 * marked) and DIR/tradeoffs.tsv (the rows, for merging). The float build's
 * rows come from a second run of the float program with `--knobs precision
 * --rows-out F`, merged with `--rows-in F` (`make tradeoffs` does both).
 * Every file is written whole or not at all.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include "ls_posix.h"
#include "args.h"

#define TR_CMD "experiment tradeoffs"
#include "commands.h"
#include "fit_job.h"

#define TR_MAX_RUNS 256
#define TR_MAX_REMESH 8

typedef struct tr_setting {
    const char *knob, *value;
    ls_fit_config cfg;
    uint32_t res, views, iters;
    uint32_t remesh_count, remesh_at[TR_MAX_REMESH];
    int gradient; /* measure the gradient error */
    int is_default; /* the default configuration: its row is copied, not rerun */
} tr_setting;

typedef struct tr_row {
    char mesh[64], build[16], knob[32], value[48];
    int ok;
    uint32_t iterations, vertices, pairs;
    double total_ms, setup_ms, ms_render, ms_shade, ms_sil, ms_solve, ms_optim;
    double peak_mib, dense_h_rel, h_rel, rms_rel, grad_err;
} tr_row;

typedef struct tr_args {
    const char *target, *out, *rows_out, *knobs;
    const char *rows_in[4];
    uint32_t rows_in_count, iters, res, views, level;
} tr_args;

static int usage(FILE *f)
{
    fprintf(f, "usage: largesteps experiment tradeoffs [TARGET] -o DIR [options]\n"
               "  --iters N       iterations of the default run (8..1000000; default 400; remeshing at 1/4 and\n"
               "                  5/8 of them)\n"
               "  --res R         default render size R x R (8..4096; default 128)\n"
               "  --views N       default number of views (1..1024; default 16)\n"
               "  --level K       initial icosphere level (0..7; default 3)\n"
               "  --knobs LIST    comma-separated subset of: silhouette,supersampling,resolution,views,lambda,power,\n"
               "                  solver,remesh,optimizer (default all; 'none': the default run only, as the float\n"
               "                  build's precision row; 'merge': no run, tables from --rows-in only)\n"
               "  --rows-out F    also write this run's rows to F (TSV)\n"
               "  --rows-in F     merge rows written by another build (up to 4)\n" LS_ARGS_GLOBAL_HELP);
    return f == stderr ? 2 : 0;
}

static const char *build_name(void)
{
    return sizeof(ls_real) == sizeof(float) ? "float" : "double";
}

static int knob_wanted(const tr_args *a, const char *knob)
{
    const char *p = a->knobs;
    size_t n = strlen(knob);
    if (p == NULL) return 1;
    while (*p) {
        const char *e = strchr(p, ',');
        size_t len = e != NULL ? (size_t)(e - p) : strlen(p);
        if (len == n && strncmp(p, knob, n) == 0) return 1;
        if (e == NULL) break;
        p = e + 1;
    }
    return 0;
}

/* The first iteration's dL/dx (no step taken that matters: the fit is
 * dropped) into g [3 n]. */
static int first_gradient(const ls_job_problem *p, const ls_fit_config *cfg, ls_arena *arena, ls_real *g)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_fit_config c = *cfg;
    ls_fit_views fv;
    ls_fit fit;
    ls_diag d;
    ls_status st;
    ls_diag_clear(&d);
    c.width = p->width;
    c.height = p->height;
    c.shading = p->shading;
    fv.count = p->views;
    fv.mvp = p->mvps;
    fv.targets = (const ls_real *const *)p->targets;
    st = ls_fit_init(&fit, &c, &fv, &p->initial, arena, &d);
    if (st == LS_OK) st = ls_fit_step(&fit, NULL, &d);
    if (st == LS_OK) memcpy(g, fit.gx, 3u * (size_t)p->initial.vertex_count * sizeof(ls_real));
    ls_arena_restore(arena, mark);
    return st == LS_OK ? 1 : ls_job_fail("gradient", st, &d);
}

static double gradient_error(const ls_job_problem *p, const ls_fit_config *cfg, ls_arena *arena)
{
    ls_arena_mark mark = ls_arena_save(arena);
    size_t n3 = 3u * (size_t)p->initial.vertex_count, i;
    ls_real *g = (ls_real *)ls_arena_alloc(arena, n3, sizeof(ls_real));
    ls_real *ref = (ls_real *)ls_arena_alloc(arena, n3, sizeof(ls_real));
    ls_fit_config rc = *cfg;
    double num = 0, den = 0;
    int ok;
    rc.silhouette = LS_FIT_SILHOUETTE_EXACT;
    rc.ss = 4;
    ok = ref != NULL && first_gradient(p, cfg, arena, g) && first_gradient(p, &rc, arena, ref);
    if (ok)
        for (i = 0; i < n3; i++) {
            double e = (double)g[i] - (double)ref[i];
            num += e * e;
            den += (double)ref[i] * (double)ref[i];
        }
    ls_arena_restore(arena, mark);
    return ok && den > 0 ? sqrt(num / den) : -1.0;
}

static void run_setting(const tr_setting *s, const ls_job_options *base, const char *mesh_name, ls_arena *arena,
                        tr_row *row)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_job_options o = *base;
    ls_job_problem p;
    ls_job_run r;
    ls_distance_report dist;
    ls_tangle_report tangle;
    ls_fit_config c = s->cfg;
    ls_job_schedule sched;
    uint32_t k;
    size_t used;
    memset(row, 0, sizeof *row);
    snprintf(row->mesh, sizeof row->mesh, "%s", mesh_name);
    snprintf(row->build, sizeof row->build, "%s", build_name());
    snprintf(row->knob, sizeof row->knob, "%s", s->knob);
    snprintf(row->value, sizeof row->value, "%s", s->value);
    row->grad_err = -1;
    o.width = o.height = s->res;
    o.views = s->views;
    if (!ls_job_load(&p, &o, arena)) return;
    if (s->gradient) row->grad_err = gradient_error(&p, &c, arena);
    if (s->iters == 0) {
        ls_arena_restore(arena, mark);
        return;
    }
    used = ls_arena_used(arena);
    ls_arena_reset_peak(arena);
    ls_job_schedule_default(&sched);
    sched.guard_every = 0; /* the paper's plain loop: these runs reproduce its experiments */
    sched.iterations = s->iters;
    sched.remesh_count = s->remesh_count < LS_JOB_MAX_REMESH ? s->remesh_count : LS_JOB_MAX_REMESH;
    for (k = 0; k < sched.remesh_count; k++) sched.remesh_at[k] = s->remesh_at[k];
    if (ls_job_fit(&p, &c, &sched, 0, 0, NULL, arena, &r)) {
        double it = r.iterations > 0 ? (double)r.iterations : 1.0;
        row->peak_mib = (double)(arena->peak - used) / 1048576.0;
        row->iterations = r.iterations;
        row->total_ms = r.total_ms;
        row->setup_ms = r.setup_ms;
        row->ms_render = (double)r.timing.render_ns / 1e6 / it;
        row->ms_shade = (double)r.timing.shade_backward_ns / 1e6 / it;
        row->ms_sil = (double)r.timing.silhouette_ns / 1e6 / it;
        row->ms_solve = (double)r.timing.solve_ns / 1e6 / it;
        row->ms_optim = (double)r.timing.optimizer_ns / 1e6 / it;
        row->vertices = r.result.vertex_count;
        if (ls_job_metrics(&p, &r.result, arena, &dist, &tangle)) {
            row->ok = 1;
            row->dense_h_rel = (double)dist.hausdorff_rel;
            row->h_rel = (double)dist.vertex_hausdorff_rel;
            row->rms_rel = (double)dist.rms_rel;
            row->pairs = tangle.intersecting_pairs;
        }
    }
    ls_arena_restore(arena, mark);
}

static void default_setting(tr_setting *s, const tr_args *a)
{
    memset(s, 0, sizeof *s);
    s->knob = "default";
    s->value = "default";
    ls_fit_config_default(&s->cfg);
    s->cfg.form = LS_SYSTEM_ALPHA; /* as largesteps fit: the paper's alpha form */
    s->cfg.weight = (ls_real)0.95;
    s->res = a->res;
    s->views = a->views;
    s->iters = a->iters;
    s->remesh_count = 2;
    s->remesh_at[0] = a->iters / 4u;       /* 200 of 800, as largesteps fit */
    s->remesh_at[1] = a->iters * 5u / 8u;  /* 500 of 800 */
}

/* The variants of one knob, each the default with one change; returns how
 * many were written to out[]. */
static uint32_t variants(const char *knob, const tr_args *a, tr_setting *out)
{
    static const char *const sil_names[3] = {"exact", "pair", "none"};
    static const char *const ss_names[3] = {"S = 1", "S = 2", "S = 4"};
    static const char *const res_names[3] = {"64^2", "128^2", "256^2"};
    static const char *const view_names[4] = {"1", "4", "16", "25"};
    static const char *const lambda_names[7] = {"alpha 0.5 (lambda 1)",   "alpha 0.75 (lambda 3)",
                                                "alpha 0.9 (lambda 9)",    "alpha 0.95 (lambda 19)",
                                                "alpha 0.98 (lambda 49)",  "alpha 0.99 (lambda 99)",
                                                "alpha 0.999 (lambda 999)"};
    static const double alphas[7] = {0.5, 0.75, 0.9, 0.95, 0.98, 0.99, 0.999};
    static const char *const solver_names[5] = {"LDL^T", "CG 1e-3", "CG 1e-4", "CG 1e-6", "CG 1e-8"};
    static const double tols[5] = {0, 1e-3, 1e-4, 1e-6, 1e-8};
    static const char *const remesh_names[4] = {"none", "at 0", "at k = iters/4", "multiscale (iters/4, 5/8)"};
    tr_setting d;
    uint32_t i, n = 0;
    default_setting(&d, a);
    d.knob = knob;
    if (strcmp(knob, "silhouette") == 0) {
        for (i = 0; i < 3; i++, n++) {
            out[n] = d;
            out[n].value = sil_names[i];
            out[n].cfg.silhouette = i;
            out[n].gradient = 1;
            out[n].is_default = i == LS_FIT_SILHOUETTE_EXACT;
        }
    } else if (strcmp(knob, "supersampling") == 0) {
        for (i = 0; i < 3; i++, n++) {
            out[n] = d;
            out[n].value = ss_names[i];
            out[n].cfg.ss = 1u << i;
            out[n].gradient = 1;
            out[n].is_default = i == 0;
        }
    } else if (strcmp(knob, "resolution") == 0) {
        for (i = 0; i < 3; i++, n++) {
            out[n] = d;
            out[n].value = res_names[i];
            out[n].res = 64u << i;
            out[n].is_default = out[n].res == a->res;
        }
    } else if (strcmp(knob, "views") == 0) {
        static const uint32_t counts[4] = {1, 4, 16, 25};
        for (i = 0; i < 4; i++, n++) {
            out[n] = d;
            out[n].value = view_names[i];
            out[n].views = counts[i];
            out[n].is_default = counts[i] == a->views;
        }
    } else if (strcmp(knob, "lambda") == 0) {
        for (i = 0; i < 7; i++, n++) {
            out[n] = d;
            out[n].value = lambda_names[i];
            out[n].cfg.weight = (ls_real)alphas[i];
            out[n].is_default = i == 3;
        }
    } else if (strcmp(knob, "power") == 0) {
        for (i = 1; i <= 2; i++, n++) {
            out[n] = d;
            out[n].value = i == 1 ? "p = 1 (Adam-uniform on x, M^-1 g)" : "p = 2 (on u = M x, the method)";
            out[n].cfg.power = i;
            out[n].is_default = i == 2;
        }
    } else if (strcmp(knob, "solver") == 0) {
        for (i = 0; i < 5; i++, n++) {
            out[n] = d;
            out[n].value = solver_names[i];
            out[n].cfg.solver = i == 0 ? LS_PARAM_LDLT : LS_PARAM_CG;
            out[n].cfg.cg_tol = (ls_real)tols[i];
            out[n].is_default = i == 0;
        }
    } else if (strcmp(knob, "remesh") == 0) {
        for (i = 0; i < 4; i++, n++) {
            out[n] = d;
            out[n].value = remesh_names[i];
            out[n].remesh_count = i == 0 ? 0u : i == 3 ? 2u : 1u;
            out[n].remesh_at[0] = i == 1 ? 0u : a->iters / 4u;
            out[n].is_default = i == 3;
        }
    } else if (strcmp(knob, "optimizer") == 0) {
        for (i = 0; i < 2; i++, n++) {
            out[n] = d;
            out[n].value = i == 0 ? "UniformAdam (the method)" : "Adam on u";
            out[n].is_default = i == 0;
            if (i == 1) {
                ls_real lr = d.cfg.optim.lr;
                (void)ls_optim_config_default(LS_OPTIM_ADAM, &out[n].cfg.optim);
                out[n].cfg.optim.lr = lr;
            }
        }
    }
    return n;
}

/* "precision" has no variants: its table is the default run of each build. */
static const char *const knob_names[10] = {"precision", "silhouette", "supersampling", "resolution", "views",
                                           "lambda", "power", "solver", "remesh", "optimizer"};

static void tsv_write(FILE *f, const tr_row *r)
{
    fprintf(f, "%s\t%s\t%s\t%s\t%d\t%u\t%u\t%u\t%.3f\t%.3f\t%.4f\t%.4f\t%.4f\t%.4f\t%.4f\t%.3f\t%.6g\t%.6g\t%.6g\t%.6g\n",
            r->mesh, r->build, r->knob, r->value, r->ok, (unsigned)r->iterations, (unsigned)r->vertices,
            (unsigned)r->pairs, r->total_ms, r->setup_ms, r->ms_render, r->ms_shade, r->ms_sil, r->ms_solve,
            r->ms_optim, r->peak_mib, r->dense_h_rel, r->h_rel, r->rms_rel, r->grad_err);
}

/* Copies the tab-separated field `k` of line into buf. */
static void tsv_field(const char *line, int k, char *buf, size_t cap)
{
    const char *p = line;
    size_t n = 0;
    while (k-- > 0 && p != NULL) {
        p = strchr(p, '\t');
        if (p != NULL) p++;
    }
    if (p != NULL)
        while (p[n] != '\0' && p[n] != '\t' && p[n] != '\n' && n + 1 < cap) n++;
    if (p != NULL) memcpy(buf, p, n);
    buf[n] = '\0';
}

static double tsv_num(const char *line, int k)
{
    char b[64];
    tsv_field(line, k, b, sizeof b);
    return strtod(b, NULL);
}

static uint32_t tsv_read(const char *path, tr_row *rows, uint32_t cap)
{
    unsigned char *text = NULL;
    size_t bytes = 0;
    uint32_t n = 0;
    char *line, *save = NULL;
    if (ls_posix_read_file(path, &text, &bytes) != LS_OK) {
        fprintf(stderr, "largesteps experiment tradeoffs: cannot read %s: %s\n", path, ls_posix_read_error());
        return 0;
    }
    text = (unsigned char *)realloc(text, bytes + 1u);
    if (text == NULL) return 0;
    text[bytes] = 0;
    for (line = strtok_r((char *)text, "\n", &save); line != NULL && n < cap; line = strtok_r(NULL, "\n", &save)) {
        tr_row *r = &rows[n++];
        memset(r, 0, sizeof *r);
        tsv_field(line, 0, r->mesh, sizeof r->mesh);
        tsv_field(line, 1, r->build, sizeof r->build);
        tsv_field(line, 2, r->knob, sizeof r->knob);
        tsv_field(line, 3, r->value, sizeof r->value);
        r->ok = (int)tsv_num(line, 4);
        r->iterations = (uint32_t)tsv_num(line, 5);
        r->vertices = (uint32_t)tsv_num(line, 6);
        r->pairs = (uint32_t)tsv_num(line, 7);
        r->total_ms = tsv_num(line, 8);
        r->setup_ms = tsv_num(line, 9);
        r->ms_render = tsv_num(line, 10);
        r->ms_shade = tsv_num(line, 11);
        r->ms_sil = tsv_num(line, 12);
        r->ms_solve = tsv_num(line, 13);
        r->ms_optim = tsv_num(line, 14);
        r->peak_mib = tsv_num(line, 15);
        r->dense_h_rel = tsv_num(line, 16);
        r->h_rel = tsv_num(line, 17);
        r->rms_rel = tsv_num(line, 18);
        r->grad_err = tsv_num(line, 19);
    }
    free(text);
    return n;
}

/* The default run of the same mesh and build (build NULL: any, double first). */
static const tr_row *default_row(const tr_row *rows, uint32_t n, const char *mesh, const char *build)
{
    uint32_t i;
    const tr_row *any = NULL;
    for (i = 0; i < n; i++)
        if (strcmp(rows[i].knob, "default") == 0 && strcmp(rows[i].mesh, mesh) == 0) {
            if (build == NULL && strcmp(rows[i].build, "double") == 0) return &rows[i];
            if (build != NULL && strcmp(rows[i].build, build) == 0) return &rows[i];
            if (any == NULL) any = &rows[i];
        }
    return build == NULL ? any : NULL;
}

/* Rows of a table: the knob's, or for "precision" the default runs. */
static int in_table(const tr_row *r, const char *knob)
{
    return strcmp(knob, "precision") == 0 ? strcmp(r->knob, "default") == 0 : strcmp(r->knob, knob) == 0;
}

static void md_table(FILE *f, const tr_row *rows, uint32_t n, const char *knob)
{
    uint32_t i;
    int any = 0, grad = 0;
    for (i = 0; i < n; i++)
        if (in_table(&rows[i], knob)) any = 1, grad |= rows[i].grad_err >= 0;
    if (!any) return;
    fprintf(f, "\n## %s\n\n", knob);
    fprintf(f, "| mesh | %s | ms/it | render | shading bwd | silhouette | solve | optimizer | total s | time ratio | "
               "peak MiB | vertices | dense H rel %% | H ratio | RMS rel %% | self-int.%s |\n",
            knob, grad ? " | gradient error" : "");
    fprintf(f, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|%s\n", grad ? "---|" : "");
    for (i = 0; i < n; i++) {
        const tr_row *r = &rows[i];
        const tr_row *d = default_row(rows, n, r->mesh, strcmp(knob, "precision") == 0 ? NULL : r->build);
        double it = r->iterations > 0 ? (double)r->iterations : 1.0;
        if (!in_table(r, knob)) continue;
        if (!r->ok) {
            fprintf(f, "| %s | %s | failed |||||||||||||%s\n", r->mesh, r->value, grad ? "|" : "");
            continue;
        }
        fprintf(f, "| %s | %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f | %.1f | %.2f | %.1f | %u | %.3f | %.2f | %.3f | %u",
                r->mesh, strcmp(knob, "precision") == 0 ? r->build : r->value, r->total_ms / it, r->ms_render, r->ms_shade,
                r->ms_sil, r->ms_solve, r->ms_optim, r->total_ms / 1000.0,
                d != NULL && d->total_ms > 0 ? r->total_ms / d->total_ms : 0.0, r->peak_mib, (unsigned)r->vertices,
                100.0 * r->dense_h_rel, d != NULL && d->dense_h_rel > 0 ? r->dense_h_rel / d->dense_h_rel : 0.0,
                100.0 * r->rms_rel, (unsigned)r->pairs);
        if (grad && r->grad_err >= 0) fprintf(f, " | %.3f", r->grad_err);
        else if (grad) fprintf(f, " | ");
        fprintf(f, " |\n");
    }
}

/* The plot's log scale. */
static double lg(double x) { return log10(x); }

static void svg_plot(FILE *f, const tr_row *rows, uint32_t n)
{
    static const char *const colours[10] = {"#555555", "#d62728", "#1f77b4", "#2ca02c", "#9467bd",
                                            "#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#bcbd22"};
    const double w = 900, h = 560, l = 80, r = 220, t = 40, b = 60;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    uint32_t i, j, k;
    int *front = (int *)calloc(n > 0 ? n : 1, sizeof(int));
    if (front == NULL) return;
    for (i = 0; i < n; i++) {
        if (!rows[i].ok || rows[i].total_ms <= 0 || rows[i].dense_h_rel <= 0) continue;
        if (lg(rows[i].total_ms / 1000.0) < x0) x0 = lg(rows[i].total_ms / 1000.0);
        if (lg(rows[i].total_ms / 1000.0) > x1) x1 = lg(rows[i].total_ms / 1000.0);
        if (lg(100.0 * rows[i].dense_h_rel) < y0) y0 = lg(100.0 * rows[i].dense_h_rel);
        if (lg(100.0 * rows[i].dense_h_rel) > y1) y1 = lg(100.0 * rows[i].dense_h_rel);
    }
    if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    x0 = floor(x0 * 4) / 4, x1 = ceil(x1 * 4) / 4 + 1e-9, y0 = floor(y0 * 4) / 4, y1 = ceil(y1 * 4) / 4 + 1e-9;
    /* the Pareto front per mesh: no run of that mesh is both faster and more accurate */
    for (i = 0; i < n; i++) {
        int dominated = 0;
        if (!rows[i].ok) continue;
        for (j = 0; j < n && !dominated; j++)
            dominated = j != i && rows[j].ok && strcmp(rows[j].mesh, rows[i].mesh) == 0 &&
                        rows[j].total_ms <= rows[i].total_ms && rows[j].dense_h_rel <= rows[i].dense_h_rel &&
                        (rows[j].total_ms < rows[i].total_ms || rows[j].dense_h_rel < rows[i].dense_h_rel);
        front[i] = !dominated;
    }
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" "
               "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n", w, h);
    fprintf(f, "<text x=\"%.0f\" y=\"24\" font-size=\"15\">largesteps: error against time, every run of the "
               "trade study (Pareto front circled)</text>\n", l);
    for (k = 0; k <= 1; k++) {
        double lo = k == 0 ? x0 : y0, hi = k == 0 ? x1 : y1, v;
        for (v = ceil(lo - 1e-9); v <= hi + 1e-9; v += 1) {
            double tick = pow(10.0, v);
            if (k == 0) {
                double px = l + (v - x0) / (x1 - x0) * (w - l - r);
                fprintf(f, "<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#ddd\"/>"
                           "<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%g</text>\n",
                        px, t, px, h - b, px, h - b + 16, tick);
            } else {
                double py = h - b - (v - y0) / (y1 - y0) * (h - t - b);
                fprintf(f, "<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                           "<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n",
                        l, py, w - r, py, l - 6, py + 4, tick);
            }
        }
    }
    fprintf(f, "<rect x=\"%.0f\" y=\"%.0f\" width=\"%.0f\" height=\"%.0f\" fill=\"none\" stroke=\"black\"/>\n", l, t,
            w - l - r, h - t - b);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">total time, s (log)</text>\n", l + (w - l - r) / 2,
            h - 20);
    fprintf(f, "<text transform=\"translate(22 %.0f) rotate(-90)\" text-anchor=\"middle\">dense Hausdorff / bounding-box "
               "diagonal, %% (log)</text>\n", t + (h - t - b) / 2);
    for (i = 0; i < n; i++) {
        const tr_row *q = &rows[i];
        double px, py;
        const char *col = colours[0];
        int shape = strcmp(q->mesh, rows[0].mesh) == 0;
        if (!q->ok || q->total_ms <= 0 || q->dense_h_rel <= 0) continue;
        for (k = 0; k < 10; k++)
            if (strcmp(q->knob, knob_names[k]) == 0) col = colours[k];
        px = l + (lg(q->total_ms / 1000.0) - x0) / (x1 - x0) * (w - l - r);
        py = h - b - (lg(100.0 * q->dense_h_rel) - y0) / (y1 - y0) * (h - t - b);
        if (shape)
            fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"><title>%s %s %s: %s</title></circle>\n", px,
                    py, col, q->mesh, q->build, q->knob, q->value);
        else
            fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"7\" height=\"7\" fill=\"%s\"><title>%s %s %s: %s</title></rect>\n",
                    px - 3.5, py - 3.5, col, q->mesh, q->build, q->knob, q->value);
        if (front[i])
            fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"8\" fill=\"none\" stroke=\"black\"/>"
                       "<text x=\"%.1f\" y=\"%.1f\" font-size=\"10\">%s</text>\n",
                    px, py, px + 10, py - 6, strcmp(q->knob, "default") == 0 ? q->build : q->value);
    }
    for (k = 0; k < 10; k++)
        fprintf(f, "<circle cx=\"%.0f\" cy=\"%.0f\" r=\"4\" fill=\"%s\"/><text x=\"%.0f\" y=\"%.0f\">%s</text>\n",
                w - r + 20, t + 14 + 18.0 * k, colours[k], w - r + 30, t + 18 + 18.0 * k,
                k == 0 ? "default / precision" : knob_names[k]);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\">circles: %s</text>\n", w - r + 20, t + 14 + 18.0 * 11, rows[0].mesh);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\">squares: other mesh</text>\n", w - r + 20, t + 14 + 18.0 * 12);
    fprintf(f, "</svg>\n");
    free(front);
}

/* The output files' bodies, for ls_posix_write_whole: rows [from, n) as
 * TSV, the tables, the plot. */
typedef struct tr_out {
    const tr_args *a;
    const tr_row *rows;
    uint32_t from, n;
} tr_out;

static int write_tsv(FILE *f, void *ctx)
{
    const tr_out *o = (const tr_out *)ctx;
    uint32_t i;
    for (i = o->from; i < o->n; i++) tsv_write(f, &o->rows[i]);
    return 1;
}

static int write_md(FILE *f, void *ctx)
{
    const tr_out *o = (const tr_out *)ctx;
    const tr_args *a = o->a;
    uint32_t k;
    fprintf(f, "# Speed against accuracy\n\nEach table varies one knob from the default configuration (`largesteps fit`'s: "
               "alpha 0.95 (M = 0.05 I + 0.95 L), UniformAdam with lr 0.01 x the target's radius, LDL^T, exact silhouettes, S = 1, %u x %u, %u views, %u iterations, remeshing "
               "before iterations %u and %u, initial icosphere level %u). Times are per iteration (ms) by stage and in "
               "total (s); ratios are to the default run of the same mesh in the same table set. H is the dense "
               "(area-sampled) symmetric Hausdorff distance over the target's bounding-box diagonal. The gradient error "
               "is ||g - g_ref|| / ||g_ref|| of the first iteration's dL/dx, g_ref with exact silhouettes at S = 4.\n",
            (unsigned)a->res, (unsigned)a->res, (unsigned)a->views, (unsigned)a->iters, (unsigned)(a->iters / 4u),
            (unsigned)(a->iters * 5u / 8u), (unsigned)a->level);
    md_table(f, o->rows, o->n, "default");
    for (k = 0; k < 10; k++) md_table(f, o->rows, o->n, knob_names[k]);
    return 1;
}

static int write_svg(FILE *f, void *ctx)
{
    const tr_out *o = (const tr_out *)ctx;
    svg_plot(f, o->rows, o->n);
    return 1;
}

static int parse_args(int argc, char **argv, tr_args *a)
{
    int i;
    memset(a, 0, sizeof *a);
    a->iters = 400;
    a->res = 128;
    a->views = 16;
    a->level = 3;
    for (i = 1; i < argc; i++) {
        const char *opt = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0) return usage(stdout), -1;
        if (opt[0] != '-') {
            if (a->target != NULL) return fprintf(stderr, "largesteps " TR_CMD ": more than one target ('%s')\n", opt), 0;
            a->target = opt;
            continue;
        }
        if (strcmp(opt, "-o") != 0 && strcmp(opt, "--iters") != 0 && strcmp(opt, "--res") != 0 &&
            strcmp(opt, "--views") != 0 && strcmp(opt, "--level") != 0 && strcmp(opt, "--knobs") != 0 &&
            strcmp(opt, "--rows-out") != 0 && strcmp(opt, "--rows-in") != 0)
            return fprintf(stderr, "largesteps " TR_CMD ": unknown option '%s'\n", opt), 0;
        if (v == NULL) return fprintf(stderr, "largesteps " TR_CMD ": %s needs a value\n", opt), 0;
        i++;
        if (strcmp(opt, "-o") == 0) a->out = v;
        else if (strcmp(opt, "--iters") == 0) ok = ls_arg_u32(TR_CMD, opt, v, 8, 1000000, &a->iters);
        else if (strcmp(opt, "--res") == 0) ok = ls_arg_u32(TR_CMD, opt, v, 8, 4096, &a->res);
        else if (strcmp(opt, "--views") == 0) ok = ls_arg_u32(TR_CMD, opt, v, 1, 1024, &a->views);
        else if (strcmp(opt, "--level") == 0) ok = ls_arg_u32(TR_CMD, opt, v, 0, 7, &a->level);
        else if (strcmp(opt, "--knobs") == 0) a->knobs = v;
        else if (strcmp(opt, "--rows-out") == 0) a->rows_out = v;
        else if (a->rows_in_count < 4) a->rows_in[a->rows_in_count++] = v;
        else ok = 0, fprintf(stderr, "largesteps " TR_CMD ": --rows-in: at most 4 files\n");
        if (!ok) return 0;
    }
    if (a->out == NULL) return fprintf(stderr, "largesteps " TR_CMD ": -o DIR is required\n"), 0;
    if (!ls_posix_check_output_dir(a->out)) return 0;
    if (a->rows_out != NULL && !ls_posix_check_output(a->rows_out)) return 0;
    return 1;
}

int ls_cmd_tradeoffs(int argc, char **argv)
{
    tr_args a;
    ls_job_options o;
    tr_row *rows;
    tr_setting s[8];
    uint32_t nrows = 0, k, i, own_start;
    size_t work_bytes = sizeof(size_t) > 4u ? (size_t)3 << 30 : (size_t)1 << 30; /* 1 GiB on 32-bit hosts */
    unsigned char *work;
    ls_arena arena;
    const char *mesh_name;
    tr_out out;
    int pa = parse_args(argc, argv, &a);
    if (pa < 0) return 0;
    if (pa == 0) return usage(stderr);
    rows = (tr_row *)calloc(TR_MAX_RUNS, sizeof *rows);
    work = (unsigned char *)malloc(work_bytes);
    if (rows == NULL || work == NULL || ls_arena_init(&arena, work, work_bytes) != LS_OK)
        return fprintf(stderr, "out of memory\n"), 1;
    if (ls_posix_mkdir_p(a.out) != 0) return fprintf(stderr, "largesteps experiment: cannot create %s\n", a.out), 1;
    for (k = 0; k < a.rows_in_count; k++) nrows += tsv_read(a.rows_in[k], rows + nrows, TR_MAX_RUNS - nrows);
    own_start = nrows;
    mesh_name = a.target != NULL ? a.target : "bunny";
    if (strrchr(mesh_name, '/') != NULL) mesh_name = strrchr(mesh_name, '/') + 1;
    memset(&o, 0, sizeof o);
    o.target = a.target;
    o.target_ss = 4;
    o.shading = LS_SHADE_SH;
    o.level = a.level;
    /* the default first: every ratio refers to it */
    default_setting(&s[0], &a);
    if (a.knobs == NULL || strcmp(a.knobs, "merge") != 0) {
        const tr_row *d = &rows[nrows];
        double grad_err = -1;
        fprintf(stderr, "tradeoffs: %s default ...\n", mesh_name);
        run_setting(&s[0], &o, mesh_name, &arena, &rows[nrows++]);
        for (k = 1; k < 10; k++) {
            uint32_t count;
            if (!knob_wanted(&a, knob_names[k])) continue;
            count = variants(knob_names[k], &a, s);
            for (i = 0; i < count && nrows < TR_MAX_RUNS; i++) {
                tr_row *r = &rows[nrows++];
                fprintf(stderr, "tradeoffs: %s %s: %s ...\n", mesh_name, s[i].knob, s[i].value);
                if (!s[i].is_default) {
                    run_setting(&s[i], &o, mesh_name, &arena, r);
                    continue;
                }
                /* the default again: its row, with the gradient error measured once */
                *r = *d;
                snprintf(r->knob, sizeof r->knob, "%s", s[i].knob);
                snprintf(r->value, sizeof r->value, "%s (default)", s[i].value);
                if (s[i].gradient && grad_err < 0) {
                    tr_row g;
                    tr_setting only = s[i];
                    only.iters = 0; /* the gradient only */
                    run_setting(&only, &o, mesh_name, &arena, &g);
                    grad_err = g.grad_err;
                }
                r->grad_err = s[i].gradient ? grad_err : -1;
            }
        }
    }
    out.a = &a;
    out.rows = rows;
    out.n = nrows;
    out.from = own_start;
    if (a.rows_out != NULL && !ls_posix_write_whole(a.rows_out, write_tsv, &out))
        return fprintf(stderr, "largesteps: cannot write %s\n", a.rows_out), 1;
    out.from = 0;
    if (!ls_posix_write_whole_in(a.out, "tradeoffs.tsv", write_tsv, &out) ||
        !ls_posix_write_whole_in(a.out, "tradeoffs.md", write_md, &out) ||
        !ls_posix_write_whole_in(a.out, "tradeoffs.svg", write_svg, &out))
        return fprintf(stderr, "largesteps: cannot write into %s\n", a.out), 1;
    (void)ls_posix_print_file_in(a.out, "tradeoffs.md");
    free(work);
    free(rows);
    return 0;
}
