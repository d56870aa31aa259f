/*
 * sim_main.c - rps3-run on a simulated scene (simulate.h): check every
 * case, then simulate them (sim_run.c) as a job of the worker pool
 * (pool.h, on this thread or on -j threads) into the file of
 * sim_output.h, a window of samples at a time, under a temporary name
 * renamed when complete (tmpout.h).
 */
#include "core/exit_codes.h"
#include "core/tmpout.h"
#include "estimate.h"
#include "sim_run.h"
#include "sweep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* a simulation as a job of the pool (pool.h): its items are the cases,
   its slots tiles */
typedef struct {
  const scene *s;
  const sim_plan *p;
  out_file *f;
  progress *pr;
  size_t done, points, nfailed;
} sim_job;

/* pool_job.run: case i on worker w */
static int sim_item(void *ctx, void *wctx, size_t i, pool_worker *w, char *err,
                    size_t errsz) {
  const sim_job *J = ctx;
  (void)wctx;
  return sim_run_case(J->s, i, w, err, errsz);
}

/* pool_job.write: one window (and the case's values with its last one) to
   the file, counted */
static int sim_write(void *ctx, void *slot, const void *info, char *err,
                     size_t errsz) {
  sim_job *J = ctx;
  const sim_tile *t = slot;
  (void)info;
  if ((t->nk > 0 &&
       sim_file_window(J->f, &t->w, t->c, t->k0, t->nk,
                       J->p->common ? NULL : t->times, err, errsz)) ||
      (t->last && sim_file_case(J->f, &t->v, t->c, err, errsz)))
    return -1;
  J->points += t->nk;
  if (t->last) {
    J->done++;
    if (t->v.status != RPS3_OK) {
      J->nfailed++;
      sim_failure(J->s, J->pr, t);
    }
    progress_update(J->pr, J->done, J->points);
  }
  return 0;
}

/*
 * Simulate every case of s into f on nthread threads (1: this one);
 * *nfailed counts the cases with a status.  The file does not depend on
 * nthread.  Returns 0, or -1 with err set.
 */
static int sim_run_all(const scene *s, const sim_plan *p, out_file *f,
                       int nthread, progress *pr, size_t *nfailed, char *err,
                       size_t errsz) {
  sim_job J;
  pool_job job;
  sim_tile *tiles;
  size_t i, nslot = pool_nslot(nthread);
  size_t points = p->nt < SIM_WINDOW ? p->nt : SIM_WINDOW;
  int rc = -1;
  memset(&J, 0, sizeof J);
  J.s = s;
  J.p = p;
  J.f = f;
  J.pr = pr;
  memset(&job, 0, sizeof job);
  job.ctx = &J;
  job.nitem = s->ncase;
  job.stride = 1;
  job.run = sim_item;
  job.write = sim_write;
  tiles = calloc(nslot, sizeof *tiles);
  job.slot = calloc(nslot, sizeof *job.slot);
  snprintf(err, errsz, "out of memory");
  for (i = 0; tiles && job.slot && i < nslot; i++) {
    if (sim_tile_alloc(&tiles[i], points)) break;
    job.slot[i] = &tiles[i];
  }
  if (tiles && job.slot && i == nslot) rc = pool_run(&job, nthread, err, errsz);
  for (i = 0; tiles && i < nslot; i++) sim_tile_free(&tiles[i]);
  free(tiles);
  free(job.slot);
  *nfailed = J.nfailed;
  return rc;
}

/* ---------------------------------------------------------- estimate */

/*
 * The run time of the plan on nthread threads into buf: the pilot's cases
 * (their controllers, integrators and steps differ), timed on the
 * process's CPU clock, and the CPU time a simulated second extrapolated
 * to the plan's simulated time, writing not counted (a simulated sample
 * costs some 100 times more than writing its 350 bytes).
 */
