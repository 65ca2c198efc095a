/* tests/test_mask.c - distances in an image's mask (mask.h) against a brute
 * force over every pair of pixels, the inscribed radius of shapes whose
 * radius is known, exact bytes and the errors. */
#include "test.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SIDE 40u
#define BUF_BYTES (1u << 20)
static unsigned char *buf;
static ls_real img[4u * MAX_SIDE * MAX_SIDE];
static ls_real dist[MAX_SIDE * MAX_SIDE];
static uint32_t lcg = 12345u;

static uint32_t next(void)
{
    lcg = lcg * 1664525u + 1013904223u;
    return lcg >> 8;
}

/* Blobs: each pixel's alpha one of 0, 0.25, 0.5, 0.75, 1, clustered so that
 * both kinds of pixel form regions of several pixels. */
static void random_mask(uint32_t w, uint32_t h)
{
    uint32_t x, y, b;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) img[4u * (y * w + x) + 3u] = (ls_real)0;
    for (b = 0; b < 3u; b++) {
        const uint32_t cx = next() % w, cy = next() % h, r = 1u + next() % 6u;
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                const long dx = (long)x - (long)cx, dy = (long)y - (long)cy;
                if (dx * dx + dy * dy <= (long)(r * r)) img[4u * (y * w + x) + 3u] = (ls_real)0.25 * (ls_real)(next() % 5u);
            }
    }
}

/* The distance from every pixel to the nearest pixel whose alpha is
 * (to_background ? at most : above) threshold, by trying them all. */
static double brute(uint32_t w, uint32_t h, uint32_t x, uint32_t y, ls_real threshold, uint32_t to_background)
{
    double best = 1e10;
    uint32_t i, j;
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            const int above = img[4u * (j * w + i) + 3u] > threshold;
            const double dx = (double)i - (double)x, dy = (double)j - (double)y, d = sqrt(dx * dx + dy * dy);
            if ((to_background ? !above : above) && d < best) best = d;
        }
    return best;
}

static void against_brute_force(void)
{
    static const uint32_t sizes[][2] = {{1, 1}, {1, 7}, {9, 1}, {13, 5}, {37, 29}, {40, 40}};
    ls_arena arena;
    uint32_t s, trial, mode, x, y;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (trial = 0; trial < 4u; trial++) {
            const uint32_t w = sizes[s][0], h = sizes[s][1];
            random_mask(w, h);
            for (mode = 0; mode < 4u; mode++) {
                const ls_real threshold = mode < 2u ? (ls_real)0 : (ls_real)0.5;
                const uint32_t to_background = mode % 2u;
                CHECK_EQ(ls_mask_distance(img, w, h, threshold, to_background, dist, &arena, NULL), LS_OK);
                for (y = 0; y < h; y++)
                    for (x = 0; x < w; x++) {
                        const double want = brute(w, h, x, y, threshold, to_background);
                        CHECK_NEAR((double)dist[y * w + x], want, want * TEST_EPS(4));
                    }
            }
            CHECK_EQ(ls_arena_used(&arena), 0u);
        }
}

/* alpha 1 inside the disc of radius r about (cx, cy) (pixel centres). */
static void disc(uint32_t w, uint32_t h, double cx, double cy, double r)
{
    uint32_t x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            const double dx = x - cx, dy = y - cy;
            img[4u * (y * w + x) + 3u] = dx * dx + dy * dy <= r * r ? (ls_real)1 : (ls_real)0;
        }
}

/* The largest distance from a pixel above 0.5 to the nearest pixel not above
 * or beyond the image, by trying them all. */
static double brute_radius(uint32_t w, uint32_t h)
{
    double best = 0;
    uint32_t x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double d = brute(w, h, x, y, (ls_real)0.5, 1);
            const double edge[4] = {x + 1.0, y + 1.0, (double)(w - x), (double)(h - y)};
            uint32_t k;
            for (k = 0; k < 4u; k++)
                if (edge[k] < d) d = edge[k];
            if (img[4u * (y * w + x) + 3u] > (ls_real)0.5 && d > best) best = d;
        }
    return best;
}

