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

#include "h5err.h"
#include "safeio.h"
#include "signals.h"
#include "study.h"
#include "tmpout.h"

/* ----------------------------------------------------------------- main */

static int usage(FILE *out) {
  fprintf(out,
          "usage: rps3-study accuracy -o OUT.h5 [--samples N] [--repeats R]\n"
          "       rps3-study workspace -o OUT.h5 [--quick]\n"
          "       rps3-study --help | --version\n"
          "\n"
          "  accuracy   what accuracy costs in time: every solver, "
          "tolerance,\n"
          "             derivative, method, effect set and dt against a "
          "precise\n"
          "             reference (docs/accuracy.md)\n"
          "  workspace  status, conditioning and assembly mode over a\n"
          "             (rho, alpha, beta, z_c) grid\n"
          "  -o OUT.h5      output file (written under a temporary name, "
          "renamed when complete)\n"
          "  --samples N    samples per trajectory, 10-1000000 (default "
          "400)\n"
          "  --repeats R    timed passes per setting, 1-1000 (default 9)\n"
          "  --quick        a coarse workspace grid\n"
          "exit: 0 ok, 2 bad command line, 3 cannot write\n");
  return EXIT_USAGE;
}

/* the value of option argv[i] (which needs one), strictly in [lo, hi] */
static int option_value(int argc, char **argv, int i, unsigned long lo,
                        unsigned long hi, unsigned long *v) {
  if (i + 1 >= argc) {
    fprintf(stderr, "rps3-study: %s needs a value\n", argv[i]);
    return -1;
  }
  if (parse_ulong(argv[i + 1], lo, hi, v)) {
    fprintf(stderr, "rps3-study: %s needs a whole number %lu-%lu, got '%s'\n",
            argv[i], lo, hi, argv[i + 1]);
    return -1;
  }
  return 0;
}

static int study_main(int argc, char **argv) {
  const char *out = NULL, *in[1];
  char cmdline[2048], err[4096 + 512];
  size_t samples = 400, len = 0;
  int repeats = 9, quick = 0, i, rc;
  unsigned long v;
  if (argc < 2) return usage(stderr);
  if (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
    usage(stdout);
    return EXIT_OK;
  }
  if (!strcmp(argv[1], "--version")) {
    printf("rps3-study %s\n", rps3_version());
    return EXIT_OK;
  }
  if (strcmp(argv[1], "accuracy") && strcmp(argv[1], "workspace")) {
    fprintf(stderr, "rps3-study: unknown study '%s'\n", argv[1]);
    return usage(stderr);
  }
  cmdline[0] = '\0';
  for (i = 0; i < argc; i++) {
    int w = snprintf(cmdline + len, sizeof cmdline - len, "%s%s", i ? " " : "",
                     argv[i]);
    if (w < 0 || (size_t)w >= sizeof cmdline - len) break;
    len += (size_t)w;
  }
  for (i = 2; i < argc; i++) {
    if (!strcmp(argv[i], "-o")) {
      if (i + 1 >= argc) {
        fprintf(stderr, "rps3-study: -o needs a value\n");
        return usage(stderr);
      }
      out = argv[++i];
    } else if (!strcmp(argv[i], "--samples")) {
      if (option_value(argc, argv, i++, 10, 1000000, &v))
        return usage(stderr);
      samples = (size_t)v;
    } else if (!strcmp(argv[i], "--repeats")) {
      if (option_value(argc, argv, i++, 1, 1000, &v)) return usage(stderr);
      repeats = (int)v;
    } else if (!strcmp(argv[i], "--quick")) {
      quick = 1;
    } else {
      fprintf(stderr, "rps3-study: unknown option '%s'\n", argv[i]);
      return usage(stderr);
    }
  }
  if (!out) {
    fprintf(stderr, "rps3-study: -o OUT.h5 is needed\n");
    return usage(stderr);
  }
  in[0] = argv[0];
  if (out_path_check(out, in, 0, err, sizeof err)) {
    fprintf(stderr, "rps3-study: %s\n", err);
    return EXIT_USAGE;
  }
  /* what killed runs of this output left: reported, and removed when
     their process was of this host */
  stale_report("rps3-study", out);
  tmpout_clean(out, 0, 1);
  if (tmpout_name(out, 0)) return EXIT_USAGE;
  tmpout_arm();
  if (!strcmp(argv[1], "accuracy"))
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
