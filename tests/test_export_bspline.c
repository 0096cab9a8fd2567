/* test_export_bspline.c — q2n_bspline_basis / _eval / _check against independent references:
 * Bernstein closed forms (one-span surfaces), finite differences of the evaluator's derivatives on
 * multi-span rational surfaces, the exact rational quarter circle, and the check's error cases. */
#include "check.h"
#include "fit/bspline.h"

#include <stdlib.h>

static double binom(int n, int k)
{
    double r = 1.0;
    for (int i = 1; i <= k; i++) r = r * (n - k + i) / i;
    return r;
}
static double bern(int n, int i, double t) { return binom(n, i) * pow(t, i) * pow(1 - t, n - i); }

/* deterministic pseudo-random numbers in [-1,1] (no global state: caller owns the seed) */
static double rnd(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return ((*s >> 8) & 0xffffff) / (double)0xffffff * 2.0 - 1.0;
}

static void make_surface(q2n_bspline_surface *s, int du, int dv, int nu, int nv, int rational, unsigned seed)
{
    s->deg_u = du; s->deg_v = dv; s->ncp_u = nu; s->ncp_v = nv;
    s->knots_u = malloc(sizeof(double) * (size_t)(nu + du + 1));
    s->knots_v = malloc(sizeof(double) * (size_t)(nv + dv + 1));
    s->cp = malloc(sizeof(double) * 3 * (size_t)(nu * nv));
    s->weights = rational ? malloc(sizeof(double) * (size_t)(nu * nv)) : NULL;
    /* clamped, non-uniform interior knots (one double knot when there is room) */
    for (int d = 0; d < 2; d++) {
        int n = d ? nv : nu, p = d ? dv : du;
        double *k = d ? s->knots_v : s->knots_u;
        int nin = n - p - 1;
        for (int i = 0; i <= p; i++) { k[i] = 0.0; k[n + i] = 1.0; }
        for (int i = 0; i < nin; i++) k[p + 1 + i] = (i + 1.0) / (nin + 1.0) + 0.03 * (i % 2);
        if (nin >= 3 && p >= 2) k[p + 2] = k[p + 1];
    }
    for (int i = 0; i < 3 * nu * nv; i++) s->cp[i] = rnd(&seed);
    if (rational)
        for (int i = 0; i < nu * nv; i++) s->weights[i] = 1.0 + 0.5 * rnd(&seed);
}

/* q2n_bspline_basis on one span (clamped [0,1], degree p): the Bernstein polynomials and their
 * first and second derivatives in closed form, B' = p (B_{p-1,i-1} - B_{p-1,i}), B'' likewise
 * (Farin, CAGD §5.3); orders above p are zero. */
static void test_basis(void)
{
    double worst = 0;
    for (int p = 1; p <= 7; p++) {
        double kv[16], ders[3 * 16];
        for (int i = 0; i <= p; i++) kv[i] = 0, kv[p + 1 + i] = 1;
        for (int s = 0; s <= 8; s++) {
            double t = s / 8.0;
            int span = q2n_bspline_span(p + 1, p, kv, t);
            CHECK(span == p, "degree %d, t %g: span %d (the only one is %d)", p, t, span, p);
            q2n_bspline_basis(span, p, kv, t, 2, ders);
            for (int i = 0; i <= p; i++) {
                double b1 = p * ((i ? bern(p - 1, i - 1, t) : 0) - (i < p ? bern(p - 1, i, t) : 0));
                double b2 = 0;
                if (p >= 2)
                    b2 = p * (p - 1) * ((i >= 2 ? bern(p - 2, i - 2, t) : 0) - 2 * (i >= 1 && i - 1 <= p - 2 ? bern(p - 2, i - 1, t) : 0) +
                                        (i <= p - 2 ? bern(p - 2, i, t) : 0));
                worst = fmax(worst, fabs(ders[i] - bern(p, i, t)));
                worst = fmax(worst, fabs(ders[(p + 1) + i] - b1) / p);
                worst = fmax(worst, fabs(ders[2 * (p + 1) + i] - b2) / (p * p));
            }
        }
    }
    CHECK(worst < 1e-13, "basis and derivatives up to 2 vs Bernstein closed forms: %.3g", worst);
}

