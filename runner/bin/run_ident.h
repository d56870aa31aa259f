/*
 * run_ident.h - rps3-run on an identification (scene/identify.h): the
 * plan and the fit of the noise-free forces checked before anything is
 * written, --check, then the file by the steps of a run (run_steps.h):
 * a whole file, or with --shard K/N the part of the Monte Carlo's draws
 * that `rps3-run merge` joins and summarises.
 */
#ifndef RPS3_RUNNER_RUN_IDENT_H
#define RPS3_RUNNER_RUN_IDENT_H

#include "run_steps.h"

/* the exit code */
int run_identify(scene *s, const run_args *a, const world *w, int argc,
                 char **argv);

#endif /* RPS3_RUNNER_RUN_IDENT_H */
