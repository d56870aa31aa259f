/*
 * test_ident_base.c - rps3_ident_base on the regressor of the standard
 * parameters: the counts of base parameters of the general model (an
 * independent count gives 25 inertial, 31 with prismatic friction, 37 with
 * pin friction too, 17 for identical legs with prismatic friction), at
 * three geometries; Y pi = Y_ind K pi; bad input refused by name.
 */
#include <stdlib.h>

#include "testutil.h"

#define NTRAJ 10
#define NT 30
#define NROW (3 * NTRAJ * NT)

/* Y (NROW x RPS3_NSTD) of model m over random trajectories */
static void stacked(const rps3_model *m, double *Y) {
  rps3_data *d;
  rps3_traj tr;
  double Yp[3][RPS3_NSTD];
  uint64_t seed = 77;
  int t, k, i, j, row = 0;
  assert_int_equal(rps3_data_alloc(m, &d), RPS3_OK);
  for (t = 0; t < NTRAJ; t++) {
    traj_random(&tr, &seed);
    for (k = 0; k < NT; k++) {
      double at = rps3_traj_duration(&tr) * (k + 0.5) / NT;
      assert_int_equal(rps3_traj_eval(m, &tr, at, d->pose, d->dpose,
                                      d->ddpose),
                       RPS3_OK);
      if (rps3_regressor_std(m, d, Yp) != RPS3_OK)
        fail_msg("regressor: %s", d->err.msg);
      for (i = 0; i < 3; i++, row++)
        for (j = 0; j < RPS3_NSTD; j++) Y[row * RPS3_NSTD + j] = Yp[i][j];
    }
  }
  rps3_data_free(d);
}

/* identical legs: the columns of cylinder i, piston i summed over the
   legs (and the friction's, when shared), into Z (NROW x 32): platform
   10, cylinder 10, piston 10, prismatic (fv, fc) */
static void identical(const double *Y, double *Z) {
  int r, k, i;
  for (r = 0; r < NROW; r++) {
    const double *y = Y + r * RPS3_NSTD;
    double *z = Z + r * 32;
    for (k = 0; k < 10; k++) {
      z[k] = y[k];
      z[10 + k] = z[20 + k] = 0.0;
      for (i = 0; i < 3; i++) {
        z[10 + k] += y[10 * (1 + 2 * i) + k];
        z[20 + k] += y[10 * (2 + 2 * i) + k];
      }
    }
    z[30] = y[70] + y[72] + y[74];
    z[31] = y[71] + y[73] + y[75];
  }
}

/* rps3_ident_base of Y (NROW x p): nbase, and Y pi = Y_ind K pi */
static int base_of(const double *Y, size_t p) {
  int *ind = malloc(p * sizeof(int)), nb, r, k, j;
  double *K = malloc(p * p * sizeof(double)), pi[RPS3_NSTD], base[RPS3_NSTD];
  rps3_check chk;
  uint64_t seed = 5;
  assert_non_null(ind);
  assert_non_null(K);
  if (rps3_ident_base(Y, NROW, p, 1e-7, ind, K, &nb, &chk) != RPS3_OK)
    fail_msg("%s", chk.msg);
  for (j = 0; j < (int)p; j++) pi[j] = rnd_uniform(&seed, -1.0, 1.0);
  for (k = 0; k < nb; k++) {
    base[k] = 0.0;
    for (j = 0; j < (int)p; j++) base[k] += K[k * p + j] * pi[j];
    if (k > 0) assert_true(ind[k] > ind[k - 1]);
  }
  for (r = 0; r < NROW; r++) {
    double f = 0.0, g = 0.0, s = 0.0;
    for (j = 0; j < (int)p; j++) {
      f += Y[r * p + j] * pi[j];
      s += fabs(Y[r * p + j] * pi[j]);
    }
    for (k = 0; k < nb; k++) g += Y[r * p + ind[k]] * base[k];
    CHECK_REL(g, f, 1e-9, s, "row %d: Y pi against Y_ind K pi", r);
  }
  free(ind);
  free(K);
  return nb;
}

static void counts_at_three_geometries(void **state) {
  static const double geo[3][2] = {{0.2286, 0.5}, {0.31, 0.37}, {0.17, 0.71}};
  double *Y = malloc(NROW * RPS3_NSTD * sizeof(double));
  double *Z = malloc(NROW * 32 * sizeof(double));
  rps3_model m;
  int g, i;
  (void)state;
  assert_non_null(Y);
  assert_non_null(Z);
  for (g = 0; g < 3; g++) {
    rps3_model_default(&m);
    m.R = geo[g][0];
    m.rho = geo[g][1];
    m.bodies = RPS3_BODIES_GENERAL;
    for (i = 0; i < 3; i++) m.leg[i].prismatic.vreg = 1e-3;
    m.opt.effects = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    stacked(&m, Y);
    assert_int_equal(base_of(Y, RPS3_NSTD), 37);
    identical(Y, Z);
    assert_int_equal(base_of(Z, 32), 17);
    m.opt.effects &= ~RPS3_EFF_PIN_FRICTION;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    stacked(&m, Y);
    assert_int_equal(base_of(Y, RPS3_NSTD), 31);
    m.opt.effects &= ~RPS3_EFF_PRISMATIC_FRICTION;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    stacked(&m, Y);
    assert_int_equal(base_of(Y, RPS3_NSTD), 25);
  }
  free(Y);
  free(Z);
}

static void bad_input(void **state) {
  double Y[6] = {1, 2, 3, 4, 5, 6}, K[4];
  int ind[2], nb;
  rps3_check chk;
  (void)state;
  Y[4] = (double)NAN;
  assert_int_equal(rps3_ident_base(Y, 3, 2, 1e-7, ind, K, &nb, &chk),
                   RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "Y[2][0]"));
  memset(Y, 0, sizeof Y);
  assert_int_equal(rps3_ident_base(Y, 3, 2, 1e-7, ind, K, &nb, &chk),
                   RPS3_ESING);
  assert_int_equal(nb, 0);
  assert_int_equal(rps3_ident_base(Y, 3, 2, 0.0, ind, K, &nb, &chk),
                   RPS3_EINVAL);
  assert_int_equal(rps3_ident_base(NULL, 3, 2, 1e-7, ind, K, &nb, &chk),
                   RPS3_EINVAL);
  /* two equal columns: the second regroups into the first */
  {
    double Y2[6] = {1, 1, 2, 2, 3, 3};
    assert_int_equal(rps3_ident_base(Y2, 3, 2, 1e-7, ind, K, &nb, &chk),
                     RPS3_OK);
    assert_int_equal(nb, 1);
    assert_int_equal(ind[0], 0);
    CHECK_REL(K[1], 1.0, 1e-14, 1.0, "the regrouping coefficient");
  }
  /* a column 1e-5 of the other's norm but independent: a parameter that
     acts weakly is still a base parameter (the unit-norm scaling) */
  {
    double Y3[6] = {1, 1e-5, 1, -1e-5, 1, 2e-5};
    assert_int_equal(rps3_ident_base(Y3, 3, 2, 1e-7, ind, K, &nb, &chk),
                     RPS3_OK);
    assert_int_equal(nb, 2);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(counts_at_three_geometries),
      cmocka_unit_test(bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
