/* surface.c — the composite-surface container (see surface.h) and exact evaluation of
 * tensor-product Bézier patches.  Other patch kinds bring their own evaluator.  Every evaluation
 * leaving the container is checked to be finite (Q2N_ERR_NUMERIC otherwise), whatever produced it. */
#include "patch/surface.h"

#include "core/poly.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct patch {
    q2n_patch_kind kind;
    void *data;
    q2n_patch_eval_fn eval;
    void (*free_data)(void *);
    q2n_patch_grid_fn grid; /* optional fast grid evaluator */
    q2n_patch_grid_fn grid_pos; /* optional fast grid evaluator, positions only */
    q2n_patch_corner_fn corner; /* optional exact mixed corner partials */
    int du, dv;  /* Bézier degrees */
    double *cp;  /* Bézier control points */
} patch;

struct q2n_surface {
    int n;
    patch *p;
    int mapped;     /* q2n_surface_map_linear: evaluator outputs go through L (Bézier points already did) */
    double L[3][3];
};

/* The n 3-vectors at x through L, in place. */
static void map_vecs(const double L[3][3], double *x, size_t n)
{
    for (size_t q = 0; q < n; q++, x += 3) {
        double y[3];
        for (int i = 0; i < 3; i++) y[i] = L[i][0] * x[0] + L[i][1] * x[1] + L[i][2] * x[2];
        memcpy(x, y, sizeof y);
    }
}

/* An evaluator's n output vectors through s's map (positions and derivatives alike). */
static void map_out(const q2n_surface *s, double *out, size_t n)
{
    if (s->mapped) map_vecs(s->L, out, n);
}

