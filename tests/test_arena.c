/* test_arena.c - the allocator, checked sizes, and the sweep helper itself. */
#include "test.h"
#include "sweep.h"

static LS_ARENA_BUFFER(work, 256);

static void arena_init_rejects_bad_buffers(void)
{
    ls_arena a;
    CHECK_STATUS(ls_arena_init(NULL, work.bytes, 8), LS_ERR_INVALID);
    CHECK_STATUS(ls_arena_init(&a, NULL, 8), LS_ERR_INVALID);
    CHECK_STATUS(ls_arena_init(&a, work.bytes + 1, 64), LS_ERR_ALIGN);
    CHECK_STATUS(ls_arena_init(&a, work.bytes + 4, 64), LS_ERR_ALIGN);
    CHECK_STATUS(ls_arena_init(&a, work.bytes, 0), LS_OK);
    CHECK_EQ(a.capacity, 0);
    CHECK_STATUS(ls_arena_init(&a, work.bytes, 63), LS_OK);
    CHECK_EQ(a.capacity, 56); /* rounded down to the alignment */
}

static void arena_buffer_macro_is_aligned_and_rounded(void)
{
    static LS_ARENA_BUFFER(odd, 13);
    CHECK_EQ((uintptr_t)odd.bytes % LS_ARENA_ALIGN, 0);
    CHECK_EQ((uintptr_t)work.bytes % LS_ARENA_ALIGN, 0);
    CHECK_EQ(sizeof odd.bytes, 16);
    CHECK_EQ(LS_ARENA_ROUND(0), 0);
    CHECK_EQ(LS_ARENA_ROUND(1), 8);
    CHECK_EQ(LS_ARENA_ROUND(8), 8);
    CHECK_EQ(LS_ARENA_ROUND(9), 16);
}

static void arena_alloc_rounds_and_aligns(void)
{
    ls_arena a;
    unsigned char *p, *q;
    REQUIRE(ls_arena_init(&a, work.bytes, sizeof work.bytes) == LS_OK);
    p = (unsigned char *)ls_arena_alloc(&a, 1, 1);
    q = (unsigned char *)ls_arena_alloc(&a, 3, 4);
    REQUIRE(p != NULL && q != NULL);
    CHECK(p == work.bytes);
    CHECK(q == work.bytes + 8);
    CHECK_EQ(ls_arena_used(&a), 8 + 16);
    CHECK_EQ((uintptr_t)q % LS_ARENA_ALIGN, 0);
    /* zero-byte requests: valid pointer, no space */
    CHECK(ls_arena_alloc(&a, 0, 8) != NULL);
    CHECK(ls_arena_alloc(&a, 8, 0) != NULL);
    CHECK_EQ(ls_arena_used(&a), 24);
    CHECK_EQ(ls_arena_available(&a), sizeof work.bytes - 24);
}

static void arena_scratch_comes_from_the_top(void)
{
    ls_arena a;
    unsigned char *s, *b;
    REQUIRE(ls_arena_init(&a, work.bytes, 64) == LS_OK);
    s = (unsigned char *)ls_arena_scratch(&a, 5, 1);
    CHECK(s == work.bytes + 56);
    b = (unsigned char *)ls_arena_alloc(&a, 6, 8);
    CHECK(b == work.bytes);
    CHECK_EQ(ls_arena_available(&a), 8);
    /* the two ends meet: one more byte from either end fails */
    CHECK(ls_arena_alloc(&a, 9, 1) == NULL);
    CHECK_EQ(a.need, 56 + 16);
    CHECK(ls_arena_scratch(&a, 8, 1) != NULL);
    CHECK_EQ(ls_arena_available(&a), 0);
    CHECK(ls_arena_scratch(&a, 1, 1) == NULL);
    CHECK_EQ(a.need, 72);
    CHECK_EQ(a.peak, 64);
}

static void arena_overflowing_requests_fail(void)
{
    ls_arena a;
    REQUIRE(ls_arena_init(&a, work.bytes, sizeof work.bytes) == LS_OK);
    CHECK(ls_arena_alloc(&a, SIZE_MAX, 2) == NULL);
    CHECK_EQ(a.need == SIZE_MAX, 1);
    CHECK(ls_arena_alloc(&a, SIZE_MAX - 3, 1) == NULL); /* overflows when rounded */
    CHECK(ls_arena_scratch(&a, (SIZE_MAX / 4) + 1, 4) == NULL);
    CHECK(ls_arena_alloc(&a, sizeof work.bytes + 1, 1) == NULL);
    CHECK_EQ(ls_arena_used(&a), 0);
    CHECK(ls_arena_alloc(NULL, 1, 1) == NULL);
}

