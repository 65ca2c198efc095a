/* tests/dense.h - dense reference computations shared by test_cg.c and
 * test_param.c (independent of the library's sparse code). */
#ifndef LS_TEST_DENSE_H
#define LS_TEST_DENSE_H

#include <math.h>

/* Solves A X = B in place by Gaussian elimination with partial pivoting, in
 * double: a is n x n row-major (destroyed), b is n x k row-major (the
 * solution on return). Returns 0 for an exactly singular pivot. */
static int dense_solve(double *a, int n, double *b, int k)
{
    int i, j, r, c;
    for (c = 0; c < n; c++) {
        int piv = c;
        for (r = c + 1; r < n; r++)
            if (fabs(a[r * n + c]) > fabs(a[piv * n + c])) piv = r;
        if (a[piv * n + c] == 0) return 0;
        for (j = 0; j < n && piv != c; j++) {
            double t = a[c * n + j];
            a[c * n + j] = a[piv * n + j];
            a[piv * n + j] = t;
        }
        for (j = 0; j < k && piv != c; j++) {
            double t = b[c * k + j];
            b[c * k + j] = b[piv * k + j];
            b[piv * k + j] = t;
        }
        for (r = c + 1; r < n; r++) {
            double f = a[r * n + c] / a[c * n + c];
            for (j = c; j < n; j++) a[r * n + j] -= f * a[c * n + j];
            for (j = 0; j < k; j++) b[r * k + j] -= f * b[c * k + j];
        }
    }
    for (i = n - 1; i >= 0; i--)
        for (j = 0; j < k; j++) {
            double s = b[i * k + j];
            for (c = i + 1; c < n; c++) s -= a[i * n + c] * b[c * k + j];
            b[i * k + j] = s / a[i * n + i];
        }
    return 1;
}

#endif /* LS_TEST_DENSE_H */
