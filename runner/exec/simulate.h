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

#include <stddef.h>

#include "scene/scene.h"

/* one simulated case, ready to run */
typedef struct {
  rps3_model ctrl_model; /* the controller's model, initialised */
  rps3_sim_options opt;
  rps3_ctrl_kind kind;
  double kp, kd;   /* the gains used (the kind's when not given) */
  double rate;     /* control rate [Hz] */
  double duration; /* simulated time [s] */
  double step;     /* sample step [s] */
  size_t nt;       /* samples, both ends included */
} sim_case;

/* the workspaces of one simulated case */
typedef struct {
  rps3_sim *sim;
  rps3_ctrl *ctrl;
  rps3_data *ref; /* the reference motion, on the plant's geometry */
} sim_work;

void sim_work_free(sim_work *wk);

/* The simulation of case c of s: controller model, options, gains and
   grid, each checked (the library's own checks, rps3_sim_alloc and
   rps3_ctrl_alloc included).  With wk, the simulation and controller
   those checks made are kept there for the run (else freed).  Returns 0,
   or -1 with err at the key (or the swept value) that is wrong. */
int sim_case_build(const scene *s, const scene_case *c, sim_case *sc,
                   sim_work *wk, scene_error *err);

/* Time of sample k of a simulated case [s]. */
double sim_case_time(const scene_case *c, const sim_case *sc, size_t k);

/* what the check of all cases found: the time axis */
typedef struct {
  size_t nt;      /* most samples of any case */
  size_t npoint;  /* samples over all cases */
  double seconds; /* simulated time over all cases [s] */
  int common;     /* 1: every case has case 0's time grid */
  scene_case first;
  sim_case sfirst;
} sim_plan;

/* Build and check every case of s (scene_case_build, sim_case_build) and
   find the time axis.  A sweep of simulate.* keys needs the section.
   Returns 0, or -1 with err at the first wrong value. */
int sim_plan_make(const scene *s, sim_plan *p, scene_error *err);

/* 1 when s is to be simulated: it has a simulate section, or sweeps a
   simulate key (which sim_plan_make then refuses) */
int sim_wanted(const scene *s);

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
