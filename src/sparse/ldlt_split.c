/* ldlt_split.c - the k = 3 solve split over the caller's workers by subtrees
 * of the elimination tree, with the bits of the whole solve.
 *
 * The factor's columns are in postorder, so a subtree is a range of columns
 * and every column's rows are its ancestors. The plan picks a top T, the
 * last columns [t, n): the columns below t then form independent subtrees
 * (the pieces: the columns below t whose parent is in T), dealt to the
 * workers largest first, to the least loaded. Of the cuts t that keep T
 * within a third of the work, it takes the one with the least estimated
 * time (T's work + the most loaded worker's + its share of the held rows).
 *
 * Forward: each worker runs the whole solve's pass over its pieces but
 * holds back the updates of rows in T and leaves the columns that have such
 * rows unscaled. Then the workers apply the held updates, each to its own
 * rows of T, column by column in column order; every piece column precedes
 * every column of T, so each row of T receives the same subtractions in the
 * same order as in the whole solve. The calling thread scales the held
 * columns and runs T's forward and backward chunks (the last chunk may
 * reach down into the piece whose root is t - 1: chunks follow parent
 * chains), and the workers run their pieces' backward from there. No sum
 * changes its order, so the bits depend neither on the plan nor on the
 * worker count. */
#include <largesteps/ldlt.h>
#include <string.h>
#include "../base/parallel.h"
#include "ldlt_internal.h"

#define NONE UINT32_MAX

/* The largest worker count a plan takes (a bound for the sizes' products). */
#define SPLIT_MAX_WORKERS 4096u

/* The most tasks the held updates and the gather and scatter are split in. */
#define HELD_TASKS 16u

/* The heap of piece roots: heaviest first, lower column on ties. */
static int heavier(const uint64_t *wsum, uint32_t a, uint32_t b)
{
    const uint64_t wa = wsum[a], wb = wsum[b];
    if (wa != wb) return wa > wb;
    return a < b;
}

static void heap_push(uint32_t *heap, uint32_t *count, const uint64_t *wsum, uint32_t v)
{
    uint32_t i = (*count)++;
    while (i > 0) {
        uint32_t up = (i - 1u) / 2u;
        if (!heavier(wsum, v, heap[up])) break;
        heap[i] = heap[up];
        i = up;
    }
    heap[i] = v;
}

static uint32_t heap_pop(uint32_t *heap, uint32_t *count, const uint64_t *wsum)
{
    uint32_t top = heap[0], v, i = 0, m = --(*count);
    if (m == 0) return top;
    v = heap[m];
    for (;;) {
        uint32_t c = 2u * i + 1u;
        if (c >= m) break;
        if (c + 1u < m && heavier(wsum, heap[c + 1u], heap[c])) c++;
        if (!heavier(wsum, heap[c], v)) break;
        heap[i] = heap[c];
        i = c;
    }
    heap[i] = v;
    return top;
}

/* The plan's words: group and rows (W + 1 each), sub and held (3 n each). */
static size_t data_words(uint32_t n, uint32_t workers)
{
    return 2u * ((size_t)workers + 1u) + 6u * (size_t)n;
}

static uint32_t *plan_group(const ls_ldlt_split *sp) { return sp->data; }
static uint32_t *plan_rows(const ls_ldlt_split *sp) { return sp->data + sp->workers + 1u; }
static uint32_t *plan_sub(const ls_ldlt_split *sp) { return sp->data + 2u * ((size_t)sp->workers + 1u); }
static uint32_t *plan_held(const ls_ldlt_split *sp)
{
    return sp->data + 2u * ((size_t)sp->workers + 1u) + 3u * (size_t)sp->n;
}

static uint32_t held_tasks(const ls_ldlt_split *sp)
{
    return sp->workers < HELD_TASKS ? sp->workers : HELD_TASKS;
}