void q2n_surface_map_linear(q2n_surface *s, const double L[3][3])
{
    double P[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            P[i][j] = s->mapped ? L[i][0] * s->L[0][j] + L[i][1] * s->L[1][j] + L[i][2] * s->L[2][j] : L[i][j];
    memcpy(s->L, P, sizeof P);
    s->mapped = 1;
    for (int k = 0; k < s->n; k++) /* Bézier points map exactly, once */
        if (s->p[k].kind == Q2N_PATCH_BEZIER) map_vecs(L, s->p[k].cp, (size_t)(s->p[k].du + 1) * (s->p[k].dv + 1));
}

/* ------------------------------------------------------------ the face parametrization */

const int q2n_corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
const int q2n_side_along[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
const int q2n_side_inward[4][2] = {{0, 1}, {-1, 0}, {0, -1}, {1, 0}};
const int q2n_side_iota[4] = {1, -1, -1, 1};
const int q2n_side_level[4] = {0, 1, 1, 0};
const int q2n_eval_order[10][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}, {3, 0}, {2, 1}, {1, 2}, {0, 3}};

void q2n_side_uv(int i, double t, double s, double *u, double *v)
{
    const int *c = q2n_corner_uv[i], *a = q2n_side_along[i], *n = q2n_side_inward[i];
    *u = c[0] + t * a[0] + s * n[0];
    *v = c[1] + t * a[1] + s * n[1];
}

void q2n_side_derivs(int i, int nder, const double *e, double D[6][3])
{
    /* ax = (a_u, n_u), ay = (a_v, n_v): the u and v components of the frame's two directions */
    const int ax[2] = {q2n_side_along[i][0], q2n_side_inward[i][0]}, ay[2] = {q2n_side_along[i][1], q2n_side_inward[i][1]};
    static const int pr[3][2] = {{0, 0}, {0, 1}, {1, 1}};
    for (int q = 0; q < 3; q++) {
        D[0][q] = e[q];
        if (nder < 1) continue;
        D[1][q] = ax[0] * e[Q2N_EV_U + q] + ay[0] * e[Q2N_EV_V + q];
        D[2][q] = ax[1] * e[Q2N_EV_U + q] + ay[1] * e[Q2N_EV_V + q];
        if (nder < 2) continue;
        for (int r = 0; r < 3; r++) {
            int a = pr[r][0], b = pr[r][1];
            D[3 + r][q] = ax[a] * ax[b] * e[Q2N_EV_UU + q] + (ax[a] * ay[b] + ay[a] * ax[b]) * e[Q2N_EV_UV + q] +
                          ay[a] * ay[b] * e[Q2N_EV_VV + q];
        }
    }
}

q2n_surface *q2n_surface_create(int npatches)
{
    q2n_surface *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->n = npatches;
    s->p = calloc(npatches > 0 ? (size_t)npatches : 1, sizeof *s->p);
    if (!s->p) { free(s); return NULL; }
    return s;
}

static void patch_clear(patch *p)
{
    if (p->free_data) p->free_data(p->data);
    free(p->cp);
    memset(p, 0, sizeof *p);
}

void q2n_surface_free(q2n_surface *s)
{
    if (!s) return;
    for (int k = 0; k < s->n; k++) patch_clear(&s->p[k]);
    free(s->p);
    free(s);
}

int q2n_surface_npatches(const q2n_surface *s) { return s->n; }

q2n_patch_kind q2n_surface_kind(const q2n_surface *s, int k)
{
    return (k >= 0 && k < s->n) ? s->p[k].kind : Q2N_PATCH_UNCOVERED;
}

int q2n_surface_count(const q2n_surface *s, q2n_patch_kind kind)
{
    int c = 0;
    for (int k = 0; k < s->n; k++) c += s->p[k].kind == kind;
    return c;
}

/* Bernstein polynomials of degree n at t with derivatives up to nder: b[d*(n+1)+i]. */
static void bernstein(int n, double t, int nder, double *b)
{
    double tmp[16][16];
    /* Derivatives via degree-reduced bases: B^(d)_{n,i} = n!/(n-d)! Σ_j (-1)^(d-j) C(d,j) B_{n-d,i-j}. */
    for (int m = 0; m <= n; m++) {  /* tmp[m][i] = B_{m,i}(t) */
        for (int i = 0; i <= m; i++) {
            if (m == 0) { tmp[0][0] = 1.0; continue; }
            double a = (i < m) ? (1 - t) * tmp[m - 1][i] : 0.0;
            double c = (i > 0) ? t * tmp[m - 1][i - 1] : 0.0;
            tmp[m][i] = a + c;
        }
    }
    for (int d = 0; d <= nder; d++) {
        double fall = 1;
        for (int q = 0; q < d; q++) fall *= n - q;
        for (int i = 0; i <= n; i++) {
            double acc = 0;
            if (d <= n) {
                for (int j = 0; j <= d; j++) {
                    int idx = i - j, m = n - d;
                    double bb = (idx >= 0 && idx <= m) ? tmp[m][idx] : 0.0;
                    acc += (((d - j) & 1) ? -1.0 : 1.0) * q2n_binom[d][j] * bb;
                }
            }
            b[d * (n + 1) + i] = fall * acc;
        }
    }
}

static void bezier_eval(const patch *p, double u, double v, int nder, double *out)
{
    double bu[3 * 16], bv[3 * 16];
    const int(*ord)[2] = q2n_eval_order;
    int nout = nder == 0 ? 1 : nder == 1 ? 3 : 6;
    bernstein(p->du, u, nder, bu);
    bernstein(p->dv, v, nder, bv);
    for (int o = 0; o < nout; o++) {
        const double *a = bu + ord[o][0] * (p->du + 1), *b = bv + ord[o][1] * (p->dv + 1);
        double r[3] = {0, 0, 0};
        for (int j = 0; j <= p->dv; j++) {
            for (int i = 0; i <= p->du; i++) {
                const double *c = p->cp + 3 * (j * (p->du + 1) + i);
                double w = a[i] * b[j];
                r[0] += w * c[0]; r[1] += w * c[1]; r[2] += w * c[2];
            }
        }
        memcpy(out + 3 * o, r, sizeof r);
    }
}

/* Q2N_ERR_NUMERIC unless all n values are finite (one pass, no branch per value). */
static q2n_status all_finite(const double *x, size_t n)
{
    double acc = 0;
    for (size_t i = 0; i < n; i++) acc += x[i] * 0.0; /* NaN iff some x[i] is NaN or Inf */
    return acc == 0.0 ? Q2N_OK : Q2N_ERR_NUMERIC;
}

q2n_status q2n_surface_eval(const q2n_surface *s, int k, double u, double v, int nder, double *out)
{
    if (k < 0 || k >= s->n || nder < 0 || nder > 2) return Q2N_ERR_ARG;
    const patch *p = &s->p[k];
    q2n_status st;
    switch (p->kind) {
    case Q2N_PATCH_BEZIER: bezier_eval(p, u, v, nder, out); st = Q2N_OK; break;
    case Q2N_PATCH_UNCOVERED: return Q2N_ERR_ARG;
    default: st = p->eval(p->data, u, v, nder, out); map_out(s, out, nder == 0 ? 1 : nder == 1 ? 3 : 6);
    }
    return st ? st : all_finite(out, nder == 0 ? 3 : nder == 1 ? 9 : 18);
}

q2n_status q2n_surface_eval_grid(const q2n_surface *s, int k, int nu, const double *us, int nv,
                                 const double *vs, double *out)
{
    if (k < 0 || k >= s->n) return Q2N_ERR_ARG;
    const patch *p = &s->p[k];
    if (p->kind == Q2N_PATCH_UNCOVERED) return Q2N_ERR_ARG;
    if (p->grid) {
        q2n_status st = p->grid(p->data, nu, us, nv, vs, out);
        map_out(s, out, 3 * (size_t)nu * nv);
        return st ? st : all_finite(out, 9 * (size_t)nu * nv);
    }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            q2n_status st = q2n_surface_eval(s, k, us[i], vs[j], 1, out + 9 * ((size_t)j * nu + i));
            if (st) return st;
        }
    return Q2N_OK;
}

