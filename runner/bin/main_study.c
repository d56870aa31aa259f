/*
 * main_study.c - rps3-study: what accuracy costs in time, and the workspace.
 *
 *   rps3-study accuracy  -o OUT.h5 [--samples N] [--repeats R]
 *   rps3-study workspace -o OUT.h5 [--quick]
 *
 * accuracy: for two trajectories (the paper's helix, Table II, and a fast,
 * strongly tilted sine near the singular surface), every knob that trades
 * accuracy for time is measured against a precise reference:
 *   theta      closed form (39) vs each GSL multiroot solver at tolerances
 *              1e-2 .. 1e-14, cold (opt.warm_start = 0) and warm;
 *   derivative exact rates vs central differences in time of the pose
 *              (fd_pose) or of the link lengths (fd_length, what encoders
 *              give), steps 1e-2 .. 1e-7 s, and the not-a-knot spline of
 *              the pose sampled every 0.1 .. 0.001 s (spline_pose: a table
 *              of measured poses, docs/trajectories.md);
 *   method     Lagrange vs Newton-Euler;
 *   effects    gravity only -> all effects, each one's extra cost (and the
 *              model error of leaving the rest out);
 *   dt         sample interval: error of the sampled peak force, and the
 *              work-energy residual over each interval with exact rates and
 *              with rates differenced from the samples.
 * The reference: theta from inverse kinematics re-evaluated in long double;
 * forces by a formulation of their own (study_ref.c: Kane's equations in
 * the pose coordinates, long double, from the model's inputs), so that the
 * library's default path is graded too (its own floor is written); the peak
 * force from 200001 samples of the same reference.
 * Time per point: the median of R timed passes over the trajectory, in one
 * process, clock_gettime(CLOCK_MONOTONIC) around each pass; a pass includes
 * evaluating the trajectory.
 *
 * workspace: a grid over (rho, alpha, beta, z_c): status of inverse
 * kinematics + static dynamics, the condition number of the lambda system,
 * the assembly mode (the sign of det df/dtheta against the level pose), and
 * the static force that holds the platform (gravity effects only).
 *
 * Both write HDF5 with the runner's conventions: units and description on
 * every dataset, dimension scales on every axis, root attributes
 * rps3_version, created_utc, command_line, gsl_version, hdf5_version.  The
 * file is written under a temporary name next to OUT.h5 (tmpout.h: the
 * one rps3-run uses, removed by a signal that ends the program and, after
 * SIGKILL, by the next run of the same OUT.h5) and renamed when complete.
 * Exit codes: 0 ok, 2 bad command line, 3 the file could not be written.
 *
 * This file: the command line and the temporary file; study.h lists the
 * others.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "core/cli.h"
#include "core/h5err.h"
#include "core/safeio.h"
#include "core/signals.h"
#include "core/tmpout.h"
#include "study/study.h"

/* ----------------------------------------------------------------- main */

/* the options, in the order of STUDY_OPTS */
enum { O_OUTPUT, O_SAMPLES, O_REPEATS, O_QUICK, O_VERSION, O_HELP, O_N };

static const cli_opt STUDY_OPTS[O_N] = {
    {"output", 'o', "OUT.h5", 0, 0, 0,
     "output file (written under a temporary name,\nrenamed when complete)"},
    {"samples", 0, "N", 1, 10, 1000000, "samples per trajectory (default 400)"},
    {"repeats", 0, "R", 1, 1, 1000, "timed passes per setting (default 9)"},
    {"quick", 0, NULL, 0, 0, 0, "a coarse workspace grid"},
    {"version", 0, NULL, 0, 0, 0, "print the version"},
    {"help", 'h', NULL, 0, 0, 0, "print this help"},
};

