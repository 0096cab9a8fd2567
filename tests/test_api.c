/* test_api.c — the public API (include/quad2nurbs.h): open, evaluate, write, errors.  The
 * evaluation is compared with the mesh vertices it must interpolate (augmented surface) and with
 * finite differences of itself for the derivatives; several outputs are all or nothing; the
 * progress callback sees every stage in order; scale, units, targets and the memory limit. */
#include "check.h"
#include "quad2nurbs.h"

/* data/demo_torus.obj: patch CORNER_PATCH has the file's first vertex at (u, v) = (0, 0) (its
 * face's first corner); FD_PATCH is any other patch, for the finite difference. */
enum { CORNER_PATCH = 0, FD_PATCH = 5 };

typedef struct progress_log {
    int n, stages_ok, order_ok;
    double last;
    char seen[256];
} progress_log;

static void on_progress(void *user, const q2n_progress *p)
{
    progress_log *l = user;
    if (!l->n) l->stages_ok = l->order_ok = 1;
    l->n++;
    if (!p->stage || !p->detail) l->stages_ok = 0;
    if (p->total < 0 || p->done < 0 || (p->total > 0 && p->done > p->total) || p->elapsed_s < l->last) l->order_ok = 0;
    l->last = p->elapsed_s;
    if (p->stage && !strstr(l->seen, p->stage) && strlen(l->seen) + strlen(p->stage) + 2 < sizeof l->seen) {
        strcat(l->seen, p->stage);
        strcat(l->seen, " ");
    }
}

/* Status strings, version macros and the string forms of every enum: each name parses back to
 * its value and appears in the list shown in messages; unknown names are refused. */
static void test_status_and_choices(void)
{
    CHECK(!strcmp(q2n_status_string(Q2N_OK), "ok") && !strcmp(q2n_status_string(Q2N_ERR_IO), "i/o error") &&
          !strcmp(q2n_status_string(Q2N_ERR_NUMERIC), "numeric failure") &&
          !strcmp(q2n_status_string((q2n_status)99), "unknown error"), "status strings");
    char v[32];
    snprintf(v, sizeof v, "%d.%d.%d", Q2N_VERSION_MAJOR, Q2N_VERSION_MINOR, Q2N_VERSION_PATCH);
    CHECK(!strcmp(v, QUAD2NURBS_VERSION) && !strcmp(q2n_version(), v), "version %s = macros %s", q2n_version(), v);
    long online = sysconf(_SC_NPROCESSORS_ONLN); /* the affinity may allow fewer, never more */
    int dt = q2n_default_threads();
    CHECK(dt >= 1 && dt <= 64 && (online < 1 || dt <= online), "default threads %d (online processors %ld)", dt, online);
    int names = 0;
    for (int c = 0; c < Q2N_CHOICE_COUNT; c++) {
        const char *name;
        for (int i = 0; (name = q2n_choice_name((q2n_choice)c, i)); i++) {
            if (!strcmp(name, "default") || !strcmp(name, "none")) continue;
            int val = -1;
            CHECK(q2n_parse_choice((q2n_choice)c, name, &val) == Q2N_OK && val == i, "choice %d: '%s' parses to %d", c, name, val);
            CHECK(strstr(q2n_choice_list((q2n_choice)c), name) != NULL, "choice %d: '%s' in the list '%s'", c, name,
                  q2n_choice_list((q2n_choice)c));
            names++;
        }
        int val = 42;
        CHECK(q2n_parse_choice((q2n_choice)c, "nurbs-magic", &val) == Q2N_ERR_ARG && val == 42, "choice %d: unknown refused", c);
        CHECK(q2n_parse_choice((q2n_choice)c, "default", &val) == Q2N_ERR_ARG, "choice %d: 'default' is no name", c);
    }
    CHECK(names == 3 + 5 + 4 + 2 + 2 + 4 + 5 + 4 + 2 + 2 + 2, "%d names", names);
    int val = -1;
    CHECK(q2n_parse_choice(Q2N_CHOICE_SURFACE, "acc-g1", &val) == Q2N_OK && val == Q2N_SURFACE_ACC_G1, "acc-g1");
    CHECK(q2n_parse_choice(Q2N_CHOICE_CLASS, "d3c1p2s4", &val) == Q2N_OK && val == Q2N_CLASS_D3C1P2S4, "class any case");
    CHECK(q2n_parse_choice(Q2N_CHOICE_UNITS, "inch", &val) == Q2N_OK && val == Q2N_UNITS_IN, "units alias");
    CHECK(q2n_parse_choice(Q2N_CHOICE_FORMAT, "stp", &val) == Q2N_OK && val == Q2N_FORMAT_STEP, "format alias");
    CHECK(q2n_parse_choice(Q2N_CHOICE_COUNT, "g1", &val) == Q2N_ERR_ARG && q2n_choice_name(Q2N_CHOICE_COUNT, 0) == NULL &&
          q2n_choice_name(Q2N_CHOICE_SURFACE, 3) == NULL && q2n_choice_name(Q2N_CHOICE_SURFACE, -1) == NULL,
          "out of range");
}

