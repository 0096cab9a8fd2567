/* poly.c — binomials, power-basis derivatives, degree elevation, Gauss–Legendre (poly.h). */
#include "core/poly.h"
#include "core/vec3.h"

#include <math.h>
#include <string.h>


const double q2n_binom[Q2N_BINOM_MAX + 1][Q2N_BINOM_MAX + 1] = {
    {1},
    {1, 1},
    {1, 2, 1},
    {1, 3, 3, 1},
    {1, 4, 6, 4, 1},
    {1, 5, 10, 10, 5, 1},
    {1, 6, 15, 20, 15, 6, 1},
    {1, 7, 21, 35, 35, 21, 7, 1},
    {1, 8, 28, 56, 70, 56, 28, 8, 1},
    {1, 9, 36, 84, 126, 126, 84, 36, 9, 1},
    {1, 10, 45, 120, 210, 252, 210, 120, 45, 10, 1},
    {1, 11, 55, 165, 330, 462, 462, 330, 165, 55, 11, 1},
    {1, 12, 66, 220, 495, 792, 924, 792, 495, 220, 66, 12, 1},
    {1, 13, 78, 286, 715, 1287, 1716, 1716, 1287, 715, 286, 78, 13, 1},
    {1, 14, 91, 364, 1001, 2002, 3003, 3432, 3003, 2002, 1001, 364, 91, 14, 1},
    {1, 15, 105, 455, 1365, 3003, 5005, 6435, 6435, 5005, 3003, 1365, 455, 105, 15, 1},
    {1, 16, 120, 560, 1820, 4368, 8008, 11440, 12870, 11440, 8008, 4368, 1820, 560, 120, 16, 1}};

const double q2n_factorial[Q2N_BINOM_MAX + 1] = {1, 1, 2, 6, 24, 120, 720, 5040, 40320, 362880, 3628800, 39916800, 479001600, 6227020800, 87178291200, 1307674368000, 20922789888000};

void q2n_poly_derivs_n(const double *c, int dim, int deg, double t, int nder, double *out)
{
    for (int q = 0; q <= nder; q++)
        for (int j = 0; j < dim; j++) {
            double r = 0;
            for (int i = deg; i >= q; i--) {
                double f = 1;
                for (int k = 0; k < q; k++) f *= (double)(i - k);
                r = r * t + f * c[i * dim + j];
            }
            out[q * dim + j] = r;
        }
}

void q2n_poly_derivs(const double *c, int deg, double t, int nder, double *out)
{
    q2n_poly_derivs_n(c, 1, deg, t, nder, out);
}

void q2n_bezier_elevation(int n, int m, double *E)
{
    for (int i = 0; i <= m; i++)
        for (int j = 0; j <= n; j++)
            E[i * (n + 1) + j] = i - j >= 0 && i - j <= m - n
                                     ? q2n_binom[n][j] * q2n_binom[m - n][i - j] / q2n_binom[m][i]
                                     : 0.0;
}

void q2n_bezier_elevate(int du, int dv, int mu, int mv, int dim, const double *cp, double *out)
{
    if (du == mu && dv == mv) { /* nothing to elevate: the points as they are (signed zeros too) */
        memcpy(out, cp, sizeof(double) * (size_t)dim * (size_t)(mu + 1) * (size_t)(mv + 1));
        return;
    }
    double Eu[(Q2N_BINOM_MAX + 1) * (Q2N_BINOM_MAX + 1)], Ev[(Q2N_BINOM_MAX + 1) * (Q2N_BINOM_MAX + 1)];
    q2n_bezier_elevation(du, mu, Eu);
    q2n_bezier_elevation(dv, mv, Ev);
    memset(out, 0, sizeof(double) * (size_t)dim * (size_t)(mu + 1) * (size_t)(mv + 1));
    for (int J = 0; J <= mv; J++)
        for (int I = 0; I <= mu; I++) {
            double *o = out + (size_t)(J * (mu + 1) + I) * dim;
            for (int b = 0; b <= dv; b++)
                for (int a = 0; a <= du; a++) {
                    double w = Eu[I * (du + 1) + a] * Ev[J * (dv + 1) + b];
                    if (w == 0.0) continue;
                    const double *p = cp + (size_t)(b * (du + 1) + a) * dim;
                    for (int k = 0; k < dim; k++) o[k] += w * p[k];
                }
        }
}

void q2n_gauss_legendre01(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double z = cos(Q2N_PI * (i + 0.75) / (n + 0.5)), pp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = 0;
            for (int j = 0; j < n; j++) { double p2 = p1; p1 = p0; p0 = ((2 * j + 1) * z * p1 - j * p2) / (j + 1); }
            pp = n * (z * p0 - p1) / (z * z - 1);
            double z1 = z;
            z = z1 - p0 / pp;
            if (fabs(z - z1) < 1e-15) break;
        }
        x[i] = 0.5 * (1 - z);
        w[i] = 1 / ((1 - z * z) * pp * pp);
    }
}
