/* coons_gregory.c — augmented Coons–Gregory patches (seed 003 §4.1 eq. (23), §4.2) and the
 * driver that gives every face left uncovered by the regular construction such a patch.
 *
 * Patch.  Data on [0,1]^2 (corners p0 (0,0), p1 (1,0), p2 (1,1), p3 (0,1)), side 0 v=0, side 1
 * u=1, side 2 v=1, side 3 u=0.  Each side carries local data (γ, inward χ, ξ; ev_side_eval) in
 * its edge's local variable; the patch sees them in (u,v) as
 *     ∂v^0 S(u,0) = γ0(x0),  ∂v S(u,0) = ε(u) χ0(x0),  ∂v² S(u,0) = ε(u)² ξ0(x0)      (eq. 22–23)
 * (signs flipped for the inward directions -u, -v of sides 1, 2), ε / δ being the local
 * parametrization functions of degree 2k+1 blending the intervals of the transverse edges
 * (§4: "following the same definition in Section 3").  With these uv fields the patch is the
 * Boolean sum of formulas.md §4.1, S = P_u + P_v - P_uv with Hermite blending of degree 2K+1
 * (K = 1: eq. (23), bicubic; K = 2: §4.2, biquintic).  The mixed corner terms M^{ab}, a,b >= 1,
 * are the Gregory pairs of formulas.md §4.2 (Ω_{1,1}, Ω_{1,2}, Ω_{2,1}, Ω_{2,2} of §4.2):
 *     M^{ab}_{ij}(u,v) = (ũ^r B^{ab} + ṽ^r A^{ab}) / (ũ^r + ṽ^r),   r = K,
 * A from the v = j side, B from the u = i side, ũ = |u - i|, ṽ = |v - j|.  Expanding
 * ∂v(ε χ) = ε' χ + ε d χ' reproduces the paper's d_i e_j scale factors, because ε' = δ' = 0 at
 * the corners.  Values and partials up to order two are exact (the rational Gregory weights are
 * differentiated analytically); at a corner itself the weight is taken as 1/2. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"
#include "patch/ev_internal.h"

typedef struct ev_patch {
    int K, r, kb;
    double d0, d1, e0, e1;     /* intervals of sides 0, 2 (u) and 3, 1 (v) */
    ev_side side[4];
    double M[2][2][3][3][3];   /* corner (i,j), a, b: constant mixed terms (a or b = 0) */
    double A[2][2][3][3][3];   /* Gregory: from the v = j side */
    double B[2][2][3][3][3];   /*          from the u = i side */
} ev_patch;

static const int side_iota[4] = {1, -1, -1, 1};

/* uv fields of side sd at side parameter s: F[b][a] = ∂s^a ∂n^b S (n = v on sides 0/2, u on 1/3). */
static void side_uv(const ev_patch *P, int sd, double s, double F[3][3][3])
{
    double loc[3][3][3], L[4];
    ev_side_eval(&P->side[sd], s, loc);
    if (sd == 0 || sd == 2) q2n_spline_blend_derivs(P->kb, P->e0, P->e1, s, L); /* ε(u) */
    else q2n_spline_blend_derivs(P->kb, P->d0, P->d1, s, L);                   /* δ(v) */
    double L2[3] = {L[0] * L[0], 2 * L[0] * L[1], 2 * L[1] * L[1] + 2 * L[0] * L[2]};
    double io = side_iota[sd];
    for (int c = 0; c < 3; c++) {
        for (int a = 0; a < 3; a++) F[0][a][c] = loc[0][a][c];
        F[1][0][c] = io * L[0] * loc[1][0][c];
        F[1][1][c] = io * (L[1] * loc[1][0][c] + L[0] * loc[1][1][c]);
        F[1][2][c] = io * (L[2] * loc[1][0][c] + 2 * L[1] * loc[1][1][c] + L[0] * loc[1][2][c]);
        F[2][0][c] = L2[0] * loc[2][0][c];
        F[2][1][c] = L2[1] * loc[2][0][c] + L2[0] * loc[2][1][c];
        F[2][2][c] = L2[2] * loc[2][0][c] + 2 * L2[1] * loc[2][1][c] + L2[0] * loc[2][2][c];
    }
}

