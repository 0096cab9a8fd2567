/* fairness.c — curvature oscillation along the faces' diagonals and bending energy (fairness.h). */
#include "patch/fairness.h"

#include "core/par.h"
#include "core/poly.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>

double q2n_curvatures(const double *e, double *H, double *K)
{
    const double *Su = e + Q2N_EV_U, *Sv = e + Q2N_EV_V;
    double N[3];
    q2n_v3_cross(N, Su, Sv);
    double w = q2n_v3_norm(N);
    *H = *K = NAN;
    if (!(w > 0)) return 0;
    double E = q2n_v3_dot(Su, Su), F = q2n_v3_dot(Su, Sv), G = q2n_v3_dot(Sv, Sv);
    double L = q2n_v3_dot(e + Q2N_EV_UU, N) / w, M = q2n_v3_dot(e + Q2N_EV_UV, N) / w, Nn = q2n_v3_dot(e + Q2N_EV_VV, N) / w;
    *H = (E * Nn - 2 * F * M + G * L) / (2 * w * w); /* w^2 = EG - F^2 */
    *K = (L * Nn - M * M) / (w * w);
    return w;
}

typedef struct job {
    const q2n_surface *s;
    int n, q;
    double x[32], w[32];
    double (*out)[2]; /* per patch: ripple, energy */
} job;

static void patch_fairness(void *arg, int k)
{
    job *J = arg;
    double *o = J->out[k];
    o[0] = o[1] = 0;
    if (q2n_surface_kind(J->s, k) == Q2N_PATCH_UNCOVERED) return;
    double e[Q2N_EVAL_MAX], H, K;
    for (int d = 0; d < 2; d++) {
        double tv = 0, len = 0, h0 = 0, hp = 0, xp[3] = {0, 0, 0};
        for (int i = 0; i < J->n; i++) {
            double t = (double)i / (J->n - 1);
            if (q2n_surface_eval(J->s, k, t, d ? 1 - t : t, 2, e) || !(q2n_curvatures(e, &H, &K) > 0)) {
                o[0] = o[1] = INFINITY;
                return;
            }
            if (i == 0) h0 = H;
            else tv += fabs(H - hp), len += q2n_v3_dist(e, xp);
            hp = H;
            for (int c = 0; c < 3; c++) xp[c] = e[c];
        }
        o[0] += (tv - fabs(hp - h0)) * len / 2;
    }
    for (int i = 0; i < J->q; i++)
        for (int j = 0; j < J->q; j++) {
            double a;
            if (q2n_surface_eval(J->s, k, J->x[i], J->x[j], 2, e) || !((a = q2n_curvatures(e, &H, &K)) > 0)) {
                o[0] = o[1] = INFINITY;
                return;
            }
            o[1] += J->w[i] * J->w[j] * (4 * H * H - 2 * K) * a;
        }
}

void q2n_surface_fairness_patches(const q2n_surface *s, int n, int q, int threads, double (*out)[2])
{
    job J = {s, n < 3 ? 3 : n, q < 1 ? 1 : q > 32 ? 32 : q, {0}, {0}, out};
    q2n_gauss_legendre01(J.q, J.x, J.w);
    q2n_par_for(q2n_surface_npatches(s), threads, patch_fairness, &J);
}

q2n_fairness q2n_surface_fairness(const q2n_surface *s, int n, int q, int threads)
{
    q2n_fairness f = {INFINITY, INFINITY, INFINITY};
    int np = q2n_surface_npatches(s);
    double (*out)[2] = malloc((np > 0 ? (size_t)np : 1) * sizeof *out);
    if (!out) return f;
    q2n_surface_fairness_patches(s, n, q, threads, out);
    f.ripple = f.energy = f.ripple_ev = 0;
    for (int k = 0; k < np; k++) {
        f.ripple += out[k][0], f.energy += out[k][1];
        if (q2n_surface_kind(s, k) == Q2N_PATCH_COONS_GREGORY) f.ripple_ev += out[k][0];
    }
    free(out);
    return f;
}
