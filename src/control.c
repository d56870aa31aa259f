/*
 * control.c - the controllers shipped with the library: open loop (inverse
 * dynamics of the desired motion), PD on the link lengths, PD + gravity
 * compensation, computed torque.  Each has its own model of the mechanism
 * and two workspaces allocated once: the desired motion, and the measured
 * state.
 */
#include <stdlib.h>
#include <string.h>

#include "control.h"

static const char *const CTRL_NAME[RPS3_NCTRL] = {
    "open_loop", "pd", "pd_gravity", "computed_torque"};

const char *rps3_ctrl_name(int kind) {
  if (kind < 0 || kind >= RPS3_NCTRL) return NULL;
  return CTRL_NAME[kind];
}

int rps3_ctrl_index(const char *name) {
  return rps3_name_lookup(CTRL_NAME, RPS3_NCTRL, name);
}

int rps3_ctrl_alloc(rps3_ctrl_kind kind, double kp, double kd,
                    const rps3_model *model, const rps3_traj *traj,
                    rps3_ctrl **out, rps3_check *chk) {
  rps3_ctrl *c;
  int st, k;
  rps3_check_clear(chk);
  if (out == NULL) {
    if (chk != NULL) snprintf(chk->msg, sizeof chk->msg, "out is NULL");
    return RPS3_EINVAL;
  }
  *out = NULL;
  if (model == NULL || !model->valid || traj == NULL) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "controller model not initialised, or no trajectory");
    return RPS3_EINVAL;
  }
  /* the kind and the gains are not rows of RPS3_FIELDS: chk->field -1 */
  if ((int)kind < 0 || (int)kind >= RPS3_NCTRL) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "simulate.controller = %d: unknown kind", kind);
    return RPS3_EINVAL;
  }
  if (!(isfinite(kp) && kp >= 0) || !(isfinite(kd) && kd >= 0)) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg, "%s = %.17g: must be finite and >= 0",
               isfinite(kp) && kp >= 0 ? "simulate.kd" : "simulate.kp",
               isfinite(kp) && kp >= 0 ? kd : kp);
    return RPS3_EINVAL;
  }
  /* the trajectory's own check, its field by identifier */
  st = rps3_traj_check(model, traj, chk);
  if (st != RPS3_OK) return st;
  c = (rps3_ctrl *)calloc(1, sizeof(*c));
  if (c == NULL) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg, "out of memory: the controller");
    return RPS3_ENOMEM;
  }
  c->kind = kind;
  c->kp = kp;
  c->kd = kd;
  c->model = *model;
  c->traj = *traj;
  c->t = (double)NAN;
  c->t_meas = (double)NAN;
  for (k = 0; k < 3; k++) c->l_des[k] = c->dl_des[k] = c->F_ff[k] = (double)NAN;
  c->fd = (rps3_fd_state *)calloc(1, sizeof(*c->fd));
  if (c->fd == NULL || rps3_data_alloc(&c->model, &c->des) != RPS3_OK ||
      rps3_data_alloc(&c->model, &c->meas) != RPS3_OK) {
    rps3_ctrl_free(c);
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "out of memory: the controller's workspaces");
    return RPS3_ENOMEM;
  }
  *out = c;
  return RPS3_OK;
}

void rps3_ctrl_free(rps3_ctrl *c) {
  if (c == NULL) return;
  rps3_data_free(c->des);
  rps3_data_free(c->meas);
  free(c->fd);
  free(c);
}

/* desired motion at t (after the span the final pose at rest): lengths,
   rates and accelerations by the closed form; the feedforward forces of
   the inverse dynamics only for the open loop, the one law that applies
   them (the others leave F_ff NaN) */
static int desired(rps3_ctrl *c, double t) {
  rps3_data *d = c->des;
  rps3_pose_trig trig;
  double T = rps3_traj_duration(&c->traj);
  int st, rest = t > T;
  st = rps3_traj_eval(&c->model, &c->traj, rest ? T : (t < 0 ? 0 : t), d->pose,
                      d->dpose, d->ddpose);
  if (st != RPS3_OK) return st;
  if (rest) {
    memset(d->dpose, 0, sizeof(d->dpose));
    memset(d->ddpose, 0, sizeof(d->ddpose));
  }
  if (c->kind == RPS3_CTRL_OPEN_LOOP) {
    st = rps3_inverse(&c->model, d);
    if (st != RPS3_OK) return st;
    v3_copy(c->F_ff, d->F);
    if (!(d->stage & RPS3_STAGE_POS)) {
      /* the leanest pass (outputs = RPS3_OUT_FORCES) forms F alone: the
         desired link motion by the closed form */
      st = rps3_link_motion(&c->model, d, 0);
      if (st != RPS3_OK) return st;
    } else if (!rps3_need_rates(&c->model)) {
      /* a static model's forces need no rates, and rps3_inverse computes
         none; the controller still tracks the desired link rates */
      st = rps3_ik(&c->model, d);
      if (st == RPS3_OK) st = rps3_velocity(&c->model, d);
      if (st != RPS3_OK) return st;
    }
  } else if (c->meas->have_theta) {
    /* the lengths and their rates alone (computed torque: and their
       accelerations), by the derivatives of l^2 = |b - P|^2 */
    st = rps3_link_motion(&c->model, d, c->kind == RPS3_CTRL_COMPUTED_TORQUE);
    if (st != RPS3_OK) return st;
    c->F_ff[0] = c->F_ff[1] = c->F_ff[2] = (double)NAN;
  } else {
    /* theta of the desired motion starts the first measured solve */
    st = rps3_ik_with(&c->model, d, &trig, RPS3_IK_THETA, NULL);
    if (st == RPS3_OK) st = rps3_velocity_with(&c->model, d, &trig);
    if (st == RPS3_OK && c->kind == RPS3_CTRL_COMPUTED_TORQUE)
      st = rps3_acceleration_with(&c->model, d, &trig);
    if (st != RPS3_OK) return st;
    c->F_ff[0] = c->F_ff[1] = c->F_ff[2] = (double)NAN;
  }
  v3_copy(c->l_des, d->l);
  v3_copy(c->dl_des, d->dl);
  return RPS3_OK;
}

