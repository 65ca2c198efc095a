/* tests/test_oom.c - out of memory at every allocation point.
 *
 * The sweeps of tests/sweep.h (in each module's test) try every size at which
 * one more allocation fails. This program adds, for the objects that read
 * untrusted bytes or carry the fit, a sweep over EVERY arena size from 0 to
 * the sizing query's answer (in steps of LS_ARENA_ALIGN: an arena's capacity
 * is rounded down to it, so no other size behaves differently), where
 *   - the call is made with bytes already in use at both ends of the arena
 *     (so a restore to zero instead of to the caller's mark would show);
 *   - every size below the answer gives LS_ERR_NOMEM, leaves the arena at
 *     its mark, the inputs byte-for-byte as they were (compared with copies)
 *     and the output object untouched (compared with its bytes before);
 *   - the answer itself succeeds.
 * Where the answer is large, sizes are taken with a stride (said in the
 * output line) AND at every size the arena's `need` leads to, which is every
 * allocation point: each allocation is made to fail once.
 *
 * Audit (which objects are swept where):
 *   parsers       mesh read (OBJ, binary PLY, OFF), image decode (PNG in
 *                 several colour types, interlaced, palette + tRNS; PFM;
 *                 PNM 16-bit), scenes (text, Mitsuba): here, every size
 *                 (test_mesh_io, test_image, test_scene sweep allocation points);
 *   factorization Laplacian, M = I + lambda L, LDL^T analyze and factor:
 *                 here, every size (test_ldlt sweeps allocation points and
 *                 solve/refine);
 *   rendering     vis init and raster: here, every size; ls_shade and
 *                 ls_shade_backward take no memory (nothing to sweep);
 *                 vertex normals backward (test_render_backward), edge
 *                 table and silhouette backward (test_silhouette): swept
 *                 at every allocation point there;
 *   remeshing     ls_remesh: every allocation point in test_remesh;
 *   a short fit   ls_fit_bytes's scratch (here, every size), ls_fit_init
 *                 (here, stride + every allocation point; test_fit sweeps
 *                 allocation points too), ls_fit_step (takes no arena: its
 *                 memory is inside the fit's block, checked untouched
 *                 around it), ls_fit_remesh after a few steps (here, every
 *                 allocation point and a stride: the fit and the arena as
 *                 before, then the successful remesh).
 */
#include "test.h"
#include <stdlib.h>

/* Under an emulator (LS_TEST_EMULATED=1: QEMU, valgrind) the every-size
 * sweeps take a stride so that about this many sizes are tried (the
 * allocation points are still every one). */
#define EMULATED_TRIES 400u
static size_t emulated_tries;

#define PRE_BOTTOM 24u
#define PRE_TOP 40u
#define MAX_INPUTS 4

typedef struct oom_job {
    const char *name;
    ls_status (*run)(void *ctx, ls_arena *arena);
    void (*undo)(void *ctx); /* optional: after a success */
    void *ctx;
    const void *inputs[MAX_INPUTS];
    size_t input_bytes[MAX_INPUTS];
    void *output; /* set to a pattern before each call: must keep it on failure */
    size_t output_bytes;
    size_t answer;
    size_t max_tries; /* 0: every size; else a stride so that about this many sizes are tried */
} oom_job;

typedef struct oom_counts {
    size_t tries;
    size_t problems;
} oom_counts;

