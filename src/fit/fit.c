/* fit.c — bi-quintic B-spline fit of a composite surface, watertight and G1/G2 across edges.
 *
 * Method (docs/fit.md has the long form).  Every patch k becomes a clamped bi-quintic B-spline on
 * [0,1]^2 with uniform interior knots: m_u spans in u and m_v in v, where the span count belongs
 * to the patch's edge RIBBON (q2n_mesh_ribbons), so both sides of every edge use the same knots
 * along it.  One fitting round for given span counts runs these linear stages (each a set of
 * independent least-squares blocks solved by Ceres, or by the direct QR reference):
 *
 *  1. corners: the patch corners are the mesh vertices (exact, bit-identical everywhere; for a
 *     construction that does not interpolate its vertices, one patch's corner point);
 *  2. edge curves: each mesh edge's boundary curve is fitted ONCE (1-D least squares of the
 *     owner patch's edge at 4m+4 samples) with Hermite end conditions — value, first and second
 *     derivative along the edge equal the construction's at both ends (exact) — and copied into
 *     both neighbours' boundary rows (bit-identical shared control points: G0 is exact);
 *  3. corner jets: the point diagonal to each corner (Q11) reproduces the construction's twist
 *     d2S/dtds there, and in G2 mode Q21, Q12, Q22 reproduce d_t^2 d_s, d_t d_s^2, d_t^2 d_s^2
 *     (exact in the spline space up to one-sided differences that are exact for quintics).
 *     With the Hermite edge curves this fixes each corner's jet from the construction, so the
 *     G1 (G2) relations of all edges meeting at a vertex are consistent there: vertex
 *     enclosure is inherited from the construction.  Gregory-type corners, where the two edges
 *     disagree about a mixed derivative, get the average twist and leave the higher points to
 *     the fits (stage_corners, stage_prefit);
 *  4. G1 rows: for each interior edge the free points of the first control rows of BOTH sides
 *     are fitted jointly: fidelity to each side's exact cross-boundary derivative at the edge
 *     samples, plus the gluing relation  d_s S_R = alpha d_s S_L + beta d_t S_L  (formulas.md
 *     §4.2, G1; seed 003 Prop. 2, eqs. 13–14) with alpha(t), beta(t) computed from the
 *     construction's exact derivatives, weighted by g1_weight, at the same samples.  The
 *     relation therefore holds in the least-squares sense at the collocation points, not
 *     exactly between them; the measured angle jump at the midpoints is reported and drives
 *     refinement.  Boundary edges: fidelity only;
 *  5. (G2 mode) the same for the second rows with the second-order relation of formulas.md
 *     §4.2 (gamma, delta = tangential part of the construction's own second-order residual);
 *  6. interiors: the remaining control points of each patch, least squares at a (4m_u+4) x
 *     (4m_v+4) sample grid, solved separably (stage_interior).
 * Then deviation (at the midpoints of the sample grid) and continuity (at the midpoints of the
 * edge samples) are measured, and the limiting ribbons of failing patches (by direction, from
 * 6th differences of the construction) and the ribbons along failing edges get more spans
 * (m <- max(m+1, ceil(1.15 m ratio^(1/order))), order 6, 5, 4 for deviation, normal and
 * curvature jumps of quintics), until all targets hold, continuity stalls (fit_all), or the
 * caps are reached.
 *
 * Bézier patches (ACC path) are converted exactly: degree elevated to 5 x 5 (Farin, Curves and
 * Surfaces for CAGD, §5.1: b_i' = i/(n+1) b_{i-1} + (1 - i/(n+1)) b_i), one span.  Why quintic
 * and not cubic: every patch of every model then has one degree, so edge curves of neighbours
 * (cubic ACC faces next to quintic G1 faces near extraordinary vertices) have identical control
 * points and knots, which the one-edge-curve-per-mesh-edge STEP/IGES writers need. */
#include "fit/fit.h"
#include "fit/fit_internal.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>   /* snprintf */
#include <string.h>

static const int corner_uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

typedef struct fpatch {
    int mu, mv, nu, nv;
    double *ku, *kv;         /* knot vectors (mu+11, mv+11) */
    double *cp;              /* 3*nu*nv, u fastest */
    unsigned char *fixed;    /* nu*nv */
    int *var;                /* nu*nv: unknown index in the current stage, or -1 */
    int unsafe22;            /* bit i: corner i's Q22 comes from the preliminary fit (G2 mode) */
    int gregory;             /* bit i: the edges through corner i disagree about a mixed derivative */
} fpatch;

/* Frame of side i of a patch: t along the side (corner i -> i+1), s into the patch. */
typedef struct side {
    int k, i;                /* patch and side */
    int ox, oy;              /* corner in grid index space */
    int tx, ty, sx, sy;      /* unit steps of t and s in (u,v) (and grid index) space */
    int nt, ns, mt, ms;      /* control points / spans along and across */
    const double *kt, *ks;   /* knots along and across */
} side;

typedef struct ctx {
    const q2n_surface *s;
    const q2n_mesh *m;
    q2n_fit_options o;
    double diag;
    int *rib, nrib, *rspan;
    fpatch *p;
    fit_ls ls;
    int *var_k, *var_g, cap_var;
    double (*jet)[4][4][4];  /* cached corner jets (compute_jets) */
    double *edata;           /* edge samples of the current round (edge_samples) */
    double *vpos;            /* nv: patch corner point of every vertex (stage_curves) */
    size_t *eoff;
    q2n_fit_report *rep;
    q2n_error *err;
} ctx;

/* A row under construction: unknown terms plus right-hand side (fixed terms moved over). */
#define ROW_MAX 256
typedef struct row {
    int n;
    int var[ROW_MAX];
    double val[ROW_MAX];
    double rhs[3];
} row;

void q2n_fit_options_default(q2n_fit_options *o)
{
    memset(o, 0, sizeof *o);
    o->tol = 1e-5;
    o->continuity = 1;
    o->threads = 1;
    o->solver = Q2N_FIT_SOLVER_CERES;
    o->max_spans = 48;
    o->max_rounds = 10;
    o->g1_target_deg = 0.005;
    o->g2_target_rel = 0.005;
    o->g1_weight = 100.0;
}

static void fill_defaults(q2n_fit_options *o, const q2n_fit_options *in)
{
    q2n_fit_options d;
    q2n_fit_options_default(&d);
    *o = in ? *in : d;
    if (o->tol <= 0) o->tol = d.tol;
    if (o->continuity != 2) o->continuity = 1;
    if (o->threads <= 0) o->threads = d.threads;
    if (o->max_spans <= 0) o->max_spans = d.max_spans;
    if (o->max_spans > FIT_MAX_SPANS) o->max_spans = FIT_MAX_SPANS;
    if (o->max_rounds <= 0) o->max_rounds = d.max_rounds;
    if (o->g1_target_deg <= 0) o->g1_target_deg = d.g1_target_deg;
    if (o->g2_target_rel <= 0) o->g2_target_rel = d.g2_target_rel;
    if (o->g1_weight <= 0) o->g1_weight = d.g1_weight;
}

/* ------------------------------------------------------------------ construction access */

static side make_side(const ctx *c, int k, int i)
{
    const fpatch *p = &c->p[k];
    const int *c0 = corner_uv[i], *c1 = corner_uv[(i + 1) & 3], *c3 = corner_uv[(i + 3) & 3];
    side sd;
    sd.k = k; sd.i = i;
    sd.ox = c0[0] * (p->nu - 1); sd.oy = c0[1] * (p->nv - 1);
    sd.tx = c1[0] - c0[0]; sd.ty = c1[1] - c0[1];
    sd.sx = c3[0] - c0[0]; sd.sy = c3[1] - c0[1];
    int along_u = sd.tx != 0;
    sd.nt = along_u ? p->nu : p->nv; sd.ns = along_u ? p->nv : p->nu;
    sd.mt = along_u ? p->mu : p->mv; sd.ms = along_u ? p->mv : p->mu;
    sd.kt = along_u ? p->ku : p->kv; sd.ks = along_u ? p->kv : p->ku;
    return sd;
}

/* Grid index of the control point it along, js across the side. */
static int side_g(const ctx *c, const side *sd, int it, int js)
{
    int a = sd->ox + it * sd->tx + js * sd->sx, b = sd->oy + it * sd->ty + js * sd->sy;
    return b * c->p[sd->k].nu + a;
}

/* Exact derivatives of patch k in the frame of its side i at (t, s): D[0] = S, D[1] = d_t,
 * D[2] = d_s, D[3] = d_tt, D[4] = d_ts, D[5] = d_ss (3 each).  Reads shared data only. */
