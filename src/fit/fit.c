/* fit.c — bi-quintic B-spline fit of a composite surface: the entry point, the rounds and the
 * measurement between them (docs/fit.md has the long form).
 *
 * Every patch k becomes a clamped bi-quintic B-spline on [0,1]^2.  Knots are local (fit_state.h):
 * every mesh edge has its own knot vector, every patch its own interior knots, and a patch's knots
 * in u (v) are the union of its two u-edges' (v-edges') knots and its interior ones; the boundary
 * curve of an edge is fitted once and each patch boundary is that curve by knot insertion.  A round
 * (fit_stages.c) fits the curves, corners, cross rows (fit_glue.c: exact G1/G2 constraints where the
 * gluing data allow) and interiors (fit_interior.c) of what changed; the measurement below finds,
 * per check cell and per edge check point, where the fit misses; fit_refine.c bisects the spans there.  Rounds
 * stop when nothing needs refining, at max_rounds, or at the span caps.  Bézier patches are
 * converted exactly instead (fit_bezier.c). */
#include "fit/fit.h"
#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/clock.h"
#include "core/vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void q2n_fit_options_default(q2n_fit_options *o)
{
    memset(o, 0, sizeof *o);
    o->tol = Q2N_FIT_TOL_DEFAULT;
    o->continuity = 1;
    o->threads = 1;
    o->solver = Q2N_FIT_SOLVER_CERES;
    o->max_spans = Q2N_FIT_MAX_SPANS_DEFAULT;
    o->max_rounds = 0; /* automatic: fit_all */
    o->g1_weight = Q2N_FIT_G1_WEIGHT_DEFAULT;
}

double q2n_fit_default_target(double tol, double base, double cap)
{
    double f = tol > Q2N_FIT_TOL_DEFAULT ? tol / Q2N_FIT_TOL_DEFAULT : 1.0;
    return base * f < cap ? base * f : cap;
}

static void fill_defaults(q2n_fit_options *o, const q2n_fit_options *in)
{
    q2n_fit_options d;
    q2n_fit_options_default(&d);
    *o = in ? *in : d;
    if (o->tol <= 0) o->tol = d.tol;
    if (o->continuity != 2) o->continuity = 1;
    if (o->threads <= 0) o->threads = d.threads;
    if (o->threads > Q2N_FIT_MAX_THREADS) o->threads = Q2N_FIT_MAX_THREADS;
    if (o->max_spans <= 0) o->max_spans = d.max_spans;
    if (o->g1_weight <= 0) o->g1_weight = d.g1_weight;
}

/* ------------------------------------------------------------------ measurement of a round */

static q2n_bspline_surface patch_view(const fit_patch *p)
{
    q2n_bspline_surface b = {Q2N_FIT_DEG, Q2N_FIT_DEG, p->nu, p->nv, p->ku, p->kv, p->cp, NULL};
    return b;
}

/* Share of the u and v directions in patch k's error around (u, v): 6th differences of the
 * construction with steps of an eighth of the local spans in each direction (the quintic error term
 * is ~ h^6 |d^6 S| per direction, and these differences are exactly (h/8)^6 d^6 S). */
static void direction_shares(fit_ctx *c, int k, double u, double v, double share[2])
{
    const fit_patch *p = &c->p[k];
    int su = q2n_fit_span(p->nu, p->ku, u), sv = q2n_fit_span(p->nv, p->kv, v);
    double h[2] = {(p->ku[su + 1] - p->ku[su]) / 8.0, (p->kv[sv + 1] - p->kv[sv]) / 8.0}, e6[2] = {0, 0};
    static const double bin[7] = {1, -6, 15, -20, 15, -6, 1};
    for (int d = 0; d < 2; d++) {
        double x0 = (d ? v : u) - 3 * h[d];
        if (x0 < 0) x0 = 0;
        if (x0 + 6 * h[d] > 1) x0 = 1 - 6 * h[d];
        double acc[3] = {0, 0, 0}, xs[7], S[7][3];
        for (int q = 0; q < 7; q++) xs[q] = x0 + q * h[d];
        /* the seven points as a 7 x 1 (1 x 7) grid: one line across, seven along */
        if (d ? q2n_fit_target_grid(c, k, 1, &u, 7, xs, &S[0][0]) : q2n_fit_target_grid(c, k, 7, xs, 1, &v, &S[0][0])) {
            share[0] = share[1] = 0.5;
            return;
        }
        for (int q = 0; q < 7; q++) q2n_v3_axpy(acc, bin[q], S[q]);
        e6[d] = q2n_v3_norm(acc);
    }
    double tot = e6[0] + e6[1];
    share[0] = tot > 0 ? e6[0] / tot : 0.5;
    share[1] = tot > 0 ? e6[1] / tot : 0.5;
}

