/* dense.h — the project's one home for dense linear algebra: small least-squares, constraint,
 * square, symmetric positive definite and tridiagonal problems solved by LAPACK (Debian
 * liblapack-dev; the Fortran routines dgelsy_, dgesvd_, dgesv_, dpotrf_, dpotrs_, dptsv_ called
 * from C).  Matrices are column-major (Fortran order) with a leading dimension, as LAPACK takes
 * them.  Functions return 0 on success, a negative value for a bad argument and a positive value
 * when out of memory or when LAPACK reports a failure.
 *
 * Alignment.  Every array handed to LAPACK or BLAS starts on a Q2N_DENSE_ALIGN-byte boundary (the
 * routines below stage their arguments; callers of BLAS use q2n_dense_alloc), because the BLAS
 * may take alignment-dependent paths: ATLAS (Debian's libblas/liblapack where installed) returns
 * two different last bits from dgesvd of one 12 x 1 matrix depending on whether the matrix starts
 * at 0 mod 32 or at 16.  malloc only promises 16 bytes, and where an allocation lands depends on
 * the heap's history, which worker threads make timing-dependent: a large mesh gave different
 * output bytes from run to run until every LAPACK array was aligned (docs/fit.md, "Determinism").
 * tests/test_dense.c checks it. */
#ifndef Q2N_CORE_DENSE_H
#define Q2N_CORE_DENSE_H

#include <stddef.h>

#define Q2N_DENSE_ALIGN 64

/* bytes (n doubles) on a Q2N_DENSE_ALIGN boundary (free with free()); NULL when out of memory. */
void *q2n_aligned_alloc(size_t bytes);
double *q2n_dense_alloc(size_t n);

/* min ||A X - B|| (Frobenius) for A m x n and B m x nrhs, by a rank-revealing complete orthogonal
 * factorisation (LAPACK dgelsy: QR with column pivoting; Golub & Van Loan, Matrix Computations
 * §5.4.1).  Columns whose pivot falls below rcond times the largest are treated as dependent;
 * *rank (may be NULL) gets the numerical rank.  A is overwritten; B (ldb >= max(m, n)) holds X in
 * its first n rows on return.  When rank < n, X is the minimum-norm solution. */
int q2n_dense_lstsq(int m, int n, int nrhs, double *A, int lda, double *B, int ldb, double rcond, int *rank);

/* Equality constraints C X = D (C c x n, D c x nrhs) in null-space form (Golub & Van Loan §12.1.4,
 * LSE by elimination): every solution is X = Xp + Z Y with Z an orthonormal basis (n x k, column-
 * major, ldz = n) of the null space of C and Xp (n x nrhs, ldx = n) the minimum-norm least-squares
 * solution of C X = D, from the SVD of C (LAPACK dgesvd).  Singular values below rcond times the
 * largest count as zero (the rows of C may be dependent; consistent dependent rows are harmless).
 * *k gets the null-space dimension, *resid (may be NULL) max |C Xp - D| (0 for consistent
 * constraints up to rounding).  C and D are not modified.  Z needs room for n x n doubles. */
int q2n_dense_nullspace(int c, int n, const double *C, int ldc, int nrhs, const double *D, int ldd, double rcond,
                        double *Z, int *k, double *Xp, double *resid);

/* A X = B for a square A (n x n), by LU factorisation with partial pivoting (LAPACK dgesv;
 * Golub & Van Loan §3.4).  A is overwritten by its factors, B (ldb >= n, nrhs columns) by X.
 * Returns 0, 1 when A is exactly singular (a zero pivot) or out of memory, -1 for a bad argument. */
int q2n_dense_solve(int n, int nrhs, double *A, int lda, double *B, int ldb);

/* Cholesky factorisation A = L L^T of a symmetric positive definite n x n matrix (LAPACK dpotrf;
 * Golub & Van Loan §4.2): the lower triangle is read and overwritten by L.  Returns 0, 1 when A
 * is not positive definite, -1 for a bad argument. */
int q2n_dense_cholesky(int n, double *A, int lda);
/* X = A^-1 B from the factor L of q2n_dense_cholesky (LAPACK dpotrs); B (ldb >= n) becomes X. */
int q2n_dense_cholesky_solve(int n, int nrhs, const double *L, int lda, double *B, int ldb);

/* A X = B for a symmetric positive definite tridiagonal A: diagonal d[0..n-1], off-diagonal
 * e[0..n-2] (LAPACK dptsv: L D L^T; Golub & Van Loan §4.3.6); d and e are overwritten, B (ldb >=
 * n) becomes X.  Returns 0, 1 when A is not positive definite, -1 for a bad argument. */
int q2n_dense_tridiag_spd(int n, int nrhs, double *d, double *e, double *B, int ldb);

/* R = A B for A m x p, B p x n (column-major, leading dimensions lda, ldb, ldr). */
void q2n_dense_mul(int m, int p, int n, const double *A, int lda, const double *B, int ldb, double *R, int ldr);

#endif
