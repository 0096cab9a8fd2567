/* test_outputs.c — the executable's outputs as one transaction, end to end:
 *   - several -o: when any fails (an unwritable place, a full device), none is written and an
 *     existing file keeps its old content; the check of every output's place happens before the
 *     input is even read; the same file twice, or the input mesh as an output, is refused;
 *   - '-' writes to standard output the same bytes as a file; without --format it is refused;
 *   - write failures exit 1 with the reason (missing directory, a directory, /proc, /dev/full);
 *   - an existing file keeps its permission bits, a new one gets 0666 minus the umask; a symbolic
 *     link keeps pointing at its (replaced) target; names of 250 characters work;
 *   - the data are fsync'ed before the rename and the directory after it (strace, when present);
 *   - SIGINT / SIGTERM during a run leave neither an output nor a temporary, and the program dies
 *     of that signal (the shell's 130 / 143).
 * Reproducers of issue 13 item 2 and issue 16 items 4 and 5. */
#define _GNU_SOURCE
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>

#include "check.h"
#include "meshgen.h"

#define EXE chk_exe()
static char dir[64], exe_abs[1024];

static void write_file(const char *name, const char *text)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    if (f) { fputs(text, f); fclose(f); }
}

/* Run `quad2nurbs ARGS` in dir (environment prefix env, may be ""); stderr into err (whole). */
static int run(const char *env, const char *args, char *err, size_t cap)
{
    char cmd[4096], ep[512];
    snprintf(ep, sizeof ep, "%s/stderr.txt", dir);
    snprintf(cmd, sizeof cmd, "cd %s && %s %s %s > stdout.txt 2> stderr.txt", dir, env, exe_abs, args);
    int st = system(cmd);
    size_t n = 0;
    char *e = chk_slurp(ep, &n);
    snprintf(err, cap, "%s", e ? e : "");
    free(e);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int exists(const char *name)
{
    char p[1024];
    struct stat st;
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return lstat(p, &st) == 0;
}

static void all_or_nothing(void)
{
    char err[4096];
    /* issue 13 item 2: the first output must not survive the failure of the second */
    int rc = run("", "quad.obj -o a.step -o /proc/x.step", err, sizeof err);
    CHECK(rc == 1 && strstr(err, "/proc/x.step: cannot create output") && !exists("a.step") && !chk_count_files(dir, ".q2n-"),
          "unwritable second output: exit %d, a.step %s (%s)", rc, exists("a.step") ? "left" : "absent", err);
    /* a failure at the very end (a full device, written after the files were ready): the existing
     * file keeps its old content */
    write_file("b.step", "OLD\n");
    rc = run("", "quad.obj -o b.step -o c.igs -o /dev/full --format step", err, sizeof err);
    char p[256];
    snprintf(p, sizeof p, "%s/b.step", dir);
    char *b = chk_slurp(p, NULL);
    CHECK(rc == 1 && strstr(err, "/dev/full: write failed: No space left on device") && b && !strcmp(b, "OLD\n") &&
          !exists("c.igs") && !chk_count_files(dir, ".q2n-"), "full device last: exit %d, b.step '%.8s', c.igs %d (%s)", rc,
          b ? b : "(none)", exists("c.igs"), err);
    free(b);
    /* every output's place is checked before the input is read */
    rc = run("", "missing.obj -o /nonexistent_dir/x.step", err, sizeof err);
    CHECK(rc == 1 && strstr(err, "/nonexistent_dir/x.step: cannot create output: No such file or directory") &&
          !strstr(err, "missing.obj"), "output place checked first: exit %d (%s)", rc, err);
    /* duplicates and the input */
    rc = run("", "quad.obj -o d.step -o ./d.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "given twice") && !exists("d.step"), "same output twice: %d (%s)", rc, err);
    rc = run("", "quad.obj -o d.step -o d.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "d.step: given twice as an output"), "same name twice: %d (%s)", rc, err);
    snprintf(p, sizeof p, "%s/quad.obj", dir);
    size_t l0, l1;
    char *before = chk_slurp(p, &l0);
    rc = run("", "quad.obj -o quad.obj", err, sizeof err);
    char *after = chk_slurp(p, &l1);
    CHECK(rc == 2 && strstr(err, "quad.obj: is the input mesh") && before && after && l0 == l1 && !memcmp(before, after, l0),
          "-o equal to the input refused and the mesh intact: %d (%s)", rc, err);
    rc = run("", "quad.obj -o ./sub/../quad.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "is the input mesh"), "the input under another name: %d (%s)", rc, err);
    free(before);
    free(after);
}

static void stdout_and_failures(void)
{
    char err[4096], p[512];
    /* '-' gives the bytes of a file of the same base name */
    int rc = run("SOURCE_DATE_EPOCH=1700000000", "quad.obj -q -o - --format step -o sub/quad.step", err, sizeof err);
    size_t ls, lf;
    snprintf(p, sizeof p, "%s/stdout.txt", dir);
    char *so = chk_slurp(p, &ls);
    snprintf(p, sizeof p, "%s/sub/quad.step", dir);
    char *fo = chk_slurp(p, &lf);
    CHECK(rc == 0 && so && fo && ls == lf && ls > 100 && !memcmp(so, fo, ls), "-o - equals the file: exit %d, %zu vs %zu "
          "bytes (%s)", rc, ls, lf, err);
    free(so);
    free(fo);
    rc = run("", "quad.obj -o -", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "--format"), "-o - without --format: %d (%s)", rc, err);
    rc = run("", "quad.obj -o - --format json -o - ", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "given twice"), "two standard outputs: %d (%s)", rc, err);
    /* issue 16 item 5: write failures are exit 1 with the reason */
    rc = run("", "quad.obj -o nodir/x.step", err, sizeof err);
    CHECK(rc == 1 && strstr(err, "nodir/x.step: cannot create output: No such file or directory"), "missing dir: %d (%s)",
          rc, err);
    rc = run("", "quad.obj -o sub", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "sub: no format extension"), "a directory without extension: %d (%s)", rc, err);
    snprintf(p, sizeof p, "%s/dir.step", dir);
    mkdir(p, 0755);
    rc = run("", "quad.obj -o dir.step", err, sizeof err);
    CHECK(rc == 1 && strstr(err, "dir.step: cannot write: Is a directory"), "directory as output: %d (%s)", rc, err);
    rc = run("", "quad.obj -o /proc/version.json", err, sizeof err);
    CHECK(rc == 1, "/proc: exit %d (%s)", rc, err);
    rc = run("", "quad.obj -o /dev/full --format obj", err, sizeof err);
    CHECK(rc == 1 && strstr(err, "/dev/full: write failed: No space left on device"), "/dev/full: %d (%s)", rc, err);
    rc = run("", "quad.obj -q -o /dev/null --format step", err, sizeof err);
    struct stat st;
    CHECK(rc == 0 && stat("/dev/null", &st) == 0 && S_ISCHR(st.st_mode), "/dev/null stays a device: %d (%s)", rc, err);
    /* a name of 250 characters (legal: NAME_MAX 255) */
    char name[300];
    memset(name, 'n', 245);
    snprintf(name + 245, sizeof name - 245, ".step");
    char args[600];
    snprintf(args, sizeof args, "quad.obj -q -o %s", name);
    rc = run("", args, err, sizeof err);
    CHECK(rc == 0 && exists(name) && !chk_count_files(dir, ".q2n-"), "a 250-character name: %d (%s)", rc, err);
}

static void modes_and_links(void)
{
    char err[4096], p[512], q[512];
    struct stat st;
    /* an existing file keeps its mode */
    write_file("m.step", "x");
    snprintf(p, sizeof p, "%s/m.step", dir);
    chmod(p, 0604);
    int rc = run("", "quad.obj -q -o m.step", err, sizeof err);
    CHECK(rc == 0 && stat(p, &st) == 0 && (st.st_mode & 07777) == 0604 && st.st_size > 100,
          "existing mode kept: %o (%s)", (unsigned)(st.st_mode & 07777), err);
    /* a new file: 0666 minus the umask */
    rc = run("umask 027 &&", "quad.obj -q -o new.step", err, sizeof err);
    snprintf(p, sizeof p, "%s/new.step", dir);
    CHECK(rc == 0 && stat(p, &st) == 0 && (st.st_mode & 07777) == 0640, "new file mode %o under umask 027",
          (unsigned)(st.st_mode & 07777));
    /* a symbolic link keeps pointing at its target, which is replaced */
    write_file("target.step", "OLD");
    snprintf(p, sizeof p, "%s/link.step", dir);
    if (symlink("target.step", p) != 0) CHECK(0, "symlink");
    rc = run("", "quad.obj -q -o link.step", err, sizeof err);
    snprintf(q, sizeof q, "%s/target.step", dir);
    CHECK(rc == 0 && lstat(p, &st) == 0 && S_ISLNK(st.st_mode) && stat(q, &st) == 0 && st.st_size > 100,
          "symlink kept, target replaced: %d (%s)", rc, err);
}

/* fsync of the data before the rename, of the directory after it. */
static void durability(void)
{
    if (access("/usr/bin/strace", X_OK) != 0) { SKIP("strace absent: fsync order not checked"); return; }
    char cmd[2048], p[512];
    /* LeakSanitizer cannot run under ptrace: an ASan build (make CONFIG=asan) traced here would exit 1 */
    snprintf(cmd, sizeof cmd, "cd %s && ASAN_OPTIONS=detect_leaks=0 strace -f -e trace=fsync,rename,renameat,renameat2,openat -o trace.txt %s -q quad.obj "
             "-o dur.step > /dev/null 2>&1", dir, exe_abs);
    int rc = system(cmd);
    snprintf(p, sizeof p, "%s/trace.txt", dir);
    char *t = chk_slurp(p, NULL);
    const char *ren = t ? strstr(t, "dur.step\"") : NULL;   /* the rename onto the target */
    while (ren && !strstr(ren - 40 > t ? ren - 40 : t, "rename")) ren = strstr(ren + 1, "dur.step\"");
    const char *f1 = t ? strstr(t, "fsync(") : NULL;
    const char *f2 = ren ? strstr(ren, "fsync(") : NULL;
    CHECK(rc == 0 && t && ren && f1 && f1 < ren && f2, "fsync of the file before the rename (%s) and of the directory "
          "after it (%s)", f1 && ren && f1 < ren ? "yes" : "no", f2 ? "yes" : "no");
    free(t);
}

/* Start a long run, wait for its temporary, send sig: the process dies of sig and leaves nothing. */
static void signal_case(int sig)
{
    char out[64];
    snprintf(out, sizeof out, "sig%d.step", sig);
    pid_t pid = fork();
    if (pid == 0) {
        if (chdir(dir) != 0) _exit(99);
        int nul = open("/dev/null", O_WRONLY);
        dup2(nul, 1);
        dup2(nul, 2);
        execl(exe_abs, exe_abs, "big.obj", "--tol", "1e-9", "-o", out, "-o", "sig.igs", (char *)NULL);
        _exit(98);
    }
    int seen = 0;
    for (int i = 0; i < 4000 && !seen; i++) {   /* up to 20 s */
        seen = chk_count_files(dir, ".q2n-") >= 2;
        if (!seen) { struct timespec ts = {0, 5000000}; nanosleep(&ts, NULL); }
    }
    struct timespec ts = {0, 50000000};
    nanosleep(&ts, NULL);
    kill(pid, sig);
    int st = 0;
    waitpid(pid, &st, 0);
    CHECK(seen, "signal %d: the temporaries never appeared", sig);
    CHECK(WIFSIGNALED(st) && WTERMSIG(st) == sig, "signal %d: the program %s %d", sig,
          WIFSIGNALED(st) ? "died of signal" : "exited with", WIFSIGNALED(st) ? WTERMSIG(st) : WEXITSTATUS(st));
    int left = chk_count_files(dir, ".q2n-");
    CHECK(!left && !exists(out) && !exists("sig.igs"), "signal %d: %d temporaries and %s left", sig, left,
          exists(out) ? "the output" : "no output");
}

int main(void)
{
    if (access(EXE, X_OK) != 0 || !realpath(EXE, exe_abs)) {
        CHECK(0, "%s not built", EXE);
        CHECK_DONE("test_outputs");
    }
    /* a folder in the scratch folder (relative to the repository, like the runner's) */
    if (chk_tmpdir(dir, sizeof dir, "outputs") != 0) { CHECK(0, "no scratch folder %s", dir); CHECK_DONE("test_outputs"); }
    char p[256];
    snprintf(p, sizeof p, "%s/sub", dir);
    mkdir(p, 0755);
    write_file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                           "f 1 2 3 4\nf 2 5 6 3\n");
    all_or_nothing();
    stdout_and_failures();
    modes_and_links();
    durability();
    /* a mesh whose fit takes seconds: 60 x 40 jittered torus at a tight tolerance */
    q2n_mesh *t = mg_torus(60, 40, 3.0, 1.0, 0.05, 1, 3u);
    snprintf(p, sizeof p, "%s/big.obj", dir);
    FILE *f = fopen(p, "w");
    for (int v = 0; t && f && v < t->nv; v++) fprintf(f, "v %.17g %.17g %.17g\n", t->pos[3 * v], t->pos[3 * v + 1], t->pos[3 * v + 2]);
    for (int k = 0; t && f && k < t->nf; k++)
        fprintf(f, "f %d %d %d %d\n", t->face_vert[4 * k] + 1, t->face_vert[4 * k + 1] + 1, t->face_vert[4 * k + 2] + 1,
                t->face_vert[4 * k + 3] + 1);
    if (f) fclose(f);
    q2n_mesh_free(t);
    signal_case(SIGINT);
    signal_case(SIGTERM);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd)) {}
    CHECK_DONE("test_outputs");
}
