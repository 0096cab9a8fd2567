/* acc.h — the Catmull–Clark path (pipeline stage 3, alternative to src/patch/): Bézier patches
 * that approximate the Catmull–Clark limit surface, computed from the mesh by explicit masks.
 *
 *   acc3    Loop–Schaefer 2008 "ACC" bicubic geometry patches: C2 (the bicubic B-spline) away from
 *           extraordinary vertices (EVs), C0 across the edges that end at an EV.
 *   acc-g1  Marsala–Mantzaflaris–Mourrain 2022 (seed 001): bicubic patches away from EVs,
 *           biquintic patches on the faces around each EV, G1 across every edge; four strategies
 *           for the order-2 (CS / NCS) and order-3/4 (S / AS) masks, default CS-S (the paper's best).
 *
 * Patch k of the output surface is a Q2N_PATCH_BEZIER patch on face k of the mesh the patches
 * were BUILT ON: that is the input mesh unless info.subdiv_steps > 0 (a non-quad input, or an EV
 * whose one-ring is not all regular for acc-g1, needs Catmull–Clark steps first); then
 * info.mesh is the subdivided mesh and patch k lives on ITS face k (q2n_acc_info_mesh()).
 * The subdivided mesh has the same limit surface as the input.
 *
 * Quality measures of seed 001 §6: [n̂] (normal jump integrated over the edges), <c_G>, <c_M>
 * (largest Gauss / mean curvature jump across an edge), and the distance to the Catmull–Clark
 * limit surface through a caller-supplied limit evaluator (OpenSubdiv in the tests). */
#ifndef Q2N_ACC_ACC_H
#define Q2N_ACC_ACC_H

#include "core/error.h"
#include "mesh/mesh.h"
#include "patch/surface.h"

typedef enum q2n_acc_method { Q2N_ACC_3 = 0, Q2N_ACC_G1 = 1 } q2n_acc_method;

/* q2n_acc_strategy (Q2N_ACC_CS_S, ...) is the public enum of include/quad2nurbs.h.  Seed 001
 * §6.1: CS = circulant system for M_{1,1} (§5.2.1), NCS = direct M_{2,0} (§5.2.2); S = symmetric
 * (θ = 1), AS = asymmetric (θ = 0) order-3/4 masks (§5.3, eq. 31). */

/* Zeroed = defaults: acc3, cs-s, at most 2 automatic subdivision steps. */
typedef struct q2n_acc_options {
    q2n_acc_method method;
    q2n_acc_strategy strategy; /* acc-g1 only */
    int max_subdiv;            /* most automatic Catmull–Clark steps (0 = default 2; -1 = none allowed) */
} q2n_acc_options;

typedef struct q2n_acc_info {
    int subdiv_steps;   /* Catmull–Clark steps applied before building (0: patches are on the input) */
    char reason[320];   /* why they were needed, one clause per step ("" when none) */
    q2n_mesh *mesh;     /* the subdivided mesh the patches are built on; NULL when subdiv_steps == 0.
                           Owned by info: release with q2n_acc_info_free(). */
    int n_patches;
    int n_bicubic, n_biquintic;
    int n_ev_interior;  /* interior vertices of valence != 4 */
    int n_ev_boundary;  /* boundary vertices with >= 3 faces */
    int max_valence;    /* largest valence of an EV (0 when there is none) */
} q2n_acc_info;

/* Build the patches.  info may be NULL (then a subdivided mesh is freed here).  Errors:
 * Q2N_ERR_UNSUPPORTED (interior valence < 3, or EVs still not isolated after max_subdiv steps),
 * Q2N_ERR_ARG, Q2N_ERR_NOMEM, or what q2n_mesh_subdivide reports. */
q2n_status q2n_acc_build(const q2n_mesh *m, const q2n_acc_options *opt, q2n_surface **out,
                         q2n_acc_info *info, q2n_error *err);

void q2n_acc_info_free(q2n_acc_info *info); /* frees info->mesh; NULL is a no-op */

/* The mesh whose face k carries patch k: info->mesh if one was made, else input. */
const q2n_mesh *q2n_acc_info_mesh(const q2n_acc_info *info, const q2n_mesh *input);

/* Option parsing for the CLI: "acc3" | "acc-g1", "cs-s" | "ncs-s" | "cs-as" | "ncs-as". */
q2n_status q2n_acc_parse_method(const char *s, q2n_acc_method *out, q2n_error *err);
q2n_status q2n_acc_parse_strategy(const char *s, q2n_acc_strategy *out, q2n_error *err);
const char *q2n_acc_method_name(q2n_acc_method m);
const char *q2n_acc_strategy_name(q2n_acc_strategy s);

