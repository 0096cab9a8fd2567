/* export_common.c — shared by the IGES and STEP writers: text buffer, real formatting, units and
 * dates, atomic output, model validation and the B-rep topology (see export_internal.h). */
#include "iges/export_internal.h"

#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/outfile.h"
#include "core/par.h"
#include "core/vec3.h"
#include "iges/export_policy.h"

/* ---------------------------------------------------------------- text buffer */

static int strbuf_reserve(q2n_strbuf *b, size_t extra)
{
    if (b->oom) return 0;
    if (b->len + extra + 1 <= b->cap) return 1;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->len + extra + 1) cap *= 2;
    char *p = realloc(b->data, cap);
    if (!p) { b->oom = 1; return 0; }
    b->data = p;
    b->cap = cap;
    return 1;
}

void q2n_strbuf_putn(q2n_strbuf *b, const char *s, size_t n)
{
    if (b->fp) {
        if (n && fwrite(s, 1, n, b->fp) != n) {} /* sticky in ferror(fp): the caller's close reports it */
        b->len += n;
        return;
    }
    if (!strbuf_reserve(b, n)) return;
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = '\0';
}

void q2n_strbuf_puts(q2n_strbuf *b, const char *s) { q2n_strbuf_putn(b, s, strlen(s)); }
void q2n_strbuf_putc(q2n_strbuf *b, char c) { q2n_strbuf_putn(b, &c, 1); }

void q2n_strbuf_printf(q2n_strbuf *b, const char *fmt, ...)
{
    char small[256];
    va_list ap;
    if (b->fp) {
        va_start(ap, fmt);
        int n = vfprintf(b->fp, fmt, ap);
        va_end(ap);
        if (n > 0) b->len += (size_t)n;
        return;
    }
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) { b->oom = 1; return; }
    if ((size_t)n < sizeof small) { q2n_strbuf_putn(b, small, (size_t)n); return; }
    if (!strbuf_reserve(b, (size_t)n)) return;
    va_start(ap, fmt);
    vsnprintf(b->data + b->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
}

void q2n_strbuf_free(q2n_strbuf *b)
{
    free(b->data);
    b->data = NULL;
    b->len = b->cap = 0;
}

/* ---------------------------------------------------------------- numbers */

void q2n_export_fmt_real(char out[Q2N_REAL_CHARS], double x)
{
    char tmp[Q2N_REAL_CHARS];
    int n = snprintf(tmp, sizeof tmp, "%.17g", x);   /* at most 24 characters: "-1.2345678901234567e-308" */
    if (n < 0) n = 0;
    if (n >= (int)sizeof tmp) n = (int)sizeof tmp - 1;
    /* callers switch to the "C" numeric locale (q2n_export_locale_begin); should that have failed,
     * a ',' decimal separator is still normalised here.  Then: the mantissa, a '.' if it has none,
     * and 'E' with the exponent's digits (no printf: the writers format millions of reals). */
    int ml = n, dot = 0, k = 0;
    for (int i = 0; i < n; i++) {
        if (tmp[i] == ',') tmp[i] = '.';
        if (tmp[i] == '.') dot = 1;
        if ((tmp[i] == 'e' || tmp[i] == 'E') && ml == n) ml = i;
    }
    memcpy(out, tmp, (size_t)ml);
    k = ml;
    if (!dot) out[k++] = '.';
    if (ml < n) {
        out[k++] = 'E';
        memcpy(out + k, tmp + ml + 1, (size_t)(n - ml - 1));
        k += n - ml - 1;
    }
    out[k] = '\0';
}

int q2n_export_fmt_int(char *out, int x, int width)
{
    char tmp[16];
    int n = 0;
    unsigned u = x < 0 ? 0u - (unsigned)x : (unsigned)x;
    do {
        tmp[n++] = (char)('0' + u % 10u);
        u /= 10u;
    } while (u);
    if (x < 0) tmp[n++] = '-';
    int len = n < width ? width : n, pad = len - n;
    memset(out, ' ', (size_t)pad);
    for (int i = 0; i < n; i++) out[pad + i] = tmp[n - 1 - i];
    return len;
}

/* ---------------------------------------------------------------- items on worker threads */

#define Q2N_EXPORT_CHUNK 256   /* items formatted at once: bounds the text held in memory */
_Static_assert(Q2N_EXPORT_PROGRESS_EVERY % Q2N_EXPORT_CHUNK == 0, "progress is emitted at chunk starts");

