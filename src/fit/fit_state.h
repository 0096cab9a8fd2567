/* fit_state.h — the fitting context shared by the files that run the fit (not a public header):
 * fit.c (driver: rounds, model), fit_stages.c (the linear stages and the construction samples),
 * fit_interior.c (the patches' free control points),
 * fit_glue.c (gluing data and exact constraints), fit_refine.c (where knots go).
 *
 * Knots are local.  Edge e owns the interior breakpoints K_e of its curve (in the orientation of
 * its owner half-edge mesh->edge_he[e]); patch k owns interior breakpoints I_u(k), I_v(k); the
 * patch's u knots are K(side 0) ∪ K(side 2) ∪ I_u(k) mapped to u, its v knots likewise.  All
 * breakpoints are dyadic rationals (refinement bisects spans), so 1 - t and unions are exact and
 * both sides of an edge agree bit for bit about every knot they share. */
#ifndef Q2N_FIT_STATE_H
#define Q2N_FIT_STATE_H

#include "fit/fit_internal.h"

#include <pthread.h>
#include <stdatomic.h>

/* A sorted growable set of breakpoints in (0,1). */
typedef struct fit_breaks {
    int n, cap;
    double *t;
} fit_breaks;

/* Cached construction values along one patch side: per parameter t (sorted), 19 doubles: t, then
 * the side-frame derivatives D[6][3] (S, d_t, d_s, d_tt, d_ts, d_ss) at (t, 0). */
#define FIT_SC_STRIDE 19
typedef struct fit_side_cache {
    int n, cap;
    double *v;       /* FIT_SC_STRIDE per parameter */
} fit_side_cache;

/* Cached construction positions of one patch on the parameter grid u[i] x v[j] (sorted, distinct);
 * have[j*nu+i] says whether S(u_i, v_j) (3 doubles at val) was evaluated. */
typedef struct fit_grid_cache {
    int nu, nv;
    double *u, *v, *val;
    unsigned char *have;
} fit_grid_cache;

typedef enum { FIT_GLUE_BOUNDARY = 0, FIT_GLUE_LS, FIT_GLUE_EXACT } fit_glue_kind;

typedef struct fit_edge {
    fit_breaks K;            /* interior breakpoints of the edge curve (owner orientation) */
    int ver, fitted;         /* K's version; version the curve was last fitted for (-1: never) */
    int n;                   /* control points of the curve: K.n + 6 */
    double *cp;              /* 3 * n, owner orientation */
    double end[2][2][3];     /* d_t S, d_tt S of the construction (owner frame) at t = 0 and t = 1 */
    int glue, glue2;         /* fit_glue_kind of the G1 and the G2 relation */
    double alpha0, alpha1;   /* the construction's alpha at t = 0 and t = 1 (fit_target.c) */
    int rep;                 /* the construction's gluing is a scale alpha(t): reparametrized to constant */
    int alpha_varies;        /* alpha(t) is not constant on the construction */
    int absorb;              /* rep: which side's cross speed absorbs alpha's variation (0 R, 1 L) */
    double x[2];             /* log of the end speeds of the edge's reparametrization at its owner's start
                                and end vertex (fit_target.c) */
    double A;                /* rep: the constant gluing scale after reparametrization */
    double alpha;            /* FIT_GLUE_EXACT: d_s S_R(1-t) = alpha d_s S_L(t), d_ss S_R = alpha^2 d_ss S_L
                                (formulas.md §4.2 with beta = gamma = delta = 0) */
    double g1c, g2c;         /* the construction's own normal / curvature jumps on this edge */
    int nchk;                /* check points of the last measurement (owner side's check parameters) */
    double *spmax;           /* FIT_SPMAX per span of K at the last measurement: the largest curve deviation
                                and cross-row deviation (position terms) / diag over its check points, and
                                the largest normal and curvature jumps over its check points and the
                                dense jump samples in it */
    int nspmax;              /* spans spmax holds (K.n + 1 at that measurement) */
    double g0, g1, g2;       /* last measured fitted gap / diag and jumps (maxima over the check points) */
    double g1d, g2d;         /* the jumps' maxima over the check points and the dense jump samples
                                between them (what refinement and acceptance judge) */
    double g1_prev, g2_prev; /* the round before, for the stall rule */
    int g1_fails, g2_fails;  /* consecutive rounds this edge drove refinement for continuity */
    int kn_prev;             /* K.n at the previous refinement decision */
    int cont_local;          /* the last continuity refinement split only the spans over the aim */
    double cont_prev;        /* the miss (jump / aim) that refinement answered */
    int cont_graded;         /* local continuity splits left its knots graded (not evened out since) */
    int stalled;             /* bit 0: G1, bit 1: G2 — no longer drives refinement */
    /* rep edges: alpha and alpha' at the owner parameters asked for so far (fit_target.c), sorted by
     * parameter; both faces of the edge read and add them, under amu */
    pthread_mutex_t amu;
    int an, acap;
    double *av;              /* an rows of FIT_AC_STRIDE: x, alpha, alpha' */
} fit_edge;
#define FIT_AC_STRIDE 3
enum { FIT_SPMAX_DEV, FIT_SPMAX_ROW, FIT_SPMAX_G1, FIT_SPMAX_G2, FIT_SPMAX };

