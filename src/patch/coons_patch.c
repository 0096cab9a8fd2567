/* coons_patch.c — Boolean-sum Coons patch with Hermite blending, Gregory corners and interior
 * bubbles (coons_patch.h).
 *
 * S = P_u + P_v - P_uv (formulas.md §4.1):
 *   P_u(u,v)  = Σ_{i,a} H_{a,i}(u) ∂u^a S(i, v)      (the u-sides 3 (i = 0) and 1 (i = 1))
 *   P_v(u,v)  = Σ_{j,b} H_{b,j}(v) ∂v^b S(u, j)      (the v-sides 0 (j = 0) and 2 (j = 1))
 *   P_uv(u,v) = Σ_{i,j,a,b} H_{a,i}(u) H_{b,j}(v) M^{ab}_{ij},
 * H of degree 2K+1 (core/hermite.h).  M^{ab} with a = 0 comes from the v-side, otherwise from the
 * u-side, so that S interpolates both sides' data when they agree at the corners; at a Gregory
 * corner the mixed terms (a, b >= 1) are the rational pairs of formulas.md §4.2 with r = K, whose
 * partials up to order two are differentiated analytically (seed 003 §4.1 eq. 23, §4.2). */
#include "patch/coons_patch.h"

#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/poly.h"
#include "core/vec3.h"
#include "patch/surface.h"


static void line_fill(const cp_patch *P, const void *lanes, int W, int s0, int s1, double t, int na, cp_line *L)
{
    double F[3][CP_NA][CP_MAXW];
    L->W = W;
    for (int i = 0; i < 2; i++) {
        P->side(P->ctx, lanes, W, i ? s1 : s0, t, na, F);
        for (int b = 0; b < 3; b++)
            for (int a = 0; a < na; a++) memcpy(CP_LS(L, i, b, a), F[b][a], sizeof(double) * W);
    }
    q2n_hermite_eval(P->K, t, na - 1, L->H);
}

void q2n_cp_line_u(const cp_patch *P, const void *lanes, int W, double u, int na, cp_line *L)
{
    line_fill(P, lanes, W, 0, 2, u, na, L);
}

void q2n_cp_line_v(const cp_patch *P, const void *lanes, int W, double v, int na, cp_line *L)
{
    line_fill(P, lanes, W, 3, 1, v, na, L);
}

void q2n_cp_corner_terms(const cp_patch *P, const void *lanes, int W, cp_corner *C)
{
    double lfv[3][CP_NA][CP_MAXW], lgu[3][CP_NA][CP_MAXW];
    C->W = W;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            P->side(P->ctx, lanes, W, j ? 2 : 0, i, 3, lfv);
            P->side(P->ctx, lanes, W, i ? 1 : 3, j, 3, lgu);
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) {
                    int okA = b <= P->K, okB = a <= P->K;
                    double *A = CP_CT(C, 1, i, j, a, b), *B = CP_CT(C, 2, i, j, a, b), *M = CP_CT(C, 0, i, j, a, b);
                    if (okA) memcpy(A, lfv[b][a], sizeof(double) * W);
                    else memset(A, 0, sizeof(double) * W);
                    if (okB) memcpy(B, lgu[a][b], sizeof(double) * W);
                    else memset(B, 0, sizeof(double) * W);
                    memcpy(M, a == 0 ? A : B, sizeof(double) * W);
                }
        }
}

double q2n_cp_corner_mismatch(const cp_patch *P, const cp_corner *C, int i, int j)
{
    double dev = 0, sc = 0;
    for (int a = 1; a <= P->K; a++)
        for (int b = 1; b <= P->K; b++) {
            const double *A = CP_CT(C, 1, i, j, a, b), *B = CP_CT(C, 2, i, j, a, b);
            dev = fmax(dev, q2n_v3_dist(A, B));
            sc = fmax(sc, fmax(q2n_v3_norm(A), q2n_v3_norm(B)));
        }
    sc = fmax(sc, q2n_v3_norm(CP_CT(C, 1, i, j, 1, 0)));
    sc = fmax(sc, q2n_v3_norm(CP_CT(C, 2, i, j, 0, 1)));
    return sc > 0 ? dev / sc : 0;
}

