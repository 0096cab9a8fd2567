/* test_harness.c — the test infrastructure itself: tests/check.h's helpers and tests/run_tests.sh.
 *  - chk_shared_mesh: a present mesh's path; an absent one is a SKIP (said once per file), or a
 *    failure under Q2N_REQUIRE_SHARED=1; q2n_test_full follows Q2N_TEST_FULL and says DEFER;
 *    chk_scratch lies in Q2N_SCRATCH; chk_exe follows Q2N_EXE;
 *  - the runner on a fake build folder of small shell programs: passes, failures, a crash, a
 *    non-zero exit without a failed check, a time-out, quick and full mode, the environment and
 *    the scratch folder each program gets, the closing line and exit status;
 *  - the Makefile (make -n): the caller's CFLAGS/CPPFLAGS/LDFLAGS from the environment and the
 *    command line reach the compiler next to the project's flags; a changed header in tests/ rebuilds
 *    the test programs that include it;
 *  - a clone without the shared meshes (the first-contact defect: every case of
 *    test_export_pipeline skipped, then the audit ran on a batch file never written and failed):
 *    test_export_pipeline passes with skips when the meshes are absent, and fails under
 *    Q2N_REQUIRE_SHARED=1. */
#include <fcntl.h>
#include <sys/wait.h>

#include "check.h"

/* Run f with stdout and stderr sent to /dev/null (the helpers' SKIP/FAIL/DEFER lines would
 * otherwise read as this program's own). */
static void quietly(void (*f)(void *), void *arg)
{
    fflush(stdout);
    fflush(stderr);
    int o = dup(1), e = dup(2), n = open("/dev/null", O_WRONLY);
    dup2(n, 1);
    dup2(n, 2);
    f(arg);
    fflush(stdout);
    fflush(stderr);
    dup2(o, 1);
    dup2(e, 2);
    close(n); close(o); close(e);
}

static const char *looked_up;
static void look_up(void *file) { looked_up = chk_shared_mesh((const char *)file); }
static int full_answer;
static void ask_full(void *what) { full_answer = q2n_test_full((const char *)what); }

static void write_text(const char *path, const char *text, int exec)
{
    FILE *f = fopen(path, "w");
    if (!f) { CHECK(0, "cannot write %s", path); return; }
    fputs(text, f);
    fclose(f);
    if (exec) chmod(path, 0755);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *b = calloc(1, 1 << 20);
    size_t n = fread(b, 1, (1 << 20) - 1, f);
    b[n] = 0;
    fclose(f);
    return b;
}