typedef struct fit_patch {
    fit_breaks I[2];         /* patch-interior breakpoints in u and v */
    int ver;                 /* bumped when the knot vectors change */
    int mu, mv, nu, nv;      /* spans and control points per direction */
    double *ku, *kv;         /* knot vectors (nu + 6, nv + 6) */
    double *kur, *kvr;       /* the same reversed (1 - t), for sides running against u or v (ku, kv
                                themselves when symmetric: q2n_fit_patch_free_reversed frees them) */
    double *cp;              /* 3 * nu * nv, u fastest */
    unsigned char *fixed;    /* nu * nv, in var's allocation (after its ints) */
    int *var;                /* nu * nv: unknown index in the current block, or -1 */
    int gregory;             /* bit i: the edges through corner i disagree about a mixed derivative (once per fit) */
    fit_grid_cache gc;       /* construction samples */
    double dev;              /* last measured max deviation / diag */
    double s2;               /* sum of squared deviations / diag^2 over the check cells */
    double *cell;            /* per check cell deviation / diag (ncu x ncv) */
    int ncu, ncv;
    double share[2];         /* share of the u and v directions in the error estimate */
    int spiky;               /* 0 not scanned, 1 scanned smooth, 2 spiky construction (no longer refined) */
    int phi;                 /* the fit target is the construction reparametrized (fit_target.c) */
    int dirty;               /* refit this round */
    int knots_changed;       /* knot vectors changed this round */
    int pending[2];          /* knots added to its u / v vectors by the current refinement */
} fit_patch;

/* Frame of side i of a patch: t along the side (corner i -> i+1), s into the patch. */
typedef struct fit_side {
    int k, i;                /* patch and side */
    int ox, oy;              /* corner in grid index space */
    int tx, ty, sx, sy;      /* unit steps of t and s in (u,v) (and grid index) space */
    int nt, ns, mt, ms;      /* control points / spans along and across */
    const double *kt, *ks;   /* knots along and across, in the side's own orientation */
} fit_side;

/* A basis matrix of the interior stage and its pseudo-inverse (fit_interior.c). */
typedef struct fit_pinv {
    unsigned long long h;    /* hash of (m, n, A) */
    int m, n;
    double *A;               /* m x n, row-major: the key */
    double *P;               /* n x m, row-major: (A^T A)^-1 A^T */
    int next;                /* next entry of its hash chain, -1: none */
    int keep;                /* kept for the later rounds (within the cache's budget) */
} fit_pinv;

typedef struct fit_pinv_cache {
    int n, cap, nbucket;
    fit_pinv *v;
    int *bucket;             /* nbucket chain heads (a power of two) */
    long bytes;              /* bytes of the kept entries */
    long budget;             /* bytes they may take: Q2N_FIT_PINV_CACHE_BYTES (q2n_fit_surface; tests set their own) */
} fit_pinv_cache;

