/* test_core.c - version, build info, the floating-point self-test, status
 * messages and diagnostics, and progress/cancellation. */
#include "test.h"
#include <fenv.h>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

static void version_matches_header(void)
{
    char expect[32];
    CHECK_EQ(ls_version(), LS_VERSION_NUMBER);
    CHECK_EQ(LS_VERSION_NUMBER, (LS_VERSION_MAJOR << 16) | (LS_VERSION_MINOR << 8) | LS_VERSION_PATCH);
    snprintf(expect, sizeof expect, "%d.%d.%d", LS_VERSION_MAJOR, LS_VERSION_MINOR, LS_VERSION_PATCH);
    CHECK(strcmp(ls_version_string(), expect) == 0);
    CHECK(strcmp(ls_version_string(), LS_VERSION_STRING) == 0);
}

static void build_info_describes_this_build(void)
{
    ls_build_info info;
    uint32_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    ls_build_info_get(&info);
    ls_build_info_get(NULL);
    CHECK_EQ(info.real_bytes, sizeof(ls_real));
    CHECK_EQ(info.real_bytes, LS_REAL_IS_FLOAT ? 4 : 8);
    CHECK(strcmp(info.real_name, LS_REAL_NAME) == 0);
    CHECK_EQ(info.arena_align, LS_ARENA_ALIGN);
    CHECK_EQ(info.pointer_bytes, sizeof(void *));
    CHECK_EQ(info.size_bytes, sizeof(size_t));
    CHECK_EQ(info.big_endian, first == 0);
    CHECK(info.compiler != NULL && strlen(info.compiler) > 3);
}

static void selftest_passes_here_and_detects_abi_mismatch(void)
{
    CHECK_STATUS(ls_selftest(sizeof(ls_real)), LS_OK);
    CHECK_STATUS(ls_selftest(LS_REAL_IS_FLOAT ? sizeof(double) : sizeof(float)), LS_ERR_ABI);
}

static void selftest_detects_other_rounding_modes(void)
{
    static const int modes[] = {FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO};
    static const char *names[] = {"upward", "downward", "toward zero"};
    int i;
    for (i = 0; i < 3; i++) {
        ls_status st;
        REQUIRE(fesetround(modes[i]) == 0);
        st = ls_selftest(sizeof(ls_real));
        fesetround(FE_TONEAREST);
        CHECK_MSG(st == LS_ERR_FPENV, "rounding %s: selftest returned %s", names[i], ls_status_name(st));
    }
    CHECK_STATUS(ls_selftest(sizeof(ls_real)), LS_OK);
}

/* Flush-to-zero is a control-register bit; set it the way firmware does. */
static int set_flush_to_zero(int on)
{
#if defined(__SSE2__)
    unsigned csr = _mm_getcsr();
    _mm_setcsr(on ? (csr | 0x8040u) : (csr & ~0x8040u)); /* FTZ | DAZ */
    return 1;
#elif defined(__aarch64__)
    uint64_t fpcr;
    __asm__ volatile("mrs %0, fpcr" : "=r"(fpcr));
    fpcr = on ? (fpcr | (1u << 24)) : (fpcr & ~(uint64_t)(1u << 24));
    __asm__ volatile("msr fpcr, %0" : : "r"(fpcr));
    return 1;
#elif defined(__arm__) && defined(__ARM_FP)
    uint32_t fpscr;
    __asm__ volatile("vmrs %0, fpscr" : "=r"(fpscr));
    fpscr = on ? (fpscr | (1u << 24)) : (fpscr & ~(1u << 24));
    __asm__ volatile("vmsr fpscr, %0" : : "r"(fpscr));
    return 1;
#else
    (void)on;
    return 0; /* riscv64 and s390x have no flush-to-zero mode: nothing to detect */
#endif
}

static void selftest_detects_flush_to_zero(void)
{
    ls_status st;
    if (!set_flush_to_zero(1)) {
        printf("     (this target has no flush-to-zero mode; IEEE subnormals always)\n");
        CHECK_STATUS(ls_selftest(sizeof(ls_real)), LS_OK);
        return;
    }
    st = ls_selftest(sizeof(ls_real));
    set_flush_to_zero(0);
    CHECK_MSG(st == LS_ERR_FPENV, "with FTZ/DAZ set selftest returned %s", ls_status_name(st));
    CHECK_STATUS(ls_selftest(sizeof(ls_real)), LS_OK);
}

