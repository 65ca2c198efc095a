/* order.c - approximate minimum degree ordering (our own implementation of
 * the method of Amestoy, Davis and Duff 1996).
 *
 * The quotient graph lives in one integer array iw. Node i is either
 *   - a variable (not yet eliminated): its list at iw[pe[i] ..] holds elen[i]
 *     elements followed by len[i] - elen[i] variables; nv[i] > 0 is the number
 *     of original variables it stands for (a supervariable);
 *   - an element (an eliminated pivot): its list holds the variables of its
 *     clique, len[i] of them, degree[i] = their total weight; elen[i] = -1;
 *   - dead: absorbed element, non-principal variable or mass-eliminated
 *     variable, pe[i] = FLIP(the node that took it over).
 * A step: take a variable me of least approximate degree, form the new element
 * Lme = union of its elements' lists and its variables (absorbing those
 * elements), compute |Le \ Lme| for every element e next to Lme (the w
 * counters), bound each degree from that, absorb elements covered by Lme
 * (aggressive absorption), eliminate variables whose only neighbour is me
 * (mass elimination), and merge variables with identical lists found by
 * hashing (supervariables). When iw is full its live lists are compacted.
 * Ties are broken by the last-in-first-out degree lists: deterministic. */
#include <largesteps/order.h>
#include <string.h>
#include <math.h>

#if LS_REAL_IS_FLOAT
#define sqrt_real sqrtf
#else
#define sqrt_real sqrt
#endif

#define FLIP(i) (-(i) - 2)
#define NONE (-1)

/* All arrays of one run, in scratch. */
typedef struct amd_ws {
    int32_t n, iwlen, pfree;
    int32_t *pe, *len, *elen, *nv, *degree, *w;
    int32_t *dhead, *dnext, *dprev, *hhead, *hnext, *hval, *mnext, *mtail, *iw;
    /* constrained mode (cons != NULL): set cons[i] of variable i; sets are
     * eliminated in increasing order; setlist[setptr[k] .. setptr[k + 1])
     * are the members of set k; only the current set is in the degree lists */
    const int32_t *cons, *setlist, *setptr;
    int32_t nsets, cur, inlist;
} amd_ws;

/* The constraint sets handed to amd_graph_run (see amd_ws). */
typedef struct amd_sets {
    const int32_t *cons, *setlist, *setptr;
    int32_t nsets;
} amd_sets;

static size_t iw_length(uint32_t nnz)
{
    size_t s = 2u * (size_t)nnz;
    return s + s / 5u;
}

ls_status ls_order_bytes(uint32_t n, uint32_t nnz, size_t *bytes)
{
    ls_size s;
    size_t iwlen;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    iwlen = iw_length(nnz) + (size_t)n + 1u;
    if (n >= (1u << 30) || iwlen > (size_t)INT32_MAX - 1u) return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, n, 14u * sizeof(int32_t)); /* 14 arrays of n, in one block */
    ls_size_add(&s, iwlen, sizeof(int32_t));
    return ls_size_get(&s, bytes);
}

int ls_order_is_perm(uint32_t n, const uint32_t *perm, unsigned char *mark)
{
    uint32_t i;
    if (n > 0 && (perm == NULL || mark == NULL)) return 0;
    memset(mark, 0, n);
    for (i = 0; i < n; i++) {
        if (perm[i] >= n || mark[perm[i]]) return 0;
        mark[perm[i]] = 1;
    }
    return 1;
}

static inline void dlist_insert(amd_ws *s, int32_t i, int32_t deg)
{
    int32_t h = s->dhead[deg];
    s->dnext[i] = h;
    s->dprev[i] = NONE;
    if (h != NONE) s->dprev[h] = i;
    s->dhead[deg] = i;
    s->degree[i] = deg;
    s->inlist++;
}

static inline void dlist_remove(amd_ws *s, int32_t i)
{
    int32_t nx = s->dnext[i], pv = s->dprev[i];
    if (pv != NONE) s->dnext[pv] = nx;
    else s->dhead[s->degree[i]] = nx;
    if (nx != NONE) s->dprev[nx] = pv;
    s->inlist--;
}

/* In constrained mode: whether variable i is (to be) in the degree lists. */
static inline int listed(const amd_ws *s, int32_t i)
{
    return s->cons == NULL || s->cons[i] == s->cur;
}

/* Appends the member list of b to that of a. */
static void members_append(amd_ws *s, int32_t a, int32_t b)
{
    s->mnext[s->mtail[a]] = b;
    s->mtail[a] = s->mtail[b];
}

/* Compacts the live lists to the front of iw; returns the new pfree. */
static int32_t amd_compact(amd_ws *s)
{
    int32_t j, src = 0, dst = 0, k, *iw = s->iw, *pe = s->pe, *len = s->len;
    for (j = 0; j < s->n; j++) {
        if (pe[j] >= 0 && len[j] > 0) {
            int32_t p = pe[j];
            pe[j] = iw[p];
            iw[p] = FLIP(j);
        }
    }
    while (src < s->pfree) {
        int32_t v = iw[src++];
        if (v < 0) {
            j = FLIP(v);
            iw[dst] = pe[j];
            pe[j] = dst++;
            for (k = 1; k < len[j]; k++) iw[dst++] = iw[src++];
        }
    }
    return dst;
}