/*
 * The start of the theta solve at the measured lengths l, time t: the last
 * measured state's root moved along its motion,
 *   theta + G (l - l_last) + (1/2) theta''_bias dt^2,
 * exact in the length change (the measured l need not follow the last
 * rates) and, for computed torque, second order in time: theta'' = G l''
 * + theta''_bias, so the part of theta'' that the length change does not
 * already carry is the velocity product theta''_bias of the last state
 * (PD + gravity evaluates at rest, where it is zero: first order).  Not
 * taken without a last state or over a step of more than
 * RPS3_FD_PREDICT_MAX: the last root is the start then.
 */
static void predict_theta(rps3_ctrl *c, const double l[3], double t) {
  const rps3_fd_state *k = c->fd;
  rps3_data *d = c->meas;
  const double dt = t - c->t_meas;
  if (!(dt > 0.0 && dt < HUGE_VAL)) return;
  /* the theta solve's root predictor along the last rates, tau = dt */
  rps3_theta_predict(d->theta, l, k->l, d->theta, M3C(k->G), k->ddth_b, dt,
                     RPS3_FD_PREDICT_MAX);
}

/*
 * The controller's model's inverse dynamics at the measured (l, dl) and
 * the given ddl at time t, F = Mq ddl + hq: the joint-space form of (23),
 * whose forces are rps3_invdyn's (tests/test_fwddyn.c holds the two
 * together, and tests/test_control.c the controllers to rps3_invdyn).
 * Positions from the theta solve of rps3_fwddyn_state (Newton from the
 * predicted start, rps3_fk when it fails), which reports the singular
 * configurations as rps3_invdyn would (RPS3_ESING past opt.cond_max); the
 * first start is the desired motion's theta.  With the plant's state
 * offered at the tick (plant, not NULL: rps3_ctrl_update_plant), the same
 * positions and maps from there when rps3_fwddyn_state_shared accepts them
 * for this model: the controller decides what it takes of the plant.
 */
static int invdyn_at(rps3_ctrl *c, double t, const double l[3],
                     const double dl[3], const double ddl[3],
                     const rps3_plant_state *plant, double F[3]) {
  rps3_data *d = c->meas;
  double x[3];
  /* the mode of the last state that succeeded (0 before one), so that a
     change through a failed tick is flagged too */
  const int mode0 = c->fd->mode;
  int st, i, had = isfinite(c->t_meas);
  c->t_meas = (double)NAN;
  v3_copy(d->l, l);
  v3_copy(d->dl, dl);
  /* in a simulation whose plant has this model's geometry, at the
     plant's state (an exact measurement): the plant's kinematics, this
     model's masses, effects and limits */
  if (plant == NULL || !rps3_fwddyn_state_shared(
                           &c->model, d, c->fd, plant->model, plant->fd, &st)) {
    if (!d->have_theta) {
      v3_copy(d->theta, c->des->theta);
      d->have_theta = 1;
    } else if (had) {
      predict_theta(c, l, t);
    }
    st = rps3_fwddyn_state(
        &c->model, d, c->fd,
        RPS3_FD_LEAN | RPS3_FD_NOFACTOR | (had ? RPS3_FD_TRIG : 0));
  }
  if (st != RPS3_OK) return st;
  if (mode0 != RPS3_MODE_ANY && d->mode != mode0) d->warn |= RPS3_WARN_MODE;
  m3_mulv(x, M3C(d->Mq), ddl);
  v3_axpy(x, x, 1.0, d->hq);
  if (!v3_finite(x)) {
    d->err.code = RPS3_ERANGE;
    snprintf(d->err.msg, sizeof(d->err.msg),
             "controller force (%g, %g, %g) N is not finite", x[0], x[1], x[2]);
    return RPS3_ERANGE;
  }
  for (i = 0; i < 3; i++) {
    d->ddl[i] = ddl[i];
    F[i] = d->F[i] = x[i];
  }
  c->t_meas = t;
  return RPS3_OK;
}

