/* test_fit_construction.c — the fit issue's targets on the shared meshes, with the construction
 * the CLI builds (augmented surface, the default extraordinary-vertex construction, centripetal
 * intervals, G2 mode for the C2 class): deviation <= tol (the fit's report, and the distance of
 * random points of the model to the construction by foot points), G0 <= 1e-12 diag, G1 <= 0.01 deg,
 * G2 <= 1 %, every boundary the edge curve by knot insertion; where every edge is exact, G1 and G2
 * to rounding; --tol 1e-4 gives a smaller file than 1e-5; the control points stay within the
 * span cap; and the construction scan reports smooth faces where spikes used to be.
 *
 * The default set is fast (a few seconds); make check-full (q2n_test_full) adds the long
 * sweep: every shared mesh (non-quad ones --subdivide 1) in G1 and G2 mode.
 * References: the construction's evaluator (foot-point distances, central differences for the
 * scan), bspline.c's evaluator (tests/fit_check.h), nothing of the fit's own. */
#include "check.h"
#include "meshgen.h"
#include "fit_check.h"
#include "api/model.h"
#include "core/vec3.h"
#include "fit/fit.h"
#include "fit/fit_internal.h"
#include "fit/fit_policy.h"
#include "iges/export.h"

#include <math.h>
#include <string.h>

static q2n_model *build(const char *file, int subdivide, int ev_patch, int frame)
{
    const char *path = strchr(file, '/') ? file : chk_shared_mesh(file);   /* a path: a generated mesh's file */
    if (!path) return NULL;
    q2n_model_options mo;
    memset(&mo, 0, sizeof mo);
    mo.param.method = Q2N_PARAM_CENTRIPETAL;   /* the CLI's defaults */
    mo.param.alpha = NAN;
    mo.subdivide = subdivide;
    mo.ev_patch = ev_patch;
    mo.frame = frame;
    q2n_model *m = NULL;
    q2n_error err;
    q2n_status st = q2n_model_build(path, &mo, &m, &err);
    CHECK(st == Q2N_OK, "%s: build: %s", file, st ? err.message : "");
    return st ? NULL : m;
}

/* One row of the table: mesh, Catmull-Clark steps, continuity mode (0: the construction's), the
 * patches at extraordinary vertices (0: the default, G2 for the C2 class), the span cap (0: the
 * default), the isotropic frame (0: auto, -1: off). */
typedef struct fit_case {
    const char *file;
    int subdivide, continuity, ev_patch, max_spans, frame;
} fit_case;

static const fit_case fast_cases[] = {
    {"osd_catmark_pawn.obj", 0, 0, 0, 0},        /* 588 faces, a valence-12 pole and twelve valence-3 vertices */
    {"osd_catmark_gregory_test1.obj", 0, 0, 0, 0},/* every face touches an extraordinary vertex */
    {"osd_catmark_helmet.obj", 0, 0, 0, 0},
    {"gismo_ev_valence5_carpet.obj", 0, 1, 0, 0},/* G1 mode */
    {"gismo_octtorus.obj", 0, 0, 0, 0},          /* regular, non-uniform: every edge exact after reparametrization */
};

static const fit_case long_cases[] = {
    {"crane_spot_control_mesh.obj", 1, 0, 0, 0}, {"osd_catmark_righthanded.obj", 0, 0, 0, 0}, {"osd_catmark_rook.obj", 1, 0, 0, 0},
    {"gismo_polycube.obj", 0, 0, 0, 0},          {"gismo_ev_valence3_carpet.obj", 0, 0, 0, 0}, {"gismo_ev_valence8_carpet.obj", 0, 0, 0, 0},
    {"osd_catmark_cube.obj", 0, 0, 0, 0},        {"osd_catmark_fvar_bound3.obj", 0, 0, 0, 0},  {"gismo_octtorus_hole.obj", 0, 0, 0, 0},
    {"crane_spot_control_mesh.obj", 1, 1, 0, 0}, {"osd_catmark_pawn.obj", 0, 1, 0, 0},         {"gismo_polycube.obj", 0, 1, 0, 0},
};

