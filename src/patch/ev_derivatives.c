/* ev_derivatives.c — derivative data at the vertices of extraordinary regions (seed 003 §4.3
 * and Appendix B), and the full set of mixed partials of a regular augmented patch.
 *
 * Every vertex that is a corner of an extraordinary patch gets one 2-jet in local variables
 * (ev_internal.h):
 *   - if a regular augmented patch has the vertex as a corner, the jet is that patch's corner
 *     derivatives divided by its edge intervals (Lemma 1 / eq. (15) of seed 003: at a corner the
 *     local parametrization functions have vanishing derivatives, so ∂u S = d ∂x S,
 *     ∂uv S = d e ∂xy S, ...), and the four edges get the directions (±1,0), (0,±1);
 *   - in the paper's construction (sections = 1), a valence-4 vertex whose two section polylines
 *     are long enough for the class (§4.3) takes the derivatives of those section curves, and its
 *     twist from the four far face corners; the fair construction gives such a vertex the fan's
 *     own chart like any other (quarter turns forced a fan of corners near 154°, 154°, 90°, 90°
 *     onto right angles and rippled its patches: docs/extraordinary.md, "Charts");
 *   - otherwise it is a least-squares local polynomial in the spirit of Appendix B, eq. (B.3):
 *     the fan is mapped onto the plane with angles η_k proportional to the spatial angles ζ_k
 *     between consecutive edges (as (B.3) does with the angles between its tangent estimates;
 *     summing to 2π inside, π on the boundary from two faces up (a smooth rim, fan_span), the
 *     face's own angle at a corner of one face; η_k = kπ/2 at boundary vertices with at most two
 *     faces, and at valence-4 interior vertices in the paper's construction, so that section curves
 *     through them stay C2), each neighbour at its spatial distance
 *     |p_k - p0| (the r of (B.3); so J1·u_k is close to the edge's speed |p_k - p0|/d_k in its
 *     local variable, whatever the ratio of the edge lengths): the discrete exponential map of the
 *     fan, which keeps the fan's own angles up to one factor.  Angles measured after projecting
 *     the edges onto an estimated tangent plane distort every fan that is far from flat: at a
 *     concave corner of five right angles they put two edges 48° apart in the chart, and the
 *     patches there folded (docs/extraordinary.md, "Charts").  J1 is the linear map that best
 *     sends the planar edge vectors X_k onto the spatial ones (weights 1/|X_k|^2); the normal part
 *     of J2 is the quadratic form fitting the heights of the one-ring neighbours and of the far
 *     corners of the faces (at X_k + X_k+1, moved out to the corner's distance where that falls
 *     nearer: fan_gather) above the tangent plane; the tangential part of J2
 *     only carries each edge's change of speed (accelerations along the edges).
 * Why not (B.1)–(B.2) as printed: on fans with very different edge lengths the Bessel-like
 * estimate (B.1) mixes long edges into the tangent of a short one (a tangent can point backwards
 * along its edge) and the degree-3 fit through 2n points is nearly
 * interpolating and ill-conditioned; both produced folded Coons–Gregory patches.  The
 * construction above keeps the paper's idea (one local polynomial per vertex, sampled along the
 * edge directions, hence G1/G2-compatible data) with a better conditioned fit.
 * docs/extraordinary.md gives the figures. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/poly.h"
#include "core/vec3.h"
#include "patch/ev_internal.h"
#include "patch/ev_policy.h"

#define MAXW Q2N_SPLINE_MAXW
#define MAXB Q2N_SPLINE_MAXB

/* ------------------------------------------------------------ regular patch partials */

