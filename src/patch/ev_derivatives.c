/* ev_derivatives.c — derivative data at the vertices of extraordinary regions (seed 003 §4.3
 * and Appendix B), and the full set of mixed partials of a regular augmented patch.
 *
 * Every vertex that is a corner of an extraordinary patch gets one 2-jet in local variables
 * (ev_internal.h):
 *   - if a regular augmented patch has the vertex as a corner, the jet is that patch's corner
 *     derivatives divided by its edge intervals (Lemma 1 / eq. (15) of seed 003: at a corner the
 *     local parametrization functions have vanishing derivatives, so ∂u S = d ∂x S,
 *     ∂uv S = d e ∂xy S, ...), and the four edges get the directions (±1,0), (0,±1);
 *   - otherwise it is the least-squares polynomial P of Appendix B (degree 3 for interior
 *     valence n >= 5, else 2) interpolating the vertex and approximating the 2n points q_j taken
 *     on cubic Hermite segments whose end tangents are the estimates (B.1)–(B.2); edge k gets the
 *     direction (cos η_k, sin η_k) with η from the angles between the tangent estimates.
 * Choices made where Appendix B leaves freedom (documented in docs/extraordinary.md):
 *   r_j in (B.3) is the parameter value of q_j (d_i/4, d_i/2), so that the directional
 *   derivatives of P are derivatives in the edge's local variable; valence-4 interior vertices
 *   and boundary vertices with at most two faces use η = kπ/2 so that section curves through
 *   them stay C2; boundary vertices spread their edge angles over a half turn (a quarter turn
 *   for corners); the normal equations get a relative ridge of 1e-9 (boundary fans may not
 *   determine every coefficient). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "patch/ev_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define MAXW Q2N_SPLINE_MAXW
#define MAXB Q2N_SPLINE_MAXB

/* ------------------------------------------------------------ regular patch partials */

void q2n_ev_regular_partials(const q2n_augmented_patch *p, double u, double v, double D[27])
{
    int w = p->w, nb = p->cls->nb, k = p->cls->k;
    q2n_jet dj[MAXW], ej[MAXW], Cu[MAXB * MAXW], Cv[MAXB * MAXW];
    double Bu[4 * MAXB], Bv[4 * MAXB];
    /* eq. (8): the u-direction functions depend on v through the blended row intervals, the
     * v-direction functions on u through the column intervals; jets give two derivatives. */
    for (int i = 0; i < w - 1; i++) {
        dj[i] = q2n_spline_blend(k, p->drow[0][i], p->drow[1][i], v);
        ej[i] = q2n_spline_blend(k, p->ecol[0][i], p->ecol[1][i], u);
    }
    q2n_spline_coeffs(p->cls, dj, Cu);
    q2n_spline_coeffs(p->cls, ej, Cv);
    p->cls->basis(u, 2, Bu);
    p->cls->basis(v, 2, Bv);
    double A[3][3][MAXW], Bf[3][3][MAXW]; /* [du][dv][index] */
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            for (int i = 0; i < w; i++) {
                double sa = 0, sb = 0;
                for (int r = 0; r < nb; r++) {
                    sa += Bu[a * nb + r] * q2n_jet_deriv(Cu[r * w + i], b);
                    sb += Bv[b * nb + r] * q2n_jet_deriv(Cv[r * w + i], a);
                }
                A[a][b][i] = sa;
                Bf[a][b][i] = sb;
            }
    static const double binom[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double r[3] = {0, 0, 0};
            for (int a1 = 0; a1 <= a; a1++)
                for (int b1 = 0; b1 <= b; b1++) {
                    double f = binom[a][a1] * binom[b][b1];
                    for (int j = 0; j < w; j++) {
                        double row[3] = {0, 0, 0};
                        for (int i = 0; i < w; i++) q2n_v3_axpy(row, A[a1][b1][i], p->P + 3 * (j * w + i));
                        q2n_v3_axpy(r, f * Bf[a - a1][b - b1][j], row);
                    }
                }
            memcpy(D + 3 * (a * 3 + b), r, sizeof r);
        }
}

/* ------------------------------------------------------------ vertex fans */

int q2n_ev_vertex_fan(const q2n_mesh *m, int v, int maxn, int *edges, int *other, int *faces)
{
    int h0 = m->vert_he[v];
    if (h0 < 0) return 0;
    if (m->vert_boundary[v]) { /* start at the outgoing boundary half-edge */
        for (int guard = 0; m->he_twin[h0] >= 0 && guard < m->nh; guard++) h0 = q2n_mesh_rotate_back(m, h0);
    }
    int n = 0, h = h0;
    do {
        if (n >= maxn) return -1;
        edges[n] = m->he_edge[h];
        other[n] = q2n_he_dest(m, h);
        faces[n] = m->he_face[h];
        n++;
        int hn = q2n_mesh_rotate(m, h);
        if (hn < 0) { /* boundary: the last edge is the incoming boundary half-edge */
            if (n >= maxn) return -1;
            int hp = q2n_he_prev(m, h);
            edges[n] = m->he_edge[hp];
            other[n] = q2n_he_origin(m, hp);
            faces[n] = -1;
            n++;
            break;
        }
        h = hn;
    } while (h != h0 && n <= m->nh);
    return n;
}

