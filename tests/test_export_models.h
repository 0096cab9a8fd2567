/* test_export_models.h — models for the export tests, built here so the writers are tested
 * independently of the fit stage:
 *   - a small half-edge builder (em_mesh_*) filling the q2n_mesh fields the writers read, so the
 *     tests do not depend on the mesh module's constructors, and a minimal OBJ reader;
 *   - bilinear patches through each quad's corners, written as bi-quintic B-splines with two
 *     interior knots (exact: Greville abscissae reproduce linear functions, NURBS Book eq. (2.21)),
 *     watertight by construction (G0 only);
 *   - the exact bicubic B-spline patches of a regular closed quad mesh (each face's 4x4
 *     neighbourhood, uniform B-spline -> Bezier conversion), C2 across every edge;
 *   - exact rational biquadratic tori and open cylinders (quarter-circle arcs, weights 1, 1/sqrt2, 1). */
#ifndef Q2N_TEST_EXPORT_MODELS_H
#define Q2N_TEST_EXPORT_MODELS_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/bspline.h"
#include "mesh/mesh.h"

#define EM_PI 3.14159265358979323846

/* ------------------------------------------------------------------ mesh */

/* Quad mesh from arrays (fv: 4 per face); fills nv, nf, pos, face_start, face_vert, nh, he_face,
 * he_twin, he_edge, ne, edge_he, all_quads.  Returns NULL on a non-manifold input. */
static inline q2n_mesh *em_mesh_build(int nv, const double *pos, int nf, const int *fv)
{
    q2n_mesh *m = (q2n_mesh *)calloc(1, sizeof *m);
    int nh = 4 * nf;
    m->nv = nv; m->nf = nf; m->nh = nh; m->all_quads = 1;
    m->pos = (double *)malloc(sizeof(double) * 3 * (size_t)nv);
    m->face_start = (int *)malloc(sizeof(int) * (size_t)(nf + 1));
    m->face_vert = (int *)malloc(sizeof(int) * (size_t)nh);
    m->he_face = (int *)malloc(sizeof(int) * (size_t)nh);
    m->he_twin = (int *)malloc(sizeof(int) * (size_t)nh);
    m->he_edge = (int *)malloc(sizeof(int) * (size_t)nh);
    m->edge_he = (int *)malloc(sizeof(int) * (size_t)nh);
    memcpy(m->pos, pos, sizeof(double) * 3 * (size_t)nv);
    memcpy(m->face_vert, fv, sizeof(int) * (size_t)nh);
    for (int f = 0; f <= nf; f++) m->face_start[f] = 4 * f;
    for (int h = 0; h < nh; h++) { m->he_face[h] = h / 4; m->he_twin[h] = -1; m->he_edge[h] = -1; }
    /* twins by brute force over a vertex -> outgoing half-edges table (test meshes are small) */
    for (int h = 0; h < nh; h++) {
        int a = fv[h], b = fv[4 * (h / 4) + (h % 4 + 1) % 4];
        for (int g = 0; g < nh; g++) {
            int c = fv[g], d = fv[4 * (g / 4) + (g % 4 + 1) % 4];
            if (c == b && d == a) {
                if (m->he_twin[h] >= 0) { fprintf(stderr, "non-manifold edge %d-%d\n", a, b); return NULL; }
                m->he_twin[h] = g;
            }
            if (g != h && c == a && d == b) { fprintf(stderr, "inconsistent orientation %d-%d\n", a, b); return NULL; }
        }
    }
    m->ne = 0;
    for (int h = 0; h < nh; h++) {
        int t = m->he_twin[h];
        if (t >= 0 && t < h) continue;
        m->he_edge[h] = m->ne;
        if (t >= 0) m->he_edge[t] = m->ne;
        m->edge_he[m->ne++] = h;
    }
    snprintf(m->name, sizeof m->name, "test mesh");
    return m;
}

