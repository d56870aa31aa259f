/*
 * timelaw.c - the time laws s(tau) of a point-to-point motion and the
 * waypoints trajectory built from them, with exact first and second
 * derivatives (see rps3_time_law in rps3.h).
 */
#include <string.h>

#include "internal.h"

static const char *const law_names[3] = {"lspb", "minimum_jerk", "quintic"};

const char *rps3_time_law_name(int law) {
  return (law >= 0 && law < 3) ? law_names[law] : NULL;
}

int rps3_time_law_index(const char *name) {
  int k;
  if (name == NULL) return -1;
  for (k = 0; k < 3; k++)
    if (strcmp(name, law_names[k]) == 0) return k;
  return -1;
}

void rps3_law_eval(int law, double f, double tau, double s[3]) {
  if (law == RPS3_LAW_LSPB) {
    /* Table I's shape on [0, 1]: blends of length f at both ends */
    double v = 1.0 / (1.0 - f), a = v / f;
    if (tau < f) {
      s[0] = 0.5 * a * tau * tau;
      s[1] = a * tau;
      s[2] = a;
    } else if (tau < 1.0 - f) {
      s[0] = v * (tau - 0.5 * f);
      s[1] = v;
      s[2] = 0.0;
    } else {
      double u = 1.0 - tau;
      s[0] = 1.0 - 0.5 * a * u * u;
      s[1] = a * u;
      s[2] = -a;
    }
    return;
  }
  /* minimum jerk between rests, Horner form */
  s[0] = tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
  s[1] = tau * tau * (30.0 + tau * (-60.0 + 30.0 * tau));
  s[2] = tau * (60.0 + tau * (-180.0 + 120.0 * tau));
}

void rps3_law_peaks(int law, double f, double *vpeak, double *apeak) {
  if (law == RPS3_LAW_LSPB) {
    *vpeak = 1.0 / (1.0 - f);
    *apeak = 1.0 / (f * (1.0 - f));
  } else {
    /* s' peaks at tau = 1/2, s'' at tau = (3 - sqrt 3) / 6 */
    *vpeak = 15.0 / 8.0;
    *apeak = 10.0 / RPS3_SQRT3;
  }
}

/* duration of segment i (time[i] -> time[i+1]) stretched to the limits */
static double segment_duration(const rps3_waypoints *w, size_t i) {
  double T = w->time[i + 1] - w->time[i], vp, ap;
  int k;
  if (w->law == RPS3_LAW_QUINTIC) return T;
  rps3_law_peaks((int)w->law, w->blend, &vp, &ap);
  for (k = 0; k < 3; k++) {
    double D = fabs(w->pose[i + 1][k] - w->pose[i][k]);
    if (w->vmax[k] > 0 && D * vp / w->vmax[k] > T) T = D * vp / w->vmax[k];
    if (w->amax[k] > 0 && sqrt(D * ap / w->amax[k]) > T)
      T = sqrt(D * ap / w->amax[k]);
  }
  return T;
}

double rps3_waypoints_duration(const rps3_waypoints *w) {
  double T = 0.0;
  size_t i;
  for (i = 0; i + 1 < w->n; i++) T += segment_duration(w, i);
  return T;
}

/* quintic law: the rate of coordinate k at waypoint i (Craig's heuristic:
   the mean of the two slopes when they agree in sign, else 0; 0 at the
   ends) */
static double via_rate(const rps3_waypoints *w, size_t i, int k) {
  double d0, d1;
  if (i == 0 || i + 1 >= w->n) return 0.0;
  d0 = (w->pose[i][k] - w->pose[i - 1][k]) / (w->time[i] - w->time[i - 1]);
  d1 = (w->pose[i + 1][k] - w->pose[i][k]) / (w->time[i + 1] - w->time[i]);
  if (d0 > 0 && d1 > 0) return 0.5 * (d0 + d1);
  if (d0 < 0 && d1 < 0) return 0.5 * (d0 + d1);
  return 0.0;
}

