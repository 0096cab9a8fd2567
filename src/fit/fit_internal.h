/* fit_internal.h — internals shared by the files of src/fit/ (not a public header): the quintic
 * B-spline basis on arbitrary clamped knot vectors, knot insertion, second-order evaluation of
 * fitted surfaces, the linear least-squares container both solvers (Ceres shim, LAPACK) consume,
 * the parallel loop, and the measurement of a model against its construction. */
#ifndef Q2N_FIT_INTERNAL_H
#define Q2N_FIT_INTERNAL_H

#include "core/error.h"
#include "core/par.h"
#include "fit/bspline.h"
#include "fit/fit.h"
#include "patch/surface.h"

#define Q2N_FIT_DEG 5                 /* every fitted or converted patch is bi-quintic */

/* ---- knot vectors and basis (fit_basis.c) ----
 * A knot vector of degree Q2N_FIT_DEG is clamped on [0,1]: 6 zeros, the interior breakpoints (all
 * simple), 6 ones; nb interior breakpoints give nb + 1 spans and nb + 6 control points. */
void q2n_fit_knots_from_breaks(int nb, const double *br, double *kv);       /* kv: nb + 12 entries */
void q2n_fit_knots_uniform(int m, double *kv);                              /* m spans, i/m */
/* Span index i (Q2N_FIT_DEG <= i <= n-1) with kv[i] <= t < kv[i+1]; n = number of control points. */
static inline int q2n_fit_span(int n, const double *kv, double t) { return q2n_bspline_span(n, Q2N_FIT_DEG, kv, t); }
/* Non-zero basis functions of span i at t and derivatives up to order nder <= 2:
 * ders[r][a] = d^r/dt^r N_{i-5+a}(t) (q2n_bspline_basis). */
static inline void q2n_fit_basis(int i, const double *kv, double t, int nder, double ders[3][Q2N_FIT_DEG + 1])
{
    q2n_bspline_basis(i, Q2N_FIT_DEG, kv, t, nder, ders[0]);
}
/* Parameters of the fit samples (per_span points per span: a + (b - a) j / per_span, then 1) and of the
 * check points between them (the midpoints); returns the count written (nspans * per_span + 1, or
 * nspans * per_span for checks). */
int q2n_fit_sample_params(int n, const double *kv, int per_span, double *out);
int q2n_fit_check_params(int n, const double *kv, int per_span, double *out);
/* Check parameter c of those (the (2 (c % per_span) + 1)-th odd fraction of span c / per_span): the
 * same value q2n_fit_check_params writes there. */
static inline double q2n_fit_check_param(const double *kv, int per_span, int c)
{
    double a = kv[5 + c / per_span], b = kv[6 + c / per_span];
    return a + (b - a) * (2 * (c % per_span) + 1) / (2 * per_span);
}
/* Knot insertion (Boehm; NURBS Book A5.4): the degree-5 curve (n control points of dim doubles
 * each, knots kv) re-expressed on kv2 (n2 control points), which must contain every knot of kv;
 * returns 0, or -1 when kv2 is not a refinement of kv. */
int q2n_fit_curve_refine(int n, const double *kv, const double *cp, int dim, int n2, const double *kv2, double *cp2);
/* Evaluate a polynomial B-spline surface with derivatives up to order nder (0..2) into out[] in
 * the layout of q2n_surface_eval (S, Su, Sv, Suu, Suv, Svv; surface.h). */
void q2n_fit_surface_eval(const q2n_bspline_surface *s, double u, double v, int nder, double *out);
/* Positions on the grid us[0..nu-1] x vs[0..nv-1] (3 per point, u fastest): each basis once per
 * column and row, every point the same sum as q2n_fit_surface_eval's (bit for bit); returns 0, or
 * -1 when out of memory. */
int q2n_fit_surface_grid(const q2n_bspline_surface *s, int nu, const double *us, int nv, const double *vs, double *out);

/* ---- linear least squares (fit_ls.c) ----
 * A stage: independent items, each with its own unknown control points (3-vectors) and rows
 *   sum_j val_j * x[col_j] = rhs (3 components, same coefficients for x, y, z: every fit condition —
 * sample fidelity, gluing relations with scalar gluing functions — acts coordinate-wise).  Items own
 * contiguous ranges of variables and rows. */
typedef struct q2n_fit_ls {
    int nvar, nrow, nent, nitem;
    int cap_row, cap_ent, cap_item;
    int *row_start;   /* nrow+1 */
    int *col;         /* nent: global variable index */
    double *val;      /* nent */
    double *rhs;      /* 3*nrow */
    int *item_var;    /* nitem+1: first variable of each item */
    int *item_row;    /* nitem+1: first row of each item */
    double *x;        /* 3*nvar: the solution */
} q2n_fit_ls;