/* RPS3_EINVAL with meas's message when a measurement is not finite (a
   sensor glitch): no law may turn it into a force */
static int measured_finite(rps3_ctrl *c, const double l[3],
                           const double dl[3]) {
  int i;
  for (i = 0; i < 6; i++) {
    double x = i < 3 ? l[i] : dl[i - 3];
    if (!isfinite(x)) {
      c->meas->err.code = RPS3_EINVAL;
      snprintf(c->meas->err.msg, sizeof(c->meas->err.msg),
               "measured %s%d = %g %s is not finite", i < 3 ? "l" : "dl",
               i % 3 + 1, x, i < 3 ? "m" : "m/s");
      return RPS3_EINVAL;
    }
  }
  return RPS3_OK;
}

/* RPS3_ERANGE with meas's message when a law's force is not finite
   (finite inputs whose products overflow, e.g. gains near 1e308) */
static int force_finite(rps3_ctrl *c, const double F[3]) {
  if (v3_finite(F)) return RPS3_OK;
  c->meas->err.code = RPS3_ERANGE;
  snprintf(c->meas->err.msg, sizeof(c->meas->err.msg),
           "controller force (%g, %g, %g) N is not finite", F[0], F[1], F[2]);
  return RPS3_ERANGE;
}

int rps3_ctrl_update(void *state, double t, const double l[3],
                     const double dl[3], double F[3]) {
  return rps3_ctrl_update_plant(state, t, l, dl, NULL, F);
}

rps3_controller rps3_ctrl_bind(rps3_ctrl *c, double rate) {
  rps3_controller ctl;
  memset(&ctl, 0, sizeof(ctl));
  ctl.fn = rps3_ctrl_update;
  ctl.state = c;
  ctl.rate = rate;
  ctl.caps = RPS3_CTRL_USES_PLANT;
  ctl.fn_plant = rps3_ctrl_update_plant;
  return ctl;
}

int rps3_ctrl_update_plant(void *state, double t, const double l[3],
                           const double dl[3], const rps3_plant_state *plant,
                           double F[3]) {
  rps3_ctrl *c = (rps3_ctrl *)state;
  const double zero[3] = {0, 0, 0};
  double e[3], de[3], a[3], G[3];
  int st, i;
  if (c == NULL || l == NULL || dl == NULL || F == NULL) return RPS3_EINVAL;
  if ((int)c->kind < 0 || (int)c->kind >= RPS3_NCTRL || c->meas == NULL ||
      c->des == NULL || c->fd == NULL)
    return RPS3_EINVAL;
  c->meas->err.code = RPS3_OK;
  c->meas->err.msg[0] = '\0';
  if (!isfinite(t)) {
    c->meas->err.code = RPS3_EINVAL;
    snprintf(c->meas->err.msg, sizeof(c->meas->err.msg),
             "time t = %g s is not finite", t);
    return RPS3_EINVAL;
  }
  st = measured_finite(c, l, dl);
  if (st != RPS3_OK) return st;
  c->t = t;
  st = desired(c, t);
  if (st != RPS3_OK) return st;
  for (i = 0; i < 3; i++) {
    e[i] = c->l_des[i] - l[i];
    de[i] = c->dl_des[i] - dl[i];
  }
  switch (c->kind) {
  case RPS3_CTRL_OPEN_LOOP: v3_copy(F, c->F_ff); break;
  case RPS3_CTRL_PD:
    for (i = 0; i < 3; i++) F[i] = c->kp * e[i] + c->kd * de[i];
    break;
  case RPS3_CTRL_PD_GRAVITY:
    /* static forces of the model: at rest only the weights remain */
    st = invdyn_at(c, t, l, zero, zero, plant, G);
    if (st != RPS3_OK) return st;
    for (i = 0; i < 3; i++) F[i] = c->kp * e[i] + c->kd * de[i] + G[i];
    break;
  case RPS3_CTRL_COMPUTED_TORQUE:
  default:
    for (i = 0; i < 3; i++)
      a[i] = c->des->ddl[i] + c->kp * e[i] + c->kd * de[i];
    return invdyn_at(c, t, l, dl, a, plant, F);
  }
  return force_finite(c, F);
}

int rps3_ctrl_last(const rps3_ctrl *c, double *t, double l_des[3],
                   double dl_des[3], double F_ff[3]) {
  const double nan = (double)NAN;
  int k;
  if (t != NULL) *t = c ? c->t : nan;
  for (k = 0; k < 3; k++) {
    if (l_des != NULL) l_des[k] = c ? c->l_des[k] : nan;
    if (dl_des != NULL) dl_des[k] = c ? c->dl_des[k] : nan;
    if (F_ff != NULL) F_ff[k] = c ? c->F_ff[k] : nan;
  }
  return c ? RPS3_OK : RPS3_EINVAL;
}

const rps3_data *rps3_ctrl_desired(const rps3_ctrl *c) {
  return c ? c->des : NULL;
}

const rps3_data *rps3_ctrl_measured(const rps3_ctrl *c) {
  return c ? c->meas : NULL;
}