/* One run in an arena with `size` bytes free between two pre-used ends. */
static ls_status oom_once(const oom_job *j, unsigned char *buf, size_t size, void *const *copies,
                          unsigned char *out_before, oom_counts *c, size_t *need)
{
    ls_arena arena;
    ls_arena_mark mark;
    ls_status st;
    size_t total = size + PRE_BOTTOM + PRE_TOP, k;
    memset(buf, 0xA5, total);
    if (ls_arena_init(&arena, buf, total) != LS_OK || ls_arena_alloc(&arena, 1, PRE_BOTTOM) == NULL ||
        ls_arena_scratch(&arena, 1, PRE_TOP) == NULL) {
        c->problems++;
        return LS_ERR_INVALID;
    }
    mark = ls_arena_save(&arena);
    /* a fully defined pattern (a struct the library filled has undefined
     * padding, which valgrind would flag in the comparison) */
    if (j->output != NULL) {
        memset(j->output, 0x5A, j->output_bytes);
        memcpy(out_before, j->output, j->output_bytes);
    }
    st = j->run(j->ctx, &arena);
    c->tries++;
    *need = arena.need > PRE_BOTTOM + PRE_TOP ? arena.need - PRE_BOTTOM - PRE_TOP : 0;
    if (st == LS_OK) {
        if (j->undo != NULL) j->undo(j->ctx);
        return st;
    }
    if (st != LS_ERR_NOMEM) {
        c->problems++;
        printf("     %s: size %lu returned %s, wanted LS_ERR_NOMEM\n", j->name, (unsigned long)size, ls_status_name(st));
    }
    if (arena.bottom != mark.bottom || arena.top != mark.top) {
        c->problems++;
        printf("     %s: size %lu left the arena at %lu+%lu, not %lu+%lu\n", j->name, (unsigned long)size,
               (unsigned long)arena.bottom, (unsigned long)arena.top, (unsigned long)mark.bottom, (unsigned long)mark.top);
    }
    for (k = 0; k < MAX_INPUTS; k++) {
        if (j->inputs[k] != NULL && memcmp(j->inputs[k], copies[k], j->input_bytes[k]) != 0) {
            c->problems++;
            printf("     %s: size %lu changed input %lu\n", j->name, (unsigned long)size, (unsigned long)k);
        }
    }
    if (j->output != NULL && memcmp(j->output, out_before, j->output_bytes) != 0) {
        c->problems++;
        printf("     %s: size %lu changed its output object\n", j->name, (unsigned long)size);
    }
    return st;
}

/* Returns the number of problems; prints one line with the sizes tried. */
static size_t oom_sweep(const oom_job *j)
{
    void *copies[MAX_INPUTS] = {NULL, NULL, NULL, NULL};
    unsigned char *out_before = (unsigned char *)malloc(j->output_bytes + 1u);
    unsigned char *buf = (unsigned char *)malloc(j->answer + PRE_BOTTOM + PRE_TOP + LS_ARENA_ALIGN);
    oom_counts c = {0, 0};
    size_t k, size, stride = LS_ARENA_ALIGN, need = 0, chain = 0;
    ls_status st;
    if (buf == NULL || out_before == NULL) return 1;
    for (k = 0; k < MAX_INPUTS; k++) {
        if (j->inputs[k] == NULL) continue;
        copies[k] = malloc(j->input_bytes[k] + 1u);
        if (copies[k] == NULL) return 1;
        memcpy(copies[k], j->inputs[k], j->input_bytes[k]);
    }
    {
        size_t tries = j->max_tries;
        if (emulated_tries != 0 && (tries == 0 || tries > emulated_tries)) tries = emulated_tries;
        if (tries != 0 && j->answer / LS_ARENA_ALIGN > tries) stride = LS_ARENA_ROUND(j->answer / tries);
    }
    /* every size (or every stride-th), below the answer */
    for (size = 0; size < j->answer && c.problems < 8; size += stride) {
        st = oom_once(j, buf, size, copies, out_before, &c, &need);
        if (st == LS_OK) {
            c.problems++;
            printf("     %s: succeeded with %lu bytes < answer %lu\n", j->name, (unsigned long)size, (unsigned long)j->answer);
            break;
        }
    }
    /* every allocation point: the sizes the arena's `need` leads to */
    if (stride > LS_ARENA_ALIGN) {
        size = 0;
        while (size < j->answer && c.problems < 8) {
            st = oom_once(j, buf, size, copies, out_before, &c, &need);
            chain++;
            if (st != LS_ERR_NOMEM) break;
            if (need <= size) {
                c.problems++;
                printf("     %s: after failing at %lu the arena asks for %lu\n", j->name, (unsigned long)size, (unsigned long)need);
                break;
            }
            size = need;
        }
    }
    st = oom_once(j, buf, j->answer, copies, out_before, &c, &need);
    if (st != LS_OK) {
        c.problems++;
        printf("     %s: failed with %s at the answer %lu\n", j->name, ls_status_name(st), (unsigned long)j->answer);
    }
    printf("     %s: answer %lu bytes, %lu runs (stride %lu%s%lu allocation points)\n", j->name, (unsigned long)j->answer,
           (unsigned long)c.tries, (unsigned long)stride, stride > LS_ARENA_ALIGN ? ", " : ", every size; ",
           (unsigned long)chain);
    for (k = 0; k < MAX_INPUTS; k++) free(copies[k]);
    free(out_before);
    free(buf);
    return c.problems;
}

static unsigned char *read_all(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    unsigned char *d = NULL;
    long len;
    *n = 0;
    if (f == NULL) return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (len = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) {
        d = (unsigned char *)malloc((size_t)len + 1u);
        if (d != NULL && fread(d, 1, (size_t)len, f) != (size_t)len) {
            free(d);
            d = NULL;
        }
        if (d != NULL) *n = (size_t)len;
    }
    fclose(f);
    return d;
}

