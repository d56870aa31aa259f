/*
 * study_sim.c - rps3-simstudy's studies: closed-loop tracking of the
 * shipped controllers, and what simulation accuracy costs in time.
 *
 * tracking: the paper's helix (Table II, 10 s) and a fast sine (2 s), the
 * plant of Table II (m/M = 0.5, the paper's effects), each of PD, PD +
 * gravity and computed torque at 1 kHz with RK4 at the control rate, the
 * controller's model either exact or without link mass (the paper's case
 * 1).  Written per sample (1 ms): the largest link length error
 * max_i |l_i - l_d,i| and the applied forces; per run the status and the
 * time of a failure.
 *
 * accuracy: computed torque on the fast sine (2 s; --quick 0.5 s) with each
 * integrator at a ladder of steps or tolerances, crossed with two theta
 * solve tolerances; the error is the largest |l - l_ref| at the 1 ms
 * samples against rk8pd at 1e-13 with theta tolerance 1e-13, the cost the
 * CPU time per simulated second (median of 3 runs; --quick: 1).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <hdf5.h>
#include <hdf5_hl.h>

#include "core/tmpout.h"
#include "rps3.h"
#include "study.h"

#define RATE_HZ 1000.0

/* a run that must succeed failed: no file (the temporary one removed) */
static void fail_run(void) {
  tmpout_discard();
  exit(EXIT_RUN);
}
#define NCTRL 3
#define NMODEL 2
#define MAXS 10001 /* samples of the longest path (10 s at 1 kHz, + 1) */

static const rps3_ctrl_kind CTRL[NCTRL] = {RPS3_CTRL_PD, RPS3_CTRL_PD_GRAVITY,
                                           RPS3_CTRL_COMPUTED_TORQUE};
/* gains: PD [N/m, N s/m]; computed torque [1/s^2, 1/s] */
static const double KP[NCTRL] = {2000.0, 2000.0, 400.0};
static const double KD[NCTRL] = {40.0, 40.0, 40.0};

static double cpu_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* a fast path within Table II's workspace: a turn of alpha per second,
   tilt and height at 2 and 3 Hz */
static const rps3_sine FAST_SINE = {{0.31, 0.21, 0.30},
                                    {1.03, 0.083, 0.029},
                                    {1.07, 2.03, 3.01},
                                    {0.0, 0.4, 0.0},
                                    2.0};

/* one closed-loop run from the start of tr to dur; per 1 ms sample the
   lengths into l[k] (NULL: not kept), the error against l_d into err[k]
   and the forces into F[k] (either may be NULL); returns the status */
typedef struct {
  double (*l)[3];
  double *err;
  double (*F)[3];
  double failed_at, cpu;
  long nevals;
} run_out;

static int run(const rps3_model *plant, const rps3_model *cm,
               const rps3_traj *tr, rps3_ctrl_kind kind, double kp, double kd,
               const rps3_sim_options *o, double dur, run_out *out) {
  rps3_sim *s = NULL;
  rps3_ctrl *c = NULL;
  rps3_data *w = NULL;
  rps3_controller ctl;
  double pose[3], dpose[3], c0;
  long k, n = (long)(dur * RATE_HZ + 0.5);
  int st = RPS3_OK, i;
  rps3_check chk;
  if (rps3_sim_alloc(plant, o, &s, &chk) != RPS3_OK ||
      rps3_ctrl_alloc(kind, kp, kd, cm, tr, &c, &chk) != RPS3_OK ||
      rps3_data_alloc(plant, &w) != RPS3_OK) {
    fprintf(stderr, "rps3-simstudy: set-up: %s\n", chk.msg);
    fail_run();
  }
  ctl = rps3_ctrl_bind(c, RATE_HZ);
  rps3_traj_eval(plant, tr, 0.0, pose, dpose, NULL);
  out->failed_at = (double)NAN;
  c0 = cpu_s();
  st = rps3_sim_start(s, 0.0, pose, dpose);
  for (k = 0; k <= n; k++) {
    double t = (double)k / RATE_HZ, e = 0.0;
    if (st == RPS3_OK && k > 0) st = rps3_sim_advance(s, &ctl, t);
    /* after a failure every sample is NaN */
    if (st != RPS3_OK && isnan(out->failed_at))
      out->failed_at = rps3_sim_now(s)->failed_at;
    if (out->err && st == RPS3_OK) {
      rps3_traj_eval(plant, tr, t, w->pose, NULL, NULL);
      rps3_ik(plant, w);
      for (i = 0; i < 3; i++)
        e = fmax(e, fabs(rps3_sim_now(s)->y[i] - w->l[i]));
    }
    if (out->err) out->err[k] = st == RPS3_OK ? e : (double)NAN;
    for (i = 0; i < 3; i++) {
      if (out->l) out->l[k][i] = st ? (double)NAN : rps3_sim_now(s)->y[i];
      if (out->F) out->F[k][i] = st ? (double)NAN : rps3_sim_now(s)->F[i];
    }
  }
  out->cpu = cpu_s() - c0;
  out->nevals = rps3_sim_now(s)->nevals;
  rps3_data_free(w);
  rps3_ctrl_free(c);
  rps3_sim_free(s);
  return st;
}

