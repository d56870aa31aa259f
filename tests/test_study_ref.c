/* test_study_ref.c - the force reference of rps3-study (runner/study/study_ref.c):
   it reads the model's inputs only, it agrees with the library's inverse
   dynamics with every effect, and its double twin measures its floor. */
#include "testutil.h"

/* the reference is runner code, not part of librps3: compiled in here */
#include "../runner/study/study_ref.c"

/* every field rps3_model_init() derives, set to NaN */
static void poison_derived(rps3_model *m) {
  int i, j;
  m->r = m->Jlink = (double)NAN;
  for (i = 0; i < 3; i++) {
    m->Ip[i] = (double)NAN;
    for (j = 0; j < 3; j++)
      m->pin[i][j] = m->radial[i][j] = m->axis[i][j] = m->body[i][j] =
          (double)NAN;
  }
  m->valid = 0;
}

static double fscale(const double F[3]) {
  return fabs(F[0]) + fabs(F[1]) + fabs(F[2]);
}

/*
 * Along random trajectories, with every effect (payload and pin friction
 * with exact sign and regularised): the library's rps3_inverse (both
 * methods) equals the reference to TOL_EXACT (two exact formulations, rounding only, at
 * condition numbers ~10-100); the reference computed from a model whose
 * derived fields are NaN is the same to the last bit; and its double twin is
 * within TOL_EXACT too.
 */
static void check_model(rps3_model *base, uint64_t *seed) {
  rps3_model m[2], poisoned;
  rps3_data *d[2];
  rps3_traj tr;
  int n, k, i, meth;
  m[0] = m[1] = *base;
  m[0].opt.method = RPS3_LAGRANGE;
  m[1].opt.method = RPS3_NEWTON_EULER;
  for (meth = 0; meth < 2; meth++) {
    assert_int_equal(rps3_model_init(&m[meth], NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m[meth], &d[meth]), RPS3_OK);
  }
  poisoned = m[0];
  poison_derived(&poisoned);
  for (n = 0; n < 8; n++) {
    traj_random(&tr, seed);
    for (k = 0; k <= 40; k++) {
      double t = rps3_traj_duration(&tr) * k / 40, F[3], Fp[3], Fd[3];
      assert_int_equal(rps3_traj_eval(&m[0], &tr, t, d[0]->pose,
                                      d[0]->dpose, d[0]->ddpose),
                       RPS3_OK);
      copy_motion(d[1], d[0]);
      assert_int_equal(study_ref_forces(&m[0], m[0].opt.effects, d[0]->pose,
                                        d[0]->dpose, d[0]->ddpose, F),
                       0);
      assert_int_equal(study_ref_forces(&poisoned, m[0].opt.effects,
                                        d[0]->pose, d[0]->dpose,
                                        d[0]->ddpose, Fp),
                       0);
      assert_int_equal(study_ref_forces_double(&m[0], m[0].opt.effects,
                                               d[0]->pose, d[0]->dpose,
                                               d[0]->ddpose, Fd),
                       0);
      assert_memory_equal(F, Fp, sizeof(F));
      for (meth = 0; meth < 2; meth++)
        if (rps3_inverse(&m[meth], d[meth]) != RPS3_OK)
          fail_msg("t = %g: %s", t, d[meth]->err.msg);
      for (i = 0; i < 3; i++) {
        CHECK_REL(d[0]->F[i], F[i], TOL_EXACT, fscale(F),
                  "F%d Lagrange vs reference at t = %g", i, t);
        CHECK_REL(d[1]->F[i], F[i], TOL_EXACT, fscale(F),
                  "F%d Newton-Euler vs reference at t = %g", i, t);
        CHECK_REL(Fd[i], F[i], TOL_EXACT, fscale(F),
                  "F%d double twin at t = %g", i, t);
      }
    }
  }
  for (meth = 0; meth < 2; meth++) rps3_data_free(d[meth]);
}

static void matches_library_every_effect(void **state) {
  rps3_model m;
  uint64_t seed = 73561;
  (void)state;
  model_entropy(&m);
  check_model(&m, &seed);
  m.friction.vreg = 0.0371;
  check_model(&m, &seed);
}

/* the paper's model (Table II, point-mass links) on its own trajectory */
static void matches_library_paper(void **state) {
  rps3_model m;
  rps3_data *d;
  rps3_traj tr;
  int k, i;
  (void)state;
  rps3_model_default(&m);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (k = 0; k <= 100; k++) {
    double t = rps3_traj_duration(&tr) * k / 100, F[3];
    assert_int_equal(rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose),
                     RPS3_OK);
    assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
    assert_int_equal(study_ref_forces(&m, m.opt.effects, d->pose, d->dpose,
                                      d->ddpose, F),
                     0);
    for (i = 0; i < 3; i++)
      CHECK_REL(d->F[i], F[i], TOL_EXACT, fscale(F), "F%d at t = %g", i, t);
  }
  rps3_data_free(d);
}

/* a pose with a ball joint below the base plane is refused, not graded */
static void unreachable_refused(void **state) {
  rps3_model m;
  double q[3] = {0.37, 0.21, -0.05}, z[3] = {0, 0, 0}, F[3];
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(study_ref_forces(&m, RPS3_EFF_ALL, q, z, z, F), -1);
  assert_int_equal(study_ref_forces_double(&m, RPS3_EFF_ALL, q, z, z, F), -1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(matches_library_every_effect),
      cmocka_unit_test(matches_library_paper),
      cmocka_unit_test(unreachable_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