static int run(const char *cmd)
{
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void test_helpers(void)
{
    int p0 = chk_passed, f0 = chk_failed, s0 = chk_skipped;
    char dir[1200];
    snprintf(dir, sizeof dir, "%s/meshes", chk_scratch_dir());
    chk_mkdirs(dir);
    write_text(chk_scratch("meshes/here.obj"), "v 0 0 0\n", 0);
    setenv("Q2N_SHARED_MESHES", dir, 1);
    unsetenv("Q2N_REQUIRE_SHARED");
    quietly(look_up, "here.obj");
    int ok_here = looked_up && !strcmp(looked_up, chk_scratch("meshes/here.obj"));
    int f1 = chk_failed, s1 = chk_skipped;
    quietly(look_up, "absent.obj");
    int absent_null = looked_up == NULL, s2 = chk_skipped, f2 = chk_failed;
    quietly(look_up, "absent.obj");
    int s3 = chk_skipped;
    setenv("Q2N_REQUIRE_SHARED", "1", 1);
    quietly(look_up, "required.obj");
    int f4 = chk_failed, s4 = chk_skipped, req_null = looked_up == NULL;
    setenv("Q2N_REQUIRE_SHARED", "0", 1);
    quietly(look_up, "other.obj");
    int f5 = chk_failed, s5 = chk_skipped;
    unsetenv("Q2N_REQUIRE_SHARED");
    chk_failed = f0; /* the helper's own counts are this test's data, not its result */
    chk_skipped = s0;
    chk_passed = p0;
    CHECK(ok_here, "present mesh: %s", looked_up ? looked_up : "NULL");
    CHECK(f1 == f0 && s1 == s0, "a present mesh counts nothing");
    CHECK(absent_null && s2 == s0 + 1 && f2 == f0, "absent mesh: one skip (skips %d, failures %d)", s2 - s0, f2 - f0);
    CHECK(s3 == s2, "the same absent mesh is said once");
    CHECK(req_null && f4 == f0 + 1 && s4 == s3, "Q2N_REQUIRE_SHARED=1: a failure, not a skip (%d, %d)", f4 - f0, s4 - s3);
    CHECK(f5 == f4 && s5 == s4 + 1, "Q2N_REQUIRE_SHARED=0: a skip again");

    int d0 = chk_deferred;
    setenv("Q2N_TEST_FULL", "1", 1);
    quietly(ask_full, "a sweep");
    CHECK(full_answer == 1 && chk_deferred == d0, "Q2N_TEST_FULL=1: full mode");
    setenv("Q2N_TEST_FULL", "0", 1);
    quietly(ask_full, "a sweep");
    CHECK(full_answer == 0 && chk_deferred == d0 + 1, "Q2N_TEST_FULL=0: quick mode, the sweep deferred");
    quietly(ask_full, NULL);
    CHECK(full_answer == 0 && chk_deferred == d0 + 1, "a question without a sweep defers nothing");
    unsetenv("Q2N_TEST_FULL");
    chk_deferred = d0;

    const char *sc = getenv("Q2N_SCRATCH");
    CHECK(!sc || !strncmp(chk_scratch("x"), sc, strlen(sc)), "chk_scratch in Q2N_SCRATCH: %s", chk_scratch("x"));
    struct stat st;
    CHECK(stat(chk_scratch_dir(), &st) == 0 && S_ISDIR(st.st_mode), "scratch folder %s exists", chk_scratch_dir());
    const char *keep = getenv("Q2N_EXE");
    char saved[1024] = "";
    if (keep) snprintf(saved, sizeof saved, "%s", keep);
    setenv("Q2N_EXE", "/some/quad2nurbs", 1);
    CHECK(!strcmp(chk_exe(), "/some/quad2nurbs"), "chk_exe follows Q2N_EXE");
    unsetenv("Q2N_EXE");
    CHECK(!strcmp(chk_exe(), "build/quad2nurbs"), "chk_exe default");
    if (keep) setenv("Q2N_EXE", saved, 1);
}

/* The runner on a fake build folder: DIR/tests/test_* are shell scripts. */
static void test_runner(void)
{
    char fb[1200], t[1400], cmd[4096];
    snprintf(fb, sizeof fb, "%s/fakebuild", chk_scratch_dir());
    snprintf(t, sizeof t, "%s/tests", fb);
    chk_mkdirs(t);
    static const struct { const char *name, *script; } progs[] = {
        {"test_ok", "#!/bin/sh\n"
                    "printf '%s %s %s %s\\n' \"$Q2N_SCRATCH\" \"$Q2N_EXE\" \"$Q2N_SHARED_MESHES\" \"$Q2N_TEST_FULL\" > \"$Q2N_SCRATCH/env\"\n"
                    "pwd > \"$Q2N_SCRATCH/pwd\"\n"
                    "echo 'SKIP one case'; echo 'test_ok: 3 passed, 0 failed, 1 skipped'\n"},
        {"test_bad", "#!/bin/sh\necho 'FAIL x.c:1: wrong' >&2; echo 'test_bad: 1 passed, 2 failed, 0 skipped'; exit 1\n"},
        {"test_crash", "#!/bin/sh\necho 'half way'; kill -SEGV $$\n"},
        {"test_liar", "#!/bin/sh\necho 'test_liar: 1 passed, 0 failed, 0 skipped'; exit 3\n"},
        {"test_slow", "#!/bin/sh\nexec sleep 60\necho 'test_slow: 1 passed, 0 failed, 0 skipped'\n"},
        {"test_modes", "#!/bin/sh\n[ \"$Q2N_TEST_FULL\" = 1 ] || echo 'DEFER the long sweep: run by make check-full'\n"
                       "echo 'test_modes: 1 passed, 0 failed, 0 skipped'\n"},
    };
    for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++) {
        char p[1500];
        snprintf(p, sizeof p, "%s/%s", t, progs[i].name);
        write_text(p, progs[i].script, 1);
    }
    char *out;
    /* quick mode, every program */
    snprintf(cmd, sizeof cmd, "env -u Q2N_EXE Q2N_SHARED_MESHES=/no/meshes Q2N_TEST_TIMEOUT=5 "
             "sh tests/run_tests.sh -j 3 --build %s > %s/quick.txt 2>&1", fb, fb);
    int rc = run(cmd);
    snprintf(t, sizeof t, "%s/quick.txt", fb);
    out = slurp(t);
    CHECK(rc == 1, "runner exit status %d with failures", rc);
    CHECK(out && strstr(out, "\n6 passed, 5 failed, 1 skipped\n"), "quick totals:\n%s", out ? out : "");
    CHECK(out && strstr(out, "failing programs: test_bad test_crash test_liar test_slow\n"), "failing programs listed");
    CHECK(out && strstr(out, "test_crash: crashed or printed no summary") && strstr(out, "half way"),
          "a crash is reported with its last lines");
    CHECK(out && strstr(out, "test_slow: timed out after 5 s"), "a time-out is reported");
    CHECK(out && strstr(out, "test_liar: exit status 3 although no check failed"), "a non-zero exit fails");
    CHECK(out && strstr(out, "FAIL x.c:1: wrong") && strstr(out, "SKIP one case"), "FAIL and SKIP lines shown");
    CHECK(out && strstr(out, "DEFER the long sweep") && strstr(out, "1 long sweeps left out"), "deferred sweeps counted");
    free(out);
    snprintf(t, sizeof t, "%s/scratch/test_ok/env", fb);
    out = slurp(t);
    char want[4096];
    snprintf(want, sizeof want, "%s/scratch/test_ok %s/quad2nurbs /no/meshes 0\n", fb, fb);
    CHECK(out && !strcmp(out, want), "environment of a program: '%s', want '%s'", out ? out : "", want);
    free(out);
    snprintf(t, sizeof t, "%s/scratch/test_ok/pwd", fb);
    out = slurp(t);
    char cwd[1024];
    CHECK(out && getcwd(cwd, sizeof cwd) && !strncmp(out, cwd, strlen(cwd)) && out[strlen(cwd)] == '\n',
          "programs run from the repository root (%s)", out ? out : "");
    free(out);
    /* full mode, the passing programs only */
    snprintf(cmd, sizeof cmd, "sh tests/run_tests.sh --full --build %s test_ok test_modes > %s/full.txt 2>&1", fb, fb);
    rc = run(cmd);
    snprintf(t, sizeof t, "%s/full.txt", fb);
    out = slurp(t);
    CHECK(rc == 0, "runner exit status %d without failures", rc);
    CHECK(out && strstr(out, "\n4 passed, 0 failed, 1 skipped\n") && !strstr(out, "DEFER"), "full mode:\n%s",
          out ? out : "");
    free(out);
    snprintf(t, sizeof t, "%s/scratch/test_ok/env", fb);
    out = slurp(t);
    CHECK(out && strstr(out, " 1\n"), "Q2N_TEST_FULL=1 in full mode: %s", out ? out : "");
    free(out);
    snprintf(cmd, sizeof cmd, "sh tests/run_tests.sh --build %s test_nonesuch > /dev/null 2>&1", fb);
    CHECK(run(cmd) == 2, "an unknown program name is a usage error");
}

