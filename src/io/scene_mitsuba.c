/* scene_mitsuba.c - the subset of Mitsuba XML that the reference's scenes
 * use (documented in include/largesteps/scene.h). A flat scanner over tags
 * with an explicit element stack: no recursion, no allocation but the
 * builder's. */
#include <string.h>
#include <largesteps/scene.h>
#include <largesteps/camera.h>
#include <largesteps/math.h>
#include "scene_internal.h"

#define R_PI ((ls_real)3.14159265358979323846)
#define MAX_ATTRS 8u
#define MAX_DEFAULTS 8u

/* Keeps the element handlers' frames apart from the scanner's (the
 * per-function stack limit). */
#if defined(__GNUC__) || defined(__clang__)
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE
#endif

/* Element kinds on the stack. */
enum { K_OTHER, K_SCENE, K_SENSOR, K_FILM, K_TRANSFORM, K_EMITTER, K_SHAPE };

typedef struct span {
    uint32_t off, len;
} span;

typedef struct tag {
    span name;
    uint32_t nattr;
    span key[MAX_ATTRS], val[MAX_ATTRS];
    int closing;      /* </name> */
    int self_closing; /* <name ... /> */
    uint32_t at;      /* offset of '<' */
} tag;

typedef struct xml_state {
    const char *text;
    unsigned char kind[LS_SCENE_XML_DEPTH];
    uint32_t depth;
    span def_name[MAX_DEFAULTS], def_value[MAX_DEFAULTS];
    uint32_t ndef;
    /* the sensor being read */
    ls_real to_world[16];
    ls_real fov, near_plane, far_plane;
    uint32_t fov_axis, has_fov;
    uint32_t film_w, film_h, has_film;
    /* the emitter or shape being read */
    span filename;
    uint32_t has_filename;
    ls_real scale;
    int shape_role; /* 1 target, 2 source, 0 other */
    int emitter_envmap;
    uint32_t res_w, res_h, has_res;
} xml_state;

static int span_is(const char *text, span s, const char *word)
{
    return ls_scene_word_is(text + s.off, s.len, word);
}

static int spans_equal(const char *text, span a, span b)
{
    uint32_t i;
    if (a.len != b.len) return 0;
    for (i = 0; i < a.len; i++)
        if (text[a.off + i] != text[b.off + i]) return 0;
    return 1;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

static int name_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == ':' || c == '.';
}

/* The value of attribute `key` of t, with $name defaults substituted; 0 when absent. */
static int attr(const xml_state *x, const tag *t, const char *key, span *out)
{
    uint32_t i, d;
    for (i = 0; i < t->nattr; i++) {
        if (!span_is(x->text, t->key[i], key)) continue;
        *out = t->val[i];
        if (out->len > 1 && x->text[out->off] == '$') {
            span nm;
            nm.off = out->off + 1u;
            nm.len = out->len - 1u;
            for (d = 0; d < x->ndef; d++)
                if (spans_equal(x->text, x->def_name[d], nm)) {
                    *out = x->def_value[d];
                    break;
                }
        }
        return 1;
    }
    return 0;
}

/* Up to `max` numbers separated by spaces or commas; returns how many, or -1 on a bad one. */
static int span_numbers(const char *text, span s, ls_real *out, int max)
{
    uint32_t i = s.off, end = s.off + s.len;
    int n = 0;
    while (i < end) {
        uint32_t start;
        if (is_space(text[i]) || text[i] == ',') {
            i++;
            continue;
        }
        start = i;
        while (i < end && !is_space(text[i]) && text[i] != ',') i++;
        if (n == max || !ls_scene_number(text + start, i - start, &out[n])) return -1;
        n++;
    }
    return n;
}

static int finite_r(ls_real x) { return x - x == x - x; }

/* Reads the next tag at or after *pos; returns 0 at the end of the text, 1
 * for a tag, -1 for malformed markup (*pos at the problem). */
