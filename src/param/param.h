/* param.h — parameter intervals of mesh edges (pipeline stage 2, seed 003 §3 eq. (5)–(6), §3.1).
 *
 * The augmented parametrization gives every edge its own interval d = |p1 - p0|^α
 * (centripetal α = 1/2, chordal α = 1, uniform α = 0).  The *mean* parametrization of §3.1 —
 * the tensor-product baseline the paper compares against — gives every edge of an edge ribbon
 * (chain of pairwise opposite quad edges) the average of the ribbon's intervals, so the
 * intervals of every face form a rectangle. */
#ifndef Q2N_PARAM_PARAM_H
#define Q2N_PARAM_PARAM_H

#include "core/error.h"
#include "mesh/mesh.h"

/* q2n_param_method (Q2N_PARAM_*): include/quad2nurbs.h.  Centripetal |Δp|^α (α = 1/2 unless
 * overridden), chordal α = 1, uniform α = 0, mean: ribbon average of |Δp|^α. */

typedef struct q2n_param_options {
    q2n_param_method method;
    double alpha;      /* exponent > 0; 0 (zeroed options) or NaN means 1/2 — uniform is
                          Q2N_PARAM_UNIFORM, not alpha 0 */
} q2n_param_options;

/* Exponent actually used by the options. */
double q2n_param_alpha(const q2n_param_options *opt);

/* |b - a|^alpha (alpha = 0 gives 1). */
double q2n_param_interval(const double a[3], const double b[3], double alpha);

/* Intervals of all undirected edges (indexed like mesh->he_edge); *iv is malloc'ed. */
q2n_status q2n_param_edge_intervals(const q2n_mesh *m, const q2n_param_options *opt, double **iv,
                                    q2n_error *err);

/* Parse "centripetal|chordal|uniform|mean"; returns 0 on success. */
int q2n_param_method_parse(const char *s, q2n_param_method *out);
const char *q2n_param_method_name(q2n_param_method m);

#endif