/* One line for stderr describing what was built, e.g. "acc-g1 cs-s: 1 Catmull-Clark step (face 0
 * has two or more EVs), patches on the subdivided mesh: 0 bicubic + 24 biquintic, EVs 8 interior
 * + 0 boundary (max valence 3)"; returns buf. */
const char *q2n_acc_describe(const q2n_acc_info *info, const q2n_acc_options *opt, char *buf,
                             int size);

/* Catmull–Clark limit positions of all vertices of an all-quad mesh into out[3*nv] (formulas.md
 * §1.1 / §1.4; valence-2 boundary corners stay fixed) and, when nrm != NULL, the unit limit
 * normals (tangent masks of formulas.md §1.2; at boundary vertices the cross-boundary tangent
 * derived in acc_masks.c).  The patch corners equal these points.  Q2N_ERR_UNSUPPORTED for a
 * non-quad mesh (subdivide it first). */
q2n_status q2n_acc_limit_points(const q2n_mesh *m, double *out, double *nrm, q2n_error *err);

/* ---- quality (seed 001 §6.1) ---- */
typedef struct q2n_acc_quality {
    double normal_jump_l2;  /* [n̂] = sqrt( Σ_e ∫_0^1 |n̂_L - n̂_R|^2 dt ), t the edge parameter */
    double normal_jump_max; /* largest angle (rad) between n̂_L and n̂_R at the sample points */
    double gauss_jump_max;  /* <c_G> = max over edges and samples |K_L - K_R| */
    double mean_jump_max;   /* <c_M> = max |H_L - H_R| */
    int n_edges;            /* interior edges measured */
    int n_points;           /* samples per edge */
} q2n_acc_quality;

/* Measure across every interior edge of m (the mesh the patches are built on) at npts points per
 * edge (Gauss–Legendre nodes, 2..16; the endpoints are not sampled, where unit normals are
 * defined as limits only). */
q2n_status q2n_acc_quality_measure(const q2n_surface *s, const q2n_mesh *m, int npts,
                                   q2n_acc_quality *q, q2n_error *err);

/* Limit-surface evaluator: point p and (not necessarily unit) normal n of the Catmull–Clark limit
 * on face `face` of the mesh the patches are built on, at (u,v) in the same face convention. */
typedef q2n_status (*q2n_acc_limit_fn)(void *ctx, int face, double u, double v, double p[3],
                                       double n[3]);

typedef struct q2n_acc_distance {
    double geom_max, geom_rms; /* distance from limit points to the patches */
    double normal_max;         /* |n̂_limit - n̂_patch| (2-norm of the unit-normal difference) */
    int n_samples;
} q2n_acc_distance;

/* Compare patch k and the limit on face k on an n x n grid per face (cell centres).  With
 * project != 0 each limit point is projected onto its patch (Gauss–Newton, clamped to [0,1]^2)
 * and, when m (the mesh the patches are built on) is given and the projection ends on the
 * patch border, onto the patches of the faces around face k as well: the closest-point
 * distance of seed 001 §6.3.  With project == 0: the distance at equal (u,v). */
q2n_status q2n_acc_limit_distance(const q2n_surface *s, const q2n_mesh *m, int n,
                                  q2n_acc_limit_fn limit, void *ctx, int project,
                                  q2n_acc_distance *d, q2n_error *err);

/* Exact limit samples without an external evaluator: the limit points and unit normals at the
 * vertices of m subdivided `levels` times (0..6), with their face and (u,v) on m (one entry per
 * fine vertex).  Free with q2n_acc_limit_samples_free. */
typedef struct q2n_acc_limit_samples {
    int n;
    int *face;    /* n: face of m */
    double *uv;   /* 2n */
    double *p;    /* 3n: limit points */
    double *nrm;  /* 3n: unit limit normals */
} q2n_acc_limit_samples;

q2n_status q2n_acc_limit_samples_make(const q2n_mesh *m, int levels, q2n_acc_limit_samples *out,
                                      q2n_error *err);
void q2n_acc_limit_samples_free(q2n_acc_limit_samples *ls); /* NULL is a no-op */

/* Distance from the exact limit samples to the patches (same options as q2n_acc_limit_distance). */
q2n_status q2n_acc_limit_distance_samples(const q2n_surface *s, const q2n_mesh *m,
                                          const q2n_acc_limit_samples *ls, int project,
                                          q2n_acc_distance *d, q2n_error *err);

#endif
