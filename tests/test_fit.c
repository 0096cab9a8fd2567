/* test_fit.c — the bi-quintic fit (src/fit/): tolerance, watertightness, G1/G2 (least squares and
 * exact), solvers, knot insertion, the dense LAPACK helpers.
 *
 * Test surfaces are exact non-polynomial maps attached with q2n_surface_set_patch: a torus and
 * a curved graph z = f(x,y), each face mapped through its own non-linear reparametrisation, so
 * neighbours join G-infinity geometrically but are NOT parametrically C1.  Two families:
 * "skewed" faces (cross terms: the gluing has beta != 0, so the fit's G1/G2 relations are least
 * squares) and "scaled" faces (the cross speed of each face varies along its edges and the edge
 * speeds differ from face to face, but nothing is skewed: the gluing is a scale alpha(t), which the
 * fit turns into an exact constraint by reparametrizing, fit_target.c).
 * References are independent of the fit: the closed-form maps, bspline.c's evaluator (not the
 * fit's own), distances to the construction by Gauss-Newton foot points, closed-form polynomial
 * reproduction, and the direct QR path vs Ceres. */
#include "check.h"
#include "fit_check.h"
#include "fit/fit.h"
#include "fit/fit_internal.h"
#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/dense.h"
#include "core/vec3.h"
#include "mesh/mesh.h"
#include "patch/surface.h"

#include <string.h>

#define PI 3.14159265358979323846

/* ---- reparametrised maps: S(u,v) = F(x0 + dx U(u,v), y0 + dy V(u,v)) ---- */
typedef struct rmap {
    int kind;                 /* 0 torus, 1 graph, 2 polynomial graph (exactly representable) */
    double x0, dx, y0, dy;
    double cu, cv;            /* ribbon-wise edge reparametrisation: U(u,0) = u + cu u(1-u) */
    double a, b;              /* face-wise cross terms (break parametric C1) */
    int scaled;               /* 1: U = u + cu(v) g(u), V = v + cv(u) g(v), g = x - smoothstep(x), with
                                 cu blending the values of the face's two horizontal grid lines
                                 (cuA at v = 0, cuB at v = 1) and cv those of its vertical lines */
    double cuA, cuB, cvA, cvB;
} rmap;

/* F and its derivatives up to order 2 in (x, y): F[0..5][3] = F, Fx, Fy, Fxx, Fxy, Fyy. */
static void base_map(int kind, double x, double y, double F[6][3])
{
    memset(F, 0, 6 * 3 * sizeof(double));
    if (kind == 0) {   /* torus R = 3, r = 1: x = theta, y = phi */
        double R = 3, r = 1, ct = cos(x), st = sin(x), cp = cos(y), sp = sin(y), w = R + r * cp;
        F[0][0] = w * ct; F[0][1] = w * st; F[0][2] = r * sp;
        F[1][0] = -w * st; F[1][1] = w * ct;
        F[2][0] = -r * sp * ct; F[2][1] = -r * sp * st; F[2][2] = r * cp;
        F[3][0] = -w * ct; F[3][1] = -w * st;
        F[4][0] = r * sp * st; F[4][1] = -r * sp * ct;
        F[5][0] = -r * cp * ct; F[5][1] = -r * cp * st; F[5][2] = -r * sp;
        return;
    }
    F[0][0] = x; F[0][1] = y; F[1][0] = 1; F[2][1] = 1;
    if (kind == 1) {   /* z = 0.4 sin(1.3x) cos(0.9y) + 0.1 x y */
        double s1 = sin(1.3 * x), c1 = cos(1.3 * x), s2 = sin(0.9 * y), c2 = cos(0.9 * y);
        F[0][2] = 0.4 * s1 * c2 + 0.1 * x * y;
        F[1][2] = 0.52 * c1 * c2 + 0.1 * y;
        F[2][2] = -0.36 * s1 * s2 + 0.1 * x;
        F[3][2] = -0.676 * s1 * c2;
        F[4][2] = -0.468 * c1 * s2 + 0.1;
        F[5][2] = -0.324 * s1 * c2;
    } else {           /* z = 0.05 x^2 y^3 - 0.01 x^5 + 0.02 y^4 (degree <= 5 in x and in y) */
        F[0][2] = 0.05 * x * x * y * y * y - 0.01 * pow(x, 5) + 0.02 * pow(y, 4);
        F[1][2] = 0.1 * x * y * y * y - 0.05 * pow(x, 4);
        F[2][2] = 0.15 * x * x * y * y + 0.08 * y * y * y;
        F[3][2] = 0.1 * y * y * y - 0.2 * x * x * x;
        F[4][2] = 0.3 * x * y * y;
        F[5][2] = 0.3 * x * x * y + 0.24 * y * y;
    }
}

static q2n_status rmap_eval(const void *data, double u, double v, int nder, double *out)
{
    const rmap *m = data;
    double U, V, Uu, Uv, Vv, Vu, Uuu, Uuv, Uvv, Vvv, Vuv, Vuu;
    if (m->scaled) {
        /* smoothstep s, g = x - s: g(0) = g(1) = 0, g' = 1 and g'' = 0 at both ends, so across an edge
         * the cross speed is (1 + c) times the base map's, c blending between the edge's lines */
        double su = 10 * u * u * u - 15 * pow(u, 4) + 6 * pow(u, 5), sv = 10 * v * v * v - 15 * pow(v, 4) + 6 * pow(v, 5);
        double su1 = 30 * u * u - 60 * u * u * u + 30 * pow(u, 4), sv1 = 30 * v * v - 60 * v * v * v + 30 * pow(v, 4);
        double su2 = 60 * u - 180 * u * u + 120 * u * u * u, sv2 = 60 * v - 180 * v * v + 120 * v * v * v;
        double gu = u - su, gv = v - sv, gu1 = 1 - su1, gv1 = 1 - sv1, gu2 = -su2, gv2 = -sv2;
        double cu = m->cuA + (m->cuB - m->cuA) * sv, cu1 = (m->cuB - m->cuA) * sv1, cu2 = (m->cuB - m->cuA) * sv2;
        double cv = m->cvA + (m->cvB - m->cvA) * su, cv1 = (m->cvB - m->cvA) * su1, cv2 = (m->cvB - m->cvA) * su2;
        U = u + cu * gu; Uu = 1 + cu * gu1; Uv = cu1 * gu; Uuu = cu * gu2; Uuv = cu1 * gu1; Uvv = cu2 * gu;
        V = v + cv * gv; Vv = 1 + cv * gv1; Vu = cv1 * gv; Vvv = cv * gv2; Vuv = cv1 * gv1; Vuu = cv2 * gv;
    } else {
        /* U = u + cu u(1-u) + b u(1-u) v(1-v),  V = v + cv v(1-v) + a u(1-u) v(1-v) */
        double pu = u * (1 - u), pv = v * (1 - v), pu1 = 1 - 2 * u, pv1 = 1 - 2 * v;
        U = u + m->cu * pu + m->b * pu * pv; V = v + m->cv * pv + m->a * pu * pv;
        Uu = 1 + m->cu * pu1 + m->b * pu1 * pv; Uv = m->b * pu * pv1;
        Vv = 1 + m->cv * pv1 + m->a * pu * pv1; Vu = m->a * pu1 * pv;
        Uuu = -2 * m->cu - 2 * m->b * pv; Uuv = m->b * pu1 * pv1; Uvv = -2 * m->b * pu;
        Vvv = -2 * m->cv - 2 * m->a * pu; Vuv = m->a * pu1 * pv1; Vuu = -2 * m->a * pv;
    }
    double F[6][3];
    base_map(m->kind, m->x0 + m->dx * U, m->y0 + m->dy * V, F);
    double xu = m->dx * Uu, xv = m->dx * Uv, yu = m->dy * Vu, yv = m->dy * Vv;
    for (int c = 0; c < 3; c++) {
        out[c] = F[0][c];
        if (nder < 1) continue;
        out[3 + c] = F[1][c] * xu + F[2][c] * yu;
        out[6 + c] = F[1][c] * xv + F[2][c] * yv;
        if (nder < 2) continue;
        out[9 + c] = F[3][c] * xu * xu + 2 * F[4][c] * xu * yu + F[5][c] * yu * yu + F[1][c] * m->dx * Uuu +
                     F[2][c] * m->dy * Vuu;
        out[12 + c] = F[3][c] * xu * xv + F[4][c] * (xu * yv + xv * yu) + F[5][c] * yu * yv +
                      F[1][c] * m->dx * Uuv + F[2][c] * m->dy * Vuv;
        out[15 + c] = F[3][c] * xv * xv + 2 * F[4][c] * xv * yv + F[5][c] * yv * yv + F[1][c] * m->dx * Uvv +
                      F[2][c] * m->dy * Vvv;
    }
    return Q2N_OK;
}

