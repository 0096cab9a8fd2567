/* model.h — the whole pipeline as one object (top of the library, used by src/cli/ and by the
 * public API in include/quad2nurbs.h): read the mesh, subdivide if asked, build the surface
 * (augmented interpolatory + Coons–Gregory, or the Catmull–Clark ACC path), fit it into
 * B-splines, and write outputs chosen by file extension, all or nothing (outputs.c); check the
 * options and estimate the resources a run needs before it starts (options.c). */
#ifndef Q2N_API_MODEL_H
#define Q2N_API_MODEL_H

#include <stdio.h>

#include "quad2nurbs.h"

#include "acc/acc.h"
#include "core/clock.h"
#include "core/outfile.h"
#include "core/progress.h"
#include "fit/fit.h"
#include "iges/export.h"
#include "mesh/mesh.h"
#include "param/param.h"
#include "patch/extraordinary.h"
#include "patch/surface.h"
#include "spline/spline.h"

/* q2n_surface_method, q2n_format and the Q2N_GIVEN_* bits are public (include/quad2nurbs.h). */

/* Zeroed = defaults (augmented, Q2N_SPLINE_CLASS_DEFAULT, centripetal α = 1/2, fair EV construction,
 * no subdivision, scale 1). */
typedef struct q2n_model_options {
    q2n_surface_method method;
    const q2n_spline_class *cls;  /* augmented: NULL = Q2N_SPLINE_CLASS_DEFAULT */
    q2n_param_options param;      /* augmented: zeroed = centripetal */
    int ev_patch;                 /* augmented: a q2n_ev_patch_kind (0 default: G2 for C2 classes) */
    int ev_method;                /* augmented: a q2n_ev_method (0 default: the fair construction) */
    int keep_flat;                /* augmented, fair construction: flat fans stay flat (q2n_options) */
    int smooth_gluing;            /* augmented, fair construction: a q2n_ev_gluing (q2n_options.ev_smooth_gluing):
                                     0 polynomial gluing, G2 patches' regions given the smoothsteps where
                                     those are fairer (gluing_choice); 1 smoothsteps everywhere; 2
                                     polynomial gluing without the choice */
    int fold_fallback;            /* augmented, default patches (G2): where they fold over, G1 patches at the
                                     extraordinary vertices instead if those fold on fewer faces (the public
                                     API sets it unless ev_patch is given or continuity is G2) */
    int frame;                    /* augmented: 0 (default) builds in the mesh's isotropic frame too where the
                                     mesh is stretched and keeps the build that ripples less; -1 never
                                     (--frame off; docs/extraordinary.md, "The isotropic frame") */
    int threads;                  /* worker threads of the construction (0: 1; results do not depend on it) */
    q2n_acc_strategy acc_strategy;
    int subdivide;                /* Catmull–Clark steps before building */
    int limit_points;             /* vertices moved to their Catmull–Clark limit positions (augmented):
                                     1 always, -1 never, 0 when subdivide > 0 */
    int pair_triangles;           /* triangles paired into quads before subdivide (q2n_options) */
    int fill_ngons;               /* even n-gons (n >= 6) filled with quads before subdivide (q2n_options) */
    double scale;                 /* multiplies every output coordinate (0: 1): --scale */
    q2n_progress_sink progress;   /* reports of every stage (fn NULL: none) */
} q2n_model_options;

/* Coordinates.  The mesh is moved into its frame right after reading (q2n_mesh_normalize):
 * internal = (input - origin) / scale with scale = scale_mant * 2^scale_exp the bounding-box
 * diagonal, so the construction and the fit always see a mesh of diagonal 1 whatever the input's
 * scale (1e-300 or 1e300).  mesh, surface and edge_iv are internal; nurbs (after q2n_model_fit)
 * and everything written or returned (files, samples, q2n_patch_eval) are mapped back, times the
 * user's --scale (opt.scale): output = scale * (origin + 2^scale_exp * (scale_mant * internal)),
 * derivatives scale * 2^scale_exp * (scale_mant * d): an affine map, exact up to rounding (the
 * power of two keeps the scale itself in range). */
