/* fit_internal.h — internals shared by the files of src/fit/ (not a public header): the uniform
 * clamped quintic B-spline basis with derivatives, second-order evaluation of fitted surfaces, and
 * the linear least-squares "stage" structure that both solvers (Ceres shim, direct Householder QR)
 * consume. */
#ifndef Q2N_FIT_INTERNAL_H
#define Q2N_FIT_INTERNAL_H

#include "core/error.h"
#include "fit/bspline.h"

#define FIT_DEG 5                 /* every fitted or converted patch is bi-quintic */
#define FIT_MAX_SPANS 256

/* Clamped uniform knot vector of degree FIT_DEG with m spans: kv[0..m+2*FIT_DEG] (m + 11 knots). */
void fit_knots_uniform(int m, double *kv);
/* Span index i (FIT_DEG <= i <= n-1) with kv[i] <= t < kv[i+1]; n = number of control points. */
int fit_span(int n, const double *kv, double t);
/* Non-zero basis functions of span i at t and their derivatives up to order nder <= 2:
 * ders[r][a] = d^r/dt^r N_{i-FIT_DEG+a}(t) (NURBS Book A2.3). */
void fit_basis(int i, const double *kv, double t, int nder, double ders[3][FIT_DEG + 1]);
/* Evaluate a polynomial B-spline surface with derivatives up to order nder (0..2) into out[] in
 * the layout of q2n_surface_eval (S, Su, Sv, Suu, Suv, Svv; surface.h). */
void fit_surface_eval(const q2n_bspline_surface *s, double u, double v, int nder, double *out);

/* A linear least-squares stage: independent items, each with its own unknown control points
 * (3-vectors) and rows  sum_j val_j * x[col_j] = rhs (3 components, same coefficients for x, y, z:
 * every fit condition here — sample fidelity and the G1/G2 gluing relations with scalar gluing
 * functions — acts coordinate-wise).  Items own contiguous ranges of variables and rows. */
typedef struct fit_ls {
    int nvar, nrow, nent, nitem;
    int cap_row, cap_ent, cap_item;
    int *row_start;   /* nrow+1 */
    int *col;         /* nent: global variable index */
    double *val;      /* nent */
    double *rhs;      /* 3*nrow */
    int *item_var;    /* nitem+1: first variable of each item */
    int *item_row;    /* nitem+1: first row of each item */
    double *x;        /* 3*nvar: the solution */
} fit_ls;

void fit_ls_init(fit_ls *ls);
void fit_ls_free(fit_ls *ls);
void fit_ls_clear(fit_ls *ls);
q2n_status fit_ls_item_begin(fit_ls *ls);          /* closes the previous item */
void fit_ls_item_end(fit_ls *ls);                  /* closes the last item */
q2n_status fit_ls_new_var(fit_ls *ls, int *id);
/* Start a row with right-hand side rhs[3]; entries follow with fit_ls_entry. */
q2n_status fit_ls_row(fit_ls *ls, const double rhs[3]);
q2n_status fit_ls_entry(fit_ls *ls, int var, double val);

/* Direct reference solver: Householder QR per item (3 right-hand sides). */
q2n_status fit_ls_solve_direct(fit_ls *ls, q2n_error *err);
/* Ceres solver (ceres_shim.cpp). */
q2n_status fit_ls_solve_ceres(fit_ls *ls, int threads, int dense, q2n_error *err);

#endif

/* ---- shared by fit.c and fit_report.c ---- */
#include "fit/fit.h"

/* Fit samples per direction for a span count m: t_k = k/(N-1), k = 0..N-1; deviation and
 * continuity are checked at the midpoints (k+1/2)/(N-1), which are never fit samples. */
static inline int fit_nsamples(int m) { return 4 * m + 4; }

/* Per-patch and per-edge results of a measurement (arrays may be NULL). */
typedef struct fit_measure_out {
    double *patch_dev;     /* nf: max deviation / diag */
    double *patch_dir;     /* 2*nf: share of the u- and v-direction in the error estimate (sum 1) */
    double *edge_g1;       /* ne: max normal-angle jump (degrees), fitted */
    double *edge_g2;       /* ne: max relative normal-curvature jump, fitted */
    double *edge_g1_c;     /* ne: the same on the construction (NULL: skip) */
    double *edge_g2_c;
} fit_measure_out;

/* threads: workers over patches and edges (results reduced in index order: thread-count
 * independent).  The construction's evaluators must be safe to call concurrently (they are pure
 * functions of const data in this project). */
q2n_status fit_measure_model(const q2n_nurbs_model *model, const q2n_surface *s, q2n_fit_report *rep,
                             fit_measure_out *mo, int threads, q2n_error *err);
double fit_now(void);   /* monotonic seconds */

/* Smoothness scan of the construction's patch k (explains a failed fit, and stops refinement of
 * patches that no spline can follow): first derivatives on an n x n grid (FIT_SCAN_N for the
 * final message, FIT_SCAN_N_QUICK during refinement); *ratio = max(|Su|, |Sv|) / its median over the grid, at
 * (*u, *v), *dmax the maximum itself.  A ratio in the hundreds means a feature narrower than any
 * knot spacing the fit may use (a near-pole of the construction), not slow convergence. */
#define FIT_SCAN_N 513
#define FIT_SCAN_N_QUICK 257
q2n_status fit_scan_construction(const q2n_surface *s, int k, int n, double *ratio, double *u, double *v,
                                 double *dmax);

/* Run fn(arg, i) for i = 0..n-1 on `threads` workers (item i on worker i mod threads, so the
 * assignment does not depend on timing); falls back to the calling thread when a thread cannot be
 * started.  fn must only write data owned by item i. */
void fit_par_for(int n, int threads, void (*fn)(void *arg, int i), void *arg);
