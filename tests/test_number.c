/* test_number.c - decimal <-> binary conversion against glibc (strtod,
 * strtof and printf("%.17g") are correctly rounded there) and hard cases.
 *
 *   build/tests/test_number                 the CI tests
 *   build/tests/test_number --all-floats [first last [glibc]]
 *                                           every float bit pattern: format,
 *                                           parse back, compare bits (and,
 *                                           with a 4th argument, the text with
 *                                           glibc's printf("%.9g"))
 */
#include "test.h"
#include <stdlib.h>
#include <time.h>
#include <largesteps/number.h>

/* Sample sizes: smaller under the sanitizers (each program must stay under
 * ~10 s there); the offline --all-floats run covers every float anyway. */
#if defined(__SANITIZE_ADDRESS__)
#define SAMPLE_DIV 5
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SAMPLE_DIV 5
#endif
#endif
#ifndef SAMPLE_DIV
#define SAMPLE_DIV 1
#endif
#define N(x) ((x) / SAMPLE_DIV)

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rnd(void)
{
    /* splitmix64 */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static uint64_t dbits(double v)
{
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    return b;
}
static uint32_t fbits(float v)
{
    uint32_t b;
    memcpy(&b, &v, sizeof b);
    return b;
}
static double from_dbits(uint64_t b)
{
    double v;
    memcpy(&v, &b, sizeof v);
    return v;
}
static float from_fbits(uint32_t b)
{
    float v;
    memcpy(&v, &b, sizeof v);
    return v;
}

static ls_status pd(const char *s, double *v)
{
    return ls_parse_double(s, strlen(s), v);
}
static ls_status pf(const char *s, float *v)
{
    return ls_parse_float(s, strlen(s), v);
}

/* One float: our text equals glibc's "%.9g" and parses back to the bits. */
static int float_roundtrip_one(uint32_t b, char *ours, char *ref, int with_glibc)
{
    float f = from_fbits(b), back = 0;
    ls_status st;
    size_t n = ls_format_float(f, ours, LS_NUMBER_CHARS);
    if (n == 0) return 1;
    if ((b & 0x7f800000u) == 0x7f800000u && (b & 0x7fffffu) != 0) { /* NaN */
        st = ls_parse_float(ours, n, &back);
        return st != LS_OK || back == back || strcmp(ours, (b >> 31) ? "-nan" : "nan") != 0;
    }
    ref[0] = 0;
    if (with_glibc) {
        snprintf(ref, 64, "%.9g", (double)f);
        if (strcmp(ours, ref) != 0) return 2;
    }
    st = ls_parse_float(ours, n, &back);
    if (st != ((b & 0x7fffffffu) == 0x7f800000u ? LS_OK : LS_OK)) return 3;
    return fbits(back) != b ? 4 : 0;
}

static void float_random_bits_roundtrip(void)
{
    char ours[LS_NUMBER_CHARS], ref[64];
    int i, bad = 0;
    for (i = 0; i < N(200000); i++) {
        uint32_t b = (uint32_t)rnd();
        int r = float_roundtrip_one(b, ours, ref, 1);
        if (r != 0 && bad++ < 5) CHECK_MSG(0, "float 0x%08x: ours '%s' ref '%s' (code %d)", b, ours, ref, r);
    }
    /* every float of a few whole binades, including the subnormal ones */
    for (i = 0; i < N(100000); i++) {
        uint32_t b = (uint32_t)i; /* the first subnormals */
        int r = float_roundtrip_one(b, ours, ref, 1);
        if (r != 0 && bad++ < 10) CHECK_MSG(0, "float 0x%08x: ours '%s' ref '%s' (code %d)", b, ours, ref, r);
        b = 0x3f800000u + (uint32_t)i * 41u; /* around 1 */
        r = float_roundtrip_one(b, ours, ref, 1);
        if (r != 0 && bad++ < 10) CHECK_MSG(0, "float 0x%08x: ours '%s' ref '%s' (code %d)", b, ours, ref, r);
        b = 0x7f7fffffu - (uint32_t)i; /* up to FLT_MAX */
        r = float_roundtrip_one(b, ours, ref, 1);
        if (r != 0 && bad++ < 10) CHECK_MSG(0, "float 0x%08x: ours '%s' ref '%s' (code %d)", b, ours, ref, r);
    }
    CHECK_EQ(bad, 0);
}

static void double_random_bits_roundtrip(void)
{
    char ours[LS_NUMBER_CHARS], ref[64];
    int i, bad = 0;
    for (i = 0; i < N(100000); i++) {
        uint64_t b = rnd();
        double v = from_dbits(b), back = 0;
        size_t n;
        if (i % 4 == 1) b = (b & 0x800fffffffffffffull) | ((uint64_t)(1023 + (int)(rnd() % 80) - 40) << 52);
        if (i % 4 == 2) b &= 0x800fffffffffffffull; /* subnormal */
        v = from_dbits(b);
        if (v != v) continue;
        n = ls_format_double(v, ours, sizeof ours);
        snprintf(ref, sizeof ref, "%.17g", v);
        if ((n == 0 || strcmp(ours, ref) != 0) && bad++ < 5) CHECK_MSG(0, "double %016llx: ours '%s' ref '%s'", (unsigned long long)b, ours, ref);
        if (ls_parse_double(ours, n, &back) != (v - v == 0 ? LS_OK : LS_OK) || dbits(back) != b) {
            if (bad++ < 5) CHECK_MSG(0, "double %016llx: '%s' parsed back as %016llx", (unsigned long long)b, ours, (unsigned long long)dbits(back));
        }
    }
    CHECK_EQ(bad, 0);
}

/* Random decimal strings (random digit counts, exponents, zeros) against
 * glibc strtod and strtof. */
static void random_decimal_strings_match_glibc(void)
{
    char s[1200];
    int i, bad = 0;
    for (i = 0; i < N(60000); i++) {
        size_t n = 0;
        int nd = 1 + (int)(rnd() % (i % 10 == 0 ? 900 : 25)), k;
        int point = (int)(rnd() % (uint64_t)(nd + 1));
        int ex = (int)(rnd() % 700) - 350;
        double d = 0, dref;
        float f = 0, fref;
        ls_status st;
        if (rnd() & 1) s[n++] = '-';
        if (i % 7 == 0) s[n++] = '0', s[n++] = '0';
        for (k = 0; k < nd; k++) {
            if (k == point) s[n++] = '.';
            /* runs of 0s and 9s make near-halfway inputs */
            s[n++] = (char)(i % 3 == 0 && k > 2 ? ((i & 8) ? '0' : '9') : '0' + (int)(rnd() % 10));
        }
        if (i % 3 == 0 && (rnd() & 1)) s[n - 1] = (char)('1' + (int)(rnd() % 9));
        if (i % 5 == 0) ex = (int)(rnd() % 90) - 45;
        n += (size_t)sprintf(s + n, "e%d", ex);
        dref = strtod(s, NULL);
        fref = strtof(s, NULL);
        st = ls_parse_double(s, n, &d);
        if ((dbits(d) != dbits(dref) || st != (isinf(dref) ? LS_ERR_TOO_LARGE : LS_OK)) && bad++ < 5)
            CHECK_MSG(0, "double '%s': ours %.17g ref %.17g (%s)", s, d, dref, ls_status_name(st));
        st = ls_parse_float(s, n, &f);
        if ((fbits(f) != fbits(fref) || st != (isinf(fref) ? LS_ERR_TOO_LARGE : LS_OK)) && bad++ < 5)
            CHECK_MSG(0, "float '%s': ours %.9g ref %.9g (%s)", s, (double)f, (double)fref, ls_status_name(st));
    }
    CHECK_EQ(bad, 0);
}

/* The exact decimal value of halfway points between neighbouring floats and
 * doubles, and those plus/minus a tiny amount: ties to even, and any excess
 * decides. */
static void halfway_cases_round_correctly(void)
{
    char s[1300], ref[1300];
    int i, bad = 0;
    for (i = 0; i < N(2000); i++) {
        uint32_t fb = (uint32_t)rnd() & 0x7f7fffffu;
        uint64_t db = rnd() & 0x7fefffffffffffffull;
        double lo, hi, mid;
        float f = 0;
        double d = 0;
        size_t n;
        if (i % 3 == 0) fb &= 0x007fffffu;            /* subnormal floats */
        if (i % 3 == 1) db &= 0x000fffffffffffffull; /* subnormal doubles */
        /* float halfway: exact in double, printed exactly by glibc */
        lo = (double)from_fbits(fb);
        hi = (double)from_fbits(fb + 1);
        mid = (lo + hi) / 2;
        n = (size_t)snprintf(s, sizeof s, "%.160e", mid); /* exact: a float halfway has < 120 digits */
        CHECK(ls_parse_float(s, n, &f) == LS_OK);
        if (fbits(f) != ((fb & 1) ? fb + 1 : fb) && bad++ < 5) CHECK_MSG(0, "float tie %s -> %08x", s, fbits(f));
        /* just above: a 1 after many zeros */
        {
            char *e = strchr(s, 'e');
            char tail[16];
            size_t pre = (size_t)(e - s);
            strcpy(tail, e);
            memset(s + pre, '0', 100);
            s[pre + 100] = '1';
            strcpy(s + pre + 101, tail);
            n = strlen(s);
            CHECK(ls_parse_float(s, n, &f) == LS_OK);
            if (fbits(f) != fb + 1 && bad++ < 5) CHECK_MSG(0, "float above tie -> %08x want %08x", fbits(f), fb + 1);
        }
        /* double halfway: digits of lo + half an ulp, exact from glibc */
        {
            double dl = from_dbits(db);
            int k;
            /* half ulp: print lo and hi exactly and average digit-wise is hard;
             * instead use long arithmetic through printf of lo and hi with 800
             * digits and add them as decimal strings. */
            char a[900], b[900];
            int carry = 0, len;
            snprintf(a, sizeof a, "%.780e", dl);
            snprintf(b, sizeof b, "%.780e", from_dbits(db + 1));
            /* same exponent unless hi crosses a power of ten: skip those */
            if (strcmp(strchr(a, 'e'), strchr(b, 'e')) != 0) continue;
            len = (int)(strchr(a, 'e') - a);
            /* sum a + b digit-wise (skip the '.') into ref, then halve */
            for (k = len - 1; k >= 0; k--) {
                int sd;
                if (a[k] == '.') {
                    ref[k] = '.';
                    continue;
                }
                sd = (a[k] - '0') + (b[k] - '0') + carry;
                ref[k] = (char)('0' + sd % 10);
                carry = sd / 10;
            }
            /* halve ref (with the carry as a leading digit) */
            {
                int rem = carry, o = 0;
                char h[900];
                for (k = 0; k < len; k++) {
                    int cur;
                    if (ref[k] == '.') {
                        h[o++] = '.';
                        continue;
                    }
                    cur = rem * 10 + (ref[k] - '0');
                    h[o++] = (char)('0' + cur / 2);
                    rem = cur % 2;
                }
                h[o] = 0;
                if (rem) continue; /* needs one more digit than printed: skip */
                /* h = (a + b) / 2, at the scale of a */
                snprintf(s, sizeof s, "%s%s", h, strchr(a, 'e'));
            }
            n = strlen(s);
            CHECK(ls_parse_double(s, n, &d) == LS_OK);
            if (dbits(d) != dbits(strtod(s, NULL)) && bad++ < 5) CHECK_MSG(0, "double tie %.40s... -> %016llx", s, (unsigned long long)dbits(d));
            if (dbits(d) != ((db & 1) ? db + 1 : db) && bad++ < 5) CHECK_MSG(0, "double tie %.40s -> %016llx want even", s, (unsigned long long)dbits(d));
        }
    }
    CHECK_EQ(bad, 0);
}

static void boundaries_and_overflow(void)
{
    double d = 0;
    float f = 0;
    /* the overflow threshold 2^1024 - 2^970 (DBL_MAX + half an ulp) ties to even: inf */
    CHECK_STATUS(pd("1.7976931348623158e308", &d), LS_OK);
    CHECK(d == 1.7976931348623157e308);
    CHECK_STATUS(pd("179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497792", &d), LS_ERR_TOO_LARGE);
    CHECK(isinf(d) && d > 0);
    CHECK_STATUS(pd("179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497792.0000000000000000000000000000001", &d), LS_ERR_TOO_LARGE);
    CHECK_STATUS(pd("179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497791.999999999999999999999", &d), LS_OK);
    CHECK(d == 1.7976931348623157e308);
    CHECK_STATUS(pd("-1e309", &d), LS_ERR_TOO_LARGE);
    CHECK(isinf(d) && d < 0);
    CHECK_STATUS(pd("1e99999999999999999999", &d), LS_ERR_TOO_LARGE);
    CHECK_STATUS(pd("1e-99999999999999999999", &d), LS_OK);
    CHECK(d == 0 && !signbit(d));
    CHECK_STATUS(pd("-1e-400", &d), LS_OK);
    CHECK(d == 0 && signbit(d));
    /* subnormal boundaries */
    CHECK_STATUS(pd("4.9406564584124654e-324", &d), LS_OK);
    CHECK_EQ(dbits(d), 1);
    CHECK_STATUS(pd("2.4703282292062327e-324", &d), LS_OK); /* just below half the min: 0 */
    CHECK_EQ(dbits(d), 0);
    CHECK_STATUS(pd("2.4703282292062328e-324", &d), LS_OK); /* just above half: min subnormal */
    CHECK_EQ(dbits(d), 1);
    CHECK_STATUS(pd("2.2250738585072011e-308", &d), LS_OK); /* the famous PHP/Java hang value */
    CHECK_EQ(dbits(d), 0x000fffffffffffffull);
    CHECK_STATUS(pd("2.2250738585072014e-308", &d), LS_OK);
    CHECK_EQ(dbits(d), 0x0010000000000000ull);
    CHECK_STATUS(pf("3.40282356779733661637539395458142568448e38", &f), LS_ERR_TOO_LARGE); /* FLT_MAX + half ulp: tie to even = inf */
    CHECK(isinf(f));
    CHECK_STATUS(pf("3.4028235677973366e38", &f), LS_OK);
    CHECK_EQ(fbits(f), 0x7f7fffffu);
    CHECK_STATUS(pf("1e39", &f), LS_ERR_TOO_LARGE);
    CHECK_STATUS(pf("1.4e-45", &f), LS_OK);
    CHECK_EQ(fbits(f), 1);
    CHECK_STATUS(pf("7.006492321624085e-46", &f), LS_OK); /* just below half the min subnormal */
    CHECK_EQ(fbits(f), 0);
    CHECK_STATUS(pf("7.006492321624087e-46", &f), LS_OK);
    CHECK_EQ(fbits(f), 1);
    CHECK_STATUS(pf("1.17549421e-38", &f), LS_OK); /* largest subnormal region edge */
    CHECK_EQ(fbits(f), fbits(strtof("1.17549421e-38", NULL)));
    /* a float parsed through double would round twice here: 1 + 2^-24 + 2^-60 */
    CHECK_STATUS(pf("1.00000005960464477550", &f), LS_OK);
    CHECK_EQ(fbits(f), 0x3f800001u);
    CHECK_EQ(fbits((float)strtod("1.00000005960464477550", NULL)), 0x3f800000u); /* the double-rounding trap is real */
    /* long digit strings and many zeros */
    {
        static char s[5000];
        size_t n;
        memset(s, '0', 4000);
        s[4000] = '1';
        s[4001] = 0;
        CHECK_STATUS(pd(s, &d), LS_OK);
        CHECK(d == 1.0);
        s[0] = '0';
        s[1] = '.';
        n = 4001;
        CHECK_STATUS(ls_parse_double(s, n, &d), LS_OK);
        CHECK_EQ(dbits(d), dbits(strtod(s, NULL))); /* 1e-3999 -> 0 */
        memcpy(s, "1.", 2);
        memset(s + 2, '0', 3000);
        strcpy(s + 3002, "e0");
        CHECK_STATUS(pd(s, &d), LS_OK);
        CHECK(d == 1.0);
        s[0] = '1';
        memset(s, '1', 2000);
        strcpy(s + 2000, "e-1990");
        CHECK_STATUS(pd(s, &d), LS_OK);
        CHECK_EQ(dbits(d), dbits(strtod(s, NULL)));
    }
    CHECK_STATUS(pd("0.1", &d), LS_OK);
    CHECK(d == 0.1);
    CHECK_STATUS(pf("0.1", &f), LS_OK);
    CHECK(f == 0.1f);
    CHECK_STATUS(pd("-0", &d), LS_OK);
    CHECK(d == 0 && signbit(d));
    CHECK_STATUS(pd("000000.000000e123456789", &d), LS_OK);
    CHECK_EQ(dbits(d), 0);
    CHECK_STATUS(pd("9007199254740993", &d), LS_OK); /* 2^53 + 1: tie to even */
    CHECK(d == 9007199254740992.0);
    CHECK_STATUS(pd("9007199254740995", &d), LS_OK);
    CHECK(d == 9007199254740996.0);
}

static void syntax_accepted_and_rejected(void)
{
    static const char *good[] = {"1", "-2.", ".5", "+1e2", "2.e+1", "1E2", "1e-7", "-inf", "INF", "Infinity",
                                 "nan", "-NaN", "0", "00012", "1.5E+0003", "+.5e-1", "123456789012345678901234567890"};
    static const double good_val[] = {1, -2, .5, 100, 20, 100, 1e-7, -HUGE_VAL, HUGE_VAL, HUGE_VAL, 0, 0, 0, 12, 1500, .05, 123456789012345678901234567890.0};
    static const char *bad[] = {"", "+", "-", ".", "e5", "1e", "1e+", "3.1+e2", "3.1-e2", "0x1p3", "1,5", " 1", "1 ",
                                "nan(1)", "1_000", "--1", "+-1", "1..2", "1.2.3", "infx", "in", "1e5.5", "1d5", "\xef\xbb\xbf\x31", "1\n", "\t1"};
    size_t i;
    for (i = 0; i < sizeof good / sizeof good[0]; i++) {
        double d = 7;
        float f = 7;
        CHECK_MSG(pd(good[i], &d) == LS_OK, "'%s' rejected", good[i]);
        CHECK_MSG(pf(good[i], &f) == LS_OK, "'%s' rejected as float", good[i]);
        if (i == 10 || i == 11) {
            CHECK(d != d && f != f);
            CHECK_EQ(dbits(d) & 0x7fffffffffffffffull, 0x7ff8000000000000ull);
            CHECK_EQ(fbits(f) & 0x7fffffffu, 0x7fc00000u);
            CHECK_EQ(signbit(d) != 0, i == 11);
        } else {
            CHECK_MSG(d == good_val[i], "'%s' -> %.17g", good[i], d);
            CHECK_MSG(f == (float)good_val[i], "'%s' -> %.9g as float", good[i], (double)f);
        }
        CHECK_EQ(ls_scan_number(good[i], strlen(good[i])), strlen(good[i]));
    }
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        double d = 7;
        float f = 7;
        CHECK_MSG(pd(bad[i], &d) == LS_ERR_PARSE, "'%s' accepted", bad[i]);
        CHECK_MSG(pf(bad[i], &f) == LS_ERR_PARSE, "'%s' accepted as float", bad[i]);
        CHECK(d == 7 && f == 7);
    }
    CHECK_EQ(ls_scan_number("3.1+e2", 6), 3);
    CHECK_EQ(ls_scan_number("1e+", 3), 1);
    CHECK_EQ(ls_scan_number("-.e1", 4), 0);
    CHECK_EQ(ls_scan_number("12abc", 5), 2);
    CHECK_EQ(ls_scan_number("info", 4), 3);
    CHECK_EQ(ls_scan_number(NULL, 0), 0);
    /* the span ends where len says, not at a NUL */
    {
        double d = 0;
        CHECK_STATUS(ls_parse_double("12345", 2, &d), LS_OK);
        CHECK(d == 12);
        CHECK_STATUS(ls_parse_double(NULL, 0, &d), LS_ERR_PARSE);
        CHECK_STATUS(ls_parse_double(NULL, 1, &d), LS_ERR_INVALID);
        CHECK_STATUS(ls_parse_double("1", 1, NULL), LS_ERR_INVALID);
    }
}