static q2n_status frame_eval(const q2n_surface *surf, int k, int i, double t, double s, int nder, double D[6][3])
{
    const int *c0 = corner_uv[i], *c1 = corner_uv[(i + 1) & 3], *c3 = corner_uv[(i + 3) & 3];
    int ax[2] = {c1[0] - c0[0], c3[0] - c0[0]}, ay[2] = {c1[1] - c0[1], c3[1] - c0[1]};
    double u = c0[0] + t * ax[0] + s * ax[1], v = c0[1] + t * ay[0] + s * ay[1];
    double e[Q2N_EVAL_MAX];
    q2n_status st = q2n_surface_eval(surf, k, u, v, nder, e);
    if (st) return st;
    for (int q = 0; q < 3 * (nder == 0 ? 1 : nder == 1 ? 3 : 6); q++)
        if (!isfinite(e[q])) return Q2N_ERR_NUMERIC;
    for (int q = 0; q < 3; q++) {
        D[0][q] = e[q];
        if (nder < 1) continue;
        D[1][q] = ax[0] * e[Q2N_EV_U + q] + ay[0] * e[Q2N_EV_V + q];
        D[2][q] = ax[1] * e[Q2N_EV_U + q] + ay[1] * e[Q2N_EV_V + q];
        if (nder < 2) continue;
        static const int pr[3][2] = {{0, 0}, {0, 1}, {1, 1}};
        for (int r = 0; r < 3; r++) {
            int a = pr[r][0], b = pr[r][1];
            D[3 + r][q] = ax[a] * ax[b] * e[Q2N_EV_UU + q] + (ax[a] * ay[b] + ay[a] * ax[b]) * e[Q2N_EV_UV + q] +
                          ay[a] * ay[b] * e[Q2N_EV_VV + q];
        }
    }
    return Q2N_OK;
}

/* Exact derivatives in the side frame at (t, s): D[0] = S, D[1] = d_t, D[2] = d_s, D[3] = d_tt,
 * D[4] = d_ts, D[5] = d_ss (3 each); errors name the face and the point. */
static q2n_status side_exact(ctx *c, const side *sd, double t, double s, int nder, double D[6][3])
{
    double t0 = fit_now();
    q2n_status st = frame_eval(c->s, sd->k, sd->i, t, s, nder, D);
    c->rep->t_sample += fit_now() - t0;
    if (st)
        return q2n_error_set(c->err, st, "fit: face %d: evaluation %s at side %d (t %g, s %g)", sd->k,
                             st == Q2N_ERR_NUMERIC ? "not finite" : "failed", sd->i, t, s);
    return Q2N_OK;
}

/* ------------------------------------------------------------------ row assembly */

static q2n_status add_term(ctx *c, row *r, int k, int g, double coef)
{
    fpatch *p = &c->p[k];
    if (coef == 0.0) return Q2N_OK;
    if (p->fixed[g]) {
        q2n_v3_axpy(r->rhs, -coef, p->cp + 3 * (size_t)g);
        return Q2N_OK;
    }
    if (p->var[g] < 0) {
        int id;
        fit_ls_new_var(&c->ls, &id);
        if (id >= c->cap_var) {
            int nc = c->cap_var ? 2 * c->cap_var : 1024;
            int *a = realloc(c->var_k, sizeof(int) * (size_t)nc), *b = a ? realloc(c->var_g, sizeof(int) * (size_t)nc) : NULL;
            if (a) c->var_k = a;
            if (!a || !b) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (unknowns)");
            c->var_g = b;
            c->cap_var = nc;
        }
        c->var_k[id] = k;
        c->var_g[id] = g;
        p->var[g] = id;
    }
    for (int i = 0; i < r->n; i++)
        if (r->var[i] == p->var[g]) { r->val[i] += coef; return Q2N_OK; }
    if (r->n == ROW_MAX) return q2n_error_set(c->err, Q2N_ERR_ARG, "fit: row too long");
    r->var[r->n] = p->var[g];
    r->val[r->n++] = coef;
    return Q2N_OK;
}

static void row_start(row *r, const double target[3], double scale)
{
    r->n = 0;
    q2n_v3_scale(r->rhs, scale, target);
}

static q2n_status row_push(ctx *c, row *r)
{
    if (r->n == 0) return Q2N_OK;     /* only fixed points: nothing to fit */
    if (fit_ls_row(&c->ls, r->rhs)) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (rows)");
    for (int i = 0; i < r->n; i++)
        if (fit_ls_entry(&c->ls, r->var[i], r->val[i])) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    return Q2N_OK;
}

/* Add  scale * d^a/dt^a d^b/ds^b S(t, 0)  of the spline on side sd (b <= 2) to row r. */
static q2n_status add_deriv(ctx *c, row *r, const side *sd, double t, int a, int b, double scale)
{
    double Nt[3][FIT_DEG + 1], Ns[3][FIT_DEG + 1];
    int span = fit_span(sd->nt, sd->kt, t);
    fit_basis(span, sd->kt, t, 2, Nt);
    fit_basis(FIT_DEG, sd->ks, 0.0, 2, Ns);
    for (int j = 0; j <= b; j++)
        for (int q = 0; q <= FIT_DEG; q++) {
            double w = scale * Nt[a][q] * Ns[b][j];
            q2n_status st = add_term(c, r, sd->k, side_g(c, sd, span - FIT_DEG + q, j), w);
            if (st) return st;
        }
    return Q2N_OK;
}

/* Solve the assembled stage and store the unknowns as fixed control points. */
/* Solve the assembled problem with the configured solver (solution in c->ls.x). */
static q2n_status solve_ls(ctx *c)
{
    fit_ls_item_end(&c->ls);
    double t0 = fit_now();
    q2n_status st;
    if (c->o.solver == Q2N_FIT_SOLVER_DIRECT) st = fit_ls_solve_direct(&c->ls, c->err);
    else st = fit_ls_solve_ceres(&c->ls, c->o.threads, c->o.solver == Q2N_FIT_SOLVER_CERES, c->err);
    c->rep->t_solve += fit_now() - t0;
    return st;
}

static q2n_status solve_stage(ctx *c)
{
    q2n_status st = solve_ls(c);
    if (st) return st;
    for (int v = 0; v < c->ls.nvar; v++) {
        fpatch *p = &c->p[c->var_k[v]];
        int g = c->var_g[v];
        memcpy(p->cp + 3 * (size_t)g, c->ls.x + 3 * (size_t)v, 3 * sizeof(double));
        p->fixed[g] = 1;
        p->var[g] = -1;
    }
    fit_ls_clear(&c->ls);
    return Q2N_OK;
}

/* ------------------------------------------------------------------ stages */

/* Side frames of the two faces of edge e: L = owner half-edge's face (its t is the edge's t),
 * R = the twin's (t_R = 1 - t); returns 0 for R on boundary edges. */
static int edge_sides(const ctx *c, int e, side *L, side *R)
{
    const q2n_mesh *m = c->m;
    int h = m->edge_he[e], ht = m->he_twin[h];
    *L = make_side(c, m->he_face[h], h - m->face_start[m->he_face[h]]);
    if (ht < 0) return 0;
    *R = make_side(c, m->he_face[ht], ht - m->face_start[m->he_face[ht]]);
    return 1;
}

/* Stage 1 + 2: corners, Hermite end conditions and least-squares fit of every edge curve, copied
 * to both sides. */
static q2n_status stage_curves(ctx *c)
{
    const q2n_mesh *m = c->m;
    if (!c->vpos) {   /* corner points, once per fit */
        c->vpos = malloc(3 * sizeof(double) * (size_t)m->nv);
        if (!c->vpos) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
        for (int v = 0; v < m->nv; v++) {
            double *P = c->vpos + 3 * (size_t)v;
            memcpy(P, q2n_mesh_vpos(m, v), 3 * sizeof(double));
            int h = m->vert_he[v];
            if (h < 0) continue;
            /* an interpolating construction passes through the vertex: keep the vertex exactly;
             * otherwise (a construction whose corners are not the vertices) take the corner of
             * the patch of the vertex's first half-edge, the same point for every patch */
            double D[6][3];
            side sd = make_side(c, m->he_face[h], h - m->face_start[m->he_face[h]]);
            q2n_status st = side_exact(c, &sd, 0.0, 0.0, 0, D);
            if (st) return st;
            if (q2n_v3_dist(D[0], P) > 1e-9 * c->diag) memcpy(P, D[0], 3 * sizeof(double));
        }
    }
    for (int k = 0; k < m->nf; k++)
        for (int i = 0; i < 4; i++) {
            side sd = make_side(c, k, i);
            int g = side_g(c, &sd, 0, 0);
            memcpy(c->p[k].cp + 3 * (size_t)g, c->vpos + 3 * (size_t)m->face_vert[m->face_start[k] + i], 3 * sizeof(double));
            c->p[k].fixed[g] = 1;
        }
    for (int e = 0; e < m->ne; e++) {
        side L, R;
        edge_sides(c, e, &L, &R);
        fpatch *p = &c->p[L.k];
        /* Hermite ends: d/dt and d2/dt2 of the spline at t = 0, 1 equal the construction's. */
        for (int end = 0; end < 2; end++) {
            double D[6][3], N[3][FIT_DEG + 1];
            q2n_status st = side_exact(c, &L, end, 0.0, 2, D);
            if (st) return st;
            int span = end ? L.nt - 1 : FIT_DEG;
            fit_basis(span, L.kt, (double)end, 2, N);
            /* indices (in N) of the end point, its neighbour and the next one */
            int q0 = end ? FIT_DEG : 0, q1 = end ? FIT_DEG - 1 : 1, q2 = end ? FIT_DEG - 2 : 2;
            int i0 = end ? L.nt - 1 : 0, i1 = end ? L.nt - 2 : 1, i2 = end ? L.nt - 3 : 2;
            double *P0 = p->cp + 3 * (size_t)side_g(c, &L, i0, 0);
            double *P1 = p->cp + 3 * (size_t)side_g(c, &L, i1, 0);
            double *P2 = p->cp + 3 * (size_t)side_g(c, &L, i2, 0);
            for (int q = 0; q < 3; q++) {
                P1[q] = (D[1][q] - N[1][q0] * P0[q]) / N[1][q1];
                P2[q] = (D[3][q] - N[2][q0] * P0[q] - N[2][q1] * P1[q]) / N[2][q2];
            }
            p->fixed[side_g(c, &L, i1, 0)] = p->fixed[side_g(c, &L, i2, 0)] = 1;
        }
    }
    /* interior curve points: one least-squares block per edge */
    for (int e = 0; e < m->ne; e++) {
        side L, R;
        edge_sides(c, e, &L, &R);
        if (fit_ls_item_begin(&c->ls)) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
        int N = fit_nsamples(L.mt);
        for (int k = 1; k + 1 < N; k++) {
            double t = (double)k / (N - 1), D[6][3];
            q2n_status st = side_exact(c, &L, t, 0.0, 0, D);
            if (st) return st;
            row r;
            row_start(&r, D[0], 1.0);
            if ((st = add_deriv(c, &r, &L, t, 0, 0, 1.0)) || (st = row_push(c, &r))) return st;
            c->rep->samples++;
        }
    }
    q2n_status st = solve_stage(c);
    if (st) return st;
    for (int e = 0; e < m->ne; e++) {
        side L, R;
        if (!edge_sides(c, e, &L, &R)) continue;
        for (int it = 0; it < L.nt; it++) {      /* bit-identical copy, reversed */
            int gl = side_g(c, &L, it, 0), gr = side_g(c, &R, R.nt - 1 - it, 0);
            memcpy(c->p[R.k].cp + 3 * (size_t)gr, c->p[L.k].cp + 3 * (size_t)gl, 3 * sizeof(double));
            c->p[R.k].fixed[gr] = 1;
        }
    }
    return Q2N_OK;
}

