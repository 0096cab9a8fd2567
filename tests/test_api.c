/* test_api.c — the public API (include/quad2nurbs.h): open, evaluate, write, errors.  The
 * evaluation is compared with the mesh vertices it must interpolate (augmented surface) and with
 * finite differences of itself for the derivatives; several outputs are all or nothing; the
 * progress callback sees every stage in order; scale, units, targets and the memory limit. */
#include "check.h"
#include "quad2nurbs.h"

/* data/demo_torus.obj: patch CORNER_PATCH has the file's first vertex at (u, v) = (0, 0) (its
 * face's first corner); FD_PATCH is any other patch, for the finite difference. */
enum { CORNER_PATCH = 0, FD_PATCH = 5 };

typedef struct progress_log {
    int n, stages_ok, order_ok;
    double last;
    char seen[256];
} progress_log;

static void on_progress(void *user, const q2n_progress *p)
{
    progress_log *l = user;
    if (!l->n) l->stages_ok = l->order_ok = 1;
    l->n++;
    if (!p->stage || !p->detail) l->stages_ok = 0;
    if (p->total < 0 || p->done < 0 || (p->total > 0 && p->done > p->total) || p->elapsed_s < l->last) l->order_ok = 0;
    l->last = p->elapsed_s;
    if (p->stage && !strstr(l->seen, p->stage) && strlen(l->seen) + strlen(p->stage) + 2 < sizeof l->seen) {
        strcat(l->seen, p->stage);
        strcat(l->seen, " ");
    }
}

/* Status strings, version macros and the string forms of every enum: each name parses back to
 * its value and appears in the list shown in messages; unknown names are refused. */
static void test_status_and_choices(void)
{
    CHECK(!strcmp(q2n_status_string(Q2N_OK), "ok") && !strcmp(q2n_status_string(Q2N_ERR_IO), "i/o error") &&
          !strcmp(q2n_status_string(Q2N_ERR_NUMERIC), "numeric failure") &&
          !strcmp(q2n_status_string((q2n_status)99), "unknown error"), "status strings");
    char v[32];
    snprintf(v, sizeof v, "%d.%d.%d", Q2N_VERSION_MAJOR, Q2N_VERSION_MINOR, Q2N_VERSION_PATCH);
    CHECK(!strcmp(v, QUAD2NURBS_VERSION) && !strcmp(q2n_version(), v), "version %s = macros %s", q2n_version(), v);
    int names = 0;
    for (int c = 0; c < Q2N_CHOICE_COUNT; c++) {
        const char *name;
        for (int i = 0; (name = q2n_choice_name((q2n_choice)c, i)); i++) {
            if (!strcmp(name, "default") || !strcmp(name, "none")) continue;
            int val = -1;
            CHECK(q2n_parse_choice((q2n_choice)c, name, &val) == Q2N_OK && val == i, "choice %d: '%s' parses to %d", c, name, val);
            CHECK(strstr(q2n_choice_list((q2n_choice)c), name) != NULL, "choice %d: '%s' in the list '%s'", c, name,
                  q2n_choice_list((q2n_choice)c));
            names++;
        }
        int val = 42;
        CHECK(q2n_parse_choice((q2n_choice)c, "nurbs-magic", &val) == Q2N_ERR_ARG && val == 42, "choice %d: unknown refused", c);
        CHECK(q2n_parse_choice((q2n_choice)c, "default", &val) == Q2N_ERR_ARG, "choice %d: 'default' is no name", c);
    }
    CHECK(names == 3 + 5 + 4 + 2 + 2 + 4 + 5 + 4 + 2 + 2 + 2, "%d names", names);
    int val = -1;
    CHECK(q2n_parse_choice(Q2N_CHOICE_SURFACE, "acc-g1", &val) == Q2N_OK && val == Q2N_SURFACE_ACC_G1, "acc-g1");
    CHECK(q2n_parse_choice(Q2N_CHOICE_CLASS, "d3c1p2s4", &val) == Q2N_OK && val == Q2N_CLASS_D3C1P2S4, "class any case");
    CHECK(q2n_parse_choice(Q2N_CHOICE_UNITS, "inch", &val) == Q2N_OK && val == Q2N_UNITS_IN, "units alias");
    CHECK(q2n_parse_choice(Q2N_CHOICE_FORMAT, "stp", &val) == Q2N_OK && val == Q2N_FORMAT_STEP, "format alias");
    CHECK(q2n_parse_choice(Q2N_CHOICE_COUNT, "g1", &val) == Q2N_ERR_ARG && q2n_choice_name(Q2N_CHOICE_COUNT, 0) == NULL &&
          q2n_choice_name(Q2N_CHOICE_SURFACE, 3) == NULL && q2n_choice_name(Q2N_CHOICE_SURFACE, -1) == NULL,
          "out of range");
}

