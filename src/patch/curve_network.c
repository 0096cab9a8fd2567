/* curve_network.c — boundary curves and cross-boundary derivative fields of the extraordinary
 * patches (seed 003 §4.3; formulas.md §4.2 "G1/G2 conditions across a shared edge").
 *
 * A constructed edge (both faces extraordinary, or a mesh-boundary edge of one) carries, in the
 * local variable x = t·d of the edge (d its interval, t in [0,1] from origin(edge_he) to dest):
 *   γ(t)  the polynomial Hermite segment (cubic for G1, quintic for G2) with end derivatives
 *         J1·u, J2[u,u] from the vertex jets (ev_derivatives.c) — when a jet comes from a
 *         regular patch these are the derivatives of the neighbouring regular section segment,
 *         so the section curve keeps its C1/C2 continuity through the vertex;
 *   n(t)  a cubic Hermite field between the unit normals of the two jets, its end derivatives
 *         the D-components of the jets' Weingarten maps along the edge (q2n_ev_jet_dn; the other
 *         components do not reach D and D' at the ends, and would tilt n towards T inside);
 *   a ribbon frame T = γ_x/|γ_x|, D = n × T/|n × T| shared by the two faces (formulas.md §4.3,
 *         the "perpendicular ribbon" of Salvi–Várady), and for each face χ = a(t) D + b(t) T with
 *         a, b linear between the values that give χ = J1·w at the two ends (w: the face's other
 *         edge there).  Hence χ_R = α χ_L + β γ_x with scalar α = a_R/a_L, β: the G1 condition;
 *   base side (of the two faces, the one whose cross direction is the more transversal to the
 *         edge, ev_edge.base_twin): ξ_L linear between J2[w,w] at the ends;
 *   derived side (face of the twin): ξ_R = τ1 D + τ2 T + c N, N = D × T, c making its normal part
 *         equal that of α² ξ_L + 2αβ ∂xχ_L + β² γ_xx (the G2 condition of formulas.md §4.2; its
 *         γ, δ terms are absorbed by τ1, τ2, linear between the tangential parts of the corner
 *         values J2[w',w']).  Since n' is the Weingarten derivative, n·∂xχ_L equals the jet's
 *         II(u,w) at the ends, so the derived side meets its corner values exactly (corner
 *         compatibility, needed by the Coons patch), and both patches join G1/G2 exactly.
 * Corner compatibility (G2 mode): polynomial bumps local to one end (ev_edge: nb, g3, g4, a2,
 * b2, x1, x2, t1, t2) set the higher end derivatives that the 2-jets leave free, so that the two
 * sides of every patch corner agree on the mixed derivatives up to ∂u²∂v² (ev_harmonize.c,
 * q2n_ev_harmonize_vertex); they are zero as built here.
 * The derived quantities are rational in t; they are evaluated with derivative arrays up to order
 * 3 (Leibniz, Faà di Bruno), since the patch needs ξ_R and its two t-derivatives.
 * Sides shared with a regular patch are not built here: q2n_ev_side_eval samples that patch's
 * boundary and cross fields and divides them by its local parametrization function (§4.1). */
#include <math.h>
#include <string.h>

#include "core/jet.h"
#include "core/poly.h"
#include "core/vec3.h"
#include "patch/ev_internal.h"
#include "patch/ev_policy.h"

/* ------------------------------------------------------------ polynomials */

void q2n_ev_poly_eval(const ev_poly *p, double t, int nder, double out[][3])
{
    q2n_poly_derivs_n(&p->c[0][0], 3, p->deg, t, nder, &out[0][0]);
}

static void poly_zero(ev_poly *p) { memset(p, 0, sizeof *p); }

/* Hermite interpolant on [0,1]: values/derivatives (in t) at 0 and 1, order K (1: cubic,
 * 2: quintic).  v0[a], v1[a] = a-th t-derivative. */
static void poly_hermite(int K, const double v0[3][3], const double v1[3][3], ev_poly *out)
{
    poly_zero(out);
    out->deg = 2 * K + 1;
    for (int a = 0; a <= K; a++)
        for (int i = 0; i < 6; i++) {
            double h0 = q2n_hermite_coef[K - 1][a][0][i], h1 = q2n_hermite_coef[K - 1][a][1][i];
            for (int c = 0; c < 3; c++) out->c[i][c] += h0 * v0[a][c] + h1 * v1[a][c];
        }
}

