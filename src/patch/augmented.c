/* augmented.c — regular augmented patches: stencil gathering on the half-edge mesh (with the
 * extrapolated layer of seed 003 §3.1 for open meshes) and evaluation of eq. (10)–(11) with
 * first and second partial derivatives.
 *
 * Evaluation: every class in spline.h has ψ_i(x; d) = Σ_r B_r(x/D) C_ri(d) with D = d_s.  On the
 * patch x = u δ00(v) and D = δ00(v), so x/D = u exactly: the u-direction functions are
 * Σ_r B_r(u) C_ri(d(v)), with C depending on v only through the blended intervals.  C is
 * evaluated on jets in v (core/jet.h), which yields ∂/∂v and ∂²/∂v² of the coefficients
 * exactly; symmetrically for the v-direction functions.  The patch is then a short sum. */
#include "patch/augmented.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec3.h"

#define MAXW Q2N_SPLINE_MAXW

/* ---------------------------------------------------------------- stencil gathering */

/* A grid cell (face f with its corner r at the cell's lower-left); f = -1: absent. */
typedef struct cell { int f, r; } cell;

typedef struct grid {
    int w, h;
    cell c[MAXW - 1][MAXW - 1];        /* [cj][ci], cell (ci,cj) spans grid points ci..ci+1 */
    int vid[MAXW][MAXW];               /* [j][i] mesh vertex or -1 */
    int known[MAXW][MAXW];
    double P[MAXW][MAXW][3];
    int hedge[MAXW][MAXW - 1];         /* edge (i..i+1, j): mesh edge id or -1 */
    int vedge[MAXW - 1][MAXW];         /* edge (i, j..j+1) */
} grid;

static int corner_vertex(const q2n_mesh *m, cell c, int q) /* q: 0 LL, 1 LR, 2 UR, 3 UL */
{
    return m->face_vert[m->face_start[c.f] + (c.r + q) % 4];
}

/* Neighbour cell across side s of c (0 bottom, 1 right, 2 top, 3 left); f = -1 if none. */
static cell cross(const q2n_mesh *m, cell c, int s, int *nonquad)
{
    cell out = {-1, 0};
    int he = q2n_face_he(m, c.f, (c.r + s) % 4);
    int t = m->he_twin[he];
    if (t < 0) return out;
    int g = m->he_face[t];
    if (q2n_face_size(m, g) != 4) { *nonquad = 1; return out; }
    int idx = t - m->face_start[g];
    /* the twin is side (s+2) of the neighbour cell: r' + s + 2 = idx (mod 4) */
    out.f = g;
    out.r = ((idx - s - 2) % 4 + 8) % 4;
    return out;
}

static int vertex_grid_regular(const q2n_mesh *m, int v)
{
    if (m->vert_boundary[v]) return m->vert_nfaces[v] <= 2;
    return m->valence[v] == 4;
}

/* Fill the cells by breadth-first walking from the face; 0 if the neighbourhood is not a grid. */
static int gather_cells(const q2n_mesh *m, int f, grid *G)
{
    int n = G->w - 1, off = G->h - 1; /* cell ci at index ci + off */
    int qi[(MAXW - 1) * (MAXW - 1)], qj[(MAXW - 1) * (MAXW - 1)], head = 0, tail = 0, nonquad = 0;
    static const int dx[4] = {0, 1, 0, -1}, dy[4] = {-1, 0, 1, 0};
    int seen[MAXW - 1][MAXW - 1] = {{0}};
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) G->c[j][i].f = -1;
    G->c[off][off].f = f;
    G->c[off][off].r = 0;
    seen[off][off] = 1;
    qi[tail] = off, qj[tail++] = off;
    while (head < tail) {
        int i = qi[head], j = qj[head++];
        for (int s = 0; s < 4; s++) {
            int ni = i + dx[s], nj = j + dy[s];
            if (ni < 0 || nj < 0 || ni >= n || nj >= n) continue;
            cell nc = cross(m, G->c[j][i], s, &nonquad);
            if (nonquad) return 0;
            if (seen[nj][ni]) {
                if (nc.f != G->c[nj][ni].f || (nc.f >= 0 && nc.r != G->c[nj][ni].r)) return 0;
                continue;
            }
            seen[nj][ni] = 1;
            G->c[nj][ni] = nc;
            if (nc.f >= 0) qi[tail] = ni, qj[tail++] = nj;
        }
    }
    return 1;
}

