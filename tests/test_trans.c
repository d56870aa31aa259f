/*
 * test_trans.c - the force transmission measure (rps3_data.transmission):
 * dimensionless, a bound on the holding force, blind to neither of the two
 * approaches where the condition number of df/dtheta says nothing (a level
 * platform lowered onto the base) or speaks too late (a tilted approach
 * to the singular surface), and its two limits opt.trans_warn/trans_max.
 */
#include "testutil.h"

static rps3_data *make(rps3_model *m, int effects, int method) {
  rps3_data *d = NULL;
  rps3_model_default(m);
  m->opt.effects = effects;
  m->opt.method = method;
  m->opt.certify = 0;
  assert_int_equal(rps3_model_init(m, NULL, 0), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &d), RPS3_OK);
  return d;
}

static double fmax3(const double F[3]) {
  double a = fabs(F[0]), b = fabs(F[1]), c = fabs(F[2]);
  return a > b ? (a > c ? a : c) : (b > c ? b : c);
}

/*
 * A level platform lowered towards the base: the condition number of the
 * lambda system stays at exactly 3, but the holding force grows like
 * 1 / z_c.  The transmission follows the force: past trans_warn (100) the
 * point carries RPS3_WARN_TRANS, past trans_max (1e8) it is RPS3_ESING
 * with a message; at z_c = 1e-12 m it is refused (it used to return 2e11 N,
 * status OK, no warning).
 */
static void level_platform_lowered(void **state) {
  rps3_model m;
  rps3_data *d = make(&m, RPS3_EFF_PLATFORM_GRAVITY, RPS3_LAGRANGE);
  double z, W;
  int nok = 0, nwarn = 0, nsing = 0, last = -1;
  (void)state;
  W = m.M * m.g;
  for (z = 0.2713; z > 5e-13; z /= 3.7) {
    int st;
    d->pose[0] = 0.0;
    d->pose[1] = 0.0;
    d->pose[2] = z;
    st = rps3_inverse(&m, d);
    if (st == RPS3_OK) {
      /* the holding force stays under its bound: a platform weight W is
         the load (0, 0, W) with no moment */
      CHECK_REL(d->cond, 3.0, 1e-9, 1.0, "cond of a level platform");
      assert_true(fmax3(d->F) <= d->transmission * W * (1 + 1e-12));
      assert_int_equal((d->warn & RPS3_WARN_TRANS) != 0,
                       d->transmission > m.opt.trans_warn);
      /* warnings come in order: none, then warn; never back */
      assert_true(last <= ((d->warn & RPS3_WARN_TRANS) != 0));
      last = (d->warn & RPS3_WARN_TRANS) != 0;
      nok++;
      nwarn += last;
    } else {
      assert_int_equal(st, RPS3_ESING);
      assert_non_null(strstr(d->err.msg, "force transmission"));
      assert_true(d->transmission > m.opt.trans_max);
      assert_true(last == 1); /* warned before refused */
      nsing++;
    }
  }
  assert_true(nok > 3 && nwarn > 3 && nsing > 3);
  /* the point */
  d->pose[2] = 1e-12;
  assert_int_equal(rps3_inverse(&m, d), RPS3_ESING);
  rps3_data_free(d);
}

/*
 * A tilted approach to the singular surface (alpha = 0.3 rad, z_c = 0.2 m,
 * beta rising): the first RPS3_WARN_TRANS must come while the holding force
 * is still moderate (under 100 times the weight), long before
 * RPS3_WARN_ILLCOND (cond > 1e6), which came at 7.6e5 times it.
 */
static void tilted_approach_warns_early(void **state) {
  rps3_model m;
  rps3_data *d = make(&m, RPS3_EFF_PLATFORM_GRAVITY, RPS3_LAGRANGE);
  double lo = 0.5, hi = 1.0, bs, e, W, f_trans = -1.0, f_ill = -1.0;
  int k;
  (void)state;
  W = m.M * m.g;
  /* the singular surface along this line: bisection on the mode */
  d->pose[0] = 0.3;
  d->pose[2] = 0.2;
  for (k = 0; k < 80; k++) {
    d->pose[1] = 0.5 * (lo + hi);
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    if (d->mode == RPS3_MODE_LEVEL)
      lo = d->pose[1];
    else
      hi = d->pose[1];
  }
  bs = lo;
  for (e = 0.2; e > 1e-13; e *= 0.9) {
    d->pose[0] = 0.3;
    d->pose[1] = bs - e;
    d->pose[2] = 0.2;
    if (rps3_inverse(&m, d) != RPS3_OK) break;
    if (f_trans < 0 && (d->warn & RPS3_WARN_TRANS)) f_trans = fmax3(d->F) / W;
    if (f_ill < 0 && (d->warn & RPS3_WARN_ILLCOND)) f_ill = fmax3(d->F) / W;
  }
  print_message("tilted approach: first transmission warning at %.3g x the "
                "weight, first condition warning at %.3g x\n", f_trans, f_ill);
  assert_true(f_trans > 0.0 && f_trans < 100.0);
  assert_true(f_ill < 0.0 || f_ill > 100.0 * f_trans);
  rps3_data_free(d);
}

