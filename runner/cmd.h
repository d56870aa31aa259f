/*
 * cmd.h - rps3-run's exit codes and its subcommands other than a run.
 */
#ifndef RPS3_RUNNER_CMD_H
#define RPS3_RUNNER_CMD_H

#include "tmpout.h"

/* exit codes of rps3-run: 0 every case ok; 1 the file is complete but some
   cases failed; 2 bad command line, scene or parts; 3 cannot read or
   write */
enum { EXIT_OK = 0, EXIT_FAILED_CASES = 1, EXIT_USAGE = 2, EXIT_IO = 3 };

/*
 * rps3-run merge OUT.h5 PART.h5 ... [--copy] [--quiet]: argv[0] is
 * "merge", cmd the whole command line (for the file's command_line).
 * Returns the exit code.
 */
int merge_main(int argc, char **argv, const char *cmd);

#endif /* RPS3_RUNNER_CMD_H */
