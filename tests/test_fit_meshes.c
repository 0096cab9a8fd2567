/* test_fit_meshes.c — the fit on the project's own constructions: augmented interpolatory
 * surfaces (seed 003) on closed and open meshes, and the exact conversion of the Catmull–Clark
 * ACC path's Bézier patches (seed 001); a ~600-face timing.  References: the construction
 * itself (deviation at points off the fit samples), bspline.c's evaluator, bit-identical shared
 * control points. */
#include "check.h"
#include "fit_check.h"
#include "acc/acc.h"
#include "fit/fit.h"
#include "mesh/mesh.h"
#include "patch/augmented.h"
#include "patch/extraordinary.h"
#include "patch/surface.h"

#include <string.h>
#include <time.h>

#define PI 3.14159265358979323846

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* n x m torus mesh, radii 3 and 1 (u along the big circle); uneven != 0 spaces the rings
 * unevenly (then the centripetal intervals differ and the augmented patches are not polynomial). */
static q2n_mesh *torus_mesh(int n, int m, int uneven)
{
    int nv = n * m;
    double *pos = malloc(3 * sizeof(double) * (size_t)nv);
    int *fs = malloc(sizeof(int) * (size_t)(nv + 1)), *fv = malloc(4 * sizeof(int) * (size_t)nv);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            double a = 2 * PI * (i + (uneven ? 0.3 * sin(2 * PI * i / n) : 0)) / n;
            double b = 2 * PI * (j + (uneven ? 0.25 * sin(4 * PI * j / m) : 0)) / m, *p = pos + 3 * (i * m + j);
            p[0] = (3 + cos(b)) * cos(a); p[1] = (3 + cos(b)) * sin(a); p[2] = sin(b);
            if (uneven) /* deterministic jitter: edge lengths no longer separable in i and j */
                for (int c = 0; c < 3; c++) p[c] += 0.03 * sin(12.9898 * (i + 1) + 78.233 * (j + 1) + 37.719 * c);
            int f = i * m + j;
            fs[f] = 4 * f;
            fv[4 * f] = f; fv[4 * f + 1] = ((i + 1) % n) * m + j;
            fv[4 * f + 2] = ((i + 1) % n) * m + (j + 1) % m; fv[4 * f + 3] = i * m + (j + 1) % m;
        }
    fs[nv] = 4 * nv;
    q2n_mesh *mesh = NULL;
    q2n_error err;
    if (q2n_mesh_from_arrays(nv, pos, nv, fs, fv, "torus", &mesh, &err)) fprintf(stderr, "%s\n", err.message);
    free(pos); free(fs); free(fv);
    return mesh;
}


