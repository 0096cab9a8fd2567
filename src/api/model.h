/* model.h — the whole pipeline as one object (top of the library, used by src/cli/ and by the
 * public API in include/quad2nurbs.h): read the mesh, subdivide if asked, build the surface
 * (augmented interpolatory + Coons–Gregory, or the Catmull–Clark ACC path), fit it into
 * B-splines, and write outputs chosen by file extension. */
#ifndef Q2N_API_MODEL_H
#define Q2N_API_MODEL_H

#include <stdio.h>

#include "acc/acc.h"
#include "fit/fit.h"
#include "iges/export.h"
#include "mesh/mesh.h"
#include "param/param.h"
#include "patch/surface.h"
#include "spline/spline.h"

typedef enum q2n_surface_method {
    Q2N_SURFACE_AUGMENTED = 0, /* seed 003: interpolates every vertex */
    Q2N_SURFACE_ACC3,          /* seed 001 / Loop–Schaefer: bicubic, C0 at EVs */
    Q2N_SURFACE_ACC_G1         /* seed 001: bicubic + biquintic, G1 everywhere */
} q2n_surface_method;

/* Zeroed = defaults (augmented, D5C2P2S4, centripetal α = 1/2, no subdivision). */
typedef struct q2n_model_options {
    q2n_surface_method method;
    const q2n_spline_class *cls;  /* augmented: NULL = D5C2P2S4 */
    q2n_param_options param;      /* augmented: zeroed = centripetal */
    int ev_patch;                 /* augmented: a q2n_ev_patch_kind (0 default: G2 for C2 classes) */
    q2n_acc_strategy acc_strategy;
    int subdivide;                /* Catmull–Clark steps before building */
} q2n_model_options;

/* Coordinates.  The mesh is moved into its frame right after reading (q2n_mesh_normalize):
 * internal = (input - origin) / scale with scale = scale_mant * 2^scale_exp the bounding-box
 * diagonal, so the construction and the fit always see a mesh of diagonal 1 whatever the input's
 * scale (1e-300 or 1e300).  mesh, surface and edge_iv are internal; nurbs (after q2n_model_fit)
 * and everything written or returned (files, samples, q2n_patch_eval) are mapped back:
 * input = origin + 2^scale_exp * (scale_mant * internal), derivatives 2^scale_exp * (scale_mant * d):
 * an affine map, exact up to rounding (the power of two keeps the scale itself in range). */
typedef struct q2n_model {
    q2n_model_options opt;
    q2n_mesh *mesh;            /* the mesh the patches are built on (after subdivision), internal */
    double origin[3];          /* input = origin + 2^scale_exp * (scale_mant * internal) */
    double scale_mant;
    int scale_exp;
    q2n_surface *surface;      /* patch k on face k of mesh, internal coordinates */
    double *edge_iv;           /* augmented: per-edge intervals */
    int uncovered;             /* faces no construction covers */
    int continuity;            /* 1 or 2: what the construction guarantees across edges (G^k) */
    char note[256];            /* e.g. why Catmull–Clark steps were applied by the ACC path */
    int input_faces;           /* faces of the mesh as read (before any subdivision) */
    char warning[320];         /* e.g. the first face whose surface folds over; "" when none */
    int folded;                /* faces whose surface folds over (normal against the face's) */
    q2n_fit_options fit_opt;   /* settings kept for later q2n_model_fit calls (public API) */
    q2n_export_options export_opt;
    q2n_nurbs_model *nurbs;    /* after q2n_model_fit, input coordinates */
    q2n_fit_report fit;        /* after q2n_model_fit */
    double t_read, t_build, t_fit, t_write; /* seconds */
} q2n_model;

/* Read obj_path and build (q2n_model_build_mesh).  Errors name the file and line. */
q2n_status q2n_model_build(const char *obj_path, const q2n_model_options *opt, q2n_model **out,
                           q2n_error *err);
/* Build on a validated mesh, which the model takes over (freed on failure too): normalise,
 * subdivide if asked, build the surface, then scan every patch (Q2N_MODEL_SCAN_GRID points a
 * side): a non-finite value fails with Q2N_ERR_NUMERIC naming the face and its line; a patch
 * whose normal turns against its face's is counted in folded and named in warning. */
q2n_status q2n_model_build_mesh(q2n_mesh *mesh, const q2n_model_options *opt, q2n_model **out,
                                q2n_error *err);
/* Fit (or convert exactly) into B-splines; continuity defaults to the construction's. */
q2n_status q2n_model_fit(q2n_model *m, const q2n_fit_options *fopt, q2n_error *err);
/* Write by extension: .obj (tessellation, n points per patch side), .step/.stp, .igs/.iges
 * (need q2n_model_fit first), .json (the fit report). */
q2n_status q2n_model_write(q2n_model *m, const char *path, int tess, const q2n_export_options *xopt,
                           q2n_error *err);
/* 1 if the extension is one q2n_model_write knows; *needs_fit set for CAD/report outputs. */
int q2n_model_output_kind(const char *path, int *needs_fit);
void q2n_model_free(q2n_model *m);

q2n_status q2n_model_write_tessellation(const q2n_model *m, int n, const char *path, q2n_error *err);
q2n_status q2n_model_write_samples(const q2n_model *m, int n, FILE *out, q2n_error *err);

/* Patch k at (u, v) in input coordinates: S, Su, Sv (9 doubles); Q2N_ERR_NUMERIC with a message
 * naming the face when a value is not finite (also after mapping back, e.g. overflow). */
q2n_status q2n_model_eval(const q2n_model *m, int k, double u, double v, double out[9], q2n_error *err);
/* Map n grid points (9 doubles each: S, Su, Sv) from internal to input coordinates, in place. */
void q2n_model_map_points(const q2n_model *m, double *e, size_t n);

double q2n_now(void);

#endif
