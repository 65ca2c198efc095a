/* largesteps/checksum.h - CRC-32 and Adler-32, as used by PNG and zlib.
 *
 * Both are running checksums with zlib's conventions: start from the value of
 * an empty input (ls_crc32(0, NULL, 0) == 0, ls_adler32(1, NULL, 0) == 1) and
 * feed the data in any number of pieces. Their names carry the library prefix
 * so that they never collide with zlib's crc32/adler32 in the same program.
 */
#ifndef LARGESTEPS_CHECKSUM_H
#define LARGESTEPS_CHECKSUM_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ls_crc32: the CRC-32 of ISO 3309 / ITU-T V.42 (polynomial 0xEDB88320
 * reflected, pre- and post-inverted) of data[0..bytes) continued from `crc`
 * (0 for a new checksum); "123456789" gives 0xCBF43926. O(bytes), table
 * driven (4 KB of constant tables); no memory. data may be NULL when bytes is 0. */
uint32_t ls_crc32(uint32_t crc, const void *data, size_t bytes);

/* ls_adler32: the Adler-32 of RFC 1950 of data[0..bytes) continued from
 * `adler` (1 for a new checksum); "Wikipedia" gives 0x11E60398. O(bytes); no
 * memory. data may be NULL when bytes is 0. */
uint32_t ls_adler32(uint32_t adler, const void *data, size_t bytes);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_CHECKSUM_H */
