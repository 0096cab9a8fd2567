/* reader.h — what the OFF and PLY readers share (internal to src/mesh/): growable face/vertex
 * arrays that end in q2n_mesh_from_arrays_lines (the same validation as OBJ), a line cursor over a
 * buffer, whitespace tokens, and numbers read in the "C" locale whatever the process locale. */
#ifndef Q2N_MESH_READER_H
#define Q2N_MESH_READER_H

#include <stddef.h>

#include "mesh/mesh.h"

/* A mesh under construction. */
typedef struct rd_mesh {
    double *pos;
    size_t nv, cap_v;
    int *fstart, *fline, *fvert;
    size_t nf, cap_f, nfv, cap_fv;
} rd_mesh;

/* Append a vertex / a face (n corners at line `line`, 0 if none); 0 on success, -1 out of memory,
 * -2 above the int range of the mesh. */
int q2n_rd_add_vertex(rd_mesh *d, const double x[3]);
int q2n_rd_add_face(rd_mesh *d, const int *idx, int n, long line);
/* Validate and build (index range, then q2n_mesh_from_arrays_lines); frees d's arrays. */
q2n_status q2n_rd_finish(rd_mesh *d, const char *name, q2n_mesh **out, q2n_error *err);
void q2n_rd_free(rd_mesh *d);

/* Lines of a buffer: each next line NUL-terminated in a private copy, CR and (when strip_comments)
 * everything from '#' removed. */
typedef struct rd_lines {
    const char *p, *end;
    long line;               /* number of the line last returned (1-based) */
    char *buf;
    size_t cap;
    int strip_comments;
} rd_lines;
/* 1 and *s = the line, 0 at the end, -1 out of memory, -2 a NUL byte in the line. */
int q2n_rd_next_line(rd_lines *l, char **s);
void q2n_rd_lines_free(rd_lines *l);

/* Next whitespace-separated token of *cur (NUL-terminated in place), NULL at the end. */
char *q2n_rd_tok(char **cur);
/* A whole token as a number: 0, -1 not a number, -2 not finite (NaN, Inf, out of range). */
int q2n_rd_double(const char *t, double *x);
/* A whole token as a decimal integer: 0, -1 not an integer, -2 beyond +-2^31. */
int q2n_rd_int(const char *t, long long *v);
/* A token quoted for a message (shortened to fit buf). */
const char *q2n_rd_quote(const char *t, char *buf, size_t n);

/* Switch this thread's numeric locale to "C" (strtod) and back. */
void *q2n_rd_locale_begin(void **old);
void q2n_rd_locale_end(void *c, void *old);

#endif