static inline void em_mesh_free(q2n_mesh *m)
{
    if (!m) return;
    free(m->pos); free(m->face_start); free(m->face_vert); free(m->he_face);
    free(m->he_twin); free(m->he_edge); free(m->edge_he);
    free(m);
}

static inline int em_mesh_boundary_edges(const q2n_mesh *m)
{
    int n = 0;
    for (int h = 0; h < m->nh; h++) n += m->he_twin[h] < 0;
    return n;
}

/* Number of connected components (faces linked across interior edges). */
static inline int em_mesh_components(const q2n_mesh *m)
{
    int *comp = (int *)malloc(sizeof(int) * (size_t)m->nf), *stack = (int *)malloc(sizeof(int) * (size_t)m->nf), n = 0;
    for (int f = 0; f < m->nf; f++) comp[f] = -1;
    for (int f0 = 0; f0 < m->nf; f0++) {
        if (comp[f0] >= 0) continue;
        int top = 0;
        stack[top++] = f0;
        comp[f0] = n;
        while (top) {
            int f = stack[--top];
            for (int i = 0; i < 4; i++) {
                int t = m->he_twin[4 * f + i];
                if (t >= 0 && comp[t / 4] < 0) { comp[t / 4] = n; stack[top++] = t / 4; }
            }
        }
        n++;
    }
    free(comp);
    free(stack);
    return n;
}

/* Minimal OBJ reader: v x y z and quad f records (a, a/b, a//c, a/b/c). NULL when not all quads. */
static inline q2n_mesh *em_mesh_read_obj(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return NULL;
    int cv = 0, cf = 0, nv = 0, nf = 0;
    double *pos = NULL;
    int *fv = NULL, ok = 1;
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (nv == cv) { cv = cv ? 2 * cv : 64; pos = (double *)realloc(pos, sizeof(double) * 3 * (size_t)cv); }
            sscanf(line + 2, "%lf %lf %lf", &pos[3 * nv], &pos[3 * nv + 1], &pos[3 * nv + 2]);
            nv++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            int idx[8], n = 0;
            char *p = line + 2, *end;
            for (;;) {
                long x = strtol(p, &end, 10);
                if (end == p) break;
                if (n < 8) idx[n] = (int)(x < 0 ? nv + x : x - 1);
                n++;
                p = end;
                while (*p && *p != ' ' && *p != '\t' && *p != '\n') p++;
            }
            if (n != 4) { ok = 0; continue; }
            if (nf == cf) { cf = cf ? 2 * cf : 64; fv = (int *)realloc(fv, sizeof(int) * 4 * (size_t)cf); }
            memcpy(fv + 4 * nf, idx, 4 * sizeof(int));
            nf++;
        }
    }
    fclose(f);
    q2n_mesh *m = ok && nf > 0 ? em_mesh_build(nv, pos, nf, fv) : NULL;
    free(pos);
    free(fv);
    return m;
}

static inline double em_mesh_diag(const q2n_mesh *m)
{
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int v = 0; v < m->nv; v++)
        for (int c = 0; c < 3; c++) { lo[c] = fmin(lo[c], m->pos[3 * v + c]); hi[c] = fmax(hi[c], m->pos[3 * v + c]); }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* ------------------------------------------------------------------ surfaces */

static inline void em_surface_alloc(q2n_bspline_surface *s, int du, int dv, int nu, int nv, int rational)
{
    s->deg_u = du; s->deg_v = dv; s->ncp_u = nu; s->ncp_v = nv;
    s->knots_u = (double *)malloc(sizeof(double) * (size_t)(nu + du + 1));
    s->knots_v = (double *)malloc(sizeof(double) * (size_t)(nv + dv + 1));
    s->cp = (double *)malloc(sizeof(double) * 3 * (size_t)(nu * nv));
    s->weights = rational ? (double *)malloc(sizeof(double) * (size_t)(nu * nv)) : NULL;
}

