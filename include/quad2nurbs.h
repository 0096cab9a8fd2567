/* quad2nurbs.h — the public C API of libquad2nurbs (the module headers under src/ are internal).
 *
 *   q2n_model *m;  char err[512];
 *   q2n_options o = {0};                                  // zeroed = defaults
 *   if (q2n_open("mesh.obj", &o, &m, err, sizeof err)) { fprintf(stderr, "%s\n", err); return 2; }
 *   double p[9];  q2n_patch_eval(m, 0, 0.5, 0.5, p);       // S, Su, Sv of patch 0 (face 0)
 *   const char *outs[] = {"part.step", "part.igs"};
 *   q2n_write_all(m, outs, 2, err, sizeof err);            // fits, then writes all or nothing
 *   q2n_close(m);
 *
 * Conventions.  Every function that can fail returns a q2n_status (Q2N_OK = 0) and, when errbuf
 * is not NULL, writes one line of printable text into it (at most errlen bytes, NUL-terminated)
 * naming the file and line, or the element (face k, vertex v; 0-based), and the reason; on
 * failure no output file is left behind and *out pointers are NULL.  The library never prints,
 * never exits and keeps no global state of its own: different models may be used from different
 * threads at the same time; one model is not to be used from two threads at once.  (One process-wide
 * setting is made, once: SuiteSparse's malloc and calloc hooks are pointed at 64-byte aligned
 * versions, whose blocks free and realloc accept, so that CHOLMOD's BLAS calls give the same bits
 * in every run; another SuiteSparse user in the process is unaffected otherwise.)  Lengths are model units:
 * the input's coordinates times q2n_options.scale (everything returned and written is in them;
 * the construction works internally at bounding-box diagonal 1 and maps back).
 *
 * Meshes: Wavefront OBJ, OFF (ASCII) and PLY (ASCII and binary), recognised by extension or by
 * their first line, or arrays in memory (q2n_open_mesh).  Patch k is built on face k of the mesh
 * (after subdivision when requested or when the Catmull–Clark path needs it); its domain is
 * [0,1]^2 with u along the face's first edge v0->v1 and v along v0->v3.
 *
 * Build against the installed library with pkg-config (the dependencies are static):
 *   cc app.c $(pkg-config --cflags --libs --static quad2nurbs)                                  */
#ifndef QUAD2NURBS_H
#define QUAD2NURBS_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version, in one place (the Makefile and the pkg-config file read it from here). */
#define Q2N_VERSION_MAJOR 0
#define Q2N_VERSION_MINOR 2
#define Q2N_VERSION_PATCH 0
#define Q2N_STRINGIFY_(x) #x
#define Q2N_STRINGIFY(x) Q2N_STRINGIFY_(x)
#define QUAD2NURBS_VERSION                                                                        \
    Q2N_STRINGIFY(Q2N_VERSION_MAJOR) "." Q2N_STRINGIFY(Q2N_VERSION_MINOR) "." Q2N_STRINGIFY(Q2N_VERSION_PATCH)
/* "MAJOR.MINOR.PATCH" of the library linked (QUAD2NURBS_VERSION is the header's). */
const char *q2n_version(void);
/* Threads a run may use on this machine: the processors this process may run on (its CPU
 * affinity), at most 64, the most the library uses; 1 where the system BLAS is not safe for calls
 * from several threads at once (OpenBLAS' serial build).  The command line's default --threads;
 * q2n_options.threads itself defaults to 1. */
int q2n_default_threads(void);

/* ------------------------------------------------------------------ status */

/* What went wrong.  The command line exits with 2 for what is the input's or the caller's fault
 * (PARSE, TOPOLOGY, GEOMETRY of the mesh, UNSUPPORTED, ARG, IO on the input) and 1 otherwise. */
