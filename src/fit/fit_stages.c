/* fit_stages.c — the linear stages of one fitting round, for the patches and edges whose knots or
 * data changed (the "dirty" set), and the caches of construction samples they read.
 *
 * A round (fit_round) for given knots:
 *  1. knots: each patch's u (v) knot vector is the union of its two u-edges' (v-edges') breakpoints
 *     and its own interior ones (fit_state.h); patches whose vectors changed are rebuilt;
 *  2. edge curves: each mesh edge's boundary curve is fitted ONCE on its own knots K_e: least
 *     squares of the owner patch's edge samples with Hermite end conditions (value, first and
 *     second derivative along the edge equal the construction's at both ends, exact);
 *  3. patch boundaries: each patch side is its edge curve re-expressed on the patch's knots along
 *     that side by knot insertion (the same curve; control points copied bit for bit where the
 *     knots agree, which is always the case when neither patch has extra knots there);
 *  4. corner jets: Q11 (and Q21, Q12, Q22) reproduce the construction's mixed derivatives at every
 *     corner (computed once per fit; exact for polynomial patches), so the jets of all edges at a
 *     vertex agree with the construction's and the G1/G2 relations hold there to that order;
 *  5. cross rows (fit_glue.c): first rows of both sides of every edge jointly, with the G1 relation
 *     as an equality constraint where the gluing data are polynomial, else as weighted rows;
 *     second rows likewise with the G2 relation in G2 mode;
 *  6. interiors (fit_interior.c): the remaining control points of each patch by least squares on
 *     its sample grid, solved separably (two passes of 1-D fits).
 * Only what changed is refitted: an edge whose knots changed, the patches whose knot vectors
 * changed, the edges of those patches and the patches on the other side of those edges. */
#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/clock.h"
#include "core/vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ breakpoints */

int q2n_fit_breaks_add(fit_breaks *b, double t)
{
    int lo = 0, hi = b->n;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (b->t[mid] < t) lo = mid + 1;
        else hi = mid;
    }
    if (lo < b->n && b->t[lo] == t) return 0;
    if (b->n == b->cap) {
        int nc = b->cap ? 2 * b->cap : 8;
        double *nt = realloc(b->t, sizeof(double) * (size_t)nc);
        if (!nt) return -1;
        b->t = nt;
        b->cap = nc;
    }
    memmove(b->t + lo + 1, b->t + lo, sizeof(double) * (size_t)(b->n - lo));
    b->t[lo] = t;
    b->n++;
    return 1;
}

void q2n_fit_breaks_free(fit_breaks *b)
{
    free(b->t);
    memset(b, 0, sizeof *b);
}

/* ------------------------------------------------------------------ frames */

fit_side q2n_fit_make_side(const fit_ctx *c, int k, int i)
{
    const fit_patch *p = &c->p[k];
    const int *c0 = q2n_corner_uv[i], *a = q2n_side_along[i], *n = q2n_side_inward[i];
    fit_side sd;
    sd.k = k; sd.i = i;
    sd.ox = c0[0] * (p->nu - 1); sd.oy = c0[1] * (p->nv - 1);
    sd.tx = a[0]; sd.ty = a[1];
    sd.sx = n[0]; sd.sy = n[1];
    int along_u = q2n_side_along_u(i);
    sd.nt = along_u ? p->nu : p->nv; sd.ns = along_u ? p->nv : p->nu;
    sd.mt = along_u ? p->mu : p->mv; sd.ms = along_u ? p->mv : p->mu;
    /* t and s run against the knot vector's direction where along / inward is negative */
    int rev_t = a[0] + a[1] < 0, rev_s = n[0] + n[1] < 0;
    sd.kt = along_u ? (rev_t ? p->kur : p->ku) : (rev_t ? p->kvr : p->kv);
    sd.ks = along_u ? (rev_s ? p->kvr : p->kv) : (rev_s ? p->kur : p->ku);
    return sd;
}

/* A side's frame from its first three control rows' curves R[j][a] (d^a/dt^a of row j at t):
 * d^a/dt^a d^b/ds^b S(t, 0) = sum_{j <= b} N_j^(b)(0) R[j][a] (the across basis of a clamped knot
 * vector has N_j^(b)(0) = 0 for j > b); the slots in q2n_eval_order with (t, s) for (u, v). */
static void frame_from_rows(const double Ns[3][Q2N_FIT_DEG + 1], const double R[3][3][3], double F[6][3])
{
    for (int o = 0; o < 6; o++) {
        int a = q2n_eval_order[o][0], b = q2n_eval_order[o][1];
        F[o][0] = F[o][1] = F[o][2] = 0.0;
        for (int j = 0; j <= b; j++) q2n_v3_axpy(F[o], Ns[b][j], R[j][a]);
    }
}

void q2n_fit_side_spline(const fit_ctx *c, const fit_side *sd, const double Ns[3][Q2N_FIT_DEG + 1], double t,
                         double F[6][3])
{
    const fit_patch *p = &c->p[sd->k];
    double Nt[3][Q2N_FIT_DEG + 1], R[3][3][3];   /* R[j][a]: d^a/dt^a of control row j's curve */
    int span = q2n_fit_span(sd->nt, sd->kt, t);
    q2n_fit_basis(span, sd->kt, t, 2, Nt);
    memset(R, 0, sizeof R);
    for (int q = 0; q <= Q2N_FIT_DEG; q++)   /* each sum over q in ascending order, as one loop per sum */
        for (int j = 0; j < 3; j++) {
            const double *P = p->cp + 3 * (size_t)q2n_fit_side_g(c, sd, span - Q2N_FIT_DEG + q, j);
            for (int a = 0; a + j < 3; a++) q2n_v3_axpy(R[j][a], Nt[a][q], P);
        }
    frame_from_rows(Ns, (const double (*)[3][3])R, F);
}

/* The first three control rows of side sd on the span of its knots that starts at or contains t0,
 * as polynomials in d = t - t0: C[j][a][k] is the coefficient of d^k in the a-th derivative of row
 * j's curve (a + j <= 2, the derivatives a side frame needs), from the along basis's derivatives up
 * to the degree at t0 (A2.3) divided by the factorials. */
