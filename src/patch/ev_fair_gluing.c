/* ev_fair_gluing.c — polynomial gluing of the fair construction's G1 patches (K = 1): every
 * constructed edge between two extraordinary faces whose end vertices are both "free" gets a
 * quadratic α and a linear β instead of the cubic smoothsteps, and every face corner's twist a
 * tangential correction, so that the derived side's cross derivative
 *     χ_G = α χ_F + β γ_t                              (formulas.md §4.2, ev_fair.c's header)
 * is a quintic (α quadratic × χ_F cubic, β linear × γ_t quartic) while every corner stays
 * compatible.  With all four sides quintic and the cubic Hermite blend, the Coons patch is a
 * bi-quintic polynomial (coons_patch.c; the K = 1 bubbles are of degree <= 5 too): the fit then
 * reproduces it with one span, and the G1 relation between two such patches holds to rounding —
 * exact G1 at extraordinary vertices (docs/extraordinary.md, "Polynomial gluing of G1 patches").
 *
 * The price is at the corners.  Writing α(s) = α0 (1-s)² + 2q s(1-s) + α1 s² (Bernstein; q free)
 * and β(s) = β0 (1-s) + β1 s, the derived face's twist at end 0 of the side (d/ds of χ_G) gains
 * α'(0) χ_F(0) + β'(0) γ_t(0), which the jets' corner maps (linear) do not have.  So each face
 * corner's outgoing twist (the mixed derivative along its two edges, parametric) becomes the jet's
 * plus J r, J the jet's tangent map and r a chart vector of that corner, and per derived side and
 * end, with G the derived face, F the base face, u, w the edge's and F's cross edge's chart
 * directions at that end, d, e_w their intervals (all as ev_fair_patch.c's side data):
 *     end 0:  r_G = α0 r_F + α'(0) e_w w0 + β' d u0,
 *     end 1:  r_G = α1 r_F - α'(1) e_w w1 + β' d u1,       α'(0) = 2(q - α0), α'(1) = 2(α1 - q).
 * (The jet parts agree as before: w_G = α w_F + β u in each chart.)  At a vertex of odd valence the
 * corrections follow uniquely (around the vertex the α's multiply to (-1)^n); at even valence the
 * equations hold only for suitable q's (two conditions per vertex).
 *
 * Which edges (ev_policy.h, EV_POLY_*):
 *   - between two free vertices — every corner there extraordinary, none with a side that is a
 *     regular patch's (whose twist it must keep, r = 0), not a boundary vertex of one or two faces:
 *     the polynomial gluing above;
 *   - from a free vertex to a pinned one: a cubic α, β, flat at the pinned end, with free slopes
 *     α'(e), β'(e) at the free end (unknowns of the same solve; the first ring of an isolated
 *     extraordinary vertex has more conditions than q's without them); least squares in the fit —
 *     except from a cross-charted vertex (fe_build.cross: opposite edges opposite, so β = 0 there, as
 *     at the regular corner): then α is the quadratic flat at the corner (q = α there) and β stays
 *     zero, a quintic χ_G with known slopes at the free end (border_end);
 *   - where a component's equations then fail, first bumps c s(1 - s) in β along edges whose β
 *     vanishes at a cross-charted end (one unknown each; γ becomes a quartic that drops its second
 *     derivative where β vanishes, which enters no corner condition there: bump_ok), then free slopes
 *     back on one such flat side per round;
 *   - from a free vertex to a boundary vertex of two faces: α and β flat at that end (quadratics
 *     v_v + (v_o - v_v) τ², τ the parameter from the other end), γ the quartic with value and slope
 *     only there (ev_fair_patch.c quartic_taylor), and the derived face's side along the boundary
 *     takes the corner's twist from this edge (fe_side.absorb_side): it has no neighbour, so any twist
 *     is consistent, including the normal one β_v (γ_tt - the jet's) the quartic leaves.  χ_G is again
 *     a quintic; the free end's equations get known slopes and no unknown.  Where a component's
 *     equations then fail (those known slopes take away the freedom an even-valence vertex needs),
 *     these edges take a free q instead (linear β, quintic γ: the boundary side takes whatever twist
 *     that gives), and where that fails too the boundary vertices are pinned;
 *   - everything else keeps the smoothsteps, whose α' = β' = 0 at the ends give r_G = α r_F.
 *
 * The corrections, q's and slopes are solved per connected set of free vertices (a component: the
 * equations of different components share no unknown) as the least change from r = 0, q at the
 * chord's middle (α linear) and zero slopes, under the equations as constraints (a quadratic penalty
 * with iterative refinement, CHOLMOD).  An edge whose q misses the sign of α's ends (its
 * Bernstein coefficients of one sign keep α from vanishing, and a vanishing α folds the derived face)
 * first makes its component take a bump in β at that edge, where one may go (bump_ok, within
 * EV_POLY_SIGN_ROUNDS), else it becomes a free-slope cubic, and the solve is repeated; a component
 * whose equations fail is solved again as above (free q at two-face boundary vertices, then those
 * pinned); what still fails keeps the smoothsteps everywhere in the component. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sparse.h"
#include "core/vec3.h"
#include "patch/ev_fair_internal.h"
#include "patch/ev_policy.h"

#define PG_NZ 4
typedef struct pg_row {
    int ix[PG_NZ]; /* r_G (one component), r_F (the same component), then q or the two slopes (-1: none) */
    double co[PG_NZ], b;
    int comp;      /* component of the row's vertex */
    int v;         /* the row's vertex */
    double res;    /* its residual after the last solve */
} pg_row;

