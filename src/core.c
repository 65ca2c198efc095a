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

ls_status ls_selftest(size_t caller_real_bytes)
{
    if (caller_real_bytes != sizeof(ls_real)) return LS_ERR_ABI;
    if (!rounds_to_nearest_even() || !keeps_subnormals() || !no_excess_precision())
        return LS_ERR_FPENV;
    return LS_OK;
}
