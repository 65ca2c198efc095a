/* imgtool.c - command-line helper for tests/stage_images.sh (test-only).
 *
 *   imgtool dump FILE                 decode FILE with largesteps and print its pixels
 *                                     as integers in `oiiotool --dumpdata` layout
 *                                     (channels and depth as OpenImageIO reports them)
 *   imgtool dumpf FILE                the same as floats (%.9f), as oiiotool prints float images
 *   imgtool convert IN OUT TYPE CH BITS [be]
 *                                     decode IN, encode OUT (TYPE png|pngstored|pnm|pfm)
 *   imgtool info FILE                 print what ls_image_decode_info found
 *   imgtool digests                   FNV-1a 64 of the encoded outputs of a fixed
 *                                     synthetic image in every format (for tests/digest.c)
 *   imgtool bench [FILE.png ...]      encode/decode throughput in MB/s
 *
 * Build: cc -std=c99 -Iinclude -Ibuild/gcc-double/include -Iport/posix tests/tools/imgtool.c \
 *        build/gcc-double/liblargesteps-posix.a build/gcc-double/liblargesteps.a -lm
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <largesteps.h>
#include "ls_posix.h"

static int fail(const char *what, ls_status st, const ls_diag *d)
{
    fprintf(stderr, "imgtool: %s: %s", what, ls_status_name(st));
    if (d != NULL && d->what != NULL && d->what[0]) fprintf(stderr, " (%s", d->what);
    if (d != NULL && d->has_offset) fprintf(stderr, " at byte %llu", (unsigned long long)d->offset);
    if (d != NULL && d->what != NULL && d->what[0]) fprintf(stderr, ")");
    fprintf(stderr, "\n");
    return 1;
}

/* Decodes a file into a malloc'd arena; returns 0 on success. */
static int load(const char *path, ls_image *img, ls_image_info *info, void **mem)
{
    unsigned char *data;
    size_t n;
    ls_diag d;
    ls_arena a;
    ls_status st = ls_posix_read_file(path, &data, &n);
    if (st != LS_OK) return fail(path, st, NULL);
    st = ls_image_decode_info(data, n, info, &d);
    if (st != LS_OK) {
        free(data);
        return fail(path, st, &d);
    }
    *mem = malloc(info->arena_bytes + 8);
    ls_arena_init(&a, *mem, info->arena_bytes);
    st = ls_image_decode(data, n, img, &a, &d);
    free(data);
    if (st != LS_OK) return fail(path, st, &d);
    return 0;
}

static int cmd_dump(const char *path, int as_float)
{
    ls_image img;
    ls_image_info info;
    void *mem;
    uint32_t x, y, k, ch, bits;
    if (load(path, &img, &info, &mem)) return 1;
    /* the layout OpenImageIO presents */
    ch = info.palette ? 3u : info.format.channels;
    if (info.transparency) ch++;
    bits = info.format.bits == 16u ? 16u : 8u;
    printf("%u x %u, %u channel, %s\n", img.width, img.height, ch,
           (info.format.type == LS_IMAGE_PFM || as_float) ? "float" : bits == 8 ? "uint8" : "uint16");
    for (y = 0; y < img.height; y++)
        for (x = 0; x < img.width; x++) {
            const float *px = img.pixels + 4 * ((size_t)y * img.width + x);
            printf("    Pixel (%u, %u):", x, y);
            for (k = 0; k < ch; k++) {
                float v = px[(ch <= 2 && k == 1) ? 3 : k];
                if (info.format.type == LS_IMAGE_PFM || as_float)
                    printf(" %.9f", (double)v);
                else
                    printf(" %u", bits == 8 ? (unsigned)ls_unorm8(v) : (unsigned)ls_unorm16(v));
            }
            printf("\n");
        }
    free(mem);
    return 0;
}

static int parse_format(const char *type, const char *ch, const char *bits, const char *be, ls_image_format *f)
{
    f->type = strcmp(type, "png") == 0 ? LS_IMAGE_PNG : strcmp(type, "pnm") == 0 ? LS_IMAGE_PNM
              : strcmp(type, "pfm") == 0 ? LS_IMAGE_PFM : strcmp(type, "pngstored") == 0 ? LS_IMAGE_PNG_STORED : 0;
    f->channels = (uint32_t)atoi(ch);
    f->bits = (uint32_t)atoi(bits);
    f->big_endian = be != NULL && strcmp(be, "be") == 0;
    return f->type != 0;
}

