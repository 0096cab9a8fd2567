/* check.h — the test harness: counting assertions, no framework.
 * Each test program ends with CHECK_DONE(), which prints "name: N passed, N failed, N skipped"
 * and exits non-zero on failure; tests/run_tests.sh runs the programs and adds the counts up.
 *
 * What a program needs from its surroundings comes from the environment, which the runner sets;
 * every value has a default, so a program also runs by hand from the repository root:
 *   Q2N_SHARED_MESHES   folder of the test meshes by others            default ../shared/meshes
 *   Q2N_REQUIRE_SHARED  1: a missing shared mesh is a failure (CI)     default: a skip, said
 *   Q2N_TEST_FULL       1: full mode (make check-full), long sweeps run default: quick mode
 *   Q2N_SCRATCH         the program's own scratch folder               default build/scratch/<program>
 *   Q2N_EXE             the quad2nurbs executable                      default build/quad2nurbs
 * Helpers: chk_shared_mesh(file), q2n_test_full(what), chk_scratch(name), chk_exe(), chk_slurp(path, &len),
 * chk_tmpdir(dir, cap, prefix), chk_count_files(dir, prefix). */
#ifndef Q2N_TEST_CHECK_H
#define Q2N_TEST_CHECK_H

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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

/* 1 when the environment variable is set to something other than "" or "0". */
static inline int chk_env_flag(const char *name)
{
    const char *e = getenv(name);
    return e && *e && strcmp(e, "0") != 0;
}

/* ------------------------------------------------------------------ shared meshes */

static inline const char *chk_shared_dir(void)
{
    const char *dir = getenv("Q2N_SHARED_MESHES");
    return dir && *dir ? dir : "../shared/meshes";
}

/* Path of a test mesh by others (Q2N_SHARED_MESHES, default ../shared/meshes), or NULL when it
 * is absent.  The absence is reported here, once per file: a SKIP naming the file and folder,
 * or under Q2N_REQUIRE_SHARED=1 (CI) a failure, so a run can never pass by skipping.  Callers
 * just move on:  const char *p = chk_shared_mesh("x.obj"); if (!p) continue;
 * The returned path stays valid for the next 7 calls. */
#define chk_shared_mesh(file) chk_shared_mesh_at((file), __FILE__, __LINE__)
static inline const char *chk_shared_mesh_at(const char *file, const char *src, int line)
{
    static char buf[8][1024];
    static unsigned slot;
    static char said[64][128];
    static int nsaid;
    const char *dir = chk_shared_dir();
    char *p = buf[slot++ & 7];
    snprintf(p, sizeof buf[0], "%s/%s", dir, file);
    if (access(p, R_OK) == 0) return p;
    for (int i = 0; i < nsaid; i++)
        if (!strcmp(said[i], file)) return NULL;
    if (nsaid < 64) snprintf(said[nsaid++], sizeof said[0], "%s", file);
    if (chk_env_flag("Q2N_REQUIRE_SHARED")) {
        chk_failed++;
        fprintf(stderr, "FAIL %s:%d: shared mesh %s not found in %s (Q2N_REQUIRE_SHARED=1)\n", src, line, file,
                dir);
    } else
        SKIP("%s not found in %s: its cases are not run", file, dir);
    return NULL;
}

/* ------------------------------------------------------------------ quick and full mode */

static int chk_deferred CHK_UNUSED;

/* 1 in full mode (make check-full, Q2N_TEST_FULL=1).  Guard a long sweep with
 *     if (q2n_test_full("rook --subdivide 1 G2 fit")) { ... }
 * In quick mode (make check) the sweep is left out and one line "DEFER <what>" says so; with
 * what == NULL nothing is printed (a program choosing a smaller budget, say). */
static inline int q2n_test_full(const char *what)
{
    int full = chk_env_flag("Q2N_TEST_FULL");
    if (!full && what) {
        chk_deferred++;
        printf("DEFER %s: run by make check-full\n", what);
    }
    return full;
}

/* ------------------------------------------------------------------ files */

/* mkdir -p; 0 on success. */
static inline int chk_mkdirs(const char *path)
{
    char p[1024];
    snprintf(p, sizeof p, "%s", path);
    for (char *s = p + 1;; s++) {
        if (*s != '/' && *s) continue;
        char c = *s;
        *s = 0;
        if (mkdir(p, 0777) != 0 && errno != EEXIST) return -1;
        if (!c) return 0;
        *s = c;
    }
}

/* This program's scratch folder (Q2N_SCRATCH; by hand: build/scratch/<program>), created on
 * first use.  Tests write every file there, never beside the binaries or in /tmp. */
static inline const char *chk_scratch_dir(void)
{
    static char dir[1024];
    if (!dir[0]) {
        const char *e = getenv("Q2N_SCRATCH");
        if (e && *e) snprintf(dir, sizeof dir, "%s", e);
        else {
            char exe[1024];
            ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
            exe[n > 0 ? n : 0] = 0;
            const char *base = strrchr(exe, '/');
            snprintf(dir, sizeof dir, "build/scratch/%s", base && base[1] ? base + 1 : "test");
        }
        if (chk_mkdirs(dir) != 0) fprintf(stderr, "cannot create scratch folder %s: %s\n", dir, strerror(errno));
    }
    return dir;
}

/* Path of `name` in the scratch folder; valid for the next 15 calls. */
static inline const char *chk_scratch(const char *name)
{
    static char buf[16][2048];
    static unsigned slot;
    char *p = buf[slot++ & 15];
    snprintf(p, sizeof buf[0], "%s/%s", chk_scratch_dir(), name);
    return p;
}

/* The whole of a file, NUL-terminated (caller frees), or NULL; *len (when len is not NULL) its size
 * once the file could be opened. */
static inline char *chk_slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = n >= 0 ? (char *)malloc((size_t)n + 1) : NULL;
    if (b && fread(b, 1, (size_t)n, f) != (size_t)n) { free(b); b = NULL; }
    if (b) b[n] = '\0';
    fclose(f);
    if (len) *len = n >= 0 ? (size_t)n : 0;
    return b;
}

/* A fresh folder "<scratch folder>/<prefix>_XXXXXX" into dir (cap bytes): 0, or -1 when the name
 * does not fit or it cannot be created. */
static inline int chk_tmpdir(char *dir, size_t cap, const char *prefix)
{
    int n = snprintf(dir, cap, "%s/%s_XXXXXX", chk_scratch_dir(), prefix);
    if (n < 0 || (size_t)n >= cap) return -1;
    return mkdtemp(dir) ? 0 : -1;
}

/* Files in dir whose names start with prefix (".q2n-": the atomic writer's temporaries). */
static inline int chk_count_files(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d))) n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    if (d) closedir(d);
    return n;
}

/* The quad2nurbs executable under test (Q2N_EXE; by hand: build/quad2nurbs). */
static inline const char *chk_exe(void)
{
    const char *e = getenv("Q2N_EXE");
    return e && *e ? e : "build/quad2nurbs";
}

#endif