/* Fit one case and check every target; returns the report (rep) for callers that compare runs. */
static int run(const fit_case *fc, double tol, q2n_fit_report *rep)
{
    q2n_model *m = build(fc->file, fc->subdivide, fc->ev_patch, fc->frame);
    if (!m) return 0;
    q2n_fit_options o;
    q2n_fit_options_default(&o);
    o.tol = tol;
    o.continuity = fc->continuity ? fc->continuity : m->continuity;
    o.threads = 2;
    if (fc->max_spans) o.max_spans = fc->max_spans;
    q2n_nurbs_model *md = NULL;
    q2n_error err;
    q2n_status st = q2n_fit_surface(m->surface, m->mesh, &o, &md, rep, &err);
    double diag = q2n_mesh_bbox_diag(m->mesh);
    int nsame = 0, nsides = 0;
    double gap = md ? fit_boundary_gap(md, &nsame, &nsides) / diag : 1, dev = md ? fit_random_distance(md, m->surface, 12, diag) : 1;
    printf("  %s%s G%d tol %g: max_dev %.2e (random %.2e), G1 %.2e deg, G2 %.2e, exact %d/%d, cp/face %d/%d/%d, "
           "spans %d/%d/%d, %d rounds, %.2f s\n", fc->file, fc->subdivide ? " --subdivide 1" : "", o.continuity, tol,
           rep->max_dev_rel, dev, rep->g1_max_deg, rep->g2_max_rel, rep->g1_exact_edges, rep->interior_edges, rep->cp_min,
           rep->cp_median, rep->cp_max, rep->spans_min, rep->spans_median, rep->spans_max, rep->rounds, rep->t_total);
    CHECK(st == Q2N_OK && rep->tol_met, "%s: targets not met: %s %s", fc->file, st ? err.message : "", rep->note);
    CHECK(rep->max_dev_rel <= tol && dev <= 2 * tol, "%s: deviation %g (random points %g)", fc->file, rep->max_dev_rel, dev);
    CHECK(rep->g0_max_rel <= 1e-12 && gap <= 1e-13, "%s: g0 %g, boundaries vs edge curves %g", fc->file, rep->g0_max_rel, gap);
    CHECK(nsame == nsides, "%s: %d boundaries with the edge's knots not bit-identical", fc->file, nsides - nsame);
    int unshared = md ? fit_unshared_knots(md) : 0;
    CHECK(unshared == 0, "%s: %d edge curves lack a knot all their sides have", fc->file, unshared);
    /* the run's continuity targets: 0.01 degrees and 1 % at tol 1e-5, loosened in proportion above */
    double t1 = q2n_fit_default_target(tol, Q2N_FIT_G1_TARGET_DEFAULT, Q2N_FIT_G1_TARGET_CAP);
    double t2 = q2n_fit_default_target(tol, Q2N_FIT_G2_TARGET_DEFAULT, Q2N_FIT_G2_TARGET_CAP);
    CHECK(rep->g1_tol_deg == t1 && rep->g2_tol_rel == t2, "%s: targets %g deg, %g (expected %g, %g)", fc->file,
          rep->g1_tol_deg, rep->g2_tol_rel, t1, t2);
    CHECK(rep->g1_max_deg <= t1, "%s: G1 %g deg > %g", fc->file, rep->g1_max_deg, t1);
    if (o.continuity == 2) CHECK(rep->g2_max_rel <= t2, "%s: G2 %g > %g", fc->file, rep->g2_max_rel, t2);
    /* the targets hold between the fit's check points too (64 points per edge, this file's own
     * curvature code): the fit's acceptance samples 4 points per knot span, and the true maximum lies
     * up to ~3x above what they see where an edge is coarse (measured: osd_catmark_rook) — the fit's
     * own samples between them (fit.c, dense_jumps) are what keep it inside */
    double dg1 = 0, dg2 = 0;
    if (md) fit_dense_continuity(md, 64, diag, &dg1, &dg2);
    printf("    dense (64 per edge): G1 %.2e deg, G2 %.2e\n", dg1, dg2);
    CHECK(dg1 <= t1, "%s: G1 between the check points %g deg > %g", fc->file, dg1, t1);
    if (o.continuity == 2) CHECK(dg2 <= t2, "%s: G2 between the check points %g > %g", fc->file, dg2, t2);
    if (rep->g1_exact_edges == rep->interior_edges) {
        CHECK(rep->g1_max_deg <= 1e-6, "%s: all edges exact but G1 %g deg", fc->file, rep->g1_max_deg);
        if (o.continuity == 2) CHECK(rep->g2_max_rel <= 1e-6, "%s: all edges exact but G2 %g", fc->file, rep->g2_max_rel);
    }
    int cap = 0;
    for (int k = 0; md && k < md->n; k++) {
        int a = md->patches[k].ncp_u - 5, b = md->patches[k].ncp_v - 5;
        cap = cap > a ? cap : a;
        cap = cap > b ? cap : b;
    }
    CHECK(cap <= o.max_spans, "%s: %d spans in a patch direction > max_spans %d", fc->file, cap, o.max_spans);
    /* the file sizes at the default tolerance: STEP at most 20 KB per face in G2 mode, 12 KB
     * with the G1 construction in G1 mode (the STEP writer's own text, default options) */
    char *text = NULL;
    size_t len = 0;
    if (md && tol <= Q2N_FIT_TOL_DEFAULT && !fc->max_spans && (o.continuity == 2 || fc->ev_patch == Q2N_EV_PATCH_G1)) {
        CHECK(q2n_export_step_text(md, NULL, &text, &len, &err) == Q2N_OK, "%s: STEP: %s", fc->file, err.message);
        double kb = (double)len / 1024.0 / md->n, lim = o.continuity == 2 ? 20.0 : 12.0;
        printf("    %s STEP %.2f KB/face\n", fc->file, kb);
        CHECK(kb <= lim, "%s: STEP %.2f KB/face > %g", fc->file, kb, lim);
    }
    free(text);
    q2n_nurbs_model_free(md);
    q2n_model_free(m);
    return 1;
}