static ls_status write_file(const char *path, const ls_image *img, const ls_image_format *f)
{
    size_t bytes;
    void *mem;
    ls_arena a;
    ls_status st;
    FILE *out;
    st = ls_image_encode_bytes(img->width, img->height, f, &bytes);
    if (st != LS_OK) return st;
    mem = malloc(bytes + 8);
    ls_arena_init(&a, mem, bytes);
    out = fopen(path, "wb");
    if (out == NULL) {
        free(mem);
        return LS_ERR_IO;
    }
    st = ls_image_encode(img, f, ls_posix_write_file, out, &a);
    if (fclose(out) != 0 && st == LS_OK) st = LS_ERR_IO;
    free(mem);
    return st;
}

static int cmd_convert(int argc, char **argv)
{
    ls_image img;
    ls_image_info info;
    ls_image_format f;
    void *mem;
    ls_status st;
    if (argc < 7 || !parse_format(argv[4], argv[5], argv[6], argc > 7 ? argv[7] : NULL, &f)) {
        fprintf(stderr, "usage: imgtool convert IN OUT png|pngstored|pnm|pfm CHANNELS BITS [be]\n");
        return 2;
    }
    if (load(argv[2], &img, &info, &mem)) return 1;
    st = write_file(argv[3], &img, &f);
    free(mem);
    if (st != LS_OK) return fail(argv[3], st, NULL);
    return 0;
}

static int cmd_info(const char *path)
{
    unsigned char *data;
    size_t n;
    ls_image_info info;
    ls_diag d;
    ls_status st = ls_posix_read_file(path, &data, &n);
    if (st != LS_OK) return fail(path, st, NULL);
    st = ls_image_decode_info(data, n, &info, &d);
    free(data);
    if (st != LS_OK) return fail(path, st, &d);
    printf("%s: type %u, %ux%u, %u channels, %u bits, palette %u, tRNS %u, interlaced %u, arena %lu bytes\n", path,
           info.format.type, info.width, info.height, info.format.channels, info.format.bits, info.palette,
           info.transparency, info.interlaced, (unsigned long)info.arena_bytes);
    return 0;
}

/* A fixed synthetic image: integer-valued samples, out-of-range values and
 * a NaN, so that encoder output covers the rounding rule too. */
static void synthetic(ls_image *img)
{
    size_t i, n = (size_t)img->width * img->height * 4;
    for (i = 0; i < n; i++) img->pixels[i] = (float)(((uint32_t)i * 2654435761u) % 70001u) / 65535.0f - 0.03f;
    img->pixels[5] = 0.5f;
    img->pixels[6] = -1.0f;
    memcpy(&img->pixels[7], "\x00\x00\xc0\x7f", 4); /* NaN */
}

typedef struct fnv_sink {
    uint64_t h;
    size_t bytes;
} fnv_sink;

static int32_t fnv_write(void *user, const void *data, size_t bytes)
{
    fnv_sink *s = (fnv_sink *)user;
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    for (i = 0; i < bytes; i++) {
        s->h ^= p[i];
        s->h *= 1099511628211ull;
    }
    s->bytes += bytes;
    return 0;
}

/* The digests tests/digest.c can adopt: FNV-1a 64 of each encoding of a
 * 67 x 45 synthetic image (rows odd, an IDAT/stored-block boundary is not
 * reached: see the large case for that). */