static void status_names_and_messages(void)
{
#define NAMED(code) {code, #code}
    static const struct { ls_status code; const char *name; } codes[] = {
        NAMED(LS_OK), NAMED(LS_ERR_INVALID), NAMED(LS_ERR_NOMEM), NAMED(LS_ERR_TOO_LARGE),
        NAMED(LS_ERR_ALIGN), NAMED(LS_ERR_PARSE), NAMED(LS_ERR_NONFINITE), NAMED(LS_ERR_MESH),
        NAMED(LS_ERR_NOT_SPD), NAMED(LS_ERR_CANCELLED), NAMED(LS_ERR_IO), NAMED(LS_ERR_UNSUPPORTED),
        NAMED(LS_ERR_FPENV), NAMED(LS_ERR_ABI), NAMED(LS_ERR_STATE)};
#undef NAMED
    size_t i, j;
    ls_build_info info;
    ls_build_info_get(&info);
    CHECK_EQ(sizeof codes / sizeof codes[0], LS_STATUS_COUNT);
    for (i = 0; i < sizeof codes / sizeof codes[0]; i++) {
        CHECK_EQ(codes[i].code, (ls_status)i);
        CHECK_MSG(strcmp(ls_status_name(codes[i].code), codes[i].name) == 0, "%s named %s",
                  codes[i].name, ls_status_name(codes[i].code));
        CHECK(strlen(ls_status_str(codes[i].code)) > 4);
        for (j = 0; j < i; j++) CHECK(strcmp(ls_status_str(codes[i].code), ls_status_str(codes[j].code)) != 0);
        /* built with -DLS_NO_STATUS_STRINGS the message is the name */
        if (!info.status_strings) CHECK(strcmp(ls_status_str(codes[i].code), codes[i].name) == 0);
    }
    CHECK(strcmp(ls_status_name(-1), "LS_ERR_UNKNOWN") == 0);
    CHECK(strcmp(ls_status_name(LS_STATUS_COUNT), "LS_ERR_UNKNOWN") == 0);
    if (info.status_strings) {
        CHECK(strstr(ls_status_str(9999), "unknown") != NULL);
        CHECK(strstr(ls_status_str(LS_ERR_NOMEM), "sizing query") != NULL);
    } else {
        CHECK(strcmp(ls_status_str(9999), "LS_ERR_UNKNOWN") == 0);
    }
}

static void diag_clear_resets_every_field(void)
{
    ls_diag d;
    memset(&d, 0x5A, sizeof d);
    ls_diag_clear(&d);
    ls_diag_clear(NULL);
    CHECK_EQ(d.status, LS_OK);
    CHECK_EQ(d.has_line + d.line + d.column + d.has_offset + d.has_index + d.has_value, 0);
    CHECK_EQ(d.offset + d.index, 0);
    CHECK(d.value == 0);
    CHECK(d.what != NULL && d.what[0] == 0);
}

typedef struct fake {
    uint64_t now;
    int calls;
    int cancel_at;
    uint64_t last_done, last_elapsed;
} fake;

static uint64_t fake_clock(void *user)
{
    fake *f = (fake *)user;
    f->now += 1000;
    return f->now;
}

static int32_t fake_progress(void *user, const ls_progress *p)
{
    fake *f = (fake *)user;
    f->calls++;
    f->last_done = p->done;
    f->last_elapsed = p->elapsed_ns;
    return f->calls >= f->cancel_at;
}

static void diag_set_records_status_what_and_index(void)
{
    ls_diag d;
    memset(&d, 0x5A, sizeof d);
    CHECK_STATUS(ls_diag_set(&d, LS_ERR_MESH, "face index out of range", 7), LS_ERR_MESH);
    CHECK_EQ(d.status, LS_ERR_MESH);
    CHECK(d.what != NULL && strcmp(d.what, "face index out of range") == 0);
    CHECK_EQ(d.has_index, 1);
    CHECK_EQ(d.index, 7);
    CHECK_EQ(d.has_line, 0);
    CHECK_EQ(d.has_offset, 0);
    CHECK_EQ(d.has_value, 0);
    CHECK_STATUS(ls_diag_set(&d, LS_ERR_PARSE, "bad", LS_DIAG_NO_INDEX), LS_ERR_PARSE);
    CHECK_EQ(d.has_index, 0);
    CHECK_EQ(d.index, 0);
    CHECK_STATUS(ls_diag_set(NULL, LS_ERR_IO, "x", 1), LS_ERR_IO);
}

static void monitor_reports_and_cancels(void)
{
    fake f = {5000, 0, 3, 0, 0};
    ls_monitor m;
    uint64_t i;
    ls_status st = LS_OK;
    m.progress = fake_progress;
    m.clock = fake_clock;
    m.user = &f;
    ls_monitor_start(&m);
    CHECK_EQ(m.start_ns, 6000);
    for (i = 0; i < 10 && st == LS_OK; i++) st = ls_monitor_report(&m, "loop", i, 10);
    CHECK_STATUS(st, LS_ERR_CANCELLED);
    CHECK_EQ(f.calls, 3);
    CHECK_EQ(f.last_done, 2);
    CHECK_EQ(f.last_elapsed, 3000); /* three clock ticks after the start */
    CHECK_STATUS(ls_monitor_report(NULL, "x", 0, 0), LS_OK);
    m.progress = NULL;
    CHECK_STATUS(ls_monitor_report(&m, "x", 0, 0), LS_OK);
    m.clock = NULL;
    CHECK_EQ(ls_monitor_elapsed_ns(&m), 0);
    CHECK_EQ(ls_monitor_elapsed_ns(NULL), 0);
}

int main(void)
{
    TEST_INIT("test_core");
    TEST_RUN(version_matches_header);
    TEST_RUN(build_info_describes_this_build);
    TEST_RUN(selftest_passes_here_and_detects_abi_mismatch);
    TEST_RUN(selftest_detects_other_rounding_modes);
    TEST_RUN(selftest_detects_flush_to_zero);
    TEST_RUN(status_names_and_messages);
    TEST_RUN(diag_clear_resets_every_field);
    TEST_RUN(diag_set_records_status_what_and_index);
    TEST_RUN(monitor_reports_and_cancels);
    return TEST_END();
}
