/* mesh_read.c — mesh input in any supported format (OBJ, OFF, PLY): the format from the
 * extension or the first line, and the helpers the OFF and PLY readers share (reader.h). */
#include "mesh/mesh_policy.h"
#include "mesh/reader.h"

#include <errno.h>
#include <limits.h>
#include <locale.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ------------------------------------------------------------------ growable mesh arrays */

static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return 1;
    size_t c = *cap ? *cap : 64;
    while (c < need) {
        if (c > (size_t)-1 / 4 / elem) return 0;
        c *= 2;
    }
    void *q = realloc(*p, c * elem);
    if (!q) return 0;
    *p = q;
    *cap = c;
    return 1;
}

int q2n_rd_add_vertex(rd_mesh *d, const double x[3])
{
    if (d->nv >= Q2N_MESH_MAX_COUNT) return -2;
    if (!grow((void **)&d->pos, &d->cap_v, 3 * (d->nv + 1), sizeof *d->pos)) return -1;
    memcpy(d->pos + 3 * d->nv++, x, 3 * sizeof *x);
    return 0;
}

int q2n_rd_add_face(rd_mesh *d, const int *idx, int n, long line)
{
    if (d->nf >= Q2N_MESH_MAX_COUNT || d->nfv + (size_t)n >= Q2N_MESH_MAX_COUNT) return -2;
    if (!grow((void **)&d->fvert, &d->cap_fv, d->nfv + (size_t)n, sizeof *d->fvert)) return -1;
    size_t cap = d->cap_f;
    if (!grow((void **)&d->fstart, &cap, d->nf + 2, sizeof *d->fstart)) return -1;
    cap = d->cap_f;
    if (!grow((void **)&d->fline, &cap, d->nf + 2, sizeof *d->fline)) return -1;
    d->cap_f = cap;
    memcpy(d->fvert + d->nfv, idx, (size_t)n * sizeof *idx);
    d->nfv += (size_t)n;
    d->fstart[0] = 0;
    d->fline[d->nf] = line > INT_MAX ? INT_MAX : (int)line;
    d->fstart[++d->nf] = (int)d->nfv;
    return 0;
}

void q2n_rd_free(rd_mesh *d)
{
    free(d->pos);
    free(d->fstart);
    free(d->fline);
    free(d->fvert);
    memset(d, 0, sizeof *d);
}

q2n_status q2n_rd_finish(rd_mesh *d, const char *name, q2n_mesh **out, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    if (d->nf == 0) st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: empty mesh (no faces)", name);
    for (size_t f = 0; !st && f < d->nf; f++)
        for (int i = d->fstart[f]; i < d->fstart[f + 1]; i++)
            if (d->fvert[i] < 0 || (size_t)d->fvert[i] >= d->nv) {
                if (d->fline[f] > 0)
                    st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s:%d: face index %d out of range (%zu vertices, "
                                       "indices start at 0)", name, d->fline[f], d->fvert[i], d->nv);
                else
                    st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: face %zu: index %d out of range (%zu vertices, "
                                       "indices start at 0)", name, f, d->fvert[i], d->nv);
                break;
            }
    if (!st)
        st = q2n_mesh_from_arrays_lines((int)d->nv, d->pos, (int)d->nf, d->fstart, d->fvert, d->fline, name, out, err);
    q2n_rd_free(d);
    return st;
}

/* ------------------------------------------------------------------ lines, tokens, numbers */

int q2n_rd_next_line(rd_lines *l, char **s)
{
    if (l->p >= l->end) return 0;
    const char *b = l->p, *e = memchr(b, '\n', (size_t)(l->end - b));
    size_t n = e ? (size_t)(e - b) : (size_t)(l->end - b);
    l->p = e ? e + 1 : l->end;
    l->line++;
    if (n + 1 > l->cap) {
        size_t c = l->cap ? l->cap : 256;
        while (c < n + 1) c *= 2;
        char *q = realloc(l->buf, c);
        if (!q) return -1;
        l->buf = q;
        l->cap = c;
    }
    if (memchr(b, '\0', n)) return -2;
    memcpy(l->buf, b, n);
    l->buf[n] = '\0';
    for (size_t i = 0; i < n; i++)   /* CR (of CRLF) is space */
        if (l->buf[i] == '\r') l->buf[i] = ' ';
    if (l->strip_comments) {
        char *h = strchr(l->buf, '#');
        if (h) *h = '\0';
    }
    *s = l->buf;
    return 1;
}

