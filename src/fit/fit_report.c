/* fit_report.c — measurement of a fitted model against its construction, and the JSON report.
 *
 * Deviation: at the midpoints of each patch's fit-sample grid (never fit samples).  Continuity
 * across every interior edge, at the midpoints of the edge's fit samples: G0 gap between the two
 * fitted sides, normal-angle jump (G1), and normal-curvature jump (G2) in three tangent directions
 * (along the edge, across it, and at 45 degrees — together they determine the second fundamental
 * form), relative to the local curvature scale max(|kappa|, 1/diag). */
#include "fit/fit.h"
#include "fit/fit_internal.h"
#include "core/outfile.h"
#include "core/vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FIT_PI 3.14159265358979323846
#define FIT_SQRT1_2 0.70710678118654752440

double fit_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const int corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

/* (u,v) of parameter t along side i of a patch (t runs from corner i to corner i+1). */
static void side_uv(int i, double t, double *u, double *v)
{
    const int *c0 = corner_uv[i], *c1 = corner_uv[(i + 1) & 3];
    *u = c0[0] + t * (c1[0] - c0[0]);
    *v = c0[1] + t * (c1[1] - c0[1]);
}

/* Normal-curvature of a surface (derivatives d[18], unit normal n) in the tangent direction
 * closest to w: w = a Su + b Sv in the least-squares sense, kappa = II(a,b) / I(a,b). */
static double normal_curvature(const double *d, const double n[3], const double w[3])
{
    const double *Su = d + Q2N_EV_U, *Sv = d + Q2N_EV_V;
    double E = q2n_v3_dot(Su, Su), F = q2n_v3_dot(Su, Sv), G = q2n_v3_dot(Sv, Sv);
    double pu = q2n_v3_dot(w, Su), pv = q2n_v3_dot(w, Sv), det = E * G - F * F;
    double a = (G * pu - F * pv) / det, b = (E * pv - F * pu) / det;
    double L = q2n_v3_dot(d + Q2N_EV_UU, n), M = q2n_v3_dot(d + Q2N_EV_UV, n), N = q2n_v3_dot(d + Q2N_EV_VV, n);
    double I = a * a * E + 2 * a * b * F + b * b * G;
    return (a * a * L + 2 * a * b * M + b * b * N) / I;
}

static void unit_normal(const double *d, double n[3])
{
    q2n_v3_cross(n, d + Q2N_EV_U, d + Q2N_EV_V);
    double l = q2n_v3_norm(n);
    q2n_v3_scale(n, 1.0 / l, n);
}

/* Angle (degrees) and relative curvature jump between two sides' derivative sets at one edge
 * point; T = tangent along the edge; diag sets the curvature floor. */
static void jumps(const double *dL, const double *dR, const double T[3], double diag, double *g1, double *g2)
{
    double nL[3], nR[3], c[3];
    unit_normal(dL, nL);
    unit_normal(dR, nR);
    q2n_v3_cross(c, nL, nR);
    *g1 = atan2(q2n_v3_norm(c), q2n_v3_dot(nL, nR)) * (180.0 / FIT_PI);
    double t[3], x[3], w[3];
    q2n_v3_scale(t, 1.0 / q2n_v3_norm(T), T);
    q2n_v3_cross(x, nL, t);
    double jmax = 0.0, kmax = 1.0 / diag;
    for (int k = 0; k < 3; k++) {
        for (int c3 = 0; c3 < 3; c3++)
            w[c3] = k == 0 ? t[c3] : k == 1 ? x[c3] : (t[c3] + x[c3]) * FIT_SQRT1_2;
        double kl = normal_curvature(dL, nL, w), kr = normal_curvature(dR, nR, w);
        if (fabs(kl - kr) > jmax) jmax = fabs(kl - kr);
        if (fabs(kl) > kmax) kmax = fabs(kl);
        if (fabs(kr) > kmax) kmax = fabs(kr);
    }
    *g2 = jmax / kmax;
}