/* --- parsers ------------------------------------------------------------- */

typedef struct bytes_job {
    const unsigned char *data;
    size_t n;
    ls_mesh mesh;
    ls_image image;
    ls_scene scene;
    int mitsuba;
} bytes_job;

static ls_status run_mesh(void *ctx, ls_arena *arena)
{
    bytes_job *b = (bytes_job *)ctx;
    return ls_mesh_read(b->data, b->n, LS_MESH_FORMAT_AUTO, arena, &b->mesh, NULL);
}

static ls_status run_image(void *ctx, ls_arena *arena)
{
    bytes_job *b = (bytes_job *)ctx;
    return ls_image_decode(b->data, b->n, &b->image, arena, NULL);
}

static ls_status run_scene(void *ctx, ls_arena *arena)
{
    bytes_job *b = (bytes_job *)ctx;
    if (b->mitsuba) return ls_scene_parse_mitsuba((const char *)b->data, b->n, arena, &b->scene, NULL);
    return ls_scene_parse((const char *)b->data, b->n, arena, &b->scene, NULL);
}

static void parsers_at_every_size(void)
{
    static const char *const meshes[] = {"fixtures/meshes/assimp/OBJ/box.obj", "fixtures/meshes/assimp/PLY/cube_binary.ply",
                                         "fixtures/meshes/assimp/OFF/Cube.off", "fixtures/meshes/assimp/PLY/cube.ply"};
    static const char *const images[] = {"fixtures/images/c3_b4_i1_t1_split.png", "fixtures/images/c6_b16_i1_t0_dyn.png",
                                         "fixtures/images/c0_b1_i0_t0_dyn.png", "fixtures/images/c2_b8_i1_t1_fix.png",
                                         "fixtures/images/tiny_1x9_c0_b16_i1.png"};
    static const char scene_text[] =
        "largesteps-scene 1\nresolution 32 24\nfov 50 y\ncamera 0 0 4 0 0 0\nimage \"a b.png\"\n"
        "views fibonacci 5 3\nviews rings 2 2 3 0 1 0\nlighting envmap sky.pfm 2\ntarget mesh t.obj\ninitial mesh s.ply\n";
    static const char mitsuba_text[] =
        "<scene version=\"2.0.0\"><default name=\"w\" value=\"40\"/>"
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/><transform name=\"to_world\">"
        "<lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/><scale value=\"2\"/></transform>"
        "<film type=\"hdrfilm\"><integer name=\"width\" value=\"$w\"/><integer name=\"height\" value=\"30\"/></film></sensor>"
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"30\"/><transform name=\"to_world\"><rotate y=\"1\" angle=\"90\"/>"
        "<translate value=\"0 0 5\"/></transform><film type=\"hdrfilm\"><integer name=\"width\" value=\"40\"/>"
        "<integer name=\"height\" value=\"30\"/></film></sensor>"
        "<emitter type=\"envmap\"><string name=\"filename\" value=\"sky.pfm\"/></emitter>"
        "<shape type=\"ply\" id=\"mesh-target\"><string name=\"filename\" value=\"t.ply\"/></shape></scene>";
    /* a 3 x 2 big-endian PFM and a 16-bit PGM */
    static const unsigned char pfm[] = "PF\n3 2\n1.0\n"
                                       "\x3f\x80\x00\x00\x40\x00\x00\x00\x40\x40\x00\x00\x3f\x00\x00\x00\x00\x00\x00\x00\x3e\x80\x00\x00"
                                       "\x3f\x80\x00\x00\x40\x00\x00\x00\x40\x40\x00\x00\x3f\x00\x00\x00\x00\x00\x00\x00\x3e\x80\x00\x00"
                                       "\x3f\x80\x00\x00\x40\x00\x00\x00\x40\x40\x00\x00\x3f\x00\x00\x00\x00\x00\x00\x00\x3e\x80\x00\x00";
    static const unsigned char pgm[] = "P5 2 2 65535\n\x00\x01\xff\xff\x80\x00\x12\x34";
    size_t i, n = 0;
    bytes_job b;
    oom_job j;
    for (i = 0; i < sizeof meshes / sizeof meshes[0]; i++) {
        ls_mesh_file_info info;
        unsigned char *d = read_all(meshes[i], &n);
        REQUIRE(d != NULL);
        memset(&b, 0, sizeof b);
        memset(&j, 0, sizeof j);
        b.data = d;
        b.n = n;
        REQUIRE(ls_mesh_read_info(d, n, LS_MESH_FORMAT_AUTO, &info, NULL) == LS_OK);
        REQUIRE(ls_mesh_read_bytes(&info, &j.answer) == LS_OK);
        j.name = meshes[i];
        j.run = run_mesh;
        j.ctx = &b;
        j.inputs[0] = d;
        j.input_bytes[0] = n;
        j.output = &b.mesh;
        j.output_bytes = sizeof b.mesh;
        CHECK_EQ(oom_sweep(&j), 0);
        free(d);
    }
    for (i = 0; i < sizeof images / sizeof images[0] + 2; i++) {
        ls_image_info info;
        unsigned char *d;
        if (i < sizeof images / sizeof images[0]) {
            d = read_all(images[i], &n);
        } else {
            n = i == sizeof images / sizeof images[0] ? sizeof pfm - 1 : sizeof pgm - 1;
            d = (unsigned char *)malloc(n);
            if (d != NULL) memcpy(d, i == sizeof images / sizeof images[0] ? pfm : pgm, n);
        }
        REQUIRE(d != NULL);
        memset(&b, 0, sizeof b);
        memset(&j, 0, sizeof j);
        b.data = d;
        b.n = n;
        REQUIRE(ls_image_decode_info(d, n, &info, NULL) == LS_OK);
        j.answer = info.arena_bytes;
        j.name = i < sizeof images / sizeof images[0] ? images[i] : i == sizeof images / sizeof images[0] ? "pfm 3x2" : "pgm 16-bit";
        j.run = run_image;
        j.ctx = &b;
        j.inputs[0] = d;
        j.input_bytes[0] = n;
        j.output = &b.image;
        j.output_bytes = sizeof b.image;
        CHECK_EQ(oom_sweep(&j), 0);
        free(d);
    }
    for (i = 0; i < 2; i++) {
        memset(&b, 0, sizeof b);
        memset(&j, 0, sizeof j);
        b.mitsuba = (int)i;
        b.data = (const unsigned char *)(i ? mitsuba_text : scene_text);
        b.n = i ? sizeof mitsuba_text - 1 : sizeof scene_text - 1;
        if (i)
            REQUIRE(ls_scene_parse_mitsuba_bytes(mitsuba_text, b.n, &j.answer, NULL) == LS_OK);
        else
            REQUIRE(ls_scene_parse_bytes(scene_text, b.n, &j.answer, NULL) == LS_OK);
        j.name = i ? "scene (mitsuba)" : "scene (text)";
        j.run = run_scene;
        j.ctx = &b;
        j.inputs[0] = b.data;
        j.input_bytes[0] = b.n;
        j.output = &b.scene;
        j.output_bytes = sizeof b.scene;
        CHECK_EQ(oom_sweep(&j), 0);
    }
}