void q2n_ev_regular_partials(const q2n_augmented_patch *p, double u, double v, double D[27])
{
    int w = p->w, nb = p->cls->nb;
    q2n_jet Cu[MAXB * MAXW], Cv[MAXB * MAXW];
    double Bu[4 * MAXB], Bv[4 * MAXB];
    /* eq. (8): the u-direction functions depend on v through the blended row intervals, the
     * v-direction functions on u through the column intervals; jets give two derivatives. */
    q2n_augmented_coeffs(p->cls, w, p->drow[0], p->drow[1], v, Cu);
    q2n_augmented_coeffs(p->cls, w, p->ecol[0], p->ecol[1], u, Cv);
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
    const double(*binom)[Q2N_BINOM_MAX + 1] = q2n_binom;
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

/* Total angle the fan of v spans in the parameter plane: a full turn inside (the fan closes), a
 * half turn on the boundary from two faces up — its two boundary edges then leave v in opposite
 * directions, so the rim runs through v smoothly (G1, and G2 with one jet), as it does through a
 * boundary vertex of two regular patches and under Catmull–Clark's boundary rule; 0 where the fan
 * keeps its own total — a corner of the mesh's boundary (one face), charted by its spatial angle
 * (fan_gather).  Until stop 52 a vertex of two faces kept its spatial total too, and the rim turned
 * there by the faces' own angles (up to 140 degrees on open pyramids, 19 on a disc of two rings
 * around a valence-10 vertex: a polygon where the regular construction draws a smooth curve). */
static double fan_span(const q2n_mesh *m, int v, int nfan)
{
    if (!m->vert_boundary[v]) return 2 * Q2N_PI;
    return nfan <= 1 ? 0 : Q2N_PI;
}

/* ------------------------------------------------------------ jets */

void q2n_ev_jet_d1(const ev_vjet *J, const double u[2], double out[3])
{
    for (int c = 0; c < 3; c++) out[c] = J->J1[c][0] * u[0] + J->J1[c][1] * u[1];
}

void q2n_ev_jet_d2(const ev_vjet *J, const double a[2], const double b[2], double out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = J->J2[c][0] * a[0] * b[0] + J->J2[c][1] * (a[0] * b[1] + a[1] * b[0]) + J->J2[c][2] * a[1] * b[1];
}

int q2n_ev_jet_normal(const ev_vjet *J, double n[3])
{
    double a1[3] = {J->J1[0][0], J->J1[1][0], J->J1[2][0]}, a2[3] = {J->J1[0][1], J->J1[1][1], J->J1[2][1]};
    q2n_v3_cross(n, a1, a2);
    double l = q2n_v3_norm(n);
    if (!(l > 0)) return 0;
    q2n_v3_scale(n, 1 / l, n);
    return 1;
}

int q2n_ev_fan_in_plane(const q2n_mesh *m, int v, const double n[3])
{
    const double *p = q2n_mesh_vpos(m, v);
    double hmax = 0, rmax = 0;
    int h0 = m->vert_he[v], h = h0, nfan = 0;
    if (h0 < 0) return 0;
    do {
        const int *fv = m->face_vert + m->face_start[m->he_face[h]];
        for (int c = 0; c < 4; c++) {
            double d[3];
            q2n_v3_sub(d, q2n_mesh_vpos(m, fv[c]), p);
            hmax = fmax(hmax, fabs(q2n_v3_dot(d, n)));
            rmax = fmax(rmax, q2n_v3_norm(d));
        }
        nfan++;
        h = q2n_mesh_rotate(m, h);
    } while (h >= 0 && h != h0);
    return rmax > 0 && hmax <= EV_FLAT_REL * rmax ? nfan : 0;
}

void q2n_ev_jet_dn(const ev_vjet *J, const double a[2], double out[3])
{
    double n[3];
    out[0] = out[1] = out[2] = 0;
    if (!q2n_ev_jet_normal(J, n)) return;
    double I[2][2] = {{0, 0}, {0, 0}}, II[3];
    for (int c = 0; c < 3; c++) {
        I[0][0] += J->J1[c][0] * J->J1[c][0];
        I[0][1] += J->J1[c][0] * J->J1[c][1];
        I[1][1] += J->J1[c][1] * J->J1[c][1];
    }
    I[1][0] = I[0][1];
    for (int q = 0; q < 3; q++) II[q] = n[0] * J->J2[0][q] + n[1] * J->J2[1][q] + n[2] * J->J2[2][q];
    double IIa[2] = {II[0] * a[0] + II[1] * a[1], II[1] * a[0] + II[2] * a[1]};
    double det = I[0][0] * I[1][1] - I[0][1] * I[1][0];
    double s0 = (I[1][1] * IIa[0] - I[0][1] * IIa[1]) / det, s1 = (I[0][0] * IIa[1] - I[1][0] * IIa[0]) / det;
    for (int c = 0; c < 3; c++) out[c] = -(J->J1[c][0] * s0 + J->J1[c][1] * s1);
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
    q2n_augmented_patch Rp, *R = &Rp;
    if (!q2n_augmented_patch_get(s, f, &Rp)) return 0;
    int c = -1;
    for (int i = 0; i < 4; i++)
        if (m->face_vert[m->face_start[f] + i] == v) c = i;
    if (c < 0) return 0;
    /* in R's (u,v): the face edge leaving corner c (side c) runs along u (A_u) or v with sign sA,
     * the other face edge at the corner (side c's inward direction) along the other axis with
     * sign sB (patch/surface.h) */
    int A_u = q2n_side_along_u(c);
    int sA = q2n_side_along[c][0] + q2n_side_along[c][1], sB = q2n_side_inward[c][0] + q2n_side_inward[c][1];
    double D[27];
    q2n_ev_regular_partials(R, q2n_corner_uv[c][0], q2n_corner_uv[c][1], D);
    int ha = q2n_face_he(m, f, c), hb = q2n_he_prev(m, ha);
    double Ia = iv[m->he_edge[ha]], Ib = iv[m->he_edge[hb]];
    /* D index (a*3+b): first derivative along u = (1,0), along v = (0,1) */
    int da = A_u ? 3 : 1, db = A_u ? 1 : 3;
    int daa = A_u ? 6 : 2, dbb = A_u ? 2 : 6;
    for (int k = 0; k < 3; k++) {
        J->J1[k][0] = sA * D[3 * da + k] / Ia;
        J->J1[k][1] = sB * D[3 * db + k] / Ib;
        J->J2[k][0] = D[3 * daa + k] / (Ia * Ia);
        J->J2[k][1] = sA * sB * D[3 * 4 + k] / (Ia * Ib);
        J->J2[k][2] = D[3 * dbb + k] / (Ib * Ib);
        /* ∂A^p ∂B^q R at D index (p*3+q) when A is u, (q*3+p) when A is v */
        int i21 = A_u ? 7 : 5, i12 = A_u ? 5 : 7;
        J->Jm[k][0] = sB * D[3 * i21 + k] / (Ia * Ia * Ib);
        J->Jm[k][1] = sA * D[3 * i12 + k] / (Ia * Ib * Ib);
        J->Jm[k][2] = D[3 * 8 + k] / (Ia * Ia * Ib * Ib);
    }
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    int n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces), ka = -1;
    for (int k = 0; k < n; k++)
        if (edges[k] == m->he_edge[ha]) ka = k;
    if (ka < 0) return 0;
    for (int k = 0; k < n; k++) { /* edge ka along +x, each next one a quarter turn further */
        int q = ((k - ka) % 4 + 4) % 4;
        set_dir(m, dir, edges[k], v, q2n_side_along[q][0], q2n_side_along[q][1]);
    }
    J->source = 1;
    return 1;
}

