/* error.c — see error.h. */
#include "core/error.h"

#include <stdarg.h>
#include <stdio.h>

/* Length of the valid UTF-8 sequence at s (RFC 3629: no overlong forms, no surrogates, at most
 * U+10FFFF) that is not a C1 control (U+0080..U+009F, which terminals obey like ESC), else 0. */
static size_t utf8_printable_len(const unsigned char *s)
{
    unsigned c = s[0];
    size_t n;
    unsigned lo = 0x80, hi = 0xBF;
    if (c >= 0xC2 && c <= 0xDF) n = 2;
    else if (c >= 0xE0 && c <= 0xEF) n = 3;
    else if (c >= 0xF0 && c <= 0xF4) n = 4;
    else return 0;
    if (c == 0xE0) lo = 0xA0;
    else if (c == 0xED) hi = 0x9F;
    else if (c == 0xF0) lo = 0x90;
    else if (c == 0xF4) hi = 0x8F;
    if (s[1] < lo || s[1] > hi) return 0;
    for (size_t i = 2; i < n; i++)
        if (s[i] < 0x80 || s[i] > 0xBF) return 0;
    if (c == 0xC2 && s[1] <= 0x9F) return 0; /* C1 control */
    return n;
}

size_t q2n_escape(char *dst, size_t cap, const char *src)
{
    static const char hex[] = "0123456789abcdef";
    const unsigned char *s = (const unsigned char *)src;
    size_t k = 0;
    if (!cap) return 0;
    while (*s) {
        size_t n = *s >= 0x20 && *s < 0x7f ? 1 : *s >= 0x80 ? utf8_printable_len(s) : 0;
        if (n) {
            if (k + n >= cap) break;
            for (size_t i = 0; i < n; i++) dst[k++] = (char)s[i];
            s += n;
        } else {
            if (k + 4 >= cap) break;
            dst[k++] = '\\';
            dst[k++] = 'x';
            dst[k++] = hex[*s >> 4];
            dst[k++] = hex[*s & 15];
            s++;
        }
    }
    dst[k] = '\0';
    return k;
}

q2n_status q2n_error_set(q2n_error *err, q2n_status code, const char *fmt, ...)
{
    if (err) {
        char raw[sizeof err->message];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(raw, sizeof raw, fmt, ap);
        va_end(ap);
        err->code = code;
        q2n_escape(err->message, sizeof err->message, raw);
    }
    return code;
}

const char *q2n_status_string(q2n_status code)
{
    static const char *names[] = {"ok", "i/o error", "parse error", "topology error",
                                  "geometry error", "unsupported input", "out of memory",
                                  "invalid argument", "numeric failure"};
    if ((unsigned)code < sizeof names / sizeof names[0]) return names[code];
    return "unknown error";
}
