/* fit_par.c — the one parallel loop of the fit stage (construction sampling, corner jets,
 * measurement): items are dealt round-robin to POSIX threads; results are written per item and
 * reduced by the caller in index order, so the output does not depend on the thread count. */
#include "fit/fit_internal.h"

#include <pthread.h>


typedef struct par_job {
    void (*fn)(void *, int);
    void *arg;
    int n, w, T;
} par_job;

static void *par_worker(void *p)
{
    par_job *j = p;
    for (int i = j->w; i < j->n; i += j->T) j->fn(j->arg, i);
    return NULL;
}

void q2n_fit_par_for(int n, int threads, void (*fn)(void *arg, int i), void *arg)
{
    int T = threads < 1 ? 1 : threads > Q2N_FIT_MAX_THREADS ? Q2N_FIT_MAX_THREADS : threads;
    if (T > n) T = n > 0 ? n : 1;
    par_job jobs[Q2N_FIT_MAX_THREADS];
    pthread_t tid[Q2N_FIT_MAX_THREADS];
    int started[Q2N_FIT_MAX_THREADS] = {0};
    for (int w = 0; w < T; w++) {
        jobs[w] = (par_job){fn, arg, n, w, T};
        if (w > 0) started[w] = pthread_create(&tid[w], NULL, par_worker, &jobs[w]) == 0;
    }
    par_worker(&jobs[0]);
    for (int w = 1; w < T; w++) {
        if (started[w]) pthread_join(tid[w], NULL);
        else par_worker(&jobs[w]);
    }
}
