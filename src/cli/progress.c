/* progress.c — the progress display of the command line (cli.h): on a terminal one line,
 * rewritten in place at most a few times per second; with --progress elsewhere plain lines at
 * most once per second; nothing with -q.  Each shows the stage, items done / total, the elapsed
 * time and, when a stage has items and has run a while, an estimate of the time left. */
#include "cli.h"

#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include "cli/policy.h"

void cli_progress_init(cli_progress *p, int quiet, int force, int utf8)
{
    memset(p, 0, sizeof *p);
    p->utf8 = utf8;
    p->shown_at = -1;
    p->mode = quiet ? CLI_PROGRESS_OFF : isatty(STDERR_FILENO) ? CLI_PROGRESS_TTY
            : force ? CLI_PROGRESS_LINES : CLI_PROGRESS_OFF;
}

static int term_width(void)
{
    struct winsize ws;
    if (ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20) return ws.ws_col;
    return 80;
}

static void fmt_time(double s, char *out, size_t n)
{
    if (s < 60) snprintf(out, n, "%.1f s", s);
    else if (s < 3600) snprintf(out, n, "%d min %02d s", (int)(s / 60), (int)s % 60);
    else snprintf(out, n, "%d h %02d min", (int)(s / 3600), (int)(s / 60) % 60);
}

void cli_progress_report(void *user, const q2n_progress *r)
{
    cli_progress *p = user;
    if (p->mode == CLI_PROGRESS_OFF) return;
    int changed = strncmp(p->stage, r->stage, sizeof p->stage - 1) || strncmp(p->detail, r->detail, sizeof p->detail - 1);
    if (strncmp(p->stage, r->stage, sizeof p->stage - 1)) {
        p->stage_t0 = r->elapsed_s;
        p->context[0] = '\0';
    }
    if (r->total == 0) snprintf(p->context, sizeof p->context, "%s", r->detail);
    snprintf(p->stage, sizeof p->stage, "%s", r->stage);
    snprintf(p->detail, sizeof p->detail, "%s", r->detail);
    double every = p->mode == CLI_PROGRESS_TTY ? CLI_PROGRESS_TTY_EVERY : CLI_PROGRESS_LINE_EVERY;
    if (r->elapsed_s < CLI_PROGRESS_DELAY) return;
    if (p->shown_at >= 0 && r->elapsed_s - p->shown_at < (changed ? CLI_PROGRESS_TTY_EVERY : every)) return;
    p->shown_at = r->elapsed_s;

    char line[640], detail[200], ctx[200], el[32], left[32];
    q2n_escape(detail, sizeof detail, r->detail);
    q2n_escape(ctx, sizeof ctx, r->total > 0 ? p->context : "");
    int n = snprintf(line, sizeof line, "quad2nurbs: %s%s%s%s%s", r->stage, ctx[0] ? " " : "", ctx,
                     detail[0] ? (ctx[0] ? ": " : " ") : "", detail);
    if (r->total > 0)
        n += snprintf(line + n, sizeof line - (size_t)n, " %ld/%ld (%d %%)", r->done, r->total,
                      (int)(100.0 * (double)r->done / (double)r->total));
    fmt_time(r->elapsed_s, el, sizeof el);
    n += snprintf(line + n, sizeof line - (size_t)n, ", %s", el);
    double ts = r->elapsed_s - p->stage_t0;
    if (r->total > 0 && r->done > 0 && ts >= CLI_PROGRESS_ETA_AFTER) {
        fmt_time(ts / (double)r->done * (double)(r->total - r->done), left, sizeof left);
        n += snprintf(line + n, sizeof line - (size_t)n, ", about %s left in %s", left, r->stage);
    }
    if (n > (int)sizeof line - 1) n = (int)sizeof line - 1;
    if (p->mode == CLI_PROGRESS_LINES) {
        fprintf(stderr, "%s\n", line);
        return;
    }
    int w = term_width() - 1;           /* never wrap: the line is rewritten with \r */
    if (n > w) n = w;
    fprintf(stderr, "\r%.*s", n, line);
    for (int i = n; i < p->line_len; i++) fputc(' ', stderr);
    p->line_len = n;
    fflush(stderr);
    cli_signals_tty_line(1);
}

void cli_progress_clear(cli_progress *p)
{
    if (p->mode != CLI_PROGRESS_TTY || !p->line_len) return;
    fputc('\r', stderr);
    for (int i = 0; i < p->line_len; i++) fputc(' ', stderr);
    fputc('\r', stderr);
    fflush(stderr);
    p->line_len = 0;
    cli_signals_tty_line(0);
}