/* ------------------------------------------------------------------ meshes from memory */

typedef struct obj_arrays {
    int nv, nf;
    double pos[3 * 1024];
    int sizes[1024], verts[4 * 1024];
} obj_arrays;

/* The v and f records of a small OBJ with plain indices (data/demo_torus.obj), 0-based. */
static int read_obj_arrays(const char *path, obj_arrays *a)
{
    FILE *f = fopen(path, "r");
    char line[256];
    int nc = 0;
    a->nv = a->nf = 0;
    while (f && fgets(line, sizeof line, f)) {
        double x, y, z;
        int q[4];
        if (a->nv < 1024 && sscanf(line, "v %lf %lf %lf", &x, &y, &z) == 3) {
            a->pos[3 * a->nv] = x, a->pos[3 * a->nv + 1] = y, a->pos[3 * a->nv + 2] = z;
            a->nv++;
        } else if (a->nf < 1024 && sscanf(line, "f %d %d %d %d", &q[0], &q[1], &q[2], &q[3]) == 4) {
            for (int i = 0; i < 4; i++) a->verts[nc++] = q[i] - 1;
            a->sizes[a->nf++] = 4;
        }
    }
    if (f) fclose(f);
    return f ? 0 : -1;
}

static long read_all(const char *path, char **out)
{
    FILE *f = fopen(path, "rb");
    *out = NULL;
    if (!f) return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    *out = malloc((size_t)n + 1);
    if (!*out || fread(*out, 1, (size_t)n, f) != (size_t)n) n = -1;
    else (*out)[n] = 0;
    fclose(f);
    return n;
}

/* The same torus from arrays and from its OBJ file: identical samples and STEP bytes (with
 * SOURCE_DATE_EPOCH); face_sizes NULL means quads. */
/* The rim in the report: a one-ring of five quads around a raised vertex of valence 5 (every face
 * at the extraordinary vertex, five rim vertices of two faces, five corners of one face): the open
 * edge runs on smoothly through the rim vertices, up to rounding. */
static void test_rim_report(void)
{
    double pos[3 * 11];
    int fv[20];
    pos[0] = pos[1] = 0, pos[2] = 0.5;
    for (int k = 0; k < 10; k++) { /* rim: vertices 1 + 2j at radius 1, 2 + 2j between at 1.1 */
        double a = 2 * 3.14159265358979323846 * k / 10, r = k % 2 ? 1.1 : 1;
        pos[3 * (1 + k)] = r * cos(a), pos[3 * (1 + k) + 1] = r * sin(a), pos[3 * (1 + k) + 2] = 0.1 * (k % 3);
    }
    for (int j = 0; j < 5; j++)
        fv[4 * j] = 0, fv[4 * j + 1] = 1 + 2 * j, fv[4 * j + 2] = 2 + 2 * j, fv[4 * j + 3] = 1 + (2 * j + 2) % 10;
    char err[512];
    q2n_model *m = NULL;
    CHECK(q2n_open_mesh(11, pos, 5, NULL, fv, NULL, &m, err, sizeof err) == Q2N_OK, "open the one-ring: %s", err);
    if (!m) return;
    q2n_report r;
    CHECK(q2n_fit(m, err, sizeof err) == Q2N_OK, "fit the one-ring: %s", err);
    CHECK(q2n_get_report(m, &r) == Q2N_OK && r.rim_vertices == 5 && r.rim_max_deg <= 1e-6 && r.rim_curvature_jump_rel <= 1e-6,
          "one-ring: %d rim vertices, the rim turns by %.3g deg, its curvature jumps by %.3g", r.rim_vertices, r.rim_max_deg,
          r.rim_curvature_jump_rel);
    q2n_close(m);
}

