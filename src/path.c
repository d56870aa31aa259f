/*
 * path.c - a Cartesian path of the platform centre turned into the pose
 * (alpha, beta, z_c) by inverting the paper's (3)-(4), with exact first and
 * second derivatives (see rps3_path in rps3.h).
 *
 * (3)-(4): x_c = -(r/2)(1 - cos beta) cos 2 alpha,
 *          y_c =  (r/2)(1 - cos beta) sin 2 alpha,
 * so with rho_c = |(x_c, y_c)| and psi its polar angle:
 *   1 - cos beta = 2 rho_c / r, i.e. beta = 2 asin(sqrt(rho_c / r)),
 *   2 alpha = pi - psi.
 */
#include "internal.h"

/* the centre c, c', c'' at time t, and a reference angle psi such that psi
   is continuous along the path (the polar angle unwrapped) */
static void centre_eval(const rps3_path *p, double t, double c[3], double dc[3],
                        double ddc[3], double *psi) {
  double s[3], T = p->duration;
  int k;
  if (p->shape == RPS3_PATH_TABLE) {
    /* the row's unwrapped angle, plus the turn from its centre to c */
    size_t i = rps3_table_eval(&p->table, t, c, dc, ddc);
    const double *a = p->table.value[i];
    *psi = p->table_psi[i] +
           atan2(a[0] * c[1] - a[1] * c[0], a[0] * c[0] + a[1] * c[1]);
    return;
  }
  rps3_law_eval(p->law == RPS3_LAW_LSPB ? RPS3_LAW_LSPB : RPS3_LAW_MINJERK,
                p->blend, t / T, s);
  s[1] /= T;
  s[2] /= T * T;
  if (p->shape == RPS3_PATH_LINE) {
    double x0 = p->start[0], y0 = p->start[1];
    for (k = 0; k < 3; k++) {
      double D = p->end[k] - p->start[k];
      c[k] = p->start[k] + s[0] * D;
      dc[k] = s[1] * D;
      ddc[k] = s[2] * D;
    }
    /* a line that misses the axis turns by less than pi as seen from it:
       the angle from the start point is continuous */
    *psi = atan2(y0, x0) + atan2(x0 * c[1] - y0 * c[0], x0 * c[0] + y0 * c[1]);
  } else {
    double w = 2.0 * RPS3_PI * p->turns, a = p->radius;
    double phi = p->angle0 + w * s[0], dphi = w * s[1], ddphi = w * s[2];
    double cp = cos(phi), sp = sin(phi), cx = p->centre[0], cy = p->centre[1];
    double cn = sqrt(cx * cx + cy * cy);
    c[0] = cx + a * cp;
    c[1] = cy + a * sp;
    dc[0] = -a * sp * dphi;
    dc[1] = a * cp * dphi;
    ddc[0] = -a * (sp * ddphi + cp * dphi * dphi);
    ddc[1] = a * (cp * ddphi - sp * dphi * dphi);
    if (p->shape == RPS3_PATH_HELIX) {
      /* rise uniform in time, as (35) */
      c[2] = p->centre[2] + p->pitch * p->turns * t / T;
      dc[2] = p->pitch * p->turns / T;
    } else {
      c[2] = p->centre[2];
      dc[2] = 0.0;
    }
    ddc[2] = 0.0;
    if (a > cn) /* the circle winds about the axis: psi follows phi */
      *psi = phi + atan2(cp * cy - sp * cx, a + cp * cx + sp * cy);
    else /* it does not: psi stays within pi/2 of the centre's angle */
      *psi =
          atan2(cy, cx) + atan2(cx * c[1] - cy * c[0], cx * c[0] + cy * c[1]);
  }
}

/* rho_c of the centre at t, and the circle's own radius when it is centred
   on the axis (exact then, so that the paper's helix is reproduced) */
