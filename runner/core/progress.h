/*
 * progress.h - progress of a sweep on stderr: a bar with cases done, rate
 * and ETA on a terminal (one line, cleared and cut to the terminal's
 * width), a plain line every few seconds otherwise, nothing when quiet but
 * the first failure's reason.
 */
#ifndef RPS3_RUNNER_PROGRESS_H
#define RPS3_RUNNER_PROGRESS_H

#include <stddef.h>

typedef enum { PROGRESS_QUIET, PROGRESS_BAR, PROGRESS_LINES } progress_mode;

typedef struct {
  progress_mode mode;
  size_t ncase;      /* cases in the sweep */
  size_t njob;       /* jobs of those cases (0: not said) */
  size_t njob_all;   /* jobs of the whole sweep (more when sharded) */
  double t0;         /* start [s, monotonic] */
  double shown;      /* time of the last output [s] */
  double interval;   /* seconds between outputs */
  size_t npoint;     /* samples to compute (0: unknown): the bar moves by
                        samples, so that it moves inside a long case too */
  int failure_shown; /* the first failure's reason has been printed */
} progress;

/* Start; mode from quiet and whether stderr is a terminal. */
void progress_start(progress *p, size_t ncase, int quiet);

/* Report cases_done cases and points_done samples so far (rate-limited). */
void progress_update(progress *p, size_t cases_done, size_t points_done);

/* Print the first failed case's reason once ("rps3-run: first failure:
   case C (KEY = VALUE, ...): MESSAGE"), also when quiet: a user who asked
   for silence still learns why the exit code is not 0. */
void progress_failure(progress *p, size_t icase, const char *what,
                      const char *msg);

/* Final line: cases, failures, samples, elapsed time and rate, jobs. */
void progress_finish(progress *p, size_t cases_done, size_t points_done,
                     size_t nfailed);

#endif /* RPS3_RUNNER_PROGRESS_H */
