/* meshgen.h — procedural test meshes written here (so a plain clone tests itself): tori with
 * optional random perturbation, open grids over a curved graph, one-ring "carpets". */
#ifndef Q2N_TEST_MESHGEN_H
#define Q2N_TEST_MESHGEN_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "mesh/mesh.h"

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

#endif