static double centre_rho(const rps3_path *p, const double c[3]) {
  if ((p->shape == RPS3_PATH_CIRCLE || p->shape == RPS3_PATH_HELIX) &&
      p->centre[0] == 0.0 && p->centre[1] == 0.0)
    return p->radius;
  return sqrt(c[0] * c[0] + c[1] * c[1]);
}

int rps3_path_eval(const rps3_model *m, const rps3_path *p, double t,
                   double q[3], double dq[3], double ddq[3]) {
  double c[3], dc[3], ddc[3], psi, rho, drho, ddrho, N, dN, dpsi, ddpsi;
  double u, du, ddu, bu, buu;
  centre_eval(p, t, c, dc, ddc, &psi);
  rho = centre_rho(p, c);
  if (!(rho > 0.0 && rho < 0.5 * m->r)) return RPS3_EREACH;
  /* rho' = (x x' + y y') / rho, rho'' from (rho^2)'' = 2 (rho'^2 + rho rho'')
   */
  drho = (c[0] * dc[0] + c[1] * dc[1]) / rho;
  ddrho = (dc[0] * dc[0] + dc[1] * dc[1] + c[0] * ddc[0] + c[1] * ddc[1] -
           drho * drho) /
          rho;
  /* psi' = (x y' - y x') / rho^2 = N / rho^2 */
  N = c[0] * dc[1] - c[1] * dc[0];
  dN = c[0] * ddc[1] - c[1] * ddc[0];
  dpsi = N / (rho * rho);
  ddpsi = dN / (rho * rho) - 2.0 * dpsi * drho / rho;
  q[0] = 0.5 * RPS3_PI - 0.5 * psi;
  dq[0] = -0.5 * dpsi;
  ddq[0] = -0.5 * ddpsi;
  /* beta = 2 asin(sqrt(u)), u = rho / r: beta_u = 1 / sqrt(u (1 - u)),
     beta_uu = -(1 - 2u) / (2 (u (1 - u))^(3/2)) */
  u = rho / m->r;
  du = drho / m->r;
  ddu = ddrho / m->r;
  bu = 1.0 / sqrt(u * (1.0 - u));
  buu = -0.5 * (1.0 - 2.0 * u) * bu * bu * bu;
  q[1] = 2.0 * asin(sqrt(u));
  dq[1] = bu * du;
  ddq[1] = buu * du * du + bu * ddu;
  q[2] = c[2];
  dq[2] = dc[2];
  ddq[2] = ddc[2];
  return RPS3_OK;
}

/* samples of the reachability scan in rps3_path_check, and bisection steps
   that locate the first bad time to duration * 2^-40 */
#define PATH_SCAN 2048
#define PATH_BISECT 40

/* 1 when the path's point at t is a valid pose: 0 < rho < r/2, z_c and the
   links as rps3_ik requires */
static int path_ok(const rps3_model *m, const rps3_path *p, double t) {
  double q[3], dq[3], ddq[3];
  if (rps3_path_eval(m, p, t, q, dq, ddq) != RPS3_OK) return 0;
  return rps3_pose_reachable(m, q);
}

double rps3_path_duration(const rps3_path *p) {
  return p->shape == RPS3_PATH_TABLE ? rps3_table_duration(&p->table)
                                     : p->duration;
}

/* a table of the centre: its rows (as any table), their distance from the
   axis, and the turn from one row to the next, each named by its row */
