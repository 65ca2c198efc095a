/* scene_internal.h - what the two scene readers (scene.c: text format,
 * scene_mitsuba.c: Mitsuba XML) share: a builder that first counts (cameras,
 * path bytes, scratch) and then writes into exactly that much arena, number
 * parsing in the build's precision, and error reporting with positions. */
#ifndef LS_SCENE_INTERNAL_H
#define LS_SCENE_INTERNAL_H

#include <largesteps/scene.h>

typedef struct ls_scene_builder {
    int measure;            /* 1: first pass, count only */
    ls_scene *scene;        /* the scene being filled (both passes) */
    uint32_t cameras_cap;   /* second pass: cameras allocated */
    size_t strings_cap;     /* second pass: bytes allocated for paths */
    size_t strings_used;    /* bytes of paths so far (both passes) */
    char *strings;          /* second pass: the paths block */
    size_t scratch_max;     /* largest scratch request (both passes) */
    ls_scene_camera dummy;  /* first pass: where cameras are written */
    ls_arena *arena;        /* second pass: for scratch */
    const char *text;       /* the input, for positions in diagnostics */
} ls_scene_builder;

/* Sets the scene's defaults (no cameras, mask lighting, icosphere level 3). */
void ls_scene_defaults(ls_scene *scene);

/* The next camera slot (count incremented), or NULL past LS_SCENE_MAX_VIEWS. */
ls_scene_camera *ls_scene_add_camera(ls_scene_builder *b);

/* A NUL-terminated copy of text[0..len) in the paths block. */
const char *ls_scene_add_string(ls_scene_builder *b, const char *text, size_t len);

/* Parses text[0..len) as a number of the build's precision; 0 on failure. */
int ls_scene_number(const char *text, size_t len, ls_real *out);

/* LS_ERR_PARSE with the 1-based line and column of `at` in b->text. */
ls_status ls_scene_error(const ls_scene_builder *b, const char *at, const char *what, ls_diag *diag);

/* Compares text[0..len) with the NUL-terminated word. */
int ls_scene_word_is(const char *text, size_t len, const char *word);

/* 1 when a camera with this fov (radians, on axis fov_axis) and these clip
 * planes has a finite projection at every aspect a scene can have (1/65536 to
 * 65536): the check both readers make before accepting a camera. */
int ls_scene_projection_ok(ls_real fov, uint32_t fov_axis, ls_real near_plane, ls_real far_plane);

/* The input of a reader pass. */
typedef struct ls_scene_input {
    const char *text;
    size_t length;
} ls_scene_input;

/* Runs `pass` twice (count, then write) and fills *scene; or only counts
 * (arena NULL: *bytes receives the exact total). Six arguments: a seventh
 * would go on the stack, which the call-graph check counts as dynamic. */
typedef ls_status (*ls_scene_pass_fn)(ls_scene_builder *b, const char *text, size_t length, ls_diag *diag);
ls_status ls_scene_run(ls_scene_pass_fn pass, const ls_scene_input *in, ls_arena *arena, ls_scene *scene, size_t *bytes,
                       ls_diag *diag);

#endif /* LS_SCENE_INTERNAL_H */