typedef enum q2n_status {
    Q2N_OK = 0,
    Q2N_ERR_IO,          /* a file cannot be opened, read or written */
    Q2N_ERR_PARSE,       /* malformed input text, bad number, NaN/Inf coordinate */
    Q2N_ERR_TOPOLOGY,    /* non-manifold, inconsistent orientation, index out of range */
    Q2N_ERR_GEOMETRY,    /* degenerate face or edge; a fit that misses its tolerance */
    Q2N_ERR_UNSUPPORTED, /* valid input the construction does not handle (non-quads, valence) */
    Q2N_ERR_NOMEM,       /* out of memory */
    Q2N_ERR_ARG,         /* invalid option or argument, a resource limit */
    Q2N_ERR_NUMERIC      /* valid input, but an evaluation gave a non-finite number */
} q2n_status;

/* "ok", "i/o error", "parse error", ... (static text; "unknown error" out of range). */
const char *q2n_status_string(q2n_status st);

/* Copy src into dst (cap bytes, NUL-terminated, cut at a whole character) with every byte that
 * could act on a terminal written as \xHH (C0 controls, DEL, invalid UTF-8, C1 controls): for
 * printing names that come from input.  Every library message is escaped already.  Returns the
 * length written. */
size_t q2n_escape(char *dst, size_t cap, const char *src);

/* ------------------------------------------------------------------ choices */

/* The surface built on the mesh. */
typedef enum q2n_surface_method {
    Q2N_SURFACE_AUGMENTED = 0, /* interpolates every vertex (Antonelli–Beccari–Casciola 2016) */
    Q2N_SURFACE_ACC3,          /* Catmull–Clark approximation, bicubic, C0 at extraordinary vertices */
    Q2N_SURFACE_ACC_G1         /* Catmull–Clark approximation, bicubic + biquintic, G1 everywhere */
} q2n_surface_method;

/* Spline class D<g>C<k>P<m>S<w> of the augmented surface's section curves. */
typedef enum q2n_class {
    Q2N_CLASS_DEFAULT = 0,     /* D5C2P4S6 */
    Q2N_CLASS_D5C2P4S6,        /* quintic, C2, reproduces quartics, support 6 */
    Q2N_CLASS_D5C2P2S4,        /* quintic, C2, support 4 */
    Q2N_CLASS_D3C1P2S4,        /* cubic, C1 (Catmull–Rom) */
    Q2N_CLASS_D2C1P2S4,        /* quadratic pieces, C1 */
    Q2N_CLASS_D3C2P2S4         /* cubic, C2 */
} q2n_class;

/* Edge parameter intervals of the augmented surface. */
typedef enum q2n_param_method {
    Q2N_PARAM_CENTRIPETAL = 0, /* |edge|^alpha, alpha = 1/2 unless given */
    Q2N_PARAM_CHORDAL,         /* alpha = 1 */
    Q2N_PARAM_UNIFORM,         /* alpha = 0 */
    Q2N_PARAM_MEAN             /* ribbon average of |edge|^alpha */
} q2n_param_method;

/* Patches at extraordinary vertices (augmented surface). */
typedef enum q2n_ev_patch_kind {
    Q2N_EV_PATCH_DEFAULT = 0,  /* G2 for C2 classes, G1 for C1 classes */
    Q2N_EV_PATCH_G1,           /* bicubically blended */
    Q2N_EV_PATCH_G2            /* biquintically blended */
} q2n_ev_patch_kind;

/* How the extraordinary regions are built (augmented surface). */
typedef enum q2n_ev_method {
    Q2N_EV_METHOD_DEFAULT = 0, /* the fair construction */
    Q2N_EV_METHOD_FAIR,        /* one jet per vertex, bending-energy solve (docs/extraordinary.md) */
    Q2N_EV_METHOD_PAPER        /* the paper's Coons–Gregory patches */
} q2n_ev_method;

/* How the fair construction glues its patches along the edges at extraordinary vertices
 * (q2n_options.ev_smooth_gluing; docs/extraordinary.md, "Polynomial gluing of G1 patches", "... of G2
 * patches", "The gluing chosen per region"). */
