/* dense.c — dense least squares and constraint elimination through LAPACK (see dense.h). */
#include "core/dense.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* LAPACK's Fortran entry points (reference LAPACK 3.x, gfortran calling convention: scalars by
 * reference, one hidden length argument per CHARACTER argument, after the others). */
extern void dgelsy_(const int *m, const int *n, const int *nrhs, double *a, const int *lda, double *b, const int *ldb,
                    int *jpvt, const double *rcond, int *rank, double *work, const int *lwork, int *info);
extern void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a, const int *lda,
                    double *s, double *u, const int *ldu, double *vt, const int *ldvt, double *work, const int *lwork,
                    int *info, size_t ljobu, size_t ljobvt);
extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b, const int *ldb,
                   int *info);
extern void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info, size_t luplo);
extern void dpotrs_(const char *uplo, const int *n, const int *nrhs, const double *a, const int *lda, double *b,
                    const int *ldb, int *info, size_t luplo);
extern void dptsv_(const int *n, const int *nrhs, double *d, double *e, double *b, const int *ldb, int *info);

/* LAPACK's info: 0 success, < 0 a bad argument (-1 here), > 0 the matrix (1 here). */
static int info_code(int info) { return info < 0 ? -1 : info > 0 ? 1 : 0; }

void *q2n_aligned_alloc(size_t bytes)
{
    size_t b = bytes ? bytes : 1;
    if (b > (size_t)-1 - Q2N_DENSE_ALIGN) return NULL;
    return aligned_alloc(Q2N_DENSE_ALIGN, (b + Q2N_DENSE_ALIGN - 1) / Q2N_DENSE_ALIGN * Q2N_DENSE_ALIGN);
}

double *q2n_dense_alloc(size_t n)
{
    return n > (size_t)-1 / sizeof(double) ? NULL : q2n_aligned_alloc(n * sizeof(double));
}

/* An aligned copy of the ld x cols column-major array X (dense.h, "Alignment"), or NULL. */
static double *stage(const double *X, int ld, int cols)
{
    size_t n = (size_t)ld * (size_t)cols;
    double *a = q2n_dense_alloc(n);
    if (a && n) memcpy(a, X, n * sizeof(double));
    return a;
}

static void unstage(double *X, const double *a, int ld, int cols)
{
    memcpy(X, a, (size_t)ld * (size_t)cols * sizeof(double));
}

int q2n_dense_solve(int n, int nrhs, double *A, int lda, double *B, int ldb)
{
    if (n < 0 || nrhs < 0 || lda < (n > 1 ? n : 1) || ldb < (n > 1 ? n : 1)) return -1;
    if (n == 0 || nrhs == 0) return 0;
    int *ipiv = malloc(sizeof(int) * (size_t)n), info = 0;
    double *a = stage(A, lda, n), *b = stage(B, ldb, nrhs);
    if (!ipiv || !a || !b) { free(ipiv); free(a); free(b); return 1; }
    dgesv_(&n, &nrhs, a, &lda, ipiv, b, &ldb, &info);
    unstage(A, a, lda, n);
    unstage(B, b, ldb, nrhs);
    free(ipiv); free(a); free(b);
    return info_code(info);
}

int q2n_dense_cholesky(int n, double *A, int lda)
{
    if (n < 0 || lda < (n > 1 ? n : 1)) return -1;
    if (n == 0) return 0;
    int info = 0;
    double *a = stage(A, lda, n);
    if (!a) return 1;
    dpotrf_("L", &n, a, &lda, &info, 1);
    unstage(A, a, lda, n);
    free(a);
    return info_code(info);
}

int q2n_dense_cholesky_solve(int n, int nrhs, const double *L, int lda, double *B, int ldb)
{
    if (n < 0 || nrhs < 0 || lda < (n > 1 ? n : 1) || ldb < (n > 1 ? n : 1)) return -1;
    if (n == 0 || nrhs == 0) return 0;
    int info = 0;
    double *l = stage(L, lda, n), *b = stage(B, ldb, nrhs);
    if (!l || !b) { free(l); free(b); return 1; }
    dpotrs_("L", &n, &nrhs, l, &lda, b, &ldb, &info, 1);
    unstage(B, b, ldb, nrhs);
    free(l); free(b);
    return info_code(info);
}

int q2n_dense_tridiag_spd(int n, int nrhs, double *d, double *e, double *B, int ldb)
{
    if (n < 0 || nrhs < 0 || ldb < (n > 1 ? n : 1)) return -1;
    if (n == 0 || nrhs == 0) return 0;
    int info = 0;
    double *dd = stage(d, n, 1), *ee = stage(e, n - 1, 1), *b = stage(B, ldb, nrhs);
    if (!dd || !ee || !b) { free(dd); free(ee); free(b); return 1; }
    dptsv_(&n, &nrhs, dd, ee, b, &ldb, &info);
    unstage(d, dd, n, 1);
    unstage(e, ee, n - 1, 1);
    unstage(B, b, ldb, nrhs);
    free(dd); free(ee); free(b);
    return info_code(info);
}

