/* acc_g1.c — the G1 masks of Marsala–Mantzaflaris–Mourrain 2022 (seed 001 §4–5) around one
 * extraordinary vertex, applied to the ACC5 (degree-elevated ACC3) sector patches.
 *
 * The paper solves for masks (weight vectors over the EV's one-ring); every step is linear and
 * commutes with the rotation of the sectors, so the same solves are done here on the sector
 * sequences of points (or of masks: the code is generic in `dim`).  Circulant systems become
 * discrete Fourier statements over the sector index k:
 *   eq. (13)+(15)-(16): x_k = b00 + (frequency ±1 part of the ACC5 points)   (orthogonal projection);
 *   eq. (21)-(25), even N: remove the alternating (frequency N/2) part of M_{2,0}^even;
 *   eq. (17)-(20), (26)-(27): z_k + z_{k-1} = d_k solved per frequency, frequency N/2 taken
 *   from ACC5 (the orthogonal projection of Corollary 3).
 * Conventions: sector k is the face (v, e_k, f_k, e_{k+1}), local (i,j) with i along v->e_k and
 * j along v->e_{k+1}.  Edge e_k is the u'-edge of sector k ("patch 1" of eq. (4)) and the v'-edge
 * of sector k-1 ("patch 0"), so M^{(0)}_{1,0} is x_{k-1} and M_{0,1} is x_{k+1}.
 *
 * Deviation from the printed text, checked against the paper's own Example 2: M_{2,0}^even
 * (§5.2.1.2) uses the new order-1 mask M_{1,0}, not the ACC5 mask; with the ACC5 mask the
 * Example-2 fractions are not reproduced, with M_{1,0} they are, exactly.  Eq. (31)'s second
 * line has a sign slip; we use M_{1,2}^{(0)} = r - M_{2,1}, which is what (30) requires. */
#include "acc/acc_masks.h"
#include "core/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dense.h"


typedef struct g1ctx {
    int n;          /* sectors */
    int dim;
    double **P;     /* output sector patches (EV-local) */
    double *A;      /* copy of the ACC5 input, n blocks of 36*dim */
    double *x, *y, *w, *z; /* per edge/sector work sequences, n*dim each */
    double *r;      /* dim scratch */
    double a0;      /* gluing data a_0 = 2 cos(angle), eq. (3) */
    double theta;   /* eq. (31): 1 symmetric, 0 asymmetric */
    int cs;         /* circulant-system strategy for order 2 */
} g1ctx;

static inline double *LP(double *p, int dim, int i, int j) { return p + (size_t)(j * 6 + i) * dim; }
static inline double *AP(const g1ctx *g, int k, int i, int j)
{
    return g->A + ((size_t)k * 36 + (size_t)(j * 6 + i)) * g->dim;
}
static inline double *SEQ(double *s, const g1ctx *g, int k) { return s + (size_t)k * g->dim; }

static void lin(double *out, int dim, int nterm, const double *c, const double *const *v)
{
    for (int t = 0; t < dim; t++) {
        double s = 0;
        for (int q = 0; q < nterm; q++) s += c[q] * v[q][t];
        out[t] = s;
    }
}

/* Point i of edge e_k (k = sector owning it as u'-edge), written into both patches. */
static void set_edge(g1ctx *g, int k, int kprev, int i, const double *val)
{
    memcpy(LP(g->P[k], g->dim, i, 0), val, (size_t)g->dim * sizeof *val);
    memcpy(LP(g->P[kprev], g->dim, 0, i), val, (size_t)g->dim * sizeof *val);
}

static q2n_status g1_alloc(g1ctx *g, int n, int dim, q2n_acc_strategy st, double **P, double a0,
                           q2n_error *err)
{
    memset(g, 0, sizeof *g);
    g->n = n;
    g->dim = dim;
    g->P = P;
    g->a0 = a0;
    g->cs = (st == Q2N_ACC_CS_S || st == Q2N_ACC_CS_AS);
    g->theta = (st == Q2N_ACC_CS_S || st == Q2N_ACC_NCS_S) ? 1.0 : 0.0;
    size_t blk = 36 * (size_t)dim, seq = (size_t)n * dim;
    g->A = malloc(((size_t)n * blk + 4 * seq + dim) * sizeof *g->A);
    if (!g->A) return q2n_error_set(err, Q2N_ERR_NOMEM, "acc-g1: out of memory (%d sectors)", n);
    for (int k = 0; k < n; k++) memcpy(g->A + k * blk, P[k], blk * sizeof *g->A);
    g->x = g->A + (size_t)n * blk;
    g->y = g->x + seq;
    g->w = g->y + seq;
    g->z = g->w + seq;
    g->r = g->z + seq;
    return Q2N_OK;
}

