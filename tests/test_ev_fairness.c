/* test_ev_fairness.c — the default extraordinary-vertex construction judged as a CAD user judges
 * a surface (issue 11): no folds, little curvature oscillation, moderate bending energy, on every
 * shared mesh with extraordinary vertices and on the repository's own hard meshes, in G2 (the
 * default) and G1 mode.  The figures are those of ../shared/tools/fairness.py (which reads fitted
 * STEP files) computed on the construction itself (fairness.h; the fit follows it to 1e-5, and on
 * osd_catmark_pawn the two agree to 1e-3: 0.028 / 2.16 here, 0.027 / 2.16 from the fitted file).
 *
 * Bounds.  Folds: every face's Jacobian ratio (min / median |Xu x Xv|) at least 0.1, or at least
 * 3/4 of that of the bilinear quad through its vertices where the mesh face itself is more
 * degenerate (osd_catmark_righthanded's face 59 is a near-triangle quad, edges 0.0027 and
 * 0.044–0.068: bilinear 0.074, construction 0.097, 0.064 before the fan charts).  Ripple and energy: the targets — oscillation per EV-face
 * diagonal <= max(0.3, 1.5 x acc-g1's), bending energy on EV faces <= 3 x acc-g1's (acc-g1 figures
 * measured with fairness.py on the acc-g1 STEP files, docs/extraordinary.md) — where the
 * construction meets them; where it does not (docs/extraordinary.md explains each), the measured
 * value plus 30 % keeps it from getting worse, and the paper's construction's figure shows the gain. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/model.h"
#include "check.h"
#include "fairness.h"
#include "meshgen.h"
#include "param/param.h"
#include "patch/augmented.h"
#include "patch/ev_fair.h"
#include "patch/extraordinary.h"
#include "spline/spline.h"

typedef struct fcase {
    const char *file; /* shared mesh, or NULL with gen */
    int sub;          /* one Catmull–Clark step first (quad-dominant meshes) */
    double osc[2];    /* bounds on the mean EV-face oscillation: G2, G1 */
    double energy;    /* bound on the bending energy of the EV faces (G2) */
    int met;          /* the targets are met (else the bounds are regression guards) */
} fcase;

/* acc-g1 (fairness.py) osc / E_ev: cube 1.248 / 25.5, gregory_test0 0.044 / 0.997, gregory_test1
 * 0.541 / 20.8, gregory_test6 0.149 / 8.01, fvar_bound3 0.043 / 14.7, xord_boundary 0.202 / 12.6,
 * helmet 0.712 / 17.5, pawn 0.090 / 1.73, carpets (3, 5..8) 0.136, 0.139, 0.244, 0.259, 0.319,
 * cube_with_boundary 0.457 / 18.4, octtorus_hole 0.916 / 79.8, polycube 0.052 / 51.8,
 * righthanded 0.460 / 314.  fvar_bound3 was a regression guard (1.75 / 2.7 / 44.1) until stop 39:
 * its one-face rim corners (172 degrees) charted by their spatial angles instead of as right
 * angles, 1.34 / 2.08 / 14.9 -> 0.79 / 0.87 / 11.6, then their curvature held near its local
 * estimate in G2 (ev_policy.h EV_FAIR_RIDGE_CORNER), 0.79 -> 0.15: the ripple target met.  Its G1
 * patches glued by polynomials since stop 41 (exactly G1 in the fit; its rim's corners take the
 * twists, docs/extraordinary.md "Polynomial gluing of G1 patches"): G1 0.87 -> 1.43, the bound that
 * measure plus 30 %. */
static const fcase shared_cases[] = {
    {"osd_catmark_cube.obj", 0, {1.87, 1.87}, 76.5, 1},
    {"osd_catmark_gregory_test0.obj", 0, {0.3, 0.3}, 2.99, 1},
    {"osd_catmark_gregory_test1.obj", 0, {1.4, 1.6}, 62.4, 0},
    {"osd_catmark_gregory_test6.obj", 0, {1.26, 1.41}, 44.6, 0},
    {"osd_catmark_fvar_bound3.obj", 0, {0.3, 1.86}, 44.1, 1},
    {"osd_catmark_xord_boundary.obj", 0, {0.7, 0.7}, 37.8, 0},
    {"osd_catmark_helmet.obj", 0, {1.07, 1.07}, 52.5, 1},
    {"osd_catmark_pawn.obj", 0, {0.3, 0.3}, 5.19, 1},
    {"gismo_ev_valence3.obj", 0, {0.3, 0.3}, 1e-6, 1},
    {"gismo_ev_valence3_carpet.obj", 0, {0.8, 0.85}, 6.3, 0},
    {"gismo_ev_valence5_carpet.obj", 0, {2.0, 1.95}, 26.2, 0},
    {"gismo_ev_valence6_carpet.obj", 0, {1.74, 1.75}, 35.9, 0},
    {"gismo_ev_valence7_carpet.obj", 0, {1.42, 1.37}, 40.1, 0},
    {"gismo_ev_valence8_carpet.obj", 0, {1.02, 1.09}, 50.8, 0},
    {"gismo_cube_with_boundary.obj", 0, {0.69, 1.0}, 55.2, 1},
    {"gismo_octtorus_hole.obj", 0, {1.37, 1.37}, 239, 1},
    {"gismo_polycube.obj", 0, {0.5, 0.51}, 155, 0},
    {"osd_catmark_righthanded.obj", 0, {0.69, 0.69}, 942, 1},
};