/* Resets the w counters when wflg gets near overflow; returns the new wflg. */
static int32_t clear_flag(amd_ws *s, int32_t wflg)
{
    int32_t x;
    if (wflg < INT32_MAX - 2 * s->n - 2) return wflg;
    for (x = 0; x < s->n; x++)
        if (s->w[x] != 0) s->w[x] = 1;
    return 2;
}

/* The elimination loop; writes perm. Returns 0 on an internal inconsistency. */
static int amd_run(amd_ws *s, uint32_t *perm)
{
    int32_t n = s->n, nel = 0, mindeg = 0, wflg = 2, lemax = 0, nout = 0;
    uint32_t hmask = 1;
    while (hmask < 4096u && hmask < (uint32_t)n) hmask <<= 1;
    hmask = hmask > (uint32_t)n ? hmask >> 1 : hmask; /* a power of two <= n */
    hmask -= 1u;
    int32_t *pe = s->pe, *len = s->len, *elen = s->elen, *nv = s->nv, *degree = s->degree, *w = s->w;
    int32_t *iw = s->iw;
    while (nel < n) {
        int32_t me, elenme, nvpiv, degme = 0, pme1, pme2, pme, p, i, e, v;
        while (s->inlist == 0 && s->cons != NULL && s->cur + 1 < s->nsets) {
            int32_t k; /* the current set is done: list the next one */
            s->cur++;
            mindeg = n;
            for (k = s->setptr[s->cur]; k < s->setptr[s->cur + 1]; k++) {
                i = s->setlist[k];
                if (elen[i] >= 0 && nv[i] > 0) {
                    int32_t d = degree[i] < n ? degree[i] : n - 1;
                    dlist_insert(s, i, d);
                    if (d < mindeg) mindeg = d;
                }
            }
        }
        while (mindeg < n && s->dhead[mindeg] == NONE) mindeg++;
        if (mindeg >= n) return 0;
        me = s->dhead[mindeg];
        dlist_remove(s, me);
        elenme = elen[me];
        nvpiv = nv[me];
        nel += nvpiv;
        nv[me] = -nvpiv;
        /* --- construct the new element Lme ------------------------------- */
        if (elenme == 0) {
            pme1 = pe[me];
            pme2 = pme1 - 1;
            for (p = pme1; p < pme1 + len[me]; p++) {
                int32_t nvi;
                i = iw[p];
                nvi = nv[i];
                if (nvi > 0) {
                    degme += nvi;
                    nv[i] = -nvi;
                    iw[++pme2] = i;
                    if (listed(s, i)) dlist_remove(s, i);
                }
            }
        } else {
            int32_t knt1, need = n - nel;
            if (s->pfree + need > s->iwlen) {
                s->pfree = amd_compact(s);
                if (s->pfree + need > s->iwlen) return 0;
            }
            p = pe[me];
            pme1 = s->pfree;
            for (knt1 = 0; knt1 <= elenme; knt1++) {
                int32_t pj, ln, k2;
                if (knt1 == elenme) {
                    e = me;
                    pj = p;
                    ln = len[me] - elenme;
                } else {
                    e = iw[p++];
                    pj = pe[e];
                    ln = len[e];
                }
                for (k2 = 0; k2 < ln; k2++) {
                    int32_t nvi;
                    i = iw[pj++];
                    nvi = nv[i];
                    if (nvi > 0) {
                        degme += nvi;
                        nv[i] = -nvi;
                        iw[s->pfree++] = i;
                        if (listed(s, i)) dlist_remove(s, i);
                    }
                }
                if (e != me) {
                    pe[e] = FLIP(me);
                    w[e] = 0;
                }
            }
            pme2 = s->pfree - 1;
        }
        pe[me] = pme1;
        elen[me] = NONE;
        wflg = clear_flag(s, wflg);
        /* --- |Le \ Lme| for every element e next to Lme ------------------- */
        for (pme = pme1; pme <= pme2; pme++) {
            int32_t eln, nvi, wnvi;
            i = iw[pme];
            eln = elen[i];
            if (eln <= 0) continue;
            nvi = -nv[i];
            wnvi = wflg - nvi;
            for (p = pe[i]; p < pe[i] + eln; p++) {
                int32_t we;
                e = iw[p];
                we = w[e];
                if (we >= wflg) we -= nvi;
                else if (we != 0) we = degree[e] + wnvi;
                w[e] = we;
            }
        }
        /* --- degree update, aggressive and mass elimination ---------------- */
        for (pme = pme1; pme <= pme2; pme++) {
            int32_t p1, p2, p3, p4, pn, deg = 0;
            uint32_t hash = 0;
            i = iw[pme];
            p1 = pe[i];
            p2 = p1 + elen[i] - 1;
            pn = p1;
            for (p = p1; p <= p2; p++) {
                int32_t we;
                e = iw[p];
                we = w[e];
                if (we != 0) {
                    int32_t dext = we - wflg;
                    if (dext > 0) {
                        deg += dext;
                        iw[pn++] = e;
                        hash += (uint32_t)e;
                    } else {
                        pe[e] = FLIP(me); /* aggressive absorption */
                        w[e] = 0;
                    }
                }
            }
            elen[i] = pn - p1 + 1;
            p3 = pn;
            p4 = p1 + len[i];
            for (p = p2 + 1; p < p4; p++) {
                int32_t j = iw[p], nvj = nv[j];
                if (nvj > 0) {
                    deg += nvj;
                    iw[pn++] = j;
                    hash += (uint32_t)j;
                }
            }
            if (elen[i] == 1 && p3 == pn && (s->cons == NULL || s->cons[i] == s->cons[me])) {
                int32_t nvi = -nv[i]; /* mass elimination */
                pe[i] = FLIP(me);
                degme -= nvi;
                nvpiv += nvi;
                nel += nvi;
                nv[i] = 0;
                elen[i] = NONE;
                members_append(s, me, i);
            } else {
                if (deg < degree[i]) degree[i] = deg;
                iw[pn] = iw[p3];
                iw[p3] = iw[p1];
                iw[p1] = me;
                len[i] = pn - p1 + 1;
                s->hval[i] = (int32_t)(hash & 0x7FFFFFFFu);
                hash &= hmask; /* a small table stays in cache; full hashes are compared */
                s->hnext[i] = s->hhead[hash];
                s->hhead[hash] = i;
            }
        }
        degree[me] = degme;
        if (degme > lemax) lemax = degme;
        /* --- supervariables: identical lists within a hash bucket ---------- */
        for (pme = pme1; pme <= pme2; pme++) {
            int32_t i2, h;
            i = iw[pme];
            if (nv[i] >= 0) continue;
            h = (int32_t)((uint32_t)s->hval[i] & hmask);
            if (s->hhead[h] == NONE) continue;
            i2 = s->hhead[h];
            s->hhead[h] = NONE;
            for (; i2 != NONE && s->hnext[i2] != NONE; i2 = s->hnext[i2]) {
                int32_t ln = len[i2], eln = elen[i2], jlast = i2, j2 = s->hnext[i2];
                for (p = pe[i2] + 1; p < pe[i2] + ln; p++) w[iw[p]] = wflg;
                while (j2 != NONE) {
                    int ok = len[j2] == ln && elen[j2] == eln && s->hval[j2] == s->hval[i2] &&
                             (s->cons == NULL || s->cons[j2] == s->cons[i2]);
                    for (p = pe[j2] + 1; ok && p < pe[j2] + ln; p++)
                        if (w[iw[p]] != wflg) ok = 0;
                    if (ok) {
                        pe[j2] = FLIP(i2);
                        nv[i2] += nv[j2];
                        nv[j2] = 0;
                        elen[j2] = NONE;
                        members_append(s, i2, j2);
                        j2 = s->hnext[j2];
                        s->hnext[jlast] = j2;
                    } else {
                        jlast = j2;
                        j2 = s->hnext[j2];
                    }
                }
                wflg++;
            }
        }
        /* --- finalize degrees, compact Lme --------------------------------- */
        p = pme1;
        for (pme = pme1; pme <= pme2; pme++) {
            int32_t nvi, deg;
            i = iw[pme];
            nvi = -nv[i];
            if (nvi <= 0) continue;
            nv[i] = nvi;
            deg = degree[i] + degme - nvi;
            if (deg > n - nel - nvi) deg = n - nel - nvi;
            if (listed(s, i)) {
                dlist_insert(s, i, deg);
                if (deg < mindeg) mindeg = deg;
            } else {
                degree[i] = deg;
            }
            iw[p++] = i;
        }
        nv[me] = nvpiv;
        len[me] = p - pme1;
        if (len[me] == 0) {
            pe[me] = NONE;
            w[me] = 0;
        }
        if (elenme != 0) s->pfree = p; /* Lme was the last list: give back the tail */
        wflg += lemax + 1;
        wflg = clear_flag(s, wflg);
        for (v = me; v != NONE; v = s->mnext[v]) {
            if (nout >= n) return 0;
            perm[nout++] = (uint32_t)v;
        }
    }
    return nout == n;
}

