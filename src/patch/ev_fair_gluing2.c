/* ev_fair_gluing2.c — polynomial gluing of the fair construction's G2 patches (K = 2), the orders
 * above the twist (docs/extraordinary.md, "Polynomial gluing of G2 patches").
 *
 * Corner maps.  Every datum a face delivers at its corner at vertex v is the vertex's jet P composed
 * with a corner map φ from the face's corner coordinates (a along one side from the corner, b along the
 * other, both in patch parameters) into the vertex's chart.  With the smoothsteps φ is linear,
 * φ(a, b) = a d u + b e_w w, and every corner agrees.  With α and β polynomials the derived face's
 * data along an edge are those of the base face composed with the gluing map
 *     ψ(a, b) = (a + B(a) b + ½ B2(a) b²,  α̃(a) b + ½ A2(a) b²),
 * (∂b S_G = α̃ ∂b S_F + B ∂a S_F and ∂b² S_G = α̃² ∂b² S_F + 2 α̃ B ∂a∂b S_F + B² ∂a² S_F + A2 ∂b S_F
 * + B2 ∂a S_F: the G1 and G2 relations, formulas.md §4.2, A2 and B2 their tangential terms γ, δ, in
 * the end's own a = s or 1 - s), so the derived face's corner map is φ_G = φ_F ∘ ψ.  Both sides of the
 * derived face's corner agree when its corner map, as its other side uses it, is that composition up to
 * a², b² — the coefficients of a b (the twist r: q2n_ev_fair_poly_gluing), of b² (zero: the other side's
 * edge is straight in the chart), and of a² b, a b², a² b² (here).  Per face corner three chart vectors
 * c21, c12, c22 (fe_side.cm), per derived side and end the values and first two derivatives of A2 and
 * B2 (fe_side.tg): the b² equation fixes A2(0), B2(0) (−2 α̃ B r_F, in the directions w_F and u), and
 * per end the three others
 *     c_G[ij] = (φ_F ∘ ψ)[ij],   ij = 21, 12, 22,
 * are linear in the c's and in A2', B2', A2'', B2''.  The a² b equations involve the c's only; A2' and B2'
 * span the chart in the a b² coefficient, A2'' and B2'' in the a² b² one, so those equations always hold
 * whatever the c's.  Per vertex the c's are the least change from zero that meets its a² b equations
 * (LAPACK's minimum-norm least squares), then each relation's four tangential unknowns meet its a b² and
 * a² b² equations (a 4 x 4 solve).  The jets enter nowhere: the
 * corner maps are fixed before the energy solve, which sees the patches linear in the jets as before
 * (ev_fair_patch.c side_ends_map composes each jet with its base face's corner map). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"
#include "patch/ev_fair_internal.h"
#include "patch/ev_policy.h"

static int fv(const q2n_mesh *m, int f, int c) { return m->face_vert[m->face_start[f] + c]; }

/* The corner of face f at vertex v (-1: none). */
static int corner_at(const q2n_mesh *m, int f, int v)
{
    for (int c = 0; c < 4; c++)
        if (fv(m, f, c) == v) return c;
    return -1;
}

/* G = F ∘ ψ truncated at a², b², F a chart-valued corner map (F[0][0] = 0), ψ from the Taylor
 * coefficients of α̃, B, A2, B2 about a = 0 (the products through ev_jet4.h's, whose terms beyond a² are
 * left out). */
static void compose(const double F[3][3][2], const double al[3], const double bt[3], const double ta[3], const double tb[3],
                    double G[3][3][2])
{
    double ap[3][EV_MA][EV_MB], bp[3][EV_MA][EV_MB]; /* powers 0..2 of a' and b' */
    memset(ap, 0, sizeof ap);
    memset(bp, 0, sizeof bp);
    ap[0][0][0] = bp[0][0][0] = 1;
    ap[1][1][0] = 1;
    for (int i = 0; i < 3; i++) {
        ap[1][i][1] += bt[i];
        ap[1][i][2] += 0.5 * tb[i];
        bp[1][i][1] += al[i];
        bp[1][i][2] += 0.5 * ta[i];
    }
    ev_bp_mul((const double (*)[EV_MB])ap[1], (const double (*)[EV_MB])ap[1], ap[2]);
    ev_bp_mul((const double (*)[EV_MB])bp[1], (const double (*)[EV_MB])bp[1], bp[2]);
    memset(G, 0, sizeof(double) * 18);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            if (F[i][j][0] == 0 && F[i][j][1] == 0) continue;
            double P[EV_MA][EV_MB];
            ev_bp_mul((const double (*)[EV_MB])ap[i], (const double (*)[EV_MB])bp[j], P);
            for (int k = 0; k < 3; k++)
                for (int l = 0; l < 3; l++)
                    for (int c = 0; c < 2; c++) G[k][l][c] += P[k][l] * F[i][j][c];
        }
}