/* Frees the patches of a model built here on the stack (q2n_nurbs_model_free frees the struct
 * too, for the heap-allocated models of the fit stage). */
static inline void em_model_release(q2n_nurbs_model *md)
{
    for (int k = 0; k < md->n; k++) q2n_bspline_free(&md->patches[k]);
    free(md->patches);
    md->patches = NULL;
    md->n = 0;
}

/* clamped knots on [0,1] with nin uniform interior knots */
static inline void em_knots(double *k, int p, int nin)
{
    for (int i = 0; i <= p; i++) { k[i] = 0.0; k[p + 1 + nin + i] = 1.0; }
    for (int i = 0; i < nin; i++) k[p + 1 + i] = (i + 1.0) / (nin + 1.0);
}

static inline q2n_nurbs_model em_model_alloc(const q2n_mesh *m)
{
    q2n_nurbs_model md;
    md.n = m->nf;
    md.patches = (q2n_bspline_surface *)calloc((size_t)m->nf, sizeof(q2n_bspline_surface));
    md.mesh = m;
    md.tol_abs = 0.0;
    md.edges = NULL;   /* the writers take each edge curve from a patch boundary */
    return md;
}

/* Bilinear patch through each face's corners as a bi-quintic with interior knots 1/3, 2/3:
 * control point (i,j) = bilinear(Greville(i), Greville(j)). */
static inline q2n_nurbs_model em_model_bilinear(const q2n_mesh *m)
{
    q2n_nurbs_model md = em_model_alloc(m);
    const int p = 5, nin = 2, n = p + 1 + nin;
    for (int f = 0; f < m->nf; f++) {
        q2n_bspline_surface *s = &md.patches[f];
        em_surface_alloc(s, p, p, n, n, 0);
        em_knots(s->knots_u, p, nin);
        em_knots(s->knots_v, p, nin);
        const double *c[4];
        for (int i = 0; i < 4; i++) c[i] = m->pos + 3 * m->face_vert[4 * f + i];
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                double u = 0, v = 0;
                for (int r = 1; r <= p; r++) { u += s->knots_u[i + r]; v += s->knots_v[j + r]; }
                u /= p; v /= p;
                for (int a = 0; a < 3; a++)
                    s->cp[3 * (j * n + i) + a] = (1 - u) * (1 - v) * c[0][a] + u * (1 - v) * c[1][a] +
                                                 u * v * c[2][a] + (1 - u) * v * c[3][a];
            }
    }
    return md;
}

/* Grid coordinates of the 4x4 neighbourhood of face f in a regular quad mesh (all valence 4):
 * g[j][i] = vertex at grid (i-1, j-1) with face f's v0 at (0,0), v1 at (1,0), v3 at (0,1).
 * Breadth-first unfolding across edges; returns 0 when the neighbourhood is not a 4x4 grid. */
