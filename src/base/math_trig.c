/* src/base/math_trig.c - sin, cos, sincos, atan, atan2 in double and float.
 *
 * Argument reduction for sin/cos: below 2^20 (float 2^10) by subtracting
 * n pi/2 with pi/2 split into chunks whose products with n are exact (152
 * bits, float 80), carried exactly. Above, Payne-Hanek in integer
 * arithmetic: the 53-bit (24-bit) significand is multiplied by a 224-bit
 * window of the bits of 2/pi, which yields the quadrant and at least 128 bits
 * of the fraction for every finite input (the closest a double comes to a
 * multiple of pi/2 is about 2^-61 relative, so at least 66 significant bits
 * remain). The fraction times pi/2 is carried as a double-double (float-float)
 * into the polynomial kernels. atan reduces with a table of atan(j/16) and the
 * addition formula, carried in double-double (float-float).
 *
 * Constants, tables and coefficients come from tests/tools/gen_math_coeffs.py.
 */
#include <largesteps/math.h>

#include "math_dd.h"

#define PIO2_HI 0x1.921fb54442d18p+0
#define PIO2_LO 0x1.1a62633145c07p-54
#define PI_HI 0x1.921fb54442d18p+1
#define PI_LO 0x1.1a62633145c07p-53
#define PIO4_HI 0x1.921fb54442d18p-1
#define PI3O4_HI 0x1.2d97c7f3321d2p+1
#define PIO2_C1 0x1.921fb54400000p+0
#define PIO2_C2 0x1.0b4611a600000p-34
#define PIO2_C3 0x1.3198a2e000000p-69
#define PIO2_C4 0x1.b839a252049c1p-104
#define INV_PIO2 0x1.45f306dc9c883p-1
#define PIO2F_HI 0x1.921fb6p+0f
#define PIO2F_LO (-0x1.777a5cp-25f)
#define PIF_HI 0x1.921fb6p+1f
#define PIF_LO (-0x1.777a5cp-24f)
#define PIO4F_HI 0x1.921fb6p-1f
#define PI3O4F_HI 0x1.2d97c8p+1f
#define PIO2F_C1 0x1.922000p+0f
#define PIO2F_C2 (-0x1.2af000p-18f)
#define PIO2F_C3 0x1.0b4800p-34f
#define PIO2F_C4 (-0x1.ee5800p-50f)
#define PIO2F_C5 (-0x1.d9ccecp-66f)
#define INV_PIO2F 0x1.45f306p-1f

/* SIN_S: degree 6 on [8.67362e-19, 0.61685], weighted error 2^-57.1 */
#define SIN_S0 (-0x1.5555555555555p-3)
#define SIN_S1 0x1.111111111110bp-7
#define SIN_S2 (-0x1.a01a01a018a6dp-13)
#define SIN_S3 0x1.71de3a53308b9p-19
#define SIN_S4 (-0x1.ae64528d7e680p-26)
#define SIN_S5 0x1.61208c47ce0c4p-33
#define SIN_S6 (-0x1.aaa24713c3645p-41)
/* COS_C: degree 5 on [8.67362e-19, 0.61685], weighted error 2^-59.7 */
#define COS_C0 0x1.555555555554bp-5
#define COS_C1 (-0x1.6c16c16c14f91p-10)
#define COS_C2 0x1.a01a019c844f5p-16
#define COS_C3 (-0x1.27e4f7eac4bc6p-22)
#define COS_C4 0x1.1ee9d7b4e3f05p-29
#define COS_C5 (-0x1.8fa49a0861a5fp-37)
/* SINF_S: degree 4 on [8.67362e-19, 0.61685], weighted error 2^-28.2 */
#define SINF_S0 (-0x1.555556p-3f)
#define SINF_S1 0x1.111112p-7f
#define SINF_S2 (-0x1.a019fap-13f)
#define SINF_S3 0x1.71d76ep-19f
#define SINF_S4 (-0x1.a961a2p-26f)
/* COSF_C: degree 3 on [8.67362e-19, 0.61685], weighted error 2^-30.4 */
#define COSF_C0 0x1.555556p-5f
#define COSF_C1 (-0x1.6c16b8p-10f)
#define COSF_C2 0x1.a010dep-16f
#define COSF_C3 (-0x1.241e9cp-22f)
/* ATAN_A: degree 5 on [8.67362e-19, 0.000984207], weighted error 2^-65.6 */
#define ATAN_A0 (-0x1.5555555555555p-2)
#define ATAN_A1 0x1.9999999999999p-3
#define ATAN_A2 (-0x1.2492492491b6bp-3)
#define ATAN_A3 0x1.c71c71b998843p-4
#define ATAN_A4 (-0x1.745cc6899d91fp-4)
#define ATAN_A5 0x1.3a266252c787dp-4
/* ATANF_A: degree 2 on [8.67362e-19, 0.000984207], weighted error 2^-36.6 */
#define ATANF_A0 (-0x1.555556p-2f)
#define ATANF_A1 0x1.99998ap-3f
#define ATANF_A2 (-0x1.242446p-3f)

