/* sim_case.c - see sim_case.h. */
#include "sim_case.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* a duration counts as a whole number of steps within this fraction of a
   step (the rule of trajectory.dt, scene.c) */
#define WHOLE_RTOL 1e-9

/* err at the value that set key k in case `index`: its swept value, the
   key in the file, or the simulate section */
static void key_error(const scene *s, size_t index, int k, const char *msg,
                      scene_error *err) {
  size_t a;
  char what[sizeof err->what];
  scene_case_what(s, index, msg, what, sizeof what);
  for (a = 0; k >= 0 && a < s->naxis && s->axis[a].key != k; a++)
    ;
  if (k >= 0 && a < s->naxis)
    scene_error_set(err, s->axis[a].mark[scene_case_coord(s, index, a)],
                    s->axis[a].path, "%s", what);
  else if (k >= 0 && s->given[k])
    scene_error_set(err, s->mark[k], scene_key_get(k)->path, "%s", what);
  else
    scene_error_set(err, s->simulate, "simulate", "%s", what);
}

/* the key a library message "simulate.NAME = VALUE: why" is about */
static int key_of_message(const char *msg) {
  static const struct {
    const char *name;
    int key;
  } alias[] = {{"simulate.epsabs", K_SIM_TOL},
               {"simulate.epsrel", K_SIM_TOL},
               {"simulate.hmin", K_SIM_H},
               {"simulate.controller", K_SIM_CONTROLLER}};
  char name[64];
  size_t i, n = strcspn(msg, " =:");
  if (n >= sizeof name) return -1;
  memcpy(name, msg, n);
  name[n] = '\0';
  for (i = 0; i < sizeof alias / sizeof alias[0]; i++)
    if (strcmp(alias[i].name, name) == 0) return alias[i].key;
  return scene_key_find(name);
}

/* the controller-model key that overrides library field id, or -1 */
static int model_key(int id) {
  switch (id) {
  case RPS3_F_PLATFORM_MASS: return K_SIM_MODEL_M;
  case RPS3_F_LINK_MASS: return K_SIM_MODEL_M_OVER_M;
  case RPS3_F_PAYLOAD_MASS: return K_SIM_MODEL_PAY_MASS;
  case RPS3_F_VISCOUS: return K_SIM_MODEL_VISCOUS;
  case RPS3_F_COULOMB: return K_SIM_MODEL_COULOMB;
  case RPS3_F_EFFECTS: return K_SIM_MODEL_EFFECTS;
  default: return -1;
  }
}

/* the controller's model: the plant's, with the given overrides */
static int ctrl_model(const scene *s, const scene_case *c, sim_case *sc,
                      scene_error *err) {
  const scene_sim *v = &c->v.sim;
  rps3_model *cm = &sc->ctrl_model;
  rps3_check chk;
  int k;
  *cm = c->model;
  if (!isnan(v->model_M)) cm->M = v->model_M;
  /* the link mass follows the controller's M only through m_over_M */
  if (!isnan(v->model_m_over_M)) cm->m = v->model_m_over_M * cm->M;
  if (!isnan(v->model_payload_mass)) cm->payload.mass = v->model_payload_mass;
  if (!isnan(v->model_viscous)) cm->friction.viscous = v->model_viscous;
  if (!isnan(v->model_coulomb)) cm->friction.coulomb = v->model_coulomb;
  if (v->model_effects >= 0) cm->opt.effects = v->model_effects;
  /* a controller's path: F alone, every check (rps3.h, enum rps3_output) */
  cm->opt.outputs = RPS3_OUT_FORCES;
  if (rps3_model_init(cm, &chk) == RPS3_OK) return 0;
  k = model_key(chk.field);
  if (k < 0 || !s->given[k])
    for (k = K_SIM_MODEL_M; k <= K_SIM_MODEL_EFFECTS && !s->given[k]; k++)
      ;
  {
    char msg[320];
    snprintf(msg, sizeof msg, "the controller's model: %s", chk.msg);
    key_error(s, c->index, k <= K_SIM_MODEL_EFFECTS ? k : -1, msg, err);
  }
  return -1;
}

