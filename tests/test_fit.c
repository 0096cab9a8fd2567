/* test_fit.c — the bi-quintic fit (src/fit/): tolerance, watertightness, G1/G2, solvers.
 *
 * Test surfaces are exact non-polynomial maps attached with q2n_surface_set_patch: a torus and
 * a curved graph z = f(x,y), each face mapped through its own non-linear reparametrisation, so
 * neighbours join G-infinity geometrically but are NOT parametrically C1 (cross-boundary
 * derivatives differ by face-dependent factors, as for the augmented surfaces, seed 003 Prop. 2).
 * References are independent of the fit: the closed-form maps, bspline.c's evaluator (not the
 * fit's own), closed-form polynomial reproduction, and the direct QR path vs Ceres. */
#include "check.h"
#include "fit_check.h"
#include "fit/fit.h"
#include "fit/fit_internal.h"
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
    /* U = u + cu u(1-u) + b u(1-u) v(1-v),  V = v + cv v(1-v) + a u(1-u) v(1-v) */
    double pu = u * (1 - u), pv = v * (1 - v), pu1 = 1 - 2 * u, pv1 = 1 - 2 * v;
    double U = u + m->cu * pu + m->b * pu * pv, V = v + m->cv * pv + m->a * pu * pv;
    double Uu = 1 + m->cu * pu1 + m->b * pu1 * pv, Uv = m->b * pu * pv1;
    double Vv = 1 + m->cv * pv1 + m->a * pu * pv1, Vu = m->a * pu1 * pv;
    double Uuu = -2 * m->cu - 2 * m->b * pv, Uuv = m->b * pu1 * pv1, Uvv = -2 * m->b * pu;
    double Vvv = -2 * m->cv - 2 * m->a * pu, Vuv = m->a * pu1 * pv1, Vuu = -2 * m->a * pv;
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
    double *cu = malloc(sizeof(double) * n), *cv = malloc(sizeof(double) * m);
    for (int i = 0; i < n; i++) cu[i] = strength * 0.3 * (2 * frand(&seed) - 1);
    for (int j = 0; j < m; j++) cv[j] = strength * 0.3 * (2 * frand(&seed) - 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            rmap *r = malloc(sizeof *r);
            r->kind = kind; r->x0 = X0 + DX * i; r->dx = DX; r->y0 = Y0 + DY * j; r->dy = DY;
            r->cu = cu[i]; r->cv = cv[j];
            r->a = strength * 0.8 * (2 * frand(&seed) - 1);
            r->b = strength * 0.8 * (2 * frand(&seed) - 1);
            q2n_surface_set_patch(*surf, i * m + j, Q2N_PATCH_AUGMENTED, r, rmap_eval, free);
        }
    free(cu); free(cv);
    return 1;
}

/* Independent checks of a model with bspline.c's evaluator (first derivatives only):
 * deviation at a pseudo-random point set, max normal angle across interior edges at random
 * edge parameters, and bit-identity of the shared boundary control points. */
