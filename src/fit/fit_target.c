/* fit_target.c — what the fit approximates: the construction S_k seen through a reparametrization
 * of each patch, T_k = S_k ∘ φ_k, chosen so that the gluing across the construction's "scaled" edges
 * becomes a constant scale, which the fit can then impose exactly (fit_glue.c).
 *
 * Why.  Across an edge where S is parametrically continuous up to a scale — d_s S_R(1-t) =
 * alpha(t) d_s S_L(t), and d_ss S_R = alpha^2 d_ss S_L in G2 (beta = gamma = delta = 0; the
 * augmented patches of seed 003 on non-uniform meshes: alpha is a ratio of the local
 * parametrization functions, not a polynomial) — no pair of spline rows satisfies the relation
 * exactly unless alpha is constant.  T_k has the same geometry as S_k (φ_k is a diffeomorphism of
 * [0,1]^2 that maps each side onto itself and fixes the corners), so its fit is a fit of the
 * surface; its parametrization is chosen so that alpha becomes constant.
 *
 * How.  (1) Every edge e gets a speed at each of its two end vertices, s_e(v) = exp(x_e(v)): its
 * curve is reparametrized by the quintic tau_e with tau(0) = 0, tau(1) = 1, tau'(0), tau'(1) the
 * speeds at its start and end vertex, tau''(0) = tau''(1) = 0.  At a vertex the cross derivative of a
 * patch is the tangent of the other edge there, so the end values of alpha across edge e (from v0 to
 * v1) become alpha(0) s_fR0(v0) / s_fL0(v0) and alpha(1) s_fR1(v1) / s_fL1(v1) (f.. = the edges of L
 * and R at the two ends); asking them to agree is one linear equation per edge,
 *      x_fR0(v0) - x_fL0(v0) - x_fR1(v1) + x_fL1(v1) = log(alpha(1) / alpha(0)),
 * in two unknowns per edge, solved in the minimum-norm least-squares sense (CGLS, Björck, Numerical
 * Methods for Least Squares Problems §7.4); edges whose equation is not met stay least squares.  (One
 * speed per edge, the same at both ends, as until 2026-12-02, couples the equations of both vertices
 * of every edge: fewer systems are consistent and the speeds it finds are larger — on the shared
 * meshes 5 835 exact edges instead of 5 960, docs/fit.md.)  (2) Along such an edge the
 * cross speed of side L is lambda_L(t) = smoothstep between its end speeds and that of side R is
 * lambda_R = A lambda_L / alpha(tau(t)), A = alpha(0) s_fR0(v0) / s_fL0(v0), so that the new gluing
 * lambda_R alpha / lambda_L is the constant A (or side L absorbs alpha's variation instead, when R
 * must keep phi = id); every other side's cross speed is the smoothstep.  Patches with a side whose
 * gluing is not a scale (extraordinary regions) keep phi = id and their edges speed 1: those
 * regions are least squares anyway, and they keep the construction's grid evaluation.
 * (3) φ_k is the Boolean-sum Coons map (formulas.md §4.1, quintic Hermite blending) with boundary
 * values tau on the sides, normal derivatives lambda and zero tangential and second derivatives;
 * the corner data are compatible because alpha' = 0 at the ends of such an edge (checked) and the
 * smoothstep is flat there.  On the boundary, with sigma = rho = kappa = 0:
 *      T = S(tau), T_t = tau' S_t, T_s = lambda S_s, T_tt = tau'^2 S_tt + tau'' S_t,
 *      T_ts = lambda' S_s + lambda tau' S_ts, T_ss = lambda^2 S_ss,
 * so d_s T_R = A d_s T_L and d_ss T_R = A^2 d_ss T_L exactly; at the corners φ is separable to
 * order (2,2), so the mixed derivatives of T are those of S times s_t^a s_s^b.
 * Patches whose sides all have speed 1 and constant gluing keep φ = id (and the grid fast path). */
#include <pthread.h>

#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/hermite.h"
#include "core/vec3.h"
#include "spline/spline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* tau(t) and its first two derivatives for end speeds s0, s1 (value 0 -> 1, curvature 0 at both):
 * H01 + s0 H10 + s1 H11 in the quintic Hermite basis (core/hermite.h). */