static int table_rows_check(const rps3_model *m, const rps3_path *p,
                            rps3_check *chk) {
  static const int id[4] = {RPS3_F_PATH_TABLE_TIME, RPS3_F_PATH_TABLE_VALUE,
                            RPS3_F_PATH_TABLE_RATE, RPS3_F_PATH_TABLE_ACC};
  const rps3_table *tb = &p->table;
  size_t i;
  if (rps3_table_check(m, tb, id, 0, chk) != RPS3_OK) return RPS3_EINVAL;
  if (p->table_psi == NULL)
    return rps3_check_fail(chk, RPS3_F_PATH_TABLE_VALUE, 0, 0.0, -1, -1,
                           "needs the rows' polar angles: "
                           "rps3_table_unwrap()");
  for (i = 0; i < tb->n; i++) {
    double rho = hypot(tb->value[i][0], tb->value[i][1]);
    if (!(rho > 0.0 && rho < 0.5 * m->r)) {
      char why[160];
      snprintf(why, sizeof why,
               "the centre must keep 0 < sqrt(x^2 + y^2) < r/2 = %.6g m; "
               "here %.6g m (value is x)",
               0.5 * m->r, rho);
      return rps3_check_fail(chk, RPS3_F_PATH_TABLE_VALUE, (int)i,
                             tb->value[i][0], -1, -1, why);
    }
    if (i > 0 && !(fabs(p->table_psi[i] - p->table_psi[i - 1]) < 0.5 * RPS3_PI))
      return rps3_check_fail(
          chk, RPS3_F_PATH_TABLE_VALUE, (int)i, tb->value[i][0], -1, -1,
          "the centre turns by pi/2 or more about the axis from the "
          "previous row: rows too far apart to follow alpha (value is x)");
  }
  return RPS3_OK;
}

/* the centre's peak rate and acceleration in closed form from the law's
   peaks v* / T, a* / T^2 (a line: |end - start| times them; a circle: the
   angle's rate w = 2 pi turns v* / T, the centre's radius w and radius w^2
   plus radius 2 pi turns a* / T^2; a helix adds the rise pitch turns / T):
   finite, with the rate's square, or no sample of the run is */
static int peaks_check(const rps3_path *p, rps3_check *chk) {
  const double T = p->duration;
  double vp, ap, v, a;
  rps3_law_peaks(p->law == RPS3_LAW_LSPB ? RPS3_LAW_LSPB : RPS3_LAW_MINJERK,
                 p->blend, &vp, &ap);
  vp /= T;
  ap /= T * T;
  if (p->shape == RPS3_PATH_LINE) {
    double D = 0.0;
    int k;
    for (k = 0; k < 3; k++) D = fmax(D, fabs(p->end[k] - p->start[k]));
    v = D * vp;
    a = D * ap;
    if (D > 0.0 && !(T * T > 0.0)) v = a = (double)INFINITY;
  } else {
    double w = 2.0 * RPS3_PI * fabs(p->turns);
    v = p->radius * w * vp;
    a = p->radius * (w * ap + (w * vp) * (w * vp));
    if (p->shape == RPS3_PATH_HELIX) v = fmax(v, fabs(p->pitch * p->turns) / T);
    if (!(T * T > 0.0)) v = a = (double)INFINITY;
  }
  if (isfinite(v * v) && isfinite(a)) return RPS3_OK;
  {
    char why[200];
    const int turns = p->shape != RPS3_PATH_LINE && fabs(p->turns) > 1.0;
    snprintf(why, sizeof why,
             "the centre's peak rate %.3g m/s or acceleration %.3g m/s^2 "
             "(its square or value) is not finite",
             v, a);
    return rps3_check_fail(
        chk, turns ? RPS3_F_PATH_TURNS : RPS3_F_PATH_DURATION, 0,
        turns ? p->turns : p->duration,
        turns ? RPS3_F_PATH_DURATION : RPS3_F_PATH_LAW, -1, why);
  }
}