static void independent(const q2n_nurbs_model *md, const q2n_surface *s, double *dev, double *ang, int *bitsame)
{
    const q2n_mesh *m = md->mesh;
    double diag = q2n_mesh_bbox_diag(m);
    unsigned seed = 99;
    *dev = 0; *ang = 0;
    for (int k = 0; k < md->n; k++)
        for (int q = 0; q < 40; q++) {
            double u = frand(&seed), v = frand(&seed), p[3], e[3];
            q2n_bspline_eval(&md->patches[k], u, v, p, NULL, NULL);
            q2n_surface_eval(s, k, u, v, 0, e);
            double d = sqrt((p[0] - e[0]) * (p[0] - e[0]) + (p[1] - e[1]) * (p[1] - e[1]) + (p[2] - e[2]) * (p[2] - e[2])) / diag;
            if (d > *dev) *dev = d;
        }
    *bitsame = fit_shared_rows_identical(md); /* shared boundary rows: bit-identical, reversed */
    static const int cuv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], ht = m->he_twin[h];
        if (ht < 0) continue;
        int f[2] = {m->he_face[h], m->he_face[ht]}, sd[2] = {h - m->face_start[f[0]], ht - m->face_start[f[1]]};
        for (int q = 0; q < 6; q++) {
            double t = frand(&seed), nrm[2][3];
            for (int x = 0; x < 2; x++) {
                double tt = x ? 1 - t : t, p[3], du[3], dv[3];
                const int *c0 = cuv[sd[x]], *c1 = cuv[(sd[x] + 1) & 3];
                q2n_bspline_eval(&md->patches[f[x]], c0[0] + tt * (c1[0] - c0[0]), c0[1] + tt * (c1[1] - c0[1]), p, du, dv);
                nrm[x][0] = du[1] * dv[2] - du[2] * dv[1];
                nrm[x][1] = du[2] * dv[0] - du[0] * dv[2];
                nrm[x][2] = du[0] * dv[1] - du[1] * dv[0];
                double l = sqrt(nrm[x][0] * nrm[x][0] + nrm[x][1] * nrm[x][1] + nrm[x][2] * nrm[x][2]);
                for (int c = 0; c < 3; c++) nrm[x][c] /= l;
            }
            double dot = nrm[0][0] * nrm[1][0] + nrm[0][1] * nrm[1][1] + nrm[0][2] * nrm[1][2];
            double cx = nrm[0][1] * nrm[1][2] - nrm[0][2] * nrm[1][1], cy = nrm[0][2] * nrm[1][0] - nrm[0][0] * nrm[1][2],
                   cz = nrm[0][0] * nrm[1][1] - nrm[0][1] * nrm[1][0];
            double a = atan2(sqrt(cx * cx + cy * cy + cz * cz), dot) * 180 / PI;
            if (a > *ang) *ang = a;
        }
    }
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
        double dev, ang;
        int same;
        independent(md, s, &dev, &ang, &same);
        printf("%-28s faces %3d  spans %d/%d/%d  rounds %d  max_dev %.2e rms %.2e (indep %.2e)  g0 %.1e  g1 %.2e deg "
               "(indep %.2e)  g2 %.2e (constr g1 %.1e g2 %.1e)  %.3f s\n",
               name, r.faces, r.spans_min, r.spans_median, r.spans_max, r.rounds, r.max_dev_rel, r.rms_dev_rel, dev,
               r.g0_max_rel, r.g1_max_deg, ang, r.g2_max_rel, r.g1_construction_deg, r.g2_construction_rel, r.t_total);
        printf("   times: sample %.3f build %.3f solve %.3f measure %.3f  samples %ld\n", r.t_sample, r.t_build, r.t_solve, r.t_measure, r.samples);
        CHECK(r.max_dev_rel <= tol, "%s: max_dev_rel %g > tol %g", name, r.max_dev_rel, tol);
        CHECK(dev <= 2 * tol, "%s: independent deviation %g > 2 tol", name, dev);
        CHECK(r.g0_max_rel <= 1e-12, "%s: g0 %g", name, r.g0_max_rel);
        CHECK(same, "%s: shared boundary control points not bit-identical", name);
        CHECK(r.g1_max_deg <= 0.01, "%s: g1 %g deg", name, r.g1_max_deg);
        CHECK(ang <= 0.01, "%s: independent g1 %g deg", name, ang);
        if (cont == 2) CHECK(r.g2_max_rel <= 0.01, "%s: g2 %g", name, r.g2_max_rel);
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
    printf("solver agreement: Ceres DENSE_QR (2 threads) vs direct QR %.2e, Ceres SPARSE_NORMAL_CHOLESKY vs direct %.2e\n", d1, d2);
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

/* The edge samples evaluated once per round, or per row stage and block of edges (the memory
 * bound of large fits): the same model bit for bit, G1 and G2 mode, over several blocks. */
