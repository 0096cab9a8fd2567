/* ev_jet4.h — vertex jets of order up to 4 for the fair extraordinary construction (ev_fair.c, ev_fair_patch.c, ev_fair_solve.c).
 *
 * A jet at vertex v is the Taylor polynomial P(x, y) of a local surface through v in the
 * vertex's chart (the 2D directions of its edges, in local variables: ev_internal.h):
 *     P(x, y) = Σ_{j=0..4} Σ_{i=0..j} x^(j-i) y^i / ((j-i)! i!) · T[slot(j, i)],
 * T[slot(j, i)] = ∂x^(j-i) ∂y^i P(0, 0), slot(j, i) = j(j+1)/2 + i (15 slots, slot 0 = v).
 * Every datum of a face at v is a contraction of this one polynomial: the j-th derivative of P
 * along the directions a (p times) and b (q times), p + q = j, is T_j[a^p, b^q]; hence all
 * corner data at v are derivatives of one surface and agree by construction.
 *
 * "Lanes": the construction is linear in the jets, and the fairness solve needs the response
 * of a patch to every free jet coefficient.  Jets and everything computed from them are
 * therefore W-wide: lanes 0..2 carry x, y, z of the fixed part, lane 3 + c the (scalar,
 * coordinate-independent) response to the c-th free coefficient.  The production evaluator is
 * the case W = 3.
 *
 * Not core/jet.h: those are univariate jets with arithmetic on them (products, reciprocals, for
 * derivatives of formulas along a curve); these are bivariate Taylor polynomials that are the
 * construction's unknowns, and their one operation is the directional contraction below. */
#ifndef Q2N_PATCH_EV_JET4_H
#define Q2N_PATCH_EV_JET4_H

#include <string.h>

#include "core/poly.h"

#define EV_JS 15                                /* jet slots, orders 0..4 */
#define EV_SLOT(j, i) ((j) * ((j) + 1) / 2 + (i)) /* ∂x^(j-i) ∂y^i */

/* out[0..W-1] += s · T_j[a^p, b^q] for the W-wide jet T (EV_JS x W, slot-major). */
static inline void ev_jet_contract(const double *T, int W, int p, const double a[2], int q, const double b[2],
                                   double s, double *out)
{
    const double(*binom)[Q2N_BINOM_MAX + 1] = q2n_binom;
    int j = p + q;
    double ap[5][2], bp[5][2]; /* powers of the x and y components */
    ap[0][0] = ap[0][1] = bp[0][0] = bp[0][1] = 1;
    for (int k = 1; k <= 4; k++) {
        ap[k][0] = ap[k - 1][0] * a[0];
        ap[k][1] = ap[k - 1][1] * a[1];
        bp[k][0] = bp[k - 1][0] * b[0];
        bp[k][1] = bp[k - 1][1] * b[1];
    }
    for (int i = 0; i <= j; i++) { /* i = number of y slots */
        double n = 0;
        for (int r = 0; r <= p && r <= i; r++) {
            int t = i - r;
            if (t > q) continue;
            n += binom[p][r] * ap[r][1] * ap[p - r][0] * binom[q][t] * bp[t][1] * bp[q - t][0];
        }
        if (n == 0) continue;
        const double *Ts = T + (size_t)EV_SLOT(j, i) * W;
        n *= s;
        for (int l = 0; l < W; l++) out[l] += n * Ts[l];
    }
}

/* Bivariate polynomials in (a, b) truncated at a^4 and b^2: the jet composed with a polynomial corner
 * map (ev_fair_gluing2.c).  c[i][j] is the coefficient of a^i b^j. */
#define EV_MA 5
#define EV_MB 3
static inline void ev_bp_mul(const double A[EV_MA][EV_MB], const double B[EV_MA][EV_MB], double C[EV_MA][EV_MB])
{
    double R[EV_MA][EV_MB] = {{0}};
    for (int i1 = 0; i1 < EV_MA; i1++)
        for (int j1 = 0; j1 < EV_MB; j1++) {
            if (A[i1][j1] == 0) continue;
            for (int i2 = 0; i1 + i2 < EV_MA; i2++)
                for (int j2 = 0; j1 + j2 < EV_MB; j2++) R[i1 + i2][j1 + j2] += A[i1][j1] * B[i2][j2];
        }
    for (int i = 0; i < EV_MA; i++)
        for (int j = 0; j < EV_MB; j++) C[i][j] = R[i][j];
}

/* M[slot(k, l)][i][j]: the coefficient of a^i b^j in x^(k-l) y^l / ((k-l)! l!), (x, y) = φ(a, b) =
 * Σ phi[i][j] a^i b^j with phi[0][0] = 0 (a corner map in the vertex's chart), truncated at a^4, b^2:
 * the jet P composed with φ is Σ_slot M[slot] T[slot] (the chain rule for every derivative at once). */
static inline void ev_jet_map_table(const double phi[EV_MA][EV_MB][2], double M[EV_JS][EV_MA][EV_MB])
{
    double pw[2][5][EV_MA][EV_MB];
    for (int c = 0; c < 2; c++) {
        memset(pw[c][0], 0, sizeof pw[c][0]);
        pw[c][0][0][0] = 1;
        for (int i = 0; i < EV_MA; i++)
            for (int j = 0; j < EV_MB; j++) pw[c][1][i][j] = phi[i][j][c];
        for (int k = 2; k <= 4; k++) ev_bp_mul(pw[c][k - 1], pw[c][1], pw[c][k]);
    }
    static const double fact[5] = {1, 1, 2, 6, 24};
    for (int k = 0; k <= 4; k++)
        for (int l = 0; l <= k; l++) {
            double (*m)[EV_MB] = M[EV_SLOT(k, l)];
            ev_bp_mul(pw[0][k - l], pw[1][l], m);
            double f = 1 / (fact[k - l] * fact[l]);
            for (int i = 0; i < EV_MA; i++)
                for (int j = 0; j < EV_MB; j++) m[i][j] *= f;
        }
}

#endif