int q2n_dense_lstsq(int m, int n, int nrhs, double *A, int lda, double *B, int ldb, double rcond, int *rank)
{
    if (m < 0 || n < 0 || nrhs < 0 || lda < (m > 1 ? m : 1) || ldb < (m > n ? m : n) || ldb < 1) return -1;
    if (n == 0 || nrhs == 0) { if (rank) *rank = 0; return 0; }
    int *jpvt = calloc((size_t)n, sizeof *jpvt), rk = 0, info = 0, lwork = -1;
    double wq = 0.0, *a = stage(A, lda, n), *b = stage(B, ldb, nrhs);
    if (!jpvt || !a || !b) { free(jpvt); free(a); free(b); return 1; }
    dgelsy_(&m, &n, &nrhs, a, &lda, b, &ldb, jpvt, &rcond, &rk, &wq, &lwork, &info);   /* workspace query */
    lwork = info == 0 ? (int)wq : 0;
    double *work = lwork > 0 ? q2n_dense_alloc((size_t)lwork) : NULL;
    if (!work) { free(jpvt); free(a); free(b); return 1; }
    dgelsy_(&m, &n, &nrhs, a, &lda, b, &ldb, jpvt, &rcond, &rk, work, &lwork, &info);
    unstage(A, a, lda, n);
    unstage(B, b, ldb, nrhs);
    free(work); free(jpvt); free(a); free(b);
    if (rank) *rank = rk;
    return info < 0 ? -1 : info > 0 ? 1 : 0;
}

int q2n_dense_nullspace(int c, int n, const double *C, int ldc, int nrhs, const double *D, int ldd, double rcond,
                        double *Z, int *k, double *Xp, double *resid)
{
    if (c < 0 || n < 0 || nrhs < 0 || ldc < (c > 1 ? c : 1) || ldd < (c > 1 ? c : 1)) return -1;
    if (resid) *resid = 0.0;
    memset(Xp, 0, sizeof(double) * (size_t)n * (size_t)nrhs);
    if (c == 0 || n == 0) {   /* no constraints: the null space is everything */
        memset(Z, 0, sizeof(double) * (size_t)n * (size_t)n);
        for (int j = 0; j < n; j++) Z[(size_t)j * n + j] = 1.0;
        *k = n;
        return 0;
    }
    int mn = c < n ? c : n, lwork = -1, info = 0, ldu = c, ldvt = n;
    double *a = q2n_dense_alloc((size_t)c * n), *s = q2n_dense_alloc((size_t)mn);
    double *u = q2n_dense_alloc((size_t)c * mn), *vt = q2n_dense_alloc((size_t)n * n), wq = 0.0;
    if (!a || !s || !u || !vt) { free(a); free(s); free(u); free(vt); return 1; }
    for (int j = 0; j < n; j++) memcpy(a + (size_t)j * c, C + (size_t)j * ldc, sizeof(double) * (size_t)c);
    /* C = U S V^T: U c x mn ("S"), V^T n x n ("A": the trailing rows span the null space) */
    dgesvd_("S", "A", &c, &n, a, &c, s, u, &ldu, vt, &ldvt, &wq, &lwork, &info, 1, 1);
    lwork = info == 0 ? (int)wq : 0;
    double *work = lwork > 0 ? q2n_dense_alloc((size_t)lwork) : NULL;
    if (!work) { free(a); free(s); free(u); free(vt); return 1; }
    dgesvd_("S", "A", &c, &n, a, &c, s, u, &ldu, vt, &ldvt, work, &lwork, &info, 1, 1);
    free(work);
    if (info != 0) { free(a); free(s); free(u); free(vt); return info < 0 ? -1 : 1; }
    int r = 0;
    while (r < mn && s[r] > rcond * s[0]) r++;
    /* Xp = V_r S_r^-1 U_r^T D */
    for (int q = 0; q < nrhs; q++)
        for (int i = 0; i < r; i++) {
            double w = 0.0;
            for (int l = 0; l < c; l++) w += u[(size_t)i * c + l] * D[(size_t)q * ldd + l];
            w /= s[i];
            for (int j = 0; j < n; j++) Xp[(size_t)q * n + j] += vt[(size_t)j * n + i] * w;   /* V[j][i] = VT[i][j] */
        }
    /* Z = V[:, r..n-1] */
    *k = n - r;
    for (int col = 0; col < n - r; col++)
        for (int j = 0; j < n; j++) Z[(size_t)col * n + j] = vt[(size_t)j * n + (r + col)];
    if (resid) {
        double e = 0.0;
        for (int q = 0; q < nrhs; q++)
            for (int l = 0; l < c; l++) {
                double w = -D[(size_t)q * ldd + l];
                for (int j = 0; j < n; j++) w += C[(size_t)j * ldc + l] * Xp[(size_t)q * n + j];
                if (fabs(w) > e) e = fabs(w);
            }
        *resid = e;
    }
    free(a); free(s); free(u); free(vt);
    return 0;
}

void q2n_dense_mul(int m, int p, int n, const double *A, int lda, const double *B, int ldb, double *R, int ldr)
{
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) {
            double w = 0.0;
            for (int l = 0; l < p; l++) w += A[(size_t)l * lda + i] * B[(size_t)j * ldb + l];
            R[(size_t)j * ldr + i] = w;
        }
}