static double frand(unsigned *s) { *s = *s * 1103515245u + 12345u; return ((*s >> 8) & 0xffff) / 65536.0; }

/* n x m faces: torus (closed, periodic) or graph (open) with reparametrised patches.
 * strength 0 gives the plain (linear) parametrisation. */
static int build_off(int kind, int n, int m, double strength, double offset, q2n_mesh **mesh, q2n_surface **surf);
static int g_scaled;   /* build scaled (1) or skewed (0) faces */
static int build(int kind, int n, int m, double strength, q2n_mesh **mesh, q2n_surface **surf)
{
    return build_off(kind, n, m, strength, 0.0, mesh, surf);
}

/* offset != 0 moves the mesh vertices off the surface along z (a construction that does not
 * interpolate its vertices, like the Catmull-Clark limit). */
static int build_off(int kind, int n, int m, double strength, double offset, q2n_mesh **mesh, q2n_surface **surf)
{
    int closed = kind == 0;
    int nvu = closed ? n : n + 1, nvv = closed ? m : m + 1, nv = nvu * nvv, nf = n * m;
    double *pos = malloc(3 * sizeof(double) * (size_t)nv), X0 = 0, DX = 3.0 / n, Y0 = 0, DY = 2.0 / m;
    if (closed) { DX = 2 * PI / n; DY = 2 * PI / m; }
    int *fs = malloc(sizeof(int) * (size_t)(nf + 1)), *fv = malloc(4 * sizeof(int) * (size_t)nf);
    for (int i = 0; i < nvu; i++)
        for (int j = 0; j < nvv; j++) {
            double F[6][3];
            base_map(kind, X0 + DX * i, Y0 + DY * j, F);
            memcpy(pos + 3 * (i * nvv + j), F[0], 3 * sizeof(double));
            pos[3 * (i * nvv + j) + 2] += offset;
        }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            int f = i * m + j, i1 = closed ? (i + 1) % n : i + 1, j1 = closed ? (j + 1) % m : j + 1;
            fs[f] = 4 * f;
            fv[4 * f] = i * nvv + j; fv[4 * f + 1] = i1 * nvv + j; fv[4 * f + 2] = i1 * nvv + j1; fv[4 * f + 3] = i * nvv + j1;
        }
    fs[nf] = 4 * nf;
    q2n_error err;
    if (q2n_mesh_from_arrays(nv, pos, nf, fs, fv, kind ? "graph" : "torus", mesh, &err)) {
        fprintf(stderr, "mesh: %s\n", err.message);
        return 0;
    }
    free(pos); free(fs); free(fv);
    *surf = q2n_surface_create(nf);
    unsigned seed = 7;
    double *cu = malloc(sizeof(double) * (n + 1)), *cv = malloc(sizeof(double) * (m + 1));
    for (int i = 0; i < n; i++) cu[i] = strength * 0.3 * (2 * frand(&seed) - 1);
    for (int j = 0; j < m; j++) cv[j] = strength * 0.3 * (2 * frand(&seed) - 1);
    /* scaled faces: one value per grid line (horizontal lines j carry cu, vertical lines i cv) */
    double *hl = malloc(sizeof(double) * (m + 1)), *vl = malloc(sizeof(double) * (n + 1));
    for (int j = 0; j <= m; j++) hl[j] = strength * 0.25 * (2 * frand(&seed) - 1);
    for (int i = 0; i <= n; i++) vl[i] = strength * 0.25 * (2 * frand(&seed) - 1);
    if (closed) { hl[m] = hl[0]; vl[n] = vl[0]; }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            rmap *r = calloc(1, sizeof *r);
            r->kind = kind; r->x0 = X0 + DX * i; r->dx = DX; r->y0 = Y0 + DY * j; r->dy = DY;
            r->cu = cu[i]; r->cv = cv[j];
            r->a = strength * 0.8 * (2 * frand(&seed) - 1);
            r->b = strength * 0.8 * (2 * frand(&seed) - 1);
            if (g_scaled) {
                r->scaled = 1;
                r->cu = r->cv = r->a = r->b = 0;
                r->cuA = hl[j]; r->cuB = hl[j + 1]; r->cvA = vl[i]; r->cvB = vl[i + 1];
            }
            q2n_surface_set_patch(*surf, i * m + j, Q2N_PATCH_AUGMENTED, r, rmap_eval, free);
        }
    free(cu); free(cv); free(hl); free(vl);
    return 1;
}

/* Independent checks of a model (tests/fit_check.h: bspline.c's evaluator and the construction's,
 * nothing of the fit's own): distance to the construction at 40 pseudo-random points per patch (foot
 * points: the fit may reparametrize), max normal angle at 6 random points per interior edge, and the
 * watertightness of the boundaries against the model's edge curves. */
static void independent(const q2n_nurbs_model *md, const q2n_surface *s, double *dev, double *ang, double *gap, int *nsame,
                        int *nsides)
{
    double diag = q2n_mesh_bbox_diag(md->mesh);
    *dev = fit_random_distance(md, s, 40, diag);
    *ang = fit_random_angle(md, 6);
    *gap = fit_boundary_gap(md, nsame, nsides) / diag;
}

