/*
 * sim_main.c - rps3-run on a simulated scene (simulate.h): check every
 * case, then simulate them (on this thread, case by case through
 * sim_run.c, or on -j threads through sim_pool.c) into the file of
 * sim_output.h, a window of samples at a time, under a temporary name
 * renamed when complete (tmpout.h).
 */
#include "core/exit_codes.h"
#include "core/safeio.h"
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

typedef struct {
  sim_sink base;
  sim_file *f;
  int common;
  char *err;
  size_t errsz;
} direct_sink;

static sim_tile *direct_put(sim_sink *k, sim_tile *t) {
  direct_sink *d = (direct_sink *)(void *)k;
  if ((t->nk > 0 &&
       sim_file_window(d->f, &t->w, t->c, t->k0, t->nk,
                       d->common ? NULL : t->times, d->err, d->errsz)) ||
      (t->last && sim_file_case(d->f, &t->v, t->c, d->err, d->errsz)))
    return NULL;
  return t;
}

/* every case on this thread */
static int run_direct(const scene *s, const sim_plan *p, sim_file *f,
                      progress *pr, size_t *nfailed, char *err, size_t errsz) {
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

/*
 * Simulate every case of s into f on nthread threads (1: this one);
 * *nfailed counts the cases with a status.  The file does not depend on
 * nthread.  Returns 0, or -1 with err set.
 */
static int sim_run_all(const scene *s, const sim_plan *p, sim_file *f,
                       int nthread, progress *pr, size_t *nfailed, char *err,
                       size_t errsz) {
  if (nthread <= 1 || s->ncase < 2)
    return run_direct(s, p, f, pr, nfailed, err, errsz);
  return sim_pool_run(s, p, f, nthread, pr, nfailed, err, errsz);
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

int sim_main(const scene *s, const sim_args *a) {
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
    fprintf(stderr,
            "rps3-run: %s: a simulated scene runs as one process: "
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
      fprintf(stderr,
              "rps3-run: warning: -j %d on %ld core%s: computing on "
              "%ld thread%s\n",
              nthread, cores, cores == 1 ? "" : "s", cores,
              cores == 1 ? "" : "s");
      nthread = (int)cores;
    }
    if ((size_t)nthread > s->ncase) nthread = (int)s->ncase;
  }
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
  avail = disk_free(a->out_path);
  if (!a->quiet)
    fprintf(stderr,
            "rps3-run: %zu simulated case%s, %zu samples: %s about "
            "%s%s, %s\n",
            s->ncase, s->ncase == 1 ? "" : "s", p.npoint, a->out_path,
            est_human(need, e1, sizeof e1),
            a->gzip ? " before compression" : "", when);
  if (avail >= 0 && need > avail && !a->gzip) {
    fprintf(stderr,
            "rps3-run: %s: the output needs about %s, the file "
            "system has %s free: nothing written\n",
            a->out_path, est_human(need, e1, sizeof e1),
            est_human(avail, e2, sizeof e2));
    return EXIT_USAGE;
  }
  tmpout_clean(a->out_path, 0, 1);
  if (tmpout_name(a->out_path, 0)) return EXIT_USAGE;
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
  rc = f ? sim_run_all(s, &p, f, nthread, &pr, &nfailed, err, sizeof err) : -1;
  if (f && sim_file_close(f, rc ? NULL : err, sizeof err) && rc == 0) rc = -1;
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
