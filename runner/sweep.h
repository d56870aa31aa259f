/*
 * sweep.h - run every case of a scene into an open output file.
 *
 * First sweep_plan() builds and validates every case (nothing is written
 * if one is invalid) and finds the time axis; then sweep_run() computes
 * the cases tile by tile and streams each tile to the file.
 */
#ifndef RPS3_RUNNER_SWEEP_H
#define RPS3_RUNNER_SWEEP_H

#include <stddef.h>

#include "output.h"
#include "progress.h"
#include "scene.h"

/* samples in one tile of output: bounds the memory of a run */
#define SWEEP_TILE_POINTS 16384

typedef struct {
  size_t nt;          /* most samples of any case: the time axis */
  int grid_common;    /* 1 when every case has the time grid of case 0 */
  size_t npoint;      /* samples over all cases */
  scene_case first;   /* case 0 */
  size_t tile_cases;  /* cases per tile (1 when a case spans tiles) */
  size_t tile_points; /* samples per tile and case */
} sweep_plan;

/* what a run did */
typedef struct {
  size_t cases_done;
  size_t points_done;
  size_t nfailed;     /* cases with a non-zero status */
} sweep_stats;

/*
 * Build every case of s through the library's checks.  Returns 0, or -1
 * with err at the swept value or key of the first invalid case.
 */
int sweep_plan_make(const scene *s, sweep_plan *p, scene_error *err);

/*
 * Compute all cases of s into f, using block b (allocated for the plan's
 * tile).  Failing cases are recorded in status/message/failed_at with NaN
 * rows, and the sweep goes on.  Returns 0, or -1 with err set when the file
 * cannot be written or memory runs out.
 */
int sweep_run(const scene *s, const sweep_plan *p, out_file *f,
              out_block *b, progress *pr, sweep_stats *st, char *err,
              size_t errsz);

#endif /* RPS3_RUNNER_SWEEP_H */