/* Gregory weight ω = ũ^r / (ũ^r + ṽ^r) of corner (i,j) and its partials W[p][q], p+q <= 2. */
static void gregory_weight(int r, int i, int j, double u, double v, double W[3][3])
{
    double ut = i ? 1 - u : u, vt = j ? 1 - v : v, su = i ? -1 : 1, sv = j ? -1 : 1;
    memset(W, 0, 9 * sizeof(double));
    double U = r == 1 ? ut : ut * ut, V = r == 1 ? vt : vt * vt, g = U + V;
    if (!(g > 0)) { W[0][0] = 0.5; return; }
    double Uu = r == 1 ? su : 2 * ut * su, Uuu = r == 1 ? 0 : 2, Vv = r == 1 ? sv : 2 * vt * sv, Vvv = r == 1 ? 0 : 2;
    double g2 = g * g, g3 = g2 * g;
    W[0][0] = U / g;
    W[1][0] = Uu * V / g2;
    W[0][1] = -U * Vv / g2;
    W[2][0] = Uuu * V / g2 - 2 * Uu * Uu * V / g3;
    W[0][2] = -U * Vvv / g2 + 2 * U * Vv * Vv / g3;
    W[1][1] = Uu * Vv / g2 - 2 * Uu * V * Vv / g3;
}

/* Bubbles φ_b = 4^(2K+2) B(u) B(v) m_b, B(t) = t^(K+1) (1-t)^(K+1), m_b = 1, 2u-1, 2v-1,
 * (2u-1)(2v-1): they vanish with K derivatives on all four sides, so adding them changes no side
 * datum (continuity and interpolation are untouched).  They are separable: */

/* the factor along one axis at t: out[0][d] = d-th derivative of 4^p B(t), out[1][d] the
 * same times the monomial 2t - 1. */
static void bubble_axis(int K, double t, double out[2][4])
{
    double r[4], pa[4], pb[4], ta[4], tb[4]; /* t^p, (1-t)^p and derivatives */
    int p = K + 1;
    double sc = p == 2 ? 16 : 64; /* 4^p */
    const double(*bn)[Q2N_BINOM_MAX + 1] = q2n_binom;
    ta[0] = tb[0] = 1;
    for (int i = 1; i < 4; i++) { ta[i] = ta[i - 1] * t; tb[i] = tb[i - 1] * (1 - t); }
    for (int d = 0; d < 4; d++) {
        double f = 1;
        for (int j = 0; j < d; j++) f *= (double)(p - j);
        pa[d] = d > p ? 0 : f * ta[p - d];
        pb[d] = d > p ? 0 : f * tb[p - d] * (d & 1 ? -1 : 1);
    }
    for (int d = 0; d < 4; d++) {
        r[d] = 0;
        for (int i = 0; i <= d; i++) r[d] += bn[d][i] * pa[i] * pb[d - i];
        r[d] *= sc;
    }
    for (int d = 0; d < 4; d++) { /* times the monomial 2t-1 (value, slope 2) */
        out[0][d] = r[d];
        out[1][d] = (2 * t - 1) * r[d] + (d ? 2 * d * r[d - 1] : 0);
    }
}

/* ph from the two axes' factors (bubble b uses the monomial in u when b & 1, in v when b & 2). */
static void bubbles_from_axes(const double U[2][4], const double V[2][4], double ph[CP_NBUB][10])
{
    const int(*ord)[2] = q2n_eval_order;
    for (int b = 0; b < CP_NBUB; b++)
        for (int o = 0; o < 10; o++) ph[b][o] = U[b & 1][ord[o][0]] * V[(b >> 1) & 1][ord[o][1]];
}

