/* curve_network.c — boundary curves and cross-boundary derivative fields of the extraordinary
 * patches (seed 003 §4.3; formulas.md §4.2 "G1/G2 conditions across a shared edge").
 *
 * A constructed edge (both faces extraordinary, or a mesh-boundary edge of one) carries, in the
 * local variable x = t·d of the edge (d its interval, t in [0,1] from origin(edge_he) to dest):
 *   γ(t)  the polynomial Hermite segment (cubic for G1, quintic for G2) with end derivatives
 *         J1·u, J2[u,u] from the vertex jets (ev_derivatives.c) — when a jet comes from a
 *         regular patch these are the derivatives of the neighbouring regular section segment,
 *         so the section curve keeps its C1/C2 continuity through the vertex;
 *   base side (face of edge_he): χ_L cubic Hermite with χ_L = J1·w, dχ_L/dx = J2[u,w] at both
 *         ends (w: the face's other edge at that end), ξ_L linear between J2[w,w];
 *   derived side (face of the twin): χ_R = α χ_L + β γ_x and
 *         ξ_R = α² ξ_L + 2αβ ∂xχ_L + β² γ_xx   (the G1 and G2 conditions with scalar α, β
 *         linear in t; the γ/δ terms of the G2 condition are zero), α, β solved at each end
 *         from w' = α w + β u in the jet's plane.  Both patches therefore join G1/G2 exactly,
 *         and at the ends every field equals the derivative of the adjacent curve (corner
 *         compatibility), also for the derived side, because all come from one jet.
 * Sides shared with a regular patch are not built here: ev_side_eval samples that patch's
 * boundary and cross fields and divides them by its local parametrization function (§4.1). */
#include <math.h>
#include <string.h>

#include "core/vec3.h"
#include "patch/ev_internal.h"

/* ------------------------------------------------------------ polynomials */

void ev_poly_eval(const ev_poly *p, double t, int nder, double out[][3])
{
    for (int q = 0; q <= nder; q++) {
        double r[3] = {0, 0, 0};
        for (int i = p->deg; i >= q; i--) {
            double f = 1;
            for (int j = 0; j < q; j++) f *= (double)(i - j);
            for (int c = 0; c < 3; c++) r[c] = r[c] * t + f * p->c[i][c];
        }
        memcpy(out[q], r, sizeof r);
    }
}

static void poly_zero(ev_poly *p) { memset(p, 0, sizeof *p); }

/* p += s(t) * v where s is a scalar polynomial (coefficients sc[0..sd]) and v a vector poly */
static void poly_add_mul(ev_poly *p, const double *sc, int sd, const ev_poly *v)
{
    for (int i = 0; i <= sd; i++)
        for (int j = 0; j <= v->deg; j++) {
            if (i + j > EV_MAXDEG) continue;
            for (int c = 0; c < 3; c++) p->c[i + j][c] += sc[i] * v->c[j][c];
            if (i + j > p->deg) p->deg = i + j;
        }
}

static void poly_deriv(const ev_poly *p, double scale, ev_poly *out)
{
    ev_poly r;
    poly_zero(&r);
    r.deg = p->deg > 0 ? p->deg - 1 : 0;
    for (int i = 1; i <= p->deg; i++)
        for (int c = 0; c < 3; c++) r.c[i - 1][c] = scale * i * p->c[i][c];
    *out = r;
}

/* Hermite interpolant on [0,1]: values/derivatives (in t) at 0 and 1, order K (1: cubic,
 * 2: quintic).  v0[a], v1[a] = a-th t-derivative. */
static void poly_hermite(int K, const double v0[3][3], const double v1[3][3], ev_poly *out)
{
    /* power coefficients of H_{a,0} and H_{a,1} (formulas.md §4.1) */
    static const double H3[2][2][6] = {{{1, 0, -3, 2, 0, 0}, {0, 0, 3, -2, 0, 0}},
                                       {{0, 1, -2, 1, 0, 0}, {0, 0, -1, 1, 0, 0}}};
    static const double H5[3][2][6] = {{{1, 0, 0, -10, 15, -6}, {0, 0, 0, 10, -15, 6}},
                                       {{0, 1, 0, -6, 8, -3}, {0, 0, 0, -4, 7, -3}},
                                       {{0, 0, 0.5, -1.5, 1.5, -0.5}, {0, 0, 0, 0.5, -1, 0.5}}};
    poly_zero(out);
    out->deg = K == 1 ? 3 : 5;
    for (int a = 0; a <= K; a++)
        for (int i = 0; i < 6; i++) {
            double h0 = K == 1 ? H3[a][0][i] : H5[a][0][i], h1 = K == 1 ? H3[a][1][i] : H5[a][1][i];
            for (int c = 0; c < 3; c++) out->c[i][c] += h0 * v0[a][c] + h1 * v1[a][c];
        }
}

