/* install_probe.c - a user's first program, built against an installed
 * largesteps through pkg-config (C and C++). Prints the ls_real it was built
 * for and the library's self-test result. */
#include <stdio.h>
#include <largesteps.h>

static LS_ARENA_BUFFER(work, 1024);

int main(void)
{
    ls_arena arena;
    ls_build_info info;
    ls_status st = ls_arena_init(&arena, work.bytes, sizeof work.bytes);
    if (st != LS_OK) {
        printf("arena: %s\n", ls_status_str(st));
        return 1;
    }
    ls_build_info_get(&info);
    st = ls_selftest(sizeof(ls_real));
    printf("%s %s %s\n", LS_REAL_NAME, info.real_name, ls_status_name(st));
    return st == LS_OK && ls_version() == LS_VERSION_NUMBER ? 0 : 1;
}
