/* iges_writer.c — IGES 5.3 writer for a q2n_nurbs_model (US PRO/IPO-100, 1996).
 *
 * File layout (§2.1): fixed 80-column records; columns 1-72 data, 73 the section letter
 * (S, G, D, P, T), 74-80 the sequence number.  Directory entries (§2.2.4) are two records of ten
 * 8-column fields; parameter data (§2.2.5) uses columns 1-64 with the entity's directory pointer
 * in columns 66-72.  Entities written, in this order:
 *   128 Rational B-Spline Surface (§4.24), one per patch, in patch order (DE 1, 3, 5, ...);
 * unless iges_plain, the shared-edge B-rep of §4.139-4.149 after them:
 *   126 Rational B-Spline Curve (§4.23), one per mesh edge (the patch boundary);
 *   502 Vertex List form 1, 504 Edge List form 1 (one each);
 *   110 Line in parameter space (entity use 05) per face side, 508 Loop form 1 (4 edges, each
 *   with its isoparametric p-curve), 510 Face form 1, one per patch; 514 Shell (form 1 closed, 2 open) per connected component; 186
 *   Manifold Solid B-Rep Object per closed component.
 * Only the top-level entities (128s when plain, otherwise 186 / open 514) are independent;
 * the rest are physically dependent (status digits 3-4 = 01). */
#include "iges/export_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { IGES_PCOLS = 64, IGES_GCOLS = 72 };

typedef struct iges_ent {
    int type, form, dependent;
    int pstart, pcount;   /* first parameter record and number of records */
    int use;              /* entity use flag (status digits 5-6): 0 geometry, 5 2D parametric */
} iges_ent;

/* Parameter writer: tokens are packed into 64-column records and never split (a %.17g real is
 * at most 25 characters).  The token before the next one gets ',', the last one ';'. */
typedef struct iges_pw {
    q2n_strbuf *b;
    int line_len;       /* characters in the current record */
    int pseq;           /* last P sequence number written */
    int de;             /* directory pointer of the entity being written */
    char pending[Q2N_REAL_CHARS + 8];
    int has_pending;
} iges_pw;

static const char blanks[IGES_PCOLS + 1] = "                                                                ";

/* " %7dP%7d\n": the parameter record's directory pointer and sequence number */
static int fmt_pd_suffix(char *out, int de, int seq)
{
    int n = 0;
    out[n++] = ' ';
    n += q2n_export_fmt_int(out + n, de, 7);
    out[n++] = 'P';
    n += q2n_export_fmt_int(out + n, seq, 7);
    out[n++] = '\n';
    return n;
}

static void pw_end_line(iges_pw *w)
{
    char suf[40];
    if (w->line_len < IGES_PCOLS) q2n_strbuf_putn(w->b, blanks, (size_t)(IGES_PCOLS - w->line_len));
    q2n_strbuf_putn(w->b, suf, (size_t)fmt_pd_suffix(suf, w->de, ++w->pseq));
    w->line_len = 0;
}

static void pw_flush(iges_pw *w, char delim)
{
    if (!w->has_pending) return;
    size_t len = strlen(w->pending);
    int n = (int)len + 1;
    if (w->line_len + n > IGES_PCOLS) pw_end_line(w);
    w->pending[len] = delim;
    q2n_strbuf_putn(w->b, w->pending, len + 1);
    w->line_len += n;
    w->has_pending = 0;
}

static void pw_token(iges_pw *w, const char *s)
{
    pw_flush(w, ',');
    size_t n = strlen(s);
    if (n > sizeof w->pending - 2) n = sizeof w->pending - 2;   /* never: tokens are reals and ints */
    memcpy(w->pending, s, n);
    w->pending[n] = '\0';
    w->has_pending = 1;
}

static void pw_int(iges_pw *w, int x)
{
    char s[16];
    s[q2n_export_fmt_int(s, x, 0)] = '\0';
    pw_token(w, s);
}

static void pw_real(iges_pw *w, double x)
{
    char s[Q2N_REAL_CHARS];
    q2n_export_fmt_real(s, x);
    pw_token(w, s);
}

static void pw_begin(iges_pw *w, iges_ent *e, int de)
{
    w->de = de;
    w->line_len = 0;
    w->has_pending = 0;
    e->pstart = w->pseq + 1;
    pw_int(w, e->type);
}