/* --- factorization and rendering --------------------------------------- */

static LS_ARENA_BUFFER(setup_mem, 4u << 20);

typedef struct solve_job {
    ls_mesh mesh;
    ls_csc lap, m;
    ls_ldlt f;
    uint32_t method;
    ls_vis vis;
    ls_real mvp[16];
    /* the outputs of the calls swept */
    ls_csc out_csc;
    ls_ldlt out_f;
} solve_job;

static ls_status run_lap(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    return ls_laplacian_uniform(&s->mesh, LS_LAP_UPPER, arena, &s->out_csc, NULL);
}

static ls_status run_system(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    return ls_laplacian_system(&s->lap, LS_SYSTEM_LAMBDA, (ls_real)19, arena, &s->out_csc, NULL);
}

static ls_status run_analyze(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    return ls_ldlt_analyze(&s->m, s->method, NULL, arena, &s->out_f, NULL);
}

static ls_status run_analyze_mesh(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    return ls_ldlt_analyze_mesh(&s->m, s->method, s->mesh.positions, arena, &s->out_f, NULL);
}

/* factor fills the analyzed object: a copy each time; on failure its state
 * and arrays must be as analyzed (else LS_ERR_STATE, which the sweep reports) */
static ls_status run_factor(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    ls_ldlt f = s->f;
    ls_status st = ls_ldlt_factor(&f, &s->m, arena, NULL);
    if (st != LS_OK && (f.state != s->f.state || f.n != s->f.n || f.a_nnz != s->f.a_nnz)) return LS_ERR_STATE;
    return st;
}

static ls_status run_vis(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    ls_vis v;
    ls_status st = ls_vis_init(&v, arena, 24, 16, 2, s->mesh.vertex_count);
    return st;
}

