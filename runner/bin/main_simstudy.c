/*
 * main_simstudy.c - rps3-simstudy: closed-loop tracking of the shipped
 * controllers, and what simulation accuracy costs in time.
 *
 *   rps3-simstudy -o OUT.h5 [--quick]
 *
 * tracking: the shipped controllers on the paper's helix and a fast sine;
 * accuracy: each integrator at a ladder of steps or tolerances against
 * rk8pd at 1e-13 (study_sim.c says what is run and written).
 *
 * HDF5 with the runner's conventions: units on every dataset, root
 * attributes rps3_version, command_line; written under a temporary name
 * next to OUT.h5 (tmpout.h, as rps3-run and rps3-study) and renamed when
 * complete.  Exit codes: 0 ok, 2 bad command line, 3 the file
 * could not be written, 4 a run that must succeed failed.
 *
 * This file: the command line.
 */
#include <stdio.h>

#include "core/cli.h"
#include "study/study.h"

/* the options, in the order of SIMSTUDY_OPTS */
enum { O_OUTPUT, O_QUICK, O_VERSION, O_HELP, O_N };

static const cli_opt SIMSTUDY_OPTS[O_N] = {
    CLI_ROW_OUTPUT,
    {"quick", 0, NULL, 0, 0, 0, "shorter runs (0.5 s), one timing each"},
    CLI_ROW_VERSION,
    CLI_ROW_HELP,
};

static void usage(FILE *out) {
  fprintf(out,
          "usage: rps3-simstudy -o OUT.h5 [--quick]\n"
          "       rps3-simstudy --help | --version\n\n"
          "Closed-loop tracking and what simulation accuracy costs in "
          "time.\n\n"
          "Options:\n");
  cli_help(out, SIMSTUDY_OPTS, O_N);
  fprintf(out, "\nExit status: 0 ok, 2 bad command line, 3 cannot write.\n");
}

static int simstudy_write(const char *path, const char *cmdline,
                          const void *quick) {
  return study_sim(path, cmdline, *(const int *)quick);
}

static int simstudy_main(int argc, char **argv) {
  const char *out = NULL, *arg;
  char **op;
  int quick = 0, row, rc;
  unsigned long v;
  cli c;
  cli_start(&c, "rps3-simstudy", SIMSTUDY_OPTS, O_N, argc, argv);
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    switch (row) {
    case O_OUTPUT: out = arg; break;
    case O_QUICK: quick = 1; break;
    case O_VERSION: cli_version(stdout, "rps3-simstudy"); return EXIT_OK;
    case O_HELP: usage(stdout); return EXIT_OK;
    default: return EXIT_USAGE;
    }
  }
  if (cli_operands(&c, &op) != 0) {
    cli_usage_error(&c, "no operand expected, got '%s'", op[0]);
    return EXIT_USAGE;
  }
  if (out == NULL) {
    cli_usage_error(&c, "missing -o OUT.h5");
    return EXIT_USAGE;
  }
  rc = study_output("rps3-simstudy", out, argc, argv, simstudy_write, &quick);
  if (rc == EXIT_OK) printf("wrote %s\n", out);
  return rc;
}

int main(int argc, char **argv) {
  return study_prog("rps3-simstudy", simstudy_main, argc, argv);
}
