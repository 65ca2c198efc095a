/* main.c - the `largesteps` command-line program (POSIX host).
 *
 *   largesteps info       the library's build configuration and self-test
 *   largesteps version    the version string
 *
 * The reconstruction commands (fit, remesh, render, ...) arrive with their
 * modules; every command reads files here and hands memory buffers to src/. */
#include <stdio.h>
#include <string.h>
#include "ls_posix.h"

static int usage(FILE *out)
{
    fprintf(out, "usage: largesteps <command>\n"
                 "  info      print the build configuration and run the self-test\n"
                 "  version   print the library version\n");
    return out == stderr ? 2 : 0;
}

static int cmd_info(void)
{
    ls_build_info info;
    ls_status st;
    ls_build_info_get(&info);
    st = ls_selftest(sizeof(ls_real));
    printf("largesteps %s\n", ls_version_string());
    printf("  ls_real          %s (%u bytes)\n", info.real_name, (unsigned)info.real_bytes);
    printf("  arena alignment  %u bytes\n", (unsigned)info.arena_align);
    printf("  pointer, size_t  %u, %u bytes\n", (unsigned)info.pointer_bytes, (unsigned)info.size_bytes);
    printf("  byte order       %s\n", info.big_endian ? "big-endian" : "little-endian");
    printf("  status messages  %s\n", info.status_strings ? "yes" : "names only");
    printf("  compiler         %s\n", info.compiler);
    printf("  self-test        %s: %s\n", ls_status_name(st), ls_status_str(st));
    return st == LS_OK ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc < 2) return usage(stderr);
    if (strcmp(argv[1], "info") == 0) return cmd_info();
    if (strcmp(argv[1], "version") == 0) {
        printf("%s\n", ls_version_string());
        return 0;
    }
    if (strcmp(argv[1], "help") == 0 || strcmp(argv[1], "--help") == 0) return usage(stdout);
    fprintf(stderr, "largesteps: unknown command '%s'\n", argv[1]);
    return usage(stderr);
}