static void measure(const char *label, const q2n_mesh *m, const q2n_surface *s, double osc_bound, double e_bound,
                    int g2, fair_figures *F)
{
    fair_measure(m, s, F);
    printf("| %-34s | %s | %6.3f (<= %.3g) | %8.3g (<= %.3g) | %6.3f (face %d) | %6.2f |\n", label, g2 ? "G2" : "G1",
           F->osc_ev_mean, osc_bound, F->E_ev, e_bound, F->jac_min, F->jac_face, F->jac_rel);
    CHECK(F->failed == 0, "%s: %d evaluations failed", label, F->failed);
    CHECK(F->jac_rel >= 1, "%s: face %d folds or degenerates: Jacobian ratio %.3g (bound min(0.1, 3/4 of its bilinear quad's))",
          label, F->jac_rel_face, F->jac_min);
    CHECK(F->osc_ev_mean <= osc_bound, "%s (%s): curvature oscillation %.4g per EV-face diagonal > %.3g", label,
          g2 ? "G2" : "G1", F->osc_ev_mean, osc_bound);
    if (g2) CHECK(F->E_ev <= e_bound, "%s: bending energy of the EV faces %.4g > %.3g", label, F->E_ev, e_bound);
}

static void shared_mesh(const fcase *c)
{
    const char *path = chk_shared_mesh(c->file);
    if (!path) return; /* reported by chk_shared_mesh */
    double maxH[2] = {-1, -1};
    for (int g = 0; g < 2; g++) {
        q2n_model_options o;
        memset(&o, 0, sizeof o);
        o.subdivide = c->sub;
        o.ev_patch = g ? Q2N_EV_PATCH_G1 : Q2N_EV_PATCH_G2;
        q2n_model *mo = NULL;
        q2n_error err;
        if (q2n_model_build(path, &o, &mo, &err)) { CHECK(0, "%s: %s", c->file, err.message); continue; }
        fair_figures F;
        char lab[96];
        snprintf(lab, sizeof lab, "%s%s", c->file, c->met ? "" : " *");
        measure(lab, mo->mesh, mo->surface, c->osc[g], c->energy, !g, &F);
        maxH[g] = F.maxH;
        q2n_model_free(mo);
    }
    /* G2 patches add no curvature spike that G1 patches do not have: the largest |H| along the
     * face diagonals (their corners included) at most 1.25 x G1's (at most 1.03 x on the shared
     * meshes; osd_catmark_xord_boundary's boundary corners reached 103.6 against 18.8 until stop
     * 39, 7.2 since: ev_policy.h EV_FAIR_RIDGE_CORNER) */
    if (maxH[0] >= 0 && maxH[1] >= 0)
        CHECK(maxH[0] <= 1.25 * maxH[1] + 1e-9, "%s: largest |H| x diagonal %.3g with G2 patches, %.3g with G1 ones",
              c->file, maxH[0], maxH[1]);
}

/* The stages before the extraordinary regions, with the default options: edge intervals and
 * the regular augmented patches (the extraordinary faces left uncovered); 1 on success. */
static int regular_stage(const q2n_mesh *m, double **iv, q2n_surface **s, q2n_error *err)
{
    q2n_param_options po = {0};
    q2n_augmented_options ao = {NULL, po};
    return q2n_param_edge_intervals(m, &po, iv, err) == Q2N_OK && q2n_augmented_build(m, &ao, *iv, s, err) == Q2N_OK;
}

/* The whole construction with the default options, G2 (g1 == 0) or G1 patches; 1 on success. */
static int default_build(const q2n_mesh *m, int g1, double **iv, q2n_surface **s, q2n_error *err)
{
    q2n_param_options po = {0};
    q2n_extraordinary_options xo = {NULL, po, g1 ? Q2N_EV_PATCH_G1 : Q2N_EV_PATCH_G2, Q2N_EV_METHOD_DEFAULT, 2, 0, 0, NULL, NULL};
    return regular_stage(m, iv, s, err) && q2n_extraordinary_build(m, &xo, *iv, *s, err) == Q2N_OK;
}

/* The paper's construction still charts a boundary vertex of one or two faces by right angles.
 * At a straight one-face corner no local surface fits, and at the 52-degree rim corners of a
 * three-sided pyramid (two faces) its ribbon finds no direction across the rim edge: each refusal
 * says so and names the construction that builds the mesh (until stop 39 "a degenerate fan?",
 * until stop 40 "degenerate ribbon"). */
