/* args.h - strict parsing of option values for every command of the
 * program: the whole string must be the number (no sign on counts, no
 * trailing characters, no wrap-around), in the option's range. On failure
 * each prints one line naming the command, the option and the range, e.g.
 *   largesteps fit: --iters: '5abc' is not a whole number in [0, 1000000]
 * and returns 0; the caller exits with status 2. */
#ifndef LS_ARGS_H
#define LS_ARGS_H

#include <stdint.h>

/* A whole number in [lo, hi]: decimal digits only. */
int ls_arg_u32(const char *cmd, const char *opt, const char *v, uint32_t lo, uint32_t hi, uint32_t *out);

/* A finite real number (the library's ls_parse_double grammar: no NaN, no
 * infinity) in [lo, hi]; lo_open / hi_open make an end open: (lo, hi]. */
int ls_arg_real(const char *cmd, const char *opt, const char *v, double lo, double hi, int open_ends,
                double *out);
#define LS_ARG_CLOSED 0
#define LS_ARG_LO_OPEN 1
#define LS_ARG_HI_OPEN 2

/* The options every command takes, removed from argv by main before the
 * command sees it: --max-input-mb N (the input limit, ls_posix.h). Returns
 * the new argc, or -1 after a message for a bad value. */
int ls_args_global(int argc, char **argv);

/* The line that --help of every command prints for the global options. */
#define LS_ARGS_GLOBAL_HELP                                                                            \
    "  --max-input-mb N   refuse input files larger than N MB, checked while reading (every command;\n"  \
    "                     default 256, 1..1048576)\n"

#endif /* LS_ARGS_H */