static void run_case(const char *name, int kind, int n, int m, double strength, double tol, int cont, int solver)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(kind, n, m, strength, &mesh, &s)) { CHECK(0, "%s: build failed", name); return; }
    q2n_fit_options o;
    q2n_fit_options_default(&o);
    o.tol = tol;
    o.continuity = cont;
    o.solver = solver;
    q2n_nurbs_model *md = NULL;
    q2n_fit_report r;
    q2n_error err = {0, ""};
    q2n_status st = q2n_fit_surface(s, mesh, &o, &md, &r, &err);
    CHECK(st == Q2N_OK, "%s: fit failed: %s", name, err.message);
    if (md) {
        double dev, ang, gap;
        int nsame, nsides;
        independent(md, s, &dev, &ang, &gap, &nsame, &nsides);
        printf("%-28s faces %3d  spans %d/%d/%d  cp %d/%d/%d  rounds %d  max_dev %.2e rms %.2e (indep %.2e)  g0 %.1e  "
               "g1 %.2e deg (indep %.2e)  g2 %.2e (constr g1 %.1e g2 %.1e)  exact %d/%d  %.3f s\n",
               name, r.faces, r.spans_min, r.spans_median, r.spans_max, r.cp_min, r.cp_median, r.cp_max, r.rounds,
               r.max_dev_rel, r.rms_dev_rel, dev, r.g0_max_rel, r.g1_max_deg, ang, r.g2_max_rel, r.g1_construction_deg,
               r.g2_construction_rel, r.g1_exact_edges, r.interior_edges, r.t_total);
        printf("   times: sample %.3f build %.3f solve %.3f measure %.3f  samples %ld\n", r.t_sample, r.t_build, r.t_solve, r.t_measure, r.samples);
        CHECK(r.max_dev_rel <= tol, "%s: max_dev_rel %g > tol %g", name, r.max_dev_rel, tol);
        CHECK(dev <= 2 * tol, "%s: independent deviation %g > 2 tol", name, dev);
        CHECK(r.g0_max_rel <= 1e-12, "%s: g0 %g", name, r.g0_max_rel);
        CHECK(gap <= 1e-14, "%s: boundaries and edge curves differ by %g (diag)", name, gap);
        CHECK(nsides > 0 && nsame == nsides, "%s: %d of %d boundaries with the edge's knots not bit-identical", name,
              nsides - nsame, nsides);
        CHECK(r.g1_max_deg <= 0.01, "%s: g1 %g deg", name, r.g1_max_deg);
        CHECK(ang <= 0.01, "%s: independent g1 %g deg", name, ang);
        if (cont == 2) CHECK(r.g2_max_rel <= 0.01, "%s: g2 %g", name, r.g2_max_rel);
        if (g_scaled) {   /* a scale gluing: every interior edge exact, G1 and G2 to rounding */
            CHECK(r.g1_exact_edges == r.interior_edges, "%s: %d of %d edges exact", name, r.g1_exact_edges, r.interior_edges);
            CHECK(r.g1_max_deg <= 1e-6 && ang <= 1e-6, "%s: exact G1 %g deg (independent %g)", name, r.g1_max_deg, ang);
            if (cont == 2) CHECK(r.g2_max_rel <= 1e-6, "%s: exact G2 %g", name, r.g2_max_rel);
        }
        for (int k = 0; k < md->n; k++) {
            q2n_error e2;
            if (q2n_bspline_check(&md->patches[k], &e2)) { CHECK(0, "%s: patch %d: %s", name, k, e2.message); break; }
        }
    }
    q2n_nurbs_model_free(md);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* The three solver paths give the same control points (same LS problems). */
static void solver_agreement(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(0, 8, 6, 1.0, &mesh, &s)) { CHECK(0, "build"); return; }
    q2n_nurbs_model *md[3] = {NULL, NULL, NULL};
    for (int k = 0; k < 3; k++) {
        for (int cont = 1; cont <= 2; cont++) {
            q2n_fit_options o;
            q2n_fit_options_default(&o);
            o.solver = k;
            o.continuity = cont;
            o.threads = k == 0 ? 2 : 1;
            o.max_rounds = 1;      /* one round: all three solve identical problems */
            o.tol = 1.0;
            o.g1_tol_deg = 180;
            o.g2_tol_rel = 2e3;
            q2n_error err;
            q2n_nurbs_model *m = NULL;
            q2n_status st = q2n_fit_surface(s, mesh, &o, &m, NULL, &err);
            CHECK(st == Q2N_OK, "solver %d: %s", k, st ? err.message : "");
            if (cont == 1) md[k] = m;
            else q2n_nurbs_model_free(m);
        }
    }
    double diag = q2n_mesh_bbox_diag(mesh), d1 = 0, d2 = 0;
    for (int f = 0; md[0] && md[1] && md[2] && f < mesh->nf; f++) {
        const q2n_bspline_surface *a = &md[2]->patches[f], *b = &md[0]->patches[f], *c = &md[1]->patches[f];
        CHECK(a->ncp_u == b->ncp_u && a->ncp_v == b->ncp_v && a->ncp_u == c->ncp_u, "sizes differ");
        for (int i = 0; i < 3 * a->ncp_u * a->ncp_v; i++) {
            d1 = fmax(d1, fabs(a->cp[i] - b->cp[i]) / diag);
            d2 = fmax(d2, fabs(a->cp[i] - c->cp[i]) / diag);
        }
    }
    printf("solver agreement: Ceres per block (2 threads) vs direct QR %.2e, Ceres SPARSE_NORMAL_CHOLESKY vs direct %.2e\n", d1, d2);
    CHECK(d1 <= 1e-11, "Ceres dense vs direct: %g", d1);
    CHECK(d2 <= 1e-8, "Ceres sparse vs direct: %g", d2);
    for (int k = 0; k < 3; k++) q2n_nurbs_model_free(md[k]);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* A construction that does not pass through the mesh vertices: corners come from the patches
 * (one point per vertex, still bit-identical), the tolerance is met, and the report says how far
 * the corners are from the vertices. */
static void non_interpolating(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build_off(1, 6, 4, 1.0, 0.01, &mesh, &s)) { CHECK(0, "build"); return; }
    q2n_nurbs_model *md = NULL;
    q2n_fit_report r;
    q2n_error err;
    q2n_status st = q2n_fit_surface(s, mesh, NULL, &md, &r, &err);
    CHECK(st == Q2N_OK, "non-interpolating: %s", st ? err.message : "");
    double expect = 0.01 / q2n_mesh_bbox_diag(mesh);
    CHECK_NEAR(r.vertex_dev_max_rel, expect, 1e-9, "vertex_dev_max_rel");
    CHECK(r.max_dev_rel <= 1e-5 && r.g0_max_rel <= 1e-12, "non-interpolating: dev %g g0 %g", r.max_dev_rel, r.g0_max_rel);
    q2n_nurbs_model_free(md);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* Same input, same bytes: the model does not depend on the thread count (G2 mode, refinement). */
static void determinism(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(1, 6, 4, 1.0, &mesh, &s)) { CHECK(0, "build"); return; }
    q2n_nurbs_model *md[2] = {NULL, NULL};
    q2n_fit_report r[2];
    for (int i = 0; i < 2; i++) {
        q2n_fit_options o;
        q2n_fit_options_default(&o);
        o.continuity = 2;
        o.tol = 1e-6;
        o.threads = i ? 3 : 1;
        q2n_error err;
        CHECK(q2n_fit_surface(s, mesh, &o, &md[i], &r[i], &err) == Q2N_OK, "determinism fit");
    }
    int same = md[0] && md[1];
    for (int k = 0; same && k < mesh->nf; k++) {
        const q2n_bspline_surface *a = &md[0]->patches[k], *b = &md[1]->patches[k];
        same = a->ncp_u == b->ncp_u && a->ncp_v == b->ncp_v &&
               !memcmp(a->cp, b->cp, 3 * sizeof(double) * (size_t)a->ncp_u * a->ncp_v) &&
               !memcmp(a->knots_u, b->knots_u, sizeof(double) * (size_t)(a->ncp_u + 6));
    }
    CHECK(same, "1 and 3 threads give different models");
    CHECK(r[0].max_dev_rel == r[1].max_dev_rel && r[0].g2_max_rel == r[1].g2_max_rel, "reports differ");
    for (int i = 0; i < 2; i++) q2n_nurbs_model_free(md[i]);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* A surface inside the spline space (bi-quintic polynomial graph, linear parametrisation) is
 * reproduced to rounding with one span, by every stage (Hermite ends, twists, rows, interior). */