void q2n_fit_ls_init(q2n_fit_ls *ls);
void q2n_fit_ls_free(q2n_fit_ls *ls);
void q2n_fit_ls_clear(q2n_fit_ls *ls);
q2n_status q2n_fit_ls_item_begin(q2n_fit_ls *ls);      /* closes the previous item */
void q2n_fit_ls_item_end(q2n_fit_ls *ls);              /* closes the last item */
q2n_status q2n_fit_ls_new_var(q2n_fit_ls *ls, int *id);
/* Start a row with right-hand side rhs[3]; entries follow with q2n_fit_ls_entry. */
q2n_status q2n_fit_ls_row(q2n_fit_ls *ls, const double rhs[3]);
q2n_status q2n_fit_ls_entry(q2n_fit_ls *ls, int var, double val);
/* A whole item at once: m rows over n new unknowns, A row-major m x n, b m x 3 (row-major);
 * *var0 gets the first unknown. */
q2n_status q2n_fit_ls_dense_item(q2n_fit_ls *ls, int m, int n, const double *A, const double *b, int *var0);

/* Direct reference solver: LAPACK rank-revealing QR per item (3 right-hand sides). */
q2n_status q2n_fit_ls_solve_direct(q2n_fit_ls *ls, q2n_error *err);
/* Ceres (core/ceres_shim.cpp): dense != 0 one solve per item over `threads` workers (TinySolver up to
 * 16 unknowns, DENSE_QR above), else one SPARSE_NORMAL_CHOLESKY solve of everything. */
q2n_status q2n_fit_ls_solve_ceres(q2n_fit_ls *ls, int threads, int dense, q2n_error *err);
/* With the solver the options name. */
q2n_status q2n_fit_ls_solve(q2n_fit_ls *ls, int solver, int threads, q2n_error *err);

/* ---- measurement (fit_measure.c) ---- */

/* Per-patch and per-edge results of a measurement (arrays may be NULL).  Deviation is measured at
 * the cell centres of each patch's check grid (q2n_fit_check_params in u and v), continuity at the
 * check points of each interior edge's owner side. */
typedef struct q2n_fit_measure_out {
    double *patch_dev;     /* nf: max deviation / diag */
    double *edge_g0;       /* ne: max gap / diag between the two fitted sides */
    double *edge_g1;       /* ne: max normal-angle jump (degrees), fitted */
    double *edge_g2;       /* ne: max relative normal-curvature jump, fitted */
    double *edge_g1_c;     /* ne: the same on the construction (NULL: skip) */
    double *edge_g2_c;
} q2n_fit_measure_out;

/* Normal-angle (degrees) and relative normal-curvature jump between two sides' derivative sets at
 * one edge point (layout of q2n_surface_eval, nder 2); T = tangent along the edge; diag sets the
 * curvature floor 1/diag. */
void q2n_fit_jumps(const double *dL, const double *dR, const double T[3], double diag, double *g1, double *g2);

/* Measure every patch and edge of `model` against s on `threads` workers (results reduced in index
 * order: thread-count independent) into rep's measured fields and mo. */
q2n_status q2n_fit_measure_model(const q2n_nurbs_model *model, const q2n_surface *s, q2n_fit_report *rep,
                                 q2n_fit_measure_out *mo, int threads, q2n_error *err);

/* Smoothness scan of the construction's patch k (explains a failed fit, and stops refinement of
 * patches that no spline can follow): first derivatives on an n x n grid; *ratio = max(|Su|, |Sv|) /
 * its median over the grid, at (*u, *v), *dmax the maximum itself.  A ratio in the hundreds means a
 * feature narrower than any knot spacing the fit may use (a near-pole of the construction). */
q2n_status q2n_fit_scan_construction(const q2n_surface *s, int k, int n, double *ratio, double *u, double *v,
                                     double *dmax);

/* Control points per face (min, median, max) and spans per patch of a model into rep. */
void q2n_fit_report_sizes(const q2n_nurbs_model *md, q2n_fit_report *rep);

/* The rim into rep (rim_vertices, rim_max_deg, rim_curv_rel and the construction's): at every boundary
 * vertex where boundary edges of two faces meet, the angle between the one face's boundary tangent and
 * the other's, and the jump of the boundary curves' curvature vector, on the fitted model (polynomial
 * patches) and on the construction s (NULL: not measured). */
void q2n_fit_report_rim(const q2n_nurbs_model *md, const q2n_surface *s, q2n_fit_report *rep);

/* ---- exact conversion (fit_bezier.c) ---- */
/* Every patch of s is Bézier: elevate each to 5 x 5 (exact), unify shared boundaries, measure. */
q2n_status q2n_fit_convert_bezier(const q2n_surface *s, const q2n_mesh *m, const q2n_fit_options *o,
                                  q2n_nurbs_model **out, q2n_fit_report *rep, q2n_error *err);

#endif
