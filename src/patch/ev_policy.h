/* ev_policy.h — tuning constants of the extraordinary-vertex constructions, each with its why.
 * The files that implement the papers' formulas hold none of these. */
#ifndef Q2N_PATCH_EV_POLICY_H
#define Q2N_PATCH_EV_POLICY_H

/* Gauss–Legendre points per direction for the fairness energy of a patch: the patches are
 * polynomials of degree up to ~17 along a side; with 6 the bending-only solve found shapes whose
 * wiggles fall between the nodes (3x the oscillation on osd_catmark_righthanded), while 8 and 10
 * give the same surfaces to 1 % (8 costs 0.64 of 10). */
#ifndef EV_FAIR_GAUSS
#define EV_FAIR_GAUSS 8
#endif

/* Weight of the curvature-variation term against bending (both dimensionless per face): it is
 * what removes the ripples (bending alone ranks a wavy and a smooth cap alike); larger values
 * trade bending for monotone curvature. */
#ifndef EV_FAIR_W3
#define EV_FAIR_W3 0.1
#endif

/* A face whose variation after the bending-only pass exceeds this many times the median face's
 * gets its variation weight scaled down to that level: thin features (a rim of a few percent of
 * the model) must change curvature fast, and unweighted they would dictate the shape elsewhere. */
#define EV_FAIR_VAR_OUTLIER 4.0

/* Ridge towards the local estimates (q2n_ev_vertex_jets), relative to each unknown's own energy
 * diagonal.  First and second order: keeps tangent planes and curvatures near the mesh's local
 * shape where the energy is indifferent; third/fourth order and bubbles: only makes the system
 * definite (the energy decides). */
#define EV_FAIR_RIDGE_LOW 1e-3
#define EV_FAIR_RIDGE_HIGH 1e-6

/* Two sides of a corner "agree" when their mixed derivatives differ by less than this fraction of
 * the corner's first- and mixed-derivative scale (rounding of the regular patches' jets); beyond
 * it the corner keeps a Gregory blend. */
#define EV_FAIR_COMPAT_REL 1e-9

/* Worker threads of the fair solve's per-face forms: more gain nothing on the machines we target
 * and each costs a stack. */
#define Q2N_EV_MAX_THREADS 64

/* Relative difference of two faces' transversality below which an edge's base face is its owner
 * face instead of the more transversal one: differences that small are rounding (a symmetric
 * mesh computed in floating point), and without the margin one ulp of input flipped the choice
 * and moved the surface by 0.45 % of the diagonal (exact cube).  Genuine differences are far
 * larger. */
#define EV_FAIR_BASE_TIE 1e-9

#endif
