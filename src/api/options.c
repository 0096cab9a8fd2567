/* options.c — what the api stage checks before a run (model.h): options the chosen path ignores,
 * the absolute tolerance, the files' date, and the estimated memory and output sizes against the
 * limits (figures in policy.h). */
#include "api/model.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/statvfs.h>
#include <time.h>
#include <unistd.h>

#include "api/api_policy.h"
#include "api/policy.h"
#include "fit/fit_policy.h"
#include "patch/extraordinary.h"

/* ------------------------------------------------------------------ warnings */

typedef struct warn_list {
    char (*msgs)[160];
    int n, max;
} warn_list;

static void warn(warn_list *w, const char *fmt, const char *a, const char *b)
{
    if (w->n < w->max) snprintf(w->msgs[w->n++], 160, fmt, a, b);
}

static const char *method_name(q2n_surface_method m)
{
    return m == Q2N_SURFACE_ACC3 ? "acc3" : m == Q2N_SURFACE_ACC_G1 ? "acc-g1" : "augmented";
}

/* The continuity the fit will impose (0: an exact conversion, none). */
static int fit_continuity(const q2n_model_options *mo, const q2n_fit_options *fo)
{
    if (mo->method != Q2N_SURFACE_AUGMENTED) return 0;
    if (fo->continuity) return fo->continuity;
    const q2n_spline_class *cls = mo->cls ? mo->cls : q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT);
    return cls && cls->k >= 2 && mo->ev_patch != Q2N_EV_PATCH_G1 ? 2 : 1;
}

int q2n_options_warnings(const q2n_model_options *mo, const q2n_fit_options *fo, unsigned set, const q2n_plan *plan,
                         char (*msgs)[160], int max)
{
    warn_list w = {msgs, 0, max};
    const char *meth = method_name(mo->method);
    static const struct { unsigned bit; const char *opt; } AUG[] = {
        {Q2N_GIVEN_CLASS, "--class"}, {Q2N_GIVEN_PARAM, "--param"}, {Q2N_GIVEN_ALPHA, "--alpha"}, {Q2N_GIVEN_EV_PATCH, "--ev-patch"}};
    if (mo->method != Q2N_SURFACE_AUGMENTED)
        for (size_t i = 0; i < sizeof AUG / sizeof AUG[0]; i++)
            if (set & AUG[i].bit)
                warn(&w, "%s is ignored with --surface %s (it shapes the augmented surface only)", AUG[i].opt, meth);
    if (mo->keep_flat && (mo->method != Q2N_SURFACE_AUGMENTED || mo->ev_method == Q2N_EV_METHOD_PAPER))
        warn(&w, "--keep-flat is ignored with %s%s (it conditions the fair construction only)",
             mo->method != Q2N_SURFACE_AUGMENTED ? "--surface " : "--ev-construction paper",
             mo->method != Q2N_SURFACE_AUGMENTED ? meth : "");
    if (mo->smooth_gluing && (mo->method != Q2N_SURFACE_AUGMENTED || mo->ev_method == Q2N_EV_METHOD_PAPER))
        warn(&w, "--ev-gluing is ignored with %s%s (the gluing is the fair construction's)",
             mo->method != Q2N_SURFACE_AUGMENTED ? "--surface " : "--ev-construction paper",
             mo->method != Q2N_SURFACE_AUGMENTED ? meth : "");
    if (mo->limit_points && mo->method != Q2N_SURFACE_AUGMENTED)
        warn(&w, "%s is ignored with --surface %s (its patches approximate the Catmull-Clark limit from the control "
                 "mesh itself)", mo->limit_points > 0 ? "--limit-points" : "--no-limit-points", meth);
    if ((set & Q2N_GIVEN_ACC_STRATEGY) && mo->method != Q2N_SURFACE_ACC_G1)
        warn(&w, "--acc-strategy is ignored with --surface %s (it chooses the masks of acc-g1 only)%s", meth, "");
    if ((set & Q2N_GIVEN_ALPHA) && mo->method == Q2N_SURFACE_AUGMENTED &&
        (mo->param.method == Q2N_PARAM_UNIFORM || mo->param.method == Q2N_PARAM_CHORDAL))
        warn(&w, "--alpha is ignored with --param %s (only centripetal and mean use an exponent)%s",
             mo->param.method == Q2N_PARAM_UNIFORM ? "uniform" : "chordal", "");
    if (!plan->fit) {
        char list[160] = "";
        static const struct { unsigned bit; const char *opt; } FIT[] = {
            {Q2N_GIVEN_TOL, "--tol/--tol-abs"}, {Q2N_GIVEN_ANGLE_TOL, "--angle-tol"}, {Q2N_GIVEN_CURVATURE_TOL, "--curvature-tol"},
            {Q2N_GIVEN_CONTINUITY, "--continuity"}, {Q2N_GIVEN_SOLVER, "--solver"}, {Q2N_GIVEN_UNITS, "--units"}};
        for (size_t i = 0; i < sizeof FIT / sizeof FIT[0]; i++)
            if (set & FIT[i].bit)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", list[0] ? ", " : "", FIT[i].opt);
        if (list[0]) warn(&w, "%s: ignored, no output needs the fit (only .step, .igs and .json do)%s", list, "");
    } else if (mo->method != Q2N_SURFACE_AUGMENTED) {
        if (set & Q2N_GIVEN_CONTINUITY)
            warn(&w, "--continuity is ignored with --surface %s (its patches are converted exactly)%s", meth, "");
        if (set & Q2N_GIVEN_SOLVER)
            warn(&w, "--solver is ignored with --surface %s (its patches are converted exactly, nothing is solved)%s",
                 meth, "");
        if (set & (Q2N_GIVEN_ANGLE_TOL | Q2N_GIVEN_CURVATURE_TOL))
            warn(&w, "--angle-tol/--curvature-tol are ignored with --surface %s (exact conversion: the continuity is "
                     "the construction's)%s", meth, "");
    } else if ((set & Q2N_GIVEN_CURVATURE_TOL) && fit_continuity(mo, fo) == 1) {
        warn(&w, "--curvature-tol is ignored: the fit imposes G1 only (%s)%s",
             fo->continuity == 1 ? "--continuity g1" : "a G1 construction", "");
    }
    if ((set & Q2N_GIVEN_TESS) && !plan->obj) warn(&w, "--tess is ignored: no .obj output%s%s", "", "");
    if ((set & Q2N_GIVEN_GRID) && !plan->sample) warn(&w, "--grid is ignored: it applies to `quad2nurbs sample`%s%s", "", "");
    if ((set & Q2N_GIVEN_THREADS) && fo->threads > Q2N_FIT_MAX_THREADS) {
        char a[16], b[16];
        snprintf(a, sizeof a, "%d", fo->threads);
        snprintf(b, sizeof b, "%d", Q2N_FIT_MAX_THREADS);
        warn(&w, "--threads %s: at most %s threads are used", a, b);
    }
    return w.n;
}

