/* mask.c - distances in an image's mask (mask.h), and the distance
 * transform the fit's mask pull shares (mask_internal.h) */
#include <largesteps/mask.h>
#include <largesteps/math.h>
#include "mask_internal.h"
#include "../base/diag_internal.h"
#include <string.h>

/* The 1D squared distance transform of f[0..n) into d: d[q] = min over p of
 * (q - p)^2 + f[p] (f: 0 or LS_MASK_FAR). v: n indices, z: n + 1 reals. */
static void dt_line(const ls_real *f, uint32_t n, ls_real *d, uint32_t *v, ls_real *z)
{
    uint32_t q, k = 0;
    v[0] = 0;
    z[0] = -(ls_real)2 * LS_MASK_FAR; /* below every intersection: s >= -LS_MASK_FAR / 2 */
    z[1] = (ls_real)2 * LS_MASK_FAR;
    for (q = 1; q < n; q++) {
        const ls_real qq = (ls_real)q;
        ls_real s;
        for (;;) {
            const ls_real p = (ls_real)v[k];
            s = ((f[q] + qq * qq) - (f[v[k]] + p * p)) / ((ls_real)2 * (qq - p));
            if (s > z[k] || k == 0) break;
            k--;
        }
        k++;
        v[k] = q;
        z[k] = s;
        z[k + 1u] = (ls_real)2 * LS_MASK_FAR;
    }
    k = 0;
    for (q = 0; q < n; q++) {
        ls_real t;
        while (z[k + 1u] < (ls_real)q) k++;
        t = (ls_real)q - (ls_real)v[k];
        d[q] = t * t + f[v[k]];
    }
}

void ls_mask_impl_distance(const ls_real *rgba, uint32_t w, uint32_t h, ls_real threshold, uint32_t to_background,
                           ls_real *g, ls_real *line, uint32_t *v)
{
    const uint32_t side = w > h ? w : h;
    ls_real *f = line, *d = line + side + 1u, *z = d + side + 1u;
    uint32_t x, y;
    size_t i;
    for (i = 0; i < (size_t)w * h; i++) { /* 0 at the pixels distances are taken to */
        const int above = rgba[4u * i + 3u] > threshold;
        g[i] = (to_background ? !above : above) ? (ls_real)0 : LS_MASK_FAR;
    }
    for (x = 0; x < w; x++) { /* columns */
        for (y = 0; y < h; y++) f[y] = g[(size_t)y * w + x];
        dt_line(f, h, d, v, z);
        for (y = 0; y < h; y++) g[(size_t)y * w + x] = d[y];
    }
    for (y = 0; y < h; y++) { /* rows */
        memcpy(f, g + (size_t)y * w, w * sizeof(ls_real));
        dt_line(f, w, d, v, z);
        for (x = 0; x < w; x++) g[(size_t)y * w + x] = LS_RSQRT(d[x]);
    }
}

static ls_status check_size(uint32_t width, uint32_t height, ls_diag *diag)
{
    if (width < 1u || width > 65535u || height < 1u || height > 65535u)
        return ls_invalid_arg(diag, "width and height must be 1..65535");
    return LS_OK;
}

static void line_size(uint32_t width, uint32_t height, ls_size *s)
{
    const size_t side = (size_t)(width > height ? width : height) + 1u;
    ls_size_add(s, 3u * side, sizeof(ls_real));
    ls_size_add(s, side, sizeof(uint32_t));
}

ls_status ls_mask_distance_bytes(uint32_t width, uint32_t height, size_t *line_bytes, size_t *field_bytes)
{
    ls_size s;
    ls_status st;
    if (line_bytes == NULL || field_bytes == NULL) return ls_invalid_arg(NULL, "line_bytes and field_bytes must not be NULL");
    st = check_size(width, height, NULL);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    line_size(width, height, &s);
    st = ls_size_get(&s, line_bytes);
    ls_size_init(&s);
    ls_size_add(&s, (size_t)width * height, sizeof(ls_real));
    return st == LS_OK ? ls_size_get(&s, field_bytes) : st;
}

/* dist over the pixels whose alpha is (background ? at most : above) threshold. */
static ls_status distance_call(const ls_real *rgba, uint32_t width, uint32_t height, ls_real threshold,
                               uint32_t to_background, ls_real *dist, ls_arena *arena, ls_diag *diag)
{
    const size_t side = (size_t)(width > height ? width : height) + 1u;
    ls_arena_mark mark;
    ls_real *line;
    uint32_t *v;
    if (rgba == NULL || dist == NULL || arena == NULL) return ls_invalid_arg(diag, "rgba, dist and arena must not be NULL");
    if (check_size(width, height, diag) != LS_OK) return LS_ERR_INVALID;
    if (!(threshold == threshold) || threshold > LS_REAL_MAX || threshold < -LS_REAL_MAX)
        return ls_invalid_arg(diag, "threshold must be finite");
    mark = ls_arena_save(arena);
    line = (ls_real *)ls_arena_scratch(arena, 3u * side, sizeof(ls_real));
    v = (uint32_t *)ls_arena_scratch(arena, side, sizeof(uint32_t));
    if (line == NULL || v == NULL) {
        ls_arena_restore(arena, mark);
        return ls_diag_set(diag, LS_ERR_NOMEM, "mask distance: the arena cannot hold a line's work (ls_mask_distance_bytes)",
                           LS_DIAG_NO_INDEX);
    }
    ls_mask_impl_distance(rgba, width, height, threshold, to_background, dist, line, v);
    ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_mask_distance(const ls_real *rgba, uint32_t width, uint32_t height, ls_real threshold,
                           uint32_t to_background, ls_real *dist, ls_arena *arena, ls_diag *diag)
{
    return distance_call(rgba, width, height, threshold, to_background, dist, arena, diag);
}

ls_status ls_mask_inscribed_radius(const ls_real *rgba, uint32_t width, uint32_t height, ls_arena *arena,
                                   ls_real *radius, ls_diag *diag)
{
    ls_arena_mark mark;
    ls_real *field, best = (ls_real)0;
    uint32_t x, y;
    ls_status st;
    if (radius == NULL || arena == NULL) return ls_invalid_arg(diag, "radius and arena must not be NULL");
    *radius = (ls_real)0;
    if (check_size(width, height, diag) != LS_OK) return LS_ERR_INVALID;
    mark = ls_arena_save(arena);
    field = (ls_real *)ls_arena_alloc(arena, (size_t)width * height, sizeof(ls_real));
    if (field == NULL)
        return ls_diag_set(diag, LS_ERR_NOMEM, "inscribed radius: the arena cannot hold the distance field (ls_mask_distance_bytes)",
                           LS_DIAG_NO_INDEX);
    st = distance_call(rgba, width, height, (ls_real)0.5, 1u, field, arena, diag);
    for (y = 0; st == LS_OK && y < height; y++)
        for (x = 0; x < width; x++) {
            /* the nearest background pixel, or the nearest one beyond the image */
            const uint32_t bx = x + 1u < width - x ? x + 1u : width - x, by = y + 1u < height - y ? y + 1u : height - y;
            ls_real r = field[(size_t)y * width + x];
            const ls_real edge = (ls_real)(bx < by ? bx : by);
            if (r > edge) r = edge;
            if (rgba[4u * ((size_t)y * width + x) + 3u] > (ls_real)0.5 && r > best) best = r;
        }
    ls_arena_restore(arena, mark);
    if (st == LS_OK) *radius = best;
    return st;
}
