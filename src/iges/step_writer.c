/* step_writer.c — STEP AP214 (ISO 10303-21 exchange structure) writer for a q2n_nurbs_model.
 *
 * Entity graph (ISO 10303-42 topology/geometry, AP214 product structure):
 *   patch  -> B_SPLINE_SURFACE_WITH_KNOTS (complex rational form when weights are given)
 *   edge   -> EDGE_CURVE(VERTEX_POINT, VERTEX_POINT, B_SPLINE_CURVE_WITH_KNOTS, .T.), one per mesh edge
 *   face   -> ADVANCED_FACE((FACE_OUTER_BOUND(EDGE_LOOP(4 ORIENTED_EDGEs), .T.)), surface, .T.)
 *   comp.  -> CLOSED_SHELL -> MANIFOLD_SOLID_BREP (all components closed) or
 *             OPEN_SHELL / CLOSED_SHELL -> SHELL_BASED_SURFACE_MODEL
 *   root   -> ADVANCED_BREP_SHAPE_REPRESENTATION / MANIFOLD_SURFACE_SHAPE_REPRESENTATION in a
 *             GEOMETRIC_REPRESENTATION_CONTEXT with units and GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT,
 *             tied to PRODUCT / PRODUCT_DEFINITION by SHAPE_DEFINITION_REPRESENTATION.
 * Control points and vertices are CARTESIAN_POINTs written once per distinct coordinate triple
 * (the same bits) and referenced by every curve, surface and vertex that has them: a boundary row
 * that is its edge curve bit for bit (docs/fit.md, "Exactness") is the same entities in both faces
 * and the curve, so shared boundaries are shared in the file (8-41 % fewer bytes: docs/export.md).
 * The face loop runs v0 -> v1 -> v2 -> v3, counter-clockwise about Su x Sv, so every face keeps
 * the surface's sense and the mesh orientation becomes the shell orientation — except in a closed
 * component oriented inwards (negative enclosed volume), whose faces are written reversed so that
 * every solid's normals point out. */
#include "iges/export_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct step_out {
    q2n_strbuf b;
    int next_id;
} step_out;

/* pre, then "#id", then post (printf-free: the writer's most frequent output) */
static void put_ref(q2n_strbuf *b, char pre, int id, char post)
{
    char s[24];
    int n = 0;
    if (pre) s[n++] = pre;
    s[n++] = '#';
    n += q2n_export_fmt_int(s + n, id, 0);
    if (post) s[n++] = post;
    q2n_strbuf_putn(b, s, (size_t)n);
}

static int step_begin(step_out *o)
{
    int id = o->next_id++;
    put_ref(&o->b, 0, id, '=');
    return id;
}

static void put_real(q2n_strbuf *b, double x)
{
    char s[Q2N_REAL_CHARS];
    q2n_export_fmt_real(s, x);
    q2n_strbuf_puts(b, s);
}

static int step_point(step_out *o, const double p[3])
{
    int id = step_begin(o);
    q2n_strbuf_puts(&o->b, "CARTESIAN_POINT('',(");
    for (int c = 0; c < 3; c++) {
        if (c) q2n_strbuf_putc(&o->b, ',');
        put_real(&o->b, p[c]);
    }
    q2n_strbuf_puts(&o->b, "));\n");
    return id;
}

static void put_id_list(q2n_strbuf *b, const int *ids, int n)
{
    q2n_strbuf_putc(b, '(');
    for (int i = 0; i < n; i++) put_ref(b, i ? ',' : 0, ids[i], 0);
    q2n_strbuf_putc(b, ')');
}

