/* export_internal.h — what the IGES and STEP writers share (not public): a growable text buffer,
 * the exchange-format real formatter, atomic file output, and the B-rep topology both formats
 * write (one edge curve per mesh edge taken from a patch boundary, one vertex per mesh vertex,
 * connected components and whether each is closed). */
#ifndef Q2N_IGES_EXPORT_INTERNAL_H
#define Q2N_IGES_EXPORT_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "iges/export.h"
#include "patch/surface.h"

/* ---- text buffer: appends never fail visibly; `oom` is checked once at the end.  With fp set
 * the text goes straight to that stream instead (len still counts it; a write error stays in the
 * stream's error flag) ---- */
typedef struct q2n_strbuf {
    char *data;
    size_t len, cap;
    int oom;
    FILE *fp;
} q2n_strbuf;

void q2n_strbuf_putn(q2n_strbuf *b, const char *s, size_t n);
void q2n_strbuf_puts(q2n_strbuf *b, const char *s);
void q2n_strbuf_putc(q2n_strbuf *b, char c);
void q2n_strbuf_printf(q2n_strbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void q2n_strbuf_free(q2n_strbuf *b);

/* A real as %.17g (round-trips exactly), made valid for IGES and STEP: always a '.', exponent 'E'
 * (e.g. 1 -> "1.", 2^-17 -> "7.62939453125E-06", -0.25 -> "-0.25").  Independent of the C locale. */
#define Q2N_REAL_CHARS 40
void q2n_export_fmt_real(char out[Q2N_REAL_CHARS], double x);

/* x as printf("%*d", width, x) into out (no terminating NUL); returns the length (at most 11 or
 * width characters).  The writers format millions of integers for a large model: printf's format
 * parsing was a tenth of their time. */
int q2n_export_fmt_int(char *out, int x, int width);

/* Items 0 .. n-1 of a writer (faces, edges, entities) formatted on `threads` workers
 * (core/par.h), a chunk of them at a time: fmt(ctx, k, b) writes item k's text into a buffer of
 * its own, in the thread's "C" numeric locale; then, on the calling thread and in item order,
 * put(ctx, k, b) appends it to the file (nonzero: stop).  The text is the one a single thread
 * writes as long as fmt writes only item k's own data.  Progress "write"/what is emitted every
 * Q2N_EXPORT_PROGRESS_EVERY items when what is not NULL.  Returns 0, or 1 when a buffer ran out of
 * memory or put stopped (nothing after that item is put). */
int q2n_export_items(int n, int threads, void *ctx, void (*fmt)(void *ctx, int k, q2n_strbuf *b),
                     int (*put)(void *ctx, int k, const q2n_strbuf *b), const q2n_progress_sink *progress,
                     const char *what);

/* Run the writers' number formatting in the "C" numeric locale of this thread only (uselocale;
 * no global state): begin returns the previous locale for end, which restores it. */
typedef struct q2n_export_locale { void *c, *old; } q2n_export_locale;
q2n_export_locale q2n_export_locale_begin(void);
void q2n_export_locale_end(q2n_export_locale l);


/* Validate strings from the options (printable ASCII, <= 64 chars); NULL is fine. */
q2n_status q2n_export_check_string(const char *s, const char *what, q2n_error *err);

/* ---- B-rep topology shared by both writers ---- */
typedef struct q2n_export_curve {
    int deg, ncp;
    double *knots;   /* ncp + deg + 1 */
    double *cp;      /* 3 * ncp */
    double *weights; /* ncp or NULL */
} q2n_export_curve;

typedef struct q2n_export_topo {
    int nv, ne, nf;
    double *vpos;          /* 3*nv: vertex positions (patch corners) */
    int *vused;            /* nv: 1 when a face uses the vertex */
    q2n_export_curve *edge_curve; /* ne: edge e's curve, parameter 0 at edge_v[2e], 1 at edge_v[2e+1] */
    int *edge_v;           /* 2*ne */
    int *he_sense;         /* nh: 1 when half-edge h runs along its edge curve's direction */
    int *face_comp;        /* nf: connected component of each face */
    int ncomp;
    int *comp_closed;      /* ncomp: 1 when the component has no boundary edge */
    int *comp_inward;      /* ncomp: 1 for a closed component whose faces point inwards (negative
                              enclosed volume): its CAD faces are written reversed */
    int all_closed;        /* every component closed (=> solids) */
    double max_coord;      /* largest |coordinate| of any control point (IGES global field 20) */
    double resolution;     /* tol_abs, or 1e-9 * bbox diagonal when tol_abs <= 0 */
} q2n_export_topo;

/* Checks the model (n == nf, all quads, every patch passes q2n_bspline_check, the two patches of
 * each interior edge agree along it within the resolution, shared corners agree) and builds the
 * topology.  Errors name the face / edge. */
q2n_status q2n_export_topo_build(const q2n_nurbs_model *m, q2n_export_topo *t, q2n_error *err);

/* A format's text builder, and the driver both writers share: option checks, topology, C locale,
 * then the text into *out (q2n_export_text), into a stream (q2n_export_to_stream) or atomically
 * into path (q2n_export_write).  A builder appends to *out, which arrives empty or with fp set. */
typedef q2n_status (*q2n_export_build_fn)(const q2n_nurbs_model *m, const q2n_export_topo *t,
                                          const q2n_export_options *opt, const char *name, q2n_strbuf *out);
q2n_status q2n_export_text(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                           const q2n_export_options *opts, char **text, size_t *len, q2n_error *err);
q2n_status q2n_export_to_stream(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                                const q2n_export_options *opts, const char *path, FILE *f, q2n_error *err);
q2n_status q2n_export_write(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                            const q2n_export_options *opts, const char *path, q2n_error *err);
/* The builders' shared pieces: the file's creation time in IGES ("YYYYMMDD.HHNNSS") or ISO 8601
 * form into out (empty when the options give none), the unit's IGES flag and name. */
void q2n_export_date(const q2n_export_options *opt, int iges, char out[32]);
int q2n_units_iges_flag(q2n_units u);
const char *q2n_units_iges_name(q2n_units u);
/* q2n_export_stream's STEP half (step_writer.c). */
q2n_status q2n_export_step_stream(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                                  FILE *f, q2n_error *err);
/* Progress every this many faces of a writer */
#define Q2N_EXPORT_PROGRESS_EVERY 1024
void q2n_export_topo_free(q2n_export_topo *t);

/* Boundary curve of patch k along side i (0: v=0, 1: u=1, 2: v=1, 3: u=0), in the patch's own
 * parameter direction (u or v increasing).  Arrays malloc'ed into c. */
q2n_status q2n_export_side_curve(const q2n_bspline_surface *s, int side, q2n_export_curve *c);
void q2n_export_curve_free(q2n_export_curve *c);

/* Distinct knots and multiplicities of a knot vector (STEP's form): returns the count; kn, mult
 * hold at least n entries. */
int q2n_export_knot_mults(const double *knots, int n, double *kn, int *mult);

#endif