/* Hermite basis H_{a,i}(x) and derivatives 0..2: H[a][i][d] (formulas.md §4.1). */
static void hermite(int K, double x, double H[3][2][3])
{
    static const double H3[2][2][6] = {{{1, 0, -3, 2, 0, 0}, {0, 0, 3, -2, 0, 0}},
                                       {{0, 1, -2, 1, 0, 0}, {0, 0, -1, 1, 0, 0}}};
    static const double H5[3][2][6] = {{{1, 0, 0, -10, 15, -6}, {0, 0, 0, 10, -15, 6}},
                                       {{0, 1, 0, -6, 8, -3}, {0, 0, 0, -4, 7, -3}},
                                       {{0, 0, 0.5, -1.5, 1.5, -0.5}, {0, 0, 0, 0.5, -1, 0.5}}};
    for (int a = 0; a <= K; a++)
        for (int i = 0; i < 2; i++) {
            const double *c = K == 1 ? H3[a][i] : H5[a][i];
            double v0 = 0, v1 = 0, v2 = 0; /* Horner for the polynomial and its derivatives */
            for (int p = 5; p >= 0; p--) v0 = v0 * x + c[p];
            for (int p = 5; p >= 1; p--) v1 = v1 * x + p * c[p];
            for (int p = 5; p >= 2; p--) v2 = v2 * x + p * (p - 1) * c[p];
            H[a][i][0] = v0;
            H[a][i][1] = v1;
            H[a][i][2] = v2;
        }
}

/* Gregory weight ω = ũ^r / (ũ^r + ṽ^r) of corner (i,j) and its partials W[p][q], p+q <= 2. */
static void gregory_weight(int r, int i, int j, double u, double v, double W[3][3])
{
    double ut = i ? 1 - u : u, vt = j ? 1 - v : v, su = i ? -1 : 1, sv = j ? -1 : 1;
    memset(W, 0, 9 * sizeof(double));
    double U = r == 1 ? ut : ut * ut, V = r == 1 ? vt : vt * vt;
    double g = U + V;
    if (!(g > 0)) { W[0][0] = 0.5; return; }
    double Uu = r == 1 ? su : 2 * ut * su, Uuu = r == 1 ? 0 : 2;
    double Vv = r == 1 ? sv : 2 * vt * sv, Vvv = r == 1 ? 0 : 2;
    double g2 = g * g, g3 = g2 * g;
    W[0][0] = U / g;
    W[1][0] = Uu * V / g2;
    W[0][1] = -U * Vv / g2;
    W[2][0] = Uuu * V / g2 - 2 * Uu * Uu * V / g3;
    W[0][2] = -U * Vvv / g2 + 2 * U * Vv * Vv / g3;
    W[1][1] = Uu * Vv / g2 - 2 * Uu * V * Vv / g3;
}

/* What a point evaluation needs from one parameter line: the two sides' uv fields at that
 * parameter and the Hermite weights (u-lines: sides 0, 2 and H(u); v-lines: sides 3, 1 and H(v)). */
typedef struct line_data {
    double side[2][3][3][3];
    double H[3][2][3];
} line_data;

static void line_u(const ev_patch *P, double u, line_data *L)
{
    side_uv(P, 0, u, L->side[0]);
    side_uv(P, 2, u, L->side[1]);
    hermite(P->K, u, L->H);
}

static void line_v(const ev_patch *P, double v, line_data *L)
{
    side_uv(P, 3, v, L->side[0]);
    side_uv(P, 1, v, L->side[1]);
    hermite(P->K, v, L->H);
}