/* Warnings a model keeps (more are dropped): a few per stage. */
#define Q2N_MODEL_MAX_WARNINGS 32

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
    q2n_mesh_read_info read_info; /* format, ignored tags (for a warning) */
    int input_faces;           /* faces of the mesh as read (before any pairing or subdivision) */
    int paired, tri_left;      /* pair_triangles: quads made of two triangles, triangles left */
    int filled, fill_quads;    /* fill_ngons: faces filled, quads made for them */
    int taken_faces;           /* faces after pairing and filling (before subdivision) */
    char warning[512];         /* e.g. the first face whose surface folds over; "" when none */
    int folded;                /* faces whose surface folds over (normal against the face's) */
    int folded_face;           /* the first of them (-1: none) */
    q2n_fit_options fit_opt;   /* settings kept for later q2n_model_fit calls (public API) */
    q2n_export_options export_opt;
    int tess;                  /* public API: tessellation points per patch side */
    int format;                /* public API: a q2n_format for names without a known extension */
    double max_memory;         /* public API: the resource limit (0 default, < 0 none) */
    unsigned given;            /* public API: Q2N_GIVEN_* bits of the options set explicitly */
    char warnings[Q2N_MODEL_MAX_WARNINGS][512]; /* what the caller should hear about, in order */
    int nwarnings;
    q2n_nurbs_model *nurbs;    /* after q2n_model_fit, output coordinates */
    q2n_fit_report fit;        /* after q2n_model_fit */
    double t_read, t_build, t_fit, t_write; /* seconds */
    double moved_rel;          /* --limit-points: largest vertex move / bbox diagonal (0: none) */
    q2n_extraordinary_stats ev_stats; /* the extraordinary regions' build (--keep-flat's vertices) */
    int g2_folded;             /* opt.fold_fallback taken: the faces the G2 patches folded on (0: not taken) */
    q2n_mesh *frame_mesh;      /* while building in the isotropic frame: the mesh mapped into it */
    const q2n_mesh *frame_charts; /* while building with the vertex charts of the isotropic frame: that mesh */
    const q2n_mesh *frame_regions; /* while building the extraordinary regions in the isotropic frame: that mesh */
    double frame_A[3][3];      /* the map into the frame */
    double frame_Ainv[3][3];   /* the map back out of the frame */
    double frame_stretch;      /* the isotropic frame's stretch (condition number; 1: none, 0: not estimated) */
    int frame_used;            /* 0: the mesh's own frame; 1: built in the isotropic frame and mapped back;
                                  2: the vertex charts measured in it; 3: the extraordinary regions built in
                                  it (the regular patches the mesh's own), mapped back */
    double frame_ripple[4];    /* the diagonal ripple of the builds: own frame, isotropic frame, charts
                                  only, regions (0: not built) */
    double frame_energy[4];    /* their bending energy */
    const char *smooth_v;      /* while building with the gluing choice's regions: per vertex, 1 where the
                                  polynomial gluing keeps out (q2n_extraordinary_options.smooth_vertices) */
    int gluing_regions[2];     /* the gluing choice (G2 patches): regions compared, regions given the
                                  smoothsteps because they are fairer there */
} q2n_model;

/* Read (any mesh format, q2n_mesh_read) and move into the internal frame, then construct:
 * q2n_model_read followed by q2n_model_construct. */
q2n_status q2n_model_build(const char *mesh_path, const q2n_model_options *opt, q2n_model **out,
                           q2n_error *err);
/* The two halves, so that a caller can check the work (q2n_model_estimate) before the slow one. */
q2n_status q2n_model_read(const char *mesh_path, const q2n_model_options *opt, q2n_model **out, q2n_error *err);
/* Subdivide if asked, build the surface, then scan every patch (Q2N_MODEL_SCAN_GRID points a
 * side): a non-finite value fails with Q2N_ERR_NUMERIC naming the face and its line; a patch
 * whose normal turns against its face's is counted in folded and named in warning. */
q2n_status q2n_model_construct(q2n_model *m, q2n_error *err);
/* The read half for a validated mesh, which the model takes over (freed on failure too). */
q2n_status q2n_model_take_mesh(q2n_mesh *mesh, const q2n_model_options *opt, q2n_model **out, q2n_error *err);
/* Build on a validated mesh, which the model takes over (freed on failure too). */
q2n_status q2n_model_build_mesh(q2n_mesh *mesh, const q2n_model_options *opt, q2n_model **out,
                                q2n_error *err);
