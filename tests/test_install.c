/* test_install.c — `make install` into a temporary DESTDIR (and PREFIX), then the example program
 * built against the installed header and library with `pkg-config --cflags --libs --static
 * quad2nurbs` (PKG_CONFIG_SYSROOT_DIR = DESTDIR, as for any staged install) and run: it must print
 * the same lines and write the same STEP bytes as the example built in the tree by make check.
 * Also: every installed file is there, the pkg-config Version and the installed command's
 * --version are the header's QUAD2NURBS_VERSION. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <libgen.h>
#include <limits.h>
#include <stdlib.h>

#include "check.h"
#include "quad2nurbs.h"

#define PREFIX "/opt/q2n"
/* A sanitizer build (make CONFIG=asan) installs an instrumented library: the example must link the
 * sanitizer runtimes too, which pkg-config cannot know about. */
#if defined(__SANITIZE_ADDRESS__)
#define EXAMPLE_SAN " -fsanitize=address,undefined"
#else
#define EXAMPLE_SAN ""
#endif
#define EXAMPLE "torus_from_arrays"

static long slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = 0;
    fclose(f);
    return (long)n;
}

/* Run a shell command; its exit status (-1 if it could not run). */
static int sh(const char *cmd)
{
    int rc = system(cmd);
    if (rc == -1 || !WIFEXITED(rc)) return -1;
    return WEXITSTATUS(rc);
}

int main(void)
{
    static char cmd[16384], build[4096], dest[4096], a[1 << 16], b[1 << 16];
    static char sa[1 << 20], sb[1 << 20];
    char exe[4096];
    snprintf(exe, sizeof exe, "%s", chk_exe());
    snprintf(build, sizeof build, "%s", dirname(exe)); /* the build folder of the executable under test */
    if (!realpath(chk_scratch_dir(), dest)) { CHECK(0, "scratch folder"); CHECK_DONE("test_install"); }
    strcat(dest, "/dest");
    if (sh("command -v pkg-config >/dev/null") != 0) {
        if (chk_env_flag("Q2N_REQUIRE_SHARED")) CHECK(0, "pkg-config is not installed (tools/install-deps.sh)");
        else SKIP("pkg-config is not installed (apt-get install pkgconf)");
        CHECK_DONE("test_install");
    }

    /* the install: a make of its own (not the caller's jobserver) */
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make -s --no-print-directory "
             "install BUILD='%s' DESTDIR='%s' PREFIX=" PREFIX " >'%s' 2>&1", dest, build, dest, chk_scratch("install.log"));
    CHECK(sh(cmd) == 0, "make install (log: %s)", chk_scratch("install.log"));
    static const char *const FILES[] = {"/bin/quad2nurbs", "/lib/libquad2nurbs.a", "/include/quad2nurbs.h",
                                        "/lib/pkgconfig/quad2nurbs.pc", NULL};
    for (int i = 0; FILES[i]; i++) {
        char p[4200];
        snprintf(p, sizeof p, "%s" PREFIX "%s", dest, FILES[i]);
        CHECK(access(p, R_OK) == 0, "installed %s", FILES[i]);
    }
    char pc[4200];
    snprintf(pc, sizeof pc, "%s" PREFIX "/lib/pkgconfig/quad2nurbs.pc", dest);
    CHECK(slurp(pc, a, sizeof a) > 0 && strstr(a, "\nVersion: " QUAD2NURBS_VERSION "\n") && strstr(a, "prefix=" PREFIX "\n") &&
          strstr(a, "Libs.private: -lceres"), "pkg-config file: %.400s", a);

    /* the installed command */
    snprintf(cmd, sizeof cmd, "'%s" PREFIX "/bin/quad2nurbs' --version >'%s'", dest, chk_scratch("version.txt"));
    CHECK(sh(cmd) == 0 && slurp(chk_scratch("version.txt"), a, sizeof a) > 0 && !strcmp(a, "quad2nurbs " QUAD2NURBS_VERSION "\n"),
          "installed quad2nurbs --version: %s", a);

    /* the example against the installed copy, through pkg-config */
    const char *flags = chk_scratch("pkg-config.txt");
    snprintf(cmd, sizeof cmd, "PKG_CONFIG_SYSROOT_DIR='%s' PKG_CONFIG_PATH='%s" PREFIX "/lib/pkgconfig' "
             "pkg-config --cflags --libs --static quad2nurbs >'%s'", dest, dest, flags);
    CHECK(sh(cmd) == 0 && slurp(flags, a, sizeof a) > 0, "pkg-config --cflags --libs --static quad2nurbs");
    char inc[4300];
    snprintf(inc, sizeof inc, "-I%s" PREFIX "/include", dest);
    CHECK(strstr(a, inc) && strstr(a, "-lquad2nurbs") && strstr(a, "-lceres"), "flags: %s", a);
    const char *prog = chk_scratch(EXAMPLE);
    snprintf(cmd, sizeof cmd, "${CC:-cc} -std=c11 -Wall -Wextra -Werror" EXAMPLE_SAN " examples/" EXAMPLE ".c -o '%s' $(cat '%s') >'%s' 2>&1",
             prog, flags, chk_scratch("example_build.log"));
    CHECK(sh(cmd) == 0, "the example builds against the installed library (log: %s)", chk_scratch("example_build.log"));

    /* installed and in-tree examples: the same lines, the same STEP bytes */
    const char *step = chk_scratch("torus.step");
    snprintf(cmd, sizeof cmd, "SOURCE_DATE_EPOCH=1700000000 '%s' '%s' >'%s'", prog, step, chk_scratch("installed.txt"));
    CHECK(sh(cmd) == 0, "the installed example runs");
    long na = slurp(chk_scratch("installed.txt"), a, sizeof a), nsa = slurp(step, sa, sizeof sa);
    snprintf(cmd, sizeof cmd, "SOURCE_DATE_EPOCH=1700000000 '%s/examples/" EXAMPLE "' '%s' >'%s'", build, step,
             chk_scratch("in_tree.txt"));
    CHECK(sh(cmd) == 0, "the in-tree example runs (%s/examples/" EXAMPLE ", built by make check)", build);
    long nb = slurp(chk_scratch("in_tree.txt"), b, sizeof b), nsb = slurp(step, sb, sizeof sb);
    CHECK(na > 0 && na == nb && !strcmp(a, b), "installed and in-tree examples print the same:\n%s---\n%s", a, b);
    CHECK(nsa > 1000 && nsa == nsb && !memcmp(sa, sb, (size_t)nsa) && !strncmp(sa, "ISO-10303-21;", 13),
          "the same STEP (%ld, %ld bytes)", nsa, nsb);
    CHECK(strstr(a, "patch 0: degrees 5 x 5") && strstr(a, "max deviation") && strstr(a, ": met"), "example output:\n%s", a);
    CHECK_DONE("test_install");
}
