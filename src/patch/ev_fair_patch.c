/* ev_fair_patch.c — a face's patch in the fair extraordinary construction (ev_fair_internal.h):
 * the fields of its constructed sides (boundary curve γ, cross derivatives χ and ξ) as polynomials
 * from the jets at the side's two ends, the data of sides shared with a regular patch, and the
 * Coons patch's side function over both (coons_patch.c).  What the fields are and why the corners
 * agree: ev_fair.c's header and docs/extraordinary.md, "The fair construction". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/poly.h"
#include "patch/ev_fair_internal.h"

/* ------------------------------------------------------------ side data (W lanes) */


/* Hermite end data of a constructed side: the jet contractions at both ends, for γ (order 2K),
 * χ_F (2K - 1) and ξ_F (2K - 2).  A patch turns them into its sides' polynomials once (q2n_ev_fair_fill_lanes,
 * side_taylor); an evaluation is then a Horner sum. */
typedef struct fe_ends {
    int W;
    double *e; /* [γ|χ|ξ][end][j <= 4][lane]: FE_END(E, p, end, j) */
} fe_ends;
#define FE_END(E, p, end, j) ((E)->e + (size_t)((((p) * 2 + (end)) * 5) + (j)) * (E)->W)
#define FE_END_SIZE(W) ((size_t)3 * 2 * 5 * (W))


/* End data of a G2 side with polynomial gluing's corner terms (ev_fair_gluing2.c): the jet composed with
 * the base face's corner map at each end, φ(a, b) = a d u + b e_w w + a b r + a² b c21 + a b² c12 + a² b² c22
 * (a from the end along the side, b across into the base face): the a^j b^p coefficient times j! p!, with
 * (-1)^j at end 1 (d/ds = -d/da there). */
static void side_ends_map(int K, const fe_side *S, const double *T0, const double *T1, fe_ends *E)
{
    int Kc = 2 * K, W = E->W;
    static const double fact[5] = {1, 1, 2, 6, 24};
    for (int e = 0; e < 2; e++) {
        double phi[EV_MA][EV_MB][2], M[EV_JS][EV_MA][EV_MB];
        const double *u = e ? S->u1 : S->u0, *w = e ? S->w1 : S->w0, *T = e ? T1 : T0;
        memset(phi, 0, sizeof phi);
        for (int c = 0; c < 2; c++) {
            phi[1][0][c] = S->d * u[c];
            phi[0][1][c] = S->ew[e] * w[c];
            phi[1][1][c] = S->rc[e][c];
            phi[2][1][c] = S->cm[e][0][c];
            phi[1][2][c] = S->cm[e][1][c];
            phi[2][2][c] = S->cm[e][2][c];
        }
        ev_jet_map_table((const double (*)[EV_MB][2])phi, M);
        for (int p = 0; p <= K; p++)
            for (int j = 0; j <= Kc - p; j++) {
                double *o = FE_END(E, p, e, j), f = fact[j] * fact[p] * ((e && (j & 1)) ? -1 : 1);
                for (int sl = 0; sl < EV_JS; sl++) {
                    double g = f * M[sl][j][p];
                    if (g == 0) continue;
                    const double *Ts = T + (size_t)sl * W;
                    for (int l = 0; l < W; l++) o[l] += g * Ts[l];
                }
            }
    }
}

/* End data of side S: d^j s T_(j+p)[u^j, w^p] at both ends, j <= 2K - p, p <= K (s: the cross-edge
 * interval to the power p). */
static void side_ends(int K, const fe_side *S, const double *T0, const double *T1, fe_ends *E)
{
    int Kc = 2 * K, W = E->W;
    memset(E->e, 0, sizeof(double) * FE_END_SIZE(W));
    if (K >= 2 && fe_side_glued(S)) {
        side_ends_map(K, S, T0, T1, E);
        return;
    }
    for (int p = 0; p <= K; p++) {
        double s0 = p == 0 ? 1 : p == 1 ? S->ew[0] : S->ew[0] * S->ew[0];
        double s1 = p == 0 ? 1 : p == 1 ? S->ew[1] : S->ew[1] * S->ew[1];
        for (int j = 0; j <= Kc - p; j++) {
            ev_jet_contract(T0, W, j, S->u0, p, S->w0, pow(S->d, j) * s0, FE_END(E, p, 0, j));
            ev_jet_contract(T1, W, j, S->u1, p, S->w1, pow(-S->d, j) * s1, FE_END(E, p, 1, j));
        }
    }
    /* twist corrections of the base face's corners: T_out += J rc (end 0: d/ds χ = T_out; end 1: -T_out) */
    if (S->rc[0][0] != 0 || S->rc[0][1] != 0) ev_jet_contract(T0, W, 1, S->rc[0], 0, S->w0, 1.0, FE_END(E, 1, 0, 1));
    if (S->rc[1][0] != 0 || S->rc[1][1] != 0) ev_jet_contract(T1, W, 1, S->rc[1], 0, S->w1, -1.0, FE_END(E, 1, 1, 1));
}


