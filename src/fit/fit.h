/* fit.h — turn a composite surface into bi-quintic B-spline patches (pipeline stage 4):
 * watertight, G1 (or G2) across every interior edge, within a tolerance of the construction.
 *
 * Augmented / Coons–Gregory patches (non-polynomial) are least-squares fitted with local knots
 * (every mesh edge has its own knot vector, every patch its own interior knots) and, wherever the
 * construction's gluing data across an edge are polynomial, with the G1 relation imposed exactly
 * as linear equality constraints; Bézier patches (the Catmull–Clark ACC path) are converted
 * exactly by degree elevation to 5 x 5.  docs/fit.md describes the method and what is exact. */
#ifndef Q2N_FIT_FIT_H
#define Q2N_FIT_FIT_H

#include <stdio.h>

#include "core/error.h"
#include "core/progress.h"
#include "fit/bspline.h"
#include "mesh/mesh.h"
#include "patch/surface.h"

typedef enum q2n_fit_solver {
    Q2N_FIT_SOLVER_CERES = 0,    /* Ceres per independent block (TinySolver up to 16 unknowns, else DENSE_QR),
                                    blocks over threads (default) */
    Q2N_FIT_SOLVER_CERES_SPARSE, /* Ceres SPARSE_NORMAL_CHOLESKY over batches of blocks (normal equations) */
    Q2N_FIT_SOLVER_DIRECT        /* LAPACK rank-revealing QR per block: the reference path */
} q2n_fit_solver;

/* Zero-initialised options mean defaults (given in brackets; fit_policy.h). */
typedef struct q2n_fit_options {
    double tol;            /* max deviation, relative to the bounding-box diagonal [1e-5] (--tol) */
    int continuity;        /* 1 = G1, 2 = G2 [1] */
    int threads;           /* worker threads [1] (--threads) */
    int solver;            /* q2n_fit_solver [Q2N_FIT_SOLVER_CERES] */
    int max_spans;         /* cap on knot spans per patch direction [64] (--max-spans) */
    int max_rounds;        /* refinement rounds [0: 12 plus the mesh's largest valence, fit_policy.h] */
    double g1_tol_deg;     /* G1 acceptance: normal-angle jump across edges [0.01 degrees at tol <=
                              1e-5, times tol / 1e-5 above, at most 0.5: q2n_fit_default_target];
                              refinement aims at 0.9 of it (Q2N_FIT_REFINE_AIM) */
    double g2_tol_rel;     /* G2 acceptance: relative normal-curvature jump, G2 mode [0.01 at tol <=
                              1e-5, times tol / 1e-5 above, at most 0.1]; refinement aims at 0.9 of it */
    double g1_weight;      /* weight of least-squares gluing rows against sample fidelity [3] */
    int no_exact;          /* 1: impose every gluing relation by least squares (no equality constraints) [0] */
    double tol_abs;        /* > 0: deviation tolerance in model units, replaces tol (tol = tol_abs /
                              bounding-box diagonal) */
    const q2n_progress_sink *progress; /* NULL: no reports ("fit": one per round and stage) */
} q2n_fit_options;

/* Threads beyond this are not started (the fit's parallel loops deal items to at most this many). */
#define Q2N_FIT_MAX_THREADS 64

/* What q2n_fit_surface measured (all relative values are divided by the bounding-box diagonal,
 * except g2_max_rel which is relative to the local curvature; see docs/fit.md). */