/* Grid points and edges from the cells; consistency of shared corners. */
static int assign_points(const q2n_mesh *m, grid *G)
{
    int n = G->w - 1;
    for (int j = 0; j < G->w; j++)
        for (int i = 0; i < G->w; i++) {
            G->vid[j][i] = -1;
            if (i < n) G->hedge[j][i] = -1;
            if (j < n) G->vedge[j][i] = -1;
        }
    for (int cj = 0; cj < n; cj++)
        for (int ci = 0; ci < n; ci++) {
            cell c = G->c[cj][ci];
            if (c.f < 0) continue;
            for (int q = 0; q < 4; q++) {
                int v = corner_vertex(m, c, q), *slot = &G->vid[cj + q2n_corner_uv[q][1]][ci + q2n_corner_uv[q][0]];
                if (*slot >= 0 && *slot != v) return 0;
                *slot = v;
            }
            int base = m->face_start[c.f];
            G->hedge[cj][ci] = m->he_edge[base + (c.r + 0) % 4];
            G->vedge[cj][ci + 1] = m->he_edge[base + (c.r + 1) % 4];
            G->hedge[cj + 1][ci] = m->he_edge[base + (c.r + 2) % 4];
            G->vedge[cj][ci] = m->he_edge[base + (c.r + 3) % 4];
        }
    /* every grid-interior mesh vertex (whose 3x3 neighbourhood lies in the grid) must be
     * regular; missing ones lie beyond the boundary and are extrapolated */
    for (int j = 1; j < G->w - 1; j++)
        for (int i = 1; i < G->w - 1; i++)
            if (G->vid[j][i] >= 0 && !vertex_grid_regular(m, G->vid[j][i])) return 0;
    return 1;
}

/* Linear extrapolation across the boundary (seed 003 §3.1): a missing point is 2a - b where a, b
 * are the next two points inward on its grid line, rows before columns, in passes so that the
 * result does not depend on visiting order. */
