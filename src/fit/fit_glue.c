/* fit_glue.c — the gluing data of every edge and the cross-row stages that impose them.
 *
 * Across an interior edge with sides L (owner) and R, t along the edge (t_R = 1 - t) and s into each
 * patch, a G1 surface satisfies (formulas.md §4.2; seed 003 Prop. 2, eqs. 13–14)
 *      d_s S_R = alpha d_s S_L + beta d_t S_L                                           (G1)
 *      d_ss S_R = alpha^2 d_ss S_L + 2 alpha beta d_ts S_L + beta^2 d_tt S_L + gamma d_s S_L + delta d_t S_L   (G2)
 * with scalar functions alpha, beta (gamma, delta) of t.  They are measured from the construction
 * at Q2N_FIT_GLUE_SAMPLES points per edge (a 2 x 2 least-squares solve per point, exact for a G1
 * construction).
 *
 * The gluing is measured twice: on the construction (q2n_fit_glue_measure: which edges glue by a
 * scale alpha(t), beta = gamma = delta = 0, which fit_target.c reparametrizes into a constant) and
 * on the fit target (q2n_fit_glue_classify: which relations are exact).
 *
 * Exact relations.  Where the target's gluing is a constant scale (alpha const, beta = 0; in
 * G2 mode also gamma = delta = 0), the relation is linear in the control points with constant
 * coefficients, and it is imposed as an EQUALITY constraint: the identity of the two sides'
 * piecewise polynomials  d_s S_R(1 - t) - alpha d_s S_L(t) = 0  holds on every span of the union of
 * the two sides' knots once it holds at 6 points per span (degree 5), so those rows are the whole
 * condition.  The block (first rows of L and R) is solved in null-space form: every solution is
 * x = x_p + Z y (core/dense.h: SVD of the constraint rows), and Ceres solves the reduced,
 * unconstrained least-squares problem for y.  The relation then holds to rounding everywhere on the
 * edge, whatever the knots: such a constraint is always satisfiable (both rows may use the knots the
 * two sides share) and consistent with the corner jets (they come from the construction, which
 * satisfies it).  Why only this case: with a non-constant polynomial alpha (or beta != 0) the
 * product alpha * d_s S_L has degree 5 + deg alpha while d_s S_R has degree 5, so on simple knots
 * both rows would be forced down to one polynomial along the whole edge (docs/fit.md counts it).
 * Elsewhere the relation is imposed by weighted least squares at the fidelity samples (g1_weight),
 * measured between them, and refinement reaches the targets. */
#include "fit/fit_policy.h"
#include "fit/fit_state.h"
#include "core/clock.h"
#include "core/dense.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* alpha, beta with  dR = alpha dL + beta T  in the least-squares sense (exact for a G1
 * construction). */
static void glue1(const double dR[3], const double dL[3], const double T[3], double *al, double *be)
{
    double a11 = q2n_v3_dot(dL, dL), a12 = q2n_v3_dot(dL, T), a22 = q2n_v3_dot(T, T);
    double b1 = q2n_v3_dot(dL, dR), b2 = q2n_v3_dot(T, dR), det = a11 * a22 - a12 * a12;
    *al = (a22 * b1 - a12 * b2) / det;
    *be = (a11 * b2 - a12 * b1) / det;
}

/* The four gluing functions at one edge point from both sides' frame derivatives. */
static void glue_at(const double DL[6][3], const double DR[6][3], double g[4])
{
    glue1(DR[2], DL[2], DL[1], &g[0], &g[1]);
    double E[3];
    for (int q = 0; q < 3; q++)
        E[q] = DR[5][q] - g[0] * g[0] * DL[5][q] - 2 * g[0] * g[1] * DL[4][q] - g[1] * g[1] * DL[3][q];
    glue1(E, DL[2], DL[1], &g[2], &g[3]);
}

/* Frame derivatives of side R in the layout q2n_fit_jumps reads (S, Su, Sv, Suu, Suv, Svv): the
 * side frame (t, s) is an orientation-preserving rotation of (u, v), so normals and normal
 * curvatures come out the same. */
static void frame_as_uv(const double D[6][3], double out[18])
{
    memcpy(out, D, 18 * sizeof(double));
}

