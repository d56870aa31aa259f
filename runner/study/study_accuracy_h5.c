/*
 * study_accuracy_h5.c - the file of rps3-study accuracy: the
 * configurations' knobs, the [trajectory, config] errors and times, and
 * the references' own numbers (main_study.c says what it holds).
 */
#include <stdint.h>
#include <stdlib.h>

#include "output/out_h5.h"
#include "study.h"
#include "study_accuracy_h5.h"

/* what the trajectory variable's description says of the two */
static const char *const study_traj_doc =
    "helix: Table II (r* = 0.266 mm, h = 30.48 mm, T* = 10 s, t_a = 1 s); "
    "sine_edge: alpha = pi sin(2 pi t), beta = 0.6 + 0.2 sin(2 pi 2.3 t), "
    "z_c = 0.28 + 0.03 sin(2 pi 1.7 t) m over 2 s: up to 20 rad/s, beta up to "
    "0.8 rad, condition number up to 4e2 near the singular surface";

/* the trajectories' and derivative kinds' names (study_accuracy_h5.h) */
const char *const study_traj_name[NTRAJ] = {"helix", "sine_edge"};
const char *const study_deriv_name[5] = {"exact", "fd_pose", "fd_length",
                                         "fd_samples", "spline_pose"};

static const char *const study_kind_name[S_NSTUDY] = {
    "theta", "derivative", "method", "effects", "dt"};

/* the trajectory and config scales and the knobs of every configuration;
   0 or -1 */