static ls_status run_raster(void *ctx, ls_arena *arena)
{
    solve_job *s = (solve_job *)ctx;
    return ls_raster(&s->vis, &(ls_view){.positions = s->mesh.positions, .indices = s->mesh.triangles,
            .triangle_count = s->mesh.face_count, .vertex_count = s->mesh.vertex_count, .mvp = s->mvp}, arena, NULL);
}

static void sweep_solve(solve_job *s, const char *name, ls_status (*run)(void *, ls_arena *), size_t answer,
                        void *output, size_t output_bytes)
{
    oom_job j;
    memset(&j, 0, sizeof j);
    j.name = name;
    j.run = run;
    j.ctx = s;
    j.answer = answer;
    j.inputs[0] = s->mesh.positions;
    j.input_bytes[0] = 3u * s->mesh.vertex_count * sizeof(ls_real);
    j.inputs[1] = s->mesh.triangles;
    j.input_bytes[1] = 3u * s->mesh.face_count * sizeof(uint32_t);
    if (s->m.values != NULL) {
        j.inputs[2] = s->m.values;
        j.input_bytes[2] = s->m.colptr[s->m.ncols] * sizeof(ls_real);
        j.inputs[3] = s->m.rowidx;
        j.input_bytes[3] = s->m.colptr[s->m.ncols] * sizeof(uint32_t);
    }
    j.output = output;
    j.output_bytes = output_bytes;
    j.max_tries = 8000;
    CHECK_MSG(oom_sweep(&j) == 0, "%s", name);
}

static void factorization_and_raster_at_every_size(void)
{
    static solve_job s;
    ls_arena a;
    ls_real proj[16], view[16];
    const ls_real center[3] = {0, 0, 0}, dir[3] = {(ls_real)0.3, (ls_real)0.5, (ls_real)0.81};
    size_t bytes = 0;
    memset(&s, 0, sizeof s);
    REQUIRE(ls_arena_init(&a, setup_mem.bytes, sizeof setup_mem.bytes) == LS_OK);
    REQUIRE(ls_icosphere(2, &a, &s.mesh) == LS_OK);
    /* the Laplacian and M = I + 19 L */
    REQUIRE(ls_laplacian_uniform(&s.mesh, LS_LAP_UPPER, &a, &s.lap, NULL) == LS_OK);
    {
        ls_arena probe;
        static LS_ARENA_BUFFER(probe_mem, 1u << 20);
        REQUIRE(ls_arena_init(&probe, probe_mem.bytes, sizeof probe_mem.bytes) == LS_OK);
        REQUIRE(ls_laplacian_uniform(&s.mesh, LS_LAP_UPPER, &probe, &s.out_csc, NULL) == LS_OK);
        bytes = probe.peak;
    }
    sweep_solve(&s, "laplacian_uniform", run_lap, bytes, &s.out_csc, sizeof s.out_csc);
    REQUIRE(ls_laplacian_system_bytes(&s.lap, &bytes) == LS_OK);
    sweep_solve(&s, "laplacian_system", run_system, bytes, &s.out_csc, sizeof s.out_csc);
    REQUIRE(ls_laplacian_system(&s.lap, LS_SYSTEM_LAMBDA, (ls_real)19, &a, &s.m, NULL) == LS_OK);
    for (s.method = LS_ORDER_NATURAL; s.method <= LS_ORDER_AMD; s.method++) {
        REQUIRE(ls_ldlt_analyze_bytes(&s.m, s.method, &bytes) == LS_OK);
        sweep_solve(&s, s.method == LS_ORDER_AMD ? "ldlt_analyze (amd)" : "ldlt_analyze (natural)", run_analyze, bytes,
                    &s.out_f, sizeof s.out_f);
    }
    s.method = LS_ORDER_AUTO;
    REQUIRE(ls_ldlt_analyze_mesh_bytes(&s.m, s.method, &bytes) == LS_OK);
    sweep_solve(&s, "ldlt_analyze_mesh (auto)", run_analyze_mesh, bytes, &s.out_f, sizeof s.out_f);
    REQUIRE(ls_ldlt_analyze(&s.m, LS_ORDER_AMD, NULL, &a, &s.f, NULL) == LS_OK);
    REQUIRE(ls_ldlt_bytes(&s.f, &bytes) == LS_OK);
    sweep_solve(&s, "ldlt_factor", run_factor, bytes, NULL, 0);
    /* rendering: the visibility buffer and one raster call */
    REQUIRE(ls_vis_bytes(24, 16, 2, s.mesh.vertex_count, &bytes) == LS_OK);
    sweep_solve(&s, "vis_init", run_vis, bytes, NULL, 0);
    REQUIRE(ls_vis_init(&s.vis, &a, 24, 16, 2, s.mesh.vertex_count) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.9, LS_FOV_X, (ls_real)1.5, (ls_real)0.1, (ls_real)10, proj) == LS_OK);
    REQUIRE(ls_camera_orbit(center, (ls_real)2.5, dir, view) == LS_OK);
    ls_mat4_mul(proj, view, s.mvp);
    REQUIRE(ls_raster_scratch_bytes(&s.vis, &(ls_view){.positions = s.mesh.positions, .indices = s.mesh.triangles,
            .triangle_count = s.mesh.face_count, .vertex_count = s.mesh.vertex_count, .mvp = s.mvp}, &bytes) == LS_OK);
    sweep_solve(&s, "raster", run_raster, bytes, NULL, 0);
}

