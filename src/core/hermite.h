/* hermite.h — Hermite basis polynomials on [0,1] of order K = 1..4 (degree 2K+1), the one home
 * of these tables (formulas.md §4.1 prints K = 1, 2; K = 3, 4 are the same conditions solved
 * exactly in rational arithmetic):
 *     H_{a,e}^{(c)}(e') = δ_ac δ_ee',   a, c = 0..K,  e, e' in {0, 1}.
 * A polynomial with derivatives f^{(a)}(0) = f0[a], f^{(a)}(1) = f1[a] (a <= K) is
 * Σ_a f0[a] H_{a,0} + f1[a] H_{a,1}.  Coefficients in the power basis t^0 .. t^9. */
#ifndef Q2N_CORE_HERMITE_H
#define Q2N_CORE_HERMITE_H

#include "core/poly.h"

#define Q2N_HERMITE_MAXK 4
#define Q2N_HERMITE_MAXD 8 /* derivatives that q2n_hermite_eval returns at most */

extern const double q2n_hermite_coef[Q2N_HERMITE_MAXK][Q2N_HERMITE_MAXK + 1][2][10];

/* H[a][e][q] = q-th derivative of H_{a,e} (order K) at t, a <= K, q <= nder (<= Q2N_HERMITE_MAXD). */
void q2n_hermite_eval(int K, double t, int nder, double H[][2][Q2N_HERMITE_MAXD + 1]);

#endif
