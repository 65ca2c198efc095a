/* scene_transforms.c - camera datasets in the NeRF-synthetic / Blender /
 * instant-ngp `transforms.json` form (format in include/largesteps/scene.h),
 * read with the strict JSON reader (json.c) into a scene. */
#include <string.h>
#include <largesteps/scene.h>
#include <largesteps/camera.h>
#include <largesteps/math.h>
#include "scene_internal.h"
#include "json_internal.h"

#define R_PI ((ls_real)3.14159265358979323846)

/* The dataset-wide fields, gathered before the cameras get them (JSON
 * members come in any order). */
typedef struct intrinsics {
    ls_real angle_x, angle_y, fl_x, fl_y, cx, cy, w, h, near_plane, far_plane;
    int has_angle_x, has_angle_y, has_fl_x, has_fl_y, has_cx, has_cy, has_w, has_h;
    const char *at; /* where the first intrinsic was given (for errors) */
} intrinsics;

typedef struct reader {
    ls_scene_builder *b;
    ls_json j;
    ls_json_event ev;
    ls_diag *diag;
} reader;

static ls_status bad(reader *r, const char *at, const char *what)
{
    return ls_scene_error(r->b, at, what, r->diag);
}

static ls_status json_error(reader *r) { return bad(r, r->ev.at, r->ev.what); }

static ls_status next(reader *r)
{
    return ls_json_next(&r->j, &r->ev) == LS_JSON_ERROR ? json_error(r) : LS_OK;
}

static ls_status skip_value(reader *r)
{
    if (next(r) != LS_OK) return LS_ERR_PARSE;
    return ls_json_skip(&r->j, &r->ev) == LS_JSON_ERROR ? json_error(r) : LS_OK;
}

/* The next value, a finite number. */
static ls_status number(reader *r, ls_real *out, const char *what)
{
    if (next(r) != LS_OK) return LS_ERR_PARSE;
    if (r->ev.type != LS_JSON_NUMBER || !ls_scene_number(r->ev.at, r->ev.len, out)) return bad(r, r->ev.at, what);
    return LS_OK;
}

/* The next value, an array of exactly n numbers. */
static ls_status numbers(reader *r, ls_real *out, uint32_t n, const char *what)
{
    uint32_t k;
    if (next(r) != LS_OK) return LS_ERR_PARSE;
    if (r->ev.type != LS_JSON_ARRAY) return bad(r, r->ev.at, what);
    for (k = 0; k < n; k++)
        if (number(r, &out[k], what) != LS_OK) return LS_ERR_PARSE;
    if (next(r) != LS_OK) return LS_ERR_PARSE;
    if (r->ev.type != LS_JSON_ARRAY_END) return bad(r, r->ev.at, what);
    return LS_OK;
}

/* A path: the decoded string, with ".png" added when its last component has
 * no extension (the NeRF-synthetic datasets leave it out). */
static ls_status add_path(reader *r, const char **out)
{
    ls_scene_builder *b = r->b;
    const char *raw = r->ev.at;
    size_t len = r->ev.len, k, last = 0, dlen = 0, need;
    int png = 1;
    char *dst;
    if (len == 0 || !ls_json_decode(raw, len, NULL, &dlen))
        return bad(r, raw, "file_path must be a file name (not empty, no NUL character or unpaired \\u surrogate)");
    for (k = 0; k < len; k++)
        if (raw[k] == '/') last = k + 1;
    for (k = last; k < len; k++)
        if (raw[k] == '.' && k > last) png = 0;
    need = len + (png ? 4u : 0u) + 1u;
    if (b->measure) {
        b->strings_used += need;
        *out = "";
        return LS_OK;
    }
    if (need > b->strings_cap - b->strings_used) return LS_ERR_NOMEM; /* not reached: pass 1 counted it */
    dst = b->strings + b->strings_used;
    memcpy(dst, raw, len);
    (void)ls_json_decode(dst, len, dst, &dlen);
    if (png) {
        memcpy(dst + dlen, ".png", 4);
        dlen += 4;
    }
    dst[dlen] = '\0';
    b->strings_used += need;
    *out = dst;
    return LS_OK;
}

/* world -> view from camera -> world, a rotation and a translation with
 * OpenGL's camera axes (the camera looks down -z, +y up): ours. */