static int extrapolate(const q2n_mesh *m, grid *G)
{
    int w = G->w, missing = 0;
    for (int j = 0; j < w; j++)
        for (int i = 0; i < w; i++) {
            G->known[j][i] = G->vid[j][i] >= 0;
            if (G->known[j][i]) memcpy(G->P[j][i], q2n_mesh_vpos(m, G->vid[j][i]), 3 * sizeof(double));
            else missing++;
        }
    while (missing > 0) {
        int filled[MAXW][MAXW] = {{0}}, progress = 0;
        for (int j = 0; j < w; j++)
            for (int i = 0; i < w; i++) {
                if (G->known[j][i]) continue;
                static const int dirs[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
                for (int d = 0; d < 4; d++) {
                    int ai = i + dirs[d][0], aj = j + dirs[d][1];
                    int bi = i + 2 * dirs[d][0], bj = j + 2 * dirs[d][1];
                    if (bi < 0 || bj < 0 || bi >= w || bj >= w) continue;
                    if (!G->known[aj][ai] || !G->known[bj][bi]) continue;
                    for (int c = 0; c < 3; c++) G->P[j][i][c] = 2 * G->P[aj][ai][c] - G->P[bj][bi][c];
                    filled[j][i] = 1;
                    break;
                }
            }
        for (int j = 0; j < w; j++)
            for (int i = 0; i < w; i++)
                if (filled[j][i]) G->known[j][i] = 1, missing--, progress = 1;
        if (!progress) return 0;
    }
    return 1;
}

/* Interval of a grid edge: the mesh edge's interval when the edge is real; for an extrapolated
 * edge |Δp|^α of the extrapolated points, except in the mean parametrization, where it takes the
 * (ribbon-averaged) interval of the nearest real edge of its ribbon — the same column pair in
 * the nearest row — or else of its section line, so faces stay rectangles. */
static double grid_interval(const grid *G, int horizontal, int i, int j, const double *edge_iv,
                            const q2n_param_options *popt)
{
    int w = G->w;
    int e = horizontal ? G->hedge[j][i] : G->vedge[j][i];
    if (e >= 0) return edge_iv[e];
    const double *a = G->P[j][i], *b = horizontal ? G->P[j][i + 1] : G->P[j + 1][i];
    if (popt->method != Q2N_PARAM_MEAN) return q2n_param_interval(a, b, q2n_param_alpha(popt));
    for (int dist = 1; dist < w; dist++) {
        for (int sgn = -1; sgn <= 1; sgn += 2) { /* same ribbon: shift across the edge direction */
            int jj = horizontal ? j + sgn * dist : j, ii = horizontal ? i : i + sgn * dist;
            if (jj < 0 || ii < 0 || (horizontal && (jj >= w)) || (!horizontal && ii >= w)) continue;
            int ee = horizontal ? G->hedge[jj][ii] : G->vedge[jj][ii];
            if (ee >= 0) return edge_iv[ee];
        }
    }
    for (int dist = 1; dist < w; dist++) {
        for (int sgn = -1; sgn <= 1; sgn += 2) { /* same section line */
            int jj = horizontal ? j : j + sgn * dist, ii = horizontal ? i + sgn * dist : i;
            if (jj < 0 || ii < 0 || (horizontal && ii >= w - 1) || (!horizontal && jj >= w - 1)) continue;
            int ee = horizontal ? G->hedge[jj][ii] : G->vedge[jj][ii];
            if (ee >= 0) return edge_iv[ee];
        }
    }
    return q2n_param_interval(a, b, q2n_param_alpha(popt));
}

/* q2n_augmented_setup with the grid (mesh vertex of every point) left in *G. */
static int setup_grid(const q2n_mesh *m, int f, const q2n_spline_class *cls, const q2n_param_options *popt,
                      const double *edge_iv, grid *G, q2n_augmented_patch *out)
{
    if (q2n_face_size(m, f) != 4) return 0;
    G->w = cls->w;
    G->h = cls->w / 2;
    if (!gather_cells(m, f, G) || !assign_points(m, G) || !extrapolate(m, G)) return 0;
    int w = G->w, h = G->h;
    memset(out, 0, sizeof *out);
    out->cls = cls;
    out->w = w;
    for (int j = 0; j < w; j++)
        for (int i = 0; i < w; i++) memcpy(out->P + 3 * (j * w + i), G->P[j][i], 3 * sizeof(double));
    for (int r = 0; r < 2; r++)
        for (int i = 0; i < w - 1; i++) {
            out->drow[r][i] = grid_interval(G, 1, i, h - 1 + r, edge_iv, popt);
            out->ecol[r][i] = grid_interval(G, 0, h - 1 + r, i, edge_iv, popt);
        }
    return 1;
}

int q2n_augmented_setup(const q2n_mesh *m, int f, const q2n_spline_class *cls,
                        const q2n_param_options *popt, const double *edge_iv,
                        q2n_augmented_patch *out)
{
    grid G;
    return setup_grid(m, f, cls, popt, edge_iv, &G, out);
}

/* ---------------------------------------------------------------- storage in the surface */

/* The surface keeps a regular patch compactly: its grid as indices into one point pool shared by
 * all the surface's augmented patches (the mesh's vertices, then the extrapolated points of open
 * meshes), expanded into a q2n_augmented_patch when evaluated — 360 instead of 1 070 bytes per
 * face, the same values. */
typedef struct aug_pool {
    double *pts;
    int n, cap;
    long refs;                      /* patches that use it: the last one frees it */
    int mapped;                     /* q2n_augmented_map_points: already through this map */
} aug_pool;

typedef struct aug_stored {
    const q2n_spline_class *cls;
    aug_pool *pool;
    int w;
    int idx[MAXW * MAXW];           /* point of grid index j * w + i in the pool */
    double drow[2][MAXW], ecol[2][MAXW];
} aug_stored;

static void expand(const aug_stored *a, q2n_augmented_patch *p)
{
    int n = a->w * a->w;
    p->cls = a->cls;
    p->w = a->w;
    memcpy(p->drow, a->drow, sizeof p->drow);
    memcpy(p->ecol, a->ecol, sizeof p->ecol);
    for (int g = 0; g < n; g++) memcpy(p->P + 3 * g, a->pool->pts + 3 * (size_t)a->idx[g], 3 * sizeof(double));
}

static int pool_add(aug_pool *pl, const double x[3])
{
    if (pl->n == pl->cap) {
        int cap = pl->cap + pl->cap / 2 + 16;
        double *np = realloc(pl->pts, 3 * sizeof(double) * (size_t)cap);
        if (!np) return -1;
        pl->pts = np;
        pl->cap = cap;
    }
    memcpy(pl->pts + 3 * (size_t)pl->n, x, 3 * sizeof(double));
    return pl->n++;
}

static void free_stored(void *d)
{
    aug_stored *a = d;
    if (a && --a->pool->refs == 0) {
        free(a->pool->pts);
        free(a->pool);
    }
    free(a);
}

int q2n_augmented_patch_get(const q2n_surface *s, int f, q2n_augmented_patch *out)
{
    if (q2n_surface_kind(s, f) != Q2N_PATCH_AUGMENTED) return 0;
    const aug_stored *a = q2n_surface_patch_data(s, f);
    if (!a) return 0;
    expand(a, out);
    return 1;
}

void q2n_augmented_map_points(q2n_surface *s, const double L[3][3])
{
    /* patches share their build's point pool: each pool is mapped once */
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < q2n_surface_npatches(s); k++) {
            if (q2n_surface_kind(s, k) != Q2N_PATCH_AUGMENTED) continue;
            aug_stored *a = q2n_surface_patch_data_mut(s, k);
            if (!a) continue;
            if (!pass) { a->pool->mapped = 0; continue; }
            if (a->pool->mapped) continue;
            for (int q = 0; q < a->pool->n; q++) {
                double *x = a->pool->pts + 3 * (size_t)q, y[3];
                for (int i = 0; i < 3; i++) y[i] = L[i][0] * x[0] + L[i][1] * x[1] + L[i][2] * x[2];
                memcpy(x, y, sizeof y);
            }
            a->pool->mapped = 1;
        }
}

