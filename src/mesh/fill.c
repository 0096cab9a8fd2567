/* fill.c — faces of an even number n >= 6 of sides filled with quads (see mesh.h for the order of
 * the result; docs/mesh.md, "Filling n-gons").
 *
 * Why.  A polygon modeller's cylinder or boss has n-gon caps.  One Catmull–Clark step (--subdivide
 * 1) splits an n-gon into n kites around a new vertex of valence n, whose sectors are 360°/n wide:
 * no polynomial patch per kite lets the surface stay fair there (a 40-gon cap pleats, one lobe per
 * kite: docs/extraordinary.md, "Found and not fixed"), and the step moves every other vertex of
 * the mesh to its limit point.  Filled instead, the cap has no vertex of high valence, its rim
 * vertices become regular, and every vertex of the mesh is still interpolated.
 *
 * How.  With a + b = n/2, the n-gon o_0 .. o_{n-1} gets an (a + 1) x (b + 1) grid of new vertices
 * g(i, j): its a x b quads, and a ring of n quads (o_{s+k}, o_{s+k+1}, r_{k+1}, r_k) between the
 * polygon and the grid's boundary r_0 .. r_{n-1} (counterclockwise in (i, j) from g(0, 0), as the
 * polygon runs), starting at the polygon's vertex s.  The grid's four corners are the only vertices
 * that are not regular: three faces each; the polygon's own vertices gain one face.  The new
 * vertices' positions are the discrete harmonic ones (each the mean of its neighbours, the polygon
 * fixed): a sparse SPD solve (core/sparse.h), which keeps a planar polygon's fill in its plane and,
 * for a convex planar polygon, is an embedding with convex faces (Tutte's theorem).  The shape a and
 * the start s are those whose fill has the largest smallest corner sine (signed by the polygon's
 * vector area): the balanced grid a = floor(n/4) on a round cap, a long thin grid in an elongated
 * slot (mesh_policy.h, Q2N_FILL_SEARCH_MAX, Q2N_FILL_TIE; a >= b and the start shifted by n/2 give
 * the same fills turned, so a <= n/4 and s < n/2 cover them all).  A polygon whose best fill still
 * has a corner that does not turn its way (a strongly non-convex or warped polygon) is refused. */
#include "mesh/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/sparse.h"
#include "core/vec3.h"
#include "mesh/mesh_policy.h"

/* Does face f get filled? */
static int fillable(const q2n_mesh *m, int f)
{
    int n = q2n_face_size(m, f);
    return n >= 6 && n % 2 == 0;
}

/* Grid vertex (i, j) of a fill whose first new vertex is g0: (a + 1) x (b + 1), i fastest. */
static int grid_at(int g0, int a, int i, int j) { return g0 + j * (a + 1) + i; }

/* The grid's boundary in the polygon's turning sense: (i, j) of its k-th vertex, k in 0..n-1. */
static void ring_ij(int a, int b, int k, int *i, int *j)
{
    if (k < a) *i = k, *j = 0;
    else if ((k -= a) < b) *i = a, *j = k;
    else if ((k -= b) < a) *i = a - k, *j = b;
    else *i = 0, *j = b - (k - a);
}

/* The quads of the fill of polygon o (n vertices; grid a x (n/2 - a) cells, ring from o_s; new
 * vertices from g0) into fv, 4 per quad: the ring (quad k starts at o_{s+k}), then the grid row by
 * row.  Returns the quads written. */
static int fill_quads(const int *o, int n, int a, int s, int g0, int *fv)
{
    int b = n / 2 - a, q = 0;
    for (int k = 0; k < n; k++) {
        int i0, j0, i1, j1;
        ring_ij(a, b, k, &i0, &j0);
        ring_ij(a, b, (k + 1) % n, &i1, &j1);
        int *Q = fv + 4 * q++;
        Q[0] = o[(s + k) % n], Q[1] = o[(s + k + 1) % n], Q[2] = grid_at(g0, a, i1, j1), Q[3] = grid_at(g0, a, i0, j0);
    }
    for (int j = 0; j < b; j++)
        for (int i = 0; i < a; i++) {
            int *Q = fv + 4 * q++;
            Q[0] = grid_at(g0, a, i, j), Q[1] = grid_at(g0, a, i + 1, j), Q[2] = grid_at(g0, a, i + 1, j + 1),
            Q[3] = grid_at(g0, a, i, j + 1);
        }
    return q;
}