typedef struct meas_arg {
    fit_ctx *c;
    q2n_status *st;
    long *evals;
} meas_arg;

static void measure_patch(void *arg, int k)
{
    meas_arg *a = arg;
    fit_ctx *c = a->c;
    fit_patch *p = &c->p[k];
    if (!p->dirty) return;
    int ncu = p->mu * Q2N_FIT_SAMPLES_PER_SPAN, ncv = p->mv * Q2N_FIT_SAMPLES_PER_SPAN;
    double *cu = malloc(sizeof(double) * (size_t)ncu), *cv = malloc(sizeof(double) * (size_t)ncv);
    double *S = malloc(3 * sizeof(double) * (size_t)ncu * ncv);
    free(p->cell);
    p->cell = malloc(sizeof(double) * (size_t)ncu * ncv);
    if (!cu || !cv || !S || !p->cell) { free(cu); free(cv); free(S); a->st[k] = Q2N_ERR_NOMEM; return; }
    p->ncu = q2n_fit_check_params(p->nu, p->ku, Q2N_FIT_SAMPLES_PER_SPAN, cu);
    p->ncv = q2n_fit_check_params(p->nv, p->kv, Q2N_FIT_SAMPLES_PER_SPAN, cv);
    q2n_status st = q2n_fit_patch_grid(c, k, ncu, cu, ncv, cv, S, &a->evals[k]);
    q2n_bspline_surface b = patch_view(p);
    double *F = st ? NULL : malloc(3 * sizeof(double) * (size_t)ncu * ncv);
    if (!st && (!F || q2n_fit_surface_grid(&b, ncu, cu, ncv, cv, F))) st = Q2N_ERR_NOMEM;
    double dev = 0.0, s2 = 0.0;
    int wi = 0, wj = 0;
    for (int j = 0; !st && j < ncv; j++)
        for (int i = 0; i < ncu; i++) {
            const double *f = F + 3 * ((size_t)j * ncu + i);
            double d = q2n_v3_dist(f, S + 3 * ((size_t)j * ncu + i)) / c->diag;
            p->cell[(size_t)j * ncu + i] = d;
            s2 += d * d;
            if (!(d <= dev)) { dev = d; wi = i; wj = j; }
        }
    p->dev = dev;
    p->s2 = s2;
    p->share[0] = p->share[1] = 0.5;
    if (!st && dev > c->o.tol) direction_shares(c, k, cu[wi], cv[wj], p->share);
    free(cu); free(cv); free(S); free(F);
    a->st[k] = st;
}

/* Is the side frame F (S, d_t, d_s, ...) far enough from singular for its normal and curvature to
 * mean something: the angle between its tangents at least Q2N_FIT_JUMP_MIN_SIN (sine)? */
static int fit_regular_frame(const double F[6][3])
{
    double n[3];
    q2n_v3_cross(n, F[1], F[2]);
    return q2n_v3_norm(n) >= Q2N_FIT_JUMP_MIN_SIN * q2n_v3_norm(F[1]) * q2n_v3_norm(F[2]);
}

/* Keep the larger of each jump (NaN-safe: a NaN jump is kept, as a failure to see) in the edge-wide
 * maxima g1, g2 and in those of its span, mx. */
