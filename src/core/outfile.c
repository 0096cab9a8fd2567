/* outfile.c — see outfile.h. */
#include "core/outfile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

q2n_status q2n_outfile_open(q2n_outfile *o, const char *path, q2n_error *err)
{
    size_t n = strlen(path);
    memset(o, 0, sizeof *o);
    o->tmp = malloc(n + 12);
    o->path = malloc(n + 1);
    if (!o->tmp || !o->path) {
        q2n_outfile_abort(o);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", path);
    }
    memcpy(o->path, path, n + 1);
    memcpy(o->tmp, path, n);
    memcpy(o->tmp + n, ".tmp.XXXXXX", 12);
    int fd = mkstemp(o->tmp);
    if (fd < 0) {
        q2n_status st = q2n_error_set(err, Q2N_ERR_IO, "%s: cannot create output: %s", path, strerror(errno));
        free(o->tmp), o->tmp = NULL;
        q2n_outfile_abort(o);
        return st;
    }
    (void)fchmod(fd, 0644); /* mkstemp creates 0600; outputs are ordinary files */
    o->f = fdopen(fd, "w");
    if (!o->f) {
        close(fd);
        q2n_outfile_abort(o);
        return q2n_error_set(err, Q2N_ERR_IO, "%s: %s", path, strerror(errno));
    }
    return Q2N_OK;
}

q2n_status q2n_outfile_commit(q2n_outfile *o, q2n_error *err)
{
    int bad = ferror(o->f);
    bad |= fclose(o->f) != 0;
    o->f = NULL;
    if (bad || rename(o->tmp, o->path) != 0) {
        q2n_status st = q2n_error_set(err, Q2N_ERR_IO, "%s: write failed: %s", o->path, strerror(errno));
        q2n_outfile_abort(o);
        return st;
    }
    free(o->tmp);
    free(o->path);
    o->tmp = o->path = NULL;
    return Q2N_OK;
}

void q2n_outfile_abort(q2n_outfile *o)
{
    if (o->f) fclose(o->f);
    if (o->tmp) unlink(o->tmp);
    free(o->tmp);
    free(o->path);
    memset(o, 0, sizeof *o);
}

q2n_status q2n_outfile_write_buffer(const char *path, const char *buf, size_t len, q2n_error *err)
{
    q2n_outfile o;
    q2n_status st = q2n_outfile_open(&o, path, err);
    if (st) return st;
    if (len && fwrite(buf, 1, len, o.f) != len) {
        q2n_outfile_abort(&o);
        return q2n_error_set(err, Q2N_ERR_IO, "%s: write failed", path);
    }
    return q2n_outfile_commit(&o, err);
}