typedef struct classify_arg {
    fit_ctx *c;
    q2n_status *st;
} classify_arg;

enum { NG = Q2N_FIT_GLUE_SAMPLES };

/* The gluing functions of edge e at t_j = j / (NG - 1) from both sides' frame derivatives, through
 * the side caches: before q2n_fit_target_setup every patch has phi = id, so these are the
 * construction's own frames (q2n_fit_glue_measure), and they stay cached for the patches that keep
 * phi = id (the setup empties the others' caches); after it, the fit target's. */
static q2n_status edge_samples(fit_ctx *c, int e, double DL[NG][6][3], double DR[NG][6][3], double g[NG][4])
{
    fit_side L, R;
    q2n_fit_edge_sides(c, e, &L, &R);
    double tl[NG], DRs[NG][6][3]; /* both sides at t_j, R's reversed into DR below */
    for (int j = 0; j < NG; j++) tl[j] = (double)j / (NG - 1);
    q2n_status st = q2n_fit_side_values(c, L.k, L.i, NG, tl, &DL[0][0][0]);
    if (!st) st = q2n_fit_side_values(c, R.k, R.i, NG, tl, &DRs[0][0][0]);
    if (st) return st;
    for (int j = 0; j < NG; j++) memcpy(DR[j], DRs[NG - 1 - j], sizeof DR[j]);
    for (int j = 0; j < NG; j++) glue_at(DL[j], DR[j], g[j]);
    return Q2N_OK;
}

/* beta = 0 (and gamma = delta = 0 when g2) at every sample, relative to the terms they multiply. */
static int scale_only(double DL[NG][6][3], double DR[NG][6][3], double g[NG][4], int g2)
{
    for (int j = 0; j < NG; j++) {
        double ds = q2n_v3_norm(DR[j][2]), dt = q2n_v3_norm(DL[j][1]), dsl = q2n_v3_norm(DL[j][2]);
        if (!(fabs(g[j][1]) * dt <= Q2N_FIT_GLUE_EXACT * ds)) return 0;
        double dss = q2n_v3_norm(DR[j][5]) + ds;
        if (g2 && (!(fabs(g[j][2]) * dsl <= Q2N_FIT_GLUE_EXACT * dss) || !(fabs(g[j][3]) * dt <= Q2N_FIT_GLUE_EXACT * dss)))
            return 0;
    }
    return 1;
}

static void measure_one(void *arg, int e)
{
    classify_arg *a = arg;
    fit_ctx *c = a->c;
    fit_edge *E = &c->e[e];
    fit_side L, R;
    E->g1c = E->g2c = 0.0;
    E->rep = E->alpha_varies = 0;
    if (!q2n_fit_edge_sides(c, e, &L, &R)) { E->glue = E->glue2 = FIT_GLUE_BOUNDARY; return; }
    E->glue = E->glue2 = FIT_GLUE_LS;
    double DL[NG][6][3], DR[NG][6][3], g[NG][4];
    if ((a->st[e] = edge_samples(c, e, DL, DR, g))) return;
    /* the construction's own continuity at the interior samples */
    for (int j = 1; j + 1 < NG; j++) {
        double dl[18], dr[18], g1, g2;
        frame_as_uv(DL[j], dl);
        frame_as_uv(DR[j], dr);
        q2n_fit_jumps(dl, dr, DL[j][1], c->diag, &g1, &g2);
        if (!(g1 <= E->g1c)) E->g1c = g1;
        if (!(g2 <= E->g2c)) E->g2c = g2;
    }
    E->alpha0 = g[0][0];
    E->alpha1 = g[NG - 1][0];
    for (int j = 0; j < NG; j++)
        if (!(fabs(g[j][0] - g[0][0]) <= Q2N_FIT_GLUE_EXACT * fabs(g[0][0]))) E->alpha_varies = 1;
    /* a scale alpha(t) with alpha' = 0 at both ends (the reparametrization's corners need it):
     * alpha' from -d_ts S_R = alpha' d_s S_L + alpha d_ts S_L (beta = 0) */
    double flat = 1;
    for (int end = 0; end < 2; end++) {
        int j = end ? NG - 1 : 0;
        double w[3], nn = q2n_v3_dot(DL[j][2], DL[j][2]);
        for (int q = 0; q < 3; q++) w[q] = -DR[j][4][q] - g[j][0] * DL[j][4][q];
        double dal = q2n_v3_dot(w, DL[j][2]) / nn;
        /* relative to alpha times the derivative scale |d_ts S| / |d_s S| */
        double scale = fabs(g[j][0]) * (q2n_v3_norm(DL[j][4]) / sqrt(nn) + 1.0);
        if (!(fabs(dal) <= Q2N_FIT_GLUE_FLAT * scale)) flat = 0;
    }
    E->rep = !c->o.no_exact && flat && g[0][0] * g[NG - 1][0] > 0 && scale_only(DL, DR, g, c->o.continuity == 2);
}

