/* quad2nurbs.h — the public C API of libquad2nurbs (small and stable; the module headers under
 * src/ are internal).
 *
 *   q2n_model *m;  char err[512];
 *   q2n_options o = {0};                      // zeroed = defaults
 *   if (q2n_open("mesh.obj", &o, &m, err, sizeof err)) { puts(err); return 2; }
 *   double p[9];  q2n_patch_eval(m, 0, 0.5, 0.5, p);   // S, Su, Sv of patch 0 (face 0)
 *   q2n_write(m, "mesh.step", err, sizeof err);          // fits into B-splines when needed
 *   q2n_close(m);
 *
 * Patch k is built on face k of the mesh (after --subdivide-like steps when requested or when
 * the ACC path needs them); its domain is [0,1]^2 with u along the face's first edge v0->v1 and
 * v along v0->v3.  Link with: -lquad2nurbs -lceres -lglog -lgflags -lstdc++ -lpthread -lm. */
#ifndef QUAD2NURBS_H
#define QUAD2NURBS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define QUAD2NURBS_VERSION "0.1.0"

typedef struct q2n_model q2n_model;

/* Zeroed fields mean defaults (in brackets). */
typedef struct q2n_options {
    const char *surface;      /* "augmented" | "acc3" | "acc-g1"  ["augmented"] */
    const char *spline_class; /* augmented: "D5C2P4S6", "D5C2P2S4", "D3C1P2S4", ...  ["D5C2P4S6"] */
    const char *param;        /* "centripetal" | "chordal" | "uniform" | "mean"  ["centripetal"] */
    double alpha;             /* exponent for centripetal/mean; <= 0 means 0.5 */
    int subdivide;            /* Catmull–Clark steps before building [0] */
    const char *acc_strategy; /* acc-g1: "cs-s" | "ncs-s" | "cs-as" | "ncs-as"  ["cs-s"] */
    double tol;               /* fit tolerance relative to the bbox diagonal [1e-5] */
    int threads;              /* fit threads [1] */
    const char *units;        /* "mm" | "in" for CAD files ["mm"] */
} q2n_options;

/* All functions returning int return 0 on success, else a non-zero error code, with a one-line
 * message in errbuf (which may be NULL). */
int q2n_open(const char *obj_path, const q2n_options *opt, q2n_model **out, char *errbuf, size_t errlen);
int q2n_patch_count(const q2n_model *m);
/* 1 if patch k exists (is covered by a construction), else 0. */
int q2n_patch_covered(const q2n_model *m, int k);
/* S, Su, Sv (9 doubles) of patch k at (u,v). */
int q2n_patch_eval(const q2n_model *m, int k, double u, double v, double out[9]);
/* Output by extension: .obj tessellation, .step/.stp, .igs/.iges, .json fit report; written
 * atomically (no partial file on failure). */
int q2n_write(q2n_model *m, const char *path, char *errbuf, size_t errlen);
void q2n_close(q2n_model *m);
const char *q2n_version(void);

#ifdef __cplusplus
}
#endif

#endif