/* Solve the symmetric positive (definite after the ridge) system N x = r, n <= 9, one right-hand
 * side (LAPACK's LU with partial pivoting, core/dense.h); 0 when N is singular. */
static int solve_sys(int n, const double N[9][9], double r[9])
{
    double A[81];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) A[j * n + i] = N[i][j];
    return q2n_dense_solve(n, 1, A, n, r, n) == 0;
}

/* Least-squares local polynomial at v (Appendix B, adapted; see the file comment). */
/* The fan of a vertex mapped onto the parameter plane (the η, r of (B.3)). */
typedef struct fan {
    int n, nfan;                       /* edges, faces */
    int far;                           /* fit_first fits the far corner too (fair construction, one face) */
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    double f[EV_MAXVAL][3];            /* edge vectors p_k - p0 */
    double X[EV_MAXVAL][2];            /* planar positions of the neighbours, in local variables */
    double q[EV_MAXVAL][3], Xq[EV_MAXVAL][2]; /* far corner of face k (minus p0) and its position */
} fan;

/* Widest chart sector for face fc at its corner v.  The patch corner's area element grows with
 * |a| |b| sin(sector) (a, b the face's two edges at v), so a sector near the straight angle makes
 * that corner degenerate while the rest of the face is not.  The sector may be as wide as keeps
 * the element at the mean of the face's other three corners' (|e × e'| of the quad's edges
 * there): a parallelogram keeps its own angle, whatever it is, and a face that is nearly a
 * triangle at v (the other corners' elements far larger) is held at EV_CHART_MAX_ANGLE as
 * before.  Never narrower than EV_CHART_MAX_ANGLE nor wider than EV_CHART_WIDE_MAX.  Why
 * (docs/extraordinary.md, "Charts"): a thin rhombus between two valence-3 vertices (161 degrees
 * at both) charted at 135 degrees put a crease along its long diagonal. */
static double sector_cap(const q2n_mesh *m, int v, int fc)
{
    int s = m->face_start[fc];
    if (m->face_start[fc + 1] - s != 4) return EV_CHART_MAX_ANGLE;
    double other = 0, mine = 0; /* mine: |a| |b| at v (0: v not a corner) */
    for (int i = 0; i < 4; i++) {
        const double *p = q2n_mesh_vpos(m, m->face_vert[s + i]);
        double a[3], b[3], x[3];
        q2n_v3_sub(a, q2n_mesh_vpos(m, m->face_vert[s + (i + 1) % 4]), p);
        q2n_v3_sub(b, q2n_mesh_vpos(m, m->face_vert[s + (i + 3) % 4]), p);
        q2n_v3_cross(x, a, b);
        if (m->face_vert[s + i] == v) mine = q2n_v3_norm(a) * q2n_v3_norm(b);
        else other += q2n_v3_norm(x) / 3;
    }
    double sn = other / mine;
    if (!(sn < sin(EV_CHART_MAX_ANGLE))) return EV_CHART_MAX_ANGLE; /* near-triangle, degenerate or v absent */
    return fmin(Q2N_PI - asin(sn), EV_CHART_WIDE_MAX);
}

