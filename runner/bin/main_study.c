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
 * This file: the command line; study.h lists the others.
 */
#include <stdio.h>
#include <string.h>

#include "core/cli.h"
#include "study/study.h"

/* ----------------------------------------------------------------- main */

/* the options, in the order of STUDY_OPTS */
enum { O_OUTPUT, O_SAMPLES, O_REPEATS, O_QUICK, O_VERSION, O_HELP, O_N };

static const cli_opt STUDY_OPTS[O_N] = {
    CLI_ROW_OUTPUT,
    {"samples", 0, "N", 1, 10, 1000000, "samples per trajectory (default 400)"},
    {"repeats", 0, "R", 1, 1, 1000, "timed passes per setting (default 9)"},
    {"quick", 0, NULL, 0, 0, 0, "a coarse workspace grid"},
    CLI_ROW_VERSION,
    CLI_ROW_HELP,
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

/* what the command line asks */
typedef struct {
  const char *study; /* "accuracy" or "workspace" */
  size_t samples;
  int repeats, quick;
} study_args;

static int study_write(const char *path, const char *cmdline, const void *arg) {
  const study_args *a = arg;
  if (!strcmp(a->study, "accuracy"))
    return study_accuracy(path, cmdline, a->samples, a->repeats);
  return study_workspace(path, cmdline, a->quick);
}

static int study_main(int argc, char **argv) {
  const char *out = NULL, *arg;
  char **op;
  study_args a = {NULL, 400, 9, 0};
  int row, nop;
  unsigned long v;
  cli c;
  cli_start(&c, "rps3-study", STUDY_OPTS, O_N, argc, argv);
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    switch (row) {
    case O_OUTPUT: out = arg; break;
    case O_SAMPLES: a.samples = (size_t)v; break;
    case O_REPEATS: a.repeats = (int)v; break;
    case O_QUICK: a.quick = 1; break;
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
  a.study = op[0];
  if (strcmp(a.study, "accuracy") && strcmp(a.study, "workspace")) {
    cli_usage_error(&c, "unknown study '%s' (accuracy or workspace)", a.study);
    return EXIT_USAGE;
  }
  if (!out) {
    cli_usage_error(&c, "missing -o OUT.h5");
    return EXIT_USAGE;
  }
  return study_output("rps3-study", out, argc, argv, study_write, &a);
}

int main(int argc, char **argv) {
  return study_prog("rps3-study", study_main, argc, argv);
}
