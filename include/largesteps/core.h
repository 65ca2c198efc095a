/* largesteps/core.h - the build's number type, version, ABI guard and self-test.
 *
 * Every other header includes this one. It pulls in <largesteps/config.h>, which
 * `make` generates per build variant (and `make install` installs): it records
 * whether the library was built with `ls_real` = double (default) or float
 * (`make REAL=float`).
 *
 * ABI guard: the header renames ls_arena_init() to ls_arena_init_f64 or
 * ls_arena_init_f32 according to config.h. Every program that uses the library
 * must create an arena, so a program compiled with double headers fails to link
 * against a float library (and the other way round) instead of silently passing
 * floats where doubles are expected.
 */
#ifndef LARGESTEPS_CORE_H
#define LARGESTEPS_CORE_H

#include <stddef.h>
#include <stdint.h>
#include <float.h>
#include <largesteps/config.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_VERSION_MAJOR 0
#define LS_VERSION_MINOR 1
#define LS_VERSION_PATCH 0
#define LS_VERSION_STRING "0.1.0"
/* One integer that orders versions: 0x00MMmmpp. */
#define LS_VERSION_NUMBER \
    ((LS_VERSION_MAJOR << 16) | (LS_VERSION_MINOR << 8) | LS_VERSION_PATCH)

#if LS_REAL_IS_FLOAT
typedef float ls_real;
#define LS_REAL_NAME "float"
#define LS_REAL_EPSILON FLT_EPSILON
#define LS_REAL_MAX FLT_MAX
#define LS_ABI_SUFFIX f32
#else
typedef double ls_real;
#define LS_REAL_NAME "double"
#define LS_REAL_EPSILON DBL_EPSILON
#define LS_REAL_MAX DBL_MAX
#define LS_ABI_SUFFIX f64
#endif

/* Results must not depend on excess precision (x87, s390x's default C99 mode):
 * build i686 with -msse2 -mfpmath=sse and s390x with -fexcess-precision=fast. */
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0
#error "largesteps needs FLT_EVAL_METHOD == 0 (i686: -msse2 -mfpmath=sse; s390x: -fexcess-precision=fast)"
#endif

/* No fast-math: it lets the compiler reassociate and contract, and the bits
 * would depend on the build. (-ffp-contract=fast has no macro to test: the
 * Makefile refuses it.) */
#if defined(__FAST_MATH__)
#error "largesteps must not be built with -ffast-math or -Ofast: results would depend on the build"
#endif

/* LS_NOINLINE keeps the frames of big helpers apart (the per-function stack
 * limit and the call chains' budget hold on every target: s390x's frames are
 * largest). The library's, for its own use. */
#if defined(__GNUC__) || defined(__clang__)
#define LS_NOINLINE __attribute__((noinline))
#else
#define LS_NOINLINE
#endif

/* GCC's vectorizers turn lane pairs a*c - b*d, a*d + b*c (a complex product)
 * into fused vfmaddsub / vfmsubadd when the target has FMA (-march=haswell,
 * x86-64-v3, native), even under -ffp-contract=off. The functions with such
 * pairs carry LS_NO_VECTORIZE, which turns GCC's vectorizers off for them
 * alone (the library's, for its own use). */
#if defined(__GNUC__) && !defined(__clang__) && !defined(LS_TEST_VECTORIZE_ALL) /* the test's planted failure */
#define LS_NO_VECTORIZE __attribute__((optimize("no-tree-vectorize")))
#else
#define LS_NO_VECTORIZE
#endif

/* Status codes are plain int32_t so that they can live in structs whose layout
 * must not depend on the compiler's enum size (arm-none-eabi uses short enums). */
typedef int32_t ls_status;

/* ls_version: the library's version as LS_VERSION_NUMBER of the build that made
 * it (compare with the header's macro to detect a stale library). O(1). */
uint32_t ls_version(void);

/* ls_version_string: "MAJOR.MINOR.PATCH", a static string. O(1). */
const char *ls_version_string(void);

/* What the library was built with, for diagnostics and `largesteps info`. */
typedef struct ls_build_info {
    uint32_t version;         /* LS_VERSION_NUMBER */
    uint32_t real_bytes;      /* sizeof(ls_real): 4 or 8 */
    uint32_t arena_align;     /* LS_ARENA_ALIGN */
    uint32_t pointer_bytes;   /* sizeof(void *) */
    uint32_t size_bytes;      /* sizeof(size_t) */
    uint32_t big_endian;      /* 1 on s390x and other big-endian targets */
    uint32_t status_strings;  /* 0 when built with LS_NO_STATUS_STRINGS */
    const char *real_name;    /* "float" or "double" */
    const char *compiler;     /* e.g. "gcc 12.2.0" */
} ls_build_info;

/* ls_build_info_get: fills *out with the library's build configuration. O(1);
 * no memory; never fails (a NULL out is ignored). */
void ls_build_info_get(ls_build_info *out);

/* ls_selftest: checks the floating-point environment the library relies on and
 * returns LS_OK or a named error: LS_ERR_FPENV when the rounding mode is not
 * round-to-nearest-even, when subnormals are flushed to zero (FZ/DAZ, often set
 * by firmware start-up code) or when arithmetic carries excess precision;
 * LS_ERR_ABI when the caller's ls_real size differs from the library's
 * (pass sizeof(ls_real)). It also checks a few outputs of the deterministic
 * elementary functions against their bit patterns. O(1), a few hundred
 * operations; no memory. Call it once at start-up on a new platform. */
ls_status ls_selftest(size_t caller_real_bytes);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_CORE_H */
