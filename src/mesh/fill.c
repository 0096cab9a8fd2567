/* fill.c — polygons of 5 or more sides filled with quads (see mesh.h for the order of the result;
 * docs/mesh.md, "Filling n-gons").
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
 * has a corner that does not turn its way (a strongly non-convex polygon: an L, a U) is split along
 * a chord from a reflex corner into two even polygons filled the same way (fill_poly); one that
 * still does not fill (a star, a warped polygon) is refused.
 *
 * Odd polygons.  A quad mesh of a disk has an even boundary, so an odd polygon cannot be filled on
 * its own; but a strip of quads from one odd polygon to another (entered through an edge, left
 * through the opposite one) can give each a vertex more: a vertex on every edge the strip crosses,
 * each strip quad split in two across it.  The new vertices are regular (four faces each), and
 * they sit where the four-point rule puts them, on a smooth curve through the mesh line, not on the
 * chord.  Polygons are paired fewest partners first, each with the nearest free odd polygon along a
 * strip; a polygon without one is left as it is (and needs --subdivide). */
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

/* Harmonic positions of the new vertices of the fills of shape a (grid a x (n/2 - a) cells) of
 * polygon o, one fill per start in starts[0 .. ns - 1]: L x = (sum of the fixed neighbours) for
 * every new vertex, L the graph Laplacian of the fill's edges restricted to the new vertices.  L
 * depends on the shape only (the ring joins its k-th boundary vertex r_k to the polygon's vertex
 * o_{s+k}, whatever s is), so one factorisation serves every start: X gets 3 columns per start
 * (x, y, z; column-major, ng rows, the grid's vertices in grid_at order from 0). */
static q2n_status harmonic(const int *o, int n, int a, const double *pos, int ns, const int *starts, double *X,
                           q2n_error *err)
{
    int b = n / 2 - a, ng = (a + 1) * (b + 1);
    long cap = 2L * a * b + a + b + ng, nt = 0;
    int *ti = malloc(sizeof(int) * (size_t)cap), *tj = malloc(sizeof(int) * (size_t)cap);
    double *tv = malloc(sizeof(double) * (size_t)cap), *deg = calloc((size_t)ng, sizeof(double));
    q2n_status st = Q2N_OK;
    if (!ti || !tj || !tv || !deg) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory filling a face"); goto done; }
    for (int j = 0; j <= b; j++) /* the grid's edges, each once */
        for (int i = 0; i <= a; i++) {
            int u = grid_at(0, a, i, j);
            if (i < a) ti[nt] = u, tj[nt] = grid_at(0, a, i + 1, j), tv[nt++] = -1, deg[u] += 1, deg[u + 1] += 1;
            if (j < b) ti[nt] = u, tj[nt] = grid_at(0, a, i, j + 1), tv[nt++] = -1, deg[u] += 1, deg[grid_at(0, a, i, j + 1)] += 1;
        }
    memset(X, 0, sizeof(double) * 3 * (size_t)ns * (size_t)ng);
    for (int k = 0; k < n; k++) { /* the ring's radial edges: r_k to o_{s+k} */
        int i, j;
        ring_ij(a, b, k, &i, &j);
        int u = grid_at(0, a, i, j);
        deg[u] += 1;
        for (int t = 0; t < ns; t++)
            for (int d = 0; d < 3; d++)
                X[(size_t)(3 * t + d) * ng + u] += pos[3 * (size_t)o[(starts[t] + k) % n] + d];
    }
    for (int k = 0; k < ng; k++) ti[nt] = tj[nt] = k, tv[nt++] = deg[k];
    st = q2n_sparse_spd_solve(ng, nt, ti, tj, tv, 3 * ns, X, X, err);
done:
    free(ti), free(tj), free(tv), free(deg);
    return st;
}

/* Column t of harmonic()'s X into pos (the new vertices from g0). */
static void fill_place(const double *X, int ng, int t, int g0, double *pos)
{
    for (int k = 0; k < ng; k++)
        for (int d = 0; d < 3; d++) pos[3 * (size_t)(g0 + k) + d] = X[(size_t)(3 * t + d) * ng + k];
}

/* The smallest sine over the corners of the quads, signed by the polygon's unit normal N (negative:
 * a corner turning against the polygon; -2 for a degenerate corner). */
