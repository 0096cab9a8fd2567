/* cli.h — the parts of the `quad2nurbs` command (src/cli/) that main.c uses: the progress display
 * on stderr (progress.c) and the signal handling that removes the outputs' temporaries
 * (signals.c). */
#ifndef Q2N_CLI_CLI_H
#define Q2N_CLI_CLI_H

#include <signal.h>

#include "quad2nurbs.h"

/* ---- progress.c ---- */
typedef enum { CLI_PROGRESS_OFF = 0, CLI_PROGRESS_TTY, CLI_PROGRESS_LINES } cli_progress_mode;

typedef struct cli_progress {
    cli_progress_mode mode;
    int utf8;
    double shown_at;        /* elapsed time of the last line shown (-1: none yet) */
    double stage_t0;        /* elapsed time when the current stage began */
    char stage[32], detail[96];
    char context[96];       /* the stage's last uncounted detail (an output's name), kept for counted reports */
    int line_len;           /* characters of the line on screen (TTY mode) */
} cli_progress;

/* TTY mode when stderr is a terminal (or `force`, then plain lines elsewhere), off when quiet. */
void cli_progress_init(cli_progress *p, int quiet, int force, int utf8);
/* The library's callback (user = the cli_progress). */
void cli_progress_report(void *user, const q2n_progress *r);
/* Erase the line on screen before something else is printed (TTY mode). */
void cli_progress_clear(cli_progress *p);

/* ---- signals.c ---- */
/* SIGINT, SIGTERM, SIGHUP: remove the registered temporaries, then die of the signal (the shell
 * reports 128 + the signal number: 130, 143, 129).  A signal ignored when the program started (nohup,
 * background jobs) stays ignored.  SIGPIPE is ignored: a closed pipe is a write error. */
void cli_signals_install(void);
/* Temporaries of an output set to remove on a signal (replaces the previous registration). */
void cli_signals_register(const q2n_outputs *s);
/* Hold the signals off (around the commit, while files are renamed), and let them in again. */
void cli_signals_block(sigset_t *old);
void cli_signals_unblock(const sigset_t *old);
/* Whether a progress line is on the terminal (the handler ends it with a newline). */
void cli_signals_tty_line(int on);

#endif