/* Harmonic positions of the fill's new vertices (pos, 3 per vertex, from g0; the polygon's are set;
 * the new ones written there):
 * L x = (sum of the fixed neighbours) for every new vertex, L the graph Laplacian of the quads' edges
 * restricted to the new vertices. */
static q2n_status harmonic(const int *fv, int nq, int g0, int ng, double *pos, q2n_error *err)
{
    /* every edge of the fill once: each quad's four sides, an edge shared by two quads counted by
     * the one that runs it from lower to higher index (the other runs it backwards); the ring's
     * outer sides (between polygon vertices) join no new vertex */
    long cap = 4L * nq + ng, nt = 0;
    int *ti = malloc(sizeof(int) * (size_t)cap), *tj = malloc(sizeof(int) * (size_t)cap);
    double *tv = malloc(sizeof(double) * (size_t)cap), *rhs = calloc(3 * (size_t)ng, sizeof(double));
    double *deg = calloc((size_t)ng, sizeof(double));
    q2n_status st = Q2N_OK;
    if (!ti || !tj || !tv || !rhs || !deg) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory filling a face"); goto done; }
    for (int q = 0; q < nq; q++)
        for (int c = 0; c < 4; c++) {
            int x = fv[4 * q + c], y = fv[4 * q + (c + 1) % 4];
            int inner = x >= g0 && y >= g0;
            /* inner edges are run once each way (each by one quad); count the forward one only.
             * Edges with a polygon vertex belong to one quad each (the ring's radial sides are shared
             * by two ring quads, in opposite directions): count the one leaving the polygon vertex */
            if (inner ? x > y : !(x < g0 && y >= g0)) continue;
            int u = inner ? x : y, w = inner ? y : x; /* u new; w new (inner) or on the polygon */
            deg[u - g0] += 1;
            if (inner) {
                deg[w - g0] += 1;
                ti[nt] = (u < w ? u : w) - g0, tj[nt] = (u < w ? w : u) - g0, tv[nt++] = -1;
            } else
                for (int d = 0; d < 3; d++) rhs[(size_t)d * ng + (u - g0)] += pos[3 * (size_t)w + d];
        }
    for (int k = 0; k < ng; k++) ti[nt] = tj[nt] = k, tv[nt++] = deg[k];
    st = q2n_sparse_spd_solve(ng, nt, ti, tj, tv, 3, rhs, rhs, err);
    if (!st)
        for (int k = 0; k < ng; k++)
            for (int d = 0; d < 3; d++) pos[3 * (size_t)(g0 + k) + d] = rhs[(size_t)d * ng + k];
done:
    free(ti), free(tj), free(tv), free(rhs), free(deg);
    return st;
}

/* The smallest sine over the corners of the quads, signed by the polygon's unit normal N (negative:
 * a corner turning against the polygon; -2 for a degenerate corner). */
static double fill_quality(const int *fv, int nq, const double *pos, const double N[3])
{
    double worst = 1;
    for (int q = 0; q < nq; q++)
        for (int c = 0; c < 4; c++) {
            const double *p = pos + 3 * (size_t)fv[4 * q + c], *pn = pos + 3 * (size_t)fv[4 * q + (c + 1) % 4],
                         *pp = pos + 3 * (size_t)fv[4 * q + (c + 3) % 4];
            double e1[3], e2[3], x[3], l = 0;
            q2n_v3_sub(e1, pn, p);
            q2n_v3_sub(e2, pp, p);
            q2n_v3_cross(x, e1, e2);
            l = q2n_v3_norm(e1) * q2n_v3_norm(e2);
            double sn = l > 0 ? q2n_v3_dot(x, N) / l : -2;
            if (!(sn >= worst)) worst = isfinite(sn) ? sn : -2;
        }
    return worst;
}

int q2n_mesh_fill_count(const q2n_mesh *m)
{
    int k = 0;
    for (int f = 0; f < m->nf; f++) k += fillable(m, f);
    return k;
}