static int write_configs(study_h5 *o, const study_config *cfg, int ncfg) {
  int c, rc = 0;
  hsize_t dims[2] = {NTRAJ, (hsize_t)ncfg};
  static const char *const s_cfgd[1] = {"config"};
  const char *sv[MAXCFG];
  int32_t iv[MAXCFG], idx[MAXCFG];
  double dv[MAXCFG];
  hsize_t dt1 = NTRAJ;
  for (c = 0; c < ncfg; c++) idx[c] = c;
  rc |= study_h5_write(o, "trajectory", o->str, 1, &dt1, study_traj_name, "1",
                       study_traj_doc, NULL);
  rc |= study_h5_write(o, "config", H5T_NATIVE_INT32, 1, &dims[1], idx, "1",
                       "configuration index; see study, label and the knobs",
                       NULL);
#define CFG_STR(name, expr, doc)             \
  for (c = 0; c < ncfg; c++) sv[c] = (expr); \
  rc |= study_h5_write(o, name, o->str, 1, &dims[1], sv, "1", doc, s_cfgd);
#define CFG_F64(name, expr, units, doc)                                    \
  for (c = 0; c < ncfg; c++) dv[c] = (expr);                               \
  rc |= study_h5_write(o, name, H5T_NATIVE_DOUBLE, 1, &dims[1], dv, units, \
                       doc, s_cfgd);
#define CFG_I32(name, expr, doc)                                             \
  for (c = 0; c < ncfg; c++) iv[c] = (int32_t)(expr);                        \
  rc |= study_h5_write(o, name, H5T_NATIVE_INT32, 1, &dims[1], iv, "1", doc, \
                       s_cfgd);
  CFG_STR("study", study_kind_name[cfg[c].study],
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
  CFG_STR("derivative", study_deriv_name[cfg[c].deriv],
          "rates: exact (the trajectory's), central differences of the pose "
          "(fd_pose) or of the link lengths (fd_length) with step h, of the "
          "samples at interval dt (fd_samples), or the not-a-knot spline of "
          "the pose sampled every h (spline_pose)")
  CFG_F64("fd_step", cfg[c].h > 0 ? cfg[c].h : DNAN, "s",
          "finite-difference step, or the spline's row spacing, h (NaN for "
          "exact rates)")
  CFG_STR("method",
          cfg[c].method == RPS3_LAGRANGE ? "lagrange" : "newton_euler",
          "formulation of the dynamics")
  CFG_I32("effects", cfg[c].effects, "selected effects, RPS3_EFF_* bits")
  CFG_F64("dt_fraction", cfg[c].dt_frac > 0 ? cfg[c].dt_frac : DNAN, "1",
          "dt study: sample interval over the trajectory's duration")
  return rc ? -1 : 0;
}

/* the [trajectory, config] results and the references' own numbers; 0 or
   -1 */
static int write_results(study_h5 *o, const study_result res[][MAXCFG],
                         const study_reference *ref, int ncfg) {
  hsize_t dims[2] = {NTRAJ, (hsize_t)ncfg}, dt1 = NTRAJ;
  static const char *const s_tc[2] = {"trajectory", "config"};
  static const char *const s_t[1] = {"trajectory"};
  /* [trajectory, config] tables, packed with row length ncfg */
  double tv[NTRAJ * MAXCFG], fl[NTRAJ];
  int32_t tiv[NTRAJ * MAXCFG];
  int t, c, rc = 0;
#define RES_F64(name, field, units, doc)                                    \
  for (t = 0; t < NTRAJ; t++)                                               \
    for (c = 0; c < ncfg; c++) tv[t * ncfg + c] = res[t][c].field;          \
  rc |= study_h5_write(o, name, H5T_NATIVE_DOUBLE, 2, dims, tv, units, doc, \
                       s_tc);
  RES_F64("ns_per_point", ns_point, "ns",
          "median over the timed passes of the time per sample (trajectory "
          "evaluation included), CLOCK_MONOTONIC, one process")
  RES_F64("ns_per_point_q1", ns_q1, "ns", "first quartile of the passes")
  RES_F64("ns_per_point_q3", ns_q3, "ns", "third quartile of the passes")
  RES_F64("ns_per_second", ns_second, "ns",
          "time to compute one second of the trajectory: ns_per_point x "
          "samples / duration (the cost axis of the dt study)")
  RES_F64("force_error", force_err, "1",
          "max over samples and links of |F - F_ref| / max |F_ref| (for the "
          "effects ladder: against the model with every effect)")
  RES_F64("theta_error", theta_err, "rad",
          "max over samples and links of |theta - theta_ref|, theta_ref from "
          "inverse kinematics in long double")
  RES_F64("peak_force_error", peak_err, "1",
          "dt study: (peak_ref - max sampled |F|) / peak_ref, peak_ref from "
          "200001 samples")
  RES_F64("energy_residual", energy_err, "1",
          "dt study: max over intervals |W_k - (E_k+1 - E_k)| / max |W_k|, W_k "
          "the trapezoid of the power sum F_i dl_i, E = T + P")
  RES_F64("mean_iterations", mean_iter, "1",
          "theta solve iterations per sample")
#define RES_I32(name, field, doc)                                   \
  for (t = 0; t < NTRAJ; t++)                                       \
    for (c = 0; c < ncfg; c++) tiv[t * ncfg + c] = res[t][c].field; \
  rc |= study_h5_write(o, name, H5T_NATIVE_INT32, 2, dims, tiv, "1", doc, s_tc);
  RES_I32("failed_samples", nfail,
          "samples whose pipeline returned an error (errors are measured over "
          "the others)")
  RES_I32("status", status,
          "rps3_status of the first failing sample, 0 if none")
#define REF_F64(name, field, units, doc)                                    \
  for (t = 0; t < NTRAJ; t++) fl[t] = ref[t].field;                         \
  rc |= study_h5_write(o, name, H5T_NATIVE_DOUBLE, 1, &dt1, fl, units, doc, \
                       s_t);
  REF_F64("reference_floor_force", floor_ref, "1",
          "the reference's own rounding error / max |F_ref|: its double twin's "
          "distance from it x LDBL_EPSILON / DBL_EPSILON")
  REF_F64("reference_floor_theta", floor_theta, "rad",
          "max |theta_closed_form - theta_long_double| on the grid")
  REF_F64("reference_force_max", fscale, "N",
          "max |F_ref| over the grid: the force_error scale")
  REF_F64("reference_peak_force", peak, "N",
          "peak |F| over 200001 samples of the span")
  return rc ? -1 : 0;
}

int study_accuracy_write(const char *path, const char *cmdline,
                         const study_config *cfg, int ncfg,
                         const study_result res[][MAXCFG],
                         const study_reference *ref, size_t nsamp,
                         int repeats) {
  study_h5 o = {-1, -1};
  const double counts[2] = {(double)nsamp, (double)repeats};
  int rc = 0;
  if (study_h5_open(
          &o, path, cmdline,
          "rps3-study accuracy: error against a precise reference and median "
          "time per point, per configuration and trajectory") < 0 ||
      write_configs(&o, cfg, ncfg) < 0 ||
      write_results(&o, res, ref, ncfg) < 0 ||
      out_h5_attr_n(o.file, "samples", H5T_NATIVE_DOUBLE, 0, &counts[0]) < 0 ||
      out_h5_attr_n(o.file, "repeats", H5T_NATIVE_DOUBLE, 0, &counts[1]) < 0)
    rc = -1;
  if (study_h5_close(&o) < 0) rc = -1;
  return rc ? -1 : 0;
}