/* fn on every edge, in parallel (side caches are written per side; two edges never share a side),
 * timed as sampling; the first edge whose construction evaluation failed is reported. */
static q2n_status each_edge(fit_ctx *c, void (*fn)(void *, int))
{
    int ne = c->m->ne;
    q2n_status *st = calloc((size_t)ne + 1, sizeof *st);
    if (!st) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    double t0 = q2n_now();
    classify_arg arg = {c, st};
    q2n_par_for(ne, c->o.threads, fn, &arg);
    c->rep->t_sample += q2n_now() - t0;
    q2n_status r = Q2N_OK;
    char where[64];
    for (int e = 0; e < ne && !r; e++)
        if (st[e]) r = q2n_error_set(c->err, st[e], "fit: edge %d (%s): construction evaluation %s", e, q2n_fit_edge_where(c, e, where, sizeof where),
                                     st[e] == Q2N_ERR_NUMERIC ? "not finite" : "failed");
    free(st);
    return r;
}

q2n_status q2n_fit_glue_measure(fit_ctx *c) { return each_edge(c, measure_one); }

static void classify_one(void *arg, int e)
{
    classify_arg *a = arg;
    fit_ctx *c = a->c;
    fit_edge *E = &c->e[e];
    if (E->glue == FIT_GLUE_BOUNDARY) return;
    double DL[NG][6][3], DR[NG][6][3], g[NG][4];
    if ((a->st[e] = edge_samples(c, e, DL, DR, g))) return;
    /* exact: alpha constant, beta = 0 (and gamma = delta = 0 for the G2 relation) */
    int exact = !c->o.no_exact;
    for (int j = 0; j < NG && exact; j++)
        if (!(fabs(g[j][0] - g[0][0]) <= Q2N_FIT_GLUE_EXACT * fabs(g[0][0]))) exact = 0;
    exact = exact && scale_only(DL, DR, g, 0);
    E->glue = exact ? FIT_GLUE_EXACT : FIT_GLUE_LS;
    E->glue2 = exact && scale_only(DL, DR, g, 1) ? FIT_GLUE_EXACT : FIT_GLUE_LS;
    E->alpha = g[0][0];
}

q2n_status q2n_fit_glue_classify(fit_ctx *c) { return each_edge(c, classify_one); }

/* ------------------------------------------------------------------ row blocks */

typedef struct row_block {
    int e, two, exact;
    int n;                   /* unknowns */
    int *vk, *vg;            /* patch and grid index of each unknown (one allocation at vk) */
    int m, capm;             /* fidelity (+ least-squares gluing) rows */
    double *A, *b;           /* row-major m x n, m x 3 */
    int nc, capc;            /* constraint rows */
    double *C, *d;           /* row-major nc x n, nc x 3 */
    double *Z, *xp;          /* null-space form: n x k (column-major), n x 3 (column-major) */
    int k;
    int var0;                /* first reduced unknown in the stage's problem */
    double resid;            /* constraint residual of x_p, relative */
    q2n_status st;
} row_block;

static void block_free(row_block *b)
{
    free(b->vk); /* and vg */
    free(b->A); free(b->b); free(b->C); free(b->d); free(b->Z); free(b->xp);
}

/* Room for at least `rows` rows of A and b (constraint == 0) or C and d (constraint == 1);
 * 0, or -1 when out of memory. */
