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
 * Output is deterministic (doubles as %.17g, C locale independent, no clock: a date is written
 * only when the caller gives one), and files are written atomically (core/outfile.h): on any
 * error no file and no temporary is left. */
#ifndef Q2N_IGES_EXPORT_H
#define Q2N_IGES_EXPORT_H

#include <stddef.h>

#include <stdio.h>

#include "core/error.h"
#include "core/progress.h"
#include "fit/bspline.h"

/* Length units of the CAD files (the model's coordinates are in this unit; nothing is scaled
 * here).  STEP: an SI_UNIT with prefix for mm, cm, m; a CONVERSION_BASED_UNIT (25.4 mm, 304.8 mm)
 * for in and ft.  IGES: global fields 14/15 with the flags of IGES 5.3 §2.2.4.3 (1 inch, 2 mm,
 * 4 feet, 6 m, 10 cm). */
/* q2n_units (Q2N_UNITS_*) is the public enum of include/quad2nurbs.h. */

/* "mm", "cm", "m", "in", "ft" (also "inch", "foot", "feet") -> *u; 0 on success, -1 unknown. */
int q2n_units_parse(const char *s, q2n_units *u);
const char *q2n_units_name(q2n_units u);   /* "mm", ... ; "?" when out of range */
double q2n_units_in_mm(q2n_units u);       /* 1, 25.4, 10, 1000, 304.8; 0 when out of range */

/* All-zero means defaults: millimetres, empty author/organisation, no date, IGES B-rep. */
typedef struct q2n_export_options {
    q2n_units units;          /* the unit the model coordinates are in (no scaling is applied) */
    const char *author;       /* <= 64 printable ASCII characters, or NULL */
    const char *organization; /* <= 64 printable ASCII characters, or NULL */
    const char *timestamp;    /* written verbatim as IGES global 18 / STEP time_stamp; overrides date */
    const char *name;         /* product / file name written into the file; NULL: from the path */
    int iges_plain;           /* 1: IGES with only the 128 surfaces (no shared-edge B-rep) */
    int has_date;             /* 1: write `date` as the file's creation time (else none: deterministic) */
    long long date;           /* seconds since 1970-01-01 UTC: IGES global 18 and 25 (YYYYMMDD.HHNNSS),
                                 STEP FILE_NAME time_stamp (ISO 8601, YYYY-MM-DDTHH:MM:SS) */
    const q2n_progress_sink *progress; /* NULL: no reports ("write", one per 1024 faces) */
    double mesh_scale;        /* the patches are in the mesh's coordinates times this (0: 1); only
                                 vertices no face uses are taken from the mesh */
    int threads;              /* the faces' and edges' entities are formatted on this many threads
                                 (0: 1; the bytes do not depend on it) */
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

/* Base name of path without directory and extension, printable ASCII (others '_'), at most 64
 * characters, into out: what names the product when opts->name is NULL. */
void q2n_export_basename(const char *path, char *out, size_t cap);

/* Write IGES (iges = 1) or STEP (iges = 0) to an open stream, e.g. a q2n_outfile: STEP goes out
 * as it is generated (nothing of the size of the file is held in memory), IGES holds its
 * parameter section (the directory before it needs its line numbers).  `path` only names the
 * product when opts->name is NULL.  Write errors stay in f's error flag for the caller's close. */
q2n_status q2n_export_stream(const q2n_nurbs_model *m, const q2n_export_options *opts, int iges,
                             const char *path, FILE *f, q2n_error *err);

/* The same texts into a malloc'ed, NUL-terminated buffer (*text, *len; caller frees *text). */
q2n_status q2n_export_iges_text(const q2n_nurbs_model *m, const q2n_export_options *opts, char **text,
                                size_t *len, q2n_error *err);
q2n_status q2n_export_step_text(const q2n_nurbs_model *m, const q2n_export_options *opts, char **text,
                                size_t *len, q2n_error *err);

#endif