/* atan(j/16) as head, tail */
static const double atan_tab[34] = {
    0.0, 0.0,
    0x1.ff55bb72cfdeap-5, -0x1.c934d86d23f1dp-60,
    0x1.fd5ba9aac2f6ep-4, -0x1.cd37686760c17p-59,
    0x1.7b97b4bce5b02p-3, 0x1.347b0b4f881cap-58,
    0x1.f5b75f92c80ddp-3, 0x1.8ab6e3cf7afbdp-57,
    0x1.362773707ebccp-2, -0x1.963a544b672d8p-57,
    0x1.6f61941e4def1p-2, -0x1.c63aae6f6e918p-56,
    0x1.a64eec3cc23fdp-2, -0x1.24dec1b50b7ffp-56,
    0x1.dac670561bb4fp-2, 0x1.a2b7f222f65e2p-56,
    0x1.0657e94db30d0p-1, -0x1.d5b495f6349e6p-56,
    0x1.1e00babdefeb4p-1, -0x1.928df287a668fp-58,
    0x1.345f01cce37bbp-1, 0x1.1021137c71102p-55,
    0x1.4978fa3269ee1p-1, 0x1.2419a87f2a458p-56,
    0x1.5d58987169b18p-1, 0x1.0028e4bc5e7cap-57,
    0x1.700a7c5784634p-1, -0x1.8c34d25aadef6p-56,
    0x1.819d0b7158a4dp-1, -0x1.bf76229d3b917p-56,
    0x1.921fb54442d18p-1, 0x1.1a62633145c07p-55,
};

/* atan(j/16) as head, tail */
static const float atanf_tab[34] = {
    0.0f, 0.0f,
    0x1.ff55bcp-5f, -0x1.1a6042p-30f,
    0x1.fd5baap-4f, -0x1.54f424p-30f,
    0x1.7b97b4p-3f, 0x1.79cb60p-28f,
    0x1.f5b760p-3f, -0x1.b4dfc8p-29f,
    0x1.362774p-2f, -0x1.1f0286p-27f,
    0x1.6f6194p-2f, 0x1.e4def0p-30f,
    0x1.a64eecp-2f, 0x1.e611fep-29f,
    0x1.dac670p-2f, 0x1.586ed4p-28f,
    0x1.0657eap-1f, -0x1.6499e6p-26f,
    0x1.1e00bap-1f, 0x1.7bdfd6p-26f,
    0x1.345f02p-1f, -0x1.98e422p-28f,
    0x1.4978fap-1f, 0x1.934f70p-28f,
    0x1.5d5898p-1f, 0x1.c5a6c6p-27f,
    0x1.700a7cp-1f, 0x1.5e118cp-27f,
    0x1.819d0cp-1f, -0x1.1d4eb6p-26f,
    0x1.921fb6p-1f, -0x1.777a5cp-26f,
};

