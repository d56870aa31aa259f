/*
 * test_ident.c - the regressor (src/ident.c) against the library's own
 * forces, and the estimators (src/ident_fit.c) on synthetic data with
 * known parameters.
 */
#include <stdlib.h>

#include "testutil.h"

/* Y pi against rps3_inverse's F: the same loads and solve, summed in
   another order (the columns, then the parameters' products): rounding
   of ~20 terms times the lambda system's condition number (< 1e3 on
   these states), ~1e-13 of the terms' scale; 1e-10 is the required
   agreement */
#define TOL_REGRESSOR 1e-10
#define NSTATE 10000

/* a model with every effect, the payload's centre of mass on platform
   axis `axis` (off the axes it has products of inertia the paper
   parameters do not hold) */
static void ident_model(rps3_model *m, int method, int axis, double vreg) {
  int k;
  model_entropy(m);
  for (k = 0; k < 3; k++)
    if (k != axis) m->payload.com[k] = 0.0;
  m->friction.vreg = vreg;
  m->opt.method = (rps3_method)method;
  assert_int_equal(rps3_model_init(m, NULL, 0), RPS3_OK);
}

static void random_state(rps3_data *d, uint64_t *s) {
  d->pose[0] = rnd_uniform(s, -PI, PI);
  d->pose[1] = rnd_uniform(s, 0.05, 0.45);
  d->pose[2] = rnd_uniform(s, 0.18, 0.40);
  d->dpose[0] = rnd_uniform(s, -2.0, 2.0);
  d->dpose[1] = rnd_uniform(s, -0.6, 0.6);
  d->dpose[2] = rnd_uniform(s, -0.2, 0.2);
  d->ddpose[0] = rnd_uniform(s, -8.0, 8.0);
  d->ddpose[1] = rnd_uniform(s, -3.0, 3.0);
  d->ddpose[2] = rnd_uniform(s, -1.0, 1.0);
}

/* Y pi = F at NSTATE random states, for a method and a theta route */
static void regressor_vs_forces(int method, int route) {
  rps3_model m;
  rps3_data *d, *d2;
  uint64_t s = 0x1d3e7ull + (uint64_t)(2 * method + route);
  double pi[RPS3_NPAPER], worst = 0.0;
  int i, r, k, nok = 0;
  ident_model(&m, method, method == 0 ? 2 : 0, route ? 0.0 : 0.05);
  m.opt.theta = (rps3_theta_route)route;
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d2), RPS3_OK);
  assert_int_equal(rps3_paper_params(&m, pi, NULL, 0), RPS3_OK);
  for (i = 0; i < NSTATE; i++) {
    double Y[3][RPS3_NPAPER];
    int st1, st2;
    random_state(d, &s);
    copy_motion(d2, d);
    st1 = rps3_inverse(&m, d);
    st2 = rps3_regressor(&m, d2, Y);
    assert_int_equal(st1, st2);
    if (st1 != RPS3_OK) continue;
    nok++;
    for (r = 0; r < 3; r++) {
      double f = 0.0, scale = 0.0, e;
      for (k = 0; k < RPS3_NPAPER; k++) {
        f += Y[r][k] * pi[k];
        scale += fabs(Y[r][k] * pi[k]);
      }
      e = fabs(f - d->F[r]) / scale;
      if (e > worst) worst = e;
      CHECK_REL(f, d->F[r], TOL_REGRESSOR, scale,
                "method %d route %d state %d row %d", method, route, i, r);
    }
  }
  /* the states are inside the workspace: nearly all of them count */
  assert_true(nok > NSTATE * 9 / 10);
  print_message("method %d route %d: %d states, worst |Y pi - F| / scale "
                "%.2g\n", method, route, nok, worst);
  rps3_data_free(d);
  rps3_data_free(d2);
}

static void test_regressor_lagrange(void **state) {
  (void)state;
  regressor_vs_forces(RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM);
  regressor_vs_forces(RPS3_LAGRANGE, RPS3_THETA_MULTIROOT);
}

static void test_regressor_newton_euler(void **state) {
  (void)state;
  regressor_vs_forces(RPS3_NEWTON_EULER, RPS3_THETA_CLOSED_FORM);
}

/* each column is the force of its parameter alone: a model with only that
   parameter nonzero (and its effect) has F = Y[:, k] pi_k; and columns of
   effects not selected are zero */
static void test_regressor_columns(void **state) {
  rps3_model m, one;
  rps3_data *d, *d1;
  uint64_t s = 77;
  double Y[3][RPS3_NPAPER], pi[RPS3_NPAPER];
  int r, k;
  (void)state;
  ident_model(&m, RPS3_LAGRANGE, 1, 0.0);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d1), RPS3_OK);
  random_state(d, &s);
  copy_motion(d1, d);
  assert_int_equal(rps3_regressor(&m, d, Y), RPS3_OK);
  /* pin friction alone */
  one = m;
  one.opt.effects = RPS3_EFF_PIN_FRICTION;
  assert_int_equal(rps3_model_init(&one, NULL, 0), RPS3_OK);
  assert_int_equal(rps3_inverse(&one, d1), RPS3_OK);
  assert_int_equal(rps3_paper_params(&one, pi, NULL, 0), RPS3_OK);
  for (r = 0; r < 3; r++)
    CHECK_REL(Y[r][10] * pi[10] + Y[r][11] * pi[11], d1->F[r], TOL_EXACT,
              1e-3, "friction row %d", r);
  /* gravity only: the dynamic columns are zero, the others agree */
  {
    double Yg[3][RPS3_NPAPER];
    one = m;
    one.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
    assert_int_equal(rps3_model_init(&one, NULL, 0), RPS3_OK);
    copy_motion(d1, d);
    assert_int_equal(rps3_regressor(&one, d1, Yg), RPS3_OK);
    for (r = 0; r < 3; r++)
      for (k = 2; k < RPS3_NPAPER; k++) assert_true(Yg[r][k] == 0.0);
    for (r = 0; r < 3; r++) {
      assert_true(Yg[r][1] == Y[r][1]);
      assert_true(Yg[r][0] != Y[r][0]); /* inertia left out of M's */
    }
  }
  rps3_data_free(d);
  rps3_data_free(d1);
}