/* Sets up the quotient graph of the pattern of the n x n matrix g in the workspace (block: 14 n ints, iw: iwlen ints) and runs the
 * elimination. Returns 0 on an internal inconsistency. */
static int amd_graph_run(const ls_csc *g, int32_t *block, int32_t *iw, size_t iwlen, uint32_t *perm,
                         const amd_sets *sets)
{
    amd_ws s;
    s.cons = sets != NULL ? sets->cons : NULL;
    s.setlist = sets != NULL ? sets->setlist : NULL;
    s.setptr = sets != NULL ? sets->setptr : NULL;
    s.nsets = sets != NULL ? sets->nsets : 0;
    s.cur = 0;
    s.inlist = 0;
    int32_t i;
    uint32_t j, q, n = g->ncols;
    const uint32_t *colptr = g->colptr, *rowidx = g->rowidx;
    s.iw = iw;
    s.n = (int32_t)n;
    s.iwlen = (int32_t)iwlen;
    s.pe = block;
    s.len = block + n;
    s.elen = block + 2u * (size_t)n;
    s.nv = block + 3u * (size_t)n;
    s.degree = block + 4u * (size_t)n;
    s.w = block + 5u * (size_t)n;
    s.dhead = block + 6u * (size_t)n;
    s.dnext = block + 7u * (size_t)n;
    s.dprev = block + 8u * (size_t)n;
    s.hhead = block + 9u * (size_t)n;
    s.hnext = block + 10u * (size_t)n;
    s.hval = block + 11u * (size_t)n;
    s.mnext = block + 12u * (size_t)n;
    s.mtail = block + 13u * (size_t)n;
    /* the graph of A + A^T without the diagonal, from the strictly upper entries */
    memset(s.len, 0, (size_t)n * sizeof(int32_t));
    for (j = 0; j < n; j++)
        for (q = colptr[j]; q < colptr[j + 1u]; q++) {
            uint32_t r = rowidx[q];
            if (r < j) {
                s.len[r]++;
                s.len[j]++;
            }
        }
    s.pfree = 0;
    for (i = 0; i < s.n; i++) {
        s.pe[i] = s.pfree;
        s.pfree += s.len[i];
        s.elen[i] = s.len[i]; /* temporary fill cursor */
    }
    for (j = 0; j < n; j++)
        for (q = colptr[j]; q < colptr[j + 1u]; q++) {
            uint32_t r = rowidx[q];
            if (r < j) {
                s.iw[s.pe[r] + s.len[r] - s.elen[r]--] = (int32_t)j;
                s.iw[s.pe[j] + s.len[j] - s.elen[j]--] = (int32_t)r;
            }
        }
    for (i = 0; i < s.n; i++) {
        s.nv[i] = 1;
        s.w[i] = 1;
        s.elen[i] = 0;
        s.dhead[i] = NONE;
        s.hhead[i] = NONE;
        s.mnext[i] = NONE;
        s.mtail[i] = i;
    }
    for (i = 0; i < s.n; i++) {
        int32_t d = s.len[i] < s.n ? s.len[i] : s.n - 1;
        if (listed(&s, i)) dlist_insert(&s, i, d);
        else s.degree[i] = d;
    }
    return amd_run(&s, perm);
}

