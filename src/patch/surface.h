/* surface.h — the composite surface: one patch per mesh face (pipeline stage 3), and the one
 * home of the face parametrization that every stage after it uses.
 *
 * Contract: patch k is built on mesh face k; its domain is [0,1]^2 with u along the face's
 * first edge (v0 -> v1) and v along v0 -> v3.  Every surface construction (augmented
 * interpolatory patches, Coons–Gregory patches at extraordinary vertices, the Catmull–Clark
 * ACC path in src/acc/) fills this container; fitting and export read it through
 * q2n_surface_eval() and, for polynomial patches, q2n_surface_bezier().
 *
 * The face parametrization (as Bfr::Parameterization is OpenSubdiv's).  Corner c is the face's
 * c-th vertex, side i its i-th half-edge, from corner i to corner i+1 (counter-clockwise seen
 * from the side the face's normal points to):
 *
 *     3 ------ 2        corner  (u,v)   side  on     along (corner i -> i+1)  inward  iota  level
 *     |        |          0     (0,0)    0    v = 0  +u                        +v      +1    0
 *     |        |          1     (1,0)    1    u = 1  +v                        -u      -1    1
 *     0 ------ 1          2     (1,1)    2    v = 1  -u                        -v      -1    1
 *    v ^                  3     (0,1)    3    u = 0  -v                        +u      +1    0
 *      +-> u
 *
 * Side frame of side i (q2n_side_uv): t along the half-edge (0 at corner i, 1 at corner i+1), s
 * inward (0 on the side):  (u, v) = corner_i + t along_i + s inward_i,  so by the chain rule
 *     ∂t = a_u ∂u + a_v ∂v,   ∂s = n_u ∂u + n_v ∂v          (a = along_i, n = inward_i)
 *     ∂tt = a_u² ∂uu + 2 a_u a_v ∂uv + a_v² ∂vv,  ∂ts = a_u n_u ∂uu + (a_u n_v + a_v n_u) ∂uv
 *           + a_v n_v ∂vv,  ∂ss likewise  (q2n_side_derivs).
 * Since along and inward are axis directions, one of a_u, a_v is 0: ∂t is ±∂u on sides 0 and 2
 * (q2n_side_along_u) and ±∂v on sides 1 and 3.
 * The Coons patches (coons_patch.h) and the augmented patches' sides use the patch coordinate
 * instead of t: the side parameter is u on sides 0, 2 and v on sides 1, 3 (increasing, so it is t
 * on sides 0, 1 and 1 - t on sides 2, 3), the cross coordinate is the other one, it equals
 * `level` on the side, and iota is the sign of the inward direction on it.  The along directions
 * are also (1, 0) turned by i quarter turns: the directions of the four edges at a regular vertex
 * in a chart whose first edge runs along +x (src/patch/ev_derivatives.c). */
#ifndef Q2N_PATCH_SURFACE_H
#define Q2N_PATCH_SURFACE_H

#include "core/error.h"

/* ---- the face parametrization (table above) ---- */
extern const int q2n_corner_uv[4][2];    /* (u, v) of corner c */
extern const int q2n_side_along[4][2];   /* direction of side i in (u, v): corner i+1 - corner i */
extern const int q2n_side_inward[4][2];  /* direction into the patch from side i: corner i+3 - corner i */
extern const int q2n_side_iota[4];       /* sign of the inward direction on the cross coordinate */
extern const int q2n_side_level[4];      /* value of the cross coordinate on side i */

/* Side i runs along u (sides 0, 2), else along v. */
static inline int q2n_side_along_u(int i) { return !(i & 1); }
/* The patch-coordinate parameter of side i (u on sides 0, 2, v on 1, 3) runs along the side's
 * half-edge on sides 0, 1 and against it on sides 2, 3: from corner q2n_side_first(i) to corner
 * q2n_side_last(i). */
static inline int q2n_side_forward(int i) { return i < 2; }
static inline int q2n_side_first(int i) { return q2n_side_forward(i) ? i : (i + 1) & 3; }
static inline int q2n_side_last(int i) { return q2n_side_forward(i) ? (i + 1) & 3 : i; }
/* Corner at (u, v) = (i, j), i, j in {0, 1}. */
static inline int q2n_corner_at(int i, int j) { return j ? 3 - i : i; }
/* (u, v) of the point t along side i (from corner i) and s into the patch. */
void q2n_side_uv(int i, double t, double s, double *u, double *v);
/* Derivatives in side i's frame from (u, v) ones: e in q2n_surface_eval's layout (nder 0..2),
 * D[0] = S, D[1] = ∂t S, D[2] = ∂s S, D[3] = ∂tt S, D[4] = ∂ts S, D[5] = ∂ss S (up to nder). */