/* Eq. (11) solved for M_{2,0} (eq. 18): y = (-b00 + 5x + 10 b30 - 5 b40 + b50)/10 (ACC5 b30..b50). */
static void m20_from_11(const g1ctx *g, int k, const double *x, double *y)
{
    const double *b00 = AP(g, 0, 0, 0);
    const double c[5] = { -0.1, 0.5, 1.0, -0.5, 0.1 };
    const double *v[5] = { b00, x, AP(g, k, 3, 0), AP(g, k, 4, 0), AP(g, k, 5, 0) };
    lin(y, g->dim, 5, c, v);
}

/* Eq. (29) (NCS): M_{2,0} = (-a0 M00 + 5(a0-2) M10 + 5(M11 + M11^{(0)}))/(4 a0), ACC5 M11's. */
static void m20_from_29(const g1ctx *g, int k, int kprev, const double *x, double *y)
{
    double a0 = g->a0, s = 1.0 / (4.0 * a0);
    const double c[4] = { -a0 * s, 5.0 * (a0 - 2.0) * s, 5.0 * s, 5.0 * s };
    const double *v[4] = { AP(g, 0, 0, 0), x, AP(g, k, 1, 1), AP(g, kprev, 1, 1) };
    lin(y, g->dim, 4, c, v);
}

/* Right-hand side of eq. (17) / (34): (a0 b00 + 5(2-a0) x + 4 a0 y)/5. */
static void rhs17(const g1ctx *g, const double *x, const double *y, double *d)
{
    double a0 = g->a0;
    const double c[3] = { a0 / 5.0, 2.0 - a0, 0.8 * a0 };
    const double *v[3] = { AP(g, 0, 0, 0), x, y };
    lin(d, g->dim, 3, c, v);
}

/* Pair (p in sector k at (i,j), q in sector kprev at (j,i)) with p + q = r: eq. (31). */
static void pair31(g1ctx *g, int k, int kprev, int i, int j, const double *r)
{
    int dim = g->dim;
    double *p = LP(g->P[k], dim, i, j), *q = LP(g->P[kprev], dim, j, i);
    const double *pa = AP(g, k, i, j), *qa = AP(g, kprev, j, i);
    double th = g->theta;
    for (int t = 0; t < dim; t++) {
        p[t] = (r[t] + th * pa[t] - qa[t]) / (th + 1.0);
        q[t] = r[t] - p[t];
    }
}

/* Orders 3 and 4 along edge e_k (§5.3): M_{3,0} from eq. (11), then eq. (30) and (32) with (31). */
static void high_orders(g1ctx *g, int k, int kprev)
{
    int dim = g->dim;
    double a0 = g->a0, *rb = g->r;
    const double *b00 = AP(g, 0, 0, 0), *x = SEQ(g->x, g, k), *y = SEQ(g->y, g, k);
    double *w = SEQ(g->w, g, k);
    {   /* M_{3,0} = (M00 - 5 M10 + 10 M20 + 5 M40 - M50)/10 */
        const double c[5] = { 0.1, -0.5, 1.0, 0.5, -0.1 };
        const double *v[5] = { b00, x, y, AP(g, k, 4, 0), AP(g, k, 5, 0) };
        lin(w, dim, 5, c, v);
        set_edge(g, k, kprev, 3, w);
    }
    {   /* eq. (30): r = (-a0 M00 + 5 a0 M10 - 10 (a0-2) M20 + 6 a0 M30)/10 */
        const double c[4] = { -0.1 * a0, 0.5 * a0, -(a0 - 2.0), 0.6 * a0 };
        const double *v[4] = { b00, x, y, w };
        lin(rb, dim, 4, c, v);
        pair31(g, k, kprev, 2, 1, rb);
    }
    {   /* eq. (32): r~ = (a0 M00 - 5 a0 M10 + 10 a0 M20 - 10 (a0-2) M30 + 4 a0 M40)/10 */
        const double c[5] = { 0.1 * a0, -0.5 * a0, a0, -(a0 - 2.0), 0.4 * a0 };
        const double *v[5] = { b00, x, y, w, AP(g, k, 4, 0) };
        lin(rb, dim, 5, c, v);
        pair31(g, k, kprev, 3, 1, rb);
    }
}

