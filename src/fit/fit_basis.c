/* fit_basis.c — the quintic B-spline basis the fit works in: clamped uniform knot vectors, span
 * search, basis functions with first and second derivatives (Piegl & Tiller, The NURBS Book 1997,
 * A2.1 FindSpan and A2.3 DersBasisFuns), and second-order evaluation of fitted surfaces (the
 * continuity measurements need curvatures, which q2n_bspline_eval does not give). */
#include "fit/fit_internal.h"

#include <string.h>

void fit_knots_uniform(int m, double *kv)
{
    int n = m + FIT_DEG;                       /* control points */
    for (int i = 0; i <= FIT_DEG; i++) {
        kv[i] = 0.0;
        kv[n + i] = 1.0;
    }
    /* i/m computed the same way everywhere, so equal span counts give bit-identical knots. */
    for (int i = 1; i < m; i++) kv[FIT_DEG + i] = (double)i / (double)m;
}

int fit_span(int n, const double *kv, double t)
{
    if (t >= kv[n]) return n - 1;
    if (t <= kv[FIT_DEG]) return FIT_DEG;
    int lo = FIT_DEG, hi = n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (t < kv[mid]) hi = mid;
        else lo = mid;
    }
    return lo;
}

/* A2.3 of the NURBS Book: triangular table of basis functions and knot differences, then the
 * derivative recurrence eq. (2.10) up to order nder. */
void fit_basis(int i, const double *kv, double t, int nder, double ders[3][FIT_DEG + 1])
{
    enum { p = FIT_DEG };
    double ndu[p + 1][p + 1], left[p + 1], right[p + 1], a[2][p + 1];
    ndu[0][0] = 1.0;
    for (int j = 1; j <= p; j++) {
        left[j] = t - kv[i + 1 - j];
        right[j] = kv[i + j] - t;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            ndu[j][r] = right[r + 1] + left[j - r];
            double tmp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * tmp;
            saved = left[j - r] * tmp;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= p; j++) ders[0][j] = ndu[j][p];
    for (int r = 0; r <= p; r++) {
        int s1 = 0, s2 = 1;
        a[0][0] = 1.0;
        for (int k = 1; k <= nder; k++) {
            double d = 0.0;
            int rk = r - k, pk = p - k;
            if (r >= k) {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            int j1 = rk >= -1 ? 1 : -rk;
            int j2 = (r - 1 <= pk) ? k - 1 : p - r;
            for (int j = j1; j <= j2; j++) {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                d += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            int tmp = s1; s1 = s2; s2 = tmp;
        }
    }
    double f = p;
    for (int k = 1; k <= nder; k++) {
        for (int j = 0; j <= p; j++) ders[k][j] *= f;
        f *= p - k;
    }
}

void fit_surface_eval(const q2n_bspline_surface *s, double u, double v, int nder, double *out)
{
    double Bu[3][FIT_DEG + 1], Bv[3][FIT_DEG + 1];
    int su = fit_span(s->ncp_u, s->knots_u, u), sv = fit_span(s->ncp_v, s->knots_v, v);
    fit_basis(su, s->knots_u, u, nder, Bu);
    fit_basis(sv, s->knots_v, v, nder, Bv);
    /* (a,b) = derivative orders in u and v for each output slot (surface.h layout). */
    static const int du[6] = {0, 1, 0, 2, 1, 0}, dv[6] = {0, 0, 1, 0, 1, 2};
    int nout = nder == 0 ? 1 : nder == 1 ? 3 : 6;
    memset(out, 0, 3 * (size_t)nout * sizeof *out);
    for (int b = 0; b <= FIT_DEG; b++) {
        int j = sv - FIT_DEG + b;
        for (int a = 0; a <= FIT_DEG; a++) {
            int i = su - FIT_DEG + a;
            const double *P = s->cp + 3 * ((size_t)j * s->ncp_u + i);
            for (int o = 0; o < nout; o++) {
                double w = Bu[du[o]][a] * Bv[dv[o]][b];
                out[3 * o] += w * P[0];
                out[3 * o + 1] += w * P[1];
                out[3 * o + 2] += w * P[2];
            }
        }
    }
}
