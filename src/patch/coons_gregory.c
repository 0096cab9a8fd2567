/* coons_gregory.c — augmented Coons–Gregory patches (seed 003 §4.1 eq. (23), §4.2) and the
 * driver that gives every face left uncovered by the regular construction such a patch.
 *
 * Patch.  Data on [0,1]^2 (corners p0 (0,0), p1 (1,0), p2 (1,1), p3 (0,1)), side 0 v=0, side 1
 * u=1, side 2 v=1, side 3 u=0.  Each side carries local data (γ, inward χ, ξ; ev_side_eval) in
 * its edge's local variable; the patch sees them in (u,v) as
 *     ∂v^0 S(u,0) = γ0(x0),  ∂v S(u,0) = ε(u) χ0(x0),  ∂v² S(u,0) = ε(u)² ξ0(x0)      (eq. 22–23)
 * (signs flipped for the inward directions -u, -v of sides 1, 2), ε / δ being the local
 * parametrization functions of degree 2k+1 blending the intervals of the transverse edges
 * (§4: "following the same definition in Section 3").  With these uv fields the patch is the
 * Boolean sum of formulas.md §4.1, S = P_u + P_v - P_uv with Hermite blending of degree 2K+1
 * (K = 1: eq. (23), bicubic; K = 2: §4.2, biquintic).  The mixed corner terms M^{ab}, a,b >= 1,
 * are the Gregory pairs of formulas.md §4.2 (Ω_{1,1}, Ω_{1,2}, Ω_{2,1}, Ω_{2,2} of §4.2):
 *     M^{ab}_{ij}(u,v) = (ũ^r B^{ab} + ṽ^r A^{ab}) / (ũ^r + ṽ^r),   r = K,
 * A from the v = j side, B from the u = i side, ũ = |u - i|, ṽ = |v - j|.  Expanding
 * ∂v(ε χ) = ε' χ + ε d χ' reproduces the paper's d_i e_j scale factors, because ε' = δ' = 0 at
 * the corners.  Values and partials up to order two are exact (the rational Gregory weights are
 * differentiated analytically); at a corner itself the weight is taken as 1/2. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "patch/ev_fair.h"
#include "patch/ev_internal.h"

typedef struct ev_patch {
    int K, r, kb;
    double d0, d1, e0, e1;     /* intervals of sides 0, 2 (u) and 3, 1 (v) */
    ev_side side[4];
    double M[2][2][3][3][3];   /* corner (i,j), a, b: constant mixed terms (a or b = 0) */
    double A[2][2][3][3][3];   /* Gregory: from the v = j side */
    double B[2][2][3][3][3];   /*          from the u = i side */
} ev_patch;

static const int side_iota[4] = {1, -1, -1, 1};

/* uv fields of side sd at side parameter s: F[b][a] = ∂s^a ∂n^b S (n = v on sides 0/2, u on 1/3). */
static void side_uv(const ev_patch *P, int sd, double s, double F[3][3][3])
{
    double loc[3][3][3], L[4];
    ev_side_eval(&P->side[sd], s, loc);
    if (sd == 0 || sd == 2) q2n_spline_blend_derivs(P->kb, P->e0, P->e1, s, L); /* ε(u) */
    else q2n_spline_blend_derivs(P->kb, P->d0, P->d1, s, L);                   /* δ(v) */
    double L2[3] = {L[0] * L[0], 2 * L[0] * L[1], 2 * L[1] * L[1] + 2 * L[0] * L[2]};
    double io = side_iota[sd];
    for (int c = 0; c < 3; c++) {
        for (int a = 0; a < 3; a++) F[0][a][c] = loc[0][a][c];
        F[1][0][c] = io * L[0] * loc[1][0][c];
        F[1][1][c] = io * (L[1] * loc[1][0][c] + L[0] * loc[1][1][c]);
        F[1][2][c] = io * (L[2] * loc[1][0][c] + 2 * L[1] * loc[1][1][c] + L[0] * loc[1][2][c]);
        F[2][0][c] = L2[0] * loc[2][0][c];
        F[2][1][c] = L2[1] * loc[2][0][c] + L2[0] * loc[2][1][c];
        F[2][2][c] = L2[2] * loc[2][0][c] + 2 * L2[1] * loc[2][1][c] + L2[0] * loc[2][2][c];
    }
}

/* Hermite basis H_{a,i}(x) and derivatives 0..2: H[a][i][d] (formulas.md §4.1). */
static void hermite(int K, double x, double H[3][2][3])
{
    static const double H3[2][2][6] = {{{1, 0, -3, 2, 0, 0}, {0, 0, 3, -2, 0, 0}},
                                       {{0, 1, -2, 1, 0, 0}, {0, 0, -1, 1, 0, 0}}};
    static const double H5[3][2][6] = {{{1, 0, 0, -10, 15, -6}, {0, 0, 0, 10, -15, 6}},
                                       {{0, 1, 0, -6, 8, -3}, {0, 0, 0, -4, 7, -3}},
                                       {{0, 0, 0.5, -1.5, 1.5, -0.5}, {0, 0, 0, 0.5, -1, 0.5}}};
    for (int a = 0; a <= K; a++)
        for (int i = 0; i < 2; i++) {
            const double *c = K == 1 ? H3[a][i] : H5[a][i];
            double v0 = 0, v1 = 0, v2 = 0; /* Horner for the polynomial and its derivatives */
            for (int p = 5; p >= 0; p--) v0 = v0 * x + c[p];
            for (int p = 5; p >= 1; p--) v1 = v1 * x + p * c[p];
            for (int p = 5; p >= 2; p--) v2 = v2 * x + p * (p - 1) * c[p];
            H[a][i][0] = v0;
            H[a][i][1] = v1;
            H[a][i][2] = v2;
        }
}

/* Gregory weight ω = ũ^r / (ũ^r + ṽ^r) of corner (i,j) and its partials W[p][q], p+q <= 2. */
static void gregory_weight(int r, int i, int j, double u, double v, double W[3][3])
{
    double ut = i ? 1 - u : u, vt = j ? 1 - v : v, su = i ? -1 : 1, sv = j ? -1 : 1;
    memset(W, 0, 9 * sizeof(double));
    double U = r == 1 ? ut : ut * ut, V = r == 1 ? vt : vt * vt;
    double g = U + V;
    if (!(g > 0)) { W[0][0] = 0.5; return; }
    double Uu = r == 1 ? su : 2 * ut * su, Uuu = r == 1 ? 0 : 2;
    double Vv = r == 1 ? sv : 2 * vt * sv, Vvv = r == 1 ? 0 : 2;
    double g2 = g * g, g3 = g2 * g;
    W[0][0] = U / g;
    W[1][0] = Uu * V / g2;
    W[0][1] = -U * Vv / g2;
    W[2][0] = Uuu * V / g2 - 2 * Uu * Uu * V / g3;
    W[0][2] = -U * Vvv / g2 + 2 * U * Vv * Vv / g3;
    W[1][1] = Uu * Vv / g2 - 2 * Uu * V * Vv / g3;
}

