/* clock.h — the project's one clock: monotonic wall seconds for timings in reports. */
#ifndef Q2N_CORE_CLOCK_H
#define Q2N_CORE_CLOCK_H

/* Seconds since an arbitrary fixed point (CLOCK_MONOTONIC): differences are elapsed wall time. */
double q2n_now(void);

#endif