static double fill_quality(const int *fv, int nq, const double *pos, const double N[3])
{
    double worst = 1;
    for (int q = 0; q < nq; q++)
        for (int c = 0; c < 4; c++) {
            const int *Q = fv + 4 * q;
            double sn = q2n_v3_corner_sine(pos + 3 * (size_t)Q[c], pos + 3 * (size_t)Q[(c + 1) % 4],
                                           pos + 3 * (size_t)Q[(c + 3) % 4], N, 1.0);
            if (!(sn >= worst)) worst = isfinite(sn) ? sn : -2;
        }
    return worst;
}

/* ------------------------------------------------------------------ odd polygons in pairs */

/* Is face f an odd polygon that a strip may make even (5 sides or more: a triangle with one more
 * vertex would be a quad with a straight corner)? */
static int odd_polygon(const q2n_mesh *m, int f)
{
    int n = q2n_face_size(m, f);
    return n >= 5 && n % 2 == 1;
}

/* The strip from odd polygon f across its half-edge h: quads entered through an edge and left
 * through the opposite one, until a face that is not a quad.  Returns the number of quads (their
 * entry half-edges in path[], at most cap) when that face is another odd polygon not yet paired
 * and no quad is used twice (used[] marks quads of earlier strips; walk[] is scratch, all 0 on
 * entry and on return), with its half-edge on the strip in *hend; -1 otherwise. */
static int strip(const q2n_mesh *m, int f, int h, const char *paired, const char *used, char *walk, int *path, int cap,
                 int *hend)
{
    int len = -1, np = 0, t = m->he_twin[h];
    while (t >= 0) {
        int g = m->he_face[t];
        if (q2n_face_size(m, g) != 4) {
            if (g != f && odd_polygon(m, g) && !paired[g]) len = np, *hend = t;
            break;
        }
        if (used[g] || walk[g] || np >= cap) break;
        walk[g] = 1;
        path[np++] = t;
        t = m->he_twin[m->face_start[g] + (t - m->face_start[g] + 2) % 4];
    }
    for (int q = 0; q < np; q++) walk[m->he_face[path[q]]] = 0;
    return len;
}

/* Odd polygon and how many others its strips reach, for pair_odd's order. */
typedef struct odd_rank { int f, reach; } odd_rank;

static int odd_rank_cmp(const void *a, const void *b)
{
    const odd_rank *x = a, *y = b;
    return x->reach != y->reach ? (x->reach > y->reach) - (x->reach < y->reach) : (x->f > y->f) - (x->f < y->f);
}

/* Odd polygons paired by strips: those with the fewest partners within reach first (ties: face
 * order), each with the odd polygon the shortest strip from it reaches (ties: its first edge).  In
 * face order alone a chain A-B-C-D listed B, C first paired B with C and left A and D without a
 * partner; the polygons with one partner going first pair a chain, a tree or two caps completely.
 * pair_he[f]: for a paired polygon, its half-edge on the strip (-1 otherwise); crossed[h] = 1 on
 * both half-edges of every edge a strip crosses, the entry half-edge of each strip quad in entry[q]
 * (-1 for other faces).  Returns the strips found, -1 out of memory. */
