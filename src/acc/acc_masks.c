/* acc_masks.c — vertex one-rings and the ACC3 bicubic masks of Loop–Schaefer 2008 (with the
 * boundary rules below), degree elevation to ACC5, and the assembly of all patches of a mesh
 * (bicubic away from EVs, biquintic G1 around them, see acc_g1.c).
 *
 * Boundary rules (formulas.md §1.4; Loop–Schaefer's own boundary rules were not available):
 *  - boundary vertices with 2 or more faces: corner point = limit of the B-spline boundary curve,
 *    (e_0 + 4v + e_k)/6, boundary edge points (2v + e)/3 — exact for the boundary curve;
 *  - valence-2 boundary vertices are corners, as in q2n_mesh_subdivide (and OpenSubdiv
 *    VTX_BOUNDARY_EDGE_AND_CORNER): corner point v, which makes the corner patch the bicubic
 *    B-spline of the reflected ("phantom") control net, i.e. the exact limit;
 *  - interior edge points at a boundary vertex with k faces: E_i = P + (cos(iπ/k) T_b +
 *    sin(iπ/k) T_x)/3 as in OpenSubdiv (formulas.md §1.4), but with the cross tangent T_x of the
 *    STANDARD boundary rules (derived in cross_tangent_weights(); the mask quoted in formulas.md
 *    is for Biermann et al.'s modified rules and tilts the normal).  For k = 2 this is the
 *    B-spline edge point, so regular boundaries are reproduced exactly;
 *  - the face (interior) point at any boundary vertex: the regular B-spline weights
 *    (4v + 2a + 2b + d)/9.  Exact at regular boundary vertices and corners; at boundary EVs the
 *    ACC3 surface is only C0 anyway and acc-g1 recomputes these points (eq. 34, seed 001 §5.4). */
#include "acc/acc_masks.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


static inline void axpy(double *y, double a, const double *x, int dim)
{
    for (int t = 0; t < dim; t++) y[t] += a * x[t];
}

static inline const double *V(const double *val, int dim, int v) { return val + (size_t)v * dim; }

void q2n_acc_rings_free(q2n_acc_rings *r)
{
    if (!r) return;
    free(r->start);
    free(r->he);
    free(r->last);
    free(r->pos);
    free(r->bnd);
    free(r->ev);
    memset(r, 0, sizeof *r);
}

q2n_status q2n_acc_rings_build(const q2n_mesh *m, q2n_acc_rings *r, q2n_error *err)
{
    memset(r, 0, sizeof *r);
    for (int f = 0; f < m->nf; f++)
        if (q2n_face_size(m, f) != 4)
            return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                                 "%s: face %d has %d vertices; the ACC masks need an all-quad mesh",
                                 m->name, f, q2n_face_size(m, f));
    r->nv = m->nv;
    r->start = malloc(((size_t)m->nv + 1) * sizeof *r->start);
    r->he = malloc(((size_t)m->nh + 1) * sizeof *r->he);
    r->last = malloc(((size_t)m->nv + 1) * sizeof *r->last);
    r->pos = malloc(((size_t)m->nh + 1) * sizeof *r->pos);
    r->bnd = calloc((size_t)m->nv + 1, 1);
    r->ev = calloc((size_t)m->nv + 1, 1);
    if (!r->start || !r->he || !r->last || !r->pos || !r->bnd || !r->ev) {
        q2n_acc_rings_free(r);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory (rings)", m->name);
    }
    int n = 0;
    for (int v = 0; v < m->nv; v++) {
        r->start[v] = n;
        r->last[v] = -1;
        int h0 = m->vert_he[v];
        if (h0 < 0) continue;
        int h = h0, k = 0;
        do {
            r->pos[h] = k++;
            r->he[n++] = h;
            int p = q2n_he_prev(m, h);
            if (m->he_twin[p] < 0) { r->last[v] = q2n_he_origin(m, p); break; }
            h = m->he_twin[p];
        } while (h != h0);
        r->bnd[v] = m->vert_boundary[v];
        if (!r->bnd[v] && k < 3) {
            char where[300], of[48];
            q2n_mesh_vertex_where(m, v, where, sizeof where);
            q2n_mesh_of(m, 0, of, sizeof of);
            q2n_status st = q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                                          "%s: vertex %d (of this face%s) is an interior vertex of only %d faces: "
                                          "the Catmull-Clark limit has no tangent plane there (merge them into one face)",
                                          where, v, of, k);
            q2n_acc_rings_free(r);
            return st;
        }
        r->ev[v] = (unsigned char)(r->bnd[v] ? k >= 3 : k != 4);
    }
    r->start[m->nv] = n;
    return Q2N_OK;
}

