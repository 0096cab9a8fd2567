/* api.c — the public API of include/quad2nurbs.h on top of the pipeline object (model.h). */
#include "quad2nurbs.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "api/model.h"

static int fail(q2n_status st, const q2n_error *e, char *buf, size_t len)
{
    if (buf && len) snprintf(buf, len, "%s", e->message);
    return (int)st;
}

static int bad(const char *what, const char *value, char *buf, size_t len)
{
    if (buf && len) snprintf(buf, len, "invalid %s '%s'", what, value);
    return (int)Q2N_ERR_ARG;
}


int q2n_open(const char *obj_path, const q2n_options *o, q2n_model **out, char *errbuf, size_t errlen)
{
    q2n_options d;
    memset(&d, 0, sizeof d);
    if (!o) o = &d;
    q2n_model_options mo;
    memset(&mo, 0, sizeof mo);
    mo.param.alpha = o->alpha > 0 ? o->alpha : NAN;
    mo.subdivide = o->subdivide;
    if (o->surface && strcmp(o->surface, "augmented") != 0) {
        if (strcmp(o->surface, "acc3") == 0) mo.method = Q2N_SURFACE_ACC3;
        else if (strcmp(o->surface, "acc-g1") == 0) mo.method = Q2N_SURFACE_ACC_G1;
        else return bad("surface", o->surface, errbuf, errlen);
    }
    if (o->spline_class && !(mo.cls = q2n_spline_class_find(o->spline_class)))
        return bad("spline class", o->spline_class, errbuf, errlen);
    if (o->param && q2n_param_method_parse(o->param, &mo.param.method))
        return bad("parametrization", o->param, errbuf, errlen);
    q2n_error e;
    if (o->acc_strategy && q2n_acc_parse_strategy(o->acc_strategy, &mo.acc_strategy, &e))
        return fail(Q2N_ERR_ARG, &e, errbuf, errlen);
    if (o->units && strcmp(o->units, "mm") != 0 && strcmp(o->units, "in") != 0)
        return bad("units", o->units, errbuf, errlen);
    q2n_status st = q2n_model_build(obj_path, &mo, out, &e);
    if (st) return fail(st, &e, errbuf, errlen);
    /* fit and export settings, used by q2n_write */
    q2n_fit_options_default(&(*out)->fit_opt);
    (*out)->fit_opt.continuity = 0;
    if (o->tol > 0) (*out)->fit_opt.tol = o->tol;
    if (o->threads > 0) (*out)->fit_opt.threads = o->threads;
    (*out)->export_opt.units = (o->units && strcmp(o->units, "in") == 0) ? Q2N_UNITS_IN : Q2N_UNITS_MM;
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

int q2n_write(q2n_model *m, const char *path, char *errbuf, size_t errlen)
{
    q2n_error e;
    int needs_fit;
    if (!q2n_model_output_kind(path, &needs_fit)) return bad("output format of", path, errbuf, errlen);
    q2n_status st = Q2N_OK;
    if (needs_fit && !m->nurbs) st = q2n_model_fit(m, &m->fit_opt, &e);
    if (!st) st = q2n_model_write(m, path, 9, &m->export_opt, &e);
    return st ? fail(st, &e, errbuf, errlen) : 0;
}

void q2n_close(q2n_model *m) { q2n_model_free(m); }

const char *q2n_version(void) { return QUAD2NURBS_VERSION; }
