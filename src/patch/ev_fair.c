/* ev_fair.c — the fair extraordinary construction: one jet per vertex, compatible Coons patches,
 * jets and interior bubbles chosen by a fairness-energy solve (issue 11; docs/extraordinary.md).
 *
 * Every vertex that is a corner of an extraordinary face gets ONE jet P_v of order 2K (4 in G2
 * mode, 2 in G1 mode) in its chart (ev_jet4.h; the charts are the edge directions of
 * q2n_ev_vertex_jets).  Every datum of the curve network is a contraction of the jets at the two ends
 * of its edge, parametric in the edge's t in [0,1] (d: the edge's interval, u: its direction in
 * an end's chart, w: the face's other edge there, e_w that edge's interval):
 *   γ(t)    boundary curve: Hermite interpolant of order 2K (degree 4K+1) of d^j T_j[u^j];
 *   χ_F(t)  inward cross derivative of the base face F: order 2K-1 Hermite interpolant of
 *           d^j e_w T_(j+1)[u^j, w];
 *   ξ_F(t)  (G2) second cross derivative: order 2K-2 interpolant of d^j e_w² T_(j+2)[u^j, w, w];
 *   derived face G: χ_G = α χ_F + β γ_t, ξ_G = α² ξ_F + 2αβ ∂t χ_F + β² γ_tt (formulas.md §4.2
 *           with its γ, δ terms zero), α, β smoothsteps of order K between their end values, which
 *           solve e_w' w' = α e_w w + β d u in each end's chart.
 * So G1 (G2) holds exactly along every constructed edge for ANY jets, and every mixed corner
 * derivative a side delivers is the jet's (α, β are flat at the ends, the corner maps linear):
 * the two sides of every corner agree and the patch (coons_patch.c) is the plain Boolean-sum Coons
 * patch with polynomial corner terms — no rational Gregory blend, no corrective bumps.  Sides
 * shared with a regular augmented patch take that patch's data (q2n_ev_side_eval, §4.1); at their
 * vertices the jet's terms with both exponents <= 2 are the regular patch's (Lemma 1), so those
 * corners agree too (checked; a corner where they do not keeps a Gregory blend, counted).
 *
 * The patches are linear in the jets' free coefficients (all but the position and, at vertices
 * of regular patches, the terms with both exponents <= 2) and in CP_NBUB interior bubbles per
 * face.  They minimise a fairness energy over the extraordinary faces, in each face's
 * arc-length-scaled parameters x = u L_u, y = v L_v:
 *     E = Σ_F ∫ |S_xx|² + 2|S_xy|² + |S_yy|² dA  +  w3 Σ_F ω_F L_F² ∫ |S_xxx|² + 3|S_xxy|² + 3|S_xyy|² + |S_yyy|² dA,
 * bending (thin plate) plus curvature variation (Moreton–Séquin's minimal-variation term), both
 * dimensionless; ω_F lowers the variation term on faces where a first, bending-only solve leaves
 * far more variation than on the typical face (thin features whose curvature must change fast:
 * they would otherwise dictate the shape everywhere).  A small ridge towards the local estimates
 * of q2n_ev_vertex_jets keeps the problem definite.  One sparse SPD solve (CHOLMOD) per pass, shared
 * by x, y and z.
 *
 * This file is the driver: the jets' initial values and unknowns, the base face of every
 * constructed edge, flat fans, and the patches attached to the surface.  A face's patch (its sides'
 * fields from the jets) is ev_fair_patch.c, the energy solve and its fold guard ev_fair_solve.c;
 * ev_fair_internal.h is what the three share. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/par.h"
#include "core/vec3.h"
#include "patch/ev_fair_internal.h"
#include "patch/ev_policy.h"

/* Slots that are unknowns at a vertex: every slot of order 1..Kc, except at vertices of regular
 * patches the terms with both exponents <= 2 (fixed by that patch, Lemma 1). */
static int slot_free(int Kc, int fixed, int j, int i)
{
    if (j < 1 || j > Kc) return 0;
    if (!fixed) return 1;
    return j - i > 2 || i > 2;
}

/* Is vertex v's fan flat: at least two faces around v, and every corner of every one of them
 * within EV_FLAT_REL of the fan's radius from the tangent plane of v's local estimate (unit
 * normal into n)?  That estimate is then exact, and the energy may not bend the plane
 * (docs/extraordinary.md, "Flat fans"); a lone face says too little. */
static int fan_flat(const q2n_mesh *m, int v, const ev_vjet *J, double n[3])
{
    return q2n_ev_jet_normal(J, n) && q2n_ev_fan_in_plane(m, v, n) >= 2;
}

/* Between the two solves of --keep-flat: the free terms of the flat fans lose what is left of their
 * normal parts (the second solve holds them fixed), every other jet returns to its local estimate
 * (the ridge's target again) and the nf faces' bubbles to zero. */
