/* acc_masks.h — internals of the Catmull–Clark path shared by the src/acc/ sources and their tests: vertex
 * one-rings, the ACC3 (Loop–Schaefer) corner masks, degree elevation to ACC5 and the G1 masks of
 * seed 001 §4–5.  Every routine is linear in the mesh data and works on "values" of any
 * dimension `dim` (xyz: dim = 3; the identity matrix: dim = nv, which yields the masks
 * themselves — that is how the tests compare with the paper's fractions).
 *
 * Ring convention (formulas.md, notation): for a vertex v, ring position i is the face
 * (v, e_i, f_i, e_{i+1}) with its corners in face order; positions run counter-clockwise
 * (q2n_mesh_rotate).  Interior: i = 0..n-1 mod n.  Boundary: i = 0..k-1, e_0 and e_k are the
 * boundary neighbours.  EV-local patch coordinates: u' along v -> e_i, v' along v -> e_{i+1};
 * a local point (i,j) of a degree-d patch is stored at q2n_acc_local_index(). */
#ifndef Q2N_ACC_ACC_MASKS_H
#define Q2N_ACC_ACC_MASKS_H

#include "acc/acc.h"
#include "core/poly.h"

typedef struct q2n_acc_rings {
    int nv;
    int *start;          /* nv+1: offsets into he[] */
    int *he;             /* outgoing half-edge of the face at each ring position */
    int *last;           /* nv: e_k of a boundary vertex (the second boundary neighbour), else -1 */
    int *pos;            /* nh: ring position of half-edge h around origin(h) */
    unsigned char *bnd;  /* nv: 1 on the boundary */
    unsigned char *ev;   /* nv: 1 if extraordinary (interior valence != 4, boundary with >= 3 faces) */
} q2n_acc_rings;

/* Build the rings of an all-quad mesh (Q2N_ERR_UNSUPPORTED for a non-quad face or an interior
 * vertex of valence < 3). */
q2n_status q2n_acc_rings_build(const q2n_mesh *m, q2n_acc_rings *r, q2n_error *err);
void q2n_acc_rings_free(q2n_acc_rings *r);
static inline int q2n_acc_ring_size(const q2n_acc_rings *r, int v) { return r->start[v + 1] - r->start[v]; }

/* 1 when every face has at most one EV (the "isolated EV" assumption of seed 001 §2, §5). */
int q2n_acc_evs_isolated(const q2n_mesh *m, const q2n_acc_rings *r, int *bad_face);

/* Face-grid index (J*(d+1)+I) of the EV-local point (i,j) of the corner c of a quad face. */
static inline int q2n_acc_local_index(int c, int d, int i, int j)
{
    int I, J;
    switch (c & 3) {
    case 0: I = i; J = j; break;
    case 1: I = d - j; J = i; break;
    case 2: I = d - i; J = d - j; break;
    default: I = j; J = d - i; break;
    }
    return J * (d + 1) + I;
}

/* ACC3 corner points b00, b10 (towards e_i), b01 (towards e_{i+1}), b11 of the face of half-edge
 * h at its origin, in EV-local order: out[0..4*dim-1].  formulas.md §1.1 and §1.4. */
void q2n_acc_corner_points(const q2n_mesh *m, const q2n_acc_rings *r, int h, const double *val,
                           int dim, double *out);

/* Catmull–Clark limit position and unit limit normal at vertex v (position and zero normal for
 * an isolated vertex). */
void q2n_acc_limit_frame(const q2n_mesh *m, const q2n_acc_rings *r, int v, double p[3], double nrm[3]);

/* Bicubic ACC3 patch of quad face f (16 points, face layout cp[(J*4+I)*dim]). */
void q2n_acc_bicubic(const q2n_mesh *m, const q2n_acc_rings *r, int f, const double *val, int dim,
                     double *cp);
/* (Degree elevation 3 -> 5 of a patch, ACC5 of seed 001 §3: q2n_bezier_elevate, core/poly.h.) */

/* G1 masks around one EV, in place on its sector patches (biquintic, EV-local layout
 * P[k][(j*6+i)*dim], k = ring position; on entry ACC5, on exit G1).  Interior EV of valence
 * N = nsec: seed 001 §5.1–5.3.  Boundary EV with nsec faces: §5.4 (eq. 33–34). */
q2n_status q2n_acc_g1_interior(int nsec, int dim, q2n_acc_strategy st, double **P, q2n_error *err);
q2n_status q2n_acc_g1_boundary(int nsec, int dim, q2n_acc_strategy st, double **P, q2n_error *err);

/* All patches of an all-quad mesh from vertex values val[v*dim ..]: deg[f] = 3 or 5 and
 * cp[f*36*dim ..] (face layout with (deg+1)^2 points).  For Q2N_ACC_G1 the EVs must be isolated
 * (Q2N_ERR_UNSUPPORTED otherwise). */
q2n_status q2n_acc_control_points(const q2n_mesh *m, const q2n_acc_rings *r, q2n_acc_method method,
                                  q2n_acc_strategy st, const double *val, int dim, int *deg,
                                  double *cp, q2n_error *err);

#endif