/* "(mults),(knots)" of a clamped knot vector */
static int put_knots(q2n_strbuf *b, const double *knots, int n, int want_mults)
{
    double *kn = malloc(sizeof(double) * (size_t)n);
    int *mu = malloc(sizeof(int) * (size_t)n);
    if (!kn || !mu) { free(kn); free(mu); b->oom = 1; return 0; }
    int m = q2n_export_knot_mults(knots, n, kn, mu);
    q2n_strbuf_putc(b, '(');
    for (int i = 0; i < m; i++) {
        if (i) q2n_strbuf_putc(b, ',');
        if (want_mults) {
            char d[16];
            q2n_strbuf_putn(b, d, (size_t)q2n_export_fmt_int(d, mu[i], 0));
        }
        else put_real(b, kn[i]);
    }
    q2n_strbuf_putc(b, ')');
    free(kn);
    free(mu);
    return m;
}

/* B_SPLINE_CURVE_WITH_KNOTS (or the rational complex entity) through the CARTESIAN_POINTs pts */
static int step_curve(step_out *o, const q2n_export_curve *c, const int *pts)
{
    int id = step_begin(o);
    q2n_strbuf *b = &o->b;
    int nk = c->ncp + c->deg + 1;
    if (!c->weights) {
        q2n_strbuf_printf(b, "B_SPLINE_CURVE_WITH_KNOTS('',%d,", c->deg);
        put_id_list(b, pts, c->ncp);
        q2n_strbuf_puts(b, ",.UNSPECIFIED.,.F.,.F.,");
        put_knots(b, c->knots, nk, 1);
        q2n_strbuf_putc(b, ',');
        put_knots(b, c->knots, nk, 0);
        q2n_strbuf_puts(b, ",.UNSPECIFIED.);\n");
    } else {
        /* complex instance: partial entity types in alphabetical order (ISO 10303-21 §11.2.5.3) */
        q2n_strbuf_printf(b, "(BOUNDED_CURVE()B_SPLINE_CURVE(%d,", c->deg);
        put_id_list(b, pts, c->ncp);
        q2n_strbuf_puts(b, ",.UNSPECIFIED.,.F.,.F.)B_SPLINE_CURVE_WITH_KNOTS(");
        put_knots(b, c->knots, nk, 1);
        q2n_strbuf_putc(b, ',');
        put_knots(b, c->knots, nk, 0);
        q2n_strbuf_puts(b, ",.UNSPECIFIED.)CURVE()GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE((");
        for (int i = 0; i < c->ncp; i++) {
            if (i) q2n_strbuf_putc(b, ',');
            put_real(b, c->weights[i]);
        }
        q2n_strbuf_puts(b, "))REPRESENTATION_ITEM(''));\n");
    }
    return id;
}

/* B_SPLINE_SURFACE_WITH_KNOTS through the CARTESIAN_POINTs pts (u fastest, as s->cp):
 * control_points_list is a list over u of lists over v. */
static int step_surface(step_out *o, const q2n_bspline_surface *s, const int *pts)
{
    int id = step_begin(o);
    q2n_strbuf *b = &o->b;
    int rational = s->weights != NULL;
    if (rational) q2n_strbuf_printf(b, "(BOUNDED_SURFACE()B_SPLINE_SURFACE(%d,%d,(", s->deg_u, s->deg_v);
    else q2n_strbuf_printf(b, "B_SPLINE_SURFACE_WITH_KNOTS('',%d,%d,(", s->deg_u, s->deg_v);
    for (int i = 0; i < s->ncp_u; i++) {
        q2n_strbuf_puts(b, i ? ",(" : "(");
        for (int j = 0; j < s->ncp_v; j++)
            put_ref(b, j ? ',' : 0, pts[(size_t)j * (size_t)s->ncp_u + (size_t)i], 0);
        q2n_strbuf_putc(b, ')');
    }
    q2n_strbuf_puts(b, rational ? "),.UNSPECIFIED.,.F.,.F.,.F.)B_SPLINE_SURFACE_WITH_KNOTS("
                                : "),.UNSPECIFIED.,.F.,.F.,.F.,");
    put_knots(b, s->knots_u, s->ncp_u + s->deg_u + 1, 1);
    q2n_strbuf_putc(b, ',');
    put_knots(b, s->knots_v, s->ncp_v + s->deg_v + 1, 1);
    q2n_strbuf_putc(b, ',');
    put_knots(b, s->knots_u, s->ncp_u + s->deg_u + 1, 0);
    q2n_strbuf_putc(b, ',');
    put_knots(b, s->knots_v, s->ncp_v + s->deg_v + 1, 0);
    if (!rational) {
        q2n_strbuf_puts(b, ",.UNSPECIFIED.);\n");
    } else {
        q2n_strbuf_puts(b, ",.UNSPECIFIED.)GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE((");
        for (int i = 0; i < s->ncp_u; i++) {
            q2n_strbuf_puts(b, i ? ",(" : "(");
            for (int j = 0; j < s->ncp_v; j++) {
                if (j) q2n_strbuf_putc(b, ',');
                put_real(b, s->weights[(size_t)j * (size_t)s->ncp_u + (size_t)i]);
            }
            q2n_strbuf_putc(b, ')');
        }
        q2n_strbuf_puts(b, "))REPRESENTATION_ITEM('')SURFACE());\n");
    }
    return id;
}

