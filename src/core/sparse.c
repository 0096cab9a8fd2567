/* sparse.c — sparse SPD solves through CHOLMOD's supernodal Cholesky (sparse.h). */
#include "core/sparse.h"

#include <dlfcn.h>
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

/* CHOLMOD's supernodal factorisation runs some of its loops as OpenMP teams of a size fixed when it
 * was built (CHOLMOD_OMP_NUM_THREADS, 4 in Debian's build), whatever the machine has: on 2 cores the
 * team outnumbers them and its wake-ups cost more than the loops save (a quarter of a construction's
 * time on a 732-face model: docs/extraordinary.md, "The solve").  OpenMP's dynamic adjustment lets
 * the runtime trim a team to the cores that are free; those loops' iterations are independent, so
 * the factor does not depend on the team (the same bytes with teams of 1, 2 and 4).  It is set for
 * the factorising thread only and restored after; the two OpenMP calls are looked up at run time,
 * since a CHOLMOD built without OpenMP brings no OpenMP runtime. */
typedef struct omp_calls {
    int (*get_dynamic)(void);
    void (*set_dynamic)(int);
} omp_calls;
static omp_calls omp;
static pthread_once_t omp_once = PTHREAD_ONCE_INIT;
static void omp_lookup(void)
{
    void *self = dlopen(NULL, RTLD_LAZY);
    if (!self) return;
    /* object to function pointer: POSIX dlsym's documented use */
    *(void **)&omp.get_dynamic = dlsym(self, "omp_get_dynamic");
    *(void **)&omp.set_dynamic = dlsym(self, "omp_set_dynamic");
    if (!omp.get_dynamic || !omp.set_dynamic) omp.get_dynamic = NULL, omp.set_dynamic = NULL;
    dlclose(self);
}

/* Turn dynamic team sizes on for this thread; returns what to restore (-1: nothing). */
static int omp_trim_begin(void)
{
    pthread_once(&omp_once, omp_lookup);
    if (!omp.set_dynamic) return -1;
    int was = omp.get_dynamic();
    omp.set_dynamic(1);
    return was;
}

static void omp_trim_end(int was)
{
    if (was >= 0) omp.set_dynamic(was);
}

/* Column of the first pivot that is not positive, or -1.  The supernodal factorisation (large
 * systems) is LL' and stops there (status CHOLMOD_NOT_POSDEF); the simplicial one CHOLMOD picks for
 * small sparse systems is LDL', which runs through an indefinite matrix without complaint, so its
 * D (the first entry of each column of L) is read. */
static long first_bad_pivot(const cholmod_factor *L, const cholmod_common *c)
{
    if (c->status == CHOLMOD_NOT_POSDEF) return (long)L->minor;
    if (L->is_super || L->is_ll) return -1;
    const int *Lp = L->p;
    const double *Lx = L->x;
    for (size_t j = 0; j < L->n; j++)
        if (!(Lx[Lp[j]] > 0)) return (long)j;
    return -1;
}

/* A X = B with the factor L. */
static q2n_status solve_with(cholmod_common *c, cholmod_factor *L, int n, int nrhs, const double *B, double *X, q2n_error *err)
{
    cholmod_dense *b = cholmod_allocate_dense((size_t)n, (size_t)nrhs, (size_t)n, CHOLMOD_REAL, c), *x = NULL;
    if (!b) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse solve)");
    q2n_status st = Q2N_OK;
    memcpy(b->x, B, sizeof(double) * (size_t)n * (size_t)nrhs);
    if (!(x = cholmod_solve(CHOLMOD_A, L, b, c)))
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "sparse solve failed (%d unknowns)", n);
    else
        memcpy(X, x->x, sizeof(double) * (size_t)n * (size_t)nrhs);
    cholmod_free_dense(&x, c);
    cholmod_free_dense(&b, c);
    return st;
}

/* Factorise A into L (analysed), refuse an indefinite matrix, solve A X = B (B, X column-major
 * n x nrhs; X may alias B): the part both entry points share. */
static q2n_status factor_solve(cholmod_common *c, cholmod_sparse *A, cholmod_factor *L, int n, int nrhs, const double *B,
                               double *X, q2n_error *err)
{
    int was = omp_trim_begin();
    int ok = cholmod_factorize(A, L, c);
    omp_trim_end(was);
    if (!ok) return q2n_error_set(err, Q2N_ERR_NOMEM, "sparse factorisation failed (%d unknowns)", n);
    long bad = first_bad_pivot(L, c);
    if (bad >= 0) return q2n_error_set(err, Q2N_ERR_GEOMETRY, "sparse system not positive definite at column %ld of %d", bad, n);
    return solve_with(c, L, n, nrhs, B, X, err);
}

