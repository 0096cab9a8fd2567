/* bspline.c — evaluation and validation of tensor-product (rational) B-spline surfaces, the
 * fit stage's output and the export stage's input (see bspline.h).
 *
 * Evaluation uses the Cox–de Boor basis functions with their first derivatives (The NURBS Book,
 * Piegl & Tiller 1997, algorithms A2.1 FindSpan and A2.3 DersBasisFuns) and, for rational surfaces,
 * the quotient rule on the homogeneous surface (eq. (4.20) of the same book). */
#include "fit/bspline.h"

#include <math.h>
#include <stdlib.h>


int q2n_bspline_span(int n, int p, const double *knots, double t)
{
    if (t >= knots[n]) {
        int i = n - 1;
        while (i > p && knots[i] >= knots[i + 1]) i--;
        return i;
    }
    if (t <= knots[p]) {
        int i = p;
        while (i < n - 1 && knots[i + 1] <= knots[p]) i++;
        return i;
    }
    int lo = p, hi = n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (t < knots[mid]) hi = mid;
        else lo = mid;
    }
    return lo;
}

/* A2.3 of the NURBS Book: the triangular table of basis functions (upper triangle) and knot
 * differences (lower), then the derivative recurrence eq. (2.10) up to order nder.  A zero knot
 * difference (a repeated knot) contributes nothing, as the convention 0/0 = 0 of eq. (2.5) says. */
static inline __attribute__((always_inline)) void basis(int i, int p, const double *knots, double t, int nder,
                                                        double *ders)
{
    if (nder == 0) {   /* A2.2: the same recurrence on one row (the same operations, so the same bits) */
        double left[Q2N_BSPLINE_MAX_DEG + 1], right[Q2N_BSPLINE_MAX_DEG + 1];
        ders[0] = 1.0;
        for (int j = 1; j <= p; j++) {
            left[j] = t - knots[i + 1 - j];
            right[j] = knots[i + j] - t;
            double saved = 0.0;
            for (int r = 0; r < j; r++) {
                double den = right[r + 1] + left[j - r];
                double tmp = den != 0.0 ? ders[r] / den : 0.0;
                ders[r] = saved + right[r + 1] * tmp;
                saved = left[j - r] * tmp;
            }
            ders[j] = saved;
        }
        return;
    }
    double ndu[Q2N_BSPLINE_MAX_DEG + 1][Q2N_BSPLINE_MAX_DEG + 1], a[2][Q2N_BSPLINE_MAX_DEG + 1];
    double left[Q2N_BSPLINE_MAX_DEG + 1], right[Q2N_BSPLINE_MAX_DEG + 1];
    const int w = p + 1;
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; j++) {
        left[j] = t - knots[i + 1 - j];
        right[j] = knots[i + j] - t;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            ndu[j][r] = right[r + 1] + left[j - r];
            double tmp = ndu[j][r] != 0.0 ? ndu[r][j - 1] / ndu[j][r] : 0.0;
            ndu[r][j] = saved + right[r + 1] * tmp;
            saved = left[j - r] * tmp;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= p; j++) ders[j] = ndu[j][p];
    if (nder > p)
        for (int k = p + 1; k <= nder; k++)
            for (int j = 0; j <= p; j++) ders[k * w + j] = 0.0;
    for (int r = 0; r <= p; r++) {
        int s1 = 0, s2 = 1;
        a[0][0] = 1.0;
        for (int k = 1; k <= nder && k <= p; k++) {
            double d = 0.0;
            int rk = r - k, pk = p - k;
            if (r >= k) {
                a[s2][0] = ndu[pk + 1][rk] != 0.0 ? a[s1][0] / ndu[pk + 1][rk] : 0.0;
                d = a[s2][0] * ndu[rk][pk];
            }
            int j1 = rk >= -1 ? 1 : -rk;
            int j2 = (r - 1 <= pk) ? k - 1 : p - r;
            for (int j = j1; j <= j2; j++) {
                a[s2][j] = ndu[pk + 1][rk + j] != 0.0 ? (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j] : 0.0;
                d += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][k] = ndu[pk + 1][r] != 0.0 ? -a[s1][k - 1] / ndu[pk + 1][r] : 0.0;
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k * w + r] = d;
            int tmp = s1; s1 = s2; s2 = tmp;
        }
    }
    double f = p;
    for (int k = 1; k <= nder && k <= p; k++) {
        for (int j = 0; j <= p; j++) ders[k * w + j] *= f;
        f *= p - k;
    }
}

