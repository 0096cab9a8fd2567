/* poly.h — small polynomial numerics, one home each: binomial coefficients, derivatives of
 * power-basis polynomials, degree elevation of Bézier coefficients, and Gauss–Legendre rules.
 * (Hermite bases: core/hermite.h; Taylor arithmetic: core/jet.h.) */
#ifndef Q2N_CORE_POLY_H
#define Q2N_CORE_POLY_H

#define Q2N_BINOM_MAX 16

/* q2n_binom[n][k] = C(n, k) for 0 <= k <= n <= Q2N_BINOM_MAX (0 for k > n): exact integers. */
extern const double q2n_binom[Q2N_BINOM_MAX + 1][Q2N_BINOM_MAX + 1];

/* q2n_factorial[n] = n! for n <= Q2N_BINOM_MAX: exact integers. */
extern const double q2n_factorial[Q2N_BINOM_MAX + 1];

/* q-th derivatives (q <= nder) of the power-basis polynomial c[0..deg] at t (Horner):
 * out[q * dim + j] for the dim polynomials whose coefficients are interleaved, c[i * dim + j]. */
void q2n_poly_derivs_n(const double *c, int dim, int deg, double t, int nder, double *out);
/* The same for one polynomial (dim 1). */
void q2n_poly_derivs(const double *c, int deg, double t, int nder, double *out);

/* Degree elevation of Bézier coefficients from degree n to degree m >= n (Farin, Curves and
 * Surfaces for CAGD, §6.1 applied m - n times at once):  b'_i = Σ_j C(n, j) C(m-n, i-j) / C(m, i) b_j.
 * E[i * (n + 1) + j] gets the weight of b_j in b'_i (m + 1 rows; m <= Q2N_BINOM_MAX). */
void q2n_bezier_elevation(int n, int m, double *E);
/* A tensor-product patch of degree (du, dv) elevated to (mu, mv): control points of dim doubles,
 * cp[(j * (du + 1) + i) * dim], out[(J * (mu + 1) + I) * dim]. */
void q2n_bezier_elevate(int du, int dv, int mu, int mv, int dim, const double *cp, double *out);

/* Gauss–Legendre rule of n points (n <= 32) on [0,1]: nodes x (decreasing) and weights w
 * (Newton's method on the Legendre polynomial P_n; Golub & Welsch would do as well). */
void q2n_gauss_legendre01(int n, double *x, double *w);

#endif