static void tau_eval(double s0, double s1, double t, double d[3])
{
    double H[3][2][Q2N_HERMITE_MAXD + 1];
    q2n_hermite_eval(2, t, 2, H);
    for (int k = 0; k < 3; k++) d[k] = H[0][1][k] + s0 * H[1][0][k] + s1 * H[1][1][k];
}

/* Edge e and whether side (k, i) runs along its owner orientation. */
static int side_edge(const fit_ctx *c, int k, int i, int *own)
{
    int h = c->m->face_start[k] + i, e = c->m->he_edge[h];
    *own = c->m->edge_he[e] == h;
    return e;
}

/* The end of edge e at vertex v: 0 at its owner half-edge's origin, 1 at its destination. */
static int edge_end(const fit_ctx *c, int e, int v) { return q2n_he_origin(c->m, c->m->edge_he[e]) == v ? 0 : 1; }

/* Speed of edge e's reparametrization at its end at vertex v. */
static double speed_at(const fit_ctx *c, int e, int v) { return exp(c->e[e].x[edge_end(c, e, v)]); }

/* Speed at corner j of patch k of the edge of side i (i = j or j - 1: the two sides at corner j). */
static double corner_speed(const fit_ctx *c, int k, int i, int j)
{
    int own;
    return speed_at(c, side_edge(c, k, i, &own), c->m->face_vert[c->m->face_start[k] + (j & 3)]);
}

/* tau_e of edge e (owner orientation) at x, from its speeds at both ends. */
static void edge_tau(const fit_ctx *c, int e, double x, double d[3])
{
    tau_eval(exp(c->e[e].x[0]), exp(c->e[e].x[1]), x, d);
}

/* tau of side (k, i) in the side's orientation at t: tau_i(t) = tau_e(t) (owner) or 1 - tau_e(1 - t). */
static void side_tau(const fit_ctx *c, int k, int i, double t, double d[3])
{
    int own, e = side_edge(c, k, i, &own);
    if (own) { edge_tau(c, e, t, d); return; }
    edge_tau(c, e, 1.0 - t, d);
    d[0] = 1.0 - d[0];
    d[2] = -d[2];
}

/* The smoothstep cross speed of side (k, i): from the speed of the edge before it (corner i) to
 * that of the edge after it (corner i + 1); value and derivative. */
static void side_lin(const fit_ctx *c, int k, int i, double t, double *l, double *dl)
{
    double a = corner_speed(c, k, (i + 3) & 3, i), b = corner_speed(c, k, (i + 1) & 3, i + 1);
    double o[4];
    q2n_spline_blend_derivs(2, a, b, t, o); /* a + (b - a) H01(t), the quintic smoothstep */
    *l = o[0];
    *dl = o[1];
}

/* alpha(x) and alpha'(x) of edge e at owner parameter x from the construction's frame derivatives
 * of both sides (d_s S_R(1 - x) = alpha d_s S_L(x); differentiating, -d_ts S_R = alpha' d_s S_L +
 * alpha d_ts S_L, projected on d_s S_L), and both sides' frames there. */
static q2n_status alpha_compute(const fit_ctx *c, int e, double x, double *al, double *dal, double DL[6][3],
                                double DR[6][3])
{
    const q2n_mesh *m = c->m;
    int h = m->edge_he[e], ht = m->he_twin[h], fL = m->he_face[h], fR = m->he_face[ht];
    q2n_status st = q2n_fit_frame_eval(c->s, fL, h - m->face_start[fL], x, 0.0, 2, DL);
    if (!st) st = q2n_fit_frame_eval(c->s, fR, ht - m->face_start[fR], 1.0 - x, 0.0, 2, DR);
    if (st) return st;
    double nn = q2n_v3_dot(DL[2], DL[2]);
    *al = q2n_v3_dot(DR[2], DL[2]) / nn;
    double w[3];
    for (int q = 0; q < 3; q++) w[q] = -DR[4][q] - *al * DL[4][q];
    *dal = q2n_v3_dot(w, DL[2]) / nn;
    return Q2N_OK;
}