/* ------------------------------------------------------------------ tolerance, date */

q2n_status q2n_model_resolve_tol(const q2n_model *m, q2n_fit_options *fo, q2n_error *err)
{
    if (!(fo->tol_abs > 0)) return Q2N_OK;
    double diag = q2n_mesh_bbox_diag(m->mesh) * q2n_model_length_scale(m), rel = diag > 0 ? fo->tol_abs / diag : INFINITY;
    if (!(rel >= Q2N_TOL_MIN && rel <= Q2N_TOL_MAX))
        return q2n_error_set(err, Q2N_ERR_ARG,
                             "--tol-abs %g is %.3g times the bounding-box diagonal (%.6g model units); it must lie "
                             "between %g and %g times it", fo->tol_abs, rel, diag, Q2N_TOL_MIN, Q2N_TOL_MAX);
    fo->tol = rel;
    fo->tol_abs = 0;
    return Q2N_OK;
}

q2n_status q2n_export_date_from_env(q2n_export_options *x, q2n_error *err)
{
    const char *s = getenv("SOURCE_DATE_EPOCH");
    if (!s) {
        x->has_date = 1;
        x->date = (long long)time(NULL);
        return Q2N_OK;
    }
    /* reproducible-builds.org/specs/source-date-epoch: a decimal count of seconds since 1970;
     * anything else must be an error, not a silent fallback to now */
    char *end;
    errno = 0;
    long long t = strtoll(s, &end, 10);
    if (!*s || *end || errno || t < 0 || t > 253402300799LL)
        return q2n_error_set(err, Q2N_ERR_ARG, "SOURCE_DATE_EPOCH='%s' is not a number of seconds since 1970 "
                             "(up to 9999-12-31)", s);
    x->has_date = 1;
    x->date = t;
    return Q2N_OK;
}

/* ------------------------------------------------------------------ resources */