/* ---------------------------------------------------------------- evaluation */

/* Evaluations along a patch side keep one parameter fixed (v = 0 on side 0, ...), so the same
 * coefficients are asked for again and again: a few recent ones per thread, keyed by everything
 * they depend on (class, intervals, parameter bits), are copied instead of recomputed.  An entry
 * holds jets (order 2) or values only (order 0: positions need no cross derivatives); a jet entry
 * answers a request for values too (its d[0] are the values, bit for bit). */
#define COEF_MEMO_N 8
typedef struct coef_memo {
    unsigned long used;                 /* last use (0: empty); the least recent is replaced */
    const q2n_spline_class *cls;
    int w, order;
    uint64_t xbits;
    double d[2][MAXW];
    q2n_jet C[Q2N_SPLINE_MAXB * MAXW];
} coef_memo;
static _Thread_local coef_memo coef_memo_tab[COEF_MEMO_N];
static _Thread_local unsigned long coef_memo_clock;

/* The coefficients at x of intervals blended from d0 to d1, as jets in x (order 2) or, order 0,
 * values only (C[.].d[1], d[2] then undefined). */
static void coeffs_memo(const q2n_spline_class *cls, int w, const double *d0, const double *d1, double x, int order,
                        q2n_jet *C)
{
    uint64_t xb;
    memcpy(&xb, &x, sizeof xb);
    size_t nd = sizeof(double) * (size_t)(w - 1), nc = sizeof(q2n_jet) * (size_t)(cls->nb * w);
    coef_memo *m = NULL, *old = &coef_memo_tab[0];
    for (int i = 0; i < COEF_MEMO_N && !m; i++) {
        coef_memo *e = &coef_memo_tab[i];
        if (e->used && e->cls == cls && e->w == w && e->order >= order && e->xbits == xb && !memcmp(e->d[0], d0, nd) &&
            !memcmp(e->d[1], d1, nd))
            m = e;
        else if (e->used < old->used)
            old = e;
    }
    if (!m) {
        m = old;
        if (order > 0) {
            q2n_jet d[MAXW];
            for (int i = 0; i < w - 1; i++) d[i] = q2n_spline_blend(cls->k, d0[i], d1[i], x);
            q2n_spline_coeffs(cls, d, m->C);
        } else {
            double d[MAXW], Cv[Q2N_SPLINE_MAXB * MAXW], h = q2n_spline_blend_weight(cls->k, x);
            for (int i = 0; i < w - 1; i++) d[i] = d0[i] + (d1[i] - d0[i]) * h;
            q2n_spline_coeffs_value(cls, d, Cv);
            for (int i = 0; i < cls->nb * w; i++) m->C[i] = q2n_jet_const(Cv[i]);
        }
        m->cls = cls;
        m->w = w;
        m->order = order;
        m->xbits = xb;
        memcpy(m->d[0], d0, nd);
        memcpy(m->d[1], d1, nd);
    }
    m->used = ++coef_memo_clock;
    memcpy(C, m->C, nc);
}

void q2n_augmented_coeffs(const q2n_spline_class *cls, int w, const double *d0, const double *d1, double x,
                          q2n_jet *C)
{
    coeffs_memo(cls, w, d0, d1, x, 2, C);
}

/* Coefficients of the u-direction functions at v (jets in v; values only when order is 0) — eq. (8a)
 * blended intervals. */
