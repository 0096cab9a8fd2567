/* test_hermite.c — the Hermite basis of core/hermite.h against its defining end conditions and an
 * independent evaluation of the printed coefficients, and the per-thread memos that serve repeated
 * requests (q2n_hermite_eval, q2n_augmented_coeffs, the Coons evaluator's lines): whatever the
 * order of requests — the same parameter with more derivatives, other orders, ±0, other intervals
 * at the same parameter, two threads at once, a patch whose data changed at the same address —
 * every answer is the one a fresh computation gives. */
#include "check.h"
#include "core/hermite.h"
#include "patch/augmented.h"
#include "patch/coons_patch.h"

#include <pthread.h>

static double rnd(unsigned *s) { *s = *s * 1103515245u + 12345u; return ((*s >> 8) & 0xffff) / 65536.0; }

/* q-th derivative at t of the polynomial with power coefficients c[0..9] (Horner on the
 * differentiated coefficients); *scale gets the sum of the terms' magnitudes (the size of the
 * rounding any evaluation order makes). */
static double poly_deriv_s(const double *c, int q, double t, double *scale)
{
    double r = 0, sc = 0;
    for (int i = 9; i >= q; i--) {
        double f = c[i];
        for (int j = 0; j < q; j++) f *= (double)(i - j);
        r = r * t + f;
        sc = sc * fabs(t) + fabs(f);
    }
    if (scale) *scale = sc;
    return r;
}

/* The end conditions H_{a,e}^{(c)}(e') = δ_ac δ_ee' (a, c <= K) that define the basis. */
static void test_end_conditions(void)
{
    double worst = 0;
    for (int K = 1; K <= Q2N_HERMITE_MAXK; K++)
        for (int ep = 0; ep < 2; ep++) {
            double H[Q2N_HERMITE_MAXK + 1][2][Q2N_HERMITE_MAXD + 1];
            q2n_hermite_eval(K, (double)ep, K, H);
            for (int a = 0; a <= K; a++)
                for (int e = 0; e < 2; e++)
                    for (int c = 0; c <= K; c++) {
                        double want = (a == c && e == ep) ? 1.0 : 0.0;
                        worst = fmax(worst, fabs(H[a][e][c] - want));
                    }
        }
    CHECK(worst < 1e-12, "Hermite end conditions: worst error %.3g", worst);
}

/* A random sequence of requests, each checked against the printed coefficients. */
static void check_sequence(unsigned seed, int n, double *worst)
{
    static const double ts[] = {0.0, -0.0, 1.0, 0.25, 0.5, 0.3125, 0.7, 0.999};
    for (int r = 0; r < n; r++) {
        int K = 1 + (int)(rnd(&seed) * Q2N_HERMITE_MAXK);
        double t = rnd(&seed) < 0.7 ? ts[(int)(rnd(&seed) * 8)] : rnd(&seed);
        int nder = (int)(rnd(&seed) * (Q2N_HERMITE_MAXD + 1));
        double H[Q2N_HERMITE_MAXK + 1][2][Q2N_HERMITE_MAXD + 1];
        q2n_hermite_eval(K, t, nder, H);
        for (int a = 0; a <= K; a++)
            for (int e = 0; e < 2; e++)
                for (int q = 0; q <= nder; q++) {
                    double sc, want = poly_deriv_s(q2n_hermite_coef[K - 1][a][e], q, t, &sc);
                    double d = fabs(H[a][e][q] - want) / (1.0 + sc);
                    if (!(d <= *worst)) *worst = d;
                }
    }
}

static void *seq_thread(void *arg)
{
    double *w = arg;
    check_sequence(77, 20000, w);
    return NULL;
}

static void test_memo(void)
{
    double worst = 0;
    check_sequence(5, 20000, &worst);
    CHECK(worst < 1e-14, "Hermite memo, one thread: worst error %.3g of the terms' size", worst);
    /* the same parameter asked for more derivatives after fewer */
    double H1[Q2N_HERMITE_MAXK + 1][2][Q2N_HERMITE_MAXD + 1], H2[Q2N_HERMITE_MAXK + 1][2][Q2N_HERMITE_MAXD + 1];
    q2n_hermite_eval(4, 0.375, 1, H1);
    q2n_hermite_eval(4, 0.375, 6, H2);
    double w2 = 0;
    for (int a = 0; a <= 4; a++)
        for (int e = 0; e < 2; e++)
            for (int q = 0; q <= 6; q++)
            {
                double sc, want = poly_deriv_s(q2n_hermite_coef[3][a][e], q, 0.375, &sc);
                w2 = fmax(w2, fabs(H2[a][e][q] - want) / (1.0 + sc));
            }
    CHECK(w2 < 1e-14, "Hermite memo: more derivatives of a remembered parameter: error %.3g", w2);
    double wt[2] = {0, 0};
    pthread_t th[2];
    for (int i = 0; i < 2; i++) CHECK(pthread_create(&th[i], NULL, seq_thread, &wt[i]) == 0, "thread %d", i);
    for (int i = 0; i < 2; i++) pthread_join(th[i], NULL);
    CHECK(wt[0] < 1e-14 && wt[1] < 1e-14, "Hermite memo, two threads: %.3g %.3g", wt[0], wt[1]);
}

/* q2n_augmented_coeffs against the blend + coefficients it remembers, bit for bit: intervals that
 * differ in one entry at the same parameter, the same intervals at ±0, each class. */
