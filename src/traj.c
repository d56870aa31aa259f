/*
 * traj.c - trajectories with exact first and second derivatives.  The
 * paper's helix (section VI, Tables I-II) and a sinusoid per pose
 * coordinate here; waypoints (timelaw.c), Cartesian paths (path.c) and
 * tables of samples (table.c).  A
 * new kind adds a struct to rps3_traj, its rows to RPS3_FIELDS, a check
 * and an eval.
 */
#include <math.h>
#include <string.h>

#include "batch_kernel.h"
#include "internal.h"

void rps3_traj_default(rps3_traj *tr) {
  if (tr == NULL) return;
  memset(tr, 0, sizeof(*tr));
  tr->kind = RPS3_TRAJ_HELIX;
  /* Table II (r* = 0.266 mm, see the errata) */
  tr->helix.radius = 0.266e-3;
  tr->helix.pitch = 0.03048;
  tr->helix.z0 = 0.3048;
  tr->helix.period = 10.0;
  tr->helix.blend = 1.0;
  /* waypoints: no poses until the caller gives them */
  tr->wp.law = RPS3_LAW_LSPB;
  tr->wp.blend = 0.1;
  /* path: the same helix of Table II as a path of the centre */
  tr->path.shape = RPS3_PATH_HELIX;
  tr->path.centre[2] = 0.3048;
  tr->path.radius = 0.266e-3;
  tr->path.turns = 1.0;
  tr->path.pitch = 0.03048;
  tr->path.duration = 10.0;
  tr->path.law = RPS3_LAW_LSPB;
  tr->path.blend = 0.1;
}

/* samples of the scan that every kind passes after its own checks */
#define TRAJ_SCAN 64

/* the field a failure of the scan names, by kind: the one that sets the
   time scale */
static int scale_field(const rps3_traj *tr) {
  switch (tr->kind) {
  case RPS3_TRAJ_HELIX: return RPS3_F_HELIX_PERIOD;
  case RPS3_TRAJ_SINE: return RPS3_F_SINE_DURATION;
  case RPS3_TRAJ_WAYPOINTS: return RPS3_F_WP_TIME;
  case RPS3_TRAJ_PATH:
    if (tr->path.shape == RPS3_PATH_TABLE) return RPS3_F_PATH_TABLE_TIME;
    /* a circle's rates scale with turns / duration: the one off scale */
    return tr->path.shape != RPS3_PATH_LINE && fabs(tr->path.turns) > 1.0
               ? RPS3_F_PATH_TURNS
               : RPS3_F_PATH_DURATION;
  default: return RPS3_F_TABLE_TIME;
  }
}

static double scale_value(const rps3_traj *tr, double T) {
  switch (tr->kind) {
  case RPS3_TRAJ_WAYPOINTS: return tr->wp.time[tr->wp.n - 1];
  case RPS3_TRAJ_HELIX: return tr->helix.period;
  case RPS3_TRAJ_SINE: return tr->sine.duration;
  case RPS3_TRAJ_PATH:
    return tr->path.shape == RPS3_PATH_TABLE      ? tr->path.table.time[0]
           : scale_field(tr) == RPS3_F_PATH_TURNS ? tr->path.turns
                                                  : tr->path.duration;
  case RPS3_TRAJ_TABLE: return tr->table.time[0];
  default: return T;
  }
}

/* the run's own arithmetic at a sample: the closed-form stages of the
   inverse dynamics (positions, rates, accelerations, forces) on a local
   workspace, nothing allocated; RPS3_ERANGE when a finite motion
   overflows in them (velocity products with the masses and lengths), the
   other statuses (a singular point) are the run's to report per sample */
static int stages_at(const rps3_model *mc, const double q[3],
                     const double dq[3], const double ddq[3], char *what,
                     size_t sz) {
  rps3_data d;
  int st;
  memset(&d, 0, sizeof d);
  v3_copy(d.pose, q);
  v3_copy(d.dpose, dq);
  v3_copy(d.ddpose, ddq);
  st = rps3_inverse_stages(mc, &d);
  if (st == RPS3_OK && !(mc->opt.effects & RPS3_EFF_DYNAMIC)) {
    /* a simulation integrates the rates whatever the effects */
    st = rps3_velocity(mc, &d);
    if (st == RPS3_OK) st = rps3_acceleration(mc, &d);
  }
  if (st == RPS3_ERANGE) snprintf(what, sz, "%.150s", d.err.msg);
  return st;
}

/* a sample whose rates or accelerations could overflow the dynamics: a
   rate past TRAJ_FAST_RATE or an acceleration past TRAJ_FAST_ACC (pose
   units), some hundred orders of magnitude below where a model of finite
   masses and lengths overflows with them; slower samples skip the stages,
   which cost a check of a large sweep two microseconds a sample */