void q2n_cp_bubbles(int K, double u, double v, double ph[CP_NBUB][10])
{
    double U[2][4], V[2][4];
    bubble_axis(K, u, U);
    bubble_axis(K, v, V);
    bubbles_from_axes((const double (*)[4])U, (const double (*)[4])V, ph);
}

void q2n_cp_sum(const cp_patch *P, const cp_corner *C, const double *bub, int W, double u, double v, int nder,
            const cp_line *Lu, const cp_line *Lv, double *out)
{
    int K = P->K;
    const int(*ord)[2] = q2n_eval_order;
    const double(*binom)[Q2N_BINOM_MAX + 1] = q2n_binom;
    double Wg[2][2][3][3];
    int anyg = 0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            if (P->greg[q2n_corner_at(i, j)]) {
                gregory_weight(K, i, j, u, v, Wg[i][j]);
                anyg = 1;
            }
    int nout = nder <= 0 ? 1 : nder == 1 ? 3 : nder == 2 ? 6 : 10;
    for (int o = 0; o < nout; o++) {
        int al = ord[o][0], be = ord[o][1];
        double *r = out + (size_t)o * W;
        memset(r, 0, sizeof(double) * W);
        for (int i = 0; i < 2; i++)
            for (int a = 0; a <= K; a++) {
                double hu = Lu->H[a][i][al], hv = Lv->H[a][i][be];
                const double *gv = CP_LS(Lv, i, a, be), *fu = CP_LS(Lu, i, a, al);
                for (int l = 0; l < W; l++) r[l] += hu * gv[l] + hv * fu[l];
            }
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++) {
                int greg = anyg && P->greg[q2n_corner_at(i, j)] && al + be <= 2;
                for (int a = 0; a <= K; a++)
                    for (int b = 0; b <= K; b++) {
                        if (!(greg && a >= 1 && b >= 1)) {
                            double h = Lu->H[a][i][al] * Lv->H[b][j][be];
                            if (h == 0) continue;
                            const double *M = CP_CT(C, 0, i, j, a, b);
                            for (int l = 0; l < W; l++) r[l] -= h * M[l];
                            continue;
                        }
                        const double *A = CP_CT(C, 1, i, j, a, b), *B = CP_CT(C, 2, i, j, a, b);
                        for (int a1 = 0; a1 <= al; a1++)
                            for (int b1 = 0; b1 <= be; b1++) {
                                int p = al - a1, q = be - b1;
                                double h = binom[al][a1] * binom[be][b1] * Lu->H[a][i][a1] * Lv->H[b][j][b1];
                                if (h == 0) continue;
                                double w = Wg[i][j][p][q];
                                if (p == 0 && q == 0)
                                    for (int l = 0; l < W; l++) r[l] -= h * (A[l] + w * (B[l] - A[l]));
                                else
                                    for (int l = 0; l < W; l++) r[l] -= h * w * (B[l] - A[l]);
                            }
                    }
            }
    }
    if (bub) {
        double ph[CP_NBUB][10];
        q2n_cp_bubbles(K, u, v, ph);
        for (int o = 0; o < nout; o++)
            for (int b = 0; b < CP_NBUB; b++) {
                double f = ph[b][o];
                const double *c = bub + (size_t)b * W;
                for (int l = 0; l < W; l++) out[(size_t)o * W + l] += f * c[l];
            }
    }
}