int q2n_acc_evs_isolated(const q2n_mesh *m, const q2n_acc_rings *r, int *bad_face)
{
    for (int f = 0; f < m->nf; f++) {
        int c = 0;
        for (int i = 0; i < 4; i++) c += r->ev[m->face_vert[m->face_start[f] + i]];
        if (c > 1) {
            if (bad_face) *bad_face = f;
            return 0;
        }
    }
    return 1;
}

/* Ring vertices of v: e(i) and f(i) for ring position i (mod n for interior vertices). */
typedef struct ring {
    const q2n_mesh *m;
    const q2n_acc_rings *r;
    int v, n, bnd;
} ring;

static int ring_e(const ring *g, int i)
{
    if (g->bnd && i == g->n) return g->r->last[g->v];
    i = ((i % g->n) + g->n) % g->n;
    return q2n_he_dest(g->m, g->r->he[g->r->start[g->v] + i]);
}

static int ring_f(const ring *g, int i)
{
    i = ((i % g->n) + g->n) % g->n;
    int h = g->r->he[g->r->start[g->v] + i];
    return q2n_he_dest(g->m, q2n_he_next(g->m, h));
}

/* Corner (limit) point: formulas.md §1.1 (interior, = eq. (1) of seed 001) and §1.4. */
static void corner_point(const ring *g, const double *val, int dim, double *out)
{
    memset(out, 0, (size_t)dim * sizeof *out);
    int n = g->n;
    if (!g->bnd) {
        double w = 1.0 / (n * (n + 5.0));
        axpy(out, n * n * w, V(val, dim, g->v), dim);
        for (int i = 0; i < n; i++) {
            axpy(out, 4 * w, V(val, dim, ring_e(g, i)), dim);
            axpy(out, w, V(val, dim, ring_f(g, i)), dim);
        }
    } else if (n == 1) {
        axpy(out, 1.0, V(val, dim, g->v), dim); /* corner vertex stays fixed */
    } else {
        axpy(out, 4.0 / 6, V(val, dim, g->v), dim);
        axpy(out, 1.0 / 6, V(val, dim, ring_e(g, 0)), dim);
        axpy(out, 1.0 / 6, V(val, dim, ring_e(g, n)), dim);
    }
}

/* Cross-boundary limit tangent T_x at a boundary vertex with n faces, as weights:
 * wv v + wb (e_0 + e_n) + Σ_{i=1}^{n-1} a sin(iθ) e_i + Σ_{i=0}^{n-1} b (sin(iθ) + sin((i+1)θ)) f_i.
 *
 * [DERIVED here; formulas.md §1.4 is NOT used for n >= 3.]  The OpenSubdiv/Biermann et al. mask
 * quoted there belongs to Biermann–Levin–Zorin's modified boundary rules: with the standard
 * Catmull–Clark boundary rules (boundary curve (e_0 + 6v + e_n)/8, which q2n_mesh_subdivide and
 * OpenSubdiv's refiner use) its normal is off by up to 0.1 rad (checked against 7 levels of
 * subdivision and Bfr).  Here T_x is the left eigenvector of the one-ring subdivision matrix for
 * the symmetric sub-dominant eigenvalue λ = (5 + C + sqrt((1+C)(9+C)))/16, C = cos(π/n)
 * (λ = 1/2 for n = 2): with e_i -> a sin(iθ), f_i -> b (sin iθ + sin(i+1)θ) the edge and face
 * rows give b = a / (16 (λ - 1/4)); the rows of e_0 and v give the two equations solved below.
 * Scale: a = 4/(3n + C) (the Loop–Schaefer normalisation, so that n = 2 is the B-spline). */
