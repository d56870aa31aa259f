/*
 * sweep.h - every case of a scene into an open output file: the plan
 * builds and checks every case first (nothing is written if one is
 * invalid), then the jobs compute them.  Job j is the cases
 * [j tile_cases, (j + 1) tile_cases), one tile and one chunk row of the
 * file; a case longer than a tile is a job of its own, in windows.  Jobs
 * share the cases, and windows the samples, evenly, and a tile writes only
 * the samples its cases have (whole chunks): the file allocates the data's
 * chunks only (docs/hdf5.md).  A case depends on nothing but its scene.
 */
#ifndef RPS3_RUNNER_SWEEP_H
#define RPS3_RUNNER_SWEEP_H

#include "core/progress.h"
#include "output/output.h"
#include "pool.h"

typedef struct {
  size_t nt;           /* most samples of any case: the time axis */
  int grid_common;     /* 1 when every case has the time grid of case 0 */
  size_t npoint;       /* samples over all cases */
  scene_case first;    /* case 0 */
  size_t tile_cases;   /* cases per tile (1 when a case spans tiles): the
                          case extent of a chunk */
  size_t tile_points;  /* samples per tile and case: a multiple of ... */
  size_t chunk_points; /* ... the time extent of a chunk */
  size_t stored;       /* samples (rows x times) of the chunks the run
                          allocates: what the file holds per sample field */
} sweep_plan;

/* how to run: threads and shard */
typedef struct {
  int nthread;   /* worker threads; 1: compute on the calling thread */
  size_t shard;  /* this run computes the jobs j with */
  size_t nshard; /*   j % nshard == shard (nshard 1: every job) */
} sweep_opts;

/* what a run did */
typedef struct {
  size_t cases_done;
  size_t points_done;
  size_t nfailed; /* cases with a non-zero status */
} sweep_stats;

/* Build every case of s through the library's checks.  Returns 0, or -1
   with err at the swept value or key of the first invalid case. */
int sweep_plan_make(const scene *s, sweep_plan *p, scene_error *err);

/* Number of jobs of a plan: ceil(ncase / tile_cases). */
size_t sweep_njob(const scene *s, const sweep_plan *p);

/* Cases in the jobs of shard `shard` of `nshard` (pool_count's jobs). */
size_t sweep_shard_cases(const scene *s, const sweep_plan *p, size_t shard,
                         size_t nshard);

/* Compute the cases of s of a shard into f on the worker pool, in block b
   (allocated for the plan's tile) and copies of it.  A failing case is
   recorded (status, message, failed_at, NaN rows) and the sweep goes on;
   each hyperslab is written once (a failing long case rewrites its own
   earlier windows).  Other shards' chunks stay unallocated (the fill
   values).  Returns 0, or -1 with err (the file, memory). */
int sweep_run_opts(const scene *s, const sweep_plan *p, out_file *f,
                   out_block *b, const sweep_opts *o, progress *pr,
                   sweep_stats *st, char *err, size_t errsz);

/* Compute samples [k0, k0 + nk) of case c into slot `slot` of b with the
   workspace d (allocated for c's solver): the trajectory, then the
   pipeline.  k0 == 0 starts the case (rps3_data_reset: no warm start leaks
   from the previous case).  Returns RPS3_OK, or the status of the first
   failing sample with *failed_at its time index and the reason in
   b->msg[slot]; the samples after it are not computed. */
int case_compute(const scene_case *c, rps3_data *d, size_t k0, size_t nk,
                 out_block *b, size_t slot, size_t *failed_at);

/* The workspace for case c in ws, one per solver kind, allocated on first
   use; NULL with err when it cannot be.  case_workspaces_free frees ws. */
rps3_data *case_workspace(rps3_data *ws[RPS3_NSOLVER], const scene_case *c,
                          char *err, size_t errsz);
void case_workspaces_free(rps3_data *ws[RPS3_NSOLVER]);

/* what the write of a filled block needs: every job of the pool (pool.h)
   writes through sweep_write_tile */
typedef struct {
  const scene *s;
  out_file *f;
  progress *pr;
  sweep_stats *st;
  int status, message; /* the fields of a case's outcome */
  int label;           /* 1: a failed case is named by its swept values */
} sweep_writer;

/* pool_job.write of every job (ctx its sweep_writer, slot an out_block,
   info an out_tile): the tile written, counted, the run's first failed
   case said (also when quiet: progress_failure).  0, or -1 with err. */
int sweep_write_tile(void *ctx, void *slot, const void *info, char *err,
                     size_t errsz);

#endif /* RPS3_RUNNER_SWEEP_H */
