/* model.c — the pipeline object (see model.h). */
#include "api/model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "core/outfile.h"
#include "core/vec3.h"
#include "patch/augmented.h"
#include "patch/extraordinary.h"

void q2n_model_free(q2n_model *m)
{
    if (!m) return;
    q2n_nurbs_model_free(m->nurbs);
    q2n_surface_free(m->surface);
    q2n_mesh_free(m->mesh);
    free(m->edge_iv);
    free(m);
}

static q2n_status build_augmented(q2n_model *m, q2n_error *err)
{
    q2n_augmented_options ao = {m->opt.cls, m->opt.param};
    q2n_extraordinary_options eo = {m->opt.cls, m->opt.param, (q2n_ev_patch_kind)m->opt.ev_patch,
                                    (q2n_ev_method)m->opt.ev_method, m->opt.threads};
    q2n_status st = q2n_param_edge_intervals(m->mesh, &m->opt.param, &m->edge_iv, err);
    if (!st) st = q2n_augmented_build(m->mesh, &ao, m->edge_iv, &m->surface, err);
    /* faces at extraordinary vertices: augmented Coons–Gregory patches (§4) */
    if (!st && q2n_surface_count(m->surface, Q2N_PATCH_UNCOVERED) > 0)
        st = q2n_extraordinary_build(m->mesh, &eo, m->edge_iv, m->surface, err);
    int regular = m->opt.cls->k >= 2 ? 2 : 1, ev = q2n_ev_patch_order(&eo);
    m->continuity = (q2n_surface_count(m->surface, Q2N_PATCH_COONS_GREGORY) > 0 && ev < regular) ? ev : regular;
    return st;
}

static q2n_status build_acc(q2n_model *m, q2n_error *err)
{
    q2n_acc_options ao = {m->opt.method == Q2N_SURFACE_ACC3 ? Q2N_ACC_3 : Q2N_ACC_G1, m->opt.acc_strategy, 0};
    q2n_acc_info info;
    memset(&info, 0, sizeof info);
    q2n_status st = q2n_acc_build(m->mesh, &ao, &m->surface, &info, err);
    if (st) { q2n_acc_info_free(&info); return st; }
    q2n_acc_describe(&info, &ao, m->note, sizeof m->note);
    if (info.mesh) { /* the patches live on the subdivided mesh: it becomes the model's mesh */
        q2n_mesh_free(m->mesh);
        m->mesh = info.mesh;
        info.mesh = NULL;
    }
    q2n_acc_info_free(&info);
    /* acc3 is C0 across edges that end at an EV (C2 elsewhere); acc-g1 is G1 everywhere */
    m->continuity = m->opt.method == Q2N_SURFACE_ACC3 ? 0 : 1;
    return Q2N_OK;
}

q2n_status q2n_model_read(const char *mesh_path, const q2n_model_options *opt, q2n_model **out, q2n_error *err)
{
    q2n_model *m = calloc(1, sizeof *m);
    if (!m) return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory");
    if (opt) m->opt = *opt;
    if (!m->opt.cls) m->opt.cls = q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT);
    if (m->opt.scale == 0.0) m->opt.scale = 1.0;
    double t0 = q2n_now();
    q2n_progress_emit(&m->opt.progress, "read", mesh_path, 0, 0);
    q2n_status st = Q2N_OK;
    if (!(m->opt.scale > 0.0 && isfinite(m->opt.scale)))
        st = q2n_error_set(err, Q2N_ERR_ARG, "scale %g is not a positive number", m->opt.scale);
    if (!st) st = q2n_mesh_read(mesh_path, &m->mesh, &m->read_info, err);
    /* --scale multiplies what leaves the library (fitted control points, tessellation, samples,
     * evaluations), not the mesh the construction sees: the output is then exactly the scaled
     * surface, whether or not the construction is scale-free */
    for (size_t i = 0; !st && i < 3 * (size_t)m->mesh->nv; i++)
        if (!isfinite(m->mesh->pos[i] * m->opt.scale))
            st = q2n_error_set(err, Q2N_ERR_ARG, "%s: vertex %zu: coordinate %g times scale %g overflows", mesh_path,
                               i / 3 + 1, m->mesh->pos[i], m->opt.scale);
    m->t_read = q2n_now() - t0;
    if (st) { q2n_model_free(m); return st; }
    *out = m;
    return Q2N_OK;
}

/* The augmented construction's extraordinary patches handle vertices of valence up to
 * Q2N_EV_MAX_VALENCE: a higher one is refused here, with the line of a face at it. */
