/*
 * sim.h - what src/sim.c (the run) and src/sim_setup.c (the set-up) of a
 * simulation share: the GSL side of rps3_sim and the right-hand side of
 * y' = f(t, y) that the set-up hands to GSL.  Internal.
 */
#ifndef RPS3_SIM_H
#define RPS3_SIM_H

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "fwddyn.h"

#define NY 8 /* l[3], dl[3], W_F, W_f */

struct rps3_sim_gsl {
  gsl_odeiv2_system sys;
  gsl_odeiv2_driver *drv;  /* adaptive methods: stepper, control, evolve */
  gsl_odeiv2_step *stp;    /* the driver's stepper, which fixed-step
                              methods call alone (the driver would reject
                              steps on their error estimate) */
  double yerr[NY];         /* the fixed stepper's error estimate, unused */
  double k[4][NY], ys[NY]; /* stages of the classical RK4 */
  int fixed;               /* 1: fixed-step method */
  /* the plant's state part (Mq, hq, maps) at (l, dl) = ky, valid while
     have_k: an evaluation at the same state with another force (the
     next period's first stage after settle) only solves with Mq */
  rps3_fd_state fd;
  double ky[6];
  int have_k;
  int lean_k;   /* 1: that state has no pose, no pose rates */
  int reported; /* 1: d, T, P and the energy residual describe
                   the state at s->t (settle, report_end) */
};

/* the simulation (opaque in rps3.h): the report the caller reads, the
   plant and its workspace, the run's own state */
struct rps3_sim {
  rps3_sim_report now; /* rps3_sim_now */
  rps3_model plant;    /* the simulated mechanism (a copy) */
  rps3_sim_options opt;
  rps3_data *d;                /* plant workspace (rps3_sim_data) */
  const rps3_controller *ctrl; /* during rps3_sim_advance */
  double t0;                   /* start time [s] */
  long last_tick;              /* index of the last tick served, -1 before */
  unsigned long long rng;      /* noise generator state */
  double spare;                /* second normal deviate of Box-Muller, or NaN */
  int started;
  struct rps3_sim_gsl *gsl;
};

/* f(t, y) of y = (l, dl, W_F, W_f), and its Jacobian by forward
   differences for the implicit methods (GSL's calling conventions) */
/* sensors and actuators (src/sim_measure.c): x as measured (noise of
   deviation sigma, quantum q; 0 for none), and Fc clamped to opt.fmax into
   F (returns 1 when one saturated) */
double rps3_sim_measure(rps3_sim *s, double x, double sigma, double q);
int rps3_sim_saturate(const rps3_sim *s, const double Fc[3], double F[3]);

int rps3_sim_rhs(double t, const double y[], double dydt[], void *params);
int rps3_sim_jac(double t, const double y[], double *dfdy, double dfdt[],
                 void *params);

#endif /* RPS3_SIM_H */
