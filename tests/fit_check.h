/* fit_check.h — checks on a fitted q2n_nurbs_model shared by the fit tests, written independently
 * of src/fit/ (they use bspline.c's evaluator and the construction's, nothing of the fit's own). */
#ifndef Q2N_TEST_FIT_CHECK_H
#define Q2N_TEST_FIT_CHECK_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fit/bspline.h"
#include "patch/surface.h"

/* Point of patch p on side i at parameter t along the side (corner i -> i+1; patch/surface.h). */
static inline void fck_side_point(const q2n_bspline_surface *p, int i, double t, double out[3])
{
    double u, v;
    q2n_side_uv(i, t, 0, &u, &v);
    q2n_bspline_eval(p, u, v, out, NULL, NULL);
}

/* Index of the it-th control point along side i (from corner i) of an nu x nv grid. */
static inline int fck_side_cp(int i, int nu, int nv, int it)
{
    const int *c0 = q2n_corner_uv[i], *d = q2n_side_along[i];
    return (c0[1] * (nv - 1) + it * d[1]) * nu + c0[0] * (nu - 1) + it * d[0];
}

static inline double fck_dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* Edges whose curve lacks an interior knot that every patch side along it has (both sides of an
 * interior edge, the one side of a boundary edge): the fit gives an edge the breakpoints its sides
 * share, so that its sides' boundary rows are its own control points (fit_refine.c).  Knots in the
 * edge's owner orientation (sides 2 and 3 run against u or v; the twin runs against the owner). */
static inline int fit_unshared_knots(const q2n_nurbs_model *md)
{
    const q2n_mesh *m = md->mesh;
    int bad = 0;
    for (int e = 0; md->edges && e < m->ne; e++) {
        int h[2] = {m->edge_he[e], m->he_twin[m->edge_he[e]]};
        const q2n_bspline_curve *E = &md->edges[e];
        const q2n_bspline_surface *P0 = &md->patches[m->he_face[h[0]]];
        int i0 = h[0] - m->face_start[m->he_face[h[0]]], n0 = (i0 & 1) ? P0->ncp_v : P0->ncp_u;
        const double *k0 = (i0 & 1) ? P0->knots_v : P0->knots_u;
        for (int q = 6; q < n0; q++) {   /* interior knots of the owner side */
            double t = i0 < 2 ? k0[q] : 1.0 - k0[q], in_twin = 1;
            if (h[1] >= 0) {
                const q2n_bspline_surface *P1 = &md->patches[m->he_face[h[1]]];
                int i1 = h[1] - m->face_start[m->he_face[h[1]]], n1 = (i1 & 1) ? P1->ncp_v : P1->ncp_u;
                const double *k1 = (i1 & 1) ? P1->knots_v : P1->knots_u;
                double x = i1 < 2 ? 1.0 - t : t;   /* the twin's side runs the other way */
                in_twin = 0;
                for (int r = 6; r < n1 && !in_twin; r++) in_twin = k1[r] == x;
            }
            if (!in_twin) continue;
            int in_edge = 0;
            for (int r = 6; r < E->ncp && !in_edge; r++) in_edge = E->knots[r] == t;
            if (!in_edge) { bad++; break; }
        }
    }
    return bad;
}

/* Watertightness of a model: along every edge, both patch boundaries (reversed on the twin) and
 * the model's edge curve (when it has them) coincide; returns the largest gap at 33 points per
 * edge, and counts in *nsame / *nsides the patch sides with the edge curve's own number of
 * control points (then the same knots) and how many of those are bit-identical to it (each must
 * be: the fit copies them). */