double q2n_default_max_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    double phys = pages > 0 && size > 0 ? (double)pages * (double)size : 4e9;
    /* a container's limit (cgroup v2) is the memory there is */
    FILE *f = fopen("/sys/fs/cgroup/memory.max", "r");
    double lim;
    if (f) {
        if (fscanf(f, "%lf", &lim) == 1 && lim > 0 && lim < phys) phys = lim;
        fclose(f);
    }
    return Q2N_MEM_DEFAULT_FRACTION * phys;
}

/* Faces after the planned Catmull–Clark steps: the first step makes one quad per corner, each
 * later one four per quad.  The ACC path subdivides non-quad meshes once by itself. */
static int planned_steps(const q2n_model *m)
{
    int s = m->opt.subdivide;
    if (s == 0 && !m->mesh->all_quads && m->opt.method != Q2N_SURFACE_AUGMENTED) s = 1;
    return s;
}

static long long planned_faces(const q2n_model *m)
{
    const q2n_mesh *me = m->mesh;
    int s = planned_steps(m);
    if (s == 0) return me->nf;
    double f = (double)me->nh;
    for (int i = 1; i < s; i++) f *= 4;
    return f > 9e18 ? (long long)9e18 : (long long)f;
}

/* Faces the extraordinary-vertex construction will build, from the mesh before subdivision:
 * those whose grid of faces (the face and Q2N_MEM_EV_RINGS rings around it: the default class's
 * support) reaches an extraordinary vertex — valence other than 4, other than 2 or 3 on the
 * boundary — or, when the mesh is subdivided, the face point of a non-quad face.  One subdivision
 * step makes those rings fine ones: the faces touching such a vertex bring all their children;
 * further steps narrow the regions to Q2N_MEM_EV_REGION_PER_VALENCE fine faces per unit of valence.
 * Zero for the ACC surfaces, which have no such solve. */
static int face_marked(const q2n_mesh *me, int f, const unsigned char *mk)
{
    int hit = 0;
    for (int k = me->face_start[f]; k < me->face_start[f + 1]; k++) hit |= mk[me->face_vert[k]];
    return hit;
}

static double planned_ev_faces(const q2n_model *m, int steps, double faces)
{
    const q2n_mesh *me = m->mesh;
    if (m->opt.method != Q2N_SURFACE_AUGMENTED) return 0;
    int *fc = calloc((size_t)me->nv + 1, sizeof *fc);
    unsigned char *mk = calloc((size_t)me->nv + 1, 1), *nx = calloc((size_t)me->nv + 1, 1);
    double fine = 0, around = 0;
    if (!fc || !mk || !nx) { free(fc); free(mk); free(nx); return faces; }
    for (int k = 0; k < me->nh; k++) fc[me->face_vert[k]]++;
    for (int v = 0; v < me->nv; v++) {
        int b = me->vert_boundary[v], val = fc[v] + b;
        if (fc[v] > 0 && (b ? val != 2 && val != 3 : val != 4)) mk[v] = 1, around += Q2N_MEM_EV_REGION_PER_VALENCE * val;
    }
    for (int f = 0; steps > 0 && f < me->nf; f++) {
        int n = me->face_start[f + 1] - me->face_start[f];
        if (n == 4) continue;
        around += Q2N_MEM_EV_REGION_PER_VALENCE * n;
        for (int k = me->face_start[f]; k < me->face_start[f + 1]; k++) mk[me->face_vert[k]] = 1;
    }
    for (int r = 0; steps == 0 && r < Q2N_MEM_EV_RINGS; r++) { /* one ring of faces around the marked vertices */
        memcpy(nx, mk, (size_t)me->nv);
        for (int f = 0; f < me->nf; f++)
            if (face_marked(me, f, mk))
                for (int k = me->face_start[f]; k < me->face_start[f + 1]; k++) nx[me->face_vert[k]] = 1;
        memcpy(mk, nx, (size_t)me->nv);
    }
    for (int f = 0; f < me->nf; f++)
        if (face_marked(me, f, mk)) fine += steps == 0 ? 1 : (me->face_start[f + 1] - me->face_start[f]) * pow(4, steps - 1);
    free(fc);
    free(mk);
    free(nx);
    if (steps >= 2 && around < fine) fine = around;
    return fine < faces ? fine : faces;
}

static int digits(double x)
{
    int d = 1;
    while (x >= 10 && d < 40) { x /= 10; d++; }
    return d;
}