/* ------------------------------------------------------------ derivative arrays
 * f[k] = k-th t-derivative, k = 0..3: jets of order JO - 1 (core/jet.h). */
#define JO 4

static void lin(double v0, double v1, double t, double *r)
{
    r[0] = v0 + (v1 - v0) * t;
    r[1] = v1 - v0;
    r[2] = r[3] = 0;
}

/* Cubic Hermite scalar: values v[0], v[1] and t-slopes s[0], s[1] at t = 0, 1. */
static void herm(const double v[2], const double s[2], double t, double *r)
{
    double H[2][2][Q2N_HERMITE_MAXD + 1];
    q2n_hermite_eval(1, t, JO - 1, H);
    for (int k = 0; k < JO; k++) r[k] = H[0][0][k] * v[0] + H[0][1][k] * v[1] + H[1][0][k] * s[0] + H[1][1][k] * s[1];
}

/* Corner-compatibility bumps (ev_edge): E_p = t^p (1-t)^q / p! at end 0 (p = 1: C, 2: B, 3, 4
 * for γ), mirrored at end 1 with the sign that makes its p-th t-derivative there 1; derivatives
 * 0..nder (<= 5) at t.  q = 4 for the ribbon data and 5 for γ: the other end's corner values use
 * up to third t-derivatives of n, a, b and up to fourth of γ (the derived side's ξ'' through
 * γ_xx''), which must not change there. */
static void bump_n(int end, int p, int loc, double t, int nder, double *r)
{
    int q = (p >= 3 ? 5 : 4) + loc;
    double c[20] = {0}, v[6];
    for (int i = 0; i <= q; i++) /* t^p (1 - t)^q / p! in the power basis */
        c[p + i] = (i & 1 ? -q2n_binom[q][i] : q2n_binom[q][i]) / q2n_factorial[p];
    double x = end ? 1 - t : t, sg = end && (p & 1) ? -1 : 1;
    q2n_poly_derivs(c, 19, x, nder, v);
    for (int k = 0; k <= nder; k++) r[k] = sg * (end && (k & 1) ? -v[k] : v[k]); /* d/dt = -d/dx at end 1 */
}

static void bump(const ev_edge *E, int end, int kind, double t, double *r) { bump_n(end, kind, E->loc[end], t, JO - 1, r); }

/* s + Σ_end (w2[end] B_end + w1[end] C_end) as derivative arrays (w1 may be NULL) */
static void add_bumps(const ev_edge *E, double *s, const double w1[2], const double w2[2], double t)
{
    double r[JO];
    for (int end = 0; end < 2; end++) {
        if (w2[end] != 0) { bump(E, end, 2, t, r); for (int k = 0; k < JO; k++) s[k] += w2[end] * r[k]; }
        if (w1 && w1[end] != 0) { bump(E, end, 1, t, r); for (int k = 0; k < JO; k++) s[k] += w1[end] * r[k]; }
    }
}

/* The ribbon frame along a constructed edge as derivative arrays: γ's t-derivatives g[0..5],
 * γ_x and γ_xx, T = γ_x/|γ_x| (with rs = 1/|γ_x|) and D = n × T/|n × T|. */
typedef struct ribbon {
    double g[6][3], Gx[JO][3], Gxx[JO][3], T[JO][3], D[JO][3], rs[JO];
} ribbon;

static void ribbon_at(const ev_edge *E, double t, ribbon *R)
{
    double n[JO][3] = {{0}}, sq[JO], rd[JO], d = E->d;
    memset(R, 0, sizeof *R);
    q2n_ev_poly_eval(&E->gamma, t, E->gamma.deg < 5 ? E->gamma.deg : 5, R->g);
    for (int end = 0; end < 2; end++)
        for (int p = 3; p <= 4; p++) {
            double w = p == 3 ? E->g3[end] : E->g4[end], r[6];
            if (w == 0) continue;
            bump_n(end, p, E->loc[end], t, 5, r);
            for (int k = 0; k < 6; k++) q2n_v3_axpy(R->g[k], w * r[k], E->nN[end]);
        }
    q2n_ev_poly_eval(&E->nrm, t, 3, n);
    for (int end = 0; end < 2; end++)
        if (E->nb[end] != 0) {
            double r[JO];
            bump(E, end, 2, t, r);
            for (int k = 0; k < JO; k++) q2n_v3_axpy(n[k], E->nb[end] * r[k], E->nD[end]);
        }
    for (int k = 0; k < JO; k++)
        for (int c = 0; c < 3; c++) {
            R->Gx[k][c] = R->g[k + 1][c] / d;
            R->Gxx[k][c] = k + 2 < 6 ? R->g[k + 2][c] / (d * d) : 0;
        }
    q2n_jet3_dot(JO - 1, R->Gx, R->Gx, sq);
    q2n_jet_rsqrt_n(JO - 1, sq, R->rs);
    q2n_jet3_scale(JO - 1, R->rs, R->Gx, R->T);
    q2n_jet3_cross(JO - 1, n, R->T, R->D);
    q2n_jet3_dot(JO - 1, R->D, R->D, sq);
    q2n_jet_rsqrt_n(JO - 1, sq, rd);
    q2n_jet3_scale(JO - 1, rd, R->D, R->D);
}