static void keep_jumps(double j1, double j2, double *g1, double *g2, double *mx)
{
    if (!(j1 <= *g1)) *g1 = j1;
    if (!(j2 <= *g2)) *g2 = j2;
    if (!(j1 <= mx[FIT_SPMAX_G1])) mx[FIT_SPMAX_G1] = j1;
    if (!(j2 <= mx[FIT_SPMAX_G2])) mx[FIT_SPMAX_G2] = j2;
}

/* The fitted jumps of edge E between its check points: at least Q2N_FIT_JUMP_SAMPLES evenly spaced
 * points per span of the union of both sides' knots along the edge and Q2N_FIT_JUMP_SAMPLES_EDGE per
 * unit of its parameter, the knots included (the fitted sides only: no construction values).  The
 * check points (4 per span of the edge's knots, the points an importer's audit samples) miss the
 * maxima by up to ~3 x (docs/fit.md); these see them.  Both sides are polynomials on such a span:
 * their rows are expanded once per span (about its start in each side's own parameter) and summed
 * by Horner's rule at the points — a tenth of a B-spline evaluation per point (the same values to
 * rounding).  The maxima are kept per span of the edge's own knots too (spmax: which spans miss). */
static q2n_status dense_jumps(const fit_ctx *c, fit_edge *E, const fit_side sd[2])
{
    int nb = 0, n0 = sd[0].nt - 4, n1 = sd[1].nt - 4;    /* breakpoints incl. 0 and 1 */
    double *brk = malloc(sizeof(double) * (size_t)(n0 + n1));
    if (!brk) return Q2N_ERR_NOMEM;
    for (int i = 0, j = 0; i < n0 || j < n1;) {
        double a = i < n0 ? sd[0].kt[5 + i] : 2.0, b = j < n1 ? 1.0 - sd[1].kt[sd[1].nt - j] : 2.0, x = a <= b ? a : b;
        if (a <= b) i++;
        if (b <= a) j++;
        if (!nb || brk[nb - 1] != x) brk[nb++] = x;
    }
    double Ns[2][3][Q2N_FIT_DEG + 1];
    for (int x = 0; x < 2; x++) q2n_fit_basis(Q2N_FIT_DEG, sd[x].ks, 0.0, 2, Ns[x]);
    int ks = 0;   /* the span of the edge's own knots K that span s of the union lies in */
    for (int s = 0; s + 1 < nb; s++) {
        while (ks < E->K.n && E->K.t[ks] <= brk[s]) ks++;
        double *mx = E->spmax + FIT_SPMAX * (size_t)ks;
        int ns = (int)ceil(Q2N_FIT_JUMP_SAMPLES_EDGE * (brk[s + 1] - brk[s]));
        if (ns < Q2N_FIT_JUMP_SAMPLES) ns = Q2N_FIT_JUMP_SAMPLES;
        /* L's parameter t runs from brk[s] to brk[s + 1]; R's, 1 - t, from 1 - brk[s + 1] to 1 - brk[s] */
        q2n_fit_side_poly C[2];
        double t0[2] = {brk[s], 1.0 - brk[s + 1]};
        q2n_fit_side_poly_at(c, &sd[0], t0[0], C[0]);
        q2n_fit_side_poly_at(c, &sd[1], t0[1], C[1]);
        for (int q = 0; q <= ns; q++) {
            if (q == ns && s + 2 < nb) continue;   /* the next span's first point */
            double t = brk[s] + (brk[s + 1] - brk[s]) * q / ns, f[2][6][3], j1, j2;
            q2n_fit_side_poly_frame(C[0], Ns[0], t - t0[0], f[0]);
            q2n_fit_side_poly_frame(C[1], Ns[1], (1.0 - t) - t0[1], f[1]);
            if (!fit_regular_frame(f[0]) || !fit_regular_frame(f[1])) continue;
            q2n_fit_jumps(f[0][0], f[1][0], f[0][1], c->diag, &j1, &j2);
            keep_jumps(j1, j2, &E->g1d, &E->g2d, mx);
        }
    }
    free(brk);
    return Q2N_OK;
}

/* Edge e: at the check points of its owner side, the curve's deviation, both cross rows' deviation
 * in position terms (a first-row error df moves the surface by at most ~0.41 df / N_1'(0), the
 * peak of the first Bernstein function times the row's offset; likewise the second row with
 * N_2''(0)), and the fitted gap and jumps. */
