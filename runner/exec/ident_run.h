/*
 * ident_run.h - an identification (scene/identify.h): the regressor of the
 * paper model (rps3_regressor), or of the general model's layout
 * (rps3_regressor_std) reduced to its structural base parameters
 * (rps3_ident_base), and the forces of the inverse dynamics
 * (rps3_inverse) at every sample of the scene's trajectory, the fit of
 * the identify section's parameters (rps3_ident_wls, and with
 * identify.consistent rps3_ident_consistent), and its Monte Carlo: draw i
 * adds Gaussian noise of force_noise times each actuator's RMS force,
 * seeded by (seed, i) alone, and its first 1 - holdout of the samples
 * are fitted (and with identify.consistent by the consistent fit too), the
 * rest predicted (held-out NRMSE).  The draws are computed in
 * work units of IDENT_UNIT draws on the worker pool (pool.h), shard K of N
 * the units j with j mod N = K; a unit is one chunk row of every per-draw
 * dataset, so a part merges as a sweep's (shards/merge.h).  The file's
 * layout: docs/identification.md, "Through the runner".
 */
#ifndef RPS3_RUNNER_IDENT_RUN_H
#define RPS3_RUNNER_IDENT_RUN_H

#include <stdio.h>

#include <hdf5.h>

#include "core/progress.h"
#include "output/output.h"
#include "scene/identify.h"
#include "sweep.h"

/* draws per work unit (a chunk row of the per-draw datasets) */
#define IDENT_UNIT 8

/* a parameter counts in the Monte Carlo's summary when its share of the
   RMS force, |Y_k theta_k| RMS over the RMS force, is at least this: below
   it the data say little about it and its relative error is no test */
#define IDENT_SHARE_MIN 0.01

/* a parameter whose truth's column carries less than this share of the
   RMS force is zero in truth (a general body's product of inertia, at
   the rounding of its parallel-axis sum): its relative error is not
   defined, and the summary gives none */
#define IDENT_SHARE_ZERO 1e-9

/* the most columns a fit has: the general model's standard parameters */
#define IDENT_PMAX RPS3_NSTD

/* the structural base parameters of the general model: the layout's
   regressor at IDENT_BASE_STATES random states (GSL's mt19937 seeded with
   IDENT_BASE_SEED: alpha U(-pi, pi), beta U(0.05, 0.45) rad, z_c U(0.27,
   0.36) m, rates N(0, 1) [1, 0.5, 0.05], accelerations N(0, 1) [5, 2,
   0.3], the lengths and z scaled by R / 0.2286; as
   rps3.ident_excite.layout_base), rps3_ident_base at IDENT_BASE_TOL */
#define IDENT_BASE_STATES 300
#define IDENT_BASE_SEED 7
#define IDENT_BASE_TOL 1e-7

/* what an identification computes, built once (ident_plan_make) */
typedef struct {
  scene_case c;                  /* the scene's one case */
  size_t ns, n, p;               /* samples, rows 3 ns, columns fitted */
  int general;                   /* 1: the general model (identify.model) */
  int col[IDENT_PMAX];           /* the paper column (general: the layout
                                    column) of fitted column j */
  const char *names[IDENT_PMAX]; /* rps3_paper_name (general: the layout's
                                    name) of each */
  /* the general model's layout (python/rps3/ident.py Layout): its
     columns, each the sum of up to three standard columns (identical
     legs), and the bodies of the consistent fit */
  size_t nlay, nbody;
  char lay_name[IDENT_PMAX][24];
  const char *lay_names[IDENT_PMAX];
  int lay_std[IDENT_PMAX][3];   /* standard columns (rps3_std_name), -1 */
  int lay_kind[IDENT_PMAX];     /* RPS3_IDENT_FREE or _NONNEG */
  char body_name[RPS3_NBODY][12];
  const char *body_names[RPS3_NBODY];
  int body_col[RPS3_NBODY][10]; /* layout columns of each body */
  double *K;                    /* nbase x nlay grouping: base = K pi */
  double *Ylay;                 /* n x nlay layout regressor */
  double lay_truth[IDENT_PMAX]; /* the scene's layout parameters */
  double std_truth[RPS3_NSTD];  /* the scene's standard parameters */
  double *Y;                    /* n x p regressor, row 3 k + i: sample k,
                                   actuator i */
  double *F0;                   /* n forces of the inverse dynamics [N] */
  double *ones;                 /* n unit weights (method ols) */
  int measured;                 /* 1: rows of identify.data, else of the
                                   trajectory */
  double truth[IDENT_PMAX];     /* the model's values (rps3_paper_params;
                                   general: K times the layout's): nominal
                                   ones with measured data */
  double rms[3];                /* each actuator's RMS force [N] */
  double share[IDENT_PMAX];     /* |Y_j truth_j| RMS / RMS force */
  scene_ident ids;              /* the identify section */
  rps3_ident_opts opts;         /* the library's defaults, ids.level */
  size_t nunit;                 /* work units of the draws */
  size_t nfit;                  /* rows the draws fit: the first of the
                                   samples, 1 - identify.monte_carlo.holdout
                                   of them; the rest are predicted */
  char warning[640];            /* why a result may be wrong, or "" */
} ident_plan;

