/*
 * study_accuracy_cfg.c - the accuracy study's configurations: each knob
 * turned from the defaults (the theta solve's solvers and tolerances, the
 * rates' derivatives, the formulation, the effects ladder, the sample
 * interval), labelled as the file names them.
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "study_accuracy_h5.h"

static const double tols[7] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14};
static const double steps[6] = {FD_MARGIN, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
/* row spacings of the spline of the pose: 100 Hz is a motion-capture rate,
   1 kHz an encoder's */
static const double spacings[3] = {1e-1, 1e-2, 1e-3};
static const double dt_fracs[9] = {5e-2, 2e-2, 1e-2, 5e-3, 2e-3,
                                   1e-3, 5e-4, 2e-4, 1e-4};
/* the effects ladder: gravity only -> every effect */
static const int ladder[RPS3_NEFFECT] = {
    RPS3_EFF_PLATFORM_GRAVITY,
    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY,
    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY |
        RPS3_EFF_PLATFORM_INERTIA,
    RPS3_EFF_DEFAULT,
    RPS3_EFF_DEFAULT | RPS3_EFF_PAYLOAD,
    RPS3_EFF_DEFAULT | RPS3_EFF_PAYLOAD | RPS3_EFF_PIN_FRICTION,
    RPS3_EFF_ALL};

void study_config_base(study_config *c, study_kind s) {
  memset(c, 0, sizeof(*c));
  c->study = s;
  c->theta = RPS3_THETA_CLOSED_FORM;
  c->solver = -1;
  c->tol = 1e-12;
  c->warm = 1;
  c->deriv = D_EXACT;
  c->method = RPS3_LAGRANGE;
  c->effects = RPS3_EFF_DEFAULT;
}

/* the next configuration cfg[(*n)++]: of study s, every knob at its
   default, labelled by the format */
static study_config *add(study_config *cfg, int *n, study_kind s,
                         const char *fmt, ...) {
  study_config *c = &cfg[(*n)++];
  va_list ap;
  study_config_base(c, s);
  va_start(ap, fmt);
  vsnprintf(c->label, sizeof c->label, fmt, ap);
  va_end(ap);
  return c;
}

int study_configs_build(study_config *cfg) {
  int n = 0, s, t, w, k, e;
  study_config *c;
  add(cfg, &n, S_THETA, "closed form (39)");
  for (s = 0; s < RPS3_NSOLVER; s++)
    for (t = 0; t < 7; t++)
      for (w = 0; w < 2; w++) {
        c = add(cfg, &n, S_THETA, "%s tol=%.0e %s", rps3_solver_name(s),
                tols[t], w ? "warm" : "cold");
        c->theta = RPS3_THETA_MULTIROOT;
        c->solver = s;
        c->tol = tols[t];
        c->warm = w;
      }
  add(cfg, &n, S_DERIV, "exact rates");
  for (k = D_FD_POSE; k <= D_SPLINE; k++) {
    /* the spline's row spacings, else the steps; fd_samples is the dt
       study's */
    const double *h = k == D_SPLINE ? spacings : steps;
    int nh = k == D_SPLINE ? 3 : k == D_FD_SAMPLES ? 0 : 6;
    for (t = 0; t < nh; t++) {
      c = add(cfg, &n, S_DERIV, "%s h=%.0e s", study_deriv_name[k], h[t]);
      c->deriv = (deriv_kind)k;
      c->h = h[t];
    }
  }
  for (k = 0; k < 2; k++)
    add(cfg, &n, S_METHOD, "%s", k ? "newton_euler" : "lagrange")->method =
        k ? RPS3_NEWTON_EULER : RPS3_LAGRANGE;
  for (e = 0; e < RPS3_NEFFECT; e++)
    add(cfg, &n, S_EFFECTS, "+%s", rps3_effect_name(e))->effects = ladder[e];
  /* sample interval, exact rates and rates differenced from the samples */
  for (k = 0; k < 2; k++)
    for (t = 0; t < 9; t++) {
      c = add(cfg, &n, S_DT, "dt=T/%.0f %s", 1.0 / dt_fracs[t],
              k ? "rates from samples" : "exact rates");
      c->dt_frac = dt_fracs[t];
      c->deriv = k ? D_FD_SAMPLES : D_EXACT;
    }
  return n;
}
