/* monitor.c - progress reports and cancellation through the caller's callback. */
#include <largesteps/monitor.h>
#include <largesteps/status.h>

void ls_monitor_start(ls_monitor *monitor)
{
    if (monitor == NULL) return;
    monitor->start_ns = monitor->clock != NULL ? monitor->clock(monitor->user) : 0;
}

uint64_t ls_monitor_elapsed_ns(const ls_monitor *monitor)
{
    uint64_t now;
    if (monitor == NULL || monitor->clock == NULL) return 0;
    now = monitor->clock(monitor->user);
    return now >= monitor->start_ns ? now - monitor->start_ns : 0;
}

ls_status ls_monitor_report(const ls_monitor *monitor, const char *stage,
                            uint64_t done, uint64_t total)
{
    ls_progress progress;
    if (monitor == NULL || monitor->progress == NULL) return LS_OK;
    progress.stage = stage != NULL ? stage : "";
    progress.done = done;
    progress.total = total;
    progress.elapsed_ns = ls_monitor_elapsed_ns(monitor);
    return monitor->progress(monitor->user, &progress) != 0 ? LS_ERR_CANCELLED : LS_OK;
}