static void reproduction(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(2, 6, 4, 0.0, &mesh, &s)) { CHECK(0, "build"); return; }
    for (int cont = 1; cont <= 2; cont++) {
        q2n_fit_options o;
        q2n_fit_options_default(&o);
        o.continuity = cont;
        o.tol = 1e-9;
        q2n_nurbs_model *md = NULL;
        q2n_fit_report r;
        q2n_error err;
        q2n_status st = q2n_fit_surface(s, mesh, &o, &md, &r, &err);
        CHECK(st == Q2N_OK, "reproduction: %s", st ? err.message : "");
        printf("reproduction G%d: max_dev %.2e spans %d rounds %d\n", cont, r.max_dev_rel, r.spans_max, r.rounds);
        /* corner jets are one-sided differences with h = 0.002: rounding ~ eps |S| / h^2 */
        CHECK(r.max_dev_rel <= 1e-12, "polynomial not reproduced: %g", r.max_dev_rel);
        CHECK(r.spans_max == 1 && r.rounds == 1, "refined a reproduced surface");
        q2n_nurbs_model_free(md);
    }
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* fit_surface_eval (second order, used by the measurements) against bspline.c's evaluator and
 * central differences of it; the direct QR on a consistent overdetermined system. */
/* Largest relative difference between a side frame F (S, d_t, d_s, d_tt, d_ts, d_ss at (t, 0) of
 * side i) and the general evaluation of surface b turned into that side's frame. */
static double frame_error(const q2n_bspline_surface *b, int i, double t, const double F[6][3])
{
    double u, v, o[18], D[6][3], e = 0;
    q2n_side_uv(i, t, 0.0, &u, &v);
    q2n_fit_surface_eval(b, u, v, 2, o);
    q2n_side_derivs(i, 2, o, D);
    for (int r = 0; r < 6; r++)
        for (int c = 0; c < 3; c++) e = fmax(e, fabs(F[r][c] - D[r][c]) / (1 + fabs(D[r][c])));
    return e;
}

