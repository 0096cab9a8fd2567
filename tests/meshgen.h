/* meshgen.h — procedural test meshes written here (so a plain clone tests itself): tori with
 * optional random perturbation, open grids over a curved graph, one-ring "carpets". */
#ifndef Q2N_TEST_MESHGEN_H
#define Q2N_TEST_MESHGEN_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "patch/surface.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static inline double mg_rnd(unsigned *s) { *s = *s * 1103515245u + 12345u; return ((*s >> 8) & 0xffff) / 65536.0; }

/* Build a mesh from malloc'ed arrays and free them; reports a failure on stderr (NULL). */
static inline q2n_mesh *mg_finish(int nv, double *pos, int nf, int *fs, int *fv, const char *name)
{
    q2n_mesh *mesh = NULL;
    q2n_error err;
    if (q2n_mesh_from_arrays(nv, pos, nf, fs, fv, name, &mesh, &err)) fprintf(stderr, "%s: %s\n", name, err.message);
    free(pos); free(fs); free(fv);
    return mesh;
}

/* Torus with n x m quads (radii R, r); vertices jittered by up to jitter*r when jitter > 0;
 * uneven spacing in the long direction when uneven != 0. */
static inline q2n_mesh *mg_torus(int n, int m, double R, double r, double jitter, int uneven, unsigned seed)
{
    int nv = n * m;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = (int *)malloc(((size_t)nv + 1) * sizeof *fs), *fv = (int *)malloc(4 * (size_t)nv * sizeof *fv);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            double a = 2 * M_PI * i / n, b = 2 * M_PI * j / m;
            if (uneven) a += 0.25 * sin(a) * 2 * M_PI / n * 2;
            double *p = pos + 3 * (i * m + j);
            p[0] = (R + r * cos(b)) * cos(a);
            p[1] = (R + r * cos(b)) * sin(a);
            p[2] = r * sin(b);
            if (jitter > 0)
                for (int c = 0; c < 3; c++) p[c] += jitter * r * (2 * mg_rnd(&seed) - 1);
        }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            int f = i * m + j, i1 = (i + 1) % n, j1 = (j + 1) % m;
            fs[f] = 4 * f;
            fv[4 * f + 0] = i * m + j;
            fv[4 * f + 1] = i1 * m + j;
            fv[4 * f + 2] = i1 * m + j1;
            fv[4 * f + 3] = i * m + j1;
        }
    fs[nv] = 4 * nv;
    return mg_finish(nv, pos, nv, fs, fv, "torus");
}

/* The n x m torus of mg_torus (radii R, r; even, no jitter) with the quads listed in collapse[] (indices into the
 * torus' faces, in order of the list, each counted after the removals before it) collapsed along
 * their diagonal: corner 2 merges into corner 0 at their midpoint and the quad disappears, so corner
 * 0 gets valence 6 and corners 1 and 3 valence 3 — extraordinary vertices of valence 3, 6, 3 in a
 * row on a closed surface of genus 1. */
static inline q2n_mesh *mg_torus_pinched(int n, int m, double R, double r, const int *collapse, int nc)
{
    q2n_mesh *t = mg_torus(n, m, R, r, 0, 0, 0);
    if (!t) return NULL;
    int nv = t->nv, nf = t->nf;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fv = (int *)malloc(4 * (size_t)nf * sizeof *fv), *fs = (int *)malloc(((size_t)nf + 1) * sizeof *fs);
    int *ren = (int *)malloc((size_t)nv * sizeof *ren);
    if (pos) memcpy(pos, t->pos, 3 * (size_t)nv * sizeof *pos);
    if (fv) memcpy(fv, t->face_vert, 4 * (size_t)nf * sizeof *fv);
    q2n_mesh_free(t);
    if (!pos || !fv || !fs || !ren) { free(pos); free(fv); free(fs); free(ren); return NULL; }
    for (int c = 0; c < nc; c++) {
        int f = collapse[c], a = fv[4 * f], b = fv[4 * f + 2];
        for (int k = 0; k < 3; k++) pos[3 * a + k] = 0.5 * (pos[3 * a + k] + pos[3 * b + k]);
        memmove(fv + 4 * f, fv + 4 * (f + 1), sizeof *fv * 4 * (size_t)(nf - f - 1));
        nf--;
        for (int k = 0; k < 4 * nf; k++)
            if (fv[k] == b) fv[k] = a;
    }
    int used = 0; /* drop the merged vertices, keep the order of the rest */
    for (int v = 0; v < nv; v++) ren[v] = -1;
    for (int k = 0; k < 4 * nf; k++) ren[fv[k]] = 0;
    for (int v = 0; v < nv; v++)
        if (ren[v] == 0) {
            for (int k = 0; k < 3; k++) pos[3 * used + k] = pos[3 * v + k];
            ren[v] = used++;
        }
    for (int k = 0; k < 4 * nf; k++) fv[k] = ren[fv[k]];
    for (int f = 0; f <= nf; f++) fs[f] = 4 * f;
    free(ren);
    return mg_finish(used, pos, nf, fs, fv, "pinched torus");
}

