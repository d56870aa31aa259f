/* test_traj_kinds.c - waypoints and Cartesian paths: exact first and second
   derivatives against central differences, the waypoints hit, limits that
   stretch the timing, the paper's helix as a path, and every refusal
   naming its field. */
#include <stdlib.h>

#include "testutil.h"

static void model_setup(rps3_model *m) {
  rps3_model_default(m);
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

/* the corners where a law's acceleration jumps: every sample within 4 h
   of one is skipped by the difference check */
static int near_any(double t, const double *c, int nc, double h) {
  int i;
  for (i = 0; i < nc; i++)
    if (fabs(t - c[i]) < 4 * h) return 1;
  return 0;
}

/* dq, ddq at random t against central differences of q and dq.  Tolerance
   TOL_FD (testutil.h) relative to max(|value|, scale). */
static void check_fd(const rps3_model *m, const rps3_traj *tr,
                     const double *corners, int nc, double scale[3],
                     uint64_t seed) {
  /* h = 2e-6 T: truncation h^2 q'''' / 6 stays below 1e-8 of the values
     on the short, brisk segments and near-axis paths used here, rounding
     eps |q'| / h below 1e-10 */
  double T = rps3_traj_duration(tr), h = 2e-6 * T;
  int n, k, done = 0;
  for (n = 0; n < 400; n++) {
    double t = rnd_uniform(&seed, 2 * h, T - 2 * h);
    double q[3], dq[3], ddq[3], qp[3], dqp[3], qm[3], dqm[3], dd[3];
    if (near_any(t, corners, nc, h)) continue;
    assert_int_equal(rps3_traj_eval(m, tr, t, q, dq, ddq), RPS3_OK);
    assert_int_equal(rps3_traj_eval(m, tr, t + h, qp, dqp, dd), RPS3_OK);
    assert_int_equal(rps3_traj_eval(m, tr, t - h, qm, dqm, dd), RPS3_OK);
    for (k = 0; k < 3; k++) {
      CHECK_REL(dq[k], (qp[k] - qm[k]) / (2 * h), TOL_FD, scale[k],
                "rate %d at t = %g", k, t);
      CHECK_REL(ddq[k], (dqp[k] - dqm[k]) / (2 * h), TOL_FD, scale[k],
                "acceleration %d at t = %g", k, t);
    }
    done++;
  }
  assert_true(done > 300); /* the corners cannot hide the check */
}

static const double wp_time[4] = {0.0, 1.0, 2.5, 3.0};
static const double wp_pose[4][3] = {{0.3, 0.05, 0.30},
                                     {0.1, 0.12, 0.32},
                                     {-0.2, 0.08, 0.28},
                                     {-0.4, 0.02, 0.31}};

static void wp_setup(rps3_traj *tr, rps3_time_law law) {
  rps3_traj_default(tr);
  tr->kind = RPS3_TRAJ_WAYPOINTS;
  tr->wp.n = 4;
  tr->wp.time = wp_time;
  tr->wp.pose = wp_pose;
  tr->wp.law = law;
  tr->wp.blend = 0.2;
}

/* segment starts and, for LSPB, the blend corners of each segment (with
   the timing the library reports, so that stretched runs are covered) */
static int wp_corners(const rps3_traj *tr, double *c) {
  int nc = 0;
  size_t i;
  double t0 = 0, tend = rps3_traj_duration(tr);
  double scale = tend / wp_time[3];
  for (i = 0; i < 4; i++) c[nc++] = wp_time[i] * scale;
  /* with limits the stretch is per segment: add generous corners from the
     reported span only when there are no limits */
  for (i = 0; i + 1 < 4 && tr->wp.law == RPS3_LAW_LSPB; i++) {
    double T = wp_time[i + 1] - wp_time[i];
    c[nc++] = t0 + tr->wp.blend * T;
    c[nc++] = t0 + (1 - tr->wp.blend) * T;
    t0 += T;
  }
  return nc;
}

static void waypoints_derivatives(void **state) {
  rps3_model m;
  rps3_traj tr;
  double c[16], scale[3] = {0.5, 0.5, 0.05};
  int law;
  (void)state;
  model_setup(&m);
  for (law = 0; law < 3; law++) {
    wp_setup(&tr, (rps3_time_law)law);
    assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
    CHECK_REL(rps3_traj_duration(&tr), 3.0, 0.0, 1.0, "span = last time");
    check_fd(&m, &tr, c, wp_corners(&tr, c), scale, 7 + (uint64_t)law);
  }
}

/* the poses are reached at their times; rest at the ends; the quintic has
   the heuristic rate at an inner waypoint and is continuous there */
static void waypoints_hit(void **state) {
  rps3_model m;
  rps3_traj tr;
  double q[3], dq[3], ddq[3], qa[3], dqa[3], ddqa[3];
  int law, i, k;
  (void)state;
  model_setup(&m);
  for (law = 0; law < 3; law++) {
    wp_setup(&tr, (rps3_time_law)law);
    for (i = 0; i < 4; i++) {
      assert_int_equal(rps3_traj_eval(&m, &tr, wp_time[i], q, dq, ddq), 0);
      for (k = 0; k < 3; k++)
        CHECK_REL(q[k], wp_pose[i][k], 1e-15, 1.0, "pose %d at t_%d", k, i);
      if (law != RPS3_LAW_QUINTIC || i == 0 || i == 3)
        for (k = 0; k < 3; k++)
          CHECK_REL(dq[k], 0.0, 1.0, 1e-13, "at rest at waypoint %d", i);
    }
  }
  /* quintic, inner waypoint 1, alpha: slopes -0.2/1 and -0.3/1.5 agree in
     sign: rate -0.2; beta: slopes disagree: rate 0 */
  wp_setup(&tr, RPS3_LAW_QUINTIC);
  assert_int_equal(rps3_traj_eval(&m, &tr, 1.0, q, dq, ddq), 0);
  CHECK_REL(dq[0], -0.2, 1e-14, 1.0, "heuristic rate");
  CHECK_REL(dq[1], 0.0, 1.0, 1e-13, "rate 0 at a turn");
  CHECK_REL(ddq[0], 0.0, 1.0, 1e-12, "acceleration 0 at a waypoint");
  assert_int_equal(rps3_traj_eval(&m, &tr, 1.0 - 1e-12, qa, dqa, ddqa), 0);
  for (k = 0; k < 3; k++) {
    CHECK_REL(dqa[k], dq[k], 1e-9, 1.0, "rate continuous");
    CHECK_REL(ddqa[k], ddq[k], 1e-9, 1.0, "acceleration continuous");
  }
}

/* limits stretch each segment to the least duration that keeps every
   coordinate within them: the bound holds and is reached */
static void waypoints_limits(void **state) {
  rps3_model m;
  rps3_traj tr;
  int law, k, n;
  (void)state;
  model_setup(&m);
  for (law = 0; law < 2; law++) {
    double peak_v[3] = {0, 0, 0}, peak_a[3] = {0, 0, 0}, T;
    wp_setup(&tr, (rps3_time_law)law);
    tr.wp.vmax[0] = 0.1;  /* rad/s: stretches every alpha segment */
    tr.wp.amax[2] = 0.05; /* m/s^2 */
    assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
    T = rps3_traj_duration(&tr);
    assert_true(T > 3.0);
    for (n = 0; n <= 200000; n++) {
      double q[3], dq[3], ddq[3];
      assert_int_equal(rps3_traj_eval(&m, &tr, T * n / 200000.0, q, dq, ddq),
                       0);
      for (k = 0; k < 3; k++) {
        if (fabs(dq[k]) > peak_v[k]) peak_v[k] = fabs(dq[k]);
        if (fabs(ddq[k]) > peak_a[k]) peak_a[k] = fabs(ddq[k]);
      }
    }
    /* never above (rounding only), and reached to the sampling's
       resolution: the peak of a segment lies between samples */
    assert_true(peak_v[0] <= 0.1 * (1 + 1e-12));
    assert_true(peak_v[0] >= 0.1 * (1 - 1e-6));
    assert_true(peak_a[2] <= 0.05 * (1 + 1e-12));
    /* the last point is reached at the stretched end */
    {
      double q[3];
      assert_int_equal(rps3_traj_eval(&m, &tr, T, q, NULL, NULL), 0);
      for (k = 0; k < 3; k++) CHECK_REL(q[k], wp_pose[3][k], 1e-15, 1.0, "end");
    }
  }
}

static void path_setup(rps3_traj *tr, rps3_path_shape shape) {
  rps3_traj_default(tr);
  tr->kind = RPS3_TRAJ_PATH;
  tr->path.shape = shape;
  tr->path.law = RPS3_LAW_MINJERK;
  tr->path.duration = 4.0;
  tr->path.start[0] = 0.01;
  tr->path.start[1] = -0.02;
  tr->path.start[2] = 0.30;
  tr->path.end[0] = 0.03;
  tr->path.end[1] = 0.025;
  tr->path.end[2] = 0.33;
  tr->path.centre[0] = 0.0;
  tr->path.centre[1] = 0.0;
  tr->path.centre[2] = 0.3;
  tr->path.radius = 0.02;
  tr->path.angle0 = 0.7;
  tr->path.turns = -1.25;
  tr->path.pitch = 0.02;
}

static void path_derivatives(void **state) {
  rps3_model m;
  rps3_traj tr;
  double scale[3] = {1.0, 0.2, 0.01}, c[2] = {0.4, 3.6};
  int shape, off;
  (void)state;
  model_setup(&m);
  for (shape = 0; shape < 3; shape++)
    for (off = 0; off < 3; off++) {
      path_setup(&tr, (rps3_path_shape)shape);
      if (off) {
        /* a circle that winds about the axis off-centre, or one that does
           not wind about it at all; LSPB */
        tr.path.centre[0] = shape == RPS3_PATH_CIRCLE ? 0.012 : 0.005;
        tr.path.centre[1] = shape == RPS3_PATH_CIRCLE ? 0.008 : -0.004;
        tr.path.law = RPS3_LAW_LSPB;
        tr.path.blend = 0.1;
      }
      if (off == 2) {
        /* a circle beside the axis: psi swings and comes back */
        tr.path.centre[0] = 0.03;
        tr.path.centre[1] = 0.01;
        tr.path.radius = 0.01;
      }
      assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
      check_fd(&m, &tr, c, off ? 2 : 0, scale, 100 + (uint64_t)(shape * 3 + off));
    }
}

/* the centre the pose puts through (3)-(4) is the path's point */
static void path_traced(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_data *d;
  int shape, n;
  (void)state;
  model_setup(&m);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (shape = 0; shape < 3; shape++) {
    path_setup(&tr, (rps3_path_shape)shape);
    tr.path.centre[0] = 0.004;
    for (n = 0; n <= 100; n++) {
      double t = 4.0 * n / 100.0, s, want[3], tau = t / 4.0, phi;
      assert_int_equal(
          rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose), 0);
      assert_int_equal(rps3_ik(&m, d), RPS3_OK);
      s = tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);
      if (shape == RPS3_PATH_LINE) {
        int k;
        for (k = 0; k < 3; k++)
          want[k] = tr.path.start[k] + s * (tr.path.end[k] - tr.path.start[k]);
      } else {
        phi = 0.7 + 2 * PI * -1.25 * s;
        want[0] = 0.004 + 0.02 * cos(phi);
        want[1] = 0.02 * sin(phi);
        want[2] = 0.3 + (shape == RPS3_PATH_HELIX ? 0.02 * -1.25 * tau : 0.0);
      }
      CHECK_REL(d->c[0], want[0], 1e-12, 0.01, "x_c, shape %d, t %g", shape, t);
      CHECK_REL(d->c[1], want[1], 1e-12, 0.01, "y_c, shape %d, t %g", shape, t);
      CHECK_REL(d->c[2], want[2], 1e-14, 0.3, "z_c, shape %d, t %g", shape, t);
    }
  }
  rps3_data_free(d);
}

