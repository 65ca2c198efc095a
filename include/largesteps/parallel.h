/* largesteps/parallel.h - parallelism the caller provides. The library
 * starts no thread: where work splits into independent tasks (the fit's
 * views, the self-intersection check's faces), it hands them to the caller's
 * parallel-for, and combines the tasks' results in an order that does not
 * depend on which worker ran which task. The results are therefore the same
 * bits for every worker count, and with no parallel-for at all.
 *
 * run(ctx, count, task, arg) must call task(arg, i, worker) exactly once for
 * each i < count, in any order and on any threads, with worker < W naming
 * the worker (W: the worker count the call was sized for; no two tasks at
 * once on one worker number: the number selects its buffers), and return
 * when every call has returned. run NULL: the calling thread runs every
 * task, as worker 0. */
#ifndef LARGESTEPS_PARALLEL_H
#define LARGESTEPS_PARALLEL_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef void (*ls_task_fn)(void *arg, uint32_t index, uint32_t worker);
typedef void (*ls_parallel_for_fn)(void *ctx, uint32_t count, ls_task_fn task, void *arg);
typedef struct ls_parallel {
    ls_parallel_for_fn run; /* NULL: the calling thread runs every task */
    void *ctx;
} ls_parallel;

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_PARALLEL_H */