void q2n_fit_side_poly_at(const fit_ctx *c, const fit_side *sd, double t0, q2n_fit_side_poly C)
{
    const fit_patch *p = &c->p[sd->k];
    double N[Q2N_FIT_DEG + 1][Q2N_FIT_DEG + 1];
    int span = q2n_fit_span(sd->nt, sd->kt, t0);
    q2n_bspline_basis(span, Q2N_FIT_DEG, sd->kt, t0, Q2N_FIT_DEG, N[0]);
    memset(C, 0, sizeof(q2n_fit_side_poly));
    for (int j = 0; j < 3; j++)
        for (int q = 0; q <= Q2N_FIT_DEG; q++) {
            const double *P = p->cp + 3 * (size_t)q2n_fit_side_g(c, sd, span - Q2N_FIT_DEG + q, j);
            double f = 1.0;
            for (int k = 0; k <= Q2N_FIT_DEG; k++) {
                if (k) f /= k;
                q2n_v3_axpy(C[j][0][k], N[k][q] * f, P);
            }
        }
    for (int j = 0; j < 2; j++)   /* derivatives: d/dd sum c_k d^k = sum (k + 1) c_(k+1) d^k */
        for (int a = 1; a + j < 3; a++)
            for (int k = 0; k + a <= Q2N_FIT_DEG; k++) q2n_v3_axpy(C[j][a][k], k + 1.0, C[j][a - 1][k + 1]);
}

/* The side's frame (the layout of q2n_fit_side_spline) at t0 + d from q2n_fit_side_poly_at's C: Horner
 * sums of the rows' polynomials, then the across basis Ns at 0. */
void q2n_fit_side_poly_frame(q2n_fit_side_poly C, const double Ns[3][Q2N_FIT_DEG + 1], double d, double F[6][3])
{
    double R[3][3][3];   /* R[j][a]: d^a/dt^a of row j's curve */
    for (int j = 0; j < 3; j++)
        for (int a = 0; a + j < 3; a++) {
            double v[3] = {0, 0, 0};
            for (int k = Q2N_FIT_DEG - a; k >= 0; k--)
                for (int x = 0; x < 3; x++) v[x] = v[x] * d + C[j][a][k][x];
            memcpy(R[j][a], v, sizeof v);
        }
    frame_from_rows(Ns, (const double (*)[3][3])R, F);
}

const char *q2n_fit_edge_where(const fit_ctx *c, int e, char *buf, size_t n)
{
    int h = c->m->edge_he[e], t = c->m->he_twin[h];
    if (t < 0) snprintf(buf, n, "face %d", c->m->he_face[h]);
    else snprintf(buf, n, "between face %d and face %d", c->m->he_face[h], c->m->he_face[t]);
    return buf;
}

int q2n_fit_edge_sides(const fit_ctx *c, int e, fit_side *L, fit_side *R)
{
    const q2n_mesh *m = c->m;
    int h = m->edge_he[e], ht = m->he_twin[h];
    *L = q2n_fit_make_side(c, m->he_face[h], h - m->face_start[m->he_face[h]]);
    if (ht < 0) return 0;
    *R = q2n_fit_make_side(c, m->he_face[ht], ht - m->face_start[m->he_face[ht]]);
    return 1;
}

q2n_status q2n_fit_frame_eval(const q2n_surface *surf, int k, int i, double t, double s, int nder, double D[6][3])
{
    double u, v, e[Q2N_EVAL_MAX];
    q2n_side_uv(i, t, s, &u, &v);
    q2n_status st = q2n_surface_eval(surf, k, u, v, nder, e);
    if (st) return st;
    for (int q = 0; q < 3 * (nder == 0 ? 1 : nder == 1 ? 3 : 6); q++)
        if (!isfinite(e[q])) return Q2N_ERR_NUMERIC;
    q2n_side_derivs(i, nder, e, D);
    return Q2N_OK;
}

/* ------------------------------------------------------------------ construction caches */

/* Index of t in the side cache; -1 when absent, *pos the insertion point. */
static int sc_find(const fit_side_cache *sc, double t, int *pos)
{
    return q2n_fit_sorted_find(sc->v, sc->n, FIT_SC_STRIDE, t, pos);
}

/* Reserve add bytes of the construction caches' budget; 0 (nothing reserved) when it would be exceeded. */
static int cache_reserve(fit_ctx *c, long add)
{
    long before = atomic_fetch_add(&c->cache_bytes, add);
    if ((double)(before + add) <= Q2N_FIT_CACHE_BYTES) return 1;
    atomic_fetch_sub(&c->cache_bytes, add);
    return 0;
}

q2n_status q2n_fit_side_values(fit_ctx *c, int k, int i, int n, const double *t, double *D)
{
    fit_side_cache *sc = &c->sc[4 * k + i];
    /* grow to exactly what this call adds (a side holds a few dozen parameters), within the
     * budget of all construction caches; a side that would exceed it is evaluated without caching (the
     * same values: which sides are cached does not change any result) */
    int missing = 0;
    for (int q = 0; q < n; q++) {
        int pos;
        missing += sc_find(sc, t[q], &pos) < 0;
    }
    int cache = 1;
    if (missing && sc->n + missing > sc->cap) {
        long add = (long)(sc->n + missing - sc->cap) * (long)(FIT_SC_STRIDE * sizeof(double)); /* t and D */
        if (!cache_reserve(c, add)) {
            cache = 0;
        } else {
            int nc = sc->n + missing;
            double *nv = realloc(sc->v, FIT_SC_STRIDE * sizeof(double) * (size_t)nc);
            if (!nv) return Q2N_ERR_NOMEM;
            sc->v = nv;
            sc->cap = nc;
        }
    }
    for (int q = 0; q < n; q++) {
        int pos, at = sc_find(sc, t[q], &pos);
        if (at >= 0) {
            if (D) memcpy(D + 18 * (size_t)q, sc->v + FIT_SC_STRIDE * (size_t)at + 1, 18 * sizeof(double));
            continue;
        }
        if (!cache && !D) continue;   /* a prefetch beyond the budget: evaluated when needed */
        double V[6][3];
        q2n_status st = q2n_fit_target_frame(c, k, i, t[q], V);
        if (st) return st;
        if (cache) {
            double *at_pos = sc->v + FIT_SC_STRIDE * (size_t)pos;
            memmove(at_pos + FIT_SC_STRIDE, at_pos, FIT_SC_STRIDE * sizeof(double) * (size_t)(sc->n - pos));
            at_pos[0] = t[q];
            memcpy(at_pos + 1, V, sizeof V);
            sc->n++;
        }
        if (D) memcpy(D + 18 * (size_t)q, V, sizeof V);
    }
    return Q2N_OK;
}

