/*
 * example_control_loop.c - rps3 in a fixed-rate control loop: every tick,
 * the feedforward actuator forces for the desired motion of the paper's
 * helix.  Built and run by `make check`; docs/performance.md quotes it.
 *
 *   example_control_loop [TICKS]     (default 300 ticks at 1 kHz)
 *
 * It reports the worst tick latency, from the scheduled tick to the forces
 * being ready, and the ticks that overran their period.  Nothing is
 * asserted about time: the exit status is 0 unless the library failed.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "rps3.h"

#define RATE_HZ 1000L
#define PERIOD_NS (1000000000L / RATE_HZ)
#define MAX_TICKS 10000L

/* per-tick timings, kept for the medians printed at the end */
static long lat_ns[MAX_TICKS], calc_ns[MAX_TICKS];

static int cmp_long(const void *a, const void *b) {
  long x = *(const long *)a, y = *(const long *)b;
  return (x > y) - (x < y);
}

static long elapsed_ns(const struct timespec *a, const struct timespec *b) {
  return (b->tv_sec - a->tv_sec) * 1000000000L + (b->tv_nsec - a->tv_nsec);
}

int main(int argc, char **argv) {
  long ticks = (argc > 1) ? atol(argv[1]) : 300, k, overruns = 0;
  double sum = 0.0;
  rps3_check chk;
  rps3_model m;
  rps3_data *d = NULL;
  rps3_traj tr;
  struct timespec next, woke, done;

  /* set up once, outside the loop: the only allocation is the data */
  rps3_model_default(&m);                 /* Table II */
  m.opt.effects = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD; /* no payload here */
  m.friction.viscous = 0.01;              /* N m s / rad at each pin */
  m.opt.theta = RPS3_THETA_CLOSED_FORM;   /* pose known: theta by (39) */
  m.opt.method = RPS3_LAGRANGE;
  if (rps3_model_init(&m, &chk) != RPS3_OK) {
    fprintf(stderr, "model: %s\n", chk.msg);
    return 1;
  }
  if (rps3_data_alloc(&m, &d) != RPS3_OK) return 1;
  rps3_traj_default(&tr);                 /* the paper's helix */
  if (ticks < 1 || ticks > MAX_TICKS) ticks = 300;

  clock_gettime(CLOCK_MONOTONIC, &next);
  for (k = 0; k < ticks; k++) {
    int status;
    /* sleep until the next tick, on an absolute schedule (no drift) */
    next.tv_nsec += PERIOD_NS;
    if (next.tv_nsec >= 1000000000L) {
      next.tv_nsec -= 1000000000L;
      next.tv_sec++;
    }
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
    clock_gettime(CLOCK_MONOTONIC, &woke);

    /* desired pose, rates and accelerations at this tick */
    rps3_traj_eval(&m, &tr, (double)k / (double)RATE_HZ, d->pose, d->dpose,
                   d->ddpose);
    /* positions -> rates -> forces; no allocation, no I/O */
    status = rps3_inverse(&m, d);
    if (status != RPS3_OK) {
      /* a real controller would hold or fault here */
      fprintf(stderr, "tick %ld: %s: %s\n", k, rps3_strerror(status),
              d->err.msg);
      rps3_data_free(d);
      return 1;
    }
    /* d->F[0..2]: feedforward forces [N] for the three actuators */
    sum += d->F[0] + d->F[1] + d->F[2];

    clock_gettime(CLOCK_MONOTONIC, &done);
    lat_ns[k] = elapsed_ns(&next, &done);  /* scheduled tick -> forces */
    calc_ns[k] = elapsed_ns(&woke, &done); /* trajectory + library */
    if (lat_ns[k] > PERIOD_NS) overruns++;
  }

  qsort(lat_ns, (size_t)ticks, sizeof(long), cmp_long);
  qsort(calc_ns, (size_t)ticks, sizeof(long), cmp_long);
  printf("control loop: %ld ticks at %ld Hz, mean F1+F2+F3 %.4f N\n"
         "  tick latency (scheduled tick -> forces ready): median %.1f us, "
         "worst %.1f us, %ld overruns of the %.0f us period\n"
         "  computation (trajectory + rps3_inverse): median %.2f us, "
         "worst %.1f us\n",
         ticks, RATE_HZ, sum / (double)ticks, 1e-3 * (double)lat_ns[ticks / 2],
         1e-3 * (double)lat_ns[ticks - 1], overruns, 1e-3 * (double)PERIOD_NS,
         1e-3 * (double)calc_ns[ticks / 2], 1e-3 * (double)calc_ns[ticks - 1]);
  rps3_data_free(d);
  return 0;
}
