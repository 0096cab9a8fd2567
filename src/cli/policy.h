/* policy.h — the command line's display rates (progress.c). */
#ifndef Q2N_CLI_POLICY_H
#define Q2N_CLI_POLICY_H

/* Nothing is shown before this many seconds: short runs stay quiet. */
#define CLI_PROGRESS_DELAY 0.5
/* At most one rewrite of the terminal line per this many seconds (a few per second). */
#define CLI_PROGRESS_TTY_EVERY 0.25
/* Plain lines (--progress without a terminal, e.g. a log): at most one per this many seconds. */
#define CLI_PROGRESS_LINE_EVERY 1.0
/* An estimate of the time left is shown once a stage has run this long (earlier ones jump). */
#define CLI_PROGRESS_ETA_AFTER 2.0

#endif
