/* mesh_ply.c - the PLY reader (ASCII, binary little- and big-endian) of
 * include/largesteps/mesh_io.h */
#include "mesh_io_internal.h"

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
    if (h->nel == 0) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "PLY property before any element");
    if (h->npr >= PLY_MAX_PROPS) return ls_mio_text_error(diag, t, at, LS_ERR_UNSUPPORTED, "more than 64 PLY properties");
    e = &h->el[h->nel - 1];
    p.count_type = 0;
    p.role = ROLE_NONE;
    p.pad = 0;
    len = ls_mio_token(t, &tok);
    if (tok_is(tok, len, "list")) {
        len = ls_mio_token(t, &tok);
        p.count_type = ply_type(tok, len);
        if (p.count_type == 0) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "unknown PLY property type");
        if (p.count_type >= 7) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "PLY list count type must be an integer type");
        len = ls_mio_token(t, &tok);
    }
    p.type = ply_type(tok, len);
    if (p.type == 0) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "unknown PLY property type");
    len = ls_mio_token(t, &tok);
    if (len == 0) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "PLY property without a name");
    if (e->kind == 1 && p.count_type == 0 && len == 1 && tok[0] >= 'x' && tok[0] <= 'z') p.role = (uint8_t)(ROLE_X + (uint8_t)(tok[0] - 'x'));
    if (e->kind == 2 && p.count_type != 0 && (tok_is(tok, len, "vertex_indices") || tok_is(tok, len, "vertex_index"))) {
        uint32_t q;
        if (p.type >= 7) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "PLY vertex_indices must have an integer type");
        p.role = ROLE_INDICES;
        for (q = e->first; q < h->npr; q++) {
            if (h->pr[q].role == ROLE_INDICES) p.role = ROLE_NONE; /* the first one counts */
        }
    }
    if (p.role >= ROLE_X && p.role < ROLE_INDICES) {
        uint32_t q;
        for (q = e->first; q < h->npr; q++) {
            if (h->pr[q].role == p.role) return ls_mio_text_error(diag, t, at, LS_ERR_PARSE, "PLY vertex coordinate declared twice");
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
    ls_mio_text_init(&t, s, n, 0, 0);
    h->nel = 0;
    h->npr = 0;
    h->has_format = 0;
    h->format = PLY_ASCII;
    len = ls_mio_token(&t, &tok);
    if (!tok_is(tok, len, "ply") || ls_mio_token(&t, &tok) != 0) return ls_mio_text_error(diag, &t, 0, LS_ERR_PARSE, "missing PLY magic line \"ply\"");
    ls_mio_next_line(&t);
    for (;;) {
        size_t at;
        if (t.pos >= t.n) return ls_mio_text_error(diag, &t, t.pos, LS_ERR_PARSE, "PLY header without end_header");
        ls_mio_skip_spaces(&t);
        at = t.pos;
        len = ls_mio_token(&t, &tok);
        if (tok_is(tok, len, "end_header")) {
            if (!h->has_format) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "PLY header without a format line");
            ls_mio_next_line(&t);
            *body = t.pos;
            return LS_OK;
        } else if (tok_is(tok, len, "comment") || tok_is(tok, len, "obj_info") || len == 0) {
            /* skipped */
        } else if (tok_is(tok, len, "format")) {
            len = ls_mio_token(&t, &tok);
            if (tok_is(tok, len, "ascii")) h->format = PLY_ASCII;
            else if (tok_is(tok, len, "binary_little_endian")) h->format = PLY_LE;
            else if (tok_is(tok, len, "binary_big_endian")) h->format = PLY_BE;
            else return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "unknown PLY format");
            len = ls_mio_token(&t, &tok);
            if (!tok_is(tok, len, "1.0")) return ls_mio_text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "PLY version other than 1.0");
            h->has_format = 1;
        } else if (tok_is(tok, len, "element")) {
            ply_elem *e;
            uint32_t q;
            if (h->nel >= PLY_MAX_ELEMENTS) return ls_mio_text_error(diag, &t, at, LS_ERR_UNSUPPORTED, "more than 16 PLY elements");
            e = &h->el[h->nel];
            len = ls_mio_token(&t, &tok);
            e->kind = tok_is(tok, len, "vertex") ? 1u : tok_is(tok, len, "face") ? 2u : 0u;
            for (q = 0; q < h->nel && e->kind != 0; q++) {
                if (h->el[q].kind == e->kind) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "PLY element declared twice");
            }
            len = ls_mio_token(&t, &tok);
            r = ls_mio_parse_uint(tok, len, UINT64_MAX, &e->count);
            if (r == 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "invalid PLY element count");
            if (r < 0) return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "PLY element count larger than the file");
            e->first = (uint16_t)h->npr;
            e->nprops = 0;
            h->nel++;
        } else if (tok_is(tok, len, "property")) {
            st = ply_property(&t, h, at, diag);
            if (st != LS_OK) return st;
        } else {
            return ls_mio_text_error(diag, &t, at, LS_ERR_PARSE, "unknown PLY header line");
        }
        ls_mio_next_line(&t);
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
    if (in->format == PLY_ASCII) return ls_mio_text_error(diag, &in->t, in->t.pos, LS_ERR_PARSE, "PLY data ends early (fewer values than the header declares)");
    return ls_mio_offset_error(diag, in->t.pos, LS_ERR_PARSE, "truncated binary body");
}

