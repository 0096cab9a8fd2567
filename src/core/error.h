/* error.h — status codes and error messages for every quad2nurbs module.
 *
 * Library functions never print and never exit: they return a q2n_status and,
 * when given a non-NULL q2n_error, write one line saying where (file:line or
 * element index) and why.  Only src/cli/ prints and picks the exit code.  Messages are one line
 * of printable text: q2n_error_set escapes control bytes (q2n_escape). */
#ifndef Q2N_CORE_ERROR_H
#define Q2N_CORE_ERROR_H

#include <stddef.h>

#include "quad2nurbs.h"

/* q2n_status (Q2N_OK, Q2N_ERR_*) is the public one of include/quad2nurbs.h. */

typedef struct q2n_error {
    q2n_status code;
    char message[512];
} q2n_error;

/* Record an error (printf-style); returns code so callers can `return q2n_error_set(...)`.
 * err may be NULL. */
q2n_status q2n_error_set(q2n_error *err, q2n_status code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;


/* q2n_escape (include/quad2nurbs.h) makes every message one line of printable text: an ESC or
 * OSC sequence quoted from input (a file name, a token) must not reach the terminal. */

#endif
