/* ev_fair_internal.h — what the three files of the fair extraordinary construction share
 * (docs/extraordinary.md, "The fair construction"); internal to src/patch/:
 *   ev_fair_patch.c  a face's patch: its constructed sides' fields from the jets of its corners,
 *                    sides shared with a regular patch from that patch, the Coons side function;
 *   ev_fair_solve.c  the energy: per-face forms, the sparse system, the passes, the fold guard;
 *   ev_fair.c        the driver: vertex jets and unknowns, base faces, flat fans, the patches
 *                    attached to the surface. */
#ifndef Q2N_PATCH_EV_FAIR_INTERNAL_H
#define Q2N_PATCH_EV_FAIR_INTERNAL_H

#include <string.h>

#include "patch/coons_patch.h"
#include "patch/ev_fair.h"
#include "patch/ev_jet4.h"

typedef struct fe_side {
    int kind;            /* 0 constructed from the jets, 1 sampled from a regular neighbour */
    ev_side reg;         /* kind 1 */
    int c0, c1;          /* kind 0: patch corners at s = 0 and s = 1 */
    double d;            /* the edge's interval */
    double u0[2], u1[2]; /* the edge's direction in the charts of its two end vertices */
    double w0[2], w1[2]; /* the base face's inward cross direction at the two ends */
    double ew[2];        /* the base face's cross-edge intervals at the two ends */
    int derived;         /* this face is the derived side */
    double al[2], be[2]; /* α, β at the two ends */
    int poly;            /* G1, derived side: α quadratic (Bernstein middle coefficient q), β linear
                            (ev_fair_gluing.c); 0: both smoothsteps */
    double q;
    double sl[2][2];     /* G1, derived side that is not poly: slopes d/ds of α (sl[0]) and β (sl[1])
                            at the two ends of their cubic Hermite interpolants (0, 0: smoothsteps;
                            ev_fair_gluing.c) */
    int flat_end;        /* G1: -1, or the end (0, 1) at a boundary vertex of two faces where this edge's
                            γ keeps value and slope only (a quartic) and, on the derived side, α and β
                            are flat (ev_fair_gluing.c) */
    int absorb_side[2], absorb_end[2]; /* boundary side: at end e its twist is the one the patch's side
                            absorb_side[e] has at its end absorb_end[e] (-1: its own) */
    double rc[2][2];     /* twist corrections of the base face's corners at the two ends (chart
                            vectors r: the corner's outgoing twist gains J r; ev_fair_gluing.c) */
    int quartic;         /* G1, an edge whose β vanishes at one end or both (ev_fair_gluing.c; both sides
                            of the edge): γ is a quartic with value and slope at both ends and the
                            second derivative at the end where β does not vanish (1: at neither, both
                            matched in least squares; 2: at end 1 only; 3: at end 0 only); 0: none */
    double bump;         /* G1, derived side with a quartic γ: β gains bump s (1 - s) */
    double cm[2][3][2];  /* G2 polynomial gluing (ev_fair_gluing2.c): the base face's corner-map terms at the two
                            ends beyond the twist, chart vectors of a² b, a b², a² b² (a: from the end along this
                            side, b: across into the base face) */
    double tg[2][2][3];  /* G2, derived side: the G2 relation's tangential terms A (times χ_F) and B (times γ_t),
                            [A or B][end][derivative 0..2 in s]: quintic Hermite interpolants */
} fe_side;

/* A constructed side with the smoothsteps' gluing: no polynomial gluing, slopes, flat end, borrowed
 * twist or twist corrections (what ev_fair_gluing.c may set). */
static inline void fe_side_smooth(fe_side *S)
{
    S->poly = 0, S->q = 0, S->quartic = 0, S->bump = 0;
    S->flat_end = S->absorb_side[0] = S->absorb_side[1] = -1;
    S->absorb_end[0] = S->absorb_end[1] = 0;
    for (int e = 0; e < 2; e++) S->sl[0][e] = S->sl[1][e] = S->rc[e][0] = S->rc[e][1] = 0;
    memset(S->cm, 0, sizeof S->cm);
    memset(S->tg, 0, sizeof S->tg);
}

/* Does side S carry G2 polynomial gluing's corner terms or tangential G2 terms (ev_fair_gluing2.c)? */
static inline int fe_side_g2(const fe_side *S)
{
    const double *c = &S->cm[0][0][0], *t = &S->tg[0][0][0];
    for (int k = 0; k < 12; k++)
        if (c[k] != 0 || t[k] != 0) return 1;
    return 0;
}

/* Does derived side S glue by α, β with free end slopes (ev_fair_gluing.c: cubic for G1 patches,
 * quintic with zero second derivatives for G2 ones)? */
static inline int fe_side_slopes(const fe_side *S)
{
    return S->sl[0][0] != 0 || S->sl[0][1] != 0 || S->sl[1][0] != 0 || S->sl[1][1] != 0;
}