/* Continuity of one interior edge at the midpoints of its samples; eval() of either the fitted
 * model (fit == 1) or the construction. */
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
    int mt = ((iL & 1) ? pL->ncp_v : pL->ncp_u) - FIT_DEG;
    int N = fit_nsamples(mt > 0 ? mt : 1);
    for (int k = 0; k + 1 < N; k++) {
        double t = (k + 0.5) / (N - 1), uL, vL, uR, vR, dL[Q2N_EVAL_MAX], dR[Q2N_EVAL_MAX];
        side_uv(iL, t, &uL, &vL);
        side_uv(iR, 1.0 - t, &uR, &vR);
        if (fit) {
            fit_surface_eval(&model->patches[fL], uL, vL, 2, dL);
            fit_surface_eval(&model->patches[fR], uR, vR, 2, dR);
        } else {
            q2n_status st = q2n_surface_eval(s, fL, uL, vL, 2, dL);
            if (!st) st = q2n_surface_eval(s, fR, uR, vR, 2, dR);
            if (st) return st;
        }
        double T[3];
        const int *c0 = corner_uv[iL], *c1 = corner_uv[(iL + 1) & 3];
        for (int c = 0; c < 3; c++)
            T[c] = (c1[0] - c0[0]) * dL[Q2N_EV_U + c] + (c1[1] - c0[1]) * dL[Q2N_EV_V + c];
        double a, b, gap = q2n_v3_dist(dL, dR) / diag;
        jumps(dL, dR, T, diag, &a, &b);
        if (gap > *g0) *g0 = gap;
        if (a > *g1) *g1 = a;
        if (b > *g2) *g2 = b;
    }
    return Q2N_OK;
}

/* Per-item results of a measurement, filled by the workers and reduced in index order (so the
 * report does not depend on the thread count). */
typedef struct measure_job {
    const q2n_nurbs_model *model;
    const q2n_surface *s;
    double diag;
    int construction;          /* also measure the construction's own continuity */
    double *pd, *ps2, *pvd;    /* per patch: max deviation, sum of squares, corner-vertex gap */
    double *pdir;              /* per patch: u and v shares of the error estimate */
    double *eg[5];             /* per edge: g0, g1, g2 (fitted), g1, g2 (construction) */
    q2n_status *pst, *est;     /* per patch / edge status */
} measure_job;