typedef enum q2n_ev_gluing {
    Q2N_EV_GLUING_AUTO = 0,       /* polynomials wherever the corner equations hold; each region of G2
                                     patches keeps the smoothsteps where they ripple less and bend no more */
    Q2N_EV_GLUING_SMOOTHSTEP = 1, /* smoothsteps on every edge (least squares in the fit) */
    Q2N_EV_GLUING_POLYNOMIAL = 2  /* polynomials wherever the corner equations hold, without the choice */
} q2n_ev_gluing;

/* Masks of the acc-g1 surface: circulant (CS) or direct (NCS) system, symmetric (S) or
 * asymmetric (AS) masks. */
typedef enum q2n_acc_strategy {
    Q2N_ACC_CS_S = 0, Q2N_ACC_NCS_S = 1, Q2N_ACC_CS_AS = 2, Q2N_ACC_NCS_AS = 3
} q2n_acc_strategy;

/* Unit the CAD files declare for the model units. */
typedef enum q2n_units {
    Q2N_UNITS_MM = 0, Q2N_UNITS_IN = 1, Q2N_UNITS_CM, Q2N_UNITS_M, Q2N_UNITS_FT, Q2N_UNITS_COUNT
} q2n_units;

/* Output formats (by extension: .obj, .step/.stp, .igs/.iges, .json). */
typedef enum q2n_format {
    Q2N_FORMAT_NONE = 0, Q2N_FORMAT_OBJ, Q2N_FORMAT_STEP, Q2N_FORMAT_IGES, Q2N_FORMAT_JSON
} q2n_format;

/* Continuity the fit imposes across edges. */
typedef enum q2n_continuity {
    Q2N_CONTINUITY_DEFAULT = 0, /* the construction's (G2 for C2 classes with G2 patches, else G1) */
    Q2N_CONTINUITY_G1 = 1,
    Q2N_CONTINUITY_G2 = 2
} q2n_continuity;

/* Solver of the fit's least-squares problems (same result). */
typedef enum q2n_solver { Q2N_SOLVER_CERES = 0, Q2N_SOLVER_DIRECT } q2n_solver;

/* How the fit imposes G1/G2 across edges. */
typedef enum q2n_gluing {
    Q2N_GLUING_EXACT = 0,      /* equality constraints wherever the construction allows */
    Q2N_GLUING_LEAST_SQUARES   /* least squares everywhere (fewer spans on uneven meshes) */
} q2n_gluing;

/* The string forms of the enums above (the command line's option values), for parsing. */
typedef enum q2n_choice {
    Q2N_CHOICE_SURFACE = 0,     /* q2n_surface_method: augmented, acc3, acc-g1 */
    Q2N_CHOICE_CLASS,           /* q2n_class: D5C2P4S6, ... (any case) */
    Q2N_CHOICE_PARAM,           /* q2n_param_method: centripetal, chordal, uniform, mean */
    Q2N_CHOICE_EV_PATCH,        /* q2n_ev_patch_kind: g1, g2 */
    Q2N_CHOICE_EV_CONSTRUCTION, /* q2n_ev_method: fair, paper */
    Q2N_CHOICE_ACC_STRATEGY,    /* q2n_acc_strategy: cs-s, ncs-s, cs-as, ncs-as */
    Q2N_CHOICE_UNITS,           /* q2n_units: mm, cm, m, in, ft (also inch, foot, feet) */
    Q2N_CHOICE_FORMAT,          /* q2n_format: obj, step, iges, json (also stp, igs) */
    Q2N_CHOICE_CONTINUITY,      /* q2n_continuity: g1, g2 */
    Q2N_CHOICE_SOLVER,          /* q2n_solver: ceres, direct */
    Q2N_CHOICE_GLUING,          /* q2n_gluing: exact, least-squares */
    Q2N_CHOICE_COUNT
} q2n_choice;