/* What a point evaluation needs from one parameter line: the two sides' uv fields at that
 * parameter and the Hermite weights (u-lines: sides 0, 2 and H(u); v-lines: sides 3, 1 and H(v)). */
typedef struct line_data {
    double side[2][3][3][3];
    double H[3][2][3];
} line_data;

static void line_u(const ev_patch *P, double u, line_data *L)
{
    side_uv(P, 0, u, L->side[0]);
    side_uv(P, 2, u, L->side[1]);
    hermite(P->K, u, L->H);
}

static void line_v(const ev_patch *P, double v, line_data *L)
{
    side_uv(P, 3, v, L->side[0]);
    side_uv(P, 1, v, L->side[1]);
    hermite(P->K, v, L->H);
}

/* S = P_u + P_v - P_uv (formulas.md §4.1) with Gregory mixed terms (§4.2), partials up to nder. */
static void patch_sum(const ev_patch *P, double u, double v, int nder, const line_data *Lu, const line_data *Lv,
                      double *out)
{
    int K = P->K;
    const double (*Hu)[2][3] = Lu->H, (*Hv)[2][3] = Lv->H;
    double W[2][2][3][3];
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) gregory_weight(P->r, i, j, u, v, W[i][j]);
    static const int ord[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
    static const double binom[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};
    int nout = nder <= 0 ? 1 : nder == 1 ? 3 : 6;
    for (int o = 0; o < nout; o++) {
        int al = ord[o][0], be = ord[o][1];
        double r[3] = {0, 0, 0};
        for (int i = 0; i < 2; i++)
            for (int a = 0; a <= K; a++) {
                q2n_v3_axpy(r, Hu[a][i][al], Lv->side[i][a][be]); /* P_u: G_{i,a}(v) */
                q2n_v3_axpy(r, Hv[a][i][be], Lu->side[i][a][al]); /* P_v: F_{j,b}(u), j = i, b = a */
            }
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++)
                for (int a = 0; a <= K; a++)
                    for (int b = 0; b <= K; b++) {
                        const double *Mc = P->M[i][j][a][b], *A = P->A[i][j][a][b], *B = P->B[i][j][a][b];
                        int greg = a >= 1 && b >= 1;
                        for (int a1 = 0; a1 <= al; a1++)
                            for (int b1 = 0; b1 <= be; b1++) {
                                int p = al - a1, q = be - b1;
                                double h = binom[al][a1] * binom[be][b1] * Hu[a][i][a1] * Hv[b][j][b1];
                                if (h == 0) continue;
                                if (!greg) {
                                    if (p == 0 && q == 0) q2n_v3_axpy(r, -h, Mc);
                                    continue;
                                }
                                double w = W[i][j][p][q];
                                for (int c = 0; c < 3; c++) {
                                    double m = (p == 0 && q == 0) ? A[c] + w * (B[c] - A[c]) : w * (B[c] - A[c]);
                                    r[c] -= h * m;
                                }
                            }
                    }
        memcpy(out + 3 * o, r, sizeof r);
    }
}

static q2n_status patch_eval(const void *data, double u, double v, int nder, double *out)
{
    const ev_patch *P = data;
    line_data Lu, Lv;
    line_u(P, u, &Lu);
    line_v(P, v, &Lv);
    patch_sum(P, u, v, nder, &Lu, &Lv, out);
    return Q2N_OK;
}

/* Grid fast path: the side data depend on u only (sides 0, 2) or v only (sides 1, 3). */
static q2n_status patch_grid(const void *data, int nu, const double *us, int nv, const double *vs, double *out)
{
    const ev_patch *P = data;
    line_data *Lu = malloc((size_t)nu * sizeof *Lu);
    if (!Lu) return Q2N_ERR_NOMEM;
    for (int a = 0; a < nu; a++) line_u(P, us[a], &Lu[a]);
    for (int b = 0; b < nv; b++) {
        line_data Lv;
        line_v(P, vs[b], &Lv);
        for (int a = 0; a < nu; a++) patch_sum(P, us[a], vs[b], 1, &Lu[a], &Lv, out + 9 * ((size_t)b * nu + a));
    }
    free(Lu);
    return Q2N_OK;
}

static void patch_free(void *d) { free(d); }

/* Exact mixed corner partials (q2n_surface_corner_mixed): the corner data A (v-side) and B
 * (u-side).  Biquintic patches only: the bicubic blend (K = 1) has no second-order side terms. */
static q2n_status patch_corner(const void *data, int i, int j, double out[2][2][2][3])
{
    const ev_patch *P = data;
    if (P->K != 2) return Q2N_ERR_UNSUPPORTED;
    for (int a = 1; a <= 2; a++)
        for (int b = 1; b <= 2; b++) {
            memcpy(out[0][a - 1][b - 1], P->A[i][j][a][b], 3 * sizeof(double));
            memcpy(out[1][a - 1][b - 1], P->B[i][j][a][b], 3 * sizeof(double));
        }
    return Q2N_OK;
}

/* Corner data: A^{ab} = ∂u^a [∂v^b S(u,j)](i) from the v = j side, B^{ab} = ∂v^b [∂u^a S(i,v)](j)
 * from the u = i side; the constant terms use the side that makes the patch interpolate both
 * (formulas.md §4.1: a = 0 from the v-side, b = 0 from the u-side). */
static void patch_corners(ev_patch *P)
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double Fv[3][3][3], Gu[3][3][3];
            side_uv(P, j ? 2 : 0, i, Fv);
            side_uv(P, i ? 1 : 3, j, Gu);
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) {
                    memcpy(P->A[i][j][a][b], Fv[b][a], 3 * sizeof(double));
                    memcpy(P->B[i][j][a][b], Gu[a][b], 3 * sizeof(double));
                    memcpy(P->M[i][j][a][b], a == 0 ? Fv[b][a] : Gu[a][b], 3 * sizeof(double));
                }
        }
}

