/* tests/sweep.h - the arena-size sweep every object's sizing query must pass.
 *
 * Given a job (a call that builds something into an arena), its sizing
 * query's answer and a hash of the state the call must not change when it
 * fails (its inputs and its output object), sweep_arena() runs the call with
 * arenas smaller than the answer and asserts, at each size:
 *   - the call returns LS_ERR_NOMEM,
 *   - the hashed state is unchanged (no partial object, inputs untouched),
 *   - the arena is back where it was (both ends);
 * and at the answer: the call succeeds, and for an exact query its peak use is
 * exactly the answer. Sizes: every byte count when the answer is small,
 * otherwise every size at which one more allocation fails (the arena reports
 * the capacity the failed request needed: that is the next size to try).
 * The buffer is filled with 0xA5 before each run so that code relying on
 * zeroed memory shows.
 */
#ifndef LS_TEST_SWEEP_H
#define LS_TEST_SWEEP_H

#include <stdlib.h>
#include "test.h"

typedef struct sweep_job {
    const char *name;
    ls_status (*run)(void *ctx, ls_arena *arena); /* may be called many times */
    uint64_t (*state_hash)(void *ctx);           /* inputs + output object */
    void (*reset)(void *ctx);                    /* optional: undo a success before the next run */
    void *ctx;
    size_t answer;  /* the sizing query's answer */
    int exact;      /* 1 for an exact query, 0 for a bound */
    int quiet;      /* 1: count problems without printing (to test the sweep itself) */
} sweep_job;

#define SWEEP_EVERY_BYTE_UP_TO 4096u

static int sweep_once_(const sweep_job *job, unsigned char *buf, size_t size, ls_status *st, ls_arena *arena)
{
    int problems = 0;
    uint64_t before = job->state_hash(job->ctx), after;
    memset(buf, 0xA5, size + LS_ARENA_ALIGN);
    if (ls_arena_init(arena, buf, size) != LS_OK) return 1;
    *st = job->run(job->ctx, arena);
    after = job->state_hash(job->ctx);
    if (*st != LS_OK) {
        if (*st != LS_ERR_NOMEM) {
            problems++;
            if (!job->quiet) printf("     sweep %s: size %lu returned %s, wanted LS_ERR_NOMEM\n", job->name, (unsigned long)size, ls_status_name(*st));
        }
        if (after != before) {
            problems++;
            if (!job->quiet) printf("     sweep %s: size %lu changed its inputs or left a partial object\n", job->name, (unsigned long)size);
        }
        if (arena->bottom != 0 || arena->top != 0) {
            problems++;
            if (!job->quiet) printf("     sweep %s: size %lu left %lu+%lu bytes in the arena\n", job->name, (unsigned long)size, (unsigned long)arena->bottom, (unsigned long)arena->top);
        }
    }
    return problems;
}

/* Returns the number of problems found (0 = the job passes). */
static int sweep_arena(const sweep_job *job)
{
    int problems = 0;
    size_t size = 0, tries = 0;
    ls_status st = LS_OK;
    ls_arena arena;
    unsigned char *buf = (unsigned char *)malloc(job->answer + 2 * LS_ARENA_ALIGN);
    if (buf == NULL) return 1;
    if (job->answer <= SWEEP_EVERY_BYTE_UP_TO) {
        for (size = 0; size < job->answer; size++) {
            problems += sweep_once_(job, buf, size, &st, &arena);
            tries++;
            if (st == LS_OK) {
                if (job->reset != NULL) job->reset(job->ctx);
                if (!job->exact) break; /* a bound may be generous */
                /* an exact query that succeeds below its answer is wrong */
                problems++;
                if (!job->quiet) printf("     sweep %s: succeeded with %lu bytes < exact answer %lu\n", job->name, (unsigned long)size, (unsigned long)job->answer);
                break;
            }
        }
    } else {
        for (;;) {
            problems += sweep_once_(job, buf, size, &st, &arena);
            tries++;
            if (st != LS_ERR_NOMEM) break;
            if (arena.need <= size || arena.need > job->answer) {
                problems++;
                if (!job->quiet) printf("     sweep %s: after failing at %lu the arena asks for %lu (answer %lu)\n", job->name, (unsigned long)size, (unsigned long)arena.need, (unsigned long)job->answer);
                break;
            }
            size = arena.need;
        }
        if (st == LS_OK && job->reset != NULL) job->reset(job->ctx);
        if (st == LS_OK && job->exact && size != job->answer) {
            problems++;
            if (!job->quiet) printf("     sweep %s: succeeded at %lu, exact answer is %lu\n", job->name, (unsigned long)size, (unsigned long)job->answer);
        }
    }
    /* At the answer itself the call must succeed; an exact query is also the peak. */
    problems += sweep_once_(job, buf, job->answer, &st, &arena);
    if (st != LS_OK) {
        problems++;
        if (!job->quiet) printf("     sweep %s: failed with %s at the answer %lu\n", job->name, ls_status_name(st), (unsigned long)job->answer);
    } else if (job->exact && arena.peak != (job->answer & ~(size_t)(LS_ARENA_ALIGN - 1))) {
        problems++;
        if (!job->quiet) printf("     sweep %s: peak %lu, exact answer %lu\n", job->name, (unsigned long)arena.peak, (unsigned long)job->answer);
    }
    if (st == LS_OK && job->reset != NULL) job->reset(job->ctx);
    free(buf);
    (void)tries;
    return problems;
}

#endif /* LS_TEST_SWEEP_H */
