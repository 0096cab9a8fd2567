/* ev_fair.c — the fair extraordinary construction: one jet per vertex, compatible Coons patches,
 * jets and interior bubbles chosen by a fairness-energy solve (issue 11; docs/extraordinary.md).
 *
 * Every vertex that is a corner of an extraordinary face gets ONE jet P_v of order 2K (4 in G2
 * mode, 2 in G1 mode) in its chart (ev_jet4.h; the charts are the edge directions of
 * q2n_ev_vertex_jets).  Every datum of the curve network is a contraction of the jets at the two ends
 * of its edge, parametric in the edge's t in [0,1] (d: the edge's interval, u: its direction in
 * an end's chart, w: the face's other edge there, e_w that edge's interval):
 *   γ(t)    boundary curve: Hermite interpolant of order 2K (degree 4K+1) of d^j T_j[u^j];
 *   χ_F(t)  inward cross derivative of the base face F: order 2K-1 Hermite interpolant of
 *           d^j e_w T_(j+1)[u^j, w];
 *   ξ_F(t)  (G2) second cross derivative: order 2K-2 interpolant of d^j e_w² T_(j+2)[u^j, w, w];
 *   derived face G: χ_G = α χ_F + β γ_t, ξ_G = α² ξ_F + 2αβ ∂t χ_F + β² γ_tt (formulas.md §4.2
 *           with its γ, δ terms zero), α, β smoothsteps of order K between their end values, which
 *           solve e_w' w' = α e_w w + β d u in each end's chart.
 * So G1 (G2) holds exactly along every constructed edge for ANY jets, and every mixed corner
 * derivative a side delivers is the jet's (α, β are flat at the ends, the corner maps linear):
 * the two sides of every corner agree and the patch (coons_patch.c) is the plain Boolean-sum Coons
 * patch with polynomial corner terms — no rational Gregory blend, no corrective bumps.  Sides
 * shared with a regular augmented patch take that patch's data (q2n_ev_side_eval, §4.1); at their
 * vertices the jet's terms with both exponents <= 2 are the regular patch's (Lemma 1), so those
 * corners agree too (checked; a corner where they do not keeps a Gregory blend, counted).
 *
 * The patches are linear in the jets' free coefficients (all but the position and, at vertices
 * of regular patches, the terms with both exponents <= 2) and in CP_NBUB interior bubbles per
 * face.  They minimise a fairness energy over the extraordinary faces, in each face's
 * arc-length-scaled parameters x = u L_u, y = v L_v:
 *     E = Σ_F ∫ |S_xx|² + 2|S_xy|² + |S_yy|² dA  +  w3 Σ_F ω_F L_F² ∫ |S_xxx|² + 3|S_xxy|² + 3|S_xyy|² + |S_yyy|² dA,
 * bending (thin plate) plus curvature variation (Moreton–Séquin's minimal-variation term), both
 * dimensionless; ω_F lowers the variation term on faces where a first, bending-only solve leaves
 * far more variation than on the typical face (thin features whose curvature must change fast:
 * they would otherwise dictate the shape everywhere).  A small ridge towards the local estimates
 * of q2n_ev_vertex_jets keeps the problem definite.  One sparse SPD solve (CHOLMOD) per pass, shared
 * by x, y and z. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <pthread.h>

#include "core/dense.h"
#include "core/par.h"
#include "core/sparse.h"
#include "core/poly.h"
#include "core/vec3.h"
#include "patch/coons_patch.h"
#include "patch/ev_fair.h"
#include "patch/ev_jet4.h"
#include "patch/ev_policy.h"

typedef struct fe_side {
    int kind;            /* 0 constructed from the jets, 1 sampled from a regular neighbour */
    ev_side reg;         /* kind 1 */
    int c0, c1;          /* kind 0: patch corners at s = 0 and s = 1 */
    double d;            /* the edge's interval */
    double u0[2], u1[2]; /* the edge's direction in the charts of its two end vertices */
    double w0[2], w1[2]; /* the base face's inward cross direction at the two ends */
    double ew[2];        /* the base face's cross-edge intervals at the two ends */
    int derived;         /* this face is the derived side */
    double al[2], be[2]; /* α, β at the two ends */
} fe_side;