int q2n_ev_patch_parse(const char *s, q2n_ev_patch_kind *out)
{
    if (!s) return -1;
    if ((s[0] == 'g' || s[0] == 'G') && s[1] && !s[2]) {
        if (s[1] == '1') { *out = Q2N_EV_PATCH_G1; return 0; }
        if (s[1] == '2') { *out = Q2N_EV_PATCH_G2; return 0; }
    }
    return -1;
}

int q2n_ev_method_parse(const char *s, q2n_ev_method *out)
{
    if (!s) return -1;
    if (!strcmp(s, "fair")) { *out = Q2N_EV_METHOD_FAIR; return 0; }
    if (!strcmp(s, "paper")) { *out = Q2N_EV_METHOD_PAPER; return 0; }
    return -1;
}

static const q2n_spline_class *opt_class(const q2n_extraordinary_options *opt)
{
    return opt && opt->cls ? opt->cls : q2n_spline_class_find("D5C2P2S4");
}

int q2n_ev_patch_order(const q2n_extraordinary_options *opt)
{
    if (opt && opt->ev_patch == Q2N_EV_PATCH_G1) return 1;
    if (opt && opt->ev_patch == Q2N_EV_PATCH_G2) return 2;
    return opt_class(opt)->k >= 2 ? 2 : 1;
}

/* Fill the patch of uncovered face f from the curve network and its regular neighbours. */
static q2n_status patch_setup(ev_patch *P, const q2n_mesh *m, const q2n_surface *s, const double *iv,
                              const char *unc, ev_edge *const *edges, int K, int kb, int f, q2n_error *err)
{
    memset(P, 0, sizeof *P);
    P->K = K;
    P->r = K;
    P->kb = kb;
    P->d0 = iv[m->he_edge[q2n_face_he(m, f, 0)]];
    P->e1 = iv[m->he_edge[q2n_face_he(m, f, 1)]];
    P->d1 = iv[m->he_edge[q2n_face_he(m, f, 2)]];
    P->e0 = iv[m->he_edge[q2n_face_he(m, f, 3)]];
    for (int sd = 0; sd < 4; sd++) {
        int h = q2n_face_he(m, f, sd), t = m->he_twin[h], e = m->he_edge[h];
        ev_side *S = &P->side[sd];
        /* the side parameter runs along h on sides 0, 1 and against it on sides 2, 3 */
        int along_h = sd < 2;
        if (t >= 0 && !unc[m->he_face[t]]) {
            int g = m->he_face[t], sR = t - m->face_start[g];
            const q2n_augmented_patch *R = q2n_surface_patch_data(s, g);
            if (!R) return q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: no regular patch data", m->name, g);
            S->kind = 1;
            S->R = *R;
            S->sR = sR;
            /* R's coordinate runs along t on its sides 0, 1 and against t on 2, 3; t is
             * opposite to h */
            int R_along_t = sR < 2;
            int R_along_h = !R_along_t;
            S->rev = R_along_h != along_h;
        } else {
            const ev_edge *E = edges[e];
            S->kind = 0;
            S->E = *E;
            S->derived = (m->edge_he[e] != h) != E->base_twin;
            int edge_along_h = m->edge_he[e] == h;
            S->rev = edge_along_h != along_h;
        }
    }
    patch_corners(P);
    return Q2N_OK;
}

/* ---- corner compatibility (G2 mode) ----
 * A Coons–Gregory corner blends two values of each mixed derivative ∂u^a ∂v^b S, a, b >= 1:
 * A from the v-side, B from the u-side.  Where they differ the patch is rational there (C2 but not
 * C3 at the corner), and no polynomial spline with uniform knots follows its curvature: the fit's
 * G2 failed next to such corners (jumps of 0.1-2 x the curvature; docs/fit.md).  (1,1) agrees by
 * construction (both twists come from the vertex jet).  The third- and fourth-order terms (2,1),
 * (1,2), (2,2) are made to agree here, vertex by vertex, with the end data that the 2-jets leave
 * free: the second t-derivatives of the normal field n (its D-part) and of the ribbon
 * coefficients a, b of both sides, the third and fourth of the curve γ (normal part), the first
 * and second of the base side's ξ and of the derived side's tangential part τ (ev_edge's bump
 * terms).  None of them touches a value, a slope or a second derivative of γ at an end, so the
 * vertex jets, the twists and the G1/G2 relations along every edge (which hold for any such
 * data: the derived side is still built from the base side) are unchanged.  The curve's normal
 * third derivatives are needed: the normal parts of the mismatches form, per vertex, a linear
 * system in which each edge contributes its cubic-form value C(u,u,u) through its curve, and
 * for valence >= 5 these over-determine the four coefficients of a cubic form.
 *
 * The corner values depend affinely on the unknowns; the map is probed (one evaluation per
 * unknown, exact for an affine map) and the correction that zeroes the mismatches while changing
 * the second derivatives along the edges least is applied (hz_edge_sample; see the solver in
 * harmonize_vertex).  Bumps vanish with three derivatives at the other end of their edge, so
 * vertices are independent.  A correction that folds, flips or spikes a patch around the vertex
 * (hz_shape) is not applied: those corners stay Gregory corners, and the fit treats them as such. */
#define HZ_GU 21 /* unknowns per edge end */
#define HZ_MAXU (HZ_GU * EV_MAXVAL)
#define HZ_MAXC (2 * EV_MAXVAL)
#define HZ_RC 12 /* residuals per corner: 4 orders x 3 */
#define HZ_MAXR (HZ_RC * HZ_MAXC)
#define HZ_NG (2 + 3 * 81) /* shape guard record: max |dS|, min sine, 81 normals */
#define HZ_NS (6 * 81)     /* surface cost samples per corner face: S_u, S_v on a 9 x 9 grid */
#define HZ_NH (2 * 9 * 9)  /* edge cost samples per edge */
#define HZ_GN 8            /* Gauss-Newton steps at most (only where slopes of a, b are unknowns) */

typedef struct hz_corner { int f, i, j; } hz_corner;

static const int hz_ab[4][2] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};

/* One vertex's corner-compatibility problem: the corners of uncovered faces at the vertex, the
 * unknowns (pointers into the edges' bump coefficients, grouped by edge end), and scratch. */