static void u_coeffs(const q2n_augmented_patch *p, double v, int order, q2n_jet *C)
{
    coeffs_memo(p->cls, p->w, p->drow[0], p->drow[1], v, order, C);
}

static void v_coeffs(const q2n_augmented_patch *p, double u, int order, q2n_jet *C)
{
    coeffs_memo(p->cls, p->w, p->ecol[0], p->ecol[1], u, order, C);
}

/* Fundamental functions and their partials in (own, cross) variables:
 * F[0]=ψ, F[1]=∂own, F[2]=∂cross, F[3]=∂own², F[4]=∂own∂cross, F[5]=∂cross². */
static void combine(int w, int nb, const double *B, const q2n_jet *C, int nder, double F[6][MAXW])
{
    for (int i = 0; i < w; i++) {
        double a[6] = {0, 0, 0, 0, 0, 0};
        for (int r = 0; r < nb; r++) {
            const q2n_jet c = C[r * w + i];
            a[0] += B[r] * c.d[0];
            if (nder >= 1) { a[1] += B[nb + r] * c.d[0]; a[2] += B[r] * c.d[1]; }
            if (nder >= 2) {
                a[3] += B[2 * nb + r] * c.d[0];
                a[4] += B[nb + r] * c.d[1];
                a[5] += B[r] * c.d[2];
            }
        }
        for (int q = 0; q < 6; q++) F[q][i] = a[q];
    }
}

/* R[j] = Σ_i p_ij f[i]: the control net's rows summed with the fundamental functions' values f. */
static void row_sums(const q2n_augmented_patch *p, const double *f, double R[][3])
{
    int w = p->w;
    for (int j = 0; j < w; j++) {
        const double *P = p->P + 3 * j * w;
        double x = 0, y = 0, z = 0;
        for (int i = 0; i < w; i++) {
            x += f[i] * P[3 * i];
            y += f[i] * P[3 * i + 1];
            z += f[i] * P[3 * i + 2];
        }
        R[j][0] = x, R[j][1] = y, R[j][2] = z;
    }
}

/* S and partials from ψ (u-direction, F[.] in (u,v)) and φ (v-direction, G[.] in (v,u)):
 * first the row sums R_q[j] = Σ_i p_ij ψ_q,i for every partial q of ψ, then Leibniz's rule
 * S_ab = Σ C(a,a')C(b,b') Σ_j R_{a'b'}[j] φ_{a-a',b-b'}[j]. */
static void assemble(const q2n_augmented_patch *p, int nder, double F[6][MAXW], double Gv[6][MAXW],
                     double *out)
{
    int w = p->w, nout = nder == 0 ? 1 : nder == 1 ? 3 : 6;
    double R[6][MAXW][3];
    for (int q = 0; q < nout; q++) row_sums(p, F[q], R[q]);
    /* partials of φ in (u,v) order: φ, φ_u, φ_v, φ_uu, φ_uv, φ_vv */
    const double *phi[6] = {Gv[0], Gv[2], Gv[1], Gv[5], Gv[4], Gv[3]};
    static const int terms[6][4][3] = {
        {{0, 0, 1}},
        {{1, 0, 1}, {0, 1, 1}},
        {{2, 0, 1}, {0, 2, 1}},
        {{3, 0, 1}, {1, 1, 2}, {0, 3, 1}},
        {{4, 0, 1}, {1, 2, 1}, {2, 1, 1}, {0, 4, 1}},
        {{5, 0, 1}, {2, 2, 2}, {0, 5, 1}}};
    static const int nterms[6] = {1, 2, 2, 3, 4, 3};
    for (int o = 0; o < nout; o++) {
        double x = 0, y = 0, z = 0;
        for (int t = 0; t < nterms[o]; t++) {
            double (*Rq)[3] = R[terms[o][t][0]];
            const double *ph = phi[terms[o][t][1]];
            double fac = terms[o][t][2];
            for (int j = 0; j < w; j++) {
                double c = fac * ph[j];
                x += c * Rq[j][0];
                y += c * Rq[j][1];
                z += c * Rq[j][2];
            }
        }
        out[3 * o] = x, out[3 * o + 1] = y, out[3 * o + 2] = z;
    }
}

