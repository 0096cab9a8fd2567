/* test_api.c — the public API (include/quad2nurbs.h): open, evaluate, write, errors.  The
 * evaluation is compared with the mesh vertices it must interpolate (augmented surface) and with
 * finite differences of itself for the derivatives. */
#include "check.h"
#include "quad2nurbs.h"

/* data/demo_torus.obj: patch CORNER_PATCH has the file's first vertex at (u, v) = (0, 0) (its
 * face's first corner); FD_PATCH is any other patch, for the finite difference. */
enum { CORNER_PATCH = 0, FD_PATCH = 5 };

int main(void)
{
    char err[512];
    q2n_model *m = NULL;
    CHECK(strcmp(q2n_version(), QUAD2NURBS_VERSION) == 0, "version");
    CHECK(q2n_open("/nonexistent.obj", NULL, &m, err, sizeof err) != 0 && strstr(err, "nonexistent"),
          "missing file reported: %s", err);
    q2n_options bad = {0};
    bad.surface = "nurbs-magic";
    CHECK(q2n_open("data/demo_torus.obj", &bad, &m, err, sizeof err) != 0 && strstr(err, "nurbs-magic"),
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
    q2n_close(m);
    q2n_close(NULL);
    CHECK_DONE("test_api");
}
