/*
 * control.h - the library controller (rps3_ctrl, opaque in rps3.h):
 * what src/control.c keeps between ticks.  Internal.
 */
#ifndef RPS3_CONTROL_H
#define RPS3_CONTROL_H

#include "fwddyn.h"

struct rps3_ctrl {
  rps3_ctrl_kind kind;
  double kp, kd;    /* gains, units of rps3.h */
  rps3_model model; /* the controller's model (a copy, initialised) */
  rps3_traj traj;   /* desired motion (a copy) */
  /* last tick, for logging (rps3_ctrl_last) */
  double t;         /* time of the last call [s], NaN before */
  double l_des[3];  /* desired lengths [m] */
  double dl_des[3]; /* desired rates [m/s] */
  double F_ff[3];   /* feedforward forces of the desired motion [N]:
                       open loop only (NaN for the others) */
  rps3_data *des;   /* workspace of the desired motion */
  rps3_data *meas;  /* workspace at the measured state; its err says
                       why a call failed */
  double t_meas;    /* time of meas's last solved state [s], NaN: none */
  struct rps3_fd_state *fd; /* the model's state at the last measured one
                               (owned) */
};

#endif /* RPS3_CONTROL_H */
