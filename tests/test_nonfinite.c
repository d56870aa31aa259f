/*
 * test_nonfinite.c - no result is reported as a success unless it is
 * finite, and the library never reaches GSL's error handler.
 *
 * Unlike the other tests this program leaves GSL's default error handler
 * ON (it never calls gsl_set_error_handler_off): the handler aborts, so any
 * path of the library that reaches it fails the test by killing it.
 */
#include "testutil.h"

static rps3_data *setup(rps3_model *m) {
  rps3_data *d = NULL;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &d), RPS3_OK);
  return d;
}

/* the message names the quantity, e.g. "F[0] = inf is not finite" */
static void assert_range(const rps3_data *d, int st, const char *what) {
  if (st != RPS3_ERANGE)
    print_error("status %d (%s), want RPS3_ERANGE: %s\n", st,
                rps3_strerror(st), d->err.msg);
  assert_int_equal(st, RPS3_ERANGE);
  assert_int_equal(d->err.code, RPS3_ERANGE);
  if (strstr(d->err.msg, what) == NULL)
    print_error("message '%s' does not name %s\n", d->err.msg, what);
  assert_non_null(strstr(d->err.msg, what));
  assert_non_null(strstr(d->err.msg, "not finite"));
}

static void strerror_has_erange(void **state) {
  (void)state;
  assert_string_equal(rps3_strerror(RPS3_ERANGE),
                      "result not finite (overflow)");
  assert_true(RPS3_ERANGE > 0); /* a point-level outcome */
}

/* masses whose weight overflows are refused once, at init */
static void model_overflow_at_init(void **state) {
  static const double big[3] = {1e308, 2.3e307, 1.7976931348623157e308};
  rps3_model m;
  rps3_check chk;
  int k;
  (void)state;
  for (k = 0; k < 3; k++) {
    rps3_model_default(&m);
    m.M = big[k];
    assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
    assert_true(strncmp(chk.msg, "M = ", 4) == 0);
    assert_non_null(strstr(chk.msg, "overflows"));
    rps3_model_default(&m);
    m.payload.mass = big[k];
    assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
    assert_true(strncmp(chk.msg, "payload.mass = ", 15) == 0);
    rps3_model_default(&m);
    m.m = big[k];
    assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
    assert_true(strncmp(chk.msg, "m = ", 4) == 0);
  }
  /* general bodies do not read M and m: a huge M is no error there, a
     platform whose second moment r^2 overflows is, named by its field */
  rps3_model_default(&m);
  m.bodies = RPS3_BODIES_GENERAL;
  m.M = big[0];
  m.m = big[0];
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_OK);
  m.platform.mass = 1.0;
  m.R = 1e200;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_true(strncmp(chk.msg, "platform.mass = ", 16) == 0);
  assert_non_null(strstr(chk.msg, "r^2 overflows"));
}

/*
 * A mass that passes init (M g finite) but whose forces overflow: from
 * M = 1e300 kg up to the largest one init accepts, every point is either
 * OK with finite forces or RPS3_ERANGE naming the quantity; near the top
 * the forces (a few M g) overflow and ERANGE must appear.
 */
static void huge_mass_forces(void **state) {
  rps3_model m;
  rps3_data *d;
  double M;
  int nrange = 0, nok = 0, st, i;
  (void)state;
  for (M = 1e300; M < 1.8e307; M *= 1.9) {
    rps3_model_default(&m);
    m.M = M;
    d = setup(&m);
    d->pose[0] = 0.7391;
    d->pose[1] = 0.6117;
    d->pose[2] = 0.1023;
    d->dpose[0] = 0.31;
    d->dpose[1] = -0.22;
    d->dpose[2] = 0.05;
    d->ddpose[0] = 1.3;
    d->ddpose[1] = 0.4;
    d->ddpose[2] = -0.9;
    st = rps3_inverse(&m, d);
    if (st == RPS3_OK) {
      nok++;
      for (i = 0; i < 3; i++) {
        assert_true(isfinite(d->F[i]) && isfinite(d->lambda[i]));
      }
      assert_true(isfinite(d->energy_residual));
    } else {
      assert_range(d, st, "");
      nrange++;
    }
    rps3_data_free(d);
  }
  assert_true(nok > 0);
  assert_true(nrange > 0);
}