typedef struct hz_vertex {
    const q2n_mesh *m;
    const q2n_surface *s;
    const double *iv;
    const char *unc;
    ev_edge **edges;
    int K, kb, v;
    hz_corner cs[HZ_MAXC];
    int nc, nr;
    double *u[HZ_MAXU];
    int ue[HZ_MAXU];     /* edge of each unknown */
    char first[HZ_MAXU]; /* 1: first-order data (n, γ); 2: slopes of a, b; 0: the rest */
    int nu;
    ev_patch *P;
    double (*gb)[HZ_NG]; /* shape of every corner face before the correction */
    double rmax, r11;
    double *M, *r0, *Mw, *rc, *rt, *Y, *G, *y, *Q, *H;
    q2n_error *err;
} hz_vertex;

/* Mismatches B - A of the corners (HZ_RC per corner); only_e >= 0: only the corners of faces
 * with edge only_e as a side are evaluated (the others are copied from r0). */
static q2n_status hz_residuals(hz_vertex *V, int only_e, const double *r0, double *r)
{
    const q2n_mesh *m = V->m;
    for (int q = 0; q < V->nc; q++) {
        const hz_corner *c = &V->cs[q];
        int touch = only_e < 0;
        for (int sd = 0; sd < 4 && !touch; sd++) touch = m->he_edge[q2n_face_he(m, c->f, sd)] == only_e;
        if (!touch) {
            memcpy(r + HZ_RC * q, r0 + HZ_RC * q, HZ_RC * sizeof(double));
            continue;
        }
        q2n_status st = patch_setup(V->P, m, V->s, V->iv, V->unc, V->edges, V->K, V->kb, c->f, V->err);
        if (st) return st;
        for (int o = 0; o < 4; o++)
            for (int x = 0; x < 3; x++) {
                int a = hz_ab[o][0], b = hz_ab[o][1];
                r[HZ_RC * q + 3 * o + x] = V->P->B[c->i][c->j][a][b][x] - V->P->A[c->i][c->j][a][b][x];
            }
    }
    return Q2N_OK;
}

/* Cholesky factorisation G = L L^T in place (lower triangle); 0 if not positive definite. */
static int chol_factor(double *G, int n)
{
    for (int j = 0; j < n; j++) {
        double d = G[j * n + j];
        for (int k = 0; k < j; k++) d -= G[j * n + k] * G[j * n + k];
        if (!(d > 0)) return 0;
        d = sqrt(d);
        G[j * n + j] = d;
        for (int i = j + 1; i < n; i++) {
            double x = G[i * n + j];
            for (int k = 0; k < j; k++) x -= G[i * n + k] * G[j * n + k];
            G[i * n + j] = x / d;
        }
    }
    return 1;
}

static void chol_solve(const double *G, double *y, int n)
{
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < i; k++) y[i] -= G[i * n + k] * y[k];
        y[i] /= G[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        for (int k = i + 1; k < n; k++) y[i] -= G[k * n + i] * y[k];
        y[i] /= G[i * n + i];
    }
}

/* Probe step of unknown k: a unit step where the mismatches are affine in it (exact), a small
 * forward step for the slopes of a, b (first == 2), which enter the derived side through
 * products. */
static double hz_step(const hz_vertex *V, int k) { return V->first[k] == 2 ? 1e-6 * fmax(1.0, fabs(*V->u[k])) : 1.0; }

/* A sampled quantity of the vertex's patches (n values, base: at the current unknowns) as
 * evaluated after a step of unknown k. */
typedef q2n_status (*hz_sample_fn)(hz_vertex *V, int k, const double *base, double *out);

/* Sensitivities of a sampled quantity: column k (n values) = d sample / d unknown k. */
static q2n_status hz_columns(hz_vertex *V, hz_sample_fn fn, int n, const double *base, double *cols)
{
    for (int k = 0; k < V->nu; k++) {
        double keep = *V->u[k], h = hz_step(V, k), *col = cols + (size_t)n * k;
        *V->u[k] = keep + h;
        q2n_status st = fn(V, k, base, col);
        *V->u[k] = keep;
        if (st) return st;
        for (int i = 0; i < n; i++) col[i] = (col[i] - base[i]) / h;
    }
    return Q2N_OK;
}

/* the mismatches after a step of unknown k: only the corners beside its edge change */
static q2n_status hz_residuals_k(hz_vertex *V, int k, const double *base, double *out)
{
    return hz_residuals(V, V->ue[k], base, out);
}

/* Mismatches rc at the unknowns' values + z and the Jacobian J there (column k = dr/du_k). */
static q2n_status hz_jacobian(hz_vertex *V, const double *z, double *rc, double *J)
{
    q2n_status st;
    for (int k = 0; k < V->nu; k++) *V->u[k] += z[k];
    if (!(st = hz_residuals(V, -1, NULL, rc))) st = hz_columns(V, hz_residuals_k, V->nr, rc, J);
    for (int k = 0; k < V->nu; k++) *V->u[k] -= z[k];
    return st;
}

/* Cost samples of a constructed edge for the corner correction: the second derivatives of the
 * surface along the edge, γ_tt, χ_t (the twist) and ξ, on both sides at t = 0.1, .., 0.9. */
static int hz_edge_sample(const ev_edge *E, double *out)
{
    int n = 0;
    for (int sd = 0; sd < (E->face[1] >= 0 ? 2 : 1); sd++) {
        ev_side S;
        memset(&S, 0, sizeof S);
        S.kind = 0;
        S.E = *E;
        S.derived = sd;
        for (int q = 1; q <= 9; q++) {
            double F[3][3][3];
            ev_side_eval(&S, q / 10.0, F);
            for (int c = 0; c < 3; c++) {
                out[n++] = F[0][2][c];
                out[n++] = F[1][1][c];
                out[n++] = F[2][0][c];
            }
        }
    }
    return n;
}

/* Edge cost: H (HZ_NH rows per unknown) = the change of the edge samples of the unknown's edge
 * per unit of the unknown. */
static void hz_edge_cost(hz_vertex *V)
{
    for (int g0 = 0; g0 < V->nu;) {
        int g1 = g0;
        while (g1 < V->nu && V->ue[g1] == V->ue[g0]) g1++;
        ev_edge *E = V->edges[V->ue[g0]];
        double base[HZ_NH];
        int nh = hz_edge_sample(E, base);
        for (int k = g0; k < g1; k++) {
            double keep = *V->u[k], h = hz_step(V, k), *col = V->H + (size_t)HZ_NH * k;
            *V->u[k] = keep + h;
            hz_edge_sample(E, col);
            *V->u[k] = keep;
            for (int i = 0; i < HZ_NH; i++) col[i] = i < nh ? (col[i] - base[i]) / h : 0;
        }
        g0 = g1;
    }
}

