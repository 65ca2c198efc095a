/* mesh_io.c - mesh files from memory (OBJ, OFF; PLY in mesh_ply.c), the
 * format dispatch and the writers (include/largesteps/mesh_io.h) */
#include "mesh_io_internal.h"
#include "../base/diag_internal.h"

/* Own byte comparisons: the library calls no libc function but memcpy,
 * memset, memmove and sqrt. */
static int bytes_equal(const char *a, const char *b, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        if (a[i] != b[i]) return 0;
    }
    return 1;
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}

int ls_mio_is_eol(char c)
{
    return c == '\n' || c == '\r';
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

void ls_mio_text_init(text *t, const char *s, size_t n, size_t start, uint32_t hash_comments)
{
    t->s = s;
    t->n = n;
    t->pos = start;
    t->line_start = start;
    t->line = 1;
    t->hash_comments = hash_comments;
}

void ls_mio_skip_spaces(text *t)
{
    while (t->pos < t->n && is_space(t->s[t->pos])) t->pos++;
}

/* Moves past the end of the current line (LF, CRLF or a lone CR). */
void ls_mio_next_line(text *t)
{
    while (t->pos < t->n && !ls_mio_is_eol(t->s[t->pos])) t->pos++;
    if (t->pos < t->n) {
        if (t->s[t->pos] == '\r' && t->pos + 1 < t->n && t->s[t->pos + 1] == '\n') t->pos++;
        t->pos++;
    }
    if (t->line < U32_LIMIT) t->line++;
    t->line_start = t->pos;
}

/* The next token of the current line (0 at its end or at a comment). */
size_t ls_mio_token(text *t, const char **tok)
{
    size_t start;
    ls_mio_skip_spaces(t);
    start = t->pos;
    *tok = t->s + start;
    if (t->pos < t->n && t->hash_comments && t->s[t->pos] == '#') return 0;
    while (t->pos < t->n && !is_space(t->s[t->pos]) && !ls_mio_is_eol(t->s[t->pos])) {
        if (t->hash_comments && t->s[t->pos] == '#') break;
        t->pos++;
    }
    return t->pos - start;
}

/* Skips empty and comment-only lines; 0 at the end of the text. */
static int content_line(text *t)
{
    for (;;) {
        const char *tok;
        size_t at = t->pos, len = ls_mio_token(t, &tok);
        if (len > 0) {
            t->pos = at;
            return 1;
        }
        if (t->pos >= t->n) return 0;
        ls_mio_next_line(t);
    }
}

ls_status ls_mio_text_error(ls_diag *diag, const text *t, size_t at, ls_status st, const char *what)
{
    if (diag != NULL) {
        size_t col = at - t->line_start + 1;
        ls_diag_clear(diag);
        diag->status = st;
        diag->what = what;
        diag->has_line = 1;
        diag->line = t->line;
        diag->column = col > U32_LIMIT ? U32_LIMIT : (uint32_t)col;
        diag->has_offset = 1;
        diag->offset = (uint64_t)at;
    }
    return st;
}

ls_status ls_mio_offset_error(ls_diag *diag, size_t at, ls_status st, const char *what)
{
    if (diag != NULL) {
        ls_diag_clear(diag);
        diag->status = st;
        diag->what = what;
        diag->has_offset = 1;
        diag->offset = (uint64_t)at;
    }
    return st;
}

/* Unsigned decimal token: 1 ok, 0 not a number, -1 above limit. */
int ls_mio_parse_uint(const char *tok, size_t len, uint64_t limit, uint64_t *out)
{
    size_t i = 0;
    uint64_t v = 0;
    if (i < len && tok[i] == '+') i++;
    if (i >= len) return 0;
    for (; i < len; i++) {
        if (!is_digit(tok[i])) return 0;
        if (v > (limit - (uint64_t)(tok[i] - '0')) / 10u) return -1;
        v = v * 10u + (uint64_t)(tok[i] - '0');
    }
    *out = v;
    return 1;
}

/* Signed decimal token within [-limit, limit]: 1 ok, 0 not a number, -1 out of range. */
int ls_mio_parse_int(const char *tok, size_t len, uint64_t limit, int64_t *out)
{
    uint64_t v = 0;
    int neg = len > 0 && tok[0] == '-', r;
    if (neg) {
        tok++;
        len--;
        if (len > 0 && tok[0] == '+') return 0;
    }
    r = ls_mio_parse_uint(tok, len, limit, &v);
    if (r != 1) return r;
    *out = neg ? -(int64_t)v : (int64_t)v;
    return 1;
}

/* Checks the bytes of a text file: UTF-16, NUL bytes, emptiness, BOM. */
static ls_status text_prepare(const unsigned char *d, size_t n, size_t *start, ls_diag *diag)
{
    size_t i, s = 0;
    int content = 0;
    if (n >= 2 && ((d[0] == 0xfe && d[1] == 0xff) || (d[0] == 0xff && d[1] == 0xfe)))
        return ls_mio_offset_error(diag, 0, LS_ERR_UNSUPPORTED, "UTF-16 text (byte-order mark); convert the file to UTF-8");
    if (n >= 3 && d[0] == 0xef && d[1] == 0xbb && d[2] == 0xbf) s = 3;
    for (i = s; i < n; i++) {
        if (d[i] == 0) return ls_mio_offset_error(diag, i, LS_ERR_PARSE, "NUL byte in a text file (UTF-16 without a byte-order mark, or binary data)");
        if (!content && !is_space((char)d[i]) && !ls_mio_is_eol((char)d[i])) content = 1;
    }
    if (!content) return ls_mio_offset_error(diag, n, LS_ERR_PARSE, "empty file");
    *start = s;
    return LS_OK;
}

/* Coordinates must be finite ("nan", "inf" and binary NaN/infinity are rejected). */
int ls_mio_coord_finite(ls_real v)
{
    return v - v == (ls_real)0;
}

/* Reads one coordinate token into *v. */
static ls_status read_coord(text *t, ls_real *v, ls_diag *diag, const char *missing)
{
    const char *tok;
    size_t at, len;
    ls_status st;
    ls_mio_skip_spaces(t);
    at = t->pos;
    len = ls_mio_token(t, &tok);
    if (len == 0) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, missing);
    st = ls_parse_real(tok, len, v);
    if (st == LS_ERR_TOO_LARGE) return ls_mio_text_error(diag, t, at, LS_ERR_TOO_LARGE, "number too large for ls_real");
    if (st != LS_OK) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "invalid number");
    if (!ls_mio_coord_finite(*v)) return ls_mio_text_error(diag, t, at, LS_ERR_NONFINITE, COORD_NONFINITE);
    return LS_OK;
}

