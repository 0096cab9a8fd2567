/* check.h — the test harness: counting assertions, no framework.
 * Each test program ends with CHECK_DONE(), which prints "name: N passed, N failed, N skipped"
 * and exits non-zero on failure; tests/run_tests.sh adds the counts up. */
#ifndef Q2N_TEST_CHECK_H
#define Q2N_TEST_CHECK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#if defined(__GNUC__)
#define CHK_UNUSED __attribute__((unused))
#else
#define CHK_UNUSED
#endif
static int chk_passed CHK_UNUSED, chk_failed CHK_UNUSED, chk_skipped CHK_UNUSED;

#define CHECK(cond, ...)                                                            \
    do {                                                                            \
        if (cond) chk_passed++;                                                     \
        else {                                                                      \
            chk_failed++;                                                           \
            fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);                    \
            fprintf(stderr, __VA_ARGS__);                                           \
            fputc('\n', stderr);                                                    \
        }                                                                           \
    } while (0)

/* |a-b| <= tol, with the values printed on failure. */
#define CHECK_NEAR(a, b, tol, what)                                                 \
    do {                                                                            \
        double chk_a_ = (a), chk_b_ = (b), chk_t_ = (tol);                          \
        CHECK(fabs(chk_a_ - chk_b_) <= chk_t_ && chk_a_ == chk_a_ && chk_b_ == chk_b_, \
              "%s: %.17g vs %.17g (|diff| %.3g > tol %.3g)", what, chk_a_, chk_b_,  \
              fabs(chk_a_ - chk_b_), chk_t_);                                       \
    } while (0)

#define SKIP(...)                                                                   \
    do {                                                                            \
        chk_skipped++;                                                              \
        printf("SKIP ");                                                            \
        printf(__VA_ARGS__);                                                        \
        putchar('\n');                                                              \
    } while (0)

#define CHECK_DONE(name)                                                            \
    do {                                                                            \
        printf("%s: %d passed, %d failed, %d skipped\n", name, chk_passed,          \
               chk_failed, chk_skipped);                                            \
        return chk_failed ? 1 : 0;                                                  \
    } while (0)

/* Path of a mesh in ../shared/meshes (or $Q2N_SHARED_MESHES), or NULL when it is absent:
 * tests then SKIP and say so. */
static inline const char *chk_shared_mesh(const char *file)
{
    static char buf[4][1024];
    static int slot;
    const char *dir = getenv("Q2N_SHARED_MESHES");
    char *p = buf[slot++ & 3];
    snprintf(p, sizeof buf[0], "%s/%s", dir ? dir : "../shared/meshes", file);
    return access(p, R_OK) == 0 ? p : NULL;
}

#endif