static void measure_edge(void *arg, int e)
{
    meas_arg *a = arg;
    fit_ctx *c = a->c;
    fit_edge *E = &c->e[e];
    fit_side sd[2];
    int two = q2n_fit_edge_sides(c, e, &sd[0], &sd[1]);
    if (!c->p[sd[0].k].dirty && !(two && c->p[sd[1].k].dirty)) return;
    /* the check points of the edge's own knots: the edge curve written to STEP/IGES has exactly
     * these knots, so an importer can sample the same points (tools/q2n_audit.py) */
    int n = (E->K.n + 1) * Q2N_FIT_SAMPLES_PER_SPAN;
    double *t = malloc(sizeof(double) * (size_t)n), *tr = malloc(sizeof(double) * (size_t)n);
    double *kv = malloc(sizeof(double) * (size_t)(E->K.n + 12));
    double *DL = malloc(18 * sizeof(double) * (size_t)n), *DR = malloc(18 * sizeof(double) * (size_t)n);
    free(E->spmax);
    E->spmax = calloc(FIT_SPMAX * (size_t)(E->K.n + 1), sizeof(double));
    E->nspmax = E->spmax ? E->K.n + 1 : 0;
    if (!t || !tr || !DL || !DR || !E->spmax || !kv) {
        free(t); free(tr); free(DL); free(DR); free(kv);
        a->st[e] = Q2N_ERR_NOMEM;
        return;
    }
    q2n_fit_knots_from_breaks(E->K.n, E->K.t, kv);
    n = q2n_fit_check_params(E->K.n + 6, kv, Q2N_FIT_SAMPLES_PER_SPAN, t);
    free(kv);
    for (int q = 0; q < n; q++) tr[q] = 1.0 - t[n - 1 - q];
    q2n_status st = q2n_fit_side_values(c, sd[0].k, sd[0].i, n, t, DL);
    if (!st && two) st = q2n_fit_side_values(c, sd[1].k, sd[1].i, n, tr, DR);
    E->nchk = st ? 0 : n;
    E->g0 = E->g1 = E->g2 = 0.0;
    double Ns[2][3][Q2N_FIT_DEG + 1];
    for (int x = 0; x < 1 + two; x++) q2n_fit_basis(Q2N_FIT_DEG, sd[x].ks, 0.0, 2, Ns[x]);
    int sp = 0;
    for (int q = 0; !st && q < n; q++) {
        /* the fitted sides in their own frames (S, ∂t, ∂s, ∂tt, ∂ts, ∂ss): a rotation of the
         * patches' (u, v), so normals and normal curvatures are those of q2n_fit_measure */
        double f[2][6][3], row = 0.0;
        for (int x = 0; x < 1 + two; x++) {
            double (*F)[3] = f[x];
            q2n_fit_side_spline(c, &sd[x], Ns[x], x ? 1.0 - t[q] : t[q], F);
            const double *D = x ? DR + 18 * (size_t)(n - 1 - q) : DL + 18 * (size_t)q;
            double ds[3], dss[3];
            for (int r = 0; r < 3; r++) {
                ds[r] = F[2][r] - D[6 + r];
                dss[r] = F[5][r] - D[15 + r];
            }
            double r1 = 0.41 * q2n_v3_norm(ds) / fabs(Ns[x][1][1]);
            double r2 = c->o.continuity == 2 ? 0.41 * q2n_v3_norm(dss) / fabs(Ns[x][2][2]) : 0.0;
            row = fmax(row, fmax(r1, r2));
        }
        /* the span of K the check point lies in (a point on a knot belongs to the span after it;
         * the check parameters ascend, so the span only moves forward) */
        while (sp < E->K.n && E->K.t[sp] <= t[q]) sp++;
        double dev = q2n_v3_dist(f[0][0], DL + 18 * (size_t)q) / c->diag, rdev = row / c->diag;
        double *mx = E->spmax + FIT_SPMAX * (size_t)sp;
        if (dev > mx[FIT_SPMAX_DEV]) mx[FIT_SPMAX_DEV] = dev;
        if (rdev > mx[FIT_SPMAX_ROW]) mx[FIT_SPMAX_ROW] = rdev;
        if (two) {   /* the tangent of the fitted side, as q2n_fit_measure and the audit use */
            double j1, j2;
            q2n_fit_jumps(f[0][0], f[1][0], f[0][1], c->diag, &j1, &j2);
            double gap = q2n_v3_dist(f[0][0], f[1][0]) / c->diag;
            if (gap > E->g0) E->g0 = gap;
            keep_jumps(j1, j2, &E->g1, &E->g2, mx);
        }
    }
    E->g1d = E->g1;
    E->g2d = E->g2;
    /* exact relations hold to rounding everywhere: only least-squares ones vary between the points,
     * and only those whose check points come near the aim need the samples between them */
    double near1 = Q2N_FIT_JUMP_DENSE_FROM * Q2N_FIT_REFINE_AIM * c->o.g1_tol_deg;
    double near2 = Q2N_FIT_JUMP_DENSE_FROM * Q2N_FIT_REFINE_AIM * c->o.g2_tol_rel;
    if (!st && two && q2n_fit_edge_ls(c, E) && (E->g1 > near1 || (c->o.continuity == 2 && E->g2 > near2)))
        st = dense_jumps(c, E, sd);
    free(t); free(tr); free(DL); free(DR);
    a->st[c->m->nf + e] = st;
}