q2n_status q2n_mesh_fill_ngons(const q2n_mesh *m, q2n_mesh **out, int *filled, int *quads, q2n_error *err)
{
    *out = NULL;
    long nv = m->nv, nf = 0, nfv = 0;
    for (int f = 0; f < m->nf; f++) {
        int n = q2n_face_size(m, f);
        if (fillable(m, f)) {
            long a = n / 4, b = n / 2 - a;
            nv += (a + 1) * (b + 1), nf += n + a * b, nfv += 4 * (n + a * b);
        } else
            nf++, nfv += n;
    }
    if (nv > 0x3fffffff || nfv > 0x3fffffff)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: filling its faces would give too many vertices", m->name);
    double *pos = malloc(sizeof(double) * 3 * (size_t)nv);
    int *fs = malloc(sizeof(int) * ((size_t)nf + 1)), *fv = malloc(sizeof(int) * ((size_t)nfv + 1));
    int *fl = malloc(sizeof(int) * ((size_t)nf + 1));
    q2n_status st = Q2N_OK;
    int nfill = 0, nquads = 0;
    if (!pos || !fs || !fv || !fl) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory filling faces", m->name); goto done; }
    memcpy(pos, m->pos, sizeof(double) * 3 * (size_t)m->nv);
    int g0 = m->nv, k = 0, w = 0;
    for (int f = 0; f < m->nf; f++) {
        int n = q2n_face_size(m, f), line = m->face_line ? m->face_line[f] : 0;
        const int *o = m->face_vert + m->face_start[f];
        if (!fillable(m, f)) {
            fs[k] = w, fl[k++] = line;
            memcpy(fv + w, o, sizeof(int) * (size_t)n);
            w += n;
            continue;
        }
        double N[3] = {0, 0, 0}; /* vector area (Newell), unit */
        for (int c = 0; c < n; c++) {
            double x[3];
            q2n_v3_cross(x, q2n_mesh_vpos(m, o[c]), q2n_mesh_vpos(m, o[(c + 1) % n]));
            for (int d = 0; d < 3; d++) N[d] += x[d];
        }
        double nn = q2n_v3_norm(N);
        for (int d = 0; d < 3; d++) N[d] = nn > 0 ? N[d] / nn : 0;
        /* the shapes and starts, balanced grid from vertex 0 first; the best fill ends in fv + w and
         * pos (rebuilt when a later candidate was the last one tried) */
        int amax = n / 4, best_a = amax, best_s = 0, last_a = -1, last_s = -1;
        double best = -3;
        for (int a = amax; a >= 1; a--)
            for (int s0 = 0; s0 < n / 2; s0++) {
                if (n > Q2N_FILL_SEARCH_MAX && (a != amax || s0 != 0)) continue;
                int ng = (a + 1) * (n / 2 - a + 1), nq = fill_quads(o, n, a, s0, g0, fv + w);
                if ((st = harmonic(fv + w, nq, g0, ng, pos, err))) goto done;
                last_a = a, last_s = s0;
                double qv = fill_quality(fv + w, nq, pos, N);
                if (qv > best + Q2N_FILL_TIE * fabs(best)) best = qv, best_a = a, best_s = s0;
            }
        int a = best_a, b = n / 2 - a, ng = (a + 1) * (b + 1), nq = fill_quads(o, n, a, best_s, g0, fv + w);
        if ((last_a != a || last_s != best_s) && (st = harmonic(fv + w, nq, g0, ng, pos, err))) goto done;
        if (!(best > 0)) {
            char at[300];
            if (line > 0) snprintf(at, sizeof at, "%s:%d", m->name, line);
            else snprintf(at, sizeof at, "%s", m->name);
            st = q2n_error_set(err, Q2N_ERR_GEOMETRY,
                               "%s: face %d (%d vertices) cannot be filled with quads that all turn its way (strongly "
                               "non-convex or warped); use --subdivide 1 instead of --fill-ngons",
                               at, f, n);
            goto done;
        }
        for (int q = 0; q < nq; q++) fs[k] = w + 4 * q, fl[k++] = line;
        w += 4 * nq;
        g0 += ng;
        nfill++, nquads += nq;
    }
    fs[k] = w;
    /* (nv and nf counted balanced grids, the most vertices and quads a fill can have; g0 and k are
     * what the chosen ones have) */
    st = q2n_mesh_from_arrays_lines(g0, pos, k, fs, fv, m->face_line ? fl : NULL, m->name, out, err);
    if (!st) {
        if (filled) *filled = nfill;
        if (quads) *quads = nquads;
    }
done:
    free(pos), free(fs), free(fv), free(fl);
    return st;
}
