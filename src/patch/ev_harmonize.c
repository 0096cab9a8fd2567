/* ev_harmonize.c — corner compatibility for the paper's construction in G2 mode (ev_paper.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "core/vec3.h"
#include "patch/ev_internal.h"
#include "patch/ev_policy.h"

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
        q2n_status st = q2n_ev_paper_patch_setup(V->P, m, V->s, V->iv, V->unc, V->edges, V->K, V->kb, c->f, V->err);
        if (st) return st;
        for (int o = 0; o < 4; o++)
            for (int x = 0; x < 3; x++) {
                int a = hz_ab[o][0], b = hz_ab[o][1];
                r[HZ_RC * q + 3 * o + x] = CP_CT(&V->P->E.C, 2, c->i, c->j, a, b)[x] - CP_CT(&V->P->E.C, 1, c->i, c->j, a, b)[x];
            }
    }
    return Q2N_OK;
}

/* Cholesky factorisation of the symmetric n x n matrix G in place (core/dense.h, LAPACK; G is
 * stored whole, so row- and column-major read the same); 0 if not positive definite. */
static int chol_factor(double *G, int n) { return q2n_dense_cholesky(n, G, n) == 0; }

static void chol_solve(const double *G, double *y, int n) { q2n_dense_cholesky_solve(n, 1, G, n, y, n); }

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
            q2n_ev_side_eval(&S, q / 10.0, F);
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
        q2n_status st = q2n_ev_paper_patch_setup(V->P, V->m, V->s, V->iv, V->unc, V->edges, V->K, V->kb, V->cs[q].f, V->err);
        if (st) return st;
        double sc = 1.0 / V->gb[q][0];
        for (int a = 0; a <= 8; a++)
            for (int b = 0; b <= 8; b++) {
                double D[9];
                q2n_cp_eval_point(V->P, a / 8.0, b / 8.0, 1, D);
                for (int x = 0; x < 6; x++) out[(size_t)HZ_NS * q + 6 * (9 * a + b) + x] = sc * D[3 + x];
            }
    }
    return Q2N_OK;
}

/* Q = the cost's Gram matrix, one block per edge end (block of the group starting at g0 at
 * Q + HZ_GU * g0, the first-order data weighted by F), or with full != NULL one nu x nu block
 * full^T full + EV_HZ_EDGE_WEIGHT of the edge cost (its trace relative), then Cholesky-factored in place.
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
        double lam = te > 0 ? EV_HZ_EDGE_WEIGHT * tf / te : 0, qmax = 0;
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
    q2n_status st = q2n_ev_paper_patch_setup(V->P, V->m, V->s, V->iv, V->unc, V->edges, V->K, V->kb, f, V->err);
    if (st) return st;
    double big = 0, sn = 1, *nr = out ? out + 2 : NULL;
    for (int a = 0; a <= 8; a++)
        for (int b = 0; b <= 8; b++) {
            double D[9], c[3];
            q2n_cp_eval_point(V->P, a / 8.0, b / 8.0, 1, D);
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
    for (int gn = 0; gn < EV_HZ_MAX_STEPS; gn++) {
        if (gn > 0) {
            memcpy(zl, z, sizeof(double) * (size_t)nu);
            if ((st = hz_jacobian(V, zl, V->rc, V->Mw))) return st;
        }
        if (!hz_min_change(V, V->Mw, V->rc, zl, grp, z)) break;
        nstep++;
        if (V->r11 <= EV_HZ_AFFINE_REL * V->rmax) break; /* affine: one step is exact */
        for (int k = 0; k < nu; k++) *V->u[k] += z[k];
        st = hz_residuals(V, -1, NULL, V->rt);
        for (int k = 0; k < nu; k++) *V->u[k] -= z[k];
        if (st) return st;
        double rn = 0;
        for (int i = 0; i < nr; i++) rn = fmax(rn, fabs(V->rt[i]));
        if (rn <= EV_HZ_DONE_REL * V->rmax) break;
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
 * corner data (mismatches tens of times the patch's first derivatives) only
 * the surface-aware correction keeps the patches unfolded.  If that fails too, the corners at v
 * stay Gregory corners.
 *
 * The mismatches are affine in every unknown but the slopes of a, b (unknowns only where a twist
 * disagrees); there Gauss-Newton steps follow (hz_attempt), each the same least-change problem
 * for the linear model at the current point. */
q2n_status q2n_ev_harmonize_vertex(const q2n_mesh *m, const q2n_surface *s, const double *iv, const char *unc,
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
        V->cs[nc] = (hz_corner){f, q2n_corner_uv[k][0], q2n_corner_uv[k][1]};
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
     * sign guard of q2n_ev_build_edge changed a slope); elsewhere the twists stay as they are */
    if (!(V->r11 > EV_HZ_AFFINE_REL * V->rmax)) {
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