static int cmd_digests(void)
{
    static const struct { const char *name; ls_image_format f; uint32_t w, h; } cases[] = {
        {"png_grey8", {LS_IMAGE_PNG, 1, 8, 0}, 67, 45},    {"png_grey16", {LS_IMAGE_PNG, 1, 16, 0}, 67, 45},
        {"png_ga8", {LS_IMAGE_PNG, 2, 8, 0}, 67, 45},      {"png_rgb8", {LS_IMAGE_PNG, 3, 8, 0}, 67, 45},
        {"png_rgb16", {LS_IMAGE_PNG, 3, 16, 0}, 67, 45},   {"png_rgba8", {LS_IMAGE_PNG, 4, 8, 0}, 67, 45},
        {"png_rgba16", {LS_IMAGE_PNG, 4, 16, 0}, 67, 45},  {"pgm8", {LS_IMAGE_PNM, 1, 8, 0}, 67, 45},
        {"ppm16", {LS_IMAGE_PNM, 3, 16, 0}, 67, 45},       {"pfm_rgb_le", {LS_IMAGE_PFM, 3, 32, 0}, 67, 45},
        {"pfm_grey_be", {LS_IMAGE_PFM, 1, 32, 1}, 67, 45}, {"png_rgba16_large", {LS_IMAGE_PNG, 4, 16, 0}, 300, 200},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t img_bytes, enc_bytes;
        void *mem;
        ls_arena a;
        ls_image img;
        fnv_sink s = {14695981039346656037ull, 0};
        ls_image_bytes(cases[i].w, cases[i].h, &img_bytes);
        ls_image_encode_bytes(cases[i].w, cases[i].h, &cases[i].f, &enc_bytes);
        mem = malloc(img_bytes + enc_bytes + 8);
        ls_arena_init(&a, mem, img_bytes + enc_bytes);
        ls_image_create(&img, cases[i].w, cases[i].h, &a);
        synthetic(&img);
        if (ls_image_encode(&img, &cases[i].f, fnv_write, &s, &a) != LS_OK) return 1;
        printf("%-18s %3ux%-3u %7lu bytes  %016llx\n", cases[i].name, cases[i].w, cases[i].h, (unsigned long)s.bytes,
               (unsigned long long)s.h);
        free(mem);
    }
    return 0;
}

/* CPU time of this process (the machine may be shared: wall time would
 * count other processes' work). */
static double now(void)
{
    return (double)clock() / (double)CLOCKS_PER_SEC;
}

static int32_t null_write(void *user, const void *data, size_t bytes)
{
    (void)data;
    *(size_t *)user += bytes;
    return 0;
}