/* Vertex of corner c of face f, and the corner of f at vertex v (-1: none). */
static int fv(const q2n_mesh *m, int f, int c) { return m->face_vert[m->face_start[f] + c]; }
static int corner_of(const q2n_mesh *m, int f, int v)
{
    for (int c = 0; c < 4; c++)
        if (fv(m, f, c) == v) return c;
    return -1;
}

int q2n_ev_fair_base_side(const fe_build *B, const int *faces, const int *fidx, int i, int sd, int *sdF)
{
    const q2n_mesh *m = B->m;
    int e = m->he_edge[q2n_face_he(m, faces[i], sd)], g = B->base[e], gi = g >= 0 ? fidx[g] : -1;
    *sdF = -1;
    for (int t = 0; gi >= 0 && t < 4; t++)
        if (m->he_edge[q2n_face_he(m, g, t)] == e) *sdF = t;
    return *sdF >= 0 ? gi : -1;
}

int q2n_ev_fair_derived_base(const fe_build *B, const int *faces, const int *fidx, const fe_ctx *X, int i, int sd, int *sdF)
{
    const fe_side *S = &X[i].side[sd];
    *sdF = -1;
    return S->kind == 0 && S->derived ? q2n_ev_fair_base_side(B, faces, fidx, i, sd, sdF) : -1;
}

static int uf_find(int *p, int a)
{
    while (p[a] != a) a = p[a] = p[p[a]];
    return a;
}

/* Does the quadratic α of side S with middle Bernstein coefficient q keep away from zero: q of the
 * sign of both ends?  Then, with a0, a1, q > 0 after a sign flip, the minimum of
 * α(s) = a0 (1-s)² + 2q s(1-s) + a1 s² is an end's or (a0 a1 - q²) / (a0 - 2q + a1) at the interior
 * extremum, in both cases at least a0 a1 / (a0 + a1), half the smaller end or more: a vanishing α
 * would fold the derived face.  Until stop 47 |q| had to be a quarter of the smaller end as well;
 * that refused profiles that never come below half of it (docs/extraordinary.md, "The sign of q"). */
static int q_keeps_sign(const fe_side *S, double q)
{
    double a0 = S->al[0], a1 = S->al[1];
    return a0 * a1 > 0 && q * a0 > 0;
}

/* A derived side from a free vertex charted with opposite edges opposite (fe_build.cross) to a
 * regular patch's corner (pinned, vpin 2), whose β is the same at both ends (zero at both: at the
 * corner the regular patch's chart continues its grid lines, at the free vertex the cross chart):
 * α quadratic flat at the corner (q = α there) and β constant keep the corner's regular twist and
 * give the free end known slopes.  Returns the free end (0, 1), or -1. */
static int border_end(const fe_build *B, const fe_side *S, int v0, int v1, const char *vin, const char *vpin)
{
    if (!B->cross || !B->border_flat || S->kind != 0 || !S->derived) return -1;
    if (!(fabs(S->be[1] - S->be[0]) <= EV_POLY_BETA_SAME)) return -1;
    for (int e = 0; e < 2; e++) {
        int vf = e ? v1 : v0, vp = e ? v0 : v1;
        if (vin[vf] && !vpin[vf] && B->cross[vf] && !(B->noflat && B->noflat[vf]) && vpin[vp] == 2) return e;
    }
    return -1;
}

/* A derived side between two cross-charted vertices (β zero at both ends, border_end's charts): it may
 * take a bump c s (1 - s) in β, one more unknown of its component, if its γ becomes the quartic of
 * ev_fair_patch.c (β γ_t stays a quintic; γ's second derivatives enter no corner condition where β
 * vanishes). */
static int bump_ok(const fe_build *B, const fe_side *S, int v0, int v1)
{
    if (!B->cross || !B->border_flat || S->kind != 0 || !S->derived) return 0;
    int z0 = B->cross[v0] && fabs(S->be[0]) <= EV_POLY_BETA_SAME, z1 = B->cross[v1] && fabs(S->be[1]) <= EV_POLY_BETA_SAME;
    return z0 && z1 ? 1 : z0 ? 2 : z1 ? 3 : 0; /* fe_side.quartic: γ drops its second derivative where β vanishes */
}

/* May derived side k (face faces[k / 4], side k % 4) still take a bump in β: glued by a quadratic α
 * (its q an unknown, qix), not bumped yet, and between cross-charted ends (bump_ok)? */
static int bump_candidate(const fe_build *B, const int *faces, const fe_ctx *X, int k, const int *qix, const char *bumped)
{
    const fe_side *S = &X[k / 4].side[k % 4];
    return qix[k] >= 0 && !bumped[k] && bump_ok(B, S, fv(B->m, faces[k / 4], S->c0), fv(B->m, faces[k / 4], S->c1));
}