/* The fit's and the export's degree with the derivative counts they ask for get copies compiled for
 * those constants (unrolled loops: the same operations in the same order, so the same bits).  With
 * p and nder known only at run time this function was 18 % of a fit's instructions, ~1 660 a call,
 * mostly loop control; ~600 now (docs/fit.md, "Measured"). */
void q2n_bspline_basis(int i, int p, const double *knots, double t, int nder, double *ders)
{
    if (p == 5) {
        if (nder == 2) basis(i, 5, knots, t, 2, ders);
        else if (nder == 1) basis(i, 5, knots, t, 1, ders);
        else if (nder == 0) basis(i, 5, knots, t, 0, ders);
        else basis(i, 5, knots, t, nder, ders);
        return;
    }
    basis(i, p, knots, t, nder, ders);
}

void q2n_bspline_eval(const q2n_bspline_surface *s, double u, double v, double p[3], double du[3],
                      double dv[3])
{
    double Bu[2 * (Q2N_BSPLINE_MAX_DEG + 1)], Bv[2 * (Q2N_BSPLINE_MAX_DEG + 1)];
    int want_d = du != NULL || dv != NULL;
    int su = q2n_bspline_span(s->ncp_u, s->deg_u, s->knots_u, u);
    int sv = q2n_bspline_span(s->ncp_v, s->deg_v, s->knots_v, v);
    q2n_bspline_basis(su, s->deg_u, s->knots_u, u, want_d, Bu);
    q2n_bspline_basis(sv, s->deg_v, s->knots_v, v, want_d, Bv);
    const double *Nu = Bu, *Du = Bu + s->deg_u + 1, *Nv = Bv, *Dv = Bv + s->deg_v + 1;

    /* Homogeneous sums A = sum N_i N_j w_ij P_ij, W = sum N_i N_j w_ij and their derivatives. */
    double A[3] = {0, 0, 0}, Au[3] = {0, 0, 0}, Av[3] = {0, 0, 0};
    double W = 0.0, Wu = 0.0, Wv = 0.0;
    for (int b = 0; b <= s->deg_v; b++) {
        int j = sv - s->deg_v + b;
        for (int a = 0; a <= s->deg_u; a++) {
            int i = su - s->deg_u + a;
            size_t k = (size_t)j * (size_t)s->ncp_u + (size_t)i;
            double w = s->weights ? s->weights[k] : 1.0;
            const double *P = s->cp + 3 * k;
            double b0 = Nu[a] * Nv[b] * w;
            double bu = want_d ? Du[a] * Nv[b] * w : 0.0;
            double bv = want_d ? Nu[a] * Dv[b] * w : 0.0;
            for (int c = 0; c < 3; c++) {
                A[c] += b0 * P[c];
                Au[c] += bu * P[c];
                Av[c] += bv * P[c];
            }
            W += b0; Wu += bu; Wv += bv;
        }
    }
    /* S = A/W, S_u = (A_u - W_u S)/W, eq. (4.20) NURBS Book (W == 1, W_u == 0 when polynomial). */
    for (int c = 0; c < 3; c++) p[c] = A[c] / W;
    if (du) for (int c = 0; c < 3; c++) du[c] = (Au[c] - Wu * p[c]) / W;
    if (dv) for (int c = 0; c < 3; c++) dv[c] = (Av[c] - Wv * p[c]) / W;
}

/* One knot vector: length n+p+1, non-decreasing, finite, clamped (p+1 equal knots at 0 and at 1),
 * interior multiplicities <= p (so the basis stays continuous). */
