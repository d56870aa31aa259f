/*
 * sim.c - the plant in time: y = (l, dl, W_F, W_f) integrated by GSL odeiv2
 * with the accelerations of rps3_fwddyn, forces from a controller at a fixed
 * rate with zero-order hold (or continuous), measured lengths with seeded
 * noise and quantisation, and the energy balance of the run.
 *
 * All memory (the plant data, GSL's stepper, control and evolve objects)
 * is allocated by rps3_sim_alloc; GSL's drivers allocate nothing while
 * stepping.  Failures inside the right-hand side are recorded in the
 * simulation and reported to GSL as GSL_EBADFUNC, which makes its driver
 * return at once with the state of the last completed step.  The set-up
 * (options, allocation) is src/sim_setup.c, the sensors and actuators
 * (noise, quantisation, saturation) src/sim_measure.c.
 */
#include <string.h>

#include "sim.h"

/* times closer than this many control periods are the same instant: far
   above the rounding of t0 + k / rate for any run, far below a step */
#define TICK_SLACK 1e-6

/* ------------------------------------------------------- equations */

/* y[0..5] is the state (l, dl) of ky, bit for bit (-0 == +0: the same
   value) */
static int same_state(const double ky[6], const double y[]) {
  int i;
  for (i = 0; i < 6; i++)
    if (!(ky[i] == y[i])) return 0;
  return 1;
}

/* the controller's law as its type declares it: with
   RPS3_CTRL_USES_PLANT fn_plant, with the plant's state or NULL */
static int call_law(const rps3_controller *c, double t, const double l[3],
                    const double dl[3], const rps3_plant_state *plant,
                    double F[3]) {
  if (c->caps & RPS3_CTRL_USES_PLANT)
    return c->fn_plant(c->state, t, l, dl, plant, F);
  return c->fn(c->state, t, l, dl, F);
}

/* 1: the measurement is the state (no noise, no quantisation) */
static int exact_measurement(const rps3_sim *s) {
  return !(s->opt.noise_l > 0.0 || s->opt.noise_dl > 0.0 ||
           s->opt.quant_l > 0.0 || s->opt.quant_dl > 0.0);
}

/* 1: the run's controller is offered the plant's state at its ticks,
   which the run then keeps (RPS3_FD_KEEP) at the end of each period */
static int keeps_plant(const rps3_sim *s) {
  const rps3_controller *c = s->ctrl;
  return c != NULL && (c->caps & RPS3_CTRL_USES_PLANT) && c->rate > 0.0 &&
         exact_measurement(s);
}

/* the plant's state part at y = (l, dl) into s->gsl->fd, unless the kept
   one is y's (with what lean and keep ask for) already */
static int plant_state(rps3_sim *s, const double y[], int lean, int keep) {
  struct rps3_sim_gsl *g = s->gsl;
  rps3_data *d = s->d;
  int st, i;
  for (i = 0; i < 3; i++) {
    d->l[i] = y[i];
    d->dl[i] = y[3 + i];
  }
  if (g->have_k && same_state(g->ky, y) && (lean || !g->lean_k) &&
      (!keep || g->fd.have_kin))
    return RPS3_OK;
  /* the last state, when it succeeded, predicts this one's theta */
  st = rps3_fwddyn_state(&s->plant, d, &g->fd,
                         (g->have_k ? RPS3_FD_PREDICT | RPS3_FD_TRIG : 0) |
                             (lean ? RPS3_FD_LEAN | RPS3_FD_SCRATCH : 0) |
                             (keep ? RPS3_FD_KEEP : 0));
  g->have_k = 0;
  if (st == RPS3_OK) {
    memcpy(g->ky, y, sizeof(g->ky));
    g->have_k = 1;
    g->lean_k = lean;
  }
  return st;
}

/* the plant at (t, y): forces (continuous controller), accelerations,
   mode; lean: for an integrator's stage (no pose, no pose rates); returns
   the status and records a failure */
