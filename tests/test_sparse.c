/* test_sparse.c — core/sparse.h: the SPD solves through CHOLMOD.
 *
 * A symmetric positive definite matrix on the pattern of a 2-D grid's 9-point stencil (the shape of
 * the fair construction's normal matrices: unknowns coupled with their neighbours' unknowns) is
 * solved three ways: as triplets (q2n_sparse_spd_solve), as a fixed pattern with values
 * (q2n_sparse_spd_create / factor_solve) and densely by LAPACK (core/dense.h).  The two sparse
 * paths must agree bit for bit (the fair construction moved from the first to the second with
 * byte-identical surfaces), both must solve the system to rounding against the dense answer, a
 * second set of values on the same pattern must be factorised afresh (not the first factor
 * reused), and an indefinite matrix must be refused with Q2N_ERR_GEOMETRY by both paths (CHOLMOD
 * factorises a system this small by simplicial LDL', which does not stop at a negative pivot: the
 * triplet path accepted this matrix until the pivots were checked). */
#include "check.h"
#include "core/dense.h"
#include "core/sparse.h"

#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9            /* grid side */
#define N (G * G)      /* unknowns */

static double rnd(unsigned *s) { *s = *s * 1103515245u + 12345u; return ((*s >> 8) & 0xffff) / 65536.0 - 0.5; }

/* Upper-triangle pattern of the 9-point stencil in compressed columns (rows ascending). */
static int pattern(int *colptr, int *rowind)
{
    int nnz = 0;
    for (int j = 0; j < N; j++) {
        colptr[j] = nnz;
        int jx = j % G, jy = j / G;
        for (int i = 0; i <= j; i++) {
            int ix = i % G, iy = i / G;
            if (abs(ix - jx) <= 1 && abs(iy - jy) <= 1) rowind[nnz++] = i;
        }
    }
    colptr[N] = nnz;
    return nnz;
}

/* Values: random couplings, a diagonal that dominates them by `shift` (negative: indefinite). */
static void values(const int *colptr, const int *rowind, unsigned seed, double shift, double *val, double *dense)
{
    memset(dense, 0, sizeof(double) * N * N);
    for (int j = 0; j < N; j++)
        for (int q = colptr[j]; q < colptr[j + 1]; q++) {
            int i = rowind[q];
            val[q] = i == j ? 0 : rnd(&seed);
            dense[i * N + j] = dense[j * N + i] = val[q];
        }
    for (int j = 0; j < N; j++) {
        double s = 0;
        for (int i = 0; i < N; i++) s += fabs(dense[i * N + j]);
        val[colptr[j + 1] - 1] = dense[j * N + j] = s + shift;
    }
}

int main(void)
{
    static int colptr[N + 1], rowind[N * 9], ti[N * 9], tj[N * 9];
    static double val[N * 9], dense[N * N], B[3 * N], X1[3 * N], X2[3 * N], Xd[3 * N], Ad[N * N];
    int nnz = pattern(colptr, rowind);
    unsigned s = 7;
    for (int k = 0; k < 3 * N; k++) B[k] = rnd(&s);
    q2n_sparse_spd *S = NULL;
    q2n_error err = {0, ""};
    CHECK(q2n_sparse_spd_create(N, colptr, rowind, &S, &err) == Q2N_OK, "create: %s", err.message);
    if (!S) CHECK_DONE("test_sparse");
    for (int round = 0; round < 2; round++) {
        values(colptr, rowind, 11 + 5 * round, round ? 0.5 : 2.0, val, dense);
        for (int j = 0, q = 0; j < N; j++)
            for (; q < colptr[j + 1]; q++) ti[q] = rowind[q], tj[q] = j;
        CHECK(q2n_sparse_spd_solve(N, nnz, ti, tj, val, 3, B, X1, &err) == Q2N_OK, "triplets: %s", err.message);
        memcpy(q2n_sparse_spd_values(S), val, sizeof(double) * (size_t)nnz);
        CHECK(q2n_sparse_spd_factor_solve(S, 3, B, X2, &err) == Q2N_OK, "pattern: %s", err.message);
        CHECK(memcmp(X1, X2, sizeof X1) == 0, "round %d: the pattern path differs from the triplet path", round);
        memcpy(Ad, dense, sizeof Ad);
        memcpy(Xd, B, sizeof Xd);
        CHECK(q2n_dense_solve(N, 3, Ad, N, Xd, N) == 0, "dense solve");
        double d = 0, sc = 0;
        for (int k = 0; k < 3 * N; k++) d = fmax(d, fabs(X2[k] - Xd[k])), sc = fmax(sc, fabs(Xd[k]));
        CHECK(d <= 1e-13 * sc, "round %d: sparse vs dense %.3g (scale %.3g)", round, d, sc);
    }
    /* indefinite: refused, with the column */
    values(colptr, rowind, 3, -40.0, val, dense);
    memcpy(q2n_sparse_spd_values(S), val, sizeof(double) * (size_t)nnz);
    for (int j = 0, q = 0; j < N; j++)
        for (; q < colptr[j + 1]; q++) ti[q] = rowind[q], tj[q] = j;
    q2n_status st0 = q2n_sparse_spd_solve(N, nnz, ti, tj, val, 3, B, X1, &err);
    CHECK(st0 == Q2N_ERR_GEOMETRY && strstr(err.message, "not positive definite"), "triplets: indefinite matrix accepted (%d: %s)",
          st0, err.message);
    q2n_status st1 = q2n_sparse_spd_factor_solve(S, 3, B, X2, &err);
    CHECK(st1 == Q2N_ERR_GEOMETRY && strstr(err.message, "not positive definite"),
          "indefinite matrix accepted (%d: %s)", st1, err.message);
    /* the factorisation trims CHOLMOD's OpenMP teams (sparse.c) for its own thread only: the
     * caller's setting is back afterwards, whichever it was */
    void *self = dlopen(NULL, RTLD_LAZY);
    int (*get_dyn)(void) = NULL;
    void (*set_dyn)(int) = NULL;
    if (self) {
        *(void **)&get_dyn = dlsym(self, "omp_get_dynamic");
        *(void **)&set_dyn = dlsym(self, "omp_set_dynamic");
    }
    if (get_dyn && set_dyn) {
        values(colptr, rowind, 11, 2.0, val, dense);
        for (int want = 0; want < 2; want++) {
            set_dyn(want);
            memcpy(q2n_sparse_spd_values(S), val, sizeof(double) * (size_t)nnz);
            CHECK(q2n_sparse_spd_factor_solve(S, 3, B, X2, &err) == Q2N_OK, "dynamic %d: %s", want, err.message);
            CHECK(get_dyn() == want, "the caller's OpenMP dynamic setting %d came back as %d", want, get_dyn());
        }
    } else
        printf("no OpenMP runtime in the process (CHOLMOD built without it): nothing to restore\n");
    if (self) dlclose(self);
    q2n_sparse_spd_free(S);
    CHECK_DONE("test_sparse");
}