static void test_arrays_match_file(void)
{
    static obj_arrays a;
    char err[512];
    CHECK(read_obj_arrays("data/demo_torus.obj", &a) == 0 && a.nv == 128 && a.nf == 128, "torus arrays: %d %d", a.nv, a.nf);
    setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
    q2n_model *mf = NULL, *ma = NULL, *mq = NULL;
    CHECK(q2n_open("data/demo_torus.obj", NULL, &mf, err, sizeof err) == Q2N_OK, "open file: %s", err);
    CHECK(q2n_open_mesh((size_t)a.nv, a.pos, (size_t)a.nf, a.sizes, a.verts, NULL, &ma, err, sizeof err) == Q2N_OK,
          "open arrays: %s", err);
    CHECK(q2n_open_mesh((size_t)a.nv, a.pos, (size_t)a.nf, NULL, a.verts, NULL, &mq, err, sizeof err) == Q2N_OK,
          "open arrays, quads: %s", err);
    if (!mf || !ma || !mq) { q2n_close(mf); q2n_close(ma); q2n_close(mq); return; }
    int same = 1;
    for (int k = 0; k < q2n_patch_count(mf); k++)
        for (int s = 0; s < 9; s++) {
            double pf[9], pa[9], pq[9], u = (s % 3) * 0.45 + 0.05, v = (s / 3) * 0.45 + 0.05;
            q2n_patch_eval(mf, k, u, v, pf);
            q2n_patch_eval(ma, k, u, v, pa);
            q2n_patch_eval(mq, k, u, v, pq);
            same &= !memcmp(pf, pa, sizeof pf) && !memcmp(pf, pq, sizeof pf);
        }
    CHECK(q2n_patch_count(ma) == 128 && same, "arrays and file: the same samples, bit for bit");
    /* the same name (the STEP product is named after the file), written from each in turn */
    char path[4096];
    snprintf(path, sizeof path, "%s", chk_scratch("torus.step"));
    char *tf = NULL, *ta = NULL;
    long nf = -1, na = -1;
    CHECK(q2n_write(mf, path, err, sizeof err) == Q2N_OK && (nf = read_all(path, &tf)) > 10000, "write from file: %s", err);
    CHECK(q2n_write(ma, path, err, sizeof err) == Q2N_OK && (na = read_all(path, &ta)) > 10000, "write from arrays: %s", err);
    CHECK(tf && ta && nf == na && !memcmp(tf, ta, (size_t)nf), "STEP from arrays = STEP from the file (%ld, %ld bytes)", nf, na);
    free(tf);
    free(ta);
    q2n_close(mf);
    q2n_close(ma);
    q2n_close(mq);
    unsetenv("SOURCE_DATE_EPOCH");
}

/* Fits run one after another in one process (and on one thread) do not see each other: the fit
 * keeps per-thread memos of construction values, keyed by the fit.  The torus mirrored in z, then
 * the torus, then the mirrored one again: the two mirrored files are the same bytes.  (Mirroring is
 * exact and keeps every dot product, so both tori ask for the same edges at the same parameter
 * bits: a memo keyed only by edge and parameter would answer the third fit with the second's
 * frames.) */
static long fit_write(const obj_arrays *a, const double *pos, const char *path, char **text)
{
    char err[512];
    q2n_options o = {0};
    o.threads = 1;
    q2n_model *m = NULL;
    long n = -1;
    if (q2n_open_mesh((size_t)a->nv, pos, (size_t)a->nf, a->sizes, a->verts, &o, &m, err, sizeof err) == Q2N_OK &&
        q2n_fit(m, err, sizeof err) == Q2N_OK && q2n_write(m, path, err, sizeof err) == Q2N_OK)
        n = read_all(path, text);
    q2n_close(m);
    return n;
}

static void test_fits_in_sequence(void)
{
    static obj_arrays a;
    static double st[3 * 1024]; /* the torus mirrored in z */
    if (read_obj_arrays("data/demo_torus.obj", &a) != 0) { CHECK(0, "read demo torus"); return; }
    for (int i = 0; i < a.nv; i++) st[3 * i] = a.pos[3 * i], st[3 * i + 1] = a.pos[3 * i + 1], st[3 * i + 2] = -a.pos[3 * i + 2];
    setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
    char path[4096], *t1 = NULL, *t2 = NULL, *t3 = NULL;
    snprintf(path, sizeof path, "%s", chk_scratch("sequence.step"));
    long n1 = fit_write(&a, st, path, &t1), n2 = fit_write(&a, a.pos, path, &t2), n3 = fit_write(&a, st, path, &t3);
    CHECK(n1 > 10000 && n2 > 10000 && n3 == n1 && !memcmp(t1, t3, (size_t)n1) && (n2 != n1 || memcmp(t1, t2, (size_t)n1)),
          "mirrored torus, torus, mirrored torus: the two mirrored files are the same bytes (%ld, %ld, %ld)", n1, n2, n3);
    free(t1);
    free(t2);
    free(t3);
    unsetenv("SOURCE_DATE_EPOCH");
}