/* The value (an enum above, as int) that s names: Q2N_OK, or Q2N_ERR_ARG (*value unchanged). */
q2n_status q2n_parse_choice(q2n_choice what, const char *s, int *value);
/* The canonical name of a value ("acc-g1"; "default" for a DEFAULT value), NULL out of range. */
const char *q2n_choice_name(q2n_choice what, int value);
/* The accepted names for messages: "augmented, acc3 or acc-g1" (static text). */
const char *q2n_choice_list(q2n_choice what);

/* ------------------------------------------------------------------ options */

typedef struct q2n_model q2n_model;

/* Progress of the long stages, reported through q2n_options.progress; the library never prints.
 * Called on the thread that called the library, at coarse points (a stage or fit round begins,
 * every few hundred patches), so it may print, but should throttle what it shows. */
typedef struct q2n_progress {
    const char *stage;   /* "read", "subdivide", "build", "fit", "write" */
    const char *detail;  /* what within the stage ("round 2: G1 rows", an output name), or "" */
    long done, total;    /* items of the stage done so far and in all; total 0: not known */
    double elapsed_s;    /* seconds since the run began (q2n_open / q2n_read) */
} q2n_progress;
typedef void (*q2n_progress_fn)(void *user, const q2n_progress *p);

/* Options the caller gave explicitly (q2n_options.given), so that q2n_plan can warn about those
 * the chosen path ignores ("--alpha is ignored with --param uniform"). */
enum {
    Q2N_GIVEN_CLASS = 1 << 0, Q2N_GIVEN_PARAM = 1 << 1, Q2N_GIVEN_ALPHA = 1 << 2, Q2N_GIVEN_EV_PATCH = 1 << 3,
    Q2N_GIVEN_ACC_STRATEGY = 1 << 4, Q2N_GIVEN_CONTINUITY = 1 << 5, Q2N_GIVEN_SOLVER = 1 << 6,
    Q2N_GIVEN_TOL = 1 << 7, Q2N_GIVEN_ANGLE_TOL = 1 << 8, Q2N_GIVEN_CURVATURE_TOL = 1 << 9,
    Q2N_GIVEN_TESS = 1 << 10, Q2N_GIVEN_GRID = 1 << 11, Q2N_GIVEN_THREADS = 1 << 12, Q2N_GIVEN_UNITS = 1 << 13
};

/* Accepted relative fit tolerances (tol, and tol_abs / bounding-box diagonal): below 1e-12
 * rounding dominates, above 0.1 the "fit" no longer resembles the surface. */
#define Q2N_TOL_MIN 1e-12
#define Q2N_TOL_MAX 0.1

/* Accepted --scale factors: beyond these a model's coordinates leave the range in which the
 * writers' 17 significant digits and the CAD importers' tolerances are meaningful. */
#define Q2N_SCALE_MIN 1e-12
#define Q2N_SCALE_MAX 1e12

