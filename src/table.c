/*
 * table.c - a motion given as samples (a table of rows), interpolated per
 * coordinate by Hermite polynomials with exact first and second derivatives
 * (see rps3_table in rps3.h): quintic when the rows carry rates and
 * accelerations, cubic when they carry rates; rates a table lacks come from
 * the not-a-knot cubic spline (rps3_table_spline).
 */
#include "internal.h"

/*
 * The spline's slopes s_i solve a tridiagonal system (h_i = t_{i+1} - t_i,
 * d_i = (y_{i+1} - y_i) / h_i):
 *   inner rows   h_i s_{i-1} + 2 (h_{i-1} + h_i) s_i + h_{i-1} s_{i+1}
 *                  = 3 (h_i d_{i-1} + h_{i-1} d_i)    (C2 at row i)
 *   first row    h_1 s_0 + (h_0 + h_1) s_1
 *                  = ((h_0 + 2 (h_0 + h_1)) h_1 d_0 + h_0^2 d_1) / (h_0 + h_1)
 *   last row     the mirror image       (C3 at rows 1 and n-2: not-a-knot)
 * solved by elimination without pivoting: every pivot is positive for
 * n >= 4 (the first elimination leaves h_0 + h_1, each inner pivot exceeds
 * 2 h_{i-1} + h_i, and the last is at least h_{n-3} h_{n-3} / (2 h_{n-3} +
 * h_{n-2})).  The matrix is the same for the three coordinates: its
 * eliminated upper diagonal goes to work, the right-hand sides to rate.
 */
int rps3_table_spline(size_t n, const double *time, const double (*value)[3],
                      double (*rate)[3], double *work) {
  size_t i;
  int k;
  if (time == NULL || value == NULL || rate == NULL || work == NULL || n < 4)
    return RPS3_EINVAL;
  for (i = 0; i < n; i++)
    if (!isfinite(time[i]) || (i > 0 && !(time[i] > time[i - 1])) ||
        !v3_finite(value[i]))
      return RPS3_EINVAL;
  for (i = 0; i < n; i++) {
    double a, b, c, rhs[3], den;
    if (i == 0) {
      double h0 = time[1] - time[0], h1 = time[2] - time[1], s = h0 + h1;
      a = 0.0;
      b = h1;
      c = s;
      for (k = 0; k < 3; k++) {
        double d0 = (value[1][k] - value[0][k]) / h0;
        double d1 = (value[2][k] - value[1][k]) / h1;
        rhs[k] = ((h0 + 2.0 * s) * h1 * d0 + h0 * h0 * d1) / s;
      }
    } else if (i + 1 == n) {
      double hb = time[n - 2] - time[n - 3], he = time[n - 1] - time[n - 2];
      double s = hb + he;
      a = s;
      b = hb;
      c = 0.0;
      for (k = 0; k < 3; k++) {
        double db = (value[n - 2][k] - value[n - 3][k]) / hb;
        double de = (value[n - 1][k] - value[n - 2][k]) / he;
        rhs[k] = (he * he * db + (2.0 * s + he) * hb * de) / s;
      }
    } else {
      double hl = time[i] - time[i - 1], hr = time[i + 1] - time[i];
      a = hr;
      b = 2.0 * (hl + hr);
      c = hl;
      for (k = 0; k < 3; k++)
        rhs[k] = 3.0 * (hr * (value[i][k] - value[i - 1][k]) / hl +
                        hl * (value[i + 1][k] - value[i][k]) / hr);
    }
    /* forward elimination */
    den = i == 0 ? b : b - a * work[i - 1];
    work[i] = c / den;
    for (k = 0; k < 3; k++)
      rate[i][k] = (rhs[k] - (i == 0 ? 0.0 : a * rate[i - 1][k])) / den;
  }
  /* back substitution */
  for (i = n - 1; i-- > 0;)
    for (k = 0; k < 3; k++) rate[i][k] -= work[i] * rate[i + 1][k];
  /* finite rows can still overflow (1e308 apart, 1e-300 s apart) */
  for (i = 0; i < n; i++)
    if (!v3_finite(rate[i])) return RPS3_ERANGE;
  return RPS3_OK;
}