static int evaluate(rps3_sim *s, double t, const double y[], int lean,
                    int keep) {
  rps3_data *d = s->d;
  int st;
  if (s->ctrl != NULL && s->ctrl->rate == 0.0) {
    /* a continuous law is offered no plant state: it acts before it */
    st = call_law(s->ctrl, t, y, y + 3, NULL, s->now.F_cmd);
    if (st != RPS3_OK) {
      if (d->err.code != st)
        snprintf(d->err.msg, sizeof(d->err.msg),
                 "controller returned %d (%s) at t = %.9g s", st,
                 rps3_strerror(st), t);
      d->err.code = st;
      return st;
    }
    rps3_sim_saturate(s, s->now.F_cmd, s->now.F);
  }
  st = plant_state(s, y, lean, keep);
  v3_copy(d->F, s->now.F);
  if (st == RPS3_OK) st = rps3_fwddyn_accel(&s->plant, d, &s->gsl->fd);
  s->now.nevals++;
  if (st != RPS3_OK) return st;
  if (d->mode != s->now.mode) {
    /* the mode is the sign of det df/dtheta: it changes only across the
       singular surface */
    d->ddl[0] = d->ddl[1] = d->ddl[2] = (double)NAN;
    d->err.code = RPS3_ESING;
    snprintf(d->err.msg, sizeof(d->err.msg),
             RPS3_SING_PREFIX
             "det df/dtheta changed sign, assembly "
             "mode %+d to %+d (theta = %.6g, %.6g, %.6g)",
             s->now.mode, d->mode, d->theta[0], d->theta[1], d->theta[2]);
    return RPS3_ESING;
  }
  return RPS3_OK;
}

/* a failure at the singular surface (RPS3_ESING, "singular configuration:
   ..." from the forward dynamics' state) says when: "singular
   configuration at t = T s: ..."; the message is cut to its buffer */
static void sing_at(rps3_sim *s, int status, double t) {
  static const char pre[] = RPS3_SING_PREFIX;
  rps3_error *e = &s->d->err;
  char rest[sizeof(e->msg)];
  if (status != RPS3_ESING || strncmp(e->msg, pre, sizeof(pre) - 1) != 0)
    return;
  memcpy(rest, e->msg + sizeof(pre) - 1, sizeof(rest) - (sizeof(pre) - 1));
  rest[sizeof(rest) - sizeof(pre)] = '\0';
  /* "%.200s": the bound that the buffer holds with the time */
  snprintf(e->msg, sizeof(e->msg),
           "singular configuration at t = %.9g s: %.200s", t, rest);
}

int rps3_sim_rhs(double t, const double y[], double dydt[], void *params) {
  rps3_sim *s = (rps3_sim *)params;
  rps3_data *d = s->d;
  double fric = 0.0;
  int st, i;
  st = evaluate(s, t, y, 1, 0);
  if (st != RPS3_OK) {
    sing_at(s, st, t);
    s->now.status = st;
    s->now.failed_at = t;
    return GSL_EBADFUNC;
  }
  if (s->plant.opt.effects & RPS3_EFF_PIN_FRICTION)
    for (i = 0; i < 3; i++)
      fric += rps3_friction_torque(&s->plant, i, d->dtheta[i]) * d->dtheta[i];
  if (s->plant.opt.effects & RPS3_EFF_PRISMATIC_FRICTION)
    for (i = 0; i < 3; i++)
      fric -= rps3_friction_law(&s->plant.leg[i].prismatic, y[3 + i]) *
              y[3 + i];
  for (i = 0; i < 3; i++) {
    dydt[i] = y[3 + i];
    dydt[3 + i] = d->ddl[i];
  }
  dydt[6] = v3_dot(d->F, y + 3);
  dydt[7] = fric;
  return GSL_SUCCESS;
}

