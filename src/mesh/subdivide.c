/* subdivide.c — Catmull–Clark subdivision of polygon meshes with boundaries (see mesh.h for the
 * vertex and face order of the result).
 *
 * Rules (E. Catmull, J. Clark, "Recursively generated B-spline surfaces on arbitrary topological
 * meshes", CAD 10(6), 1978; boundary as in OpenSubdiv's Sdc::SCHEME_CATMARK with
 * VTX_BOUNDARY_EDGE_AND_CORNER, which treats boundary edges as infinitely sharp creases):
 *   face point             f = centroid of the face's vertices
 *   interior edge point    e = (v0 + v1 + f0 + f1) / 4
 *   boundary edge point    e = (v0 + v1) / 2
 *   interior vertex        v' = (F + 2R + (n-3) P) / n, F = mean of the n adjacent face points,
 *                          R = mean of the n incident edge midpoints, n = valence
 *   boundary vertex        v' = (e_a + 6 v + e_b) / 8, e_a, e_b its two boundary neighbours
 *                          (cubic B-spline boundary curve)
 *   corner (boundary vertex with one incident face, valence 2): v' = v.
 * Each step rebuilds and revalidates the topology through q2n_mesh_from_arrays_lines; the sub-faces
 * inherit the OBJ line of their parent face, so later messages still point into the input file. */
#include "mesh/mesh.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"

/* Face points: centroids (Catmull & Clark 1978, "new face points"; OpenSubdiv
 * sdc/scheme.h ComputeFaceVertexMask: 1/n each). */
static void face_points(const q2n_mesh *m, double *fp)
{
    for (int f = 0; f < m->nf; f++) {
        double c[3] = {0, 0, 0};
        int n = q2n_face_size(m, f);
        for (int h = m->face_start[f]; h < m->face_start[f + 1]; h++)
            q2n_v3_add(c, c, q2n_mesh_vpos(m, m->face_vert[h]));
        q2n_v3_scale(fp + 3 * (size_t)f, 1.0 / n, c);
    }
}

static void edge_points(const q2n_mesh *m, const double *fp, double *ep)
{
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], t = m->he_twin[h];
        const double *a = q2n_mesh_vpos(m, q2n_he_origin(m, h));
        const double *b = q2n_mesh_vpos(m, q2n_he_dest(m, h));
        double *r = ep + 3 * (size_t)e;
        q2n_v3_add(r, a, b);
        if (t < 0) {
            q2n_v3_scale(r, 0.5, r); /* boundary = infinitely sharp: midpoint (OSD sdc/scheme.h,
                                         * assignCreaseMaskForEdge) */
        } else {
            q2n_v3_add(r, r, fp + 3 * (size_t)m->he_face[h]);
            q2n_v3_add(r, r, fp + 3 * (size_t)m->he_face[t]);
            q2n_v3_scale(r, 0.25, r); /* (v0 + v1 + f0 + f1) / 4: Catmull & Clark 1978, "new edge
                                          * points"; OSD catmarkScheme.h assignSmoothMaskForEdge */
        }
    }
}

/* Vertex points.  Sums over outgoing half-edges: each gives one incident face and, for interior
 * vertices, one incident edge; boundary neighbours come from the boundary half-edges. */