/* one fit: rps3_ident_result's values, the consistent fit's */
typedef struct {
  int status; /* rps3_ident_wls's */
  char msg[512];
  double theta[IDENT_PMAX], std[IDENT_PMAX], ci[IDENT_PMAX][2];
  double *cov; /* p x p, malloc'd by ident_fit_run (ident_fit_free) */
  int unident[IDENT_PMAX];
  double sigma[3], s2, cond, resid_rms;
  size_t rank, dof;
  int cstatus;    /* rps3_ident_consistent's; -1 not run */
  int consistent; /* fit->consistent */
  char cmsg[256];
  /* the consistent fit: the fitted columns (general: the layout's) */
  double ctheta[IDENT_PMAX], body[RPS3_NBODY][10], eig[RPS3_NBODY][4];
  double crss, gap;
  int niter;
} ident_fit;

/* The plan of identification s: its case, the parameters, Y and F0 along
   the trajectory, the truth and shares.  0, or -1 with err at the key or
   section that is wrong (a parameter the effects leave at zero, a sample
   the inverse dynamics fails at); free with ident_plan_free. */
int ident_plan_make(const scene *s, ident_plan *p, scene_error *err);
void ident_plan_free(ident_plan *p);

/* Fit forces F (n) with the plan's method (and the consistent fit when
   `consistent`) into r; r->status the fit's.  Allocates (GSL): not for a
   per-point path. */
void ident_fit_run(const ident_plan *p, const double *F, int consistent,
                   ident_fit *r);

/* ident_fit_run on the first n rows of the plan (Y, Ylay) and F */
void ident_fit_rows(const ident_plan *p, const double *F, size_t n,
                    int consistent, ident_fit *r);

/* The held-out NRMSE of fit r on rows [p->nfit, p->n) of forces F: the
   RMS of the prediction minus F over the RMS of F, the prediction Y theta
   (wls) and that of the consistent fit (general: Ylay times its layout
   parameters) in cons; NaN for a fit that failed, none held out, or a
   consistent fit not run. */
void ident_holdout_nrmse(const ident_plan *p, const double *F,
                         const ident_fit *r, double *wls, double *cons);

/* free what ident_fit_run allocated (r may be zeroed) */
void ident_fit_free(ident_fit *r);

/*
 * The manipulator section (YAML, "manipulator:\n  ...") of the fit r: the
 * general model's from the consistent fit (bodies general, each body's
 * mass, com and inertia about the com, the friction), the paper model's
 * from the consistent fit or else the estimate (M, m = md / d, link_Ic =
 * Ipin - m d^2, the payload, the pin friction); what is not fitted keeps
 * the scene's values.  Returns a malloc'd text, or NULL with why (no
 * consistent fit for the general model, a value outside the scene's
 * ranges).
 */
char *ident_manipulator_yaml(const ident_plan *p, const ident_fit *r,
                             char *why, size_t whysz);

/* draws of shard k of n (all for n = 1) */
size_t ident_shard_draws(const ident_plan *p, size_t k, size_t n);

/* Create the file at path: root attributes and scene (out_open), the fit
   r of the noise-free forces, the manipulator section yaml (root attribute
   manipulator_yaml; NULL: yaml_why in manipulator_yaml_missing), and the
   per-draw datasets when the plan has draws; NULL with err.  Closed by out_close. */
out_file *ident_file_open(const char *path, const scene *s, const ident_plan *p,
                          const ident_fit *r, const char *yaml,
                          const char *yaml_why, const out_meta *meta,
                          char *err, size_t errsz);

/* The draws of shard `shard` of `nshard` into f on nthread threads,
   counts in st.  Returns 0, or -1 with err. */
int ident_mc_run(const ident_plan *p, out_file *f, size_t shard, size_t nshard,
                 int nthread, progress *pr, sweep_stats *st, char *err,
                 size_t errsz);

/*
 * The Monte Carlo's summary of the open file (read-write): per parameter
 * its median relative error, relative bias and the coverage of its
 * intervals over the draws whose status is 0, and of the draws' held-out
 * NRMSEs and consistent fits (the fractions consistent and converged, the
 * NRMSE ratio consistent / WLS), written to the mc_* summary datasets
 * and, when out is not NULL, printed.
 * A file that is not an identification with draws: nothing, 0.  Returns
 * 0 or -1 with err.
 */
int ident_summary(hid_t file, FILE *out, char *err, size_t errsz);

/* ident_summary of the file at path (merge's last step) */
int ident_summary_path(const char *path, FILE *out, char *err, size_t errsz);

#endif /* RPS3_RUNNER_IDENT_RUN_H */
