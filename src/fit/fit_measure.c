/* fit_measure.c — measurement of a fitted model against its construction.
 *
 * Deviation: at the cell centres of each patch's check grid (the midpoints between the fit
 * samples in u and in v: never fit samples).  Continuity across every interior edge, at the check
 * points of the owner side: G0 gap between the two fitted sides, normal-angle jump (G1), and
 * normal-curvature jump (G2) in three tangent directions (along the edge, across it, and at 45
 * degrees — together they determine the second fundamental form), relative to the local curvature
 * scale max(|kappa|, 1/diag). */
#include "fit/fit_internal.h"
#include "fit/fit_policy.h"
#include "core/vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIT_SQRT1_2 0.70710678118654752440

typedef struct side_forms {
    const double *Su, *Sv;
    double E, F, G, det;   /* first fundamental form; det = |Su x Sv|^2 = EG - F^2 without cancellation */
    double L, M, N;        /* second fundamental form against the unit normal */
} side_forms;

/* The fundamental forms of derivatives d with unit normal n (computed once per side: every
 * direction's curvature below uses the same values). */
static void side_forms_of(const double *d, const double n[3], side_forms *f)
{
    double c[3];
    f->Su = d + Q2N_EV_U;
    f->Sv = d + Q2N_EV_V;
    f->E = q2n_v3_dot(f->Su, f->Su);
    f->F = q2n_v3_dot(f->Su, f->Sv);
    f->G = q2n_v3_dot(f->Sv, f->Sv);
    q2n_v3_cross(c, f->Su, f->Sv);
    f->det = q2n_v3_dot(c, c);
    f->L = q2n_v3_dot(d + Q2N_EV_UU, n);
    f->M = q2n_v3_dot(d + Q2N_EV_UV, n);
    f->N = q2n_v3_dot(d + Q2N_EV_VV, n);
}

/* Normal-curvature of a surface (its fundamental forms f) in the tangent direction
 * closest to w: w = a Su + b Sv in the least-squares sense, kappa = II(a,b) / I(a,b).  0 where the
 * parametrization is singular (Su x Sv = 0: no tangent plane, no curvature to compare): returns
 * 0 then, else 1. */
static int normal_curvature(const side_forms *f, const double w[3], double *kappa)
{
    double pu = q2n_v3_dot(w, f->Su), pv = q2n_v3_dot(w, f->Sv), det = f->det;
    if (!(det > 0)) return 0;
    double E = f->E, F = f->F, G = f->G;
    double a = (G * pu - F * pv) / det, b = (E * pv - F * pu) / det;
    double I = a * a * E + 2 * a * b * F + b * b * G;
    *kappa = (a * a * f->L + 2 * a * b * f->M + b * b * f->N) / I;
    return I > 0 && isfinite(*kappa);
}

/* Unit normal; 0 when Su x Sv vanishes (returns 0, else 1). */
static int unit_normal(const double *d, double n[3])
{
    q2n_v3_cross(n, d + Q2N_EV_U, d + Q2N_EV_V);
    double l = q2n_v3_norm(n);
    if (!(l > 0) || !isfinite(l)) {
        n[0] = n[1] = n[2] = 0.0;
        return 0;
    }
    q2n_v3_scale(n, 1.0 / l, n);
    return 1;
}

