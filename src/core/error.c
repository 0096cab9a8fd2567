/* error.c — see error.h. */
#include "core/error.h"

#include <stdarg.h>
#include <stdio.h>

q2n_status q2n_error_set(q2n_error *err, q2n_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        err->code = code;
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return code;
}

const char *q2n_status_name(q2n_status code)
{
    static const char *names[] = {"ok", "i/o error", "parse error", "topology error",
                                  "geometry error", "unsupported input", "out of memory",
                                  "invalid argument", "numeric failure"};
    if ((unsigned)code < sizeof names / sizeof names[0]) return names[code];
    return "unknown error";
}
