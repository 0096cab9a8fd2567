/* fit_refine.c — where the knots go: the refinement policy of the fit (thresholds in fit_policy.h).
 *
 * After each round the driver has measured, per patch, the deviation in every cell of its check
 * grid and, per edge, at the check points of its owner side: the edge curve's deviation, the cross
 * rows' deviation (in position terms) and the fitted normal and curvature jumps.  Refinement bisects
 * knot spans where the error is, so the knots grade towards it and never travel:
 *  - a cell over the tolerance bisects its patch's span(s) in the direction(s) that limit it (6th
 *    differences of the construction around the worst cell: the quintic error term is
 *    ~ h^6 |d^6 S| per direction) — an interior knot of that patch only;
 *  - an edge whose curve or cross rows are off bisects that span of the edge's own knots, which
 *    both neighbours (and only they) take up;
 *  - an edge whose G1 or G2 relation is least squares and misses half its target, where the
 *    construction itself meets that, bisects every span of its knots (that converges; grading
 *    towards the worst point did not next to extraordinary corners);
 * all within max_spans per patch direction.  A bisection halves h: the deviation falls ~64x, the
 * normal jump ~32x, the curvature jump ~16x per round where the construction is smooth. */
#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/clock.h"
#include "core/vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Spans of patch k in direction d, counting the knots added to it in this round. */
static int patch_spans(const fit_ctx *c, int k, int d) { return (d ? c->p[k].mv : c->p[k].mu) + c->p[k].pending[d]; }

/* Would breakpoint t (in side orientation of side i of patch k) be new in that patch? */
static int new_in_patch(const fit_ctx *c, int k, int i, double t)
{
    const fit_patch *p = &c->p[k];
    double x = i < 2 ? t : 1.0 - t;
    const double *kv = (i & 1) ? p->kv : p->ku;
    int n = (i & 1) ? p->nv : p->nu;
    for (int q = 6; q < n; q++)
        if (kv[q] == x) return 0;
    return 1;
}

/* Add breakpoint mid (owner orientation; the midpoint of one of its spans) to edge e unless a cap
 * forbids it; returns 1 when a knot was added. */
static int bisect_edge(fit_ctx *c, int e, double mid)
{
    fit_edge *E = &c->e[e];
    if (E->K.n + 1 >= c->o.max_spans) return 0;
    const q2n_mesh *m = c->m;
    int h[2] = {m->edge_he[e], m->he_twin[m->edge_he[e]]};
    for (int x = 0; x < 2; x++) {
        if (h[x] < 0) continue;
        int k = m->he_face[h[x]], i = h[x] - m->face_start[k];
        double ts = x ? 1.0 - mid : mid;
        if (new_in_patch(c, k, i, ts) && patch_spans(c, k, i & 1) >= c->o.max_spans) return 0;
    }
    int r = fit_breaks_add(&E->K, mid);
    if (r <= 0) return 0;
    E->ver++;
    for (int x = 0; x < 2; x++)
        if (h[x] >= 0) {
            int k = m->he_face[h[x]], i = h[x] - m->face_start[k];
            if (new_in_patch(c, k, i, x ? 1.0 - mid : mid)) c->p[k].pending[i & 1]++;
        }
    return 1;
}

/* Bisect patch k's span in direction d containing x; returns 1 when a knot was added. */
static int bisect_patch(fit_ctx *c, int k, int d, double x)
{
    fit_patch *p = &c->p[k];
    if (patch_spans(c, k, d) >= c->o.max_spans) return 0;
    const double *kv = d ? p->kv : p->ku;
    int n = d ? p->nv : p->nu;
    int s = q2n_fit_span(n, kv, x);
    double mid = 0.5 * (kv[s] + kv[s + 1]);
    if (!(mid > kv[s] && mid < kv[s + 1])) return 0;
    if (fit_breaks_add(&p->I[d], mid) <= 0) return 0;
    p->pending[d]++;
    return 1;
}

/* Stalled: refined twice in a row (its knots grew) while failing, without improving by
 * Q2N_FIT_STALL_GAIN either time — a smooth construction's jumps fall ~16-32x per bisection, and one
 * round may get worse while the neighbours' knots change.  *fails counts such rounds. */
