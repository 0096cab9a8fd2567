/* spline.h — local univariate interpolating splines of class DgCkPmSw (seed 003 §2, Appendix A).
 *
 * On the interval [x_s, x_{s+1}] of length D = d_s, the w fundamental functions that do not
 * vanish there, ψ_{s-w/2+1} .. ψ_{s+w/2}, depend only on the local parameter vector
 * d = (d_{s-w/2+1}, ..., d_s, ..., d_{s+w/2-1}) (eq. 3–4).  Every class implemented here has the
 * form
 *        ψ_i(x; d) = Σ_r B_r(x/D) · C_{r,i}(d),
 * where B_r are 2(k+1) fixed functions on [0,1] (a Hermite-type basis: value and derivatives up
 * to order k at both ends, possibly piecewise) and C_{r,i} are the D^a-scaled weights of the
 * derivative functionals at the two interval ends (formulas.md §3.3: the derivatives of the
 * Lagrange interpolant through the nearby knots).  The split into a t-basis and d-dependent
 * coefficients is what makes augmented patches cheap to evaluate: x/D = u on a patch.
 * The coefficients are computed on jets (core/jet.h) so their derivatives with respect to the
 * variable the intervals depend on come for free. */
#ifndef Q2N_SPLINE_SPLINE_H
#define Q2N_SPLINE_SPLINE_H

#include "core/jet.h"

#define Q2N_SPLINE_MAXW 6      /* largest support width */
#define Q2N_SPLINE_MAXB 6      /* largest number of basis functions B_r = 2(k+1) */

typedef struct q2n_spline_class {
    const char *name;          /* e.g. "D5C2P2S4" */
    int g, k, m, w;            /* degree, continuity, reproduction degree, support width */
    int nb;                    /* number of basis functions 2(k+1) */
    int nlagr;                 /* nodes of the Lagrange interpolant giving the functionals */
    /* B_r(t) and its derivatives up to order nder (<= 3) at t in [0,1]: out[d*nb + r]. */
    void (*basis)(double t, int nder, double *out);
} q2n_spline_class;

/* Registry: the classes this build provides, NULL-terminated; lookup by name (case-insensitive). */
/* The product's default class: D5C2P4S6 (C2, reproduces quartics, support 6) is the fairest class
 * that keeps G2 on the shared meshes (docs/extraordinary.md, "Default class"). */
#define Q2N_SPLINE_CLASS_DEFAULT "D5C2P4S6"

const q2n_spline_class *const *q2n_spline_classes(void);
const q2n_spline_class *q2n_spline_class_find(const char *name);

/* Coefficients C[r*w + i] (r < nb, i < w) for the local parameter vector d[0..w-2] (jets). */
void q2n_spline_coeffs(const q2n_spline_class *c, const q2n_jet *d, q2n_jet *C);
/* The same for values only (each jet's d[0]; the same numbers, bit for bit). */
void q2n_spline_coeffs_value(const q2n_spline_class *c, const double *d, double *C);

/* Fundamental functions on [0, D], D = d[w/2-1], at x, with x-derivatives up to nder (<= 3):
 * psi[q*w + i] = d^q/dx^q ψ_i(x; d), i = 0..w-1 standing for s-w/2+1 .. s+w/2. */
void q2n_spline_fundamental(const q2n_spline_class *c, const double *d, double x, int nder,
                            double *psi);

/* Evaluate the interpolating curve of points p[0..n-1] (dim-dimensional, stride dim) with
 * parameter intervals iv[j] = x_{j+1}-x_j, on interval s at local x in [0, iv[s]], derivatives up to
 * nder into out[q*dim + c].  closed != 0: periodic data (p[n] = p[0]); open curves need
 * s-w/2+1 >= 0 and s+w/2 <= n-1.  Returns 0, or -1 if the window leaves an open polyline. */
int q2n_spline_curve_eval(const q2n_spline_class *c, int n, int dim, const double *p,
                          const double *iv, int closed, int s, double x, int nder, double *out);

/* Local parametrization function of degree 2k+1 (eq. 7): δ(0)=a, δ(1)=b, derivatives of order
 * 1..k vanish at 0 and 1.  Returns the jet of δ at t (value, first and second derivative). */
q2n_jet q2n_spline_blend(int k, double a, double b, double t);
/* Its value only, as the weight h(t) of δ = a + (b - a) h(t): the same bits as the jet's value. */
double q2n_spline_blend_weight(int k, double t);
/* The same with derivatives up to 3: out[0..3]. */
void q2n_spline_blend_derivs(int k, double a, double b, double t, double out[4]);

#endif