void q2n_augmented_eval(const q2n_augmented_patch *p, double u, double v, int nder, double *out)
{
    int w = p->w, nb = p->cls->nb;
    q2n_jet Cu[Q2N_SPLINE_MAXB * MAXW], Cv[Q2N_SPLINE_MAXB * MAXW];
    double Bu[4 * Q2N_SPLINE_MAXB], Bv[4 * Q2N_SPLINE_MAXB], F[6][MAXW], Gv[6][MAXW];
    u_coeffs(p, v, nder > 0 ? 2 : 0, Cu); /* positions need no cross derivatives */
    v_coeffs(p, u, nder > 0 ? 2 : 0, Cv);
    p->cls->basis(u, nder, Bu);
    p->cls->basis(v, nder, Bv);
    combine(w, nb, Bu, Cu, nder, F);
    combine(w, nb, Bv, Cv, nder, Gv);
    assemble(p, nder, F, Gv, out);
}

/* Mixed partials ∂u^a ∂v^b S (a, b <= 2) at (u, v): the same sum as q2n_augmented_eval with the full
 * 3 x 3 table of the fundamental functions' partials (basis derivatives in the own variable, the
 * coefficients' jets in the cross one) and Leibniz's rule over both factors of eq. (10):
 *   S_ab = Σ_{a'<=a, b'<=b} C(a,a') C(b,b') Σ_j (Σ_i p_ij ψ_i^{a'b'}) φ_j^{(b-b')(a-a')},
 * ψ^{a'b'} = ∂u^a' ∂v^b' ψ, φ^{cd} = ∂v^c ∂u^d φ. */
static void augmented_mixed(const q2n_augmented_patch *p, double u, double v, double S[3][3][3])
{
    int w = p->w, nb = p->cls->nb;
    q2n_jet Cu[Q2N_SPLINE_MAXB * MAXW], Cv[Q2N_SPLINE_MAXB * MAXW];
    double Bu[4 * Q2N_SPLINE_MAXB], Bv[4 * Q2N_SPLINE_MAXB], Psi[3][3][MAXW], Phi[3][3][MAXW];
    u_coeffs(p, v, 2, Cu);
    v_coeffs(p, u, 2, Cv);
    p->cls->basis(u, 2, Bu);
    p->cls->basis(v, 2, Bv);
    for (int a = 0; a <= 2; a++)
        for (int b = 0; b <= 2; b++)
            for (int i = 0; i < w; i++) {
                double x = 0, y = 0;
                for (int r = 0; r < nb; r++) {
                    x += Bu[a * nb + r] * Cu[r * w + i].d[b];
                    y += Bv[a * nb + r] * Cv[r * w + i].d[b];
                }
                Psi[a][b][i] = x;
                Phi[a][b][i] = y;
            }
    double R[3][3][MAXW][3]; /* R[a'][b'][j] = Σ_i p_ij ψ_i^{a'b'} */
    for (int a = 0; a <= 2; a++)
        for (int b = 0; b <= 2; b++) row_sums(p, Psi[a][b], R[a][b]);
    for (int a = 0; a <= 2; a++)
        for (int b = 0; b <= 2; b++) {
            double x = 0, y = 0, z = 0;
            for (int a1 = 0; a1 <= a; a1++)
                for (int b1 = 0; b1 <= b; b1++) {
                    double c = q2n_binom[a][a1] * q2n_binom[b][b1];
                    const double *ph = Phi[b - b1][a - a1];
                    for (int j = 0; j < w; j++) {
                        double f = c * ph[j];
                        x += f * R[a1][b1][j][0];
                        y += f * R[a1][b1][j][1];
                        z += f * R[a1][b1][j][2];
                    }
                }
            S[a][b][0] = x, S[a][b][1] = y, S[a][b][2] = z;
        }
}

/* The exact corner hook (q2n_surface_set_patch_corner): the patch is smooth at its corners, so both
 * sides through one report the same partials. */
static q2n_status corner_cb(const void *data, int i, int j, double out[2][2][2][3])
{
    q2n_augmented_patch p;
    expand(data, &p);
    double S[3][3][3];
    augmented_mixed(&p, i, j, S);
    for (int sd = 0; sd < 2; sd++)
        for (int a = 1; a <= 2; a++)
            for (int b = 1; b <= 2; b++) memcpy(out[sd][a - 1][b - 1], S[a][b], sizeof S[a][b]);
    return Q2N_OK;
}

static q2n_status eval_cb(const void *data, double u, double v, int nder, double *out)
{
    q2n_augmented_patch p;
    expand(data, &p);
    q2n_augmented_eval(&p, u, v, nder, out);
    return Q2N_OK;
}