/* the sample grid: the trajectory's step up to the duration */
static int grid(const scene *s, const scene_case *c, sim_case *sc,
                scene_error *err) {
  double q, n;
  char msg[256];
  sc->duration = isnan(c->v.sim.duration) ? c->span : c->v.sim.duration;
  sc->step = c->step;
  q = sc->duration / sc->step;
  n = floor(q + 0.5);
  if (q >= 2147483646.0 || fabs(q - n) > WHOLE_RTOL * (q > 1 ? q : 1) ||
      n < 1) {
    snprintf(msg, sizeof msg,
             q >= 2147483646.0
                 ? "duration %.9g s is %.6g samples of the trajectory's "
                   "step %.9g s: at most 2147483646"
                 : "duration %.9g s is not a whole number of the "
                   "trajectory's steps %.9g s (%.6g steps)",
             sc->duration, q >= 2147483646.0 ? q : sc->step,
             q >= 2147483646.0 ? sc->step : q);
    key_error(s, c->index, K_SIM_DURATION, msg, err);
    return -1;
  }
  sc->nt = (size_t)n + 1;
  return 0;
}

/* the controller's gains (each kind's default when not given), rate and
   the integrator's options of the case's simulate section */
static void case_options(const scene_sim *v, sim_case *sc) {
  int pd;
  sc->kind = (rps3_ctrl_kind)v->controller;
  pd = sc->kind == RPS3_CTRL_PD || sc->kind == RPS3_CTRL_PD_GRAVITY;
  sc->kp = !isnan(v->kp)                           ? v->kp
           : pd                                    ? SIM_KP_PD
           : sc->kind == RPS3_CTRL_COMPUTED_TORQUE ? SIM_KP_CT
                                                   : 0.0;
  sc->kd = !isnan(v->kd)                           ? v->kd
           : pd                                    ? SIM_KD_PD
           : sc->kind == RPS3_CTRL_COMPUTED_TORQUE ? SIM_KD_CT
                                                   : 0.0;
  sc->rate = v->rate;
  rps3_sim_options_default(&sc->opt);
  sc->opt.integrator = (rps3_integrator)v->integrator;
  sc->opt.h = v->h;
  sc->opt.epsabs = sc->opt.epsrel = v->tolerance;
  sc->opt.max_steps = v->max_steps;
  sc->opt.fmax = v->fmax;
  sc->opt.l_min = v->l_min;
  sc->opt.l_max = v->l_max > 0 ? v->l_max : HUGE_VAL;
  sc->opt.noise_l = v->noise_l;
  sc->opt.noise_dl = v->noise_dl;
  sc->opt.quant_l = v->quant_l;
  sc->opt.quant_dl = v->quant_dl;
  sc->opt.seed = (unsigned long)v->seed;
}

void sim_work_free(sim_work *wk) {
  rps3_sim_free(wk->sim);
  rps3_ctrl_free(wk->ctrl);
  rps3_data_free(wk->ref);
  memset(wk, 0, sizeof *wk);
}

/* the library's own checks of the options, the rate over the run and the
   controller: a status, with msg; the simulation and controller kept in
   wk when it is not NULL and they pass */
static int library_checks(const scene_case *c, const sim_case *sc, sim_work *wk,
                          char *msg, size_t sz) {
  rps3_sim *sim = NULL;
  rps3_ctrl *ctrl = NULL;
  rps3_check chk;
  int st = rps3_sim_alloc(&c->model, &sc->opt, &sim, &chk);
  /* the rate's limits over the run (rps3_sim_advance refuses the same) */
  if (st == RPS3_OK)
    st = rps3_sim_check_rate(&sc->opt, sc->rate, sc->duration, &chk);
  if (st != RPS3_OK) snprintf(msg, sz, "%s", chk.msg);
  if (st == RPS3_OK && sc->rate == 0.0 &&
      (sc->opt.integrator == RPS3_INT_RK4 ||
       sc->opt.integrator == RPS3_INT_RK4IMP) &&
      ceil(sc->step / sc->opt.h - 1e-6) > (double)sc->opt.max_steps) {
    /* a continuous controller: one integration a sample */
    snprintf(msg, sz,
             "simulate.h = %.17g: a sample step of %.6g s takes %.6g steps "
             "of h, more than max_steps = %ld",
             sc->opt.h, sc->step, ceil(sc->step / sc->opt.h - 1e-6),
             sc->opt.max_steps);
    st = RPS3_EINVAL;
  }
  if (st == RPS3_OK) {
    st = rps3_ctrl_alloc(sc->kind, sc->kp, sc->kd, &sc->ctrl_model, &c->traj,
                         &ctrl, &chk);
    if (st != RPS3_OK) snprintf(msg, sz, "%s", chk.msg);
  }
  if (wk && st == RPS3_OK) {
    wk->sim = sim;
    wk->ctrl = ctrl;
    return st;
  }
  rps3_sim_free(sim);
  rps3_ctrl_free(ctrl);
  return st;
}

