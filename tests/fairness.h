/* fairness.h — fairness figures of a constructed surface, the definitions of
 * ../shared/tools/fairness.py (which reads fitted STEP files) applied to q2n_surface_eval:
 *   E        bending energy ∫ (κ1² + κ2²) dA = ∫ (4H² − 2K) dA, Gauss–Legendre 12 x 12 per face;
 *   jac      min |Xu × Xv| / median |Xu × Xv| over a face's Gauss nodes (worst face): a fold or
 *            a degenerate parametrisation drives it to 0;
 *   osc      curvature oscillation along each diagonal of each face, (TV(H) − |H_end − H_start|)·L/2
 *            with H sampled at 129 points and L the diagonal's 3-D length: 0 when H is monotone;
 * split into faces touching an extraordinary vertex (interior valence != 4, boundary valence not
 * in {2, 3}) and the others. */
#ifndef Q2N_TEST_FAIRNESS_H
#define Q2N_TEST_FAIRNESS_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "mesh/mesh.h"
#include "patch/fairness.h"
#include "patch/surface.h"

typedef struct fair_figures {
    double E_ev, E_reg;
    double osc_ev_mean, osc_ev_max, osc_reg_mean;
    int ev_lines, reg_lines, ev_faces;
    double jac_min; /* over all faces */
    int jac_face;
    double jac_rel;  /* min over faces of jac / min(0.1, 0.75 x the bilinear quad's jac): >= 1 when no
                        face is more degenerate than both 0.1 and (within 25 %) its own mesh quad */
    int jac_rel_face;
    int failed;     /* evaluation errors */
    double maxH;    /* largest |H| along the face diagonals, their ends (the face corners) included */
    int maxH_face;
} fair_figures;

static inline int fair_is_ev(const q2n_mesh *m, int v)
{
    return m->vert_boundary[v] ? (m->valence[v] != 2 && m->valence[v] != 3) : m->valence[v] != 4;
}

/* H, K and |Xu x Xv| from an evaluation with second derivatives (q2n_surface_eval layout). */
static inline void fair_curv(const double *o, double *H, double *K, double *W)
{
    const double *Xu = o + 3, *Xv = o + 6, *Xuu = o + 9, *Xuv = o + 12, *Xvv = o + 15;
    double N[3] = {Xu[1] * Xv[2] - Xu[2] * Xv[1], Xu[2] * Xv[0] - Xu[0] * Xv[2], Xu[0] * Xv[1] - Xu[1] * Xv[0]};
    double w = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]), n[3];
    for (int c = 0; c < 3; c++) n[c] = N[c] / fmax(w, 1e-300);
    double E = 0, F = 0, G = 0, L = 0, M = 0, Nn = 0;
    for (int c = 0; c < 3; c++) {
        E += Xu[c] * Xu[c]; F += Xu[c] * Xv[c]; G += Xv[c] * Xv[c];
        L += Xuu[c] * n[c]; M += Xuv[c] * n[c]; Nn += Xvv[c] * n[c];
    }
    double den = fmax(E * G - F * F, 1e-300);
    *H = (E * Nn - 2 * F * M + G * L) / (2 * den);
    *K = (L * Nn - M * M) / den;
    *W = w;
}

static inline int fair_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The same min/median Jacobian ratio for the bilinear quad through the face's four vertices: how
 * degenerate the mesh face itself is (a near-triangle quad has a small one whatever the surface). */
static const double fair_gx[12] = {0.009219682876640378, 0.04794137181476255, 0.11504866290284765, 0.20634102285669127,
                                   0.31608425050090994, 0.43738329574426554, 0.5626167042557344, 0.6839157494990901,
                                   0.7936589771433087, 0.8849513370971523, 0.9520586281852375, 0.9907803171233596};

static inline double fair_bilinear_jac(const q2n_mesh *m, int f)
{
    const double *P[4];
    for (int i = 0; i < 4; i++) P[i] = q2n_mesh_vpos(m, m->face_vert[m->face_start[f] + i]);
    double J[144];
    for (int a = 0; a < 12; a++)
        for (int b = 0; b < 12; b++) {
            double u = fair_gx[a], v = fair_gx[b], Pu[3], Pv[3];
            for (int c = 0; c < 3; c++) {
                Pu[c] = (1 - v) * (P[1][c] - P[0][c]) + v * (P[2][c] - P[3][c]);
                Pv[c] = (1 - u) * (P[3][c] - P[0][c]) + u * (P[2][c] - P[1][c]);
            }
            double N[3] = {Pu[1] * Pv[2] - Pu[2] * Pv[1], Pu[2] * Pv[0] - Pu[0] * Pv[2], Pu[0] * Pv[1] - Pu[1] * Pv[0]};
            J[a * 12 + b] = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
        }
    qsort(J, 144, sizeof *J, fair_cmp);
    return J[0] / fmax(0.5 * (J[71] + J[72]), 1e-300);
}

static inline void fair_measure_range(const q2n_mesh *m, const q2n_surface *s, int f0, int f1, fair_figures *out);
static inline void fair_measure(const q2n_mesh *m, const q2n_surface *s, fair_figures *out) { fair_measure_range(m, s, 0, m->nf, out); }