static double row_residual(const pg_row *R, const double *x)
{
    double r = R->b;
    for (int p = 0; p < PG_NZ; p++)
        if (R->ix[p] >= 0) r -= R->co[p] * x[R->ix[p]];
    return r;
}

/* min |x - x0|² subject to the rows, as the penalty problem (W² AᵀA + I) x = W² Aᵀ b + x0 refined:
 * each refinement solves for the rows' residuals again, which removes the penalty's bias. */
static q2n_status pg_solve(int n, const pg_row *R, int nrow, const double *x0, double *x, q2n_error *err)
{
    const double W2 = EV_POLY_PENALTY * EV_POLY_PENALTY;
    long cap = (long)PG_NZ * PG_NZ * nrow + n, nt = 0;
    int *ti = malloc(sizeof(int) * (size_t)cap), *tj = malloc(sizeof(int) * (size_t)cap);
    double *tv = malloc(sizeof(double) * (size_t)cap), *rhs = malloc(sizeof(double) * (size_t)n);
    double *dx = malloc(sizeof(double) * (size_t)n);
    q2n_status st = Q2N_OK;
    if (!ti || !tj || !tv || !rhs || !dx) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (polynomial gluing)"); goto done; }
    for (int k = 0; k < nrow; k++)
        for (int p = 0; p < PG_NZ; p++)
            for (int q = 0; q < PG_NZ; q++)
                if (R[k].ix[p] >= 0 && R[k].ix[q] >= 0 && R[k].ix[p] <= R[k].ix[q])
                    ti[nt] = R[k].ix[p], tj[nt] = R[k].ix[q], tv[nt++] = W2 * R[k].co[p] * R[k].co[q];
    for (int k = 0; k < n; k++) ti[nt] = tj[nt] = k, tv[nt++] = 1;
    memcpy(x, x0, sizeof(double) * (size_t)n);
    q2n_sparse_spd *S = NULL;
    if ((st = q2n_sparse_spd_from_triplets(n, nt, ti, tj, tv, &S, err))) goto done;
    for (int it = 0; it < EV_POLY_REFINE && !st; it++) { /* one factorisation, then solves */
        memset(rhs, 0, sizeof(double) * (size_t)n);
        for (int k = 0; k < nrow; k++) {
            double r = row_residual(&R[k], x);
            for (int p = 0; p < PG_NZ; p++)
                if (R[k].ix[p] >= 0) rhs[R[k].ix[p]] += W2 * R[k].co[p] * r;
        }
        st = it ? q2n_sparse_spd_resolve(S, 1, rhs, dx, err) : q2n_sparse_spd_factor_solve(S, 1, rhs, dx, err);
        if (!st)
            for (int k = 0; k < n; k++) x[k] += dx[k];
    }
    q2n_sparse_spd_free(S);
done:
    free(ti);
    free(tj);
    free(tv);
    free(rhs);
    free(dx);
    return st;
}

/* min Σ D_k (x_k - x0_k)² subject to the rows, exactly: x = x0 + D⁻¹ Aᵀ λ with (A D⁻¹ Aᵀ) λ = b - A x0
 * (the rows' normal equations; EV_POLY_DUAL_REG on the diagonal for rows that depend on each other),
 * refined.  Its error is rounding times the rows' own conditioning, where the penalty form's is
 * rounding times the penalty's square (1e10): the G2 gluing's twists must not move by more than
 * rounding when the mesh does (test_extraordinary, test_robust: scaled and translated cubes). */
