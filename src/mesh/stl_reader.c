/* stl_reader.c — STL input (the tessellation format of CAD systems), ASCII and binary.
 *
 * Binary: an 80-byte header, a little-endian uint32 facet count N, then N records of 50 bytes
 * (normal, three vertices: twelve little-endian float32; a uint16 attribute).  ASCII: "solid
 * [name]", then per facet "facet normal nx ny nz", "outer loop", three "vertex x y z" lines,
 * "endloop", "endfacet", and "endsolid [name]" (several solids are read one after the other).  A
 * file whose size is exactly 84 + 50 N for the count it states is binary, even when its header
 * starts with "solid" (many exporters write that); otherwise a file starting with "solid" is ASCII
 * (keywords in any case: some exporters write them in capitals).
 *
 * STL lists every facet's corners by value: corners with the same coordinates (exactly; -0 and +0
 * alike) become one vertex, numbered in the order they first appear.  The normals are ignored (the
 * corners' order gives the orientation, as everywhere).  The result is validated as any mesh
 * (reader.h): a facet whose corners coincide, a non-manifold edge or an inconsistent orientation is an
 * error naming the facet and, in ASCII, its "facet" line; nothing is repaired.  Errors of the binary
 * layout name the facet and its byte offset. */
#include "mesh/reader.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Exact-coordinate vertex welding: open addressing over the positions' bits. */
typedef struct weld {
    rd_mesh *d;
    int *slot;
    size_t cap;
} weld;

static uint64_t bits(double x)
{
    uint64_t u;
    if (x == 0) x = 0; /* -0 and +0 alike */
    memcpy(&u, &x, sizeof u);
    return u;
}

static size_t hash3(const double p[3], size_t mask)
{
    uint64_t h = 1469598103934665603ull;
    for (int c = 0; c < 3; c++) h = (h ^ bits(p[c])) * 1099511628211ull, h ^= h >> 29;
    return (size_t)h & mask;
}

/* Index of the vertex at p (appended when new); -1 out of memory, -2 too many vertices. */
static int weld_vertex(weld *w, const double p[3])
{
    if (2 * (w->d->nv + 1) > w->cap) {
        size_t nc = w->cap ? 2 * w->cap : 1024;
        int *ns = malloc(sizeof(int) * nc);
        if (!ns) return -1;
        for (size_t i = 0; i < nc; i++) ns[i] = -1;
        for (size_t v = 0; v < w->d->nv; v++) {
            size_t i = hash3(w->d->pos + 3 * v, nc - 1);
            while (ns[i] >= 0) i = (i + 1) & (nc - 1);
            ns[i] = (int)v;
        }
        free(w->slot);
        w->slot = ns, w->cap = nc;
    }
    size_t i = hash3(p, w->cap - 1);
    for (; w->slot[i] >= 0; i = (i + 1) & (w->cap - 1)) {
        const double *q = w->d->pos + 3 * (size_t)w->slot[i];
        if (bits(q[0]) == bits(p[0]) && bits(q[1]) == bits(p[1]) && bits(q[2]) == bits(p[2])) return w->slot[i];
    }
    int r = q2n_rd_add_vertex(w->d, p);
    if (r) return r;
    w->slot[i] = (int)(w->d->nv - 1);
    return w->slot[i];
}

/* One facet: its three corners welded, the triangle appended (line: its "facet" line, 0 in binary). */
static int add_facet(weld *w, const double c[3][3], long line)
{
    int idx[3];
    for (int k = 0; k < 3; k++)
        if ((idx[k] = weld_vertex(w, c[k])) < 0) return idx[k];
    return q2n_rd_add_face(w->d, idx, 3, line);
}

