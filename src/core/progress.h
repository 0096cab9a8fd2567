/* progress.h — progress reports of long stages through the caller's callback (the library never
 * prints).  The record and the callback type are the public ones of include/quad2nurbs.h; a sink
 * adds the start time.  Stages report at coarse points (a stage or round begins, every few
 * hundred items), so a callback costs nothing measurable; throttling the display is the
 * caller's business. */
#ifndef Q2N_CORE_PROGRESS_H
#define Q2N_CORE_PROGRESS_H

#include "quad2nurbs.h"

typedef struct q2n_progress_sink {
    q2n_progress_fn fn;   /* NULL: no reports */
    void *user;
    double t0;            /* q2n_now() (core/clock.h) when the run started */
} q2n_progress_sink;

/* Report (stage, detail, done of total) to s->fn; s or s->fn NULL: nothing.  detail may be NULL. */
void q2n_progress_emit(const q2n_progress_sink *s, const char *stage, const char *detail, long done, long total);

#endif
