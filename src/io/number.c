/* number.c - correctly rounded, locale-free decimal <-> binary conversion.
 *
 * Slow path: the decimal value is held as digits d[0..nd) with value
 * 0.d0 d1 d2... * 10^dp, plus a flag saying that nonzero digits beyond the
 * buffer were dropped. Multiplying or dividing by 2^k (k <= 60) is exact on
 * the digits (long multiplication / division with a 64-bit carry); digits
 * that fall off the end of the buffer only set the flag. Truncation is
 * monotone and every halfway point between two doubles has at most 767
 * significant digits, so comparing the truncated digits with the halfway
 * point, with the flag breaking the tie, rounds exactly.
 * Fast path (Clinger): up to 19 digits with a mantissa that is exact in the
 * target type and a small power of ten: one correctly rounded IEEE multiply
 * or divide of exact operands.
 */
#include <largesteps/number.h>
#include <largesteps/status.h>
#include <string.h>

#define DEC_CAP 800
#define EXP_SATURATE 100000000

typedef struct dec {
    int32_t nd;    /* digits in use; d[0] != 0 when nd > 0 */
    int32_t dp;    /* value = 0.d[0]d[1]... * 10^dp */
    int32_t trunc; /* nonzero digits were dropped after d[nd-1] */
    uint8_t d[DEC_CAP];
} dec;

/* floor(j * log2(10)): shifting by this many bits never crosses 10^j. */
static const uint8_t pow10_bits[19] = {0, 3, 6, 9, 13, 16, 19, 23, 26, 29, 33, 36, 39, 43, 46, 49, 53, 56, 59};

static const double pow10_double[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                        1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
static const float pow10_float[11] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f,
                                      1e6f, 1e7f, 1e8f, 1e9f, 1e10f};

static void dec_trim(dec *a)
{
    while (a->nd > 0 && a->d[a->nd - 1] == 0) a->nd--;
    if (a->nd == 0) a->dp = 0;
}

/* a /= 2^k, 1 <= k <= 60. */
static void dec_shr(dec *a, uint32_t k)
{
    int32_t r = 0, w = 0;
    uint64_t n = 0;
    const uint64_t mask = ((uint64_t)1 << k) - 1u;
    if (a->nd == 0) return;
    while ((n >> k) == 0) {
        n = n * 10u + (r < a->nd ? a->d[r] : 0u);
        r++;
    }
    a->dp -= r - 1;
    while (r < a->nd) {
        a->d[w++] = (uint8_t)(n >> k);
        n = (n & mask) * 10u + a->d[r++];
    }
    while (n != 0) {
        uint8_t q = (uint8_t)(n >> k);
        if (w < DEC_CAP) {
            a->d[w++] = q;
        } else if (q != 0) {
            a->trunc = 1;
        }
        n = (n & mask) * 10u;
    }
    a->nd = w;
    dec_trim(a);
}

