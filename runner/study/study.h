/*
 * study.h - what the files of rps3-study and rps3-simstudy share: the
 * programs' main, the clock, the median, the sine trajectories and the
 * HDF5 helpers (study_run.c), and the studies, a file each:
 * study_accuracy.c (its force reference in study_ref.c, Kane's equations),
 * study_workspace.c and study_sim.c.
 */
#ifndef RPS3_RUNNER_STUDY_H
#define RPS3_RUNNER_STUDY_H

#include <math.h>
#include <stddef.h>

#include <hdf5.h>

#include "core/cli.h"
#include "core/exit_codes.h"
#include "rps3.h"

#define PI 3.14159265358979323846

/* a quiet NaN as a double (DNAN is a float) */
#define DNAN ((double)NAN)

/* rps3-simstudy's exit code when a run that must succeed failed */
enum { EXIT_RUN = 4 };

/* CLOCK_MONOTONIC in ns; the median of v[0..n) (sorts v) */
double study_now_ns(void);
double study_median(double *v, int n);

/* *tr = the sine trajectory `sine` */
void study_traj_sine(rps3_traj *tr, const rps3_sine *sine);

/* the studies into the HDF5 file at path: an exit code (study_sim exits
   EXIT_RUN when a run that must succeed fails) */
int study_accuracy(const char *path, const char *cmdline, size_t nsamp,
                   int repeats);
int study_workspace(const char *path, const char *cmdline, int quick);
int study_sim(const char *path, const char *cmdline, int quick);

/* what a study program's command line asks: OUT.h5, the study named (NULL
   when none), and row r's value of every other option in v[r]: a number's
   value, 1 for a flag given (else as the program set it) */
typedef struct {
  const char *out, *study;
  unsigned long v[CLI_MAX];
} study_args;

/* a study program: its option table (row 0 -o, the last two --version and
   --help: CLI_ROW_OUTPUT, CLI_ROW_VERSION, CLI_ROW_HELP), the top of its
   --help, its studies (NULL: it takes no operand) and what writes its
   file at path with the command line for its attributes (an exit code) */
typedef struct {
  const char *prog;
  const cli_opt *opt;
  int nopt;
  const char *help;
  const char *const *studies;
  int (*write)(const char *path, const char *cmdline, const study_args *a);
  int says_written; /* "wrote OUT.h5" on stdout when done */
} study_prog;

/*
 * A study program's main: the process set-up (fds, signals, temporary
 * file, GSL's and HDF5's errors), its command line into a (whose v holds
 * the defaults), then OUT.h5 checked, the leftovers of killed runs of it
 * reported and removed, written by p->write under a temporary name and
 * renamed when complete; messages "PROG: ..." on stderr.  The exit code.
 */
int study_main(const study_prog *p, study_args *a, int argc, char **argv);

/* an open study file and its UTF-8 string type */
typedef struct {
  hid_t file, str;
} study_h5;

/* create path with the root attributes of the runner's files and title,
   and close it (what was opened, even when open failed): 0 or -1 each */
int study_h5_open(study_h5 *o, const char *path, const char *cmdline,
                  const char *title);
int study_h5_close(study_h5 *o);

/*
 * Write a dataset of `rank` dims with its units and description, and attach
 * the named dimension scales (scales NULL: this dataset is itself the scale
 * of its name).  type is H5T_NATIVE_DOUBLE, H5T_NATIVE_INT32 or the
 * string type.  0 or -1.
 */
int study_h5_write(study_h5 *o, const char *name, hid_t type, int rank,
                   const hsize_t *dims, const void *data, const char *units,
                   const char *doc, const char *const *scales);

#endif /* RPS3_RUNNER_STUDY_H */