q2n_status q2n_acc_g1_interior(int N, int dim, q2n_acc_strategy st, double **P, q2n_error *err)
{
    if (N < 3 || N == 4) return q2n_error_set(err, Q2N_ERR_ARG, "acc-g1: interior valence %d is not an EV", N);
    g1ctx g;
    q2n_status s = g1_alloc(&g, N, dim, st, P, 2.0 * cos(2.0 * Q2N_PI / N), err);
    if (s != Q2N_OK) return s;
    const double *b00 = AP(&g, 0, 0, 0);
    int even = (N % 2 == 0);

    /* order 1, eq. (13), (15)-(16): x_k = b00 + (2/N) Σ_j cos(2π(k-j)/N) xACC5_j */
    for (int k = 0; k < N; k++) {
        double *x = SEQ(g.x, &g, k);
        memcpy(x, b00, (size_t)dim * sizeof *x);
        for (int j = 0; j < N; j++) {
            double c = 2.0 / N * cos(2.0 * Q2N_PI * (k - j) / N);
            const double *xa = AP(&g, j, 1, 0);
            for (int t = 0; t < dim; t++) x[t] += c * xa[t];
        }
    }
    for (int k = 0; k < N; k++) set_edge(&g, k, (k + N - 1) % N, 1, SEQ(g.x, &g, k));

    /* order 2 */
    for (int k = 0; k < N; k++) {
        int kp = (k + N - 1) % N;
        if (g.cs) m20_from_11(&g, k, SEQ(g.x, &g, k), SEQ(g.y, &g, k)); /* eq. (18); (M_{2,0}^even) */
        else m20_from_29(&g, k, kp, SEQ(g.x, &g, k), SEQ(g.y, &g, k));  /* eq. (29) */
    }
    if (g.cs && even) { /* eq. (21)-(25): remove the alternating part so the V.E.R. holds */
        for (int t = 0; t < dim; t++) {
            double a = 0;
            for (int k = 0; k < N; k++) a += ((k & 1) ? -1.0 : 1.0) * SEQ(g.y, &g, k)[t];
            for (int k = 0; k < N; k++) SEQ(g.y, &g, k)[t] -= ((k & 1) ? -1.0 : 1.0) * a / N;
        }
    }
    for (int k = 0; k < N; k++) set_edge(&g, k, (k + N - 1) % N, 2, SEQ(g.y, &g, k));
    if (g.cs) {
        /* eq. (17): z_k + z_{k-1} = d_k.  z = G * d with G_j = (1/N) Σ_m cos(φ_m (j+1/2)) /
         * (2 cos(φ_m/2)), φ_m = 2πm/N, over m != N/2; plus the ACC5 alternating part (eq. 26-27). */
        double *d = g.w; /* scratch */
        for (int k = 0; k < N; k++) rhs17(&g, SEQ(g.x, &g, k), SEQ(g.y, &g, k), SEQ(d, &g, k));
        double *G = malloc((size_t)N * sizeof *G);
        if (!G) { free(g.A); return q2n_error_set(err, Q2N_ERR_NOMEM, "acc-g1: out of memory"); }
        for (int j = 0; j < N; j++) {
            G[j] = 0;
            for (int m = 0; m < N; m++) {
                if (even && 2 * m == N) continue;
                double ph = 2.0 * Q2N_PI * m / N;
                G[j] += cos(ph * (j + 0.5)) / (2.0 * cos(ph / 2.0));
            }
            G[j] /= N;
        }
        for (int k = 0; k < N; k++) {
            double *z = SEQ(g.z, &g, k);
            memset(z, 0, (size_t)dim * sizeof *z);
            for (int j = 0; j < N; j++) {
                const double *dk = SEQ(d, &g, ((k - j) % N + N) % N);
                for (int t = 0; t < dim; t++) z[t] += G[j] * dk[t];
            }
        }
        free(G);
        if (even)
            for (int t = 0; t < dim; t++) {
                double a = 0;
                for (int k = 0; k < N; k++) a += ((k & 1) ? -1.0 : 1.0) * AP(&g, k, 1, 1)[t];
                for (int k = 0; k < N; k++) SEQ(g.z, &g, k)[t] += ((k & 1) ? -1.0 : 1.0) * a / N;
            }
        for (int k = 0; k < N; k++) memcpy(LP(P[k], dim, 1, 1), SEQ(g.z, &g, k), (size_t)dim * sizeof(double));
    }
    /* orders 3 and 4 */
    for (int k = 0; k < N; k++) high_orders(&g, k, (k + N - 1) % N);
    free(g.A);
    return Q2N_OK;
}

