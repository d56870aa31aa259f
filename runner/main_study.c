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
 * file is written under OUT.h5.tmp.PID and renamed when complete.
 * Exit codes: 0 ok, 2 bad command line, 3 the file could not be written.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_version.h>
#include <hdf5.h>
#include <hdf5_hl.h>

#include "h5err.h"
#include "rps3.h"
#include "study_ref.h"
#include "safeio.h"
#include "signals.h"

enum { EXIT_OK = 0, EXIT_USAGE = 2, EXIT_IO = 3 };

#define PI 3.14159265358979323846
#define NTRAJ 2
#define MAXCFG 256
#define NREF_PEAK 200001

/* the largest finite-difference step: samples keep this margin from the
   ends of the span so that every stencil fits inside it */
#define FD_MARGIN 1e-2

/* a quiet NaN as a double (DNAN is a float) */
#define DNAN ((double)NAN)

/* ------------------------------------------------------------- timing */

static double now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return 1e9 * (double)ts.tv_sec + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof(double), cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ------------------------------------------------ the two trajectories */

static const char *const traj_name[NTRAJ] = {"helix", "sine_edge"};
static const char *const traj_doc =
    "helix: Table II (r* = 0.266 mm, h = 30.48 mm, T* = 10 s, t_a = 1 s); "
    "sine_edge: alpha = pi sin(2 pi t), beta = 0.6 + 0.2 sin(2 pi 2.3 t), "
    "z_c = 0.28 + 0.03 sin(2 pi 1.7 t) m over 2 s: up to 20 rad/s, beta up to "
    "0.8 rad, condition number up to 4e2 near the singular surface";

static void traj_make(int k, rps3_traj *tr) {
  rps3_traj_default(tr);
  if (k == 0) return;
  memset(tr, 0, sizeof(*tr));
  tr->kind = RPS3_TRAJ_SINE;
  tr->sine.mean[1] = 0.6;
  tr->sine.mean[2] = 0.28;
  tr->sine.amp[0] = PI;
  tr->sine.amp[1] = 0.2;
  tr->sine.amp[2] = 0.03;
  tr->sine.freq[0] = 1.0;
  tr->sine.freq[1] = 2.3;
  tr->sine.freq[2] = 1.7;
  tr->sine.duration = 2.0;
}

/* ----------------------------------------------- long-double reference */

/*
 * Inverse kinematics (2)-(7), (39) in long double, written independently
 * of src/ik.c from the rotation Rz(a) Ry(b) Rz(-a), the centre (3)-(4) and
 * b_i = c + rot r_i: the reference angles theta_i and lengths l_i.
 */