/* Jacobian for the implicit methods by forward differences, NY extra
   evaluations; dfdt = 0 within a control period (held forces), and for a
   continuous controller its time dependence is left to the corrector */
int rps3_sim_jac(double t, const double y[], double *dfdy, double dfdt[],
                 void *params) {
  double f0[NY], f1[NY], yp[NY];
  int i, j, st;
  st = rps3_sim_rhs(t, y, f0, params);
  if (st != GSL_SUCCESS) return st;
  memcpy(yp, y, sizeof(yp));
  for (j = 0; j < NY; j++) {
    /* sqrt(eps) relative step, with the scale of a length or a rate */
    double h = 1.4901161193847656e-8 * fmax(fabs(y[j]), j < 3 ? 0.1 : 0.01);
    yp[j] = y[j] + h;
    st = rps3_sim_rhs(t, yp, f1, params);
    yp[j] = y[j];
    if (st != GSL_SUCCESS) return st;
    for (i = 0; i < NY; i++) dfdy[i * NY + j] = (f1[i] - f0[i]) / h;
  }
  for (i = 0; i < NY; i++) dfdt[i] = 0.0;
  return GSL_SUCCESS;
}

/* T and P of the state at s->now.t (the plant data was just evaluated there) */
static void update_energy(rps3_sim *s) {
  rps3_energy(&s->plant, s->d, &s->now.T, &s->now.P, NULL);
  s->now.energy_residual =
      s->now.T + s->now.P - s->now.E0 - s->now.y[6] - s->now.y[7];
}

static int fail(rps3_sim *s, int status, double t) {
  if (s->now.status == RPS3_OK) sing_at(s, status, t);
  s->now.status = status;
  s->now.failed_at = t;
  return status;
}

int rps3_sim_start(rps3_sim *s, double t0, const double pose[3],
                   const double dpose[3]) {
  rps3_data *d;
  int st, i;
  if (s == NULL || pose == NULL || dpose == NULL || !isfinite(t0))
    return RPS3_EINVAL;
  d = s->d;
  rps3_data_reset(d);
  s->now.t = s->t0 = t0;
  s->now.nsteps = s->now.nevals = s->now.nticks = s->now.nsat = 0;
  s->last_tick = -1;
  s->rng = (unsigned long long)s->opt.seed;
  s->spare = (double)NAN;
  s->ctrl = NULL;
  s->now.status = RPS3_OK;
  s->now.failed_at = (double)NAN;
  s->started = 0;
  s->gsl->have_k = 0;
  memset(s->now.F, 0, sizeof(s->now.F));
  memset(s->now.F_cmd, 0, sizeof(s->now.F_cmd));
  /* the closed form fixes the assembly mode; the solve tracks it on */
  v3_copy(d->pose, pose);
  v3_copy(d->dpose, dpose);
  st = rps3_ik(&s->plant, d);
  if (st == RPS3_OK) st = rps3_velocity(&s->plant, d);
  if (st != RPS3_OK) return fail(s, st, t0);
  d->have_theta = 1;
  for (i = 0; i < 3; i++) {
    s->now.y[i] = s->now.l_meas[i] = d->l[i];
    s->now.y[3 + i] = s->now.dl_meas[i] = d->dl[i];
  }
  s->now.y[6] = s->now.y[7] = 0.0;
  /* the mode the run must keep: evaluate once, with zero forces */
  v3_copy(d->F, s->now.F);
  st = rps3_fwddyn(&s->plant, d);
  if (st != RPS3_OK) return fail(s, st, t0);
  s->now.mode = d->mode;
  rps3_energy(&s->plant, d, &s->now.T, &s->now.P, NULL);
  s->now.E0 = s->now.T + s->now.P;
  s->now.energy_residual = 0.0;
  s->gsl->reported = 1;
  s->started = 1;
  return RPS3_OK;
}

