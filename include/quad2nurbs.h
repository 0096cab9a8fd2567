/* quad2nurbs.h — the public C API of libquad2nurbs (small and stable; the module headers under
 * src/ are internal).
 *
 *   q2n_model *m;  char err[512];
 *   q2n_options o = {0};                      // zeroed = defaults
 *   if (q2n_open("mesh.obj", &o, &m, err, sizeof err)) { puts(err); return 2; }
 *   double p[9];  q2n_patch_eval(m, 0, 0.5, 0.5, p);   // S, Su, Sv of patch 0 (face 0)
 *   q2n_write(m, "mesh.step", err, sizeof err);          // fits into B-splines when needed
 *   const char *outs[] = {"part.step", "part.igs"};
 *   q2n_write_all(m, outs, 2, err, sizeof err);          // all or nothing
 *   q2n_close(m);
 *
 * Meshes: Wavefront OBJ, OFF (ASCII) and PLY (ASCII and binary), recognised by extension or by
 * their first line.  Patch k is built on face k of the mesh (after --subdivide-like steps when
 * requested or when the ACC path needs them); its domain is [0,1]^2 with u along the face's first
 * edge v0->v1 and v along v0->v3.  Link with: -lquad2nurbs -lceres -lglog -lgflags -lstdc++
 * -lpthread -lm. */
#ifndef QUAD2NURBS_H
#define QUAD2NURBS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define QUAD2NURBS_VERSION "0.1.0"

typedef struct q2n_model q2n_model;

/* Progress of the long stages, reported through q2n_options.progress; the library never prints.
 * Called on the thread that called q2n_open / q2n_write, at coarse points (a stage or fit round
 * begins, every few hundred patches), so it may print, but should throttle what it shows. */
typedef struct q2n_progress {
    const char *stage;   /* "read", "subdivide", "build", "fit", "write" */
    const char *detail;  /* what within the stage ("round 2: G1 rows", an output name), or "" */
    long done, total;    /* items of the stage done so far and in all; total 0: not known */
    double elapsed_s;    /* seconds since the run began (q2n_open) */
} q2n_progress;
typedef void (*q2n_progress_fn)(void *user, const q2n_progress *p);

/* Zeroed fields mean defaults (in brackets). */
typedef struct q2n_options {
    const char *surface;      /* "augmented" | "acc3" | "acc-g1"  ["augmented"] */
    const char *spline_class; /* augmented: "D5C2P4S6", "D5C2P2S4", "D3C1P2S4", ...  ["D5C2P4S6"] */
    const char *param;        /* "centripetal" | "chordal" | "uniform" | "mean"  ["centripetal"] */
    double alpha;             /* exponent for centripetal/mean; <= 0 means 0.5 */
    int subdivide;            /* Catmull–Clark steps before building [0] */
    const char *acc_strategy; /* acc-g1: "cs-s" | "ncs-s" | "cs-as" | "ncs-as"  ["cs-s"] */
    double tol;               /* fit tolerance relative to the bbox diagonal [1e-5] */
    int threads;              /* threads of the construction and the fit [1]; results do not depend on it */
    const char *units;        /* unit of the CAD files: "mm" | "cm" | "m" | "in" | "ft"  ["mm"] */
    /* --- added in 0.1.0 with the tolerances, units and output options of the command line --- */
    double scale;             /* multiplies the mesh coordinates on input [1] */
    double tol_abs;           /* fit tolerance in model units (after scale); > 0 replaces tol */
    double angle_tol_deg;     /* G1 acceptance: normal-angle jump across edges, degrees [0.01] */
    double curvature_tol;     /* G2 acceptance: curvature jump relative to the curvature [0.01] */
    int tess;                 /* .obj tessellation points per patch side [9] */
    const char *format;       /* format of outputs whose name has no known extension, such as
                                 "-" (standard output): "obj" | "step" | "iges" | "json"  [none] */
    double max_memory;        /* bytes: refuse work estimated above it [half the physical memory];
                                 < 0: no limit */
    q2n_progress_fn progress; /* NULL: no progress reports */
    void *progress_user;      /* passed to progress */
} q2n_options;

/* All functions returning int return 0 on success, else a non-zero error code, with a one-line
 * message in errbuf (which may be NULL). */
int q2n_open(const char *mesh_path, const q2n_options *opt, q2n_model **out, char *errbuf, size_t errlen);
int q2n_patch_count(const q2n_model *m);
/* 1 if patch k exists (is covered by a construction), else 0. */
int q2n_patch_covered(const q2n_model *m, int k);
/* S, Su, Sv (9 doubles) of patch k at (u,v). */
int q2n_patch_eval(const q2n_model *m, int k, double u, double v, double out[9]);
/* Output by extension: .obj tessellation, .step/.stp, .igs/.iges, .json fit report; written
 * atomically and durably (no partial file on failure; an existing file keeps its mode). */
int q2n_write(q2n_model *m, const char *path, char *errbuf, size_t errlen);
/* Several outputs, all or nothing: every one is written to a temporary next to it and they are
 * renamed only when all succeeded.  The same file twice, or the input mesh, is refused. */
int q2n_write_all(q2n_model *m, const char *const *paths, int n, char *errbuf, size_t errlen);
void q2n_close(q2n_model *m);
const char *q2n_version(void);

#ifdef __cplusplus
}
#endif

#endif