static void pw_end(iges_pw *w, iges_ent *e)
{
    pw_flush(w, ';');
    if (w->line_len > 0) pw_end_line(w);
    e->pcount = w->pseq - e->pstart + 1;
}

/* 128: K1, K2, M1, M2, PROP1..5, knots S, knots T, weights, control points (u fastest), U0, U1, V0, V1 */
static void write_128(iges_pw *w, const q2n_bspline_surface *s)
{
    int nu = s->ncp_u, nv = s->ncp_v;
    pw_int(w, nu - 1); pw_int(w, nv - 1);
    pw_int(w, s->deg_u); pw_int(w, s->deg_v);
    pw_int(w, 0); pw_int(w, 0);                  /* not closed in u, v */
    pw_int(w, s->weights ? 0 : 1);               /* PROP3: 1 = polynomial (all weights equal) */
    pw_int(w, 0); pw_int(w, 0);                  /* not periodic */
    for (int i = 0; i < nu + s->deg_u + 1; i++) pw_real(w, s->knots_u[i]);
    for (int i = 0; i < nv + s->deg_v + 1; i++) pw_real(w, s->knots_v[i]);
    size_t n = (size_t)nu * (size_t)nv;
    for (size_t k = 0; k < n; k++) pw_real(w, s->weights ? s->weights[k] : 1.0);
    for (size_t k = 0; k < n; k++)
        for (int c = 0; c < 3; c++) pw_real(w, s->cp[3 * k + c]);
    pw_real(w, s->knots_u[s->deg_u]); pw_real(w, s->knots_u[nu]);
    pw_real(w, s->knots_v[s->deg_v]); pw_real(w, s->knots_v[nv]);
}

/* 126: K, M, PROP1..4, knots, weights, control points, V0, V1, unit normal (unused: not planar) */
static void write_126(iges_pw *w, const q2n_export_curve *c)
{
    pw_int(w, c->ncp - 1); pw_int(w, c->deg);
    pw_int(w, 0); pw_int(w, 0);                  /* not planar, not closed */
    pw_int(w, c->weights ? 0 : 1);               /* polynomial */
    pw_int(w, 0);                                /* not periodic */
    for (int i = 0; i < c->ncp + c->deg + 1; i++) pw_real(w, c->knots[i]);
    for (int i = 0; i < c->ncp; i++) pw_real(w, c->weights ? c->weights[i] : 1.0);
    for (int i = 0; i < 3 * c->ncp; i++) pw_real(w, c->cp[i]);
    pw_real(w, c->knots[c->deg]); pw_real(w, c->knots[c->ncp]);
    pw_real(w, 0.0); pw_real(w, 0.0); pw_real(w, 0.0);
}

/* Hollerith string nHxxx (§2.2.2.4) */
static void hollerith(char *out, size_t cap, const char *s)
{
    snprintf(out, cap, "%zuH%s", strlen(s), s);
}

