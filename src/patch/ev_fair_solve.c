/* ev_fair_solve.c — the fairness-energy solve of the fair extraordinary construction
 * (ev_fair_internal.h; docs/extraordinary.md, "The fair construction", 5 and 6): per-face
 * quadratic forms of the bending and curvature-variation terms (assembled in lanes, on worker
 * threads), one sparse SPD system of their sum shared by x, y and z (CHOLMOD), a bending-only pass
 * whose result sets the variation weights ω_F, the full pass, and the fold guard. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <pthread.h>

#include "core/dense.h"
#include "core/par.h"
#include "core/sparse.h"
#include "core/vec3.h"
#include "patch/ev_fair_internal.h"
#include "patch/ev_policy.h"

/* W-wide corner jets and bubbles of face fi (faces[fi] = f) for the assembly: fixed slots in
 * lanes 0..2, free unknown k (local numbering; loc[k] = global index) in lane 3 + k. */
static int assembly_lanes(const fe_build *B, int fi, int f, double *Jl, double *bl, int *loc)
{
    const q2n_mesh *m = B->m;
    int n = 0;
    for (int c = 0; c < 4; c++) {
        int v = m->face_vert[m->face_start[f] + c];
        for (int k = 0; k < EV_JS; k++)
            if (B->var[v * EV_JS + k] >= 0) loc[n++] = B->var[v * EV_JS + k];
    }
    for (int b = 0; b < CP_NBUB; b++) loc[n++] = B->bvar[fi] + b;
    int W = 3 + n, q = 0;
    memset(Jl, 0, sizeof(double) * 4 * EV_JS * CP_MAXW);
    memset(bl, 0, sizeof(double) * CP_NBUB * CP_MAXW);
    for (int c = 0; c < 4; c++) {
        int v = m->face_vert[m->face_start[f] + c];
        double *J = Jl + (size_t)c * EV_JS * W;
        for (int k = 0; k < EV_JS; k++) {
            if (B->var[v * EV_JS + k] >= 0) J[k * W + 3 + q++] = 1;
            else memcpy(J + k * W, B->jet[v][k], 3 * sizeof(double));
        }
    }
    for (int b = 0; b < CP_NBUB; b++) bl[(size_t)b * W + 3 + q++] = 1;
    return W;
}

/* Face scale for the energy: mean lengths of the u-edges and of the v-edges. */
static void face_scale(const q2n_mesh *m, int f, double *Lu, double *Lv)
{
    const double *p[4];
    for (int i = 0; i < 4; i++) p[i] = q2n_mesh_vpos(m, m->face_vert[m->face_start[f] + i]);
    *Lu = 0.5 * (q2n_v3_dist(p[0], p[1]) + q2n_v3_dist(p[3], p[2]));
    *Lv = 0.5 * (q2n_v3_dist(p[0], p[3]) + q2n_v3_dist(p[1], p[2]));
}

/* Per-face quadratic forms of the two energy terms in the face's unknowns (local numbering loc):
 * E_t(x) = Σ_xyz (xᵀ K_t x - 2 x·r_t + c_t), t = 0 bending, 1 curvature variation (unit weight;
 * K_t shared by x, y and z, its upper triangle packed by rows: entry (i, k >= i) at pk(nl, i, k)). */
typedef struct fe_form {
    int nl;
    int loc[4 * EV_JS + CP_NBUB];
    double *K[2], *r[2];
    double c[2];
} fe_form;

static inline size_t pk(int nl, int i, int k) { return (size_t)i * (size_t)(2 * nl - i + 1) / 2 + (size_t)(k - i); }

/* Entry q of the face's weighted normal block: bending plus w1 times variation. */
static inline double form_at(const fe_form *f, size_t q, double w1) { return f->K[0][q] + (w1 != 0 ? w1 * f->K[1][q] : 0); }

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return x < y ? -1 : x > y;
}

static void form_free(fe_form *F)
{
    for (int t = 0; t < 2; t++) {
        free(F->K[t]);
        free(F->r[t]);
    }
}

