/* bspline.h — tensor-product (rational) B-spline surfaces: the fit stage's output and the
 * export stage's input (pipeline stage 4).
 *
 * A q2n_nurbs_model holds one surface per mesh face, in face order, each on [0,1]^2 with the
 * face's orientation (u along v0->v1, v along v0->v3), clamped knot vectors.  Shared mesh edges
 * carry identical boundary curves on both sides (watertight) — the STEP/IGES writers rely on it
 * to emit one edge curve per mesh edge. */
#ifndef Q2N_FIT_BSPLINE_H
#define Q2N_FIT_BSPLINE_H

#include "core/error.h"
#include "mesh/mesh.h"

typedef struct q2n_bspline_surface {
    int deg_u, deg_v;   /* degrees */
    int ncp_u, ncp_v;   /* control points per direction */
    double *knots_u;    /* ncp_u + deg_u + 1, clamped, from 0 to 1 */
    double *knots_v;    /* ncp_v + deg_v + 1 */
    double *cp;         /* 3 * ncp_u * ncp_v, u fastest: cp[3*(j*ncp_u + i)] */
    double *weights;    /* ncp_u * ncp_v, or NULL for a polynomial (non-rational) surface */
} q2n_bspline_surface;

/* A polynomial B-spline curve in 3-space (clamped knots on [0,1]). */
typedef struct q2n_bspline_curve {
    int deg, ncp;
    double *knots;      /* ncp + deg + 1 */
    double *cp;         /* 3 * ncp */
} q2n_bspline_curve;

/* What the export stage needs: the surfaces plus the mesh they sit on (edges shared by two
 * faces become shared CAD edges) and the tolerance they were fitted to. */
typedef struct q2n_nurbs_model {
    int n;                          /* = mesh->nf */
    q2n_bspline_surface *patches;   /* n surfaces, patch k on face k */
    const q2n_mesh *mesh;           /* borrowed */
    double tol_abs;                 /* fit tolerance in model units (sets file resolutions) */
    /* Optional (NULL: the writers take each edge from its owner patch's boundary): one curve per
     * mesh edge, parameter 0 at the origin of mesh->edge_he[e].  Each patch boundary along edge e
     * is this curve re-expressed on the patch's knots by knot insertion (the same curve; control
     * points bit-identical where the knots agree). */
    q2n_bspline_curve *edges;
} q2n_nurbs_model;

/* Highest degree the evaluators support (stack buffers); q2n_bspline_check enforces it. */
#define Q2N_BSPLINE_MAX_DEG 15

/* Knot span index i with knots[i] <= t < knots[i+1], p <= i <= n-1 (n control points, degree p);
 * t at (or beyond) either end maps to the first / last non-empty span.  A2.1, NURBS Book. */
int q2n_bspline_span(int n, int p, const double *knots, double t);
/* The p+1 non-zero basis functions of span i at t and their derivatives up to order nder:
 * ders[k * (p + 1) + a] = d^k/dt^k N_{i-p+a,p}(t) (A2.3, NURBS Book; p <= Q2N_BSPLINE_MAX_DEG).
 * The one B-spline basis of the library: the fit (degree 5, fit_internal.h) and the evaluators. */
void q2n_bspline_basis(int i, int p, const double *knots, double t, int nder, double *ders);

/* Evaluate a B-spline surface (value and first derivatives; d may be NULL): p[3], du[3], dv[3]. */
void q2n_bspline_eval(const q2n_bspline_surface *s, double u, double v, double p[3], double du[3],
                      double dv[3]);
/* Knot-vector and size checks (tests, writers). */
q2n_status q2n_bspline_check(const q2n_bspline_surface *s, q2n_error *err);
void q2n_bspline_free(q2n_bspline_surface *s);      /* frees the arrays, not s itself */
void q2n_nurbs_model_free(q2n_nurbs_model *m);      /* frees patches and edges; NULL is a no-op */
/* Evaluate a curve (point, first derivative; d may be NULL). */
void q2n_bspline_curve_eval(const q2n_bspline_curve *c, double t, double p[3], double d[3]);

#endif