/* pose rates of 1e200: their squares overflow in the acceleration stage */
static void huge_rates(void **state) {
  rps3_model m;
  rps3_data *d;
  int st;
  (void)state;
  rps3_model_default(&m);
  d = setup(&m);
  d->pose[0] = 0.4127;
  d->pose[1] = 0.2213;
  d->pose[2] = 0.2871;
  d->dpose[0] = 1e200;
  d->dpose[1] = -3.7e199;
  d->dpose[2] = 0.5;
  d->ddpose[0] = d->ddpose[1] = d->ddpose[2] = 0.0;
  st = rps3_inverse(&m, d);
  assert_range(d, st, "[");
  /* 1e300: the velocity stage already overflows (dl, vc) */
  d->dpose[0] = 1e300;
  d->dpose[1] = 1e300;
  d->dpose[2] = 1e300;
  st = rps3_inverse(&m, d);
  assert_range(d, st, "[");
  rps3_data_free(d);
}

/* a finite height of 1e200 m: the link lengths overflow in ik */
static void huge_height(void **state) {
  rps3_model m;
  rps3_data *d;
  (void)state;
  rps3_model_default(&m);
  d = setup(&m);
  d->pose[0] = 0.3;
  d->pose[1] = 0.2;
  d->pose[2] = 1e200;
  assert_range(d, rps3_ik(&m, d), "l[");
  assert_range(d, rps3_inverse(&m, d), "l[");
  /* 1e150 m is long but finite: ik succeeds, every field finite */
  d->pose[2] = 1e150;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  assert_true(isfinite(d->l[0]) && isfinite(d->l[1]) && isfinite(d->l[2]));
  rps3_data_free(d);
}

/* trajectories: a sine whose acceleration overflows (rps3_traj_check
   refuses it; evaluated unchecked it is RPS3_ERANGE), and an unchecked
   one holding NaN */
static void traj_overflow(void **state) {
  rps3_model m;
  rps3_traj tr;
  double p[3], dp[3], ddp[3];
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  memset(&tr, 0, sizeof tr);
  tr.kind = RPS3_TRAJ_SINE;
  tr.sine.mean[2] = 0.3;
  tr.sine.amp[0] = 1e306;
  tr.sine.freq[0] = 37.0;
  tr.sine.phase[0] = 0.5;
  tr.sine.duration = 1.0;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_EINVAL);
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.25, p, dp, ddp), RPS3_ERANGE);
  assert_false(isfinite(ddp[0]));
  /* amplitude 1e306 at zero frequency stays finite */
  tr.sine.freq[0] = 0.0;
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.25, p, dp, ddp), RPS3_OK);
  /* unchecked: NaN in the mean */
  tr.sine.amp[0] = 0.1;
  tr.sine.mean[1] = nan("");
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.25, p, NULL, NULL),
                   RPS3_ERANGE);
  assert_true(isnan(p[1]));
  /* unchecked helix with an infinite pitch */
  rps3_traj_default(&tr);
  tr.helix.pitch = HUGE_VAL;
  assert_int_equal(rps3_traj_eval(&m, &tr, 1.0, p, dp, ddp), RPS3_ERANGE);
}

/* the joint-rate route: link rates of 1e300 overflow */
static void joint_rates_overflow(void **state) {
  rps3_model m;
  rps3_data *d;
  int st;
  (void)state;
  rps3_model_default(&m);
  d = setup(&m);
  d->pose[0] = 0.2;
  d->pose[1] = 0.3;
  d->pose[2] = 0.25;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  d->dl[0] = 1e300;
  d->dl[1] = -1e300;
  d->dl[2] = 1e300;
  st = rps3_joint_velocity(&m, d);
  if (st == RPS3_OK) {
    d->ddl[0] = d->ddl[1] = d->ddl[2] = 0.0;
    st = rps3_joint_acceleration(&m, d);
  }
  assert_range(d, st, "[");
  rps3_data_free(d);
}

