/* largesteps/contact.h - contact sheets: many equally sized images tiled in
 * one image (the views of a render, the target / initial / final renders of
 * a fit).
 *
 * Layout: `columns` tiles per row, rows = ceil(count / columns), tiles in
 * row-major order (tile i at column i % columns, row i / columns, row 0 at
 * the top), separated by lines `sep` pixels wide between neighbouring tiles
 * (none around the border):
 *     width  = columns tile_w + (columns - 1) sep
 *     height = rows tile_h + (rows - 1) sep.
 * Separator lines and cells without a tile keep the separator colour the
 * sheet was created with. columns = 0 picks the smallest c with c^2 >= count
 * (a near-square grid). Tiles can be labelled (ls_contact_label: a built-in
 * bitmap font) and the sheet put over a grey checkerboard so that masks and
 * transparent backgrounds show (ls_contact_backdrop). The sheet is an
 * ls_image (largesteps/image.h), to be encoded with ls_image_encode.
 */
#ifndef LARGESTEPS_CONTACT_H
#define LARGESTEPS_CONTACT_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>
#include <largesteps/image.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ls_contact {
    ls_image image;     /* the sheet */
    uint32_t count;     /* tiles */
    uint32_t columns;   /* tiles per row */
    uint32_t rows;      /* rows of tiles */
    uint32_t tile_w;    /* tile width in pixels */
    uint32_t tile_h;    /* tile height in pixels */
    uint32_t sep;       /* separator width in pixels */
    uint32_t magic;     /* set by ls_contact_init */
} ls_contact;

/* ls_contact_layout: the grid of `count` tiles of tile_w x tile_h with
 * `columns` per row (0: automatic, see above) and `sep`-pixel separators:
 * fills every field of *layout but the pixels (image.pixels = NULL; the
 * sheet is not usable before ls_contact_init). Errors: LS_ERR_INVALID (NULL
 * layout, zero count or tile side), LS_ERR_TOO_LARGE (the sheet beyond
 * LS_IMAGE_MAX_SIDE / LS_IMAGE_MAX_PIXELS). O(sqrt(count)); no memory. */
ls_status ls_contact_layout(uint32_t count, uint32_t tile_w, uint32_t tile_h, uint32_t columns, uint32_t sep,
                            ls_contact *layout);

/* ls_contact_bytes: the exact arena bytes of ls_contact_init (the sheet's
 * pixels, ls_image_bytes of its size). Errors as ls_contact_layout, and
 * LS_ERR_INVALID for NULL bytes. O(sqrt(count)). */
ls_status ls_contact_bytes(uint32_t count, uint32_t tile_w, uint32_t tile_h, uint32_t columns, uint32_t sep,
                           size_t *bytes);

/* ls_contact_init: allocates the sheet from the bottom of the arena and fills
 * it with the separator colour sep_rgba (RGBA; NULL: opaque black). Errors as
 * ls_contact_bytes, LS_ERR_NOMEM (arena and *sheet unchanged). O(sheet pixels). */
ls_status ls_contact_init(ls_contact *sheet, ls_arena *arena, uint32_t count, uint32_t tile_w, uint32_t tile_h,
                          uint32_t columns, uint32_t sep, const float sep_rgba[4]);

/* ls_contact_put_image: copies a tile_w x tile_h image into cell `index`.
 * Errors: LS_ERR_STATE (sheet not initialised), LS_ERR_INVALID (NULL, index
 * >= count, a tile of another size). O(tile pixels); no memory. */
ls_status ls_contact_put_image(ls_contact *sheet, uint32_t index, const ls_image *tile);

/* ls_contact_put_rgba: the same from tile_w x tile_h RGBA ls_real pixels,
 * rows top first (the layout of ls_shade's output), each value rounded to
 * float. Errors as ls_contact_put_image. O(tile pixels); no memory. */
ls_status ls_contact_put_rgba(ls_contact *sheet, uint32_t index, const ls_real *rgba);

/* ls_contact_label: writes `text` at the top-left corner of cell `index` in
 * the built-in 5 x 7 pixel font (digits, letters, space and - . : / = + %
 * ( ) _ ? , #; upper case is drawn as lower case, other bytes as '?'), white
 * glyphs on an opaque black box, the glyphs and their margin of one glyph
 * pixel scaled by ls_contact_label_scale(tile_w); the box is
 * (6 n + 1) s x 9 s pixels for n characters at scale s, clipped to the cell.
 * Call it after the tile is put (putting a tile overwrites its cell).
 * Errors as ls_contact_put_image (a NULL text: LS_ERR_INVALID).
 * O(label pixels); no memory. */
ls_status ls_contact_label(ls_contact *sheet, uint32_t index, const char *text);

/* ls_contact_label_scale: the label's pixel scale for tiles tile_w wide:
 * 1 + tile_w / 256, at most 4. O(1). */
uint32_t ls_contact_label_scale(uint32_t tile_w);

/* ls_contact_backdrop: puts every pixel with alpha below 1 over an opaque
 * checkerboard of `square`-pixel squares (0: plain) of the greys dark (the
 * top-left square) and light, both in [0, 1]: the colour channels are taken
 * as premultiplied by alpha (ls_shade's output over its default black
 * background), so c = c + (1 - a) grey and a = 1 (alpha below 0 or NaN
 * counts as 0). A white mask, invisible over white in a viewer, shows
 * against the greys. Errors: LS_ERR_INVALID (NULL sheet, a grey outside
 * [0, 1]), LS_ERR_STATE (sheet not initialised). O(sheet pixels); no memory. */
ls_status ls_contact_backdrop(ls_contact *sheet, uint32_t square, float dark, float light);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_CONTACT_H */
