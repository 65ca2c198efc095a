/* scene.c - the scene builder shared by both readers, and the text scene
 * format (documented in include/largesteps/scene.h). */
#include <string.h>
#include <largesteps/scene.h>
#include <largesteps/camera.h>
#include <largesteps/number.h>
#include <largesteps/math.h>
#include "scene_internal.h"

#define R_PI ((ls_real)3.14159265358979323846)
#define MAX_TOKENS 40u /* "lighting sh" and 27 values, with room to report extras */

/* ---- the builder -------------------------------------------------------- */

void ls_scene_defaults(ls_scene *s)
{
    memset(s, 0, sizeof *s);
    s->lighting = LS_SCENE_LIGHT_MASK;
    s->envmap_scale = (ls_real)1;
    s->initial = LS_SCENE_INITIAL_ICOSPHERE;
    s->initial_level = 3;
}

ls_scene_camera *ls_scene_add_camera(ls_scene_builder *b)
{
    ls_scene *s = b->scene;
    if (s->camera_count >= LS_SCENE_MAX_VIEWS) return NULL;
    if (b->measure) {
        s->camera_count++;
        memset(&b->dummy, 0, sizeof b->dummy);
        return &b->dummy;
    }
    if (s->camera_count >= b->cameras_cap) return NULL; /* not reached: pass 1 counted them */
    memset(&s->cameras[s->camera_count], 0, sizeof s->cameras[0]);
    return &s->cameras[s->camera_count++];
}

const char *ls_scene_add_string(ls_scene_builder *b, const char *text, size_t len)
{
    char *out;
    if (b->measure) {
        b->strings_used += len + 1u;
        return "";
    }
    if (len + 1u > b->strings_cap - b->strings_used) return ""; /* not reached: pass 1 counted them */
    out = b->strings + b->strings_used;
    if (len > 0) memcpy(out, text, len);
    out[len] = '\0';
    b->strings_used += len + 1u;
    return out;
}

int ls_scene_number(const char *text, size_t len, ls_real *out)
{
#if LS_REAL_IS_FLOAT
    float v;
    if (ls_parse_float(text, len, &v) != LS_OK) return 0;
#else
    double v;
    if (ls_parse_double(text, len, &v) != LS_OK) return 0;
#endif
    *out = v;
    return 1;
}

ls_status ls_scene_error(const ls_scene_builder *b, const char *at, const char *what, ls_diag *diag)
{
    if (diag != NULL) {
        const char *p = b->text;
        uint32_t line = 1, col = 1;
        for (; p < at; p++) {
            if (*p == '\n') {
                line++;
                col = 1;
            } else {
                col++;
            }
        }
        ls_diag_clear(diag);
        diag->status = LS_ERR_PARSE;
        diag->has_line = 1;
        diag->line = line;
        diag->column = col;
        diag->has_offset = 1;
        diag->offset = (uint64_t)(at - b->text);
        diag->what = what;
    }
    return LS_ERR_PARSE;
}

int ls_scene_word_is(const char *text, size_t len, const char *word)
{
    size_t i;
    for (i = 0; i < len; i++)
        if (word[i] == '\0' || word[i] != text[i]) return 0;
    return word[len] == '\0';
}

ls_status ls_scene_run(ls_scene_pass_fn pass, const ls_scene_input *in, ls_arena *arena, ls_scene *scene, size_t *bytes,
                       ls_diag *diag)
{
    const char *text = in->text;
    size_t length = in->length;
    ls_scene_builder b;
    ls_scene s;
    ls_arena_mark mark;
    ls_size size;
    size_t total;
    ls_status st;
    if (text == NULL && length > 0)
        return ls_diag_set(diag, LS_ERR_INVALID, "text is NULL with length > 0", LS_DIAG_NO_INDEX);
    memset(&b, 0, sizeof b);
    b.measure = 1;
    b.scene = &s;
    b.text = text;
    ls_scene_defaults(&s);
    st = pass(&b, text, length, diag);
    if (st != LS_OK) return st;
    ls_size_init(&size);
    ls_size_add(&size, s.camera_count, sizeof(ls_scene_camera));
    ls_size_add(&size, b.strings_used, 1);
    ls_size_add(&size, b.scratch_max, 1);
    st = ls_size_get(&size, &total);
    if (st != LS_OK) return st;
    if (arena == NULL) {
        *bytes = total;
        return LS_OK;
    }
    mark = ls_arena_save(arena);
    b.cameras_cap = s.camera_count;
    b.strings_cap = b.strings_used;
    ls_scene_defaults(&s);
    s.cameras = (ls_scene_camera *)ls_arena_alloc(arena, b.cameras_cap, sizeof(ls_scene_camera));
    b.strings = (char *)ls_arena_alloc(arena, b.strings_cap, 1);
    if (s.cameras == NULL || b.strings == NULL) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    b.measure = 0;
    b.strings_used = 0;
    b.arena = arena;
    st = pass(&b, text, length, diag);
    if (st != LS_OK) { /* only scratch can fail now */
        ls_arena_restore(arena, mark);
        return st;
    }
    *scene = s;
    return LS_OK;
}

