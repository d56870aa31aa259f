/*
 * sim_run.h - inside rps3-run's simulation (simulate.h): a case simulated
 * window by window, each window a tile (a slot of the worker pool, pool.h)
 * that the pool writes at once (one thread) or queues for the writing
 * thread (-j N).  Only the thread that created the file calls HDF5.
 */
#ifndef RPS3_RUNNER_SIM_RUN_H
#define RPS3_RUNNER_SIM_RUN_H

#include <stddef.h>

#include "core/progress.h"
#include "output/sim_output.h"
#include "pool.h"
#include "simulate.h"

/* samples per window (and chunk) of a case: memory does not grow with the
   length of a case */
#define SIM_WINDOW 4096

/* a window on its way to the file */
typedef struct {
  sim_window w;  /* samples [k0, k0 + nk) of case c */
  double *times; /* their times [points] */
  size_t c, k0, nk;
  int last; /* 1: the case's last window; v holds its values */
  sim_case_values v;
  scene_text yaml; /* storage of v.scene_resolved */
} sim_tile;

/* Allocate a tile of `points` samples: 0, or -1 (nothing leaks). */
int sim_tile_alloc(sim_tile *t, size_t points);
void sim_tile_free(sim_tile *t);

/*
 * Simulate case i of s (built and checked by the plan) on worker w of the
 * pool, into its tiles (pool_slot, pool_emit).  Returns 0, or -1 when the
 * pool stopped or memory ran out (err set).
 */
int sim_run_case(const scene *s, size_t i, pool_worker *w, char *err,
                 size_t errsz);

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

/*
 * Case i simulated as the run does (its samples' references included) up
 * to the pilot's budget: adds the CPU seconds and the simulated seconds it
 * covered to *cpu and *sim, the samples to *samples.  -1 when the case
 * cannot be set up (memory).
 */
int sim_pilot_case(const scene *s, size_t i, double *cpu, double *sim,
                   size_t *samples);

/* Print the reason of the first failed case (tile t, its last window) once,
   also when quiet. */
void sim_failure(const scene *s, progress *pr, const sim_tile *t);

#endif /* RPS3_RUNNER_SIM_RUN_H */