static void fix_flat_jets(fe_build *B, const char *flat, const double (*flatn)[3], const double (*jet0)[EV_JS][3], int nf)
{
    for (int v = 0; v < B->m->nv; v++) {
        if (!flat[v]) {
            memcpy(B->jet[v], jet0[v], sizeof jet0[v]);
            continue;
        }
        for (int k = 0; k < EV_JS; k++) {
            if (B->var[v * EV_JS + k] < 0) continue; /* the estimates and a regular patch's terms stay */
            double *T = B->jet[v][k], d = q2n_v3_dot(T, flatn[v]);
            for (int c = 0; c < 3; c++) T[c] -= d * flatn[v][c];
        }
    }
    memset(B->bub, 0, (size_t)nf * sizeof *B->bub);
}

/* Number the unknowns: the free jet slots of every vertex with a jet (slot_free), except those of
 * the vertices marked in skip and those of orders 1 and 2 of the vertices marked in low (NULL:
 * none), then CP_NBUB bubbles per face of the list. */
static void assign_unknowns(fe_build *B, const ev_vjet *vj, int nf, const char *skip, const char *low)
{
    int Kc = 2 * B->K;
    B->nvar = 0;
    for (int i = 0; i < B->m->nv * EV_JS; i++) B->var[i] = -1;
    for (int v = 0; v < B->m->nv; v++) {
        if (!vj[v].source || (skip && skip[v])) continue;
        for (int j = (low && low[v]) ? 3 : 1; j <= Kc; j++)
            for (int i = 0; i <= j; i++)
                if (slot_free(Kc, vj[v].source == 1, j, i)) B->var[v * EV_JS + EV_SLOT(j, i)] = B->nvar++;
    }
    for (int i = 0; i < nf; i++) {
        B->bvar[i] = B->nvar;
        B->nvar += CP_NBUB;
    }
}

/* Corners whose two sides disagree (possible only where a side comes from a regular patch:
 * constructed data are jet contractions, and they involve only the fixed terms there) keep a
 * Gregory blend. */
static void mark_gregory(const fe_build *B, const int *faces, int nf, const fe_ctx *X, cp_patch *CP, ev_fair_stats *stats)
{
    const q2n_mesh *m = B->m;
    if (stats) stats->gregory_corners = 0, stats->corner_mismatch_max = 0;
    for (int i = 0; i < nf; i++) {
        double ctv[3 * 36 * 3], tayv[4 * FE_TAYLOR_SIZE(3)];
        cp_corner C = {3, ctv};
        const double *J[4];
        fe_lanes L;
        memset(CP[i].greg, 0, sizeof CP[i].greg);
        for (int c = 0; c < 4; c++) J[c] = &B->jet[m->face_vert[m->face_start[faces[i]] + c]][0][0];
        q2n_ev_fair_fill_lanes(&X[i], J, 3, &L, tayv);
        q2n_cp_corner_terms(&CP[i], &L, 3, &C);
        for (int ci = 0; ci < 2; ci++)
            for (int cj = 0; cj < 2; cj++) {
                double mis = q2n_cp_corner_mismatch(&CP[i], &C, ci, cj);
                if (mis > EV_FAIR_COMPAT_REL) {
                    CP[i].greg[q2n_corner_at(ci, cj)] = 1;
                    if (stats) stats->gregory_corners++;
                }
                if (stats) stats->corner_mismatch_max = fmax(stats->corner_mismatch_max, mis);
            }
    }
}

/* What one construction leaves: its polynomial edges and the solve's fold figures. */
typedef struct fe_run {
    int poly_edges, border_edges, held, folds, shrinks;
} fe_run;

/* What every construction of one build starts from: the faces of the list with their side contexts
 * and patches, the local estimates (jet0) and the flat fans. */
typedef struct fe_inputs {
    const ev_vjet *vj;
    const int *faces;
    int nf;
    fe_ctx *X;
    cp_patch *CP;
    const double (*jet0)[EV_JS][3];
    const char *flat;
    const double (*flatn)[3];
    int nflat, threads;
    ev_fair_stats *stats;
} fe_inputs;

/* The polynomial gluing (ev_fair_gluing.c; for G2 patches also ev_fair_gluing2.c, whose vertices that
 * fail are pinned and the gluing solved again, at most EV_POLY2_PIN_ROUNDS times; what fails after
 * that keeps the smoothsteps everywhere). */
