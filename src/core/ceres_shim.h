/* ceres_shim.h — the C interface of ceres_shim.cpp, the thin C++ layer over Ceres' Solver API
 * (the Ceres C API hard-codes solver options and prints reports; toolchain.md). */
#ifndef Q2N_CORE_CERES_SHIM_H
#define Q2N_CORE_CERES_SHIM_H

#ifdef __cplusplus
extern "C" {
#endif

/* Solve the sparse linear least-squares problem  min sum_r | sum_e val_e x[col_e] - rhs_r |^2 over
 * 3-vectors x[0..nvar-1] (row r has entries row_start[r] .. row_start[r+1]-1; same coefficients
 * for x, y, z).  dense == 0: one SPARSE_NORMAL_CHOLESKY solve of everything; dense != 0: one
 * solve per independent block (Ceres' TinySolver up to 16 unknowns, ceres::Solve with DENSE_QR
 * above) of rows item_row[i] .. item_row[i+1]-1 whose unknowns
 * are item_var[i] .. item_var[i+1]-1 (nitem blocks; block i on worker i mod threads, so the
 * result does not depend on threads).  A block's rows should use only its own unknowns, each at
 * least once: it is then one dense Ceres residual block (the fast path), else one residual
 * block per row.  x holds the start
 * point on entry (any; the problem is linear) and the solution on return.  Returns 0 on success,
 * else 1 with a message. */
int q2n_ceres_linear_ls(int nvar, int nrow, const int *row_start, const int *col, const double *val,
                        const double *rhs, double *x, int threads, int dense, int nitem, const int *item_row,
                        const int *item_var, char *msg, int msglen);

#ifdef __cplusplus
}
#endif

#endif
