/* test_export_roundtrip.c — parses the IGES and STEP texts the writers produce and checks them
 * against the format rules and the model they came from (no CAD system needed):
 *   IGES: 80-column records, section letters and sequence numbers, Terminate counts, Directory
 *         pairs and Parameter back-pointers, Global fields (units, scale, resolution, max
 *         coordinate), entity counts per type, every pointer, 110 p-curves along the loops,
 *         128/126 data equal to the model's
 *         control points, knots and weights bit for bit (%.17g round trip), loops using each
 *         interior edge twice in opposite senses;
 *   STEP: entity ids, every #reference defined, counts per type, each EDGE_CURVE used by two
 *         ORIENTED_EDGEs of opposite sense, surfaces' control points (u-outer lists) and weights
 *         equal to the model's, shell/solid form and units;
 *   both: determinism (two writes, identical bytes), atomic write (no temporary, no file on error),
 *         rejected inputs (gap between patches, bad extension, bad strings, missing directory). */
#include "check.h"
#include "iges/export.h"
#include "patch/surface.h"
#include "test_export_models.h"

#include <ctype.h>
#include <sys/stat.h>
#include <time.h>

/* ------------------------------------------------------------------ IGES parsing */

typedef struct iges_file {
    int nS, nG, nD, nP;
    const char *line[200000]; /* start of each record */
    int nlines;
    int ent_type[20000], ent_pptr[20000], ent_pcount[20000], ent_form[20000], ent_status[20000];
    int nent;
} iges_file;

static int field8(const char *l, int k) /* integer in 8-column field k (0-based) */
{
    char b[9];
    memcpy(b, l + 8 * k, 8);
    b[8] = 0;
    return atoi(b);
}

/* Checks the record layout; returns 1 when everything is well formed. */
static int iges_parse(const char *text, iges_file *F)
{
    memset(F, 0, sizeof *F);
    const char *p = text;
    int ok = 1, seq[5] = {0, 0, 0, 0, 0}, stage = 0;
    const char *letters = "SGDPT";
    while (*p) {
        const char *nl = strchr(p, '\n');
        if (!nl || nl - p != 80) { CHECK(0, "IGES record %d is %d columns", F->nlines + 1, nl ? (int)(nl - p) : -1); return 0; }
        char c = p[72];
        const char *pos = strchr(letters, c);
        if (!pos || c == 0) { CHECK(0, "IGES record %d: section letter '%c'", F->nlines + 1, c); return 0; }
        int s = (int)(pos - letters);
        if (s < stage) { ok = 0; CHECK(0, "IGES sections out of order at record %d", F->nlines + 1); }
        stage = s;
        int n = atoi(p + 73);
        if (n != ++seq[s]) { ok = 0; CHECK(0, "IGES %c sequence %d, expected %d", c, n, seq[s]); }
        F->line[F->nlines++] = p;
        p = nl + 1;
    }
    F->nS = seq[0]; F->nG = seq[1]; F->nD = seq[2]; F->nP = seq[3];
    CHECK(seq[4] == 1, "one T record (%d)", seq[4]);
    const char *T = F->line[F->nlines - 1];
    char tb[80];
    snprintf(tb, sizeof tb, "S%7dG%7dD%7dP%7d", F->nS, F->nG, F->nD, F->nP);
    CHECK(strncmp(T, tb, 32) == 0, "T record counts: %.32s vs %s", T, tb);
    CHECK(F->nD % 2 == 0, "D section has %d records (pairs)", F->nD);
    F->nent = F->nD / 2;
    const char **D = F->line + F->nS + F->nG, **P = D + F->nD;
    for (int k = 0; k < F->nent; k++) {
        const char *a = D[2 * k], *b = D[2 * k + 1];
        F->ent_type[k] = field8(a, 0);
        F->ent_pptr[k] = field8(a, 1);
        F->ent_status[k] = field8(a, 8);
        F->ent_pcount[k] = field8(b, 3);
        F->ent_form[k] = field8(b, 4);
        ok &= field8(b, 0) == F->ent_type[k];
        /* the entity's P records: the pointer, the count, and each record's back-pointer */
        for (int r = 0; r < F->ent_pcount[k]; r++) {
            int li = F->ent_pptr[k] - 1 + r;
            if (li < 0 || li >= F->nP) { ok = 0; break; }
            int back = atoi(P[li] + 65);
            if (back != 2 * k + 1) { ok = 0; CHECK(0, "P record %d points back to %d, not %d", li + 1, back, 2 * k + 1); break; }
        }
        if (k + 1 < F->nent) ok &= field8(D[2 * k + 2], 1) == F->ent_pptr[k] + F->ent_pcount[k];
    }
    CHECK(ok, "IGES directory / parameter cross-references");
    return ok;
}