/* Expansion about end e of the Hermite interpolant of order Kh of field p's end data (degree
 * 2Kh + 1).  About 1, in σ = s - 1: H_{j,0}(1 + σ) = (-1)^j H_{j,1}(-σ), H_{j,1}(1 + σ) = (-1)^j H_{j,0}(-σ)
 * (the basis is symmetric under s -> 1 - s). */
static void hermite_taylor(int Kh, const fe_ends *E, int p, int e, int W, double *out)
{
    int n = 2 * Kh + 1;
    memset(out, 0, sizeof(double) * (size_t)(n + 1) * W);
    for (int j = 0; j <= Kh; j++) {
        const double *h0 = q2n_hermite_coef[Kh - 1][j][0], *h1 = q2n_hermite_coef[Kh - 1][j][1];
        const double *e0 = FE_END(E, p, 0, j), *e1 = FE_END(E, p, 1, j);
        for (int k = 0; k <= n; k++) {
            double f0 = e ? h1[k] : h0[k], f1 = e ? h0[k] : h1[k];
            if (e && ((j + k) & 1)) f0 = -f0, f1 = -f1;
            if (f0 == 0 && f1 == 0) continue;
            double *o = out + (size_t)k * W;
            for (int l = 0; l < W; l++) o[l] += f0 * e0[l] + f1 * e1[l];
        }
    }
}

/* The n coefficients c of a polynomial about 0 rewritten about 1 (Σ_{j >= k} C(j, k) c_j), or copied
 * when shift is 0. */
static void about_end(int n, const double *c, int shift, double *out)
{
    for (int k = 0; k < n; k++) {
        out[k] = c[k];
        if (shift)
            for (int j = k + 1; j < n; j++) out[k] += q2n_binom[j][k] * c[j];
    }
}

/* The smoothstep of order K from v0 to v1 (v0 + (v1 - v0) H_{0,1} = v1 - (v1 - v0) H_{0,0}) about end
 * e: n + 1 = 2K + 2 coefficients. */
static void smooth_taylor(int K, double v0, double v1, int e, double *out)
{
    const double *h = q2n_hermite_coef[K - 1][0][1];
    int n = 2 * K + 1;
    for (int k = 0; k <= n; k++) out[k] = e ? -(v1 - v0) * ((k & 1) ? -h[k] : h[k]) : (v1 - v0) * h[k];
    out[0] = e ? v1 : v0;
}

/* The cubic Hermite interpolant with values v0, v1 and slopes m0, m1 at s = 0, 1, about end e (4
 * coefficients): G1 gluing functions with free end slopes (ev_fair_gluing.c). */
static void cubic_taylor(double v0, double v1, double m0, double m1, int e, double *out)
{
    double c[4];
    for (int k = 0; k < 4; k++)
        c[k] = v0 * q2n_hermite_coef[0][0][0][k] + v1 * q2n_hermite_coef[0][0][1][k] + m0 * q2n_hermite_coef[0][1][0][k] +
               m1 * q2n_hermite_coef[0][1][1][k];
    about_end(4, c, e, out);
}

/* γ of an edge with a flat end (fe_side.flat_end): the quartic with value, slope and second
 * derivative at the other end and value and slope at the flat end, about end e; the end data are E's
 * (s-derivatives). */
static void quartic_taylor(const fe_ends *E, int flat, int e, int W, double *out)
{
    int k0 = !flat; /* the end that keeps its second derivative */
    double sg = k0 ? -1 : 1; /* t = s (k0 = 0) or 1 - s (k0 = 1): d/dt = sg d/ds */
    for (int l = 0; l < W; l++) {
        double p0 = FE_END(E, 0, k0, 0)[l], d0 = sg * FE_END(E, 0, k0, 1)[l], c0 = FE_END(E, 0, k0, 2)[l];
        double p1 = FE_END(E, 0, flat, 0)[l], d1 = sg * FE_END(E, 0, flat, 1)[l];
        double R1 = p1 - p0 - d0 - 0.5 * c0, R2 = d1 - d0 - c0;
        double c[5] = {p0, d0, 0.5 * c0, 4 * R1 - R2, R2 - 3 * R1}; /* in t, about t = 0 (end k0) */
        double o[5];
        about_end(5, c, e != k0, o); /* about t = 1 when e is the flat end */
        for (int k = 0; k < 5; k++) out[(size_t)k * W + l] = (sg < 0 && (k & 1)) ? -o[k] : o[k]; /* back to s */
        out[(size_t)5 * W + l] = 0;
    }
}

