/* jet.h — truncated Taylor arithmetic in one variable ("jets"), the one home of it.  A jet of
 * order n holds the derivatives f(t0), f'(t0), ..., f^(n)(t0) of a function at a point; sums,
 * products (Leibniz' rule), reciprocals and inverse square roots (Faà di Bruno) of jets are the
 * jets of the sums, products, ... of the functions, so a formula evaluated on jets gives its exact
 * derivatives without hand-derived formulas (forward-mode automatic differentiation; Griewank &
 * Walther, Evaluating Derivatives, 2nd ed., ch. 13).
 *
 * Two spellings of the same rules:
 *   - arrays a[0..n] (n <= Q2N_JET_MAXN), scalar or 3-vector valued (q2n_jet_*_n, q2n_jet3_*):
 *     the extraordinary-vertex curve network (patch/curve_network.c) needs order 3;
 *   - q2n_jet, the order-2 value type: the augmented patches depend on v through the local
 *     parametrization functions δ(v) inside rational functionals, and this is their hot path.  Its
 *     operations are the array rules written out for n = 2 (tests/test_spline.c checks that they
 *     agree bit for bit). */
#ifndef Q2N_CORE_JET_H
#define Q2N_CORE_JET_H

#include <math.h>
#include <string.h>

#include "core/poly.h"

#define Q2N_JET_MAXN 5 /* largest order of the array jets */

/* ---- array jets: a[k] = k-th derivative, k = 0..n; results may alias the arguments ---- */

/* r = a b: r_k = Σ_i C(k, i) a_i b_(k-i). */
static inline void q2n_jet_mul_n(int n, const double *a, const double *b, double *r)
{
    double t[Q2N_JET_MAXN + 1];
    for (int k = 0; k <= n; k++) {
        double s = a[0] * b[k];
        for (int i = 1; i <= k; i++) s += q2n_binom[k][i] * a[i] * b[k - i];
        t[k] = s;
    }
    memcpy(r, t, sizeof(double) * (size_t)(n + 1));
}

/* r = 1 / a (a[0] != 0): from (a r)_k = 0 for k >= 1, r_k = -(Σ_{i>=1} C(k, i) a_i r_(k-i)) / a_0. */
static inline void q2n_jet_inv_n(int n, const double *a, double *r)
{
    double t[Q2N_JET_MAXN + 1];
    t[0] = 1.0 / a[0];
    for (int k = 1; k <= n; k++) {
        double s = q2n_binom[k][1] * a[1] * t[k - 1];
        for (int i = 2; i <= k; i++) s += q2n_binom[k][i] * a[i] * t[k - i];
        t[k] = -s * t[0];
    }
    memcpy(r, t, sizeof(double) * (size_t)(n + 1));
}

/* r = a^(-1/2) (a[0] > 0), n <= 3: Faà di Bruno with the derivatives f^(j) of x^(-1/2). */
static inline void q2n_jet_rsqrt_n(int n, const double *a, double *r)
{
    double x = a[0], f1 = -0.5 * pow(x, -1.5), f2 = 0.75 * pow(x, -2.5), f3 = -1.875 * pow(x, -3.5), t[4];
    t[0] = 1 / sqrt(x);
    t[1] = f1 * a[1];
    t[2] = n >= 2 ? f2 * a[1] * a[1] + f1 * a[2] : 0;
    t[3] = n >= 3 ? f3 * a[1] * a[1] * a[1] + 3 * f2 * a[1] * a[2] + f1 * a[3] : 0;
    memcpy(r, t, sizeof(double) * (size_t)(n + 1));
}

/* 3-vector jets V[k][xyz].  R = s V for a scalar jet s. */
static inline void q2n_jet3_scale(int n, const double *s, double (*V)[3], double (*R)[3])
{
    double T[Q2N_JET_MAXN + 1][3];
    for (int k = 0; k <= n; k++)
        for (int c = 0; c < 3; c++) {
            double x = s[0] * V[k][c];
            for (int i = 1; i <= k; i++) x += q2n_binom[k][i] * s[i] * V[k - i][c];
            T[k][c] = x;
        }
    memcpy(R, T, sizeof(double) * 3 * (size_t)(n + 1));
}

