/*
 * exit_codes.h - rps3-run's exit codes, shared by its commands.
 */
#ifndef RPS3_RUNNER_EXIT_CODES_H
#define RPS3_RUNNER_EXIT_CODES_H

/* exit codes of rps3-run: 0 every case ok; 1 the file is complete but some
   cases failed; 2 bad command line, scene or parts; 3 cannot read or
   write */
enum { EXIT_OK = 0, EXIT_FAILED_CASES = 1, EXIT_USAGE = 2, EXIT_IO = 3 };

#endif /* RPS3_RUNNER_EXIT_CODES_H */