/* S = P_u + P_v - P_uv (formulas.md §4.1) with Gregory mixed terms (§4.2), partials up to nder. */
static void patch_sum(const ev_patch *P, double u, double v, int nder, const line_data *Lu, const line_data *Lv,
                      double *out)
{
    int K = P->K;
    const double (*Hu)[2][3] = Lu->H, (*Hv)[2][3] = Lv->H;
    double W[2][2][3][3];
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) gregory_weight(P->r, i, j, u, v, W[i][j]);
    static const int ord[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
    static const double binom[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};
    int nout = nder <= 0 ? 1 : nder == 1 ? 3 : 6;
    for (int o = 0; o < nout; o++) {
        int al = ord[o][0], be = ord[o][1];
        double r[3] = {0, 0, 0};
        for (int i = 0; i < 2; i++)
            for (int a = 0; a <= K; a++) {
                q2n_v3_axpy(r, Hu[a][i][al], Lv->side[i][a][be]); /* P_u: G_{i,a}(v) */
                q2n_v3_axpy(r, Hv[a][i][be], Lu->side[i][a][al]); /* P_v: F_{j,b}(u), j = i, b = a */
            }
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++)
                for (int a = 0; a <= K; a++)
                    for (int b = 0; b <= K; b++) {
                        const double *Mc = P->M[i][j][a][b], *A = P->A[i][j][a][b], *B = P->B[i][j][a][b];
                        int greg = a >= 1 && b >= 1;
                        for (int a1 = 0; a1 <= al; a1++)
                            for (int b1 = 0; b1 <= be; b1++) {
                                int p = al - a1, q = be - b1;
                                double h = binom[al][a1] * binom[be][b1] * Hu[a][i][a1] * Hv[b][j][b1];
                                if (h == 0) continue;
                                if (!greg) {
                                    if (p == 0 && q == 0) q2n_v3_axpy(r, -h, Mc);
                                    continue;
                                }
                                double w = W[i][j][p][q];
                                for (int c = 0; c < 3; c++) {
                                    double m = (p == 0 && q == 0) ? A[c] + w * (B[c] - A[c]) : w * (B[c] - A[c]);
                                    r[c] -= h * m;
                                }
                            }
                    }
        memcpy(out + 3 * o, r, sizeof r);
    }
}

static q2n_status patch_eval(const void *data, double u, double v, int nder, double *out)
{
    const ev_patch *P = data;
    line_data Lu, Lv;
    line_u(P, u, &Lu);
    line_v(P, v, &Lv);
    patch_sum(P, u, v, nder, &Lu, &Lv, out);
    return Q2N_OK;
}

/* Grid fast path: the side data depend on u only (sides 0, 2) or v only (sides 1, 3). */
static q2n_status patch_grid(const void *data, int nu, const double *us, int nv, const double *vs, double *out)
{
    const ev_patch *P = data;
    line_data *Lu = malloc((size_t)nu * sizeof *Lu);
    if (!Lu) return Q2N_ERR_NOMEM;
    for (int a = 0; a < nu; a++) line_u(P, us[a], &Lu[a]);
    for (int b = 0; b < nv; b++) {
        line_data Lv;
        line_v(P, vs[b], &Lv);
        for (int a = 0; a < nu; a++) patch_sum(P, us[a], vs[b], 1, &Lu[a], &Lv, out + 9 * ((size_t)b * nu + a));
    }
    free(Lu);
    return Q2N_OK;
}

static void patch_free(void *d) { free(d); }

/* Corner data: A^{ab} = ∂u^a [∂v^b S(u,j)](i) from the v = j side, B^{ab} = ∂v^b [∂u^a S(i,v)](j)
 * from the u = i side; the constant terms use the side that makes the patch interpolate both
 * (formulas.md §4.1: a = 0 from the v-side, b = 0 from the u-side). */
static void patch_corners(ev_patch *P)
{
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            double Fv[3][3][3], Gu[3][3][3];
            side_uv(P, j ? 2 : 0, i, Fv);
            side_uv(P, i ? 1 : 3, j, Gu);
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) {
                    memcpy(P->A[i][j][a][b], Fv[b][a], 3 * sizeof(double));
                    memcpy(P->B[i][j][a][b], Gu[a][b], 3 * sizeof(double));
                    memcpy(P->M[i][j][a][b], a == 0 ? Fv[b][a] : Gu[a][b], 3 * sizeof(double));
                }
        }
}

int q2n_ev_patch_parse(const char *s, q2n_ev_patch_kind *out)
{
    if (!s) return -1;
    if ((s[0] == 'g' || s[0] == 'G') && s[1] && !s[2]) {
        if (s[1] == '1') { *out = Q2N_EV_PATCH_G1; return 0; }
        if (s[1] == '2') { *out = Q2N_EV_PATCH_G2; return 0; }
    }
    return -1;
}

static const q2n_spline_class *opt_class(const q2n_extraordinary_options *opt)
{
    return opt && opt->cls ? opt->cls : q2n_spline_class_find("D5C2P2S4");
}

int q2n_ev_patch_order(const q2n_extraordinary_options *opt)
{
    if (opt && opt->ev_patch == Q2N_EV_PATCH_G1) return 1;
    if (opt && opt->ev_patch == Q2N_EV_PATCH_G2) return 2;
    return opt_class(opt)->k >= 2 ? 2 : 1;
}

