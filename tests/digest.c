/* tests/digest.c - bit-exact digests of library outputs: every target must
 * print exactly the lines committed in fixtures/digest-<ls_real>.txt.
 *
 * Output: one line per entry of the table at the end of this file, then a
 * line that digests all entries together:
 *     <name>               n=<values> nan=<NaNs>  <hash, 16 hex digits>  <what it hashed>
 * `make check` (every native variant, every cross target, Cortex-M4) runs
 * this program and compares its stdout with the fixture, byte for byte
 * (tests/tools/digest_check.sh); a drift between commits or between targets
 * shows as the entries whose lines differ.
 *
 * The hash. FNV-1a, 64 bits, over a canonical byte stream: every value is
 * first turned into an unsigned integer - a float into its 32 IEEE-754 bits,
 * a double into its 64 bits, any integer or size into a uint64_t - and that
 * integer is appended least significant byte first. So the digest is a
 * function of the values alone, not of how they lie in memory: big-endian
 * s390x, 32-bit armhf and x86-64 print the same hash. Strings are appended as
 * their length (uint64) followed by their bytes. The n= count is the number
 * of values appended.
 *
 * NaN never enters a digest: the sign and payload bits of a NaN differ
 * between architectures (x86 makes negative NaNs, ARM positive ones), so any
 * NaN is appended as one fixed token (the bits of the positive quiet NaN of
 * its type) and counted in nan=. Whether a result is NaN is thus pinned;
 * its bits are not. Signed zeros and infinities are hashed as they are.
 *
 * Adding outputs (every module does this for its public results):
 *   1. write `static void dg_NAME(digest *d)` that computes the outputs from
 *      inputs made here (integer sweeps, the LCG below, small built-in data;
 *      no files) and appends them with dg_real / dg_f32 / dg_f64 / dg_u32 /
 *      dg_u64 / dg_size / dg_str / dg_status;
 *   2. add a row {"module.what", dg_NAME, "what it hashed"} to `entries`;
 *   3. run `make digest-update` (writes both fixtures from the native gcc
 *      build), check with `git diff fixtures/` that only your lines changed,
 *      and commit the fixtures with the code.
 * Rules for an entry: hash only values that must be the same on every target
 * (a size that depends on sizeof(void *) is not: hash sizes of pointer-free
 * requests only); keep the work to a few milliseconds natively (the whole
 * program takes about 10 ms on x86-64; QEMU runs float code 10-20x slower,
 * and double on Cortex-M4 is soft float, about 100x); the
 * program must run in the MCU profile (256 KiB of RAM, 8 KiB of stack), so
 * use the shared arena `dg_arena` (DG_ARENA_BYTES) and no large locals, no
 * malloc.
 */
#include <stdio.h>
#include <string.h>
#include <stdint.h>
#include <largesteps.h>

/* The deterministic math module (largesteps/math.h), present when its
 * type-generic macros are. */
#if defined(LS_RSIN)
#define DIGEST_MATH 1
#else
#define DIGEST_MATH 0
#endif

typedef struct digest {
    uint64_t hash;
    uint64_t count;
    uint64_t nans;
} digest;

#define DG_FNV_OFFSET 14695981039346656037ull
#define DG_FNV_PRIME 1099511628211ull

static void dg_byte(digest *d, unsigned char b)
{
    d->hash ^= b;
    d->hash *= DG_FNV_PRIME;
}

/* Appends v least significant byte first (one value). */
static void dg_word(digest *d, uint64_t v, int bytes)
{
    int i;
    for (i = 0; i < bytes; i++) dg_byte(d, (unsigned char)((v >> (8 * i)) & 0xFFu));
    d->count++;
}

static void dg_u32(digest *d, uint32_t v) { dg_word(d, v, 4); }
static void dg_u64(digest *d, uint64_t v) { dg_word(d, v, 8); }
static void dg_size(digest *d, size_t v) { dg_word(d, (uint64_t)v, 8); }
static void dg_status(digest *d, ls_status s) { dg_word(d, (uint64_t)(uint32_t)s, 4); }

static void dg_f32(digest *d, float v)
{
    uint32_t bits;
    if (v != v) {
        d->nans++;
        bits = 0x7FC00000u;
    } else {
        memcpy(&bits, &v, sizeof bits);
    }
    dg_word(d, bits, 4);
}

static void dg_f64(digest *d, double v)
{
    uint64_t bits;
    if (v != v) {
        d->nans++;
        bits = 0x7FF8000000000000ull;
    } else {
        memcpy(&bits, &v, sizeof bits);
    }
    dg_word(d, bits, 8);
}

static void dg_real(digest *d, ls_real v)
{
#if LS_REAL_IS_FLOAT
    dg_f32(d, v);
#else
    dg_f64(d, v);
#endif
}

