/* outfile.c — see outfile.h. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "core/outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TMP_PATTERN ".q2n-XXXXXX"

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* The directory part of path ("." when there is none), malloc'ed. */
static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return dup_str(".");
    size_t n = slash == path ? 1 : (size_t)(slash - path);
    char *d = malloc(n + 1);
    if (d) { memcpy(d, path, n); d[n] = '\0'; }
    return d;
}

/* The process umask without changing it (umask(2) would, for a moment, for every thread):
 * Linux reports it in /proc/self/status; 022 when it cannot be read. */
static mode_t current_umask(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    unsigned m = 022;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "Umask: %o", &m) == 1) break;
    if (f) fclose(f);
    return (mode_t)(m & 0777);
}

static q2n_status fail(q2n_outfile *o, q2n_error *err, const char *path, const char *what, int e)
{
    q2n_status st = q2n_error_set(err, Q2N_ERR_IO, "%s: %s: %s", strcmp(path, "-") ? path : "standard output", what,
                                  strerror(e));
    q2n_outfile_abort(o);
    return st;
}

q2n_status q2n_outfile_open(q2n_outfile *o, const char *path, q2n_error *err)
{
    memset(o, 0, sizeof *o);
    if (!path || !*path) return q2n_error_set(err, Q2N_ERR_ARG, "empty output name");
    if (!(o->path = dup_str(path))) return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", path);
    struct stat st;
    int exists = 0;
    if (strcmp(path, "-") == 0) {
        o->stream = 1;
    } else {
        if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) o->target = realpath(path, NULL); /* dangling: replace the link */
        if (!o->target && !(o->target = dup_str(path))) return fail(o, err, path, "out of memory", ENOMEM);
        if (stat(o->target, &st) == 0) {
            exists = 1;
            if (S_ISDIR(st.st_mode)) return fail(o, err, path, "cannot write", EISDIR);
            if (!S_ISREG(st.st_mode)) {
                o->stream = 1;
                if (access(o->target, W_OK) != 0) return fail(o, err, path, "cannot write", errno);
            }
        }
    }
    if (o->stream) {
        if (!(o->f = tmpfile())) return fail(o, err, path, "cannot create a temporary file", errno);
        return Q2N_OK;
    }
    char *dir = dir_of(o->target);
    size_t n = dir ? strlen(dir) : 0;
    o->tmp = dir ? malloc(n + sizeof "/" TMP_PATTERN) : NULL;
    if (!o->tmp) { free(dir); return fail(o, err, path, "out of memory", ENOMEM); }
    memcpy(o->tmp, dir, n);
    memcpy(o->tmp + n, "/" TMP_PATTERN, sizeof "/" TMP_PATTERN);
    free(dir);
    int fd = mkstemp(o->tmp);
    if (fd < 0) {
        int e = errno;
        free(o->tmp);
        o->tmp = NULL; /* nothing to remove */
        return fail(o, err, path, "cannot create output", e);
    }
    /* mkstemp creates 0600: an existing file keeps its mode, a new one gets what open(2) gives */
    (void)fchmod(fd, exists ? (st.st_mode & 07777) : (0666 & ~current_umask()));
    if (!(o->f = fdopen(fd, "w"))) {
        int e = errno;
        close(fd);
        return fail(o, err, path, "cannot create output", e);
    }
    return Q2N_OK;
}

q2n_status q2n_outfile_finish(q2n_outfile *o, q2n_error *err)
{
    if (o->finished) return Q2N_OK;
    if (!o->f) return q2n_error_set(err, Q2N_ERR_ARG, "output not open");
    int e = 0, saved = errno;
    if (ferror(o->f)) {
        /* a write failed earlier; flushing what is left usually fails the same way, and says why */
        clearerr(o->f);
        e = fflush(o->f) != 0 ? errno : saved ? saved : EIO;
    } else if (fflush(o->f) != 0) {
        e = errno;
    }
    if (!e && !o->stream && fsync(fileno(o->f)) != 0) e = errno;
    if (!o->stream) {
        if (fclose(o->f) != 0 && !e) e = errno;
        o->f = NULL;
    }
    if (e) return fail(o, err, o->path, "write failed", e);
    o->finished = 1;
    return Q2N_OK;
}

/* Copy the staged data to standard output, a device or a FIFO. */
static int copy_out(q2n_outfile *o)
{
    int fd = strcmp(o->path, "-") == 0 ? STDOUT_FILENO : open(o->target, O_WRONLY | O_NOCTTY);
    if (fd < 0) return errno;
    if (fd == STDOUT_FILENO) fflush(stdout);
    int in = fileno(o->f), e = 0;
    char buf[1 << 16];
    if (lseek(in, 0, SEEK_SET) < 0) e = errno;
    while (!e) {
        ssize_t r = read(in, buf, sizeof buf);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) { e = errno; break; }
        if (r == 0) break;
        for (ssize_t w = 0; w < r && !e;) {
            ssize_t k = write(fd, buf + w, (size_t)(r - w));
            if (k < 0 && errno == EINTR) continue;
            if (k < 0) e = errno;
            else w += k;
        }
    }
    if (fd != STDOUT_FILENO && close(fd) != 0 && !e) e = errno;
    return e;
}

/* fsync the directory holding path, so that the rename itself survives a crash.  File systems
 * that cannot sync a directory (EINVAL) have nothing to sync. */
static int sync_dir(const char *path)
{
    char *dir = dir_of(path);
    if (!dir) return ENOMEM;
    int fd = open(dir, O_RDONLY | O_DIRECTORY), e = 0;
    free(dir);
    if (fd < 0) return errno;
    if (fsync(fd) != 0 && errno != EINVAL) e = errno;
    close(fd);
    return e;
}

q2n_status q2n_outfile_commit(q2n_outfile *o, q2n_error *err)
{
    q2n_status st = q2n_outfile_finish(o, err);
    if (st) return st;
    int e;
    if (o->stream) {
        if ((e = copy_out(o))) return fail(o, err, o->path, "write failed", e);
    } else {
        if (rename(o->tmp, o->target) != 0) return fail(o, err, o->path, "cannot replace", errno);
        free(o->tmp);
        o->tmp = NULL; /* renamed: nothing to remove any more */
        if ((e = sync_dir(o->target))) return fail(o, err, o->path, "write failed", e);
    }
    q2n_outfile_abort(o); /* closes the staging file, frees the names */
    return Q2N_OK;
}

void q2n_outfile_abort(q2n_outfile *o)
{
    if (o->f) fclose(o->f);
    if (o->tmp) unlink(o->tmp);
    free(o->tmp);
    free(o->target);
    free(o->path);
    memset(o, 0, sizeof *o);
}

q2n_status q2n_outfile_write_buffer(const char *path, const char *buf, size_t len, q2n_error *err)
{
    q2n_outfile o;
    q2n_status st = q2n_outfile_open(&o, path, err);
    if (st) return st;
    if (len && fwrite(buf, 1, len, o.f) != len) {} /* the error is sticky: finish reports it */
    return q2n_outfile_commit(&o, err);
}