#define TRAJ_FAST_RATE 1e6
#define TRAJ_FAST_ACC 1e12
static int fast_motion(const double dq[3], const double ddq[3]) {
  int k;
  for (k = 0; k < 3; k++)
    if (!(fabs(dq[k]) <= TRAJ_FAST_RATE && fabs(ddq[k]) <= TRAJ_FAST_ACC))
      return 1;
  return 0;
}

/*
 * After each kind's own checks (closed forms of its peaks), the one rule
 * of every kind: a span in (0, RPS3_TRAJ_SPAN_MAX] (a stretched or summed
 * duration can overflow), and the trajectory evaluated at TRAJ_SCAN + 1
 * times over it gives finite poses, accelerations and rates whose squares
 * are finite, and at its fast samples dynamics that do not overflow: what
 * a run needs at every sample.
 */
static int motion_scan(const rps3_model *m, const rps3_traj *tr,
                       rps3_check *chk) {
  const double T = rps3_traj_duration(tr);
  double q[3], dq[3], ddq[3];
  rps3_model mc = *m;
  char what[200];
  int i, rc, comp = tr->kind == RPS3_TRAJ_WAYPOINTS ? (int)tr->wp.n - 1 : 0;
  int field = scale_field(tr);
  double value;
  mc.opt.theta = RPS3_THETA_CLOSED_FORM; /* the stages without a solver */
  if (!(T > 0.0 && T <= (double)RPS3_TRAJ_SPAN_MAX)) {
    char why[160];
    snprintf(why, sizeof why, "the span %g s must be > 0 and at most %g s", T,
             (double)RPS3_TRAJ_SPAN_MAX);
    return rps3_check_fail(chk, scale_field(tr), comp, scale_value(tr, T), -1,
                           -1, why);
  }
  value = scale_value(tr, T);
  if (tr->kind == RPS3_TRAJ_SINE) {
    /* the rates scale with amp freq: the coordinate where it is largest */
    int k;
    field = RPS3_F_SINE_FREQ;
    for (k = comp = 0; k < 3; k++)
      if (fabs(tr->sine.amp[k] * tr->sine.freq[k]) >
          fabs(tr->sine.amp[comp] * tr->sine.freq[comp]))
        comp = k;
    value = tr->sine.freq[comp];
  }
  for (i = 0; i <= TRAJ_SCAN; i++) {
    double t = i == TRAJ_SCAN ? T : T * ((double)i / TRAJ_SCAN);
    rc = rps3_traj_eval(m, tr, t, q, dq, ddq);
    if (rc != RPS3_OK || !rps3_motion_finite(dq, ddq)) {
      char why[320];
      snprintf(why, sizeof why,
               "the motion overflows at t = %.9g s: rate (%g, %g, %g), "
               "acceleration (%g, %g, %g); a rate's square or an "
               "acceleration is not finite",
               t, dq[0], dq[1], dq[2], ddq[0], ddq[1], ddq[2]);
      return rps3_check_fail(chk, field, comp, value, -1, -1, why);
    }
    if (fast_motion(dq, ddq) &&
        stages_at(&mc, q, dq, ddq, what, sizeof what) == RPS3_ERANGE) {
      char why[400];
      snprintf(why, sizeof why,
               "the motion overflows the dynamics at t = %.9g s (rate %g, "
               "%g, %g): %s",
               t, dq[0], dq[1], dq[2], what);
      return rps3_check_fail(chk, field, comp, value, -1, -1, why);
    }
  }
  return RPS3_OK;
}