/* Does constructed side S carry anything of ev_fair_gluing.c's (what fe_side_smooth clears)? */
static inline int fe_side_glued(const fe_side *S)
{
    if (S->kind != 0) return 0;
    int g = S->poly || S->quartic || S->flat_end >= 0 || S->absorb_side[0] >= 0 || S->absorb_side[1] >= 0;
    for (int e = 0; e < 2; e++) g |= S->rc[e][0] != 0 || S->rc[e][1] != 0;
    return g || fe_side_slopes(S) || fe_side_g2(S);
}

/* Side context of one patch (the Coons patch's ctx); lanes: fe_lanes, its constructed sides' fields
 * as polynomials (fill_lanes, from the W-wide jets of the four corners). */
typedef struct fe_ctx {
    int K, kb;
    double d0, d1, e0, e1; /* intervals of sides 0, 2 (u) and 3, 1 (v) */
    fe_side side[4];
} fe_ctx;

/* The sides' three fields as polynomials in s, expanded about both ends: FE_TC(T, b, e, k) is the
 * coefficient of (s - e)^k in field b (γ, then the face's first and second cross derivatives), k <=
 * deg[b].  An evaluation expands about the nearer end (|s - e| <= 1/2: no cancellation grows with the
 * degree), and at the ends the coefficients are the end data themselves (divided by k!): the
 * corner values are exact. */
#define FE_TDEG 17 /* ξ_G of order K = 2: degree 2(2K + 1) + 4K - 1 */
#define FE_TRUNS 8  /* runs of nonzero lanes an evaluation visits (more: all lanes) */
typedef struct fe_taylor {
    int W, deg[3];
    double *c;
    int nrun, run[FE_TRUNS][2]; /* the lanes [run[r][0], run[r][1]) hold every nonzero coefficient */
} fe_taylor;
#define FE_TC(T, b, e, k) ((T)->c + (size_t)((((b) * 2 + (e)) * (FE_TDEG + 1)) + (k)) * (T)->W)
#define FE_TAYLOR_SIZE(W) ((size_t)3 * 2 * (FE_TDEG + 1) * (W))

/* The lanes a fair patch's side function reads: its sides' fields (fill_lanes). */
typedef struct fe_lanes {
    fe_taylor T[4];
} fe_lanes;

/* The production patch: the Coons evaluator first (the surface's data pointer is this struct). */
typedef struct fe_eval {
    cp_eval E;
    fe_ctx X;
    fe_lanes lanes;
    double tayv[4][FE_TAYLOR_SIZE(3)];
} fe_eval;

/* The ridge of an unknown towards its local estimate (fair_pass). */
typedef enum { RIDGE_HIGH = 0, RIDGE_LOW = 1, RIDGE_HELD = 2, RIDGE_CORNER = 3 } fe_ridge; /* orders 3, 4 and bubbles; orders 1, 2; held (fold guard, a boundary corner's orders 3, 4); a boundary corner's order 2 (G2) */

typedef struct fe_build {
    const q2n_mesh *m;
    const q2n_surface *s;
    const double *iv;
    const double (*dir)[2];
    const char *unc;
    int K, kb;
    int *base;                  /* per edge: base face (-1 when not constructed) */
    int *region;                /* per vertex: its region, the smallest vertex of the listed faces joined
                                   by their corners that it is a corner of (q2n_mesh_corner_regions): each
                                   region's jets are solved apart from the others' */
    double (*jet)[EV_JS][3];    /* per vertex: current jet values */
    int *var;                   /* per vertex and slot: unknown index or -1 (fixed) */
    int *bvar;                  /* per face of the list: first of its CP_NBUB bubble unknowns */
    double (*bub)[CP_NBUB][3];  /* per face of the list: bubble values */
    char *ridge;                /* per unknown: its ridge towards the local estimate, an fe_ridge */
    int nvar;
    const char *flat;           /* per vertex: its fan is flat (fan_flat) and the first solve keeps its
                                   free jet terms in the plane (coupled_solve); NULL: none */
    const double (*flatn)[3];   /* per vertex: the unit normal of a flat fan's plane */
    const char *cross;          /* G1 polynomial gluing: per vertex, charted with opposite edges opposite
                                   (border_cross: its edges to regular patches' corners glue exactly);
                                   NULL: none */
    int border_flat;            /* ... and those edges are glued flat at the corner (ev_fair_gluing.c
                                   border_end); 0: they keep free slopes at w */
    const char *noflat;         /* per vertex: with border_flat, its edges keep free slopes all the same
                                   (the border guard's neighbourhoods of sheared faces); NULL: none */
} fe_build;

/* ------------------------------------------------------------ ev_fair_patch.c */

/* Direction of edge e in the chart of its end vertex v (dir of q2n_ev_vertex_jets). */
const double *q2n_ev_fair_edge_dir(const q2n_mesh *m, const double (*dir)[2], int e, int v);
/* Face f's other edge at its corner v (e one of f's edges at v), and its direction in v's chart
 * (NULL when e is not an edge of f at v). */
