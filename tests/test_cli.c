/* test_cli.c — the quad2nurbs executable end to end: bad input gives one clear line on stderr
 * naming file:line (or the element), exit code 2 and no output file (not even a temporary one);
 * `sample` prints one line per patch and grid point; the tessellation has the expected size.
 * Also (issues 13 and 16): GNU-style option errors; control bytes of the input escaped in
 * messages; progress on a pseudo-terminal (script -qc), as plain lines with --progress, never with
 * -q; OpenSubdiv tags warned about once; the tolerances --tol-abs, --angle-tol, --curvature-tol in
 * the report and as the fit's acceptance targets; the summary's units; warnings for options the
 * chosen path ignores; --threads above 64; the valence limit with a line; an interior vertex of two faces; resource limits. */
#define _GNU_SOURCE
#include <sys/statvfs.h>
#include <time.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <sys/resource.h>

#include "check.h"
#include "meshgen.h"
#include "patch/surface.h"

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

static int leftovers(void) /* temporaries (.q2n-*) or out.* in the scratch dir */
{
    return chk_count_files(dir, ".q2n-") + chk_count_files(dir, "out");
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

/* Run a shell command line in the scratch dir (the executable as $Q), all of stderr into err. */
static int run_sh(const char *line, char *err, size_t cap)
{
    char cmd[4096], ep[512], exe[1024];
    if (!realpath(EXE, exe)) snprintf(exe, sizeof exe, "%s", EXE);
    snprintf(ep, sizeof ep, "%s/stderr.txt", dir);
    snprintf(cmd, sizeof cmd, "cd %s && Q=%s && %s 2> stderr.txt", dir, exe, line);
    int st = system(cmd);
    char *e = chk_slurp(ep, NULL);
    snprintf(err, cap, "%s", e ? e : "");
    free(e);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static double jnum(const char *js, const char *key)
{
    char k[64];
    snprintf(k, sizeof k, "\"%s\": ", key);
    const char *p = js ? strstr(js, k) : NULL;
    return p ? strtod(p + strlen(k), NULL) : NAN;
}

static char *report(const char *name)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return chk_slurp(p, NULL);
}

/* Issue 13 item 4: getopt errors name the program (not its path) and end with one hint line. */
static void option_errors(void)
{
    char err[4096];
    int rc = run_sh("$Q --frobnicate quad.obj -o x.obj", err, sizeof err);
    CHECK(rc == 2 && !strcmp(err, "quad2nurbs: unrecognized option '--frobnicate'\n"
                                  "Try 'quad2nurbs --help' for more information.\n"), "unknown option: %d '%s'", rc, err);
    rc = run_sh("$Q -z quad.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "quad2nurbs: invalid option -- 'z'\nTry 'quad2nurbs --help'") && !strstr(err, "usage:"),
          "unknown short option: %d '%s'", rc, err);
    rc = run_sh("$Q quad.obj --tol", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "quad2nurbs: option '--tol' requires an argument") && !strstr(err, "/quad2nurbs"),
          "missing argument: %d '%s'", rc, err);
    rc = run_sh("$Q quad.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "no output given") && strstr(err, "Try 'quad2nurbs --help'"), "no output: '%s'", err);
    rc = run_sh("$Q quad.obj -o x.step --tol 1e-4 --tol-abs 0.1", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "--tol and --tol-abs"), "--tol with --tol-abs: %d '%s'", rc, err);
    rc = run_sh("$Q quad.obj -o x.step --max-memory lots", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "--max-memory"), "bad --max-memory: %d '%s'", rc, err);
    rc = run_sh("$Q --help > help.txt", err, sizeof err);
    char p[512];
    snprintf(p, sizeof p, "%s/help.txt", dir);
    char *h = chk_slurp(p, NULL);
    static const char *const opts[] = {"--output", "--format", "--surface", "--acc-strategy", "--class", "--ev-patch",
                                       "--param", "--alpha", "--subdivide", "--scale", "--units", "--tess", "--tol ",
                                       "--tol-abs", "--angle-tol", "--curvature-tol", "--continuity", "--threads",
                                       "--solver", "--grid", "--max-memory", "--progress", "--quiet", "--help", "--version"};
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++)
        CHECK(rc == 0 && h && strstr(h, opts[i]), "--help lacks %s", opts[i]);
    free(h);
}

/* Issue 16 item 6: escaped control bytes, messages without doubled prefixes or "1 vertices". */
static void messages(void)
{
    char err[4096];
    write_file("esc.obj", "v 0 0 0\n\x1b]0;pwned\x07 1 2\n");
    int rc = run_sh("$Q esc.obj -o out.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "esc.obj:2: unknown keyword '\\x1b]0;pwned\\x07'") && !strchr(err, 0x1b) && !strchr(err, 0x07),
          "control bytes escaped: %d '%s'", rc, err);
    rc = run_sh("$Q \"$(printf 'no\\033[31mfile.obj')\" -o out.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "no\\x1b[31mfile.obj") && !strchr(err, 0x1b), "file name escaped: '%s'", err);
    write_file("one.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1\n");
    rc = run_sh("$Q one.obj -o out.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "one.obj:5: face with only 1 vertex (a face needs at least 3)"), "1 vertex: '%s'", err);
    /* coordinates near the bottom of the double range: built and fitted at diagonal 1, mapped back
     * (and a fit message, if any, says "fit:" once) */
    write_file("tiny.obj", "v 0 0 0\nv 1e-200 0 0\nv 1e-200 1e-200 0\nv 0 1e-200 0\nf 1 2 3 4\n");
    rc = run_sh("$Q tiny.obj -q -o tiny.step", err, sizeof err);
    CHECK(rc == 0 && !strstr(err, "fit: fit:"), "1e-200 quad: %d '%s'", rc, err);
    /* OpenSubdiv tags: one warning with the count, the first line and the names; then ignored */
    write_file("tags.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n"
                           "t crease 2/1/0 1 2 4.0\nt crease 2/1/0 2 3 4.0\nt corner 1/1/0 4 2.0\n");
    rc = run_sh("$Q tags.obj -o tags.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "quad2nurbs: warning: tags.obj:9: 3 OpenSubdiv tag lines ignored (crease, corner): "
                                 "sharp features are not supported yet\n") && strstr(err, "2 faces"),
          "tags warned about once: %d '%s'", rc, err);
    rc = run_sh("$Q sample quad.obj -o - --format obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "both write to standard output"), "sample with -o -: %d '%s'", rc, err);
    /* valence above 64: refused with the line of a face at the vertex */
    FILE *f;
    char p[512];
    snprintf(p, sizeof p, "%s/fan.obj", dir);
    if ((f = fopen(p, "w"))) {
        int n = 70;
        fputs("v 0 0 0\n", f);
        for (int k = 0; k < n; k++) fprintf(f, "v %.17g %.17g 0\n", cos(2 * M_PI * k / n), sin(2 * M_PI * k / n));
        for (int k = 0; k < n; k++)
            fprintf(f, "v %.17g %.17g 0.1\n", 1.6 * cos(2 * M_PI * (k + 0.5) / n), 1.6 * sin(2 * M_PI * (k + 0.5) / n));
        for (int k = 0; k < n; k++) fprintf(f, "f 1 %d %d %d\n", 2 + k, 2 + n + k, 2 + (k + 1) % n);
        fclose(f);
    }
    rc = run_sh("$Q fan.obj -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "fan.obj:142: vertex 0 (of this face) has valence 70") && leftovers() == 0,
          "valence 70: %d '%s'", rc, err);
    rc = run_sh("$Q fan.obj -q --surface acc3 -o fan.step", err, sizeof err);
    CHECK(rc == 0, "valence 70 with acc3: %d '%s'", rc, err);
    /* an interior vertex of two faces (a cube whose top is two quads sharing two edges at a centre
     * vertex): refused with its line, in every construction (it used to fail in the vertex estimates
     * with "vertex 8: derivative estimate failed (Appendix B)") */
    write_file("val2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nv 0.5 0.5 1.1\n"
                           "f 1 3 4 2\nf 1 2 6 5\nf 2 4 8 6\nf 4 3 7 8\nf 3 1 5 7\nf 5 6 8 9\nf 5 9 8 7\n");
    static const char *const v2opt[] = {"", "--ev-patch g1", "--ev-construction paper", "--subdivide 1"};
    for (int i = 0; i < 4; i++) {
        char cmd[128];
        snprintf(cmd, sizeof cmd, "$Q val2.obj %s -o out.step", v2opt[i]);
        rc = run_sh(cmd, err, sizeof err);
        /* numbered in the subdivided mesh after --subdivide, and the message says so */
        CHECK(rc == 2 &&
                  strstr(err, i == 3 ? "val2.obj:15: vertex 8 (of this face of the subdivided mesh) is an interior vertex of "
                                       "only 2 faces"
                                     : "val2.obj:15: vertex 8 (of this face) is an interior vertex of only 2 faces") &&
                  leftovers() == 0,
              "valence-2 interior vertex %s: %d '%s'", v2opt[i], rc, err);
    }
}

/* Issue 16 item 6: options the chosen path ignores are named; --threads above the cap. */
static void option_warnings(void)
{
    char err[4096];
    int rc = run_sh("$Q quad.obj --surface acc3 --class D3C1P2S4 -o w.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: --class is ignored with --surface acc3"), "--class with acc3: '%s'", err);
    rc = run_sh("$Q quad.obj --param uniform --alpha 0.7 -o w.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: --alpha is ignored with --param uniform"), "--alpha with uniform: '%s'", err);
    rc = run_sh("$Q quad.obj --surface acc-g1 --ev-patch g1 -o w.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: --ev-patch is ignored with --surface acc-g1"), "--ev-patch with acc-g1: '%s'", err);
    rc = run_sh("$Q quad.obj --acc-strategy ncs-s -o w.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: --acc-strategy is ignored with --surface augmented"), "--acc-strategy: '%s'", err);
    rc = run_sh("$Q quad.obj --tol 1e-4 --tess 5 -o w.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: --tess is ignored: no .obj output"), "--tess without .obj: '%s'", err);
    rc = run_sh("$Q quad.obj --tol 1e-4 -o w.obj", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "--tol/--tol-abs: ignored, no output needs the fit"), "--tol without a fit: '%s'", err);
    rc = run_sh("$Q -q quad.obj --surface acc3 --class D3C1P2S4 -o w.step", err, sizeof err);
    CHECK(rc == 0 && err[0] == 0, "-q silences warnings: '%s'", err);
    rc = run_sh("$Q quad.obj --threads 256 -o w.json", err, sizeof err);
    char *js = report("w.json");
    CHECK(rc == 0 && strstr(err, "warning: --threads 256: at most 64 threads are used") && jnum(js, "threads") == 64,
          "--threads 256: report says %g (%s)", jnum(js, "threads"), err);
    free(js);
}

