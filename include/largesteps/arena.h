/* largesteps/arena.h - the only source of memory in the library.
 *
 * An ls_arena is a double-ended bump allocator over one caller buffer:
 * objects that outlive a call are taken from the bottom, scratch for the
 * duration of one call from the top, and a mark/restore pair rolls both ends
 * back. Nothing is ever freed individually and nothing else allocates.
 *
 * Sizes never depend on where the buffer lies: the buffer must be aligned to
 * LS_ARENA_ALIGN (else LS_ERR_ALIGN) and every request is rounded up to a
 * multiple of LS_ARENA_ALIGN. So the byte count of a job is a property of the
 * job alone, and the library's sizing queries can state it up front:
 *
 *   - exact queries, named ls_X_bytes(): the bytes are a function of the input
 *     (a parsed mesh, a factor after symbolic analysis, an image). Building
 *     the object in an arena of exactly that many bytes succeeds; one byte less
 *     (after alignment) fails with LS_ERR_NOMEM.
 *   - bound queries, named ls_X_bytes_bound(): a documented worst case (raster
 *     bins, remeshing); the object reports the bytes it really used.
 *
 * Queries are computed by the library on the machine that runs it (pointer and
 * size_t widths differ between targets), with checked arithmetic: a size that
 * overflows size_t gives LS_ERR_TOO_LARGE (size_t is 32 bits on armhf, i686 and
 * Cortex-M). When a call fails, the arena is left as it was before the call.
 */
#ifndef LARGESTEPS_ARENA_H
#define LARGESTEPS_ARENA_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Alignment of the buffer and of every allocation, in bytes: enough for
 * double, uint64_t and pointers on every supported target. */
#define LS_ARENA_ALIGN 8u

/* n rounded up to a multiple of LS_ARENA_ALIGN (n must be at most
 * SIZE_MAX - 7; use ls_size_add for untrusted sizes). */
#define LS_ARENA_ROUND(n) (((size_t)(n) + (LS_ARENA_ALIGN - 1u)) & ~(size_t)(LS_ARENA_ALIGN - 1u))

#if defined(__GNUC__) || defined(__clang__)
#define LS_ARENA_ALIGNED_ __attribute__((aligned(8)))
#else
#define LS_ARENA_ALIGNED_
#endif

/* Declares `name`, a suitably aligned buffer of at least n bytes, e.g.
 *     static LS_ARENA_BUFFER(work, 64 * 1024);
 *     ls_arena_init(&arena, work.bytes, sizeof work.bytes);              */
#define LS_ARENA_BUFFER(name, n)                       \
    union {                                            \
        uint64_t align_u64_;                           \
        double align_double_;                          \
        void *align_pointer_;                          \
        unsigned char bytes[LS_ARENA_ROUND(n)];        \
    } LS_ARENA_ALIGNED_ name

typedef struct ls_arena {
    unsigned char *base; /* the caller's buffer */
    size_t capacity;     /* usable bytes: the buffer size rounded down to LS_ARENA_ALIGN */
    size_t bottom;       /* bytes in use from the bottom (objects) */
    size_t top;          /* bytes in use from the top (scratch) */
    size_t peak;         /* high-water mark of bottom + top since init or reset_peak */
    size_t need;         /* after a failed request: the capacity at which it would have
                            fit (bottom + top + request), else 0 */
} ls_arena;

/* Both ends of an arena at one moment; restore returns to it. */
typedef struct ls_arena_mark {
    size_t bottom;
    size_t top;
} ls_arena_mark;

/* The ABI guard of core.h: the linked symbol is ls_arena_init_f64 or _f32. */
#define LS_CAT_(a, b) a##b
#define LS_CAT(a, b) LS_CAT_(a, b)
#define ls_arena_init LS_CAT(ls_arena_init_, LS_ABI_SUFFIX)

/* ls_arena_init: makes *arena use `buffer` (bytes long; bytes may be 0).
 * Errors: LS_ERR_INVALID for a NULL arena or buffer, LS_ERR_ALIGN when buffer
 * is not a multiple of LS_ARENA_ALIGN (declare it with LS_ARENA_BUFFER). O(1);
 * the buffer is not touched. */
ls_status ls_arena_init(ls_arena *arena, void *buffer, size_t bytes);

/* ls_arena_alloc: count * elem_bytes bytes from the bottom, rounded up to
 * LS_ARENA_ALIGN, aligned, not cleared. Returns NULL when they do not fit or
 * the product overflows (then arena->need says how large the arena would have
 * to be); callers turn that into LS_ERR_NOMEM. A zero-byte request returns a
 * valid non-NULL pointer that must not be dereferenced. O(1). */
void *ls_arena_alloc(ls_arena *arena, size_t count, size_t elem_bytes);

/* ls_arena_alloc_zero: ls_arena_alloc, then the bytes are set to zero. O(bytes). */
void *ls_arena_alloc_zero(ls_arena *arena, size_t count, size_t elem_bytes);

/* ls_arena_scratch: like ls_arena_alloc, from the top end: memory for the
 * duration of one call, released by ls_arena_restore to a mark taken before. */
void *ls_arena_scratch(ls_arena *arena, size_t count, size_t elem_bytes);

/* ls_arena_save: the current ends of the arena. O(1). */
ls_arena_mark ls_arena_save(const ls_arena *arena);

/* ls_arena_restore: rolls both ends back to `mark` (taken from this arena and
 * not older than a later restore). Memory allocated since is released; the
 * peak is kept. O(1). */
void ls_arena_restore(ls_arena *arena, ls_arena_mark mark);

/* ls_arena_used: bytes in use at both ends. O(1). */
size_t ls_arena_used(const ls_arena *arena);

/* ls_arena_available: bytes still free between the two ends. O(1). */
size_t ls_arena_available(const ls_arena *arena);

/* ls_arena_reset_peak: sets the high-water mark to the current use, so that
 * the peak of the next call can be measured. O(1). */
void ls_arena_reset_peak(ls_arena *arena);

/* --- sizing -----------------------------------------------------------
 * An ls_size adds up allocations exactly as ls_arena_alloc rounds them, with a
 * sticky overflow flag, so a sizing query mirrors the allocation sequence of
 * the call it sizes. */
typedef struct ls_size {
    size_t bytes;      /* total so far */
    uint32_t overflow; /* 1 once any addition overflowed size_t */
} ls_size;

/* ls_size_init: starts an empty total. O(1). */
void ls_size_init(ls_size *size);

/* ls_size_add: adds one allocation of count * elem_bytes bytes (rounded as
 * the arena rounds it). O(1). */
void ls_size_add(ls_size *size, size_t count, size_t elem_bytes);

/* ls_size_add_size: adds another total (e.g. a sub-object's query). O(1). */
void ls_size_add_size(ls_size *size, const ls_size *other);

/* ls_size_max: keeps the larger of two totals (for phases whose scratch is
 * released between them). O(1). */
void ls_size_max(ls_size *size, const ls_size *other);

/* ls_size_get: the total in *bytes, or LS_ERR_TOO_LARGE if it overflowed
 * (then *bytes is set to 0). LS_ERR_INVALID for NULL pointers. O(1). */
ls_status ls_size_get(const ls_size *size, size_t *bytes);

/* ls_size_mul: *out = a * b, or LS_ERR_TOO_LARGE on overflow. O(1). */
ls_status ls_size_mul(size_t a, size_t b, size_t *out);

/* ls_size_sum: *out = a + b, or LS_ERR_TOO_LARGE on overflow. O(1). */
ls_status ls_size_sum(size_t a, size_t b, size_t *out);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_ARENA_H */