typedef struct items_job {
    void *ctx;
    void (*fmt)(void *, int, q2n_strbuf *);
    int base;
    q2n_strbuf *buf;
} items_job;

static void items_one(void *arg, int i)
{
    items_job *J = arg;
    q2n_export_locale loc = q2n_export_locale_begin();   /* per thread */
    memset(&J->buf[i], 0, sizeof J->buf[i]);
    J->fmt(J->ctx, J->base + i, &J->buf[i]);
    q2n_export_locale_end(loc);
}

int q2n_export_items(int n, int threads, void *ctx, void (*fmt)(void *ctx, int k, q2n_strbuf *b),
                     int (*put)(void *ctx, int k, const q2n_strbuf *b), const q2n_progress_sink *progress,
                     const char *what)
{
    q2n_strbuf buf[Q2N_EXPORT_CHUNK];
    items_job J = {ctx, fmt, 0, buf};
    int bad = 0;
    for (int k0 = 0; k0 < n && !bad; k0 += Q2N_EXPORT_CHUNK) {
        int cn = n - k0 < Q2N_EXPORT_CHUNK ? n - k0 : Q2N_EXPORT_CHUNK;
        if (what && k0 % Q2N_EXPORT_PROGRESS_EVERY == 0) q2n_progress_emit(progress, "write", what, k0, n);
        J.base = k0;
        q2n_par_for(cn, threads, items_one, &J);
        for (int i = 0; i < cn; i++) {
            if (!bad && (buf[i].oom || put(ctx, k0 + i, &buf[i]))) bad = 1;
            q2n_strbuf_free(&buf[i]);
        }
    }
    return bad;
}

q2n_export_locale q2n_export_locale_begin(void)
{
    q2n_export_locale l = {NULL, NULL};
    locale_t c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    if (c) {
        l.c = c;
        l.old = uselocale(c);
    }
    return l;
}

void q2n_export_locale_end(q2n_export_locale l)
{
    if (!l.c) return;
    uselocale((locale_t)l.old);
    freelocale((locale_t)l.c);
}

/* ---------------------------------------------------------------- units and dates */

/* IGES 5.3 §2.2.4.3 (global 14, 15); STEP: ISO 10303-41 si_prefix, or a conversion-based unit
 * defined in millimetres (AP214 recommended practice for inch and foot). */
static const struct unit_row {
    const char *name, *alias1, *alias2;
    int iges_flag;
    const char *iges_name;
    double mm;
} UNITS[Q2N_UNITS_COUNT] = {
    [Q2N_UNITS_MM] = {"mm", "millimetre", "millimeter", 2, "MM", 1.0},
    [Q2N_UNITS_IN] = {"in", "inch", "inches", 1, "INCH", 25.4},
    [Q2N_UNITS_CM] = {"cm", "centimetre", "centimeter", 10, "CM", 10.0},
    [Q2N_UNITS_M] = {"m", "metre", "meter", 6, "M", 1000.0},
    [Q2N_UNITS_FT] = {"ft", "foot", "feet", 4, "FT", 304.8},
};

int q2n_units_parse(const char *s, q2n_units *u)
{
    for (int i = 0; s && i < Q2N_UNITS_COUNT; i++)
        if (!strcmp(s, UNITS[i].name) || !strcmp(s, UNITS[i].alias1) || !strcmp(s, UNITS[i].alias2)) {
            *u = (q2n_units)i;
            return 0;
        }
    return -1;
}

static int units_ok(q2n_units u) { return (int)u >= 0 && (int)u < Q2N_UNITS_COUNT; }
const char *q2n_units_name(q2n_units u) { return units_ok(u) ? UNITS[u].name : "?"; }
double q2n_units_in_mm(q2n_units u) { return units_ok(u) ? UNITS[u].mm : 0.0; }
int q2n_units_iges_flag(q2n_units u) { return units_ok(u) ? UNITS[u].iges_flag : 2; }
const char *q2n_units_iges_name(q2n_units u) { return units_ok(u) ? UNITS[u].iges_name : "MM"; }

/* Civil date of a day count since 1970-01-01 (H. Hinnant, "chrono-compatible low-level date
 * algorithms", days_from_civil inverse): no gmtime, so any 64-bit time works on any time_t. */