static q2n_status check_valence(const q2n_model *m, q2n_error *err)
{
    const q2n_mesh *me = m->mesh;
    for (int v = 0; v < me->nv; v++) {
        if (me->valence[v] <= Q2N_EV_MAX_VALENCE) continue;
        int f = me->vert_he[v] >= 0 ? me->he_face[me->vert_he[v]] : 0, line = me->face_line ? me->face_line[f] : 0;
        char where[300];
        if (line > 0) snprintf(where, sizeof where, "%s:%d", me->name, line);
        else snprintf(where, sizeof where, "%s: face %d", me->name, f);
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s: vertex %d (of this face) has valence %d; the augmented construction handles at "
                             "most %d (--surface acc3 or acc-g1 have no limit)", where, v + 1, me->valence[v],
                             Q2N_EV_MAX_VALENCE);
    }
    return Q2N_OK;
}

q2n_status q2n_model_construct(q2n_model *m, q2n_error *err)
{
    double t0 = q2n_now();
    q2n_status st = Q2N_OK;
    const char *path = m->mesh->name;
    if (m->opt.subdivide > 0) {
        q2n_progress_emit(&m->opt.progress, "subdivide", NULL, 0, m->opt.subdivide);
        q2n_mesh *sub = NULL;
        st = q2n_mesh_subdivide(m->mesh, m->opt.subdivide, &sub, err);
        if (!st) { q2n_mesh_free(m->mesh); m->mesh = sub; }
    }
    if (!st && !m->mesh->all_quads && m->opt.method == Q2N_SURFACE_AUGMENTED) {
        int f = 0;
        while (f < m->mesh->nf && q2n_face_size(m->mesh, f) == 4) f++;
        st = q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                           "%s:%d: face %d has %d vertices; only quad meshes are supported "
                           "(use --subdivide 1 to apply one Catmull-Clark step first)",
                           path, m->mesh->face_line[f], f, q2n_face_size(m->mesh, f));
    }
    if (!st && m->opt.method == Q2N_SURFACE_AUGMENTED) st = check_valence(m, err);
    m->t_read += q2n_now() - t0;
    t0 = q2n_now();
    if (!st) q2n_progress_emit(&m->opt.progress, "build", NULL, 0, m->mesh->nf);
    if (!st) st = m->opt.method == Q2N_SURFACE_AUGMENTED ? build_augmented(m, err) : build_acc(m, err);
    if (st) return st;
    m->uncovered = q2n_surface_count(m->surface, Q2N_PATCH_UNCOVERED);
    m->t_build = q2n_now() - t0;
    q2n_progress_emit(&m->opt.progress, "build", NULL, m->mesh->nf, m->mesh->nf);
    return Q2N_OK;
}

q2n_status q2n_model_build(const char *mesh_path, const q2n_model_options *opt, q2n_model **out,
                           q2n_error *err)
{
    q2n_model *m = NULL;
    q2n_status st = q2n_model_read(mesh_path, opt, &m, err);
    if (!st && (st = q2n_model_construct(m, err))) q2n_model_free(m);
    if (!st) *out = m;
    return st;
}

q2n_status q2n_model_fit(q2n_model *m, const q2n_fit_options *fopt, q2n_error *err)
{
    q2n_fit_options o;
    if (fopt) o = *fopt;
    else q2n_fit_options_default(&o);
    if (o.tol_abs > 0) o.tol_abs /= m->opt.scale; /* model units are output units: the mesh is unscaled */
    if (o.continuity == 0) o.continuity = m->continuity >= 2 ? 2 : 1;
    if (m->uncovered)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "fit: %d faces are not covered by a patch; cannot fit an incomplete surface",
                             m->uncovered);
    if (!o.progress && m->opt.progress.fn) o.progress = &m->opt.progress;
    double t0 = q2n_now();
    q2n_nurbs_model_free(m->nurbs);
    m->nurbs = NULL;
    q2n_status st = q2n_fit_surface(m->surface, m->mesh, &o, &m->nurbs, &m->fit, err);
    double sc = m->opt.scale;
    if (m->nurbs && sc != 1.0) { /* into output coordinates (--scale); relative figures stay */
        for (int k = 0; k < m->nurbs->n; k++) {
            q2n_bspline_surface *b = &m->nurbs->patches[k];
            for (size_t i = 0; i < 3 * (size_t)b->ncp_u * b->ncp_v; i++) b->cp[i] *= sc;
        }
        for (int e = 0; m->nurbs->edges && e < m->mesh->ne; e++) { /* the shared edge curves too */
            q2n_bspline_curve *c = &m->nurbs->edges[e];
            for (size_t i = 0; i < 3 * (size_t)c->ncp; i++) c->cp[i] *= sc;
        }
        m->nurbs->tol_abs *= sc;
        m->fit.diag *= sc;
        m->fit.tol_abs *= sc;
    }
    m->t_fit = q2n_now() - t0;
    if (st && err && strncmp(err->message, "fit: ", 5) != 0) { /* every fit message says where it comes from */
        char msg[sizeof err->message];
        snprintf(msg, sizeof msg, "%s", err->message);
        q2n_error_set(err, st, "fit: %s", msg);
    }
    return st;
}