double rps3_table_duration(const rps3_table *tb) {
  if (tb->n < 2 || tb->time == NULL) return 0.0;
  return tb->time[tb->n - 1] - tb->time[0];
}

/* the segment [time[i], time[i+1]] holding ta by bisection; a time on a
   row takes the segment that starts there, the last row the last one */
static size_t segment_find(const rps3_table *tb, double ta) {
  size_t lo = 0, hi = tb->n - 1;
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (ta >= tb->time[mid])
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

size_t rps3_table_eval(const rps3_table *tb, double t, double q[3],
                       double dq[3], double ddq[3]) {
  double ta = tb->time[0] + t;
  size_t i = segment_find(tb, ta);
  double h = tb->time[i + 1] - tb->time[i], u = (ta - tb->time[i]) / h;
  int k;
  for (k = 0; k < 3; k++) {
    /* the polynomial in u = (t - t_i) / h on [0, 1]:
       y0 + h v0 u + c2 u^2 + c3 u^3 + c4 u^4 + c5 u^5 */
    double y0 = tb->value[i][k], y1 = tb->value[i + 1][k];
    double v0 = h * tb->rate[i][k], v1 = h * tb->rate[i + 1][k];
    double c2, c3, c4 = 0.0, c5 = 0.0;
    if (tb->acc != NULL) {
      /* quintic Hermite: c2 = h^2 a0 / 2 and c3..c5 from the value, rate
         and acceleration at u = 1 (D, V, A: what c3 u^3 + c4 u^4 + c5 u^5
         must add there) */
      double a0 = h * h * tb->acc[i][k], a1 = h * h * tb->acc[i + 1][k];
      double D = y1 - y0 - v0 - 0.5 * a0, V = v1 - v0 - a0, A = a1 - a0;
      c2 = 0.5 * a0;
      c3 = 10.0 * D - 4.0 * V + 0.5 * A;
      c4 = -15.0 * D + 7.0 * V - A;
      c5 = 6.0 * D - 3.0 * V + 0.5 * A;
    } else {
      /* cubic Hermite */
      c2 = 3.0 * (y1 - y0) - 2.0 * v0 - v1;
      c3 = 2.0 * (y0 - y1) + v0 + v1;
    }
    q[k] = y0 + u * (v0 + u * (c2 + u * (c3 + u * (c4 + u * c5))));
    dq[k] =
        (v0 + u * (2.0 * c2 + u * (3.0 * c3 + u * (4.0 * c4 + u * 5.0 * c5)))) /
        h;
    ddq[k] =
        (2.0 * c2 + u * (6.0 * c3 + u * (12.0 * c4 + u * 20.0 * c5))) / (h * h);
  }
  return i;
}

int rps3_table_unwrap(size_t n, const double (*centre)[3], double *psi) {
  size_t i;
  if (centre == NULL || psi == NULL) return RPS3_EINVAL;
  for (i = 0; i < n; i++)
    if (!v3_finite(centre[i])) return RPS3_EINVAL;
  for (i = 0; i < n; i++) {
    const double *a = centre[i > 0 ? i - 1 : 0], *b = centre[i];
    psi[i] = i == 0 ? atan2(b[1], b[0])
                    : psi[i - 1] + atan2(a[0] * b[1] - a[1] * b[0],
                                         a[0] * b[0] + a[1] * b[1]);
  }
  return RPS3_OK;
}

int rps3_table_check(const rps3_model *m, const rps3_table *tb, const int id[4],
                     int pose, rps3_check *chk) {
  size_t i;
  int k;
  if (tb->n < 2 || tb->time == NULL || tb->value == NULL)
    return rps3_check_fail(chk, id[1], 0, (double)tb->n, id[0], -1,
                           "needs at least 2 rows");
  if (tb->rate == NULL)
    return rps3_check_fail(chk, id[2], 0, 0.0, id[1], -1,
                           "needs rates: the table's own, or the spline's "
                           "from rps3_table_spline()");
  for (i = 0; i < tb->n; i++) {
    const double *row[3];
    int j;
    if (!isfinite(tb->time[i]) || (i > 0 && !(tb->time[i] > tb->time[i - 1])))
      return rps3_check_fail(chk, id[0], (int)i, tb->time[i], -1, -1,
                             "times must be finite and strictly increasing");
    row[0] = tb->value[i];
    row[1] = tb->rate[i];
    row[2] = tb->acc != NULL ? tb->acc[i] : NULL;
    for (j = 0; j < 3; j++)
      for (k = 0; k < 3 && row[j] != NULL; k++)
        if (!isfinite(row[j][k]))
          return rps3_check_fail(chk, id[1 + j], (int)i, row[j][k], -1, -1,
                                 "must be finite");
    if (pose && !rps3_pose_reachable(m, tb->value[i]))
      return rps3_check_fail(chk, id[1], (int)i, tb->value[i][2], -1, -1,
                             "pose unreachable (a link of zero length or a "
                             "ball joint not above the base plane); value "
                             "is z_c");
  }
  /* each segment's interpolant in closed form, where a scan could step
     over a short segment: the Hermite basis bounds its rate by about
     (|dv| / h + |r0| + |r1| + h (|a0| + |a1|)) and its acceleration by
     that over h, times small constants (1.5 and 6 for the cubic, below 4
     and 20 for the quintic; 8 and 32 taken), which must be finite with
     the rate's square (the dynamics square the rates) */
  for (i = 0; i + 1 < tb->n; i++) {
    double h = tb->time[i + 1] - tb->time[i];
    for (k = 0; k < 3; k++) {
      double sum = fabs(tb->value[i + 1][k] - tb->value[i][k]) / h +
                   fabs(tb->rate[i][k]) + fabs(tb->rate[i + 1][k]);
      char why[200];
      if (tb->acc != NULL)
        sum += h * (fabs(tb->acc[i][k]) + fabs(tb->acc[i + 1][k]));
      if (isfinite(8.0 * sum * 8.0 * sum) && isfinite(32.0 * sum / h)) continue;
      snprintf(why, sizeof why,
               "the interpolant's rate or acceleration to the next row "
               "(%.3g s later) overflows: rows too close for their values "
               "and rates (value is the time)",
               h);
      return rps3_check_fail(chk, id[0], (int)i + 1, tb->time[i + 1], id[1], -1,
                             why);
    }
  }
  /* the interpolant between the rows: its midpoints, where an overshoot
     between two reachable rows is largest */
  for (i = 0; pose && i + 1 < tb->n; i++) {
    double q[3], dq[3], ddq[3], t;
    char why[200];
    t = 0.5 * (tb->time[i] + tb->time[i + 1]) - tb->time[0];
    rps3_table_eval(tb, t, q, dq, ddq);
    if (!v3_finite(q) || !v3_finite(dq) || !v3_finite(ddq)) {
      /* not a pose out of reach: rows too close for their change */
      snprintf(why, sizeof why,
               "the interpolant's rate or acceleration is not finite "
               "between this row and the next (%.3g s apart: too close for "
               "their change, or below 1.5e-154 s, whose square underflows)",
               tb->time[i + 1] - tb->time[i]);
      return rps3_check_fail(chk, id[1], (int)i, tb->value[i][2], -1, -1, why);
    }
    if (!rps3_pose_reachable(m, q)) {
      snprintf(why, sizeof why,
               "the interpolant leaves the reachable set between this row "
               "and the next, at t = %.9g s (z_c there %.6g m)",
               t, q[2]);
      return rps3_check_fail(chk, id[1], (int)i, tb->value[i][2], -1, -1, why);
    }
  }
  return RPS3_OK;
}