/* Open n x m grid of quads over z = f(x,y), with uneven x spacing. */
static inline q2n_mesh *mg_grid(int n, int m, unsigned seed)
{
    int nv = (n + 1) * (m + 1), nf = n * m;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = (int *)malloc(((size_t)nf + 1) * sizeof *fs), *fv = (int *)malloc(4 * (size_t)nf * sizeof *fv);
    double x = 0;
    for (int i = 0; i <= n; i++) {
        for (int j = 0; j <= m; j++) {
            double *p = pos + 3 * (i * (m + 1) + j);
            double y = j * (1.0 + 0.3 * sin(j));
            p[0] = x + 0.05 * (2 * mg_rnd(&seed) - 1);
            p[1] = y;
            p[2] = 0.6 * sin(0.7 * x) * cos(0.5 * y);
        }
        x += 0.5 + mg_rnd(&seed);
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < m; j++) {
            int f = i * m + j;
            fs[f] = 4 * f;
            fv[4 * f + 0] = i * (m + 1) + j;
            fv[4 * f + 1] = (i + 1) * (m + 1) + j;
            fv[4 * f + 2] = (i + 1) * (m + 1) + j + 1;
            fv[4 * f + 3] = i * (m + 1) + j + 1;
        }
    fs[nf] = 4 * nf;
    return mg_finish(nv, pos, nf, fs, fv, "grid");
}

/* Hard meshes for the extraordinary-vertex constructions (issue 11): every triangle of a
 * triangle mesh split into three quads at its centroid and edge midpoints, so that the old
 * vertices become extraordinary vertices of twice their valence and the centroids valence-3 ones,
 * on opposite corners of every quad (extraordinary vertices sharing faces everywhere).  sphere:
 * new points pushed onto the unit sphere; scale: per-axis stretch applied last (anisotropic,
 * near-degenerate quads); noise: random displacement of every vertex. */
static inline q2n_mesh *mg_tri_to_quad(int nv0, const double *v0, int nt, const int *tri, int sphere, const double scale[3],
                                       double noise, unsigned seed, const char *name)
{
    int cap = nv0 + nt + 3 * nt;
    double *pos = (double *)malloc(3 * (size_t)cap * sizeof *pos);
    int *fs = (int *)malloc((3 * (size_t)nt + 1) * sizeof *fs), *fv = (int *)malloc(12 * (size_t)nt * sizeof *fv);
    int *ekey = (int *)malloc(2 * 3 * (size_t)nt * sizeof *ekey), *eidx = (int *)malloc(3 * (size_t)nt * sizeof *eidx), ne = 0;
    int nv = nv0;
    for (int i = 0; i < 3 * nv0; i++) pos[i] = v0[i];
#define MG_PUSH(P)                                                                                  \
    do {                                                                                            \
        double *q_ = pos + 3 * nv;                                                                  \
        for (int c_ = 0; c_ < 3; c_++) q_[c_] = (P)[c_];                                            \
        if (sphere) {                                                                               \
            double l_ = sqrt(q_[0] * q_[0] + q_[1] * q_[1] + q_[2] * q_[2]);                        \
            for (int c_ = 0; c_ < 3; c_++) q_[c_] /= l_;                                            \
        }                                                                                           \
        nv++;                                                                                       \
    } while (0)
    for (int t = 0; t < nt; t++) {
        const int *T = tri + 3 * t;
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = (v0[3 * T[0] + k] + v0[3 * T[1] + k] + v0[3 * T[2] + k]) / 3;
        int ci = nv;
        MG_PUSH(c);
        int mid[3];
        for (int e = 0; e < 3; e++) {
            int a = T[e], b = T[(e + 1) % 3], lo = a < b ? a : b, hi = a < b ? b : a, found = -1;
            for (int k = 0; k < ne; k++)
                if (ekey[2 * k] == lo && ekey[2 * k + 1] == hi) found = eidx[k];
            if (found < 0) {
                double m[3];
                for (int k = 0; k < 3; k++) m[k] = 0.5 * (v0[3 * a + k] + v0[3 * b + k]);
                found = nv;
                MG_PUSH(m);
                ekey[2 * ne] = lo;
                ekey[2 * ne + 1] = hi;
                eidx[ne++] = found;
            }
            mid[e] = found;
        }
        for (int k = 0; k < 3; k++) { /* quad at corner T[k]: T[k], mid(k), centre, mid(k-1) */
            int f = 3 * t + k;
            fs[f] = 4 * f;
            fv[4 * f + 0] = T[k];
            fv[4 * f + 1] = mid[k];
            fv[4 * f + 2] = ci;
            fv[4 * f + 3] = mid[(k + 2) % 3];
        }
    }
#undef MG_PUSH
    fs[3 * nt] = 12 * nt;
    for (int i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) pos[3 * i + k] = pos[3 * i + k] * scale[k] + noise * (2 * mg_rnd(&seed) - 1);
    free(ekey);
    free(eidx);
    return mg_finish(nv, pos, 3 * nt, fs, fv, name);
}

