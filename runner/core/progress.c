/* progress.c - see progress.h. */
#include "progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

/* seconds between updates of the bar, and between plain lines */
#define BAR_INTERVAL 0.1
#define LINE_INTERVAL 5.0
#define BAR_WIDTH 30

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* h:mm:ss of a duration */
static void hms(char *buf, size_t sz, double s) {
  long t = (long)(s + 0.5);
  if (s != s || s < 0 || s > 1e8) {
    snprintf(buf, sz, "--:--");
    return;
  }
  snprintf(buf, sz, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
}

void progress_start(progress *p, size_t ncase, int quiet) {
  p->ncase = ncase;
  p->njob = p->njob_all = 0;
  p->t0 = now();
  p->shown = p->t0;
  p->npoint = 0;
  p->failure_shown = 0;
  p->mode = quiet                   ? PROGRESS_QUIET
            : isatty(STDERR_FILENO) ? PROGRESS_BAR
                                    : PROGRESS_LINES;
  p->interval = p->mode == PROGRESS_BAR ? BAR_INTERVAL : LINE_INTERVAL;
}

/* columns of the terminal on stderr (re-read at every update: the window
   may be resized), else $COLUMNS, else 80 */
static int term_width(void) {
  struct winsize w;
  const char *c = getenv("COLUMNS");
  long n;
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 0)
    return (int)w.ws_col;
  n = c ? strtol(c, NULL, 10) : 0;
  return n > 0 && n < 10000 ? (int)n : 80;
}

/* the fraction done: by samples when their total is known (a single long
   case moves the bar too), else by cases */
static double fraction(const progress *p, size_t cases_done,
                       size_t points_done) {
  double f = p->npoint  ? (double)points_done / (double)p->npoint
             : p->ncase ? (double)cases_done / (double)p->ncase
                        : 0;
  return f > 1 ? 1 : f;
}

/* the bar: "[###...] 3/48 cases  1.2 cases/s  5e+05 samples/s  ETA h:mm:ss"
   (without the rates on a narrow terminal) cut to the terminal's width, drawn
   over the previous one and the rest of the line cleared (a shorter line leaves
   no tail of the longer one) */
static void draw_bar(const progress *p, double f, size_t cases_done,
                     double rate, double srate, const char *eta) {
  char text[160], line[512];
  int width = term_width() - 1, bar, i, n;
  snprintf(text, sizeof text,
           " %zu/%zu cases  %.3g cases/s  %.3g samples/s  ETA %s", cases_done,
           p->ncase, rate, srate, eta);
  bar = width - (int)strlen(text) - 2;
  if (bar < 10) { /* a narrow terminal: the bar before the rates */
    snprintf(text, sizeof text, " %zu/%zu cases  ETA %s", cases_done, p->ncase,
             eta);
    bar = width - (int)strlen(text) - 2;
  }
  if (bar > BAR_WIDTH) bar = BAR_WIDTH;
  n = 0;
  if (bar >= 5) {
    int fill = (int)((double)bar * f);
    line[n++] = '[';
    for (i = 0; i < bar; i++) line[n++] = i < fill ? '#' : '.';
    line[n++] = ']';
  }
  snprintf(line + n, sizeof line - (size_t)n, "%s", n ? text : text + 1);
  if (width > 0 && width < (int)sizeof line && (int)strlen(line) > width)
    line[width] = '\0';
  fprintf(stderr, "\r%s\033[K", line);
}

void progress_update(progress *p, size_t cases_done, size_t points_done) {
  double t = now(), el = t - p->t0, rate, eta, f;
  char e1[32], e2[32];
  if (p->mode == PROGRESS_QUIET || t - p->shown < p->interval) return;
  p->shown = t;
  rate = el > 0 ? (double)cases_done / el : 0;
  f = fraction(p, cases_done, points_done);
  eta = f > 0 ? el * (1 - f) / f : -1;
  hms(e1, sizeof e1, el);
  hms(e2, sizeof e2, eta);
  if (p->mode == PROGRESS_BAR) {
    draw_bar(p, f, cases_done, rate, el > 0 ? (double)points_done / el : 0, e2);
  } else {
    fprintf(stderr,
            "rps3-run: %zu/%zu cases, %zu samples, %s elapsed, %.3g cases/s, "
            "ETA %s\n",
            cases_done, p->ncase, points_done, e1, rate, e2);
  }
  fflush(stderr);
}

void progress_failure(progress *p, size_t icase, const char *what,
                      const char *msg) {
  if (p->failure_shown) return;
  p->failure_shown = 1;
  if (p->mode == PROGRESS_BAR) fputs("\r\033[K", stderr);
  fprintf(stderr, "rps3-run: first failure: case %zu%s%s%s: %s\n", icase,
          what && *what ? " (" : "", what ? what : "", what && *what ? ")" : "",
          msg);
  fflush(stderr);
  /* the bar is drawn again at the next update */
  if (p->mode == PROGRESS_BAR) p->shown = 0;
}

void progress_finish(progress *p, size_t cases_done, size_t points_done,
                     size_t nfailed) {
  double el = now() - p->t0;
  char e1[32];
  if (p->mode == PROGRESS_QUIET) return;
  hms(e1, sizeof e1, el);
  if (p->mode == PROGRESS_BAR)
    fputs("\r\033[K", stderr); /* the bar gives way to the summary */
  fprintf(stderr,
          "rps3-run: %zu/%zu cases (%zu failed), %zu samples in %s (%.3g "
          "samples/s)",
          cases_done, p->ncase, nfailed, points_done, e1,
          el > 0 ? (double)points_done / el : 0);
  if (p->njob && p->njob != p->njob_all)
    fprintf(stderr, ", %zu of %zu work units", p->njob, p->njob_all);
  else if (p->njob)
    fprintf(stderr, ", %zu work unit%s", p->njob, p->njob == 1 ? "" : "s");
  fputc('\n', stderr);
  fflush(stderr);
}