/* dimensionless: the same at every size of mechanism, and the same under
   both formulations (it reads positions only) */
static void scale_and_method_invariant(void **state) {
  static const double s[4] = {1e-3, 0.37, 1.0, 85.0};
  rps3_model m;
  rps3_data *d;
  double ref = 0.0;
  int k, method;
  (void)state;
  for (method = 0; method < 2; method++)
    for (k = 0; k < 4; k++) {
      d = make(&m, RPS3_EFF_PLATFORM_GRAVITY, method);
      m.R *= s[k];
      m.d *= s[k];
      assert_int_equal(rps3_model_init(&m, NULL, 0), RPS3_OK);
      d->pose[0] = 0.7311;
      d->pose[1] = 0.4127;
      d->pose[2] = 0.9173 * m.R;
      assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
      if (ref == 0.0) ref = d->transmission;
      CHECK_REL(d->transmission, ref, 1e-12, 0.0, "scale %g method %d", s[k],
                method);
      rps3_data_free(d);
    }
  assert_true(ref > 1.0 && ref < 100.0);
}

/* the bound holds for any wrench: random poses, a load made of the
   platform weight plus an off-centre payload (force and moment) */
static void bound_on_holding_force(void **state) {
  rps3_model m;
  rps3_data *d = make(&m, RPS3_EFF_PAYLOAD, RPS3_NEWTON_EULER);
  uint64_t seed = 99;
  int n, ok = 0;
  (void)state;
  m.payload.mass = 0.3137;
  m.payload.com[0] = 0.0411;
  m.payload.com[1] = -0.0271;
  m.payload.com[2] = 0.0317;
  m.payload.inertia[0] = m.payload.inertia[1] = m.payload.inertia[2] = 1e-4;
  assert_int_equal(rps3_model_init(&m, NULL, 0), RPS3_OK);
  for (n = 0; n < 2000; n++) {
    double f, nm, load;
    int i;
    d->pose[0] = rnd_uniform(&seed, -PI, PI);
    d->pose[1] = rnd_uniform(&seed, 0.0, 0.6);
    d->pose[2] = rnd_uniform(&seed, 0.3, 2.5) * m.R;
    if (rps3_inverse(&m, d) != RPS3_OK) continue;
    /* the static payload load: force m g e_z, moment (R p) x (m g e_z)
       with p the payload centre of mass in base axes */
    f = m.payload.mass * m.g;
    nm = 0.0;
    for (i = 0; i < 2; i++) {
      double pc = 0.0;
      int k;
      for (k = 0; k < 3; k++) pc += d->rot[i][k] * m.payload.com[k];
      if (fabs(pc * f) > nm) nm = fabs(pc * f);
    }
    load = f > nm / m.R ? f : nm / m.R;
    assert_true(fmax3(d->F) <= d->transmission * load * (1 + 1e-12));
    ok++;
  }
  assert_true(ok > 1000);
  rps3_data_free(d);
}

/* the limits are options: validated, and trans_max >= trans_warn */
static void limits_are_options(void **state) {
  rps3_model m;
  char err[256];
  (void)state;
  rps3_model_default(&m);
  assert_true(m.opt.trans_warn == 100.0 && m.opt.trans_max == 1e8);
  m.opt.trans_warn = 0.0;
  assert_int_equal(rps3_model_init(&m, err, sizeof err), RPS3_EINVAL);
  assert_true(strncmp(err, "opt.trans_warn = ", 17) == 0);
  rps3_model_default(&m);
  m.opt.trans_max = 50.0;
  assert_int_equal(rps3_model_init(&m, err, sizeof err), RPS3_EINVAL);
  assert_true(strncmp(err, "opt.trans_max = ", 16) == 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(level_platform_lowered),
      cmocka_unit_test(tilted_approach_warns_early),
      cmocka_unit_test(scale_and_method_invariant),
      cmocka_unit_test(bound_on_holding_force),
      cmocka_unit_test(limits_are_options),
  };
  gsl_set_error_handler_off();
  return cmocka_run_group_tests(tests, NULL, NULL);
}