static inline int em_regular_ring(const q2n_mesh *m, int f0, int g[4][4])
{
    int qf[16], qc[16][4][2], nq = 0, head = 0;
    int *seen = (int *)calloc((size_t)m->nf, sizeof(int));
    static const int corner[4][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
    for (int j = 0; j < 4; j++) for (int i = 0; i < 4; i++) g[j][i] = -1;
    qf[nq] = f0;
    memcpy(qc[nq], corner, sizeof corner);
    nq++;
    seen[f0] = 1;
    while (head < nq) {
        int f = qf[head];
        int (*c)[2] = qc[head++];
        for (int i = 0; i < 4; i++) {
            int v = m->face_vert[4 * f + i], *x = c[i];
            if (g[x[1]][x[0]] >= 0 && g[x[1]][x[0]] != v) { free(seen); return 0; }
            g[x[1]][x[0]] = v;
        }
        for (int i = 0; i < 4 && nq < 9; i++) {
            int h = 4 * f + i, t = m->he_twin[h];
            if (t < 0) continue;
            int nf = m->he_face[t];
            if (seen[nf]) continue;
            /* across A->B with interior direction n = c[i+2]-c[i+1]... the face {B, A, A-n, B-n} */
            int *A = c[i], *B = c[(i + 1) % 4], *Bn = c[(i + 2) % 4];
            int n[2] = {Bn[0] - B[0], Bn[1] - B[1]};
            int C[2] = {A[0] - n[0], A[1] - n[1]}, D[2] = {B[0] - n[0], B[1] - n[1]};
            if (C[0] < 0 || C[0] > 3 || C[1] < 0 || C[1] > 3 || D[0] < 0 || D[0] > 3 || D[1] < 0 || D[1] > 3) continue;
            int k = t - 4 * nf; /* twin runs B -> A: corners k (B), k+1 (A), k+2 (A-n), k+3 (B-n) */
            int (*d)[2] = qc[nq];
            d[k][0] = B[0]; d[k][1] = B[1];
            d[(k + 1) % 4][0] = A[0]; d[(k + 1) % 4][1] = A[1];
            d[(k + 2) % 4][0] = C[0]; d[(k + 2) % 4][1] = C[1];
            d[(k + 3) % 4][0] = D[0]; d[(k + 3) % 4][1] = D[1];
            qf[nq++] = nf;
            seen[nf] = 1;
        }
    }
    free(seen);
    for (int j = 0; j < 4; j++) for (int i = 0; i < 4; i++) if (g[j][i] < 0) return 0;
    return 1;
}

/* Exact bicubic B-spline patches (single Bezier span) of a regular closed quad mesh.
 * Uniform cubic B-spline -> Bezier on one span: rows (1,4,1)/6, (0,4,2)/6, (0,2,4)/6, (0,1,4,1)/6. */
static inline int em_model_bicubic(const q2n_mesh *m, q2n_nurbs_model *out)
{
    static const double M[4][4] = {{1, 4, 1, 0}, {0, 4, 2, 0}, {0, 2, 4, 0}, {0, 1, 4, 1}};
    q2n_nurbs_model md = em_model_alloc(m);
    for (int f = 0; f < m->nf; f++) {
        int g[4][4];
        if (!em_regular_ring(m, f, g)) { em_model_release(&md); return 0; }
        q2n_bspline_surface *s = &md.patches[f];
        em_surface_alloc(s, 3, 3, 4, 4, 0);
        em_knots(s->knots_u, 3, 0);
        em_knots(s->knots_v, 3, 0);
        for (int b = 0; b < 4; b++)
            for (int a = 0; a < 4; a++)
                for (int c = 0; c < 3; c++) {
                    double x = 0;
                    for (int j = 0; j < 4; j++)
                        for (int i = 0; i < 4; i++) x += M[a][i] * M[b][j] * m->pos[3 * g[j][i] + c];
                    s->cp[3 * (b * 4 + a) + c] = x / 36.0;
                }
    }
    *out = md;
    return 1;
}

/* Rational quarter arc from angle k*pi/2 to (k+1)*pi/2 of the unit circle: 3 points (x,y), weights. */
static inline void em_arc(int k, double xy[3][2], double w[3])
{
    double c0 = cos(k * EM_PI / 2), s0 = sin(k * EM_PI / 2), c1 = cos((k + 1) * EM_PI / 2), s1 = sin((k + 1) * EM_PI / 2);
    xy[0][0] = c0; xy[0][1] = s0;
    xy[1][0] = c0 + c1; xy[1][1] = s0 + s1;  /* corner of the tangent lines */
    xy[2][0] = c1; xy[2][1] = s1;
    w[0] = w[2] = 1.0;
    w[1] = sqrt(0.5);
}

/* Torus (major R, minor r) with 4 x 4 faces: mesh vertices at phi = k pi/2, theta = l pi/2, exact
 * rational biquadratic patches (outward normals). *mesh_out must be freed with em_mesh_free. */
static inline q2n_nurbs_model em_model_torus_rational(double R, double r, q2n_mesh **mesh_out)
{
    double pos[3 * 16];
    int fv[4 * 16];
    for (int l = 0; l < 4; l++)
        for (int k = 0; k < 4; k++) {
            double ph = k * EM_PI / 2, th = l * EM_PI / 2, rho = R + r * cos(th);
            pos[3 * (l * 4 + k)] = rho * cos(ph);
            pos[3 * (l * 4 + k) + 1] = rho * sin(ph);
            pos[3 * (l * 4 + k) + 2] = r * sin(th);
            int f = l * 4 + k, k1 = (k + 1) % 4, l1 = (l + 1) % 4;
            fv[4 * f] = l * 4 + k; fv[4 * f + 1] = l * 4 + k1; fv[4 * f + 2] = l1 * 4 + k1; fv[4 * f + 3] = l1 * 4 + k;
        }
    q2n_mesh *m = em_mesh_build(16, pos, 16, fv);
    q2n_nurbs_model md = em_model_alloc(m);
    for (int f = 0; f < 16; f++) {
        int k = f % 4, l = f / 4;
        double a[3][2], wa[3], b[3][2], wb[3];
        em_arc(k, a, wa);
        em_arc(l, b, wb);
        q2n_bspline_surface *s = &md.patches[f];
        em_surface_alloc(s, 2, 2, 3, 3, 1);
        em_knots(s->knots_u, 2, 0);
        em_knots(s->knots_v, 2, 0);
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++) {
                /* (rho x, rho y, z) with rho = R + r cos(theta) in homogeneous form, per arc point */
                double rho = R * 1.0 + r * b[j][0], z = r * b[j][1];
                double *P = s->cp + 3 * (j * 3 + i);
                P[0] = rho * a[i][0]; P[1] = rho * a[i][1]; P[2] = z;
                s->weights[j * 3 + i] = wa[i] * wb[j];
            }
    }
    *mesh_out = m;
    return md;
}