/* Zeroed fields mean defaults (in brackets).  The command line's options of the same names. */
typedef struct q2n_options {
    q2n_surface_method surface;    /* [augmented] */
    q2n_class spline_class;        /* augmented [D5C2P4S6] */
    q2n_param_method param;        /* augmented [centripetal] */
    double alpha;                  /* exponent of centripetal / mean, (0, 2]; 0: [0.5] */
    q2n_ev_patch_kind ev_patch;    /* augmented [G2 for C2 classes, else G1; unless continuity is G2,
                                      G1 where the G2 patches fold over and G1 ones fold on fewer
                                      faces (a warning, and the report's g2_folded_faces)] */
    q2n_ev_method ev_construction; /* augmented [fair] */
    int keep_flat;                 /* augmented, fair construction: where the mesh is flat around a vertex
                                      (every corner of its faces in one plane) the surface stays in that
                                      plane exactly: 1 yes, 0 [no] (docs/extraordinary.md, "Flat fans") */
    int ev_smooth_gluing;          /* augmented, fair construction: a q2n_ev_gluing.  1 glues every
                                      constructed edge by smoothsteps (G1 patches as before stop 41, G2
                                      patches as before stop 54: least squares in the fit); 2 by
                                      polynomials wherever their corner equations hold (G1 patches are
                                      then bi-quintic polynomials, fitted with one span and exactly G1;
                                      G2 patches ripple less and fit with fewer spans); 0 [the same, and
                                      each region of G2 patches keeps the smoothsteps where it ripples
                                      less and bends no more with them] (docs/extraordinary.md,
                                      "Polynomial gluing of G1 patches", "... of G2 patches", "The gluing
                                      chosen per region") */
    int frame;                     /* augmented: where a mesh with extraordinary vertices has its faces
                                      stretched on the whole (a model scaled along an axis), the surface
                                      is also built in the mesh's isotropic frame and mapped back (or
                                      only its extraordinary regions, against the mesh's own regular
                                      patches, or with only their vertex charts measured there),
                                      and the build kept that ripples less without more bending energy
                                      or folds: 0 [auto], -1 never (--frame off; docs/extraordinary.md,
                                      "The isotropic frame") */
    q2n_acc_strategy acc_strategy; /* acc-g1 [cs-s] */
    int subdivide;                 /* Catmull–Clark steps before building, 0..6 [0] */
    int limit_points;              /* every vertex (after subdivide) moved to its Catmull–Clark limit
                                      position first, so the augmented surface interpolates points of the
                                      subdivision surface instead of the control vertices: 1 always, -1
                                      never, 0 [when subdivide > 0]; needs quads around every interior
                                      vertex */
    int pair_triangles;            /* triangles paired into quads across their shared edges before
                                      anything else (convex pairs, best shaped first; docs/mesh.md,
                                      "Pairing triangles"): 1 yes, 0 [no]; triangles left need subdivide */
    int fill_ngons;                /* polygons of n >= 6 sides, n even, filled with quads (a ring and a
                                      grid, no vertex of high valence), odd ones of 5 or more sides in
                                      pairs made even along a strip of quads, after pairing, before
                                      subdivide (docs/mesh.md, "Filling n-gons"): 1 yes, 0 [no] */
    double scale;                  /* multiplies the mesh coordinates, Q2N_SCALE_MIN..Q2N_SCALE_MAX [1] */
    q2n_units units;               /* unit of the CAD files [mm] */
    double tol;                    /* fit tolerance relative to the bounding-box diagonal, 1e-12..0.1 [1e-5] */
    double tol_abs;                /* fit tolerance in model units; > 0 replaces tol */
    double angle_tol_deg;          /* G1 target: normal-angle jump across edges, degrees [0.01 at
                                      tol <= 1e-5, x tol / 1e-5 above, at most 0.5] */
    double curvature_tol;          /* G2 target: curvature jump relative to the curvature [0.01 at
                                      tol <= 1e-5, x tol / 1e-5 above, at most 0.1] */
    q2n_continuity continuity;     /* what the fit imposes [the construction's] */
    int max_spans;                 /* knot spans per patch direction, 1..1024 [64] */
    q2n_gluing gluing;             /* [exact] */
    q2n_solver solver;             /* [ceres] */
    int threads;                   /* threads of the construction, the fit and the STEP/IGES writers [1]; results do not depend on it */
    int tess;                      /* .obj tessellation points per patch side, >= 2 [9] */
    q2n_format format;             /* format of outputs whose name has no known extension, such as
                                      "-" (standard output) [none: refused] */
    double max_memory;             /* bytes: refuse work estimated above it [half the physical
                                      memory]; < 0: no limit */
    unsigned given;                /* Q2N_GIVEN_* bits: options set explicitly (for warnings) */
    q2n_progress_fn progress;      /* NULL: no progress reports */
    void *progress_user;           /* passed to progress */
} q2n_options;

