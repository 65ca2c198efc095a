/* sort.c - stable bottom-up merge sort of an index array by key. */
#include <largesteps/sort.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <string.h>

/* Runs of this many elements are first sorted by insertion (stable). */
#define RUN 16u

ls_status ls_sort_scratch_bytes(size_t n, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, n, sizeof(uint32_t));
    return ls_size_get(&s, bytes);
}

/* The two sorts differ only in the key type; the macro writes each once. */
#define LS_DEFINE_SORT(NAME, KEY)                                                         \
    ls_status NAME(const KEY *keys, uint32_t *idx, size_t n, uint32_t *scratch)           \
    {                                                                                     \
        size_t i, width;                                                                  \
        uint32_t *src = idx, *dst = scratch;                                              \
        if (n == 0) return LS_OK;                                                         \
        if (keys == NULL || idx == NULL || scratch == NULL) return LS_ERR_INVALID;        \
        for (i = 0; i < n; i += RUN) {                                                    \
            size_t end = n - i < RUN ? n : i + RUN, j;                                    \
            for (j = i + 1; j < end; j++) {                                               \
                uint32_t v = idx[j];                                                      \
                KEY k = keys[v];                                                          \
                size_t p = j;                                                             \
                while (p > i && keys[idx[p - 1]] > k) {                                   \
                    idx[p] = idx[p - 1];                                                  \
                    p--;                                                                  \
                }                                                                         \
                idx[p] = v;                                                               \
            }                                                                             \
        }                                                                                 \
        for (width = RUN; width < n; width = width > n / 2 ? n : width * 2) {             \
            uint32_t *t;                                                                  \
            for (i = 0; i < n; i += 2 * width) {                                          \
                size_t mid = n - i < width ? n : i + width;                               \
                size_t end = n - mid < width ? n : mid + width;                           \
                size_t a = i, b = mid, o = i;                                             \
                while (a < mid && b < end) {                                              \
                    if (keys[src[b]] < keys[src[a]]) dst[o++] = src[b++];                 \
                    else dst[o++] = src[a++];                                             \
                }                                                                         \
                while (a < mid) dst[o++] = src[a++];                                      \
                while (b < end) dst[o++] = src[b++];                                      \
            }                                                                             \
            t = src;                                                                      \
            src = dst;                                                                    \
            dst = t;                                                                      \
        }                                                                                 \
        if (src != idx) memcpy(idx, src, n * sizeof(uint32_t));                           \
        return LS_OK;                                                                     \
    }

LS_DEFINE_SORT(ls_sort_u32, uint32_t)
LS_DEFINE_SORT(ls_sort_u64, uint64_t)