/* Open cylinder (radius r, height h) with 4 faces around and `rows` rows: rational (degree 2 x 1). */
static inline q2n_nurbs_model em_model_cylinder_rational(double r, double h, int rows, q2n_mesh **mesh_out)
{
    int nv = 4 * (rows + 1), nf = 4 * rows;
    double *pos = (double *)malloc(sizeof(double) * 3 * (size_t)nv);
    int *fv = (int *)malloc(sizeof(int) * 4 * (size_t)nf);
    for (int l = 0; l <= rows; l++)
        for (int k = 0; k < 4; k++) {
            pos[3 * (l * 4 + k)] = r * cos(k * EM_PI / 2);
            pos[3 * (l * 4 + k) + 1] = r * sin(k * EM_PI / 2);
            pos[3 * (l * 4 + k) + 2] = h * l / rows;
        }
    for (int l = 0; l < rows; l++)
        for (int k = 0; k < 4; k++) {
            int f = l * 4 + k, k1 = (k + 1) % 4;
            fv[4 * f] = l * 4 + k; fv[4 * f + 1] = l * 4 + k1; fv[4 * f + 2] = (l + 1) * 4 + k1; fv[4 * f + 3] = (l + 1) * 4 + k;
        }
    q2n_mesh *m = em_mesh_build(nv, pos, nf, fv);
    free(pos);
    free(fv);
    q2n_nurbs_model md = em_model_alloc(m);
    for (int f = 0; f < nf; f++) {
        int k = f % 4, l = f / 4;
        double a[3][2], wa[3];
        em_arc(k, a, wa);
        q2n_bspline_surface *s = &md.patches[f];
        em_surface_alloc(s, 2, 1, 3, 2, 1);
        em_knots(s->knots_u, 2, 0);
        em_knots(s->knots_v, 1, 0);
        for (int j = 0; j < 2; j++)
            for (int i = 0; i < 3; i++) {
                double *P = s->cp + 3 * (j * 3 + i);
                P[0] = r * a[i][0]; P[1] = r * a[i][1]; P[2] = h * (l + j) / rows;
                s->weights[j * 3 + i] = wa[i];
            }
    }
    *mesh_out = m;
    return md;
}

