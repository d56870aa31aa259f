/*
 * study_run.c - what rps3-study and rps3-simstudy share around their
 * studies: the process set-up, the command line (cli.h, from each one's
 * option table) and the output file, written under a temporary name next
 * to OUT.h5 (tmpout.h, as rps3-run's) and renamed when complete; the
 * clock, the median and the sine trajectories of the studies.
 *
 * The files of rps3-study follow the runner's conventions, with its
 * helpers (output.h): units and description on every dataset, dimension
 * scales on every axis, Fletcher-32 on every chunk, and the root
 * attributes rps3_version, created_utc, command_line, gsl_version,
 * hdf5_version and title; CF's long_name on every dataset (long_names
 * below) and the root Conventions, history and git_revision (out_h5.h).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>
#include <gsl/gsl_version.h>
#include <hdf5_hl.h>

#include "core/h5err.h"
#include "core/safeio.h"
#include "core/tmpout.h"
#include "output/output.h"
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
  for (i = 0; p->studies[i] && strcmp(p->studies[i], op[0]) != 0; i++) continue;
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

/* the CF long_name of every dataset of the study files, by name: a
   dataset missing here is refused (study_h5_write), so that none is
   written without one */
static const struct {
  const char *name, *long_name;
} long_names[] = {
    /* workspace */
    {"rho", "platform radius over base radius"},
    {"alpha", "platform precession angle"},
    {"beta", "platform nutation angle"},
    {"z_c", "platform centre height"},
    {"link", "link number"},
    {"status", "status"},
    {"condition", "condition number of the constraint Jacobian"},
    {"transmission", "force transmission"},
    {"force", "static actuating force along the link"},
    {"max_force", "largest static actuating force magnitude"},
    {"mode", "assembly mode"},
    /* accuracy */
    {"trajectory", "trajectory name"},
    {"config", "configuration index"},
    {"study", "knob the configuration turns"},
    {"label", "configuration label"},
    {"theta_route", "theta route"},
    {"solver", "theta solver"},
    {"derivative", "rate computation"},
    {"method", "formulation of the dynamics"},
    {"tolerance", "theta solve tolerance"},
    {"fd_step", "finite-difference step"},
    {"dt_fraction", "sample interval over trajectory duration"},
    {"effects", "selected effects bits"},
    {"warm_start", "theta solve warm start"},
    {"ns_per_point", "median time per sample"},
    {"ns_per_point_q1", "first quartile of time per sample"},
    {"ns_per_point_q3", "third quartile of time per sample"},
    {"ns_per_second", "time per simulated second of trajectory"},
    {"force_error", "relative actuating force error"},
    {"theta_error", "link angle error"},
    {"peak_force_error", "relative peak force error"},
    {"energy_residual", "relative energy residual"},
    {"mean_iterations", "mean theta solve iterations"},
    {"failed_samples", "failed samples"},
    {"reference_floor_force", "relative rounding floor of the reference force"},
    {"reference_floor_theta", "rounding floor of the reference theta"},
    {"reference_force_max", "largest reference force magnitude"},
    {"reference_peak_force", "peak reference force magnitude"}};

static const char *long_name_of(const char *name) {
  size_t i;
  for (i = 0; i < sizeof long_names / sizeof long_names[0]; i++)
    if (strcmp(long_names[i].name, name) == 0) return long_names[i].long_name;
  return NULL;
}

/* the compression of the maps (rank >= 3), as the runner's default */
#define STUDY_GZIP 4

int study_h5_open(study_h5 *o, const char *path, const char *cmdline,
                  const char *title) {
  char now[32], h5v[32];
  unsigned maj, min, rel;
  const char *const kv[][2] = {{"rps3_version", rps3_version()},
                               {"created_utc", now},
                               {"command_line", cmdline},
                               {"gsl_version", gsl_version},
                               {"hdf5_version", h5v},
                               {"title", title}};
  o->str = -1;
  o->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (o->file < 0) return -1;
  o->str = H5Tcopy(H5T_C_S1);
  if (o->str < 0 || H5Tset_size(o->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(o->str, H5T_CSET_UTF8) < 0)
    return -1;
  out_utc_now(now);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return out_h5_attrs(o->file, o->str, kv, 6) < 0 ||
                 out_cf_root(o->file, o->str, now, cmdline) < 0
             ? -1
             : 0;
}

int study_h5_close(study_h5 *o) {
  int rc = 0;
  if (o->str >= 0 && H5Tclose(o->str) < 0) rc = -1;
  if (o->file >= 0 && H5Fclose(o->file) < 0) rc = -1;
  return rc;
}

/* attach the named scales to ds's dimensions (NULL: ds is that scale) */
static int attach_scales(const study_h5 *o, hid_t ds, const char *name,
                         int rank, const char *const *scales) {
  int k, bad;
  if (!scales) return H5DSset_scale(ds, name) < 0 ? -1 : 0;
  for (k = 0; k < rank; k++) {
    hid_t sc = H5Dopen2(o->file, scales[k], H5P_DEFAULT);
    if (sc < 0) return -1;
    bad = H5DSattach_scale(ds, sc, (unsigned)k) < 0;
    H5Dclose(sc);
    if (bad) return -1;
  }
  return 0;
}

int study_h5_write(study_h5 *o, const char *name, hid_t type, int rank,
                   const hsize_t *dims, const void *data, const char *units,
                   const char *doc, const char *const *scales) {
  hsize_t chunk[8];
  hid_t ds;
  const char *long_name = long_name_of(name);
  int k, rc = -1;
  if (rank > 8 || !long_name) return -1;
  /* the maps: one chunk per leading index, deflated */
  chunk[0] = 1;
  for (k = 1; k < rank; k++) chunk[k] = dims[k];
  ds = out_h5_dataset(o->file, o->str, name, type, rank, dims,
                      rank >= 3 ? chunk : NULL, STUDY_GZIP, NULL, units, doc);
  if (ds < 0) return -1;
  if (out_cf_long_name(ds, o->str, long_name) == 0 &&
      H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0 &&
      attach_scales(o, ds, name, rank, scales) == 0)
    rc = 0;
  H5Dclose(ds);
  return rc;
}