static q2n_status vertex_points(const q2n_mesh *m, const double *fp, double *vp)
{
    double *fs = calloc(3 * (size_t)m->nv + 1, sizeof *fs); /* sum of adjacent face points */
    double *ns = calloc(3 * (size_t)m->nv + 1, sizeof *ns); /* sum of edge / boundary neighbours */
    if (!fs || !ns) {
        free(fs);
        free(ns);
        return Q2N_ERR_NOMEM;
    }
    for (int h = 0; h < m->nh; h++) {
        int a = q2n_he_origin(m, h), b = q2n_he_dest(m, h);
        q2n_v3_add(fs + 3 * (size_t)a, fs + 3 * (size_t)a, fp + 3 * (size_t)m->he_face[h]);
        if (!m->vert_boundary[a]) {
            q2n_v3_add(ns + 3 * (size_t)a, ns + 3 * (size_t)a, q2n_mesh_vpos(m, b));
        }
        if (m->he_twin[h] < 0) { /* boundary edge a->b: both ends are boundary vertices */
            q2n_v3_add(ns + 3 * (size_t)a, ns + 3 * (size_t)a, q2n_mesh_vpos(m, b));
            q2n_v3_add(ns + 3 * (size_t)b, ns + 3 * (size_t)b, q2n_mesh_vpos(m, a));
        }
    }
    for (int v = 0; v < m->nv; v++) {
        const double *p = q2n_mesh_vpos(m, v);
        double *r = vp + 3 * (size_t)v, *F = fs + 3 * (size_t)v, *Q = ns + 3 * (size_t)v;
        int n = m->valence[v];
        if (m->vert_nfaces[v] == 0 || (m->vert_boundary[v] && m->vert_nfaces[v] == 1)) {
            memcpy(r, p, 3 * sizeof *p); /* unreferenced, or corner: fixed (OSD sdc/scheme.h
                                          * assignCornerMaskForVertex) */
        } else if (m->vert_boundary[v]) {
            /* (e_a + 6v + e_b)/8: cubic B-spline curve rule, OSD catmarkScheme.h
             * assignCreaseMaskForVertex (weights 1/8, 3/4, 1/8) */
            for (int c = 0; c < 3; c++) r[c] = (Q[c] + 6.0 * p[c]) / 8.0;
        } else {
            /* (F + 2R + (n-3)P)/n with F = ΣF_i/n, R = Σ(P + Q_i)/(2n): Catmull & Clark 1978,
             * "new vertex points"; equals OSD assignSmoothMaskForVertex ((n-2)/n, 1/n² per
             * neighbour and per face point) */
            for (int c = 0; c < 3; c++) {
                double Fm = F[c] / n, R = (n * p[c] + Q[c]) / (2.0 * n);
                r[c] = (Fm + 2.0 * R + (n - 3) * p[c]) / n;
            }
        }
    }
    free(fs);
    free(ns);
    return Q2N_OK;
}

static q2n_status cc_step(const q2n_mesh *m, q2n_mesh **out, q2n_error *err)
{
    long long nv2 = (long long)m->nv + m->nf + m->ne, nh2 = 4LL * m->nh;
    if (nv2 > INT_MAX || nh2 > INT_MAX || (long long)m->nh > INT_MAX / 4)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: subdivided mesh too large for int "
                             "indices", m->name);
    int nf2 = m->nh, fbase = m->nv, ebase = m->nv + m->nf;
    double *pos = malloc(3 * (size_t)nv2 * sizeof *pos);
    int *fstart = malloc(((size_t)nf2 + 1) * sizeof *fstart);
    int *fvert = malloc((size_t)nh2 * sizeof *fvert);
    int *fline = malloc((size_t)nf2 * sizeof *fline);
    q2n_status st = Q2N_OK;
    if (!pos || !fstart || !fvert || !fline) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", m->name);
        goto done;
    }
    face_points(m, pos + 3 * (size_t)fbase);
    edge_points(m, pos + 3 * (size_t)fbase, pos + 3 * (size_t)ebase);
    if (vertex_points(m, pos + 3 * (size_t)fbase, pos)) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", m->name);
        goto done;
    }
    /* sub-quad at corner i of face f: (v_i, e_i, f, e_{i-1}); its index is half-edge h = s+i */
    for (int f = 0; f < m->nf; f++) {
        for (int h = m->face_start[f]; h < m->face_start[f + 1]; h++) {
            int *q = fvert + 4 * (size_t)h;
            q[0] = m->face_vert[h];
            q[1] = ebase + m->he_edge[h];
            q[2] = fbase + f;
            q[3] = ebase + m->he_edge[q2n_he_prev(m, h)];
            fstart[h] = 4 * h;
            fline[h] = m->face_line[f];
        }
    }
    fstart[nf2] = (int)nh2;
    st = q2n_mesh_from_arrays_lines((int)nv2, pos, nf2, fstart, fvert, fline, m->name, out, err);
done:
    free(pos);
    free(fstart);
    free(fvert);
    free(fline);
    return st;
}

q2n_status q2n_mesh_subdivide(const q2n_mesh *m, int steps, q2n_mesh **out, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "subdivide: no output pointer");
    *out = NULL;
    if (!m) return q2n_error_set(err, Q2N_ERR_ARG, "subdivide: NULL mesh");
    if (steps < 0)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: subdivision steps %d < 0", m->name, steps);
    if (steps == 0)
        return q2n_mesh_from_arrays_lines(m->nv, m->pos, m->nf, m->face_start, m->face_vert,
                                          m->face_line, m->name, out, err);
    q2n_mesh *cur = NULL;
    const q2n_mesh *src = m;
    for (int s = 0; s < steps; s++) {
        q2n_mesh *next = NULL;
        q2n_status st = cc_step(src, &next, err);
        q2n_mesh_free(cur);
        if (st) return st;
        src = cur = next;
    }
    *out = cur;
    return Q2N_OK;
}