/* Index of x in edge e's alpha cache (under amu); -1 when absent, *pos the insertion point. */
static int ac_find(const fit_edge *E, double x, int *pos)
{
    return q2n_fit_sorted_find(E->av, E->an, FIT_AC_STRIDE, x, pos);
}

/* alpha_compute through edge e's cache: every sample grid asks for alpha at its side parameters, the
 * grids of a patch (rounds, missing points, measurement) and the two faces of the edge (at the same
 * owner parameter) ask for the same ones again.  The cache keeps alpha and alpha' (the same numbers);
 * beyond its budget (Q2N_FIT_ALPHA_CACHE_BYTES) values are computed and not kept.  *frames is 1 when
 * DL, DR were evaluated on the way (a miss), 0 when the cache answered. */
static q2n_status edge_alpha(fit_ctx *c, int e, double x, double *al, double *dal, double DL[6][3], double DR[6][3],
                             int *frames)
{
    fit_edge *E = &c->e[e];
    int pos, at;
    *frames = 0;
    pthread_mutex_lock(&E->amu);
    if ((at = ac_find(E, x, &pos)) >= 0) {
        *al = E->av[FIT_AC_STRIDE * (size_t)at + 1];
        *dal = E->av[FIT_AC_STRIDE * (size_t)at + 2];
        pthread_mutex_unlock(&E->amu);
        return Q2N_OK;
    }
    pthread_mutex_unlock(&E->amu);
    q2n_status st = alpha_compute(c, e, x, al, dal, DL, DR);
    if (st) return st;
    *frames = 1;
    pthread_mutex_lock(&E->amu);
    if (ac_find(E, x, &pos) < 0) { /* the other face may have added it meanwhile */
        if (E->an == E->acap) {
            int nc = E->acap ? 2 * E->acap : 16;
            long add = (long)(nc - E->acap) * FIT_AC_STRIDE * (long)sizeof(double);
            if ((double)(atomic_fetch_add(&c->alpha_bytes, add) + add) <= Q2N_FIT_ALPHA_CACHE_BYTES) {
                double *nv = realloc(E->av, sizeof(double) * FIT_AC_STRIDE * (size_t)nc);
                if (nv) E->av = nv, E->acap = nc;
                else atomic_fetch_sub(&c->alpha_bytes, add);
            } else {
                atomic_fetch_sub(&c->alpha_bytes, add);
            }
        }
        if (E->an < E->acap) {
            double *r = E->av + FIT_AC_STRIDE * (size_t)pos;
            memmove(r + FIT_AC_STRIDE, r, sizeof(double) * FIT_AC_STRIDE * (size_t)(E->an - pos));
            r[0] = x;
            r[1] = *al;
            r[2] = *dal;
            E->an++;
        }
    }
    pthread_mutex_unlock(&E->amu);
    return Q2N_OK;
}

/* Cross speed of side (k, i) at t: value and derivative.  Where it needs alpha (the side that absorbs
 * its variation) and alpha is not cached, the construction's frame of this side at tau_i(t) is
 * evaluated on the way; it goes to D when D is given (*have = 1), the same bits q2n_fit_frame_eval
 * gives there. */
static q2n_status side_lambda(fit_ctx *c, int k, int i, double t, double *l, double *dl, double D[6][3],
                              int *have)
{
    int own, e = side_edge(c, k, i, &own);
    const fit_edge *E = &c->e[e];
    if (have) *have = 0;
    /* the side that absorbs alpha's variation: R (absorb 0) or L (absorb 1) */
    if (!E->rep || own != E->absorb) { side_lin(c, k, i, t, l, dl); return Q2N_OK; }
    const q2n_mesh *m = c->m;
    int h = own ? m->he_twin[m->edge_he[e]] : m->edge_he[e], fo = m->he_face[h], io = h - m->face_start[fo];
    double x = 1.0 - t, lo, dlo, tau[3], al, dal;   /* x: the other side's parameter, x = 1 - t */
    side_lin(c, fo, io, x, &lo, &dlo);
    double xe = own ? t : x;                         /* owner parameter of this point */
    edge_tau(c, e, xe, tau);
    double DL[6][3], DR[6][3];
    int frames;
    q2n_status st = edge_alpha(c, e, tau[0], &al, &dal, DL, DR, &frames);
    if (st) return st;
    /* this side's frame: L at tau_e(t) (owner), R at 1 - tau_e(1 - t) — side_tau's tau_i(t) */
    if (D && frames) {
        memcpy(D, own ? DL : DR, sizeof DL);
        *have = 1;
    }
    if (!own) {   /* R: lambda_R(t) = A lambda_L(x) / alpha(tau(x)); d/dt = -d/dx */
        *l = E->A * lo / al;
        *dl = -E->A * (dlo / al - lo * dal * tau[1] / (al * al));
    } else {      /* L: lambda_L(t) = lambda_R(x) alpha(tau(t)) / A; d lambda_R(x)/dt = -lambda_R'(x) */
        *l = lo * al / E->A;
        *dl = (-dlo * al + lo * dal * tau[1]) / E->A;
    }
    return Q2N_OK;
}

