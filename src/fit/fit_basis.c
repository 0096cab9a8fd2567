/* fit_basis.c — the quintic B-spline basis the fit works in: clamped knot vectors from interior
 * breakpoints, span search and basis functions
 * (q2n_bspline_span / q2n_bspline_basis, fit/bspline.c), knot insertion (A5.4), the fit's sample
 * and check parameters, and second-order evaluation of fitted surfaces (the continuity
 * measurements need curvatures, which q2n_bspline_eval does not give). */
#include "fit/fit_internal.h"
#include "core/vec3.h"

#include <stdlib.h>
#include <string.h>

void q2n_fit_knots_from_breaks(int nb, const double *br, double *kv)
{
    int n = nb + Q2N_FIT_DEG + 1;              /* control points */
    for (int i = 0; i <= Q2N_FIT_DEG; i++) {
        kv[i] = 0.0;
        kv[n + i] = 1.0;
    }
    for (int i = 0; i < nb; i++) kv[Q2N_FIT_DEG + 1 + i] = br[i];
}

void q2n_fit_knots_uniform(int m, double *kv)
{
    int n = m + Q2N_FIT_DEG;                   /* control points */
    for (int i = 0; i <= Q2N_FIT_DEG; i++) {
        kv[i] = 0.0;
        kv[n + i] = 1.0;
    }
    /* i/m computed the same way everywhere, so equal span counts give bit-identical knots. */
    for (int i = 1; i < m; i++) kv[Q2N_FIT_DEG + i] = (double)i / (double)m;
}

/* The distinct spans [kv[i], kv[i+1]] of a clamped knot vector with n control points are
 * i = 5 .. n-1 (all non-empty: interior knots are simple). */
int q2n_fit_sample_params(int n, const double *kv, int per_span, double *out)
{
    int c = 0;
    for (int i = Q2N_FIT_DEG; i < n; i++) {
        double a = kv[i], b = kv[i + 1];
        for (int j = 0; j < per_span; j++) out[c++] = j == 0 ? a : a + (b - a) * j / per_span;
    }
    out[c++] = 1.0;
    return c;
}

int q2n_fit_check_params(int n, const double *kv, int per_span, double *out)
{
    int c = 0;
    for (; c < (n - Q2N_FIT_DEG) * per_span; c++) out[c] = q2n_fit_check_param(kv, per_span, c);
    return c;
}

/* Boehm's algorithm, one knot at a time (NURBS Book A5.1 for a single insertion): inserting u in
 * span k replaces P_{k-p+1..k} by Q_i = a_i P_i + (1 - a_i) P_{i-1}, a_i = (u - u_i)/(u_{i+p} - u_i). */
int q2n_fit_curve_refine(int n, const double *kv, const double *cp, int dim, int n2, const double *kv2, double *cp2)
{
    enum { p = Q2N_FIT_DEG };
    int m = n + p + 1, m2 = n2 + p + 1;
    double *K = malloc(sizeof(double) * (size_t)m2), *P = malloc(sizeof(double) * (size_t)dim * n2);
    if (!K || !P) { free(K); free(P); return -1; }
    memcpy(K, kv, sizeof(double) * (size_t)m);
    memcpy(P, cp, sizeof(double) * (size_t)dim * n);
    int cur = n, ok = 1, i2 = 0;
    /* walk kv2; every knot of kv2 missing (by count) from the current vector is inserted */
    for (int i = 0; i < m2 && ok; i++) {
        double u = kv2[i];
        int have = 0, need = 0;
        for (int j = 0; j < cur + p + 1; j++) have += K[j] == u;
        for (int j = 0; j < m2; j++) need += kv2[j] == u;
        if (i > 0 && kv2[i - 1] == u) continue;       /* each distinct value once */
        if (have > need) ok = 0;
        for (; have < need && ok; have++) {
            if (cur >= n2) { ok = 0; break; }
            int k = q2n_fit_span(cur, K, u);
            for (int j = cur; j > k; j--) memcpy(P + (size_t)dim * j, P + (size_t)dim * (j - 1), sizeof(double) * dim);
            for (int j = k; j >= k - p + 1; j--) {
                double a = (u - K[j]) / (K[j + p] - K[j]);
                for (int q = 0; q < dim; q++)
                    P[(size_t)dim * j + q] = a * P[(size_t)dim * j + q] + (1.0 - a) * P[(size_t)dim * (j - 1) + q];
            }
            for (int j = cur + p; j > k; j--) K[j + 1] = K[j];
            K[k + 1] = u;
            cur++;
        }
        i2++;
    }
    if (ok && cur != n2) ok = 0;
    if (ok) memcpy(cp2, P, sizeof(double) * (size_t)dim * n2);
    free(K);
    free(P);
    return ok ? 0 : -1;
}