int q2n_ev_fair_cross_edge(const q2n_mesh *m, int f, int e, int v);
const double *q2n_ev_fair_cross_dir(const q2n_mesh *m, const double (*dir)[2], int f, int e, int v);
/* |sin| of the angle between two chart directions. */
double q2n_ev_fair_sine2(const double a[2], const double b[2]);
/* Face f's side context X and Coons patch P (sides, α and β of its derived sides). */
q2n_status q2n_ev_fair_setup_patch(const fe_build *B, int f, fe_ctx *X, cp_patch *P, q2n_error *err);
/* The lanes of a patch whose corner jets are J (W lanes each, slot-major): the constructed sides'
 * fields, in tayv (4 sides, FE_TAYLOR_SIZE(W) doubles each). */
void q2n_ev_fair_fill_lanes(const fe_ctx *X, const double *const J[4], int W, fe_lanes *L, double *tayv);
/* Patch i of the list (face f, context FX) with the current jets and bubbles, ready to evaluate
 * (the caller frees it with q2n_ev_fair_eval_free). */
fe_eval *q2n_ev_fair_make_eval(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P);
void q2n_ev_fair_eval_free(void *d);

/* ------------------------------------------------------------ ev_fair_gluing.c */

/* G1 patches (K = 1): quadratic α and linear β on the constructed edges between free vertices, and
 * the corners' twist corrections that keep them compatible (the sides' poly, q and rc), wherever a
 * component's equations hold; *poly_edges counts the edges that took it, *border_edges those of
 * them glued flat at a regular patch's corner (fe_build.border_flat).  pin (per vertex, NULL: none):
 * vertices kept out, as the corners of regular patches are. */
q2n_status q2n_ev_fair_poly_gluing(const fe_build *B, const int *faces, int nf, fe_ctx *X, const char *pin, int *poly_edges,
                                   int *border_edges, q2n_error *err);

/* The base face of constructed side sd of face faces[i] (its edge's base), as an index of the list
 * (fidx: per mesh face its index, -1 when not listed), and *sdF its side on that edge; -1 when the base
 * face is not in the list or the side is no constructed one (ev_fair_gluing.c). */
int q2n_ev_fair_base_side(const fe_build *B, const int *faces, const int *fidx, int i, int sd, int *sdF);
/* The same for a derived side only (its base face the other face on its edge): -1 for a base side too. */
int q2n_ev_fair_derived_base(const fe_build *B, const int *faces, const int *fidx, const fe_ctx *X, int i, int sd, int *sdF);

/* ------------------------------------------------------------ ev_fair_gluing2.c */

/* G2 patches (K = 2) glued by polynomials: after q2n_ev_fair_poly_gluing (the twists), the corner-map
 * terms of orders (2, 1), (1, 2), (2, 2) of every face corner and the G2 relation's tangential terms of
 * every derived side, so that both sides of every corner agree to order (2, 2) (fe_side.cm, tg).
 * fail (per vertex, may be NULL) marks vertices whose equations did not hold (their corners keep
 * what they had: the caller pins them and builds again); *nfail counts them. */
q2n_status q2n_ev_fair_poly_gluing2(const fe_build *B, const int *faces, int nf, fe_ctx *X, char *fail, int *nfail,
                                    q2n_error *err);

/* The Taylor coefficients, about end e of derived side S of a G2 patch in the distance a from that end,
 * of α̃(a) and B(a) (∂b S_G = α̃ ∂b S_F + B ∂a S_F, a = s or 1 - s): al[0..2], bt[0..2] (ev_fair_patch.c,
 * as side_taylor glues it). */
void q2n_ev_fair_glue_taylor(const fe_side *S, int e, double al[3], double bt[3]);

/* ------------------------------------------------------------ ev_fair_solve.c */

/* Smallest |S_u x S_v| of patch i (context FX) on a grid, over its median (near 0: nearly folded). */
double q2n_ev_fair_jacobian_ratio(const fe_build *B, int i, int f, const fe_ctx *FX, const cp_patch *P);

/* The faces of the list whose patches fold over (r[i] 1, else 0); their number, -1 out of memory or
 * where one cannot be evaluated. */
int q2n_ev_fair_folded(const fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX, int threads,
                       signed char *r);

/* The energy solve over the nfaces faces of the list (their patches P, contexts FX): the jets'
 * and bubbles' values in B become the minimiser, with the fold guard; *held_vertices, *folds_left
 * and *shrinks describe the result (docs/extraordinary.md, "The fair construction", 5). */
q2n_status q2n_ev_fair_solve(fe_build *B, const int *faces, int nfaces, const cp_patch *P, const fe_ctx *FX, int threads,
                             int *held_vertices, int *folds_left, int *shrinks, q2n_error *err);

#endif