/* Grid fast path.  On a tensor grid the v-direction coefficients depend on u only (one set per
 * column) and the u-direction ones on v only (one set per row), so per point only contractions
 * remain:  with T_rj = Σ_i C_ri p_ij per row (and T'_rj from the v-derivatives of C),
 *   S = Σ_j φ_j Σ_r B_r(u) T_rj,   φ_j = Σ_s B_s(v) C'_sj(u).
 * Points are processed in batches of QB columns held in one vector register (GCC/Clang vector
 * extension, no intrinsics), so the arithmetic runs on QB points at once and the accumulators
 * stay in registers. */
#define QB 2
/* QB doubles processed together (GCC/Clang vector extension: one SSE2 register) */
typedef double vqb __attribute__((vector_size(16)));
typedef struct grid_cols {   /* per batch of QB columns */
    vqb B0[Q2N_SPLINE_MAXB], B1[Q2N_SPLINE_MAXB];            /* B_r(u), B_r'(u) */
    vqb C0[Q2N_SPLINE_MAXB][MAXW], C1[Q2N_SPLINE_MAXB][MAXW]; /* C'_sj(u) and d/du */
} grid_cols;

static inline __attribute__((always_inline)) void grid_batch_k(int w, int nb, const grid_cols *gc,
                                                               const double *bv0, const double *bv1,
                                                               double T0[][MAXW][3], double T1[][MAXW][3],
                                                               int np, double *out)
{
    vqb S[9] = {{0}};
    for (int j = 0; j < w; j++) {
        vqb p0 = {0}, pu = {0}, pv = {0};
        for (int s = 0; s < nb; s++) {
            p0 += bv0[s] * gc->C0[s][j];
            pu += bv0[s] * gc->C1[s][j];
            pv += bv1[s] * gc->C0[s][j];
        }
        for (int c = 0; c < 3; c++) {
            vqb r0 = {0}, r1 = {0}, r2 = {0};
            for (int r = 0; r < nb; r++) {
                r0 += gc->B0[r] * T0[r][j][c];
                r1 += gc->B1[r] * T0[r][j][c];
                r2 += gc->B0[r] * T1[r][j][c];
            }
            S[c] += p0 * r0;
            S[3 + c] += p0 * r1 + pu * r0;
            S[6 + c] += p0 * r2 + pv * r0;
        }
    }
    for (int q = 0; q < np; q++)
        for (int k = 0; k < 9; k++) out[9 * q + k] = S[k][q];
}

/* Specializations for the supported (w, nb) pairs: constant loop bounds let the compiler unroll
 * and vectorize the kernel. */
#define GRID_BATCH(W, NB)                                                                         \
    static void grid_batch_##W##_##NB(const grid_cols *gc, const double *bv0, const double *bv1,  \
                                      double T0[][MAXW][3], double T1[][MAXW][3], int np, double *out) \
    {                                                                                            \
        grid_batch_k(W, NB, gc, bv0, bv1, T0, T1, np, out);                                      \
    }
GRID_BATCH(4, 4)
GRID_BATCH(4, 6)
GRID_BATCH(6, 6)

static void grid_batch(const q2n_augmented_patch *p, const grid_cols *gc, const double *bv0, const double *bv1,
                       double T0[][MAXW][3], double T1[][MAXW][3], int np, double *out)
{
    int w = p->w, nb = p->cls->nb;
    if (w == 4 && nb == 4) grid_batch_4_4(gc, bv0, bv1, T0, T1, np, out);
    else if (w == 4 && nb == 6) grid_batch_4_6(gc, bv0, bv1, T0, T1, np, out);
    else if (w == 6 && nb == 6) grid_batch_6_6(gc, bv0, bv1, T0, T1, np, out);
    else grid_batch_k(w, nb, gc, bv0, bv1, T0, T1, np, out);
}

