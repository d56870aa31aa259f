/*
 * sim_run.c - one simulated case (simulate.h), window by window into the
 * tiles of sim_run.h; the whole run is sim_main.c's, a job of the worker
 * pool (pool.h).
 */
#include "sim_run.h"
#include "core/exit_codes.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "estimate.h"
#include "sweep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* the workspaces of one case */
typedef struct {
  rps3_sim *sim;
  rps3_ctrl *ctrl;
  rps3_data *ref; /* the reference motion, on the plant's geometry */
} sim_work;

static void work_free(sim_work *wk) {
  rps3_sim_free(wk->sim);
  rps3_ctrl_free(wk->ctrl);
  rps3_data_free(wk->ref);
  memset(wk, 0, sizeof *wk);
}

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

/* sample j of the window: the plant's state, the reference, the forces */
static void store(sim_window *w, sim_case_values *v, size_t j,
                  const rps3_sim *sim, const rps3_data *r, int first) {
  const rps3_data *d = rps3_sim_data(sim);
  const rps3_sim_report *now = rps3_sim_now(sim);
  double e;
  int i;
  for (i = 0; i < 3; i++) {
    size_t x = 3 * j + (size_t)i;
    w->buf[OUT_sim_length][x] = now->y[i];
    w->buf[OUT_sim_length_rate][x] = now->y[3 + i];
    w->buf[OUT_length_ref][x] = r->l[i];
    w->buf[OUT_length_rate_ref][x] = r->dl[i];
    e = r->l[i] - now->y[i];
    w->buf[OUT_tracking_error][x] = e;
    if (fabs(e) > v->tracking_error_max) v->tracking_error_max = fabs(e);
    /* no force has acted yet at the start */
    w->buf[OUT_force_cmd][x] = first ? (double)NAN : now->F_cmd[i];
    w->buf[OUT_sim_force][x] = first ? (double)NAN : now->F[i];
    w->buf[OUT_sim_theta][x] = d->theta[i];
  }
  w->buf[OUT_sim_alpha][j] = d->pose[0];
  w->buf[OUT_beta][j] = d->pose[1];
  w->buf[OUT_z_c][j] = d->pose[2];
  w->buf[OUT_x_c][j] = d->c[0];
  w->buf[OUT_y_c][j] = d->c[1];
  w->buf[OUT_alpha_ref][j] = r->pose[0];
  w->buf[OUT_beta_ref][j] = r->pose[1];
  w->buf[OUT_z_c_ref][j] = r->pose[2];
  w->buf[OUT_x_c_ref][j] = r->c[0];
  w->buf[OUT_y_c_ref][j] = r->c[1];
  w->buf[OUT_kinetic_energy][j] = now->T;
  w->buf[OUT_potential_energy][j] = now->P;
  w->buf[OUT_work_actuators][j] = now->y[6];
  w->buf[OUT_work_friction][j] = now->y[7];
  w->buf[OUT_sim_energy_residual][j] = now->energy_residual;
}

/* the message of a failure at sample k (time t_k): the simulation's, and
   the controller's own when it was the controller that failed */
static void failure(sim_case_values *w, const sim_work *wk, int st, size_t k,
                    double t_k) {
  const rps3_sim *sim = wk->sim;
  const rps3_data *meas = rps3_ctrl_measured(wk->ctrl);
  const rps3_data *des = rps3_ctrl_desired(wk->ctrl);
  const char *why = meas && meas->err.code != RPS3_OK ? meas->err.msg
                    : des && des->err.code != RPS3_OK ? des->err.msg
                                                      : "";
  double t = isnan(rps3_sim_now(sim)->failed_at) ? t_k : rps3_sim_now(sim)->failed_at;
  w->status = st;
  w->failed_at = (int32_t)k;
  w->failed_time = t;
  snprintf(w->message, sizeof w->message,
           "t = %.9g s (before sample %zu): "
           "%s: %s%s%s%s",
           t, k, rps3_strerror(st), rps3_sim_data(sim)->err.msg,
           why[0] && strstr(rps3_sim_data(sim)->err.msg, "controller") ? " (" : "",
           why[0] && strstr(rps3_sim_data(sim)->err.msg, "controller") ? why : "",
           why[0] && strstr(rps3_sim_data(sim)->err.msg, "controller") ? ")" : "");
}