/* Merge sorted distinct a[0..na-1] with sorted distinct b into out (sorted distinct); returns count. */
static int merge_params(int na, const double *a, int nb, const double *b, double *out)
{
    int i = 0, j = 0, n = 0;
    while (i < na || j < nb) {
        double x = j >= nb || (i < na && a[i] < b[j]) ? a[i++] : b[j++];
        if (n == 0 || out[n - 1] != x) out[n++] = x;
        while (i < na && a[i] == x) i++;
        while (j < nb && b[j] == x) j++;
    }
    return n;
}

/* Bytes of a grid cache of nu x nv parameters: u, v, positions, have. */
static long grid_cache_bytes(int nu, int nv)
{
    return (long)(nu + nv) * (long)sizeof(double) + (long)nu * nv * (long)(3 * sizeof(double) + 1);
}

/* Positions of patch k on the grid us x vs into out, evaluated without the cache. */
static q2n_status grid_uncached(fit_ctx *c, int k, int nu, const double *us, int nv, const double *vs, double *out,
                                long *evals)
{
    q2n_status st = q2n_fit_target_grid(c, k, nu, us, nv, vs, out);
    for (size_t q = 0; !st && q < (size_t)nu * nv; q++) {
        const double *x = out + 3 * q;
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) st = Q2N_ERR_NUMERIC;
    }
    *evals += (long)nu * nv;
    return st;
}

/* Positions of the construction's patch k on the grid us x vs (sorted, distinct) into out
 * (3 per point, u fastest), from the patch's grid cache; missing points are evaluated with the
 * grid fast path, in at most two grids (below). */
static q2n_status grid_values(fit_ctx *c, int k, int nu, const double *us, int nv, const double *vs, double *out,
                              long *evals)
{
    fit_grid_cache *g = &c->p[k].gc;
    /* grow the cache to the union of parameters, within the budget of all construction caches;
     * beyond it the grid is evaluated without caching (the same values) */
    double *nu_t = malloc(sizeof(double) * (size_t)(g->nu + nu)), *nv_t = malloc(sizeof(double) * (size_t)(g->nv + nv));
    if (!nu_t || !nv_t) { free(nu_t); free(nv_t); return Q2N_ERR_NOMEM; }
    int NU = merge_params(g->nu, g->u, nu, us, nu_t), NV = merge_params(g->nv, g->v, nv, vs, nv_t);
    if ((NU != g->nu || NV != g->nv) && !cache_reserve(c, grid_cache_bytes(NU, NV) - grid_cache_bytes(g->nu, g->nv))) {
        free(nu_t); free(nv_t);
        return grid_uncached(c, k, nu, us, nv, vs, out, evals);
    }
    if (NU != g->nu || NV != g->nv) {
        double *su = realloc(nu_t, sizeof(double) * (size_t)NU), *sv = realloc(nv_t, sizeof(double) * (size_t)NV);
        if (su) nu_t = su;
        if (sv) nv_t = sv;
        double *val = malloc(3 * sizeof(double) * (size_t)NU * NV);
        unsigned char *have = calloc((size_t)NU * NV, 1);
        int *mu = malloc(sizeof(int) * (size_t)(g->nu + 1)), *mv = malloc(sizeof(int) * (size_t)(g->nv + 1));
        if (!val || !have || !mu || !mv) {
            free(val); free(have); free(mu); free(mv); free(nu_t); free(nv_t);
            return Q2N_ERR_NOMEM;
        }
        for (int i = 0, a = 0; i < g->nu; i++) { while (nu_t[a] != g->u[i]) a++; mu[i] = a; }
        for (int j = 0, b = 0; j < g->nv; j++) { while (nv_t[b] != g->v[j]) b++; mv[j] = b; }
        for (int j = 0; j < g->nv; j++)
            for (int i = 0; i < g->nu; i++)
                if (g->have[(size_t)j * g->nu + i]) {
                    size_t to = (size_t)mv[j] * NU + mu[i];
                    memcpy(val + 3 * to, g->val + 3 * ((size_t)j * g->nu + i), 3 * sizeof(double));
                    have[to] = 1;
                }
        free(mu); free(mv);
        free(g->u); free(g->v); free(g->val); free(g->have);
        g->u = nu_t; g->v = nv_t; g->val = val; g->have = have; g->nu = NU; g->nv = NV;
    } else {
        free(nu_t);
        free(nv_t);
    }
    int *iu = malloc(sizeof(int) * (size_t)nu), *iv = malloc(sizeof(int) * (size_t)nv);
    double *ru = malloc(sizeof(double) * (size_t)nu), *buf = malloc(3 * sizeof(double) * (size_t)nu * nv);
    if (!iu || !iv || !ru || !buf) { free(iu); free(iv); free(ru); free(buf); return Q2N_ERR_NOMEM; }
    for (int i = 0, a = 0; i < nu; i++) { while (g->u[a] != us[i]) a++; iu[i] = a; }
    for (int j = 0, b = 0; j < nv; j++) { while (g->v[b] != vs[j]) b++; iv[j] = b; }
    /* A grid evaluation costs a line per parameter and a little per point: the rows missing entirely
     * are evaluated as one grid over all columns (nothing cached: the whole grid), the partly cached
     * rows as one grid over the columns they miss (a point's value does not depend on the grid it is
     * evaluated in). */
    q2n_status st = Q2N_OK;
    int *rows = malloc(sizeof(int) * (size_t)nv), *miss = malloc(sizeof(int) * (size_t)nv);
    int *cols = malloc(sizeof(int) * (size_t)nu), missing = 0;
    double *rv = malloc(sizeof(double) * (size_t)nv);
    unsigned char *cm = calloc((size_t)nu, 1);
    if (!rows || !miss || !cols || !rv || !cm) st = Q2N_ERR_NOMEM;
    for (int j = 0; !st && j < nv; j++) {
        miss[j] = 0;
        for (int i = 0; i < nu; i++) miss[j] += !g->have[(size_t)iv[j] * g->nu + iu[i]];
        missing += miss[j];
    }
    for (int pass = 0; pass < 2 && !st && missing; pass++) { /* 0: rows missing entirely, 1: the others */
        int n = 0, nc = 0;
        for (int j = 0; j < nv; j++) {
            if (!miss[j] || (miss[j] == nu) != (pass == 0)) continue;
            rows[n] = j;
            rv[n++] = vs[j];
            if (pass)
                for (int i = 0; i < nu; i++) cm[i] |= !g->have[(size_t)iv[j] * g->nu + iu[i]];
        }
        if (!n) continue;
        for (int i = 0; i < nu; i++)
            if (pass == 0 || cm[i]) { cols[nc] = i; ru[nc++] = us[i]; }
        st = q2n_fit_target_grid(c, k, nc, ru, n, rv, buf);
        for (int r = 0; !st && r < n; r++)
            for (int q = 0; q < nc; q++) {
                size_t at = (size_t)iv[rows[r]] * g->nu + iu[cols[q]];
                if (g->have[at]) continue;
                memcpy(g->val + 3 * at, buf + 3 * ((size_t)r * nc + q), 3 * sizeof(double));
                g->have[at] = 1;
            }
        *evals += (long)nc * n;
    }
    free(rows); free(miss); free(cols); free(rv); free(cm);
    for (int j = 0; !st && j < nv; j++)
        for (int i = 0; i < nu; i++) {
            const double *x = g->val + 3 * ((size_t)iv[j] * g->nu + iu[i]);
            if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) st = Q2N_ERR_NUMERIC;
            memcpy(out + 3 * ((size_t)j * nu + i), x, 3 * sizeof(double));
        }
    free(iu); free(iv); free(ru); free(buf);
    return st;
}