/* Global section (§2.2.4): 26 fields packed into 72-column G records. */
static void write_global(q2n_strbuf *b, const q2n_export_options *opt, const char *name, const q2n_export_topo *t)
{
    char f[26][160];
    int nf = 0;
    hollerith(f[nf++], sizeof f[0], ",");                       /* 1 parameter delimiter */
    hollerith(f[nf++], sizeof f[0], ";");                       /* 2 record delimiter */
    hollerith(f[nf++], sizeof f[0], name);                      /* 3 product id (sender) */
    hollerith(f[nf++], sizeof f[0], name);                      /* 4 file name */
    hollerith(f[nf++], sizeof f[0], "quad2nurbs");              /* 5 native system */
    hollerith(f[nf++], sizeof f[0], "quad2nurbs IGES writer");  /* 6 preprocessor version */
    snprintf(f[nf++], sizeof f[0], "32");                       /* 7 integer bits */
    snprintf(f[nf++], sizeof f[0], "308");                      /* 8-11 float ranges: IEEE double */
    snprintf(f[nf++], sizeof f[0], "15");
    snprintf(f[nf++], sizeof f[0], "308");
    snprintf(f[nf++], sizeof f[0], "15");
    hollerith(f[nf++], sizeof f[0], name);                      /* 12 product id (receiver) */
    snprintf(f[nf++], sizeof f[0], "1.");                       /* 13 model space scale */
    char date[32];
    q2n_export_date(opt, 1, date);                              /* "" when none: deterministic output */
    snprintf(f[nf++], sizeof f[0], "%d", q2n_units_iges_flag(opt->units));     /* 14 units flag */
    hollerith(f[nf++], sizeof f[0], q2n_units_iges_name(opt->units));          /* 15 units name */
    snprintf(f[nf++], sizeof f[0], "1");                        /* 16 line weight gradations */
    q2n_export_fmt_real(f[nf++], 0.01);                         /* 17 width of the heaviest line (unused) */
    hollerith(f[nf++], sizeof f[0], date);                      /* 18 date of generation */
    q2n_export_fmt_real(f[nf++], t->resolution);                /* 19 minimum resolution */
    q2n_export_fmt_real(f[nf++], t->max_coord);                 /* 20 max coordinate value */
    hollerith(f[nf++], sizeof f[0], opt->author ? opt->author : "");          /* 21 author */
    hollerith(f[nf++], sizeof f[0], opt->organization ? opt->organization : ""); /* 22 organization */
    snprintf(f[nf++], sizeof f[0], "11");                       /* 23 version: 5.3 */
    snprintf(f[nf++], sizeof f[0], "0");                        /* 24 drafting standard: none */
    hollerith(f[nf++], sizeof f[0], date);                      /* 25 date the model was made */
    f[nf++][0] = '\0';                                          /* 26 protocol: none */
    /* a Hollerith "0H" is not valid: empty strings are written as defaulted (empty) fields */
    for (int i = 0; i < nf; i++)
        if (strcmp(f[i], "0H") == 0) f[i][0] = '\0';
    int len = 0, seq = 0;
    for (int i = 0; i < nf; i++) {
        int n = (int)strlen(f[i]) + 1;
        if (len + n > IGES_GCOLS) {
            for (; len < IGES_GCOLS; len++) q2n_strbuf_putc(b, ' ');
            q2n_strbuf_printf(b, "G%7d\n", ++seq);
            len = 0;
        }
        q2n_strbuf_puts(b, f[i]);
        q2n_strbuf_putc(b, i == nf - 1 ? ';' : ',');
        len += n;
    }
    for (; len < IGES_GCOLS; len++) q2n_strbuf_putc(b, ' ');
    q2n_strbuf_printf(b, "G%7d\n", ++seq);
}

static void write_directory(q2n_strbuf *b, const iges_ent *ents, int n)
{
    char line[200];
    for (int k = 0; k < n; k++) {
        const iges_ent *e = &ents[k];
        /* status: blank 00, subordinate 00/01, entity use 00 (geometry) / 05 (2D parametric), hierarchy 00;
         * as printf("%8d%8d%8d%8d%8d%8d%8d%8d00%02d%02d00D%7d\n", type, pstart, 0, .., dependent, use, 2k+1) */
        int m = 0;
        const int f1[8] = {e->type, e->pstart, 0, 0, 0, 0, 0, 0};
        for (int i = 0; i < 8; i++) m += q2n_export_fmt_int(line + m, f1[i], 8);
        line[m++] = '0'; line[m++] = '0';
        line[m++] = '0'; line[m++] = (char)('0' + (e->dependent ? 1 : 0));
        line[m++] = (char)('0' + e->use / 10); line[m++] = (char)('0' + e->use % 10);
        line[m++] = '0'; line[m++] = '0'; line[m++] = 'D';
        m += q2n_export_fmt_int(line + m, 2 * k + 1, 7);
        line[m++] = '\n';
        /* printf("%8d%8d%8d%8d%8d%8s%8s%8s%8dD%7d\n", type, 0, 0, pcount, form, "", "", "", 0, 2k+2) */
        const int f2[5] = {e->type, 0, 0, e->pcount, e->form};
        for (int i = 0; i < 5; i++) m += q2n_export_fmt_int(line + m, f2[i], 8);
        memset(line + m, ' ', 24);
        m += 24;
        m += q2n_export_fmt_int(line + m, 0, 8);
        line[m++] = 'D';
        m += q2n_export_fmt_int(line + m, 2 * k + 2, 7);
        line[m++] = '\n';
        q2n_strbuf_putn(b, line, (size_t)m);
    }
}

/* Entity indices of the B-rep part; DE pointer of index k is 2k+1. */
typedef struct iges_layout {
    int n128, c126, i502, i504, c110, c508, c510, c514, c186, nent;
} iges_layout;