/* ------------------------------------------------------------ constructed edges */

static const double *edge_dir(const q2n_mesh *m, const double (*dir)[2], int e, int v)
{
    return dir[2 * e + (q2n_he_origin(m, m->edge_he[e]) == v ? 0 : 1)];
}

/* The end of edge e other than v. */
static int edge_other(const q2n_mesh *m, int e, int v)
{
    int h = m->edge_he[e];
    return q2n_he_origin(m, h) == v ? q2n_he_dest(m, h) : q2n_he_origin(m, h);
}

/* The face's other edges at p and q for the half-edge hF of edge e (p = origin(edge_he)). */
static void other_edges(const q2n_mesh *m, int hF, int p, int *ep, int *eq)
{
    int fwd = q2n_he_origin(m, hF) == p;
    *ep = m->he_edge[fwd ? q2n_he_prev(m, hF) : q2n_he_next(m, hF)];
    *eq = m->he_edge[fwd ? q2n_he_next(m, hF) : q2n_he_prev(m, hF)];
}

/* Coefficients (a, b) with a D + b G = r for r in the plane of D and G (least squares). */
static int decompose(const double D[3], const double G[3], const double r[3], double *a, double *b)
{
    double dd = q2n_v3_dot(D, D), dg = q2n_v3_dot(D, G), gg = q2n_v3_dot(G, G);
    double rd = q2n_v3_dot(r, D), rg = q2n_v3_dot(r, G), det = dd * gg - dg * dg;
    if (!(det > 1e-14 * dd * gg)) return 0;
    *a = (rd * gg - rg * dg) / det;
    *b = (rg * dd - rd * dg) / det;
    return 1;
}


/* The refusal of an edge whose cross-boundary ribbon has no direction across it at its end vertex
 * v (the face's other edge there is ew): named by the vertex, with the face's corner angle there.
 * The usual cause is the paper's chart of a boundary vertex of one or two faces, quarter turns
 * whatever its angles (a three-sided pyramid's 52-degree rim corners; until stop 40 the message
 * was "degenerate ribbon"). */
static q2n_status ribbon_error(const q2n_mesh *m, int e, int v, int ew, q2n_error *err)
{
    char where[300], of[48];
    q2n_mesh_vertex_where(m, v, where, sizeof where);
    q2n_mesh_of(m, 0, of, sizeof of);
    int o = edge_other(m, e, v), ow = edge_other(m, ew, v);
    double ang = q2n_v3_corner_deg(q2n_mesh_vpos(m, v), q2n_mesh_vpos(m, o), q2n_mesh_vpos(m, ow));
    int quarter = m->vert_boundary[v] && m->vert_nfaces[v] <= 2; /* charted by quarter turns */
    return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                         "%s: vertex %d (of this face%s): the paper's construction finds no direction across "
                         "edge %d-%d there (the face's corner between it and edge %d-%d is %.1f degrees%s); the "
                         "default, --ev-construction fair, charts every vertex by its own angles",
                         where, v, of, v, o, v, ow, ang,
                         quarter ? ", and its chart draws a boundary vertex of one or two faces with right angles"
                                 : ": a degenerate fan?");
}