void q2n_model_estimate(const q2n_model *m, const q2n_plan *plan, q2n_estimate *e)
{
    memset(e, 0, sizeof *e);
    long long nf = planned_faces(m);
    double faces = (double)nf, ev = planned_ev_faces(m, planned_steps(m), faces);
    double build = Q2N_MEM_BASE + faces * Q2N_MEM_BUILD_PER_FACE + ev * Q2N_MEM_BUILD_PER_EV_FACE, peak;
    if (m->opt.method == Q2N_SURFACE_AUGMENTED && m->opt.frame >= 0 && ev > 0) { /* the isotropic frame's second build */
        double A[3][3], Ai[3][3];
        if (q2n_mesh_isotropic_frame(m->mesh, A, Ai) >= Q2N_MODEL_FRAME_MIN_STRETCH)
            build += faces * Q2N_MEM_FRAME_PER_FACE + ev * Q2N_MEM_FRAME_PER_EV_FACE;
    }
    peak = build;
    e->faces = nf;
    e->peak_stage = "build";
    double cache = faces * Q2N_MEM_FIT_CACHE_PER_FACE;
    if (cache > Q2N_FIT_CACHE_BYTES) cache = Q2N_FIT_CACHE_BYTES;
    double fit = faces * Q2N_MEM_FIT_PER_FACE + ev * Q2N_MEM_FIT_PER_EV_FACE + cache;
    if (plan->fit && build + fit > peak) {
        peak = build + fit;
        e->peak_stage = "fit";
    }
    /* per-patch evaluation buffers (9 doubles per point) of the tessellation and of `sample` */
    double tess = plan->obj ? 72.0 * plan->tess * plan->tess : 0, grid = plan->sample ? 72.0 * plan->grid * plan->grid : 0;
    if (build + tess > peak) { peak = build + tess; e->peak_stage = "tessellation"; }
    if (build + grid > peak) { peak = build + grid; e->peak_stage = "sample"; }
    for (int i = 0; i < plan->nout && i < 16; i++) {
        q2n_format f = plan->out[i].format;
        double n = plan->tess, pts = faces * n * n;
        if (f == Q2N_FORMAT_OBJ) /* "v x y z" + "vn ..." per point, "f a//a b//b c//c d//d" per quad */
            e->output[i] = pts * 125.0 + faces * (n - 1) * (n - 1) * (8.0 * digits(pts) + 14.0) + faces * 16.0;
        else if (f == Q2N_FORMAT_STEP) e->output[i] = faces * Q2N_OUT_STEP_PER_FACE;
        else if (f == Q2N_FORMAT_IGES) e->output[i] = faces * Q2N_OUT_IGES_PER_FACE;
        else if (f == Q2N_FORMAT_JSON) e->output[i] = Q2N_OUT_JSON;
    }
    e->memory = peak;
}

/* 1.2 GB, 35 MB, ... */
static void human(double b, char *out, size_t n)
{
    static const char *const u[] = {"B", "kB", "MB", "GB", "TB", "PB"};
    int i = 0;
    while (b >= 1000 && i < 5) { b /= 1000; i++; }
    snprintf(out, n, i ? "%.3g %s" : "%.0f %s", b, u[i]);
}

q2n_status q2n_model_check_resources(const q2n_model *m, const q2n_plan *plan, double max_memory, q2n_error *err)
{
    q2n_estimate e;
    q2n_model_estimate(m, plan, &e);
    int dflt = max_memory == 0;
    if (dflt) max_memory = q2n_default_max_memory();
    char a[32], b[32];
    if (max_memory > 0 && e.memory > max_memory) {
        human(e.memory, a, sizeof a);
        human(max_memory, b, sizeof b);
        char faces[96] = "";
        if (m->opt.subdivide > 0) snprintf(faces, sizeof faces, " after --subdivide %d", m->opt.subdivide);
        return q2n_error_set(err, Q2N_ERR_ARG,
                             "%s: the run would need about %s of memory (estimated: %lld faces%s; peak in the %s stage), more than "
                             "the limit %s (--max-memory%s)", m->mesh->name, a, e.faces, faces, e.peak_stage, b,
                             dflt ? ", default: half the physical memory" : "");
    }
    for (int i = 0; i < plan->nout && i < 16; i++) {
        const q2n_output *o = &plan->out[i];
        struct statvfs vf;
        if (o->file.stream || !o->file.tmp || statvfs(o->file.tmp, &vf) != 0) continue;
        double avail = (double)vf.f_bavail * (double)vf.f_frsize;
        if (e.output[i] > avail) {
            human(e.output[i], a, sizeof a);
            human(avail, b, sizeof b);
            return q2n_error_set(err, Q2N_ERR_IO, "%s: the output would take about %s, only %s are free on its file system",
                                 o->path, a, b);
        }
    }
    return Q2N_OK;
}
