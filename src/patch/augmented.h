/* augmented.h — regular augmented interpolatory patches (seed 003 §3, eq. (7)–(11)).
 *
 * For a face whose w x w vertex grid exists (every grid-interior vertex has valence 4, or is a
 * boundary vertex with at most two faces; open meshes get the extrapolated layer of §3.1),
 * the patch is S(u,v) = Σ_ij p_ij ψ_i(u δ00(v); d(v)) ψ_j(v ε00(u); e(u)), with local
 * parameter vectors d(v), e(u) blended by the local parametrization functions δ, ε of degree
 * 2k+1 (eq. 7–8).  Faces without such a grid are left uncovered here (extraordinary regions,
 * see extraordinary.h). */
#ifndef Q2N_PATCH_AUGMENTED_H
#define Q2N_PATCH_AUGMENTED_H

#include "mesh/mesh.h"
#include "param/param.h"
#include "patch/surface.h"
#include "spline/spline.h"

typedef struct q2n_augmented_options {
    const q2n_spline_class *cls; /* NULL: Q2N_SPLINE_CLASS_DEFAULT (D5C2P4S6) */
    q2n_param_options param;
} q2n_augmented_options;

/* One regular patch (for tests and the extraordinary-patch builder; the surface stores it compactly). */
typedef struct q2n_augmented_patch {
    const q2n_spline_class *cls;
    int w;
    double P[3 * Q2N_SPLINE_MAXW * Q2N_SPLINE_MAXW]; /* grid p_ij, i (along u) fastest; grid index
                                                        g = -w/2+1 .. w/2 at array index g+w/2-1 */
    double drow[2][Q2N_SPLINE_MAXW];                 /* d_{i,0}, d_{i,1}: intervals of rows v=0, v=1 */
    double ecol[2][Q2N_SPLINE_MAXW];                 /* e_{0,j}, e_{1,j}: intervals of columns u=0, u=1 */
} q2n_augmented_patch;

/* Build a surface with one patch per face; regular faces get augmented patches, the others
 * stay Q2N_PATCH_UNCOVERED.  edge_iv: per-edge intervals (q2n_param_edge_intervals) or NULL to
 * compute them from opt->param. */
q2n_status q2n_augmented_build(const q2n_mesh *m, const q2n_augmented_options *opt,
                               const double *edge_iv, q2n_surface **out, q2n_error *err);

/* Try to set up the regular patch of face f; returns 1 on success, 0 if the face is not regular. */
int q2n_augmented_setup(const q2n_mesh *m, int f, const q2n_spline_class *cls,
                        const q2n_param_options *popt, const double *edge_iv,
                        q2n_augmented_patch *out);

/* The regular patch of face f of a surface built by q2n_augmented_build, expanded into *out;
 * returns 0 when face f has no augmented patch. */
int q2n_augmented_patch_get(const q2n_surface *s, int f, q2n_augmented_patch *out);

/* Every augmented patch of s mapped by the linear map L: their grid points (the mesh's vertices and
 * the extrapolated ones) go through L, their intervals stay.  A patch is linear in its points for
 * given intervals (eq. 10), so each becomes L times the patch it was, exactly up to rounding: the
 * regular patches of the mesh, intervals and all, as seen in another frame (the model's
 * extraordinary regions built in the isotropic frame, api/model.c). */
void q2n_augmented_map_points(q2n_surface *s, const double L[3][3]);

/* Coefficients C_ri (jets in x) of the direction functions of class cls at x, from the end
 * intervals d0[i], d1[i] (i < w - 1) blended by eq. (8a): C has cls->nb * w jets. */
void q2n_augmented_coeffs(const q2n_spline_class *cls, int w, const double *d0, const double *d1, double x,
                          q2n_jet *C);

/* Evaluate a patch (same output layout as q2n_surface_eval). */
void q2n_augmented_eval(const q2n_augmented_patch *p, double u, double v, int nder, double *out);

#endif