static void internals(void)
{
    q2n_bspline_surface b;
    double ku[14], kv[12], cp[3 * 8 * 6];
    b.deg_u = b.deg_v = 5; b.ncp_u = 8; b.ncp_v = 6; b.knots_u = ku; b.knots_v = kv; b.cp = cp; b.weights = NULL;
    q2n_fit_knots_uniform(3, ku);
    q2n_fit_knots_uniform(1, kv);
    unsigned seed = 3;
    for (int i = 0; i < 3 * 48; i++) cp[i] = frand(&seed);
    double emax = 0, dmax = 0, h = 1e-5;
    for (int q = 0; q < 50; q++) {
        double u = frand(&seed), v = frand(&seed), o[18], p[3], du[3], dv[3], pu[3], pv[3], mu[3], mv[3];
        u = 0.02 + 0.96 * u; v = 0.02 + 0.96 * v;
        q2n_fit_surface_eval(&b, u, v, 2, o);
        q2n_bspline_eval(&b, u, v, p, du, dv);
        for (int c = 0; c < 3; c++)
            emax = fmax(emax, fmax(fabs(o[c] - p[c]), fmax(fabs(o[3 + c] - du[c]), fabs(o[6 + c] - dv[c]))));
        q2n_bspline_eval(&b, u + h, v, p, pu, pv);
        q2n_bspline_eval(&b, u - h, v, p, mu, mv);
        for (int c = 0; c < 3; c++) {
            dmax = fmax(dmax, fabs(o[9 + c] - (pu[c] - mu[c]) / (2 * h)) / (1 + fabs(o[9 + c])));
            dmax = fmax(dmax, fabs(o[12 + c] - (pv[c] - mv[c]) / (2 * h)) / (1 + fabs(o[12 + c])));
        }
        q2n_bspline_eval(&b, u, v + h, p, pu, pv);
        q2n_bspline_eval(&b, u, v - h, p, mu, mv);
        for (int c = 0; c < 3; c++) dmax = fmax(dmax, fabs(o[15 + c] - (pv[c] - mv[c]) / (2 * h)) / (1 + fabs(o[15 + c])));
    }
    CHECK(emax <= 1e-13, "fit_surface_eval vs q2n_bspline_eval: %g", emax);
    CHECK(dmax <= 1e-6, "second derivatives vs central differences: %g", dmax);
    /* the measurement's grid evaluation: every point the same sum as the pointwise one, including
     * parameters on knots and at the ends */
    {
        double us[7] = {0.0, 1.0 / 3, 0.2, 0.5, 2.0 / 3, 0.9, 1.0}, vs[5] = {0.0, 0.25, 0.5, 0.75, 1.0}, G[3 * 35];
        CHECK(q2n_fit_surface_grid(&b, 7, us, 5, vs, G) == 0, "grid evaluation");
        int diff = 0;
        for (int j = 0; j < 5; j++)
            for (int i = 0; i < 7; i++) {
                double o[3];
                q2n_fit_surface_eval(&b, us[i], vs[j], 0, o);
                diff += memcmp(o, G + 3 * (j * 7 + i), sizeof o) != 0;
            }
        CHECK(diff == 0, "grid evaluation differs from the pointwise one at %d of 35 points", diff);
    }

    /* the measurement's side evaluation (q2n_fit_side_spline: the along basis and the first three
     * rows of control points) against the general evaluation turned into each side's frame, on
     * non-uniform knots in both directions */
    {
        double ku2[15], kv2[14], kur[15], kvr[14], cp2[3 * 9 * 8];
        const double bu[3] = {0.15, 0.4, 0.8}, bv[2] = {0.3, 0.35};
        q2n_fit_knots_from_breaks(3, bu, ku2);
        q2n_fit_knots_from_breaks(2, bv, kv2);
        for (int q = 0; q < 15; q++) kur[q] = 1.0 - ku2[14 - q];
        for (int q = 0; q < 14; q++) kvr[q] = 1.0 - kv2[13 - q];
        for (int i = 0; i < 3 * 72; i++) cp2[i] = frand(&seed);
        fit_patch fp;
        memset(&fp, 0, sizeof fp);
        fp.nu = 9; fp.nv = 8; fp.mu = 4; fp.mv = 3;
        fp.ku = ku2; fp.kv = kv2; fp.kur = kur; fp.kvr = kvr; fp.cp = cp2;
        fit_ctx fc;
        memset(&fc, 0, sizeof fc);
        fc.p = &fp;
        q2n_bspline_surface b2 = {5, 5, 9, 8, ku2, kv2, cp2, NULL};
        /* per side: the side evaluation at 21 points, and the same frames from each span's polynomial
         * expansion (q2n_fit_side_poly_at / _frame, the dense jump samples of fit.c), expanded at every
         * span start of the side's knots and summed at 9 points of the span, its ends included */
        double smax = 0, pmax = 0;
        int npts = 0;
        for (int i = 0; i < 4; i++) {
            fit_side sd = q2n_fit_make_side(&fc, 0, i);
            double Ns[3][Q2N_FIT_DEG + 1];
            q2n_fit_basis(Q2N_FIT_DEG, sd.ks, 0.0, 2, Ns);
            for (int q = 0; q <= 20; q++) {
                double t = q == 20 ? 0.4 : q / 19.0, F[6][3];
                q2n_fit_side_spline(&fc, &sd, Ns, t, F);
                smax = fmax(smax, frame_error(&b2, i, t, F));
            }
            for (int sp = Q2N_FIT_DEG; sp < sd.nt; sp++) {
                double a = sd.kt[sp], b = sd.kt[sp + 1];
                if (!(b > a)) continue;
                q2n_fit_side_poly C;
                q2n_fit_side_poly_at(&fc, &sd, a, C);
                for (int q = 0; q <= 8; q++) {
                    double t = a + (b - a) * q / 8.0, F[6][3];
                    q2n_fit_side_poly_frame(C, Ns, t - a, F);
                    pmax = fmax(pmax, frame_error(&b2, i, t, F));
                    npts++;
                }
            }
        }
        CHECK(smax <= 1e-12, "side evaluation vs the general one in the side's frame: %g", smax);
        CHECK(npts >= 4 * 3 * 9 && pmax <= 1e-11, "span polynomials vs the general evaluation: %g at %d points", pmax, npts);
    }

    q2n_fit_ls ls;
    q2n_fit_ls_init(&ls);
    q2n_fit_ls_item_begin(&ls);
    int v0, v1;
    q2n_fit_ls_new_var(&ls, &v0);
    q2n_fit_ls_new_var(&ls, &v1);
    const double X0[3] = {1, -2, 0.5}, X1[3] = {3, 0.25, -1};
    for (int r = 0; r < 5; r++) {          /* rows (1, r) . (X0, X1) = rhs, consistent */
        double rhs[3];
        for (int c = 0; c < 3; c++) rhs[c] = X0[c] + r * X1[c];
        q2n_fit_ls_row(&ls, rhs);
        q2n_fit_ls_entry(&ls, v0, 1.0);
        q2n_fit_ls_entry(&ls, v1, (double)r);
    }
    q2n_fit_ls_item_end(&ls);
    q2n_error err;
    CHECK(q2n_fit_ls_solve_direct(&ls, &err) == Q2N_OK, "direct solve");
    double e = 0;
    for (int c = 0; c < 3; c++) e = fmax(e, fmax(fabs(ls.x[c] - X0[c]), fabs(ls.x[3 + c] - X1[c])));
    CHECK(e <= 1e-14, "direct QR solution error %g", e);
    CHECK(q2n_fit_ls_solve_ceres(&ls, 1, 1, &err) == Q2N_OK, "ceres solve");
    e = 0;
    for (int c = 0; c < 3; c++) e = fmax(e, fmax(fabs(ls.x[c] - X0[c]), fabs(ls.x[3 + c] - X1[c])));
    CHECK(e <= 1e-12, "Ceres solution error %g", e);
    q2n_fit_ls_free(&ls);

    /* both Ceres paths of the shim: a block of 20 unknowns (ceres::Solve, DENSE_QR) and one of 2
     * (TinySolver) whose two columns are equal (singular normal equations): consistent rows are met
     * either way, and the singular block's two unknowns share what the rows fix (their sum) */
    q2n_fit_ls_init(&ls);
    q2n_fit_ls_item_begin(&ls);
    int big[20];
    for (int j = 0; j < 20; j++) q2n_fit_ls_new_var(&ls, &big[j]);
    unsigned sd = 11;
    double Xb[20][3];
    for (int j = 0; j < 20; j++)
        for (int c = 0; c < 3; c++) Xb[j][c] = frand(&sd);
    double coef[60][20];
    for (int r = 0; r < 60; r++) {
        double rhs[3] = {0, 0, 0};
        for (int j = 0; j < 20; j++) {
            coef[r][j] = frand(&sd);
            for (int c = 0; c < 3; c++) rhs[c] += coef[r][j] * Xb[j][c];
        }
        q2n_fit_ls_row(&ls, rhs);
        for (int j = 0; j < 20; j++) q2n_fit_ls_entry(&ls, big[j], coef[r][j]);
    }
    q2n_fit_ls_item_end(&ls);
    q2n_fit_ls_item_begin(&ls);
    int s0, s1;
    q2n_fit_ls_new_var(&ls, &s0);
    q2n_fit_ls_new_var(&ls, &s1);
    for (int r = 0; r < 4; r++) {
        double rhs[3] = {2.0 * (r + 1), -1.0 * (r + 1), 0.5 * (r + 1)}; /* (r+1)(a + b) = rhs: a + b = (2, -1, 0.5) */
        q2n_fit_ls_row(&ls, rhs);
        q2n_fit_ls_entry(&ls, s0, r + 1.0);
        q2n_fit_ls_entry(&ls, s1, r + 1.0);
    }
    q2n_fit_ls_item_end(&ls);
    CHECK(q2n_fit_ls_solve_ceres(&ls, 2, 1, &err) == Q2N_OK, "ceres solve of the two blocks: %s", err.message);
    e = 0;
    for (int j = 0; j < 20; j++)
        for (int c = 0; c < 3; c++) e = fmax(e, fabs(ls.x[3 * big[j] + c] - Xb[j][c]));
    CHECK(e <= 1e-10, "Ceres (DENSE_QR block of 20) solution error %g", e);
    static const double sum[3] = {2, -1, 0.5};
    e = 0;
    for (int c = 0; c < 3; c++) {
        double a = ls.x[3 * s0 + c], b = ls.x[3 * s1 + c];
        e = fmax(e, isfinite(a) && isfinite(b) ? fabs(a + b - sum[c]) : INFINITY);
    }
    CHECK(e <= 1e-9, "Ceres (singular block of 2): a + b off by %g", e);
    q2n_fit_ls_free(&ls);
}

/* The interior stage (fit_interior.c: two 1-D passes with cached pseudo-inverses) against the 2-D
 * least-squares problem it stands for, solved whole by LAPACK's QR on the Kronecker matrix: two
 * patches of the skewed graph on the same non-uniform knots (4 x 3 spans), border rows 0..2 fixed
 * at random values, the 3 x 2 block inside free.  The two patches share their two matrices (two
 * cache entries, not four), and a patch refitted from the cache gets the same bits. */