static void paper_refusal(int sides, const char *want, const char *want2)
{
    q2n_mesh *m = mg_rim_pyramid(sides, 1, 1);
    CHECK(m != NULL, "rim pyramid: generator");
    if (!m) return;
    double *iv = NULL;
    q2n_surface *s = NULL;
    q2n_error err = {0, ""};
    q2n_param_options po = {0};
    q2n_extraordinary_options xo = {NULL, po, Q2N_EV_PATCH_G2, Q2N_EV_METHOD_PAPER, 2, 0, 0, NULL, NULL};
    int ok = regular_stage(m, &iv, &s, &err) && q2n_extraordinary_build(m, &xo, iv, s, &err) == Q2N_OK;
    CHECK(!ok && strstr(err.message, want) && strstr(err.message, want2) && strstr(err.message, "--ev-construction fair"),
          "paper construction, %d-sided straight pyramid: %s", sides, ok ? "built" : err.message);
    q2n_surface_free(s);
    free(iv);
    q2n_mesh_free(m);
}

static void paper_straight_corner(void)
{
    paper_refusal(6, "is a boundary corner of one face with an angle of 180.0 degrees", "right angle");
    paper_refusal(3, "finds no direction across edge", "degrees, and its chart draws a boundary vertex of one or two faces with right angles");
}

/* tools/q2n_ripple_bound.py (the fairest interpolant of a height-field mesh, an independent
 * reference for the ripple target; docs/extraordinary.md): its self-test, and the claim the docs
 * make with it — on the valence-5 carpet that interpolant ripples past the 0.3 per
 * diagonal (2.16), more than the construction does (1.46). */
/* Run tools/q2n_ripple_bound.py with args; its output (stdout and stderr) into buf; its exit status. */
static int ripple_script(const char *args, char *buf, size_t len)
{
    char cmd[700];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tools/q2n_ripple_bound.py %s 2>&1", args);
    FILE *p = popen(cmd, "r");
    size_t n = p ? fread(buf, 1, len - 1, p) : 0;
    buf[n] = 0;
    return p ? pclose(p) : -1;
}

/* The number after "key": in the script's JSON output (-1 when absent). */
static double json_number(const char *buf, const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *at = strstr(buf, pat);
    return at ? atof(at + strlen(pat)) : -1;
}

static void ripple_bound(void)
{
    char buf[512], arg[600];
    int rc = ripple_script("--self-test", buf, sizeof buf);
    CHECK(rc == 0 && strstr(buf, "\"self_test\": \"ok\""), "q2n_ripple_bound.py --self-test: %s", buf);
    const char *path = chk_shared_mesh("gismo_ev_valence5_carpet.obj");
    if (!path) return;
    snprintf(arg, sizeof arg, "'%s'", path);
    rc = ripple_script(arg, buf, sizeof buf);
    double osc = json_number(buf, "osc_ev_mean");
    printf("polyharmonic interpolant of the valence-5 carpet: %.3f per EV diagonal\n", osc);
    CHECK(rc == 0 && osc > 1.5 && osc < 3, "q2n_ripple_bound.py on the valence-5 carpet: %s", buf);
    /* closed meshes: the radial reference.  osd_catmark_cube's eight vertices lie on a sphere, which
     * it gives back: no oscillation (the construction: 0.93 per EV diagonal, acc-g1 1.25), the
     * sphere's bending energy 8 pi */
    if (!(path = chk_shared_mesh("osd_catmark_cube.obj"))) return;
    snprintf(arg, sizeof arg, "'%s'", path);
    rc = ripple_script(arg, buf, sizeof buf);
    osc = json_number(buf, "osc_ev_mean");
    double E = json_number(buf, "E_ev");
    printf("radial reference of osd_catmark_cube: %.2e per EV diagonal, E_ev %.6f (8 pi %.6f)\n", osc, E, 8 * M_PI);
    CHECK(rc == 0 && strstr(buf, "\"reference\": \"radial\"") && osc >= 0 && osc < 1e-3 && fabs(E / (8 * M_PI) - 1) < 1e-6,
          "q2n_ripple_bound.py on osd_catmark_cube: %s", buf);
}

/* Generated meshes go through the library's stages directly (no file); jac_min > 0: also a bound on
 * the smallest Jacobian ratio, where a change is known to have lowered it. */
static void generated_jac(const char *label, q2n_mesh *m, double osc_g2, double osc_g1, double e_bound, double jac_min)
{
    CHECK(m != NULL, "%s: generator", label);
    if (!m) return;
    for (int g = 0; g < 2; g++) {
        double *iv = NULL;
        q2n_surface *s = NULL;
        q2n_error err = {0, ""};
        int ok = default_build(m, g, &iv, &s, &err);
        CHECK(ok, "%s: build: %s", label, err.message);
        if (ok) {
            fair_figures F;
            measure(label, m, s, g ? osc_g1 : osc_g2, e_bound, !g, &F);
            if (jac_min > 0)
                CHECK(F.jac_min >= jac_min, "%s (%s): Jacobian ratio %.3g (face %d) < %.3g", label, g ? "G1" : "G2", F.jac_min,
                      F.jac_face, jac_min);
        }
        q2n_surface_free(s);
        free(iv);
    }
    q2n_mesh_free(m);
}