void q2n_fit_jumps(const double *dL, const double *dR, const double T[3], double diag, double *g1, double *g2)
{
    double nL[3], nR[3], c[3], lt = q2n_v3_norm(T);
    *g1 = *g2 = 0.0;
    /* a singular point (no tangent plane on a side, or no tangent along the edge: a collapsed
     * side of a degenerate face) has no normal or curvature to compare: it measures nothing */
    if (!unit_normal(dL, nL) || !unit_normal(dR, nR) || !(lt > 0) || !isfinite(lt)) return;
    q2n_v3_cross(c, nL, nR);
    *g1 = atan2(q2n_v3_norm(c), q2n_v3_dot(nL, nR)) * (180.0 / Q2N_PI);
    double t[3], x[3], w[3];
    q2n_v3_scale(t, 1.0 / lt, T);
    q2n_v3_cross(x, nL, t);
    double jmax = 0.0, kmax = 1.0 / diag;
    side_forms fL, fR;
    side_forms_of(dL, nL, &fL);
    side_forms_of(dR, nR, &fR);
    for (int k = 0; k < 3; k++) {
        for (int c3 = 0; c3 < 3; c3++)
            w[c3] = k == 0 ? t[c3] : k == 1 ? x[c3] : (t[c3] + x[c3]) * FIT_SQRT1_2;
        double kl, kr;
        if (!normal_curvature(&fL, w, &kl) || !normal_curvature(&fR, w, &kr)) return; /* singular: g2 stays 0 */
        if (fabs(kl - kr) > jmax) jmax = fabs(kl - kr);
        if (fabs(kl) > kmax) kmax = fabs(kl);
        if (fabs(kr) > kmax) kmax = fabs(kr);
    }
    *g2 = jmax / kmax;
}

/* Knot vector of side i of a B-spline surface in the side's own orientation (t from corner i to
 * i+1): sides 2 and 3 run against u and v, so their knots are 1 - t reversed.  out: n + 6. */
static int side_knots(const q2n_bspline_surface *p, int i, double *out)
{
    int along_u = !(i & 1), n = along_u ? p->ncp_u : p->ncp_v;
    const double *k = along_u ? p->knots_u : p->knots_v;
    for (int q = 0; q < n + Q2N_FIT_DEG + 1; q++) out[q] = i < 2 ? k[q] : 1.0 - k[n + Q2N_FIT_DEG - q];
    return n;
}

/* Continuity of one interior edge at the check points of its owner side; derivatives of either
 * the fitted model (fit == 1) or the construction. */
static q2n_status edge_measure(const q2n_nurbs_model *model, const q2n_surface *s, int fit, int e,
                               double diag, double *g0, double *g1, double *g2)
{
    const q2n_mesh *m = model->mesh;
    int h = m->edge_he[e], ht = m->he_twin[h];
    *g0 = *g1 = *g2 = 0.0;
    if (ht < 0) return Q2N_OK;
    int fL = m->he_face[h], fR = m->he_face[ht];
    int iL = h - m->face_start[fL], iR = ht - m->face_start[fR];
    const q2n_bspline_surface *pL = &model->patches[fL];
    int nmax = (pL->ncp_u > pL->ncp_v ? pL->ncp_u : pL->ncp_v) + Q2N_FIT_DEG + 1;
    if (model->edges && model->edges[e].ncp + Q2N_FIT_DEG + 1 > nmax) nmax = model->edges[e].ncp + Q2N_FIT_DEG + 1;
    double *kv = malloc(sizeof(double) * (size_t)nmax), *ts = malloc(sizeof(double) * (size_t)nmax * Q2N_FIT_SAMPLES_PER_SPAN);
    if (!kv || !ts) { free(kv); free(ts); return Q2N_ERR_NOMEM; }
    /* the check points of the edge curve's knots (the owner side's when the model has no edge curves) */
    int n;
    if (model->edges) {
        n = model->edges[e].ncp;
        memcpy(kv, model->edges[e].knots, sizeof(double) * (size_t)(n + Q2N_FIT_DEG + 1));
    } else
        n = side_knots(pL, iL, kv);
    int N = q2n_fit_check_params(n, kv, Q2N_FIT_SAMPLES_PER_SPAN, ts);
    q2n_status st = Q2N_OK;
    for (int k = 0; k < N && !st; k++) {
        double t = ts[k], uL, vL, uR, vR, dL[Q2N_EVAL_MAX], dR[Q2N_EVAL_MAX];
        q2n_side_uv(iL, t, 0.0, &uL, &vL);
        q2n_side_uv(iR, 1.0 - t, 0.0, &uR, &vR);
        if (fit) {
            q2n_fit_surface_eval(&model->patches[fL], uL, vL, 2, dL);
            q2n_fit_surface_eval(&model->patches[fR], uR, vR, 2, dR);
        } else {
            st = q2n_surface_eval(s, fL, uL, vL, 2, dL);
            if (!st) st = q2n_surface_eval(s, fR, uR, vR, 2, dR);
            if (st) break;
        }
        double F[6][3]; /* F[1]: the tangent along the edge */
        q2n_side_derivs(iL, 1, dL, F);
        double a, b, gap = q2n_v3_dist(dL, dR) / diag;
        q2n_fit_jumps(dL, dR, F[1], diag, &a, &b);
        if (gap > *g0) *g0 = gap;
        if (!(a <= *g1)) *g1 = a;
        if (!(b <= *g2)) *g2 = b;
    }
    free(kv);
    free(ts);
    return st;
}

