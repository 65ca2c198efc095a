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

int main(void)
{
    TEST_INIT("test_contact");
    TEST_RUN(layout_matches_the_formula);
    TEST_RUN(every_pixel_lands_in_its_cell);
    TEST_RUN(sizing_and_arena_sweep);
    return TEST_END();
}