static int block_reserve(row_block *bl, int constraint, int rows)
{
    int *cap = constraint ? &bl->capc : &bl->capm;
    double **M = constraint ? &bl->C : &bl->A, **R = constraint ? &bl->d : &bl->b;
    if (rows <= *cap) return 0;
    double *a = realloc(*M, sizeof(double) * (size_t)rows * (bl->n > 0 ? bl->n : 1));
    if (a) *M = a;
    double *r = a ? realloc(*R, 3 * sizeof(double) * (size_t)rows) : NULL;
    if (!a || !r) return -1;
    *R = r;
    *cap = rows;
    return 0;
}

/* Append a zero row to A (constraint == 0) or C (constraint == 1); returns its coefficients (n) and
 * right-hand side (3), or NULL when out of memory. */
static double *block_row(row_block *bl, int constraint, double **rhs)
{
    int *cnt = constraint ? &bl->nc : &bl->m, cap = constraint ? bl->capc : bl->capm;
    if (*cnt == cap && block_reserve(bl, constraint, cap ? 2 * cap : 64)) return NULL;
    double **M = constraint ? &bl->C : &bl->A, **R = constraint ? &bl->d : &bl->b;
    double *row = *M + (size_t)*cnt * bl->n;
    memset(row, 0, sizeof(double) * (size_t)bl->n);
    *rhs = *R + 3 * (size_t)*cnt;
    (*cnt)++;
    return row;
}

/* Side sd's spline bases at (t, 0): the span of t and the along basis with nder <= 2 derivatives
 * there (rows that use only values along the side ask for none: a third of the basis' cost), the
 * across basis at s = 0 (the same for every t of the side: computed once per block). */
typedef struct side_at {
    int span;
    double Nt[3][Q2N_FIT_DEG + 1];
    double (*Ns)[Q2N_FIT_DEG + 1];
} side_at;

static void side_at_t(const fit_side *sd, double (*Ns)[Q2N_FIT_DEG + 1], double t, int nder, side_at *A)
{
    A->span = q2n_fit_span(sd->nt, sd->kt, t);
    q2n_fit_basis(A->span, sd->kt, t, nder, A->Nt);
    A->Ns = Ns;
}

/* row += scale * d^a/dt^a d^b/ds^b S(t, 0) of side sd's spline (bases A at t, computed with at
 * least a derivatives): fixed control points go to rhs (subtracted), the block's unknowns (p->var)
 * to the row. */
static int add_deriv(fit_ctx *c, double *row, double *rhs, const fit_side *sd, const side_at *A, int a, int b, double scale)
{
    const fit_patch *p = &c->p[sd->k];
    for (int j = 0; j <= b; j++)
        for (int q = 0; q <= Q2N_FIT_DEG; q++) {
            double w = scale * A->Nt[a][q] * A->Ns[b][j];
            if (w == 0.0) continue;
            int g = q2n_fit_side_g(c, sd, A->span - Q2N_FIT_DEG + q, j);
            if (p->fixed[g]) q2n_v3_axpy(rhs, -w, p->cp + 3 * (size_t)g);
            else if (p->var[g] >= 0) row[p->var[g]] += w;
            else return -1;   /* a free point of another block: the stages' ordering forbids it */
        }
    return 0;
}

/* Number the block's unknowns: the free points of row `order` of each side. */
static int block_vars(fit_ctx *c, row_block *bl, const fit_side *sd, int nsd, int order)
{
    int cap = 0;   /* exactly the free points: every edge of the stage holds its block until the solve */
    for (int x = 0; x < nsd; x++) {
        if (order >= sd[x].ns) continue;
        const fit_patch *p = &c->p[sd[x].k];
        for (int it = 0; it < sd[x].nt; it++) {
            int g = q2n_fit_side_g(c, &sd[x], it, order);
            cap += !p->fixed[g] && p->var[g] < 0;
        }
    }
    bl->vk = malloc(2 * sizeof(int) * (size_t)(cap + 1));   /* vk, then vg */
    if (!bl->vk) return -1;
    bl->vg = bl->vk + cap + 1;
    bl->n = 0;
    for (int x = 0; x < nsd; x++) {
        if (order >= sd[x].ns) continue;
        fit_patch *p = &c->p[sd[x].k];
        for (int it = 0; it < sd[x].nt; it++) {
            int g = q2n_fit_side_g(c, &sd[x], it, order);
            if (p->fixed[g] || p->var[g] >= 0) continue;
            p->var[g] = bl->n;
            bl->vk[bl->n] = sd[x].k;
            bl->vg[bl->n++] = g;
        }
    }
    return 0;
}

