/* tests/test.h - the test harness shared by every test program.
 *
 * A test program is a main() that calls TEST_RUN(fn) for each test function
 * and returns TEST_END(). Inside a test, CHECK* macros record failures without
 * stopping the test (so one run shows every broken assertion); REQUIRE* stops
 * the current test. Output, one line per test, then the summary line:
 *     ok   arena_alloc_rounds
 *     FAIL arena_restore  tests/test_arena.c:88: used == 0 (got 16)
 *     test_arena: 12 passed, 1 failed
 * The Makefile reads that last line. Test programs may use stdio and libm:
 * only src/ is held to the library's rules.
 */
#ifndef LS_TEST_H
#define LS_TEST_H

#include <stdio.h>
#include <string.h>
#include <stdint.h>
#include <math.h>
#include <largesteps.h>

typedef struct test_state {
    const char *program;
    const char *current;
    int failures_in_test; /* CHECK failures in the running test */
    int passed;
    int failed;
    int checks;
} test_state;

/* One instance per test program (tests are single-file programs). */
static test_state test_g;

#define TEST_INIT(name) ((void)test_hash, (void)test_hash_reals, test_g.program = (name))

#define TEST_FAILMSG_(...)                                                         \
    do {                                                                           \
        if (test_g.failures_in_test == 0) printf("FAIL %s\n", test_g.current);     \
        test_g.failures_in_test++;                                                 \
        printf("     %s:%d: ", __FILE__, __LINE__);                                \
        printf(__VA_ARGS__);                                                       \
        printf("\n");                                                              \
    } while (0)

#define CHECK(cond)                                                                \
    do {                                                                           \
        test_g.checks++;                                                           \
        if (!(cond)) TEST_FAILMSG_("%s", #cond);                                  \
    } while (0)

#define CHECK_MSG(cond, ...)                                                       \
    do {                                                                           \
        test_g.checks++;                                                           \
        if (!(cond)) TEST_FAILMSG_(__VA_ARGS__);                                   \
    } while (0)

/* Integer equality, printing both values. */
#define CHECK_EQ(a, b)                                                             \
    do {                                                                           \
        long long a_ = (long long)(a), b_ = (long long)(b);                        \
        test_g.checks++;                                                           \
        if (a_ != b_) TEST_FAILMSG_("%s == %s (%lld vs %lld)", #a, #b, a_, b_);   \
    } while (0)

#define CHECK_STATUS(expr, want)                                                   \
    do {                                                                           \
        ls_status s_ = (expr);                                                     \
        test_g.checks++;                                                           \
        if (s_ != (want))                                                          \
            TEST_FAILMSG_("%s returned %s, wanted %s", #expr, ls_status_name(s_), \
                          ls_status_name(want));                                   \
    } while (0)

/* |a - b| <= tol, compared in double; NaN never passes. */
#define CHECK_NEAR(a, b, tol)                                                      \
    do {                                                                           \
        double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);             \
        test_g.checks++;                                                           \
        if (!(fabs(a_ - b_) <= t_))                                                \
            TEST_FAILMSG_("%s ~ %s (%.17g vs %.17g, tol %.3g)", #a, #b, a_, b_, t_); \
    } while (0)

/* Stop the current test when a precondition fails. */
#define REQUIRE(cond)                                                              \
    do {                                                                           \
        test_g.checks++;                                                           \
        if (!(cond)) {                                                             \
            TEST_FAILMSG_("required: %s", #cond);                                  \
            return;                                                                \
        }                                                                          \
    } while (0)

#define TEST_RUN(fn)                                                               \
    do {                                                                           \
        test_g.current = #fn;                                                      \
        test_g.failures_in_test = 0;                                               \
        fn();                                                                      \
        if (test_g.failures_in_test == 0) {                                        \
            test_g.passed++;                                                       \
            printf("ok   %s\n", #fn);                                              \
        } else {                                                                   \
            test_g.failed++;                                                       \
        }                                                                          \
        fflush(stdout);                                                            \
    } while (0)

#define TEST_END()                                                                 \
    (printf("%s: %d passed, %d failed\n", test_g.program, test_g.passed,          \
            test_g.failed),                                                        \
     test_g.failed == 0 && test_g.passed > 0 ? 0 : 1)

/* Tolerance scaled to the build's precision: k units of LS_REAL_EPSILON. */
#define TEST_EPS(k) ((double)(k) * (double)LS_REAL_EPSILON)

/* The tests' one random generator: xorshift64 (Marsaglia's shifts 13, 7,
 * 17) on a state the caller owns, one per program or per case. The same
 * sequence on every target. A state must not be 0: test_rng_seed makes a
 * well-mixed one from any seed (small seeds such as 1, 2, 3 give
 * xorshift64 a slow start). (tests/digest.c keeps its own generator: the
 * committed digests pin its sequence.) */
static inline uint64_t test_rng_next(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

/* 53 random bits. */
static inline uint64_t test_rng_bits(uint64_t *s) { return test_rng_next(s) >> 11; }

/* Uniform in [0, 1). */
static inline double test_rng_unit(uint64_t *s) { return (double)test_rng_bits(s) * (1.0 / 9007199254740992.0); }

/* Uniform in [lo, hi). */
static inline double test_rng_range(uint64_t *s, double lo, double hi) { return lo + (hi - lo) * test_rng_unit(s); }

/* A state from any seed (splitmix64's finalizer; never 0). */
static inline uint64_t test_rng_seed(uint64_t seed)
{
    uint64_t z = seed + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return z != 0 ? z : 0x9E3779B97F4A7C15ull;
}

/* FNV-1a over raw bytes: for "inputs unchanged" checks and digests. */
static uint64_t test_hash(const void *data, size_t bytes, uint64_t h)
{
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    for (i = 0; i < bytes; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}
#define TEST_HASH_SEED 14695981039346656037ull

/* FNV-1a over ls_real values, each as its IEEE bits in little-endian byte
 * order: the same digest on big-endian targets (s390x) as on little-endian
 * ones, and equal to test_hash over the raw memory on little-endian hosts. */
static uint64_t test_hash_reals(const ls_real *v, size_t n, uint64_t h)
{
    size_t i, b;
    for (i = 0; i < n; i++) {
        unsigned char le[sizeof(ls_real)];
#if LS_REAL_IS_FLOAT
        uint32_t bits;
#else
        uint64_t bits;
#endif
        memcpy(&bits, &v[i], sizeof bits);
        for (b = 0; b < sizeof bits; b++) le[b] = (unsigned char)(bits >> (8 * b));
        h = test_hash(le, sizeof le, h);
    }
    return h;
}

#endif /* LS_TEST_H */