/* Assemble the forms of face fi (faces[fi] = f) on the Gauss grid. */
static q2n_status face_form(const fe_build *B, int fi, int f, const cp_patch *P, const double *gx, const double *gw, int ng,
                            fe_form *F)
{
    const q2n_mesh *m = B->m;
    double *Jl = malloc(sizeof(double) * 4 * EV_JS * CP_MAXW), bl[CP_NBUB * CP_MAXW];
    cp_line *Lu = malloc(2 * (size_t)ng * sizeof *Lu), *Lv = Lu ? Lu + ng : NULL;
    double *lst = malloc(2 * (size_t)ng * CP_LINE_SIZE(CP_MAXW) * sizeof *lst);
    cp_corner C = {0, malloc(sizeof(double) * 3 * 36 * CP_MAXW)};
    size_t np = (size_t)ng * ng;
    double *G = malloc(sizeof(double) * np * 7 * CP_MAXW);
    /* BLAS arrays on an aligned boundary: core/dense.h, "Alignment" */
    double *A = q2n_dense_alloc((size_t)np * 4 * (4 * EV_JS + CP_NBUB)), *A0 = q2n_dense_alloc((size_t)np * 4 * 3);
    q2n_status st = Q2N_OK;
    memset(F, 0, sizeof *F);
    if (!Jl || !Lu || !lst || !C.v || !G || !A || !A0) { st = Q2N_ERR_NOMEM; goto done; }
    for (int k = 0; k < 2 * ng; k++) Lu[k].s = lst + (size_t)k * CP_LINE_SIZE(CP_MAXW);
    int W = assembly_lanes(B, fi, f, Jl, bl, F->loc), nl = W - 3;
    F->nl = nl;
    const double *J[4];
    for (int c = 0; c < 4; c++) J[c] = Jl + (size_t)c * EV_JS * W;
    double Lsu, Lsv;
    face_scale(m, f, &Lsu, &Lsv);
    double Lc2 = Lsu * Lsv, Lc = sqrt(Lc2);
    /* x = u Lsu, y = v Lsv: bending |S_xx|² + 2|S_xy|² + |S_yy|², variation L² (|S_xxx|² + 3|S_xxy|²
     * + 3|S_xyy|² + |S_yyy|²) */
    const double sc[7] = {1 / (Lsu * Lsu), 1.4142135623730951 / (Lsu * Lsv), 1 / (Lsv * Lsv),
                          Lc / (Lsu * Lsu * Lsu), Lc * 1.7320508075688772 / (Lsu * Lsu * Lsv),
                          Lc * 1.7320508075688772 / (Lsu * Lsv * Lsv), Lc / (Lsv * Lsv * Lsv)};
    fe_lanes L;
    double *tayv = malloc(sizeof(double) * 4 * FE_TAYLOR_SIZE(W));
    if (!tayv) { st = Q2N_ERR_NOMEM; goto done; }
    q2n_ev_fair_fill_lanes(P->ctx, J, W, &L, tayv);
    q2n_cp_corner_terms(P, &L, W, &C);
    for (int a = 0; a < ng; a++) q2n_cp_line_u(P, &L, W, gx[a], 4, &Lu[a]);
    for (int b = 0; b < ng; b++) q2n_cp_line_v(P, &L, W, gx[b], 4, &Lv[b]);
    free(tayv);
    q2n_cp_grid(P, &C, bl, W, ng, gx, Lu, ng, gx, Lv, 3, 9, G);
    for (int t = 0; t < 2 && !st; t++) {
        int r0 = t ? 3 : 0, nr = t ? 4 : 3, nrow = 0;
        size_t nk = (size_t)(nl ? nl : 1) * (nl ? nl : 1), nrr = (size_t)(nl ? nl : 1) * 3;
        F->K[t] = q2n_dense_alloc(nk);
        F->r[t] = q2n_dense_alloc(nrr);
        if (F->K[t]) memset(F->K[t], 0, nk * sizeof(double));
        if (F->r[t]) memset(F->r[t], 0, nrr * sizeof(double));
        if (!F->K[t] || !F->r[t]) { st = Q2N_ERR_NOMEM; break; }
        F->c[t] = 0;
        for (size_t p = 0; p < np; p++) {
            int a = (int)(p % ng), b = (int)(p / ng);
            double wq = gw[a] * gw[b] * Lc2;
            for (int r = r0; r < r0 + nr; r++) {
                const double *row = G + (p * 7 + r) * W, sq = sqrt(wq) * sc[r];
                for (int i = 0; i < nl; i++) A[(size_t)nrow * nl + i] = sq * row[3 + i];
                for (int c = 0; c < 3; c++) A0[(size_t)nrow * 3 + c] = sq * row[c];
                F->c[t] += sq * sq * q2n_v3_dot(row, row);
                nrow++;
            }
        }
        if (nl > 0) {
            cblas_dsyrk(CblasRowMajor, CblasUpper, CblasTrans, nl, nrow, 1.0, A, nl, 0.0, F->K[t], nl);
            cblas_dgemm(CblasRowMajor, CblasTrans, CblasNoTrans, nl, 3, nrow, -1.0, A, nl, A0, 3, 0.0, F->r[t], 3);
            /* keep the upper triangle only, packed (in place: row i moves to a lower address) */
            for (int i = 0; i < nl; i++) memmove(F->K[t] + pk(nl, i, i), F->K[t] + (size_t)i * nl + i, sizeof(double) * (size_t)(nl - i));
            double *Kp = realloc(F->K[t], sizeof(double) * pk(nl, nl - 1, nl - 1) + sizeof(double));
            if (Kp) F->K[t] = Kp;
        }
    }
done:
    free(Jl);
    free(Lu);
    free(lst);
    free(C.v);
    free(G);
    free(A);
    free(A0);
    if (st) form_free(F);
    return st;
}