static q2n_status measure_round(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    q2n_status *st = calloc((size_t)(m->nf + m->ne) + 1, sizeof *st);
    long *ev = calloc((size_t)m->nf + 1, sizeof *ev);
    if (!st || !ev) { free(st); free(ev); return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); }
    double t0 = q2n_now();
    char what[64];
    snprintf(what, sizeof what, "round %d: measuring", c->round + 1);
    q2n_progress_emit(c->o.progress, "fit", what, 0, 0);
    meas_arg arg = {c, st, ev};
    q2n_par_for(m->nf, c->o.threads, measure_patch, &arg);
    q2n_par_for(m->ne, c->o.threads, measure_edge, &arg);
    c->rep->t_measure += q2n_now() - t0;
    q2n_status r = Q2N_OK;
    for (int k = 0; k < m->nf; k++) {
        c->rep->checks += ev[k];
        if (st[k] && !r)
            r = q2n_error_set(c->err, st[k], "fit: face %d: %s", k,
                              st[k] == Q2N_ERR_NOMEM ? "out of memory (measure)" : "construction evaluation failed");
    }
    for (int e = 0; e < m->ne && !r; e++)
        if (st[m->nf + e])
            r = q2n_error_set(c->err, st[m->nf + e], "fit: edge %d: %s", e,
                              st[m->nf + e] == Q2N_ERR_NOMEM ? "out of memory (measure)" : "construction evaluation failed");
    free(st);
    free(ev);
    return r;
}

/* ------------------------------------------------------------------ model and report */

/* Copy the fitted patches and edge curves into a model. */
static q2n_status make_model(fit_ctx *c, q2n_nurbs_model **out)
{
    const q2n_mesh *m = c->m;
    q2n_nurbs_model *md = calloc(1, sizeof *md);
    if (!md) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (model)");
    md->n = m->nf;
    md->mesh = m;
    md->tol_abs = c->o.tol * c->diag;
    md->patches = calloc((size_t)md->n, sizeof *md->patches);
    md->edges = calloc((size_t)m->ne, sizeof *md->edges);
    if (!md->patches || !md->edges) goto oom;
    for (int k = 0; k < md->n; k++) {
        fit_patch *p = &c->p[k];
        q2n_bspline_surface *b = &md->patches[k];
        b->deg_u = b->deg_v = Q2N_FIT_DEG;
        b->ncp_u = p->nu; b->ncp_v = p->nv;
        /* the fit is over: its arrays move into the model (no copy at the peak) */
        b->knots_u = p->ku; p->ku = NULL;
        b->knots_v = p->kv; p->kv = NULL;
        b->cp = p->cp; p->cp = NULL;
        if (!b->knots_u || !b->knots_v || !b->cp) goto oom;
    }
    for (int e = 0; e < m->ne; e++) {
        fit_edge *E = &c->e[e];
        q2n_bspline_curve *cv = &md->edges[e];
        cv->deg = Q2N_FIT_DEG;
        cv->ncp = E->n;
        cv->knots = malloc(sizeof(double) * (size_t)(E->n + 6));
        cv->cp = E->cp;
        E->cp = NULL;
        if (!cv->knots || !cv->cp) goto oom;
        q2n_fit_knots_from_breaks(E->K.n, E->K.t, cv->knots);
    }
    *out = md;
    return Q2N_OK;
oom:
    q2n_nurbs_model_free(md);
    return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (model)");
}