/* bits of 2/pi, 32 per word, most significant first */
static const uint32_t two_over_pi[40] = {
    0xa2f9836eu, 0x4e441529u, 0xfc2757d1u, 0xf534ddc0u, 0xdb629599u, 0x3c439041u,
    0xfe5163abu, 0xdebbc561u, 0xb7246e3au, 0x424dd2e0u, 0x06492eeau, 0x09d1921cu,
    0xfe1deb1cu, 0xb129a73eu, 0xe88235f5u, 0x2ebb4484u, 0xe99c7026u, 0xb45f7e41u,
    0x3991d639u, 0x835339f4u, 0x9c845f8bu, 0xbdf9283bu, 0x1ff897ffu, 0xde05980fu,
    0xef2f118bu, 0x5a0a6d1fu, 0x6d367ecfu, 0x27cb09b7u, 0x4f463f66u, 0x9e5fea2du,
    0x7527bac7u, 0xebe5f17bu, 0x3d0739f7u, 0x8a5292eau, 0x6bfb5fb1u, 0x1f8d5d08u,
    0x56033046u, 0xfc7b6babu, 0xf0cfbc20u, 0x9af4361du,
};

/* ------------------------------------------------------------------ */
/* Payne-Hanek reduction (integer only, shared by double and float)    */

#define PH_WORDS 7 /* 224-bit window of 2/pi */
#define PH_PROD (PH_WORDS + 2)

/* 64 bits of the little-endian multiword p starting at bit pos (pos >= 0). */
static uint64_t ph_get64(const uint32_t *p, int32_t pos)
{
    int32_t w = pos / 32;
    int32_t s = pos % 32;
    uint64_t w0 = w < PH_PROD ? p[w] : 0u;
    uint64_t w1 = w + 1 < PH_PROD ? p[w + 1] : 0u;
    uint64_t w2 = w + 2 < PH_PROD ? p[w + 2] : 0u;
    uint64_t r = (w0 | (w1 << 32)) >> s;
    if (s != 0) r |= w2 << (64 - s);
    return r;
}

/* Number of leading zero bits of a nonzero u. */
static int32_t ph_clz64(uint64_t u)
{
    int32_t n = 0;
    if ((u >> 32) == 0) { n += 32; u <<= 32; }
    if ((u >> 48) == 0) { n += 16; u <<= 16; }
    if ((u >> 56) == 0) { n += 8; u <<= 8; }
    if ((u >> 60) == 0) { n += 4; u <<= 4; }
    if ((u >> 62) == 0) { n += 2; u <<= 2; }
    if ((u >> 63) == 0) { n += 1; }
    return n;
}

/* For x = m * 2^e (m < 2^53, x >= pi/4, e <= 971): x * 2/pi = n + f with n
 * an integer and -1/2 <= f < 1/2. Returns n mod 4 and writes |f| normalised:
 * |f| ~= (*hi * 2^64 + *lo) * 2^(-128 - *lz) with bit 63 of *hi set, and the
 * sign of f in *neg. Error of |f|: below 2^-127 absolute. */
static uint32_t ph_reduce(uint64_t m, int32_t e, uint64_t *hi, uint64_t *lo,
                          int32_t *lz, int32_t *neg)
{
    uint32_t p[PH_PROD];
    uint32_t w[PH_WORDS];
    uint32_t mw[2];
    int32_t j0 = e >= 2 ? (e - 2) / 32 : 0; /* bits below index e-1 only add multiples of 4 */
    int32_t q = 32 * (j0 + PH_WORDS) - e;   /* binary point of the product, 191..278 */
    int32_t i, k;
    uint32_t quad;
    uint64_t fh, fl;

    for (i = 0; i < PH_WORDS; i++) w[i] = two_over_pi[j0 + PH_WORDS - 1 - i];
    for (i = 0; i < PH_PROD; i++) p[i] = 0u;
    mw[0] = (uint32_t)m;
    mw[1] = (uint32_t)(m >> 32);
    for (i = 0; i < 2; i++) {
        uint64_t carry = 0u;
        for (k = 0; k < PH_WORDS; k++) {
            uint64_t t = (uint64_t)mw[i] * w[k] + p[i + k] + carry;
            p[i + k] = (uint32_t)t;
            carry = t >> 32;
        }
        p[i + PH_WORDS] = (uint32_t)carry;
    }
    quad = (uint32_t)ph_get64(p, q) & 3u;
    fh = ph_get64(p, q - 64);
    fl = ph_get64(p, q - 128);
    *neg = 0;
    if (fh >> 63) { /* f >= 1/2: round n up, f -= 1 */
        quad = (quad + 1u) & 3u;
        *neg = 1;
        fl = ~fl + 1u;
        /* cppcheck-suppress knownConditionTrueFalse ; fl == 0 after the wrap of ~0 + 1: the negation's carry */
        fh = ~fh + (fl == 0u ? 1u : 0u);
    }
    *lz = 0;
    if (fh == 0u) { /* cannot happen for finite doubles; kept for safety */
        fh = fl;
        fl = 0u;
        *lz = 64;
    }
    if (fh != 0u) {
        int32_t n = ph_clz64(fh);
        if (n != 0) {
            fh = (fh << n) | (fl >> (64 - n));
            fl <<= n;
        }
        *lz += n;
    }
    *hi = fh;
    *lo = fl;
    return quad;
}

