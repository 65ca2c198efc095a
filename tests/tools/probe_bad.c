/* probe_bad.c - breaks every rule the hygiene checks enforce, so that the
 * checks are seen to fail on it (a check that cannot fail proves nothing).
 * Never part of the library. */
#include <stdlib.h>

int probe_counter;                 /* writable global state, no ls_ prefix */
static int probe_table[4] = {1, 2, 3, 4};

int probe_recurse(int n);
int probe_recurse(int n)           /* recursion */
{
    probe_table[n & 3]++;
    return n <= 0 ? probe_counter : probe_recurse(n - 1) + 1;
}

void *probe_alloc(size_t n);
void *probe_alloc(size_t n)        /* heap use */
{
    return malloc(n);
}
