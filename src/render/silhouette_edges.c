/* silhouette_edges.c - the edge table: each half-edge's twin, built once per connectivity */
#include "silhouette_internal.h"

static ls_status face_error(ls_diag *diag, uint32_t t, const char *what)
{
    if (diag != NULL) {
        ls_diag_clear(diag);
        diag->status = LS_ERR_MESH;
        diag->has_index = 1;
        diag->index = t;
        diag->what = what;
    }
    return LS_ERR_MESH;
}

static void table_size(ls_size *obj, ls_size *scratch, uint32_t triangle_count)
{
    size_t n = 3 * (size_t)triangle_count;
    ls_size_init(obj);
    ls_size_init(scratch);
    if (n == 0) return;
    ls_size_add(obj, n, sizeof(uint32_t));
    ls_size_add(scratch, n, sizeof(uint64_t)); /* keys */
    ls_size_add(scratch, n, sizeof(uint32_t)); /* sorted order */
    ls_size_add(scratch, n, sizeof(uint32_t)); /* sort scratch */
}

ls_status ls_edge_table_bytes(uint32_t triangle_count, size_t *bytes)
{
    ls_size obj, scratch;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if ((uint64_t)triangle_count * 3u >= (uint64_t)LS_EDGE_NONE) return LS_ERR_TOO_LARGE;
    table_size(&obj, &scratch, triangle_count);
    ls_size_add_size(&obj, &scratch);
    return ls_size_get(&obj, bytes);
}

ls_status ls_edge_table_build(ls_edge_table *table, const uint32_t *indices, uint32_t triangle_count,
                              uint32_t vertex_count, ls_arena *arena, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    uint32_t *twin = NULL, t, n, boundary = 0;
    if (table == NULL) return ls_invalid_arg(diag, "table is NULL");
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (triangle_count > 0 && indices == NULL) return ls_invalid_arg(diag, "indices is NULL with triangle_count > 0");
    if ((uint64_t)triangle_count * 3u >= (uint64_t)LS_EDGE_NONE) return LS_ERR_TOO_LARGE;
    for (t = 0; t < triangle_count; t++) {
        const uint32_t *f = indices + 3 * (size_t)t;
        if (f[0] >= vertex_count || f[1] >= vertex_count || f[2] >= vertex_count)
            return face_error(diag, t, "triangle vertex index out of range");
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
            return face_error(diag, t, "triangle with a repeated vertex");
    }
    n = 3u * triangle_count;
    mark = ls_arena_save(arena);
    if (n > 0) {
        uint32_t *order, *sscr, i;
        uint64_t *keys;
        twin = (uint32_t *)ls_arena_alloc(arena, n, sizeof(uint32_t));
        keys = twin ? (uint64_t *)ls_arena_scratch(arena, n, sizeof(uint64_t)) : NULL;
        order = keys ? (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t)) : NULL;
        sscr = order ? (uint32_t *)ls_arena_scratch(arena, n, sizeof(uint32_t)) : NULL;
        if (sscr == NULL) {
            ls_arena_restore(arena, mark);
            return LS_ERR_NOMEM;
        }
        for (i = 0; i < n; i++) {
            uint32_t a = indices[i], b = indices[i - i % 3u + (i % 3u + 1u) % 3u];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            keys[i] = ((uint64_t)lo << 32) | hi;
            order[i] = i;
        }
        if (ls_sort_u64(keys, order, n, sscr) != LS_OK) { /* not reached: its arrays are allocated above */
            ls_arena_restore(arena, mark);
            return ls_invalid_arg(diag, "internal: the edge sort refused its arrays");
        }
        i = 0;
        while (i < n) {
            uint32_t j = i + 1u;
            while (j < n && keys[order[j]] == keys[order[i]]) j++;
            if (j - i == 2u) {
                twin[order[i]] = order[i + 1u];
                twin[order[i + 1u]] = order[i];
            } else {
                uint32_t k;
                for (k = i; k < j; k++) twin[order[k]] = LS_EDGE_NONE;
                boundary += j - i;
            }
            i = j;
        }
        /* release the scratch, keep the twins */
        {
            ls_arena_mark keep = mark;
            keep.bottom = arena->bottom;
            ls_arena_restore(arena, keep);
        }
    }
    table->triangle_count = triangle_count;
    table->vertex_count = vertex_count;
    table->twin = twin;
    table->boundary_edges = boundary;
    table->magic = EDGE_TABLE_MAGIC;
    return LS_OK;
}
