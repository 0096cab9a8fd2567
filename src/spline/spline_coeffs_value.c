/* spline_coeffs_value.c — q2n_spline_coeffs_value: the knot functionals (spline_coeffs.inc) on
 * plain values, for position evaluations (each operation is the d[0] of the jet one: the same
 * numbers as q2n_spline_coeffs' values, bit for bit). */
#include "spline/spline.h"

#define SC_T double
#define SC_FN(name) name##_value
#define SC_CONST(a) ((double)(a))
#define SC_ADD(a, b) ((a) + (b))
#define SC_SUB(a, b) ((a) - (b))
#define SC_MUL(a, b) ((a) * (b))
#define SC_INV(a) (1.0 / (a))
#define SC_SCALE(s, a) ((s) * (a))
#include "spline/spline_coeffs.inc"