static int pair_odd(const q2n_mesh *m, int *pair_he, char *crossed, int *entry)
{
    char *paired = calloc((size_t)m->nf + 1, 1), *used = calloc((size_t)m->nf + 1, 1), *walk = calloc((size_t)m->nf + 1, 1);
    int *path = malloc(sizeof(int) * ((size_t)m->nf + 1)), *best = malloc(sizeof(int) * ((size_t)m->nf + 1)), n = 0;
    if (!paired || !used || !walk || !path || !best) n = -1;
    for (int f = 0; f < m->nf; f++) pair_he[f] = -1, entry[f] = -1;
    int nodd = 0, *seen = calloc((size_t)m->nf + 1, sizeof(int));
    odd_rank *order = malloc(sizeof(odd_rank) * ((size_t)m->nf + 1));
    if (!seen || !order) n = -1;
    for (int f = 0; f < m->nf && n >= 0; f++) { /* how many partners each odd polygon's strips reach */
        if (!odd_polygon(m, f)) continue;
        int reach = 0;
        for (int i = 0; i < q2n_face_size(m, f); i++) {
            int hend = -1;
            if (strip(m, f, m->face_start[f] + i, paired, used, walk, path, m->nf, &hend) < 0) continue;
            int g = m->he_face[hend];
            if (seen[g] != f + 1) seen[g] = f + 1, reach++;
        }
        order[nodd].f = f, order[nodd++].reach = reach;
    }
    if (n >= 0) qsort(order, (size_t)nodd, sizeof *order, odd_rank_cmp);
    for (int k = 0; k < nodd && n >= 0; k++) {
        int f = order[k].f;
        if (paired[f]) continue;
        int blen = -1, bh = -1, bend = -1;
        for (int i = 0; i < q2n_face_size(m, f); i++) {
            int h = m->face_start[f] + i, hend = -1;
            int len = strip(m, f, h, paired, used, walk, path, m->nf, &hend);
            if (len >= 0 && (blen < 0 || len < blen)) {
                blen = len, bh = h, bend = hend;
                memcpy(best, path, sizeof(int) * (size_t)len);
            }
        }
        if (blen < 0) continue;
        int g = m->he_face[bend];
        paired[f] = paired[g] = 1;
        pair_he[f] = bh, pair_he[g] = bend;
        crossed[bh] = 1, crossed[m->he_twin[bh]] = 1;
        for (int q = 0; q < blen; q++) {
            int t = best[q], k = m->he_face[t], x = m->face_start[k] + (t - m->face_start[k] + 2) % 4;
            used[k] = 1, entry[k] = t;
            crossed[x] = 1, crossed[m->he_twin[x]] = 1;
        }
        n++;
    }
    free(paired), free(used), free(walk), free(path), free(best), free(seen), free(order);
    return n;
}

/* Face f's unit normal (its vector area's direction; 0 for a face of no area) into N; the area's
 * length is returned. */
static double unit_normal(const q2n_mesh *m, int f, double N[3])
{
    q2n_mesh_face_area(m, f, N);
    double nn = q2n_v3_norm(N);
    for (int d = 0; d < 3; d++) N[d] = nn > 0 ? N[d] / nn : 0;
    return nn;
}

/* Is face f a planar polygon of 5 sides or more (its vertices within Q2N_FILL_PLANAR_REL of their
 * largest distance from the centroid of the plane through the centroid normal to its vector area)?
 * Then its unit normal N and offset (N . x = off on the plane). */
static int polygon_plane(const q2n_mesh *m, int f, double N[3], double *off)
{
    int n = q2n_face_size(m, f);
    if (n < 5) return 0;
    const int *fv = m->face_vert + m->face_start[f];
    double c[3] = {0, 0, 0}, dev = 0, size = 0;
    if (!(unit_normal(m, f, N) > 0)) return 0;
    for (int k = 0; k < n; k++) q2n_v3_axpy(c, 1.0 / n, q2n_mesh_vpos(m, fv[k]));
    for (int k = 0; k < n; k++) {
        double r[3];
        q2n_v3_sub(r, q2n_mesh_vpos(m, fv[k]), c);
        dev = fmax(dev, fabs(q2n_v3_dot(r, N))), size = fmax(size, q2n_v3_norm(r));
    }
    *off = q2n_v3_dot(N, c);
    return dev <= Q2N_FILL_PLANAR_REL * size;
}

/* Where the vertex on the edge of half-edge h goes: the four-point rule (-p0 + 9 p1 + 9 p2 - p3) / 16
 * along the mesh line through the edge (Dyn, Levin and Gregory's interpolatory scheme: a point of
 * a smooth curve through the line's vertices, where the midpoint would cut the chord: 1 - cos(pi/n)
 * inside a round n-gon's rim), the line continuing straight through valence-4 vertices, else along
 * polygon f's boundary when h is one of its half-edges; the midpoint where the line ends.  On the
 * edge of planar polygons the point is then projected into their planes. */