int rps3_waypoints_eval(const rps3_waypoints *w, double t, double q[3],
                        double dq[3], double ddq[3]) {
  double t0 = 0.0, T = 0.0;
  size_t i;
  int k;
  /* the segment holding t; t = the end belongs to the last segment */
  for (i = 0; i + 1 < w->n; i++) {
    T = segment_duration(w, i);
    if (t < t0 + T || i + 2 == w->n) break;
    t0 += T;
  }
  for (k = 0; k < 3; k++) {
    double q0 = w->pose[i][k], D = w->pose[i + 1][k] - q0;
    double u = t - t0;
    if (w->law == RPS3_LAW_QUINTIC) {
      /* q0 + v0 u + a3 u^3 + a4 u^4 + a5 u^5 with the accelerations zero
         at both ends and the rates v0, v1 of via_rate */
      double v0 = via_rate(w, i, k), v1 = via_rate(w, i + 1, k);
      double T2 = T * T, T3 = T2 * T;
      double a3 = (20.0 * D - (8.0 * v1 + 12.0 * v0) * T) / (2.0 * T3);
      double a4 = (-30.0 * D + (14.0 * v1 + 16.0 * v0) * T) / (2.0 * T3 * T);
      double a5 = (12.0 * D - 6.0 * (v1 + v0) * T) / (2.0 * T3 * T2);
      q[k] = q0 + u * (v0 + u * u * (a3 + u * (a4 + u * a5)));
      dq[k] = v0 + u * u * (3.0 * a3 + u * (4.0 * a4 + u * 5.0 * a5));
      ddq[k] = u * (6.0 * a3 + u * (12.0 * a4 + u * 20.0 * a5));
    } else {
      double s[3], tau = u / T;
      if (tau > 1.0) tau = 1.0; /* rounding of the stretched sum */
      rps3_law_eval((int)w->law, w->blend, tau, s);
      q[k] = q0 + D * s[0];
      dq[k] = D * s[1] / T;
      ddq[k] = D * s[2] / (T * T);
    }
  }
  return RPS3_OK;
}

/* each waypoint must be reachable: closed-form inverse kinematics on a
   local workspace (no solver is touched, nothing is allocated) */
int rps3_pose_reachable(const rps3_model *m, const double pose[3]) {
  rps3_data d;
  memset(&d, 0, sizeof d);
  memcpy(d.pose, pose, sizeof d.pose);
  return rps3_ik(m, &d) == RPS3_OK;
}

/*
 * Each segment's motion in closed form, where a scan could step over a
 * short segment: its stretched duration T finite, and the peaks of the
 * law, D v* / T and D a* / T^2 (LSPB, MINJERK), or the quintic's
 * coefficients and the bounds of its rate and acceleration they give,
 * finite with the rates' squares (the dynamics square them).  A segment
 * of 1e-300 s or a limit of 1e-308 fails here, named by its waypoint.
 */