void q2n_cp_grid(const cp_patch *P, const cp_corner *C, const double *bub, int W, int nu, const double *us,
             const cp_line *Lu, int nv, const double *vs, const cp_line *Lv, int omin, int omax, double *out)
{
    const int(*ord)[2] = q2n_eval_order;
    int K = P->K, no = omax - omin + 1;
    double Dv[2][3][CP_NA][CP_MAXW]; /* per v-line: u-side data minus the corner tensor contracted in v */
    /* the bubbles are separable: their u factors once per column, v factors once per row */
    double (*Ua)[2][4] = bub ? malloc(sizeof *Ua * (size_t)(nu > 0 ? nu : 1)) : NULL;
    for (int a = 0; Ua && a < nu; a++) bubble_axis(K, us[a], Ua[a]);
    /* only the v-orders the requested outputs use: the lines hold no more (their weights and
     * fields beyond na - 1 are not filled) */
    int qmax = 0;
    for (int o = omin; o <= omax; o++)
        if (ord[o][1] > qmax) qmax = ord[o][1];
    for (int b = 0; b < nv; b++) {
        double Vb[2][4];
        if (Ua) bubble_axis(K, vs[b], Vb);
        const cp_line *L = &Lv[b];
        for (int i = 0; i < 2; i++)
            for (int k = 0; k <= K; k++)
                for (int q = 0; q <= qmax; q++) {
                    double *r = Dv[i][k][q];
                    memcpy(r, CP_LS(L, i, k, q), sizeof(double) * W);
                    for (int j = 0; j < 2; j++)
                        for (int l = 0; l <= K; l++) {
                            double h = L->H[l][j][q];
                            if (h == 0) continue;
                            const double *M = CP_CT(C, 0, i, j, k, l);
                            for (int x = 0; x < W; x++) r[x] -= h * M[x];
                        }
                }
        for (int a = 0; a < nu; a++) {
            const cp_line *U = &Lu[a];
            if (omax == 0 && W == 3 && (Ua || !bub)) {
                /* positions of the three production lanes (the fit's samples): the loop below for
                 * o = 0 with its lane loops written out — the same operations in the same order */
                double r0 = 0.0, r1 = 0.0, r2 = 0.0;
                for (int i = 0; i < 2; i++)
                    for (int k = 0; k <= K; k++) {
                        double hu = U->H[k][i][0], hv = L->H[k][i][0];
                        const double *d = Dv[i][k][0], *f = CP_LS(U, i, k, 0);
                        r0 += hu * d[0] + hv * f[0];
                        r1 += hu * d[1] + hv * f[1];
                        r2 += hu * d[2] + hv * f[2];
                    }
                for (int bb = 0; bub && bb < CP_NBUB; bb++) {
                    double f = Ua[a][bb & 1][0] * Vb[(bb >> 1) & 1][0]; /* bubbles_from_axes' order 0 */
                    const double *c = bub + (size_t)bb * 3;
                    r0 += f * c[0];
                    r1 += f * c[1];
                    r2 += f * c[2];
                }
                double *r = out + (size_t)(b * nu + a) * 3;
                r[0] = r0;
                r[1] = r1;
                r[2] = r2;
                continue;
            }
            double ph[CP_NBUB][10];
            /* the bubble weights of the requested orders only (the same products as
             * bubbles_from_axes) */
            if (Ua)
                for (int bb = 0; bb < CP_NBUB; bb++)
                    for (int o = omin; o <= omax; o++) ph[bb][o] = Ua[a][bb & 1][ord[o][0]] * Vb[(bb >> 1) & 1][ord[o][1]];
            else if (bub) q2n_cp_bubbles(K, us[a], vs[b], ph);
            for (int o = omin; o <= omax; o++) {
                int p = ord[o][0], q = ord[o][1];
                double *r = out + ((size_t)(b * nu + a) * no + (o - omin)) * W;
                memset(r, 0, sizeof(double) * W);
                for (int i = 0; i < 2; i++)
                    for (int k = 0; k <= K; k++) {
                        double hu = U->H[k][i][p], hv = L->H[k][i][q];
                        const double *d = Dv[i][k][q], *f = CP_LS(U, i, k, p);
                        for (int x = 0; x < W; x++) r[x] += hu * d[x] + hv * f[x];
                    }
                for (int bb = 0; bub && bb < CP_NBUB; bb++) {
                    double f = ph[bb][o];
                    const double *c = bub + (size_t)bb * W;
                    for (int x = 0; x < W; x++) r[x] += f * c[x];
                }
            }
        }
    }
    free(Ua);
}