/* Faces' forms on worker threads (face fi on thread fi mod nt: the result does not depend on nt). */
typedef struct fe_job {
    const fe_build *B;
    const int *faces;
    int nfaces, t, nt;
    const cp_patch *P;
    fe_form *F;
    q2n_status st;
} fe_job;

static void *form_worker(void *arg)
{
    fe_job *J = arg;
    int ng = J->B->K >= 2 ? EV_FAIR_GAUSS_G2 : EV_FAIR_GAUSS_G1;
    double gx[EV_FAIR_GAUSS_MAX], gw[EV_FAIR_GAUSS_MAX];
    q2n_gauss_legendre01(ng, gx, gw);
    for (int fi = J->t; fi < J->nfaces && !J->st; fi += J->nt)
        J->st = face_form(J->B, fi, J->faces[fi], &J->P[fi], gx, gw, ng, &J->F[fi]);
    return NULL;
}

/* The normal matrix's pattern: the pairs of unknowns some face's forms couple (and every
 * diagonal), upper triangle in compressed columns, and the sparse factorisation object that keeps
 * its analysis for both passes. */
typedef struct fe_sys {
    const int *colptr, *rowind; /* the pattern, held by S */
    q2n_sparse_spd *S;
} fe_sys;

static void sys_free(fe_sys *Y) { q2n_sparse_spd_free(Y->S); }

/* Room for `need` ints in *a (capacity *cap, doubled as it grows); 0 when out of memory. */
static int grow_ints(int **a, size_t *cap, size_t need)
{
    if (need <= *cap) return 1;
    size_t nc = *cap ? 2 * *cap : 1 << 16;
    int *r = realloc(*a, nc * sizeof *r);
    if (!r) return 0;
    *a = r;
    *cap = nc;
    return 1;
}

static q2n_status sys_build(int n, int nfaces, const fe_form *F, fe_sys *Y, q2n_error *err)
{
    memset(Y, 0, sizeof *Y);
    /* faces of each unknown (compressed), then per column the union of their rows <= column */
    int *fstart = calloc((size_t)n + 1, sizeof *fstart), *fl = NULL, *mark = malloc((size_t)(n ? n : 1) * sizeof *mark);
    int *colptr = malloc(((size_t)n + 1) * sizeof *colptr), *rowind = NULL;
    q2n_status st = Q2N_OK;
    size_t cap = 0, nnz = 0;
    if (!fstart || !mark || !colptr) { st = Q2N_ERR_NOMEM; goto done; }
    for (int fi = 0; fi < nfaces; fi++)
        for (int i = 0; i < F[fi].nl; i++) fstart[F[fi].loc[i] + 1]++;
    for (int x = 0; x < n; x++) fstart[x + 1] += fstart[x];
    if (!(fl = malloc(((size_t)fstart[n] + 1) * sizeof *fl))) { st = Q2N_ERR_NOMEM; goto done; }
    for (int fi = 0; fi < nfaces; fi++)
        for (int i = 0; i < F[fi].nl; i++) fl[fstart[F[fi].loc[i]]++] = fi;
    for (int x = n; x > 0; x--) fstart[x] = fstart[x - 1];
    fstart[0] = 0;
    for (int x = 0; x < n; x++) mark[x] = -1;
    for (int j = 0; j < n; j++) {
        size_t c0 = nnz;
        if (!grow_ints(&rowind, &cap, nnz + 1)) { st = Q2N_ERR_NOMEM; goto done; }
        colptr[j] = (int)nnz;
        mark[j] = j;
        rowind[nnz++] = j;
        for (int q = fstart[j]; q < fstart[j + 1]; q++) {
            const fe_form *f = &F[fl[q]];
            int ij = 0;
            while (f->loc[ij] != j) ij++;
            for (int i = 0; i < f->nl; i++) {
                int r = f->loc[i];
                if (r > j || mark[r] == j) continue;
                size_t e = i < ij ? pk(f->nl, i, ij) : pk(f->nl, ij, i);
                if (f->K[0][e] == 0 && f->K[1][e] == 0) continue; /* no coupling in this face */
                mark[r] = j;
                if (!grow_ints(&rowind, &cap, nnz + 1)) { st = Q2N_ERR_NOMEM; goto done; }
                rowind[nnz++] = r;
            }
        }
        qsort(rowind + c0, nnz - c0, sizeof *rowind, cmp_int);
        if (nnz > (size_t)INT_MAX) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "fair solve: %d unknowns give too many matrix entries", n); goto done; }
    }
    colptr[n] = (int)nnz;
    if ((st = q2n_sparse_spd_create(n, colptr, rowind, &Y->S, err)) == Q2N_OK) q2n_sparse_spd_pattern(Y->S, &Y->colptr, &Y->rowind);