static void dg_str(digest *d, const char *s)
{
    size_t n = s != NULL ? strlen(s) : 0, i;
    dg_word(d, (uint64_t)n, 8);
    for (i = 0; i < n; i++) dg_byte(d, (unsigned char)s[i]);
}

/* A fixed pseudo-random sequence for inputs (the 32-bit LCG of Numerical
 * Recipes): the same numbers on every target. */
static uint32_t dg_lcg(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state;
}

/* The arena every entry may use (MCU profile: keep it small). */
#define DG_ARENA_BYTES (96u * 1024u) /* the ldlt entry takes 80 KiB in double, PNG decoding 22 KiB */
static LS_ARENA_BUFFER(dg_arena, DG_ARENA_BYTES);

/* ---- core and status ------------------------------------------------- */

static void dg_core(digest *d)
{
    ls_build_info info;
    ls_build_info_get(&info);
    dg_u32(d, ls_version());
    dg_str(d, ls_version_string());
    dg_u32(d, info.real_bytes);
    dg_u32(d, info.arena_align);
    dg_str(d, info.real_name);
    dg_status(d, ls_selftest(sizeof(ls_real)));
    dg_status(d, ls_selftest(sizeof(ls_real) == 4 ? 8 : 4));
}

static void dg_status_text(digest *d)
{
    ls_status s;
    ls_diag diag;
    /* The names only: the messages of ls_status_str are compiled out by
     * -DLS_NO_STATUS_STRINGS (the clang variant of `make test`), which must
     * print the same digest; tests/test_core.c checks the messages. */
    for (s = -2; s <= LS_STATUS_COUNT + 1; s++) {
        dg_status(d, s);
        dg_str(d, ls_status_name(s));
    }
    memset(&diag, 0x5A, sizeof diag);
    ls_diag_clear(&diag);
    dg_status(d, diag.status);
    dg_u32(d, diag.has_line);
    dg_u64(d, diag.offset);
    dg_real(d, diag.value);
    dg_str(d, diag.what);
}

/* ---- arena ------------------------------------------------------------ */

/* Sizing arithmetic on sizes that fit 32 bits (the same on every target),
 * plus overflows that overflow everywhere. */
static void dg_arena_sizing(digest *d)
{
    uint32_t seed = 7u;
    int round;
    for (round = 0; round < 64; round++) {
        ls_size a, b;
        size_t bytes = 0;
        int k;
        ls_size_init(&a);
        ls_size_init(&b);
        for (k = 0; k < 1 + round % 7; k++) {
            size_t count = (size_t)(dg_lcg(&seed) >> 22);      /* 0..1023 */
            size_t elem = (size_t)(1u + (dg_lcg(&seed) >> 28)); /* 1..16 */
            ls_size_add(&a, count, elem);
            ls_size_add(&b, elem, (size_t)k + 1u);
        }
        ls_size_max(&b, &a);
        ls_size_add_size(&a, &b);
        dg_status(d, ls_size_get(&a, &bytes));
        dg_size(d, bytes);
        dg_status(d, ls_size_get(&b, &bytes));
        dg_size(d, bytes);
    }
    {
        ls_size big;
        size_t out = 1;
        ls_size_init(&big);
        ls_size_add(&big, SIZE_MAX, 2);
        dg_status(d, ls_size_get(&big, &out));
        dg_size(d, out);
        dg_status(d, ls_size_mul(SIZE_MAX / 2 + 1, 2, &out));
        dg_status(d, ls_size_sum(SIZE_MAX, 1, &out));
        dg_status(d, ls_size_mul(1000, 1000, &out));
        dg_size(d, out);
        dg_status(d, ls_size_sum(4000000, 96, &out));
        dg_size(d, out);
    }
}

/* A script of allocations, scratch and restores in a 4 KiB arena: offsets
 * from the base, use, peak and the `need` of failed requests. */
static void dg_arena_script(digest *d)
{
    ls_arena arena;
    uint32_t seed = 11u;
    int step;
    dg_status(d, ls_arena_init(&arena, dg_arena.bytes, 4096));
    dg_status(d, ls_arena_init(&arena, dg_arena.bytes + 4, 64));
    dg_status(d, ls_arena_init(&arena, dg_arena.bytes, 4096));
    for (step = 0; step < 200; step++) {
        uint32_t r = dg_lcg(&seed);
        size_t count = (size_t)((r >> 8) % 300u), elem = (size_t)(1u + (r >> 28));
        ls_arena_mark mark = ls_arena_save(&arena);
        unsigned char *p;
        if ((r & 3u) == 0) {
            p = (unsigned char *)ls_arena_scratch(&arena, count, elem);
        } else {
            p = (unsigned char *)ls_arena_alloc(&arena, count, elem);
        }
        dg_u32(d, p == NULL ? 0u : 1u);
        dg_size(d, p == NULL ? 0u : (size_t)(p - dg_arena.bytes));
        dg_size(d, ls_arena_used(&arena));
        dg_size(d, ls_arena_available(&arena));
        dg_size(d, arena.peak);
        dg_size(d, arena.need);
        if ((r & 0x30u) == 0x30u) ls_arena_restore(&arena, mark);
        if (step % 50 == 49) {
            ls_arena_restore(&arena, ls_arena_save(&arena));
            ls_arena_reset_peak(&arena);
            dg_status(d, ls_arena_init(&arena, dg_arena.bytes, 4096));
        }
    }
}