/* Angles between consecutive edges (spatial), each oriented by the normal of its own face (the
 * face's vector area): a corner that turns against its face is reflex (its sector is 2π minus the
 * angle), or, when that angle is acute, the face overlaps itself at v and the fan counts as folded.
 * Sectors narrower than EV_CHART_MIN_ANGLE count as that wide.  Mapped onto the fan's span, sectors
 * capped by sector_cap (`wide`: the fair construction) or at EV_CHART_MAX_ANGLE (the paper's) —
 * else the two faces at an edge would not lie on its two sides, and a nearly straight corner would
 * leave its patch corner nearly degenerate; folded fans get uniform angles.  Why each face's
 * normal and not the fan's (the mean of its sectors' normals, until stop 35): on a strongly curved
 * fan the two differ by up to a right angle, and a nearly straight corner — two edges of a split
 * sliver triangle — then flips its sign with the fan's normal; such fans were called folded and
 * charted uniformly, a 3-degree needle corner drawn as a 60-degree one (docs/extraordinary.md,
 * "Charts"). */
static void fan_angles(const q2n_mesh *m, int v, const fan *F, int wide, int cross, double *eta)
{
    double zeta[EV_MAXVAL], tot = 0, span = fan_span(m, v, F->nfan);
    int folded = 0;
    for (int k = 0; k < F->nfan; k++) {
        double c[3], fa[3];
        const double *a = F->f[k], *b = F->f[(k + 1) % F->n];
        q2n_v3_cross(c, a, b);
        zeta[k] = atan2(q2n_v3_norm(c), q2n_v3_dot(a, b));
        q2n_mesh_face_area(m, F->faces[k], fa);
        if (q2n_v3_dot(c, fa) < 0) {
            folded |= zeta[k] < 0.5 * Q2N_PI;
            zeta[k] = 2 * Q2N_PI - zeta[k];
        }
        zeta[k] = fmax(zeta[k], EV_CHART_MIN_ANGLE);
        tot += zeta[k];
    }
    if (span == 0) span = folded ? 0.5 * Q2N_PI * F->nfan : tot; /* folded: quarter turns */
    for (int k = 0; k < F->nfan; k++) zeta[k] = folded ? span / F->nfan : zeta[k] * span / tot;
    double cap[EV_MAXVAL];
    for (int k = 0; k < F->nfan; k++) cap[k] = wide ? sector_cap(m, v, F->faces[k]) : EV_CHART_MAX_ANGLE;
    /* The excess of the sectors over their caps goes to the sectors below theirs, in proportion,
     * and only to those: a sector already at its cap neither gives nor takes, so the sectors keep
     * their sum (until stop 49 such a sector counted in the share, its part of the excess was
     * lost, and the last sector of a closed fan, eta's implicit 2π - eta[n-1], took it up: a
     * parallelogram's 161.5 degrees became 178, its patch corner nearly degenerate).  Each pass
     * caps at least one more sector for good, so nfan passes settle any fan whose caps can take
     * the span; where they cannot, the last sector keeps the rest. */
    for (int it = 0; it < F->nfan; it++) {
        double over = 0, rest = 0;
        for (int k = 0; k < F->nfan; k++) {
            if (zeta[k] > cap[k]) over += zeta[k] - cap[k], zeta[k] = cap[k];
            else if (zeta[k] < cap[k]) rest += zeta[k];
        }
        if (over <= 0 || rest <= 0) break;
        for (int k = 0; k < F->nfan; k++)
            if (zeta[k] < cap[k]) zeta[k] += over * zeta[k] / rest;
    }
    if (cross && F->nfan == 4 && F->n == 4) { /* opposite sectors equal: opposite edges opposite */
        double a = 0.5 * (zeta[0] + zeta[2]), b = 0.5 * (zeta[1] + zeta[3]);
        zeta[0] = zeta[2] = a;
        zeta[1] = zeta[3] = b;
    }
    eta[0] = 0;
    for (int k = 1; k < F->n; k++) eta[k] = eta[k - 1] + zeta[k - 1];
}

/* Gather the fan of v and map it onto the plane: angles from fan_angles, or, in the paper's
 * construction (`quarter`), kπ/2 at boundary vertices with at most two faces and at valence-4
 * interior vertices — opposite edges then sharing their length so that section lines through v
 * stay C2 — each neighbour at its distance from v.  0 when the fan has no normal (area-weighted;
 * a fan of one face takes that face's, which a straight corner has too).  Why the fair
 * construction charts boundary vertices of one or two faces by their own angles (stop 39; a vertex of
 * two faces scaled to a half turn since stop 52, fan_span): quarter turns drew a one-face corner of
 * 172 degrees as a right angle, and a hexagonal pyramid whose rim has such corners rippled
 * (docs/extraordinary.md, "Charts"). */