ls_status ls_order_amd(const ls_csc *a, ls_arena *arena, uint32_t *perm, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    int32_t *block, *iw;
    uint32_t n, j, q;
    size_t bytes, iwlen;
    ls_status st;
    if (diag != NULL) ls_diag_clear(diag);
    if (a == NULL || arena == NULL || (a->ncols > 0 && (perm == NULL || a->colptr == NULL)) ||
        a->nrows != a->ncols) {
        if (diag != NULL) {
            diag->status = LS_ERR_INVALID;
            diag->what = a == NULL ? "a is NULL" : arena == NULL ? "arena is NULL"
                       : a->nrows != a->ncols ? "a: not square (nrows != ncols)"
                       : perm == NULL ? "perm is NULL" : "a->colptr is NULL";
        }
        return LS_ERR_INVALID;
    }
    n = a->ncols;
    st = ls_order_bytes(n, a->colptr[n], &bytes);
    if (st != LS_OK) return st;
    if (n == 0) return LS_OK;
    for (j = 0; j < n; j++)
        for (q = a->colptr[j]; q < a->colptr[j + 1u]; q++)
            if (a->rowidx[q] >= n) {
                if (diag != NULL) {
                    diag->status = LS_ERR_INVALID;
                    diag->what = "a->rowidx[k]: allowed < a->nrows";
                    diag->has_index = 1;
                    diag->index = q;
                }
                return LS_ERR_INVALID;
            }
    iwlen = iw_length(a->colptr[n]) + (size_t)n + 1u;
    mark = ls_arena_save(arena);
    block = (int32_t *)ls_arena_scratch(arena, n, 14u * sizeof(int32_t));
    iw = (int32_t *)ls_arena_scratch(arena, iwlen, sizeof(int32_t));
    if (block == NULL || iw == NULL) {
        ls_arena_restore(arena, mark);
        if (diag != NULL) {
            diag->status = LS_ERR_NOMEM;
            diag->what = "arena too small for the ordering";
        }
        return LS_ERR_NOMEM;
    }
    if (!amd_graph_run(a, block, iw, iwlen, perm, NULL)) {
        ls_arena_restore(arena, mark);
        if (diag != NULL) {
            diag->status = LS_ERR_INVALID;
            diag->what = "ordering failed (duplicate entries in a column?)";
        }
        return LS_ERR_INVALID;
    }
    ls_arena_restore(arena, mark);
    return LS_OK;
}

