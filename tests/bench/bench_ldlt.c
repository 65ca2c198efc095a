/* tests/bench/bench_ldlt.c - times the library's LDL^T on M = I + lambda L.
 *
 * Bench-only dependencies (for the peer in peer_cholmod.c, not this file):
 * Debian libsuitesparse-dev (CHOLMOD) and libeigen3-dev; run_ldlt.sh installs
 * nothing itself, it says what is missing. CI does not run benchmarks.
 *
 * usage: bench_ldlt MESH LAMBDA REPEAT [amd|nd|auto]
 *   MESH: ico:LEVEL | grid:WxH | obj:PATH
 *   ordering: amd (default), nd (geometric nested dissection), auto (the one
 *   with the smaller predicted nnz(L); analyze then includes both)
 * prints one line:
 *   ours-ORDER MESH n nnzL(with diag) analyze_ms factor_ms solve3_ms bytes flushed resid
 * bytes = what the factor keeps (symbolic object + numeric factor), not the
 * ordering's scratch; flushed = entries of L set to zero by the tiny-value flush.
 * Each time is the minimum over REPEAT runs (the machine is shared).
 * analyze = ordering (AMD) + elimination tree + column counts + postorder;
 * factor = numeric LDL^T (first factorization; refactor costs the same);
 * solve3 = one solve with 3 interleaved right-hand sides (permutations included).
 */
#define _POSIX_C_SOURCE 199309L
#include <time.h>
#include <largesteps.h>
#include "meshgen.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static int load_mesh(const char *spec, tmesh *m)
{
    if (strncmp(spec, "ico:", 4) == 0) {
        *m = icosphere(atoi(spec + 4));
        return 1;
    }
    if (strncmp(spec, "grid:", 5) == 0) {
        unsigned w = 0, h = 0;
        if (sscanf(spec + 5, "%ux%u", &w, &h) != 2) return 0;
        *m = gridmesh(w, h);
        return 1;
    }
    if (strncmp(spec, "obj:", 4) == 0) return obj_read(spec + 4, m);
    return 0;
}