/* γ of an edge whose β vanishes at both ends (fe_side.quartic 1): the cubic Hermite interpolant of
 * the values and slopes at both ends plus k s² (1 - s)², k matching the two ends' second derivatives
 * in least squares (that of s² (1 - s)² is 2 at both ends), about end e. */
static void quartic_sym_taylor(const fe_ends *E, int e, int W, double *out)
{
    for (int l = 0; l < W; l++) {
        double p0 = FE_END(E, 0, 0, 0)[l], d0 = FE_END(E, 0, 0, 1)[l], c0 = FE_END(E, 0, 0, 2)[l];
        double p1 = FE_END(E, 0, 1, 0)[l], d1 = FE_END(E, 0, 1, 1)[l], c1 = FE_END(E, 0, 1, 2)[l];
        /* cubic Hermite in s: a0 + a1 s + a2 s² + a3 s³ */
        double a2 = 3 * (p1 - p0) - 2 * d0 - d1, a3 = 2 * (p0 - p1) + d0 + d1;
        double h0 = 2 * a2, h1 = 2 * a2 + 6 * a3; /* its second derivatives at 0 and 1 */
        double k = 0.25 * ((c0 - h0) + (c1 - h1));
        double c[5] = {p0, d0, a2 + k, a3 - 2 * k, k}, o[5]; /* + k (s² - 2 s³ + s⁴) */
        about_end(5, c, e, o);
        for (int q = 0; q < 5; q++) out[(size_t)q * W + l] = o[q];
        out[(size_t)5 * W + l] = 0;
    }
}

/* The quintic Hermite interpolant with values, slopes and second derivatives v[e][0..2] at s = e, about
 * end e (6 coefficients): G2 gluing functions (ev_fair_gluing2.c). */
static void quintic_taylor(const double v0[3], const double v1[3], int e, double *out)
{
    double c[6];
    for (int k = 0; k < 6; k++) {
        c[k] = 0;
        for (int j = 0; j < 3; j++) c[k] += v0[j] * q2n_hermite_coef[1][j][0][k] + v1[j] * q2n_hermite_coef[1][j][1][k];
    }
    about_end(6, c, e, out);
}

/* α or β flat at end f (value v_f there, v_o at the other end), about end e: v_f + (v_o - v_f) τ², τ the
 * distance from end f. */
static void flat_quadratic(double v0, double v1, int f, int e, double *out)
{
    double vf = f ? v1 : v0, vo = f ? v0 : v1, d = vo - vf;
    if (e == f) out[0] = vf, out[1] = 0, out[2] = d;
    else out[0] = vo, out[1] = f ? -2 * d : 2 * d, out[2] = d; /* τ = 1 + σ (f = 0) or 1 - σ (f = 1) */
}

/* out[k] += f Σ_i a[i] v[k - i] (a scalar polynomial of degree na times a lane polynomial of
 * degree nv, shifted by dv derivatives: v[k] here is (k + dv)! / k! V[k + dv]). */
static void conv_add(const double *a, int na, const double *V, int nv, int dv, int W, double f, double *out)
{
    for (int i = 0; i <= na; i++) {
        if (a[i] == 0) continue;
        for (int k = 0; k + dv <= nv; k++) {
            double g = f * a[i];
            for (int q = 1; q <= dv; q++) g *= (double)(k + q);
            const double *v = V + (size_t)(k + dv) * W;
            double *o = out + (size_t)(i + k) * W;
            for (int l = 0; l < W; l++) o[l] += g * v[l];
        }
    }
}

/* The side's fields about both ends from its end data: γ (order 2K), χ (2K - 1), ξ (2K - 2) of the
 * base face; a derived side's χ_G = α χ_F + β γ_t, ξ_G = α² ξ_F + 2αβ ∂t χ_F + β² γ_tt. */