static void arena_mark_restore_and_peak(void)
{
    ls_arena a;
    ls_arena_mark m0, m1;
    REQUIRE(ls_arena_init(&a, work.bytes, sizeof work.bytes) == LS_OK);
    ls_arena_alloc(&a, 16, 1);
    m0 = ls_arena_save(&a);
    ls_arena_alloc(&a, 32, 1);
    ls_arena_scratch(&a, 40, 1);
    m1 = ls_arena_save(&a);
    ls_arena_scratch(&a, 8, 1);
    CHECK_EQ(ls_arena_used(&a), 16 + 32 + 40 + 8);
    ls_arena_restore(&a, m1);
    CHECK_EQ(ls_arena_used(&a), 16 + 32 + 40);
    ls_arena_restore(&a, m0);
    CHECK_EQ(a.bottom, 16);
    CHECK_EQ(a.top, 0);
    CHECK_EQ(a.peak, 96);
    /* a stale (newer) mark cannot grow the arena back */
    ls_arena_restore(&a, m1);
    CHECK_EQ(ls_arena_used(&a), 16);
    ls_arena_reset_peak(&a);
    CHECK_EQ(a.peak, 16);
}

static void arena_alloc_zero_clears(void)
{
    ls_arena a;
    unsigned char *p;
    size_t i, nonzero = 0;
    memset(work.bytes, 0xFF, sizeof work.bytes);
    REQUIRE(ls_arena_init(&a, work.bytes, sizeof work.bytes) == LS_OK);
    p = (unsigned char *)ls_arena_alloc_zero(&a, 13, 3);
    REQUIRE(p != NULL);
    for (i = 0; i < 39; i++) nonzero += p[i] != 0;
    CHECK_EQ(nonzero, 0);
    CHECK(ls_arena_alloc_zero(&a, 1000, 1) == NULL);
}