static void interior_stage(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(1, 2, 1, 0.6, &mesh, &s)) { CHECK(0, "interior stage: build failed"); return; }
    const double bu[3] = {0.2, 0.5, 0.7}, bv[2] = {0.3, 0.6};
    enum { NU = 9, NV = 8 };
    q2n_fit_report rep;
    q2n_error err;
    memset(&rep, 0, sizeof rep);
    fit_ctx fc;
    memset(&fc, 0, sizeof fc);
    fc.s = s; fc.m = mesh; fc.rep = &rep; fc.err = &err;
    fc.o.threads = 1; fc.o.solver = Q2N_FIT_SOLVER_CERES;
    fc.pinv.budget = (long)Q2N_FIT_PINV_CACHE_BYTES;
    atomic_init(&fc.cache_bytes, 0);
    q2n_fit_ls_init(&fc.ls);
    fit_patch P[2];
    memset(P, 0, sizeof P);
    fc.p = P;
    unsigned seed = 5;
    double ku[NU + 6], kv[NV + 6], cp[2][3 * NU * NV];
    unsigned char fixed[2][NU * NV];
    int var[2][NU * NV];
    q2n_fit_knots_from_breaks(3, bu, ku);
    q2n_fit_knots_from_breaks(2, bv, kv);
    for (int k = 0; k < 2; k++) {
        P[k].nu = NU; P[k].nv = NV; P[k].mu = NU - 5; P[k].mv = NV - 5;
        P[k].ku = ku; P[k].kv = kv; P[k].cp = cp[k]; P[k].fixed = fixed[k]; P[k].var = var[k];
        for (int g = 0; g < NU * NV; g++) {
            int a = g % NU, b = g / NU;
            fixed[k][g] = a < 3 || a > NU - 4 || b < 3 || b > NV - 4;
            var[k][g] = -1;
            for (int c = 0; c < 3; c++) cp[k][3 * g + c] = fixed[k][g] ? 2 * frand(&seed) - 1 : 1e300;
        }
    }
    const int list[2] = {0, 1};
    CHECK(q2n_fit_stage_interior(&fc, list, 2) == Q2N_OK, "interior stage: %s", err.message);
    CHECK(fc.pinv.n == 2, "interior stage: %d cached matrices for two patches on the same knots (2 expected)", fc.pinv.n);
    /* the reference: every sample row, every free unknown */
    double us[64], vs[64];
    int Nu = q2n_fit_sample_params(NU, ku, Q2N_FIT_SAMPLES_PER_SPAN, us), Nv = q2n_fit_sample_params(NV, kv, Q2N_FIT_SAMPLES_PER_SPAN, vs);
    int nfree = (NU - 6) * (NV - 6), mrow = Nu * Nv;
    double *A = calloc((size_t)mrow * nfree, sizeof(double)), *B = calloc((size_t)mrow * 3, sizeof(double));
    double *S = malloc(3 * sizeof(double) * (size_t)mrow);
    double emax = 0;
    for (int k = 0; k < 2 && A && B && S; k++) {
        memset(A, 0, sizeof(double) * (size_t)mrow * nfree);
        q2n_surface_eval_grid_pos(s, k, Nu, us, Nv, vs, S);
        for (int j = 0; j < Nv; j++)
            for (int i = 0; i < Nu; i++) {
                int r = j * Nu + i;
                double Bu[3][Q2N_FIT_DEG + 1], Bv[3][Q2N_FIT_DEG + 1];
                int su = q2n_fit_span(NU, ku, us[i]), sv = q2n_fit_span(NV, kv, vs[j]);
                q2n_fit_basis(su, ku, us[i], 0, Bu);
                q2n_fit_basis(sv, kv, vs[j], 0, Bv);
                for (int c = 0; c < 3; c++) B[(size_t)c * mrow + r] = S[3 * r + c];
                for (int b = 0; b <= Q2N_FIT_DEG; b++)
                    for (int a = 0; a <= Q2N_FIT_DEG; a++) {
                        int ga = su - Q2N_FIT_DEG + a, gb = sv - Q2N_FIT_DEG + b, g = gb * NU + ga;
                        double w = Bu[0][a] * Bv[0][b];
                        if (ga < 3 || ga > NU - 4 || gb < 3 || gb > NV - 4)   /* fixed (the stage fixes all) */
                            for (int c = 0; c < 3; c++) B[(size_t)c * mrow + r] -= w * cp[k][3 * g + c];
                        else
                            A[(size_t)((gb - 3) * (NU - 6) + ga - 3) * mrow + r] += w;
                    }
            }
        int rank = 0;
        CHECK(q2n_dense_lstsq(mrow, nfree, 3, A, mrow, B, mrow, 1e-13, &rank) == 0 && rank == nfree, "reference solve");
        for (int b = 3; b <= NV - 4; b++)
            for (int a = 3; a <= NU - 4; a++)
                for (int c = 0; c < 3; c++)
                    emax = fmax(emax, fabs(cp[k][3 * (b * NU + a) + c] - B[(size_t)c * mrow + (b - 3) * (NU - 6) + a - 3]));
    }
    printf("interior stage vs the whole 2-D least squares (LAPACK QR): %.2e\n", emax);
    CHECK(emax <= 1e-11, "interior stage vs the 2-D least-squares solution: %g", emax);
    /* patch 1 again, its free points unfixed: from the cache, the same bits */
    double keep[3 * NU * NV];
    memcpy(keep, cp[1], sizeof keep);
    for (int g = 0; g < NU * NV; g++)
        if (!(g % NU < 3 || g % NU > NU - 4 || g / NU < 3 || g / NU > NV - 4)) fixed[1][g] = 0, cp[1][3 * g] = 1e300;
    CHECK(q2n_fit_stage_interior(&fc, list + 1, 1) == Q2N_OK && fc.pinv.n == 2 && !memcmp(keep, cp[1], sizeof keep),
          "interior stage from the cache: %d entries, same bits %d", fc.pinv.n, !memcmp(keep, cp[1], sizeof keep));
    /* and with no room to keep anything: solved again, the same bits, nothing kept */
    q2n_fit_pinv_free(&fc.pinv);
    fc.pinv.budget = 0;
    for (int g = 0; g < NU * NV; g++)
        if (!(g % NU < 3 || g % NU > NU - 4 || g / NU < 3 || g / NU > NV - 4)) fixed[1][g] = 0, cp[1][3 * g] = 1e300;
    CHECK(q2n_fit_stage_interior(&fc, list + 1, 1) == Q2N_OK && fc.pinv.n == 0 && !memcmp(keep, cp[1], sizeof keep),
          "interior stage without a cache budget: %d entries kept, same bits %d", fc.pinv.n,
          !memcmp(keep, cp[1], sizeof keep));
    free(A); free(B); free(S);
    for (int k = 0; k < 2; k++) { free(P[k].gc.u); free(P[k].gc.v); free(P[k].gc.val); free(P[k].gc.have); }
    q2n_fit_pinv_free(&fc.pinv);
    q2n_fit_ls_free(&fc.ls);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* Knot insertion against evaluation; a vector that is not a refinement is refused. */
static void knot_insertion(void)
{
    double br[2] = {0.25, 0.5}, br2[5] = {0.125, 0.25, 0.5, 0.625, 0.75}, bad[3] = {0.25, 0.375, 0.75};
    double kv[14], kv2[17], kb[15], cp[3 * 8], cp2[3 * 11], cb[3 * 9];
    q2n_fit_knots_from_breaks(2, br, kv);
    q2n_fit_knots_from_breaks(5, br2, kv2);
    q2n_fit_knots_from_breaks(3, bad, kb);
    unsigned seed = 5;
    for (int i = 0; i < 24; i++) cp[i] = frand(&seed);
    CHECK(q2n_fit_curve_refine(8, kv, cp, 3, 11, kv2, cp2) == 0, "refinement refused");
    q2n_bspline_curve a = {5, 8, kv, cp}, b = {5, 11, kv2, cp2};
    double e = 0;
    for (int q = 0; q <= 200; q++) {
        double pa[3], pb[3], da[3], db[3];
        q2n_bspline_curve_eval(&a, q / 200.0, pa, da);
        q2n_bspline_curve_eval(&b, q / 200.0, pb, db);
        for (int c = 0; c < 3; c++) e = fmax(e, fmax(fabs(pa[c] - pb[c]), 1e-2 * fabs(da[c] - db[c])));
    }
    CHECK(e <= 1e-14, "knot insertion changed the curve by %g", e);
    CHECK(q2n_fit_curve_refine(8, kv, cp, 3, 9, kb, cb) != 0, "a knot vector without 0.5 accepted as a refinement");
}

