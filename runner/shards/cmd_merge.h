/*
 * cmd_merge.h - `rps3-run merge`, the subcommand that joins parts.
 */
#ifndef RPS3_RUNNER_CMD_MERGE_H
#define RPS3_RUNNER_CMD_MERGE_H

/* rps3-run merge OUT.h5 PART.h5 ... [--copy] [--quiet]: argv[1] is
   "merge".  Returns the exit code (exit_codes.h). */
int merge_main(int argc, char **argv);

#endif /* RPS3_RUNNER_CMD_MERGE_H */
