/* off_reader.c — ASCII OFF input (Geomview's Object File Format, as written by Blender, MeshLab,
 * CGAL and OpenSubdiv's tools).
 *
 * An optional keyword line [ST][C][N]OFF (only 3-D: the "4" and "n" prefixes and "OFF BINARY" are
 * refused), then "NV NF NE" (NE is ignored; the counts may follow the keyword on its line), NV
 * vertex lines "x y z" with optional further numbers (normal, colour, texture coordinates), NF
 * face lines "n i_1 .. i_n" with 0-based indices and an optional colour (at most 4 numbers).
 * '#' starts a comment; blank lines are skipped; anything after the last face is an error.
 * Errors read "FILE:LINE: reason"; the topology is validated as for OBJ (reader.h). */
#include "mesh/reader.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct off_ctx {
    rd_lines l;
    const char *name;
    q2n_error *err;
} off_ctx;

/* Next line with a token: 1 and *cur set, 0 at the end, or an error status stored in *st. */
static int next_data_line(off_ctx *c, char **cur, q2n_status *st)
{
    char *s;
    for (;;) {
        int r = q2n_rd_next_line(&c->l, &s);
        if (r == 0) return 0;
        if (r == -1) { *st = q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s:%ld: out of memory", c->name, c->l.line); return 0; }
        if (r == -2) { *st = q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: NUL byte in line", c->name, c->l.line); return 0; }
        char *p = s;
        while (*p == ' ' || *p == '\t' || *p == '\v' || *p == '\f') p++;
        if (*p) { *cur = p; return 1; }
    }
}

static q2n_status count(off_ctx *c, const char *t, const char *what, long long *v)
{
    char q[48];
    if (!t) return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: missing %s count (expected \"NV NF NE\")", c->name,
                                 c->l.line, what);
    int r = q2n_rd_int(t, v);
    if (r || *v < 0)
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: bad %s count '%s' (a number 0 .. 2^31-2)", c->name,
                             c->l.line, what, q2n_rd_quote(t, q, sizeof q));
    return Q2N_OK;
}

static q2n_status read_vertex(off_ctx *c, rd_mesh *d, char *cur, long k, long nv)
{
    double x[3], extra;
    int n = 0;
    char q[48];
    for (char *t; (t = q2n_rd_tok(&cur)); n++) {
        int r = q2n_rd_double(t, n < 3 ? &x[n] : &extra);
        if (r == -1)
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: bad number '%s'", c->name, c->l.line,
                                 q2n_rd_quote(t, q, sizeof q));
        if (r == -2)
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: non-finite coordinate '%s' (NaN/Inf or out of "
                                 "double range)", c->name, c->l.line, q2n_rd_quote(t, q, sizeof q));
    }
    if (n < 3)
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: vertex %ld of %ld has %d number%s (need x y z)", c->name,
                             c->l.line, k, nv, n, n == 1 ? "" : "s");
    int r = q2n_rd_add_vertex(d, x);
    if (r) return q2n_error_set(c->err, r == -1 ? Q2N_ERR_NOMEM : Q2N_ERR_UNSUPPORTED, "%s:%ld: %s", c->name, c->l.line,
                                r == -1 ? "out of memory" : "more than 2^31-2 vertices");
    return Q2N_OK;
}

static q2n_status read_face(off_ctx *c, rd_mesh *d, char *cur, int **idx, int *cap)
{
    char q[48], *t = q2n_rd_tok(&cur);
    long long n, v;
    if (q2n_rd_int(t, &n) || n < 0)
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: bad vertex count '%s' of a face", c->name, c->l.line,
                             q2n_rd_quote(t, q, sizeof q));
    if (n < 3)
        return q2n_error_set(c->err, Q2N_ERR_TOPOLOGY, "%s:%ld: face with %s%lld vert%s (a face needs at least 3)",
                             c->name, c->l.line, n ? "only " : "", n, n == 1 ? "ex" : "ices");
    for (long long i = 0; i < n; i++) {
        if (!(t = q2n_rd_tok(&cur)))
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: face with %lld vertices lists only %lld", c->name,
                                 c->l.line, n, i);
        int r = q2n_rd_int(t, &v);
        if (r == -1)
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: bad face vertex '%s'", c->name, c->l.line,
                                 q2n_rd_quote(t, q, sizeof q));
        if (r == -2 || v < 0 || v > 0x7ffffffe)
            return q2n_error_set(c->err, Q2N_ERR_TOPOLOGY, "%s:%ld: face index '%s' out of range (indices start at 0)",
                                 c->name, c->l.line, q2n_rd_quote(t, q, sizeof q));
        if (i >= *cap) {
            int nc = *cap ? 2 * *cap : 16;
            int *p = realloc(*idx, sizeof(int) * (size_t)nc);
            if (!p) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s:%ld: out of memory", c->name, c->l.line);
            *idx = p;
            *cap = nc;
        }
        (*idx)[i] = (int)v;
    }
    int extra = 0;
    double x;
    for (; (t = q2n_rd_tok(&cur)); extra++)
        if (q2n_rd_double(t, &x))
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: bad colour value '%s' after the face's vertices",
                                 c->name, c->l.line, q2n_rd_quote(t, q, sizeof q));
    if (extra > 4)
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: %d numbers after the face's %lld vertices (a colour has at "
                             "most 4)", c->name, c->l.line, extra, n);
    int r = q2n_rd_add_face(d, *idx, (int)n, c->l.line);
    if (r) return q2n_error_set(c->err, r == -1 ? Q2N_ERR_NOMEM : Q2N_ERR_UNSUPPORTED, "%s:%ld: %s", c->name, c->l.line,
                                r == -1 ? "out of memory" : "more than 2^31-2 faces");
    return Q2N_OK;
}

