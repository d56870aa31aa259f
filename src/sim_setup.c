/*
 * sim_setup.c - a simulation's set-up: the integrators' names, the
 * options' defaults and their checks, and the allocation of everything a
 * run uses (the plant data, GSL's stepper, control and evolve objects);
 * src/sim.c runs it.
 */
#include <stdlib.h>
#include <string.h>

#include "sim.h"

static const char *const INT_NAME[RPS3_NINTEGRATOR] = {"rk4", "rkf45", "rk8pd",
                                                       "msbdf", "rk4imp"};

const char *rps3_integrator_name(int integrator) {
  if (integrator < 0 || integrator >= RPS3_NINTEGRATOR) return NULL;
  return INT_NAME[integrator];
}

int rps3_integrator_index(const char *name) {
  return rps3_name_lookup(INT_NAME, RPS3_NINTEGRATOR, name);
}

void rps3_sim_options_default(rps3_sim_options *o) {
  if (o == NULL) return;
  memset(o, 0, sizeof(*o));
  o->integrator = RPS3_INT_RK4;
  o->h = 1e-3;
  o->epsabs = 1e-9;
  o->epsrel = 1e-9;
  o->hmin = 1e-12;
  o->max_steps = 100000;
  o->l_min = 0.0;
  o->l_max = HUGE_VAL;
  o->seed = 0x5eedUL;
}

/* a refused option: "FIELD = VALUE: why" in chk (the simulation's options
   are not rows of RPS3_FIELDS: chk->field stays -1) */
static int bad(rps3_check *chk, const char *field, double value,
               const char *why) {
  if (chk != NULL)
    snprintf(chk->msg, sizeof chk->msg, "%s = %.17g: %s", field, value, why);
  return RPS3_EINVAL;
}

/* an allocation that failed: RPS3_ENOMEM, with what in chk */
static int nomem(rps3_check *chk, const char *what) {
  if (chk != NULL)
    snprintf(chk->msg, sizeof chk->msg, "out of memory: %s", what);
  return RPS3_ENOMEM;
}

#define REQUIRE(cond, field, value, why)                       \
  do {                                                         \
    if (!(cond)) return bad(chk, field, (double)(value), why); \
  } while (0)

static int check_options(const rps3_sim_options *o, rps3_check *chk) {
  REQUIRE((int)o->integrator >= 0 && (int)o->integrator < RPS3_NINTEGRATOR,
          "simulate.integrator", o->integrator, "unknown integrator");
  REQUIRE(isfinite(o->h) && o->h > 0, "simulate.h", o->h,
          "must be finite and > 0");
  REQUIRE(isfinite(o->epsabs) && o->epsabs >= 0, "simulate.epsabs", o->epsabs,
          "must be finite and >= 0");
  REQUIRE(isfinite(o->epsrel) && o->epsrel >= 0, "simulate.epsrel", o->epsrel,
          "must be finite and >= 0");
  /* GSL's error control (cstd.c) divides by epsabs + epsrel |y_i|, and
     msbdf raises "errlev <= zero" through GSL's process-global error
     handler (which aborts by default) where that is 0: y_i = 0 happens
     (the work integrals start at 0), so an adaptive method needs
     epsabs > 0.  The fixed-step methods get their own positive value. */
  REQUIRE(o->epsabs > 0 || o->integrator == RPS3_INT_RK4 ||
              o->integrator == RPS3_INT_RK4IMP,
          "simulate.epsabs", o->epsabs,
          "must be > 0 for an adaptive integrator");
  REQUIRE(isfinite(o->hmin) && o->hmin > 0 && o->hmin <= o->h, "simulate.hmin",
          o->hmin, "must be finite, > 0 and <= h");
  REQUIRE(o->max_steps >= 1, "simulate.max_steps", o->max_steps,
          "must be >= 1");
  REQUIRE(isfinite(o->fmax) && o->fmax >= 0, "simulate.fmax", o->fmax,
          "must be finite and >= 0");
  REQUIRE(isfinite(o->l_min) && o->l_min >= 0, "simulate.l_min", o->l_min,
          "must be finite and >= 0");
  REQUIRE(!isnan(o->l_max) && o->l_max > o->l_min, "simulate.l_max", o->l_max,
          "must be > l_min");
  REQUIRE(isfinite(o->noise_l) && o->noise_l >= 0, "simulate.noise_l",
          o->noise_l, "must be finite and >= 0");
  REQUIRE(isfinite(o->noise_dl) && o->noise_dl >= 0, "simulate.noise_dl",
          o->noise_dl, "must be finite and >= 0");
  REQUIRE(isfinite(o->quant_l) && o->quant_l >= 0, "simulate.quant_l",
          o->quant_l, "must be finite and >= 0");
  REQUIRE(isfinite(o->quant_dl) && o->quant_dl >= 0, "simulate.quant_dl",
          o->quant_dl, "must be finite and >= 0");
  return RPS3_OK;
}