typedef struct fit_ctx {
    const q2n_surface *s;
    const q2n_mesh *m;
    q2n_fit_options o;
    double diag;
    fit_patch *p;            /* nf */
    fit_edge *e;             /* ne */
    fit_side_cache *sc;      /* 4 * nf: side i of patch k at 4k + i */
    atomic_long cache_bytes; /* bytes held by the side and grid caches (Q2N_FIT_CACHE_BYTES bounds them) */
    atomic_long alpha_bytes; /* bytes held by the edges' alpha caches (Q2N_FIT_ALPHA_CACHE_BYTES) */
    int amu_n;               /* edges whose amu is initialised */
    double (*jet)[4][4][3];  /* corner jets of the construction (patch, corner, jet_order), once per fit */
    double *vpos;            /* nv: patch corner point of every vertex */
    int round;
    q2n_fit_ls ls;
    fit_pinv_cache pinv;     /* the interior stage's pseudo-inverses, for the whole fit */
    q2n_fit_report *rep;
    q2n_error *err;
} fit_ctx;

/* ---- breakpoints (fit_stages.c) ---- */
int q2n_fit_breaks_add(fit_breaks *b, double t);            /* 1 added, 0 present, -1 out of memory */
void q2n_fit_breaks_free(fit_breaks *b);

void q2n_fit_patch_free_reversed(fit_patch *p);              /* kur, kvr (not ku, kv) */
/* Interior breakpoints of patch k in direction d (0 u, 1 v): its two d-edges' knots and its own,
 * sorted and distinct, into br (room for both edges' and its own); returns their number. */
int q2n_fit_patch_breaks(const fit_ctx *c, int k, int d, double *br);
/* Does edge e glue by least squares in an order the fit imposes (G1, or G2 in G2 mode)? */
static inline int q2n_fit_edge_ls(const fit_ctx *c, const fit_edge *E)
{
    return E->glue == FIT_GLUE_LS || (c->o.continuity == 2 && E->glue2 == FIT_GLUE_LS);
}

/* Row of key t in rows sorted by their first entry (n rows of stride doubles; binary search): its
 * index, or -1 when absent with *pos the insertion point.  The side caches and the edges' alpha
 * caches are kept this way. */
static inline int q2n_fit_sorted_find(const double *v, int n, size_t stride, double t, int *pos)
{
    int lo = 0, hi = n;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (v[stride * (size_t)mid] < t) lo = mid + 1;
        else hi = mid;
    }
    *pos = lo;
    return lo < n && v[stride * (size_t)lo] == t ? lo : -1;
}

/* ---- frames and construction access (fit_stages.c) ---- */
fit_side q2n_fit_make_side(const fit_ctx *c, int k, int i);
/* Grid index of control point (t index, s index) of side sd (inline: the row assembly asks for it
 * in its innermost loops). */
static inline int q2n_fit_side_g(const fit_ctx *c, const fit_side *sd, int it, int js)
{
    int a = sd->ox + it * sd->tx + js * sd->sx, b = sd->oy + it * sd->ty + js * sd->sy;
    return b * c->p[sd->k].nu + a;
}
/* The sides of edge e: L = owner half-edge's face (its t is the edge's t), R = the twin's
 * (t_R = 1 - t); returns 0 (R unset) on boundary edges. */
int q2n_fit_edge_sides(const fit_ctx *c, int e, fit_side *L, fit_side *R);
/* The fitted spline of side sd (its current control points) at (t, 0) in the side's frame, the
 * layout of q2n_side_derivs (S, d_t, d_s, d_tt, d_ts, d_ss): the along basis at t and the across
 * basis Ns at s = 0 (the same for every t of a side: the caller computes it once), so only the
 * first nder + 1 rows of control points are read — a third of a general evaluation's work. */
void q2n_fit_side_spline(const fit_ctx *c, const fit_side *sd, const double Ns[3][Q2N_FIT_DEG + 1], double t,
                         double F[6][3]);