static int fan_gather(const q2n_mesh *m, const double *iv, int v, int quarter, int cross, fan *F)
{
    F->n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, F->edges, F->other, F->faces);
    if (F->n < 2) return 0;
    F->nfan = m->vert_boundary[v] ? F->n - 1 : F->n;
    const double *p0 = q2n_mesh_vpos(m, v);
    double nrm[3] = {0, 0, 0}, len[EV_MAXVAL], eta[EV_MAXVAL];
    for (int k = 0; k < F->n; k++) q2n_v3_sub(F->f[k], q2n_mesh_vpos(m, F->other[k]), p0);
    for (int k = 0; k < F->nfan; k++) {
        double c[3];
        q2n_v3_cross(c, F->f[k], F->f[(k + 1) % F->n]);
        q2n_v3_add(nrm, nrm, c);
    }
    F->far = !quarter && F->nfan == 1;
    if (F->far) q2n_mesh_face_area(m, F->faces[0], nrm);
    if (!(q2n_v3_norm(nrm) > 0)) return 0; /* no tangent plane: every sector degenerate */
    for (int k = 0; k < F->n; k++) len[k] = q2n_v3_norm(F->f[k]);
    int regular = quarter && (m->vert_boundary[v] ? m->vert_nfaces[v] <= 2 : m->valence[v] == 4);
    if (regular) {
        for (int k = 0; k + 2 < F->n; k++) { /* equal speeds (len/d) on the two sides */
            double sp = 0.5 * (len[k] / iv[F->edges[k]] + len[k + 2] / iv[F->edges[k + 2]]);
            len[k] = sp * iv[F->edges[k]];
            len[k + 2] = sp * iv[F->edges[k + 2]];
        }
    } else {
        fan_angles(m, v, F, !quarter, cross, eta);
    }
    for (int k = 0; k < F->n; k++) { /* regular: k quarter turns (patch/surface.h) */
        F->X[k][0] = len[k] * (regular ? q2n_side_along[k % 4][0] : cos(eta[k]));
        F->X[k][1] = len[k] * (regular ? q2n_side_along[k % 4][1] : sin(eta[k]));
    }
    for (int k = 0; k < F->nfan; k++) {
        int fc = F->faces[k], c = 0;
        for (int i = 0; i < 4; i++)
            if (m->face_vert[m->face_start[fc] + i] == v) c = i;
        q2n_v3_sub(F->q[k], q2n_mesh_vpos(m, m->face_vert[m->face_start[fc] + (c + 2) % 4]), p0);
        /* The parallelogram's fourth corner, moved out to the far corner's distance where it falls
         * nearer (the chart keeps every point's distance to v, as for the neighbours): a face with a
         * wide angle at v (a kite, a quad that is nearly a triangle) has X_k + X_k+1 near zero while
         * its far corner is far, and placed there its height would read as a curvature
         * (d / |X_k + X_k+1|)^2 too large with (d / |X_k + X_k+1|)^4 of the weight
         * (fit_normal_second); a position farther than the corner only lowers its weight and is
         * kept (a long thin face's far corner lies beside v, not beyond its long edge). */
        double *Xq = F->Xq[k], d = q2n_v3_norm(F->q[k]);
        Xq[0] = F->X[k][0] + F->X[(k + 1) % F->n][0];
        Xq[1] = F->X[k][1] + F->X[(k + 1) % F->n][1];
        double dc = hypot(Xq[0], Xq[1]);
        if (dc > 0 && d > dc) Xq[0] *= d / dc, Xq[1] *= d / dc;
    }
    return 1;
}

/* The fan of v on m, charted on cm (m under a linear map: the isotropic frame) where not NULL: the
 * angles and distances of cm's fan place the neighbours and far corners (X, Xq), while the edge
 * vectors the jet is fitted to (f, q) stay m's. */
static int fan_chart(const q2n_mesh *m, const q2n_mesh *cm, const double *iv, int v, int quarter, int cross, fan *F)
{
    if (!cm) return fan_gather(m, iv, v, quarter, cross, F);
    fan C;
    if (!fan_gather(cm, iv, v, quarter, cross, &C) || !fan_gather(m, iv, v, quarter, cross, F)) return 0;
    memcpy(F->X, C.X, sizeof C.X);
    memcpy(F->Xq, C.Xq, sizeof C.Xq);
    return 1;
}

