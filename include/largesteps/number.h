/* largesteps/number.h - locale-free decimal text <-> float/double conversion.
 *
 * Parsing is correctly rounded (IEEE round-to-nearest-even) directly to the
 * target type: text -> float never goes through double, so it never rounds
 * twice. It uses integer arithmetic on a decimal digit buffer (800 significant
 * digits plus a "nonzero digits were dropped" flag, which is enough for exact
 * rounding of any input length), and single IEEE operations on exactly
 * representable operands for the short inputs of the fast path. The result
 * bits are therefore the same on every compiler, C library and architecture,
 * and never depend on the C locale (the decimal separator is always '.').
 *
 * Grammar accepted by ls_parse_double / ls_parse_float (the whole span must
 * match; no leading or trailing white space):
 *     number   = [sign] ( decimal | special )
 *     sign     = '+' | '-'
 *     decimal  = ( digits ['.' [digits]] | '.' digits ) [exponent]
 *     exponent = ('e' | 'E') [sign] digits
 *     special  = "inf" | "infinity" | "nan"        (any letter case)
 * So "1", "-2.", ".5", "+1e2", "2.e+1", "1E-7", "-inf", "NaN" are accepted;
 * "", "+", ".", "e5", "1e", "1e+", "3.1+e2", "0x1p3", "1,5", " 1", "1 ",
 * "nan(1)", "1_000" are rejected with LS_ERR_PARSE. Any number of digits and
 * leading or trailing zeros is accepted; the exponent may have any number of
 * digits (it saturates, so "1e99999999999999" overflows and
 * "1e-99999999999999" underflows as it should).
 *
 * Results: NaN is the quiet NaN with an empty payload (0x7ff8000000000000 /
 * 0x7fc00000, sign bit from the text). Values below half the smallest
 * subnormal become +-0 and values in the subnormal range are rounded
 * correctly (both LS_OK). Values at or above the overflow threshold (for
 * double, 2^1024 - 2^970, i.e. DBL_MAX plus half an ulp, and above) give
 * +-inf and LS_ERR_TOO_LARGE.
 *
 * Formatting writes 17 (double) or 9 (float) significant digits, correctly
 * rounded from the exact binary value, in the layout of C's "%.17g" / "%.9g"
 * (trailing zeros removed; "inf", "-inf", "nan", "-nan" for the specials),
 * so parsing the text gives back the same bits. No memory is used by any of
 * these functions; stack use is about 900 bytes.
 */
#ifndef LARGESTEPS_NUMBER_H
#define LARGESTEPS_NUMBER_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Buffer size (including the terminating NUL) that always suffices for
 * ls_format_double and ls_format_float. */
#define LS_NUMBER_CHARS 32u

/* ls_scan_number: the length of the longest prefix of text[0..len) that
 * matches the grammar above (0 when none does). Use it to find where a number
 * ends inside a longer string, then parse that span. O(length). */
size_t ls_scan_number(const char *text, size_t len);

/* ls_parse_double: text[0..len) (need not be NUL-terminated) to the
 * correctly rounded double. Errors: LS_ERR_INVALID (NULL out, or NULL text
 * with len > 0), LS_ERR_PARSE when the span does not match the grammar (*out
 * unchanged), LS_ERR_TOO_LARGE on overflow (*out = +-inf). O(length) for up
 * to 19 significant digits with a decimal exponent of at most 22; otherwise
 * O(800 * |exponent| / 18) digit operations at worst. No memory. */
ls_status ls_parse_double(const char *text, size_t len, double *out);

/* ls_parse_float: as ls_parse_double, correctly rounded directly to float
 * (overflow threshold FLT_MAX plus half an ulp). Uses no double arithmetic. */
ls_status ls_parse_float(const char *text, size_t len, float *out);

/* ls_format_double: writes v with 17 significant digits in the "%.17g"
 * layout, NUL-terminated, into buf[0..cap). Returns the length without the
 * NUL, or 0 (and buf[0] = 0 when cap > 0) if cap is too small; cap >=
 * LS_NUMBER_CHARS always suffices. Parsing the result with ls_parse_double
 * gives back v's bits (NaN payloads excepted). O(1) for typical values, up to
 * a few thousand digit operations for subnormals. No memory. */
size_t ls_format_double(double v, char *buf, size_t cap);

/* ls_format_float: as ls_format_double with 9 significant digits ("%.9g" of
 * the float's exact value); ls_parse_float of the text gives back v's bits. */
size_t ls_format_float(float v, char *buf, size_t cap);

/* The functions matching the build's ls_real. */
#if LS_REAL_IS_FLOAT
#define ls_parse_real ls_parse_float
#define ls_format_real ls_format_float
#else
#define ls_parse_real ls_parse_double
#define ls_format_real ls_format_double
#endif

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_NUMBER_H */