static int write_ds(hid_t g, const char *name, int rank, const hsize_t *dims,
                    hid_t type, const void *data, const char *units,
                    const char *doc) {
  if (H5LTmake_dataset(g, name, rank, dims, type, data) < 0 ||
      H5LTset_attribute_string(g, name, "units", units) < 0 ||
      H5LTset_attribute_string(g, name, "description", doc) < 0)
    return -1;
  return 0;
}

static double nanmax(const double *x, long n) {
  double m = 0.0;
  long k;
  for (k = 0; k < n; k++)
    if (x[k] > m) m = x[k];
  return m;
}

/* one path: every controller with both models, into group gp */
static int tracking_path(hid_t gp, const rps3_traj *tr) {
  static double err[NCTRL * NMODEL * MAXS], F[NCTRL * NMODEL * MAXS * 3],
      t[MAXS];
  static const char *const names = "pd, pd_gravity, computed_torque";
  int status[NCTRL][NMODEL], a, b, rc = 0;
  double failed[NCTRL][NMODEL];
  long n = (long)(rps3_traj_duration(tr) * RATE_HZ + 0.5) + 1, k;
  /* [controller, model, time, link]; the time axis alone at d + 2 */
  hsize_t d[4] = {NCTRL, NMODEL, (hsize_t)n, 3};
  rps3_model plant, light;
  rps3_sim_options o;
  rps3_model_default(&plant);
  rps3_model_init(&plant, NULL);
  light = plant;
  light.m = 0.0; /* the paper's case 1 */
  rps3_model_init(&light, NULL);
  rps3_sim_options_default(&o);
  for (k = 0; k < n; k++) t[k] = (double)k / RATE_HZ;
  for (a = 0; a < NCTRL; a++)
    for (b = 0; b < NMODEL; b++) {
      long off = (long)(a * NMODEL + b) * n;
      run_out ro = {NULL, err + off, (double(*)[3])(F + 3 * off), 0, 0, 0};
      status[a][b] = run(&plant, b ? &light : &plant, tr, CTRL[a], KP[a], KD[a],
                         &o, rps3_traj_duration(tr), &ro);
      failed[a][b] = ro.failed_at;
      printf("  %-16s %-13s %-10s max |l - l_d| %.3g m\n",
             rps3_ctrl_name(CTRL[a]), b ? "no link mass" : "exact model",
             rps3_strerror(status[a][b]), nanmax(ro.err, n));
    }
  rc |= write_ds(gp, "time", 1, d + 2, H5T_NATIVE_DOUBLE, t, "s",
                 "sample times, 1 kHz");
  rc |= write_ds(gp, "error", 3, d, H5T_NATIVE_DOUBLE, err, "m",
                 "max_i |l_i - l_d,i| [controller, model, time]; NaN after "
                 "a failure");
  rc |= write_ds(gp, "force", 4, d, H5T_NATIVE_DOUBLE, F, "N",
                 "applied forces [controller, model, time, link]");
  rc |= write_ds(gp, "status", 2, d, H5T_NATIVE_INT, status, "1",
                 "rps3_status of each run [controller, model]");
  rc |= write_ds(gp, "failed_at", 2, d, H5T_NATIVE_DOUBLE, failed, "s",
                 "time of the failure, NaN if none");
  rc |= H5LTset_attribute_string(gp, ".", "controllers", names) < 0;
  rc |= H5LTset_attribute_string(gp, ".", "models", "exact, no_link_mass") < 0;
  rc |= H5LTset_attribute_double(gp, ".", "kp", KP, NCTRL) < 0;
  rc |= H5LTset_attribute_double(gp, ".", "kd", KD, NCTRL) < 0;
  return rc ? -1 : 0;
}