/* The spike q2n_fit_scan_construction reports is the construction's: |dS| from central differences
 * of evaluated positions at that point agrees with it; smooth faces stay below the spike ratio. */
static void check_scan(const char *file, int k)
{
    q2n_model *m = build(file, 0, 0, 0);
    if (!m) return;
    double ratio, u, v, dmax;
    CHECK(q2n_fit_scan_construction(m->surface, k, Q2N_FIT_SCAN_N, &ratio, &u, &v, &dmax) == Q2N_OK, "%s: scan", file);
    printf("  %s face %d: max |dS| %.3g at (%.4f, %.4f), %.3g x median\n", file, k, dmax, u, v, ratio);
    CHECK(ratio < Q2N_FIT_SPIKE_RATIO, "%s face %d: scan ratio %g", file, k, ratio);
    const double h = 1e-7;
    double a[Q2N_EVAL_MAX], b[Q2N_EVAL_MAX], du[3], dv[3];
    q2n_surface_eval(m->surface, k, u + h, v, 0, a);
    q2n_surface_eval(m->surface, k, u - h, v, 0, b);
    for (int q = 0; q < 3; q++) du[q] = (a[q] - b[q]) / (2 * h);
    q2n_surface_eval(m->surface, k, u, v + h, 0, a);
    q2n_surface_eval(m->surface, k, u, v - h, 0, b);
    for (int q = 0; q < 3; q++) dv[q] = (a[q] - b[q]) / (2 * h);
    double fd = q2n_v3_norm(du) > q2n_v3_norm(dv) ? q2n_v3_norm(du) : q2n_v3_norm(dv);
    CHECK_NEAR(fd / dmax, 1.0, 0.02, "central-difference |dS| / scanned |dS|");
    q2n_model_free(m);
}

