/* fit_refine.c — where the knots go: the refinement policy of the fit (thresholds in fit_policy.h).
 *
 * After each round the driver has measured, per patch, the deviation in every cell of its check
 * grid and, per edge, at the check points of its owner side: the edge curve's deviation, the cross
 * rows' deviation (in position terms) and the fitted normal and curvature jumps.  Refinement bisects
 * knot spans where the error is, so the knots grade towards it and never travel:
 *  - a cell over the tolerance bisects its patch's span(s) in the direction(s) that limit it (6th
 *    differences of the construction around the worst cell: the quintic error term is
 *    ~ h^6 |d^6 S| per direction; the dominant direction alone where bisecting it brings the
 *    modelled error within the tolerance) — an interior knot of that patch only; unless every failing
 *    cell of the patch lies next to a side whose edge is being split there this round (then the
 *    patch waits for the refitted edge: near_split); cells next to such a side do not count
 *    towards the splits of a patch that does not wait either, unless no round is left after this;
 *  - an edge whose curve, or whose cross rows where its gluing is exact, are off bisects that span
 *    of the edge's own knots, which both neighbours (and only they) take up;
 *  - an edge whose G1 or G2 relation is least squares and misses Q2N_FIT_REFINE_AIM of its target
 *    (at its check points or between them: fit.c), where the construction itself meets that,
 *    splits every span of its knots (that converges; grading towards the worst point did not next
 *    to extraordinary corners) — or, missing by less than Q2N_FIT_CONT_LOCAL, only the spans whose
 *    jumps miss, while such local splits lower the miss by Q2N_FIT_STALL_GAIN per round and the
 *    span cap leaves room (after them, the spans they left coarser: the knots are uniform again);
 * all within max_spans per patch direction.  A bisection halves h: the deviation falls ~64x, the
 * normal jump ~32x, the curvature jump ~16x per round where the construction is smooth; a span
 * whose error needs more is split into 4 or 8 at once (split_levels). */
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

/* Add breakpoint mid (owner orientation, inside one of its spans) to edge e unless a cap forbids
 * it; returns 1 when a knot was added. */
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
    int r = q2n_fit_breaks_add(&E->K, mid);
    if (r <= 0) return 0;
    E->ver++;
    for (int x = 0; x < 2; x++)
        if (h[x] >= 0) {
            int k = m->he_face[h[x]], i = h[x] - m->face_start[k];
            if (new_in_patch(c, k, i, x ? 1.0 - mid : mid)) c->p[k].pending[i & 1]++;
        }
    return 1;
}

/* Add breakpoint t (inside one of its spans) to patch k's interior knots in direction d unless the
 * span cap forbids it; returns 1 when a knot was added. */
