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

/* --- labels and backdrop -------------------------------------------------- */

/* The built-in font: 5 x 7 glyphs of the characters below (upper case is
 * drawn as lower case, anything else as '?'). */
static const char font_chars[] = " #%()+,-./0123456789:=?_abcdefghijklmnopqrstuvwxyz";
/* each glyph: 7 rows top first, bit 4 = leftmost column */
static const uint8_t font_rows[50][7] = {
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /* ' ' */
    {0x0a, 0x0a, 0x1f, 0x0a, 0x1f, 0x0a, 0x0a}, /* '#' */
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}, /* '%' */
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}, /* '(' */
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}, /* ')' */
    {0x00, 0x04, 0x04, 0x1f, 0x04, 0x04, 0x00}, /* '+' */
    {0x00, 0x00, 0x00, 0x00, 0x0c, 0x04, 0x08}, /* ',' */
    {0x00, 0x00, 0x00, 0x1f, 0x00, 0x00, 0x00}, /* '-' */
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0c, 0x0c}, /* '.' */
    {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}, /* '/' */
    {0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e}, /* '0' */
    {0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e}, /* '1' */
    {0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f}, /* '2' */
    {0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e}, /* '3' */
    {0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02}, /* '4' */
    {0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e}, /* '5' */
    {0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e}, /* '6' */
    {0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}, /* '7' */
    {0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e}, /* '8' */
    {0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c}, /* '9' */
    {0x00, 0x0c, 0x0c, 0x00, 0x0c, 0x0c, 0x00}, /* ':' */
    {0x00, 0x00, 0x1f, 0x00, 0x1f, 0x00, 0x00}, /* '=' */
    {0x0e, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}, /* '?' */
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1f}, /* '_' */
    {0x00, 0x00, 0x0e, 0x01, 0x0f, 0x11, 0x0f}, /* 'a' */
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1e}, /* 'b' */
    {0x00, 0x00, 0x0e, 0x10, 0x10, 0x11, 0x0e}, /* 'c' */
    {0x01, 0x01, 0x0d, 0x13, 0x11, 0x11, 0x0f}, /* 'd' */
    {0x00, 0x00, 0x0e, 0x11, 0x1f, 0x10, 0x0e}, /* 'e' */
    {0x06, 0x09, 0x08, 0x1c, 0x08, 0x08, 0x08}, /* 'f' */
    {0x00, 0x0f, 0x11, 0x11, 0x0f, 0x01, 0x0e}, /* 'g' */
    {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11}, /* 'h' */
    {0x04, 0x00, 0x0c, 0x04, 0x04, 0x04, 0x0e}, /* 'i' */
    {0x02, 0x00, 0x06, 0x02, 0x02, 0x12, 0x0c}, /* 'j' */
    {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}, /* 'k' */
    {0x0c, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e}, /* 'l' */
    {0x00, 0x00, 0x1a, 0x15, 0x15, 0x11, 0x11}, /* 'm' */
    {0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11}, /* 'n' */
    {0x00, 0x00, 0x0e, 0x11, 0x11, 0x11, 0x0e}, /* 'o' */
    {0x00, 0x00, 0x1e, 0x11, 0x1e, 0x10, 0x10}, /* 'p' */
    {0x00, 0x00, 0x0d, 0x13, 0x0f, 0x01, 0x01}, /* 'q' */
    {0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10}, /* 'r' */
    {0x00, 0x00, 0x0e, 0x10, 0x0e, 0x01, 0x1e}, /* 's' */
    {0x08, 0x08, 0x1c, 0x08, 0x08, 0x09, 0x06}, /* 't' */
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0d}, /* 'u' */
    {0x00, 0x00, 0x11, 0x11, 0x11, 0x0a, 0x04}, /* 'v' */
    {0x00, 0x00, 0x11, 0x11, 0x15, 0x15, 0x0a}, /* 'w' */
    {0x00, 0x00, 0x11, 0x0a, 0x04, 0x0a, 0x11}, /* 'x' */
    {0x00, 0x00, 0x11, 0x11, 0x0f, 0x01, 0x0e}, /* 'y' */
    {0x00, 0x00, 0x1f, 0x02, 0x04, 0x08, 0x1f}, /* 'z' */
};

#define GLYPH_W 5u
#define GLYPH_H 7u

static uint32_t glyph_of(unsigned char c)
{
    uint32_t i, unknown = 0;
    if (c >= 'A' && c <= 'Z') c = (unsigned char)(c - 'A' + 'a');
    for (i = 0; font_chars[i] != '\0'; i++) {
        if ((unsigned char)font_chars[i] == c) return i;
        if (font_chars[i] == '?') unknown = i;
    }
    return unknown;
}

uint32_t ls_contact_label_scale(uint32_t tile_w)
{
    uint32_t s = 1u + tile_w / 256u;
    return s > 4u ? 4u : s;
}

ls_status ls_contact_label(ls_contact *sheet, uint32_t index, const char *text)
{
    static const float box[4] = {0.0f, 0.0f, 0.0f, 1.0f}, ink[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    uint32_t n = 0, s, bw, bh, x, y;
    float *dst;
    ls_status st = check_put(sheet, index, text);
    if (st != LS_OK) return st;
    s = ls_contact_label_scale(sheet->tile_w);
    while (n < sheet->tile_w && text[n] != '\0') n++;
    /* the box: one glyph column of margin around the text, clipped to the cell */
    bw = (n * (GLYPH_W + 1u) + 1u) * s;
    bh = (GLYPH_H + 2u) * s;
    if (bw > sheet->tile_w) bw = sheet->tile_w;
    if (bh > sheet->tile_h) bh = sheet->tile_h;
    dst = cell_origin(sheet, index);
    for (y = 0; y < bh; y++)
        for (x = 0; x < bw; x++) {
            /* glyph pixel: (x / s - 1) across glyphs of GLYPH_W + 1, (y / s - 1) down */
            uint32_t gx = x / s, gy = y / s, on = 0;
            if (gx >= 1u && gy >= 1u && gy <= GLYPH_H) {
                uint32_t k = (gx - 1u) / (GLYPH_W + 1u), c = (gx - 1u) % (GLYPH_W + 1u);
                if (k < n && c < GLYPH_W)
                    on = (font_rows[glyph_of((unsigned char)text[k])][gy - 1u] >> (GLYPH_W - 1u - c)) & 1u;
            }
            memcpy(dst + 4 * ((size_t)y * sheet->image.width + x), on ? ink : box, 4 * sizeof(float));
        }
    return LS_OK;
}

ls_status ls_contact_backdrop(ls_contact *sheet, uint32_t square, float dark, float light)
{
    uint32_t x, y;
    if (sheet == NULL) return LS_ERR_INVALID;
    if (sheet->magic != CONTACT_MAGIC || sheet->image.pixels == NULL) return LS_ERR_STATE;
    if (!(dark >= 0.0f && dark <= 1.0f) || !(light >= 0.0f && light <= 1.0f)) return LS_ERR_INVALID;
    for (y = 0; y < sheet->image.height; y++)
        for (x = 0; x < sheet->image.width; x++) {
            float *p = sheet->image.pixels + 4 * ((size_t)y * sheet->image.width + x);
            float a = p[3], bg = dark, t;
            if (a >= 1.0f) continue;
            if (!(a > 0.0f)) a = 0.0f;
            if (square > 0 && ((x / square + y / square) & 1u)) bg = light;
            t = (1.0f - a) * bg;
            p[0] += t;
            p[1] += t;
            p[2] += t;
            p[3] = 1.0f;
        }
    return LS_OK;
}