done:
    if (st == Q2N_ERR_NOMEM && !Y->S) q2n_error_set(err, st, "out of memory (fair solve, %d unknowns)", n);
    free(fstart);
    free(fl);
    free(mark);
    free(colptr);
    free(rowind);
    if (st) sys_free(Y), memset(Y, 0, sizeof *Y);
    return st;
}

/* Position of entry (r <= c) in the pattern. */
static size_t sys_at(const fe_sys *Y, int r, int c)
{
    int lo = Y->colptr[c], hi = Y->colptr[c + 1] - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (Y->rowind[mid] < r) lo = mid + 1;
        else hi = mid;
    }
    return (size_t)lo;
}

/* The scaled system of fair_pass (values val on Y's pattern, right-hand sides Bm, column-major
 * n x 3) solved with the free jet terms of flat fans kept in their planes: that ties the three
 * coordinates together, so the matrix is expanded to 3n (A (x) I3, interleaved) and each such
 * unknown's 3 x 3 diagonal block gets EV_FLAT_PENALTY n n^T (the scaled diagonal is 1): its part
 * normal to the plane is that much stiffer than the energy.  The solution replaces Bm. */
static q2n_status coupled_solve(const fe_build *B, const fe_sys *Y, const double *val, double *Bm, q2n_error *err)
{
    int n = B->nvar, N = 3 * n;
    long nnz = 3L * Y->colptr[n];
    for (int v = 0; v < B->m->nv; v++)
        if (B->flat[v]) nnz += 6L * EV_JS;
    int *ti = malloc((size_t)nnz * sizeof *ti), *tj = malloc((size_t)nnz * sizeof *tj);
    double *tv = malloc((size_t)nnz * sizeof *tv), *b3 = malloc((size_t)(N ? N : 1) * sizeof *b3);
    q2n_status st = Q2N_OK;
    if (!ti || !tj || !tv || !b3) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair solve, flat fans)"); goto done; }
    long q = 0;
    for (int j = 0; j < n; j++)
        for (int e = Y->colptr[j]; e < Y->colptr[j + 1]; e++)
            for (int c = 0; c < 3; c++) ti[q] = 3 * Y->rowind[e] + c, tj[q] = 3 * j + c, tv[q++] = val[e];
    for (int v = 0; v < B->m->nv; v++) {
        if (!B->flat[v]) continue;
        const double *nv = B->flatn[v];
        for (int k = 0; k < EV_JS; k++) {
            int x = B->var[v * EV_JS + k];
            if (x < 0) continue;
            for (int a = 0; a < 3; a++)
                for (int c = a; c < 3; c++) ti[q] = 3 * x + a, tj[q] = 3 * x + c, tv[q++] = EV_FLAT_PENALTY * nv[a] * nv[c];
        }
    }
    for (int k = 0; k < n; k++)
        for (int c = 0; c < 3; c++) b3[3 * k + c] = Bm[(size_t)c * n + k];
    if ((st = q2n_sparse_spd_solve(N, q, ti, tj, tv, 1, b3, b3, err))) goto done;
    for (int k = 0; k < n; k++)
        for (int c = 0; c < 3; c++) Bm[(size_t)c * n + k] = b3[3 * k + c];
done:
    free(ti);
    free(tj);
    free(tv);
    free(b3);
    return st;
}

/* Sum the forms with weights w_t (per face for the variation term), add the ridge, solve; X holds
 * the solution per unknown (3 per unknown).  The matrix is scaled symmetrically by its diagonal
 * (the unknowns' scales differ by orders of magnitude); each entry is the sum, face by face and the
 * ridge last, of its scaled contributions. */