/* Object and build scratch, in the order ls_ldlt_split_init takes them. */
static ls_status split_sizes(uint32_t n, uint32_t workers, ls_size *object, ls_size *peak)
{
    if (workers == 0 || workers > SPLIT_MAX_WORKERS) return LS_ERR_INVALID;
    /* data_words stays below SIZE_MAX / 4 (a 32-bit size_t and a huge n) */
    if ((size_t)n > (SIZE_MAX / sizeof(uint32_t) - 2u * ((size_t)workers + 1u)) / 6u) return LS_ERR_TOO_LARGE;
    ls_size_init(object);
    ls_size_add(object, data_words(n, workers), sizeof(uint32_t)); /* group, rows, sub, held */
    *peak = *object;
    ls_size_add(peak, n, sizeof(uint64_t));       /* subtree weights */
    ls_size_add(peak, n, sizeof(uint32_t));       /* first column of each subtree */
    ls_size_add(peak, n, sizeof(uint32_t));       /* row counts of L, then each piece's worker */
    ls_size_add(peak, n, sizeof(uint32_t));       /* heap */
    ls_size_add(peak, workers, sizeof(uint64_t)); /* each worker's load */
    ls_size_add(peak, workers, sizeof(uint32_t)); /* the workers' heap, then fill positions */
    return LS_OK;
}

ls_status ls_ldlt_split_bytes_n(uint32_t n, uint32_t workers, size_t *object, size_t *peak)
{
    ls_size o, p;
    ls_status st;
    if (object == NULL || peak == NULL) return LS_ERR_INVALID;
    *object = *peak = 0;
    st = split_sizes(n, workers, &o, &p);
    if (st == LS_OK) st = ls_size_get(&o, object);
    if (st == LS_OK) st = ls_size_get(&p, peak);
    if (st != LS_OK) *object = *peak = 0;
    return st;
}

/* The build's scratch arrays. */
typedef struct plan_scratch {
    uint64_t *wsum, *load;
    uint32_t *first, *rowcount, *heap, *workers;
} plan_scratch;

static uint64_t column_weight(const ls_ldlt *f, uint32_t c)
{
    return (uint64_t)(f->lp[c + 1u] - f->lp[c]) + 1u;
}

/* Subtree weights, first columns and the row counts of L; the total. */
static uint64_t tree_sums(const ls_ldlt *f, plan_scratch *z)
{
    uint32_t n = f->n, c, t;
    uint64_t total = 0;
    for (c = 0; c < n; c++) {
        z->wsum[c] = column_weight(f, c);
        z->first[c] = c;
        z->rowcount[c] = 0;
    }
    for (t = 0; t < f->lp[n]; t++) z->rowcount[f->li[t]]++;
    for (c = 0; c < n; c++) { /* children precede parents */
        uint32_t p = f->parent[c];
        if (p == NONE) {
            total += z->wsum[c];
            continue;
        }
        z->wsum[p] += z->wsum[c];
        if (z->first[c] < z->first[p]) z->first[p] = z->first[c];
    }
    return total;
}

/* The cut t: moving column t - 1 into T takes its weight from the pieces,
 * makes its children pieces, and holds its row of L (entries from the
 * columns below) while its column's entries stop being held. The estimate
 * of each cut: T's work + max(the heaviest piece, the pieces' share) + the
 * share of the held updates (forward only: half an entry's weight). */
static uint32_t choose_cut(const ls_ldlt *f, uint32_t w, uint64_t total, plan_scratch *z)
{
    uint32_t n = f->n, t = n, best = n, count = 0, c;
    uint64_t top = 0, held = 0, best_time = total;
    if (w < 2u) return n;
    for (c = 0; c < n; c++)
        if (f->parent[c] == NONE) heap_push(z->heap, &count, z->wsum, c);
    while (t > 0) {
        uint64_t rest, heaviest = 0, time;
        uint32_t r = t - 1u, k;
        if ((top + column_weight(f, r)) * 3u > total) break;
        top += column_weight(f, r);
        held += (uint64_t)z->rowcount[r];
        held -= (uint64_t)(f->lp[r + 1u] - f->lp[r]);
        /* r's children, last first: r - 1, then the column before each
         * child's subtree while it stays in r's */
        for (k = r; k > z->first[r]; k = z->first[k - 1u]) heap_push(z->heap, &count, z->wsum, k - 1u);
        t = r;
        while (count > 0 && z->heap[0] >= t) (void)heap_pop(z->heap, &count, z->wsum); /* now in T */
        if (count > 0) heaviest = z->wsum[z->heap[0]];
        rest = (total - top + w - 1u) / w;
        time = top + (heaviest > rest ? heaviest : rest) + held / (2u * (uint64_t)w);
        if (time < best_time) {
            best_time = time;
            best = t;
        }
    }
    return best;
}

