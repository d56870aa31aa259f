/*
 * study_run.c - what rps3-study and rps3-simstudy share around their
 * studies: the process set-up, the command line (cli.h, from each one's
 * option table) and the output file, written under a temporary name next
 * to OUT.h5 (tmpout.h, as rps3-run's) and renamed when complete; and the
 * clock, the median and the sine trajectories of the studies.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "core/h5err.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "study.h"

/* the operands: the one study of p->studies, or none when it has none; 0,
   or -1 after the message */
static int study_operands(const study_prog *p, const cli *c, study_args *a) {
  char **op;
  int nop = cli_operands(c, &op), i;
  if (!p->studies) {
    if (nop == 0) return 0;
    cli_usage_error(c, "no operand expected, got '%s'", op[0]);
    return -1;
  }
  if (nop != 1) {
    if (nop == 0)
      cli_usage_error(c, "missing the study: %s or %s", p->studies[0],
                      p->studies[1]);
    else
      cli_usage_error(c, "one study at a time ('%s' and '%s')", op[0], op[1]);
    return -1;
  }
  i = 0;
  while (p->studies[i] && strcmp(p->studies[i], op[0]) != 0) i++;
  if (!p->studies[i]) {
    cli_usage_error(c, "unknown study '%s' (%s or %s)", op[0], p->studies[0],
                    p->studies[1]);
    return -1;
  }
  a->study = op[0];
  return 0;
}

/* the command line into a: -1 to go on, else the exit code (after --help,
   --version, or a message) */
static int study_parse(const study_prog *p, study_args *a, int argc,
                       char **argv) {
  const char *arg;
  unsigned long v;
  int row;
  cli c;
  cli_start(&c, p->prog, p->opt, p->nopt, argc, argv);
  while ((row = cli_next(&c, &arg, &v)) != CLI_END) {
    if (row == CLI_BAD) return EXIT_USAGE;
    if (row == 0)
      a->out = arg;
    else if (row == p->nopt - 2) {
      cli_version(stdout, p->prog);
      return EXIT_OK;
    } else if (row == p->nopt - 1) {
      fputs(p->help, stdout);
      cli_help(stdout, p->opt, p->nopt);
      printf("\nExit status: 0 ok, 2 bad command line, 3 cannot write.\n");
      return EXIT_OK;
    } else
      a->v[row] = arg ? v : 1;
  }
  if (study_operands(p, &c, a)) return EXIT_USAGE;
  if (!a->out) {
    cli_usage_error(&c, "missing -o OUT.h5");
    return EXIT_USAGE;
  }
  return -1;
}

/* OUT.h5 written by p->write under a temporary name: the exit code */
static int study_output(const study_prog *p, const study_args *a, int argc,
                        char **argv) {
  char *cmdline, err[4096 + 512];
  int rc;
  if (out_path_check(a->out, NULL, 0, err, sizeof err)) {
    fprintf(stderr, "%s: %s\n", p->prog, err);
    return EXIT_USAGE;
  }
  if (!(cmdline = cli_command_line(argc, argv))) {
    fprintf(stderr, "%s: out of memory\n", p->prog);
    return EXIT_IO;
  }
  /* what killed runs of this output left: reported, and removed when
     their process was of this host */
  stale_report(p->prog, a->out);
  tmpout_clean(a->out, 0, 1);
  if (tmpout_name(a->out, 0)) {
    free(cmdline);
    return EXIT_USAGE;
  }
  tmpout_arm();
  rc = p->write(tmpout_path(), cmdline, a);
  if (rc != EXIT_OK) {
    h5_cause(err, sizeof err);
    if (err[0]) fprintf(stderr, "%s: %s: HDF5: %s\n", p->prog, a->out, err);
  } else if (tmpout_commit(a->out)) {
    rc = EXIT_IO;
  }
  if (rc != EXIT_OK) {
    tmpout_discard();
    fprintf(stderr, "%s: %s not written\n", p->prog, a->out);
  }
  free(cmdline);
  return rc;
}

int study_main(const study_prog *p, study_args *a, int argc, char **argv) {
  int rc;
  /* fds 0-2 open, HDF5 without atexit, then the signal policy of
     tmpout.h: the temporary file is removed by a signal that ends us;
     GSL's errors returned, HDF5's captured */
  proc_init();
  tmpout_prog(p->prog);
  sig_init();
  gsl_set_error_handler_off();
  h5_errors_capture();
  if ((rc = study_parse(p, a, argc, argv)) < 0) {
    rc = study_output(p, a, argc, argv);
    if (rc == EXIT_OK && p->says_written) printf("wrote %s\n", a->out);
  }
  return proc_exit(rc);
}

double study_now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return 1e9 * (double)ts.tv_sec + (double)ts.tv_nsec;
}

double study_median(double *v, int n) {
  gsl_sort(v, 1, (size_t)n);
  return gsl_stats_median_from_sorted_data(v, 1, (size_t)n);
}

void study_traj_sine(rps3_traj *tr, const rps3_sine *sine) {
  memset(tr, 0, sizeof(*tr));
  tr->kind = RPS3_TRAJ_SINE;
  tr->sine = *sine;
}
