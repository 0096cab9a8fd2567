/* api.c — the public API of include/quad2nurbs.h on top of the pipeline object (model.h): the
 * public options checked and turned into the stages' options, status codes with their messages
 * copied into the caller's buffer. */
#include "quad2nurbs.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api/model.h"
#include "api/policy.h"
#include "core/blas.h"
#include "core/par.h"
#include "patch/extraordinary.h"

static q2n_status fail(q2n_status st, const q2n_error *e, char *buf, size_t len)
{
    if (buf && len) snprintf(buf, len, "%s", e->message);
    return st;
}

/* Q2N_ERR_ARG with a printf-style message into the caller's buffer (escaped as every message). */
static q2n_status bad(char *buf, size_t len, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static q2n_status bad(char *buf, size_t len, const char *fmt, ...)
{
    char raw[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    if (buf && len) q2n_escape(buf, len, raw);
    return Q2N_ERR_ARG;
}

/* An enum field of the options: in range, else Q2N_ERR_ARG naming it. */
static int bad_choice(q2n_choice what, int value, const char *field, char *buf, size_t len)
{
    if (q2n_choice_name(what, value)) return 0;
    bad(buf, len, "invalid %s %d (expected one of %s)", field, value, q2n_choice_list(what));
    return 1;
}

/* Every option in range: 0, or Q2N_ERR_ARG with the message. */
static q2n_status check_options(const q2n_options *o, char *errbuf, size_t errlen)
{
    if (bad_choice(Q2N_CHOICE_SURFACE, (int)o->surface, "surface", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_CLASS, (int)o->spline_class, "spline class", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_PARAM, (int)o->param, "parametrization", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_EV_PATCH, (int)o->ev_patch, "ev_patch", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_EV_CONSTRUCTION, (int)o->ev_construction, "ev_construction", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_ACC_STRATEGY, (int)o->acc_strategy, "acc_strategy", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_UNITS, (int)o->units, "units", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_FORMAT, (int)o->format, "format", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_CONTINUITY, (int)o->continuity, "continuity", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_SOLVER, (int)o->solver, "solver", errbuf, errlen) ||
        bad_choice(Q2N_CHOICE_GLUING, (int)o->gluing, "gluing", errbuf, errlen))
        return Q2N_ERR_ARG;
    if (!(o->alpha >= 0 && o->alpha <= 2))
        return bad(errbuf, errlen, "invalid alpha %g (expected (0, 2], 0 for the default)", o->alpha);
    if (o->subdivide < 0 || o->subdivide > 6)
        return bad(errbuf, errlen, "invalid subdivide %d (expected 0 .. 6)", o->subdivide);
    if (o->pair_triangles < 0 || o->pair_triangles > 1)
        return bad(errbuf, errlen, "invalid pair_triangles %d (expected 0 or 1)", o->pair_triangles);
    if (o->fill_ngons < 0 || o->fill_ngons > 1)
        return bad(errbuf, errlen, "invalid fill_ngons %d (expected 0 or 1)", o->fill_ngons);
    if (o->keep_flat < 0 || o->keep_flat > 1) return bad(errbuf, errlen, "invalid keep_flat %d (expected 0 or 1)", o->keep_flat);
    if (o->frame < -1 || o->frame > 0) return bad(errbuf, errlen, "invalid frame %d (expected 0 auto or -1 off)", o->frame);
    if (o->ev_smooth_gluing < Q2N_EV_GLUING_AUTO || o->ev_smooth_gluing > Q2N_EV_GLUING_POLYNOMIAL)
        return bad(errbuf, errlen, "invalid ev_smooth_gluing %d (expected 0, 1 or 2: a q2n_ev_gluing)", o->ev_smooth_gluing);
    if (o->limit_points < -1 || o->limit_points > 1)
        return bad(errbuf, errlen, "invalid limit_points %d (expected -1, 0 or 1)", o->limit_points);
    if (o->scale != 0 && !(o->scale >= Q2N_SCALE_MIN && o->scale <= Q2N_SCALE_MAX))
        return bad(errbuf, errlen, "invalid scale %g (expected %g .. %g)", o->scale, Q2N_SCALE_MIN, Q2N_SCALE_MAX);
    if (o->tol != 0 && !(o->tol >= Q2N_TOL_MIN && o->tol <= Q2N_TOL_MAX))
        return bad(errbuf, errlen, "invalid tol %g (expected %g .. %g)", o->tol, Q2N_TOL_MIN, Q2N_TOL_MAX);
    if (!(o->tol_abs >= 0 && o->tol_abs < INFINITY))
        return bad(errbuf, errlen, "invalid tol_abs %g (expected a length > 0, 0 for none)", o->tol_abs);
    if (o->tol > 0 && o->tol_abs > 0) return bad(errbuf, errlen, "tol and tol_abs are alternatives: give one");
    if (!(o->angle_tol_deg >= 0 && o->angle_tol_deg <= 90))
        return bad(errbuf, errlen, "invalid angle_tol_deg %g (expected an angle in (0, 90] degrees)", o->angle_tol_deg);
    if (!(o->curvature_tol >= 0 && o->curvature_tol <= 10))
        return bad(errbuf, errlen, "invalid curvature_tol %g (expected a ratio in (0, 10])", o->curvature_tol);
    if (o->max_spans < 0 || o->max_spans > 1024)
        return bad(errbuf, errlen, "invalid max_spans %d (expected 1 .. 1024)", o->max_spans);
    if (o->threads < 0 || o->threads > 4096) return bad(errbuf, errlen, "invalid threads %d (expected 1 .. 4096)", o->threads);
    if (o->tess < 0 || o->tess == 1 || o->tess > 10000)
        return bad(errbuf, errlen, "invalid tess %d (expected 2 .. 10000)", o->tess);
    if (isnan(o->max_memory)) return bad(errbuf, errlen, "invalid max_memory (NaN)");
    return Q2N_OK;
}

/* Model options from the public ones (checked). */
static void model_options(const q2n_options *o, q2n_model_options *mo)
{
    memset(mo, 0, sizeof *mo);
    mo->method = o->surface;
    mo->cls = o->spline_class ? q2n_spline_class_find(q2n_choice_name(Q2N_CHOICE_CLASS, (int)o->spline_class)) : NULL;
    mo->param.method = o->param;
    mo->param.alpha = o->alpha > 0 ? o->alpha : NAN;
    mo->ev_patch = (int)o->ev_patch;
    mo->ev_method = (int)o->ev_construction;
    mo->keep_flat = o->keep_flat;
    mo->frame = o->frame;
    mo->smooth_gluing = o->ev_smooth_gluing;
    mo->fold_fallback = o->ev_patch == Q2N_EV_PATCH_DEFAULT && o->continuity != Q2N_CONTINUITY_G2;
    mo->acc_strategy = o->acc_strategy;
    mo->subdivide = o->subdivide;
    mo->limit_points = o->limit_points;
    mo->pair_triangles = o->pair_triangles;
    mo->fill_ngons = o->fill_ngons;
    mo->threads = o->threads;
    mo->scale = o->scale;
    mo->progress.fn = o->progress;
    mo->progress.user = o->progress_user;
    mo->progress.t0 = q2n_now();
}

/* Fit and export settings kept in the model for q2n_fit and the writers. */
static q2n_status write_options(const q2n_options *o, q2n_model *m, char *errbuf, size_t errlen)
{
    q2n_fit_options_default(&m->fit_opt);
    m->fit_opt.continuity = (int)o->continuity;
    if (o->tol > 0) m->fit_opt.tol = o->tol;
    if (o->threads > 0) m->fit_opt.threads = o->threads;
    if (o->angle_tol_deg > 0) m->fit_opt.g1_tol_deg = o->angle_tol_deg;
    if (o->curvature_tol > 0) m->fit_opt.g2_tol_rel = o->curvature_tol;
    if (o->max_spans > 0) m->fit_opt.max_spans = o->max_spans;
    m->fit_opt.no_exact = o->gluing == Q2N_GLUING_LEAST_SQUARES;
    m->fit_opt.solver = o->solver == Q2N_SOLVER_DIRECT ? Q2N_FIT_SOLVER_DIRECT : Q2N_FIT_SOLVER_CERES;
    m->fit_opt.tol_abs = o->tol_abs > 0 ? o->tol_abs : 0;
    memset(&m->export_opt, 0, sizeof m->export_opt);
    m->export_opt.units = o->units;
    q2n_error e;
    if (q2n_export_date_from_env(&m->export_opt, &e)) return fail(Q2N_ERR_ARG, &e, errbuf, errlen);
    m->tess = o->tess > 0 ? o->tess : 9;
    m->format = (int)o->format;
    m->max_memory = o->max_memory;
    m->given = o->given;
    return Q2N_OK;
}

/* The mesh read or taken and moved into its frame, the options kept: no construction yet. */
static q2n_status open_model(const char *path, q2n_mesh *mesh, const q2n_options *o, q2n_model **out, char *errbuf,
                             size_t errlen)
{
    q2n_options d;
    memset(&d, 0, sizeof d);
    if (!o) o = &d;
    q2n_status st = check_options(o, errbuf, errlen);
    if (st) { q2n_mesh_free(mesh); return st; }
    q2n_model_options mo;
    model_options(o, &mo);
    q2n_error e;
    q2n_model *m = NULL;
    st = path ? q2n_model_read(path, &mo, &m, &e) : q2n_model_take_mesh(mesh, &mo, &m, &e);
    if (st) return fail(st, &e, errbuf, errlen);
    if ((st = write_options(o, m, errbuf, errlen))) { q2n_model_free(m); return st; }
    if ((m->opt.threads > 1 || m->fit_opt.threads > 1) && q2n_blas_thread_unsafe()) {
        m->opt.threads = m->fit_opt.threads = 1;
        q2n_model_warn(m, "the system BLAS is OpenBLAS' serial build, which is not safe for calls from several threads "
                          "at once: the construction and the fit run on 1 thread (select another BLAS with "
                          "update-alternatives --config libblas.so.3-x86_64-linux-gnu)");
    }
    *out = m;
    return Q2N_OK;
}

/* The construction after the resource check, then the absolute tolerance resolved. */
static q2n_status build(q2n_model *m, char *errbuf, size_t errlen)
{
    q2n_error e;
    q2n_plan plan = {0};
    q2n_status st;
    if ((st = q2n_model_check_resources(m, &plan, m->max_memory, &e)) || (st = q2n_model_construct(m, &e)) ||
        (st = q2n_model_resolve_tol(m, &m->fit_opt, &e)))
        return fail(st, &e, errbuf, errlen);
    return Q2N_OK;
}

q2n_status q2n_read(const char *mesh_path, const q2n_options *o, q2n_model **out, char *errbuf, size_t errlen)
{
    if (!out) return bad(errbuf, errlen, "q2n_read: no output pointer");
    *out = NULL;
    if (!mesh_path) return bad(errbuf, errlen, "q2n_read: no mesh path");
    return open_model(mesh_path, NULL, o, out, errbuf, errlen);
}

/* Name of an array mesh in messages. */
#define ARRAY_MESH "mesh"

q2n_status q2n_read_mesh(size_t nv, const double *positions, size_t nf, const int *face_sizes, const int *face_verts,
                         const q2n_options *o, q2n_model **out, char *errbuf, size_t errlen)
{
    if (!out) return bad(errbuf, errlen, "q2n_read_mesh: no output pointer");
    *out = NULL;
    if (nv > INT_MAX / 3 || nf > INT_MAX - 1)
        return bad(errbuf, errlen, ARRAY_MESH ": %zu vertices and %zu faces: too many (at most %d)", nv, nf, INT_MAX / 3);
    if ((nv && !positions) || (nf && !face_verts)) return bad(errbuf, errlen, ARRAY_MESH ": no positions or face_verts");
    if (nf == 0) {
        if (errbuf && errlen) snprintf(errbuf, errlen, ARRAY_MESH ": empty mesh (no faces)");
        return Q2N_ERR_TOPOLOGY;
    }
    int *start = malloc((nf + 1) * sizeof *start);
    if (!start) {
        if (errbuf && errlen) snprintf(errbuf, errlen, ARRAY_MESH ": out of memory");
        return Q2N_ERR_NOMEM;
    }
    start[0] = 0;
    for (size_t k = 0; k < nf; k++) {
        int n = face_sizes ? face_sizes[k] : 4;
        if (n < 3) {
            free(start);
            if (errbuf && errlen) snprintf(errbuf, errlen, ARRAY_MESH ": face %zu has %d vertices (< 3)", k, n);
            return Q2N_ERR_TOPOLOGY;
        }
        if (start[k] > INT_MAX - n) {
            free(start);
            return bad(errbuf, errlen, ARRAY_MESH ": more than %d face corners", INT_MAX);
        }
        start[k + 1] = start[k] + n;
    }
    q2n_error e;
    q2n_mesh *mesh = NULL;
    q2n_status st = q2n_mesh_from_arrays((int)nv, positions, (int)nf, start, face_verts, ARRAY_MESH, &mesh, &e);
    free(start);
    if (st) return fail(st, &e, errbuf, errlen);
    return open_model(NULL, mesh, o, out, errbuf, errlen);
}

q2n_status q2n_build(q2n_model *m, char *errbuf, size_t errlen)
{
    if (!m || m->surface) return bad(errbuf, errlen, "q2n_build: %s", m ? "the model is built already" : "no model");
    return build(m, errbuf, errlen);
}

q2n_status q2n_open(const char *mesh_path, const q2n_options *o, q2n_model **out, char *errbuf, size_t errlen)
{
    q2n_status st = q2n_read(mesh_path, o, out, errbuf, errlen);
    if (!st && (st = build(*out, errbuf, errlen))) {
        q2n_model_free(*out);
        *out = NULL;
    }
    return st;
}

q2n_status q2n_open_mesh(size_t nv, const double *positions, size_t nf, const int *face_sizes, const int *face_verts,
                         const q2n_options *o, q2n_model **out, char *errbuf, size_t errlen)
{
    q2n_status st = q2n_read_mesh(nv, positions, nf, face_sizes, face_verts, o, out, errbuf, errlen);
    if (!st && (st = build(*out, errbuf, errlen))) {
        q2n_model_free(*out);
        *out = NULL;
    }
    return st;
}

int q2n_patch_count(const q2n_model *m) { return m ? m->mesh->nf : 0; }

int q2n_patch_covered(const q2n_model *m, int k)
{
    return m && m->surface && k >= 0 && k < m->mesh->nf && q2n_surface_kind(m->surface, k) != Q2N_PATCH_UNCOVERED;
}

q2n_status q2n_patch_eval(const q2n_model *m, int k, double u, double v, double out[9])
{
    if (!m || !m->surface) return Q2N_ERR_ARG;
    return q2n_model_eval(m, k, u, v, out, NULL);
}

struct q2n_outputs;
static void make_plan(const q2n_model *m, const struct q2n_outputs *o, int sample_grid, q2n_plan *plan);

/* Fit when an output needs it and the model has no fit yet; a failed fit leaves none. */
static q2n_status fit_model(q2n_model *m, q2n_error *e)
{
    q2n_status st = q2n_model_fit(m, &m->fit_opt, e);
    if (st) {
        q2n_nurbs_model_free(m->nurbs);
        m->nurbs = NULL;
    }
    return st;
}

q2n_status q2n_write_all(q2n_model *m, const char *const *paths, int n, char *errbuf, size_t errlen)
{
    if (!m || !m->surface) return bad(errbuf, errlen, "q2n_write_all: no model built");
    q2n_outputs *o = NULL;
    q2n_status st = q2n_outputs_open(paths, n, (q2n_format)m->format, m->mesh->name, &o, errbuf, errlen);
    if (st) return st;
    q2n_plan plan;
    make_plan(m, o, 0, &plan);
    plan.fit &= !m->nurbs;
    q2n_error e;
    if ((st = q2n_model_check_resources(m, &plan, m->max_memory, &e))) fail(st, &e, errbuf, errlen);
    if (!st) st = q2n_outputs_write(m, o, errbuf, errlen);
    if (!st) return q2n_outputs_commit(o, errbuf, errlen);
    q2n_outputs_abort(o);
    return st;
}

q2n_status q2n_write(q2n_model *m, const char *path, char *errbuf, size_t errlen)
{
    return q2n_write_all(m, &path, 1, errbuf, errlen);
}

q2n_status q2n_fit(q2n_model *m, char *errbuf, size_t errlen)
{
    if (!m || !m->surface) return bad(errbuf, errlen, "q2n_fit: no model built");
    if (m->nurbs) return Q2N_OK;
    q2n_error e;
    q2n_status st = fit_model(m, &e);
    return st ? fail(st, &e, errbuf, errlen) : Q2N_OK;
}

q2n_status q2n_patch_spline_get(const q2n_model *m, int k, q2n_patch_spline *out)
{
    if (!m || !m->nurbs || !out || k < 0 || k >= m->nurbs->n) return Q2N_ERR_ARG;
    const q2n_bspline_surface *p = &m->nurbs->patches[k];
    out->deg_u = p->deg_u;
    out->deg_v = p->deg_v;
    out->ncp_u = p->ncp_u;
    out->ncp_v = p->ncp_v;
    out->knots_u = p->knots_u;
    out->knots_v = p->knots_v;
    out->cp = p->cp;
    out->weights = p->weights;
    return Q2N_OK;
}

q2n_status q2n_get_report(const q2n_model *m, q2n_report *r)
{
    if (!m || !r) return Q2N_ERR_ARG;
    memset(r, 0, sizeof *r);
    r->input_faces = m->input_faces;
    r->faces = m->mesh->nf;
    r->paired_quads = m->paired;
    r->triangles_left = m->tri_left;
    r->filled_faces = m->filled;
    r->fill_quads = m->fill_quads;
    r->patches = m->surface ? m->mesh->nf - m->uncovered : 0;
    r->construction_continuity = m->continuity;
    r->diag = q2n_mesh_bbox_diag(m->mesh) * q2n_model_length_scale(m);
    r->t_read = m->t_read;
    r->t_build = m->t_build;
    r->t_fit = m->t_fit;
    r->t_write = m->t_write;
    r->units = m->export_opt.units;
    r->unit_mm = q2n_units_in_mm(m->export_opt.units);
    snprintf(r->construction_note, sizeof r->construction_note, "%s", m->note);
    if (!m->nurbs) return Q2N_OK;
    const q2n_fit_report *f = &m->fit;
    r->fitted = 1;
    r->exact = f->exact;
    r->continuity = f->continuity;
    r->tol = f->tol;
    r->tol_abs = f->tol_abs;
    r->g1_tol_deg = f->g1_tol_deg;
    r->g2_tol_rel = f->g2_tol_rel;
    r->max_dev_rel = f->max_dev_rel;
    r->max_dev = f->max_dev_rel * f->diag;
    r->rms_dev_rel = f->rms_dev_rel;
    r->vertex_dev_max_rel = f->vertex_dev_max_rel;
    r->g0_max_rel = f->g0_max_rel;
    r->g0_max = f->g0_max_rel * f->diag;
    r->g1_max_deg = f->g1_max_deg;
    r->g2_max_rel = f->g2_max_rel;
    r->dev_met = f->dev_met;
    r->g1_met = f->g1_met;
    r->g2_met = f->g2_met;
    r->tol_met = f->tol_met;
    snprintf(r->note, sizeof r->note, "%s", f->note);
    r->rounds = f->rounds;
    r->g1_exact_edges = f->g1_exact_edges;
    r->g1_rounding_edges = f->g1_rounding_edges;
    r->g1_ls_edges = f->g1_ls_edges;
    r->spans_min = f->spans_min;
    r->spans_median = f->spans_median;
    r->spans_max = f->spans_max;
    r->cp_min = f->cp_min;
    r->cp_median = f->cp_median;
    r->cp_max = f->cp_max;
    r->cp_total = f->cp_total;
    r->step_bytes = f->step_bytes;
    r->iges_bytes = f->iges_bytes;
    r->rim_vertices = f->rim_vertices;
    r->rim_max_deg = f->rim_max_deg;
    r->rim_curvature_jump_rel = f->rim_curv_rel;
    return Q2N_OK;
}

const char *q2n_warning(const q2n_model *m, int i)
{
    return m && i >= 0 && i < m->nwarnings ? m->warnings[i] : NULL;
}

q2n_status q2n_write_samples(const q2n_model *m, int n, FILE *f, char *errbuf, size_t errlen)
{
    if (!m || !m->surface || !f || n < 1) return bad(errbuf, errlen, "q2n_write_samples: no model built or no grid");
    q2n_error e;
    q2n_status st = q2n_model_write_samples(m, n, f, &e);
    return st ? fail(st, &e, errbuf, errlen) : Q2N_OK;
}

/* ------------------------------------------------------------------ outputs */

struct q2n_outputs {
    q2n_output_set s;
};

q2n_status q2n_outputs_open(const char *const *paths, int n, q2n_format fallback, const char *input, q2n_outputs **out,
                            char *errbuf, size_t errlen)
{
    if (!out) return bad(errbuf, errlen, "q2n_outputs_open: no output pointer");
    *out = NULL;
    q2n_outputs *o = calloc(1, sizeof *o);
    if (!o) {
        if (errbuf && errlen) snprintf(errbuf, errlen, "out of memory");
        return Q2N_ERR_NOMEM;
    }
    q2n_error e;
    q2n_status st = q2n_outputs_open_set(&o->s, n, paths, fallback, input, &e);
    if (st) {
        free(o);
        return fail(st, &e, errbuf, errlen);
    }
    *out = o;
    return Q2N_OK;
}

int q2n_outputs_count(const q2n_outputs *o) { return o ? o->s.n : 0; }

q2n_format q2n_outputs_format(const q2n_outputs *o, int i)
{
    return o && i >= 0 && i < o->s.n ? o->s.out[i].format : Q2N_FORMAT_NONE;
}

const char *q2n_outputs_temp_path(const q2n_outputs *o, int i)
{
    return o && i >= 0 && i < o->s.n ? o->s.out[i].file.tmp : NULL;
}

/* The plan of a run: what the outputs need. */
static void make_plan(const q2n_model *m, const q2n_outputs *o, int sample_grid, q2n_plan *plan)
{
    memset(plan, 0, sizeof *plan);
    plan->sample = sample_grid > 0;
    plan->grid = sample_grid;
    plan->tess = m->tess;
    plan->continuity = m->fit_opt.continuity;
    plan->nout = o ? o->s.n : 0;
    plan->out = o ? o->s.out : NULL;
    for (int i = 0; i < plan->nout; i++) {
        plan->fit |= q2n_format_needs_fit(plan->out[i].format);
        plan->obj |= plan->out[i].format == Q2N_FORMAT_OBJ;
    }
}

q2n_status q2n_check_plan(q2n_model *m, const q2n_outputs *o, int sample_grid, char *errbuf, size_t errlen)
{
    if (!m) return bad(errbuf, errlen, "q2n_check_plan: no model");
    q2n_plan plan;
    make_plan(m, o, sample_grid, &plan);
    char w[16][160];
    int nw = q2n_options_warnings(&m->opt, &m->fit_opt, m->given, &plan, w, 16);
    for (int i = 0; i < nw; i++) q2n_model_warn(m, "%s", w[i]);
    q2n_error e;
    q2n_status st = q2n_model_check_resources(m, &plan, m->max_memory, &e);
    return st ? fail(st, &e, errbuf, errlen) : Q2N_OK;
}

q2n_status q2n_outputs_write(q2n_model *m, q2n_outputs *o, char *errbuf, size_t errlen)
{
    if (!m || !m->surface || !o) return bad(errbuf, errlen, "q2n_outputs_write: no model built or no outputs");
    q2n_plan plan;
    make_plan(m, o, 0, &plan);
    q2n_error e;
    q2n_status st = plan.fit && !m->nurbs ? fit_model(m, &e) : Q2N_OK;
    /* CAD files first, so that a report written after them gives their sizes */
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; !st && i < o->s.n; i++)
            if ((o->s.out[i].format == Q2N_FORMAT_JSON) == pass)
                st = q2n_model_write_output(m, &o->s.out[i], m->tess, &m->export_opt, &e);
    return st ? fail(st, &e, errbuf, errlen) : Q2N_OK;
}

q2n_status q2n_outputs_commit(q2n_outputs *o, char *errbuf, size_t errlen)
{
    if (!o) return bad(errbuf, errlen, "q2n_outputs_commit: no outputs");
    q2n_error e;
    q2n_status st = q2n_outputs_commit_set(&o->s, &e);
    free(o);
    return st ? fail(st, &e, errbuf, errlen) : Q2N_OK;
}

void q2n_outputs_abort(q2n_outputs *o)
{
    if (!o) return;
    q2n_outputs_abort_set(&o->s);
    free(o);
}

void q2n_close(q2n_model *m) { q2n_model_free(m); }

const char *q2n_version(void) { return QUAD2NURBS_VERSION; }

int q2n_default_threads(void) { return q2n_blas_thread_unsafe() ? 1 : q2n_par_cpus(); }
