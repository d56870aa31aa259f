/*
 * ident_plan.h - what an identification computes (ident_run.h): its
 * constants, the plan (built once by ident_plan_make) and one fit's
 * results (ident_fit.h), shared by the plan, the fits, the draws and the
 * file.
 */
#ifndef RPS3_RUNNER_IDENT_PLAN_H
#define RPS3_RUNNER_IDENT_PLAN_H

#include <stddef.h>

#include "scene/identify.h"

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

#endif /* RPS3_RUNNER_IDENT_PLAN_H */