/* Skips ascii white space and line ends (binary: nothing). */
static void ply_skip_ws(ply_in *in)
{
    if (in->format != PLY_ASCII) return;
    for (;;) {
        ls_mio_skip_spaces(&in->t);
        if (in->t.pos >= in->t.n || !ls_mio_is_eol(in->t.s[in->t.pos])) return;
        ls_mio_next_line(&in->t);
    }
}

/* The next ascii token across line ends. */
static size_t ply_token(ply_in *in, const char **tok, size_t *at)
{
    for (;;) {
        size_t len;
        ls_mio_skip_spaces(&in->t);
        *at = in->t.pos;
        len = ls_mio_token(&in->t, tok);
        if (len > 0 || in->t.pos >= in->t.n) return len;
        ls_mio_next_line(&in->t);
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
        r = ls_mio_parse_int(tok, len, U32_LIMIT, out);
        if (r == 0) return ls_mio_text_error(diag, &in->t, at, LS_ERR_PARSE, "invalid integer in PLY data");
        if (r < 0 || (type % 2u == 0 && *out < 0) || (ply_size[type] == 1 && (*out > 255 || *out < -128)) ||
            (ply_size[type] == 2 && (*out > 65535 || *out < -32768)))
            return ls_mio_text_error(diag, &in->t, at, LS_ERR_PARSE, "PLY integer out of range for its type");
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
        if (st == LS_ERR_TOO_LARGE) return ls_mio_text_error(diag, &in->t, at, LS_ERR_TOO_LARGE, "number too large for ls_real");
        if (st != LS_OK) return ls_mio_text_error(diag, &in->t, at, LS_ERR_PARSE, "invalid number");
        if (!ls_mio_coord_finite(*out)) return ls_mio_text_error(diag, &in->t, at, LS_ERR_NONFINITE, COORD_NONFINITE);
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
        if (!ls_mio_coord_finite(*out)) {
            /* a finite double beyond float's range (float build) is too large, as in text */
            if (type == 8 && ((raw >> 52) & 0x7ffu) != 0x7ffu)
                return ls_mio_offset_error(diag, at, LS_ERR_TOO_LARGE, "number too large for ls_real");
            return ls_mio_offset_error(diag, at, LS_ERR_NONFINITE, COORD_NONFINITE);
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
        if (ls_scan_number(tok, len) != len) return ls_mio_text_error(diag, &in->t, at, LS_ERR_PARSE, "invalid number");
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
    if (cnt < 0) return ls_mio_offset_error(diag, at, LS_ERR_PARSE, "negative PLY list count");
    if (p->role == ROLE_INDICES && cnt < 3) {
        if (in->format == PLY_ASCII) return ls_mio_text_error(diag, &in->t, at, LS_ERR_PARSE, "face with fewer than 3 vertices");
        return ls_mio_offset_error(diag, at, LS_ERR_PARSE, "face with fewer than 3 vertices");
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
                if (in->format == PLY_ASCII) return ls_mio_text_error(diag, &in->t, at, LS_ERR_PARSE, "face index out of range");
                return ls_mio_offset_error(diag, at, LS_ERR_PARSE, "face index out of range");
            }
            if (j == 0) first = (uint32_t)idx;
            if (j >= 2 && !ls_mio_add_tri(k, first, prev, (uint32_t)idx)) return ls_mio_offset_error(diag, at, LS_ERR_TOO_LARGE, "more than 2^32 - 1 triangles");
            prev = (uint32_t)idx;
        }
    }
    if (p->role == ROLE_INDICES) k->np++;
    return LS_OK;
}

ls_status ls_mio_read_ply(const char *s, size_t n, sink *k, ls_diag *diag)
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
    if (roles != 0xeu) return ls_mio_offset_error(diag, body, LS_ERR_PARSE, "PLY vertex element without x, y and z (or no vertex element)");
    for (e = 0; e < h.nel; e++) {
        if (h.el[e].kind == 2 && !has_indices) return ls_mio_offset_error(diag, body, LS_ERR_PARSE, "PLY face element without vertex_indices");
    }
    /* header counts against the bytes that are there (2 bytes per ascii value at least) */
    for (e = 0; e < h.nel; e++) {
        const ply_elem *el = &h.el[e];
        uint64_t min_bytes = 0;
        for (q = el->first; q < (uint32_t)el->first + el->nprops; q++)
            min_bytes += h.format == PLY_ASCII ? 2u : ply_size[h.pr[q].count_type != 0 ? h.pr[q].count_type : h.pr[q].type];
        if (min_bytes > 0 && el->count > (uint64_t)(n - body + 1u) / min_bytes)
            return ls_mio_offset_error(diag, body, LS_ERR_PARSE, "PLY element count larger than the file");
    }
    if (nv > U32_LIMIT) return ls_mio_offset_error(diag, body, LS_ERR_TOO_LARGE, "more than 2^32 - 1 vertices");
    ls_mio_text_init(&in.t, s, n, body, 0);
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

/* 1 when the PLY header says binary (for the info field). */
uint32_t ls_mio_ply_is_binary(const void *data, size_t bytes)
{
    ply_header h;
    size_t body = 0;
    if (ply_header_read((const char *)data, bytes, &h, &body, NULL) != LS_OK) return 0;
    return h.format != PLY_ASCII ? 1u : 0u;
}