static int tracking(hid_t f, int quick) {
  rps3_traj tr;
  hid_t g, gp;
  int p, rc = 0;
  g = H5Gcreate2(f, "tracking", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (g < 0) return -1;
  for (p = 0; p < 2; p++) {
    if (p == 0) {
      rps3_traj_default(&tr);
      if (quick) {
        tr.helix.period = 2.0;
        tr.helix.blend = 0.5;
      }
    } else {
      study_traj_sine(&tr, &FAST_SINE);
    }
    printf("tracking, %s:\n", p ? "fast sine" : "helix");
    gp = H5Gcreate2(g, p ? "fast_sine" : "helix", H5P_DEFAULT, H5P_DEFAULT,
                    H5P_DEFAULT);
    if (gp < 0 || tracking_path(gp, &tr) != 0) rc = -1;
    if (gp >= 0) H5Gclose(gp);
  }
  H5Gclose(g);
  return rc;
}

#define NCFG 13
static const struct {
  rps3_integrator integ;
  double h_or_tol; /* step [s] for rk4, tolerance for the adaptive ones */
} CFG[NCFG] = {
    {RPS3_INT_RK4, 1e-3},    {RPS3_INT_RK4, 5e-4},    {RPS3_INT_RK4, 2.5e-4},
    {RPS3_INT_RK4, 1e-4},    {RPS3_INT_RKF45, 1e-6},  {RPS3_INT_RKF45, 1e-8},
    {RPS3_INT_RKF45, 1e-10}, {RPS3_INT_RK8PD, 1e-6},  {RPS3_INT_RK8PD, 1e-8},
    {RPS3_INT_RK8PD, 1e-10}, {RPS3_INT_RK8PD, 1e-12}, {RPS3_INT_MSBDF, 1e-6},
    {RPS3_INT_MSBDF, 1e-8}};
static const double THETA_TOL[2] = {1e-12, 1e-8};

/* computed torque on tr by integrator integ at step (rk4) or tolerance
   h_or_tol, theta solved to tol; the status */
static int accuracy_run(rps3_model *plant, const rps3_traj *tr, double dur,
                        rps3_integrator integ, double h_or_tol, double tol,
                        run_out *ro) {
  rps3_sim_options o;
  plant->opt.tol = tol;
  rps3_model_init(plant, NULL);
  rps3_sim_options_default(&o);
  o.integrator = integ;
  if (integ == RPS3_INT_RK4)
    o.h = h_or_tol;
  else
    o.epsabs = o.epsrel = h_or_tol;
  return run(plant, plant, tr, RPS3_CTRL_COMPUTED_TORQUE, KP[2], KD[2], &o, dur,
             ro);
}

/* the accuracy study's results, [configuration, theta tolerance] */
typedef struct {
  int integ[NCFG];
  double htol[NCFG];
  double err[NCFG][2], cpu[NCFG][2];
  int st[NCFG][2];
  long evals[NCFG][2];
} acc_table;

/* configuration c at theta tolerance j: nrep timed runs, graded against
   lref */
static void accuracy_point(rps3_model *plant, const rps3_traj *tr, double dur,
                           int nrep, double (*lref)[3], int c, int j,
                           acc_table *a) {
  static double l[MAXS][3];
  double times[3];
  long k, n = (long)(dur * RATE_HZ + 0.5) + 1;
  int rep, i;
  run_out ro = {l, NULL, NULL, 0, 0, 0};
  for (rep = 0; rep < nrep; rep++) {
    a->st[c][j] = accuracy_run(plant, tr, dur, CFG[c].integ, CFG[c].h_or_tol,
                               THETA_TOL[j], &ro);
    times[rep] = ro.cpu / dur;
  }
  a->cpu[c][j] = study_median(times, nrep); /* nrep is odd */
  a->evals[c][j] = ro.nevals;
  a->err[c][j] = 0.0;
  for (k = 0; k < n; k++)
    for (i = 0; i < 3; i++)
      a->err[c][j] = fmax(a->err[c][j], fabs(l[k][i] - lref[k][i]));
  if (a->st[c][j] != RPS3_OK) a->err[c][j] = (double)NAN;
  printf(
      "  %-6s %-8.3g theta tol %-6.0e error %-9.3g m  CPU %.3g s per "
      "simulated s  (%ld evaluations)\n",
      rps3_integrator_name(a->integ[c]), a->htol[c], THETA_TOL[j], a->err[c][j],
      a->cpu[c][j], a->evals[c][j]);
}

/* the group /accuracy */
static int accuracy_write(hid_t f, const acc_table *a, double dur) {
  hsize_t dc[1] = {NCFG}, d2[2] = {NCFG, 2}, dt[1] = {2};
  hid_t g = H5Gcreate2(f, "accuracy", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int rc = 0;
  if (g < 0) return -1;
  rc |= write_ds(g, "integrator", 1, dc, H5T_NATIVE_INT, a->integ, "1",
                 "rps3_integrator code (0 rk4, 1 rkf45, 2 rk8pd, 3 msbdf)");
  rc |= write_ds(g, "h_or_tol", 1, dc, H5T_NATIVE_DOUBLE, a->htol, "1",
                 "fixed step h [s] for rk4, epsabs = epsrel for the others");
  rc |= write_ds(g, "theta_tol", 1, dt, H5T_NATIVE_DOUBLE, THETA_TOL, "1",
                 "theta solve tolerance opt.tol");
  rc |= write_ds(g, "error", 2, d2, H5T_NATIVE_DOUBLE, a->err, "m",
                 "max over 1 ms samples and links of |l - l_ref| "
                 "[config, theta_tol]; NaN if the run failed");
  rc |= write_ds(g, "cpu_per_sim_s", 2, d2, H5T_NATIVE_DOUBLE, a->cpu, "s/s",
                 "CPU time per simulated second, median of the repeats");
  rc |= write_ds(g, "nevals", 2, d2, H5T_NATIVE_LONG, a->evals, "1",
                 "forward dynamics evaluations");
  rc |= write_ds(g, "status", 2, d2, H5T_NATIVE_INT, a->st, "1", "rps3_status");
  rc |= H5LTset_attribute_double(g, ".", "duration", &dur, 1) < 0;
  H5Gclose(g);
  return rc ? -1 : 0;
}

static int accuracy(hid_t f, int quick) {
  static double lref[MAXS][3];
  static acc_table a;
  double dur = quick ? 0.5 : 2.0;
  int c, j, nrep = quick ? 1 : 3;
  run_out ref = {lref, NULL, NULL, 0, 0, 0};
  rps3_model plant;
  rps3_traj tr;
  rps3_model_default(&plant);
  /* on the slow helix one RK4 step per period is exact to rounding:
     nothing to measure */
  study_traj_sine(&tr, &FAST_SINE);
  /* the reference: rk8pd at 1e-13, theta to 1e-13 */
  if (accuracy_run(&plant, &tr, dur, RPS3_INT_RK8PD, 1e-13, 1e-13, &ref) !=
      RPS3_OK) {
    fprintf(stderr, "rps3-simstudy: the reference run failed\n");
    fail_run();
  }
  printf(
      "accuracy: computed torque on the fast sine, %.1f s, against rk8pd "
      "1e-13\n",
      dur);
  for (c = 0; c < NCFG; c++) {
    a.integ[c] = CFG[c].integ;
    a.htol[c] = CFG[c].h_or_tol;
    for (j = 0; j < 2; j++)
      accuracy_point(&plant, &tr, dur, nrep, lref, c, j, &a);
  }
  return accuracy_write(f, &a, dur);
}

int study_sim(const char *path, const char *cmdline, int quick) {
  hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  int rc = f < 0 ? -1 : tracking(f, quick);
  if (rc == 0) rc = accuracy(f, quick);
  if (rc == 0)
    rc =
        (H5LTset_attribute_string(f, "/", "rps3_version", rps3_version()) < 0 ||
         H5LTset_attribute_string(f, "/", "command_line", cmdline) < 0)
            ? -1
            : 0;
  if (f >= 0 && H5Fclose(f) < 0) rc = -1;
  return rc ? EXIT_IO : EXIT_OK;
}