/* Side context of one patch (the Coons patch's ctx); lanes: fe_lanes, its constructed sides' fields
 * as polynomials (fill_lanes, from the W-wide jets of the four corners). */
typedef struct fe_ctx {
    int K, kb;
    double d0, d1, e0, e1; /* intervals of sides 0, 2 (u) and 3, 1 (v) */
    fe_side side[4];
} fe_ctx;


/* ------------------------------------------------------------ side data (W lanes) */

/* Hermite end data of a constructed side: the jet contractions at both ends, for γ (order 2K),
 * χ_F (2K - 1) and ξ_F (2K - 2).  A patch turns them into its sides' polynomials once (fill_lanes,
 * side_taylor); an evaluation is then a Horner sum. */
typedef struct fe_ends {
    int W;
    double *e; /* [γ|χ|ξ][end][j <= 4][lane]: FE_END(E, p, end, j) */
} fe_ends;
#define FE_END(E, p, end, j) ((E)->e + (size_t)((((p) * 2 + (end)) * 5) + (j)) * (E)->W)
#define FE_END_SIZE(W) ((size_t)3 * 2 * 5 * (W))


/* End data of side S: d^j s T_(j+p)[u^j, w^p] at both ends, j <= 2K - p, p <= K (s: the cross-edge
 * interval to the power p). */
static void side_ends(int K, const fe_side *S, const double *T0, const double *T1, fe_ends *E)
{
    int Kc = 2 * K, W = E->W;
    memset(E->e, 0, sizeof(double) * FE_END_SIZE(W));
    for (int p = 0; p <= K; p++) {
        double s0 = p == 0 ? 1 : p == 1 ? S->ew[0] : S->ew[0] * S->ew[0];
        double s1 = p == 0 ? 1 : p == 1 ? S->ew[1] : S->ew[1] * S->ew[1];
        for (int j = 0; j <= Kc - p; j++) {
            ev_jet_contract(T0, W, j, S->u0, p, S->w0, pow(S->d, j) * s0, FE_END(E, p, 0, j));
            ev_jet_contract(T1, W, j, S->u1, p, S->w1, pow(-S->d, j) * s1, FE_END(E, p, 1, j));
        }
    }
}

/* The sides' three fields as polynomials in s, expanded about both ends: FE_TC(T, b, e, k) is the
 * coefficient of (s - e)^k in field b (γ, then the face's first and second cross derivatives), k <=
 * deg[b].  An evaluation expands about the nearer end (|s - e| <= 1/2: no cancellation grows with the
 * degree), and at the ends the coefficients are the end data themselves (divided by k!): the
 * corner values are exact. */
#define FE_TDEG 17 /* ξ_G of order K = 2: degree 2(2K + 1) + 4K - 1 */
#define FE_TRUNS 8  /* runs of nonzero lanes an evaluation visits (more: all lanes) */
typedef struct fe_taylor {
    int W, deg[3];
    double *c;
    int nrun, run[FE_TRUNS][2]; /* the lanes [run[r][0], run[r][1]) hold every nonzero coefficient */
} fe_taylor;
#define FE_TC(T, b, e, k) ((T)->c + (size_t)((((b) * 2 + (e)) * (FE_TDEG + 1)) + (k)) * (T)->W)
#define FE_TAYLOR_SIZE(W) ((size_t)3 * 2 * (FE_TDEG + 1) * (W))

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

/* The smoothstep of order K from v0 to v1 (v0 + (v1 - v0) H_{0,1} = v1 - (v1 - v0) H_{0,0}) about end
 * e: n + 1 = 2K + 2 coefficients. */
