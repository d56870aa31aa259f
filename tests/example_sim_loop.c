/*
 * example_sim_loop.c - a 1 kHz control loop against the simulated plant:
 * computed torque on the paper's helix (Table II), the plant with its link
 * mass (m/M = 0.5), the controller with its own model of the mechanism.
 * Built and run by `make check`; docs/simulation.md quotes it.
 *
 *   example_sim_loop [--light] [--realtime] [SECONDS]
 *
 * --light gives the controller a model without link mass (the paper's case
 * 1); --realtime paces the loop on the wall clock (one tick per
 * millisecond) instead of running as fast as it can.  It prints the
 * tracking error and the CPU time per simulated second, and (without
 * --realtime) the CPU time of the same run as one rps3_sim_advance call.
 * Nothing is asserted about time: the exit status is 0 unless the
 * library failed.
 */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "rps3.h"

#define RATE_HZ 1000.0

static double cpu_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv) {
  rps3_model plant, cmodel;
  rps3_traj tr;
  rps3_sim_options o;
  rps3_sim *s = NULL;
  rps3_ctrl *c = NULL;
  rps3_controller ctl;
  rps3_check chk;
  double seconds = 10.0, pose[3], dpose[3], emax = 0.0, c0, c1;
  int light = 0, realtime = 0, a, status = RPS3_OK;
  long k, ticks;
  struct timespec next;

  for (a = 1; a < argc; a++) {
    if (strcmp(argv[a], "--light") == 0)
      light = 1;
    else if (strcmp(argv[a], "--realtime") == 0)
      realtime = 1;
    else if (sscanf(argv[a], "%lf", &seconds) != 1 || !(seconds > 0)) {
      fprintf(stderr, "usage: %s [--light] [--realtime] [SECONDS]\n", argv[0]);
      return 2;
    }
  }

  /* set up once, outside the loop: every allocation happens here */
  rps3_model_default(&plant);               /* Table II, m/M = 0.5 */
  if (rps3_model_init(&plant, &chk) != RPS3_OK) goto fail_chk;
  cmodel = plant;                           /* the controller's own model */
  if (light) cmodel.m = 0.0;
  if (rps3_model_init(&cmodel, &chk) != RPS3_OK) goto fail_chk;
  rps3_traj_default(&tr);                   /* the paper's helix, 10 s */
  rps3_sim_options_default(&o);             /* RK4, h = 1 ms */
  if (rps3_sim_alloc(&plant, &o, &s, &chk) != RPS3_OK ||
      rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0, &cmodel, &tr, &c,
                      &chk) != RPS3_OK)
    goto fail_chk;
  /* the law, offered the plant's state at every tick */
  ctl = rps3_ctrl_bind(c, RATE_HZ);
  rps3_traj_eval(&plant, &tr, 0.0, pose, dpose, NULL);
  if (rps3_sim_start(s, 0.0, pose, dpose) != RPS3_OK) goto fail_sim;

  /* the loop: one control period per iteration, no allocation */
  ticks = (long)(seconds * RATE_HZ + 0.5);
  clock_gettime(CLOCK_MONOTONIC, &next);
  c0 = cpu_seconds();
  for (k = 1; k <= ticks; k++) {
    double l_des[3];
    int i;
    status = rps3_sim_advance(s, &ctl, (double)k / RATE_HZ);
    if (status != RPS3_OK) goto fail_sim;
    /* l_des: what the controller wanted at the last tick; rps3_sim_now(s)->y: where
       the plant is now, one period later */
    rps3_ctrl_last(c, NULL, l_des, NULL, NULL);
    for (i = 0; i < 3; i++) {
      double e = rps3_sim_now(s)->y[i] - l_des[i];
      if (e < 0) e = -e;
      if (e > emax && k > 1) emax = e;
    }
    if (realtime) {
      next.tv_nsec += 1000000L;
      if (next.tv_nsec >= 1000000000L) {
        next.tv_nsec -= 1000000000L;
        next.tv_sec++;
      }
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
    }
  }
  c1 = cpu_seconds();
  printf("simulated %.3g s of the helix at %.0f Hz, computed torque with %s "
         "model: |l - l_d(t - 1 ms)| <= %.3g m; %ld fwddyn evaluations; "
         "energy residual %.2g J; CPU %.3g s (%.0fx real time)\n",
         seconds, RATE_HZ, light ? "a massless-link" : "the plant's", emax,
         rps3_sim_now(s)->nevals, rps3_sim_now(s)->energy_residual, c1 - c0,
         seconds / (c1 - c0 > 0 ? c1 - c0 : 1e-9));

  /* the same run as one call: the state is reported at the call's end
     only, where the loop above had it reported every period */
  if (!realtime) {
    rps3_ctrl_free(c);
    c = NULL;
    if (rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0, &cmodel, &tr,
                        &c, &chk) != RPS3_OK)
      goto fail_chk;
    ctl.state = c;
    if (rps3_sim_start(s, 0.0, pose, dpose) != RPS3_OK) goto fail_sim;
    c0 = cpu_seconds();
    status = rps3_sim_advance(s, &ctl, ticks / RATE_HZ);
    c1 = cpu_seconds();
    if (status != RPS3_OK) goto fail_sim;
    printf("the same run as one rps3_sim_advance call: CPU %.3g s (%.0fx "
           "real time)\n",
           c1 - c0, seconds / (c1 - c0 > 0 ? c1 - c0 : 1e-9));
  }
  rps3_ctrl_free(c);
  rps3_sim_free(s);
  return 0;

fail_sim:
  fprintf(stderr, "simulation stopped at t = %g s: %s: %s\n", rps3_sim_now(s)->failed_at,
          rps3_strerror(rps3_sim_now(s)->status), rps3_sim_data(s)->err.msg);
  rps3_ctrl_free(c);
  rps3_sim_free(s);
  return 1;
fail_chk:
  fprintf(stderr, "setup: %s\n", chk.msg);
  rps3_ctrl_free(c);
  rps3_sim_free(s);
  return 1;
}
