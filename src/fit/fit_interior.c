/* fit_interior.c — stage 6 of a round: the control points of each dirty patch that the edge curves,
 * corner jets and cross rows left free, by least squares on the patch's sample grid.
 *
 * The free points usually form a tensor block [lu..hu] x [lv..hv] and the samples a tensor grid, so
 * min |Bu X Bv^T - R| (R: the samples less the fixed points' part) has the solution
 * X = Au^+ R Av^+T, A^+ = (A^T A)^-1 A^T the pseudo-inverse of the rows of the basis matrix that reach
 * the free block, restricted to its columns: every sample column shares one v matrix and every
 * control column one u matrix.  So each distinct matrix is solved once — a Ceres least-squares solve
 * of A x = e_j for every unit right-hand side e_j gives A^+ column by column (fit_ls.c; three columns
 * per item, one per coordinate) — and kept for the later rounds (the pseudo-inverse cache: patches on
 * the same knots in a direction share an entry, and a patch refitted only because a neighbour changed
 * solves nothing); the patches then take two small matrix products.  A free set that is not a tensor
 * block (rare) is one least-squares item over all its points and samples. */
#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/clock.h"
#include "core/vec3.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ the pseudo-inverse cache */

static uint64_t pinv_hash(int m, int n, const double *A)
{
    uint64_t h = 1469598103934665603ull;   /* FNV-1a over the dimensions and the bytes of A */
    const unsigned char *b = (const unsigned char *)A;
    int dims[2] = {m, n};
    const unsigned char *d = (const unsigned char *)dims;
    for (size_t i = 0; i < sizeof dims; i++) h = (h ^ d[i]) * 1099511628211ull;
    for (size_t i = 0; i < (size_t)m * n * sizeof(double); i++) h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* Rebuild the hash chains (nbucket a power of two, at least the entries). */
static int pinv_rehash(fit_pinv_cache *pc, int nbucket)
{
    int *b = malloc(sizeof(int) * (size_t)nbucket);
    if (!b) return 0;
    for (int i = 0; i < nbucket; i++) b[i] = -1;
    for (int i = 0; i < pc->n; i++) {
        int s = (int)(pc->v[i].h & (uint64_t)(nbucket - 1));
        pc->v[i].next = b[s];
        b[s] = i;
    }
    free(pc->bucket);
    pc->bucket = b;
    pc->nbucket = nbucket;
    return 1;
}

/* The entry of matrix A (m x n, row-major), added without its pseudo-inverse (P NULL) when new;
 * -1 when out of memory.  A is copied. */
static int pinv_find_add(fit_pinv_cache *pc, int m, int n, const double *A)
{
    uint64_t h = pinv_hash(m, n, A);
    size_t bytes = (size_t)m * n * sizeof(double);
    if (pc->nbucket)
        for (int i = pc->bucket[h & (uint64_t)(pc->nbucket - 1)]; i >= 0; i = pc->v[i].next)
            if (pc->v[i].h == h && pc->v[i].m == m && pc->v[i].n == n && !memcmp(pc->v[i].A, A, bytes)) return i;
    if (pc->n == pc->cap) {
        int nc = pc->cap ? 2 * pc->cap : 64;
        fit_pinv *v = realloc(pc->v, sizeof *v * (size_t)nc);
        if (!v) return -1;
        pc->v = v;
        pc->cap = nc;
    }
    fit_pinv *e = &pc->v[pc->n];
    memset(e, 0, sizeof *e);
    e->h = h;
    e->m = m;
    e->n = n;
    e->A = malloc(bytes);
    if (!e->A) return -1;
    memcpy(e->A, A, bytes);
    pc->n++;
    if (pc->n > pc->nbucket) {
        if (!pinv_rehash(pc, pc->nbucket ? 2 * pc->nbucket : 64)) { pc->n--; free(e->A); return -1; }
    } else {
        int s = (int)(h & (uint64_t)(pc->nbucket - 1));
        e->next = pc->bucket[s];
        pc->bucket[s] = pc->n - 1;
    }
    return pc->n - 1;
}

/* Drop the entries not kept for later rounds (those beyond the budget). */
static void pinv_drop_transient(fit_pinv_cache *pc)
{
    int n = 0;
    for (int i = 0; i < pc->n; i++) {
        if (pc->v[i].keep) { pc->v[n++] = pc->v[i]; continue; }
        free(pc->v[i].A); free(pc->v[i].P);
    }
    if (n == pc->n) return;
    pc->n = n;
    if (!pinv_rehash(pc, pc->nbucket)) {   /* out of memory: forget every entry (the chains are stale) */
        for (int i = 0; i < pc->n; i++) { free(pc->v[i].A); free(pc->v[i].P); }
        for (int i = 0; i < pc->nbucket; i++) pc->bucket[i] = -1;
        pc->n = 0;
        pc->bytes = 0;
    }
}

void q2n_fit_pinv_free(fit_pinv_cache *pc)
{
    long budget = pc->budget;
    for (int i = 0; i < pc->n; i++) { free(pc->v[i].A); free(pc->v[i].P); }
    free(pc->v); free(pc->bucket);
    memset(pc, 0, sizeof *pc);
    pc->budget = budget;
}

/* Pseudo-inverses of the entries from `from` on (those new in this stage): A x = e_j for every unit
 * right-hand side, three per least-squares item (one per coordinate), all in one solve. */
static q2n_status pinv_solve(fit_ctx *c, int from)
{
    fit_pinv_cache *pc = &c->pinv;
    if (from >= pc->n) return Q2N_OK;
    int nitem = 0, mmax = 0;
    for (int i = from; i < pc->n; i++) {
        nitem += (pc->v[i].m + 2) / 3;
        if (pc->v[i].m > mmax) mmax = pc->v[i].m;
    }
    int *var0 = malloc(sizeof(int) * (size_t)nitem);
    double *rhs = calloc(3 * (size_t)mmax, sizeof(double));
    q2n_status st = Q2N_OK;
    if (!var0 || !rhs) { st = Q2N_ERR_NOMEM; goto out; }
    q2n_fit_ls_clear(&c->ls);
    int it = 0;
    for (int i = from; i < pc->n && !st; i++) {
        fit_pinv *e = &pc->v[i];
        for (int q = 0; 3 * q < e->m && !st; q++, it++) {
            for (int d = 0; d < 3 && 3 * q + d < e->m; d++) rhs[3 * (size_t)(3 * q + d) + d] = 1.0;
            if (q2n_fit_ls_dense_item(&c->ls, e->m, e->n, e->A, rhs, &var0[it])) st = Q2N_ERR_NOMEM;
            for (int d = 0; d < 3 && 3 * q + d < e->m; d++) rhs[3 * (size_t)(3 * q + d) + d] = 0.0;
        }
    }
    if (st) goto out;
    double t1 = q2n_now();
    st = q2n_fit_ls_solve(&c->ls, c->o.solver, c->o.threads, c->err);
    c->rep->t_solve += q2n_now() - t1;
    if (st) goto out;
    it = 0;
    for (int i = from; i < pc->n && !st; i++) {
        fit_pinv *e = &pc->v[i];
        e->P = malloc(sizeof(double) * (size_t)e->m * e->n);
        if (!e->P) { st = Q2N_ERR_NOMEM; break; }
        for (int q = 0; 3 * q < e->m; q++, it++)
            for (int d = 0; d < 3 && 3 * q + d < e->m; d++)
                for (int b = 0; b < e->n; b++) e->P[(size_t)b * e->m + 3 * q + d] = c->ls.x[3 * (size_t)(var0[it] + b) + d];
        long add = (long)(2 * sizeof(double)) * e->m * e->n;
        if (pc->bytes + add <= pc->budget) {
            e->keep = 1;
            pc->bytes += add;
        }
    }
out:
    q2n_fit_ls_clear(&c->ls);
    free(var0); free(rhs);
    if (st == Q2N_ERR_NOMEM) return q2n_error_set(c->err, st, "fit: out of memory (interior)");
    return st;
}

/* ------------------------------------------------------------------ patches */

/* The free control points of patch k when they form a tensor block [lu..hu] x [lv..hv]; 0 otherwise. */
static int free_block(const fit_patch *p, int *lu, int *hu, int *lv, int *hv)
{
    *lu = p->nu; *hu = -1; *lv = p->nv; *hv = -1;
    for (int b = 0; b < p->nv; b++)
        for (int a = 0; a < p->nu; a++)
            if (!p->fixed[b * p->nu + a]) {
                if (a < *lu) *lu = a;
                if (a > *hu) *hu = a;
                if (b < *lv) *lv = b;
                if (b > *hv) *hv = b;
            }
    for (int b = 0; b < p->nv; b++)
        for (int a = 0; a < p->nu; a++) {
            int in = a >= *lu && a <= *hu && b >= *lv && b <= *hv;
            if (in == p->fixed[b * p->nu + a]) return 0;
        }
    return 1;
}

/* Per-patch data of the interior solve. */
typedef struct sep_patch {
    int k, lu, hu, lv, hv, Nu, Nv, tensor;
    double *R;       /* Nu*Nv*3: samples minus the fixed control points' contribution */
    double *Bu, *Bv; /* Nu x nu and Nv x nv basis matrices (row-major) */
    int *rows1;      /* the m1 sample rows j (v) whose basis reaches the free rows lv..hv */
    int *rows2;      /* the m2 sample columns i (u) whose basis reaches the free columns lu..hu */
    int m1, m2;
    double *A1, *A2; /* m1 x (hv-lv+1) and m2 x (hu-lu+1): those rows of Bv and Bu, the free columns */
    int id1, id2;    /* their entries in the pseudo-inverse cache */
    int var0;        /* a non-tensor free set: its first unknown in the least-squares item, or -1 */
    long evals;
    q2n_status st;
} sep_patch;

static void sep_free(sep_patch *sp, int n)
{
    for (int i = 0; sp && i < n; i++) {
        free(sp[i].R); free(sp[i].Bu); free(sp[i].Bv); free(sp[i].rows1); free(sp[i].rows2); free(sp[i].A1); free(sp[i].A2);
    }
    free(sp);
}

/* The rows of the N x stride basis matrix B that reach its columns lo .. lo + n - 1, restricted to
 * them, into A (row-major, n per row), their indices into rows; returns their number. */
static int reach_rows(int N, const double *B, int stride, int lo, int n, double *A, int *rows)
{
    int m = 0;
    for (int j = 0; j < N; j++) {
        const double *w = B + (size_t)j * stride + lo;
        int any = 0;
        for (int b = 0; b < n; b++) any |= w[b] != 0.0;
        if (!any) continue;
        memcpy(A + (size_t)m * n, w, sizeof(double) * (size_t)n);
        rows[m++] = j;
    }
    return m;
}

/* The two matrices of a tensor block: the sample rows j whose v basis reaches the free rows lv..hv
 * with those columns of Bv (A1), the sample columns i whose u basis reaches lu..hu with those
 * columns of Bu (A2). */
static q2n_status sep_blocks(sep_patch *sp, const fit_patch *p)
{
    int n1 = sp->hv - sp->lv + 1, n2 = sp->hu - sp->lu + 1;
    sp->rows1 = malloc(sizeof(int) * (size_t)sp->Nv);
    sp->rows2 = malloc(sizeof(int) * (size_t)sp->Nu);
    sp->A1 = malloc(sizeof(double) * (size_t)sp->Nv * n1);
    sp->A2 = malloc(sizeof(double) * (size_t)sp->Nu * n2);
    if (!sp->rows1 || !sp->rows2 || !sp->A1 || !sp->A2) return Q2N_ERR_NOMEM;
    sp->m1 = reach_rows(sp->Nv, sp->Bv, p->nv, sp->lv, n1, sp->A1, sp->rows1);
    sp->m2 = reach_rows(sp->Nu, sp->Bu, p->nu, sp->lu, n2, sp->A2, sp->rows2);
    return Q2N_OK;
}

/* Sample patch k (through its cache), build its basis matrices and the residual R of the fixed
 * control points. */
static q2n_status sep_prepare(fit_ctx *c, sep_patch *sp)
{
    fit_patch *p = &c->p[sp->k];
    int cu = (p->nu - 5) * Q2N_FIT_SAMPLES_PER_SPAN + 1, cv = (p->nv - 5) * Q2N_FIT_SAMPLES_PER_SPAN + 1;
    double *us = malloc(sizeof(double) * (size_t)cu), *vs = malloc(sizeof(double) * (size_t)cv);
    double *S = malloc(3 * sizeof(double) * (size_t)cu * cv);
    sp->R = malloc(3 * sizeof(double) * (size_t)cu * cv);
    sp->Bu = calloc((size_t)cu * p->nu, sizeof(double));
    sp->Bv = calloc((size_t)cv * p->nv, sizeof(double));
    if (!us || !vs || !S || !sp->R || !sp->Bu || !sp->Bv) {
        free(us); free(vs); free(S);
        return Q2N_ERR_NOMEM;
    }
    int Nu = sp->Nu = q2n_fit_sample_params(p->nu, p->ku, Q2N_FIT_SAMPLES_PER_SPAN, us);
    int Nv = sp->Nv = q2n_fit_sample_params(p->nv, p->kv, Q2N_FIT_SAMPLES_PER_SPAN, vs);
    q2n_status st = q2n_fit_patch_grid(c, sp->k, Nu, us, Nv, vs, S, &sp->evals);
    if (st) { free(us); free(vs); free(S); return st; }
    double B[3][Q2N_FIT_DEG + 1];
    /* first control index of each sample's support (Q2N_FIT_DEG + 1 basis functions from there) */
    int *a0 = malloc(sizeof(int) * (size_t)(Nu + Nv)), *b0 = a0 ? a0 + Nu : NULL;
    if (!a0) { free(us); free(vs); free(S); return Q2N_ERR_NOMEM; }
    for (int i = 0; i < Nu; i++) {
        int su = q2n_fit_span(p->nu, p->ku, us[i]);
        q2n_fit_basis(su, p->ku, us[i], 0, B);
        a0[i] = su - Q2N_FIT_DEG;
        for (int a = 0; a <= Q2N_FIT_DEG; a++) sp->Bu[(size_t)i * p->nu + su - Q2N_FIT_DEG + a] = B[0][a];
    }
    for (int j = 0; j < Nv; j++) {
        int sv = q2n_fit_span(p->nv, p->kv, vs[j]);
        q2n_fit_basis(sv, p->kv, vs[j], 0, B);
        b0[j] = sv - Q2N_FIT_DEG;
        for (int b = 0; b <= Q2N_FIT_DEG; b++) sp->Bv[(size_t)j * p->nv + sv - Q2N_FIT_DEG + b] = B[0][b];
    }
    /* R = S - (the fixed control points' part), separably: T[b][i], control row b's fixed points
     * summed with sample column i's u-basis (its support only, stepping over a tensor block's free
     * points, none of which is fixed), then each sample's v-sum of the six rows it reaches */
    double *T = calloc(3 * (size_t)p->nv * Nu, sizeof(double));
    if (!T) { free(a0); free(us); free(vs); free(S); return Q2N_ERR_NOMEM; }
    for (int b = 0; b < p->nv; b++) {
        int free_row = sp->tensor && b >= sp->lv && b <= sp->hv;
        for (int i = 0; i < Nu; i++) {
            double *t = T + 3 * ((size_t)b * Nu + i);
            for (int a = a0[i]; a <= a0[i] + Q2N_FIT_DEG; a++) {
                if (free_row && a >= sp->lu && a <= sp->hu) {
                    a = sp->hu;
                    continue;
                }
                if (p->fixed[b * p->nu + a]) q2n_v3_axpy(t, sp->Bu[(size_t)i * p->nu + a], p->cp + 3 * ((size_t)b * p->nu + a));
            }
        }
    }
    for (int j = 0; j < Nv; j++)
        for (int i = 0; i < Nu; i++) {
            double *r = sp->R + 3 * ((size_t)j * Nu + i);
            memcpy(r, S + 3 * ((size_t)j * Nu + i), 3 * sizeof(double));
            for (int b = b0[j]; b <= b0[j] + Q2N_FIT_DEG; b++) {
                double wv = sp->Bv[(size_t)j * p->nv + b];
                if (wv != 0.0) q2n_v3_axpy(r, -wv, T + 3 * ((size_t)b * Nu + i));
            }
        }
    free(T);
    free(a0); free(us); free(vs); free(S);
    return sp->tensor ? sep_blocks(sp, p) : Q2N_OK;
}

typedef struct sep_arg {
    fit_ctx *c;
    sep_patch *sp;
} sep_arg;

static void sep_one(void *arg, int l)
{
    sep_arg *a = arg;
    a->sp[l].st = sep_prepare(a->c, &a->sp[l]);
}

/* A non-tensor free set (rare): one block over every free point, rows = all samples. */
static q2n_status general_item(fit_ctx *c, sep_patch *q)
{
    fit_patch *p = &c->p[q->k];
    int n = 0;
    for (int g = 0; g < p->nu * p->nv; g++)
        if (!p->fixed[g]) p->var[g] = n++;
    q->var0 = -1;
    if (!n) return Q2N_OK;
    if (q2n_fit_ls_item_begin(&c->ls)) return Q2N_ERR_NOMEM;
    q->var0 = c->ls.nvar;
    for (int j = 0; j < n; j++) { int id; q2n_fit_ls_new_var(&c->ls, &id); }
    for (int j = 0; j < q->Nv; j++)
        for (int i = 0; i < q->Nu; i++) {
            if (q2n_fit_ls_row(&c->ls, q->R + 3 * ((size_t)j * q->Nu + i))) return Q2N_ERR_NOMEM;
            for (int b = 0; b < p->nv; b++) {
                double wv = q->Bv[(size_t)j * p->nv + b];
                if (wv == 0.0) continue;
                for (int a = 0; a < p->nu; a++) {
                    double w = q->Bu[(size_t)i * p->nu + a] * wv;
                    int g = b * p->nu + a;
                    if (w != 0.0 && !p->fixed[g] && q2n_fit_ls_entry(&c->ls, q->var0 + p->var[g], w)) return Q2N_ERR_NOMEM;
                }
            }
        }
    return Q2N_OK;
}

/* X = A2^+ (R restricted to rows1 x rows2) A1^+T into the free block of patch sp->k. */
static void apply_one(void *arg, int l)
{
    sep_arg *a = arg;
    sep_patch *q = &a->sp[l];
    if (!q->tensor) return;
    fit_patch *p = &a->c->p[q->k];
    const fit_pinv *e1 = &a->c->pinv.v[q->id1], *e2 = &a->c->pinv.v[q->id2];
    int n1 = e1->n, n2 = e2->n, m1 = q->m1, m2 = q->m2;
    /* Z[i'][b'] = sum_j' P1[b'][j'] R[rows1[j']][rows2[i']]: every sample column fitted in v */
    double *Z = calloc(3 * (size_t)m2 * n1, sizeof(double));
    if (!Z) { q->st = Q2N_ERR_NOMEM; return; }
    for (int i = 0; i < m2; i++)
        for (int b = 0; b < n1; b++) {
            double *z = Z + 3 * ((size_t)i * n1 + b);
            const double *P = e1->P + (size_t)b * m1;
            for (int j = 0; j < m1; j++) q2n_v3_axpy(z, P[j], q->R + 3 * ((size_t)q->rows1[j] * q->Nu + q->rows2[i]));
        }
    /* X[b'][a'] = sum_i' P2[a'][i'] Z[i'][b']: every control column fitted in u */
    for (int b = 0; b < n1; b++)
        for (int c2 = 0; c2 < n2; c2++) {
            int g = (q->lv + b) * p->nu + q->lu + c2;
            double x[3] = {0, 0, 0};
            const double *P = e2->P + (size_t)c2 * m2;
            for (int i = 0; i < m2; i++) q2n_v3_axpy(x, P[i], Z + 3 * ((size_t)i * n1 + b));
            memcpy(p->cp + 3 * (size_t)g, x, sizeof x);
            p->fixed[g] = 1;
        }
    free(Z);
}

/* Stage 6: every control point of the listed patches not fixed yet, least squares on the patch's
 * sample grid (the file's comment). */
q2n_status q2n_fit_stage_interior(fit_ctx *c, const int *list, int nlist)
{
    sep_patch *sp = calloc((size_t)nlist + 1, sizeof *sp);
    q2n_status st = Q2N_OK;
    int nsp = 0, from = c->pinv.n;
    if (!sp) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    for (int l = 0; l < nlist; l++) {
        sep_patch q;
        memset(&q, 0, sizeof q);
        q.k = list[l];
        q.tensor = free_block(&c->p[q.k], &q.lu, &q.hu, &q.lv, &q.hv);
        if (q.tensor && q.hu < q.lu) continue;      /* nothing free */
        sp[nsp++] = q;
    }
    double t0 = q2n_now();
    sep_arg arg = {c, sp};
    q2n_par_for(nsp, c->o.threads, sep_one, &arg);
    c->rep->t_sample += q2n_now() - t0;
    for (int l = 0; l < nsp; l++) {
        c->rep->samples += sp[l].evals;
        if (sp[l].st && !st)
            st = q2n_error_set(c->err, sp[l].st, "fit: face %d: %s", sp[l].k,
                               sp[l].st == Q2N_ERR_NOMEM ? "out of memory (samples)" : "construction evaluation failed");
    }
    if (st) goto out;
    /* the matrices of the tensor blocks, in list order (the cache's content does not depend on the
     * threads), and their pseudo-inverses where new */
    for (int l = 0; l < nsp; l++) {
        sep_patch *q = &sp[l];
        if (!q->tensor) continue;
        q->id1 = pinv_find_add(&c->pinv, q->m1, q->hv - q->lv + 1, q->A1);
        q->id2 = q->id1 < 0 ? -1 : pinv_find_add(&c->pinv, q->m2, q->hu - q->lu + 1, q->A2);
        if (q->id2 < 0) goto nomem;
    }
    if ((st = pinv_solve(c, from))) goto out;
    t0 = q2n_now();
    q2n_par_for(nsp, c->o.threads, apply_one, &arg);
    c->rep->t_solve += q2n_now() - t0;
    for (int l = 0; l < nsp; l++)
        if (sp[l].st) goto nomem;
    /* non-tensor free sets: one item each */
    int ngen = 0;
    for (int l = 0; l < nsp; l++)
        if (!sp[l].tensor) {
            if (general_item(c, &sp[l])) goto nomem;
            ngen++;
        }
    if (ngen) {
        double t1 = q2n_now();
        st = q2n_fit_ls_solve(&c->ls, c->o.solver, c->o.threads, c->err);
        c->rep->t_solve += q2n_now() - t1;
        if (st) goto out;
        for (int l = 0; l < nsp; l++) {
            sep_patch *q = &sp[l];
            fit_patch *p = &c->p[q->k];
            if (q->tensor || q->var0 < 0) continue;
            for (int g = 0; g < p->nu * p->nv; g++)
                if (!p->fixed[g]) {
                    memcpy(p->cp + 3 * (size_t)g, c->ls.x + 3 * (size_t)(q->var0 + p->var[g]), 3 * sizeof(double));
                    p->fixed[g] = 1;
                    p->var[g] = -1;
                }
        }
    }
    goto out;
nomem:
    st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (interior)");
out:
    q2n_fit_ls_clear(&c->ls);
    pinv_drop_transient(&c->pinv);
    sep_free(sp, nsp);
    return st;
}
