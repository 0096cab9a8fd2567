/* ev_fair.h — the fair extraordinary construction (ev_fair.c): one jet per vertex, compatible
 * Coons patches, jets chosen by a bending-energy solve.  Internal to src/patch/. */
#ifndef Q2N_PATCH_EV_FAIR_H
#define Q2N_PATCH_EV_FAIR_H

#include "patch/ev_internal.h"

typedef struct ev_fair_stats {
    int vertices;              /* vertices with a jet */
    int fixed_vertices;        /* of which corners of regular patches */
    int flat_vertices;         /* of which vertices whose fan is flat (keep_flat: their jets kept in its plane) */
    int edges;                 /* constructed edges between two extraordinary faces */
    int unknowns;              /* free jet coefficients (3-vectors) */
    int gregory_corners;       /* corners whose two sides disagreed (kept a Gregory blend) */
    double corner_mismatch_max;/* largest relative disagreement of two sides at a corner */
    int held_vertices;         /* vertices whose jets of order <= 2 the fold guard held at their local estimates */
    int folded_faces;          /* faces still folded after the guard (0 unless it ran out of passes) */
    int shrinks;               /* halvings of the held jets in the kept solution (0: the local estimates themselves) */
    int polynomial_edges;      /* constructed edges glued by polynomials (ev_fair_gluing.c; G2 patches: ev_fair_gluing2.c too) */
    int jac_pinned_faces;      /* faces whose Jacobian the polynomial gluing collapsed: their corners kept out of it */
    int border_edges;          /* G1: of the polynomial edges, those glued flat at a regular patch's corner */
    int noflat_vertices;       /* G1: cross-charted vertices near sheared faces whose edges gave that up (border guard) */
} ev_fair_stats;

/* Give every uncovered face of s a fair patch of continuity order K (1: G1, 2: G2).  iv: the
 * edge intervals the regular patches were built with; chart_mesh: m under a linear map, on which
 * the vertex charts are measured (NULL: m); keep_flat: vertices whose fan is flat (EV_FLAT_REL)
 * keep the surface in its plane exactly; threads: workers for the energy assembly (the result does
 * not depend on it); smooth_v: per vertex of m, 1 where the polynomial gluing keeps out (its edges keep
 * the smoothsteps; NULL: none); stats may be NULL. */
q2n_status q2n_ev_fair_build(const q2n_mesh *m, const q2n_mesh *chart_mesh, q2n_surface *s, const double *iv, const q2n_spline_class *cls, int K,
                         int keep_flat, int poly_gluing, const char *smooth_v, int threads, ev_fair_stats *stats, q2n_error *err);

#endif