/* The sizes on meshes of the project's own (meshgen.h; a plain clone tests them too) with
 * many extraordinary vertices, in G2 mode and with the G1 construction in G1 mode: run() checks
 * every target and the STEP bytes per face.  Measured (stop 34, KB/face G2 / G1 mode): the noisy
 * icosahedron split into quads (valence 5 and 3, closed) 14.8 / 7.0, a valence-7 one-ring stretched
 * 4:1 (open) 15.3 / 6.1, the L-block of unit cubes (valence 3 and 5, adjacent along its concave
 * edges) 14.9 / 7.0; since stop 43 a torus with two quads collapsed along a diagonal (valence 3, 6, 3
 * in a row, genus 1; bench/sweep.py's torus_pinched) 7.4 / 3.9; since stop 44 a rhombic
 * triacontahedron on a 2:1:0.5 ellipsoid (every vertex extraordinary, valence 5 and 3, rhombi of
 * 6:1 whose wide corners keep their angle in the charts) 14.7 / 3.2. */
static void generated_sizes(void)
{
    static const int cl[7][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 0, 1}, {1, 0, 1}};
    static const int pinch[2] = {5, 50}; /* two quads of a 12 x 8 torus collapsed: valences 3, 6, 3 twice (stop 43) */
    struct { const char *name; q2n_mesh *m; } g[] = {
        {"gen_icosa_noisy.obj", mg_icosa_quad(0.05, 3)},
        {"gen_star7_stretched.obj", mg_polar_star(7, 3, 4)},
        {"gen_lblock.obj", mg_polycube(7, cl, "L-block")},
        {"gen_torus_pinched.obj", mg_torus_pinched(12, 8, 3, 1, pinch, 2)},
        {"gen_triacontahedron.obj", mg_triacontahedron(2, 1, 0.5, 1)},
    };
    for (size_t i = 0; i < sizeof g / sizeof *g; i++) {
        char path[4096];
        q2n_error err;
        snprintf(path, sizeof path, "%s", chk_scratch(g[i].name));
        int ok = g[i].m && q2n_mesh_write_obj(g[i].m, path, &err) == Q2N_OK;
        CHECK(ok, "%s: not written", g[i].name);
        q2n_mesh_free(g[i].m);
        if (!ok) continue;
        q2n_fit_report r;
        const fit_case g2 = {path, 0, 0, 0, 0}, g1 = {path, 0, 1, Q2N_EV_PATCH_G1, 0};
        run(&g2, 1e-5, &r);
        run(&g1, 1e-5, &r);
    }
}

