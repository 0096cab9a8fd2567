/* ev_internal.h — data shared by the extraordinary-patch sources (ev_derivatives.c,
 * curve_network.c, ev_paper.c, ev_harmonize.c, ev_fair*.c); not part of the public API.
 *
 * Conventions.  Every vertex that is a corner of an extraordinary patch gets a 2-jet in local
 * variables: J1 = (∂x P, ∂y P), J2 = (∂xx P, ∂xy P, ∂yy P) of a local surface P(x,y) through
 * the vertex, and every edge end at that vertex a 2D direction u (the edge leaves the vertex
 * along u, its local variable being the arc of P along u).  The derivative of the edge's curve at
 * that end is J1·u, its second derivative J2[u,u]; the cross-boundary field of a face whose
 * other edge there has direction w is J1·w with edge-derivative J2[u,w].  One jet per vertex is
 * what makes all the data at the vertex G1/G2-compatible. */
#ifndef Q2N_PATCH_EV_INTERNAL_H
#define Q2N_PATCH_EV_INTERNAL_H

#include "patch/augmented.h"
#include "patch/coons_patch.h"
#include "patch/extraordinary.h"

#define EV_MAXDEG 10   /* polynomial degree bound of the constructed edge data */
#define EV_MAXVAL Q2N_EV_MAX_VALENCE /* largest vertex valence handled */

/* Vector polynomial in the edge parameter t in [0,1] (power basis). */
typedef struct ev_poly {
    int deg;
    double c[EV_MAXDEG + 1][3];
} ev_poly;

typedef struct ev_vjet {
    int source;        /* 0 none, 1 corner of a regular patch, 2 fit (Appendix B), 3 section curves */
    double J1[3][2];   /* [xyz][x|y] */
    double J2[3][3];   /* [xyz][xx|xy|yy] */
    double Jm[3][3];   /* source 1 only: [xyz][xxy|xyy|xxyy], the mixed third and fourth
                          derivatives of the regular patch (the fair construction fixes them) */
} ev_vjet;

/* Data of one mesh edge of the curve network (constructed edges only), all in the edge
 * parameter t in [0,1] from origin(edge_he) to dest, local variable x = t d. */
typedef struct ev_edge {
    int built;
    double d;            /* the edge's interval */
    ev_poly gamma;       /* boundary curve */
    ev_poly nrm;         /* normal field n(t) (cubic, not unit) spanning the ribbon with γ_x */
    int face[2];         /* face of the base side and of the derived side (-1 none) */
    int base_twin;       /* the base side is the face of edge_he's twin (else of edge_he) */
    double a[2][2], b[2][2]; /* [side][end]: χ_side = a D + b T (unit ribbon frame T = γ_x/|γ_x|,
                                D = n × T/|n × T|), a, b cubic Hermite in t with ... */
    double as[2][2], bs[2][2]; /* ... the t-slopes as, bs at the ends */
    ev_poly xi;          /* base side ξ (linear) */
    double tau[2][2];    /* derived side: tangential part of ξ = τ1 D + τ2 γ_x at each end [end][1|2] */
    /* Corner-compatibility terms (ev_harmonize.c, q2n_ev_harmonize_vertex), all zero when built.
     * Each is a polynomial bump local to one end: B_end (t²(1-t)⁴/2 at end 0, its mirror at
     * end 1: second derivative 1 there) or C_end (t(1-t)⁴, mirror: first derivative 1), both
     * vanishing with three derivatives at the other end (γ's: four).  They change the second t-derivatives
     * of n, a, b, the first two of ξ and τ and the third and fourth of γ at that end only, never
     * a value, a slope, or (for γ) a second derivative: */
    double nD[2][3], nN[2][3]; /* D and N = D x T at the ends (set by q2n_ev_build_edge) */
    int loc[2];          /* locality of the bumps at each end: (1-t)^(4+loc) (γ: 5+loc), 0 as built */
    double g3[2], g4[2]; /* γ += (g3[end] E3_end + g4[end] E4_end) N_end, E_p = t^p (1-t)^5 / p!
                            (mirrored at end 1): the normal third and fourth derivatives */
    double nb[2];        /* n += nb[end] D_end B_end */
    double a2[2][2], b2[2][2]; /* [side][end]: a += a1 C_end + a2 B_end, b += b1 C_end + b2 B_end */
    double a1[2][2], b1[2][2]; /* (slopes: only where the sign guard below changed a twist) */
    double x1[2][3], x2[2][3]; /* base side: ξ += x1[end] C_end + x2[end] B_end */
    double t1[2][2], t2[2][2]; /* derived side: τ_k += t1[end][k] C_end + t2[end][k] B_end */
} ev_edge;