struct q2n_sparse_spd {
    cholmod_common c;
    cholmod_sparse *A;
    cholmod_factor *L;
    int n;
};

/* An empty object of n unknowns, its CHOLMOD workspace started (NULL: out of memory). */
static q2n_sparse_spd *spd_new(int n)
{
    q2n_sparse_init();
    q2n_sparse_spd *S = calloc(1, sizeof *S);
    if (!S) return NULL;
    cholmod_start(&S->c);
    S->c.print = 0;
    S->c.error_handler = NULL;
    S->n = n;
    return S;
}

q2n_status q2n_sparse_spd_create(int n, const int *colptr, const int *rowind, q2n_sparse_spd **out, q2n_error *err)
{
    *out = NULL;
    q2n_sparse_spd *S = spd_new(n);
    if (!S) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse matrix, %d unknowns)", n);
    size_t nnz = (size_t)colptr[n];
    S->A = cholmod_allocate_sparse((size_t)n, (size_t)n, nnz, 1 /* sorted */, 1 /* packed */, 1 /* upper */, CHOLMOD_REAL,
                                   &S->c);
    if (!S->A) {
        q2n_sparse_spd_free(S);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse matrix, %d unknowns)", n);
    }
    memcpy(S->A->p, colptr, sizeof(int) * ((size_t)n + 1));
    memcpy(S->A->i, rowind, sizeof(int) * nnz);
    memset(S->A->x, 0, sizeof(double) * nnz);
    *out = S;
    return Q2N_OK;
}

double *q2n_sparse_spd_values(q2n_sparse_spd *S) { return S->A->x; }

void q2n_sparse_spd_pattern(const q2n_sparse_spd *S, const int **colptr, const int **rowind)
{
    *colptr = S->A->p;
    *rowind = S->A->i;
}

q2n_status q2n_sparse_spd_factor_solve(q2n_sparse_spd *S, int nrhs, const double *B, double *X, q2n_error *err)
{
    if (S->n <= 0 || nrhs <= 0) return Q2N_OK;
    if (!S->L && !(S->L = cholmod_analyze(S->A, &S->c)))
        return q2n_error_set(err, Q2N_ERR_NOMEM, "sparse factorisation failed (%d unknowns)", S->n);
    return factor_solve(&S->c, S->A, S->L, S->n, nrhs, B, X, err);
}

q2n_status q2n_sparse_spd_from_triplets(int n, long nnz, const int *ti, const int *tj, const double *tv, q2n_sparse_spd **out,
                                        q2n_error *err)
{
    *out = NULL;
    q2n_sparse_spd *S = spd_new(n);
    if (!S) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse matrix, %d unknowns)", n);
    cholmod_triplet *T = cholmod_allocate_triplet((size_t)n, (size_t)n, (size_t)nnz, 1 /* upper */, CHOLMOD_REAL, &S->c);
    if (T) {
        int *Ti = T->i, *Tj = T->j;
        double *Tx = T->x;
        for (long k = 0; k < nnz; k++) Ti[k] = ti[k], Tj[k] = tj[k], Tx[k] = tv[k];
        T->nnz = (size_t)nnz;
        S->A = cholmod_triplet_to_sparse(T, (size_t)nnz, &S->c);
        cholmod_free_triplet(&T, &S->c);
    }
    if (!S->A) {
        q2n_sparse_spd_free(S);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (sparse matrix, %d unknowns)", n);
    }
    *out = S;
    return Q2N_OK;
}

q2n_status q2n_sparse_spd_solve(int n, long nnz, const int *ti, const int *tj, const double *tv, int nrhs,
                                const double *B, double *X, q2n_error *err)
{
    if (n <= 0 || nrhs <= 0) return Q2N_OK;
    q2n_sparse_spd *S = NULL;
    q2n_status st = q2n_sparse_spd_from_triplets(n, nnz, ti, tj, tv, &S, err);
    if (!st) st = q2n_sparse_spd_factor_solve(S, nrhs, B, X, err);
    q2n_sparse_spd_free(S);
    return st;
}

q2n_status q2n_sparse_spd_resolve(q2n_sparse_spd *S, int nrhs, const double *B, double *X, q2n_error *err)
{
    if (S->n <= 0 || nrhs <= 0) return Q2N_OK;
    if (!S->L) return q2n_error_set(err, Q2N_ERR_ARG, "sparse solve before the factorisation");
    return solve_with(&S->c, S->L, S->n, nrhs, B, X, err);
}

void q2n_sparse_spd_free(q2n_sparse_spd *S)
{
    if (!S) return;
    cholmod_free_factor(&S->L, &S->c);
    cholmod_free_sparse(&S->A, &S->c);
    cholmod_finish(&S->c);
    free(S);
}