q2n_status q2n_ev_build_edge(const q2n_mesh *m, const double *iv, const ev_vjet *jets,
                         const double (*dir)[2], int order, int e, ev_edge *out, q2n_error *err)
{
    int h = m->edge_he[e], p = q2n_he_origin(m, h), q = q2n_he_dest(m, h), tw = m->he_twin[h];
    double d = iv[e];
    const ev_vjet *Jp = &jets[p], *Jq = &jets[q];
    memset(out, 0, sizeof *out);
    out->d = d;
    if (!Jp->source || !Jq->source)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: edge %d: missing vertex derivative data", m->name, e);
    const double *up = edge_dir(m, dir, e, p), *uq = edge_dir(m, dir, e, q);
    /* boundary curve γ: Hermite data in t (x = t d) */
    double g0[3][3], g1[3][3];
    memcpy(g0[0], q2n_mesh_vpos(m, p), sizeof g0[0]);
    memcpy(g1[0], q2n_mesh_vpos(m, q), sizeof g1[0]);
    q2n_ev_jet_d1(Jp, up, g0[1]);
    q2n_ev_jet_d1(Jq, uq, g1[1]);
    q2n_ev_jet_d2(Jp, up, up, g0[2]);
    q2n_ev_jet_d2(Jq, uq, uq, g1[2]);
    for (int c = 0; c < 3; c++) {
        g0[1][c] *= d; g1[1][c] *= -d; /* towards q: the jet at q looks back along -x */
        g0[2][c] *= d * d; g1[2][c] *= d * d;
    }
    poly_hermite(order, g0, g1, &out->gamma);
    /* normal field: the jets' normals, with their Weingarten derivatives along the edge (this
     * makes the normal twist of the fields equal to the jets' II(u, w), which G2 needs) */
    double n0[3][3], n1[3][3];
    if (!q2n_ev_jet_normal(Jp, n0[0]) || !q2n_ev_jet_normal(Jq, n1[0]))
        return q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: edge %d: degenerate tangent plane at a vertex", m->name, e);
    q2n_ev_jet_dn(Jp, up, n0[1]);
    q2n_ev_jet_dn(Jq, uq, n1[1]);
    for (int c = 0; c < 3; c++) { n0[1][c] *= d; n1[1][c] *= -d; n0[2][c] = n1[2][c] = 0; }
    poly_hermite(1, n0, n1, &out->nrm);
    out->face[0] = m->he_face[h];
    out->face[1] = tw >= 0 ? m->he_face[tw] : -1;
    ribbon R0, R1;
    ribbon_at(out, 0, &R0);
    ribbon_at(out, 1, &R1);
    /* Keep only the D-component of the end slopes n'.  At an end n is the unit jet normal and
     * T lies in its tangent plane, so (n × T)' = n' × T + n × T' and: the n-component of n'
     * gives a multiple of n × T, removed by the normalisation of D; the T-component gives
     * T × T = 0; only n'·D turns D (D' · n = -n'·D).  D and D' at the ends, hence the corner
     * values, the twists and the G1/G2 argument above, are unchanged.  The T-component (the
     * normal curvature along the edge) otherwise tilts the interior of the cubic n(t) towards
     * the edge tangent: |n × T|/|n| can fall to a few thousandths, and D then swings around the
     * edge within a short stretch, a derivative spike the fit cannot follow. */
    {
        double k0 = q2n_v3_dot(n0[1], R0.D[0]), k1 = q2n_v3_dot(n1[1], R1.D[0]);
        for (int c = 0; c < 3; c++) { n0[1][c] = k0 * R0.D[0][c]; n1[1][c] = k1 * R1.D[0][c]; }
    }
    poly_hermite(1, n0, n1, &out->nrm);
    ribbon_at(out, 0, &R0);
    ribbon_at(out, 1, &R1);
    const double *D0 = R0.D[0], *G0 = R0.T[0], *D1 = R1.D[0], *G1 = R1.T[0];
    /* Base side: the face whose cross-boundary direction is the more transversal to the edge
     * (larger min over the ends of |a| / |χ|, the sine of the angle to the edge).  The derived
     * side divides by the base side's a (α = a_R / a_L): with the other choice, a face meeting
     * the edge at a small angle made α and its derivatives large, and the derived data wild
     * near the vertex (mixed corner derivatives tens of times those of the base side).  Within
     * EV_BASE_TIE of a tie the base is the edge's owner face (h), so that rounding-level changes
     * of a symmetric mesh do not flip the choice (docs/extraordinary.md, "Base faces"). */
    int hs[2] = {h, tw};
    if (tw >= 0) {
        double sn[2];
        for (int x = 0; x < 2; x++) {
            int ep, eq;
            other_edges(m, hs[x], p, &ep, &eq);
            double c0[3], c1[3], a0 = 0, b0 = 0, a1 = 0, b1 = 0;
            q2n_ev_jet_d1(Jp, edge_dir(m, dir, ep, p), c0);
            q2n_ev_jet_d1(Jq, edge_dir(m, dir, eq, q), c1);
            decompose(D0, G0, c0, &a0, &b0);
            decompose(D1, G1, c1, &a1, &b1);
            sn[x] = fmin(fabs(a0) / (q2n_v3_norm(c0) + 1e-300), fabs(a1) / (q2n_v3_norm(c1) + 1e-300));
        }
        if (sn[1] > sn[0] * (1.0 + EV_BASE_TIE)) { hs[0] = tw; hs[1] = h; out->base_twin = 1; }
    }
    out->face[0] = m->he_face[hs[0]];
    out->face[1] = tw >= 0 ? m->he_face[hs[1]] : -1;
    memcpy(out->nD[0], D0, sizeof out->nD[0]);
    memcpy(out->nD[1], D1, sizeof out->nD[1]);
    q2n_v3_cross(out->nN[0], D0, G0);
    q2n_v3_cross(out->nN[1], D1, G1);
    for (int side = 0; side < (tw >= 0 ? 2 : 1); side++) {
        int ep, eq;
        other_edges(m, hs[side], p, &ep, &eq);
        const double *wb = edge_dir(m, dir, ep, p), *wc = edge_dir(m, dir, eq, q);
        double c0[3], c1[3], x0[3], x1[3], t0[3], t1[3];
        q2n_ev_jet_d1(Jp, wb, c0);
        q2n_ev_jet_d1(Jq, wc, c1);
        q2n_ev_jet_d2(Jp, wb, wb, x0);
        q2n_ev_jet_d2(Jq, wc, wc, x1);
        int ok0 = decompose(D0, G0, c0, &out->a[side][0], &out->b[side][0]);
        if (!ok0 || !decompose(D1, G1, c1, &out->a[side][1], &out->b[side][1]))
            return ribbon_error(m, e, ok0 ? q : p, ok0 ? eq : ep, err);
        /* slopes of a, b: the field's t-derivative at each end is the jet's twist d·J2[u,w]
         * (its normal part holds by the choice of n'; the slopes fix the tangential part), so
         * that the two sides of a patch corner that both come from one jet have compatible
         * twists and the Gregory correction is not needed there */
        q2n_ev_jet_d2(Jp, up, wb, t0);
        q2n_ev_jet_d2(Jq, uq, wc, t1);
        for (int end = 0; end < 2; end++) {
            const ribbon *R = end ? &R1 : &R0;
            double want[3], rest[3];
            double a = out->a[side][end], b = out->b[side][end];
            for (int c = 0; c < 3; c++) {
                want[c] = (end ? -d * t1[c] : d * t0[c]);
                rest[c] = want[c] - a * R->D[1][c] - b * R->T[1][c];
            }
            out->as[side][end] = q2n_v3_dot(rest, R->D[0]);
            out->bs[side][end] = q2n_v3_dot(rest, R->T[0]);
        }
        /* a must keep its sign along the edge (a = 0 would fold the ribbon): keep the Bézier
         * coefficients a0 + s0/3, a1 - s1/3 of the cubic on the side of a0, a1 (at least a sixth) */
        double *av = out->a[side], *sl = out->as[side];
        double sg = av[0] > 0 ? 1 : -1;
        if (sg * (av[0] + sl[0] / 3) < sg * av[0] / 6) sl[0] = 3 * (av[0] / 6 - av[0]);
        if (sg * (av[1] - sl[1] / 3) < sg * av[1] / 6) sl[1] = -3 * (av[1] / 6 - av[1]);
        if (side == 0) {
            poly_zero(&out->xi);
            out->xi.deg = 1;
            for (int c = 0; c < 3; c++) { out->xi.c[0][c] = x0[c]; out->xi.c[1][c] = x1[c] - x0[c]; }
        } else { /* tangential part of the corner values of the derived side's ξ */
            double N[3], xt[3];
            for (int end = 0; end < 2; end++) {
                const double *X = end ? x1 : x0, *D = end ? D1 : D0, *G = end ? G1 : G0;
                q2n_v3_cross(N, D, G);
                memcpy(xt, X, sizeof xt);
                q2n_v3_axpy(xt, -q2n_v3_dot(X, N) / q2n_v3_dot(N, N), N);
                decompose(D, G, xt, &out->tau[end][0], &out->tau[end][1]);
            }
        }
    }
    if (tw >= 0 && !(out->a[0][0] * out->a[1][0] < 0 && out->a[0][1] * out->a[1][1] < 0))
        return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                             "%s: edge %d (%d-%d): fan directions do not separate the two faces", m->name, e, p, q);
    out->built = 1;
    return Q2N_OK;
}