static q2n_status eval_grid_cb(const void *data, int nu, const double *us, int nv, const double *vs,
                               double *out)
{
    q2n_augmented_patch pe;
    expand(data, &pe);
    const q2n_augmented_patch *p = &pe;
    int w = p->w, nb = p->cls->nb, nbatch = (nu + QB - 1) / QB;
    grid_cols *gc = aligned_alloc(32, (size_t)nbatch * sizeof *gc);
    if (!gc) return Q2N_ERR_NOMEM;
    memset(gc, 0, (size_t)nbatch * sizeof *gc);
    for (int a = 0; a < nu; a++) {
        q2n_jet Cv[Q2N_SPLINE_MAXB * MAXW];
        double Bu[4 * Q2N_SPLINE_MAXB];
        grid_cols *g = gc + a / QB;
        int q = a % QB;
        v_coeffs(p, us[a], 2, Cv);
        p->cls->basis(us[a], 1, Bu);
        for (int r = 0; r < nb; r++) {
            g->B0[r][q] = Bu[r];
            g->B1[r][q] = Bu[nb + r];
            for (int j = 0; j < w; j++) {
                g->C0[r][j][q] = Cv[r * w + j].d[0];
                g->C1[r][j][q] = Cv[r * w + j].d[1];
            }
        }
    }
    for (int b = 0; b < nv; b++) {
        q2n_jet Cu[Q2N_SPLINE_MAXB * MAXW];
        double Bv[4 * Q2N_SPLINE_MAXB], T0[Q2N_SPLINE_MAXB][MAXW][3], T1[Q2N_SPLINE_MAXB][MAXW][3];
        u_coeffs(p, vs[b], 2, Cu);
        p->cls->basis(vs[b], 1, Bv);
        for (int r = 0; r < nb; r++)
            for (int j = 0; j < w; j++) {
                double x0[3] = {0, 0, 0}, x1[3] = {0, 0, 0};
                for (int i = 0; i < w; i++) {
                    q2n_v3_axpy(x0, Cu[r * w + i].d[0], p->P + 3 * (j * w + i));
                    q2n_v3_axpy(x1, Cu[r * w + i].d[1], p->P + 3 * (j * w + i));
                }
                memcpy(T0[r][j], x0, sizeof x0);
                memcpy(T1[r][j], x1, sizeof x1);
            }
        for (int k = 0; k < nbatch; k++) {
            int np = nu - k * QB < QB ? nu - k * QB : QB;
            grid_batch(p, gc + k, Bv, Bv + nb, T0, T1, np, out + 9 * ((size_t)b * nu + (size_t)k * QB));
        }
    }
    free(gc);
    return Q2N_OK;
}

q2n_status q2n_augmented_build(const q2n_mesh *m, const q2n_augmented_options *opt,
                               const double *edge_iv, q2n_surface **out, q2n_error *err)
{
    const q2n_spline_class *cls = opt->cls ? opt->cls : q2n_spline_class_find(Q2N_SPLINE_CLASS_DEFAULT);
    double *own = NULL;
    q2n_status st;
    if (!edge_iv) {
        if ((st = q2n_param_edge_intervals(m, &opt->param, &own, err))) return st;
        edge_iv = own;
    }
    q2n_surface *s = q2n_surface_create(m->nf);
    aug_pool *pool = calloc(1, sizeof *pool);
    if (!s || !pool) {
        q2n_surface_free(s); free(pool); free(own);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (surface)");
    }
    /* the pool starts with the mesh's vertices: a grid point that is a mesh vertex is its index */
    for (int v = 0; v < m->nv && pool->n >= 0; v++)
        if (pool_add(pool, q2n_mesh_vpos(m, v)) < 0) pool->n = -1;
    pool->refs = 1;   /* the build's own reference, dropped at the end */
    for (int f = 0; f < m->nf && pool->n >= 0; f++) {
        q2n_augmented_patch tmp;
        grid G;
        if (!setup_grid(m, f, cls, &opt->param, edge_iv, &G, &tmp)) continue;
        aug_stored *a = malloc(sizeof *a);
        if (!a) { pool->n = -1; break; }
        a->cls = tmp.cls;
        a->pool = pool;
        a->w = tmp.w;
        memcpy(a->drow, tmp.drow, sizeof a->drow);
        memcpy(a->ecol, tmp.ecol, sizeof a->ecol);
        for (int j = 0; j < tmp.w; j++)
            for (int i = 0; i < tmp.w; i++) {
                int id = G.vid[j][i] >= 0 ? G.vid[j][i] : pool->n < 0 ? -1 : pool_add(pool, G.P[j][i]);
                if (id < 0) pool->n = -1;
                a->idx[j * tmp.w + i] = id;
            }
        pool->refs++;
        q2n_surface_set_patch(s, f, Q2N_PATCH_AUGMENTED, a, eval_cb, free_stored);
        q2n_surface_set_patch_grid(s, f, eval_grid_cb);
        q2n_surface_set_patch_corner(s, f, corner_cb);
    }
    int failed = pool->n < 0;
    if (--pool->refs == 0) { free(pool->pts); free(pool); }
    if (failed) {
        q2n_surface_free(s); free(own);
        return q2n_error_set(err, Q2N_ERR_NOMEM, "out of memory (patches)");
    }
    free(own);
    *out = s;
    return Q2N_OK;
}