/* Total angle the fan of v spans in the parameter plane: a full turn inside, a half turn on the
 * boundary, a quarter turn at a corner (one face). */
static double fan_span(const q2n_mesh *m, int v, int n)
{
    if (!m->vert_boundary[v]) return 2 * M_PI;
    return n <= 2 ? 0.5 * M_PI : M_PI;
}

/* Preliminary (uniform) angle of edge k of the fan. */
static double uniform_angle(const q2n_mesh *m, int v, int n, int k)
{
    if (!m->vert_boundary[v]) return 2 * M_PI * k / n;
    return n <= 1 ? 0 : fan_span(m, v, n) * k / (n - 1);
}

void q2n_ev_tangent_estimate(const q2n_mesh *m, const double *edge_iv, int v, int k, double T[3])
{
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    int n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces);
    const double *p0 = q2n_mesh_vpos(m, v);
    double fk[3], fbar[3] = {0, 0, 0}, dk, dbar = 0;
    if (n <= 0 || k < 0 || k >= n) { T[0] = T[1] = T[2] = 0; return; }
    q2n_v3_sub(fk, q2n_mesh_vpos(m, other[k]), p0);
    dk = edge_iv[edges[k]];
    double tk = uniform_angle(m, v, n, k);
    for (int j = 0; j < n; j++) { /* eq. (B.2) */
        if (j == k) continue;
        double c = cos(uniform_angle(m, v, n, j) - tk), fj[3];
        q2n_v3_sub(fj, q2n_mesh_vpos(m, other[j]), p0);
        dbar -= c * edge_iv[edges[j]];
        q2n_v3_axpy(fbar, fabs(c), fj);
    }
    if (!(dbar > 1e-3 * dk)) { /* no opposite edge to speak of: the chord slope */
        q2n_v3_scale(T, 1.0 / dk, fk);
        return;
    }
    double al = dbar / (dk + dbar); /* eq. (B.1) */
    for (int c = 0; c < 3; c++) T[c] = al / dk * fk[c] - (1 - al) / dbar * fbar[c];
}

/* ------------------------------------------------------------ jets */

void ev_jet_d1(const ev_vjet *J, const double u[2], double out[3])
{
    for (int c = 0; c < 3; c++) out[c] = J->J1[c][0] * u[0] + J->J1[c][1] * u[1];
}

void ev_jet_d2(const ev_vjet *J, const double a[2], const double b[2], double out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = J->J2[c][0] * a[0] * b[0] + J->J2[c][1] * (a[0] * b[1] + a[1] * b[0]) + J->J2[c][2] * a[1] * b[1];
}

static int vertex_regular(const q2n_mesh *m, int v)
{
    if (m->vert_boundary[v]) return m->vert_nfaces[v] <= 2;
    return m->valence[v] == 4;
}

static void set_dir(const q2n_mesh *m, double (*dir)[2], int e, int v, double x, double y)
{
    int end = q2n_he_origin(m, m->edge_he[e]) == v ? 0 : 1;
    dir[2 * e + end][0] = x;
    dir[2 * e + end][1] = y;
}