/* --- a short fit --------------------------------------------------------- */

#define FIT_RES 16u
#define FIT_VIEWS 3u

typedef struct fit_ctx {
    ls_fit_config c;
    ls_fit_views views;
    ls_mesh init;
    ls_real mvps[FIT_VIEWS][16];
    ls_real *targets[FIT_VIEWS];
    ls_real sh[27];
    ls_fit fit;
    size_t fit_bottom; /* bytes at the arena's bottom after ls_fit_init */
} fit_ctx;

static ls_status run_fit_bytes(void *ctx, ls_arena *arena)
{
    fit_ctx *f = (fit_ctx *)ctx;
    size_t bytes = 0;
    return ls_fit_bytes(&f->c, &f->views, &f->init, arena, &bytes, NULL);
}

static ls_status run_fit_init(void *ctx, ls_arena *arena)
{
    fit_ctx *f = (fit_ctx *)ctx;
    ls_fit fit;
    ls_status st = ls_fit_init(&fit, &f->c, &f->views, &f->init, arena, NULL);
    return st;
}

static void fit_setup(fit_ctx *f, ls_arena *a)
{
    ls_mesh target;
    ls_vis vis;
    ls_real dirs[3 * FIT_VIEWS], proj[16], view[16], *normals;
    const ls_real center[3] = {0, 0, 0};
    ls_shade_opts o;
    uint32_t v, i;
    memset(f, 0, sizeof *f);
    memset(f->sh, 0, sizeof f->sh);
    for (v = 0; v < 3; v++) f->sh[9 * v] = (ls_real)1.5, f->sh[9 * v + 1] = (ls_real)0.7;
    REQUIRE(ls_icosphere(2, a, &target) == LS_OK);
    for (i = 0; i < target.vertex_count; i++) target.positions[3 * i + 1] *= (ls_real)0.7;
    normals = (ls_real *)ls_arena_alloc(a, 3u * target.vertex_count, sizeof(ls_real));
    REQUIRE(normals != NULL);
    REQUIRE(ls_shade_vertex_normals(target.positions, target.vertex_count, target.triangles, target.face_count, normals,
                                    NULL) == LS_OK);
    REQUIRE(ls_camera_fibonacci_dirs(FIT_VIEWS, dirs) == LS_OK);
    REQUIRE(ls_camera_perspective((ls_real)0.8, LS_FOV_X, 1, (ls_real)0.1, (ls_real)10, proj) == LS_OK);
    REQUIRE(ls_vis_init(&vis, a, FIT_RES, FIT_RES, 2, target.vertex_count) == LS_OK);
    ls_shade_opts_init(&o);
    o.mode = LS_SHADE_SH;
    o.sh = f->sh;
    for (v = 0; v < FIT_VIEWS; v++) {
        REQUIRE(ls_camera_orbit(center, (ls_real)3.2, dirs + 3 * v, view) == LS_OK);
        ls_mat4_mul(proj, view, f->mvps[v]);
        f->targets[v] = (ls_real *)ls_arena_alloc(a, 4u * FIT_RES * FIT_RES, sizeof(ls_real));
        REQUIRE(f->targets[v] != NULL);
        REQUIRE(ls_raster(&vis, &(ls_view){.positions = target.positions, .indices = target.triangles,
                .triangle_count = target.face_count, .vertex_count = target.vertex_count, .mvp = f->mvps[v]}, a,
                NULL) == LS_OK);
        REQUIRE(ls_shade(&(ls_view){.vis = &vis, .indices = target.triangles, .triangle_count = target.face_count,
                .vertex_count = target.vertex_count, .normals = normals, .opts = &o}, f->targets[v], NULL) ==
                LS_OK);
    }
    REQUIRE(ls_icosphere(1, a, &f->init) == LS_OK);
    for (i = 0; i < 3u * f->init.vertex_count; i++) f->init.positions[i] *= (ls_real)0.6;
    ls_fit_config_default(&f->c);
    f->c.width = f->c.height = FIT_RES;
    f->c.shading.mode = LS_SHADE_SH;
    f->c.shading.sh = f->sh;
    f->c.optim.lr = (ls_real)0.05;
    f->views.count = FIT_VIEWS;
    f->views.mvp = &f->mvps[0][0];
    f->views.targets = (const ls_real *const *)f->targets;
}