q2n_status q2n_fit_patch_grid(fit_ctx *c, int k, int nu, const double *us, int nv, const double *vs, double *out,
                          long *evals)
{
    return grid_values(c, k, nu, us, nv, vs, out, evals);
}

/* ------------------------------------------------------------------ once per fit */

/* One-sided weights at 0 for the nodes h, 2h, .., 6h (the corner itself is avoided: Gregory-type
 * corners have direction-dependent mixed derivatives there): value, first and second derivative
 * of the quintic through the six values, exact for polynomials of degree <= 5. */
static const double FD[3][6] = {{6, -15, 20, -15, 6, -1},
                                {-87.0 / 10, 117.0 / 4, -127.0 / 3, 33, -27.0 / 2, 137.0 / 60},
                                {29.0 / 3, -461.0 / 12, 62, -307.0 / 6, 65.0 / 3, -15.0 / 4}};

/* The mixed corner derivatives J[o] = d_t^a d_s^b S(0,0) for the four orders (a, b) of jet_order
 * at corner i of patch k (side i's frame), and spread[o], the gap between the two edge-wise values:
 * exact from the construction where it reports them (q2n_surface_corner_mixed), else read along both
 * edges through the corner by one-sided 6-point differences of the evaluated second derivatives
 * (the corner itself is avoided: Gregory-type corners have direction-dependent mixed derivatives
 * there), averaged.  Every order uses the same 12 evaluations. */
static q2n_status corner_mixed(const q2n_surface *surf, int k, int i, double J[4][3], double spread[4])
{
    static const int ord[4][2] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};
    double X[2][2][2][3];
    const int *c0 = q2n_corner_uv[i];
    if (q2n_surface_corner_mixed(surf, k, c0[0], c0[1], X) == Q2N_OK) {
        int tu = q2n_side_along_u(i); /* t is ±u, s is ±v (or the other way round) */
        double st = q2n_side_along[i][0] + q2n_side_along[i][1], ss = q2n_side_inward[i][0] + q2n_side_inward[i][1];
        for (int o = 0; o < 4; o++) {
            int a = ord[o][0], b = ord[o][1], au = tu ? a : b, bv = tu ? b : a;
            double sg = (a & 1 ? st : 1) * (b & 1 ? ss : 1);
            const double *E0 = X[0][au - 1][bv - 1], *E1 = X[1][au - 1][bv - 1];
            for (int r = 0; r < 3; r++) J[o][r] = sg * 0.5 * (E0[r] + E1[r]);
            spread[o] = q2n_v3_dist(E0, E1);
        }
        return Q2N_OK;
    }
    /* [o][edge] = {slot of the frame derivatives (3 d_tt, 4 d_ts, 5 d_ss), order of the difference} */
    static const int tab[4][2][2] = {{{4, 0}, {4, 0}}, {{4, 1}, {3, 1}}, {{5, 1}, {4, 1}}, {{5, 2}, {3, 2}}};
    const double h = Q2N_FIT_JET_H;
    double D[2][6][6][3];
    for (int dir = 0; dir < 2; dir++)
        for (int q = 1; q <= 6; q++) {
            q2n_status st = q2n_fit_frame_eval(surf, k, i, dir ? 0.0 : q * h, dir ? q * h : 0.0, 2, D[dir][q - 1]);
            if (st) return st;
        }
    for (int o = 0; o < 4; o++) {
        double E[2][3] = {{0, 0, 0}, {0, 0, 0}};
        for (int dir = 0; dir < 2; dir++) {
            int slot = tab[o][dir][0], nd = tab[o][dir][1];
            double scale = nd == 0 ? 1.0 : nd == 1 ? 1.0 / h : 1.0 / (h * h);
            for (int q = 0; q < 6; q++) q2n_v3_axpy(E[dir], FD[nd][q] * scale, D[dir][q][slot]);
        }
        for (int r = 0; r < 3; r++) J[o][r] = 0.5 * (E[0][r] + E[1][r]);
        spread[o] = q2n_v3_dist(E[0], E[1]);
    }
    return Q2N_OK;
}