/* Boundary EV with K faces (seed 001 §5.4): edges e_1..e_{K-1} are interior (shared); the
 * boundary edges e_0, e_K keep their ACC5 points.  The angle of the gluing data is π/K (the K
 * sectors span a half plane), i.e. a0 = 2cos(π/K): this is 0 for the regular boundary vertex
 * (K = 2), matching the interior a0 = 2cos(2π/N) = 0 at N = 4. */
q2n_status q2n_acc_g1_boundary(int K, int dim, q2n_acc_strategy st, double **P, q2n_error *err)
{
    if (K < 3) return q2n_error_set(err, Q2N_ERR_ARG, "acc-g1: boundary vertex with %d faces is not an EV", K);
    g1ctx g;
    double th = Q2N_PI / K;
    q2n_status s = g1_alloc(&g, K, dim, st, P, 2.0 * cos(th), err);
    if (s != Q2N_OK) return s;
    const double *b00 = AP(&g, 0, 0, 0), *x0 = AP(&g, 0, 1, 0);

    /* order 1, eq. (33): x_i - b00 = A cos(iθ) + B sin(iθ) solves the K-1 relations (5) with the
     * ACC5 boundary tangents (x_0 - b00 = -(x_K - b00) = A); B: orthogonal projection of ACC5. */
    double ss = 0;
    for (int i = 1; i < K; i++) ss += sin(i * th) * sin(i * th);
    for (int t = 0; t < dim; t++) {
        double A = x0[t] - b00[t], B = 0;
        for (int i = 1; i < K; i++) B += sin(i * th) * (AP(&g, i, 1, 0)[t] - b00[t] - A * cos(i * th));
        B /= ss;
        for (int i = 1; i < K; i++) SEQ(g.x, &g, i)[t] = b00[t] + A * cos(i * th) + B * sin(i * th);
    }
    for (int i = 1; i < K; i++) set_edge(&g, i, i - 1, 1, SEQ(g.x, &g, i));

    /* order 2 on the interior edges */
    for (int i = 1; i < K; i++) {
        if (g.cs) m20_from_11(&g, i, SEQ(g.x, &g, i), SEQ(g.y, &g, i));
        else m20_from_29(&g, i, i - 1, SEQ(g.x, &g, i), SEQ(g.y, &g, i));
        set_edge(&g, i, i - 1, 2, SEQ(g.y, &g, i));
    }
    if (g.cs) {
        /* eq. (34): z_i + z_{i-1} = g_i (i = 1..K-1); z = zACC5 + R^T ρ, R R^T ρ = g - R zACC5,
         * R R^T = tridiag(1, 2, 1) of size K-1 (LAPACK's L D L^T, core/dense.h). */
        int m = K - 1;
        double *rho = malloc((size_t)m * (2 * dim + 2) * sizeof *rho);
        if (!rho) { free(g.A); return q2n_error_set(err, Q2N_ERR_NOMEM, "acc-g1: out of memory"); }
        double *B = rho + (size_t)m * dim, *diag = B + (size_t)m * dim, *off = diag + m; /* B: column-major m x dim */
        double *gi = g.w; /* scratch */
        for (int i = 1; i < K; i++) {
            rhs17(&g, SEQ(g.x, &g, i), SEQ(g.y, &g, i), SEQ(gi, &g, i));
            for (int t = 0; t < dim; t++)
                B[(size_t)t * m + i - 1] = SEQ(gi, &g, i)[t] - AP(&g, i, 1, 1)[t] - AP(&g, i - 1, 1, 1)[t];
        }
        for (int i = 0; i < m; i++) diag[i] = 2.0, off[i] = 1.0;
        q2n_dense_tridiag_spd(m, dim, diag, off, B, m); /* positive definite: eigenvalues 2 + 2 cos(k pi / K) > 0 */
        for (int i = 0; i < m; i++)
            for (int t = 0; t < dim; t++) rho[(size_t)i * dim + t] = B[(size_t)t * m + i];
        /* z_k = zACC5_k + ρ_k (k = 1..m, equation index k) + ρ_{k+1} (equation k+1 <= m) */
        for (int k = 0; k < K; k++) {
            double *z = LP(P[k], dim, 1, 1);
            for (int t = 0; t < dim; t++) {
                double v = AP(&g, k, 1, 1)[t];
                if (k >= 1) v += rho[(size_t)(k - 1) * dim + t];
                if (k + 1 <= m) v += rho[(size_t)k * dim + t];
                z[t] = v;
            }
        }
        free(rho);
    }
    for (int i = 1; i < K; i++) high_orders(&g, i, i - 1);
    free(g.A);
    return Q2N_OK;
}
