/*
 * run_steps.h - rps3-run's command lines (run_cli.c: the option table of a
 * run, its --help, and `rps3-run --clean`), and the steps of an rps3-run
 * that writes OUT.h5, the same for a sweep and a design study (main_run.c):
 * the input files recorded, --resume, the temporary file renamed when
 * complete, and under rps3-run-mpi the ranks' parts joined or merged by
 * rank 0.
 */
#ifndef RPS3_RUNNER_RUN_STEPS_H
#define RPS3_RUNNER_RUN_STEPS_H

#include <stddef.h>

#include "core/progress.h"
#include "exec/sweep.h"
#include "mpi/world.h"
#include "output/output.h"
#include "scene/scene.h"

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
  const char *manip_path; /* --manipulator FILE, or NULL */
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

/* what a sweep and a design study do differently around the steps of a
   run that writes OUT.h5 (run_output) */
typedef struct run_job {
  const char *fields; /* the fields written: a part's root attribute */
  const char *noun;   /* what the cases are: "case" or "design" */
  size_t ncase;       /* this shard's cases */
  /* the progress's jobs and samples set and the file written at
     tmpout_path(); the exit code */
  int (*write)(struct run_job *j, const out_meta *meta, progress *pr,
               sweep_stats *st);
  void *ctx;
  char note[256]; /* said after a whole file is written, unless --quiet */
} run_job;

/* The worst of the ranks' codes (this code without MPI); *first, when not
   NULL, gets rank 0's. */
int run_agree(const world *w, int code, int *first);

/* A usage error, said by rank 0: "rps3-run: MSG" and where --help is;
   EXIT_USAGE. */
int run_usage_error(const world *w, const char *msg);

/* "rps3-run: OUT.h5: err" on stderr; EXIT_IO. */
int run_io(const run_args *a, const char *err);

/*
 * The steps of a run that writes OUT.h5 after its own checks (`code`,
 * their outcome on this rank): the input files recorded, --resume, the
 * leftovers of killed runs, j's file under a temporary name, renamed when
 * complete or joined with the other ranks' parts.  The exit code, the same
 * on every rank.
 */
int run_output(const run_args *a, const world *w, const scene *s, int code,
               run_job *j, int argc, char **argv);

#endif /* RPS3_RUNNER_RUN_STEPS_H */