static void civil_from_days(long long z, long long *y, int *m, int *d)
{
    z += 719468;
    long long era = (z >= 0 ? z : z - 146096) / 146097;
    long long doe = z - era * 146097;
    long long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    long long doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    long long mp = (5 * doy + 2) / 153;
    *d = (int)(doy - (153 * mp + 2) / 5 + 1);
    *m = (int)(mp < 10 ? mp + 3 : mp - 9);
    *y = yoe + era * 400 + (*m <= 2);
}

void q2n_export_date(const q2n_export_options *opt, int iges, char out[32])
{
    out[0] = '\0';
    if (opt->timestamp) { snprintf(out, 32, "%s", opt->timestamp); return; }
    if (!opt->has_date) return;
    long long t = opt->date, days = t / 86400, sec = t % 86400, y;
    if (sec < 0) { sec += 86400; days--; }
    int mo, d;
    civil_from_days(days, &y, &mo, &d);
    int h = (int)(sec / 3600), mi = (int)(sec / 60 % 60), s = (int)(sec % 60);
    if (iges) snprintf(out, 32, "%04lld%02d%02d.%02d%02d%02d", y, mo, d, h, mi, s);
    else snprintf(out, 32, "%04lld-%02d-%02dT%02d:%02d:%02d", y, mo, d, h, mi, s);
}

/* ---------------------------------------------------------------- strings */

q2n_status q2n_export_check_string(const char *s, const char *what, q2n_error *err)
{
    if (!s) return Q2N_OK;
    size_t n = strlen(s);
    if (n > 64) return q2n_error_set(err, Q2N_ERR_ARG, "export: %s longer than 64 characters", what);
    for (size_t i = 0; i < n; i++)
        if (s[i] < 0x20 || s[i] > 0x7e || s[i] == '\'' || s[i] == '\\')
            return q2n_error_set(err, Q2N_ERR_ARG,
                                 "export: %s has a character that is not printable ASCII (or a quote/backslash) "
                                 "at position %zu", what, i);
    return Q2N_OK;
}

void q2n_export_basename(const char *path, char *out, size_t cap)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    const char *dot = strrchr(b, '.');
    size_t n = dot && dot != b ? (size_t)(dot - b) : strlen(b);
    size_t k = 0;
    for (size_t i = 0; i < n && k + 1 < cap && k < 64; i++) {
        char c = b[i];
        out[k++] = (c >= 0x20 && c <= 0x7e && c != '\'' && c != '\\') ? c : '_';
    }
    out[k] = '\0';
}

int q2n_export_knot_mults(const double *knots, int n, double *kn, int *mult)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (m > 0 && knots[i] == kn[m - 1]) mult[m - 1]++;
        else { kn[m] = knots[i]; mult[m] = 1; m++; }
    }
    return m;
}

/* ---------------------------------------------------------------- patch sides */

void q2n_export_curve_free(q2n_export_curve *c)
{
    if (!c) return;
    free(c->knots);
    free(c->cp);
    free(c->weights);
    c->knots = c->cp = c->weights = NULL;
}

q2n_status q2n_export_side_curve(const q2n_bspline_surface *s, int side, q2n_export_curve *c)
{
    /* side 0: row j = 0; 2: row j = ncp_v-1 (along u); 1: column i = ncp_u-1; 3: column i = 0 (along v);
     * in the direction of increasing u or v (patch/surface.h) */
    int along_u = q2n_side_along_u(side);
    int n = along_u ? s->ncp_u : s->ncp_v, deg = along_u ? s->deg_u : s->deg_v;
    const double *kn = along_u ? s->knots_u : s->knots_v;
    c->deg = deg;
    c->ncp = n;
    c->knots = malloc(sizeof(double) * (size_t)(n + deg + 1));
    c->cp = malloc(sizeof(double) * 3 * (size_t)n);
    c->weights = s->weights ? malloc(sizeof(double) * (size_t)n) : NULL;
    if (!c->knots || !c->cp || (s->weights && !c->weights)) {
        q2n_export_curve_free(c);
        return Q2N_ERR_NOMEM;
    }
    memcpy(c->knots, kn, sizeof(double) * (size_t)(n + deg + 1));
    for (int a = 0; a < n; a++) {
        int i, j;
        if (along_u) { i = a; j = q2n_side_level[side] * (s->ncp_v - 1); }
        else { j = a; i = q2n_side_level[side] * (s->ncp_u - 1); }
        size_t k = (size_t)j * (size_t)s->ncp_u + (size_t)i;
        memcpy(c->cp + 3 * a, s->cp + 3 * k, 3 * sizeof(double));
        if (c->weights) c->weights[a] = s->weights[k];
    }
    return Q2N_OK;
}

