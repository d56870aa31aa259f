/*
 * progress.c - see progress.h.
 */
#include "progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

/* seconds between updates of the bar, and between plain lines */
#define BAR_INTERVAL 0.1
#define LINE_INTERVAL 5.0
#define BAR_WIDTH 30

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* h:mm:ss of a duration */
static void hms(char *buf, size_t sz, double s)
{
  long t = (long)(s + 0.5);
  if (s != s || s < 0 || s > 1e8) {
    snprintf(buf, sz, "--:--");
    return;
  }
  snprintf(buf, sz, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
}

void progress_start(progress *p, size_t ncase, int quiet)
{
  p->ncase = ncase;
  p->njob = p->njob_all = 0;
  p->t0 = now();
  p->shown = p->t0;
  if (quiet)
    p->mode = PROGRESS_QUIET;
  else if (isatty(STDERR_FILENO))
    p->mode = PROGRESS_BAR;
  else
    p->mode = PROGRESS_LINES;
  p->interval = p->mode == PROGRESS_BAR ? BAR_INTERVAL : LINE_INTERVAL;
}

void progress_update(progress *p, size_t cases_done, size_t points_done)
{
  double t = now(), el = t - p->t0, rate, eta;
  char e1[32], e2[32];
  if (p->mode == PROGRESS_QUIET || t - p->shown < p->interval)
    return;
  p->shown = t;
  rate = el > 0 ? (double)cases_done / el : 0;
  eta = rate > 0 ? (double)(p->ncase - cases_done) / rate : -1;
  hms(e1, sizeof e1, el);
  hms(e2, sizeof e2, eta);
  if (p->mode == PROGRESS_BAR) {
    int i, fill = (int)((double)BAR_WIDTH * (double)cases_done /
                        (double)(p->ncase ? p->ncase : 1));
    fputc('\r', stderr);
    fputc('[', stderr);
    for (i = 0; i < BAR_WIDTH; i++)
      fputc(i < fill ? '#' : '.', stderr);
    fprintf(stderr, "] %zu/%zu cases  %.3g cases/s  %.3g samples/s  ETA %s ",
            cases_done, p->ncase, rate, el > 0 ? (double)points_done / el : 0,
            e2);
  } else {
    fprintf(stderr,
            "rps3-run: %zu/%zu cases, %zu samples, %s elapsed, %.3g cases/s, "
            "ETA %s\n",
            cases_done, p->ncase, points_done, e1, rate, e2);
  }
  fflush(stderr);
}

void progress_finish(progress *p, size_t cases_done, size_t points_done,
                     size_t nfailed)
{
  double el = now() - p->t0;
  char e1[32];
  if (p->mode == PROGRESS_QUIET)
    return;
  hms(e1, sizeof e1, el);
  if (p->mode == PROGRESS_BAR)
    fputc('\n', stderr);
  fprintf(stderr,
          "rps3-run: %zu/%zu cases (%zu failed), %zu samples in %s "
          "(%.3g samples/s)",
          cases_done, p->ncase, nfailed, points_done, e1,
          el > 0 ? (double)points_done / el : 0);
  if (p->njob && p->njob != p->njob_all)
    fprintf(stderr, ", %zu of %zu jobs", p->njob, p->njob_all);
  else if (p->njob)
    fprintf(stderr, ", %zu job%s", p->njob, p->njob == 1 ? "" : "s");
  fputc('\n', stderr);
  fflush(stderr);
}