/* The icosahedron: its 20 triangles (counter-clockwise seen from outside) on the 12 vertices that
 * mg_icosahedron writes into v, on the unit sphere. */
static const int mg_icosa_tri[60] = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                                     3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
static inline void mg_icosahedron(double v[36])
{
    const double t = (1 + sqrt(5.0)) / 2;
    const double c[36] = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
    for (int i = 0; i < 12; i++) {
        double l = sqrt(c[3 * i] * c[3 * i] + c[3 * i + 1] * c[3 * i + 1] + c[3 * i + 2] * c[3 * i + 2]);
        for (int k = 0; k < 3; k++) v[3 * i + k] = c[3 * i + k] / l;
    }
}

/* Icosahedron (12 valence-10 and 20 valence-3 extraordinary vertices after the split, 60 quads). */
static inline q2n_mesh *mg_icosa_quad(double noise, unsigned seed)
{
    double v[36];
    mg_icosahedron(v);
    static const double one[3] = {1, 1, 1};
    return mg_tri_to_quad(12, v, 20, mg_icosa_tri, 1, one, noise, seed, "icosahedron split into quads");
}

/* Rhombic triacontahedron: every vertex extraordinary (the icosahedron's 12 of valence 5 and its
 * 20 face centres of valence 3, at radius `centre`), 30 rhombi, one per icosahedron edge, on an
 * ellipsoid with the given axes.  On 2 : 1 : 0.5 the rhombi across the short axis are 6 : 1, with
 * corners of about 160 degrees at their valence-3 vertices. */
static inline q2n_mesh *mg_triacontahedron(double ax, double ay, double az, double centre)
{
    const double sc[3] = {ax, ay, az};
    const int *tri = mg_icosa_tri;
    double ico[36], *pos = (double *)malloc(32 * 3 * sizeof *pos);
    int *fs = (int *)malloc(31 * sizeof *fs), *fv = (int *)malloc(120 * sizeof *fv), nf = 0;
    mg_icosahedron(ico);
    for (int i = 0; i < 12; i++)
        for (int k = 0; k < 3; k++) pos[3 * i + k] = ico[3 * i + k] * sc[k];
    for (int f = 0; f < 20; f++) {
        double c[3] = {0, 0, 0}, l = 0;
        for (int k = 0; k < 3; k++) {
            for (int j = 0; j < 3; j++) c[k] += ico[3 * tri[3 * f + j] + k];
            l += c[k] * c[k];
        }
        for (int k = 0; k < 3; k++) pos[3 * (12 + f) + k] = c[k] / sqrt(l) * centre * sc[k];
    }
    for (int f = 0; f < 20; f++) /* edge a -> b of triangle f (counter-clockwise) and its twin */
        for (int j = 0; j < 3; j++) {
            int a = tri[3 * f + j], b = tri[3 * f + (j + 1) % 3];
            if (a > b) continue;
            for (int g = 0; g < 20; g++)
                for (int i = 0; i < 3; i++)
                    if (tri[3 * g + i] == b && tri[3 * g + (i + 1) % 3] == a) {
                        fs[nf] = 4 * nf;
                        fv[4 * nf] = a, fv[4 * nf + 1] = 12 + g, fv[4 * nf + 2] = b, fv[4 * nf + 3] = 12 + f;
                        nf++;
                    }
        }
    fs[nf] = 4 * nf;
    return mg_finish(32, pos, nf, fs, fv, "rhombic triacontahedron");
}

/* Octahedron (6 valence-8 and 8 valence-3 extraordinary vertices, 24 quads) on an ellipsoid with
 * the given axes (3 : 1 : 0.5 gives quads of aspect up to ~6). */
