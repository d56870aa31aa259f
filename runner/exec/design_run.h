/*
 * design_run.h - a design study (scene/design.h) into its file (the
 * OUT_DESIGN rows of the schema, one row per design): every design checked
 * before anything is written, then evaluated by the library over the
 * section's grid (and along the trajectory, when the scene has one) in
 * work units of whole designs on the worker pool.  A work unit is one
 * chunk row of every dataset, about DESIGN_UNIT_POSES poses; shard K of N
 * computes the units j with j mod N = K, its part merged as a sweep's.
 */
#ifndef RPS3_RUNNER_DESIGN_RUN_H
#define RPS3_RUNNER_DESIGN_RUN_H

#include "scene/design.h"
#include "sweep.h"

/* poses of evaluation per work unit (a unit is at least one design) */
#define DESIGN_UNIT_POSES 65536

typedef struct {
  size_t ncase;        /* designs */
  rps3_design_grid gr; /* the pose grid */
  size_t npose;        /* its poses */
  size_t unit;         /* designs per work unit */
  size_t nunit;        /* work units */
  int task;            /* the scene has a trajectory: the task is evaluated */
  int per_pose;        /* the per-pose indices are written */
  int files;           /* the OUT_DESIGN bits of the file's fields */
  size_t nsample;      /* samples of the task (its time grid) */
} design_plan;

/* Build and check every design of s and lay out the work units.  Returns
   0, or -1 with err at the swept value or key of the first invalid one. */
int design_plan_make(const scene *s, design_plan *p, scene_error *err);

/* designs of shard k of n (all for n = 1) */
size_t design_shard_cases(const design_plan *p, size_t k, size_t n);

/* What --check prints (stdout) and a run first (stderr, unless quiet):
   designs, poses, size, time, work units.  A run refuses (-1, nothing
   written) an output above the free space (not with gzip: an upper bound)
   and --shard K/N with N above the work units. */
int design_preflight(const char *scene_path, const scene *s,
                     const design_plan *p, size_t shard, size_t nshard,
                     int nrank, int nthread, int gzip, int check, int quiet,
                     const char *out_path);

/* Create the file at `path` for the designs of s (out_open, chunks of a
   work unit); NULL with a message in err.  Closed with out_close. */
out_file *design_file_open(const char *path, const scene *s,
                           const design_plan *p, const out_meta *meta,
                           char *err, size_t errsz);

/* Evaluate the designs of shard `shard` of `nshard` into f on nthread
   threads, counts in st (its points the poses and task samples) and
   *nempty (designs with an empty workspace).  A failed design is a row of
   its file (status, message), not a failure of the run.  Returns 0, or -1
   with err (the file, memory). */
int design_run(const scene *s, const design_plan *p, out_file *f, size_t shard,
               size_t nshard, int nthread, progress *pr, sweep_stats *st,
               size_t *nempty, char *err, size_t errsz);

#endif /* RPS3_RUNNER_DESIGN_RUN_H */