static int bisect_patch(fit_ctx *c, int k, int d, double t)
{
    fit_patch *p = &c->p[k];
    if (patch_spans(c, k, d) >= c->o.max_spans) return 0;
    if (q2n_fit_breaks_add(&p->I[d], t) <= 0) return 0;
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

/* Levels of bisection (each halves the span) that bring an error `ratio` times its target down
 * to it when the error falls like h^order, at least one and at most Q2N_FIT_SPLIT_LEVELS per round;
 * a further level only when the model asks for Q2N_FIT_SPLIT_MARGIN times more (it overshoots
 * otherwise: the error model is asymptotic and the next round can still bisect). */
static int split_levels(double ratio, double order)
{
    double f = pow(ratio > 1 ? ratio : 1, 1.0 / order);
    int lv = 1;
    while (Q2N_FIT_SPLIT_MARGIN * (double)(1 << lv) < f && lv < Q2N_FIT_SPLIT_LEVELS) lv++;
    return lv;
}

/* Split span [a, b] into 2^lv equal parts through add(t) (dyadic knots stay dyadic); returns the
 * number of knots added. */
typedef int (*split_fn)(fit_ctx *c, int id, int d, double t);
static int split_span(fit_ctx *c, int id, int d, double a, double b, int lv, split_fn add)
{
    int n = 1 << lv, r = 0;
    for (int i = 1; i < n; i++) r += add(c, id, d, a + (b - a) * i / n);
    return r;
}

static int add_edge(fit_ctx *c, int e, int d, double t) { (void)d; return bisect_edge(c, e, t); }
static int add_patch(fit_ctx *c, int k, int d, double t) { return bisect_patch(c, k, d, t); }

/* Is span (iu, iv) of patch p within `reach` spans of a side whose edge is being split over a
 * range overlapping it (lo[i], hi[i]: side i's split range in the patch's u or v; empty when
 * lo > hi)?  Sides: 0 v = 0, 1 u = 1, 2 v = 1, 3 u = 0. */
static int near_split(const fit_patch *p, int iu, int iv, int reach, const double *lo, const double *hi)
{
    double u0 = p->ku[5 + iu], u1 = p->ku[6 + iu], v0 = p->kv[5 + iv], v1 = p->kv[6 + iv];
    return (iv < reach && u1 > lo[0] && u0 < hi[0]) || (iu >= p->mu - reach && v1 > lo[1] && v0 < hi[1]) ||
           (iv >= p->mv - reach && u1 > lo[2] && u0 < hi[2]) || (iu < reach && v1 > lo[3] && v0 < hi[3]);
}

/* Breakpoints of side (k, i) in the owner orientation of its edge, sorted; returns their number. */
static int side_set(const fit_ctx *c, int k, int i, double *out)
{
    const q2n_mesh *m = c->m;
    int h = m->face_start[k] + i, e = m->he_edge[h], own = m->edge_he[e] == h;
    int n = q2n_fit_patch_breaks(c, k, i & 1, out);
    for (int q = 0; q < n; q++) {
        double t = i < 2 ? out[q] : 1.0 - out[q];
        out[q] = own ? t : 1.0 - t;
    }
    if ((i >= 2) == own)   /* the map reversed the order */
        for (int q = 0; q < n / 2; q++) { double t = out[q]; out[q] = out[n - 1 - q]; out[n - 1 - q] = t; }
    return n;
}

/* An edge takes up the breakpoints both its sides have (one side: a boundary edge) — the patches'
 * own knots or their other edges': its curve is then fitted on the knots its sides' boundary rows
 * have, and those rows are the curve itself, point for point (the STEP file shares them), at no
 * cost in the patches' control points; returns the number added. */
static int promote(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    int added = 0;
    for (int e = 0; e < m->ne; e++) {
        fit_edge *E = &c->e[e];
        int h[2] = {m->edge_he[e], m->he_twin[m->edge_he[e]]}, n[2] = {0, 0};
        double *s[2] = {NULL, NULL};
        int ok = 1;
        for (int x = 0; x < 2 && ok; x++) {
            if (h[x] < 0) continue;
            int k = m->he_face[h[x]];
            const fit_patch *p = &c->p[k];
            int cap = 0;
            for (int i = 0; i < 4; i++) cap += c->e[m->he_edge[4 * k + i]].K.n;
            cap += p->I[0].n + p->I[1].n + 1;
            s[x] = malloc(sizeof(double) * (size_t)cap);
            if (!s[x]) ok = 0;
            else n[x] = side_set(c, k, h[x] - m->face_start[k], s[x]);
        }
        if (ok) {
            int i = 0, j = 0, two = h[1] >= 0;
            while (i < n[0] && (!two || j < n[1])) {
                if (two && s[1][j] < s[0][i]) { j++; continue; }
                if (two && s[1][j] > s[0][i]) { i++; continue; }
                int r = q2n_fit_breaks_add(&E->K, s[0][i]);
                if (r > 0) { E->ver++; added++; }
                i++;
                if (two) j++;
            }
        }
        free(s[0]); free(s[1]);
    }
    return added;
}

int q2n_fit_refine(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    double tol = c->o.tol;
    int added = 0;
    for (int k = 0; k < m->nf; k++) c->p[k].pending[0] = c->p[k].pending[1] = 0;
    /* edges refined in this round: their curve and cross rows are refitted on the new knots, so
     * the cells those rows reach are judged again next round, not now (below) */
    double *eref = malloc(sizeof(double) * 2 * ((size_t)m->ne + 1));   /* split range [lo, hi], owner side */
    if (!eref) return 0;
    for (int e = 0; e < m->ne; e++) eref[2 * e] = 1.0, eref[2 * e + 1] = 0.0;
    /* edges: curve, rows, continuity */
    for (int e = 0; e < m->ne; e++) {
        fit_edge *E = &c->e[e];
        if (!E->nchk) continue;
        int lsg1 = E->glue == FIT_GLUE_LS, lsg2 = c->o.continuity == 2 && E->glue2 == FIT_GLUE_LS;
        double aim1 = Q2N_FIT_REFINE_AIM * c->o.g1_tol_deg, aim2 = Q2N_FIT_REFINE_AIM * c->o.g2_tol_rel;
        int c1 = lsg1 && E->g1c <= aim1 && !(E->stalled & 1), c2 = lsg2 && E->g2c <= aim2 && !(E->stalled & 2);
        /* stalling is judged only in the asymptotic range (a coarse edge's jumps may not fall
         * until its rows resolve the construction) */
        int refined = E->K.n > E->kn_prev && E->kn_prev + 1 >= Q2N_FIT_STALL_SPANS;
        if (c1 && stall_update(E->g1d, E->g1_prev, &E->g1_fails, E->g1d > aim1, refined)) { E->stalled |= 1; c1 = 0; }
        if (c2 && stall_update(E->g2d, E->g2_prev, &E->g2_fails, E->g2d > aim2, refined)) { E->stalled |= 2; c2 = 0; }
        E->g1_prev = E->g1d;
        E->g2_prev = E->g2d;
        E->kn_prev = E->K.n;
        /* split levels per span of the knots as measured: the curve and the rows where they miss
         * their share of the tolerance; a least-squares gluing relation that misses its aim splits
         * every span (it converges under uniform refinement of its edge; graded towards the worst
         * point it did not next to extraordinary corners: docs/fit.md) — unless it misses by less
         * than Q2N_FIT_CONT_LOCAL: then only the spans whose jumps miss the aim, as long as that
         * answers (the miss fell by Q2N_FIT_STALL_GAIN since the last such split) and the span cap
         * leaves room; a round that is not local on knots that local rounds graded splits every span
         * coarser than the finest, which evens them out */
        int nsp = E->K.n + 1, cont = 0;
        double *br = malloc(sizeof(double) * (size_t)(nsp + 1));
        if (!br) continue;
        br[0] = 0.0;
        for (int q = 0; q < E->K.n; q++) br[q + 1] = E->K.t[q];
        br[nsp] = 1.0;
        /* split_levels grows with the ratio: the per-edge jump maxima and the per-span deviation
         * maxima decide */
        double r2 = c1 ? E->g1d / aim1 : 0.0, r3 = c2 ? E->g2d / aim2 : 0.0;
        if (r2 > 1) cont = split_levels(r2, 5.0);
        if (r3 > 1 && split_levels(r3, 4.0) > cont) cont = split_levels(r3, 4.0);
        int local = 0, even = 0;
        double wmin = 1.0;
        if (cont) {
            double miss = fmax(r2, r3);
            int failed = E->cont_local && !(miss < E->cont_prev / Q2N_FIT_STALL_GAIN);
            for (int sp = 0; sp < nsp; sp++) wmin = fmin(wmin, br[sp + 1] - br[sp]);
            /* local only while the edge's knots, evened out at the level a local round reaches,
             * leave room under the span cap (Q2N_FIT_CONT_LOCAL_ROOM) */
            int room = Q2N_FIT_CONT_LOCAL_ROOM * (double)(1 << cont) / wmin <= c->o.max_spans + 0.5;
            local = miss < Q2N_FIT_CONT_LOCAL && !failed && room;
            even = !local && E->cont_graded;
            E->cont_prev = miss;
            E->cont_graded = local || (E->cont_graded && !even);
        }
        E->cont_local = local;
        for (int sp = 0; sp < nsp; sp++) {
            const double *mx = E->spmax + FIT_SPMAX * (size_t)sp;
            /* the rows of a least-squares-glued edge are a compromise between the construction's cross
             * derivatives and the gluing, so their distance from those derivatives is not a position
             * error: the cells beside the edge judge it (and refine that patch alone) */
            double r0 = mx[FIT_SPMAX_DEV] / (Q2N_FIT_EDGE_SHARE * tol);
            double r1 = q2n_fit_edge_ls(c, E) ? 0.0 : mx[FIT_SPMAX_ROW] / (Q2N_FIT_ROW_SHARE * tol);
            int l = cont;
            if (local && !((c1 && mx[FIT_SPMAX_G1] > aim1) || (c2 && mx[FIT_SPMAX_G2] > aim2))) l = 0;
            /* knots graded by local rounds: the spans they did not split (breakpoints are dyadic,
             * so span widths differ by powers of two), which gives the edge the uniform knots that
             * splitting every span would have given it a round earlier */
            if (even && !(br[sp + 1] - br[sp] > 1.5 * wmin)) l = 0;
            if (r0 > 1 && split_levels(r0, 6.0) > l) l = split_levels(r0, 6.0);
            if (r1 > 1 && split_levels(r1, 5.0) > l) l = split_levels(r1, 5.0);
            if (l) {
                int a = split_span(c, e, 0, br[sp], br[sp + 1], l, add_edge);
                added += a;
                if (a) {
                    eref[2 * e] = fmin(eref[2 * e], br[sp]);
                    eref[2 * e + 1] = fmax(eref[2 * e + 1], br[sp + 1]);
                }
            }
        }
        free(br);
    }
    /* edges beside failing cells: a cell in the first row along a side that misses the tolerance,
     * where the side's edge curve itself uses more than Q2N_FIT_EDGE_ASSIST of it in that span,
     * splits that span of the edge too — the patch's own knots cannot remove its boundary's error */
    for (int k = 0; k < m->nf; k++) {
        const fit_patch *p = &c->p[k];
        if (!(p->dev > tol) || !p->cell) continue;
        for (int j = 0; j < p->ncv; j++)
            for (int i = 0; i < p->ncu; i++) {
                if (!(p->cell[(size_t)j * p->ncu + i] > tol)) continue;
                int sides[2], ns = 0;   /* a corner cell is beside two sides */
                if (j == 0) sides[ns++] = 0;
                if (j == p->ncv - 1) sides[ns++] = 2;
                if (i == 0) sides[ns++] = 3;
                if (i == p->ncu - 1) sides[ns++] = 1;
                for (int q = 0; q < ns; q++) {
                    int sd = sides[q];
                    double x = sd & 1 ? q2n_fit_check_param(p->kv, Q2N_FIT_SAMPLES_PER_SPAN, j)
                                      : q2n_fit_check_param(p->ku, Q2N_FIT_SAMPLES_PER_SPAN, i);
                    int h = m->face_start[k] + sd, e = m->he_edge[h];
                    double t = sd < 2 ? x : 1.0 - x;                 /* side orientation */
                    if (m->edge_he[e] != h) t = 1.0 - t;             /* owner orientation */
                    fit_edge *E = &c->e[e];
                    if (!E->spmax || E->nspmax != E->K.n + 1) continue;   /* split this round already */
                    int sp = 0;
                    while (sp < E->K.n && E->K.t[sp] <= t) sp++;
                    double lo = sp ? E->K.t[sp - 1] : 0.0, hi = sp < E->K.n ? E->K.t[sp] : 1.0;
                    if (!(E->spmax[FIT_SPMAX * (size_t)sp + FIT_SPMAX_DEV] > Q2N_FIT_EDGE_ASSIST * tol)) continue;
                    if (eref[2 * e] < hi && eref[2 * e + 1] > lo) continue;   /* being split there */
                    int add = split_span(c, e, 0, lo, hi, 1, add_edge);
                    added += add;
                    if (add) eref[2 * e] = fmin(eref[2 * e], lo), eref[2 * e + 1] = fmax(eref[2 * e + 1], hi);
                }
            }
    }
    /* patches: cells over the tolerance, in the limiting direction(s).  Only while a round after
     * this one judges the cells again may a patch wait for its edges or set cells aside (below) */
    const int judged_later = c->round + 2 < c->o.max_rounds;
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
        /* per span and direction, the worst cell ratio decides the split levels.  A patch whose
         * failing cells all lie next to sides whose edges were just split there — within the reach
         * of the rows those edges fix (rows 0..C, C the continuity order: row r of a side is zero
         * beyond its first r + 1 spans) — waits for the refitted edges instead: such cells show
         * that edge's error (a boundary curve one level coarser than its neighbours shows in the
         * cells next to it), which the edge's own refinement removes; bisecting the patch as well
         * doubled the spans of patches whose interior already met the tolerance. */
        double lo[4], hi[4];  /* per side: the range its edge is splitting, in the patch's u or v */
        for (int i = 0; i < 4; i++) {
            int h = m->face_start[k] + i, e = m->he_edge[h];
            double a = eref[2 * e], b = eref[2 * e + 1];
            if (m->edge_he[e] != h) { double t = 1.0 - b; b = 1.0 - a; a = t; }  /* owner -> this side */
            if (i >= 2) { double t = 1.0 - b; b = 1.0 - a; a = t; }            /* side -> u or v */
            lo[i] = a, hi[i] = b;
        }
        /* the refinement before the last round cannot wait: no round after it judges the cells */
        int reach = c->o.continuity + 1, wait = judged_later;
        for (int j = 0; j < p->ncv && wait; j++)
            for (int i = 0; i < p->ncu && wait; i++)
                if (p->cell[(size_t)j * p->ncu + i] > tol &&
                    !near_split(p, i / Q2N_FIT_SAMPLES_PER_SPAN, j / Q2N_FIT_SAMPLES_PER_SPAN, reach, lo, hi))
                    wait = 0;
        if (wait) continue;
        double *ru = calloc((size_t)p->mu, sizeof(double)), *rv = calloc((size_t)p->mv, sizeof(double));
        if (!ru || !rv) { free(ru); free(rv); continue; }
        /* a failing cell beside an edge being split there this round is judged again after that
         * edge's refit, like a patch all of whose failing cells are such (above), unless no round is
         * left to judge it: the cells elsewhere decide this round's splits.  Counting them too
         * bisected whole patches for bands the edges' own refinement removes (a patch failing by
         * 8 x tol in a band along a side being split and by 2 x next to another side had every span
         * split in both directions, where the cells by the other side ask for some v spans) */
        for (int j = 0; j < p->ncv; j++)
            for (int i = 0; i < p->ncu; i++) {
                double r = p->cell[(size_t)j * p->ncu + i] / tol;
                if (!(r > 1)) continue;
                int iu = i / Q2N_FIT_SAMPLES_PER_SPAN, iv = j / Q2N_FIT_SAMPLES_PER_SPAN;
                if (judged_later && near_split(p, iu, iv, reach, lo, hi)) continue;
                /* each refined direction takes its share of the error; one direction alone where the
                 * error model says it suffices (a bisection in direction d divides d's h^6 term by
                 * 64, leaving r (1 - s_d 63/64) of the cell's error) */
                int du = dirs[0], dv = dirs[1];
                if (du && dv) {
                    int d = p->share[1] > p->share[0];
                    if (r * (1.0 - p->share[d] * 63.0 / 64.0) <= 1.0) {
                        if (d) du = 0;
                        else dv = 0;
                    }
                }
                if (du && r * p->share[0] > ru[iu]) ru[iu] = fmax(r * p->share[0], 1.0001);
                if (dv && r * p->share[1] > rv[iv]) rv[iv] = fmax(r * p->share[1], 1.0001);
            }
        int mu = p->mu, mv = p->mv;
        for (int sp = 0; sp < mu; sp++)
            if (ru[sp] > 1) added += split_span(c, k, 0, p->ku[5 + sp], p->ku[6 + sp], split_levels(ru[sp], 6.0), add_patch);
        for (int sp = 0; sp < mv; sp++)
            if (rv[sp] > 1) added += split_span(c, k, 1, p->kv[5 + sp], p->kv[6 + sp], split_levels(rv[sp], 6.0), add_patch);
        free(ru); free(rv);
    }
    added += promote(c);
    free(eref);
    return added;
}