void q2n_side_derivs(int i, int nder, const double *e, double D[6][3]);

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
/* Slot o of that layout (o = Q2N_EV_x / 3), extended by the third orders some producers use
 * (Suuu, Suuv, Suvv, Svvv: slots 6..9), holds ∂u^a ∂v^b S with (a, b) = q2n_eval_order[o]. */
extern const int q2n_eval_order[10][2];

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

/* Foot point of P on patch k: Gauss–Newton on |S(u, v) - P|^2 from (*u, *v), the parameters
 * clamped to [0,1]^2, at most maxit steps; it stops early when the normal equations are singular,
 * an evaluation fails, or a step moves (u, v) by less than rounding.  Returns the smallest
 * distance |S - P| met (INFINITY if none was evaluated); *u, *v get the last iterate. */
double q2n_surface_project(const q2n_surface *s, int k, const double P[3], int maxit, double *u, double *v);

/* Evaluate patch k on the tensor grid us[0..nu-1] x vs[0..nv-1] with first derivatives:
 * out has 9 doubles (S, Su, Sv) per point, u fastest.  Shares per-row work, so it is the
 * fast path for tessellation, sampling and fitting.  Q2N_ERR_NUMERIC when a value is not
 * finite (then q2n_surface_first_nonfinite finds the point). */
q2n_status q2n_surface_eval_grid(const q2n_surface *s, int k, int nu, const double *us, int nv,
                                 const double *vs, double *out);

/* The same grid, positions only: out has 3 doubles per point (the fit's samples and check points
 * need no derivatives; a patch with a positions-only fast path skips them, any other gets its
 * grid evaluation's positions).  Q2N_ERR_NUMERIC as above. */
q2n_status q2n_surface_eval_grid_pos(const q2n_surface *s, int k, int nu, const double *us, int nv,
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

/* Map the whole surface by the linear map L, after its producers are done: every evaluation (values
 * and derivatives, grids, corner partials) comes out as L times the producer's, and Bézier control
 * points are mapped in place (exact).  Maps compose.  Affine maps keep G1 and G2 across edges,
 * interpolation, and the sign of a fold (det L > 0). */
void q2n_surface_map_linear(q2n_surface *s, const double L[3][3]);

/* Bézier patches: set / get degree and control points cp[3*(j*(du+1)+i)], i along u. */
q2n_status q2n_surface_set_bezier(q2n_surface *s, int k, int du, int dv, const double *cp);
int q2n_surface_bezier(const q2n_surface *s, int k, int *du, int *dv, const double **cp);

/* Producers of other patch kinds attach an evaluator with its private data (freed by
 * free_data when the surface is freed). */
typedef q2n_status (*q2n_patch_eval_fn)(const void *data, double u, double v, int nder, double *out);
q2n_status q2n_surface_set_patch(q2n_surface *s, int k, q2n_patch_kind kind, void *data,
                                 q2n_patch_eval_fn eval, void (*free_data)(void *));
const void *q2n_surface_patch_data(const q2n_surface *s, int k);
/* The same data for its producer to change in place (q2n_augmented_map_points). */
void *q2n_surface_patch_data_mut(q2n_surface *s, int k);
/* Optional fast path for q2n_surface_eval_grid (same output layout). */
typedef q2n_status (*q2n_patch_grid_fn)(const void *data, int nu, const double *us, int nv,
                                        const double *vs, double *out);
q2n_status q2n_surface_set_patch_grid(q2n_surface *s, int k, q2n_patch_grid_fn grid);
/* Optional fast path for q2n_surface_eval_grid_pos (3 doubles per point). */
q2n_status q2n_surface_set_patch_grid_pos(q2n_surface *s, int k, q2n_patch_grid_fn grid_pos);

/* Mixed corner partials ∂u^a ∂v^b S (a, b = 1, 2) of patch k at its corner (i, j) in {0,1}^2, as
 * the two sides through the corner give them: out[0][a-1][b-1] from the side v = j, out[1][..]
 * from the side u = i.  They agree where the patch is smooth at the corner; they differ at
 * Gregory-type corners (rational blends).  Exact values, from an optional producer hook;
 * Q2N_ERR_UNSUPPORTED when the patch has none (evaluate and difference instead). */
typedef q2n_status (*q2n_patch_corner_fn)(const void *data, int i, int j, double out[2][2][2][3]);
q2n_status q2n_surface_set_patch_corner(q2n_surface *s, int k, q2n_patch_corner_fn fn);
q2n_status q2n_surface_corner_mixed(const q2n_surface *s, int k, int i, int j, double out[2][2][2][3]);

#endif
