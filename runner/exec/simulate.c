/*
 * simulate.c - see simulate.h: each simulated case built from the scene's
 * simulate section and checked; then the cases simulated on the worker
 * pool (its items the cases, its slots windows of samples) into a file
 * under a temporary name, renamed when complete (tmpout.h).
 */
#include "simulate.h"
#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "estimate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* a duration counts as a whole number of steps within this fraction of a
   step (the rule of trajectory.dt, scene.c) */
#define WHOLE_RTOL 1e-9

/* one simulated case, ready to run */
typedef struct {
  rps3_model ctrl_model; /* the controller's model, initialised */
  rps3_sim_options opt;
  rps3_ctrl_kind kind;
  double kp, kd;   /* the gains used (the kind's when not given) */
  double rate;     /* control rate [Hz] */
  double duration; /* simulated time [s] */
  double step;     /* sample step [s] */
  size_t nt;       /* samples, both ends included */
} sim_case;

/* the workspaces of one simulated case */
typedef struct {
  rps3_sim *sim;
  rps3_ctrl *ctrl;
  rps3_data *ref; /* the reference motion, on the plant's geometry */
} sim_work;

/* what the check of all cases found: the time axis */
typedef struct {
  size_t nt;      /* most samples of any case */
  size_t npoint;  /* samples over all cases */
  double seconds; /* simulated time over all cases [s] */
  int common;     /* 1: every case has case 0's time grid */
  scene_case first;
  sim_case sfirst;
} sim_plan;

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

