/* sparse.c — sparse SPD solves through CHOLMOD's supernodal Cholesky (sparse.h). */
#include "core/sparse.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <suitesparse/cholmod.h>

#include "core/dense.h"

/* CHOLMOD's supernodal factorisation hands its own arrays to the BLAS, whose results may depend on
 * their alignment (core/dense.h, "Alignment"), and malloc's alignment depends on the heap's
 * history.  SuiteSparse takes its allocator from SuiteSparse_config: malloc and calloc are
 * replaced, once, by aligned ones whose blocks realloc and free accept as they are, so blocks
 * allocated before the switch (or by another user of SuiteSparse in the process) stay valid. */
static void *aligned_calloc(size_t n, size_t size)
{
    if (size && n > (size_t)-1 / size) return NULL;
    void *p = q2n_aligned_alloc(n * size);
    if (p) memset(p, 0, n * size);
    return p;
}

static pthread_once_t alloc_once = PTHREAD_ONCE_INIT;
static void use_aligned_alloc(void)
{
    SuiteSparse_config.malloc_func = q2n_aligned_alloc;
    SuiteSparse_config.calloc_func = aligned_calloc;
}

void q2n_sparse_init(void)
{
    pthread_once(&alloc_once, use_aligned_alloc);
}

q2n_status q2n_sparse_spd_solve(int n, long nnz, const int *ti, const int *tj, const double *tv, int nrhs,
                                const double *B, double *X, q2n_error *err)
{
    if (n <= 0 || nrhs <= 0) return Q2N_OK;
    q2n_sparse_init();
    cholmod_common c;
    cholmod_start(&c);
    c.print = 0;
    c.error_handler = NULL;
    q2n_status st = Q2N_OK;
    cholmod_triplet *T = cholmod_allocate_triplet((size_t)n, (size_t)n, (size_t)nnz, 1 /* upper */, CHOLMOD_REAL, &c);
    cholmod_sparse *A = NULL;
    cholmod_factor *L = NULL;
    cholmod_dense *b = NULL, *x = NULL;
    if (!T) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse matrix, %d unknowns)", n); goto done; }
    int *Ti = T->i, *Tj = T->j;
    double *Tx = T->x;
    for (long k = 0; k < nnz; k++) {
        Ti[k] = ti[k];
        Tj[k] = tj[k];
        Tx[k] = tv[k];
    }
    T->nnz = (size_t)nnz;
    A = cholmod_triplet_to_sparse(T, (size_t)nnz, &c);
    if (!A) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse matrix, %d unknowns)", n); goto done; }
    L = cholmod_analyze(A, &c);
    if (!L || !cholmod_factorize(A, L, &c)) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "sparse factorisation failed (%d unknowns)", n);
        goto done;
    }
    if (c.status == CHOLMOD_NOT_POSDEF) {
        st = q2n_error_set(err, Q2N_ERR_GEOMETRY, "sparse system not positive definite at column %d of %d",
                           (int)L->minor, n);
        goto done;
    }
    b = cholmod_allocate_dense((size_t)n, (size_t)nrhs, (size_t)n, CHOLMOD_REAL, &c);
    if (!b) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse solve)"); goto done; }
    memcpy(b->x, B, sizeof(double) * (size_t)n * (size_t)nrhs);
    x = cholmod_solve(CHOLMOD_A, L, b, &c);
    if (!x) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "sparse solve failed (%d unknowns)", n); goto done; }
    memcpy(X, x->x, sizeof(double) * (size_t)n * (size_t)nrhs);
done:
    cholmod_free_dense(&x, &c);
    cholmod_free_dense(&b, &c);
    cholmod_free_factor(&L, &c);
    cholmod_free_sparse(&A, &c);
    cholmod_free_triplet(&T, &c);
    cholmod_finish(&c);
    return st;
}
