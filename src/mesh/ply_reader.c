/* ply_reader.c — PLY input (Turk's Polygon File Format 1.0: ascii, binary_little_endian,
 * binary_big_endian), as written by Blender, MeshLab and Open3D.
 *
 * The header declares elements in file order, each with scalar properties ("property TYPE NAME")
 * and list properties ("property list COUNT_TYPE ITEM_TYPE NAME"); types char/int8 uchar/uint8
 * short/int16 ushort/uint16 int/int32 uint/uint32 float/float32 double/float64.  Used: element
 * "vertex" with x, y, z (any numeric type) and element "face" with the list "vertex_indices" (or
 * "vertex_index", 0-based); every other element and property is read past.  ASCII data are a
 * stream of numbers (an element may span lines); errors name "FILE:LINE".  Binary data have no
 * lines: errors name the element and byte offset.  The topology is validated as for OBJ. */
#include "mesh/reader.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

static const struct { const char *a, *b; ply_type t; int size; } TYPES[] = {
    {"char", "int8", T_I8, 1},    {"uchar", "uint8", T_U8, 1},     {"short", "int16", T_I16, 2},
    {"ushort", "uint16", T_U16, 2}, {"int", "int32", T_I32, 4},    {"uint", "uint32", T_U32, 4},
    {"float", "float32", T_F32, 4}, {"double", "float64", T_F64, 8}};

static int type_size(ply_type t)
{
    for (size_t i = 0; i < sizeof TYPES / sizeof TYPES[0]; i++)
        if (TYPES[i].t == t) return TYPES[i].size;
    return 0;
}

static ply_type type_parse(const char *s)
{
    for (size_t i = 0; s && i < sizeof TYPES / sizeof TYPES[0]; i++)
        if (!strcmp(s, TYPES[i].a) || !strcmp(s, TYPES[i].b)) return TYPES[i].t;
    return T_NONE;
}

typedef struct ply_prop {
    char name[32];
    ply_type type, count_type; /* count_type != T_NONE: a list */
} ply_prop;

typedef struct ply_elem {
    char name[32];
    long long count;
    ply_prop *props;
    int nprops, cap;
    int role;                  /* 1 vertex, 2 face, 0 skipped */
    int px[3], plist;          /* vertex: properties x, y, z; face: the index list */
} ply_elem;

enum { FMT_ASCII = 1, FMT_LE, FMT_BE };

typedef struct ply_ctx {
    const char *name;
    q2n_error *err;
    const unsigned char *data, *end, *p; /* binary cursor */
    rd_lines l;                          /* header, and the ASCII body */
    char *cur;                           /* rest of the current ASCII line */
    long tok_line;                       /* line of the last ASCII token */
    int format;
    ply_elem *el;
    int nel, capel;
} ply_ctx;

/* ------------------------------------------------------------------ header */

static q2n_status header_error(ply_ctx *c, const char *what)
{
    return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: %s", c->name, c->l.line, what);
}

static q2n_status add_elem(ply_ctx *c, char *cur)
{
    char *name = q2n_rd_tok(&cur), *cnt = q2n_rd_tok(&cur), q[48], msg[160];
    long long n;
    if (!name || !cnt || q2n_rd_tok(&cur)) return header_error(c, "expected \"element NAME COUNT\"");
    if (q2n_rd_int(cnt, &n) || n < 0) {
        snprintf(msg, sizeof msg, "bad element count '%s'", q2n_rd_quote(cnt, q, sizeof q));
        return header_error(c, msg);
    }
    if (c->nel == c->capel) {
        int nc = c->capel ? 2 * c->capel : 4;
        ply_elem *e = realloc(c->el, sizeof *e * (size_t)nc);
        if (!e) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s: out of memory", c->name);
        c->el = e;
        c->capel = nc;
    }
    ply_elem *e = &c->el[c->nel++];
    memset(e, 0, sizeof *e);
    snprintf(e->name, sizeof e->name, "%s", name);
    e->count = n;
    e->px[0] = e->px[1] = e->px[2] = e->plist = -1;
    e->role = !strcmp(name, "vertex") ? 1 : !strcmp(name, "face") ? 2 : 0;
    return Q2N_OK;
}