/* Point of patch k on side i at parameter t along the half-edge's direction (origin -> dest):
 * side 0: (t,0), 1: (1,t), 2: (1-t,1), 3: (0,1-t). */
static void side_point(const q2n_bspline_surface *s, int side, double t, double p[3])
{
    double u, v;
    q2n_side_uv(side, t, 0.0, &u, &v);
    q2n_bspline_eval(s, u, v, p, NULL, NULL);
}

/* ---------------------------------------------------------------- topology */

void q2n_export_topo_free(q2n_export_topo *t)
{
    if (!t) return;
    if (t->edge_curve)
        for (int e = 0; e < t->ne; e++) q2n_export_curve_free(&t->edge_curve[e]);
    free(t->edge_curve);
    free(t->vpos);
    free(t->vused);
    free(t->edge_v);
    free(t->he_sense);
    free(t->face_comp);
    free(t->comp_closed);
    free(t->comp_inward);
    memset(t, 0, sizeof *t);
}

static int uf_find(int *parent, int x)
{
    while (parent[x] != x) { parent[x] = parent[parent[x]]; x = parent[x]; }
    return x;
}

static q2n_status check_model(const q2n_nurbs_model *m, q2n_error *err)
{
    if (!m || !m->mesh || !m->patches) return q2n_error_set(err, Q2N_ERR_ARG, "export: empty model");
    const q2n_mesh *me = m->mesh;
    if (m->n != me->nf)
        return q2n_error_set(err, Q2N_ERR_ARG, "export: %d patches for %d mesh faces", m->n, me->nf);
    for (int f = 0; f < me->nf; f++) {
        if (q2n_face_size(me, f) != 4)
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "export: face %d has %d vertices (quads only)", f,
                                 q2n_face_size(me, f));
        q2n_error e2;
        if (q2n_bspline_check(&m->patches[f], &e2) != Q2N_OK)
            return q2n_error_set(err, Q2N_ERR_ARG, "export: patch %d: %s", f, e2.message);
    }
    if (!(m->tol_abs >= 0.0) || !isfinite(m->tol_abs))
        return q2n_error_set(err, Q2N_ERR_ARG, "export: tolerance %g is not a finite value >= 0", m->tol_abs);
    return Q2N_OK;
}

/* Both patches of every interior edge must agree along it (samples t = j/8) and every corner must
 * sit on its vertex's first-seen position, within the resolution. */
static q2n_status check_watertight(const q2n_nurbs_model *m, q2n_export_topo *t, q2n_error *err)
{
    const q2n_mesh *me = m->mesh;
    double tol = 10.0 * t->resolution;
    for (int e = 0; e < me->ne; e++) {
        int h = me->edge_he[e], g = me->he_twin[h];
        if (g < 0) continue;
        int fh = me->he_face[h], fg = me->he_face[g];
        int sh = h - me->face_start[fh], sg = g - me->face_start[fg];
        for (int j = 0; m->edges && j <= 8; j++) {   /* the model's edge curve lies on the patch boundary */
            double a[3], b[3];
            side_point(&m->patches[fh], sh, j / 8.0, a);
            q2n_bspline_curve_eval(&m->edges[e], j / 8.0, b, NULL);
            double d = q2n_v3_dist_scaled(a, b);
            if (!(d <= tol))
                return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                                     "export: edge %d: its curve and the boundary of face %d differ by %.3g at t = %g "
                                     "(resolution %.3g)", e, fh, d, j / 8.0, t->resolution);
        }
        for (int j = 0; j <= 8; j++) {
            double a[3], b[3];
            side_point(&m->patches[fh], sh, j / 8.0, a);
            side_point(&m->patches[fg], sg, 1.0 - j / 8.0, b);
            double d = q2n_v3_dist_scaled(a, b);
            if (!(d <= tol))
                return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                                     "export: edge %d (faces %d and %d) is not watertight: the two patch "
                                     "boundaries differ by %.3g at t = %g (resolution %.3g)", e, fh, fg, d, j / 8.0,
                                     t->resolution);
        }
    }
    for (int h = 0; h < me->nh; h++) {
        int f = me->he_face[h], side = h - me->face_start[f], v = me->face_vert[h];
        double p[3];
        side_point(&m->patches[f], side, 0.0, p);
        double d = q2n_v3_dist_scaled(p, t->vpos + 3 * v);
        if (!(d <= tol))
            return q2n_error_set(err, Q2N_ERR_GEOMETRY,
                                 "export: patch corners at vertex %d differ by %.3g (face %d corner %d)", v, d, f, side);
    }
    return Q2N_OK;
}

