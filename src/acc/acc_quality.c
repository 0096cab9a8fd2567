/* acc_quality.c — the quality measures of seed 001 §6: the unit-normal jump [n̂] integrated over
 * the mesh edges, the largest Gauss / mean curvature jumps <c_G>, <c_M> across edges (§6.1), and
 * the geometry / unit-normal distance to the Catmull–Clark limit surface (§6.3). */
#include "acc/acc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "acc/acc_masks.h"
#include "acc/acc_policy.h"
#include "core/poly.h"
#include "core/vec3.h"
#include "patch/fairness.h"



typedef struct diffgeo {
    double n[3];   /* unit normal */
    double K, H;   /* Gauss and mean curvature */
} diffgeo;

static q2n_status eval_geo(const q2n_surface *s, int k, double u, double v, diffgeo *g)
{
    double e[Q2N_EVAL_MAX];
    q2n_status st = q2n_surface_eval(s, k, u, v, 2, e);
    if (st != Q2N_OK) return st;
    double len = q2n_curvatures(e, &g->H, &g->K); /* NAN where the normal vanishes: no jump counted */
    q2n_v3_cross(g->n, e + Q2N_EV_U, e + Q2N_EV_V);
    q2n_v3_scale(g->n, 1.0 / (len > 0 ? len : 1e-300), g->n);
    return Q2N_OK;
}

q2n_status q2n_acc_quality_measure(const q2n_surface *s, const q2n_mesh *m, int npts,
                                   q2n_acc_quality *q, q2n_error *err)
{
    if (!s || !m || !q || npts < 2 || npts > 16 || q2n_surface_npatches(s) != m->nf)
        return q2n_error_set(err, Q2N_ERR_ARG, "acc quality: bad arguments (npts %d, %d patches, %d faces)",
                             npts, s ? q2n_surface_npatches(s) : -1, m ? m->nf : -1);
    memset(q, 0, sizeof *q);
    q->n_points = npts;
    double x[16], w[16], sum = 0;
    q2n_gauss_legendre01(npts, x, w);
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], t = m->he_twin[h];
        if (t < 0) continue;
        int f = m->he_face[h], g = m->he_face[t];
        int c = h - m->face_start[f], cg = t - m->face_start[g];
        q->n_edges++;
        for (int i = 0; i < npts; i++) {
            double u1, v1, u2, v2;
            q2n_side_uv(c & 3, x[i], 0, &u1, &v1);
            q2n_side_uv(cg & 3, 1 - x[i], 0, &u2, &v2);
            diffgeo a, b;
            q2n_status st = eval_geo(s, f, u1, v1, &a);
            if (st == Q2N_OK) st = eval_geo(s, g, u2, v2, &b);
            if (st != Q2N_OK)
                return q2n_error_set(err, st, "acc quality: edge %d (faces %d, %d) cannot be evaluated", e, f, g);
            double d[3], cr[3];
            q2n_v3_sub(d, a.n, b.n);
            sum += w[i] * q2n_v3_dot(d, d);
            q2n_v3_cross(cr, a.n, b.n);
            double ang = atan2(q2n_v3_norm(cr), q2n_v3_dot(a.n, b.n));
            if (ang > q->normal_jump_max) q->normal_jump_max = ang;
            if (fabs(a.K - b.K) > q->gauss_jump_max) q->gauss_jump_max = fabs(a.K - b.K);
            if (fabs(a.H - b.H) > q->mean_jump_max) q->mean_jump_max = fabs(a.H - b.H);
        }
    }
    q->normal_jump_l2 = sqrt(sum);
    return Q2N_OK;
}

/* Projection of p onto patch k from (u,v), clamped to the unit square. */
static void project(const q2n_surface *s, int k, const double p[3], double *u, double *v)
{
    q2n_surface_project(s, k, p, Q2N_ACC_PROJECT_STEPS, u, v);
}

/* Try patch g for the closest point of p (from its centre); keep it when it is closer. */
static void try_patch(const q2n_surface *s, int g, const double p[3], double *best, double *u,
                      double *v, int *kk)
{
    double gu = 0.5, gv = 0.5, e[3];
    project(s, g, p, &gu, &gv);
    q2n_surface_eval(s, g, gu, gv, 0, e);
    double d = q2n_v3_dist(p, e);
    if (d < *best) { *best = d; *u = gu; *v = gv; *kk = g; }
}

/* Closest point of p on patch k, and on the patches around face k when the projection stops on
 * the border of the unit square (the closest point then lies on a neighbour). */