/*
 * Where to advance for sample time t: the tick at t when t is one up to
 * rounding (k dt and k / rate differ in the last bit), so that the tick
 * at t is served by the next advance and the force stored with sample t
 * is the one held over the control period ending at t.  Within the
 * library's own slack (TICK_SLACK of src/sim.c, 1e-6 periods).
 */
static double tick_time(double t, double rate) {
  double j;
  if (!(rate > 0)) return t;
  j = floor(t * rate + 0.5);
  return fabs(t - j / rate) <= 1e-6 / rate ? j / rate : t;
}

int sim_tile_alloc(sim_tile *t, size_t points) {
  memset(t, 0, sizeof *t);
  if (sim_window_alloc(&t->w, points) ||
      !(t->times = malloc(points * sizeof *t->times))) {
    sim_window_free(&t->w);
    return -1;
  }
  return 0;
}

void sim_tile_free(sim_tile *t) {
  sim_window_free(&t->w);
  free(t->times);
  scene_text_free(&t->yaml);
  memset(t, 0, sizeof *t);
}

/* the simulation of case c and its controller, started on the trajectory
   (plus the start offset); 0, or -1 (memory: the plan built this case
   already) */
static int start(const scene_case *c, const sim_case *sc, sim_work *wk,
                 rps3_controller *ctl, int *st, char *err, size_t errsz) {
  double pose[3], dpose[3];
  rps3_check chk;
  int i, rc;
  memset(wk, 0, sizeof *wk);
  rc = rps3_sim_alloc(&c->model, &sc->opt, &wk->sim, &chk);
  if (rc == RPS3_OK)
    rc = rps3_ctrl_alloc(sc->kind, sc->kp, sc->kd, &sc->ctrl_model, &c->traj,
                         &wk->ctrl, &chk);
  if (rc == RPS3_OK && rps3_data_alloc(&c->model, &wk->ref) != RPS3_OK)
    rc = RPS3_ENOMEM;
  if (rc != RPS3_OK) {
    snprintf(err, errsz, "case %zu: %s", c->index,
             rc == RPS3_ENOMEM ? "out of memory" : chk.msg);
    work_free(wk);
    return -1;
  }
  *ctl = rps3_ctrl_bind(wk->ctrl, sc->rate);
  /* from the trajectory's start, at its rates */
  *st = rps3_traj_eval(&c->model, &c->traj, 0.0, pose, dpose, NULL);
  for (i = 0; i < 3; i++) pose[i] += c->v.sim.start_offset[i];
  if (*st == RPS3_OK) *st = rps3_sim_start(wk->sim, 0.0, pose, dpose);
  return 0;
}

/* hand the window of t over; the case's values with its last one */
static sim_tile *flush(pool_worker *w, sim_tile *t, size_t c, size_t k0,
                       size_t nk, const sim_case_values *v, int last, char *err,
                       size_t errsz) {
  t->c = c;
  t->k0 = k0;
  t->nk = nk;
  t->last = last;
  if (last) t->v = *v;
  return pool_emit(w, NULL, err, errsz);
}