/* the plant's state at a tick for a controller that declares
   RPS3_CTRL_USES_PLANT, into *v: the state the run keeps at s->now.y (settle's,
   which the next period's first stage reuses; evaluated here at a run's
   first tick, where the first stage then reuses it); NULL when the
   measurement is not the state (noise, quantisation) */
static const rps3_plant_state *offer_plant(rps3_sim *s, rps3_plant_state *v,
                                           int *status) {
  const rps3_fd_state *k = &s->gsl->fd;
  *status = RPS3_OK;
  if (!keeps_plant(s)) return NULL;
  *status = plant_state(s, s->now.y, 1, 1);
  if (*status != RPS3_OK) return NULL;
  v->model = &s->plant;
  v->t = s->now.t;
  v3_copy(v->l, k->kin.q.l);
  v3_copy(v->dl, k->kin.dl);
  v3_copy(v->theta, k->th);
  v3_copy(v->dtheta, k->kin.dth);
  memcpy(v->Mq, k->Mq, sizeof(v->Mq));
  v3_copy(v->hq, k->hq);
  v->mode = k->mode;
  v->fd = k;
  return v;
}

/* the controller at a tick, from the measured state; a controller that
   declares RPS3_CTRL_USES_PLANT is offered the plant's state there */
static int tick(rps3_sim *s, const rps3_controller *c) {
  rps3_plant_state view;
  const rps3_plant_state *plant = NULL;
  int st, i;
  for (i = 0; i < 3; i++) {
    s->now.l_meas[i] =
        rps3_sim_measure(s, s->now.y[i], s->opt.noise_l, s->opt.quant_l);
    s->now.dl_meas[i] =
        rps3_sim_measure(s, s->now.y[3 + i], s->opt.noise_dl, s->opt.quant_dl);
  }
  if (c->caps & RPS3_CTRL_USES_PLANT) {
    plant = offer_plant(s, &view, &st);
    if (st != RPS3_OK) return fail(s, st, s->now.t);
  }
  st =
      call_law(c, s->now.t, s->now.l_meas, s->now.dl_meas, plant, s->now.F_cmd);
  s->now.nticks++;
  if (st != RPS3_OK) {
    s->d->err.code = st;
    snprintf(s->d->err.msg, sizeof(s->d->err.msg),
             "controller returned %d (%s) at t = %.9g s", st, rps3_strerror(st),
             s->now.t);
    return fail(s, st, s->now.t);
  }
  for (i = 0; i < 3; i++)
    if (!isfinite(s->now.F_cmd[i])) {
      s->d->err.code = RPS3_EINVAL;
      snprintf(s->d->err.msg, sizeof(s->d->err.msg),
               "controller force F%d = %g at t = %.9g s", i + 1,
               s->now.F_cmd[i], s->now.t);
      return fail(s, RPS3_EINVAL, s->now.t);
    }
  s->now.nsat += rps3_sim_saturate(s, s->now.F_cmd, s->now.F);
  return RPS3_OK;
}

/*
 * One step of the classical Runge-Kutta method, four evaluations.  GSL's
 * rk4 stepper estimates its error by step doubling, twelve evaluations a
 * step, an estimate a fixed-step real-time run has no use for; its other
 * methods are used as they are.
 */
static int rk4_step(rps3_sim *s, double t, double h) {
  struct rps3_sim_gsl *g = s->gsl;
  static const double c[4] = {0.0, 0.5, 0.5, 1.0};
  int j, i, st;
  st = rps3_sim_rhs(t, s->now.y, g->k[0], s);
  for (j = 1; j < 4 && st == GSL_SUCCESS; j++) {
    const double ch = c[j] * h;
    for (i = 0; i < NY; i++) g->ys[i] = s->now.y[i] + ch * g->k[j - 1][i];
    st = rps3_sim_rhs(t + ch, g->ys, g->k[j], s);
  }
  if (st != GSL_SUCCESS) return st;
  for (i = 0; i < NY; i++)
    s->now.y[i] +=
        h / 6.0 *
        (g->k[0][i] + 2.0 * g->k[1][i] + 2.0 * g->k[2][i] + g->k[3][i]);
  return GSL_SUCCESS;
}