static void test_coeff_memo(void)
{
    unsigned seed = 11;
    int bad = 0, n = 0;
    for (const q2n_spline_class *const *c = q2n_spline_classes(); *c; c++) {
        const q2n_spline_class *cls = *c;
        int w = cls->w;
        double d[3][2][Q2N_SPLINE_MAXW];
        for (int s = 0; s < 3; s++)
            for (int i = 0; i < w - 1; i++) d[s][0][i] = 0.5 + rnd(&seed), d[s][1][i] = 0.5 + rnd(&seed);
        d[2][1][w - 2] = d[1][1][w - 2] * (1 + 1e-15); /* set 2: set 1 but one interval one ulp-ish off */
        for (int i = 0; i < w - 1; i++) d[2][0][i] = d[1][0][i];
        for (int i = 0; i < w - 2; i++) d[2][1][i] = d[1][1][i];
        static const double xs[] = {0.0, -0.0, 0.5, 1.0, 0.125};
        for (int r = 0; r < 300; r++) {
            int s = (int)(rnd(&seed) * 3);
            double x = xs[(int)(rnd(&seed) * 5)];
            q2n_jet C[Q2N_SPLINE_MAXB * Q2N_SPLINE_MAXW], R[Q2N_SPLINE_MAXB * Q2N_SPLINE_MAXW], dj[Q2N_SPLINE_MAXW];
            q2n_augmented_coeffs(cls, w, d[s][0], d[s][1], x, C);
            for (int i = 0; i < w - 1; i++) dj[i] = q2n_spline_blend(cls->k, d[s][0][i], d[s][1][i], x);
            q2n_spline_coeffs(cls, dj, R);
            bad += memcmp(C, R, sizeof(q2n_jet) * (size_t)(cls->nb * w)) != 0;
            n++;
        }
    }
    CHECK(bad == 0, "coefficient memo: %d of %d requests differ from a fresh computation", bad, n);
}

/* A biquintic-reproducing Coons patch (K = 2) fed with the boundary data of a polynomial of bidegree
 * <= 5: f_x = c0 u^3 v^2 + c1 u v + c2, f_y = c1 u^2 + v^3, f_z = c2 u v^4. */
typedef struct poly_ctx { double c[3]; } poly_ctx;

/* d^i/du^i u^n */
static double mono(int n, int i, double u)
{
    if (i > n) return 0;
    double f = 1;
    for (int j = 0; j < i; j++) f *= (double)(n - j);
    return f * pow(u, n - i);
}

static void poly_partial(const poly_ctx *P, double u, double v, int du, int dv, double o[3])
{
    o[0] = P->c[0] * mono(3, du, u) * mono(2, dv, v) + P->c[1] * mono(1, du, u) * mono(1, dv, v) + P->c[2] * mono(0, du, u) * mono(0, dv, v);
    o[1] = P->c[1] * mono(2, du, u) * mono(0, dv, v) + mono(0, du, u) * mono(3, dv, v);
    o[2] = P->c[2] * mono(1, du, u) * mono(4, dv, v);
}

static void poly_side(const void *ctx, const void *lanes, int W, int sd, double s, int na, double F[3][CP_NA][CP_MAXW])
{
    (void)lanes, (void)W;
    const poly_ctx *P = ctx;
    for (int b = 0; b <= 2; b++)
        for (int a = 0; a < na; a++) {
            double o[3];
            if (sd == 0 || sd == 2) poly_partial(P, s, sd == 0 ? 0.0 : 1.0, a, b, o);
            else poly_partial(P, sd == 3 ? 0.0 : 1.0, s, b, a, o);
            for (int x = 0; x < 3; x++) F[b][a][x] = o[x];
        }
}

/* Points along v = 0 reuse the line at v = 0; the patch's data then changes at the same address
 * and is re-initialised: the evaluator must not serve the old line. */
static void test_line_memo(void)
{
    static cp_eval E;
    poly_ctx P = {{1.0, 2.0, 3.0}};
    memset(&E, 0, sizeof E);
    E.P.K = 2;
    E.P.side = poly_side;
    E.P.ctx = &P;
    double worst[2] = {0, 0};
    for (int pass = 0; pass < 2; pass++) {
        if (pass) P.c[0] = -4.0, P.c[1] = 0.5, P.c[2] = 7.0;
        q2n_cp_eval_init(&E);
        for (int q = 0; q <= 8; q++) {
            double u = q / 8.0, v = q % 3 == 0 ? 0.0 : 0.375, out[18], f[3], fu[3], fv[3];
            q2n_cp_eval_point(&E, u, v, 1, out);
            poly_partial(&P, u, v, 0, 0, f);
            poly_partial(&P, u, v, 1, 0, fu);
            poly_partial(&P, u, v, 0, 1, fv);
            for (int x = 0; x < 3; x++)
                worst[pass] = fmax(worst[pass], fmax(fabs(out[x] - f[x]), fmax(fabs(out[3 + x] - fu[x]), fabs(out[6 + x] - fv[x]))));
        }
    }
    CHECK(worst[0] < 1e-12 && worst[1] < 1e-12, "Coons patch reproduces a biquintic polynomial, before and after its data "
          "changed at the same address: %.3g, %.3g", worst[0], worst[1]);
}

int main(void)
{
    test_end_conditions();
    test_memo();
    test_coeff_memo();
    test_line_memo();
    CHECK_DONE("test_hermite");
}
