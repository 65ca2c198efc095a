/* json_internal.h - a strict JSON reader (RFC 8259) for the dataset formats
 * (scene_transforms.c): a pull parser over a text in memory that hands out
 * one event at a time, checks the whole grammar (also in the values it is
 * asked to skip), needs no memory beyond its struct and no recursion (the
 * open containers are a fixed stack of LS_JSON_DEPTH levels). Private to
 * src/io. */
#ifndef LS_JSON_INTERNAL_H
#define LS_JSON_INTERNAL_H

#include <largesteps/core.h>

#define LS_JSON_DEPTH 64u /* open objects and arrays at most */

#define LS_JSON_END 0        /* the text is done (after one value) */
#define LS_JSON_OBJECT 1     /* { */
#define LS_JSON_OBJECT_END 2 /* } */
#define LS_JSON_ARRAY 3      /* [ */
#define LS_JSON_ARRAY_END 4  /* ] */
#define LS_JSON_KEY 5        /* a member's name: at, len span its raw text between the quotes */
#define LS_JSON_STRING 6     /* a string value: the same */
#define LS_JSON_NUMBER 7     /* a number: at, len span it */
#define LS_JSON_TRUE 8
#define LS_JSON_FALSE 9
#define LS_JSON_NULL 10
#define LS_JSON_ERROR (-1) /* at: where; what: the problem */

typedef struct ls_json {
    const char *text;
    size_t length, pos;
    uint32_t depth;
    int state;
    const char *error; /* the first error's message */
    unsigned char open[LS_JSON_DEPTH]; /* 'o' or 'a' per open container */
} ls_json;

typedef struct ls_json_event {
    int type;         /* LS_JSON_* */
    const char *at;   /* the token (for strings: after the opening quote) */
    size_t len;       /* its length (strings: the raw text, escapes not decoded) */
    const char *what; /* LS_JSON_ERROR: what was wrong */
} ls_json_event;

/* Starts reading text[0..length). */
void ls_json_init(ls_json *j, const char *text, size_t length);

/* The next event; LS_JSON_ERROR stays the answer once given. */
int ls_json_next(ls_json *j, ls_json_event *ev);

/* Skips the value whose first event is ev (a container's whole content);
 * LS_JSON_ERROR (ev filled) on malformed text, else 0. */
int ls_json_skip(ls_json *j, ls_json_event *ev);

/* Decodes a string's raw text (escapes, \u with surrogate pairs to UTF-8)
 * into out, which may be raw itself (the decoded text is never longer) or
 * NULL (only checked); *out_len gets the length. 0 when a \u escape is an unpaired surrogate or
 * the result holds a NUL byte (neither can name a file), else 1. */
int ls_json_decode(const char *raw, size_t len, char *out, size_t *out_len);

/* 1 when the raw string equals the NUL-terminated ASCII word. */
int ls_json_is(const ls_json_event *ev, const char *word);

#endif /* LS_JSON_INTERNAL_H */
