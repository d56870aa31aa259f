/* test_table.c - a motion from a table of samples: the interpolants
   reproduce the polynomials they are exact for (cubic spline: cubics;
   cubic Hermite: cubics; quintic Hermite: quintics), their derivatives
   against central differences, the spline's convergence order on a smooth
   motion, and every refusal naming its field and row; a path of the
   centre from a table against the circle path it samples. */
#include <stdlib.h>

#include "testutil.h"

#define NROW 9
#define NDENSE 161 /* rows of the finest table of the convergence study */

static void model_setup(rps3_model *m) {
  rps3_model_default(m);
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

/* a reachable motion of Table II's manipulator, polynomial of degree deg
   in the absolute time ta (value, rate, acceleration per coordinate) */
static const double poly[3][6] = {{0.3, 0.2, -0.05, 0.01, 0.004, -0.0009},
                                  {0.08, 0.01, -0.004, 0.0007, 3e-4, -5e-5},
                                  {0.3, 0.01, 0.002, -0.0011, 2e-4, 3e-5}};

static void poly_eval(int deg, double ta, double q[3], double dq[3],
                      double ddq[3]) {
  int k, j;
  for (k = 0; k < 3; k++) {
    double p = 1.0; /* ta^(j-2) in the loop, from j = 2 */
    q[k] = poly[k][0] + poly[k][1] * ta;
    dq[k] = poly[k][1];
    ddq[k] = 0.0;
    for (j = 2; j <= deg; j++) {
      ddq[k] += j * (j - 1) * poly[k][j] * p;
      dq[k] += j * poly[k][j] * p * ta;
      q[k] += poly[k][j] * p * ta * ta;
      p *= ta;
    }
  }
}

/* non-uniform rows from ta = 0.21 (high entropy, not a grid) */
static void rows_make(double *time, int n, double span) {
  int i;
  for (i = 0; i < n; i++)
    time[i] = 0.21 + span * (i + 0.23 * sin(1.7 * i) * (i > 0 && i < n - 1)) /
                         (n - 1);
}

typedef struct {
  double time[NROW], value[NROW][3], rate[NROW][3], acc[NROW][3];
  double work[NROW];
} rows;

/* rows of the polynomial of degree deg; what = 0: values only (rates from
   the spline), 1: exact rates, 2: exact rates and accelerations */
static void table_setup(rps3_traj *tr, rows *r, int deg, int what) {
  int i;
  rows_make(r->time, NROW, 3.0);
  for (i = 0; i < NROW; i++)
    poly_eval(deg, r->time[i], r->value[i], r->rate[i], r->acc[i]);
  if (what == 0)
    assert_int_equal(rps3_table_spline(NROW, r->time,
                                       (const double(*)[3])r->value, r->rate,
                                       r->work),
                     RPS3_OK);
  rps3_traj_default(tr);
  tr->kind = RPS3_TRAJ_TABLE;
  tr->table.n = NROW;
  tr->table.time = r->time;
  tr->table.value = (const double(*)[3])r->value;
  tr->table.rate = (const double(*)[3])r->rate;
  tr->table.acc = what == 2 ? (const double(*)[3])r->acc : NULL;
}

/* each interpolant reproduces the polynomials of its degree: value, rate
   and acceleration at random times and on every row.  1e-11: the spline's
   slopes come from an elimination of condition ~ max h / min h ~ 3 on
   values ~0.3; the acceleration divides rounding ~1e-16 by h^2 ~ 0.1 */
static void exact_for_polynomials(void **state) {
  static const int cases[3][2] = {{3, 0}, {3, 1}, {5, 2}};
  rps3_model m;
  rps3_traj tr;
  rows r;
  int c, n, k;
  uint64_t seed = 0x7ab1e;
  (void)state;
  model_setup(&m);
  for (c = 0; c < 3; c++) {
    double T;
    table_setup(&tr, &r, cases[c][0], cases[c][1]);
    assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
    T = rps3_traj_duration(&tr);
    CHECK_REL(T, r.time[NROW - 1] - r.time[0], 0.0, 1.0, "span");
    for (n = 0; n < 300 + NROW; n++) {
      double t = n < NROW ? r.time[n] - r.time[0] : rnd_uniform(&seed, 0, T);
      double q[3], dq[3], ddq[3], w[3], dw[3], ddw[3];
      assert_int_equal(rps3_traj_eval(&m, &tr, t, q, dq, ddq), RPS3_OK);
      poly_eval(cases[c][0], r.time[0] + t, w, dw, ddw);
      for (k = 0; k < 3; k++) {
        CHECK_REL(q[k], w[k], 1e-11, 1.0, "case %d value %d t %g", c, k, t);
        CHECK_REL(dq[k], dw[k], 1e-11, 1.0, "case %d rate %d t %g", c, k, t);
        CHECK_REL(ddq[k], ddw[k], 1e-11, 1.0, "case %d acc %d t %g", c, k, t);
      }
    }
  }
  /* and a cubic is where the cubic Hermite stops: a quartic is not
     reproduced (the check above can fail) */
  table_setup(&tr, &r, 4, 1);
  {
    double q[3], dq[3], ddq[3], w[3], dw[3], ddw[3], t = 0.5 * (r.time[3] +
                                                            r.time[4]) -
                                                       r.time[0];
    assert_int_equal(rps3_traj_eval(&m, &tr, t, q, dq, ddq), RPS3_OK);
    poly_eval(4, r.time[0] + t, w, dw, ddw);
    assert_true(fabs(ddq[0] - ddw[0]) > 1e-6);
  }
}

/* rate and acceleration against central differences of the value and
   rate, off the rows (where the cubic Hermite's acceleration jumps) */
static void derivatives_fd(void **state) {
  rps3_model m;
  rps3_traj tr;
  rows r;
  int c, n, k, i;
  uint64_t seed = 0x5eed;
  (void)state;
  model_setup(&m);
  for (c = 0; c < 3; c++) {
    double T, h;
    table_setup(&tr, &r, 5, c);
    /* a non-polynomial motion: the interpolant is not the truth here */
    for (i = 0; i < NROW; i++)
      for (k = 0; k < 3; k++) {
        double w = 1.3 + 0.4 * k, a = k == 2 ? 0.01 : 0.05;
        r.value[i][k] += a * sin(w * r.time[i]);
        r.rate[i][k] += a * w * cos(w * r.time[i]);
        r.acc[i][k] -= a * w * w * sin(w * r.time[i]);
      }
    if (c == 0)
      assert_int_equal(rps3_table_spline(NROW, r.time,
                                         (const double(*)[3])r.value, r.rate,
                                         r.work),
                       RPS3_OK);
    assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
    T = rps3_traj_duration(&tr);
    /* h as in test_traj_kinds: truncation and rounding below 1e-8 */
    h = 2e-6 * T;
    for (n = 0; n < 300; n++) {
      double t = rnd_uniform(&seed, 2 * h, T - 2 * h);
      double q[3], dq[3], ddq[3], qp[3], dqp[3], qm[3], dqm[3], dd[3];
      int near = 0;
      for (i = 0; i < NROW; i++)
        if (fabs(r.time[0] + t - r.time[i]) < 4 * h) near = 1;
      if (near) continue;
      assert_int_equal(rps3_traj_eval(&m, &tr, t, q, dq, ddq), RPS3_OK);
      assert_int_equal(rps3_traj_eval(&m, &tr, t + h, qp, dqp, dd), RPS3_OK);
      assert_int_equal(rps3_traj_eval(&m, &tr, t - h, qm, dqm, dd), RPS3_OK);
      for (k = 0; k < 3; k++) {
        CHECK_REL(dq[k], (qp[k] - qm[k]) / (2 * h), TOL_FD, 0.1,
                  "case %d rate %d at t = %g", c, k, t);
        CHECK_REL(ddq[k], (dqp[k] - dqm[k]) / (2 * h), TOL_FD, 0.1,
                  "case %d acceleration %d at t = %g", c, k, t);
      }
    }
  }
}

/* the spline is C2 across the rows: the left and right limits of the
   acceleration agree at every inner row (the cubic Hermite's do not) */
static void spline_continuity(void **state) {
  rps3_model m;
  rps3_traj tr;
  rows r;
  int i, k, jumps = 0;
  (void)state;
  model_setup(&m);
  table_setup(&tr, &r, 5, 0);
  for (i = 1; i + 1 < NROW; i++) {
    double t = r.time[i] - r.time[0], e = 1e-9, a[3], b[3], x[3], y[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, t - e, x, y, a), RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, t + e, x, y, b), RPS3_OK);
    /* the third derivative is bounded (~1): over 2e-9 s the acceleration
       moves by < 1e-8 */
    for (k = 0; k < 3; k++)
      CHECK_REL(b[k], a[k], 1e-7, 0.01, "acceleration %d at row %d", k, i);
  }
  table_setup(&tr, &r, 5, 1);
  for (i = 1; i + 1 < NROW; i++) {
    double t = r.time[i] - r.time[0], e = 1e-9, a[3], b[3], x[3], y[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, t - e, x, y, a), RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, t + e, x, y, b), RPS3_OK);
    jumps += fabs(b[0] - a[0]) > 1e-6;
  }
  assert_true(jumps > 0);
}