static inline double fit_boundary_gap(const q2n_nurbs_model *md, int *nsame, int *nsides)
{
    const q2n_mesh *m = md->mesh;
    double gap = 0.0;
    *nsame = *nsides = 0;
    for (int e = 0; e < m->ne; e++) {
        int h[2] = {m->edge_he[e], m->he_twin[m->edge_he[e]]};
        for (int q = 0; q <= 32; q++) {
            double t = q / 32.0, p[2][3], c[3];
            for (int x = 0; x < 2; x++)
                if (h[x] >= 0) {
                    int f = m->he_face[h[x]];
                    fck_side_point(&md->patches[f], h[x] - m->face_start[f], x ? 1.0 - t : t, p[x]);
                }
            if (h[1] >= 0) gap = fmax(gap, fck_dist(p[0], p[1]));
            if (md->edges) {
                q2n_bspline_curve_eval(&md->edges[e], t, c, NULL);
                gap = fmax(gap, fck_dist(p[0], c));
            }
        }
        for (int x = 0; x < 2; x++) {
            if (h[x] < 0) continue;
            int f = m->he_face[h[x]], i = h[x] - m->face_start[f];
            const q2n_bspline_surface *P = &md->patches[f];
            int along_u = !(i & 1), n = along_u ? P->ncp_u : P->ncp_v;
            /* reference: the edge curve, or (models without edge curves) the owner side's row */
            const double *ref;
            int rn, rev = x;
            double *own = NULL;
            if (md->edges) {
                ref = md->edges[e].cp;
                rn = md->edges[e].ncp;
            } else {
                if (x == 0 || h[1] < 0) continue;
                int f0 = m->he_face[h[0]], i0 = h[0] - m->face_start[f0];
                const q2n_bspline_surface *P0 = &md->patches[f0];
                rn = (i0 & 1) ? P0->ncp_v : P0->ncp_u;
                own = (double *)malloc(3 * sizeof(double) * (size_t)rn);
                if (!own) continue;
                for (int it = 0; it < rn; it++) {
                    memcpy(own + 3 * it, P0->cp + 3 * fck_side_cp(i0, P0->ncp_u, P0->ncp_v, it), 3 * sizeof(double));
                }
                ref = own;
            }
            if (rn != n) { free(own); continue; }   /* different knots: compared through the points above */
            (*nsides)++;
            int same = 1;
            for (int it = 0; it < n && same; it++) {
                const double *pc = P->cp + 3 * fck_side_cp(i, P->ncp_u, P->ncp_v, it), *rc = ref + 3 * (rev ? n - 1 - it : it);
                same = !memcmp(pc, rc, 3 * sizeof(double));
            }
            *nsame += same;
            free(own);
        }
    }
    return gap;
}

/* Distance from P to patch k of the construction: Gauss–Newton on |S(u, v) - P|^2 from (u0, v0),
 * parameters kept in [0,1]^2 (the fitted patch may be a reparametrization of the construction's,
 * so parametric differences only bound the distance from above). */
static inline double fit_foot_distance(const q2n_surface *s, int k, double u, double v, const double P[3])
{
    double best = 1e300;
    for (int it = 0; it < 12; it++) {
        double e[Q2N_EVAL_MAX], r[3];
        if (q2n_surface_eval(s, k, u, v, 1, e)) break;
        for (int c = 0; c < 3; c++) r[c] = e[c] - P[c];
        double d = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        if (d < best) best = d;
        const double *Su = e + 3, *Sv = e + 6;
        double a = Su[0] * Su[0] + Su[1] * Su[1] + Su[2] * Su[2], b = Su[0] * Sv[0] + Su[1] * Sv[1] + Su[2] * Sv[2];
        double cc = Sv[0] * Sv[0] + Sv[1] * Sv[1] + Sv[2] * Sv[2];
        double gu = -(Su[0] * r[0] + Su[1] * r[1] + Su[2] * r[2]), gv = -(Sv[0] * r[0] + Sv[1] * r[1] + Sv[2] * r[2]);
        double det = a * cc - b * b;
        if (!(det > 0)) break;
        double du = (cc * gu - b * gv) / det, dv = (a * gv - b * gu) / det;
        u = fmin(1.0, fmax(0.0, u + du));
        v = fmin(1.0, fmax(0.0, v + dv));
        if (fabs(du) + fabs(dv) < 1e-15) break;
    }
    return best;
}

