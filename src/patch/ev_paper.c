/* ev_paper.c — the paper's construction for extraordinary regions (seed 003 §4.1 eq. (23),
 * §4.2; kept as --ev-construction paper for comparison): augmented Coons–Gregory patches over a
 * curve network of Hermite segments and ribbon cross fields (curve_network.c) with 2-jets per
 * vertex (ev_derivatives.c), in G2 mode made corner-compatible by ev_harmonize.c.
 *
 * Patch.  Data on [0,1]^2 (corners p0 (0,0), p1 (1,0), p2 (1,1), p3 (0,1)), side 0 v=0, side 1
 * u=1, side 2 v=1, side 3 u=0.  Each side carries local data (γ, inward χ, ξ; q2n_ev_side_eval) in
 * its edge's local variable; the patch sees them in (u,v) as
 *     ∂v^0 S(u,0) = γ0(x0),  ∂v S(u,0) = ε(u) χ0(x0),  ∂v² S(u,0) = ε(u)² ξ0(x0)      (eq. 22–23)
 * (signs flipped for the inward directions -u, -v of sides 1, 2), ε / δ being the local
 * parametrization functions of degree 2k+1 blending the intervals of the transverse edges
 * (§4: "following the same definition in Section 3").  The Boolean sum with Hermite blending of
 * degree 2K+1 and Gregory corners (r = K) is coons_patch.c's.  Expanding ∂v(ε χ) = ε' χ + ε d χ'
 * reproduces the paper's d_i e_j scale factors, because ε' = δ' = 0 at the corners. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/jet.h"
#include "patch/ev_internal.h"

/* The paper's patch: the shared Boolean-sum Coons patch (coons_patch.c) over side data from the
 * curve network (q2n_ev_side_eval) seen through the local parametrization functions, with Gregory
 * blends at all four corners (r = K). */


/* uv fields of side sd at s: the local data (γ, inward χ, ξ) times the local parametrization
 * function across the side: ∂n S = ε χ, ∂n² S = ε² ξ (eq. 22–23; signs for the inward -u, -v of
 * sides 1, 2).  Along derivatives up to 2 (W = 3 lanes only). */
static void pp_side(const void *ctx, const void *lanes, int W, int sd, double s, int na, double F[3][CP_NA][CP_MAXW])
{
    const pp_ctx *X = ctx;
    double loc[3][3][3], L[4];
    (void)lanes;
    (void)W;
    q2n_ev_side_eval(&X->side[sd], s, loc);
    if (q2n_side_along_u(sd)) q2n_spline_blend_derivs(X->kb, X->e0, X->e1, s, L); /* ε(u) */
    else q2n_spline_blend_derivs(X->kb, X->d0, X->d1, s, L);                   /* δ(v) */
    double L2[3], io = q2n_side_iota[sd];
    q2n_jet_mul_n(2, L, L, L2);
    for (int b = 0; b < 3; b++)
        for (int a = 0; a < na; a++) memset(F[b][a], 0, 3 * sizeof(double));
    for (int c = 0; c < 3; c++) { /* jets in s: ∂n S = ε χ, ∂n² S = ε² ξ */
        double l[3][3], p[3];
        for (int b = 0; b < 3; b++)
            for (int a = 0; a < 3; a++) l[b][a] = loc[b][a][c];
        for (int a = 0; a < 3 && a < na; a++) F[0][a][c] = l[0][a];
        q2n_jet_mul_n(2, L, l[1], p);
        for (int a = 0; a < 3 && a < na; a++) F[1][a][c] = io * p[a];
        q2n_jet_mul_n(2, L2, l[2], p);
        for (int a = 0; a < 3 && a < na; a++) F[2][a][c] = p[a];
    }
}


