/* progress.c — see progress.h. */
#include "core/progress.h"

#include <time.h>

double q2n_progress_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void q2n_progress_emit(const q2n_progress_sink *s, const char *stage, const char *detail, long done, long total)
{
    if (!s || !s->fn) return;
    q2n_progress p = {stage, detail ? detail : "", done, total, q2n_progress_clock() - s->t0};
    s->fn(s->user, &p);
}