/*
 * An integrator that gave up at (t, y) with no evaluation failing (GSL's
 * implicit iteration diverging, an adaptive step shrinking to nothing)
 * may have stopped short of the singular surface, where the solution's
 * derivatives grow without bound.  The same criterion as every
 * evaluation decides, at the end of one step h (opt.h: the fixed step,
 * or the adaptive methods' first guess) of y's Taylor polynomial, l + h
 * l' + h^2 l'' / 2: RPS3_ESING with that evaluation's message when it
 * lies past the surface, else RPS3_OK (the integrator's own failure
 * stands).  d's theta and mode are those of y again afterwards.
 */
static int stopped_short(rps3_sim *s, double t) {
  rps3_data *d = s->d;
  const double h = s->opt.h;
  double yp[NY], th[3], ddl[3];
  const int mode = d->mode, have = d->have_theta;
  int st, i;
  v3_copy(th, d->theta);
  s->gsl->have_k = 0;
  if (evaluate(s, t, s->now.y, 1, 0) != RPS3_OK) return RPS3_OK;
  v3_copy(ddl, d->ddl);
  memcpy(yp, s->now.y, sizeof(yp));
  for (i = 0; i < 3; i++) {
    yp[i] += h * s->now.y[3 + i] + 0.5 * h * h * ddl[i];
    yp[3 + i] += h * ddl[i];
  }
  st = evaluate(s, t + h, yp, 1, 0);
  s->gsl->have_k = 0;
  v3_copy(d->theta, th);
  d->mode = mode;
  d->have_theta = have;
  return st == RPS3_ESING ? st : RPS3_OK;
}

/* integrate y from s->now.t to t1 with the forces as they are */
static int integrate(rps3_sim *s, double t1) {
  struct rps3_sim_gsl *g = s->gsl;
  double t = s->now.t, span = t1 - s->now.t;
  int st;
  if (!(span > 0.0)) return RPS3_OK;
  if (g->fixed) {
    /* the largest step <= h that divides the span evenly; a span longer
       than n h by rounding only (t1 - t loses digits as t grows) is n */
    double n = fmax(1.0, ceil(span / s->opt.h - TICK_SLACK));
    if (n > (double)s->opt.max_steps) {
      s->d->err.code = RPS3_ENOCONV;
      snprintf(s->d->err.msg, sizeof(s->d->err.msg),
               "%.0f steps of h = %g s for %g s exceed max_steps %ld", n,
               s->opt.h, span, s->opt.max_steps);
      return fail(s, RPS3_ENOCONV, s->now.t);
    }
    long k, nk = (long)n;
    double h = span / n;
    /* GSL's stepper (rk4imp) starts afresh: the force may have jumped */
    if (s->opt.integrator != RPS3_INT_RK4) gsl_odeiv2_step_reset(g->stp);
    st = GSL_SUCCESS;
    for (k = 0; k < nk && st == GSL_SUCCESS; k++) {
      /* on failure y stays at the start of the step */
      st = (s->opt.integrator == RPS3_INT_RK4)
               ? rk4_step(s, t, h)
               : gsl_odeiv2_step_apply(g->stp, t, h, s->now.y, g->yerr, NULL,
                                       NULL, &g->sys);
      if (st == GSL_SUCCESS) {
        t = (k + 1 == nk) ? t1 : s->now.t + (double)(k + 1) * h;
        s->now.nsteps++;
      }
    }
  } else {
    /* the force may have jumped at s->now.t: forget the step history */
    gsl_odeiv2_driver_reset(g->drv);
    st = gsl_odeiv2_driver_apply(g->drv, &t, t1, s->now.y);
    s->now.nsteps += (long)g->drv->n;
  }
  /* a failure of the plant or the controller was recorded by rhs, with
     its own message; GSL reports it as GSL_EBADFUNC or, from inside a
     fixed step, as a failure of its own */
  if (st != GSL_SUCCESS) s->now.t = t; /* the last completed step's, y's */
  if (s->now.status != RPS3_OK) return s->now.status;
  if (st != GSL_SUCCESS && stopped_short(s, t) == RPS3_ESING) {
    /* the probe's message, "singular configuration: ...", says what */
    rps3_error *e = &s->d->err;
    char rest[sizeof(e->msg)];
    const size_t np = sizeof(RPS3_SING_PREFIX) - 1;
    memcpy(rest, e->msg + np, sizeof(rest) - np);
    rest[sizeof(rest) - np - 1] = '\0';
    e->code = RPS3_ESING;
    snprintf(e->msg, sizeof(e->msg),
             "singular configuration at t = %.9g s (%s stopped a step of "
             "%g s short): %.160s",
             t, rps3_integrator_name(s->opt.integrator), s->opt.h, rest);
    s->now.status = RPS3_ESING;
    s->now.failed_at = t;
    return RPS3_ESING;
  }
  if (st != GSL_SUCCESS) {
    s->d->err.code = RPS3_ENOCONV;
    snprintf(s->d->err.msg, sizeof(s->d->err.msg),
             "integrator %s stopped at t = %.9g s: %s",
             rps3_integrator_name(s->opt.integrator), t, gsl_strerror(st));
    return fail(s, RPS3_ENOCONV, t);
  }
  s->now.t = t1;
  return RPS3_OK;
}