static iges_layout layout(const q2n_export_topo *t, int plain)
{
    iges_layout L;
    int nclosed = 0;
    for (int c = 0; c < t->ncomp; c++) nclosed += t->comp_closed[c];
    L.n128 = t->nf;
    if (plain) {
        L.nent = t->nf;
        L.c126 = L.i502 = L.i504 = L.c110 = L.c508 = L.c510 = L.c514 = L.c186 = L.nent;
        return L;
    }
    L.c126 = L.n128;
    L.i502 = L.c126 + t->ne;
    L.i504 = L.i502 + 1;
    L.c110 = L.i504 + 1;
    L.c508 = L.c110 + 4 * t->nf;
    L.c510 = L.c508 + t->nf;
    L.c514 = L.c510 + t->nf;
    L.c186 = L.c514 + t->ncomp;
    L.nent = L.c186 + nclosed;
    return L;
}

#define DE(k) (2 * (k) + 1)

/* ---- entities formatted on worker threads ----
 * The parameter data of the many per-face and per-edge entities (128, 126, 110, 508, 510) are
 * formatted on opt->threads workers (q2n_export_items), each into its own buffer as if it were the
 * file's first entity (P sequence numbers from 1); the buffers are appended in entity order with
 * every record's sequence number rewritten to its place in the file, so the text is the one a
 * single thread writes. */
typedef struct iges_items {
    const q2n_nurbs_model *m;
    const q2n_export_topo *t;
    const iges_layout *L;
    iges_ent *ents;
    int kind;             /* 128, 126, 110, 508, 510 */
    int plain;            /* 128s only (they are then independent) */
    int first;            /* entity index of item 0 */
    iges_pw *w;           /* the parameter section being written */
} iges_items;

static void format_item(const iges_items *J, iges_pw *w, iges_ent *en, int k)
{
    const q2n_mesh *me = J->m->mesh;
    const iges_layout *L = J->L;
    switch (J->kind) {
    case 128:
        *en = (iges_ent){128, 0, !J->plain, 0, 0, 0};
        pw_begin(w, en, DE(k));
        write_128(w, &J->m->patches[k]);
        break;
    case 126:
        *en = (iges_ent){126, 0, 1, 0, 0, 0};
        pw_begin(w, en, DE(L->c126 + k));
        write_126(w, &J->t->edge_curve[k]);
        break;
    case 110: {   /* side i of face f runs from corner i to corner i+1 of [0,1]^2 in (u,v,0), the loop's
                   * direction (as OCCT's own B-rep writer does) */
        const int(*corner)[2] = q2n_corner_uv;
        int i = k & 3;
        *en = (iges_ent){110, 0, 1, 0, 0, 5};
        pw_begin(w, en, DE(L->c110 + k));
        pw_real(w, corner[i][0]); pw_real(w, corner[i][1]); pw_real(w, 0.0);
        pw_real(w, corner[(i + 1) & 3][0]); pw_real(w, corner[(i + 1) & 3][1]); pw_real(w, 0.0);
        break;
    }
    case 508:     /* per edge type 0, list, index, orientation (1 = along the curve), one isoparametric
                   * p-curve (K = 1, ISOP = 1) */
        *en = (iges_ent){508, 1, 1, 0, 0, 0};
        pw_begin(w, en, DE(L->c508 + k));
        pw_int(w, 4);
        for (int i = 0; i < 4; i++) {
            int h = q2n_face_he(me, k, i);
            pw_int(w, 0); pw_int(w, DE(L->i504)); pw_int(w, me->he_edge[h] + 1);
            pw_int(w, J->t->he_sense[h]); pw_int(w, 1); pw_int(w, 1); pw_int(w, DE(L->c110 + 4 * k + i));
        }
        break;
    default:      /* 510: surface, one loop, outer-loop flag 1 */
        *en = (iges_ent){510, 1, 1, 0, 0, 0};
        pw_begin(w, en, DE(L->c510 + k));
        pw_int(w, DE(k)); pw_int(w, 1); pw_int(w, 1); pw_int(w, DE(L->c508 + k));
        break;
    }
    pw_end(w, en);
}

static void iges_item(void *arg, int k, q2n_strbuf *b)
{
    iges_items *J = arg;
    iges_pw w = {b, 0, 0, 0, {0}, 0};
    format_item(J, &w, &J->ents[J->first + k], k);   /* pstart relative to b, set when appended */
}