void q2n_rd_lines_free(rd_lines *l)
{
    free(l->buf);
    l->buf = NULL;
    l->cap = 0;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

char *q2n_rd_tok(char **cur)
{
    char *p = *cur;
    while (is_space(*p)) p++;
    if (!*p) { *cur = p; return NULL; }
    char *t = p;
    while (*p && !is_space(*p)) p++;
    if (*p) *p++ = '\0';
    *cur = p;
    return t;
}

int q2n_rd_double(const char *t, double *x)
{
    char *end;
    errno = 0;
    double v = strtod(t, &end);
    if (end == t || *end) return -1;
    if (!isfinite(v)) return -2;
    *x = v;
    return 0;
}

int q2n_rd_int(const char *t, long long *v)
{
    const char *s = t;
    int neg = 0;
    if (*s == '+' || *s == '-') neg = *s++ == '-';
    if (*s < '0' || *s > '9') return -1;
    long long a = 0;
    int big = 0;
    for (; *s >= '0' && *s <= '9'; s++)
        if ((a = a * 10 + (*s - '0')) > INT_MAX) { a = (long long)INT_MAX + 1; big = 1; }
    if (*s) return -1;
    *v = neg ? -a : a;
    return big ? -2 : 0;
}

const char *q2n_rd_quote(const char *t, char *buf, size_t n)
{
    snprintf(buf, n, "%s", t);
    if (strlen(t) >= n) memcpy(buf + n - 4, "...", 4);
    return buf;
}

void *q2n_rd_locale_begin(void **old)
{
    locale_t c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    *old = c ? (void *)uselocale(c) : NULL;
    return c;
}

void q2n_rd_locale_end(void *c, void *old)
{
    if (!c) return;
    uselocale((locale_t)old);
    freelocale((locale_t)c);
}

/* ------------------------------------------------------------------ format dispatch */

typedef enum { FMT_OBJ, FMT_OFF, FMT_PLY, FMT_STL } mesh_format;

static int has_ext(const char *path, const char *ext)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) && strcasecmp(dot, ext) == 0;
}

/* OFF keyword: [ST][C][N][4][n]OFF followed by space or the end of the line. */
static int off_magic(const char *p, size_t n)
{
    size_t i = 0;
    if (n >= 2 && p[0] == 'S' && p[1] == 'T') i = 2;
    while (i < n && (p[i] == 'C' || p[i] == 'N' || p[i] == '4' || p[i] == 'n')) i++;
    return i + 3 <= n && !memcmp(p + i, "OFF", 3) && (i + 3 == n || is_space(p[i + 3]) || p[i + 3] == '\n');
}

static mesh_format detect(const char *path, const char *head, size_t n)
{
    if (has_ext(path, ".obj")) return FMT_OBJ;
    if (has_ext(path, ".off")) return FMT_OFF;
    if (has_ext(path, ".ply")) return FMT_PLY;
    if (has_ext(path, ".stl")) return FMT_STL;
    if (n >= 4 && !memcmp(head, "ply", 3) && (head[3] == '\n' || head[3] == '\r')) return FMT_PLY;
    if (off_magic(head, n)) return FMT_OFF;
    return FMT_OBJ;
}

/* The whole file into memory. */
static q2n_status slurp(const char *path, char **data, size_t *len, q2n_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) return q2n_error_set(err, Q2N_ERR_IO, "%s: %s", path, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *b = malloc(cap);
    for (;;) {
        if (!b) { fclose(f); return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", path); }
        n += fread(b + n, 1, cap - n, f);
        if (n < cap) break;
        char *q = cap < (size_t)-1 / 2 ? realloc(b, cap *= 2) : NULL;
        if (!q) free(b);
        b = q;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) { free(b); return q2n_error_set(err, Q2N_ERR_IO, "%s: read error", path); }
    *data = b;
    *len = n;
    return Q2N_OK;
}

q2n_status q2n_mesh_read(const char *path, q2n_mesh **out, q2n_mesh_read_info *info, q2n_error *err)
{
    q2n_mesh_read_info dummy;
    if (!info) info = &dummy;
    memset(info, 0, sizeof *info);
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "read: no output pointer");
    *out = NULL;
    if (!path) return q2n_error_set(err, Q2N_ERR_ARG, "read: NULL path");
    char head[16] = "";
    size_t n = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return q2n_error_set(err, Q2N_ERR_IO, "%s: %s", path, strerror(errno));
    n = fread(head, 1, sizeof head, f);
    fclose(f);
    mesh_format fmt = detect(path, head, n);
    if (fmt == FMT_OBJ) {
        snprintf(info->format, sizeof info->format, "obj");
        return q2n_mesh_read_obj_info(path, out, info, err);
    }
    char *data = NULL;
    size_t len = 0;
    q2n_status st = slurp(path, &data, &len, err);
    if (st) return st;
    snprintf(info->format, sizeof info->format, fmt == FMT_OFF ? "off" : fmt == FMT_PLY ? "ply" : "stl");
    st = fmt == FMT_OFF   ? q2n_mesh_parse_off(data, len, path, out, err)
         : fmt == FMT_PLY ? q2n_mesh_parse_ply(data, len, path, out, err)
                          : q2n_mesh_parse_stl(data, len, path, out, err);
    free(data);
    return st;
}