/* the paper's helix as a path is the helix: pose, rate and acceleration
   at every sample of Table II's grid and at the corners */
static void helix_as_path(void **state) {
  rps3_model m;
  rps3_traj h, p;
  int n, k;
  (void)state;
  model_setup(&m);
  rps3_traj_default(&h);
  rps3_traj_default(&p);
  p.kind = RPS3_TRAJ_PATH; /* the default path is Table II's helix */
  assert_int_equal(rps3_traj_check(&m, &p, NULL), RPS3_OK);
  CHECK_REL(rps3_traj_duration(&p), rps3_traj_duration(&h), 0.0, 1.0, "T*");
  for (n = 0; n <= 1000; n++) {
    double t = 10.0 * n / 1000.0, a[3], da[3], dda[3], b[3], db[3], ddb[3];
    assert_int_equal(rps3_traj_eval(&m, &h, t, a, da, dda), 0);
    assert_int_equal(rps3_traj_eval(&m, &p, t, b, db, ddb), 0);
    /* 1e-12: the two compute phi through different roundings (rate
       2 pi / (T - t_a) against 2 pi s(t/T) with s' = 1/(1 - f)) */
    for (k = 0; k < 3; k++) {
      CHECK_REL(b[k], a[k], 1e-12, 1.0, "pose %d at t = %g", k, t);
      CHECK_REL(db[k], da[k], 1e-12, 1.0, "rate %d at t = %g", k, t);
      CHECK_REL(ddb[k], dda[k], 1e-12, 1.0, "acceleration %d at t = %g", k, t);
    }
  }
}

