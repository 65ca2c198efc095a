/* cmd_toy1d.c - `largesteps toy1d [-o DIR] [--iters N]`: the 1D toy problem
 * (largesteps/toy1d.h). Prints, per iteration, every method's largest
 * interior error |x_i - t_i| (0 < i < 31), marked '*' while the points are
 * inverted (some x_{i+1} < x_i); then a summary per method; and writes one
 * SVG per method, DIR/toy1d-METHOD.svg: the 32 point positions (vertical)
 * over the iterations (horizontal), the targets dashed, the iterations with
 * an inversion shaded red. Files are written whole (temporary name, then
 * rename) or not at all. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <errno.h>
#include <largesteps.h>
#include "commands.h"
#include "ls_posix.h"
#include "args.h"

#define N LS_TOY1D_N

static int inverted(const ls_real *x)
{
    uint32_t i;
    for (i = 0; i + 1u < N; i++)
        if (x[i + 1u] < x[i]) return 1;
    return 0;
}

static double interior_error(const ls_real *x, const ls_real *t)
{
    double e = 0;
    uint32_t i;
    for (i = 1; i + 1u < N; i++) {
        double d = fabs((double)x[i] - (double)t[i]);
        if (d > e) e = d;
    }
    return e;
}

typedef struct svg_plot {
    const ls_toy1d_method *m;
    const ls_real *traj, *target;
    uint32_t iters;
} svg_plot;

static int svg_body(FILE *f, void *ctx)
{
    const svg_plot *p = (const svg_plot *)ctx;
    const ls_toy1d_method *m = p->m;
    const ls_real *traj = p->traj, *target = p->target;
    const uint32_t iters = p->iters;
    const double w = 720, h = 420, left = 50, right = 20, top = 30, bottom = 40;
    double sx = (w - left - right) / (iters > 0 ? (double)iters : 1.0), sy = (h - top - bottom) / 2.2;
    uint32_t it, i;
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\">\n", w, h, w, h);
    fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    for (it = 0; it <= iters; it++) { /* inverted iterations */
        if (!inverted(traj + (size_t)it * N)) continue;
        fprintf(f, "<rect x=\"%.2f\" y=\"%.0f\" width=\"%.2f\" height=\"%.0f\" fill=\"#fdd\"/>\n",
                left + ((double)it - 0.5) * sx, top, sx, h - top - bottom);
    }
    for (i = 0; i < N; i++) { /* targets */
        double y = top + (1.1 - (double)target[i]) * sy;
        fprintf(f, "<line x1=\"%.0f\" y1=\"%.2f\" x2=\"%.0f\" y2=\"%.2f\" stroke=\"#bbb\" stroke-width=\"0.5\" stroke-dasharray=\"3,3\"/>\n",
                left, y, w - right, y);
    }
    for (i = 0; i < N; i++) { /* trajectories */
        const char *colour = (i == 0 || i + 1u == N) ? "#c00" : "#236";
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1\" points=\"", colour);
        for (it = 0; it <= iters; it++)
            fprintf(f, "%.2f,%.2f ", left + (double)it * sx, top + (1.1 - (double)traj[(size_t)it * N + i]) * sy);
        fprintf(f, "\"/>\n");
    }
    fprintf(f, "<line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"black\"/>\n", left, h - bottom, w - right, h - bottom);
    fprintf(f, "<line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"black\"/>\n", left, top, left, h - bottom);
    fprintf(f, "<text x=\"%.0f\" y=\"20\" font-family=\"sans-serif\" font-size=\"14\">%s: step %g, %s %g, power %u</text>\n",
            left, m->name, (double)m->step, m->kind == LS_TOY1D_REG ? "w" : "lambda", (double)m->lambda, m->power);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" font-family=\"sans-serif\" font-size=\"12\">iteration 0 .. %u</text>\n",
            left, h - 12, iters);
    fprintf(f, "<text x=\"4\" y=\"%.2f\" font-family=\"sans-serif\" font-size=\"12\">1</text>\n", top + 0.1 * sy + 4);
    fprintf(f, "<text x=\"4\" y=\"%.2f\" font-family=\"sans-serif\" font-size=\"12\">-1</text>\n", top + 2.1 * sy + 4);
    fprintf(f, "</svg>\n");
    return !ferror(f);
}

static int write_svg(ls_posix_outset *set, const ls_toy1d_method *m, const ls_real *traj, uint32_t iters,
                     const ls_real *target)
{
    char name[256];
    svg_plot p;
    if ((size_t)snprintf(name, sizeof name, "toy1d-%s.svg", m->name) >= sizeof name) return 0;
    p.m = m;
    p.traj = traj;
    p.target = target;
    p.iters = iters;
    return ls_posix_outset_add(set, name, svg_body, &p);
}