/* Fit s (on mesh) and check the targets; prints the figures. */
static void fit_and_check(const char *name, const q2n_mesh *mesh, const q2n_surface *s, double tol, int cont,
                          int threads, int expect_g2, q2n_fit_report *rout)
{
    q2n_fit_options o;
    q2n_fit_options_default(&o);
    o.tol = tol;
    o.continuity = cont;
    o.threads = threads;
    q2n_nurbs_model *md = NULL;
    q2n_fit_report r;
    q2n_error err = {0, ""};
    double t0 = now();
    q2n_status st = q2n_fit_surface(s, mesh, &o, &md, &r, &err);
    double t = now() - t0;
    CHECK(st == Q2N_OK, "%s: %s", name, err.message);
    printf("%-40s faces %4d spans %d/%d/%d cp %d/%d/%d rounds %d max_dev %.2e rms %.2e vdev %.1e g0 %.1e g1 %.2e deg "
           "g2 %.2e (constr g1 %.1e deg g2 %.1e) exact %d/%d  fit %.3f s (solve %.3f, %d thr)\n",
           name, r.faces, r.spans_min, r.spans_median, r.spans_max, r.cp_min, r.cp_median, r.cp_max, r.rounds,
           r.max_dev_rel, r.rms_dev_rel, r.vertex_dev_max_rel, r.g0_max_rel, r.g1_max_deg, r.g2_max_rel,
           r.g1_construction_deg, r.g2_construction_rel, r.g1_exact_edges, r.interior_edges, t, r.t_solve, threads);
    if (md) {
        double diag = q2n_mesh_bbox_diag(mesh);
        int nsame, nsides;
        double gap = fit_boundary_gap(md, &nsame, &nsides) / diag, dev = fit_random_distance(md, s, 20, diag);
        CHECK(r.max_dev_rel <= tol, "%s: max_dev_rel %g", name, r.max_dev_rel);
        CHECK(dev <= 2 * tol, "%s: distance to the construction at random points %g", name, dev);
        CHECK(r.g0_max_rel <= 1e-12, "%s: g0 %g", name, r.g0_max_rel);
        CHECK(gap <= 1e-14 && nsame == nsides, "%s: boundaries vs edge curves %g, %d of %d not bit-identical", name, gap,
              nsides - nsame, nsides);
        if (r.g1_construction_deg < 1e-3) CHECK(r.g1_max_deg <= 0.01, "%s: g1 %g deg", name, r.g1_max_deg);
        if (cont == 2 && expect_g2 && r.g2_construction_rel < 1e-3)
            CHECK(r.g2_max_rel <= 0.01, "%s: g2 %g", name, r.g2_max_rel);
        /* q2n_fit_measure measures the model again from scratch: the same edge check points give the
         * same continuity; its deviation is the distance to the construction by foot points, which
         * the report's (against the reparametrized target) bounds from above */
        q2n_fit_report mr;
        memset(&mr, 0, sizeof mr);
        CHECK(q2n_fit_measure(md, s, 2, &mr, &err) == Q2N_OK, "%s: q2n_fit_measure: %s", name, err.message);
        CHECK(mr.max_dev_rel <= r.max_dev_rel * (1 + 1e-9) + 1e-15, "%s: measured deviation %g > report %g", name,
              mr.max_dev_rel, r.max_dev_rel);
        CHECK(fabs(mr.g1_max_deg - r.g1_max_deg) <= 1e-9 * (1 + r.g1_max_deg) &&
                  fabs(mr.g2_max_rel - r.g2_max_rel) <= 1e-9 * (1 + r.g2_max_rel),
              "%s: q2n_fit_measure G1 %g / G2 %g, report %g / %g", name, mr.g1_max_deg, mr.g2_max_rel, r.g1_max_deg,
              r.g2_max_rel);
        if (expect_g2 && r.g1_exact_edges == r.interior_edges) {   /* all exact: G1 (and G2) to rounding */
            CHECK(r.g1_max_deg <= 1e-6, "%s: exact G1 %g deg", name, r.g1_max_deg);
            if (cont == 2) CHECK(r.g2_max_rel <= 1e-6, "%s: exact G2 %g", name, r.g2_max_rel);
        }
    }
    if (rout) *rout = r;
    q2n_nurbs_model_free(md);
}

static void augmented_case(const char *name, q2n_mesh *mesh, double tol, int cont)
{
    if (!mesh) { SKIP("%s: mesh missing", name); return; }
    q2n_surface *s = NULL;
    q2n_error err;
    q2n_augmented_options ao;
    memset(&ao, 0, sizeof ao);
    ao.param.alpha = -1;   /* the method's default: centripetal, non-uniform intervals */
    if (q2n_augmented_build(mesh, &ao, NULL, &s, &err)) { CHECK(0, "%s: %s", name, err.message); return; }
    if (q2n_surface_count(s, Q2N_PATCH_UNCOVERED)) {
        SKIP("%s: %d faces not covered by the regular construction", name, q2n_surface_count(s, Q2N_PATCH_UNCOVERED));
    } else {
        /* the regular augmented construction glues every edge by a scale: all exact */
        q2n_fit_report r;
        fit_and_check(name, mesh, s, tol, cont, 1, 1, &r);
        CHECK(r.g1_exact_edges == r.interior_edges, "%s: %d of %d edges exact", name, r.g1_exact_edges, r.interior_edges);
    }
    q2n_surface_free(s);
}

