/* tests/fuzz/fuzz_common.h - shared parts of the libFuzzer harnesses.
 *
 * Every harness decodes its input from memory through the library's public
 * API, in an arena whose size is chosen by the input's first byte (the
 * "selector"), so that both the success paths and the out-of-memory paths of
 * the decoders are fuzzed:
 *   selector < 128   the arena holds the sizing query's answer (the call must
 *                    not fail with LS_ERR_NOMEM, and for an exact query its
 *                    peak use is exactly the answer);
 *   selector >= 128  the arena holds (selector - 128) / 128 of the answer
 *                    (rounded down to LS_ARENA_ALIGN): the call must fail
 *                    (LS_ERR_NOMEM, or the input error the sizing query
 *                    already reported).
 * The arena has bytes in use at both ends before the call (so a restore to
 * zero instead of to the caller's mark would show), and the harness asserts:
 *   - the status is one of the codes of status.h;
 *   - on failure: the arena is back at its mark (both ends), the output
 *     object is byte-for-byte as before, and every error other than
 *     LS_ERR_NOMEM has a diag with that status and a non-empty `what`;
 *   - on success: the output is well-formed (the harness's own checks).
 * A failed invariant prints what failed and calls abort(), which libFuzzer
 * reports as a crash with the input saved.
 *
 * The sizing answers can be huge for hostile headers (a PNG may claim 2^28
 * pixels); arenas are capped at FUZZ_ARENA_CAP bytes, above which the call
 * must fail with LS_ERR_NOMEM.
 */
#ifndef LS_FUZZ_COMMON_H
#define LS_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <largesteps.h>

#define FUZZ_ARENA_CAP ((size_t)64 << 20)
#define FUZZ_PRE_BOTTOM 24u /* bytes in use at each end before the call */
#define FUZZ_PRE_TOP 40u

#define FUZZ_ASSERT(cond)                                                                   \
    do {                                                                                    \
        if (!(cond)) {                                                                      \
            fprintf(stderr, "fuzz invariant failed: %s (%s:%d)\n", #cond, __FILE__, __LINE__); \
            abort();                                                                        \
        }                                                                                   \
    } while (0)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct fuzz_arena {
    unsigned char *buf;
    ls_arena arena;
    ls_arena_mark mark;
    size_t size;  /* bytes available to the call */
    int enough;   /* 1 when size >= the sizing answer */
} fuzz_arena;

/* Sets up an arena for a call whose sizing query answered `need` (0 when the
 * query failed: then any arena will do and the call must fail). */
static inline void fuzz_arena_open(fuzz_arena *fa, uint8_t selector, size_t need)
{
    size_t size, total;
    if (need > FUZZ_ARENA_CAP) {
        size = FUZZ_ARENA_CAP / 2u;
        fa->enough = 0;
    } else if (selector < 128u) {
        size = need;
        fa->enough = 1;
    } else {
        size = (size_t)(((uint64_t)need * (uint64_t)(selector - 128u)) / 128u);
        size &= ~(size_t)(LS_ARENA_ALIGN - 1u);
        fa->enough = size >= need;
    }
    size = LS_ARENA_ROUND(size);
    total = size + FUZZ_PRE_BOTTOM + FUZZ_PRE_TOP;
    fa->buf = (unsigned char *)malloc(total);
    FUZZ_ASSERT(fa->buf != NULL);
    memset(fa->buf, 0xA5, total);
    FUZZ_ASSERT(ls_arena_init(&fa->arena, fa->buf, total) == LS_OK);
    FUZZ_ASSERT(ls_arena_alloc(&fa->arena, 1, FUZZ_PRE_BOTTOM) != NULL);
    FUZZ_ASSERT(ls_arena_scratch(&fa->arena, 1, FUZZ_PRE_TOP) != NULL);
    ls_arena_reset_peak(&fa->arena);
    fa->mark = ls_arena_save(&fa->arena);
    fa->size = size;
}

/* Bytes the call took at its peak (beyond what was in use before). */
static inline size_t fuzz_arena_peak(const fuzz_arena *fa)
{
    return fa->arena.peak - (FUZZ_PRE_BOTTOM + FUZZ_PRE_TOP);
}

static inline void fuzz_arena_close(fuzz_arena *fa)
{
    free(fa->buf);
    fa->buf = NULL;
}

/* The invariants every failing call must keep. */
static inline void fuzz_check_failure(ls_status st, const ls_diag *diag, const fuzz_arena *fa, const void *out,
                               const void *out_before, size_t out_bytes)
{
    FUZZ_ASSERT(st > LS_OK && st < LS_STATUS_COUNT);
    FUZZ_ASSERT(fa->arena.bottom == fa->mark.bottom && fa->arena.top == fa->mark.top);
    FUZZ_ASSERT(memcmp(out, out_before, out_bytes) == 0);
    if (st != LS_ERR_NOMEM) {
        FUZZ_ASSERT(diag->what != NULL && diag->what[0] != '\0');
        FUZZ_ASSERT(diag->status == st);
    }
}

/* The call's status against its sizing query's: the call fails with the
 * query's status when the query failed; in an arena of the answer it does not
 * run out of memory; in less it does not succeed (strict: it runs out). */
static inline void fuzz_check_status(ls_status query_st, ls_status st, const fuzz_arena *fa, int strict)
{
    FUZZ_ASSERT(st >= LS_OK && st < LS_STATUS_COUNT);
    if (query_st != LS_OK)
        FUZZ_ASSERT(st == query_st);
    else if (fa->enough)
        FUZZ_ASSERT(st != LS_ERR_NOMEM);
    else if (strict)
        FUZZ_ASSERT(st == LS_ERR_NOMEM);
    else
        FUZZ_ASSERT(st != LS_OK);
}

static inline int fuzz_finite(double x)
{
    return x - x == 0.0;
}

static inline int fuzz_finite_real(ls_real x)
{
    return fuzz_finite((double)x);
}

/* 1 when p points into [lo, hi) and a NUL lies before hi. */
static inline int fuzz_cstring_in(const char *p, const unsigned char *lo, const unsigned char *hi)
{
    const unsigned char *q = (const unsigned char *)p;
    if (q < lo || q >= hi) return 0;
    while (q < hi && *q != 0) q++;
    return q < hi;
}

#endif /* LS_FUZZ_COMMON_H */
