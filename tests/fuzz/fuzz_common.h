/* fuzz_common.h — invariants shared by the fuzz harnesses (tests/fuzz/fuzz_*.c).
 *
 * A harness feeds one input through the library and checks what must hold for every input:
 *   - a failure is a clean status: a known q2n_status, err.code equal to it, a one-line message
 *     naming the input ("fuzz.obj..."), no output object;
 *   - a success never carries a non-finite number: evaluations, samples, fitted control points
 *     and exported text are finite.
 * A violated invariant calls fz_fail: under libFuzzer it aborts (a crash with the input saved);
 * in tests/test_fuzz_corpus.c (the seeds replayed by `make check`) it counts a failure. */
#ifndef Q2N_TEST_FUZZ_COMMON_H
#define Q2N_TEST_FUZZ_COMMON_H

#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/error.h"

#define FZ_NAME "fuzz.obj"

#ifdef Q2N_LIBFUZZER
static void fz_fail(const char *file, int line, const char *what, const char *detail)
{
    fprintf(stderr, "fuzz invariant violated at %s:%d: %s (%s)\n", file, line, what, detail ? detail : "");
    abort();
}
#else
void fz_fail(const char *file, int line, const char *what, const char *detail); /* the test defines it */
#endif

/* Check cond; on violation report and leave the harness (returning 0 to the fuzzer). */
#define FZ_REQUIRE(cond, detail)                                                  \
    do {                                                                          \
        if (!(cond)) { fz_fail(__FILE__, __LINE__, #cond, (detail)); return 0; }  \
    } while (0)

/* A clean failure: known status, recorded in err, one line naming the input. */
static int fz_clean_error(q2n_status st, const q2n_error *err)
{
    return st > Q2N_OK && st <= Q2N_ERR_NUMERIC && err->code == st && err->message[0] &&
           !strchr(err->message, '\n') && strncmp(err->message, FZ_NAME, strlen(FZ_NAME)) == 0;
}

/* The same without the name prefix (messages about a model's later stages, e.g. "fit: ...",
 * may name the face only). */
static int fz_clean_status(q2n_status st, const q2n_error *err)
{
    return st > Q2N_OK && st <= Q2N_ERR_NUMERIC && err->code == st && err->message[0] &&
           !strchr(err->message, '\n');
}

static int fz_all_finite(const double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* 1 when text has no printed non-finite number: a "nan" or "inf" (any case) that is a word of
 * its own ("-nan", "inf", "1 nan 2"), not part of a longer word ("information"). */
static int fz_text_finite(const char *text, size_t len)
{
    for (size_t i = 0; i + 3 <= len; i++) {
        char a = (char)tolower((unsigned char)text[i]), b = (char)tolower((unsigned char)text[i + 1]);
        char c = (char)tolower((unsigned char)text[i + 2]);
        int word = (a == 'n' && b == 'a' && c == 'n') || (a == 'i' && b == 'n' && c == 'f');
        if (!word) continue;
        int before = i > 0 && isalpha((unsigned char)text[i - 1]);
        int after = i + 3 < len && isalpha((unsigned char)text[i + 3]) &&
                    !(a == 'i' && strncasecmp(text + i, "infinity", 8) == 0);
        if (!before && !after) return 0;
    }
    return 1;
}

#endif