static q2n_status pg_solve_exact(int n, const pg_row *R, int nrow, const double *x0, const double *D, double *x, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    memcpy(x, x0, sizeof(double) * (size_t)n);
    if (nrow == 0) return st;
    int *cnt = calloc((size_t)n + 1, sizeof(int)), *rows = malloc(sizeof(int) * ((size_t)PG_NZ * nrow + 1));
    int *pos = malloc(sizeof(int) * ((size_t)PG_NZ * nrow + 1));
    long cap = 0;
    for (int k = 0; k < nrow; k++)
        for (int p = 0; p < PG_NZ; p++)
            if (R[k].ix[p] >= 0 && cnt) cnt[R[k].ix[p] + 1]++;
    for (int j = 0; cnt && j < n; j++) cnt[j + 1] += cnt[j];
    for (int j = 0; cnt && j < n; j++) {
        long c = cnt[j + 1] - cnt[j];
        cap += c * (c + 1) / 2;
    }
    cap += nrow;
    int *ti = malloc(sizeof(int) * (size_t)cap), *tj = malloc(sizeof(int) * (size_t)cap);
    double *tv = malloc(sizeof(double) * (size_t)cap), *rhs = malloc(sizeof(double) * ((size_t)nrow + 1));
    double *lam = malloc(sizeof(double) * ((size_t)nrow + 1));
    if (!cnt || !rows || !pos || !ti || !tj || !tv || !rhs || !lam) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (polynomial gluing)"); goto done; }
    {
        int *fill = malloc(sizeof(int) * ((size_t)n + 1));
        if (!fill) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (polynomial gluing)"); goto done; }
        memcpy(fill, cnt, sizeof(int) * (size_t)n);
        for (int k = 0; k < nrow; k++)
            for (int p = 0; p < PG_NZ; p++)
                if (R[k].ix[p] >= 0) rows[fill[R[k].ix[p]]] = k, pos[fill[R[k].ix[p]]++] = p;
        free(fill);
    }
    long nt = 0;
    double dmax = 0;
    for (int j = 0; j < n; j++)
        for (int a = cnt[j]; a < cnt[j + 1]; a++)
            for (int b = a; b < cnt[j + 1]; b++) {
                int k = rows[a], l = rows[b];
                double v = R[k].co[pos[a]] * R[l].co[pos[b]] / D[j];
                ti[nt] = k < l ? k : l, tj[nt] = k < l ? l : k, tv[nt++] = v;
                if (k == l) dmax = fmax(dmax, v);
            }
    for (int k = 0; k < nrow; k++) ti[nt] = tj[nt] = k, tv[nt++] = EV_POLY_DUAL_REG * (dmax > 0 ? dmax : 1);
    q2n_sparse_spd *S = NULL;
    if ((st = q2n_sparse_spd_from_triplets(nrow, nt, ti, tj, tv, &S, err))) goto done;
    for (int it = 0; it < EV_POLY_DUAL_REFINE && !st; it++) {
        for (int k = 0; k < nrow; k++) rhs[k] = row_residual(&R[k], x);
        st = it ? q2n_sparse_spd_resolve(S, 1, rhs, lam, err) : q2n_sparse_spd_factor_solve(S, 1, rhs, lam, err);
        if (!st)
            for (int k = 0; k < nrow; k++)
                for (int p = 0; p < PG_NZ; p++)
                    if (R[k].ix[p] >= 0) x[R[k].ix[p]] += R[k].co[p] * lam[k] / D[R[k].ix[p]];
    }
    q2n_sparse_spd_free(S);
done:
    free(cnt);
    free(rows);
    free(pos);
    free(ti);
    free(tj);
    free(tv);
    free(rhs);
    free(lam);
    return st;
}

q2n_status q2n_ev_fair_poly_gluing(const fe_build *B, const int *faces, int nf, fe_ctx *X, const char *pin, int *poly_edges,
                                   int *border_edges, q2n_error *err)
{
    const q2n_mesh *m = B->m;
    size_t n4 = 4 * (size_t)(nf > 0 ? nf : 1);
    int *fidx = malloc(sizeof(int) * (size_t)m->nf), *uf = malloc(sizeof(int) * (size_t)m->nv);
    int *worst = malloc(sizeof(int) * (size_t)m->nv);
    char *vin = calloc((size_t)m->nv, 1), *vpin = calloc((size_t)m->nv, 1), *cbad = calloc((size_t)m->nv, 1);
    char *vabs = calloc((size_t)m->nv, 1); /* boundary vertices of two faces: their corners absorb the twist */
    char *vfq = calloc((size_t)m->nv, 1);  /* ... and their edges keep a free q instead of flat α, β */
    char *cubic = calloc(n4, 1); /* derived side: α, β cubic with free end slopes instead of poly */
    char *knoff = calloc(n4, 1); /* derived side that could be flat at a regular corner (border_end) but
                                    keeps free slopes: its component's equations needed them */
    double *kq = calloc(n4, sizeof(double)); /* border sides: q (α's value at the regular corner) */
    char *bumped = calloc(n4, 1); /* derived side between two cross-charted vertices with a bump in β */
    char *cand = calloc((size_t)m->nv, 1); /* per component: a side that may still take a bump */
    int *qsv = malloc(sizeof(int) * (size_t)m->nv); /* per component: a vertex of an edge whose q has the wrong sign */
    int *bix = malloc(sizeof(int) * n4), *nbump = calloc((size_t)m->nv, sizeof(int));
    int *bend = malloc(sizeof(int) * n4);                 /* this pass's border_end of each side */
    int *best = malloc(sizeof(int) * (size_t)m->nv);      /* per failed component: its chosen side */
    double *score = malloc(sizeof(double) * (size_t)m->nv);
    int *rix = malloc(sizeof(int) * n4), *qix = malloc(sizeof(int) * n4), (*six)[2] = malloc(sizeof *six * n4);
    int *comp = malloc(sizeof(int) * (8 * n4 + 1));
    pg_row *R = malloc(sizeof(pg_row) * 2 * n4);
    double *x = malloc(sizeof(double) * (8 * n4 + 1)), *x0 = malloc(sizeof(double) * (8 * n4 + 1));
    double *D = B->K >= 2 ? malloc(sizeof(double) * (8 * n4 + 1)) : NULL;
    /* G2 patches: per region Σ |d u| and the count of sides (2 nv), then per face its region's mean (nf) */
    double *hreg = B->K >= 2 ? calloc(2 * (size_t)m->nv + (size_t)nf + 1, sizeof(double)) : NULL, *hface = hreg ? hreg + 2 * m->nv : NULL;
    q2n_status st = Q2N_OK;
    *poly_edges = *border_edges = 0;
    if (B->K >= 2 && (!D || !hreg)) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (polynomial gluing)"); goto done; }
    if (D) { /* G2 patches: the twists' unit (below), per region of faces joined by their corners (whose
              * equations and jets are apart from the other regions') */
        for (int i = 0; i < nf; i++)
            for (int sd = 0; sd < 4; sd++)
                if (X[i].side[sd].kind == 0) {
                    int r = B->region[fv(m, faces[i], 0)];
                    hreg[2 * r] += X[i].side[sd].d * hypot(X[i].side[sd].u0[0], X[i].side[sd].u0[1]), hreg[2 * r + 1]++;
                }
        for (int v = 0; v < m->nv; v++) hreg[2 * v] = hreg[2 * v + 1] > 0 && hreg[2 * v] > 0 ? hreg[2 * v] / hreg[2 * v + 1] : 1;
        for (int i = 0; i < nf; i++) hface[i] = hreg[2 * B->region[fv(m, faces[i], 0)]];
    }
    if (!fidx || !uf || !worst || !vin || !vpin || !cbad || !vabs || !vfq || !cubic || !knoff || !kq || !bumped || !cand || !qsv || !bix || !nbump || !bend || !best || !score || !rix || !qix || !six || !comp || !R || !x || !x0) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (polynomial gluing)");
        goto done;
    }
    for (int f = 0; f < m->nf; f++) fidx[f] = -1;
    for (int i = 0; i < nf; i++) fidx[faces[i]] = i;
    /* free vertices: corners of extraordinary faces none of whose corners there has a regular side (vpin
     * 2), nor a boundary vertex of fewer than EV_POLY_BOUNDARY_FACES faces (vpin 1); absorbing ones:
     * boundary vertices of two faces without a regular side */
    for (int i = 0; i < nf; i++)
        for (int c = 0; c < 4; c++) {
            int v = fv(m, faces[i], c);
            vin[v] = 1;
            if (X[i].side[c].kind != 0 || X[i].side[(c + 3) & 3].kind != 0) vpin[v] = 2;
            else if (!vpin[v] && m->vert_boundary[v] && m->vert_nfaces[v] < EV_POLY_BOUNDARY_FACES) vpin[v] = 1;
        }
    /* G2 patches: no absorbing boundary vertices (their quartic γ is a G1 device); they stay pinned */
    for (int v = 0; v < m->nv; v++) vabs[v] = B->K == 1 && vin[v] && vpin[v] != 2 && m->vert_boundary[v] && m->vert_nfaces[v] == 2;
    for (int v = 0; pin && v < m->nv; v++) /* kept out by the caller (the construction's near-fold guard) */
        if (pin[v] && vin[v]) vpin[v] = 3, vabs[v] = 0;