static double model_bbox_diag(const q2n_nurbs_model *m, double *max_coord)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, mc = 0.0;
    for (int k = 0; k < m->n; k++) {
        const q2n_bspline_surface *s = &m->patches[k];
        for (int i = 0; i < s->ncp_u * s->ncp_v; i++)
            for (int c = 0; c < 3; c++) {
                double x = s->cp[3 * i + c];
                lo[c] = fmin(lo[c], x);
                hi[c] = fmax(hi[c], x);
                mc = fmax(mc, fabs(x));
            }
    }
    *max_coord = mc;
    double d[3];
    q2n_v3_sub(d, hi, lo);
    return q2n_v3_norm_scaled(d);
}

/* Signed volume enclosed by each closed component, from its faces' corner quads split into two
 * triangles (divergence theorem: V = 1/6 sum det(a, b, c) over outward-oriented triangles); the
 * sign tells the orientation, which is all that is needed, so the polygon approximation of the
 * patches suffices. */
static void mark_inward(const q2n_mesh *me, q2n_export_topo *t)
{
    double *vol = calloc((size_t)t->ncomp, sizeof(double));
    if (!vol) return; /* orientation left as given */
    /* in the vertices' frame (centre of their box, power-of-two scale): triple products of
     * coordinates of 1e150 or 1e-150 would overflow or underflow, and far from the origin they
     * would cancel */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, c0[3], h = 0;
    for (int v = 0; v < me->nv; v++)
        for (int c = 0; t->vused[v] && c < 3; c++) {
            lo[c] = fmin(lo[c], t->vpos[3 * v + c]);
            hi[c] = fmax(hi[c], t->vpos[3 * v + c]);
        }
    for (int c = 0; c < 3; c++) c0[c] = lo[c] / 2 + hi[c] / 2, h = fmax(h, hi[c] / 2 - lo[c] / 2);
    int e = h > 0 ? ilogb(h) + 1 : 0;
    for (int f = 0; f < me->nf; f++) {
        double p[4][3];
        for (int i = 0; i < 4; i++)
            for (int c = 0; c < 3; c++)
                p[i][c] = ldexp(t->vpos[3 * me->face_vert[me->face_start[f] + i] + c], -e) - ldexp(c0[c], -e);
        for (int k = 1; k <= 2; k++) {
            double c[3];
            q2n_v3_cross(c, p[k], p[k + 1]);
            vol[t->face_comp[f]] += q2n_v3_dot(p[0], c) / 6.0;
        }
    }
    for (int c = 0; c < t->ncomp; c++) t->comp_inward[c] = t->comp_closed[c] && vol[c] < 0.0;
    free(vol);
}

/* Connected components (union-find over interior edges), numbered in face order; a component
 * is closed when none of its half-edges lies on the boundary.  Returns 0 when out of memory. */
static int build_components(const q2n_mesh *me, q2n_export_topo *t)
{
    int *parent = malloc(sizeof(int) * (size_t)me->nf), *rc = malloc(sizeof(int) * (size_t)me->nf);
    t->comp_closed = malloc(sizeof(int) * (size_t)me->nf);
    t->comp_inward = calloc((size_t)me->nf, sizeof(int));
    if (!parent || !rc || !t->comp_closed || !t->comp_inward) {
        free(parent);
        free(rc);
        return 0;
    }
    for (int f = 0; f < me->nf; f++) { parent[f] = f; rc[f] = -1; }
    for (int h = 0; h < me->nh; h++) {
        int g = me->he_twin[h];
        if (g < 0) continue;
        int a = uf_find(parent, me->he_face[h]), b = uf_find(parent, me->he_face[g]);
        if (a != b) parent[a > b ? a : b] = a < b ? a : b;
    }
    for (int f = 0; f < me->nf; f++) {
        int r = uf_find(parent, f);
        if (rc[r] < 0) { rc[r] = t->ncomp; t->comp_closed[t->ncomp] = 1; t->ncomp++; }
        t->face_comp[f] = rc[r];
    }
    for (int h = 0; h < me->nh; h++)
        if (me->he_twin[h] < 0) t->comp_closed[t->face_comp[me->he_face[h]]] = 0;
    t->all_closed = 1;
    for (int c = 0; c < t->ncomp; c++) t->all_closed &= t->comp_closed[c];
    free(parent);
    free(rc);
    return 1;
}