/* Parameter tokens of entity k as doubles (type first). Caller frees. */
static double *iges_params(const iges_file *F, int k, int *n)
{
    const char *const *P = F->line + F->nS + F->nG + F->nD;
    size_t cap = 64 * (size_t)F->ent_pcount[k] + 1;
    char *s = malloc(cap), *q = s;
    for (int r = 0; r < F->ent_pcount[k]; r++) { memcpy(q, P[F->ent_pptr[k] - 1 + r], 64); q += 64; }
    *q = 0;
    double *v = malloc(sizeof(double) * cap / 2);
    int m = 0;
    char *t = s;
    while (*t) {
        while (*t == ' ') t++;
        if (!*t) break;
        char *end;
        v[m++] = strtod(t, &end);
        if (end == t) break;
        t = end;
        while (*t == ' ') t++;
        if (*t == ';') break;
        if (*t == ',') t++;
    }
    free(s);
    *n = m;
    return v;
}

/* ------------------------------------------------------------------ IGES checks */

static int exact_cps(const double *par, const q2n_bspline_surface *s)
{
    int nu = s->ncp_u, nv = s->ncp_v, at = 10, ok = 1;
    ok &= (int)par[1] == nu - 1 && (int)par[2] == nv - 1 && (int)par[3] == s->deg_u && (int)par[4] == s->deg_v;
    ok &= (int)par[7] == (s->weights ? 0 : 1);
    for (int i = 0; i < nu + s->deg_u + 1; i++) ok &= par[at++] == s->knots_u[i];
    for (int i = 0; i < nv + s->deg_v + 1; i++) ok &= par[at++] == s->knots_v[i];
    for (int i = 0; i < nu * nv; i++) ok &= par[at++] == (s->weights ? s->weights[i] : 1.0);
    for (int i = 0; i < 3 * nu * nv; i++) ok &= par[at++] == s->cp[i];
    ok &= par[at] == 0.0 && par[at + 1] == 1.0 && par[at + 2] == 0.0 && par[at + 3] == 1.0;
    return ok;
}

/* Global section fields (up to 26): Hollerith strings nH... unwrapped, numbers as text; blanks
 * outside strings (record padding) skipped.  Returns the field count. */
static int iges_global(const iges_file *F, char fields[26][160])
{
    char g[8192] = {0};
    for (int i = 0; i < F->nG && i < 100; i++) strncat(g, F->line[F->nS + i], 72);
    int n = 0;
    const char *p = g;
    while (*p && n < 26) {
        while (*p == ' ') p++;
        char *out = fields[n];
        size_t k = 0;
        if (isdigit((unsigned char)*p)) {
            char *e;
            long len = strtol(p, &e, 10);
            if (*e == 'H') { /* Hollerith: the next len characters verbatim */
                for (long i = 0; i < len && e[1 + i] && k < 159; i++) out[k++] = e[1 + i];
                p = e + 1 + len;
            }
        }
        while (*p && *p != ',' && *p != ';' && k < 159) { if (*p != ' ') out[k++] = *p; p++; }
        out[k] = 0;
        n++;
        if (*p == ';' || !*p) break;
        p++;
    }
    return n;
}

static int count_type(const iges_file *F, int type)
{
    int n = 0;
    for (int k = 0; k < F->nent; k++) n += F->ent_type[k] == type;
    return n;
}