/* Surface samples of the corner faces: S_u, S_v on a 9 x 9 grid, each face in units of its
 * largest first derivative before the correction (hz_sample_fn; k and base unused). */
static q2n_status hz_surface_sample(hz_vertex *V, int k, const double *base, double *out)
{
    (void)k, (void)base;
    for (int q = 0; q < V->nc; q++) {
        q2n_status st = patch_setup(V->P, V->m, V->s, V->iv, V->unc, V->edges, V->K, V->kb, V->cs[q].f, V->err);
        if (st) return st;
        double sc = 1.0 / V->gb[q][0];
        for (int a = 0; a <= 8; a++)
            for (int b = 0; b <= 8; b++) {
                double D[9];
                patch_eval(V->P, a / 8.0, b / 8.0, 1, D);
                for (int x = 0; x < 6; x++) out[(size_t)HZ_NS * q + 6 * (9 * a + b) + x] = sc * D[3 + x];
            }
    }
    return Q2N_OK;
}

/* Q = the cost's Gram matrix, one block per edge end (block of the group starting at g0 at
 * Q + HZ_GU * g0, the first-order data weighted by F), or with full != NULL one nu x nu block
 * full^T full + 1e-3 of the edge cost (its trace relative), then Cholesky-factored in place.
 * grp[] receives the grouping the factors follow.  0 where a block is not positive definite. */
static int hz_cost_factor(hz_vertex *V, double F, const double *full, int nfull, int *grp)
{
    int nu = V->nu;
    if (full) {
        double tf = 0, te = 0;
        for (int k = 0; k < nu; k++) {
            grp[k] = 0;
            for (int i = 0; i < nfull; i++) tf += full[(size_t)nfull * k + i] * full[(size_t)nfull * k + i];
            for (int i = 0; i < HZ_NH; i++) te += V->H[(size_t)HZ_NH * k + i] * V->H[(size_t)HZ_NH * k + i];
        }
        double lam = te > 0 ? 1e-3 * tf / te : 0, qmax = 0;
        for (int a = 0; a < nu; a++)
            for (int b = 0; b <= a; b++) {
                double q = 0;
                const double *fa = full + (size_t)nfull * a, *fb = full + (size_t)nfull * b;
                for (int i = 0; i < nfull; i++) q += fa[i] * fb[i];
                if (V->ue[a] == V->ue[b]) {
                    const double *ha = V->H + (size_t)HZ_NH * a, *hb = V->H + (size_t)HZ_NH * b;
                    double e = 0;
                    for (int i = 0; i < HZ_NH; i++) e += ha[i] * hb[i];
                    q += lam * e;
                }
                V->Q[a * nu + b] = V->Q[b * nu + a] = q;
                if (a == b) qmax = fmax(qmax, q);
            }
        for (int a = 0; a < nu; a++) V->Q[a * nu + a] += 1e-9 * qmax + 1e-300;
        return chol_factor(V->Q, nu);
    }
    for (int g0 = 0; g0 < nu;) {
        int g1 = g0;
        while (g1 < nu && V->ue[g1] == V->ue[g0]) g1++;
        int ne = g1 - g0;
        double *Q = V->Q + (size_t)HZ_GU * g0, qmax = 0;
        for (int a = 0; a < ne; a++)
            for (int b = 0; b < ne; b++) {
                double q = 0, wa = V->first[g0 + a] ? F : 1, wb = V->first[g0 + b] ? F : 1;
                const double *ha = V->H + (size_t)HZ_NH * (g0 + a), *hb = V->H + (size_t)HZ_NH * (g0 + b);
                for (int i = 0; i < HZ_NH; i++) q += ha[i] * hb[i];
                Q[a * ne + b] = wa * wb * q;
                if (a == b) qmax = fmax(qmax, Q[a * ne + b]);
            }
        for (int a = 0; a < ne; a++) Q[a * ne + a] += 1e-9 * qmax + 1e-300;
        if (!chol_factor(Q, ne)) return 0;
        for (int k = g0; k < g1; k++) grp[k] = g0;
        g0 = g1;
    }
    return 1;
}

/* Least change z (z^T Q z, Q's block Cholesky factors: the block of unknowns g0.. with grp[k] ==
 * g0 at Q + HZ_GU * g0, or one block at Q when every grp[k] is 0) with rc + J (z - zl) = 0:
 * z = Q^-1 J^T l, (J Q^-1 J^T + mu) l = J zl - rc with rows equilibrated (the orders (2,1),
 * (1,2), (2,2) differ in scale, so that the Tikhonov term mu is relative to every row alike),
 * three passes of refinement against the linear model.  0 where it cannot be factored. */
static int hz_min_change(hz_vertex *V, const double *J, const double *rc, const double *zl, const int *grp, double *z)
{
    int nu = V->nu, nr = V->nr;
    double *Y = V->Y, *G = V->G, *y = V->y;
    for (int g0 = 0; g0 < nu;) {
        int g1 = g0;
        while (g1 < nu && grp[g1] == grp[g0]) g1++;
        int ne = g1 - g0;
        const double *Q = V->Q + (size_t)HZ_GU * g0;
        for (int i = 0; i < nr; i++) {
            double col[HZ_MAXU];
            for (int k = 0; k < ne; k++) col[k] = J[(size_t)nr * (g0 + k) + i];
            chol_solve(Q, col, ne);
            for (int k = 0; k < ne; k++) Y[(size_t)nr * (g0 + k) + i] = col[k];
        }
        g0 = g1;
    }
    for (int i = 0; i < nr; i++)
        for (int j = 0; j <= i; j++) {
            double g = 0;
            for (int k = 0; k < nu; k++) g += J[(size_t)nr * k + i] * Y[(size_t)nr * k + j];
            G[i * nr + j] = G[j * nr + i] = g;
        }
    double dr[HZ_MAXR];
    for (int i = 0; i < nr; i++) dr[i] = G[i * nr + i] > 0 ? 1 / sqrt(G[i * nr + i]) : 0;
    for (int i = 0; i < nr; i++)
        for (int j = 0; j < nr; j++) G[i * nr + j] *= dr[i] * dr[j];
    for (int i = 0; i < nr; i++) G[i * nr + i] += 1e-10 + (dr[i] == 0);
    if (!chol_factor(G, nr)) return 0;
    for (int k = 0; k < nu; k++) z[k] = 0;
    for (int pass = 0; pass < 4; pass++) {
        for (int i = 0; i < nr; i++) {
            double ri = rc[i];
            for (int k = 0; k < nu; k++) ri += J[(size_t)nr * k + i] * (z[k] - zl[k]);
            y[i] = -ri * dr[i];
        }
        chol_solve(G, y, nr);
        for (int i = 0; i < nr; i++) y[i] *= dr[i];
        for (int k = 0; k < nu; k++) {
            double dz = 0;
            for (int i = 0; i < nr; i++) dz += Y[(size_t)nr * k + i] * y[i];
            z[k] += dz;
        }
    }
    return 1;
}