/* The report's measured fields from the last measurement of every patch and edge. */
static void report_totals(fit_ctx *c, const q2n_nurbs_model *md)
{
    const q2n_mesh *m = c->m;
    q2n_fit_report *rep = c->rep;
    double maxd = 0, s2 = 0, vd = 0;
    long ncell = 0;
    for (int k = 0; k < m->nf; k++) {
        const fit_patch *p = &c->p[k];
        if (!(p->dev <= maxd)) maxd = p->dev;
        s2 += p->s2;
        ncell += (long)p->ncu * p->ncv;
        for (int i = 0; i < 4; i++) {   /* construction corners vs mesh vertices */
            double S[Q2N_EVAL_MAX];
            if (q2n_surface_eval(c->s, k, q2n_corner_uv[i][0], q2n_corner_uv[i][1], 0, S)) continue;
            double d = q2n_v3_dist(S, q2n_mesh_vpos(m, m->face_vert[m->face_start[k] + i])) / c->diag;
            if (d > vd) vd = d;
        }
    }
    rep->max_dev_rel = maxd;
    rep->rms_dev_rel = ncell ? sqrt(s2 / (double)ncell) : 0.0;
    rep->vertex_dev_max_rel = vd;
    rep->g0_max_rel = rep->g1_max_deg = rep->g2_max_rel = 0.0;
    rep->g1_construction_deg = rep->g2_construction_rel = 0.0;
    rep->g1_exact_edges = rep->g1_ls_edges = rep->g1_rounding_edges = 0;
    for (int e = 0; e < m->ne; e++) {
        const fit_edge *E = &c->e[e];
        if (E->glue == FIT_GLUE_BOUNDARY) continue;
        rep->g1_exact_edges += E->glue == FIT_GLUE_EXACT;
        rep->g1_ls_edges += E->glue == FIT_GLUE_LS;
        rep->g1_rounding_edges += E->g1 <= Q2N_FIT_G1_ROUNDING_DEG;
        if (E->g0 > rep->g0_max_rel) rep->g0_max_rel = E->g0;
        if (!(E->g1 <= rep->g1_max_deg)) rep->g1_max_deg = E->g1;
        if (!(E->g2 <= rep->g2_max_rel)) rep->g2_max_rel = E->g2;
        if (E->g1c > rep->g1_construction_deg) rep->g1_construction_deg = E->g1c;
        if (E->g2c > rep->g2_construction_rel) rep->g2_construction_rel = E->g2c;
    }
    q2n_fit_report_rim(md, c->s, rep);
    q2n_fit_report_sizes(md, rep);
}

/* Free what only the rounds need (construction caches, measurement cells, work arrays); called
 * before the model takes the fitted arrays, and by ctx_free. */
static void free_round_state(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    for (int k = 0; c->p && k < m->nf; k++) {
        fit_patch *p = &c->p[k];
        free(p->gc.u); free(p->gc.v); free(p->gc.val); free(p->gc.have);
        memset(&p->gc, 0, sizeof p->gc);
        q2n_fit_patch_free_reversed(p);
        free(p->cell); free(p->var);   /* var's block holds fixed */
        p->cell = NULL; p->fixed = NULL; p->var = NULL;
    }
    for (int e = 0; c->e && e < m->ne; e++) {
        free(c->e[e].spmax);
        c->e[e].spmax = NULL;
        free(c->e[e].av);
        c->e[e].av = NULL;
        c->e[e].an = c->e[e].acap = 0;
    }
    for (int q = 0; c->sc && q < 4 * m->nf; q++) {
        free(c->sc[q].v);
        memset(&c->sc[q], 0, sizeof c->sc[q]);
    }
    atomic_store(&c->cache_bytes, 0);
    atomic_store(&c->alpha_bytes, 0);
    q2n_fit_pinv_free(&c->pinv);
}