static void smooth_taylor(int K, double v0, double v1, int e, double *out)
{
    const double *h = q2n_hermite_coef[K - 1][0][1];
    int n = 2 * K + 1;
    for (int k = 0; k <= n; k++) out[k] = e ? -(v1 - v0) * ((k & 1) ? -h[k] : h[k]) : (v1 - v0) * h[k];
    out[0] = e ? v1 : v0;
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
        hermite_taylor(Kc, E, 0, e, W, FE_TC(T, 0, e, 0));
        if (!S->derived) {
            hermite_taylor(Kc - 1, E, 1, e, W, FE_TC(T, 1, e, 0));
            if (K >= 2) hermite_taylor(Kc - 2, E, 2, e, W, FE_TC(T, 2, e, 0));
            continue;
        }
        double c[(FE_TDEG + 1) * CP_MAXW], x[(FE_TDEG + 1) * CP_MAXW];
        double al[2 * Q2N_HERMITE_MAXK + 2], be[2 * Q2N_HERMITE_MAXK + 2];
        hermite_taylor(Kc - 1, E, 1, e, W, c);
        smooth_taylor(K, S->al[0], S->al[1], e, al);
        smooth_taylor(K, S->be[0], S->be[1], e, be);
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
    }
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

/* The lanes a fair patch's side function reads: its sides' fields (fill_lanes). */
typedef struct fe_lanes {
    fe_taylor T[4];
} fe_lanes;

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
    for (int b = 0; b < 3; b++)
        for (int a = 0; a < na; a++) memset(F[b][a], 0, sizeof(double) * W);
    if (S->kind == 1) {
        regular(X, sd, s, na, F);
        return;
    }
    const fe_lanes *L = lanes;
    double loc[3][CP_NA][CP_MAXW];
    constructed(X->K, &L->T[sd], W, s, na, loc);
    double io = q2n_side_iota[sd]; /* inward -> axis direction */
    for (int a = 0; a < na; a++)
        for (int l = 0; l < W; l++) {
            F[0][a][l] = loc[0][a][l];
            F[1][a][l] = io * loc[1][a][l];
            F[2][a][l] = loc[2][a][l];
        }
}

/* The production patch: the Coons evaluator first (the surface's data pointer is this struct). */
typedef struct fe_eval {
    cp_eval E;
    fe_ctx X;
    fe_lanes lanes;
    double tayv[4][FE_TAYLOR_SIZE(3)];
} fe_eval;

/* The lanes of a patch whose corner jets are J (W lanes each, slot-major): the constructed sides'
 * fields, in tayv (4 sides, FE_TAYLOR_SIZE(W) doubles each). */
static void fill_lanes(const fe_ctx *X, const double *const J[4], int W, fe_lanes *L, double *tayv)
{
    double endv[FE_END_SIZE(CP_MAXW)];
    fe_ends E = {W, endv};
    for (int sd = 0; sd < 4; sd++) {
        fe_taylor *T = &L->T[sd];
        T->W = W;
        T->c = tayv + FE_TAYLOR_SIZE(W) * sd;
        T->deg[0] = T->deg[1] = T->deg[2] = 0;
        if (X->side[sd].kind != 0) continue;
        side_ends(X->K, &X->side[sd], J[X->side[sd].c0], J[X->side[sd].c1], &E);
        side_taylor(X->K, &X->side[sd], &E, T);
        taylor_runs(T);
    }
}

static void fe_eval_free(void *d) { free(d); }

/* ------------------------------------------------------------ the driver */

/* Direction of edge e in the chart of its end vertex v (dir of q2n_ev_vertex_jets). */
static const double *edge_dir(const q2n_mesh *m, const double (*dir)[2], int e, int v)
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
static double sine2(const double a[2], const double b[2])
{
    double la = hypot(a[0], a[1]), lb = hypot(b[0], b[1]);
    return la > 0 && lb > 0 ? fabs(a[0] * b[1] - a[1] * b[0]) / (la * lb) : 0;
}

/* The other edge of face f at its vertex v, for its side on edge e (-1 if v is not a corner). */
static int cross_edge(const q2n_mesh *m, int f, int e, int v)
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
static const double *cross_dir(const q2n_mesh *m, const double (*dir)[2], int f, int e, int v)
{
    int other = cross_edge(m, f, e, v);
    return other < 0 ? NULL : edge_dir(m, dir, other, v);
}

/* The ridge of an unknown towards its local estimate (fair_pass). */
typedef enum { RIDGE_HIGH = 0, RIDGE_LOW = 1, RIDGE_HELD = 2 } fe_ridge; /* orders 3, 4 and bubbles; orders 1, 2; held by the fold guard */

