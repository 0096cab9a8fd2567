/* fit_check.h — checks on a fitted q2n_nurbs_model shared by the fit tests. */
#ifndef Q2N_TEST_FIT_CHECK_H
#define Q2N_TEST_FIT_CHECK_H

#include <string.h>

#include "fit/bspline.h"

/* 1 when the two patches of every interior edge have bit-identical boundary control points
 * (the watertightness the export relies on), traversed in opposite directions. */
static inline int fit_shared_rows_identical(const q2n_nurbs_model *md)
{
    static const int cuv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const q2n_mesh *m = md->mesh;
    for (int e = 0; e < m->ne; e++) {
        int h = m->edge_he[e], ht = m->he_twin[h];
        if (ht < 0) continue;
        int f[2] = {m->he_face[h], m->he_face[ht]}, sd[2] = {h - m->face_start[f[0]], ht - m->face_start[f[1]]};
        const q2n_bspline_surface *P[2] = {&md->patches[f[0]], &md->patches[f[1]]};
        int nt = (sd[0] & 1) ? P[0]->ncp_v : P[0]->ncp_u;
        for (int it = 0; it < nt; it++) {
            const double *pt[2];
            for (int x = 0; x < 2; x++) {
                int i = x ? nt - 1 - it : it;
                const int *c0 = cuv[sd[x]], *c1 = cuv[(sd[x] + 1) & 3];
                int a = c0[0] * (P[x]->ncp_u - 1) + i * (c1[0] - c0[0]), b = c0[1] * (P[x]->ncp_v - 1) + i * (c1[1] - c0[1]);
                pt[x] = P[x]->cp + 3 * (b * P[x]->ncp_u + a);
            }
            if (memcmp(pt[0], pt[1], 3 * sizeof(double)) != 0) return 0;
        }
    }
    return 1;
}

#endif
