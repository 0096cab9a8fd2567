/* fit_ls.c — the linear least-squares stages of the fit and their solvers.
 *
 * Every fit condition (sample fidelity, G1/G2 gluing relations with scalar gluing functions) is
 * linear in the unknown control points with the same coefficients for x, y and z, so a stage is
 * a sparse matrix A with three right-hand sides, split into independent items (one per mesh edge
 * or per patch).  The Ceres shim (core/ceres_shim.cpp) is the solver; q2n_fit_ls_solve_direct
 * solves each item with LAPACK's rank-revealing QR (core/dense.h) and is the reference the Ceres
 * path is tested against. */
#include "fit/fit_internal.h"
#include "fit/fit_policy.h"
#include "core/ceres_shim.h"
#include "core/dense.h"
#include "core/sparse.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void q2n_fit_ls_init(q2n_fit_ls *ls) { memset(ls, 0, sizeof *ls); }

void q2n_fit_ls_free(q2n_fit_ls *ls)
{
    if (!ls) return;
    free(ls->row_start); free(ls->col); free(ls->val); free(ls->rhs);
    free(ls->item_var); free(ls->item_row); free(ls->x);
    q2n_fit_ls_init(ls);
}

void q2n_fit_ls_clear(q2n_fit_ls *ls)
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

q2n_status q2n_fit_ls_item_begin(q2n_fit_ls *ls)
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

void q2n_fit_ls_item_end(q2n_fit_ls *ls)
{
    if (ls->nitem == 0) return;
    ls->item_var[ls->nitem] = ls->nvar;
    ls->item_row[ls->nitem] = ls->nrow;
}

q2n_status q2n_fit_ls_new_var(q2n_fit_ls *ls, int *id)
{
    *id = ls->nvar++;
    ls->item_var[ls->nitem] = ls->nvar;
    return Q2N_OK;
}

q2n_status q2n_fit_ls_row(q2n_fit_ls *ls, const double rhs[3])
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

q2n_status q2n_fit_ls_entry(q2n_fit_ls *ls, int var, double val)
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

q2n_status q2n_fit_ls_solve_direct(q2n_fit_ls *ls, q2n_error *err)
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
        int rank = 0, rc = q2n_dense_lstsq(m, n, 3, A, m, B, m, Q2N_FIT_LS_RCOND, &rank);
        if (rc > 0) { free(A); free(B); return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (LAPACK)"); }
        if (rc < 0 || rank < n) {
            free(A); free(B);
            return q2n_error_set(err, Q2N_ERR_GEOMETRY, "fit: item %d (%d unknowns) is rank deficient (rank %d)", it, n,
                                 rank);
        }
        for (int j = 0; j < n; j++)
            for (int c = 0; c < 3; c++) ls->x[3 * (size_t)(v0 + j) + c] = B[(size_t)c * m + j];
    }
    free(A); free(B);
    return Q2N_OK;
}

q2n_status q2n_fit_ls_solve_ceres(q2n_fit_ls *ls, int threads, int dense, q2n_error *err)
{
    free(ls->x);
    ls->x = calloc(3 * (size_t)(ls->nvar > 0 ? ls->nvar : 1), sizeof(double));
    if (!ls->x) return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (solution)");
    char msg[256] = "";
    q2n_sparse_init();   /* Ceres' sparse path factors with CHOLMOD */
    if (q2n_ceres_linear_ls(ls->nvar, ls->nrow, ls->row_start, ls->col, ls->val, ls->rhs, ls->x, threads,
                            dense, ls->nitem, ls->item_row, ls->item_var, msg, (int)sizeof msg))
        return q2n_error_set(err, Q2N_ERR_GEOMETRY, "fit: %s", msg);
    return Q2N_OK;
}

q2n_status q2n_fit_ls_dense_item(q2n_fit_ls *ls, int m, int n, const double *A, const double *b, int *var0)
{
    if (q2n_fit_ls_item_begin(ls)) return Q2N_ERR_NOMEM;
    *var0 = ls->nvar;
    for (int j = 0; j < n; j++) {
        int id;
        q2n_fit_ls_new_var(ls, &id);
    }
    int nc = new_cap(ls->cap_ent, ls->nent + m * n);
    if (nc) {
        if (!resize((void **)&ls->col, nc, sizeof(int)) || !resize((void **)&ls->val, nc, sizeof(double)))
            return Q2N_ERR_NOMEM;
        ls->cap_ent = nc;
    }
    for (int i = 0; i < m; i++) {   /* entries are distinct by construction: no merge scan */
        if (q2n_fit_ls_row(ls, b + 3 * (size_t)i)) return Q2N_ERR_NOMEM;
        for (int j = 0; j < n; j++)
            if (A[(size_t)i * n + j] != 0.0) {
                ls->col[ls->nent] = *var0 + j;
                ls->val[ls->nent++] = A[(size_t)i * n + j];
            }
        ls->row_start[ls->nrow] = ls->nent;
    }
    return Q2N_OK;
}

q2n_status q2n_fit_ls_solve(q2n_fit_ls *ls, int solver, int threads, q2n_error *err)
{
    q2n_fit_ls_item_end(ls);
    if (solver == Q2N_FIT_SOLVER_DIRECT) return q2n_fit_ls_solve_direct(ls, err);
    return q2n_fit_ls_solve_ceres(ls, threads, solver == Q2N_FIT_SOLVER_CERES, err);
}