/* Sorted distinct union of a and b (each sorted) into out; returns the count. */
static int union_sorted(int na, const double *a, int nb, const double *b, double *out)
{
    int i = 0, j = 0, n = 0;
    while (i < na || j < nb) {
        double x;
        if (j >= nb || (i < na && a[i] <= b[j])) x = a[i++];
        else x = b[j++];
        if (n == 0 || out[n - 1] != x) out[n++] = x;
    }
    return n;
}

/* Fidelity samples of side sd: its sample parameters (the ends are dropped by the caller). */
static int side_params(const fit_side *sd, double *out)
{
    return q2n_fit_sample_params(sd->nt, sd->kt, Q2N_FIT_SAMPLES_PER_SPAN, out);
}

/* Assemble block e for the given order: fidelity rows of each side's order-th cross derivative (in
 * control-point units), and the gluing relation — as constraint rows at 6 points per span of the
 * union knots when exact, else as weighted rows at every sample of either side. */
static q2n_status block_assemble(fit_ctx *c, row_block *bl, int order)
{
    fit_side sd[2];
    int e = bl->e, two = q2n_fit_edge_sides(c, e, &sd[0], &sd[1]);
    const fit_edge *E = &c->e[e];
    bl->two = two;
    bl->exact = two && (order == 1 ? E->glue : E->glue2) == FIT_GLUE_EXACT;
    if (block_vars(c, bl, sd, 1 + two, order)) return Q2N_ERR_NOMEM;
    if (bl->n == 0) return Q2N_OK;
    int nmax = sd[0].nt * Q2N_FIT_SAMPLES_PER_SPAN + (two ? sd[1].nt * Q2N_FIT_SAMPLES_PER_SPAN : 0) + 4;
    double *ts[2], *tu = malloc(sizeof(double) * (size_t)nmax), *D = malloc(18 * sizeof(double) * (size_t)nmax);
    double *DR = malloc(18 * sizeof(double) * (size_t)nmax);
    ts[0] = malloc(sizeof(double) * (size_t)nmax);
    ts[1] = malloc(sizeof(double) * (size_t)nmax);
    int ns[2] = {0, 0};
    q2n_status st = Q2N_OK;
    if (!tu || !D || !DR || !ts[0] || !ts[1]) { st = Q2N_ERR_NOMEM; goto out; }
    double Ns[2][3][Q2N_FIT_DEG + 1];
    for (int x = 0; x < 1 + two; x++) {
        q2n_fit_basis(Q2N_FIT_DEG, sd[x].ks, 0.0, 2, Ns[x]);
        ns[x] = side_params(&sd[x], ts[x]);
    }
    /* the rows to come (fidelity, and least-squares gluing at the union of both sides' samples) in
     * one allocation instead of doublings from 64 rows (malloc was 2 % of a large regular mesh's fit) */
    if (block_reserve(bl, 0, ns[0] + (two ? ns[1] : 0) + (two && !bl->exact ? ns[0] + ns[1] : 0))) { st = Q2N_ERR_NOMEM; goto out; }
    /* fidelity */
    for (int x = 0; x < 1 + two; x++) {
        if ((st = q2n_fit_side_values(c, sd[x].k, sd[x].i, ns[x], ts[x], D))) goto out;
        double sc = 1.0 / Ns[x][order][order];
        for (int q = 1; q + 1 < ns[x]; q++) {
            double *rhs, *row = block_row(bl, 0, &rhs);
            if (!row) { st = Q2N_ERR_NOMEM; goto out; }
            q2n_v3_scale(rhs, sc, D + 18 * (size_t)q + 3 * (order == 1 ? 2 : 5));
            side_at A;
            side_at_t(&sd[x], Ns[x], ts[x][q], 0, &A);
            if (add_deriv(c, row, rhs, &sd[x], &A, 0, order, sc)) { st = Q2N_ERR_ARG; goto out; }
        }
    }
    if (!two) goto out;
    double w1 = 1.0 / Ns[1][order][order];
    if (bl->exact) {
        /* d_s^o S_R(1 - t) - alpha^o d_s^o S_L(t) = 0 at 6 Chebyshev points of every span of the union
         * of L's breakpoints and R's mirrored ones: a degree-5 identity on each span */
        int nb = 0;
        for (int q = 0; q < sd[1].nt + 6; q++) tu[q] = 1.0 - sd[1].kt[sd[1].nt + 5 - q];
        double *brk = malloc(sizeof(double) * (size_t)(sd[0].nt + sd[1].nt + 12));
        if (!brk) { st = Q2N_ERR_NOMEM; goto out; }
        nb = union_sorted(sd[0].nt - 4, sd[0].kt + 5, sd[1].nt - 4, tu + 5, brk);   /* 0, breakpoints, 1 */
        double al = order == 1 ? E->alpha : E->alpha * E->alpha;
        for (int s = 0; s + 1 < nb && !st; s++)
            for (int q = 0; q < 6; q++) {
                double x = cos(Q2N_PI * (2 * q + 1) / 12.0), t = brk[s] + (brk[s + 1] - brk[s]) * 0.5 * (1.0 - x);
                double *rhs, *row = block_row(bl, 1, &rhs);
                if (!row) { st = Q2N_ERR_NOMEM; break; }
                rhs[0] = rhs[1] = rhs[2] = 0.0;
                side_at A0, A1;
                side_at_t(&sd[1], Ns[1], 1.0 - t, 0, &A1);
                side_at_t(&sd[0], Ns[0], t, 0, &A0);
                if (add_deriv(c, row, rhs, &sd[1], &A1, 0, order, w1) ||
                    add_deriv(c, row, rhs, &sd[0], &A0, 0, order, -al * w1)) {
                    st = Q2N_ERR_ARG;
                    break;
                }
            }
        free(brk);
        goto out;
    }
    /* least-squares gluing at every sample of either side (t in L's parameter) */
    for (int q = 0; q < ns[1]; q++) tu[q] = 1.0 - ts[1][ns[1] - 1 - q];
    {
        double *tt = malloc(sizeof(double) * (size_t)(ns[0] + ns[1])), *tr = malloc(sizeof(double) * (size_t)(ns[0] + ns[1]));
        if (!tt || !tr) { free(tt); free(tr); st = Q2N_ERR_NOMEM; goto out; }
        int nt = union_sorted(ns[0], ts[0], ns[1], tu, tt);
        for (int q = 0; q < nt; q++) tr[q] = 1.0 - tt[nt - 1 - q];
        if ((st = q2n_fit_side_values(c, sd[0].k, sd[0].i, nt, tt, D)) || (st = q2n_fit_side_values(c, sd[1].k, sd[1].i, nt, tr, DR))) {
            free(tt); free(tr);
            goto out;
        }
        double w = c->o.g1_weight * w1;
        for (int q = 1; q + 1 < nt && !st; q++) {
            double (*DLq)[3] = (double (*)[3])(D + 18 * (size_t)q), (*DRq)[3] = (double (*)[3])(DR + 18 * (size_t)(nt - 1 - q));
            double g[4], t = tt[q];
            glue_at((const double (*)[3])DLq, (const double (*)[3])DRq, g);
            double *rhs, *row = block_row(bl, 0, &rhs);
            if (!row) { st = Q2N_ERR_NOMEM; break; }
            rhs[0] = rhs[1] = rhs[2] = 0.0;
            side_at A0, A1;
            side_at_t(&sd[1], Ns[1], 1.0 - t, 0, &A1);
            side_at_t(&sd[0], Ns[0], t, order, &A0);
            int bad;
            if (order == 1)   /* d_s S_R - alpha d_s S_L - beta d_t S_L = 0 */
                bad = add_deriv(c, row, rhs, &sd[1], &A1, 0, 1, w) || add_deriv(c, row, rhs, &sd[0], &A0, 0, 1, -g[0] * w) ||
                      add_deriv(c, row, rhs, &sd[0], &A0, 1, 0, -g[1] * w);
            else              /* the G2 relation with gamma, delta the tangential part of the residual */
                bad = add_deriv(c, row, rhs, &sd[1], &A1, 0, 2, w) ||
                      add_deriv(c, row, rhs, &sd[0], &A0, 0, 2, -g[0] * g[0] * w) ||
                      add_deriv(c, row, rhs, &sd[0], &A0, 1, 1, -2 * g[0] * g[1] * w) ||
                      add_deriv(c, row, rhs, &sd[0], &A0, 2, 0, -g[1] * g[1] * w) ||
                      add_deriv(c, row, rhs, &sd[0], &A0, 0, 1, -g[2] * w) || add_deriv(c, row, rhs, &sd[0], &A0, 1, 0, -g[3] * w);
            if (bad) st = Q2N_ERR_ARG;
        }
        free(tt); free(tr);
    }
out:
    free(tu); free(D); free(DR); free(ts[0]); free(ts[1]);
    return st;
}