/* Deals the pieces (the columns below t whose parent is in T or none) to
 * the workers, heaviest first, to the least loaded; fills sub by worker. */
static void deal_pieces(ls_ldlt_split *sp, const ls_ldlt *f, plan_scratch *z)
{
    uint32_t c, g, count = 0, free_count = 0, w = sp->workers, t = sp->top;
    uint32_t *group = plan_group(sp), *sub = plan_sub(sp);
    uint32_t *worker = z->rowcount; /* reused: the row counts are no longer needed */
    uint64_t *slack = z->load;      /* UINT64_MAX - load: the least loaded is the "heaviest" */
    for (c = 0; c < t; c++)
        if (f->parent[c] == NONE || f->parent[c] >= t) heap_push(z->heap, &count, z->wsum, c);
    for (g = 0; g < w; g++) {
        slack[g] = UINT64_MAX;
        heap_push(z->workers, &free_count, slack, g);
    }
    for (g = 0; g <= w; g++) group[g] = 0;
    while (count > 0) {
        uint32_t r = heap_pop(z->heap, &count, z->wsum), best = heap_pop(z->workers, &free_count, slack);
        slack[best] -= z->wsum[r];
        heap_push(z->workers, &free_count, slack, best);
        worker[r] = best;
        group[best + 1u]++;
    }
    for (g = 0; g < w; g++) group[g + 1u] += group[g];
    for (g = 0; g < w; g++) z->workers[g] = group[g]; /* fill positions */
    for (c = 0; c < t; c++) {
        uint32_t *piece;
        if (f->parent[c] != NONE && f->parent[c] < t) continue;
        piece = sub + 3u * (size_t)z->workers[worker[c]]++;
        piece[0] = z->first[c];
        piece[1] = c + 1u;
        piece[2] = c + 1u == t ? sp->top_start : c + 1u; /* backward start */
    }
}

/* The held columns (piece columns with rows in T) in chunks of 1, 2 or 4
 * chained columns (they share their rows in T), and each worker's rows of
 * T, split by the held entries. */
static void held_lists(ls_ldlt_split *sp, const ls_ldlt *f, plan_scratch *z)
{
    uint32_t c = 0, g, t = sp->top, row = t, tasks = held_tasks(sp);
    uint32_t *rows = plan_rows(sp), *held = plan_held(sp);
    uint64_t entries = 0;
    uint32_t *count = z->rowcount; /* rows [t, n): the held entries of each row of T */
    uint64_t done = 0;
    for (g = t; g < f->n; g++) count[g] = 0;
    while (c < t) {
        const uint32_t m = ls_ldlt_fwd_chunk_width(f, c, t), last = c + m - 1u, end = f->lp[last + 1u];
        uint32_t o = end;
        while (o > f->lp[last] && f->li[o - 1u] >= t) o--;
        if (o != end) {
            uint32_t *h = held + 3u * (size_t)sp->held_chunks++, q;
            h[0] = c;
            h[1] = m;
            h[2] = o; /* the last column's first entry in T */
            entries += (uint64_t)(end - o) * m;
            for (q = o; q < end; q++) count[f->li[q]] += m;
        }
        c += m;
    }
    /* each task scans every held chunk: more than HELD_TASKS tasks would
     * cost more in scans than they share */
    rows[0] = t;
    for (g = 1; g < tasks; g++) { /* task g - 1 takes rows up to its share */
        uint64_t want = entries * g / tasks;
        while (row < f->n && done + count[row] <= want) done += count[row++];
        rows[g] = row;
    }
    rows[tasks] = f->n;
}

