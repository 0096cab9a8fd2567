/* spline_class.c — the classes DgCkPmSw implemented by quad2nurbs (see spline.h).
 *
 * Each class = a basis B_r on [0,1] (Hermite data of order k at both ends) + derivative
 * functionals at the knots taken from the Lagrange interpolant through `nlagr` nearby knots
 * (formulas.md §3.3: exact on Π_m, hence polynomial reproduction of degree m; the
 * Hermite basis gives C^k; support w = 2h with h-1 = (nlagr-1)/2 + ... ).
 *   D3C1P2S4  Catmull–Rom: cubic Hermite, parabola slopes (Appendix A.1 of seed 003)
 *   D5C2P2S4  quintic Hermite, parabola slopes and second derivatives (Appendix A.2)
 *   D2C1P2S4  C1 quadratic with a breakpoint at the interval midpoint (formulas.md §3.3)
 *   D3C2P2S4  C2 cubic with breakpoints at 1/3, 2/3 (formulas.md §3.3)
 *   D5C2P4S6  quintic Hermite, derivatives of the quartic through 5 knots (formulas.md §3.2)
 * Tests (tests/test_spline.c) check the closed forms of Appendix A, interpolation, polynomial
 * reproduction and C^k continuity on random non-uniform knots for every class. */
#include "spline/spline.h"

#include <ctype.h>
#include <string.h>

#include "core/hermite.h"

/* A basis function: polynomial c[0..5] in t plus up to two truncated powers
 * tr[q] * (t - brk[q])_+^pw. */
typedef struct basis_fn {
    const double *c;
    double tr[2];
} basis_fn;

typedef struct basis_table {
    int nb, pw;
    double brk[2];
    basis_fn f[Q2N_SPLINE_MAXB];
} basis_table;

/* falling factorials p!/(p-d)! for p <= 7, d <= 3 */
static const double FALL[8][4] = {{1, 0, 0, 0},   {1, 1, 0, 0},    {1, 2, 2, 0},     {1, 3, 6, 6},
                                  {1, 4, 12, 24}, {1, 5, 20, 60},  {1, 6, 30, 120},  {1, 7, 42, 210}};

static void eval_table(const basis_table *T, double t, int nder, double *out)
{
    double pw[8], y[2][4];
    pw[0] = 1;
    for (int p = 1; p < 8; p++) pw[p] = pw[p - 1] * t;
    for (int q = 0; q < 2; q++) { /* d-th derivative of (t - brk)_+^pw */
        double yy = t - T->brk[q];
        for (int d = 0; d < 4; d++) {
            y[q][d] = 0;
            if (T->pw == 0 || yy <= 0 || d > T->pw) continue;
            double pp = FALL[T->pw][d];
            for (int e = 0; e < T->pw - d; e++) pp *= yy;
            y[q][d] = pp;
        }
    }
    for (int r = 0; r < T->nb; r++) {
        const basis_fn *f = &T->f[r];
        for (int d = 0; d <= nder; d++) {
            double acc = 0;
            for (int p = d; p < 6; p++) acc += f->c[p] * FALL[p][d] * pw[p - d];
            acc += f->tr[0] * y[0][d] + f->tr[1] * y[1][d];
            out[d * T->nb + r] = acc;
        }
    }
}

/* Order of basis functions: end 0 orders 0..k, then end 1 orders 0..k.  The Hermite classes use
 * the Hermite basis of core/hermite.h (q2n_hermite_coef[K - 1][order][end]). */
#define HC(K, a, e) {q2n_hermite_coef[(K) - 1][a][e], {0, 0}}
static const basis_table cubic_hermite = {4, 0, {2, 2}, {HC(1, 0, 0), HC(1, 1, 0), HC(1, 0, 1), HC(1, 1, 1)}};
static const basis_table quintic_hermite = {6, 0, {2, 2},
                                            {HC(2, 0, 0), HC(2, 1, 0), HC(2, 2, 0), HC(2, 0, 1), HC(2, 1, 1), HC(2, 2, 1)}};
#undef HC
/* formulas.md §3.3, D2C1P2S4 with H = 1 */
static const basis_table quad_c1 = {4, 2, {0.5, 2}, {
    {(const double[6]){1, 0, -2, 0, 0, 0}, {4, 0}},
    {(const double[6]){0, 1, -1.5, 0, 0, 0}, {2, 0}},
    {(const double[6]){0, 0, 2, 0, 0, 0}, {-4, 0}},
    {(const double[6]){0, 0, -0.5, 0, 0, 0}, {2, 0}}}};
/* formulas.md §3.3, D3C2P2S4 with H = 1 */
static const basis_table cubic_c2 = {6, 3, {1.0 / 3.0, 2.0 / 3.0}, {
    {(const double[6]){1, 0, 0, -4.5, 0, 0}, {13.5, -13.5}},
    {(const double[6]){0, 1, 0, -3, 0, 0}, {7.5, -6}},
    {(const double[6]){0, 0, 0.5, -11.0 / 12.0, 0, 0}, {1.5, -0.75}},
    {(const double[6]){0, 0, 0, 4.5, 0, 0}, {-13.5, 13.5}},
    {(const double[6]){0, 0, 0, -1.5, 0, 0}, {6, -7.5}},
    {(const double[6]){0, 0, 0, 1.0 / 6.0, 0, 0}, {-0.75, 1.5}}}};

