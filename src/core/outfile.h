/* outfile.h — atomic output files: data go to PATH.tmp.XXXXXX in the same directory and are
 * renamed over PATH only after a successful close, so a failed run never leaves a partial file. */
#ifndef Q2N_CORE_OUTFILE_H
#define Q2N_CORE_OUTFILE_H

#include <stddef.h>
#include <stdio.h>

#include "core/error.h"

typedef struct q2n_outfile {
    FILE *f;      /* write here */
    char *tmp;    /* temporary name */
    char *path;   /* final name */
} q2n_outfile;

q2n_status q2n_outfile_open(q2n_outfile *o, const char *path, q2n_error *err);
/* Close and rename; on any write error removes the temporary file and reports it. */
q2n_status q2n_outfile_commit(q2n_outfile *o, q2n_error *err);
/* Discard (close and remove the temporary file); safe on a zeroed or committed struct. */
void q2n_outfile_abort(q2n_outfile *o);
/* The whole of buf into path, atomically. */
q2n_status q2n_outfile_write_buffer(const char *path, const char *buf, size_t len, q2n_error *err);

#endif