static q2n_status add_prop(ply_ctx *c, char *cur)
{
    char *t = q2n_rd_tok(&cur), *name, q[48], msg[160];
    ply_prop p = {"", T_NONE, T_NONE};
    if (!c->nel) return header_error(c, "property before any element");
    if (t && !strcmp(t, "list")) {
        char *ct = q2n_rd_tok(&cur), *it = q2n_rd_tok(&cur);
        p.count_type = type_parse(ct);
        p.type = type_parse(it);
        if (p.count_type == T_NONE || p.type == T_NONE || p.count_type >= T_F32) {
            snprintf(msg, sizeof msg, "bad list types '%s %s' (count: an integer type)", q2n_rd_quote(ct ? ct : "", q, sizeof q),
                     it ? it : "");
            return header_error(c, msg);
        }
    } else if ((p.type = type_parse(t)) == T_NONE) {
        snprintf(msg, sizeof msg, "unknown property type '%s'", q2n_rd_quote(t ? t : "", q, sizeof q));
        return header_error(c, msg);
    }
    if (!(name = q2n_rd_tok(&cur)) || q2n_rd_tok(&cur)) return header_error(c, "expected \"property [list CT IT] TYPE NAME\"");
    snprintf(p.name, sizeof p.name, "%s", name);
    ply_elem *e = &c->el[c->nel - 1];
    if (e->nprops == e->cap) {
        int nc = e->cap ? 2 * e->cap : 8;
        ply_prop *pp = realloc(e->props, sizeof *pp * (size_t)nc);
        if (!pp) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s: out of memory", c->name);
        e->props = pp;
        e->cap = nc;
    }
    int k = e->nprops++;
    e->props[k] = p;
    int list = p.count_type != T_NONE;
    if (e->role == 1 && !list && name[0] >= 'x' && name[0] <= 'z' && !name[1]) e->px[name[0] - 'x'] = k;
    if (e->role == 2 && list && (!strcmp(name, "vertex_indices") || !strcmp(name, "vertex_index"))) e->plist = k;
    return Q2N_OK;
}

static q2n_status parse_header(ply_ctx *c)
{
    char *s, *cur, *kw;
    int r = q2n_rd_next_line(&c->l, &s);
    if (r <= 0 || (cur = s, kw = q2n_rd_tok(&cur), !kw || strcmp(kw, "ply") || q2n_rd_tok(&cur)))
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:1: not a PLY file (the first line must be \"ply\")", c->name);
    for (;;) {
        if ((r = q2n_rd_next_line(&c->l, &s)) <= 0)
            return r == -1 ? q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s: out of memory", c->name)
                           : r == -2 ? header_error(c, "NUL byte in the header")
                                     : q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: no \"end_header\" line", c->name);
        cur = s;
        if (!(kw = q2n_rd_tok(&cur))) continue;
        q2n_status st = Q2N_OK;
        if (!strcmp(kw, "comment") || !strcmp(kw, "obj_info")) continue;
        if (!strcmp(kw, "end_header")) break;
        if (!strcmp(kw, "format")) {
            char *f = q2n_rd_tok(&cur), *v = q2n_rd_tok(&cur);
            c->format = !f ? 0 : !strcmp(f, "ascii") ? FMT_ASCII : !strcmp(f, "binary_little_endian") ? FMT_LE
                      : !strcmp(f, "binary_big_endian") ? FMT_BE : 0;
            if (!c->format || !v || strcmp(v, "1.0"))
                return header_error(c, "expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
        } else if (!strcmp(kw, "element")) {
            st = add_elem(c, cur);
        } else if (!strcmp(kw, "property")) {
            st = add_prop(c, cur);
        } else {
            char msg[96], q[48];
            snprintf(msg, sizeof msg, "unknown header keyword '%s'", q2n_rd_quote(kw, q, sizeof q));
            st = header_error(c, msg);
        }
        if (st) return st;
    }
    if (!c->format) return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: no \"format\" line in the header", c->name);
    for (int i = 0; i < c->nel; i++) {
        ply_elem *e = &c->el[i];
        if (e->role == 1 && (e->px[0] < 0 || e->px[1] < 0 || e->px[2] < 0))
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: element vertex lacks a scalar property x, y or z", c->name);
        if (e->role == 2 && e->plist < 0)
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: element face lacks the list property vertex_indices",
                                 c->name);
    }
    return Q2N_OK;
}

/* ------------------------------------------------------------------ values */

