/* sparse.c - compressed sparse column matrices: triplets, triangles,
 * symmetric permutation, products. Every sort is a stable bucket sort. */
#include <largesteps/sparse.h>
#include <string.h>

#define IDX_LIMIT ((size_t)UINT32_MAX - 1u)

static void diag_set(ls_diag *diag, ls_status st, const char *what, uint64_t index, int has_index)
{
    (void)ls_diag_set(diag, st, what, has_index ? index : LS_DIAG_NO_INDEX);
}

uint32_t ls_csc_nnz(const ls_csc *a)
{
    if (a == NULL || a->colptr == NULL) return 0;
    return a->colptr[a->ncols];
}

/* Object part of a CSC with `cap` entries. */
static void csc_size(ls_size *s, uint32_t ncols, size_t cap)
{
    ls_size_add(s, (size_t)ncols + 1u, sizeof(uint32_t));
    ls_size_add(s, cap, sizeof(uint32_t));
    ls_size_add(s, cap, sizeof(ls_real));
}

/* Allocates the object arrays from the bottom; 0 on failure. */
static int csc_alloc(ls_arena *arena, uint32_t nrows, uint32_t ncols, size_t cap, ls_csc *m)
{
    m->nrows = nrows;
    m->ncols = ncols;
    m->capacity = (uint32_t)cap;
    m->colptr = (uint32_t *)ls_arena_alloc(arena, (size_t)ncols + 1u, sizeof(uint32_t));
    m->rowidx = (uint32_t *)ls_arena_alloc(arena, cap, sizeof(uint32_t));
    m->values = (ls_real *)ls_arena_alloc(arena, cap, sizeof(ls_real));
    return m->colptr != NULL && m->rowidx != NULL && m->values != NULL;
}

ls_status ls_csc_from_triplets_bytes(uint32_t nrows, uint32_t ncols, size_t count, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (count > IDX_LIMIT || nrows > IDX_LIMIT - 1u || ncols > IDX_LIMIT - 1u) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    csc_size(&s, ncols, count);
    ls_size_add(&s, (size_t)nrows + 1u, sizeof(uint32_t)); /* row buckets */
    ls_size_add(&s, count, sizeof(uint32_t));              /* triplets in row order */
    return ls_size_get(&s, bytes);
}

static ls_status from_triplets(uint32_t nrows, uint32_t ncols, size_t count, const uint32_t *rows,
                               const uint32_t *cols, const ls_real *vals, ls_arena *arena, ls_csc *out,
                               ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_csc m;
    uint32_t *rs, *order, j, w, p, start, end;
    size_t t, bytes;
    ls_status st;
    if (arena == NULL || out == NULL || (count > 0 && (rows == NULL || cols == NULL))) {
        diag_set(diag, LS_ERR_INVALID,
                 arena == NULL ? "arena is NULL" : out == NULL ? "out is NULL" : "t->rows or t->cols is NULL; needed when t->count > 0",
                 0, 0);
        return LS_ERR_INVALID;
    }
    st = ls_csc_from_triplets_bytes(nrows, ncols, count, &bytes);
    if (st != LS_OK) {
        diag_set(diag, st, "matrix too large for 32-bit indices", 0, 0);
        return st;
    }
    for (t = 0; t < count; t++) {
        if (rows[t] >= nrows || cols[t] >= ncols) {
            diag_set(diag, LS_ERR_INVALID, "t->rows[i] or t->cols[i]: allowed < t->nrows, < t->ncols", (uint64_t)t, 1);
            return LS_ERR_INVALID;
        }
    }
    mark = ls_arena_save(arena);
    if (!csc_alloc(arena, nrows, ncols, count, &m)) goto nomem;
    rs = (uint32_t *)ls_arena_scratch(arena, (size_t)nrows + 1u, sizeof(uint32_t));
    order = (uint32_t *)ls_arena_scratch(arena, count, sizeof(uint32_t));
    if (rs == NULL || order == NULL) goto nomem;
    /* pass 1: triplets bucketed by row, stable */
    memset(rs, 0, ((size_t)nrows + 1u) * sizeof(uint32_t));
    for (t = 0; t < count; t++) rs[rows[t] + 1u]++;
    for (j = 0; j < nrows; j++) rs[j + 1u] += rs[j];
    for (t = 0; t < count; t++) order[rs[rows[t]]++] = (uint32_t)t;
    /* pass 2: by column, stable, so rows ascend within a column */
    memset(m.colptr, 0, ((size_t)ncols + 1u) * sizeof(uint32_t));
    for (t = 0; t < count; t++) m.colptr[cols[t] + 1u]++;
    for (j = 0; j < ncols; j++) m.colptr[j + 1u] += m.colptr[j];
    for (t = 0; t < count; t++) {
        uint32_t o = order[t];
        p = m.colptr[cols[o]]++;
        m.rowidx[p] = rows[o];
        m.values[p] = vals != NULL ? vals[o] : (ls_real)1;
    }
    for (j = ncols; j > 0; j--) m.colptr[j] = m.colptr[j - 1u];
    m.colptr[0] = 0;
    /* sum duplicates (adjacent now, in input order) */
    w = 0;
    for (j = 0; j < ncols; j++) {
        start = m.colptr[j];
        end = m.colptr[j + 1u];
        m.colptr[j] = w;
        for (p = start; p < end; p++) {
            if (w > m.colptr[j] && m.rowidx[w - 1u] == m.rowidx[p]) {
                m.values[w - 1u] += m.values[p];
            } else {
                m.rowidx[w] = m.rowidx[p];
                m.values[w] = m.values[p];
                w++;
            }
        }
    }
    m.colptr[ncols] = w;
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    *out = m;
    return LS_OK;
nomem:
    ls_arena_restore(arena, mark);
    diag_set(diag, LS_ERR_NOMEM, "arena too small for the matrix", 0, 0);
    return LS_ERR_NOMEM;
}