/* max errors of the spline of a smooth motion over rows every T / (n - 1):
   value, rate, acceleration (dense sampling between the rows) */
static void spline_errors(int n, double err[3]) {
  static double time[NDENSE], value[NDENSE][3], rate[NDENSE][3], work[NDENSE];
  rps3_table tb;
  rps3_traj tr;
  rps3_model m;
  int i, j;
  const double T = 2.0, w = 2.9, a = 0.1;
  for (i = 0; i < n; i++) {
    time[i] = T * i / (n - 1);
    value[i][0] = value[i][1] = value[i][2] = a * sin(w * time[i]);
  }
  assert_int_equal(
      rps3_table_spline((size_t)n, time, (const double(*)[3])value, rate, work),
      RPS3_OK);
  memset(&tb, 0, sizeof tb);
  tb.n = (size_t)n;
  tb.time = time;
  tb.value = (const double(*)[3])value;
  tb.rate = (const double(*)[3])rate;
  model_setup(&m);
  rps3_traj_default(&tr);
  tr.kind = RPS3_TRAJ_TABLE;
  tr.table = tb;
  err[0] = err[1] = err[2] = 0.0;
  for (j = 0; j <= 4000; j++) {
    double t = T * j / 4000.0, q[3], dq[3], ddq[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, t, q, dq, ddq), RPS3_OK);
    err[0] = fmax(err[0], fabs(q[0] - a * sin(w * t)));
    err[1] = fmax(err[1], fabs(dq[0] - a * w * cos(w * t)));
    err[2] = fmax(err[2], fabs(ddq[0] + a * w * w * sin(w * t)));
  }
}