/* ------------------------------------------------------------------ */
/* double                                                               */

/* |x| >= pi/4, finite: returns the quadrant, *rh + *rl = x - n*pi/2. */
static uint32_t reduce_d(double ax, double *rh, double *rl)
{
    uint64_t u = md_bits(ax);
    uint64_t m = (u & 0x000fffffffffffffull) | 0x0010000000000000ull;
    int32_t e = (int32_t)(u >> 52) - 1075;
    uint64_t fh, fl;
    int32_t lz, neg;
    uint32_t quad = ph_reduce(m, e, &fh, &fl, &lz, &neg);
    double a = (double)(int64_t)(fh >> 11) * md_pow2(-53 - lz);
    double b = (double)(int64_t)(((fh & 0x7ffu) << 42) | (fl >> 22)) * md_pow2(-106 - lz);
    double ph, pl;
    md_two_prod(a, PIO2_HI, &ph, &pl);
    pl += a * PIO2_LO + b * PIO2_HI;
    md_fast_two_sum(ph, pl, rh, rl);
    if (neg) {
        *rh = -*rh;
        *rl = -*rl;
    }
    return quad;
}

/* pi/4 < ax < 2^20: n = round(ax 2/pi) < 2^20, so n times each 33-bit chunk
 * of pi/2 is exact, and the subtractions are carried exactly (two_sum); pi/2
 * is represented to 152 bits, the result to about 2^-130 absolute. Returns
 * n mod 4, *rh + *rl = ax - n pi/2. */
static uint32_t reduce_medium_d(double ax, double *rh, double *rl)
{
    double nf = (ax * INV_PIO2 + 0x1.8p52) - 0x1.8p52;
    double r = ax - nf * PIO2_C1; /* exact */
    double t, e1, e2, lo;
    md_two_sum(r, -(nf * PIO2_C2), &t, &e1);
    md_two_sum(t, -(nf * PIO2_C3), &t, &e2);
    lo = (e1 + e2) - nf * PIO2_C4;
    md_two_sum(t, lo, rh, rl);
    return (uint32_t)(int32_t)nf & 3u;
}

/* sin(x + xl), |x| <= pi/4, |xl| <= ulp(x). */
static double sin_kernel(double x, double xl)
{
    double z = x * x;
    double s = SIN_S0 + z * (SIN_S1 + z * (SIN_S2 + z * (SIN_S3 + z * (SIN_S4 + z * (SIN_S5 + z * SIN_S6)))));
    return x + (x * z * s + xl * (1.0 - 0.5 * z));
}

/* cos(x + xl), |x| <= pi/4, |xl| <= ulp(x). 1 - x^2/2 is formed exactly. */
static double cos_kernel(double x, double xl)
{
    double zh, zl, hz, w, c;
    md_two_prod(x, x, &zh, &zl);
    hz = 0.5 * zh;
    w = 1.0 - hz;
    c = COS_C0 + zh * (COS_C1 + zh * (COS_C2 + zh * (COS_C3 + zh * (COS_C4 + zh * COS_C5))));
    return w + ((((1.0 - w) - hz) - 0.5 * zl) + (zh * zh * c - x * xl));
}