/* after a segment: the workspace, and the plant data at the new state.
   Within one rps3_sim_advance only the state's part that the next
   period's first stage reuses is evaluated (a lean state); the report
   (positions, pose, pose rates, platform motion, energy), which the caller
   reads after the call alone, is made at the call's last segment
   (`report`) or by report_end when the last segment was not settled */
static int settle(rps3_sim *s, int report) {
  int i, st;
  for (i = 0; i < 3; i++)
    if (!(s->now.y[i] >= s->opt.l_min && s->now.y[i] <= s->opt.l_max)) {
      s->d->err.code = RPS3_EREACH;
      snprintf(s->d->err.msg, sizeof(s->d->err.msg),
               "link %d length %.9g m left the stroke [%g, %g] m at t = "
               "%.9g s",
               i + 1, s->now.y[i], s->opt.l_min, s->opt.l_max, s->now.t);
      return fail(s, RPS3_EREACH, s->now.t);
    }
  st = evaluate(s, s->now.t, s->now.y, !report, keeps_plant(s));
  if (st != RPS3_OK) return fail(s, st, s->now.t);
  s->gsl->reported = report;
  if (report) update_energy(s);
  return RPS3_OK;
}

/* a run stopped inside a call: the report of the state it stopped at
   (s->now.t, s->now.y: the last good one), with the failure's status, time and
   message kept; NaN where that state cannot be evaluated either (the
   controller is not called again) */
static void report_failed(rps3_sim *s) {
  const rps3_error err = s->d->err;
  const rps3_controller *c = s->ctrl;
  const int status = s->now.status;
  const double at = s->now.failed_at;
  rps3_data *d = s->d;
  int i;
  s->ctrl = NULL;
  s->now.status = RPS3_OK;
  if (evaluate(s, s->now.t, s->now.y, 0, 0) == RPS3_OK) {
    update_energy(s);
  } else {
    s->now.T = s->now.P = s->now.energy_residual = (double)NAN;
    rps3_fd_positions_unset(d);
    for (i = 0; i < 3; i++)
      d->pose[i] = d->dpose[i] = d->vc[i] = d->omega[i] = d->ddl[i] =
          (double)NAN;
    d->stage = 0;
  }
  s->gsl->reported = 1;
  d->err = err;
  s->now.status = status;
  s->now.failed_at = at;
  s->ctrl = c;
}

