/* memory.c - the program's working memory (ls_posix.h) */
#define _POSIX_C_SOURCE 200809L
#include "ls_posix.h"
#include <stdlib.h>
#include <unistd.h>

void *ls_posix_work_memory(size_t *bytes)
{
    const size_t floor = (size_t)1 << 30;
    size_t want = floor;
    void *mem;
    if (sizeof(size_t) >= 8u) {
        const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0) {
            const unsigned long long phys = (unsigned long long)pages * (unsigned long long)page;
            if (phys / 4u * 3u > (unsigned long long)floor) want = (size_t)(phys / 4u * 3u);
        }
    }
    mem = malloc(want); /* untouched pages are not committed */
    if (mem == NULL && want > floor) mem = malloc(want = floor);
    *bytes = mem != NULL ? want : 0u;
    return mem;
}
