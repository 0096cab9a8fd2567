/* signals.c — clean exit on SIGINT / SIGTERM / SIGHUP (cli.h).  The handler only calls
 * async-signal-safe functions (unlink, write, signal, raise) on names registered before. */
#include "cli.h"

#include <string.h>
#include <unistd.h>

#define MAX_TEMPS 32

static const char *volatile temps[MAX_TEMPS];
static volatile sig_atomic_t ntemps, tty_line;
static const int SIGNALS[] = {SIGINT, SIGTERM, SIGHUP};

static void on_signal(int sig)
{
    for (sig_atomic_t i = 0; i < ntemps; i++)
        if (temps[i]) unlink(temps[i]);
    if (tty_line) {
        ssize_t r = write(STDERR_FILENO, "\n", 1);
        (void)r;
    }
    signal(sig, SIG_DFL);   /* die of the signal, so that the caller (a shell, make) sees it */
    raise(sig);
}

void cli_signals_install(void)
{
    struct sigaction sa, old;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < sizeof SIGNALS / sizeof SIGNALS[0]; i++) {
        sigaddset(&sa.sa_mask, SIGNALS[i]);   /* one handler at a time */
    }
    for (size_t i = 0; i < sizeof SIGNALS / sizeof SIGNALS[0]; i++) {
        if (sigaction(SIGNALS[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        sigaction(SIGNALS[i], &sa, NULL);
    }
    signal(SIGPIPE, SIG_IGN);
}

void cli_signals_register(const q2n_outputs *s)
{
    sigset_t old;
    cli_signals_block(&old);   /* nested blocks are fine: the caller's mask comes back */
    ntemps = 0;
    int n = q2n_outputs_count(s);
    for (int i = 0; i < n && i < MAX_TEMPS; i++) temps[i] = q2n_outputs_temp_path(s, i);
    ntemps = n < MAX_TEMPS ? n : MAX_TEMPS;
    cli_signals_unblock(&old);
}

void cli_signals_block(sigset_t *old)
{
    sigset_t set;
    sigemptyset(&set);
    for (size_t i = 0; i < sizeof SIGNALS / sizeof SIGNALS[0]; i++) sigaddset(&set, SIGNALS[i]);
    sigprocmask(SIG_BLOCK, &set, old);
}

void cli_signals_unblock(const sigset_t *old) { sigprocmask(SIG_SETMASK, old, NULL); }

void cli_signals_tty_line(int on) { tty_line = on; }
