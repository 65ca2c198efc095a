/* json.c - a strict JSON pull parser (json_internal.h): RFC 8259's grammar,
 * no recursion, no memory. O(length) over a whole text. */
#include "json_internal.h"

/* What may come next. */
#define ST_VALUE 0       /* a value (the top, after ':' or ',' in an array) */
#define ST_FIRST_ITEM 1  /* after '[': a value or ']' */
#define ST_FIRST_KEY 2   /* after '{': a key or '}' */
#define ST_KEY 3         /* after ',' in an object: a key */
#define ST_COLON 4       /* after a key */
#define ST_AFTER_VALUE 5 /* ',' or the container's end */
#define ST_DONE 6        /* only white space */
#define ST_FAILED 7

void ls_json_init(ls_json *j, const char *text, size_t length)
{
    j->text = text;
    j->length = text == NULL ? 0 : length;
    j->pos = 0;
    j->depth = 0;
    j->state = ST_VALUE;
    j->error = NULL;
}

static int fail(ls_json *j, ls_json_event *ev, size_t at, const char *what)
{
    j->state = ST_FAILED;
    j->error = what;
    j->pos = at;
    ev->type = LS_JSON_ERROR;
    ev->at = j->text + at;
    ev->len = 0;
    ev->what = what;
    return LS_JSON_ERROR;
}

static int emit(ls_json_event *ev, int type, const char *at, size_t len)
{
    ev->type = type;
    ev->at = at;
    ev->len = len;
    ev->what = NULL;
    return type;
}

