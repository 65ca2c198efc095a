/* cmd_render.c - `largesteps render` (arrives with its module). */
#include <stdio.h>
#include "commands.h"

int ls_cmd_render(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "largesteps: '%s' is not available yet\n", argv[0]);
    return 2;
}