/* ---- geometric nested dissection --------------------------------------
 * The vertex set of a task (a range of idx) is cut at the median of its
 * projection on the best of several directions (the smallest boundary);
 * the boundary of one half is the separator, refined by greedy vertex moves,
 * and placed last; both halves become tasks (an explicit task stack, no
 * recursion) down to leaves of ND_LEAF vertices. The separators' positions
 * then define constraint sets for the minimum degree above (leaves first,
 * inner separators before outer ones), which gives the final order. */

#define ND_LEAF 16u
#define ND_PASSES 12u
#define ND_CAND 10u
#define ND_FEW 100u

static size_t nd_adj_length(uint32_t nnz)
{
    return 2u * (size_t)nnz;
}

ls_status ls_order_nd_bytes(uint32_t n, uint32_t nnz, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (n >= (1u << 30) || nd_adj_length(nnz) > (size_t)UINT32_MAX - 1u ||
        iw_length(nnz) + (size_t)n + 1u > (size_t)INT32_MAX - 1u)
        return LS_ERR_TOO_LARGE;
    ls_size_init(&s);
    ls_size_add(&s, (size_t)n + 1u, sizeof(uint32_t)); /* xadj */
    ls_size_add(&s, nd_adj_length(nnz), sizeof(uint32_t)); /* adj */
    ls_size_add(&s, n, sizeof(uint32_t));              /* stamp */
    ls_size_add(&s, n, sizeof(uint32_t));              /* tmp */
    ls_size_add(&s, n, sizeof(uint32_t));              /* separator worklist */
    ls_size_add(&s, n, 2u * sizeof(uint32_t));         /* task stack */
    ls_size_add(&s, n, sizeof(ls_real));               /* projection keys */
    ls_size_add(&s, n, 3u * sizeof(int32_t));         /* constraint sets: cons, setlist, setptr */
    ls_size_add(&s, 1u, sizeof(int32_t));
    ls_size_add(&s, n, 14u * sizeof(int32_t));        /* constrained minimum degree */
    ls_size_add(&s, iw_length(nnz) + (size_t)n + 1u, sizeof(int32_t));
    return ls_size_get(&s, bytes);
}

static int nd_less(const ls_real *key, uint32_t u, uint32_t v)
{
    ls_real a = key[u], b = key[v];
    return a < b || (a == b && u < v);
}

static void nd_swap(uint32_t *v, uint32_t i, uint32_t j)
{
    uint32_t t = v[i];
    v[i] = v[j];
    v[j] = t;
}

/* Places the element of rank k of v[lo, hi) at k, smaller ones before it. */
static void nd_select(uint32_t *v, uint32_t lo, uint32_t hi, uint32_t k, const ls_real *key)
{
    while (hi - lo > 1u) {
        uint32_t a = lo, b = lo + (hi - lo) / 2u, c = hi - 1u, med, i, store;
        /* median of three to the end */
        if (nd_less(key, v[b], v[a])) nd_swap(v, a, b);
        if (nd_less(key, v[c], v[b])) nd_swap(v, b, c);
        if (nd_less(key, v[b], v[a])) nd_swap(v, a, b);
        med = b;
        nd_swap(v, med, c);
        store = lo;
        for (i = lo; i < c; i++)
            if (nd_less(key, v[i], v[c])) nd_swap(v, i, store++);
        nd_swap(v, store, c);
        if (k == store) return;
        if (k < store) hi = store;
        else lo = store + 1u;
    }
}

/* The principal direction of the points xyz[vs[0..m)]: power iteration on
 * their covariance, started from the longest bounding-box axis; a fixed
 * number of steps (deterministic). */
static void nd_direction(const ls_real *xyz, const uint32_t *vs, uint32_t m, ls_real *dir)
{
    ls_real mean[3] = {0, 0, 0}, cov[9], mn[3], mx[3], ext = -1, inv = (ls_real)1 / (ls_real)m;
    uint32_t i, c, r, it, axis = 0;
    for (c = 0; c < 3u; c++) mn[c] = mx[c] = xyz[3u * (size_t)vs[0] + c];
    for (i = 0; i < m; i++)
        for (c = 0; c < 3u; c++) {
            ls_real x = xyz[3u * (size_t)vs[i] + c];
            mean[c] += x;
            if (x < mn[c]) mn[c] = x;
            if (x > mx[c]) mx[c] = x;
        }
    for (c = 0; c < 3u; c++) {
        mean[c] *= inv;
        if (mx[c] - mn[c] > ext) {
            ext = mx[c] - mn[c];
            axis = c;
        }
    }
    for (c = 0; c < 9u; c++) cov[c] = 0;
    for (i = 0; i < m; i++) {
        ls_real d[3];
        for (c = 0; c < 3u; c++) d[c] = xyz[3u * (size_t)vs[i] + c] - mean[c];
        for (r = 0; r < 3u; r++)
            for (c = 0; c < 3u; c++) cov[3u * (size_t)r + c] += d[r] * d[c];
    }
    for (c = 0; c < 3u; c++) dir[c] = c == axis ? (ls_real)1 : (ls_real)0;
    for (it = 0; it < 16u; it++) {
        ls_real y[3], nrm = 0;
        for (r = 0; r < 3u; r++) y[r] = cov[3u * (size_t)r] * dir[0] + cov[3u * (size_t)r + 1u] * dir[1] + cov[3u * (size_t)r + 2u] * dir[2];
        for (r = 0; r < 3u; r++) nrm += y[r] * y[r];
        if (!(nrm > 0) || nrm > LS_REAL_MAX) break; /* degenerate: keep the axis */
        nrm = (ls_real)1 / sqrt_real(nrm);
        for (r = 0; r < 3u; r++) dir[r] = y[r] * nrm;
    }
}