static void fit_job_inputs(oom_job *j, const fit_ctx *f)
{
    uint32_t v;
    j->inputs[0] = f->init.positions;
    j->input_bytes[0] = 3u * f->init.vertex_count * sizeof(ls_real);
    j->inputs[1] = f->init.triangles;
    j->input_bytes[1] = 3u * f->init.face_count * sizeof(uint32_t);
    j->inputs[2] = f->mvps;
    j->input_bytes[2] = sizeof f->mvps;
    for (v = 0; v < 1; v++) {
        j->inputs[3] = f->targets[v];
        j->input_bytes[3] = 4u * FIT_RES * FIT_RES * sizeof(ls_real);
    }
}

/* The fit's block (every byte) and its scalar fields (the struct as a whole
 * has padding the library's copies leave undefined, which valgrind flags). */
static uint64_t fit_state_hash(const ls_fit *fit)
{
    uint64_t h = test_hash(fit->block.base, fit->block.capacity, TEST_HASH_SEED);
    const void *ptrs[4];
    uint32_t u[4];
    ls_real r[2];
    size_t z[3];
    ptrs[0] = fit->x, ptrs[1] = fit->u, ptrs[2] = fit->params, ptrs[3] = fit->triangles;
    u[0] = fit->vertex_count, u[1] = fit->face_count, u[2] = fit->iteration, u[3] = fit->remeshes;
    r[0] = fit->loss, r[1] = fit->config.optim.lr;
    z[0] = fit->block.bottom, z[1] = fit->block.top, z[2] = fit->scratch_bytes;
    h = test_hash(ptrs, sizeof ptrs, h);
    h = test_hash(u, sizeof u, h);
    h = test_hash(r, sizeof r, h);
    return test_hash(z, sizeof z, h);
}

static LS_ARENA_BUFFER(fit_mem, 8u << 20);

/* A fit in fit_mem after 3 steps, its cache x = M^-1 u in sync; returns the
 * bytes it holds at the arena's bottom. */
static size_t short_fit(fit_ctx *f, ls_arena *fa)
{
    ls_diag d;
    ls_real *pos;
    ls_mesh cur;
    unsigned char *block;
    size_t base;
    uint32_t it;
    if (ls_arena_init(fa, fit_mem.bytes, sizeof fit_mem.bytes) != LS_OK) return 0;
    if (ls_fit_init(&f->fit, &f->c, &f->views, &f->init, fa, &d) != LS_OK) return 0;
    base = fa->bottom;
    block = f->fit.block.base;
    for (it = 0; it < 3; it++) CHECK_STATUS(ls_fit_step(&f->fit, NULL, &d), LS_OK);
    CHECK(f->fit.block.base == block && fa->bottom == base && fa->top == 0);
    CHECK(f->fit.loss > (ls_real)0);
    /* ls_fit_remesh starts with ls_fit_mesh, which refreshes the cache
     * x = M^-1 u in the fit (stale after a step; the next step recomputes it
     * anyway): sync it here so that a failing remesh must leave every byte */
    pos = (ls_real *)malloc(3u * f->fit.vertex_count * sizeof(ls_real));
    if (pos == NULL) return 0;
    CHECK_STATUS(ls_fit_mesh(&f->fit, pos, &cur), LS_OK);
    free(pos);
    return base;
}

/* ls_fit_remesh with the fit (base bytes at the bottom of fit_mem) plus
 * `size` bytes free: the same buffer, its capacity cut, the fit's bytes taken
 * again from the bottom (ls_arena_alloc does not clear them). On failure the
 * fit (struct and block, every byte) and the arena must be as before. */