int main(int argc, char **argv)
{
    tmesh m;
    mtrip t;
    double lambda, ta = 1e30, tf = 1e30, ts = 1e30, t0, resid = 0;
    int repeat, r;
    size_t bytes_a = 0, bytes_f = 0, i, flushed = 0, arena_bytes, kept_a = 0;
    ls_real *vals, *b, *x;
    unsigned char *mem;
    ls_arena arena;
    ls_csc a;
    ls_ldlt f;
    ls_status st;
    uint32_t method = LS_ORDER_AMD;
    ls_real *xyz;
    const char *oname = "amd";
    if (argc >= 5) {
        oname = argv[4];
        method = strcmp(oname, "nd") == 0 ? LS_ORDER_ND : strcmp(oname, "auto") == 0 ? LS_ORDER_AUTO : LS_ORDER_AMD;
    }
    if (argc < 4 || !load_mesh(argv[1], &m)) {
        fprintf(stderr, "usage: bench_ldlt ico:L|grid:WxH|obj:PATH LAMBDA REPEAT\n");
        return 2;
    }
    lambda = atof(argv[2]);
    repeat = atoi(argv[3]);
    t = laplacian_system(&m, lambda, 0);
    xyz = (ls_real *)malloc(3 * (size_t)m.nv * sizeof(ls_real));
    for (i = 0; i < 3 * (size_t)m.nv; i++) xyz[i] = (ls_real)m.pos[i];
    vals = (ls_real *)malloc(t.count * sizeof(ls_real));
    for (i = 0; i < t.count; i++) vals[i] = (ls_real)t.v[i];
    arena_bytes = (size_t)t.count * 64 + ((size_t)1 << 20);
    mem = (unsigned char *)malloc(arena_bytes);
    ls_arena_init(&arena, mem, arena_bytes);
    st = ls_csc_from_triplets(&(ls_triplets){t.n, t.n, t.count, t.r, t.c, vals}, &arena, &a, NULL);
    if (st != LS_OK) return 1;
    /* ordering + symbolic */
    ls_ldlt_analyze_mesh_bytes(&a, method, &bytes_a);
    {
        unsigned char *mem2 = (unsigned char *)malloc(bytes_a);
        for (r = 0; r < repeat; r++) {
            ls_arena ar;
            ls_arena_init(&ar, mem2, bytes_a);
            t0 = now_ms();
            st = ls_ldlt_analyze_mesh(&a, method, xyz, &ar, &f, NULL);
            t0 = now_ms() - t0;
            if (st != LS_OK) return 1;
            if (t0 < ta) ta = t0;
            kept_a = ar.bottom;
        }
        ls_ldlt_bytes(&f, &bytes_f);
        /* numeric: the first factorization allocates, refactor reuses */
        {
            unsigned char *mem3 = (unsigned char *)malloc(bytes_f);
            ls_arena af;
            ls_arena_init(&af, mem3, bytes_f);
            t0 = now_ms();
            st = ls_ldlt_factor(&f, &a, &af, NULL);
            t0 = now_ms() - t0;
            if (st != LS_OK) {
                fprintf(stderr, "factor: %s\n", ls_status_name(st));
                return 1;
            }
            tf = t0;
            for (r = 1; r < repeat; r++) {
                t0 = now_ms();
                ls_ldlt_refactor(&f, &a, NULL);
                t0 = now_ms() - t0;
                if (t0 < tf) tf = t0;
            }
            for (i = 0; i < f.l_nnz; i++) flushed += f.lx[i] == 0;
            b = (ls_real *)malloc(3 * (size_t)t.n * sizeof(ls_real));
            x = (ls_real *)malloc(3 * (size_t)t.n * sizeof(ls_real));
            for (i = 0; i < 3 * (size_t)t.n; i++) b[i] = (ls_real)((double)(i % 1013) / 1013.0 - 0.5);
            for (r = 0; r < repeat * 5; r++) {
                memcpy(x, b, 3 * (size_t)t.n * sizeof(ls_real));
                t0 = now_ms();
                ls_ldlt_solve(&f, 3, x, &arena);
                t0 = now_ms() - t0;
                if (t0 < ts) ts = t0;
            }
            /* residual ||Mx - b|| / ||b|| (max norms), as in the peer harness;
             * M x in double from the double triplets (not limited by float) */
            {
                double *y = (double *)calloc(3 * (size_t)t.n, sizeof(double)), rn = 0, bn = 0;
                size_t e;
                int c;
                for (e = 0; e < t.count; e++) {
                    uint32_t r0 = t.r[e], c0 = t.c[e];
                    for (c = 0; c < 3; c++) {
                        y[3 * (size_t)r0 + c] += t.v[e] * (double)x[3 * (size_t)c0 + c];
                        if (r0 != c0) y[3 * (size_t)c0 + c] += t.v[e] * (double)x[3 * (size_t)r0 + c];
                    }
                }
                for (i = 0; i < 3 * (size_t)t.n; i++) {
                    double d = fabs(y[i] - (double)b[i]);
                    if (d > rn) rn = d;
                    if (fabs((double)b[i]) > bn) bn = fabs((double)b[i]);
                }
                resid = rn / bn;
                free(y);
            }
            free(mem3);
        }
        free(mem2);
    }
    printf("ours-%s%s %s %u %llu %.3f %.3f %.3f %llu %llu %.1e\n", oname,
           method == LS_ORDER_AUTO ? (f.method == LS_ORDER_ND ? "=nd" : "=amd") : "", argv[1], t.n,
           (unsigned long long)f.l_nnz + t.n, ta, tf, ts, (unsigned long long)(kept_a + bytes_f),
           (unsigned long long)flushed, resid);
    return 0;
}