static float le_float(const unsigned char *b)
{
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static q2n_status parse_binary(const unsigned char *b, uint32_t n, const char *name, weld *w, q2n_error *err)
{
    for (uint32_t k = 0; k < n; k++) {
        const unsigned char *r = b + 84 + 50 * (size_t)k;
        double c[3][3];
        for (int v = 0; v < 3; v++)
            for (int j = 0; j < 3; j++) {
                c[v][j] = le_float(r + 12 + 12 * v + 4 * j);
                if (!isfinite(c[v][j]))
                    return q2n_error_set(err, Q2N_ERR_PARSE, "%s: facet %u (byte %zu): non-finite coordinate (NaN/Inf)",
                                         name, k, 84 + 50 * (size_t)k + 12 + 12 * (size_t)v + 4 * (size_t)j);
            }
        int st = add_facet(w, (const double (*)[3])c, 0);
        if (st) return q2n_error_set(err, st == -1 ? Q2N_ERR_NOMEM : Q2N_ERR_UNSUPPORTED, "%s: facet %u: %s", name, k,
                                     st == -1 ? "out of memory" : "more than 2^31-2 vertices or faces");
    }
    return Q2N_OK;
}

static q2n_status parse_ascii(const char *data, size_t len, const char *name, weld *w, q2n_error *err)
{
    rd_lines l = {data, data + len, 0, NULL, 0, 0};
    char *s, q[48];
    int in_facet = 0, nvert = 0, solids = 0;
    long facet_line = 0;
    double c[3][3];
    q2n_status st = Q2N_OK;
    for (int r; (r = q2n_rd_next_line(&l, &s)) != 0;) {
        if (r < 0) {
            st = r == -1 ? q2n_error_set(err, Q2N_ERR_NOMEM, "%s:%ld: out of memory", name, l.line)
                         : q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: NUL byte in line", name, l.line);
            break;
        }
        char *cur = s, *t = q2n_rd_tok(&cur);
        if (!t) continue;
        if (!strcasecmp(t, "solid")) {
            if (in_facet) { st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: \"solid\" inside a facet", name, l.line); break; }
            solids++;
        } else if (!strcasecmp(t, "facet")) {
            if (in_facet) { st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: \"facet\" before \"endfacet\"", name, l.line); break; }
            in_facet = 1, nvert = 0, facet_line = l.line;
        } else if (!strcasecmp(t, "vertex")) {
            if (!in_facet) { st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: \"vertex\" outside a facet", name, l.line); break; }
            if (nvert == 3) {
                st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s:%ld: a facet with more than 3 vertices (STL facets are "
                                   "triangles)", name, l.line);
                break;
            }
            for (int j = 0; j < 3 && !st; j++) {
                char *x = q2n_rd_tok(&cur);
                int rr = x ? q2n_rd_double(x, &c[nvert][j]) : -1;
                if (rr == -1)
                    st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: bad vertex coordinate '%s' (need \"vertex x y z\")",
                                       name, l.line, x ? q2n_rd_quote(x, q, sizeof q) : "");
                else if (rr == -2)
                    st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: non-finite coordinate '%s' (NaN/Inf or out of "
                                       "double range)", name, l.line, q2n_rd_quote(x, q, sizeof q));
            }
            if (st) break;
            nvert++;
        } else if (!strcasecmp(t, "endfacet")) {
            if (!in_facet) { st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: \"endfacet\" without \"facet\"", name, l.line); break; }
            if (nvert != 3) {
                st = q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s:%ld: a facet with %d vert%s (STL facets are triangles)", name,
                                   facet_line, nvert, nvert == 1 ? "ex" : "ices");
                break;
            }
            int rr = add_facet(w, (const double (*)[3])c, facet_line);
            if (rr) {
                st = q2n_error_set(err, rr == -1 ? Q2N_ERR_NOMEM : Q2N_ERR_UNSUPPORTED, "%s:%ld: %s", name, facet_line,
                                   rr == -1 ? "out of memory" : "more than 2^31-2 vertices or faces");
                break;
            }
            in_facet = 0;
        } else if (strcasecmp(t, "outer") && strcasecmp(t, "endloop") && strcasecmp(t, "endsolid")) {
            st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: unexpected '%s' in an ASCII STL file", name, l.line,
                               q2n_rd_quote(t, q, sizeof q));
            break;
        }
    }
    if (!st && in_facet) st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:%ld: the file ends inside a facet", name, facet_line);
    if (!st && !solids) st = q2n_error_set(err, Q2N_ERR_PARSE, "%s:1: not an ASCII STL file (no \"solid\" line)", name);
    q2n_rd_lines_free(&l);
    return st;
}

q2n_status q2n_mesh_parse_stl(const char *data, size_t len, const char *name, q2n_mesh **out, q2n_error *err)
{
    *out = NULL;
    const unsigned char *b = (const unsigned char *)data;
    uint32_t n = len >= 84 ? (uint32_t)b[80] | (uint32_t)b[81] << 8 | (uint32_t)b[82] << 16 | (uint32_t)b[83] << 24 : 0;
    int binary = len >= 84 && (size_t)n <= (len - 84) / 50 && 84 + 50 * (size_t)n == len;
    if (!binary && len >= 3 && !memcmp(data, "\xEF\xBB\xBF", 3)) data += 3, len -= 3; /* ASCII after a UTF-8 BOM */
    int ascii = !binary && len >= 5 && !strncasecmp(data, "solid", 5) && (len == 5 || data[5] == ' ' || data[5] == '\t' ||
                                                                      data[5] == '\n' || data[5] == '\r');
    if (!binary && !ascii) {
        if (len < 84) return q2n_error_set(err, Q2N_ERR_PARSE, "%s: not an STL file (%zu bytes: too short for a binary "
                                           "header, and not ASCII \"solid\")", name, len);
        return q2n_error_set(err, Q2N_ERR_PARSE, "%s: binary STL of %u facets should be %zu bytes, the file has %zu "
                             "(truncated or not STL)", name, n, 84 + 50 * (size_t)n, len);
    }
    rd_mesh d;
    memset(&d, 0, sizeof d);
    weld w = {&d, NULL, 0};
    void *old = NULL, *loc = q2n_rd_locale_begin(&old);
    q2n_status st = binary ? parse_binary(b, n, name, &w, err) : parse_ascii(data, len, name, &w, err);
    q2n_rd_locale_end(loc, old);
    free(w.slot);
    if (st) { q2n_rd_free(&d); return st; }
    if (!d.nf) {
        q2n_rd_free(&d);
        return q2n_error_set(err, Q2N_ERR_TOPOLOGY, "%s: no facets", name);
    }
    return q2n_rd_finish(&d, name, out, err);
}
