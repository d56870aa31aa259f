/*
 * user_law.h - computed torque written as a user would write it, with the
 * public API alone, declaring RPS3_CTRL_USES_PLANT: the law of the
 * library's RPS3_CTRL_COMPUTED_TORQUE (include/rps3.h),
 *   F = Mq(l) a + hq(l, dl),  a = ddl_d + kp (l_d - l) + kd (dl_d - dl),
 * whose Mq and hq are the plant's offered state when the law's model is the
 * plant's (the user says so: plant_is_mine), else its own model's by
 * rps3_fwddyn at the measured state.  The desired motion is
 * rps3_link_motion of the trajectory's pose (after the trajectory's span:
 * its final pose, at rest).  Used by tests/test_sim.c
 * (the same run as the library's law) and by rps3-bench (its speed).
 */
#ifndef RPS3_USER_LAW_H
#define RPS3_USER_LAW_H

#include <string.h>

#include "rps3.h"

typedef struct {
  rps3_model model;  /* the law's model (initialised) */
  rps3_traj traj;    /* desired motion */
  double kp, kd;     /* [1/s^2], [1/s] */
  int plant_is_mine; /* 1: the model is the plant's, take its Mq and hq */
  rps3_data *des;    /* workspace of the desired motion */
  rps3_data *own;    /* the model at the measured state when it solves */
  long offered;      /* calls that were offered the plant's state */
  long solved;       /* calls that solved their own model */
} user_law;

/* the workspaces; 0 or a status */
static int user_law_init(user_law *u, const rps3_model *m,
                         const rps3_traj *tr, double kp, double kd,
                         int plant_is_mine) {
  memset(u, 0, sizeof(*u));
  u->model = *m;
  u->traj = *tr;
  u->kp = kp;
  u->kd = kd;
  u->plant_is_mine = plant_is_mine;
  if (rps3_data_alloc(&u->model, &u->des) != RPS3_OK ||
      rps3_data_alloc(&u->model, &u->own) != RPS3_OK)
    return RPS3_ENOMEM;
  return RPS3_OK;
}

static void user_law_free(user_law *u) {
  rps3_data_free(u->des);
  rps3_data_free(u->own);
}

/* an rps3_control_plant_fn */
static int user_law_update(void *state, double t, const double l[3],
                           const double dl[3], const rps3_plant_state *plant,
                           double F[3]) {
  user_law *u = (user_law *)state;
  rps3_data *d = u->des;
  double T = rps3_traj_duration(&u->traj), a[3], M[3][3], h[3];
  int st, i, j, rest = t > T;
  st = rps3_traj_eval(&u->model, &u->traj, rest ? T : (t < 0 ? 0 : t),
                      d->pose, d->dpose, d->ddpose);
  if (st != RPS3_OK) return st;
  if (rest)
    for (i = 0; i < 3; i++) d->dpose[i] = d->ddpose[i] = 0.0;
  st = rps3_link_motion(&u->model, d, 1);
  if (st != RPS3_OK) return st;
  for (i = 0; i < 3; i++)
    a[i] = d->ddl[i] + u->kp * (d->l[i] - l[i]) + u->kd * (d->dl[i] - dl[i]);
  if (plant != NULL && u->plant_is_mine) {
    u->offered++;
    for (i = 0; i < 3; i++) {
      for (j = 0; j < 3; j++) M[i][j] = plant->Mq[3 * i + j];
      h[i] = plant->hq[i];
    }
  } else {
    rps3_data *o = u->own;
    u->solved++;
    for (i = 0; i < 3; i++) {
      o->l[i] = l[i];
      o->dl[i] = dl[i];
      o->F[i] = 0.0;
    }
    st = rps3_fwddyn(&u->model, o);
    if (st != RPS3_OK) return st;
    memcpy(M, o->Mq, sizeof(M));
    memcpy(h, o->hq, sizeof(h));
  }
  for (i = 0; i < 3; i++)
    F[i] = M[i][0] * a[0] + M[i][1] * a[1] + M[i][2] * a[2] + h[i];
  return RPS3_OK;
}

/* the controller of u at rate [Hz], with its capability */
static rps3_controller user_law_controller(user_law *u, double rate) {
  rps3_controller c = {NULL, NULL, 0.0, 0u, NULL};
  c.state = u;
  c.rate = rate;
  c.caps = RPS3_CTRL_USES_PLANT;
  c.fn_plant = user_law_update;
  return c;
}

#endif /* RPS3_USER_LAW_H */
