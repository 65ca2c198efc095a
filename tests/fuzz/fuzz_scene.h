/* tests/fuzz/fuzz_scene.h - the scene-parser harness, included by
 * fuzz_scene.c (text scenes) and fuzz_mitsuba.c (the Mitsuba XML subset)
 * with FUZZ_SCENE_BYTES / FUZZ_SCENE_PARSE naming the sizing query and the
 * parser.
 *
 * Input: the selector byte (fuzz_common.h), then the scene text. Checks,
 * besides the common invariants: the parser fails with the sizing query's
 * status when that fails; in an arena of the query's answer it does not fail
 * with LS_ERR_NOMEM and takes exactly that many bytes, in less it does not
 * succeed. On success: resolution 1..65536 per side, 1..LS_SCENE_MAX_VIEWS
 * cameras inside the arena, each with a finite view matrix, a field of view
 * in (0, pi), finite clip planes 0 < near < far and a projection that
 * ls_scene_projection computes finite; lighting, target and initial fields
 * hold known values; every path is a NUL-terminated string in the arena; the
 * SH coefficients, background and environment scale are finite. With
 * FUZZ_SCENE_DATASET (camera datasets): the resolution may be 0 x 0 (the
 * images give it; no projection then), the lighting unknown, and each
 * camera's principal point lies inside the image.
 */
#ifndef LS_FUZZ_SCENE_H
#define LS_FUZZ_SCENE_H

#include "fuzz_common.h"

static void check_path(const char *p, const fuzz_arena *fa, int may_be_null)
{
    if (p == NULL) {
        FUZZ_ASSERT(may_be_null);
        return;
    }
    FUZZ_ASSERT(fuzz_cstring_in(p, fa->buf, fa->buf + fa->arena.capacity));
}

static void check_scene(const ls_scene *s, const fuzz_arena *fa)
{
    uint32_t v, k;
    ls_real proj[16];
    int sized = 1;
#ifdef FUZZ_SCENE_DATASET
    sized = s->width != 0;
    if (!sized) FUZZ_ASSERT(s->height == 0);
#endif
    if (sized) FUZZ_ASSERT(s->width >= 1 && s->width <= 65536u && s->height >= 1 && s->height <= 65536u);
    FUZZ_ASSERT(s->camera_count >= 1 && s->camera_count <= LS_SCENE_MAX_VIEWS);
    FUZZ_ASSERT((const unsigned char *)s->cameras >= fa->buf &&
                (const unsigned char *)(s->cameras + s->camera_count) <= fa->buf + fa->arena.capacity);
    for (v = 0; v < s->camera_count; v++) {
        const ls_scene_camera *c = &s->cameras[v];
        for (k = 0; k < 16; k++) FUZZ_ASSERT(fuzz_finite_real(c->view[k]));
        FUZZ_ASSERT(c->fov > (ls_real)0 && c->fov < (ls_real)3.1415927);
        FUZZ_ASSERT(c->fov_axis == LS_FOV_X || c->fov_axis == LS_FOV_Y);
        FUZZ_ASSERT(c->near_plane > (ls_real)0 && c->far_plane > c->near_plane && fuzz_finite_real(c->far_plane));
        check_path(c->image, fa, 1);
        for (k = 0; k < 2; k++) FUZZ_ASSERT(c->center[k] > (ls_real)-1 && c->center[k] < (ls_real)1);
        if (!sized) continue;
        FUZZ_ASSERT(ls_scene_projection(s, v, proj) == LS_OK);
        for (k = 0; k < 16; k++) FUZZ_ASSERT(fuzz_finite_real(proj[k]));
    }
    FUZZ_ASSERT(s->lighting == LS_SCENE_LIGHT_MASK || s->lighting == LS_SCENE_LIGHT_SH ||
                s->lighting == LS_SCENE_LIGHT_ENVMAP || s->lighting == LS_SCENE_LIGHT_UNKNOWN);
    if (s->lighting == LS_SCENE_LIGHT_SH)
        for (k = 0; k < 27; k++) FUZZ_ASSERT(fuzz_finite_real(s->sh[k]));
    if (s->lighting == LS_SCENE_LIGHT_ENVMAP) {
        check_path(s->envmap, fa, 0);
        FUZZ_ASSERT(fuzz_finite_real(s->envmap_scale));
    }
    for (k = 0; k < 3; k++) FUZZ_ASSERT(fuzz_finite_real(s->background[k]));
    FUZZ_ASSERT(s->target == LS_SCENE_TARGET_MESH || s->target == LS_SCENE_TARGET_IMAGES);
    if (s->target == LS_SCENE_TARGET_MESH) check_path(s->target_mesh, fa, 0);
    FUZZ_ASSERT(s->initial == LS_SCENE_INITIAL_ICOSPHERE || s->initial == LS_SCENE_INITIAL_MESH);
    if (s->initial == LS_SCENE_INITIAL_MESH) check_path(s->initial_mesh, fa, 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ls_scene scene, before;
    ls_diag diag, size_diag;
    ls_status size_st, st;
    fuzz_arena fa;
    size_t need = 0;
    const char *text;
    if (size < 1) return 0;
    text = (const char *)(data + 1);
    size--;
    ls_diag_clear(&size_diag);
    size_st = FUZZ_SCENE_BYTES(text, size, &need, &size_diag);
    FUZZ_ASSERT(size_st >= LS_OK && size_st < LS_STATUS_COUNT && size_st != LS_ERR_NOMEM);
    if (size_st != LS_OK) {
        need = 0;
        FUZZ_ASSERT(size_diag.what != NULL && size_diag.what[0] != '\0' && size_diag.status == size_st);
    }
    fuzz_arena_open(&fa, data[0], need);
    memset(&scene, 0x5A, sizeof scene);
    before = scene;
    ls_diag_clear(&diag);
    st = FUZZ_SCENE_PARSE(text, size, &fa.arena, &scene, &diag);
    fuzz_check_status(size_st, st, &fa, 0);
    if (st != LS_OK) {
        fuzz_check_failure(st, &diag, &fa, &scene, &before, sizeof scene);
    } else {
        FUZZ_ASSERT(fuzz_arena_peak(&fa) == need);
        check_scene(&scene, &fa);
    }
    fuzz_arena_close(&fa);
    return 0;
}

#endif /* LS_FUZZ_SCENE_H */
