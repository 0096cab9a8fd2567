/* api.c — the public API of include/quad2nurbs.h on top of the pipeline object (model.h). */
#include "quad2nurbs.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "api/model.h"
#include "api/policy.h"

static int fail(q2n_status st, const q2n_error *e, char *buf, size_t len)
{
    if (buf && len) snprintf(buf, len, "%s", e->message);
    return (int)st;
}

static int bad(const char *what, const char *value, char *buf, size_t len)
{
    if (buf && len) {
        char v[128];
        q2n_escape(v, sizeof v, value);
        snprintf(buf, len, "invalid %s '%s'", what, v);
    }
    return (int)Q2N_ERR_ARG;
}

static int bad_number(const char *what, double x, const char *range, char *buf, size_t len)
{
    if (buf && len) snprintf(buf, len, "invalid %s %g (expected %s)", what, x, range);
    return (int)Q2N_ERR_ARG;
}

/* Model options from the public ones; 0 or an error code with the message in errbuf. */
static int model_options(const q2n_options *o, q2n_model_options *mo, char *errbuf, size_t errlen)
{
    memset(mo, 0, sizeof *mo);
    mo->param.alpha = o->alpha > 0 ? o->alpha : NAN;
    mo->subdivide = o->subdivide;
    mo->threads = o->threads;
    mo->scale = o->scale;
    if (o->scale != 0 && !(o->scale >= 1e-12 && o->scale <= 1e12))
        return bad_number("scale", o->scale, "1e-12 .. 1e12", errbuf, errlen);
    if (o->surface && strcmp(o->surface, "augmented") != 0) {
        if (strcmp(o->surface, "acc3") == 0) mo->method = Q2N_SURFACE_ACC3;
        else if (strcmp(o->surface, "acc-g1") == 0) mo->method = Q2N_SURFACE_ACC_G1;
        else return bad("surface", o->surface, errbuf, errlen);
    }
    if (o->spline_class && !(mo->cls = q2n_spline_class_find(o->spline_class)))
        return bad("spline class", o->spline_class, errbuf, errlen);
    if (o->param && q2n_param_method_parse(o->param, &mo->param.method))
        return bad("parametrization", o->param, errbuf, errlen);
    q2n_error e;
    if (o->acc_strategy && q2n_acc_parse_strategy(o->acc_strategy, &mo->acc_strategy, &e))
        return fail(Q2N_ERR_ARG, &e, errbuf, errlen);
    mo->progress.fn = o->progress;
    mo->progress.user = o->progress_user;
    mo->progress.t0 = q2n_now();
    return 0;
}

/* Fit and export settings kept in the model for q2n_write. */
static int write_options(const q2n_options *o, q2n_model *m, char *errbuf, size_t errlen)
{
    q2n_units u = Q2N_UNITS_MM;
    if (o->units && q2n_units_parse(o->units, &u)) return bad("units", o->units, errbuf, errlen);
    if (o->tol != 0 && !(o->tol >= Q2N_TOL_MIN && o->tol <= Q2N_TOL_MAX))
        return bad_number("tol", o->tol, "1e-12 .. 0.1", errbuf, errlen);
    if (o->angle_tol_deg < 0 || o->angle_tol_deg > 90 || o->curvature_tol < 0 || !isfinite(o->curvature_tol))
        return bad_number("angle or curvature tolerance", o->angle_tol_deg < 0 || o->angle_tol_deg > 90
                          ? o->angle_tol_deg : o->curvature_tol, "an angle in (0, 90] degrees, a ratio > 0", errbuf, errlen);
    if (o->tess < 0 || o->tess == 1) return bad_number("tess", o->tess, ">= 2", errbuf, errlen);
    q2n_format fmt = Q2N_FORMAT_NONE;
    if (o->format && (fmt = q2n_format_parse(o->format)) == Q2N_FORMAT_NONE) return bad("format", o->format, errbuf, errlen);
    q2n_fit_options_default(&m->fit_opt);
    m->fit_opt.continuity = 0;
    if (o->tol > 0) m->fit_opt.tol = o->tol;
    if (o->threads > 0) m->fit_opt.threads = o->threads;
    if (o->angle_tol_deg > 0) m->fit_opt.g1_tol_deg = o->angle_tol_deg;
    if (o->curvature_tol > 0) m->fit_opt.g2_tol_rel = o->curvature_tol;
    m->fit_opt.tol_abs = o->tol_abs > 0 ? o->tol_abs : 0;
    memset(&m->export_opt, 0, sizeof m->export_opt);
    m->export_opt.units = u;
    q2n_error e;
    if (q2n_export_date_from_env(&m->export_opt, &e)) return fail(Q2N_ERR_ARG, &e, errbuf, errlen);
    m->tess = o->tess > 0 ? o->tess : 9;
    m->format = (int)fmt;
    m->max_memory = o->max_memory;
    return 0;
}