/* The same over faces f0 <= f < f1 only. */
static inline void fair_measure_range(const q2n_mesh *m, const q2n_surface *s, int f0, int f1, fair_figures *out)
{
    static const double gx[12] = {0.009219682876640378, 0.04794137181476255, 0.11504866290284765, 0.20634102285669127,
                                  0.31608425050090994, 0.43738329574426554, 0.5626167042557344, 0.6839157494990901,
                                  0.7936589771433087, 0.8849513370971523, 0.9520586281852375, 0.9907803171233596};
    static const double gw[12] = {0.02358766819325591, 0.053469662997659216, 0.08003916427167311, 0.10158371336153296,
                                  0.11674626826917739, 0.12457352290670139, 0.12457352290670139, 0.11674626826917739,
                                  0.10158371336153296, 0.08003916427167311, 0.053469662997659216, 0.02358766819325591};
    memset(out, 0, sizeof *out);
    out->jac_min = out->jac_rel = INFINITY;
    out->jac_face = out->jac_rel_face = -1;
    for (int f = f0; f < f1; f++) {
        int ev = 0;
        for (int i = 0; i < 4; i++) ev |= fair_is_ev(m, m->face_vert[m->face_start[f] + i]);
        out->ev_faces += ev;
        double E = 0, Wn[144];
        for (int a = 0; a < 12; a++)
            for (int b = 0; b < 12; b++) {
                double o[18], H, K, W;
                if (q2n_surface_eval(s, f, gx[a], gx[b], 2, o)) { out->failed++; continue; }
                fair_curv(o, &H, &K, &W);
                Wn[a * 12 + b] = W;
                E += (4 * H * H - 2 * K) * W * gw[a] * gw[b];
            }
        if (ev) out->E_ev += E;
        else out->E_reg += E;
        double med[144];
        memcpy(med, Wn, sizeof med);
        qsort(med, 144, sizeof *med, fair_cmp);
        double mn = med[0], jr = mn / fmax(0.5 * (med[71] + med[72]), 1e-300);
        if (jr < out->jac_min) { out->jac_min = jr; out->jac_face = f; }
        double rel = jr / fmin(0.1, 0.75 * fair_bilinear_jac(m, f));
        if (rel < out->jac_rel) { out->jac_rel = rel; out->jac_rel_face = f; }
        for (int d = 0; d < 2; d++) { /* (0,0)->(1,1) and (0,1)->(1,0) */
            double tv = 0, Hp = 0, H0 = 0, L = 0, Xp[3] = {0, 0, 0};
            for (int k = 0; k <= 128; k++) {
                double t = k / 128.0, o[18], H, K, W;
                if (q2n_surface_eval(s, f, t, d ? 1 - t : t, 2, o)) { out->failed++; break; }
                fair_curv(o, &H, &K, &W);
                if (fabs(H) > out->maxH) out->maxH = fabs(H), out->maxH_face = f;
                if (k == 0) H0 = H;
                else {
                    tv += fabs(H - Hp);
                    L += sqrt((o[0] - Xp[0]) * (o[0] - Xp[0]) + (o[1] - Xp[1]) * (o[1] - Xp[1]) + (o[2] - Xp[2]) * (o[2] - Xp[2]));
                }
                Hp = H;
                memcpy(Xp, o, sizeof Xp);
            }
            double osc = (tv - fabs(Hp - H0)) * L / 2;
            if (ev) {
                out->osc_ev_mean += osc;
                out->osc_ev_max = fmax(out->osc_ev_max, osc);
                out->ev_lines++;
            } else {
                out->osc_reg_mean += osc;
                out->reg_lines++;
            }
        }
    }
    if (out->ev_lines) out->osc_ev_mean /= out->ev_lines;
    if (out->reg_lines) out->osc_reg_mean /= out->reg_lines;
}

/* Across every interior edge of s on m, at the nx parameters xs along it (from the first face's
 * side start): the largest angle between the two sides' normals (rad, *g1) and the largest jump of
 * the mean curvature relative to 1 + |H| (*g2). */
static inline void fair_edge_jumps(const q2n_mesh *m, const q2n_surface *s, const double *xs, int nx, double *g1, double *g2)
{
    *g1 = *g2 = 0;
    for (int h = 0; h < m->nh; h++) {
        int t = m->he_twin[h];
        if (t < h) continue; /* boundary (-1) or seen from the other side */
        int f = m->he_face[h], g = m->he_face[t], i = h - m->face_start[f], j = t - m->face_start[g];
        for (int q = 0; q < nx; q++) {
            double uv[2][2], e[2][18], n[2][3], H[2], K;
            q2n_side_uv(i, xs[q], 0, &uv[0][0], &uv[0][1]);
            q2n_side_uv(j, 1 - xs[q], 0, &uv[1][0], &uv[1][1]);
            for (int sd = 0; sd < 2; sd++) {
                q2n_surface_eval(s, sd ? g : f, uv[sd][0], uv[sd][1], 2, e[sd]);
                q2n_v3_cross(n[sd], e[sd] + Q2N_EV_U, e[sd] + Q2N_EV_V);
                q2n_curvatures(e[sd], &H[sd], &K);
            }
            *g1 = fmax(*g1, q2n_v3_angle(n[0], n[1]));
            *g2 = fmax(*g2, fabs(H[0] - H[1]) / (1 + fabs(H[0])));
        }
    }
}

#endif
