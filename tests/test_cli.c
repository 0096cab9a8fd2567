/* test_cli.c — the quad2nurbs executable end to end: bad input gives one clear line on stderr
 * naming file:line (or the element), exit code 2 and no output file (not even a temporary one);
 * `sample` prints one line per patch and grid point; the tessellation has the expected size. */
#define _GNU_SOURCE
#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "check.h"

static const char *EXE; /* chk_exe() */
static char dir[256];

static void write_file(const char *name, const char *text)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    fputs(text, f);
    fclose(f);
}

/* Run a command line, capture stderr (first line) and stdout line count. */
static int run(const char *args, char *errline, size_t cap, long *outlines)
{
    char cmd[2048], ep[512], op[512];
    snprintf(ep, sizeof ep, "%s/stderr.txt", dir);
    snprintf(op, sizeof op, "%s/stdout.txt", dir);
    snprintf(cmd, sizeof cmd, "%s %s > %s 2> %s", EXE, args, op, ep);
    int st = system(cmd);
    FILE *f = fopen(ep, "r");
    errline[0] = 0;
    if (f) {
        if (!fgets(errline, (int)cap, f)) errline[0] = 0;
        fclose(f);
    }
    if (outlines) {
        *outlines = 0;
        f = fopen(op, "r");
        int c;
        while (f && (c = fgetc(f)) != EOF) *outlines += c == '\n';
        if (f) fclose(f);
    }
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int leftovers(void) /* files named *.tmp.* or out.* in the scratch dir */
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)))
        n += strstr(e->d_name, ".tmp.") != NULL || strncmp(e->d_name, "out", 3) == 0;
    if (d) closedir(d);
    return n;
}

static void expect_error(const char *label, const char *file, const char *text, const char *extra,
                         const char *needle)
{
    char args[1024], err[1024];
    if (text) write_file(file, text);
    snprintf(args, sizeof args, "%s %s/%s -o %s/out.obj", extra ? extra : "", dir, file, dir);
    int rc = run(args, err, sizeof err, NULL);
    CHECK(rc == 2, "%s: exit code %d, expected 2 (%s)", label, rc, err);
    CHECK(strstr(err, needle) != NULL, "%s: message '%s' lacks '%s'", label, err, needle);
    CHECK(leftovers() == 0, "%s: an output or temporary file was left behind", label);
}

int main(void)
{
    EXE = chk_exe();
    if (access(EXE, X_OK) != 0) {
        SKIP("%s not built", EXE);
        CHECK_DONE("test_cli");
    }
    snprintf(dir, sizeof dir, "%.200s/cli_XXXXXX", chk_scratch_dir());
    if (!mkdtemp(dir)) { CHECK(0, "mkdtemp"); CHECK_DONE("test_cli"); }

    const char *quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    expect_error("missing file", "nope.obj", NULL, NULL, "nope.obj");
    expect_error("bad number", "badnum.obj", "v 0 0 0\nv 1 x 0\n", NULL, "badnum.obj:2:");
    expect_error("NaN", "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 1 0\nf 1 2 3 4\n", NULL, "nan.obj:3:");
    expect_error("Inf", "inf.obj", "v 0 0 0\nv 1 0 inf\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", NULL, "inf.obj:2:");
    expect_error("index range", "range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3 9\n", NULL, "range.obj:4:");
    expect_error("repeated vertex", "rep.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 2 4\n", NULL, "rep.obj:5:");
    expect_error("zero-length edge", "zero.obj", "v 0 0 0\nv 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n", NULL,
                 "zero.obj:5:");
    expect_error("non-manifold edge", "nm.obj",
                 "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nv 1 0 1\nv 0 0 1\n"
                 "f 1 2 3 4\nf 2 1 6 5\nf 1 2 7 8\n", NULL, "nm.obj:11:");
    expect_error("orientation", "orient.obj",
                 "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 3 6 5\n", NULL, "orient.obj:8:");
    expect_error("empty mesh", "empty.obj", "# nothing\nv 0 0 0\n", NULL, "empty.obj");
    expect_error("triangle", "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", NULL, "--subdivide");
    expect_error("unknown keyword", "kw.obj", "v 0 0 0\nfoo 1 2\n", NULL, "kw.obj:2:");
    write_file("quad.obj", quad);
    expect_error("bad --grid", "quad.obj", NULL, "--tess x", "--tess");
    expect_error("bad class", "quad.obj", NULL, "--class D9", "D9");
    expect_error("bad extension", "quad.obj", NULL, "-o x.xyz", "xyz");
    expect_error("bad --max-spans", "quad.obj", NULL, "--max-spans 0", "--max-spans");
    expect_error("bad --gluing", "quad.obj", NULL, "--gluing loose", "--gluing");

    /* success paths */
    char args[1024], err[1024];
    long lines = 0;
    snprintf(args, sizeof args, "sample --grid 3 %s/quad.obj", dir);
    CHECK(run(args, err, sizeof err, &lines) == 0 && lines == 9, "sample on a single quad: %ld lines (%s)", lines, err);
    snprintf(args, sizeof args, "--subdivide 1 -q %s/tri.obj -o %s/tri_out.obj", dir, dir);
    CHECK(run(args, err, sizeof err, NULL) == 0, "triangle with --subdivide 1: %s", err);
    const char *torus = chk_shared_mesh("osd_catmark_torus.obj");
    if (torus) {
        snprintf(args, sizeof args, "sample --grid 4 %s", torus);
        CHECK(run(args, err, sizeof err, &lines) == 0 && lines == 32 * 16, "torus sample lines %ld", lines);
    }
    snprintf(args, sizeof args, "rm -rf %s", dir);
    if (system(args)) {}
    CHECK_DONE("test_cli");
}
