/*
 * run_cli.h - rps3-run's command lines: the option table of a run, its
 * --help, and `rps3-run --clean` (cli.h parses them).
 */
#ifndef RPS3_RUNNER_RUN_CLI_H
#define RPS3_RUNNER_RUN_CLI_H

#include <stddef.h>

#include "output/output.h"

/* what the command line of a run asks */
typedef struct {
  const char *scene_path;
  const char *out_path;  /* NULL with --check */
  const char *shard_arg; /* "K/N" as given, or NULL */
  size_t shard, nshard;  /* --shard K/N (0/1 without) */
  int nthread;           /* -j */
  int quiet, check, copy, resume, failed_ok;
  int gzip;            /* --gzip level, 0: none */
  out_mask fields;     /* --fields */
  char shard_text[64]; /* under mpirun: "rank/size", shard_arg's text */
} run_args;

/*
 * Parse a run's command line into a.  Returns -1 to go on with the run;
 * else the exit code: EXIT_OK after an option that prints and ends
 * (--help, --version, --keys, --schema, --sim-schema), EXIT_USAGE after a
 * message on stderr.
 */
int run_args_parse(int argc, char **argv, run_args *a);

/* rps3-run --clean OUT.h5 [--force] (argv[1] is "--clean"): the exit
   code */
int clean_main(int argc, char **argv);

#endif /* RPS3_RUNNER_RUN_CLI_H */