/* ---- math --------------------------------------------------------------- */
#if DIGEST_MATH
/* The functions of the build's ls_real (largesteps/math.h's LS_R* macros). */
#define DG_SIN(x) LS_RSIN(x)
#define DG_COS(x) LS_RCOS(x)
#define DG_ATAN(x) LS_RATAN(x)
#define DG_EXP(x) LS_REXP(x)
#define DG_LOG(x) LS_RLOG(x)
#define DG_LOG10(x) LS_RLOG10(x)
#define DG_ATAN2(y, x) LS_RATAN2((y), (x))
#define DG_POW(x, y) LS_RPOW((x), (y))

/* Special inputs every function sees: signed zeros, a subnormal, tiny, huge,
 * infinities, a NaN, +-1 and 0.5. */
static ls_real dg_special(int i)
{
    volatile ls_real zero = (ls_real)0;
    const ls_real inf = LS_REAL_MAX * (ls_real)2;
    switch (i) {
    case 0: return zero;
    case 1: return -zero;
    case 2: return LS_REAL_EPSILON * LS_REAL_EPSILON * LS_REAL_EPSILON * LS_REAL_EPSILON; /* tiny */
    case 3: return LS_REAL_MAX;
    case 4: return -LS_REAL_MAX;
    case 5: return inf;
    case 6: return -inf;
    case 7: return inf - inf; /* NaN */
    case 8: return (ls_real)1;
    case 9: return (ls_real)-1;
    case 10: return (LS_REAL_IS_FLOAT ? (ls_real)FLT_MIN : (ls_real)DBL_MIN) / (ls_real)4; /* subnormal */
    default: return (ls_real)0.5;
    }
}
#define DG_SPECIALS 12

/* Input k of a sweep: k/denominator exactly (an integer over a power of two),
 * then pseudo-random values scaled by 2^-shift. */
static ls_real dg_grid(int k, int denominator)
{
    return (ls_real)k / (ls_real)denominator;
}

static ls_real dg_random(uint32_t *seed, ls_real scale)
{
    int32_t r = (int32_t)(dg_lcg(seed) >> 8) - (1 << 23); /* |r| < 2^23: exact in float */
    return (ls_real)r * scale;
}

typedef ls_real (*dg_fn1)(ls_real);

static void dg_sweep1(digest *d, dg_fn1 f, int lo, int hi, int den, ls_real random_scale, int randoms)
{
    uint32_t seed = 12345u;
    int k;
    for (k = 0; k < DG_SPECIALS; k++) dg_real(d, f(dg_special(k)));
    for (k = lo; k <= hi; k++) dg_real(d, f(dg_grid(k, den)));
    for (k = 0; k < randoms; k++) dg_real(d, f(dg_random(&seed, random_scale)));
}

static ls_real dg_sin1(ls_real x) { return DG_SIN(x); }
static ls_real dg_cos1(ls_real x) { return DG_COS(x); }
static ls_real dg_exp1(ls_real x) { return DG_EXP(x); }
static ls_real dg_log1(ls_real x) { return DG_LOG(x); }
static ls_real dg_atan1(ls_real x) { return DG_ATAN(x); }
static ls_real dg_log101(ls_real x) { return DG_LOG10(x); }

/* 2^-23 * |r| < 1: random scales below are range / 2^23. */
#define DG_SCALE(range) ((ls_real)(range) / (ls_real)8388608)

static void dg_math_sin(digest *d) { dg_sweep1(d, dg_sin1, -1024, 1024, 64, DG_SCALE(100000), 1000); }
static void dg_math_cos(digest *d) { dg_sweep1(d, dg_cos1, -1024, 1024, 64, DG_SCALE(100000), 1000); }
static void dg_math_exp(digest *d) { dg_sweep1(d, dg_exp1, -1600, 1600, 16, DG_SCALE(90), 1000); }
static void dg_math_atan(digest *d) { dg_sweep1(d, dg_atan1, -1024, 1024, 32, DG_SCALE(1000), 500); }
static void dg_math_log10(digest *d) { dg_sweep1(d, dg_log101, 1, 2048, 16, DG_SCALE(1000000), 500); }

/* Rounding and the clamped float-to-integer conversions, whose plain C casts
 * differ between x86 and ARM out of range: halves, large and huge values. */