int ls_scene_projection_ok(ls_real fov, uint32_t fov_axis, ls_real near_plane, ls_real far_plane)
{
    ls_real proj[16];
    return ls_camera_perspective(fov, fov_axis, (ls_real)65536, near_plane, far_plane, proj) == LS_OK &&
           ls_camera_perspective(fov, fov_axis, (ls_real)1 / (ls_real)65536, near_plane, far_plane, proj) == LS_OK;
}

ls_status ls_scene_projection(const ls_scene *scene, uint32_t index, ls_real proj[16])
{
    const ls_scene_camera *c;
    ls_status st;
    if (scene == NULL || proj == NULL || index >= scene->camera_count || scene->height == 0 || scene->width == 0)
        return LS_ERR_INVALID;
    c = &scene->cameras[index];
    st = ls_camera_perspective(c->fov, c->fov_axis, (ls_real)scene->width / (ls_real)scene->height, c->near_plane,
                               c->far_plane, proj);
    /* NDC x' = x + cx: X' = X + cx W with W = -z_view */
    if (st == LS_OK && (c->center[0] != (ls_real)0 || c->center[1] != (ls_real)0)) {
        proj[2] -= c->center[0];
        proj[6] -= c->center[1];
    }
    return st;
}

/* ---- the text format ----------------------------------------------------- */

typedef struct token {
    uint32_t off; /* offset in the text */
    uint32_t len;
} token;

typedef struct text_state {
    ls_real fov, near_plane, far_plane;
    uint32_t fov_axis;
    int header, resolution, lighting, background, target, initial;
    uint32_t images;         /* cameras with an image */
    uint32_t last_image_cam; /* 1 + the camera that got the last image (0: none) */
} text_state;

static int tok_is(const char *text, const token *t, const char *word)
{
    return ls_scene_word_is(text + t->off, t->len, word);
}

/* Splits one line into tokens (quoted tokens keep their spaces, without the
 * quotes); returns the count, or MAX_TOKENS + 1 for too many, or
 * MAX_TOKENS + 2 for an unterminated quote (*bad = its position). */
static uint32_t split_line(const char *text, size_t begin, size_t end, token *tok, size_t *bad)
{
    uint32_t n = 0;
    size_t i = begin;
    while (i < end) {
        size_t start;
        char c = text[i];
        if (c == ' ' || c == '\t' || c == '\r') {
            i++;
            continue;
        }
        if (c == '#') break;
        if (n == MAX_TOKENS) return MAX_TOKENS + 1u;
        if (c == '"') {
            start = ++i;
            while (i < end && text[i] != '"') i++;
            if (i >= end) {
                *bad = start - 1u;
                return MAX_TOKENS + 2u;
            }
            tok[n].off = (uint32_t)start;
            tok[n].len = (uint32_t)(i - start);
            i++;
        } else {
            start = i;
            while (i < end && text[i] != ' ' && text[i] != '\t' && text[i] != '\r' && text[i] != '#') i++;
            tok[n].off = (uint32_t)start;
            tok[n].len = (uint32_t)(i - start);
        }
        n++;
    }
    return n;
}

