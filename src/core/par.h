/* par.h — the parallel loop every stage uses (POSIX threads): items 0 .. n-1, each handed to the
 * next free thread.  fn(arg, i) must write item i's results to item i's own place; the caller
 * reduces them in index order afterwards, so results never depend on the thread count or on which
 * thread did what. */
#ifndef Q2N_CORE_PAR_H
#define Q2N_CORE_PAR_H

#define Q2N_PAR_MAX_THREADS 64   /* threads beyond this are not started (the --threads cap) */

/* fn(arg, i) for every i in [0, n) on min(threads, n, Q2N_PAR_MAX_THREADS) threads, the caller's
 * among them; returns when all are done.  threads < 1 counts as 1. */
void q2n_par_for(int n, int threads, void (*fn)(void *arg, int i), void *arg);

/* The processors this process may run on (its CPU affinity: taskset, cpusets), at most
 * Q2N_PAR_MAX_THREADS; the online count where the affinity cannot be read. */
int q2n_par_cpus(void);

#endif