static q2n_status check_knots(const double *k, int n, int p, char dir, q2n_error *err)
{
    if (p < 1 || p > Q2N_BSPLINE_MAX_DEG)
        return q2n_error_set(err, Q2N_ERR_ARG, "bspline: degree %c = %d outside 1..%d", dir, p,
                             Q2N_BSPLINE_MAX_DEG);
    if (n < p + 1)
        return q2n_error_set(err, Q2N_ERR_ARG, "bspline: %d control points in %c for degree %d (need >= %d)",
                             n, dir, p, p + 1);
    if (!k) return q2n_error_set(err, Q2N_ERR_ARG, "bspline: knot vector %c missing", dir);
    int m = n + p + 1, mult = 1;
    for (int i = 0; i < m; i++) {
        if (!isfinite(k[i]))
            return q2n_error_set(err, Q2N_ERR_ARG, "bspline: knot %c[%d] is not finite", dir, i);
        if (i == 0) continue;
        if (k[i] < k[i - 1])
            return q2n_error_set(err, Q2N_ERR_ARG, "bspline: knots %c decrease at index %d (%.17g < %.17g)",
                                 dir, i, k[i], k[i - 1]);
        mult = k[i] == k[i - 1] ? mult + 1 : 1;
        if (i > p && i < m - p - 1 && mult > p)
            return q2n_error_set(err, Q2N_ERR_ARG, "bspline: interior knot %c[%d] = %.17g has multiplicity > %d",
                                 dir, i, k[i], p);
    }
    for (int i = 0; i <= p; i++) {
        if (k[i] != 0.0 || k[m - 1 - i] != 1.0)
            return q2n_error_set(err, Q2N_ERR_ARG,
                                 "bspline: knots %c not clamped on [0,1] (need %d knots 0 and %d knots 1; "
                                 "k[%d] = %.17g, k[%d] = %.17g)", dir, p + 1, p + 1, i, k[i], m - 1 - i,
                                 k[m - 1 - i]);
    }
    return Q2N_OK;
}

q2n_status q2n_bspline_check(const q2n_bspline_surface *s, q2n_error *err)
{
    if (!s) return q2n_error_set(err, Q2N_ERR_ARG, "bspline: NULL surface");
    q2n_status st = check_knots(s->knots_u, s->ncp_u, s->deg_u, 'u', err);
    if (st != Q2N_OK) return st;
    st = check_knots(s->knots_v, s->ncp_v, s->deg_v, 'v', err);
    if (st != Q2N_OK) return st;
    if (!s->cp) return q2n_error_set(err, Q2N_ERR_ARG, "bspline: control points missing");
    size_t ncp = (size_t)s->ncp_u * (size_t)s->ncp_v;
    for (size_t k = 0; k < ncp; k++) {
        for (int c = 0; c < 3; c++)
            if (!isfinite(s->cp[3 * k + c]))
                return q2n_error_set(err, Q2N_ERR_ARG, "bspline: control point (%zu,%zu) is not finite",
                                     k % (size_t)s->ncp_u, k / (size_t)s->ncp_u);
        if (s->weights && !(s->weights[k] > 0.0 && isfinite(s->weights[k])))
            return q2n_error_set(err, Q2N_ERR_ARG, "bspline: weight (%zu,%zu) = %.17g is not positive and finite",
                                 k % (size_t)s->ncp_u, k / (size_t)s->ncp_u, s->weights[k]);
    }
    return Q2N_OK;
}

void q2n_bspline_free(q2n_bspline_surface *s)
{
    if (!s) return;
    free(s->knots_u);
    free(s->knots_v);
    free(s->cp);
    free(s->weights);
    s->knots_u = s->knots_v = s->cp = s->weights = NULL;
}

/* Frees each patch's arrays, the patch array and the (heap-allocated) model itself, as the fit
 * stage allocates it; the mesh is borrowed and stays. */
void q2n_nurbs_model_free(q2n_nurbs_model *m)
{
    if (!m) return;
    if (m->patches)
        for (int k = 0; k < m->n; k++) q2n_bspline_free(&m->patches[k]);
    free(m->patches);
    if (m->edges && m->mesh)
        for (int e = 0; e < m->mesh->ne; e++) {
            free(m->edges[e].knots);
            free(m->edges[e].cp);
        }
    free(m->edges);
    free(m);
}

void q2n_bspline_curve_eval(const q2n_bspline_curve *c, double t, double p[3], double d[3])
{
    double B[2 * (Q2N_BSPLINE_MAX_DEG + 1)];
    int sp = q2n_bspline_span(c->ncp, c->deg, c->knots, t);
    q2n_bspline_basis(sp, c->deg, c->knots, t, d != NULL, B);
    const double *N = B, *D = B + c->deg + 1;
    for (int q = 0; q < 3; q++) {
        p[q] = 0.0;
        if (d) d[q] = 0.0;
    }
    for (int a = 0; a <= c->deg; a++) {
        const double *P = c->cp + 3 * (size_t)(sp - c->deg + a);
        for (int q = 0; q < 3; q++) {
            p[q] += N[a] * P[q];
            if (d) d[q] += D[a] * P[q];
        }
    }
}