int rps3_path_check(const rps3_model *m, const rps3_path *p, rps3_check *chk) {
  double T = rps3_path_duration(p), tbad = -1.0, x0, y0, dx, dy, L2;
  int i;
  if (p->shape != RPS3_PATH_TABLE && peaks_check(p, chk) != RPS3_OK)
    return RPS3_EINVAL;
  if (p->shape == RPS3_PATH_TABLE) {
    if (table_rows_check(m, p, chk) != RPS3_OK) return RPS3_EINVAL;
  } else if (p->shape != RPS3_PATH_LINE) {
    if (!(p->radius > 0.0))
      return rps3_check_fail(chk, RPS3_F_PATH_RADIUS, 0, p->radius,
                             RPS3_F_PATH_SHAPE, -1,
                             "a circle or helix needs a radius > 0");
    if (p->turns == 0.0)
      return rps3_check_fail(chk, RPS3_F_PATH_TURNS, 0, p->turns,
                             RPS3_F_PATH_SHAPE, -1,
                             "a circle or helix needs turns != 0");
    if (fabs(sqrt(p->centre[0] * p->centre[0] + p->centre[1] * p->centre[1]) -
             p->radius) <= 1e-12 * p->radius)
      return rps3_check_fail(
          chk, RPS3_F_PATH_RADIUS, 0, p->radius, RPS3_F_PATH_CENTRE, -1,
          "the circle passes through the axis x = y = 0, where alpha is not "
          "defined");
  } else {
    /* the closest point of the segment to the axis, in closed form: a scan
       could step over it */
    x0 = p->start[0];
    y0 = p->start[1];
    dx = p->end[0] - x0;
    dy = p->end[1] - y0;
    L2 = dx * dx + dy * dy;
    if (L2 > 0.0) {
      double s = -(x0 * dx + y0 * dy) / L2;
      if (s < 0.0) s = 0.0;
      if (s > 1.0) s = 1.0;
      if (hypot(x0 + s * dx, y0 + s * dy) <= 1e-12 * m->r)
        return rps3_check_fail(
            chk, RPS3_F_PATH_START, 0, x0, RPS3_F_PATH_END, -1,
            "the line passes through the axis x = y = 0, where alpha is not "
            "defined");
    } else if (hypot(x0, y0) <= 1e-12 * m->r) {
      return rps3_check_fail(chk, RPS3_F_PATH_START, 0, x0, RPS3_F_PATH_END, -1,
                             "the point is on the axis x = y = 0, where "
                             "alpha is not defined");
    }
  }
  /* scan for the first unreachable time, then bisect to locate it */
  for (i = 0; i <= PATH_SCAN; i++) {
    double t = (i == PATH_SCAN) ? T : T * (double)i / PATH_SCAN;
    if (!path_ok(m, p, t)) {
      double lo = i ? T * (double)(i - 1) / PATH_SCAN : 0.0, hi = t;
      int b;
      if (i > 0)
        for (b = 0; b < PATH_BISECT; b++) {
          double mid = 0.5 * (lo + hi);
          if (path_ok(m, p, mid))
            lo = mid;
          else
            hi = mid;
        }
      tbad = hi;
      break;
    }
  }
  if (tbad >= 0.0 && p->shape == RPS3_PATH_TABLE) {
    /* the row that starts the segment of the first bad time */
    double q[3], dq[3], ddq[3];
    size_t row = rps3_table_eval(&p->table, tbad, q, dq, ddq);
    char why[200];
    snprintf(why, sizeof why,
             "the path leaves the reachable set at t = %.9g s, after this "
             "row (value is x)",
             tbad);
    return rps3_check_fail(chk, RPS3_F_PATH_TABLE_VALUE, (int)row,
                           p->table.value[row][0], -1, -1, why);
  }
  if (tbad >= 0.0) {
    char why[200];
    snprintf(why, sizeof why,
             "the path leaves the reachable set at t = %.9g s (the centre "
             "must keep 0 < sqrt(x^2 + y^2) < r/2 = %.6g m and every link "
             "reachable)",
             tbad, 0.5 * m->r);
    return rps3_check_fail(
        chk, p->shape == RPS3_PATH_LINE ? RPS3_F_PATH_END : RPS3_F_PATH_RADIUS,
        0, p->shape == RPS3_PATH_LINE ? p->end[0] : p->radius,
        p->shape == RPS3_PATH_LINE ? RPS3_F_PATH_START : RPS3_F_PATH_CENTRE,
        RPS3_F_PATH_DURATION, why);
  }
  return RPS3_OK;
}
