/* core.c - version, build configuration and the floating-point self-test. */
#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/math.h>
#include <string.h>

uint32_t ls_version(void)
{
    return (uint32_t)LS_VERSION_NUMBER;
}

const char *ls_version_string(void)
{
    return LS_VERSION_STRING;
}

static uint32_t is_big_endian(void)
{
    const uint32_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 0 ? 1u : 0u;
}

void ls_build_info_get(ls_build_info *out)
{
    if (out == NULL) return;
    out->version = ls_version();
    out->real_bytes = (uint32_t)sizeof(ls_real);
    out->arena_align = LS_ARENA_ALIGN;
    out->pointer_bytes = (uint32_t)sizeof(void *);
    out->size_bytes = (uint32_t)sizeof(size_t);
    out->big_endian = is_big_endian();
#ifdef LS_NO_STATUS_STRINGS
    out->status_strings = 0;
#else
    out->status_strings = 1;
#endif
    out->real_name = LS_REAL_NAME;
#if defined(__clang__)
    out->compiler = "clang " __clang_version__;
#elif defined(__GNUC__)
    out->compiler = "gcc " __VERSION__;
#else
    out->compiler = "unknown C99 compiler";
#endif
}

/* Each check runs in ls_real arithmetic on volatile operands so that the
 * compiler cannot fold it and the float build uses float operations only. */
static int rounds_to_nearest_even(void)
{
    volatile ls_real one = (ls_real)1;
    volatile ls_real half_ulp = (ls_real)(LS_REAL_EPSILON / 2); /* exactly half an ulp of 1 */
    volatile ls_real three_quarter = (ls_real)(LS_REAL_EPSILON * 3 / 4);
    ls_real up = one + half_ulp;           /* tie: even is 1 (round-up mode gives 1 + eps) */
    ls_real down = -one - half_ulp;        /* tie: even is -1 (round-down mode gives -1 - eps) */
    ls_real above = one + three_quarter;   /* above the tie: 1 + eps (toward-zero gives 1) */
    return up == one && down == -one && above == one + (ls_real)LS_REAL_EPSILON;
}

static int keeps_subnormals(void)
{
#if LS_REAL_IS_FLOAT
    volatile ls_real smallest_normal = FLT_MIN;
#else
    volatile ls_real smallest_normal = DBL_MIN;
#endif
    volatile ls_real half = (ls_real)0.5;
    ls_real sub = smallest_normal * half;  /* FZ flushes this product to 0 */
    volatile ls_real vsub = sub;
    ls_real twice = vsub + vsub;           /* DAZ reads the operand as 0 */
    return sub != 0 && twice == smallest_normal;
}

static int no_excess_precision(void)
{
    volatile ls_real one = (ls_real)1;
    volatile ls_real tiny = (ls_real)(LS_REAL_EPSILON / 4);
    /* With excess precision the sum keeps tiny and the difference is non-zero. */
    return (one + tiny) - one == 0;
}

/* A few outputs of the deterministic functions with their exact bit patterns
 * (the same on every target; tests/test_math.c holds the full table). A
 * mismatch means the compiler broke IEEE semantics (fast-math, contraction,
 * excess precision) or the environment changed the arithmetic. */
static int math_matches_known_bits(void)
{
#if LS_REAL_IS_FLOAT
    static const uint32_t expect[5] = {0x3f576aa4u, 0x402df854u, 0x40135d8eu, 0x402b6374u, 0x3fb504f3u};
    volatile float one = 1.0f, ten = 10.0f, two = 2.0f, half = 0.5f;
    float got[5];
    uint32_t bits;
#else
    static const uint64_t expect[5] = {0x3feaed548f090ceeull, 0x4005bf0a8b145769ull, 0x40026bb1bbb55516ull,
                                       0x40056c6e7397f5aeull, 0x3ff6a09e667f3bcdull};
    volatile double one = 1.0, ten = 10.0, two = 2.0, half = 0.5;
    double got[5];
    uint64_t bits;
#endif
    int i;
    got[0] = LS_RSIN(one);
    got[1] = LS_REXP(one);
    got[2] = LS_RLOG(ten);
    got[3] = LS_RATAN2(one, -two);
    got[4] = LS_RPOW(two, half);
    for (i = 0; i < 5; i++) {
        memcpy(&bits, &got[i], sizeof bits);
        if (bits != expect[i]) return 0;
    }
    return 1;
}

ls_status ls_selftest(size_t caller_real_bytes)
{
    if (caller_real_bytes != sizeof(ls_real)) return LS_ERR_ABI;
    if (!rounds_to_nearest_even() || !keeps_subnormals() || !no_excess_precision() ||
        !math_matches_known_bits())
        return LS_ERR_FPENV;
    return LS_OK;
}
