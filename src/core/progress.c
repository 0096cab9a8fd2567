/* progress.c — see progress.h. */
#include "core/progress.h"

#include "core/clock.h"

void q2n_progress_emit(const q2n_progress_sink *s, const char *stage, const char *detail, long done, long total)
{
    if (!s || !s->fn) return;
    q2n_progress p = {stage, detail ? detail : "", done, total, q2n_now() - s->t0};
    s->fn(s->user, &p);
}
