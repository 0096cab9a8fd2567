/* model.h — the whole pipeline as one object (top of the library, used by src/cli/ and by the
 * public API in include/quad2nurbs.h): read the mesh, subdivide if asked, build the surface
 * (augmented interpolatory + Coons–Gregory, or the Catmull–Clark ACC path), fit it into
 * B-splines, and write outputs chosen by file extension. */
#ifndef Q2N_API_MODEL_H
#define Q2N_API_MODEL_H

#include <stdio.h>

#include "acc/acc.h"
#include "core/clock.h"
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

/* Zeroed = defaults (augmented, Q2N_SPLINE_CLASS_DEFAULT, centripetal α = 1/2, no subdivision). */
typedef struct q2n_model_options {
    q2n_surface_method method;
    const q2n_spline_class *cls;  /* augmented: NULL = Q2N_SPLINE_CLASS_DEFAULT */
    q2n_param_options param;      /* augmented: zeroed = centripetal */
    int ev_patch;                 /* augmented: a q2n_ev_patch_kind (0 default: G2 for C2 classes) */
    int ev_method;                /* augmented: a q2n_ev_method (0 default: the fair construction) */
    int threads;                  /* worker threads of the construction (0: 1; results do not depend on it) */
    q2n_acc_strategy acc_strategy;
    int subdivide;                /* Catmull–Clark steps before building */
} q2n_model_options;

typedef struct q2n_model {
    q2n_model_options opt;
    q2n_mesh *mesh;            /* the mesh the patches are built on (after subdivision) */
    q2n_surface *surface;      /* patch k on face k of mesh */
    double *edge_iv;           /* augmented: per-edge intervals */
    int uncovered;             /* faces no construction covers */
    int continuity;            /* 1 or 2: what the construction guarantees across edges (G^k) */
    char note[256];            /* e.g. why Catmull–Clark steps were applied by the ACC path */
    q2n_fit_options fit_opt;   /* settings kept for later q2n_model_fit calls (public API) */
    q2n_export_options export_opt;
    q2n_nurbs_model *nurbs;    /* after q2n_model_fit */
    q2n_fit_report fit;        /* after q2n_model_fit */
    double t_read, t_build, t_fit, t_write; /* seconds */
} q2n_model;

q2n_status q2n_model_build(const char *obj_path, const q2n_model_options *opt, q2n_model **out,
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


#endif