int rps3_sim_check_rate(const rps3_sim_options *o, double rate, double t_max,
                        rps3_check *chk) {
  rps3_sim_options def;
  double period, steps, step;
  int st, fixed;
  rps3_check_clear(chk);
  if (o == NULL) {
    rps3_sim_options_default(&def);
    o = &def;
  }
  st = check_options(o, chk);
  if (st != RPS3_OK) return st;
  if (!(isfinite(t_max) && t_max >= 0.0)) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "t_max = %.17g s: must be finite and >= 0", t_max);
    return RPS3_EINVAL;
  }
  REQUIRE(isfinite(rate) && rate >= 0.0, "simulate.rate", rate,
          "must be finite and >= 0 (0: a continuous controller)");
  if (rate == 0.0) return RPS3_OK;
  period = 1.0 / rate;
  /* the step a period is measured against: the fixed methods' h, the
     adaptive ones' smallest step (h is only their first guess) */
  fixed = o->integrator == RPS3_INT_RK4 || o->integrator == RPS3_INT_RK4IMP;
  step = fixed ? o->h : o->hmin;
  if (!(period >= step / (double)RPS3_SIM_RATE_H_MAX)) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "simulate.rate = %.17g: its period %.3g s is shorter than "
               "%s / %g = %.3g s (%s = %g s): at most %g control periods a "
               "step",
               rate, period, fixed ? "h" : "hmin", (double)RPS3_SIM_RATE_H_MAX,
               step / (double)RPS3_SIM_RATE_H_MAX,
               fixed ? "simulate.h" : "hmin", step,
               (double)RPS3_SIM_RATE_H_MAX);
    return RPS3_EINVAL;
  }
  /* k / rate and t0 + k / rate must tell the ticks apart far below the
     slack that merges times (TICK_SLACK of sim.c, 1e-6 periods) */
  if (!(period >= t_max / (double)RPS3_SIM_MAX_PERIODS)) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "simulate.rate = %.17g: its period %.3g s is below %g of the "
               "run's time %.6g s, where double precision does not tell "
               "its ticks apart: at most %g control periods a run",
               rate, period, 1.0 / (double)RPS3_SIM_MAX_PERIODS, t_max,
               (double)RPS3_SIM_MAX_PERIODS);
    return RPS3_EINVAL;
  }
  if (fixed) {
    /* the fixed steps of one control period (integrate in sim.c) */
    steps = ceil(period / o->h - 1e-6);
    if (steps > (double)o->max_steps) {
      if (chk != NULL)
        snprintf(chk->msg, sizeof chk->msg,
                 "simulate.h = %.17g: a control period of %.6g s takes %.6g "
                 "steps of h, more than max_steps = %ld",
                 o->h, period, steps, o->max_steps);
      return RPS3_EINVAL;
    }
  }
  return RPS3_OK;
}

