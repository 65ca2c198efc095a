/* parallel.c - a pool of POSIX threads for the fit's parallel-for (fit.h's
 * ls_parallel): workers - 1 threads that wait for work, and the calling
 * thread as worker 0. Tasks are handed out one at a time from a shared
 * counter; which worker runs which task does not change the fit's bits.
 *
 * An iteration hands out about ten runs, some of a fraction of a
 * millisecond, with short serial stretches (a solve) between them. A thread
 * that slept on a condition variable between every two runs would be woken
 * tens of microseconds late each time, so a thread that finishes its tasks,
 * and the caller waiting for the others, first watch the run's counters for
 * a short while (SPIN_NS) and only then sleep. The counters are read and
 * written with the compiler's atomic builtins where it has them (gcc and
 * clang); elsewhere every access takes the lock and nobody spins. */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#include "ls_posix.h"

/* How long a thread watches for the next run before it sleeps: longer than
 * the serial stretches within an iteration, short against a remesh. */
#define SPIN_NS 200000

struct ls_posix_pool {
    pthread_mutex_t lock;
    pthread_cond_t start, done;
    pthread_t *threads;
    uint32_t workers, started; /* threads started: workers - 1 unless creation failed */
    uint32_t generation;       /* counts the runs: a thread works once per run */
    uint32_t count, next, busy; /* the run's tasks, the next to hand out, threads still in it */
    ls_task_fn task;
    void *arg;
    int quit;
};

#if defined(__GNUC__) || defined(__clang__)
#define HAVE_ATOMICS 1
static uint32_t load_u32(ls_posix_pool *p, const uint32_t *v)
{
    (void)p;
    return __atomic_load_n(v, __ATOMIC_ACQUIRE);
}
static uint32_t fetch_add_u32(ls_posix_pool *p, uint32_t *v, uint32_t x)
{
    (void)p;
    return __atomic_fetch_add(v, x, __ATOMIC_ACQ_REL);
}
/* under the lock: */
static uint32_t load_locked_u32(const uint32_t *v) { return __atomic_load_n(v, __ATOMIC_ACQUIRE); }
static void store_locked_u32(uint32_t *v, uint32_t x) { __atomic_store_n(v, x, __ATOMIC_RELEASE); }
#else
#define HAVE_ATOMICS 0
static uint32_t load_u32(ls_posix_pool *p, const uint32_t *v)
{
    uint32_t x;
    pthread_mutex_lock(&p->lock);
    x = *v;
    pthread_mutex_unlock(&p->lock);
    return x;
}
static uint32_t fetch_add_u32(ls_posix_pool *p, uint32_t *v, uint32_t x)
{
    uint32_t old;
    pthread_mutex_lock(&p->lock);
    old = *v;
    *v = old + x;
    pthread_mutex_unlock(&p->lock);
    return old;
}
static uint32_t load_locked_u32(const uint32_t *v) { return *v; }
static void store_locked_u32(uint32_t *v, uint32_t x) { *v = x; }
#endif

/* Watches *v until (*v == x) is `until_equal` or SPIN_NS pass; returns
 * whether it got there. */
static int spin(ls_posix_pool *p, const uint32_t *v, uint32_t x, int until_equal)
{
    struct timespec t0, t;
    uint32_t k = 0;
    if (!HAVE_ATOMICS) return 0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (;;) {
        if ((load_u32(p, v) == x) == until_equal) return 1;
        if (++k % 64u != 0u) continue;
        clock_gettime(CLOCK_MONOTONIC, &t);
        if ((int64_t)(t.tv_sec - t0.tv_sec) * 1000000000 + (t.tv_nsec - t0.tv_nsec) > SPIN_NS) return 0;
    }
}

/* Takes the run's tasks until none is left. */
static void drain(ls_posix_pool *p, uint32_t worker)
{
    for (;;) {
        const uint32_t i = fetch_add_u32(p, &p->next, 1u);
        if (i >= p->count) return;
        p->task(p->arg, i, worker);
    }
}

