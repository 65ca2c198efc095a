/* cmd_toy1d.c - `largesteps toy1d` (arrives with its module). */
#include <stdio.h>
#include "commands.h"

int ls_cmd_toy1d(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "largesteps: '%s' is not available yet\n", argv[0]);
    return 2;
}