/* Per-item results of a measurement, filled by the workers and reduced in index order (so the
 * report does not depend on the thread count). */
typedef struct measure_job {
    const q2n_nurbs_model *model;
    const q2n_surface *s;
    double diag;
    int construction;          /* also measure the construction's own continuity */
    double *pd, *ps2, *pvd;    /* per patch: max deviation, sum of squares, corner-vertex gap */
    long *pn;                  /* per patch: check points */
    double *eg[5];             /* per edge: g0, g1, g2 (fitted), g1, g2 (construction) */
    q2n_status *pst, *est;     /* per patch / edge status */
} measure_job;

/* Distance from P to the construction's patch k, by Gauss–Newton on |S(u, v) - P|^2 from (u, v)
 * with the parameters kept in [0,1]^2 (the fit's patches may be reparametrizations of the
 * construction's, fit_target.c: the parametric distance d0 is only an upper bound). */
static double foot_distance(const q2n_surface *s, int k, double u, double v, const double P[3], double d0)
{
    return fmin(d0, q2n_surface_project(s, k, P, Q2N_FIT_FOOT_STEPS, &u, &v));
}

/* Deviation of patch k at the cell centres of its check grid: the distance of each fitted point to
 * the construction's patch (its foot point; the parametric distance when that is already at
 * rounding level). */
static void measure_patch(void *arg, int k)
{
    measure_job *j = arg;
    const q2n_bspline_surface *p = &j->model->patches[k];
    const q2n_mesh *m = j->model->mesh;
    double *us = malloc(sizeof(double) * (size_t)(p->ncp_u * Q2N_FIT_SAMPLES_PER_SPAN + 1));
    double *vs = malloc(sizeof(double) * (size_t)(p->ncp_v * Q2N_FIT_SAMPLES_PER_SPAN + 1));
    int nu = us ? q2n_fit_check_params(p->ncp_u, p->knots_u, Q2N_FIT_SAMPLES_PER_SPAN, us) : 0;
    int nv = vs ? q2n_fit_check_params(p->ncp_v, p->knots_v, Q2N_FIT_SAMPLES_PER_SPAN, vs) : 0;
    double *buf = malloc(9 * sizeof(double) * (size_t)(nu > 0 ? nu : 1) * (nv > 0 ? nv : 1));
    if (!us || !vs || !buf) { free(us); free(vs); free(buf); j->pst[k] = Q2N_ERR_NOMEM; return; }
    q2n_status st = q2n_surface_eval_grid(j->s, k, nu, us, nv, vs, buf);
    double pd = 0.0, s2 = 0.0, vd = 0.0;
    for (int b = 0; !st && b < nv; b++)
        for (int a = 0; a < nu; a++) {
            double f[3];
            q2n_fit_surface_eval(p, us[a], vs[b], 0, f);
            double d = q2n_v3_dist(f, buf + 9 * ((size_t)b * nu + a));
            if (d > 1e-14 * j->diag) d = foot_distance(j->s, k, us[a], vs[b], f, d);
            d /= j->diag;
            s2 += d * d;
            if (!(d <= pd)) pd = d;
        }
    free(buf); free(us); free(vs);
    for (int c = 0; !st && c < 4; c++) {   /* construction corners vs mesh vertices */
        double S[3];
        if ((st = q2n_surface_eval(j->s, k, q2n_corner_uv[c][0], q2n_corner_uv[c][1], 0, S))) break;
        double d = q2n_v3_dist(S, q2n_mesh_vpos(m, m->face_vert[m->face_start[k] + c])) / j->diag;
        if (d > vd) vd = d;
    }
    j->pst[k] = st;
    j->pd[k] = pd;
    j->ps2[k] = s2;
    j->pn[k] = (long)nu * nv;
    j->pvd[k] = vd;
}