/* trajectory tr is refused for model m, naming field id_ (component or
   row comp_): TRAJ_REFUSED in testutil.h */
#define REFUSED(tr_, id_, comp_) TRAJ_REFUSED(m, tr_, id_, comp_)

static void refusals(void **state) {
  rps3_model m;
  rps3_traj tr;
  double t_bad[4] = {0.0, 1.0, 1.0, 3.0}, t_late[4] = {0.5, 1.0, 2.0, 3.0};
  double p_bad[4][3];
  rps3_check chk;
  (void)state;
  model_setup(&m);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.time = t_bad;
  REFUSED(tr, RPS3_F_WP_TIME, 2); /* not strictly increasing, row 2 */
  tr.wp.time = t_late;
  REFUSED(tr, RPS3_F_WP_TIME, 0);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.n = 1;
  REFUSED(tr, RPS3_F_WP_POSE, 0);
  wp_setup(&tr, RPS3_LAW_LSPB);
  memcpy(p_bad, wp_pose, sizeof p_bad);
  p_bad[2][2] = -0.1; /* below the base */
  tr.wp.pose = (const double(*)[3])p_bad;
  REFUSED(tr, RPS3_F_WP_POSE, 2);
  p_bad[2][2] = (double)NAN;
  REFUSED(tr, RPS3_F_WP_POSE, 2);
  wp_setup(&tr, RPS3_LAW_QUINTIC);
  tr.wp.vmax[1] = 1.0;
  REFUSED(tr, RPS3_F_WP_VMAX, 1);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.blend = 0.6;
  REFUSED(tr, RPS3_F_WP_BLEND, 0);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.law = (rps3_time_law)3;
  REFUSED(tr, RPS3_F_WP_LAW, 0);

  /* a line through the axis, a circle through it, a zero radius */
  path_setup(&tr, RPS3_PATH_LINE);
  tr.path.start[0] = -0.01;
  tr.path.start[1] = -0.01;
  tr.path.end[0] = 0.02;
  tr.path.end[1] = 0.02;
  REFUSED(tr, RPS3_F_PATH_START, 0);
  path_setup(&tr, RPS3_PATH_CIRCLE);
  tr.path.centre[0] = 0.02;
  REFUSED(tr, RPS3_F_PATH_RADIUS, 0);
  path_setup(&tr, RPS3_PATH_HELIX);
  tr.path.radius = 0.0;
  REFUSED(tr, RPS3_F_PATH_RADIUS, 0);
  path_setup(&tr, RPS3_PATH_HELIX);
  tr.path.turns = 0.0;
  REFUSED(tr, RPS3_F_PATH_TURNS, 0);
  path_setup(&tr, RPS3_PATH_HELIX);
  tr.path.duration = 0.0;
  REFUSED(tr, RPS3_F_PATH_DURATION, 0);

  /* a line leaving rho < r/2: the first bad time is named, to the
     bisection's resolution; here the crossing is where
     hypot(x, 0.01) = r/2 with x = 0.01 + 0.09 s(t/4), s minimum jerk */
  path_setup(&tr, RPS3_PATH_LINE);
  tr.path.start[0] = 0.01;
  tr.path.start[1] = 0.01;
  tr.path.end[0] = 0.10;
  tr.path.end[1] = 0.01;
  tr.path.end[2] = 0.30;
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_PATH_END);
  {
    double xs = sqrt(0.25 * m.r * m.r - 1e-4), sw = (xs - 0.01) / 0.09;
    double lo = 0, hi = 1, t_want, t_got;
    const char *at = strstr(chk.msg, "at t = ");
    int it;
    for (it = 0; it < 200; it++) {
      double mid = 0.5 * (lo + hi);
      if (mid * mid * mid * (10 - 15 * mid + 6 * mid * mid) < sw) lo = mid;
      else hi = mid;
    }
    t_want = 4.0 * hi;
    assert_non_null(at);
    t_got = strtod(at + 7, NULL);
    CHECK_REL(t_got, t_want, 1e-8, 1.0, "first bad time: %s", chk.msg);
  }
}

