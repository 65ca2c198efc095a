/* largesteps/status.h - status codes, their messages, and optional error details.
 *
 * Every call that can fail returns an ls_status; outputs go through pointers.
 * Calls that read caller input (files, meshes, images) also take an optional
 * `ls_diag *` (may be NULL) that receives where and why the input was rejected.
 * Every call that takes a diag clears it first, so after a success it holds
 * no stale message (status LS_OK, what = "").
 * There is no global "last error": the details travel with the call.
 */
#ifndef LARGESTEPS_STATUS_H
#define LARGESTEPS_STATUS_H

#include <largesteps/core.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The codes are stable: new ones are appended, none is renumbered. */
#define LS_OK              0  /* success */
#define LS_ERR_INVALID     1  /* an argument is out of its documented range (NULL, negative, ...) */
#define LS_ERR_NOMEM       2  /* the arena is too small: ask the sizing query for the bytes */
#define LS_ERR_TOO_LARGE   3  /* a size computation overflows size_t, a format's limit or a caller's capacity (ls_fit_capacity) */
#define LS_ERR_ALIGN       4  /* a buffer is not aligned to LS_ARENA_ALIGN */
#define LS_ERR_PARSE       5  /* malformed input text or bytes; ls_diag says where */
#define LS_ERR_NONFINITE   6  /* a NaN or infinity where a finite number is required */
#define LS_ERR_MESH        7  /* a mesh violates a requirement (empty, non-manifold, ...) */
#define LS_ERR_NOT_SPD     8  /* a matrix is not symmetric positive definite */
#define LS_ERR_CANCELLED   9  /* the progress callback asked to stop */
#define LS_ERR_IO         10  /* a caller read/write callback reported failure */
#define LS_ERR_UNSUPPORTED 11 /* valid input using a feature this build does not support */
#define LS_ERR_FPENV      12  /* the floating-point environment is not IEEE round-to-nearest without FTZ */
#define LS_ERR_ABI        13  /* the caller was compiled for another ls_real */
#define LS_ERR_STATE      14  /* an object is used before it is initialised or after it was invalidated */
#define LS_STATUS_COUNT   15

/* ls_status_str: a sentence a user can act on, for any code (unknown codes
 * included). Static storage; O(1). Built with -DLS_NO_STATUS_STRINGS (saves
 * the message text on small targets) it returns only the code's short name. */
const char *ls_status_str(ls_status status);

/* ls_status_name: the code's identifier, e.g. "LS_ERR_NOMEM". O(1). */
const char *ls_status_name(ls_status status);

/* Where and why an input was rejected. Fields that do not apply are 0 (the
 * `has_*` flags say which were set). `what` is a static string, never NULL
 * after a failing call that filled the diag. */
typedef struct ls_diag {
    ls_status status;    /* the code the call returned */
    uint32_t has_line;   /* 1 when line/column are set */
    uint32_t line;       /* 1-based line in a text input */
    uint32_t column;     /* 1-based column (bytes) in that line */
    uint32_t has_offset; /* 1 when offset is set */
    uint64_t offset;     /* 0-based byte offset in the input */
    uint32_t has_index;  /* 1 when index is set */
    uint64_t index;      /* element index: vertex, face, pixel, iteration, ... */
    uint32_t has_value;  /* 1 when value is set */
    ls_real value;       /* the offending number, e.g. a NaN coordinate or a pivot */
    const char *what;    /* short static description, e.g. "face index out of range" */
} ls_diag;

/* ls_diag_clear: resets every field to zero (what = ""). O(1). NULL is ignored. */
void ls_diag_clear(ls_diag *diag);

/* An index argument of ls_diag_set meaning "no element". */
#define LS_DIAG_NO_INDEX UINT64_MAX

/* ls_diag_set: clears *diag (NULL is ignored) and records `status`, the
 * static description `what` and, unless index is LS_DIAG_NO_INDEX, the
 * element index. Returns status, so that a failing call can end with
 * `return ls_diag_set(diag, LS_ERR_MESH, "face index out of range", f);`. O(1). */
ls_status ls_diag_set(ls_diag *diag, ls_status status, const char *what, uint64_t index);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_STATUS_H */