/* the void functions accept NULL */
static void void_functions_null(void **state) {
  double T[4][4], w[3] = {1, 2, 3};
  rps3_model m;
  (void)state;
  rps3_model_default(NULL);
  rps3_options_default(NULL);
  rps3_traj_default(NULL);
  rps3_data_free(NULL);
  rps3_data_reset(NULL);
  rps3_transform(NULL, NULL);
  rps3_transform(NULL, T);
  assert_true(isnan(T[0][0]) && isnan(T[2][3]));
  assert_true(T[3][3] == 1.0);
  rps3_omega_paper(NULL, NULL, w);
  assert_true(isnan(w[0]) && isnan(w[1]) && isnan(w[2]));
  rps3_model_default(&m);
  rps3_omega_paper(&m, NULL, NULL);
}

/* ------------------------------------------------ GSL's error handler */

/*
 * The theta solve with every solver on hard inputs: random and extreme
 * link lengths (1e-8 to 1e8 R), starts at 0 and pi (where every sine
 * vanishes), far outside (0, pi).  Whatever the outcome, the library must
 * not reach GSL's error handler (which would abort this program).  Without
 * the library's checks, dnewton reaches lu.c ("matrix is singular") and
 * broyden broyden.c ("approximation to Jacobian has collapsed") within a
 * few thousand of these.
 */
static void solvers_never_reach_gsl_handler(void **state) {
  /* a broyden stall found this way: it converges to 4.9e-12 > tol and
     then steps in place */
  static const double stall_l[3] = {0.21717413247341313, 0.21648214141143293,
                                    0.11098196487123266};
  static const double stall_th[3] = {2.8474195186044966, 1.6174391319416408,
                                     2.4739038728259026};
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 7;
  int s, n, i;
  (void)state;
  for (s = 0; s < RPS3_NSOLVER; s++) {
    int nst[8] = {0};
    /* the finite-difference Newton solvers most, the others a sample */
    int count = (s == RPS3_SOLVER_DNEWTON || s == RPS3_SOLVER_BROYDEN) ? 20000
                                                                       : 1500;
#ifdef RPS3_SANITIZE
    /* the sanitizer build checks memory, not coverage: a tenth */
    count /= 10;
#endif
    rps3_model_default(&m);
    m.opt.solver = (rps3_solver)s;
    m.opt.max_iter = 200;
    d = setup(&m);
    for (n = 0; n < count; n++) {
      int kind = n % 4, st;
      for (i = 0; i < 3; i++) {
        if (kind == 0)
          d->l[i] = rnd_uniform(&seed, 0.01, 3.0) * m.R;
        else if (kind == 1)
          d->l[i] = pow(10.0, rnd_uniform(&seed, -8.0, 8.0)) * m.R;
        else
          d->l[i] = rnd_uniform(&seed, 0.3, 1.5) * m.R;
        if (kind == 3)
          d->theta[i] = (n / 4) % 3 == 0   ? 0.0
                        : (n / 4) % 3 == 1 ? PI
                                           : rnd_uniform(&seed, -10.0, 10.0);
        else
          d->theta[i] = rnd_uniform(&seed, 0.0, PI);
      }
      d->have_theta = 1;
      st = rps3_fk(&m, d);
      if (st != RPS3_OK) assert_true(strlen(d->err.msg) > 0);
      assert_true(st >= 0 && st < 8);
      nst[st]++;
    }
    memcpy(d->l, stall_l, sizeof stall_l);
    memcpy(d->theta, stall_th, sizeof stall_th);
    d->have_theta = 1;
    (void)rps3_fk(&m, d);
    print_message("%-8s %d ok, %d no convergence, %d other branch\n",
                  rps3_solver_name(s), nst[RPS3_OK], nst[RPS3_ENOCONV],
                  nst[RPS3_EBRANCH]);
    assert_true(nst[RPS3_OK] > count / 20);
    rps3_data_free(d);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(strerror_has_erange),
      cmocka_unit_test(model_overflow_at_init),
      cmocka_unit_test(huge_mass_forces),
      cmocka_unit_test(huge_rates),
      cmocka_unit_test(huge_height),
      cmocka_unit_test(traj_overflow),
      cmocka_unit_test(joint_rates_overflow),
      cmocka_unit_test(void_functions_null),
      cmocka_unit_test(solvers_never_reach_gsl_handler),
  };
  /* GSL's default error handler stays on: see the top of the file */
  return cmocka_run_group_tests(tests, NULL, NULL);
}