typedef struct fe_build {
    const q2n_mesh *m;
    const q2n_surface *s;
    const double *iv;
    const double (*dir)[2];
    const char *unc;
    int K, kb;
    int *base;                  /* per edge: base face (-1 when not constructed) */
    double (*jet)[EV_JS][3];    /* per vertex: current jet values */
    int *var;                   /* per vertex and slot: unknown index or -1 (fixed) */
    int *bvar;                  /* per face of the list: first of its CP_NBUB bubble unknowns */
    double (*bub)[CP_NBUB][3];  /* per face of the list: bubble values */
    char *ridge;                /* per unknown: its ridge towards the local estimate, an fe_ridge */
    int nvar;
    const char *flat;           /* per vertex: its fan is flat (fan_flat) and the first solve keeps its
                                   free jet terms in the plane (coupled_solve); NULL: none */
    const double (*flatn)[3];   /* per vertex: the unit normal of a flat fan's plane */
} fe_build;

/* Slots that are unknowns at a vertex: every slot of order 1..Kc, except at vertices of regular
 * patches the terms with both exponents <= 2 (fixed by that patch, Lemma 1). */
static int slot_free(int Kc, int fixed, int j, int i)
{
    if (j < 1 || j > Kc) return 0;
    if (!fixed) return 1;
    return j - i > 2 || i > 2;
}

static q2n_status setup_patch(const fe_build *B, int f, fe_ctx *X, cp_patch *P, q2n_error *err)
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
        S->c0 = q2n_side_first(sd);
        S->c1 = q2n_side_last(sd);
        S->d = B->iv[e];
        int v0 = m->face_vert[m->face_start[f] + S->c0], v1 = m->face_vert[m->face_start[f] + S->c1];
        memcpy(S->u0, edge_dir(m, B->dir, e, v0), sizeof S->u0);
        memcpy(S->u1, edge_dir(m, B->dir, e, v1), sizeof S->u1);
        int fb = B->base[e];
        S->derived = fb != f;
        const double *wb0 = cross_dir(m, B->dir, fb, e, v0), *wb1 = cross_dir(m, B->dir, fb, e, v1);
        if (!wb0 || !wb1) return q2n_error_set(err, Q2N_ERR_ARG, "%s: edge %d: inconsistent faces", m->name, e);
        memcpy(S->w0, wb0, sizeof S->w0);
        memcpy(S->w1, wb1, sizeof S->w1);
        S->ew[0] = B->iv[cross_edge(m, fb, e, v0)];
        S->ew[1] = B->iv[cross_edge(m, fb, e, v1)];
        if (S->derived) {
            /* w_G = α w_F + β u in each end's chart (u at end 1 is -u1); parametric: the cross
             * derivatives carry the cross edges' intervals, the tangent γ_t the edge's */
            const double *w0 = cross_dir(m, B->dir, f, e, v0), *w1 = cross_dir(m, B->dir, f, e, v1);
            double mu1[2] = {-S->u1[0], -S->u1[1]};
            if (!w0 || !w1 || !solve2(w0, S->w0, S->u0, &S->al[0], &S->be[0]) ||
                !solve2(w1, S->w1, mu1, &S->al[1], &S->be[1]))
                return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                                     "%s: edge %d: the two faces' cross directions are parallel to the edge",
                                     m->name, e);
            for (int k = 0; k < 2; k++) {
                double eg = B->iv[cross_edge(m, f, e, k ? v1 : v0)];
                S->al[k] *= eg / S->ew[k];
                S->be[k] *= eg / S->d;
            }
        }
    }
    return Q2N_OK;
}

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
    fill_lanes(P->ctx, J, W, &L, tayv);
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
        lam[x] = (B->ridge[x] == RIDGE_HELD ? EV_FOLD_HOLD : B->ridge[x] == RIDGE_LOW ? EV_FAIR_RIDGE_LOW : EV_FAIR_RIDGE_HIGH) * diag[x];
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

/* Patch i of the list (face f, context FX) with the current jets and bubbles, ready to evaluate
 * (the production evaluator's state: the caller frees it). */
