/* test_export_format.c — the writers' number formatting without printf (export_internal.h):
 * q2n_export_fmt_int against printf("%*d") itself, and q2n_export_fmt_real against its
 * definition (printf's %.17g, then always a '.', exponent 'E') and an exact round trip. */
#include "check.h"
#include "iges/export_internal.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned rng = 12345u;
static unsigned next(void) { rng = rng * 1103515245u + 12345u; return rng; }

static void test_int(void)
{
    const int fixed[] = {0, 1, -1, 9, -9, 10, -10, 99, 100, 1234567, 9999999, 10000000, -1234567, 99999999,
                         INT_MAX, INT_MIN, INT_MAX - 1, INT_MIN + 1};
    const int widths[] = {0, 1, 2, 7, 8, 12};
    int bad = 0, n = 0;
    for (int w = 0; w < 6; w++)
        for (int i = 0; i < (int)(sizeof fixed / sizeof fixed[0]) + 2000; i++) {
            int x = i < (int)(sizeof fixed / sizeof fixed[0]) ? fixed[i] : (int)next() >> (next() % 31);
            char a[40], b[40];
            int la = q2n_export_fmt_int(a, x, widths[w]);
            int lb = snprintf(b, sizeof b, "%*d", widths[w], x);
            bad += la != lb || memcmp(a, b, (size_t)lb) != 0;
            n++;
        }
    CHECK(bad == 0, "fmt_int = printf(\"%%*d\") on %d values and widths (%d differ)", n, bad);
}

static void test_real(void)
{
    struct { double x; const char *s; } ex[] = {
        {1.0, "1."}, {1e-05, "1.0000000000000001E-05"}, {0x1p-17, "7.62939453125E-06"}, {-0.25, "-0.25"}, {0.0, "0."}, {-0.0, "-0."},
        {1e300, "1.0000000000000001E+300"}, {0.5, "0.5"}, {100.0, "100."}, {2.5e-4, "0.00025000000000000001"}};
    for (size_t i = 0; i < sizeof ex / sizeof ex[0]; i++) {
        char out[Q2N_REAL_CHARS];
        q2n_export_fmt_real(out, ex[i].x);
        CHECK(strcmp(out, ex[i].s) == 0, "fmt_real(%.17g) = \"%s\" (expected \"%s\")", ex[i].x, out, ex[i].s);
    }
    int bad = 0, n = 0;
    for (int i = 0; i < 20000; i++) {
        double x;
        unsigned long long u = ((unsigned long long)next() << 32) ^ next();
        memcpy(&x, &u, sizeof x);
        if (!isfinite(x)) continue;
        if (i % 3 == 0) x = (double)(int)(next() % 2001) - 1000.0;   /* integers: the '.' is added */
        char out[Q2N_REAL_CHARS], ref[64];
        q2n_export_fmt_real(out, x);
        /* the definition: %.17g, a '.' in the mantissa, 'E' for 'e' */
        snprintf(ref, sizeof ref, "%.17g", x);
        char *e = strchr(ref, 'e'), want[80];
        size_t ml = e ? (size_t)(e - ref) : strlen(ref);
        snprintf(want, sizeof want, "%.*s%s%s%s", (int)ml, ref, memchr(ref, '.', ml) ? "" : ".", e ? "E" : "", e ? e + 1 : "");
        bad += strcmp(out, want) != 0 || strtod(out, NULL) != x || (x == 0 && signbit(strtod(out, NULL)) != signbit(x));
        n++;
    }
    CHECK(bad == 0, "fmt_real: the definition and an exact round trip on %d doubles (%d differ)", n, bad);
}

int main(void)
{
    test_int();
    test_real();
    CHECK_DONE("test_export_format");
}