static q2n_status fair_pass(const fe_build *B, fe_sys *Y, int nfaces, const fe_form *F, const double *omega, double w3,
                            const double *x0, double *X, q2n_error *err)
{
    int n = B->nvar;
    double *rhs = calloc(3 * (size_t)n, sizeof *rhs), *diag = calloc((size_t)n, sizeof *diag), *Bm = NULL, *dg = NULL;
    double *lam = malloc((size_t)(n ? n : 1) * sizeof *lam);
    double *val = q2n_sparse_spd_values(Y->S);
    q2n_status st = Q2N_OK;
    if (!rhs || !diag || !lam) { st = Q2N_ERR_NOMEM; goto done; }
    /* right-hand sides and the diagonal (which sets the ridge) */
    for (int fi = 0; fi < nfaces; fi++) {
        const fe_form *f = &F[fi];
        double w[2] = {1, w3 * (omega ? omega[fi] : 1)};
        for (int i = 0; i < f->nl; i++) {
            int gi = f->loc[i];
            for (int t = 0; t < 2; t++) {
                if (w[t] == 0) continue;
                for (int c = 0; c < 3; c++) rhs[3 * gi + c] += w[t] * f->r[t][3 * i + c];
            }
            diag[gi] += form_at(f, pk(f->nl, i, i), w[1]);
        }
    }
    /* ridge towards x0: jets' first and second orders firmer than the rest */
    dg = malloc((size_t)(n ? n : 1) * sizeof *dg);
    Bm = malloc(3 * (size_t)(n ? n : 1) * sizeof *Bm);
    if (!dg || !Bm) { st = Q2N_ERR_NOMEM; goto done; }
    for (int x = 0; x < n; x++) {
        lam[x] = (B->ridge[x] == RIDGE_HELD     ? EV_FOLD_HOLD
                  : B->ridge[x] == RIDGE_CORNER ? EV_FAIR_RIDGE_CORNER
                  : B->ridge[x] == RIDGE_LOW    ? EV_FAIR_RIDGE_LOW
                                                : EV_FAIR_RIDGE_HIGH) * diag[x];
        if (!(lam[x] > 0)) lam[x] = 1;
        for (int c = 0; c < 3; c++) rhs[3 * x + c] += lam[x] * x0[3 * x + c];
        double d = diag[x] + lam[x];
        dg[x] = d > 0 ? 1 / sqrt(d) : 1;
    }
    /* scaled entries */
    memset(val, 0, sizeof(double) * (size_t)Y->colptr[n]);
    for (int fi = 0; fi < nfaces; fi++) {
        const fe_form *f = &F[fi];
        double w1 = w3 * (omega ? omega[fi] : 1);
        for (int i = 0; i < f->nl; i++) {
            int gi = f->loc[i];
            for (int k = i; k < f->nl; k++) {
                double v = form_at(f, pk(f->nl, i, k), w1);
                if (v == 0) continue;
                int gk = f->loc[k], r = gi < gk ? gi : gk, c = gi < gk ? gk : gi;
                val[sys_at(Y, r, c)] += v * (dg[r] * dg[c]);
            }
        }
    }
    for (int x = 0; x < n; x++) val[Y->colptr[x + 1] - 1] += lam[x] * (dg[x] * dg[x]); /* the diagonal ends its column */
    for (int k = 0; k < n; k++)
        for (int c = 0; c < 3; c++) Bm[(size_t)c * n + k] = rhs[3 * k + c] * dg[k];
    if (B->flat) st = coupled_solve(B, Y, val, Bm, err);
    else st = q2n_sparse_spd_factor_solve(Y->S, 3, Bm, Bm, err);
    if (st) goto done;
    for (int k = 0; k < n; k++)
        for (int c = 0; c < 3; c++) X[3 * k + c] = Bm[(size_t)c * n + k] * dg[k];
done:
    if (st == Q2N_ERR_NOMEM) q2n_error_set(err, st, "out of memory (fair solve, %d unknowns)", n);
    free(rhs);
    free(diag);
    free(lam);
    free(Bm);
    free(dg);
    return st;
}

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}


/* The unnormalised normals S_u x S_v of patch i (context FX) on the EV_FOLD_GRID x EV_FOLD_GRID grid
 * of [0,1]^2 (row-major in v); 0 when it cannot be evaluated. */
static int grid_normals(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P,
                        double nrm[EV_FOLD_GRID * EV_FOLD_GRID][3])
{
    enum { NG = EV_FOLD_GRID };
    double t[NG], out[NG * NG * 9];
    for (int a = 0; a < NG; a++) t[a] = (double)a / (NG - 1);
    fe_eval *E = q2n_ev_fair_make_eval(B, i, f, FX, P);
    if (!E) return 0;
    q2n_status st = q2n_cp_eval_grid(E, NG, t, NG, t, out);
    free(E);
    if (st) return 0;
    for (int q = 0; q < NG * NG; q++) q2n_v3_cross(nrm[q], out + 9 * q + 3, out + 9 * q + 6);
    return 1;
}

/* Does patch i fold: do the normals of two neighbouring points of an EV_FOLD_GRID grid point
 * away from each other?  A smooth patch turns them by a small angle per grid step; a fold turns
 * them over.  -1 when it cannot be evaluated. */
static int patch_folds(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P)
{
    enum { NG = EV_FOLD_GRID };
    double nrm[NG * NG][3];
    if (!grid_normals(B, i, f, FX, P, nrm)) return -1;
    for (int b = 0; b < NG; b++)
        for (int a = 0; a < NG; a++) {
            const double *n0 = nrm[b * NG + a];
            if ((a + 1 < NG && q2n_v3_dot(n0, nrm[b * NG + a + 1]) < 0) || (b + 1 < NG && q2n_v3_dot(n0, nrm[(b + 1) * NG + a]) < 0))
                return 1;
        }
    return 0;
}

/* Smallest |S_u x S_v| over an EV_FOLD_GRID grid of patch i (context FX), relative to its median there:
 * 1 for a parallelogram, near 0 where the face nearly folds or degenerates.  -1 when it cannot be
 * evaluated. */