static void ctx_free(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    free_round_state(c);
    for (int k = 0; c->p && k < m->nf; k++) {
        fit_patch *p = &c->p[k];
        q2n_fit_breaks_free(&p->I[0]);
        q2n_fit_breaks_free(&p->I[1]);
        free(p->ku); free(p->kv); free(p->cp);
    }
    for (int e = 0; c->e && e < m->ne; e++) {
        q2n_fit_breaks_free(&c->e[e].K);
        free(c->e[e].cp);
    }
    for (int e = 0; c->e && e < c->amu_n; e++) pthread_mutex_destroy(&c->e[e].amu);
    free(c->p);
    free(c->e);
    free(c->sc);
    free(c->jet);
    free(c->vpos);
    q2n_fit_ls_free(&c->ls);
}

static q2n_status fit_all(fit_ctx *c, q2n_nurbs_model **out)
{
    const q2n_mesh *m = c->m;
    q2n_fit_report *rep = c->rep;
    c->p = calloc((size_t)m->nf, sizeof *c->p);
    c->e = calloc((size_t)m->ne, sizeof *c->e);
    c->sc = calloc(4 * (size_t)m->nf, sizeof *c->sc);
    atomic_init(&c->cache_bytes, 0);
    atomic_init(&c->alpha_bytes, 0);
    if (!c->p || !c->e || !c->sc) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    for (int e = 0; e < m->ne; e++) {
        c->e[e].fitted = -1;
        if (pthread_mutex_init(&c->e[e].amu, NULL)) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of resources (mutex)");
        c->amu_n = e + 1;
    }
    if (c->o.max_rounds <= 0) { /* automatic: the depth's rounds and a wave around the highest valence */
        int vmax = 0;
        for (int v = 0; v < m->nv; v++) vmax = m->valence[v] > vmax ? m->valence[v] : vmax;
        c->o.max_rounds = Q2N_FIT_MAX_ROUNDS_DEFAULT + vmax;
    }
    q2n_status st = q2n_fit_glue_measure(c);
    if (!st) st = q2n_fit_target_setup(c);
    if (!st) st = q2n_fit_prepare(c);
    if (!st) st = q2n_fit_glue_classify(c);
    for (int round = 0; !st; round++) {
        c->round = round;
        if ((st = q2n_fit_round(c)) || (st = measure_round(c))) break;
        rep->rounds = round + 1;
        if (round + 1 >= c->o.max_rounds) break;
        double t0 = q2n_now();
        int added = q2n_fit_refine(c);
        rep->t_build += q2n_now() - t0;
        if (!added) break;
    }
    if (st) return st;
    free_round_state(c); /* before the model takes the fitted arrays: the peak */
    if ((st = make_model(c, out))) return st;
    report_totals(c, *out);
    q2n_fit_accept(c);
    if (!rep->dev_met) {
        int worst = 0;
        for (int k = 1; k < m->nf; k++)
            if (c->p[k].dev > c->p[worst].dev) worst = k;
        /* say whether the construction itself is to blame: a derivative far above its median on
         * the patch is a feature narrower than any knot spacing (docs/fit.md, Limits) */
        double ratio = 1.0, su = 0.0, sv = 0.0, dmax = 0.0;
        char why[320] = "";
        if (!q2n_fit_scan_construction(c->s, worst, Q2N_FIT_SCAN_N, &ratio, &su, &sv, &dmax) &&
            !(ratio <= Q2N_FIT_SPIKE_RATIO))
            snprintf(why, sizeof why,
                     "; the construction is not smooth there: |dS| = %.3g at (u %.3f, v %.3f) is %.3g x its "
                     "median on the face (a spike narrower than any knot spacing: a near-degenerate face nearby? "
                     "--subdivide 1 smooths the mesh first)", dmax, su, sv, ratio);
        char where[300], par[56];
        q2n_mesh_face_where(m, worst, where, sizeof where);
        q2n_mesh_of(m, 1, par, sizeof par);
        st = q2n_error_set(c->err, Q2N_ERR_GEOMETRY,
                           "fit: %s: face %d%s: deviation %.3g (relative) > tol %.3g with %d x %d spans (max_spans %d)%s",
                           where, worst, par, c->p[worst].dev, c->o.tol, c->p[worst].mu, c->p[worst].mv,
                           c->o.max_spans, why);
    }
    return st;
}

