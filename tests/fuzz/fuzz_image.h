/* tests/fuzz/fuzz_image.h - the image-decoder harness: fuzz_image_decode()
 * runs ls_image_decode_info and ls_image_decode on one file and checks them.
 * Used by fuzz_png.c, fuzz_ppm.c and fuzz_pfm.c.
 *
 * Checks, besides the common invariants (fuzz_common.h): the header's limits
 * (sides 1..LS_IMAGE_MAX_SIDE, pixels up to LS_IMAGE_MAX_PIXELS), that the
 * decoder fails with the status of ls_image_decode_info when that fails,
 * never fails with LS_ERR_NOMEM in an arena of info.arena_bytes and takes
 * exactly that many bytes at its peak, never succeeds in less; on success the
 * image has the header's size and every value of an integer format lies in
 * [0, 1] (PFM keeps every float as stored, NaN included, by design).
 */
#ifndef LS_FUZZ_IMAGE_H
#define LS_FUZZ_IMAGE_H

#include "fuzz_common.h"

static void fuzz_image_decode(uint8_t selector, const uint8_t *data, size_t size)
{
    ls_image_info info;
    ls_image image, before;
    ls_diag diag, info_diag;
    ls_status info_st, st;
    fuzz_arena fa;
    size_t need = 0, i, n;
    ls_diag_clear(&info_diag);
    info_st = ls_image_decode_info(data, size, &info, &info_diag);
    FUZZ_ASSERT(info_st >= LS_OK && info_st < LS_STATUS_COUNT && info_st != LS_ERR_NOMEM);
    if (info_st == LS_OK) {
        size_t img = 0;
        FUZZ_ASSERT(info.width >= 1 && info.width <= LS_IMAGE_MAX_SIDE);
        FUZZ_ASSERT(info.height >= 1 && info.height <= LS_IMAGE_MAX_SIDE);
        FUZZ_ASSERT((uint64_t)info.width * info.height <= LS_IMAGE_MAX_PIXELS);
        FUZZ_ASSERT(ls_image_bytes(info.width, info.height, &img) == LS_OK && img == info.image_bytes);
        FUZZ_ASSERT(info.arena_bytes >= info.image_bytes);
        FUZZ_ASSERT(info.format.channels >= 1 && info.format.channels <= 4);
        need = info.arena_bytes;
    } else {
        FUZZ_ASSERT(info_diag.what != NULL && info_diag.what[0] != '\0' && info_diag.status == info_st);
    }
    fuzz_arena_open(&fa, selector, need);
    memset(&image, 0x5A, sizeof image);
    before = image;
    ls_diag_clear(&diag);
    st = ls_image_decode(data, size, &image, &fa.arena, &diag);
    fuzz_check_status(info_st, st, &fa, 1);
    if (st != LS_OK) {
        fuzz_check_failure(st, &diag, &fa, &image, &before, sizeof image);
    } else {
        FUZZ_ASSERT(fuzz_arena_peak(&fa) == need);
        FUZZ_ASSERT(fa.arena.bottom == fa.mark.bottom + info.image_bytes && fa.arena.top == fa.mark.top);
        FUZZ_ASSERT(image.width == info.width && image.height == info.height);
        FUZZ_ASSERT((unsigned char *)image.pixels >= fa.buf &&
                    (unsigned char *)image.pixels + info.image_bytes <= fa.buf + fa.arena.capacity);
        n = (size_t)image.width * image.height * 4u;
        if (info.format.type != LS_IMAGE_PFM) {
            for (i = 0; i < n; i++) FUZZ_ASSERT(image.pixels[i] >= 0.0f && image.pixels[i] <= 1.0f);
        } else {
            volatile float sum = 0.0f; /* touch every value (ASan/valgrind see reads) */
            for (i = 0; i < n; i++) sum += image.pixels[i];
            (void)sum;
        }
    }
    fuzz_arena_close(&fa);
}

#endif /* LS_FUZZ_IMAGE_H */
