/* sparse.h — sparse symmetric positive definite solves (CHOLMOD, Debian libsuitesparse-dev).
 *
 * The matrix is given as triplets of its upper or lower triangle (or both: duplicates add up,
 * so callers may scatter per-element contributions without merging them first). */
#ifndef Q2N_CORE_SPARSE_H
#define Q2N_CORE_SPARSE_H

#include "core/error.h"

/* Point SuiteSparse's allocator at 64-byte aligned blocks (once; q2n_sparse_spd_solve does it
 * itself): callers that reach CHOLMOD through another library (Ceres' sparse solver) call it first,
 * so that CHOLMOD's BLAS calls see the same alignment in every run (core/dense.h, "Alignment"). */
void q2n_sparse_init(void);

/* Solve A X = B for nrhs right-hand sides: A is n x n symmetric positive definite, given by nnz
 * triplets (ti[k], tj[k], tv[k]) with ti[k] <= tj[k] (upper triangle; entries with the same
 * (i, j) are summed); B and X are column-major n x nrhs (X may alias B).  Q2N_ERR_GEOMETRY when A
 * is not positive definite (the message names the column where the factorisation stopped). */
q2n_status q2n_sparse_spd_solve(int n, long nnz, const int *ti, const int *tj, const double *tv, int nrhs,
                                const double *B, double *X, q2n_error *err);

/* A symmetric positive definite matrix of fixed pattern, analysed once (fill-reducing ordering,
 * symbolic factorisation) and factorised for each set of values: callers that solve several
 * systems of one pattern (the fair construction's two passes) pay the analysis once and need no
 * triplets.  The pattern is the upper triangle in compressed columns: column j holds rows
 * rowind[colptr[j] .. colptr[j+1] - 1], ascending, each <= j, the diagonal present. */
typedef struct q2n_sparse_spd q2n_sparse_spd;
q2n_status q2n_sparse_spd_create(int n, const int *colptr, const int *rowind, q2n_sparse_spd **out, q2n_error *err);
/* The pattern's values, in its order (colptr[n] of them), to be filled before each solve. */
double *q2n_sparse_spd_values(q2n_sparse_spd *S);
/* The pattern as the object holds it (the caller's copy may be freed after create). */
void q2n_sparse_spd_pattern(const q2n_sparse_spd *S, const int **colptr, const int **rowind);
/* Factorise the current values and solve A X = B (as q2n_sparse_spd_solve; the same bits as it
 * gives for the same matrix entered as triplets in one per pattern entry). */
q2n_status q2n_sparse_spd_factor_solve(q2n_sparse_spd *S, int nrhs, const double *B, double *X, q2n_error *err);
/* The same object made from triplets (as q2n_sparse_spd_solve takes them), values included. */
q2n_status q2n_sparse_spd_from_triplets(int n, long nnz, const int *ti, const int *tj, const double *tv, q2n_sparse_spd **out,
                                        q2n_error *err);
/* Solve A X = B again with the factor of the last q2n_sparse_spd_factor_solve (iterative refinement:
 * one factorisation for every right-hand side that depends on the previous solution). */
q2n_status q2n_sparse_spd_resolve(q2n_sparse_spd *S, int nrhs, const double *B, double *X, q2n_error *err);
void q2n_sparse_spd_free(q2n_sparse_spd *S);

#endif