static int next_tag(const char *text, uint32_t length, uint32_t *pos, tag *t)
{
    uint32_t i = *pos;
    for (;;) {
        while (i < length && text[i] != '<') i++;
        if (i >= length) return 0;
        if (i + 3u < length && ls_scene_word_is(text + i, 4, "<!--")) {
            uint32_t j = i + 4u;
            while (j + 2u < length && !ls_scene_word_is(text + j, 3, "-->")) j++;
            if (j + 2u >= length) return *pos = i, -1;
            i = j + 3u;
            continue;
        }
        if (i + 1u < length && (text[i + 1] == '?' || text[i + 1] == '!')) {
            while (i < length && text[i] != '>') i++;
            if (i >= length) return -1;
            i++;
            continue;
        }
        break;
    }
    memset(t, 0, sizeof *t);
    t->at = i;
    i++;
    if (i < length && text[i] == '/') {
        t->closing = 1;
        i++;
    }
    t->name.off = i;
    while (i < length && name_char(text[i])) i++;
    t->name.len = i - t->name.off;
    if (t->name.len == 0) return *pos = t->at, -1;
    for (;;) {
        char q;
        while (i < length && is_space(text[i])) i++;
        if (i >= length) return *pos = t->at, -1;
        if (text[i] == '>') {
            *pos = i + 1u;
            return 1;
        }
        if (text[i] == '/' && i + 1u < length && text[i + 1] == '>' && !t->closing) {
            t->self_closing = 1;
            *pos = i + 2u;
            return 1;
        }
        if (t->closing || t->nattr == MAX_ATTRS) return *pos = i, -1;
        t->key[t->nattr].off = i;
        while (i < length && name_char(text[i])) i++;
        t->key[t->nattr].len = i - t->key[t->nattr].off;
        while (i < length && is_space(text[i])) i++;
        if (t->key[t->nattr].len == 0 || i >= length || text[i] != '=') return *pos = i, -1;
        i++;
        while (i < length && is_space(text[i])) i++;
        if (i >= length || (text[i] != '"' && text[i] != '\'')) return *pos = i, -1;
        q = text[i++];
        t->val[t->nattr].off = i;
        while (i < length && text[i] != q && text[i] != '<') i++;
        if (i >= length || text[i] != q) return *pos = t->val[t->nattr].off, -1;
        t->val[t->nattr].len = i - t->val[t->nattr].off;
        t->nattr++;
        i++;
    }
}

/* m = op * m (Mitsuba applies transform children in document order),
 * column by column so that no second matrix is needed on the stack. */
static void premultiply(ls_real m[16], const ls_real op[16])
{
    int r, c;
    for (c = 0; c < 4; c++) {
        ls_real col[4];
        for (r = 0; r < 4; r++) col[r] = m[4 * (size_t)r + (size_t)c];
        for (r = 0; r < 4; r++)
            m[4 * (size_t)r + (size_t)c] = ((op[4 * (size_t)r] * col[0] + op[4 * (size_t)r + 1] * col[1]) + op[4 * (size_t)r + 2] * col[2]) +
                                          op[4 * (size_t)r + 3] * col[3];
    }
}