/* Append src's records to w's stream with their sequence numbers (1, 2, .. in src) moved after
 * w's last one. */
static void append_records(iges_pw *w, const q2n_strbuf *src)
{
    const char *p = src->data, *end = src->data + src->len;
    int r = 0;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl) break;
        char num[24];
        int lr = q2n_export_fmt_int(num, ++r, 7) + 1, la = q2n_export_fmt_int(num, ++w->pseq, 7);   /* "%7d\n" */
        num[la++] = '\n';
        q2n_strbuf_putn(w->b, p, (size_t)(nl + 1 - p) - (size_t)lr);
        q2n_strbuf_putn(w->b, num, (size_t)la);
        p = nl + 1;
    }
}

static int iges_put(void *arg, int k, const q2n_strbuf *b)
{
    iges_items *J = arg;
    J->ents[J->first + k].pstart = J->w->pseq + 1;
    append_records(J->w, b);
    return J->w->b->oom;
}

/* Items [0, n) of one kind into ents[first ..], appended in order. */
static void iges_items_run(iges_pw *w, iges_items *J, int first, int n, const q2n_export_options *opt)
{
    J->first = first;
    J->w = w;
    if (q2n_export_items(n, opt->threads, J, iges_item, iges_put, opt->progress, J->kind == 128 ? "IGES" : NULL))
        w->b->oom = 1;
}

static void write_brep(iges_pw *w, iges_ent *ents, const iges_layout *L, const q2n_nurbs_model *m,
                       const q2n_export_topo *t, const q2n_export_options *opt)
{
    iges_items J = {m, t, L, ents, 126, 0, 0, NULL};
    iges_items_run(w, &J, L->c126, t->ne, opt);
    /* 502: all mesh vertices (index v+1); unused ones are harmless but keep the numbering simple */
    iges_ent *vl = &ents[L->i502];
    *vl = (iges_ent){502, 1, 1, 0, 0, 0};
    pw_begin(w, vl, DE(L->i502));
    pw_int(w, t->nv);
    for (int i = 0; i < 3 * t->nv; i++) pw_real(w, t->vpos[i]);
    pw_end(w, vl);
    /* 504: edge e (index e+1) = curve, start vertex, end vertex */
    iges_ent *el = &ents[L->i504];
    *el = (iges_ent){504, 1, 1, 0, 0, 0};
    pw_begin(w, el, DE(L->i504));
    pw_int(w, t->ne);
    for (int e = 0; e < t->ne; e++) {
        pw_int(w, DE(L->c126 + e));
        pw_int(w, DE(L->i502)); pw_int(w, t->edge_v[2 * e] + 1);
        pw_int(w, DE(L->i502)); pw_int(w, t->edge_v[2 * e + 1] + 1);
    }
    pw_end(w, el);
    /* 110 parameter-space lines (2D parametric use, §4.13), one per face side; 508 loops; 510 faces */
    J.kind = 110;
    iges_items_run(w, &J, L->c110, 4 * t->nf, opt);
    J.kind = 508;
    iges_items_run(w, &J, L->c508, t->nf, opt);
    J.kind = 510;
    iges_items_run(w, &J, L->c510, t->nf, opt);
    /* 514 shells per component (faces agree with their surfaces: flag 1, except in inward closed
     * components: 0); 186 for closed ones */
    int k186 = L->c186;
    for (int c = 0; c < t->ncomp; c++) {
        int n = 0;
        for (int f = 0; f < t->nf; f++) n += t->face_comp[f] == c;
        iges_ent *en = &ents[L->c514 + c];
        *en = (iges_ent){514, t->comp_closed[c] ? 1 : 2, t->comp_closed[c], 0, 0, 0};
        pw_begin(w, en, DE(L->c514 + c));
        pw_int(w, n);
        for (int f = 0; f < t->nf; f++)
            if (t->face_comp[f] == c) { pw_int(w, DE(L->c510 + f)); pw_int(w, !t->comp_inward[c]); }
        pw_end(w, en);
        if (!t->comp_closed[c]) continue;
        iges_ent *so = &ents[k186];
        *so = (iges_ent){186, 0, 0, 0, 0, 0};
        pw_begin(w, so, DE(k186));
        pw_int(w, DE(L->c514 + c)); pw_int(w, 1); pw_int(w, 0);
        pw_end(w, so);
        k186++;
    }
}

