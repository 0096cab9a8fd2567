/* obj_reader.c — Wavefront OBJ input: `v` and `f` records, streamed line by line.
 *
 * Lines have no length limit (getline / realloc growth); a trailing backslash joins the next
 * line; CRLF and a leading UTF-8 byte order mark are accepted; `#` starts a comment anywhere; vt vn vp g o s usemtl mtllib l are
 * ignored; `t` lines (OpenSubdiv's tags: crease, corner, interpolateboundary, ...) are counted
 * and ignored (the caller warns: sharp features are not supported); any other keyword is an
 * error.  `v x y z [w]` (or `v x y z r g b`, the common
 * vertex-colour extension; w and colours are ignored), `f` with a, a/b, a//c, a/b/c and negative
 * (relative) indices; positive indices may refer to vertices defined later in the file.
 * Numbers are read in the "C" locale whatever the process locale is (thread-local uselocale).
 * Errors: "FILE:LINE: reason" (the line where the record starts), "FILE: strerror" when the file
 * cannot be read.  After parsing, q2n_mesh_from_arrays_lines validates the topology. */
#include "mesh/mesh.h"
#include "mesh/mesh_policy.h"
#include "mesh/reader.h"

#include <errno.h>
#include <limits.h>
#include <locale.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

/* growable arrays of the parse */
typedef struct obj_data {
    double *pos;
    size_t nv, cap_v;       /* vertices */
    int *fstart, *fline;
    size_t nf, cap_fs, cap_fl; /* faces (fstart has nf+1 entries) */
    int *fvert;
    size_t nfv, cap_fv;     /* face-vertex entries */
} obj_data;

/* a source of physical lines: a buffer or a stream */
typedef struct obj_src {
    const char *text;
    size_t len, off;
    FILE *fp;
    char *phys;
    size_t physcap;
    long line;              /* physical lines consumed */
    char *lb;               /* current logical line, NUL-terminated */
    size_t lbn, lbcap;
} obj_src;

static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return 1;
    size_t c = *cap ? *cap : 64;
    while (c < need) {
        if (c > SIZE_MAX / 2 / elem) return 0;
        c *= 2;
    }
    void *q = realloc(*p, c * elem);
    if (!q) return 0;
    *p = q;
    *cap = c;
    return 1;
}

/* Next physical line without its '\n': 1, or 0 at end of input, -1 on a read error. */
static int src_phys(obj_src *s, const char **p, size_t *n)
{
    if (s->fp) {
        errno = 0;
        ssize_t r = getline(&s->phys, &s->physcap, s->fp);
        if (r < 0) return ferror(s->fp) ? -1 : 0;
        *p = s->phys;
        *n = (size_t)r;
    } else {
        if (s->off >= s->len) return 0;
        const char *b = s->text + s->off, *e = memchr(b, '\n', s->len - s->off);
        *p = b;
        *n = e ? (size_t)(e - b) + 1 : s->len - s->off;
        s->off += *n;
    }
    if (*n && (*p)[*n - 1] == '\n') (*n)--;
    s->line++;
    return 1;
}

/* Next logical line (continuations joined) into s->lb; *first = its first physical line.
 * Returns 1, 0 at end, -1 read error, -2 out of memory. */
static int src_line(obj_src *s, long *first)
{
    const char *p;
    size_t n;
    int r = src_phys(s, &p, &n);
    if (r <= 0) return r;
    *first = s->line;
    s->lbn = 0;
    if (s->line == 1 && n >= 3 && !memcmp(p, "\xEF\xBB\xBF", 3)) { /* UTF-8 byte order mark */
        p += 3;
        n -= 3;
    }
    for (;;) {
        if (n && p[n - 1] == '\r') n--;
        int cont = n && p[n - 1] == '\\';
        if (cont) n--;
        if (!grow((void **)&s->lb, &s->lbcap, s->lbn + n + 2, 1)) return -2;
        memcpy(s->lb + s->lbn, p, n);
        s->lbn += n;
        if (cont) s->lb[s->lbn++] = ' ';
        s->lb[s->lbn] = '\0';
        if (!cont) return 1;
        r = src_phys(s, &p, &n);
        if (r < 0) return r;
        if (r == 0) return 1;
    }
}

/* A token quoted for a message, shortened. */
static const char *quote(const char *t, char *buf, size_t n)
{
    snprintf(buf, n, "%s", t);
    if (strlen(t) >= n) memcpy(buf + n - 4, "...", 4);
    return buf;
}