/* ---- ev_derivatives.c ---- */
/* Jets and edge-end directions of all vertices touching an uncovered face.  dir[2*e + end]
 * (end 0: origin of edge_he[e]).  jets[v].source == 0 for vertices not needed.  sections: valence-4
 * interior vertices without a regular patch take the class's section curves and quarter-turn
 * directions (seed 003 §4.3; the paper's construction), else the fan's own chart like every other
 * vertex without a regular patch (the fair construction), measured on chart_mesh where not NULL (m
 * under a linear map: the same fans, other angles and lengths). */
q2n_status q2n_ev_vertex_jets(const q2n_mesh *m, const q2n_mesh *chart_mesh, const q2n_surface *s, const double *iv,
                              const q2n_spline_class *cls, int sections, const char *cross, ev_vjet *jets,
                              double (*dir)[2], q2n_error *err);
void q2n_ev_jet_d1(const ev_vjet *J, const double u[2], double out[3]);
void q2n_ev_jet_d2(const ev_vjet *J, const double a[2], const double b[2], double out[3]);
/* Unit normal of the jet, and its derivative along the 2D direction a (Weingarten map of the
 * surface the jet describes: dn(a) = -J1 I^-1 II a); 0 when J1 is degenerate. */
int q2n_ev_jet_normal(const ev_vjet *J, double n[3]);
/* The faces around vertex v when every corner of every one of them lies within EV_FLAT_REL of the
 * fan's radius of the plane through v with unit normal n (a flat fan: --keep-flat), else 0. */
int q2n_ev_fan_in_plane(const q2n_mesh *m, int v, const double n[3]);
void q2n_ev_jet_dn(const ev_vjet *J, const double a[2], double out[3]);

/* ---- curve_network.c ---- */
q2n_status q2n_ev_build_edge(const q2n_mesh *m, const double *iv, const ev_vjet *jets,
                         const double (*dir)[2], int order, int e, ev_edge *out, q2n_error *err);
void q2n_ev_poly_eval(const ev_poly *p, double t, int nder, double out[][3]);

/* Side of a Coons–Gregory patch: local data (curve γ, inward χ, ξ) as functions of the
 * patch's side parameter s, with s-derivatives up to 2: out[field][deriv][xyz]. */
typedef struct ev_side {
    int kind;            /* 0 constructed edge, 1 sampled from a regular patch */
    int rev;             /* the data's own parameter is 1 - s */
    ev_edge E;           /* kind 0: the edge data */
    int derived;         /* kind 0: this face is the derived side of E */
    q2n_augmented_patch R; /* kind 1: the regular neighbour */
    int sR;              /* kind 1: its side index (0..3, the face half-edge) */
} ev_side;
void q2n_ev_side_eval(const ev_side *sd, double s, double out[3][3][3]);

/* ---- ev_paper.c: the paper's Coons–Gregory patch of one face ---- */
typedef struct pp_ctx {
    int kb;
    double d0, d1, e0, e1; /* intervals of sides 0, 2 (u) and 3, 1 (v) */
    ev_side side[4];
} pp_ctx;

typedef struct ev_patch {
    cp_eval E; /* first: the surface's data pointer is this struct (q2n_cp_eval_point) */
    pp_ctx X;
} ev_patch;

/* Fill the patch of uncovered face f from the curve network and its regular neighbours. */
q2n_status q2n_ev_paper_patch_setup(ev_patch *P, const q2n_mesh *m, const q2n_surface *s, const double *iv,
                                const char *unc, ev_edge *const *edges, int K, int kb, int f, q2n_error *err);
/* The paper's construction for every uncovered face of s. */
q2n_status q2n_ev_paper_build(const q2n_mesh *m, q2n_surface *s, const double *iv, const q2n_spline_class *cls, int K,
                          q2n_error *err);

/* ---- ev_harmonize.c: corner compatibility of vertex v (G2 mode; vc_*: corners by vertex) ---- */
q2n_status q2n_ev_harmonize_vertex(const q2n_mesh *m, const q2n_surface *s, const double *iv, const char *unc,
                               ev_edge **edges, int K, int kb, const int *vc_start, const int *vc_list, int v,
                               q2n_error *err);

#endif