int main(void)
{
    generated_sizes();
    q2n_fit_report r5, r4, g1r5;   /* g1r5: gregory_test1 at 1e-5, checked twice below */
    for (size_t i = 0; i < sizeof fast_cases / sizeof *fast_cases; i++) run(&fast_cases[i], 1e-5, &r5);
    /* the user's tolerance decides the size: --tol 1e-4 needs fewer control points than 1e-5; on a mesh
     * whose every face touches an extraordinary vertex far fewer, since the default continuity targets
     * follow the tolerance (with 0.01 degrees and 1 % kept at 1e-4 it was 0.84 x; 1183 against 2196
     * control points, 0.54 x, until patches stopped being bisected for their sides' edge errors, which
     * made the 1e-5 fit lighter: 1183 against 1956, 0.60 x — every 1e-4 patch is 8 x 8 spans, the
     * fewest that meet 1e-4 there; 1033 against 1601, 0.65 x, at stop 29; since continuity misses
     * under Q2N_FIT_CONT_LOCAL split only their spans and a cell splits one direction where that
     * suffices, the 1e-5 fit is lighter again, the 1e-4 one hardly: 1010 against 1398, 0.72 x) */
    const fit_case pawn = {"osd_catmark_pawn.obj", 0, 0, 0, 0}, g1 = {"osd_catmark_gregory_test1.obj", 0, 0, 0, 0};
    if (run(&pawn, 1e-5, &r5) && run(&pawn, 1e-4, &r4))
        CHECK(r4.cp_total < r5.cp_total, "pawn: %ld control points at 1e-4, %ld at 1e-5", r4.cp_total, r5.cp_total);
    int g1ran = run(&g1, 1e-5, &g1r5);
    if (g1ran && run(&g1, 1e-4, &r4))
        CHECK(r4.cp_total < 0.78 * g1r5.cp_total, "gregory_test1: %ld control points at 1e-4, %ld at 1e-5", r4.cp_total,
              g1r5.cp_total);
    /* a patch whose failing cells all lie next to sides whose edges are being split waits for those
     * edges (fit_refine.c): bisecting it as well doubled the spans of patches whose interior met the
     * tolerance.  Measured: gregory_test6 3038 -> 2327 control points, fvar_bound3 1974 -> 1430. */
    const fit_case g6 = {"osd_catmark_gregory_test6.obj", 0, 0, 0, 0}, fb3 = {"osd_catmark_fvar_bound3.obj", 0, 0, 0, 0};
    if (run(&g6, 1e-5, &r5)) CHECK(r5.cp_total <= 2500, "gregory_test6: %ld control points (2197 expected)", r5.cp_total);
    /* continuity refinement judges the jumps between the check points too (fit.c, dense_jumps) and so
     * aims at 0.9 of the targets instead of half: fvar_bound3 1430 -> 1014 control points (every
     * patch 8 x 8 spans), xord_boundary 3794 -> 3042; the jumps at 64 points per edge stay within the
     * targets (fit_dense_continuity, every run of this test) */
    const fit_case xb = {"osd_catmark_xord_boundary.obj", 0, 0, 0, 0};
    /* cells beside an edge being split do not drive the splits of a patch that does not wait for it
     * (fit_refine.c): gregory_test1 1831 -> 1601 control points (one patch 16 x 16 spans before: a
     * band along one side asked for every span in both directions) */
    /* (stop 32: the vertex charts place a wide-angled face's far corner at its distance —
     * ev_derivatives.c fan_gather — and gregory_test1's valence-3 vertex on a 180-degree corner, whose
     * far corner lies a unit below its flat fan, reads a normal curvature of -0.45 there instead of
     * -10.5: 1398 -> 1781 control points, 18.2 -> 23.6 KB/face; with the chart's sectors capped at
     * 0.75 pi instead of 0.8 pi (ev_policy.h) 1576, 21.0 KB/face, over the 20; the same
     * changes keep UV-sphere poles of merged triangle fans on their sphere, test_ev_fairness
     * sphere_pole) */
    /* (stop 34: the least-squares gluing rows weigh 3 against the fidelity rows instead of 10,
     * fit_policy.h: 1576 -> 1434 control points, 21.0 -> 19.1 KB/face; 1500 is about the 20) */
    if (g1ran) CHECK(g1r5.cp_total <= 1500, "gregory_test1: %ld control points (1434 expected)", g1r5.cp_total);
    /* ... and since (fit_refine.c) a least-squares relation that misses its aim by less than
     * Q2N_FIT_CONT_LOCAL splits only its spans that miss, not every span (gregory_test1: one edge
     * missing the curvature aim by 1.38 x in its last span doubled two patches' spans: 1601 -> 1398
     * control points, 21.3 -> 18.2 KB/face, under the 20), and a failing cell splits only its
     * dominant direction where the error model says that suffices (the G1 construction in G1 mode:
     * gregory_test1 711 -> 603, osd_catmark_cube 566 -> 522; the 1e-5 bound above was 1700) */
    const fit_case g1g1 = {"osd_catmark_gregory_test1.obj", 0, 1, Q2N_EV_PATCH_G1, 0}, cube = {"osd_catmark_cube.obj", 0, 1, Q2N_EV_PATCH_G1, 0};
    if (run(&g1g1, 1e-5, &r5)) CHECK(r5.cp_total <= 650, "gregory_test1, G1 patches: %ld control points (567 expected)", r5.cp_total);
    if (run(&cube, 1e-5, &r5)) CHECK(r5.cp_total <= 545, "cube, G1 patches: %ld control points (522 expected)", r5.cp_total);
    /* after a local continuity round that did not lower its miss, an edge splits the spans that round
     * left coarser (its knots uniform again), not every span: the valence-8 carpet 5680 control points
     * before the local rule, 5566 with every span split after it, 5418 so; 5188 at stop 53, 5613 since
     * its G2 patches are glued by polynomials (stop 54: one patch beside the valence-8 vertex takes 483
     * control points, 196 before — docs/extraordinary.md, "Polynomial gluing of G2 patches") */
    const fit_case c8 = {"gismo_ev_valence8_carpet.obj", 0, 0, 0, 0};
    if (run(&c8, 1e-5, &r5)) CHECK(r5.cp_total <= 5900, "valence-8 carpet: %ld control points (5613 expected)", r5.cp_total);
    /* near the span cap local continuity splits wait (Q2N_FIT_CONT_LOCAL_ROOM): graded knots there
     * spent the span budget the continuity targets needed — at --max-spans 8 the valence-5 carpet
     * met them before the local rule (G1 0.004 deg) and missed G1 with local splits up to the cap
     * (0.026 deg on one edge; run() checks every target) */
    const fit_case c5cap = {"gismo_ev_valence5_carpet.obj", 0, 0, 0, 8};
    run(&c5cap, 1e-5, &r5);
    if (run(&fb3, 1e-5, &r5)) CHECK(r5.cp_total <= 1100, "fvar_bound3: %ld control points (1014 expected)", r5.cp_total);
    if (run(&xb, 1e-5, &r5)) CHECK(r5.cp_total <= 3300, "xord_boundary: %ld control points (3042 expected)", r5.cp_total);
    /* the cross rows of a least-squares-glued edge are judged by the cells beside it, not by their
     * distance from the construction's cross derivatives (fit_refine.c): gregory_test6 at 1e-4 1991 ->
     * 1496 control points */
    if (run(&g6, 1e-4, &r4)) CHECK(r4.cp_total <= 1700, "gregory_test6 1e-4: %ld control points (1225 expected)", r4.cp_total);
    /* the reparametrization of scale-glued edges has a speed per edge end (fit_target.c): more speed
     * systems are consistent and the speeds are smaller than with one speed per edge (measured:
     * octtorus_hole 13 -> 25 exact edges; tent, every edge exact either way, 1190 -> 973 control points).
     * octtorus_hole in its own frame: in its isotropic frame, the default, the construction's
     * intervals differ and 12 of its edges glue by a scale (docs/extraordinary.md, "The isotropic frame").
     * Since stop 54 its G2 patches are glued by polynomials: five edges inside its extraordinary region
     * whose smoothsteps were constant (the same α at both ends, β zero) take a quadratic α and are least
     * squares in the fit, 25 -> 20 (the file 13.5 -> 9.9 KB per face all the same) */
    const fit_case oh = {"gismo_octtorus_hole.obj", 0, 0, 0, 0, -1}, tent = {"osd_catmark_tent.obj", 0, 0, 0, 0};
    if (run(&oh, 1e-5, &r5)) CHECK(r5.g1_exact_edges >= 20, "octtorus_hole: %d exact edges (20 expected)", r5.g1_exact_edges);
    if (run(&tent, 1e-5, &r5))
        CHECK(r5.g1_exact_edges == r5.interior_edges && r5.cp_total <= 1050, "tent: %d of %d edges exact, %ld control points (973 expected)",
              r5.g1_exact_edges, r5.interior_edges, r5.cp_total);
    /* an edge curve may use 0.9 of the tolerance, and a failing cell beside it splits it further
     * where it uses more than a quarter (fit_refine.c): octtorus 2640 -> 2160 control points (every
     * edge exact); without that second rule a rook --subdivide 1 patch failed --tol 1e-4 at the last
     * round (run in the long sweep) */
    const fit_case ot = {"gismo_octtorus.obj", 0, 0, 0, 0};
    if (run(&ot, 1e-5, &r5)) CHECK(r5.cp_total <= 2300, "octtorus: %ld control points (2160 expected)", r5.cp_total);
    if (q2n_test_full("the long fit sweep (rook, righthanded, spot --subdivide 1)")) {
        for (size_t i = 0; i < sizeof long_cases / sizeof *long_cases; i++) run(&long_cases[i], 1e-5, &r5);
        const fit_case rook = {"osd_catmark_rook.obj", 1, 0, 0, 0};
        run(&rook, 1e-4, &r4);
    }
    check_scan("osd_catmark_gregory_test1.obj", 6);     /* a spike narrower than any knot spacing once */
    if (q2n_test_full("the construction scan of osd_catmark_righthanded")) check_scan("osd_catmark_righthanded.obj", 117);
    CHECK_DONE("test_fit_construction");
}