static void sim_work_free(sim_work *wk) {
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

/* The simulation of case c of s: controller model, options, gains and
   grid, each checked (the library's own checks, rps3_sim_alloc and
   rps3_ctrl_alloc included).  With wk, the simulation and controller
   those checks made are kept there for the run (else freed).  Returns 0,
   or -1 with err at the key (or the swept value) that is wrong. */
static int sim_case_build(const scene *s, const scene_case *c, sim_case *sc,
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

/* Time of sample k of a simulated case [s]. */
static double sim_case_time(const scene_case *c, const sim_case *sc, size_t k) {
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

/* Build and check every case of s (scene_case_build, sim_case_build) and
   find the time axis.  A sweep of simulate.* keys needs the section.
   Returns 0, or -1 with err at the first wrong value. */
static int sim_plan_make(const scene *s, sim_plan *p, scene_error *err) {
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

/* samples per window (and chunk) of a case: memory does not grow with the
   length of a case */
#define SIM_WINDOW 4096

/* the estimate's pilot: up to PILOT_CASES cases spread over the sweep,
   each simulated for PILOT_SAMPLES samples at most and within a budget of
   PILOT_WORK control periods or steps and PILOT_CPU CPU seconds, whichever
   ends first, so that the estimate's own work is bounded whatever the
   rate, step and duration; advanced in chunks of PILOT_CHUNK of them */
#define PILOT_SAMPLES 400
#define PILOT_CASES 4
#define PILOT_WORK 20000.0
#define PILOT_CHUNK 256.0
#define PILOT_CPU 0.2

/* a window on its way to the file: a slot of the pool, a block of one
   case (its times in b.t, its resolved scene in b.yaml[0]) */
typedef struct {
  out_block b;
  char message[640]; /* storage of the message */
} sim_tile;

/* the reference at t: the trajectory, after its span its final pose at
   rest, through the closed-form inverse kinematics */
static int reference(const scene_case *c, rps3_data *r, double t) {
  int st, rest = t > c->span;
  st = rps3_traj_eval(&c->model, &c->traj, rest ? c->span : t, r->pose,
                      r->dpose, r->ddpose);
  if (st != RPS3_OK) return st;
  if (rest) r->dpose[0] = r->dpose[1] = r->dpose[2] = 0.0;
  st = rps3_ik(&c->model, r);
  return st == RPS3_OK ? rps3_velocity(&c->model, r) : st;
}

/* sample j of the window: the plant's state, the reference, the forces;
 *emax the largest tracking error so far */
static void store(out_block *b, double *emax, size_t j, const rps3_sim *sim,
                  const rps3_data *r, int first) {
  const rps3_data *d = rps3_sim_data(sim);
  const rps3_sim_report *now = rps3_sim_now(sim);
  double e;
  int i;
  for (i = 0; i < 3; i++) {
    size_t x = 3 * j + (size_t)i;
    OUT_D(b, sim_length)[x] = now->y[i];
    OUT_D(b, sim_length_rate)[x] = now->y[3 + i];
    OUT_D(b, length_ref)[x] = r->l[i];
    OUT_D(b, length_rate_ref)[x] = r->dl[i];
    e = r->l[i] - now->y[i];
    OUT_D(b, tracking_error)[x] = e;
    if (fabs(e) > *emax) *emax = fabs(e);
    /* no force has acted yet at the start */
    OUT_D(b, force_cmd)[x] = first ? (double)NAN : now->F_cmd[i];
    OUT_D(b, sim_force)[x] = first ? (double)NAN : now->F[i];
    OUT_D(b, sim_theta)[x] = d->theta[i];
  }
  OUT_D(b, sim_alpha)[j] = d->pose[0];
  OUT_D(b, beta)[j] = d->pose[1];
  OUT_D(b, z_c)[j] = d->pose[2];
  OUT_D(b, x_c)[j] = d->c[0];
  OUT_D(b, y_c)[j] = d->c[1];
  OUT_D(b, alpha_ref)[j] = r->pose[0];
  OUT_D(b, beta_ref)[j] = r->pose[1];
  OUT_D(b, z_c_ref)[j] = r->pose[2];
  OUT_D(b, x_c_ref)[j] = r->c[0];
  OUT_D(b, y_c_ref)[j] = r->c[1];
  OUT_D(b, kinetic_energy)[j] = now->T;
  OUT_D(b, potential_energy)[j] = now->P;
  OUT_D(b, work_actuators)[j] = now->y[6];
  OUT_D(b, work_friction)[j] = now->y[7];
  OUT_D(b, sim_energy_residual)[j] = now->energy_residual;
}

/* Where to advance for sample time t: the tick at t when t is one up to
   rounding (k dt and k / rate differ in the last bit), so that the tick
   at t is served by the next advance and the force stored with sample t
   is the one held over the control period ending at t.  Within the
   library's own slack (TICK_SLACK of src/sim.c, 1e-6 periods). */
static double tick_time(double t, double rate) {
  double j;
  if (!(rate > 0)) return t;
  j = floor(t * rate + 0.5);
  return fabs(t - j / rate) <= 1e-6 / rate ? j / rate : t;
}

typedef struct {
  sweep_writer w; /* first: the ctx of sweep_write_tile */
  size_t points;  /* samples of a window */
} sim_job;

/* pool_job.slot_make, slot_free: a window's buffers */
static int tile_make(void *ctx, void *slot, size_t i) {
  sim_tile *t = slot;
  (void)i;
  if (out_block_alloc(&t->b, OUT_SIM, 1, ((const sim_job *)ctx)->points, 0))
    return -1;
  OUT_S(&t->b, message)[0] = t->message;
  return 0;
}

static void tile_free(void *ctx, void *slot, size_t i) {
  (void)ctx;
  (void)i;
  out_block_free(&((sim_tile *)slot)->b);
}

/* case i built and its simulation and controller started on the
   trajectory (plus the start offset), *st the start's status; 0, or -1
   (memory: the plan built this case already) */
static int start(const scene *s, size_t i, scene_case *c, sim_case *sc,
                 sim_work *wk, rps3_controller *ctl, int *st, char *err,
                 size_t errsz) {
  double pose[3], dpose[3];
  scene_error serr;
  int k;
  memset(wk, 0, sizeof *wk);
  if (scene_case_build(s, i, c, &serr) || sim_case_build(s, c, sc, wk, &serr)) {
    snprintf(err, errsz, "case %zu: %s", i, serr.what);
    return -1;
  }
  if (rps3_data_alloc(&c->model, &wk->ref)) {
    snprintf(err, errsz, "case %zu: out of memory", i);
    sim_work_free(wk);
    return -1;
  }
  *ctl = rps3_ctrl_bind(wk->ctrl, sc->rate);
  /* from the trajectory's start, at its rates */
  *st = rps3_traj_eval(&c->model, &c->traj, 0.0, pose, dpose, NULL);
  for (k = 0; k < 3; k++) pose[k] += c->v.sim.start_offset[k];
  if (*st == RPS3_OK) *st = rps3_sim_start(wk->sim, 0.0, pose, dpose);
  return 0;
}

/* hand the window over: samples [k0, k0 + nk) of case c */
static sim_tile *flush(pool_worker *w, size_t c, size_t k0, size_t nk, int last,
                       char *err, size_t errsz) {
  out_tile in = {c, 1, k0, nk, last, 0, nk};
  return pool_emit(w, &in, err, errsz);
}

/* the per-case values of case c into its last window w: the outcome st
   (failed before sample n, at time tn: the message the simulation's, and
   the controller's own when it was the controller that failed), the
   largest tracking error emax and the simulation's counts */
static void case_values(sim_tile *w, const sim_work *wk, int st, size_t n,
                        double tn, double emax) {
  const rps3_sim_report *now = rps3_sim_now(wk->sim);
  const rps3_data *meas = rps3_ctrl_measured(wk->ctrl);
  const rps3_data *des = rps3_ctrl_desired(wk->ctrl);
  const char *msg = rps3_sim_data(wk->sim)->err.msg;
  const char *why = meas && meas->err.code != RPS3_OK ? meas->err.msg
                    : des && des->err.code != RPS3_OK ? des->err.msg
                                                      : "";
  double t = isnan(now->failed_at) ? tn : now->failed_at;
  int ctrl = why[0] && strstr(msg, "controller");
  out_block *b = &w->b;
  OUT_I(b, sim_status)[0] = st;
  OUT_I(b, sim_failed_at)[0] = st != RPS3_OK ? (int32_t)n : -1;
  OUT_D(b, failed_time)[0] = st != RPS3_OK ? t : (double)NAN;
  w->message[0] = '\0';
  if (st != RPS3_OK)
    snprintf(w->message, sizeof w->message,
             "t = %.9g s (before sample %zu): %s: %s%s%s%s", t, n,
             rps3_strerror(st), msg, ctrl ? " (" : "", ctrl ? why : "",
             ctrl ? ")" : "");
  OUT_D(b, tracking_error_max)[0] = emax;
  OUT_L(b, nsteps)[0] = (int64_t)now->nsteps;
  OUT_L(b, nevals)[0] = (int64_t)now->nevals;
  OUT_L(b, nticks)[0] = (int64_t)now->nticks;
  OUT_L(b, nsat)[0] = (int64_t)now->nsat;
}

/* pool_job.run: case i on worker w, window by window into its slots;
   0, or -1 when the pool stopped or memory ran out (err set) */
static int sim_item(void *ctx, void *wctx, size_t i, pool_worker *w, char *err,
                    size_t errsz) {
  const sim_job *J = ctx;
  sim_tile *t = pool_slot(w);
  scene_case c;
  sim_case sc;
  sim_work wk;
  rps3_controller ctl;
  double tn = 0.0, emax = 0.0;
  size_t n, j = 0, k0 = 0;
  int st;
  (void)wctx;
  if (start(J->w.s, i, &c, &sc, &wk, &ctl, &st, err, errsz)) return -1;
  for (n = 0; n < sc.nt && t; n++) {
    tn = sim_case_time(&c, &sc, n);
    if (st == RPS3_OK && n > 0)
      /* a tick just behind the state (samples closer than the slack) is
         the state's time: the library refuses a t_end before it */
      st = rps3_sim_advance(
          wk.sim, &ctl, fmax(tick_time(tn, sc.rate), rps3_sim_now(wk.sim)->t));
    if (st == RPS3_OK) st = reference(&c, wk.ref, tn);
    if (st != RPS3_OK) break;
    store(&t->b, &emax, j, wk.sim, wk.ref, n == 0);
    t->b.t[j] = tn;
    if (++j == t->b.points && n + 1 < sc.nt) {
      t = flush(w, i, k0, j, 0, err, errsz);
      k0 += j;
      j = 0;
    }
  }
  if (t) case_values(t, &wk, st, n, tn, emax);
  sim_work_free(&wk);
  /* the samples up to the end or the failure (those after a failure keep
     the fill, NaN), with the case's values and its resolved scene */
  if (t && scene_case_yaml(&c, &t->b.yaml[0])) {
    snprintf(err, errsz, "case %zu: cannot write its scene", i);
    return -1;
  }
  if (t) {
    OUT_S(&t->b, scene_resolved)[0] = t->b.yaml[0].s;
    t = flush(w, i, k0, j, 1, err, errsz);
  }
  return t ? 0 : -1;
}

/* Bytes of a file of ncase cases and npoint samples in all, uncompressed
   (the per-case strings estimated): an estimate for the disk check. */
static double sim_file_bytes(size_t ncase, size_t npoint) {
  double per_point = 0, per_case = 0;
  int i;
  for (i = 0; i < OUT_NFIELD; i++)
    if (!(out_field_table[i].files & OUT_SIM))
      continue;
    else if (out_field_table[i].shape == OUT_C)
      per_case += out_field_table[i].type == OUT_STR ? 512.0 : 8.0;
    else
      per_point += 8.0 * (double)out_columns(out_field_table[i].shape, 0);
  /* the scene, the scales and HDF5's metadata: a bound */
  return per_point * (double)npoint + per_case * (double)ncase + 65536.0;
}

/* control periods or integrator steps a simulated second of case sc (the
   finer of the two; the adaptive methods' first step stands for theirs) */
static double work_rate(const sim_case *sc) {
  double steps = 1.0 / sc->opt.h;
  return sc->rate > steps ? sc->rate : steps;
}

/* Case i simulated as the run does (its samples' references included) up
   to the pilot's budget: adds the CPU seconds and the simulated seconds it
   covered to *cpu and *sim, the samples to *samples.  -1 when the case
   cannot be set up (memory). */
static int pilot_case(const scene *s, size_t i, double *cpu, double *sim,
                      size_t *samples) {
  scene_case c;
  sim_case sc;
  sim_work wk;
  rps3_controller ctl;
  double c0 = est_cpu_now(), t_stop, chunk, t = 0.0;
  size_t n, nrun;
  int st;
  char err[256];
  if (start(s, i, &c, &sc, &wk, &ctl, &st, err, sizeof err)) return -1;
  nrun = sc.nt < PILOT_SAMPLES ? sc.nt : PILOT_SAMPLES;
  t_stop = PILOT_WORK / work_rate(&sc);
  chunk = PILOT_CHUNK / work_rate(&sc);
  for (n = 0; n < nrun && st == RPS3_OK; n++) {
    double tn = sim_case_time(&c, &sc, n), now;
    if (n > 0) tn = tick_time(tn, sc.rate);
    /* the sample's time in chunks, each against the budget */
    while (st == RPS3_OK && (now = rps3_sim_now(wk.sim)->t) < tn) {
      t = now + chunk < tn ? now + chunk : tn;
      if (t > t_stop) t = t_stop > now ? t_stop : now;
      if (t <= now || est_cpu_now() - c0 > PILOT_CPU) break;
      st = rps3_sim_advance(wk.sim, &ctl, t);
    }
    if (st != RPS3_OK || rps3_sim_now(wk.sim)->t < tn) break;
    if (reference(&c, wk.ref, tn) != RPS3_OK) break;
    ++*samples;
  }
  *sim += rps3_sim_now(wk.sim)->t;
  *cpu += est_cpu_now() - c0;
  sim_work_free(&wk);
  return 0;
}

/* The run time of the plan on nthread threads into buf: the pilot's cases
   (their controllers, integrators and steps differ), timed on the
   process's CPU clock, and the CPU time a simulated second extrapolated
   to the plan's simulated time, writing not counted (a simulated sample
   costs some 100 times more than writing its 350 bytes). */
static void run_time(const scene *s, const sim_plan *p, int nthread, char *buf,
                     size_t sz) {
  est_cost c;
  size_t q, last = (size_t)-1, samples = 0;
  double cpu = 0.0, sim = 0.0;
  char when[64];
  for (q = 0; q < PILOT_CASES; q++) {
    size_t i = (s->ncase - 1) * q / (PILOT_CASES - 1);
    if (i == last) continue;
    last = i;
    if (pilot_case(s, i, &cpu, &sim, &samples)) {
      snprintf(buf, sz, "run time not estimated (out of memory)");
      return;
    }
  }
  if (!(sim > 0.0)) {
    snprintf(buf, sz,
             "run time not estimated (the cases timed stop at their start)");
    return;
  }
  /* est_when's unit of work: a simulated second */
  memset(&c, 0, sizeof c);
  c.sample = cpu / sim;
  snprintf(
      buf, sz,
      "run time %s (an estimate: %.3g s a simulated second, timed on "
      "%.3g simulated s, %zu sample%s)",
      est_when(&c, p->seconds, (double)s->ncase, nthread, when, sizeof when),
      c.sample, sim, samples, samples == 1 ? "" : "s");
}

/* every case into the file under its temporary name on nthread threads,
   renamed when complete: the exit code */
static int sim_write_file(const scene *s, const sim_plan *p, const sim_args *a,
                          int nthread) {
  progress pr;
  sweep_stats st = {0};
  sim_job J = {{s, NULL, &pr, &st, OUT_sim_status, OUT_message, 1},
               p->nt < SIM_WINDOW ? p->nt : SIM_WINDOW};
  out_meta meta = {.command_line = a->command_line, .gzip = a->gzip};
  pool_job job = {.ctx = &J,
                  .nitem = s->ncase,
                  .stride = 1,
                  .info_size = sizeof(out_tile),
                  .slot_size = sizeof(sim_tile),
                  .slot_make = tile_make,
                  .slot_free = tile_free,
                  .run = sim_item,
                  .write = sweep_write_tile};
  double *times = NULL;
  size_t k;
  int rc = -1;
  char err[768] = "out of memory";
  tmpout_clean(a->out_path, 0, 1);
  if (tmpout_name(a->out_path, 0)) return EXIT_USAGE;
  tmpout_arm();
  progress_start(&pr, s->ncase, a->quiet);
  pr.npoint = p->npoint;
  /* the common time axis, or none (the grid differs by case) */
  if (!p->common || (times = malloc(p->nt * sizeof *times))) {
    for (k = 0; times && k < p->nt; k++)
      times[k] = sim_case_time(&p->first, &p->sfirst, k);
    J.w.f = out_create(tmpout_path(), s, OUT_SIM, p->nt, times, J.points, NULL,
                       &meta, err, sizeof err);
  }
  free(times);
  if (J.w.f) {
    snprintf(err, sizeof err, "out of memory");
    rc = pool_run(&job, nthread, err, sizeof err);
    if (out_close(J.w.f, rc ? NULL : err, sizeof err) && rc == 0) rc = -1;
  }
  if (rc) fprintf(stderr, "rps3-run: %s: %s\n", a->out_path, err);
  if (rc || tmpout_commit(a->out_path)) {
    tmpout_discard();
    return EXIT_IO;
  }
  progress_finish(&pr, s->ncase, p->npoint, st.nfailed);
  return st.nfailed ? EXIT_FAILED_CASES : EXIT_OK;
}

int sim_main(const scene *s, const sim_args *a) {
  sim_plan p;
  scene_error serr;
  double need;
  int nthread;
  char when[160] = "";
  if (sim_plan_make(s, &p, &serr)) {
    scene_error_print(s->file, &serr);
    return EXIT_USAGE;
  }
  need = sim_file_bytes(s->ncase, p.npoint);
  if (a->sharded && !a->check) {
    fprintf(stderr,
            "rps3-run: %s: a simulated scene runs as one process: "
            "--shard, --resume and rps3-run-mpi are not supported "
            "(split the sweep into scenes instead)\n",
            s->file);
    return EXIT_USAGE;
  }
  /* -j beyond the cores or the cases computes nothing faster */
  nthread = pool_cores(a->nthread, 1);
  if ((size_t)nthread > s->ncase) nthread = (int)s->ncase;
  if (a->check || !a->quiet) run_time(s, &p, nthread, when, sizeof when);
  if (a->check) {
    est_check_print(s->file, "simulated: ", s->ncase, p.npoint, p.nt, p.common,
                    need);
    printf("%s\n", when);
    return EXIT_OK;
  }
  if (est_room(a->out_path, "simulated ", s->ncase, p.npoint, need, a->gzip,
               a->quiet, when))
    return EXIT_USAGE;
  return sim_write_file(s, &p, a, nthread);
}