/* ------------------------------------------------------------------ models */

/* Read a mesh file and build the surface (q2n_read, the memory check of q2n_check_plan without
 * outputs, q2n_build).  opt may be NULL (defaults); it is copied.  *out is freed with q2n_close. */
q2n_status q2n_open(const char *mesh_path, const q2n_options *opt, q2n_model **out, char *errbuf, size_t errlen);

/* The same from arrays in memory (borrowed; copied): nv vertices, positions[3*i .. 3*i+2] those
 * of vertex i; nf faces, face k with face_sizes[k] corners (face_sizes NULL: 4 each, a quad
 * mesh), their vertex indices (0-based, counter-clockwise seen from outside) one face after the
 * other in face_verts.  The arrays are validated as files are (indices in range, finite
 * coordinates, no repeated or degenerate corners, a manifold, consistently oriented mesh), and
 * messages name the element ("mesh: face 3 vertex index 9 out of range (8 vertices)").  The same
 * mesh gives the same surface, fit and files (to the byte) as from an OBJ file. */
q2n_status q2n_open_mesh(size_t nv, const double *positions, size_t nf, const int *face_sizes, const int *face_verts,
                         const q2n_options *opt, q2n_model **out, char *errbuf, size_t errlen);

/* The two halves of q2n_open / q2n_open_mesh, so that a caller can plan (q2n_check_plan: warnings,
 * resource estimate) between the read and the slow construction.  Before q2n_build a model
 * answers only q2n_get_info, q2n_check_plan and q2n_close. */
q2n_status q2n_read(const char *mesh_path, const q2n_options *opt, q2n_model **out, char *errbuf, size_t errlen);
q2n_status q2n_read_mesh(size_t nv, const double *positions, size_t nf, const int *face_sizes, const int *face_verts,
                         const q2n_options *opt, q2n_model **out, char *errbuf, size_t errlen);
/* Pair triangles and subdivide if asked, build the surface and check it (every value finite; folds are warnings),
 * then resolve tol_abs against the bounding box.  Errors name the face and its line. */
q2n_status q2n_build(q2n_model *m, char *errbuf, size_t errlen);

/* Number of patches (= faces of the mesh the surface is built on). */
int q2n_patch_count(const q2n_model *m);
/* 1 if patch k exists and is covered by a construction, else 0. */
int q2n_patch_covered(const q2n_model *m, int k);
/* S, Su, Sv (9 doubles, model units) of patch k at (u,v) in [0,1]^2 — the construction, not the fit. */
q2n_status q2n_patch_eval(const q2n_model *m, int k, double u, double v, double out[9]);

/* Output by extension (.obj tessellation, .step/.stp, .igs/.iges, .json fit report); the three
 * last fit first when the model is not fitted yet.  Written atomically and durably (no partial
 * file on failure; an existing file keeps its mode). */
q2n_status q2n_write(q2n_model *m, const char *path, char *errbuf, size_t errlen);
/* Several outputs, all or nothing: every one is written to a temporary next to it and they are
 * renamed only when all succeeded.  The same file twice, or the input mesh, is refused. */
q2n_status q2n_write_all(q2n_model *m, const char *const *paths, int n, char *errbuf, size_t errlen);
/* ------------------------------------------------------------------ the fitted B-splines */

/* Fit the surface into B-spline patches (or convert the Catmull–Clark path's polynomial patches
 * exactly), unless m is fitted already; q2n_write_all does it when an output needs it.  Fails
 * with Q2N_ERR_GEOMETRY (the worst face named; first a mesh edge shorter than the tolerance, when
 * there is one: its face is nearly degenerate) when the tolerance cannot be met within max_spans;
 * continuity targets that cannot be met are not an error (q2n_report: g1_met, g2_met, note).  On
 * failure m has no fit. */