/* Side sd's first three control rows on the span of its knots that starts at or contains t0, as
 * polynomials in d = t - t0 with their derivatives: C[j][a][k] is the coefficient of d^k in the
 * a-th derivative of row j's curve (a + j <= 2); q2n_fit_side_poly_frame sums them at t0 + d into
 * q2n_fit_side_spline's frame (the same values to rounding, a tenth of the work per point where many
 * points share a span: fit.c's dense jump samples). */
typedef double q2n_fit_side_poly[3][3][Q2N_FIT_DEG + 1][3];
void q2n_fit_side_poly_at(const fit_ctx *c, const fit_side *sd, double t0, q2n_fit_side_poly C);
void q2n_fit_side_poly_frame(q2n_fit_side_poly C, const double Ns[3][Q2N_FIT_DEG + 1], double d, double F[6][3]);
/* "face F" or "between face F and face G" for messages about edge e; returns buf. */
const char *q2n_fit_edge_where(const fit_ctx *c, int e, char *buf, size_t n);
/* Exact construction derivatives of patch k in the frame of its side i at (t, s) (see
 * fit_side_cache; nder 0..2). */
q2n_status q2n_fit_frame_eval(const q2n_surface *s, int k, int i, double t, double s_, int nder, double D[6][3]);
/* Side-frame derivatives (nder 2) at parameters t[0..n-1] of side (k, i) from the side cache,
 * evaluating and caching what is missing; D gets 18 doubles per parameter. */
q2n_status q2n_fit_side_values(fit_ctx *c, int k, int i, int n, const double *t, double *D);

/* ---- stages (fit_stages.c) ---- */
q2n_status q2n_fit_prepare(fit_ctx *c);        /* once per fit: corner points, edge ends, corner jets */
q2n_status q2n_fit_round(fit_ctx *c);          /* knots, curves, corners, rows, interiors of the dirty set */
/* Positions of the construction's patch k on the grid us x vs (sorted, distinct), through the
 * patch's sample cache (evaluations counted in *evals). */
q2n_status q2n_fit_patch_grid(fit_ctx *c, int k, int nu, const double *us, int nv, const double *vs, double *out,
                          long *evals);

/* ---- interiors (fit_interior.c) ---- */
/* The free control points of the listed patches by least squares on their sample grids. */
q2n_status q2n_fit_stage_interior(fit_ctx *c, const int *list, int nlist);
void q2n_fit_pinv_free(fit_pinv_cache *pc);

/* ---- the fit target T_k = S_k o phi_k (fit_target.c) ---- */
q2n_status q2n_fit_target_setup(fit_ctx *c);   /* edge speeds and which patches are reparametrized */
/* Side-frame derivatives of T (nder 2) at (t, 0) of side i of patch k. */
q2n_status q2n_fit_target_frame(fit_ctx *c, int k, int i, double t, double D[6][3]);
/* Positions of T on the grid us x vs into out (3 doubles per point, u fastest). */
q2n_status q2n_fit_target_grid(fit_ctx *c, int k, int nu, const double *us, int nv, const double *vs, double *out);
/* Factor turning the construction's mixed derivative d_t^a d_s^b at corner i of patch k into T's. */
double q2n_fit_target_jet_scale(const fit_ctx *c, int k, int i, int a, int b);

/* ---- gluing (fit_glue.c) ---- */
q2n_status q2n_fit_glue_measure(fit_ctx *c);   /* once per fit, on the construction: which edges are scaled (rep) */
q2n_status q2n_fit_glue_classify(fit_ctx *c);  /* once per fit, on the target: gluing kind of every edge */
/* The order-th cross rows of interior edge e with its gluing relation (order 1: exact or least
 * squares; order 2: least squares), solved and stored into both patches. */
q2n_status q2n_fit_rows_stage(fit_ctx *c, const int *edges, int n, int order);

/* ---- refinement (fit_refine.c) ---- */
/* From the last measurement: add breakpoints where the errors are; returns the number of knots
 * added (0: converged or nothing refinable). */
int q2n_fit_refine(fit_ctx *c);
/* Acceptance after the last round: fills rep's met flags and note. */
void q2n_fit_accept(fit_ctx *c);

#endif
