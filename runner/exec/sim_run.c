/*
 * sim_run.c - rps3-run on a simulated scene (simulate.h): check every
 * case, then simulate them (on this thread, or on -j threads through
 * sim_pool.c) into the file of sim_output.h, a window of samples at a
 * time, under a temporary name renamed when complete (tmpout.h).
 */
#include "sim_run.h"
#include "sweep.h"
#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "estimate.h"
#include "core/safeio.h"

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
static void store(sim_window *w, sim_case_values *v, size_t j,
                  const rps3_sim *sim, const rps3_data *r, int first)
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
    if (fabs(e) > v->tracking_error_max)
      v->tracking_error_max = fabs(e);
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
static void failure(sim_case_values *w, const sim_work *wk, int st, size_t k,
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

int sim_tile_alloc(sim_tile *t, size_t points)
{
  memset(t, 0, sizeof *t);
  if (sim_window_alloc(&t->w, points) ||
      !(t->times = malloc(points * sizeof *t->times))) {
    sim_window_free(&t->w);
    return -1;
  }
  return 0;
}

void sim_tile_free(sim_tile *t)
{
  sim_window_free(&t->w);
  free(t->times);
  scene_text_free(&t->yaml);
  memset(t, 0, sizeof *t);
}

/* the simulation of case c and its controller, started on the trajectory
   (plus the start offset); 0, or -1 (memory: the plan built this case
   already) */
static int start(const scene_case *c, const sim_case *sc, sim_work *wk,
                 rps3_controller *ctl, int *st, char *err, size_t errsz)
{
  double pose[3], dpose[3];
  char msg[320] = "out of memory";
  int i;
  memset(wk, 0, sizeof *wk);
  if (rps3_sim_alloc(&c->model, &sc->opt, &wk->sim, msg, sizeof msg) ||
      rps3_ctrl_alloc(sc->kind, sc->kp, sc->kd, &sc->ctrl_model, &c->traj,
                      &wk->ctrl, msg, sizeof msg) ||
      rps3_data_alloc(&c->model, &wk->ref)) {
    snprintf(err, errsz, "case %zu: %s", c->index, msg);
    work_free(wk);
    return -1;
  }
  ctl->fn = rps3_ctrl_update;
  ctl->state = wk->ctrl;
  ctl->rate = sc->rate;
  /* from the trajectory's start, at its rates */
  *st = rps3_traj_eval(&c->model, &c->traj, 0.0, pose, dpose, NULL);
  for (i = 0; i < 3; i++)
    pose[i] += c->v.sim.start_offset[i];
  if (*st == RPS3_OK)
    *st = rps3_sim_start(wk->sim, 0.0, pose, dpose);
  return 0;
}

/* hand the window of t over; the case's values with its last one */
static sim_tile *flush(sim_sink *k, sim_tile *t, size_t c, size_t k0,
                       size_t nk, const sim_case_values *v, int last)
{
  t->c = c;
  t->k0 = k0;
  t->nk = nk;
  t->last = last;
  if (last)
    t->v = *v;
  return k->put(k, t);
}

sim_tile *sim_run_case(const scene *s, size_t i, size_t limit, sim_tile *t,
                       sim_sink *k, char *err, size_t errsz)
{
  scene_case c;
  sim_case sc;
  scene_error serr;
  sim_work wk;
  rps3_controller ctl;
  sim_case_values v;
  size_t n, nrun, j = 0, k0 = 0;
  int st;
  if (scene_case_build(s, i, &c, &serr) || sim_case_build(s, &c, &sc, &serr)) {
    snprintf(err, errsz, "case %zu: %s", i, serr.what);
    return NULL;
  }
  /* the pilot of the estimate runs the first samples only */
  nrun = sc.nt < limit ? sc.nt : limit;
  if (start(&c, &sc, &wk, &ctl, &st, err, errsz))
    return NULL;
  memset(&v, 0, sizeof v);
  v.failed_time = (double)NAN;
  v.failed_at = -1;
  for (n = 0; n < nrun && t; n++) {
    double tn = sim_case_time(&c, &sc, n);
    if (st == RPS3_OK && n > 0)
      /* a tick just behind the state (samples closer than the slack) is
         the state's time: the library refuses a t_end before it */
      st = rps3_sim_advance(wk.sim, &ctl,
                            fmax(tick_time(tn, sc.rate), wk.sim->t));
    if (st == RPS3_OK)
      st = reference(&c, wk.ref, tn);
    if (st != RPS3_OK) {
      failure(&v, &wk, st, n, tn);
      break;
    }
    store(&t->w, &v, j, wk.sim, wk.ref, n == 0);
    t->times[j] = tn;
    if (++j == t->w.points && n + 1 < nrun) {
      t = flush(k, t, i, k0, j, &v, 0);
      k0 += j;
      j = 0;
    }
  }
  v.nsteps = wk.sim->nsteps;
  v.nevals = wk.sim->nevals;
  v.nticks = wk.sim->nticks;
  v.nsat = wk.sim->nsat;
  work_free(&wk);
  /* the samples up to the end or the failure (those after a failure keep
     the fill, NaN), with the case's values and its resolved scene */
  if (t && scene_case_yaml(&c, &t->yaml)) {
    snprintf(err, errsz, "case %zu: cannot write its scene", i);
    return NULL;
  }
  if (t) {
    v.scene_resolved = t->yaml.s;
    t = flush(k, t, i, k0, j, &v, 1);
  }
  return t;
}

/* ---------------------------------------------------------- one thread */

/* the sink of one thread: write at once */
typedef struct {
  sim_sink base;
  sim_file *f;
  int common;
  char *err;
  size_t errsz;
} direct_sink;

static sim_tile *direct_put(sim_sink *k, sim_tile *t)
{
  direct_sink *d = (direct_sink *)(void *)k;
  if ((t->nk > 0 && sim_file_window(d->f, &t->w, t->c, t->k0, t->nk,
                                    d->common ? NULL : t->times, d->err,
                                    d->errsz)) ||
      (t->last && sim_file_case(d->f, &t->v, t->c, d->err, d->errsz)))
    return NULL;
  return t;
}

/* every case on this thread */
/* the first failed case's reason on stderr (progress_failure) */
void sim_failure(const scene *s, progress *pr, const sim_tile *t)
{
  char what[512];
  if (pr->failure_shown)
    return;
  sweep_case_label(s, t->c, what, sizeof what);
  progress_failure(pr, t->c, what, t->v.message);
}

static int run_direct(const scene *s, const sim_plan *p, sim_file *f,
                      progress *pr, size_t *nfailed, char *err, size_t errsz)
{
  direct_sink d;
  sim_tile tile, *t = &tile;
  size_t i, points = 0;
  if (sim_tile_alloc(&tile, p->nt < SIM_WINDOW ? p->nt : SIM_WINDOW)) {
    snprintf(err, errsz, "out of memory");
    return -1;
  }
  d.base.put = direct_put;
  d.f = f;
  d.common = p->common;
  d.err = err;
  d.errsz = errsz;
  for (i = 0; i < s->ncase && t; i++) {
    t = sim_run_case(s, i, (size_t)-1, t, &d.base, err, errsz);
    if (t && t->v.status != RPS3_OK) {
      ++*nfailed;
      sim_failure(s, pr, t);
    }
    points += t ? t->k0 + t->nk : 0;
    progress_update(pr, i + 1, points);
  }
  sim_tile_free(&tile);
  return t ? 0 : -1;
}

int sim_run_all(const scene *s, const sim_plan *p, sim_file *f, int nthread,
                progress *pr, size_t *nfailed, char *err, size_t errsz)
{
  if (nthread <= 1 || s->ncase < 2)
    return run_direct(s, p, f, pr, nfailed, err, errsz);
  return sim_pool_run(s, p, f, nthread, pr, nfailed, err, errsz);
}

/* ---------------------------------------------------------- estimate */

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

static double cpu_seconds(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* control periods or integrator steps a simulated second of case sc (the
   finer of the two; the adaptive methods' first step stands for theirs) */
static double work_rate(const sim_case *sc)
{
  double steps = 1.0 / sc->opt.h;
  return sc->rate > steps ? sc->rate : steps;
}

/*
 * Case i simulated as the run does (its samples' references included) up
 * to the pilot's budget: adds the CPU seconds and the simulated seconds it
 * covered to *cpu and *sim, the samples to *samples.  -1 when the case
 * cannot be set up (memory).
 */
static int pilot_case(const scene *s, size_t i, double *cpu, double *sim,
                      size_t *samples)
{
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
  if (start(&c, &sc, &wk, &ctl, &st, err, sizeof err))
    return -1;
  nrun = sc.nt < PILOT_SAMPLES ? sc.nt : PILOT_SAMPLES;
  t_stop = PILOT_WORK / work_rate(&sc);
  chunk = PILOT_CHUNK / work_rate(&sc);
  for (n = 0; n < nrun && st == RPS3_OK; n++) {
    double tn = sim_case_time(&c, &sc, n);
    if (n > 0)
      tn = tick_time(tn, sc.rate);
    /* the sample's time in chunks, each against the budget */
    while (st == RPS3_OK && wk.sim->t < tn) {
      t = wk.sim->t + chunk < tn ? wk.sim->t + chunk : tn;
      if (t > t_stop)
        t = t_stop > wk.sim->t ? t_stop : wk.sim->t;
      if (t <= wk.sim->t || cpu_seconds() - c0 > PILOT_CPU)
        break;
      st = rps3_sim_advance(wk.sim, &ctl, t);
    }
    if (st != RPS3_OK || wk.sim->t < tn)
      break;
    if (reference(&c, wk.ref, tn) != RPS3_OK)
      break;
    ++*samples;
  }
  *sim += wk.sim->t;
  *cpu += cpu_seconds() - c0;
  work_free(&wk);
  return 0;
}

/*
 * The run time of the plan on nthread threads into buf: the pilot's cases
 * (their controllers, integrators and steps differ), timed on the
 * process's CPU clock, and the CPU time a simulated second extrapolated
 * to the plan's simulated time, writing not counted (a simulated sample
 * costs some 100 times more than writing its 350 bytes).
 */
static void run_time(const scene *s, const sim_plan *p, int nthread,
                     char *buf, size_t sz)
{
  est_cost c;
  size_t q, last = (size_t)-1, samples = 0;
  double cpu = 0.0, sim = 0.0;
  char when[32];
  for (q = 0; q < PILOT_CASES; q++) {
    size_t i = (s->ncase - 1) * q / (PILOT_CASES - 1);
    if (i == last)
      continue;
    last = i;
    if (pilot_case(s, i, &cpu, &sim, &samples)) {
      snprintf(buf, sz, "run time not estimated (out of memory)");
      return;
    }
  }
  memset(&c, 0, sizeof c);
  if (sim > 0.0) {
    /* est_run_seconds's unit of work: a simulated second */
    c.sample = cpu / sim;
    snprintf(buf, sz, "run time about %s on %d thread%s (an estimate: %.3g "
             "s a simulated second, timed on %.3g simulated s, %zu "
             "sample%s)",
             est_human_time(est_run_seconds(&c, p->seconds, (double)s->ncase,
                                            nthread),
                            when, sizeof when),
             nthread, nthread == 1 ? "" : "s", c.sample, sim, samples,
             samples == 1 ? "" : "s");
  } else
    snprintf(buf, sz, "run time not estimated (the cases timed stop at "
             "their start)");
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
  int rc, nthread;
  char err[768], e1[32], e2[32], when[160] = "";
  if (sim_plan_make(s, &p, &serr)) {
    scene_error_print(s->file, &serr);
    return EXIT_USAGE;
  }
  need = sim_file_bytes(s->ncase, p.npoint);
  if (a->sharded && !a->check) {
    fprintf(stderr, "rps3-run: %s: a simulated scene runs as one process: "
                    "--shard, --resume and rps3-run-mpi are not supported "
                    "(split the sweep into scenes instead)\n",
            s->file);
    return EXIT_USAGE;
  }
  {
    /* threads beyond the cores or the cases compute nothing faster */
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    nthread = a->nthread;
    if (cores >= 1 && nthread > cores) {
      fprintf(stderr, "rps3-run: warning: -j %d on %ld core%s: computing on "
                      "%ld thread%s\n",
              nthread, cores, cores == 1 ? "" : "s", cores,
              cores == 1 ? "" : "s");
      nthread = (int)cores;
    }
    if ((size_t)nthread > s->ncase)
      nthread = (int)s->ncase;
  }
  if (a->check || !a->quiet)
    run_time(s, &p, nthread, when, sizeof when);
  if (a->check) {
    printf("%s: simulated: %zu case%s, %zu samples (%zu per case at "
           "most)%s; output about %s uncompressed\n%s\n",
           s->file, s->ncase, s->ncase == 1 ? "" : "s", p.npoint, p.nt,
           p.common ? "" : ", time grid differs by case",
           est_human(need, e1, sizeof e1), when);
    return EXIT_OK;
  }
  avail = disk_free(a->out_path);
  if (!a->quiet)
    fprintf(stderr, "rps3-run: %zu simulated case%s, %zu samples: %s about "
                    "%s%s, %s\n",
            s->ncase, s->ncase == 1 ? "" : "s", p.npoint, a->out_path,
            est_human(need, e1, sizeof e1),
            a->gzip ? " before compression" : "", when);
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
  pr.npoint = p.npoint;
  err[0] = '\0';
  f = sim_file_create(tmpout_path(), s, p.nt, times,
                      p.nt < SIM_WINDOW ? p.nt : SIM_WINDOW, a->gzip,
                      a->command_line, err, sizeof err);
  free(times);
  rc = f ? sim_run_all(s, &p, f, nthread, &pr, &nfailed, err, sizeof err)
         : -1;
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
