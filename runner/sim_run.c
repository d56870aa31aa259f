/*
 * sim_run.c - rps3-run on a simulated scene (simulate.h): check every
 * case, then simulate them one after the other into the file of
 * sim_output.h, a window of samples at a time, under a temporary name
 * renamed when complete (tmpout.h).
 */
#include "cmd.h"
#include "estimate.h"
#include "progress.h"
#include "safeio.h"
#include "sim_output.h"
#include "simulate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* samples per window (and chunk) of a case: memory does not grow with the
   length of a case */
#define SIM_WINDOW 4096

/* the workspaces of one case */
typedef struct {
  rps3_sim *sim;
  rps3_ctrl *ctrl;
  rps3_data *ref;   /* the reference motion, on the plant's geometry */
} sim_work;

static void work_free(sim_work *wk)
{
  rps3_sim_free(wk->sim);
  rps3_ctrl_free(wk->ctrl);
  rps3_data_free(wk->ref);
  memset(wk, 0, sizeof *wk);
}

/* the reference at t: the trajectory, after its span its final pose at
   rest, through the closed-form inverse kinematics */
static int reference(const scene_case *c, rps3_data *r, double t)
{
  int st, rest = t > c->span;
  st = rps3_traj_eval(&c->model, &c->traj, rest ? c->span : t, r->pose,
                      r->dpose, r->ddpose);
  if (st != RPS3_OK)
    return st;
  if (rest)
    r->dpose[0] = r->dpose[1] = r->dpose[2] = 0.0;
  st = rps3_ik(&c->model, r);
  return st == RPS3_OK ? rps3_velocity(&c->model, r) : st;
}

/* sample j of the window: the plant's state, the reference, the forces */
static void store(sim_window *w, size_t j, const rps3_sim *sim,
                  const rps3_data *r, int first)
{
  const rps3_data *d = sim->d;
  double e;
  int i;
  for (i = 0; i < 3; i++) {
    size_t x = 3 * j + (size_t)i;
    w->buf[SIM_length][x] = sim->y[i];
    w->buf[SIM_length_rate][x] = sim->y[3 + i];
    w->buf[SIM_length_ref][x] = r->l[i];
    w->buf[SIM_length_rate_ref][x] = r->dl[i];
    e = r->l[i] - sim->y[i];
    w->buf[SIM_tracking_error][x] = e;
    if (fabs(e) > w->tracking_error_max)
      w->tracking_error_max = fabs(e);
    /* no force has acted yet at the start */
    w->buf[SIM_force_cmd][x] = first ? (double)NAN : sim->F_cmd[i];
    w->buf[SIM_force][x] = first ? (double)NAN : sim->F[i];
    w->buf[SIM_theta][x] = d->theta[i];
  }
  w->buf[SIM_alpha][j] = d->pose[0];
  w->buf[SIM_beta][j] = d->pose[1];
  w->buf[SIM_z_c][j] = d->pose[2];
  w->buf[SIM_x_c][j] = d->c[0];
  w->buf[SIM_y_c][j] = d->c[1];
  w->buf[SIM_alpha_ref][j] = r->pose[0];
  w->buf[SIM_beta_ref][j] = r->pose[1];
  w->buf[SIM_z_c_ref][j] = r->pose[2];
  w->buf[SIM_x_c_ref][j] = r->c[0];
  w->buf[SIM_y_c_ref][j] = r->c[1];
  w->buf[SIM_kinetic_energy][j] = sim->T;
  w->buf[SIM_potential_energy][j] = sim->P;
  w->buf[SIM_work_actuators][j] = sim->y[6];
  w->buf[SIM_work_friction][j] = sim->y[7];
  w->buf[SIM_energy_residual][j] = sim->energy_residual;
}

/* the message of a failure at sample k (time t_k): the simulation's, and
   the controller's own when it was the controller that failed */
static void failure(sim_window *w, const sim_work *wk, int st, size_t k,
                    double t_k)
{
  const rps3_sim *sim = wk->sim;
  const rps3_ctrl *ctrl = wk->ctrl;
  const char *why = ctrl && ctrl->meas->err.code != RPS3_OK
                        ? ctrl->meas->err.msg
                    : ctrl && ctrl->des->err.code != RPS3_OK
                        ? ctrl->des->err.msg
                        : "";
  double t = isnan(sim->failed_at) ? t_k : sim->failed_at;
  w->status = st;
  w->failed_at = (int32_t)k;
  w->failed_time = t;
  snprintf(w->message, sizeof w->message, "t = %.9g s (before sample %zu): "
           "%s: %s%s%s%s", t, k, rps3_strerror(st), sim->d->err.msg,
           why[0] && strstr(sim->d->err.msg, "controller") ? " (" : "",
           why[0] && strstr(sim->d->err.msg, "controller") ? why : "",
           why[0] && strstr(sim->d->err.msg, "controller") ? ")" : "");
}