void q2n_fit_accept(fit_ctx *c)
{
    const q2n_mesh *m = c->m;
    q2n_fit_report *rep = c->rep;
    double aim1 = Q2N_FIT_REFINE_AIM * c->o.g1_tol_deg, aim2 = Q2N_FIT_REFINE_AIM * c->o.g2_tol_rel;
    int worst_f = -1, worst_e1 = -1, worst_e2 = -1;
    for (int k = 0; k < m->nf; k++)
        if (c->p[k].dev > c->o.tol && (worst_f < 0 || c->p[k].dev > c->p[worst_f].dev)) worst_f = k;
    for (int e = 0; e < m->ne; e++) {
        const fit_edge *E = &c->e[e];
        if (E->glue == FIT_GLUE_BOUNDARY) continue;
        if (E->g1d > c->o.g1_tol_deg && E->g1c <= aim1 && (worst_e1 < 0 || E->g1d > c->e[worst_e1].g1d)) worst_e1 = e;
        if (c->o.continuity == 2 && E->g2d > c->o.g2_tol_rel && E->g2c <= aim2 &&
            (worst_e2 < 0 || E->g2d > c->e[worst_e2].g2d))
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
        int f0 = m->he_face[m->edge_he[e]], f1 = m->he_face[m->he_twin[m->edge_he[e]]];
        if (c->o.continuity == 2)
            snprintf(rep->note, sizeof rep->note,
                     "edge %d (faces %d, %d): normal jump %.3g deg, curvature jump %.3g (targets %.3g deg, %.3g; "
                     "the construction's own: %.3g deg, %.3g) not reached", e, f0, f1, E->g1d, E->g2d, c->o.g1_tol_deg,
                     c->o.g2_tol_rel, E->g1c, E->g2c);
        else /* G1: no curvature target */
            snprintf(rep->note, sizeof rep->note,
                     "edge %d (faces %d, %d): normal jump %.3g deg (target %.3g deg; the construction's own: %.3g deg) "
                     "not reached", e, f0, f1, E->g1d, c->o.g1_tol_deg, E->g1c);
    }
}
