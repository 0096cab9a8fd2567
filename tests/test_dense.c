/* test_dense.c — core/dense.h: the same input gives the same bits whatever the heap looks like.
 *
 * The BLAS under LAPACK may take alignment-dependent paths.  With ATLAS (Debian's libblas and
 * liblapack where it is installed) dgesvd of the 12 x 1 matrix below — a constraint block met in a
 * fit (the basis values of a span, symmetric) — returns u with different last bits when the matrix
 * starts at 16 mod 32 than at 0, and malloc only promises 16-byte alignment, so where an
 * allocation lands depended on the heap's history: osd_catmark_rook --subdivide 1 gave different
 * output bytes in about one run in six.  Here every routine of dense.h is called on fixed inputs
 * after many different heap histories (allocations and frees of random sizes) and with its
 * arguments at every 8-byte offset, and each answer must be bit for bit the first one.  With the
 * old code (LAPACK arrays straight from malloc) the null-space check fails on ATLAS machines; with
 * the reference BLAS both pass either way.  Also: the answers are right (residuals), and
 * q2n_dense_alloc aligns. */
#include "check.h"
#include "core/dense.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static double rnd(unsigned *s) { *s = *s * 1103515245u + 12345u; return ((*s >> 8) & 0xffff) / 65536.0 - 0.5; }

/* Leave the heap in a different state: allocate blocks of random sizes, free about half. */
#define KEEP_MAX 4096
static void *keep[KEEP_MAX];
static int nkeep;
static void churn(unsigned seed)
{
    for (int q = 0; q < 24; q++) {
        seed = seed * 1103515245u + 12345u;
        size_t n = 8 + (seed >> 8) % 3000;
        void *p = malloc(n);
        if (!p) continue;
        memset(p, 0x5a, n);
        if ((seed >> 4) & 1 || nkeep >= KEEP_MAX) free(p);
        else keep[nkeep++] = p;
    }
}

static void release(void)
{
    for (int i = 0; i < nkeep; i++) free(keep[i]);
    nkeep = 0;
}

/* A copy of n doubles at byte offset off (0, 8, .., 56) from a 64-byte boundary. */
static double *at_offset(const double *x, size_t n, int off, void **base)
{
    char *raw = malloc((n + 8) * sizeof(double) + 64);
    *base = raw;
    if (!raw) return NULL;
    char *p = raw + (64 - (uintptr_t)raw % 64) % 64 + off;
    memcpy(p, x, n * sizeof(double));
    return (double *)p;
}

static const double bell[12] = {-1.1886318514915189e-05, -0.006366846702040583, -0.07395041822210331,
                                -0.22758931085183756, -0.3427895859824758, -0.3679846209091715,
                                -0.3679846209091715, -0.3427895859824758, -0.22758931085183756,
                                -0.07395041822210331, -0.0063668467020405895, -1.1886318514915304e-05};

static void test_alloc(void)
{
    int bad = 0;
    for (size_t n = 0; n < 200; n += 7) {
        double *p = q2n_dense_alloc(n);
        bad += !p || (uintptr_t)p % Q2N_DENSE_ALIGN != 0;
        if (p && n) p[n - 1] = 1;   /* the whole size is usable */
        free(p);
    }
    CHECK(bad == 0, "q2n_dense_alloc: every block on a %d-byte boundary (%d bad)", Q2N_DENSE_ALIGN, bad);
}

/* q2n_dense_nullspace on C (c x n) with D (c x 3): same bits after 200 heap histories and at 8
 * argument offsets; Xp solves C X = D (consistent data) and C Z = 0. */
static void nullspace_case(const char *what, int c, int n, const double *C, const double *D)
{
    double Z0[64], X0[24], r0 = 0, Z[64], X[24], r;
    int k0 = -1, k, differ = 0;
    CHECK(q2n_dense_nullspace(c, n, C, c, 3, D, c, 1e-11, Z0, &k0, X0, &r0) == 0, "%s: null space computed", what);
    for (int h = 0; h < 200; h++) {
        churn(1000u + (unsigned)h);
        void *bc, *bd;
        double *Cc = at_offset(C, (size_t)c * n, 8 * (h % 8), &bc), *Dc = at_offset(D, (size_t)c * 3, 8 * ((h / 8) % 8), &bd);
        if (!Cc || !Dc || q2n_dense_nullspace(c, n, Cc, c, 3, Dc, c, 1e-11, Z, &k, X, &r) != 0) differ++;
        else differ += k != k0 || memcmp(Z, Z0, sizeof(double) * (size_t)n * k0) || memcmp(X, X0, sizeof(double) * (size_t)n * 3) || r != r0;
        free(bc);
        free(bd);
    }
    release();
    CHECK(differ == 0, "%s: the same bits after 200 heap histories and argument offsets (%d differ)", what, differ);
    double worst = 0;
    for (int l = 0; l < c; l++) {
        for (int q = 0; q < 3; q++) {
            double w = -D[(size_t)q * c + l];
            for (int j = 0; j < n; j++) w += C[(size_t)j * c + l] * X0[(size_t)q * n + j];
            worst = fmax(worst, fabs(w));
        }
        for (int col = 0; col < k0; col++) {
            double w = 0;
            for (int j = 0; j < n; j++) w += C[(size_t)j * c + l] * Z0[(size_t)col * n + j];
            worst = fmax(worst, fabs(w));
        }
    }
    CHECK(worst < 1e-13, "%s: C Xp = D and C Z = 0 to %.2g", what, worst);
}

