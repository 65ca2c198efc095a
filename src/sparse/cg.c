/* cg.c - Jacobi-preconditioned conjugate gradient, k columns at once. */
#include <largesteps/cg.h>
#include <largesteps/math.h>
#include <string.h>

ls_status ls_cg_bytes(uint32_t n, uint32_t k, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (k == 0 || k > LS_CG_MAX_K) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)n * k, sizeof(ls_real)); /* r */
    ls_size_add(&s, (size_t)n * k, sizeof(ls_real)); /* p */
    ls_size_add(&s, (size_t)n * k, sizeof(ls_real)); /* q = M p */
    ls_size_add(&s, (size_t)n, sizeof(ls_real));     /* 1 / diag(M) */
    return ls_size_get(&s, bytes);
}

/* 1 / M_jj from the diagonal entries (upper triangle: row == col); 0 and
 * *bad = j for a missing, non-positive or non-finite one. */
static int inverse_diagonal(const ls_csc *m, ls_real *dinv, uint32_t *bad)
{
    uint32_t j, p;
    for (j = 0; j < m->ncols; j++) {
        ls_real d = (ls_real)0;
        for (p = m->colptr[j]; p < m->colptr[j + 1u]; p++)
            if (m->rowidx[p] == j) d = m->values[p];
        if (!(d > (ls_real)0) || !LS_RISFINITE(d)) {
            *bad = j;
            return 0;
        }
        dinv[j] = (ls_real)1 / d;
    }
    return 1;
}

static int all_finite(const ls_real *v, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        if (!LS_RISFINITE(v[i])) return 0;
    return 1;
}

/* out[c] = sum_i a[i k + c] * b[i k + c], in index order */
static void col_dots(const ls_real *a, const ls_real *b, uint32_t n, uint32_t k, ls_real *out)
{
    uint32_t i, c;
    for (c = 0; c < k; c++) out[c] = (ls_real)0;
    for (i = 0; i < n; i++)
        for (c = 0; c < k; c++) out[c] += a[(size_t)i * k + c] * b[(size_t)i * k + c];
}

/* out[c] = sum_i r[i k + c]^2 * dinv[i] */
static void col_precond_dots(const ls_real *r, const ls_real *dinv, uint32_t n, uint32_t k, ls_real *out)
{
    uint32_t i, c;
    for (c = 0; c < k; c++) out[c] = (ls_real)0;
    for (i = 0; i < n; i++)
        for (c = 0; c < k; c++) {
            ls_real v = r[(size_t)i * k + c];
            out[c] += v * v * dinv[i];
        }
}

/* info->residual: ||b - M x|| / ||b|| per column, using q as scratch */
static void final_residuals(const ls_csc *m, uint32_t k, const ls_real *b, const ls_real *x, ls_real *q,
                            const ls_real *bb, ls_cg_info *info)
{
    uint32_t c;
    size_t i, count = (size_t)m->ncols * k;
    ls_real rr[LS_CG_MAX_K];
    (void)ls_csc_matvec_sym(m, k, x, q);
    for (i = 0; i < count; i++) q[i] = b[i] - q[i];
    col_dots(q, q, m->ncols, k, rr);
    for (c = 0; c < k; c++) info->residual[c] = bb[c] > (ls_real)0 ? LS_RSQRT(rr[c] / bb[c]) : (ls_real)0;
}