/* Cross field of one side (0 base, 1 derived): χ = a D + b T with its ribbon coefficients a, b
 * (cubic Hermite plus the corner-compatibility bumps), as derivative arrays. */
static void side_chi(const ev_edge *E, int side, double t, double D[JO][3], double T[JO][3], double *a, double *b,
                     double C[JO][3])
{
    double tmp[JO][3];
    herm(E->a[side], E->as[side], t, a);
    herm(E->b[side], E->bs[side], t, b);
    add_bumps(E, a, E->a1[side], E->a2[side], t);
    add_bumps(E, b, E->b1[side], E->b2[side], t);
    q2n_jet3_scale(JO - 1, a, D, C);
    q2n_jet3_scale(JO - 1, b, T, tmp);
    q2n_jet3_add(JO - 1, C, tmp, C);
}

/* Constructed edge: fields of one side at t, t-derivatives 0..2. */
static void constructed_eval(const ev_edge *E, int derived, double t, double out[3][3][3])
{
    ribbon R;
    ribbon_at(E, t, &R);
    double (*D)[3] = R.D, (*Tu)[3] = R.T, (*Gx)[3] = R.Gx, (*Gxx)[3] = R.Gxx, (*g)[3] = R.g, *rs = R.rs, d = E->d;
    (void)Gx;
    double aL[JO], bL[JO], CL[JO][3], tmp[JO][3];
    side_chi(E, 0, t, D, Tu, aL, bL, CL);
    double xl[JO][3] = {{0}};
    q2n_ev_poly_eval(&E->xi, t, 2, xl);
    for (int end = 0; end < 2; end++) {
        double r1[JO], r2[JO];
        bump(E, end, 1, t, r1);
        bump(E, end, 2, t, r2);
        for (int k = 0; k < JO; k++)
            for (int c = 0; c < 3; c++) xl[k][c] += E->x1[end][c] * r1[k] + E->x2[end][c] * r2[k];
    }
    for (int k = 0; k < 3; k++) memcpy(out[0][k], g[k], sizeof g[k]);
    if (!derived) {
        for (int k = 0; k < 3; k++) { memcpy(out[1][k], CL[k], sizeof CL[k]); memcpy(out[2][k], xl[k], sizeof xl[k]); }
        return;
    }
    /* derived side: χ_R = a_R D + b_R γ_x; G2 condition (formulas.md §4.2) with α = a_R / a_L,
     * β = b_R - b_L α: the normal part of ξ_R is that of α² ξ_L + 2αβ ∂xχ_L + β² γ_xx */
    double aR[JO], bR[JO], CR[JO][3], al[JO], be[JO], inv[JO];
    side_chi(E, 1, t, D, Tu, aR, bR, CR);
    q2n_jet_inv_n(JO - 1, aL, inv);
    q2n_jet_mul_n(JO - 1, aR, inv, al);
    q2n_jet_mul_n(JO - 1, bL, al, be);
    for (int k = 0; k < JO; k++) be[k] = bR[k] - be[k];
    q2n_jet_mul_n(JO - 1, be, rs, be); /* χ_R = α χ_L + β γ_x */
    double CLx[JO][3] = {{0}}, XL[JO][3] = {{0}}, Y[JO][3], al2[JO], ab2[JO], be2[JO], N[JO][3];
    for (int k = 0; k + 1 < JO; k++)
        for (int c = 0; c < 3; c++) CLx[k][c] = CL[k + 1][c] / d;
    for (int k = 0; k < JO; k++) memcpy(XL[k], xl[k], sizeof xl[k]);
    q2n_jet_mul_n(JO - 1, al, al, al2);
    q2n_jet_mul_n(JO - 1, al, be, ab2);
    for (int k = 0; k < JO; k++) ab2[k] *= 2;
    q2n_jet_mul_n(JO - 1, be, be, be2);
    q2n_jet3_scale(JO - 1, al2, XL, Y);
    q2n_jet3_scale(JO - 1, ab2, CLx, tmp);
    q2n_jet3_add(JO - 1, Y, tmp, Y);
    q2n_jet3_scale(JO - 1, be2, Gxx, tmp);
    q2n_jet3_add(JO - 1, Y, tmp, Y);
    q2n_jet3_cross(JO - 1, D, Gx, N);
    double ny[JO], nn[JO], c[JO], t1[JO], t2[JO], XR[JO][3];
    q2n_jet3_dot(JO - 1, N, Y, ny);
    q2n_jet3_dot(JO - 1, N, N, nn);
    q2n_jet_inv_n(JO - 1, nn, inv);
    q2n_jet_mul_n(JO - 1, ny, inv, c);
    q2n_jet3_scale(JO - 1, c, N, XR);
    lin(E->tau[0][0], E->tau[1][0], t, t1);
    lin(E->tau[0][1], E->tau[1][1], t, t2);
    {
        double w1[2][2] = {{E->t1[0][0], E->t1[1][0]}, {E->t1[0][1], E->t1[1][1]}};
        double w2[2][2] = {{E->t2[0][0], E->t2[1][0]}, {E->t2[0][1], E->t2[1][1]}};
        add_bumps(E, t1, w1[0], w2[0], t);
        add_bumps(E, t2, w1[1], w2[1], t);
    }
    q2n_jet3_scale(JO - 1, t1, D, tmp);
    q2n_jet3_add(JO - 1, XR, tmp, XR);
    q2n_jet3_scale(JO - 1, t2, Tu, tmp);
    q2n_jet3_add(JO - 1, XR, tmp, XR);
    for (int k = 0; k < 3; k++) { memcpy(out[1][k], CR[k], sizeof CR[k]); memcpy(out[2][k], XR[k], sizeof XR[k]); }
}