static void edge_sample_blocks(void)
{
    q2n_mesh *mesh;
    q2n_surface *s;
    if (!build(1, 20, 16, 1.0, &mesh, &s)) { CHECK(0, "build"); return; }
    for (int cont = 1; cont <= 2; cont++) {
        q2n_nurbs_model *md[2] = {NULL, NULL};
        for (int i = 0; i < 2; i++) {
            q2n_fit_options o;
            q2n_fit_options_default(&o);
            o.continuity = cont;
            o.tol = 1e-6;
            if (i) o.edge_samples_once = 1;   /* every stage, blocks of edges */
            q2n_error err;
            CHECK(q2n_fit_surface(s, mesh, &o, &md[i], NULL, &err) == Q2N_OK, "blocks fit: %s", err.message);
        }
        int same = md[0] && md[1] && mesh->ne > 512;
        for (int k = 0; same && k < mesh->nf; k++) {
            const q2n_bspline_surface *a = &md[0]->patches[k], *b = &md[1]->patches[k];
            same = a->ncp_u == b->ncp_u && a->ncp_v == b->ncp_v &&
                   !memcmp(a->cp, b->cp, 3 * sizeof(double) * (size_t)a->ncp_u * a->ncp_v);
        }
        CHECK(same, "G%d: edge samples in blocks change the model (%d edges)", cont, mesh->ne);
        for (int i = 0; i < 2; i++) q2n_nurbs_model_free(md[i]);
    }
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
static void internals(void)
{
    q2n_bspline_surface b;
    double ku[14], kv[12], cp[3 * 8 * 6];
    b.deg_u = b.deg_v = 5; b.ncp_u = 8; b.ncp_v = 6; b.knots_u = ku; b.knots_v = kv; b.cp = cp; b.weights = NULL;
    fit_knots_uniform(3, ku);
    fit_knots_uniform(1, kv);
    unsigned seed = 3;
    for (int i = 0; i < 3 * 48; i++) cp[i] = frand(&seed);
    double emax = 0, dmax = 0, h = 1e-5;
    for (int q = 0; q < 50; q++) {
        double u = frand(&seed), v = frand(&seed), o[18], p[3], du[3], dv[3], pu[3], pv[3], mu[3], mv[3];
        u = 0.02 + 0.96 * u; v = 0.02 + 0.96 * v;
        fit_surface_eval(&b, u, v, 2, o);
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

    fit_ls ls;
    fit_ls_init(&ls);
    fit_ls_item_begin(&ls);
    int v0, v1;
    fit_ls_new_var(&ls, &v0);
    fit_ls_new_var(&ls, &v1);
    const double X0[3] = {1, -2, 0.5}, X1[3] = {3, 0.25, -1};
    for (int r = 0; r < 5; r++) {          /* rows (1, r) . (X0, X1) = rhs, consistent */
        double rhs[3];
        for (int c = 0; c < 3; c++) rhs[c] = X0[c] + r * X1[c];
        fit_ls_row(&ls, rhs);
        fit_ls_entry(&ls, v0, 1.0);
        fit_ls_entry(&ls, v1, (double)r);
    }
    fit_ls_item_end(&ls);
    q2n_error err;
    CHECK(fit_ls_solve_direct(&ls, &err) == Q2N_OK, "direct solve");
    double e = 0;
    for (int c = 0; c < 3; c++) e = fmax(e, fmax(fabs(ls.x[c] - X0[c]), fabs(ls.x[3 + c] - X1[c])));
    CHECK(e <= 1e-14, "direct QR solution error %g", e);
    CHECK(fit_ls_solve_ceres(&ls, 1, 1, &err) == Q2N_OK, "ceres solve");
    e = 0;
    for (int c = 0; c < 3; c++) e = fmax(e, fmax(fabs(ls.x[c] - X0[c]), fabs(ls.x[3 + c] - X1[c])));
    CHECK(e <= 1e-12, "Ceres solution error %g", e);
    fit_ls_free(&ls);
}

/* Errors: uncovered patches, wrong sizes, targets out of reach (model still returned). */
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
    const char *path = "build/test_fit_report.json";
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
    reproduction();
    solver_agreement();
    determinism();
    edge_sample_blocks();
    non_interpolating();
    errors_and_report();
    run_case("torus 8x6 G1 1e-5", 0, 8, 6, 1.0, 1e-5, 1, Q2N_FIT_SOLVER_CERES);
    run_case("torus 8x6 G1 1e-6", 0, 8, 6, 1.0, 1e-6, 1, Q2N_FIT_SOLVER_CERES);
    run_case("graph 6x4 G1 1e-5", 1, 6, 4, 1.0, 1e-5, 1, Q2N_FIT_SOLVER_CERES);
    run_case("graph 6x4 G1 1e-6", 1, 6, 4, 1.0, 1e-6, 1, Q2N_FIT_SOLVER_CERES);
    run_case("torus 8x6 G2 1e-5", 0, 8, 6, 1.0, 1e-5, 2, Q2N_FIT_SOLVER_CERES);
    run_case("graph 6x4 G2 1e-6", 1, 6, 4, 1.0, 1e-6, 2, Q2N_FIT_SOLVER_CERES);
    CHECK_DONE("test_fit");
}
