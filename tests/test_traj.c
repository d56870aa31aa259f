/* test_traj.c - the paper's helix (Tables I-II, (35)-(38) with the errata)
   and the sinusoid: exact derivatives, blend corners, the helix traced. */
#include "testutil.h"

static void setup(rps3_model *m, rps3_traj *tr) {
  rps3_model_default(m);
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
  rps3_traj_default(tr);
  assert_int_equal(rps3_traj_check(m, tr, NULL), RPS3_OK);
}

/* Table II: phi(T*) = 2 pi, peak rate 2 pi / 9 rad/s, beta ~ 5.5 degrees */
static void table_ii(void **state) {
  rps3_model m;
  rps3_traj tr;
  double q[3], dq[3], ddq[3];
  (void)state;
  setup(&m, &tr);
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.0, q, dq, ddq), RPS3_OK);
  CHECK_REL(q[0], PI / 2, 1e-15, 0.0, "alpha(0) = pi/2");
  CHECK_REL(q[2], 0.3048, 1e-15, 0.0, "z_i");
  CHECK_REL(dq[2], 0.03048 / 10.0, 1e-15, 0.0, "z rate h/T*");
  /* cos beta = 1 - 2 r* / r (errata of (37)) */
  CHECK_REL(cos(q[1]), 1.0 - 2.0 * 0.266e-3 / m.r, 1e-14, 0.0, "(37)");
  CHECK_REL(q[1] * 180 / PI, 5.53, 2e-3, 0.0, "beta in degrees");
  assert_int_equal(rps3_traj_eval(&m, &tr, 5.0, q, dq, ddq), RPS3_OK);
  CHECK_REL(dq[0], -0.5 * 2 * PI / 9, 1e-15, 0.0, "peak alpha rate (38)");
  assert_int_equal(rps3_traj_eval(&m, &tr, 10.0, q, dq, ddq), RPS3_OK);
  CHECK_REL(q[0], PI / 2 - PI, 1e-14, 1.0, "alpha(T*): phi = 2 pi");
  CHECK_REL(dq[0], 0.0, 0.0, 1.0, "at rest at T*");
}

/* the platform centre traces the helix (35): x = r* cos phi, y = r* sin phi */
static void centre_traces_helix(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_data *d;
  int k;
  (void)state;
  setup(&m, &tr);
  tr.helix.radius = 0.0217; /* a wide helix shows phase errors */
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (k = 0; k <= 100; k++) {
    double t = 0.1 * k, phi;
    assert_int_equal(rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose), 0);
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    phi = PI - 2.0 * d->pose[0]; /* (36), n = 1 */
    CHECK_REL(d->c[0], 0.0217 * cos(phi), 1e-12, 0.0217, "x_c = r* cos phi");
    CHECK_REL(d->c[1], 0.0217 * sin(phi), 1e-12, 0.0217, "y_c = r* sin phi");
  }
  rps3_data_free(d);
}

/* rates and accelerations are the derivatives, away from the corners */
static void derivatives_exact(void **state) {
  rps3_model m;
  rps3_traj tr[2];
  uint64_t seed = 31;
  const double h = 1e-5;
  int n, k, i;
  (void)state;
  setup(&m, &tr[0]);
  traj_random(&tr[1], &seed);
  for (n = 0; n < 2; n++)
    for (k = 1; k < 40; k++) {
      double T = rps3_traj_duration(&tr[n]), t = T * (k + 0.37) / 41.0;
      double q0[3], q1[3], dq[3], ddq[3], d0[3], d1[3];
      if (n == 0 && (fabs(t - 1.0) < 2 * h || fabs(t - 9.0) < 2 * h)) continue;
      assert_int_equal(rps3_traj_eval(&m, &tr[n], t, NULL, dq, ddq), 0);
      assert_int_equal(rps3_traj_eval(&m, &tr[n], t - h, q0, d0, NULL), 0);
      assert_int_equal(rps3_traj_eval(&m, &tr[n], t + h, q1, d1, NULL), 0);
      for (i = 0; i < 3; i++) {
        CHECK_REL(dq[i], (q1[i] - q0[i]) / (2 * h), TOL_FD, 1.0, "rate %d", i);
        CHECK_REL(ddq[i], (d1[i] - d0[i]) / (2 * h), TOL_FD, 1.0, "accel %d", i);
      }
    }
}