static inline q2n_mesh *mg_octa_quad(double ax, double ay, double az)
{
    static const double v[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    static const int tri[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    double sc[3] = {ax, ay, az};
    return mg_tri_to_quad(6, v, 8, tri, 1, sc, 0, 1, "octahedron split into quads");
}

/* The faces of mg_polar_star and mg_sphere_pole on their vertices (pos: the apex, then `rings`
 * rings of 2n, malloc'ed; taken over): n kites around the apex, each from a spoke end over the
 * in-between vertex of ring 1 to the next spoke end, then 2n quads per ring step. */
static inline q2n_mesh *mg_kite_rings(int n, int rings, double *pos, const char *name)
{
    int nv = 1 + 2 * n * rings, nf = n + 2 * n * (rings - 1);
    int *fs = (int *)malloc(((size_t)nf + 1) * sizeof *fs), *fv = (int *)malloc(4 * (size_t)nf * sizeof *fv);
#define MG_RV(k, s) (1 + ((k) - 1) * 2 * n + ((s) % (2 * n)))
    int f = 0;
    for (int i = 0; i < n; i++, f++) {
        fs[f] = 4 * f;
        fv[4 * f] = 0;
        fv[4 * f + 1] = MG_RV(1, 2 * i);
        fv[4 * f + 2] = MG_RV(1, 2 * i + 1);
        fv[4 * f + 3] = MG_RV(1, 2 * i + 2);
    }
    for (int k = 1; k < rings; k++)
        for (int s = 0; s < 2 * n; s++, f++) {
            fs[f] = 4 * f;
            fv[4 * f] = MG_RV(k, s);
            fv[4 * f + 1] = MG_RV(k + 1, s);
            fv[4 * f + 2] = MG_RV(k + 1, s + 1);
            fv[4 * f + 3] = MG_RV(k, s + 1);
        }
#undef MG_RV
    fs[nf] = 4 * nf;
    return mg_finish(nv, pos, nf, fs, fv, name);
}

/* Open polar grid around one extraordinary vertex of valence n: `rings` rings of 2n vertices,
 * a Gaussian bump with a 3-fold ripple, x stretched by aniso (thin sectors for aniso >> 1). */
static inline q2n_mesh *mg_polar_star(int n, int rings, double aniso)
{
    double *pos = (double *)malloc(3 * ((size_t)1 + 2 * (size_t)n * rings) * sizeof *pos);
    pos[0] = pos[1] = 0;
    pos[2] = 0.3;
    for (int k = 1; k <= rings; k++)
        for (int s = 0; s < 2 * n; s++) {
            double a = M_PI * s / n, x = aniso * k * cos(a), y = k * sin(a), *p = pos + 3 * (1 + (k - 1) * 2 * n + s);
            p[0] = x;
            p[1] = y;
            p[2] = 0.3 * exp(-(x * x + y * y) / 2) + 0.05 * sin(3 * a) * k;
        }
    return mg_kite_rings(n, rings, pos, "polar star");
}

/* Surface of a union of unit cubes ("polycube", CAD-like: flat faces, sharp convex and concave
 * edges), one quad per exposed cube face, outward oriented: convex corners are valence-3 vertices,
 * concave ones valence 5 or 6.  cells: ncell integer cube positions in 0..7. */
static inline q2n_mesh *mg_polycube(int ncell, const int (*cell)[3], const char *name)
{
    int nf = 0, nv = 0, *key = (int *)malloc(729 * sizeof *key);
    int *fs = (int *)malloc(((size_t)6 * ncell + 1) * sizeof *fs), *fv = (int *)malloc(24 * (size_t)ncell * sizeof *fv);
    double *pos = (double *)malloc(3 * 729 * sizeof *pos);
    for (int i = 0; i < 729; i++) key[i] = -1;
    for (int c = 0; c < ncell; c++)
        for (int d = 0; d < 3; d++)
            for (int sg = -1; sg <= 1; sg += 2) {
                int nb[3] = {cell[c][0], cell[c][1], cell[c][2]}, cov = 0;
                nb[d] += sg;
                for (int o = 0; o < ncell; o++) cov |= cell[o][0] == nb[0] && cell[o][1] == nb[1] && cell[o][2] == nb[2];
                if (cov) continue;
                int o[3] = {cell[c][0], cell[c][1], cell[c][2]}, a = (d + 1) % 3, b = (d + 2) % 3;
                if (sg > 0) o[d]++;
                /* corners o + u e_a + v e_b at the face corners' (u, v): counter-clockwise about +e_d */
                fs[nf] = 4 * nf;
                for (int k = 0; k < 4; k++) {
                    int kk = sg > 0 ? k : (4 - k) % 4, p[3] = {o[0], o[1], o[2]};
                    p[a] += q2n_corner_uv[kk][0];
                    p[b] += q2n_corner_uv[kk][1];
                    int id = (p[0] * 9 + p[1]) * 9 + p[2];
                    if (key[id] < 0) {
                        key[id] = nv;
                        for (int q = 0; q < 3; q++) pos[3 * nv + q] = p[q];
                        nv++;
                    }
                    fv[4 * nf + k] = key[id];
                }
                nf++;
            }
    fs[nf] = 4 * nf;
    free(key);
    return mg_finish(nv, pos, nf, fs, fv, name);
}

/* The surface of a 2 x 2 x 2 block of unit cubes (every corner valence 3, 24 quads) with its corner
 * (2, 2, 2) (and with both != 0 the opposite corner too) moved away from the centre to `pull` times
 * its distance: a spike whose tip faces are long, skewed quads and whose tip's three edges are nearly
 * parallel. */
static inline q2n_mesh *mg_spike_cube(double pull, int both)
{
    static const int cells[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    q2n_mesh *m = mg_polycube(8, cells, both ? "cube with two spikes" : "cube with a spike");
    for (int v = 0; m && v < m->nv; v++) {
        double *p = m->pos + 3 * (size_t)v;
        int tip = p[0] == 2 && p[1] == 2 && p[2] == 2, far = both && p[0] == 0 && p[1] == 0 && p[2] == 0;
        if (tip || far)
            for (int q = 0; q < 3; q++) p[q] = 1 + pull * (p[q] - 1);
    }
    return m;
}

/* A thin plate: the surface of n x n x 1 unit cubes (n <= 8; one quad across the thickness) scaled
 * to 1 x 1 x t: eight valence-3 corners, side faces 1/n by t. */
static inline q2n_mesh *mg_thin_plate(int n, double t)
{
    int cells[64][3], k = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) cells[k][0] = i, cells[k][1] = j, cells[k][2] = 0, k++;
    q2n_mesh *m = mg_polycube(k, (const int (*)[3])cells, "thin plate");
    for (int v = 0; m && v < m->nv; v++) {
        double *p = m->pos + 3 * (size_t)v;
        p[0] /= n, p[1] /= n, p[2] *= t;
    }
    return m;
}

/* A lip as a tessellator leaves it: a quarter turn of a surface of revolution (radius 8 about the y
 * axis; a U-shaped profile of 5 points, 0.5 s wide and high: up the inner wall, over the top, down
 * the outer one) on a grid of a angular steps, every quad cut into two triangles along a diagonal,
 * then split into quads (mg_tri_to_quad).  Each angular step is ~3 long, each profile step
 * 0.12-0.5 s: sliver triangles of aspect ~6-50 whose split leaves needle quads with 1-3-degree
 * corners and nearly straight ones on a tightly curved fan (the charts' hard case: fan_angles).
 * split 0: the triangles themselves, for Catmull-Clark (--subdivide 1) to split. */
static inline q2n_mesh *mg_lip_split(int a, double s, int split)
{
    static const double prof[5][2] = {{0, 0}, {0.1, 0.37}, {0, 0.49}, {-0.23, 0.37}, {-0.5, 0}};
    int nv = 5 * (a + 1), nt = 8 * a;
    double *v = (double *)malloc(3 * (size_t)nv * sizeof *v);
    int *t = (int *)malloc(3 * (size_t)nt * sizeof *t), k = 0;
    for (int i = 0; i <= a; i++)
        for (int j = 0; j < 5; j++) {
            double th = 0.5 * M_PI * i / a, r = 8 + s * prof[j][0];
            double *p = v + 3 * (5 * i + j);
            p[0] = r * cos(th), p[1] = s * prof[j][1], p[2] = r * sin(th);
        }
    for (int i = 0; i < a; i++)
        for (int j = 0; j < 4; j++) {
            int q[4] = {5 * i + j, 5 * (i + 1) + j, 5 * (i + 1) + j + 1, 5 * i + j + 1};
            int tri[6] = {q[0], q[1], q[2], q[2], q[3], q[0]};
            for (int c = 0; c < 6; c++) t[k++] = tri[c];
        }
    if (!split) { /* the triangles themselves (for --subdivide) */
        int *fs = (int *)malloc((size_t)(nt + 1) * sizeof *fs);
        for (int f = 0; f <= nt; f++) fs[f] = 3 * f;
        return mg_finish(nv, v, nt, fs, t, "triangulated lip");
    }
    const double one[3] = {1, 1, 1};
    q2n_mesh *m = mg_tri_to_quad(nv, v, nt, t, 0, one, 0, 1, "lip");
    free(v);
    free(t);
    return m;
}

static inline q2n_mesh *mg_lip(int a, double s) { return mg_lip_split(a, s, 1); }

/* Two rings of quads around a valence-5 vertex whose edges leave at 0, 40, 80, 120 and 160 degrees
 * on a gently waved height field: the face of the last sector (200 degrees) is a dart, non-convex
 * at the vertex, a reflex corner (fan_angles). */
static inline q2n_mesh *mg_dart_fan(void)
{
    static const double ang[5] = {0, 40, 80, 120, 160};
    double *pos = (double *)malloc(3 * 21 * sizeof *pos);
    int *fs = (int *)malloc(16 * sizeof *fs), *fv = (int *)malloc(60 * sizeof *fv), nv = 1, spk[5][2], cor[5][2];
    pos[0] = pos[1] = pos[2] = 0;
#define MG_DART_PUT(X, Y)                                                                           \
    do {                                                                                            \
        double x_ = (X), y_ = (Y);                                                                  \
        pos[3 * nv] = x_, pos[3 * nv + 1] = y_, pos[3 * nv + 2] = 0.15 * sin(1.3 * x_) * cos(0.9 * y_); \
        nv++;                                                                                       \
    } while (0)
    for (int k = 0; k < 5; k++)
        for (int r = 1; r <= 2; r++) {
            spk[k][r - 1] = nv;
            MG_DART_PUT(r * cos(ang[k] * M_PI / 180), r * sin(ang[k] * M_PI / 180));
        }
    for (int k = 0; k < 5; k++) {
        double a0 = ang[k], a1 = k < 4 ? ang[k + 1] : 360, am = 0.5 * (a0 + a1) * M_PI / 180, rr = k < 4 ? 1.2 : 0.96;
        for (int r = 1; r <= 2; r++) {
            cor[k][r - 1] = nv;
            MG_DART_PUT(r * rr * cos(am), r * rr * sin(am));
        }
    }
#undef MG_DART_PUT
    int f = 0;
    for (int k = 0; k < 5; k++) {
        int k1 = (k + 1) % 5;
        int q[3][4] = {{0, spk[k][0], cor[k][0], spk[k1][0]},
                       {spk[k][0], spk[k][1], cor[k][1], cor[k][0]},
                       {cor[k][0], cor[k][1], spk[k1][1], spk[k1][0]}};
        for (int i = 0; i < 3; i++, f++) {
            fs[f] = 4 * f;
            for (int c = 0; c < 4; c++) fv[4 * f + c] = q[i][c];
        }
    }
    fs[15] = 60;
    return mg_finish(nv, pos, 15, fs, fv, "dart fan");
}

/* A valence-3 vertex (the last point) whose fan has two wide sectors side by side, as a sliver
 * triangle split at its centroid leaves them: a near-parallelogram of 161.5 degrees there (corners
 * 164.9, 17.4, 161.5, 16.1) and a quad that is nearly a triangle at 160.9 degrees, then 37.5
 * degrees.  The near-triangle's sector is capped at EV_CHART_MAX_ANGLE, the parallelogram may keep
 * its own angle (ev_derivatives.c sector_cap): two sectors capped in turn (fan_angles). */
static inline q2n_mesh *mg_wide_pair_fan(void)
{
    static const double p[21] = {1.1188, -0.2354, -0.5594, 0.4201,  -0.0654, 0.0599, 0.7468,
                                 -0.1431, -0.1119, -1.7146, 0.4139,  0.4743, -0.181, 0.0476,
                                 0.1921, -0.5194, 0.0223,  -0.0691, 0.1292, -0.04,  0.0141};
    static const int q[12] = {3, 5, 6, 4, 0, 2, 6, 5, 1, 4, 6, 2};
    double *pos = (double *)malloc(sizeof p);
    int *fs = (int *)malloc(4 * sizeof *fs), *fv = (int *)malloc(sizeof q);
    memcpy(pos, p, sizeof p);
    memcpy(fv, q, sizeof q);
    for (int f = 0; f <= 3; f++) fs[f] = 4 * f;
    return mg_finish(7, pos, 3, fs, fv, "wide pair fan");
}

/* A unit cube as a subdivision modeller builds a box with support loops: 4 x 4 quads per side at
 * the breakpoints 0, d, 1/2, 1 - d, 1 of every axis (holding edge loops at d from every edge;
 * corners valence 3; the 2 x 2 quads in the middle of each side have planar one-rings). */
static inline q2n_mesh *mg_loop_box(double d)
{
    int cells[64][3], k = 0;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            for (int l = 0; l < 4; l++) cells[k][0] = i, cells[k][1] = j, cells[k][2] = l, k++;
    q2n_mesh *m = mg_polycube(k, (const int (*)[3])cells, "box with support loops");
    const double b[5] = {0, d, 0.5, 1 - d, 1};
    for (int v = 0; m && v < m->nv; v++)
        for (int q = 0; q < 3; q++) m->pos[3 * (size_t)v + q] = b[(int)m->pos[3 * (size_t)v + q]];
    return m;
}

/* An open n-sided pyramid of n quads around its apex (0, 0, h), the only extraordinary vertex
 * (n != 4): quad k is (apex, rim vertex k, rim point k, rim vertex k + 1), rim vertices on the
 * unit circle at z = 0, rim point k at `bulge` times the distance of the rim edge's midpoint from
 * the axis.  Every rim point is a boundary corner of one face, every rim vertex a boundary vertex
 * of two; bulge 1 puts the rim points on the rim edges (straight corners, up to rounding), above 1
 * the faces' corners there are convex (n = 6, bulge 1.15: 151 degrees), below 1 reflex (0.9: 199). */
static inline q2n_mesh *mg_rim_pyramid(int n, double h, double bulge)
{
    int nv = 2 * n + 1, nf = n;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = (int *)malloc((size_t)(nf + 1) * sizeof *fs), *fv = (int *)malloc(4 * (size_t)nf * sizeof *fv);
    if (!pos || !fs || !fv) { free(pos); free(fs); free(fv); return NULL; }
    pos[0] = 0, pos[1] = 0, pos[2] = h;
    for (int k = 0; k < n; k++) {
        double a = 2 * M_PI * k / n, r = cos(M_PI / n) * bulge, *p = pos + 3 * (1 + k), *q = pos + 3 * (1 + n + k);
        p[0] = cos(a), p[1] = sin(a), p[2] = 0;
        q[0] = r * cos(a + M_PI / n), q[1] = r * sin(a + M_PI / n), q[2] = 0;
        fs[k] = 4 * k;
        fv[4 * k] = 0, fv[4 * k + 1] = 1 + k, fv[4 * k + 2] = 1 + n + k, fv[4 * k + 3] = 1 + (k + 1) % n;
    }
    fs[nf] = 4 * nf;
    return mg_finish(nv, pos, nf, fs, fv, "rim pyramid");
}

/* A cylinder of n sides and `rows` rows of quads, height h (radius 1, axis z), closed by two flat
 * n-gon caps: faces 0 .. n rows - 1 the side, then the bottom cap (z = 0) and the top one (z = h). */
static inline q2n_mesh *mg_ngon_cylinder(int n, int rows, double h)
{
    int nv = n * (rows + 1), nf = n * rows + 2;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = (int *)malloc(((size_t)nf + 1) * sizeof *fs), *fv = (int *)malloc((4 * (size_t)n * rows + 2 * (size_t)n) * sizeof *fv);
    for (int r = 0; r <= rows; r++)
        for (int k = 0; k < n; k++) {
            double a = 2 * M_PI * k / n, *p = pos + 3 * (r * n + k);
            p[0] = cos(a);
            p[1] = sin(a);
            p[2] = h * r / rows;
        }
    int f = 0, q = 0;
    for (int r = 0; r < rows; r++)
        for (int k = 0; k < n; k++, f++) {
            fs[f] = q;
            fv[q++] = r * n + k;
            fv[q++] = r * n + (k + 1) % n;
            fv[q++] = (r + 1) * n + (k + 1) % n;
            fv[q++] = (r + 1) * n + k;
        }
    fs[f++] = q;
    for (int k = n - 1; k >= 0; k--) fv[q++] = k;
    fs[f++] = q;
    for (int k = 0; k < n; k++) fv[q++] = rows * n + k;
    fs[f] = q;
    return mg_finish(nv, pos, nf, fs, fv, "capped cylinder");
}

/* A unit UV sphere of n sectors and `rings` rings of vertices (none at the poles), closed by two
 * n-gons around the poles: faces 0 .. n (rings - 1) - 1 the quads, then the north and south n-gon. */
static inline q2n_mesh *mg_uv_ngon_sphere(int n, int rings)
{
    int nv = n * rings, nf = n * (rings - 1) + 2;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = (int *)malloc(((size_t)nf + 1) * sizeof *fs), *fv = (int *)malloc((4 * (size_t)n * rings + 2 * (size_t)n) * sizeof *fv);
    for (int r = 0; r < rings; r++)
        for (int k = 0; k < n; k++) {
            double th = M_PI * (r + 1) / (rings + 1), ph = 2 * M_PI * k / n, *p = pos + 3 * (r * n + k);
            p[0] = sin(th) * cos(ph), p[1] = sin(th) * sin(ph), p[2] = cos(th);
        }
    int f = 0, q = 0;
    for (int r = 0; r + 1 < rings; r++)
        for (int k = 0; k < n; k++, f++) {
            fs[f] = q;
            fv[q++] = r * n + k, fv[q++] = (r + 1) * n + k, fv[q++] = (r + 1) * n + (k + 1) % n, fv[q++] = r * n + (k + 1) % n;
        }
    fs[f++] = q;
    for (int k = 0; k < n; k++) fv[q++] = k;
    fs[f++] = q;
    for (int k = n - 1; k >= 0; k--) fv[q++] = (rings - 1) * n + k;
    fs[f] = q;
    return mg_finish(nv, pos, nf, fs, fv, "UV sphere with n-gon poles");
}

/* The same after one Catmull–Clark step (each cap becomes n kites around a valence-n vertex, its
 * rim n valence-3 vertices). */
static inline q2n_mesh *mg_capped_cylinder(int n, int rows, double h)
{
    q2n_mesh *m = mg_ngon_cylinder(n, rows, h), *sub = NULL;
    q2n_error err;
    if (m && q2n_mesh_subdivide(m, 1, &sub, &err)) fprintf(stderr, "capped cylinder: %s\n", err.message);
    q2n_mesh_free(m);
    return sub;
}

/* A cylinder of 4n sides and `rows` rows of quads (radius 1, axis z, height h) closed by two n x n
 * grids mapped onto the disk by the elliptical grid mapping (a modeller's "grid fill"): each grid's
 * four corners lie on the rim as vertices of valence 3, where the cap's corner face is a kite whose
 * corner there is nearly straight (155.7 degrees at n = 4).  bench/sweep.py's cyl_gridfill at n = 4,
 * rows = 3, h = 1.5. */
static inline q2n_mesh *mg_gridfill_cylinder(int n, int rows, double h)
{
    int g = n + 1, M = 4 * n, nv = 2 * g * g + (rows - 1) * M, nf = 2 * n * n + rows * M, k = 0, q = 0;
    double *pos = (double *)malloc(3 * (size_t)nv * sizeof *pos);
    int *fs = (int *)malloc((size_t)(nf + 1) * sizeof *fs), *fv = (int *)malloc(4 * (size_t)nf * sizeof *fv);
    int *rim = (int *)malloc(2 * (size_t)M * sizeof *rim), *ring = (int *)malloc((size_t)(rows + 1) * M * sizeof *ring);
    if (!pos || !fs || !fv || !rim || !ring) { free(pos); free(fs); free(fv); free(rim); free(ring); return NULL; }
    for (int i = 0; i < n; i++) rim[2 * k] = i, rim[2 * k + 1] = 0, k++;      /* the grid's boundary, */
    for (int j = 0; j < n; j++) rim[2 * k] = n, rim[2 * k + 1] = j, k++;      /* counter-clockwise */
    for (int i = n; i > 0; i--) rim[2 * k] = i, rim[2 * k + 1] = n, k++;
    for (int j = n; j > 0; j--) rim[2 * k] = 0, rim[2 * k + 1] = j, k++;
    for (int c = 0; c < 2; c++) { /* cap c: vertices c g^2 + i g + j, the bottom one facing down */
        for (int i = 0; i < g; i++)
            for (int j = 0; j < g; j++) {
                double a = 2.0 * i / n - 1, b = 2.0 * j / n - 1, *p = pos + 3 * (c * g * g + i * g + j);
                p[0] = a * sqrt(1 - b * b / 2), p[1] = b * sqrt(1 - a * a / 2), p[2] = c * h;
            }
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                int v[4] = {c * g * g + i * g + j, c * g * g + (i + 1) * g + j, c * g * g + (i + 1) * g + j + 1, c * g * g + i * g + j + 1};
                fs[q] = 4 * q;
                for (int t = 0; t < 4; t++) fv[4 * q + t] = v[c ? t : 3 - t];
                q++;
            }
    }
    for (int t = 0; t < M; t++) {
        ring[t] = rim[2 * t] * g + rim[2 * t + 1];
        ring[rows * M + t] = g * g + ring[t];
    }
    for (int r = 1; r < rows; r++)
        for (int t = 0; t < M; t++) {
            int v = 2 * g * g + (r - 1) * M + t;
            ring[r * M + t] = v;
            pos[3 * v] = pos[3 * ring[t]], pos[3 * v + 1] = pos[3 * ring[t] + 1], pos[3 * v + 2] = h * r / rows;
        }
    for (int r = 0; r < rows; r++)
        for (int t = 0; t < M; t++) {
            fs[q] = 4 * q;
            fv[4 * q] = ring[r * M + t], fv[4 * q + 1] = ring[r * M + (t + 1) % M];
            fv[4 * q + 2] = ring[(r + 1) * M + (t + 1) % M], fv[4 * q + 3] = ring[(r + 1) * M + t];
            q++;
        }
    fs[nf] = 4 * nf;
    free(rim);
    free(ring);
    return mg_finish(nv, pos, nf, fs, fv, "grid-filled cylinder");
}

/* The pole of a UV sphere whose triangle fan was merged into quads in pairs (a modeller's "triangles
 * to quads"): n kites around a valence-n apex on the unit sphere, each kite's fourth vertex on the
 * first ring between two spoke ends (valence 3, its kite angle pi - pi/n: nearly a triangle), then
 * rings - 1 rows of 2n quads, ring k at polar angle k * dtheta (the quads beside the kites are
 * slivers: 2 sin(dtheta) sin(pi/2n) wide, dtheta high). */
static inline q2n_mesh *mg_sphere_pole(int n, int rings, double dtheta)
{
    double *pos = (double *)malloc(3 * ((size_t)1 + 2 * (size_t)n * rings) * sizeof *pos);
    pos[0] = pos[1] = 0;
    pos[2] = 1;
    for (int k = 1; k <= rings; k++)
        for (int s = 0; s < 2 * n; s++) {
            double a = M_PI * s / n, th = k * dtheta, *p = pos + 3 * (1 + (k - 1) * 2 * n + s);
            p[0] = sin(th) * cos(a);
            p[1] = sin(th) * sin(a);
            p[2] = cos(th);
        }
    return mg_kite_rings(n, rings, pos, "sphere pole");
}

#endif