/* One-sided weights at 0 for the nodes h, 2h, .., 6h (the corner itself is avoided: Gregory-type
 * corners have direction-dependent mixed derivatives there): value, first and second derivative
 * of the quintic through the six values, exact for polynomials of degree <= 5 (so bi-quintic
 * patches are reproduced to rounding); h = 0.01 keeps the rounding of the second derivative
 * near 2e-10 relative. */
static const double FD[3][6] = {{6, -15, 20, -15, 6, -1},
                                {-87.0 / 10, 117.0 / 4, -127.0 / 3, 33, -27.0 / 2, 137.0 / 60},
                                {29.0 / 3, -461.0 / 12, 62, -307.0 / 6, 65.0 / 3, -15.0 / 4}};

/* Mixed corner derivative J = d_t^a d_s^b S(0,0) (a, b in 1..2) of side sd: exact from the
 * construction where it reports the two sides' values (q2n_surface_corner_mixed), else read along both
 * edges through the corner and averaged (they agree for a smooth patch; Gregory-type corners
 * have direction-dependent mixed derivatives, and the average is the compromise).  Along s = 0
 * it is the nd-th t-derivative of an evaluated second-derivative field at (t, 0), along t = 0
 * the nd-th s-derivative of one at (0, s) (nd = 0: extrapolated value).  Patch k, corner i. */
static q2n_status corner_mixed(const q2n_surface *surf, int k, int i, int a, int b, double J[3], double *spread)
{
    /* exact values where the construction provides them (Coons–Gregory patches) */
    double X[2][2][2][3];
    const int *c0 = corner_uv[i], *c1 = corner_uv[(i + 1) & 3], *c3 = corner_uv[(i + 3) & 3];
    if (q2n_surface_corner_mixed(surf, k, c0[0], c0[1], X) == Q2N_OK) {
        /* d_t, d_s are ±d_u, ±d_v (or swapped): the edge from corner i to i+1 is t */
        int tu = c1[0] != c0[0];
        double st = tu ? c1[0] - c0[0] : c1[1] - c0[1], ss = tu ? c3[1] - c0[1] : c3[0] - c0[0];
        int au = tu ? a : b, bv = tu ? b : a; /* orders in u and v */
        double sg = (a & 1 ? st : 1) * (b & 1 ? ss : 1);
        const double *E0 = X[0][au - 1][bv - 1], *E1 = X[1][au - 1][bv - 1];
        for (int r = 0; r < 3; r++) J[r] = sg * 0.5 * (E0[r] + E1[r]);
        *spread = q2n_v3_dist(E0, E1);
        return Q2N_OK;
    }
    /* [a-1][b-1][edge] = {slot of frame_eval's D (3 d_tt, 4 d_ts, 5 d_ss), nd} */
    static const int tab[2][2][2][2] = {{{{4, 0}, {4, 0}}, {{5, 1}, {4, 1}}},
                                        {{{4, 1}, {3, 1}}, {{5, 2}, {3, 2}}}};
    const double h = 0.002;
    double E[2][3] = {{0, 0, 0}, {0, 0, 0}};
    for (int dir = 0; dir < 2; dir++) {
        int slot = tab[a - 1][b - 1][dir][0], nd = tab[a - 1][b - 1][dir][1];
        const double *w = FD[nd];
        double scale = nd == 0 ? 1.0 : nd == 1 ? 1.0 / h : 1.0 / (h * h);
        for (int q = 1; q <= 6; q++) {
            double D[6][3];
            q2n_status st = frame_eval(surf, k, i, dir ? 0.0 : q * h, dir ? q * h : 0.0, 2, D);
            if (st) return st;
            q2n_v3_axpy(E[dir], w[q - 1] * scale, D[slot]);
        }
    }
    for (int r = 0; r < 3; r++) J[r] = 0.5 * (E[0][r] + E[1][r]);
    *spread = q2n_v3_dist(E[0], E[1]);
    return Q2N_OK;
}

/* Stage 3: the corner blocks.  Q11 (and in G2 mode Q21, Q12, Q22) of every corner reproduce the
 * construction's mixed derivatives d_t^a d_s^b S at the corner: exact in the spline space up to
 * the one-sided differences of corner_mixed (exact for bi-quintic patches).  With the Hermite
 * edge curves this fixes the 2-jet (the jets of rows 0..2 in G2 mode) at every corner, so the
 * G1/G2 relations of all edges through a vertex hold there to that order: the vertex-enclosure
 * conditions are inherited from the construction, which satisfies them.  Where the two edges
 * through a corner disagree about a higher mixed derivative by more than a tenth of the
 * tolerance in control-point terms (Gregory-type corners, whose rational blends make it
 * direction-dependent), Q21/Q12 are left to the row fits and Q22 to a preliminary interior fit
 * (stage_prefit); the twist is always the average of the two edge-wise values. */
/* Corner jets depend on the construction only, not on the knots: computed once per fit, patches
 * spread over the worker threads (jet[k][corner][order] = J[3], spread). */
typedef struct jet_arg {
    const q2n_surface *s;
    double (*jet)[4][4][4];
    int npin;
    q2n_status *st;
} jet_arg;

static const int jet_order[4][2] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};

static void jet_one(void *arg, int k)
{
    jet_arg *a = arg;
    for (int i = 0; i < 4 && !a->st[k]; i++)
        for (int o = 0; o < a->npin && !a->st[k]; o++) {
            double *J = a->jet[k][i][o];
            a->st[k] = corner_mixed(a->s, k, i, jet_order[o][0], jet_order[o][1], J, &J[3]);
        }
}