/* at a blend corner the sample takes the segment that starts there */
static void blend_corners(void **state) {
  rps3_model m;
  rps3_traj tr;
  double ddq[3], dq[3], q[3], acc = (2 * PI / 9) / 1.0;
  (void)state;
  setup(&m, &tr);
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.0, q, dq, ddq), 0);
  CHECK_REL(ddq[0], -0.5 * acc, 1e-15, 0.0, "t = 0: accelerating");
  assert_int_equal(rps3_traj_eval(&m, &tr, 1.0, q, dq, ddq), 0);
  CHECK_REL(ddq[0], 0.0, 0.0, 1.0, "t = t_a: cruise");
  CHECK_REL(dq[0], -0.5 * 2 * PI / 9, 1e-15, 0.0, "rate continuous at t_a");
  assert_int_equal(rps3_traj_eval(&m, &tr, 9.0, q, dq, ddq), 0);
  CHECK_REL(ddq[0], 0.5 * acc, 1e-15, 0.0, "t = t_b: decelerating");
  assert_int_equal(rps3_traj_eval(&m, &tr, 10.0, q, dq, ddq), 0);
  CHECK_REL(ddq[0], 0.5 * acc, 1e-15, 0.0, "t = T*: left limit");
  /* positions continuous across the corners */
  {
    double a[3], b[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, 1.0 - 1e-12, a, NULL, NULL), 0);
    assert_int_equal(rps3_traj_eval(&m, &tr, 1.0, b, NULL, NULL), 0);
    CHECK_REL(a[0], b[0], 1e-11, 1.0, "alpha continuous at t_a");
    assert_int_equal(rps3_traj_eval(&m, &tr, 9.0 - 1e-12, a, NULL, NULL), 0);
    assert_int_equal(rps3_traj_eval(&m, &tr, 9.0, b, NULL, NULL), 0);
    CHECK_REL(a[0], b[0], 1e-11, 1.0, "alpha continuous at t_b");
  }
}

static void errors(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_check chk;
  double q[3];
  (void)state;
  setup(&m, &tr);
  assert_int_equal(rps3_traj_eval(&m, &tr, -1e-9, q, NULL, NULL), RPS3_EDOMAIN);
  assert_int_equal(rps3_traj_eval(&m, &tr, 10.001, q, NULL, NULL), RPS3_EDOMAIN);
  assert_int_equal(rps3_traj_eval(&m, &tr, (double)NAN, q, NULL, NULL), RPS3_EINVAL);
  assert_int_equal(rps3_traj_eval(&m, NULL, 1.0, q, NULL, NULL), RPS3_EINVAL);
  tr.helix.radius = 0.06; /* r/2 = 0.05715: beta would pass 90 degrees */
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "trajectory.radius"));
  assert_int_equal(chk.field, RPS3_F_HELIX_RADIUS);
  rps3_traj_default(&tr);
  tr.helix.blend = 6.0;
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "trajectory.blend"));
  assert_int_equal(chk.field, RPS3_F_HELIX_BLEND);
  rps3_traj_default(&tr);
  tr.helix.period = 0.0;
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "trajectory.period"));
  assert_int_equal(chk.field, RPS3_F_HELIX_PERIOD);
  rps3_traj_default(&tr);
  tr.helix.z0 = -0.1;
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  tr.kind = RPS3_TRAJ_SINE;
  tr.sine.duration = 1.0;
  tr.sine.freq[1] = -2.0;
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "trajectory.freq[1]"));
  assert_int_equal(chk.field, RPS3_F_SINE_FREQ);
  assert_int_equal(chk.comp, 1);
  tr.kind = (rps3_traj_kind)9;
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_KIND);
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.0, q, NULL, NULL), RPS3_EINVAL);
  /* without chk the same status; a success clears chk */
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_EINVAL);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_traj_check(&m, &tr, &chk), RPS3_OK);
  assert_int_equal(chk.field, -1);
  assert_string_equal(chk.msg, "");
  assert_int_equal(rps3_traj_check(&m, NULL, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, -1);
  assert_non_null(strstr(chk.msg, "trajectory NULL"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(table_ii),
      cmocka_unit_test(centre_traces_helix),
      cmocka_unit_test(derivatives_exact),
      cmocka_unit_test(blend_corners),
      cmocka_unit_test(errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
