/* tests/test_math.c - accuracy, special values and bit patterns of
 * largesteps/math.h.
 *
 * Accuracy: each function runs on dense samples (uniform, log-spaced, strided
 * sweeps over the float range, and hard cases near multiples of pi/2, the
 * exp thresholds, subnormals) against libm. Double functions are compared with
 * the x87 long double libm where long double has 64 bits (x86), which gives
 * the error in ulps to ~2^-11; elsewhere with the double libm, which only
 * gives an integer distance (then the bound is relaxed by 1 for the
 * reference's own error). Float functions are compared with the double libm,
 * so their error is measured to ~2^-29 ulp everywhere. The maxima are printed.
 *
 * Bit patterns: a table of input -> output bits produced by this
 * implementation; a difference on another target means lost determinism.
 */
#include "test.h"

#include <float.h>
#include <stdlib.h>

/* ------------------------------------------------------------------ */
/* helpers                                                              */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rng_next(void) { return test_rng_next(&rng_state); }

/* uniform in [0, 1) */
static double rng_unit(void) { return test_rng_unit(&rng_state); }

static double rng_range(double a, double b) { return a + (b - a) * rng_unit(); }

/* 2^u with u uniform in [lo, hi), random sign if sign != 0 */
static double rng_log(double lo, double hi, int sign)
{
    double v = exp2(rng_range(lo, hi));
    if (sign && (rng_next() >> 63)) v = -v;
    return v;
}