/* A copy of a model edge curve in the writers' form. */
static q2n_status copy_curve(const q2n_bspline_curve *in, q2n_export_curve *c)
{
    memset(c, 0, sizeof *c);
    c->deg = in->deg;
    c->ncp = in->ncp;
    c->knots = malloc(sizeof(double) * (size_t)(in->ncp + in->deg + 1));
    c->cp = malloc(3 * sizeof(double) * (size_t)in->ncp);
    if (!c->knots || !c->cp) { q2n_export_curve_free(c); return Q2N_ERR_NOMEM; }
    memcpy(c->knots, in->knots, sizeof(double) * (size_t)(in->ncp + in->deg + 1));
    memcpy(c->cp, in->cp, 3 * sizeof(double) * (size_t)in->ncp);
    return Q2N_OK;
}

/* Edge curves: the model's edge curves when it has them (each patch boundary is the same curve by
 * knot insertion), else the boundary of the patch of edge_he[e], in that patch's parameter direction
 * (sides 0, 1 run origin -> dest, sides 2, 3 dest -> origin); he_sense says which half-edges
 * run along their curve.  Returns 0 when out of memory. */
static int build_edges(const q2n_nurbs_model *m, q2n_export_topo *t)
{
    const q2n_mesh *me = m->mesh;
    for (int e = 0; e < me->ne; e++) {
        int h = me->edge_he[e], f = me->he_face[h], side = h - me->face_start[f], fwd = side < 2;
        if (m->edges) {   /* the model's own edge curve (owner orientation) */
            if (copy_curve(&m->edges[e], &t->edge_curve[e]) != Q2N_OK) return 0;
            fwd = 1;
        } else if (q2n_export_side_curve(&m->patches[f], side, &t->edge_curve[e]) != Q2N_OK)
            return 0;
        t->edge_v[2 * e] = fwd ? q2n_he_origin(me, h) : q2n_he_dest(me, h);
        t->edge_v[2 * e + 1] = fwd ? q2n_he_dest(me, h) : q2n_he_origin(me, h);
    }
    for (int h = 0; h < me->nh; h++) t->he_sense[h] = q2n_he_origin(me, h) == t->edge_v[2 * me->he_edge[h]];
    return 1;
}

static q2n_status topo_build(const q2n_nurbs_model *m, double mesh_scale, q2n_export_topo *t, q2n_error *err);

q2n_status q2n_export_topo_build(const q2n_nurbs_model *m, q2n_export_topo *t, q2n_error *err)
{
    return topo_build(m, 1.0, t, err);
}

static q2n_status topo_build(const q2n_nurbs_model *m, double mesh_scale, q2n_export_topo *t, q2n_error *err)
{
    memset(t, 0, sizeof *t);
    q2n_status st = check_model(m, err);
    if (st != Q2N_OK) return st;
    const q2n_mesh *me = m->mesh;
    t->nv = me->nv; t->ne = me->ne; t->nf = me->nf;
    double diag = model_bbox_diag(m, &t->max_coord);
    t->resolution = m->tol_abs > 0.0 ? m->tol_abs : Q2N_EXPORT_RESOLUTION_REL * (diag > 0.0 ? diag : 1.0);
    t->vpos = calloc(3 * (size_t)me->nv, sizeof(double));
    t->vused = calloc((size_t)me->nv, sizeof(int));
    t->edge_curve = calloc((size_t)me->ne, sizeof(q2n_export_curve));
    t->edge_v = malloc(sizeof(int) * 2 * (size_t)me->ne);
    t->he_sense = malloc(sizeof(int) * (size_t)me->nh);
    t->face_comp = malloc(sizeof(int) * (size_t)me->nf);
    if (!t->vpos || !t->vused || !t->edge_curve || !t->edge_v || !t->he_sense || !t->face_comp) goto oom;
    /* vertices: the corner of the first patch that uses each vertex */
    for (int h = 0; h < me->nh; h++) {
        int v = me->face_vert[h], f = me->he_face[h];
        if (t->vused[v]) continue;
        t->vused[v] = 1;
        side_point(&m->patches[f], h - me->face_start[f], 0.0, t->vpos + 3 * v);
    }
    for (int v = 0; v < me->nv; v++) /* unused vertices (listed in IGES 502 only): the mesh position */
        if (!t->vused[v])
            for (int c = 0; c < 3; c++) t->vpos[3 * v + c] = mesh_scale * me->pos[3 * v + c];
    if ((st = check_watertight(m, t, err)) != Q2N_OK) {
        q2n_export_topo_free(t);
        return st;
    }
    if (!build_edges(m, t) || !build_components(me, t)) goto oom;
    mark_inward(me, t);
    return Q2N_OK;
oom:
    q2n_export_topo_free(t);
    return q2n_error_set(err, Q2N_ERR_NOMEM, "export: out of memory (%d faces)", me->nf);
}