/* J1: the linear map X_k -> f_k in the least-squares sense, weights 1/|X_k|^2 (relative errors,
 * so short and long edges count alike).  In the fair construction a fan of one face (a corner of
 * the mesh's boundary) fits its far corner too, like a third neighbour: its two edges alone would
 * fix J1 by interpolation, and not at all where they are collinear — a straight corner, whose
 * cross direction only the far corner gives (such a vertex was refused as "a degenerate fan" until
 * stop 39). */
static int fit_first(const fan *F, ev_vjet *J)
{
    double A[2][2] = {{0, 0}, {0, 0}}, r[2][3] = {{0}};
    for (int k = 0; k < F->n + F->far; k++) {
        const double *X = k < F->n ? F->X[k] : F->Xq[0], *f = k < F->n ? F->f[k] : F->q[0];
        double w = 1 / (X[0] * X[0] + X[1] * X[1]);
        for (int i = 0; i < 2; i++) {
            for (int j = 0; j < 2; j++) A[i][j] += w * X[i] * X[j];
            for (int c = 0; c < 3; c++) r[i][c] += w * X[i] * f[c];
        }
    }
    double det = A[0][0] * A[1][1] - A[0][1] * A[1][0], tr = A[0][0] + A[1][1];
    if (!(fabs(det) > 1e-14 * tr * tr)) return 0;
    for (int c = 0; c < 3; c++) {
        J->J1[c][0] = (A[1][1] * r[0][c] - A[0][1] * r[1][c]) / det;
        J->J1[c][1] = (A[0][0] * r[1][c] - A[1][0] * r[0][c]) / det;
    }
    return 1;
}

/* Normal part of J2: the quadratic form fitting the heights above the tangent plane of the
 * neighbours (at X_k) and of the far face corners (at Xq_k, fan_gather), weights 1/|X|^4.  Only the
 * normal part carries shape; G2 compatibility concerns it alone. */
static int fit_normal_second(const fan *F, const double nj[3], ev_vjet *J)
{
    double N[9][9] = {{0}}, R[9] = {0};
    for (int k = 0; k < F->n + F->nfan; k++) {
        const double *X = k < F->n ? F->X[k] : F->Xq[k - F->n], *q = k < F->n ? F->f[k] : F->q[k - F->n];
        double x = X[0], y = X[1], r2 = x * x + y * y, w = 1 / (r2 * r2), h = q2n_v3_dot(q, nj);
        double mono[3] = {0.5 * x * x, x * y, 0.5 * y * y};
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) N[i][j] += w * mono[i] * mono[j];
            R[i] += w * mono[i] * h;
        }
    }
    double tr = N[0][0] + N[1][1] + N[2][2];
    for (int i = 0; i < 3; i++) N[i][i] += EV_JET_NORMAL_RIDGE * tr;
    if (!solve_sys(3, N, R)) return 0;
    for (int q = 0; q < 3; q++)
        for (int c = 0; c < 3; c++) J->J2[c][q] = R[q] * nj[c];
    return 1;
}

/* Tangential part of J2: only the acceleration along each edge is meaningful (the change of
 * speed from the vertex to its neighbour, which keeps the Hermite segments evenly
 * parametrized).  Written as J1·C m(X) with C a 2x3 matrix and m = (x²/2, xy, y²/2), fitted to
 * t_k·J1·C m(X_k) = t_k·(f_k - J1 X_k), t_k the unit tangent of edge k, weights 1/|X_k|^4, with a
 * ridge (minimum norm: fans do not determine all six numbers). */
static void fit_tangential_second(const fan *F, ev_vjet *J)
{
    double M[9][9] = {{0}}, R[9] = {0};
    for (int k = 0; k < F->n; k++) {
        double x = F->X[k][0], y = F->X[k][1], t[3], r[3], g[2];
        q2n_ev_jet_d1(J, F->X[k], t);
        q2n_v3_sub(r, F->f[k], t);
        double tl = q2n_v3_norm(t);
        if (!(tl > 0)) continue;
        q2n_v3_scale(t, 1 / tl, t);
        for (int i = 0; i < 2; i++) g[i] = t[0] * J->J1[0][i] + t[1] * J->J1[1][i] + t[2] * J->J1[2][i];
        double mk[3] = {0.5 * x * x, x * y, 0.5 * y * y}, row[6], a = q2n_v3_dot(t, r);
        for (int i = 0; i < 2; i++)
            for (int q = 0; q < 3; q++) row[3 * i + q] = g[i] * mk[q];
        double r2 = x * x + y * y, w = 1 / (r2 * r2);
        for (int i = 0; i < 6; i++) {
            for (int j = 0; j < 6; j++) M[i][j] += w * row[i] * row[j];
            R[i] += w * row[i] * a;
        }
    }
    double tr = 0;
    for (int i = 0; i < 6; i++) tr += M[i][i];
    if (!(tr > 0)) return;
    for (int i = 0; i < 6; i++) M[i][i] += EV_JET_ACCEL_RIDGE * tr / 6;
    if (!solve_sys(6, M, R)) return;
    for (int q = 0; q < 3; q++)
        for (int c = 0; c < 3; c++) J->J2[c][q] += J->J1[c][0] * R[q] + J->J1[c][1] * R[3 + q];
}