static ls_status remesh_once(fit_ctx *f, ls_arena *fa, size_t base, size_t size, size_t *need, size_t *problems)
{
    uint64_t before = fit_state_hash(&f->fit), after;
    ls_arena_mark mark;
    ls_diag d;
    ls_status st;
    if (ls_arena_init(fa, fit_mem.bytes, base + size) != LS_OK || ls_arena_alloc(fa, 1, base) != fit_mem.bytes) {
        (*problems)++;
        return LS_ERR_INVALID;
    }
    mark = ls_arena_save(fa);
    st = ls_fit_remesh(&f->fit, fa, (ls_real)0.5, (ls_real)0.8, NULL, &d);
    if (st == LS_OK) return st;
    after = fit_state_hash(&f->fit);
    *need = fa->need > base ? fa->need - base : 0;
    if (st != LS_ERR_NOMEM || after != before || fa->bottom != mark.bottom || fa->top != mark.top || *need <= size) {
        (*problems)++;
        printf("     fit_remesh: size %lu: %s, fit %s, arena %lu+%lu (mark %lu+0), need %lu\n", (unsigned long)size,
               ls_status_name(st), after == before ? "unchanged" : "CHANGED", (unsigned long)fa->bottom,
               (unsigned long)fa->top, (unsigned long)mark.bottom, (unsigned long)*need);
    }
    return st;
}

static void short_fit_at_every_allocation_point(void)
{
    static fit_ctx f;
    ls_arena a, scratch, fa;
    oom_job j;
    size_t answer = 0, init_bytes = 0, size, base, tries = 0, chain, need = 0, problems = 0;
    ls_diag d;
    REQUIRE(ls_arena_init(&a, setup_mem.bytes, sizeof setup_mem.bytes) == LS_OK);
    fit_setup(&f, &a);
    /* ls_fit_bytes runs the symbolic analysis in the caller's scratch */
    REQUIRE(ls_arena_init(&scratch, fit_mem.bytes, sizeof fit_mem.bytes) == LS_OK);
    REQUIRE(ls_fit_bytes(&f.c, &f.views, &f.init, &scratch, &init_bytes, NULL) == LS_OK);
    CHECK_EQ(ls_arena_used(&scratch), 0);
    memset(&j, 0, sizeof j);
    j.name = "fit_bytes (scratch)";
    j.run = run_fit_bytes;
    j.ctx = &f;
    j.answer = scratch.peak;
    fit_job_inputs(&j, &f);
    j.max_tries = 3000;
    CHECK_EQ(oom_sweep(&j), 0);
    /* ls_fit_init */
    j.name = "fit_init";
    j.run = run_fit_init;
    j.answer = init_bytes;
    j.max_tries = 1500;
    CHECK_EQ(oom_sweep(&j), 0);
    /* a few steps (no arena: the fit's block must stay where it is), then the
     * remesh at every allocation point (the arena's need chain, which ends at
     * the answer), then a second, identical fit at every stride-th size below
     * that answer, then the remesh at the answer */
    base = short_fit(&f, &fa);
    answer = 0;
    size = 0;
    for (;;) {
        ls_status st;
        if (base + size > sizeof fit_mem.bytes) break;
        st = remesh_once(&f, &fa, base, size, &need, &problems);
        tries++;
        if (st == LS_OK) {
            answer = size;
            break;
        }
        if (st != LS_ERR_NOMEM || need <= size) break;
        size = need;
    }
    chain = tries;
    if (answer > 0) {
        size_t stride = LS_ARENA_ROUND(answer / (emulated_tries != 0 ? 40u : 400u));
        CHECK_EQ(short_fit(&f, &fa), base);
        for (size = 0; size < answer && problems == 0; size += stride) {
            CHECK_STATUS(remesh_once(&f, &fa, base, size, &need, &problems), LS_ERR_NOMEM);
            tries++;
        }
        CHECK_STATUS(remesh_once(&f, &fa, base, answer, &need, &problems), LS_OK);
        printf("     fit_remesh after 3 steps: answer fit + %lu bytes, %lu runs (%lu allocation points, then stride %lu)\n",
               (unsigned long)answer, (unsigned long)tries + 1u, (unsigned long)chain, (unsigned long)stride);
    }
    CHECK_EQ(problems, 0);
    CHECK(answer > 0);
    CHECK_EQ(f.fit.remeshes, 1);
    CHECK(f.fit.vertex_count > f.init.vertex_count);
    /* and a step after the remesh works */
    CHECK_STATUS(ls_fit_step(&f.fit, NULL, &d), LS_OK);
}

int main(void)
{
    const char *emu = getenv("LS_TEST_EMULATED");
    TEST_INIT("test_oom");
    if (emu != NULL && emu[0] == '1') emulated_tries = EMULATED_TRIES;
    TEST_RUN(parsers_at_every_size);
    TEST_RUN(factorization_and_raster_at_every_size);
    TEST_RUN(short_fit_at_every_allocation_point);
    return TEST_END();
}
