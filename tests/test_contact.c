/* test_contact.c - contact sheets: the layout formula written out by hand,
 * every pixel of a sheet against an independent placement (which tile, which
 * pixel of it, or the separator), argument errors and the arena sweep. */
#include "test.h"
#include "sweep.h"
#include <stdlib.h>
#include <largesteps/contact.h>

static void layout_matches_the_formula(void)
{
    ls_contact g;
    uint32_t count;
    /* automatic columns: smallest c with c^2 >= count */
    static const uint32_t want_cols[17] = {0, 1, 2, 2, 2, 3, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4};
    for (count = 1; count <= 16; count++) {
        uint32_t c = want_cols[count], r = (count + c - 1) / c;
        REQUIRE(ls_contact_layout(count, 10, 7, 0, 1, &g) == LS_OK);
        CHECK_EQ(g.columns, c);
        CHECK_EQ(g.rows, r);
        CHECK_EQ(g.image.width, c * 10 + (c - 1));
        CHECK_EQ(g.image.height, r * 7 + (r - 1));
        CHECK(g.count == count && g.tile_w == 10 && g.tile_h == 7 && g.sep == 1 && g.image.pixels == NULL);
    }
    REQUIRE(ls_contact_layout(3, 5, 4, 3, 2, &g) == LS_OK);
    CHECK(g.columns == 3 && g.rows == 1 && g.image.width == 19 && g.image.height == 4);
    REQUIRE(ls_contact_layout(3, 5, 4, 1, 0, &g) == LS_OK);
    CHECK(g.columns == 1 && g.rows == 3 && g.image.width == 5 && g.image.height == 12);
    REQUIRE(ls_contact_layout(2, 5, 4, 9, 1, &g) == LS_OK); /* more columns than tiles */
    CHECK(g.columns == 2 && g.rows == 1 && g.image.width == 11 && g.image.height == 4);
    CHECK_STATUS(ls_contact_layout(0, 5, 4, 0, 1, &g), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_layout(2, 0, 4, 0, 1, &g), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_layout(2, 4, 0, 0, 1, &g), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_layout(2, 4, 4, 0, 1, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_layout(4, LS_IMAGE_MAX_SIDE, 1, 2, 0, &g), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_contact_layout(2, 1, 1, 2, UINT32_MAX, &g), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_contact_layout(UINT32_MAX, 4096, 4096, 0, 1, &g), LS_ERR_TOO_LARGE);
}

/* The value tile t holds at (x, y), channel k (both put functions use it). */
static float tile_value(uint32_t t, uint32_t x, uint32_t y, uint32_t k)
{
    return (float)(t * 1000u + y * 100u + x * 10u + k) / 8192.0f;
}

static void every_pixel_lands_in_its_cell(void)
{
    const uint32_t tw = 6, th = 4, count = 7, cols = 3, sep = 2;
    const float sepc[4] = {0.25f, 0.5f, 0.75f, 1.0f};
    size_t bytes, bad = 0;
    void *mem;
    ls_arena a;
    ls_contact s;
    ls_image tile;
    ls_real rgba[4 * 6 * 4];
    uint32_t t, x, y, k;
    REQUIRE(ls_contact_bytes(count, tw, th, cols, sep, &bytes) == LS_OK);
    mem = malloc(bytes + 4096);
    REQUIRE(ls_arena_init(&a, mem, bytes + 4096) == LS_OK);
    REQUIRE(ls_contact_init(&s, &a, count, tw, th, cols, sep, sepc) == LS_OK);
    CHECK_EQ(ls_arena_used(&a), bytes);
    CHECK(s.image.width == 3 * 6 + 2 * 2 && s.image.height == 3 * 4 + 2 * 2);
    REQUIRE(ls_image_create(&tile, tw, th, &a) == LS_OK);
    for (t = 0; t < 6; t++) { /* tile 6 stays empty; odd tiles through ls_real */
        for (y = 0; y < th; y++)
            for (x = 0; x < tw; x++)
                for (k = 0; k < 4; k++) {
                    tile.pixels[4 * (y * tw + x) + k] = tile_value(t, x, y, k);
                    rgba[4 * (y * tw + x) + k] = (ls_real)tile_value(t, x, y, k);
                }
        if (t % 2) CHECK_STATUS(ls_contact_put_rgba(&s, t, rgba), LS_OK);
        else CHECK_STATUS(ls_contact_put_image(&s, t, &tile), LS_OK);
    }
    for (y = 0; y < s.image.height; y++)
        for (x = 0; x < s.image.width; x++) {
            /* independent placement: cell pitch tw + sep, th + sep */
            uint32_t cx = x / (tw + sep), ox = x % (tw + sep), cy = y / (th + sep), oy = y % (th + sep);
            uint32_t tt = cy * cols + cx;
            int in_tile = ox < tw && oy < th && tt < 6;
            for (k = 0; k < 4; k++) {
                float want = in_tile ? tile_value(tt, ox, oy, k) : sepc[k];
                if (s.image.pixels[4 * ((size_t)y * s.image.width + x) + k] != want) bad++;
            }
        }
    CHECK_EQ(bad, 0);
    /* errors */
    CHECK_STATUS(ls_contact_put_image(&s, count, &tile), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_put_rgba(&s, 0, NULL), LS_ERR_INVALID);
    tile.width = 5;
    CHECK_STATUS(ls_contact_put_image(&s, 0, &tile), LS_ERR_INVALID);
    {
        ls_contact blank;
        memset(&blank, 0, sizeof blank);
        CHECK_STATUS(ls_contact_put_rgba(&blank, 0, rgba), LS_ERR_STATE);
    }
    free(mem);
}

typedef struct init_job {
    ls_contact s;
} init_job;

static ls_status run_init(void *ctx, ls_arena *arena)
{
    return ls_contact_init(&((init_job *)ctx)->s, arena, 5, 9, 3, 0, 1, NULL);
}

static uint64_t hash_init(void *ctx)
{
    return test_hash(&((init_job *)ctx)->s, sizeof(ls_contact), TEST_HASH_SEED);
}

static void sizing_and_arena_sweep(void)
{
    init_job j;
    sweep_job sj;
    size_t bytes, want;
    REQUIRE(ls_contact_bytes(5, 9, 3, 0, 1, &bytes) == LS_OK);
    REQUIRE(ls_image_bytes(3 * 9 + 2, 2 * 3 + 1, &want) == LS_OK);
    CHECK_EQ(bytes, want);
    CHECK_STATUS(ls_contact_bytes(5, 9, 3, 0, 1, NULL), LS_ERR_INVALID);
    memset(&j, 0, sizeof j);
    memset(&sj, 0, sizeof sj);
    sj.name = "contact_init";
    sj.run = run_init;
    sj.state_hash = hash_init;
    sj.ctx = &j;
    sj.answer = bytes;
    sj.exact = 1;
    CHECK_EQ(sweep_arena(&sj), 0);
    /* default separator: opaque black (the sweep's buffer is gone: a new run) */
    {
        void *mem = malloc(bytes);
        ls_arena a;
        REQUIRE(ls_arena_init(&a, mem, bytes) == LS_OK);
        REQUIRE(run_init(&j, &a) == LS_OK);
        CHECK(j.s.image.pixels[4 * 9 + 0] == 0.0f && j.s.image.pixels[4 * 9 + 2] == 0.0f &&
              j.s.image.pixels[4 * 9 + 3] == 1.0f);
        free(mem);
    }
}


/* The glyphs as drawn: ink (1) or box (0) at glyph pixel (c, r) of the
 * 5 x 7 cell, written out here independently of the library's table. */
static const char *const glyph_1[7] = {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."};
static const char *const glyph_t[7] = {".#...", ".#...", "###..", ".#...", ".#...", ".#..#", "..##."};

/* Labels: the box and the glyphs pixel by pixel, the tile around them
 * untouched, the neighbouring cell untouched, clipping, scale, errors. */
static void labels_are_drawn_pixel_by_pixel(void)
{
    static LS_ARENA_BUFFER(m, 64u << 10);
    ls_arena a;
    ls_contact s;
    const float grey[4] = {0.25f, 0.25f, 0.25f, 1.0f};
    uint32_t x, y, k, t, bad = 0;
    ls_arena_init(&a, m.bytes, sizeof m.bytes);
    REQUIRE(ls_contact_init(&s, &a, 3, 40, 20, 3, 1, grey) == LS_OK);
    for (t = 0; t < 3; t++)
        for (y = 0; y < 20; y++)
            for (x = 0; x < 40; x++)
                for (k = 0; k < 4; k++) s.image.pixels[4 * (y * s.image.width + t * 41 + x) + k] = 0.5f;
    CHECK_STATUS(ls_contact_label(&s, 1, "1t"), LS_OK);
    for (y = 0; y < 20; y++)
        for (x = 0; x < 40; x++) {
            const float *p = s.image.pixels + 4 * (y * s.image.width + 41 + x);
            float want = 0.5f, a_want = 0.5f;
            if (x < 13 && y < 9) { /* the box: 6 n + 1 by 9 */
                int ink = 0;
                if (x >= 1 && y >= 1 && y <= 7 && (x - 1) % 6 < 5) {
                    const char *const *g = (x - 1) / 6 == 0 ? glyph_1 : glyph_t;
                    ink = g[y - 1][(x - 1) % 6] == '#';
                }
                want = ink ? 1.0f : 0.0f;
                a_want = 1.0f;
            }
            if (p[0] != want || p[1] != want || p[2] != want || p[3] != a_want) bad++;
        }
    CHECK_EQ(bad, 0);
    /* the cells on either side and the separators */
    for (y = 0; y < 20; y++) {
        CHECK(s.image.pixels[4 * (y * s.image.width + 39)] == 0.5f);
        CHECK(s.image.pixels[4 * (y * s.image.width + 40)] == 0.25f);
        CHECK(s.image.pixels[4 * (y * s.image.width + 80)] == 0.5f);
        CHECK(s.image.pixels[4 * (y * s.image.width + 81)] == 0.25f);
        CHECK(s.image.pixels[4 * (y * s.image.width + 82)] == 0.5f);
    }
    /* upper case as lower case, unknown bytes as '?' */
    {
        float first[4 * 13 * 9];
        for (y = 0; y < 9; y++) memcpy(first + 4 * 13 * y, s.image.pixels + 4 * (y * s.image.width + 41), sizeof(float) * 4 * 13);
        CHECK_STATUS(ls_contact_label(&s, 1, "1T"), LS_OK);
        for (y = 0; y < 9; y++)
            CHECK(memcmp(first + 4 * 13 * y, s.image.pixels + 4 * (y * s.image.width + 41), sizeof(float) * 4 * 13) == 0);
        CHECK_STATUS(ls_contact_label(&s, 0, "\x01"), LS_OK);
        CHECK_STATUS(ls_contact_label(&s, 2, "?"), LS_OK);
        for (y = 0; y < 9; y++)
            CHECK(memcmp(s.image.pixels + 4 * (y * s.image.width), s.image.pixels + 4 * (y * s.image.width + 82),
                         sizeof(float) * 4 * 7) == 0);
    }
    /* a label longer than the cell is clipped to it */
    CHECK_STATUS(ls_contact_label(&s, 0, "a long label that does not fit"), LS_OK);
    for (y = 0; y < 20; y++) CHECK(s.image.pixels[4 * (y * s.image.width + 40)] == 0.25f);
    for (y = 9; y < 20; y++) CHECK(s.image.pixels[4 * (y * s.image.width + 5)] == 0.5f);
    CHECK_EQ(ls_contact_label_scale(40), 1);
    CHECK_EQ(ls_contact_label_scale(256), 2);
    CHECK_EQ(ls_contact_label_scale(100000), 4);
    CHECK_STATUS(ls_contact_label(&s, 3, "x"), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_label(&s, 0, NULL), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_label(NULL, 0, "x"), LS_ERR_INVALID);
}

/* Scale 2 (tiles 256 wide): every glyph pixel is 2 x 2. */
static void labels_scale_with_the_tile(void)
{
    ls_arena a;
    ls_contact s;
    uint32_t x, y, bad = 0;
    size_t bytes;
    void *mem;
    REQUIRE(ls_contact_bytes(1, 256, 32, 1, 0, &bytes) == LS_OK);
    mem = malloc(bytes + 64);
    REQUIRE(mem != NULL && ls_arena_init(&a, mem, bytes + 64) == LS_OK);
    REQUIRE(ls_contact_init(&s, &a, 1, 256, 32, 1, 0, NULL) == LS_OK);
    CHECK_STATUS(ls_contact_label(&s, 0, "1"), LS_OK);
    for (y = 0; y < 32; y++)
        for (x = 0; x < 256; x++) {
            float want = 0.0f; /* the box and the black initial sheet */
            if (x >= 2 && x < 12 && y >= 2 && y < 16) want = glyph_1[y / 2 - 1][x / 2 - 1] == '#' ? 1.0f : 0.0f;
            if (s.image.pixels[4 * (y * 256 + x)] != want) bad++;
        }
    CHECK_EQ(bad, 0);
    free(mem);
}

/* The backdrop: transparent pixels show the checkerboard, partly covered
 * ones blend (premultiplied), opaque ones and the separators keep their
 * values; alpha becomes 1. */
static void backdrop_shows_masks(void)
{
    static LS_ARENA_BUFFER(m, 16u << 10);
    ls_arena a;
    ls_contact s;
    const float sepc[4] = {0.1f, 0.2f, 0.3f, 1.0f};
    uint32_t x, y, k, bad = 0;
    ls_arena_init(&a, m.bytes, sizeof m.bytes);
    REQUIRE(ls_contact_init(&s, &a, 2, 8, 6, 2, 1, sepc) == LS_OK);
    /* tile 0: a white mask (alpha = coverage) on transparent black; tile 1 opaque */
    for (y = 0; y < 6; y++)
        for (x = 0; x < 8; x++) {
            float *p0 = s.image.pixels + 4 * (y * s.image.width + x), *p1 = p0 + 4 * 9;
            float cov = x < 3 ? 1.0f : x == 3 ? 0.5f : 0.0f;
            for (k = 0; k < 3; k++) p0[k] = cov, p1[k] = 0.75f;
            p0[3] = cov;
            p1[3] = 1.0f;
        }
    CHECK_STATUS(ls_contact_backdrop(&s, 2, 0.25f, 0.5f), LS_OK);
    for (y = 0; y < 6; y++)
        for (x = 0; x < s.image.width; x++) {
            const float *p = s.image.pixels + 4 * (y * s.image.width + x);
            float grey = ((x / 2 + y / 2) & 1) ? 0.5f : 0.25f, want[4];
            if (x == 8) memcpy(want, sepc, sizeof want);
            else if (x > 8) want[0] = want[1] = want[2] = 0.75f;
            else if (x < 3) want[0] = want[1] = want[2] = 1.0f;
            else if (x == 3) want[0] = want[1] = want[2] = 0.5f + 0.5f * grey;
            else want[0] = want[1] = want[2] = grey;
            want[3] = 1.0f;
            if (x == 8) want[3] = sepc[3];
            if (memcmp(p, want, sizeof want) != 0) bad++;
        }
    CHECK_EQ(bad, 0);
    CHECK_STATUS(ls_contact_backdrop(&s, 0, 1.5f, 0.5f), LS_ERR_INVALID);
    CHECK_STATUS(ls_contact_backdrop(NULL, 0, 0.5f, 0.5f), LS_ERR_INVALID);
    s.magic = 0;
    CHECK_STATUS(ls_contact_backdrop(&s, 0, 0.5f, 0.5f), LS_ERR_STATE);
}

int main(void)
{
    TEST_INIT("test_contact");
    TEST_RUN(layout_matches_the_formula);
    TEST_RUN(every_pixel_lands_in_its_cell);
    TEST_RUN(sizing_and_arena_sweep);
    TEST_RUN(labels_are_drawn_pixel_by_pixel);
    TEST_RUN(labels_scale_with_the_tile);
    TEST_RUN(backdrop_shows_masks);
    return TEST_END();
}