/* Deviation of patch k at the midpoints of its sample grid. */
static void measure_patch(void *arg, int k)
{
    measure_job *j = arg;
    const q2n_bspline_surface *p = &j->model->patches[k];
    const q2n_mesh *m = j->model->mesh;
    int Nu = fit_nsamples(p->ncp_u - FIT_DEG), Nv = fit_nsamples(p->ncp_v - FIT_DEG);
    int nu = Nu - 1, nv = Nv - 1;
    double us[4 * FIT_MAX_SPANS + 4] = {0}, vs[4 * FIT_MAX_SPANS + 4] = {0};
    for (int i = 0; i < nu; i++) us[i] = (i + 0.5) / (Nu - 1);
    for (int jj = 0; jj < nv; jj++) vs[jj] = (jj + 0.5) / (Nv - 1);
    double *buf = malloc(9 * sizeof(double) * (size_t)nu * nv);
    if (!buf) { j->pst[k] = Q2N_ERR_NOMEM; return; }
    q2n_status st = q2n_surface_eval_grid(j->s, k, nu, us, nv, vs, buf);
    double pd = 0.0, s2 = 0.0, vd = 0.0;
    for (int b = 0; !st && b < nv; b++)
        for (int a = 0; a < nu; a++) {
            double f[3];
            fit_surface_eval(p, us[a], vs[b], 0, f);
            double d = q2n_v3_dist(f, buf + 9 * ((size_t)b * nu + a)) / j->diag;
            s2 += d * d;
            if (d > pd) pd = d;
        }
    /* Which direction limits the spline: the quintic error term is ~ h^6 |d^6 S| per direction;
     * 6th differences of the construction on the check grid give spacing^6 |d^6 S|, and the
     * ratio h / spacing = (Nu - 1) / m_u converts them to the knot spacing. */
    double e6[2] = {0, 0};
    for (int dir = 0; !st && dir < 2; dir++) {
        int n1 = dir ? nv : nu, n2 = dir ? nu : nv;
        static const double bin[7] = {1, -6, 15, -20, 15, -6, 1};
        for (int b = 0; b + 6 < n1; b++)
            for (int a = 0; a < n2; a++) {
                double d6[3] = {0, 0, 0};
                for (int q = 0; q <= 6; q++) {
                    size_t idx = dir ? (size_t)(b + q) * nu + a : (size_t)a * nu + b + q;
                    q2n_v3_axpy(d6, bin[q], buf + 9 * idx);
                }
                double v6 = q2n_v3_norm(d6);
                if (v6 > e6[dir]) e6[dir] = v6;
            }
        double ratio = (double)((dir ? Nv : Nu) - 1) / (dir ? p->ncp_v - FIT_DEG : p->ncp_u - FIT_DEG);
        e6[dir] *= pow(ratio, 6.0);
    }
    double tot = e6[0] + e6[1];
    j->pdir[2 * k] = tot > 0 ? e6[0] / tot : 0.5;
    j->pdir[2 * k + 1] = tot > 0 ? e6[1] / tot : 0.5;
    free(buf);
    for (int c = 0; !st && c < 4; c++) {   /* construction corners vs mesh vertices */
        double S[3];
        if ((st = q2n_surface_eval(j->s, k, corner_uv[c][0], corner_uv[c][1], 0, S))) break;
        double d = q2n_v3_dist(S, q2n_mesh_vpos(m, m->face_vert[m->face_start[k] + c])) / j->diag;
        if (d > vd) vd = d;
    }
    j->pst[k] = st;
    j->pd[k] = pd;
    j->ps2[k] = s2;
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

q2n_status fit_measure_model(const q2n_nurbs_model *model, const q2n_surface *s, q2n_fit_report *rep,
                             fit_measure_out *mo, int threads, q2n_error *err)
{
    const q2n_mesh *m = model->mesh;
    measure_job j;
    memset(&j, 0, sizeof j);
    j.model = model;
    j.s = s;
    j.diag = q2n_mesh_bbox_diag(m);
    j.construction = mo && mo->edge_g1_c;
    size_t nf = (size_t)model->n, ne = (size_t)m->ne;
    double *mem = calloc(5 * nf + 5 * ne, sizeof(double));
    q2n_status *sts = calloc(nf + ne, sizeof *sts);
    if (!mem || !sts) {
        free(mem);
        free(sts);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (measure)");
    }
    j.pd = mem; j.ps2 = mem + nf; j.pvd = mem + 2 * nf; j.pdir = mem + 3 * nf;
    for (int i = 0; i < 5; i++) j.eg[i] = mem + 5 * nf + i * ne;
    j.pst = sts; j.est = sts + nf;
    fit_par_for(model->n, threads, measure_patch, &j);
    fit_par_for(m->ne, threads, measure_edge, &j);
    for (size_t k = 0; k < nf; k++)
        if (j.pst[k]) {
            q2n_status st = j.pst[k];
            free(mem); free(sts);
            return q2n_error_set(err, st, "fit: face %zu: construction evaluation failed", k);
        }
    for (size_t e = 0; e < ne; e++)
        if (j.est[e]) {
            q2n_status st = j.est[e];
            free(mem); free(sts);
            return q2n_error_set(err, st, "fit: edge %zu: evaluation failed", e);
        }
    double maxd = 0, sum2 = 0, vdev = 0, g0 = 0, g1 = 0, g2 = 0, g1c = 0, g2c = 0;
    long nchk = 0;
    for (size_t k = 0; k < nf; k++) {
        const q2n_bspline_surface *p = &model->patches[k];
        nchk += (long)(fit_nsamples(p->ncp_u - FIT_DEG) - 1) * (fit_nsamples(p->ncp_v - FIT_DEG) - 1);
        sum2 += j.ps2[k];
        if (j.pd[k] > maxd) maxd = j.pd[k];
        if (j.pvd[k] > vdev) vdev = j.pvd[k];
        if (mo && mo->patch_dev) mo->patch_dev[k] = j.pd[k];
        if (mo && mo->patch_dir) {
            mo->patch_dir[2 * k] = j.pdir[2 * k];
            mo->patch_dir[2 * k + 1] = j.pdir[2 * k + 1];
        }
    }
    for (size_t e = 0; e < ne; e++) {
        if (j.eg[0][e] > g0) g0 = j.eg[0][e];
        if (j.eg[1][e] > g1) g1 = j.eg[1][e];
        if (j.eg[2][e] > g2) g2 = j.eg[2][e];
        if (mo && mo->edge_g1) mo->edge_g1[e] = j.eg[1][e];
        if (mo && mo->edge_g2) mo->edge_g2[e] = j.eg[2][e];
        if (j.construction) {
            mo->edge_g1_c[e] = j.eg[3][e];
            mo->edge_g2_c[e] = j.eg[4][e];
            if (j.eg[3][e] > g1c) g1c = j.eg[3][e];
            if (j.eg[4][e] > g2c) g2c = j.eg[4][e];
        }
    }
    free(mem);
    free(sts);
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
    return Q2N_OK;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

q2n_status fit_scan_construction(const q2n_surface *s, int k, int n, double *ratio, double *u, double *v,
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
        if (model->patches[k].deg_u != FIT_DEG || model->patches[k].deg_v != FIT_DEG ||
            model->patches[k].weights)
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "fit_measure: patch %d is not polynomial bi-quintic", k);
    double *g1c = malloc(sizeof(double) * (size_t)model->mesh->ne);
    double *g2c = malloc(sizeof(double) * (size_t)model->mesh->ne);
    if (!g1c || !g2c) { free(g1c); free(g2c); return q2n_error_set(err, Q2N_ERR_NOMEM, "fit_measure: out of memory"); }
    fit_measure_out mo = {NULL, NULL, NULL, NULL, g1c, g2c};
    q2n_status st = fit_measure_model(model, s, rep, &mo, threads, err);
    free(g1c);
    free(g2c);
    return st;
}

void q2n_fit_report_write_json_file(const q2n_fit_report *r, const char *units, FILE *f)
{
    static const char *solvers[] = {"ceres_dense_qr_per_block", "ceres_sparse_normal_cholesky", "direct_householder_qr"};
    fprintf(f, "{\n  \"stage\": \"fit\",\n  \"faces\": %d,\n  \"edges\": %d,\n  \"interior_edges\": %d,\n",
            r->faces, r->edges, r->interior_edges);
    fprintf(f, "  \"mode\": \"%s\",\n  \"continuity\": \"G%d\",\n  \"tol\": %.17g,\n  \"tol_met\": %s,\n",
            r->exact ? "exact_bezier_conversion" : "least_squares_fit", r->continuity, r->tol,
            r->tol_met ? "true" : "false");
    if (units) fprintf(f, "  \"units\": \"%s\",\n", units);
    fprintf(f, "  \"tol_abs\": %.17g,\n  \"bbox_diag\": %.17g,\n  \"g1_tol_deg\": %.6g,\n  \"g2_tol_rel\": %.6g,\n",
            r->tol_abs, r->diag, r->g1_tol_deg, r->g2_tol_rel);
    fprintf(f, "  \"dev_met\": %s,\n  \"g1_met\": %s,\n  \"g2_met\": %s,\n  \"note\": \"%s\",\n",
            r->dev_met ? "true" : "false", r->g1_met ? "true" : "false", r->g2_met ? "true" : "false", r->note);
    fprintf(f, "  \"degree\": [5, 5],\n  \"rounds\": %d,\n", r->rounds);
    fprintf(f, "  \"spans_per_patch\": {\"min\": %d, \"median\": %d, \"max\": %d},\n  \"ribbon_spans_max\": %d,\n",
            r->spans_min, r->spans_median, r->spans_max, r->ribbon_spans_max);
    fprintf(f, "  \"samples\": %ld,\n  \"check_points\": %ld,\n", r->samples, r->checks);
    fprintf(f, "  \"max_dev_rel\": %.6g,\n  \"rms_dev_rel\": %.6g,\n  \"vertex_dev_max_rel\": %.6g,\n",
            r->max_dev_rel, r->rms_dev_rel, r->vertex_dev_max_rel);
    fprintf(f, "  \"g0_max_rel\": %.6g,\n  \"g1_max_deg\": %.6g,\n  \"g2_max_rel\": %.6g,\n",
            r->g0_max_rel, r->g1_max_deg, r->g2_max_rel);
    fprintf(f, "  \"construction\": {\"g1_max_deg\": %.6g, \"g2_max_rel\": %.6g},\n", r->g1_construction_deg,
            r->g2_construction_rel);
    fprintf(f, "  \"solver\": \"%s\",\n  \"threads\": %d,\n",
            solvers[r->solver >= 0 && r->solver <= 2 ? r->solver : 0], r->threads);
    fprintf(f, "  \"timings_s\": {\"sample\": %.6f, \"build\": %.6f, \"solve\": %.6f, \"measure\": %.6f, "
               "\"total\": %.6f}\n}\n", r->t_sample, r->t_build, r->t_solve, r->t_measure, r->t_total);
}

q2n_status q2n_fit_report_write_json(const q2n_fit_report *r, const char *path, q2n_error *err)
{
    q2n_outfile of;
    q2n_status st = q2n_outfile_open(&of, path, err);
    if (st) return st;
    q2n_fit_report_write_json_file(r, NULL, of.f);
    return q2n_outfile_commit(&of, err);
}