/* the convergence order of the spline: halving the row spacing divides
   the errors of the value, rate and acceleration by 2^4, 2^3 and 2^2
   (orders measured between 41 and 161 rows within 0.3 of 4, 3, 2; the
   table of docs/trajectories.md is this test's output) */
static void spline_convergence(void **state) {
  static const int rows_n[4] = {21, 41, 81, 161};
  double e[4][3];
  int i, k;
  (void)state;
  for (i = 0; i < 4; i++) {
    spline_errors(rows_n[i], e[i]);
    print_message("rows %3d  h %.4f s  value %.3e  rate %.3e  acc %.3e\n",
                  rows_n[i], 2.0 / (rows_n[i] - 1), e[i][0], e[i][1], e[i][2]);
  }
  for (i = 2; i < 4; i++)
    for (k = 0; k < 3; k++) {
      double order = log2(e[i - 1][k] / e[i][k]);
      if (fabs(order - (4 - k)) > 0.3)
        fail_msg("derivative %d: order %.2f between %d and %d rows, want %d",
                 k, order, rows_n[i - 1], rows_n[i], 4 - k);
    }
}

/* trajectory tr is refused for model m, naming field id_ (component or
   row comp_): TRAJ_REFUSED in testutil.h */
#define REFUSED(tr_, id_, comp_) TRAJ_REFUSED(m, tr_, id_, comp_)