/* flags: 1 = want sin, 2 = want cos. */
static void sincos_d(double x, double *s, double *c, int flags)
{
    uint64_t ax = md_bits(x) & LS_D_ABS;
    double rh, rl, sv = 0.0, cv = 0.0;
    uint32_t q;
    if (ax >= LS_D_INF) { /* NaN, +-Inf */
        if (flags & 1) *s = md_nan();
        if (flags & 2) *c = md_nan();
        return;
    }
    if (ax < 0x3e40000000000000ull) { /* |x| < 2^-27: sin x = x, cos x = 1 */
        if (flags & 1) *s = x;
        if (flags & 2) *c = 1.0;
        return;
    }
    if (ax <= md_bits(PIO4_HI)) {
        if (flags & 1) *s = sin_kernel(x, 0.0);
        if (flags & 2) *c = cos_kernel(x, 0.0);
        return;
    }
    if (ax < 0x4130000000000000ull) q = reduce_medium_d(md_from(ax), &rh, &rl); /* < 2^20 */
    else q = reduce_d(md_from(ax), &rh, &rl);
    /* sin x needs the sin kernel in even quadrants, cos x in odd ones */
    if (((flags & 1) && !(q & 1u)) || ((flags & 2) && (q & 1u))) sv = sin_kernel(rh, rl);
    if (((flags & 1) && (q & 1u)) || ((flags & 2) && !(q & 1u))) cv = cos_kernel(rh, rl);
    if (flags & 1) {
        double r = (q & 1u) ? cv : sv;
        if (q & 2u) r = -r;
        *s = (x < 0.0) ? -r : r;
    }
    if (flags & 2) {
        double r = (q & 1u) ? sv : cv;
        if (((q + 1u) & 2u) != 0u) r = -r;
        *c = r;
    }
}

double ls_sin(double x)
{
    double s = 0.0;
    sincos_d(x, &s, &s, 1);
    return s;
}

double ls_cos(double x)
{
    double c = 0.0;
    sincos_d(x, &c, &c, 2);
    return c;
}

void ls_sincos(double x, double *s, double *c)
{
    double sv = 0.0, cv = 0.0;
    sincos_d(x, &sv, &cv, 3);
    if (s) *s = sv;
    if (c) *c = cv;
}

/* atan(th + tl) for 0 <= th <= 1, as *rh + *rl. */
static void atan_dd(double th, double tl, double *rh, double *rl)
{
    int32_t j = (int32_t)(th * 16.0 + 0.5);
    double uh, ul, z, a, sh, se, lo;
    if (j == 0) {
        uh = th;
        ul = tl;
    } else {
        /* u = (t - c) / (1 + t c), c = j/16: atan t = atan c + atan u */
        double c = (double)j * 0.0625;
        double nh, nl, ph, pl, dh, dl;
        md_two_sum(th - c, tl, &nh, &nl); /* th - c is exact */
        md_two_prod(c, th, &ph, &pl);
        md_fast_two_sum(1.0, ph, &dh, &dl);
        dl += pl + c * tl;
        uh = nh / dh;
        md_two_prod(uh, dh, &ph, &pl);
        ul = (((nh - ph) - pl) + nl - uh * dl) / dh;
    }
    z = uh * uh;
    a = ATAN_A0 + z * (ATAN_A1 + z * (ATAN_A2 + z * (ATAN_A3 + z * (ATAN_A4 + z * ATAN_A5))));
    md_two_sum(atan_tab[2 * (size_t)j], uh, &sh, &se);
    lo = se + (atan_tab[2 * (size_t)j + 1] + (ul + uh * z * a));
    md_fast_two_sum(sh, lo, rh, rl);
}

/* (ah + al) - (bh + bl) as a double-double. */
static void dd_sub(double ah, double al, double bh, double bl, double *rh, double *rl)
{
    double s, e;
    md_two_sum(ah, -bh, &s, &e);
    e += al - bl;
    md_fast_two_sum(s, e, rh, rl);
}

