/* largesteps/math.h - deterministic elementary functions and safe conversions.
 *
 * C libraries differ in the last bit of sin, exp, pow (glibc vs newlib), so no
 * libm function other than sqrt sits on a path whose output is compared bit for
 * bit. These are the library's own: plain IEEE arithmetic in a fixed order,
 * no FMA contraction, constant tables only, so every target produces the same
 * bits. Each exists in double (ls_sin) and float (ls_sinf); the float versions
 * use float arithmetic only (a float build on a Cortex-M4 contains no double
 * arithmetic). The LS_R* macros pick the one that matches ls_real. Error
 * bounds are stated per function and tested against libm on dense samples
 * (tests/test_math.c prints the measured maxima); "ulp" is the spacing of the
 * format at the exact result.
 *
 * Common rules for all functions below:
 *  - Rounding mode must be round-to-nearest and subnormals must not be flushed
 *    (the IEEE default; LS_ERR_FPENV reports otherwise).
 *  - Every NaN result is the canonical quiet NaN (bits 0x7ff8000000000000,
 *    float 0x7fc00000), whatever the input NaN's sign or payload: hardware
 *    default NaNs differ between x86 and ARM, these do not. Functions that
 *    only move bits (fabs, copysign, floor, ...) return a NaN input unchanged.
 *  - Special values follow C99 Annex F; signed zeros are preserved where it
 *    says so (sin(-0) = -0, atan2(-0, -1) = -pi, pow(-0, 3) = -0, ...).
 *  - Subnormal inputs are exact inputs; subnormal outputs underflow gradually.
 *  - No function reads or writes errno or the floating-point flags on purpose
 *    (intermediate operations may raise inexact/overflow/underflow flags).
 *  - Costs are for a desktop x86-64 core and scale with the target's FPU; no
 *    function allocates, recurses or uses more than ~150 bytes of stack.
 */
#ifndef LARGESTEPS_MATH_H
#define LARGESTEPS_MATH_H

#include <math.h> /* sqrt, sqrtf for LS_RSQRT: correctly rounded everywhere */
#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- trigonometric ---------------------------------------------------- */

/* ls_sin, ls_sinf: sine of x in radians, for every finite x. The reduction
 * modulo pi/2 keeps the bound for all inputs: below 2^20 (float 2^10) with
 * pi/2 in exact chunks (152 bits, float 80), above by Payne-Hanek in integer
 * arithmetic on 224 bits of 2/pi, so sin(1e22) and sin(0x1p1023) are as
 * accurate as sin(1). Error < 1 ulp (measured max 0.76 ulp double, 0.75 ulp
 * float). sin(+-0) = +-0 (sign kept), sin(+-Inf) = NaN, |x| < 2^-27 (float
 * 2^-12) returns x, subnormals included. Cost ~25 flops for |x| <= pi/4, ~45
 * below 2^20, plus 14 32x32->64-bit integer multiplies beyond. */
double ls_sin(double x);
float ls_sinf(float x);

/* ls_cos, ls_cosf: cosine of x in radians, every finite x, reduced as ls_sin.
 * Error < 1 ulp (measured max 0.77 ulp double, 0.78 ulp float). cos(+-0) = 1,
 * cos(+-Inf) = NaN. Cost as ls_sin. */
double ls_cos(double x);
float ls_cosf(float x);

/* ls_sincos, ls_sincosf: *s = ls_sin(x) and *c = ls_cos(x), bit-identical to
 * the separate calls, sharing one argument reduction. Either pointer may be
 * NULL (that result is skipped). Cost ~1.3x one call. */
void ls_sincos(double x, double *s, double *c);
void ls_sincosf(float x, float *s, float *c);

/* ls_atan, ls_atanf: arctangent in [-pi/2, pi/2]. Reduction by a table of
 * atan(j/16) and the addition formula in double-double (float-float).
 * Error < 1 ulp (measured max 0.501 ulp double, 0.501 ulp float: nearly
 * always correctly rounded). atan(+-0) = +-0, atan(+-Inf) = +-pi/2 rounded,
 * |x| < 2^-27 (float 2^-12) returns x. Cost ~60 flops and one to three
 * divisions. */
double ls_atan(double x);
float ls_atanf(float x);