/* ------------------------------------------------------------ side evaluation */

/* Local parametrization function of a regular patch across its side sR, at side parameter t
 * (eq. 7): ε(u) for the sides v = 0, 1, δ(v) for u = 0, 1; out[0..2] value and derivatives. */
static void regular_lambda(const q2n_augmented_patch *R, int sR, double t, double out[4])
{
    int c = R->w / 2 - 1;
    if (q2n_side_along_u(sR)) q2n_spline_blend_derivs(R->cls->k, R->ecol[0][c], R->ecol[1][c], t, out);
    else q2n_spline_blend_derivs(R->cls->k, R->drow[0][c], R->drow[1][c], t, out);
}

void q2n_ev_side_eval(const ev_side *sd, double s, double out[3][3][3])
{
    double t = sd->rev ? 1 - s : s;
    if (sd->kind == 0) {
        constructed_eval(&sd->E, sd->derived, t, out);
    } else {
        /* regular neighbour: its side sR in its own coordinate (u on sides 0/2, v on 1/3) */
        const q2n_augmented_patch *R = &sd->R;
        int sR = sd->sR, along_u = q2n_side_along_u(sR);
        double uR = along_u ? t : q2n_side_level[sR];
        double vR = along_u ? q2n_side_level[sR] : t;
        double D[27], f[3][3], L[4], iL[3], iL2[3];
        q2n_ev_regular_partials(R, uR, vR, D);
        regular_lambda(R, sR, t, L);
        q2n_jet_inv_n(2, L, iL);
        q2n_jet_mul_n(2, iL, iL, iL2);
        double sg = -q2n_side_iota[sR];
        for (int c = 0; c < 3; c++)
            for (int b = 0; b < 3; b++) { /* transverse order b: jets (along-side derivatives) of ∂n^b R */
                for (int a = 0; a < 3; a++) f[b][a] = D[3 * (along_u ? a * 3 + b : b * 3 + a) + c];
                /* §4.1: χ = (inward ∂ of R) / λ_R, then seen from the other side: -χ; ξ = ∂²/λ_R² */
                double q[3];
                if (b == 0) memcpy(q, f[0], sizeof q);
                else q2n_jet_mul_n(2, f[b], b == 1 ? iL : iL2, q);
                for (int a = 0; a < 3; a++) out[b][a][c] = (b == 1 ? sg : 1) * q[a];
            }
    }
    if (sd->rev)
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 3; c++) out[b][1][c] = -out[b][1][c];
}