/* test_export_pipeline without the shared meshes (skips, passes) and with them required (fails). */
static void test_plain_clone(void)
{
    char exe[1024], prog[1100], cmd[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    exe[n > 0 ? n : 0] = 0;
    char *slash = strrchr(exe, '/');
    if (slash) *slash = 0;
    snprintf(prog, sizeof prog, "%s/test_export_pipeline", exe);
    if (access(prog, X_OK) != 0) { SKIP("%s not built: plain-clone case not run", prog); return; }
    char empty[1200];
    snprintf(empty, sizeof empty, "%s/no_meshes", chk_scratch_dir());
    chk_mkdirs(empty);
    for (int req = 0; req < 2; req++) {
        snprintf(cmd, sizeof cmd, "Q2N_SHARED_MESHES=%s Q2N_REQUIRE_SHARED=%d Q2N_SCRATCH=%s/pipeline%d %s > %s/pipeline%d.txt 2>&1",
                 empty, req, chk_scratch_dir(), req, prog, chk_scratch_dir(), req);
        int rc = run(cmd);
        char p[1300];
        snprintf(p, sizeof p, "%s/pipeline%d.txt", chk_scratch_dir(), req);
        char *out = slurp(p);
        const char *sum = out ? strstr(out, "test_export_pipeline: ") : NULL;
        int np = -1, nf = -1, ns = -1;
        if (sum) sscanf(sum, "test_export_pipeline: %d passed, %d failed, %d skipped", &np, &nf, &ns);
        if (out && strstr(out, "is not installed") && ns == 1) {
            SKIP("FreeCAD not installed: test_export_pipeline skips as a whole");
        } else if (!req) {
            CHECK(rc == 0 && nf == 0 && ns >= 5, "no shared meshes: exit %d, %d failed, %d skipped\n%s", rc, nf, ns,
                  out ? out : "");
        } else {
            CHECK(rc != 0 && nf >= 5 && ns == 0, "Q2N_REQUIRE_SHARED=1 without meshes: exit %d, %d failed, %d skipped",
                  rc, nf, ns);
        }
        free(out);
    }
}

/* make -n with the given prefix/arguments; its output (caller frees). */
static char *make_n(const char *env, const char *args)
{
    char cmd[2048];
    const char *out = chk_scratch("make_n.txt");
    snprintf(cmd, sizeof cmd, "env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL %s make -n %s > %s 2>&1", env, args, out);
    if (system(cmd) == -1) return NULL;
    return slurp(out);
}

static void test_makefile(void)
{
    if (run("command -v make > /dev/null") != 0) { SKIP("make not installed"); return; }
    const char *obj = "build/src/core/error.o";
    char args[512];
    snprintf(args, sizeof args, "-B %s build/quad2nurbs", obj);
    char *o = make_n("CFLAGS=-DQ2N_ENV_CFLAGS CPPFLAGS=-DQ2N_ENV_CPPFLAGS LDFLAGS=-Wl,-O1", args);
    CHECK(o && strstr(o, "-DQ2N_ENV_CFLAGS") && strstr(o, "-DQ2N_ENV_CPPFLAGS") && strstr(o, "-std=c11") &&
              strstr(o, "-Isrc"), "environment CFLAGS/CPPFLAGS with the project's flags:\n%s", o ? o : "");
    const char *link = o ? strstr(o, "-o build/quad2nurbs") : NULL;
    CHECK(link && strstr(o, "-Wl,-O1"), "environment LDFLAGS on the link line:\n%s", o ? o : "");
    free(o);
    snprintf(args, sizeof args, "-B CFLAGS=-DQ2N_CMD_CFLAGS %s", obj);
    o = make_n("", args);
    CHECK(o && strstr(o, "-DQ2N_CMD_CFLAGS") && strstr(o, "-std=c11") && strstr(o, "-D_POSIX_C_SOURCE"),
          "command-line CFLAGS with the project's flags:\n%s", o ? o : "");
    free(o);
    o = make_n("", "-W tests/check.h build/tests/test_api");
    CHECK(o && strstr(o, "tests/test_api.c -o build/tests/test_api"), "tests/check.h changed: test_api rebuilt:\n%s",
          o ? o : "");
    free(o);
}

int main(void)
{
    test_helpers();
    test_makefile();
    test_runner();
    test_plain_clone();
    CHECK_DONE("test_harness");
}