static void size_mirrors_alloc_and_detects_overflow(void)
{
    ls_size s, t;
    size_t bytes = 1;
    ls_arena a;
    ls_size_init(&s);
    ls_size_add(&s, 1, 1);
    ls_size_add(&s, 3, 4);
    ls_size_add(&s, 0, 100);
    CHECK_STATUS(ls_size_get(&s, &bytes), LS_OK);
    CHECK_EQ(bytes, 24);
    REQUIRE(ls_arena_init(&a, work.bytes, sizeof work.bytes) == LS_OK);
    ls_arena_alloc(&a, 1, 1);
    ls_arena_alloc(&a, 3, 4);
    ls_arena_alloc(&a, 0, 100);
    CHECK_EQ(ls_arena_used(&a), bytes);

    ls_size_init(&t);
    ls_size_add(&t, 100, 1);
    ls_size_max(&s, &t);
    CHECK_STATUS(ls_size_get(&s, &bytes), LS_OK);
    CHECK_EQ(bytes, 104);
    ls_size_add_size(&s, &t);
    CHECK_STATUS(ls_size_get(&s, &bytes), LS_OK);
    CHECK_EQ(bytes, 208);

    ls_size_add(&t, SIZE_MAX / 2, 3);
    CHECK_STATUS(ls_size_get(&t, &bytes), LS_ERR_TOO_LARGE);
    CHECK_EQ(bytes, 0);
    ls_size_init(&s);
    ls_size_add(&s, SIZE_MAX / 2, 1);
    ls_size_add(&s, SIZE_MAX / 2, 1);
    ls_size_add(&s, 16, 1); /* the sum overflows, not any one term */
    CHECK_STATUS(ls_size_get(&s, &bytes), LS_ERR_TOO_LARGE);
    ls_size_init(&t);
    ls_size_max(&t, &s); /* overflow is sticky through max and add_size */
    CHECK_STATUS(ls_size_get(&t, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_size_get(NULL, &bytes), LS_ERR_INVALID);

    CHECK_STATUS(ls_size_mul(SIZE_MAX / 2 + 1, 2, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_size_mul(SIZE_MAX / 2, 2, &bytes), LS_OK);
    CHECK_EQ(bytes == SIZE_MAX - 1, 1);
    CHECK_STATUS(ls_size_sum(SIZE_MAX, 1, &bytes), LS_ERR_TOO_LARGE);
    CHECK_STATUS(ls_size_sum(SIZE_MAX - 1, 1, &bytes), LS_OK);
}

/* A toy object built the way every library object is: sized by a query that
 * mirrors its allocations, built into the bottom with scratch from the top,
 * rolled back completely on failure. It checks the sweep helper end to end. */
typedef struct toy {
    uint32_t n;
    uint32_t *items;
    ls_real *weights;
} toy;

typedef struct toy_job {
    uint32_t n;
    const uint32_t *input;
    toy out;
    int leak_on_failure; /* a broken builder: the sweep must catch it */
} toy_job;

static ls_status toy_bytes(uint32_t n, size_t *bytes)
{
    ls_size s, scratch;
    ls_size_init(&s);
    ls_size_add(&s, n, sizeof(uint32_t));
    ls_size_add(&s, n, sizeof(ls_real));
    ls_size_init(&scratch);
    ls_size_add(&scratch, 2 * (size_t)n, sizeof(uint32_t));
    ls_size_add_size(&s, &scratch);
    return ls_size_get(&s, bytes);
}

static ls_status toy_build(void *ctx, ls_arena *arena)
{
    toy_job *job = (toy_job *)ctx;
    ls_arena_mark mark = ls_arena_save(arena);
    uint32_t *items, *tmp, i;
    ls_real *w;
    items = (uint32_t *)ls_arena_alloc(arena, job->n, sizeof *items);
    tmp = (uint32_t *)ls_arena_scratch(arena, 2 * (size_t)job->n, sizeof *tmp);
    w = (ls_real *)ls_arena_alloc(arena, job->n, sizeof *w);
    if (items == NULL || tmp == NULL || w == NULL) {
        if (job->leak_on_failure && items != NULL) job->out.items = items;
        if (!job->leak_on_failure) ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    for (i = 0; i < job->n; i++) {
        tmp[i] = job->input[i] * 2u;
        items[i] = tmp[i] + 1u;
        w[i] = (ls_real)items[i];
    }
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    job->out.n = job->n;
    job->out.items = items;
    job->out.weights = w;
    return LS_OK;
}

static uint64_t toy_hash(void *ctx)
{
    toy_job *job = (toy_job *)ctx;
    uint64_t h = test_hash(job->input, job->n * sizeof *job->input, TEST_HASH_SEED);
    return test_hash(&job->out, sizeof job->out, h);
}

static void toy_reset(void *ctx)
{
    toy_job *job = (toy_job *)ctx;
    memset(&job->out, 0, sizeof job->out);
}

static void sweep_passes_a_correct_object_and_catches_broken_ones(void)
{
    static uint32_t input[3000];
    uint32_t i;
    size_t sizes[3] = {3, 100, 3000};
    for (i = 0; i < 3000; i++) input[i] = i * 7u;
    for (i = 0; i < 3; i++) {
        toy_job job;
        sweep_job sj;
        size_t bytes = 0;
        memset(&job, 0, sizeof job);
        job.n = (uint32_t)sizes[i];
        job.input = input;
        REQUIRE(toy_bytes(job.n, &bytes) == LS_OK);
        sj.name = "toy";
        sj.run = toy_build;
        sj.state_hash = toy_hash;
        sj.reset = toy_reset;
        sj.ctx = &job;
        sj.answer = bytes;
        sj.exact = 1;
        sj.quiet = 0;
        CHECK_EQ(sweep_arena(&sj), 0);
        /* a query that is one allocation unit too large is caught (exact) */
        sj.quiet = 1;
        sj.answer = bytes + LS_ARENA_ALIGN;
        CHECK(sweep_arena(&sj) > 0);
        /* ... as is a query that is too small */
        sj.answer = bytes - LS_ARENA_ALIGN;
        CHECK(sweep_arena(&sj) > 0);
        /* ... and a builder that leaves a partial object behind */
        sj.answer = bytes;
        job.leak_on_failure = 1;
        CHECK(sweep_arena(&sj) > 0);
    }
}

int main(void)
{
    TEST_INIT("test_arena");
    TEST_RUN(arena_init_rejects_bad_buffers);
    TEST_RUN(arena_buffer_macro_is_aligned_and_rounded);
    TEST_RUN(arena_alloc_rounds_and_aligns);
    TEST_RUN(arena_scratch_comes_from_the_top);
    TEST_RUN(arena_overflowing_requests_fail);
    TEST_RUN(arena_mark_restore_and_peak);
    TEST_RUN(arena_alloc_zero_clears);
    TEST_RUN(size_mirrors_alloc_and_detects_overflow);
    TEST_RUN(sweep_passes_a_correct_object_and_catches_broken_ones);
    return TEST_END();
}