static q2n_mesh *shared(const char *file)
{
    const char *p = chk_shared_mesh(file);
    if (!p) return NULL;
    q2n_mesh *m = NULL;
    q2n_error err;
    if (q2n_mesh_read_obj(p, &m, &err)) { CHECK(0, "%s", err.message); return NULL; }
    return m;
}

/* Extraordinary vertices: augmented surface completed by Coons–Gregory patches (seed 003 §4),
 * whose corners are made polynomial-compatible in G2 mode (the rational Gregory blend is then
 * inactive): every target holds, G2 included. */
static void ev_cases(void)
{
    const char *files[] = {"gismo_ev_valence3_carpet.obj", "gismo_ev_valence5_carpet.obj"};
    for (int i = 0; i < 2; i++) {
        q2n_mesh *m = shared(files[i]);
        if (!m) continue;
        q2n_augmented_options ao;
        memset(&ao, 0, sizeof ao);
        ao.param.alpha = -1;
        q2n_extraordinary_options eo;
        memset(&eo, 0, sizeof eo);
        eo.param.alpha = -1;
        q2n_surface *s = NULL;
        q2n_error err;
        if (q2n_augmented_build(m, &ao, NULL, &s, &err) || q2n_extraordinary_build(m, &eo, NULL, s, &err)) {
            CHECK(0, "%s: %s", files[i], err.message);
            q2n_surface_free(s);
            q2n_mesh_free(m);
            continue;
        }
        CHECK(q2n_surface_count(s, Q2N_PATCH_COONS_GREGORY) > 0, "%s: no Coons-Gregory patch", files[i]);
        for (int cont = 1; cont <= 2; cont++) {
            char nm[128];
            q2n_fit_report r;
            snprintf(nm, sizeof nm, "%s EV G%d 1e-5", files[i], cont);
            fit_and_check(nm, m, s, 1e-5, cont, 1, 0, &r);
            CHECK(r.g1_max_deg <= 0.01, "%s: g1 %g", nm, r.g1_max_deg);
            if (cont == 2) CHECK(r.g2_met && r.g2_max_rel <= 0.01, "%s: g2 %g (%s)", nm, r.g2_max_rel, r.note);
        }
        q2n_surface_free(s);
        q2n_mesh_free(m);
    }
}

/* Catmull–Clark path: Bézier patches convert exactly (elevated to 5 x 5), shared edges
 * bit-identical, continuity = the construction's. */