/* Splits v[lo, hi) at the median of the projection on dir: the lower half
 * gets stamp sa, the upper sb; counts the vertices of each half with a
 * neighbour in the other (*na, *nb) and returns the smaller count. */
typedef struct nd_ctx {
    const ls_real *xyz;
    const uint32_t *xadj, *adj;
    uint32_t *v, *stamp;
    ls_real *key;
} nd_ctx;

static uint32_t nd_cut(const nd_ctx *cx, uint32_t lo, uint32_t hi, const ls_real *dir, uint32_t sa, uint32_t *cnt)
{
    const ls_real *xyz = cx->xyz;
    const uint32_t *xadj = cx->xadj, *adj = cx->adj;
    uint32_t *v = cx->v, *stamp = cx->stamp, *na = cnt, *nb = cnt + 1, sb = sa + 1u;
    ls_real *key = cx->key;
    uint32_t i, mid = lo + (hi - lo) / 2u;
    for (i = lo; i < hi; i++) {
        const ls_real *x = xyz + 3u * (size_t)v[i];
        key[v[i]] = x[0] * dir[0] + x[1] * dir[1] + x[2] * dir[2];
    }
    nd_select(v, lo, hi, mid, key);
    for (i = lo; i < mid; i++) stamp[v[i]] = sa;
    for (i = mid; i < hi; i++) stamp[v[i]] = sb;
    *na = *nb = 0;
    for (i = lo; i < hi; i++) {
        uint32_t u = v[i], other = stamp[u] == sa ? sb : sa, p;
        for (p = xadj[u]; p < xadj[u + 1u]; p++)
            if (stamp[adj[p]] == other) {
                if (i < mid) (*na)++;
                else (*nb)++;
                break;
            }
    }
    return *na < *nb ? *na : *nb;
}

