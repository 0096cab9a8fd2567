/* test_hermite.c — the Hermite basis of core/hermite.h against its defining end conditions and an
 * independent evaluation of the printed coefficients, and the per-thread memos that serve repeated
 * requests (q2n_hermite_eval, q2n_augmented_coeffs): whatever the order of requests — the same
 * parameter with more derivatives, other orders, ±0, other intervals at the same parameter, two
 * threads at once — every answer is the one a fresh computation gives. */
#include "check.h"
#include "core/hermite.h"
#include "patch/augmented.h"

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

int main(void)
{
    test_end_conditions();
    test_memo();
    test_coeff_memo();
    CHECK_DONE("test_hermite");
}