q2n_status q2n_fit(q2n_model *m, char *errbuf, size_t errlen);

/* Patch k of the fit: a clamped tensor-product B-spline on [0,1]^2 in model units, exactly the
 * B_SPLINE_SURFACE_WITH_KNOTS of STEP face k and the IGES entity 128 of patch k (knots listed
 * with their multiplicities).  The arrays belong to m and stay valid until the next fit or
 * q2n_close.  Q2N_ERR_ARG when m is not fitted or k is out of range. */
typedef struct q2n_patch_spline {
    int deg_u, deg_v;          /* degrees (5 and 5) */
    int ncp_u, ncp_v;          /* control points per direction */
    const double *knots_u;     /* ncp_u + deg_u + 1 knots, from 0 to 1 */
    const double *knots_v;     /* ncp_v + deg_v + 1 */
    const double *cp;          /* 3 * ncp_u * ncp_v, u fastest: point (i, j) at cp + 3 * (j * ncp_u + i) */
    const double *weights;     /* ncp_u * ncp_v, or NULL: polynomial (non-rational) */
} q2n_patch_spline;
q2n_status q2n_patch_spline_get(const q2n_model *m, int k, q2n_patch_spline *out);

/* What a model is and, after the fit, how good the fit is: the figures of the .json report.
 * Lengths in model units; *_rel figures relative to the bounding-box diagonal, except
 * g2_max_rel (relative to the local curvature). */
typedef struct q2n_report {
    /* the mesh and the construction (after q2n_read / q2n_build) */
    int input_faces;           /* faces as read */
    int faces;                 /* faces the surface is built on (after pairing, filling and subdivision) */
    int paired_quads;          /* pair_triangles: quads made of two input triangles */
    int triangles_left;        /* pair_triangles: input triangles left unpaired */
    int filled_faces;          /* fill_ngons: faces filled with quads */
    int fill_quads;            /* fill_ngons: quads made for them */
    int patches;               /* faces covered by a patch (= faces unless uncovered) */
    int construction_continuity; /* 0, 1, 2: G^k across edges the construction guarantees */
    double diag;               /* bounding-box diagonal */
    double t_read, t_build, t_fit, t_write;  /* seconds */
    /* the fit (fitted = 1 after q2n_fit or a write that needed it) */
    int fitted;
    int exact;                 /* 1: the patches were polynomial and converted exactly */
    int continuity;            /* 1 or 2: what the fit imposed */
    double tol, tol_abs;       /* the deviation target, relative and in model units */
    double g1_tol_deg, g2_tol_rel; /* the continuity targets */
    double max_dev, max_dev_rel, rms_dev_rel; /* fit vs construction, at check points */
    double vertex_dev_max_rel; /* construction's patch corners vs mesh vertices */
    double g0_max, g0_max_rel; /* largest gap across an interior edge */
    double g1_max_deg;         /* largest normal-angle jump across an interior edge */
    double g2_max_rel;         /* largest normal-curvature jump / local curvature (G2 fits) */
    int dev_met, g1_met, g2_met, tol_met; /* targets met (tol_met: all three) */
    char note[240];            /* which edge missed a continuity target, or "" */
    int rounds;                /* refinement rounds */
    int g1_exact_edges, g1_ls_edges; /* interior edges glued by constraints / by least squares */
    int g1_rounding_edges;     /* interior edges whose measured normal jump is at most 1e-6 degrees:
                                  exactly G1 up to rounding, whether by constraints or because both
                                  sides reproduce polynomial patches exactly */
    int spans_min, spans_median, spans_max; /* knot spans per patch */
    int cp_min, cp_median, cp_max;          /* control points per patch */
    long cp_total;
    long step_bytes, iges_bytes; /* sizes of the CAD files written from this fit (0: none yet) */
    q2n_units units;           /* the unit the CAD files declare */
    double unit_mm;            /* millimetres per model unit (1, 25.4, 10, 1000, 304.8) */
    char construction_note[256]; /* what the construction did by itself (e.g. Catmull–Clark steps
                                    of the ACC path on a mesh with triangles), or "" */
    int rim_vertices;          /* the fit: boundary vertices where boundary edges of two faces meet */
    double rim_max_deg;        /* there: the largest angle between the two faces' boundary tangents
                                  (how far the open edge turns; 0 where it runs on smoothly, as the
                                  augmented surface draws it), on the fitted patches */
    double rim_curvature_jump_rel; /* there: the largest jump of the boundary curves' curvature vector over
                                  the larger one (at least 1/diag): 0 up to rounding in G2 mode */
} q2n_report;
q2n_status q2n_get_report(const q2n_model *m, q2n_report *out);