static q2n_status glue(fe_build *B, const fe_inputs *in, const char *pin, fe_run *R, q2n_error *err)
{
    const q2n_mesh *m = B->m;
    fe_ctx *X = in->X;
    int nf = in->nf;
    if (B->K < 2) return q2n_ev_fair_poly_gluing(B, in->faces, nf, X, pin, &R->poly_edges, &R->border_edges, err);
    char *pin2 = calloc((size_t)m->nv, 1), *fail = calloc((size_t)m->nv, 1);
    q2n_status st = Q2N_OK;
    if (!pin2 || !fail) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory"); goto done; }
    if (pin) memcpy(pin2, pin, (size_t)m->nv);
    for (int round = 0;; round++) {
        if ((st = q2n_ev_fair_poly_gluing(B, in->faces, nf, X, pin2, &R->poly_edges, &R->border_edges, err))) break;
        int nfail = 0;
        memset(fail, 0, (size_t)m->nv);
        if ((st = q2n_ev_fair_poly_gluing2(B, in->faces, nf, X, fail, &nfail, err))) break;
        if (nfail == 0) break;
        for (int i = 0; i < nf; i++)
            for (int sd = 0; sd < 4; sd++)
                if (X[i].side[sd].kind == 0) fe_side_smooth(&X[i].side[sd]);
        R->poly_edges = R->border_edges = 0;
        if (round >= EV_POLY2_PIN_ROUNDS) break;
        for (int v = 0; v < m->nv; v++) pin2[v] |= fail[v];
    }
done:
    free(pin2);
    free(fail);
    return st;
}

/* One construction from the local estimates: the sides' gluing (smoothsteps; with poly, polynomial
 * where the corner equations allow it, the vertices marked in pin kept out), the Gregory corners and
 * the energy solve.  With flat fans (keep_flat): their jets' orders 1 and 2 are the local
 * estimates, exact for planar data; a first solve keeps their higher orders in the plane up to
 * EV_FLAT_PENALTY (coupled_solve), those then lose what is left of their normal parts and are fixed,
 * and a second solve fits everything else to them (docs/extraordinary.md, "Flat fans"). */
static q2n_status construct(fe_build *B, const fe_inputs *in, int poly, const char *pin, fe_run *R, q2n_error *err)
{
    const q2n_mesh *m = B->m;
    const ev_vjet *vj = in->vj;
    const int *faces = in->faces;
    int nf = in->nf, nflat = in->nflat;
    fe_ctx *X = in->X;
    const double (*jet0)[EV_JS][3] = in->jet0;
    const char *flat = in->flat;
    q2n_status st = Q2N_OK;
    memset(R, 0, sizeof *R);
    memcpy(B->jet, jet0, (size_t)m->nv * sizeof *jet0);
    memset(B->bub, 0, (size_t)nf * sizeof *B->bub);
    for (int i = 0; i < nf; i++)
        for (int sd = 0; sd < 4; sd++)
            if (X[i].side[sd].kind == 0) fe_side_smooth(&X[i].side[sd]);
    assign_unknowns(B, vj, nf, NULL, nflat ? flat : NULL);
    B->flat = NULL;
    if (poly && (st = glue(B, in, pin, R, err))) return st;
    mark_gregory(B, faces, nf, X, in->CP, in->stats);
    for (int stage = 0; stage < (nflat ? 2 : 1); stage++) {
        if (stage == 1) {
            fix_flat_jets(B, flat, in->flatn, jet0, nf);
            B->flat = NULL;
            assign_unknowns(B, vj, nf, flat, NULL);
        } else if (nflat) {
            B->flat = flat;
            B->flatn = in->flatn;
        }
        free(B->ridge);
        if (!(B->ridge = calloc((size_t)(B->nvar ? B->nvar : 1), 1))) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory");
        for (int i = 0; i < m->nv * EV_JS; i++)
            if (B->var[i] >= 0) {
                /* a corner of the mesh's boundary (one face) keeps its curvature near its local
                 * estimate and its orders 3 and 4 at zero (ev_policy.h, EV_FAIR_RIDGE_CORNER) */
                int v = i / EV_JS, sl = i % EV_JS, corner = m->vert_boundary[v] && m->vert_nfaces[v] == 1;
                B->ridge[B->var[i]] = sl < EV_SLOT(2, 0) ? RIDGE_LOW
                                      : sl <= EV_SLOT(2, 2) ? (corner ? RIDGE_CORNER : RIDGE_LOW)
                                      : corner ? RIDGE_HELD : RIDGE_HIGH;
            }
        if ((st = q2n_ev_fair_solve(B, faces, nf, in->CP, X, in->threads, &R->held, &R->folds, &R->shrinks, err))) return st;
    }
    return Q2N_OK;
}

/* A construction's state: the jets, bubbles and side contexts (their gluing), and what it left. */
typedef struct fe_state {
    double (*jet)[EV_JS][3];
    double (*bub)[CP_NBUB][3];
    fe_ctx *X;
    fe_run run;
} fe_state;

static void state_free(fe_state *S) { free(S->jet), free(S->bub), free(S->X); }
/* Save B's state and R into S, allocated at its first use (only a repeated construction needs one);
 * 0: out of memory. */