static void edge_point(const q2n_mesh *m, int h, int f, double *out)
{
    int v1 = q2n_he_origin(m, h), v2 = q2n_he_dest(m, h), v0 = -1, v3 = -1, t = m->he_twin[h];
    int g = q2n_mesh_continue(m, h), g0 = t >= 0 ? q2n_mesh_continue(m, t) : -1;
    if (g >= 0) v3 = q2n_he_dest(m, g);
    if (g0 >= 0) v0 = q2n_he_dest(m, g0);
    if (f >= 0 && (v0 < 0 || v3 < 0)) {
        int n = q2n_face_size(m, f), i = h - m->face_start[f];
        if (i >= 0 && i < n) {
            v0 = m->face_vert[m->face_start[f] + (i + n - 1) % n];
            v3 = m->face_vert[m->face_start[f] + (i + 2) % n];
        }
    }
    const double *p1 = q2n_mesh_vpos(m, v1), *p2 = q2n_mesh_vpos(m, v2);
    for (int d = 0; d < 3; d++) out[d] = 0.5 * (p1[d] + p2[d]);
    if (v0 < 0 || v3 < 0 || v0 == v2 || v3 == v1) return;
    const double *p0 = q2n_mesh_vpos(m, v0), *p3 = q2n_mesh_vpos(m, v3);
    for (int d = 0; d < 3; d++) out[d] = (-p0[d] + 9 * p1[d] + 9 * p2[d] - p3[d]) / 16;
    /* on the edge of planar polygons (5 sides or more) the point stays in their planes: where the
     * line bends round a sharp edge of the part (a box's), the four-point rule bulges out of the
     * faces there, and a polygon's fill would warp (new vertices 1.6 % of the diagonal off a cube's
     * face); on two polygons, onto the line where their planes meet */
    double N[2][3], off[2];
    int np = 0;
    for (int side = 0; side < 2; side++) {
        int hh = side ? t : h;
        if (hh >= 0 && polygon_plane(m, m->he_face[hh], N[np], &off[np])) np++;
    }
    if (np == 2) {
        double c = q2n_v3_dot(N[0], N[1]), det = 1 - c * c;
        double r0 = q2n_v3_dot(N[0], out) - off[0], r1 = q2n_v3_dot(N[1], out) - off[1];
        if (det > 1e-12) { /* x - a N0 - b N1 in both planes (else parallel: the same plane twice) */
            double al = (r0 - c * r1) / det, be = (r1 - c * r0) / det;
            q2n_v3_axpy(out, -al, N[0]);
            q2n_v3_axpy(out, -be, N[1]);
            return;
        }
        np = 1; /* the same plane twice */
    }
    if (np == 1) q2n_v3_axpy(out, -(q2n_v3_dot(N[0], out) - off[0]), N[0]);
}

/* pair_odd's result with its arrays (odd_plan_make; n < 0: out of memory). */
typedef struct odd_plan {
    int *pair_he, *entry;
    char *crossed;
    int n;
} odd_plan;

static odd_plan odd_plan_make(const q2n_mesh *m)
{
    odd_plan P = {malloc(sizeof(int) * ((size_t)m->nf + 1)), malloc(sizeof(int) * ((size_t)m->nf + 1)),
                  calloc((size_t)m->nh + 1, 1), -1};
    if (P.pair_he && P.entry && P.crossed) P.n = pair_odd(m, P.pair_he, P.crossed, P.entry);
    return P;
}

static void odd_plan_free(odd_plan *P) { free(P->pair_he), free(P->entry), free(P->crossed); }

/* The odd polygons paired by strips made even: a vertex on every edge a strip crosses, each strip
 * quad split in two across it, each polygon one vertex more.  *out is NULL when no strip was found. */