/* 1 when the run's own arithmetic fails somewhere on a dense grid of the
   span: the trajectory, or the inverse dynamics (rates included), not OK
   or not finite at a sample.  The oracle that a refusal of
   overflow_refusals is one the run would meet, computed without
   rps3_traj_check */
static int run_would_fail(const rps3_model *m, const rps3_traj *tr) {
  rps3_model mc = *m;
  rps3_data *d;
  double T = rps3_traj_duration(tr);
  int i, bad = 0;
  mc.opt.effects |= RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA;
  mc.opt.outputs |= RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(&mc, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&mc, &d), RPS3_OK);
  for (i = 0; i <= 4096 && !bad; i++) {
    double t = T * ((double)i / 4096.0);
    int st = rps3_traj_eval(&mc, tr, t, d->pose, d->dpose, d->ddpose);
    if (st == RPS3_OK) st = rps3_inverse(&mc, d);
    bad = st == RPS3_ERANGE || (st == RPS3_OK && !(isfinite(d->F[0]) && isfinite(d->F[1]) && isfinite(d->F[2]))) ||
          st == RPS3_EINVAL;
  }
  rps3_data_free(d);
  return bad;
}

/* the refusal names its field and says no "nan" of its own making */
#define OVERFLOW_REFUSED(tr_, id_, comp_, oracle_)                            \
  do {                                                                        \
    rps3_check c_;                                                            \
    REFUSED(tr_, id_, comp_);                                                 \
    rps3_traj_check(&m, &(tr_), &c_);                                      \
    if ((oracle_) && !run_would_fail(&m, &(tr_)))                             \
      fail_msg("refused, but the run's arithmetic holds: %s", c_.msg);        \
  } while (0)