/* Least-squares local polynomial at v (Appendix B, adapted; see the file comment); quarter: as
 * fan_gather. */
static int jet_from_fit(const q2n_mesh *m, const q2n_mesh *cm, const double *iv, int v, ev_vjet *J, double (*dir)[2], int quarter,
                        int cross)
{
    fan F;
    double nj[3];
    if (!fan_chart(m, cm, iv, v, quarter, cross, &F) || !fit_first(&F, J) || !q2n_ev_jet_normal(J, nj) || !fit_normal_second(&F, nj, J))
        return 0;
    fit_tangential_second(&F, J);
    for (int k = 0; k < F.n; k++) {
        /* The least-squares J1 cannot match every edge of a fan whose edge lengths differ
         * widely: a short edge may get an end speed |J1·X_k| of several times its chord, and the
         * quintic edge curve then nearly stops before its other end.  Scaling the edge's
         * direction u_k by s is a change of the edge's local variable: every datum read from the
         * jet along that edge (J1·u, J2[u,u], the neighbours' cross fields J1·u, the twists
         * J2[u,w]) scales consistently, so the data stay the derivatives of one surface.  s keeps
         * the end speed at most EV_SPEED_MAX times the chord (ev_policy.h). */
        double g[3], sp, ch = q2n_v3_norm(F.f[k]), sc = 1;
        q2n_ev_jet_d1(J, F.X[k], g);
        sp = q2n_v3_norm(g);
        if (sp > EV_SPEED_MAX * ch) sc = EV_SPEED_MAX * ch / sp;
        set_dir(m, dir, F.edges[k], v, sc * F.X[k][0] / iv[F.edges[k]], sc * F.X[k][1] / iv[F.edges[k]]);
    }
    J->source = 2;
    return 1;
}

/* Derivatives (1st, 2nd, in the local variable) at v of the section curve of class cls through v
 * that leaves v along the half-edge h0 (v -> ...) and arrives along the opposite edge h_back
 * (v -> ... backwards); 0 when the section polyline does not reach far enough (§4.3). */
static int section_derivs(const q2n_mesh *m, const double *iv, const q2n_spline_class *cls, int v, int h0,
                          int hb, double d1[3], double d2[3])
{
    int w = cls->w, half = w / 2, nf = 0, nb = 0;
    double pts[3 * (2 * Q2N_SPLINE_MAXW + 1)], ivs[2 * Q2N_SPLINE_MAXW];
    int fwd[Q2N_SPLINE_MAXW], bwd[Q2N_SPLINE_MAXW];
    for (int h = h0; h >= 0 && nf < half; h = q2n_mesh_continue(m, h)) fwd[nf++] = h;
    for (int h = hb; h >= 0 && nb < half; h = q2n_mesh_continue(m, h)) bwd[nb++] = h;
    /* window for the interval after v (v at x = 0) or before it (v at its end) */
    int after = nb >= half - 1 && nf >= half, before = nb >= half && nf >= half - 1;
    if (!after && !before) return 0;
    int useb = after ? half - 1 : half, usef = after ? half : half - 1, n = useb + 1 + usef;
    for (int i = 0; i < useb; i++) { /* p_{-useb} .. p_{-1} */
        int h = bwd[useb - 1 - i];
        memcpy(pts + 3 * i, q2n_mesh_vpos(m, q2n_he_dest(m, h)), 3 * sizeof(double));
        ivs[i] = iv[m->he_edge[h]];
    }
    memcpy(pts + 3 * useb, q2n_mesh_vpos(m, v), 3 * sizeof(double));
    for (int i = 0; i < usef; i++) {
        memcpy(pts + 3 * (useb + 1 + i), q2n_mesh_vpos(m, q2n_he_dest(m, fwd[i])), 3 * sizeof(double));
        ivs[useb + i] = iv[m->he_edge[fwd[i]]];
    }
    double out[9];
    int sidx = after ? useb : useb - 1;
    double x = after ? 0 : ivs[useb - 1];
    if (q2n_spline_curve_eval(cls, n, 3, pts, ivs, 0, sidx, x, 2, out)) return 0;
    memcpy(d1, out + 3, 3 * sizeof(double));
    memcpy(d2, out + 6, 3 * sizeof(double));
    return 1;
}

