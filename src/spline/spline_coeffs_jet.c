/* spline_coeffs_jet.c — q2n_spline_coeffs: the knot functionals (spline_coeffs.inc) on order-2
 * jets, for the augmented patches' derivatives in the cross parameter. */
#include "spline/spline.h"

#define SC_T q2n_jet
#define SC_FN(name) name
#define SC_CONST q2n_jet_const
#define SC_ADD q2n_jet_add
#define SC_SUB q2n_jet_sub
#define SC_MUL q2n_jet_mul
#define SC_INV q2n_jet_inv
#define SC_SCALE q2n_jet_scale
#include "spline/spline_coeffs.inc"
