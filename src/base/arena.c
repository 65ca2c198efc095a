/* arena.c - double-ended bump allocator over a caller buffer, and checked sizes. */
#include <largesteps/arena.h>
#include <largesteps/status.h>
#include <string.h>

#define ALIGN_MASK ((size_t)LS_ARENA_ALIGN - 1u)

/* count * elem_bytes rounded up to the alignment; 0 on overflow (callers
 * treat a 0 result for a non-zero request as "cannot fit"). */
static int request_bytes(size_t count, size_t elem_bytes, size_t *out)
{
    size_t bytes;
    if (elem_bytes != 0 && count > SIZE_MAX / elem_bytes) return 0;
    bytes = count * elem_bytes;
    if (bytes > SIZE_MAX - ALIGN_MASK) return 0;
    *out = (bytes + ALIGN_MASK) & ~ALIGN_MASK;
    return 1;
}

/* Records the capacity the failed request would have needed (saturating). */
static void *fail(ls_arena *arena, size_t bytes)
{
    size_t used = arena->bottom + arena->top;
    arena->need = bytes > SIZE_MAX - used ? SIZE_MAX : used + bytes;
    return NULL;
}

static void note_peak(ls_arena *arena)
{
    size_t used = arena->bottom + arena->top;
    if (used > arena->peak) arena->peak = used;
}

ls_status ls_arena_init(ls_arena *arena, void *buffer, size_t bytes)
{
    if (arena == NULL || buffer == NULL) return LS_ERR_INVALID;
    if (((uintptr_t)buffer & (uintptr_t)ALIGN_MASK) != 0) return LS_ERR_ALIGN;
    arena->base = (unsigned char *)buffer;
    arena->capacity = bytes & ~ALIGN_MASK;
    arena->bottom = 0;
    arena->top = 0;
    arena->peak = 0;
    arena->need = 0;
    return LS_OK;
}

void *ls_arena_alloc(ls_arena *arena, size_t count, size_t elem_bytes)
{
    size_t bytes = 0;
    void *p;
    if (arena == NULL) return NULL;
    if (!request_bytes(count, elem_bytes, &bytes)) return fail(arena, SIZE_MAX);
    if (bytes > arena->capacity - arena->bottom - arena->top) return fail(arena, bytes);
    p = arena->base + arena->bottom;
    arena->bottom += bytes;
    note_peak(arena);
    return p;
}

void *ls_arena_alloc_zero(ls_arena *arena, size_t count, size_t elem_bytes)
{
    void *p = ls_arena_alloc(arena, count, elem_bytes);
    if (p != NULL && count != 0 && elem_bytes != 0) memset(p, 0, count * elem_bytes);
    return p;
}

void *ls_arena_scratch(ls_arena *arena, size_t count, size_t elem_bytes)
{
    size_t bytes = 0;
    if (arena == NULL) return NULL;
    if (!request_bytes(count, elem_bytes, &bytes)) return fail(arena, SIZE_MAX);
    if (bytes > arena->capacity - arena->bottom - arena->top) return fail(arena, bytes);
    arena->top += bytes;
    note_peak(arena);
    return arena->base + (arena->capacity - arena->top);
}

ls_arena_mark ls_arena_save(const ls_arena *arena)
{
    ls_arena_mark mark;
    mark.bottom = arena != NULL ? arena->bottom : 0;
    mark.top = arena != NULL ? arena->top : 0;
    return mark;
}

void ls_arena_restore(ls_arena *arena, ls_arena_mark mark)
{
    if (arena == NULL) return;
    /* A mark can only move the ends back; a stale mark from a later state is ignored
     * per end rather than growing the arena's use. */
    if (mark.bottom <= arena->bottom) arena->bottom = mark.bottom;
    if (mark.top <= arena->top) arena->top = mark.top;
}

size_t ls_arena_used(const ls_arena *arena)
{
    return arena != NULL ? arena->bottom + arena->top : 0;
}

size_t ls_arena_available(const ls_arena *arena)
{
    return arena != NULL ? arena->capacity - arena->bottom - arena->top : 0;
}

void ls_arena_reset_peak(ls_arena *arena)
{
    if (arena == NULL) return;
    arena->peak = arena->bottom + arena->top;
    arena->need = 0;
}

void ls_size_init(ls_size *size)
{
    if (size == NULL) return;
    size->bytes = 0;
    size->overflow = 0;
}

static void size_add_bytes(ls_size *size, size_t bytes)
{
    if (bytes > SIZE_MAX - size->bytes) {
        size->overflow = 1;
        size->bytes = SIZE_MAX;
    } else {
        size->bytes += bytes;
    }
}

void ls_size_add(ls_size *size, size_t count, size_t elem_bytes)
{
    size_t bytes = 0;
    if (size == NULL) return;
    if (!request_bytes(count, elem_bytes, &bytes)) {
        size->overflow = 1;
        size->bytes = SIZE_MAX;
        return;
    }
    size_add_bytes(size, bytes);
}

void ls_size_add_size(ls_size *size, const ls_size *other)
{
    if (size == NULL || other == NULL) return;
    if (other->overflow) size->overflow = 1;
    size_add_bytes(size, other->bytes);
}

void ls_size_max(ls_size *size, const ls_size *other)
{
    if (size == NULL || other == NULL) return;
    if (other->overflow) size->overflow = 1;
    if (other->bytes > size->bytes) size->bytes = other->bytes;
}

ls_status ls_size_get(const ls_size *size, size_t *bytes)
{
    if (size == NULL || bytes == NULL) return LS_ERR_INVALID;
    if (size->overflow) {
        *bytes = 0;
        return LS_ERR_TOO_LARGE;
    }
    *bytes = size->bytes;
    return LS_OK;
}

ls_status ls_size_mul(size_t a, size_t b, size_t *out)
{
    if (out == NULL) return LS_ERR_INVALID;
    if (b != 0 && a > SIZE_MAX / b) {
        *out = 0;
        return LS_ERR_TOO_LARGE;
    }
    *out = a * b;
    return LS_OK;
}

ls_status ls_size_sum(size_t a, size_t b, size_t *out)
{
    if (out == NULL) return LS_ERR_INVALID;
    if (a > SIZE_MAX - b) {
        *out = 0;
        return LS_ERR_TOO_LARGE;
    }
    *out = a + b;
    return LS_OK;
}
