/* sim_case.h - a scene's simulated cases, built and checked from its
   simulate section (sim_case.c), for the run of simulate.h */
#ifndef RPS3_RUNNER_SIM_CASE_H
#define RPS3_RUNNER_SIM_CASE_H

#include "scene/scene.h"

/* 1 when s is to be simulated: it has a simulate section, or sweeps a
   simulate key (which sim_plan_make then refuses) */
int sim_wanted(const scene *s);

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

/* what the check of all cases found: the time axis */
typedef struct {
  size_t nt;      /* most samples of any case */
  size_t npoint;  /* samples over all cases */
  double seconds; /* simulated time over all cases [s] */
  int common;     /* 1: every case has case 0's time grid */
  scene_case first;
  sim_case sfirst;
} sim_plan;

/* frees what wk holds and clears it */
void sim_work_free(sim_work *wk);

/* The simulation of case c of s: controller model, options, gains and
   grid, each checked with the library's (rps3_sim_alloc, rps3_ctrl_alloc);
   with wk, the simulation and controller they made are kept there for the
   run (else freed).  0, or -1 with err at the key (or swept value). */
int sim_case_build(const scene *s, const scene_case *c, sim_case *sc,
                   sim_work *wk, scene_error *err);

/* Time of sample k of a simulated case [s]. */
double sim_case_time(const scene_case *c, const sim_case *sc, size_t k);

/* Build and check every case of s (scene_case_build, sim_case_build) and
   find the time axis.  A sweep of simulate.* keys needs the section.
   Returns 0, or -1 with err at the first wrong value. */
int sim_plan_make(const scene *s, sim_plan *p, scene_error *err);

#endif /* RPS3_RUNNER_SIM_CASE_H */
