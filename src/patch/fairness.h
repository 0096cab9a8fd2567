/* fairness.h — how fair a built surface is, in the figures of ../shared/tools/fairness.py (issue
 * 11), measured on the construction itself: the curvature oscillation along the faces' diagonals
 * and the bending energy.  The model uses them to choose between two builds of the same mesh
 * (api/model.c, the isotropic frame). */
#ifndef Q2N_PATCH_FAIRNESS_H
#define Q2N_PATCH_FAIRNESS_H

#include "patch/surface.h"

typedef struct q2n_fairness {
    double ripple;  /* sum over the covered patches' two diagonals of osc (below) */
    double energy;  /* bending energy, the integral of k1^2 + k2^2 over the covered patches */
    double ripple_ev; /* the ripple of the extraordinary regions' patches (Q2N_PATCH_COONS_GREGORY) */
} q2n_fairness;

/* Along each diagonal of each covered patch ((t, t) and (t, 1 - t), n >= 3 samples), with H the
 * mean curvature, TV = sum |dH| and L the polyline's length:
 *     osc = (TV - |H_end - H_start|) L / 2,
 * zero where H is monotone along the line, growing with every bump; dimensionless (invariant under
 * uniform scaling).  The energy, integral of (k1^2 + k2^2) = (4 H^2 - 2 K) over each patch, by a
 * q x q Gauss–Legendre rule (q <= 32): dimensionless too.  Both INFINITY where an evaluation fails
 * or a normal vanishes (a fold's cusp).  Results do not depend on threads. */
q2n_fairness q2n_surface_fairness(const q2n_surface *s, int n, int q, int threads);

/* The same per patch: out[k][0] patch k's ripple (both diagonals), out[k][1] its energy (0, 0 for an
 * uncovered patch). */
void q2n_surface_fairness_patches(const q2n_surface *s, int n, int q, int threads, double (*out)[2]);

/* Mean and Gaussian curvature from S_u, S_v, S_uu, S_uv, S_vv (the q2n_surface_eval layout at
 * nder = 2) and the area element |S_u x S_v|; 0 (and H = K = NAN) where S_u x S_v vanishes. */
double q2n_curvatures(const double *e, double *H, double *K);

#endif