/* R = A x B. */
static inline void q2n_jet3_cross(int n, double (*A)[3], double (*B)[3], double (*R)[3])
{
    double T[Q2N_JET_MAXN + 1][3];
    for (int k = 0; k <= n; k++) {
        T[k][0] = T[k][1] = T[k][2] = 0;
        for (int i = 0; i <= k; i++) {
            const double *a = A[i], *b = B[k - i], w = q2n_binom[k][i];
            T[k][0] += w * (a[1] * b[2] - a[2] * b[1]);
            T[k][1] += w * (a[2] * b[0] - a[0] * b[2]);
            T[k][2] += w * (a[0] * b[1] - a[1] * b[0]);
        }
    }
    memcpy(R, T, sizeof(double) * 3 * (size_t)(n + 1));
}

/* r = A · B (a scalar jet). */
static inline void q2n_jet3_dot(int n, double (*A)[3], double (*B)[3], double *r)
{
    double t[Q2N_JET_MAXN + 1];
    for (int k = 0; k <= n; k++) {
        t[k] = 0;
        for (int i = 0; i <= k; i++)
            t[k] += q2n_binom[k][i] * (A[i][0] * B[k - i][0] + A[i][1] * B[k - i][1] + A[i][2] * B[k - i][2]);
    }
    memcpy(r, t, sizeof(double) * (size_t)(n + 1));
}

/* R = A + B. */
static inline void q2n_jet3_add(int n, double (*A)[3], double (*B)[3], double (*R)[3])
{
    for (int k = 0; k <= n; k++)
        for (int c = 0; c < 3; c++) R[k][c] = A[k][c] + B[k][c];
}

/* ---- the order-2 value type: d[k] = k-th derivative, k = 0, 1, 2 ---- */

typedef struct q2n_jet { double d[3]; } q2n_jet;

static inline q2n_jet q2n_jet_const(double a) { q2n_jet r = {{a, 0, 0}}; return r; }
static inline q2n_jet q2n_jet_add(q2n_jet a, q2n_jet b)
{ q2n_jet r = {{a.d[0] + b.d[0], a.d[1] + b.d[1], a.d[2] + b.d[2]}}; return r; }
static inline q2n_jet q2n_jet_sub(q2n_jet a, q2n_jet b)
{ q2n_jet r = {{a.d[0] - b.d[0], a.d[1] - b.d[1], a.d[2] - b.d[2]}}; return r; }
static inline q2n_jet q2n_jet_scale(double s, q2n_jet a)
{ q2n_jet r = {{s * a.d[0], s * a.d[1], s * a.d[2]}}; return r; }
/* q2n_jet_mul_n for n = 2 */
static inline q2n_jet q2n_jet_mul(q2n_jet a, q2n_jet b)
{
    q2n_jet r = {{a.d[0] * b.d[0], a.d[0] * b.d[1] + a.d[1] * b.d[0],
                  a.d[0] * b.d[2] + 2 * a.d[1] * b.d[1] + a.d[2] * b.d[0]}};
    return r;
}
/* q2n_jet_inv_n for n = 2 */
static inline q2n_jet q2n_jet_inv(q2n_jet a)
{
    double i0 = 1.0 / a.d[0], i1 = -(a.d[1] * i0) * i0;
    q2n_jet r = {{i0, i1, -(2 * a.d[1] * i1 + a.d[2] * i0) * i0}};
    return r;
}
static inline q2n_jet q2n_jet_div(q2n_jet a, q2n_jet b) { return q2n_jet_mul(a, q2n_jet_inv(b)); }
/* derivative of order k (0, 1, 2) of the function the jet represents */
static inline double q2n_jet_deriv(q2n_jet a, int k) { return a.d[k]; }

#endif
