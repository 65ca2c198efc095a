/* tests/fuzz/fuzz_ppm.c - libFuzzer target: ls_image_decode on PGM/PPM (P5,
 * P6) files. Input: the selector byte (fuzz_common.h), then the file. */
#include "fuzz_image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    fuzz_image_decode(data[0], data + 1, size - 1);
    return 0;
}