ls_status ls_order_nd_geom(const ls_csc *a, const ls_real *xyz, ls_arena *arena, uint32_t *perm, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    uint32_t n, j, q, *xadj, *adj, *stamp, *tmp, *sepw, *stack, top = 0, task = 0;
    int32_t *cons, *setlist, *setptr, *block, *iw;
    ls_real *key;
    size_t bytes, iwlen;
    ls_status st;
    if (diag != NULL) ls_diag_clear(diag);
    if (a == NULL || arena == NULL || a->colptr == NULL || a->nrows != a->ncols ||
        (a->ncols > 0 && (perm == NULL || xyz == NULL))) {
        if (diag != NULL) {
            diag->status = LS_ERR_INVALID;
            diag->what = a == NULL ? "a is NULL" : arena == NULL ? "arena is NULL"
                       : a->colptr == NULL ? "a->colptr is NULL"
                       : a->nrows != a->ncols ? "a: not square (nrows != ncols)"
                       : perm == NULL ? "perm is NULL" : "xyz is NULL";
        }
        return LS_ERR_INVALID;
    }
    n = a->ncols;
    st = ls_order_nd_bytes(n, a->colptr[n], &bytes);
    if (st != LS_OK) return st;
    for (j = 0; j < 3u * n; j++) {
        ls_real d = xyz[j] - xyz[j];
        if (!(d == 0)) {
            if (diag != NULL) {
                diag->status = LS_ERR_NONFINITE;
                diag->what = "non-finite vertex coordinate";
                diag->has_index = 1;
                diag->index = j / 3u;
            }
            return LS_ERR_NONFINITE;
        }
    }
    for (j = 0; j < n; j++)
        for (q = a->colptr[j]; q < a->colptr[j + 1u]; q++)
            if (a->rowidx[q] >= n) {
                if (diag != NULL) {
                    diag->status = LS_ERR_INVALID;
                    diag->what = "a->rowidx[k]: allowed < a->nrows";
                    diag->has_index = 1;
                    diag->index = q;
                }
                return LS_ERR_INVALID;
            }
    mark = ls_arena_save(arena);
    xadj = (uint32_t *)ls_arena_scratch(arena, (size_t)n + 1u, sizeof(uint32_t));
    adj = (uint32_t *)ls_arena_scratch(arena, nd_adj_length(a->colptr[n]), sizeof(uint32_t));
    stamp = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    tmp = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    sepw = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    stack = (uint32_t *)ls_arena_scratch(arena, n, 2u * sizeof(uint32_t));
    key = (ls_real *)ls_arena_scratch(arena, n, sizeof(ls_real));
    iwlen = iw_length(a->colptr[n]) + (size_t)n + 1u;
    cons = (int32_t *)ls_arena_scratch(arena, n, sizeof(int32_t));
    setlist = (int32_t *)ls_arena_scratch(arena, n, sizeof(int32_t));
    setptr = (int32_t *)ls_arena_scratch(arena, (size_t)n + 1u, sizeof(int32_t));
    block = (int32_t *)ls_arena_scratch(arena, n, 14u * sizeof(int32_t));
    iw = (int32_t *)ls_arena_scratch(arena, iwlen, sizeof(int32_t));
    if (xadj == NULL || adj == NULL || stamp == NULL || tmp == NULL || sepw == NULL || stack == NULL || key == NULL ||
        cons == NULL || setlist == NULL || setptr == NULL || block == NULL || iw == NULL) {
        ls_arena_restore(arena, mark);
        if (diag != NULL) {
            diag->status = LS_ERR_NOMEM;
            diag->what = "arena too small for the ordering";
        }
        return LS_ERR_NOMEM;
    }
    if (n == 0) {
        ls_arena_restore(arena, mark);
        return LS_OK;
    }
    /* adjacency of A + A^T without the diagonal */
    memset(xadj, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (j = 0; j < n; j++)
        for (q = a->colptr[j]; q < a->colptr[j + 1u]; q++)
            if (a->rowidx[q] < j) {
                xadj[a->rowidx[q] + 1u]++;
                xadj[j + 1u]++;
            }
    for (j = 0; j < n; j++) xadj[j + 1u] += xadj[j];
    memcpy(tmp, xadj, (size_t)n * sizeof(uint32_t));
    for (j = 0; j < n; j++)
        for (q = a->colptr[j]; q < a->colptr[j + 1u]; q++) {
            uint32_t r = a->rowidx[q];
            if (r < j) {
                adj[tmp[r]++] = j;
                adj[tmp[j]++] = r;
            }
        }
    for (j = 0; j < n; j++) {
        perm[j] = j;
        stamp[j] = UINT32_MAX;
        cons[j] = 0;
    }
    stack[top++] = 0;
    stack[top++] = n;
    while (top > 0) {
        uint32_t hi = stack[--top], lo = stack[--top], mid, sa, sb, na = 0, nb = 0;
        uint32_t *v = perm;
        if (hi - lo <= ND_LEAF) continue; /* a leaf: ordered by the constrained minimum degree */
        /* candidate cut directions: the principal one and the three axes;
         * keep the one with the smallest separator (first on ties) */
        {
            /* principal direction, the 3 axes, the 6 face diagonals */
            static const signed char dirs[9][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, -1, 0},
                                                   {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};
            ls_real cand[ND_CAND][3];
            uint32_t c, best = UINT32_MAX, bi = 0, ncand, nanb[2];
            nd_ctx ctx;
            ctx.xyz = xyz;
            ctx.xadj = xadj;
            ctx.adj = adj;
            ctx.v = v;
            ctx.stamp = stamp;
            ctx.key = key;
            nd_direction(xyz, v + lo, hi - lo, cand[0]);
            for (c = 1; c < ND_CAND; c++) {
                cand[c][0] = (ls_real)dirs[c - 1u][0];
                cand[c][1] = (ls_real)dirs[c - 1u][1];
                cand[c][2] = (ls_real)dirs[c - 1u][2];
            }
            sa = 4u * task;
            sb = 4u * task + 1u;
            task++;
            if (task >= (1u << 29)) task = 0; /* stamps only need to differ from live ones */
            mid = lo + (hi - lo) / 2u;
            ncand = hi - lo > ND_FEW ? ND_CAND : 4u; /* small sets: fewer tries */
            for (c = 0; c < ncand; c++) {
                uint32_t sz = nd_cut(&ctx, lo, hi, cand[c], sa, nanb);
                if (sz < best) {
                    best = sz;
                    bi = c;
                }
            }
            if (bi != ncand - 1u) (void)nd_cut(&ctx, lo, hi, cand[bi], sa, nanb);
            na = nanb[0];
            nb = nanb[1];
        }
        /* the separator starts as the smaller boundary, then is refined */
        {
            uint32_t i, w1, w2, ws = 0, ss = sa + 2u, total = hi - lo, limit = total - total / 3u, cnt_a = 0, cnt_b = 0;
            uint32_t pass, keep_a = nb <= na;
            for (i = lo; i < hi; i++) {
                uint32_t u = v[i], other = stamp[u] == sa ? sb : sa, in_sep = 0;
                if (keep_a ? (i >= mid) : (i < mid)) {
                    uint32_t p;
                    for (p = xadj[u]; p < xadj[u + 1u]; p++)
                        if (stamp[adj[p]] == other) {
                            in_sep = 1;
                            break;
                        }
                }
                if (in_sep) sepw[lo + ws++] = u;
                else if (i < mid) cnt_a++;
                else cnt_b++;
            }
            for (i = 0; i < ws; i++) stamp[sepw[lo + i]] = ss;
            /* greedy vertex-separator refinement: move a separator vertex to
             * the side where fewer of its neighbours must join the separator;
             * gains > 0 always, gain 0 only towards the smaller side; a fixed
             * work budget per pass (deterministic, terminates) */
            for (pass = 0; pass < ND_PASSES && ws > 0; pass++) {
                uint32_t k = 0, budget = 4u * ws + 16u, moved = 0;
                while (k < ws && budget > 0) {
                    uint32_t u = sepw[lo + k++], p, n_a = 0, n_b = 0, to_a;
                    int32_t gain_a, gain_b, gain;
                    budget--;
                    if (stamp[u] != ss) continue;
                    for (p = xadj[u]; p < xadj[u + 1u]; p++) {
                        uint32_t st2 = stamp[adj[p]];
                        if (st2 == sa) n_a++;
                        else if (st2 == sb) n_b++;
                    }
                    gain_a = 1 - (int32_t)n_b;
                    gain_b = 1 - (int32_t)n_a;
                    if (gain_a != gain_b) to_a = gain_a > gain_b;
                    else to_a = cnt_a <= cnt_b;
                    gain = to_a ? gain_a : gain_b;
                    if (gain < 0) continue;
                    if (gain == 0 && (to_a ? cnt_a >= cnt_b : cnt_b >= cnt_a)) continue;
                    if ((to_a ? cnt_a : cnt_b) + 1u > limit) continue;
                    if (ws + (to_a ? n_b : n_a) > total) break; /* worklist full */
                    stamp[u] = to_a ? sa : sb;
                    if (to_a) cnt_a++;
                    else cnt_b++;
                    for (p = xadj[u]; p < xadj[u + 1u]; p++) {
                        uint32_t x = adj[p];
                        if (stamp[x] == (to_a ? sb : sa)) {
                            stamp[x] = ss;
                            if (to_a) cnt_b--;
                            else cnt_a--;
                            sepw[lo + ws++] = x;
                        }
                    }
                    moved++;
                }
                /* compact the worklist to the live separator, in order */
                {
                    uint32_t k2 = 0;
                    for (k = 0; k < ws; k++) {
                        uint32_t u = sepw[lo + k];
                        if (stamp[u] == ss) {
                            stamp[u] = ss + 1u; /* dedup mark */
                            sepw[lo + k2++] = u;
                        }
                    }
                    for (k = 0; k < k2; k++) stamp[sepw[lo + k]] = ss;
                    ws = k2;
                }
                if (moved == 0) break;
            }
            /* reorder: A, then B (original relative order), then the separator */
            w1 = lo;
            for (i = lo; i < hi; i++)
                if (stamp[v[i]] == sa) tmp[w1++] = v[i];
            w2 = w1;
            for (i = lo; i < hi; i++)
                if (stamp[v[i]] == sb) tmp[w2++] = v[i];
            for (i = lo; i < hi; i++)
                if (stamp[v[i]] == ss) tmp[w2++] = v[i];
            memcpy(v + lo, tmp + lo, (size_t)(hi - lo) * sizeof(uint32_t));
            for (i = w2 - ws; i < w2; i++) cons[v[i]] = (int32_t)(w2 - ws) + 1; /* its block */
            if (w1 > lo) {
                stack[top++] = lo;
                stack[top++] = w1;
            }
            if (w2 - ws > w1) {
                stack[top++] = w1;
                stack[top++] = w2 - ws;
            }
        }
    }
    /* constraint sets: all leaf vertices first (set 0), then each separator
     * in the order of perm (a separator follows the separators inside it);
     * minimum degree within the sets orders leaves and separators knowing
     * the whole graph */
    {
        int32_t nsets = 1, last = 0, k = 0;
        amd_sets sets;
        setptr[0] = 0;
        for (j = 0; j < n; j++)
            if (cons[perm[j]] == 0) setlist[k++] = (int32_t)perm[j];
        for (j = 0; j < n; j++) {
            uint32_t u = perm[j];
            if (cons[u] == 0) continue;
            if (cons[u] != last) {
                setptr[nsets++] = k;
                last = cons[u];
            }
            cons[u] = nsets - 1;
            setlist[k++] = (int32_t)u;
        }
        setptr[nsets] = k;
        sets.cons = cons;
        sets.setlist = setlist;
        sets.setptr = setptr;
        sets.nsets = nsets;
        if (amd_graph_run(a, block, iw, iwlen, tmp, &sets))
            memcpy(perm, tmp, (size_t)n * sizeof(uint32_t));
    }
    ls_arena_restore(arena, mark);
    return LS_OK;
}