static void generated(const char *label, q2n_mesh *m, double osc_g2, double osc_g1, double e_bound)
{
    generated_jac(label, m, osc_g2, osc_g1, e_bound, 0);
}

/* m with its even n-gons filled with quads (--fill-ngons; the mesh freed). */
static q2n_mesh *filled(q2n_mesh *m)
{
    q2n_mesh *out = NULL;
    q2n_error err = {0, ""};
    if (m && q2n_mesh_fill_ngons(m, &out, NULL, NULL, &err)) CHECK(0, "fill: %s", err.message);
    q2n_mesh_free(m);
    return out;
}

/* The fold guard's own account (ev_fair_stats): on the spike it holds the corners of the folded
 * tip faces and leaves no fold; on a mesh whose energy solution does not fold it holds nothing (the
 * surface is the energy's, untouched).  At 7 x the held local estimates fold too in G2, and one
 * halving of the held jets (shrink_stage) leaves none; the tip's parametrisation stays thin there
 * (construction Jacobian ratio 0.034 in G2, 0.071 in G1, below the bound generated() applies), so
 * the 7 x spike is checked here only. */
static void fold_guard(const char *label, q2n_mesh *m, int expect_held, int expect_shrinks_g2)
{
    CHECK(m != NULL, "%s: generator", label);
    if (!m) return;
    for (int K = 1; K <= 2; K++) {
        double *iv = NULL;
        q2n_surface *s = NULL;
        q2n_error err = {0, ""};
        ev_fair_stats st;
        int ok = regular_stage(m, &iv, &s, &err) &&
                 q2n_ev_fair_build(m, NULL, s, iv, q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT), K, 0, 1, NULL, 2, &st, &err) == Q2N_OK;
        CHECK(ok, "%s: build: %s", label, err.message);
        if (ok) {
            printf("fold guard, %s, G%d: %d vertices held, %d faces still folded, %d halvings\n", label, K, st.held_vertices,
                   st.folded_faces, st.shrinks);
            int want = K == 2 ? expect_shrinks_g2 : 0;
            CHECK(want ? st.shrinks >= 1 : st.shrinks == 0, "%s (G%d): %d halvings of the held jets, expected %s", label, K, st.shrinks,
                  want ? "some" : "none");
            CHECK(st.folded_faces == 0, "%s (G%d): %d faces fold after the guard", label, K, st.folded_faces);
            CHECK(expect_held ? st.held_vertices > 0 : st.held_vertices == 0, "%s (G%d): the guard held %d vertices", label, K,
                  st.held_vertices);
        }
        q2n_surface_free(s);
        free(iv);
    }
    q2n_mesh_free(m);
}

/* A UV sphere's pole with its triangle fan merged into kites (mg_sphere_pole): every vertex lies on
 * the unit sphere, so the surface must stay near it — within 1.5 x the sagitta of one ring step,
 * 1 - cos(dtheta / 2), which is how far the mesh's own chords are from the sphere.  Until the far
 * corners of wide-angled faces were placed at their distance in the vertex charts
 * (ev_derivatives.c fan_gather), the valence-3 vertex of each kite read curvatures 100-300 x the
 * sphere's from the apex's height, and the construction left the sphere by 0.061 at valence 48
 * (G1 patches 0.015; both past the bound 0.0117; 0.0067 at valence 24): 0.0045 / 0.0034 now. */
static void sphere_pole(int n)
{
    const double dth = 0.25, bound = 1.5 * (1 - cos(dth / 2));
    q2n_mesh *m = mg_sphere_pole(n, 3, dth);
    CHECK(m != NULL, "sphere pole %d: generator", n);
    if (!m) return;
    for (int g = 0; g < 2; g++) {
        double *iv = NULL, dmax = 0, us[17], P[3 * 17 * 17];
        int kmax = -1;
        q2n_surface *s = NULL;
        q2n_error err = {0, ""};
        int ok = default_build(m, g, &iv, &s, &err);
        CHECK(ok, "sphere pole %d: build: %s", n, err.message);
        for (int i = 0; i < 17; i++) us[i] = i / 16.0;
        for (int k = 0; ok && k < m->nf; k++) {
            if (q2n_surface_eval_grid_pos(s, k, 17, us, 17, us, P)) { CHECK(0, "sphere pole %d: patch %d", n, k); break; }
            for (int i = 0; i < 17 * 17; i++) {
                double d = fabs(sqrt(P[3 * i] * P[3 * i] + P[3 * i + 1] * P[3 * i + 1] + P[3 * i + 2] * P[3 * i + 2]) - 1);
                if (d > dmax) dmax = d, kmax = k;
            }
        }
        if (ok) {
            printf("sphere pole, valence %d, G%d: max |r - 1| %.4f (patch %d), bound %.4f\n", n, g ? 1 : 2, dmax, kmax, bound);
            CHECK(dmax <= bound, "sphere pole %d (G%d): the surface leaves the sphere by %.4g (patch %d) > %.4g", n, g ? 1 : 2, dmax,
                  kmax, bound);
        }
        q2n_surface_free(s);
        free(iv);
    }
    q2n_mesh_free(m);
}