static const int jet_order[4][2] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};

typedef struct prep_arg {
    fit_ctx *c;
    q2n_status *st;
    double (*S)[2][3];       /* per edge: the construction's points at t = 0 and t = 1 */
} prep_arg;

static void jet_one(void *arg, int k)
{
    prep_arg *a = arg;
    for (int i = 0; i < 4 && !a->st[k]; i++) {
        double J[4][3], sp[4];
        a->st[k] = corner_mixed(a->c->s, k, i, J, sp);
        for (int o = 0; o < 4; o++) {
            int ja = jet_order[o][0], jb = jet_order[o][1];
            double f = q2n_fit_target_jet_scale(a->c, k, i, ja, jb);
            for (int q = 0; q < 3; q++) a->c->jet[k][i][o][q] = f * J[o][q];
            /* the two edge-wise estimates as positions of the control point they fix, for one span
             * (Bézier factors 5, 20 for orders 1, 2), so the verdict does not depend on the knots */
            double dq = f * sp[o] / ((ja == 1 ? 5.0 : 20.0) * (jb == 1 ? 5.0 : 20.0));
            if (o < 3 && dq > Q2N_FIT_JET_SPREAD * a->c->o.tol * a->c->diag) a->c->p[k].gregory |= 1 << i;
        }
    }
}

static void ends_one(void *arg, int e)
{
    prep_arg *a = arg;
    fit_ctx *c = a->c;
    int h = c->m->edge_he[e], f = c->m->he_face[h];
    for (int end = 0; end < 2 && !a->st[e]; end++) {
        double D[6][3];
        a->st[e] = q2n_fit_target_frame(c, f, h - c->m->face_start[f], (double)end, D);
        memcpy(a->S[e][end], D[0], sizeof D[0]);
        memcpy(c->e[e].end[end][0], D[1], sizeof D[1]);   /* d_t */
        memcpy(c->e[e].end[end][1], D[3], sizeof D[3]);   /* d_tt */
    }
}

q2n_status q2n_fit_prepare(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    c->vpos = malloc(3 * sizeof(double) * (size_t)m->nv);
    c->jet = malloc(sizeof *c->jet * (size_t)m->nf);
    int nmax = m->nf > m->ne ? m->nf : m->ne;
    q2n_status *st = calloc((size_t)nmax + 1, sizeof *st);
    double (*S)[2][3] = malloc(sizeof *S * ((size_t)m->ne + 1));
    if (!c->vpos || !c->jet || !st || !S) {
        free(st); free(S);
        return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    }
    double t0 = q2n_now();
    prep_arg arg = {c, st, S};
    q2n_par_for(m->ne, c->o.threads, ends_one, &arg);
    q2n_status r = Q2N_OK;
    char where[64];
    for (int e = 0; e < m->ne && !r; e++)
        if (st[e]) r = q2n_error_set(c->err, st[e], "fit: edge %d (%s): evaluation at its ends %s", e, q2n_fit_edge_where(c, e, where, sizeof where),
                                     st[e] == Q2N_ERR_NUMERIC ? "not finite" : "failed");
    memset(st, 0, sizeof *st * (size_t)nmax);
    if (!r) q2n_par_for(m->nf, c->o.threads, jet_one, &arg);
    for (int k = 0; k < m->nf && !r; k++)
        if (st[k]) r = q2n_error_set(c->err, st[k], "fit: face %d: corner derivatives %s", k,
                                     st[k] == Q2N_ERR_NUMERIC ? "not finite" : "cannot be evaluated");
    free(st);
    c->rep->t_sample += q2n_now() - t0;
    if (r) { free(S); return r; }
    /* corner points: an interpolating construction passes through the vertex (kept exactly);
     * otherwise the corner of the patch of the vertex's first half-edge, the same point for every
     * patch there */
    for (int v = 0; v < m->nv; v++) {
        double *P = c->vpos + 3 * (size_t)v;
        memcpy(P, q2n_mesh_vpos(m, v), 3 * sizeof(double));
        int h = m->vert_he[v];
        if (h < 0) continue;
        int e = m->he_edge[h];
        const double *Se = S[e][m->edge_he[e] == h ? 0 : 1];
        if (q2n_v3_dist(Se, P) > Q2N_FIT_INTERP_REL * c->diag) memcpy(P, Se, 3 * sizeof(double));
    }
    free(S);
    return Q2N_OK;
}

/* ------------------------------------------------------------------ knots */

/* Breakpoints of edge e as seen along half-edge h (t from origin(h) to dest(h)), then as u or v of
 * face side i (sides 2, 3 run against u, v): appended to out; returns the new count. */
