/* parallel.c - a pool of POSIX threads for the fit's parallel-for (fit.h's
 * ls_parallel): workers - 1 threads that wait for work, and the calling
 * thread as worker 0. Tasks are handed out one at a time under a mutex (a
 * task is a view or a range of a few thousand values: the lock is not what
 * costs); which worker runs which task does not change the fit's bits. */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>
#include "ls_posix.h"

struct ls_posix_pool {
    pthread_mutex_t lock;
    pthread_cond_t start, done;
    pthread_t *threads;
    uint32_t workers, started; /* threads started: workers - 1 unless creation failed */
    uint64_t generation;       /* counts the runs: a thread works once per run */
    uint32_t count, next, busy; /* the run's tasks, the next to hand out, threads still in it */
    ls_task_fn task;
    void *arg;
    int quit;
};

/* Takes the run's tasks until none is left. */
static void drain(ls_posix_pool *p, uint32_t worker)
{
    for (;;) {
        uint32_t i;
        pthread_mutex_lock(&p->lock);
        i = p->next < p->count ? p->next++ : p->count;
        pthread_mutex_unlock(&p->lock);
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
    uint64_t seen = 0;
    free(t);
    for (;;) {
        pthread_mutex_lock(&p->lock);
        while (!p->quit && p->generation == seen) pthread_cond_wait(&p->start, &p->lock);
        if (p->quit) {
            pthread_mutex_unlock(&p->lock);
            return NULL;
        }
        seen = p->generation;
        pthread_mutex_unlock(&p->lock);
        drain(p, worker);
        pthread_mutex_lock(&p->lock);
        if (--p->busy == 0) pthread_cond_signal(&p->done);
        pthread_mutex_unlock(&p->lock);
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
    p->next = 0;
    p->busy = p->started;
    p->generation++;
    pthread_cond_broadcast(&p->start);
    pthread_mutex_unlock(&p->lock);
    drain(p, 0);
    pthread_mutex_lock(&p->lock);
    while (p->busy > 0) pthread_cond_wait(&p->done, &p->lock);
    pthread_mutex_unlock(&p->lock);
}