/* the batch is the loop of rps3_regressor, bit for bit; a failed point is
   NaN, named in the message, and the others computed */
static void test_regressor_batch(void **state) {
  enum { N = 57 };
  rps3_model m;
  rps3_data *d, *d1;
  double pose[3 * N], dpose[3 * N], ddpose[3 * N], *Y, theta[3 * N];
  int status[N], i, c, k;
  uint64_t s = 5;
  rps3_batch_in in;
  rps3_batch_out out;
  (void)state;
  ident_model(&m, RPS3_LAGRANGE, 0, 0.01);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d1), RPS3_OK);
  for (i = 0; i < N; i++) {
    random_state(d, &s);
    for (c = 0; c < 3; c++) {
      pose[c * N + i] = d->pose[c];
      dpose[c * N + i] = d->dpose[c];
      ddpose[c * N + i] = d->ddpose[c];
    }
  }
  pose[2 * N + 13] = -0.3; /* below the base: unreachable */
  Y = malloc(sizeof(double) * 3 * RPS3_NPAPER * N);
  assert_non_null(Y);
  memset(&in, 0, sizeof(in));
  memset(&out, 0, sizeof(out));
  in.n = N;
  in.pose = pose;
  in.dpose = dpose;
  in.ddpose = ddpose;
  out.status = status;
  out.theta = theta;
  assert_int_equal(rps3_regressor_batch(&m, d, &in, Y, &out), RPS3_OK);
  assert_int_equal(out.nfail, 1);
  assert_int_equal(out.first_fail, 13);
  assert_int_equal(status[13], RPS3_EREACH);
  assert_non_null(strstr(d->err.msg, "point 13: "));
  for (i = 0; i < N; i++) {
    double Yp[3][RPS3_NPAPER];
    int st;
    for (c = 0; c < 3; c++) {
      d1->pose[c] = pose[c * N + i];
      d1->dpose[c] = dpose[c * N + i];
      d1->ddpose[c] = ddpose[c * N + i];
    }
    st = rps3_regressor(&m, d1, Yp);
    assert_int_equal(st, status[i]);
    for (c = 0; c < 3; c++)
      for (k = 0; k < RPS3_NPAPER; k++) {
        double b = Y[(c * RPS3_NPAPER + k) * N + i];
        if (st == RPS3_OK)
          assert_memory_equal(&b, &Yp[c][k], sizeof(double));
        else
          assert_true(isnan(b) && isnan(Yp[c][k]));
      }
  }
  /* invalid calls compute nothing */
  assert_int_equal(rps3_regressor_batch(&m, d, &in, NULL, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "Y"));
  in.dpose = NULL;
  assert_int_equal(rps3_regressor_batch(&m, d, &in, Y, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "dpose"));
  free(Y);
  rps3_data_free(d);
  rps3_data_free(d1);
}

static void test_regressor_errors(void **state) {
  rps3_model m;
  rps3_data *d;
  double Y[3][RPS3_NPAPER], pi[RPS3_NPAPER];
  char err[256];
  (void)state;
  ident_model(&m, RPS3_LAGRANGE, 2, 0.0);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_regressor(NULL, d, Y), RPS3_EINVAL);
  assert_int_equal(rps3_regressor(&m, NULL, Y), RPS3_EINVAL);
  assert_int_equal(rps3_regressor(&m, d, NULL), RPS3_EINVAL);
  d->pose[0] = 0.3;
  d->pose[1] = 0.2;
  d->pose[2] = NAN;
  assert_int_equal(rps3_regressor(&m, d, Y), RPS3_EINVAL);
  assert_true(isnan(Y[1][4]));
  /* the names and units of the Python package's PAPER_NAMES */
  assert_string_equal(rps3_paper_name(2), "Ipin");
  assert_string_equal(rps3_paper_name(11), "pin.fc");
  assert_string_equal(rps3_paper_unit(7), "kg m^2");
  assert_null(rps3_paper_name(12));
  assert_null(rps3_paper_unit(-1));
  /* a payload off the platform axes is refused by name */
  m.payload.com[0] = 0.01;
  m.payload.com[2] = 0.02;
  assert_int_equal(rps3_paper_params(&m, pi, err, sizeof(err)), RPS3_EINVAL);
  assert_non_null(strstr(err, "payload.com"));
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_regressor_lagrange),
      cmocka_unit_test(test_regressor_newton_euler),
      cmocka_unit_test(test_regressor_columns),
      cmocka_unit_test(test_regressor_batch),
      cmocka_unit_test(test_regressor_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
