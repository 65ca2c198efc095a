/* tests/bench/bench_param.c - the parameterization's two solvers on a mesh:
 * the LDL^T factor against Jacobi-preconditioned CG, for M = I + lambda L
 * (uniform Laplacian), one thread, CPU time, minimum of REPEAT runs.
 *
 * usage: bench_param MESH.obj REPEAT TOL LAMBDA...
 * prints one markdown row per (lambda, solver):
 *   | mesh | n | lambda | solver | init ms | solve ms | iterations | warm iterations | warm ms | rel. error | bytes |
 * init = ls_param_init (LDL^T: ordering (auto) + symbolic + numeric factor;
 * CG: M and buffers); solve = ls_param_from_differential of u = M x, x the
 * vertex positions (3 columns), CG from a zero start; warm = CG again after
 * u changed by a 1e-3 relative perturbation, from the previous solution (what
 * one optimizer step costs); rel. error = ||x - x_ldlt|| / ||x_ldlt|| (CG) or
 * ||x_ldlt - x_true|| / ||x_true|| (LDL^T, round trip); bytes = the object's
 * arena bytes (ls_param_bytes). */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <largesteps.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static double rel(const ls_real *a, const ls_real *b, size_t n)
{
    double e = 0, s = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        e += ((double)a[i] - (double)b[i]) * ((double)a[i] - (double)b[i]);
        s += (double)b[i] * (double)b[i];
    }
    return sqrt(e / s);
}

int main(int argc, char **argv)
{
    FILE *f;
    unsigned char *data;
    long len;
    size_t arena_bytes, nk, i;
    void *mem, *smem;
    ls_arena a, s;
    ls_mesh m;
    ls_csc L;
    ls_real *u, *u2, *x, *xl, tol;
    int repeat, li, r;
    const char *name;
    if (argc < 5) {
        fprintf(stderr, "usage: bench_param MESH.obj REPEAT TOL LAMBDA...\n");
        return 2;
    }
    name = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
    repeat = atoi(argv[2]);
    tol = (ls_real)atof(argv[3]);
    f = fopen(argv[1], "rb");
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) <= 0 || fseek(f, 0, SEEK_SET) != 0) {
        fprintf(stderr, "bench_param: cannot read %s\n", argv[1]);
        return 1;
    }
    data = (unsigned char *)malloc((size_t)len);
    if (data == NULL || fread(data, 1, (size_t)len, f) != (size_t)len) return 1;
    fclose(f);
    arena_bytes = (size_t)len * 64 + ((size_t)64 << 20);
    mem = malloc(arena_bytes);
    smem = malloc(arena_bytes / 2);
    if (mem == NULL || smem == NULL || ls_arena_init(&a, mem, arena_bytes) != LS_OK ||
        ls_arena_init(&s, smem, arena_bytes / 2) != LS_OK)
        return 1;
    if (ls_mesh_read(data, (size_t)len, LS_MESH_FORMAT_AUTO, &a, &m, NULL) != LS_OK) {
        fprintf(stderr, "bench_param: cannot parse %s\n", argv[1]);
        return 1;
    }
    free(data);
    if (ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) != LS_OK) return 1;
    nk = 3u * (size_t)m.vertex_count;
    u = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    u2 = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    x = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    xl = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    for (li = 4; li < argc; li++) {
        double lambda = atof(argv[li]);
        int solver;
        for (solver = 0; solver < 2; solver++) {
            ls_param_config c;
            ls_param p;
            double ti = 1e30, ts = 1e30, tw = 1e30, err;
            size_t bytes = 0;
            uint32_t iters = 0, witers = 0;
            memset(&c, 0, sizeof c);
            c.solver = (uint32_t)solver;
            c.form = LS_SYSTEM_LAMBDA;
            c.weight = (ls_real)lambda;
            c.k = 3;
            c.order = LS_ORDER_AUTO;
            c.cg_max_iter = 100000;
            c.cg_tol = tol;
            if (ls_param_bytes(&L, &c, m.positions, &s, &bytes) != LS_OK) return 1;
            for (r = 0; r < repeat; r++) {
                ls_arena_mark mk = ls_arena_save(&a);
                double t0 = now_ms(), t1;
                ls_status st = ls_param_init(&p, &L, &c, m.positions, &a, NULL);
                t1 = now_ms();
                if (st != LS_OK) {
                    fprintf(stderr, "bench_param: init: %s\n", ls_status_name(st));
                    return 1;
                }
                if (t1 - t0 < ti) ti = t1 - t0;
                ls_param_to_differential(&p, m.positions, u);
                t0 = now_ms();
                st = ls_param_from_differential(&p, u, x);
                t1 = now_ms();
                if (st != LS_OK) return 1;
                if (t1 - t0 < ts) ts = t1 - t0;
                iters = p.cg.max_iterations;
                if (solver == LS_PARAM_CG) {
                    for (i = 0; i < nk; i++) u2[i] = u[i] * (ls_real)(1.0 + 1e-3 * sin((double)i));
                    t0 = now_ms();
                    st = ls_param_from_differential(&p, u2, u2);
                    t1 = now_ms();
                    if (st != LS_OK) return 1;
                    if (t1 - t0 < tw) tw = t1 - t0;
                    witers = p.cg.max_iterations;
                }
                if (r + 1 < repeat) ls_arena_restore(&a, mk);
            }
            if (solver == LS_PARAM_LDLT) {
                memcpy(xl, x, nk * sizeof(ls_real));
                err = rel(x, m.positions, nk);
                printf("| %s | %u | %g | LDL^T (%s) | %.2f | %.3f | - | - | - | %.2e | %lu |\n", name, m.vertex_count, lambda,
                       p.f.method == LS_ORDER_ND ? "nd" : "amd", ti, ts, err, (unsigned long)bytes);
            } else {
                err = rel(x, xl, nk);
                printf("| %s | %u | %g | CG tol %g | %.2f | %.3f | %u | %u | %.3f | %.2e | %lu |\n", name, m.vertex_count,
                       lambda, (double)tol, ti, ts, iters, witers, tw, err, (unsigned long)bytes);
            }
            fflush(stdout);
        }
    }
    free(mem);
    free(smem);
    return 0;
}