static q2n_status parse(off_ctx *c, rd_mesh *d)
{
    q2n_status st = Q2N_OK;
    char *cur, *t, q[48];
    if (!next_data_line(c, &cur, &st)) return st ? st : q2n_error_set(c->err, Q2N_ERR_TOPOLOGY, "%s: empty file", c->name);
    size_t tl = strcspn(cur, " \t\v\f");
    if (tl >= 3 && !strncmp(cur + tl - 3, "OFF", 3)) {         /* the keyword (optional in OFF) */
        char kw[16];
        snprintf(kw, sizeof kw, "%.*s", (int)(tl < 15 ? tl : 15), cur);
        if (strchr(kw, '4') || strchr(kw, 'n'))
            return q2n_error_set(c->err, Q2N_ERR_UNSUPPORTED, "%s:%ld: '%s': only 3-D OFF is supported", c->name,
                                 c->l.line, kw);
        cur += tl;
        while (*cur == ' ' || *cur == '\t' || *cur == '\v' || *cur == '\f') cur++;
        if (!strncmp(cur, "BINARY", 6))
            return q2n_error_set(c->err, Q2N_ERR_UNSUPPORTED, "%s:%ld: binary OFF is not supported (ASCII only)",
                                 c->name, c->l.line);
        if (!*cur && !next_data_line(c, &cur, &st))
            return st ? st : q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: no counts line after '%s'", c->name, kw);
    }
    long long nv, nf, ne;
    if ((st = count(c, q2n_rd_tok(&cur), "vertex", &nv)) || (st = count(c, q2n_rd_tok(&cur), "face", &nf))) return st;
    if ((t = q2n_rd_tok(&cur)) && (st = count(c, t, "edge", &ne))) return st;
    if ((t = q2n_rd_tok(&cur)))
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: unexpected '%s' after the counts \"NV NF NE\"", c->name,
                             c->l.line, q2n_rd_quote(t, q, sizeof q));
    for (long long k = 0; k < nv; k++) {
        if (!next_data_line(c, &cur, &st))
            return st ? st : q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: the file ends after %lld of %lld vertices",
                                          c->name, k, nv);
        if ((st = read_vertex(c, d, cur, (long)k + 1, (long)nv))) return st;
    }
    int *idx = NULL, cap = 0;
    for (long long k = 0; k < nf && !st; k++) {
        if (!next_data_line(c, &cur, &st)) {
            if (!st) st = q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: the file ends after %lld of %lld faces", c->name, k, nf);
            break;
        }
        st = read_face(c, d, cur, &idx, &cap);
    }
    free(idx);
    if (!st && next_data_line(c, &cur, &st))
        st = q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: data after the last of %lld faces", c->name, c->l.line, nf);
    return st;
}

q2n_status q2n_mesh_parse_off(const char *text, size_t len, const char *name, q2n_mesh **out, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "parse_off: no output pointer");
    *out = NULL;
    if (!text && len) return q2n_error_set(err, Q2N_ERR_ARG, "parse_off: NULL text");
    off_ctx c = {{text, text + len, 0, NULL, 0, 1}, name && *name ? name : "<off>", err};
    rd_mesh d = {0};
    void *old, *loc = q2n_rd_locale_begin(&old);
    q2n_status st = parse(&c, &d);
    q2n_rd_locale_end(loc, old);
    q2n_rd_lines_free(&c.l);
    if (st) { q2n_rd_free(&d); return st; }
    return q2n_rd_finish(&d, c.name, out, err);
}
