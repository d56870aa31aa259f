/*
 * sim_run.h - inside rps3-run's simulation (simulate.h): a case simulated
 * window by window, each window handed to a sink as a tile; the sink
 * writes it (one thread) or queues it for the writing thread (sim_pool.c,
 * -j N).  Only the thread that created the file calls HDF5.
 */
#ifndef RPS3_RUNNER_SIM_RUN_H
#define RPS3_RUNNER_SIM_RUN_H

#include <stddef.h>

#include "core/progress.h"
#include "output/sim_output.h"
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

/* where the tiles go: put hands t over and returns the tile to fill next
   (t itself when it was written at once), or NULL to stop */
typedef struct sim_sink sim_sink;
struct sim_sink {
  sim_tile *(*put)(sim_sink *k, sim_tile *t);
};

/*
 * Simulate case i of s (built and checked by the plan), its first `limit`
 * samples at most, into tiles through k, starting with tile t.  Returns the
 * tile it holds at the end, or NULL when the sink stopped or memory ran out
 * (err set, when known).
 */
sim_tile *sim_run_case(const scene *s, size_t i, size_t limit, sim_tile *t,
                       sim_sink *k, char *err, size_t errsz);

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

/* every case on nthread >= 2 worker threads (sim_pool.c; sim_main.c
   runs a single thread itself) */
int sim_pool_run(const scene *s, const sim_plan *p, sim_file *f, int nthread,
                 progress *pr, size_t *nfailed, char *err, size_t errsz);

/* Print the reason of the first failed case (tile t, its last window) once,
   also when quiet. */
void sim_failure(const scene *s, progress *pr, const sim_tile *t);

#endif /* RPS3_RUNNER_SIM_RUN_H */