static void dg_math_rounding(digest *d)
{
    int k;
    for (k = 0; k < DG_SPECIALS + 260; k++) {
        ls_real x;
        if (k < DG_SPECIALS) {
            x = dg_special(k);
        } else if (k < DG_SPECIALS + 130) {
            x = dg_grid(k - DG_SPECIALS - 65, 4); /* -16.25 .. 16 in quarters */
        } else {
            int e = (k - DG_SPECIALS - 130) / 2, j; /* +-2^e, e = 0..64 */
            x = (k & 1) ? (ls_real)-1 : (ls_real)1;
            for (j = 0; j < e; j++) x *= (ls_real)2;
            x += (k & 2) ? (ls_real)0.5 : (ls_real)0;
        }
        dg_real(d, LS_RFLOOR(x));
        dg_real(d, LS_RCEIL(x));
        dg_real(d, LS_RTRUNC(x));
        dg_real(d, LS_RROUND(x));
        dg_u32(d, (uint32_t)LS_RTO_I32(x));
        dg_u32(d, LS_RTO_U32(x));
        dg_u64(d, (uint64_t)LS_RTO_I64(x));
    }
}

static void dg_math_log(digest *d)
{
    uint32_t seed = 99u;
    int k;
    dg_sweep1(d, dg_log1, -16, 2048, 256, DG_SCALE(1000), 500);
    /* positive values across the exponent range: m * 2^e, e from -60 to 60 */
    for (k = 0; k < 500; k++) {
        ls_real m = (ls_real)1 + (ls_real)(dg_lcg(&seed) >> 9) / (ls_real)8388608;
        int e = (int)(dg_lcg(&seed) >> 25) - 60, j;
        for (j = 0; j < e; j++) m *= (ls_real)2;
        for (j = 0; j > e; j--) m *= (ls_real)0.5;
        dg_real(d, DG_LOG(m));
    }
}

static void dg_math_atan2(digest *d)
{
    int i, j;
    for (i = 0; i < DG_SPECIALS; i++)
        for (j = 0; j < DG_SPECIALS; j++) dg_real(d, DG_ATAN2(dg_special(i), dg_special(j)));
    for (i = -24; i <= 24; i++)
        for (j = -24; j <= 24; j++) dg_real(d, DG_ATAN2(dg_grid(i, 6), dg_grid(j, 6)));
}

static void dg_math_pow(digest *d)
{
    int i, j;
    for (i = 0; i < DG_SPECIALS; i++)
        for (j = 0; j < DG_SPECIALS; j++) dg_real(d, DG_POW(dg_special(i), dg_special(j)));
    for (i = -8; i <= 40; i++)       /* x = i/8: negatives, 0, fractions, up to 5 */
        for (j = -20; j <= 20; j++)  /* y = j/4: integers and quarters */
            dg_real(d, DG_POW(dg_grid(i, 8), dg_grid(j, 4)));
}
#endif /* DIGEST_MATH */

/* ---- the table ---------------------------------------------------------- */

/* ---- images: encoders and decoders ------------------------------------ */

/* A write callback that hashes the bytes it is given (no output buffer). */
static int32_t dg_sink(void *user, const void *data, size_t bytes)
{
    digest *d = (digest *)user;
    const unsigned char *p = (const unsigned char *)data;
    size_t i;
    for (i = 0; i < bytes; i++) dg_byte(d, p[i]);
    d->count += bytes;
    return 0;
}

/* 29 x 17 pixels: values spread over [-0.03, 1.04] so that clamping and
 * halfway rounding occur, plus 0.5, -1 and a NaN. */
static int dg_synthetic_image(ls_image *img, ls_arena *a)
{
    uint32_t i, n;
    if (ls_image_create(img, 29, 17, a) != LS_OK) return 0;
    n = 4u * img->width * img->height;
    for (i = 0; i < n; i++) img->pixels[i] = (float)((i * 2654435761u) % 70001u) / 65535.0f - 0.03f;
    img->pixels[5] = 0.5f;
    img->pixels[6] = -1.0f;
    memcpy(&img->pixels[7], &(uint32_t){0x7fc00000u}, 4);
    return 1;
}

/* PNG as stored blocks: the compressor's state (282 KiB) does not fit
 * the MCU profile's arena; its bytes are pinned by tests/test_image.c
 * (png_deflate_bytes_are_pinned), which every target runs. */
static void dg_image_encode(digest *d)
{
    static const ls_image_format formats[] = {
        {LS_IMAGE_PNG_STORED, 1, 8, 0}, {LS_IMAGE_PNG_STORED, 1, 16, 0}, {LS_IMAGE_PNG_STORED, 2, 8, 0},
        {LS_IMAGE_PNG_STORED, 3, 8, 0}, {LS_IMAGE_PNG_STORED, 3, 16, 0}, {LS_IMAGE_PNG_STORED, 4, 8, 0},
        {LS_IMAGE_PNG_STORED, 4, 16, 0}, {LS_IMAGE_PNM, 1, 8, 0},
        {LS_IMAGE_PNM, 3, 16, 0}, {LS_IMAGE_PFM, 3, 32, 0}, {LS_IMAGE_PFM, 1, 32, 1}};
    ls_arena a;
    ls_image img;
    size_t i;
    ls_arena_init(&a, dg_arena.bytes, sizeof dg_arena.bytes);
    if (!dg_synthetic_image(&img, &a)) return;
    for (i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        size_t file_bytes = 0;
        dg_status(d, ls_image_encoded_size(img.width, img.height, &formats[i], &file_bytes));
        dg_size(d, file_bytes);
        dg_status(d, ls_image_encode(&img, &formats[i], dg_sink, d, &a));
    }
}