/* the report of the state at s->now.t after a call whose last segment was a
   rounding sliver (no settle) following a lean one */
static int report_end(rps3_sim *s) {
  int st;
  if (s->gsl->reported) return RPS3_OK;
  st = evaluate(s, s->now.t, s->now.y, 0, keeps_plant(s));
  if (st != RPS3_OK) return fail(s, st, s->now.t);
  s->gsl->reported = 1;
  update_energy(s);
  return RPS3_OK;
}

/* 1: c declares known capabilities and has the law they call */
static int law_declared(const rps3_controller *c) {
  if (c->caps & ~(unsigned)RPS3_CTRL_CAPS_ALL) return 0;
  return (c->caps & RPS3_CTRL_USES_PLANT) ? c->fn_plant != NULL : c->fn != NULL;
}

int rps3_sim_advance(rps3_sim *s, const rps3_controller *c, double t_end) {
  rps3_check chk;
  int st;
  if (s == NULL) return RPS3_EINVAL;
  if (!s->started) return RPS3_ESTATE;
  if (s->now.status != RPS3_OK) return s->now.status;
  if (c == NULL || !law_declared(c) || !isfinite(t_end)) {
    s->d->err.code = RPS3_EINVAL;
    snprintf(s->d->err.msg, sizeof(s->d->err.msg),
             "controller NULL, without the law its caps name, or t_end = %g s "
             "not finite",
             t_end);
    return RPS3_EINVAL;
  }
  if (t_end < s->now.t) {
    s->d->err.code = RPS3_EINVAL;
    snprintf(s->d->err.msg, sizeof(s->d->err.msg),
             "t_end = %.17g s is before the simulation's time t = %.17g s",
             t_end, s->now.t);
    return RPS3_EINVAL;
  }
  /* the rate's limits over the call's times (a few operations: the loop
     below counts on them to end) */
  st = rps3_sim_check_rate(&s->opt, c->rate, fmax(fabs(s->t0), fabs(t_end)),
                           &chk);
  if (st != RPS3_OK) {
    s->d->err.code = st;
    snprintf(s->d->err.msg, sizeof(s->d->err.msg), "%s", chk.msg);
    return st;
  }
  s->ctrl = c;
  if (c->rate == 0.0) {
    /* continuous force law: one integration, forces at every evaluation */
    st = integrate(s, t_end);
    if (st == RPS3_OK) st = settle(s, 1);
    if (s->now.status != RPS3_OK) report_failed(s);
    s->ctrl = NULL;
    return s->now.status;
  }
  while (s->now.t < t_end) {
    /* tick k at t0 + k / rate, counted from the start (no drift); a time
       within TICK_SLACK periods of a tick is at it (times the caller
       computes, such as 1e-3 * k, differ from it by rounding) */
    double k = floor((s->now.t - s->t0) * c->rate + TICK_SLACK);
    double t_next = s->t0 + (k + 1.0) / c->rate, t1 = fmin(t_next, t_end);
    if ((long)k > s->last_tick &&
        fabs(s->now.t - (s->t0 + k / c->rate)) <= TICK_SLACK / c->rate) {
      s->last_tick = (long)k;
      st = tick(s, c);
      if (st != RPS3_OK) break;
    }
    if (t1 - s->now.t <= TICK_SLACK / c->rate) {
      /* a rounding sliver, not a step */
      s->now.t = t1;
      continue;
    }
    st = integrate(s, t1);
    if (st == RPS3_OK) st = settle(s, t1 == t_end);
    if (st != RPS3_OK) break;
  }
  if (s->now.status == RPS3_OK)
    report_end(s);
  else
    report_failed(s);
  s->ctrl = NULL;
  return s->now.status;
}
