/* outputs.c — the outputs of a run as one transaction (model.h): formats, the checks on the
 * whole set, one temporary per output (core/outfile.h), and the commit that replaces files only
 * when every output was written and synced. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "api/model.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

static const struct { const char *ext, *name; q2n_format f; } FORMATS[] = {
    {".obj", "obj", Q2N_FORMAT_OBJ},   {".step", "step", Q2N_FORMAT_STEP}, {".stp", "stp", Q2N_FORMAT_STEP},
    {".igs", "igs", Q2N_FORMAT_IGES},  {".iges", "iges", Q2N_FORMAT_IGES}, {".json", "json", Q2N_FORMAT_JSON}};
#define NFORMATS (sizeof FORMATS / sizeof FORMATS[0])

q2n_format q2n_format_of_path(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL, *slash = path ? strrchr(path, '/') : NULL;
    if (!dot || (slash && dot < slash)) return Q2N_FORMAT_NONE;
    for (size_t i = 0; i < NFORMATS; i++)
        if (strcasecmp(dot, FORMATS[i].ext) == 0) return FORMATS[i].f;
    return Q2N_FORMAT_NONE;
}

q2n_format q2n_format_parse(const char *name)
{
    for (size_t i = 0; name && i < NFORMATS; i++)
        if (strcasecmp(name, FORMATS[i].name) == 0) return FORMATS[i].f;
    return Q2N_FORMAT_NONE;
}

const char *q2n_format_name(q2n_format f)
{
    static const char *const names[] = {"none", "obj", "step", "iges", "json"};
    return (unsigned)f < sizeof names / sizeof names[0] ? names[f] : "none";
}

/* ------------------------------------------------------------------ which file a name means */

/* The absolute name a path will have: realpath of an existing file, else of its directory plus
 * the last component; the path itself when even the directory does not exist. */
static char *canonical(const char *path)
{
    char *r = realpath(path, NULL);
    if (r) return r;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    char dir[PATH_MAX];
    if (slash) snprintf(dir, sizeof dir, "%.*s", (int)(slash == path ? 1 : slash - path), path);
    else snprintf(dir, sizeof dir, ".");
    char *d = realpath(dir, NULL);
    size_t n = (d ? strlen(d) : strlen(path)) + strlen(base) + 2;
    char *c = malloc(n);
    if (c && d) snprintf(c, n, "%s/%s", strcmp(d, "/") ? d : "", base);
    else if (c) snprintf(c, n, "%s", path);
    free(d);
    return c;
}

/* Do a and b name the same file (the same name, a link to it, or the same inode)? */
static int same_file(const char *a, const char *b)
{
    if (!strcmp(a, b)) return 1;
    if (!strcmp(a, "-") || !strcmp(b, "-")) return 0;
    struct stat sa, sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char *ca = canonical(a), *cb = canonical(b);
    int same = ca && cb && !strcmp(ca, cb);
    free(ca);
    free(cb);
    return same;
}

/* ------------------------------------------------------------------ the transaction */

void q2n_outputs_abort_set(q2n_output_set *s)
{
    for (int i = 0; s->out && i < s->n; i++) q2n_outfile_abort(&s->out[i].file);
    free(s->out);
    s->out = NULL;
    s->n = 0;
}

