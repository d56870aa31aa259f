/*
 * study_run.c - what rps3-study and rps3-simstudy share around their
 * studies: the process set-up and the output file, written under a
 * temporary name next to OUT.h5 (tmpout.h, as rps3-run's) and renamed when
 * complete.
 */
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_errno.h>

#include "core/cli.h"
#include "core/h5err.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "study.h"

int study_prog(const char *prog, int (*body)(int, char **), int argc,
               char **argv) {
  /* fds 0-2 open, HDF5 without atexit, then the signal policy of
     tmpout.h: the temporary file is removed by a signal that ends us;
     GSL's errors returned, HDF5's captured */
  proc_init();
  tmpout_prog(prog);
  sig_init();
  gsl_set_error_handler_off();
  h5_errors_capture();
  return proc_exit(body(argc, argv));
}

int study_output(const char *prog, const char *out, int argc, char **argv,
                 study_writer write, const void *arg) {
  char *cmdline, err[4096 + 512];
  int rc;
  if (out_path_check(out, NULL, 0, err, sizeof err)) {
    fprintf(stderr, "%s: %s\n", prog, err);
    return EXIT_USAGE;
  }
  if (!(cmdline = cli_command_line(argc, argv))) {
    fprintf(stderr, "%s: out of memory\n", prog);
    return EXIT_IO;
  }
  /* what killed runs of this output left: reported, and removed when
     their process was of this host */
  stale_report(prog, out);
  tmpout_clean(out, 0, 1);
  if (tmpout_name(out, 0)) {
    free(cmdline);
    return EXIT_USAGE;
  }
  tmpout_arm();
  rc = write(tmpout_path(), cmdline, arg);
  if (rc != EXIT_OK) {
    h5_cause(err, sizeof err);
    if (err[0]) fprintf(stderr, "%s: %s: HDF5: %s\n", prog, out, err);
  } else if (tmpout_commit(out)) {
    rc = EXIT_IO;
  }
  if (rc != EXIT_OK) {
    tmpout_discard();
    fprintf(stderr, "%s: %s not written\n", prog, out);
  }
  free(cmdline);
  return rc;
}