static uint64_t dbits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static double dfrom(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static uint32_t fbits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static float ffrom(uint32_t u)
{
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

#if defined(LDBL_MANT_DIG) && LDBL_MANT_DIG == 64
#define PRECISE_REF 1
typedef long double ref_t;
#define RSIN(x) sinl((ref_t)(x))
#define RCOS(x) cosl((ref_t)(x))
#define RATAN(x) atanl((ref_t)(x))
#define RATAN2(y, x) atan2l((ref_t)(y), (ref_t)(x))
#define REXP(x) expl((ref_t)(x))
#define RLOG(x) logl((ref_t)(x))
#define RLOG10(x) log10l((ref_t)(x))
#define RPOW(x, y) powl((ref_t)(x), (ref_t)(y))
#define RFABS(x) fabsl(x)
#else
#define PRECISE_REF 0
typedef double ref_t;
#define RSIN(x) sin(x)
#define RCOS(x) cos(x)
#define RATAN(x) atan(x)
#define RATAN2(y, x) atan2((y), (x))
#define REXP(x) exp(x)
#define RLOG(x) log(x)
#define RLOG10(x) log10(x)
#define RPOW(x, y) pow((x), (y))
#define RFABS(x) fabs(x)
#endif

/* Error of got in ulps of the double nearest ref; 1e9 for a wrong class. */
static double ulp_err_d(double got, ref_t ref)
{
    double rd = (double)ref;
    int e;
    ref_t diff;
    if (isnan(rd)) return isnan(got) ? 0.0 : 1e9;
    if (isnan(got)) return 1e9;
    if (isinf(got) || isinf(rd)) return got == rd ? 0.0 : 1e9;
    if (ref == 0) return got == 0.0 ? 0.0 : 1e9;
    (void)frexp(rd, &e); /* |rd| in [2^(e-1), 2^e) */
    if (RFABS(ref) < (ref_t)ldexp(1.0, e - 1)) e--; /* ref just below a power of 2 */
    diff = RFABS((ref_t)got - ref);
    return (double)(diff / (ref_t)ldexp(1.0, e - 53 < -1074 ? -1074 : e - 53));
}

static double ulp_err_f(float got, double ref)
{
    float rf = (float)ref;
    int e;
    if (isnan(ref)) return isnan(got) ? 0.0 : 1e9;
    if (isnan(got)) return 1e9;
    if (isinf(got) || isinf(rf)) return (double)got == (double)rf ? 0.0 : 1e9;
    if (ref == 0.0) return got == 0.0f ? 0.0 : 1e9;
    (void)frexp(ref, &e);
    return fabs((double)got - ref) / ldexp(1.0, e - 24 < -149 ? -149 : e - 24);
}

/* Running maximum with the worst input, per function. */
typedef struct acc {
    const char *name;
    double max;
    double x, y;
    long n;
} acc;

static void acc_add(acc *a, double err, double x, double y)
{
    a->n++;
    if (err > a->max || a->n == 1) {
        a->max = err;
        a->x = x;
        a->y = y;
    }
}

static void acc_report(const acc *a, double bound)
{
    printf("     %-8s max %.3f ulp over %ld points (worst at %a, %a), bound %.1f\n", a->name,
           a->max, a->n, a->x, a->y, bound);
    CHECK_MSG(a->max <= bound, "%s: max error %.3f ulp > %.1f at x=%a y=%a", a->name, a->max,
              bound, a->x, a->y);
}

/* Double bounds become distances to the double libm without a precise ref. */
static double dbound(double b) { return PRECISE_REF ? b : b + 1.0; }

/* ------------------------------------------------------------------ */
/* accuracy, double                                                     */

/* Points per sample family; divided by 16 under an emulator
 * (LS_TEST_EMULATED=1, set by the Makefile for cross targets). */
#define NS_NATIVE 150000
static long NS = NS_NATIVE;
static uint32_t sweep_mul = 1; /* stride multiplier of the float sweeps */

/* ls_sincos results that differ from ls_sin / ls_cos (must stay 0) */
static long sincos_mismatch = 0;

static void sin_cos_point(acc *as, acc *ac, double x)
{
    double s = 0.0, c = 0.0;
    acc_add(as, ulp_err_d(ls_sin(x), RSIN(x)), x, 0.0);
    acc_add(ac, ulp_err_d(ls_cos(x), RCOS(x)), x, 0.0);
    ls_sincos(x, &s, &c);
    if (dbits(s) != dbits(ls_sin(x)) || dbits(c) != dbits(ls_cos(x))) sincos_mismatch++;
}

static void test_sin_cos_double(void)
{
    acc as = {"sin", 0, 0, 0, 0}, ac = {"cos", 0, 0, 0, 0};
    long i;
    int k;
    static const double hard[] = {
        0x1.921fb54442d18p+0, 0x1.921fb54442d18p+1, 0x1.2d97c7f3321d2p+2,
        0x1.921fb54442d18p+2, 1e22, 0x1p1023, DBL_MAX, 0x1p-1022, 0x1p-1074,
        0x1.e0000637b1e7ep+3, 355.0, 103993.0, 5419351.0, 8.0, 1e300, 1e100,
        0x1.5bf0a8b145769p+0, 7.0, 22.0, 3.14159265358979, 0x1.fffffffffffffp-2,
    };
    for (i = 0; i < NS; i++) sin_cos_point(&as, &ac, rng_range(-10.0, 10.0));
    for (i = 0; i < NS; i++) sin_cos_point(&as, &ac, rng_log(-30.0, 1024.0, 1));
    /* doubles next to multiples of pi/2 up to 2^21 pi/2 */
    for (i = 0; i < NS / 4; i++) {
        double n = (double)(rng_next() >> 43);
        double x = n * 0x1.921fb54442d18p+0;
        int d = (int)(rng_next() >> 61) - 4;
        sin_cos_point(&as, &ac, nextafter(x, d < 0 ? 0.0 : 1e300));
        sin_cos_point(&as, &ac, x);
    }
    for (i = 0; i < (long)(sizeof hard / sizeof hard[0]); i++) {
        double x = hard[i];
        for (k = 0; k < 8; k++) {
            sin_cos_point(&as, &ac, x);
            sin_cos_point(&as, &ac, -x);
            x = nextafter(x, 0.0);
        }
    }
    /* 6381956970095103 * 2^797, the double closest to a multiple of pi/2
     * (|x mod pi/2| ~ 2^-61): the double libm of some targets (glibc's generic
     * code) is 8 ulp off here, so it is compared only with a precise reference;
     * test_bit_patterns checks the exact result everywhere. */
    if (PRECISE_REF) {
        double x = 0x1.6ac5b262ca1ffp+849;
        for (k = 0; k < 8; k++) {
            sin_cos_point(&as, &ac, x);
            x = nextafter(x, 0.0);
        }
    }
    acc_report(&as, dbound(1.0));
    acc_report(&ac, dbound(1.0));
    CHECK_EQ(sincos_mismatch, 0);
}

static void test_atan_double(void)
{
    acc a1 = {"atan", 0, 0, 0, 0}, a2 = {"atan2", 0, 0, 0, 0};
    long i;
    for (i = 0; i < NS; i++) {
        double x = rng_log(-40.0, 60.0, 1);
        acc_add(&a1, ulp_err_d(ls_atan(x), RATAN(x)), x, 0.0);
    }
    for (i = 0; i < NS; i++) {
        double x = rng_range(-2.0, 2.0);
        acc_add(&a1, ulp_err_d(ls_atan(x), RATAN(x)), x, 0.0);
    }
    for (i = 0; i < NS; i++) {
        double y = rng_log(-20.0, 20.0, 1), x = rng_log(-20.0, 20.0, 1);
        acc_add(&a2, ulp_err_d(ls_atan2(y, x), RATAN2(y, x)), y, x);
    }
    for (i = 0; i < NS / 4; i++) { /* extreme exponents and ratios */
        double y = rng_log(-1074.0, 1024.0, 1), x = rng_log(-1074.0, 1024.0, 1);
        acc_add(&a2, ulp_err_d(ls_atan2(y, x), RATAN2(y, x)), y, x);
        x = y * rng_log(-70.0, 70.0, 1);
        acc_add(&a2, ulp_err_d(ls_atan2(y, x), RATAN2(y, x)), y, x);
    }
    acc_report(&a1, dbound(1.0));
    acc_report(&a2, dbound(1.0));
}

static void test_exp_log_double(void)
{
    acc ae = {"exp", 0, 0, 0, 0}, al = {"log", 0, 0, 0, 0}, a10 = {"log10", 0, 0, 0, 0};
    long i;
    for (i = 0; i < NS; i++) {
        double x = rng_range(-746.0, 710.0);
        acc_add(&ae, ulp_err_d(ls_exp(x), REXP(x)), x, 0.0);
        x = rng_log(-60.0, 3.0, 1);
        acc_add(&ae, ulp_err_d(ls_exp(x), REXP(x)), x, 0.0);
    }
    for (i = 0; i < 4096; i++) { /* overflow and underflow thresholds */
        double x = rng_range(709.0, 709.8);
        acc_add(&ae, ulp_err_d(ls_exp(x), REXP(x)), x, 0.0);
        x = rng_range(-745.2, -707.0);
        acc_add(&ae, ulp_err_d(ls_exp(x), REXP(x)), x, 0.0);
    }
    for (i = 0; i < NS; i++) {
        /* random positive doubles of every exponent, incl. subnormals */
        double x = dfrom(rng_next() % 0x7ff0000000000000ull);
        acc_add(&al, ulp_err_d(ls_log(x), RLOG(x)), x, 0.0);
        acc_add(&a10, ulp_err_d(ls_log10(x), RLOG10(x)), x, 0.0);
        x = 1.0 + rng_log(-53.0, -1.0, 1);
        acc_add(&al, ulp_err_d(ls_log(x), RLOG(x)), x, 0.0);
        acc_add(&a10, ulp_err_d(ls_log10(x), RLOG10(x)), x, 0.0);
        x = rng_range(0.5, 4.0);
        acc_add(&al, ulp_err_d(ls_log(x), RLOG(x)), x, 0.0);
        acc_add(&a10, ulp_err_d(ls_log10(x), RLOG10(x)), x, 0.0);
    }
    acc_report(&ae, dbound(1.0));
    acc_report(&al, dbound(1.0));
    acc_report(&a10, dbound(1.0));
}

static void test_pow_double(void)
{
    acc ap = {"pow", 0, 0, 0, 0};
    long i;
    for (i = 0; i < NS; i++) {
        double x = rng_log(-40.0, 40.0, 0), y = rng_range(-20.0, 20.0);
        acc_add(&ap, ulp_err_d(ls_pow(x, y), RPOW(x, y)), x, y);
        /* results over the whole range, incl. subnormal and near overflow */
        x = rng_log(-1074.0, 1024.0, 0);
        y = rng_range(-1075.0, 1024.0) / log2(x);
        acc_add(&ap, ulp_err_d(ls_pow(x, y), RPOW(x, y)), x, y);
        /* x near 1, large y */
        x = 1.0 + rng_log(-52.0, -4.0, 1);
        y = rng_log(0.0, 50.0, 1);
        acc_add(&ap, ulp_err_d(ls_pow(x, y), RPOW(x, y)), x, y);
        /* negative x, integer y */
        x = -rng_log(-8.0, 8.0, 0);
        y = (double)((int)(rng_next() >> 56) - 128);
        acc_add(&ap, ulp_err_d(ls_pow(x, y), RPOW(x, y)), x, y);
    }
    acc_report(&ap, dbound(1.0));
}

/* ------------------------------------------------------------------ */
/* accuracy, float                                                      */

static void test_trig_float(void)
{
    acc as = {"sinf", 0, 0, 0, 0}, ac = {"cosf", 0, 0, 0, 0};
    acc a1 = {"atanf", 0, 0, 0, 0}, a2 = {"atan2f", 0, 0, 0, 0};
    uint32_t u;
    long i;
    /* sweep over all positive finite floats with a stride, both signs */
    for (u = 0x00000001u; u < 0x7f800000u; u += 0x1001u * sweep_mul) {
        float x = ffrom(u), s = 0.0f, c = 0.0f;
        int sg;
        for (sg = 0; sg < 2; sg++) {
            acc_add(&as, ulp_err_f(ls_sinf(x), sin((double)x)), (double)x, 0.0);
            acc_add(&ac, ulp_err_f(ls_cosf(x), cos((double)x)), (double)x, 0.0);
            acc_add(&a1, ulp_err_f(ls_atanf(x), atan((double)x)), (double)x, 0.0);
            ls_sincosf(x, &s, &c);
            if (fbits(s) != fbits(ls_sinf(x)) || fbits(c) != fbits(ls_cosf(x))) sincos_mismatch++;
            x = -x;
        }
    }
    for (i = 0; i < NS; i++) {
        float x = (float)rng_range(-10.0, 10.0);
        acc_add(&as, ulp_err_f(ls_sinf(x), sin((double)x)), (double)x, 0.0);
        acc_add(&ac, ulp_err_f(ls_cosf(x), cos((double)x)), (double)x, 0.0);
    }
    for (i = 0; i < NS; i++) {
        float y = (float)rng_log(-20.0, 20.0, 1), x = (float)rng_log(-20.0, 20.0, 1);
        acc_add(&a2, ulp_err_f(ls_atan2f(y, x), atan2((double)y, (double)x)), (double)y,
                (double)x);
        y = (float)rng_log(-149.0, 128.0, 1);
        x = (float)rng_log(-149.0, 128.0, 1);
        acc_add(&a2, ulp_err_f(ls_atan2f(y, x), atan2((double)y, (double)x)), (double)y,
                (double)x);
    }
    acc_report(&as, 1.0);
    acc_report(&ac, 1.0);
    CHECK_EQ(sincos_mismatch, 0);
    acc_report(&a1, 1.0);
    acc_report(&a2, 1.0);
}

static void test_exp_log_float(void)
{
    acc ae = {"expf", 0, 0, 0, 0}, al = {"logf", 0, 0, 0, 0}, a10 = {"log10f", 0, 0, 0, 0};
    acc ap = {"powf", 0, 0, 0, 0};
    uint32_t u;
    long i;
    for (u = 0x00000001u; u < 0x7f800000u; u += 0xa01u * sweep_mul) {
        float x = ffrom(u);
        acc_add(&al, ulp_err_f(ls_logf(x), log((double)x)), (double)x, 0.0);
        acc_add(&a10, ulp_err_f(ls_log10f(x), log10((double)x)), (double)x, 0.0);
        if (x < 105.0f) {
            acc_add(&ae, ulp_err_f(ls_expf(x), exp((double)x)), (double)x, 0.0);
            acc_add(&ae, ulp_err_f(ls_expf(-x), exp((double)-x)), (double)-x, 0.0);
        }
    }
    for (i = 0; i < NS; i++) {
        float x = (float)rng_range(-104.0, 89.0);
        acc_add(&ae, ulp_err_f(ls_expf(x), exp((double)x)), (double)x, 0.0);
        x = (float)(1.0 + rng_log(-24.0, -1.0, 1));
        acc_add(&al, ulp_err_f(ls_logf(x), log((double)x)), (double)x, 0.0);
        acc_add(&a10, ulp_err_f(ls_log10f(x), log10((double)x)), (double)x, 0.0);
    }
    for (i = 0; i < NS; i++) {
        float x = (float)rng_log(-20.0, 20.0, 0), y = (float)rng_range(-6.0, 6.0);
        acc_add(&ap, ulp_err_f(ls_powf(x, y), pow((double)x, (double)y)), (double)x, (double)y);
        x = (float)rng_log(-149.0, 128.0, 0);
        y = (float)(rng_range(-150.0, 128.0) / log2((double)x));
        acc_add(&ap, ulp_err_f(ls_powf(x, y), pow((double)x, (double)y)), (double)x, (double)y);
        x = (float)(1.0 + rng_log(-23.0, -3.0, 1));
        y = (float)rng_log(0.0, 24.0, 1);
        acc_add(&ap, ulp_err_f(ls_powf(x, y), pow((double)x, (double)y)), (double)x, (double)y);
        x = -(float)rng_log(-4.0, 4.0, 0);
        y = (float)((int)(rng_next() >> 58) - 32);
        acc_add(&ap, ulp_err_f(ls_powf(x, y), pow((double)x, (double)y)), (double)x, (double)y);
    }
    acc_report(&ae, 1.0);
    acc_report(&al, 1.0);
    acc_report(&a10, 1.0);
    acc_report(&ap, 1.0);
}

/* ------------------------------------------------------------------ */
/* special values                                                       */

#define QNAN_D 0x7ff8000000000000ull
#define QNAN_F 0x7fc00000u

/* got must have exactly the bits of want (any NaN want means the canonical NaN) */
static void chk_d(double got, double want, int line)
{
    uint64_t g = dbits(got), w = isnan(want) ? QNAN_D : dbits(want);
    CHECK_MSG(g == w, "line %d: got %a (0x%016llx), want %a (0x%016llx)", line, got,
              (unsigned long long)g, want, (unsigned long long)w);
}

static void chk_f(float got, float want, int line)
{
    uint32_t g = fbits(got), w = isnan(want) ? QNAN_F : fbits(want);
    CHECK_MSG(g == w, "line %d: got %a (0x%08x), want %a (0x%08x)", line, (double)got,
              (unsigned)g, (double)want, (unsigned)w);
}

static void test_special_double(void)
{
    const double inf = dfrom(0x7ff0000000000000ull), nan_in = dfrom(0xfff8000000000123ull);
    const double pi = 0x1.921fb54442d18p+1, pio2 = 0x1.921fb54442d18p+0;
    const double pio4 = 0x1.921fb54442d18p-1, pi3o4 = 0x1.2d97c7f3321d2p+1;
#define T(g, w) chk_d((g), (w), __LINE__)
        T(ls_sin(0.0), 0.0), T(ls_sin(-0.0), -0.0), T(ls_sin(inf), nan_in),
        T(ls_sin(-inf), nan_in), T(ls_sin(nan_in), nan_in), T(ls_cos(-0.0), 1.0),
        T(ls_cos(inf), nan_in), T(ls_sin(0x1p-1074), 0x1p-1074),
        T(ls_sin(-0x1p-1022), -0x1p-1022),
        T(ls_atan(-0.0), -0.0), T(ls_atan(inf), pio2), T(ls_atan(-inf), -pio2),
        T(ls_atan(nan_in), nan_in), T(ls_atan(0x1p-1074), 0x1p-1074),
        T(ls_atan2(0.0, 0.0), 0.0), T(ls_atan2(-0.0, 0.0), -0.0),
        T(ls_atan2(0.0, -0.0), pi), T(ls_atan2(-0.0, -0.0), -pi),
        T(ls_atan2(0.0, -1.0), pi), T(ls_atan2(-0.0, -1.0), -pi),
        T(ls_atan2(-0.0, 1.0), -0.0), T(ls_atan2(1.0, 0.0), pio2),
        T(ls_atan2(-1.0, -0.0), -pio2), T(ls_atan2(1.0, -inf), pi),
        T(ls_atan2(-1.0, -inf), -pi), T(ls_atan2(1.0, inf), 0.0),
        T(ls_atan2(-1.0, inf), -0.0), T(ls_atan2(inf, 1.0), pio2),
        T(ls_atan2(-inf, -1.0), -pio2), T(ls_atan2(inf, -inf), pi3o4),
        T(ls_atan2(-inf, inf), -pio4), T(ls_atan2(nan_in, 1.0), nan_in),
        T(ls_atan2(1.0, nan_in), nan_in), T(ls_atan2(1.0, 1.0), pio4),
        T(ls_atan2(0x1p-1074, 1e300), 0.0), T(ls_atan2(0x1p-1074, 0x1p-1020), 0x1p-1074 * 0x1p1020),
        T(ls_atan2(1e-300, -1e300), pi), T(ls_atan2(DBL_MAX, 0x1p-1074), pio2),
        T(ls_exp(0.0), 1.0), T(ls_exp(-0.0), 1.0), T(ls_exp(-inf), 0.0),
        T(ls_exp(inf), inf), T(ls_exp(nan_in), nan_in), T(ls_exp(710.0), inf),
        T(ls_exp(-746.0), 0.0), T(ls_exp(-745.0), 0x1p-1074), T(ls_exp(1e-300), 1.0),
        T(ls_exp(709.7), 0x1.d75ae7a50ee14p+1023), T(ls_exp(-708.4), 0x0.ff15b469edf89p-1022),
        T(ls_exp(-740.0), 0x0.0000000000055p-1022),
        T(ls_log(1.0), 0.0), T(ls_log(0.0), -inf), T(ls_log(-0.0), -inf),
        T(ls_log(-1.0), nan_in), T(ls_log(-inf), nan_in), T(ls_log(inf), inf),
        T(ls_log(nan_in), nan_in), T(ls_log(0x1p-1074), -0x1.74385446d71c3p+9),
        T(ls_log(DBL_MAX), 0x1.62e42fefa39efp+9), T(ls_log(2.0), 0x1.62e42fefa39efp-1),
        T(ls_log10(1.0), 0.0), T(ls_log10(1000.0), 3.0), T(ls_log10(1e-300), -300.0),
        T(ls_log10(1e22), 22.0), T(ls_log10(0.0), -inf), T(ls_log10(-2.0), nan_in),
        T(ls_pow(nan_in, 0.0), 1.0), T(ls_pow(nan_in, -0.0), 1.0), T(ls_pow(1.0, nan_in), 1.0),
        T(ls_pow(1.0, inf), 1.0), T(ls_pow(-1.0, inf), 1.0), T(ls_pow(-1.0, -inf), 1.0),
        T(ls_pow(nan_in, 1.0), nan_in), T(ls_pow(2.0, nan_in), nan_in),
        T(ls_pow(0.0, -3.0), inf), T(ls_pow(-0.0, -3.0), -inf), T(ls_pow(-0.0, -2.0), inf),
        T(ls_pow(-0.0, -0.5), inf), T(ls_pow(0.0, -inf), inf), T(ls_pow(-0.0, -inf), inf),
        T(ls_pow(0.0, 3.0), 0.0), T(ls_pow(-0.0, 3.0), -0.0), T(ls_pow(-0.0, 2.0), 0.0),
        T(ls_pow(-0.0, 0.5), 0.0), T(ls_pow(-0.0, inf), 0.0),
        T(ls_pow(0.5, -inf), inf), T(ls_pow(-0.5, -inf), inf), T(ls_pow(2.0, -inf), 0.0),
        T(ls_pow(0.5, inf), 0.0), T(ls_pow(-2.0, inf), inf),
        T(ls_pow(-inf, -3.0), -0.0), T(ls_pow(-inf, -2.0), 0.0), T(ls_pow(-inf, -0.5), 0.0),
        T(ls_pow(-inf, 3.0), -inf), T(ls_pow(-inf, 2.0), inf), T(ls_pow(-inf, 0.5), inf),
        T(ls_pow(inf, -1.0), 0.0), T(ls_pow(inf, 0.5), inf),
        T(ls_pow(-2.0, 0.5), nan_in), T(ls_pow(-1.0, 1.5), nan_in),
        T(ls_pow(-2.0, 3.0), -8.0), T(ls_pow(-2.0, -3.0), -0.125), T(ls_pow(-2.0, 2.0), 4.0),
        T(ls_pow(-1.0, 0x1p60), 1.0), T(ls_pow(-1.0, 3.0), -1.0),
        T(ls_pow(2.0, 1024.0), inf), T(ls_pow(-2.0, 1025.0), -inf),
        T(ls_pow(2.0, -1074.0), 0x1p-1074), T(ls_pow(2.0, -1075.0), 0.0),
        T(ls_pow(-2.0, -1075.0), -0.0), T(ls_pow(2.0, 0.5), 0x1.6a09e667f3bcdp+0),
        T(ls_pow(10.0, 22.0), 1e22), T(ls_pow(3.0, 40.0), 0x1.517168a4523fdp+63),
        T(ls_pow(1.0000001, 0x1p70), inf), T(ls_pow(0.9999999, 0x1p70), 0.0),
        T(ls_pow(0x1p-1074, 0.5), 0x1p-537), T(ls_pow(4.0, -0.5), 0.5),
        (void)0;
#undef T
}

static void test_special_float(void)
{
    const float inf = ffrom(0x7f800000u), nan_in = ffrom(0xffc00123u);
    const float pi = 0x1.921fb6p+1f, pio2 = 0x1.921fb6p+0f;
#define T(g, w) chk_f((g), (w), __LINE__)
        T(ls_sinf(-0.0f), -0.0f), T(ls_sinf(inf), nan_in), T(ls_cosf(-inf), nan_in),
        T(ls_cosf(0.0f), 1.0f), T(ls_sinf(0x1p-149f), 0x1p-149f), T(ls_sinf(nan_in), nan_in),
        T(ls_atanf(-0.0f), -0.0f), T(ls_atanf(-inf), -pio2), T(ls_atan2f(-0.0f, -0.0f), -pi),
        T(ls_atan2f(0.0f, -1.0f), pi), T(ls_atan2f(-1.0f, inf), -0.0f),
        T(ls_atan2f(1.0f, -0.0f), pio2), T(ls_atan2f(nan_in, 1.0f), nan_in),
        T(ls_atan2f(0x1p-149f, 0x1p-146f), 0x1.fd5baap-4f),
        T(ls_atan2f(FLT_MAX, 0x1p-149f), pio2),
        T(ls_expf(-inf), 0.0f), T(ls_expf(inf), inf), T(ls_expf(-0.0f), 1.0f),
        T(ls_expf(89.0f), inf), T(ls_expf(-103.9f), 0x1p-149f), T(ls_expf(-104.0f), 0.0f), T(ls_expf(-110.0f), 0.0f),
        T(ls_expf(nan_in), nan_in),
        T(ls_logf(1.0f), 0.0f), T(ls_logf(-0.0f), -inf), T(ls_logf(-1.0f), nan_in),
        T(ls_logf(inf), inf), T(ls_logf(0x1p-149f), -0x1.9d1da0p+6f),
        T(ls_log10f(1000.0f), 3.0f), T(ls_log10f(1e-30f), -30.0f), T(ls_log10f(0.0f), -inf),
        T(ls_powf(nan_in, -0.0f), 1.0f), T(ls_powf(1.0f, nan_in), 1.0f),
        T(ls_powf(-1.0f, -inf), 1.0f), T(ls_powf(-0.0f, -3.0f), -inf),
        T(ls_powf(-0.0f, -2.0f), inf), T(ls_powf(-0.0f, 3.0f), -0.0f),
        T(ls_powf(-inf, -3.0f), -0.0f), T(ls_powf(-inf, 3.0f), -inf),
        T(ls_powf(-inf, 0.5f), inf), T(ls_powf(0.5f, -inf), inf), T(ls_powf(2.0f, -inf), 0.0f),
        T(ls_powf(-2.0f, 0.5f), nan_in), T(ls_powf(-2.0f, 3.0f), -8.0f),
        T(ls_powf(2.0f, 128.0f), inf), T(ls_powf(2.0f, -149.0f), 0x1p-149f),
        T(ls_powf(-2.0f, -151.0f), -0.0f), T(ls_powf(10.0f, 10.0f), 1e10f),
        T(ls_powf(0x1p-149f, 0.5f), 0x1.6a09e6p-75f),
        (void)0;
#undef T
}

/* ------------------------------------------------------------------ */
/* rounding, classification, conversion                                 */

static void test_rounding(void)
{
    static const double v[] = {0.0, 0.5, 1.0, 1.5, 2.5, 0.49999999999999994, 0.3, 1e-320,
                               0x1p52, 0x1p52 + 1.0, 0x1p52 - 0.5, 0x1p53 + 2.0, 4503599627370495.5,
                               1e300, DBL_MAX, 0x1p-1074, 2.7, 123456.5, 7.999999999999999};
    long i;
    size_t k;
    int sg;
    for (k = 0; k < sizeof v / sizeof v[0]; k++) {
        for (sg = 0; sg < 2; sg++) {
            double x = sg ? -v[k] : v[k];
            float xf = (float)x;
            CHECK_EQ(dbits(ls_floor(x)), dbits(floor(x)));
            CHECK_EQ(dbits(ls_ceil(x)), dbits(ceil(x)));
            CHECK_EQ(dbits(ls_trunc(x)), dbits(trunc(x)));
            CHECK_EQ(dbits(ls_round(x)), dbits(round(x)));
            CHECK_EQ(fbits(ls_floorf(xf)), fbits(floorf(xf)));
            CHECK_EQ(fbits(ls_ceilf(xf)), fbits(ceilf(xf)));
            CHECK_EQ(fbits(ls_truncf(xf)), fbits(truncf(xf)));
            CHECK_EQ(fbits(ls_roundf(xf)), fbits(roundf(xf)));
        }
    }
    for (i = 0; i < NS; i++) {
        double x = dfrom(rng_next());
        float xf = ffrom((uint32_t)rng_next());
        if (isnan(x) || isnan(xf)) continue;
        if (i & 1) x = ldexp(rng_range(-1.0, 1.0), (int)(rng_next() >> 58)); /* |x| < 2^64 */
        if (i & 2) xf = (float)ldexp(rng_range(-1.0, 1.0), (int)(rng_next() >> 59));
        CHECK(dbits(ls_floor(x)) == dbits(floor(x)) && dbits(ls_ceil(x)) == dbits(ceil(x)) &&
              dbits(ls_trunc(x)) == dbits(trunc(x)) && dbits(ls_round(x)) == dbits(round(x)));
        CHECK(fbits(ls_floorf(xf)) == fbits(floorf(xf)) && fbits(ls_ceilf(xf)) == fbits(ceilf(xf)) &&
              fbits(ls_truncf(xf)) == fbits(truncf(xf)) && fbits(ls_roundf(xf)) == fbits(roundf(xf)));
    }
    /* NaN and Inf pass through unchanged */
    CHECK_EQ(dbits(ls_floor(dfrom(0xfff8000000000123ull))), 0xfff8000000000123ull);
    CHECK_EQ(fbits(ls_roundf(ffrom(0x7fc00001u))), 0x7fc00001u);
    CHECK(ls_ceil(-HUGE_VAL) == -HUGE_VAL && ls_truncf(HUGE_VALF) == HUGE_VALF);
}

static void test_classify(void)
{
    const double nan_in = dfrom(0x7ff0000000000001ull), inf = HUGE_VAL;
    const float nanf_in = ffrom(0xff800001u), inff = HUGE_VALF;
    CHECK(ls_isnan(nan_in) && ls_isnan(-nan_in) && !ls_isnan(inf) && !ls_isnan(0.0));
    CHECK(ls_isnanf(nanf_in) && !ls_isnanf(inff) && !ls_isnanf(-0.0f));
    CHECK(ls_isfinite(DBL_MAX) && ls_isfinite(0x1p-1074) && !ls_isfinite(-inf) &&
          !ls_isfinite(nan_in));
    CHECK(ls_isfinitef(FLT_MAX) && !ls_isfinitef(inff) && !ls_isfinitef(nanf_in));
    CHECK(ls_isinf(-inf) && !ls_isinf(DBL_MAX) && !ls_isinf(nan_in));
    CHECK(ls_isinff(inff) && !ls_isinff(nanf_in));
    CHECK_EQ(dbits(ls_fabs(-0.0)), 0u);
    CHECK_EQ(dbits(ls_fabs(dfrom(0xfff8000000000001ull))), 0x7ff8000000000001ull);
    CHECK_EQ(fbits(ls_fabsf(-3.0f)), fbits(3.0f));
    CHECK_EQ(dbits(ls_copysign(2.0, -0.0)), dbits(-2.0));
    CHECK_EQ(dbits(ls_copysign(-inf, 1.0)), dbits(inf));
    CHECK_EQ(fbits(ls_copysignf(0.0f, -1.0f)), 0x80000000u);
}

static void test_conversions(void)
{
    const double inf = HUGE_VAL, nan_in = dfrom(0xfff8000000000000ull);
    const float inff = HUGE_VALF, nanf_in = ffrom(0x7fc00000u);
    CHECK_EQ(ls_to_i32(nan_in), 0);
    CHECK_EQ(ls_to_i32(inf), INT32_MAX);
    CHECK_EQ(ls_to_i32(-inf), INT32_MIN);
    CHECK_EQ(ls_to_i32(2147483647.9), INT32_MAX);
    CHECK_EQ(ls_to_i32(2147483648.0), INT32_MAX);
    CHECK_EQ(ls_to_i32(-2147483648.9), INT32_MIN);
    CHECK_EQ(ls_to_i32(-2147483649.0), INT32_MIN);
    CHECK_EQ(ls_to_i32(-1.9), -1);
    CHECK_EQ(ls_to_i32(1e300), INT32_MAX);
    CHECK_EQ(ls_to_i32(-0.0), 0);
    CHECK_EQ(ls_to_i32f(nanf_in), 0);
    CHECK_EQ(ls_to_i32f(2147483520.0f), 2147483520);
    CHECK_EQ(ls_to_i32f(2147483648.0f), INT32_MAX);
    CHECK_EQ(ls_to_i32f(-2147483648.0f), INT32_MIN);
    CHECK_EQ(ls_to_i32f(-2147483904.0f), INT32_MIN);
    CHECK_EQ(ls_to_i32f(-inff), INT32_MIN);
    CHECK_EQ(ls_to_i32f(-2.5f), -2);
    CHECK_EQ(ls_to_u32(nan_in), 0);
    CHECK_EQ(ls_to_u32(-0.7), 0);
    CHECK_EQ(ls_to_u32(-1.0), 0);
    CHECK_EQ(ls_to_u32(-inf), 0);
    CHECK_EQ(ls_to_u32(4294967295.5), UINT32_MAX);
    CHECK_EQ(ls_to_u32(4294967296.0), UINT32_MAX);
    CHECK_EQ(ls_to_u32(inf), UINT32_MAX);
    CHECK_EQ(ls_to_u32(3.99), 3);
    CHECK_EQ(ls_to_u32f(nanf_in), 0);
    CHECK_EQ(ls_to_u32f(-0.99f), 0);
    CHECK_EQ(ls_to_u32f(4294967040.0f), 4294967040u);
    CHECK_EQ(ls_to_u32f(4294967296.0f), UINT32_MAX);
    CHECK_EQ(ls_to_u32f(inff), UINT32_MAX);
    CHECK(ls_to_i64(nan_in) == 0);
    CHECK(ls_to_i64(inf) == INT64_MAX && ls_to_i64(-inf) == INT64_MIN);
    CHECK(ls_to_i64(9223372036854774784.0) == 9223372036854774784ll);
    CHECK(ls_to_i64(9223372036854775808.0) == INT64_MAX);
    CHECK(ls_to_i64(-9223372036854775808.0) == INT64_MIN);
    CHECK(ls_to_i64(-1e300) == INT64_MIN && ls_to_i64(-3.7) == -3);
    CHECK(ls_to_i64f(nanf_in) == 0 && ls_to_i64f(inff) == INT64_MAX && ls_to_i64f(-inff) == INT64_MIN);
    CHECK(ls_to_i64f(9223371487098961920.0f) == 9223371487098961920ll);
    CHECK(ls_to_i64f(9223372036854775808.0f) == INT64_MAX);
    CHECK(ls_to_i64f(-9223372036854775808.0f) == INT64_MIN);
    CHECK(ls_to_i64f(-1e30f) == INT64_MIN);
    CHECK(ls_to_i64f(-0.0f) == 0 && ls_to_i64f(0.99f) == 0 && ls_to_i64f(-1.0f) == -1);
    CHECK(ls_to_i64f(8388607.5f) == 8388607 && ls_to_i64f(-16777217.0f) == -16777216);
    { /* every in-range float exponent, both signs: equal to the C cast */
        uint32_t e, k, bad = 0;
        for (e = 0; e < 190; e++)
            for (k = 0; k < 64; k++) {
                uint32_t bits = (e << 23) | ((k * 0x1f3a5u * 977u) & 0x7fffffu) | ((k & 1u) << 31);
                float v;
                memcpy(&v, &bits, 4);
                if (fabsf(v) < 9.2233715e18f && ls_to_i64f(v) != (int64_t)v) bad++;
            }
        CHECK_EQ(bad, 0);
    }
}

/* ------------------------------------------------------------------ */
/* bit patterns: outputs of this implementation (must match everywhere)  */

static void test_bit_patterns(void)
{
    static const struct {
        const char *fn;
        uint64_t x, y, want;
    } d[] = {
        {"sin", 0x3ff0000000000000ull, 0x0000000000000000ull, 0x3feaed548f090ceeull}, /* 0x1p+0 0x0p+0 -> 0x1.aed548f090ceep-1 */
        {"sin", 0x4480f0cf064dd592ull, 0x0000000000000000ull, 0xbfeb453ab76bf397ull}, /* 0x1.0f0cf064dd592p+73 0x0p+0 -> -0x1.b453ab76bf397p-1 */
        {"sin", 0x7fe0000000000000ull, 0x0000000000000000ull, 0x3fe205248cbdb760ull}, /* 0x1p+1023 0x0p+0 -> 0x1.205248cbdb76p-1 */
        {"sin", 0x7506ac5b262ca1ffull, 0x0000000000000000ull, 0x3ff0000000000000ull}, /* 0x1.6ac5b262ca1ffp+849 0x0p+0 -> 0x1p+0 */
        {"sin", 0xc008000000000000ull, 0x0000000000000000ull, 0xbfc210386db6d55bull}, /* -0x1.8p+1 0x0p+0 -> -0x1.210386db6d55bp-3 */
        {"sin", 0x3ff921fb54442d18ull, 0x0000000000000000ull, 0x3ff0000000000000ull}, /* 0x1.921fb54442d18p+0 0x0p+0 -> 0x1p+0 */
        {"cos", 0x3ff0000000000000ull, 0x0000000000000000ull, 0x3fe14a280fb5068cull}, /* 0x1p+0 0x0p+0 -> 0x1.14a280fb5068cp-1 */
        {"cos", 0x4480f0cf064dd592ull, 0x0000000000000000ull, 0x3fe0be2cef01c8f4ull}, /* 0x1.0f0cf064dd592p+73 0x0p+0 -> 0x1.0be2cef01c8f4p-1 */
        {"cos", 0x3ff921fb54442d18ull, 0x0000000000000000ull, 0x3c91a62633145c07ull}, /* 0x1.921fb54442d18p+0 0x0p+0 -> 0x1.1a62633145c07p-54 */
        {"cos", 0x4059000000000000ull, 0x0000000000000000ull, 0x3feb981dbf665fdfull}, /* 0x1.9p+6 0x0p+0 -> 0x1.b981dbf665fdfp-1 */
        {"atan", 0x3fd3333333333333ull, 0x0000000000000000ull, 0x3fd2a73a661eaf06ull}, /* 0x1.3333333333333p-2 0x0p+0 -> 0x1.2a73a661eaf06p-2 */
        {"atan", 0xc01e000000000000ull, 0x0000000000000000ull, 0xbff7030cf9403197ull}, /* -0x1.ep+2 0x0p+0 -> -0x1.7030cf9403197p+0 */
        {"atan2", 0x3ff0000000000000ull, 0xc000000000000000ull, 0x40056c6e7397f5aeull}, /* 0x1p+0 -0x1p+1 -> 0x1.56c6e7397f5aep+1 */
        {"atan2", 0x81c01297d23ab683ull, 0x7e37e43c8800759cull, 0x8000000000000000ull}, /* -0x1.01297d23ab683p-995 0x1.7e43c8800759cp+996 -> -0x0p+0 */
        {"atan2", 0x0000000000000001ull, 0xbff0000000000000ull, 0x400921fb54442d18ull}, /* 0x0.0000000000001p-1022 -0x1p+0 -> 0x1.921fb54442d18p+1 */
        {"exp", 0x3ff0000000000000ull, 0x0000000000000000ull, 0x4005bf0a8b145769ull}, /* 0x1p+0 0x0p+0 -> 0x1.5bf0a8b145769p+1 */
        {"exp", 0xbff8000000000000ull, 0x0000000000000000ull, 0x3fcc8f87724b5c1dull}, /* -0x1.8p+0 0x0p+0 -> 0x1.c8f87724b5c1dp-3 */
        {"exp", 0x4086280000000000ull, 0x0000000000000000ull, 0x7fdd422d2be5dc9bull}, /* 0x1.628p+9 0x0p+0 -> 0x1.d422d2be5dc9bp+1022 */
        {"exp", 0xc087400000000000ull, 0x0000000000000000ull, 0x0000000000000002ull}, /* -0x1.74p+9 0x0p+0 -> 0x0.0000000000002p-1022 */
        {"exp", 0x3ddb7cdfd9d7bdbbull, 0x0000000000000000ull, 0x3ff000000006df38ull}, /* 0x1.b7cdfd9d7bdbbp-34 0x0p+0 -> 0x1.000000006df38p+0 */
        {"log", 0x4024000000000000ull, 0x0000000000000000ull, 0x40026bb1bbb55516ull}, /* 0x1.4p+3 0x0p+0 -> 0x1.26bb1bbb55516p+1 */
        {"log", 0x0000000000000001ull, 0x0000000000000000ull, 0xc0874385446d71c3ull}, /* 0x0.0000000000001p-1022 0x0p+0 -> -0x1.74385446d71c3p+9 */
        {"log", 0x3ff000000006df38ull, 0x0000000000000000ull, 0x3ddb7cdffffa18d8ull}, /* 0x1.000000006df38p+0 0x0p+0 -> 0x1.b7cdffffa18d8p-34 */
        {"log", 0x3feff7ced916872bull, 0x0000000000000000ull, 0xbf5064670d979b73ull}, /* 0x1.ff7ced916872bp-1 0x0p+0 -> -0x1.064670d979b73p-10 */
        {"log10", 0x4000000000000000ull, 0x0000000000000000ull, 0x3fd34413509f79ffull}, /* 0x1p+1 0x0p+0 -> 0x1.34413509f79ffp-2 */
        {"log10", 0x405edd2f1a9fbe77ull, 0x0000000000000000ull, 0x4000bb6abfc968efull}, /* 0x1.edd2f1a9fbe77p+6 0x0p+0 -> 0x1.0bb6abfc968efp+1 */
        {"pow", 0x4000000000000000ull, 0x3fe0000000000000ull, 0x3ff6a09e667f3bcdull}, /* 0x1p+1 0x1p-1 -> 0x1.6a09e667f3bcdp+0 */
        {"pow", 0x3ff8000000000000ull, 0x4059100000000000ull, 0x4398f9f20247e3a3ull}, /* 0x1.8p+0 0x1.91p+6 -> 0x1.8f9f20247e3a3p+58 */
        {"pow", 0xc008000000000000ull, 0xc01c000000000000ull, 0xbf3df75680feb65full}, /* -0x1.8p+1 -0x1.cp+2 -> -0x1.df75680feb65fp-12 */
        {"pow", 0x3fefae147ae147aeull, 0xc0b3888000000000ull, 0x4476b5200bbfd1abull}, /* 0x1.fae147ae147aep-1 -0x1.3888p+12 -> 0x1.6b5200bbfd1abp+72 */
        {"pow", 0x4024000000000000ull, 0xc074000000000000ull, 0x00000000000007e8ull}, /* 0x1.4p+3 -0x1.4p+8 -> 0x0.00000000007e8p-1022 */
        {"cos", 0x7506ac5b262ca1ffull, 0x0000000000000000ull, 0xbc214ae72e6ba22full}, /* hardest reduction -> -0x1.14ae72e6ba22fp-61 */
    };
    static const struct {
        const char *fn;
        uint32_t x, y, want;
    } f[] = {
        {"sinf", 0x3f800000u, 0x00000000u, 0x3f576aa4u}, /* 0x1p+0 0x0p+0 -> 0x1.aed548p-1 */
        {"sinf", 0x7149f2cau, 0x00000000u, 0xbf4a89b0u}, /* 0x1.93e594p+99 0x0p+0 -> -0x1.95136p-1 */
        {"sinf", 0xc0400000u, 0x00000000u, 0xbe1081c3u}, /* -0x1.8p+1 0x0p+0 -> -0x1.210386p-3 */
        {"sinf", 0x3fc90fdbu, 0x00000000u, 0x3f800000u}, /* 0x1.921fb6p+0 0x0p+0 -> 0x1p+0 */
        {"cosf", 0x3f800000u, 0x00000000u, 0x3f0a5140u}, /* 0x1p+0 0x0p+0 -> 0x1.14a28p-1 */
        {"cosf", 0x71800000u, 0x00000000u, 0x3efa75a0u}, /* 0x1p+100 0x0p+0 -> 0x1.f4eb4p-2 */
        {"cosf", 0x42c80000u, 0x00000000u, 0x3f5cc0eeu}, /* 0x1.9p+6 0x0p+0 -> 0x1.b981dcp-1 */
        {"atanf", 0x3e99999au, 0x00000000u, 0x3e9539d4u}, /* 0x1.333334p-2 0x0p+0 -> 0x1.2a73a8p-2 */
        {"atanf", 0xc0f00000u, 0x00000000u, 0xbfb81868u}, /* -0x1.ep+2 0x0p+0 -> -0x1.7030dp+0 */
        {"atan2f", 0x3f800000u, 0xc0000000u, 0x402b6374u}, /* 0x1p+0 -0x1p+1 -> 0x1.56c6e8p+1 */
        {"atan2f", 0x8e736390u, 0x7149f2cau, 0x80000000u}, /* -0x1.e6c72p-99 0x1.93e594p+99 -> -0x0p+0 */
        {"expf", 0x3f800000u, 0x00000000u, 0x402df854u}, /* 0x1p+0 0x0p+0 -> 0x1.5bf0a8p+1 */
        {"expf", 0xbfc00000u, 0x00000000u, 0x3e647c3cu}, /* -0x1.8p+0 0x0p+0 -> 0x1.c8f878p-3 */
        {"expf", 0x42b00000u, 0x00000000u, 0x7ef882b7u}, /* 0x1.6p+6 0x0p+0 -> 0x1.f1056ep+126 */
        {"expf", 0xc2cc0000u, 0x00000000u, 0x00000004u}, /* -0x1.98p+6 0x0p+0 -> 0x1p-147 */
        {"logf", 0x41200000u, 0x00000000u, 0x40135d8eu}, /* 0x1.4p+3 0x0p+0 -> 0x1.26bb1cp+1 */
        {"logf", 0x00000001u, 0x00000000u, 0xc2ce8ed0u}, /* 0x1p-149 0x0p+0 -> -0x1.9d1dap+6 */
        {"logf", 0x3f7fbe77u, 0x00000000u, 0xba8322cau}, /* 0x1.ff7ceep-1 0x0p+0 -> -0x1.064594p-10 */
        {"log10f", 0x40000000u, 0x00000000u, 0x3e9a209bu}, /* 0x1p+1 0x0p+0 -> 0x1.344136p-2 */
        {"log10f", 0x42f6e979u, 0x00000000u, 0x4005db56u}, /* 0x1.edd2f2p+6 0x0p+0 -> 0x1.0bb6acp+1 */
        {"powf", 0x40000000u, 0x3f000000u, 0x3fb504f3u}, /* 0x1p+1 0x1p-1 -> 0x1.6a09e6p+0 */
        {"powf", 0x3fc00000u, 0x42c88000u, 0x5cc7cf90u}, /* 0x1.8p+0 0x1.91p+6 -> 0x1.8f9f2p+58 */
        {"powf", 0xc0400000u, 0xc0e00000u, 0xb9efbab4u}, /* -0x1.8p+1 -0x1.cp+2 -> -0x1.df7568p-12 */
        {"powf", 0x3f7d70a4u, 0xc3fa4000u, 0x4318f639u}, /* 0x1.fae148p-1 -0x1.f48p+8 -> 0x1.31ec72p+7 */
    };
    size_t i;
    for (i = 0; i < sizeof d / sizeof d[0]; i++) {
        double x = dfrom(d[i].x), y = dfrom(d[i].y), r = 0.0;
        switch (d[i].fn[0]) {
        case 's': r = ls_sin(x); break;
        case 'c': r = ls_cos(x); break;
        case 'a': r = d[i].fn[4] == '2' ? ls_atan2(x, y) : ls_atan(x); break;
        case 'e': r = ls_exp(x); break;
        case 'l': r = d[i].fn[3] == '1' ? ls_log10(x) : ls_log(x); break;
        case 'p': r = ls_pow(x, y); break;
        default: break;
        }
        CHECK_MSG(dbits(r) == d[i].want, "%s(%a, %a) = 0x%016llx, want 0x%016llx", d[i].fn, x, y,
                  (unsigned long long)dbits(r), (unsigned long long)d[i].want);
    }
    for (i = 0; i < sizeof f / sizeof f[0]; i++) {
        float x = ffrom(f[i].x), y = ffrom(f[i].y), r = 0.0f;
        switch (f[i].fn[0]) {
        case 's': r = ls_sinf(x); break;
        case 'c': r = ls_cosf(x); break;
        case 'a': r = f[i].fn[4] == '2' ? ls_atan2f(x, y) : ls_atanf(x); break;
        case 'e': r = ls_expf(x); break;
        case 'l': r = f[i].fn[3] == '1' ? ls_log10f(x) : ls_logf(x); break;
        case 'p': r = ls_powf(x, y); break;
        default: break;
        }
        CHECK_MSG(fbits(r) == f[i].want, "%s(%a, %a) = 0x%08x, want 0x%08x", f[i].fn, (double)x,
                  (double)y, (unsigned)fbits(r), (unsigned)f[i].want);
    }
}

/* The LS_R* macros pick the function of the build's ls_real. */
static void test_real_macros(void)
{
    ls_real x = (ls_real)0.7, y = (ls_real)1.3, s = 0, c = 0;
#if LS_REAL_IS_FLOAT
    CHECK(fbits(LS_RSIN(x)) == fbits(ls_sinf(x)) && fbits(LS_RPOW(x, y)) == fbits(ls_powf(x, y)));
    CHECK(fbits(LS_RATAN2(y, x)) == fbits(ls_atan2f(y, x)) && LS_RSQRT(x) == sqrtf(x));
#else
    CHECK(dbits(LS_RSIN(x)) == dbits(ls_sin(x)) && dbits(LS_RPOW(x, y)) == dbits(ls_pow(x, y)));
    CHECK(dbits(LS_RATAN2(y, x)) == dbits(ls_atan2(y, x)) && LS_RSQRT(x) == sqrt(x));
#endif
    LS_RSINCOS(x, &s, &c);
    CHECK(s == LS_RSIN(x) && c == LS_RCOS(x));
    CHECK(LS_RFLOOR(y) == 1 && LS_RCEIL(y) == 2 && LS_RROUND(y) == 1 && LS_RTRUNC(-y) == -1);
    CHECK(LS_REXP(LS_RLOG(y)) - y < (ls_real)1e-6 && LS_RLOG10((ls_real)100) == 2);
    CHECK(LS_RATAN(x) > 0 && LS_RFABS(-x) == x && LS_RCOPYSIGN(x, -y) == -x);
    CHECK(LS_RISFINITE(x) && !LS_RISNAN(x) && !LS_RISINF(x));
    CHECK(LS_RTO_I32(-y) == -1 && LS_RTO_U32(y) == 1 && LS_RTO_I64(y) == 1);
}

int main(void)
{
    const char *emu = getenv("LS_TEST_EMULATED");
    TEST_INIT("test_math");
    if (emu && emu[0] == '1') {
        NS = NS_NATIVE / 16;
        sweep_mul = 16;
    }
    printf("     reference for double: %s\n",
           PRECISE_REF ? "x87 long double libm (fractional ulps)"
                       : "double libm (integer distance; bounds + 1)");
    TEST_RUN(test_special_double);
    TEST_RUN(test_special_float);
    TEST_RUN(test_bit_patterns);
    TEST_RUN(test_rounding);
    TEST_RUN(test_classify);
    TEST_RUN(test_conversions);
    TEST_RUN(test_real_macros);
    TEST_RUN(test_sin_cos_double);
    TEST_RUN(test_atan_double);
    TEST_RUN(test_exp_log_double);
    TEST_RUN(test_pow_double);
    TEST_RUN(test_trig_float);
    TEST_RUN(test_exp_log_float);
    return TEST_END();
}