/* ------------------------------------------------------------ constructed edges */

static const double *edge_dir(const q2n_mesh *m, const double (*dir)[2], int e, int v)
{
    return dir[2 * e + (q2n_he_origin(m, m->edge_he[e]) == v ? 0 : 1)];
}

/* The face's other edges at p and q for the half-edge hF of edge e (p = origin(edge_he)). */
static void other_edges(const q2n_mesh *m, int hF, int p, int *ep, int *eq)
{
    int fwd = q2n_he_origin(m, hF) == p;
    *ep = m->he_edge[fwd ? q2n_he_prev(m, hF) : q2n_he_next(m, hF)];
    *eq = m->he_edge[fwd ? q2n_he_next(m, hF) : q2n_he_prev(m, hF)];
}

/* a x + b y = r in 2D; 0 if singular */
static int solve2(const double x[2], const double y[2], const double r[2], double *a, double *b)
{
    double det = x[0] * y[1] - x[1] * y[0];
    double sc = (fabs(x[0]) + fabs(x[1])) * (fabs(y[0]) + fabs(y[1]));
    if (!(fabs(det) > 1e-12 * sc)) return 0;
    *a = (r[0] * y[1] - r[1] * y[0]) / det;
    *b = (x[0] * r[1] - x[1] * r[0]) / det;
    return 1;
}

q2n_status ev_build_edge(const q2n_mesh *m, const double *iv, const ev_vjet *jets,
                         const double (*dir)[2], int order, int e, ev_edge *out, q2n_error *err)
{
    int h = m->edge_he[e], p = q2n_he_origin(m, h), q = q2n_he_dest(m, h), tw = m->he_twin[h];
    double d = iv[e];
    const ev_vjet *Jp = &jets[p], *Jq = &jets[q];
    memset(out, 0, sizeof *out);
    if (!Jp->source || !Jq->source)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: edge %d: missing vertex derivative data", m->name, e);
    const double *up = edge_dir(m, dir, e, p), *uq = edge_dir(m, dir, e, q);
    /* boundary curve γ: Hermite data in t (x = t d) */
    double g0[3][3], g1[3][3];
    memcpy(g0[0], q2n_mesh_vpos(m, p), sizeof g0[0]);
    memcpy(g1[0], q2n_mesh_vpos(m, q), sizeof g1[0]);
    ev_jet_d1(Jp, up, g0[1]);
    ev_jet_d1(Jq, uq, g1[1]);
    ev_jet_d2(Jp, up, up, g0[2]);
    ev_jet_d2(Jq, uq, uq, g1[2]);
    for (int c = 0; c < 3; c++) {
        g0[1][c] *= d; g1[1][c] *= -d; /* towards q: the jet at q looks back along -x */
        g0[2][c] *= d * d; g1[2][c] *= d * d;
    }
    poly_hermite(order, g0, g1, &out->gamma);
    out->face[0] = m->he_face[h];
    out->face[1] = tw >= 0 ? m->he_face[tw] : -1;

    /* base side */
    int ep, eq;
    other_edges(m, h, p, &ep, &eq);
    const double *wb = edge_dir(m, dir, ep, p), *wc = edge_dir(m, dir, eq, q);
    double c0[3][3], c1[3][3];
    ev_jet_d1(Jp, wb, c0[0]);
    ev_jet_d1(Jq, wc, c1[0]);
    ev_jet_d2(Jp, up, wb, c0[1]);
    ev_jet_d2(Jq, uq, wc, c1[1]);
    for (int c = 0; c < 3; c++) { c0[1][c] *= d; c1[1][c] *= -d; c0[2][c] = c1[2][c] = 0; }
    poly_hermite(1, c0, c1, &out->chi[0]);
    double x0[3], x1[3];
    ev_jet_d2(Jp, wb, wb, x0);
    ev_jet_d2(Jq, wc, wc, x1);
    poly_zero(&out->xi[0]);
    out->xi[0].deg = 1;
    for (int c = 0; c < 3; c++) { out->xi[0].c[0][c] = x0[c]; out->xi[0].c[1][c] = x1[c] - x0[c]; }
    if (tw < 0) { out->built = 1; return Q2N_OK; }

    /* derived side: G1/G2 conditions with scalar α, β linear in t */
    int fp, fq;
    other_edges(m, tw, p, &fp, &fq);
    const double *wb2 = edge_dir(m, dir, fp, p), *wc2 = edge_dir(m, dir, fq, q);
    double a0, b0, a1, b1, muq[2] = {-uq[0], -uq[1]};
    if (!solve2(wb, up, wb2, &a0, &b0) || !solve2(wc, muq, wc2, &a1, &b1) || !(a0 < 0) || !(a1 < 0))
        return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                             "%s: edge %d (%d-%d): fan directions do not separate the two faces", m->name, e, p, q);
    double al[2] = {a0, a1 - a0}, be[2] = {b0, b1 - b0};
    ev_poly gx, gxx, cx;
    poly_deriv(&out->gamma, 1.0 / d, &gx);  /* γ_x */
    poly_deriv(&gx, 1.0 / d, &gxx);         /* γ_xx */
    poly_deriv(&out->chi[0], 1.0 / d, &cx); /* ∂x χ_L */
    poly_zero(&out->chi[1]);
    poly_add_mul(&out->chi[1], al, 1, &out->chi[0]);
    poly_add_mul(&out->chi[1], be, 1, &gx);
    double al2[3] = {al[0] * al[0], 2 * al[0] * al[1], al[1] * al[1]};
    double be2[3] = {be[0] * be[0], 2 * be[0] * be[1], be[1] * be[1]};
    double ab2[3] = {2 * al[0] * be[0], 2 * (al[0] * be[1] + al[1] * be[0]), 2 * al[1] * be[1]};
    poly_zero(&out->xi[1]);
    poly_add_mul(&out->xi[1], al2, 2, &out->xi[0]);
    poly_add_mul(&out->xi[1], ab2, 2, &cx);
    poly_add_mul(&out->xi[1], be2, 2, &gxx);
    out->built = 1;
    return Q2N_OK;
}

