/* diag_internal.h - the library's one helper for an invalid argument or
 * configuration: LS_ERR_INVALID with diag naming it (diag may be NULL). */
#ifndef LS_DIAG_INTERNAL_H
#define LS_DIAG_INTERNAL_H

#include <largesteps/status.h>

/* what: static text naming the argument or field and what is allowed. */
static inline ls_status ls_invalid_arg(ls_diag *diag, const char *what)
{
    (void)ls_diag_set(diag, LS_ERR_INVALID, what, LS_DIAG_NO_INDEX);
    return LS_ERR_INVALID; /* spelled out: the analyzer does not see ls_diag_set return it */
}

#endif /* LS_DIAG_INTERNAL_H */