#define VFREE(v) (vin[v] && !vpin[v])
    /* rounds: a component whose equations fail with the edges flat at boundary vertices of two faces
     * is solved again with a free q on those edges (their twists at the boundary vertex go to the
     * boundary sides as well: any α', β' there is consistent), and if that fails too, with those
     * vertices pinned (their edges then cubics with free slopes at the other end); a component that
     * fails otherwise gets the vertex of its largest residual pinned, and is solved again */
    int n = 0, nrow = 0, nr = 0;
    for (int round = 0, rev = 0; round < 2 + EV_POLY_PIN_ROUNDS; round++) {
        /* components: free vertices joined by constructed edges */
        for (int v = 0; v < m->nv; v++) uf[v] = v;
        for (int i = 0; i < nf; i++)
            for (int sd = 0; sd < 4; sd++) {
                const fe_side *S = &X[i].side[sd];
                int v0 = fv(m, faces[i], S->c0), v1 = fv(m, faces[i], S->c1);
                if (S->kind != 0 || !VFREE(v0) || !VFREE(v1)) continue;
                int a = uf_find(uf, v0), b = uf_find(uf, v1);
                if (a != b) uf[a < b ? b : a] = a < b ? a : b;
            }
        nr = 0;
        for (int i = 0; i < nf; i++)
            for (int c = 0; c < 4; c++) rix[4 * i + c] = VFREE(fv(m, faces[i], c)) ? (nr += 2) - 2 : -1;
        memset(cbad, 0, (size_t)m->nv);
        memset(cubic, 0, n4);
        /* passes: an edge whose q would let α approach zero keeps a cubic α, β with free slopes instead
         * (least squares in the fit, as before), and the component is solved again */
        for (int pass = 0; pass < EV_POLY_PASSES; pass++) {
            n = nr;
            for (int i = 0; i < nf; i++)
                for (int sd = 0; sd < 4; sd++) {
                    const fe_side *S = &X[i].side[sd];
                    int k = 4 * i + sd, v0 = fv(m, faces[i], S->c0), v1 = fv(m, faces[i], S->c1);
                    qix[k] = six[k][0] = six[k][1] = bix[k] = bend[k] = -1;
                    if (S->kind != 0 || !S->derived) continue;
                    int fq = (VFREE(v0) && vabs[v1] && vfq[v1]) || (VFREE(v1) && vabs[v0] && vfq[v0]);
                    if (((VFREE(v0) && VFREE(v1)) || fq) && !cubic[k]) {
                        comp[n] = uf_find(uf, VFREE(v0) ? v0 : v1);
                        x0[n] = 0.5 * (S->al[0] + S->al[1]);
                        qix[k] = n++;
                        if (bumped[k]) comp[n] = comp[n - 1], x0[n] = 0, bix[k] = n++;
                        continue;
                    }
                    if ((VFREE(v0) && vabs[v1]) || (VFREE(v1) && vabs[v0])) continue; /* flat at the absorbing end */
                    if (!knoff[k] && (bend[k] = border_end(B, S, v0, v1, vin, vpin)) >= 0) {
                        kq[k] = S->al[!bend[k]]; /* flat at the regular corner: known slopes at the free end */
                        continue;
                    }
                    for (int e = 0; e < 2; e++) {
                        int v = e ? v1 : v0;
                        if (!VFREE(v)) continue;
                        six[k][e] = n;
                        comp[n] = comp[n + 1] = uf_find(uf, v);
                        x0[n] = x0[n + 1] = 0;
                        n += 2;
                    }
                }
            for (int k = 0; k < nr; k++) x0[k] = 0;
            /* two rows per derived side and free end */
            nrow = 0;
            for (int i = 0; i < nf; i++)
                for (int sd = 0; sd < 4; sd++) {
                    const fe_side *S = &X[i].side[sd];
                    int sdF, gi = q2n_ev_fair_derived_base(B, faces, fidx, X, i, sd, &sdF);
                    if (gi < 0) continue;
                    int f = faces[i], g = faces[gi];
                    int k = 4 * i + sd, qi = qix[k];
                    for (int end = 0; end < 2; end++) {
                        int c = end ? S->c1 : S->c0, v = fv(m, f, c);
                        if (!VFREE(v)) continue;
                        int iG = rix[4 * i + c], iF = rix[4 * gi + corner_of(m, g, v)], si = six[k][end];
                        const double *w = end ? S->w1 : S->w0, *u = end ? S->u1 : S->u0;
                        double a = S->al[end], ew = S->ew[end], db = S->be[1] - S->be[0], sg = end ? -1 : 1;
                        for (int j = 0; j < 2; j++) {
                            pg_row *r = &R[nrow++];
                            r->ix[0] = iG + j, r->co[0] = 1;
                            r->ix[1] = iF + j, r->co[1] = -a;
                            r->ix[2] = r->ix[3] = -1, r->co[2] = r->co[3] = 0, r->b = 0;
                            if (qi >= 0) { /* α'(0) = 2(q - α0), α'(1) = 2(α1 - q); β' = β1 - β0 (± a bump) */
                                r->ix[2] = qi, r->co[2] = -2 * ew * w[j];
                                r->b = -2 * a * ew * w[j] + db * S->d * u[j];
                                if (bix[k] >= 0) r->ix[3] = bix[k], r->co[3] = (end ? 1 : -1) * S->d * u[j];
                            } else if (bend[k] == end) {
                                r->b = 2 * (kq[k] - a) * ew * w[j] + db * S->d * u[j]; /* q = kq known */
                            } else if (si >= 0) { /* the slopes α'(end), β'(end) */
                                r->ix[2] = si, r->co[2] = -sg * ew * w[j];
                                r->ix[3] = si + 1, r->co[3] = -S->d * u[j];
                            } else if (vabs[fv(m, f, end ? S->c0 : S->c1)]) { /* flat at the other end: known slopes */
                                double da = 2 * (S->al[end] - S->al[!end]), dbb = 2 * (S->be[end] - S->be[!end]);
                                double ap = end ? da : -da, bp = end ? dbb : -dbb; /* α'(end), β'(end) in d/ds */
                                r->b = sg * ap * ew * w[j] + bp * S->d * u[j];
                            }
                            r->comp = uf_find(uf, v), r->v = v;
                        }
                    }
                }
            /* G2 patches: the twists weighed in units of their region's mean edge vector d u in the
             * charts (the rows are homogeneous in chart units, q and the slopes are ratios), so that the
             * solution scales with the mesh (test_extraordinary's scaled cubes) and a region's does not
             * depend on the others' (until stop 55 one mean over every region); G1 patches keep the unit
             * weights they were measured with */
            if (D) {
                for (int k = 0; k < n; k++) D[k] = 1;
                for (int i = 0; i < nf; i++)
                    for (int c = 0; c < 4; c++)
                        if (rix[4 * i + c] >= 0) D[rix[4 * i + c]] = D[rix[4 * i + c] + 1] = 1 / (hface[i] * hface[i]);
            }
            if (n > 0 && (st = D ? pg_solve_exact(n, R, nrow, x0, D, x, err) : pg_solve(n, R, nrow, x0, x, err))) goto done;
            /* a q of the wrong sign: while its component may still take a bump (below), the bump comes
             * first, placed at that edge (qsv); else the edge becomes a cubic */
            int more = 0;
            memset(cand, 0, (size_t)m->nv);
            for (int k = 0; k < 4 * nf; k++)
                if (bump_candidate(B, faces, X, k, qix, bumped)) cand[comp[qix[k]]] = 1;
            for (int v = 0; v < m->nv; v++) qsv[v] = -1;
            for (int i = 0; i < nf; i++)
                for (int sd = 0; sd < 4; sd++) {
                    int k = 4 * i + sd, qi = qix[k];
                    if (qi < 0 || q_keeps_sign(&X[i].side[sd], x[qi])) continue;
                    int c = comp[qi];
                    if (cand[c] && nbump[c] < EV_POLY_BUMPS && rev < EV_POLY_SIGN_ROUNDS) {
                        if (qsv[c] < 0) qsv[c] = fv(m, faces[i], X[i].side[sd].c0);
                        continue;
                    }
                    cubic[k] = 1, more = 1;
                }
            for (int k = 0; k < 4 * nf; k++)
                if (bend[k] >= 0 && !q_keeps_sign(&X[k / 4].side[k % 4], kq[k])) knoff[k] = 1, more = 1;
            if (!more) break;
        }
        /* a component keeps its gluing when all its rows hold and its α's keep their sign */
        for (int k = 0; k < nrow; k++)
            if (!((R[k].res = fabs(row_residual(&R[k], x))) <= EV_POLY_RESIDUAL)) cbad[R[k].comp] = 1;
        for (int i = 0; i < nf; i++)
            for (int sd = 0; sd < 4; sd++) {
                int qi = qix[4 * i + sd];
                if (qi >= 0 && !q_keeps_sign(&X[i].side[sd], x[qi])) cbad[comp[qi]] = 1;
            }
        /* a failed component takes, one per round, a bump in β (at most EV_POLY_BUMPS), then gives back
         * the free slopes of the side flat at a regular corner whose free vertex lies nearest to the vertex
         * of its largest residual (an even-valence region lacks two unknowns, which one side's slopes
         * give); only then the round sequence below (free q at boundary vertices, pins) goes on */
        int reverted = 0;
        for (int v = 0; v < m->nv; v++) worst[v] = -1;
        for (int k = 0; k < nrow; k++) {
            int c = R[k].comp;
            if (cbad[c] && (worst[c] < 0 || R[k].res > R[worst[c]].res)) worst[c] = k;
        }
        /* one pass over the sides, the best candidate per failed component: a bump first (at the vertex
         * of the largest residual the edge whose direction there is nearest the failing chart component,
         * since a bump moves the corner equations along its edge; else the nearest edge), while the
         * component has had fewer than EV_POLY_BUMPS; else a flat side's slopes back (its free vertex
         * nearest that vertex).  Rows come in pairs j = 0, 1: the worst row's parity is its component. */
        for (int c = 0; c < m->nv; c++) best[c] = -1, score[c] = -1;
        for (int k = 0; k < 4 * nf; k++) {
            const fe_side *S = &X[k / 4].side[k % 4];
            int v0 = fv(m, faces[k / 4], S->c0), v1 = fv(m, faces[k / 4], S->c1), c = uf_find(uf, v0);
            if (worst[c] < 0 || nbump[c] >= EV_POLY_BUMPS || !bump_candidate(B, faces, X, k, qix, bumped)) continue;
            int vw = qsv[c] >= 0 ? qsv[c] : R[worst[c]].v;
            double sc;
            if (v0 == vw || v1 == vw) {
                const double *u = v0 == vw ? S->u0 : S->u1;
                sc = 2 + fabs(u[worst[c] & 1]) / hypot(u[0], u[1]);
            } else {
                double mid[3], d[3];
                q2n_v3_add(mid, q2n_mesh_vpos(m, v0), q2n_mesh_vpos(m, v1));
                q2n_v3_scale(mid, 0.5, mid);
                q2n_v3_sub(d, mid, q2n_mesh_vpos(m, vw));
                sc = 1 / (1 + q2n_v3_dot(d, d));
            }
            if (sc > score[c]) score[c] = sc, best[c] = k;
        }
        for (int c = 0; c < m->nv; c++)
            if (best[c] >= 0) bumped[best[c]] = 1, nbump[c]++, worst[c] = -1, reverted = 1;
        for (int c = 0; c < m->nv; c++) best[c] = -1, score[c] = INFINITY;
        for (int k = 0; k < 4 * nf; k++) {
            if (bend[k] < 0 || knoff[k]) continue;
            const fe_side *S = &X[k / 4].side[k % 4];
            int vf = fv(m, faces[k / 4], bend[k] ? S->c1 : S->c0), c = uf_find(uf, vf);
            if (worst[c] < 0) continue;
            double d[3];
            q2n_v3_sub(d, q2n_mesh_vpos(m, vf), q2n_mesh_vpos(m, R[worst[c]].v));
            double sc = q2n_v3_dot(d, d);
            if (sc < score[c]) score[c] = sc, best[c] = k;
        }
        for (int c = 0; c < m->nv; c++)
            if (best[c] >= 0) knoff[best[c]] = 1, reverted = 1;
        if (reverted && rev++ < EV_POLY_REVERT_ROUNDS) { /* not a round of the sequence below */
            round--;
            continue;
        }
        /* round 0 failed: the edges at those boundary vertices take a free q (their twists there go to the
         * boundary sides too); round 1 failed: the vertices are pinned */
        int changed = 0;
        for (int i = 0; round < 2 && i < nf; i++)
            for (int sd = 0; sd < 4; sd++) {
                const fe_side *S = &X[i].side[sd];
                if (S->kind != 0 || !S->derived) continue;
                int v0 = fv(m, faces[i], S->c0), v1 = fv(m, faces[i], S->c1);
                for (int e = 0; e < 2; e++) {
                    int vf = e ? v1 : v0, va = e ? v0 : v1;
                    if (!VFREE(vf) || !vabs[va] || !cbad[uf_find(uf, vf)]) continue;
                    if (round == 0 && !vfq[va]) vfq[va] = 1, changed = 1;
                    else if (round == 1 && vfq[va]) vabs[va] = 0, changed = 1;
                }
            }
        if (!changed) { /* the vertex of each failed component's largest residual pinned */
            for (int v = 0; v < m->nv; v++) worst[v] = -1; /* per component (its vertex): its worst row */
            for (int k = 0; k < nrow; k++) {
                int c = R[k].comp;
                if (cbad[c] && (worst[c] < 0 || R[k].res > R[worst[c]].res)) worst[c] = k;
            }
            for (int v = 0; v < m->nv; v++)
                if (worst[v] >= 0) vpin[R[worst[v]].v] = 3, changed = 1; /* one vertex per component and round */
        }
        if (!changed) break;
    }
    for (int i = 0; i < nf; i++)
        for (int sd = 0; sd < 4; sd++) {
            fe_side *S = &X[i].side[sd];
            if (S->kind != 0) continue;
            int f = faces[i], e = m->he_edge[q2n_face_he(m, f, sd)], g = B->base[e], gi = g >= 0 ? fidx[g] : -1;
            if (gi < 0) continue;
            int k = 4 * i + sd, qi = S->derived ? qix[k] : -1;
            if (qi >= 0 && !cbad[comp[qi]]) {
                S->poly = 1, S->q = x[qi], ++*poly_edges;
                if (bix[k] >= 0) { /* both sides of the edge: the quartic γ (in each side's own direction) */
                    int qk = bump_ok(B, S, fv(m, f, S->c0), fv(m, f, S->c1));
                    S->bump = x[bix[k]], S->quartic = qk;
                    for (int t = 0; t < 4; t++) {
                        fe_side *Sb = &X[gi].side[t];
                        if (Sb->kind != 0 || m->he_edge[q2n_face_he(m, g, t)] != e) continue;
                        int same = fv(m, g, Sb->c0) == fv(m, f, S->c0);
                        Sb->quartic = qk == 1 || same ? qk : 5 - qk;
                    }
                }
            }
            if (bend[k] >= 0 && !knoff[k] && !cbad[uf_find(uf, fv(m, f, bend[k] ? S->c1 : S->c0))]) /* as the last solve took it */
                S->poly = 1, S->q = kq[k], ++*poly_edges, ++*border_edges;
            int v0 = fv(m, f, S->c0), v1 = fv(m, f, S->c1);
            if (S->derived && ((VFREE(v0) && vabs[v1]) || (VFREE(v1) && vabs[v0])) && !cbad[uf_find(uf, VFREE(v0) ? v0 : v1)]) {
                int fe = vabs[v1] ? 1 : 0, va = fe ? v1 : v0, ca = fe ? S->c1 : S->c0;
                if (qi < 0) { /* flat α, β there; the base face's side on this edge has the same quartic γ */
                    S->flat_end = fe;
                    ++*poly_edges;
                    for (int t = 0; t < 4; t++) {
                        fe_side *Sb = &X[gi].side[t];
                        if (Sb->kind != 0 || m->he_edge[q2n_face_he(m, g, t)] != e) continue;
                        Sb->flat_end = fv(m, g, Sb->c1) == va ? 1 : 0;
                    }
                }
                /* this face's other side at that corner (on the boundary) takes the corner's twist from here */
                int so = ca == sd ? (sd + 3) & 3 : (sd + 1) & 3;
                fe_side *Sx = &X[i].side[so];
                int ex = Sx->c0 == ca ? 0 : 1;
                Sx->absorb_side[ex] = sd, Sx->absorb_end[ex] = fe;
            }
            for (int end = 0; end < 2; end++) {
                int v = fv(m, f, end ? S->c1 : S->c0), keep = VFREE(v) && !cbad[uf_find(uf, v)];
                int iF = rix[4 * gi + corner_of(m, g, v)], si = S->derived ? six[k][end] : -1;
                S->rc[end][0] = keep ? x[iF] : 0; /* the base face's corrections */
                S->rc[end][1] = keep ? x[iF + 1] : 0;
                S->sl[0][end] = keep && si >= 0 ? x[si] : 0;
                S->sl[1][end] = keep && si >= 0 ? x[si + 1] : 0;
            }
        }
#undef VFREE
done:
    free(D);
    free(hreg);
    free(fidx);
    free(uf);
    free(worst);
    free(vin);
    free(vpin);
    free(cbad);
    free(vabs);
    free(vfq);
    free(cubic);
    free(knoff);
    free(kq);
    free(bumped);
    free(cand);
    free(qsv);
    free(bix);
    free(nbump);
    free(bend);
    free(best);
    free(score);
    free(rix);
    free(qix);
    free(six);
    free(comp);
    free(R);
    free(x);
    free(x0);
    return st;
}