/* Bad arrays: the status and a message naming the element. */
static void test_bad_arrays(void)
{
    static const double P[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0};
    static const int Q[] = {0, 1, 2, 3, 1, 4, 5, 2};
    static const int SIZES[] = {4, 4};
    char err[512];
    q2n_model *m = NULL;
    CHECK(q2n_open_mesh(6, P, 2, SIZES, Q, NULL, &m, err, sizeof err) == Q2N_OK && q2n_patch_count(m) == 2,
          "two quads: %s", err);
    q2n_close(m);
    static const int OUT[] = {0, 1, 2, 3, 1, 4, 9, 2};
    CHECK(q2n_open_mesh(6, P, 2, SIZES, OUT, NULL, &m, err, sizeof err) == Q2N_ERR_TOPOLOGY && !m &&
          strstr(err, "mesh: face 1 vertex index 9 out of range (6 vertices)"), "index out of range: %s", err);
    static const int NEG[] = {0, 1, 2, -1, 1, 4, 5, 2};
    CHECK(q2n_open_mesh(6, P, 2, SIZES, NEG, NULL, &m, err, sizeof err) == Q2N_ERR_TOPOLOGY &&
          strstr(err, "face 0 vertex index -1 out of range"), "negative index: %s", err);
    double nan_p[18];
    memcpy(nan_p, P, sizeof nan_p);
    nan_p[3 * 4 + 1] = NAN;
    CHECK(q2n_open_mesh(6, nan_p, 2, SIZES, Q, NULL, &m, err, sizeof err) == Q2N_ERR_PARSE &&
          strstr(err, "mesh: vertex 4 has a non-finite coordinate"), "NaN: %s", err);
    static const int TRI[] = {0, 1, 2, 3, 1, 4, 2};
    static const int TSIZES[] = {4, 3};
    CHECK(q2n_open_mesh(6, P, 2, TSIZES, TRI, NULL, &m, err, sizeof err) == Q2N_ERR_UNSUPPORTED &&
          strstr(err, "mesh: face 1 has 3 vertices; only quad meshes"), "non-quad: %s", err);
    q2n_options sub = {0};
    sub.subdivide = 1;
    CHECK(q2n_open_mesh(6, P, 2, TSIZES, TRI, &sub, &m, err, sizeof err) == Q2N_OK && q2n_patch_count(m) == 7,
          "non-quad with one Catmull-Clark step: %s", err);
    q2n_close(m);
    static const int TWO[] = {4, 2};
    CHECK(q2n_open_mesh(6, P, 2, TWO, Q, NULL, &m, err, sizeof err) == Q2N_ERR_TOPOLOGY && strstr(err, "mesh: face 1 has 2"),
          "two-corner face: %s", err);
    static const int REP[] = {0, 1, 2, 3, 1, 4, 4, 2};
    q2n_status st = q2n_open_mesh(6, P, 2, SIZES, REP, NULL, &m, err, sizeof err);
    CHECK(st != Q2N_OK && !m && strstr(err, "mesh") && strstr(err, "face 1"), "repeated corner: %s (%s)", err,
          q2n_status_string(st));
    /* a zero-area quad: all four corners on a line */
    static const double LINE[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
    static const int LQ[] = {0, 1, 2, 3};
    st = q2n_open_mesh(4, LINE, 1, NULL, LQ, NULL, &m, err, sizeof err);
    CHECK((st == Q2N_ERR_GEOMETRY || st == Q2N_ERR_TOPOLOGY) && !m && strstr(err, "mesh"), "degenerate quad: %s (%s)", err,
          q2n_status_string(st));
    CHECK(q2n_open_mesh(6, P, 0, NULL, Q, NULL, &m, err, sizeof err) == Q2N_ERR_TOPOLOGY && strstr(err, "empty mesh"),
          "no faces: %s", err);
    CHECK(q2n_open_mesh(6, NULL, 2, NULL, Q, NULL, &m, err, sizeof err) == Q2N_ERR_ARG, "no positions: %s", err);
}

/* ------------------------------------------------------------------ the fitted result */

/* Cox–de Boor: the basis functions of degree p at t (clamped knots, t in [0,1]) into N (p+1
 * values) for the span returned. */
static int basis(const double *U, int n, int p, double t, double *N)
{
    int s = p;
    while (s < n - 1 && !(t < U[s + 1])) s++;
    double left[16], right[16];
    N[0] = 1;
    for (int j = 1; j <= p; j++) {
        left[j] = t - U[s + 1 - j];
        right[j] = U[s + j] - t;
        double saved = 0;
        for (int r = 0; r < j; r++) {
            double tmp = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * tmp;
            saved = left[j - r] * tmp;
        }
        N[j] = saved;
    }
    return s;
}

/* Distance from p to patch k of the construction: Gauss–Newton foot point from (u, v), kept in
 * [0,1]^2 (the fit's reparametrization maps every side onto itself, so the foot lies in the
 * patch). */
static double foot_distance(const q2n_model *m, int k, double u, double v, const double p[3])
{
    double e[9], d = INFINITY;
    for (int it = 0; it < 30; it++) {
        if (q2n_patch_eval(m, k, u, v, e) != Q2N_OK) return INFINITY;
        double r[3] = {e[0] - p[0], e[1] - p[1], e[2] - p[2]};
        d = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        double a = 0, b = 0, c = 0, gu = 0, gv = 0;
        for (int i = 0; i < 3; i++) {
            a += e[3 + i] * e[3 + i], b += e[3 + i] * e[6 + i], c += e[6 + i] * e[6 + i];
            gu += e[3 + i] * r[i], gv += e[6 + i] * r[i];
        }
        double det = a * c - b * b;
        if (!(det > 0)) break;
        double du = -(c * gu - b * gv) / det, dv = -(a * gv - b * gu) / det;
        u = fmin(1, fmax(0, u + du));
        v = fmin(1, fmax(0, v + dv));
        if (fabs(du) + fabs(dv) < 1e-15) break;
    }
    return d;
}

static void deboor(const q2n_patch_spline *sp, double u, double v, double out[3])
{
    double Nu[16], Nv[16];
    int su = basis(sp->knots_u, sp->ncp_u, sp->deg_u, u, Nu), sv = basis(sp->knots_v, sp->ncp_v, sp->deg_v, v, Nv);
    out[0] = out[1] = out[2] = 0;
    for (int j = 0; j <= sp->deg_v; j++)
        for (int i = 0; i <= sp->deg_u; i++) {
            const double *c = sp->cp + 3 * ((size_t)(sv - sp->deg_v + j) * sp->ncp_u + (size_t)(su - sp->deg_u + i));
            for (int d = 0; d < 3; d++) out[d] += Nu[i] * Nv[j] * c[d];
        }
}

/* The k-th B_SPLINE_SURFACE_WITH_KNOTS of a STEP text: its control points (u fastest, as
 * q2n_patch_spline) and knots with multiplicities expanded; returns 0 on success. */
static int step_surface(const char *t, int k, int *ncp_u, int *ncp_v, double *cp, int cap, double *ku, double *kv)
{
    const char *s = t;
    for (int i = 0; i <= k; i++) {
        s = strstr(s, "B_SPLINE_SURFACE_WITH_KNOTS('',");
        if (!s) return -1;
        if (i < k) s++;
    }
    int du, dv, n;
    if (sscanf(s, "B_SPLINE_SURFACE_WITH_KNOTS('',%d,%d,(%n", &du, &dv, &n) != 2) return -1;
    s += n;
    int ids[4096], nu = 0, nv = 0, cnt = 0;
    while (*s == '(' || *s == ',') {
        if (*s == ',') s++;
        if (*s != '(') break;
        s++, nu++;
        int row = 0;
        while (*s == '#') {
            int id;
            if (sscanf(s, "#%d%n", &id, &n) != 1 || cnt >= 4096) return -1;
            ids[cnt++] = id;
            s += n;
            row++;
            if (*s == ',') s++;
        }
        if (*s++ != ')') return -1;
        nv = row;
    }
    if (nu * nv != cnt || cnt > cap) return -1;
    *ncp_u = nu, *ncp_v = nv;
    /* the lists are over u of lists over v */
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            char key[32];
            snprintf(key, sizeof key, "\n#%d=CARTESIAN_POINT('',(", ids[i * nv + j]);
            const char *p = strstr(t, key + 1) ;
            while (p && p > t && p[-1] != '\n') p = strstr(p + 1, key + 1);
            if (!p) return -1;
            double *c = cp + 3 * (j * nu + i);
            if (sscanf(p + strlen(key) - 1, "%lf,%lf,%lf", &c[0], &c[1], &c[2]) != 3) return -1;
        }
    /* "),.UNSPECIFIED.,.F.,.F.,.F.,(mults u),(mults v),(knots u),(knots v)" */
    s = strstr(s, ".F.,.F.,.F.,(");
    if (!s) return -1;
    s += strlen(".F.,.F.,.F.,");
    int mu[64], mv[64], nmu = 0, nmv = 0;
    double xu[64], xv[64];
    int *ms[2] = {mu, mv}, *nms[2] = {&nmu, &nmv};
    for (int l = 0; l < 2; l++) {
        if (*s++ != '(') return -1;
        while (sscanf(s, "%d%n", &ms[l][*nms[l]], &n) == 1 && *nms[l] < 64) {
            (*nms[l])++, s += n;
            if (*s == ',') s++;
        }
        if (*s++ != ')' || *s++ != ',') return -1;
    }
    double *xs[2] = {xu, xv};
    for (int l = 0; l < 2; l++) {
        int c = 0;
        if (*s++ != '(') return -1;
        while (c < 64 && sscanf(s, "%lf%n", &xs[l][c], &n) == 1) {
            c++, s += n;
            if (*s == ',') s++;
        }
        if (*s++ != ')' || *s++ != ',' || c != *nms[l]) return -1;
    }
    int w = 0;
    for (int i = 0; i < nmu; i++)
        for (int r = 0; r < mu[i]; r++) ku[w++] = xu[i];
    if (w != nu + du + 1) return -1;
    w = 0;
    for (int i = 0; i < nmv; i++)
        for (int r = 0; r < mv[i]; r++) kv[w++] = xv[i];
    return w == nv + dv + 1 ? 0 : -1;
}