/* --keep-flat (ev_fair.c "flat fans"): where the mesh is flat around a vertex the surface stays in
 * that plane (measured by q2n_flat_faces_dev, the build's own check, on 17 x 17 points of each face
 * whose corners' fans lie in its plane; test_cli checks one such face independently, through the
 * CLI's samples).  The default construction lets the energy spread the bends beside a flat region into
 * it: on a box with support loops at 0.1 the middle of every side bulges by ~1 % of the diagonal
 * (measured 0.0095 in G2; the check that it is above 1e-3 shows that the measurement sees it), on
 * osd_catmark_gregory_test6 (a flat sheet with a bump) by ~1 %; with keep_flat every face whose
 * one-ring is planar stays in its plane to rounding.  The fairness figures of both are printed: the
 * bends beside flat regions are tighter with it (docs/extraordinary.md, "Flat fans"), and these
 * bounds keep them from growing unnoticed (measured + 20 %). */
static void keep_flat(void)
{
    q2n_mesh *box = mg_loop_box(0.1);
    const char *path = chk_shared_mesh("osd_catmark_gregory_test6.obj");
    static const double osc_bound[2][2] = {{3.2, 2.65}, {1.22, 1.47}}; /* [mesh][G2, G1] with keep_flat */
    for (int mi = 0; mi < 2; mi++) {
        if (mi == 0 && !box) { CHECK(0, "box with support loops: generator"); continue; }
        if (mi == 1 && !path) continue; /* reported by chk_shared_mesh */
        for (int g = 0; g < 2; g++)
            for (int kf = 0; kf < 2; kf++) {
                q2n_model *mo = NULL;
                double *iv = NULL;
                q2n_surface *s = NULL;
                const q2n_mesh *m = box;
                q2n_error err = {0, ""};
                int ok;
                if (mi == 0) {
                    q2n_param_options po = {0};
                    q2n_extraordinary_options xo = {NULL, po, g ? Q2N_EV_PATCH_G1 : Q2N_EV_PATCH_G2, Q2N_EV_METHOD_DEFAULT, 2, kf, 0, NULL, NULL};
                    ok = regular_stage(box, &iv, &s, &err) && q2n_extraordinary_build(box, &xo, iv, s, &err) == Q2N_OK;
                } else {
                    q2n_model_options o;
                    memset(&o, 0, sizeof o);
                    o.ev_patch = g ? Q2N_EV_PATCH_G1 : Q2N_EV_PATCH_G2;
                    o.keep_flat = kf;
                    ok = q2n_model_build(path, &o, &mo, &err) == Q2N_OK;
                    if (ok) m = mo->mesh, s = mo->surface;
                }
                const char *name = mi ? "osd_catmark_gregory_test6" : "box with support loops at 0.1";
                CHECK(ok, "%s: build: %s", name, err.message);
                if (ok) {
                    int nflat = 0, bface = -1;
                    double bulge = INFINITY;
                    CHECK(q2n_flat_faces_dev(m, s, 17, &nflat, &bulge, &bface) == Q2N_OK, "%s: flat faces", name);
                    fair_figures F;
                    fair_measure(m, s, &F);
                    printf("keep-flat %s, %s, G%d: %d faces with a planar one-ring, largest distance from their plane %.3g "
                           "x diag; osc per EV diagonal %.3f, E_ev %.3g, min jac %.3f\n",
                           kf ? "on " : "off", name, g ? 1 : 2, nflat, bulge, F.osc_ev_mean, F.E_ev, F.jac_min);
                    CHECK(nflat >= (mi ? 3 : 24), "%s: %d faces with a planar one-ring", name, nflat);
                    if (kf) {
                        CHECK(bulge <= 1e-12, "%s (G%d, keep-flat): the flat faces leave their plane by %.3g x diag", name,
                              g ? 1 : 2, bulge);
                        CHECK(F.jac_rel >= 1 && F.osc_ev_mean <= osc_bound[mi][g], "%s (G%d, keep-flat): osc %.4g (bound %.3g), "
                              "Jacobian ratio %.3g", name, g ? 1 : 2, F.osc_ev_mean, osc_bound[mi][g], F.jac_min);
                    } else
                        CHECK(bulge >= 1e-3, "%s (G%d): the default bulges the flat faces by %.3g x diag only", name, g ? 1 : 2,
                              bulge);
                }
                if (mo) q2n_model_free(mo);
                else q2n_surface_free(s);
                free(iv);
            }
    }
    q2n_mesh_free(box);
}

