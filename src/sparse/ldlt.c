/* ldlt.c - sparse LDL^T: symbolic analysis (ordering, elimination tree,
 * column counts, postorder) and up-looking numeric factorization.
 * The solves are in ldlt_solve.c. */
#include <largesteps/ldlt.h>
#include <string.h>

#define NONE UINT32_MAX

static void diag_fill(ls_diag *diag, ls_status st, const char *what)
{
    if (diag == NULL) return;
    ls_diag_clear(diag);
    diag->status = st;
    diag->what = what;
}

/* Entries of a with row <= col; 0 with *bad set when a row is out of range. */
static uint32_t upper_count(const ls_csc *a, int *bad)
{
    uint32_t j, p, c = 0, n = a->ncols;
    *bad = 0;
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            if (a->rowidx[p] >= n) {
                *bad = 1;
                return 0;
            }
            if (a->rowidx[p] <= j) c++;
        }
    return c;
}

static int square_ok(const ls_csc *a)
{
    return a != NULL && a->colptr != NULL && a->nrows == a->ncols &&
           (a->colptr[a->ncols] == 0 || a->rowidx != NULL);
}

/* Object part of the symbolic analysis. */
static void symbolic_size(ls_size *s, uint32_t n, uint32_t c_nnz)
{
    ls_size_add(s, n, sizeof(uint32_t));              /* perm */
    ls_size_add(s, n, sizeof(uint32_t));              /* pinv */
    ls_size_add(s, n, sizeof(uint32_t));              /* parent */
    ls_size_add(s, (size_t)n + 1u, sizeof(uint32_t)); /* lp */
    ls_size_add(s, (size_t)n + 1u, sizeof(uint32_t)); /* cp */
    ls_size_add(s, c_nnz, sizeof(uint32_t));          /* ci */
    ls_size_add(s, c_nnz, sizeof(uint32_t));          /* csrc */
}

/* Scratch of the symbolic phase: 7 arrays of n, and the transposed pattern. */
typedef struct sym_ws {
    uint32_t *w;    /* 5 n: postorder lists, then the count workspaces */
    uint32_t *post; /* n */
    uint32_t *ipost;/* n */
    uint32_t *tp;   /* n + 1 */
    uint32_t *ti;   /* c_nnz */
} sym_ws;

static void sym_size(ls_size *s, uint32_t n, uint32_t c_nnz)
{
    ls_size_add(s, n, 7u * sizeof(uint32_t));
    ls_size_add(s, (size_t)n + 1u, sizeof(uint32_t));
    ls_size_add(s, c_nnz, sizeof(uint32_t));
}

static int sym_alloc(ls_arena *arena, uint32_t n, uint32_t c_nnz, sym_ws *ws)
{
    ws->w = (uint32_t *)ls_arena_scratch(arena, n, 7u * sizeof(uint32_t));
    ws->tp = (uint32_t *)ls_arena_scratch(arena, (size_t)n + 1u, sizeof(uint32_t));
    ws->ti = (uint32_t *)ls_arena_scratch(arena, c_nnz, sizeof(uint32_t));
    if (ws->w == NULL || ws->tp == NULL || ws->ti == NULL) return 0;
    ws->post = ws->w + 5u * (size_t)n;
    ws->ipost = ws->post + n;
    return 1;
}

/* The bytes of an analysis of an n x n matrix with nnz stored entries,
 * c_nnz of them in the upper triangle with the diagonal. */
static ls_status analyze_bytes_n(uint32_t n, uint32_t nnz, uint32_t c_nnz, uint32_t method, size_t *bytes)
{
    ls_size s, scratch, ord;
    ls_status st;
    size_t ob = 0;
    ls_size_init(&s);
    symbolic_size(&s, n, c_nnz);
    ls_size_init(&scratch);
    sym_size(&scratch, n, c_nnz);
    if (method == LS_ORDER_AMD || method == LS_ORDER_AUTO) {
        st = ls_order_bytes(n, nnz, &ob);
        if (st != LS_OK) return st;
        ls_size_init(&ord);
        ord.bytes = ob;
        ls_size_max(&scratch, &ord);
    }
    if (method == LS_ORDER_ND || method == LS_ORDER_AUTO) {
        st = ls_order_nd_bytes(n, nnz, &ob);
        if (st != LS_OK) return st;
        ls_size_init(&ord);
        ord.bytes = ob;
        ls_size_max(&scratch, &ord);
    }
    if (method == LS_ORDER_AUTO) ls_size_add(&s, n, sizeof(uint32_t)); /* the ND candidate */
    ls_size_add_size(&s, &scratch);
    return ls_size_get(&s, bytes);
}