/* Null-space form of an exact block and its reduced rows: A Z y = b - A x_p.  A block whose
 * constraints cannot all hold (inconsistent corner data) keeps them as heavily weighted rows. */
static q2n_status block_reduce(fit_ctx *c, row_block *bl)
{
    if (!bl->exact || bl->n == 0 || bl->nc == 0) return Q2N_OK;
    int n = bl->n, nc = bl->nc;
    double *Cc = malloc(sizeof(double) * (size_t)nc * n), *Dc = malloc(3 * sizeof(double) * (size_t)nc);
    bl->Z = malloc(sizeof(double) * (size_t)n * n);
    bl->xp = malloc(3 * sizeof(double) * (size_t)n);
    if (!Cc || !Dc || !bl->Z || !bl->xp) { free(Cc); free(Dc); return Q2N_ERR_NOMEM; }
    double scale = 0.0;
    for (int r = 0; r < nc; r++) {
        for (int j = 0; j < n; j++) {
            Cc[(size_t)j * nc + r] = bl->C[(size_t)r * n + j];
            if (fabs(bl->C[(size_t)r * n + j]) > scale) scale = fabs(bl->C[(size_t)r * n + j]);
        }
        for (int q = 0; q < 3; q++) Dc[(size_t)q * nc + r] = bl->d[3 * (size_t)r + q];
    }
    int rc = q2n_dense_nullspace(nc, n, Cc, nc, 3, Dc, nc, Q2N_FIT_CONSTRAINT_RCOND, bl->Z, &bl->k, bl->xp, &bl->resid);
    free(Cc);
    free(Dc);
    if (rc) return rc > 0 ? Q2N_ERR_NOMEM : Q2N_ERR_ARG;
    /* the residual against the size of the terms: control points of the patch (diag) times the
     * largest coefficient */
    bl->resid /= (scale > 0 ? scale : 1.0) * c->diag;
    if (!(bl->resid <= Q2N_FIT_CONSTRAINT_RESID)) {
        /* inconsistent: least squares with the constraint rows weighted like gluing rows */
        for (int r = 0; r < nc; r++) {
            double *rhs, *row = block_row(bl, 0, &rhs);
            if (!row) return Q2N_ERR_NOMEM;
            for (int j = 0; j < n; j++) row[j] = c->o.g1_weight * bl->C[(size_t)r * n + j];
            for (int q = 0; q < 3; q++) rhs[q] = c->o.g1_weight * bl->d[3 * (size_t)r + q];
        }
        bl->exact = 0;
        return Q2N_OK;
    }
    /* reduced rows in place: A <- A Z (m x k), b <- b - A x_p */
    int m = bl->m, k = bl->k;
    double *AZ = malloc(sizeof(double) * (size_t)(m > 0 ? m : 1) * (k > 0 ? k : 1));
    if (!AZ) return Q2N_ERR_NOMEM;
    for (int i = 0; i < m; i++) {
        const double *a = bl->A + (size_t)i * n;
        for (int q = 0; q < 3; q++) {
            double w = 0.0;
            for (int j = 0; j < n; j++) w += a[j] * bl->xp[(size_t)q * n + j];
            bl->b[3 * (size_t)i + q] -= w;
        }
        for (int col = 0; col < k; col++) {
            double w = 0.0;
            for (int j = 0; j < n; j++) w += a[j] * bl->Z[(size_t)col * n + j];
            AZ[(size_t)i * k + col] = w;
        }
    }
    free(bl->A);
    bl->A = AZ;
    return Q2N_OK;
}