double q2n_ev_fair_jacobian_ratio(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P)
{
    enum { NG = EV_FOLD_GRID };
    double nrm[NG * NG][3], srt[NG * NG];
    if (!grid_normals(B, i, f, FX, P, nrm)) return -1;
    for (int q = 0; q < NG * NG; q++) srt[q] = q2n_v3_norm(nrm[q]);
    qsort(srt, NG * NG, sizeof *srt, cmp_dbl);
    double med = srt[NG * NG / 2], mn = srt[0];
    return med > 0 ? mn / med : 0;
}

/* The jets and bubbles of solution X. */
static void put_solution(fe_build *B, int nfaces, const double *X)
{
    for (int v = 0; v < B->m->nv; v++)
        for (int k = 0; k < EV_JS; k++) {
            int x = B->var[v * EV_JS + k];
            if (x >= 0) memcpy(B->jet[v][k], X + 3 * x, 3 * sizeof(double));
        }
    for (int fi = 0; fi < nfaces; fi++)
        for (int b = 0; b < CP_NBUB; b++) memcpy(B->bub[fi][b], X + 3 * (B->bvar[fi] + b), 3 * sizeof(double));
}

typedef struct reg_val {
    int root;
    double v;
} reg_val;

static int cmp_reg_val(const void *a, const void *b)
{
    const reg_val *x = a, *y = b;
    return x->root != y->root ? (x->root < y->root ? -1 : 1) : (x->v < y->v ? -1 : x->v > y->v ? 1 : 0);
}

/* Per region of the listed faces (fe_build.region), the median of the values v: med[fi] for each face;
 * 0, -1 out of memory. */
static int region_medians(const fe_build *B, const int *faces, int nfaces, const double *v, double *med)
{
    const q2n_mesh *m = B->m;
    const int *root = B->region;
    int *mid = malloc(sizeof(int) * (size_t)(m->nv > 0 ? m->nv : 1));
    reg_val *rv = malloc(sizeof(reg_val) * (size_t)(nfaces > 0 ? nfaces : 1));
    if (!mid || !rv) { free(mid), free(rv); return -1; }
    for (int fi = 0; fi < nfaces; fi++) rv[fi] = (reg_val){root[m->face_vert[m->face_start[faces[fi]]]], v[fi]};
    qsort(rv, (size_t)nfaces, sizeof *rv, cmp_reg_val);
    for (int a = 0, b; a < nfaces; a = b) {
        for (b = a; b < nfaces && rv[b].root == rv[a].root; b++) {}
        mid[rv[a].root] = a + (b - a) / 2; /* the region's median, by its root */
    }
    for (int fi = 0; fi < nfaces; fi++) med[fi] = rv[mid[root[m->face_vert[m->face_start[faces[fi]]]]]].v;
    free(mid), free(rv);
    return 0;
}

/* A bending-only pass, the variation weights ω_F from its result, then the full pass (X: the
 * solution; v3, med: nfaces doubles of work space, med for each face its region's median variation). */
static q2n_status energy_passes(const fe_build *B, fe_sys *Y, const int *faces, int nfaces, const fe_form *F, double *v3, double *med,
                                const double *x0, double *X, q2n_error *err)
{
    q2n_status st = fair_pass(B, Y, nfaces, F, NULL, 0, x0, X, err);
    if (st || !(EV_FAIR_W3 > 0)) return st;
    for (int fi = 0; fi < nfaces; fi++) { /* variation left by the bending-only pass */
        const fe_form *f = &F[fi];
        double e = f->c[1];
        for (int i = 0; i < f->nl; i++) {
            const double *xi = X + 3 * f->loc[i];
            e -= 2 * q2n_v3_dot(xi, f->r[1] + 3 * i);
            for (int k = i; k < f->nl; k++)
                e += (k == i ? 1 : 2) * f->K[1][pk(f->nl, i, k)] * q2n_v3_dot(xi, X + 3 * f->loc[k]);
        }
        v3[fi] = e;
    }
    if (region_medians(B, faces, nfaces, v3, med)) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair solve)");
    for (int fi = 0; fi < nfaces; fi++) {
        double cap = EV_FAIR_VAR_OUTLIER * med[fi];
        v3[fi] = cap > 0 && v3[fi] > cap ? cap / v3[fi] : 1;
    }
    return fair_pass(B, Y, nfaces, F, v3, EV_FAIR_W3, x0, X, err);
}

typedef struct fold_arg {
    const fe_build *B;
    const int *faces;
    const cp_patch *P;
    const fe_ctx *FX;
    signed char *r;   /* per face of the list: patch_folds */
} fold_arg;

static void fold_one(void *arg, int fi)
{
    fold_arg *a = arg;
    a->r[fi] = (signed char)patch_folds(a->B, fi, a->faces[fi], &a->FX[fi], &a->P[fi]);
}

/* The faces of the list whose patches fold in the current solution (patch_folds, on `threads`
 * workers): r[i] 1 or 0 per face of the list; the number folded, -1 when one cannot be evaluated
 * or out of memory. */
