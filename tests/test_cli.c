/* test_cli.c — the quad2nurbs executable end to end: bad input gives one clear line on stderr
 * naming file:line (or the element), exit code 2 and no output file (not even a temporary one);
 * `sample` prints one line per patch and grid point; the tessellation has the expected size. */
#define _GNU_SOURCE
#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "check.h"

static const char *EXE = "build/quad2nurbs";
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
    if (access(EXE, X_OK) != 0) {
        SKIP("build/quad2nurbs not built");
        CHECK_DONE("test_cli");
    }
    snprintf(dir, sizeof dir, "/tmp/q2n_cli_XXXXXX");
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
    /* issue 16: degenerate geometry relative to the bounding box (accepted before, NaN or a
     * zero-area CAD face with exit 0) */
    expect_error("near-zero edge", "tiny.obj", "v 0 0 0\nv 1 0 0\nv 1 1e-50 0\nv 0 1 0\nf 1 2 3 4\n", NULL,
                 "tiny.obj:5: face 0 has a degenerate edge");
    expect_error("collinear quad", "line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\n", NULL,
                 "line.obj:5: face 0 has (near) zero area");
    expect_error("v0 = v2", "v0v2.obj", "v 0 0 0\nv 1 0 0\nv 0 0 0\nv 0 1 0\nf 1 2 3 4\n", NULL,
                 "v0v2.obj:5: face 0 has opposite corners");
    expect_error("bow-tie", "bowtie.obj", "v 0 0 0\nv 2 2 0\nv 2 0 0\nv 0 1 0\nf 1 2 3 4\n", NULL,
                 "bowtie.obj:5: face 0 is self-crossing");
    /* a non-quad mesh hears about --subdivide first, even with a bow-tie (a fine control face) */
    expect_error("bow-tie + triangle", "bt3.obj", "v 0 0 0\nv 2 2 0\nv 2 0 0\nv 0 1 0\nv 3 1 0\nf 1 2 3 4\n"
                 "f 3 2 5\n", NULL, "--subdivide 1");
    expect_error("too large", "huge.obj", "v 0 0 0\nv 1e308 0 0\nv 1e308 1e308 0\nv 0 1e308 0\nf 1 2 3 4\n",
                 NULL, "huge.obj: the bounding box is too large");
    write_file("quad.obj", quad);
    expect_error("bad --grid", "quad.obj", NULL, "--tess x", "--tess");
    expect_error("bad class", "quad.obj", NULL, "--class D9", "D9");
    expect_error("bad extension", "quad.obj", NULL, "-o x.xyz", "xyz");

    /* success paths */
    char args[1024], err[1024];
    long lines = 0;
    snprintf(args, sizeof args, "sample --grid 3 %s/quad.obj", dir);
    CHECK(run(args, err, sizeof err, &lines) == 0 && lines == 9, "sample on a single quad: %ld lines (%s)", lines, err);
    snprintf(args, sizeof args, "--subdivide 1 -q %s/tri.obj -o %s/tri_out.obj", dir, dir);
    CHECK(run(args, err, sizeof err, NULL) == 0, "triangle with --subdivide 1: %s", err);
    /* extreme scales: finite samples, exit 0 (NaN at 1e-200 / 5e307 before) */
    write_file("small.obj", "v 0 0 0\nv 1e-200 0 0\nv 1e-200 1e-200 3e-201\nv 0 1e-200 0\nv 2e-200 0 1e-201\n"
                            "v 2e-200 1e-200 0\nf 1 2 3 4\nf 2 5 6 3\n");
    write_file("big.obj", "v 0 0 0\nv 5e300 0 0\nv 5e300 5e300 1.5e300\nv 0 5e300 0\nv 1e301 0 5e299\n"
                          "v 1e301 5e300 0\nf 1 2 3 4\nf 2 5 6 3\n");
    for (int i = 0; i < 2; i++) {
        snprintf(args, sizeof args, "sample --grid 4 %s/%s > %s/s.txt", dir, i ? "big.obj" : "small.obj", dir);
        char cmd[4096];
        snprintf(cmd, sizeof cmd, "%s %s 2>/dev/null && ! grep -qi 'nan\\|inf' %s/s.txt && "
                 "test $(wc -l < %s/s.txt) = 32", EXE, args, dir, dir);
        CHECK(system(cmd) == 0, "%s: samples not finite or wrong count", i ? "big.obj" : "small.obj");
        snprintf(args, sizeof args, "-q %s/%s -o %s/x%d.step", dir, i ? "big.obj" : "small.obj", dir, i);
        CHECK(run(args, err, sizeof err, NULL) == 0, "%s: fit and export: %s", i ? "big" : "small", err);
        snprintf(args, sizeof args, "%s/x%d.step", dir, i);
        unlink(args);
    }
    /* a fold is reported, with the face's line */
    write_file("dart.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 3 1 0\n"
                           "v 0 2 0\nv 1 2 0\nv 1.3 1.3 0\nv 3 2 0\nv 0 3 0\nv 1 3 0\nv 2 3 0\nv 3 3 0\n"
                           "f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 5 6 10 9\nf 6 7 11 10\nf 7 8 12 11\n"
                           "f 9 10 14 13\nf 10 11 15 14\nf 11 12 16 15\n");
    snprintf(args, sizeof args, "sample --grid 2 %s/dart.obj", dir);
    CHECK(run(args, err, sizeof err, NULL) == 0 && strstr(err, "warning: ") &&
          strstr(err, "dart.obj:21: face 4: the surface folds over"), "dart: %s", err);
    const char *torus = chk_shared_mesh("osd_catmark_torus.obj");
    if (torus) {
        snprintf(args, sizeof args, "sample --grid 4 %s", torus);
        CHECK(run(args, err, sizeof err, &lines) == 0 && lines == 32 * 16, "torus sample lines %ld", lines);
    } else SKIP("osd_catmark_torus.obj: ../shared/meshes absent");
    snprintf(args, sizeof args, "rm -rf %s", dir);
    if (system(args)) {}
    CHECK_DONE("test_cli");
}