int q2n_open(const char *mesh_path, const q2n_options *o, q2n_model **out, char *errbuf, size_t errlen)
{
    q2n_options d;
    memset(&d, 0, sizeof d);
    if (!o) o = &d;
    *out = NULL;
    q2n_model_options mo;
    int rc = model_options(o, &mo, errbuf, errlen);
    if (rc) return rc;
    q2n_error e;
    q2n_model *m = NULL;
    q2n_status st = q2n_model_read(mesh_path, &mo, &m, &e);
    if (st) return fail(st, &e, errbuf, errlen);
    if ((rc = write_options(o, m, errbuf, errlen))) { q2n_model_free(m); return rc; }
    q2n_plan plan = {0};
    if ((st = q2n_model_check_resources(m, &plan, m->max_memory, &e)) || (st = q2n_model_construct(m, &e)) ||
        (st = q2n_model_resolve_tol(m, &m->fit_opt, &e))) {
        q2n_model_free(m);
        return fail(st, &e, errbuf, errlen);
    }
    *out = m;
    return 0;
}

int q2n_patch_count(const q2n_model *m) { return m->mesh->nf; }

int q2n_patch_covered(const q2n_model *m, int k)
{
    return q2n_surface_kind(m->surface, k) != Q2N_PATCH_UNCOVERED;
}

int q2n_patch_eval(const q2n_model *m, int k, double u, double v, double out[9])
{
    return (int)q2n_model_eval(m, k, u, v, out, NULL);
}

int q2n_write_all(q2n_model *m, const char *const *paths, int n, char *errbuf, size_t errlen)
{
    q2n_error e;
    q2n_output_set s;
    q2n_status st = q2n_outputs_open(&s, n, paths, (q2n_format)m->format, m->mesh->name, &e);
    if (st) return fail(st, &e, errbuf, errlen);
    q2n_plan plan = {0};
    plan.tess = m->tess;
    plan.nout = s.n;
    plan.out = s.out;
    for (int i = 0; i < s.n; i++) {
        plan.fit |= q2n_format_needs_fit(s.out[i].format) && !m->nurbs;
        plan.obj |= s.out[i].format == Q2N_FORMAT_OBJ;
    }
    st = q2n_model_check_resources(m, &plan, m->max_memory, &e);
    if (!st && plan.fit) st = q2n_model_fit(m, &m->fit_opt, &e);
    for (int i = 0; !st && i < s.n; i++) st = q2n_model_write_output(m, &s.out[i], m->tess, &m->export_opt, &e);
    if (!st) return q2n_outputs_commit(&s, &e) ? fail(e.code, &e, errbuf, errlen) : 0;
    q2n_outputs_abort(&s);
    return fail(st, &e, errbuf, errlen);
}

int q2n_write(q2n_model *m, const char *path, char *errbuf, size_t errlen)
{
    return q2n_write_all(m, &path, 1, errbuf, errlen);
}

void q2n_close(q2n_model *m) { q2n_model_free(m); }

const char *q2n_version(void) { return QUAD2NURBS_VERSION; }