/* The model's warnings so far, in order (i from 0; NULL past the last): OBJ tags ignored (read),
 * options the chosen path ignores (q2n_check_plan), faces whose surface folds over and faces left
 * uncovered (build), continuity targets not met (fit).  Valid until q2n_close. */
const char *q2n_warning(const q2n_model *m, int i);

/* The construction at an n x n grid of every covered patch, one line per point to f:
 * "k u v x y z xu yu zu xv yv zv" (%.17g).  Q2N_ERR_IO when f reports a write error (errno
 * tells which, e.g. EPIPE). */
q2n_status q2n_write_samples(const q2n_model *m, int n, FILE *f, char *errbuf, size_t errlen);

/* ------------------------------------------------------------------ outputs as a transaction */

/* What q2n_write_all does, in steps, for a caller that wants to check the outputs before the slow
 * work (an unwritable directory fails in milliseconds) and to remove temporaries on a signal:
 * q2n_outputs_open checks the set (known formats, fallback for names without a known extension
 * such as "-" = standard output; no file twice; none is the input mesh `input`, which may be
 * NULL) and creates one temporary per output next to it; q2n_outputs_write writes them (fitting
 * first if needed; CAD files before the report, which gives their sizes); q2n_outputs_commit
 * syncs all, then renames them over their targets; q2n_outputs_abort removes the temporaries.
 * Commit and abort free the set (abort(NULL) does nothing); on any failure nothing is left
 * behind.  Errors: Q2N_ERR_ARG for a set that makes no sense, Q2N_ERR_IO ("PATH: REASON"). */
typedef struct q2n_outputs q2n_outputs;
q2n_status q2n_outputs_open(const char *const *paths, int n, q2n_format fallback, const char *input, q2n_outputs **out,
                            char *errbuf, size_t errlen);
int q2n_outputs_count(const q2n_outputs *o);
q2n_format q2n_outputs_format(const q2n_outputs *o, int i);
/* The temporary of output i (NULL for a stream): for a signal handler to unlink (the string stays
 * valid until commit or abort). */
const char *q2n_outputs_temp_path(const q2n_outputs *o, int i);
q2n_status q2n_outputs_write(q2n_model *m, q2n_outputs *o, char *errbuf, size_t errlen);
q2n_status q2n_outputs_commit(q2n_outputs *o, char *errbuf, size_t errlen);
void q2n_outputs_abort(q2n_outputs *o);

/* Plan a run of a read model (before q2n_build): adds warnings about options the chosen path
 * ignores (from q2n_options.given) and checks the estimated peak memory against max_memory
 * (Q2N_ERR_ARG with both figures) and each output's estimated size against the free space of its
 * file system (Q2N_ERR_IO).  outs may be NULL (no outputs); sample_grid > 0: q2n_write_samples
 * with that grid will run. */
q2n_status q2n_check_plan(q2n_model *m, const q2n_outputs *outs, int sample_grid, char *errbuf, size_t errlen);

/* Frees everything of m (NULL: nothing). */
void q2n_close(q2n_model *m);

#ifdef __cplusplus
}
#endif

#endif