static double *grid_params(int n)
{
    double *t = malloc((size_t)n * sizeof *t);
    if (t)
        for (int i = 0; i < n; i++) t[i] = n == 1 ? 0.5 : (double)i / (n - 1);
    return t;
}

q2n_status q2n_model_write_tessellation(const q2n_model *m, int n, const char *path, q2n_error *err)
{
    q2n_outfile of;
    q2n_status st = q2n_outfile_open(&of, path, err);
    if (st) return st;
    if ((st = q2n_model_write_tessellation_file(m, n, of.f, err))) {
        q2n_outfile_abort(&of);
        return st;
    }
    return q2n_outfile_commit(&of, err);
}

q2n_status q2n_model_write_tessellation_file(const q2n_model *m, int n, FILE *f, q2n_error *err)
{
    q2n_status st = Q2N_OK;
    double *t = grid_params(n), *buf = malloc(9 * (size_t)n * n * sizeof *buf);
    if (!t || !buf) {
        free(t); free(buf);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (tessellation)");
    }
    char name[sizeof m->mesh->name * 4];
    q2n_escape(name, sizeof name, m->mesh->name); /* a file name is not allowed to end the comment line */
    fprintf(f, "# quad2nurbs tessellation of %s: %d x %d points per patch\n", name, n, n);
    long base = 1;
    for (int k = 0; k < m->mesh->nf; k++) {
        if (k % 256 == 0) q2n_progress_emit(&m->opt.progress, "write", "tessellation", k, m->mesh->nf);
        if (q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        if ((st = q2n_surface_eval_grid(m->surface, k, n, t, n, t, buf))) {
            q2n_error_set(err, st, "patch %d: evaluation failed", k);
            break;
        }
        fprintf(f, "g patch_%d\n", k);
        for (int p = 0; p < n * n; p++) {
            double *e = buf + 9 * p;
            for (int c = 0; c < 3; c++) e[c] *= m->opt.scale;
            double nrm[3];
            q2n_v3_cross(nrm, e + 3, e + 6);
            double len = q2n_v3_norm(nrm);
            if (len > 0) q2n_v3_scale(nrm, 1 / len, nrm);
            fprintf(f, "v %.17g %.17g %.17g\nvn %.9g %.9g %.9g\n", e[0], e[1], e[2], nrm[0], nrm[1], nrm[2]);
        }
        for (int j = 0; j + 1 < n; j++)
            for (int i = 0; i + 1 < n; i++) {
                long a = base + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
                fprintf(f, "f %ld//%ld %ld//%ld %ld//%ld %ld//%ld\n", a, a, b, b, c, c, d, d);
            }
        base += (long)n * n;
    }
    free(t);
    free(buf);
    return st;
}

q2n_status q2n_model_write_samples(const q2n_model *m, int n, FILE *out, q2n_error *err)
{
    double *t = grid_params(n), *buf = malloc(9 * (size_t)n * n * sizeof *buf);
    q2n_status st = Q2N_OK;
    if (!t || !buf) {
        free(t); free(buf);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (samples)");
    }
    for (int k = 0; k < m->mesh->nf && !st; k++) {
        if (q2n_surface_kind(m->surface, k) == Q2N_PATCH_UNCOVERED) continue;
        if ((st = q2n_surface_eval_grid(m->surface, k, n, t, n, t, buf))) {
            q2n_error_set(err, st, "patch %d: evaluation failed", k);
            break;
        }
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                double *e = buf + 9 * ((size_t)j * n + i);
                for (int c = 0; c < 9; c++) e[c] *= m->opt.scale;
                fprintf(out, "%d %.17g %.17g", k, t[i], t[j]);
                for (int c = 0; c < 9; c++) fprintf(out, " %.17g", e[c]);
                fputc('\n', out);
            }
    }
    free(t);
    free(buf);
    if (!st && ferror(out)) st = q2n_error_set(err, Q2N_ERR_IO, "error writing samples");
    return st;
}