static void test_nullspace(void)
{
    double D[36];
    for (int l = 0; l < 12; l++)
        for (int q = 0; q < 3; q++) D[q * 12 + l] = bell[l] * (q + 1);   /* consistent: X = (1, 2, 3) */
    nullspace_case("12 x 1 symmetric bell", 12, 1, bell, D);
    /* a rank-3 block of 24 constraints on 6 unknowns (dependent rows, as the fit's exact blocks) */
    unsigned s = 7;
    double R1[72], R2[18], C[144], X[18], D2[72];
    for (int i = 0; i < 72; i++) R1[i] = rnd(&s);
    for (int i = 0; i < 18; i++) R2[i] = rnd(&s);
    for (int i = 0; i < 18; i++) X[i] = rnd(&s);
    for (int j = 0; j < 6; j++)
        for (int l = 0; l < 24; l++) {
            double w = 0;
            for (int q = 0; q < 3; q++) w += R1[q * 24 + l] * R2[j * 3 + q];
            C[j * 24 + l] = w;
        }
    for (int q = 0; q < 3; q++)
        for (int l = 0; l < 24; l++) {
            double w = 0;
            for (int j = 0; j < 6; j++) w += C[j * 24 + l] * X[q * 6 + j];
            D2[q * 24 + l] = w;
        }
    nullspace_case("24 x 6 of rank 3", 24, 6, C, D2);
}

/* The solvers on fixed inputs: the same bits after different heap histories. */
static void test_solvers(void)
{
    unsigned s = 11;
    enum { M = 30, N = 8 };
    double A[M * N], B[M * 3], S[N * N], Bs[N * 3];
    for (int i = 0; i < M * N; i++) A[i] = rnd(&s);
    for (int i = 0; i < M * 3; i++) B[i] = rnd(&s);
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double w = i == j ? N : 0;
            for (int l = 0; l < M; l++) w += A[i * M + l] * A[j * M + l];
            S[j * N + i] = w;   /* symmetric positive definite */
        }
    for (int i = 0; i < N * 3; i++) Bs[i] = rnd(&s);
    double ref_ls[M * 3], ref_lu[N * 3], ref_ch[N * N], ref_cs[N * 3];
    int differ = 0;
    for (int h = 0; h <= 60; h++) {
        if (h) churn(5000u + (unsigned)h);
        double a[M * N], b[M * 3], sa[N * N], sb[N * 3], ca[N * N], cb[N * 3];
        int rank = 0;
        memcpy(a, A, sizeof a);
        memcpy(b, B, sizeof b);
        int e1 = q2n_dense_lstsq(M, N, 3, a, M, b, M, 1e-12, &rank);
        memcpy(sa, S, sizeof sa);
        memcpy(sb, Bs, sizeof sb);
        int e2 = q2n_dense_solve(N, 3, sa, N, sb, N);
        memcpy(ca, S, sizeof ca);
        int e3 = q2n_dense_cholesky(N, ca, N);
        memcpy(cb, Bs, sizeof cb);
        int e4 = e3 ? 1 : q2n_dense_cholesky_solve(N, 3, ca, N, cb, N);
        if (h == 0) {
            CHECK(!e1 && !e2 && !e3 && !e4 && rank == N, "solvers succeed (rank %d)", rank);
            memcpy(ref_ls, b, sizeof b);
            memcpy(ref_lu, sb, sizeof sb);
            memcpy(ref_ch, ca, sizeof ca);
            memcpy(ref_cs, cb, sizeof cb);
            double worst = 0;
            for (int i = 0; i < N * 3; i++) worst = fmax(worst, fabs(sb[i] - cb[i]));
            CHECK(worst < 1e-12, "LU and Cholesky agree to %.2g", worst);
        } else {
            differ += e1 || e2 || e3 || e4 || memcmp(b, ref_ls, sizeof b) || memcmp(sb, ref_lu, sizeof sb) ||
                      memcmp(ca, ref_ch, sizeof ca) || memcmp(cb, ref_cs, sizeof cb);
        }
    }
    release();
    CHECK(differ == 0, "lstsq, solve, cholesky: the same bits after 60 heap histories (%d differ)", differ);
}

int main(void)
{
    test_alloc();
    test_nullspace();
    test_solvers();
    CHECK_DONE("test_dense");
}