static void step_header(step_out *o, const q2n_export_options *opt, const char *name)
{
    q2n_strbuf *b = &o->b;
    q2n_strbuf_puts(b, "ISO-10303-21;\nHEADER;\n");
    q2n_strbuf_puts(b, "FILE_DESCRIPTION(('quad2nurbs NURBS surfaces, one face per mesh face'),'2;1');\n");
    char date[32];
    q2n_export_date(opt, 0, date);
    q2n_strbuf_printf(b, "FILE_NAME('%s','%s',('%s'),('%s'),'quad2nurbs','quad2nurbs','');\n", name, date,
                      opt->author ? opt->author : "", opt->organization ? opt->organization : "");
    q2n_strbuf_puts(b, "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n");
}

/* Product structure, units and the representation context; returns the context id and the
 * PRODUCT_DEFINITION_SHAPE id in *pds. */
static int step_context(step_out *o, const q2n_export_options *opt, const char *name, double resolution, int *pds)
{
    q2n_strbuf *b = &o->b;
    int app = step_begin(o);
    q2n_strbuf_puts(b, "APPLICATION_CONTEXT('core data for automotive mechanical design processes');\n");
    step_begin(o);
    q2n_strbuf_printf(b, "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#%d);\n",
                      app);
    int pc = step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT_CONTEXT('',#%d,'mechanical');\n", app);
    int prod = step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT('%s','%s','',(#%d));\n", name, name, pc);
    step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#%d));\n", prod);
    int pdf = step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT_DEFINITION_FORMATION('','',#%d);\n", prod);
    int pdc = step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT_DEFINITION_CONTEXT('part definition',#%d,'design');\n", app);
    int pd = step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT_DEFINITION('design','',#%d,#%d);\n", pdf, pdc);
    *pds = step_begin(o);
    q2n_strbuf_printf(b, "PRODUCT_DEFINITION_SHAPE('','',#%d);\n", pd);

    /* the length unit: metric ones are SI units with a prefix (ISO 10303-41 si_prefix); inch and
     * foot are conversion-based units defined in millimetres */
    static const char *const prefix[Q2N_UNITS_COUNT] = {
        [Q2N_UNITS_MM] = ".MILLI.", [Q2N_UNITS_CM] = ".CENTI.", [Q2N_UNITS_M] = "$"};
    static const char *const conv[Q2N_UNITS_COUNT] = {[Q2N_UNITS_IN] = "INCH", [Q2N_UNITS_FT] = "FOOT"};
    static const char *const conv_mm[Q2N_UNITS_COUNT] = {[Q2N_UNITS_IN] = "25.4", [Q2N_UNITS_FT] = "304.8"};
    int len_unit = step_begin(o);
    q2n_strbuf_printf(b, "(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(%s,.METRE.));\n",
                      conv[opt->units] ? ".MILLI." : prefix[opt->units]);
    if (conv[opt->units]) {
        int lmu = step_begin(o);
        q2n_strbuf_printf(b, "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(%s),#%d);\n", conv_mm[opt->units], len_unit);
        int dim = step_begin(o);
        q2n_strbuf_puts(b, "DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);\n");
        len_unit = step_begin(o);
        q2n_strbuf_printf(b, "(CONVERSION_BASED_UNIT('%s',#%d)LENGTH_UNIT()NAMED_UNIT(#%d));\n", conv[opt->units],
                          lmu, dim);
    }
    int ang = step_begin(o);
    q2n_strbuf_puts(b, "(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.));\n");
    int sol = step_begin(o);
    q2n_strbuf_puts(b, "(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT());\n");
    int unc = step_begin(o);
    q2n_strbuf_puts(b, "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(");
    put_real(b, resolution);
    q2n_strbuf_printf(b, "),#%d,'distance_accuracy_value','fit tolerance');\n", len_unit);
    int ctx = step_begin(o);
    q2n_strbuf_printf(b, "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#%d))"
                         "GLOBAL_UNIT_ASSIGNED_CONTEXT((#%d,#%d,#%d))REPRESENTATION_CONTEXT('%s','3D'));\n",
                      unc, len_unit, ang, sol, name);
    return ctx;
}

/* One face: its surface, four ORIENTED_EDGEs on the shared EDGE_CURVEs, the loop, the bound. */
static int step_face(step_out *o, const q2n_nurbs_model *m, const q2n_export_topo *t, const int *eid, const int *pts,
                     int f)
{
    const q2n_mesh *me = m->mesh;
    int srf = step_surface(o, &m->patches[f], pts), oe[4];
    for (int i = 0; i < 4; i++) {
        int h = q2n_face_he(me, f, i);
        oe[i] = step_begin(o);
        q2n_strbuf_printf(&o->b, "ORIENTED_EDGE('',*,*,#%d,%s);\n", eid[me->he_edge[h]], t->he_sense[h] ? ".T." : ".F.");
    }
    int loop = step_begin(o);
    q2n_strbuf_puts(&o->b, "EDGE_LOOP('',");
    put_id_list(&o->b, oe, 4);
    q2n_strbuf_puts(&o->b, ");\n");
    /* an inward closed component: face normal = -(Su x Sv) and, so that the loop still runs
     * counter-clockwise about it, the bound reversed too (ISO 10303-42 face_bound.orientation) */
    const char *sense = t->comp_inward[t->face_comp[f]] ? ".F." : ".T.";
    int bound = step_begin(o);
    q2n_strbuf_printf(&o->b, "FACE_OUTER_BOUND('',#%d,%s);\n", loop, sense);
    int id = step_begin(o);
    q2n_strbuf_printf(&o->b, "ADVANCED_FACE('',(#%d),#%d,%s);\n", bound, srf, sense);
    return id;
}

/* Shells per component, then the solids or surface model, the shape representation in context
 * ctx and its link to the product (pds).  list has room for max(nf, ncomp) ids. */
static void step_root(step_out *o, const q2n_export_topo *t, const int *fid, int *shell, int *list,
                      const char *name, int ctx, int pds)
{
    for (int c = 0; c < t->ncomp; c++) {
        int n = 0;
        for (int f = 0; f < t->nf; f++)
            if (t->face_comp[f] == c) list[n++] = fid[f];
        shell[c] = step_begin(o);
        q2n_strbuf_puts(&o->b, t->comp_closed[c] ? "CLOSED_SHELL('',": "OPEN_SHELL('',");
        put_id_list(&o->b, list, n);
        q2n_strbuf_puts(&o->b, ");\n");
    }
    int origin_pt = step_point(o, (const double[3]){0, 0, 0});
    int dz = step_begin(o);
    q2n_strbuf_puts(&o->b, "DIRECTION('',(0.,0.,1.));\n");
    int dx = step_begin(o);
    q2n_strbuf_puts(&o->b, "DIRECTION('',(1.,0.,0.));\n");
    int ax = step_begin(o);
    q2n_strbuf_printf(&o->b, "AXIS2_PLACEMENT_3D('',#%d,#%d,#%d);\n", origin_pt, dz, dx);
    int rep;
    if (t->all_closed) {
        for (int c = 0; c < t->ncomp; c++) {
            list[c] = step_begin(o);
            q2n_strbuf_printf(&o->b, "MANIFOLD_SOLID_BREP('',#%d);\n", shell[c]);
        }
        rep = step_begin(o);
        q2n_strbuf_printf(&o->b, "ADVANCED_BREP_SHAPE_REPRESENTATION('%s',(#%d", name, ax);
        for (int c = 0; c < t->ncomp; c++) q2n_strbuf_printf(&o->b, ",#%d", list[c]);
    } else {
        int sbsm = step_begin(o);
        q2n_strbuf_puts(&o->b, "SHELL_BASED_SURFACE_MODEL('',");
        put_id_list(&o->b, shell, t->ncomp);
        q2n_strbuf_puts(&o->b, ");\n");
        rep = step_begin(o);
        q2n_strbuf_printf(&o->b, "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('%s',(#%d,#%d", name, ax, sbsm);
    }
    q2n_strbuf_printf(&o->b, "),#%d);\n", ctx);
    step_begin(o);
    q2n_strbuf_printf(&o->b, "SHAPE_DEFINITION_REPRESENTATION(#%d,#%d);\n", pds, rep);
}

/* Edges and faces are formatted on opt->threads workers (q2n_export_items), each item into its
 * own buffer starting at its own first entity id, and appended in order: the ids an item takes
 * are known in advance (an edge: its curve's points, the curve, the EDGE_CURVE; a face: its
 * surface's points, the surface, four ORIENTED_EDGEs, the loop, the bound, the face), so the text
 * is the one a single thread writes. */
typedef struct step_items {
    const q2n_nurbs_model *m;
    const q2n_export_topo *t;
    const int *vid, *eid;
    const int *pid;      /* CARTESIAN_POINT ids of every control point, edges' then faces' (step_points) */
    const size_t *pat;   /* ne + nf + 1: where each item's ids start in pid */
    int *out_id;         /* the EDGE_CURVE / ADVANCED_FACE id of each item */
    int face;            /* 1: faces, 0: edges */
    int *first;          /* n + 1: first entity id of each item, then the next free one */
    int *end;            /* n: the next free id after each item as formatted (checked against first) */
    step_out *o;
} step_items;

/* entity ids an item takes: an edge its curve and the EDGE_CURVE; a face its surface, four
 * ORIENTED_EDGEs, the loop, the bound and the face (the points are written before, once) */
enum { EDGE_IDS = 2, FACE_IDS = 8 };

static void step_item(void *arg, int k, q2n_strbuf *b)
{
    step_items *J = arg;
    step_out o = {*b, J->first[k]};
    if (J->face) {
        J->out_id[k] = step_face(&o, J->m, J->t, J->eid, J->pid + J->pat[J->t->ne + k], k);
    } else {
        int c = step_curve(&o, &J->t->edge_curve[k], J->pid + J->pat[k]);
        J->out_id[k] = step_begin(&o);
        q2n_strbuf_printf(&o.b, "EDGE_CURVE('',#%d,#%d,#%d,.T.);\n", J->vid[J->t->edge_v[2 * k]],
                          J->vid[J->t->edge_v[2 * k + 1]], c);
    }
    J->end[k] = o.next_id;
    *b = o.b;
}

static int step_put(void *arg, int k, const q2n_strbuf *b)
{
    step_items *J = arg;
    if (J->end[k] != J->first[k + 1]) return 1;   /* another number of ids than counted: a writer defect, no file */
    q2n_strbuf_putn(&J->o->b, b->data, b->len);
    return J->o->b.oom;
}

/* Items [0, n) (edges or faces), appended to o in order. */
static void step_items_run(step_out *o, step_items *J, int n, const q2n_export_options *opt)
{
    J->first = malloc(sizeof(int) * ((size_t)n + 1));
    J->end = malloc(sizeof(int) * ((size_t)n + 1));
    J->o = o;
    if (!J->first || !J->end) {
        o->b.oom = 1;
    } else {
        for (int k = 0; k < n; k++) {
            J->first[k] = o->next_id;
            o->next_id += J->face ? FACE_IDS : EDGE_IDS;
        }
        J->first[n] = o->next_id;
        if (q2n_export_items(n, opt->threads, J, step_item, step_put, opt->progress, J->face ? "STEP" : NULL))
            o->b.oom = 1;
    }
    free(J->first);
    free(J->end);
    J->first = J->end = NULL;
}

/* ---- shared CARTESIAN_POINTs ---- */

typedef struct point_set {
    int *slot;           /* cap slots: 1 + the index in uniq of the triple hashed there, or 0 */
    size_t cap;
} point_set;

static size_t point_hash(const double *p)
{
    unsigned char k[3 * sizeof(double)];
    memcpy(k, p, sizeof k);
    size_t h = 1469598103934665603u;   /* FNV-1a over the bits */
    for (size_t i = 0; i < sizeof k; i++) h = (h ^ k[i]) * 1099511628211u;
    return h;
}

/* The entity id of triple p: that of an earlier triple with the same bits, else the next one (p is
 * appended to uniq; the id of uniq[u] is first + u). */
static int point_id(point_set *S, const double *p, int first, const double **uniq, int *nuniq)
{
    size_t i = point_hash(p) & (S->cap - 1);
    while (S->slot[i]) {
        int u = S->slot[i] - 1;
        if (memcmp(uniq[u], p, 3 * sizeof(double)) == 0) return first + u;
        i = (i + 1) & (S->cap - 1);
    }
    uniq[*nuniq] = p;
    S->slot[i] = ++*nuniq;
    return first + *nuniq - 1;
}

typedef struct points_job {
    const double *const *uniq;
    int first;           /* id of uniq[0] */
    int n;
    step_out *o;
} points_job;

enum { POINTS_PER_ITEM = 256 };

static void points_item(void *arg, int k, q2n_strbuf *b)
{
    points_job *J = arg;
    step_out o = {*b, J->first + k * POINTS_PER_ITEM};
    for (int i = k * POINTS_PER_ITEM; i < J->n && i < (k + 1) * POINTS_PER_ITEM; i++) step_point(&o, J->uniq[i]);
    *b = o.b;
}

static int points_put(void *arg, int k, const q2n_strbuf *b)
{
    (void)k;
    points_job *J = arg;
    q2n_strbuf_putn(&J->o->b, b->data, b->len);
    return J->o->b.oom;
}

/* Every vertex's and control point's CARTESIAN_POINT id (vertices into vpt, the edges' and faces'
 * control points into pid at pat[item]), the distinct triples written once, in order of first use
 * (formatted on the threads). */
static void step_points(step_out *o, const q2n_nurbs_model *m, const q2n_export_topo *t, const q2n_export_options *opt,
                        int *vpt, int **pid_out, size_t **pat_out)
{
    size_t n = 0, ni = (size_t)t->ne + (size_t)t->nf;
    size_t *pat = malloc(sizeof(size_t) * (ni + 1));
    if (!pat) { o->b.oom = 1; return; }
    for (int e = 0; e < t->ne; e++) pat[e] = n, n += (size_t)t->edge_curve[e].ncp;
    for (int f = 0; f < t->nf; f++) pat[t->ne + f] = n, n += (size_t)m->patches[f].ncp_u * m->patches[f].ncp_v;
    pat[ni] = n;
    size_t total = n + (size_t)t->nv, cap = 16;
    while (cap < 2 * total) cap *= 2;
    point_set S = {calloc(cap, sizeof(int)), cap};
    int *pid = malloc(sizeof(int) * (n ? n : 1));
    const double **uniq = malloc(sizeof(double *) * (total ? total : 1));
    if (!S.slot || !pid || !uniq) {
        o->b.oom = 1;
        free(S.slot); free(pid); free(uniq); free(pat);
        return;
    }
    int first = o->next_id, nu = 0;
    for (int v = 0; v < t->nv; v++)
        if (t->vused[v]) vpt[v] = point_id(&S, t->vpos + 3 * v, first, uniq, &nu);
    for (int e = 0; e < t->ne; e++)
        for (int i = 0; i < t->edge_curve[e].ncp; i++) pid[pat[e] + i] = point_id(&S, t->edge_curve[e].cp + 3 * i, first, uniq, &nu);
    for (int f = 0; f < t->nf; f++) {
        const q2n_bspline_surface *p = &m->patches[f];
        for (int i = 0; i < p->ncp_u * p->ncp_v; i++) pid[pat[t->ne + f] + i] = point_id(&S, p->cp + 3 * i, first, uniq, &nu);
    }
    points_job J = {uniq, first, nu, o};
    if (q2n_export_items((nu + POINTS_PER_ITEM - 1) / POINTS_PER_ITEM, opt->threads, &J, points_item, points_put, NULL, NULL))
        o->b.oom = 1;
    o->next_id = first + nu;
    free(S.slot); free(uniq);
    *pid_out = pid;
    *pat_out = pat;
}

static q2n_status step_build(const q2n_nurbs_model *m, const q2n_export_topo *t, const q2n_export_options *opt,
                             const char *name, q2n_strbuf *out)
{
    step_out o = {*out, 1};
    int *pid = NULL;
    size_t *pat = NULL;
    int *vid = calloc((size_t)t->nv, sizeof(int));
    int *eid = malloc(sizeof(int) * (size_t)t->ne);
    int *fid = malloc(sizeof(int) * (size_t)t->nf);
    int *shell = malloc(sizeof(int) * (size_t)t->ncomp);
    int *list = malloc(sizeof(int) * (size_t)(t->nf > t->ncomp ? t->nf : t->ncomp));
    if (vid && eid && fid && shell && list) {
        int pds = 0;
        step_header(&o, opt, name);
        int ctx = step_context(&o, opt, name, t->resolution, &pds);
        int *vpt = calloc((size_t)t->nv + 1, sizeof(int));
        if (!vpt) o.b.oom = 1;
        else step_points(&o, m, t, opt, vpt, &pid, &pat);
        for (int v = 0; v < t->nv && !o.b.oom; v++) {
            if (!t->vused[v]) continue;
            vid[v] = step_begin(&o);
            q2n_strbuf_printf(&o.b, "VERTEX_POINT('',#%d);\n", vpt[v]);
        }
        free(vpt);
        step_items J = {m, t, vid, eid, pid, pat, eid, 0, NULL, NULL, NULL};
        if (!o.b.oom) step_items_run(&o, &J, t->ne, opt);
        J.face = 1;
        J.out_id = fid;
        if (!o.b.oom) step_items_run(&o, &J, t->nf, opt);
        if (!o.b.oom) step_root(&o, t, fid, shell, list, name, ctx, pds);
        q2n_strbuf_puts(&o.b, "ENDSEC;\nEND-ISO-10303-21;\n");
    } else {
        o.b.oom = 1;
    }
    free(vid); free(eid); free(fid); free(shell); free(list); free(pid); free(pat);
    *out = o.b;
    return o.b.oom ? Q2N_ERR_NOMEM : Q2N_OK;
}

q2n_status q2n_export_step_text(const q2n_nurbs_model *m, const q2n_export_options *opts, char **text,
                                size_t *len, q2n_error *err)
{
    return q2n_export_text("STEP", step_build, m, opts, text, len, err);
}

q2n_status q2n_export_step(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                           q2n_error *err)
{
    return q2n_export_write("STEP", step_build, m, opts, path, err);
}

q2n_status q2n_export_step_stream(const q2n_nurbs_model *m, const q2n_export_options *opts, const char *path,
                                  FILE *f, q2n_error *err)
{
    return q2n_export_to_stream("STEP", step_build, m, opts, path, f, err);
}