int main(void)
{
    test_basis();
    q2n_error err;
    /* 1. One-span bi-quintic (Bézier) surface with weights: closed form sum B_i B_j w P / sum B_i B_j w. */
    {
        q2n_bspline_surface s;
        make_surface(&s, 5, 3, 6, 4, 1, 7u);
        CHECK(q2n_bspline_check(&s, &err) == Q2N_OK, "check: %s", err.message);
        double maxe = 0.0;
        for (int t = 0; t <= 10; t++) {
            double u = t / 10.0, v = fmod(0.37 * t, 1.0), A[3] = {0, 0, 0}, W = 0, p[3];
            for (int j = 0; j < 4; j++)
                for (int i = 0; i < 6; i++) {
                    double b = bern(5, i, u) * bern(3, j, v) * s.weights[j * 6 + i];
                    for (int c = 0; c < 3; c++) A[c] += b * s.cp[3 * (j * 6 + i) + c];
                    W += b;
                }
            q2n_bspline_eval(&s, u, v, p, NULL, NULL);
            for (int c = 0; c < 3; c++) maxe = fmax(maxe, fabs(p[c] - A[c] / W));
        }
        CHECK(maxe < 1e-14, "Bezier closed form: max error %.3g", maxe);
        q2n_bspline_free(&s);
    }
    /* 2. Multi-span surfaces (polynomial and rational): derivatives vs central differences;
     *    partition of unity shows as affine invariance (all cps translated => surface translated). */
    for (int rational = 0; rational < 2; rational++) {
        q2n_bspline_surface s;
        make_surface(&s, 5, 4, 11, 9, rational, 11u + (unsigned)rational);
        CHECK(q2n_bspline_check(&s, &err) == Q2N_OK, "check: %s", err.message);
        double maxe = 0.0, maxt = 0.0, h = 1e-6;
        unsigned seed = 3u;
        for (int t = 0; t < 200; t++) {
            double u = 0.5 + 0.4999 * rnd(&seed), v = 0.5 + 0.4999 * rnd(&seed);
            double p[3], du[3], dv[3], pp[3], pm[3], q[3];
            q2n_bspline_eval(&s, u, v, p, du, dv);
            q2n_bspline_eval(&s, u + h, v, pp, NULL, NULL);
            q2n_bspline_eval(&s, u - h, v, pm, NULL, NULL);
            for (int c = 0; c < 3; c++) maxe = fmax(maxe, fabs(du[c] - (pp[c] - pm[c]) / (2 * h)) / (1 + fabs(du[c])));
            q2n_bspline_eval(&s, u, v + h, pp, NULL, NULL);
            q2n_bspline_eval(&s, u, v - h, pm, NULL, NULL);
            for (int c = 0; c < 3; c++) maxe = fmax(maxe, fabs(dv[c] - (pp[c] - pm[c]) / (2 * h)) / (1 + fabs(dv[c])));
            for (int i = 0; i < s.ncp_u * s.ncp_v; i++) s.cp[3 * i] += 10.0;
            q2n_bspline_eval(&s, u, v, q, NULL, NULL);
            for (int i = 0; i < s.ncp_u * s.ncp_v; i++) s.cp[3 * i] -= 10.0;
            maxt = fmax(maxt, fabs(q[0] - p[0] - 10.0));
        }
        CHECK(maxe < 1e-6, "derivatives vs finite differences (rational=%d): %.3g", rational, maxe);
        CHECK(maxt < 1e-12, "translation invariance (rational=%d): %.3g", rational, maxt);
        /* corners interpolate the corner control points (clamped knots) */
        double p[3], e = 0.0;
        q2n_bspline_eval(&s, 1.0, 1.0, p, NULL, NULL);
        for (int c = 0; c < 3; c++) e = fmax(e, fabs(p[c] - s.cp[3 * (s.ncp_u * s.ncp_v - 1) + c]));
        q2n_bspline_eval(&s, 0.0, 1.0, p, NULL, NULL);
        for (int c = 0; c < 3; c++) e = fmax(e, fabs(p[c] - s.cp[3 * (s.ncp_u * (s.ncp_v - 1)) + c]));
        CHECK(e < 1e-14, "corner interpolation (rational=%d): %.3g", rational, e);
        q2n_bspline_free(&s);
    }
    /* 3. Exact rational quarter circle (degree 2, weights 1, 1/sqrt2, 1) extruded linearly in v. */
    {
        double ku[6] = {0, 0, 0, 1, 1, 1}, kv[4] = {0, 0, 1, 1};
        double cp[18] = {1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 2, 1, 1, 2, 0, 1, 2};
        double w[6] = {1, 0.70710678118654752440, 1, 1, 0.70710678118654752440, 1};
        q2n_bspline_surface s = {2, 1, 3, 2, ku, kv, cp, w};
        CHECK(q2n_bspline_check(&s, &err) == Q2N_OK, "check: %s", err.message);
        double er = 0.0, et = 0.0;
        for (int t = 0; t <= 20; t++) {
            double p[3], du[3];
            q2n_bspline_eval(&s, t / 20.0, 0.3, p, du, NULL);
            er = fmax(er, fabs(hypot(p[0], p[1]) - 1.0));
            et = fmax(et, fabs(p[0] * du[0] + p[1] * du[1]) / hypot(du[0], du[1])); /* tangent _|_ radius */
            er = fmax(er, fabs(p[2] - 0.6));
        }
        CHECK(er < 1e-15, "quarter circle radius error %.3g", er);
        CHECK(et < 1e-14, "quarter circle tangent error %.3g", et);
    }
    /* 4. check() rejects what writers must not see. */
    {
        q2n_bspline_surface s;
        make_surface(&s, 3, 3, 6, 5, 1, 5u);
        CHECK(q2n_bspline_check(&s, &err) == Q2N_OK, "check: %s", err.message);
        s.knots_u[0] = -0.1;
        CHECK(q2n_bspline_check(&s, &err) == Q2N_ERR_ARG && strstr(err.message, "clamped"), "unclamped: %s", err.message);
        s.knots_u[0] = 0.0;
        double t = s.knots_v[5]; s.knots_v[5] = s.knots_v[4] - 0.1;
        CHECK(q2n_bspline_check(&s, &err) == Q2N_ERR_ARG && strstr(err.message, "decrease"), "decreasing: %s", err.message);
        s.knots_v[5] = t;
        s.cp[7] = NAN;
        CHECK(q2n_bspline_check(&s, &err) == Q2N_ERR_ARG && strstr(err.message, "finite"), "NaN cp: %s", err.message);
        s.cp[7] = 0.0;
        s.weights[3] = 0.0;
        CHECK(q2n_bspline_check(&s, &err) == Q2N_ERR_ARG && strstr(err.message, "weight"), "zero weight: %s", err.message);
        s.weights[3] = 1.0;
        s.ncp_u = 3;
        CHECK(q2n_bspline_check(&s, &err) == Q2N_ERR_ARG, "too few control points accepted");
        s.ncp_u = 6;
        CHECK(q2n_bspline_check(&s, &err) == Q2N_OK, "restored: %s", err.message);
        q2n_bspline_free(&s);
        q2n_bspline_free(NULL);
        q2n_nurbs_model_free(NULL);
        /* a heap model as the fit stage makes it: free releases patches, arrays and the struct
         * (run under valgrind / CONFIG=asan to see it leak-free) */
        q2n_nurbs_model *hm = calloc(1, sizeof *hm);
        hm->n = 2;
        hm->patches = calloc(2, sizeof(q2n_bspline_surface));
        make_surface(&hm->patches[0], 3, 2, 5, 4, 1, 9u);
        make_surface(&hm->patches[1], 5, 5, 6, 6, 0, 10u);
        CHECK(q2n_bspline_check(&hm->patches[1], &err) == Q2N_OK, "heap model patch: %s", err.message);
        q2n_nurbs_model_free(hm);
    }
    CHECK_DONE("test_export_bspline");
}