/* a *= 2^k, 1 <= k <= 60. */
static void dec_shl(dec *a, uint32_t k)
{
    const int32_t extra = (int32_t)(k / 3u) + 1; /* >= decimal digits of a carry < 2^k */
    int32_t i, w, len;
    uint64_t carry = 0;
    if (a->nd == 0) return;
    len = a->nd + extra;
    if (len > DEC_CAP) len = DEC_CAP;
    for (i = a->nd - 1; i >= 0; i--) {
        uint64_t n = ((uint64_t)a->d[i] << k) + carry;
        uint8_t digit = (uint8_t)(n % 10u);
        carry = n / 10u;
        w = i + extra;
        if (w < DEC_CAP) {
            a->d[w] = digit;
        } else if (digit != 0) {
            a->trunc = 1;
        }
    }
    w = extra;
    while (carry != 0) {
        w--;
        a->d[w] = (uint8_t)(carry % 10u);
        carry /= 10u;
    }
    if (w > 0) memmove(a->d, a->d + w, (size_t)(len - w));
    a->nd = len - w;
    a->dp += extra - w;
    dec_trim(a);
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

/* Case-insensitive match of the lowercase word at s[i..). */
static int match_word(const char *s, size_t len, size_t i, const char *word)
{
    size_t k;
    for (k = 0; word[k] != 0; k++) {
        int c;
        if (i + k >= len) return 0;
        c = s[i + k] >= 'A' && s[i + k] <= 'Z' ? s[i + k] - 'A' + 'a' : s[i + k];
        if (c != word[k]) return 0;
    }
    return 1;
}

#define SPECIAL_NONE 0
#define SPECIAL_INF 1
#define SPECIAL_NAN 2

/* Scans the longest number at s[0..len); fills a (if not NULL) with its
 * significant digits. Returns the length matched, 0 for none. */
static size_t scan(const char *s, size_t len, dec *a, int *neg, int *special)
{
    size_t i = 0;
    int64_t dp = 0;
    int seen_digit = 0, seen_nonzero = 0;
    *neg = 0;
    *special = SPECIAL_NONE;
    if (a != NULL) {
        a->nd = 0;
        a->dp = 0;
        a->trunc = 0;
    }
    if (s == NULL) return 0;
    if (i < len && (s[i] == '+' || s[i] == '-')) {
        *neg = s[i] == '-';
        i++;
    }
    if (match_word(s, len, i, "infinity")) {
        *special = SPECIAL_INF;
        return i + 8;
    }
    if (match_word(s, len, i, "inf")) {
        *special = SPECIAL_INF;
        return i + 3;
    }
    if (match_word(s, len, i, "nan")) {
        *special = SPECIAL_NAN;
        return i + 3;
    }
    for (; i < len && is_digit(s[i]); i++) {
        uint8_t c = (uint8_t)(s[i] - '0');
        seen_digit = 1;
        if (c == 0 && !seen_nonzero) continue;
        seen_nonzero = 1;
        dp++;
        if (a == NULL) continue;
        if (a->nd < DEC_CAP) {
            a->d[a->nd++] = c;
        } else if (c != 0) {
            a->trunc = 1;
        }
    }
    if (i < len && s[i] == '.') {
        for (i++; i < len && is_digit(s[i]); i++) {
            uint8_t c = (uint8_t)(s[i] - '0');
            seen_digit = 1;
            if (c == 0 && !seen_nonzero) {
                dp--;
                continue;
            }
            seen_nonzero = 1;
            if (a == NULL) continue;
            if (a->nd < DEC_CAP) {
                a->d[a->nd++] = c;
            } else if (c != 0) {
                a->trunc = 1;
            }
        }
    }
    if (!seen_digit) return 0;
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        size_t j = i + 1;
        int eneg = 0;
        if (j < len && (s[j] == '+' || s[j] == '-')) {
            eneg = s[j] == '-';
            j++;
        }
        if (j < len && is_digit(s[j])) {
            int64_t e = 0;
            for (; j < len && is_digit(s[j]); j++) {
                if (e < EXP_SATURATE) e = e * 10 + (s[j] - '0');
            }
            dp += eneg ? -e : e;
            i = j;
        }
    }
    if (a != NULL) {
        if (dp > EXP_SATURATE) dp = EXP_SATURATE;
        if (dp < -EXP_SATURATE) dp = -EXP_SATURATE;
        a->dp = (int32_t)dp;
        dec_trim(a);
    }
    return i;
}

size_t ls_scan_number(const char *text, size_t len)
{
    int neg, special;
    return scan(text, len, NULL, &neg, &special);
}

/* The format parameters of one binary type. */
typedef struct fmt {
    uint32_t mbits; /* stored fraction bits: 52 or 23 */
    int32_t emin;   /* smallest normal exponent: -1022 or -126 */
    int32_t emax;   /* largest exponent: 1023 or 127 */
    int32_t dpmax;  /* dp at or above this: certainly overflows */
    int32_t dpmin;  /* dp at or below this: certainly rounds to zero */
} fmt;

static const fmt fmt_double = {52u, -1022, 1023, 310, -324};
static const fmt fmt_float = {23u, -126, 127, 40, -46};

/* The bits (without sign) of the correctly rounded value of a; sets
 * *overflow and returns the infinity's bits when it does not fit. */
static uint64_t dec_to_bits(dec *a, const fmt *f, int *overflow)
{
    int32_t e = 0, E, i;
    uint64_t m = 0, biased;
    const uint64_t inf_bits = (uint64_t)(f->emax * 2 + 1) << f->mbits;
    *overflow = 0;
    if (a->nd == 0 || a->dp <= f->dpmin) return 0;
    if (a->dp >= f->dpmax) {
        *overflow = 1;
        return inf_bits;
    }
    while (a->dp > 0) {
        uint32_t k = a->dp >= 19 ? 60u : pow10_bits[a->dp];
        dec_shr(a, k);
        e += (int32_t)k;
    }
    while (a->dp < 0 || (a->dp == 0 && a->d[0] < 5)) {
        uint32_t k = a->dp <= -19 ? 60u : (a->dp == 0 ? 1u : pow10_bits[-a->dp]);
        dec_shl(a, k);
        e -= (int32_t)k;
    }
    /* value = v * 2^e with v in [0.5, 1), i.e. (2v) * 2^E */
    E = e - 1;
    if (E < f->emin) {
        int32_t s = f->emin - E;
        if (s > (int32_t)f->mbits + 2) return 0;
        dec_shr(a, (uint32_t)s);
        E = f->emin;
    }
    dec_shl(a, f->mbits + 1u);
    for (i = 0; i < a->dp; i++) m = m * 10u + (i < a->nd ? a->d[i] : 0u);
    if (a->dp >= 0 && a->dp < a->nd) {
        uint8_t r = a->d[a->dp];
        if (r > 5 || (r == 5 && (a->dp + 1 < a->nd || a->trunc || (m & 1u)))) m++;
    }
    if ((m >> (f->mbits + 1u)) != 0) {
        m >>= 1;
        E++;
    }
    if (E > f->emax) {
        *overflow = 1;
        return inf_bits;
    }
    biased = (m >> f->mbits) != 0 ? (uint64_t)(E + f->emax) : 0u;
    return (biased << f->mbits) | (m & (((uint64_t)1 << f->mbits) - 1u));
}