int rps3_traj_check(const rps3_model *m, const rps3_traj *tr, rps3_check *chk) {
  rps3_check_clear(chk);
  if (m == NULL || tr == NULL || !m->valid) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg,
               "model not initialised or trajectory NULL");
    return RPS3_EINVAL;
  }
  /* the kind, then each field of that kind against its range
     (RPS3_FIELDS), then the rules that involve several fields */
  if (rps3_fields_check(RPS3_IN_TRAJ, tr, chk) != RPS3_OK ||
      rps3_fields_check(1 + (int)tr->kind, tr, chk) != RPS3_OK)
    return RPS3_EINVAL;
  if (tr->kind == RPS3_TRAJ_HELIX) {
    const rps3_helix *h = &tr->helix;
    double wmax = 2.0 * RPS3_PI / (h->period - h->blend);
    if (!(h->radius < 0.5 * m->r))
      return rps3_check_fail(
          chk, RPS3_F_HELIX_RADIUS, 0, h->radius, RPS3_F_RHO, RPS3_F_R,
          "needs 0 <= r* < r/2 = rho R / 2 (cos beta = 1 - 2 r* / r)");
    if (!(h->blend <= 0.5 * h->period))
      return rps3_check_fail(chk, RPS3_F_HELIX_BLEND, 0, h->blend,
                             RPS3_F_HELIX_PERIOD, -1,
                             "needs 0 < t_a <= T* / 2");
    /* Table I's peak rate 2 pi / (T* - t_a) and acceleration over t_a,
       the rise h / T*, and z at T*: finite, the rates squared too */
    if (!isfinite(wmax * wmax) || !isfinite(wmax / h->blend) ||
        !isfinite((h->pitch / h->period) * (h->pitch / h->period)))
      return rps3_check_fail(
          chk, RPS3_F_HELIX_PERIOD, 0, h->period, RPS3_F_HELIX_BLEND,
          RPS3_F_HELIX_PITCH,
          "the rates overflow: 2 pi / (T* - t_a), its square, its rate over "
          "t_a or (h / T*)^2 is not finite");
    if (!isfinite(h->z0 + h->pitch))
      return rps3_check_fail(chk, RPS3_F_HELIX_PITCH, 0, h->pitch,
                             RPS3_F_HELIX_Z0, -1,
                             "z_i + h, the height at T*, is not finite");
  }
  if (tr->kind == RPS3_TRAJ_SINE) {
    const rps3_sine *s = &tr->sine;
    int k;
    /* the rates reach amp w and amp w^2, and the dynamics square the
       rates: each must be finite, or every sample fails at run time */
    for (k = 0; k < 3; k++) {
      double w = 2.0 * RPS3_PI * s->freq[k], a = fabs(s->amp[k]);
      if (!isfinite((a * w) * w) || !isfinite((a * w) * (a * w)) ||
          !isfinite(w * s->duration + s->phase[k]))
        return rps3_check_fail(
            chk, RPS3_F_SINE_FREQ, k, s->freq[k], RPS3_F_SINE_AMP, -1,
            "the rates overflow: amp (2 pi freq)^2 or (amp 2 pi freq)^2 is "
            "not finite");
    }
  }
  if (tr->kind == RPS3_TRAJ_WAYPOINTS &&
      rps3_waypoints_check(m, &tr->wp, chk) != RPS3_OK)
    return RPS3_EINVAL;
  if (tr->kind == RPS3_TRAJ_PATH &&
      rps3_path_check(m, &tr->path, chk) != RPS3_OK)
    return RPS3_EINVAL;
  if (tr->kind == RPS3_TRAJ_TABLE) {
    static const int id[4] = {RPS3_F_TABLE_TIME, RPS3_F_TABLE_VALUE,
                              RPS3_F_TABLE_RATE, RPS3_F_TABLE_ACC};
    if (rps3_table_check(m, &tr->table, id, 1, chk) != RPS3_OK)
      return RPS3_EINVAL;
  }
  return motion_scan(m, tr, chk);
}

double rps3_traj_duration(const rps3_traj *tr) {
  if (tr == NULL) return 0.0;
  if (tr->kind == RPS3_TRAJ_HELIX) return tr->helix.period;
  if (tr->kind == RPS3_TRAJ_SINE) return tr->sine.duration;
  if (tr->kind == RPS3_TRAJ_WAYPOINTS)
    return tr->wp.n >= 2 && tr->wp.time != NULL && tr->wp.pose != NULL
               ? rps3_waypoints_duration(&tr->wp)
               : 0.0;
  if (tr->kind == RPS3_TRAJ_PATH) return rps3_path_duration(&tr->path);
  if (tr->kind == RPS3_TRAJ_TABLE) return rps3_table_duration(&tr->table);
  return 0.0;
}

/* phi(t) of Table I: linear segment with parabolic blends, phi(T*) = 2 pi.
   A sample on a corner takes the segment that starts there; t = T* the
   last segment's end. */
static void helix_phi(const rps3_helix *h, double t, double out[3]) {
  double ta = h->blend, T = h->period, tb = T - ta;
  double wmax = 2.0 * RPS3_PI / (T - ta); /* Table II: 2 pi / 9 rad/s */
  double acc = wmax / ta;
  if (t < ta) {
    out[0] = 0.5 * acc * t * t;
    out[1] = acc * t;
    out[2] = acc;
  } else if (t < tb) {
    out[0] = wmax * (t - 0.5 * ta);
    out[1] = wmax;
    out[2] = 0.0;
  } else {
    double tau = T - t;
    out[0] = 2.0 * RPS3_PI - 0.5 * acc * tau * tau;
    out[1] = acc * tau;
    out[2] = -acc;
  }
}

/* the outputs of a call that failed before computing them: NaN, never
   what the caller's arrays held */
static int eval_fail(int rc, double pose[3], double dpose[3],
                     double ddpose[3]) {
  int k;
  for (k = 0; k < 3; k++) {
    if (pose != NULL) pose[k] = (double)NAN;
    if (dpose != NULL) dpose[k] = (double)NAN;
    if (ddpose != NULL) ddpose[k] = (double)NAN;
  }
  return rc;
}