/* ------------------------------------------------------------ side evaluation */

/* Local parametrization function of a regular patch across its side sR, at side parameter t
 * (eq. 7): ε(u) for the sides v = 0, 1, δ(v) for u = 0, 1; out[0..2] value and derivatives. */
static void regular_lambda(const q2n_augmented_patch *R, int sR, double t, double out[4])
{
    int c = R->w / 2 - 1;
    if (sR == 0 || sR == 2) q2n_spline_blend_derivs(R->cls->k, R->ecol[0][c], R->ecol[1][c], t, out);
    else q2n_spline_blend_derivs(R->cls->k, R->drow[0][c], R->drow[1][c], t, out);
}

void ev_side_eval(const ev_side *sd, double s, double out[3][3][3])
{
    double t = sd->rev ? 1 - s : s;
    if (sd->kind == 0) {
        ev_poly_eval(&sd->gamma, t, 2, out[0]);
        ev_poly_eval(&sd->chi, t, 2, out[1]);
        ev_poly_eval(&sd->xi, t, 2, out[2]);
    } else {
        /* regular neighbour: its side sR in its own coordinate (u on sides 0/2, v on 1/3) */
        static const int iota[4] = {1, -1, -1, 1}; /* inward sign of the transverse coordinate */
        const q2n_augmented_patch *R = &sd->R;
        int sR = sd->sR;
        double uR = sR == 0 || sR == 2 ? t : sR == 1 ? 1 : 0;
        double vR = sR == 1 || sR == 3 ? t : sR == 2 ? 1 : 0;
        double D[27], f[3][3][3], L[4];
        q2n_ev_regular_partials(R, uR, vR, D);
        for (int b = 0; b < 3; b++)     /* transverse order */
            for (int a = 0; a < 3; a++) /* along-side order */
                memcpy(f[b][a], D + 3 * ((sR == 0 || sR == 2) ? a * 3 + b : b * 3 + a), 3 * sizeof(double));
        regular_lambda(R, sR, t, L);
        double L2[3] = {L[0] * L[0], 2 * L[0] * L[1], 2 * L[1] * L[1] + 2 * L[0] * L[2]};
        for (int c = 0; c < 3; c++) {
            out[0][0][c] = f[0][0][c];
            out[0][1][c] = f[0][1][c];
            out[0][2][c] = f[0][2][c];
            /* §4.1: χ = (inward ∂ of R) / λ_R, then seen from the other side: -χ; ξ = ∂²/λ_R² */
            double q0 = f[1][0][c] / L[0];
            double q1 = (f[1][1][c] - q0 * L[1]) / L[0];
            double q2 = (f[1][2][c] - 2 * q1 * L[1] - q0 * L[2]) / L[0];
            double sg = -iota[sR];
            out[1][0][c] = sg * q0;
            out[1][1][c] = sg * q1;
            out[1][2][c] = sg * q2;
            double r0 = f[2][0][c] / L2[0];
            double r1 = (f[2][1][c] - r0 * L2[1]) / L2[0];
            double r2 = (f[2][2][c] - 2 * r1 * L2[1] - r0 * L2[2]) / L2[0];
            out[2][0][c] = r0;
            out[2][1][c] = r1;
            out[2][2][c] = r2;
        }
    }
    if (sd->rev)
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 3; c++) out[b][1][c] = -out[b][1][c];
}