/* Append a warning line to m->warnings (printf-style, escaped). */
void q2n_model_warn(q2n_model *m, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Output units per internal unit: scale * 2^scale_exp * scale_mant. */
double q2n_model_length_scale(const q2n_model *m);
/* Fit (or convert exactly) into B-splines; continuity defaults to the construction's. */
q2n_status q2n_model_fit(q2n_model *m, const q2n_fit_options *fopt, q2n_error *err);
void q2n_model_free(q2n_model *m);

q2n_status q2n_model_write_tessellation(const q2n_model *m, int n, const char *path, q2n_error *err);
/* The tessellation into an open stream (write errors stay in the stream's error flag). */
q2n_status q2n_model_write_tessellation_file(const q2n_model *m, int n, FILE *f, q2n_error *err);
q2n_status q2n_model_write_samples(const q2n_model *m, int n, FILE *out, q2n_error *err);

/* Patch k at (u, v) in output coordinates (input times --scale): S, Su, Sv (9 doubles);
 * Q2N_ERR_NUMERIC with a message naming the face when a value is not finite (also after mapping
 * back, e.g. overflow). */
q2n_status q2n_model_eval(const q2n_model *m, int k, double u, double v, double out[9], q2n_error *err);
/* Map n grid points (9 doubles each: S, Su, Sv) from internal to output coordinates, in place. */
void q2n_model_map_points(const q2n_model *m, double *e, size_t n);

/* ---------------------------------------------------------------- outputs (outputs.c) */

/* By extension (.obj, .step/.stp, .igs/.iges, .json; any case), else NONE. */
q2n_format q2n_format_of_path(const char *path);
/* "obj", "step"/"stp", "iges"/"igs", "json", else NONE. */
q2n_format q2n_format_parse(const char *name);
const char *q2n_format_name(q2n_format f);
/* STEP, IGES and the report come from the fitted B-splines. */
static inline int q2n_format_needs_fit(q2n_format f) { return f == Q2N_FORMAT_STEP || f == Q2N_FORMAT_IGES || f == Q2N_FORMAT_JSON; }

/* Several outputs as one transaction: q2n_outputs_open_set checks the whole set (known formats —
 * names without a known extension, such as "-" for standard output, take `fallback`; no file
 * twice; none is the input mesh) and creates every temporary (so an unwritable directory shows
 * in milliseconds, before any slow work), the caller writes each (q2n_model_write_output), and
 * q2n_outputs_commit_set makes all data durable before it replaces any file.  On any failure nothing
 * is left behind: no output, no temporary.  Errors: Q2N_ERR_ARG for a set that makes no sense,
 * Q2N_ERR_IO (message "PATH: REASON") for the file system. */
typedef struct q2n_output {
    const char *path;
    q2n_format format;
    q2n_outfile file;
} q2n_output;

typedef struct q2n_output_set {
    int n;
    q2n_output *out;
} q2n_output_set;

q2n_status q2n_outputs_open_set(q2n_output_set *s, int n, const char *const *paths, q2n_format fallback,
                            const char *input, q2n_error *err);
q2n_status q2n_model_write_output(q2n_model *m, q2n_output *o, int tess, const q2n_export_options *xopt,
                                  q2n_error *err);
q2n_status q2n_outputs_commit_set(q2n_output_set *s, q2n_error *err);
void q2n_outputs_abort_set(q2n_output_set *s);

/* One output by extension (a set of one): .obj (tessellation, tess points per patch side),
 * .step/.stp, .igs/.iges, .json (the fit report; these three need q2n_model_fit first). */
q2n_status q2n_model_write(q2n_model *m, const char *path, int tess, const q2n_export_options *xopt,
                           q2n_error *err);

/* ---------------------------------------------------------------- options, limits (options.c) */


/* What a run will do, for the warnings and the estimates. */
typedef struct q2n_plan {
    int fit;          /* some output needs the fit */
    int obj;          /* some output is a tessellation */
    int sample;       /* `sample` prints the construction */
    int tess, grid;   /* points per patch side */
    int continuity;   /* --continuity (0: the construction's) */
    int nout;
    const q2n_output *out;  /* the outputs (their formats and paths) */
} q2n_plan;

/* Options that the chosen path ignores or that contradict each other, as warning lines
 * ("--alpha is ignored with --param uniform ..."), written into msgs[i] (at most max lines of 160
 * bytes); returns how many. */
int q2n_options_warnings(const q2n_model_options *mo, const q2n_fit_options *fo, unsigned set, const q2n_plan *plan,
                         char (*msgs)[160], int max);

/* Relative fit tolerance from an absolute one (model units), checked against the range the fit
 * accepts ([1e-12, 0.1] x the bounding-box diagonal of m's mesh): Q2N_ERR_ARG with the numbers. */
q2n_status q2n_model_resolve_tol(const q2n_model *m, q2n_fit_options *fo, q2n_error *err);

/* The files' creation time: SOURCE_DATE_EPOCH when set (reproducible builds; a malformed value is
 * Q2N_ERR_ARG), else now.  Sets x->has_date, x->date. */
q2n_status q2n_export_date_from_env(q2n_export_options *x, q2n_error *err);

/* Estimated peak memory (bytes) and output sizes of the planned run on the read mesh, from the
 * faces the construction will have (after --subdivide) and measured bytes per face of each stage
 * (docs/cli.md, "Resource limits"). */
typedef struct q2n_estimate {
    long long faces;          /* faces after subdivision */
    double memory;            /* bytes, peak */
    double output[16];        /* bytes per output (plan order) */
    const char *peak_stage;   /* the stage that sets the peak */
} q2n_estimate;
void q2n_model_estimate(const q2n_model *m, const q2n_plan *plan, q2n_estimate *e);
/* Refuse the run when the estimated memory is above max_memory (bytes; < 0 no limit, 0 the
 * default: half the physical memory) — Q2N_ERR_ARG, message with both figures — or an output is
 * estimated larger than the free space of its file system (Q2N_ERR_IO). */
q2n_status q2n_model_check_resources(const q2n_model *m, const q2n_plan *plan, double max_memory, q2n_error *err);
/* Half the physical memory (the default limit), bytes. */
double q2n_default_max_memory(void);

#endif
