/* tests/bench/peer_cholmod.c - the peer for bench_ldlt.c: CHOLMOD on the same
 * matrix M = I + lambda L (upper triangle, same triplets, same meshes).
 *
 * Bench-only dependency: Debian libsuitesparse-dev (links -lcholmod), with
 * Debian's reference BLAS (libblas3) and one thread (OMP_NUM_THREADS=1).
 *
 * usage: peer_cholmod MESH LAMBDA REPEAT MODE
 *   MODE: amd | metis | nesdis (simplicial LDL^T), super-amd | super-metis
 *         (supernodal LL^T)
 * prints: MODE MESH n nnzL analyze_ms factor_ms solve3_ms peak_bytes resid
 * analyze = cholmod_analyze (ordering, etree, postorder, column counts);
 * factor = cholmod_factorize on an analyzed L (refactorization, min of REPEAT);
 * solve3 = cholmod_solve2 with an n x 3 dense B and reused workspace.
 */
#define _POSIX_C_SOURCE 199309L
#include <time.h>
#include <cholmod.h>
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
    cholmod_common c;
    cholmod_triplet *T;
    cholmod_sparse *A;
    cholmod_factor *L = NULL;
    cholmod_dense *B, *X = NULL, *Y = NULL, *E = NULL, *R;
    double lambda, ta = 1e30, tf = 1e30, ts = 1e30, t0, one[2] = {1, 0}, mone[2] = {-1, 0}, rn = 0, bn = 0;
    int repeat, r, super;
    const char *mode;
    size_t i;
    if (argc < 5 || !load_mesh(argv[1], &m)) {
        fprintf(stderr, "usage: peer_cholmod MESH LAMBDA REPEAT amd|metis|nesdis|super-amd|super-metis\n");
        return 2;
    }
    lambda = atof(argv[2]);
    repeat = atoi(argv[3]);
    mode = argv[4];
    super = strncmp(mode, "super-", 6) == 0;
    t = laplacian_system(&m, lambda, 0);
    cholmod_start(&c);
    c.nmethods = 1;
    c.method[0].ordering = strstr(mode, "metis") ? CHOLMOD_METIS : strstr(mode, "nesdis") ? CHOLMOD_NESDIS : CHOLMOD_AMD;
    c.postorder = 1;
    c.supernodal = super ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c.final_ll = super ? 1 : 0;
    T = cholmod_allocate_triplet(t.n, t.n, t.count, 1, CHOLMOD_REAL, &c);
    for (i = 0; i < t.count; i++) {
        ((int *)T->i)[i] = (int)t.r[i];
        ((int *)T->j)[i] = (int)t.c[i];
        ((double *)T->x)[i] = t.v[i];
    }
    T->nnz = t.count;
    A = cholmod_triplet_to_sparse(T, t.count, &c);
    for (r = 0; r < repeat; r++) {
        if (L) cholmod_free_factor(&L, &c);
        t0 = now_ms();
        L = cholmod_analyze(A, &c);
        t0 = now_ms() - t0;
        if (t0 < ta) ta = t0;
    }
    for (r = 0; r < repeat; r++) {
        t0 = now_ms();
        cholmod_factorize(A, L, &c);
        t0 = now_ms() - t0;
        if (c.status != CHOLMOD_OK) {
            fprintf(stderr, "cholmod status %d\n", c.status);
            return 1;
        }
        if (t0 < tf) tf = t0;
    }
    B = cholmod_zeros(t.n, 3, CHOLMOD_REAL, &c);
    for (i = 0; i < 3 * (size_t)t.n; i++) ((double *)B->x)[i] = (double)(i % 1013) / 1013.0 - 0.5;
    for (r = 0; r < repeat * 5; r++) {
        t0 = now_ms();
        cholmod_solve2(CHOLMOD_A, L, B, NULL, &X, NULL, &Y, &E, &c);
        t0 = now_ms() - t0;
        if (t0 < ts) ts = t0;
    }
    R = cholmod_copy_dense(B, &c);
    cholmod_sdmult(A, 0, mone, one, X, R, &c);
    for (i = 0; i < 3 * (size_t)t.n; i++) {
        double d = fabs(((double *)R->x)[i]), bb = fabs(((double *)B->x)[i]);
        if (d > rn) rn = d;
        if (bb > bn) bn = bb;
    }
    printf("%s %s %u %.0f %.3f %.3f %.3f %llu %.1e\n", mode, argv[1], t.n, c.lnz, ta, tf, ts,
           (unsigned long long)c.memory_usage, rn / bn);
    cholmod_free_dense(&R, &c);
    cholmod_free_dense(&B, &c);
    cholmod_free_dense(&X, &c);
    cholmod_free_dense(&Y, &c);
    cholmod_free_dense(&E, &c);
    cholmod_free_factor(&L, &c);
    cholmod_free_sparse(&A, &c);
    cholmod_free_triplet(&T, &c);
    cholmod_finish(&c);
    return 0;
}