/* Reads `count` numbers from tokens first.. into out; 0 on a bad one (*bad). */
static int numbers(const char *text, const token *tok, uint32_t first, uint32_t count, ls_real *out, uint32_t *bad)
{
    uint32_t i;
    for (i = 0; i < count; i++) {
        if (!ls_scene_number(text + tok[first + i].off, tok[first + i].len, &out[i])) {
            *bad = first + i;
            return 0;
        }
    }
    return 1;
}

static int finite_r(ls_real x) { return x - x == x - x; }

/* A whole positive integer token (1 .. max). */
static int count_value(const char *text, const token *t, uint32_t max, uint32_t *out)
{
    uint32_t v = 0, i;
    if (t->len == 0 || t->len > 10) return 0;
    for (i = 0; i < t->len; i++) {
        char c = text[t->off + i];
        if (c < '0' || c > '9') return 0;
        if (v > (UINT32_MAX - 9u) / 10u) return 0;
        v = v * 10u + (uint32_t)(c - '0');
    }
    if (v == 0 || v > max) return 0;
    *out = v;
    return 1;
}

static ls_status set_camera(ls_scene_builder *b, const text_state *ts, const char *at, const ls_real view[16],
                            ls_diag *diag)
{
    ls_scene_camera *c;
    if (!ls_scene_projection_ok(ts->fov, ts->fov_axis, ts->near_plane, ts->far_plane))
        return ls_scene_error(b, at, "camera: fov and clip planes give a projection that overflows", diag);
    c = ls_scene_add_camera(b);
    if (c == NULL) return ls_scene_error(b, at, "more cameras than LS_SCENE_MAX_VIEWS", diag);
    memcpy(c->view, view, sizeof c->view);
    c->fov = ts->fov;
    c->fov_axis = ts->fov_axis;
    c->near_plane = ts->near_plane;
    c->far_plane = ts->far_plane;
    return LS_OK;
}

/* views fibonacci N D [C] | views rings R P D [C] */
static ls_status views_statement(ls_scene_builder *b, text_state *ts, const char *text, const token *tok, uint32_t n,
                                 ls_diag *diag)
{
    int rings = tok_is(text, &tok[1], "rings");
    uint32_t nums = rings ? 3u : 2u, r = 1, p = 0, count, i, bad = 0;
    ls_real dist, center[3] = {0, 0, 0}, *dirs;
    ls_arena_mark mark;
    ls_status st = LS_OK;
    size_t need;
    if (!rings && !tok_is(text, &tok[1], "fibonacci"))
        return ls_scene_error(b, text + tok[1].off, "views: expected 'fibonacci' or 'rings'", diag);
    if (n != 2u + nums && n != 5u + nums)
        return ls_scene_error(b, text + tok[0].off, "views: wrong number of values", diag);
    if (!count_value(text, &tok[2], LS_SCENE_MAX_VIEWS, rings ? &r : &p) ||
        (rings && !count_value(text, &tok[3], LS_SCENE_MAX_VIEWS, &p)))
        return ls_scene_error(b, text + tok[2].off, "views: counts must be whole numbers from 1 to 4096", diag);
    if ((uint64_t)r * p > LS_SCENE_MAX_VIEWS)
        return ls_scene_error(b, text + tok[2].off, "views: more cameras than LS_SCENE_MAX_VIEWS", diag);
    count = r * p;
    if (!numbers(text, tok, 1u + nums, 1, &dist, &bad) || !(dist > (ls_real)0) || !finite_r(dist))
        return ls_scene_error(b, text + tok[1u + nums].off, "views: the distance must be a positive number", diag);
    if (n == 5u + nums && !numbers(text, tok, 2u + nums, 3, center, &bad))
        return ls_scene_error(b, text + tok[bad].off, "views: bad centre coordinate", diag);
    need = 3u * (size_t)count * sizeof(ls_real);
    if (need > b->scratch_max) b->scratch_max = need;
    if (b->measure) {
        for (i = 0; i < count; i++)
            if (ls_scene_add_camera(b) == NULL) return ls_scene_error(b, text + tok[0].off, "more cameras than LS_SCENE_MAX_VIEWS", diag);
        return LS_OK;
    }
    mark = ls_arena_save(b->arena);
    dirs = (ls_real *)ls_arena_scratch(b->arena, 3u * (size_t)count, sizeof(ls_real));
    if (dirs == NULL) return LS_ERR_NOMEM;
    if (rings)
        (void)ls_camera_ring_dirs(r, p, dirs);
    else
        (void)ls_camera_fibonacci_dirs(p, dirs);
    for (i = 0; i < count && st == LS_OK; i++) {
        ls_real view[16];
        if (ls_camera_orbit(center, dist, dirs + 3u * (size_t)i, view) != LS_OK)
            st = ls_scene_error(b, text + tok[0].off, "views: a camera could not be placed", diag);
        else
            st = set_camera(b, ts, text + tok[0].off, view, diag);
    }
    ls_arena_restore(b->arena, mark);
    return st;
}