/* Adds triangle (a, b, c). */
int ls_mio_add_tri(sink *k, uint32_t a, uint32_t b, uint32_t c)
{
    if (k->nt >= U32_LIMIT) return 0;
    if (k->t != NULL) {
        k->t[3 * k->nt] = a;
        k->t[3 * k->nt + 1] = b;
        k->t[3 * k->nt + 2] = c;
    }
    k->nt++;
    return 1;
}

/* --- OBJ ------------------------------------------------------------------ */

/* "i", "i/t", "i/t/n", "i//n": 1 ok, 0 malformed, -1 out of range. */
static int obj_index(const char *tok, size_t len, int64_t *out)
{
    size_t i = 0, end;
    int r, pass;
    while (i < len && tok[i] != '/') i++;
    r = ls_mio_parse_int(tok, i, U32_LIMIT, out);
    if (r != 1) return r;
    end = i;
    for (pass = 0; pass < 2 && end < len; pass++) {
        end++; /* the '/' */
        if (end < len && (tok[end] == '-' || tok[end] == '+')) end++;
        while (end < len && is_digit(tok[end])) end++;
        if (end < len && tok[end] != '/') return 0;
    }
    return end == len ? 1 : 0;
}

static ls_status read_obj(const char *s, size_t n, size_t start, sink *k, ls_diag *diag)
{
    text t;
    uint64_t max_index = 0;
    size_t max_at = 0, max_line_start = 0;
    uint32_t max_line = 0;
    ls_status st;
    ls_mio_text_init(&t, s, n, start, 1);
    while (t.pos < t.n) {
        const char *kw, *tok;
        size_t kat, kl, len;
        ls_mio_skip_spaces(&t);
        kat = t.pos;
        kl = ls_mio_token(&t, &kw);
        if (kl == 1 && kw[0] == 'v') {
            uint32_t c;
            if (k->nv >= U32_LIMIT) return ls_mio_text_error(diag, &t, kat, LS_ERR_TOO_LARGE, "more than 2^32 - 1 vertices");
            for (c = 0; c < 3; c++) {
                ls_real v = 0;
                st = read_coord(&t, &v, diag, "vertex with fewer than 3 coordinates");
                if (st != LS_OK) return st;
                if (k->p != NULL) k->p[3 * k->nv + c] = v;
            }
            k->nv++;
        } else if (kl == 1 && kw[0] == 'f') {
            uint32_t first = 0, prev = 0, r;
            uint64_t corners = 0;
            for (;;) {
                int64_t idx = 0;
                int ok;
                size_t at;
                ls_mio_skip_spaces(&t);
                at = t.pos;
                len = ls_mio_token(&t, &tok);
                if (len == 0) break;
                ok = obj_index(tok, len, &idx);
                if (ok == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid face index token");
                if (ok < 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "face index out of range");
                if (idx == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "face index 0 (OBJ indices start at 1)");
                if (idx < 0) {
                    if ((uint64_t)(-idx) > k->nv)
                        return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "relative face index before the first vertex");
                    r = (uint32_t)(k->nv - (uint64_t)(-idx));
                } else {
                    r = (uint32_t)(idx - 1);
                    if ((uint64_t)idx > max_index) {
                        max_index = (uint64_t)idx;
                        max_at = at;
                        max_line = t.line;
                        max_line_start = t.line_start;
                    }
                }
                if (corners == 0) first = r;
                if (corners >= 2 && !ls_mio_add_tri(k, first, prev, r))
                    return ls_mio_text_error(diag, &t, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 triangles");
                prev = r;
                corners++;
            }
            if (corners < 3) return ls_mio_text_error(diag, &t, kat, LS_ERR_PARSE, "face with fewer than 3 vertices");
            k->np++;
        }
        ls_mio_next_line(&t);
    }
    if (max_index > k->nv) {
        t.line = max_line;
        t.line_start = max_line_start;
        return ls_mio_text_error(diag, &t, max_at, LS_ERR_PARSE, "face index out of range");
    }
    return LS_OK;
}

/* --- OFF ------------------------------------------------------------------ */

static ls_status read_off(const char *s, size_t n, size_t start, int explicit_off, sink *k, ls_diag *diag)
{
    text t;
    const char *tok;
    size_t len, at, rem;
    uint64_t nv = 0, nf = 0, i, ne = 0;
    int r;
    ls_status st;
    ls_mio_text_init(&t, s, n, start, 1);
    if (!content_line(&t)) return ls_mio_text_error(diag, &t, t.pos, LS_ERR_PARSE, "empty file");
    at = t.pos;
    len = ls_mio_token(&t, &tok);
    if (len >= 3 && bytes_equal(tok + len - 3, "OFF", 3)) {
        for (i = 0; i + 3 < len; i++) {
            if (tok[i] == '4' || tok[i] == 'n') return ls_mio_text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "4D or n-dimensional OFF");
            if (tok[i] != 'S' && tok[i] != 'T' && tok[i] != 'C' && tok[i] != 'N')
                return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "unknown OFF keyword");
        }
        ls_mio_skip_spaces(&t);
        at = t.pos;
        len = ls_mio_token(&t, &tok);
        if (len == 6 && bytes_equal(tok, "BINARY", 6)) return ls_mio_text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "binary OFF");
        t.pos = at;
        if (len == 0) {
            ls_mio_next_line(&t);
            if (!content_line(&t)) return ls_mio_text_error(diag, &t, t.pos, LS_ERR_PARSE, "OFF file ends before its counts");
        }
    } else if (!explicit_off) {
        return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "missing OFF keyword");
    } else {
        t.pos = at;
    }
    ls_mio_skip_spaces(&t);
    at = t.pos;
    len = ls_mio_token(&t, &tok);
    r = ls_mio_parse_uint(tok, len, UINT64_MAX, &nv);
    if (r == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF vertex count");
    if (r < 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "OFF vertex count larger than the file");
    ls_mio_skip_spaces(&t);
    at = t.pos;
    len = ls_mio_token(&t, &tok);
    r = ls_mio_parse_uint(tok, len, UINT64_MAX, &nf);
    if (r == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF face count");
    if (r < 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "OFF face count larger than the file");
    ls_mio_skip_spaces(&t);
    at = t.pos;
    len = ls_mio_token(&t, &tok);
    if (len > 0 && ls_mio_parse_uint(tok, len, UINT64_MAX, &ne) != 1) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF edge count");
    /* a vertex record takes at least 6 bytes ("0 0 0\n"), a face record 2 ("3\n" is short but still a record) */
    rem = t.n - t.pos;
    if (nv > (uint64_t)rem / 6u + 1u || nf > (uint64_t)rem / 2u + 1u || nv * 6u + nf * 2u > (uint64_t)rem + 2u)
        return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "OFF counts larger than the file");
    if (nv > U32_LIMIT) return ls_mio_text_error(diag, &t, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 vertices");
    ls_mio_next_line(&t);
    for (i = 0; i < nv; i++) {
        uint32_t c;
        if (!content_line(&t)) return ls_mio_text_error(diag, &t, t.pos, LS_ERR_PARSE, "OFF file ends before all its vertices");
        for (c = 0; c < 3; c++) {
            ls_real v = 0;
            st = read_coord(&t, &v, diag, "vertex with fewer than 3 coordinates");
            if (st != LS_OK) return st;
            if (k->p != NULL) k->p[3 * i + c] = v;
        }
        ls_mio_next_line(&t);
    }
    k->nv = nv;
    for (i = 0; i < nf; i++) {
        uint64_t cnt = 0, j;
        uint32_t first = 0, prev = 0;
        if (!content_line(&t)) return ls_mio_text_error(diag, &t, t.pos, LS_ERR_PARSE, "OFF file ends before all its faces");
        at = t.pos;
        len = ls_mio_token(&t, &tok);
        r = ls_mio_parse_uint(tok, len, U32_LIMIT, &cnt);
        if (r == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF face vertex count");
        if (r < 0 || cnt > t.n) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "OFF face vertex count larger than the file");
        if (cnt < 3) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "face with fewer than 3 vertices");
        for (j = 0; j < cnt; j++) {
            uint64_t idx = 0;
            ls_mio_skip_spaces(&t);
            at = t.pos;
            len = ls_mio_token(&t, &tok);
            if (len == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "face with fewer indices than its count");
            r = ls_mio_parse_uint(tok, len, U32_LIMIT, &idx);
            if (r == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid face index");
            if (r < 0 || idx >= nv) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "face index out of range");
            if (j == 0) first = (uint32_t)idx;
            if (j >= 2 && !ls_mio_add_tri(k, first, prev, (uint32_t)idx))
                return ls_mio_text_error(diag, &t, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 triangles");
            prev = (uint32_t)idx;
        }
        k->np++;
        ls_mio_next_line(&t);
    }
    (void)ne;
    return LS_OK;
}

/* --- dispatch --------------------------------------------------------------- */

uint32_t ls_mesh_format_guess(const void *data, size_t bytes)
{
    text t;
    const char *s = (const char *)data, *tok;
    size_t start = 0, len;
    if (s == NULL || bytes == 0) return LS_MESH_FORMAT_OBJ;
    if (bytes >= 3 && (unsigned char)s[0] == 0xef && (unsigned char)s[1] == 0xbb && (unsigned char)s[2] == 0xbf) start = 3;
    if (bytes - start >= 4 && bytes_equal(s + start, "ply", 3) && ls_mio_is_eol(s[start + 3])) return LS_MESH_FORMAT_PLY;
    ls_mio_text_init(&t, s, bytes, start, 1);
    if (!content_line(&t)) return LS_MESH_FORMAT_OBJ;
    len = ls_mio_token(&t, &tok);
    if (len >= 3 && bytes_equal(tok + len - 3, "OFF", 3)) return LS_MESH_FORMAT_OFF;
    return LS_MESH_FORMAT_OBJ;
}

static ls_status read_any(const void *data, size_t bytes, uint32_t format, sink *k, ls_mesh_file_info *info, ls_diag *diag)
{
    const unsigned char *d = (const unsigned char *)data;
    size_t start = 0;
    ls_status st;
    if (data == NULL && bytes > 0) return ls_invalid_arg(diag, "data is NULL with bytes > 0");
    if (format > LS_MESH_FORMAT_OFF) return ls_invalid_arg(diag, "format: allowed LS_MESH_FORMAT_AUTO .. LS_MESH_FORMAT_OFF");
    if (bytes == 0) return ls_mio_offset_error(diag, 0, LS_ERR_PARSE, "empty file");
    if (format == LS_MESH_FORMAT_AUTO) format = ls_mesh_format_guess(data, bytes);
    k->nv = k->nt = k->np = 0;
    if (format == LS_MESH_FORMAT_PLY) {
        if (bytes >= 2 && ((d[0] == 0xfe && d[1] == 0xff) || (d[0] == 0xff && d[1] == 0xfe)))
            return ls_mio_offset_error(diag, 0, LS_ERR_UNSUPPORTED, "UTF-16 text (byte-order mark); convert the file to UTF-8");
        st = ls_mio_read_ply((const char *)data, bytes, k, diag);
    } else {
        st = text_prepare(d, bytes, &start, diag);
        if (st != LS_OK) return st;
        if (format == LS_MESH_FORMAT_OBJ) st = read_obj((const char *)data, bytes, start, k, diag);
        else st = read_off((const char *)data, bytes, start, 1, k, diag);
    }
    if (st != LS_OK) return st;
    if (k->nt == 0) return ls_mio_offset_error(diag, bytes, LS_ERR_MESH, "no triangles in the file (points or lines only?)");
    if (info != NULL) {
        info->format = format;
        info->vertex_count = (uint32_t)k->nv;
        info->face_count = (uint32_t)k->nt;
        info->polygon_count = k->np > U32_LIMIT ? U32_LIMIT : (uint32_t)k->np;
        info->binary = 0;
    }
    return LS_OK;
}

ls_status ls_mesh_read_info(const void *data, size_t bytes, uint32_t format, ls_mesh_file_info *info, ls_diag *diag)
{
    ls_diag_clear(diag);
    sink k;
    ls_mesh_file_info i;
    ls_status st;
    if (info == NULL) return ls_invalid_arg(diag, "info is NULL");
    k.p = NULL;
    k.t = NULL;
    st = read_any(data, bytes, format, &k, &i, diag);
    if (st != LS_OK) return st;
    if (i.format == LS_MESH_FORMAT_PLY) i.binary = ls_mio_ply_is_binary(data, bytes);
    *info = i;
    return LS_OK;
}

ls_status ls_mesh_read_bytes(const ls_mesh_file_info *info, size_t *bytes)
{
    if (info == NULL || bytes == NULL) return LS_ERR_INVALID;
    return ls_mesh_bytes(info->vertex_count, info->face_count, bytes);
}

ls_status ls_mesh_read(const void *data, size_t bytes, uint32_t format, ls_arena *arena, ls_mesh *mesh, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_mesh_file_info info;
    ls_mesh m;
    ls_arena_mark mark;
    sink k;
    ls_status st;
    if (arena == NULL) return ls_invalid_arg(diag, "arena is NULL");
    if (mesh == NULL) return ls_invalid_arg(diag, "mesh is NULL");
    st = ls_mesh_read_info(data, bytes, format, &info, diag);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    st = ls_mesh_alloc(&m, info.vertex_count, info.face_count, arena);
    if (st != LS_OK) return st;
    k.p = m.positions;
    k.t = m.triangles;
    st = read_any(data, bytes, info.format, &k, NULL, diag);
    if (st == LS_OK && (k.nv != info.vertex_count || k.nt != info.face_count)) st = LS_ERR_STATE;
    if (st != LS_OK) {
        ls_arena_restore(arena, mark);
        return st;
    }
    *mesh = m;
    return LS_OK;
}

/* --- writers ---------------------------------------------------------------- */

typedef struct out {
    ls_write_fn fn;
    void *user;
    size_t n;
    int32_t failed;
    unsigned char buf[512];
} out;

static void out_flush(out *o)
{
    if (o->n > 0 && !o->failed && o->fn(o->user, o->buf, o->n) != 0) o->failed = 1;
    o->n = 0;
}

static void out_put(out *o, const void *data, size_t len)
{
    const unsigned char *p = (const unsigned char *)data;
    while (len > 0 && !o->failed) {
        size_t room = sizeof o->buf - o->n, c = len < room ? len : room;
        memcpy(o->buf + o->n, p, c);
        o->n += c;
        p += c;
        len -= c;
        if (o->n == sizeof o->buf) out_flush(o);
    }
}

/* A string literal without its NUL. */
#define OUT_LIT(o, lit) out_put((o), (lit), sizeof(lit) - 1u)

static void out_u64(out *o, uint64_t v)
{
    char tmp[24];
    size_t i = sizeof tmp;
    do {
        tmp[--i] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0);
    out_put(o, tmp + i, sizeof tmp - i);
}

static ls_status write_begin(const ls_mesh *mesh, ls_write_fn write, out *o)
{
    size_t c;
    if (mesh == NULL || write == NULL) return LS_ERR_INVALID;
    if ((mesh->vertex_count > 0 && mesh->positions == NULL) || (mesh->face_count > 0 && mesh->triangles == NULL)) return LS_ERR_INVALID;
    for (c = 0; c < 3 * (size_t)mesh->face_count; c++) {
        if (mesh->triangles[c] >= mesh->vertex_count) return LS_ERR_MESH;
    }
    o->fn = write;
    o->n = 0;
    o->failed = 0;
    return LS_OK;
}

static ls_status write_end(out *o)
{
    out_flush(o);
    return o->failed ? LS_ERR_IO : LS_OK;
}

ls_status ls_mesh_write_obj(const ls_mesh *mesh, ls_write_fn write, void *user)
{
    out o;
    size_t i;
    uint32_t k;
    ls_status st = write_begin(mesh, write, &o);
    if (st != LS_OK) return st;
    o.user = user;
    for (i = 0; i < mesh->vertex_count && !o.failed; i++) {
        out_put(&o, "v", 1);
        for (k = 0; k < 3; k++) {
            char num[LS_NUMBER_CHARS + 1];
            size_t len;
            num[0] = ' ';
            len = ls_format_real(mesh->positions[3 * i + k], num + 1, LS_NUMBER_CHARS);
            out_put(&o, num, len + 1);
        }
        out_put(&o, "\n", 1);
    }
    for (i = 0; i < mesh->face_count && !o.failed; i++) {
        out_put(&o, "f", 1);
        for (k = 0; k < 3; k++) {
            out_put(&o, " ", 1);
            out_u64(&o, (uint64_t)mesh->triangles[3 * i + k] + 1u);
        }
        out_put(&o, "\n", 1);
    }
    return write_end(&o);
}

ls_status ls_mesh_write_ply(const ls_mesh *mesh, ls_write_fn write, void *user)
{
    out o;
    size_t i;
    uint32_t k;
    ls_status st = write_begin(mesh, write, &o);
    if (st != LS_OK) return st;
    o.user = user;
    OUT_LIT(&o, "ply\nformat binary_little_endian 1.0\ncomment written by largesteps\nelement vertex ");
    out_u64(&o, mesh->vertex_count);
#if LS_REAL_IS_FLOAT
    OUT_LIT(&o, "\nproperty float x\nproperty float y\nproperty float z\nelement face ");
#else
    OUT_LIT(&o, "\nproperty double x\nproperty double y\nproperty double z\nelement face ");
#endif
    out_u64(&o, mesh->face_count);
    OUT_LIT(&o, "\nproperty list uchar uint vertex_indices\nend_header\n");
    for (i = 0; i < 3 * (size_t)mesh->vertex_count && !o.failed; i++) {
        unsigned char b[8];
        uint64_t bits = 0;
#if LS_REAL_IS_FLOAT
        uint32_t fb;
        memcpy(&fb, &mesh->positions[i], sizeof fb);
        bits = fb;
#else
        memcpy(&bits, &mesh->positions[i], sizeof bits);
#endif
        for (k = 0; k < sizeof(ls_real); k++) b[k] = (unsigned char)(bits >> (8 * k));
        out_put(&o, b, sizeof(ls_real));
    }
    for (i = 0; i < mesh->face_count && !o.failed; i++) {
        unsigned char b[13];
        b[0] = 3;
        for (k = 0; k < 12; k++) b[1 + k] = (unsigned char)(mesh->triangles[3 * i + k / 4] >> (8 * (k % 4)));
        out_put(&o, b, sizeof b);
    }
    return write_end(&o);
}