/*
 * Where to advance for sample time t: the tick at t when t is one up to
 * rounding (k dt and k / rate differ in the last bit), so that the tick
 * at t is served by the next advance and the force stored with sample t
 * is the one held over the control period ending at t.  Within the
 * library's own slack (TICK_SLACK of src/sim.c, 1e-6 periods).
 */
static double tick_time(double t, double rate)
{
  double j;
  if (!(rate > 0))
    return t;
  j = floor(t * rate + 0.5);
  return fabs(t - j / rate) <= 1e-6 / rate ? j / rate : t;
}

/* simulate case c into the file; 0, or -1 (file or memory) with err */
static int run_case(const scene_case *c, const sim_case *sc, sim_file *f,
                    sim_window *w, double *times, int common, char *err,
                    size_t errsz)
{
  sim_work wk;
  rps3_controller ctl;
  double pose[3], dpose[3];
  size_t k, j = 0, k0 = 0;
  int st;
  char msg[320];
  memset(&wk, 0, sizeof wk);
  w->tracking_error_max = 0;
  w->failed_time = (double)NAN;
  w->status = RPS3_OK;
  w->failed_at = -1;
  w->message[0] = '\0';
  if (rps3_sim_alloc(&c->model, &sc->opt, &wk.sim, msg, sizeof msg) ||
      rps3_ctrl_alloc(sc->kind, sc->kp, sc->kd, &sc->ctrl_model, &c->traj,
                      &wk.ctrl, msg, sizeof msg) ||
      rps3_data_alloc(&c->model, &wk.ref)) {
    /* the plan built this case already: only memory can fail here */
    snprintf(err, errsz, "case %zu: %s", c->index, msg);
    work_free(&wk);
    return -1;
  }
  ctl.fn = rps3_ctrl_update;
  ctl.state = wk.ctrl;
  ctl.rate = sc->rate;
  /* from the trajectory's start, at its rates */
  st = rps3_traj_eval(&c->model, &c->traj, 0.0, pose, dpose, NULL);
  if (st == RPS3_OK)
    st = rps3_sim_start(wk.sim, 0.0, pose, dpose);
  for (k = 0; k < sc->nt; k++) {
    double t = sim_case_time(c, sc, k);
    if (st == RPS3_OK && k > 0)
      st = rps3_sim_advance(wk.sim, &ctl, tick_time(t, sc->rate));
    if (st == RPS3_OK)
      st = reference(c, wk.ref, t);
    if (st != RPS3_OK) {
      failure(w, &wk, st, k, t);
      break;
    }
    store(w, j, wk.sim, wk.ref, k == 0);
    times[j] = t;
    if (++j == w->points || k + 1 == sc->nt) {
      if (sim_file_window(f, w, c->index, k0, j, common ? NULL : times, err,
                          errsz)) {
        work_free(&wk);
        return -1;
      }
      k0 += j;
      j = 0;
    }
  }
  /* the samples before a failure; those after it keep the fill, NaN */
  if (j > 0 && sim_file_window(f, w, c->index, k0, j, common ? NULL : times,
                               err, errsz)) {
    work_free(&wk);
    return -1;
  }
  w->nsteps = wk.sim->nsteps;
  w->nevals = wk.sim->nevals;
  w->nticks = wk.sim->nticks;
  w->nsat = wk.sim->nsat;
  work_free(&wk);
  return 0;
}