int q2n_ev_fair_folded(const fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX, int threads,
                       signed char *r)
{
    fold_arg a = {B, faces, P, FX, r};
    q2n_par_for(nfaces, threads, fold_one, &a);
    int folded = 0;
    for (int fi = 0; fi < nfaces; fi++) {
        if (r[fi] < 0) return -1;
        folded += r[fi];
    }
    return folded;
}

/* The folded faces of the current solution (q2n_ev_fair_folded); the corners of each that are not
 * held yet are held from now on (their jets of orders 1 and 2 get the EV_FOLD_HOLD ridge), counted
 * in *held_vertices.  Returns the number of folded faces, -1 out of memory. */
static int fold_scan(fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX, int threads,
                     char *held, int *held_vertices)
{
    const q2n_mesh *m = B->m;
    signed char *r = malloc((size_t)(nfaces ? nfaces : 1));
    if (!r) return -1;
    int folded = q2n_ev_fair_folded(B, faces, nfaces, P, FX, threads, r);
    for (int fi = 0; fi < nfaces && folded > 0; fi++) {
        if (!r[fi]) continue;
        for (int c = 0; c < 4; c++) {
            int v = m->face_vert[m->face_start[faces[fi]] + c];
            if (held[v]) continue;
            held[v] = 1;
            ++*held_vertices;
            for (int k = EV_SLOT(1, 0); k <= EV_SLOT(2, 2); k++)
                if (B->var[v * EV_JS + k] >= 0) B->ridge[B->var[v * EV_JS + k]] = RIDGE_HELD;
        }
    }
    free(r);
    return folded;
}

/* What the solve and the fold guard share: the system, the forms, the faces and their patches,
 * work space, and the vertices held so far. */
typedef struct fe_solve {
    fe_build *B;
    fe_sys *Y;
    const fe_form *F;
    const int *faces;
    int nfaces;
    const cp_patch *P;
    const fe_ctx *FX;
    int threads;
    double *v3, *med; /* nfaces doubles each (energy_passes) */
    char *held;       /* per vertex: its jets held by the guard */
    int nheld;        /* vertices held so far */
} fe_solve;

/* energy_passes towards x0, the jets and bubbles from the solution X, then fold_scan (holding the
 * corners of faces that fold); *folded: their number. */
static q2n_status solve_scan(fe_solve *S, const double *x0, double *X, int *folded, q2n_error *err)
{
    q2n_status st = energy_passes(S->B, S->Y, S->faces, S->nfaces, S->F, S->v3, S->med, x0, X, err);
    if (st) return st;
    put_solution(S->B, S->nfaces, X);
    *folded = fold_scan(S->B, S->faces, S->nfaces, S->P, S->FX, S->threads, S->held, &S->nheld);
    return *folded < 0 ? q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fold check)") : Q2N_OK;
}

/* The fold guard's second stage, where holding the local estimates left folds (*folds_left > 0,
 * the kept solution Xkept in B): at a tip sharper than the estimates can turn, their tangents are
 * too long for the turn the tip faces must make within their first quads.  The held jets are
 * shrunk toward the vertex (order 1 by EV_FOLD_SHRINK, order 2 by its square, orders 3 and 4 held
 * at zero) and the passes repeated, up to EV_FOLD_SHRINKS times, each shrinking once more and
 * holding the corners of faces newly folded; the solution with the fewest folded faces is kept,
 * Xkept when none has fewer (then *held_vertices stays).  *shrinks: the halvings of the kept
 * solution. */
static q2n_status shrink_stage(fe_solve *S, const double *x0, const double *Xkept, int *held_vertices, int *folds_left,
                               int *shrinks, q2n_error *err)
{
    fe_build *B = S->B;
    size_t n3 = 3 * (size_t)B->nvar;
    double *xs = malloc(n3 * sizeof *xs), *X = malloc(n3 * sizeof *X), *Xb = malloc(n3 * sizeof *Xb);
    q2n_status st = Q2N_OK;
    int best = *folds_left, kept = 0;
    if (!xs || !X || !Xb) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fold guard)"); goto done; }
    double f1 = 1;
    for (int k = 1; k <= EV_FOLD_SHRINKS && best > 0; k++) {
        f1 *= EV_FOLD_SHRINK;
        memcpy(xs, x0, n3 * sizeof *xs);
        for (int v = 0; v < B->m->nv; v++) {
            if (!S->held[v]) continue;
            for (int j = EV_SLOT(1, 0); j < EV_JS; j++) {
                int x = B->var[v * EV_JS + j];
                if (x < 0) continue;
                double f = j <= EV_SLOT(1, 1) ? f1 : j <= EV_SLOT(2, 2) ? f1 * f1 : 0;
                for (int c = 0; c < 3; c++) xs[3 * x + c] *= f;
                B->ridge[x] = RIDGE_HELD;
            }
        }
        int folded;
        if ((st = solve_scan(S, xs, X, &folded, err))) goto done;
        if (folded < best) {
            best = folded;
            kept = k;
            memcpy(Xb, X, n3 * sizeof *Xb);
            *held_vertices = S->nheld;
        }
    }
    put_solution(B, S->nfaces, kept ? Xb : Xkept);
    *folds_left = best;
    *shrinks = kept;
