/* par.c — the one parallel loop of the pipeline's stages (the fit's sampling, assembly and
 * measurement, the STEP and IGES writers' items; see par.h): each thread takes the next undone
 * item from a shared counter (items differ in cost by 100x: a regular patch against an
 * extraordinary one with hundreds of spans, so a fixed deal left one thread idle for a third of a
 * stage); results are written per item and reduced by the caller
 * in index order, so the output does not depend on the thread count or on which thread did what. */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "core/par.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <unistd.h>

typedef struct par_job {
    void (*fn)(void *, int);
    void *arg;
    int n;
    atomic_int next;
} par_job;

static void *par_worker(void *p)
{
    par_job *j = p;
    for (;;) {
        int i = atomic_fetch_add_explicit(&j->next, 1, memory_order_relaxed);
        if (i >= j->n) break;
        j->fn(j->arg, i);
    }
    return NULL;
}

void q2n_par_for(int n, int threads, void (*fn)(void *arg, int i), void *arg)
{
    int T = threads < 1 ? 1 : threads > Q2N_PAR_MAX_THREADS ? Q2N_PAR_MAX_THREADS : threads;
    if (T > n) T = n > 0 ? n : 1;
    par_job job;
    job.fn = fn;
    job.arg = arg;
    job.n = n;
    atomic_init(&job.next, 0);
    pthread_t tid[Q2N_PAR_MAX_THREADS];
    int started[Q2N_PAR_MAX_THREADS] = {0};
    for (int w = 1; w < T; w++) started[w] = pthread_create(&tid[w], NULL, par_worker, &job) == 0;
    par_worker(&job);   /* the calling thread works too; a thread that failed to start leaves its share to the others */
    for (int w = 1; w < T; w++)
        if (started[w]) pthread_join(tid[w], NULL);
}

int q2n_par_cpus(void)
{
    cpu_set_t set;
    long n = 0;
    if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
    if (n < 1) n = sysconf(_SC_NPROCESSORS_ONLN); /* more processors than a cpu_set_t holds, or no affinity */
    if (n < 1) n = 1;
    return n > Q2N_PAR_MAX_THREADS ? Q2N_PAR_MAX_THREADS : (int)n;
}