static ls_status view_from_c2w(reader *r, const ls_real m[16], const char *at, ls_real view[16])
{
    int i, k;
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) {
            ls_real d = m[i] * m[k] + m[4 + i] * m[4 + k] + m[8 + i] * m[8 + k] - (i == k ? (ls_real)1 : (ls_real)0);
            if (!(d <= (ls_real)1e-3 && d >= (ls_real)-1e-3))
                return bad(r, at, "transform_matrix must be a rotation and a translation (its 3 x 3 part is not "
                                  "orthonormal: undo the dataset's scale first)");
        }
    if (m[12] != (ls_real)0 || m[13] != (ls_real)0 || m[14] != (ls_real)0 || m[15] != (ls_real)1)
        return bad(r, at, "transform_matrix's last row must be 0 0 0 1");
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 3; k++) view[4 * i + k] = m[4 * k + i];
        view[4 * i + 3] = -(m[i] * m[3] + m[4 + i] * m[7] + m[8 + i] * m[11]);
    }
    view[12] = view[13] = view[14] = (ls_real)0;
    view[15] = (ls_real)1;
    return LS_OK;
}

static int is_intrinsic(const ls_json_event *ev)
{
    static const char *const names[] = {"camera_angle_x", "camera_angle_y", "fl_x", "fl_y", "cx", "cy", "w", "h"};
    size_t k;
    for (k = 0; k < sizeof names / sizeof names[0]; k++)
        if (ls_json_is(ev, names[k])) return 1;
    return 0;
}

/* One element of "frames": an object with file_path and transform_matrix. */
static ls_status frame(reader *r)
{
    ls_scene_camera *cam;
    const char *start = r->ev.at, *path = NULL;
    ls_real m[16], rows[4];
    int has_matrix = 0, i;
    if (r->ev.type != LS_JSON_OBJECT) return bad(r, r->ev.at, "each element of frames must be an object");
    cam = ls_scene_add_camera(r->b);
    if (cam == NULL) return bad(r, r->ev.at, "more frames than a scene holds (4096)");
    for (;;) {
        if (next(r) != LS_OK) return LS_ERR_PARSE;
        if (r->ev.type == LS_JSON_OBJECT_END) break;
        if (ls_json_is(&r->ev, "file_path")) {
            if (path != NULL) return bad(r, r->ev.at, "file_path given twice in one frame");
            if (next(r) != LS_OK) return LS_ERR_PARSE;
            if (r->ev.type != LS_JSON_STRING) return bad(r, r->ev.at, "file_path must be a string");
            if (add_path(r, &path) != LS_OK) return LS_ERR_PARSE;
        } else if (ls_json_is(&r->ev, "transform_matrix")) {
            const char *at = r->ev.at;
            if (has_matrix) return bad(r, at, "transform_matrix given twice in one frame");
            if (next(r) != LS_OK) return LS_ERR_PARSE;
            if (r->ev.type != LS_JSON_ARRAY) return bad(r, r->ev.at, "transform_matrix must be 4 rows of 4 numbers");
            for (i = 0; i < 4; i++) {
                if (numbers(r, rows, 4, "transform_matrix must be 4 rows of 4 finite numbers") != LS_OK)
                    return LS_ERR_PARSE;
                memcpy(m + (size_t)4 * (size_t)i, rows, sizeof rows);
            }
            if (next(r) != LS_OK) return LS_ERR_PARSE;
            if (r->ev.type != LS_JSON_ARRAY_END) return bad(r, r->ev.at, "transform_matrix must be 4 rows of 4 numbers");
            if (view_from_c2w(r, m, at, cam->view) != LS_OK) return LS_ERR_PARSE;
            has_matrix = 1;
        } else if (is_intrinsic(&r->ev)) {
            return bad(r, r->ev.at, "intrinsics per frame are not supported: give camera_angle_x (or fl_x, cx, cy, w, "
                                    "h) once for the whole dataset");
        } else if (skip_value(r) != LS_OK) {
            return LS_ERR_PARSE;
        }
    }
    if (path == NULL) return bad(r, start, "a frame without file_path");
    if (!has_matrix) return bad(r, start, "a frame without transform_matrix");
    cam->image = path;
    return LS_OK;
}

static ls_status frames(reader *r)
{
    if (next(r) != LS_OK) return LS_ERR_PARSE;
    if (r->ev.type != LS_JSON_ARRAY) return bad(r, r->ev.at, "frames must be an array of objects");
    for (;;) {
        if (next(r) != LS_OK) return LS_ERR_PARSE;
        if (r->ev.type == LS_JSON_ARRAY_END) return LS_OK;
        if (frame(r) != LS_OK) return LS_ERR_PARSE;
    }
}