static fe_eval *make_eval(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P)
{
    fe_eval *E = calloc(1, sizeof *E);
    if (!E) return NULL;
    E->X = *FX;
    E->E.P = *P;
    E->E.P.ctx = &E->X;
    const double *Jc[4];
    for (int c = 0; c < 4; c++) Jc[c] = &B->jet[B->m->face_vert[B->m->face_start[f] + c]][0][0];
    fill_lanes(&E->X, Jc, 3, &E->lanes, &E->tayv[0][0]);
    E->E.lanes = &E->lanes;
    memcpy(E->E.bub, B->bub[i], sizeof E->E.bub);
    q2n_cp_eval_init(&E->E);
    return E;
}

/* Does patch i fold: do the normals of two neighbouring points of an EV_FOLD_GRID grid point
 * away from each other?  A smooth patch turns them by a small angle per grid step; a fold turns
 * them over.  -1 when it cannot be evaluated. */
static int patch_folds(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P)
{
    enum { NG = EV_FOLD_GRID };
    double t[NG], out[NG * NG * 9], nrm[NG * NG][3];
    for (int a = 0; a < NG; a++) t[a] = (double)a / (NG - 1);
    fe_eval *E = make_eval(B, i, f, FX, P);
    if (!E) return -1;
    q2n_status st = q2n_cp_eval_grid(E, NG, t, NG, t, out);
    free(E);
    if (st) return -1;
    for (int q = 0; q < NG * NG; q++) q2n_v3_cross(nrm[q], out + 9 * q + 3, out + 9 * q + 6);
    for (int b = 0; b < NG; b++)
        for (int a = 0; a < NG; a++) {
            const double *n0 = nrm[b * NG + a];
            if ((a + 1 < NG && q2n_v3_dot(n0, nrm[b * NG + a + 1]) < 0) || (b + 1 < NG && q2n_v3_dot(n0, nrm[(b + 1) * NG + a]) < 0))
                return 1;
        }
    return 0;
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

/* A bending-only pass, the variation weights ω_F from its result, then the full pass (X: the
 * solution; v3, srt: nfaces doubles of work space). */
static q2n_status energy_passes(const fe_build *B, fe_sys *Y, int nfaces, const fe_form *F, double *v3, double *srt,
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
        v3[fi] = srt[fi] = e;
    }
    qsort(srt, (size_t)nfaces, sizeof *srt, cmp_dbl);
    double cap = EV_FAIR_VAR_OUTLIER * srt[nfaces / 2];
    for (int fi = 0; fi < nfaces; fi++) v3[fi] = cap > 0 && v3[fi] > cap ? cap / v3[fi] : 1;
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

/* The folded faces of the current solution (patch_folds, on `threads` workers); the corners of
 * each that are not held yet are held from now on (their jets of orders 1 and 2 get the
 * EV_FOLD_HOLD ridge), counted in *held_vertices.  Returns the number of folded faces, -1 out of
 * memory. */
static int fold_scan(fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX, int threads,
                     char *held, int *held_vertices)
{
    const q2n_mesh *m = B->m;
    fold_arg a = {B, faces, P, FX, malloc((size_t)nfaces)};
    if (!a.r) return -1;
    q2n_par_for(nfaces, threads, fold_one, &a);
    int folded = 0;
    for (int fi = 0; fi < nfaces; fi++) {
        if (a.r[fi] < 0) { folded = -1; break; }
        if (!a.r[fi]) continue;
        folded++;
        for (int c = 0; c < 4; c++) {
            int v = m->face_vert[m->face_start[faces[fi]] + c];
            if (held[v]) continue;
            held[v] = 1;
            ++*held_vertices;
            for (int k = EV_SLOT(1, 0); k <= EV_SLOT(2, 2); k++)
                if (B->var[v * EV_JS + k] >= 0) B->ridge[B->var[v * EV_JS + k]] = RIDGE_HELD;
        }
    }
    free(a.r);
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
    double *v3, *srt; /* nfaces doubles each (energy_passes) */
    char *held;       /* per vertex: its jets held by the guard */
    int nheld;        /* vertices held so far */
} fe_solve;

/* energy_passes towards x0, the jets and bubbles from the solution X, then fold_scan (holding the
 * corners of faces that fold); *folded: their number. */
static q2n_status solve_scan(fe_solve *S, const double *x0, double *X, int *folded, q2n_error *err)
{
    q2n_status st = energy_passes(S->B, S->Y, S->nfaces, S->F, S->v3, S->srt, x0, X, err);
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
static q2n_status fair_solve(fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX,
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
    double *v3 = malloc((size_t)nfaces * sizeof *v3), *srt = malloc((size_t)nfaces * sizeof *srt);
    char *held = calloc((size_t)m->nv, 1);
    int folds0 = 0;
    if (!F || !jobs || !tid || !x0 || !X || !X0 || !v3 || !srt || !held) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair solve)"); goto done; }
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
    fe_solve S = {B, &Y, F, faces, nfaces, P, FX, threads, v3, srt, held, 0};
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
    free(srt);
    return st;
}

/* Is vertex v's fan flat: at least two faces around v, and every corner of every one of them
 * within EV_FLAT_REL of the fan's radius from the tangent plane of v's local estimate (unit
 * normal into n)?  That estimate is then exact, and the energy may not bend the plane
 * (docs/extraordinary.md, "Flat fans"); a lone face says too little. */
static int fan_flat(const q2n_mesh *m, int v, const ev_vjet *J, double n[3])
{
    return q2n_ev_jet_normal(J, n) && q2n_ev_fan_in_plane(m, v, n) >= 2;
}

/* Between the two solves of --keep-flat: the free terms of the flat fans lose what is left of their
 * normal parts (the second solve holds them fixed), every other jet returns to its local estimate
 * (the ridge's target again) and the nf faces' bubbles to zero. */
static void fix_flat_jets(fe_build *B, const char *flat, const double (*flatn)[3], const double (*jet0)[EV_JS][3], int nf)
{
    for (int v = 0; v < B->m->nv; v++) {
        if (!flat[v]) {
            memcpy(B->jet[v], jet0[v], sizeof jet0[v]);
            continue;
        }
        for (int k = 0; k < EV_JS; k++) {
            if (B->var[v * EV_JS + k] < 0) continue; /* the estimates and a regular patch's terms stay */
            double *T = B->jet[v][k], d = q2n_v3_dot(T, flatn[v]);
            for (int c = 0; c < 3; c++) T[c] -= d * flatn[v][c];
        }
    }
    memset(B->bub, 0, (size_t)nf * sizeof *B->bub);
}

/* Number the unknowns: the free jet slots of every vertex with a jet (slot_free), except those of
 * the vertices marked in skip and those of orders 1 and 2 of the vertices marked in low (NULL:
 * none), then CP_NBUB bubbles per face of the list. */
static void assign_unknowns(fe_build *B, const ev_vjet *vj, int nf, const char *skip, const char *low)
{
    int Kc = 2 * B->K;
    B->nvar = 0;
    for (int i = 0; i < B->m->nv * EV_JS; i++) B->var[i] = -1;
    for (int v = 0; v < B->m->nv; v++) {
        if (!vj[v].source || (skip && skip[v])) continue;
        for (int j = (low && low[v]) ? 3 : 1; j <= Kc; j++)
            for (int i = 0; i <= j; i++)
                if (slot_free(Kc, vj[v].source == 1, j, i)) B->var[v * EV_JS + EV_SLOT(j, i)] = B->nvar++;
    }
    for (int i = 0; i < nf; i++) {
        B->bvar[i] = B->nvar;
        B->nvar += CP_NBUB;
    }
}

q2n_status q2n_ev_fair_build(const q2n_mesh *m, q2n_surface *s, const double *iv, const q2n_spline_class *cls, int K,
                         int keep_flat, int threads, ev_fair_stats *stats, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    fe_build B = {0};
    B.m = m;
    B.s = s;
    B.iv = iv;
    B.K = K;
    B.kb = cls->k;
    int nf = 0;
    ev_vjet *vj = calloc((size_t)m->nv, sizeof *vj);
    double (*dir)[2] = calloc(2 * (size_t)m->ne, sizeof *dir);
    char *unc = calloc((size_t)m->nf, 1);
    int *faces = malloc((size_t)m->nf * sizeof *faces);
    double (*jet0)[EV_JS][3] = calloc((size_t)m->nv, sizeof *jet0);
    char *flat = calloc((size_t)m->nv, 1);
    double (*flatn)[3] = calloc((size_t)m->nv, sizeof *flatn);
    int nflat = 0;
    fe_ctx *X = calloc((size_t)m->nf, sizeof *X);
    cp_patch *CP = calloc((size_t)m->nf, sizeof *CP);
    B.jet = calloc((size_t)m->nv, sizeof *B.jet);
    B.var = malloc((size_t)m->nv * EV_JS * sizeof *B.var);
    B.base = malloc((size_t)m->ne * sizeof *B.base);
    B.bvar = malloc((size_t)m->nf * sizeof *B.bvar);
    B.bub = calloc((size_t)m->nf, sizeof *B.bub);
    if (stats) memset(stats, 0, sizeof *stats);
    if (!vj || !dir || !unc || !faces || !jet0 || !flat || !flatn || !X || !CP || !B.jet || !B.var || !B.base || !B.bvar || !B.bub) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair extraordinary construction)");
        goto done;
    }
    B.dir = (const double (*)[2])dir;
    B.unc = unc;
    for (int f = 0; f < m->nf; f++)
        if ((unc[f] = q2n_surface_kind(s, f) == Q2N_PATCH_UNCOVERED)) faces[nf++] = f;
    if ((st = q2n_ev_vertex_jets(m, s, iv, cls, 0, vj, dir, err))) goto done;

    /* jets: initial values (the local estimates; orders 3, 4 zero) and unknowns */
    for (int v = 0; v < m->nv; v++) {
        if (!vj[v].source) continue;
        double (*T)[3] = jet0[v];
        memcpy(T[0], q2n_mesh_vpos(m, v), 3 * sizeof(double));
        for (int c = 0; c < 3; c++) {
            T[EV_SLOT(1, 0)][c] = vj[v].J1[c][0];
            T[EV_SLOT(1, 1)][c] = vj[v].J1[c][1];
            T[EV_SLOT(2, 0)][c] = vj[v].J2[c][0];
            T[EV_SLOT(2, 1)][c] = vj[v].J2[c][1];
            T[EV_SLOT(2, 2)][c] = vj[v].J2[c][2];
            if (vj[v].source == 1) {
                T[EV_SLOT(3, 1)][c] = vj[v].Jm[c][0];
                T[EV_SLOT(3, 2)][c] = vj[v].Jm[c][1];
                T[EV_SLOT(4, 2)][c] = vj[v].Jm[c][2];
            }
        }
        if (keep_flat && fan_flat(m, v, &vj[v], flatn[v])) {
            flat[v] = 1;
            nflat++;
        }
        if (stats) stats->vertices++, stats->fixed_vertices += vj[v].source == 1;
    }
    if (stats) stats->flat_vertices = nflat;
    assign_unknowns(&B, vj, nf, NULL, nflat ? flat : NULL);
    memcpy(B.jet, jet0, (size_t)m->nv * sizeof *jet0);

    /* constructed edges and their base faces: the face whose cross direction is the more
     * transversal to the edge at its worse end (α = ratio of the transversal parts stays moderate);
     * within EV_BASE_TIE of a tie the edge's owner face, so that rounding-level changes of a
     * symmetric mesh do not flip the choice (docs/extraordinary.md, "Base faces") */
    for (int e = 0; e < m->ne; e++) {
        B.base[e] = -1;
        int h = m->edge_he[e], t = m->he_twin[h], f0 = m->he_face[h], f1 = t >= 0 ? m->he_face[t] : -1;
        int c0 = unc[f0], c1 = f1 >= 0 && unc[f1];
        if (!(c0 || c1) || (f1 >= 0 && (!c0 || !c1))) continue; /* not constructed */
        if (stats) stats->edges++;
        if (f1 < 0) { B.base[e] = f0; continue; }
        int va = q2n_he_origin(m, h), vb = q2n_he_dest(m, h);
        double q[2];
        for (int k = 0; k < 2; k++) {
            int f = k ? f1 : f0;
            const double *wa = cross_dir(m, B.dir, f, e, va), *wb = cross_dir(m, B.dir, f, e, vb);
            q[k] = fmin(sine2(wa, edge_dir(m, B.dir, e, va)), sine2(wb, edge_dir(m, B.dir, e, vb)));
        }
        B.base[e] = q[1] > q[0] * (1.0 + EV_BASE_TIE) ? f1 : f0;
    }
    for (int i = 0; i < nf && !st; i++) st = setup_patch(&B, faces[i], &X[i], &CP[i], err);
    if (st) goto done;

    /* corners whose two sides disagree (possible only where a side comes from a regular patch:
     * constructed data are jet contractions, and they involve only the fixed terms there) keep a
     * Gregory blend */
    for (int i = 0; i < nf; i++) {
        double ctv[3 * 36 * 3], tayv[4 * FE_TAYLOR_SIZE(3)];
        cp_corner C = {3, ctv};
        const double *J[4];
        fe_lanes L;
        for (int c = 0; c < 4; c++) J[c] = &B.jet[m->face_vert[m->face_start[faces[i]] + c]][0][0];
        fill_lanes(&X[i], J, 3, &L, tayv);
        q2n_cp_corner_terms(&CP[i], &L, 3, &C);
        for (int ci = 0; ci < 2; ci++)
            for (int cj = 0; cj < 2; cj++) {
                double mis = q2n_cp_corner_mismatch(&CP[i], &C, ci, cj);
                if (mis > EV_FAIR_COMPAT_REL) {
                    CP[i].greg[q2n_corner_at(ci, cj)] = 1;
                    if (stats) stats->gregory_corners++;
                }
                if (stats) stats->corner_mismatch_max = fmax(stats->corner_mismatch_max, mis);
            }
    }

    int held = 0, folds = 0, shrinks = 0;
    /* with flat fans (keep_flat): their jets' orders 1 and 2 are the local estimates, exact for planar
     * data; a first solve keeps their higher orders in the plane up to EV_FLAT_PENALTY
     * (coupled_solve), those then lose what is left of their normal parts and are fixed, and a
     * second solve fits everything else to them (docs/extraordinary.md, "Flat fans") */
    for (int stage = 0; stage < (nflat ? 2 : 1); stage++) {
        if (stage == 1) {
            fix_flat_jets(&B, flat, (const double (*)[3])flatn, (const double (*)[EV_JS][3])jet0, nf);
            B.flat = NULL;
            assign_unknowns(&B, vj, nf, flat, NULL);
        } else if (nflat) {
            B.flat = flat;
            B.flatn = (const double (*)[3])flatn;
        }
        free(B.ridge);
        if (!(B.ridge = calloc((size_t)(B.nvar ? B.nvar : 1), 1))) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory"); goto done; }
        for (int i = 0; i < m->nv * EV_JS; i++)
            if (B.var[i] >= 0) B.ridge[B.var[i]] = i % EV_JS <= EV_SLOT(2, 2) ? RIDGE_LOW : RIDGE_HIGH;
        if ((st = fair_solve(&B, faces, nf, CP, X, threads, &held, &folds, &shrinks, err))) goto done;
    }
    if (stats) stats->unknowns = B.nvar, stats->held_vertices = held, stats->folded_faces = folds, stats->shrinks = shrinks;

    for (int i = 0; i < nf; i++) {
        int f = faces[i];
        fe_eval *E = make_eval(&B, i, f, &X[i], &CP[i]);
        if (!E) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (patch %d)", f); goto done; }
        if ((st = q2n_surface_set_patch(s, f, Q2N_PATCH_COONS_GREGORY, E, q2n_cp_eval_point, fe_eval_free))) {
            free(E);
            q2n_error_set(err, st, "%s: face %d: cannot attach the patch", m->name, f);
            goto done;
        }
        q2n_surface_set_patch_grid(s, f, q2n_cp_eval_grid);
        q2n_surface_set_patch_grid_pos(s, f, q2n_cp_eval_grid_pos);
        q2n_surface_set_patch_corner(s, f, q2n_cp_eval_corner);
    }
done:
    free(vj);
    free(dir);
    free(unc);
    free(faces);
    free(jet0);
    free(flat);
    free(flatn);
    free(X);
    free(CP);
    free(B.jet);
    free(B.var);
    free(B.base);
    free(B.bvar);
    free(B.bub);
    free(B.ridge);
    return st;
}