static void b_cubic(double t, int n, double *o) { eval_table(&cubic_hermite, t, n, o); }
static void b_quintic(double t, int n, double *o) { eval_table(&quintic_hermite, t, n, o); }
static void b_quad_c1(double t, int n, double *o) { eval_table(&quad_c1, t, n, o); }
static void b_cubic_c2(double t, int n, double *o) { eval_table(&cubic_c2, t, n, o); }

static const q2n_spline_class cls_d3c1p2s4 = {"D3C1P2S4", 3, 1, 2, 4, 4, 3, b_cubic};
static const q2n_spline_class cls_d5c2p2s4 = {"D5C2P2S4", 5, 2, 2, 4, 6, 3, b_quintic};
static const q2n_spline_class cls_d2c1p2s4 = {"D2C1P2S4", 2, 1, 2, 4, 4, 3, b_quad_c1};
static const q2n_spline_class cls_d3c2p2s4 = {"D3C2P2S4", 3, 2, 2, 4, 6, 3, b_cubic_c2};
static const q2n_spline_class cls_d5c2p4s6 = {"D5C2P4S6", 5, 2, 4, 6, 6, 5, b_quintic};

static const q2n_spline_class *const registry[] = {&cls_d5c2p2s4, &cls_d3c1p2s4, &cls_d2c1p2s4,
                                                   &cls_d3c2p2s4, &cls_d5c2p4s6, NULL};

const q2n_spline_class *const *q2n_spline_classes(void) { return registry; }

const q2n_spline_class *q2n_spline_class_find(const char *name)
{
    for (int i = 0; registry[i]; i++) {
        const char *a = registry[i]->name, *b = name;
        while (*a && *b && toupper((unsigned char)*a) == toupper((unsigned char)*b)) a++, b++;
        if (!*a && !*b) return registry[i];
    }
    return NULL;
}

void q2n_spline_fundamental(const q2n_spline_class *c, const double *d, double x, int nder,
                            double *psi)
{
    int w = c->w, nb = c->nb;
    q2n_jet dj[Q2N_SPLINE_MAXW] = {{{0}}}, C[Q2N_SPLINE_MAXB * Q2N_SPLINE_MAXW]; /* dj zeroed: GCC 12 cannot see that w >= 2 */
    double B[4 * Q2N_SPLINE_MAXB];
    for (int i = 0; i < w - 1; i++) dj[i] = q2n_jet_const(d[i]);
    q2n_spline_coeffs(c, dj, C);
    double D = d[w / 2 - 1];
    c->basis(x / D, nder, B);
    double scale = 1;
    for (int q = 0; q <= nder; q++) {
        for (int i = 0; i < w; i++) {
            double acc = 0;
            for (int r = 0; r < nb; r++) acc += B[q * nb + r] * C[r * w + i].d[0];
            psi[q * w + i] = acc * scale;
        }
        scale /= D;
    }
}

int q2n_spline_curve_eval(const q2n_spline_class *c, int n, int dim, const double *p,
                          const double *iv, int closed, int s, double x, int nder, double *out)
{
    int w = c->w, h = w / 2;
    double d[Q2N_SPLINE_MAXW], psi[4 * Q2N_SPLINE_MAXW];
    int idx[Q2N_SPLINE_MAXW];
    for (int i = 0; i < w; i++) {
        int j = s - h + 1 + i;
        if (closed) j = ((j % n) + n) % n;
        else if (j < 0 || j >= n) return -1;
        idx[i] = j;
        if (i < w - 1) {
            int e = s - h + 1 + i;
            d[i] = iv[closed ? ((e % n) + n) % n : e];
        }
    }
    q2n_spline_fundamental(c, d, x, nder, psi);
    for (int q = 0; q <= nder; q++)
        for (int cc = 0; cc < dim; cc++) {
            double acc = 0;
            for (int i = 0; i < w; i++) acc += psi[q * w + i] * p[idx[i] * dim + cc];
            out[q * dim + cc] = acc;
        }
    return 0;
}

/* Smoothstep polynomials of degree 2k+1 with vanishing derivatives of order 1..k at 0 and 1: t for
 * k = 0, else the Hermite function H_{0,1} of order k (core/hermite.h); power coefficients t^0..t^7. */
static const double *blend_coef(int k)
{
    static const double linear[8] = {0, 1, 0, 0, 0, 0, 0, 0};
    return k <= 0 ? linear : q2n_hermite_coef[(k > 3 ? 3 : k) - 1][0][1];
}

void q2n_spline_blend_derivs(int k, double a, double b, double t, double out[4])
{
    const double *c = blend_coef(k);
    double pw[8];
    pw[0] = 1;
    for (int p = 1; p < 8; p++) pw[p] = pw[p - 1] * t;
    for (int d = 0; d < 4; d++) {
        double acc = 0;
        for (int p = d; p < 8; p++) acc += c[p] * FALL[p][d] * pw[p - d];
        out[d] = (d == 0 ? a : 0) + (b - a) * acc;
    }
}

double q2n_spline_blend_weight(int k, double t)
{
    const double *c = blend_coef(k);
    double pw = 1, acc = 0;
    for (int p = 0; p < 8; p++) {
        acc += c[p] * FALL[p][0] * pw;
        pw *= t;
    }
    return acc;
}

q2n_jet q2n_spline_blend(int k, double a, double b, double t)
{
    double o[4];
    q2n_spline_blend_derivs(k, a, b, t, o);
    q2n_jet r = {{o[0], o[1], o[2]}};
    return r;
}