static void refusals(void **state) {
  rps3_model m;
  rps3_traj tr;
  rows r;
  double q[3];
  (void)state;
  model_setup(&m);
  /* the spline: too few rows, times not increasing, NULL */
  table_setup(&tr, &r, 3, 1);
  assert_int_equal(rps3_table_spline(3, r.time, (const double(*)[3])r.value,
                                     r.rate, r.work),
                   RPS3_EINVAL);
  assert_int_equal(rps3_table_spline(NROW, r.time, NULL, r.rate, r.work),
                   RPS3_EINVAL);
  /* a value not finite; rows that overflow the slopes */
  r.value[6][1] = (double)NAN;
  assert_int_equal(rps3_table_spline(NROW, r.time, (const double(*)[3])r.value,
                                     r.rate, r.work),
                   RPS3_EINVAL);
  r.value[6][1] = 1.7e308;
  r.value[7][1] = -1.7e308;
  assert_int_equal(rps3_table_spline(NROW, r.time, (const double(*)[3])r.value,
                                     r.rate, r.work),
                   RPS3_ERANGE);
  table_setup(&tr, &r, 3, 1);
  r.time[5] = r.time[4];
  assert_int_equal(rps3_table_spline(NROW, r.time, (const double(*)[3])r.value,
                                     r.rate, r.work),
                   RPS3_EINVAL);
  REFUSED(tr, RPS3_F_TABLE_TIME, 5);
  r.time[5] = (double)NAN;
  REFUSED(tr, RPS3_F_TABLE_TIME, 5);
  /* too few rows, no rates */
  table_setup(&tr, &r, 3, 1);
  tr.table.n = 1;
  REFUSED(tr, RPS3_F_TABLE_VALUE, 0);
  table_setup(&tr, &r, 3, 1);
  tr.table.rate = NULL;
  REFUSED(tr, RPS3_F_TABLE_RATE, 0);
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.1, q, NULL, NULL), RPS3_EINVAL);
  /* NaN in a value, a rate, an acceleration: named with the row */
  table_setup(&tr, &r, 5, 2);
  r.value[3][1] = (double)NAN;
  REFUSED(tr, RPS3_F_TABLE_VALUE, 3);
  table_setup(&tr, &r, 5, 2);
  r.rate[6][2] = (double)INFINITY;
  REFUSED(tr, RPS3_F_TABLE_RATE, 6);
  table_setup(&tr, &r, 5, 2);
  r.acc[7][0] = (double)NAN;
  REFUSED(tr, RPS3_F_TABLE_ACC, 7);
  /* a row below the base plane */
  table_setup(&tr, &r, 3, 1);
  r.value[4][2] = -0.05;
  REFUSED(tr, RPS3_F_TABLE_VALUE, 4);
  /* reachable rows, but a rate that swings z_c below the base between
     rows 2 and 3 */
  table_setup(&tr, &r, 3, 1);
  r.rate[2][2] = -40.0;
  r.rate[3][2] = 40.0;
  REFUSED(tr, RPS3_F_TABLE_VALUE, 2);
  /* rows 1e-300 s apart, all at one reachable pose: the interpolant's
     acceleration divides by step^2, which underflows to 0, and the
     failure is named as such, not as a pose out of reach */
  {
    rps3_check chk;
    int i;
    table_setup(&tr, &r, 3, 1);
    for (i = 0; i < NROW; i++) {
      r.time[i] = 1e-300 * i;
      memcpy(r.value[i], r.value[0], sizeof r.value[i]);
      r.rate[i][0] = r.rate[i][1] = r.rate[i][2] = 0.0;
    }
    assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
    assert_int_equal(chk.field, RPS3_F_TABLE_VALUE);
    assert_int_equal(chk.comp, 0);
    assert_non_null(strstr(chk.msg, "not finite between this row and the "
                                    "next (1e-300 s apart"));
    assert_null(strstr(chk.msg, "reachable"));
  }
  /* outside the span */
  table_setup(&tr, &r, 3, 1);
  assert_int_equal(
      rps3_traj_eval(&m, &tr, rps3_traj_duration(&tr) * 1.001, q, NULL, NULL),
      RPS3_EDOMAIN);
  assert_int_equal(rps3_traj_eval(&m, &tr, rps3_traj_duration(&tr), q, NULL,
                                  NULL),
                   RPS3_OK);
}


/* ---------------------------------------------------------- path table */

#define NPATH 61

/* the circle (centre (0.011, 0.004, 0.3), radius 0.027, 1.25 turns from
   angle 0.7, minimum jerk over 4 s) and its centre, rate and acceleration,
   from its definition (not through the library) */
