/*
 * simulate.h - rps3-run on a scene with a `simulate:` section: each case is
 * simulated (rps3_sim) under the section's controller, into a file of its
 * own schema.  The controller follows the case's trajectory with the
 * plant's model, the simulate.model.* keys given overriding it; the run
 * starts on the trajectory at t = 0 and lasts simulate.duration (default:
 * the span), sampled on the trajectory's grid continued past the span.
 */
#ifndef RPS3_RUNNER_SIMULATE_H
#define RPS3_RUNNER_SIMULATE_H

#include "sim_case.h"

/* how rps3-run was asked to run */
typedef struct {
  const char *out_path; /* NULL with check */
  int check;            /* --check: validate and say what would run */
  int quiet;
  int gzip;
  int nthread; /* -j: worker threads */
  int sharded; /* --shard, --resume or MPI ranks: refused */
  const char *command_line;
} sim_args;

/* Check every case of s and simulate them into a->out_path, written
   under a temporary name and renamed when complete.  Returns rps3-run's
   exit code (core/exit_codes.h). */
int sim_main(const scene *s, const sim_args *a);

#endif /* RPS3_RUNNER_SIMULATE_H */
