/* parallel.h (src/base) - the library's one way to run tasks
 * (largesteps/parallel.h): on the caller's parallel-for, or on this thread. */
#ifndef LS_BASE_PARALLEL_H
#define LS_BASE_PARALLEL_H

#include <stddef.h>
#include <largesteps/parallel.h>

/* Runs task(arg, i, worker) for i < count: through p->run when there is one,
 * more than one worker and more than one task; else here, in index order, as
 * worker 0. Inline, so that the tasks' chains start in the caller's frame:
 * tests/tools/task_edges.txt names each caller's tasks for the stack check
 * (the call is through a pointer). */
static inline void ls_parallel_run(const ls_parallel *p, uint32_t workers, uint32_t count, ls_task_fn task, void *arg)
{
    uint32_t i;
    if (p != NULL && p->run != NULL && workers > 1u && count > 1u) {
        p->run(p->ctx, count, task, arg);
        return;
    }
    for (i = 0; i < count; i++) task(arg, i, 0u);
}

#endif /* LS_BASE_PARALLEL_H */