static q2n_status split_strips(const q2n_mesh *m, q2n_mesh **out, q2n_error *err)
{
    *out = NULL;
    odd_plan P = odd_plan_make(m);
    int *pair_he = P.pair_he, *entry = P.entry, *vat = malloc(sizeof(int) * ((size_t)m->nh + 1));
    char *crossed = P.crossed;
    double *pos = NULL;
    int *fs = NULL, *fv = NULL, *fl = NULL;
    q2n_status st = Q2N_OK;
    if (P.n < 0 || !vat) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory filling faces", m->name); goto done; }
    if (P.n == 0) goto done;
    int nnew = 0, nf = m->nf, nfv = m->nh;
    for (int h = 0; h < m->nh; h++) vat[h] = -1;
    for (int h = 0; h < m->nh; h++)
        if (crossed[h] && vat[h] < 0) vat[h] = vat[m->he_twin[h]] = m->nv + nnew++;
    for (int f = 0; f < m->nf; f++) {
        if (entry[f] >= 0) nf++, nfv += 4;
        if (pair_he[f] >= 0) nfv++;
    }
    pos = malloc(sizeof(double) * 3 * ((size_t)m->nv + nnew));
    fs = malloc(sizeof(int) * ((size_t)nf + 1)), fv = malloc(sizeof(int) * ((size_t)nfv + 1)), fl = malloc(sizeof(int) * ((size_t)nf + 1));
    if (!pos || !fs || !fv || !fl) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory filling faces", m->name); goto done; }
    memcpy(pos, m->pos, sizeof(double) * 3 * (size_t)m->nv);
    /* each new vertex once: on a polygon's edge from the polygon's half-edge (its boundary is the
     * line where the mesh's ends), elsewhere from either */
    char *done = calloc((size_t)nnew + 1, 1);
    if (!done) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory filling faces", m->name); goto done; }
    for (int f = 0; f < m->nf; f++)
        if (pair_he[f] >= 0 && !done[vat[pair_he[f]] - m->nv]) {
            edge_point(m, pair_he[f], f, pos + 3 * (size_t)vat[pair_he[f]]);
            done[vat[pair_he[f]] - m->nv] = 1;
        }
    for (int h = 0; h < m->nh; h++)
        if (crossed[h] && !done[vat[h] - m->nv]) {
            edge_point(m, h, -1, pos + 3 * (size_t)vat[h]);
            done[vat[h] - m->nv] = 1;
        }
    free(done);
    int k = 0, w = 0;
    for (int f = 0; f < m->nf; f++) {
        const int *v = m->face_vert + m->face_start[f];
        int n = q2n_face_size(m, f), line = m->face_line ? m->face_line[f] : 0;
        if (entry[f] >= 0) { /* quad (q_a, q_a+1, q_a+2, q_a+3) entered at q_a -> q_a+1 */
            int a = entry[f] - m->face_start[f], mi = vat[entry[f]], mo = vat[m->face_start[f] + (a + 2) % 4];
            int q0 = v[a], q1 = v[(a + 1) % 4], q2 = v[(a + 2) % 4], q3 = v[(a + 3) % 4];
            fs[k] = w, fl[k++] = line;
            fv[w++] = q0, fv[w++] = mi, fv[w++] = mo, fv[w++] = q3;
            fs[k] = w, fl[k++] = line;
            fv[w++] = mi, fv[w++] = q1, fv[w++] = q2, fv[w++] = mo;
            continue;
        }
        fs[k] = w, fl[k++] = line;
        for (int i = 0; i < n; i++) {
            fv[w++] = v[i];
            if (m->face_start[f] + i == pair_he[f]) fv[w++] = vat[pair_he[f]];
        }
    }
    fs[k] = w;
    st = q2n_mesh_from_arrays_lines(m->nv + nnew, pos, k, fs, fv, m->face_line ? fl : NULL, m->name, out, err);
done:
    odd_plan_free(&P);
    free(vat), free(pos), free(fs), free(fv), free(fl);
    return st;
}

/* ------------------------------------------------------------------ the fill */

static q2n_status fill_even(const q2n_mesh *m, q2n_mesh **out, int *filled, int *quads, q2n_error *err);

int q2n_mesh_fill_count(const q2n_mesh *m, int min_sides)
{
    odd_plan P = odd_plan_make(m);
    int k = 0;
    for (int f = 0; f < m->nf; f++)
        k += q2n_face_size(m, f) >= min_sides && (fillable(m, f) || (P.n > 0 && P.pair_he[f] >= 0));
    odd_plan_free(&P);
    return k;
}

q2n_status q2n_mesh_fill_ngons(const q2n_mesh *m, q2n_mesh **out, int *filled, int *quads, q2n_error *err)
{
    *out = NULL;
    q2n_mesh *even = NULL;
    q2n_status st = split_strips(m, &even, err);
    if (st) return st;
    st = fill_even(even ? even : m, out, filled, quads, err);
    q2n_mesh_free(even);
    return st;
}

/* One polygon's search for the best fill: its inputs, scratch and the best so far. */
typedef struct fill_search {
    const int *o;
    int n, g0;
    const double *N;
    double *pos;
    int *fv;
    double *X;
    int *starts;
    double best;
    int best_a, best_s;
} fill_search;

/* Try the shapes a = a_hi, a_hi - da, ... down to a_lo and, for each, the starts s0, s0 + ds, ...
 * (count of them: ns_total; taken modulo n/2, where the start shifted by n/2 gives the same fill
 * turned), keeping the best by the smallest corner sine (a later candidate must beat it by
 * Q2N_FILL_TIE).  Each shape's fills share one factorisation, Q2N_FILL_BATCH starts at a time. */