typedef struct q2n_fit_report {
    int faces, edges, interior_edges;
    int exact;                 /* 1: all patches were Bézier and converted exactly */
    int continuity;            /* 1 or 2 */
    double tol;                /* requested relative tolerance */
    double tol_abs, diag;      /* the same in model units, and the bounding-box diagonal */
    double g1_tol_deg, g2_tol_rel; /* the continuity acceptance targets used */
    int tol_met;               /* dev_met && g1_met && g2_met */
    int dev_met;               /* max_dev_rel <= tol (else q2n_fit_surface fails) */
    int g1_met, g2_met;        /* continuity targets held on every edge where the construction
                                  meets them itself (g2_met is 1 in G1 mode) */
    char note[240];            /* which edge missed a continuity target, or "" */
    int rounds;                /* refinement rounds used */
    int g1_exact_edges;        /* interior edges whose G1 relation is an equality constraint */
    int g1_rounding_edges;     /* interior edges whose measured normal jump is at most Q2N_FIT_G1_ROUNDING_DEG */
    int g1_ls_edges;           /* interior edges whose G1 relation is least squares */
    int spans_min, spans_median, spans_max;   /* knot spans per patch (m_u * m_v) */
    int cp_min, cp_median, cp_max;            /* control points per patch (n_u * n_v) */
    long cp_total;             /* control points of all patches */
    int edge_spans_max;        /* largest span count of any edge curve */
    long samples, checks;      /* construction evaluations for fit samples and check points */
    double max_dev_rel, rms_dev_rel;          /* at check points between the fit samples */
    double vertex_dev_max_rel; /* construction's patch corners vs mesh vertices */
    double g0_max_rel;         /* gap between the two fitted sides of every interior edge */
    double g1_max_deg;         /* max normal-angle jump across interior edges (fitted) */
    double g2_max_rel;         /* max normal-curvature jump / local curvature (fitted) */
    double g1_construction_deg, g2_construction_rel;  /* the same on the construction itself */
    int rim_vertices;              /* boundary vertices where boundary edges of two faces meet */
    double rim_max_deg, rim_construction_deg; /* there: the largest angle between the two faces' boundary
                                      tangents (the rim's turn; 0 where it runs on smoothly), fitted and
                                      on the construction */
    double rim_curv_rel, rim_construction_curv_rel; /* and the largest jump of the boundary curves' curvature
                                      vector, over the larger one (at least 1/diag) */
    int folded_faces, folded_face; /* faces whose construction folds over, the first (-1: none); set by
                                      the caller that scanned it (q2n_model_fit), else 0 and -1 */
    double vertices_moved_rel;     /* largest distance the mesh's vertices were moved before the
                                      construction (--limit-points), relative to bbox_diag; set by the
                                      caller, else 0 */
    int flat_vertices;             /* --keep-flat: vertices whose fan the construction kept in its
                                      plane; set by the caller, else 0 */
    int polynomial_edges;          /* constructed edges glued by polynomials (G1 patches: the fit
                                      reproduces both sides exactly); set by the caller, else 0 */
    int gluing_regions, smoothstep_regions; /* the gluing choice (G2 patches): extraordinary regions
                                      compared, and those glued by smoothsteps because they are fairer
                                      so (docs/extraordinary.md, "The gluing chosen per region"); set by
                                      the caller, else 0 */
    int g2_folded_faces;           /* the construction's G2 patches folded on this many faces and G1 patches
                                      replaced them (q2n_model_options.fold_fallback); set by the caller, else 0 */
    int paired_quads, triangles_left; /* --pair-triangles: quads made of two input triangles, triangles
                                      left unpaired; set by the caller, else 0 */
    int filled_faces, fill_quads;  /* --fill-ngons: faces filled with quads, quads made; set by the caller, else 0 */
    double frame_stretch;          /* the mesh's isotropic frame: its stretch (0: not estimated), which build
                                      was kept (0 own frame, 1 built in it, 2 its vertex charts, 3 the
                                      extraordinary regions built in it), and the diagonal ripple and
                                      bending energy of the builds in that order (0: not built); set by the
                                      caller, else 0 */
    int frame_used;
    double frame_ripple[4], frame_energy[4];
    double t_sample, t_build, t_solve, t_measure, t_total;  /* seconds per stage */
    long step_bytes, iges_bytes;   /* sizes of the CAD files written from this fit (0: none; set by the writer's caller) */
    int solver, threads;        /* threads: the number used */
} q2n_fit_report;

void q2n_fit_options_default(q2n_fit_options *o);

/* The default continuity target for relative tolerance tol: base at tol <= 1e-5, base * tol / 1e-5
 * above, at most cap (fit_policy.h says why). */
double q2n_fit_default_target(double tol, double base, double cap);

/* Fit (or convert) every patch of s (one per face of m; all faces quads) into *out (free with
 * q2n_nurbs_model_free).  rep may be NULL.  Fails with Q2N_ERR_UNSUPPORTED for uncovered
 * patches, non-quads or a mix of Bézier and non-polynomial patches; with Q2N_ERR_GEOMETRY
 * (message names the worst face) when the deviation tolerance is not met within max_spans /
 * max_rounds — *out is then still set, so the caller may inspect or export it.  Continuity
 * targets that refinement cannot reach (the construction's own limits) do not fail the call:
 * rep->g1_met / g2_met say so and rep->note names the worst edge. */
q2n_status q2n_fit_surface(const q2n_surface *s, const q2n_mesh *m, const q2n_fit_options *opt,
                           q2n_nurbs_model **out, q2n_fit_report *rep, q2n_error *err);

/* Measure a model against the construction (deviation, G0/G1/G2 across edges, also on the
 * construction itself) into rep's measured fields, with `threads` workers; used by
 * q2n_fit_surface and by tests. */
q2n_status q2n_fit_measure(const q2n_nurbs_model *model, const q2n_surface *s, int threads,
                           q2n_fit_report *rep, q2n_error *err);

/* Write the report as JSON (atomic: temp file + rename), or into an open stream; units names the
 * model's length unit in the report ("mm", ...; NULL: left out). */
q2n_status q2n_fit_report_write_json(const q2n_fit_report *rep, const char *path, q2n_error *err);
void q2n_fit_report_write_json_file(const q2n_fit_report *rep, const char *units, FILE *f);

#endif