static void dg_image_decode(digest *d)
{
    static const ls_image_format formats[] = {{LS_IMAGE_PNG_STORED, 4, 16, 0}, {LS_IMAGE_PNG_STORED, 3, 8, 0}, {LS_IMAGE_PNM, 1, 16, 0},
                                              {LS_IMAGE_PFM, 3, 32, 1}};
    ls_arena a;
    ls_image img;
    size_t i, k;
    ls_status st;
    ls_arena_init(&a, dg_arena.bytes, sizeof dg_arena.bytes);
    if (!dg_synthetic_image(&img, &a)) return;
    for (i = 0; i < sizeof formats / sizeof formats[0]; i++) {
        ls_arena_mark mark = ls_arena_save(&a);
        ls_membuf mb;
        ls_image back;
        size_t file_bytes = 0;
        ls_image_encoded_size(img.width, img.height, &formats[i], &file_bytes);
        mb.data = (unsigned char *)ls_arena_alloc(&a, file_bytes, 1);
        mb.capacity = file_bytes;
        mb.size = 0;
        mb.overflow = 0;
        if (mb.data == NULL || ls_image_encode(&img, &formats[i], ls_membuf_write, &mb, &a) != LS_OK) {
            dg_status(d, LS_ERR_NOMEM);
            ls_arena_restore(&a, mark);
            continue;
        }
        st = ls_image_decode(mb.data, mb.size, &back, &a, NULL);
        dg_status(d, st);
        if (st == LS_OK)
            for (k = 0; k < 4u * (size_t)back.width * back.height; k++) dg_f32(d, back.pixels[k]);
        ls_arena_restore(&a, mark);
    }
}

/* ---- numbers and meshes ------------------------------------------------ */

static void dg_number(digest *d)
{
    static const char *const texts[] = {"0", "-0", "1", "0.1", "3.14159265358979323846", "1e308", "1.7976931348623157e308",
                                        "1.7976931348623159e308", "2.2250738585072011e-308", "4.9e-324", "2.4e-324",
                                        "1e-400", "123456789012345678901234567890", "0.30000000000000004",
                                        "3.4028235e38", "3.4028236e38", "1.17549435e-38", "1.4e-45", "7e-46",
                                        "16777217", "9007199254740993", "inf", "-Infinity", "nan", "3.1+e2", "1e",
                                        ".", "", "+.5", "-.5e-3"};
    size_t i;
    char buf[40];
    uint32_t seed = 7u;
    for (i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        double x = 0;
        float f = 0;
        size_t len = strlen(texts[i]);
        dg_status(d, ls_parse_double(texts[i], len, &x));
        dg_f64(d, x);
        dg_status(d, ls_parse_float(texts[i], len, &f));
        dg_f32(d, f);
    }
    for (i = 0; i < 300; i++) { /* formatting of random bit patterns, and parsing back */
        uint32_t hi = dg_lcg(&seed), lo = dg_lcg(&seed);
        uint64_t bits = ((uint64_t)hi << 32) | lo;
        double x;
        float f;
        memcpy(&x, &bits, 8);
        memcpy(&f, &hi, 4);
        dg_size(d, ls_format_double(x, buf, sizeof buf));
        dg_str(d, buf);
        dg_size(d, ls_format_float(f, buf, sizeof buf));
        dg_str(d, buf);
    }
}

/* A small OBJ with quads, i/t/n and i//n corners, negative indices, CRLF
 * line ends, comments and skipped statements, no final newline. */
static const char dg_obj_text[] =
    "# digest mesh\r\nmtllib x.mtl\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
    "v 0.5 0.5 0.7071067811865476\r\nv 0.25 -0.125 1e-3\r\nvt 0 0\r\nvn 0 0 1\r\n"
    "f 1/1/1 4/1/1 3/1/1 2/1/1\r\nf 1//1 2//1 5//1\r\nf -4 -3 -2\r\ng part\r\nf 3 4 5\r\nf 4 1 5\r\n"
    "f 1 6 2\r\nf 6 1 2";