static void side_taylor(int K, const fe_side *S, const fe_ends *E, fe_taylor *T)
{
    int Kc = 2 * K, W = T->W, ng = 2 * Kc + 1, nc = 2 * Kc - 1, nx = 2 * Kc - 3, ns = 2 * K + 1;
    memset(T->c, 0, sizeof(double) * FE_TAYLOR_SIZE(W));
    T->deg[0] = ng;
    T->deg[1] = S->derived ? ns + ng - 1 : nc;
    T->deg[2] = K < 2 ? 0 : S->derived ? 2 * ns + ng - 2 : nx;
    for (int e = 0; e < 2; e++) {
        if (K == 1 && S->flat_end >= 0) quartic_taylor(E, S->flat_end, e, W, FE_TC(T, 0, e, 0));
        else if (K == 1 && S->quartic == 1) quartic_sym_taylor(E, e, W, FE_TC(T, 0, e, 0));
        else if (K == 1 && S->quartic >= 2) quartic_taylor(E, S->quartic - 2, e, W, FE_TC(T, 0, e, 0));
        else hermite_taylor(Kc, E, 0, e, W, FE_TC(T, 0, e, 0));
        if (!S->derived) {
            hermite_taylor(Kc - 1, E, 1, e, W, FE_TC(T, 1, e, 0));
            if (K >= 2) hermite_taylor(Kc - 2, E, 2, e, W, FE_TC(T, 2, e, 0));
            continue;
        }
        double c[(FE_TDEG + 1) * CP_MAXW], x[(FE_TDEG + 1) * CP_MAXW];
        double al[2 * Q2N_HERMITE_MAXK + 2], be[2 * Q2N_HERMITE_MAXK + 2];
        hermite_taylor(Kc - 1, E, 1, e, W, c);
        for (int k = 0; k < 2 * Q2N_HERMITE_MAXK + 2; k++) al[k] = be[k] = 0;
        if (K == 1 && S->flat_end >= 0) {
            flat_quadratic(S->al[0], S->al[1], S->flat_end, e, al);
            flat_quadratic(S->be[0], S->be[1], S->flat_end, e, be);
        } else if (S->poly) {
            double a0 = S->al[0], a1 = S->al[1], q = S->q, c2 = a0 - 2 * q + a1;
            al[0] = e ? a1 : a0;
            al[1] = e ? 2 * (a1 - q) : 2 * (q - a0);
            al[2] = c2;
            be[0] = e ? S->be[1] : S->be[0];
            be[1] = S->be[1] - S->be[0] + (e ? -S->bump : S->bump); /* bump s (1 - s): σ - σ² about 0, -σ - σ² about 1 */
            be[2] = -S->bump;
        } else if (K == 1 && fe_side_slopes(S)) {
            cubic_taylor(S->al[0], S->al[1], S->sl[0][0], S->sl[0][1], e, al);
            cubic_taylor(S->be[0], S->be[1], S->sl[1][0], S->sl[1][1], e, be);
        } else if (K == 2 && fe_side_slopes(S)) {
            const double va[2][3] = {{S->al[0], S->sl[0][0], 0}, {S->al[1], S->sl[0][1], 0}};
            const double vb[2][3] = {{S->be[0], S->sl[1][0], 0}, {S->be[1], S->sl[1][1], 0}};
            quintic_taylor(va[0], va[1], e, al);
            quintic_taylor(vb[0], vb[1], e, be);
        } else {
            smooth_taylor(K, S->al[0], S->al[1], e, al);
            smooth_taylor(K, S->be[0], S->be[1], e, be);
        }
        const double *g = FE_TC(T, 0, e, 0);
        conv_add(al, ns, c, nc, 0, W, 1, FE_TC(T, 1, e, 0));
        conv_add(be, ns, g, ng, 1, W, 1, FE_TC(T, 1, e, 0));
        if (K < 2) continue;
        double a2[2 * (2 * Q2N_HERMITE_MAXK + 2)], ab[2 * (2 * Q2N_HERMITE_MAXK + 2)], b2[2 * (2 * Q2N_HERMITE_MAXK + 2)];
        for (int k = 0; k <= 2 * ns; k++) {
            a2[k] = ab[k] = b2[k] = 0;
            for (int i = 0; i <= k; i++)
                if (i <= ns && k - i <= ns) {
                    a2[k] += al[i] * al[k - i];
                    ab[k] += 2 * al[i] * be[k - i];
                    b2[k] += be[i] * be[k - i];
                }
        }
        hermite_taylor(Kc - 2, E, 2, e, W, x);
        conv_add(a2, 2 * ns, x, nx, 0, W, 1, FE_TC(T, 2, e, 0));
        conv_add(ab, 2 * ns, c, nc, 1, W, 1, FE_TC(T, 2, e, 0));
        conv_add(b2, 2 * ns, g, ng, 2, W, 1, FE_TC(T, 2, e, 0));
        if (fe_side_g2(S)) { /* the G2 relation's tangential terms: + A χ_F + B γ_t */
            double ta[6], tb[6];
            quintic_taylor(S->tg[0][0], S->tg[0][1], e, ta);
            quintic_taylor(S->tg[1][0], S->tg[1][1], e, tb);
            conv_add(ta, 5, c, nc, 0, W, 1, FE_TC(T, 2, e, 0));
            conv_add(tb, 5, g, ng, 1, W, 1, FE_TC(T, 2, e, 0));
        }
    }
}

