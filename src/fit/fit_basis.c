/* fit_basis.c — the quintic B-spline basis the fit works in: clamped knot vectors from interior
 * breakpoints, span search, basis functions with first and second derivatives (Piegl & Tiller, The
 * NURBS Book 1997, A2.1 FindSpan and A2.3 DersBasisFuns), knot insertion (A5.4), the fit's sample
 * and check parameters, and second-order evaluation of fitted surfaces (the continuity
 * measurements need curvatures, which q2n_bspline_eval does not give). */
#include "fit/fit_internal.h"

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
    for (int i = Q2N_FIT_DEG; i < n; i++) {
        double a = kv[i], b = kv[i + 1];
        for (int j = 0; j < per_span; j++) out[c++] = a + (b - a) * (2 * j + 1) / (2 * per_span);
    }
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

int q2n_fit_span(int n, const double *kv, double t)
{
    if (t >= kv[n]) return n - 1;
    if (t <= kv[Q2N_FIT_DEG]) return Q2N_FIT_DEG;
    int lo = Q2N_FIT_DEG, hi = n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (t < kv[mid]) hi = mid;
        else lo = mid;
    }
    return lo;
}

/* A2.3 of the NURBS Book: triangular table of basis functions and knot differences, then the
 * derivative recurrence eq. (2.10) up to order nder. */
void q2n_fit_basis(int i, const double *kv, double t, int nder, double ders[3][Q2N_FIT_DEG + 1])
{
    enum { p = Q2N_FIT_DEG };
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

void q2n_fit_surface_eval(const q2n_bspline_surface *s, double u, double v, int nder, double *out)
{
    double Bu[3][Q2N_FIT_DEG + 1], Bv[3][Q2N_FIT_DEG + 1];
    int su = q2n_fit_span(s->ncp_u, s->knots_u, u), sv = q2n_fit_span(s->ncp_v, s->knots_v, v);
    q2n_fit_basis(su, s->knots_u, u, nder, Bu);
    q2n_fit_basis(sv, s->knots_v, v, nder, Bv);
    /* (a,b) = derivative orders in u and v for each output slot (surface.h layout). */
    static const int du[6] = {0, 1, 0, 2, 1, 0}, dv[6] = {0, 0, 1, 0, 1, 2};
    int nout = nder == 0 ? 1 : nder == 1 ? 3 : 6;
    memset(out, 0, 3 * (size_t)nout * sizeof *out);
    for (int b = 0; b <= Q2N_FIT_DEG; b++) {
        int j = sv - Q2N_FIT_DEG + b;
        for (int a = 0; a <= Q2N_FIT_DEG; a++) {
            int i = su - Q2N_FIT_DEG + a;
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
