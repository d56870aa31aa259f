/* test_ik.c - inverse kinematics against the paper's literal (3)-(7), the
   geometry it must satisfy, and its error codes. */
#include "testutil.h"

/* (5)-(7) exactly as printed, in the paper's normalized variables */
static void paper_L2(double rho, double al, double be, double Zc,
                     double L2[3]) {
  double Ca = cos(al), Sa = sin(al), Cb = cos(be), Sb = sin(be);
  double S2a = sin(2 * al), C2a = cos(2 * al), s3 = sqrt(3.0);
  double Xc = -0.5 * rho * (1 - Cb) * C2a; /* (3) */
  double Yc = 0.5 * rho * (1 - Cb) * S2a;  /* (4) */
  double base = 1 + rho * rho + Xc * Xc + Yc * Yc + Zc * Zc;
  L2[0] = base - 2 * Xc + 2 * rho * (Ca * Ca * Cb + Sa * Sa) * (Xc - 1) +
          rho * (Cb - 1) * S2a * Yc - 2 * rho * Sb * Ca * Zc;
  L2[1] = base + Xc - s3 * Yc -
          rho * (Ca * Ca * Cb + Sa * Sa - s3 * Ca * Sa * (Cb - 1)) * (Xc + 0.5) -
          rho * (Sa * Ca * (Cb - 1) - s3 * (Sa * Sa * Cb + Ca * Ca)) *
              (Yc - s3 / 2) +
          rho * Sb * (Ca - s3 * Sa) * Zc;
  L2[2] = base + Xc + s3 * Yc -
          rho * (Ca * Ca * Cb + Sa * Sa + s3 * Ca * Sa * (Cb - 1)) * (Xc + 0.5) -
          rho * (Sa * Ca * (Cb - 1) + s3 * (Sa * Sa * Cb + Ca * Ca)) *
              (Yc + s3 / 2) +
          rho * Sb * (Ca + s3 * Sa) * Zc;
}

static void random_pose(uint64_t *s, double pose[3]) {
  pose[0] = rnd_uniform(s, -3.14, 3.14);
  pose[1] = rnd_uniform(s, 0.0, 0.7);
  pose[2] = rnd_uniform(s, 0.12, 0.6);
}

static void lengths_match_paper(void **state) {
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 2385;
  int n, i, ok = 0;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 2000; n++) {
    double L2[3];
    random_pose(&seed, d->pose);
    if (rps3_ik(&m, d) != RPS3_OK) continue;
    ok++;
    paper_L2(m.rho, d->pose[0], d->pose[1], d->pose[2] / m.R, L2);
    for (i = 0; i < 3; i++) {
      double L = d->l[i] / m.R;
      CHECK_REL(L * L, L2[i], TOL_EXACT, 1.0, "L%d^2 at pose %d", i + 1, n);
    }
    /* (3)-(4) */
    CHECK_REL(d->c[0] / m.R, -0.5 * m.rho * (1 - cos(d->pose[1])) * cos(2 * d->pose[0]),
              TOL_EXACT, 1e-3, "Xc");
    CHECK_REL(d->c[1] / m.R, 0.5 * m.rho * (1 - cos(d->pose[1])) * sin(2 * d->pose[0]),
              TOL_EXACT, 1e-3, "Yc");
  }
  assert_true(ok > 1500);
  rps3_data_free(d);
}

static void geometry_holds(void **state) {
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 7131;
  int n, i, j, k;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 500; n++) {
    random_pose(&seed, d->pose);
    if (rps3_ik(&m, d) != RPS3_OK) continue;
    for (i = 0; i < 3; i++) {
      double D[3], s = 0.0, b2[3];
      /* the ball joint stays in the plane of its pin (tangential = 0) */
      CHECK_REL(d->b[i][0] * m.axis[i][0] + d->b[i][1] * m.axis[i][1], 0.0,
                1e-15, m.R, "ball %d out of its pin plane", i);
      /* adjacent ball joints sqrt(3) r apart, (8)-(10) */
      j = (i + 1) % 3;
      for (k = 0; k < 3; k++) D[k] = d->b[i][k] - d->b[j][k];
      CHECK_REL(sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]), sqrt(3.0) * m.r,
                TOL_EXACT, 0.0, "|b%d - b%d|", i + 1, j + 1);
      /* (39): sin(theta) = Z_b / L, and b = P + l phi */
      CHECK_REL(sin(d->theta[i]), d->b[i][2] / d->l[i], TOL_EXACT, 1.0,
                "(39) link %d", i + 1);
      for (k = 0; k < 3; k++) b2[k] = m.pin[i][k] + d->l[i] * d->phi[i][k];
      for (k = 0; k < 3; k++)
        CHECK_REL(b2[k], d->b[i][k], TOL_EXACT, m.R, "b = P + l phi");
      /* phi, dphi, axis orthonormal, dphi = axis x phi */
      for (k = 0; k < 3; k++) s += d->phi[i][k] * d->dphi[i][k];
      CHECK_REL(s, 0.0, 1e-15, 1.0, "phi . dphi");
      CHECK_REL(m.axis[i][1] * d->phi[i][2] - m.axis[i][2] * d->phi[i][1],
                d->dphi[i][0], 1e-15, 1.0, "axis x phi");
    }
    /* rot orthonormal with det +1 */
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        double s = 0.0;
        for (k = 0; k < 3; k++) s += d->rot[k][i] * d->rot[k][j];
        CHECK_REL(s, i == j ? 1.0 : 0.0, 1e-14, 1.0, "rot^T rot");
      }
  }
  rps3_data_free(d);
}

/* a wide platform (rho > 1) puts the ball joints outside the pins: theta >
   pi/2, which the printed arcsin form (39) alone would miss */
static void obtuse_branch(void **state) {
  rps3_model m;
  rps3_data *d;
  int i;
  (void)state;
  rps3_model_default(&m);
  m.rho = 1.6385;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = 0.3;
  d->pose[1] = 0.05;
  d->pose[2] = 0.2;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  for (i = 0; i < 3; i++) {
    assert_true(d->theta[i] > PI / 2 && d->theta[i] < PI);
    CHECK_REL(d->l[i] * cos(d->theta[i]), m.R - (d->b[i][0] * m.radial[i][0] + d->b[i][1] * m.radial[i][1]),
              TOL_EXACT, m.R, "radial offset");
  }
  rps3_data_free(d);
}

static void unreachable_and_invalid(void **state) {
  rps3_model m;
  rps3_data *d;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = 0.4;
  d->pose[1] = 0.1;
  d->pose[2] = -0.25; /* platform below the base */
  assert_int_equal(rps3_ik(&m, d), RPS3_EREACH);
  assert_int_equal(d->err.code, RPS3_EREACH);
  assert_non_null(strstr(d->err.msg, "link"));
  assert_int_equal(d->stage, 0);
  d->pose[2] = 0.0; /* in the base plane */
  assert_int_equal(rps3_ik(&m, d), RPS3_EREACH);
  d->pose[1] = 1.45; /* tipped so far that a ball joint dips below */
  d->pose[2] = 0.05;
  assert_int_equal(rps3_ik(&m, d), RPS3_EREACH);
  d->pose[1] = (double)NAN;
  assert_int_equal(rps3_ik(&m, d), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "not finite"));
  assert_int_equal(rps3_ik(NULL, d), RPS3_EINVAL);
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lengths_match_paper),
      cmocka_unit_test(geometry_holds),
      cmocka_unit_test(obtuse_branch),
      cmocka_unit_test(unreachable_and_invalid),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