q2n_status q2n_fit_target_frame(fit_ctx *c, int k, int i, double t, double D[6][3])
{
    if (!c->p[k].phi) return q2n_fit_frame_eval(c->s, k, i, t, 0.0, 2, D);
    double tau[3], l, dl, S[6][3];
    int have = 0;
    side_tau(c, k, i, t, tau);
    q2n_status st = side_lambda(c, k, i, t, &l, &dl, S, &have);
    if (!st && !have) st = q2n_fit_frame_eval(c->s, k, i, tau[0], 0.0, 2, S);
    if (st) return st;
    for (int q = 0; q < 3; q++) {
        D[0][q] = S[0][q];
        D[1][q] = tau[1] * S[1][q];
        D[2][q] = l * S[2][q];
        D[3][q] = tau[1] * tau[1] * S[3][q] + tau[2] * S[1][q];
        D[4][q] = dl * S[2][q] + l * tau[1] * S[4][q];
        D[5][q] = l * l * S[5][q];
    }
    return Q2N_OK;
}

/* The quintic Hermite functions at x (formulas.md §4.1's blending): h[0] = H00 (value at 0), h[1] =
 * H01 (value at 1), h[2] = H10 (slope at 0), h[3] = H11 (slope at 1). */
static void hermite4(double x, double h[4])
{
    double H[3][2][Q2N_HERMITE_MAXD + 1];
    q2n_hermite_eval(2, x, 0, H);
    h[0] = H[0][0][0]; h[1] = H[0][1][0]; h[2] = H[1][0][0]; h[3] = H[1][1][0];
}

/* phi_k(u, v) from the Hermite functions at u and v (hu, hv: hermite4), the sides' tau values (tu0 =
 * tau_0(u), tu2 = tau_2(1 - u), tv1 = tau_1(v), tv3 = tau_3(1 - v)) and cross speeds (l0(u), l2(1 - u),
 * l1(v), l3(1 - v)) and the corner speeds: the Boolean sum P_u + P_v - P_uv (formulas.md §4.1) of each
 * component. */
static void coons_phi(const double hu[4], const double hv[4], double tu0, double tu2, double tv1, double tv3, double l0,
                      double l1, double l2, double l3, const double cs[4][2], double out[2])
{
    /* phi^u: u = 0: 0, d_u = l3; u = 1: 1, d_u = l1; v = 0: tau_0(u), v = 1: 1 - tau_2(1 - u) */
    double Pu = hu[1] + hu[2] * l3 + hu[3] * l1;
    double Pv = hv[0] * tu0 + hv[1] * (1.0 - tu2);
    double Puv = hu[1] + hu[2] * (hv[0] * cs[0][0] + hv[1] * cs[3][0]) + hu[3] * (hv[0] * cs[1][0] + hv[1] * cs[2][0]);
    out[0] = Pu + Pv - Puv;
    /* phi^v: v = 0: 0, d_v = l0; v = 1: 1, d_v = l2; u = 0: 1 - tau_3(1 - v), u = 1: tau_1(v) */
    double Qv = hv[1] + hv[2] * l0 + hv[3] * l2;
    double Qu = hu[0] * (1.0 - tv3) + hu[1] * tv1;
    double Quv = hv[1] + hv[2] * (hu[0] * cs[0][1] + hu[1] * cs[1][1]) + hv[3] * (hu[0] * cs[3][1] + hu[1] * cs[2][1]);
    out[1] = Qv + Qu - Quv;
}