static void cross_tangent_weights(int n, double *wv, double *wb, double *a, double *b)
{
    double th = Q2N_PI / n, C = cos(th), S = 0;
    for (int i = 1; i < n; i++) S += sin(i * th);
    *a = 4.0 / (3.0 * n + C);
    if (n == 2) { /* regular boundary vertex: B-spline cross tangent [-4v - (e_0+e_2) + 4e_1 + f_0 + f_1]/6 */
        *wv = -4.0 / 6.0;
        *wb = -1.0 / 6.0;
        *b = 1.0 / 6.0;
        return;
    }
    double lam = (5.0 + C + sqrt((1.0 + C) * (9.0 + C))) / 16.0;
    *b = *a / (16.0 * (lam - 0.25));
    /* row of v:   wv (λ - 3/4) = 2 wb/2 + (3/8) a S + (b/4) 2S
     * row of e_0: wb (λ - 1/2) = wv/8 + λ b sin θ */
    double s1 = sin(th);
    *wv = (s1 * lam * *b / (lam - 0.5) + S * (0.375 * *a + 0.5 * *b)) /
          ((lam - 0.75) - 1.0 / (8.0 * (lam - 0.5)));
    *wb = (*wv / 8.0 + s1 * lam * *b) / (lam - 0.5);
}

/* Edge point on ring edge j (towards e_j), at v's third of the edge. */
static void edge_point(const ring *g, int j, const double *val, int dim, double *out)
{
    memset(out, 0, (size_t)dim * sizeof *out);
    int n = g->n;
    if (!g->bnd) { /* Loop–Schaefer edge mask, formulas.md §1.1 */
        double w = 1.0 / (2.0 * n + 10.0);
        axpy(out, 2 * n * w, V(val, dim, g->v), dim);
        axpy(out, 4 * w, V(val, dim, ring_e(g, j)), dim);
        axpy(out, 2 * w, V(val, dim, ring_e(g, j - 1)), dim);
        axpy(out, 2 * w, V(val, dim, ring_e(g, j + 1)), dim);
        axpy(out, w, V(val, dim, ring_f(g, j - 1)), dim);
        axpy(out, w, V(val, dim, ring_f(g, j)), dim);
        return;
    }
    if (j == 0 || j == n) { /* boundary edge: cubic B-spline boundary curve */
        axpy(out, 2.0 / 3, V(val, dim, g->v), dim);
        axpy(out, 1.0 / 3, V(val, dim, ring_e(g, j)), dim);
        return;
    }
    /* interior edge at a boundary vertex with n faces: E_j = P + (cos(jθ) T_b + sin(jθ) T_x)/3,
     * θ = π/n, T_b = (e_0 - e_n)/2 (formulas.md §1.4), T_x the cross-boundary limit tangent */
    double th = Q2N_PI / n, cj = cos(j * th) / 3.0, sj = sin(j * th) / 3.0;
    corner_point(g, val, dim, out);
    axpy(out, cj * 0.5, V(val, dim, ring_e(g, 0)), dim);
    axpy(out, -cj * 0.5, V(val, dim, ring_e(g, n)), dim);
    double wv, wb, a, b;
    cross_tangent_weights(n, &wv, &wb, &a, &b);
    axpy(out, sj * wv, V(val, dim, g->v), dim);
    axpy(out, sj * wb, V(val, dim, ring_e(g, 0)), dim);
    axpy(out, sj * wb, V(val, dim, ring_e(g, n)), dim);
    for (int i = 1; i < n; i++) axpy(out, sj * a * sin(i * th), V(val, dim, ring_e(g, i)), dim);
    for (int i = 0; i < n; i++)
        axpy(out, sj * b * (sin(i * th) + sin((i + 1) * th)), V(val, dim, ring_f(g, i)), dim);
}

/* Unit normal of the limit surface at v: interior vertices from the limit tangent masks of
 * formulas.md §1.2 (t_j = Σ_i α_{i-j} e_i + β_{i-j} f_i, normal t_0 × t_1); boundary vertices
 * T_b × T_x (T_x of cross_tangent_weights); corners (e_0 - v) × (e_1 - v). */