static void measure_edge(void *arg, int e)
{
    measure_job *j = arg;
    q2n_status st = edge_measure(j->model, j->s, 1, e, j->diag, &j->eg[0][e], &j->eg[1][e], &j->eg[2][e]);
    double g0;
    if (!st && j->construction) st = edge_measure(j->model, j->s, 0, e, j->diag, &g0, &j->eg[3][e], &j->eg[4][e]);
    j->est[e] = st;
}

q2n_status q2n_fit_measure_model(const q2n_nurbs_model *model, const q2n_surface *s, q2n_fit_report *rep,
                                 q2n_fit_measure_out *mo, int threads, q2n_error *err)
{
    const q2n_mesh *m = model->mesh;
    measure_job j;
    memset(&j, 0, sizeof j);
    j.model = model;
    j.s = s;
    j.diag = q2n_mesh_bbox_diag(m);
    j.construction = mo && mo->edge_g1_c;
    size_t nf = (size_t)model->n, ne = (size_t)m->ne;
    double *mem = calloc(3 * nf + 5 * ne + 1, sizeof(double));
    long *pn = calloc(nf + 1, sizeof(long));
    q2n_status *sts = calloc(nf + ne + 1, sizeof *sts);
    if (!mem || !sts || !pn) {
        free(mem); free(sts); free(pn);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (measure)");
    }
    j.pd = mem; j.ps2 = mem + nf; j.pvd = mem + 2 * nf; j.pn = pn;
    for (int i = 0; i < 5; i++) j.eg[i] = mem + 3 * nf + i * ne;
    j.pst = sts; j.est = sts + nf;
    q2n_par_for(model->n, threads, measure_patch, &j);
    q2n_par_for(m->ne, threads, measure_edge, &j);
    q2n_status st = Q2N_OK;
    for (size_t k = 0; k < nf && !st; k++)
        if (j.pst[k]) st = q2n_error_set(err, j.pst[k], "fit: face %zu: construction evaluation failed", k);
    for (size_t e = 0; e < ne && !st; e++)
        if (j.est[e]) st = q2n_error_set(err, j.est[e], "fit: edge %zu: evaluation failed", e);
    if (st) { free(mem); free(sts); free(pn); return st; }
    double maxd = 0, sum2 = 0, vdev = 0, g0 = 0, g1 = 0, g2 = 0, g1c = 0, g2c = 0;
    long nchk = 0;
    for (size_t k = 0; k < nf; k++) {
        nchk += pn[k];
        sum2 += j.ps2[k];
        if (!(j.pd[k] <= maxd)) maxd = j.pd[k];
        if (j.pvd[k] > vdev) vdev = j.pvd[k];
        if (mo && mo->patch_dev) mo->patch_dev[k] = j.pd[k];
    }
    for (size_t e = 0; e < ne; e++) {
        if (j.eg[0][e] > g0) g0 = j.eg[0][e];
        if (!(j.eg[1][e] <= g1)) g1 = j.eg[1][e];
        if (!(j.eg[2][e] <= g2)) g2 = j.eg[2][e];
        if (mo && mo->edge_g0) mo->edge_g0[e] = j.eg[0][e];
        if (mo && mo->edge_g1) mo->edge_g1[e] = j.eg[1][e];
        if (mo && mo->edge_g2) mo->edge_g2[e] = j.eg[2][e];
        if (j.construction) {
            mo->edge_g1_c[e] = j.eg[3][e];
            mo->edge_g2_c[e] = j.eg[4][e];
            if (j.eg[3][e] > g1c) g1c = j.eg[3][e];
            if (j.eg[4][e] > g2c) g2c = j.eg[4][e];
        }
    }
    free(mem); free(sts); free(pn);
    rep->max_dev_rel = maxd;
    rep->rms_dev_rel = nchk ? sqrt(sum2 / (double)nchk) : 0.0;
    rep->checks = nchk;
    rep->vertex_dev_max_rel = vdev;
    rep->g0_max_rel = g0;
    rep->g1_max_deg = g1;
    rep->g2_max_rel = g2;
    if (j.construction) {
        rep->g1_construction_deg = g1c;
        rep->g2_construction_rel = g2c;
    }
    q2n_fit_report_rim(model, s, rep);
    return Q2N_OK;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

q2n_status q2n_fit_scan_construction(const q2n_surface *s, int k, int n, double *ratio, double *u, double *v,
                                 double *dmax)
{
    if (n < 2) n = 2;
    double *ts = malloc(sizeof(double) * n), *buf = malloc(9 * sizeof(double) * (size_t)n * n);
    double *g = malloc(sizeof(double) * (size_t)n * n);
    *ratio = 1.0; *u = *v = *dmax = 0.0;
    if (!ts || !buf || !g) { free(ts); free(buf); free(g); return Q2N_ERR_NOMEM; }
    for (int i = 0; i < n; i++) ts[i] = (double)i / (n - 1);
    q2n_status st = q2n_surface_eval_grid(s, k, n, ts, n, ts, buf);
    for (size_t q = 0; !st && q < (size_t)n * n; q++) {
        double a = q2n_v3_norm(buf + 9 * q + 3), b = q2n_v3_norm(buf + 9 * q + 6);
        g[q] = a > b ? a : b;
        if (!(g[q] <= *dmax)) { *dmax = g[q]; *u = ts[q % n]; *v = ts[q / n]; }   /* NaN wins too */
    }
    if (!st) {
        qsort(g, (size_t)n * n, sizeof *g, cmp_double);
        double med = g[(size_t)n * n / 2];
        *ratio = med > 0 ? *dmax / med : HUGE_VAL;
    }
    free(ts); free(buf); free(g);
    return st;
}

q2n_status q2n_fit_measure(const q2n_nurbs_model *model, const q2n_surface *s, int threads,
                           q2n_fit_report *rep, q2n_error *err)
{
    if (!model || !s || !rep || !model->mesh || q2n_surface_npatches(s) != model->n)
        return q2n_error_set(err, Q2N_ERR_ARG, "fit_measure: model and surface do not match");
    for (int k = 0; k < model->n; k++)
        if (model->patches[k].deg_u != Q2N_FIT_DEG || model->patches[k].deg_v != Q2N_FIT_DEG ||
            model->patches[k].weights)
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "fit_measure: patch %d is not polynomial bi-quintic", k);
    double *g1c = malloc(sizeof(double) * (size_t)model->mesh->ne);
    double *g2c = malloc(sizeof(double) * (size_t)model->mesh->ne);
    if (!g1c || !g2c) { free(g1c); free(g2c); return q2n_error_set(err, Q2N_ERR_NOMEM, "fit_measure: out of memory"); }
    q2n_fit_measure_out mo = {NULL, NULL, NULL, NULL, g1c, g2c};
    q2n_status st = q2n_fit_measure_model(model, s, rep, &mo, threads, err);
    free(g1c);
    free(g2c);
    return st;
}


