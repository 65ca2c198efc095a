/* m4_tradeoffs.c - the low end of the trade study: memory and
 * instruction counts of the reconstruction on the Cortex-M4 port, against
 * render resolution and mesh size, so that an integrator can size a part.
 *
 * Runs on QEMU's mps2-an386 with `-icount shift=0` (LS_M4_ICOUNT=1
 * tests/tools/run_m4.sh ...): one guest instruction per virtual nanosecond,
 * read through the board's counter (port/cortex-m4/counter.c), so the
 * figures are instruction counts (to within 40), not QEMU's time. Cycles on
 * a real part are these times its CPI (about 1.1-1.5 on a Cortex-M4 with
 * zero-wait-state memory; flash wait states add more).
 *
 * For each resolution R (one view, S = 1, SH shading, exact silhouettes)
 * and initial icosphere level: ls_fit_bytes (the whole fit's arena), the
 * instructions of ls_fit_init and of one ls_fit_step (mean of 3) by stage
 * (the fit's stage timing driven by an instruction clock), and whether the
 * fit fits the MCU profile's 224 KiB arena. Prints a Markdown table.
 */
#include <stdio.h>
#include <string.h>
#include <largesteps.h>
#include "ls_m4.h"

#define STUDY_ARENA_BYTES (3u * 1024u * 1024u)
#define MCU_ARENA_BYTES (224u * 1024u)

static LS_ARENA_BUFFER(study_buffer, STUDY_ARENA_BYTES);

static uint64_t instruction_clock(void *user)
{
    return ls_m4_instructions(*(const uint32_t *)user);
}

static const ls_real sh[27] = {(ls_real)1.6, (ls_real)0.8, (ls_real)0.4, 0, 0, 0, 0, 0, 0,
                               (ls_real)1.6, (ls_real)0.8, (ls_real)0.4, 0, 0, 0, 0, 0, 0,
                               (ls_real)1.6, (ls_real)0.8, (ls_real)0.4, 0, 0, 0, 0, 0, 0};