/* The same surfaces on the reversed mesh: face (v0,v1,v2,v3) becomes (v0,v3,v2,v1) and its patch
 * is transposed (u <-> v), so the geometry is unchanged and every normal Su x Sv flips
 * (e.g. an inward-oriented closed mesh).  *mesh_out must be freed with em_mesh_free. */
static inline q2n_nurbs_model em_model_reversed(const q2n_nurbs_model *in, q2n_mesh **mesh_out)
{
    const q2n_mesh *m = in->mesh;
    int *fv = (int *)malloc(sizeof(int) * 4 * (size_t)m->nf);
    for (int f = 0; f < m->nf; f++) {
        const int *q = m->face_vert + 4 * f;
        fv[4 * f] = q[0]; fv[4 * f + 1] = q[3]; fv[4 * f + 2] = q[2]; fv[4 * f + 3] = q[1];
    }
    q2n_mesh *rm = em_mesh_build(m->nv, m->pos, m->nf, fv);
    free(fv);
    q2n_nurbs_model r = em_model_alloc(rm);
    for (int f = 0; f < m->nf; f++) {
        const q2n_bspline_surface *s = &in->patches[f];
        q2n_bspline_surface *d = &r.patches[f];
        em_surface_alloc(d, s->deg_v, s->deg_u, s->ncp_v, s->ncp_u, s->weights != NULL);
        memcpy(d->knots_u, s->knots_v, sizeof(double) * (size_t)(s->ncp_v + s->deg_v + 1));
        memcpy(d->knots_v, s->knots_u, sizeof(double) * (size_t)(s->ncp_u + s->deg_u + 1));
        for (int j = 0; j < s->ncp_v; j++)
            for (int i = 0; i < s->ncp_u; i++) {
                int a = j * s->ncp_u + i, b = i * s->ncp_v + j;
                memcpy(d->cp + 3 * b, s->cp + 3 * a, 3 * sizeof(double));
                if (s->weights) d->weights[b] = s->weights[a];
            }
    }
    *mesh_out = rm;
    return r;
}

/* Regular open grid (nx x ny faces) on a gently curved height field z = 0.1 sin(x) cos(y). */
static inline q2n_mesh *em_mesh_grid(int nx, int ny)
{
    int nv = (nx + 1) * (ny + 1);
    double *pos = (double *)malloc(sizeof(double) * 3 * (size_t)nv);
    int *fv = (int *)malloc(sizeof(int) * 4 * (size_t)(nx * ny));
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            double *p = pos + 3 * (j * (nx + 1) + i);
            p[0] = i; p[1] = j + 0.1 * i; p[2] = 0.3 * sin(0.9 * i) * cos(0.7 * j);
        }
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int *q = fv + 4 * (j * nx + i), v = j * (nx + 1) + i;
            q[0] = v; q[1] = v + 1; q[2] = v + nx + 2; q[3] = v + nx + 1;
        }
    q2n_mesh *m = em_mesh_build(nv, pos, nx * ny, fv);
    free(pos);
    free(fv);
    return m;
}

/* Whole file as a NUL-terminated string (caller frees), or NULL. */
static inline char *em_slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = (char *)malloc((size_t)n + 1);
    size_t k = fread(b, 1, (size_t)n, f);
    b[k] = 0;
    fclose(f);
    return b;
}

/* Value of "key": NUMBER / true / false / null in an audit or report JSON (keys used are unique). */
static inline double em_jnum(const char *json, const char *key)
{
    char pat[96];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = json ? strstr(json, pat) : NULL;
    if (!p) return NAN;
    p += strlen(pat);
    if (!strncmp(p, "true", 4)) return 1.0;
    if (!strncmp(p, "false", 5)) return 0.0;
    return strtod(p, NULL);
}

#endif