/* core/dense.h: rank-revealing least squares and the null-space form of equality constraints,
 * against hand-made problems. */
static void dense(void)
{
    /* x + y = 2, x - y = 0, 2x + 2y = 4 (consistent, full rank): x = y = 1 */
    double A[6] = {1, 1, 2, 1, -1, 2}, B[3] = {2, 0, 4};
    int rank = 0;
    CHECK(q2n_dense_lstsq(3, 2, 1, A, 3, B, 3, 1e-13, &rank) == 0 && rank == 2, "lstsq rank %d", rank);
    CHECK(fabs(B[0] - 1) <= 1e-15 && fabs(B[1] - 1) <= 1e-15, "lstsq %g %g", B[0], B[1]);
    /* dependent columns: min-norm solution of [1 1] [x y]^T = 2 is (1, 1) */
    double A2[4] = {1, 1, 1, 1}, B2[2] = {2, 2};
    CHECK(q2n_dense_lstsq(2, 2, 1, A2, 2, B2, 2, 1e-13, &rank) == 0 && rank == 1, "rank-deficient: rank %d", rank);
    CHECK(fabs(B2[0] - 1) <= 1e-14 && fabs(B2[1] - 1) <= 1e-14, "min-norm %g %g", B2[0], B2[1]);
    /* constraints x0 - x1 = 1 and 2 x0 - 2 x1 = 2 (dependent, consistent) on 3 unknowns: null space
     * spanned by (1,1,0)/sqrt2 and (0,0,1), particular min-norm (0.5, -0.5, 0) */
    double C[6] = {1, 2, -1, -2, 0, 0}, D[2] = {1, 2}, Z[9], Xp[3], resid;
    int k = 0;
    CHECK(q2n_dense_nullspace(2, 3, C, 2, 1, D, 2, 1e-12, Z, &k, Xp, &resid) == 0 && k == 2, "null space dim %d", k);
    CHECK(fabs(Xp[0] - 0.5) <= 1e-15 && fabs(Xp[1] + 0.5) <= 1e-15 && fabs(Xp[2]) <= 1e-15 && resid <= 1e-15,
          "particular %g %g %g (resid %g)", Xp[0], Xp[1], Xp[2], resid);
    double cz = 0, zz = 0;
    for (int j = 0; j < k; j++) {
        cz = fmax(cz, fabs(Z[3 * j] - Z[3 * j + 1]));   /* C Z = 0 */
        for (int l = 0; l < k; l++) {
            double d = Z[3 * j] * Z[3 * l] + Z[3 * j + 1] * Z[3 * l + 1] + Z[3 * j + 2] * Z[3 * l + 2];
            zz = fmax(zz, fabs(d - (j == l)));
        }
    }
    CHECK(cz <= 1e-15 && zz <= 1e-15, "null space basis: C Z %g, orthonormality %g", cz, zz);
    /* inconsistent constraints report their residual */
    double D3[2] = {1, 3};
    q2n_dense_nullspace(2, 3, C, 2, 1, D3, 2, 1e-12, Z, &k, Xp, &resid);
    CHECK(resid > 0.1, "inconsistent constraints: residual %g", resid);
}

/* The dimension count behind the exact gluing (docs/fit.md, "Which relations are exact").  Rows
 * f_L, f_R and an edge curve gamma in the quintic C4 spline space of m spans (dim m + 5 each), glued
 * by the identity f_R = a f_L + b gamma' on every span (7 points per span: the pieces have degree
 * <= 6).  The solution space has dimension
 *   2m + 10 for a constant scale a and b = 0 (f_L, gamma free, f_R = a f_L): any knots work;
 *   m + 10  for a linear a and b = 0 (a f_L must stay quintic and C4: f_L is one quartic);
 *   m + 10  for a constant a and a quadratic b (b gamma' must stay quintic and C4: gamma is one quartic),
 * so beyond one span a non-constant gluing leaves the rows or the curve one polynomial. */
static void dimension_counts(void)
{
    for (int m = 1; m <= 4; m++)
        for (int kind = 0; kind < 3; kind++) {
            int nb = m - 1, n = m + 5, nu = 3 * n, nc = 7 * m;
            double br[8], kv[32];
            for (int i = 0; i < nb; i++) br[i] = (i + 1.0) / m + 0.07 * (i % 2 ? 1 : -1) / m;   /* non-uniform */
            q2n_fit_knots_from_breaks(nb, br, kv);
            double *C = calloc((size_t)nc * nu, sizeof(double)), *D = calloc((size_t)nc, sizeof(double));
            double *Z = malloc(sizeof(double) * (size_t)nu * nu), Xp[64], resid;
            int row = 0;
            for (int sp = 0; sp < m; sp++)
                for (int q = 0; q < 7; q++) {
                    double t = kv[5 + sp] + (kv[6 + sp] - kv[5 + sp]) * (q + 0.5) / 7.0, N[3][6];
                    int span = q2n_fit_span(n, kv, t);
                    q2n_fit_basis(span, kv, t, 1, N);
                    double a = kind == 1 ? 1.3 + 0.4 * t : 1.3, b = kind == 2 ? 0.5 - 0.8 * t + 0.6 * t * t : 0.0;
                    for (int j = 0; j < 6; j++) {
                        int c = span - 5 + j;
                        C[(size_t)c * nc + row] -= a * N[0][j];            /* f_L */
                        C[(size_t)(n + c) * nc + row] += N[0][j];          /* f_R */
                        C[(size_t)(2 * n + c) * nc + row] -= b * N[1][j];  /* gamma' */
                    }
                    row++;
                }
            int k = -1;
            q2n_dense_nullspace(nc, nu, C, nc, 1, D, nc, 1e-10, Z, &k, Xp, &resid);
            int expect = kind == 0 ? 2 * m + 10 : m + 10;
            CHECK(k == expect, "gluing %s, %d spans: solution space %d, expected %d",
                  kind == 0 ? "constant scale" : kind == 1 ? "linear scale" : "scale + quadratic tangential", m, k, expect);
            free(C); free(D); free(Z);
        }
}

/* max_spans is a hard cap on every patch direction. */
static void span_cap(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(0, 4, 3, 1.0, &mesh, &s)) { CHECK(0, "build"); return; }
    q2n_fit_options o;
    q2n_fit_options_default(&o);
    o.tol = 1e-9;
    o.max_spans = 3;
    q2n_nurbs_model *md = NULL;
    q2n_fit_report r;
    q2n_error err;
    q2n_fit_surface(s, mesh, &o, &md, &r, &err);
    int worst = 0;
    for (int k = 0; md && k < md->n; k++) {
        worst = worst > md->patches[k].ncp_u - 5 ? worst : md->patches[k].ncp_u - 5;
        worst = worst > md->patches[k].ncp_v - 5 ? worst : md->patches[k].ncp_v - 5;
    }
    CHECK(md && worst <= 3, "max_spans 3: a patch direction has %d spans", worst);
    q2n_nurbs_model_free(md);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