/* ls_atan2, ls_atan2f: angle of the point (x, y) in [-pi, pi], computed from
 * y/x (or x/y) carried as a double-double, without overflow or spurious
 * underflow of the quotient for any finite x, y. Error < 1 ulp (measured
 * max 0.501 ulp double, 0.501 ulp float). Special values as C99 F.9.1.4:
 * atan2(+-0, +0 or x > 0) = +-0, atan2(+-0, -0 or x < 0) = +-pi,
 * atan2(+-y, 0) = +-pi/2, atan2(+-y, +Inf) = +-0, atan2(+-y, -Inf) = +-pi,
 * atan2(+-Inf, x) = +-pi/2, atan2(+-Inf, +-Inf) = +-pi/4, +-3pi/4; any NaN
 * gives NaN. Cost ~70 flops and two or three divisions. */
double ls_atan2(double y, double x);
float ls_atan2f(float y, float x);

/* ---- exponential and logarithm ---------------------------------------- */

/* ls_exp, ls_expf: e^x. Error < 1 ulp: measured max 0.513 ulp double,
 * 0.526 ulp float for normal results; subnormal results (gradual underflow)
 * are rounded twice, measured max 0.75 ulp (bound 0.76). exp(-Inf) = +0,
 * exp(+Inf) = +Inf, overflow to +Inf above ln(DBL_MAX) ~ 709.78 (float
 * 88.72), +0 below about -745.13 (float -103.97); exp(+-0) = 1. Cost ~25
 * flops and a 1 KB (float 256 B) table. */
double ls_exp(double x);
float ls_expf(float x);

/* ls_log, ls_logf: natural logarithm. Error < 1 ulp (measured max 0.500 ulp
 * double, 0.500 ulp float: the double-double sum is nearly always correctly
 * rounded); log(1) = +0. log(+-0) = -Inf, log(x < 0) =
 * NaN, log(+Inf) = +Inf; subnormal x is exact. Cost ~40 flops and a 3 KB
 * (float 384 B) table. */
double ls_log(double x);
float ls_logf(float x);

/* ls_log10, ls_log10f: base-10 logarithm, the double-double natural log
 * times 1/ln 10. Error < 1 ulp (measured max 0.500 ulp double, 0.500 ulp
 * float); exact for exact powers of ten (log10(1000) = 3, log10(1e22) = 22).
 * Special values as ls_log. Cost ls_log + 10 flops. */
double ls_log10(double x);
float ls_log10f(float x);

/* ls_pow, ls_powf: x^y = exp(y log x) with log in double-double (float-float,
 * ~2^-70 and ~2^-40 relative) and the product's low part carried into exp.
 * Error < 1 ulp: measured max 0.514 ulp double, 0.527 ulp float for normal
 * results, 0.75 ulp for subnormal results (rounded twice, as ls_exp). Special
 * cases
 * of C99 F.9.4.4 (with C11's pow(+-0, -Inf) = +Inf): pow(x, +-0) = 1 for any
 * x even NaN; pow(+1, y) = 1 for any y even NaN; pow(-1, +-Inf) = 1;
 * pow(+-0, y) = +-Inf for odd integer y < 0, +Inf for other y < 0, +-0 for
 * odd integer y > 0, +0 for other y > 0; pow(x, -Inf) = +Inf for |x| < 1, +0
 * for |x| > 1; pow(x, +Inf) the reverse; pow(-Inf, y) = -0 / -Inf for odd
 * integer y < 0 / > 0, else +0 / +Inf; pow(+Inf, y) = +0 for y < 0, +Inf for
 * y > 0; pow(x < 0 finite, y finite non-integer) = NaN; a negative x with an
 * odd integer y gives a negative result. Overflow gives +-Inf, underflow
 * gradual then +-0. Cost ~ ls_log + ls_exp + 20 flops. */
double ls_pow(double x, double y);
float ls_powf(float x, float y);

/* ---- rounding and bit-level helpers (exact, any flags) ----------------- */

/* ls_floor, ls_ceil, ls_trunc, ls_round (+f): round to an integral value
 * downward, upward, toward zero, and to nearest with halfway cases away from
 * zero (C99 round). Exact, by bit manipulation (no libm, no conversion to an
 * integer type), correct for every double including |x| >= 2^52 (returned
 * as is), +-0 and values that round to zero (sign kept: floor(-0.0) = -0,
 * ceil(-0.5) = -0, round(-0.4) = -0), +-Inf (returned) and NaN (returned
 * unchanged). Cost a few integer operations. */
double ls_floor(double x);
float ls_floorf(float x);
double ls_ceil(double x);
float ls_ceilf(float x);
double ls_trunc(double x);
float ls_truncf(float x);
double ls_round(double x);
float ls_roundf(float x);

/* ls_fabs, ls_copysign (+f): |x| and |x| with the sign bit of y, by clearing
 * or copying the sign bit (exact for every input, NaN payload kept). O(1). */