/* Where a value came from, for messages: "FILE:LINE" (ASCII) or "FILE: ELEM K (byte B)". */
static void where(const ply_ctx *c, const ply_elem *e, long long k, char *buf, size_t n)
{
    if (c->format == FMT_ASCII) snprintf(buf, n, "%s:%ld", c->name, c->tok_line);
    else snprintf(buf, n, "%s: %s %lld (byte %ld)", c->name, e->name, k, (long)(c->p - c->data));
}

/* Next ASCII token (over line ends), NULL at the end of the file (*st set on errors). */
static char *next_token(ply_ctx *c, q2n_status *st)
{
    for (;;) {
        char *t = c->cur ? q2n_rd_tok(&c->cur) : NULL, *s;
        if (t) { c->tok_line = c->l.line; return t; }
        int r = q2n_rd_next_line(&c->l, &s);
        if (r == 0) return NULL;
        if (r < 0) {
            *st = r == -1 ? q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s: out of memory", c->name)
                          : q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: NUL byte in line", c->name, c->l.line);
            return NULL;
        }
        c->cur = s;
    }
}

static int host_big_endian(void)
{
    const uint16_t one = 1;
    return *(const unsigned char *)&one == 0;
}

/* One value of type t: *x (always), and whether it is an integer type.  Returns Q2N_OK or an error
 * naming where. */
static q2n_status read_value(ply_ctx *c, const ply_elem *e, long long k, ply_type t, double *x)
{
    char w[320], q[48];
    if (c->format == FMT_ASCII) {
        q2n_status st = Q2N_OK;
        char *tok = next_token(c, &st);
        if (!tok) {
            if (st) return st;
            return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: the file ends inside %s %lld of %lld", c->name, e->name, k,
                                 e->count);
        }
        where(c, e, k, w, sizeof w);
        if (t >= T_F32) {
            int r = q2n_rd_double(tok, x);
            if (r == -1) return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: bad number '%s'", w, q2n_rd_quote(tok, q, sizeof q));
            if (r == -2)
                return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: non-finite value '%s' (NaN/Inf or out of double range)",
                                     w, q2n_rd_quote(tok, q, sizeof q));
        } else {
            long long v;
            if (q2n_rd_int(tok, &v) == -1)
                return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: bad integer '%s'", w, q2n_rd_quote(tok, q, sizeof q));
            *x = (double)v;
        }
        return Q2N_OK;
    }
    int n = type_size(t);
    if (c->end - c->p < n) {
        where(c, e, k, w, sizeof w);
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: the file ends inside %s %lld of %lld", w, e->name, k, e->count);
    }
    unsigned char b[8];
    memcpy(b, c->p, (size_t)n);
    if ((c->format == FMT_BE) != host_big_endian())
        for (int i = 0; i < n / 2; i++) { unsigned char s = b[i]; b[i] = b[n - 1 - i]; b[n - 1 - i] = s; }
    switch (t) {
    case T_I8: { int8_t v; memcpy(&v, b, 1); *x = v; break; }
    case T_U8: *x = b[0]; break;
    case T_I16: { int16_t v; memcpy(&v, b, 2); *x = v; break; }
    case T_U16: { uint16_t v; memcpy(&v, b, 2); *x = v; break; }
    case T_I32: { int32_t v; memcpy(&v, b, 4); *x = v; break; }
    case T_U32: { uint32_t v; memcpy(&v, b, 4); *x = v; break; }
    case T_F32: { float v; memcpy(&v, b, 4); *x = v; break; }
    default: { double v; memcpy(&v, b, 8); *x = v; break; }
    }
    c->p += n;
    if (!isfinite(*x)) {
        c->p -= n;
        where(c, e, k, w, sizeof w);
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: non-finite value (NaN/Inf)", w);
    }
    return Q2N_OK;
}

/* ------------------------------------------------------------------ body */