/* ------------------------------------------------------------ production evaluators (W = 3) */

static atomic_ulong cp_gen;

void q2n_cp_eval_init(cp_eval *E)
{
    E->gen = atomic_fetch_add(&cp_gen, 1) + 1;
    E->C.W = 3;
    E->C.v = E->ct;
    q2n_cp_corner_terms(&E->P, E->lanes, 3, &E->C);
}

/* Point evaluations along a patch side keep one parameter fixed, so one of the two lines is the
 * same from point to point: the last few lines per thread, keyed by the patch state's generation
 * (q2n_cp_eval_init), the direction, na and the bits of the parameter, are copied instead of
 * recomputed (the same numbers). */
#define LINE_MEMO_N 4
typedef struct line_memo {
    unsigned long gen, used;     /* used 0: empty */
    int dir, na;
    uint64_t tbits;
    double s[CP_LINE_SIZE(3)];
    double H[3][2][Q2N_HERMITE_MAXD + 1];
} line_memo;
static _Thread_local line_memo line_memo_tab[LINE_MEMO_N];
static _Thread_local unsigned long line_memo_clock;

static void eval_line(const cp_eval *E, int dir, double t, int na, cp_line *L)
{
    uint64_t tb;
    memcpy(&tb, &t, sizeof tb);
    line_memo *m = NULL, *old = &line_memo_tab[0];
    for (int i = 0; i < LINE_MEMO_N && !m; i++) {
        line_memo *x = &line_memo_tab[i];
        if (x->used && x->gen == E->gen && x->dir == dir && x->na == na && x->tbits == tb) m = x;
        else if (x->used < old->used) old = x;
    }
    if (!m) {
        m = old;
        cp_line F = {3, m->s, {{{0}}}};
        if (dir) q2n_cp_line_v(&E->P, E->lanes, 3, t, na, &F);
        else q2n_cp_line_u(&E->P, E->lanes, 3, t, na, &F);
        memcpy(m->H, F.H, sizeof m->H);
        m->gen = E->gen;
        m->dir = dir;
        m->na = na;
        m->tbits = tb;
    }
    m->used = ++line_memo_clock;
    memcpy(L->s, m->s, sizeof m->s);
    memcpy(L->H, m->H, sizeof m->H);
}

/* On a side the patch interpolates that side's data (the Boolean sum's corrections cancel there when
 * the corners agree, and the bubbles vanish with K derivatives on every side), so a point on a side
 * with nder <= K is the side function itself: one side evaluation instead of two lines and the sum.
 * Not where a corner keeps a Gregory blend.  out as q2n_cp_eval_point's. */
static int side_point(const cp_eval *E, double u, double v, int nder, double *out)
{
    const cp_patch *P = &E->P;
    if (nder > P->K || nder > 2 || P->greg[0] || P->greg[1] || P->greg[2] || P->greg[3]) return 0;
    int sd = v == 0 ? 0 : v == 1 ? 2 : u == 0 ? 3 : u == 1 ? 1 : -1;
    if (sd < 0) return 0;
    int along_u = sd == 0 || sd == 2, nout = nder == 0 ? 1 : nder == 1 ? 3 : 6;
    double F[3][CP_NA][CP_MAXW];
    P->side(P->ctx, E->lanes, 3, sd, along_u ? u : v, nder + 1, F); /* F[cross order][along order] */
    for (int o = 0; o < nout; o++) {
        int a = q2n_eval_order[o][0], b = q2n_eval_order[o][1]; /* ∂u^a ∂v^b */
        memcpy(out + 3 * o, along_u ? F[b][a] : F[a][b], 3 * sizeof(double));
    }
    return 1;
}