static int state_save(fe_state *S, const fe_build *B, const fe_inputs *in, const fe_run *R)
{
    const fe_ctx *X = in->X;
    int nf = in->nf;
    if (!S->jet) S->jet = malloc((size_t)B->m->nv * sizeof *S->jet);
    if (!S->bub) S->bub = malloc((size_t)(nf ? nf : 1) * sizeof *S->bub);
    if (!S->X) S->X = malloc((size_t)(nf ? nf : 1) * sizeof *S->X);
    if (!S->jet || !S->bub || !S->X) return 0;
    memcpy(S->jet, B->jet, (size_t)B->m->nv * sizeof *S->jet);
    memcpy(S->bub, B->bub, (size_t)nf * sizeof *S->bub);
    memcpy(S->X, X, (size_t)nf * sizeof *S->X);
    S->run = *R;
    return 1;
}
/* Take the saved construction back into B and R; its Gregory corners marked again. */
static void state_restore(const fe_state *S, fe_build *B, const fe_inputs *in, fe_run *R)
{
    memcpy(B->jet, S->jet, (size_t)B->m->nv * sizeof *S->jet);
    memcpy(B->bub, S->bub, (size_t)in->nf * sizeof *S->bub);
    memcpy(in->X, S->X, (size_t)in->nf * sizeof *S->X);
    *R = S->run;
    mark_gregory(B, in->faces, in->nf, in->X, in->CP, in->stats);
}

/* Every face's Jacobian ratio (q2n_ev_fair_jacobian_ratio; -1: out of memory), on the threads. */
typedef struct jr_arg {
    const fe_build *B;
    const fe_inputs *in;
    double *r;
} jr_arg;
static void jac_one(void *arg, int i)
{
    const jr_arg *a = arg;
    a->r[i] = q2n_ev_fair_jacobian_ratio(a->B, i, a->in->faces[i], &a->in->X[i], &a->in->CP[i]);
}
static void jac_ratios(const fe_build *B, const fe_inputs *in, double *r)
{
    jr_arg a = {B, in, r};
    q2n_par_for(in->nf, in->threads, jac_one, &a);
}

/* Mark the four corners of face f of m. */
static void mark_corners(const q2n_mesh *m, int f, char *mark)
{
    for (int c = 0; c < 4; c++) mark[m->face_vert[m->face_start[f] + c]] = 1;
}

/* Faces whose Jacobian ratio r is below EV_POLY_JAC_REL of the reference's rb, their corners marked in
 * mark; -1 out of memory (a ratio of -1). */
static int sheared(const fe_build *B, const fe_inputs *in, const double *r, const double *rb, char *mark)
{
    int n = 0;
    for (int i = 0; i < in->nf; i++) {
        if (r[i] < -0.5 || rb[i] < -0.5) return -1;
        if (r[i] < EV_POLY_JAC_REL * rb[i]) n++, mark_corners(B->m, in->faces[i], mark);
    }
    return n;
}

/* Border guard of the G1 polynomial gluing.  Glued flat at a regular patch's corner (border_flat),
 * the edges from cross-charted vertices give their free ends known slopes, and the twist corrections
 * those force can shear a face nearby toward a fold — one the near-fold guard below does not see,
 * since the face's own sides may be smooth: the energy solve passes the shear on.  So the construction
 * is repeated with those edges' free slopes (border_flat 0, same jets and charts), and a face is
 * sheared where its Jacobian ratio is below EV_POLY_JAC_REL of what this gives it.  Where none is, the
 * first is kept; else the construction is repeated with free slopes only on the edges from vertices
 * within 0, 1, ... EV_POLY_GUARD_RINGS - 1 edges of a sheared face's corners (fe_build.noflat; the
 * faces sheared on the way join them) while each ring shears fewer faces than the one before, the
 * first that shears none kept; if none does, the one without flat edges (B->border_flat 0).  R and
 * the state are the kept construction's.  S: scratch. */
