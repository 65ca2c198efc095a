/* largesteps/sort.h - the library's own stable sort (no qsort).
 *
 * C libraries implement qsort differently (and unstably), so the order of
 * equal keys, and everything built on it, would differ between glibc, musl
 * and newlib. These sorts are bottom-up merge sorts: stable, O(n log n)
 * comparisons in the worst case, no recursion, and the same order on every
 * platform. They reorder an index array by the keys it points to, so one key
 * array can serve several sorts (sort by the minor key first, then stably by
 * the major key, for a lexicographic order).
 */
#ifndef LARGESTEPS_SORT_H
#define LARGESTEPS_SORT_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ls_sort_scratch_bytes: the scratch a sort of n indices needs: n uint32_t
 * (rounded as the arena rounds). LS_ERR_TOO_LARGE on size_t overflow,
 * LS_ERR_INVALID for a NULL bytes. O(1). */
ls_status ls_sort_scratch_bytes(size_t n, size_t *bytes);

/* ls_sort_u32: stably reorders idx[0..n) so that keys[idx[i]] is
 * non-decreasing (equal keys keep their order in idx). scratch has room for
 * n uint32_t (caller-owned, e.g. from ls_arena_scratch; contents are
 * destroyed). O(n log n) time; no other memory. Errors: LS_ERR_INVALID for
 * NULL arrays when n > 0. */
ls_status ls_sort_u32(const uint32_t *keys, uint32_t *idx, size_t n, uint32_t *scratch);

/* ls_sort_u64: as ls_sort_u32 with 64-bit keys. */
ls_status ls_sort_u64(const uint64_t *keys, uint32_t *idx, size_t n, uint32_t *scratch);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_SORT_H */
