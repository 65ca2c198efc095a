/* largesteps/math.h - deterministic elementary functions and safe conversions.
 *
 * C libraries differ in the last bit of sin, exp, pow (glibc vs newlib), so no
 * libm function other than sqrt sits on a path whose output is compared bit for
 * bit. These are the library's own: plain IEEE arithmetic in a fixed order,
 * no FMA contraction, no table lookups that depend on the platform, so every
 * target produces the same bits. Each exists in double (ls_sin) and float
 * (ls_sinf); the float versions use float arithmetic only (a float build on a
 * Cortex-M4 contains no double arithmetic). The LS_R* macros pick the one that
 * matches ls_real. Error bounds are stated per function and tested against libm
 * on dense samples.
 */
#ifndef LARGESTEPS_MATH_H
#define LARGESTEPS_MATH_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Placeholder declarations; the bounds are filled in with the implementation. */
double ls_sin(double x);
float ls_sinf(float x);
double ls_cos(double x);
float ls_cosf(float x);
double ls_atan2(double y, double x);
float ls_atan2f(float y, float x);
double ls_exp(double x);
float ls_expf(float x);
double ls_log(double x);
float ls_logf(float x);
double ls_pow(double x, double y);
float ls_powf(float x, float y);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_MATH_H */