static q2n_status compute_jets(ctx *c)
{
    int nf = c->m->nf;
    c->jet = malloc(sizeof *c->jet * (size_t)nf);
    q2n_status *st = calloc((size_t)nf, sizeof *st);
    if (!c->jet || !st) { free(st); return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (jets)"); }
    jet_arg arg = {c->s, c->jet, 4, st};
    double t0 = fit_now();
    fit_par_for(nf, c->o.threads, jet_one, &arg);
    c->rep->t_sample += fit_now() - t0;
    q2n_status r = Q2N_OK;
    for (int k = 0; k < nf && !r; k++)
        if (st[k]) r = q2n_error_set(c->err, st[k], "fit: face %d: corner derivatives %s", k,
                                     st[k] == Q2N_ERR_NUMERIC ? "not finite" : "cannot be evaluated");
    free(st);
    return r;
}

#define FIT_JET_SPREAD 0.1   /* fraction of the tolerance two corner estimates may disagree by */
static q2n_status stage_corners(ctx *c)
{
    /* G1 mode too pins Q21, Q12 (first rows; a consistent corner jet makes the G1 relation hold
     * there to that order), but not Q22: inside the interior block it would break its tensor
     * structure (stage_interior) */
    int npin = c->o.continuity == 2 ? 4 : 3;
    q2n_status st0 = c->jet ? Q2N_OK : compute_jets(c);
    if (st0) return st0;
    for (int k = 0; k < c->m->nf; k++) {
        c->p[k].unsafe22 = c->p[k].gregory = 0;
        for (int i = 0; i < 4; i++) {
            side sd = make_side(c, k, i);
            double Nt[3][FIT_DEG + 1], Ns[3][FIT_DEG + 1];
            fit_basis(FIT_DEG, sd.kt, 0.0, 2, Nt);
            fit_basis(FIT_DEG, sd.ks, 0.0, 2, Ns);
            fpatch *p = &c->p[k];
            int unsafe = 0;
            for (int o = 0; o < npin; o++) {
                int a = jet_order[o][0], b = jet_order[o][1];
                double J[3], spread = c->jet[k][i][o][3];
                memcpy(J, c->jet[k][i][o], sizeof J);
                /* the two edge-wise estimates as positions of the control point they fix, for one
                 * span (Bézier factors d^a B_a(0) = 5, 20 for a = 1, 2), so that the verdict does
                 * not change as refinement shrinks the corner's influence */
                double dq = spread / ((a == 1 ? 5.0 : 20.0) * (b == 1 ? 5.0 : 20.0));
                /* a disagreement in the fourth-order term (2,2) alone leaves the patch C3 at the
                 * corner: its curvature is followed, only Q22 is not pinned (unsafe22) */
                if (dq > FIT_JET_SPREAD * c->o.tol * c->diag && o < 3) p->gregory |= 1 << i;
                if (o > 0 && (unsafe || dq > FIT_JET_SPREAD * c->o.tol * c->diag)) {
                    unsafe = 1;
                    if (o == 3) p->unsafe22 |= 1 << i;
                    continue;
                }
                /* J = sum_{p<=a, q<=b} N_p^(a)(0) M_q^(b)(0) Q_pq, solved for Q_ab */
                for (int pp = 0; pp <= a; pp++)
                    for (int qq = 0; qq <= b; qq++) {
                        if (pp == a && qq == b) continue;
                        q2n_v3_axpy(J, -Nt[a][pp] * Ns[b][qq], p->cp + 3 * (size_t)side_g(c, &sd, pp, qq));
                    }
                int g = side_g(c, &sd, a, b);
                q2n_v3_scale(p->cp + 3 * (size_t)g, 1.0 / (Nt[a][a] * Ns[b][b]), J);
                p->fixed[g] = 1;
            }
        }
    }
    return Q2N_OK;
}

/* alpha, beta with  dR = alpha dL + beta T  in the least-squares sense (exact for a G1
 * construction); returns the relative residual. */
static double glue1(const double dR[3], const double dL[3], const double T[3], double *al, double *be)
{
    double a11 = q2n_v3_dot(dL, dL), a12 = q2n_v3_dot(dL, T), a22 = q2n_v3_dot(T, T);
    double b1 = q2n_v3_dot(dL, dR), b2 = q2n_v3_dot(T, dR), det = a11 * a22 - a12 * a12;
    *al = (a22 * b1 - a12 * b2) / det;
    *be = (a11 * b2 - a12 * b1) / det;
    double r[3];
    for (int q = 0; q < 3; q++) r[q] = dR[q] - *al * dL[q] - *be * T[q];
    return q2n_v3_norm(r) / q2n_v3_norm(dR);
}

/* Does edge e end at a Gregory-type corner of either neighbour? */
static int edge_gregory(const ctx *c, int e)
{
    side sd[2];
    int two = edge_sides(c, e, &sd[0], &sd[1]);
    for (int x = 0; x < 1 + two; x++) {
        int g = c->p[sd[x].k].gregory, i = sd[x].i;
        if (g & ((1 << i) | (1 << ((i + 1) & 3)))) return 1;
    }
    return 0;
}

/* Stage 4 (order 1) or 5 (order 2): joint fit of the order-th rows next to every interior edge
 * (and, for order 1, of the first row next to boundary edges) with the gluing relation. */
/* Exact derivatives of both sides of every edge at its interior samples, evaluated once per round
 * on the worker threads and shared by the G1 and G2 row stages: edge e's block starts at
 * c->eoff[e] and holds, per sample k = 1..N-2 and side x, the 6 x 3 doubles of frame_eval. */
typedef struct edata_arg {
    ctx *c;
    q2n_status *st;
} edata_arg;

static void edata_one(void *arg, int e)
{
    edata_arg *a = arg;
    ctx *c = a->c;
    side sd[2];
    int two = edge_sides(c, e, &sd[0], &sd[1]), N = fit_nsamples(sd[0].mt);
    double *D = c->edata + c->eoff[e];
    for (int k = 1; k + 1 < N && !a->st[e]; k++)
        for (int x = 0; x < 1 + two && !a->st[e]; x++) {
            double t = (double)k / (N - 1);
            a->st[e] = frame_eval(c->s, sd[x].k, sd[x].i, x ? 1.0 - t : t, 0.0, 2,
                                  (double (*)[3])(D + ((size_t)(k - 1) * 2 + x) * 18));
        }
}

static q2n_status edge_samples(ctx *c)
{
    const q2n_mesh *m = c->m;
    free(c->edata);
    free(c->eoff);
    c->edata = NULL;
    c->eoff = malloc(sizeof(size_t) * ((size_t)m->ne + 1));
    if (!c->eoff) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    c->eoff[0] = 0;
    for (int e = 0; e < m->ne; e++) {
        side L, R;
        edge_sides(c, e, &L, &R);
        c->eoff[e + 1] = c->eoff[e] + (size_t)(fit_nsamples(L.mt) - 2) * 2 * 18;
    }
    c->edata = malloc(sizeof(double) * (c->eoff[m->ne] ? c->eoff[m->ne] : 1));
    q2n_status *st = calloc((size_t)m->ne + 1, sizeof *st);
    if (!c->edata || !st) { free(st); return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (edge samples)"); }
    edata_arg arg = {c, st};
    double t0 = fit_now();
    fit_par_for(m->ne, c->o.threads, edata_one, &arg);
    c->rep->t_sample += fit_now() - t0;
    q2n_status r = Q2N_OK;
    for (int e = 0; e < m->ne && !r; e++)
        if (st[e]) r = q2n_error_set(c->err, st[e], "fit: edge %d (face %d): evaluation %s", e,
                                     m->he_face[m->edge_he[e]],
                                     st[e] == Q2N_ERR_NUMERIC ? "not finite" : "failed");
    free(st);
    return r;
}

static q2n_status stage_rows(ctx *c, int order)
{
    if (order == 1) {
        q2n_status st = edge_samples(c);
        if (st) return st;
    }
    for (int e = 0; e < c->m->ne; e++) {
        side sd[2];
        int two = edge_sides(c, e, &sd[0], &sd[1]);
        if (fit_ls_item_begin(&c->ls)) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
        int N = fit_nsamples(sd[0].mt);
        /* second-order gluing is left out next to Gregory-type corners, where no polynomial
         * spline can satisfy it (it would only cost deviation); those edges get fidelity rows */
        int glue = two && !(order == 2 && edge_gregory(c, e));
        double Ns[2][3][FIT_DEG + 1];
        for (int x = 0; x < 1 + two; x++) fit_basis(FIT_DEG, sd[x].ks, 0.0, 2, Ns[x]);
        for (int k = 1; k + 1 < N; k++) {
            double t = (double)k / (N - 1);
            const double(*D)[6][3] = (const double(*)[6][3])(c->edata + c->eoff[e] + (size_t)(k - 1) * 2 * 18);
            row r;
            q2n_status st;
            for (int x = 0; x < 1 + two; x++) {
                double tx = x ? 1.0 - t : t;
                /* fidelity to the exact order-th cross derivative, in units of control points */
                double sc = 1.0 / Ns[x][order][order];
                row_start(&r, D[x][order == 1 ? 2 : 5], sc);
                if ((st = add_deriv(c, &r, &sd[x], tx, 0, order, sc)) || (st = row_push(c, &r))) return st;
            }
            if (!glue) continue;
            double al, be, zero[3] = {0, 0, 0};
            glue1(D[1][2], D[0][2], D[0][1], &al, &be);
            double w = c->o.g1_weight / Ns[1][order][order];
            row_start(&r, zero, 0.0);
            if (order == 1) {
                /* d_s S_R - alpha d_s S_L - beta d_t S_L = 0   (formulas.md §4.2, G1) */
                if ((st = add_deriv(c, &r, &sd[1], 1.0 - t, 0, 1, w)) || (st = add_deriv(c, &r, &sd[0], t, 0, 1, -al * w)) ||
                    (st = add_deriv(c, &r, &sd[0], t, 1, 0, -be * w)))
                    return st;
            } else {
                /* d_ss S_R = al^2 d_ss S_L + 2 al be d_ts S_L + be^2 d_tt S_L + ga d_s S_L + de d_t S_L
                 * (formulas.md §4.2, G2); gamma, delta: tangential part of the exact residual. */
                double E[3], ga, de;
                for (int q = 0; q < 3; q++)
                    E[q] = D[1][5][q] - al * al * D[0][5][q] - 2 * al * be * D[0][4][q] - be * be * D[0][3][q];
                glue1(E, D[0][2], D[0][1], &ga, &de);
                if ((st = add_deriv(c, &r, &sd[1], 1.0 - t, 0, 2, w)) ||
                    (st = add_deriv(c, &r, &sd[0], t, 0, 2, -al * al * w)) ||
                    (st = add_deriv(c, &r, &sd[0], t, 1, 1, -2 * al * be * w)) ||
                    (st = add_deriv(c, &r, &sd[0], t, 2, 0, -be * be * w)) ||
                    (st = add_deriv(c, &r, &sd[0], t, 0, 1, -ga * w)) || (st = add_deriv(c, &r, &sd[0], t, 1, 0, -de * w)))
                    return st;
            }
            if ((st = row_push(c, &r))) return st;
        }
    }
    return solve_stage(c);
}

/* Stage 6, general form: every control point of the listed patches not fixed yet, least squares
 * on the patch's sample grid (one block per patch). */
static q2n_status stage_interior_general(ctx *c, const int *list, int nlist)
{
    double *S = NULL;
    size_t cap = 0;
    if (nlist == 0) return Q2N_OK;
    for (int l = 0; l < nlist; l++) {
        int k = list[l];
        fpatch *p = &c->p[k];
        int Nu = fit_nsamples(p->mu), Nv = fit_nsamples(p->mv);
        double us[4 * FIT_MAX_SPANS + 4], vs[4 * FIT_MAX_SPANS + 4];
        for (int i = 0; i < Nu; i++) us[i] = (double)i / (Nu - 1);
        for (int j = 0; j < Nv; j++) vs[j] = (double)j / (Nv - 1);
        if ((size_t)Nu * Nv * 9 > cap) {
            cap = (size_t)Nu * Nv * 9;
            double *t = realloc(S, cap * sizeof *S);
            if (!t) { free(S); return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (samples)"); }
            S = t;
        }
        double t0 = fit_now();
        q2n_status st = q2n_surface_eval_grid(c->s, k, Nu, us, Nv, vs, S);
        c->rep->t_sample += fit_now() - t0;
        if (st) {
            free(S);
            return q2n_error_set(c->err, st, "fit: face %d: grid evaluation %s", k,
                                 st == Q2N_ERR_NUMERIC ? "not finite" : "failed");
        }
        if ((st = fit_ls_item_begin(&c->ls))) { free(S); return q2n_error_set(c->err, st, "fit: out of memory"); }
        for (int j = 0; j < Nv; j++) {
            double Bv[3][FIT_DEG + 1], Bu[3][FIT_DEG + 1];
            int sv = fit_span(p->nv, p->kv, vs[j]);
            fit_basis(sv, p->kv, vs[j], 0, Bv);
            for (int i = 0; i < Nu; i++) {
                int su = fit_span(p->nu, p->ku, us[i]);
                fit_basis(su, p->ku, us[i], 0, Bu);
                row r;
                row_start(&r, S + 9 * ((size_t)j * Nu + i), 1.0);
                for (int b = 0; b <= FIT_DEG; b++)
                    for (int a = 0; a <= FIT_DEG; a++) {
                        int g = (sv - FIT_DEG + b) * p->nu + su - FIT_DEG + a;
                        if ((st = add_term(c, &r, k, g, Bu[0][a] * Bv[0][b]))) { free(S); return st; }
                    }
                if ((st = row_push(c, &r))) { free(S); return st; }
                c->rep->samples++;
            }
        }
    }
    free(S);
    return solve_stage(c);
}

/* The free control points of patch k when they form a tensor block [lu..hu] x [lv..hv] (the
 * usual case: everything at distance >= 2, or >= 3 in G2 mode, from the boundary); 0 otherwise. */
static int free_block(const fpatch *p, int *lu, int *hu, int *lv, int *hv)
{
    *lu = p->nu; *hu = -1; *lv = p->nv; *hv = -1;
    for (int b = 0; b < p->nv; b++)
        for (int a = 0; a < p->nu; a++)
            if (!p->fixed[b * p->nu + a]) {
                if (a < *lu) *lu = a;
                if (a > *hu) *hu = a;
                if (b < *lv) *lv = b;
                if (b > *hv) *hv = b;
            }
    for (int b = 0; b < p->nv; b++)
        for (int a = 0; a < p->nu; a++) {
            int in = a >= *lu && a <= *hu && b >= *lv && b <= *hv;
            if (in == p->fixed[b * p->nu + a]) return 0;
        }
    return 1;
}

/* Per-patch data of the separable interior solve. */
typedef struct sep_patch {
    int k, lu, hu, lv, hv, Nu, Nv;
    double *R;       /* Nu*Nv*3: samples minus the fixed control points' contribution */
    double *Bu, *Bv; /* Nu x nu and Nv x nv basis matrices (row-major) */
    int *var1;       /* Nu: first unknown of the pass-1 block of sample column i, or -1 */
    int *var2;       /* hv-lv+1: first unknown of the pass-2 block of control column b */
} sep_patch;

static void sep_free(sep_patch *sp, int n)
{
    for (int i = 0; sp && i < n; i++) {
        free(sp[i].R); free(sp[i].Bu); free(sp[i].Bv); free(sp[i].var1); free(sp[i].var2);
    }
    free(sp);
}

/* Sample patch k, build its basis matrices and the residual R of the fixed control points. */
static q2n_status sep_prepare(const ctx *c, sep_patch *sp)
{
    fpatch *p = &c->p[sp->k];
    int Nu = sp->Nu = fit_nsamples(p->mu), Nv = sp->Nv = fit_nsamples(p->mv);
    double us[4 * FIT_MAX_SPANS + 4], vs[4 * FIT_MAX_SPANS + 4];
    for (int i = 0; i < Nu; i++) us[i] = (double)i / (Nu - 1);
    for (int j = 0; j < Nv; j++) vs[j] = (double)j / (Nv - 1);
    double *S = malloc(9 * sizeof(double) * (size_t)Nu * Nv);
    sp->R = malloc(3 * sizeof(double) * (size_t)Nu * Nv);
    sp->Bu = calloc((size_t)Nu * p->nu, sizeof(double));
    sp->Bv = calloc((size_t)Nv * p->nv, sizeof(double));
    sp->var1 = malloc(sizeof(int) * (size_t)Nu);
    sp->var2 = malloc(sizeof(int) * (size_t)(sp->hv - sp->lv + 1));
    if (!S || !sp->R || !sp->Bu || !sp->Bv || !sp->var1 || !sp->var2) {
        free(S);
        return Q2N_ERR_NOMEM;
    }
    q2n_status st = q2n_surface_eval_grid(c->s, sp->k, Nu, us, Nv, vs, S);
    if (st) { free(S); return st; }
    double B[3][FIT_DEG + 1];
    for (int i = 0; i < Nu; i++) {
        int su = fit_span(p->nu, p->ku, us[i]);
        fit_basis(su, p->ku, us[i], 0, B);
        for (int a = 0; a <= FIT_DEG; a++) sp->Bu[(size_t)i * p->nu + su - FIT_DEG + a] = B[0][a];
    }
    for (int j = 0; j < Nv; j++) {
        int sv = fit_span(p->nv, p->kv, vs[j]);
        fit_basis(sv, p->kv, vs[j], 0, B);
        for (int b = 0; b <= FIT_DEG; b++) sp->Bv[(size_t)j * p->nv + sv - FIT_DEG + b] = B[0][b];
    }
    for (int j = 0; j < Nv; j++)
        for (int i = 0; i < Nu; i++) {
            double *r = sp->R + 3 * ((size_t)j * Nu + i);
            memcpy(r, S + 9 * ((size_t)j * Nu + i), 3 * sizeof(double));
            for (int b = 0; b < p->nv; b++) {
                double wv = sp->Bv[(size_t)j * p->nv + b];
                if (wv == 0.0) continue;
                for (int a = 0; a < p->nu; a++) {
                    double w = sp->Bu[(size_t)i * p->nu + a] * wv;
                    if (w != 0.0 && p->fixed[b * p->nu + a]) q2n_v3_axpy(r, -w, p->cp + 3 * ((size_t)b * p->nu + a));
                }
            }
        }
    free(S);
    return Q2N_OK;
}

typedef struct prep_arg {
    const ctx *c;
    sep_patch *sp;
    q2n_status *st;            /* per patch */
} prep_arg;

static void prep_one(void *arg, int l)
{
    prep_arg *a = arg;
    a->st[l] = sep_prepare(a->c, &a->sp[l]);
}

/* sep_prepare for all n patches on the worker threads; the first failing patch in index order
 * is reported. */
static q2n_status prepare_all(ctx *c, sep_patch *sp, int n)
{
    q2n_status *st = calloc((size_t)(n > 0 ? n : 1), sizeof *st);
    if (!st) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    prep_arg arg = {c, sp, st};
    double t0 = fit_now();
    fit_par_for(n, c->o.threads, prep_one, &arg);
    c->rep->t_sample += fit_now() - t0;
    q2n_status r = Q2N_OK;
    for (int l = 0; l < n; l++) {
        c->rep->samples += (long)sp[l].Nu * sp[l].Nv;
        if (st[l] && !r)
            r = q2n_error_set(c->err, st[l], "fit: face %d: %s", sp[l].k,
                              st[l] == Q2N_ERR_NOMEM ? "out of memory (samples)" : "grid evaluation failed");
    }
    free(st);
    return r;
}

/* Does sample i (u) touch the free block? */
static int sep_touches(const sep_patch *sp, const fpatch *p, int i)
{
    for (int a = sp->lu; a <= sp->hu; a++)
        if (sp->Bu[(size_t)i * p->nu + a] != 0.0) return 1;
    return 0;
}

/* Stage 6: every control point not fixed yet, least squares on the patch's (4m_u+4) x (4m_v+4)
 * sample grid.  The free points form a tensor block and the samples a tensor grid, so
 * min |A X B^T - R| (A, B the block's u and v basis columns at the samples, R the samples minus
 * the fixed points' part) has the solution X = A^+ R B^+T: pass 1 fits every sample column in v
 * (Z = R B^+T), pass 2 every column of Z in u — the same solution as the 2-D least-squares
 * problem at a fraction of its cost (1-D blocks instead of (m_u+1)(m_v+1) unknowns at once). */
static q2n_status stage_interior(ctx *c, const int *list, int nlist)
{
    const int nf = list ? nlist : c->m->nf;
    sep_patch *sp = calloc((size_t)nf, sizeof *sp);
    int *gen = malloc(sizeof(int) * (size_t)nf), ngen = 0, nsp = 0;
    q2n_status st = Q2N_OK;
    if (!sp || !gen) { st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); goto out; }
    for (int l = 0; l < nf; l++) {
        int k = list ? list[l] : l;
        sep_patch q = {0};
        q.k = k;
        if (!free_block(&c->p[k], &q.lu, &q.hu, &q.lv, &q.hv)) { gen[ngen++] = k; continue; }
        if (q.hu < q.lu) continue;                 /* nothing free */
        sp[nsp++] = q;
    }
    if ((st = prepare_all(c, sp, nsp))) goto out;
    /* pass 1: for each sample column i, min_z |Bv[:, lv..hv] z - R[i, :]| */
    for (int l = 0; l < nsp; l++) {
        sep_patch *q = &sp[l];
        fpatch *p = &c->p[q->k];
        for (int i = 0; i < q->Nu; i++) {
            q->var1[i] = -1;
            if (!sep_touches(q, p, i)) continue;
            if (fit_ls_item_begin(&c->ls)) { st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); goto out; }
            q->var1[i] = c->ls.nvar;
            for (int b = q->lv; b <= q->hv; b++) { int id; fit_ls_new_var(&c->ls, &id); }
            for (int j = 0; j < q->Nv; j++) {
                const double *w = q->Bv + (size_t)j * p->nv;
                int any = 0;
                for (int b = q->lv; b <= q->hv; b++) any |= w[b] != 0.0;
                if (!any) continue;
                if (fit_ls_row(&c->ls, q->R + 3 * ((size_t)j * q->Nu + i))) { st = Q2N_ERR_NOMEM; goto nomem; }
                for (int b = q->lv; b <= q->hv; b++)
                    if (w[b] != 0.0 && fit_ls_entry(&c->ls, q->var1[i] + b - q->lv, w[b])) { st = Q2N_ERR_NOMEM; goto nomem; }
            }
        }
    }
    if ((st = solve_ls(c))) goto out;
    double *Z = c->ls.x;
    c->ls.x = NULL;
    fit_ls_clear(&c->ls);
    /* pass 2: for each control column b, min_x |Bu[touching i, lu..hu] x - Z[i, b]| */
    for (int l = 0; l < nsp; l++) {
        sep_patch *q = &sp[l];
        fpatch *p = &c->p[q->k];
        for (int b = q->lv; b <= q->hv; b++) {
            if (fit_ls_item_begin(&c->ls)) { free(Z); st = Q2N_ERR_NOMEM; goto nomem; }
            q->var2[b - q->lv] = c->ls.nvar;
            for (int a = q->lu; a <= q->hu; a++) { int id; fit_ls_new_var(&c->ls, &id); }
            for (int i = 0; i < q->Nu; i++) {
                if (q->var1[i] < 0) continue;
                if (fit_ls_row(&c->ls, Z + 3 * (size_t)(q->var1[i] + b - q->lv))) { free(Z); st = Q2N_ERR_NOMEM; goto nomem; }
                const double *w = q->Bu + (size_t)i * p->nu;
                for (int a = q->lu; a <= q->hu; a++)
                    if (w[a] != 0.0 && fit_ls_entry(&c->ls, q->var2[b - q->lv] + a - q->lu, w[a])) {
                        free(Z);
                        st = Q2N_ERR_NOMEM;
                        goto nomem;
                    }
            }
        }
    }
    free(Z);
    if ((st = solve_ls(c))) goto out;
    for (int l = 0; l < nsp; l++) {
        sep_patch *q = &sp[l];
        fpatch *p = &c->p[q->k];
        for (int b = q->lv; b <= q->hv; b++)
            for (int a = q->lu; a <= q->hu; a++) {
                int g = b * p->nu + a;
                memcpy(p->cp + 3 * (size_t)g, c->ls.x + 3 * (size_t)(q->var2[b - q->lv] + a - q->lu), 3 * sizeof(double));
                p->fixed[g] = 1;
            }
    }
    fit_ls_clear(&c->ls);
    st = stage_interior_general(c, gen, ngen);
    goto out;
nomem:
    st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (interior)");
out:
    fit_ls_clear(&c->ls);
    sep_free(sp, nsp);
    free(gen);
    return st;
}

/* ------------------------------------------------------------------ rounds */

static q2n_status alloc_patches(ctx *c)
{
    const q2n_mesh *m = c->m;
    for (int k = 0; k < m->nf; k++) {
        fpatch *p = &c->p[k];
        int mu = c->rspan[c->rib[m->he_edge[4 * k]]], mv = c->rspan[c->rib[m->he_edge[4 * k + 1]]];
        if (p->cp && p->mu == mu && p->mv == mv) {
            memset(p->fixed, 0, (size_t)p->nu * p->nv);
            continue;
        }
        free(p->ku); free(p->kv); free(p->cp); free(p->fixed); free(p->var);
        p->mu = mu; p->mv = mv; p->nu = mu + FIT_DEG; p->nv = mv + FIT_DEG;
        size_t n = (size_t)p->nu * p->nv;
        p->ku = malloc(sizeof(double) * (size_t)(mu + 2 * FIT_DEG + 1));
        p->kv = malloc(sizeof(double) * (size_t)(mv + 2 * FIT_DEG + 1));
        p->cp = calloc(3 * n, sizeof(double));
        p->fixed = calloc(n, 1);
        p->var = malloc(n * sizeof(int));
        if (!p->ku || !p->kv || !p->cp || !p->fixed || !p->var)
            return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (patch %d)", k);
        fit_knots_uniform(mu, p->ku);
        fit_knots_uniform(mv, p->kv);
        for (size_t g = 0; g < n; g++) p->var[g] = -1;
    }
    return Q2N_OK;
}

/* G2 mode, corners whose Q22 could not be read from the construction: a preliminary interior
 * fit of those patches (rows 0 and 1 fixed, everything further in free) supplies it; all else
 * it fitted is restored / freed again for the G2 rows and the final interior fit. */
static q2n_status stage_prefit(ctx *c)
{
    int *list = malloc(sizeof(int) * (size_t)c->m->nf), n = 0;
    unsigned char **save = calloc((size_t)c->m->nf, sizeof *save);
    q2n_status st = Q2N_OK;
    if (!list || !save) { st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); goto out; }
    for (int k = 0; k < c->m->nf; k++) {
        fpatch *p = &c->p[k];
        if (!p->unsafe22) continue;
        save[k] = malloc((size_t)p->nu * p->nv);
        if (!save[k]) { st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory"); goto out; }
        memcpy(save[k], p->fixed, (size_t)p->nu * p->nv);
        list[n++] = k;
    }
    for (int l = 0; l < n; l++) {      /* free everything two or more rows in: a tensor block */
        fpatch *p = &c->p[list[l]];
        for (int b = 2; b < p->nv - 2; b++)
            for (int a = 2; a < p->nu - 2; a++) p->fixed[b * p->nu + a] = 0;
    }
    if ((st = stage_interior(c, list, n))) goto out;
    for (int l = 0; l < n; l++) {
        fpatch *p = &c->p[list[l]];
        memcpy(p->fixed, save[list[l]], (size_t)p->nu * p->nv);
        for (int i = 0; i < 4; i++)
            if (p->unsafe22 & (1 << i)) {
                side sd = make_side(c, list[l], i);
                p->fixed[side_g(c, &sd, 2, 2)] = 1;
            }
    }
out:
    for (int k = 0; save && k < c->m->nf; k++) free(save[k]);
    free(save);
    free(list);
    return st;
}

static q2n_status fit_round(ctx *c)
{
    q2n_status st = alloc_patches(c);
    if (st) return st;
    double t0 = fit_now(), s0 = c->rep->t_sample, v0 = c->rep->t_solve;
    if ((st = stage_curves(c)) || (st = stage_corners(c)) || (st = stage_rows(c, 1))) return st;
    if (c->o.continuity == 2 && ((st = stage_prefit(c)) || (st = stage_rows(c, 2)))) return st;
    if ((st = stage_interior(c, NULL, 0))) return st;
    c->rep->t_build += (fit_now() - t0) - (c->rep->t_sample - s0) - (c->rep->t_solve - v0);
    return Q2N_OK;
}

/* Copy the fitted patches into a model (knots and control points). */
static q2n_status make_model(ctx *c, q2n_nurbs_model **out)
{
    q2n_nurbs_model *md = calloc(1, sizeof *md);
    if (!md) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (model)");
    md->n = c->m->nf;
    md->mesh = c->m;
    md->tol_abs = c->o.tol * c->diag;
    md->patches = calloc((size_t)md->n, sizeof *md->patches);
    if (!md->patches) { free(md); return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (model)"); }
    for (int k = 0; k < md->n; k++) {
        fpatch *p = &c->p[k];
        q2n_bspline_surface *b = &md->patches[k];
        b->deg_u = b->deg_v = FIT_DEG;
        b->ncp_u = p->nu; b->ncp_v = p->nv;
        size_t nku = (size_t)p->nu + FIT_DEG + 1, nkv = (size_t)p->nv + FIT_DEG + 1, n = (size_t)p->nu * p->nv;
        b->knots_u = malloc(nku * sizeof(double));
        b->knots_v = malloc(nkv * sizeof(double));
        b->cp = malloc(3 * n * sizeof(double));
        if (!b->knots_u || !b->knots_v || !b->cp) {
            q2n_nurbs_model_free(md);
            return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (model)");
        }
        memcpy(b->knots_u, p->ku, nku * sizeof(double));
        memcpy(b->knots_v, p->kv, nkv * sizeof(double));
        memcpy(b->cp, p->cp, 3 * n * sizeof(double));
    }
    *out = md;
    return Q2N_OK;
}

/* Continuity-driven refinement towards the refinement targets stops at this many spans per
 * ribbon (and at half of max_spans); a ribbon already there whose edge would still fail
 * acceptance (twice the targets) goes on to max_spans, like the deviation.  Beyond FIT_CONT_SPANS
 * spans every ribbon is expensive (knots are shared along the whole chain of patches), so it is
 * spent only where the acceptance needs it: rook --subdivide 1 has an edge (6127) next to a
 * vertex with wild corner data whose curvature jump is 0.149 at 24 spans, 0.04 at 28, 0.006-0.013
 * at 36 (depending on the neighbouring ribbons; 0.0129 at --tol 1e-6) and 5e-4 at 48; refining
 * every edge to the tighter target beyond 24 instead cost spot 25 % more time for nothing the
 * acceptance sees. */
#define FIT_CONT_SPANS 24
/* fit_scan_construction ratio above which a failed fit is blamed on the construction: smooth
 * patches of the shared meshes stay below 3.3 (pawn 1.5, helmet 3.3, spot 2.1); the spikes of
 * gregory_test1 reach 15-31, those of righthanded 1e6-1e7. */
#define FIT_SPIKE_RATIO 10.0

static int cmp_int(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

static void span_stats(const q2n_nurbs_model *md, q2n_fit_report *rep)
{
    int *s = malloc(sizeof(int) * (size_t)md->n);
    if (!s) return;
    for (int k = 0; k < md->n; k++) s[k] = (md->patches[k].ncp_u - FIT_DEG) * (md->patches[k].ncp_v - FIT_DEG);
    qsort(s, (size_t)md->n, sizeof(int), cmp_int);
    rep->spans_min = s[0];
    rep->spans_median = s[md->n / 2];
    rep->spans_max = s[md->n - 1];
    free(s);
}

/* New span count of a ribbon whose error is ratio times the target and falls like h^order
 * (quintic: deviation h^6, normal jump h^5, curvature jump h^4). */
static int bump(int m, double ratio, double order, int cap)
{
    int n = (int)ceil(1.15 * m * pow(ratio, 1.0 / order));
    if (n < m + 1) n = m + 1;
    return n > cap ? cap : n;
}

/* Refinement state of one edge's continuity (G1 or G2): value and failure in the previous round.
 * An edge that failed twice in a row without the improvement refinement brings to smooth
 * constructions is "stalled" (e.g. next to Gregory-type corners, whose rational blends no
 * polynomial spline follows to second order): it stops driving refinement and is reported. */
typedef struct refine_item {
    double prev;
    int failed, prev_m;
} refine_item;

/* Stalled: failed last round too, was refined since (m > prev_m spans), and improved by less
 * than (m / prev_m)^power (at least 1.2x) — convergent edges do better (the normal and
 * curvature jumps fall like h^5 and h^4 for smooth constructions; power 2 is conservative). */
static int stalled(refine_item *it, double now, int fails, int m, double power)
{
    double need = it->prev_m > 0 ? pow((double)m / it->prev_m, power) : 1.0;
    int st = fails && it->failed && m > it->prev_m && now > it->prev / (need > 1.2 ? need : 1.2);
    it->failed = fails;
    it->prev = now;
    it->prev_m = m;
    return st;
}

static q2n_status fit_all(ctx *c, q2n_nurbs_model **out)
{
    const q2n_mesh *m = c->m;
    q2n_fit_report *rep = c->rep;
    q2n_status st = q2n_mesh_ribbons(m, &c->rib, &c->nrib, c->err);
    if (st) return st;
    c->rspan = malloc(sizeof(int) * (size_t)c->nrib);
    int *next = malloc(sizeof(int) * (size_t)c->nrib);
    double *pdev = malloc(sizeof(double) * (size_t)m->nf), *pdir = malloc(2 * sizeof(double) * (size_t)m->nf);
    refine_item *rf = calloc(2 * (size_t)m->ne, sizeof *rf);
    /* per patch: 0 not scanned, 1 scanned smooth, 2 spiky construction (no longer refined for) */
    unsigned char *spiky = calloc((size_t)m->nf, 1);
    double *eg[4];
    for (int i = 0; i < 4; i++) eg[i] = malloc(sizeof(double) * (size_t)m->ne);
    if (!c->rspan || !next || !pdev || !pdir || !rf || !spiky || !eg[0] || !eg[1] || !eg[2] || !eg[3]) {
        st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
        goto done;
    }
    for (int r = 0; r < c->nrib; r++) c->rspan[r] = 1;
    for (int round = 0;; round++) {
        rep->samples = 0;
        if ((st = fit_round(c))) goto done;
        q2n_nurbs_model *md = NULL;
        if ((st = make_model(c, &md))) goto done;
        double t0 = fit_now();
        fit_measure_out mo = {pdev, pdir, eg[0], eg[1], round == 0 ? eg[2] : NULL, round == 0 ? eg[3] : NULL};
        st = fit_measure_model(md, c->s, rep, &mo, c->o.threads, c->err);
        rep->t_measure += fit_now() - t0;
        if (st) { q2n_nurbs_model_free(md); goto done; }
        rep->rounds = round + 1;
        /* refine: the limiting ribbon(s) of a patch over tolerance; the ribbon along an edge
         * whose continuity misses its target (only where the construction itself meets it) */
        int worst_f = -1, worst_e1 = -1, worst_e2 = -1, active = 0;
        memcpy(next, c->rspan, sizeof(int) * (size_t)c->nrib);
        for (int k = 0; k < m->nf; k++) {
            int fails = pdev[k] > c->o.tol;
            if (fails && (worst_f < 0 || pdev[k] > pdev[worst_f])) worst_f = k;
            if (!fails) continue;         /* the deviation must be met: no stall rule here ... */
            /* ... except where the construction has a spike below any knot spacing (docs/fit.md,
             * Limits): before a failing patch gets FIT_CONT_SPANS or more spans in some direction,
             * its construction is scanned (once); a spiky one stops driving refinement (the fit
             * fails on it anyway, and its ribbons' spans would only cost time elsewhere) */
            int nd[2] = {0, 0};
            for (int d = 0; d < 2; d++) {
                double share = pdir[2 * k + d];
                if (share < 0.25) continue;
                nd[d] = bump(c->rspan[c->rib[m->he_edge[4 * k + d]]], share * pdev[k] / c->o.tol, 6.0, c->o.max_spans);
            }
            if (!spiky[k] && (nd[0] >= FIT_CONT_SPANS || nd[1] >= FIT_CONT_SPANS)) {
                double ratio = 1.0, su, sv, dmax, t1 = fit_now();
                if ((st = fit_scan_construction(c->s, k, FIT_SCAN_N_QUICK, &ratio, &su, &sv, &dmax))) {
                    q2n_nurbs_model_free(md);
                    st = q2n_error_set(c->err, st, "fit: face %d: construction scan failed", k);
                    goto done;
                }
                rep->t_measure += fit_now() - t1;
                spiky[k] = ratio <= FIT_SPIKE_RATIO ? 1 : 2;
            }
            if (spiky[k] == 2) continue;
            /* refine the direction(s) whose estimated share of the error is at least 1/4, each
             * by its share of the excess (fit_measure_model estimates the shares) */
            for (int d = 0; d < 2; d++) {
                int r = c->rib[m->he_edge[4 * k + d]];
                if (nd[d] > next[r]) next[r] = nd[d];
            }
        }
        for (int e = 0; e < m->ne; e++) {
            double r1 = eg[0][e] / c->o.g1_target_deg, r2 = eg[1][e] / c->o.g2_target_rel;
            int bad1 = r1 > 1.0 && eg[2][e] < 0.5 * c->o.g1_target_deg;
            int bad2 = c->o.continuity == 2 && r2 > 1.0 && eg[3][e] < 0.5 * c->o.g2_target_rel;
            int me = c->rspan[c->rib[e]];
            if (stalled(&rf[e], eg[0][e], bad1, me, 2.0)) bad1 = 0;
            if (stalled(&rf[m->ne + e], eg[1][e], bad2, me, 2.0)) bad2 = 0;
            /* curvature next to Gregory-type corners cannot follow the construction (docs/fit.md,
             * Limits): reported, never a reason to refine */
            if (bad2 && edge_gregory(c, e)) bad2 = 0;
            if (!bad1 && !bad2) continue;
            /* continuity alone refines a ribbon up to half the span cap, at most FIT_CONT_SPANS;
             * a ribbon already there goes on to the span cap where the edge would fail
             * acceptance */
            int cap = c->o.max_spans / 2 > 1 ? c->o.max_spans / 2 : 1, me0 = c->rspan[c->rib[e]];
            if (cap > FIT_CONT_SPANS) cap = FIT_CONT_SPANS;
            int full = c->o.max_spans, cap1 = me0 >= cap && r1 > 2.0 ? full : cap;
            int cap2 = me0 >= cap && r2 > 2.0 ? full : cap;
            int n1 = bad1 && me0 < cap1 ? bump(me0, r1, 5.0, cap1) : 0;
            int n2 = bad2 && me0 < cap2 ? bump(me0, r2, 4.0, cap2) : 0;
            int n = n1 > n2 ? n1 : n2;
            if (n > next[c->rib[e]]) next[c->rib[e]] = n;
        }
        for (int r = 0; r < c->nrib; r++) active |= next[r] != c->rspan[r];
        if (active && round + 1 < c->o.max_rounds) {
            q2n_nurbs_model_free(md);
            memcpy(c->rspan, next, sizeof(int) * (size_t)c->nrib);
            continue;
        }
        /* acceptance: twice the refinement targets (0.01 deg, 1 % by default), on every edge
         * where the construction itself meets the refinement target */
        for (int e = 0; e < m->ne; e++) {
            if (eg[0][e] > 2 * c->o.g1_target_deg && eg[2][e] < 0.5 * c->o.g1_target_deg &&
                (worst_e1 < 0 || eg[0][e] > eg[0][worst_e1]))
                worst_e1 = e;
            if (c->o.continuity == 2 && eg[1][e] > 2 * c->o.g2_target_rel && eg[3][e] < 0.5 * c->o.g2_target_rel &&
                (worst_e2 < 0 || eg[1][e] > eg[1][worst_e2]))
                worst_e2 = e;
        }
        rep->dev_met = worst_f < 0;
        rep->g1_met = worst_e1 < 0;
        rep->g2_met = c->o.continuity == 1 || worst_e2 < 0;
        rep->tol_met = rep->dev_met && rep->g1_met && rep->g2_met;
        span_stats(md, rep);
        rep->ribbon_spans_max = 0;
        for (int r = 0; r < c->nrib; r++)
            if (c->rspan[r] > rep->ribbon_spans_max) rep->ribbon_spans_max = c->rspan[r];
        if (worst_e1 >= 0 || worst_e2 >= 0) {
            int e = worst_e1 >= 0 ? worst_e1 : worst_e2;
            snprintf(rep->note, sizeof rep->note,
                     "edge %d: normal jump %.3g deg, curvature jump %.3g (targets %.3g deg, %.3g) not reached",
                     e, eg[0][e], eg[1][e], 2 * c->o.g1_target_deg, 2 * c->o.g2_target_rel);
        }
        *out = md;
        if (worst_f >= 0) {
            /* say whether the construction itself is to blame: a derivative far above its
             * median on the patch is a feature narrower than any knot spacing (docs/fit.md,
             * Limits: near-poles of the Coons–Gregory side data) */
            double ratio = 1.0, su = 0.0, sv = 0.0, dmax = 0.0;
            char why[200] = "";
            if (!fit_scan_construction(c->s, worst_f, FIT_SCAN_N, &ratio, &su, &sv, &dmax) && !(ratio <= FIT_SPIKE_RATIO))
                snprintf(why, sizeof why,
                         "; the construction is not smooth there: |dS| = %.3g at (u %.3f, v %.3f) is %.3g x its "
                         "median on the face (a spike narrower than any knot spacing)", dmax, su, sv, ratio);
            st = q2n_error_set(c->err, Q2N_ERR_GEOMETRY,
                               "fit: face %d: deviation %.3g (relative) > tol %.3g with %d x %d spans%s", worst_f,
                               pdev[worst_f], c->o.tol, c->p[worst_f].mu, c->p[worst_f].mv, why);
        }
        goto done;
    }
done:
    free(spiky);
    free(next);
    free(pdev);
    free(pdir);
    free(rf);
    for (int i = 0; i < 4; i++) free(eg[i]);
    return st;
}

/* ------------------------------------------------------------------ exact Bézier conversion */

/* Elevate a Bézier patch of degree (du, dv) to (5, 5) in place of the grid out[3*36]. */
static void elevate(int du, int dv, const double *cp, double *out)
{
    double a[3 * 36], b[3 * 36];
    int nu = du + 1, nv = dv + 1;
    memcpy(a, cp, 3 * (size_t)nu * nv * sizeof(double));
    for (; nu < FIT_DEG + 1; nu++) {       /* u: b_i = i/n a_{i-1} + (1 - i/n) a_i, n = new degree */
        for (int j = 0; j < nv; j++)
            for (int i = 0; i <= nu; i++)
                for (int q = 0; q < 3; q++) {
                    double l = i > 0 ? a[3 * (j * nu + i - 1) + q] : 0.0, r = i < nu ? a[3 * (j * nu + i) + q] : 0.0;
                    b[3 * (j * (nu + 1) + i) + q] = (double)i / nu * l + (1.0 - (double)i / nu) * r;
                }
        memcpy(a, b, 3 * (size_t)(nu + 1) * nv * sizeof(double));
    }
    for (; nv < FIT_DEG + 1; nv++) {
        for (int j = 0; j <= nv; j++)
            for (int i = 0; i < nu; i++)
                for (int q = 0; q < 3; q++) {
                    double l = j > 0 ? a[3 * ((j - 1) * nu + i) + q] : 0.0, r = j < nv ? a[3 * (j * nu + i) + q] : 0.0;
                    b[3 * (j * nu + i) + q] = (double)j / nv * l + (1.0 - (double)j / nv) * r;
                }
        memcpy(a, b, 3 * (size_t)nu * (nv + 1) * sizeof(double));
    }
    memcpy(out, a, 3 * 36 * sizeof(double));
}

static q2n_status convert_bezier(ctx *c, q2n_nurbs_model **out)
{
    const q2n_mesh *m = c->m;
    c->nrib = 0;
    for (int k = 0; k < m->nf; k++) {
        int du, dv;
        const double *cp;
        q2n_surface_bezier(c->s, k, &du, &dv, &cp);
        if (du > FIT_DEG || dv > FIT_DEG)
            return q2n_error_set(c->err, Q2N_ERR_UNSUPPORTED, "fit: face %d: Bézier degree %d x %d above 5", k, du, dv);
        fpatch *p = &c->p[k];
        p->mu = p->mv = 1;
        p->nu = p->nv = FIT_DEG + 1;
        p->ku = malloc(12 * sizeof(double));
        p->kv = malloc(12 * sizeof(double));
        p->cp = malloc(3 * 36 * sizeof(double));
        p->fixed = calloc(36, 1);
        p->var = malloc(36 * sizeof(int));
        if (!p->ku || !p->kv || !p->cp || !p->fixed || !p->var)
            return q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory (patch %d)", k);
        fit_knots_uniform(1, p->ku);
        fit_knots_uniform(1, p->kv);
        elevate(du, dv, cp, p->cp);
    }
    /* shared edges: identical control points on both sides (copy the owner's row) */
    for (int e = 0; e < m->ne; e++) {
        side L, R;
        if (!edge_sides(c, e, &L, &R)) continue;
        for (int it = 0; it < L.nt; it++) {
            double *pl = c->p[L.k].cp + 3 * (size_t)side_g(c, &L, it, 0);
            double *pr = c->p[R.k].cp + 3 * (size_t)side_g(c, &R, R.nt - 1 - it, 0);
            if (q2n_v3_dist(pl, pr) > 1e-9 * c->diag)
                return q2n_error_set(c->err, Q2N_ERR_GEOMETRY,
                                     "fit: edge %d (faces %d, %d): Bézier boundaries differ by %.3g", e, L.k, R.k,
                                     q2n_v3_dist(pl, pr));
            memcpy(pr, pl, 3 * sizeof(double));
        }
    }
    q2n_status st = make_model(c, out);
    if (st) return st;
    double t0 = fit_now();
    double *g1c = malloc(sizeof(double) * (size_t)m->ne), *g2c = malloc(sizeof(double) * (size_t)m->ne);
    fit_measure_out mo = {NULL, NULL, NULL, NULL, g1c, g2c};
    st = g1c && g2c ? fit_measure_model(*out, c->s, c->rep, &mo, c->o.threads, c->err)
                    : q2n_error_set(c->err, Q2N_ERR_NOMEM, "fit: out of memory");
    free(g1c);
    free(g2c);
    c->rep->t_measure += fit_now() - t0;
    c->rep->exact = 1;
    c->rep->rounds = 0;
    c->rep->dev_met = c->rep->max_dev_rel <= c->o.tol;
    c->rep->g1_met = c->rep->g2_met = 1;   /* the conversion is exact: continuity is the construction's */
    c->rep->tol_met = c->rep->dev_met;
    span_stats(*out, c->rep);
    c->rep->ribbon_spans_max = 1;
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
    ctx c;
    memset(&c, 0, sizeof c);
    c.s = s; c.m = m; c.err = err; c.rep = &rep;
    fill_defaults(&c.o, opt);
    c.diag = q2n_mesh_bbox_diag(m);
    fit_ls_init(&c.ls);
    c.p = calloc((size_t)m->nf, sizeof *c.p);
    double t0 = fit_now();
    q2n_status st = c.p ? Q2N_OK : q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory");
    if (!st) st = nbez == m->nf ? convert_bezier(&c, out) : fit_all(&c, out);
    rep.t_total = fit_now() - t0;
    rep.faces = m->nf;
    rep.edges = m->ne;
    for (int e = 0; e < m->ne; e++) rep.interior_edges += m->he_twin[m->edge_he[e]] >= 0;
    rep.continuity = c.o.continuity;
    rep.tol = c.o.tol;
    rep.solver = c.o.solver;
    rep.threads = c.o.threads;
    if (rep_out) *rep_out = rep;
    for (int k = 0; c.p && k < m->nf; k++) {
        free(c.p[k].ku); free(c.p[k].kv); free(c.p[k].cp); free(c.p[k].fixed); free(c.p[k].var);
    }
    free(c.p);
    free(c.rib);
    free(c.rspan);
    free(c.var_k);
    free(c.var_g);
    free(c.jet);
    free(c.edata);
    free(c.eoff);
    free(c.vpos);
    fit_ls_free(&c.ls);
    if (st && st != Q2N_ERR_GEOMETRY && *out) {
        q2n_nurbs_model_free(*out);
        *out = NULL;
    }
    return st;
}