/* Shape guard of the corner correction: on a 9 x 9 grid of face f, out[0] = max(|S_u|, |S_v|),
 * out[1] = min |S_u x S_v| / (|S_u| |S_v|), out[2..] the unit normals.  With ref == NULL they are
 * measured into out; else *ok = 0 when the corrected patch's derivatives grew past 1.5 x ref, its
 * sine of the angle between S_u and S_v fell below half of ref's, or a normal turned by 90
 * degrees or more (a fold, a flip or a spike). */
static q2n_status hz_shape(hz_vertex *V, int f, const double *ref, int *ok, double *out)
{
    q2n_status st = patch_setup(V->P, V->m, V->s, V->iv, V->unc, V->edges, V->K, V->kb, f, V->err);
    if (st) return st;
    double big = 0, sn = 1, *nr = out ? out + 2 : NULL;
    for (int a = 0; a <= 8; a++)
        for (int b = 0; b <= 8; b++) {
            double D[9], c[3];
            patch_eval(V->P, a / 8.0, b / 8.0, 1, D);
            double nu = q2n_v3_norm(D + 3), nv = q2n_v3_norm(D + 6);
            q2n_v3_cross(c, D + 3, D + 6);
            big = fmax(big, fmax(nu, nv));
            double cn = q2n_v3_norm(c), q = nu > 0 && nv > 0 ? cn / (nu * nv) : 0;
            sn = fmin(sn, isfinite(q) ? q : 0);
            if (!isfinite(nu) || !isfinite(nv)) big = INFINITY;
            int g = 3 * (9 * a + b);
            if (!ref) {
                for (int x = 0; x < 3; x++) nr[g + x] = cn > 0 ? c[x] / (nu * nv) : 0; /* length: the sine */
            } else {
                const double *rn = ref + 2 + g;
                double rs = q2n_v3_norm(rn);
                /* where the patch was well shaped (sine > 0.2), the normal may not turn by 90
                 * degrees or more (near-degenerate points have no meaningful normal) */
                if (rs > 0.2 && !(q2n_v3_dot(c, rn) > 0)) *ok = 0;
            }
        }
    if (!ref) {
        out[0] = big;
        out[1] = sn;
    } else if (!(big <= 1.5 * ref[0]) || !(sn >= 0.5 * ref[1])) {
        *ok = 0;
    }
    return Q2N_OK;
}

/* Bump localisation l (0, 2, 4: (1-t)^(4+l)) of every unknown's edge at the vertex's end. */
static void hz_set_loc(hz_vertex *V, int l)
{
    for (int k = 0; k < V->nu; k++) {
        int e = V->ue[k];
        V->edges[e]->loc[q2n_he_origin(V->m, V->m->edge_he[e]) == V->v ? 0 : 1] = l;
    }
}

/* One correction with the factored cost: Gauss-Newton from z = 0 (the Jacobian there in M, r0),
 * applied when it passes the shape guard (*ok = 1), else undone. */
static q2n_status hz_attempt(hz_vertex *V, const int *grp, int *ok)
{
    int nu = V->nu, nr = V->nr, nstep = 0;
    double zl[HZ_MAXU], z[HZ_MAXU];
    for (int k = 0; k < nu; k++) z[k] = zl[k] = 0;
    memcpy(V->Mw, V->M, sizeof(double) * (size_t)nr * (size_t)nu);
    memcpy(V->rc, V->r0, sizeof(double) * (size_t)nr);
    q2n_status st;
    *ok = 0;
    for (int gn = 0; gn < HZ_GN; gn++) {
        if (gn > 0) {
            memcpy(zl, z, sizeof(double) * (size_t)nu);
            if ((st = hz_jacobian(V, zl, V->rc, V->Mw))) return st;
        }
        if (!hz_min_change(V, V->Mw, V->rc, zl, grp, z)) break;
        nstep++;
        if (V->r11 <= 1e-9 * V->rmax) break; /* affine: one step is exact */
        for (int k = 0; k < nu; k++) *V->u[k] += z[k];
        st = hz_residuals(V, -1, NULL, V->rt);
        for (int k = 0; k < nu; k++) *V->u[k] -= z[k];
        if (st) return st;
        double rn = 0;
        for (int i = 0; i < nr; i++) rn = fmax(rn, fabs(V->rt[i]));
        if (rn <= 1e-10 * V->rmax) break;
    }
    if (!nstep) return Q2N_OK;
    for (int k = 0; k < nu; k++) *V->u[k] += z[k];
    *ok = 1;
    for (int q = 0; q < V->nc && *ok; q++)
        if ((st = hz_shape(V, V->cs[q].f, V->gb[q], ok, NULL))) return st;
    if (!*ok)
        for (int k = 0; k < nu; k++) *V->u[k] -= z[k];
    return Q2N_OK;
}

/* The corner correction at vertex v (see above): unknowns and corners collected, then tried with
 * bumps over the whole edge first and, where every weighting folds a patch, bumps concentrated
 * nearer to the vertex ((1-t)^6, then (1-t)^8 instead of (1-t)^4; γ: ^7, ^9).
 *
 * Cost: the change of the second derivatives along the edges (hz_edge_sample), Q block-diagonal
 * by edge end, the first-order data (n, γ, the slopes of a, b) weighted by F.  F = 1000 first:
 * changing the normal field or the curve costs most and makes the patches hardest to fit; where
 * that correction folds or spikes a patch (hz_shape), F = 100, 10, 1 are tried.  Where all of
 * these fail, the cost becomes the change of the patches themselves (their first derivatives on
 * a grid, hz_surface_sample): the edge-wise cost does not see that a mixed-derivative change at
 * the corner bends the whole patch through its Hermite corner blend, and at vertices with wild
 * corner data (mismatches tens of times the patch's first derivatives, righthanded, rook) only
 * the surface-aware correction keeps the patches unfolded.  If that fails too, the corners at v
 * stay Gregory corners.
 *
 * The mismatches are affine in every unknown but the slopes of a, b (unknowns only where a twist
 * disagrees); there Gauss-Newton steps follow (hz_attempt), each the same least-change problem
 * for the linear model at the current point. */