/* Jet of v from the corner of the regular patch on face f. */
static int jet_from_regular(const q2n_mesh *m, const q2n_surface *s, const double *iv, int v, int f,
                            ev_vjet *J, double (*dir)[2])
{
    const q2n_augmented_patch *R = q2n_surface_patch_data(s, f);
    if (!R) return 0;
    int c = -1;
    for (int i = 0; i < 4; i++)
        if (m->face_vert[m->face_start[f] + i] == v) c = i;
    if (c < 0) return 0;
    static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    /* in R's (u,v): the face edge leaving corner c runs along axA with sign sA, the other face
     * edge at the corner along axB with sign sB (axis 0: u, 1: v) */
    static const int axA[4] = {0, 1, 0, 1}, sA[4] = {1, 1, -1, -1};
    static const int axB[4] = {1, 0, 1, 0}, sB[4] = {1, -1, -1, 1};
    double D[27];
    q2n_ev_regular_partials(R, cu[c], cv[c], D);
    int ha = q2n_face_he(m, f, c), hb = q2n_he_prev(m, ha);
    double Ia = iv[m->he_edge[ha]], Ib = iv[m->he_edge[hb]];
    /* D index (a*3+b): first derivative along u = (1,0), along v = (0,1) */
    int da = axA[c] == 0 ? 3 : 1, db = axB[c] == 0 ? 3 : 1;
    int daa = axA[c] == 0 ? 6 : 2, dbb = axB[c] == 0 ? 6 : 2;
    for (int k = 0; k < 3; k++) {
        J->J1[k][0] = sA[c] * D[3 * da + k] / Ia;
        J->J1[k][1] = sB[c] * D[3 * db + k] / Ib;
        J->J2[k][0] = D[3 * daa + k] / (Ia * Ia);
        J->J2[k][1] = sA[c] * sB[c] * D[3 * 4 + k] / (Ia * Ib);
        J->J2[k][2] = D[3 * dbb + k] / (Ib * Ib);
    }
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    int n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces), ka = -1;
    for (int k = 0; k < n; k++)
        if (edges[k] == m->he_edge[ha]) ka = k;
    if (ka < 0) return 0;
    static const double ax[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (int k = 0; k < n; k++) {
        int q = ((k - ka) % 4 + 4) % 4;
        set_dir(m, dir, edges[k], v, ax[q][0], ax[q][1]);
    }
    J->source = 1;
    return 1;
}

/* Solve the symmetric positive (definite after the ridge) system N x = r for 3 right-hand
 * sides by Gaussian elimination with partial pivoting; n <= 9. */
static int solve_sys(int n, double N[9][9], double r[9][3])
{
    for (int c = 0; c < n; c++) {
        int piv = c;
        for (int i = c + 1; i < n; i++)
            if (fabs(N[i][c]) > fabs(N[piv][c])) piv = i;
        if (N[piv][c] == 0) return 0;
        if (piv != c) {
            for (int j = 0; j < n; j++) { double t = N[c][j]; N[c][j] = N[piv][j]; N[piv][j] = t; }
            for (int j = 0; j < 3; j++) { double t = r[c][j]; r[c][j] = r[piv][j]; r[piv][j] = t; }
        }
        for (int i = c + 1; i < n; i++) {
            double f = N[i][c] / N[c][c];
            for (int j = c; j < n; j++) N[i][j] -= f * N[c][j];
            for (int j = 0; j < 3; j++) r[i][j] -= f * r[c][j];
        }
    }
    for (int c = n - 1; c >= 0; c--) {
        for (int j = 0; j < 3; j++) {
            double acc = r[c][j];
            for (int i = c + 1; i < n; i++) acc -= N[c][i] * r[i][j];
            r[c][j] = acc / N[c][c];
        }
    }
    return 1;
}

/* Derivative at neighbour p_k of the segment towards v (T_{p_k,p_0}): from its jet when it has
 * one from a regular patch, else from (B.1)–(B.2) at p_k. */
static void neighbour_tangent(const q2n_mesh *m, const double *iv, const ev_vjet *jets,
                              double (*dir)[2], int e, int pk, double T[3])
{
    if (jets[pk].source == 1) {
        int end = q2n_he_origin(m, m->edge_he[e]) == pk ? 0 : 1;
        ev_jet_d1(&jets[pk], dir[2 * e + end], T);
        return;
    }
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    int n = q2n_ev_vertex_fan(m, pk, EV_MAXVAL, edges, other, faces);
    for (int k = 0; k < n; k++)
        if (edges[k] == e) { q2n_ev_tangent_estimate(m, iv, pk, k, T); return; }
    T[0] = T[1] = T[2] = 0;
}