q2n_status q2n_cp_eval_point(const void *data, double u, double v, int nder, double *out)
{
    const cp_eval *E = data;
    if (side_point(E, u, v, nder, out)) return Q2N_OK;
    double su[CP_LINE_SIZE(3)], sv[CP_LINE_SIZE(3)];
    cp_line Lu = {3, su, {{{0}}}}, Lv = {3, sv, {{{0}}}};
    int na = nder < 2 ? 2 : 3;
    eval_line(E, 0, u, na, &Lu);
    eval_line(E, 1, v, na, &Lv);
    q2n_cp_sum(&E->P, &E->C, &E->bub[0][0], 3, u, v, nder, &Lu, &Lv, out);
    return Q2N_OK;
}

/* The grid with first derivatives (nder 1: S, Su, Sv, 9 doubles per point) or positions only
 * (nder 0: 3 per point, lines without along derivatives, the sum's first output). */
static q2n_status eval_grid(const cp_eval *E, int nder, int nu, const double *us, int nv, const double *vs, double *out)
{
    int greg = E->P.greg[0] || E->P.greg[1] || E->P.greg[2] || E->P.greg[3], nl = nu + (greg ? 1 : nv);
    int na = nder + 1, nout = nder ? 3 : 1;
    cp_line *Lu = malloc((size_t)nl * sizeof *Lu);
    double *st = malloc((size_t)nl * CP_LINE_SIZE(3) * sizeof *st);
    if (!Lu || !st) {
        free(Lu);
        free(st);
        return Q2N_ERR_NOMEM;
    }
    for (int k = 0; k < nl; k++) Lu[k].s = st + (size_t)k * CP_LINE_SIZE(3);
    for (int a = 0; a < nu; a++) q2n_cp_line_u(&E->P, E->lanes, 3, us[a], na, &Lu[a]);
    if (!greg) { /* constant corner terms: the tensor form (S, Su, Sv are q2n_cp_grid's orders 0..2) */
        cp_line *Lv = Lu + nu;
        for (int b = 0; b < nv; b++) q2n_cp_line_v(&E->P, E->lanes, 3, vs[b], na, &Lv[b]);
        q2n_cp_grid(&E->P, &E->C, &E->bub[0][0], 3, nu, us, Lu, nv, vs, Lv, 0, nout - 1, out);
        free(Lu);
        free(st);
        return Q2N_OK;
    }
    for (int b = 0; b < nv; b++) {
        cp_line *Lv = &Lu[nu];
        q2n_cp_line_v(&E->P, E->lanes, 3, vs[b], na, Lv);
        for (int a = 0; a < nu; a++)
            q2n_cp_sum(&E->P, &E->C, &E->bub[0][0], 3, us[a], vs[b], nder, &Lu[a], Lv, out + 3 * nout * ((size_t)b * nu + a));
    }
    free(Lu);
    free(st);
    return Q2N_OK;
}

q2n_status q2n_cp_eval_grid(const void *data, int nu, const double *us, int nv, const double *vs, double *out)
{
    return eval_grid(data, 1, nu, us, nv, vs, out);
}

q2n_status q2n_cp_eval_grid_pos(const void *data, int nu, const double *us, int nv, const double *vs, double *out)
{
    return eval_grid(data, 0, nu, us, nv, vs, out);
}

q2n_status q2n_cp_eval_corner(const void *data, int i, int j, double out[2][2][2][3])
{
    const cp_eval *E = data;
    if (E->P.K != 2) return Q2N_ERR_UNSUPPORTED;
    for (int a = 1; a <= 2; a++)
        for (int b = 1; b <= 2; b++) {
            memcpy(out[0][a - 1][b - 1], CP_CT(&E->C, 1, i, j, a, b), 3 * sizeof(double));
            memcpy(out[1][a - 1][b - 1], CP_CT(&E->C, 2, i, j, a, b), 3 * sizeof(double));
        }
    return Q2N_OK;
}