static void circle_centre(double t, double c[3], double dc[3], double ddc[3]) {
  const double T = 4.0, a = 0.027, w = 2 * PI * 1.25;
  double tau = t / T;
  double s = tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
  double ds = 30 * tau * tau * (1 - tau) * (1 - tau) / T;
  double dds = 60 * tau * (1 - tau) * (1 - 2 * tau) / (T * T);
  double ph = 0.7 + w * s, dph = w * ds, ddph = w * dds;
  c[0] = 0.011 + a * cos(ph);
  c[1] = 0.004 + a * sin(ph);
  c[2] = 0.3;
  dc[0] = -a * sin(ph) * dph;
  dc[1] = a * cos(ph) * dph;
  dc[2] = 0.0;
  ddc[0] = -a * (sin(ph) * ddph + cos(ph) * dph * dph);
  ddc[1] = a * (cos(ph) * ddph - sin(ph) * dph * dph);
  ddc[2] = 0.0;
}

typedef struct {
  double time[NPATH], c[NPATH][3], dc[NPATH][3], ddc[NPATH][3], psi[NPATH];
  double work[NPATH];
} path_rows;

/* what = 0: centres only (spline), 2: with rates and accelerations */
static void path_table_setup(rps3_traj *tr, path_rows *r, int what) {
  int i;
  for (i = 0; i < NPATH; i++) {
    r->time[i] = 4.0 * i / (NPATH - 1);
    circle_centre(r->time[i], r->c[i], r->dc[i], r->ddc[i]);
  }
  if (what == 0)
    assert_int_equal(rps3_table_spline(NPATH, r->time,
                                       (const double(*)[3])r->c, r->dc,
                                       r->work),
                     RPS3_OK);
  assert_int_equal(rps3_table_unwrap(NPATH, (const double(*)[3])r->c, r->psi),
                   RPS3_OK);
  rps3_traj_default(tr);
  tr->kind = RPS3_TRAJ_PATH;
  tr->path.shape = RPS3_PATH_TABLE;
  tr->path.table.n = NPATH;
  tr->path.table.time = r->time;
  tr->path.table.value = (const double(*)[3])r->c;
  tr->path.table.rate = (const double(*)[3])r->dc;
  tr->path.table.acc = what == 2 ? (const double(*)[3])r->ddc : NULL;
  tr->path.table_psi = r->psi;
}

/* the same circle as the path kind computes it */
static void circle_path(rps3_traj *tr) {
  rps3_traj_default(tr);
  tr->kind = RPS3_TRAJ_PATH;
  tr->path.shape = RPS3_PATH_CIRCLE;
  tr->path.law = RPS3_LAW_MINJERK;
  tr->path.duration = 4.0;
  tr->path.centre[0] = 0.011;
  tr->path.centre[1] = 0.004;
  tr->path.centre[2] = 0.3;
  tr->path.radius = 0.027;
  tr->path.angle0 = 0.7;
  tr->path.turns = 1.25;
}

/* with the centre's rates and accelerations the table path takes the
   circle's pose, rate and acceleration at every row (the quintic Hermite
   interpolates all three there; 1e-12 as TOL_EXACT: the inversion of
   (3)-(4) runs on the same numbers, its psi reached by another rounding);
   the circle winds about the axis (radius 0.027 > 0.0117 from the axis),
   so psi runs past pi and alpha must follow it without a jump */
static void path_table_is_the_circle(void **state) {
  rps3_model m;
  rps3_traj tr, circ;
  path_rows r;
  int i, k;
  double prev = 0.0;
  (void)state;
  model_setup(&m);
  path_table_setup(&tr, &r, 2);
  circle_path(&circ);
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  assert_int_equal(rps3_traj_check(&m, &circ, NULL), RPS3_OK);
  CHECK_REL(rps3_traj_duration(&tr), 4.0, 0.0, 1.0, "span");
  for (i = 0; i < NPATH; i++) {
    double a[3], da[3], dda[3], b[3], db[3], ddb[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, r.time[i], a, da, dda), 0);
    assert_int_equal(rps3_traj_eval(&m, &circ, r.time[i], b, db, ddb), 0);
    for (k = 0; k < 3; k++) {
      CHECK_REL(a[k], b[k], TOL_EXACT, 1.0, "pose %d row %d", k, i);
      CHECK_REL(da[k], db[k], TOL_EXACT, 1.0, "rate %d row %d", k, i);
      CHECK_REL(dda[k], ddb[k], TOL_EXACT, 1.0, "acceleration %d row %d", k,
                i);
    }
  }
  /* alpha continuous on a fine grid over the 1.25 turns */
  for (i = 0; i <= 4000; i++) {
    double q[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, 4.0 * i / 4000, q, NULL, NULL),
                     0);
    if (i > 0 && fabs(q[0] - prev) > 0.01)
      fail_msg("alpha jumps by %g at sample %d", q[0] - prev, i);
    prev = q[0];
  }
  /* and it turned more than half a turn of alpha (the rows after psi
     passed pi were compared with the circle kind above) */
  assert_true(prev - (0.5 * PI - 0.5 * r.psi[0]) < -PI);
}