/* Largest distance / diag from n pseudo-random points per patch of the model to the construction. */
static inline double fit_random_distance(const q2n_nurbs_model *md, const q2n_surface *s, int n, double diag)
{
    double worst = 0;
    unsigned x = 12345u;
    for (int k = 0; k < md->n; k++)
        for (int i = 0; i < n; i++) {
            x = x * 1664525u + 1013904223u;
            double u = (x >> 8) / 16777216.0;
            x = x * 1664525u + 1013904223u;
            double v = (x >> 8) / 16777216.0, p[3];
            q2n_bspline_eval(&md->patches[k], u, v, p, NULL, NULL);
            double d = fit_foot_distance(s, k, u, v, p) / diag;
            if (d > worst) worst = d;
        }
    return worst;
}

/* Unit normal du x dv / |du x dv|. */
static inline void fck_unit_normal(const double du[3], const double dv[3], double n[3])
{
    n[0] = du[1] * dv[2] - du[2] * dv[1];
    n[1] = du[2] * dv[0] - du[0] * dv[2];
    n[2] = du[0] * dv[1] - du[1] * dv[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int c = 0; c < 3; c++) n[c] /= l;
}

/* Angle between unit vectors a and b in degrees (atan2 of |a x b| and a . b: accurate near 0). */
static inline double fck_angle_deg(const double a[3], const double b[3])
{
    double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2], cz = a[0] * b[1] - a[1] * b[0];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * 180 / 3.14159265358979323846;
}

/* Largest normal-angle jump (degrees) across interior edges at n pseudo-random edge points, from
 * bspline.c's first derivatives. */
static inline double fit_random_angle(const q2n_nurbs_model *md, int n)
{
    const q2n_mesh *m = md->mesh;
    double worst = 0;
    unsigned seed = 777u;
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], ht = m->he_twin[h];
        if (ht < 0) continue;
        int f[2] = {m->he_face[h], m->he_face[ht]}, sd[2] = {h - m->face_start[f[0]], ht - m->face_start[f[1]]};
        for (int q = 0; q < n; q++) {
            seed = seed * 1664525u + 1013904223u;
            double t = (seed >> 8) / 16777216.0, nrm[2][3];
            for (int x = 0; x < 2; x++) {
                double tt = x ? 1 - t : t, p[3], du[3], dv[3], u, v;
                q2n_side_uv(sd[x], tt, 0, &u, &v);
                q2n_bspline_eval(&md->patches[f[x]], u, v, p, du, dv);
                fck_unit_normal(du, dv, nrm[x]);
            }
            worst = fmax(worst, fck_angle_deg(nrm[0], nrm[1]));
        }
    }
    return worst;
}

/* Position and first and second partials of a (non-rational) B-spline patch at (u, v) in the
 * order of q2n_eval_order (D[0] S, D[1] Su, D[2] Sv, D[3] Suu, D[4] Suv, D[5] Svv), from
 * bspline.c's basis. */
static inline void fck_eval2(const q2n_bspline_surface *s, double u, double v, double D[6][3])
{
    double Bu[3 * (Q2N_BSPLINE_MAX_DEG + 1)], Bv[3 * (Q2N_BSPLINE_MAX_DEG + 1)];
    int su = q2n_bspline_span(s->ncp_u, s->deg_u, s->knots_u, u), sv = q2n_bspline_span(s->ncp_v, s->deg_v, s->knots_v, v);
    q2n_bspline_basis(su, s->deg_u, s->knots_u, u, 2, Bu);
    q2n_bspline_basis(sv, s->deg_v, s->knots_v, v, 2, Bv);
    memset(D, 0, 18 * sizeof(double));
    for (int b = 0; b <= s->deg_v; b++)
        for (int a = 0; a <= s->deg_u; a++) {
            const double *P = s->cp + 3 * ((size_t)(sv - s->deg_v + b) * s->ncp_u + (size_t)(su - s->deg_u + a));
            for (int o = 0; o < 6; o++) {
                double w = Bu[q2n_eval_order[o][0] * (s->deg_u + 1) + a] * Bv[q2n_eval_order[o][1] * (s->deg_v + 1) + b];
                for (int c = 0; c < 3; c++) D[o][c] += w * P[c];
            }
        }
}

