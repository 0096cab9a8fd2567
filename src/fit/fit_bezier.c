/* fit_bezier.c — exact conversion of Bézier patches (the Catmull–Clark ACC path) into the fit's
 * output: every patch is degree-elevated to 5 x 5 with one span (q2n_bezier_elevate, core/poly.h),
 * which is exact.  Why quintic and not
 * cubic: every patch of every model then has one degree, so the edge curves of neighbours (cubic
 * ACC faces next to quintic G1 faces near extraordinary vertices) have identical control points and
 * knots, which the one-edge-curve-per-mesh-edge STEP/IGES writers need. */
#include "fit/fit_internal.h"
#include "fit/fit_policy.h"
#include "core/clock.h"
#include "core/poly.h"
#include "core/vec3.h"

#include <stdlib.h>
#include <string.h>

/* Grid index of the it-th control point along side i of a 6 x 6 patch. */
static int side_index(int i, int it)
{
    const int *c0 = q2n_corner_uv[i], *d = q2n_side_along[i];
    int a = c0[0] * 5 + it * d[0], b = c0[1] * 5 + it * d[1];
    return b * 6 + a;
}

q2n_status q2n_fit_convert_bezier(const q2n_surface *s, const q2n_mesh *m, const q2n_fit_options *o,
                                  q2n_nurbs_model **out, q2n_fit_report *rep, q2n_error *err)
{
    double diag = q2n_mesh_bbox_diag(m);
    q2n_nurbs_model *md = calloc(1, sizeof *md);
    if (!md) return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (model)");
    md->n = m->nf;
    md->mesh = m;
    md->tol_abs = o->tol * diag;
    md->patches = calloc((size_t)m->nf, sizeof *md->patches);
    if (!md->patches) { free(md); return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (model)"); }
    for (int k = 0; k < m->nf; k++) {
        int du, dv;
        const double *cp;
        q2n_surface_bezier(s, k, &du, &dv, &cp);
        q2n_bspline_surface *b = &md->patches[k];
        if (du > Q2N_FIT_DEG || dv > Q2N_FIT_DEG) {
            q2n_nurbs_model_free(md);
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "fit: face %d: Bézier degree %d x %d above 5", k, du, dv);
        }
        b->deg_u = b->deg_v = Q2N_FIT_DEG;
        b->ncp_u = b->ncp_v = Q2N_FIT_DEG + 1;
        b->knots_u = malloc(12 * sizeof(double));
        b->knots_v = malloc(12 * sizeof(double));
        b->cp = malloc(3 * 36 * sizeof(double));
        if (!b->knots_u || !b->knots_v || !b->cp) {
            q2n_nurbs_model_free(md);
            return q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory (patch %d)", k);
        }
        q2n_fit_knots_uniform(1, b->knots_u);
        q2n_fit_knots_uniform(1, b->knots_v);
        q2n_bezier_elevate(du, dv, Q2N_FIT_DEG, Q2N_FIT_DEG, 3, cp, b->cp);
    }
    /* shared edges: identical control points on both sides (copy the owner's row) */
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], ht = m->he_twin[h];
        if (ht < 0) continue;
        int kl = m->he_face[h], kr = m->he_face[ht], il = h - m->face_start[kl], ir = ht - m->face_start[kr];
        for (int it = 0; it < 6; it++) {
            double *pl = md->patches[kl].cp + 3 * side_index(il, it), *pr = md->patches[kr].cp + 3 * side_index(ir, 5 - it);
            if (q2n_v3_dist(pl, pr) > Q2N_FIT_BEZIER_AGREE * diag) {
                double d = q2n_v3_dist(pl, pr);
                q2n_nurbs_model_free(md);
                return q2n_error_set(err, Q2N_ERR_GEOMETRY, "fit: edge %d (faces %d, %d): Bézier boundaries differ by %.3g",
                                     e, kl, kr, d);
            }
            memcpy(pr, pl, 3 * sizeof(double));
        }
    }
    *out = md;
    double t0 = q2n_now();
    size_t ne = m->ne > 0 ? (size_t)m->ne : 1;
    double *g1 = malloc(sizeof(double) * ne), *g1c = malloc(sizeof(double) * ne), *g2c = malloc(sizeof(double) * ne);
    q2n_fit_measure_out mo = {NULL, NULL, g1, NULL, g1c, g2c};
    q2n_status st = g1 && g1c && g2c ? q2n_fit_measure_model(md, s, rep, &mo, o->threads, err)
                                     : q2n_error_set(err, Q2N_ERR_NOMEM, "fit: out of memory");
    /* the report's count of edges G1 up to rounding (as the fit's, fit.c): here every interior edge
     * whose measured normal jump is that small, since nothing is glued */
    rep->g1_rounding_edges = 0;
    for (int e = 0; !st && e < m->ne; e++)
        rep->g1_rounding_edges += m->he_twin[m->edge_he[e]] >= 0 && g1[e] <= Q2N_FIT_G1_ROUNDING_DEG;
    free(g1);
    free(g1c);
    free(g2c);
    rep->t_measure += q2n_now() - t0;
    rep->exact = 1;
    rep->rounds = 0;
    rep->dev_met = rep->max_dev_rel <= o->tol;
    rep->g1_met = rep->g2_met = 1;   /* the conversion is exact: continuity is the construction's */
    rep->tol_met = rep->dev_met;
    q2n_fit_report_sizes(md, rep);
    return st;
}
