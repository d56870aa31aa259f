/*
 * sweep_int.h - what sweep.c (plan, jobs, the serial run) shares with
 * sweep_threads.c (the threaded run); not for the programs (they use
 * sweep.h).
 */
#ifndef RPS3_RUNNER_SWEEP_INT_H
#define RPS3_RUNNER_SWEEP_INT_H

#include <stddef.h>

#include "rps3.h"

#include "core/progress.h"
#include "output/output.h"
#include "scene/scene.h"
#include "sweep.h"

/* a filled block to write: slots [0, nc) are cases c0 .., samples
   [k0, k0 + nk); and what it adds to the run's counts */
typedef struct {
  size_t c0, nc, k0, nk;
  int with_case;      /* write the per-case fields too */
  size_t blank_below; /* > 0: first write the (blank) block over the windows
                         [0, blank_below) of case c0: a late failure */
  size_t cases;       /* cases this tile completes */
  size_t points;      /* samples computed */
  size_t failed;      /* cases that failed */
} tile;

/* where a job's tiles go: emit() takes the filled *b and sets *b to the
   block to fill next; returns 0, or -1 with err set */
typedef struct sink sink;
struct sink {
  int (*emit)(sink *k, out_block **b, const tile *t, char *err, size_t errsz);
};

/* write tile t of block b to f */
int sweep_tile_write(out_file *f, const out_block *b, const tile *t, char *err,
                     size_t errsz);

/* count a written tile of block b and show the progress, and the reason
   of the run's first failed case (also when quiet) */
void sweep_tile_count(const scene *s, const out_block *b, const tile *t,
                      sweep_stats *st, progress *pr);

/* the job after j of a shard of nshard, or nj when none */
size_t sweep_next_job(size_t j, size_t nshard, size_t nj);

/* compute job j of plan p into *bp (a tile of whole cases, or one long
   case in windows), handing each filled tile to k; ws holds the
   workspaces, one per solver kind, allocated on first use */
int sweep_job_run(const scene *s, const sweep_plan *p, size_t j, out_block **bp,
                  rps3_data *ws[], sink *k, char *err, size_t errsz);

/* free the workspaces of sweep_job_run */
void sweep_workspaces_free(rps3_data *ws[RPS3_NSOLVER]);

/* sweep_run_opts with o->nthread == 1: the jobs of the shard in turn on
   this thread (sweep.c) */
int sweep_run_serial(const scene *s, const sweep_plan *p, out_file *f,
                     out_block *b, const sweep_opts *o, progress *pr,
                     sweep_stats *st, char *err, size_t errsz);

/* sweep_run_opts with o->nthread > 1 workers (sweep_threads.c) */
int sweep_run_threads(const scene *s, const sweep_plan *p, out_file *f,
                      out_block *b, const sweep_opts *o, progress *pr,
                      sweep_stats *st, char *err, size_t errsz);

#endif /* RPS3_RUNNER_SWEEP_INT_H */