static int segments_check(const rps3_waypoints *w, rps3_check *chk) {
  double total = 0.0, vp = 0.0, ap = 0.0;
  size_t i;
  int k;
  if (w->law != RPS3_LAW_QUINTIC)
    rps3_law_peaks((int)w->law, w->blend, &vp, &ap);
  for (i = 0; i + 1 < w->n; i++) {
    double T = segment_duration(w, i), T2 = T * T;
    char why[200];
    total += T;
    if (!(isfinite(T) && total <= (double)RPS3_TRAJ_SPAN_MAX)) {
      /* the limit that stretches the segment most, or its time */
      int id = RPS3_F_WP_TIME, kk = (int)i + 1;
      double worst = -1.0, val = w->time[i + 1];
      for (k = 0; k < 3; k++) {
        double D = fabs(w->pose[i + 1][k] - w->pose[i][k]);
        if (w->law == RPS3_LAW_QUINTIC) break;
        if (w->vmax[k] > 0 && !(D * vp / w->vmax[k] <= worst)) {
          worst = D * vp / w->vmax[k];
          id = RPS3_F_WP_VMAX, kk = k, val = w->vmax[k];
        }
        if (w->amax[k] > 0 && !(sqrt(D * ap / w->amax[k]) <= worst)) {
          worst = sqrt(D * ap / w->amax[k]);
          id = RPS3_F_WP_AMAX, kk = k, val = w->amax[k];
        }
      }
      if (!(worst > w->time[i + 1] - w->time[i])) {
        id = RPS3_F_WP_TIME, kk = (int)i + 1, val = w->time[i + 1];
      }
      snprintf(why, sizeof why,
               "the segment from waypoint %zu%s makes the span %g s, more "
               "than %g s%s",
               i, id == RPS3_F_WP_TIME ? "" : ", stretched to the limits,",
               total, (double)RPS3_TRAJ_SPAN_MAX,
               id == RPS3_F_WP_TIME ? ""
                                    : " (a limit too small for the "
                                      "motion)");
      return rps3_check_fail(chk, id, kk, val, RPS3_F_WP_TIME, -1, why);
    }
    for (k = 0; k < 3; k++) {
      double D = fabs(w->pose[i + 1][k] - w->pose[i][k]), v, a;
      if (w->law == RPS3_LAW_QUINTIC) {
        double v0 = fabs(via_rate(w, i, k)), v1 = fabs(via_rate(w, i + 1, k));
        double T3 = T2 * T;
        double a3 = (20.0 * D + (8.0 * v1 + 12.0 * v0) * T) / (2.0 * T3);
        double a4 = (30.0 * D + (14.0 * v1 + 16.0 * v0) * T) / (2.0 * T3 * T);
        double a5 = (12.0 * D + 6.0 * (v1 + v0) * T) / (2.0 * T3 * T2);
        /* the magnitudes' sums bound |q'| and |q''| over the segment */
        v = v0 + T2 * (3.0 * a3 + T * (4.0 * a4 + T * 5.0 * a5));
        a = T * (6.0 * a3 + T * (12.0 * a4 + T * 20.0 * a5));
        if (!isfinite(a5)) v = a = (double)INFINITY;
      } else {
        v = D * vp / T;
        a = D * ap / T2;
        if (D > 0 && !(T2 > 0)) v = a = (double)INFINITY;
      }
      if (!isfinite(v * v) || !isfinite(a)) {
        snprintf(why, sizeof why,
                 "the segment from the previous waypoint (%.3g s, "
                 "coordinate %d moving %.3g) needs a rate %.3g or an "
                 "acceleration %.3g whose square or value is not finite",
                 T, k, D, v, a);
        return rps3_check_fail(chk, RPS3_F_WP_TIME, (int)i + 1, w->time[i + 1],
                               RPS3_F_WP_POSE, -1, why);
      }
    }
  }
  return RPS3_OK;
}

int rps3_waypoints_check(const rps3_model *m, const rps3_waypoints *w,
                         rps3_check *chk) {
  size_t i;
  int k;
  if (w->n < 2 || w->time == NULL || w->pose == NULL)
    return rps3_check_fail(chk, RPS3_F_WP_POSE, 0, (double)w->n, RPS3_F_WP_TIME,
                           -1, "needs at least 2 waypoints with times");
  if (w->law == RPS3_LAW_QUINTIC)
    for (k = 0; k < 3; k++)
      if (w->vmax[k] > 0 || w->amax[k] > 0)
        return rps3_check_fail(
            chk, w->vmax[k] > 0 ? RPS3_F_WP_VMAX : RPS3_F_WP_AMAX, k,
            w->vmax[k] > 0 ? w->vmax[k] : w->amax[k], RPS3_F_WP_LAW, -1,
            "limits need law lspb or minimum_jerk (a quintic through the "
            "waypoints has no closed-form peak)");
  if (w->time[0] != 0.0)
    return rps3_check_fail(chk, RPS3_F_WP_TIME, 0, w->time[0], -1, -1,
                           "the first waypoint is at t = 0");
  for (i = 0; i < w->n; i++) {
    if (!isfinite(w->time[i]) || (i > 0 && !(w->time[i] > w->time[i - 1])))
      return rps3_check_fail(chk, RPS3_F_WP_TIME, (int)i, w->time[i], -1, -1,
                             "times must be finite and strictly increasing");
    for (k = 0; k < 3; k++)
      if (!isfinite(w->pose[i][k]))
        return rps3_check_fail(chk, RPS3_F_WP_POSE, (int)i, w->pose[i][k], -1,
                               -1, "must be finite");
    if (!rps3_pose_reachable(m, w->pose[i]))
      return rps3_check_fail(chk, RPS3_F_WP_POSE, (int)i, w->pose[i][2], -1, -1,
                             "pose unreachable (a link of zero length or a "
                             "ball joint not above the base plane); value "
                             "is z_c");
  }
  return segments_check(w, chk);
}