static int side_breaks(const fit_ctx *c, int h, int i, double *out, int n)
{
    int e = c->m->he_edge[h], own = c->m->edge_he[e] == h;
    const fit_breaks *K = &c->e[e].K;
    for (int q = 0; q < K->n; q++) {
        double t = own ? K->t[q] : 1.0 - K->t[K->n - 1 - q];
        out[n++] = i < 2 ? t : 1.0 - t;
    }
    return n;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The union knot vector of patch k in direction d (0 u, 1 v) into br (sorted distinct); returns nb. */
int q2n_fit_patch_breaks(const fit_ctx *c, int k, int d, double *br)
{
    int n = 0, h0 = c->m->face_start[k];
    n = side_breaks(c, h0 + d, d, br, n);
    n = side_breaks(c, h0 + d + 2, d + 2, br, n);
    const fit_breaks *I = &c->p[k].I[d];
    for (int q = 0; q < I->n; q++) br[n++] = I->t[q];
    qsort(br, (size_t)n, sizeof *br, cmp_double);
    int w = 0;
    for (int q = 0; q < n; q++)
        if (w == 0 || br[w - 1] != br[q]) br[w++] = br[q];
    return w;
}

/* The knot vector k (n knots) reversed, 1 - k[n-1-q]: k itself when it is symmetric (one span,
 * or symmetric refinement: most patches), else a new array; NULL when k is NULL or out of memory. */
static double *reversed_knots(int n, double *k)
{
    if (!k) return NULL;
    int sym = 1;
    for (int q = 0; q < n && sym; q++) sym = k[q] == 1.0 - k[n - 1 - q];
    if (sym) return k;
    double *r = malloc(sizeof(double) * (size_t)n);
    if (r)
        for (int q = 0; q < n; q++) r[q] = 1.0 - k[n - 1 - q];
    return r;
}

void q2n_fit_patch_free_reversed(fit_patch *p)
{
    if (p->kur != p->ku) free(p->kur);
    if (p->kvr != p->kv) free(p->kvr);
    p->kur = p->kvr = NULL;
}

/* Rebuild patch k's knot vectors from its edges and interior breakpoints; sets knots_changed. */
static q2n_status patch_knots(fit_ctx *c, int k)
{
    fit_patch *p = &c->p[k];
    const q2n_mesh *m = c->m;
    int cap = 2 * (c->e[m->he_edge[4 * k]].K.n + c->e[m->he_edge[4 * k + 1]].K.n + c->e[m->he_edge[4 * k + 2]].K.n +
                   c->e[m->he_edge[4 * k + 3]].K.n) + p->I[0].n + p->I[1].n + 2;
    double *bu = malloc(sizeof(double) * (size_t)cap), *bv = malloc(sizeof(double) * (size_t)cap);
    if (!bu || !bv) { free(bu); free(bv); return Q2N_ERR_NOMEM; }
    int nbu = q2n_fit_patch_breaks(c, k, 0, bu), nbv = q2n_fit_patch_breaks(c, k, 1, bv);
    int same = p->cp && nbu + 6 == p->nu && nbv + 6 == p->nv &&
               !memcmp(bu, p->ku + 6, sizeof(double) * (size_t)nbu) && !memcmp(bv, p->kv + 6, sizeof(double) * (size_t)nbv);
    p->knots_changed = !same;
    if (same) { free(bu); free(bv); return Q2N_OK; }
    q2n_fit_patch_free_reversed(p);
    free(p->ku); free(p->kv); free(p->cp); free(p->var);   /* var's block holds fixed */
    p->mu = nbu + 1; p->mv = nbv + 1; p->nu = nbu + 6; p->nv = nbv + 6;
    size_t n = (size_t)p->nu * p->nv;
    p->ku = malloc(sizeof(double) * (size_t)(p->nu + 6));
    p->kv = malloc(sizeof(double) * (size_t)(p->nv + 6));
    p->cp = calloc(3 * n, sizeof(double));
    p->var = malloc(n * (sizeof(int) + 1));
    p->fixed = p->var ? (unsigned char *)(p->var + n) : NULL;
    if (p->fixed) memset(p->fixed, 0, n);
    if (p->ku) q2n_fit_knots_from_breaks(nbu, bu, p->ku);
    if (p->kv) q2n_fit_knots_from_breaks(nbv, bv, p->kv);
    p->kur = reversed_knots(p->nu + 6, p->ku);
    p->kvr = reversed_knots(p->nv + 6, p->kv);
    if (!p->ku || !p->kv || !p->kur || !p->kvr || !p->cp || !p->fixed || !p->var) {
        free(bu); free(bv);
        return Q2N_ERR_NOMEM;
    }
    for (size_t g = 0; g < n; g++) p->var[g] = -1;
    p->ver++;
    free(bu); free(bv);
    return Q2N_OK;
}

/* ------------------------------------------------------------------ edge curves */

/* Fit edge e's curve on its knots: Hermite ends exact, interior points by least squares of the
 * owner side's samples (one dense block; returns the rows through *A, *b for the caller's solve). */
typedef struct curve_block {
    int e, n, m, var0;
    double *A, *b;
} curve_block;

static q2n_status curve_assemble(fit_ctx *c, int e, curve_block *cb)
{
    fit_edge *E = &c->e[e];
    int h = c->m->edge_he[e], f = c->m->he_face[h], i = h - c->m->face_start[f];
    E->n = E->K.n + 6;
    free(E->cp);
    E->cp = calloc(3 * (size_t)E->n, sizeof(double));
    double *kv = malloc(sizeof(double) * (size_t)(E->n + 6));
    if (!E->cp || !kv) { free(kv); return Q2N_ERR_NOMEM; }
    q2n_fit_knots_from_breaks(E->K.n, E->K.t, kv);
    /* ends: the vertex points, then d/dt and d2/dt2 of the spline at t = 0, 1 equal the construction's */
    const q2n_mesh *m = c->m;
    int v0 = q2n_he_origin(m, h), v1 = q2n_he_dest(m, h);
    memcpy(E->cp, c->vpos + 3 * (size_t)v0, 3 * sizeof(double));
    memcpy(E->cp + 3 * (size_t)(E->n - 1), c->vpos + 3 * (size_t)v1, 3 * sizeof(double));
    for (int end = 0; end < 2; end++) {
        double N[3][Q2N_FIT_DEG + 1];
        int span = end ? E->n - 1 : Q2N_FIT_DEG;
        q2n_fit_basis(span, kv, (double)end, 2, N);
        int q0 = end ? 5 : 0, q1 = end ? 4 : 1, q2 = end ? 3 : 2;
        int i0 = end ? E->n - 1 : 0, i1 = end ? E->n - 2 : 1, i2 = end ? E->n - 3 : 2;
        double *P0 = E->cp + 3 * i0, *P1 = E->cp + 3 * i1, *P2 = E->cp + 3 * i2;
        for (int q = 0; q < 3; q++) {
            P1[q] = (E->end[end][0][q] - N[1][q0] * P0[q]) / N[1][q1];
            P2[q] = (E->end[end][1][q] - N[2][q0] * P0[q] - N[2][q1] * P1[q]) / N[2][q2];
        }
    }
    /* interior points 3 .. n-4 */
    cb->e = e;
    cb->n = E->n - 6;
    cb->m = 0;
    cb->A = cb->b = NULL;
    if (cb->n <= 0) { free(kv); return Q2N_OK; }
    int ns = (E->n - 5) * Q2N_FIT_SAMPLES_PER_SPAN + 1;
    double *ts = malloc(sizeof(double) * (size_t)ns), *D = malloc(18 * sizeof(double) * (size_t)ns);
    cb->A = calloc((size_t)ns * cb->n, sizeof(double));
    cb->b = malloc(3 * sizeof(double) * (size_t)ns);
    if (!ts || !D || !cb->A || !cb->b) { free(kv); free(ts); free(D); return Q2N_ERR_NOMEM; }
    ns = q2n_fit_sample_params(E->n, kv, Q2N_FIT_SAMPLES_PER_SPAN, ts);
    q2n_status st = q2n_fit_side_values(c, f, i, ns, ts, D);
    if (st) { free(kv); free(ts); free(D); return st; }
    for (int q = 1; q + 1 < ns; q++) {
        double N[3][Q2N_FIT_DEG + 1];
        int span = q2n_fit_span(E->n, kv, ts[q]);
        q2n_fit_basis(span, kv, ts[q], 0, N);
        double *row = cb->A + (size_t)cb->m * cb->n, *rhs = cb->b + 3 * (size_t)cb->m;
        memcpy(rhs, D + 18 * (size_t)q, 3 * sizeof(double));
        for (int a = 0; a <= Q2N_FIT_DEG; a++) {
            int j = span - Q2N_FIT_DEG + a;
            if (j >= 3 && j <= E->n - 4) row[j - 3] += N[0][a];
            else q2n_v3_axpy(rhs, -N[0][a], E->cp + 3 * (size_t)j);
        }
        cb->m++;
    }
    free(kv); free(ts); free(D);
    return Q2N_OK;
}

typedef struct curves_arg {
    fit_ctx *c;
    curve_block *cb;
    q2n_status *st;
} curves_arg;

static void curve_one(void *arg, int l)
{
    curves_arg *a = arg;
    a->st[l] = curve_assemble(a->c, a->cb[l].e, &a->cb[l]);
}

static q2n_status stage_curves(fit_ctx *c, const int *list, int n)
{
    curve_block *cb = calloc((size_t)n + 1, sizeof *cb);
    q2n_status *st = calloc((size_t)n + 1, sizeof *st);
    q2n_status r = Q2N_OK;
    if (!cb || !st) { free(cb); free(st); return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); }
    for (int l = 0; l < n; l++) cb[l].e = list[l];
    double t0 = q2n_now();
    curves_arg arg = {c, cb, st};
    q2n_par_for(n, c->o.threads, curve_one, &arg);
    c->rep->t_sample += q2n_now() - t0;
    for (int l = 0; l < n && !r; l++)
        if (st[l]) r = q2n_error_set(c->err, st[l], "fit: edge %d: %s", list[l],
                                     st[l] == Q2N_ERR_NOMEM ? "out of memory" : "construction evaluation failed");
    for (int l = 0; l < n && !r; l++)
        if (cb[l].n > 0 && q2n_fit_ls_dense_item(&c->ls, cb[l].m, cb[l].n, cb[l].A, cb[l].b, &cb[l].var0))
            r = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    if (!r) {
        double t1 = q2n_now();
        r = q2n_fit_ls_solve(&c->ls, c->o.solver, c->o.threads, c->err);
        c->rep->t_solve += q2n_now() - t1;
    }
    for (int l = 0; l < n && !r; l++) {
        fit_edge *E = &c->e[list[l]];
        for (int j = 0; j < cb[l].n; j++) memcpy(E->cp + 3 * (size_t)(3 + j), c->ls.x + 3 * (size_t)(cb[l].var0 + j), 3 * sizeof(double));
        E->fitted = E->ver;
    }
    q2n_fit_ls_clear(&c->ls);
    for (int l = 0; l < n; l++) { free(cb[l].A); free(cb[l].b); }
    free(cb);
    free(st);
    return r;
}