static void patch_free(void *d) { free(d); }
/* Fill the patch of uncovered face f from the curve network and its regular neighbours. */
q2n_status q2n_ev_paper_patch_setup(ev_patch *P, const q2n_mesh *m, const q2n_surface *s, const double *iv,
                              const char *unc, ev_edge *const *edges, int K, int kb, int f, q2n_error *err)
{
    memset(P, 0, sizeof *P);
    pp_ctx *X = &P->X;
    X->kb = kb;
    X->d0 = iv[m->he_edge[q2n_face_he(m, f, 0)]];
    X->e1 = iv[m->he_edge[q2n_face_he(m, f, 1)]];
    X->d1 = iv[m->he_edge[q2n_face_he(m, f, 2)]];
    X->e0 = iv[m->he_edge[q2n_face_he(m, f, 3)]];
    for (int sd = 0; sd < 4; sd++) {
        int h = q2n_face_he(m, f, sd), t = m->he_twin[h], e = m->he_edge[h];
        ev_side *S = &X->side[sd];
        /* the side parameter runs along h on sides 0, 1 and against it on sides 2, 3 */
        int along_h = q2n_side_forward(sd);
        if (t >= 0 && !unc[m->he_face[t]]) {
            int g = m->he_face[t], sR = t - m->face_start[g];
            q2n_augmented_patch Rp, *R = &Rp;
            if (!q2n_augmented_patch_get(s, g, &Rp)) return q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: no regular patch data", m->name, g);
            S->kind = 1;
            S->R = *R;
            S->sR = sR;
            /* R's coordinate runs along t on its sides 0, 1 and against t on 2, 3; t is
             * opposite to h */
            int R_along_t = q2n_side_forward(sR);
            int R_along_h = !R_along_t;
            S->rev = R_along_h != along_h;
        } else {
            const ev_edge *E = edges[e];
            S->kind = 0;
            S->E = *E;
            S->derived = (m->edge_he[e] != h) != E->base_twin;
            int edge_along_h = m->edge_he[e] == h;
            S->rev = edge_along_h != along_h;
        }
    }
    P->E.P.K = K;
    for (int c = 0; c < 4; c++) P->E.P.greg[c] = 1;
    P->E.P.side = pp_side;
    P->E.P.ctx = X;
    q2n_cp_eval_init(&P->E);
    return Q2N_OK;
}
q2n_status q2n_ev_paper_build(const q2n_mesh *m, q2n_surface *s, const double *iv, const q2n_spline_class *cls, int K,
                          q2n_error *err)
{
    q2n_status st = Q2N_OK;
    ev_vjet *jets = calloc((size_t)m->nv, sizeof *jets);
    double (*dir)[2] = calloc(2 * (size_t)m->ne, sizeof *dir);
    ev_edge **edges = calloc((size_t)m->ne, sizeof *edges);
    char *unc = calloc((size_t)m->nf, 1);
    ev_patch **patches = calloc((size_t)m->nf, sizeof *patches);
    if (!jets || !dir || !edges || !unc || !patches) {
        st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (extraordinary patches)");
        goto done;
    }
    for (int f = 0; f < m->nf; f++) unc[f] = q2n_surface_kind(s, f) == Q2N_PATCH_UNCOVERED;
    if ((st = q2n_ev_vertex_jets(m, NULL, s, iv, cls, 1, NULL, jets, dir, err))) goto done;

    /* curve network: every edge of an uncovered face not shared with a regular patch */
    for (int f = 0; f < m->nf && !st; f++) {
        if (!unc[f]) continue;
        for (int i = 0; i < 4 && !st; i++) {
            int h = q2n_face_he(m, f, i), t = m->he_twin[h], e = m->he_edge[h];
            if (t >= 0 && !unc[m->he_face[t]]) continue;
            if (edges[e]) continue;
            if (!(edges[e] = malloc(sizeof **edges))) {
                st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (edge %d)", e);
                break;
            }
            st = q2n_ev_build_edge(m, iv, jets, (const double (*)[2])dir, K, e, edges[e], err);
        }
    }
    if (st) goto done;

    if (K == 2) { /* corners of uncovered faces, bucketed by vertex: (face << 2) | corner */
        int *vc_start = calloc((size_t)m->nv + 1, sizeof *vc_start), *vc_list = malloc(4 * (size_t)m->nf * sizeof *vc_list);
        if (!vc_start || !vc_list) st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (corner lists)");
        for (int f = 0; f < m->nf && !st; f++)
            if (unc[f])
                for (int k = 0; k < 4; k++) vc_start[q2n_he_origin(m, q2n_face_he(m, f, k)) + 1]++;
        for (int v = 0; v < m->nv && !st; v++) vc_start[v + 1] += vc_start[v];
        for (int f = 0; f < m->nf && !st; f++)
            if (unc[f])
                for (int k = 0; k < 4; k++) {
                    int v = q2n_he_origin(m, q2n_face_he(m, f, k));
                    vc_list[vc_start[v]++] = f << 2 | k;
                }
        for (int v = m->nv; v > 0 && !st; v--) vc_start[v] = vc_start[v - 1];
        if (!st) vc_start[0] = 0;
        for (int v = 0; v < m->nv && !st; v++)
            st = q2n_ev_harmonize_vertex(m, s, iv, unc, edges, K, cls->k, vc_start, vc_list, v, err);
        free(vc_start);
        free(vc_list);
    }
    if (st) goto done;

    for (int f = 0; f < m->nf; f++) {
        if (!unc[f]) continue;
        ev_patch *P = calloc(1, sizeof *P);
        if (!P) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (patch %d)", f); goto done; }
        patches[f] = P;
        if ((st = q2n_ev_paper_patch_setup(P, m, s, iv, unc, edges, K, cls->k, f, err))) goto done;
    }
    for (int f = 0; f < m->nf; f++) {
        if (!patches[f]) continue;
        if ((st = q2n_surface_set_patch(s, f, Q2N_PATCH_COONS_GREGORY, patches[f], q2n_cp_eval_point, patch_free))) {
            q2n_error_set(err, st, "%s: face %d: cannot attach the patch", m->name, f);
            goto done;
        }
        q2n_surface_set_patch_grid(s, f, q2n_cp_eval_grid);
        q2n_surface_set_patch_grid_pos(s, f, q2n_cp_eval_grid_pos);
        q2n_surface_set_patch_corner(s, f, q2n_cp_eval_corner);
        patches[f] = NULL;
    }
done:
    if (patches)
        for (int f = 0; f < m->nf; f++) free(patches[f]);
    if (edges)
        for (int e = 0; e < m->ne; e++) free(edges[e]);
    free(patches);
    free(edges);
    free(unc);
    free(dir);
    free(jets);
    return st;
}
