/*
 * simulate.c - see simulate.h: the cases of sim_case.c simulated on the
 * worker pool (its items the cases, its slots windows of samples) into a
 * file under a temporary name, renamed when complete (tmpout.h).
 */
#include "simulate.h"
#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "estimate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
