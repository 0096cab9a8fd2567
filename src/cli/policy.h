/* policy.h — the command line's display rates (progress.c) and its allocator settings (main.c). */
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

/* glibc's allocator: blocks up to this size come from the heap instead of fresh mappings, and up to
 * CLI_TRIM_THRESHOLD of free heap is kept.  The construction and the fit allocate and free work
 * arrays of 0.1-1 MB per face, thousands of times: mapped afresh, each is zero-filled by the kernel
 * page by page and unmapped again (whole runs 6-12 % faster, most where every face is at an
 * extraordinary vertex; the peak memory 2-14 % higher; docs/status.md, stop 45). */
#define CLI_MMAP_THRESHOLD (256 << 20)
#define CLI_TRIM_THRESHOLD (512 << 20)

#endif
