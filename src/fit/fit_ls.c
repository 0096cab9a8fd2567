/* fit_ls.c — the linear least-squares stages of the fit and their direct reference solver.
 *
 * Every fit condition (sample fidelity, G1/G2 gluing relations with scalar gluing functions) is
 * linear in the unknown control points with the same coefficients for x, y and z, so a stage is
 * a sparse matrix A with three right-hand sides, split into independent items (one per mesh edge
 * or per patch).  fit_ls_solve_direct solves each item with a dense Householder QR (Golub & Van
 * Loan, Matrix Computations, §5.2 and §5.3.3: QR solution of the full-rank LS problem); it is the
 * reference the Ceres path (ceres_shim.cpp) is tested against. */
#include "fit/fit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void fit_ls_init(fit_ls *ls) { memset(ls, 0, sizeof *ls); }

void fit_ls_free(fit_ls *ls)
{
    if (!ls) return;
    free(ls->row_start); free(ls->col); free(ls->val); free(ls->rhs);
    free(ls->item_var); free(ls->item_row); free(ls->x);
    fit_ls_init(ls);
}

void fit_ls_clear(fit_ls *ls)
{
    ls->nvar = ls->nrow = ls->nent = ls->nitem = 0;
    if (ls->row_start) ls->row_start[0] = 0;
}

/* Capacity for at least need elements (doubling); 0 when unchanged, else the new capacity. */
static int new_cap(int cap, int need)
{
    if (need <= cap) return 0;
    int nc = cap ? cap : 64;
    while (nc < need) nc *= 2;
    return nc;
}

/* realloc *p to n elements of size sz. */
static int resize(void **p, int n, size_t sz)
{
    void *q = realloc(*p, (size_t)n * sz);
    if (!q) return 0;
    *p = q;
    return 1;
}

q2n_status fit_ls_item_begin(fit_ls *ls)
{
    int nc = new_cap(ls->cap_item, ls->nitem + 2);
    if (nc) {
        if (!resize((void **)&ls->item_var, nc, sizeof(int)) || !resize((void **)&ls->item_row, nc, sizeof(int)))
            return Q2N_ERR_NOMEM;
        ls->cap_item = nc;
    }
    if (!ls->row_start) {
        if (!resize((void **)&ls->row_start, 64, sizeof(int)) || !resize((void **)&ls->rhs, 64, 3 * sizeof(double)))
            return Q2N_ERR_NOMEM;
        ls->cap_row = 63;
        ls->row_start[0] = 0;
    }
    ls->item_var[ls->nitem] = ls->nvar;
    ls->item_row[ls->nitem] = ls->nrow;
    ls->nitem++;
    ls->item_var[ls->nitem] = ls->nvar;
    ls->item_row[ls->nitem] = ls->nrow;
    return Q2N_OK;
}

void fit_ls_item_end(fit_ls *ls)
{
    if (ls->nitem == 0) return;
    ls->item_var[ls->nitem] = ls->nvar;
    ls->item_row[ls->nitem] = ls->nrow;
}

q2n_status fit_ls_new_var(fit_ls *ls, int *id)
{
    *id = ls->nvar++;
    ls->item_var[ls->nitem] = ls->nvar;
    return Q2N_OK;
}

q2n_status fit_ls_row(fit_ls *ls, const double rhs[3])
{
    int nc = new_cap(ls->cap_row, ls->nrow + 1);
    if (nc) {   /* row_start needs nrow+2 entries: allocate cap+1 */
        if (!resize((void **)&ls->row_start, nc + 1, sizeof(int)) || !resize((void **)&ls->rhs, nc, 3 * sizeof(double)))
            return Q2N_ERR_NOMEM;
        ls->cap_row = nc;
    }
    memcpy(ls->rhs + 3 * (size_t)ls->nrow, rhs, 3 * sizeof(double));
    ls->nrow++;
    ls->row_start[ls->nrow] = ls->nent;
    ls->item_row[ls->nitem] = ls->nrow;
    return Q2N_OK;
}

q2n_status fit_ls_entry(fit_ls *ls, int var, double val)
{
    /* merge with an existing entry of the same variable in this row */
    for (int e = ls->row_start[ls->nrow - 1]; e < ls->nent; e++)
        if (ls->col[e] == var) { ls->val[e] += val; return Q2N_OK; }
    int nc = new_cap(ls->cap_ent, ls->nent + 1);
    if (nc) {
        if (!resize((void **)&ls->col, nc, sizeof(int)) || !resize((void **)&ls->val, nc, sizeof(double)))
            return Q2N_ERR_NOMEM;
        ls->cap_ent = nc;
    }
    ls->col[ls->nent] = var;
    ls->val[ls->nent] = val;
    ls->nent++;
    ls->row_start[ls->nrow] = ls->nent;
    return Q2N_OK;
}