static void vertex_normal(const ring *g, const double *pos, double *out)
{
    double t0[3] = { 0, 0, 0 }, t1[3] = { 0, 0, 0 };
    const double *pv = V(pos, 3, g->v);
    int n = g->n;
    if (!g->bnd) {
        double c = cos(Q2N_PI / n), q = 1.0 / (n * sqrt(4.0 + c * c));
        for (int i = 0; i < n; i++) {
            double a0 = (1.0 / n + c * q) * cos(2 * Q2N_PI * i / n), b0 = q * cos((2 * Q2N_PI * i + Q2N_PI) / n);
            double a1 = (1.0 / n + c * q) * cos(2 * Q2N_PI * (i - 1) / n),
                   b1 = q * cos((2 * Q2N_PI * (i - 1) + Q2N_PI) / n);
            axpy(t0, a0, V(pos, 3, ring_e(g, i)), 3);
            axpy(t0, b0, V(pos, 3, ring_f(g, i)), 3);
            axpy(t1, a1, V(pos, 3, ring_e(g, i)), 3);
            axpy(t1, b1, V(pos, 3, ring_f(g, i)), 3);
        }
    } else if (n == 1) {
        axpy(t0, 1, V(pos, 3, ring_e(g, 0)), 3);
        axpy(t0, -1, pv, 3);
        axpy(t1, 1, V(pos, 3, ring_e(g, 1)), 3);
        axpy(t1, -1, pv, 3);
    } else {
        double th = Q2N_PI / n, wv, wb, a, b;
        cross_tangent_weights(n, &wv, &wb, &a, &b);
        axpy(t0, 0.5, V(pos, 3, ring_e(g, 0)), 3);
        axpy(t0, -0.5, V(pos, 3, ring_e(g, n)), 3);
        axpy(t1, wv, pv, 3);
        axpy(t1, wb, V(pos, 3, ring_e(g, 0)), 3);
        axpy(t1, wb, V(pos, 3, ring_e(g, n)), 3);
        for (int i = 1; i < n; i++) axpy(t1, a * sin(i * th), V(pos, 3, ring_e(g, i)), 3);
        for (int i = 0; i < n; i++) axpy(t1, b * (sin(i * th) + sin((i + 1) * th)), V(pos, 3, ring_f(g, i)), 3);
    }
    double c[3] = { t0[1] * t1[2] - t0[2] * t1[1], t0[2] * t1[0] - t0[0] * t1[2], t0[0] * t1[1] - t0[1] * t1[0] };
    double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int t = 0; t < 3; t++) out[t] = len > 0 ? c[t] / len : 0.0;
}

void q2n_acc_limit_frame(const q2n_mesh *m, const q2n_acc_rings *r, int v, double p[3], double nrm[3])
{
    ring g = { m, r, v, q2n_acc_ring_size(r, v), r->bnd[v] };
    if (g.n == 0) {
        memcpy(p, q2n_mesh_vpos(m, v), 3 * sizeof *p);
        nrm[0] = nrm[1] = nrm[2] = 0;
        return;
    }
    corner_point(&g, m->pos, 3, p);
    vertex_normal(&g, m->pos, nrm);
}

/* Face (interior) point of ring face i: (n v + 2 e_i + 2 e_{i+1} + f_i)/(n+5), formulas.md §1.1;
 * n = 4 (B-spline weights) at boundary vertices, see the file comment. */
static void face_point(const ring *g, int i, const double *val, int dim, double *out)
{
    memset(out, 0, (size_t)dim * sizeof *out);
    double n = g->bnd ? 4.0 : g->n, w = 1.0 / (n + 5.0);
    axpy(out, n * w, V(val, dim, g->v), dim);
    axpy(out, 2 * w, V(val, dim, ring_e(g, i)), dim);
    axpy(out, 2 * w, V(val, dim, ring_e(g, i + 1)), dim);
    axpy(out, w, V(val, dim, ring_f(g, i)), dim);
}

void q2n_acc_corner_points(const q2n_mesh *m, const q2n_acc_rings *r, int h, const double *val,
                           int dim, double *out)
{
    int v = q2n_he_origin(m, h);
    ring g = { m, r, v, q2n_acc_ring_size(r, v), r->bnd[v] };
    int i = r->pos[h];
    corner_point(&g, val, dim, out);
    edge_point(&g, i, val, dim, out + dim);
    edge_point(&g, i + 1, val, dim, out + 2 * dim);
    face_point(&g, i, val, dim, out + 3 * dim);
}

void q2n_acc_bicubic(const q2n_mesh *m, const q2n_acc_rings *r, int f, const double *val, int dim,
                     double *cp)
{
    for (int c = 0; c < 4; c++) { /* each corner writes its 2x2 block (EV-local (0..1, 0..1)) */
        int h = q2n_face_he(m, f, c), v = q2n_he_origin(m, h), i = r->pos[h];
        ring g = { m, r, v, q2n_acc_ring_size(r, v), r->bnd[v] };
        corner_point(&g, val, dim, cp + (size_t)q2n_acc_local_index(c, 3, 0, 0) * dim);
        edge_point(&g, i, val, dim, cp + (size_t)q2n_acc_local_index(c, 3, 1, 0) * dim);
        edge_point(&g, i + 1, val, dim, cp + (size_t)q2n_acc_local_index(c, 3, 0, 1) * dim);
        face_point(&g, i, val, dim, cp + (size_t)q2n_acc_local_index(c, 3, 1, 1) * dim);
    }
}

