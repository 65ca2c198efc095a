/* tests/bench/peer_eigen.cpp - the Eigen peer of bench_ldlt.c: Eigen's
 * SimplicialLDLT (AMD ordering, its own port of CSparse's cs_amd) on
 * M = I + lambda L from the same triplets. Bench only (Debian libeigen3-dev).
 *
 * usage: peer_eigen MESH LAMBDA REPEAT
 * prints one line like peer_cholmod:
 *   eigen MESH n nnzL(with diag) analyze_ms factor_ms solve3_ms bytes resid
 * analyze = analyzePattern (ordering, etree, column counts); factor =
 * factorize; solve3 = solve of an n x 3 dense right-hand side (Eigen solves
 * column by column); bytes = 12 nnz(L) + 12 n (its factor arrays: values,
 * row indices, D, and the permutation), not measured from the heap. */
#define _POSIX_C_SOURCE 199309L
#include <time.h>
#include <vector>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include "meshgen.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

int main(int argc, char **argv)
{
    tmesh m;
    if (argc < 4) {
        fprintf(stderr, "usage: peer_eigen ico:L|grid:WxH|obj:PATH LAMBDA REPEAT\n");
        return 2;
    }
    const char *spec = argv[1];
    if (strncmp(spec, "ico:", 4) == 0) {
        m = icosphere(atoi(spec + 4));
    } else if (strncmp(spec, "grid:", 5) == 0) {
        unsigned w = 0, h = 0;
        if (sscanf(spec + 5, "%ux%u", &w, &h) != 2) return 2;
        m = gridmesh(w, h);
    } else if (strncmp(spec, "obj:", 4) == 0) {
        if (!obj_read(spec + 4, &m)) return 2;
    } else {
        return 2;
    }
    double lambda = atof(argv[2]), ta = 1e30, tf = 1e30, ts = 1e30, t0;
    int repeat = atoi(argv[3]);
    mtrip t = laplacian_system(&m, lambda, 1);
    std::vector<Eigen::Triplet<double> > trip;
    trip.reserve(t.count);
    for (size_t i = 0; i < t.count; i++) trip.push_back(Eigen::Triplet<double>((int)t.r[i], (int)t.c[i], t.v[i]));
    Eigen::SparseMatrix<double> A((int)t.n, (int)t.n);
    A.setFromTriplets(trip.begin(), trip.end());
    A.makeCompressed();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int> > ldlt;
    for (int r = 0; r < repeat; r++) {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int> > tmp;
        t0 = now_ms();
        tmp.analyzePattern(A);
        t0 = now_ms() - t0;
        if (t0 < ta) ta = t0;
    }
    ldlt.analyzePattern(A);
    for (int r = 0; r < repeat; r++) {
        t0 = now_ms();
        ldlt.factorize(A);
        t0 = now_ms() - t0;
        if (ldlt.info() != Eigen::Success) {
            fprintf(stderr, "eigen: factorization failed\n");
            return 1;
        }
        if (t0 < tf) tf = t0;
    }
    Eigen::MatrixXd B((int)t.n, 3), X;
    for (size_t i = 0; i < 3 * (size_t)t.n; i++) B((int)(i / 3), (int)(i % 3)) = (double)(i % 1013) / 1013.0 - 0.5;
    for (int r = 0; r < repeat * 5; r++) {
        t0 = now_ms();
        X = ldlt.solve(B);
        t0 = now_ms() - t0;
        if (t0 < ts) ts = t0;
    }
    Eigen::MatrixXd R = A * X - B;
    double rn = R.cwiseAbs().maxCoeff(), bn = B.cwiseAbs().maxCoeff();
    double nnzl = (double)ldlt.matrixL().nestedExpression().nonZeros() + (double)t.n;
    printf("eigen %s %u %.0f %.3f %.3f %.3f %llu %.1e\n", argv[1], t.n, nnzl, ta, tf, ts,
           (unsigned long long)(12.0 * nnzl + 12.0 * t.n), rn / bn);
    mtrip_free(&t);
    tmesh_free(&m);
    return 0;
}