int main(void)
{
    test_status_and_choices();
    char err[512];
    q2n_model *m = NULL;
    CHECK(strcmp(q2n_version(), QUAD2NURBS_VERSION) == 0, "version");
    CHECK(q2n_open("/nonexistent.obj", NULL, &m, err, sizeof err) != 0 && strstr(err, "nonexistent"),
          "missing file reported: %s", err);
    q2n_options bad = {0};
    bad.surface = (q2n_surface_method)7;
    CHECK(q2n_open("data/demo_torus.obj", &bad, &m, err, sizeof err) != 0 && strstr(err, "invalid surface 7"),
          "bad option reported: %s", err);
    CHECK(q2n_open("data/demo_torus.obj", NULL, &m, err, sizeof err) == 0, "open demo: %s", err);
    if (!m) CHECK_DONE("test_api");
    CHECK(q2n_patch_count(m) == 128, "128 patches");
    FILE *f = fopen("data/demo_torus.obj", "r");
    char line[256];
    double v0[3] = {0, 0, 0};
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "v %lf %lf %lf", &v0[0], &v0[1], &v0[2]) == 3) break; /* vertex 1 = v0 of face 0 */
    if (f) fclose(f);
    double p[9], a[9], b[9], h = 1e-6;
    CHECK(q2n_patch_covered(m, CORNER_PATCH) && q2n_patch_eval(m, CORNER_PATCH, 0, 0, p) == 0, "eval");
    CHECK_NEAR(p[0], v0[0], 1e-12, "corner x");
    CHECK_NEAR(p[1], v0[1], 1e-12, "corner y");
    CHECK_NEAR(p[2], v0[2], 1e-12, "corner z");
    q2n_patch_eval(m, FD_PATCH, 0.3 - h, 0.6, a);
    q2n_patch_eval(m, FD_PATCH, 0.3 + h, 0.6, b);
    q2n_patch_eval(m, FD_PATCH, 0.3, 0.6, p);
    CHECK_NEAR(p[3], (b[0] - a[0]) / (2 * h), 1e-6, "Su vs finite difference");
    const char *objp = chk_scratch("api.obj");
    remove(objp);
    CHECK(q2n_write(m, objp, err, sizeof err) == 0 && access(objp, R_OK) == 0, "write obj: %s", err);
    CHECK(q2n_write(m, chk_scratch("x.unknown"), err, sizeof err) != 0 && access(chk_scratch("x.unknown"), F_OK) != 0,
          "unknown extension refused, nothing written");
    remove(objp);
    /* several outputs: all or nothing; the same file twice is refused */
    char stepp[4096], igsp[4096];
    snprintf(stepp, sizeof stepp, "%s", chk_scratch("api.step"));
    snprintf(igsp, sizeof igsp, "%s", chk_scratch("api.igs"));
    const char *bad2[] = {stepp, "/nonexistent_dir/x.igs"};
    CHECK(q2n_write_all(m, bad2, 2, err, sizeof err) != 0 && strstr(err, "/nonexistent_dir/x.igs") && access(stepp, F_OK) != 0,
          "write_all with an unwritable second output leaves nothing: %s", err);
    const char *twice[] = {stepp, stepp};
    CHECK(q2n_write_all(m, twice, 2, err, sizeof err) != 0 && strstr(err, "twice"), "same output twice: %s", err);
    const char *good[] = {stepp, igsp};
    CHECK(q2n_write_all(m, good, 2, err, sizeof err) == 0 && access(stepp, R_OK) == 0 && access(igsp, R_OK) == 0,
          "write_all: %s", err);
    remove(stepp);
    remove(igsp);
    q2n_close(m);
    q2n_close(NULL);

    /* options of the public header: progress reports, scale, units, tolerances, memory limit */
    progress_log log = {0};
    q2n_options o = {0};
    o.progress = on_progress;
    o.progress_user = &log;
    o.scale = 2;
    o.units = Q2N_UNITS_IN;
    o.angle_tol_deg = 0.5;
    o.tol = 1e-4;
    q2n_model *s = NULL;
    CHECK(q2n_open("data/demo_torus.obj", &o, &s, err, sizeof err) == 0, "open with options: %s", err);
    if (s) {
        double a[9];
        q2n_patch_eval(s, CORNER_PATCH, 0, 0, a);
        CHECK(a[0] == 2 * v0[0] && a[1] == 2 * v0[1] && a[2] == 2 * v0[2], "scale 2 doubles the evaluation");
        char jp[4096];
        snprintf(jp, sizeof jp, "%s", chk_scratch("api_opts.json"));
        CHECK(q2n_write(s, jp, err, sizeof err) == 0, "fit and report: %s", err);
        FILE *jf = fopen(jp, "r");
        char js[4096] = "";
        if (jf) { size_t n = fread(js, 1, sizeof js - 1, jf); js[n] = 0; fclose(jf); }
        CHECK(strstr(js, "\"units\": \"in\"") && strstr(js, "\"g1_tol_deg\": 0.5") && strstr(js, "\"tol\": 0.0001"),
              "report shows units and targets: %.300s", js);
        unlink(jp);
        CHECK(log.n > 0 && log.stages_ok && log.order_ok, "progress: %d reports, stages %s, counts and times %s", log.n,
              log.stages_ok ? "ok" : "missing", log.order_ok ? "ok" : "wrong");
        CHECK(strstr(log.seen, "read") && strstr(log.seen, "build") && strstr(log.seen, "fit") && strstr(log.seen, "write"),
              "stages reported: %s", log.seen);
        q2n_close(s);
    }
    q2n_options bu = {0};
    bu.units = (q2n_units)9;
    CHECK(q2n_open("data/demo_torus.obj", &bu, &s, err, sizeof err) == Q2N_ERR_ARG && strstr(err, "invalid units 9"),
          "unknown unit: %s", err);
    q2n_options mm = {0};
    mm.max_memory = 1e5;
    CHECK(q2n_open("data/demo_torus.obj", &mm, &s, err, sizeof err) != 0 && strstr(err, "needs at least"),
          "memory limit: %s", err);
    CHECK_DONE("test_api");
}