static ls_status camera_statement(ls_scene_builder *b, text_state *ts, const char *text, const token *tok, uint32_t n,
                                  ls_diag *diag)
{
    ls_real v[9] = {0, 0, 0, 0, 0, 0, 0, 1, 0}, view[16];
    uint32_t bad = 0;
    if (n != 7u && n != 10u) return ls_scene_error(b, text + tok[0].off, "camera: expected 6 or 9 numbers", diag);
    if (!numbers(text, tok, 1, n - 1u, v, &bad)) return ls_scene_error(b, text + tok[bad].off, "camera: bad number", diag);
    if (ls_camera_look_at(v, v + 3, v + 6, view) != LS_OK)
        return ls_scene_error(b, text + tok[0].off, "camera: eye equals target, up is parallel to the view, or not finite", diag);
    return set_camera(b, ts, text + tok[0].off, view, diag);
}

static ls_status lighting_statement(ls_scene_builder *b, const char *text, const token *tok, uint32_t n,
                                    ls_diag *diag)
{
    ls_scene *s = b->scene;
    uint32_t bad = 0;
    if (n >= 2 && tok_is(text, &tok[1], "mask")) {
        if (n != 2) return ls_scene_error(b, text + tok[2].off, "lighting mask: unexpected value", diag);
        s->lighting = LS_SCENE_LIGHT_MASK;
    } else if (n >= 2 && tok_is(text, &tok[1], "sh")) {
        if (n != 29) return ls_scene_error(b, text + tok[0].off, "lighting sh: expected 27 numbers", diag);
        if (!numbers(text, tok, 2, 27, s->sh, &bad)) return ls_scene_error(b, text + tok[bad].off, "lighting sh: bad number", diag);
        s->lighting = LS_SCENE_LIGHT_SH;
    } else if (n >= 2 && tok_is(text, &tok[1], "envmap")) {
        if (n != 3 && n != 4) return ls_scene_error(b, text + tok[0].off, "lighting envmap: expected PATH [SCALE]", diag);
        if (n == 4 && (!numbers(text, tok, 3, 1, &s->envmap_scale, &bad) || !(s->envmap_scale >= (ls_real)0) ||
                       !finite_r(s->envmap_scale)))
            return ls_scene_error(b, text + tok[3].off, "lighting envmap: the scale must be a number >= 0", diag);
        s->envmap = ls_scene_add_string(b, text + tok[2].off, tok[2].len);
        s->lighting = LS_SCENE_LIGHT_ENVMAP;
    } else {
        return ls_scene_error(b, text + tok[n > 1 ? 1 : 0].off, "lighting: expected mask, sh or envmap", diag);
    }
    return LS_OK;
}

static ls_status target_initial_statement(ls_scene_builder *b, const char *text, const token *tok, uint32_t n,
                                          int target, ls_diag *diag)
{
    ls_scene *s = b->scene;
    uint32_t level = 0;
    if (n >= 2 && tok_is(text, &tok[1], "mesh")) {
        if (n != 3) return ls_scene_error(b, text + tok[0].off, "expected 'mesh PATH'", diag);
        if (target) {
            s->target = LS_SCENE_TARGET_MESH;
            s->target_mesh = ls_scene_add_string(b, text + tok[2].off, tok[2].len);
        } else {
            s->initial = LS_SCENE_INITIAL_MESH;
            s->initial_mesh = ls_scene_add_string(b, text + tok[2].off, tok[2].len);
        }
        return LS_OK;
    }
    if (target && n == 2 && tok_is(text, &tok[1], "images")) {
        s->target = LS_SCENE_TARGET_IMAGES;
        return LS_OK;
    }
    if (!target && n == 3 && tok_is(text, &tok[1], "icosphere")) {
        if (tok_is(text, &tok[2], "0"))
            level = 0;
        else if (!count_value(text, &tok[2], 9, &level))
            return ls_scene_error(b, text + tok[2].off, "initial icosphere: the level must be 0 to 9", diag);
        s->initial = LS_SCENE_INITIAL_ICOSPHERE;
        s->initial_level = level;
        return LS_OK;
    }
    return ls_scene_error(b, text + tok[n > 1 ? 1 : 0].off,
                          target ? "target: expected 'mesh PATH' or 'images'" : "initial: expected 'mesh PATH' or 'icosphere LEVEL'",
                          diag);
}

