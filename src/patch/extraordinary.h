/* extraordinary.h — augmented Coons–Gregory patches for the faces that the regular augmented
 * construction leaves uncovered (seed 003 §4, Appendix B).
 *
 * q2n_extraordinary_build() completes a surface produced by q2n_augmented_build(): every
 * Q2N_PATCH_UNCOVERED face of an all-quad mesh gets a Q2N_PATCH_COONS_GREGORY patch
 *   - bicubically blended with first-order Gregory correction (G1, eq. 23, §4.1), or
 *   - biquintically blended with second-order Gregory correction (G2, §4.2).
 * Boundary curves and cross-boundary fields (χ, ξ) are sampled from the neighbouring regular
 * patch (divided by its local parametrization function, §4.1) where there is one; elsewhere
 * they are built from a curve network of Hermite segments whose end derivatives come from a
 * per-vertex 2-jet (a regular neighbour's corner derivatives, or the least-squares polynomial of
 * Appendix B), and the two patches on an edge between extraordinary patches receive fields
 * related by the G1/G2 conditions of formulas.md §4.2.  Regular patches are not touched.
 * docs/extraordinary.md describes the construction and the measured figures. */
#ifndef Q2N_PATCH_EXTRAORDINARY_H
#define Q2N_PATCH_EXTRAORDINARY_H

#include "mesh/mesh.h"
#include "param/param.h"
#include "patch/surface.h"
#include "spline/spline.h"

/* The largest vertex valence the construction handles (callers refuse higher ones up front). */
#define Q2N_EV_MAX_VALENCE 64

/* q2n_ev_patch_kind (Q2N_EV_PATCH_*: default, G1 bicubically blended with Gregory r = 1, G2
 * biquintically blended with r = 2) and q2n_ev_method (Q2N_EV_METHOD_*: default = fair, fair =
 * one jet per vertex, compatible Coons patches, bending-energy solve (ev_fair.c), paper = the
 * paper's Coons–Gregory patches with Appendix-B-style 2-jets, ribbon cross fields and corner
 * harmonisation) are the public enums of include/quad2nurbs.h. */

typedef struct q2n_extraordinary_options {
    const q2n_spline_class *cls; /* the class of the regular patches; NULL: Q2N_SPLINE_CLASS_DEFAULT */
    q2n_param_options param;     /* used when edge_iv is NULL (must match the regular build) */
    q2n_ev_patch_kind ev_patch;
    q2n_ev_method method;
    int threads;                 /* worker threads for the construction's solves (0: 1) */
    int keep_flat;               /* fair construction: flat fans stay flat (ev_fair.h); 0: no */
    int smooth_gluing;           /* fair construction, G1 patches: keep the smoothstep gluing everywhere
                                    (0: polynomial gluing where it holds, ev_fair_gluing.c) */
    const q2n_mesh *chart_mesh;  /* fair construction: the same mesh under a linear map (its isotropic
                                    frame, mesh.h); the vertex charts are measured on it instead (NULL:
                                    on the mesh itself; docs/extraordinary.md, "The isotropic frame") */
    const char *smooth_vertices; /* fair construction: per mesh vertex, 1 where the polynomial gluing
                                    keeps out (the edges there keep the smoothsteps; NULL: none): the
                                    regions the model's gluing choice gave the smoothsteps (api/model.c) */
} q2n_extraordinary_options;

/* Parse "fair" / "paper"; returns 0 on success. */
int q2n_ev_method_parse(const char *s, q2n_ev_method *out);

/* Fill every uncovered face of s (built on m by q2n_augmented_build with the same class and
 * intervals) with a Coons–Gregory patch.  edge_iv: per-edge intervals or NULL to compute them
 * from opt->param.  Q2N_ERR_UNSUPPORTED for meshes with non-quad faces. */
q2n_status q2n_extraordinary_build(const q2n_mesh *m, const q2n_extraordinary_options *opt,
                                   const double *edge_iv, q2n_surface *s, q2n_error *err);

/* Faces of m where the mesh is flat — the one-ring of every corner in the face's plane, to the
 * tolerance --keep-flat uses (ev_policy.h EV_FLAT_REL) — and how far surface s leaves that plane
 * there: *nflat such faces, *dev the largest distance relative to the bounding-box diagonal on an
 * n x n grid of each, *face the face where it is largest (-1: none).  A check of what a build did
 * with flat data (the default lets the energy bulge them; --keep-flat keeps them flat). */
q2n_status q2n_flat_faces_dev(const q2n_mesh *m, const q2n_surface *s, int n, int *nflat, double *dev, int *face);

/* What the build did, for the report. */
typedef struct q2n_extraordinary_stats {
    int flat_vertices;     /* keep_flat: vertices whose fan is flat, their jets kept in its plane */
    int polynomial_edges;  /* G1 patches: constructed edges glued by polynomials (exact in the fit) */
    int guard_faces;       /* G1 patches: faces whose Jacobian the gluing collapsed (corners kept out of it) */
    int border_edges;      /* G1 patches: of the polynomial edges, those glued flat at a regular patch's corner */
    int noflat_vertices;   /* G1 patches: vertices near faces the flat edges sheared, whose edges keep free slopes */
    int gregory_corners;   /* fair construction: corners whose two sides disagreed (a Gregory blend) */
} q2n_extraordinary_stats;

/* q2n_extraordinary_build, and its account into *stats (zeroed first). */
q2n_status q2n_extraordinary_build_stats(const q2n_mesh *m, const q2n_extraordinary_options *opt, const double *edge_iv,
                                         q2n_surface *s, q2n_extraordinary_stats *stats, q2n_error *err);

/* Parse "g1" / "g2" (case-insensitive); returns 0 on success. */
int q2n_ev_patch_parse(const char *s, q2n_ev_patch_kind *out);

/* The continuity order the options resolve to for class cls (1 or 2). */
int q2n_ev_patch_order(const q2n_extraordinary_options *opt);

/* ---- building blocks (exposed for tests) ---- */

/* All partial derivatives ∂u^a ∂v^b (a, b = 0..2) of a regular augmented patch at (u,v):
 * D[(a*3 + b)*3 + c].  Needed for the cross-boundary fields sampled from regular neighbours,
 * whose derivatives along the edge involve third and fourth order mixed partials. */
struct q2n_augmented_patch;
void q2n_ev_regular_partials(const struct q2n_augmented_patch *p, double u, double v, double D[27]);

/* Counter-clockwise fan of vertex v: edges[0..n-1] (n = valence), other[k] the vertex at the far
 * end of edges[k]; face k lies between edges k and k+1 (cyclic for interior vertices, k < n-1
 * on the boundary).  Returns n, or -1 when more than maxn edges. */
int q2n_ev_vertex_fan(const q2n_mesh *m, int v, int maxn, int *edges, int *other, int *faces);

#endif