double ls_atan(double x)
{
    uint64_t ax = md_bits(x) & LS_D_ABS;
    double a = md_from(ax), rh, rl, r;
    if (ax > LS_D_INF) return md_nan();
    if (ax < 0x3e40000000000000ull) return x; /* |x| < 2^-27 */
    if (ax <= 0x3ff0000000000000ull) {
        atan_dd(a, 0.0, &rh, &rl);
        r = rh + rl;
    } else if (ax >= 0x43b0000000000000ull) { /* |x| >= 2^60, incl. Inf */
        r = PIO2_HI + (PIO2_LO - 1.0 / a);
    } else {
        double th = 1.0 / a, tl, p, e;
        md_two_prod(th, a, &p, &e);
        tl = ((1.0 - p) - e) / a;
        atan_dd(th, tl, &rh, &rl);
        dd_sub(PIO2_HI, PIO2_LO, rh, rl, &rh, &rl);
        r = rh + rl;
    }
    return (x < 0.0) ? -r : r;
}

double ls_atan2(double y, double x)
{
    uint64_t ux = md_bits(x), uy = md_bits(y);
    uint64_t ax = ux & LS_D_ABS, ay = uy & LS_D_ABS;
    int32_t xneg = (int32_t)(ux >> 63);
    double r;
    if (ax > LS_D_INF || ay > LS_D_INF) return md_nan();
    if (ay == 0u) {
        if (!xneg) return y;   /* atan2(+-0, +x) = +-0 */
        r = PI_HI;             /* atan2(+-0, -x) = +-pi */
    } else if (ax == 0u || (ay == LS_D_INF && ax != LS_D_INF)) {
        r = PIO2_HI;
    } else if (ax == LS_D_INF) {
        if (ay == LS_D_INF) r = xneg ? PI3O4_HI : PIO4_HI;
        else if (xneg) r = PI_HI;
        else return (uy >> 63) ? -0.0 : 0.0;
    } else {
        int32_t swap = ay > ax;
        double num = md_from(swap ? ax : ay), den = md_from(swap ? ay : ax);
        double th, tl;
        if (num * 0x1p60 < den) { /* atan q = q to 2^-120 relative */
            th = num / den;
            tl = 0.0;
        } else {
            double qh, ql, p, e;
            if (den < 0x1p-500) {
                num *= 0x1p600;
                den *= 0x1p600;
            } else if (den > 0x1p500) {
                num *= 0x1p-600;
                den *= 0x1p-600;
            }
            qh = num / den;
            md_two_prod(qh, den, &p, &e);
            ql = ((num - p) - e) / den;
            atan_dd(qh, ql, &th, &tl);
        }
        if (swap) dd_sub(PIO2_HI, PIO2_LO, th, tl, &th, &tl);
        if (xneg) dd_sub(PI_HI, PI_LO, th, tl, &th, &tl);
        r = th + tl;
    }
    return (uy >> 63) ? -r : r;
}

/* ------------------------------------------------------------------ */
/* float (float arithmetic only)                                        */

static uint32_t reduce_f(float ax, float *rh, float *rl)
{
    uint32_t u = mf_bits(ax);
    uint64_t m = (uint64_t)((u & 0x007fffffu) | 0x00800000u);
    int32_t e = (int32_t)(u >> 23) - 150;
    uint64_t fh, fl;
    int32_t lz, neg;
    uint32_t quad = ph_reduce(m, e, &fh, &fl, &lz, &neg);
    float a, b, ph, pl;
    (void)fl;
    if (lz > 70) lz = 70; /* unreachable for floats (|f| > 2^-40); keeps 2^k in range */
    a = (float)(int32_t)(fh >> 40) * mf_pow2(-24 - lz);
    b = (float)(int32_t)((fh >> 16) & 0xffffffu) * mf_pow2(-48 - lz);
    mf_two_prod(a, PIO2F_HI, &ph, &pl);
    pl += a * PIO2F_LO + b * PIO2F_HI;
    mf_fast_two_sum(ph, pl, rh, rl);
    if (neg) {
        *rh = -*rh;
        *rl = -*rl;
    }
    return quad;
}