/* Corner speeds of patch k: cs[i][0] = d_u phi^u and cs[i][1] = d_v phi^v at corner i (the speeds
 * of the edges along u and v there). */
static void corner_speeds(const fit_ctx *c, int k, double cs[4][2])
{
    cs[0][0] = corner_speed(c, k, 0, 0); cs[0][1] = corner_speed(c, k, 3, 0);
    cs[1][0] = corner_speed(c, k, 0, 1); cs[1][1] = corner_speed(c, k, 1, 1);
    cs[2][0] = corner_speed(c, k, 2, 2); cs[2][1] = corner_speed(c, k, 1, 2);
    cs[3][0] = corner_speed(c, k, 2, 3); cs[3][1] = corner_speed(c, k, 3, 3);
}

q2n_status q2n_fit_target_grid(fit_ctx *c, int k, int nu, const double *us, int nv, const double *vs, double *out)
{
    if (!c->p[k].phi) return q2n_surface_eval_grid_pos(c->s, k, nu, us, nv, vs, out);
    /* side data and Hermite functions at the grid's parameters (once per grid line) */
    double *a = malloc(sizeof(double) * 8 * (size_t)(nu + nv));
    if (!a) return Q2N_ERR_NOMEM;
    double *tu0 = a, *tu2 = a + nu, *l0 = a + 2 * nu, *l2 = a + 3 * nu;
    double *tv1 = a + 4 * nu, *tv3 = tv1 + nv, *l1 = tv1 + 2 * nv, *l3 = tv1 + 3 * nv, d[3], dl;
    double *hu = tv1 + 4 * nv, *hv = hu + 4 * (size_t)nu;
    for (int i = 0; i < nu; i++) hermite4(us[i], hu + 4 * (size_t)i);
    for (int j = 0; j < nv; j++) hermite4(vs[j], hv + 4 * (size_t)j);
    q2n_status st = Q2N_OK;
    for (int i = 0; i < nu && !st; i++) {
        side_tau(c, k, 0, us[i], d); tu0[i] = d[0];
        side_tau(c, k, 2, 1.0 - us[i], d); tu2[i] = d[0];
        st = side_lambda(c, k, 0, us[i], &l0[i], &dl, NULL, NULL);
        if (!st) st = side_lambda(c, k, 2, 1.0 - us[i], &l2[i], &dl, NULL, NULL);
    }
    for (int j = 0; j < nv && !st; j++) {
        side_tau(c, k, 1, vs[j], d); tv1[j] = d[0];
        side_tau(c, k, 3, 1.0 - vs[j], d); tv3[j] = d[0];
        st = side_lambda(c, k, 1, vs[j], &l1[j], &dl, NULL, NULL);
        if (!st) st = side_lambda(c, k, 3, 1.0 - vs[j], &l3[j], &dl, NULL, NULL);
    }
    double cs[4][2];
    corner_speeds(c, k, cs);
    for (int j = 0; j < nv && !st; j++)
        for (int i = 0; i < nu && !st; i++) {
            double uv[2], S[Q2N_EVAL_MAX];
            coons_phi(hu + 4 * (size_t)i, hv + 4 * (size_t)j, tu0[i], tu2[i], tv1[j], tv3[j], l0[i], l1[j], l2[i], l3[j], cs,
                      uv);
            st = q2n_surface_eval(c->s, k, uv[0], uv[1], 0, S);
            memcpy(out + 3 * ((size_t)j * nu + i), S, 3 * sizeof(double));
        }
    free(a);
    return st;
}

/* Mixed corner derivatives of T from those of S (φ is separable to order (2, 2) at the corners):
 * d_t^a d_s^b T = s_t^a s_s^b d_t^a d_s^b S for corner i of patch k (side i's frame). */
double q2n_fit_target_jet_scale(const fit_ctx *c, int k, int i, int a, int b)
{
    double st = corner_speed(c, k, i, i), ss = corner_speed(c, k, (i + 3) & 3, i);
    return pow(st, a) * pow(ss, b);
}