static void inscribed_radius(void)
{
    ls_arena arena;
    ls_real r = -1;
    uint32_t x, y;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    /* a disc of radius 12 on the pixel lattice, against every pair of pixels */
    disc(40, 40, 19.5, 20, 12);
    CHECK_EQ(ls_mask_inscribed_radius(img, 40, 40, &arena, &r, NULL), LS_OK);
    CHECK_NEAR((double)r, brute_radius(40, 40), 12 * TEST_EPS(4));
    CHECK(r > (ls_real)11 && r <= (ls_real)12);
    /* random blobs */
    for (x = 0; x < 8u; x++) {
        random_mask(37, 29);
        CHECK_EQ(ls_mask_inscribed_radius(img, 37, 29, &arena, &r, NULL), LS_OK);
        CHECK_NEAR((double)r, brute_radius(37, 29), 40 * TEST_EPS(4));
    }
    /* a line one pixel thick, then a bar three thick (alpha 0.75: above 0.5) */
    for (y = 0; y < 20u; y++)
        for (x = 0; x < 30u; x++) img[4u * (y * 30u + x) + 3u] = y == 9u && x > 2u && x < 27u ? (ls_real)1 : (ls_real)0;
    CHECK_EQ(ls_mask_inscribed_radius(img, 30, 20, &arena, &r, NULL), LS_OK);
    CHECK_EQ(r, (ls_real)1);
    for (y = 0; y < 20u; y++)
        for (x = 0; x < 30u; x++)
            img[4u * (y * 30u + x) + 3u] = y >= 8u && y <= 10u && x > 2u && x < 27u ? (ls_real)0.75 : (ls_real)0.5;
    CHECK_EQ(ls_mask_inscribed_radius(img, 30, 20, &arena, &r, NULL), LS_OK);
    CHECK_EQ(r, (ls_real)2);
    /* the whole image inside: the pixels beyond it are the background */
    for (y = 0; y < 7u * 5u; y++) img[4u * y + 3u] = (ls_real)1;
    CHECK_EQ(ls_mask_inscribed_radius(img, 5, 7, &arena, &r, NULL), LS_OK);
    CHECK_EQ(r, (ls_real)3);
    /* nothing inside */
    for (y = 0; y < 7u * 5u; y++) img[4u * y + 3u] = (ls_real)0.5;
    CHECK_EQ(ls_mask_inscribed_radius(img, 5, 7, &arena, &r, NULL), LS_OK);
    CHECK_EQ(r, (ls_real)0);
    CHECK_EQ(ls_arena_used(&arena), 0u);
}

/* The sizes are exact: one byte less fails with LS_ERR_NOMEM, leaving the arena as it was. */
static void exact_bytes(void)
{
    size_t line = 0, field = 0;
    ls_arena arena;
    ls_real r = -1;
    ls_diag d;
    REQUIRE(ls_mask_distance_bytes(37, 29, &line, &field) == LS_OK);
    CHECK(line > 0 && field >= 37u * 29u * sizeof(ls_real));
    random_mask(37, 29);
    REQUIRE(ls_arena_init(&arena, buf, line) == LS_OK);
    CHECK_EQ(ls_mask_distance(img, 37, 29, (ls_real)0, 0, dist, &arena, NULL), LS_OK);
    REQUIRE(ls_arena_init(&arena, buf, line - 1u) == LS_OK);
    CHECK_EQ(ls_mask_distance(img, 37, 29, (ls_real)0, 0, dist, &arena, &d), LS_ERR_NOMEM);
    CHECK(strstr(d.what, "ls_mask_distance_bytes") != NULL);
    CHECK_EQ(ls_arena_used(&arena), 0u);
    REQUIRE(ls_arena_init(&arena, buf, line + field) == LS_OK);
    CHECK_EQ(ls_mask_inscribed_radius(img, 37, 29, &arena, &r, NULL), LS_OK);
    REQUIRE(ls_arena_init(&arena, buf, line + field - 1u) == LS_OK);
    CHECK_EQ(ls_mask_inscribed_radius(img, 37, 29, &arena, &r, NULL), LS_ERR_NOMEM);
    CHECK_EQ(ls_arena_used(&arena), 0u);
}

static void errors(void)
{
    ls_arena arena;
    size_t line, field;
    ls_real r;
    ls_diag d;
    REQUIRE(ls_arena_init(&arena, buf, BUF_BYTES) == LS_OK);
    CHECK_EQ(ls_mask_distance_bytes(0, 5, &line, &field), LS_ERR_INVALID);
    CHECK_EQ(ls_mask_distance_bytes(5, 65536, &line, &field), LS_ERR_INVALID);
    CHECK_EQ(ls_mask_distance_bytes(5, 5, NULL, &field), LS_ERR_INVALID);
    CHECK_EQ(ls_mask_distance(NULL, 5, 5, (ls_real)0, 0, dist, &arena, &d), LS_ERR_INVALID);
    CHECK_EQ(ls_mask_distance(img, 5, 0, (ls_real)0, 0, dist, &arena, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "width and height") != NULL);
    CHECK_EQ(ls_mask_distance(img, 5, 5, (ls_real)(1.0 / 0.0 * 0.0), 0, dist, &arena, &d), LS_ERR_INVALID);
    CHECK(strstr(d.what, "threshold") != NULL);
    CHECK_EQ(ls_mask_inscribed_radius(img, 5, 5, &arena, NULL, &d), LS_ERR_INVALID);
    CHECK_EQ(ls_mask_inscribed_radius(img, 5, 5, NULL, &r, &d), LS_ERR_INVALID);
    CHECK_EQ(ls_mask_inscribed_radius(NULL, 5, 5, &arena, &r, &d), LS_ERR_INVALID);
    CHECK_EQ(ls_arena_used(&arena), 0u);
}

int main(void)
{
    TEST_INIT("test_mask");
    buf = (unsigned char *)malloc(BUF_BYTES);
    if (buf == NULL) return 1;
    TEST_RUN(against_brute_force);
    TEST_RUN(inscribed_radius);
    TEST_RUN(exact_bytes);
    TEST_RUN(errors);
    free(buf);
    return TEST_END();
}