done:
    free(xs);
    free(X);
    free(Xb);
    return st;
}

/* The energy solve: the faces' forms (once, on worker threads), then energy_passes; the jets and
 * bubbles get the solution.  Fold guard: the energy is parametric, and where the data force a face
 * to turn fast (a spike's tip) its minimiser can fold the face over; the jets of order <= 2 at the
 * corners of every folded face are then held at their local estimates (a ridge of EV_FOLD_HOLD)
 * and the passes repeated, at most EV_FOLD_PASSES times, growing the held set; when that does not
 * lower the number of folded faces, the first solution stays.  Where folds are left, shrink_stage
 * tries shorter held jets.  Meshes without a fold are solved once, as before; *held_vertices,
 * *folds_left and *shrinks describe the result. */
q2n_status q2n_ev_fair_solve(fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX,
                             int threads, int *held_vertices, int *folds_left, int *shrinks, q2n_error *err)
{
    const q2n_mesh *m = B->m;
    int n = B->nvar, nt = threads < 1 ? 1 : threads > nfaces ? (nfaces > 0 ? nfaces : 1) : threads;
    if (nt > Q2N_EV_MAX_THREADS) nt = Q2N_EV_MAX_THREADS;
    q2n_status st = Q2N_OK;
    *held_vertices = *folds_left = *shrinks = 0;
    if (nfaces <= 0 || n <= 0) return Q2N_OK;
    fe_sys Y = {0};
    fe_form *F = calloc((size_t)nfaces, sizeof *F);
    fe_job *jobs = calloc((size_t)nt, sizeof *jobs);
    pthread_t *tid = calloc((size_t)nt, sizeof *tid);
    double *x0 = calloc(3 * (size_t)n, sizeof *x0), *X = calloc(3 * (size_t)n, sizeof *X);
    double *X0 = malloc(3 * (size_t)n * sizeof *X0);
    double *v3 = malloc((size_t)nfaces * sizeof *v3), *med = malloc((size_t)nfaces * sizeof *med);
    char *held = calloc((size_t)m->nv, 1);
    int folds0 = 0;
    if (!F || !jobs || !tid || !x0 || !X || !X0 || !v3 || !med || !held) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair solve)"); goto done; }
    for (int t = 0; t < nt; t++) {
        jobs[t] = (fe_job){B, faces, nfaces, t, nt, P, F, Q2N_OK};
        if (t > 0 && pthread_create(&tid[t], NULL, form_worker, &jobs[t])) jobs[t].st = Q2N_ERR_NOMEM, tid[t] = 0;
    }
    form_worker(&jobs[0]);
    for (int t = 1; t < nt; t++)
        if (tid[t]) pthread_join(tid[t], NULL);
    for (int t = 0; t < nt && !st; t++)
        if (jobs[t].st) st = q2n_error_set(err, jobs[t].st, "out of memory (fair energy forms)");
    if (st) goto done;
    if ((st = sys_build(n, nfaces, F, &Y, err))) goto done;
    /* x0: the current values (local estimates for the jets, zero bubbles) */
    for (int v = 0; v < m->nv; v++)
        for (int k = 0; k < EV_JS; k++) {
            int x = B->var[v * EV_JS + k];
            if (x >= 0) memcpy(x0 + 3 * x, B->jet[v][k], 3 * sizeof(double));
        }
    fe_solve S = {B, &Y, F, faces, nfaces, P, FX, threads, v3, med, held, 0};
    for (int pass = 0;; pass++) {
        int held_before = S.nheld, folded;
        if ((st = solve_scan(&S, x0, X, &folded, err))) goto done;
        if (pass == 0) {
            folds0 = folded;
            if (folded) memcpy(X0, X, 3 * (size_t)n * sizeof *X);
        }
        if (folded && S.nheld > held_before && pass < EV_FOLD_PASSES) continue;
        const double *Xkept = X;
        *folds_left = folded;
        *held_vertices = S.nheld;
        if (pass > 0 && folded >= folds0) { /* the guard did not help: the energy's own solution */
            Xkept = X0;
            put_solution(B, nfaces, X0);
            *folds_left = folds0;
            *held_vertices = 0;
        }
        if (*folds_left > 0 && S.nheld > 0) st = shrink_stage(&S, x0, Xkept, held_vertices, folds_left, shrinks, err);
        break;
    }
done:
    sys_free(&Y);
    free(held);
    free(X0);
    if (F)
        for (int fi = 0; fi < nfaces; fi++) form_free(&F[fi]);
    free(F);
    free(jobs);
    free(tid);
    free(x0);
    free(X);
    free(v3);
    free(med);
    return st;
}