/* Copy between a face's biquintic points and the EV-local sector layout of corner c. */
static void to_local(const double *face, int c, int dim, double *loc)
{
    for (int j = 0; j < 6; j++)
        for (int i = 0; i < 6; i++)
            memcpy(loc + (size_t)(j * 6 + i) * dim, face + (size_t)q2n_acc_local_index(c, 5, i, j) * dim,
                   (size_t)dim * sizeof *loc);
}

static void from_local(const double *loc, int c, int dim, double *face)
{
    for (int j = 0; j < 6; j++)
        for (int i = 0; i < 6; i++)
            memcpy(face + (size_t)q2n_acc_local_index(c, 5, i, j) * dim, loc + (size_t)(j * 6 + i) * dim,
                   (size_t)dim * sizeof *loc);
}

/* G1 construction around one EV v: gather its sector patches (ACC5), solve, scatter back. */
static q2n_status g1_vertex(const q2n_mesh *m, const q2n_acc_rings *r, int v, q2n_acc_strategy st,
                            int dim, double *cp, q2n_error *err)
{
    int n = q2n_acc_ring_size(r, v);
    size_t blk = 36 * (size_t)dim;
    double *buf = malloc((size_t)n * blk * sizeof *buf);
    double **P = malloc((size_t)n * sizeof *P);
    if (!buf || !P) {
        free(buf);
        free(P);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory (vertex %d)", m->name, v);
    }
    for (int k = 0; k < n; k++) {
        int h = r->he[r->start[v] + k], f = m->he_face[h], c = h - m->face_start[f];
        P[k] = buf + (size_t)k * blk;
        to_local(cp + (size_t)f * blk, c, dim, P[k]);
    }
    q2n_status s = r->bnd[v] ? q2n_acc_g1_boundary(n, dim, st, P, err)
                             : q2n_acc_g1_interior(n, dim, st, P, err);
    if (s == Q2N_OK)
        for (int k = 0; k < n; k++) {
            int h = r->he[r->start[v] + k], f = m->he_face[h], c = h - m->face_start[f];
            from_local(P[k], c, dim, cp + (size_t)f * blk);
        }
    free(buf);
    free(P);
    return s;
}

q2n_status q2n_acc_control_points(const q2n_mesh *m, const q2n_acc_rings *r, q2n_acc_method method,
                                  q2n_acc_strategy st, const double *val, int dim, int *deg,
                                  double *cp, q2n_error *err)
{
    size_t blk = 36 * (size_t)dim;
    int bad = -1;
    if (method == Q2N_ACC_G1 && !q2n_acc_evs_isolated(m, r, &bad))
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s: face %d has more than one extraordinary vertex (acc-g1 needs "
                             "isolated EVs: subdivide first)", m->name, bad);
    double *c3 = malloc(16 * (size_t)dim * sizeof *c3);
    if (!c3) return q2n_error_set(err, Q2N_ERR_NOMEM, "%s: out of memory", m->name);
    for (int f = 0; f < m->nf; f++) {
        double *out = cp + (size_t)f * blk;
        int quintic = 0;
        if (method == Q2N_ACC_G1)
            for (int i = 0; i < 4; i++) quintic |= r->ev[m->face_vert[m->face_start[f] + i]];
        q2n_acc_bicubic(m, r, f, val, dim, c3);
        if (quintic) {
            q2n_bezier_elevate(3, 3, 5, 5, dim, c3, out);
            deg[f] = 5;
        } else {
            memcpy(out, c3, 16 * (size_t)dim * sizeof *c3);
            deg[f] = 3;
        }
    }
    free(c3);
    if (method != Q2N_ACC_G1) return Q2N_OK;
    for (int v = 0; v < m->nv; v++) {
        if (!r->ev[v]) continue;
        q2n_status s = g1_vertex(m, r, v, st, dim, cp, err);
        if (s != Q2N_OK) return s;
    }
    return Q2N_OK;
}