/*
 * Every kind refuses, by its field, parameters whose motion overflows
 * (rates whose squares, or accelerations, are not finite; dynamics that
 * overflow) or whose span is not in (0, RPS3_TRAJ_SPAN_MAX], where the
 * run would fail at every sample; each such refusal (but the span's,
 * which is a bound of the runner's arithmetic) is checked against the
 * run's own arithmetic on a grid, and the same kinds with sane
 * parameters near them pass.
 */
static void overflow_refusals(void **state) {
  rps3_model m;
  rps3_traj tr;
  double t_short[4] = {0.0, 1e-300, 2.5, 3.0};
  double t_tbl[4] = {0.0, 1e-300, 1.0, 3.0};
  double v_tbl[4][3], r_tbl[4][3], psi[4];
  int i, k;
  (void)state;
  model_setup(&m);

  /* helix: a period of 1e-300 s (its blend 4e-301 s) */
  rps3_traj_default(&tr);
  tr.helix.period = 1e-300;
  tr.helix.blend = 4e-301;
  OVERFLOW_REFUSED(tr, RPS3_F_HELIX_PERIOD, 0, 1);
  tr.helix.period = 1e-3; /* fast, not absurd */
  tr.helix.blend = 4e-4;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);

  /* sine: a span past the bound, rates that overflow the dynamics */
  rps3_traj_default(&tr);
  tr.kind = RPS3_TRAJ_SINE;
  tr.sine.mean[1] = 0.1;
  tr.sine.mean[2] = 0.3;
  tr.sine.amp[0] = 0.1;
  tr.sine.freq[0] = 1.0;
  tr.sine.duration = 1e13;
  OVERFLOW_REFUSED(tr, RPS3_F_SINE_DURATION, 0, 0);
  tr.sine.duration = 1.0;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  tr.sine.freq[0] = 1e150;
  REFUSED(tr, RPS3_F_SINE_FREQ, 0);
  {
    /* amp w^2 overflows where (amp w)^2 does not (amp 0.1 < 1): the
       closed form names the cause, not a sample of the scan */
    rps3_check c;
    tr.sine.freq[0] = 8e153;
    REFUSED(tr, RPS3_F_SINE_FREQ, 0);
    rps3_traj_check(&m, &tr, &c);
    assert_non_null(strstr(c.msg, "the rates overflow"));
  }

  /* waypoints: a limit that stretches the span past the bound, by the
     limit; a segment of 1e-300 s, by its time, for each law */
  wp_setup(&tr, RPS3_LAW_MINJERK);
  tr.wp.vmax[0] = 3e-308;
  OVERFLOW_REFUSED(tr, RPS3_F_WP_VMAX, 0, 0);
  /* segments each within the bound (0.6e12 and 0.9e12 s) whose sum is
     past it: by the limit too */
  tr.wp.vmax[0] = 6.25e-13;
  REFUSED(tr, RPS3_F_WP_VMAX, 0);
  tr.wp.vmax[0] = 0.0;
  tr.wp.amax[2] = 1e-300;
  OVERFLOW_REFUSED(tr, RPS3_F_WP_AMAX, 2, 0);
  tr.wp.amax[2] = 1e-3; /* a slow, sane stretch */
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  for (k = 0; k < 3; k++) {
    wp_setup(&tr, (rps3_time_law)k);
    tr.wp.time = t_short;
    OVERFLOW_REFUSED(tr, RPS3_F_WP_TIME, 1, 1);
  }

  /* path: turns 1e300 (rates overflow) and 1e150 (the dynamics do), a
     line lasting 1e-300 s, a helix 1e-200 s */
  path_setup(&tr, RPS3_PATH_CIRCLE);
  tr.path.centre[0] = 0.01;
  tr.path.radius = 0.03;
  tr.path.turns = 1e300;
  OVERFLOW_REFUSED(tr, RPS3_F_PATH_TURNS, 0, 1);
  tr.path.turns = 1e150;
  OVERFLOW_REFUSED(tr, RPS3_F_PATH_TURNS, 0, 1);
  tr.path.turns = 1e3;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  path_setup(&tr, RPS3_PATH_LINE);
  tr.path.duration = 1e-300;
  OVERFLOW_REFUSED(tr, RPS3_F_PATH_DURATION, 0, 1);
  path_setup(&tr, RPS3_PATH_HELIX);
  tr.path.turns = 1.0;
  tr.path.duration = 1e-200;
  OVERFLOW_REFUSED(tr, RPS3_F_PATH_DURATION, 0, 1);

  /* tables: two rows 1e-300 s apart, of the pose and of a path */
  for (i = 0; i < 4; i++) {
    double a = 0.3 - 0.1 * i;
    v_tbl[i][0] = a;
    v_tbl[i][1] = 0.08;
    v_tbl[i][2] = 0.3;
    r_tbl[i][0] = r_tbl[i][1] = r_tbl[i][2] = 0.0;
  }
  rps3_traj_default(&tr);
  tr.kind = RPS3_TRAJ_TABLE;
  tr.table.n = 4;
  tr.table.time = t_tbl;
  tr.table.value = (const double(*)[3])v_tbl;
  tr.table.rate = (const double(*)[3])r_tbl;
  OVERFLOW_REFUSED(tr, RPS3_F_TABLE_TIME, 1, 1);
  {
    /* two equal rows at rest 1e-170 s apart: finite rates and values,
       but h^2 underflows and the interpolant's acceleration there is
       0 / 0: refused by the rows' value, not taken for a slow motion */
    double t_eq[4] = {0.0, 1e-170, 1.0, 3.0}, v_eq[4][3];
    for (i = 0; i < 4; i++)
      for (k = 0; k < 3; k++) v_eq[i][k] = v_tbl[i == 0 ? 1 : i][k];
    tr.table.time = t_eq;
    tr.table.value = (const double(*)[3])v_eq;
    REFUSED(tr, RPS3_F_TABLE_VALUE, 0);
    tr.table.value = (const double(*)[3])v_tbl;
  }
  tr.table.time = wp_time;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  for (i = 0; i < 4; i++) {
    v_tbl[i][0] = 0.02 * cos(0.3 * i);
    v_tbl[i][1] = 0.02 * sin(0.3 * i);
  }
  assert_int_equal(rps3_table_unwrap(4, (const double(*)[3])v_tbl, psi),
                   RPS3_OK);
  path_setup(&tr, RPS3_PATH_TABLE);
  tr.path.table.n = 4;
  tr.path.table.time = t_tbl;
  tr.path.table.value = (const double(*)[3])v_tbl;
  tr.path.table.rate = (const double(*)[3])r_tbl;
  tr.path.table_psi = psi;
  OVERFLOW_REFUSED(tr, RPS3_F_PATH_TABLE_TIME, 1, 1);
  tr.path.table.time = wp_time;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
}

