/* lint_probe.c - a planted bug every static analyser must report (an
 * uninitialised read and a NULL dereference), so that lint.sh can tell a
 * working analyser from a silent one. Never part of the library. */
#include <stddef.h>

int lint_probe(int flag);
int lint_probe(int flag)
{
    int value;
    int *p = NULL;
    if (flag) value = 1;
    if (!flag) return *p;
    return value + (flag ? 0 : value);
}