static void dg_mesh(digest *d)
{
    static const uint32_t weightings[3] = {LS_NORMALS_UNIFORM, LS_NORMALS_AREA, LS_NORMALS_ANGLE};
    ls_arena a;
    ls_mesh m;
    ls_diag diag;
    ls_mesh_report rep;
    ls_real *normals, lo[3], hi[3];
    uint32_t i, w;
    ls_status st;
    ls_arena_init(&a, dg_arena.bytes, sizeof dg_arena.bytes);
    st = ls_mesh_read(dg_obj_text, sizeof dg_obj_text - 1, LS_MESH_FORMAT_OBJ, &a, &m, &diag);
    dg_status(d, st);
    if (st != LS_OK) return;
    dg_u32(d, m.vertex_count);
    dg_u32(d, m.face_count);
    for (i = 0; i < 3 * m.vertex_count; i++) dg_real(d, m.positions[i]);
    for (i = 0; i < 3 * m.face_count; i++) dg_u32(d, m.triangles[i]);
    normals = (ls_real *)ls_arena_alloc(&a, 3 * (size_t)(m.vertex_count > m.face_count ? m.vertex_count : m.face_count),
                                        sizeof(ls_real));
    if (normals == NULL) return;
    dg_status(d, ls_mesh_face_normals(&m, normals, NULL));
    for (i = 0; i < 3 * m.face_count; i++) dg_real(d, normals[i]);
    for (w = 0; w < 3; w++) {
        dg_status(d, ls_mesh_vertex_normals(&m, weightings[w], normals, NULL));
        for (i = 0; i < 3 * m.vertex_count; i++) dg_real(d, normals[i]);
    }
    dg_status(d, ls_mesh_bounds(&m, lo, hi));
    for (i = 0; i < 3; i++) {
        dg_real(d, lo[i]);
        dg_real(d, hi[i]);
    }
    dg_status(d, ls_mesh_validate(&m, &a, &rep));
    dg_u32(d, (uint32_t)rep.boundary_edges);
    dg_u32(d, (uint32_t)rep.components);
    dg_status(d, ls_mesh_write_obj(&m, dg_sink, d));
    dg_status(d, ls_mesh_write_ply(&m, dg_sink, d));
}

/* ---- primitives ------------------------------------------------------- */

/* Icosphere of level 2 (162 vertices) and a 5 x 3 grid: every position and index. */
static void dg_primitive(digest *d)
{
    ls_arena arena;
    ls_mesh m;
    uint32_t i;
    dg_status(d, ls_arena_init(&arena, dg_arena.bytes, sizeof dg_arena.bytes));
    dg_status(d, ls_icosphere(2, &arena, &m));
    for (i = 0; i < 3u * m.vertex_count; i++) dg_real(d, m.positions[i]);
    for (i = 0; i < 3u * m.face_count; i++) dg_u32(d, m.triangles[i]);
    dg_status(d, ls_grid_mesh(5, 3, &arena, &m));
    for (i = 0; i < 3u * m.vertex_count; i++) dg_real(d, m.positions[i]);
    for (i = 0; i < 3u * m.face_count; i++) dg_u32(d, m.triangles[i]);
}

/* ---- scenes ------------------------------------------------------------ */

/* A text scene (look-at camera, Fibonacci and ring views) and a Mitsuba
 * sensor with rotate/translate/lookat: every camera's view matrix and fov. */
static void dg_scene(digest *d)
{
    static const char text[] = "largesteps-scene 1\nresolution 64 48\nfov 50 y\ncamera 0.3 0.2 4 0 0.1 0 0 1 0\n"
                               "views fibonacci 5 3.5 0.1 -0.2 0.3\nviews rings 2 3 2\ntarget mesh t.obj\n";
    static const char xml[] = "<scene><sensor type=\"perspective\"><float name=\"fov\" value=\"39.3\"/>"
                              "<transform name=\"to_world\"><rotate x=\"1\" y=\"0.5\" angle=\"33\"/>"
                              "<translate x=\"0.5\" z=\"4\"/><lookat origin=\"1 2 3\" target=\"0 0.5 0\"/>"
                              "</transform></sensor></scene>";
    ls_arena arena;
    ls_scene s;
    uint32_t c, k;
    int pass;
    for (pass = 0; pass < 2; pass++) {
        dg_status(d, ls_arena_init(&arena, dg_arena.bytes, sizeof dg_arena.bytes));
        s.camera_count = 0;
        dg_status(d, pass == 0 ? ls_scene_parse(text, sizeof text - 1, &arena, &s, NULL)
                               : ls_scene_parse_mitsuba(xml, sizeof xml - 1, &arena, &s, NULL));
        dg_u32(d, s.camera_count);
        for (c = 0; c < s.camera_count; c++) {
            for (k = 0; k < 16; k++) dg_real(d, s.cameras[c].view[k]);
            dg_real(d, s.cameras[c].fov);
        }
    }
}

/* ---- the fit loop ---------------------------------------------------------- */

/* 20 iterations of large steps: an icosahedron fitted to renders of an
 * ellipsoid (icosphere level 1) from 2 framed views at 8 x 8, SH shading:
 * the loss of every iteration and the final vertices. */