static q2n_status search(fill_search *S, int a_hi, int a_lo, int da, int s0, int ns_total, int ds, q2n_error *err)
{
    int n = S->n, h = n / 2;
    for (int a = a_hi; a >= a_lo; a -= da) {
        int ng = (a + 1) * (h - a + 1);
        for (int t0 = 0; t0 < ns_total; t0 += Q2N_FILL_BATCH) {
            int ns = 0;
            for (int t = t0; t < ns_total && ns < Q2N_FILL_BATCH; t++) S->starts[ns++] = ((s0 + t * ds) % h + h) % h;
            q2n_status st = harmonic(S->o, n, a, S->pos, ns, S->starts, S->X, err);
            if (st) return st;
            for (int t = 0; t < ns; t++) {
                int nq = fill_quads(S->o, n, a, S->starts[t], S->g0, S->fv);
                fill_place(S->X, ng, t, S->g0, S->pos);
                double qv = fill_quality(S->fv, nq, S->pos, S->N);
                if (qv > S->best + Q2N_FILL_TIE * fabs(S->best)) S->best = qv, S->best_a = a, S->best_s = S->starts[t];
            }
        }
    }
    return Q2N_OK;
}

/* A polygon's fill being built: the output arrays, where its next quad and new vertex go, its unit
 * normal and the searches' scratch. */
typedef struct fill_ctx {
    double *pos;
    int *fv;
    double *X;
    int *starts;
    const double *N;
    int w, g0;
} fill_ctx;

/* The ring and grid of polygon o (n even, >= 6): the best shape and start (search) in *a, *s, its
 * smallest corner sine in *quality. */
static q2n_status ring_grid(fill_ctx *C, const int *o, int n, double *quality, int *a, int *s, q2n_error *err)
{
    /* the shapes and starts, balanced grid from vertex 0 first (ties keep the first): all of them up
     * to Q2N_FILL_SEARCH_MAX sides, else a coarse lattice of them, then every shape and every start
     * within a lattice step of the best */
    fill_search S = {o, n, C->g0, C->N, C->pos, C->fv + C->w, C->X, C->starts, -3, n / 4, 0};
    int amax = n / 4, h = n / 2;
    q2n_status st;
    if (n <= Q2N_FILL_SEARCH_MAX) st = search(&S, amax, 1, 1, 0, h, 1, err);
    else {
        int da = (amax + Q2N_FILL_COARSE - 1) / Q2N_FILL_COARSE, ds = (h + Q2N_FILL_COARSE - 1) / Q2N_FILL_COARSE;
        st = search(&S, amax, 1, da, 0, (h + ds - 1) / ds, ds, err);
        int ca = S.best_a; /* then the shapes between the lattice's, at the best start, */
        if (!st) st = search(&S, ca + da - 1 < amax ? ca + da - 1 : amax, ca - da + 1 > 1 ? ca - da + 1 : 1, 1, S.best_s, 1, 1, err);
        int cs = S.best_s; /* and the starts between, with the best shape */
        if (!st) st = search(&S, S.best_a, S.best_a, 1, cs - ds + 1, 2 * ds - 1, 1, err);
    }
    *quality = S.best, *a = S.best_a, *s = S.best_s;
    return st;
}

/* Write the ring and grid of shape a from start s of polygon o at C->w and C->g0 (both advanced);
 * its quads in *nq. */
static q2n_status ring_grid_write(fill_ctx *C, const int *o, int n, int a, int s, int *nq, q2n_error *err)
{
    int ng = (a + 1) * (n / 2 - a + 1);
    *nq = fill_quads(o, n, a, s, C->g0, C->fv + C->w);
    q2n_status st = harmonic(o, n, a, C->pos, 1, &s, C->X, err);
    if (st) return st;
    fill_place(C->X, ng, 0, C->g0, C->pos);
    C->w += 4 * *nq, C->g0 += ng;
    return Q2N_OK;
}

/* Does the chord o_i o_j lie inside polygon o (n vertices), seen along the unit normal N: it crosses
 * no side (other than at o_i, o_j) and its midpoint is inside (winding number)? */