/* The tangent T of patch k's side i at its parameter t (0: the side's first corner) and the side's
 * curvature vector K there, (S'' - (S'' . T) T / |T|^2) / |T|^2, fitted (p: the fit's polynomial
 * patches, as the measurement above reads them) or on the construction (s). */
static void side_tangent(const q2n_bspline_surface *p, const q2n_surface *s, int k, int i, double t, double T[3],
                         double K[3])
{
    double u, v, e[Q2N_EVAL_MAX], D[6][3];
    q2n_side_uv(i, t, 0, &u, &v);
    if (p) q2n_fit_surface_eval(p, u, v, 2, e);
    else q2n_surface_eval(s, k, u, v, 2, e);
    q2n_side_derivs(i, 2, e, D);
    memcpy(T, D[1], sizeof D[1]);
    double l2 = q2n_v3_dot(T, T), a = l2 > 0 ? q2n_v3_dot(D[3], T) / l2 : 0;
    for (int c = 0; c < 3; c++) K[c] = l2 > 0 ? (D[3][c] - a * T[c]) / l2 : 0;
}

/* |Ka - Kb| over the larger of |Ka|, |Kb| and 1/diag (the fit report's G2 floor). */
static double curvature_jump(const double Ka[3], const double Kb[3], double diag)
{
    double d[3];
    q2n_v3_sub(d, Ka, Kb);
    return q2n_v3_norm(d) / fmax(fmax(q2n_v3_norm(Ka), q2n_v3_norm(Kb)), 1 / diag);
}