/* One control row's u-sum: t = sum_a bu[a] P[a] (P: six consecutive control points).  The positions
 * of q2n_fit_surface_eval and q2n_fit_surface_grid are v-sums of these, in the same order, so the
 * two give the same bits. */
static inline void row_sum(double t[3], const double *bu, const double *P)
{
    t[0] = t[1] = t[2] = 0.0;
    for (int a = 0; a <= Q2N_FIT_DEG; a++) q2n_v3_axpy(t, bu[a], P + 3 * a);
}

void q2n_fit_surface_eval(const q2n_bspline_surface *s, double u, double v, int nder, double *out)
{
    double Bu[3][Q2N_FIT_DEG + 1], Bv[3][Q2N_FIT_DEG + 1];
    int su = q2n_fit_span(s->ncp_u, s->knots_u, u), sv = q2n_fit_span(s->ncp_v, s->knots_v, v);
    q2n_fit_basis(su, s->knots_u, u, nder, Bu);
    q2n_fit_basis(sv, s->knots_v, v, nder, Bv);
    if (nder == 0) {   /* positions: each control row's u-sum, then the v-sum (q2n_fit_surface_grid's order) */
        out[0] = out[1] = out[2] = 0.0;
        for (int b = 0; b <= Q2N_FIT_DEG; b++) {
            const double *P = s->cp + 3 * ((size_t)(sv - Q2N_FIT_DEG + b) * s->ncp_u + (su - Q2N_FIT_DEG));
            double t[3];
            row_sum(t, Bu[0], P);
            q2n_v3_axpy(out, Bv[0][b], t);
        }
        return;
    }
    const int(*ord)[2] = q2n_eval_order; /* derivative orders in u and v of each output slot */
    int nout = nder == 1 ? 3 : 6;
    memset(out, 0, 3 * (size_t)nout * sizeof *out);
    for (int b = 0; b <= Q2N_FIT_DEG; b++) {
        int j = sv - Q2N_FIT_DEG + b;
        for (int a = 0; a <= Q2N_FIT_DEG; a++) {
            int i = su - Q2N_FIT_DEG + a;
            const double *P = s->cp + 3 * ((size_t)j * s->ncp_u + i);
            for (int o = 0; o < nout; o++) {
                double w = Bu[ord[o][0]][a] * Bv[ord[o][1]][b];
                out[3 * o] += w * P[0];
                out[3 * o + 1] += w * P[1];
                out[3 * o + 2] += w * P[2];
            }
        }
    }
}

int q2n_fit_surface_grid(const q2n_bspline_surface *s, int nu, const double *us, int nv, const double *vs, double *out)
{
    enum { P1 = Q2N_FIT_DEG + 1 };
    int *su = malloc(sizeof(int) * (size_t)(nu + nv));
    double *Bu = malloc(sizeof(double) * P1 * (size_t)(nu + nv));
    if (!su || !Bu) { free(su); free(Bu); return -1; }
    int *sv = su + nu;
    double *Bv = Bu + P1 * (size_t)nu;
    for (int i = 0; i < nu; i++) {
        double B[3][P1];
        su[i] = q2n_fit_span(s->ncp_u, s->knots_u, us[i]);
        q2n_fit_basis(su[i], s->knots_u, us[i], 0, B);
        memcpy(Bu + P1 * (size_t)i, B[0], sizeof B[0]);
    }
    for (int j = 0; j < nv; j++) {
        double B[3][P1];
        sv[j] = q2n_fit_span(s->ncp_v, s->knots_v, vs[j]);
        q2n_fit_basis(sv[j], s->knots_v, vs[j], 0, B);
        memcpy(Bv + P1 * (size_t)j, B[0], sizeof B[0]);
    }
    /* T[r][i]: control row r's u-sum at sample column i (the rows column i's support reaches),
     * then each point is the v-sum of its six rows: the order of q2n_fit_surface_eval's positions,
     * so the same bits, at a sixth of the work */
    double *T = malloc(3 * sizeof(double) * (size_t)s->ncp_v * (nu > 0 ? nu : 1));
    if (!T) { free(su); free(Bu); return -1; }
    for (int r = 0; r < s->ncp_v; r++)
        for (int i = 0; i < nu; i++) {
            row_sum(T + 3 * ((size_t)r * nu + i), Bu + P1 * (size_t)i, s->cp + 3 * ((size_t)r * s->ncp_u + (su[i] - Q2N_FIT_DEG)));
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            const double *bv = Bv + P1 * (size_t)j;
            double *o = out + 3 * ((size_t)j * nu + i);
            o[0] = o[1] = o[2] = 0.0;
            for (int b = 0; b <= Q2N_FIT_DEG; b++) q2n_v3_axpy(o, bv[b], T + 3 * ((size_t)(sv[j] - Q2N_FIT_DEG + b) * nu + i));
        }
    free(T);
    free(su);
    free(Bu);
    return 0;
}