void q2n_ev_fair_glue_taylor(const fe_side *S, int e, double al[3], double bt[3])
{
    double a[3], b[3]; /* α, β and their first two s-derivatives at end e */
    double a0 = S->al[0], a1 = S->al[1], b0 = S->be[0], b1 = S->be[1];
    a[0] = e ? a1 : a0, b[0] = e ? b1 : b0;
    a[1] = a[2] = b[1] = b[2] = 0; /* the smoothsteps: flat to second order */
    if (S->poly) {
        double q = S->q;
        a[1] = e ? 2 * (a1 - q) : 2 * (q - a0), a[2] = 2 * (a0 - 2 * q + a1);
        b[1] = b1 - b0 + (e ? -S->bump : S->bump), b[2] = -2 * S->bump;
    } else if (fe_side_slopes(S)) { /* quintic: free slope, zero second derivative */
        a[1] = S->sl[0][e], b[1] = S->sl[1][e];
    }
    /* in a = s (end 0) or a = 1 - s (end 1); B(a) = β(a) at end 0 and -β(1 - a) at end 1 (∂s = -∂a there) */
    double sg = e ? -1 : 1;
    al[0] = a[0], al[1] = sg * a[1], al[2] = 0.5 * a[2];
    bt[0] = sg * b[0], bt[1] = b[1], bt[2] = sg * 0.5 * b[2];
}

/* The runs of lanes where some coefficient of T is nonzero: a side's fields involve the fixed lanes
 * and the unknowns of its two end vertices only, about half of an assembly's lanes. */
static void taylor_runs(fe_taylor *T)
{
    int W = T->W, n = 0, in = 0;
    for (int l = 0; l <= W; l++) {
        int nz = 0;
        for (int b = 0; l < W && b < 3 && !nz; b++)
            for (int e = 0; e < 2 && !nz; e++)
                for (int k = 0; k <= T->deg[b] && !nz; k++) nz = FE_TC(T, b, e, k)[l] != 0;
        if (nz && !in) {
            if (n == FE_TRUNS) { n = 1, T->run[0][0] = 0, T->run[0][1] = W; break; }
            T->run[n][0] = l, in = 1;
        } else if (!nz && in) {
            T->run[n++][1] = l, in = 0;
        }
    }
    T->nrun = n;
}

/* out[a] = a-th derivative at σ of the polynomial with coefficients c[0..n] (W lanes, nonzero only
 * in T's runs), a < na: repeated synthetic division (Horner), then a! */
static void taylor_eval(const fe_taylor *T, const double *c, int n, int W, double x, int na, double out[][CP_MAXW])
{
    for (int a = 0; a < na; a++) memset(out[a], 0, sizeof(double) * W);
    for (int r = 0; r < T->nrun; r++) {
        int l0 = T->run[r][0], l1 = T->run[r][1];
        for (int k = n; k >= 0; k--) {
            for (int a = na - 1; a >= 1; a--) {
                double *d = out[a], *dp = out[a - 1];
                for (int l = l0; l < l1; l++) d[l] = d[l] * x + dp[l];
            }
            const double *ck = c + (size_t)k * W;
            double *d = out[0];
            for (int l = l0; l < l1; l++) d[l] = d[l] * x + ck[l];
        }
        for (int a = 2; a < na; a++) {
            double f = a == 2 ? 2 : 6;
            for (int l = l0; l < l1; l++) out[a][l] *= f;
        }
    }
}

/* taylor_eval for the production patches' three lanes (x, y, z), the fit's hot path: the same
 * operations in the same order, the lanes held in registers instead of a loop of three. */