/* Unit normal and the normal curvature in the direction of the 3-vector w (projected on the
 * tangent plane: w = a Su + b Sv in the least-squares sense): II(a, b) / I(a, b). */
static inline double fck_normal_curvature(const double D[6][3], const double n[3], const double w[3])
{
    double E = 0, F = 0, G = 0, wu = 0, wv = 0, L = 0, M = 0, N = 0;
    for (int c = 0; c < 3; c++) {
        E += D[1][c] * D[1][c]; F += D[1][c] * D[2][c]; G += D[2][c] * D[2][c];
        wu += w[c] * D[1][c]; wv += w[c] * D[2][c];
        L += D[3][c] * n[c]; M += D[4][c] * n[c]; N += D[5][c] * n[c];
    }
    double det = E * G - F * F, a = (G * wu - F * wv) / det, b = (E * wv - F * wu) / det;
    return (a * a * L + 2 * a * b * M + b * b * N) / (a * a * E + 2 * a * b * F + b * b * G);
}

/* Continuity of a model across every interior edge at n equally spaced interior points per edge,
 * independent of the fit's own measurement (which checks 4 points per knot span): the largest
 * normal-angle jump in degrees (*g1) and the largest jump of normal curvature in the directions
 * along the edge, across it and between them, over the larger of the two sides' curvatures and
 * 1/diag (*g2) — the report's definitions (docs/fit.md). */
static inline void fit_dense_continuity(const q2n_nurbs_model *md, int n, double diag, double *g1, double *g2)
{
    const q2n_mesh *m = md->mesh;
    *g1 = *g2 = 0;
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], ht = m->he_twin[h];
        if (ht < 0) continue;
        int f[2] = {m->he_face[h], m->he_face[ht]}, sd[2] = {h - m->face_start[f[0]], ht - m->face_start[f[1]]};
        for (int q = 1; q < n; q++) {
            double t = (double)q / n, D[2][6][3], nrm[2][3];
            for (int x = 0; x < 2; x++) {
                double u, v;
                q2n_side_uv(sd[x], x ? 1 - t : t, 0, &u, &v);
                fck_eval2(&md->patches[f[x]], u, v, D[x]);
                fck_unit_normal(D[x][1], D[x][2], nrm[x]);
            }
            *g1 = fmax(*g1, fck_angle_deg(nrm[0], nrm[1]));
            /* the tangent along the edge (side orientation of the first patch), the perpendicular in its tangent plane */
            const int *dir = q2n_side_along[sd[0]];
            double tan[3];
            for (int c = 0; c < 3; c++) tan[c] = dir[0] * D[0][1][c] + dir[1] * D[0][2][c];
            double lt = sqrt(tan[0] * tan[0] + tan[1] * tan[1] + tan[2] * tan[2]);
            for (int c = 0; c < 3; c++) tan[c] /= lt;
            double per[3] = {nrm[0][1] * tan[2] - nrm[0][2] * tan[1], nrm[0][2] * tan[0] - nrm[0][0] * tan[2],
                             nrm[0][0] * tan[1] - nrm[0][1] * tan[0]};
            double jmax = 0, kmax = 1 / diag;
            for (int k = 0; k < 3; k++) {
                double w[3];
                for (int c = 0; c < 3; c++) w[c] = k == 0 ? tan[c] : k == 1 ? per[c] : (tan[c] + per[c]) / sqrt(2.0);
                double kl = fck_normal_curvature((const double (*)[3])D[0], nrm[0], w);
                double kr = fck_normal_curvature((const double (*)[3])D[1], nrm[1], w);
                jmax = fmax(jmax, fabs(kl - kr));
                kmax = fmax(kmax, fmax(fabs(kl), fabs(kr)));
            }
            *g2 = fmax(*g2, jmax / kmax);
        }
    }
}

#endif