static ls_status analyze_bytes(const ls_csc *a, uint32_t method, size_t *bytes)
{
    uint32_t c_nnz;
    int bad;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (!square_ok(a) || method > LS_ORDER_AUTO) return LS_ERR_INVALID;
    c_nnz = upper_count(a, &bad);
    if (bad) return LS_ERR_INVALID;
    return analyze_bytes_n(a->ncols, a->colptr[a->ncols], c_nnz, method, bytes);
}

ls_status ls_ldlt_analyze_bytes(const ls_csc *a, uint32_t method, size_t *bytes)
{
    if (method == LS_ORDER_ND || method == LS_ORDER_AUTO) {
        if (bytes != NULL) *bytes = 0;
        return LS_ERR_INVALID; /* need coordinates: ls_ldlt_analyze_mesh_bytes */
    }
    return analyze_bytes(a, method, bytes);
}

ls_status ls_ldlt_analyze_mesh_bytes(const ls_csc *a, uint32_t method, size_t *bytes)
{
    return analyze_bytes(a, method, bytes);
}

/* The upper triangle of P A P^T: entry (i, j), i <= j, of A goes to column
 * max(pinv i, pinv j), row min; csrc keeps its position in A. */
static void build_c(const ls_csc *a, const uint32_t *pinv, uint32_t *cp, uint32_t *ci, uint32_t *csrc)
{
    uint32_t n = a->ncols, j, p;
    memset(cp, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            uint32_t i = a->rowidx[p], pi, pj;
            if (i > j) continue;
            pi = pinv[i];
            pj = pinv[j];
            cp[(pi > pj ? pi : pj) + 1u]++;
        }
    for (j = 0; j < n; j++) cp[j + 1u] += cp[j];
    for (j = 0; j < n; j++)
        for (p = a->colptr[j]; p < a->colptr[j + 1u]; p++) {
            uint32_t i = a->rowidx[p], pi, pj, dst;
            if (i > j) continue;
            pi = pinv[i];
            pj = pinv[j];
            dst = cp[pi > pj ? pi : pj]++;
            ci[dst] = pi < pj ? pi : pj;
            csrc[dst] = p;
        }
    for (j = n; j > 0; j--) cp[j] = cp[j - 1u];
    cp[0] = 0;
}

/* Postorder of the forest `parent` (children visited in increasing order),
 * without recursion: post[k] = the node placed k-th. */
static void postorder(uint32_t n, const uint32_t *parent, uint32_t *post, uint32_t *head, uint32_t *next,
                      uint32_t *stack)
{
    uint32_t j, k = 0;
    for (j = 0; j < n; j++) head[j] = NONE;
    for (j = n; j > 0; j--) {
        uint32_t v = j - 1u;
        if (parent[v] != NONE) {
            next[v] = head[parent[v]];
            head[parent[v]] = v;
        }
    }
    for (j = 0; j < n; j++) {
        uint32_t top = 0;
        if (parent[j] != NONE) continue;
        stack[top++] = j;
        while (top > 0) {
            uint32_t v = stack[top - 1u], c = head[v];
            if (c == NONE) {
                top--;
                post[k++] = v;
            } else {
                head[v] = next[c];
                stack[top++] = c;
            }
        }
    }
}

/* Elimination tree (Liu's algorithm with path compression), postorder, and
 * the exact column counts of L below the diagonal by the skeleton / least
 * common ancestor method of Gilbert, Ng and Peyton (1994): time about
 * O(nnz(A) alpha(n)), independent of nnz(L). */