/* simulate every case of s into the open file; 0 or -1 with err */
static int run_all(const scene *s, const sim_plan *p, sim_file *f,
                   progress *pr, size_t *nfailed, char *err, size_t errsz)
{
  sim_window w;
  scene_text yaml;
  scene_case c;
  sim_case sc;
  scene_error serr;
  double *times = NULL;
  size_t i, points = 0;
  int rc = 0;
  memset(&yaml, 0, sizeof yaml);
  if (sim_window_alloc(&w, p->nt < SIM_WINDOW ? p->nt : SIM_WINDOW) ||
      !(times = malloc(w.points * sizeof *times))) {
    snprintf(err, errsz, "out of memory");
    sim_window_free(&w);
    return -1;
  }
  for (i = 0; i < s->ncase && rc == 0; i++) {
    if (scene_case_build(s, i, &c, &serr) ||
        sim_case_build(s, &c, &sc, &serr)) {
      snprintf(err, errsz, "case %zu: %s", i, serr.what);
      rc = -1;
      break;
    }
    if (scene_case_yaml(&c, &yaml)) {
      snprintf(err, errsz, "case %zu: cannot write its scene", i);
      rc = -1;
      break;
    }
    w.scene_resolved = yaml.s;
    rc = run_case(&c, &sc, f, &w, times, p->common, err, errsz);
    if (rc == 0)
      rc = sim_file_case(f, &w, i, err, errsz);
    if (w.status != RPS3_OK)
      ++*nfailed;
    points += sc.nt;
    progress_update(pr, i + 1, points);
  }
  scene_text_free(&yaml);
  sim_window_free(&w);
  free(times);
  return rc;
}

/* the common time axis of the plan, or NULL (differs, or no memory) */
static double *time_axis(const sim_plan *p)
{
  double *t;
  size_t k;
  if (!p->common || !(t = malloc(p->nt * sizeof *t)))
    return NULL;
  for (k = 0; k < p->nt; k++)
    t[k] = sim_case_time(&p->first, &p->sfirst, k);
  return t;
}

int sim_main(const scene *s, const sim_args *a)
{
  sim_plan p;
  scene_error serr;
  progress pr;
  sim_file *f;
  double *times, need, avail;
  size_t nfailed = 0;
  int rc;
  char err[768], e1[32], e2[32];
  if (sim_plan_make(s, &p, &serr)) {
    scene_error_print(s->file, &serr);
    return EXIT_USAGE;
  }
  need = sim_file_bytes(s->ncase, p.npoint);
  if (a->check) {
    printf("%s: simulated: %zu case%s, %zu samples (%zu per case at "
           "most)%s; output about %s uncompressed\n",
           s->file, s->ncase, s->ncase == 1 ? "" : "s", p.npoint, p.nt,
           p.common ? "" : ", time grid differs by case",
           est_human(need, e1, sizeof e1));
    return EXIT_OK;
  }
  if (a->sharded) {
    fprintf(stderr, "rps3-run: %s: a simulated scene runs as one process: "
                    "--shard, --resume and rps3-run-mpi are not supported "
                    "(split the sweep into scenes instead)\n",
            s->file);
    return EXIT_USAGE;
  }
  if (a->nthread > 1)
    fprintf(stderr, "rps3-run: warning: -j %d: a simulated scene computes "
                    "on one thread\n",
            a->nthread);
  avail = disk_free(a->out_path);
  if (!a->quiet)
    fprintf(stderr, "rps3-run: %zu simulated case%s, %zu samples: %s about "
                    "%s%s\n",
            s->ncase, s->ncase == 1 ? "" : "s", p.npoint, a->out_path,
            est_human(need, e1, sizeof e1),
            a->gzip ? " before compression" : "");
  if (avail >= 0 && need > avail && !a->gzip) {
    fprintf(stderr, "rps3-run: %s: the output needs about %s, the file "
                    "system has %s free: nothing written\n",
            a->out_path, est_human(need, e1, sizeof e1),
            est_human(avail, e2, sizeof e2));
    return EXIT_USAGE;
  }
  tmpout_clean(a->out_path, 0, 1);
  if (tmpout_name(a->out_path, 0))
    return EXIT_USAGE;
  times = time_axis(&p);
  if (p.common && !times) {
    fprintf(stderr, "rps3-run: out of memory\n");
    return EXIT_IO;
  }
  tmpout_arm();
  progress_start(&pr, s->ncase, a->quiet);
  err[0] = '\0';
  f = sim_file_create(tmpout_path(), s, p.nt, times,
                      p.nt < SIM_WINDOW ? p.nt : SIM_WINDOW, a->gzip,
                      a->command_line, err, sizeof err);
  free(times);
  rc = f ? run_all(s, &p, f, &pr, &nfailed, err, sizeof err) : -1;
  if (f && sim_file_close(f, rc ? NULL : err, sizeof err) && rc == 0)
    rc = -1;
  if (rc) {
    fprintf(stderr, "rps3-run: %s: %s\n", a->out_path, err);
    tmpout_discard();
    return EXIT_IO;
  }
  if (tmpout_commit(a->out_path)) {
    tmpout_discard();
    return EXIT_IO;
  }
  progress_finish(&pr, s->ncase, p.npoint, nfailed);
  return nfailed ? EXIT_FAILED_CASES : EXIT_OK;
}
