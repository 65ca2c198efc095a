/* largesteps/monitor.h - progress reports, cancellation and the caller's clock.
 *
 * Long calls (factorization, remeshing, fitting) take an optional
 * `ls_monitor *` (NULL: no reports). They call its progress callback at
 * natural boundaries (a block of columns, a remesh pass, an iteration); a
 * non-zero return cancels the call, which then returns LS_ERR_CANCELLED and
 * leaves its outputs and the arena as they were. The clock is the caller's
 * too (the library has no notion of time): port/posix supplies a monotonic
 * one, firmware can pass a cycle counter.
 */
#ifndef LARGESTEPS_MONITOR_H
#define LARGESTEPS_MONITOR_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ls_progress {
    const char *stage;   /* static name of the work, e.g. "ldlt.numeric" */
    uint64_t done;       /* units finished */
    uint64_t total;      /* units in all, 0 when not known in advance */
    uint64_t elapsed_ns; /* clock time since ls_monitor_start, 0 without a clock */
} ls_progress;

/* Return 0 to go on, anything else to cancel the call. */
typedef int32_t (*ls_progress_fn)(void *user, const ls_progress *progress);

/* A monotonic clock in nanoseconds (any origin). */
typedef uint64_t (*ls_clock_fn)(void *user);

typedef struct ls_monitor {
    ls_progress_fn progress; /* may be NULL */
    ls_clock_fn clock;       /* may be NULL */
    void *user;              /* passed to both callbacks */
    uint64_t start_ns;       /* set by ls_monitor_start */
} ls_monitor;

/* ls_monitor_start: records the clock's current time as the origin of
 * elapsed_ns. O(1). NULL is ignored. */
void ls_monitor_start(ls_monitor *monitor);

/* ls_monitor_elapsed_ns: clock time since ls_monitor_start, 0 without a
 * monitor or clock (or if the clock went backwards). O(1). */
uint64_t ls_monitor_elapsed_ns(const ls_monitor *monitor);

/* ls_monitor_report: calls the progress callback (if any) and returns
 * LS_ERR_CANCELLED when it asks to stop, else LS_OK. Library loops use it;
 * callers may use it in their own loops too. O(1) plus the callback. */
ls_status ls_monitor_report(const ls_monitor *monitor, const char *stage,
                            uint64_t done, uint64_t total);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_MONITOR_H */