static void symbolic_counts(uint32_t n, const uint32_t *cp, const uint32_t *ci, uint32_t *parent, uint32_t *cnt,
                            sym_ws *ws)
{
    uint32_t k, p, j, *anc = ws->w, *first, *maxfirst, *prevleaf, *post = ws->post;
    /* etree */
    for (k = 0; k < n; k++) {
        parent[k] = NONE;
        anc[k] = NONE;
        for (p = cp[k]; p < cp[k + 1u]; p++) {
            uint32_t i = ci[p], inext;
            for (; i != NONE && i < k; i = inext) {
                inext = anc[i];
                anc[i] = k;
                if (inext == NONE) parent[i] = k;
            }
        }
    }
    postorder(n, parent, post, ws->w, ws->w + n, ws->w + 2u * (size_t)n);
    /* rows of C: tp/ti list, for row j, the columns k > j with C(j, k) != 0 */
    memset(ws->tp, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (k = 0; k < n; k++)
        for (p = cp[k]; p < cp[k + 1u]; p++)
            if (ci[p] < k) ws->tp[ci[p] + 1u]++;
    for (k = 0; k < n; k++) ws->tp[k + 1u] += ws->tp[k];
    for (k = 0; k < n; k++) cnt[k] = ws->tp[k]; /* cursors */
    for (k = 0; k < n; k++)
        for (p = cp[k]; p < cp[k + 1u]; p++)
            if (ci[p] < k) ws->ti[cnt[ci[p]]++] = k;
    /* skeleton counts (unsigned arithmetic wraps; the final sums are exact) */
    anc = ws->w;
    first = ws->w + n;
    maxfirst = ws->w + 2u * (size_t)n;
    prevleaf = ws->w + 3u * (size_t)n;
    for (k = 0; k < n; k++) {
        first[k] = NONE;
        maxfirst[k] = NONE;
        prevleaf[k] = NONE;
        anc[k] = k;
    }
    for (k = 0; k < n; k++) {
        j = post[k];
        cnt[j] = first[j] == NONE ? 1u : 0u; /* 1 for a leaf of the etree */
        for (; j != NONE && first[j] == NONE; j = parent[j]) first[j] = k;
    }
    for (k = 0; k < n; k++) {
        j = post[k];
        if (parent[j] != NONE) cnt[parent[j]]--;
        for (p = ws->tp[j]; p < ws->tp[j + 1u]; p++) {
            uint32_t i = ws->ti[p], jprev, q, sx, sp;
            if (maxfirst[i] != NONE && first[j] <= maxfirst[i]) continue; /* j is not a leaf of row i's subtree */
            maxfirst[i] = first[j];
            jprev = prevleaf[i];
            prevleaf[i] = j;
            cnt[j]++;
            if (jprev == NONE) continue; /* first leaf */
            for (q = jprev; q != anc[q]; q = anc[q]) {
            }
            for (sx = jprev; sx != q; sx = sp) {
                sp = anc[sx];
                anc[sx] = q;
            }
            cnt[q]--; /* the least common ancestor was counted twice */
        }
        if (parent[j] != NONE) anc[j] = parent[j];
    }
    for (j = 0; j < n; j++)
        if (parent[j] != NONE) cnt[parent[j]] += cnt[j];
    for (j = 0; j < n; j++) cnt[j]--; /* below the diagonal */
}

/* nnz(L) below the diagonal for the ordering g->perm (uses g's arrays and
 * flag as workspace). */
static uint64_t predicted_nnz(const ls_csc *a, ls_ldlt *g, sym_ws *ws)
{
    uint32_t j, n = g->n;
    uint64_t total = 0;
    for (j = 0; j < n; j++) g->pinv[g->perm[j]] = j;
    build_c(a, g->pinv, g->cp, g->ci, g->csrc);
    symbolic_counts(n, g->cp, g->ci, g->parent, g->lp, ws);
    for (j = 0; j < n; j++) total += g->lp[j];
    return total;
}

/* The caller's ordering input: a permutation (LS_ORDER_GIVEN) or coordinates. */
typedef struct order_in {
    const uint32_t *perm;
    const ls_real *xyz;
} order_in;

/* gcc's scalar replacement would split *in back into two arguments (seven in
 * all, one passed on the stack, which its stack-usage report calls a dynamic
 * frame): keep the call as written. */
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 8
#define LDLT_NOIPA __attribute__((noipa))
#else
#define LDLT_NOIPA
#endif

LDLT_NOIPA static ls_status analyze_impl(const ls_csc *a, uint32_t method, const order_in *in, ls_arena *arena,
                                         ls_ldlt *f, ls_diag *diag)
{
    const uint32_t *perm = in->perm;
    const ls_real *xyz = in->xyz;
    ls_arena_mark mark;
    ls_ldlt g;
    uint32_t n, j, *post, *ipost;
    uint64_t total = 0, flops = 0;
    sym_ws ws;
    int bad;
    ls_status st;
    size_t bytes;
    if (!square_ok(a) || arena == NULL || f == NULL || method > LS_ORDER_AUTO ||
        (method == LS_ORDER_GIVEN && perm == NULL && a->ncols > 0) ||
        (method >= LS_ORDER_ND && xyz == NULL && a->ncols > 0)) {
        diag_fill(diag, LS_ERR_INVALID,
                  !square_ok(a)     ? "a: NULL, or not square, or colptr/rowidx NULL"
                  : arena == NULL   ? "arena is NULL"
                  : f == NULL       ? "f is NULL"
                  : method > LS_ORDER_AUTO ? "method: allowed LS_ORDER_NATURAL .. LS_ORDER_AUTO"
                  : method == LS_ORDER_GIVEN ? "perm is NULL; needed by LS_ORDER_GIVEN"
                                    : "xyz is NULL; needed by LS_ORDER_ND and LS_ORDER_AUTO");
        return LS_ERR_INVALID;
    }
    n = a->ncols;
    memset(&g, 0, sizeof g);
    g.c_nnz = upper_count(a, &bad);
    st = bad ? LS_ERR_INVALID : analyze_bytes_n(n, a->colptr[n], g.c_nnz, method, &bytes);
    if (st != LS_OK) {
        diag_fill(diag, st, st == LS_ERR_INVALID ? "a->rowidx[k]: allowed < a->nrows" : "matrix too large");
        return st;
    }
    g.n = n;
    g.state = LS_LDLT_ANALYZED;
    g.a_nnz = a->colptr[n];
    g.method = method;
    mark = ls_arena_save(arena);
    g.perm = (uint32_t *)ls_arena_alloc(arena, n, sizeof(uint32_t));
    g.pinv = (uint32_t *)ls_arena_alloc(arena, n, sizeof(uint32_t));
    g.parent = (uint32_t *)ls_arena_alloc(arena, n, sizeof(uint32_t));
    g.lp = (uint32_t *)ls_arena_alloc(arena, (size_t)n + 1u, sizeof(uint32_t));
    g.cp = (uint32_t *)ls_arena_alloc(arena, (size_t)n + 1u, sizeof(uint32_t));
    g.ci = (uint32_t *)ls_arena_alloc(arena, g.c_nnz, sizeof(uint32_t));
    g.csrc = (uint32_t *)ls_arena_alloc(arena, g.c_nnz, sizeof(uint32_t));
    if (g.perm == NULL || g.pinv == NULL || g.parent == NULL || g.lp == NULL || g.cp == NULL ||
        g.ci == NULL || g.csrc == NULL)
        goto nomem;
    /* ordering */
    if (method == LS_ORDER_AUTO) {
        uint32_t *nd = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
        ls_arena_mark inner;
        uint64_t nnz_nd, nnz_amd;
        if (nd == NULL) goto nomem;
        st = ls_order_nd_geom(a, xyz, arena, nd, diag);
        if (st == LS_OK) st = ls_order_amd(a, arena, g.perm, diag);
        if (st != LS_OK) {
            ls_arena_restore(arena, mark);
            return st;
        }
        inner = ls_arena_save(arena);
        if (!sym_alloc(arena, n, g.c_nnz, &ws)) goto nomem;
        nnz_amd = predicted_nnz(a, &g, &ws);
        memcpy(ws.ipost, g.perm, (size_t)n * sizeof(uint32_t));
        memcpy(g.perm, nd, (size_t)n * sizeof(uint32_t));
        nnz_nd = predicted_nnz(a, &g, &ws);
        if (nnz_nd < nnz_amd) {
            g.method = LS_ORDER_ND;
        } else {
            memcpy(g.perm, ws.ipost, (size_t)n * sizeof(uint32_t));
            g.method = LS_ORDER_AMD;
        }
        ls_arena_restore(arena, inner);
    } else if (method == LS_ORDER_AMD || method == LS_ORDER_ND) {
        st = method == LS_ORDER_AMD ? ls_order_amd(a, arena, g.perm, diag)
                                    : ls_order_nd_geom(a, xyz, arena, g.perm, diag);
        if (st != LS_OK) {
            ls_arena_restore(arena, mark);
            return st;
        }
    } else if (method == LS_ORDER_GIVEN) {
        for (j = 0; j < n; j++) g.pinv[j] = NONE;
        for (j = 0; j < n; j++) {
            if (perm[j] >= n || g.pinv[perm[j]] != NONE) {
                ls_arena_restore(arena, mark);
                diag_fill(diag, LS_ERR_INVALID, "perm: not a permutation of 0 .. n-1");
                if (diag != NULL) {
                    diag->has_index = 1;
                    diag->index = j;
                }
                return LS_ERR_INVALID;
            }
            g.pinv[perm[j]] = j;
            g.perm[j] = perm[j];
        }
    } else {
        for (j = 0; j < n; j++) g.perm[j] = j;
    }
    /* elimination tree, counts, postorder */
    if (!sym_alloc(arena, n, g.c_nnz, &ws)) goto nomem;
    post = ws.post;
    ipost = ws.ipost;
    for (j = 0; j < n; j++) g.pinv[g.perm[j]] = j;
    build_c(a, g.pinv, g.cp, g.ci, g.csrc);
    symbolic_counts(n, g.cp, g.ci, g.parent, g.lp, &ws);
    for (j = 0; j < n; j++) ipost[post[j]] = j;
    /* relabel: perm, parent and counts in postorder (same fill, better locality) */
    {
        uint32_t *nperm = ws.w, *nparent = ws.w + n, *ncnt = ws.w + 2u * (size_t)n;
        for (j = 0; j < n; j++) nperm[j] = g.perm[post[j]];
        for (j = 0; j < n; j++) nparent[j] = g.parent[post[j]] == NONE ? NONE : ipost[g.parent[post[j]]];
        for (j = 0; j < n; j++) ncnt[j] = g.lp[post[j]];
        memcpy(g.perm, nperm, (size_t)n * sizeof(uint32_t));
        memcpy(g.parent, nparent, (size_t)n * sizeof(uint32_t));
        memcpy(g.lp, ncnt, (size_t)n * sizeof(uint32_t));
    }
    for (j = 0; j < n; j++) g.pinv[g.perm[j]] = j;
    /* C of the postordered permutation: relabel the columns and rows of C
     * (a postorder keeps descendants before ancestors, so entries stay in
     * the upper triangle; each column keeps the order build_c gives it) */
    {
        uint32_t *ncp = ws.tp, *nci = ws.ti, *ncsrc = g.ci, *swap, p, d = 0;
        for (j = 0; j < n; j++) {
            uint32_t k = post[j];
            ncp[j] = d;
            for (p = g.cp[k]; p < g.cp[k + 1u]; p++) nci[d++] = ipost[g.ci[p]];
        }
        ncp[n] = d;
        for (j = 0, d = 0; j < n; j++) {
            uint32_t k = post[j];
            for (p = g.cp[k]; p < g.cp[k + 1u]; p++) ncsrc[d++] = g.csrc[p];
        }
        memcpy(g.cp, ncp, ((size_t)n + 1u) * sizeof(uint32_t));
        memcpy(g.csrc, nci, (size_t)d * sizeof(uint32_t));
        swap = g.ci; /* now holds the sources */
        g.ci = g.csrc;
        g.csrc = swap;
    }
    {
        uint32_t prev = 0;
        for (j = 0; j < n; j++) { /* counts to column starts, in place */
            uint32_t c = g.lp[j];
            g.lp[j] = prev;
            total += c;
            flops += (uint64_t)c * ((uint64_t)c + 1u);
            if (total > (uint64_t)UINT32_MAX - 1u) break;
            prev = (uint32_t)total;
        }
    }
    if (total > (uint64_t)UINT32_MAX - 1u) {
        ls_arena_restore(arena, mark);
        diag_fill(diag, LS_ERR_TOO_LARGE, "nnz(L) exceeds 32-bit indices");
        return LS_ERR_TOO_LARGE;
    }
    g.lp[n] = (uint32_t)total;
    g.l_nnz = (uint32_t)total;
    g.flops = flops;
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    *f = g;
    return LS_OK;
nomem:
    ls_arena_restore(arena, mark);
    diag_fill(diag, LS_ERR_NOMEM, "arena too small for the symbolic analysis");
    return LS_ERR_NOMEM;
}

ls_status ls_ldlt_analyze(const ls_csc *a, uint32_t method, const uint32_t *perm, ls_arena *arena,
                          ls_ldlt *f, ls_diag *diag)
{
    ls_diag_clear(diag);
    order_in in;
    if (method == LS_ORDER_ND || method == LS_ORDER_AUTO) {
        diag_fill(diag, LS_ERR_INVALID, "this ordering needs vertex coordinates: ls_ldlt_analyze_mesh");
        return LS_ERR_INVALID;
    }
    in.perm = perm;
    in.xyz = NULL;
    return analyze_impl(a, method, &in, arena, f, diag);
}

ls_status ls_ldlt_analyze_mesh(const ls_csc *a, uint32_t method, const ls_real *xyz, ls_arena *arena, ls_ldlt *f,
                               ls_diag *diag)
{
    ls_diag_clear(diag);
    order_in in;
    in.perm = NULL;
    in.xyz = xyz;
    return analyze_impl(a, method, &in, arena, f, diag);
}

/* The numeric factor of n rows with l_nnz entries below the diagonal. */
static ls_status factor_bytes_n(uint32_t n, uint32_t l_nnz, size_t *bytes)
{
    ls_size s;
    ls_size_init(&s);
    ls_size_add(&s, l_nnz, sizeof(uint32_t)); /* li */
    ls_size_add(&s, l_nnz, sizeof(ls_real));  /* lx */
    ls_size_add(&s, n, sizeof(ls_real));      /* dinv */
    ls_size_add(&s, n, sizeof(ls_acc));       /* y */
    ls_size_add(&s, n, sizeof(uint32_t));     /* flag */
    ls_size_add(&s, n, sizeof(uint32_t));     /* stack */
    ls_size_add(&s, n, sizeof(uint32_t));     /* lnz */
    return ls_size_get(&s, bytes);
}

ls_status ls_ldlt_bytes(const ls_ldlt *f, size_t *bytes)
{
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (f == NULL || f->state == 0 || f->lp == NULL) return LS_ERR_INVALID;
    return factor_bytes_n(f->n, f->l_nnz, bytes);
}

ls_status ls_ldlt_bytes_bound(uint32_t n, uint32_t nnz, uint32_t c_nnz, uint32_t l_nnz, uint32_t method,
                              size_t *analyze, size_t *object, size_t *factor)
{
    ls_size s;
    ls_status st;
    if (analyze == NULL || object == NULL || factor == NULL) return LS_ERR_INVALID;
    *analyze = *object = *factor = 0;
    if (method > LS_ORDER_AUTO || c_nnz > nnz) return LS_ERR_INVALID;
    ls_size_init(&s);
    symbolic_size(&s, n, c_nnz);
    st = ls_size_get(&s, object);
    if (st == LS_OK) st = analyze_bytes_n(n, nnz, c_nnz, method, analyze);
    if (st == LS_OK) st = factor_bytes_n(n, l_nnz, factor);
    if (st != LS_OK) *analyze = *object = *factor = 0;
    return st;
}

static ls_real real_abs(ls_real v)
{
    return v < 0 ? -v : v;
}

static ls_acc acc_abs(ls_acc v)
{
    return v < 0 ? -v : v;
}

/* The up-looking factorization: row k of L solves L(0:k-1,0:k-1) D y = A(0:k-1,k)
 * over the elimination-tree reach of column k. Returns LS_OK or
 * LS_ERR_NOT_SPD with *bad_col = k and *bad_val = the pivot. Sums (y, d) are
 * ls_acc; each entry of L and 1/D is rounded once to ls_real when stored. */
static ls_status numeric(ls_ldlt *f, const ls_real *ax, uint32_t *bad_col, ls_real *bad_val)
{
    uint32_t n = f->n, k, p, i, len;
    const uint32_t *cp = f->cp, *ci = f->ci, *csrc = f->csrc, *parent = f->parent, *lp = f->lp;
    uint32_t *li = f->li, *flag = f->flag, *stack = f->stack, *lnz = f->lnz;
    ls_real *lx = f->lx, *dinv = f->dinv;
    ls_acc *y = f->y;
    const ls_acc tiny = (ls_acc)LS_LDLT_FLUSH;
    for (k = 0; k < n; k++) y[k] = 0;
    for (k = 0; k < n; k++) {
        ls_acc d;
        uint32_t top = n;
        flag[k] = k;
        lnz[k] = 0;
        for (p = cp[k]; p < cp[k + 1u]; p++) {
            i = ci[p];
            y[i] += (ls_acc)ax[csrc[p]];
            for (len = 0; flag[i] != k; i = parent[i]) {
                stack[len++] = i;
                flag[i] = k;
            }
            while (len > 0) stack[--top] = stack[--len];
        }
        d = y[k];
        y[k] = 0;
        for (; top < n; top++) {
            ls_acc yi;
            ls_real lki;
            uint32_t p2;
            i = stack[top];
            yi = y[i];
            y[i] = 0;
            p2 = lp[i] + lnz[i];
            /* A chain i -> i+1 (parent, nested pattern) processed next: both
             * columns update the same rows, fused so that each y[r] is loaded
             * and stored once. The operations and their order are those of
             * the two separate steps: the same bits. */
            if (top + 1u < n && stack[top + 1u] == i + 1u && parent[i] == i + 1u && lnz[i] > 0 &&
                lnz[i] == lnz[i + 1u] + 1u && lp[i + 1u] - lp[i] == lp[i + 2u] - lp[i + 1u] + 1u &&
                !(acc_abs(yi) < tiny)) {
                const uint32_t i2 = i + 1u, q1 = lp[i] + 1u, q2 = lp[i2], m = lnz[i2];
                const ls_acc myi = -yi;
                ls_acc yi2;
                y[i2] += (ls_acc)lx[lp[i]] * myi;
                yi2 = y[i2];
                if (!(acc_abs(yi2) < tiny)) {
                    const ls_acc myi2 = -yi2;
                    ls_real lki2;
                    uint32_t t;
                    y[i2] = 0;
                    for (t = 0; t < m; t++) {
                        const uint32_t r = li[q2 + t];
                        y[r] = (y[r] + (ls_acc)lx[q1 + t] * myi) + (ls_acc)lx[q2 + t] * myi2;
                    }
                    lki = (ls_real)(yi * (ls_acc)dinv[i]);
                    if ((ls_acc)real_abs(lki) < tiny) lki = 0;
                    d -= (ls_acc)lki * yi;
                    li[p2] = k;
                    lx[p2] = lki;
                    lnz[i]++;
                    lki2 = (ls_real)(yi2 * (ls_acc)dinv[i2]);
                    if ((ls_acc)real_abs(lki2) < tiny) lki2 = 0;
                    d -= (ls_acc)lki2 * yi2;
                    li[q2 + m] = k;
                    lx[q2 + m] = lki2;
                    lnz[i2]++;
                    top++;
                    continue;
                }
                /* i+1's value is tiny: finish column i alone (its first row done) */
                for (p = lp[i] + 1u; p < p2; p++) y[li[p]] += (ls_acc)lx[p] * myi;
                lki = (ls_real)(yi * (ls_acc)dinv[i]);
                if ((ls_acc)real_abs(lki) < tiny) lki = 0;
                d -= (ls_acc)lki * yi;
                li[p2] = k;
                lx[p2] = lki;
                lnz[i]++;
                continue;
            }
            if (acc_abs(yi) < tiny) {
                lki = 0; /* flush: no subnormal fill */
            } else {
                const ls_acc myi = -yi;
                for (p = lp[i]; p < p2; p++) y[li[p]] += (ls_acc)lx[p] * myi;
                lki = (ls_real)(yi * (ls_acc)dinv[i]);
                if ((ls_acc)real_abs(lki) < tiny) lki = 0;
                d -= (ls_acc)lki * yi;
            }
            li[p2] = k;
            lx[p2] = lki;
            lnz[i]++;
        }
        if (!(d > 0) || d > (ls_acc)LS_REAL_MAX) {
            *bad_col = k;
            *bad_val = (ls_real)d;
            return LS_ERR_NOT_SPD;
        }
        dinv[k] = (ls_real)((ls_acc)1 / d);
    }
    return LS_OK;
}

static ls_status factor_values(ls_ldlt *f, const ls_csc *a, ls_diag *diag)
{
    uint32_t col = 0;
    ls_real val = 0;
    ls_status st = numeric(f, a->values, &col, &val);
    if (st != LS_OK) {
        f->state = LS_LDLT_INVALID;
        if (diag != NULL) {
            ls_diag_clear(diag);
            diag->status = st;
            diag->what = (val - val == 0) ? "pivot not positive: matrix not positive definite (or singular)"
                                          : "non-finite pivot: NaN or infinity in the matrix";
            diag->has_index = 1;
            diag->index = f->perm[col];
            diag->has_value = 1;
            diag->value = val;
        }
        return st;
    }
    f->state = LS_LDLT_VALID;
    return LS_OK;
}

static ls_status check_matrix(const ls_ldlt *f, const ls_csc *a, ls_diag *diag)
{
    if (f == NULL || f->state == 0) {
        diag_fill(diag, LS_ERR_INVALID, "f: NULL or not analyzed (ls_ldlt_analyze first)");
        return LS_ERR_INVALID;
    }
    if (!square_ok(a) || a->ncols != f->n || a->colptr[a->ncols] != f->a_nnz ||
        (f->a_nnz > 0 && a->values == NULL)) {
        diag_fill(diag, LS_ERR_INVALID, "a: NULL, no values, or not the analyzed pattern (n, nnz)");
        return LS_ERR_INVALID;
    }
    return LS_OK;
}

ls_status ls_ldlt_factor(ls_ldlt *f, const ls_csc *a, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_ldlt g;
    ls_status st = check_matrix(f, a, diag);
    if (st != LS_OK) return st;
    if (f->li != NULL) return ls_ldlt_refactor(f, a, diag);
    if (arena == NULL) {
        diag_fill(diag, LS_ERR_INVALID, "arena is NULL; needed by the first factorization");
        return LS_ERR_INVALID;
    }
    g = *f;
    mark = ls_arena_save(arena);
    g.li = (uint32_t *)ls_arena_alloc(arena, g.l_nnz, sizeof(uint32_t));
    g.lx = (ls_real *)ls_arena_alloc(arena, g.l_nnz, sizeof(ls_real));
    g.dinv = (ls_real *)ls_arena_alloc(arena, g.n, sizeof(ls_real));
    g.y = (ls_acc *)ls_arena_alloc(arena, g.n, sizeof(ls_acc));
    g.flag = (uint32_t *)ls_arena_alloc(arena, g.n, sizeof(uint32_t));
    g.stack = (uint32_t *)ls_arena_alloc(arena, g.n, sizeof(uint32_t));
    g.lnz = (uint32_t *)ls_arena_alloc(arena, g.n, sizeof(uint32_t));
    if (g.li == NULL || g.lx == NULL || g.dinv == NULL || g.y == NULL || g.flag == NULL || g.stack == NULL ||
        g.lnz == NULL) {
        ls_arena_restore(arena, mark);
        diag_fill(diag, LS_ERR_NOMEM, "arena too small for the factor (ask ls_ldlt_bytes)");
        return LS_ERR_NOMEM;
    }
    st = factor_values(&g, a, diag);
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        f->state = LS_LDLT_INVALID;
        return st;
    }
    *f = g;
    return LS_OK;
}

ls_status ls_ldlt_refactor(ls_ldlt *f, const ls_csc *a, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_status st = check_matrix(f, a, diag);
    if (st != LS_OK) return st;
    if (f->li == NULL) {
        diag_fill(diag, LS_ERR_STATE, "refactor before the first ls_ldlt_factor");
        return LS_ERR_STATE;
    }
    return factor_values(f, a, diag);
}