/* Statements that set a value once. */
static ls_status once(ls_scene_builder *b, int *flag, const char *at, ls_diag *diag)
{
    if (*flag) return ls_scene_error(b, at, "statement given twice", diag);
    *flag = 1;
    return LS_OK;
}

static ls_status statement(ls_scene_builder *b, text_state *ts, const char *text, const token *tok, uint32_t n,
                           ls_diag *diag)
{
    ls_scene *s = b->scene;
    const char *at = text + tok[0].off;
    ls_real v[3];
    uint32_t bad = 0;
    ls_status st;
    if (!ts->header) {
        if (n == 2 && tok_is(text, &tok[0], "largesteps-scene") && tok_is(text, &tok[1], "1")) {
            ts->header = 1;
            return LS_OK;
        }
        return ls_scene_error(b, at, "the first statement must be 'largesteps-scene 1'", diag);
    }
    if (tok_is(text, &tok[0], "resolution")) {
        if ((st = once(b, &ts->resolution, at, diag)) != LS_OK) return st;
        if (n != 3 || !count_value(text, &tok[1], 65536, &s->width) || !count_value(text, &tok[2], 65536, &s->height))
            return ls_scene_error(b, at, "resolution: expected two whole numbers from 1 to 65536", diag);
        return LS_OK;
    }
    if (tok_is(text, &tok[0], "fov")) {
        if (n != 2 && n != 3) return ls_scene_error(b, at, "fov: expected DEGREES [x|y]", diag);
        if (!numbers(text, tok, 1, 1, v, &bad) || !(v[0] > (ls_real)0) || !(v[0] < (ls_real)180))
            return ls_scene_error(b, text + tok[1].off, "fov: degrees must lie in (0, 180)", diag);
        ts->fov = v[0] * R_PI / (ls_real)180;
        ts->fov_axis = LS_FOV_X;
        if (n == 3) {
            if (tok_is(text, &tok[2], "y"))
                ts->fov_axis = LS_FOV_Y;
            else if (!tok_is(text, &tok[2], "x"))
                return ls_scene_error(b, text + tok[2].off, "fov: the axis must be x or y", diag);
        }
        return LS_OK;
    }
    if (tok_is(text, &tok[0], "clip")) {
        if (n != 3 || !numbers(text, tok, 1, 2, v, &bad) || !(v[0] > (ls_real)0) || !(v[1] > v[0]) || !finite_r(v[1]))
            return ls_scene_error(b, at, "clip: expected NEAR FAR with 0 < NEAR < FAR", diag);
        ts->near_plane = v[0];
        ts->far_plane = v[1];
        return LS_OK;
    }
    if (tok_is(text, &tok[0], "camera")) return camera_statement(b, ts, text, tok, n, diag);
    if (tok_is(text, &tok[0], "views")) {
        if (n < 2) return ls_scene_error(b, at, "views: expected 'fibonacci' or 'rings'", diag);
        return views_statement(b, ts, text, tok, n, diag);
    }
    if (tok_is(text, &tok[0], "image")) {
        if (n != 2) return ls_scene_error(b, at, "image: expected PATH", diag);
        if (s->camera_count == 0) return ls_scene_error(b, at, "image: no camera before it", diag);
        if (ts->last_image_cam == s->camera_count) return ls_scene_error(b, at, "image: the camera has one already", diag);
        ts->last_image_cam = s->camera_count;
        ts->images++;
        if (b->measure)
            (void)ls_scene_add_string(b, text + tok[1].off, tok[1].len);
        else
            s->cameras[s->camera_count - 1u].image = ls_scene_add_string(b, text + tok[1].off, tok[1].len);
        return LS_OK;
    }
    if (tok_is(text, &tok[0], "lighting")) {
        if ((st = once(b, &ts->lighting, at, diag)) != LS_OK) return st;
        return lighting_statement(b, text, tok, n, diag);
    }
    if (tok_is(text, &tok[0], "background")) {
        if ((st = once(b, &ts->background, at, diag)) != LS_OK) return st;
        if (n != 4 || !numbers(text, tok, 1, 3, s->background, &bad) || !finite_r(s->background[0]) ||
            !finite_r(s->background[1]) || !finite_r(s->background[2]))
            return ls_scene_error(b, at, "background: expected R G B (finite numbers)", diag);
        return LS_OK;
    }
    if (tok_is(text, &tok[0], "target")) {
        if ((st = once(b, &ts->target, at, diag)) != LS_OK) return st;
        return target_initial_statement(b, text, tok, n, 1, diag);
    }
    if (tok_is(text, &tok[0], "initial")) {
        if ((st = once(b, &ts->initial, at, diag)) != LS_OK) return st;
        return target_initial_statement(b, text, tok, n, 0, diag);
    }
    return ls_scene_error(b, at, "unknown statement", diag);
}

