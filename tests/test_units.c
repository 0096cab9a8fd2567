/* test_units.c — real units and scale, end to end (issue 13 items 6 and 7):
 *   - a 10 mm cube (mesh vertices at +-5) written with --units in --scale 1/25.4 (and m, cm, ft with
 *     their factors) imports into FreeCAD / OpenCASCADE, which converts to millimetres, with its
 *     vertices at +-5 mm and the same bounding box as the plain millimetre file, STEP and IGES;
 *   - --scale multiplies every output exactly: `sample --scale 2` is twice `sample`, the report's
 *     bounding-box diagonal and absolute tolerance are in the scaled unit; --tol-abs is in that
 *     unit too;
 *   - the files' dates come from SOURCE_DATE_EPOCH (IGES global 18 and 25, STEP FILE_NAME), from
 *     the clock otherwise, and a malformed value is refused.
 * The FreeCAD part skips (saying so) when FreeCAD's Python modules are absent. */
#define _GNU_SOURCE
#include <sys/wait.h>
#include <time.h>

#include "check.h"

static char dir[64], exe[1024];

static int sh(const char *fmt, const char *a, const char *b)
{
    char cmd[4096], inner[3500];
    snprintf(inner, sizeof inner, fmt, a, b);
    snprintf(cmd, sizeof cmd, "cd %s && %s", dir, inner);
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static double jnum(const char *js, const char *key)
{
    char k[64];
    snprintf(k, sizeof k, "\"%s\": ", key);
    const char *p = js ? strstr(js, k) : NULL;
    return p ? strtod(p + strlen(k), NULL) : NAN;
}

static const struct { const char *unit, *scale; double mm; } UNITS[] = {
    {"mm", "1", 1.0}, {"in", "0.03937007874015748", 25.4}, {"m", "0.001", 1000.0}, {"cm", "0.1", 10.0},
    {"ft", "0.0032808398950131233", 304.8}};
#define NUNITS (sizeof UNITS / sizeof UNITS[0])

static void write_files(void)
{
    char args[512];
    for (size_t i = 0; i < NUNITS; i++) {
        snprintf(args, sizeof args, "-q cube.obj --tol 1e-4 --units %s --scale %s -o u_%s.step -o u_%s.igs -o u_%s.json",
                 UNITS[i].unit, UNITS[i].scale, UNITS[i].unit, UNITS[i].unit, UNITS[i].unit);
        CHECK(sh("SOURCE_DATE_EPOCH=0 %s %s", exe, args) == 0, "run --units %s", UNITS[i].unit);
        char p[256];
        snprintf(p, sizeof p, "%s/u_%s.json", dir, UNITS[i].unit);
        char *js = chk_slurp(p, NULL);
        double diag = jnum(js, "bbox_diag"), want = 10.0 * sqrt(3.0) / UNITS[i].mm;
        CHECK(fabs(diag - want) <= 1e-12 * want, "%s: report diagonal %.17g, want %.17g", UNITS[i].unit, diag, want);
        CHECK(js && strstr(js, "\"units\": \"") && fabs(jnum(js, "tol_abs") - 1e-4 * want) <= 1e-9 * want,
              "%s: report units and tol_abs %g", UNITS[i].unit, jnum(js, "tol_abs"));
        free(js);
    }
}

/* FreeCAD: every file's vertices at +-5 mm and the bounding box of the millimetre file. */
static void freecad(void)
{
    if (system("/usr/bin/python3 -c \"import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD, Part\" "
               ">/dev/null 2>&1") != 0) {
        SKIP("FreeCAD Python modules absent: unit round trip through an importer not checked");
        return;
    }
    char py[256], out[256];
    snprintf(py, sizeof py, "%s/fc.py", dir);
    FILE *f = fopen(py, "w");
    if (!f) return;
    fputs("import sys\nsys.path.append('/usr/lib/freecad-python3/lib')\nimport FreeCAD, Part\n"
          "for name in sys.argv[1:]:\n"
          "    s = Part.read(name)\n"
          "    b = s.optimalBoundingBox()\n"
          "    m = max(max(abs(v.X), abs(v.Y), abs(v.Z)) for v in s.Vertexes)\n"
          "    print(name, len(s.Faces), len(s.Solids), '%.17g' % m, ' '.join('%.17g' % x for x in\n"
          "          (b.XMin, b.YMin, b.ZMin, b.XMax, b.YMax, b.ZMax)))\n", f);
    fclose(f);
    char files[1024] = "";
    for (size_t i = 0; i < NUNITS; i++)
        snprintf(files + strlen(files), sizeof files - strlen(files), " u_%s.step u_%s.igs", UNITS[i].unit, UNITS[i].unit);
    CHECK(sh("/usr/bin/python3 fc.py %s > fc.txt 2>/dev/null%s", files, "") == 0, "FreeCAD import script failed");
    snprintf(out, sizeof out, "%s/fc.txt", dir);
    f = fopen(out, "r");
    char name[64];
    int faces, solids, n = 0;
    double vmax, b[6], ref[6] = {0};
    while (f && fscanf(f, "%63s %d %d %lf %lf %lf %lf %lf %lf %lf", name, &faces, &solids, &vmax, &b[0], &b[1], &b[2], &b[3],
                       &b[4], &b[5]) == 10) {
        if (n++ == 0) memcpy(ref, b, sizeof ref);  /* u_mm.step comes first */
        CHECK(faces == 6 && solids == 1, "%s: %d faces, %d solids", name, faces, solids);
        CHECK(fabs(vmax - 5.0) <= 1e-9, "%s: vertices at %.17g mm, want 5", name, vmax);
        double d = 0;
        for (int c = 0; c < 6; c++) d = fmax(d, fabs(b[c] - ref[c]));
        CHECK(d <= 1e-9 && fabs(b[3] - b[0]) > 10.0, "%s: bounding box differs from the millimetre file's by %.3g mm "
              "(x extent %.6g)", name, d, b[3] - b[0]);
    }
    if (f) fclose(f);
    CHECK(n == 2 * (int)NUNITS, "FreeCAD read %d of %d files", n, 2 * (int)NUNITS);
}

static void scale_and_tolerance(void)
{
    CHECK(sh("%s sample --grid 3 cube.obj > s1.txt && %s sample --grid 3 --scale 2 cube.obj > s2.txt", exe, exe) == 0,
          "sample runs");
    char p[256];
    snprintf(p, sizeof p, "%s/s1.txt", dir);
    char *a = chk_slurp(p, NULL);
    snprintf(p, sizeof p, "%s/s2.txt", dir);
    char *b = chk_slurp(p, NULL);
    int lines = 0, exact = 1;
    for (char *x = a, *y = b; x && y && *x && *y; lines++) {
        double va[12], vb[12];
        int k = sscanf(x, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &va[0], &va[1], &va[2], &va[3], &va[4], &va[5],
                       &va[6], &va[7], &va[8], &va[9], &va[10], &va[11]);
        sscanf(y, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &vb[0], &vb[1], &vb[2], &vb[3], &vb[4], &vb[5], &vb[6],
               &vb[7], &vb[8], &vb[9], &vb[10], &vb[11]);
        for (int c = 0; c < k; c++) exact &= c < 3 ? va[c] == vb[c] : 2 * va[c] == vb[c];
        x = strchr(x, '\n');
        y = strchr(y, '\n');
        if (x) x++;
        if (y) y++;
    }
    CHECK(lines == 54 && exact, "sample --scale 2 is exactly twice sample (%d lines)", lines);
    free(a);
    free(b);
    /* --tol-abs in the scaled unit: 1e-4 in on a 10 mm cube written in inches */
    CHECK(sh("%s -q cube.obj --units in --scale 0.03937007874015748 --tol-abs 1e-4 -o t.json%s", exe, "") == 0, "--tol-abs");
    snprintf(p, sizeof p, "%s/t.json", dir);
    char *js = chk_slurp(p, NULL);
    double diag = 10.0 * sqrt(3.0) / 25.4;
    CHECK(fabs(jnum(js, "tol") - 1e-4 / diag) <= 1e-12 && fabs(jnum(js, "tol_abs") - 1e-4) <= 1e-9,
          "--tol-abs 1e-4: tol %.17g (want %.17g), tol_abs %g", jnum(js, "tol"), 1e-4 / diag, jnum(js, "tol_abs"));
    free(js);
}

static void dates(void)
{
    CHECK(sh("SOURCE_DATE_EPOCH=1700000000 %s -q cube.obj -o d.step -o d.igs%s", exe, "") == 0, "dated run");
    char p[256];
    snprintf(p, sizeof p, "%s/d.step", dir);
    char *s = chk_slurp(p, NULL);
    CHECK(s && strstr(s, "FILE_NAME('d','2023-11-14T22:13:20'"), "STEP time stamp from SOURCE_DATE_EPOCH");
    free(s);
    snprintf(p, sizeof p, "%s/d.igs", dir);
    s = chk_slurp(p, NULL);
    char g[800] = "";
    for (const char *q = s ? strchr(s, '\n') + 1 : NULL; q && q[72] == 'G'; q += 81) strncat(g, q, 72);
    const char *d1 = strstr(g, "15H20231114.221320");
    CHECK(d1 && strstr(d1 + 1, "15H20231114.221320"), "IGES global 18 and 25 from SOURCE_DATE_EPOCH: %s", g);
    free(s);
    /* without it: today (UTC) */
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    char today[16];
    strftime(today, sizeof today, "'%Y-%m-%d", &tm);
    CHECK(sh("env -u SOURCE_DATE_EPOCH %s -q cube.obj -o n.step%s", exe, "") == 0, "undated run");
    snprintf(p, sizeof p, "%s/n.step", dir);
    s = chk_slurp(p, NULL);
    CHECK(s && strstr(s, today), "STEP time stamp of today %s", today + 1);
    free(s);
    CHECK(sh("SOURCE_DATE_EPOCH=yesterday %s -q cube.obj -o x.step 2> err.txt%s", exe, "") == 2, "malformed SOURCE_DATE_EPOCH");
}

int main(void)
{
    if (access(chk_exe(), X_OK) != 0 || !realpath(chk_exe(), exe)) {
        CHECK(0, "%s not built", chk_exe());
        CHECK_DONE("test_units");
    }
    /* a folder in the scratch folder (relative to the repository, like the runner's) */
    if (chk_tmpdir(dir, sizeof dir, "units") != 0) { CHECK(0, "no scratch folder %s", dir); CHECK_DONE("test_units"); }
    char p[128];
    snprintf(p, sizeof p, "%s/cube.obj", dir);
    FILE *f = fopen(p, "w");
    if (f) {
        fputs("v -5 -5 -5\nv 5 -5 -5\nv -5 5 -5\nv 5 5 -5\nv -5 -5 5\nv 5 -5 5\nv -5 5 5\nv 5 5 5\n"
              "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 2 4 8 6\nf 4 3 7 8\nf 3 1 5 7\n", f);
        fclose(f);
    }
    write_files();
    freecad();
    scale_and_tolerance();
    dates();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd)) {}
    CHECK_DONE("test_units");
}
