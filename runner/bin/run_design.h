/*
 * run_design.h - rps3-run on a design study (scene/design.h): the plan,
 * --check, the file of this process's designs (a whole file, a --shard
 * part, or under rps3-run-mpi a rank's part joined as a sweep's are), by
 * the steps of a sweep's run (run_steps.h).
 */
#ifndef RPS3_RUNNER_RUN_DESIGN_H
#define RPS3_RUNNER_RUN_DESIGN_H

#include <stddef.h>

#include "mpi/world.h"
#include "run_cli.h"
#include "scene/scene.h"

/* Run the design study s as the command line a asks; the exit code. */
int run_design(scene *s, const run_args *a, const world *w, int argc,
               char **argv);

#endif /* RPS3_RUNNER_RUN_DESIGN_H */