ls_status ls_ldlt_split_init(ls_ldlt_split *sp, const ls_ldlt *f, uint32_t workers, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_ldlt_split q;
    plan_scratch z;
    uint32_t n;
    if (sp == NULL || f == NULL || arena == NULL || workers == 0 || workers > SPLIT_MAX_WORKERS) return LS_ERR_INVALID;
    if (f->li == NULL || f->state == LS_LDLT_ANALYZED) return LS_ERR_STATE; /* the pattern of L comes with the factor */
    n = f->n;
    {
        ls_size object, peak;
        ls_status st = split_sizes(n, workers, &object, &peak);
        if (st != LS_OK) return st;
    }
    memset(&q, 0, sizeof q);
    q.n = n;
    q.workers = workers;
    mark = ls_arena_save(arena);
    q.data = (uint32_t *)ls_arena_alloc(arena, data_words(n, workers), sizeof(uint32_t));
    z.wsum = (uint64_t *)ls_arena_scratch(arena, n, sizeof(uint64_t));
    z.first = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    z.rowcount = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    z.heap = (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t));
    z.load = (uint64_t *)ls_arena_scratch(arena, workers, sizeof(uint64_t));
    z.workers = (uint32_t *)ls_arena_scratch(arena, workers, sizeof(uint32_t));
    if (q.data == NULL || z.wsum == NULL || z.first == NULL ||
        z.rowcount == NULL || z.heap == NULL || z.load == NULL || z.workers == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    {
        const uint64_t work = tree_sums(f, &z);
        if (work < LS_LDLT_SPLIT_MIN_WORK) q.workers = 1; /* whole: the data's layout keeps W */
        q.top = choose_cut(f, q.workers, work, &z);
    }
    for (q.top_start = q.top < n ? n : 0; q.top_start > q.top;) /* T's backward chunks, the last may reach below t */
        q.top_start = ls_ldlt_back_chunk_start(f, 0, q.top_start);
    if (q.top == n) q.top_start = n;
    if (q.workers > 1u) {
        deal_pieces(&q, f, &z);
        held_lists(&q, f, &z);
    }
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    *sp = q;
    return LS_OK;
}


ls_status ls_ldlt_split_get_stats(const ls_ldlt_split *sp, const ls_ldlt *f, ls_ldlt_split_stats *stats)
{
    uint32_t c, g, i;
    if (sp == NULL || f == NULL || stats == NULL || sp->n != f->n) return LS_ERR_INVALID;
    memset(stats, 0, sizeof *stats);
    for (c = 0; c < f->n; c++) {
        stats->work += column_weight(f, c);
        if (c >= sp->top) stats->top_work += column_weight(f, c);
    }
    if (sp->workers < 2u) {
        stats->max_load = stats->work;
        return LS_OK;
    }
    for (g = 0; g < sp->workers; g++) {
        uint64_t load = 0;
        for (i = plan_group(sp)[g]; i < plan_group(sp)[g + 1u]; i++)
            for (c = plan_sub(sp)[3u * (size_t)i]; c < plan_sub(sp)[3u * (size_t)i + 1u]; c++) load += column_weight(f, c);
        if (load > stats->max_load) stats->max_load = load;
    }
    stats->pieces = plan_group(sp)[sp->workers];
    for (i = 0; i < sp->held_chunks; i++) {
        const uint32_t *h = plan_held(sp) + 3u * (size_t)i;
        stats->held_entries += (uint64_t)(f->lp[h[0] + h[1]] - h[2]) * h[1];
    }
    return LS_OK;
}

typedef struct split_run {
    const ls_ldlt *f;
    const ls_ldlt_split *sp;
    ls_acc *w;
    ls_real *x;
    unsigned char finite[HELD_TASKS];/* each one's verdict */
} split_run;

static void move_range(const split_run *r, uint32_t i, uint32_t *lo, uint32_t *hi)
{
    const uint64_t n = r->f->n, moves = held_tasks(r->sp);
    *lo = (uint32_t)(n * i / moves);
    *hi = (uint32_t)(n * (i + 1u) / moves);
}

static void gather_task(void *arg, uint32_t i, uint32_t worker)
{
    split_run *r = (split_run *)arg;
    uint32_t lo, hi;
    (void)worker;
    move_range(r, i, &lo, &hi);
    r->finite[i] = (unsigned char)ls_ldlt_gather3(r->f, r->x, r->w, lo, hi);
}

static void scatter_task(void *arg, uint32_t i, uint32_t worker)
{
    split_run *r = (split_run *)arg;
    uint32_t lo, hi;
    (void)worker;
    move_range(r, i, &lo, &hi);
    r->finite[i] = (unsigned char)ls_ldlt_scatter3(r->f, r->w, r->x, lo, hi);
}

