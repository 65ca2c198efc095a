/* status.c - messages for ls_status codes, and ls_diag reset. */
#include <largesteps/status.h>

typedef struct status_text {
    const char *name;
    /* cppcheck-suppress unusedStructMember ; read by ls_status_str unless LS_NO_STATUS_STRINGS */
    const char *message;
} status_text;

#ifdef LS_NO_STATUS_STRINGS
#define LS_MSG_(text) ""
#else
#define LS_MSG_(text) text
#endif

/* Indexed by code; the order must match the LS_* values in status.h. */
static const status_text status_texts[LS_STATUS_COUNT] = {
    {"LS_OK", LS_MSG_("success")},
    {"LS_ERR_INVALID", LS_MSG_("invalid argument: a pointer is NULL or a value is outside its documented range")},
    {"LS_ERR_NOMEM", LS_MSG_("arena too small: give the call an arena of at least the bytes its sizing query returns")},
    {"LS_ERR_TOO_LARGE", LS_MSG_("too large: the sizes involved overflow size_t or exceed a format limit or a capacity; use smaller inputs or raise the capacity")},
    {"LS_ERR_ALIGN", LS_MSG_("misaligned buffer: the arena buffer must be aligned to LS_ARENA_ALIGN (declare it with LS_ARENA_BUFFER)")},
    {"LS_ERR_PARSE", LS_MSG_("malformed input: the diagnostic gives the line, column or byte offset")},
    {"LS_ERR_NONFINITE", LS_MSG_("non-finite number: a NaN or infinity where a finite value is required")},
    {"LS_ERR_MESH", LS_MSG_("invalid mesh: empty, non-manifold or otherwise unusable; the diagnostic names the element")},
    {"LS_ERR_NOT_SPD", LS_MSG_("matrix not symmetric positive definite: check lambda >= 0 and the mesh for degenerate parts")},
    {"LS_ERR_CANCELLED", LS_MSG_("cancelled by the progress callback; outputs are unchanged")},
    {"LS_ERR_IO", LS_MSG_("input/output failure reported by a read or write callback")},
    {"LS_ERR_UNSUPPORTED", LS_MSG_("unsupported feature: the input is valid but uses something this build does not implement")},
    {"LS_ERR_FPENV", LS_MSG_("floating-point environment not supported: set round-to-nearest and disable flush-to-zero (FZ/DAZ)")},
    {"LS_ERR_ABI", LS_MSG_("ABI mismatch: the program was compiled for another ls_real than the library")},
    {"LS_ERR_STATE", LS_MSG_("object in the wrong state: initialise it first, or rebuild it after its inputs changed")},
};

static int status_known(ls_status status)
{
    return status >= 0 && status < LS_STATUS_COUNT;
}

const char *ls_status_name(ls_status status)
{
    return status_known(status) ? status_texts[status].name : "LS_ERR_UNKNOWN";
}

const char *ls_status_str(ls_status status)
{
#ifdef LS_NO_STATUS_STRINGS
    return ls_status_name(status);
#else
    return status_known(status) ? status_texts[status].message
                                : "unknown status code: the library and its headers may be of different versions";
#endif
}

void ls_diag_clear(ls_diag *diag)
{
    if (diag == NULL) return;
    diag->status = LS_OK;
    diag->has_line = 0;
    diag->line = 0;
    diag->column = 0;
    diag->has_offset = 0;
    diag->offset = 0;
    diag->has_index = 0;
    diag->index = 0;
    diag->has_value = 0;
    diag->value = 0;
    diag->what = "";
}

ls_status ls_diag_set(ls_diag *diag, ls_status status, const char *what, uint64_t index)
{
    if (diag == NULL) return status;
    ls_diag_clear(diag);
    diag->status = status;
    diag->what = what;
    if (index != LS_DIAG_NO_INDEX) {
        diag->has_index = 1;
        diag->index = index;
    }
    return status;
}