/* After the fit: patch k's spline equals STEP face k's B_SPLINE_SURFACE bit for bit, evaluating
 * it (de Boor, written here) stays within the reported deviation of the construction, and the
 * report's figures agree with what the splines show (control point count). */
static void test_fitted_result(void)
{
    char err[512];
    q2n_options o = {0};
    o.scale = 3; /* everything returned is in model units: the input times scale */
    q2n_model *m = NULL;
    q2n_patch_spline sp;
    CHECK(q2n_open("data/demo_torus.obj", &o, &m, err, sizeof err) == Q2N_OK, "open: %s", err);
    if (!m) return;
    CHECK(q2n_patch_spline_get(m, 0, &sp) == Q2N_ERR_ARG, "no spline before the fit");
    q2n_report r;
    CHECK(q2n_get_report(m, &r) == Q2N_OK && !r.fitted && r.faces == 128 && r.patches == 128 && r.input_faces == 128,
          "report before the fit: %d faces", r.faces);
    CHECK(q2n_fit(m, err, sizeof err) == Q2N_OK, "fit: %s", err);
    char path[4096];
    snprintf(path, sizeof path, "%s", chk_scratch("fitted.step"));
    CHECK(q2n_write(m, path, err, sizeof err) == Q2N_OK, "write: %s", err);
    CHECK(q2n_get_report(m, &r) == Q2N_OK && r.fitted && r.dev_met && r.max_dev > 0 && r.continuity == 2,
          "report: fitted, max dev %g", r.max_dev);
    CHECK_NEAR(r.max_dev, r.max_dev_rel * r.diag, 1e-15 * r.diag, "max_dev = max_dev_rel x diag");
    CHECK(r.step_bytes > 0 && r.units == Q2N_UNITS_MM && r.t_fit > 0, "report: STEP %ld bytes", r.step_bytes);
    char *text;
    CHECK(read_all(path, &text) > 0, "read STEP");
    long cps = 0;
    int same = 1, n_checked = 0;
    double worst = 0;
    static double cp[3 * 4096], ku[128], kv[128];
    for (int k = 0; k < q2n_patch_count(m); k++) {
        if (q2n_patch_spline_get(m, k, &sp) != Q2N_OK) { same = 0; break; }
        cps += (long)sp.ncp_u * sp.ncp_v;
        if (k % 17 == 0 && text) { /* a spread of patches against the file */
            int nu, nv;
            int ok = step_surface(text, k, &nu, &nv, cp, 4096, ku, kv) == 0 && nu == sp.ncp_u && nv == sp.ncp_v &&
                     sp.deg_u == 5 && sp.deg_v == 5 && !sp.weights;
            ok = ok && !memcmp(cp, sp.cp, 3 * sizeof(double) * (size_t)nu * nv) &&
                 !memcmp(ku, sp.knots_u, sizeof(double) * (size_t)(nu + 6)) &&
                 !memcmp(kv, sp.knots_v, sizeof(double) * (size_t)(nv + 6));
            if (!ok) fprintf(stderr, "patch %d differs from STEP face %d\n", k, k);
            same &= ok;
            n_checked++;
            for (int j = 0; j <= 10; j++)
                for (int i = 0; i <= 10; i++) {
                    double s[3], u = i / 10.0, v = j / 10.0;
                    deboor(&sp, u, v, s);
                    double d = foot_distance(m, k, u, v, s);
                    if (d > worst) worst = d;
                }
        }
    }
    CHECK(same && n_checked == 8, "control points and knots of %d patches = STEP's", n_checked);
    CHECK(cps == r.cp_total, "control points %ld = report's cp_total %ld", cps, r.cp_total);
    printf("test_api: de Boor to construction %.3g, reported max dev %.3g\n", worst, r.max_dev);
    CHECK(worst <= r.max_dev * 1.01 && worst > 0, "de Boor of the returned spline to the construction (foot points): %.3g <= max dev %.3g",
          worst, r.max_dev);
    CHECK(q2n_patch_spline_get(m, 128, &sp) == Q2N_ERR_ARG && q2n_patch_spline_get(m, -1, &sp) == Q2N_ERR_ARG,
          "patch out of range");
    free(text);
    q2n_close(m);
}