/* A parallel-for for the digest: the tasks on this thread, last first, on
 * worker numbers that rotate (any order and any worker must give the same
 * bits). */
static void dg_scrambled_for(void *ctx, uint32_t count, ls_task_fn task, void *arg)
{
    const uint32_t workers = *(const uint32_t *)ctx;
    uint32_t i;
    for (i = count; i-- > 0;) task(arg, i, (i * 7u + 1u) % workers);
}

static void dg_fit_run(digest *d, uint32_t workers)
{
    static const ls_real sh[27] = {(ls_real)1.6, (ls_real)0.8, (ls_real)0.4, (ls_real)-0.3, 0, 0, 0, 0, 0,
                                   (ls_real)1.6, (ls_real)0.8, (ls_real)0.4, (ls_real)-0.3, 0, 0, 0, 0, 0,
                                   (ls_real)1.5, (ls_real)0.8, (ls_real)0.4, (ls_real)-0.3, 0, 0, 0, 0, 0};
    ls_arena arena;
    ls_mesh target, init, out;
    ls_camera_framing fr;
    ls_vis vis;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_real mvp[32], dirs[6], *img[2], *normals, *pos;
    const ls_real *targets[2];
    uint32_t i, k;
    dg_status(d, ls_arena_init(&arena, dg_arena.bytes, sizeof dg_arena.bytes));
    dg_status(d, ls_icosphere(1, &arena, &target));
    for (i = 0; i < target.vertex_count; i++) {
        target.positions[3 * i] *= (ls_real)1.3;
        target.positions[3 * i + 1] *= (ls_real)0.8;
    }
    ls_fit_config_default(&c);
    c.width = c.height = 8;
    c.shading.mode = LS_SHADE_SH;
    c.shading.sh = sh;
    c.optim.lr = (ls_real)0.01;
    c.workers = workers;
    c.parallel.run = workers > 1u ? dg_scrambled_for : NULL;
    c.parallel.ctx = &workers;
    dg_status(d, ls_camera_frame(target.positions, target.vertex_count, (ls_real)0.8, LS_FOV_X, 1, (ls_real)1.1, &fr, NULL));
    dg_status(d, ls_camera_fibonacci_dirs(2, dirs));
    normals = (ls_real *)ls_arena_alloc(&arena, 3u * target.vertex_count, sizeof(ls_real));
    for (k = 0; k < 2; k++) {
        dg_status(d, ls_camera_framed_view(&fr, dirs + 3 * k, NULL, mvp + 16 * k));
        img[k] = (ls_real *)ls_arena_alloc(&arena, 4u * 64u, sizeof(ls_real));
        targets[k] = img[k];
    }
    {
        ls_arena_mark mark = ls_arena_save(&arena);
        dg_status(d, ls_shade_vertex_normals(target.positions, target.vertex_count, target.triangles, target.face_count,
                                             normals, NULL));
        dg_status(d, ls_vis_init(&vis, &arena, 8, 8, 2, target.vertex_count));
        for (k = 0; k < 2; k++) {
            dg_status(d, ls_raster(&vis, &(ls_view){.positions = target.positions, .indices = target.triangles,
                    .triangle_count = target.face_count, .vertex_count = target.vertex_count, .mvp = mvp + 16 * k},
                    &arena, NULL));
            dg_status(d, ls_shade(&(ls_view){.vis = &vis, .indices = target.triangles,
                    .triangle_count = target.face_count, .vertex_count = target.vertex_count, .normals = normals,
                    .opts = &c.shading}, img[k], NULL));
        }
        ls_arena_restore(&arena, mark);
    }
    dg_status(d, ls_icosphere(0, &arena, &init));
    views.count = 2;
    views.mvp = mvp;
    views.targets = targets;
    dg_status(d, ls_fit_init(&fit, &c, &views, &init, &arena, NULL));
    for (i = 0; i < 20; i++) {
        dg_status(d, ls_fit_step(&fit, NULL, NULL));
        dg_real(d, fit.loss);
    }
    pos = (ls_real *)ls_arena_alloc(&arena, 3u * init.vertex_count, sizeof(ls_real));
    dg_status(d, pos == NULL ? LS_ERR_NOMEM : ls_fit_mesh(&fit, pos, &out));
    for (i = 0; pos != NULL && i < 3u * init.vertex_count; i++) dg_real(d, pos[i]);
}

static void dg_fit(digest *d) { dg_fit_run(d, 1); }
/* The same fit with 3 workers: the same hash as "fit". */
static void dg_fit_workers(digest *d) { dg_fit_run(d, 3); }

/* Entries of the later modules, one file each (tests/digest_NAME.inc, owned
 * by the module): it defines its static dg_ functions and a macro
 * DG_ENTRIES_NAME expanding to its rows of `entries` (empty when it has none). */