/*
 * rps3_traj_eval's argument errors, on trajectories that never passed
 * rps3_traj_check: RPS3_EINVAL (as rps3.h promises) before the span is
 * looked at, for missing arrays, a law or shape out of range, an unknown
 * kind; the outputs are NaN, never what the caller's arrays held.
 */
static void eval_argument_errors(void **state) {
  rps3_model m;
  rps3_traj tr;
  double q[3] = {7, 7, 7}, dq[3] = {7, 7, 7}, ddq[3] = {7, 7, 7};
  int k;
  (void)state;
  model_setup(&m);
#define EVAL_EINVAL(t_)                                                       \
  do {                                                                        \
    q[0] = dq[1] = ddq[2] = 7.0;                                              \
    assert_int_equal(rps3_traj_eval(&m, &tr, (t_), q, dq, ddq), RPS3_EINVAL); \
    for (k = 0; k < 3; k++)                                                   \
      assert_true(isnan(q[k]) && isnan(dq[k]) && isnan(ddq[k]));             \
  } while (0)
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.time = NULL;
  EVAL_EINVAL(0.5);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.pose = NULL;
  EVAL_EINVAL(0.5);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.law = (rps3_time_law)7;
  EVAL_EINVAL(0.5);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.law = (rps3_time_law)-1;
  EVAL_EINVAL(0.5);
  wp_setup(&tr, RPS3_LAW_LSPB);
  tr.wp.blend = 0.7; /* blends that overlap: no motion from 0 to 1 */
  EVAL_EINVAL(0.5);
  tr.wp.blend = 0.0;
  EVAL_EINVAL(0.5);
  rps3_traj_default(&tr);
  tr.helix.blend = 6.0; /* past T* / 2 */
  EVAL_EINVAL(0.5);
  tr.helix.blend = 1.0;
  tr.helix.period = -10.0;
  EVAL_EINVAL(0.0);
  path_setup(&tr, RPS3_PATH_CIRCLE);
  tr.path.shape = (rps3_path_shape)9;
  EVAL_EINVAL(1.0);
  path_setup(&tr, RPS3_PATH_CIRCLE);
  tr.path.law = RPS3_LAW_LSPB;
  tr.path.blend = 0.9;
  EVAL_EINVAL(1.0);
  path_setup(&tr, RPS3_PATH_LINE);
  tr.path.law = (rps3_time_law)5;
  EVAL_EINVAL(1.0);
  path_setup(&tr, RPS3_PATH_TABLE); /* no rows */
  EVAL_EINVAL(0.0);
  rps3_traj_default(&tr);
  tr.kind = RPS3_TRAJ_TABLE;
  EVAL_EINVAL(0.0);
  tr.kind = (rps3_traj_kind)0;
  EVAL_EINVAL(0.0);
  /* a valid one outside its span: EDOMAIN, NaN out */
  wp_setup(&tr, RPS3_LAW_LSPB);
  assert_int_equal(rps3_traj_eval(&m, &tr, 3.5, q, dq, ddq), RPS3_EDOMAIN);
  assert_true(isnan(q[0]) && isnan(dq[0]) && isnan(ddq[0]));
  assert_int_equal(rps3_traj_eval(&m, &tr, 1.5, q, dq, ddq), RPS3_OK);
#undef EVAL_EINVAL
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(waypoints_derivatives),
      cmocka_unit_test(waypoints_hit),
      cmocka_unit_test(waypoints_limits),
      cmocka_unit_test(path_derivatives),
      cmocka_unit_test(path_traced),
      cmocka_unit_test(helix_as_path),
      cmocka_unit_test(refusals),
      cmocka_unit_test(overflow_refusals),
      cmocka_unit_test(eval_argument_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
