/* jet.h — truncated Taylor arithmetic in one variable (order 2): a jet holds f(t0), f'(t0)
 * and f''(t0)/2.  The augmented patches depend on v through the local parametrization
 * functions δ(v) inside rational functionals; evaluating those functionals on jets gives their
 * exact first and second v-derivatives without hand-derived formulas (forward-mode AD). */
#ifndef Q2N_CORE_JET_H
#define Q2N_CORE_JET_H

typedef struct q2n_jet { double c[3]; } q2n_jet; /* Taylor coefficients c0 + c1 t + c2 t^2 */

static inline q2n_jet q2n_jet_const(double a) { q2n_jet r = {{a, 0, 0}}; return r; }
static inline q2n_jet q2n_jet_add(q2n_jet a, q2n_jet b)
{ q2n_jet r = {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}}; return r; }
static inline q2n_jet q2n_jet_sub(q2n_jet a, q2n_jet b)
{ q2n_jet r = {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}}; return r; }
static inline q2n_jet q2n_jet_scale(double s, q2n_jet a)
{ q2n_jet r = {{s * a.c[0], s * a.c[1], s * a.c[2]}}; return r; }
static inline q2n_jet q2n_jet_mul(q2n_jet a, q2n_jet b)
{
    q2n_jet r = {{a.c[0] * b.c[0], a.c[0] * b.c[1] + a.c[1] * b.c[0],
                  a.c[0] * b.c[2] + a.c[1] * b.c[1] + a.c[2] * b.c[0]}};
    return r;
}
static inline q2n_jet q2n_jet_inv(q2n_jet a)
{
    double i0 = 1.0 / a.c[0], i1 = -a.c[1] * i0 * i0;
    q2n_jet r = {{i0, i1, -(a.c[1] * i1 + a.c[2] * i0) * i0}};
    return r;
}
static inline q2n_jet q2n_jet_div(q2n_jet a, q2n_jet b) { return q2n_jet_mul(a, q2n_jet_inv(b)); }
/* derivative of order d (0,1,2) of the function the jet represents */
static inline double q2n_jet_deriv(q2n_jet a, int d) { return d == 2 ? 2.0 * a.c[2] : a.c[d]; }

#endif