/* Valence-4 interior vertex without a regular patch but with both section polylines long enough:
 * J1, J2xx, J2yy from the class's section curves (§4.3: "section curves of the class where the
 * section polyline allows it"), J2xy from the four far face corners. */
static int jet_from_sections(const q2n_mesh *m, const double *iv, const q2n_spline_class *cls, int v,
                             ev_vjet *J, double (*dir)[2])
{
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    if (m->vert_boundary[v] || m->valence[v] != 4) return 0;
    if (q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces) != 4) return 0;
    int hout[4];
    for (int k = 0; k < 4; k++) {
        int h = m->edge_he[edges[k]];
        hout[k] = q2n_he_origin(m, h) == v ? h : m->he_twin[h];
        if (hout[k] < 0) return 0;
    }
    double d1[2][3], d2[2][3];
    for (int l = 0; l < 2; l++)
        if (!section_derivs(m, iv, cls, v, hout[l], hout[l + 2], d1[l], d2[l])) return 0;
    const int(*ax)[2] = q2n_side_along; /* edge k: k quarter turns from +x (patch/surface.h) */
    for (int c = 0; c < 3; c++) {
        J->J1[c][0] = d1[0][c];
        J->J1[c][1] = d1[1][c];
        J->J2[c][0] = d2[0][c];
        J->J2[c][2] = d2[1][c];
    }
    /* twist: least squares over the far corners q of the faces, at X = d_k u_k + d_k+1 u_k+1:
     * q - p - J1 X - (J2xx x² + J2yy y²)/2 ≈ J2xy x y */
    double num[3] = {0, 0, 0}, den = 0;
    const double *p0 = q2n_mesh_vpos(m, v);
    for (int k = 0; k < 4; k++) {
        int fc = faces[k], c = 0;
        for (int i = 0; i < 4; i++)
            if (m->face_vert[m->face_start[fc] + i] == v) c = i;
        const double *q = q2n_mesh_vpos(m, m->face_vert[m->face_start[fc] + (c + 2) % 4]);
        double x = iv[edges[k]] * ax[k][0] + iv[edges[(k + 1) % 4]] * ax[(k + 1) % 4][0];
        double y = iv[edges[k]] * ax[k][1] + iv[edges[(k + 1) % 4]] * ax[(k + 1) % 4][1];
        for (int c2 = 0; c2 < 3; c2++) {
            double r = q[c2] - p0[c2] - J->J1[c2][0] * x - J->J1[c2][1] * y - 0.5 * (J->J2[c2][0] * x * x + J->J2[c2][2] * y * y);
            num[c2] += r * x * y;
        }
        den += x * x * y * y;
    }
    for (int c = 0; c < 3; c++) J->J2[c][1] = num[c] / den;
    for (int k = 0; k < 4; k++) set_dir(m, dir, edges[k], v, ax[k][0], ax[k][1]);
    J->source = 3;
    return 1;
}

q2n_status q2n_ev_vertex_jets(const q2n_mesh *m, const q2n_mesh *chart_mesh, const q2n_surface *s, const double *iv,
                              const q2n_spline_class *cls, int sections, const char *cross, ev_vjet *jets,
                              double (*dir)[2], q2n_error *err)
{
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
    /* pass 2: section curves of the class through valence-4 vertices (the paper's construction),
     * else Appendix B */
    for (int v = 0; v < m->nv; v++) {
        if (!need[v] || jets[v].source) continue;
        if (!(sections && jet_from_sections(m, iv, cls, v, &jets[v], dir)) && !jet_from_fit(m, chart_mesh, iv, v, &jets[v], dir, sections, cross && cross[v])) {
            free(need);
            char where[300], of[48];
            q2n_mesh_vertex_where(m, v, where, sizeof where);
            q2n_mesh_of(m, 0, of, sizeof of);
            int n = q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces);
            if (sections && m->vert_boundary[v] && n == 2) { /* a corner of one face */
                double ang = q2n_v3_corner_deg(q2n_mesh_vpos(m, v), q2n_mesh_vpos(m, other[0]), q2n_mesh_vpos(m, other[1]));
                return q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: vertex %d (of this face%s) is a boundary corner of one "
                                     "face with an angle of %.1f degrees: the paper's construction charts it as a right "
                                     "angle and no local surface fits it (the default, --ev-construction fair, charts "
                                     "it by its own angle)", where, v, of, ang);
            }
            return q2n_error_set(err, Q2N_ERR_GEOMETRY, "%s: vertex %d (of this face%s): no local surface fits its "
                                 "neighbours (Appendix B): a degenerate fan?", where, v, of);
        }
    }
    free(need);
    return Q2N_OK;
}
