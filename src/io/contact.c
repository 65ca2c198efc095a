/* contact.c - contact sheets: equally sized images tiled in one image.
 * Layout and conventions: include/largesteps/contact.h. */
#include <largesteps/contact.h>
#include <string.h>

#define CONTACT_MAGIC 0x43544354u /* "CTCT" */

ls_status ls_contact_layout(uint32_t count, uint32_t tile_w, uint32_t tile_h, uint32_t columns, uint32_t sep,
                            ls_contact *layout)
{
    uint64_t cols = columns, rows, w, h;
    if (layout == NULL || count == 0 || tile_w == 0 || tile_h == 0) return LS_ERR_INVALID;
    if (cols == 0) {
        cols = 1;
        while (cols * cols < count) cols++;
    }
    if (cols > count) cols = count;
    rows = (count + cols - 1u) / cols;
    /* each step stays far below 2^64: the tile sides are checked before the
     * separators are added */
    w = cols * tile_w;
    h = rows * tile_h;
    if (w > LS_IMAGE_MAX_SIDE || h > LS_IMAGE_MAX_SIDE) return LS_ERR_TOO_LARGE;
    w += (cols - 1u) * (uint64_t)sep;
    h += (rows - 1u) * (uint64_t)sep;
    if (w > LS_IMAGE_MAX_SIDE || h > LS_IMAGE_MAX_SIDE || w * h > LS_IMAGE_MAX_PIXELS) return LS_ERR_TOO_LARGE;
    memset(layout, 0, sizeof *layout);
    layout->count = count;
    layout->columns = (uint32_t)cols;
    layout->rows = (uint32_t)rows;
    layout->tile_w = tile_w;
    layout->tile_h = tile_h;
    layout->sep = sep;
    layout->image.width = (uint32_t)w;
    layout->image.height = (uint32_t)h;
    return LS_OK;
}

ls_status ls_contact_bytes(uint32_t count, uint32_t tile_w, uint32_t tile_h, uint32_t columns, uint32_t sep,
                           size_t *bytes)
{
    ls_contact c;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    st = ls_contact_layout(count, tile_w, tile_h, columns, sep, &c);
    if (st != LS_OK) return st;
    return ls_image_bytes(c.image.width, c.image.height, bytes);
}

ls_status ls_contact_init(ls_contact *sheet, ls_arena *arena, uint32_t count, uint32_t tile_w, uint32_t tile_h,
                          uint32_t columns, uint32_t sep, const float sep_rgba[4])
{
    static const float black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    ls_contact c;
    size_t i, n;
    ls_status st;
    if (sheet == NULL || arena == NULL) return LS_ERR_INVALID;
    st = ls_contact_layout(count, tile_w, tile_h, columns, sep, &c);
    if (st != LS_OK) return st;
    st = ls_image_create(&c.image, c.image.width, c.image.height, arena);
    if (st != LS_OK) return st;
    if (sep_rgba == NULL) sep_rgba = black;
    n = (size_t)c.image.width * c.image.height;
    for (i = 0; i < n; i++) memcpy(c.image.pixels + 4 * i, sep_rgba, 4 * sizeof(float));
    c.magic = CONTACT_MAGIC;
    *sheet = c;
    return LS_OK;
}

/* The first value of cell `index` in the sheet's pixels (checks done). */
static float *cell_origin(const ls_contact *c, uint32_t index)
{
    size_t col = index % c->columns, row = index / c->columns;
    size_t x0 = col * ((size_t)c->tile_w + c->sep), y0 = row * ((size_t)c->tile_h + c->sep);
    return c->image.pixels + 4 * (y0 * c->image.width + x0);
}

static ls_status check_put(const ls_contact *c, uint32_t index, const void *p)
{
    if (c == NULL || p == NULL) return LS_ERR_INVALID;
    if (c->magic != CONTACT_MAGIC || c->image.pixels == NULL) return LS_ERR_STATE;
    if (index >= c->count) return LS_ERR_INVALID;
    return LS_OK;
}

ls_status ls_contact_put_image(ls_contact *sheet, uint32_t index, const ls_image *tile)
{
    uint32_t y;
    float *dst;
    ls_status st = check_put(sheet, index, tile);
    if (st != LS_OK) return st;
    if (tile->pixels == NULL || tile->width != sheet->tile_w || tile->height != sheet->tile_h)
        return LS_ERR_INVALID;
    dst = cell_origin(sheet, index);
    for (y = 0; y < sheet->tile_h; y++)
        memcpy(dst + 4 * (size_t)y * sheet->image.width, tile->pixels + 4 * (size_t)y * tile->width,
               4 * (size_t)tile->width * sizeof(float));
    return LS_OK;
}

ls_status ls_contact_put_rgba(ls_contact *sheet, uint32_t index, const ls_real *rgba)
{
    uint32_t y;
    size_t x, row;
    float *dst;
    ls_status st = check_put(sheet, index, rgba);
    if (st != LS_OK) return st;
    row = 4 * (size_t)sheet->tile_w;
    dst = cell_origin(sheet, index);
    for (y = 0; y < sheet->tile_h; y++) {
        float *d = dst + 4 * (size_t)y * sheet->image.width;
        const ls_real *s = rgba + row * y;
        for (x = 0; x < row; x++) d[x] = (float)s[x];
    }
    return LS_OK;
}