typedef struct rows_arg {
    fit_ctx *c;
    row_block *bl;
    int order;
} rows_arg;

static void rows_one(void *arg, int l)
{
    rows_arg *a = arg;
    row_block *bl = &a->bl[l];
    bl->st = block_assemble(a->c, bl, a->order);
    if (!bl->st) bl->st = block_reduce(a->c, bl);
}

q2n_status q2n_fit_rows_stage(fit_ctx *c, const int *edges, int n, int order)
{
    row_block *bl = calloc((size_t)n + 1, sizeof *bl);
    if (!bl) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    for (int l = 0; l < n; l++) bl[l].e = edges[l];
    q2n_status st = Q2N_OK;
    /* assembly reads the construction through the side caches, written per side: the edges'
     * blocks own disjoint sides and disjoint unknowns, so they are assembled in parallel */
    double t0 = q2n_now();
    rows_arg arg = {c, bl, order};
    q2n_par_for(n, c->o.threads, rows_one, &arg);
    c->rep->t_sample += q2n_now() - t0;
    for (int l = 0; l < n && !st; l++)
        if (bl[l].st)
            st = q2n_error_set(c->err, bl[l].st, "fit: edge %d: %s rows: %s", bl[l].e, order == 1 ? "first" : "second",
                               bl[l].st == Q2N_ERR_NOMEM ? "out of memory" :
                               bl[l].st == Q2N_ERR_ARG ? "internal block error" : "construction evaluation failed");
    for (int l = 0; l < n && !st; l++) {
        row_block *b = &bl[l];
        int cols = b->exact && b->nc ? b->k : b->n;
        if (b->n == 0 || cols == 0) continue;
        if (b->m < cols) {   /* too few samples for the free points (cannot happen with 4 per span) */
            st = q2n_error_set(c->err, Q2N_ERR_GEOMETRY, "fit: edge %d: %d rows for %d unknowns", b->e, b->m, cols);
            break;
        }
        if (q2n_fit_ls_dense_item(&c->ls, b->m, cols, b->A, b->b, &b->var0))
            st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
        /* the problem holds the rows now: only the map back (vk, vg, Z, xp) is kept for the solve */
        free(b->A); free(b->b); free(b->C); free(b->d);
        b->A = b->b = b->C = b->d = NULL;
    }
    if (!st) {
        double t1 = q2n_now();
        st = q2n_fit_ls_solve(&c->ls, c->o.solver, c->o.threads, c->err);
        c->rep->t_solve += q2n_now() - t1;
    }
    for (int l = 0; l < n; l++) {
        row_block *b = &bl[l];
        if (!st && b->n > 0) {
            int red = b->exact && b->nc;
            for (int j = 0; j < b->n; j++) {
                double x[3];
                if (red) {
                    for (int q = 0; q < 3; q++) {
                        double w = b->xp[(size_t)q * b->n + j];
                        for (int col = 0; col < b->k; col++) w += b->Z[(size_t)col * b->n + j] * c->ls.x[3 * (size_t)(b->var0 + col) + q];
                        x[q] = w;
                    }
                } else
                    memcpy(x, c->ls.x + 3 * (size_t)(b->var0 + j), sizeof x);
                fit_patch *p = &c->p[b->vk[j]];
                memcpy(p->cp + 3 * (size_t)b->vg[j], x, sizeof x);
                p->fixed[b->vg[j]] = 1;
            }
        }
        int *kind = order == 1 ? &c->e[b->e].glue : &c->e[b->e].glue2;
        if (!st && b->two && *kind == FIT_GLUE_EXACT && !b->exact) *kind = FIT_GLUE_LS;   /* inconsistent: demoted */
        for (int j = 0; j < b->n; j++) c->p[b->vk[j]].var[b->vg[j]] = -1;
        block_free(b);
    }
    q2n_fit_ls_clear(&c->ls);
    free(bl);
    return st;
}