/* The digits as an integer when there are at most 19 of them. */
static int dec_small(const dec *a, uint64_t *w, int32_t *q)
{
    int32_t i;
    uint64_t v = 0;
    if (a->nd > 19 || a->trunc) return 0;
    for (i = 0; i < a->nd; i++) v = v * 10u + a->d[i];
    *w = v;
    *q = a->dp - a->nd;
    return 1;
}

ls_status ls_parse_double(const char *text, size_t len, double *out)
{
    dec a;
    int neg, special, overflow = 0;
    uint64_t bits, w;
    int32_t q;
    double v;
    if (out == NULL || (text == NULL && len > 0)) return LS_ERR_INVALID;
    if (len == 0 || scan(text, len, &a, &neg, &special) != len) return LS_ERR_PARSE;
    if (special == SPECIAL_INF) {
        bits = (uint64_t)0x7ff0000000000000u;
    } else if (special == SPECIAL_NAN) {
        bits = (uint64_t)0x7ff8000000000000u;
    } else if (dec_small(&a, &w, &q) && w <= ((uint64_t)1 << 53) && q >= -22 && q <= 22) {
        v = (double)w;
        v = q < 0 ? v / pow10_double[-q] : v * pow10_double[q];
        memcpy(&bits, &v, sizeof bits);
    } else {
        bits = dec_to_bits(&a, &fmt_double, &overflow);
    }
    if (neg) bits |= (uint64_t)1 << 63;
    memcpy(&v, &bits, sizeof v);
    *out = v;
    return overflow ? LS_ERR_TOO_LARGE : LS_OK;
}

ls_status ls_parse_float(const char *text, size_t len, float *out)
{
    dec a;
    int neg, special, overflow = 0;
    uint64_t wide, w;
    uint32_t bits;
    int32_t q;
    float v;
    if (out == NULL || (text == NULL && len > 0)) return LS_ERR_INVALID;
    if (len == 0 || scan(text, len, &a, &neg, &special) != len) return LS_ERR_PARSE;
    if (special == SPECIAL_INF) {
        bits = 0x7f800000u;
    } else if (special == SPECIAL_NAN) {
        bits = 0x7fc00000u;
    } else if (dec_small(&a, &w, &q) && w <= ((uint64_t)1 << 24) && q >= -10 && q <= 10) {
        v = (float)(uint32_t)w;
        v = q < 0 ? v / pow10_float[-q] : v * pow10_float[q];
        memcpy(&bits, &v, sizeof bits);
    } else {
        wide = dec_to_bits(&a, &fmt_float, &overflow);
        bits = (uint32_t)wide;
    }
    if (neg) bits |= 0x80000000u;
    memcpy(&v, &bits, sizeof v);
    *out = v;
    return overflow ? LS_ERR_TOO_LARGE : LS_OK;
}

/* --- formatting ------------------------------------------------------- */

static size_t emit(const char *tmp, size_t n, char *buf, size_t cap)
{
    if (buf == NULL || cap == 0) return 0;
    if (n + 1 > cap) {
        buf[0] = 0;
        return 0;
    }
    memcpy(buf, tmp, n);
    buf[n] = 0;
    return n;
}

/* Writes +-mant * 2^e2 with prec significant digits in the "%.<prec>g"
 * layout. */