/* 1 when law (with blend f for LSPB) is a law: LSPB's blends must not
   overlap, or its s(tau) is no motion from 0 to 1 */
static int law_ok(rps3_time_law law, double f) {
  if (law == RPS3_LAW_LSPB) return f > 0.0 && f <= 0.5;
  return law == RPS3_LAW_MINJERK || law == RPS3_LAW_QUINTIC;
}

/* 1 when tr can be evaluated at all: a known kind, law and path shape,
   the arrays of its kind, blends that fit (the other values are
   rps3_traj_check's; an unchecked one that overflows is RPS3_ERANGE) */
static int evaluable(const rps3_traj *tr) {
  switch (tr->kind) {
  case RPS3_TRAJ_HELIX:
    return tr->helix.period > 0.0 && tr->helix.blend > 0.0 &&
           tr->helix.blend <= 0.5 * tr->helix.period;
  case RPS3_TRAJ_SINE: return 1;
  case RPS3_TRAJ_WAYPOINTS:
    return tr->wp.n >= 2 && tr->wp.time != NULL && tr->wp.pose != NULL &&
           law_ok(tr->wp.law, tr->wp.blend);
  case RPS3_TRAJ_PATH:
    if (tr->path.shape == RPS3_PATH_TABLE)
      return tr->path.table.n >= 2 && tr->path.table.time != NULL &&
             tr->path.table.value != NULL && tr->path.table.rate != NULL &&
             tr->path.table_psi != NULL;
    return (int)tr->path.shape >= 0 && (int)tr->path.shape < RPS3_PATH_TABLE &&
           law_ok(tr->path.law, tr->path.blend);
  case RPS3_TRAJ_TABLE:
    return tr->table.n >= 2 && tr->table.time != NULL &&
           tr->table.value != NULL && tr->table.rate != NULL;
  default: return 0;
  }
}

int rps3_traj_eval(const rps3_model *m, const rps3_traj *tr, double t,
                   double pose[3], double dpose[3], double ddpose[3]) {
  double q[3], dq[3], ddq[3];
  int k;
  if (m == NULL || tr == NULL || !m->valid || !isfinite(t) || !evaluable(tr))
    return eval_fail(RPS3_EINVAL, pose, dpose, ddpose);
  if (t < 0.0 || t > rps3_traj_duration(tr))
    return eval_fail(RPS3_EDOMAIN, pose, dpose, ddpose);
  if (tr->kind == RPS3_TRAJ_HELIX) {
    const rps3_helix *h = &tr->helix;
    double phi[3];
    helix_phi(h, t, phi);
    /* Table I: alpha = -phi/2 + pi/2 (36) with n = 1 */
    q[0] = -0.5 * phi[0] + 0.5 * RPS3_PI;
    dq[0] = -0.5 * phi[1];
    ddq[0] = -0.5 * phi[2];
    /* (37) corrected: 1 - cos(beta) = 2 r* / r, i.e. sin(beta/2) = sqrt(r* / r)
     */
    q[1] = 2.0 * asin(sqrt(h->radius / m->r));
    dq[1] = ddq[1] = 0.0;
    q[2] = h->z0 + h->pitch * t / h->period;
    dq[2] = h->pitch / h->period;
    ddq[2] = 0.0;
  } else if (tr->kind == RPS3_TRAJ_SINE) {
    const rps3_sine *s = &tr->sine;
    for (k = 0; k < 3; k++) {
      double w = 2.0 * RPS3_PI * s->freq[k], ph = w * t + s->phase[k];
      q[k] = s->mean[k] + s->amp[k] * sin(ph);
      dq[k] = s->amp[k] * w * cos(ph);
      ddq[k] = -s->amp[k] * w * w * sin(ph);
    }
  } else if (tr->kind == RPS3_TRAJ_WAYPOINTS) {
    rps3_waypoints_eval(&tr->wp, t, q, dq, ddq);
  } else if (tr->kind == RPS3_TRAJ_PATH) {
    int rc = rps3_path_eval(m, &tr->path, t, q, dq, ddq);
    if (rc != RPS3_OK) return eval_fail(rc, pose, dpose, ddpose);
  } else {
    rps3_table_eval(&tr->table, t, q, dq, ddq);
  }
  for (k = 0; k < 3; k++) {
    if (pose != NULL) pose[k] = q[k];
    if (dpose != NULL) dpose[k] = dq[k];
    if (ddpose != NULL) ddpose[k] = ddq[k];
  }
  /* a trajectory that passed rps3_traj_check can still overflow (amp
     1e300 times (2 pi freq)^2), and an unchecked one can hold anything */
  if (!v3_finite(q) || !v3_finite(dq) || !v3_finite(ddq)) return RPS3_ERANGE;
  return RPS3_OK;
}