static int chord_inside(const double *pos, const int *o, int n, int i, int j, const double N[3])
{
    double e1[3] = {1, 0, 0}, e2[3];
    if (fabs(N[0]) > 0.9) e1[0] = 0, e1[1] = 1;
    q2n_v3_axpy(e1, -q2n_v3_dot(e1, N), N);
    q2n_v3_scale(e1, 1 / q2n_v3_norm(e1), e1);
    q2n_v3_cross(e2, N, e1);
#define FILL_UV(k, u) (u)[0] = q2n_v3_dot(pos + 3 * (size_t)o[k], e1), (u)[1] = q2n_v3_dot(pos + 3 * (size_t)o[k], e2)
    double a[2], b[2], p[2], q[2];
    FILL_UV(i, a);
    FILL_UV(j, b);
    for (int k = 0; k < n; k++) {
        int l = (k + 1) % n;
        if (k == i || k == j || l == i || l == j) continue;
        FILL_UV(k, p);
        FILL_UV(l, q);
        double d1 = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        double d2 = (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
        double d3 = (q[0] - p[0]) * (a[1] - p[1]) - (q[1] - p[1]) * (a[0] - p[0]);
        double d4 = (q[0] - p[0]) * (b[1] - p[1]) - (q[1] - p[1]) * (b[0] - p[0]);
        if ((d1 > 0) != (d2 > 0) && (d3 > 0) != (d4 > 0)) return 0;
    }
    double c[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])}, wind = 0;
    for (int k = 0; k < n; k++) {
        FILL_UV(k, p);
        FILL_UV((k + 1) % n, q);
        wind += atan2((p[0] - c[0]) * (q[1] - c[1]) - (p[1] - c[1]) * (q[0] - c[0]),
                      (p[0] - c[0]) * (q[0] - c[0]) + (p[1] - c[1]) * (q[1] - c[1]));
    }
#undef FILL_UV
    return wind > Q2N_PI;
}

/* The two polygons polygon o (n vertices) splits into along its chord o_i o_j (i < j): o_i .. o_j in
 * piece[0 ..], o_j .. o_i in piece[n ..]; returns the first one's size (the second has n + 2 less it). */
static int split_pieces(const int *o, int n, int i, int j, int *piece)
{
    for (int k = 0; k <= j - i; k++) piece[k] = o[i + k];
    for (int k = 0; k <= n - (j - i); k++) piece[n + k] = o[(j + k) % n];
    return j - i + 1;
}

/* The fill of polygon o (n even, >= 4) with the largest smallest corner sine (*quality): a quad is
 * itself; a larger polygon gets its ring and grid, or, where that has a corner turning against the
 * polygon (a strongly non-convex one: an L, a U), is split along a chord from a reflex corner into
 * two even polygons filled the same way, the split whose worse part is best (at most
 * Q2N_FILL_SPLIT_DEPTH levels, Q2N_FILL_SPLIT_TRIES candidates a polygon).  commit: the fill is
 * written at C->w and C->g0 (both advanced), its quads counted in *nq; else only measured. */
static q2n_status fill_poly(fill_ctx *C, const int *o, int n, int depth, int commit, double *quality, int *nq,
                            q2n_error *err)
{
    *nq = 0;
    if (n == 4) {
        *quality = fill_quality(o, 1, C->pos, C->N);
        if (commit) memcpy(C->fv + C->w, o, 4 * sizeof(int)), C->w += 4, *nq = 1;
        return Q2N_OK;
    }
    int a, s;
    q2n_status st = ring_grid(C, o, n, quality, &a, &s, err);
    if (st) return st;
    if (*quality > 0 || depth >= Q2N_FILL_SPLIT_DEPTH) return commit ? ring_grid_write(C, o, n, a, s, nq, err) : Q2N_OK;
    int *piece = malloc(sizeof(int) * 2 * (size_t)n), bi = -1, bj = -1, budget = Q2N_FILL_SPLIT_TRIES, dummy;
    char *reflex = malloc((size_t)n);
    if (!piece || !reflex) {
        free(piece), free(reflex);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory filling a face");
    }
    for (int k = 0; k < n; k++)
        reflex[k] = q2n_v3_corner_sine(C->pos + 3 * (size_t)o[k], C->pos + 3 * (size_t)o[(k + 1) % n],
                                       C->pos + 3 * (size_t)o[(k + n - 1) % n], C->N, 1.0) < 0;
    double best = *quality, q1 = 0, q2 = 0;
    for (int i = 0; i < n && !st; i++)
        for (int j = i + 3; j <= i + n - 3 && j < n && !st && budget > 0; j += 2) {
            if (!(reflex[i] || reflex[j]) || !chord_inside(C->pos, o, n, i, j, C->N)) continue;
            budget--;
            int n1 = split_pieces(o, n, i, j, piece);
            if ((st = fill_poly(C, piece, n1, depth + 1, 0, &q1, &dummy, err)) || !(q1 > best)) continue;
            if ((st = fill_poly(C, piece + n, n + 2 - n1, depth + 1, 0, &q2, &dummy, err))) continue;
            if (fmin(q1, q2) > best) best = fmin(q1, q2), bi = i, bj = j;
        }
    if (!st && commit) {
        if (bi < 0) st = ring_grid_write(C, o, n, a, s, nq, err);
        else { /* the chosen pieces, written (each searched again: the trials kept no fill) */
            int n1 = split_pieces(o, n, bi, bj, piece), nq1 = 0, nq2 = 0;
            if (!(st = fill_poly(C, piece, n1, depth + 1, 1, &q1, &nq1, err)))
                st = fill_poly(C, piece + n, n + 2 - n1, depth + 1, 1, &q2, &nq2, err);
            *nq = nq1 + nq2;
        }
    }
    if (!st) *quality = best;
    free(piece), free(reflex);
    return st;
}