/* Limit positions of the same rules (the position each vertex converges to under repeated steps):
 *   interior vertex of valence n, every incident face a quad:
 *                          p = (n² v + 4 Σ e_j + Σ d_j) / (n (n + 5)), e_j its n edge neighbours,
 *                          d_j the vertex opposite v in each incident quad (OSD catmarkScheme.h
 *                          assignSmoothLimitMask, applied as PrimvarRefiner::Limit does: n/(n+5) for
 *                          v, 4/(n(n+5)) per edge, 1/(n(n+5)) per opposite vertex; formulas.md §2.1)
 *   boundary vertex        p = (e_a + 4 v + e_b) / 6, the cubic B-spline boundary curve's point
 *                          (OSD assignCreaseLimitMask)
 *   corner, unreferenced, interior valence 2   p = v. */
q2n_status q2n_mesh_limit_points(const q2n_mesh *m, q2n_mesh **out, q2n_error *err)
{
    if (!out) return q2n_error_set(err, Q2N_ERR_ARG, "limit points: no output pointer");
    *out = NULL;
    if (!m) return q2n_error_set(err, Q2N_ERR_ARG, "limit points: NULL mesh");
    double *pos = calloc(3 * (size_t)m->nv + 1, sizeof *pos), *es = calloc(3 * (size_t)m->nv + 1, sizeof *es);
    double *ds = calloc(3 * (size_t)m->nv + 1, sizeof *ds);
    q2n_status st = Q2N_OK;
    if (!pos || !es || !ds) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", m->name);
        goto done;
    }
    for (int h = 0; h < m->nh; h++) {
        int a = q2n_he_origin(m, h), f = m->he_face[h];
        if (m->vert_boundary[a]) {
            if (m->he_twin[h] < 0) { /* boundary edge a->b: each end's boundary neighbour */
                int b = q2n_he_dest(m, h);
                q2n_v3_add(es + 3 * (size_t)a, es + 3 * (size_t)a, q2n_mesh_vpos(m, b));
                q2n_v3_add(es + 3 * (size_t)b, es + 3 * (size_t)b, q2n_mesh_vpos(m, a));
            }
            continue;
        }
        if (q2n_face_size(m, f) != 4) {
            char where[300];
            q2n_mesh_face_where(m, f, where, sizeof where);
            st = q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: face %d has %d vertices; limit points need quads around "
                               "every interior vertex (subdivide first)", where, f, q2n_face_size(m, f));
            goto done;
        }
        q2n_v3_add(es + 3 * (size_t)a, es + 3 * (size_t)a, q2n_mesh_vpos(m, q2n_he_dest(m, h)));
        q2n_v3_add(ds + 3 * (size_t)a, ds + 3 * (size_t)a, q2n_mesh_vpos(m, q2n_he_dest(m, q2n_he_next(m, h))));
    }
    for (int v = 0; v < m->nv; v++) {
        const double *p = q2n_mesh_vpos(m, v), *E = es + 3 * (size_t)v, *D = ds + 3 * (size_t)v;
        double *r = pos + 3 * (size_t)v;
        if (m->vert_nfaces[v] == 0 || (m->vert_boundary[v] && m->vert_nfaces[v] == 1) ||
            (!m->vert_boundary[v] && m->valence[v] < 3)) {
            memcpy(r, p, 3 * sizeof *p); /* corners; an interior valence 2 is one for Sdc too */
        } else if (m->vert_boundary[v]) {
            for (int c = 0; c < 3; c++) r[c] = (E[c] + 4.0 * p[c]) / 6.0;
        } else {
            double n = m->valence[v];
            for (int c = 0; c < 3; c++) r[c] = (n * n * p[c] + 4.0 * E[c] + D[c]) / (n * (n + 5.0));
        }
    }
    st = q2n_mesh_from_arrays_lines(m->nv, pos, m->nf, m->face_start, m->face_vert, m->face_line, m->name, out, err);
done:
    free(pos);
    free(es);
    free(ds);
    return st;
}