static int toy1d_usage(FILE *f)
{
    fprintf(f, "usage: largesteps toy1d [-o DIR] [--iters N]\n"
               "  the 1D toy of large steps: a table of errors per iteration and one SVG plot per method\n"
               "  -o DIR      output directory for toy1d-METHOD.svg (default: the current directory)\n"
               "  --iters N   iterations (1..100000; default 100)\n" LS_ARGS_GLOBAL_HELP);
    return f == stderr ? 2 : 0;
}

int ls_cmd_toy1d(int argc, char **argv)
{
    const char *dir = ".";
    uint32_t iters = 100, it, k;
    int a, status = 0;
    ls_real *traj[LS_TOY1D_METHODS], target[N];
    ls_toy1d_method m[LS_TOY1D_METHODS];
    void *mem;
    size_t mem_bytes = 64u * 1024u;
    ls_arena arena;
    ls_posix_outset *set;
    for (a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--help") == 0 || strcmp(argv[a], "-h") == 0) return toy1d_usage(stdout);
        if (strcmp(argv[a], "-o") == 0 && a + 1 < argc) {
            dir = argv[++a];
        } else if (strcmp(argv[a], "--iters") == 0 && a + 1 < argc) {
            if (!ls_arg_u32("toy1d", "--iters", argv[++a], 1, 100000, &iters)) return 2;
        } else {
            fprintf(stderr, "largesteps toy1d: %s '%s'\n",
                    strcmp(argv[a], "-o") == 0 || strcmp(argv[a], "--iters") == 0 ? "a value is missing after" : "unknown argument", argv[a]);
            return toy1d_usage(stderr);
        }
    }
    if (!ls_posix_check_output_dir(dir)) return 2;
    mem = malloc(mem_bytes);
    if (mem == NULL || ls_arena_init(&arena, mem, mem_bytes) != LS_OK) {
        free(mem);
        fprintf(stderr, "largesteps toy1d: out of memory\n");
        return 1;
    }
    ls_toy1d_points(NULL, target);
    for (k = 0; k < LS_TOY1D_METHODS; k++) {
        ls_status st;
        traj[k] = (ls_real *)malloc(((size_t)iters + 1u) * N * sizeof(ls_real));
        (void)ls_toy1d_method_get(k, &m[k]);
        st = traj[k] == NULL ? LS_ERR_NOMEM : ls_toy1d_run(k, iters, traj[k], &arena);
        if (st != LS_OK) {
            fprintf(stderr, "largesteps toy1d: %s: %s\n", m[k].name, ls_status_str(st));
            for (; k + 1u > 0; k--) free(traj[k]);
            free(mem);
            return 1;
        }
    }
    printf("largest interior error |x_i - t_i| per method; '*' = inverted (some x[i+1] < x[i])\n%5s", "it");
    for (k = 0; k < LS_TOY1D_METHODS; k++) printf(" %13s", m[k].name);
    printf("\n");
    for (it = 0; it <= iters; it++) {
        printf("%5u", it);
        for (k = 0; k < LS_TOY1D_METHODS; k++) {
            const ls_real *x = traj[k] + (size_t)it * N;
            printf(" %12.6f%c", interior_error(x, target), inverted(x) ? '*' : ' ');
        }
        printf("\n");
    }
    printf("\n%-14s %6s %7s %6s %10s %10s %10s  %s\n", "method", "step", "lambda", "power", "first_inv", "end_err",
           "interior", "svg");
    if (ls_posix_mkdir_p(dir) != 0) {
        fprintf(stderr, "largesteps toy1d: cannot create %s: %s\n", dir, strerror(errno));
        status = 1;
    }
    set = status == 0 ? ls_posix_outset_begin(dir) : NULL; /* the plots appear together or not at all */
    for (k = 0; k < LS_TOY1D_METHODS; k++) {
        const ls_real *x = traj[k] + (size_t)iters * N;
        long first = -1;
        double end_err = fabs((double)x[0] - (double)target[0]);
        if (fabs((double)x[N - 1] - (double)target[N - 1]) > end_err) end_err = fabs((double)x[N - 1] - (double)target[N - 1]);
        for (it = 0; it <= iters && first < 0; it++)
            if (inverted(traj[k] + (size_t)it * N)) first = (long)it;
        int written = set != NULL && write_svg(set, &m[k], traj[k], iters, target);
        if (!written) status = 1;
        printf("%-14s %6g %7g %6u %10ld %10.3e %10.6f  %s/toy1d-%s.svg%s\n", m[k].name, (double)m[k].step,
               (double)m[k].lambda, m[k].power, first, end_err, interior_error(x, target), dir, m[k].name,
               written ? "" : " (NOT WRITTEN)");
    }
    if (set == NULL || !ls_posix_outset_commit(set)) status = 1;
    for (k = 0; k < LS_TOY1D_METHODS; k++) free(traj[k]);
    free(mem);
    if (status) fprintf(stderr, "largesteps toy1d: could not write the SVG files into %s\n", dir);
    return status;
}