static void ik_long(const rps3_model *m, const double pose[3],
                    long double theta[3], long double len[3]) {
  long double a = (long double)pose[0], b = (long double)pose[1];
  long double z = (long double)pose[2];
  long double ca = cosl(a), sa = sinl(a), cb = cosl(b), sb = sinl(b);
  long double r = (long double)m->rho * (long double)m->R;
  long double R = (long double)m->R;
  long double rot[3][3], c[3];
  long double s3 = sqrtl(3.0L);
  int i;
  /* Rz(a) Ry(b) Rz(-a) */
  rot[0][0] = ca * ca * cb + sa * sa;
  rot[0][1] = ca * sa * cb - ca * sa;
  rot[0][2] = ca * sb;
  rot[1][0] = sa * ca * cb - sa * ca;
  rot[1][1] = sa * sa * cb + ca * ca;
  rot[1][2] = sa * sb;
  rot[2][0] = -sb * ca;
  rot[2][1] = -sb * sa;
  rot[2][2] = cb;
  /* (3)-(4) */
  c[0] = -0.5L * r * (1.0L - cb) * cosl(2.0L * a);
  c[1] = 0.5L * r * (1.0L - cb) * sinl(2.0L * a);
  c[2] = z;
  for (i = 0; i < 3; i++) {
    long double cp = i == 0 ? 1.0L : -0.5L;
    long double sp = i == 0 ? 0.0L : (i == 1 ? 0.5L : -0.5L) * s3;
    long double bb[3], v[3];
    int k;
    for (k = 0; k < 3; k++)
      bb[k] = c[k] + rot[k][0] * r * cp + rot[k][1] * r * sp;
    v[0] = bb[0] - R * cp;
    v[1] = bb[1] - R * sp;
    v[2] = bb[2];
    len[i] = sqrtl(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    theta[i] = atan2l(v[2], -(v[0] * cp + v[1] * sp));
  }
}

/* ------------------------------------------------------ configurations */

typedef enum {
  S_THETA, S_DERIV, S_METHOD, S_EFFECTS, S_DT, S_NSTUDY
} study_kind;
static const char *const study_name[S_NSTUDY] = {"theta", "derivative",
                                                 "method", "effects", "dt"};

typedef enum {
  D_EXACT, D_FD_POSE, D_FD_LENGTH, D_FD_SAMPLES, D_SPLINE
} deriv_kind;
static const char *const deriv_name[5] = {"exact", "fd_pose", "fd_length",
                                          "fd_samples", "spline_pose"};

typedef struct {
  study_kind study;
  char label[64];
  rps3_theta_route theta;
  int solver;       /* rps3_solver, -1 for closed form */
  double tol;
  int warm;
  deriv_kind deriv;
  double h;         /* finite-difference step, or the spline's row spacing
                       [s]; 0 for exact */
  rps3_method method;
  int effects;
  double dt_frac;   /* dt study: sample interval / duration; 0 otherwise */
} config;

/* results of one configuration on one trajectory */
typedef struct {
  double ns_point;      /* median ns per sample */
  double ns_q1, ns_q3;  /* quartiles of the passes */
  double ns_second;     /* ns per second of trajectory */
  double force_err;     /* max |F - F_ref| / max |F_ref| */
  double theta_err;     /* max |theta - theta_ld| [rad] */
  double peak_err;      /* dt: (peak_ref - peak) / peak_ref */
  double energy_err;    /* dt: max |W_k - dE_k| / max |W_k| */
  double mean_iter;     /* theta solve iterations per sample */
  int nfail;            /* samples that failed */
  int status;           /* first failing status, 0 if none */
} result;

static const double tols[7] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14};
static const double steps[6] = {FD_MARGIN, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
/* row spacings of the spline of the pose: 100 Hz is a motion-capture rate,
   1 kHz an encoder's */
static const double spacings[3] = {1e-1, 1e-2, 1e-3};
static const double dt_fracs[9] = {5e-2, 2e-2, 1e-2, 5e-3,
                                   2e-3, 1e-3, 5e-4, 2e-4, 1e-4};
/* the effects ladder: gravity only -> every effect */
static const int ladder[RPS3_NEFFECT] = {
    RPS3_EFF_PLATFORM_GRAVITY,
    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY,
    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY |
        RPS3_EFF_PLATFORM_INERTIA,
    RPS3_EFF_DEFAULT,
    RPS3_EFF_DEFAULT | RPS3_EFF_PAYLOAD,
    RPS3_EFF_ALL};

static void config_base(config *c, study_kind s) {
  memset(c, 0, sizeof(*c));
  c->study = s;
  c->theta = RPS3_THETA_CLOSED_FORM;
  c->solver = -1;
  c->tol = 1e-12;
  c->warm = 1;
  c->deriv = D_EXACT;
  c->method = RPS3_LAGRANGE;
  c->effects = RPS3_EFF_DEFAULT;
}

static int configs_build(config *cfg) {
  int n = 0, s, t, w, k, e;
  /* theta */
  config_base(&cfg[n], S_THETA);
  snprintf(cfg[n].label, sizeof cfg[n].label, "closed form (39)");
  n++;
  for (s = 0; s < RPS3_NSOLVER; s++)
    for (t = 0; t < 7; t++)
      for (w = 0; w < 2; w++) {
        config_base(&cfg[n], S_THETA);
        cfg[n].theta = RPS3_THETA_MULTIROOT;
        cfg[n].solver = s;
        cfg[n].tol = tols[t];
        cfg[n].warm = w;
        snprintf(cfg[n].label, sizeof cfg[n].label, "%s tol=%.0e %s",
                 rps3_solver_name(s), tols[t], w ? "warm" : "cold");
        n++;
      }
  /* derivative route */
  config_base(&cfg[n], S_DERIV);
  snprintf(cfg[n].label, sizeof cfg[n].label, "exact rates");
  n++;
  for (k = D_FD_POSE; k <= D_FD_LENGTH; k++)
    for (t = 0; t < 6; t++) {
      config_base(&cfg[n], S_DERIV);
      cfg[n].deriv = (deriv_kind)k;
      cfg[n].h = steps[t];
      snprintf(cfg[n].label, sizeof cfg[n].label, "%s h=%.0e s",
               deriv_name[k], steps[t]);
      n++;
    }
  for (t = 0; t < 3; t++) {
    config_base(&cfg[n], S_DERIV);
    cfg[n].deriv = D_SPLINE;
    cfg[n].h = spacings[t];
    snprintf(cfg[n].label, sizeof cfg[n].label, "%s h=%.0e s",
             deriv_name[D_SPLINE], spacings[t]);
    n++;
  }
  /* method */
  for (k = 0; k < 2; k++) {
    config_base(&cfg[n], S_METHOD);
    cfg[n].method = k ? RPS3_NEWTON_EULER : RPS3_LAGRANGE;
    snprintf(cfg[n].label, sizeof cfg[n].label, "%s",
             k ? "newton_euler" : "lagrange");
    n++;
  }
  /* effects */
  for (e = 0; e < RPS3_NEFFECT; e++) {
    config_base(&cfg[n], S_EFFECTS);
    cfg[n].effects = ladder[e];
    snprintf(cfg[n].label, sizeof cfg[n].label, "+%s", rps3_effect_name(e));
    n++;
  }
  /* sample interval, exact rates and rates differenced from the samples */
  for (k = 0; k < 2; k++)
    for (t = 0; t < 9; t++) {
      config_base(&cfg[n], S_DT);
      cfg[n].dt_frac = dt_fracs[t];
      cfg[n].deriv = k ? D_FD_SAMPLES : D_EXACT;
      snprintf(cfg[n].label, sizeof cfg[n].label, "dt=T/%.0f %s",
               1.0 / dt_fracs[t], k ? "rates from samples" : "exact rates");
      n++;
    }
  return n;
}

/* ------------------------------------------------------------ one point */

typedef struct {
  rps3_model model;     /* the configuration's model */
  rps3_data *d;
  const rps3_traj *tr;
  const config *c;
  double prev[3];       /* last theta solution, for the explicit warm start */
  int have_prev;
  rps3_traj table;      /* spline_pose: the trajectory's poses every h */
  double *rows;         /* its arrays (time, pose, rate, scratch), or NULL */
} runner;

/*
 * Forces at time t by the configuration's route.  Exact: the trajectory's
 * derivatives and rps3_inverse.  fd_pose: central differences of the pose
 * at t +- h.  fd_length: inverse kinematics at t +- h, central differences
 * of the link lengths, then the joint-rate route (25)-(30).
 */
static int point(runner *r, double t, double span) {
  rps3_data *d = r->d;
  const rps3_model *m = &r->model;
  double h = r->c->h, p0[3], pm[3], pp[3], lm[3], lp[3];
  int st, i;
  if (r->c->deriv == D_EXACT || r->c->deriv == D_FD_SAMPLES)
    return rps3_traj_eval(m, r->tr, t, d->pose, d->dpose, d->ddpose) ||
           rps3_inverse(m, d);
  if (r->c->deriv == D_SPLINE)
    return rps3_traj_eval(m, &r->table, t, d->pose, d->dpose, d->ddpose) ||
           rps3_inverse(m, d);
  (void)span;
  if ((st = rps3_traj_eval(m, r->tr, t - h, pm, NULL, NULL)) != RPS3_OK ||
      (st = rps3_traj_eval(m, r->tr, t + h, pp, NULL, NULL)) != RPS3_OK ||
      (st = rps3_traj_eval(m, r->tr, t, p0, NULL, NULL)) != RPS3_OK)
    return st;
  if (r->c->deriv == D_FD_POSE) {
    for (i = 0; i < 3; i++) {
      d->pose[i] = p0[i];
      d->dpose[i] = (pp[i] - pm[i]) / (2.0 * h);
      d->ddpose[i] = (pp[i] - 2.0 * p0[i] + pm[i]) / (h * h);
    }
    return rps3_inverse(m, d);
  }
  /* fd_length */
  memcpy(d->pose, pm, sizeof(pm));
  if ((st = rps3_ik(m, d)) != RPS3_OK) return st;
  memcpy(lm, d->l, sizeof(lm));
  memcpy(d->pose, pp, sizeof(pp));
  if ((st = rps3_ik(m, d)) != RPS3_OK) return st;
  memcpy(lp, d->l, sizeof(lp));
  memcpy(d->pose, p0, sizeof(p0));
  if ((st = rps3_ik(m, d)) != RPS3_OK) return st;
  for (i = 0; i < 3; i++) {
    d->dl[i] = (lp[i] - lm[i]) / (2.0 * h);
    d->ddl[i] = (lp[i] - 2.0 * d->l[i] + lm[i]) / (h * h);
  }
  if ((st = rps3_joint_velocity(m, d)) != RPS3_OK ||
      (st = rps3_joint_acceleration(m, d)) != RPS3_OK)
    return st;
  return rps3_invdyn(m, d);
}

/* the time of sample k of n: interior points (k + 1/2) / n of the span
   less the margins, so that no sample sits on a helix corner */
static double sample_time(size_t k, size_t n, double span) {
  return FD_MARGIN + (span - 2.0 * FD_MARGIN) * ((double)k + 0.5) / (double)n;
}

/* spline_pose: the trajectory's poses every h (the last row at the span),
   the rates from rps3_table_spline, as rps3-run reads a table */
static int spline_rows(runner *r) {
  double span = rps3_traj_duration(r->tr), *time, (*pose)[3], (*rate)[3];
  size_t n = (size_t)floor(span / r->c->h + 0.5) + 1, i;
  r->rows = malloc(8 * n * sizeof(double));
  if (!r->rows) return -1;
  time = r->rows;
  pose = (double(*)[3])(void *)(r->rows + n);
  rate = (double(*)[3])(void *)(r->rows + 4 * n);
  for (i = 0; i < n; i++) {
    time[i] = i + 1 == n ? span : (double)i * r->c->h;
    if (rps3_traj_eval(&r->model, r->tr, time[i], pose[i], NULL, NULL) !=
        RPS3_OK)
      return -1;
  }
  if (rps3_table_spline(n, time, (const double(*)[3])pose, rate,
                        r->rows + 7 * n) != RPS3_OK)
    return -1;
  rps3_traj_default(&r->table);
  r->table.kind = RPS3_TRAJ_TABLE;
  r->table.table.n = n;
  r->table.table.time = time;
  r->table.table.value = (const double(*)[3])pose;
  r->table.table.rate = (const double(*)[3])rate;
  return rps3_traj_check(&r->model, &r->table, NULL, 0) == RPS3_OK ? 0 : -1;
}

static int runner_init(runner *r, const config *c, const rps3_traj *tr,
                       const rps3_model *base) {
  char err[256];
  r->model = *base;
  r->model.opt.theta = c->theta;
  r->model.opt.solver = c->solver < 0 ? RPS3_SOLVER_HYBRIDSJ
                                      : (rps3_solver)c->solver;
  r->model.opt.tol = c->tol;
  r->model.opt.warm_start = c->warm;
  r->model.opt.method = c->method;
  r->model.opt.effects = c->effects;
  r->model.opt.certify = c->study == S_DT;
  r->model.opt.max_iter = 100;
  if (rps3_model_init(&r->model, err, sizeof err) != RPS3_OK) {
    fprintf(stderr, "rps3-study: %s: %s\n", c->label, err);
    return -1;
  }
  r->tr = tr;
  r->c = c;
  r->d = NULL;
  r->rows = NULL;
  if (rps3_data_alloc(&r->model, &r->d) != RPS3_OK ||
      (c->deriv == D_SPLINE && spline_rows(r) < 0)) {
    fprintf(stderr, "rps3-study: %s: out of memory\n", c->label);
    return -1;
  }
  return 0;
}

/* ------------------------------------------------------------ energy */

/* kinetic and potential energy of the default effects at the data's
   current state, written here from vc, omega, dtheta (not by the library) */
static double energy(const rps3_model *m, const rps3_data *d) {
  double T, P, wb[3] = {0, 0, 0};
  int i, k;
  /* omega in platform axes: rot^T omega */
  for (k = 0; k < 3; k++)
    for (i = 0; i < 3; i++) wb[k] += d->rot[i][k] * d->omega[i];
  T = 0.5 * m->M * (d->vc[0] * d->vc[0] + d->vc[1] * d->vc[1] +
                    d->vc[2] * d->vc[2]) +
      0.5 * (m->Ip[0] * wb[0] * wb[0] + m->Ip[1] * wb[1] * wb[1] +
             m->Ip[2] * wb[2] * wb[2]);
  P = m->M * m->g * d->c[2];
  for (i = 0; i < 3; i++) {
    T += 0.5 * m->Jlink * d->dtheta[i] * d->dtheta[i];
    P += m->m * m->g * m->d * sin(d->theta[i]); /* (22) */
  }
  return T + P;
}

/* ------------------------------------------------------ accuracy study */

typedef struct {
  size_t n;             /* samples of the fixed grid */
  double span;
  double *F;            /* reference forces [n][3] */
  long double *theta;   /* long-double theta [n][3] */
  double fscale;        /* max |F_ref| */
  double floor_ref;     /* estimated rounding error of F_ref / fscale */
  double floor_theta;   /* max |theta_closed - theta_ld| */
  double peak;          /* reference peak |F| over NREF_PEAK samples */
} reference;

/*
 * The reference forces of `effects` at the n grid samples, by study_ref.c
 * (Kane's equations in long double, from the model's inputs: nothing of the
 * library's dynamics).  Its own floor: the same code in double lands at
 * some distance from it, the rounding of double amplified by the
 * formulation; in long double that amplification costs LDBL_EPSILON /
 * DBL_EPSILON as much.
 */
static int reference_forces(const rps3_model *base, const rps3_traj *tr,
                            int effects, reference *ref) {
  size_t k;
  int i;
  double dev = 0.0;
  ref->fscale = 0.0;
  for (k = 0; k < ref->n; k++) {
    double t = sample_time(k, ref->n, ref->span), q[3], dq[3], ddq[3], Fd[3];
    double *F = &ref->F[3 * k];
    if (rps3_traj_eval(base, tr, t, q, dq, ddq) != RPS3_OK ||
        study_ref_forces(base, effects, q, dq, ddq, F) != 0 ||
        study_ref_forces_double(base, effects, q, dq, ddq, Fd) != 0) {
      fprintf(stderr, "rps3-study: reference fails at t = %g\n", t);
      return -1;
    }
    for (i = 0; i < 3; i++) {
      if (fabs(F[i]) > ref->fscale) ref->fscale = fabs(F[i]);
      if (fabs(F[i] - Fd[i]) > dev) dev = fabs(F[i] - Fd[i]);
    }
  }
  ref->floor_ref = dev / ref->fscale * ((double)LDBL_EPSILON / DBL_EPSILON);
  return 0;
}

static int reference_build(const rps3_model *base, const rps3_traj *tr,
                           size_t n, reference *ref) {
  config c;
  runner r;
  size_t k;
  int i;
  ref->n = n;
  ref->span = rps3_traj_duration(tr);
  ref->F = malloc(3 * n * sizeof(double));
  ref->theta = malloc(3 * n * sizeof(long double));
  if (!ref->F || !ref->theta) return -1;
  if (reference_forces(base, tr, RPS3_EFF_DEFAULT, ref) < 0) return -1;
  /* theta: inverse kinematics in long double; its floor against the
     library's closed form */
  config_base(&c, S_METHOD);
  if (runner_init(&r, &c, tr, base) < 0) return -1;
  ref->floor_theta = ref->peak = 0.0;
  for (k = 0; k < n; k++) {
    double t = sample_time(k, n, ref->span);
    long double len[3];
    if (point(&r, t, ref->span) != RPS3_OK) {
      fprintf(stderr, "rps3-study: closed form fails at t = %g: %s\n", t,
              r.d->err.msg);
      return -1;
    }
    ik_long(&r.model, r.d->pose, &ref->theta[3 * k], len);
    for (i = 0; i < 3; i++) {
      double dth = fabs(r.d->theta[i] - (double)ref->theta[3 * k + i]);
      if (dth > ref->floor_theta) ref->floor_theta = dth;
    }
  }
  rps3_data_free(r.d);
  /* the peak force: a dense grid, ends and both sides of corners included */
  for (k = 0; k < NREF_PEAK; k++) {
    double t = ref->span * (double)k / (double)(NREF_PEAK - 1), q[3], dq[3],
           ddq[3], F[3];
    if (rps3_traj_eval(base, tr, t, q, dq, ddq) != RPS3_OK ||
        study_ref_forces(base, RPS3_EFF_DEFAULT, q, dq, ddq, F) != 0)
      return -1;
    for (i = 0; i < 3; i++)
      if (fabs(F[i]) > ref->peak) ref->peak = fabs(F[i]);
  }
  return 0;
}

/* one pass over the fixed grid; with out != NULL record the errors */
static int pass_grid(runner *r, const reference *ref, result *out) {
  size_t k;
  int i, st;
  double ferr = 0.0, terr = 0.0, iters = 0.0;
  rps3_data_reset(r->d);
  for (k = 0; k < ref->n; k++) {
    st = point(r, sample_time(k, ref->n, ref->span), ref->span);
    if (st != RPS3_OK) {
      if (!out) continue;
      if (out->nfail++ == 0) out->status = st;
      /* the next sample must not warm-start from a failed one */
      rps3_data_reset(r->d);
      continue;
    }
    if (!out) continue;
    iters += r->d->solve_niter;
    for (i = 0; i < 3; i++) {
      double fe = fabs(r->d->F[i] - ref->F[3 * k + i]);
      double te = fabs(r->d->theta[i] - (double)ref->theta[3 * k + i]);
      if (fe > ferr) ferr = fe;
      if (te > terr) terr = te;
    }
  }
  if (out) {
    int nok = (int)ref->n - out->nfail;
    out->force_err = nok ? ferr / ref->fscale : DNAN;
    out->theta_err = nok ? terr : DNAN;
    out->mean_iter = nok ? iters / nok : DNAN;
  }
  return 0;
}

/*
 * The sample-interval study: samples t_k = k dt over the whole span.  The
 * peak |F| over the samples against the reference peak; and the work of the
 * actuators over each interval (trapezoid of the power sum F_i dl_i) against
 * the change of T + P.  With exact rates the residual is the trapezoid's
 * O(dt^2); with rates differenced from the samples (what a logger gives:
 * central differences of the sampled poses, one-sided at the ends) it also
 * carries their error.
 */
static int pass_dt(runner *r, const reference *ref, result *out) {
  double span = ref->span, dt = r->c->dt_frac * span;
  size_t n = (size_t)floor(span / dt + 0.5) + 1, k;
  double peak = 0.0, Wmax = 0.0, resmax = 0.0, Eprev = 0.0, Pprev = 0.0;
  double tprev = 0.0;
  double q[3][3]; /* poses at k-1, k, k+1 */
  int i, st;
  rps3_data_reset(r->d);
  for (k = 0; k < n; k++) {
    double t = k == n - 1 ? span : (double)k * dt, E, P = 0.0;
    if (r->c->deriv == D_EXACT) {
      st = point(r, t, span);
    } else {
      /* rates from the samples themselves */
      size_t j;
      for (j = 0; j < 3; j++) {
        long kk = (long)k - 1 + (long)j;
        if (kk < 0) kk = 0;
        if (kk > (long)n - 1) kk = (long)n - 1;
        st = rps3_traj_eval(&r->model, r->tr,
                            kk == (long)n - 1 ? span : (double)kk * dt, q[j],
                            NULL, NULL);
        if (st != RPS3_OK) return st;
      }
      for (i = 0; i < 3; i++) {
        r->d->pose[i] = q[1][i];
        if (k == 0) {
          r->d->dpose[i] = (q[2][i] - q[1][i]) / dt;
          r->d->ddpose[i] = 0.0;
        } else if (k == n - 1) {
          r->d->dpose[i] = (q[1][i] - q[0][i]) / dt;
          r->d->ddpose[i] = 0.0;
        } else {
          r->d->dpose[i] = (q[2][i] - q[0][i]) / (2.0 * dt);
          r->d->ddpose[i] = (q[2][i] - 2.0 * q[1][i] + q[0][i]) / (dt * dt);
        }
      }
      st = rps3_inverse(&r->model, r->d);
    }
    if (st != RPS3_OK) {
      if (out && out->nfail++ == 0) out->status = st;
      return 0;
    }
    if (!out) continue;
    for (i = 0; i < 3; i++) {
      if (fabs(r->d->F[i]) > peak) peak = fabs(r->d->F[i]);
      P += r->d->F[i] * r->d->dl[i];
    }
    E = energy(&r->model, r->d);
    if (k > 0) {
      double W = 0.5 * (P + Pprev) * (t - tprev);
      if (fabs(W) > Wmax) Wmax = fabs(W);
      if (fabs(W - (E - Eprev)) > resmax) resmax = fabs(W - (E - Eprev));
    }
    Eprev = E;
    Pprev = P;
    tprev = t;
  }
  if (out) {
    out->peak_err = (ref->peak - peak) / ref->peak;
    out->energy_err = resmax / Wmax;
  }
  return 0;
}

/* samples of one pass of configuration c */
static size_t pass_points(const config *c, const reference *ref) {
  return c->study == S_DT ? (size_t)floor(1.0 / c->dt_frac + 0.5) + 1
                          : ref->n;
}

/* one pass of configuration c; with res != NULL, record its errors */
static void pass(runner *r, const reference *ref, result *res) {
  if (r->c->study == S_DT)
    pass_dt(r, ref, res);
  else
    pass_grid(r, ref, res);
}

/* the first, untimed pass: the errors of configuration c against ref */
static int measure_errors(runner *r, const config *c, const rps3_traj *tr,
                          const rps3_model *base, const reference *ref,
                          result *res) {
  memset(res, 0, sizeof(*res));
  res->peak_err = res->energy_err = DNAN;
  if (runner_init(r, c, tr, base) < 0) return -1;
  pass(r, ref, res);
  if (c->study == S_DT) res->force_err = res->theta_err = res->mean_iter = DNAN;
  return 0;
}

/*
 * The timed passes, round-robin over the configurations (repeat k of every
 * configuration before repeat k + 1 of any), so that a burst of load from
 * other processes spreads over all of them instead of shifting a few; the
 * median of each configuration's passes is its time per point.
 */
static int measure_times(runner *r, const config *cfg, int ncfg,
                         const reference *ref, int repeats, result *res) {
  double *ns = malloc((size_t)ncfg * (size_t)repeats * sizeof(double));
  int c, k;
  if (!ns) return -1;
  for (k = 0; k < repeats; k++)
    for (c = 0; c < ncfg; c++) {
      double t0 = now_ns();
      pass(&r[c], ref, NULL);
      ns[c * repeats + k] =
          (now_ns() - t0) / (double)pass_points(&cfg[c], ref);
    }
  for (c = 0; c < ncfg; c++) {
    double *v = &ns[c * repeats];
    res[c].ns_point = median(v, repeats); /* sorts v */
    res[c].ns_q1 = v[repeats / 4];
    res[c].ns_q3 = v[(3 * repeats) / 4];
    res[c].ns_second =
        res[c].ns_point * (double)pass_points(&cfg[c], ref) / ref->span;
  }
  free(ns);
  return 0;
}

/* ------------------------------------------------------------- HDF5 */

typedef struct {
  hid_t file, str;
} h5out;

/* a scalar attribute of any type; value points at the element */
static int attr(hid_t obj, const char *name, hid_t type, const void *value) {
  hid_t sp = H5Screate(H5S_SCALAR), a;
  int rc = -1;
  if (sp < 0) return -1;
  a = H5Acreate2(obj, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    rc = H5Awrite(a, type, value) < 0 ? -1 : 0;
    H5Aclose(a);
  }
  H5Sclose(sp);
  return rc;
}

static int attr_str(hid_t obj, hid_t str, const char *name,
                    const char *value) {
  return attr(obj, name, str, &value);
}

static int attr_f64(hid_t obj, const char *name, double v) {
  return attr(obj, name, H5T_NATIVE_DOUBLE, &v);
}

static int h5_open(h5out *o, const char *path, const char *cmdline,
                   const char *title) {
  char now[32], h5v[32];
  unsigned maj, min, rel;
  time_t t = time(NULL);
  struct tm tm;
  o->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (o->file < 0) return -1;
  o->str = H5Tcopy(H5T_C_S1);
  if (o->str < 0 || H5Tset_size(o->str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(o->str, H5T_CSET_UTF8) < 0)
    return -1;
  gmtime_r(&t, &tm);
  strftime(now, sizeof now, "%Y-%m-%dT%H:%M:%SZ", &tm);
  H5get_libversion(&maj, &min, &rel);
  snprintf(h5v, sizeof h5v, "%u.%u.%u", maj, min, rel);
  return (attr_str(o->file, o->str, "rps3_version", rps3_version()) < 0 ||
          attr_str(o->file, o->str, "created_utc", now) < 0 ||
          attr_str(o->file, o->str, "command_line", cmdline) < 0 ||
          attr_str(o->file, o->str, "gsl_version", gsl_version) < 0 ||
          attr_str(o->file, o->str, "hdf5_version", h5v) < 0 ||
          attr_str(o->file, o->str, "title", title) < 0)
             ? -1
             : 0;
}

static int h5_close(h5out *o) {
  int rc = 0;
  if (o->str >= 0 && H5Tclose(o->str) < 0) rc = -1;
  if (o->file >= 0 && H5Fclose(o->file) < 0) rc = -1;
  return rc;
}

/*
 * Write a dataset of `rank` dims with its units and description, and attach
 * the named dimension scales (NULL entries: this dataset is itself the
 * scale of that name).  type is H5T_NATIVE_DOUBLE, H5T_NATIVE_INT32 or the
 * string type.
 */
static int h5_write(h5out *o, const char *name, hid_t type, int rank,
                    const hsize_t *dims, const void *data, const char *units,
                    const char *doc, const char *const *scales) {
  hid_t sp = H5Screate_simple(rank, dims, NULL), ds = -1;
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  hsize_t chunk[8];
  int rc = -1, k;
  if (sp < 0 || dcpl < 0 || rank > 8) goto done;
  /* the maps: one chunk per leading index, deflated */
  if (rank >= 3) {
    chunk[0] = 1;
    for (k = 1; k < rank; k++) chunk[k] = dims[k];
    if (H5Pset_chunk(dcpl, rank, chunk) < 0 || H5Pset_deflate(dcpl, 4) < 0)
      goto done;
  }
  ds = H5Dcreate2(o->file, name, type, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (ds < 0) goto done;
  if (H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0 ||
      attr_str(ds, o->str, "units", units) < 0 ||
      attr_str(ds, o->str, "description", doc) < 0)
    goto done;
  for (k = 0; k < rank; k++) {
    hid_t sc;
    if (scales[k] == NULL) {
      if (H5DSset_scale(ds, name) < 0) goto done;
      continue;
    }
    sc = H5Dopen2(o->file, scales[k], H5P_DEFAULT);
    if (sc < 0) goto done;
    if (H5DSattach_scale(ds, sc, (unsigned)k) < 0) {
      H5Dclose(sc);
      goto done;
    }
    H5Dclose(sc);
  }
  rc = 0;
done:
  if (ds >= 0) H5Dclose(ds);
  if (dcpl >= 0) H5Pclose(dcpl);
  if (sp >= 0) H5Sclose(sp);
  return rc;
}

/* ------------------------------------------------------------- accuracy */

static int run_accuracy(const char *path, const char *cmdline, size_t nsamp,
                        int repeats) {
  static config cfg[MAXCFG];
  static result res[NTRAJ][MAXCFG];
  static runner run[MAXCFG];
  reference ref[NTRAJ];
  rps3_model base;
  char err[256];
  int ncfg = configs_build(cfg), t, c, rc = 0;
  h5out o = {-1, -1};
  double t_start = now_ns();

  /* the model: Table II, plus a payload and pin friction so that the
     effects ladder has something to add; the other studies use the default
     effects (the paper's four) */
  rps3_model_default(&base);
  base.payload.mass = 0.05;
  base.payload.com[0] = 0.011;
  base.payload.com[2] = 0.023;
  base.payload.inertia[0] = base.payload.inertia[1] = 1.3e-5;
  base.payload.inertia[2] = 2.1e-5;
  base.friction.viscous = 0.011;
  base.friction.coulomb = 0.0023;
  if (rps3_model_init(&base, err, sizeof err) != RPS3_OK) {
    fprintf(stderr, "rps3-study: %s\n", err);
    return EXIT_IO;
  }
  for (t = 0; t < NTRAJ; t++) {
    rps3_traj tr;
    traj_make(t, &tr);
    if (rps3_traj_check(&base, &tr, err, sizeof err) != RPS3_OK) {
      fprintf(stderr, "rps3-study: %s: %s\n", traj_name[t], err);
      return EXIT_IO;
    }
    if (reference_build(&base, &tr, nsamp, &ref[t]) < 0) return EXIT_IO;
    fprintf(stderr,
            "rps3-study: %s: reference |F|max %.4g N, peak %.6g N, floors: "
            "reference (long double) %.2g, theta closed form - long double "
            "%.2g rad\n",
            traj_name[t], ref[t].fscale, ref[t].peak, ref[t].floor_ref,
            ref[t].floor_theta);
    for (c = 0; c < ncfg; c++) {
      /* the effects ladder's error is against the model with every effect */
      reference *rf = &ref[t], rall;
      if (cfg[c].study == S_EFFECTS) {
        rall = ref[t];
        rall.F = malloc(3 * nsamp * sizeof(double));
        if (!rall.F || reference_forces(&base, &tr, RPS3_EFF_ALL, &rall) < 0)
          return EXIT_IO;
        rf = &rall;
      }
      if (measure_errors(&run[c], &cfg[c], &tr, &base, rf, &res[t][c]) < 0)
        return EXIT_IO;
      if (rf != &ref[t]) free(rall.F);
    }
    if (measure_times(run, cfg, ncfg, &ref[t], repeats, res[t]) < 0)
      return EXIT_IO;
    for (c = 0; c < ncfg; c++) {
      rps3_data_free(run[c].d);
      free(run[c].rows);
    }
  }
  fprintf(stderr, "rps3-study: accuracy: %d configurations x %d trajectories "
          "in %.1f s\n", ncfg, NTRAJ, 1e-9 * (now_ns() - t_start));

  /* the file */
  if (h5_open(&o, path, cmdline,
              "rps3-study accuracy: error against a precise reference and "
              "median time per point, per configuration and trajectory") < 0)
    rc = -1;
  if (rc == 0) {
    hsize_t dims[2] = {NTRAJ, (hsize_t)ncfg};
    static const char *const s_traj[1] = {NULL};
    static const char *const s_cfg[1] = {NULL};
    static const char *const s_cfgd[1] = {"config"};
    static const char *const s_tc[2] = {"trajectory", "config"};
    static const char *const s_t[1] = {"trajectory"};
    const char *sv[MAXCFG];
    int32_t iv[MAXCFG], idx[MAXCFG];
    /* [trajectory, config] tables, packed with row length ncfg */
    double dv[MAXCFG], tv[NTRAJ * MAXCFG];
    int32_t tiv[NTRAJ * MAXCFG];
    double fl[NTRAJ];
    hsize_t dt1 = NTRAJ;
    for (c = 0; c < ncfg; c++) idx[c] = c;
    rc |= h5_write(&o, "trajectory", o.str, 1, &dt1, traj_name, "1",
                   traj_doc, s_traj);
    rc |= h5_write(&o, "config", H5T_NATIVE_INT32, 1, &dims[1], idx, "1",
                   "configuration index; see study, label and the knobs",
                   s_cfg);
#define CFG_STR(name, expr, doc)                                              \
  for (c = 0; c < ncfg; c++) sv[c] = (expr);                                  \
  rc |= h5_write(&o, name, o.str, 1, &dims[1], sv, "1", doc, s_cfgd);
#define CFG_F64(name, expr, units, doc)                                       \
  for (c = 0; c < ncfg; c++) dv[c] = (expr);                                  \
  rc |= h5_write(&o, name, H5T_NATIVE_DOUBLE, 1, &dims[1], dv, units, doc,    \
                 s_cfgd);
#define CFG_I32(name, expr, doc)                                              \
  for (c = 0; c < ncfg; c++) iv[c] = (int32_t)(expr);                         \
  rc |= h5_write(&o, name, H5T_NATIVE_INT32, 1, &dims[1], iv, "1", doc,      \
                 s_cfgd);
    CFG_STR("study", study_name[cfg[c].study],
            "which knob the configuration turns: theta, derivative, method, "
            "effects or dt")
    CFG_STR("label", cfg[c].label, "short name of the configuration")
    CFG_STR("theta_route",
            cfg[c].theta == RPS3_THETA_MULTIROOT ? "multiroot" : "closed_form",
            "closed form (39) or GSL multiroot solve of (8)-(10)")
    CFG_STR("solver", cfg[c].solver < 0 ? "" : rps3_solver_name(cfg[c].solver),
            "GSL multiroot solver (empty for the closed form)")
    CFG_F64("tolerance", cfg[c].theta == RPS3_THETA_MULTIROOT ? cfg[c].tol : DNAN,
            "1", "theta solve tolerance on max |f_k| (lengths in units of R)")
    CFG_I32("warm_start", cfg[c].warm,
            "1: theta solve starts from the previous sample; 0: cold")
    CFG_STR("derivative", deriv_name[cfg[c].deriv],
            "rates: exact (the trajectory's), central differences of the "
            "pose (fd_pose) or of the link lengths (fd_length) with step h, "
            "of the samples at interval dt (fd_samples), or the not-a-knot "
            "spline of the pose sampled every h (spline_pose)")
    CFG_F64("fd_step", cfg[c].h > 0 ? cfg[c].h : DNAN, "s",
            "finite-difference step, or the spline's row spacing, h (NaN "
            "for exact rates)")
    CFG_STR("method",
            cfg[c].method == RPS3_LAGRANGE ? "lagrange" : "newton_euler",
            "formulation of the dynamics")
    CFG_I32("effects", cfg[c].effects, "selected effects, RPS3_EFF_* bits")
    CFG_F64("dt_fraction", cfg[c].dt_frac > 0 ? cfg[c].dt_frac : DNAN, "1",
            "dt study: sample interval over the trajectory's duration")
#define RES_F64(name, field, units, doc)                                      \
  for (t = 0; t < NTRAJ; t++)                                                 \
    for (c = 0; c < ncfg; c++) tv[t * ncfg + c] = res[t][c].field;                    \
  rc |= h5_write(&o, name, H5T_NATIVE_DOUBLE, 2, dims, tv, units, doc, s_tc);
    RES_F64("ns_per_point", ns_point, "ns",
            "median over the timed passes of the time per sample (trajectory "
            "evaluation included), CLOCK_MONOTONIC, one process")
    RES_F64("ns_per_point_q1", ns_q1, "ns", "first quartile of the passes")
    RES_F64("ns_per_point_q3", ns_q3, "ns", "third quartile of the passes")
    RES_F64("ns_per_second", ns_second, "ns",
            "time to compute one second of the trajectory: ns_per_point x "
            "samples / duration (the cost axis of the dt study)")
    RES_F64("force_error", force_err, "1",
            "max over samples and links of |F - F_ref| / max |F_ref| (for "
            "the effects ladder: against the model with every effect)")
    RES_F64("theta_error", theta_err, "rad",
            "max over samples and links of |theta - theta_ref|, theta_ref "
            "from inverse kinematics in long double")
    RES_F64("peak_force_error", peak_err, "1",
            "dt study: (peak_ref - max sampled |F|) / peak_ref, peak_ref from "
            "200001 samples")
    RES_F64("energy_residual", energy_err, "1",
            "dt study: max over intervals |W_k - (E_k+1 - E_k)| / max |W_k|, "
            "W_k the trapezoid of the power sum F_i dl_i, E = T + P")
    RES_F64("mean_iterations", mean_iter, "1",
            "theta solve iterations per sample")
    for (t = 0; t < NTRAJ; t++)
      for (c = 0; c < ncfg; c++) tiv[t * ncfg + c] = res[t][c].nfail;
    rc |= h5_write(&o, "failed_samples", H5T_NATIVE_INT32, 2, dims, tiv, "1",
                   "samples whose pipeline returned an error (errors are "
                   "measured over the others)", s_tc);
    for (t = 0; t < NTRAJ; t++)
      for (c = 0; c < ncfg; c++) tiv[t * ncfg + c] = res[t][c].status;
    rc |= h5_write(&o, "status", H5T_NATIVE_INT32, 2, dims, tiv, "1",
                   "rps3_status of the first failing sample, 0 if none",
                   s_tc);
    for (t = 0; t < NTRAJ; t++) fl[t] = ref[t].floor_ref;
    rc |= h5_write(&o, "reference_floor_force", H5T_NATIVE_DOUBLE, 1, &dt1,
                   fl, "1",
                   "the reference's own rounding error / max |F_ref|: "
                   "its double twin's distance from it x LDBL_EPSILON / "
                   "DBL_EPSILON", s_t);
    for (t = 0; t < NTRAJ; t++) fl[t] = ref[t].floor_theta;
    rc |= h5_write(&o, "reference_floor_theta", H5T_NATIVE_DOUBLE, 1, &dt1,
                   fl, "rad",
                   "max |theta_closed_form - theta_long_double| on the grid",
                   s_t);
    for (t = 0; t < NTRAJ; t++) fl[t] = ref[t].fscale;
    rc |= h5_write(&o, "reference_force_max", H5T_NATIVE_DOUBLE, 1, &dt1, fl,
                   "N", "max |F_ref| over the grid: the force_error scale",
                   s_t);
    for (t = 0; t < NTRAJ; t++) fl[t] = ref[t].peak;
    rc |= h5_write(&o, "reference_peak_force", H5T_NATIVE_DOUBLE, 1, &dt1, fl,
                   "N", "peak |F| over 200001 samples of the span", s_t);
    rc |= attr_f64(o.file, "samples", (double)nsamp);
    rc |= attr_f64(o.file, "repeats", (double)repeats);
  }
  if (h5_close(&o) < 0) rc = -1;
  for (t = 0; t < NTRAJ; t++) {
    free(ref[t].F);
    free(ref[t].theta);
  }
  return rc ? EXIT_IO : EXIT_OK;
}

/* ------------------------------------------------------------ workspace */

/* det of d f / d theta from the vector form (b_i - b_j) . l dphi */
static double det_jt(const rps3_data *d) {
  double J[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  int k, q;
  for (k = 0; k < 3; k++) {
    int i = k, j = (k + 1) % 3;
    double si = 0.0, sj = 0.0;
    for (q = 0; q < 3; q++) {
      double D = d->b[i][q] - d->b[j][q];
      si += D * d->dphi[i][q];
      sj += D * d->dphi[j][q];
    }
    J[k][i] = 2.0 * d->l[i] * si;
    J[k][j] = -2.0 * d->l[j] * sj;
  }
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

static void linspace(double *v, size_t n, double a, double b) {
  size_t k;
  for (k = 0; k < n; k++)
    v[k] = n == 1 ? a : a + (b - a) * (double)k / (double)(n - 1);
}

static int run_workspace(const char *path, const char *cmdline, int quick) {
  static const double rhos[3] = {0.3, 0.5, 0.8};
  size_t na = quick ? 13 : 25, nb = quick ? 25 : 61, nz = quick ? 20 : 60;
  size_t nr = 3, npt, ir, ia, ib, iz, p;
  double *alpha, *beta, *zc, *cond, *trans, *force, *fmax;
  int32_t *status, *mode, link[3] = {1, 2, 3};
  h5out o = {-1, -1};
  int rc = 0;
  double t_start = now_ns();
  npt = nr * na * nb * nz;
  alpha = malloc(na * sizeof(double));
  beta = malloc(nb * sizeof(double));
  zc = malloc(nz * sizeof(double));
  cond = malloc(npt * sizeof(double));
  trans = malloc(npt * sizeof(double));
  fmax = malloc(npt * sizeof(double));
  force = malloc(3 * npt * sizeof(double));
  status = malloc(npt * sizeof(int32_t));
  mode = malloc(npt * sizeof(int32_t));
  if (!alpha || !beta || !zc || !cond || !trans || !fmax || !force || !status ||
      !mode) {
    fprintf(stderr, "rps3-study: out of memory\n");
    return EXIT_IO;
  }
  /* alpha over a full turn (the mechanism repeats every 2 pi / 3), beta to
     1.2 rad, z_c from 0.1 R to 3 R */
  linspace(alpha, na, -PI, PI);
  linspace(beta, nb, 0.0, 1.2);
  linspace(zc, nz, 0.02286, 0.6858);
  for (ir = 0; ir < nr; ir++) {
    rps3_model m;
    rps3_data *d = NULL;
    char err[256];
    rps3_model_default(&m);
    m.rho = rhos[ir];
    m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
    m.opt.certify = 0;
    if (rps3_model_init(&m, err, sizeof err) != RPS3_OK ||
        rps3_data_alloc(&m, &d) != RPS3_OK) {
      fprintf(stderr, "rps3-study: workspace model: %s\n", err);
      return EXIT_IO;
    }
    for (ia = 0; ia < na; ia++)
      for (ib = 0; ib < nb; ib++)
        for (iz = 0; iz < nz; iz++) {
          int st, i;
          double home;
          p = ((ir * na + ia) * nb + ib) * nz + iz;
          /* the assembly mode of the level pose at this height */
          d->pose[0] = 0.0;
          d->pose[1] = 0.0;
          d->pose[2] = zc[iz];
          home = rps3_ik(&m, d) == RPS3_OK ? det_jt(d) : DNAN;
          d->pose[0] = alpha[ia];
          d->pose[1] = beta[ib];
          d->pose[2] = zc[iz];
          st = rps3_inverse(&m, d);
          status[p] = st;
          mode[p] = 0;
          if (st == RPS3_OK || st == RPS3_ESING) {
            double dj = det_jt(d);
            mode[p] = (dj > 0) == (home > 0) ? 1 : -1;
          }
          cond[p] = (st == RPS3_OK || st == RPS3_ESING) ? d->cond : DNAN;
          trans[p] = (st == RPS3_OK || st == RPS3_ESING) ? d->transmission
                                                         : DNAN;
          fmax[p] = st == RPS3_OK ? 0.0 : DNAN;
          for (i = 0; i < 3; i++) {
            force[3 * p + (size_t)i] = st == RPS3_OK ? d->F[i] : DNAN;
            if (st == RPS3_OK && fabs(d->F[i]) > fmax[p])
              fmax[p] = fabs(d->F[i]);
          }
        }
    rps3_data_free(d);
  }
  fprintf(stderr, "rps3-study: workspace: %zu points in %.1f s\n", npt,
          1e-9 * (now_ns() - t_start));

  if (h5_open(&o, path, cmdline,
              "rps3-study workspace: reachability, condition number and the "
              "static force holding the platform over (rho, alpha, beta, "
              "z_c)") < 0)
    rc = -1;
  if (rc == 0) {
    static const char *const self[1] = {NULL};
    static const char *const grid[4] = {"rho", "alpha", "beta", "z_c"};
    static const char *const gridl[5] = {"rho", "alpha", "beta", "z_c",
                                         "link"};
    hsize_t dims[5] = {nr, na, nb, nz, 3}, d3 = 3;
    rc |= h5_write(&o, "rho", H5T_NATIVE_DOUBLE, 1, &dims[0], rhos, "1",
                   "rho = r / R (R = 0.2286 m, Table II)", self);
    rc |= h5_write(&o, "alpha", H5T_NATIVE_DOUBLE, 1, &dims[1], alpha, "rad",
                   "precession angle alpha", self);
    rc |= h5_write(&o, "beta", H5T_NATIVE_DOUBLE, 1, &dims[2], beta, "rad",
                   "nutation angle beta (tilt)", self);
    rc |= h5_write(&o, "z_c", H5T_NATIVE_DOUBLE, 1, &dims[3], zc, "m",
                   "height of the platform centre", self);
    rc |= h5_write(&o, "link", H5T_NATIVE_INT32, 1, &d3, link, "1",
                   "link number", self);
    rc |= h5_write(&o, "status", H5T_NATIVE_INT32, 4, dims, status, "1",
                   "rps3_inverse status: 0 ok, 1 unreachable (EREACH), 4 "
                   "singular (ESING, condition above cond_max = 1e13 or "
                   "transmission above trans_max = 1e8)", grid);
    rc |= h5_write(&o, "condition", H5T_NATIVE_DOUBLE, 4, dims, cond, "1",
                   "1-norm condition number of the lambda system df/dtheta "
                   "(NaN where unreachable); warn above 1e6", grid);
    rc |= h5_write(&o, "transmission", H5T_NATIVE_DOUBLE, 4, dims, trans, "1",
                   "force transmission: largest actuator force per unit "
                   "platform load (force, moment / R); warn above 100, "
                   "refused above 1e8 (NaN where not computed)", grid);
    rc |= h5_write(&o, "mode", H5T_NATIVE_INT32, 4, dims, mode, "1",
                   "assembly mode: 1 same sign of det(df/dtheta) as the level "
                   "pose at this height (reachable from it without crossing "
                   "a singularity), -1 the other side, 0 unreachable", grid);
    rc |= h5_write(&o, "force", H5T_NATIVE_DOUBLE, 5, dims, force, "N",
                   "static actuating force holding the platform: platform "
                   "and link gravity (M = 0.18 kg, m = 0.09 kg, d = 0.1524 "
                   "m), positive extends the link", gridl);
    rc |= h5_write(&o, "max_force", H5T_NATIVE_DOUBLE, 4, dims, fmax, "N",
                   "max_i |force_i|", grid);
  }
  if (h5_close(&o) < 0) rc = -1;
  free(alpha);
  free(beta);
  free(zc);
  free(cond);
  free(trans);
  free(fmax);
  free(force);
  free(status);
  free(mode);
  return rc ? EXIT_IO : EXIT_OK;
}

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
          "  -o OUT.h5      output file (written as OUT.h5.tmp.PID, renamed "
          "when complete)\n"
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
  char cmdline[2048], tmp[4096], err[4096 + 512];
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
  stale_report("rps3-study", out);
  if (snprintf(tmp, sizeof tmp, "%s.tmp.%ld", out, (long)getpid()) >=
          (int)sizeof tmp ||
      tmp_set(tmp)) {
    fprintf(stderr, "rps3-study: %s: path too long\n", out);
    return EXIT_USAGE;
  }
  if (!strcmp(argv[1], "accuracy"))
    rc = run_accuracy(tmp, cmdline, samples, repeats);
  else
    rc = run_workspace(tmp, cmdline, quick);
  if (rc != EXIT_OK) {
    h5_cause(err, sizeof err);
    if (err[0]) fprintf(stderr, "rps3-study: %s: HDF5: %s\n", out, err);
  } else if (tmp_commit(out, err, sizeof err)) {
    fprintf(stderr, "rps3-study: %s\n", err);
    rc = EXIT_IO;
  }
  if (rc != EXIT_OK) {
    tmp_discard();
    fprintf(stderr, "rps3-study: %s not written\n", out);
  }
  return rc;
}

int main(int argc, char **argv) {
  /* fds 0-2 open, HDF5 without atexit, then the signal policy of
     signals.h: the temporary file is removed by a signal that ends us */
  proc_init();
  sig_init();
  gsl_set_error_handler_off();
  h5_errors_capture();
  return proc_exit(study_main(argc, argv));
}