static q2n_status parse_vertex(obj_data *d, char *cur, const char *where, q2n_error *err)
{
    double x[8];
    int k = 0;
    char q[48];
    for (char *t; (t = q2n_rd_tok(&cur));) {
        char *end;
        errno = 0;
        double v = strtod(t, &end);
        if (end == t || *end)
            return q2n_error_set(err, Q2N_ERR_PARSE, "%s: bad number '%s'", where,
                                 quote(t, q, sizeof q));
        if (!isfinite(v))
            return q2n_error_set(err, Q2N_ERR_PARSE, "%s: non-finite coordinate '%s' (NaN/Inf "
                                 "or out of double range)", where, quote(t, q, sizeof q));
        if (k == 8) {
            k++;
            break;
        }
        x[k++] = v;
    }
    if (k < 3)
        return q2n_error_set(err, Q2N_ERR_PARSE, "%s: too few coordinates (%d, need x y z)", where,
                             k);
    if (k == 5 || k > 6)
        return q2n_error_set(err, Q2N_ERR_PARSE, "%s: %s numbers in a v record (expected x y z "
                             "[w] or x y z r g b)", where, k > 8 ? "more than 8" : k == 5 ? "5" :
                             k == 7 ? "7" : "8");
    if (d->nv >= Q2N_MESH_MAX_COUNT)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: more than 2^31-2 vertices", where);
    if (!grow((void **)&d->pos, &d->cap_v, 3 * (d->nv + 1), sizeof *d->pos))
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", where);
    memcpy(d->pos + 3 * d->nv++, x, 3 * sizeof *x);
    return Q2N_OK;
}

/* Signed decimal integer at *p (digits required); *big = 1 if |value| > INT_MAX. */
static int parse_int(const char **p, long long *val, int *big)
{
    const char *s = *p;
    int neg = 0;
    if (*s == '+' || *s == '-') neg = *s++ == '-';
    if (*s < '0' || *s > '9') return 0;
    long long v = 0;
    for (; *s >= '0' && *s <= '9'; s++)
        if ((v = v * 10 + (*s - '0')) > INT_MAX) { v = (long long)INT_MAX + 1; *big = 1; }
    *val = neg ? -v : v;
    *p = s;
    return 1;
}

/* One face corner token: a, a/b, a//c or a/b/c.  *idx = the 0-based vertex index (>= nv
 * allowed: a forward reference, checked at the end). */
static q2n_status parse_corner(const char *t, size_t nv, const char *where, int *idx,
                               q2n_error *err)
{
    const char *p = t;
    long long a, b;
    int big = 0, ok = parse_int(&p, &a, &big);
    char q[48];
    if (ok && *p == '/') {
        p++;
        if (*p == '/') {                                          /* a//c */
            p++;
            ok = parse_int(&p, &b, &big);
        } else if ((ok = parse_int(&p, &b, &big)) && *p == '/') { /* a/b or a/b/c */
            p++;
            ok = parse_int(&p, &b, &big);
        }
    }
    if (!ok || *p)
        return q2n_error_set(err, Q2N_ERR_PARSE, "%s: bad face vertex '%s'", where,
                             quote(t, q, sizeof q));
    if (big || a > INT_MAX || a < -(long long)INT_MAX)
        return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: face index '%s' out of range (> 2^31-1)",
                             where, quote(t, q, sizeof q));
    if (a == 0)
        return q2n_error_set(err, Q2N_ERR_PARSE, "%s: face index 0 (OBJ indices start at 1)", where);
    if (a < 0 && (long long)nv + a < 0)
        return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: relative face index %lld out of range "
                             "(%zu vertices so far)", where, a, nv);
    *idx = (int)(a > 0 ? a - 1 : (long long)nv + a);
    return Q2N_OK;
}

static q2n_status parse_face(obj_data *d, char *cur, long line, const char *where, q2n_error *err)
{
    size_t n0 = d->nfv;
    for (char *t; (t = q2n_rd_tok(&cur));) {
        int idx = 0;
        q2n_status st = parse_corner(t, d->nv, where, &idx, err);
        if (st) return st;
        if (d->nfv >= Q2N_MESH_MAX_COUNT)
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: more than 2^31-2 face vertices",
                                 where);
        if (!grow((void **)&d->fvert, &d->cap_fv, d->nfv + 1, sizeof *d->fvert))
            return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", where);
        d->fvert[d->nfv++] = idx;
    }
    size_t n = d->nfv - n0;
    if (n < 3)
        return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: face with %s%zu vert%s (a face needs at least 3)",
                             where, n ? "only " : "", n, n == 1 ? "ex" : "ices");
    if (d->nf >= Q2N_MESH_MAX_COUNT)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: more than 2^31-2 faces", where);
    if (!grow((void **)&d->fstart, &d->cap_fs, d->nf + 2, sizeof *d->fstart) ||
        !grow((void **)&d->fline, &d->cap_fl, d->nf + 1, sizeof *d->fline))
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", where);
    d->fstart[0] = 0;
    d->fline[d->nf] = line > INT_MAX ? INT_MAX : (int)line;
    d->fstart[++d->nf] = (int)d->nfv;
    return Q2N_OK;
}

static int keyword_ignored(const char *k)
{
    static const char *const ignored[] = {"vt", "vn", "vp", "g", "o", "s", "usemtl", "mtllib", "l"};
    for (size_t i = 0; i < sizeof ignored / sizeof ignored[0]; i++)
        if (!strcmp(k, ignored[i])) return 1;
    return 0;
}