/* Errors: uncovered patches, wrong sizes, targets out of reach (model still returned). */
/* The report's rim (q2n_fit_report_rim) against a closed form: two bilinear quads side by side (as
 * the fit's quintic patches: control points on the bilinear grid) whose shared boundary vertex
 * (1, 0.2) turns the rim by 2 atan(0.2); the other vertex of two faces is straight, the four corners
 * of one face are not counted. */
static void rim_report(void)
{
    static const double pos[] = {0, 0, 0, 1, 0.2, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    static const int fs[] = {0, 4, 8}, fvv[] = {0, 1, 4, 3, 1, 2, 5, 4};
    q2n_mesh *m = NULL;
    q2n_error err = {0, ""};
    CHECK(q2n_mesh_from_arrays(6, pos, 2, fs, fvv, "rim", &m, &err) == Q2N_OK, "rim mesh: %s", err.message);
    if (!m) return;
    double kn[12] = {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1}, cp[2][3 * 36];
    q2n_bspline_surface P[2];
    for (int k = 0; k < 2; k++) {
        const double *c[4];
        for (int i = 0; i < 4; i++) c[i] = pos + 3 * fvv[4 * k + i];
        for (int j = 0; j < 6; j++)
            for (int i = 0; i < 6; i++)
                for (int d = 0; d < 3; d++) { /* u along v0 -> v1, v along v0 -> v3 */
                    double x = i / 5.0, y = j / 5.0;
                    cp[k][3 * (6 * j + i) + d] = (1 - x) * (1 - y) * c[0][d] + x * (1 - y) * c[1][d] + x * y * c[2][d] + (1 - x) * y * c[3][d];
                }
        P[k] = (q2n_bspline_surface){5, 5, 6, 6, kn, kn, cp[k], NULL};
    }
    q2n_nurbs_model md = {2, P, m, 1e-5, NULL};
    q2n_fit_report rep;
    memset(&rep, 0, sizeof rep);
    q2n_fit_report_rim(&md, NULL, &rep);
    double want = 2 * atan(0.2) * 180 / Q2N_PI;
    printf("rim of two bilinear quads: %d vertices, turn %.15g deg (closed form %.15g)\n", rep.rim_vertices, rep.rim_max_deg, want);
    CHECK(rep.rim_vertices == 2 && fabs(rep.rim_max_deg - want) <= 1e-12, "rim: %d vertices, %.15g deg, want 2 and %.15g",
          rep.rim_vertices, rep.rim_max_deg, want);
    CHECK(rep.rim_curv_rel <= 1e-12, "rim of straight edges: curvature jump %.3g", rep.rim_curv_rel);
    q2n_mesh_free(m);
}

static void errors_and_report(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(1, 3, 2, 1.0, &mesh, &s)) { CHECK(0, "build"); return; }
    q2n_error err;
    q2n_nurbs_model *md = NULL;
    q2n_surface *bad = q2n_surface_create(mesh->nf);
    CHECK(q2n_fit_surface(bad, mesh, NULL, &md, NULL, &err) == Q2N_ERR_UNSUPPORTED && md == NULL, "uncovered accepted");
    CHECK(strstr(err.message, "face 0") != NULL, "message names the face: %s", err.message);
    q2n_surface_free(bad);
    bad = q2n_surface_create(mesh->nf + 1);
    CHECK(q2n_fit_surface(bad, mesh, NULL, &md, NULL, &err) == Q2N_ERR_ARG, "size mismatch accepted");
    q2n_surface_free(bad);
    q2n_fit_options o;
    q2n_fit_options_default(&o);
    o.tol = 1e-12;
    o.max_spans = 2;
    q2n_fit_report r;
    q2n_status st = q2n_fit_surface(s, mesh, &o, &md, &r, &err);
    CHECK(st == Q2N_ERR_GEOMETRY && md != NULL && !r.tol_met, "unreachable tolerance: status %d", st);
    CHECK(strstr(err.message, "face") != NULL, "message: %s", err.message);
    q2n_nurbs_model_free(md);
    md = NULL;
    st = q2n_fit_surface(s, mesh, NULL, &md, &r, &err);
    CHECK(st == Q2N_OK, "default fit: %s", st ? err.message : "");
    const char *path = chk_scratch("test_fit_report.json");
    CHECK(q2n_fit_report_write_json(&r, path, &err) == Q2N_OK, "json: %s", err.message);
    FILE *f = fopen(path, "r");
    char buf[4096] = "";
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    buf[n] = 0;
    if (f) fclose(f);
    const char *keys[] = {"\"faces\": 6", "\"max_dev_rel\"", "\"rms_dev_rel\"", "\"vertex_dev_max_rel\"",
                          "\"g0_max_rel\"", "\"g1_max_deg\"", "\"g2_max_rel\"", "\"spans_per_patch\"",
                          "\"timings_s\"", "\"tol_met\": true"};
    for (int i = 0; i < 10; i++) CHECK(strstr(buf, keys[i]) != NULL, "json lacks %s", keys[i]);
    const char *p = strstr(buf, "\"max_dev_rel\": ");
    CHECK(p && fabs(atof(p + 15) - r.max_dev_rel) <= 1e-5 * r.max_dev_rel, "json max_dev_rel value");
    CHECK(q2n_fit_report_write_json(&r, "/nonexistent_dir/x.json", &err) == Q2N_ERR_IO, "unwritable path");
    remove(path);
    q2n_nurbs_model_free(md);
    q2n_surface_free(s);
    q2n_mesh_free(mesh);
}

int main(void)
{
    internals();
    interior_stage();
    knot_insertion();
    dense();
    dimension_counts();
    span_cap();
    reproduction();
    solver_agreement();
    determinism();
    non_interpolating();
    errors_and_report();
    rim_report();
    run_case("torus 8x6 G1 1e-5", 0, 8, 6, 1.0, 1e-5, 1, Q2N_FIT_SOLVER_CERES);
    run_case("torus 8x6 G1 1e-6", 0, 8, 6, 1.0, 1e-6, 1, Q2N_FIT_SOLVER_CERES);
    run_case("graph 6x4 G1 1e-5", 1, 6, 4, 1.0, 1e-5, 1, Q2N_FIT_SOLVER_CERES);
    run_case("graph 6x4 G1 1e-6", 1, 6, 4, 1.0, 1e-6, 1, Q2N_FIT_SOLVER_CERES);
    run_case("torus 8x6 G2 1e-5", 0, 8, 6, 1.0, 1e-5, 2, Q2N_FIT_SOLVER_CERES);
    run_case("graph 6x4 G2 1e-6", 1, 6, 4, 1.0, 1e-6, 2, Q2N_FIT_SOLVER_CERES);
    g_scaled = 1;   /* scale gluing that varies along the edges: reparametrized, exact */
    run_case("scaled torus 8x6 G1 1e-5", 0, 8, 6, 1.0, 1e-5, 1, Q2N_FIT_SOLVER_CERES);
    run_case("scaled graph 6x4 G2 1e-5", 1, 6, 4, 1.0, 1e-5, 2, Q2N_FIT_SOLVER_CERES);
    run_case("scaled torus 8x6 G2 1e-6", 0, 8, 6, 1.0, 1e-6, 2, Q2N_FIT_SOLVER_DIRECT);
    CHECK_DONE("test_fit");
}
