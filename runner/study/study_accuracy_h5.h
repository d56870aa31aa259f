/*
 * study_accuracy_h5.h - the file of rps3-study accuracy
 * (study_accuracy_h5.c) and what the measurements (study_accuracy.c)
 * hand to it: the configurations, their results and the references.
 */
#ifndef RPS3_STUDY_ACCURACY_H5_H
#define RPS3_STUDY_ACCURACY_H5_H

#include <stddef.h>

#include "rps3.h"

#define NTRAJ 2
#define MAXCFG 256

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

/* the trajectories' names and the derivative kinds' */
extern const char *const study_traj_name[NTRAJ];
extern const char *const study_deriv_name[5];

/* the largest finite-difference step: samples keep this margin from the
   trajectory's ends */
#define FD_MARGIN 1e-2

/* a configuration of study s with every other knob at its default */
void study_config_base(study_config *c, study_kind s);

/* every configuration into cfg[MAXCFG] (study_accuracy_cfg.c); their
   number */
int study_configs_build(study_config *cfg);

/* the study's file at path: the configurations, the [trajectory, config]
   results and the references' numbers, with the samples and repeats
   counts; 0 or -1 (reported) */
int study_accuracy_write(const char *path, const char *cmdline,
                         const study_config *cfg, int ncfg,
                         const study_result res[][MAXCFG],
                         const study_reference *ref, size_t nsamp, int repeats);

#endif /* RPS3_STUDY_ACCURACY_H5_H */