#include "digest_laplacian.inc"
#include "digest_optim.inc"
#include "digest_distance.inc"
#include "digest_remesh.inc"
#include "digest_render.inc"
#include "digest_gradient.inc"
#include "digest_grid.inc"
#include "digest_texture.inc"

typedef struct digest_entry {
    const char *name;
    void (*run)(digest *d);
    const char *what;
} digest_entry;

static const digest_entry entries[] = {
    {"core.build", dg_core, "ls_version, version string, real size, arena alignment, selftest (own and other ls_real)"},
    {"status.text", dg_status_text, "ls_status_name of codes -2..LS_STATUS_COUNT+1, ls_diag_clear"},
    {"arena.sizing", dg_arena_sizing, "ls_size_add/max/add_size/get on 64 random request lists; overflow cases"},
    {"arena.script", dg_arena_script, "200 random alloc/scratch/restore steps in 4 KiB: offsets, used, available, peak, need"},
#if DIGEST_MATH
    {"math.sin", dg_math_sin, "sin: specials, k/64 for |k|<=1024, 1000 random in +-1e5"},
    {"math.cos", dg_math_cos, "cos: specials, k/64 for |k|<=1024, 1000 random in +-1e5"},
    {"math.atan", dg_math_atan, "atan: specials, k/32 for |k|<=1024, 500 random in +-1000"},
    {"math.exp", dg_math_exp, "exp: specials, k/16 for |k|<=1600, 1000 random in +-90"},
    {"math.log", dg_math_log, "log: specials, k/256 for -16<=k<=2048, 500 random in +-1000, 500 m*2^e, |e|<=60"},
    {"math.log10", dg_math_log10, "log10: specials, k/16 for 1<=k<=2048, 500 random in +-1e6"},
    {"math.atan2", dg_math_atan2, "atan2: specials x specials, (i/6, j/6) for |i|,|j|<=24"},
    {"math.pow", dg_math_pow, "pow: specials x specials, x=i/8 (-8<=i<=40) x y=j/4 (|j|<=20)"},
    {"image.encode", dg_image_encode, "29x17 synthetic RGBA (clamping, halves, NaN): PNG g8/g16/ga8/rgb8/rgb16/rgba8/rgba16, PGM8, PPM16, PFM rgb LE, grey BE: sizes and bytes"},
    {"image.decode", dg_image_decode, "the same image encoded as PNG rgba16, rgb8, PGM16, PFM BE and decoded back: float pixels"},
    {"number", dg_number, "parse double/float of 30 texts (hard cases, errors), format of 300 random double/float bit patterns"},
    {"mesh", dg_mesh, "OBJ with quads, i/t/n, negative indices, CRLF: positions, triangles, face and vertex normals (3 weightings), bounds, validation, OBJ/PLY bytes"},
    {"math.rounding", dg_math_rounding, "floor, ceil, trunc, round, to_i32/u32/i64: specials, k/4, +-2^e(+0.5), e<=64"},
    {"primitive", dg_primitive, "icosphere level 2, grid 5x3: positions and indices"},
    {"scene", dg_scene, "text scene (look-at, Fibonacci, rings) and Mitsuba sensor (rotate, translate, lookat): views, fovs"},
    {"fit", dg_fit, "20 large-steps iterations, icosahedron to an ellipsoid, 2 views at 8x8, SH: losses, vertices"},
    {"fit.workers", dg_fit_workers, "the same with 3 workers, the views' tasks in another order: the same hash as fit"},
    DG_ENTRIES_LAPLACIAN
    DG_ENTRIES_OPTIM
    DG_ENTRIES_DISTANCE
    DG_ENTRIES_REMESH
    DG_ENTRIES_RENDER
    DG_ENTRIES_GRADIENT
    DG_ENTRIES_GRID
    DG_ENTRIES_TEXTURE
#endif
};

static void print_line(const char *name, const digest *d, const char *what)
{
    printf("%-16s n=%-6lu nan=%-5lu %08lx%08lx  %s\n", name, (unsigned long)d->count,
           (unsigned long)d->nans, (unsigned long)(d->hash >> 32),
           (unsigned long)(d->hash & 0xFFFFFFFFu), what);
}

int main(void)
{
    digest all;
    size_t i;
    all.hash = DG_FNV_OFFSET;
    all.count = 0;
    all.nans = 0;
    (void)dg_f32; /* both exist in both builds; entries may hash either type */
    (void)dg_f64;
    printf("# largesteps digest, ls_real = %s\n", LS_REAL_NAME);
    for (i = 0; i < sizeof entries / sizeof entries[0]; i++) {
        digest d;
        d.hash = DG_FNV_OFFSET;
        d.count = 0;
        d.nans = 0;
        entries[i].run(&d);
        print_line(entries[i].name, &d, entries[i].what);
        dg_str(&all, entries[i].name);
        dg_u64(&all, d.hash);
        all.nans += d.nans;
    }
    print_line("all", &all, "the names and hashes of every entry above");
    fflush(stdout);
    return 0;
}
