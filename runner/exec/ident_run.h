/*
 * ident_run.h - an identification (scene/identify.h): the regressor of the
 * paper model (rps3_regressor) and the forces of the inverse dynamics
 * (rps3_inverse) at every sample of the scene's trajectory, the fit of
 * the identify section's parameters (rps3_ident_wls, and with
 * identify.consistent rps3_ident_consistent), and its Monte Carlo: draw i
 * adds Gaussian noise of force_noise times each actuator's RMS force,
 * seeded by (seed, i) alone, and is fitted.  The draws are computed in
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

/* what an identification computes, built once (ident_plan_make) */
typedef struct {
  scene_case c;                   /* the scene's one case */
  size_t ns, n, p;                /* samples, rows 3 ns, columns fitted */
  int col[RPS3_NPAPER];           /* the paper column of fitted column j */
  const char *names[RPS3_NPAPER]; /* rps3_paper_name of each */
  double *Y;                      /* n x p regressor, row 3 k + i: sample k,
                                     actuator i */
  double *F0;                     /* n forces of the inverse dynamics [N] */
  double *ones;                   /* n unit weights (method ols) */
  int measured;                   /* 1: rows of identify.data, else of the
                                     trajectory */
  double truth[RPS3_NPAPER];      /* the model's values (rps3_paper_params):
                                     nominal ones with measured data */
  double rms[3];                  /* each actuator's RMS force [N] */
  double share[RPS3_NPAPER];      /* |Y_j truth_j| RMS / RMS force */
  scene_ident ids;                /* the identify section */
  rps3_ident_opts opts;           /* the library's defaults, ids.level */
  size_t nunit;                   /* work units of the draws */
  char warning[320];              /* why a result may be wrong, or "" */
} ident_plan;

/* one fit: rps3_ident_result's values, the consistent fit's */
typedef struct {
  int status; /* rps3_ident_wls's */
  char msg[256];
  double theta[RPS3_NPAPER], std[RPS3_NPAPER], ci[RPS3_NPAPER][2];
  double cov[RPS3_NPAPER * RPS3_NPAPER];
  int unident[RPS3_NPAPER];
  double sigma[3], s2, cond, resid_rms;
  size_t rank, dof;
  int cstatus;    /* rps3_ident_consistent's; -1 not run */
  int consistent; /* fit->consistent */
  char cmsg[256];
  double ctheta[RPS3_NPAPER], body[2][10], eig[2][4], crss, gap;
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

/* draws of shard k of n (all for n = 1) */
size_t ident_shard_draws(const ident_plan *p, size_t k, size_t n);

/* Create the file at path: root attributes and scene (out_open), the fit
   r of the noise-free forces, and the per-draw datasets when the plan has
   draws; NULL with err.  Closed by out_close. */
out_file *ident_file_open(const char *path, const scene *s, const ident_plan *p,
                          const ident_fit *r, const out_meta *meta, char *err,
                          size_t errsz);

/* The draws of shard `shard` of `nshard` into f on nthread threads,
   counts in st.  Returns 0, or -1 with err. */
int ident_mc_run(const ident_plan *p, out_file *f, size_t shard, size_t nshard,
                 int nthread, progress *pr, sweep_stats *st, char *err,
                 size_t errsz);

/*
 * The Monte Carlo's summary of the open file (read-write): per parameter
 * its median relative error, relative bias and the coverage of its
 * intervals over the draws whose status is 0, written to the mc_*
 * summary datasets and, when out is not NULL, printed as a table.
 * A file that is not an identification with draws: nothing, 0.  Returns
 * 0 or -1 with err.
 */
int ident_summary(hid_t file, FILE *out, char *err, size_t errsz);

/* ident_summary of the file at path (merge's last step) */
int ident_summary_path(const char *path, FILE *out, char *err, size_t errsz);

#endif /* RPS3_RUNNER_IDENT_RUN_H */