q2n_status q2n_extraordinary_build(const q2n_mesh *m, const q2n_extraordinary_options *opt,
                                   const double *edge_iv, q2n_surface *s, q2n_error *err)
{
    if (!m || !s || !opt) return q2n_error_set(err, Q2N_ERR_ARG, "extraordinary: missing argument");
    if (!m->all_quads)
        return q2n_error_set(err, Q2N_ERR_UNSUPPORTED,
                             "%s: extraordinary patches need an all-quad mesh (subdivide once first)", m->name);
    if (q2n_surface_npatches(s) != m->nf)
        return q2n_error_set(err, Q2N_ERR_ARG, "%s: surface has %d patches for %d faces", m->name,
                             q2n_surface_npatches(s), m->nf);
    const q2n_spline_class *cls = opt_class(opt);
    if (!cls) return q2n_error_set(err, Q2N_ERR_ARG, "extraordinary: unknown spline class");
    int K = q2n_ev_patch_order(opt), nunc = 0;
    for (int f = 0; f < m->nf; f++) {
        q2n_patch_kind kd = q2n_surface_kind(s, f);
        if (kd == Q2N_PATCH_UNCOVERED) nunc++;
        else if (kd != Q2N_PATCH_AUGMENTED)
            return q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: patch kind %d is neither regular nor uncovered",
                                 m->name, f, (int)kd);
    }
    if (nunc == 0) return Q2N_OK;
    q2n_status st = Q2N_OK;
    double *own = NULL;
    if (!edge_iv) {
        if ((st = q2n_param_edge_intervals(m, &opt->param, &own, err))) return st;
        edge_iv = own;
    }
    const double *iv = edge_iv;
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
    if ((st = ev_vertex_jets(m, s, iv, cls, jets, dir, err))) goto done;

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
            st = ev_build_edge(m, iv, jets, (const double (*)[2])dir, K, e, edges[e], err);
        }
    }
    if (st) goto done;

    for (int f = 0; f < m->nf; f++) {
        if (!unc[f]) continue;
        ev_patch *P = calloc(1, sizeof *P);
        if (!P) { st = q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (patch %d)", f); goto done; }
        patches[f] = P;
        P->K = K;
        P->r = K;
        P->kb = cls->k;
        P->d0 = iv[m->he_edge[q2n_face_he(m, f, 0)]];
        P->e1 = iv[m->he_edge[q2n_face_he(m, f, 1)]];
        P->d1 = iv[m->he_edge[q2n_face_he(m, f, 2)]];
        P->e0 = iv[m->he_edge[q2n_face_he(m, f, 3)]];
        for (int sd = 0; sd < 4; sd++) {
            int h = q2n_face_he(m, f, sd), t = m->he_twin[h], e = m->he_edge[h];
            ev_side *S = &P->side[sd];
            /* the side parameter runs along h on sides 0, 1 and against it on sides 2, 3 */
            int along_h = sd < 2;
            if (t >= 0 && !unc[m->he_face[t]]) {
                int g = m->he_face[t], sR = t - m->face_start[g];
                const q2n_augmented_patch *R = q2n_surface_patch_data(s, g);
                if (!R) { st = q2n_error_set(err, Q2N_ERR_ARG, "%s: face %d: no regular patch data", m->name, g); goto done; }
                S->kind = 1;
                S->R = *R;
                S->sR = sR;
                /* R's coordinate runs along t on its sides 0, 1 and against t on 2, 3; t is
                 * opposite to h */
                int R_along_t = sR < 2;
                int R_along_h = !R_along_t;
                S->rev = R_along_h != along_h;
            } else {
                const ev_edge *E = edges[e];
                S->kind = 0;
                S->E = *E;
                S->derived = m->edge_he[e] != h;
                int edge_along_h = m->edge_he[e] == h;
                S->rev = edge_along_h != along_h;
            }
        }
        patch_corners(P);
    }
    for (int f = 0; f < m->nf; f++) {
        if (!patches[f]) continue;
        if ((st = q2n_surface_set_patch(s, f, Q2N_PATCH_COONS_GREGORY, patches[f], patch_eval, patch_free))) {
            q2n_error_set(err, st, "%s: face %d: cannot attach the patch", m->name, f);
            goto done;
        }
        q2n_surface_set_patch_grid(s, f, patch_grid);
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
    free(own);
    return st;
}