static q2n_status harmonize_vertex(const q2n_mesh *m, const q2n_surface *s, const double *iv, const char *unc,
                                   ev_edge **edges, int K, int kb, const int *vc_start, const int *vc_list, int v,
                                   q2n_error *err)
{
    hz_vertex *V = calloc(1, sizeof *V);
    if (!V) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (vertex %d)", v);
    *V = (hz_vertex){.m = m, .s = s, .iv = iv, .unc = unc, .edges = edges, .K = K, .kb = kb, .v = v, .err = err};
    /* unknowns: the bump coefficients of the constructed edges at v */
    int nu = 0, nc = 0;
    for (int ci = vc_start[v]; ci < vc_start[v + 1]; ci++) {
        int f = vc_list[ci] >> 2, k = vc_list[ci] & 3;
        int h = q2n_face_he(m, f, k);
        /* sides at this corner: the face's edges k (leaving v) and k-1 (arriving at v) */
        int e1 = m->he_edge[h], e0 = m->he_edge[q2n_face_he(m, f, (k + 3) % 4)];
        int any = 0;
        for (int x = 0; x < 2; x++) {
            int e = x ? e1 : e0;
            if (!edges[e]) continue;
            any = 1;
            int end = q2n_he_origin(m, m->edge_he[e]) == v ? 0 : 1;
            ev_edge *E = edges[e];
            int dup = 0;
            for (int q = 0; q < nu; q++) dup |= V->u[q] == &E->nb[end];
            if (dup) continue;
            if (nu + HZ_GU > HZ_MAXU) { free(V); return Q2N_OK; } /* valence beyond the table: left as is */
            int two = E->face[1] >= 0, nu0 = nu;
            V->first[nu] = 1, V->u[nu++] = &E->nb[end];
            V->first[nu] = 1, V->u[nu++] = &E->g3[end];
            V->first[nu] = 1, V->u[nu++] = &E->g4[end];
            for (int sd = 0; sd < (two ? 2 : 1); sd++) {
                V->u[nu++] = &E->a2[sd][end];
                V->u[nu++] = &E->b2[sd][end];
                V->first[nu] = 2, V->u[nu++] = &E->a1[sd][end];
                V->first[nu] = 2, V->u[nu++] = &E->b1[sd][end];
            }
            for (int c = 0; c < 3; c++) {
                V->u[nu++] = &E->x1[end][c];
                V->u[nu++] = &E->x2[end][c];
            }
            if (two)
                for (int c = 0; c < 2; c++) {
                    V->u[nu++] = &E->t1[end][c];
                    V->u[nu++] = &E->t2[end][c];
                }
            for (int q = nu0; q < nu; q++) V->ue[q] = e;
        }
        if (!any) continue;
        if (nc == HZ_MAXC) { free(V); return Q2N_OK; }
        static const int cuv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        V->cs[nc] = (hz_corner){f, cuv[k][0], cuv[k][1]};
        nc++;
    }
    if (!nc || !nu) { free(V); return Q2N_OK; }
    int nr = HZ_RC * nc;
    V->nc = nc;
    V->nr = nr;
    V->nu = nu;
    q2n_status st = Q2N_OK;
    size_t nrs = (size_t)nr, nus = (size_t)nu;
    V->P = malloc(sizeof *V->P);
    V->M = malloc(sizeof(double) * nrs * (2 * nus + 3)); /* M, r0, Mw, rc, rt */
    V->G = malloc(sizeof(double) * nrs * nrs);
    V->y = malloc(sizeof(double) * nrs);
    V->Y = malloc(sizeof(double) * nrs * nus);
    V->H = malloc(sizeof(double) * HZ_NH * nus);
    V->Q = malloc(sizeof(double) * (nus * nus + HZ_GU * nus));
    V->gb = malloc(sizeof *V->gb * (size_t)nc);
    double *Hs = NULL;
    int grp[HZ_MAXU];
    if (!V->P || !V->M || !V->G || !V->y || !V->Y || !V->H || !V->Q || !V->gb) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (vertex %d)", v);
        goto out;
    }
    V->r0 = V->M + nrs * nus;
    V->Mw = V->r0 + nrs;
    V->rc = V->Mw + nrs * nus;
    V->rt = V->rc + nrs;
    if ((st = hz_residuals(V, -1, NULL, V->r0))) goto out;
    for (int i = 0; i < nr; i++) {
        V->rmax = fmax(V->rmax, fabs(V->r0[i]));
        if (i % HZ_RC < 3) V->r11 = fmax(V->r11, fabs(V->r0[i]));
    }
    if (!(V->rmax > 0)) goto out;
    /* the slopes of a, b (first[] == 2) are unknowns only where a twist disagrees (where the
     * sign guard of ev_build_edge changed a slope); elsewhere the twists stay as they are */
    if (!(V->r11 > 1e-9 * V->rmax)) {
        int w = 0;
        for (int k = 0; k < nu; k++)
            if (V->first[k] != 2) { V->u[w] = V->u[k]; V->ue[w] = V->ue[k]; V->first[w] = V->first[k]; w++; }
        V->nu = nu = w;
    }
    for (int q = 0; q < nc; q++)
        if ((st = hz_shape(V, V->cs[q].f, NULL, NULL, V->gb[q]))) goto out;
    int done = 0;
    static const double Fs[4] = {1000, 100, 10, 1};
    for (int pass = 0; pass < 2 && !done; pass++) {
        /* pass 0: the edge cost with four weightings F, pass 1: the surface cost */
        if (pass == 1 && !(Hs = malloc(sizeof(double) * HZ_NS * (size_t)nc * ((size_t)nu + 1)))) {
            st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (vertex %d)", v);
            goto out;
        }
        for (int li = 0; li < 3 && !done; li++) {
            hz_set_loc(V, 2 * li);
            double z0[HZ_MAXU] = {0};
            if ((st = hz_jacobian(V, z0, V->r0, V->M))) goto out;
            hz_edge_cost(V);
            if (pass == 1) {
                int ns = HZ_NS * nc;
                double *base = Hs + (size_t)ns * (size_t)nu;
                if ((st = hz_surface_sample(V, -1, NULL, base)) || (st = hz_columns(V, hz_surface_sample, ns, base, Hs)))
                    goto out;
                if (!hz_cost_factor(V, 1.0, Hs, ns, grp)) continue;
                if ((st = hz_attempt(V, grp, &done))) goto out;
                continue;
            }
            for (int fi = 0; fi < 4 && !done; fi++) {
                if (!hz_cost_factor(V, Fs[fi], NULL, 0, grp)) continue;
                if ((st = hz_attempt(V, grp, &done))) goto out;
            }
        }
    }
    if (!done) hz_set_loc(V, 0);
