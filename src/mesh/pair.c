/* pair.c — triangles paired into quads across their shared edges (see mesh.h for the order of the
 * result).
 *
 * Why.  Many triangle meshes handed to us are quad meshes whose quads a tessellator or an
 * exporter cut along one diagonal: CAD tessellations (STL), the triangulated output of modellers,
 * surfaces of revolution sampled on a grid.  One Catmull–Clark step (--subdivide 1) turns each
 * triangle into three quads, makes every vertex extraordinary and, where the triangles are long
 * and thin, leaves needle quads with corners of a few degrees, from which no interpolating patch
 * stays regular (docs/mesh.md, "Pairing triangles").  Removing the diagonals instead gives the
 * quads back, and with them the mesh's own regular structure.
 *
 * How.  Every interior edge between two triangles (x, y, c) and (y, x, d) is a candidate; removing
 * it gives the quad (x, d, y, c), in the orientation of both.  A candidate is kept when the quad is
 * convex with a margin — every corner's sine, signed by the quad's vector area (Newell), at least
 * Q2N_PAIR_MIN_SINE — and the two triangles' normals lie within Q2N_PAIR_MAX_BEND of each other
 * (mesh_policy.h).  Candidates are taken best first (the largest smallest corner sine: rectangles
 * before rhombi before kites; ties by edge index, so the result does not depend on anything but
 * the mesh), each triangle at most once, and never so that an interior vertex is left with fewer
 * than three faces (two would share two edges and leave it no tangent plane): a greedy pass, which
 * on a triangulated quad grid finds every original quad (its diagonals are the only candidates whose
 * quads are rectangles); then augmenting paths (augment) pair most of what a general triangulation
 * leaves over.  Triangles left unpaired stay triangles. */
#include "mesh/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "mesh/mesh_policy.h"

typedef struct pair_cand {
    double q; /* smallest corner sine of the quad */
    int e;    /* the edge removed */
} pair_cand;

static int cand_cmp(const void *a, const void *b)
{
    const pair_cand *x = a, *y = b;
    if (x->q != y->q) return x->q > y->q ? -1 : 1;
    return (x->e > y->e) - (x->e < y->e);
}

/* Smallest signed corner sine of the quad q (vertex indices), signed by its vector area; -1 when
 * it has no area. */
static double quad_min_sine(const q2n_mesh *m, const int q[4])
{
    const double *p[4];
    double n[3] = {0, 0, 0}, c[3];
    for (int i = 0; i < 4; i++) p[i] = q2n_mesh_vpos(m, q[i]);
    for (int i = 0; i < 4; i++) {
        q2n_v3_cross(c, p[i], p[(i + 1) & 3]);
        q2n_v3_add(n, n, c);
    }
    double nn = q2n_v3_norm(n), s = 1;
    if (!(nn > 0)) return -1;
    for (int i = 0; i < 4; i++) {
        double si = q2n_v3_corner_sine(p[i], p[(i + 1) & 3], p[(i + 3) & 3], n, nn);
        if (si == -2) return -1;
        s = fmin(s, si);
    }
    return s;
}

/* Cosine of the angle between the normals of triangles (x, y, c) and (y, x, d). */
static double bend_cos(const q2n_mesh *m, int x, int y, int c, int d)
{
    double a[3], b[3], n1[3], n2[3];
    q2n_v3_sub(a, q2n_mesh_vpos(m, y), q2n_mesh_vpos(m, x));
    q2n_v3_sub(b, q2n_mesh_vpos(m, c), q2n_mesh_vpos(m, x));
    q2n_v3_cross(n1, a, b);
    q2n_v3_sub(a, q2n_mesh_vpos(m, x), q2n_mesh_vpos(m, y));
    q2n_v3_sub(b, q2n_mesh_vpos(m, d), q2n_mesh_vpos(m, y));
    q2n_v3_cross(n2, a, b);
    double l = q2n_v3_norm(n1) * q2n_v3_norm(n2);
    return l > 0 ? q2n_v3_dot(n1, n2) / l : -1;
}

/* The quad of edge e's two triangles, starting at the first corner of the lower-numbered one. */
static void edge_quad(const q2n_mesh *m, int e, int q[4])
{
    int h = m->edge_he[e], t = m->he_twin[h];
    int x = q2n_he_origin(m, h), y = q2n_he_dest(m, h);
    int c = q2n_he_origin(m, q2n_he_prev(m, h)), d = q2n_he_origin(m, q2n_he_prev(m, t));
    int r[4] = {x, d, y, c};
    int f = m->he_face[h] < m->he_face[t] ? m->he_face[h] : m->he_face[t];
    int first = m->face_vert[m->face_start[f]], k = 0;
    while (r[k] != first) k++;
    for (int i = 0; i < 4; i++) q[i] = r[(k + i) & 3];
}