int sim_run_case(const scene *s, size_t i, pool_worker *w, char *err,
                 size_t errsz) {
  sim_tile *t = pool_slot(w);
  scene_case c;
  sim_case sc;
  scene_error serr;
  sim_work wk;
  rps3_controller ctl;
  sim_case_values v;
  size_t n, j = 0, k0 = 0;
  int st;
  if (scene_case_build(s, i, &c, &serr) || sim_case_build(s, &c, &sc, &serr)) {
    snprintf(err, errsz, "case %zu: %s", i, serr.what);
    return -1;
  }
  if (start(&c, &sc, &wk, &ctl, &st, err, errsz)) return -1;
  memset(&v, 0, sizeof v);
  v.failed_time = (double)NAN;
  v.failed_at = -1;
  for (n = 0; n < sc.nt && t; n++) {
    double tn = sim_case_time(&c, &sc, n);
    if (st == RPS3_OK && n > 0)
      /* a tick just behind the state (samples closer than the slack) is
         the state's time: the library refuses a t_end before it */
      st = rps3_sim_advance(wk.sim, &ctl,
                            fmax(tick_time(tn, sc.rate), rps3_sim_now(wk.sim)->t));
    if (st == RPS3_OK) st = reference(&c, wk.ref, tn);
    if (st != RPS3_OK) {
      failure(&v, &wk, st, n, tn);
      break;
    }
    store(&t->w, &v, j, wk.sim, wk.ref, n == 0);
    t->times[j] = tn;
    if (++j == t->w.points && n + 1 < sc.nt) {
      t = flush(w, t, i, k0, j, &v, 0, err, errsz);
      k0 += j;
      j = 0;
    }
  }
  v.nsteps = rps3_sim_now(wk.sim)->nsteps;
  v.nevals = rps3_sim_now(wk.sim)->nevals;
  v.nticks = rps3_sim_now(wk.sim)->nticks;
  v.nsat = rps3_sim_now(wk.sim)->nsat;
  work_free(&wk);
  /* the samples up to the end or the failure (those after a failure keep
     the fill, NaN), with the case's values and its resolved scene */
  if (t && scene_case_yaml(&c, &t->yaml)) {
    snprintf(err, errsz, "case %zu: cannot write its scene", i);
    return -1;
  }
  if (t) {
    v.scene_resolved = t->yaml.s;
    t = flush(w, t, i, k0, j, &v, 1, err, errsz);
  }
  return t ? 0 : -1;
}

/* the first failed case's reason on stderr (progress_failure) */
void sim_failure(const scene *s, progress *pr, const sim_tile *t) {
  char what[512];
  if (pr->failure_shown) return;
  sweep_case_label(s, t->c, what, sizeof what);
  progress_failure(pr, t->c, what, t->v.message);
}

static double cpu_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* control periods or integrator steps a simulated second of case sc (the
   finer of the two; the adaptive methods' first step stands for theirs) */
static double work_rate(const sim_case *sc) {
  double steps = 1.0 / sc->opt.h;
  return sc->rate > steps ? sc->rate : steps;
}

/*
 * Case i simulated as the run does (its samples' references included) up
 * to the pilot's budget: adds the CPU seconds and the simulated seconds it
 * covered to *cpu and *sim, the samples to *samples.  -1 when the case
 * cannot be set up (memory).
 */
int sim_pilot_case(const scene *s, size_t i, double *cpu, double *sim,
                   size_t *samples) {
  scene_case c;
  sim_case sc;
  scene_error serr;
  sim_work wk;
  rps3_controller ctl;
  double c0 = cpu_seconds(), t_stop, chunk, t = 0.0;
  size_t n, nrun;
  int st;
  char err[256];
  if (scene_case_build(s, i, &c, &serr) || sim_case_build(s, &c, &sc, &serr))
    return -1;
  if (start(&c, &sc, &wk, &ctl, &st, err, sizeof err)) return -1;
  nrun = sc.nt < PILOT_SAMPLES ? sc.nt : PILOT_SAMPLES;
  t_stop = PILOT_WORK / work_rate(&sc);
  chunk = PILOT_CHUNK / work_rate(&sc);
  for (n = 0; n < nrun && st == RPS3_OK; n++) {
    double tn = sim_case_time(&c, &sc, n);
    if (n > 0) tn = tick_time(tn, sc.rate);
    /* the sample's time in chunks, each against the budget */
    while (st == RPS3_OK && rps3_sim_now(wk.sim)->t < tn) {
      t = rps3_sim_now(wk.sim)->t + chunk < tn ? rps3_sim_now(wk.sim)->t + chunk : tn;
      if (t > t_stop) t = t_stop > rps3_sim_now(wk.sim)->t ? t_stop : rps3_sim_now(wk.sim)->t;
      if (t <= rps3_sim_now(wk.sim)->t || cpu_seconds() - c0 > PILOT_CPU) break;
      st = rps3_sim_advance(wk.sim, &ctl, t);
    }
    if (st != RPS3_OK || rps3_sim_now(wk.sim)->t < tn) break;
    if (reference(&c, wk.ref, tn) != RPS3_OK) break;
    ++*samples;
  }
  *sim += rps3_sim_now(wk.sim)->t;
  *cpu += cpu_seconds() - c0;
  work_free(&wk);
  return 0;
}