int main(void)
{
    printf("| mesh (* targets not met: regression bound) | mode | osc per EV diagonal | E_ev | min jac | jac / bound |\n");
    for (size_t i = 0; i < sizeof shared_cases / sizeof shared_cases[0]; i++) {
        if (strstr(shared_cases[i].file, "righthanded") && !q2n_test_full("fairness of osd_catmark_righthanded")) continue;
        shared_mesh(&shared_cases[i]);
    }
    /* the repository's hard meshes: extraordinary vertices on opposite corners of every face
     * (valence 10 and 3; 8 and 3 on an ellipsoid with quads of aspect up to ~6), valence 12, thin
     * sectors (x stretched 4:1); acc-g1 figures (fairness.py): 0.043 / 26.3, 0.181 / 110, -, 0.068 / 0.87 */
    generated("icosahedron split into quads", mg_icosa_quad(0, 1), 0.3, 0.3, 79);
    generated("the same, noisy", mg_icosa_quad(0.05, 3), 0.3, 0.3, 100);
    /* The ellipsoidal octahedron missed the ripple target in G2 (0.355) since the valence-4
     * vertices of extraordinary regions take the fan's own chart (0.284 with quarter turns and
     * section curves, which made the helmet, righthanded and the carpets rougher;
     * docs/extraordinary.md, "Charts"), and so did the stretched valence 7 (0.376).  Since stop 32
     * (far corners at their distance, sectors capped at 0.75 pi) both meet it (0.261, 0.297; the
     * stretched valence 7 0.189 since stop 44, whose parallelogram-like faces keep wide sectors), so
     * their G2 bound is the target; G1 mode keeps the regression bounds (0.305, 0.246 measured).
     * The energy quadrature matters here too: 8 Gauss points gave 0.397 against 0.312 with 12
     * (quarter-turn charts; ev_policy.h EV_FAIR_GAUSS_G2). */
    generated("octahedron on a 3:1:0.5 ellipsoid *", mg_octa_quad(3, 1, 0.5), 0.3, 0.45, 330);
    generated("valence 12, two rings", mg_polar_star(12, 3, 1), 0.3, 0.3, 5);
    /* Every vertex extraordinary, rhombi of 6 : 1 with corners of ~160 degrees at valence-3
     * vertices; acc-g1 (fairness.py) 0.255 / 80.0, so the targets are 0.383 and 240.  Until the
     * charts let a parallelogram keep its wide corner (ev_derivatives.c sector_cap, stop 44), the
     * 135-degree cap put a crease along those rhombi's long diagonals: 1.12 / 114 fitted, the
     * target missed (docs/extraordinary.md, "Charts"). */
    generated("triacontahedron on a 2:1:0.5 ellipsoid", mg_triacontahedron(2, 1, 0.5, 1), 0.383, 0.383, 240);
    generated("valence 7, sectors stretched 4:1", mg_polar_star(7, 3, 4), 0.3, 0.65, 6.5);
    /* CAD-like blocks of unit cubes, one quad per cube face: flat faces, sharp edges, every vertex
     * extraordinary (valence 3 at convex corners, 5 at concave ones).  With the fan charts taken
     * from projected angles (until 2026-12) the G2 construction folded on four of them (Jacobian
     * ratio 0.002 - 0.018 next to the concave edges).  acc-g1 (fairness.py): L 0.383 / 88.6,
     * T 0.447 / 73.6, U 0.432 / 72.1, stairs 0.367 / 72.4, notched cube 0.389 / 57.9; energy
     * bounds 3 x those (met), oscillation bounds 1.5 x acc-g1's where met (T and U in G2, U in G1),
     * else the measured value + 30 % (L 0.650 / 0.685, T 0.801 in G1, stairs 0.593 / 0.741,
     * notched cube 0.995 / 1.056: the ripple target is missed there). */
    static const int cl[7][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 0, 1}, {1, 0, 1}};
    static const int ct[5][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, 2, 0}};
    static const int cu[5][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}};
    static const int cs[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {2, 0, 1}, {2, 0, 2}};
    static const int cn[7][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    generated("unit cubes: L-block", mg_polycube(7, cl, "L-block"), 0.85, 0.9, 266);
    generated("unit cubes: T-block", mg_polycube(5, ct, "T-block"), 0.67, 1.05, 221);
    generated("unit cubes: U-block", mg_polycube(5, cu, "U-block"), 0.648, 0.648, 216);
    generated("unit cubes: stairs", mg_polycube(5, cs, "stairs"), 0.78, 0.97, 217);
    generated("unit cubes: notched cube", mg_polycube(7, cn, "notched cube"), 1.3, 1.38, 174);
    /* The plainest box cage, every face at a valence-3 corner (stop 45): both targets missed
     * (acc-g1 0.460 / 48.5 by fairness.py: 0.69 and 146), and not by the data — the radial
     * reference of tools/q2n_ripple_bound.py, an interpolant of the same 26 vertices, ripples
     * 0.591 per EV diagonal with E_ev 95.0 (docs/extraordinary.md, "Closed meshes: a radial
     * reference").  Measured values + 30 %. */
    static const int cb[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    generated("unit cubes: 2 x 2 x 2 block", mg_polycube(8, cb, "2 x 2 x 2 block"), 2.73, 2.84, 217);
    /* Flat n-gon caps (--subdivide 1: n thin kites around a valence-n vertex, a sharp rim).  With
     * 12 sides the ripple target holds (0.261; acc-g1 0.050 / 9.5), the energy's does not (33.7
     * against 28.5); with 40 the caps ripple one lobe per sector (docs/extraordinary.md, "Found and
     * not fixed"; acc-g1 0.263 / 82.9 there): 1.48 / 249 measured.  Measured values + 30 %, so that
     * neither gets worse unnoticed. */
    generated("capped cylinder, 12 sides *", mg_capped_cylinder(12, 3, 2.0), 0.34, 0.34, 43.8);
    generated("capped cylinder, 40 sides *", mg_capped_cylinder(40, 2, 1.0), 1.93, 1.49, 324);
    /* The same cylinders with their caps filled (--fill-ngons: a ring of n quads and a grid, four
     * valence-3 vertices a cap, the rim regular; docs/mesh.md, "Filling n-gons"): the ripple
     * target holds in both modes (measured 0.072 / 0.079 and 0.046 / 0.063), the energy bounds are
     * the measured values + 30 % (its extraordinary faces are other faces than above), and no face
     * comes near a fold (Jacobian ratio 0.63 and 0.39 measured). */
    generated_jac("capped cylinder, 12 sides, filled", filled(mg_ngon_cylinder(12, 3, 2.0)), 0.3, 0.3, 38.6, 0.5);
    generated_jac("capped cylinder, 40 sides, filled", filled(mg_ngon_cylinder(40, 2, 1.0)), 0.3, 0.3, 8.2, 0.3);
    /* A cylinder with grid-filled caps (mg_gridfill_cylinder, stop 57): the rim's valence-3 vertices
     * sit at kite corners of 156 degrees, and the surface turns over the rim inside those kites instead
     * of at their corner (|H| 27.7 x the diagonal at 0.28 of the kite's diagonal, 11.1 at the corner, 16 at
     * the regular rim vertices beside it).  Issue 11's ripple target is missed where the radial reference
     * of tools/q2n_ripple_bound.py meets it (0.286 per EV diagonal, E_ev 56.0): measured here G2 / G1
     * 0.722 / 1.045, E_ev 89.6 in G2 (acc-g1 0.103 / 38.6: the energy target holds); docs/extraordinary.md,
     * "Found and not fixed: grid-filled caps".  Bounds: the measured values + 30 %. */
    generated("cylinder, 4 x 4 grid-filled caps *", mg_gridfill_cylinder(4, 3, 1.5), 0.94, 1.36, 117);
    /* A tessellated lip, its sliver triangles split (mg_lip): needle quads with 1-3-degree corners
     * around tightly curved fans.  Until stop 35 the charts called such fans folded and spread
     * their sectors uniformly: here G2 / G1 Jacobian ratios 0.037 / 0.029 and 0.002 / 0.025,
     * oscillation 643 / 13 985 and 34 807 / 452, bending energy 2e5 and 1.5e8 (the fitted files
     * folded on 24 and 66 faces).  Now 0.33-0.42, 4.94 / 5.44 and 3.79 / 4.42, 1 280 and 2 310
     * (stop 43: 5.21 / 5.03 and 3.85 / 4.15; their needle corners keep wider sectors since stop 44).
     * acc-g1 (fairness.py): 1.14 / 445 and 0.865 / 763: the energy target (3 x) holds on the first,
     * neither ripple target does; the bounds are the measured values + 30 %. */
    generated("triangulated lip, 4 steps *", mg_lip(4, 1), 6.76, 5.77, 1700);
    generated("triangulated lip, 8 steps, half as wide *", mg_lip(8, 0.5), 5.0, 5.1, 3130);
    /* A dart at the extraordinary vertex (mg_dart_fan: a 200-degree, non-convex sector).  Read against
     * the fan's normal that sector turned the wrong way, the fan counted as folded and was charted
     * uniformly, 72 degrees a sector: Jacobian ratios 0.198 (G2) and 0.243 (G1), oscillation 0.107 /
     * 0.082, bending energy 0.720 / 0.747.  Read against its own face it is a reflex corner and keeps
     * its width up to the 0.75 pi cap (stop 35): 0.457 / 0.411, 0.087 / 0.074, 0.608 / 0.655.  The
     * Jacobian bound sits between the two (0.35), the others are the new figures + 30 %. */
    generated_jac("valence 5 with a dart", mg_dart_fan(), 0.113, 0.096, 0.79, 0.35);
    /* Two wide sectors side by side at a valence-3 vertex (mg_wide_pair_fan: a near-triangle capped
     * at 0.75 pi, then a parallelogram at its own 161.5 degrees).  Until stop 49 the chart's capping
     * lost the second excess to the fan's last sector, the parallelogram's: 178 degrees in the
     * chart, its patch corner nearly straight, Jacobian ratio 0.053 (G2) and 0.052 (G1) — found on
     * a random convex hull through --subdivide 1 (bench/sweep.py).  Now 0.373 / 0.322; oscillation
     * 0.219 / 0.295 -> 0.183 / 0.080, bending energy 0.109 / 0.226 -> 0.125 / 0.202.  Bounds: the
     * ripple target, the energy + 30 %, a Jacobian ratio between the two.  Stop 52 (its boundary
     * vertices of two faces charted by a half turn: a smooth rim): 0.116 / 0.170, 0.155 / 0.261,
     * Jacobian ratio 0.323 / 0.241; the bound 0.25 -> 0.2, still far above the old failure. */
    generated_jac("valence 3, two wide sectors side by side", mg_wide_pair_fan(), 0.3, 0.3, 0.27, 0.2);
    /* Spikes: a cube's corner pulled out to 5 times its distance from the centre (one corner, two
     * opposite ones).  The energy is parametric, and its minimiser folded the three long tip faces
     * over (Jacobian ratio 0.014 in G2, 0.027 in G1, bending energy 19 249: fairness.py on the
     * fitted file) until the fold guard held their corners' jets at the local estimates (ev_fair.c
     * fair_solve): 0.089 / 405 now; two spikes 0.0016 / 219 723 -> 0.084 / 485.  acc-g1 (fairness.py):
     * one spike 0.684 / 107, two 0.908 / 166: the energy target is 3x those; the oscillation target
     * (at most 1.5 x acc-g1's) is not met: these bounds are the measured values + 30 %. */
    generated("cube with a spike (5x) *", mg_spike_cube(5, 0), 15.0, 5.8, 527);
    generated("cube with two spikes (5x) *", mg_spike_cube(5, 1), 5.7, 7.3, 631);
    /* Open pyramids (mg_rim_pyramid): every rim point is a boundary corner of one face, every rim
     * vertex a boundary vertex of two, all inside the apex's extraordinary region.  Until stop 39
     * the fair construction charted such vertices by quarter turns (a nearly straight one-face
     * corner drawn as a right angle), and a straight one refused the mesh ("a degenerate fan?");
     * now by their spatial angles, and a one-face corner's tangent map fits its far corner too.
     * G2 / G1 oscillation, G2 energy, before -> after: reflex rim corners of 199 degrees (rim points
     * at 0.9) 3.37 / 3.49 -> 1.62 / 1.98 (acc-g1 21.2, energy 28.9 against its 92.5); straight
     * corners, 5 and 6 sides: refused -> 1.32 / 1.28, 15.7 and 1.00 / 1.38, 14.4 (acc-g1 0.99 and
     * 0.55, 5.45); 3 sides: 4.67 / 4.71, 31.2 -> 4.44 / 5.16, 30.5 (acc-g1 1.43, 9.15; the targets
     * missed either way); convex rim corners of 151 degrees (rim points at 1.15): 0.721 / 0.912 ->
     * 0.393 / 0.462, Jacobian ratio 0.171 -> 0.320 (acc-g1 0.098, 2.56).  The bounds: the new
     * figures + 30 %, the Jacobian's between the two.  Since stop 52 a rim vertex (two faces) is charted
     * by a half turn, so that the rim runs smoothly through it as between regular patches, and G1
     * patches hold a one-face corner's curvature too; before, the rim turned there by the faces'
     * spatial angles (up to 144 degrees on these pyramids).  G2 / G1 oscillation, energy (G2),
     * stop 51 -> 52: reflex 1.54 / 2.43, 30.1 -> 1.48 / 2.22, 30.5; straight, 5 sides 0.82 / 1.15,
     * 15.8 -> 0.87 / 1.59, 17.1 (G1 18.3), 6 sides 0.40 / 1.17, 14.1 -> 0.44 / 1.23, 15.2, 3 sides
     * 5.50 / 4.01, 33.8 -> 4.04 / 3.91, 32.3; convex 0.229 / 0.221 -> 0.197 / 0.193.  The 5-sided
     * one's G1 and energy bounds: the new figures + 30 %. */
    generated("pyramid, 6 sides, reflex rim corners (199 degrees)", mg_rim_pyramid(6, 1.5, 0.9), 2.1, 2.6, 37.6);
    generated("pyramid, 5 sides, straight rim corners", mg_rim_pyramid(5, 1, 1), 1.49, 2.06, 23.8);
    generated("pyramid, 6 sides, straight rim corners *", mg_rim_pyramid(6, 1, 1), 1.3, 1.79, 16.3);
    generated("pyramid, 3 sides, straight rim corners *", mg_rim_pyramid(3, 1, 1), 5.77, 6.71, 39.7);
    generated_jac("pyramid, 6 sides, rim corners of 151 degrees *", mg_rim_pyramid(6, 0.5, 1.15), 0.51, 0.6, 4.67, 0.25);
    paper_straight_corner();
    ripple_bound();
    sphere_pole(24);
    sphere_pole(48);
    fold_guard("cube with a spike (5x)", mg_spike_cube(5, 0), 1, 0);
    fold_guard("unit cubes: L-block", mg_polycube(7, cl, "L-block"), 0, 0);
    fold_guard("cube with a spike (7x)", mg_spike_cube(7, 0), 1, 1);
    keep_flat();
    CHECK_DONE("test_ev_fairness");
}