/* ------------------------------------------------------------------ setup */

/* CGLS for min |M x - r| (M sparse: rows of 4 entries +-1 over edges), from x = 0: the minimum-norm
 * solution for a consistent system; it stops when every equation is met to within stop (checked every
 * 10 iterations), when the normal equations' residual has fallen by 1e-30, or after maxit.  Returns the
 * final max residual. */
static double cgls(int n, int nrow, const int (*col)[4], const double (*val)[4], const double *r, double *x, int maxit,
                   double stop)
{
    double *res = malloc(sizeof(double) * (size_t)nrow), *s = calloc((size_t)n, sizeof(double));
    double *p = calloc((size_t)n, sizeof(double)), *q = malloc(sizeof(double) * (size_t)nrow);
    double out = HUGE_VAL;
    if (!res || !s || !p || !q) goto done;
    memset(x, 0, sizeof(double) * (size_t)n);
    memcpy(res, r, sizeof(double) * (size_t)nrow);
    for (int i = 0; i < nrow; i++)
        for (int j = 0; j < 4; j++) s[col[i][j]] += val[i][j] * res[i];
    memcpy(p, s, sizeof(double) * (size_t)n);
    double gamma = 0.0, g0;
    for (int j = 0; j < n; j++) gamma += s[j] * s[j];
    g0 = gamma;
    for (int it = 0; it < maxit && gamma > 1e-30 * (g0 > 0 ? g0 : 1); it++) {
        if (it % 10 == 0) {
            double mr = 0.0;
            for (int i = 0; i < nrow; i++) mr = fmax(mr, fabs(res[i]));
            if (mr <= stop) break;
        }
        double qq = 0.0;
        for (int i = 0; i < nrow; i++) {
            q[i] = 0.0;
            for (int j = 0; j < 4; j++) q[i] += val[i][j] * p[col[i][j]];
            qq += q[i] * q[i];
        }
        if (qq <= 0) break;
        double al = gamma / qq;
        for (int j = 0; j < n; j++) x[j] += al * p[j];
        for (int i = 0; i < nrow; i++) res[i] -= al * q[i];
        memset(s, 0, sizeof(double) * (size_t)n);
        for (int i = 0; i < nrow; i++)
            for (int j = 0; j < 4; j++) s[col[i][j]] += val[i][j] * res[i];
        double gn = 0.0;
        for (int j = 0; j < n; j++) gn += s[j] * s[j];
        for (int j = 0; j < n; j++) p[j] = s[j] + gn / gamma * p[j];
        gamma = gn;
    }
    out = 0.0;
    for (int i = 0; i < nrow; i++) {
        double w = -r[i];
        for (int j = 0; j < 4; j++) w += val[i][j] * x[col[i][j]];
        if (fabs(w) > out) out = fabs(w);
    }
done:
    free(res); free(s); free(p); free(q);
    return out;
}