/* Householder QR least squares of one dense item: A (m x n, column-major, lda = m) and B (m x 3,
 * column-major) are overwritten; the solution goes to x[3*n] (xyz per unknown).  Returns 0 when
 * a column is numerically dependent (|R_jj| <= 1e-13 * max column norm). */
static int qr_solve(int m, int n, double *A, double *B, double *x)
{
    double amax = 0.0;
    for (int j = 0; j < n; j++) {
        double s = 0.0;
        for (int i = 0; i < m; i++) s += A[(size_t)j * m + i] * A[(size_t)j * m + i];
        if (sqrt(s) > amax) amax = sqrt(s);
    }
    for (int j = 0; j < n; j++) {
        double *a = A + (size_t)j * m;
        double s = 0.0;
        for (int i = j; i < m; i++) s += a[i] * a[i];
        double nrm = sqrt(s);
        if (nrm <= 1e-13 * amax) return 0;
        double alpha = a[j] > 0 ? -nrm : nrm;   /* reflect a[j:] onto alpha e_j */
        double v0 = a[j] - alpha;
        a[j] = v0;                                /* v = (v0, a[j+1:]) stored in place */
        double vv = 0.0;
        for (int i = j; i < m; i++) vv += a[i] * a[i];
        for (int k = j + 1; k < n + 3; k++) {
            double *c = k < n ? A + (size_t)k * m : B + (size_t)(k - n) * m;
            double d = 0.0;
            for (int i = j; i < m; i++) d += a[i] * c[i];
            d = 2.0 * d / vv;
            for (int i = j; i < m; i++) c[i] -= d * a[i];
        }
        a[j] = alpha;                             /* R_jj; below-diagonal part no longer needed */
    }
    for (int c = 0; c < 3; c++) {
        const double *b = B + (size_t)c * m;
        for (int j = n - 1; j >= 0; j--) {
            double s = b[j];
            for (int k = j + 1; k < n; k++) s -= A[(size_t)k * m + j] * x[3 * k + c];
            x[3 * j + c] = s / A[(size_t)j * m + j];
        }
    }
    return 1;
}

q2n_status fit_ls_solve_direct(fit_ls *ls, q2n_error *err)
{
    free(ls->x);
    ls->x = calloc(3 * (size_t)(ls->nvar > 0 ? ls->nvar : 1), sizeof(double));
    if (!ls->x) return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (solution)");
    double *A = NULL, *B = NULL;
    size_t capA = 0, capB = 0;
    for (int it = 0; it < ls->nitem; it++) {
        int v0 = ls->item_var[it], n = ls->item_var[it + 1] - v0;
        int r0 = ls->item_row[it], m = ls->item_row[it + 1] - r0;
        if (n == 0) continue;
        if (m < n) {
            free(A); free(B);
            return q2n_error_set(err, Q2N_ERR_GEOMETRY, "fit: item %d has %d conditions for %d unknowns",
                                 it, m, n);
        }
        if ((size_t)m * n > capA) {
            capA = (size_t)m * n;
            double *t = realloc(A, capA * sizeof *A);
            if (!t) { free(A); free(B); return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory"); }
            A = t;
        }
        if ((size_t)m * 3 > capB) {
            capB = (size_t)m * 3;
            double *t = realloc(B, capB * sizeof *B);
            if (!t) { free(A); free(B); return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory"); }
            B = t;
        }
        memset(A, 0, (size_t)m * n * sizeof *A);
        for (int r = 0; r < m; r++) {
            for (int e = ls->row_start[r0 + r]; e < ls->row_start[r0 + r + 1]; e++)
                A[(size_t)(ls->col[e] - v0) * m + r] += ls->val[e];
            for (int c = 0; c < 3; c++) B[(size_t)c * m + r] = ls->rhs[3 * (size_t)(r0 + r) + c];
        }
        if (!qr_solve(m, n, A, B, ls->x + 3 * (size_t)v0)) {
            free(A); free(B);
            return q2n_error_set(err, Q2N_ERR_GEOMETRY, "fit: item %d (%d unknowns) is rank deficient", it, n);
        }
    }
    free(A); free(B);
    return Q2N_OK;
}

#include "core/ceres_shim.h"

q2n_status fit_ls_solve_ceres(fit_ls *ls, int threads, int dense, q2n_error *err)
{
    free(ls->x);
    ls->x = calloc(3 * (size_t)(ls->nvar > 0 ? ls->nvar : 1), sizeof(double));
    if (!ls->x) return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (solution)");
    char msg[256] = "";
    if (q2n_ceres_linear_ls(ls->nvar, ls->nrow, ls->row_start, ls->col, ls->val, ls->rhs, ls->x, threads,
                            dense, ls->nitem, ls->item_row, ls->item_var, msg, (int)sizeof msg))
        return q2n_error_set(err, Q2N_ERR_GEOMETRY, "fit: %s", msg);
    return Q2N_OK;
}