/* Side (k, i)'s boundary row: its edge curve in the side's orientation, refined to the side's knots. */
static q2n_status boundary_row(fit_ctx *c, int k, int i)
{
    const q2n_mesh *m = c->m;
    int h = m->face_start[k] + i, e = m->he_edge[h], own = m->edge_he[e] == h;
    const fit_edge *E = &c->e[e];
    fit_side sd = q2n_fit_make_side(c, k, i);
    fit_patch *p = &c->p[k];
    double *kv = malloc(sizeof(double) * (size_t)(E->n + 6)), *cp = malloc(3 * sizeof(double) * (size_t)E->n);
    double *out = malloc(3 * sizeof(double) * (size_t)sd.nt);
    if (!kv || !cp || !out) { free(kv); free(cp); free(out); return Q2N_ERR_NOMEM; }
    q2n_fit_knots_from_breaks(E->K.n, E->K.t, kv);
    if (own) memcpy(cp, E->cp, 3 * sizeof(double) * (size_t)E->n);
    else {
        for (int q = 0; q < E->n; q++) memcpy(cp + 3 * q, E->cp + 3 * (size_t)(E->n - 1 - q), 3 * sizeof(double));
        double *kr = malloc(sizeof(double) * (size_t)(E->n + 6));
        if (!kr) { free(kv); free(cp); free(out); return Q2N_ERR_NOMEM; }
        for (int q = 0; q < E->n + 6; q++) kr[q] = 1.0 - kv[E->n + 5 - q];
        free(kv);
        kv = kr;
    }
    int r = 0;
    if (E->n == sd.nt && !memcmp(kv, sd.kt, sizeof(double) * (size_t)(sd.nt + 6))) memcpy(out, cp, 3 * sizeof(double) * (size_t)sd.nt);
    else r = q2n_fit_curve_refine(E->n, kv, cp, 3, sd.nt, sd.kt, out);
    if (!r)
        for (int it = 0; it < sd.nt; it++) {
            int g = q2n_fit_side_g(c, &sd, it, 0);
            memcpy(p->cp + 3 * (size_t)g, out + 3 * it, 3 * sizeof(double));
            p->fixed[g] = 1;
        }
    free(kv); free(cp); free(out);
    return r ? Q2N_ERR_GEOMETRY : Q2N_OK;
}

/* ------------------------------------------------------------------ corners */

/* Pin patch k's corner points from the cached jets: Q11 always, Q21 and Q12 unless the corner is
 * Gregory-type, Q22 in G2 mode (the average of the two edge-wise values at a Gregory corner). */