/* Issue 13 item 5: tolerances in model units and the continuity targets, in the report and as
 * what the fit accepts; the summary names its units. */
/* Limit points: the cube [-5,5]^3 subdivided once has its corner vertex at 5 x 5/9; moved to its
 * Catmull-Clark limit it is at 5 x 1/2 (test_subdivide.c works the mask by hand).  After --subdivide
 * the surface passes through the limit point (patch 0's corner (0, 0) is that vertex), also with
 * --limit-points; with --no-limit-points through the control vertex, 25/9.  Without --subdivide the
 * cube's own corner (-5, -5, -5) is interpolated, unless --limit-points moves it to its limit,
 * (9 (-5) + 4 (-5) + 5) / 24 = -2.5 per coordinate (valence 3: three edge neighbours, three
 * opposite corners).  The ACC surfaces ignore both options, saying so. */
static void limit_points(void)
{
    char err[4096];
    static const struct { const char *opts; double want; } S[] = {
        {"--subdivide 1", -2.5}, {"--subdivide 1 --limit-points", -2.5}, {"--subdivide 1 --no-limit-points", -25.0 / 9},
        {"", -5.0}, {"--no-limit-points", -5.0}, {"--limit-points", -2.5}};
    for (size_t i = 0; i < sizeof S / sizeof S[0]; i++) {
        char cmd[256];
        snprintf(cmd, sizeof cmd, "$Q sample cube.obj %s --grid 2 > lp.txt", S[i].opts);
        int rc = run_sh(cmd, err, sizeof err);
        char *s = report("lp.txt");
        int k = -1;
        double u = -1, v = -1, x = 0, y = 0, z = 0, want = S[i].want;
        if (s) sscanf(s, "%d %lf %lf %lf %lf %lf", &k, &u, &v, &x, &y, &z);
        CHECK(rc == 0 && k == 0 && u == 0 && v == 0 && fabs(x - want) < 1e-12 && fabs(y - want) < 1e-12 && fabs(z - want) < 1e-12,
              "'%s': patch 0 at (0, 0) is (%.15g %.15g %.15g), expected %.15g each: %d '%s'", S[i].opts, x, y, z, want, rc, err);
        free(s);
    }
    /* the report says how far the vertices moved: on the cube subdivided once the most is an edge
     * point's, (3.75, 3.75, 0) -> (x, x, 0) with x = (16 * 3.75 + 4 (5 + 2 * 25/9) + 2 * 3.75) / 36 =
     * 987.5 / 324 (valence 4: two face points and two corners beside it, four edge points opposite),
     * a move of sqrt(2) (3.75 - x) = sqrt(2) 227.5 / 324 on a diagonal of 10 sqrt(3) (a corner moves
     * sqrt(3) 5/18, a face point 0.80); 0 through the control vertices */
    int rc;
    for (int lp = 0; lp < 2; lp++) {
        rc = run_sh(lp ? "$Q cube.obj --subdivide 1 -q -o lp.json" : "$Q cube.obj --subdivide 1 --no-limit-points -q -o lp.json",
                    err, sizeof err);
        char *js = report("lp.json");
        double mv = jnum(js, "vertices_moved_max_rel");
        CHECK(rc == 0 && (lp ? fabs(mv - sqrt(2.0 / 3) * 227.5 / 3240) < 1e-7 /* 6 digits printed */ : mv == 0),
              "report's vertices_moved_max_rel %s: %.17g: %d '%s'", lp ? "with limit points" : "without", mv, rc, err);
        free(js);
    }
    rc = run_sh("$Q cube.obj --surface acc-g1 --limit-points -o lp.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "--limit-points is ignored with --surface acc-g1"), "acc-g1 with --limit-points: %d '%s'", rc, err);
    rc = run_sh("$Q cube.obj --surface acc3 --no-limit-points -o lp.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "--no-limit-points is ignored with --surface acc3"), "acc3 with --no-limit-points: %d '%s'", rc, err);
}

/* --keep-flat: a 3 x 3 x 3 box (every side's middle quad has a planar one-ring).  The default fair
 * construction bulges those middle quads out of their sides by ~2 % of the diagonal (the energy
 * spreads the rounded edges into them); with --keep-flat they stay in their planes to rounding.
 * The box is written side by side, so face 4 + 9 s is the middle of side s (x = 3 for s = 1). */
static void keep_flat(void)
{
    char text[8192] = "", err[4096];
    int n = 0, vid[4][4][4];
    memset(vid, 0, sizeof vid);
    for (int x = 0; x < 4; x++)
        for (int y = 0; y < 4; y++)
            for (int z = 0; z < 4; z++)
                if (x % 3 == 0 || y % 3 == 0 || z % 3 == 0) {
                    vid[x][y][z] = ++n;
                    size_t l = strlen(text);
                    snprintf(text + l, sizeof text - l, "v %d %d %d\n", x, y, z);
                }
    for (int s = 0; s < 6; s++) { /* axis s / 2, at 0 (s even) or 3 */
        int d = s / 2, a = (d + 1) % 3, b = (d + 2) % 3, hi = s % 2;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                int c[4][3], q[4];
                for (int k = 0; k < 4; k++) {
                    int kk = hi ? k : (4 - k) % 4;
                    c[k][d] = 3 * hi, c[k][a] = i + q2n_corner_uv[kk][0], c[k][b] = j + q2n_corner_uv[kk][1];
                    q[k] = vid[c[k][0]][c[k][1]][c[k][2]];
                }
                size_t l = strlen(text);
                snprintf(text + l, sizeof text - l, "f %d %d %d %d\n", q[0], q[1], q[2], q[3]);
            }
    }
    write_file("box3.obj", text);
    double diag = 3 * sqrt(3.0);
    for (int kf = 0; kf < 2; kf++) {
        int rc = run_sh(kf ? "$Q sample box3.obj --keep-flat --grid 9 > kf.txt" : "$Q sample box3.obj --grid 9 > kf.txt", err,
                        sizeof err);
        char *t = report("kf.txt"), *line = t;
        double dev = 0;
        int pts = 0;
        while (line && *line) {
            int k;
            double u, v, X, Y, Z;
            if (sscanf(line, "%d %lf %lf %lf %lf %lf", &k, &u, &v, &X, &Y, &Z) == 6 && k == 13) dev = fmax(dev, fabs(X - 3) / diag), pts++;
            line = strchr(line, '\n');
            if (line) line++;
        }
        free(t);
        CHECK(rc == 0 && pts == 81 && (kf ? dev <= 1e-12 : dev >= 1e-3),
              "%s: the middle of side x = 3 leaves its plane by %.3g x diag (%d points): %d '%s'", kf ? "--keep-flat" : "default", dev,
              pts, rc, err);
    }
    /* the report counts them: 4 flat fans inside each side */
    for (int kf = 0; kf < 2; kf++) {
        int rc = run_sh(kf ? "$Q box3.obj --keep-flat -q -o kf.json" : "$Q box3.obj -q -o kf.json", err, sizeof err);
        char *js = report("kf.json");
        double nfl = jnum(js, "flat_vertices");
        CHECK(rc == 0 && nfl == (kf ? 24 : 0), "%s: report's flat_vertices %g: %d '%s'", kf ? "--keep-flat" : "default", nfl, rc,
              err);
        free(js);
    }
    /* the default says where it bends a flat region, and what keeps it flat; --keep-flat has nothing to say */
    for (int kf = 0; kf < 2; kf++) {
        int rc = run_sh(kf ? "$Q box3.obj --keep-flat -o kf.json" : "$Q box3.obj -o kf.json", err, sizeof err);
        int said = strstr(err, "box3.obj:") && strstr(err, "the mesh is flat there (and on 6 faces in all), the surface leaves "
                                                        "the plane by") && strstr(err, "--keep-flat keeps flat regions flat");
        CHECK(rc == 0 && (kf ? !strstr(err, "the mesh is flat there") : said), "%s: flat-region warning: %d '%s'",
              kf ? "--keep-flat" : "default", rc, err);
    }
    int rc = run_sh("$Q box3.obj --surface acc-g1 --keep-flat -o kf.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "--keep-flat is ignored with --surface acc-g1"), "acc-g1 with --keep-flat: %d '%s'", rc, err);
    rc = run_sh("$Q box3.obj --ev-construction paper --keep-flat -o kf.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "--keep-flat is ignored with --ev-construction paper"), "paper with --keep-flat: %d '%s'", rc, err);
}

/* G2 patches that fold on a thin part: a 1 x 1 plate 0.01 thick, 4 x 4 quads a side and one across
 * the thickness (meshgen.h mg_thin_plate; test_robust builds it through the model).  By default (no --ev-patch, and no
 * --continuity g2) the run builds G1 patches instead, which do not fold, says so and reports it;
 * asked for G2 it keeps the folded G2 surface and warns of the fold. */
static void fold_fallback(void)
{
    char err[4096], path[512];
    q2n_mesh *pm = mg_thin_plate(4, 0.01);
    q2n_error e;
    snprintf(path, sizeof path, "%s/plate.obj", dir);
    CHECK(pm && q2n_mesh_write_obj(pm, path, &e) == Q2N_OK, "thin plate: not written");
    q2n_mesh_free(pm);
    int rc = run_sh("$Q plate.obj -o plate.json", err, sizeof err);
    char *js = report("plate.json");
    CHECK(rc == 0 && strstr(err, "plate.obj:") && strstr(err, "G2 patches at the extraordinary vertices fold over there") &&
              strstr(err, "built with G1 patches at every extraordinary vertex instead (0 faces fold)") &&
              !strstr(err, "the surface folds over") && js && strstr(js, "\"continuity\": \"G1\"") &&
              jnum(js, "folded_faces") == 0 && jnum(js, "g2_folded_faces") >= 1 &&
              strstr(js, "\"note\": \"G2 patches folded over on ") && strstr(js, "G2 not imposed"),
          "thin plate, default: %d '%s' %s", rc, err, js ? js : "(no report)");
    free(js);
    /* asked for a G1 fit, the same (the G2 patches' curvature continuity was not asked for either) */
    rc = run_sh("$Q plate.obj --continuity g1 -o plate.json", err, sizeof err);
    js = report("plate.json");
    CHECK(rc == 0 && strstr(err, "built with G1 patches") && js && jnum(js, "folded_faces") == 0 && jnum(js, "g2_folded_faces") >= 1,
          "thin plate, --continuity g1: %d '%s'", rc, err);
    free(js);
    for (int i = 0; i < 2; i++) {
        rc = run_sh(i ? "$Q plate.obj --ev-patch g2 -o plate.json" : "$Q plate.obj --continuity g2 -o plate.json", err,
                    sizeof err);
        js = report("plate.json");
        CHECK(rc == 0 && strstr(err, "the surface folds over") && !strstr(err, "built with G1 patches") && js &&
                  strstr(js, "\"continuity\": \"G2\"") && jnum(js, "folded_faces") >= 1 && jnum(js, "g2_folded_faces") == 0 &&
                  !strstr(js, "G2 patches folded over"),
              "thin plate, %s: %d '%s'", i ? "--ev-patch g2" : "--continuity g2", rc, err);
        free(js);
    }
}

/* --pair-triangles on an STL-style torus (12 x 32 quads of aspect ~20, each cut along a diagonal):
 * through --subdivide 1 its needle quads cross (a bow-tie, exit 2) and the run says that the
 * triangles would pair; paired, the torus is its quad grid again (384 regular faces, one span each,
 * exact G1/G2); a cap fan left over asks for --subdivide, and with it the run succeeds. */
static void pair_triangles(void)
{
    char err[4096], p[512];
    snprintf(p, sizeof p, "%s/tt.obj", dir);
    FILE *f = fopen(p, "w");
    for (int i = 0; f && i < 12; i++)
        for (int j = 0; j < 32; j++) {
            double a = 2 * M_PI * i / 12, b = 2 * M_PI * j / 32;
            fprintf(f, "v %.17g %.17g %.17g\n", (5 + 0.3 * cos(b)) * cos(a), (5 + 0.3 * cos(b)) * sin(a), 0.3 * sin(b));
        }
    for (int i = 0; f && i < 12; i++)
        for (int j = 0; j < 32; j++) {
            int a = i * 32 + j + 1, b = (i + 1) % 12 * 32 + j + 1, c = (i + 1) % 12 * 32 + (j + 1) % 32 + 1,
                d = i * 32 + (j + 1) % 32 + 1;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", a, b, c, c, d, a);
        }
    if (f) fclose(f);
    int rc = run_sh("$Q tt.obj --subdivide 1 -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "768 of its 768 triangles pair into convex quads") && strstr(err, "(of the subdivided mesh) is self-crossing") &&
              leftovers() == 0, "triangulated torus, --subdivide 1: %d '%s'", rc, err);
    /* the ACC path splits triangles by itself: the same note (its surface of the split torus folds on
     * 528 faces; paired, it is the torus' own bicubic patches) */
    rc = run_sh("$Q tt.obj --surface acc-g1 -o ttacc.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "768 of its 768 triangles pair into convex quads"), "triangulated torus, acc-g1: %d '%s'",
          rc, err);
    rc = run_sh("$Q tt.obj --surface acc-g1 --pair-triangles -o ttacc.step", err, sizeof err);
    CHECK(rc == 0 && !strstr(err, "folds over") && strstr(err, "384 faces"), "triangulated torus, acc-g1 paired: %d '%s'",
          rc, err);
    /* the resource estimate is made for the paired mesh (384 faces), not for 768 triangles */
    rc = run_sh("$Q tt.obj --pair-triangles --max-memory 1K -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "(estimated: 384 faces;") && leftovers() == 0, "triangulated torus, estimate: %d '%s'", rc, err);
    rc = run_sh("$Q tt.obj --pair-triangles -o tt.json", err, sizeof err);
    char *js = report("tt.json");
    CHECK(rc == 0 && strstr(err, "384 faces (384 pairs of triangles merged into quads, 0 triangles left)") && js &&
              jnum(js, "paired_quads") == 384 && jnum(js, "triangles_left") == 0 && strstr(js, "\"tol_met\": true") &&
              jnum(js, "g1_max_deg") < 1e-6 && jnum(js, "edge_spans_max") == 1,
          "triangulated torus, --pair-triangles: %d '%s' %s", rc, err, js ? js : "(no report)");
    free(js);
    /* a hexagon's fan and a triangle beside it: seven triangles, so one is left however they pair
     * (three pairs: kites of 60 and 120 degrees, or a trapezoid): --subdivide is still needed, and named */
    write_file("fan.obj", "v 0 0 0\nv 1 0 0\nv 0.5 0.87 0\nv -0.5 0.87 0\nv -1 0 0\nv -0.5 -0.87 0\nv 0.5 -0.87 0\n"
                          "v 1.5 0.87 0\n"
                          "f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\nf 1 6 7\nf 1 7 2\nf 2 8 3\n");
    rc = run_sh("$Q fan.obj --pair-triangles -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "fan.obj:") && strstr(err, "(of the paired mesh) has 3 vertices") &&
              strstr(err, "--subdivide 1") && !strstr(err, "--pair-triangles to") && leftovers() == 0,
          "fan, --pair-triangles: %d '%s'", rc, err);
    rc = run_sh("$Q fan.obj --pair-triangles --subdivide 1 -o fan.json", err, sizeof err);
    js = report("fan.json");
    CHECK(rc == 0 && js && jnum(js, "paired_quads") == 3 && jnum(js, "triangles_left") == 1,
          "fan, --pair-triangles --subdivide 1: %d '%s'", rc, err);
    free(js);
    expect_error("triangle, no option", "tri2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", NULL,
                 "or --pair-triangles to merge triangles into quads");
}

/* --fill-ngons on a 12-sided cylinder with flat 12-gon caps: without it the run names the option
 * (an error without --subdivide, a warning with it);
 * with it each cap becomes a ring of 12 quads and a 3 x 3 grid (21 quads), the summary and the
 * report count them, and the fit meets its targets; a star-shaped cap is refused, naming its line,
 * and nothing is written. */
static void fill_ngons(void)
{
    char err[4096], p[512];
    for (int star = 0; star < 2; star++) {
        snprintf(p, sizeof p, "%s/%s.obj", dir, star ? "star" : "cyl12");
        FILE *f = fopen(p, "w");
        for (int r = 0; f && r <= 2; r++)
            for (int k = 0; k < 12; k++) {
                double a = 2 * M_PI * k / 12, rad = star && k % 2 ? 0.3 : 1;
                fprintf(f, "v %.17g %.17g %.17g\n", rad * cos(a), rad * sin(a), 0.6 * r);
            }
        for (int r = 0; f && r < 2; r++)
            for (int k = 0; k < 12; k++)
                fprintf(f, "f %d %d %d %d\n", r * 12 + k + 1, r * 12 + (k + 1) % 12 + 1, (r + 1) * 12 + (k + 1) % 12 + 1,
                        (r + 1) * 12 + k + 1);
        if (f) {
            fprintf(f, "f");
            for (int k = 11; k >= 0; k--) fprintf(f, " %d", k + 1);
            fprintf(f, "\nf");
            for (int k = 0; k < 12; k++) fprintf(f, " %d", 24 + k + 1);
            fprintf(f, "\n");
            fclose(f);
        }
    }
    int rc = run_sh("$Q cyl12.obj -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "cyl12.obj:61: face 24 has 12 vertices") && strstr(err, "or --fill-ngons") &&
              leftovers() == 0, "12-gon caps, no option: %d '%s'", rc, err);
    rc = run_sh("$Q cyl12.obj --subdivide 1 -o out.step", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "2 of its faces have 12 or more sides; --fill-ngons fills them with quads"),
          "12-gon caps, --subdivide 1: %d '%s'", rc, err);
    rc = run_sh("rm -f out.step && $Q cyl12.obj --fill-ngons -o cyl12.json", err, sizeof err);
    char *js = report("cyl12.json");
    CHECK(rc == 0 && strstr(err, "66 faces (2 faces of 5 or more sides filled with 42 quads)") && js &&
              jnum(js, "filled_faces") == 2 && jnum(js, "fill_quads") == 42 && strstr(js, "\"tol_met\": true") &&
              strstr(js, "\"g1_met\": true") && strstr(js, "\"g2_met\": true"),
          "12-gon caps, --fill-ngons: %d '%s' %s", rc, err, js ? js : "(no report)");
    free(js);
    rc = run_sh("$Q star.obj --fill-ngons -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "star.obj:61: face 24 (12 vertices) cannot be filled") && leftovers() == 0,
          "star-shaped cap, --fill-ngons: %d '%s'", rc, err);
    /* a pentagon with no other odd polygon to pair with: the error says why the fill left it */
    write_file("pent.obj", "v 0 0 0\nv 1 0 0\nv 1.3 0.8 0\nv 0.5 1.4 0\nv -0.3 0.8 0\nf 1 2 3 4 5\n");
    rc = run_sh("$Q pent.obj --fill-ngons -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "pent.obj:6: face 0 has 5 vertices") && strstr(err, "found none free for this one") &&
              leftovers() == 0, "lone pentagon, --fill-ngons: %d '%s'", rc, err);
}

static void tolerances(void)
{
    char err[4096];
    write_file("cube.obj", "v -5 -5 -5\nv 5 -5 -5\nv -5 5 -5\nv 5 5 -5\nv -5 -5 5\nv 5 -5 5\nv -5 5 5\nv 5 5 5\n"
                           "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 2 4 8 6\nf 4 3 7 8\nf 3 1 5 7\n");
    double diag = 10 * sqrt(3.0);
    /* the default targets: 0.01 degrees and 1 % at tol <= 1e-5, loosened in proportion above, capped
     * at 0.5 degrees and 10 % (fit_policy.h); the summary states them */
    static const struct { const char *tol; double g1, g2; } D[] = {{"1e-5", 0.01, 0.01}, {"3e-5", 0.03, 0.03},
                                                                    {"1e-4", 0.1, 0.1}, {"1e-3", 0.5, 0.1}};
    int rc = 0;
    char *d = NULL;
    for (int i = 0; i < 4; i++) {
        char cmd[128];
        snprintf(cmd, sizeof cmd, "$Q cube.obj --tol %s -o t0.json", D[i].tol);
        rc = run_sh(cmd, err, sizeof err);
        free(d);
        d = report("t0.json");
        CHECK(rc == 0 && fabs(jnum(d, "g1_tol_deg") - D[i].g1) < 1e-12 && fabs(jnum(d, "g2_tol_rel") - D[i].g2) < 1e-12 &&
                  strstr(d, "\"g1_met\": true") && strstr(d, "\"g2_met\": true") && strstr(err, "(target "),
              "--tol %s: default targets %g deg, %g in the report (expected %g, %g); '%s'", D[i].tol, jnum(d, "g1_tol_deg"),
              jnum(d, "g2_tol_rel"), D[i].g1, D[i].g2, err);
        CHECK(jnum(d, "folded_faces") == 0 && jnum(d, "first_folded_face") == -1, "cube: folds in the report");
    }
    CHECK(rc == 0 && strstr(err, "max dev ") && strstr(err, "diag = ") && (strstr(err, " nm") || strstr(err, " um") ||
          strstr(err, " \xc2\xb5m") || strstr(err, " mm")) && (strstr(err, " deg") || strstr(err, "\xc2\xb0")) &&
          strstr(err, " %"), "summary without units: '%s'", err);
    CHECK(fabs(jnum(d, "tol_abs") - 1e-3 * diag) < 1e-9, "tol_abs in the report: %g", jnum(d, "tol_abs"));
    /* the strict targets asked for explicitly at --tol 1e-3: the reference for the span counts below */
    free(d);
    rc = run_sh("$Q cube.obj -q --tol 1e-3 --angle-tol 0.01 --curvature-tol 0.01 -o t0.json", err, sizeof err);
    d = report("t0.json");
    CHECK(rc == 0 && jnum(d, "g1_tol_deg") == 0.01 && jnum(d, "g2_tol_rel") == 0.01 && strstr(d, "\"g1_met\": true"),
          "--angle-tol 0.01 at --tol 1e-3: %g %g", jnum(d, "g1_tol_deg"), jnum(d, "g2_tol_rel"));
    /* loose targets: accepted above 0.01 degrees, with fewer spans */
    rc = run_sh("$Q cube.obj -q --tol 1e-3 --angle-tol 1 --curvature-tol 0.5 -o t1.json", err, sizeof err);
    char *l = report("t1.json");
    CHECK(rc == 0 && jnum(l, "g1_tol_deg") == 1 && jnum(l, "g2_tol_rel") == 0.5 && strstr(l, "\"g1_met\": true") &&
          jnum(l, "g1_max_deg") > 0.01 && jnum(l, "g1_max_deg") <= 1 && jnum(l, "g2_max_rel") <= 0.5 &&
          jnum(l, "edge_spans_max") < jnum(d, "edge_spans_max"),
          "--angle-tol 1: G1 %g deg, %g spans per edge curve (0.01 deg: %g)", jnum(l, "g1_max_deg"), jnum(l, "edge_spans_max"),
          jnum(d, "edge_spans_max"));
    /* tight targets: met, with more spans */
    rc = run_sh("$Q cube.obj -q --tol 1e-3 --angle-tol 0.001 --curvature-tol 0.001 -o t2.json", err, sizeof err);
    char *t = report("t2.json");
    CHECK(rc == 0 && strstr(t, "\"g1_met\": true") && strstr(t, "\"g2_met\": true") && jnum(t, "g1_max_deg") <= 0.001 &&
          jnum(t, "g2_max_rel") <= 0.001 && jnum(t, "edge_spans_max") > jnum(d, "edge_spans_max"),
          "--angle-tol 0.001: G1 %g, G2 %g, %g spans per edge curve", jnum(t, "g1_max_deg"), jnum(t, "g2_max_rel"),
          jnum(t, "edge_spans_max"));
    free(d);
    free(l);
    free(t);
    /* G1 mode with G1 patches: every edge of the cube glued by polynomials (stop 41), so the fit is
     * exactly G1 with one span per patch, and the report counts the edges */
    rc = run_sh("$Q cube.obj -q --ev-patch g1 --continuity g1 -o t6.json", err, sizeof err);
    char *p6 = report("t6.json");
    CHECK(rc == 0 && jnum(p6, "polynomial_edges") == 12 && jnum(p6, "g1_max_deg") <= 1e-6 && jnum(p6, "max_dev_rel") <= 1e-12 &&
              jnum(p6, "within_rounding") == 12,
          "G1 mode, polynomial gluing: %g polynomial edges, G1 %g deg, deviation %g, %g edges within rounding",
          jnum(p6, "polynomial_edges"), jnum(p6, "g1_max_deg"), jnum(p6, "max_dev_rel"), jnum(p6, "within_rounding"));
    free(p6);
    /* the exact conversion of the Catmull-Clark approximations counts them too (until stop 43 it
     * reported 0 whatever it measured): acc-g1 is G1 on every edge, acc3 at no edge of the cube, every
     * one of whose faces touches an extraordinary vertex */
    rc = run_sh("$Q cube.obj -q --surface acc-g1 -o t8.json", err, sizeof err);
    char *a8 = report("t8.json");
    CHECK(rc == 0 && jnum(a8, "interior_edges") > 0 && jnum(a8, "within_rounding") == jnum(a8, "interior_edges") &&
              jnum(a8, "g1_max_deg") <= 1e-6,
          "acc-g1: %g of %g edges within rounding, G1 %g deg", jnum(a8, "within_rounding"), jnum(a8, "interior_edges"),
          jnum(a8, "g1_max_deg"));
    free(a8);
    rc = run_sh("$Q cube.obj -q --surface acc3 -o t9.json", err, sizeof err);
    char *a9 = report("t9.json");
    CHECK(rc == 0 && jnum(a9, "within_rounding") == 0 && jnum(a9, "g1_max_deg") > 1,
          "acc3: %g edges within rounding, G1 %g deg", jnum(a9, "within_rounding"), jnum(a9, "g1_max_deg"));
    free(a9);
    rc = run_sh("$Q cube.obj --ev-gluing cubic -o t7.json", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "--ev-gluing: unknown 'cubic' (expected auto, polynomial or smoothstep)"), "--ev-gluing cubic: %d '%s'", rc, err);
    rc = run_sh("$Q cube.obj --surface acc-g1 --ev-gluing smoothstep -o t7.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "--ev-gluing is ignored with --surface acc-g1"), "--ev-gluing with acc-g1: %d '%s'", rc, err);
    /* the gluing choice (G2 patches): the cube's one region ripples less with the smoothsteps (0.93
     * against 1.52 per extraordinary diagonal, and bends less), so the default keeps them there and says
     * so in the report; --ev-gluing polynomial keeps the polynomials, smoothstep gives the same surface
     * as the default, with no choice made (until stop 55 the option was said to be ignored with G2
     * patches, and was not) */
    const char *gl[3] = {"", "--ev-gluing polynomial", "--ev-gluing smoothstep"};
    double glv[3][3];
    for (int k = 0; k < 3; k++) {
        char cmd[160];
        snprintf(cmd, sizeof cmd, "$Q cube.obj -q %s -o t7.json -o t7.step", gl[k]);
        rc = run_sh(cmd, err, sizeof err);
        char *a7 = report("t7.json");
        glv[k][0] = rc == 0 ? jnum(a7, "gluing_regions") : -1, glv[k][1] = jnum(a7, "smoothstep_regions"), glv[k][2] = jnum(a7, "polynomial_edges");
        CHECK(rc == 0 && !strstr(err, "warning"), "cube %s: %d '%s'", gl[k], rc, err);
        free(a7);
    }
    CHECK(glv[0][0] == 1 && glv[0][1] == 1 && glv[0][2] == 0, "default: %g regions, %g smoothstep, %g polynomial edges", glv[0][0], glv[0][1], glv[0][2]);
    CHECK(glv[1][0] == 0 && glv[1][1] == 0 && glv[1][2] == 12, "polynomial: %g regions, %g smoothstep, %g polynomial edges", glv[1][0], glv[1][1], glv[1][2]);
    CHECK(glv[2][0] == 0 && glv[2][1] == 0 && glv[2][2] == 0, "smoothstep: %g regions, %g smoothstep, %g polynomial edges", glv[2][0], glv[2][1], glv[2][2]);
    /* targets the span cap cannot reach: the warning names the edge with the figures of the continuity
     * the fit imposes — in G1 mode the normal jump alone (until stop 40 it listed a curvature target
     * there too); the smoothsteps' gluing, least squares in the fit, since polynomial gluing is exact */
    rc = run_sh("$Q cube.obj --ev-patch g1 --continuity g1 --ev-gluing smoothstep --tol 1e-2 --max-spans 2 --angle-tol 1e-5 -o t5.json", err,
                sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: continuity target not met: edge ") && strstr(err, "(target 1e-05 deg; the construction's own: ") &&
              !strstr(err, "curvature jump") && !strstr(err, "G2 "),
          "G1 target missed, G1 mode: %d '%s'", rc, err);
    rc = run_sh("$Q cube.obj --tol 1e-2 --max-spans 2 --angle-tol 1e-5 --curvature-tol 1e-5 -o t5.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "warning: continuity target not met: edge ") && strstr(err, "curvature jump") &&
              strstr(err, "(targets 1e-05 deg, 1e-05; the construction's own: "),
          "continuity targets missed, G2 mode: %d '%s'", rc, err);
    /* --tol-abs in model units: 0.01 mm on the 17.3 mm diagonal */
    rc = run_sh("$Q cube.obj -q --tol-abs 0.01 -o t3.json", err, sizeof err);
    char *a = report("t3.json");
    CHECK(rc == 0 && fabs(jnum(a, "tol") - 0.01 / diag) < 1e-15 && fabs(jnum(a, "tol_abs") - 0.01) < 1e-9 &&
          jnum(a, "max_dev_rel") * diag <= 0.01, "--tol-abs 0.01: tol %.17g (want %.17g), deviation %g mm",
          jnum(a, "tol"), 0.01 / diag, jnum(a, "max_dev_rel") * diag);
    free(a);
    /* a tolerance the span cap cannot meet: exit 1, the face named with its line, the file once */
    rc = run_sh("$Q cube.obj --max-spans 1 --tol 1e-8 -o out.step", err, sizeof err);
    {
        /* whichever face deviates most (the cube's faces are alike up to rounding), its line: faces start at line 9 */
        const char *p = strstr(err, "quad2nurbs: fit: cube.obj:");
        int line = -1, face = -1;
        if (p) sscanf(p, "quad2nurbs: fit: cube.obj:%d: face %d: deviation", &line, &face);
        CHECK(rc == 1 && face >= 0 && face < 6 && line == 9 + face && strstr(err, "(max_spans 1)") && leftovers() == 0,
              "tolerance beyond the span cap: %d '%s'", rc, err);
    }
    rc = run_sh("$Q cube.obj --tol-abs 5 -o t4.json", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "--tol-abs 5 is 0.289 times the bounding-box diagonal"), "--tol-abs too large: '%s'", err);
    /* an edge shorter than the fit tolerance makes a nearly degenerate face whose patch spikes: a 3 x 3
     * grid (diagonal 3 sqrt 2 + a little) whose vertex (1, 0) is moved to 2e-5 from (0, 0).  At the
     * default tolerance (4.25e-5 absolute) the fit fails, and the message names that edge first; at
     * --tol 1e-2 the fit meets its tolerance (such an edge is not refused: rook --subdivide 1 at --tol
     * 1e-3 has edges of 7.5e-4 of its diagonal, and OCCT imports its file as it is) */
    char grid[1024] = "", *g = grid;
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++) {
            double x = i == 1 && j == 0 ? 2e-5 : (double)i;
            g += sprintf(g, "v %.17g %d %.17g\n", x, j, 0.1 * sin(x + 2.0 * j));
        }
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++)
            g += sprintf(g, "f %d %d %d %d\n", 4 * j + i + 1, 4 * j + i + 2, 4 * j + i + 6, 4 * j + i + 5);
    write_file("short.obj", grid);
    rc = run_sh("$Q short.obj -o out.step -o out.json", err, sizeof err);
    CHECK(rc == 1 && strstr(err, "quad2nurbs: fit: short.obj:17: face 0 has an edge 0-1 of length 2.01e-05 (") &&
              strstr(err, "shorter than the fit tolerance 4.2") && strstr(err, "; then short.obj:") && leftovers() == 0,
          "edge shorter than the tolerance: %d '%s'", rc, err);
    rc = run_sh("$Q short.obj --tol 1e-2 -q -o t6.json", err, sizeof err);
    CHECK(rc == 0, "edge shorter than a loose tolerance: %d '%s'", rc, err);
    rc = run_sh("$Q short.obj -o out.obj", err, sizeof err); /* no fit: the tessellation is written */
    CHECK(rc == 0, "short edge, tessellation only: %d '%s'", rc, err);
    char op[512];
    snprintf(op, sizeof op, "%s/out.obj", dir);
    remove(op);
}

/* An n x m torus (name.obj), radii 3 and 1. */
static void write_torus_nm(const char *name, int n, int m)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    for (int i = 0; f && i < n; i++)
        for (int j = 0; j < m; j++) {
            double a = 2 * M_PI * i / n, b = 2 * M_PI * j / m;
            fprintf(f, "v %.17g %.17g %.17g\n", (3 + cos(b)) * cos(a), (3 + cos(b)) * sin(a), sin(b));
        }
    for (int i = 0; f && i < n; i++)
        for (int j = 0; j < m; j++)
            fprintf(f, "f %d %d %d %d\n", i * m + j + 1, (i + 1) % n * m + j + 1, (i + 1) % n * m + (j + 1) % m + 1,
                    i * m + (j + 1) % m + 1);
    if (f) fclose(f);
}

/* A 60 x 40 torus (a fit of well under a second), and a 200 x 120 one whose fit lasts long enough
 * (~5 s here) for the progress reports, which start after half a second, to show a fit round on any
 * machine the tests run on. */
static void write_torus(void)
{
    write_torus_nm("t2400.obj", 60, 40);
    write_torus_nm("t24000.obj", 200, 120);
}

/* Issue 13 item 3: progress on a terminal, as lines with --progress, never with -q. */
static void progress(void)
{
    if (access("/usr/bin/script", X_OK) != 0) { SKIP("script(1) absent: progress on a terminal not checked"); return; }
    char p[512], err[4096];
    int rc = run_sh("script -qc \"$Q t24000.obj -o p.json\" /dev/null > tty.txt", err, sizeof err);
    snprintf(p, sizeof p, "%s/tty.txt", dir);
    char *tty = chk_slurp(p, NULL);
    CHECK(rc == 0 && tty && strstr(tty, "\rquad2nurbs: fit round ") && strstr(tty, "t24000.obj: 24000 faces"),
          "progress on a pseudo-terminal: '%.300s'", tty ? tty : "");
    free(tty);
    rc = run_sh("script -qc \"$Q -q t2400.obj -o p.json\" /dev/null > tty.txt", err, sizeof err);
    tty = chk_slurp(p, NULL);
    CHECK(rc == 0 && tty && tty[0] == 0, "-q on a terminal prints nothing: '%.200s'", tty ? tty : "");
    free(tty);
    rc = run_sh("$Q --progress t24000.obj -o p.json", err, sizeof err);
    CHECK(rc == 0 && strstr(err, "quad2nurbs: fit round ") && !strchr(err, '\r'), "--progress as lines: '%.300s'", err);
    rc = run_sh("$Q t2400.obj -o p.json", err, sizeof err);
    CHECK(rc == 0 && !strstr(err, "fit round") && strstr(err, "2400 faces"), "no progress in a pipe without --progress: "
          "'%.300s'", err);
}

/* Issue 16 item 8: runs estimated above the memory limit, or above the free disk space, are
 * refused before the work starts. */
static void resources(void)
{
    char err[4096];
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    int rc = run_sh("$Q quad.obj --tess 10000 --max-memory 1G -o out.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "would need about 7.21 GB of memory") && strstr(err, "more than the limit 1.07 GB") &&
          leftovers() == 0, "--tess 10000 refused: %d '%s'", rc, err);
    rc = run_sh("$Q t2400.obj --subdivide 6 --max-memory 4G -o out.step", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "9830400 faces after --subdivide 6") && leftovers() == 0, "--subdivide 6 refused: %d '%s'",
          rc, err);
    rc = run_sh("$Q quad.obj --max-memory 10K -o out.obj", err, sizeof err);
    CHECK(rc == 2 && strstr(err, "more than the limit 10.2 kB (--max-memory)"), "--max-memory 10K: %d '%s'", rc, err);
    rc = run_sh("$Q quad.obj -q --max-memory 0 -o nolimit.obj", err, sizeof err);
    CHECK(rc == 0, "--max-memory 0 is no limit: %d '%s'", rc, err);
    clock_gettime(CLOCK_MONOTONIC, &b);
    CHECK(b.tv_sec - a.tv_sec < 20, "refusals took %ld s: the work started", (long)(b.tv_sec - a.tv_sec));
    /* The fit's peak memory on the 2400-face torus (one span per patch) stays near the estimate
     * (8 MB + 2400 x (0.56 + 3.15 + 5.75) KB = 30.7 MB): its side caches once grew in blocks of 32
     * parameters per side, 74 MB here (27 KB per face; 2.4 GB for a 90 000-face torus); before the
     * construction kept its grids as indices and the fit its per-span maxima, 36 MB. */
    char exe[1024], tor[512];
    if (!realpath(EXE, exe)) snprintf(exe, sizeof exe, "%s", EXE);
    snprintf(tor, sizeof tor, "%s/t2400.obj", dir);
    pid_t pid = fork();
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stderr)) _exit(126);
        execl(exe, exe, "-q", tor, "-o", chk_scratch("mem.json"), (char *)NULL);
        _exit(127);
    }
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
#if defined(__SANITIZE_ADDRESS__)
    /* AddressSanitizer's shadow memory and quarantine triple the resident set: only the exit */
    CHECK(pid > 0 && wait4(pid, &status, 0, &ru) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0,
          "fit of 2400 faces under ASan: exit %d", WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    SKIP("fit of 2400 faces: peak resident %ld KB not bounded under AddressSanitizer", ru.ru_maxrss);
#else
    CHECK(pid > 0 && wait4(pid, &status, 0, &ru) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0 &&
              ru.ru_maxrss < 34 * 1024,
          "fit of 2400 faces: peak resident %ld KB (estimate ~31 MB, bound 34 MB), exit %d", ru.ru_maxrss,
          WIFEXITED(status) ? WEXITSTATUS(status) : -1);
#endif
    /* Extraordinary regions cost ~100 times a regular face (the fair construction's forms and sparse
     * factor, the fit's refined patches): the estimate counts them.  A sphere of 80 triangles,
     * subdivided once (240 quads, every one in an extraordinary region): the estimate ignored them
     * (10.3 MB against 75 MB measured; now 48.7 MB) until 2026-12. */
    {
        char sph[512];
        snprintf(sph, sizeof sph, "%s/sphere80.obj", dir);
        FILE *f = fopen(sph, "w");
        static const int ico[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                       {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                       {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
        double t = (1 + sqrt(5.0)) / 2, P[42][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                                     {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
        int np = 12, mid[12][12];
        memset(mid, -1, sizeof mid);
        for (int k = 0; k < 20; k++) /* one split: a vertex at the middle of every edge */
            for (int e = 0; e < 3; e++) {
                int a = ico[k][e], b = ico[k][(e + 1) % 3];
                if (mid[a][b] >= 0) continue;
                for (int c = 0; c < 3; c++) P[np][c] = 0.5 * (P[a][c] + P[b][c]);
                mid[a][b] = mid[b][a] = np++;
            }
        for (int v = 0; f && v < np; v++) {
            double r = sqrt(P[v][0] * P[v][0] + P[v][1] * P[v][1] + P[v][2] * P[v][2]);
            fprintf(f, "v %.17g %.17g %.17g\n", P[v][0] / r, P[v][1] / r, P[v][2] / r);
        }
        for (int k = 0; f && k < 20; k++) {
            int a = ico[k][0], b = ico[k][1], c = ico[k][2], ab = mid[a][b] + 1, bc = mid[b][c] + 1, ca = mid[c][a] + 1;
            fprintf(f, "f %d %d %d\nf %d %d %d\nf %d %d %d\nf %d %d %d\n", a + 1, ab, ca, b + 1, bc, ab, c + 1, ca, bc, ab, bc, ca);
        }
        if (f) fclose(f);
        rc = run_sh("$Q sphere80.obj --subdivide 1 --max-memory 1K -o ev.json", err, sizeof err);
        const char *at = strstr(err, "would need about ");
        double est = at ? atof(at + 17) : 0;
        if (at && strstr(at, " MB")) est *= 1e6;
        pid = fork();
        if (pid == 0) {
            if (!freopen("/dev/null", "w", stderr)) _exit(126);
            execl(exe, exe, "-q", sph, "--subdivide", "1", "-o", chk_scratch("ev.json"), (char *)NULL);
            _exit(127);
        }
        memset(&ru, 0, sizeof ru);
        int ok = pid > 0 && wait4(pid, &status, 0, &ru) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
        double rss = 1024.0 * (double)ru.ru_maxrss;
        printf("240 extraordinary faces: estimate %.1f MB, peak resident %.1f MB\n", est / 1e6, rss / 1e6);
#if defined(__SANITIZE_ADDRESS__)
        CHECK(rc == 2 && est > 0 && ok, "240 extraordinary faces under ASan: estimate '%s', exit %d", err, ok);
        SKIP("240 extraordinary faces: peak resident %.0f MB not compared with the estimate under AddressSanitizer", rss / 1e6);
#else
        CHECK(rc == 2 && ok && est >= 0.5 * rss && est <= 1.5 * rss,
              "240 extraordinary faces: estimate %.1f MB against %.1f MB measured ('%.200s')", est / 1e6, rss / 1e6, err);
#endif
    }
    /* the tessellation file would not fit on the disk: 2400 patches of 10000 x 10000 points (30 TB) */
    struct statvfs vf;
    if (statvfs(dir, &vf) == 0 && (double)vf.f_bavail * vf.f_frsize < 3e13) {
        rc = run_sh("$Q t2400.obj --tess 10000 --max-memory 0 -o out.obj", err, sizeof err);
        CHECK(rc == 1 && strstr(err, "out.obj: the output would take about") && strstr(err, " TB, only") && strstr(err, "free on its file system") &&
              leftovers() == 0, "output larger than the free space refused: %d '%s'", rc, err);
    } else {
        SKIP("more than 30 TB free: the free-space refusal not checked");
    }
}

/* A BLAS that is not safe for concurrent calls (OpenBLAS' serial build, README "Dependencies") is
 * found at run time and the run drops to one thread, saying so: simulated by preloading a library
 * that answers openblas_get_parallel() = 0, as that build does.  The report's "threads" says what
 * the fit used; without the stand-in the same command runs on two threads and says nothing.  Without
 * --threads the run takes the processors it may use, one under the stand-in (silently). */
static void test_serial_blas(void)
{
    char err[2048];
    write_file("blas0.c", "int openblas_get_parallel(void) { return 0; }\n");
    if (run_sh("cc -shared -fPIC -o blas0.so blas0.c", err, sizeof err) != 0) {
        SKIP("no C compiler for the serial-BLAS stand-in: %s", err);
        return;
    }
    write_torus_nm("t384.obj", 24, 16);
    /* (an ASan build checks that its runtime comes first; the stand-in may come before it) */
    int rc = run_sh("ASAN_OPTIONS=\"$ASAN_OPTIONS:verify_asan_link_order=0\" LD_PRELOAD=$PWD/blas0.so $Q t384.obj --threads 2 -o s1.json",
                    err, sizeof err);
    char *js = report("s1.json");
    CHECK(rc == 0 && strstr(err, "OpenBLAS' serial build") && strstr(err, "run on 1 thread") && jnum(js, "threads") == 1,
          "serial OpenBLAS: the run drops to 1 thread (report %g) and warns: %d '%s'", jnum(js, "threads"), rc, err);
    free(js);
    rc = run_sh("$Q t384.obj --threads 2 -o s2.json", err, sizeof err);
    js = report("s2.json");
    CHECK(rc == 0 && !strstr(err, "OpenBLAS") && jnum(js, "threads") == 2, "any other BLAS: 2 threads (report %g), no warning: %d '%s'",
          jnum(js, "threads"), rc, err);
    free(js);
    /* without --threads: the processors the process may use (coreutils' nproc, which honours the
     * CPU affinity, is the reference; at most 64), one under taskset to one processor; under the
     * serial BLAS one, without a warning (nothing was asked for) */
    int ncpu = 0;
    if (run_sh("nproc > nproc.txt", err, sizeof err) == 0) {
        char *np = report("nproc.txt");
        ncpu = np ? atoi(np) : 0;
        free(np);
    }
    if (ncpu > 64) ncpu = 64;
    rc = run_sh("$Q t384.obj -o s3.json", err, sizeof err);
    js = report("s3.json");
    CHECK(ncpu >= 1 && rc == 0 && jnum(js, "threads") == ncpu,
          "default threads: report %g, nproc %d: %d '%s'", jnum(js, "threads"), ncpu, rc, err);
    free(js);
    if (run_sh("taskset -c 0 true", err, sizeof err) == 0) {
        rc = run_sh("taskset -c 0 $Q t384.obj -o s4.json", err, sizeof err);
        js = report("s4.json");
        CHECK(rc == 0 && jnum(js, "threads") == 1, "default threads on one processor (taskset): report %g: %d '%s'", jnum(js, "threads"),
              rc, err);
        free(js);
    } else
        SKIP("no taskset: the default thread count under a one-processor affinity not checked");
    rc = run_sh("ASAN_OPTIONS=\"$ASAN_OPTIONS:verify_asan_link_order=0\" LD_PRELOAD=$PWD/blas0.so $Q t384.obj -o s5.json", err, sizeof err);
    js = report("s5.json");
    CHECK(rc == 0 && !strstr(err, "OpenBLAS") && jnum(js, "threads") == 1, "serial OpenBLAS, no --threads: 1 thread (report %g), no warning: %d '%s'",
          jnum(js, "threads"), rc, err);
    free(js);
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
    pair_triangles();
    fill_ngons();
    test_serial_blas();
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
    CHECK(!strstr(err, "nearly a triangle"), "dart: not a near-triangle: %s", err);
    /* a near-triangle quad (one edge 1/1000 of the others, a regular torus): the fold warning names
     * the short edge and the remedies (docs/mesh.md) */
    {
        q2n_mesh *tm = mg_torus(20, 10, 2.0, 0.7, 0, 0, 1);
        q2n_error e;
        char tp[600];
        snprintf(tp, sizeof tp, "%s/neartri.obj", dir);
        if (tm) {
            int a = tm->face_vert[tm->face_start[52]], b = tm->face_vert[tm->face_start[52] + 1];
            for (int c = 0; c < 3; c++) tm->pos[3 * a + c] = tm->pos[3 * b + c] + 1e-3 * (tm->pos[3 * a + c] - tm->pos[3 * b + c]);
        }
        CHECK(tm && q2n_mesh_write_obj(tm, tp, &e) == Q2N_OK, "near-triangle torus: not written");
        q2n_mesh_free(tm);
        snprintf(args, sizeof args, "sample --grid 2 --frame off %s", tp); /* built in its isotropic frame it does not fold */
        CHECK(run(args, err, sizeof err, NULL) == 0 && strstr(err, "the surface folds over") &&
                  strstr(err, "the face is nearly a triangle, its edge") && strstr(err, "--limit-points"),
              "near-triangle torus: %s", err);
        snprintf(args, sizeof args, "sample --grid 2 --frame off --limit-points %s", tp);
        CHECK(run(args, err, sizeof err, NULL) == 0 && !strstr(err, "folds over"), "near-triangle torus, --limit-points: %s", err);
    }
    /* and counted in the fit report, under the construction */
    snprintf(args, sizeof args, "-q %s/dart.obj -o %s/dart.json", dir, dir);
    char *dj = run(args, err, sizeof err, NULL) == 0 ? report("dart.json") : NULL;
    CHECK(dj && jnum(dj, "folded_faces") >= 1 && strstr(dj, "\"first_folded_face\": 4,"), "dart report: %s",
          dj ? dj : err);
    free(dj);
    const char *torus = chk_shared_mesh("osd_catmark_torus.obj");
    if (torus) {
        snprintf(args, sizeof args, "sample --grid 4 %s", torus);
        CHECK(run(args, err, sizeof err, &lines) == 0 && lines == 32 * 16, "torus sample lines %ld", lines);
    }
    write_file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
    option_errors();
    messages();
    option_warnings();
    tolerances();
    limit_points();
    keep_flat();
    fold_fallback();
    write_torus();
    progress();
    resources();
    snprintf(args, sizeof args, "rm -rf %s", dir);
    if (system(args)) {}
    CHECK_DONE("test_cli");
}