static const gsl_odeiv2_step_type *step_type(rps3_integrator k) {
  switch (k) {
  case RPS3_INT_RKF45: return gsl_odeiv2_step_rkf45;
  case RPS3_INT_RK8PD: return gsl_odeiv2_step_rk8pd;
  case RPS3_INT_MSBDF: return gsl_odeiv2_step_msbdf;
  case RPS3_INT_RK4IMP: return gsl_odeiv2_step_rk4imp;
  case RPS3_INT_RK4:
  default: return gsl_odeiv2_step_rk4;
  }
}

int rps3_sim_alloc(const rps3_model *plant, const rps3_sim_options *o,
                   rps3_sim **out, rps3_check *chk) {
  rps3_sim *s;
  rps3_sim_options def;
  int st;
  rps3_check_clear(chk);
  if (out == NULL) {
    if (chk != NULL) snprintf(chk->msg, sizeof chk->msg, "out is NULL");
    return RPS3_EINVAL;
  }
  *out = NULL;
  if (plant == NULL || !plant->valid) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "plant model is NULL or not initialised");
    return RPS3_EINVAL;
  }
  if (o == NULL) {
    rps3_sim_options_default(&def);
    o = &def;
  }
  st = check_options(o, chk);
  if (st != RPS3_OK) return st;
  s = (rps3_sim *)calloc(1, sizeof(*s));
  if (s == NULL) return nomem(chk, "the simulation");
  s->plant = *plant;
  s->opt = *o;
  s->now.status = RPS3_ESTATE;
  s->now.failed_at = (double)NAN;
  s->gsl = (struct rps3_sim_gsl *)calloc(1, sizeof(*s->gsl));
  if (s->gsl == NULL || rps3_data_alloc(&s->plant, &s->d) != RPS3_OK) {
    rps3_sim_free(s);
    return nomem(chk, "the plant's workspace");
  }
  s->gsl->sys.function = rps3_sim_rhs;
  s->gsl->sys.jacobian = rps3_sim_jac;
  s->gsl->sys.dimension = NY;
  s->gsl->sys.params = s;
  s->gsl->fixed =
      (o->integrator == RPS3_INT_RK4 || o->integrator == RPS3_INT_RK4IMP);
  /* the implicit steppers reach their Newton solver's settings through a
     driver, so every method gets one; a fixed-step method then steps with
     the driver's stepper alone (its tolerance is not used) */
  s->gsl->drv = gsl_odeiv2_driver_alloc_y_new(
      &s->gsl->sys, step_type(o->integrator), o->h,
      s->gsl->fixed ? 1e-6 : o->epsabs, s->gsl->fixed ? 0.0 : o->epsrel);
  if (s->gsl->drv == NULL) {
    rps3_sim_free(s);
    return nomem(chk, "GSL's odeiv2 driver");
  }
  s->gsl->stp = s->gsl->drv->s;
  if (gsl_odeiv2_driver_set_hmin(s->gsl->drv, o->hmin) != GSL_SUCCESS ||
      gsl_odeiv2_driver_set_nmax(s->gsl->drv, (unsigned long)o->max_steps) !=
          GSL_SUCCESS) {
    rps3_sim_free(s);
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg, "simulate.hmin = %g: GSL refused it",
               o->hmin);
    return RPS3_EINVAL;
  }
  *out = s;
  return RPS3_OK;
}

void rps3_sim_free(rps3_sim *s) {
  if (s == NULL) return;
  if (s->gsl != NULL && s->gsl->drv != NULL)
    gsl_odeiv2_driver_free(s->gsl->drv);
  free(s->gsl);
  rps3_data_free(s->d);
  free(s);
}

const rps3_sim_report *rps3_sim_now(const rps3_sim *s) {
  return s ? &s->now : NULL;
}

const rps3_data *rps3_sim_data(const rps3_sim *s) { return s ? s->d : NULL; }

const rps3_model *rps3_sim_plant(const rps3_sim *s) {
  return s ? &s->plant : NULL;
}

const rps3_sim_options *rps3_sim_opts(const rps3_sim *s) {
  return s ? &s->opt : NULL;
}