static q2n_status fill_even(const q2n_mesh *m, q2n_mesh **out, int *filled, int *quads, q2n_error *err)
{
    *out = NULL;
    long nv = m->nv, nf = 0, nfv = 0;
    for (int f = 0; f < m->nf; f++) {
        int n = q2n_face_size(m, f);
        if (fillable(m, f)) { /* the balanced grid, and room for the pieces of a split polygon (at most
                                 2^depth pieces, their sides n + 2 per split in all) and a trial fill */
            long a = n / 4, b = n / 2 - a, ns = n + 2L * (1L << Q2N_FILL_SPLIT_DEPTH);
            long pv = (ns / 4 + 1) * (ns / 4 + 1) + 2 * ns, pq = ns + ns * ns / 16;
            nv += (a + 1) * (b + 1) + pv, nf += n + a * b + pq, nfv += 4 * (n + a * b + pq);
        } else
            nf++, nfv += n;
    }
    if (nv > 0x3fffffff || nfv > 0x3fffffff)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED, "%s: filling its faces would give too many vertices", m->name);
    double *pos = malloc(sizeof(double) * 3 * (size_t)nv);
    int *fs = malloc(sizeof(int) * ((size_t)nf + 1)), *fv = malloc(sizeof(int) * ((size_t)nfv + 1));
    int *fl = malloc(sizeof(int) * ((size_t)nf + 1));
    int nmax = 4; /* the largest filled polygon: X holds a batch of its fills' solutions */
    for (int f = 0; f < m->nf; f++)
        if (fillable(m, f) && q2n_face_size(m, f) > nmax) nmax = q2n_face_size(m, f);
    long ngmax = (long)(nmax / 4 + 1) * (nmax / 2 - nmax / 4 + 1);
    double *X = malloc(sizeof(double) * 3 * Q2N_FILL_BATCH * (size_t)ngmax);
    int starts[Q2N_FILL_BATCH];
    q2n_status st = Q2N_OK;
    int nfill = 0, nquads = 0;
    if (!pos || !fs || !fv || !fl || !X) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory filling faces", m->name); goto done; }
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
        double N[3];
        unit_normal(m, f, N);
        fill_ctx C = {pos, fv, X, starts, N, w, g0};
        double best;
        int nq;
        if ((st = fill_poly(&C, o, n, 0, 1, &best, &nq, err))) goto done;
        if (!(best > 0)) {
            char at[300];
            q2n_mesh_face_where(m, f, at, sizeof at);
            st = q2n_error_set(err, Q2N_ERR_GEOMETRY,
                               "%s: face %d (%d vertices) cannot be filled with quads that all turn its way (strongly "
                               "non-convex or warped); use --subdivide 1 instead of --fill-ngons",
                               at, f, n);
            goto done;
        }
        int ng = C.g0 - g0;
        for (int q = 0; q < nq; q++) fs[k] = w + 4 * q, fl[k++] = line;
        w += 4 * nq;
        g0 += ng;
        nfill++, nquads += nq;
    }
    fs[k] = w;
    /* (nv and nf counted the room a fill may need; g0 and k are what the chosen ones have) */
    st = q2n_mesh_from_arrays_lines(g0, pos, k, fs, fv, m->face_line ? fl : NULL, m->name, out, err);
    if (!st) {
        if (filled) *filled = nfill;
        if (quads) *quads = nquads;
    }
done:
    free(pos), free(fs), free(fv), free(fl), free(X);
    return st;
}