static void pin_corners(fit_ctx *c, int k)
{
    fit_patch *p = &c->p[k];
    int npin = c->o.continuity == 2 ? 4 : 3;
    for (int i = 0; i < 4; i++) {
        fit_side sd = q2n_fit_make_side(c, k, i);
        double Nt[3][Q2N_FIT_DEG + 1], Ns[3][Q2N_FIT_DEG + 1];
        q2n_fit_basis(Q2N_FIT_DEG, sd.kt, 0.0, 2, Nt);
        q2n_fit_basis(Q2N_FIT_DEG, sd.ks, 0.0, 2, Ns);
        for (int o = 0; o < npin; o++) {
            if (o > 0 && o < 3 && (p->gregory & (1 << i))) continue;
            int a = jet_order[o][0], b = jet_order[o][1];
            double J[3];
            memcpy(J, c->jet[k][i][o], sizeof J);
            /* J = sum_{p<=a, q<=b} N_p^(a)(0) M_q^(b)(0) Q_pq, solved for Q_ab */
            for (int pp = 0; pp <= a; pp++)
                for (int qq = 0; qq <= b; qq++) {
                    if (pp == a && qq == b) continue;
                    q2n_v3_axpy(J, -Nt[a][pp] * Ns[b][qq], p->cp + 3 * (size_t)q2n_fit_side_g(c, &sd, pp, qq));
                }
            int g = q2n_fit_side_g(c, &sd, a, b);
            q2n_v3_scale(p->cp + 3 * (size_t)g, 1.0 / (Nt[a][a] * Ns[b][b]), J);
            p->fixed[g] = 1;
        }
    }
}

/* ------------------------------------------------------------------ a round */

/* Mark side i's rows (0 .. order) of patch k fixed with their current values. */
static void keep_rows(fit_ctx *c, int k, int i, int order)
{
    fit_side sd = q2n_fit_make_side(c, k, i);
    for (int js = 0; js <= order && js < sd.ns; js++)
        for (int it = 0; it < sd.nt; it++) c->p[k].fixed[q2n_fit_side_g(c, &sd, it, js)] = 1;
}

q2n_status q2n_fit_round(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    int nf = m->nf, ne = m->ne, order = c->o.continuity;
    double t0 = q2n_now(), s0 = c->rep->t_sample, v0 = c->rep->t_solve;
    unsigned char *edirty = calloc((size_t)ne, 1), *pdirty = calloc((size_t)nf, 1);
    int *elist = malloc(sizeof(int) * (size_t)ne), *plist = malloc(sizeof(int) * (size_t)nf);
    q2n_status st = Q2N_OK;
    if (!edirty || !pdirty || !elist || !plist) { st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); goto out; }
    /* 1. knots; dirty sets: edges whose knots changed, the edges of patches whose knot vectors
     * changed, and the patches on both sides of every dirty edge */
    for (int k = 0; k < nf; k++)
        if ((st = patch_knots(c, k))) { st = q2n_error_set(c->err, st, "fit: out of memory (patch %d)", k); goto out; }
    for (int e = 0; e < ne; e++) edirty[e] = c->e[e].fitted != c->e[e].ver;
    for (int k = 0; k < nf; k++)
        if (c->p[k].knots_changed)
            for (int i = 0; i < 4; i++) edirty[m->he_edge[4 * k + i]] = 1;
    int ncurve = 0, nedge = 0, npatch = 0;
    for (int e = 0; e < ne; e++) {
        if (c->e[e].fitted != c->e[e].ver) elist[ncurve++] = e;
        if (!edirty[e]) continue;
        int h = m->edge_he[e], ht = m->he_twin[h];
        pdirty[m->he_face[h]] = 1;
        if (ht >= 0) pdirty[m->he_face[ht]] = 1;
    }
    /* 2. edge curves */
    char what[80];
    int ndirty = 0;
    for (int k = 0; k < nf; k++) ndirty += pdirty[k];
    snprintf(what, sizeof what, "round %d: %d edge curves, %d patches", c->round + 1, ncurve, ndirty);
    q2n_progress_emit(c->o.progress, "fit", what, 0, 0);
    if (ncurve && (st = stage_curves(c, elist, ncurve))) goto out;
    /* 3., 4. dirty patches: corners, boundaries, jets, rows of the sides that stay */
    for (int k = 0; k < nf; k++) {
        fit_patch *p = &c->p[k];
        p->dirty = pdirty[k];
        if (!pdirty[k]) continue;
        plist[npatch++] = k;
        memset(p->fixed, 0, (size_t)p->nu * p->nv);
        for (int i = 0; i < 4; i++)
            if ((st = boundary_row(c, k, i))) {
                st = q2n_error_set(c->err, st, "fit: face %d side %d: edge curve not refinable to the patch knots", k, i);
                goto out;
            }
        pin_corners(c, k);
        for (int i = 0; i < 4; i++)
            if (!edirty[m->he_edge[4 * k + i]]) keep_rows(c, k, i, order);
    }
    /* 5. cross rows of the dirty edges */
    for (int e = 0; e < ne; e++)
        if (edirty[e]) elist[nedge++] = e;
    snprintf(what, sizeof what, "round %d: G1 rows", c->round + 1);
    q2n_progress_emit(c->o.progress, "fit", what, 0, 0);
    if ((st = q2n_fit_rows_stage(c, elist, nedge, 1))) goto out;
    snprintf(what, sizeof what, "round %d: G2 rows", c->round + 1);
    if (order == 2) q2n_progress_emit(c->o.progress, "fit", what, 0, 0);
    if (order == 2 && (st = q2n_fit_rows_stage(c, elist, nedge, 2))) goto out;
    /* 6. interiors */
    snprintf(what, sizeof what, "round %d: interiors", c->round + 1);
    q2n_progress_emit(c->o.progress, "fit", what, 0, 0);
    if ((st = q2n_fit_stage_interior(c, plist, npatch))) goto out;
out:
    free(edirty); free(pdirty); free(elist); free(plist);
    c->rep->t_build += (q2n_now() - t0) - (c->rep->t_sample - s0) - (c->rep->t_solve - v0);
    return st;
}