static double closest(const q2n_surface *s, const q2n_mesh *m, int k, const double p[3], double *u,
                      double *v, int *kk)
{
    double e[3];
    project(s, k, p, u, v);
    q2n_surface_eval(s, k, *u, *v, 0, e);
    double best = q2n_v3_dist(p, e);
    *kk = k;
    int border = *u <= 0 || *u >= 1 || *v <= 0 || *v >= 1;
    if (!m || !border) return best;
    for (int c = 0; c < q2n_face_size(m, k); c++) { /* the faces around each corner of face k */
        int h0 = q2n_face_he(m, k, c), h = q2n_mesh_rotate(m, h0);
        for (; h >= 0 && h != h0; h = q2n_mesh_rotate(m, h)) try_patch(s, m->he_face[h], p, &best, u, v, kk);
        if (h < 0) /* stopped at the boundary: the other way round too */
            for (h = q2n_mesh_rotate_back(m, h0); h >= 0 && h != h0; h = q2n_mesh_rotate_back(m, h))
                try_patch(s, m->he_face[h], p, &best, u, v, kk);
    }
    return best;
}

/* Add one sample (limit point p, limit normal nl, patch kk at (u,v)) to the statistics. */
static q2n_status accumulate(const q2n_surface *s, int kk, double u, double v, const double p[3],
                             const double nl[3], q2n_acc_distance *d, double *sum, q2n_error *err)
{
    double e[9], np[3];
    q2n_status st = q2n_surface_eval(s, kk, u, v, 1, e);
    if (st != Q2N_OK) return q2n_error_set(err, st, "acc distance: patch %d cannot be evaluated", kk);
    double dist = q2n_v3_dist(p, e);
    q2n_v3_cross(np, e + 3, e + 6);
    double ln = q2n_v3_norm(nl), lp = q2n_v3_norm(np);
    if (ln > 0 && lp > 0) {
        double diff[3];
        for (int t = 0; t < 3; t++) diff[t] = nl[t] / ln - np[t] / lp;
        double ne = q2n_v3_norm(diff);
        if (ne > d->normal_max) d->normal_max = ne;
    }
    if (dist > d->geom_max) d->geom_max = dist;
    *sum += dist * dist;
    d->n_samples++;
    return Q2N_OK;
}

q2n_status q2n_acc_limit_distance(const q2n_surface *s, const q2n_mesh *m, int n, q2n_acc_limit_fn limit,
                                  void *ctx, int proj, q2n_acc_distance *d, q2n_error *err)
{
    if (!s || !limit || !d || n < 1 || (m && m->nf != q2n_surface_npatches(s)))
        return q2n_error_set(err, Q2N_ERR_ARG, "acc distance: bad arguments");
    memset(d, 0, sizeof *d);
    double sum = 0;
    for (int k = 0; k < q2n_surface_npatches(s); k++)
        for (int b = 0; b < n; b++)
            for (int a = 0; a < n; a++) {
                double u = (a + 0.5) / n, v = (b + 0.5) / n, p[3], nl[3];
                int kk = k;
                q2n_status st = limit(ctx, k, u, v, p, nl);
                if (st != Q2N_OK) return q2n_error_set(err, st, "acc distance: limit evaluator failed on face %d", k);
                if (proj) closest(s, m, k, p, &u, &v, &kk);
                st = accumulate(s, kk, u, v, p, nl, d, &sum, err);
                if (st != Q2N_OK) return st;
            }
    d->geom_rms = d->n_samples ? sqrt(sum / d->n_samples) : 0;
    return Q2N_OK;
}

void q2n_acc_limit_samples_free(q2n_acc_limit_samples *ls)
{
    if (!ls) return;
    free(ls->face);
    free(ls->uv);
    free(ls->p);
    free(ls->nrm);
    memset(ls, 0, sizeof *ls);
}

/* Affine maps (origin, image of the unit u step, of the unit v step: 6 doubles) of the faces of
 * an all-quad mesh with nf0 faces subdivided `levels` times onto their base faces.  Sub-quad c
 * of a quad p is face 4p + c, (v_c, e_c, f, e_{c-1}) (mesh.h): it covers the quarter of p at
 * corner c, u towards corner c+1, v towards corner c-1.  map and tmp hold nf0 * 4^levels maps. */