q2n_status q2n_outputs_open_set(q2n_output_set *s, int n, const char *const *paths, q2n_format fallback,
                            const char *input, q2n_error *err)
{
    memset(s, 0, sizeof *s);
    if (n <= 0) return Q2N_OK;
    /* the set first: nothing is created when it makes no sense */
    for (int i = 0; i < n; i++) {
        const char *p = paths[i];
        if (!p || !*p) return q2n_error_set(err, Q2N_ERR_ARG, "empty output name");
        if (q2n_format_of_path(p) == Q2N_FORMAT_NONE && fallback == Q2N_FORMAT_NONE) {
            const char *dot = strrchr(p, '.'), *slash = strrchr(p, '/');
            return q2n_error_set(err, Q2N_ERR_ARG, "%s: %s (known: .obj .step .stp .igs .iges .json; name the format "
                                 "with --format for standard output '-' or a device)", p,
                                 dot && (!slash || dot > slash) ? "unsupported output format" : "no format extension");
        }
        for (int j = 0; j < i; j++)
            if (same_file(p, paths[j]))
                return q2n_error_set(err, Q2N_ERR_ARG, "%s: given twice as an output%s", p,
                                     strcmp(p, paths[j]) ? " (the same file as the other name)" : "");
        if (input && same_file(p, input))
            return q2n_error_set(err, Q2N_ERR_ARG, "%s: is the input mesh; refusing to overwrite it", p);
    }
    s->out = calloc((size_t)n, sizeof *s->out);
    if (!s->out) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory");
    s->n = n;
    for (int i = 0; i < n; i++) {
        q2n_output *o = &s->out[i];
        o->path = paths[i];
        o->format = q2n_format_of_path(paths[i]);
        if (o->format == Q2N_FORMAT_NONE) o->format = fallback;
        q2n_status st = q2n_outfile_open(&o->file, paths[i], err);
        if (st) { q2n_outputs_abort_set(s); return st; }
    }
    return Q2N_OK;
}

q2n_status q2n_model_write_output(q2n_model *m, q2n_output *o, int tess, const q2n_export_options *xopt,
                                  q2n_error *err)
{
    q2n_export_options x = {0};
    if (xopt) x = *xopt;
    if (!x.progress && m->opt.progress.fn) x.progress = &m->opt.progress;
    x.mesh_scale = m->opt.scale;
    if (!x.threads) x.threads = m->fit_opt.threads;
    char name[72];
    if (!x.name && !strcmp(o->path, "-")) {   /* standard output: the product is named after the mesh */
        q2n_export_basename(m->mesh->name, name, sizeof name);
        x.name = name;
    }
    if (q2n_format_needs_fit(o->format) && !m->nurbs)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: the surface has not been fitted", o->path);
    double t0 = q2n_now();
    q2n_progress_emit(&m->opt.progress, "write", o->path, 0, 0);
    q2n_status st;
    switch (o->format) {
    case Q2N_FORMAT_OBJ: st = q2n_model_write_tessellation_file(m, tess, o->file.f, err); break;
    case Q2N_FORMAT_JSON:
        q2n_fit_report_write_json_file(&m->fit, q2n_units_name(x.units), o->file.f);
        st = Q2N_OK;
        break;
    case Q2N_FORMAT_STEP:
    case Q2N_FORMAT_IGES:
        st = q2n_export_stream(m->nurbs, &x, o->format == Q2N_FORMAT_IGES, o->path, o->file.f, err);
        if (!st) {   /* the size goes into the fit report (written after the CAD files) */
            long n = ftell(o->file.f);
            if (n > 0) *(o->format == Q2N_FORMAT_STEP ? &m->fit.step_bytes : &m->fit.iges_bytes) = n;
        }
        break;
    default: st = q2n_error_set(err, Q2N_ERR_ARG, "%s: unsupported output format", o->path);
    }
    m->t_write += q2n_now() - t0;
    return st;
}

q2n_status q2n_outputs_commit_set(q2n_output_set *s, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    /* 1. every output's data on disk (a full disk shows here, before anything is replaced) */
    for (int i = 0; i < s->n && !st; i++) st = q2n_outfile_finish(&s->out[i].file, err);
    /* 2. standard output and devices, which cannot be taken back; 3. the renames */
    for (int pass = 0; pass < 2 && !st; pass++)
        for (int i = 0; i < s->n && !st; i++)
            if (s->out[i].file.path && s->out[i].file.stream == !pass) st = q2n_outfile_commit(&s->out[i].file, err);
    q2n_outputs_abort_set(s); /* removes what was not committed */
    return st;
}

q2n_status q2n_model_write(q2n_model *m, const char *path, int tess, const q2n_export_options *xopt, q2n_error *err)
{
    q2n_output_set s;
    q2n_status st = q2n_outputs_open_set(&s, 1, &path, Q2N_FORMAT_NONE, m->mesh ? m->mesh->name : NULL, err);
    if (st) return st;
    if ((st = q2n_model_write_output(m, &s.out[0], tess, xopt, err))) {
        q2n_outputs_abort_set(&s);
        return st;
    }
    return q2n_outputs_commit_set(&s, err);
}
