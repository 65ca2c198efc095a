/* src/base/math_dd.h - private helpers of the math module: bit access and
 * error-free transformations (double-double and float-float arithmetic).
 *
 * Every helper uses only IEEE +, -, * in a fixed order, so results are the same
 * bits on every target as long as FLT_EVAL_METHOD == 0 (checked by core.h) and
 * no FMA contraction happens (-ffp-contract=off). The float helpers use float
 * arithmetic only.
 */
#ifndef LS_MATH_DD_H
#define LS_MATH_DD_H

#include <stdint.h>
#include <string.h>

#define LS_D_ABS 0x7fffffffffffffffull
#define LS_D_INF 0x7ff0000000000000ull
#define LS_D_QNAN 0x7ff8000000000000ull
#define LS_F_ABS 0x7fffffffu
#define LS_F_INF 0x7f800000u
#define LS_F_QNAN 0x7fc00000u

static inline uint64_t md_bits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static inline double md_from(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static inline uint32_t mf_bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static inline float mf_from(uint32_t u)
{
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* The canonical quiet NaN: results are NaN with these exact bits on every
 * target (hardware default NaNs differ: x86 sets the sign bit, ARM does not). */
static inline double md_nan(void) { return md_from(LS_D_QNAN); }
static inline float mf_nan(void) { return mf_from(LS_F_QNAN); }
static inline double md_inf(void) { return md_from(LS_D_INF); }
static inline float mf_inf(void) { return mf_from(LS_F_INF); }

/* 2^k for -1022 <= k <= 1023 (float: -126 <= k <= 127). */
static inline double md_pow2(int32_t k)
{
    return md_from((uint64_t)(k + 1023) << 52);
}

static inline float mf_pow2(int32_t k)
{
    return mf_from((uint32_t)(k + 127) << 23);
}

/* s + e == a + b exactly, s = fl(a + b) (Knuth). */
static inline void md_two_sum(double a, double b, double *s, double *e)
{
    double t = a + b;
    double bb = t - a;
    *e = (a - (t - bb)) + (b - bb);
    *s = t;
}

/* Same when |a| >= |b| or a == 0 (Dekker). */
static inline void md_fast_two_sum(double a, double b, double *s, double *e)
{
    double t = a + b;
    *e = b - (t - a);
    *s = t;
}

/* Veltkamp split: a == h + l, h with 26 significant bits. |a| < 2^995. */
static inline void md_split(double a, double *h, double *l)
{
    double c = 134217729.0 * a; /* 2^27 + 1 */
    double hh = c - (c - a);
    *h = hh;
    *l = a - hh;
}

/* p + e == a * b exactly (Dekker), barring underflow of e. */
static inline void md_two_prod(double a, double b, double *p, double *e)
{
    double ah, al, bh, bl;
    double t = a * b;
    md_split(a, &ah, &al);
    md_split(b, &bh, &bl);
    *e = ((ah * bh - t) + ah * bl + al * bh) + al * bl;
    *p = t;
}

static inline void mf_two_sum(float a, float b, float *s, float *e)
{
    float t = a + b;
    float bb = t - a;
    *e = (a - (t - bb)) + (b - bb);
    *s = t;
}

static inline void mf_fast_two_sum(float a, float b, float *s, float *e)
{
    float t = a + b;
    *e = b - (t - a);
    *s = t;
}

/* h has 12 significant bits. |a| < 2^114. */
static inline void mf_split(float a, float *h, float *l)
{
    float c = 4097.0f * a; /* 2^12 + 1 */
    float hh = c - (c - a);
    *h = hh;
    *l = a - hh;
}

static inline void mf_two_prod(float a, float b, float *p, float *e)
{
    float ah, al, bh, bl;
    float t = a * b;
    mf_split(a, &ah, &al);
    mf_split(b, &bh, &bl);
    *e = ((ah * bh - t) + ah * bl + al * bh) + al * bl;
    *p = t;
}

#endif /* LS_MATH_DD_H */