ls_status ls_cg_solve(const ls_csc *m, uint32_t k, const ls_real *b, ls_real *x, ls_arena *arena, ls_cg_info *info)
{
    ls_arena_mark mark;
    ls_real *r, *p, *q, *dinv;
    ls_real bb[LS_CG_MAX_K], rho[LS_CG_MAX_K], rz[LS_CG_MAX_K], tmp[LS_CG_MAX_K], limit[LS_CG_MAX_K], alpha[LS_CG_MAX_K];
    uint32_t active[LS_CG_MAX_K], n, c, i, it, nactive = 0, bad = 0;
    size_t count, e;
    uint32_t max_iter;
    ls_real tol;
    ls_status st = LS_OK;
    if (m == NULL || m->colptr == NULL || m->nrows != m->ncols || b == NULL || x == NULL || info == NULL ||
        arena == NULL || k == 0 || k > LS_CG_MAX_K || !(info->tol >= (ls_real)0))
        return LS_ERR_INVALID;
    max_iter = info->max_iter;
    tol = info->tol;
    memset(info, 0, sizeof *info);
    info->max_iter = max_iter;
    info->tol = tol;
    n = m->ncols;
    count = (size_t)n * k;
    if (!all_finite(b, count) || !all_finite(x, count)) return LS_ERR_NONFINITE;
    mark = ls_arena_save(arena);
    r = (ls_real *)ls_arena_scratch(arena, count, sizeof(ls_real));
    p = r == NULL ? NULL : (ls_real *)ls_arena_scratch(arena, count, sizeof(ls_real));
    q = p == NULL ? NULL : (ls_real *)ls_arena_scratch(arena, count, sizeof(ls_real));
    dinv = q == NULL ? NULL : (ls_real *)ls_arena_scratch(arena, n, sizeof(ls_real));
    if (dinv == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    if (!inverse_diagonal(m, dinv, &bad)) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOT_SPD;
    }
    col_dots(b, b, n, k, bb);
    /* r = b - M x */
    (void)ls_csc_matvec_sym(m, k, x, q);
    for (e = 0; e < count; e++) r[e] = b[e] - q[e];
    col_dots(r, r, n, k, tmp);
    for (c = 0; c < k; c++) {
        limit[c] = tol * tol * bb[c];
        active[c] = 0;
        if (bb[c] == (ls_real)0) {
            for (i = 0; i < n; i++) x[(size_t)i * k + c] = (ls_real)0;
            for (i = 0; i < n; i++) r[(size_t)i * k + c] = (ls_real)0;
            info->converged++;
        } else if (tmp[c] <= limit[c]) {
            info->converged++;
        } else {
            active[c] = 1;
            nactive++;
        }
    }
    col_precond_dots(r, dinv, n, k, rho);
    for (i = 0; i < n; i++)
        for (c = 0; c < k; c++) {
            size_t at = (size_t)i * k + c;
            p[at] = active[c] ? dinv[i] * r[at] : (ls_real)0;
        }
    for (it = 0; it < max_iter && nactive > 0; it++) {
        (void)ls_csc_matvec_sym(m, k, p, q);
        col_dots(p, q, n, k, tmp);
        for (c = 0; c < k; c++) {
            if (!active[c]) continue;
            if (!(tmp[c] > (ls_real)0) || !LS_RISFINITE(tmp[c])) {
                st = LS_RISFINITE(tmp[c]) ? LS_ERR_NOT_SPD : LS_ERR_NONFINITE;
                goto done;
            }
            alpha[c] = rho[c] / tmp[c];
        }
        /* x += alpha p, r -= alpha q, and the two norms of the new r, in
         * one pass (each sum in index order) */
        for (c = 0; c < k; c++) {
            tmp[c] = (ls_real)0;
            rz[c] = (ls_real)0;
        }
        for (i = 0; i < n; i++) {
            ls_real di = dinv[i];
            for (c = 0; c < k; c++) {
                size_t at = (size_t)i * k + c;
                ls_real v;
                if (!active[c]) continue;
                x[at] += alpha[c] * p[at];
                v = r[at] - alpha[c] * q[at];
                r[at] = v;
                tmp[c] += v * v;
                rz[c] += v * v * di;
            }
        }
        for (c = 0; c < k; c++) {
            if (!active[c]) continue;
            info->iterations[c]++;
            if (!LS_RISFINITE(tmp[c]) || !LS_RISFINITE(rz[c])) {
                st = LS_ERR_NONFINITE;
                goto done;
            }
            if (tmp[c] <= limit[c]) {
                active[c] = 0;
                nactive--;
                info->converged++;
            }
        }
        for (c = 0; c < k; c++) {
            alpha[c] = active[c] ? rz[c] / rho[c] : (ls_real)0; /* beta */
            if (active[c]) rho[c] = rz[c];
        }
        for (i = 0; i < n; i++)
            for (c = 0; c < k; c++) {
                size_t at = (size_t)i * k + c;
                if (active[c]) p[at] = dinv[i] * r[at] + alpha[c] * p[at];
            }
    }
done:
    for (c = 0; c < k; c++)
        if (info->iterations[c] > info->max_iterations) info->max_iterations = info->iterations[c];
    if (st == LS_OK) final_residuals(m, k, b, x, q, bb, info);
    ls_arena_restore(arena, mark);
    return st;
}