/* One member of the top object that names an intrinsic: into in. */
static ls_status intrinsic(reader *r, intrinsics *in)
{
    static const char *const names[] = {"camera_angle_x", "camera_angle_y", "fl_x", "fl_y", "cx", "cy", "w", "h"};
    ls_real *vals[8];
    int *has[8];
    size_t k;
    vals[0] = &in->angle_x, has[0] = &in->has_angle_x;
    vals[1] = &in->angle_y, has[1] = &in->has_angle_y;
    vals[2] = &in->fl_x, has[2] = &in->has_fl_x;
    vals[3] = &in->fl_y, has[3] = &in->has_fl_y;
    vals[4] = &in->cx, has[4] = &in->has_cx;
    vals[5] = &in->cy, has[5] = &in->has_cy;
    vals[6] = &in->w, has[6] = &in->has_w;
    vals[7] = &in->h, has[7] = &in->has_h;
    for (k = 0; k < 8; k++)
        if (ls_json_is(&r->ev, names[k])) break;
    if (k == 8) return bad(r, r->ev.at, "not an intrinsic"); /* not reached: the caller checked the name */
    if (*has[k]) return bad(r, r->ev.at, "an intrinsic given twice");
    if (in->at == NULL) in->at = r->ev.at;
    if (number(r, vals[k], "camera_angle_x, camera_angle_y, fl_x, fl_y, cx, cy, w and h must be finite numbers") !=
        LS_OK)
        return LS_ERR_PARSE;
    *has[k] = 1;
    return LS_OK;
}

/* Field of view, principal point and resolution from the intrinsics. */
static ls_status camera_model(reader *r, const intrinsics *in, const char *end)
{
    ls_scene *s = r->b->scene;
    const char *at = in->at != NULL ? in->at : end;
    ls_real fov, center[2] = {(ls_real)0, (ls_real)0};
    uint32_t axis, v;
    if (in->has_w || in->has_h) {
        if (!in->has_w || !in->has_h || !(in->w >= (ls_real)1 && in->w <= (ls_real)65536) ||
            !(in->h >= (ls_real)1 && in->h <= (ls_real)65536) || in->w != (ls_real)(uint32_t)in->w ||
            in->h != (ls_real)(uint32_t)in->h)
            return bad(r, at, "w and h must both be given, whole numbers of pixels from 1 to 65536");
        s->width = (uint32_t)in->w;
        s->height = (uint32_t)in->h;
    }
    if (in->has_angle_x) {
        fov = in->angle_x;
        axis = LS_FOV_X;
    } else if (in->has_angle_y) {
        fov = in->angle_y;
        axis = LS_FOV_Y;
    } else if (in->has_fl_x && in->has_w) {
        fov = (ls_real)2 * LS_RATAN2(in->w, (ls_real)2 * in->fl_x);
        axis = LS_FOV_X;
    } else if (in->has_fl_y && in->has_h) {
        fov = (ls_real)2 * LS_RATAN2(in->h, (ls_real)2 * in->fl_y);
        axis = LS_FOV_Y;
    } else {
        return bad(r, at, "no field of view: give camera_angle_x (radians), or fl_x with w");
    }
    if (in->has_fl_x && in->has_fl_y &&
        !(in->fl_y - in->fl_x <= (ls_real)1e-3 * in->fl_x && in->fl_x - in->fl_y <= (ls_real)1e-3 * in->fl_x))
        return bad(r, at, "fl_x and fl_y differ: non-square pixels are not supported (resample the images)");
    if (in->has_cx || in->has_cy) {
        if (!in->has_cx || !in->has_cy || !in->has_w)
            return bad(r, at, "cx and cy need each other and w, h (the principal point in pixels)");
        center[0] = (ls_real)2 * in->cx / in->w - (ls_real)1;
        center[1] = (ls_real)1 - (ls_real)2 * in->cy / in->h;
        if (!(center[0] > (ls_real)-1 && center[0] < (ls_real)1 && center[1] > (ls_real)-1 && center[1] < (ls_real)1))
            return bad(r, at, "the principal point (cx, cy) must lie inside the image");
    }
    if (!(fov > (ls_real)0 && fov < R_PI) || !ls_scene_projection_ok(fov, axis, in->near_plane, in->far_plane))
        return bad(r, at, "the field of view must lie between 0 and pi radians (camera_angle_x is in radians)");
    if (r->b->measure) return LS_OK;
    for (v = 0; v < s->camera_count; v++) {
        ls_scene_camera *c = &s->cameras[v];
        c->fov = fov;
        c->fov_axis = axis;
        c->near_plane = in->near_plane;
        c->far_plane = in->far_plane;
        c->center[0] = center[0];
        c->center[1] = center[1];
    }
    return LS_OK;
}

/* largesteps_sh, largesteps_lighting or largesteps_background: the members
 * `largesteps render` writes. */