static void taylor_eval3(const double *c, int n, double x, int na, double out[][CP_MAXW])
{
    double d[CP_NA][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int k = n; k >= 0; k--) {
        for (int a = na - 1; a >= 1; a--)
            for (int l = 0; l < 3; l++) d[a][l] = d[a][l] * x + d[a - 1][l];
        const double *ck = c + 3 * (size_t)k;
        for (int l = 0; l < 3; l++) d[0][l] = d[0][l] * x + ck[l];
    }
    for (int a = 0; a < na; a++) {
        double f = a < 2 ? 1 : a == 2 ? 2 : 6;
        for (int l = 0; l < 3; l++) out[a][l] = a < 2 ? d[a][l] : d[a][l] * f;
    }
}

/* Parametric data of a constructed side at s: out[b][a] = ∂n^b ∂s^a with n the inward cross
 * parameter, b <= K, a < na (<= 4). */
static void constructed(int K, const fe_taylor *T, int W, double s, int na, double out[3][CP_NA][CP_MAXW])
{
    int e = s > 0.5;
    double x = s - e;
    for (int b = 0; b < 3; b++) {
        if (b > K) {
            for (int a = 0; a < na; a++) memset(out[b][a], 0, sizeof(double) * W);
            continue;
        }
        if (W == 3 && T->nrun == 1 && T->run[0][0] == 0 && T->run[0][1] == 3) taylor_eval3(FE_TC(T, b, e, 0), T->deg[b], x, na, out[b]);
        else taylor_eval(T, FE_TC(T, b, e, 0), T->deg[b], W, x, na, out[b]);
    }
}


/* Regular side: local data of the neighbour (q2n_ev_side_eval, along derivatives <= 2; the third by
 * central differences of the second, only the energy asks for it) times the local
 * parametrization function across the side (seed 003 §4, eq. 22–23). */
static void regular(const fe_ctx *X, int sd, double s, int na, double F[3][CP_NA][CP_MAXW])
{
    const fe_side *S = &X->side[sd];
    double loc[3][4][3], r[3][3][3], L[4];
    q2n_ev_side_eval(&S->reg, s, r);
    for (int b = 0; b < 3; b++)
        for (int a = 0; a < 3; a++) memcpy(loc[b][a], r[b][a], sizeof r[b][a]);
    if (na > 3) {
        const double h = 1e-4;
        double rp[3][3][3], rm[3][3][3];
        q2n_ev_side_eval(&S->reg, s + h, rp);
        q2n_ev_side_eval(&S->reg, s - h, rm);
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 3; c++) loc[b][3][c] = (rp[b][2][c] - rm[b][2][c]) / (2 * h);
    }
    if (q2n_side_along_u(sd)) q2n_spline_blend_derivs(X->kb, X->e0, X->e1, s, L); /* ε(u) */
    else q2n_spline_blend_derivs(X->kb, X->d0, X->d1, s, L);                   /* δ(v) */
    double L2[4] = {L[0] * L[0], 2 * L[0] * L[1], 2 * L[1] * L[1] + 2 * L[0] * L[2], 6 * L[1] * L[2] + 2 * L[0] * L[3]};
    double io = q2n_side_iota[sd];
    for (int a = 0; a < na; a++)
        for (int c = 0; c < 3; c++) {
            double f1 = 0, f2 = 0;
            for (int i = 0; i <= a; i++) {
                f1 += q2n_binom[a][i] * L[i] * loc[1][a - i][c];
                f2 += q2n_binom[a][i] * L2[i] * loc[2][a - i][c];
            }
            F[0][a][c] = loc[0][a][c];
            F[1][a][c] = io * f1;
            F[2][a][c] = f2;
        }
}

static void fe_side_fn(const void *ctx, const void *lanes, int W, int sd, double s, int na,
                       double F[3][CP_NA][CP_MAXW])
{
    const fe_ctx *X = ctx;
    const fe_side *S = &X->side[sd];
    if (S->kind == 1) {
        for (int b = 0; b < 3; b++)
            for (int a = 0; a < na; a++) memset(F[b][a], 0, sizeof(double) * W);
        regular(X, sd, s, na, F);
        return;
    }
    const fe_lanes *L = lanes;
    constructed(X->K, &L->T[sd], W, s, na, F); /* every lane of every row written */
    if (q2n_side_iota[sd] < 0) /* inward -> axis direction: the cross derivative's sign */
        for (int a = 0; a < na; a++)
            for (int l = 0; l < W; l++) F[1][a][l] = -F[1][a][l];
}