static int hex_value(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/* Bytes of the UTF-8 sequence starting at s[0..n) (1..4), 0 if malformed
 * (a stray continuation byte, an overlong form, a surrogate, beyond U+10FFFF). */
static size_t utf8_length(const unsigned char *s, size_t n)
{
    uint32_t cp, min;
    size_t k, len;
    if (s[0] < 0x80u) return 1;
    if (s[0] >= 0xC2u && s[0] <= 0xDFu) {
        len = 2;
        cp = s[0] & 0x1Fu;
        min = 0x80u;
    } else if (s[0] >= 0xE0u && s[0] <= 0xEFu) {
        len = 3;
        cp = s[0] & 0x0Fu;
        min = 0x800u;
    } else if (s[0] >= 0xF0u && s[0] <= 0xF4u) {
        len = 4;
        cp = s[0] & 0x07u;
        min = 0x10000u;
    } else {
        return 0;
    }
    if (len > n) return 0;
    for (k = 1; k < len; k++) {
        if ((s[k] & 0xC0u) != 0x80u) return 0;
        cp = (cp << 6) | (s[k] & 0x3Fu);
    }
    if (cp < min || cp > 0x10FFFFu || (cp >= 0xD800u && cp <= 0xDFFFu)) return 0;
    return len;
}

/* A string from j->pos (after its opening quote): the event spans the raw
 * text; j->pos ends after the closing quote. */
static int string_token(ls_json *j, ls_json_event *ev, int type)
{
    const char *t = j->text;
    size_t start = j->pos, i = start;
    while (i < j->length) {
        unsigned char c = (unsigned char)t[i];
        if (c == '"') {
            j->pos = i + 1;
            return emit(ev, type, t + start, i - start);
        }
        if (c < 0x20u) return fail(j, ev, i, "a control character inside a string (write it as an escape, such as \\n)");
        if (c == '\\') {
            char e;
            if (i + 1 >= j->length) break;
            e = t[i + 1];
            if (e == 'u') {
                int k;
                for (k = 0; k < 4; k++)
                    if (i + 2 + (size_t)k >= j->length || hex_value(t[i + 2 + (size_t)k]) < 0)
                        return fail(j, ev, i, "\\u must be followed by four hexadecimal digits");
                i += 6;
            } else if (e == '"' || e == '\\' || e == '/' || e == 'b' || e == 'f' || e == 'n' || e == 'r' || e == 't') {
                i += 2;
            } else {
                return fail(j, ev, i, "an unknown escape in a string (JSON has \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX)");
            }
        } else {
            size_t n = utf8_length((const unsigned char *)t + i, j->length - i);
            if (n == 0) return fail(j, ev, i, "a string that is not valid UTF-8");
            i += n;
        }
    }
    return fail(j, ev, start > 0 ? start - 1 : 0, "a string without its closing quote");
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)? from j->pos. */
static int number_token(ls_json *j, ls_json_event *ev)
{
    const char *t = j->text;
    size_t start = j->pos, i = start, n = j->length;
    if (i < n && t[i] == '-') i++;
    if (i < n && t[i] == '0') {
        i++;
    } else if (i < n && is_digit(t[i])) {
        while (i < n && is_digit(t[i])) i++;
    } else {
        return fail(j, ev, start, "a malformed number (JSON numbers are like -12, 0.5 or 3e-4)");
    }
    if (i < n && t[i] == '.') {
        i++;
        if (!(i < n && is_digit(t[i]))) return fail(j, ev, start, "a number with no digit after its decimal point");
        while (i < n && is_digit(t[i])) i++;
    }
    if (i < n && (t[i] == 'e' || t[i] == 'E')) {
        i++;
        if (i < n && (t[i] == '+' || t[i] == '-')) i++;
        if (!(i < n && is_digit(t[i]))) return fail(j, ev, start, "a number with no digit in its exponent");
        while (i < n && is_digit(t[i])) i++;
    }
    if (i < n && (is_digit(t[i]) || t[i] == '.' || t[i] == 'e' || t[i] == 'E' || t[i] == '+' || t[i] == '-'))
        return fail(j, ev, start, "a malformed number (no leading zeros, one sign, one decimal point)");
    j->pos = i;
    return emit(ev, LS_JSON_NUMBER, t + start, i - start);
}

static int literal(ls_json *j, ls_json_event *ev, const char *word, int type)
{
    size_t k = 0, start = j->pos;
    while (word[k] != '\0') {
        if (start + k >= j->length || j->text[start + k] != word[k])
            return fail(j, ev, start, "an unknown word (JSON values are objects, arrays, strings, numbers, true, false "
                                      "and null)");
        k++;
    }
    j->pos = start + k;
    return emit(ev, type, j->text + start, k);
}

static void after_value(ls_json *j) { j->state = j->depth == 0 ? ST_DONE : ST_AFTER_VALUE; }

static int open_container(ls_json *j, ls_json_event *ev, unsigned char kind)
{
    if (j->depth >= LS_JSON_DEPTH) return fail(j, ev, j->pos, "objects and arrays nested more than 64 deep");
    j->open[j->depth++] = kind;
    j->pos++;
    j->state = kind == 'o' ? ST_FIRST_KEY : ST_FIRST_ITEM;
    return emit(ev, kind == 'o' ? LS_JSON_OBJECT : LS_JSON_ARRAY, j->text + j->pos - 1, 1);
}

static int close_container(ls_json *j, ls_json_event *ev)
{
    int type = j->open[j->depth - 1] == 'o' ? LS_JSON_OBJECT_END : LS_JSON_ARRAY_END;
    j->depth--;
    j->pos++;
    after_value(j);
    return emit(ev, type, j->text + j->pos - 1, 1);
}

static int value(ls_json *j, ls_json_event *ev)
{
    char c = j->text[j->pos];
    if (c == '{') return open_container(j, ev, 'o');
    if (c == '[') return open_container(j, ev, 'a');
    if (c == '"') {
        j->pos++;
        if (string_token(j, ev, LS_JSON_STRING) == LS_JSON_ERROR) return LS_JSON_ERROR;
    } else if (c == '-' || is_digit(c)) {
        if (number_token(j, ev) == LS_JSON_ERROR) return LS_JSON_ERROR;
    } else if (c == 't') {
        if (literal(j, ev, "true", LS_JSON_TRUE) == LS_JSON_ERROR) return LS_JSON_ERROR;
    } else if (c == 'f') {
        if (literal(j, ev, "false", LS_JSON_FALSE) == LS_JSON_ERROR) return LS_JSON_ERROR;
    } else if (c == 'n') {
        if (literal(j, ev, "null", LS_JSON_NULL) == LS_JSON_ERROR) return LS_JSON_ERROR;
    } else {
        return fail(j, ev, j->pos, "a value was expected (an object, array, string, number, true, false or null)");
    }
    after_value(j);
    return ev->type;
}

int ls_json_next(ls_json *j, ls_json_event *ev)
{
    for (;;) {
        char c;
        while (j->pos < j->length && (j->text[j->pos] == ' ' || j->text[j->pos] == '\t' || j->text[j->pos] == '\n' ||
                                      j->text[j->pos] == '\r'))
            j->pos++;
        if (j->state == ST_FAILED) return fail(j, ev, j->pos, j->error);
        if (j->pos >= j->length) {
            if (j->state == ST_DONE) return emit(ev, LS_JSON_END, j->text + j->pos, 0);
            return fail(j, ev, j->pos, j->depth > 0 ? "the text ends inside an object or array" : "the text is empty");
        }
        c = j->text[j->pos];
        switch (j->state) {
        case ST_DONE:
            return fail(j, ev, j->pos, "more text after the JSON value");
        case ST_FIRST_KEY:
        case ST_KEY:
            if (c == '}' && j->state == ST_FIRST_KEY) return close_container(j, ev);
            if (c != '"') return fail(j, ev, j->pos, "a member name (a string in double quotes) was expected");
            j->pos++;
            if (string_token(j, ev, LS_JSON_KEY) == LS_JSON_ERROR) return LS_JSON_ERROR;
            j->state = ST_COLON;
            return LS_JSON_KEY;
        case ST_COLON:
            if (c != ':') return fail(j, ev, j->pos, "':' was expected after the member name");
            j->pos++;
            j->state = ST_VALUE;
            break;
        case ST_AFTER_VALUE:
            if (c == ',') {
                j->pos++;
                j->state = j->open[j->depth - 1] == 'o' ? ST_KEY : ST_VALUE;
                break;
            }
            if ((c == '}' && j->open[j->depth - 1] == 'o') || (c == ']' && j->open[j->depth - 1] == 'a'))
                return close_container(j, ev);
            return fail(j, ev, j->pos,
                        j->open[j->depth - 1] == 'o' ? "',' or '}' was expected" : "',' or ']' was expected");
        case ST_FIRST_ITEM:
            if (c == ']') return close_container(j, ev);
            j->state = ST_VALUE;
            return value(j, ev);
        default:
            return value(j, ev);
        }
    }
}

int ls_json_skip(ls_json *j, ls_json_event *ev)
{
    uint32_t depth;
    if (ev->type == LS_JSON_ERROR) return LS_JSON_ERROR;
    if (ev->type != LS_JSON_OBJECT && ev->type != LS_JSON_ARRAY) return 0;
    depth = j->depth; /* the container ev opened is open */
    while (j->depth >= depth) {
        if (ls_json_next(j, ev) == LS_JSON_ERROR) return LS_JSON_ERROR;
    }
    return 0;
}

/* The code point of the escape or character at raw[*i], *i moved past it;
 * 0xFFFFFFFF for an unpaired surrogate. */
static uint32_t next_code(const char *raw, size_t len, size_t *i)
{
    size_t k = *i;
    uint32_t cp;
    if (raw[k] != '\\') {
        const unsigned char *s = (const unsigned char *)raw + k;
        size_t n = utf8_length(s, len - k), m;
        if (n == 0) n = 1; /* not reached on a checked string */
        cp = n == 1 ? s[0] : (uint32_t)(s[0] & (0xFFu >> (n + 1u)));
        for (m = 1; m < n; m++) cp = (cp << 6) | (s[m] & 0x3Fu);
        *i = k + n;
        return cp;
    }
    switch (raw[k + 1]) {
    case 'b': cp = 8; break;
    case 'f': cp = 12; break;
    case 'n': cp = 10; break;
    case 'r': cp = 13; break;
    case 't': cp = 9; break;
    case 'u': {
        int d;
        cp = 0;
        for (d = 0; d < 4; d++) cp = (cp << 4) | (uint32_t)hex_value(raw[k + 2 + (size_t)d]);
        *i = k + 6;
        if (cp >= 0xDC00u && cp <= 0xDFFFu) return 0xFFFFFFFFu;
        if (cp >= 0xD800u && cp <= 0xDBFFu) {
            uint32_t lo = 0;
            if (*i + 6 > len || raw[*i] != '\\' || raw[*i + 1] != 'u') return 0xFFFFFFFFu;
            for (d = 0; d < 4; d++) lo = (lo << 4) | (uint32_t)hex_value(raw[*i + 2 + (size_t)d]);
            if (lo < 0xDC00u || lo > 0xDFFFu) return 0xFFFFFFFFu;
            *i += 6;
            cp = 0x10000u + ((cp - 0xD800u) << 10) + (lo - 0xDC00u);
        }
        return cp;
    }
    default: cp = (unsigned char)raw[k + 1]; break; /* " \ / */
    }
    *i = k + 2;
    return cp;
}

int ls_json_decode(const char *raw, size_t len, char *out, size_t *out_len)
{
    size_t i = 0, o = 0;
    while (i < len) {
        uint32_t cp = next_code(raw, len, &i);
        if (cp == 0xFFFFFFFFu || cp == 0) return 0;
        if (out == NULL) {
            o += cp < 0x80u ? 1u : cp < 0x800u ? 2u : cp < 0x10000u ? 3u : 4u;
        } else if (cp < 0x80u) {
            out[o++] = (char)cp;
        } else if (cp < 0x800u) {
            out[o++] = (char)(0xC0u | (cp >> 6));
            out[o++] = (char)(0x80u | (cp & 0x3Fu));
        } else if (cp < 0x10000u) {
            out[o++] = (char)(0xE0u | (cp >> 12));
            out[o++] = (char)(0x80u | ((cp >> 6) & 0x3Fu));
            out[o++] = (char)(0x80u | (cp & 0x3Fu));
        } else {
            out[o++] = (char)(0xF0u | (cp >> 18));
            out[o++] = (char)(0x80u | ((cp >> 12) & 0x3Fu));
            out[o++] = (char)(0x80u | ((cp >> 6) & 0x3Fu));
            out[o++] = (char)(0x80u | (cp & 0x3Fu));
        }
    }
    *out_len = o;
    return 1;
}

int ls_json_is(const ls_json_event *ev, const char *word)
{
    size_t i = 0, k = 0;
    while (i < ev->len) {
        uint32_t cp = next_code(ev->at, ev->len, &i);
        if (word[k] == '\0' || cp != (uint32_t)(unsigned char)word[k]) return 0;
        k++;
    }
    return word[k] == '\0';
}