static q2n_status border_shear(fe_build *B, const fe_inputs *in, fe_run *R, fe_state *S, q2n_error *err)
{
    const q2n_mesh *m = B->m;
    int nf = in->nf, bad = 0, kept = 0;
    q2n_status st = Q2N_OK;
    size_t nb = sizeof(double) * (size_t)(nf ? nf : 1);
    double *rf = malloc(nb), *rb = malloc(nb);
    char *nof = calloc((size_t)m->nv, 1), *grow = calloc((size_t)m->nv, 1);
    fe_state S1 = {0};
    if (!rf || !rb || !nof || !grow || !state_save(S, B, in, R)) { st = Q2N_ERR_NOMEM; goto out; }
    jac_ratios(B, in, rf);
    B->border_flat = 0;
    if ((st = construct(B, in, 1, NULL, R, err))) goto out;
    jac_ratios(B, in, rb);
    if ((bad = sheared(B, in, rf, rb, nof)) < 0) { st = Q2N_ERR_NOMEM; goto out; }
    if (!bad) {
        state_restore(S, B, in, R);
        B->border_flat = 1;
        goto out;
    }
    if (!state_save(&S1, B, in, R)) { st = Q2N_ERR_NOMEM; goto out; }
    B->noflat = nof;
    for (int ring = 0; ring < EV_POLY_GUARD_RINGS && !kept; ring++) {
        if (ring > 0) { /* one edge further */
            memcpy(grow, nof, (size_t)m->nv);
            for (int e = 0; e < m->ne; e++) {
                int h = m->edge_he[e], a = q2n_he_origin(m, h), b = q2n_he_dest(m, h);
                if (grow[a] || grow[b]) nof[a] = nof[b] = 1;
            }
        }
        B->border_flat = 1;
        if ((st = construct(B, in, 1, NULL, R, err))) goto out;
        if (R->border_edges == 0) break; /* nothing flat left: the construction without is kept */
        jac_ratios(B, in, rf);
        int nbad = sheared(B, in, rf, rb, nof);
        if (nbad < 0) { st = Q2N_ERR_NOMEM; goto out; }
        kept = nbad == 0;
        if (nbad >= bad) break; /* no fewer sheared faces than before: growing does not help */
        bad = nbad;
    }
    if (!kept) {
        state_restore(&S1, B, in, R);
        B->border_flat = 0;
    } else {
        nof = NULL; /* B->noflat now; the caller frees it */
    }
out:
    if (nof && B->noflat == nof) B->noflat = NULL; /* not kept (or an error): B lets go of it */
    free(rf);
    free(rb);
    free(nof);
    free(grow);
    state_free(&S1);
    return st == Q2N_ERR_NOMEM ? q2n_error_set(err, st, "out of memory (border guard)") : st;
}

/* Faces whose Jacobian ratio (q2n_ev_fair_jacobian_ratio) the polynomial gluing takes below
 * EV_POLY_JAC_REL of what the smoothsteps give with the same jets and bubbles (G2 patches: or below
 * EV_POLY2_JAC_FLOOR where the smoothsteps give at least that); their corners are
 * marked in pin (NULL: only counted).  -1 out of memory.  The smoothsteps' ratio is at most 1 (a
 * minimum over a median), so it is evaluated only where the gluing's is below EV_POLY_JAC_REL. */
typedef struct nf_arg {
    const fe_build *B;
    const int *faces;
    const fe_ctx *X;
    const cp_patch *CP;
    signed char *bad; /* per face of the list: 1 nearly folded by the gluing, 0 not, -1 out of memory */
} nf_arg;

static void near_fold_one(void *arg, int i)
{
    nf_arg *a = arg;
    const fe_ctx *X = &a->X[i];
    int glued = 0;
    a->bad[i] = 0;
    for (int sd = 0; sd < 4; sd++) glued |= fe_side_glued(&X->side[sd]);
    if (!glued) return;
    double rp = q2n_ev_fair_jacobian_ratio(a->B, i, a->faces[i], X, &a->CP[i]);
    if (rp < -0.5) { a->bad[i] = -1; return; }
    if (!(rp < EV_POLY_JAC_REL)) return;
    fe_ctx Xs = *X;
    for (int sd = 0; sd < 4; sd++)
        if (Xs.side[sd].kind == 0) fe_side_smooth(&Xs.side[sd]);
    double rs = q2n_ev_fair_jacobian_ratio(a->B, i, a->faces[i], &Xs, &a->CP[i]);
    /* G2 patches: also where the gluing takes the face below the fold target that the smoothsteps keep */
    int floor = a->B->K >= 2 && rp < EV_POLY2_JAC_FLOOR && rs >= EV_POLY2_JAC_FLOOR;
    a->bad[i] = rs < -0.5 ? -1 : rp < EV_POLY_JAC_REL * rs || floor;
}

static int near_folds(const fe_build *B, const int *faces, int nf, const fe_ctx *X, const cp_patch *CP, int threads, char *pin)
{
    const q2n_mesh *m = B->m;
    nf_arg a = {B, faces, X, CP, malloc((size_t)(nf ? nf : 1))};
    if (!a.bad) return -1;
    q2n_par_for(nf, threads, near_fold_one, &a);
    int nbad = 0;
    for (int i = 0; i < nf && nbad >= 0; i++) {
        if (a.bad[i] < 0) nbad = -1;
        else if (a.bad[i]) {
            nbad++;
            if (pin) mark_corners(m, faces[i], pin);
        }
    }
    free(a.bad);
    return nbad;
}

/* Free vertices at a region's border (G1 polynomial gluing): interior vertices of valence 4 whose
 * four faces are all extraordinary and one of whose neighbours is a regular patch's corner.  Charted
 * with opposite edges exactly opposite (ev_derivatives.c fan_angles), such a vertex has β = 0 at its
 * end of every edge, and so has that corner (a regular patch's chart continues its grid lines), so
 * the edge between them can take β constant and α a quadratic flat at the corner: the corner keeps
 * its regular twist and the derived side is still a quintic (ev_fair_gluing.c).  0 when out of
 * memory. */
