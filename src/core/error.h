/* error.h — status codes and error messages for every quad2nurbs module.
 *
 * Library functions never print and never exit: they return a q2n_status and,
 * when given a non-NULL q2n_error, write one line saying where (file:line or
 * element index) and why.  Only src/cli/ prints and picks the exit code.  Messages are one line
 * of printable text: q2n_error_set escapes control bytes (q2n_escape). */
#ifndef Q2N_CORE_ERROR_H
#define Q2N_CORE_ERROR_H

#include <stddef.h>

typedef enum q2n_status {
    Q2N_OK = 0,
    Q2N_ERR_IO,          /* file cannot be opened, read or written */
    Q2N_ERR_PARSE,       /* malformed input text, bad number, NaN/Inf */
    Q2N_ERR_TOPOLOGY,    /* non-manifold, inconsistent orientation, index out of range */
    Q2N_ERR_GEOMETRY,    /* degenerate face or edge */
    Q2N_ERR_UNSUPPORTED, /* valid input this construction does not handle (e.g. non-quads) */
    Q2N_ERR_NOMEM,
    Q2N_ERR_ARG,         /* invalid option or argument */
    Q2N_ERR_NUMERIC      /* valid input, but an evaluation gave a non-finite number (NaN/Inf) */
} q2n_status;

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

const char *q2n_status_name(q2n_status code);

/* Copy src into dst (cap bytes, NUL-terminated, truncated at a whole character) with every byte
 * that could act on a terminal written as \xHH: C0 controls, DEL, bytes that are not valid UTF-8
 * and the UTF-8 form of C1 controls.  Messages quote input bytes (a file name, a token), and an
 * ESC or OSC sequence in them must not reach the terminal.  q2n_error_set applies it to every
 * message.  Returns the length written. */
size_t q2n_escape(char *dst, size_t cap, const char *src);

#endif