/* ------------------------------------------------------------------ entry point */

q2n_status q2n_fit_surface(const q2n_surface *s, const q2n_mesh *m, const q2n_fit_options *opt,
                           q2n_nurbs_model **out, q2n_fit_report *rep_out, q2n_error *err)
{
    if (out) *out = NULL;
    if (!s || !m || !out) return q2n_error_set(err, Q2N_ERR_ARG, "fit: NULL argument");
    if (q2n_surface_npatches(s) != m->nf)
        return q2n_error_set(err, Q2N_ERR_ARG, "fit: surface has %d patches for %d faces", q2n_surface_npatches(s), m->nf);
    if (!m->all_quads) return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "fit: mesh %s has non-quad faces", m->name);
    int nbez = q2n_surface_count(s, Q2N_PATCH_BEZIER);
    for (int k = 0; k < m->nf; k++) {
        q2n_patch_kind kd = q2n_surface_kind(s, k);
        if (kd == Q2N_PATCH_UNCOVERED) return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "fit: face %d has no patch", k);
        if (nbez && nbez < m->nf && kd == Q2N_PATCH_BEZIER)
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                                 "fit: face %d is Bézier but %d other faces are not (mixed surfaces unsupported)", k,
                                 m->nf - nbez);
    }
    q2n_fit_report rep;
    memset(&rep, 0, sizeof rep);
    fit_ctx c;
    memset(&c, 0, sizeof c);
    c.s = s; c.m = m; c.err = err; c.rep = &rep;
    fill_defaults(&c.o, opt);
    c.diag = q2n_mesh_bbox_diag(m);
    if (c.o.tol_abs > 0 && c.diag > 0) c.o.tol = c.o.tol_abs / c.diag;
    if (c.o.g1_tol_deg <= 0)
        c.o.g1_tol_deg = q2n_fit_default_target(c.o.tol, Q2N_FIT_G1_TARGET_DEFAULT, Q2N_FIT_G1_TARGET_CAP);
    if (c.o.g2_tol_rel <= 0)
        c.o.g2_tol_rel = q2n_fit_default_target(c.o.tol, Q2N_FIT_G2_TARGET_DEFAULT, Q2N_FIT_G2_TARGET_CAP);
    q2n_fit_ls_init(&c.ls);
    c.pinv.budget = (long)Q2N_FIT_PINV_CACHE_BYTES;
    double t0 = q2n_now();
    q2n_status st = nbez == m->nf ? q2n_fit_convert_bezier(s, m, &c.o, out, &rep, err) : fit_all(&c, out);
    rep.t_total = q2n_now() - t0;
    rep.faces = m->nf;
    rep.edges = m->ne;
    for (int e = 0; e < m->ne; e++) rep.interior_edges += m->he_twin[m->edge_he[e]] >= 0;
    rep.continuity = c.o.continuity;
    rep.tol = c.o.tol;
    rep.diag = c.diag;
    rep.tol_abs = c.o.tol * c.diag;
    rep.g1_tol_deg = c.o.g1_tol_deg;
    rep.g2_tol_rel = c.o.g2_tol_rel;
    rep.solver = c.o.solver;
    rep.threads = c.o.threads;
    if (rep_out) *rep_out = rep;
    ctx_free(&c);
    if (st && st != Q2N_ERR_GEOMETRY && *out) {
        q2n_nurbs_model_free(*out);
        *out = NULL;
    }
    return st;
}