static ls_status text_pass(ls_scene_builder *b, const char *text, size_t length, ls_diag *diag)
{
    token tok[MAX_TOKENS];
    text_state ts;
    size_t begin = 0;
    uint32_t i;
    ls_status st;
    if (length > UINT32_MAX) return LS_ERR_TOO_LARGE;
    memset(&ts, 0, sizeof ts);
    ts.fov = (ls_real)45 * R_PI / (ls_real)180;
    ts.fov_axis = LS_FOV_X;
    ts.near_plane = (ls_real)0.01;
    ts.far_plane = (ls_real)100;
    while (begin < length) {
        size_t end = begin, bad = 0;
        uint32_t n;
        while (end < length && text[end] != '\n') end++;
        for (i = (uint32_t)begin; i < end; i++)
            if (text[i] == '\0') return ls_scene_error(b, text + i, "NUL byte in the scene text", diag);
        n = split_line(text, begin, end, tok, &bad);
        if (n == MAX_TOKENS + 1u) return ls_scene_error(b, text + begin, "too many values on one line", diag);
        if (n == MAX_TOKENS + 2u) return ls_scene_error(b, text + bad, "unterminated quote", diag);
        if (n > 0) {
            st = statement(b, &ts, text, tok, n, diag);
            if (st != LS_OK) return st;
        }
        begin = end + 1u;
    }
    if (!ts.header) return ls_scene_error(b, text + length, "empty scene: 'largesteps-scene 1' expected", diag);
    if (!ts.resolution) return ls_scene_error(b, text + length, "the scene has no 'resolution'", diag);
    if (b->scene->camera_count == 0) return ls_scene_error(b, text + length, "the scene has no camera", diag);
    if (!ts.target) return ls_scene_error(b, text + length, "the scene has no 'target'", diag);
    if (b->scene->target == LS_SCENE_TARGET_IMAGES && ts.images != b->scene->camera_count)
        return ls_scene_error(b, text + length, "target images: a camera has no 'image'", diag);
    return LS_OK;
}

ls_status ls_scene_parse_bytes(const char *text, size_t length, size_t *bytes, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_scene_input in;
    if (bytes == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "bytes is NULL", LS_DIAG_NO_INDEX);
    in.text = text;
    in.length = length;
    return ls_scene_run(text_pass, &in, NULL, NULL, bytes, diag);
}

ls_status ls_scene_parse(const char *text, size_t length, ls_arena *arena, ls_scene *scene, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_scene_input in;
    if (arena == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "arena is NULL", LS_DIAG_NO_INDEX);
    if (scene == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "scene is NULL", LS_DIAG_NO_INDEX);
    in.text = text;
    in.length = length;
    return ls_scene_run(text_pass, &in, arena, scene, NULL, diag);
}