/* the library's refusal st (msg) at its key: "simulate.NAME =
   0.20000000000000001: why" said as "NAME = 0.2: why" */
static void library_error(const scene *s, const scene_case *c, int st,
                          const char *msg, scene_error *err) {
  const char *eq = strstr(msg, " = "), *why = eq ? strstr(eq, ": ") : NULL;
  char short_msg[320];
  if (st == RPS3_ENOMEM)
    key_error(s, c->index, -1, "out of memory", err);
  else if (eq && why && strncmp(msg, "simulate.", 9) == 0) {
    snprintf(short_msg, sizeof short_msg, "%.*s = %.9g%s", (int)(eq - msg - 9),
             msg + 9, strtod(eq + 3, NULL), why);
    key_error(s, c->index, key_of_message(msg), short_msg, err);
  } else
    key_error(s, c->index, key_of_message(msg), msg, err);
}

int sim_case_build(const scene *s, const scene_case *c, sim_case *sc,
                   sim_work *wk, scene_error *err) {
  const int inertia =
      RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA | RPS3_EFF_PAYLOAD;
  int st;
  char msg[320];
  memset(sc, 0, sizeof *sc);
  if (!(c->model.opt.effects & inertia)) {
    scene_error_set(err, s->mark[K_EFFECTS], "effects",
                    "a simulated plant needs a mass to accelerate: list "
                    "platform_inertia, link_inertia or payload");
    return -1;
  }
  case_options(&c->v.sim, sc);
  if (ctrl_model(s, c, sc, err) || grid(s, c, sc, err)) return -1;
  st = library_checks(c, sc, wk, msg, sizeof msg);
  if (st != RPS3_OK) {
    library_error(s, c, st, msg, err);
    return -1;
  }
  return 0;
}

double sim_case_time(const scene_case *c, const sim_case *sc, size_t k) {
  if (k + 1 >= sc->nt) return sc->duration;
  if (k < c->nt) return scene_case_time(c, k);
  return (double)k * sc->step;
}

static int same_grid(const scene_case *a, const sim_case *sa,
                     const scene_case *b, const sim_case *sb) {
  return sa->nt == sb->nt && sa->step == sb->step &&
         sa->duration == sb->duration && scene_case_same_grid(a, b) &&
         a->by_dt == b->by_dt;
}

/* the first axis that sweeps a simulate key, or s->naxis */
static size_t sim_axis(const scene *s) {
  size_t a;
  for (a = 0; a < s->naxis; a++)
    if (scene_key_get(s->axis[a].key)->src == SRC_SIM) break;
  return a;
}

/* a sweep of simulate.* keys in a scene without the section is refused */
static int section_rule(const scene *s, scene_error *err) {
  size_t a = sim_axis(s);
  if (s->simulate.line > 0 || a == s->naxis) return 0;
  scene_error_set(err, s->axis[a].mark[0], s->axis[a].path,
                  "a simulate key, but the scene has no simulate section: add "
                  "`simulate: {}` to simulate with the defaults");
  return -1;
}

int sim_plan_make(const scene *s, sim_plan *p, scene_error *err) {
  scene_case c;
  sim_case sc;
  size_t i;
  memset(p, 0, sizeof *p);
  p->common = 1;
  if (section_rule(s, err)) return -1;
  for (i = 0; i < s->ncase; i++) {
    if (scene_case_build(s, i, &c, err) ||
        sim_case_build(s, &c, &sc, NULL, err))
      return -1;
    if (i == 0) {
      p->first = c;
      p->sfirst = sc;
    } else if (!same_grid(&p->first, &p->sfirst, &c, &sc))
      p->common = 0;
    if (sc.nt > p->nt) p->nt = sc.nt;
    p->npoint += sc.nt;
    p->seconds += sc.duration;
  }
  return 0;
}

int sim_wanted(const scene *s) {
  return s->simulate.line > 0 || sim_axis(s) < s->naxis;
}