static char *border_cross(const q2n_mesh *m, const char *unc)
{
    char *cross = calloc((size_t)m->nv, 1), *pinned = calloc((size_t)m->nv, 1);
    if (!cross || !pinned) { free(cross); free(pinned); return NULL; }
    for (int f = 0; f < m->nf; f++)
        if (!unc[f]) mark_corners(m, f, pinned);
    int edges[EV_MAXVAL], other[EV_MAXVAL], faces[EV_MAXVAL];
    for (int v = 0; v < m->nv; v++) {
        if (m->vert_boundary[v] || m->valence[v] != 4 || pinned[v]) continue;
        if (q2n_ev_vertex_fan(m, v, EV_MAXVAL, edges, other, faces) != 4) continue;
        int all = 1, border = 0;
        for (int k = 0; k < 4; k++) {
            all &= faces[k] >= 0 && unc[faces[k]];
            border |= pinned[other[k]];
        }
        cross[v] = all && border;
    }
    free(pinned);
    return cross;
}

/* The corners of the faces of the list that fold in the current construction (q2n_ev_fair_folded),
 * marked 1 in hit (m->nv, zeroed).  The number of folded faces, -1 out of memory. */
static int folded_corners(const fe_build *B, const fe_inputs *in, char *hit)
{
    signed char *r = malloc((size_t)(in->nf ? in->nf : 1));
    int n = r ? q2n_ev_fair_folded(B, in->faces, in->nf, in->CP, in->X, in->threads, r) : -1;
    for (int i = 0; i < in->nf && n > 0; i++)
        if (r[i]) mark_corners(B->m, in->faces[i], hit);
    free(r);
    return n;
}

/* The folded faces and the ring of faces around them kept out of the gluing in the next construction:
 * every vertex of a face that has a corner of a folded face goes into pin.  The number of folded
 * faces, -1 out of memory. */
static int pin_fold_rings(const fe_build *B, const fe_inputs *in, char *pin)
{
    const q2n_mesh *m = B->m;
    char *hit = calloc((size_t)m->nv, 1);
    int n = hit ? folded_corners(B, in, hit) : -1;
    for (int i = 0; i < in->nf && n > 0; i++) {
        int near = 0;
        for (int c = 0; c < 4; c++) near |= hit[m->face_vert[m->face_start[in->faces[i]] + c]];
        if (near) mark_corners(m, in->faces[i], pin);
    }
    free(hit);
    return n;
}

/* The regions (B->region) with a folded face kept out of the gluing in the next construction: pin
 * becomes used's vertices (the construction's own; NULL: none) and every vertex of those regions.  The
 * number of corners of listed faces left out of pin (0: no region is left glued), -1 out of memory. */
static int pin_fold_regions(const fe_build *B, const fe_inputs *in, const char *used, char *pin)
{
    const q2n_mesh *m = B->m;
    char *hit = calloc((size_t)m->nv, 1);
    int n = hit ? folded_corners(B, in, hit) : -1;
    if (n >= 0) {
        for (int v = 0; v < m->nv; v++) /* a folded face's corner marks its region's root (bit 2) */
            if (hit[v] & 1) hit[B->region[v]] |= 2;
        for (int v = 0; v < m->nv; v++) pin[v] = (used && used[v]) || (hit[B->region[v]] & 2);
        n = 0;
        for (int i = 0; i < in->nf; i++)
            for (int c = 0; c < 4; c++) n += !pin[m->face_vert[m->face_start[in->faces[i]] + c]];
    }
    free(hit);
    return n;
}