/* One derived side's end at the vertex: the faces' slots and what the equations need. */
typedef struct g2_rel {
    int i, sd, end;      /* derived face (list index), its side, the side's end at the vertex */
    int sG, sF;          /* corner slots of the derived and the base face */
    int tG, tF;          /* 1: that face's side on the edge runs along v (its corner terms transposed) */
    double F[3][3][2];   /* the base face's corner map without its unknowns */
    double al[3], bt[3]; /* α̃, B about the end */
    double ta0, tb0;     /* A2(0), B2(0) */
    double sw, su;       /* scales of the A2, B2 unknowns: e_w, d */
} g2_rel;

/* The six equations of relation R for the unknowns x (slots: 6 per corner, then 4 per relation at
 * index xr): out = (φ_F ∘ ψ)[ij] - c_G[ij], ij = 21, 12, 22. */
static void rel_residual(const g2_rel *R, const double *x, int xr, double out[6])
{
    double F[3][3][2], G[3][3][2];
    memcpy(F, R->F, sizeof F);
    const double *cF = x + 6 * R->sF, *cG = x + 6 * R->sG;
    for (int c = 0; c < 2; c++) { /* canonical (2,1), (1,2), (2,2) into this edge's frame */
        F[2][1][c] = cF[(R->tF ? 2 : 0) + c];
        F[1][2][c] = cF[(R->tF ? 0 : 2) + c];
        F[2][2][c] = cF[4 + c];
    }
    const double *y = x + xr;
    double ta[3] = {R->ta0, y[0] / R->sw, y[2] / R->sw}, tb[3] = {R->tb0, y[1] / R->su, y[3] / R->su};
    compose((const double (*)[3][2])F, R->al, R->bt, ta, tb, G);
    for (int c = 0; c < 2; c++) {
        out[c] = G[2][1][c] - cG[(R->tG ? 2 : 0) + c];
        out[2 + c] = G[1][2][c] - cG[(R->tG ? 0 : 2) + c];
        out[4 + c] = G[2][2][c] - cG[4 + c];
    }
}