static int stall_update(double now, double prev, int *fails, int failing, int refined)
{
    if (!failing) { *fails = 0; return 0; }
    if (refined) *fails = now < prev / Q2N_FIT_STALL_GAIN ? 0 : *fails + 1;
    return *fails >= 2;
}

int fit_refine(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    double tol = c->o.tol;
    int added = 0, why[6] = {0};
    for (int k = 0; k < m->nf; k++) c->p[k].pending[0] = c->p[k].pending[1] = 0;
    /* edges: curve, rows, continuity */
    for (int e = 0; e < m->ne; e++) {
        fit_edge *E = &c->e[e];
        if (!E->nchk) continue;
        int lsg1 = E->glue == FIT_GLUE_LS, lsg2 = c->o.continuity == 2 && E->glue2 == FIT_GLUE_LS;
        double aim1 = Q2N_FIT_REFINE_AIM * c->o.g1_target_deg, aim2 = Q2N_FIT_REFINE_AIM * c->o.g2_target_rel;
        int c1 = lsg1 && E->g1c <= aim1 && !(E->stalled & 1), c2 = lsg2 && E->g2c <= aim2 && !(E->stalled & 2);
        /* stalling is judged only in the asymptotic range (a coarse edge's jumps may not fall
         * until its rows resolve the construction) */
        int refined = E->K.n > E->kn_prev && E->kn_prev + 1 >= Q2N_FIT_STALL_SPANS;
        if (getenv("Q2N_FIT_EDGE") && atoi(getenv("Q2N_FIT_EDGE")) == e)
            fprintf(stderr, "  edge %d: glue %d/%d K.n %d g1 %.3g g2 %.3g g1c %.3g g2c %.3g stalled %d fails %d/%d c1 %d c2 %d nchk %d\n", e,
                    E->glue, E->glue2, E->K.n, E->g1, E->g2, E->g1c, E->g2c, E->stalled, E->g1_fails, E->g2_fails, c1, c2, E->nchk);
        if (getenv("Q2N_FIT_EDGE") && atoi(getenv("Q2N_FIT_EDGE")) == e) {
            for (int q = 0; q < E->nchk; q++) fprintf(stderr, " (%.3g: %.2g %.2g)", E->chk[5*q], E->chk[5*q+3], E->chk[5*q+4]);
            fprintf(stderr, "\n");
        }
        if (c1 && stall_update(E->g1, E->g1_prev, &E->g1_fails, E->g1 > aim1, refined)) { E->stalled |= 1; c1 = 0; }
        if (c2 && stall_update(E->g2, E->g2_prev, &E->g2_fails, E->g2 > aim2, refined)) { E->stalled |= 2; c2 = 0; }
        E->g1_prev = E->g1;
        E->g2_prev = E->g2;
        E->kn_prev = E->K.n;
        /* the spans of the knots as they were measured: each bad one is bisected once */
        int nsp = E->K.n + 1, nmark = 0;
        unsigned char *mark = calloc((size_t)nsp, 1);
        if (!mark) continue;
        for (int q = 0; q < E->nchk; q++) {
            const double *ck = E->chk + 5 * (size_t)q;
            int r0 = ck[1] > Q2N_FIT_EDGE_SHARE * tol, r1 = ck[2] > Q2N_FIT_ROW_SHARE * tol;
            int r2 = c1 && ck[3] > aim1, r3 = c2 && ck[4] > aim2;
            if (!(r0 || r1 || r2 || r3)) continue;
            int sp = 0;
            while (sp < E->K.n && E->K.t[sp] <= ck[0]) sp++;
            if (r2 || r3) {
                /* a least-squares gluing relation converges under uniform refinement of its edge;
                 * graded towards the worst point it did not (the jump next to an extraordinary
                 * corner grew as the spans there shrank: docs/fit.md) */
                for (int z = 0; z < nsp; z++)
                    if (!mark[z]) { mark[z] = 1; nmark++; }
                why[2] += r2; why[3] += r3;
                continue;
            }
            if (!mark[sp]) {
                mark[sp] = 1;
                nmark++;
                why[0] += r0; why[1] += r1; why[2] += r2; why[3] += r3;
            }
        }
        double *mids = malloc(sizeof(double) * (size_t)(nmark + 1));
        int nm = 0;
        for (int sp = 0; mids && sp < nsp; sp++)
            if (mark[sp]) mids[nm++] = 0.5 * ((sp ? E->K.t[sp - 1] : 0.0) + (sp < E->K.n ? E->K.t[sp] : 1.0));
        for (int q = 0; mids && q < nm; q++) added += bisect_edge(c, e, mids[q]);
        free(mids);
        free(mark);
    }
    /* patches: cells over the tolerance, in the limiting direction(s) */
    for (int k = 0; k < m->nf; k++) {
        fit_patch *p = &c->p[k];
        if (!(p->dev > tol) || p->spiky == 2 || !p->cell) continue;
        int dirs[2] = {p->share[0] >= Q2N_FIT_DIR_SHARE, p->share[1] >= Q2N_FIT_DIR_SHARE};
        if (!p->spiky && ((dirs[0] && p->mu * 2 >= Q2N_FIT_SCAN_SPANS) || (dirs[1] && p->mv * 2 >= Q2N_FIT_SCAN_SPANS))) {
            /* before a patch gets many spans, make sure its construction is smooth at the scale of
             * the knots (a spike narrower than any knot spacing is reported, not chased) */
            double ratio = 1.0, su, sv, dmax, t1 = q2n_now();
            if (q2n_fit_scan_construction(c->s, k, Q2N_FIT_SCAN_N_QUICK, &ratio, &su, &sv, &dmax)) ratio = 1.0;
            c->rep->t_measure += q2n_now() - t1;
            p->spiky = ratio <= Q2N_FIT_SPIKE_RATIO ? 1 : 2;
            if (p->spiky == 2) continue;
        }
        /* cells in span order; one bisection per span and direction */
        double *cu = malloc(sizeof(double) * (size_t)p->ncu), *cv = malloc(sizeof(double) * (size_t)p->ncv);
        if (!cu || !cv) { free(cu); free(cv); continue; }
        q2n_fit_check_params(p->nu, p->ku, Q2N_FIT_SAMPLES_PER_SPAN, cu);
        q2n_fit_check_params(p->nv, p->kv, Q2N_FIT_SAMPLES_PER_SPAN, cv);
        unsigned char *su = calloc((size_t)p->mu, 1), *sv = calloc((size_t)p->mv, 1);
        if (su && sv)
            for (int j = 0; j < p->ncv; j++)
                for (int i = 0; i < p->ncu; i++) {
                    if (!(p->cell[(size_t)j * p->ncu + i] > tol)) continue;
                    if (dirs[0]) su[i / Q2N_FIT_SAMPLES_PER_SPAN] = 1;
                    if (dirs[1]) sv[j / Q2N_FIT_SAMPLES_PER_SPAN] = 1;
                }
        int mu = p->mu, mv = p->mv;
        for (int s = 0; su && sv && s < mu; s++)
            if (su[s]) { int r = bisect_patch(c, k, 0, cu[s * Q2N_FIT_SAMPLES_PER_SPAN]); added += r; why[4] += r; }
        for (int s = 0; su && sv && s < mv; s++)
            if (sv[s]) { int r = bisect_patch(c, k, 1, cv[s * Q2N_FIT_SAMPLES_PER_SPAN]); added += r; why[5] += r; }
        free(su); free(sv); free(cu); free(cv);
    }
    if (getenv("Q2N_FIT_DEBUG")) {
        double md = 0; int nbad = 0;
        for (int k = 0; k < m->nf; k++) { if (c->p[k].dev > md) md = c->p[k].dev; nbad += c->p[k].dev > tol; }
        fprintf(stderr, "round %d: maxdev %.3g (%d patches over), added %d: curve %d row %d g1 %d g2 %d patch-u %d patch-v %d\n",
                c->round, md, nbad, added, why[0], why[1], why[2], why[3], why[4], why[5]);
        int wk = 0;
        for (int k = 0; k < m->nf; k++) if (c->p[k].dev > c->p[wk].dev) wk = k;
        const fit_patch *p = &c->p[wk];
        fprintf(stderr, "  worst patch %d: %d x %d spans, share %.2f/%.2f, ku:", wk, p->mu, p->mv, p->share[0], p->share[1]);
        for (int q = 5; q <= p->nu; q++) fprintf(stderr, " %g", p->ku[q]);
        fprintf(stderr, " kv:");
        for (int q = 5; q <= p->nv; q++) fprintf(stderr, " %g", p->kv[q]);
        fprintf(stderr, " I_u %d I_v %d; edges:", p->I[0].n, p->I[1].n);
        for (int i = 0; i < 4; i++) { int h = 4 * wk + i, e = m->he_edge[h]; fprintf(stderr, " [e%d %s glue %d:", e, m->edge_he[e] == h ? "own" : "twin", c->e[e].glue); for (int q = 0; q < c->e[e].K.n; q++) fprintf(stderr, " %g", c->e[e].K.t[q]); fprintf(stderr, "]"); }
        fprintf(stderr, "\n");
        for (int j = p->ncv - 1; j >= 0 && p->ncu <= 32; j--) {
            fprintf(stderr, "   ");
            for (int i = 0; i < p->ncu; i++) fprintf(stderr, " %5.1f", p->cell[j * p->ncu + i] / tol);
            fprintf(stderr, "\n");
        }
        double mr = 0, mc = 0; int er = -1;
        for (int e = 0; e < m->ne; e++) for (int q = 0; q < c->e[e].nchk; q++) {
            if (c->e[e].chk[5*q+2] > mr) { mr = c->e[e].chk[5*q+2]; er = e; }
            if (c->e[e].chk[5*q+1] > mc) mc = c->e[e].chk[5*q+1]; }
        fprintf(stderr, "  max row err %.3g (edge %d glue %d), max curve err %.3g\n", mr/tol, er, er >= 0 ? c->e[er].glue : -1, mc/tol);
    }
    return added;
}