static int all_moved_finite(const split_run *r)
{
    uint32_t i;
    for (i = 0; i < held_tasks(r->sp); i++)
        if (!r->finite[i]) return 0;
    return 1;
}

static void forward_task(void *arg, uint32_t g, uint32_t worker)
{
    const split_run *r = (const split_run *)arg;
    uint32_t i;
    (void)worker;
    for (i = plan_group(r->sp)[g]; i < plan_group(r->sp)[g + 1u]; i++) {
        const uint32_t *t = plan_sub(r->sp) + 3u * (size_t)i;
        ls_ldlt_fwd3_range(r->f, r->w, t[0], t[1], t[1]);
    }
}

/* The held updates of worker g's rows of T, chunk by chunk in column
 * order, with the columns' unscaled values. */
static void held_task(void *arg, uint32_t g, uint32_t worker)
{
    const split_run *r = (const split_run *)arg;
    const ls_ldlt *f = r->f;
    const uint32_t lo = plan_rows(r->sp)[g], hi = plan_rows(r->sp)[g + 1u];
    uint32_t i, j;
    (void)worker;
    if (lo == hi) return;
    for (i = 0; i < r->sp->held_chunks; i++) {
        const uint32_t *h = plan_held(r->sp) + 3u * (size_t)i;
        const uint32_t c = h[0], m = h[1], last = c + m - 1u, end = f->lp[last + 1u];
        const ls_real *pc[4];
        uint32_t a = h[2], b = end, e;
        while (a < b) { /* the first entry with row >= lo (rows ascend) */
            const uint32_t mid = a + (b - a) / 2u;
            if (f->li[mid] < lo) a = mid + 1u;
            else b = mid;
        }
        for (e = a; e < end && f->li[e] < hi; e++) {
        }
        if (e == a) continue;
        for (j = 0; j < m; j++) /* column c + j: the chunk's later columns, then the last one's rows */
            pc[j] = f->lx + f->lp[c + j] + (m - 1u - j) + (a - f->lp[last]);
        ls_ldlt_fwd_rows3(m, e - a, f->li + a, pc, r->w + 3u * (size_t)c, r->w);
    }
}

static void backward_task(void *arg, uint32_t g, uint32_t worker)
{
    const split_run *r = (const split_run *)arg;
    uint32_t i;
    (void)worker;
    for (i = plan_group(r->sp)[g]; i < plan_group(r->sp)[g + 1u]; i++) {
        const uint32_t *t = plan_sub(r->sp) + 3u * (size_t)i;
        ls_ldlt_bwd3_range(r->f, r->w, t[0], t[2]);
    }
}

ls_status ls_ldlt_split_solve3(const ls_ldlt *f, const ls_ldlt_split *sp, const ls_parallel *par, ls_real *x,
                               ls_acc *w)
{
    split_run r;
    uint32_t i;
    r.f = f;
    r.sp = sp;
    r.w = w;
    r.x = x;
    ls_parallel_run(par, sp->workers, held_tasks(sp), gather_task, &r);
    if (!all_moved_finite(&r)) return LS_ERR_NONFINITE;
    ls_parallel_run(par, sp->workers, sp->workers, forward_task, &r);
    ls_parallel_run(par, sp->workers, held_tasks(sp), held_task, &r);
    for (i = 0; i < sp->held_chunks; i++) { /* the held scalings */
        const uint32_t *h = plan_held(sp) + 3u * (size_t)i;
        uint32_t c;
        for (c = h[0]; c < h[0] + h[1]; c++) {
            const ls_acc di = (ls_acc)f->dinv[c];
            w[3u * (size_t)c] *= di;
            w[3u * (size_t)c + 1u] *= di;
            w[3u * (size_t)c + 2u] *= di;
        }
    }
    ls_ldlt_fwd3_range(f, w, sp->top, f->n, f->n);
    ls_ldlt_bwd3_range(f, w, sp->top_start, f->n);
    ls_parallel_run(par, sp->workers, sp->workers, backward_task, &r);
    ls_parallel_run(par, sp->workers, held_tasks(sp), scatter_task, &r);
    return all_moved_finite(&r) ? LS_OK : LS_ERR_NONFINITE;
}
