/* tests/bench/bench_split.c - the parameterization's solve on one thread
 * against the same solve split over W workers of the POSIX pool
 * (ls_ldlt_split), M = I + 19 L on a mesh, in turn, wall time.
 *
 * usage: bench_split MESH.obj ORDER(amd|nd) WORKERS ROUNDS
 * prints one markdown row:
 *   | mesh | n | ordering | nnz(L) | workers | T % | most loaded % | one ms | split ms | ratio | same bits |
 * one, split: medians over ROUNDS rounds of 20 solves each (x = M^{-1} u, 3
 * columns); ratio: the median of the rounds' split / one; T %: the plan's
 * top (run by the calling thread) as a share of the tree's weight; most
 * loaded %: the heaviest worker's share. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <largesteps.h>
#include "ls_posix.h"

#define SOLVES 20
#define MAX_ROUNDS 64

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static double median(double *v, int n)
{
    int i, j;
    for (i = 1; i < n; i++) /* insertion sort: a few dozen values */
        for (j = i; j > 0 && v[j] < v[j - 1]; j--) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static double time_solves(ls_param *p, const ls_real *u, ls_real *x)
{
    double t0 = now_ms();
    int i;
    for (i = 0; i < SOLVES; i++)
        if (ls_param_from_differential(p, u, x) != LS_OK) exit(1);
    return (now_ms() - t0) / SOLVES;
}

int main(int argc, char **argv)
{
    FILE *f;
    unsigned char *data;
    long len;
    size_t arena_bytes, nk, i;
    void *mem;
    ls_arena a;
    ls_mesh m;
    ls_csc L;
    ls_real *u, *x1, *xw;
    ls_param one, split;
    ls_param_config c;
    ls_parallel par;
    ls_ldlt_split_stats stats;
    ls_posix_pool *pool;
    double t1[MAX_ROUNDS], tw[MAX_ROUNDS], ratio[MAX_ROUNDS];
    uint32_t workers;
    int rounds, r, same;
    const char *name;
    if (argc < 5) {
        fprintf(stderr, "usage: bench_split MESH.obj amd|nd WORKERS ROUNDS\n");
        return 2;
    }
    name = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
    workers = (uint32_t)atoi(argv[3]);
    rounds = atoi(argv[4]);
    if (rounds < 1 || rounds > MAX_ROUNDS || workers < 2) return 2;
    f = fopen(argv[1], "rb");
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) <= 0 || fseek(f, 0, SEEK_SET) != 0) {
        fprintf(stderr, "bench_split: cannot read %s\n", argv[1]);
        return 1;
    }
    data = (unsigned char *)malloc((size_t)len);
    if (data == NULL || fread(data, 1, (size_t)len, f) != (size_t)len) return 1;
    fclose(f);
    arena_bytes = (size_t)len * 96 + ((size_t)64 << 20);
    mem = malloc(arena_bytes);
    if (mem == NULL || ls_arena_init(&a, mem, arena_bytes) != LS_OK) return 1;
    if (ls_mesh_read(data, (size_t)len, LS_MESH_FORMAT_AUTO, &a, &m, NULL) != LS_OK) {
        fprintf(stderr, "bench_split: cannot parse %s\n", argv[1]);
        return 1;
    }
    free(data);
    if (ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &L, NULL) != LS_OK) return 1;
    nk = 3u * (size_t)m.vertex_count;
    u = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    x1 = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    xw = (ls_real *)ls_arena_alloc(&a, nk, sizeof(ls_real));
    pool = ls_posix_pool_create(workers);
    if (u == NULL || x1 == NULL || xw == NULL || pool == NULL) return 1;
    ls_param_config_default(&c);
    c.order = strcmp(argv[2], "nd") == 0 ? LS_ORDER_ND : LS_ORDER_AMD;
    if (ls_param_init(&one, &L, &c, m.positions, &a, NULL) != LS_OK) return 1;
    par.run = ls_posix_pool_run;
    par.ctx = pool;
    c.workers = workers;
    c.parallel = &par;
    if (ls_param_init(&split, &L, &c, m.positions, &a, NULL) != LS_OK) return 1;
    if (ls_param_to_differential(&one, m.positions, u) != LS_OK) return 1;
    for (r = 0; r < rounds; r++) {
        t1[r] = time_solves(&one, u, x1);
        tw[r] = time_solves(&split, u, xw);
        ratio[r] = tw[r] / t1[r];
    }
    if (split.split == NULL || ls_ldlt_split_get_stats(&split.split->plan, &split.f, &stats) != LS_OK) return 1;
    same = 1;
    for (i = 0; i < nk; i++) same &= memcmp(&x1[i], &xw[i], sizeof(ls_real)) == 0;
    printf("| %s | %u | %s | %u | %u | %.1f | %.1f | %.3f | %.3f | %.3f | %s |\n", name, m.vertex_count,
           one.f.method == LS_ORDER_ND ? "nd" : "amd", one.f.l_nnz, workers,
           100.0 * (double)stats.top_work / (double)stats.work, 100.0 * (double)stats.max_load / (double)stats.work,
           median(t1, rounds), median(tw, rounds),
           median(ratio, rounds), same ? "yes" : "no");
    ls_posix_pool_destroy(pool);
    free(mem);
    return same ? 0 : 1;
}