q2n_status q2n_ev_fair_poly_gluing2(const fe_build *B, const int *faces, int nf, fe_ctx *X, char *fail, int *nfail,
                                    q2n_error *err)
{
    const q2n_mesh *m = B->m;
    q2n_status st = Q2N_OK;
    *nfail = 0;
    int *fidx = malloc(sizeof(int) * (size_t)m->nf), *vstart = calloc((size_t)m->nv + 1, sizeof(int));
    g2_rel *rel = malloc(sizeof(g2_rel) * (8 * (size_t)nf + 1));
    int *order = malloc(sizeof(int) * (8 * (size_t)nf + 1)), *vof = malloc(sizeof(int) * (8 * (size_t)nf + 1));
    double (*cm)[6] = calloc(4 * (size_t)nf + 1, sizeof *cm); /* per face corner: c21, c12, c22 (canonical) */
    double (*tg)[2][2][3] = calloc(4 * (size_t)nf + 1, sizeof *tg); /* per derived side: A2, B2 end data */
    if (!fidx || !vstart || !rel || !order || !vof || !cm || !tg) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (G2 gluing)"); goto done; }
    for (int f = 0; f < m->nf; f++) fidx[f] = -1;
    for (int i = 0; i < nf; i++) fidx[faces[i]] = i;
    /* the relations: every derived side's two ends whose base face is in the list */
    int nrel = 0;
    for (int i = 0; i < nf; i++)
        for (int sd = 0; sd < 4; sd++) {
            const fe_side *S = &X[i].side[sd];
            int sdF, gi = q2n_ev_fair_derived_base(B, faces, fidx, X, i, sd, &sdF);
            if (gi < 0) continue;
            int f = faces[i], g = faces[gi];
            for (int end = 0; end < 2; end++) {
                g2_rel *R = &rel[nrel];
                int cG = end ? S->c1 : S->c0, v = fv(m, f, cG), cF = corner_at(m, g, v);
                if (cF < 0) continue;
                memset(R, 0, sizeof *R);
                R->i = i, R->sd = sd, R->end = end;
                R->sG = 4 * i + cG, R->sF = 4 * gi + cF; /* global corner indices for now */
                R->tG = !q2n_side_along_u(sd), R->tF = !q2n_side_along_u(sdF);
                const double *u = end ? S->u1 : S->u0, *w = end ? S->w1 : S->w0;
                for (int c = 0; c < 2; c++) {
                    R->F[1][0][c] = S->d * u[c];
                    R->F[0][1][c] = S->ew[end] * w[c];
                    R->F[1][1][c] = S->rc[end][c];
                }
                q2n_ev_fair_glue_taylor(S, end, R->al, R->bt);
                /* the b² coefficient of φ_F ∘ ψ vanishes: ½ A2(0) e_w w + ½ B2(0) d u = -α̃ B r_F */
                double rhs[2] = {-2 * R->al[0] * R->bt[0] * S->rc[end][0], -2 * R->al[0] * R->bt[0] * S->rc[end][1]};
                double a11 = S->ew[end] * w[0], a12 = S->d * u[0], a21 = S->ew[end] * w[1], a22 = S->d * u[1];
                double det = a11 * a22 - a12 * a21;
                if (!(fabs(det) > 0)) { /* the edge and the cross edge parallel in the chart: no gluing there */
                    if (fail && !fail[v]) fail[v] = 1, ++*nfail;
                    continue;
                }
                R->ta0 = (rhs[0] * a22 - a12 * rhs[1]) / det;
                R->tb0 = (a11 * rhs[1] - a21 * rhs[0]) / det;
                R->sw = S->ew[end] > 0 ? S->ew[end] : 1;
                R->su = S->d > 0 ? S->d : 1;
                vof[nrel] = v;
                vstart[v + 1]++;
                nrel++;
            }
        }
    for (int v = 0; v < m->nv; v++) vstart[v + 1] += vstart[v];
    {
        int *fill = malloc(sizeof(int) * ((size_t)m->nv + 1));
        if (!fill) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (G2 gluing)"); goto done; }
        memcpy(fill, vstart, sizeof(int) * (size_t)m->nv);
        for (int k = 0; k < nrel; k++) order[fill[vof[k]]++] = k;
        free(fill);
    }
    /* per vertex: the least change that meets its relations' equations */
    for (int v = 0; v < m->nv && !st; v++) {
        int r0 = vstart[v], nr = vstart[v + 1] - r0;
        if (nr == 0) continue;
        /* local corner slots */
        int *slot = malloc(sizeof(int) * 2 * (size_t)nr), ns = 0;
        g2_rel *loc = malloc(sizeof(g2_rel) * (size_t)nr);
        int nu = 0, mr = 6 * nr, ld = 0;
        double *A = NULL, *b = NULL, *x = NULL;
        if (slot && loc)
            for (int k = 0; k < nr; k++) {
                loc[k] = rel[order[r0 + k]];
                int *gl[2] = {&loc[k].sG, &loc[k].sF};
                for (int t = 0; t < 2; t++) {
                    int s = -1;
                    for (int q = 0; q < ns; q++)
                        if (slot[q] == *gl[t]) s = q;
                    if (s < 0) s = ns, slot[ns++] = *gl[t];
                    *gl[t] = s;
                }
            }
        nu = 6 * ns + 4 * nr, ld = mr > nu ? mr : nu;
        if (slot && loc) {
            A = calloc((size_t)mr * nu, sizeof(double));
            b = calloc((size_t)ld, sizeof(double));
            x = calloc((size_t)nu, sizeof(double));
        }
        if (!slot || !loc || !A || !b || !x) {
            free(slot), free(loc), free(A), free(b), free(x);
            st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (G2 gluing)");
            break;
        }
        double c0[6], cx[6], scale = 0;
        int any = 0;
        /* 1. the corner terms: the least change that meets every relation's (2, 1) equations (two rows
         *    per relation; neither the tangential terms nor c22 enter them) */
        for (int k = 0; k < nr; k++) {
            int xr = 6 * ns + 4 * k;
            rel_residual(&loc[k], x, xr, c0);
            for (int q = 0; q < 6; q++) any |= c0[q] != 0;
            b[2 * k] = -c0[0], b[2 * k + 1] = -c0[1];
            scale = fmax(scale, hypot(loc[k].F[1][0][0], loc[k].F[1][0][1]));
            scale = fmax(scale, hypot(loc[k].F[0][1][0], loc[k].F[0][1][1]));
            int cols[12], nc = 0;
            for (int q = 0; q < 4; q++) cols[nc++] = 6 * loc[k].sG + q;
            if (loc[k].sF != loc[k].sG)
                for (int q = 0; q < 4; q++) cols[nc++] = 6 * loc[k].sF + q;
            for (int t = 0; t < nc; t++) {
                x[cols[t]] = 1;
                rel_residual(&loc[k], x, xr, cx);
                x[cols[t]] = 0;
                A[(size_t)cols[t] * mr + 2 * k] = cx[0] - c0[0];
                A[(size_t)cols[t] * mr + 2 * k + 1] = cx[1] - c0[1];
            }
        }
        if (any) {
            int m2 = 2 * nr, rank = 0, rc = q2n_dense_lstsq(m2, 6 * ns, 1, A, mr, b, ld, EV_POLY2_RCOND, &rank);
            if (rc) {
                free(slot), free(loc), free(A), free(b), free(x);
                st = q2n_error_set(err, rc < 0 ? Q2N_ERR_ARG : Q2N_ERR_NOMEM, "G2 gluing: least squares failed at vertex %d", v);
                break;
            }
            memcpy(x, b, sizeof(double) * 6 * (size_t)ns);
            /* 2. per relation, its four tangential unknowns from its (1, 2) and (2, 2) equations */
            double res = 0, mag = scale;
            for (int k = 0; k < nr && any; k++) {
                int xr = 6 * ns + 4 * k;
                double M[16], y[4];
                rel_residual(&loc[k], x, xr, c0);
                for (int q = 0; q < 6; q++) mag = fmax(mag, fabs(c0[q]));
                for (int t = 0; t < 4; t++) {
                    x[xr + t] = 1;
                    rel_residual(&loc[k], x, xr, cx);
                    x[xr + t] = 0;
                    for (int q = 0; q < 4; q++) M[t * 4 + q] = cx[2 + q] - c0[2 + q];
                }
                for (int q = 0; q < 4; q++) y[q] = -c0[2 + q];
                if (q2n_dense_solve(4, 1, M, 4, y, 4)) { res = INFINITY; break; }
                memcpy(x + xr, y, sizeof y);
                rel_residual(&loc[k], x, xr, cx);
                for (int q = 0; q < 6; q++) res = fmax(res, fabs(cx[q]));
            }
            /* the equations must hold, relative to their terms' size (the edge vectors, what the tangential
             * terms cancel, the unknowns) */
            for (int q = 0; q < nu; q++) mag = fmax(mag, fabs(x[q]));
            if (!(res <= EV_POLY2_RESIDUAL * (mag > 0 ? mag : 1))) {
                if (fail) fail[v] = 1;
                ++*nfail;
                memset(x, 0, sizeof(double) * (size_t)nu);
            }
        }
        /* keep: corner terms per face corner, the tangential terms per derived side's end */
        for (int q = 0; q < ns; q++) memcpy(cm[slot[q]], x + 6 * q, sizeof cm[0]);
        for (int k = 0; k < nr; k++) {
            const g2_rel *R = &loc[k];
            const double *y = x + 6 * ns + 4 * k;
            double ta[3] = {R->ta0, y[0] / R->sw, y[2] / R->sw}, tb[3] = {R->tb0, y[1] / R->su, y[3] / R->su};
            if (fail && fail[v]) ta[0] = tb[0] = 0;
            /* s-derivatives: A2(s) = Ã2(a), B2(s) = ±B̃2(a), a = s at end 0 and 1 - s at end 1 */
            double sg = R->end ? -1 : 1;
            double (*T)[2][3] = tg[4 * R->i + R->sd];
            T[0][R->end][0] = ta[0], T[0][R->end][1] = sg * ta[1], T[0][R->end][2] = 2 * ta[2];
            T[1][R->end][0] = sg * tb[0], T[1][R->end][1] = tb[1], T[1][R->end][2] = sg * 2 * tb[2];
        }
        free(slot), free(loc), free(A), free(b), free(x);
    }
    if (st) goto done;
    /* into the sides: every constructed side takes its base face's corner terms at both ends (in its
     * own frame), a derived side its tangential terms */
    for (int i = 0; i < nf; i++)
        for (int sd = 0; sd < 4; sd++) {
            fe_side *S = &X[i].side[sd];
            if (S->kind != 0) continue;
            int sdF, gi = q2n_ev_fair_base_side(B, faces, fidx, i, sd, &sdF), f = faces[i], g = gi >= 0 ? faces[gi] : -1;
            if (gi < 0) continue;
            int tF = !q2n_side_along_u(sdF);
            for (int end = 0; end < 2; end++) {
                int v = fv(m, f, end ? S->c1 : S->c0), cF = corner_at(m, g, v);
                if (cF < 0 || (fail && fail[v])) continue;
                const double *c6 = cm[4 * gi + cF];
                for (int c = 0; c < 2; c++) {
                    S->cm[end][0][c] = c6[(tF ? 2 : 0) + c];
                    S->cm[end][1][c] = c6[(tF ? 0 : 2) + c];
                    S->cm[end][2][c] = c6[4 + c];
                }
            }
            if (S->derived) memcpy(S->tg, tg[4 * i + sd], sizeof S->tg);
        }
done:
    free(fidx);
    free(vstart);
    free(rel);
    free(order);
    free(vof);
    free(cm);
    free(tg);
    return st;
}