static void usage(FILE *out) {
  fprintf(out,
          "usage: rps3-study accuracy -o OUT.h5 [--samples N] [--repeats R]\n"
          "       rps3-study workspace -o OUT.h5 [--quick]\n"
          "       rps3-study --help | --version\n"
          "\n"
          "Measure what accuracy costs in time, and map the workspace.\n"
          "\n"
          "Studies:\n"
          "  accuracy              what accuracy costs in time: every "
          "solver,\n"
          "                        tolerance, derivative, method, effect set "
          "and dt\n"
          "                        against a precise reference "
          "(docs/accuracy.md)\n"
          "  workspace             status, conditioning and assembly mode "
          "over a\n"
          "                        (rho, alpha, beta, z_c) grid\n"
          "\n"
          "Options:\n");
  cli_help(out, STUDY_OPTS, O_N);
  fprintf(out, "\nExit status: 0 ok, 2 bad command line, 3 cannot write.\n");
}

static int study_main(int argc, char **argv) {
  const char *out = NULL, *in[1], *arg, *study;
  char *cmdline, err[4096 + 512], **op;
  size_t samples = 400;
  int repeats = 9, quick = 0, row, rc, nop;
  unsigned long v;
  cli c;
  cli_start(&c, "rps3-study", STUDY_OPTS, O_N, argc, argv);
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    switch (row) {
    case O_OUTPUT: out = arg; break;
    case O_SAMPLES: samples = (size_t)v; break;
    case O_REPEATS: repeats = (int)v; break;
    case O_QUICK: quick = 1; break;
    case O_VERSION: cli_version(stdout, "rps3-study"); return EXIT_OK;
    case O_HELP: usage(stdout); return EXIT_OK;
    default: return EXIT_USAGE;
    }
  }
  nop = cli_operands(&c, &op);
  if (nop != 1) {
    if (nop == 0)
      cli_usage_error(&c, "missing the study: accuracy or workspace");
    else
      cli_usage_error(&c, "one study at a time ('%s' and '%s')", op[0], op[1]);
    return EXIT_USAGE;
  }
  study = op[0];
  if (strcmp(study, "accuracy") && strcmp(study, "workspace")) {
    cli_usage_error(&c, "unknown study '%s' (accuracy or workspace)", study);
    return EXIT_USAGE;
  }
  if (!out) {
    cli_usage_error(&c, "missing -o OUT.h5");
    return EXIT_USAGE;
  }
  in[0] = argv[0];
  if (out_path_check(out, in, 0, err, sizeof err)) {
    fprintf(stderr, "rps3-study: %s\n", err);
    return EXIT_USAGE;
  }
  if (!(cmdline = cli_command_line(argc, argv))) {
    fprintf(stderr, "rps3-study: out of memory\n");
    return EXIT_IO;
  }
  /* what killed runs of this output left: reported, and removed when
     their process was of this host */
  stale_report("rps3-study", out);
  tmpout_clean(out, 0, 1);
  if (tmpout_name(out, 0)) {
    free(cmdline);
    return EXIT_USAGE;
  }
  tmpout_arm();
  if (!strcmp(study, "accuracy"))
    rc = study_accuracy(tmpout_path(), cmdline, samples, repeats);
  else
    rc = study_workspace(tmpout_path(), cmdline, quick);
  if (rc != EXIT_OK) {
    h5_cause(err, sizeof err);
    if (err[0]) fprintf(stderr, "rps3-study: %s: HDF5: %s\n", out, err);
  } else if (tmpout_commit(out)) {
    rc = EXIT_IO;
  }
  if (rc != EXIT_OK) {
    tmpout_discard();
    fprintf(stderr, "rps3-study: %s not written\n", out);
  }
  free(cmdline);
  return rc;
}

int main(int argc, char **argv) {
  /* fds 0-2 open, HDF5 without atexit, then the signal policy of
     signals.h: the temporary file is removed by a signal that ends us */
  proc_init();
  tmpout_prog("rps3-study");
  sig_init();
  gsl_set_error_handler_off();
  h5_errors_capture();
  return proc_exit(study_main(argc, argv));
}