/* One configuration; returns 0 on failure (printed). */
static int study(uint32_t res, uint32_t level)
{
    const ls_real dir[3] = {(ls_real)0.3, (ls_real)0.4, 1};
    ls_arena arena;
    ls_mesh target, init;
    ls_camera_framing fr;
    ls_fit_config c;
    ls_fit_views views;
    ls_fit fit;
    ls_vis vis;
    ls_monitor mon;
    ls_real mvp[16], *img, *normals;
    const ls_real *targets[1];
    ls_arena_mark mark;
    size_t bytes = 0;
    uint32_t i, start;
    uint64_t init_insn;
    double per_it, render, shade, sil, solve, optim;
    ls_status st;
    if (ls_arena_init(&arena, study_buffer.bytes, sizeof study_buffer.bytes) != LS_OK) return 0;
    if (ls_icosphere(3, &arena, &target) != LS_OK) return 0;
    for (i = 0; i < target.vertex_count; i++) target.positions[3 * i] *= (ls_real)1.4;
    ls_fit_config_default(&c);
    c.width = c.height = res;
    c.shading.mode = LS_SHADE_SH;
    c.shading.sh = sh;
    c.optim.lr = (ls_real)0.02;
    if (ls_camera_frame(target.positions, target.vertex_count, (ls_real)0.8, LS_FOV_X, 1, (ls_real)1.1, &fr, NULL) != LS_OK ||
        ls_camera_framed_view(&fr, dir, NULL, mvp) != LS_OK)
        return 0;
    img = (ls_real *)ls_arena_alloc(&arena, 4u * res * res, sizeof(ls_real));
    if (img == NULL) return 0;
    targets[0] = img;
    mark = ls_arena_save(&arena);
    normals = (ls_real *)ls_arena_alloc(&arena, 3u * target.vertex_count, sizeof(ls_real));
    if (normals == NULL ||
        ls_shade_vertex_normals(target.positions, target.vertex_count, target.triangles, target.face_count, normals,
                                NULL) != LS_OK ||
        ls_vis_init(&vis, &arena, res, res, 1, target.vertex_count) != LS_OK ||
        ls_raster(&vis, &(ls_view){.positions = target.positions, .indices = target.triangles,
                .triangle_count = target.face_count, .vertex_count = target.vertex_count, .mvp = mvp}, &arena, NULL) !=
            LS_OK ||
        ls_shade(&(ls_view){.vis = &vis, .indices = target.triangles, .triangle_count = target.face_count,
                .vertex_count = target.vertex_count, .normals = normals, .opts = &c.shading}, img, NULL) != LS_OK)
        return 0;
    ls_arena_restore(&arena, mark);
    if (ls_icosphere(level, &arena, &init) != LS_OK) return 0;
    for (i = 0; i < 3u * init.vertex_count; i++) init.positions[i] *= fr.radius * (ls_real)0.8;
    for (i = 0; i < init.vertex_count; i++) {
        init.positions[3 * i] += fr.center[0];
        init.positions[3 * i + 1] += fr.center[1];
        init.positions[3 * i + 2] += fr.center[2];
    }
    views.count = 1;
    views.mvp = mvp;
    views.targets = targets;
    st = ls_fit_bytes(&c, &views, &init, &arena, &bytes, NULL);
    if (st != LS_OK) return printf("| %u^2 | %u | ls_fit_bytes: %s |\n", (unsigned)res, (unsigned)init.vertex_count, ls_status_str(st)), 0;
    if (bytes > ls_arena_available(&arena)) {
        printf("| %u^2 | %u | %u | %.1f | no | (does not fit the study's arena: %u KiB free) |||||||\n", (unsigned)res,
               (unsigned)init.vertex_count, (unsigned)init.face_count, (double)bytes / 1024.0,
               (unsigned)(ls_arena_available(&arena) / 1024u));
        return 1;
    }
    start = ls_m4_counter();
    st = ls_fit_init(&fit, &c, &views, &init, &arena, NULL);
    init_insn = ls_m4_instructions(start);
    if (st != LS_OK) return printf("| %u^2 | %u | ls_fit_init: %s |\n", (unsigned)res, (unsigned)init.vertex_count, ls_status_str(st)), 0;
    memset(&mon, 0, sizeof mon);
    mon.clock = instruction_clock;
    mon.user = &start;
    start = ls_m4_counter();
    for (i = 0; i < 3; i++) {
        st = ls_fit_step(&fit, &mon, NULL);
        if (st != LS_OK) return printf("| %u^2 | %u | ls_fit_step: %s |\n", (unsigned)res, (unsigned)init.vertex_count, ls_status_str(st)), 0;
    }
    per_it = (double)ls_m4_instructions(start) / 3.0 / 1e6;
    render = (double)fit.timing.render_ns / 3.0 / 1e6;
    shade = (double)fit.timing.shade_backward_ns / 3.0 / 1e6;
    sil = (double)fit.timing.silhouette_ns / 3.0 / 1e6;
    solve = (double)fit.timing.solve_ns / 3.0 / 1e6;
    optim = (double)fit.timing.optimizer_ns / 3.0 / 1e6;
    printf("| %u^2 | %u | %u | %.1f | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %.3f |\n", (unsigned)res,
           (unsigned)init.vertex_count, (unsigned)init.face_count, (double)bytes / 1024.0,
           bytes <= MCU_ARENA_BYTES ? "yes" : "no", (double)init_insn / 1e6, per_it, render, shade, sil, solve, optim);
    return 1;
}

int main(void)
{
    static const uint32_t res[4] = {16, 32, 64, 128};
    uint32_t r, level;
    int ok = 1;
    printf("# Cortex-M4 (%s): the fit's memory and instructions\n\n",
           sizeof(ls_real) == sizeof(float) ? "float, single-precision FPU" : "double, in software: no double FPU");
    printf("One view, S = 1, SH shading, exact silhouettes, large steps (lambda 19, LDL^T). Instructions counted by "
           "QEMU (-icount shift=0), in millions (M).\n\n");
    printf("| resolution | vertices | faces | ls_fit_bytes KiB | fits 224 KiB | init M | step M | render | shading bwd | "
           "silhouette | solve | optimizer |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (r = 0; r < 4; r++)
        for (level = 0; level <= 3; level++) ok &= study(res[r], level);
    return ok ? 0 : 1;
}