/* The lanes of a patch whose corner jets are J (W lanes each, slot-major): the constructed sides'
 * fields, in tayv (4 sides, FE_TAYLOR_SIZE(W) doubles each). */
void q2n_ev_fair_fill_lanes(const fe_ctx *X, const double *const J[4], int W, fe_lanes *L, double *tayv)
{
    double endv[FE_END_SIZE(CP_MAXW)];
    fe_ends E = {W, endv};
    for (int pass = 0; pass < 2; pass++) /* sides that take a twist from another side after it */
        for (int sd = 0; sd < 4; sd++) {
            const fe_side *S = &X->side[sd];
            int absorbs = S->absorb_side[0] >= 0 || S->absorb_side[1] >= 0;
            if (absorbs != pass) continue;
            fe_taylor *T = &L->T[sd];
            T->W = W;
            T->c = tayv + FE_TAYLOR_SIZE(W) * sd;
            T->deg[0] = T->deg[1] = T->deg[2] = 0;
            if (S->kind != 0) continue;
            side_ends(X->K, S, J[S->c0], J[S->c1], &E);
            for (int e = 0; e < 2; e++) { /* the corner's mixed derivative as the other side has it */
                if (S->absorb_side[e] < 0) continue;
                int eo = S->absorb_end[e];
                const double *tw = FE_TC(&L->T[S->absorb_side[e]], 1, eo, 1);
                double sg = (e ? -1 : 1) * (eo ? -1 : 1);
                for (int l = 0; l < W; l++) FE_END(&E, 1, e, 1)[l] = sg * tw[l];
            }
            side_taylor(X->K, S, &E, T);
            taylor_runs(T);
        }
}

void q2n_ev_fair_eval_free(void *d) { free(d); }

/* Direction of edge e in the chart of its end vertex v (dir of q2n_ev_vertex_jets). */
const double *q2n_ev_fair_edge_dir(const q2n_mesh *m, const double (*dir)[2], int e, int v)
{
    return dir[2 * e + (q2n_he_origin(m, m->edge_he[e]) == v ? 0 : 1)];
}

/* Solve w = α a + β b in the plane; 0 when a, b are parallel. */
static int solve2(const double w[2], const double a[2], const double b[2], double *al, double *be)
{
    double det = a[0] * b[1] - a[1] * b[0];
    if (!(fabs(det) > 1e-12 * (fabs(a[0]) + fabs(a[1])) * (fabs(b[0]) + fabs(b[1])))) return 0;
    *al = (w[0] * b[1] - w[1] * b[0]) / det;
    *be = (a[0] * w[1] - a[1] * w[0]) / det;
    return 1;
}

/* |sin| of the angle between a and b */
double q2n_ev_fair_sine2(const double a[2], const double b[2])
{
    double la = hypot(a[0], a[1]), lb = hypot(b[0], b[1]);
    return la > 0 && lb > 0 ? fabs(a[0] * b[1] - a[1] * b[0]) / (la * lb) : 0;
}

/* The other edge of face f at its vertex v, for its side on edge e (-1 if v is not a corner). */
int q2n_ev_fair_cross_edge(const q2n_mesh *m, int f, int e, int v)
{
    for (int i = 0; i < 4; i++) {
        int h = q2n_face_he(m, f, i), hp = q2n_he_prev(m, h);
        if (q2n_he_origin(m, h) != v) continue;
        return m->he_edge[h] == e ? m->he_edge[hp] : m->he_edge[h];
    }
    return -1;
}

/* The face's inward cross direction at vertex v for its side on edge e: the direction of its
 * other edge at v. */
const double *q2n_ev_fair_cross_dir(const q2n_mesh *m, const double (*dir)[2], int f, int e, int v)
{
    int other = q2n_ev_fair_cross_edge(m, f, e, v);
    return other < 0 ? NULL : q2n_ev_fair_edge_dir(m, dir, other, v);
}