q2n_status q2n_ev_fair_build(const q2n_mesh *m, const q2n_mesh *chart_mesh, q2n_surface *s, const double *iv, const q2n_spline_class *cls, int K,
                         int keep_flat, int poly_gluing, const char *smooth_v, int threads, ev_fair_stats *stats, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    fe_build B = {0};
    fe_state S0 = {0};
    char *gpin = NULL, *cross = NULL;
    B.m = m;
    B.s = s;
    B.iv = iv;
    B.K = K;
    B.kb = cls->k;
    int nf = 0;
    ev_vjet *vj = calloc((size_t)m->nv, sizeof *vj);
    double (*dir)[2] = calloc(2 * (size_t)m->ne, sizeof *dir);
    char *unc = calloc((size_t)m->nf, 1);
    int *faces = malloc((size_t)m->nf * sizeof *faces);
    double (*jet0)[EV_JS][3] = calloc((size_t)m->nv, sizeof *jet0);
    char *flat = calloc((size_t)m->nv, 1);
    double (*flatn)[3] = calloc((size_t)m->nv, sizeof *flatn);
    int nflat = 0;
    fe_ctx *X = calloc((size_t)m->nf, sizeof *X);
    cp_patch *CP = calloc((size_t)m->nf, sizeof *CP);
    B.jet = calloc((size_t)m->nv, sizeof *B.jet);
    B.var = malloc((size_t)m->nv * EV_JS * sizeof *B.var);
    B.base = malloc((size_t)m->ne * sizeof *B.base);
    B.bvar = malloc((size_t)m->nf * sizeof *B.bvar);
    B.bub = calloc((size_t)m->nf, sizeof *B.bub);
    B.region = malloc((size_t)m->nv * sizeof *B.region);
    if (stats) memset(stats, 0, sizeof *stats);
    if (!vj || !dir || !unc || !faces || !jet0 || !flat || !flatn || !X || !CP || !B.jet || !B.var || !B.base || !B.bvar || !B.bub ||
        !B.region) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair extraordinary construction)");
        goto done;
    }
    B.dir = (const double (*)[2])dir;
    B.unc = unc;
    for (int f = 0; f < m->nf; f++)
        if ((unc[f] = q2n_surface_kind(s, f) == Q2N_PATCH_UNCOVERED)) faces[nf++] = f;
    q2n_mesh_corner_regions(m, unc, B.region);
    if (K == 1 && poly_gluing && !(cross = border_cross(m, unc))) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fair extraordinary construction)");
        goto done;
    }
    B.cross = cross;
    if ((st = q2n_ev_vertex_jets(m, chart_mesh, s, iv, cls, 0, cross, vj, dir, err))) goto done;

    /* jets: initial values (the local estimates; orders 3, 4 zero) and unknowns */
    for (int v = 0; v < m->nv; v++) {
        if (!vj[v].source) continue;
        double (*T)[3] = jet0[v];
        memcpy(T[0], q2n_mesh_vpos(m, v), 3 * sizeof(double));
        for (int c = 0; c < 3; c++) {
            T[EV_SLOT(1, 0)][c] = vj[v].J1[c][0];
            T[EV_SLOT(1, 1)][c] = vj[v].J1[c][1];
            T[EV_SLOT(2, 0)][c] = vj[v].J2[c][0];
            T[EV_SLOT(2, 1)][c] = vj[v].J2[c][1];
            T[EV_SLOT(2, 2)][c] = vj[v].J2[c][2];
            if (vj[v].source == 1) {
                T[EV_SLOT(3, 1)][c] = vj[v].Jm[c][0];
                T[EV_SLOT(3, 2)][c] = vj[v].Jm[c][1];
                T[EV_SLOT(4, 2)][c] = vj[v].Jm[c][2];
            }
        }
        if (keep_flat && fan_flat(m, v, &vj[v], flatn[v])) {
            flat[v] = 1;
            nflat++;
        }
        if (stats) stats->vertices++, stats->fixed_vertices += vj[v].source == 1;
    }
    if (stats) stats->flat_vertices = nflat;
    assign_unknowns(&B, vj, nf, NULL, nflat ? flat : NULL);
    memcpy(B.jet, jet0, (size_t)m->nv * sizeof *jet0);

    /* constructed edges and their base faces: the face whose cross direction is the more
     * transversal to the edge at its worse end (α = ratio of the transversal parts stays moderate);
     * within EV_BASE_TIE of a tie the edge's owner face, so that rounding-level changes of a
     * symmetric mesh do not flip the choice (docs/extraordinary.md, "Base faces") */
    for (int e = 0; e < m->ne; e++) {
        B.base[e] = -1;
        int h = m->edge_he[e], t = m->he_twin[h], f0 = m->he_face[h], f1 = t >= 0 ? m->he_face[t] : -1;
        int c0 = unc[f0], c1 = f1 >= 0 && unc[f1];
        if (!(c0 || c1) || (f1 >= 0 && (!c0 || !c1))) continue; /* not constructed */
        if (stats) stats->edges++;
        if (f1 < 0) { B.base[e] = f0; continue; }
        int va = q2n_he_origin(m, h), vb = q2n_he_dest(m, h);
        double q[2];
        for (int k = 0; k < 2; k++) {
            int f = k ? f1 : f0;
            const double *wa = q2n_ev_fair_cross_dir(m, B.dir, f, e, va), *wb = q2n_ev_fair_cross_dir(m, B.dir, f, e, vb);
            q[k] = fmin(q2n_ev_fair_sine2(wa, q2n_ev_fair_edge_dir(m, B.dir, e, va)), q2n_ev_fair_sine2(wb, q2n_ev_fair_edge_dir(m, B.dir, e, vb)));
        }
        B.base[e] = q[1] > q[0] * (1.0 + EV_BASE_TIE) ? f1 : f0;
    }
    for (int i = 0; i < nf && !st; i++) st = q2n_ev_fair_setup_patch(&B, faces[i], &X[i], &CP[i], err);
    if (st) goto done;
    /* G1: polynomial gluing where a region's corner equations allow it (ev_fair_gluing.c).  Its twist
     * corrections are fixed before the energy solve, whose fold guard cannot hold them, so two guards
     * of its own follow: faces whose Jacobian ratio the gluing takes below EV_POLY_JAC_REL of the
     * smoothsteps' (same jets) get their corners pinned (out of the gluing) and the construction is
     * repeated, kept when fewer faces are left so; and where the solve leaves faces folded over, the
     * smoothsteps are tried and kept when they fold on fewer faces. */
    int poly = poly_gluing;
    fe_run R = {0};
    const fe_inputs in = {vj, faces, nf, X, CP, (const double (*)[EV_JS][3])jet0, flat, (const double (*)[3])flatn, nflat,
                          threads, stats};
    B.border_flat = cross != NULL;
    if ((st = construct(&B, &in, poly, smooth_v, &R, err))) goto done;
    if (R.border_edges > 0 && (st = border_shear(&B, &in, &R, &S0, err))) goto done;
    const char *pin_used = smooth_v; /* the vertices the kept construction kept out of the gluing */
    if (poly && R.poly_edges > 0) {
        if (!(gpin = calloc((size_t)m->nv, 1))) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory"); goto done; }
        int nbad = near_folds(&B, faces, nf, X, CP, threads, gpin);
        if (nbad < 0) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fold check)"); goto done; }
        for (int v = 0; smooth_v && v < m->nv; v++) gpin[v] |= smooth_v[v];
        if (nbad > 0) {
            int folds0 = R.folds;
            if (!state_save(&S0, &B, &in, &R)) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory"); goto done; }
            if ((st = construct(&B, &in, 1, gpin, &R, err))) goto done;
            int nbad2 = near_folds(&B, faces, nf, X, CP, threads, NULL);
            if (stats) stats->jac_pinned_faces = nbad;
            if (!(nbad2 >= 0 && nbad2 < nbad && R.folds <= folds0)) { /* the guard did not help */
                state_restore(&S0, &B, &in, &R);
                if (stats) stats->jac_pinned_faces = 0;
            } else {
                pin_used = gpin;
            }
        }
        if (R.folds > 0 && R.poly_edges > 0) {
            /* where faces fold: first they and the ring of faces around them leave the gluing, kept
             * where no face is left folded; else the smoothsteps in the regions that fold (regions
             * are solved apart; everywhere when no region is left glued), kept where that folds on
             * fewer faces than the gluing did */
            int folds0 = R.folds;
            if (!state_save(&S0, &B, &in, &R)) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory"); goto done; }
            for (int v = 0; v < m->nv; v++) gpin[v] = pin_used && pin_used[v];
            if (pin_fold_rings(&B, &in, gpin) < 0) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fold check)"); goto done; }
            if ((st = construct(&B, &in, 1, gpin, &R, err))) goto done;
            if (R.folds > 0) { /* back to the gluing's construction, its folded regions with the smoothsteps */
                state_restore(&S0, &B, &in, &R);
                int left = pin_fold_regions(&B, &in, pin_used, gpin);
                if (left < 0) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (fold check)"); goto done; }
                if ((st = construct(&B, &in, left > 0, left > 0 ? gpin : NULL, &R, err))) goto done;
                if (!(R.folds < folds0)) state_restore(&S0, &B, &in, &R);
            }
        }
    }
    int poly_edges = R.poly_edges, held = R.held, folds = R.folds, shrinks = R.shrinks;
    if (stats) stats->polynomial_edges = poly_edges, stats->border_edges = R.border_edges;
    for (int v = 0; stats && R.poly_edges > 0 && B.noflat && B.cross && v < m->nv; v++) stats->noflat_vertices += B.noflat[v] && B.cross[v];
    if (stats) stats->unknowns = B.nvar, stats->held_vertices = held, stats->folded_faces = folds, stats->shrinks = shrinks;

    for (int i = 0; i < nf; i++) {
        int f = faces[i];
        fe_eval *E = q2n_ev_fair_make_eval(&B, i, f, &X[i], &CP[i]);
        if (!E) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (patch %d)", f); goto done; }
        if ((st = q2n_surface_set_patch(s, f, Q2N_PATCH_COONS_GREGORY, E, q2n_cp_eval_point, q2n_ev_fair_eval_free))) {
            free(E);
            q2n_error_set(err, st, "%s: face %d: cannot attach the patch", m->name, f);
            goto done;
        }
        q2n_surface_set_patch_grid(s, f, q2n_cp_eval_grid);
        q2n_surface_set_patch_grid_pos(s, f, q2n_cp_eval_grid_pos);
        q2n_surface_set_patch_corner(s, f, q2n_cp_eval_corner);
    }
done:
    free(gpin);
    free(cross);
    free((char *)B.noflat);
    state_free(&S0);
    free(vj);
    free(dir);
    free(unc);
    free(faces);
    free(jet0);
    free(flat);
    free(flatn);
    free(X);
    free(CP);
    free(B.jet);
    free(B.var);
    free(B.base);
    free(B.region);
    free(B.bvar);
    free(B.bub);
    free(B.ridge);
    return st;
}
