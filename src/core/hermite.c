/* hermite.c — Hermite basis tables and evaluation (hermite.h). */
#include "core/hermite.h"

#include <pthread.h>
#include <stdint.h>
#include <string.h>

const double q2n_hermite_coef[Q2N_HERMITE_MAXK][Q2N_HERMITE_MAXK + 1][2][10] = {
    { /* K = 1 */
        {{1, 0, -3, 2, 0, 0, 0, 0, 0, 0}, {0, 0, 3, -2, 0, 0, 0, 0, 0, 0}},
        {{0, 1, -2, 1, 0, 0, 0, 0, 0, 0}, {0, 0, -1, 1, 0, 0, 0, 0, 0, 0}}},
    { /* K = 2 */
        {{1, 0, 0, -10, 15, -6, 0, 0, 0, 0}, {0, 0, 0, 10, -15, 6, 0, 0, 0, 0}},
        {{0, 1, 0, -6, 8, -3, 0, 0, 0, 0}, {0, 0, 0, -4, 7, -3, 0, 0, 0, 0}},
        {{0, 0, 1.0 / 2, -3.0 / 2, 3.0 / 2, -1.0 / 2, 0, 0, 0, 0}, {0, 0, 0, 1.0 / 2, -1, 1.0 / 2, 0, 0, 0, 0}}},
    { /* K = 3 */
        {{1, 0, 0, 0, -35, 84, -70, 20, 0, 0}, {0, 0, 0, 0, 35, -84, 70, -20, 0, 0}},
        {{0, 1, 0, 0, -20, 45, -36, 10, 0, 0}, {0, 0, 0, 0, -15, 39, -34, 10, 0, 0}},
        {{0, 0, 1.0 / 2, 0, -5, 10, -15.0 / 2, 2, 0, 0}, {0, 0, 0, 0, 5.0 / 2, -7, 13.0 / 2, -2, 0, 0}},
        {{0, 0, 0, 1.0 / 6, -2.0 / 3, 1, -2.0 / 3, 1.0 / 6, 0, 0}, {0, 0, 0, 0, -1.0 / 6, 1.0 / 2, -1.0 / 2, 1.0 / 6, 0, 0}}},
    { /* K = 4 */
        {{1, 0, 0, 0, 0, -126, 420, -540, 315, -70}, {0, 0, 0, 0, 0, 126, -420, 540, -315, 70}},
        {{0, 1, 0, 0, 0, -70, 224, -280, 160, -35}, {0, 0, 0, 0, 0, -56, 196, -260, 155, -35}},
        {{0, 0, 1.0 / 2, 0, 0, -35.0 / 2, 105.0 / 2, -63, 35, -15.0 / 2}, {0, 0, 0, 0, 0, 21.0 / 2, -77.0 / 2, 53, -65.0 / 2, 15.0 / 2}},
        {{0, 0, 0, 1.0 / 6, 0, -5.0 / 2, 20.0 / 3, -15.0 / 2, 4, -5.0 / 6}, {0, 0, 0, 0, 0, -1, 23.0 / 6, -11.0 / 2, 7.0 / 2, -5.0 / 6}},
        {{0, 0, 0, 0, 1.0 / 24, -5.0 / 24, 5.0 / 12, -5.0 / 12, 5.0 / 24, -1.0 / 24}, {0, 0, 0, 0, 0, 1.0 / 24, -1.0 / 6, 1.0 / 4, -1.0 / 6, 1.0 / 24}}}
};

/* Derivative tables: D[K-1][a][e][q][i] = coefficient of t^i in the q-th derivative of H_{a,e}
 * (order K), filled once. */
static double D[Q2N_HERMITE_MAXK][Q2N_HERMITE_MAXK + 1][2][Q2N_HERMITE_MAXD + 1][10];
static pthread_once_t D_once = PTHREAD_ONCE_INIT;

static void fill_tables(void)
{
    for (int K = 1; K <= Q2N_HERMITE_MAXK; K++)
        for (int a = 0; a <= K; a++)
            for (int e = 0; e < 2; e++)
                for (int q = 0; q <= Q2N_HERMITE_MAXD; q++)
                    for (int i = 0; i < 10; i++) {
                        int p = i + q; /* t^i comes from t^p */
                        double f = p < 10 ? q2n_hermite_coef[K - 1][a][e][p] : 0;
                        for (int j = 0; j < q && f != 0; j++) f *= (double)(p - j);
                        D[K - 1][a][e][q][i] = f;
                    }
}

/* The evaluation proper (q2n_hermite_eval without the memo). */
static void hermite_compute(int K, double t, int nder, double H[][2][Q2N_HERMITE_MAXD + 1])
{
    int deg = 2 * K + 1;
    double pw[10];
    pw[0] = 1;
    for (int i = 1; i <= deg; i++) pw[i] = pw[i - 1] * t;
    for (int a = 0; a <= K; a++)
        for (int e = 0; e < 2; e++)
            for (int q = 0; q <= nder; q++) {
                const double *c = D[K - 1][a][e][q];
                double r = 0;
                for (int i = 0; i + q <= deg; i++) r += c[i] * pw[i];
                H[a][e][q] = r;
            }
}

/* A composite patch asks for the same bases many times: every point of a Coons patch evaluates
 * its two opposite sides at the same parameter, each side three or four fields of different
 * orders, points along one side share the cross parameter, and the extraordinary construction's
 * energy evaluates every face's sides at the same quadrature nodes.  A table per thread, keyed by
 * (K, the bits of t) — direct-mapped: the slot is a hash of the key, a new key replaces the slot's
 * old one — and computed up to some nder, answers repeated requests by copying: the same numbers,
 * a fraction of the work.  (A 16-entry LRU list missed 39 % of the requests on a subdivided
 * 732-face mesh: the quadrature cycles through more keys than that.) */
#define MEMO_BITS 8
#define MEMO_N (1 << MEMO_BITS)
typedef struct memo_entry {
    int K, nder;             /* order (0: empty), derivatives computed */
    uint64_t tbits;
    double H[Q2N_HERMITE_MAXK + 1][2][Q2N_HERMITE_MAXD + 1];
} memo_entry;
static _Thread_local memo_entry memo[MEMO_N];

void q2n_hermite_eval(int K, double t, int nder, double H[][2][Q2N_HERMITE_MAXD + 1])
{
    pthread_once(&D_once, fill_tables);
    uint64_t tb;
    memcpy(&tb, &t, sizeof tb);
    uint64_t h = (tb ^ (tb >> 32) ^ (uint64_t)K * 0x9e3779b97f4a7c15ull) * 0xff51afd7ed558ccdull;
    memo_entry *m = &memo[h >> (64 - MEMO_BITS)];
    if (m->K != K || m->tbits != tb || m->nder < nder) {   /* a miss, or the same key asked for more derivatives */
        m->K = K;
        m->tbits = tb;
        m->nder = nder;
        hermite_compute(K, t, nder, m->H);
    }
    for (int a = 0; a <= K; a++)
        for (int e = 0; e < 2; e++) memcpy(H[a][e], m->H[a][e], sizeof(double) * (size_t)(nder + 1));
}