static ls_status own_member(reader *r, int *lighting_given)
{
    ls_scene *s = r->b->scene;
    const char *at = r->ev.at;
    if (ls_json_is(&r->ev, "largesteps_sh")) {
        if (*lighting_given) return bad(r, at, "the lighting given twice");
        *lighting_given = 1;
        s->lighting = LS_SCENE_LIGHT_SH;
        return numbers(r, s->sh, 27, "largesteps_sh must be 27 finite numbers (9 SH coefficients per channel)");
    }
    if (ls_json_is(&r->ev, "largesteps_lighting")) {
        if (*lighting_given) return bad(r, at, "the lighting given twice");
        *lighting_given = 1;
        if (next(r) != LS_OK) return LS_ERR_PARSE;
        if (r->ev.type != LS_JSON_STRING || !ls_json_is(&r->ev, "mask"))
            return bad(r, r->ev.at, "largesteps_lighting must be \"mask\" (SH lighting: largesteps_sh)");
        s->lighting = LS_SCENE_LIGHT_MASK;
        return LS_OK;
    }
    {
        ls_real bg[3]; /* largesteps_background */
        if (numbers(r, bg, 3, "largesteps_background must be 3 finite numbers (R G B)") != LS_OK) return LS_ERR_PARSE;
        memcpy(s->background, bg, sizeof bg);
        return LS_OK;
    }
}

static ls_status transforms_pass(ls_scene_builder *b, const char *text, size_t length, ls_diag *diag)
{
    reader r;
    intrinsics in;
    int lighting_given = 0, has_frames = 0;
    ls_scene *s = b->scene;
    memset(&in, 0, sizeof in);
    in.near_plane = (ls_real)0.01;
    in.far_plane = (ls_real)100;
    r.b = b;
    r.diag = diag;
    ls_json_init(&r.j, text, length);
    s->lighting = LS_SCENE_LIGHT_UNKNOWN;
    s->target = LS_SCENE_TARGET_IMAGES;
    if (next(&r) != LS_OK) return LS_ERR_PARSE;
    if (r.ev.type != LS_JSON_OBJECT) return bad(&r, r.ev.at, "a transforms.json file is one JSON object");
    for (;;) {
        if (next(&r) != LS_OK) return LS_ERR_PARSE;
        if (r.ev.type == LS_JSON_OBJECT_END) break;
        if (ls_json_is(&r.ev, "frames")) {
            if (has_frames) return bad(&r, r.ev.at, "frames given twice");
            has_frames = 1;
            if (frames(&r) != LS_OK) return LS_ERR_PARSE;
        } else if (is_intrinsic(&r.ev)) {
            if (intrinsic(&r, &in) != LS_OK) return LS_ERR_PARSE;
        } else if (ls_json_is(&r.ev, "largesteps_clip")) {
            ls_real clip[2] = {(ls_real)0, (ls_real)0};
            const char *at = r.ev.at;
            if (numbers(&r, clip, 2, "largesteps_clip must be 2 finite numbers (near far)") != LS_OK)
                return LS_ERR_PARSE;
            if (!(clip[0] > (ls_real)0 && clip[1] > clip[0])) return bad(&r, at, "largesteps_clip needs 0 < near < far");
            in.near_plane = clip[0];
            in.far_plane = clip[1];
        } else if (ls_json_is(&r.ev, "largesteps_sh") || ls_json_is(&r.ev, "largesteps_lighting") ||
                   ls_json_is(&r.ev, "largesteps_background")) {
            if (own_member(&r, &lighting_given) != LS_OK) return LS_ERR_PARSE;
        } else if (ls_json_is(&r.ev, "k1") || ls_json_is(&r.ev, "k2") || ls_json_is(&r.ev, "k3") ||
                   ls_json_is(&r.ev, "p1") || ls_json_is(&r.ev, "p2")) {
            ls_real k = (ls_real)0;
            const char *at = r.ev.at;
            if (number(&r, &k, "lens distortion coefficients must be numbers") != LS_OK) return LS_ERR_PARSE;
            if (k != (ls_real)0)
                return bad(&r, at, "lens distortion (k1, k2, k3, p1, p2) is not supported: undistort the images first");
        } else if (skip_value(&r) != LS_OK) {
            return LS_ERR_PARSE;
        }
    }
    if (next(&r) != LS_OK) return LS_ERR_PARSE;
    if (!has_frames || s->camera_count == 0) return bad(&r, text + length, "the dataset has no frames");
    return camera_model(&r, &in, text + length);
}

ls_status ls_scene_parse_transforms_bytes(const char *text, size_t length, size_t *bytes, ls_diag *diag)
{
    ls_scene_input in;
    if (bytes == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "bytes is NULL", LS_DIAG_NO_INDEX);
    in.text = text;
    in.length = length;
    return ls_scene_run(transforms_pass, &in, NULL, NULL, bytes, diag);
}

ls_status ls_scene_parse_transforms(const char *text, size_t length, ls_arena *arena, ls_scene *scene, ls_diag *diag)
{
    ls_scene_input in;
    if (arena == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "arena is NULL", LS_DIAG_NO_INDEX);
    if (scene == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "scene is NULL", LS_DIAG_NO_INDEX);
    in.text = text;
    in.length = length;
    return ls_scene_run(transforms_pass, &in, arena, scene, NULL, diag);
}