/* pi/4 < ax < 2^10: as reduce_medium_d with four 14-bit chunks (80 bits). */
static uint32_t reduce_medium_f(float ax, float *rh, float *rl)
{
    float nf = (ax * INV_PIO2F + 0x1.8p23f) - 0x1.8p23f;
    float r = ax - nf * PIO2F_C1; /* exact */
    float t, e1, e2, e3, lo;
    mf_two_sum(r, -(nf * PIO2F_C2), &t, &e1);
    mf_two_sum(t, -(nf * PIO2F_C3), &t, &e2);
    mf_two_sum(t, -(nf * PIO2F_C4), &t, &e3);
    lo = ((e1 + e2) + e3) - nf * PIO2F_C5;
    mf_two_sum(t, lo, rh, rl);
    return (uint32_t)(int32_t)nf & 3u;
}

static float sinf_kernel(float x, float xl)
{
    float z = x * x;
    float s = SINF_S0 + z * (SINF_S1 + z * (SINF_S2 + z * (SINF_S3 + z * SINF_S4)));
    return x + (x * z * s + xl * (1.0f - 0.5f * z));
}

static float cosf_kernel(float x, float xl)
{
    float zh, zl, hz, w, c;
    mf_two_prod(x, x, &zh, &zl);
    hz = 0.5f * zh;
    w = 1.0f - hz;
    c = COSF_C0 + zh * (COSF_C1 + zh * (COSF_C2 + zh * COSF_C3));
    return w + ((((1.0f - w) - hz) - 0.5f * zl) + (zh * zh * c - x * xl));
}

static void sincos_f(float x, float *s, float *c, int flags)
{
    uint32_t ax = mf_bits(x) & LS_F_ABS;
    float rh, rl, sv = 0.0f, cv = 0.0f;
    uint32_t q;
    if (ax >= LS_F_INF) {
        if (flags & 1) *s = mf_nan();
        if (flags & 2) *c = mf_nan();
        return;
    }
    if (ax < 0x39800000u) { /* |x| < 2^-12 */
        if (flags & 1) *s = x;
        if (flags & 2) *c = 1.0f;
        return;
    }
    if (ax <= 0x3f490fdau) { /* largest float below pi/4 */
        if (flags & 1) *s = sinf_kernel(x, 0.0f);
        if (flags & 2) *c = cosf_kernel(x, 0.0f);
        return;
    }
    if (ax < 0x44800000u) q = reduce_medium_f(mf_from(ax), &rh, &rl); /* < 2^10 */
    else q = reduce_f(mf_from(ax), &rh, &rl);
    /* sin x needs the sin kernel in even quadrants, cos x in odd ones */
    if (((flags & 1) && !(q & 1u)) || ((flags & 2) && (q & 1u))) sv = sinf_kernel(rh, rl);
    if (((flags & 1) && (q & 1u)) || ((flags & 2) && !(q & 1u))) cv = cosf_kernel(rh, rl);
    if (flags & 1) {
        float r = (q & 1u) ? cv : sv;
        if (q & 2u) r = -r;
        *s = (x < 0.0f) ? -r : r;
    }
    if (flags & 2) {
        float r = (q & 1u) ? sv : cv;
        if (((q + 1u) & 2u) != 0u) r = -r;
        *c = r;
    }
}

float ls_sinf(float x)
{
    float s = 0.0f;
    sincos_f(x, &s, &s, 1);
    return s;
}

float ls_cosf(float x)
{
    float c = 0.0f;
    sincos_f(x, &c, &c, 2);
    return c;
}

void ls_sincosf(float x, float *s, float *c)
{
    float sv = 0.0f, cv = 0.0f;
    sincos_f(x, &sv, &cv, 3);
    if (s) *s = sv;
    if (c) *c = cv;
}