out:
    free(Hs);
    free(V->P);
    free(V->M);
    free(V->G);
    free(V->y);
    free(V->Y);
    free(V->H);
    free(V->Q);
    free(V->gb);
    free(V);
    return st;
}

q2n_status q2n_extraordinary_build(const q2n_mesh *m, const q2n_extraordinary_options *opt,
                                   const double *edge_iv, q2n_surface *s, q2n_error *err)
{
    if (!m || !s || !opt) return q2n_error_set(err, Q2N_ERR_ARG, "extraordinary: missing argument");
    if (!m->all_quads)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s: extraordinary patches need an all-quad mesh (subdivide once first)", m->name);
    if (q2n_surface_npatches(s) != m->nf)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: surface has %d patches for %d faces", m->name,
                             q2n_surface_npatches(s), m->nf);
    const q2n_spline_class *cls = opt_class(opt);
    if (!cls) return q2n_error_set(err, Q2N_ERR_ARG, "extraordinary: unknown spline class");
    int K = q2n_ev_patch_order(opt), nunc = 0;
    for (int f = 0; f < m->nf; f++) {
        q2n_patch_kind kd = q2n_surface_kind(s, f);
        if (kd == Q2N_PATCH_UNCOVERED) nunc++;
        else if (kd != Q2N_PATCH_AUGMENTED)
            return q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: patch kind %d is neither regular nor uncovered",
                                 m->name, f, (int)kd);
    }
    if (nunc == 0) return Q2N_OK;
    q2n_status st = Q2N_OK;
    double *own = NULL;
    if (!edge_iv) {
        if ((st = q2n_param_edge_intervals(m, &opt->param, &own, err))) return st;
        edge_iv = own;
    }
    const double *iv = edge_iv;
    if (opt->method != Q2N_EV_METHOD_PAPER) {
        st = ev_fair_build(m, s, iv, cls, K, NULL, err);
        free(own);
        return st;
    }
    ev_vjet *jets = calloc((size_t)m->nv, sizeof *jets);
    double (*dir)[2] = calloc(2 * (size_t)m->ne, sizeof *dir);
    ev_edge **edges = calloc((size_t)m->ne, sizeof *edges);
    char *unc = calloc((size_t)m->nf, 1);
    ev_patch **patches = calloc((size_t)m->nf, sizeof *patches);
    if (!jets || !dir || !edges || !unc || !patches) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (extraordinary patches)");
        goto done;
    }
    for (int f = 0; f < m->nf; f++) unc[f] = q2n_surface_kind(s, f) == Q2N_PATCH_UNCOVERED;
    if ((st = ev_vertex_jets(m, s, iv, cls, jets, dir, err))) goto done;

    /* curve network: every edge of an uncovered face not shared with a regular patch */
    for (int f = 0; f < m->nf && !st; f++) {
        if (!unc[f]) continue;
        for (int i = 0; i < 4 && !st; i++) {
            int h = q2n_face_he(m, f, i), t = m->he_twin[h], e = m->he_edge[h];
            if (t >= 0 && !unc[m->he_face[t]]) continue;
            if (edges[e]) continue;
            if (!(edges[e] = malloc(sizeof **edges))) {
                st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (edge %d)", e);
                break;
            }
            st = ev_build_edge(m, iv, jets, (const double (*)[2])dir, K, e, edges[e], err);
        }
    }
    if (st) goto done;

    if (K == 2) { /* corners of uncovered faces, bucketed by vertex: (face << 2) | corner */
        int *vc_start = calloc((size_t)m->nv + 1, sizeof *vc_start), *vc_list = malloc(4 * (size_t)m->nf * sizeof *vc_list);
        if (!vc_start || !vc_list) st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (corner lists)");
        for (int f = 0; f < m->nf && !st; f++)
            if (unc[f])
                for (int k = 0; k < 4; k++) vc_start[q2n_he_origin(m, q2n_face_he(m, f, k)) + 1]++;
        for (int v = 0; v < m->nv && !st; v++) vc_start[v + 1] += vc_start[v];
        for (int f = 0; f < m->nf && !st; f++)
            if (unc[f])
                for (int k = 0; k < 4; k++) {
                    int v = q2n_he_origin(m, q2n_face_he(m, f, k));
                    vc_list[vc_start[v]++] = f << 2 | k;
                }
        for (int v = m->nv; v > 0 && !st; v--) vc_start[v] = vc_start[v - 1];
        if (!st) vc_start[0] = 0;
        for (int v = 0; v < m->nv && !st; v++)
            st = harmonize_vertex(m, s, iv, unc, edges, K, cls->k, vc_start, vc_list, v, err);
        free(vc_start);
        free(vc_list);
    }
    if (st) goto done;

    for (int f = 0; f < m->nf; f++) {
        if (!unc[f]) continue;
        ev_patch *P = calloc(1, sizeof *P);
        if (!P) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (patch %d)", f); goto done; }
        patches[f] = P;
        if ((st = patch_setup(P, m, s, iv, unc, edges, K, cls->k, f, err))) goto done;
    }
    for (int f = 0; f < m->nf; f++) {
        if (!patches[f]) continue;
        if ((st = q2n_surface_set_patch(s, f, Q2N_PATCH_COONS_GREGORY, patches[f], patch_eval, patch_free))) {
            q2n_error_set(err, st, "%s: face %d: cannot attach the patch", m->name, f);
            goto done;
        }
        q2n_surface_set_patch_grid(s, f, patch_grid);
        q2n_surface_set_patch_corner(s, f, patch_corner);
        patches[f] = NULL;
    }
done:
    if (patches)
        for (int f = 0; f < m->nf; f++) free(patches[f]);
    if (edges)
        for (int e = 0; e < m->ne; e++) free(edges[e]);
    free(patches);
    free(edges);
    free(unc);
    free(dir);
    free(jets);
    free(own);
    return st;
}