static void normalize3(ls_real v[3])
{
    ls_real l = LS_RSQRT(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > (ls_real)0) v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross3(const ls_real a[3], const ls_real b[3], ls_real c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* x/y/z attributes, or value="a b c" (default `def` per missing axis). */
static int vector_attr(const xml_state *x, const tag *t, const char *name, ls_real def, ls_real v[3])
{
    static const char *const axis[3] = {"x", "y", "z"};
    span s;
    int k;
    if (attr(x, t, name, &s)) {
        int n = span_numbers(x->text, s, v, 3);
        if (n == 1) v[1] = v[2] = v[0];
        return n == 1 || n == 3;
    }
    for (k = 0; k < 3; k++) {
        v[k] = def;
        if (attr(x, t, axis[k], &s) && span_numbers(x->text, s, &v[k], 1) != 1) return 0;
    }
    return 1;
}

/* A child of <transform>: returns 0 when malformed. */
static int transform_op(xml_state *x, const tag *t)
{
    ls_real op[16], v[3];
    span s;
    ls_mat4_identity(op);
    if (span_is(x->text, t->name, "translate")) {
        if (!vector_attr(x, t, "value", (ls_real)0, v)) return 0;
        op[3] = v[0], op[7] = v[1], op[11] = v[2];
    } else if (span_is(x->text, t->name, "scale")) {
        if (!vector_attr(x, t, "value", (ls_real)1, v)) return 0;
        op[0] = v[0], op[5] = v[1], op[10] = v[2];
    } else if (span_is(x->text, t->name, "rotate")) {
        ls_real angle, c, sn, ic;
        if (!vector_attr(x, t, "value", (ls_real)0, v)) return 0;
        if (!attr(x, t, "angle", &s) || span_numbers(x->text, s, &angle, 1) != 1) return 0;
        normalize3(v);
        if (v[0] == (ls_real)0 && v[1] == (ls_real)0 && v[2] == (ls_real)0) return 0;
        angle = angle * R_PI / (ls_real)180;
        LS_RSINCOS(angle, &sn, &c);
        ic = (ls_real)1 - c;
        op[0] = c + v[0] * v[0] * ic, op[1] = v[0] * v[1] * ic - v[2] * sn, op[2] = v[0] * v[2] * ic + v[1] * sn;
        op[4] = v[1] * v[0] * ic + v[2] * sn, op[5] = c + v[1] * v[1] * ic, op[6] = v[1] * v[2] * ic - v[0] * sn;
        op[8] = v[2] * v[0] * ic - v[1] * sn, op[9] = v[2] * v[1] * ic + v[0] * sn, op[10] = c + v[2] * v[2] * ic;
    } else if (span_is(x->text, t->name, "lookat")) {
        /* columns of op: left, up, dir (Mitsuba's camera x, y, z), origin */
        ls_real tg[3], up[3] = {0, 1, 0}, dir[3], left[3];
        int k;
        if (!attr(x, t, "origin", &s) || span_numbers(x->text, s, v, 3) != 3) return 0;
        if (!attr(x, t, "target", &s) || span_numbers(x->text, s, tg, 3) != 3) return 0;
        if (attr(x, t, "up", &s) && span_numbers(x->text, s, up, 3) != 3) return 0;
        for (k = 0; k < 3; k++) dir[k] = tg[k] - v[k];
        normalize3(dir);
        cross3(up, dir, left);
        normalize3(left);
        if (left[0] == (ls_real)0 && left[1] == (ls_real)0 && left[2] == (ls_real)0) return 0;
        cross3(dir, left, up);
        for (k = 0; k < 3; k++) {
            op[4 * (size_t)k] = left[k];
            op[4 * (size_t)k + 1] = up[k];
            op[4 * (size_t)k + 2] = dir[k];
            op[4 * (size_t)k + 3] = v[k];
        }
    } else if (span_is(x->text, t->name, "matrix")) {
        if (!attr(x, t, "value", &s) || span_numbers(x->text, s, op, 16) != 16) return 0;
    } else {
        return 0;
    }
    premultiply(x->to_world, op);
    return 1;
}

/* view = R_y(pi) inverse(to_world) for an affine to_world; 0 if singular. */
static int sensor_view(const ls_real m[16], ls_real view[16])
{
    ls_real inv[9], det, t[3];
    int r, c;
    inv[0] = m[5] * m[10] - m[6] * m[9];
    inv[1] = m[2] * m[9] - m[1] * m[10];
    inv[2] = m[1] * m[6] - m[2] * m[5];
    inv[3] = m[6] * m[8] - m[4] * m[10];
    inv[4] = m[0] * m[10] - m[2] * m[8];
    inv[5] = m[2] * m[4] - m[0] * m[6];
    inv[6] = m[4] * m[9] - m[5] * m[8];
    inv[7] = m[1] * m[8] - m[0] * m[9];
    inv[8] = m[0] * m[5] - m[1] * m[4];
    det = m[0] * inv[0] + m[1] * inv[3] + m[2] * inv[6];
    if (!(det != (ls_real)0) || !finite_r(det) || m[12] != (ls_real)0 || m[13] != (ls_real)0 || m[14] != (ls_real)0 ||
        m[15] != (ls_real)1)
        return 0;
    for (r = 0; r < 9; r++) inv[r] /= det;
    for (r = 0; r < 3; r++) t[r] = -(inv[3 * (size_t)r] * m[3] + inv[3 * (size_t)r + 1] * m[7] + inv[3 * (size_t)r + 2] * m[11]);
    for (r = 0; r < 3; r++) {
        ls_real sign = r == 1 ? (ls_real)1 : (ls_real)-1; /* R_y(pi): x -> -x, z -> -z */
        for (c = 0; c < 3; c++) view[4 * r + c] = sign * inv[3 * r + c];
        view[4 * r + 3] = sign * t[r];
    }
    view[12] = view[13] = view[14] = (ls_real)0;
    view[15] = (ls_real)1;
    return 1;
}

static ls_status property(ls_scene_builder *b, xml_state *x, const tag *t, unsigned parent, ls_diag *diag)
{
    const char *text = x->text;
    span name, value;
    ls_real v;
    if (!attr(x, t, "name", &name) || !attr(x, t, "value", &value)) return LS_OK; /* not ours */
    if (parent == K_SENSOR) {
        if (span_is(text, name, "fov")) {
            if (span_numbers(text, value, &v, 1) != 1 || !(v > (ls_real)0) || !(v < (ls_real)180))
                return ls_scene_error(b, text + value.off, "sensor fov: degrees must lie in (0, 180)", diag);
            x->fov = v * R_PI / (ls_real)180;
            x->has_fov = 1;
        } else if (span_is(text, name, "fov_axis")) {
            if (span_is(text, value, "x"))
                x->fov_axis = LS_FOV_X;
            else if (span_is(text, value, "y"))
                x->fov_axis = LS_FOV_Y;
            else
                return ls_scene_error(b, text + value.off, "sensor fov_axis: only x and y are supported", diag);
        } else if (span_is(text, name, "near_clip") || span_is(text, name, "far_clip")) {
            if (span_numbers(text, value, &v, 1) != 1 || !(v > (ls_real)0) || !finite_r(v))
                return ls_scene_error(b, text + value.off, "sensor clip distance: a positive number expected", diag);
            if (span_is(text, name, "near_clip"))
                x->near_plane = v;
            else
                x->far_plane = v;
        }
    } else if (parent == K_FILM) {
        ls_real w;
        if (span_is(text, name, "width") || span_is(text, name, "height")) {
            if (span_numbers(text, value, &w, 1) != 1 || !(w >= (ls_real)1) || !(w <= (ls_real)65536) ||
                w != LS_RFLOOR(w))
                return ls_scene_error(b, text + value.off, "film size: a whole number from 1 to 65536 expected", diag);
            if (span_is(text, name, "width"))
                x->film_w = LS_RTO_U32(w);
            else
                x->film_h = LS_RTO_U32(w);
            x->has_film = 1;
        }
    } else if (parent == K_EMITTER || parent == K_SHAPE) {
        if (span_is(text, name, "filename")) {
            x->filename = value;
            x->has_filename = 1;
        } else if (parent == K_EMITTER && span_is(text, name, "scale")) {
            if (span_numbers(text, value, &v, 1) != 1 || !(v >= (ls_real)0) || !finite_r(v))
                return ls_scene_error(b, text + value.off, "envmap scale: a number >= 0 expected", diag);
            x->scale = v;
        }
    } else if (parent == K_SCENE && span_is(text, t->name, "default")) {
        if (x->ndef == MAX_DEFAULTS) return ls_scene_error(b, text + t->at, "more than 8 <default> elements", diag);
        x->def_name[x->ndef] = name;
        x->def_value[x->ndef] = value;
        x->ndef++;
    }
    return LS_OK;
}

static NOINLINE ls_status open_element(ls_scene_builder *b, xml_state *x, const tag *t, unsigned *kind, ls_diag *diag)
{
    const char *text = x->text;
    unsigned parent = x->depth > 0 ? x->kind[x->depth - 1u] : K_OTHER;
    span s;
    *kind = K_OTHER;
    if (x->depth == 0) {
        if (!span_is(text, t->name, "scene")) return ls_scene_error(b, text + t->at, "the root element must be <scene>", diag);
        *kind = K_SCENE;
        return LS_OK;
    }
    if (span_is(text, t->name, "sensor") && parent == K_SCENE) {
        if (!attr(x, t, "type", &s) || !span_is(text, s, "perspective"))
            return ls_scene_error(b, text + t->at, "only perspective sensors are supported", diag);
        ls_mat4_identity(x->to_world);
        x->has_fov = 0;
        x->fov_axis = LS_FOV_X;
        x->near_plane = (ls_real)0.01; /* Mitsuba's defaults */
        x->far_plane = (ls_real)10000;
        x->has_film = 0;
        x->film_w = 768;
        x->film_h = 576;
        *kind = K_SENSOR;
    } else if (span_is(text, t->name, "film") && parent == K_SENSOR) {
        *kind = K_FILM;
    } else if (span_is(text, t->name, "transform") && parent == K_SENSOR) {
        if (attr(x, t, "name", &s) && !span_is(text, s, "to_world") && !span_is(text, s, "toWorld"))
            return ls_scene_error(b, text + t->at, "sensor transform: only to_world is supported", diag);
        *kind = K_TRANSFORM;
    } else if (parent == K_TRANSFORM) {
        if (!transform_op(x, t)) return ls_scene_error(b, text + t->at, "malformed or unsupported transform", diag);
    } else if ((span_is(text, t->name, "emitter") || span_is(text, t->name, "shape")) && parent == K_SCENE) {
        int emitter = span_is(text, t->name, "emitter");
        x->has_filename = 0;
        x->scale = (ls_real)1;
        x->shape_role = 0;
        x->emitter_envmap = 0;
        if (emitter) {
            x->emitter_envmap = attr(x, t, "type", &s) && span_is(text, s, "envmap");
        } else if (attr(x, t, "id", &s)) {
            x->shape_role = span_is(text, s, "mesh-target") ? 1 : span_is(text, s, "mesh-source") ? 2 : 0;
        }
        *kind = emitter ? K_EMITTER : K_SHAPE;
    } else {
        return property(b, x, t, parent, diag);
    }
    return LS_OK;
}

static ls_status close_element(ls_scene_builder *b, xml_state *x, unsigned kind, uint32_t at, ls_diag *diag)
{
    ls_scene *s = b->scene;
    const char *text = x->text;
    if (kind == K_SENSOR) {
        ls_scene_camera *c;
        ls_real view[16];
        if (!x->has_fov) return ls_scene_error(b, text + at, "sensor without fov", diag);
        if (!(x->far_plane > x->near_plane)) return ls_scene_error(b, text + at, "sensor: far_clip must exceed near_clip", diag);
        if (!ls_scene_projection_ok(x->fov, x->fov_axis, x->near_plane, x->far_plane))
            return ls_scene_error(b, text + at, "sensor: fov and clip planes give a projection that overflows", diag);
        if (!sensor_view(x->to_world, view)) return ls_scene_error(b, text + at, "sensor: singular or projective to_world", diag);
        if (x->has_res && (x->film_w != x->res_w || x->film_h != x->res_h))
            return ls_scene_error(b, text + at, "sensors with different film sizes", diag);
        x->res_w = x->film_w;
        x->res_h = x->film_h;
        x->has_res = 1;
        c = ls_scene_add_camera(b);
        if (c == NULL) return ls_scene_error(b, text + at, "more cameras than LS_SCENE_MAX_VIEWS", diag);
        memcpy(c->view, view, sizeof view);
        c->fov = x->fov;
        c->fov_axis = x->fov_axis;
        c->near_plane = x->near_plane;
        c->far_plane = x->far_plane;
    } else if (kind == K_EMITTER && x->emitter_envmap) {
        if (!x->has_filename) return ls_scene_error(b, text + at, "envmap emitter without filename", diag);
        if (s->lighting == LS_SCENE_LIGHT_ENVMAP) return ls_scene_error(b, text + at, "more than one envmap emitter", diag);
        s->lighting = LS_SCENE_LIGHT_ENVMAP;
        s->envmap = ls_scene_add_string(b, text + x->filename.off, x->filename.len);
        s->envmap_scale = x->scale;
    } else if (kind == K_SHAPE && x->shape_role != 0) {
        if (!x->has_filename) return ls_scene_error(b, text + at, "shape without filename", diag);
        if (x->shape_role == 1) {
            if (s->target == LS_SCENE_TARGET_MESH) return ls_scene_error(b, text + at, "more than one mesh-target", diag);
            s->target = LS_SCENE_TARGET_MESH;
            s->target_mesh = ls_scene_add_string(b, text + x->filename.off, x->filename.len);
        } else {
            if (s->initial == LS_SCENE_INITIAL_MESH) return ls_scene_error(b, text + at, "more than one mesh-source", diag);
            s->initial = LS_SCENE_INITIAL_MESH;
            s->initial_mesh = ls_scene_add_string(b, text + x->filename.off, x->filename.len);
        }
    }
    return LS_OK;
}

static ls_status xml_pass(ls_scene_builder *b, const char *text, size_t length, ls_diag *diag)
{
    xml_state x;
    tag t;
    uint32_t pos = 0;
    ls_status st;
    if (length > UINT32_MAX) return LS_ERR_TOO_LARGE;
    memset(&x, 0, sizeof x);
    x.text = text;
    for (;;) {
        int r = next_tag(text, (uint32_t)length, &pos, &t);
        if (r == 0) break;
        if (r < 0) return ls_scene_error(b, text + pos, "malformed XML markup", diag);
        if (t.closing) {
            unsigned kind;
            if (x.depth == 0) return ls_scene_error(b, text + t.at, "closing tag without an open element", diag);
            kind = x.kind[--x.depth];
            st = close_element(b, &x, kind, t.at, diag);
            if (st != LS_OK) return st;
            continue;
        }
        {
            unsigned kind;
            if (x.depth == 0 && b->scene->camera_count > 0)
                return ls_scene_error(b, text + t.at, "content after the <scene> element", diag);
            st = open_element(b, &x, &t, &kind, diag);
            if (st != LS_OK) return st;
            if (t.self_closing) {
                st = close_element(b, &x, kind, t.at, diag);
                if (st != LS_OK) return st;
            } else {
                if (x.depth == LS_SCENE_XML_DEPTH) return ls_scene_error(b, text + t.at, "XML nested too deeply", diag);
                x.kind[x.depth++] = (unsigned char)kind;
            }
        }
    }
    if (x.depth != 0) return ls_scene_error(b, text + length, "unclosed XML element", diag);
    if (b->scene->camera_count == 0) return ls_scene_error(b, text + length, "the scene has no sensor", diag);
    b->scene->width = x.res_w;
    b->scene->height = x.res_h;
    if (b->scene->target == 0) b->scene->target = LS_SCENE_TARGET_IMAGES;
    return LS_OK;
}

ls_status ls_scene_parse_mitsuba_bytes(const char *text, size_t length, size_t *bytes, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_scene_input in;
    if (bytes == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "bytes is NULL", LS_DIAG_NO_INDEX);
    in.text = text;
    in.length = length;
    return ls_scene_run(xml_pass, &in, NULL, NULL, bytes, diag);
}

ls_status ls_scene_parse_mitsuba(const char *text, size_t length, ls_arena *arena, ls_scene *scene, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_scene_input in;
    if (arena == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "arena is NULL", LS_DIAG_NO_INDEX);
    if (scene == NULL) return ls_diag_set(diag, LS_ERR_INVALID, "scene is NULL", LS_DIAG_NO_INDEX);
    in.text = text;
    in.length = length;
    return ls_scene_run(xml_pass, &in, arena, scene, NULL, diag);
}