typedef struct pool_thread {
    ls_posix_pool *pool;
    uint32_t worker;
} pool_thread;

static void *thread_main(void *arg)
{
    pool_thread *t = (pool_thread *)arg;
    ls_posix_pool *p = t->pool;
    const uint32_t worker = t->worker;
    uint32_t seen = 0;
    free(t);
    for (;;) {
        if (!spin(p, &p->generation, seen, 0)) {
            pthread_mutex_lock(&p->lock);
            while (!p->quit && p->generation == seen) pthread_cond_wait(&p->start, &p->lock);
            if (p->quit) {
                pthread_mutex_unlock(&p->lock);
                return NULL;
            }
            pthread_mutex_unlock(&p->lock);
        }
        seen = load_u32(p, &p->generation); /* the run's task, arg and count were written before it */
        drain(p, worker);
        if (fetch_add_u32(p, &p->busy, (uint32_t)-1) == 1u) { /* the last thread out wakes the caller */
            pthread_mutex_lock(&p->lock);
            pthread_cond_signal(&p->done);
            pthread_mutex_unlock(&p->lock);
        }
    }
}

uint32_t ls_posix_cores(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1u : n > (long)LS_FIT_MAX_WORKERS ? LS_FIT_MAX_WORKERS : (uint32_t)n;
}

ls_posix_pool *ls_posix_pool_create(uint32_t workers)
{
    ls_posix_pool *p;
    uint32_t k;
    if (workers == 0 || workers > LS_FIT_MAX_WORKERS) return NULL;
    p = (ls_posix_pool *)calloc(1, sizeof *p);
    if (p == NULL) return NULL;
    p->workers = workers;
    p->threads = (pthread_t *)calloc(workers, sizeof(pthread_t));
    if (p->threads == NULL || pthread_mutex_init(&p->lock, NULL) != 0) {
        free(p->threads);
        free(p);
        return NULL;
    }
    if (pthread_cond_init(&p->start, NULL) != 0 || pthread_cond_init(&p->done, NULL) != 0) {
        pthread_mutex_destroy(&p->lock);
        free(p->threads);
        free(p);
        return NULL;
    }
    for (k = 1; k < workers; k++) {
        pool_thread *t = (pool_thread *)malloc(sizeof *t);
        if (t == NULL) break;
        t->pool = p;
        t->worker = k;
        if (pthread_create(&p->threads[k - 1u], NULL, thread_main, t) != 0) {
            free(t);
            break;
        }
        p->started++;
    }
    if (p->started + 1u < workers) { /* fewer threads than asked: refuse rather than run slower than said */
        ls_posix_pool_destroy(p);
        return NULL;
    }
    return p;
}

void ls_posix_pool_destroy(ls_posix_pool *p)
{
    uint32_t k;
    if (p == NULL) return;
    pthread_mutex_lock(&p->lock);
    p->quit = 1;
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->lock);
    for (k = 0; k < p->started; k++) pthread_join(p->threads[k], NULL);
    pthread_cond_destroy(&p->start);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->lock);
    free(p->threads);
    free(p);
}

void ls_posix_pool_run(void *pool, uint32_t count, ls_task_fn task, void *arg)
{
    ls_posix_pool *p = (ls_posix_pool *)pool;
    uint32_t i;
    if (p == NULL || p->started == 0 || count < 2u) { /* no thread to share with */
        for (i = 0; i < count; i++) task(arg, i, 0);
        return;
    }
    pthread_mutex_lock(&p->lock);
    p->task = task;
    p->arg = arg;
    p->count = count;
    store_locked_u32(&p->next, 0);
    store_locked_u32(&p->busy, p->started);
    store_locked_u32(&p->generation, p->generation + 1u); /* releases the fields above to the spinning threads */
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->lock);
    drain(p, 0);
    if (spin(p, &p->busy, 0u, 1)) return;
    pthread_mutex_lock(&p->lock);
    while (load_locked_u32(&p->busy) > 0u) pthread_cond_wait(&p->done, &p->lock);
    pthread_mutex_unlock(&p->lock);
}