/* An OpenSubdiv tag line `t NAME ints/floats/strings ...`: counted, its name remembered. */
static void note_tag(q2n_mesh_read_info *info, char *cur, long line)
{
    if (!info) return;
    char *name = q2n_rd_tok(&cur);
    if (!info->tags++) info->tag_line = line;
    if (!name) return;
    size_t have = strlen(info->tag_names), n = strlen(name);
    for (const char *p = info->tag_names; (p = strstr(p, name)); p += n)
        if ((p == info->tag_names || p[-1] == ' ') && (p[n] == ',' || p[n] == '\0')) return; /* listed */
    if (have + n + 3 < sizeof info->tag_names)
        snprintf(info->tag_names + have, sizeof info->tag_names - have, "%s%s", have ? ", " : "", name);
}

static q2n_status parse_all(obj_src *s, obj_data *d, const char *name, q2n_mesh_read_info *info, q2n_error *err)
{
    long line = 0;
    char where[320], q[48];
    for (;;) {
        int r = src_line(s, &line);
        if (r == 0) return Q2N_OK;
        if (r == -1)
            return q2n_error_set(err, Q2N_ERR_IO, "%s: read error: %s", name, strerror(errno));
        if (r == -2) return q2n_error_set(err, Q2N_ERR_NOMEM, "%s:%ld: out of memory", name, s->line);
        snprintf(where, sizeof where, "%s:%ld", name, line);
        if (memchr(s->lb, '\0', s->lbn))
            return q2n_error_set(err, Q2N_ERR_PARSE, "%s: NUL byte in line", where);
        char *hash = strchr(s->lb, '#');
        if (hash) *hash = '\0';
        char *cur = s->lb, *kw = q2n_rd_tok(&cur);
        q2n_status st = Q2N_OK;
        if (!kw || keyword_ignored(kw)) continue;
        if (!strcmp(kw, "t")) note_tag(info, cur, line);
        else if (!strcmp(kw, "v")) st = parse_vertex(d, cur, where, err);
        else if (!strcmp(kw, "f")) st = parse_face(d, cur, line, where, err);
        else st = q2n_error_set(err, Q2N_ERR_PARSE, "%s: unknown keyword '%s'", where,
                                quote(kw, q, sizeof q));
        if (st) return st;
    }
}

/* Forward references: every index must name a vertex of the whole file. */
static q2n_status check_ranges(const obj_data *d, const char *name, q2n_error *err)
{
    for (size_t f = 0; f < d->nf; f++)
        for (int i = d->fstart[f]; i < d->fstart[f + 1]; i++)
            if ((size_t)d->fvert[i] >= d->nv)
                return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s:%d: face index %d out of range "
                                     "(%zu vertices)", name, d->fline[f], d->fvert[i] + 1, d->nv);
    return Q2N_OK;
}

static q2n_status parse_source(obj_src *s, const char *name, q2n_mesh **out, q2n_mesh_read_info *info,
                               q2n_error *err)
{
    obj_data d = {0};
    /* numbers in the "C" locale (thread-local switch; restored before returning) */
    locale_t cloc = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0), old = (locale_t)0;
    if (cloc) old = uselocale(cloc);
    q2n_status st = parse_all(s, &d, name, info, err);
    if (cloc) {
        uselocale(old);
        freelocale(cloc);
    }
    if (!st && d.nf == 0) st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: empty mesh (no faces)", name);
    if (!st) st = check_ranges(&d, name, err);
    if (!st)
        st = q2n_mesh_from_arrays_lines((int)d.nv, d.pos, (int)d.nf, d.fstart, d.fvert, d.fline,
                                        name, out, err);
    free(d.pos);
    free(d.fstart);
    free(d.fline);
    free(d.fvert);
    free(s->phys);
    free(s->lb);
    return st;
}

q2n_status q2n_mesh_parse_obj_info(const char *text, size_t len, const char *name, q2n_mesh **out,
                                   q2n_mesh_read_info *info, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "parse_obj: no output pointer");
    *out = NULL;
    if (!text && len) return q2n_error_set(err, Q2N_ERR_ARG, "parse_obj: NULL text");
    obj_src s = {0};
    s.text = text;
    s.len = len;
    return parse_source(&s, name && name[0] ? name : "<obj>", out, info, err);
}

q2n_status q2n_mesh_parse_obj(const char *text, size_t len, const char *name, q2n_mesh **out,
                              q2n_error *err)
{
    return q2n_mesh_parse_obj_info(text, len, name, out, NULL, err);
}

q2n_status q2n_mesh_read_obj_info(const char *path, q2n_mesh **out, q2n_mesh_read_info *info, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "read_obj: no output pointer");
    *out = NULL;
    if (!path) return q2n_error_set(err, Q2N_ERR_ARG, "read_obj: NULL path");
    obj_src s = {0};
    s.fp = fopen(path, "rb");
    if (!s.fp) return q2n_error_set(err, Q2N_ERR_IO, "%s: %s", path, strerror(errno));
    q2n_status st = parse_source(&s, path, out, info, err);
    fclose(s.fp);
    return st;
}

q2n_status q2n_mesh_read_obj(const char *path, q2n_mesh **out, q2n_error *err)
{
    return q2n_mesh_read_obj_info(path, out, NULL, err);
}