/* Shared by the IGES and STEP writers: validate the options, build the edge topology, switch to
 * the C locale, run the format's builder. */
static q2n_status export_run(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                             const q2n_export_options *opts, const char *path, FILE *fp, q2n_strbuf *out,
                             q2n_error *err)
{
    q2n_export_options def = {0};
    const q2n_export_options *opt = opts ? opts : &def;
    memset(out, 0, sizeof *out);
    out->fp = fp;
    q2n_status st;
    if ((st = q2n_export_check_string(opt->author, "author", err)) != Q2N_OK) return st;
    if ((st = q2n_export_check_string(opt->organization, "organization", err)) != Q2N_OK) return st;
    if ((st = q2n_export_check_string(opt->timestamp, "timestamp", err)) != Q2N_OK) return st;
    if ((st = q2n_export_check_string(opt->name, "name", err)) != Q2N_OK) return st;
    if (!units_ok(opt->units)) return q2n_error_set(err, Q2N_ERR_ARG, "export: unknown units %d", (int)opt->units);
    if (opt->has_date && (opt->date < 0 || opt->date > 253402300799LL))
        return q2n_error_set(err, Q2N_ERR_ARG, "export: date %lld is not between 1970 and 9999", opt->date);
    char name[72];
    if (opt->name) snprintf(name, sizeof name, "%s", opt->name);
    else q2n_export_basename(path ? path : "quad2nurbs", name, sizeof name);
    q2n_export_topo t;
    if ((st = topo_build(m, opt->mesh_scale > 0 ? opt->mesh_scale : 1.0, &t, err)) != Q2N_OK) return st;
    q2n_export_locale loc = q2n_export_locale_begin();
    st = build(m, &t, opt, name, out);
    q2n_export_locale_end(loc);
    q2n_export_topo_free(&t);
    if (st != Q2N_OK) {
        q2n_strbuf_free(out);
        return q2n_error_set(err, st, "%s: out of memory while writing %s", path ? path : format, format);
    }
    return Q2N_OK;
}

q2n_status q2n_export_text(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                           const q2n_export_options *opts, char **text, size_t *len, q2n_error *err)
{
    q2n_strbuf b;
    q2n_status st = export_run(format, build, m, opts, NULL, NULL, &b, err);
    *text = st == Q2N_OK ? b.data : NULL;
    *len = st == Q2N_OK ? b.len : 0;
    return st;
}

q2n_status q2n_export_to_stream(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                                const q2n_export_options *opts, const char *path, FILE *f, q2n_error *err)
{
    q2n_strbuf b;
    if (!f) return q2n_error_set(err, Q2N_ERR_ARG, "export: no output stream");
    q2n_status st = export_run(format, build, m, opts, path, f, &b, err);
    q2n_strbuf_free(&b);
    return st;
}

q2n_status q2n_export_write(const char *format, q2n_export_build_fn build, const q2n_nurbs_model *m,
                            const q2n_export_options *opts, const char *path, q2n_error *err)
{
    q2n_outfile of;
    q2n_status st = q2n_outfile_open(&of, path, err);
    if (st) return st;
    if ((st = q2n_export_to_stream(format, build, m, opts, path, of.f, err))) {
        q2n_outfile_abort(&of);
        return st;
    }
    return q2n_outfile_commit(&of, err);
}