q2n_status q2n_ev_fair_setup_patch(const fe_build *B, int f, fe_ctx *X, cp_patch *P, q2n_error *err)
{
    const q2n_mesh *m = B->m;
    memset(X, 0, sizeof *X);
    X->K = B->K;
    X->kb = B->kb;
    X->d0 = B->iv[m->he_edge[q2n_face_he(m, f, 0)]];
    X->e1 = B->iv[m->he_edge[q2n_face_he(m, f, 1)]];
    X->d1 = B->iv[m->he_edge[q2n_face_he(m, f, 2)]];
    X->e0 = B->iv[m->he_edge[q2n_face_he(m, f, 3)]];
    memset(P, 0, sizeof *P);
    P->K = B->K;
    P->side = fe_side_fn;
    P->ctx = X;
    for (int sd = 0; sd < 4; sd++) {
        int h = q2n_face_he(m, f, sd), t = m->he_twin[h], e = m->he_edge[h];
        fe_side *S = &X->side[sd];
        int along_h = q2n_side_forward(sd); /* side sd's parameter runs along h (patch/surface.h) */
        if (t >= 0 && !B->unc[m->he_face[t]]) {
            int g = m->he_face[t], sR = t - m->face_start[g];
            q2n_augmented_patch Rp, *R = &Rp;
            if (!q2n_augmented_patch_get(B->s, g, &Rp)) return q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: no regular patch data", m->name, g);
            S->kind = 1;
            S->reg.kind = 1;
            S->reg.R = *R;
            S->reg.sR = sR;
            S->reg.rev = (!q2n_side_forward(sR)) != along_h; /* R runs along t (= against h) on its sides 0, 1 */
            continue;
        }
        S->kind = 0;
        fe_side_smooth(S);
        S->c0 = q2n_side_first(sd);
        S->c1 = q2n_side_last(sd);
        S->d = B->iv[e];
        int v0 = m->face_vert[m->face_start[f] + S->c0], v1 = m->face_vert[m->face_start[f] + S->c1];
        memcpy(S->u0, q2n_ev_fair_edge_dir(m, B->dir, e, v0), sizeof S->u0);
        memcpy(S->u1, q2n_ev_fair_edge_dir(m, B->dir, e, v1), sizeof S->u1);
        int fb = B->base[e];
        S->derived = fb != f;
        const double *wb0 = q2n_ev_fair_cross_dir(m, B->dir, fb, e, v0), *wb1 = q2n_ev_fair_cross_dir(m, B->dir, fb, e, v1);
        if (!wb0 || !wb1) return q2n_error_set(err, Q2N_ERR_ARG, "%s: edge %d: inconsistent faces", m->name, e);
        memcpy(S->w0, wb0, sizeof S->w0);
        memcpy(S->w1, wb1, sizeof S->w1);
        S->ew[0] = B->iv[q2n_ev_fair_cross_edge(m, fb, e, v0)];
        S->ew[1] = B->iv[q2n_ev_fair_cross_edge(m, fb, e, v1)];
        if (S->derived) {
            /* w_G = α w_F + β u in each end's chart (u at end 1 is -u1); parametric: the cross
             * derivatives carry the cross edges' intervals, the tangent γ_t the edge's */
            const double *w0 = q2n_ev_fair_cross_dir(m, B->dir, f, e, v0), *w1 = q2n_ev_fair_cross_dir(m, B->dir, f, e, v1);
            double mu1[2] = {-S->u1[0], -S->u1[1]};
            if (!w0 || !w1 || !solve2(w0, S->w0, S->u0, &S->al[0], &S->be[0]) ||
                !solve2(w1, S->w1, mu1, &S->al[1], &S->be[1]))
                return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                                     "%s: edge %d: the two faces' cross directions are parallel to the edge",
                                     m->name, e);
            for (int k = 0; k < 2; k++) {
                double eg = B->iv[q2n_ev_fair_cross_edge(m, f, e, k ? v1 : v0)];
                S->al[k] *= eg / S->ew[k];
                S->be[k] *= eg / S->d;
            }
        }
    }
    return Q2N_OK;
}

/* Patch i of the list (face f, context FX) with the current jets and bubbles, ready to evaluate
 * (the production evaluator's state: the caller frees it). */
fe_eval *q2n_ev_fair_make_eval(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P)
{
    fe_eval *E = calloc(1, sizeof *E);
    if (!E) return NULL;
    E->X = *FX;
    E->E.P = *P;
    E->E.P.ctx = &E->X;
    const double *Jc[4];
    for (int c = 0; c < 4; c++) Jc[c] = &B->jet[B->m->face_vert[B->m->face_start[f] + c]][0][0];
    q2n_ev_fair_fill_lanes(&E->X, Jc, 3, &E->lanes, &E->tayv[0][0]);
    E->E.lanes = &E->lanes;
    memcpy(E->E.bub, B->bub[i], sizeof E->E.bub);
    q2n_cp_eval_init(&E->E);
    return E;
}