static void format_layout_and_small_buffers(void)
{
    char b[LS_NUMBER_CHARS];
    CHECK(ls_format_double(0.1, b, sizeof b) == 19 && strcmp(b, "0.10000000000000001") == 0);
    CHECK(ls_format_double(1.0, b, sizeof b) == 1 && strcmp(b, "1") == 0);
    CHECK(ls_format_double(-0.0, b, sizeof b) == 2 && strcmp(b, "-0") == 0);
    CHECK(ls_format_double(1e100, b, sizeof b) > 0 && strcmp(b, "1e+100") == 0);
    CHECK(ls_format_double(HUGE_VAL, b, sizeof b) == 3 && strcmp(b, "inf") == 0);
    CHECK(ls_format_double(-HUGE_VAL, b, sizeof b) == 4 && strcmp(b, "-inf") == 0);
    CHECK(ls_format_double(4.9406564584124654e-324, b, sizeof b) > 0 && strcmp(b, "4.9406564584124654e-324") == 0);
    CHECK(ls_format_double(-1.7976931348623157e308, b, sizeof b) > 0 && strcmp(b, "-1.7976931348623157e+308") == 0);
    CHECK(ls_format_float(0.1f, b, sizeof b) > 0 && strcmp(b, "0.100000001") == 0);
    CHECK(ls_format_float(1e-5f, b, sizeof b) > 0 && strcmp(b, "9.99999975e-06") == 0);
    CHECK(ls_format_float(123456792.0f, b, sizeof b) > 0 && strcmp(b, "123456792") == 0);
    CHECK(ls_format_float(1e10f, b, sizeof b) > 0 && strcmp(b, "1e+10") == 0);
    /* too small: 0 and an empty string */
    CHECK_EQ(ls_format_double(0.1, b, 19), 0);
    CHECK_EQ(b[0], 0);
    CHECK_EQ(ls_format_double(0.1, b, 20), 19);
    CHECK_EQ(ls_format_double(0.1, NULL, 0), 0);
    /* the longest outputs fit LS_NUMBER_CHARS */
    CHECK(ls_format_double(-1.2345678901234567e-300, b, sizeof b) > 0 && strlen(b) < LS_NUMBER_CHARS);
    CHECK(ls_format_double(-0.00012345678901234567, b, sizeof b) == 23);
}