/* Add d to the face count of both ends of each of the n edges (a pair takes one face from each). */
static void pair_counts(const q2n_mesh *m, int *vfaces, const int *edges, int n, int d)
{
    for (int k = 0; k < n; k++) {
        int h = m->edge_he[edges[k]];
        vfaces[q2n_he_origin(m, h)] += d, vfaces[q2n_he_dest(m, h)] += d;
    }
}

/* Would removing the pairs across old[0..no) and adding those across add[0..na) leave an interior
 * vertex with fewer than three faces?  (Each pair takes one face from both ends of its edge.) */
static int guard_fails(const q2n_mesh *m, const int *vfaces, const int *add, int na, const int *old, int no)
{
    int vx[4 * (Q2N_PAIR_AUG_DEPTH + 2)], dv[4 * (Q2N_PAIR_AUG_DEPTH + 2)], n = 0;
    for (int k = 0; k < na + no; k++) {
        int e = k < na ? add[k] : old[k - na], h = m->edge_he[e];
        int ends[2] = {q2n_he_origin(m, h), q2n_he_dest(m, h)};
        for (int j = 0; j < 2; j++) {
            int i = 0;
            while (i < n && vx[i] != ends[j]) i++;
            if (i == n) vx[n] = ends[j], dv[n++] = 0;
            dv[i] += k < na ? -1 : 1;
        }
    }
    for (int i = 0; i < n; i++)
        if (!m->vert_boundary[vx[i]] && vfaces[vx[i]] + dv[i] < 3 && dv[i] < 0) return 1;
    return 0;
}

/* Augmenting paths (Berge 1957): from a triangle left unpaired, a path through candidate edges
 * that alternates between an unpaired link and a pair, ending at another unpaired triangle, gives one
 * pair more when its links and pairs trade places.  Breadth first, at most Q2N_PAIR_AUG_DEPTH pairs
 * long (mesh_policy.h), the triangles in index order; a path that would leave an interior vertex two
 * faces is not taken.  Returns the pairs gained. */
static int augment(const q2n_mesh *m, const unsigned char *ok, int *mate, int *mate_e, int *vfaces, int *ws)
{
    int nf = m->nf, *prev = ws, *prev_e = ws + nf, *seen = ws + 2 * nf, *depth = ws + 3 * nf, *queue = ws + 4 * nf;
    int gained = 0;
    for (int f = 0; f < nf; f++) seen[f] = -1;
    for (int t = 0; t < nf; t++) {
        if (mate[t] >= 0 || q2n_face_size(m, t) != 3) continue;
        int qh = 0, qt = 0, end = -1;
        queue[qt++] = t, seen[t] = t, prev[t] = -1, depth[t] = 0;
        while (qh < qt && end < 0) {
            int a = queue[qh++];
            for (int h = m->face_start[a]; h < m->face_start[a + 1] && end < 0; h++) {
                int e = m->he_edge[h], tw = m->he_twin[h];
                if (!ok[e] || tw < 0) continue;
                int u = m->he_face[tw];
                if (seen[u] == t) continue;
                seen[u] = t, prev[u] = a, prev_e[u] = e;
                if (mate[u] < 0) { end = u; break; }
                int w = mate[u];
                if (seen[w] == t || depth[a] + 1 > Q2N_PAIR_AUG_DEPTH) continue;
                seen[w] = t, prev[w] = u, prev_e[w] = mate_e[u], depth[w] = depth[a] + 1;
                queue[qt++] = w;
            }
        }
        if (end < 0) continue;
        int add[Q2N_PAIR_AUG_DEPTH + 1], old[Q2N_PAIR_AUG_DEPTH], na = 0, no = 0;
        for (int u = end; u != t;) { /* u was reached from a over a link; a from its mate over their pair */
            int a = prev[u];
            add[na++] = prev_e[u];
            if (a == t) break;
            old[no++] = mate_e[a];
            u = prev[a];
        }
        if (guard_fails(m, vfaces, add, na, old, no)) continue;
        for (int u = end; u != t;) {
            int a = prev[u], e = prev_e[u], next = a == t ? t : prev[a];
            mate[u] = a, mate[a] = u, mate_e[u] = mate_e[a] = e;
            u = next;
        }
        pair_counts(m, vfaces, add, na, -1);
        pair_counts(m, vfaces, old, no, 1);
        gained++;
    }
    return gained;
}

/* The matching: mate[f] the triangle paired with f (-1: none), mate_e[f] the edge between them;
 * *np the pairs.  -1 when out of memory. */