ls_status ls_csc_from_triplets(const ls_triplets *t, ls_arena *arena, ls_csc *out, ls_diag *diag)
{
    if (t == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "t is NULL", LS_DIAG_NO_INDEX);
    return from_triplets(t->nrows, t->ncols, t->count, t->rows, t->cols, t->vals, arena, out, diag);
}

static int csc_ok(const ls_csc *a)
{
    return a != NULL && a->colptr != NULL && (a->colptr[a->ncols] == 0 || (a->rowidx != NULL && a->values != NULL));
}

static uint32_t triangle_count(const ls_csc *a, int upper)
{
    uint32_t j, p, c = 0;
    for (j = 0; j < a->ncols; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++)
            if (upper ? a->rowidx[p] <= j : a->rowidx[p] >= j) c++;
    return c;
}

ls_status ls_csc_triangle_bytes(const ls_csc *a, int upper, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL || !csc_ok(a)) return LS_ERR_INVALID;
    ls_size_init(&s);
    csc_size(&s, a->ncols, triangle_count(a, upper));
    return ls_size_get(&s, bytes);
}

ls_status ls_csc_triangle(const ls_csc *a, int upper, ls_arena *arena, ls_csc *out)
{
    ls_arena_mark mark;
    ls_csc m;
    uint32_t j, p, w = 0;
    if (arena == NULL || out == NULL || !csc_ok(a)) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    if (!csc_alloc(arena, a->nrows, a->ncols, triangle_count(a, upper), &m)) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    for (j = 0; j < a->ncols; j++) {
        m.colptr[j] = w;
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            uint32_t i = a->rowidx[p];
            if (upper ? i <= j : i >= j) {
                m.rowidx[w] = i;
                m.values[w] = a->values[p];
                w++;
            }
        }
    }
    m.colptr[a->ncols] = w;
    *out = m;
    return LS_OK;
}

ls_status ls_csc_symperm_bytes(const ls_csc *a, size_t *bytes)
{
    ls_size s;
    uint32_t cnt;
    if (bytes == NULL || !csc_ok(a) || a->nrows != a->ncols) return LS_ERR_INVALID;
    cnt = triangle_count(a, 1);
    ls_size_init(&s);
    csc_size(&s, a->ncols, cnt);
    ls_size_add(&s, a->ncols, sizeof(uint32_t));               /* pinv */
    ls_size_add(&s, (size_t)a->ncols + 1u, sizeof(uint32_t));  /* row buckets */
    ls_size_add(&s, cnt, sizeof(uint32_t));                    /* new row of each entry */
    ls_size_add(&s, cnt, sizeof(uint32_t));                    /* new column of each entry */
    ls_size_add(&s, cnt, sizeof(uint32_t));                    /* entries in row order */
    return ls_size_get(&s, bytes);
}