q2n_status q2n_fit_target_setup(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    int ne = m->ne, nf = m->nf, nrow = 0;
    int (*col)[4] = malloc(sizeof *col * (size_t)(ne + 1));
    double (*val)[4] = malloc(sizeof *val * (size_t)(ne + 1)), *r = malloc(sizeof(double) * (size_t)(ne + 1));
    int *row_e = malloc(sizeof(int) * (size_t)(ne + 1));
    double *x = calloc(2 * (size_t)ne + 1, sizeof(double));   /* x[2e + end] */
    unsigned char *fixed = calloc((size_t)nf + 1, 1), *efix = calloc((size_t)ne + 1, 1);
    if (!col || !val || !r || !row_e || !x || !fixed || !efix) {
        free(col); free(val); free(r); free(row_e); free(x); free(fixed); free(efix);
        return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    }
    /* patches with a side whose gluing is not a scale (extraordinary regions) keep phi = id: their
     * least-squares sides gain nothing, and they keep the construction's grid fast path */
    for (int e = 0; e < ne; e++) {
        const fit_edge *E = &c->e[e];
        if (E->glue == FIT_GLUE_BOUNDARY || E->rep) continue;
        int h = m->edge_he[e];
        fixed[m->he_face[h]] = fixed[m->he_face[m->he_twin[h]]] = 1;
    }
    for (int k = 0; k < nf; k++)
        if (fixed[k])
            for (int i = 0; i < 4; i++) efix[m->he_edge[4 * k + i]] = 1;
    for (int e = 0; e < ne; e++) {
        fit_edge *E = &c->e[e];
        E->x[0] = E->x[1] = 0.0;
        if (!E->rep) continue;
        int h = m->edge_he[e], fL = fixed[m->he_face[h]], fR = fixed[m->he_face[m->he_twin[h]]];
        E->absorb = fR;                       /* the free side absorbs alpha's variation */
        if (fL && fR && E->alpha_varies) E->rep = 0;
    }
    for (int pass = 0; pass < 4; pass++) {
        nrow = 0;
        for (int e = 0; e < ne; e++) {
            fit_edge *E = &c->e[e];
            if (!E->rep) continue;
            int h = m->edge_he[e], ht = m->he_twin[h], v0 = q2n_he_origin(m, h), v1 = q2n_he_dest(m, h);
            int fL0 = m->he_edge[q2n_he_prev(m, h)], fL1 = m->he_edge[q2n_he_next(m, h)];
            int fR0 = m->he_edge[q2n_he_next(m, ht)], fR1 = m->he_edge[q2n_he_prev(m, ht)];
            int cc[4] = {fR0, fL0, fR1, fL1}, vx[4] = {v0, v0, v1, v1};
            double vv[4] = {1.0, -1.0, -1.0, 1.0};
            for (int j = 0; j < 4; j++) {   /* edges of fixed patches keep speed 1 (x = 0) */
                col[nrow][j] = 2 * cc[j] + edge_end(c, cc[j], vx[j]);
                val[nrow][j] = efix[cc[j]] ? 0.0 : vv[j];
            }
            r[nrow] = log(E->alpha1 / E->alpha0);
            row_e[nrow++] = e;
        }
        if (!nrow) break;
        cgls(2 * ne, nrow, (const int (*)[4])col, (const double (*)[4])val, r, x, Q2N_FIT_SPEED_ITER, Q2N_FIT_SPEED_STOP);
        int dropped = 0;
        for (int i = 0; i < nrow; i++) {
            double w = -r[i];
            for (int j = 0; j < 4; j++) w += val[i][j] * x[col[i][j]];
            if (fabs(w) > Q2N_FIT_SPEED_RESID) { c->e[row_e[i]].rep = 0; dropped++; }
        }
        if (!dropped) break;
        if (pass == 3) for (int i = 0; i < nrow; i++) c->e[row_e[i]].rep = 0;   /* no consistent set found */
    }
    for (int e = 0; e < ne; e++)
        for (int end = 0; end < 2; end++) c->e[e].x[end] = efix[e] ? 0.0 : x[2 * e + end];
    for (int e = 0; e < ne; e++) {
        fit_edge *E = &c->e[e];
        if (!E->rep) continue;
        int h = m->edge_he[e], ht = m->he_twin[h];
        int fL0 = m->he_edge[q2n_he_prev(m, h)], fR0 = m->he_edge[q2n_he_next(m, ht)], v0 = q2n_he_origin(m, h);
        E->A = E->alpha0 * speed_at(c, fR0, v0) / speed_at(c, fL0, v0);
    }
    /* phi = id when every side has speed 1 and none absorbs a varying alpha */
    for (int k = 0; k < nf; k++) {
        fit_patch *p = &c->p[k];
        p->phi = 0;
        for (int i = 0; i < 4; i++) {
            int own, e = side_edge(c, k, i, &own);
            if (c->e[e].x[0] != 0.0 || c->e[e].x[1] != 0.0 || (c->e[e].rep && own == c->e[e].absorb && c->e[e].alpha_varies)) p->phi = 1;
        }
        /* its sides' caches hold the construction's frames (q2n_fit_glue_measure): T's differ */
        if (p->phi)
            for (int i = 0; i < 4; i++) c->sc[4 * k + i].n = 0;
    }
    free(col); free(val); free(r); free(row_e); free(x); free(fixed); free(efix);
    return Q2N_OK;
}