static void acc_cases(void)
{
    const char *files[] = {"osd_catmark_pawn.obj", "gismo_ev_valence5_carpet.obj"};
    for (int i = 0; i < 2; i++) {
        q2n_mesh *m = shared(files[i]);
        if (!m) continue;
        for (int meth = 0; meth < 2; meth++) {
            q2n_acc_options ao;
            memset(&ao, 0, sizeof ao);
            ao.method = meth ? Q2N_ACC_G1 : Q2N_ACC_3;
            q2n_acc_info info;
            q2n_surface *s = NULL;
            q2n_error err;
            if (q2n_acc_build(m, &ao, &s, &info, &err)) { CHECK(0, "%s acc: %s", files[i], err.message); continue; }
            const q2n_mesh *pm = q2n_acc_info_mesh(&info, m);
            q2n_fit_options o;
            q2n_fit_options_default(&o);
            q2n_nurbs_model *md = NULL;
            q2n_fit_report r;
            q2n_status st = q2n_fit_surface(s, pm, &o, &md, &r, &err);
            printf("%-22s %-6s faces %4d exact %d max_dev %.2e g0 %.1e g1 %.2e deg (constr %.2e) g2 %.2e  %.3f s\n",
                   files[i], meth ? "acc-g1" : "acc3", r.faces, r.exact, r.max_dev_rel, r.g0_max_rel, r.g1_max_deg,
                   r.g1_construction_deg, r.g2_max_rel, r.t_total);
            CHECK(st == Q2N_OK, "%s: %s", files[i], err.message);
            CHECK(r.exact == 1, "%s: not converted exactly", files[i]);
            CHECK(r.max_dev_rel <= 1e-13, "%s: exact conversion deviates %g", files[i], r.max_dev_rel);
            CHECK(r.g0_max_rel <= 1e-12, "%s: g0 %g", files[i], r.g0_max_rel);
            CHECK(fabs(r.g1_max_deg - r.g1_construction_deg) <= 1e-6 * (1 + r.g1_construction_deg),
                  "%s: g1 %g vs construction %g", files[i], r.g1_max_deg, r.g1_construction_deg);
            int nsame = 0, nsides = 0;
            double gap = md ? fit_boundary_gap(md, &nsame, &nsides) : 1;
            CHECK(md && gap <= 1e-14 * q2n_mesh_bbox_diag(pm) && nsame == nsides && nsides > 0, "%s: shared rows differ (%g, %d of %d)", files[i], gap,
                  nsides - nsame, nsides);
            q2n_nurbs_model_free(md);
            q2n_surface_free(s);
            q2n_acc_info_free(&info);
        }
        q2n_mesh_free(m);
    }
}

/* A 600-face fit (augmented surface on an unevenly spaced torus), 1 and 2 threads. */
static void timing(void)
{
    q2n_mesh *t = torus_mesh(30, 20, 1);
    q2n_surface *s = NULL;
    q2n_augmented_options ao;
    memset(&ao, 0, sizeof ao);
    ao.param.alpha = -1;
    q2n_error err;
    if (!t || q2n_augmented_build(t, &ao, NULL, &s, &err)) { CHECK(0, "timing mesh"); return; }
    q2n_fit_report r1, r2;
    fit_and_check("augmented torus 30x20 G1 1e-5", t, s, 1e-5, 1, 1, 1, &r1);
    fit_and_check("augmented torus 30x20 G1 1e-5", t, s, 1e-5, 1, 2, 1, &r2);
    printf("TIMING 600-face fit (G1, tol 1e-5): %.3f s with 1 thread, %.3f s with 2 threads\n", r1.t_total, r2.t_total);
    fit_and_check("augmented torus 30x20 G2 1e-5", t, s, 1e-5, 2, 2, 1, &r2);
    printf("TIMING 600-face fit (G2, tol 1e-5): %.3f s with 2 threads\n", r2.t_total);
    q2n_surface_free(s);
    q2n_mesh_free(t);
}

int main(void)
{
    q2n_mesh *t = torus_mesh(8, 6, 1);
    augmented_case("augmented torus 8x6 G1 1e-5", t, 1e-5, 1);
    augmented_case("augmented torus 8x6 G1 1e-6", t, 1e-6, 1);
    augmented_case("augmented torus 8x6 G2 1e-5", t, 1e-5, 2);
    q2n_mesh_free(t);
    const char *files[] = {"osd_catmark_torus.obj", "gismo_octtorus.obj", "osd_catmark_tent.obj", "osd_catmark_flap.obj"};
    for (int i = 0; i < 4; i++) {
        q2n_mesh *m = shared(files[i]);
        char nm[128];
        if (!m) continue;
        snprintf(nm, sizeof nm, "%s G1 1e-5", files[i]);
        augmented_case(nm, m, 1e-5, 1);
        snprintf(nm, sizeof nm, "%s G1 1e-6", files[i]);
        augmented_case(nm, m, 1e-6, 1);
        q2n_mesh_free(m);
    }
    ev_cases();
    acc_cases();
    timing();
    CHECK_DONE("test_fit_meshes");
}