static void atanf_ff(float th, float tl, float *rh, float *rl)
{
    int32_t j = (int32_t)(th * 16.0f + 0.5f);
    float uh, ul, z, a, sh, se, lo;
    if (j == 0) {
        uh = th;
        ul = tl;
    } else {
        float c = (float)j * 0.0625f;
        float nh, nl, ph, pl, dh, dl;
        mf_two_sum(th - c, tl, &nh, &nl);
        mf_two_prod(c, th, &ph, &pl);
        mf_fast_two_sum(1.0f, ph, &dh, &dl);
        dl += pl + c * tl;
        uh = nh / dh;
        mf_two_prod(uh, dh, &ph, &pl);
        ul = (((nh - ph) - pl) + nl - uh * dl) / dh;
    }
    z = uh * uh;
    a = ATANF_A0 + z * (ATANF_A1 + z * ATANF_A2);
    mf_two_sum(atanf_tab[2 * (size_t)j], uh, &sh, &se);
    lo = se + (atanf_tab[2 * (size_t)j + 1] + (ul + uh * z * a));
    mf_fast_two_sum(sh, lo, rh, rl);
}

static void ff_sub(float ah, float al, float bh, float bl, float *rh, float *rl)
{
    float s, e;
    mf_two_sum(ah, -bh, &s, &e);
    e += al - bl;
    mf_fast_two_sum(s, e, rh, rl);
}

float ls_atanf(float x)
{
    uint32_t ax = mf_bits(x) & LS_F_ABS;
    float a = mf_from(ax), rh, rl, r;
    if (ax > LS_F_INF) return mf_nan();
    if (ax < 0x39800000u) return x; /* |x| < 2^-12 */
    if (ax <= 0x3f800000u) {
        atanf_ff(a, 0.0f, &rh, &rl);
        r = rh + rl;
    } else if (ax >= 0x4d800000u) { /* |x| >= 2^28, incl. Inf */
        r = PIO2F_HI + (PIO2F_LO - 1.0f / a);
    } else {
        float th = 1.0f / a, tl, p, e;
        mf_two_prod(th, a, &p, &e);
        tl = ((1.0f - p) - e) / a;
        atanf_ff(th, tl, &rh, &rl);
        ff_sub(PIO2F_HI, PIO2F_LO, rh, rl, &rh, &rl);
        r = rh + rl;
    }
    return (x < 0.0f) ? -r : r;
}

float ls_atan2f(float y, float x)
{
    uint32_t ux = mf_bits(x), uy = mf_bits(y);
    uint32_t ax = ux & LS_F_ABS, ay = uy & LS_F_ABS;
    int32_t xneg = (int32_t)(ux >> 31);
    float r;
    if (ax > LS_F_INF || ay > LS_F_INF) return mf_nan();
    if (ay == 0u) {
        if (!xneg) return y;
        r = PIF_HI;
    } else if (ax == 0u || (ay == LS_F_INF && ax != LS_F_INF)) {
        r = PIO2F_HI;
    } else if (ax == LS_F_INF) {
        if (ay == LS_F_INF) r = xneg ? PI3O4F_HI : PIO4F_HI;
        else if (xneg) r = PIF_HI;
        else return (uy >> 31) ? -0.0f : 0.0f;
    } else {
        int32_t swap = ay > ax;
        float num = mf_from(swap ? ax : ay), den = mf_from(swap ? ay : ax);
        float th, tl;
        if (num * 0x1p30f < den) {
            th = num / den;
            tl = 0.0f;
        } else {
            float qh, ql, p, e;
            uint32_t ud = mf_bits(den);
            int32_t ed;
            if (ud < 0x00800000u) { /* subnormal: scale up first (exact) */
                num *= 0x1p24f;
                den *= 0x1p24f;
                ud = mf_bits(den);
            }
            /* scale both by 2^-ed (exact) so that den is in [1, 2) and
             * the error terms of the products below stay normal */
            ed = (int32_t)(ud >> 23) - 127;
            num = (num * mf_pow2(-(ed / 2))) * mf_pow2(ed / 2 - ed);
            den = (den * mf_pow2(-(ed / 2))) * mf_pow2(ed / 2 - ed);
            qh = num / den;
            mf_two_prod(qh, den, &p, &e);
            ql = ((num - p) - e) / den;
            atanf_ff(qh, ql, &th, &tl);
        }
        if (swap) ff_sub(PIO2F_HI, PIO2F_LO, th, tl, &th, &tl);
        if (xneg) ff_sub(PIF_HI, PIF_LO, th, tl, &th, &tl);
        r = th + tl;
    }
    return (uy >> 31) ? -r : r;
}