static void run_time(const scene *s, const sim_plan *p, int nthread, char *buf,
                     size_t sz) {
  est_cost c;
  size_t q, last = (size_t)-1, samples = 0;
  double cpu = 0.0, sim = 0.0;
  char when[32];
  for (q = 0; q < PILOT_CASES; q++) {
    size_t i = (s->ncase - 1) * q / (PILOT_CASES - 1);
    if (i == last) continue;
    last = i;
    if (sim_pilot_case(s, i, &cpu, &sim, &samples)) {
      snprintf(buf, sz, "run time not estimated (out of memory)");
      return;
    }
  }
  memset(&c, 0, sizeof c);
  if (sim > 0.0) {
    /* est_run_seconds's unit of work: a simulated second */
    c.sample = cpu / sim;
    snprintf(buf, sz,
             "run time about %s on %d thread%s (an estimate: %.3g "
             "s a simulated second, timed on %.3g simulated s, %zu "
             "sample%s)",
             est_human_time(
                 est_run_seconds(&c, p->seconds, (double)s->ncase, nthread),
                 when, sizeof when),
             nthread, nthread == 1 ? "" : "s", c.sample, sim, samples,
             samples == 1 ? "" : "s");
  } else
    snprintf(buf, sz,
             "run time not estimated (the cases timed stop at "
             "their start)");
}

/* the common time axis of the plan, or NULL (differs, or no memory) */
static double *time_axis(const sim_plan *p) {
  double *t;
  size_t k;
  if (!p->common || !(t = malloc(p->nt * sizeof *t))) return NULL;
  for (k = 0; k < p->nt; k++) t[k] = sim_case_time(&p->first, &p->sfirst, k);
  return t;
}

/* -j beyond the cores or the cases computes nothing faster */
static int sim_threads(const scene *s, int nthread) {
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (cores >= 1 && nthread > cores) {
    fprintf(stderr,
            "rps3-run: warning: -j %d on %ld core%s: computing on "
            "%ld thread%s\n",
            nthread, cores, cores == 1 ? "" : "s", cores,
            cores == 1 ? "" : "s");
    nthread = (int)cores;
  }
  if ((size_t)nthread > s->ncase) nthread = (int)s->ncase;
  return nthread;
}

/* every case into the file under its temporary name, renamed when
   complete: the exit code */
static int sim_write_file(const scene *s, const sim_plan *p, const sim_args *a,
                          int nthread) {
  progress pr;
  out_file *f;
  double *times;
  size_t nfailed = 0;
  int rc;
  char err[768];
  tmpout_clean(a->out_path, 0, 1);
  if (tmpout_name(a->out_path, 0)) return EXIT_USAGE;
  times = time_axis(p);
  if (p->common && !times) {
    fprintf(stderr, "rps3-run: out of memory\n");
    return EXIT_IO;
  }
  tmpout_arm();
  progress_start(&pr, s->ncase, a->quiet);
  pr.npoint = p->npoint;
  err[0] = '\0';
  f = sim_file_create(tmpout_path(), s, p->nt, times,
                      p->nt < SIM_WINDOW ? p->nt : SIM_WINDOW, a->gzip,
                      a->command_line, err, sizeof err);
  free(times);
  rc = f ? sim_run_all(s, p, f, nthread, &pr, &nfailed, err, sizeof err) : -1;
  if (f && out_close(f, rc ? NULL : err, sizeof err) && rc == 0) rc = -1;
  if (rc) {
    fprintf(stderr, "rps3-run: %s: %s\n", a->out_path, err);
    tmpout_discard();
    return EXIT_IO;
  }
  if (tmpout_commit(a->out_path)) {
    tmpout_discard();
    return EXIT_IO;
  }
  progress_finish(&pr, s->ncase, p->npoint, nfailed);
  return nfailed ? EXIT_FAILED_CASES : EXIT_OK;
}

int sim_main(const scene *s, const sim_args *a) {
  sim_plan p;
  scene_error serr;
  double need;
  int nthread;
  char e1[32], when[160] = "";
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
  nthread = sim_threads(s, a->nthread);
  if (a->check || !a->quiet) run_time(s, &p, nthread, when, sizeof when);
  if (a->check) {
    printf(
        "%s: simulated: %zu case%s, %zu samples (%zu per case at "
        "most)%s; output about %s uncompressed\n%s\n",
        s->file, s->ncase, s->ncase == 1 ? "" : "s", p.npoint, p.nt,
        p.common ? "" : ", time grid differs by case",
        est_human(need, e1, sizeof e1), when);
    return EXIT_OK;
  }
  if (est_room(a->out_path, "simulated ", s->ncase, p.npoint, need, a->gzip,
               a->quiet, when))
    return EXIT_USAGE;
  return sim_write_file(s, &p, a, nthread);
}
