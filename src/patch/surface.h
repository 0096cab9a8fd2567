/* surface.h — the composite surface: one patch per mesh face (pipeline stage 3).
 *
 * Contract: patch k is built on mesh face k; its domain is [0,1]^2 with u along the face's
 * first edge (v0 -> v1) and v along v0 -> v3.  Every surface construction (augmented
 * interpolatory patches, Coons–Gregory patches at extraordinary vertices, the Catmull–Clark
 * ACC path in src/acc/) fills this container; fitting and export read it through
 * q2n_surface_eval() and, for polynomial patches, q2n_surface_bezier(). */
#ifndef Q2N_PATCH_SURFACE_H
#define Q2N_PATCH_SURFACE_H

#include "core/error.h"

typedef enum q2n_patch_kind {
    Q2N_PATCH_UNCOVERED = 0, /* no construction covers this face (yet): never evaluated */
    Q2N_PATCH_AUGMENTED,     /* regular augmented patch, eq. (10) of seed 003 */
    Q2N_PATCH_COONS_GREGORY, /* augmented Coons–Gregory patch at extraordinary vertices, §4 */
    Q2N_PATCH_BEZIER         /* tensor-product Bézier patch (ACC path): exact polynomial */
} q2n_patch_kind;

typedef struct q2n_surface q2n_surface;

/* Evaluation output layout, 3 doubles each: S, Su, Sv (nder >= 1), Suu, Suv, Svv (nder == 2). */
enum { Q2N_EV_S = 0, Q2N_EV_U = 3, Q2N_EV_V = 6, Q2N_EV_UU = 9, Q2N_EV_UV = 12, Q2N_EV_VV = 15 };
#define Q2N_EVAL_MAX 18

/* Container with n uncovered patches (producers fill them). */
q2n_surface *q2n_surface_create(int npatches);
void q2n_surface_free(q2n_surface *s); /* NULL is a no-op */

int q2n_surface_npatches(const q2n_surface *s);
q2n_patch_kind q2n_surface_kind(const q2n_surface *s, int k);
int q2n_surface_count(const q2n_surface *s, q2n_patch_kind kind);

/* Evaluate patch k at (u,v) in [0,1]^2 with derivatives up to order nder (0, 1 or 2) into
 * out[0 .. 3*(1,3,6)[nder]-1] (layout above).  Q2N_ERR_ARG for an uncovered patch,
 * Q2N_ERR_NUMERIC when a value is not finite (NaN/Inf; out is filled anyway). */
q2n_status q2n_surface_eval(const q2n_surface *s, int k, double u, double v, int nder, double *out);

/* Evaluate patch k on the tensor grid us[0..nu-1] x vs[0..nv-1] with first derivatives:
 * out has 9 doubles (S, Su, Sv) per point, u fastest.  Shares per-row work, so it is the
 * fast path for tessellation, sampling and fitting.  Q2N_ERR_NUMERIC when a value is not
 * finite (then q2n_surface_first_nonfinite finds the point). */
q2n_status q2n_surface_eval_grid(const q2n_surface *s, int k, int nu, const double *us, int nv,
                                 const double *vs, double *out);

/* Index of the first of npoints grid points (9 doubles each) with a non-finite value, or -1. */
int q2n_surface_first_nonfinite(const double *out, int npoints);

/* Scan patch k at the n x n cell centres ((i + 1/2) / n, 1 <= n <= Q2N_SCAN_MAX): Q2N_ERR_NUMERIC
 * (with *u, *v at the first bad point) when a value is not finite; otherwise *folded = 1 (and
 * *u, *v there) when the normal Su x Sv points against ref somewhere (ref: the face's vector
 * area, so the patch runs backwards over part of its face: a fold), else 0. */
#define Q2N_SCAN_MAX 16
q2n_status q2n_surface_scan(const q2n_surface *s, int k, int n, const double ref[3], int *folded,
                            double *u, double *v);

/* Bézier patches: set / get degree and control points cp[3*(j*(du+1)+i)], i along u. */
q2n_status q2n_surface_set_bezier(q2n_surface *s, int k, int du, int dv, const double *cp);
int q2n_surface_bezier(const q2n_surface *s, int k, int *du, int *dv, const double **cp);

/* Producers of other patch kinds attach an evaluator with its private data (freed by
 * free_data when the surface is freed). */
typedef q2n_status (*q2n_patch_eval_fn)(const void *data, double u, double v, int nder, double *out);
q2n_status q2n_surface_set_patch(q2n_surface *s, int k, q2n_patch_kind kind, void *data,
                                 q2n_patch_eval_fn eval, void (*free_data)(void *));
const void *q2n_surface_patch_data(const q2n_surface *s, int k);
/* Optional fast path for q2n_surface_eval_grid (same output layout). */
typedef q2n_status (*q2n_patch_grid_fn)(const void *data, int nu, const double *us, int nv,
                                        const double *vs, double *out);
q2n_status q2n_surface_set_patch_grid(q2n_surface *s, int k, q2n_patch_grid_fn grid);

/* Mixed corner partials ∂u^a ∂v^b S (a, b = 1, 2) of patch k at its corner (i, j) in {0,1}^2, as
 * the two sides through the corner give them: out[0][a-1][b-1] from the side v = j, out[1][..]
 * from the side u = i.  They agree where the patch is smooth at the corner; they differ at
 * Gregory-type corners (rational blends).  Exact values, from an optional producer hook;
 * Q2N_ERR_UNSUPPORTED when the patch has none (evaluate and difference instead). */
typedef q2n_status (*q2n_patch_corner_fn)(const void *data, int i, int j, double out[2][2][2][3]);
q2n_status q2n_surface_set_patch_corner(q2n_surface *s, int k, q2n_patch_corner_fn fn);
q2n_status q2n_surface_corner_mixed(const q2n_surface *s, int k, int i, int j, double out[2][2][2][3]);

#endif
