/* clock.c - monotonic time for progress reports and benchmarks. */
#define _POSIX_C_SOURCE 199309L
#include <time.h>
#include "ls_posix.h"

uint64_t ls_posix_clock_ns(void *user)
{
    struct timespec ts;
    (void)user;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0) return 0;
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}
