/*
 * study.h - what the files of rps3-study and rps3-simstudy share: the
 * configurations of the accuracy study, one configuration on one
 * trajectory, the reference it is graded against, the programs' main
 * (study_run.c) and the HDF5 helpers (study_h5.c).  study_points.c holds
 * the trajectories, the configurations and one point by a configuration's
 * route; study_ref.c the force reference (Kane's equations).
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
#define NTRAJ 2
#define MAXCFG 256
#define NREF_PEAK 200001

/* the largest finite-difference step: samples keep this margin from the
   trajectory's ends */
#define FD_MARGIN 1e-2

/* a quiet NaN as a double (DNAN is a float) */
#define DNAN ((double)NAN)

/* rps3-simstudy's exit code when a run that must succeed failed */
enum { EXIT_RUN = 4 };

typedef enum {
  S_THETA,
  S_DERIV,
  S_METHOD,
  S_EFFECTS,
  S_DT,
  S_NSTUDY
} study_kind;

typedef enum {
  D_EXACT,
  D_FD_POSE,
  D_FD_LENGTH,
  D_FD_SAMPLES,
  D_SPLINE
} deriv_kind;

extern const char *const study_kind_name[S_NSTUDY];
extern const char *const study_deriv_name[5];

typedef struct {
  study_kind study;
  char label[64];
  rps3_theta_route theta;
  int solver; /* rps3_solver, -1 for closed form */
  double tol;
  int warm;
  deriv_kind deriv;
  double h; /* finite-difference step, or the spline's row spacing
               [s]; 0 for exact */
  rps3_method method;
  int effects;
  double dt_frac; /* dt study: sample interval / duration; 0 otherwise */
} study_config;

/* results of one configuration on one trajectory */
typedef struct {
  double ns_point;     /* median ns per sample */
  double ns_q1, ns_q3; /* quartiles of the passes */
  double ns_second;    /* ns per second of trajectory */
  double force_err;    /* max |F - F_ref| / max |F_ref| */
  double theta_err;    /* max |theta - theta_ld| [rad] */
  double peak_err;     /* dt: (peak_ref - peak) / peak_ref */
  double energy_err;   /* dt: max |W_k - dE_k| / max |W_k| */
  double mean_iter;    /* theta solve iterations per sample */
  int nfail;           /* samples that failed */
  int status;          /* first failing status, 0 if none */
} study_result;

/* one configuration on one trajectory: its model, data and tables */
typedef struct {
  rps3_model model; /* the configuration's model */
  rps3_data *d;
  const rps3_traj *tr;
  const study_config *c;
  rps3_traj table; /* spline_pose: the trajectory's poses every h */
  double *rows;    /* its arrays (time, pose, rate, scratch), or NULL */
} study_runner;

/* the precise reference of one trajectory */
typedef struct {
  size_t n; /* samples of the fixed grid */
  double span;
  double *F;          /* reference forces [n][3] */
  long double *theta; /* long-double theta [n][3] */
  double fscale;      /* max |F_ref| */
  double floor_ref;   /* estimated rounding error of F_ref / fscale */
  double floor_theta; /* max |theta_closed - theta_ld| */
  double peak;        /* reference peak |F| over NREF_PEAK samples */
} study_reference;

/* CLOCK_MONOTONIC in ns; the median of v[0..n) (sorts v) */
double study_now_ns(void);
double study_median(double *v, int n);

/* the two trajectories: names, one description, trajectory k */
extern const char *const study_traj_name[NTRAJ];
extern const char *const study_traj_doc;
void study_traj_make(int k, rps3_traj *tr);

/* *tr = the sine trajectory `sine` */
void study_traj_sine(rps3_traj *tr, const rps3_sine *sine);

/* inverse kinematics in long double, independent of src/ik.c: the
   reference angles theta_i of the pose */
void study_ik_long(const rps3_model *m, const double pose[3],
                   long double theta[3]);

/* a configuration of study s with every other knob at its default */
void study_config_base(study_config *c, study_kind s);

/* every configuration into cfg[MAXCFG]; their number */
int study_configs_build(study_config *cfg);

/* forces at time t by r's configuration; an rps3_status */
int study_point(study_runner *r, double t);

/* the time of sample k of n of the span, inside the margins */
double study_sample_time(size_t k, size_t n, double span);

/* r for configuration c on tr from the model base; 0, or -1 with a
   message on stderr */
int study_runner_init(study_runner *r, const study_config *c,
                      const rps3_traj *tr, const rps3_model *base);

/* T + P of the default effects at the data's state, written here from
   vc, omega and dtheta (not by the library) */
double study_energy(const rps3_model *m, const rps3_data *d);

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

/* create path with the root attributes of the runner's files and title;
   0 or -1 (study_h5_close then closes what was opened) */
int study_h5_open(study_h5 *o, const char *path, const char *cmdline,
                  const char *title);

/* close the file: 0 or -1 */
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