static size_t format_value(uint64_t mant, int32_t e2, int neg, int32_t prec, char *buf, size_t cap)
{
    dec a;
    char *tmp;
    size_t n = 0;
    int32_t i, x, nd = 0;
    if (mant == 0) return emit(neg ? "-0" : "0", neg ? 2u : 1u, buf, cap);
    while ((mant & 1u) == 0) {
        mant >>= 1;
        e2++;
    }
    /* the integer mant as digits (generated backwards, then reversed) */
    while (mant != 0) {
        a.d[nd++] = (uint8_t)(mant % 10u);
        mant /= 10u;
    }
    for (i = 0; i < nd / 2; i++) {
        uint8_t t = a.d[i];
        a.d[i] = a.d[nd - 1 - i];
        a.d[nd - 1 - i] = t;
    }
    a.nd = nd;
    a.dp = nd;
    a.trunc = 0;
    dec_trim(&a);
    while (e2 > 0) {
        uint32_t k = e2 > 60 ? 60u : (uint32_t)e2;
        dec_shl(&a, k);
        e2 -= (int32_t)k;
    }
    while (e2 < 0) {
        uint32_t k = e2 < -60 ? 60u : (uint32_t)-e2;
        dec_shr(&a, k);
        e2 += (int32_t)k;
    }
    /* round to prec digits, half to even (ties happen only when exact) */
    if (a.nd > prec) {
        uint8_t r = a.d[prec];
        int up = r > 5 || (r == 5 && (a.nd > prec + 1 || (a.d[prec - 1] & 1u)));
        a.nd = prec;
        if (up) {
            i = prec - 1;
            while (i >= 0 && a.d[i] == 9) {
                a.d[i] = 0;
                i--;
            }
            if (i < 0) {
                a.d[0] = 1;
                a.nd = 1;
                a.dp++;
            } else {
                a.d[i]++;
            }
        }
        dec_trim(&a);
    }
    /* at most prec (<= 17) digits remain: the text is built in the free
     * part of the digit buffer (keeps the stack frame under 1 KiB) */
    tmp = (char *)(a.d + 64);
    if (neg) tmp[n++] = '-';
    x = a.dp - 1; /* decimal exponent of the leading digit */
    if (x >= -4 && x < prec) {
        if (x >= 0) {
            for (i = 0; i <= x; i++) tmp[n++] = (char)('0' + (i < a.nd ? a.d[i] : 0));
            if (a.nd > x + 1) {
                tmp[n++] = '.';
                for (i = x + 1; i < a.nd; i++) tmp[n++] = (char)('0' + a.d[i]);
            }
        } else {
            tmp[n++] = '0';
            tmp[n++] = '.';
            for (i = 0; i < -x - 1; i++) tmp[n++] = '0';
            for (i = 0; i < a.nd; i++) tmp[n++] = (char)('0' + a.d[i]);
        }
    } else {
        int32_t ex = x < 0 ? -x : x;
        tmp[n++] = (char)('0' + a.d[0]);
        if (a.nd > 1) {
            tmp[n++] = '.';
            for (i = 1; i < a.nd; i++) tmp[n++] = (char)('0' + a.d[i]);
        }
        tmp[n++] = 'e';
        tmp[n++] = x < 0 ? '-' : '+';
        if (ex >= 100) tmp[n++] = (char)('0' + ex / 100);
        tmp[n++] = (char)('0' + (ex / 10) % 10);
        tmp[n++] = (char)('0' + ex % 10);
    }
    return emit(tmp, n, buf, cap);
}

static size_t format_special(int neg, int is_nan, char *buf, size_t cap)
{
    char tmp[8];
    size_t n = 0;
    if (neg) tmp[n++] = '-';
    tmp[n++] = is_nan ? 'n' : 'i';
    tmp[n++] = is_nan ? 'a' : 'n';
    tmp[n++] = is_nan ? 'n' : 'f';
    return emit(tmp, n, buf, cap);
}

size_t ls_format_double(double v, char *buf, size_t cap)
{
    uint64_t bits, frac;
    uint32_t ex;
    int neg;
    memcpy(&bits, &v, sizeof bits);
    neg = (int)(bits >> 63);
    ex = (uint32_t)(bits >> 52) & 0x7ffu;
    frac = bits & (((uint64_t)1 << 52) - 1u);
    if (ex == 0x7ffu) return format_special(neg, frac != 0, buf, cap);
    if (ex == 0) return format_value(frac, -1074, neg, 17, buf, cap);
    return format_value(frac | ((uint64_t)1 << 52), (int32_t)ex - 1075, neg, 17, buf, cap);
}

size_t ls_format_float(float v, char *buf, size_t cap)
{
    uint32_t bits, frac, ex;
    int neg;
    memcpy(&bits, &v, sizeof bits);
    neg = (int)(bits >> 31);
    ex = (bits >> 23) & 0xffu;
    frac = bits & 0x7fffffu;
    if (ex == 0xffu) return format_special(neg, frac != 0, buf, cap);
    if (ex == 0) return format_value(frac, -149, neg, 9, buf, cap);
    return format_value(frac | 0x800000u, (int32_t)ex - 150, neg, 9, buf, cap);
}