static int pair_match(const q2n_mesh *m, int *mate, int *mate_e, int *np)
{
    pair_cand *cand = malloc(sizeof *cand * ((size_t)m->ne + 1));
    int *vfaces = malloc(sizeof(int) * ((size_t)m->nv + 1)), *ws = malloc(sizeof(int) * (5 * (size_t)m->nf + 1));
    unsigned char *ok = calloc((size_t)m->ne + 1, 1);
    if (!cand || !vfaces || !ws || !ok) {
        free(cand), free(vfaces), free(ws), free(ok);
        return -1;
    }
    int nc = 0;
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], t = m->he_twin[h];
        if (t < 0 || q2n_face_size(m, m->he_face[h]) != 3 || q2n_face_size(m, m->he_face[t]) != 3) continue;
        int x = q2n_he_origin(m, h), y = q2n_he_dest(m, h);
        int c = q2n_he_origin(m, q2n_he_prev(m, h)), d = q2n_he_origin(m, q2n_he_prev(m, t));
        if (c == d || bend_cos(m, x, y, c, d) < cos(Q2N_PAIR_MAX_BEND)) continue;
        int q[4] = {x, d, y, c};
        double s = quad_min_sine(m, q);
        if (s >= Q2N_PAIR_MIN_SINE) cand[nc].q = s, cand[nc].e = e, ok[e] = 1, nc++;
    }
    qsort(cand, (size_t)nc, sizeof *cand, cand_cmp);
    for (int f = 0; f < m->nf; f++) mate[f] = -1;
    for (int v = 0; v < m->nv; v++) vfaces[v] = m->vert_nfaces[v];
    *np = 0;
    for (int i = 0; i < nc; i++) {
        int e = cand[i].e, h = m->edge_he[e], a = m->he_face[h], b = m->he_face[m->he_twin[h]];
        if (mate[a] >= 0 || mate[b] >= 0 || guard_fails(m, vfaces, &e, 1, NULL, 0)) continue;
        mate[a] = b, mate[b] = a, mate_e[a] = mate_e[b] = e, ++*np;
        pair_counts(m, vfaces, &e, 1, -1);
    }
    *np += augment(m, ok, mate, mate_e, vfaces, ws);
    free(cand), free(vfaces), free(ws), free(ok);
    return 0;
}

int q2n_mesh_pair_count(const q2n_mesh *m, int *triangles)
{
    int *mate = malloc(sizeof(int) * ((size_t)m->nf + 1)), *mate_e = malloc(sizeof(int) * ((size_t)m->nf + 1)), np = -1;
    if (mate && mate_e && pair_match(m, mate, mate_e, &np)) np = -1;
    free(mate), free(mate_e);
    if (triangles) {
        *triangles = 0;
        for (int f = 0; f < m->nf; f++) *triangles += q2n_face_size(m, f) == 3;
    }
    return np;
}

q2n_status q2n_mesh_pair_triangles(const q2n_mesh *m, q2n_mesh **out, int *paired, int *left, q2n_error *err)
{
    *out = NULL;
    int *mate = malloc(sizeof(int) * ((size_t)m->nf + 1)), *mate_e = malloc(sizeof(int) * ((size_t)m->nf + 1));
    int *fs = malloc(sizeof(int) * ((size_t)m->nf + 1)), *fv = malloc(sizeof(int) * ((size_t)m->nh + 1));
    int *fl = malloc(sizeof(int) * ((size_t)m->nf + 1)), np = 0;
    if (!mate || !mate_e || !fs || !fv || !fl || pair_match(m, mate, mate_e, &np)) {
        free(mate), free(mate_e), free(fs), free(fv), free(fl);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory pairing triangles", m->name);
    }
    /* the quad takes the place of the lower-numbered triangle; the other one goes */
    int nf = 0, nfv = 0, ntri = 0;
    for (int f = 0; f < m->nf; f++) {
        if (mate[f] >= 0 && mate[f] < f) continue;
        fs[nf] = nfv;
        fl[nf] = m->face_line ? m->face_line[f] : 0;
        if (mate[f] >= 0) {
            edge_quad(m, mate_e[f], fv + nfv);
            nfv += 4;
        } else {
            int n = q2n_face_size(m, f);
            memcpy(fv + nfv, m->face_vert + m->face_start[f], sizeof(int) * (size_t)n);
            nfv += n;
            ntri += n == 3;
        }
        nf++;
    }
    fs[nf] = nfv;
    q2n_status st = q2n_mesh_from_arrays_lines(m->nv, m->pos, nf, fs, fv, m->face_line ? fl : NULL, m->name, out, err);
    free(mate), free(mate_e), free(fs), free(fv), free(fl);
    if (!st) {
        if (paired) *paired = np;
        if (left) *left = ntri;
    }
    return st;
}
