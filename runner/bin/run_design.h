/*
 * run_design.h - rps3-run on a design study (scene/design.h): the plan,
 * --check, the file of this process's designs (a whole file, a --shard
 * part, or under rps3-run-mpi a rank's part joined as a sweep's are).
 */
#ifndef RPS3_RUNNER_RUN_DESIGN_H
#define RPS3_RUNNER_RUN_DESIGN_H

#include <stddef.h>

#include "core/progress.h"
#include "exec/sweep.h"
#include "mpi/world.h"
#include "run_cli.h"
#include "scene/scene.h"

/*
 * After every rank has written its part: join them (rank 0) into OUT.h5,
 * or merge them with copy; the exit code of the run, the same on every
 * rank (main_run.c's, for sweeps and design studies alike).
 */
typedef int (*ranks_join_fn)(const world *w, int code, int copy,
                             const char *out_path, const char *cmd,
                             progress *pr, const sweep_stats *st, size_t ncase);

/* Run the design study s as the command line a asks, the ranks' parts
   joined by join; the exit code. */
int run_design(scene *s, const run_args *a, const world *w, int argc,
               char **argv, ranks_join_fn join);

#endif /* RPS3_RUNNER_RUN_DESIGN_H */