/* Appendix B fit at v. */
static int jet_from_fit(const q2n_mesh *m, const double *iv, int v, ev_vjet *jets, double (*dir)[2])
{
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    int n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces);
    if (n < 2) return 0;
    const double *p0 = q2n_mesh_vpos(m, v);
    int boundary = m->vert_boundary[v];
    double T[EV_MAXVAL][3], eta[EV_MAXVAL];
    for (int k = 0; k < n; k++) q2n_ev_tangent_estimate(m, iv, v, k, T[k]);
    if (vertex_regular(m, v)) {
        for (int k = 0; k < n; k++) eta[k] = 0.5 * M_PI * k;
    } else { /* angles ζ between consecutive tangent estimates, mapped onto the fan's span */
        int gaps = boundary ? n - 1 : n;
        double zeta[EV_MAXVAL], tot = 0;
        for (int k = 0; k < gaps; k++) {
            const double *a = T[k], *b = T[(k + 1) % n];
            double na = q2n_v3_norm(a), nb = q2n_v3_norm(b), c = na > 0 && nb > 0 ? q2n_v3_dot(a, b) / (na * nb) : 0;
            zeta[k] = acos(fmax(-1.0, fmin(1.0, c)));
            if (!(zeta[k] > 1e-3)) zeta[k] = 1e-3;
            tot += zeta[k];
        }
        double span = fan_span(m, v, n);
        eta[0] = 0;
        for (int k = 1; k < n; k++) eta[k] = eta[k - 1] + zeta[k - 1] * span / tot;
    }
    /* the 2n points q_j on the cubic Hermite segments λ (Appendix B) */
    int deg = (!boundary && n >= 5) ? 3 : 2, nc = deg == 3 ? 9 : 5;
    double rho = 0;
    for (int k = 0; k < n; k++) rho = fmax(rho, iv[edges[k]]);
    double N[9][9] = {{0}}, rhs[9][3] = {{0}};
    for (int k = 0; k < n; k++) {
        double d = iv[edges[k]], Tn[3], pk[3];
        memcpy(pk, q2n_mesh_vpos(m, other[k]), sizeof pk);
        neighbour_tangent(m, iv, jets, dir, edges[k], other[k], Tn);
        for (int h = 1; h <= 2; h++) {
            double s = 0.25 * h, s2 = s * s, s3 = s2 * s;
            double h00 = 1 - 3 * s2 + 2 * s3, h10 = s - 2 * s2 + s3, h01 = 3 * s2 - 2 * s3, h11 = s3 - s2;
            double q[3], X = s * d * cos(eta[k]) / rho, Y = s * d * sin(eta[k]) / rho;
            for (int c = 0; c < 3; c++)
                q[c] = h00 * p0[c] + h10 * d * T[k][c] + h01 * pk[c] + h11 * d * (-Tn[c]) - p0[c];
            double mono[9] = {X, Y, X * X, X * Y, Y * Y, X * X * X, X * X * Y, X * Y * Y, Y * Y * Y};
            for (int i = 0; i < nc; i++) {
                for (int j = 0; j < nc; j++) N[i][j] += mono[i] * mono[j];
                for (int c = 0; c < 3; c++) rhs[i][c] += mono[i] * q[c];
            }
        }
    }
    double tr = 0;
    for (int i = 0; i < nc; i++) tr += N[i][i];
    for (int i = 0; i < nc; i++) N[i][i] += 1e-9 * tr / nc;
    if (!solve_sys(nc, N, rhs)) return 0;
    ev_vjet *J = &jets[v];
    for (int c = 0; c < 3; c++) {
        J->J1[c][0] = rhs[0][c] / rho;
        J->J1[c][1] = rhs[1][c] / rho;
        J->J2[c][0] = 2 * rhs[2][c] / (rho * rho);
        J->J2[c][1] = rhs[3][c] / (rho * rho);
        J->J2[c][2] = 2 * rhs[4][c] / (rho * rho);
    }
    for (int k = 0; k < n; k++) {
        double x = cos(eta[k]), y = sin(eta[k]);
        if (vertex_regular(m, v)) { /* exact axis directions */
            static const double ax[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
            x = ax[k % 4][0], y = ax[k % 4][1];
        }
        set_dir(m, dir, edges[k], v, x, y);
    }
    J->source = 2;
    return 1;
}

q2n_status ev_vertex_jets(const q2n_mesh *m, const q2n_surface *s, const double *iv, int kblend,
                          ev_vjet *jets, double (*dir)[2], q2n_error *err)
{
    (void)kblend;
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    char *need = calloc((size_t)m->nv, 1);
    if (!need) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (vertex jets)");
    for (int f = 0; f < m->nf; f++)
        if (q2n_surface_kind(s, f) == Q2N_PATCH_UNCOVERED)
            for (int i = 0; i < 4; i++) need[m->face_vert[m->face_start[f] + i]] = 1;
    /* pass 1: corners of regular patches */
    for (int v = 0; v < m->nv; v++) {
        if (!need[v]) continue;
        int n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces);
        if (n < 0) {
            free(need);
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: vertex %d: valence above %d", m->name, v,
                                 EV_MAXVAL);
        }
        for (int k = 0; k < n; k++)
            if (faces[k] >= 0 && q2n_surface_kind(s, faces[k]) == Q2N_PATCH_AUGMENTED &&
                jet_from_regular(m, s, iv, v, faces[k], &jets[v], dir))
                break;
    }
    /* pass 2: Appendix B */
    for (int v = 0; v < m->nv; v++) {
        if (!need[v] || jets[v].source) continue;
        if (!jet_from_fit(m, iv, v, jets, dir)) {
            free(need);
            return q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: vertex %d: derivative estimate failed (Appendix B)",
                                 m->name, v);
        }
    }
    free(need);
    return Q2N_OK;
}