q2n_status q2n_surface_eval_grid_pos(const q2n_surface *s, int k, int nu, const double *us, int nv,
                                     const double *vs, double *out)
{
    if (k < 0 || k >= s->n) return Q2N_ERR_ARG;
    const patch *p = &s->p[k];
    size_t n = (size_t)nu * nv;
    if (p->grid_pos && p->kind != Q2N_PATCH_UNCOVERED) {
        q2n_status st = p->grid_pos(p->data, nu, us, nv, vs, out);
        map_out(s, out, n);
        return st ? st : all_finite(out, 3 * n);
    }
    double *buf = malloc(9 * sizeof(double) * (n ? n : 1));
    if (!buf) return Q2N_ERR_NOMEM;
    q2n_status st = q2n_surface_eval_grid(s, k, nu, us, nv, vs, buf);
    for (size_t q = 0; !st && q < n; q++) memcpy(out + 3 * q, buf + 9 * q, 3 * sizeof(double));
    free(buf);
    return st;
}

int q2n_surface_first_nonfinite(const double *out, int npoints)
{
    for (int p = 0; p < npoints; p++)
        if (all_finite(out + 9 * (size_t)p, 9)) return p;
    return -1;
}

q2n_status q2n_surface_scan(const q2n_surface *s, int k, int n, const double ref[3], int *folded,
                            double *u, double *v)
{
    double t[Q2N_SCAN_MAX], buf[9 * Q2N_SCAN_MAX * Q2N_SCAN_MAX];
    *folded = 0;
    if (n < 1 || n > Q2N_SCAN_MAX) return Q2N_ERR_ARG;
    for (int i = 0; i < n; i++) t[i] = (i + 0.5) / n;
    q2n_status st = q2n_surface_eval_grid(s, k, n, t, n, t, buf);
    if (st == Q2N_ERR_NUMERIC) {
        int p = q2n_surface_first_nonfinite(buf, n * n);
        if (p >= 0) *u = t[p % n], *v = t[p / n];
    }
    if (st) return st;
    for (int p = 0; p < n * n && !*folded; p++) {
        const double *a = buf + 9 * p + Q2N_EV_U, *b = buf + 9 * p + Q2N_EV_V;
        double nrm[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        if (nrm[0] * ref[0] + nrm[1] * ref[1] + nrm[2] * ref[2] < 0) {
            *folded = 1;
            *u = t[p % n];
            *v = t[p / n];
        }
    }
    return Q2N_OK;
}

q2n_status q2n_surface_set_bezier(q2n_surface *s, int k, int du, int dv, const double *cp)
{
    if (k < 0 || k >= s->n || du < 1 || dv < 1 || du > 15 || dv > 15) return Q2N_ERR_ARG;
    size_t n = 3 * (size_t)(du + 1) * (dv + 1);
    double *c = malloc(n * sizeof *c);
    if (!c) return Q2N_ERR_NOMEM;
    memcpy(c, cp, n * sizeof *c);
    patch_clear(&s->p[k]);
    s->p[k].kind = Q2N_PATCH_BEZIER;
    s->p[k].du = du;
    s->p[k].dv = dv;
    s->p[k].cp = c;
    return Q2N_OK;
}

int q2n_surface_bezier(const q2n_surface *s, int k, int *du, int *dv, const double **cp)
{
    if (q2n_surface_kind(s, k) != Q2N_PATCH_BEZIER) return 0;
    *du = s->p[k].du;
    *dv = s->p[k].dv;
    *cp = s->p[k].cp;
    return 1;
}

q2n_status q2n_surface_set_patch(q2n_surface *s, int k, q2n_patch_kind kind, void *data,
                                 q2n_patch_eval_fn eval, void (*free_data)(void *))
{
    if (k < 0 || k >= s->n || !eval || kind == Q2N_PATCH_BEZIER || kind == Q2N_PATCH_UNCOVERED)
        return Q2N_ERR_ARG;
    patch_clear(&s->p[k]);
    s->p[k].kind = kind;
    s->p[k].data = data;
    s->p[k].eval = eval;
    s->p[k].free_data = free_data;
    return Q2N_OK;
}

const void *q2n_surface_patch_data(const q2n_surface *s, int k)
{
    return (k >= 0 && k < s->n) ? s->p[k].data : NULL;
}

void *q2n_surface_patch_data_mut(q2n_surface *s, int k)
{
    return (k >= 0 && k < s->n) ? s->p[k].data : NULL;
}

q2n_status q2n_surface_set_patch_grid(q2n_surface *s, int k, q2n_patch_grid_fn grid)
{
    if (k < 0 || k >= s->n || s->p[k].kind == Q2N_PATCH_UNCOVERED || s->p[k].kind == Q2N_PATCH_BEZIER)
        return Q2N_ERR_ARG;
    s->p[k].grid = grid;
    return Q2N_OK;
}

q2n_status q2n_surface_set_patch_grid_pos(q2n_surface *s, int k, q2n_patch_grid_fn grid_pos)
{
    if (k < 0 || k >= s->n || s->p[k].kind == Q2N_PATCH_UNCOVERED || s->p[k].kind == Q2N_PATCH_BEZIER)
        return Q2N_ERR_ARG;
    s->p[k].grid_pos = grid_pos;
    return Q2N_OK;
}

q2n_status q2n_surface_set_patch_corner(q2n_surface *s, int k, q2n_patch_corner_fn fn)
{
    if (k < 0 || k >= s->n || s->p[k].kind == Q2N_PATCH_UNCOVERED || s->p[k].kind == Q2N_PATCH_BEZIER)
        return Q2N_ERR_ARG;
    s->p[k].corner = fn;
    return Q2N_OK;
}

q2n_status q2n_surface_corner_mixed(const q2n_surface *s, int k, int i, int j, double out[2][2][2][3])
{
    if (!s || k < 0 || k >= s->n || (i & ~1) || (j & ~1)) return Q2N_ERR_ARG;
    if (!s->p[k].corner) return Q2N_ERR_UNSUPPORTED;
    q2n_status st = s->p[k].corner(s->p[k].data, i, j, out);
    map_out(s, &out[0][0][0][0], 8);
    return st;
}

double q2n_surface_project(const q2n_surface *s, int k, const double P[3], int maxit, double *u, double *v)
{
    double best = INFINITY;
    for (int it = 0; it < maxit; it++) {
        double e[Q2N_EVAL_MAX], r[3];
        if (q2n_surface_eval(s, k, *u, *v, 1, e) != Q2N_OK) break;
        q2n_v3_sub(r, e, P);
        best = fmin(best, q2n_v3_norm(r));
        const double *Su = e + Q2N_EV_U, *Sv = e + Q2N_EV_V;
        double a = q2n_v3_dot(Su, Su), b = q2n_v3_dot(Su, Sv), c = q2n_v3_dot(Sv, Sv);
        double gu = -q2n_v3_dot(Su, r), gv = -q2n_v3_dot(Sv, r), det = a * c - b * b;
        if (!(det > 0)) break;
        double du = (c * gu - b * gv) / det, dv = (a * gv - b * gu) / det;
        double nu = fmin(1.0, fmax(0.0, *u + du)), nv = fmin(1.0, fmax(0.0, *v + dv));
        double step = fabs(nu - *u) + fabs(nv - *v);
        *u = nu;
        *v = nv;
        if (step < 1e-15) break; /* rounding of parameters in [0,1] */
    }
    return best;
}