/* the spline of the centres: exact derivatives of what it gives, against
   central differences, between the rows */
static void path_table_derivatives(void **state) {
  rps3_model m;
  rps3_traj tr;
  path_rows r;
  int n, k;
  uint64_t seed = 0xce47e;
  double h = 2e-6 * 4.0;
  (void)state;
  model_setup(&m);
  path_table_setup(&tr, &r, 0);
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  for (n = 0; n < 300; n++) {
    double t = rnd_uniform(&seed, 2 * h, 4.0 - 2 * h);
    double q[3], dq[3], ddq[3], qp[3], dqp[3], qm[3], dqm[3], dd[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, t, q, dq, ddq), RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, t + h, qp, dqp, dd), RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, t - h, qm, dqm, dd), RPS3_OK);
    for (k = 0; k < 3; k++) {
      CHECK_REL(dq[k], (qp[k] - qm[k]) / (2 * h), TOL_FD, 0.1,
                "rate %d at t = %g", k, t);
      CHECK_REL(ddq[k], (dqp[k] - dqm[k]) / (2 * h), TOL_FD, 0.1,
                "acceleration %d at t = %g", k, t);
    }
  }
}

static void path_table_refusals(void **state) {
  rps3_model m;
  rps3_traj tr;
  path_rows r;
  (void)state;
  model_setup(&m);
  /* no polar angles */
  path_table_setup(&tr, &r, 2);
  tr.path.table_psi = NULL;
  REFUSED(tr, RPS3_F_PATH_TABLE_VALUE, 0);
  /* a row on the axis, a row beyond r/2 */
  path_table_setup(&tr, &r, 2);
  r.c[17][0] = r.c[17][1] = 0.0;
  REFUSED(tr, RPS3_F_PATH_TABLE_VALUE, 17);
  path_table_setup(&tr, &r, 2);
  r.c[23][0] = 0.06;
  REFUSED(tr, RPS3_F_PATH_TABLE_VALUE, 23);
  /* rows too far apart to follow the turn about the axis */
  path_table_setup(&tr, &r, 2);
  r.psi[30] += 2.0;
  REFUSED(tr, RPS3_F_PATH_TABLE_VALUE, 30);
  /* times, NaN: as any table, with the path's field ids */
  path_table_setup(&tr, &r, 2);
  r.time[9] = r.time[8];
  REFUSED(tr, RPS3_F_PATH_TABLE_TIME, 9);
  path_table_setup(&tr, &r, 2);
  r.ddc[12][1] = (double)NAN;
  REFUSED(tr, RPS3_F_PATH_TABLE_ACC, 12);
  /* rows inside the workspace, but a rate that throws the centre out
     between rows 40 and 41: the first bad time is after row 40 */
  path_table_setup(&tr, &r, 2);
  r.dc[40][0] = 3.0;
  REFUSED(tr, RPS3_F_PATH_TABLE_VALUE, 40);
  assert_int_equal(rps3_table_unwrap(3, NULL, r.psi), RPS3_EINVAL);
  r.c[2][0] = (double)INFINITY;
  assert_int_equal(rps3_table_unwrap(NPATH, (const double(*)[3])r.c, r.psi),
                   RPS3_EINVAL);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(exact_for_polynomials),
      cmocka_unit_test(derivatives_fd),
      cmocka_unit_test(spline_continuity),
      cmocka_unit_test(spline_convergence),
      cmocka_unit_test(refusals),
      cmocka_unit_test(path_table_is_the_circle),
      cmocka_unit_test(path_table_derivatives),
      cmocka_unit_test(path_table_refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