static q2n_status read_elem(ply_ctx *c, ply_elem *e, rd_mesh *d, int **idx, long long *cap)
{
    char w[320];
    if (!e->nprops) return Q2N_OK;   /* nothing stored per instance */
    for (long long k = 0; k < e->count; k++) {
        double xyz[3] = {0, 0, 0};
        long line = 0;
        for (int pi = 0; pi < e->nprops; pi++) {
            const ply_prop *p = &e->props[pi];
            double x;
            q2n_status st = read_value(c, e, k, p->count_type != T_NONE ? p->count_type : p->type, &x);
            if (st) return st;
            if (pi == 0) line = c->format == FMT_ASCII ? c->tok_line : 0;
            if (p->count_type == T_NONE) {
                if (e->role == 1 && (pi == e->px[0] || pi == e->px[1] || pi == e->px[2]))
                    xyz[pi == e->px[0] ? 0 : pi == e->px[1] ? 1 : 2] = x;
                continue;
            }
            long long n = (long long)x;
            if (n < 0 || n > INT_MAX / 2) {
                where(c, e, k, w, sizeof w);
                return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: bad list length %lld", w, n);
            }
            int keep = e->role == 2 && pi == e->plist;
            if (keep && n > *cap) {
                int *q = realloc(*idx, sizeof(int) * (size_t)n);
                if (!q) return q2n_error_set(c->err, Q2N_ERR_NOMEM, "%s: out of memory", c->name);
                *idx = q;
                *cap = n;
            }
            for (long long i = 0; i < n; i++) {
                if ((st = read_value(c, e, k, p->type, &x))) return st;
                if (!keep) continue;
                if (x != floor(x) || x < 0 || x > 0x7ffffffe) {
                    where(c, e, k, w, sizeof w);
                    return q2n_error_set(c->err, Q2N_ERR_TOPOLOGY, "%s: face index %.17g out of range (indices start at 0)",
                                         w, x);
                }
                (*idx)[i] = (int)x;
            }
            if (!keep) continue;
            if (n < 3) {
                where(c, e, k, w, sizeof w);
                return q2n_error_set(c->err, Q2N_ERR_TOPOLOGY, "%s: face with %s%lld vert%s (a face needs at least 3)",
                                     w, n ? "only " : "", n, n == 1 ? "ex" : "ices");
            }
            int r = q2n_rd_add_face(d, *idx, (int)n, line);
            if (r) return q2n_error_set(c->err, r == -1 ? Q2N_ERR_NOMEM : Q2N_ERR_UNSUPPORTED, "%s: %s", c->name,
                                        r == -1 ? "out of memory" : "more than 2^31-2 faces");
        }
        if (e->role == 1) {
            int r = q2n_rd_add_vertex(d, xyz);
            if (r) return q2n_error_set(c->err, r == -1 ? Q2N_ERR_NOMEM : Q2N_ERR_UNSUPPORTED, "%s: %s", c->name,
                                        r == -1 ? "out of memory" : "more than 2^31-2 vertices");
        }
    }
    return Q2N_OK;
}

static q2n_status parse_body(ply_ctx *c, rd_mesh *d)
{
    int *idx = NULL;
    long long cap = 0;
    q2n_status st = Q2N_OK;
    if (c->format != FMT_ASCII) c->p = (const unsigned char *)c->l.p;  /* right after "end_header\n" */
    for (int i = 0; i < c->nel && !st; i++) st = read_elem(c, &c->el[i], d, &idx, &cap);
    free(idx);
    if (st) return st;
    if (c->format == FMT_ASCII) {
        char *t = next_token(c, &st);
        if (t) return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s:%ld: data after the last element", c->name, c->tok_line);
    } else if (c->p != c->end) {
        return q2n_error_set(c->err, Q2N_ERR_PARSE, "%s: %ld bytes after the last element", c->name,
                             (long)(c->end - c->p));
    }
    return st;
}

q2n_status q2n_mesh_parse_ply(const char *data, size_t len, const char *name, q2n_mesh **out, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "parse_ply: no output pointer");
    *out = NULL;
    if (!data && len) return q2n_error_set(err, Q2N_ERR_ARG, "parse_ply: NULL data");
    ply_ctx c;
    memset(&c, 0, sizeof c);
    c.name = name && *name ? name : "<ply>";
    c.err = err;
    c.data = (const unsigned char *)data;
    c.end = c.data + len;
    if (len >= 3 && !memcmp(data, "\xEF\xBB\xBF", 3)) data += 3, len -= 3; /* a UTF-8 byte order mark */
    c.l.p = data;
    c.l.end = data + len;
    rd_mesh d = {0};
    void *old, *loc = q2n_rd_locale_begin(&old);
    q2n_status st = parse_header(&c);
    if (!st) st = parse_body(&c, &d);
    q2n_rd_locale_end(loc, old);
    q2n_rd_lines_free(&c.l);
    for (int i = 0; i < c.nel; i++) free(c.el[i].props);
    free(c.el);
    if (st) { q2n_rd_free(&d); return st; }
    return q2n_rd_finish(&d, c.name, out, err);
}
