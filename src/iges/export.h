/* export.h — CAD exchange writers (pipeline stage 5): IGES 5.3 and STEP AP214 (ISO 10303-21).
 *
 * Both writers take a q2n_nurbs_model (one clamped B-spline surface per quad face, on [0,1]^2,
 * u along v0->v1, v along v0->v3, watertight: a mesh edge's two patches share one boundary curve)
 * and write one CAD face per mesh face, in face order, untrimmed, four-sided:
 *   STEP: B_SPLINE_SURFACE_WITH_KNOTS (the rational complex form only when weights != NULL) per
 *         patch, ADVANCED_FACEs bounded by EDGE_LOOPs whose ORIENTED_EDGEs share one EDGE_CURVE
 *         (the patch boundary as B_SPLINE_CURVE_WITH_KNOTS) per mesh edge and one VERTEX_POINT per
 *         mesh vertex; one shell per connected component: CLOSED_SHELL -> MANIFOLD_SOLID_BREP ->
 *         ADVANCED_BREP_SHAPE_REPRESENTATION when every component is closed, otherwise OPEN_SHELLs
 *         (and CLOSED_SHELLs) -> SHELL_BASED_SURFACE_MODEL -> MANIFOLD_SURFACE_SHAPE_REPRESENTATION.
 *   IGES: Rational B-Spline Surface entities (128) in patch order; by default followed by the
 *         shared-edge B-rep: 126 edge curves, 502 vertex list, 504 edge list, 508 loops, 510 faces,
 *         514 shells (form 1 closed, 2 open) and 186 solids for closed components; with
 *         iges_plain = 1 only the 128 entities (CAD systems then import unconnected faces).
 * Output is deterministic (doubles as %.17g, C locale independent, no clock), and files are
 * written atomically: PATH.tmp, then rename; on any error no file (and no PATH.tmp) is left. */
#ifndef Q2N_IGES_EXPORT_H
#define Q2N_IGES_EXPORT_H

#include <stddef.h>

#include "core/error.h"
#include "fit/bspline.h"

typedef enum q2n_units { Q2N_UNITS_MM = 0, Q2N_UNITS_IN = 1 } q2n_units;

/* All-zero means defaults: millimetres, empty author/organisation, no timestamp, IGES B-rep. */
typedef struct q2n_export_options {
    q2n_units units;          /* the unit the model coordinates are in (no scaling is applied) */
    const char *author;       /* <= 64 printable ASCII characters, or NULL */
    const char *organization; /* <= 64 printable ASCII characters, or NULL */
    const char *timestamp;    /* "YYYYMMDD.HHNNSS" for IGES / ISO 8601 for STEP, or NULL: omitted */
    const char *name;         /* product / file name written into the file; NULL: from the path */
    int iges_plain;           /* 1: IGES with only the 128 surfaces (no shared-edge B-rep) */
} q2n_export_options;

/* Write an IGES 5.3 / STEP AP214 file (atomic). opts may be NULL (defaults). */
q2n_status q2n_export_iges(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                           q2n_error *err);
q2n_status q2n_export_step(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                           q2n_error *err);

/* Format from the extension (case-insensitive): .igs/.iges -> IGES, .step/.stp -> STEP;
 * anything else is Q2N_ERR_ARG. */
q2n_status q2n_export_file(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                           q2n_error *err);

/* The same texts into a malloc'ed, NUL-terminated buffer (*text, *len; caller frees *text). */
q2n_status q2n_export_iges_text(const q2n_nurbs_model *m, const q2n_export_options *opts, char **text,
                                size_t *len, q2n_error *err);
q2n_status q2n_export_step_text(const q2n_nurbs_model *m, const q2n_export_options *opts, char **text,
                                size_t *len, q2n_error *err);

#endif
