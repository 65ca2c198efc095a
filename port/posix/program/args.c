/* args.c - strict option values (args.h). */
#include <stdio.h>
#include <string.h>
#include <stdint.h>
#include "args.h"
#include "ls_posix.h"

int ls_arg_u32(const char *cmd, const char *opt, const char *v, uint32_t lo, uint32_t hi, uint32_t *out)
{
    uint64_t x = 0;
    const char *c = v;
    int ok = v != NULL && *v != '\0';
    for (; ok && *c != '\0'; c++) {
        if (*c < '0' || *c > '9') ok = 0;
        else if ((x = x * 10u + (uint64_t)(*c - '0')) > (uint64_t)UINT32_MAX) ok = 0;
    }
    if (ok && (x < lo || x > hi)) ok = 0;
    if (!ok) {
        fprintf(stderr, "largesteps %s: %s: '%s' is not a whole number in [%lu, %lu]\n", cmd, opt,
                v != NULL ? v : "", (unsigned long)lo, (unsigned long)hi);
        return 0;
    }
    *out = (uint32_t)x;
    return 1;
}

int ls_arg_real(const char *cmd, const char *opt, const char *v, double lo, double hi, int open_ends, double *out)
{
    double x = 0;
    int ok = v != NULL && ls_parse_double(v, strlen(v), &x) == LS_OK && x == x && x - x == 0;
    if (ok && ((open_ends & LS_ARG_LO_OPEN) ? !(x > lo) : !(x >= lo))) ok = 0;
    if (ok && ((open_ends & LS_ARG_HI_OPEN) ? !(x < hi) : !(x <= hi))) ok = 0;
    if (!ok) {
        fprintf(stderr, "largesteps %s: %s: '%s' is not a number in %c%.9g, %.9g%c\n", cmd, opt, v != NULL ? v : "",
                (open_ends & LS_ARG_LO_OPEN) ? '(' : '[', lo, hi, (open_ends & LS_ARG_HI_OPEN) ? ')' : ']');
        return 0;
    }
    *out = x;
    return 1;
}

int ls_args_global(int argc, char **argv)
{
    int i, n = 1;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--max-input-mb") == 0) {
            uint32_t mb = 0;
            if (i + 1 >= argc) {
                fprintf(stderr, "largesteps: --max-input-mb needs a value\n");
                return -1;
            }
            if (!ls_arg_u32(argv[1], "--max-input-mb", argv[i + 1], 1, 1048576u, &mb)) return -1;
            {
                size_t lim = (size_t)mb;
                ls_posix_set_input_limit(lim > (SIZE_MAX >> 20) ? SIZE_MAX : lim << 20);
            }
            i++;
            continue;
        }
        argv[n++] = argv[i];
    }
    argv[n] = NULL;
    return n;
}