void fit_accept(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    q2n_fit_report *rep = c->rep;
    double aim1 = Q2N_FIT_REFINE_AIM * c->o.g1_target_deg, aim2 = Q2N_FIT_REFINE_AIM * c->o.g2_target_rel;
    int worst_f = -1, worst_e1 = -1, worst_e2 = -1;
    for (int k = 0; k < m->nf; k++)
        if (c->p[k].dev > c->o.tol && (worst_f < 0 || c->p[k].dev > c->p[worst_f].dev)) worst_f = k;
    for (int e = 0; e < m->ne; e++) {
        const fit_edge *E = &c->e[e];
        if (E->glue == FIT_GLUE_BOUNDARY) continue;
        if (E->g1 > c->o.g1_target_deg && E->g1c <= aim1 && (worst_e1 < 0 || E->g1 > c->e[worst_e1].g1)) worst_e1 = e;
        if (c->o.continuity == 2 && E->g2 > c->o.g2_target_rel && E->g2c <= aim2 &&
            (worst_e2 < 0 || E->g2 > c->e[worst_e2].g2))
            worst_e2 = e;
    }
    rep->dev_met = worst_f < 0;
    rep->g1_met = worst_e1 < 0;
    rep->g2_met = c->o.continuity == 1 || worst_e2 < 0;
    rep->tol_met = rep->dev_met && rep->g1_met && rep->g2_met;
    rep->note[0] = 0;
    if (worst_e1 >= 0 || worst_e2 >= 0) {
        int e = worst_e1 >= 0 ? worst_e1 : worst_e2;
        const fit_edge *E = &c->e[e];
        snprintf(rep->note, sizeof rep->note,
                 "edge %d (faces %d, %d): normal jump %.3g deg, curvature jump %.3g (targets %.3g deg, %.3g; "
                 "the construction's own: %.3g deg, %.3g) not reached", e, m->he_face[m->edge_he[e]],
                 m->he_face[m->he_twin[m->edge_he[e]]], E->g1, E->g2, c->o.g1_target_deg, c->o.g2_target_rel, E->g1c,
                 E->g2c);
    }
}