static q2n_status iges_build(const q2n_nurbs_model *m, const q2n_export_topo *t, const q2n_export_options *opt,
                             const char *name, q2n_strbuf *out)
{
    iges_layout L = layout(t, opt->iges_plain);
    iges_ent *ents = calloc((size_t)L.nent, sizeof(iges_ent));
    /* the parameter section comes last but must be written first (the directory before it points
     * into it): when the file is a stream it goes to an anonymous temporary file and is copied
     * after the directory, so no copy of the file is held in memory; else into memory */
    q2n_strbuf pb = {0}, b = *out;
    if (!ents) return Q2N_ERR_NOMEM;
    if (b.fp) pb.fp = tmpfile();
    iges_pw w = {&pb, 0, 0, 0, {0}, 0};
    iges_items J = {m, t, &L, ents, 128, opt->iges_plain, 0, NULL};
    iges_items_run(&w, &J, 0, t->nf, opt);
    if (!opt->iges_plain) write_brep(&w, ents, &L, m, t, opt);

    /* Start section: one line of free text */
    char start[80];
    snprintf(start, sizeof start, "quad2nurbs: %d B-spline surface(s), one per mesh face", t->nf);
    q2n_strbuf_printf(&b, "%-72.72sS%7d\n", start, 1);
    size_t g0 = b.len;
    write_global(&b, opt, name, t);
    int gcount = (int)((b.len - g0) / 81);
    write_directory(&b, ents, L.nent);
    int bad = 0;
    if (pb.fp) { /* the parameter section back from its temporary file */
        char chunk[1 << 16];
        size_t n;
        bad = fflush(pb.fp) != 0 || ferror(pb.fp) || fseek(pb.fp, 0, SEEK_SET) != 0;
        while (!bad && (n = fread(chunk, 1, sizeof chunk, pb.fp)) > 0) q2n_strbuf_putn(&b, chunk, n);
        bad |= ferror(pb.fp);
        fclose(pb.fp);
        pb.fp = NULL;
    } else {
        q2n_strbuf_putn(&b, pb.data ? pb.data : "", pb.len);
    }
    q2n_strbuf_printf(&b, "S%7dG%7dD%7dP%7d%40sT%7d\n", 1, gcount, 2 * L.nent, w.pseq, "", 1);
    if (bad && b.fp) b.oom = 1; /* a failed temporary: reported like a failed allocation */
    int oom = b.oom || pb.oom;
    q2n_strbuf_free(&pb);
    free(ents);
    *out = b;
    return oom ? Q2N_ERR_NOMEM : Q2N_OK;
}

q2n_status q2n_export_iges_text(const q2n_nurbs_model *m, const q2n_export_options *opts, char **text,
                                size_t *len, q2n_error *err)
{
    return q2n_export_text("IGES", iges_build, m, opts, text, len, err);
}

q2n_status q2n_export_iges(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                           q2n_error *err)
{
    return q2n_export_write("IGES", iges_build, m, opts, path, err);
}

static int ends_with_ci(const char *s, const char *suf)
{
    size_t n = strlen(s), k = strlen(suf);
    if (k > n) return 0;
    for (size_t i = 0; i < k; i++) {
        char a = s[n - k + i], c = suf[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (a != c) return 0;
    }
    return 1;
}

q2n_status q2n_export_file(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                           q2n_error *err)
{
    if (!path) return q2n_error_set(err, Q2N_ERR_ARG, "export: no output path");
    if (ends_with_ci(path, ".igs") || ends_with_ci(path, ".iges")) return q2n_export_iges(m, opts, path, err);
    if (ends_with_ci(path, ".step") || ends_with_ci(path, ".stp")) return q2n_export_step(m, opts, path, err);
    return q2n_error_set(err, Q2N_ERR_ARG, "%s: unknown output format (use .igs, .iges, .step or .stp)", path);
}

q2n_status q2n_export_stream(const q2n_nurbs_model *m, const q2n_export_options *opts, int iges, const char *path,
                             FILE *f, q2n_error *err)
{
    return iges ? q2n_export_to_stream("IGES", iges_build, m, opts, path, f, err)
                : q2n_export_step_stream(m, opts, path, f, err);
}
