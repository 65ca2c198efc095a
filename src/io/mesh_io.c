/* mesh_io.c - OBJ, PLY and OFF readers (two passes over a memory buffer:
 * check and count, then fill) and OBJ / binary PLY writers. */
#include <largesteps/mesh_io.h>
#include <largesteps/number.h>
#include <string.h>

#define U32_LIMIT 0xffffffffu

/* --- text cursor ------------------------------------------------------- */

typedef struct text {
    const char *s;
    size_t n;
    size_t pos;
    size_t line_start;
    uint32_t line;
    uint32_t hash_comments; /* '#' ends the useful part of a line */
} text;

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

static int is_eol(char c)
{
    return c == '\n' || c == '\r';
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

static void text_init(text *t, const char *s, size_t n, size_t start, uint32_t hash_comments)
{
    t->s = s;
    t->n = n;
    t->pos = start;
    t->line_start = start;
    t->line = 1;
    t->hash_comments = hash_comments;
}

static void skip_spaces(text *t)
{
    while (t->pos < t->n && is_space(t->s[t->pos])) t->pos++;
}

/* Moves past the end of the current line (LF, CRLF or a lone CR). */
static void next_line(text *t)
{
    while (t->pos < t->n && !is_eol(t->s[t->pos])) t->pos++;
    if (t->pos < t->n) {
        if (t->s[t->pos] == '\r' && t->pos + 1 < t->n && t->s[t->pos + 1] == '\n') t->pos++;
        t->pos++;
    }
    if (t->line < U32_LIMIT) t->line++;
    t->line_start = t->pos;
}

/* The next token of the current line (0 at its end or at a comment). */
static size_t token(text *t, const char **tok)
{
    size_t start;
    skip_spaces(t);
    start = t->pos;
    *tok = t->s + start;
    if (t->pos < t->n && t->hash_comments && t->s[t->pos] == '#') return 0;
    while (t->pos < t->n && !is_space(t->s[t->pos]) && !is_eol(t->s[t->pos])) {
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
        size_t at = t->pos, len = token(t, &tok);
        if (len > 0) {
            t->pos = at;
            return 1;
        }
        if (t->pos >= t->n) return 0;
        next_line(t);
    }
}

static ls_status text_error(ls_diag *diag, const text *t, size_t at, ls_status st, const char *what)
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

static ls_status offset_error(ls_diag *diag, size_t at, ls_status st, const char *what)
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
static int parse_uint(const char *tok, size_t len, uint64_t limit, uint64_t *out)
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
static int parse_int(const char *tok, size_t len, uint64_t limit, int64_t *out)
{
    uint64_t v = 0;
    int neg = len > 0 && tok[0] == '-', r;
    if (neg) {
        tok++;
        len--;
        if (len > 0 && tok[0] == '+') return 0;
    }
    r = parse_uint(tok, len, limit, &v);
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
        return offset_error(diag, 0, LS_ERR_UNSUPPORTED, "UTF-16 text (byte-order mark); convert the file to UTF-8");
    if (n >= 3 && d[0] == 0xef && d[1] == 0xbb && d[2] == 0xbf) s = 3;
    for (i = s; i < n; i++) {
        if (d[i] == 0) return offset_error(diag, i, LS_ERR_PARSE, "NUL byte in a text file (UTF-16 without a byte-order mark, or binary data)");
        if (!content && !is_space((char)d[i]) && !is_eol((char)d[i])) content = 1;
    }
    if (!content) return offset_error(diag, n, LS_ERR_PARSE, "empty file");
    *start = s;
    return LS_OK;
}

/* Coordinates must be finite ("nan", "inf" and binary NaN/infinity are rejected). */
#define COORD_NONFINITE "vertex coordinate is NaN or infinite"
static int coord_finite(ls_real v) { return v - v == (ls_real)0; }

/* Reads one coordinate token into *v. */
static ls_status read_coord(text *t, ls_real *v, ls_diag *diag, const char *missing)
{
    const char *tok;
    size_t at, len;
    ls_status st;
    skip_spaces(t);
    at = t->pos;
    len = token(t, &tok);
    if (len == 0) return text_error(diag, t, at, LS_ERR_PARSE, missing);
    st = ls_parse_real(tok, len, v);
    if (st == LS_ERR_TOO_LARGE) return text_error(diag, t, at, LS_ERR_TOO_LARGE, "number too large for ls_real");
    if (st != LS_OK) return text_error(diag, t, at, LS_ERR_PARSE, "invalid number");
    if (!coord_finite(*v)) return text_error(diag, t, at, LS_ERR_NONFINITE, COORD_NONFINITE);
    return LS_OK;
}

/* Output of the second pass (NULL pointers in the first). */
typedef struct sink {
    ls_real *p;
    uint32_t *t;
    uint64_t nv; /* vertices so far */
    uint64_t nt; /* triangles so far */
    uint64_t np; /* polygons so far */
} sink;

/* Adds triangle (a, b, c). */
static int add_tri(sink *k, uint32_t a, uint32_t b, uint32_t c)
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
    r = parse_int(tok, i, U32_LIMIT, out);
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
    text_init(&t, s, n, start, 1);
    while (t.pos < t.n) {
        const char *kw, *tok;
        size_t kat, kl, len;
        skip_spaces(&t);
        kat = t.pos;
        kl = token(&t, &kw);
        if (kl == 1 && kw[0] == 'v') {
            uint32_t c;
            if (k->nv >= U32_LIMIT) return text_error(diag, &t, kat, LS_ERR_TOO_LARGE, "more than 2^32 - 1 vertices");
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
                skip_spaces(&t);
                at = t.pos;
                len = token(&t, &tok);
                if (len == 0) break;
                ok = obj_index(tok, len, &idx);
                if (ok == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid face index token");
                if (ok < 0) return text_error(diag, &t, at, LS_ERR_PARSE, "face index out of range");
                if (idx == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "face index 0 (OBJ indices start at 1)");
                if (idx < 0) {
                    if ((uint64_t)(-idx) > k->nv)
                        return text_error(diag, &t, at, LS_ERR_PARSE, "relative face index before the first vertex");
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
                if (corners >= 2 && !add_tri(k, first, prev, r))
                    return text_error(diag, &t, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 triangles");
                prev = r;
                corners++;
            }
            if (corners < 3) return text_error(diag, &t, kat, LS_ERR_PARSE, "face with fewer than 3 vertices");
            k->np++;
        }
        next_line(&t);
    }
    if (max_index > k->nv) {
        t.line = max_line;
        t.line_start = max_line_start;
        return text_error(diag, &t, max_at, LS_ERR_PARSE, "face index out of range");
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
    text_init(&t, s, n, start, 1);
    if (!content_line(&t)) return text_error(diag, &t, t.pos, LS_ERR_PARSE, "empty file");
    at = t.pos;
    len = token(&t, &tok);
    if (len >= 3 && bytes_equal(tok + len - 3, "OFF", 3)) {
        for (i = 0; i + 3 < len; i++) {
            if (tok[i] == '4' || tok[i] == 'n') return text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "4D or n-dimensional OFF");
            if (tok[i] != 'S' && tok[i] != 'T' && tok[i] != 'C' && tok[i] != 'N')
                return text_error(diag, &t, at, LS_ERR_PARSE, "unknown OFF keyword");
        }
        skip_spaces(&t);
        at = t.pos;
        len = token(&t, &tok);
        if (len == 6 && bytes_equal(tok, "BINARY", 6)) return text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "binary OFF");
        t.pos = at;
        if (len == 0) {
            next_line(&t);
            if (!content_line(&t)) return text_error(diag, &t, t.pos, LS_ERR_PARSE, "OFF file ends before its counts");
        }
    } else if (!explicit_off) {
        return text_error(diag, &t, at, LS_ERR_PARSE, "missing OFF keyword");
    } else {
        t.pos = at;
    }
    skip_spaces(&t);
    at = t.pos;
    len = token(&t, &tok);
    r = parse_uint(tok, len, UINT64_MAX, &nv);
    if (r == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF vertex count");
    if (r < 0) return text_error(diag, &t, at, LS_ERR_PARSE, "OFF vertex count larger than the file");
    skip_spaces(&t);
    at = t.pos;
    len = token(&t, &tok);
    r = parse_uint(tok, len, UINT64_MAX, &nf);
    if (r == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF face count");
    if (r < 0) return text_error(diag, &t, at, LS_ERR_PARSE, "OFF face count larger than the file");
    skip_spaces(&t);
    at = t.pos;
    len = token(&t, &tok);
    if (len > 0 && parse_uint(tok, len, UINT64_MAX, &ne) != 1) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF edge count");
    /* a vertex record takes at least 6 bytes ("0 0 0\n"), a face record 2 ("3\n" is short but still a record) */
    rem = t.n - t.pos;
    if (nv > (uint64_t)rem / 6u + 1u || nf > (uint64_t)rem / 2u + 1u || nv * 6u + nf * 2u > (uint64_t)rem + 2u)
        return text_error(diag, &t, at, LS_ERR_PARSE, "OFF counts larger than the file");
    if (nv > U32_LIMIT) return text_error(diag, &t, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 vertices");
    next_line(&t);
    for (i = 0; i < nv; i++) {
        uint32_t c;
        if (!content_line(&t)) return text_error(diag, &t, t.pos, LS_ERR_PARSE, "OFF file ends before all its vertices");
        for (c = 0; c < 3; c++) {
            ls_real v = 0;
            st = read_coord(&t, &v, diag, "vertex with fewer than 3 coordinates");
            if (st != LS_OK) return st;
            if (k->p != NULL) k->p[3 * i + c] = v;
        }
        next_line(&t);
    }
    k->nv = nv;
    for (i = 0; i < nf; i++) {
        uint64_t cnt = 0, j;
        uint32_t first = 0, prev = 0;
        if (!content_line(&t)) return text_error(diag, &t, t.pos, LS_ERR_PARSE, "OFF file ends before all its faces");
        at = t.pos;
        len = token(&t, &tok);
        r = parse_uint(tok, len, U32_LIMIT, &cnt);
        if (r == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid OFF face vertex count");
        if (r < 0 || cnt > t.n) return text_error(diag, &t, at, LS_ERR_PARSE, "OFF face vertex count larger than the file");
        if (cnt < 3) return text_error(diag, &t, at, LS_ERR_PARSE, "face with fewer than 3 vertices");
        for (j = 0; j < cnt; j++) {
            uint64_t idx = 0;
            skip_spaces(&t);
            at = t.pos;
            len = token(&t, &tok);
            if (len == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "face with fewer indices than its count");
            r = parse_uint(tok, len, U32_LIMIT, &idx);
            if (r == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid face index");
            if (r < 0 || idx >= nv) return text_error(diag, &t, at, LS_ERR_PARSE, "face index out of range");
            if (j == 0) first = (uint32_t)idx;
            if (j >= 2 && !add_tri(k, first, prev, (uint32_t)idx))
                return text_error(diag, &t, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 triangles");
            prev = (uint32_t)idx;
        }
        k->np++;
        next_line(&t);
    }
    (void)ne;
    return LS_OK;
}

/* --- PLY ------------------------------------------------------------------ */

#define PLY_MAX_ELEMENTS 16u
#define PLY_MAX_PROPS 64u
#define PLY_ASCII 0u
#define PLY_LE 1u
#define PLY_BE 2u

/* scalar types: 1 int8, 2 uint8, 3 int16, 4 uint16, 5 int32, 6 uint32, 7 float32, 8 float64 */
static const uint8_t ply_size[9] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

#define ROLE_NONE 0u
#define ROLE_X 1u /* X, Y, Z = 1, 2, 3 */
#define ROLE_INDICES 4u

typedef struct ply_prop {
    uint8_t type;       /* item type for lists */
    uint8_t count_type; /* 0 for a scalar */
    uint8_t role;
    uint8_t pad;
} ply_prop;

typedef struct ply_elem {
    uint64_t count;
    uint16_t first;  /* index of its first property */
    uint16_t nprops;
    uint32_t kind;   /* 0 other, 1 vertex, 2 face */
} ply_elem;

typedef struct ply_header {
    ply_elem el[PLY_MAX_ELEMENTS];
    ply_prop pr[PLY_MAX_PROPS];
    uint32_t nel;
    uint32_t npr;
    uint32_t format;
    uint32_t has_format;
} ply_header;

/* 1 when tok[0..len) is the NUL-terminated word. */
static int tok_is(const char *tok, size_t len, const char *word)
{
    size_t i;
    for (i = 0; i < len; i++) {
        if (word[i] == 0 || word[i] != tok[i]) return 0;
    }
    return word[len] == 0;
}

static uint8_t ply_type(const char *tok, size_t len)
{
    static const char *const names[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                        "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
    uint8_t i;
    for (i = 0; i < 16; i++) {
        if (tok_is(tok, len, names[i])) return (uint8_t)(i % 8u + 1u);
    }
    return 0;
}


static ls_status ply_property(text *t, ply_header *h, size_t at, ls_diag *diag)
{
    const char *tok;
    size_t len;
    ply_elem *e;
    ply_prop p;
    if (h->nel == 0) return text_error(diag, t, at, LS_ERR_PARSE, "PLY property before any element");
    if (h->npr >= PLY_MAX_PROPS) return text_error(diag, t, at, LS_ERR_UNSUPPORTED, "more than 64 PLY properties");
    e = &h->el[h->nel - 1];
    p.count_type = 0;
    p.role = ROLE_NONE;
    p.pad = 0;
    len = token(t, &tok);
    if (tok_is(tok, len, "list")) {
        len = token(t, &tok);
        p.count_type = ply_type(tok, len);
        if (p.count_type == 0) return text_error(diag, t, at, LS_ERR_PARSE, "unknown PLY property type");
        if (p.count_type >= 7) return text_error(diag, t, at, LS_ERR_PARSE, "PLY list count type must be an integer type");
        len = token(t, &tok);
    }
    p.type = ply_type(tok, len);
    if (p.type == 0) return text_error(diag, t, at, LS_ERR_PARSE, "unknown PLY property type");
    len = token(t, &tok);
    if (len == 0) return text_error(diag, t, at, LS_ERR_PARSE, "PLY property without a name");
    if (e->kind == 1 && p.count_type == 0 && len == 1 && tok[0] >= 'x' && tok[0] <= 'z') p.role = (uint8_t)(ROLE_X + (uint8_t)(tok[0] - 'x'));
    if (e->kind == 2 && p.count_type != 0 && (tok_is(tok, len, "vertex_indices") || tok_is(tok, len, "vertex_index"))) {
        uint32_t q;
        if (p.type >= 7) return text_error(diag, t, at, LS_ERR_PARSE, "PLY vertex_indices must have an integer type");
        p.role = ROLE_INDICES;
        for (q = e->first; q < h->npr; q++) {
            if (h->pr[q].role == ROLE_INDICES) p.role = ROLE_NONE; /* the first one counts */
        }
    }
    if (p.role >= ROLE_X && p.role < ROLE_INDICES) {
        uint32_t q;
        for (q = e->first; q < h->npr; q++) {
            if (h->pr[q].role == p.role) return text_error(diag, t, at, LS_ERR_PARSE, "PLY vertex coordinate declared twice");
        }
    }
    h->pr[h->npr++] = p;
    e->nprops++;
    return LS_OK;
}

/* Parses the header; *body is the offset of the first data byte. */
static ls_status ply_header_read(const char *s, size_t n, ply_header *h, size_t *body, ls_diag *diag)
{
    text t;
    const char *tok;
    size_t len;
    int r;
    ls_status st;
    text_init(&t, s, n, 0, 0);
    h->nel = 0;
    h->npr = 0;
    h->has_format = 0;
    h->format = PLY_ASCII;
    len = token(&t, &tok);
    if (!tok_is(tok, len, "ply") || token(&t, &tok) != 0) return text_error(diag, &t, 0, LS_ERR_PARSE, "missing PLY magic line \"ply\"");
    next_line(&t);
    for (;;) {
        size_t at;
        if (t.pos >= t.n) return text_error(diag, &t, t.pos, LS_ERR_PARSE, "PLY header without end_header");
        skip_spaces(&t);
        at = t.pos;
        len = token(&t, &tok);
        if (tok_is(tok, len, "end_header")) {
            if (!h->has_format) return text_error(diag, &t, at, LS_ERR_PARSE, "PLY header without a format line");
            next_line(&t);
            *body = t.pos;
            return LS_OK;
        } else if (tok_is(tok, len, "comment") || tok_is(tok, len, "obj_info") || len == 0) {
            /* skipped */
        } else if (tok_is(tok, len, "format")) {
            len = token(&t, &tok);
            if (tok_is(tok, len, "ascii")) h->format = PLY_ASCII;
            else if (tok_is(tok, len, "binary_little_endian")) h->format = PLY_LE;
            else if (tok_is(tok, len, "binary_big_endian")) h->format = PLY_BE;
            else return text_error(diag, &t, at, LS_ERR_PARSE, "unknown PLY format");
            len = token(&t, &tok);
            if (!tok_is(tok, len, "1.0")) return text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "PLY version other than 1.0");
            h->has_format = 1;
        } else if (tok_is(tok, len, "element")) {
            ply_elem *e;
            uint32_t q;
            if (h->nel >= PLY_MAX_ELEMENTS) return text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "more than 16 PLY elements");
            e = &h->el[h->nel];
            len = token(&t, &tok);
            e->kind = tok_is(tok, len, "vertex") ? 1u : tok_is(tok, len, "face") ? 2u : 0u;
            for (q = 0; q < h->nel && e->kind != 0; q++) {
                if (h->el[q].kind == e->kind) return text_error(diag, &t, at, LS_ERR_PARSE, "PLY element declared twice");
            }
            len = token(&t, &tok);
            r = parse_uint(tok, len, UINT64_MAX, &e->count);
            if (r == 0) return text_error(diag, &t, at, LS_ERR_PARSE, "invalid PLY element count");
            if (r < 0) return text_error(diag, &t, at, LS_ERR_PARSE, "PLY element count larger than the file");
            e->first = (uint16_t)h->npr;
            e->nprops = 0;
            h->nel++;
        } else if (tok_is(tok, len, "property")) {
            st = ply_property(&t, h, at, diag);
            if (st != LS_OK) return st;
        } else {
            return text_error(diag, &t, at, LS_ERR_PARSE, "unknown PLY header line");
        }
        next_line(&t);
    }
}

/* The data of a PLY body: binary bytes or ascii tokens. */
typedef struct ply_in {
    text t;
    const unsigned char *d;
    uint32_t format;
} ply_in;

static ls_status ply_truncated(ply_in *in, ls_diag *diag)
{
    if (in->format == PLY_ASCII) return text_error(diag, &in->t, in->t.pos, LS_ERR_PARSE, "PLY data ends early (fewer values than the header declares)");
    return offset_error(diag, in->t.pos, LS_ERR_PARSE, "truncated binary body");
}

/* Skips ascii white space and line ends (binary: nothing). */
static void ply_skip_ws(ply_in *in)
{
    if (in->format != PLY_ASCII) return;
    for (;;) {
        skip_spaces(&in->t);
        if (in->t.pos >= in->t.n || !is_eol(in->t.s[in->t.pos])) return;
        next_line(&in->t);
    }
}

/* The next ascii token across line ends. */
static size_t ply_token(ply_in *in, const char **tok, size_t *at)
{
    for (;;) {
        size_t len;
        skip_spaces(&in->t);
        *at = in->t.pos;
        len = token(&in->t, tok);
        if (len > 0 || in->t.pos >= in->t.n) return len;
        next_line(&in->t);
    }
}

/* Raw binary scalar as 64 bits (sign-extended integers, float bits as is). */
static ls_status ply_raw(ply_in *in, uint8_t type, uint64_t *out, ls_diag *diag)
{
    size_t sz = ply_size[type], i;
    uint64_t v = 0;
    const unsigned char *b;
    if (in->t.n - in->t.pos < sz) return ply_truncated(in, diag);
    b = in->d + in->t.pos;
    for (i = 0; i < sz; i++) {
        size_t at = in->format == PLY_LE ? sz - 1 - i : i;
        v = (v << 8) | b[at];
    }
    in->t.pos += sz;
    if ((type == 1 || type == 3 || type == 5) && sz > 0 && sz < 8 && (v >> (8 * sz - 1)) != 0) v |= ~(uint64_t)0 << (8 * sz);
    *out = v;
    return LS_OK;
}

/* An integer-typed value. */
static ls_status ply_int(ply_in *in, uint8_t type, int64_t *out, ls_diag *diag)
{
    if (in->format == PLY_ASCII) {
        const char *tok;
        size_t at, len = ply_token(in, &tok, &at);
        int r;
        if (len == 0) return ply_truncated(in, diag);
        r = parse_int(tok, len, U32_LIMIT, out);
        if (r == 0) return text_error(diag, &in->t, at, LS_ERR_PARSE, "invalid integer in PLY data");
        if (r < 0 || (type % 2u == 0 && *out < 0) || (ply_size[type] == 1 && (*out > 255 || *out < -128)) ||
            (ply_size[type] == 2 && (*out > 65535 || *out < -32768)))
            return text_error(diag, &in->t, at, LS_ERR_PARSE, "PLY integer out of range for its type");
        return LS_OK;
    } else {
        uint64_t raw = 0;
        ls_status st = ply_raw(in, type, &raw, diag);
        if (st != LS_OK) return st;
        memcpy(out, &raw, sizeof raw); /* sign-extended or below 2^32: the value as int64 */
        return LS_OK;
    }
}

#if LS_REAL_IS_FLOAT
/* The float nearest to the double with these bits (ties to even), with
 * integer operations only: the float build has no double arithmetic. */
static float float_from_double_bits(uint64_t b)
{
    uint32_t out, sign = (uint32_t)(b >> 32) & 0x80000000u;
    int32_t e = (int32_t)((b >> 52) & 0x7ffu), E = e - 1023 + 127;
    uint64_t full = (b & (((uint64_t)1 << 52) - 1u)) | ((uint64_t)1 << 52);
    float f;
    if (e == 0x7ff) {
        out = (b & (((uint64_t)1 << 52) - 1u)) != 0 ? 0x7fc00000u : 0x7f800000u;
    } else if (e == 0 || E < -30) {
        out = 0; /* below 2^-157: rounds to zero */
    } else {
        int32_t sh = E >= 1 ? 29 : 30 - E; /* bits dropped from the 53-bit significand */
        uint64_t q = full >> sh, r = full & (((uint64_t)1 << sh) - 1u), half = (uint64_t)1 << (sh - 1);
        if (r > half || (r == half && (q & 1u) != 0)) q++;
        if (E >= 1) {
            if ((q >> 24) != 0) {
                q >>= 1;
                E++;
            }
            out = E >= 255 ? 0x7f800000u : ((uint32_t)E << 23) | ((uint32_t)q & 0x7fffffu);
        } else {
            out = (uint32_t)q; /* a carry into bit 23 is the smallest normal, as it should be */
        }
    }
    out |= sign;
    memcpy(&f, &out, sizeof f);
    return f;
}
#endif

/* A coordinate of any type as ls_real. */
static ls_status ply_real(ply_in *in, uint8_t type, ls_real *out, ls_diag *diag)
{
    if (in->format == PLY_ASCII) {
        const char *tok;
        size_t at, len = ply_token(in, &tok, &at);
        ls_status st;
        if (len == 0) return ply_truncated(in, diag);
        st = ls_parse_real(tok, len, out);
        if (st == LS_ERR_TOO_LARGE) return text_error(diag, &in->t, at, LS_ERR_TOO_LARGE, "number too large for ls_real");
        if (st != LS_OK) return text_error(diag, &in->t, at, LS_ERR_PARSE, "invalid number");
        if (!coord_finite(*out)) return text_error(diag, &in->t, at, LS_ERR_NONFINITE, COORD_NONFINITE);
        return LS_OK;
    } else {
        uint64_t raw = 0;
        size_t at = in->t.pos;
        ls_status st = ply_raw(in, type, &raw, diag);
        if (st != LS_OK) return st;
        if (type == 7) {
            uint32_t b = (uint32_t)raw;
            float f;
            memcpy(&f, &b, sizeof f);
            *out = (ls_real)f;
        } else if (type == 8) {
#if LS_REAL_IS_FLOAT
            *out = float_from_double_bits(raw);
#else
            memcpy(out, &raw, sizeof raw);
#endif
        } else {
            /* int8 ... uint32: exact in 32 bits (converted without 64-bit helpers) */
            if (type == 6) {
                *out = (ls_real)(uint32_t)raw;
            } else {
                int64_t i;
                memcpy(&i, &raw, sizeof i);
                *out = (ls_real)(int32_t)i;
            }
        }
        if (!coord_finite(*out)) {
            /* a finite double beyond float's range (float build) is too large, as in text */
            if (type == 8 && ((raw >> 52) & 0x7ffu) != 0x7ffu)
                return offset_error(diag, at, LS_ERR_TOO_LARGE, "number too large for ls_real");
            return offset_error(diag, at, LS_ERR_NONFINITE, COORD_NONFINITE);
        }
        return LS_OK;
    }
}

/* Skips one value of any type (checking ascii numbers). */
static ls_status ply_skip(ply_in *in, uint8_t type, ls_diag *diag)
{
    if (in->format == PLY_ASCII) {
        const char *tok;
        size_t at, len = ply_token(in, &tok, &at);
        if (len == 0) return ply_truncated(in, diag);
        if (ls_scan_number(tok, len) != len) return text_error(diag, &in->t, at, LS_ERR_PARSE, "invalid number");
        return LS_OK;
    }
    if (in->t.n - in->t.pos < ply_size[type]) return ply_truncated(in, diag);
    in->t.pos += ply_size[type];
    return LS_OK;
}

static ls_status ply_list(ply_in *in, const ply_prop *p, uint64_t nv, sink *k, ls_diag *diag)
{
    int64_t cnt = 0, j;
    uint32_t first = 0, prev = 0;
    size_t at;
    ls_status st;
    ply_skip_ws(in);
    at = in->t.pos;
    st = ply_int(in, p->count_type, &cnt, diag);
    if (st != LS_OK) return st;
    if (cnt < 0) return offset_error(diag, at, LS_ERR_PARSE, "negative PLY list count");
    if (p->role == ROLE_INDICES && cnt < 3) {
        if (in->format == PLY_ASCII) return text_error(diag, &in->t, at, LS_ERR_PARSE, "face with fewer than 3 vertices");
        return offset_error(diag, at, LS_ERR_PARSE, "face with fewer than 3 vertices");
    }
    for (j = 0; j < cnt; j++) {
        if (p->role != ROLE_INDICES) {
            st = ply_skip(in, p->type, diag);
            if (st != LS_OK) return st;
        } else {
            int64_t idx = 0;
            ply_skip_ws(in);
            at = in->t.pos;
            st = ply_int(in, p->type, &idx, diag);
            if (st != LS_OK) return st;
            if (idx < 0 || (uint64_t)idx >= nv) {
                if (in->format == PLY_ASCII) return text_error(diag, &in->t, at, LS_ERR_PARSE, "face index out of range");
                return offset_error(diag, at, LS_ERR_PARSE, "face index out of range");
            }
            if (j == 0) first = (uint32_t)idx;
            if (j >= 2 && !add_tri(k, first, prev, (uint32_t)idx)) return offset_error(diag, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 triangles");
            prev = (uint32_t)idx;
        }
    }
    if (p->role == ROLE_INDICES) k->np++;
    return LS_OK;
}

static ls_status read_ply(const char *s, size_t n, sink *k, ls_diag *diag)
{
    ply_header h;
    ply_in in;
    size_t body = 0;
    uint32_t e, q, roles = 0, has_indices = 0;
    uint64_t nv = 0;
    ls_status st = ply_header_read(s, n, &h, &body, diag);
    if (st != LS_OK) return st;
    /* the vertex element, its coordinates, the face list */
    for (e = 0; e < h.nel; e++) {
        const ply_elem *el = &h.el[e];
        for (q = el->first; q < (uint32_t)el->first + el->nprops; q++) {
            if (el->kind == 1 && h.pr[q].role >= ROLE_X && h.pr[q].role < ROLE_INDICES) roles |= 1u << h.pr[q].role;
            if (h.pr[q].role == ROLE_INDICES) has_indices = 1;
        }
        if (el->kind == 1) nv = el->count;
    }
    if (roles != 0xeu) return offset_error(diag, body, LS_ERR_PARSE, "PLY vertex element without x, y and z (or no vertex element)");
    for (e = 0; e < h.nel; e++) {
        if (h.el[e].kind == 2 && !has_indices) return offset_error(diag, body, LS_ERR_PARSE, "PLY face element without vertex_indices");
    }
    /* header counts against the bytes that are there (2 bytes per ascii value at least) */
    for (e = 0; e < h.nel; e++) {
        const ply_elem *el = &h.el[e];
        uint64_t min_bytes = 0;
        for (q = el->first; q < (uint32_t)el->first + el->nprops; q++)
            min_bytes += h.format == PLY_ASCII ? 2u : ply_size[h.pr[q].count_type != 0 ? h.pr[q].count_type : h.pr[q].type];
        if (min_bytes > 0 && el->count > (uint64_t)(n - body + 1u) / min_bytes)
            return offset_error(diag, body, LS_ERR_PARSE, "PLY element count larger than the file");
    }
    if (nv > U32_LIMIT) return offset_error(diag, body, LS_ERR_TOO_LARGE, "more than 2^32 - 1 vertices");
    text_init(&in.t, s, n, body, 0);
    in.d = (const unsigned char *)s;
    in.format = h.format;
    {
        /* line numbers of ascii data: count the header lines */
        size_t i;
        for (i = 0; i < body; i++) {
            if (s[i] == '\n' || (s[i] == '\r' && (i + 1 >= body || s[i + 1] != '\n'))) in.t.line++;
        }
    }
    for (e = 0; e < h.nel; e++) {
        const ply_elem *el = &h.el[e];
        uint64_t item;
        if (el->nprops == 0) continue;
        for (item = 0; item < el->count; item++) {
            for (q = el->first; q < (uint32_t)el->first + el->nprops; q++) {
                const ply_prop *p = &h.pr[q];
                if (p->count_type != 0) {
                    st = ply_list(&in, p, nv, k, diag);
                } else if (p->role >= ROLE_X && p->role < ROLE_INDICES && el->kind == 1) {
                    ls_real v = 0;
                    st = ply_real(&in, p->type, &v, diag);
                    if (k->p != NULL) k->p[3 * item + (p->role - ROLE_X)] = v;
                } else {
                    st = ply_skip(&in, p->type, diag);
                }
                if (st != LS_OK) return st;
            }
        }
    }
    k->nv = nv;
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
    if (bytes - start >= 4 && bytes_equal(s + start, "ply", 3) && is_eol(s[start + 3])) return LS_MESH_FORMAT_PLY;
    text_init(&t, s, bytes, start, 1);
    if (!content_line(&t)) return LS_MESH_FORMAT_OBJ;
    len = token(&t, &tok);
    if (len >= 3 && bytes_equal(tok + len - 3, "OFF", 3)) return LS_MESH_FORMAT_OFF;
    return LS_MESH_FORMAT_OBJ;
}

static ls_status read_any(const void *data, size_t bytes, uint32_t format, sink *k, ls_mesh_file_info *info, ls_diag *diag)
{
    const unsigned char *d = (const unsigned char *)data;
    size_t start = 0;
    ls_status st;
    if (data == NULL && bytes > 0) return LS_ERR_INVALID;
    if (format > LS_MESH_FORMAT_OFF) return LS_ERR_INVALID;
    if (bytes == 0) return offset_error(diag, 0, LS_ERR_PARSE, "empty file");
    if (format == LS_MESH_FORMAT_AUTO) format = ls_mesh_format_guess(data, bytes);
    k->nv = k->nt = k->np = 0;
    if (format == LS_MESH_FORMAT_PLY) {
        if (bytes >= 2 && ((d[0] == 0xfe && d[1] == 0xff) || (d[0] == 0xff && d[1] == 0xfe)))
            return offset_error(diag, 0, LS_ERR_UNSUPPORTED, "UTF-16 text (byte-order mark); convert the file to UTF-8");
        st = read_ply((const char *)data, bytes, k, diag);
    } else {
        st = text_prepare(d, bytes, &start, diag);
        if (st != LS_OK) return st;
        if (format == LS_MESH_FORMAT_OBJ) st = read_obj((const char *)data, bytes, start, k, diag);
        else st = read_off((const char *)data, bytes, start, 1, k, diag);
    }
    if (st != LS_OK) return st;
    if (k->nt == 0) return offset_error(diag, bytes, LS_ERR_MESH, "no triangles in the file (points or lines only?)");
    if (info != NULL) {
        info->format = format;
        info->vertex_count = (uint32_t)k->nv;
        info->face_count = (uint32_t)k->nt;
        info->polygon_count = k->np > U32_LIMIT ? U32_LIMIT : (uint32_t)k->np;
        info->binary = 0;
    }
    return LS_OK;
}

/* 1 when the PLY header says binary (for the info field). */
static uint32_t ply_is_binary(const void *data, size_t bytes)
{
    ply_header h;
    size_t body = 0;
    if (ply_header_read((const char *)data, bytes, &h, &body, NULL) != LS_OK) return 0;
    return h.format != PLY_ASCII ? 1u : 0u;
}

ls_status ls_mesh_read_info(const void *data, size_t bytes, uint32_t format, ls_mesh_file_info *info, ls_diag *diag)
{
    ls_diag_clear(diag);
    sink k;
    ls_mesh_file_info i;
    ls_status st;
    if (info == NULL) return LS_ERR_INVALID;
    k.p = NULL;
    k.t = NULL;
    st = read_any(data, bytes, format, &k, &i, diag);
    if (st != LS_OK) return st;
    if (i.format == LS_MESH_FORMAT_PLY) i.binary = ply_is_binary(data, bytes);
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
    if (arena == NULL || mesh == NULL) return LS_ERR_INVALID;
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