static void face_maps(int nf0, int levels, double *map, double *tmp)
{
    for (int k = 0; k < nf0; k++) {
        double *a = map + 6 * (size_t)k;
        a[0] = a[1] = a[3] = a[4] = 0;
        a[2] = a[5] = 1;
    }
    for (int l = 0, cur = nf0; l < levels; l++, cur *= 4) {
        for (int p = 0; p < cur; p++)
            for (int c = 0; c < 4; c++) {
                /* the quarter at corner c: u along side c, v along its inward direction (patch/surface.h) */
                const double *a = map + 6 * (size_t)p;
                const int *P0 = q2n_corner_uv[c], *al = q2n_side_along[c], *in = q2n_side_inward[c];
                double *b = tmp + 6 * ((size_t)4 * p + c);
                double lu[2] = { al[0] / 2.0, al[1] / 2.0 }, lv[2] = { in[0] / 2.0, in[1] / 2.0 };
                for (int t = 0; t < 2; t++) { /* x -> a(P0 + s lu + t lv), a(y) = o + y0 U + y1 V */
                    b[t] = a[t] + P0[0] * a[2 + t] + P0[1] * a[4 + t];
                    b[2 + t] = lu[0] * a[2 + t] + lu[1] * a[4 + t];
                    b[4 + t] = lv[0] * a[2 + t] + lv[1] * a[4 + t];
                }
            }
        memcpy(map, tmp, (size_t)4 * cur * 6 * sizeof *map);
    }
}

q2n_status q2n_acc_limit_samples_make(const q2n_mesh *m, int levels, q2n_acc_limit_samples *out,
                                      q2n_error *err)
{
    memset(out, 0, sizeof *out);
    if (!m || levels < 0 || levels > 6 || !m->all_quads)
        return q2n_error_set(err, Q2N_ERR_ARG, "acc limit samples: need an all-quad mesh and 0..6 levels");
    q2n_mesh *fine = NULL;
    q2n_status st = levels ? q2n_mesh_subdivide(m, levels, &fine, err) : Q2N_OK;
    if (st != Q2N_OK) return st;
    const q2n_mesh *f = levels ? fine : m;
    size_t nv = (size_t)f->nv + 1;
    double *map = malloc((size_t)f->nf * 6 * sizeof *map), *tmp = malloc((size_t)f->nf * 6 * sizeof *tmp);
    out->n = f->nv;
    out->face = malloc(nv * sizeof *out->face);
    out->uv = malloc(nv * 2 * sizeof *out->uv);
    out->p = malloc(nv * 3 * sizeof *out->p);
    out->nrm = malloc(nv * 3 * sizeof *out->nrm);
    if (!map || !tmp || !out->face || !out->uv || !out->p || !out->nrm) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "acc limit samples: out of memory");
    } else {
        face_maps(m->nf, levels, map, tmp);
        for (int v = 0; v < f->nv; v++) out->face[v] = -1;
        for (int F = 0; F < f->nf; F++) /* the first face corner at each fine vertex gives its (face, u, v) */
            for (int c = 0; c < 4; c++) {
                int v = f->face_vert[f->face_start[F] + c];
                if (out->face[v] >= 0) continue;
                const double *a = map + 6 * (size_t)F;
                out->face[v] = F >> (2 * levels); /* face F descends from base face F / 4^levels */
                out->uv[2 * v] = a[0] + q2n_corner_uv[c][0] * a[2] + q2n_corner_uv[c][1] * a[4];
                out->uv[2 * v + 1] = a[1] + q2n_corner_uv[c][0] * a[3] + q2n_corner_uv[c][1] * a[5];
            }
        st = q2n_acc_limit_points(f, out->p, out->nrm, err);
    }
    free(map);
    free(tmp);
    q2n_mesh_free(fine);
    if (st != Q2N_OK) q2n_acc_limit_samples_free(out);
    return st;
}

q2n_status q2n_acc_limit_distance_samples(const q2n_surface *s, const q2n_mesh *m,
                                          const q2n_acc_limit_samples *ls, int proj,
                                          q2n_acc_distance *d, q2n_error *err)
{
    if (!s || !ls || !d || (m && m->nf != q2n_surface_npatches(s)))
        return q2n_error_set(err, Q2N_ERR_ARG, "acc distance: bad arguments");
    memset(d, 0, sizeof *d);
    double sum = 0;
    for (int i = 0; i < ls->n; i++) {
        int k = ls->face[i], kk = k;
        if (k < 0) continue; /* isolated vertex */
        double u = ls->uv[2 * i], v = ls->uv[2 * i + 1];
        if (proj) closest(s, m, k, ls->p + 3 * (size_t)i, &u, &v, &kk);
        q2n_status st = accumulate(s, kk, u, v, ls->p + 3 * (size_t)i, ls->nrm + 3 * (size_t)i, d, &sum, err);
        if (st != Q2N_OK) return st;
    }
    d->geom_rms = d->n_samples ? sqrt(sum / d->n_samples) : 0;
    return Q2N_OK;
}