static void check_iges(const char *what, const char *text, const q2n_nurbs_model *m, int plain, int ncomp, int nclosed)
{
    static iges_file F;
    if (!iges_parse(text, &F)) return;
    const q2n_mesh *me = m->mesh;
    CHECK(F.nS == 1, "%s: one Start record", what);
    /* Global: units MM, scale 1., resolution */
    char g[4096] = {0};
    for (int i = 0; i < F.nG; i++) strncat(g, F.line[F.nS + i], 72);
    CHECK(strncmp(g, "1H,,1H;,", 8) == 0, "%s: Global delimiters: %.8s", what, g);
    CHECK(strstr(g, ",1.,2,2HMM,") != NULL, "%s: Global scale 1.0, units flag 2 (mm)", what);
    CHECK(strstr(g, ",11,0,,;") != NULL, "%s: Global IGES 5.3 version flag", what);
    /* field by field: scale, units, resolution (tol_abs or 1e-9 x control-net diagonal), max coordinate */
    char gf[26][160];
    int ngf = iges_global(&F, gf);
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, mc = 0.0;
    for (int f = 0; f < m->n; f++)
        for (int i = 0; i < 3 * m->patches[f].ncp_u * m->patches[f].ncp_v; i++) {
            double x = m->patches[f].cp[i];
            lo[i % 3] = fmin(lo[i % 3], x); hi[i % 3] = fmax(hi[i % 3], x); mc = fmax(mc, fabs(x));
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double res = m->tol_abs > 0 ? m->tol_abs : 1e-9 * diag;
    CHECK(ngf == 26, "%s: %d Global fields", what, ngf);
    CHECK(ngf == 26 && strcmp(gf[0], ",") == 0 && strcmp(gf[1], ";") == 0 && strcmp(gf[12], "1.") == 0 &&
          strcmp(gf[13], "2") == 0 && strcmp(gf[14], "MM") == 0 && strcmp(gf[22], "11") == 0,
          "%s: Global delimiters, scale, units, version: '%s' '%s' '%s'", what, gf[12], gf[13], gf[14]);
    CHECK(ngf == 26 && fabs(strtod(gf[18], NULL) - res) <= 1e-15 * res && strtod(gf[19], NULL) == mc,
          "%s: Global resolution %s (want %.17g), max coordinate %s (want %.17g)", what, gf[18], res, gf[19], mc);
    int n128 = count_type(&F, 128);
    CHECK(n128 == me->nf, "%s: %d entities 128 for %d faces", what, n128, me->nf);
    int exact = 1;
    for (int f = 0; f < me->nf && f < F.nent; f++) {
        CHECK(F.ent_type[f] == 128, "%s: entity %d is %d, not 128 (patch order)", what, f, F.ent_type[f]);
        int n;
        double *par = iges_params(&F, f, &n);
        exact &= exact_cps(par, &m->patches[f]);
        free(par);
    }
    CHECK(exact, "%s: 128 data equal the model's knots, weights and control points exactly", what);
    if (plain) {
        CHECK(F.nent == me->nf, "%s: plain IGES has only 128s (%d entities)", what, F.nent);
        for (int f = 0; f < F.nent; f++) CHECK(F.ent_status[f] == 0, "%s: plain 128 #%d independent", what, f);
        return;
    }
    CHECK(count_type(&F, 126) == me->ne, "%s: %d curves 126 for %d edges", what, count_type(&F, 126), me->ne);
    CHECK(count_type(&F, 502) == 1 && count_type(&F, 504) == 1, "%s: one 502 and one 504", what);
    CHECK(count_type(&F, 508) == me->nf && count_type(&F, 510) == me->nf, "%s: loops/faces per patch", what);
    CHECK(count_type(&F, 110) == 4 * me->nf, "%s: %d parameter-space lines 110 (4 per face)", what, count_type(&F, 110));
    CHECK(count_type(&F, 514) == ncomp, "%s: %d shells (%d components)", what, count_type(&F, 514), ncomp);
    CHECK(count_type(&F, 186) == nclosed, "%s: %d solids (%d closed)", what, count_type(&F, 186), nclosed);
    /* pointers and edge usage: every 510 -> its 128 and 508; every 508 edge -> 504 index; 504 -> 126 */
    int *use = calloc((size_t)me->ne, sizeof(int)), *sense_sum = calloc((size_t)me->ne, sizeof(int)), ok = 1;
    int face_no = 0, n504 = 0;
    for (int k = 0; k < F.nent; k++) {
        int n;
        double *par = iges_params(&F, k, &n);
        if (F.ent_type[k] == 510) {
            ok &= (int)par[1] == 2 * face_no + 1 && (int)par[2] == 1 && F.ent_type[((int)par[4] - 1) / 2] == 508;
            face_no++;
        } else if (F.ent_type[k] == 508) {
            /* per edge: TYPE 0, EDGE (504), NDX, OF, K = 1, ISOP = 1, CURV (110 from corner i to i+1) */
            const int(*corner)[2] = q2n_corner_uv;
            ok &= (int)par[1] == 4 && n == 2 + 4 * 7;
            for (int i = 0; i < 4 && n == 30; i++) {
                const double *q = par + 2 + 7 * i;
                int e = (int)q[2] - 1, c = ((int)q[6] - 1) / 2;
                ok &= q[0] == 0 && F.ent_type[((int)q[1] - 1) / 2] == 504 && e >= 0 && e < me->ne;
                ok &= q[4] == 1 && q[5] == 1 && c >= 0 && c < F.nent && F.ent_type[c] == 110 && F.ent_status[c] == 10500;
                if (e >= 0 && e < me->ne) { use[e]++; sense_sum[e] += (int)q[3]; }
                if (c >= 0 && c < F.nent && F.ent_type[c] == 110) {
                    int nl;
                    double *ln = iges_params(&F, c, &nl);
                    ok &= nl == 7 && ln[1] == corner[i][0] && ln[2] == corner[i][1] && ln[3] == 0 &&
                          ln[4] == corner[(i + 1) & 3][0] && ln[5] == corner[(i + 1) & 3][1] && ln[6] == 0;
                    free(ln);
                }
            }
        } else if (F.ent_type[k] == 504) {
            n504 = (int)par[1];
            for (int e = 0; e < n504 && 2 + 5 * e + 4 < n; e++) {
                int c = (int)par[2 + 5 * e];
                ok &= F.ent_type[(c - 1) / 2] == 126 && F.ent_type[((int)par[3 + 5 * e] - 1) / 2] == 502;
                /* the 126's end points are the two listed vertices */
                int nc;
                double *cv = iges_params(&F, (c - 1) / 2, &nc);
                int K = (int)cv[1], M = (int)cv[2], off = 7 + (K + M + 2) + (K + 1);
                int v0 = (int)par[4 + 5 * e] - 1, v1 = (int)par[6 + 5 * e] - 1;
                for (int a = 0; a < 3; a++) {
                    ok &= fabs(cv[off + a] - me->pos[3 * v0 + a]) < 1e-12 * (1 + fabs(me->pos[3 * v0 + a]));
                    ok &= fabs(cv[off + 3 * K + a] - me->pos[3 * v1 + a]) < 1e-12 * (1 + fabs(me->pos[3 * v1 + a]));
                }
                free(cv);
            }
        } else if (F.ent_type[k] == 186 || F.ent_type[k] == 514) {
            ok &= F.ent_status[k] == (F.ent_type[k] == 186 || F.ent_form[k] == 2 ? 0 : 10000);
        }
        free(par);
    }
    CHECK(ok, "%s: B-rep pointers, 126 end points at the mesh vertices, p-curves along the loops, independent "
              "top entities", what);
    CHECK(n504 == me->ne, "%s: 504 lists %d edges", what, n504);
    int usage_ok = 1;
    for (int e = 0; e < me->ne; e++) {
        int interior = me->he_twin[me->edge_he[e]] >= 0;
        usage_ok &= interior ? use[e] == 2 && sense_sum[e] == 1 : use[e] == 1;
    }
    CHECK(usage_ok, "%s: each interior edge used by two loops in opposite senses, boundary edges once", what);
    free(use);
    free(sense_sum);
}

/* ------------------------------------------------------------------ STEP parsing */

typedef struct step_ent { const char *body; int len; } step_ent;

/* Entities by id (one per line: "#id=BODY;").  Returns the count (ids 1..n), 0 on a format error. */
static int step_parse(const char *text, step_ent *E, int cap)
{
    const char *p = strstr(text, "DATA;\n");
    CHECK(strncmp(text, "ISO-10303-21;\nHEADER;\n", 22) == 0, "STEP header line");
    CHECK(strstr(text, "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));") != NULL, "AP214 schema");
    CHECK(p != NULL, "DATA section");
    if (!p) return 0;
    p += 6;
    int n = 0;
    while (*p == '#') {
        int id = atoi(p + 1);
        const char *eq = strchr(p, '='), *nl = strchr(p, '\n');
        if (!eq || !nl || id != n + 1 || n + 1 >= cap || nl[-1] != ';') { CHECK(0, "STEP entity %d malformed", n + 1); return 0; }
        E[++n].body = eq + 1;
        E[n].len = (int)(nl - eq - 2);
        p = nl + 1;
    }
    CHECK(strcmp(p, "ENDSEC;\nEND-ISO-10303-21;\n") == 0, "STEP trailer");
    /* every reference resolves */
    int ok = 1;
    for (int i = 1; i <= n; i++)
        for (const char *q = E[i].body; q < E[i].body + E[i].len; q++)
            if (*q == '#') { int r = atoi(q + 1); ok &= r >= 1 && r <= n; }
    CHECK(ok, "STEP: every #reference is defined");
    return n;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static int step_is(const step_ent *e, const char *type)
{
    size_t k = strlen(type);
    return strncmp(e->body, type, k) == 0 && e->body[k] == '(';
}

static int step_count(const step_ent *E, int n, const char *type)
{
    int c = 0;
    for (int i = 1; i <= n; i++) c += step_is(&E[i], type);
    return c;
}

/* ids referenced in body after the first `skip` references */
static int step_refs(const step_ent *e, int *out, int cap)
{
    int m = 0;
    for (const char *q = e->body; q < e->body + e->len && m < cap; q++)
        if (*q == '#') out[m++] = atoi(q + 1);
    return m;
}

static void check_step(const char *what, const char *text, const q2n_nurbs_model *m, int ncomp, int nclosed)
{
    int all_closed = nclosed == ncomp;
    static step_ent E[400000];
    int n = step_parse(text, E, 400000);
    if (!n) return;
    const q2n_mesh *me = m->mesh;
    int rational = m->patches[0].weights != NULL;
    CHECK(step_count(E, n, "ADVANCED_FACE") == me->nf, "%s: %d ADVANCED_FACEs", what, step_count(E, n, "ADVANCED_FACE"));
    CHECK(step_count(E, n, "EDGE_CURVE") == me->ne, "%s: %d EDGE_CURVEs for %d edges", what, step_count(E, n, "EDGE_CURVE"), me->ne);
    CHECK(step_count(E, n, "VERTEX_POINT") == me->nv, "%s: VERTEX_POINTs", what);
    CHECK(step_count(E, n, "ORIENTED_EDGE") == 4 * me->nf, "%s: ORIENTED_EDGEs", what);
    CHECK(step_count(E, n, "CLOSED_SHELL") == nclosed && step_count(E, n, "OPEN_SHELL") == ncomp - nclosed,
          "%s: shells", what);
    CHECK(step_count(E, n, "MANIFOLD_SOLID_BREP") == (all_closed ? ncomp : 0), "%s: solids", what);
    CHECK(step_count(E, n, all_closed ? "ADVANCED_BREP_SHAPE_REPRESENTATION" : "MANIFOLD_SURFACE_SHAPE_REPRESENTATION") == 1,
          "%s: representation", what);
    CHECK(step_count(E, n, "SHAPE_DEFINITION_REPRESENTATION") == 1 && step_count(E, n, "PRODUCT") == 1,
          "%s: product structure", what);
    CHECK(strstr(text, "SI_UNIT(.MILLI.,.METRE.)") && strstr(text, "GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT"), "%s: units", what);
    /* edge usage */
    int *use = calloc((size_t)n + 1, sizeof(int)), *fwd = calloc((size_t)n + 1, sizeof(int)), ok = 1;
    for (int i = 1; i <= n; i++)
        if (step_is(&E[i], "ORIENTED_EDGE")) {
            int r = 0;
            step_refs(&E[i], &r, 1);
            use[r]++;
            fwd[r] += E[i].len > 5 && memcmp(E[i].body + E[i].len - 5, ",.T.)", 5) == 0;
        }
    int nint = 0;
    for (int i = 1; i <= n; i++)
        if (step_is(&E[i], "EDGE_CURVE")) {
            ok &= (use[i] == 2 && fwd[i] == 1) || (use[i] == 1);
            nint += use[i] == 2;
        }
    int nint_mesh = 0;
    for (int e = 0; e < me->ne; e++) nint_mesh += me->he_twin[me->edge_he[e]] >= 0;
    CHECK(ok && nint == nint_mesh, "%s: %d shared EDGE_CURVEs used twice in opposite senses (mesh: %d)", what, nint, nint_mesh);
    free(use);
    free(fwd);
    /* every coordinate triple is one CARTESIAN_POINT (the placement's origin apart): a boundary row
     * that is its edge curve bit for bit, and the curve's ends where they are the vertices, are the
     * same entities; fewer points than the patches' and curves' control points together */
    int dup = 0, npt = 0, ncp = 0;
    for (int f = 0; f < me->nf; f++) ncp += m->patches[f].ncp_u * m->patches[f].ncp_v;
    for (int e = 0; e < me->ne; e++) ncp += m->edges ? m->edges[e].ncp : 0;
    char **pb = malloc(sizeof(char *) * ((size_t)n + 1));
    for (int i = 1; pb && i <= n; i++)
        if (step_is(&E[i], "CARTESIAN_POINT")) pb[npt++] = strndup(E[i].body, (size_t)E[i].len);
    if (pb) qsort(pb, (size_t)npt, sizeof *pb, cmp_str);
    for (int i = 1; pb && i < npt; i++) dup += strcmp(pb[i - 1], pb[i]) == 0;
    for (int i = 0; pb && i < npt; i++) free(pb[i]);
    free(pb);
    CHECK(dup <= 1, "%s: %d CARTESIAN_POINTs repeat another's coordinates", what, dup);
    CHECK(npt < ncp, "%s: %d CARTESIAN_POINTs for %d control points: no boundary shared", what, npt, ncp);
    /* surfaces in face order: control points (u-outer lists) and weights, exactly */
    const char *stype = rational ? "(BOUNDED_SURFACE()B_SPLINE_SURFACE" : "B_SPLINE_SURFACE_WITH_KNOTS";
    int f = 0, exact = 1;
    int *refs = malloc(sizeof(int) * 4096);
    for (int i = 1; i <= n && f < me->nf; i++) {
        if (strncmp(E[i].body, stype, strlen(stype)) != 0) continue;
        const q2n_bspline_surface *s = &m->patches[f++];
        int nr = step_refs(&E[i], refs, 4096);
        exact &= nr == s->ncp_u * s->ncp_v;
        for (int a = 0; a < nr && exact; a++) {
            int iu = a / s->ncp_v, jv = a % s->ncp_v;
            const double *P = s->cp + 3 * (jv * s->ncp_u + iu);
            double x[3];
            exact &= sscanf(E[refs[a]].body, "CARTESIAN_POINT('',(%lf,%lf,%lf))", &x[0], &x[1], &x[2]) == 3;
            exact &= x[0] == P[0] && x[1] == P[1] && x[2] == P[2];
        }
        if (rational) {
            const char *w = strstr(E[i].body, "RATIONAL_B_SPLINE_SURFACE((");
            exact &= w != NULL;
            if (w) w += strlen("RATIONAL_B_SPLINE_SURFACE((");
            for (int a = 0; a < s->ncp_u * s->ncp_v && w && exact; a++) {
                while (*w == '(' || *w == ',' || *w == ')') w++;
                char *end;
                double x = strtod(w, &end);
                exact &= x == s->weights[(a % s->ncp_v) * s->ncp_u + a / s->ncp_v];
                w = end;
            }
        }
    }
    free(refs);
    CHECK(f == me->nf && exact, "%s: %d surfaces in face order, control points%s equal to the model bit for bit",
          what, f, rational ? " and weights" : "");
}

/* ------------------------------------------------------------------ driver */

static int exists(const char *p) { struct stat st; return stat(p, &st) == 0; }

static void roundtrip(const char *what, const q2n_nurbs_model *m, int ncomp, int nclosed)
{
    q2n_error err;
    char *t1, *t2;
    size_t l1, l2;
    q2n_export_options o = {0};
    o.name = "model";
    CHECK(q2n_export_iges_text(m, &o, &t1, &l1, &err) == Q2N_OK, "%s: IGES: %s", what, err.message);
    check_iges(what, t1, m, 0, ncomp, nclosed);
    CHECK(q2n_export_iges_text(m, &o, &t2, &l2, &err) == Q2N_OK && l1 == l2 && memcmp(t1, t2, l1) == 0,
          "%s: IGES deterministic", what);
    free(t2);
    /* entities formatted on 3 threads (records renumbered when appended): the same bytes */
    o.threads = 3;
    CHECK(q2n_export_iges_text(m, &o, &t2, &l2, &err) == Q2N_OK && l1 == l2 && memcmp(t1, t2, l1) == 0,
          "%s: IGES on 3 threads = on one", what);
    o.threads = 0;
    free(t1); free(t2);
    o.iges_plain = 1;
    CHECK(q2n_export_iges_text(m, &o, &t1, &l1, &err) == Q2N_OK, "%s: plain IGES: %s", what, err.message);
    check_iges(what, t1, m, 1, ncomp, nclosed);
    o.threads = 3;
    CHECK(q2n_export_iges_text(m, &o, &t2, &l2, &err) == Q2N_OK && l1 == l2 && memcmp(t1, t2, l1) == 0,
          "%s: plain IGES on 3 threads = on one", what);
    o.threads = 0;
    free(t1); free(t2);
    o.iges_plain = 0;
    CHECK(q2n_export_step_text(m, &o, &t1, &l1, &err) == Q2N_OK, "%s: STEP: %s", what, err.message);
    check_step(what, t1, m, ncomp, nclosed);
    /* edges and faces formatted on 3 threads: the same bytes */
    o.threads = 3;
    CHECK(q2n_export_step_text(m, &o, &t2, &l2, &err) == Q2N_OK && t1 && t2 && l1 == l2 && memcmp(t1, t2, l1) == 0,
          "%s: STEP on 3 threads = on one", what);
    free(t2);
    o.threads = 0;
    /* file output equals the text, twice (determinism), and leaves no temporary file */
    const char *path = chk_scratch("export_rt.step");
    CHECK(q2n_export_file(m, &o, path, &err) == Q2N_OK, "%s: write %s: %s", what, path, err.message);
    t2 = chk_slurp(path, &l2);
    CHECK(t2 && l1 == l2 && memcmp(t1, t2, l1) == 0, "%s: STEP file = text (deterministic)", what);
    CHECK(!chk_count_files(chk_scratch_dir(), ".q2n-"), "%s: no temporary file left", what);
    free(t1); free(t2);
    remove(path);
    /* IGES through a stream (the parameter section goes through a temporary file) = its text */
    CHECK(q2n_export_iges_text(m, &o, &t1, &l1, &err) == Q2N_OK, "%s: IGES: %s", what, err.message);
    path = chk_scratch("export_rt.igs");
    CHECK(q2n_export_file(m, &o, path, &err) == Q2N_OK, "%s: write %s: %s", what, path, err.message);
    t2 = chk_slurp(path, &l2);
    CHECK(t2 && l1 == l2 && memcmp(t1, t2, l1) == 0, "%s: IGES file = text", what);
    CHECK(!chk_count_files(chk_scratch_dir(), ".q2n-"), "%s: no temporary file left (IGES)", what);
    free(t1); free(t2);
    remove(path);
}

int main(void)
{
    q2n_error err;
    /* 1. open polynomial grid (bi-quintic, interior knots) */
    q2n_mesh *g = em_mesh_grid(5, 3);
    q2n_nurbs_model gm = em_model_bilinear(g);
    roundtrip("grid 5x3 bilinear", &gm, 1, 0);
    {   /* 600 faces: the threaded writers' chunks (256 items) end inside every entity kind */
        q2n_mesh *bg = em_mesh_grid(30, 20);
        q2n_nurbs_model bm = em_model_bilinear(bg);
        roundtrip("grid 30x20 bilinear", &bm, 1, 0);
        em_model_release(&bm);
        em_mesh_free(bg);
    }
    gm.tol_abs = 2.5e-4; /* the fit tolerance becomes the IGES resolution and the STEP uncertainty */
    roundtrip("grid with tolerance", &gm, 1, 0);
    {
        char *t;
        size_t l;
        const char *key = "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(";
        CHECK(q2n_export_step_text(&gm, NULL, &t, &l, &err) == Q2N_OK && strstr(t, key) &&
              strtod(strstr(t, key) + strlen(key), NULL) == 2.5e-4, "STEP uncertainty = tol_abs");
        free(t);
    }
    gm.tol_abs = 0.0;
    /* 2. closed rational torus, open rational cylinder */
    q2n_mesh *tm, *cm;
    q2n_nurbs_model tr = em_model_torus_rational(3.0, 1.0, &tm);
    roundtrip("rational torus", &tr, 1, 1);
    q2n_nurbs_model cy = em_model_cylinder_rational(2.0, 3.0, 2, &cm);
    roundtrip("rational cylinder", &cy, 1, 0);
    /* 2b. the torus on the reversed (inward) mesh: faces written reversed so the solid points out */
    {
        q2n_mesh *rm;
        q2n_nurbs_model rv = em_model_reversed(&tr, &rm);
        roundtrip("inward torus", &rv, 1, 1);
        char *t; size_t l;
        CHECK(q2n_export_step_text(&rv, NULL, &t, &l, &err) == Q2N_OK, "inward STEP: %s", err.message);
        int nf = 0, nb = 0;
        for (const char *p = t; (p = strstr(p, "ADVANCED_FACE('',(")); p++) nf += strncmp(strchr(p, ';') - 5, ",.F.)", 5) == 0;
        for (const char *p = t; (p = strstr(p, "FACE_OUTER_BOUND('',")); p++) nb += strncmp(strchr(p, ';') - 5, ",.F.)", 5) == 0;
        CHECK(nf == 16 && nb == 16, "inward torus: %d faces and %d bounds reversed (16)", nf, nb);
        free(t);
        CHECK(q2n_export_step_text(&tr, NULL, &t, &l, &err) == Q2N_OK, "outward STEP: %s", err.message);
        nf = 0;
        for (const char *p = t; (p = strstr(p, "ADVANCED_FACE('',(")); p++) nf += strncmp(strchr(p, ';') - 5, ",.F.)", 5) == 0;
        CHECK(nf == 0, "outward torus: %d faces reversed", nf);
        free(t);
        em_model_release(&rv);
        em_mesh_free(rm);
    }
    /* 3. two components: a grid and the torus side by side (one open, one closed shell) */
    {
        int nv = g->nv + tm->nv, nf = g->nf + tm->nf;
        double *pos = malloc(sizeof(double) * 3 * (size_t)nv);
        int *fv = malloc(sizeof(int) * 4 * (size_t)nf);
        memcpy(pos, g->pos, sizeof(double) * 3 * (size_t)g->nv);
        for (int i = 0; i < 3 * tm->nv; i++) pos[3 * g->nv + i] = tm->pos[i] + (i % 3 == 0 ? 20.0 : 0.0);
        memcpy(fv, g->face_vert, sizeof(int) * 4 * (size_t)g->nf);
        for (int i = 0; i < 4 * tm->nf; i++) fv[4 * g->nf + i] = tm->face_vert[i] + g->nv;
        q2n_mesh *two = em_mesh_build(nv, pos, nf, fv);
        q2n_nurbs_model both = em_model_bilinear(two);
        roundtrip("grid + torus (2 components)", &both, 2, 1);
        em_model_release(&both);
        em_mesh_free(two);
        free(pos); free(fv);
    }
    /* 4. options: inches, author, timestamp */
    {
        q2n_export_options o = {.units = Q2N_UNITS_IN, .author = "A. Author", .organization = "Org, Inc.",
                                .timestamp = "20260101.120000", .name = "m"};
        char *t; size_t l;
        CHECK(q2n_export_iges_text(&gm, &o, &t, &l, &err) == Q2N_OK, "IGES inch: %s", err.message);
        char gl[600] = {0};
        for (const char *p = strchr(t, '\n') + 1; p[72] == 'G'; p += 81) strncat(gl, p, 72);
        CHECK(strstr(gl, ",1.,1,4HINCH,") && strstr(gl, "15H20260101.120000") && strstr(gl, "9HA. Author,9HOrg, Inc.,"),
              "IGES Global units/author/timestamp: %s", gl);
        free(t);
        CHECK(q2n_export_step_text(&gm, &o, &t, &l, &err) == Q2N_OK, "STEP inch: %s", err.message);
        CHECK(strstr(t, "CONVERSION_BASED_UNIT('INCH'") && strstr(t, "LENGTH_MEASURE(25.4)") &&
              strstr(t, "('A. Author'),('Org, Inc.')"), "STEP inch unit and author");
        free(t);
        o.author = "O'Brien";
        CHECK(q2n_export_step_text(&gm, &o, &t, &l, &err) == Q2N_ERR_ARG, "quote in author rejected");
    }
    /* 4b. every unit: IGES global 14/15 (IGES 5.3 table 3) and the STEP unit entity; dates in both
     * formats against the C library's gmtime_r, including a leap day and the epoch */
    {
        static const struct { q2n_units u; const char *iges, *step; } U[] = {
            {Q2N_UNITS_MM, ",1.,2,2HMM,", "SI_UNIT(.MILLI.,.METRE.)"},
            {Q2N_UNITS_CM, ",1.,10,2HCM,", "SI_UNIT(.CENTI.,.METRE.)"},
            {Q2N_UNITS_M, ",1.,6,1HM,", "SI_UNIT($,.METRE.)"},
            {Q2N_UNITS_IN, ",1.,1,4HINCH,", "CONVERSION_BASED_UNIT('INCH'"},
            {Q2N_UNITS_FT, ",1.,4,2HFT,", "CONVERSION_BASED_UNIT('FOOT'"}};
        static const long long dates[] = {0, 951782400, 1700000000, 4102444799LL};
        for (size_t i = 0; i < sizeof U / sizeof U[0]; i++) {
            long long d = dates[i % 4];
            q2n_export_options o = {.units = U[i].u, .has_date = 1, .date = d};
            char *t; size_t l;
            time_t tt = (time_t)d;
            struct tm tm;
            gmtime_r(&tt, &tm);
            char iges_date[32], step_date[32];
            strftime(iges_date, sizeof iges_date, "15H%Y%m%d.%H%M%S", &tm);
            strftime(step_date, sizeof step_date, "'%Y-%m-%dT%H:%M:%S'", &tm);
            CHECK(q2n_export_iges_text(&gm, &o, &t, &l, &err) == Q2N_OK, "IGES %s: %s", q2n_units_name(U[i].u), err.message);
            char gl[600] = {0};
            for (const char *p = strchr(t, '\n') + 1; p[72] == 'G'; p += 81) strncat(gl, p, 72);
            const char *first = strstr(gl, iges_date);
            CHECK(strstr(gl, U[i].iges) && first && strstr(first + 1, iges_date), "IGES global units %s, dates 18/25 %s: %s",
                  q2n_units_name(U[i].u), iges_date, gl);
            free(t);
            CHECK(q2n_export_step_text(&gm, &o, &t, &l, &err) == Q2N_OK, "STEP %s: %s", q2n_units_name(U[i].u), err.message);
            CHECK(strstr(t, U[i].step) && strstr(t, step_date), "STEP unit %s and date %s", U[i].step, step_date);
            if (U[i].u == Q2N_UNITS_FT) CHECK(strstr(t, "LENGTH_MEASURE(304.8)") != NULL, "STEP foot = 304.8 mm");
            free(t);
        }
        q2n_units u;
        CHECK(q2n_units_parse("inch", &u) == 0 && u == Q2N_UNITS_IN && q2n_units_parse("yd", &u) == -1 &&
              q2n_units_in_mm(Q2N_UNITS_FT) == 304.8, "unit names");
        q2n_export_options o = {.has_date = 1, .date = -5};
        char *t; size_t l;
        CHECK(q2n_export_step_text(&gm, &o, &t, &l, &err) == Q2N_ERR_ARG, "a date before 1970 is refused");
    }
    /* 5. rejected inputs leave no file */
    {
        const char *p = chk_scratch("export_bad.igs");
        remove(p);
        enum { GAP_PATCH = 3 }; /* its corner (0,1) is an interior vertex of the grid, shared with 3 neighbours */
        q2n_bspline_surface *s = &gm.patches[GAP_PATCH];
        double keep = s->cp[3 * (s->ncp_u * (s->ncp_v - 1)) + 2];
        s->cp[3 * (s->ncp_u * (s->ncp_v - 1)) + 2] += 1e-3; /* corner (0,1) moves: a gap */
        CHECK(q2n_export_file(&gm, NULL, p, &err) == Q2N_ERR_GEOMETRY && strstr(err.message, "watertight"),
              "gap detected: %s", err.message);
        CHECK(!exists(p) && !chk_count_files(chk_scratch_dir(), ".q2n-"), "no file (and no temporary) after an error");
        s->cp[3 * (s->ncp_u * (s->ncp_v - 1)) + 2] = keep;
        CHECK(q2n_export_file(&gm, NULL, chk_scratch("export_bad.obj"), &err) == Q2N_ERR_ARG, "unknown extension");
        CHECK(q2n_export_file(&gm, NULL, chk_scratch("no/such/dir/x.step"), &err) == Q2N_ERR_IO, "missing dir: %s", err.message);
        double k = s->knots_u[0];
        s->knots_u[0] = -1.0;
        char want[32];
        snprintf(want, sizeof want, "patch %d", GAP_PATCH);
        CHECK(q2n_export_file(&gm, NULL, p, &err) == Q2N_ERR_ARG && strstr(err.message, want), "bad knots: %s", err.message);
        s->knots_u[0] = k;
        CHECK(!exists(p), "no file after the knot error");
        gm.n--;
        CHECK(q2n_export_file(&gm, NULL, p, &err) == Q2N_ERR_ARG, "patch count mismatch");
        gm.n++;
    }
    /* 6. real formatting rules shared by both formats: every real has a '.' and an upper-case E */
    {
        char *t; size_t l;
        q2n_export_step_text(&cy, NULL, &t, &l, &err);
        int bad = 0;
        for (const char *p = t; (p = strstr(p, "CARTESIAN_POINT('',(")); p++) {
            const char *q = p + 20, *e = strchr(q, ')');
            for (const char *tok = q; tok < e;) {
                const char *c = memchr(tok, ',', (size_t)(e - tok));
                const char *te = c ? c : e;
                if (!memchr(tok, '.', (size_t)(te - tok)) || memchr(tok, 'e', (size_t)(te - tok))) bad++;
                tok = te + 1;
            }
        }
        CHECK(bad == 0, "%d STEP reals without '.' or with lower-case exponent", bad);
        free(t);
    }
    em_model_release(&gm); em_mesh_free(g);
    em_model_release(&tr); em_mesh_free(tm);
    em_model_release(&cy); em_mesh_free(cm);
    CHECK_DONE("test_export_roundtrip");
}