/* Offline: every float. */
static int all_floats(uint64_t first, uint64_t last, int with_glibc)
{
    char ours[LS_NUMBER_CHARS], ref[64];
    uint64_t b, bad = 0;
    clock_t t0 = clock();
    for (b = first; b <= last; b++) {
        int r = float_roundtrip_one((uint32_t)b, ours, ref, with_glibc);
        if (r != 0) {
            if (bad < 20) printf("FAIL float 0x%08x: ours '%s' ref '%s' (code %d)\n", (unsigned)b, ours, ref, r);
            bad++;
        }
        if ((b & 0x00ffffffu) == 0x00ffffffu) {
            printf("  .. 0x%08x, %llu bad, %.0f s\n", (unsigned)b, (unsigned long long)bad, (double)(clock() - t0) / CLOCKS_PER_SEC);
            fflush(stdout);
        }
    }
    printf("all floats 0x%08llx..0x%08llx: %llu mismatches, %.1f s cpu\n", (unsigned long long)first, (unsigned long long)last,
           (unsigned long long)bad, (double)(clock() - t0) / CLOCKS_PER_SEC);
    return bad != 0;
}

int main(int argc, char **argv)
{
    TEST_INIT("test_number");
    if (argc > 1 && strcmp(argv[1], "--all-floats") == 0) {
        uint64_t first = argc > 2 ? strtoull(argv[2], NULL, 0) : 0, last = argc > 3 ? strtoull(argv[3], NULL, 0) : 0xffffffffull;
        return all_floats(first, last, argc > 4);
    }
    TEST_RUN(syntax_accepted_and_rejected);
    TEST_RUN(format_layout_and_small_buffers);
    TEST_RUN(boundaries_and_overflow);
    TEST_RUN(float_random_bits_roundtrip);
    TEST_RUN(double_random_bits_roundtrip);
    TEST_RUN(random_decimal_strings_match_glibc);
    TEST_RUN(halfway_cases_round_correctly);
    return TEST_END();
}