double ls_fabs(double x);
float ls_fabsf(float x);
double ls_copysign(double x, double y);
float ls_copysignf(float x, float y);

/* ls_isnan, ls_isfinite, ls_isinf (+f): classification by inspecting the
 * bits, so they keep working under -ffast-math / -ffinite-math-only, where
 * the compiler may fold x != x to false. Return 1 or 0. O(1). */
int ls_isnan(double x);
int ls_isnanf(float x);
int ls_isfinite(double x);
int ls_isfinitef(float x);
int ls_isinf(double x);
int ls_isinff(float x);

/* ---- float-to-integer conversions -------------------------------------- */

/* ls_to_i32, ls_to_u32, ls_to_i64 (+f): truncate toward zero (like a C cast)
 * and saturate: values above the type's range give its maximum (INT32_MAX,
 * UINT32_MAX, INT64_MAX), values below give its minimum (INT32_MIN, 0,
 * INT64_MIN), +Inf and -Inf saturate likewise, and NaN gives 0. A plain C cast
 * of an out-of-range value or NaN is undefined behaviour, and in practice x86
 * returns 0x80000000 where ARM saturates; these are the same everywhere.
 * Exact within range (ls_to_u32(-0.7) = 0, ls_to_i32(2147483647.9) =
 * INT32_MAX). O(1). */
int32_t ls_to_i32(double x);
int32_t ls_to_i32f(float x);
uint32_t ls_to_u32(double x);
uint32_t ls_to_u32f(float x);
int64_t ls_to_i64(double x);
int64_t ls_to_i64f(float x);

/* ---- type-generic for ls_real ------------------------------------------ */

/* Each LS_R* macro calls the double or the float function according to
 * LS_REAL_IS_FLOAT; arguments should be ls_real. LS_RSQRT is the C library's
 * sqrt/sqrtf (IEEE correctly rounded, hence deterministic), the only libm
 * function the library uses. */
#if LS_REAL_IS_FLOAT
#define LS_RSIN(x) ls_sinf(x)
#define LS_RCOS(x) ls_cosf(x)
#define LS_RSINCOS(x, s, c) ls_sincosf((x), (s), (c))
#define LS_RATAN(x) ls_atanf(x)
#define LS_RATAN2(y, x) ls_atan2f((y), (x))
#define LS_REXP(x) ls_expf(x)
#define LS_RLOG(x) ls_logf(x)
#define LS_RLOG10(x) ls_log10f(x)
#define LS_RPOW(x, y) ls_powf((x), (y))
#define LS_RSQRT(x) sqrtf(x)
#define LS_RFLOOR(x) ls_floorf(x)
#define LS_RCEIL(x) ls_ceilf(x)
#define LS_RTRUNC(x) ls_truncf(x)
#define LS_RROUND(x) ls_roundf(x)
#define LS_RFABS(x) ls_fabsf(x)
#define LS_RCOPYSIGN(x, y) ls_copysignf((x), (y))
#define LS_RISNAN(x) ls_isnanf(x)
#define LS_RISFINITE(x) ls_isfinitef(x)
#define LS_RISINF(x) ls_isinff(x)
#define LS_RTO_I32(x) ls_to_i32f(x)
#define LS_RTO_U32(x) ls_to_u32f(x)
#define LS_RTO_I64(x) ls_to_i64f(x)
#else
#define LS_RSIN(x) ls_sin(x)
#define LS_RCOS(x) ls_cos(x)
#define LS_RSINCOS(x, s, c) ls_sincos((x), (s), (c))
#define LS_RATAN(x) ls_atan(x)
#define LS_RATAN2(y, x) ls_atan2((y), (x))
#define LS_REXP(x) ls_exp(x)
#define LS_RLOG(x) ls_log(x)
#define LS_RLOG10(x) ls_log10(x)
#define LS_RPOW(x, y) ls_pow((x), (y))
#define LS_RSQRT(x) sqrt(x)
#define LS_RFLOOR(x) ls_floor(x)
#define LS_RCEIL(x) ls_ceil(x)
#define LS_RTRUNC(x) ls_trunc(x)
#define LS_RROUND(x) ls_round(x)
#define LS_RFABS(x) ls_fabs(x)
#define LS_RCOPYSIGN(x, y) ls_copysign((x), (y))
#define LS_RISNAN(x) ls_isnan(x)
#define LS_RISFINITE(x) ls_isfinite(x)
#define LS_RISINF(x) ls_isinf(x)
#define LS_RTO_I32(x) ls_to_i32(x)
#define LS_RTO_U32(x) ls_to_u32(x)
#define LS_RTO_I64(x) ls_to_i64(x)
#endif

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_MATH_H */
