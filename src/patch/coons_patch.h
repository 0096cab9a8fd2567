/* coons_patch.h — the Boolean-sum Coons patch with Hermite blending (formulas.md §4.1), optional
 * Gregory corners (§4.2) and interior bubbles, shared by the extraordinary-vertex constructions
 * (ev_fair_patch.c, ev_paper.c).  Internal to src/patch/.
 *
 * A construction supplies, for each of the four sides (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0;
 * the side parameter s is u on sides 0, 2 and v on sides 1, 3: patch/surface.h), the uv fields
 *     F[b][a] = ∂s^a ∂n^b S  on the side   (n = v on sides 0, 2, u on sides 1, 3; b <= K, a < na)
 * and the patch is  S = P_u + P_v - P_uv + Σ_b φ_b bub_b  with blending functions of degree 2K+1.
 * The mixed corner terms a, b >= 1 are the constant corner values where the two sides agree;
 * at a Gregory corner (greg[c] set) they are the rational pairs (ũ^K B + ṽ^K A)/(ũ^K + ṽ^K).
 *
 * Everything is linear in the side data, so all values are W-wide "lanes" (ev_jet4.h): the
 * production evaluator is W = 3; the fair construction's energy assembly carries the response to
 * every free coefficient in lanes 3.. W-1. */
#ifndef Q2N_PATCH_COONS_PATCH_H
#define Q2N_PATCH_COONS_PATCH_H

#include "core/error.h"
#include "core/hermite.h"

#define CP_NBUB 4                  /* interior bubbles per face */
#define CP_MAXW (3 + 4 * 14 + CP_NBUB) /* lanes: xyz + four corner jets' free coefficients + bubbles */
#define CP_NA 4                    /* along-side derivatives 0..3 */

/* Side data of side sd at s into F (lanes 0..W-1, along derivatives 0..na-1, cross orders 0..K). */
typedef void (*cp_side_fn)(const void *ctx, const void *lanes, int W, int sd, double s, int na,
                           double F[3][CP_NA][CP_MAXW]);

typedef struct cp_patch {
    int K;             /* 1: bicubic blend (G1 data), 2: biquintic (G2 data) */
    int greg[4];       /* corner c (q2n_corner_uv, patch/surface.h) keeps a Gregory blend */
    cp_side_fn side;
    const void *ctx;
} cp_patch;

/* Corner values, W lanes each: kind 0 M (the constant terms), 1 A (from the v = j side), 2 B
 * (from the u = i side); (i, j) the corner, a, b <= 2 the orders. */
typedef struct cp_corner {
    int W;
    double *v; /* 3 * 2 * 2 * 3 * 3 * W */
} cp_corner;
#define CP_CT(C, k, i, j, a, b) ((C)->v + (size_t)(((((k) * 2 + (i)) * 2 + (j)) * 3 + (a)) * 3 + (b)) * (C)->W)

/* What the sum needs from one parameter line: the two sides' fields (u-lines: sides 0, 2; v-lines:
 * sides 3, 1; W lanes each, CP_LS) and the Hermite weights.  The fields live in the caller's
 * storage (CP_LINE_SIZE(W) doubles), so the production evaluators (W = 3) stay small. */
typedef struct cp_line {
    int W;
    double *s;
    double H[3][2][Q2N_HERMITE_MAXD + 1];
} cp_line;
#define CP_LINE_SIZE(W) ((size_t)2 * 3 * CP_NA * (W))
#define CP_LS(L, i, b, a) ((L)->s + (size_t)((((i) * 3 + (b)) * CP_NA) + (a)) * (L)->W)

void q2n_cp_corner_terms(const cp_patch *P, const void *lanes, int W, cp_corner *C);
/* Fill line L (its storage L->s set by the caller, CP_LINE_SIZE(W) doubles) at u or v. */
void q2n_cp_line_u(const cp_patch *P, const void *lanes, int W, double u, int na, cp_line *L);
void q2n_cp_line_v(const cp_patch *P, const void *lanes, int W, double v, int na, cp_line *L);

/* Partials of S at (u, v) up to total order nder (0..3) into out (W lanes each, in the order
 * S; Su, Sv; Suu, Suv, Svv; Suuu, Suuv, Suvv, Svvv): needs lines computed with na > nder.
 * bub: CP_NBUB x W bubble coefficients, or NULL.  Third derivatives treat a Gregory corner as
 * its constant A values (the energy assembly is their only user). */
void q2n_cp_sum(const cp_patch *P, const cp_corner *C, const double *bub, int W, double u, double v, int nder,
            const cp_line *Lu, const cp_line *Lv, double *out);

/* The same partials on the tensor grid us[a] x vs[b] (lines Lu[a], Lv[b], na > 3 for third
 * orders), orders omin..omax of q2n_cp_sum's list, out[((b * nu + a) * (omax - omin + 1) + o - omin) * W
 * + l].  Corner terms are the constant M (Gregory blends are ignored: the energy assembly is the
 * user; they differ from M by rounding-level mismatches). */
void q2n_cp_grid(const cp_patch *P, const cp_corner *C, const double *bub, int W, int nu, const double *us,
             const cp_line *Lu, int nv, const double *vs, const cp_line *Lv, int omin, int omax, double *out);

/* The bubbles φ_b and their partials up to order 3 at (u, v), in q2n_cp_sum's order. */
void q2n_cp_bubbles(int K, double u, double v, double ph[CP_NBUB][10]);

/* Largest disagreement of the two sides' mixed corner values (a, b = 1..K) at corner (i, j),
 * relative to the corner's first- and mixed-derivative scale (W = 3 corner terms). */
double q2n_cp_corner_mismatch(const cp_patch *P, const cp_corner *C, int i, int j);

/* Production evaluators over a struct that starts with these fields (W = 3). */
typedef struct cp_eval {
    cp_patch P;
    cp_corner C;             /* points at ct */
    double ct[3 * 36 * 3];
    double bub[CP_NBUB][3];
    const void *lanes;       /* passed to the side callback */
    unsigned long gen;       /* set by q2n_cp_eval_init: identifies this state in the evaluators' line memo */
} cp_eval;

/* Sets C and computes the corner terms (after P, lanes, bub); call it again after any change of
 * the patch's data (it also renews gen, so no evaluator reuses a line of the old data). */
void q2n_cp_eval_init(cp_eval *E);
q2n_status q2n_cp_eval_point(const void *data, double u, double v, int nder, double *out);
q2n_status q2n_cp_eval_grid(const void *data, int nu, const double *us, int nv, const double *vs, double *out);
/* Positions only (3 per point): lines without along derivatives and the sum's first output. */
q2n_status q2n_cp_eval_grid_pos(const void *data, int nu, const double *us, int nv, const double *vs, double *out);
q2n_status q2n_cp_eval_corner(const void *data, int i, int j, double out[2][2][2][3]);

#endif