void q2n_fit_report_rim(const q2n_nurbs_model *md, const q2n_surface *s, q2n_fit_report *rep)
{
    const q2n_mesh *m = md->mesh;
    double diag = q2n_mesh_bbox_diag(m);
    rep->rim_vertices = 0;
    rep->rim_max_deg = rep->rim_construction_deg = rep->rim_curv_rel = rep->rim_construction_curv_rel = 0;
    int *inc = malloc(sizeof(int) * (size_t)(m->nv ? m->nv : 1)); /* the boundary half-edge ending at v */
    if (!inc) return;
    for (int v = 0; v < m->nv; v++) inc[v] = -1;
    for (int h = 0; h < m->nh; h++)
        if (m->he_twin[h] < 0) inc[q2n_he_origin(m, q2n_he_next(m, h))] = h;
    for (int h = 0; h < m->nh; h++) {
        int v = q2n_he_origin(m, h), hb = inc[v];
        if (m->he_twin[h] >= 0 || hb < 0 || m->he_face[hb] == m->he_face[h]) continue; /* a corner of one face */
        int fa = m->he_face[h], fb = m->he_face[hb], ia = h - m->face_start[fa], ib = hb - m->face_start[fb];
        double a[3], b[3], ka[3], kb[3];
        side_tangent(&md->patches[fa], NULL, fa, ia, 0, a, ka);
        side_tangent(&md->patches[fb], NULL, fb, ib, 1, b, kb);
        rep->rim_vertices++;
        rep->rim_max_deg = fmax(rep->rim_max_deg, q2n_v3_angle(a, b) * (180.0 / Q2N_PI));
        rep->rim_curv_rel = fmax(rep->rim_curv_rel, curvature_jump(ka, kb, diag));
        if (!s) continue;
        side_tangent(NULL, s, fa, ia, 0, a, ka);
        side_tangent(NULL, s, fb, ib, 1, b, kb);
        rep->rim_construction_deg = fmax(rep->rim_construction_deg, q2n_v3_angle(a, b) * (180.0 / Q2N_PI));
        rep->rim_construction_curv_rel = fmax(rep->rim_construction_curv_rel, curvature_jump(ka, kb, diag));
    }
    free(inc);
}

static int cmp_int(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

void q2n_fit_report_sizes(const q2n_nurbs_model *md, q2n_fit_report *rep)
{
    int *s = malloc(sizeof(int) * (size_t)md->n), *c = malloc(sizeof(int) * (size_t)md->n);
    if (!s || !c) { free(s); free(c); return; }
    rep->cp_total = 0;
    for (int k = 0; k < md->n; k++) {
        const q2n_bspline_surface *p = &md->patches[k];
        s[k] = (p->ncp_u - Q2N_FIT_DEG) * (p->ncp_v - Q2N_FIT_DEG);
        c[k] = p->ncp_u * p->ncp_v;
        rep->cp_total += c[k];
    }
    qsort(s, (size_t)md->n, sizeof(int), cmp_int);
    qsort(c, (size_t)md->n, sizeof(int), cmp_int);
    rep->spans_min = s[0];
    rep->spans_median = s[md->n / 2];
    rep->spans_max = s[md->n - 1];
    rep->cp_min = c[0];
    rep->cp_median = c[md->n / 2];
    rep->cp_max = c[md->n - 1];
    rep->edge_spans_max = 1;
    for (int e = 0; md->edges && e < md->mesh->ne; e++)
        if (md->edges[e].ncp - Q2N_FIT_DEG > rep->edge_spans_max) rep->edge_spans_max = md->edges[e].ncp - Q2N_FIT_DEG;
    free(s);
    free(c);
}
