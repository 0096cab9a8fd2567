/* extraordinary.c — the driver: gives every face that the regular augmented construction left
 * uncovered a patch of the chosen extraordinary-vertex construction (seed 003 §4):
 *   fair  (default) one jet per vertex, compatible Coons patches, fairness-energy solve (ev_fair.c, ev_fair_patch.c, ev_fair_solve.c);
 *   paper the paper's augmented Coons–Gregory patches with Appendix-B-style jets, ribbon cross
 *         fields and corner harmonisation (ev_paper.c, ev_harmonize.c).
 * Both build on the Boolean-sum Coons patch of coons_patch.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "patch/ev_fair.h"
#include "patch/ev_internal.h"

int q2n_ev_patch_parse(const char *s, q2n_ev_patch_kind *out)
{
    if (!s) return -1;
    if ((s[0] == 'g' || s[0] == 'G') && s[1] && !s[2]) {
        if (s[1] == '1') { *out = Q2N_EV_PATCH_G1; return 0; }
        if (s[1] == '2') { *out = Q2N_EV_PATCH_G2; return 0; }
    }
    return -1;
}

int q2n_ev_method_parse(const char *s, q2n_ev_method *out)
{
    if (!s) return -1;
    if (!strcmp(s, "fair")) { *out = Q2N_EV_METHOD_FAIR; return 0; }
    if (!strcmp(s, "paper")) { *out = Q2N_EV_METHOD_PAPER; return 0; }
    return -1;
}

static const q2n_spline_class *opt_class(const q2n_extraordinary_options *opt)
{
    return opt && opt->cls ? opt->cls : q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT);
}

int q2n_ev_patch_order(const q2n_extraordinary_options *opt)
{
    if (opt && opt->ev_patch == Q2N_EV_PATCH_G1) return 1;
    if (opt && opt->ev_patch == Q2N_EV_PATCH_G2) return 2;
    return opt_class(opt)->k >= 2 ? 2 : 1;
}

q2n_status q2n_extraordinary_build(const q2n_mesh *m, const q2n_extraordinary_options *opt,
                                   const double *edge_iv, q2n_surface *s, q2n_error *err)
{
    return q2n_extraordinary_build_stats(m, opt, edge_iv, s, NULL, err);
}

q2n_status q2n_extraordinary_build_stats(const q2n_mesh *m, const q2n_extraordinary_options *opt, const double *edge_iv,
                                         q2n_surface *s, q2n_extraordinary_stats *stats, q2n_error *err)
{
    if (stats) memset(stats, 0, sizeof *stats);
    if (!m || !s || !opt) return q2n_error_set(err, Q2N_ERR_ARG, "extraordinary: missing argument");
    if (!m->all_quads)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s: extraordinary patches need an all-quad mesh (subdivide once first)", m->name);
    if (q2n_surface_npatches(s) != m->nf)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: surface has %d patches for %d faces", m->name,
                             q2n_surface_npatches(s), m->nf);
    const q2n_spline_class *cls = opt_class(opt);
    if (!cls) return q2n_error_set(err, Q2N_ERR_ARG, "extraordinary: unknown spline class");
    int K = q2n_ev_patch_order(opt), nunc = 0;
    for (int f = 0; f < m->nf; f++) {
        q2n_patch_kind kd = q2n_surface_kind(s, f);
        if (kd == Q2N_PATCH_UNCOVERED) nunc++;
        else if (kd != Q2N_PATCH_AUGMENTED)
            return q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: patch kind %d is neither regular nor uncovered",
                                 m->name, f, (int)kd);
    }
    if (nunc == 0) return Q2N_OK;
    q2n_status st = Q2N_OK;
    double *own = NULL;
    if (!edge_iv) {
        if ((st = q2n_param_edge_intervals(m, &opt->param, &own, err))) return st;
        edge_iv = own;
    }
    const double *iv = edge_iv;
    if (opt->method == Q2N_EV_METHOD_PAPER) st = q2n_ev_paper_build(m, s, iv, cls, K, err);
    else {
        ev_fair_stats fs;
        st = q2n_ev_fair_build(m, opt->chart_mesh, s, iv, cls, K, opt->keep_flat, !opt->smooth_gluing, opt->smooth_vertices,
                               opt->threads, &fs, err);
        if (!st && stats) stats->flat_vertices = fs.flat_vertices, stats->polynomial_edges = fs.polynomial_edges,
                           stats->guard_faces = fs.jac_pinned_faces, stats->gregory_corners = fs.gregory_corners,
                           stats->border_edges = fs.border_edges, stats->noflat_vertices = fs.noflat_vertices;
    }
    free(own);
    return st;
}

q2n_status q2n_flat_faces_dev(const q2n_mesh *m, const q2n_surface *s, int n, int *nflat, double *dev, int *face)
{
    double diag = q2n_mesh_bbox_diag(m);
    double *t = malloc((size_t)n * sizeof *t), *P = malloc(3 * (size_t)n * n * sizeof *P);
    *nflat = 0, *dev = 0, *face = -1;
    if (!t || !P) { free(t); free(P); return Q2N_ERR_NOMEM; }
    for (int i = 0; i < n; i++) t[i] = n > 1 ? (double)i / (n - 1) : 0.5;
    q2n_status st = Q2N_OK;
    for (int f = 0; f < m->nf && !st; f++) {
        const int *fv = m->face_vert + m->face_start[f];
        const double *p0 = q2n_mesh_vpos(m, fv[0]);
        double a[3], b[3], nrm[3];
        q2n_v3_sub(a, q2n_mesh_vpos(m, fv[2]), p0);
        q2n_v3_sub(b, q2n_mesh_vpos(m, fv[3]), q2n_mesh_vpos(m, fv[1]));
        q2n_v3_cross(nrm, a, b);
        double ln = q2n_v3_norm(nrm);
        if (!(ln > 0)) continue;
        q2n_v3_scale(nrm, 1 / ln, nrm);
        int flat = 1; /* every corner's fan in the face's plane (corner 0's fan holds the face's corners) */
        for (int c = 0; c < 4 && flat; c++) flat = q2n_ev_fan_in_plane(m, fv[c], nrm) > 0;
        if (!flat) continue;
        ++*nflat;
        if ((st = q2n_surface_eval_grid_pos(s, f, n, t, n, t, P))) break;
        for (int i = 0; i < n * n; i++) {
            double d[3];
            q2n_v3_sub(d, P + 3 * i, p0);
            double x = fabs(q2n_v3_dot(d, nrm)) / diag;
            if (x > *dev) *dev = x, *face = f;
        }
    }
    free(t);
    free(P);
    return st;
}
