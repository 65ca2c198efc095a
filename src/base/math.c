/* src/base/math.c - exact helpers of the math module: rounding to integral values,
 * sign and classification by bit inspection, saturating float-to-integer
 * conversions. No floating-point arithmetic beyond comparisons and casts of
 * in-range values, so the results cannot depend on compiler flags.
 */
#include <largesteps/math.h>

#include "math_dd.h"

/* ---- rounding --------------------------------------------------------- */

double ls_trunc(double x)
{
    uint64_t u = md_bits(x);
    int32_t ex = (int32_t)((u >> 52) & 0x7ffu) - 1023;
    if (ex >= 52) return x;                            /* integral, Inf, NaN */
    if (ex < 0) return md_from(u & 0x8000000000000000ull); /* +-0 */
    return md_from(u & ~(0x000fffffffffffffull >> ex));
}

float ls_truncf(float x)
{
    uint32_t u = mf_bits(x);
    int32_t ex = (int32_t)((u >> 23) & 0xffu) - 127;
    if (ex >= 23) return x;
    if (ex < 0) return mf_from(u & 0x80000000u);
    return mf_from(u & ~(0x007fffffu >> ex));
}

double ls_floor(double x)
{
    double t = ls_trunc(x);
    /* t - 1 is exact: a non-integral x has |x| < 2^52 */
    return (x < 0.0 && t != x) ? t - 1.0 : t;
}

float ls_floorf(float x)
{
    float t = ls_truncf(x);
    return (x < 0.0f && t != x) ? t - 1.0f : t;
}

double ls_ceil(double x)
{
    double t = ls_trunc(x);
    return (x > 0.0 && t != x) ? t + 1.0 : t;
}

float ls_ceilf(float x)
{
    float t = ls_truncf(x);
    return (x > 0.0f && t != x) ? t + 1.0f : t;
}

double ls_round(double x)
{
    uint64_t u = md_bits(x);
    int32_t ex = (int32_t)((u >> 52) & 0x7ffu) - 1023;
    if (ex >= 52) return x;
    if (ex < -1) return md_from(u & 0x8000000000000000ull);                         /* |x| < 1/2 */
    if (ex == -1) return md_from((u & 0x8000000000000000ull) | 0x3ff0000000000000ull); /* +-1 */
    /* add one half (bit 51 - ex of the significand), then clear the fraction;
     * a carry into the exponent is the correct result (1.5 -> 2) */
    u += 0x0008000000000000ull >> ex;
    return md_from(u & ~(0x000fffffffffffffull >> ex));
}

float ls_roundf(float x)
{
    uint32_t u = mf_bits(x);
    int32_t ex = (int32_t)((u >> 23) & 0xffu) - 127;
    if (ex >= 23) return x;
    if (ex < -1) return mf_from(u & 0x80000000u);
    if (ex == -1) return mf_from((u & 0x80000000u) | 0x3f800000u);
    u += 0x00400000u >> ex;
    return mf_from(u & ~(0x007fffffu >> ex));
}

/* ---- sign and classification ------------------------------------------ */

double ls_fabs(double x) { return md_from(md_bits(x) & LS_D_ABS); }
float ls_fabsf(float x) { return mf_from(mf_bits(x) & LS_F_ABS); }

double ls_copysign(double x, double y)
{
    return md_from((md_bits(x) & LS_D_ABS) | (md_bits(y) & ~LS_D_ABS));
}

float ls_copysignf(float x, float y)
{
    return mf_from((mf_bits(x) & LS_F_ABS) | (mf_bits(y) & ~LS_F_ABS));
}

int ls_isnan(double x) { return (md_bits(x) & LS_D_ABS) > LS_D_INF; }
int ls_isnanf(float x) { return (mf_bits(x) & LS_F_ABS) > LS_F_INF; }
int ls_isfinite(double x) { return (md_bits(x) & LS_D_ABS) < LS_D_INF; }
int ls_isfinitef(float x) { return (mf_bits(x) & LS_F_ABS) < LS_F_INF; }
int ls_isinf(double x) { return (md_bits(x) & LS_D_ABS) == LS_D_INF; }
int ls_isinff(float x) { return (mf_bits(x) & LS_F_ABS) == LS_F_INF; }

/* ---- saturating conversions ------------------------------------------- */
/* NaN first, then the two saturating ends: the cast is reached only for
 * values whose truncation fits the type. */

int32_t ls_to_i32(double x)
{
    if (ls_isnan(x)) return 0;
    if (x >= 2147483648.0) return INT32_MAX;
    if (x <= -2147483649.0) return INT32_MIN;
    return (int32_t)x;
}

int32_t ls_to_i32f(float x)
{
    if (ls_isnanf(x)) return 0;
    if (x >= 2147483648.0f) return INT32_MAX;
    if (x < -2147483648.0f) return INT32_MIN;
    return (int32_t)x;
}

uint32_t ls_to_u32(double x)
{
    if (ls_isnan(x) || x <= -1.0) return 0;
    if (x >= 4294967296.0) return UINT32_MAX;
    return (uint32_t)x;
}

uint32_t ls_to_u32f(float x)
{
    if (ls_isnanf(x) || x <= -1.0f) return 0;
    if (x >= 4294967296.0f) return UINT32_MAX;
    return (uint32_t)x;
}

int64_t ls_to_i64(double x)
{
    if (ls_isnan(x)) return 0;
    if (x >= 9223372036854775808.0) return INT64_MAX;
    if (x < -9223372036854775808.0) return INT64_MIN;
    return (int64_t)x;
}

/* From the bits, not a cast: on 32-bit ARM a float -> int64 cast calls
 * libgcc's __aeabi_f2lz, which converts through double (no double arithmetic
 * may appear in a float build on a Cortex-M4). */
int64_t ls_to_i64f(float x)
{
    uint32_t bits = mf_bits(x);
    int32_t e = (int32_t)((bits >> 23) & 0xffu) - 127; /* unbiased exponent */
    uint64_t mag;
    if (ls_isnanf(x)) return 0;
    if (e < 0) return 0;                                  /* |x| < 1 truncates to 0 */
    if (e >= 63) return (bits >> 31) ? INT64_MIN : INT64_MAX; /* includes -2^63 exactly */
    mag = (uint64_t)((bits & 0x7fffffu) | 0x800000u);
    mag = e >= 23 ? mag << (e - 23) : mag >> (23 - e);
    return (bits >> 31) ? -(int64_t)mag : (int64_t)mag;
}