/* Encode and decode a 2048 x 2048 image in memory; decode each given file. */
static int cmd_bench(int argc, char **argv)
{
    static const ls_image_format fmts[] = {{LS_IMAGE_PNG, 4, 8, 0}, {LS_IMAGE_PNG, 4, 16, 0},
                                           {LS_IMAGE_PNG_STORED, 4, 8, 0}, {LS_IMAGE_PNG_STORED, 4, 16, 0},
                                           {LS_IMAGE_PNM, 3, 8, 0}, {LS_IMAGE_PFM, 3, 32, 0}};
    static const char *names[] = {"png rgba8", "png rgba16", "stored rgba8", "stored rgba16", "ppm rgb8", "pfm rgb"};
    uint32_t w = 2048, h = 2048;
    size_t img_bytes, i;
    void *mem;
    ls_arena a;
    ls_image img;
    int k;
    ls_image_bytes(w, h, &img_bytes);
    mem = malloc(img_bytes + (1u << 20));
    ls_arena_init(&a, mem, img_bytes + (1u << 20));
    ls_image_create(&img, w, h, &a);
    synthetic(&img);
    for (i = 0; i < sizeof fmts / sizeof fmts[0]; i++) {
        size_t file_bytes, written = 0, dec_bytes;
        unsigned char *file;
        ls_membuf m;
        void *dmem;
        ls_arena da;
        ls_image out;
        ls_image_info info;
        double t0, t1, t2;
        int reps = 3, r;
        ls_image_encoded_size(w, h, &fmts[i], &file_bytes);
        t0 = now();
        for (r = 0; r < reps; r++) ls_image_encode(&img, &fmts[i], null_write, &written, &a);
        t1 = now();
        file = (unsigned char *)malloc(file_bytes);
        m.data = file;
        m.capacity = file_bytes;
        m.size = 0;
        m.overflow = 0;
        ls_image_encode(&img, &fmts[i], ls_membuf_write, &m, &a);
        file_bytes = m.size; /* LS_IMAGE_PNG: the size query is a bound */
        ls_image_decode_info(file, file_bytes, &info, NULL);
        dec_bytes = info.arena_bytes;
        dmem = malloc(dec_bytes + 8);
        t2 = now();
        for (r = 0; r < reps; r++) {
            ls_arena_init(&da, dmem, dec_bytes);
            if (ls_image_decode(file, file_bytes, &out, &da, NULL) != LS_OK) return 1;
        }
        t2 = now() - t2;
        printf("%-11s %ux%u: file %.1f MB; encode %.0f MB/s of file (%.1f Mpixel/s); decode %.0f MB/s of file (%.1f Mpixel/s)\n",
               names[i], w, h, (double)file_bytes / 1e6, (double)file_bytes * reps / 1e6 / (t1 - t0),
               (double)w * h * reps / 1e6 / (t1 - t0), (double)file_bytes * reps / 1e6 / t2,
               (double)w * h * reps / 1e6 / t2);
        free(dmem);
        free(file);
    }
    free(mem);
    for (k = 2; k < argc; k++) {
        unsigned char *data;
        size_t n;
        ls_image_info info;
        void *dmem;
        ls_arena da;
        ls_image out;
        double t;
        int r, reps = 5;
        if (ls_posix_read_file(argv[k], &data, &n) != LS_OK || ls_image_decode_info(data, n, &info, NULL) != LS_OK)
            return 1;
        dmem = malloc(info.arena_bytes + 8);
        t = now();
        for (r = 0; r < reps; r++) {
            ls_arena_init(&da, dmem, info.arena_bytes);
            if (ls_image_decode(data, n, &out, &da, NULL) != LS_OK) return 1;
        }
        t = now() - t;
        {
            /* bytes the inflater produces (non-interlaced layout) */
            double raw = (double)info.height *
                         (1.0 + (double)(((uint64_t)info.width * info.format.channels * info.format.bits + 7) / 8));
            printf("decode %s (%ux%u, %lu bytes compressed, %.0f bytes inflated): %.0f MB/s compressed in, %.0f MB/s "
                   "inflated out, %.1f Mpixel/s\n",
                   argv[k], info.width, info.height, (unsigned long)n, raw, (double)n * reps / 1e6 / t,
                   raw * reps / 1e6 / t, (double)info.width * info.height * reps / 1e6 / t);
        }
        free(dmem);
        /* the inflater alone: the IDAT data joined, through ls_zlib_decompress */
        if (info.format.type == LS_IMAGE_PNG) {
            unsigned char *z = (unsigned char *)malloc(n), *out;
            size_t zn = 0, pos = 8, cap = 0, got = 0, st_bytes;
            void *smem;
            ls_arena sa;
            while (pos + 12 <= n) {
                size_t len = ((size_t)data[pos] << 24) | ((size_t)data[pos + 1] << 16) | ((size_t)data[pos + 2] << 8) | data[pos + 3];
                if (memcmp(data + pos + 4, "IDAT", 4) == 0) {
                    memcpy(z + zn, data + pos + 8, len);
                    zn += len;
                }
                pos += 12 + len;
            }
            cap = (size_t)info.height * (1 + ((size_t)info.width * info.format.channels * info.format.bits + 7) / 8) * 2;
            out = (unsigned char *)malloc(cap);
            ls_inflate_bytes(&st_bytes);
            smem = malloc(st_bytes + 8);
            t = now();
            for (r = 0; r < reps; r++) {
                ls_arena_init(&sa, smem, st_bytes);
                if (ls_zlib_decompress(z, zn, out, cap, &got, &sa, NULL) != LS_OK) return 1;
            }
            t = now() - t;
            printf("   inflate only (ls_zlib_decompress): %.0f MB/s out\n", (double)got * reps / 1e6 / t);
            free(smem);
            free(out);
            free(z);
        }
        free(data);
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "dump") == 0) return cmd_dump(argv[2], 0);
    if (argc >= 3 && strcmp(argv[1], "dumpf") == 0) return cmd_dump(argv[2], 1);
    if (argc >= 2 && strcmp(argv[1], "convert") == 0) return cmd_convert(argc, argv);
    if (argc >= 3 && strcmp(argv[1], "info") == 0) return cmd_info(argv[2]);
    if (argc >= 2 && strcmp(argv[1], "digests") == 0) return cmd_digests();
    if (argc >= 2 && strcmp(argv[1], "bench") == 0) return cmd_bench(argc, argv);
    fprintf(stderr, "usage: imgtool dump|convert|info|digests|bench ...\n");
    return 2;
}