int main(void)
{
    test_status_and_choices();
    test_arrays_match_file();
    test_rim_report();
    test_bad_arrays();
    test_fitted_result();
    test_fits_in_sequence();
    char err[512];
    q2n_model *m = NULL;
    CHECK(strcmp(q2n_version(), QUAD2NURBS_VERSION) == 0, "version");
    CHECK(q2n_open("/nonexistent.obj", NULL, &m, err, sizeof err) != 0 && strstr(err, "nonexistent"),
          "missing file reported: %s", err);
    q2n_options bad = {0};
    bad.surface = (q2n_surface_method)7;
    CHECK(q2n_open("data/demo_torus.obj", &bad, &m, err, sizeof err) != 0 && strstr(err, "invalid surface 7"),
          "bad option reported: %s", err);
    q2n_options badl = {0};
    badl.limit_points = 2;
    CHECK(q2n_open("data/demo_torus.obj", &badl, &m, err, sizeof err) == Q2N_ERR_ARG && strstr(err, "invalid limit_points 2"),
          "bad limit_points reported: %s", err);
    q2n_options badf = {0};
    badf.keep_flat = 2;
    CHECK(q2n_open("data/demo_torus.obj", &badf, &m, err, sizeof err) == Q2N_ERR_ARG && strstr(err, "invalid keep_flat 2"),
          "bad keep_flat reported: %s", err);
    CHECK(q2n_open("data/demo_torus.obj", NULL, &m, err, sizeof err) == 0, "open demo: %s", err);
    if (!m) CHECK_DONE("test_api");
    CHECK(q2n_patch_count(m) == 128, "128 patches");
    FILE *f = fopen("data/demo_torus.obj", "r");
    char line[256];
    double v0[3] = {0, 0, 0};
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "v %lf %lf %lf", &v0[0], &v0[1], &v0[2]) == 3) break; /* vertex 1 = v0 of face 0 */
    if (f) fclose(f);
    double p[9], a[9], b[9], h = 1e-6;
    CHECK(q2n_patch_covered(m, CORNER_PATCH) && q2n_patch_eval(m, CORNER_PATCH, 0, 0, p) == 0, "eval");
    CHECK_NEAR(p[0], v0[0], 1e-12, "corner x");
    CHECK_NEAR(p[1], v0[1], 1e-12, "corner y");
    CHECK_NEAR(p[2], v0[2], 1e-12, "corner z");
    q2n_patch_eval(m, FD_PATCH, 0.3 - h, 0.6, a);
    q2n_patch_eval(m, FD_PATCH, 0.3 + h, 0.6, b);
    q2n_patch_eval(m, FD_PATCH, 0.3, 0.6, p);
    CHECK_NEAR(p[3], (b[0] - a[0]) / (2 * h), 1e-6, "Su vs finite difference");
    const char *objp = chk_scratch("api.obj");
    remove(objp);
    CHECK(q2n_write(m, objp, err, sizeof err) == 0 && access(objp, R_OK) == 0, "write obj: %s", err);
    CHECK(q2n_write(m, chk_scratch("x.unknown"), err, sizeof err) != 0 && access(chk_scratch("x.unknown"), F_OK) != 0,
          "unknown extension refused, nothing written");
    remove(objp);
    /* several outputs: all or nothing; the same file twice is refused */
    char stepp[4096], igsp[4096];
    snprintf(stepp, sizeof stepp, "%s", chk_scratch("api.step"));
    snprintf(igsp, sizeof igsp, "%s", chk_scratch("api.igs"));
    const char *bad2[] = {stepp, "/nonexistent_dir/x.igs"};
    CHECK(q2n_write_all(m, bad2, 2, err, sizeof err) != 0 && strstr(err, "/nonexistent_dir/x.igs") && access(stepp, F_OK) != 0,
          "write_all with an unwritable second output leaves nothing: %s", err);
    const char *twice[] = {stepp, stepp};
    CHECK(q2n_write_all(m, twice, 2, err, sizeof err) != 0 && strstr(err, "twice"), "same output twice: %s", err);
    const char *good[] = {stepp, igsp};
    CHECK(q2n_write_all(m, good, 2, err, sizeof err) == 0 && access(stepp, R_OK) == 0 && access(igsp, R_OK) == 0,
          "write_all: %s", err);
    remove(stepp);
    remove(igsp);
    q2n_close(m);
    q2n_close(NULL);

    /* options of the public header: progress reports, scale, units, tolerances, memory limit */
    progress_log log = {0};
    q2n_options o = {0};
    o.progress = on_progress;
    o.progress_user = &log;
    o.scale = 2;
    o.units = Q2N_UNITS_IN;
    o.angle_tol_deg = 0.5;
    o.tol = 1e-4;
    q2n_model *s = NULL;
    CHECK(q2n_open("data/demo_torus.obj", &o, &s, err, sizeof err) == 0, "open with options: %s", err);
    if (s) {
        double a[9];
        q2n_patch_eval(s, CORNER_PATCH, 0, 0, a);
        CHECK(a[0] == 2 * v0[0] && a[1] == 2 * v0[1] && a[2] == 2 * v0[2], "scale 2 doubles the evaluation");
        char jp[4096];
        snprintf(jp, sizeof jp, "%s", chk_scratch("api_opts.json"));
        CHECK(q2n_write(s, jp, err, sizeof err) == 0, "fit and report: %s", err);
        FILE *jf = fopen(jp, "r");
        char js[4096] = "";
        if (jf) { size_t n = fread(js, 1, sizeof js - 1, jf); js[n] = 0; fclose(jf); }
        CHECK(strstr(js, "\"units\": \"in\"") && strstr(js, "\"g1_tol_deg\": 0.5") && strstr(js, "\"tol\": 0.0001"),
              "report shows units and targets: %.300s", js);
        unlink(jp);
        CHECK(log.n > 0 && log.stages_ok && log.order_ok, "progress: %d reports, stages %s, counts and times %s", log.n,
              log.stages_ok ? "ok" : "missing", log.order_ok ? "ok" : "wrong");
        CHECK(strstr(log.seen, "read") && strstr(log.seen, "build") && strstr(log.seen, "fit") && strstr(log.seen, "write"),
              "stages reported: %s", log.seen);
        q2n_close(s);
    }
    q2n_options bu = {0};
    bu.units = (q2n_units)9;
    CHECK(q2n_open("data/demo_torus.obj", &bu, &s, err, sizeof err) == Q2N_ERR_ARG && strstr(err, "invalid units 9"),
          "unknown unit: %s", err);
    q2n_options mm = {0};
    mm.max_memory = 1e5;
    CHECK(q2n_open("data/demo_torus.obj", &mm, &s, err, sizeof err) != 0 && strstr(err, "would need about"),
          "memory limit: %s", err);
    CHECK_DONE("test_api");
}
