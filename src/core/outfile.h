/* outfile.h — durable, atomic output files.
 *
 * A regular file is written to a temporary with a short name (".q2n-XXXXXX") in the directory of
 * its target, so that names of any legal length work, and only replaces the target on commit:
 * fflush + fsync of the data, rename, fsync of the directory.  A failed or interrupted run never
 * leaves a partial file; an existing file keeps its permission bits (a new one gets 0666 minus
 * the umask); a symbolic link keeps pointing where it pointed and its target is replaced.
 * Standard output ("-"), devices and FIFOs cannot be renamed onto: their data are staged in an
 * anonymous temporary file (which vanishes with the process whatever happens) and copied there on
 * commit.  Opening checks what can be checked early: the directory is writable (the temporary is
 * created), the target is not a directory. */
#ifndef Q2N_CORE_OUTFILE_H
#define Q2N_CORE_OUTFILE_H

#include <stddef.h>
#include <stdio.h>

#include "core/error.h"

typedef struct q2n_outfile {
    FILE *f;        /* write here */
    char *path;     /* the name given (for messages); "-" is standard output */
    char *target;   /* the file replaced: path, or where a symbolic link points */
    char *tmp;      /* the named temporary next to target (regular files), else NULL */
    int stream;     /* 1: standard output, a device or a FIFO (staged, copied on commit) */
    int finished;   /* data flushed and synced (q2n_outfile_finish) */
} q2n_outfile;

/* Check the target and create the temporary; errors (Q2N_ERR_IO) name the path and the reason. */
q2n_status q2n_outfile_open(q2n_outfile *o, const char *path, q2n_error *err);
/* Flush and fsync the data (a full disk shows here): "PATH: write failed: REASON".  Optional
 * before commit; lets a caller with several outputs learn that all data are safe before it
 * replaces any file. */
q2n_status q2n_outfile_finish(q2n_outfile *o, q2n_error *err);
/* Finish, then rename over the target and sync the directory (or copy to the stream).  On any
 * error the temporary is removed and the target left as it was. */
q2n_status q2n_outfile_commit(q2n_outfile *o, q2n_error *err);
/* Discard (close and remove the temporary); safe on a zeroed or committed struct.  Uses only
 * free(), fclose() and unlink(). */
void q2n_outfile_abort(q2n_outfile *o);
/* The whole of buf into path, atomically. */
q2n_status q2n_outfile_write_buffer(const char *path, const char *buf, size_t len, q2n_error *err);

#endif