ls_status ls_csc_symperm(const ls_csc *a, const uint32_t *perm, ls_arena *arena, ls_csc *out)
{
    ls_arena_mark mark;
    ls_csc m;
    uint32_t n, j, p, t, cnt, *pinv, *rs, *er, *ec, *ord;
    if (arena == NULL || out == NULL || perm == NULL || !csc_ok(a) || a->nrows != a->ncols)
        return LS_ERR_INVALID;
    n = a->ncols;
    cnt = triangle_count(a, 1);
    mark = ls_arena_save(arena);
    if (!csc_alloc(arena, n, n, cnt, &m)) goto nomem;
    pinv = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    rs = (uint32_t *)ls_arena_scratch(arena, (size_t)n + 1u, sizeof(uint32_t));
    er = (uint32_t *)ls_arena_scratch(arena, cnt, sizeof(uint32_t));
    ec = (uint32_t *)ls_arena_scratch(arena, cnt, sizeof(uint32_t));
    ord = (uint32_t *)ls_arena_scratch(arena, cnt, sizeof(uint32_t));
    if (pinv == NULL || rs == NULL || er == NULL || ec == NULL || ord == NULL) goto nomem;
    for (j = 0; j < n; j++) pinv[j] = UINT32_MAX;
    for (j = 0; j < n; j++) {
        if (perm[j] >= n || pinv[perm[j]] != UINT32_MAX) {
            ls_arena_restore(arena, mark);
            return LS_ERR_INVALID;
        }
        pinv[perm[j]] = j;
    }
    /* Upper entry number t, (i, j) of a, goes to (min, max) of (pinv i, pinv j). */
    t = 0;
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            uint32_t i = a->rowidx[p], pi, pj;
            if (i > j) continue;
            pi = pinv[i];
            pj = pinv[j];
            er[t] = pi < pj ? pi : pj;
            ec[t] = pi < pj ? pj : pi;
            t++;
        }
    /* stable bucket sort by new row, then by new column */
    memset(rs, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (t = 0; t < cnt; t++) rs[er[t] + 1u]++;
    for (j = 0; j < n; j++) rs[j + 1u] += rs[j];
    for (t = 0; t < cnt; t++) ord[rs[er[t]]++] = t;
    memset(m.colptr, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (t = 0; t < cnt; t++) m.colptr[ec[t] + 1u]++;
    for (j = 0; j < n; j++) m.colptr[j + 1u] += m.colptr[j];
    /* scatter in row order; the value of entry t is found through a's order */
    for (t = 0; t < cnt; t++) {
        uint32_t e = ord[t];
        uint32_t dst = m.colptr[ec[e]]++;
        m.rowidx[dst] = er[e];
        ec[e] = dst; /* ec now: destination of entry e */
    }
    t = 0;
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++)
            if (a->rowidx[p] <= j) m.values[ec[t++]] = a->values[p];
    for (j = n; j > 0; j--) m.colptr[j] = m.colptr[j - 1u];
    m.colptr[0] = 0;
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    *out = m;
    return LS_OK;
nomem:
    ls_arena_restore(arena, mark);
    return LS_ERR_NOMEM;
}

ls_status ls_csc_matvec(const ls_csc *a, uint32_t k, const ls_real *x, ls_real *y)
{
    uint32_t j, p, c;
    if (!csc_ok(a) || k == 0 || x == NULL || y == NULL) return LS_ERR_INVALID;
    memset(y, 0, (size_t)a->nrows * k * sizeof(ls_real));
    for (j = 0; j < a->ncols; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            ls_real v = a->values[p];
            ls_real *yi = y + (size_t)a->rowidx[p] * k;
            const ls_real *xj = x + (size_t)j * k;
            for (c = 0; c < k; c++) yi[c] += v * xj[c];
        }
    return LS_OK;
}

ls_status ls_csc_matvec_sym(const ls_csc *a, uint32_t k, const ls_real *x, ls_real *y)
{
    uint32_t j, p, c;
    if (!csc_ok(a) || a->nrows != a->ncols || k == 0 || x == NULL || y == NULL) return LS_ERR_INVALID;
    memset(y, 0, (size_t)a->nrows * k * sizeof(ls_real));
    for (j = 0; j < a->ncols; j++) {
        const ls_real *xj = x + (size_t)j * k;
        ls_real *yj = y + (size_t)j * k;
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            uint32_t i = a->rowidx[p];
            ls_real v = a->values[p];
            ls_real *yi = y + (size_t)i * k;
            const ls_real *xi = x + (size_t)i * k;
            if (i > j) continue;
            for (c = 0; c < k; c++) yi[c] += v * xj[c];
            if (i != j)
                for (c = 0; c < k; c++) yj[c] += v * xi[c];
        }
    }
    return LS_OK;
}
