/*
 * test_bodies.c - the general model's bodies (rps3_model.bodies =
 * RPS3_BODIES_GENERAL): the paper's bodies as a special case of them, the
 * two formulations on general bodies, the energy-rate certificate written
 * from the bodies' motion, and the regressor of the standard parameters.
 * tests/test_ident_std.py checks the same forces against an independent
 * regressor (tests/ident_oracle.py).
 */
#include "testutil.h"

#include "bodies_random.h"

static void run_at(const rps3_model *m, rps3_data *d, const rps3_traj *tr,
                   double t) {
  int st;
  /* t a fraction of the span */
  t *= rps3_traj_duration(tr) / 3.4;
  assert_int_equal(rps3_traj_eval(m, tr, t, d->pose, d->dpose, d->ddpose),
                   RPS3_OK);
  st = rps3_inverse(m, d);
  if (st != RPS3_OK) fail_msg("t %g: %s", t, d->err.msg);
}

/* the forces' scale: the largest share */
static double fscale(const rps3_data *d) {
  double s = 1e-300;
  int e, i;
  for (e = 0; e < RPS3_NEFFECT; e++)
    for (i = 0; i < 3; i++)
      if (fabs(d->F_effect[e][i]) > s) s = fabs(d->F_effect[e][i]);
  return s;
}

/* the paper's bodies written as general ones give every effect's share
   to rounding, by both formulations, with prismatic friction too */
static void paper_is_a_special_case(void **state) {
  rps3_model p, g;
  rps3_data *dp, *dg;
  rps3_traj tr;
  uint64_t seed = 4242;
  int meth, n, k, e, i;
  (void)state;
  for (meth = 0; meth < 2; meth++)
    for (n = 0; n < 4; n++) {
      model_entropy(&p);
      p.opt.method = meth;
      for (i = 0; i < 3; i++) {
        p.leg[i].prismatic.viscous = 0.3 + 0.1 * i;
        p.leg[i].prismatic.coulomb = 0.05;
        p.leg[i].prismatic.vreg = 1e-3;
      }
      paper_as_general(&p, &g);
      assert_int_equal(rps3_model_init(&p, NULL), RPS3_OK);
      assert_int_equal(rps3_model_init(&g, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&p, &dp), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&g, &dg), RPS3_OK);
      traj_random(&tr, &seed);
      for (k = 0; k <= 20; k++) {
        run_at(&p, dp, &tr, 0.13 * k);
        run_at(&g, dg, &tr, 0.13 * k);
        for (e = 0; e < RPS3_NEFFECT; e++)
          for (i = 0; i < 3; i++)
            CHECK_REL(dg->F_effect[e][i], dp->F_effect[e][i], TOL_EXACT,
                      fscale(dp), "%s, method %d, t %g", rps3_effect_name(e),
                      meth, 0.13 * k);
        CHECK_REL(dg->energy_residual, 0.0, TOL_PHYS, dg->energy_scale,
                  "certificate of the general bodies");
        CHECK_REL(dg->dTdt, dp->dTdt, TOL_EXACT, dp->energy_scale, "dT/dt");
        CHECK_REL(dg->dPdt, dp->dPdt, TOL_EXACT, dp->energy_scale, "dP/dt");
      }
      rps3_data_free(dp);
      rps3_data_free(dg);
    }
}

/* on general bodies the Lagrange route (the platform through its ball
   joints) and Newton-Euler (the platform as a free body) agree, and each
   effect alone meets its energy balance, written from the bodies' motion */
static void general_bodies_two_formulations(void **state) {
  rps3_model ml, mn, one;
  rps3_data *dl, *dn, *d1;
  rps3_traj tr;
  uint64_t seed = 991, s2;
  int n, k, i, e;
  (void)state;
  for (n = 0; n < 6; n++) {
    s2 = seed + 17 * (uint64_t)n;
    random_general(&ml, &s2, RPS3_LAGRANGE);
    mn = ml;
    mn.opt.method = RPS3_NEWTON_EULER;
    assert_int_equal(rps3_model_init(&mn, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&ml, &dl), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&mn, &dn), RPS3_OK);
    traj_random(&tr, &seed);
    for (k = 0; k <= 20; k++) {
      run_at(&ml, dl, &tr, 0.11 * k);
      run_at(&mn, dn, &tr, 0.11 * k);
      for (e = 0; e < RPS3_NEFFECT; e++)
        for (i = 0; i < 3; i++)
          CHECK_REL(dn->F_effect[e][i], dl->F_effect[e][i], TOL_PHYS,
                    fscale(dl), "%s", rps3_effect_name(e));
      CHECK_REL(dl->energy_residual, 0.0, TOL_PHYS, dl->energy_scale,
                "energy, Lagrange");
      CHECK_REL(dn->energy_residual, 0.0, TOL_PHYS, dn->energy_scale,
                "energy, Newton-Euler");
    }
    for (e = 0; e < RPS3_NEFFECT; e++) {
      one = ml;
      one.opt.effects = 1 << e;
      assert_int_equal(rps3_model_init(&one, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&one, &d1), RPS3_OK);
      for (k = 0; k <= 10; k++) {
        run_at(&one, d1, &tr, 0.2 * k);
        CHECK_REL(d1->energy_residual, 0.0, TOL_PHYS, d1->energy_scale,
                  "%s alone", rps3_effect_name(e));
      }
      rps3_data_free(d1);
    }
    rps3_data_free(dl);
    rps3_data_free(dn);
  }
}

/* Y pi = F for the standard parameters, both methods, general and paper
   bodies; a batch equals the points */
static void regressor_std_equals_forces(void **state) {
  rps3_model m;
  rps3_data *d;
  rps3_traj tr;
  double Y[3][RPS3_NSTD], pi[RPS3_NSTD];
  uint64_t seed = 31337;
  int n, k, i, j;
  (void)state;
  for (n = 0; n < 8; n++) {
    if (n % 2)
      random_general(&m, &seed, n % 4 == 1 ? RPS3_LAGRANGE : RPS3_NEWTON_EULER);
    else {
      model_entropy(&m);
      m.opt.method = n % 4 == 0 ? RPS3_LAGRANGE : RPS3_NEWTON_EULER;
      m.leg[1].prismatic.viscous = 0.4;
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    }
    assert_int_equal(rps3_std_params(&m, pi), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    traj_random(&tr, &seed);
    for (k = 0; k <= 15; k++) {
      double F[3];
      run_at(&m, d, &tr, 0.17 * k);
      for (i = 0; i < 3; i++) F[i] = d->F[i];
      assert_int_equal(rps3_regressor_std(&m, d, Y), RPS3_OK);
      for (i = 0; i < 3; i++) {
        double f = 0.0, s = 0.0;
        for (j = 0; j < RPS3_NSTD; j++) {
          f += Y[i][j] * pi[j];
          s += fabs(Y[i][j] * pi[j]);
        }
        CHECK_REL(f, F[i], TOL_EXACT, s, "model %d point %d row %d", n, k, i);
      }
    }
    rps3_data_free(d);
  }
  assert_string_equal(rps3_std_name(0), "platform.m");
  assert_string_equal(rps3_std_name(29), "piston1.Izz");
  assert_string_equal(rps3_std_name(70), "prismatic1.fv");
  assert_string_equal(rps3_std_name(81), "pin3.fc");
  assert_string_equal(rps3_std_unit(81), "N m");
  assert_string_equal(rps3_std_unit(71), "N");
  assert_null(rps3_std_name(RPS3_NSTD));
}

/* a body that is not a real one is refused, its field named */
static void refuses_unreal_bodies(void **state) {
  rps3_model m;
  rps3_check chk;
  (void)state;
  rps3_model_default(&m);
  m.leg[1].piston.mass = 0.1;
  m.leg[1].piston.inertia[0] = 1e-3; /* Ixx > Iyy + Izz */
  m.leg[1].piston.inertia[3] = 1e-4;
  m.leg[1].piston.inertia[5] = 1e-4;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_LEG2_PISTON_INERTIA);
  assert_non_null(strstr(chk.msg, "leg2.piston.inertia"));
  /* 2 % above the sum of the other two: the triangle inequality, named */
  m.leg[1].piston.inertia[0] = 1.02 * 2e-4;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_LEG2_PISTON_INERTIA);
  assert_non_null(strstr(chk.msg, "triangle inequality"));
  /* at the limit (a rod's moments): a real body */
  m.leg[1].piston.inertia[0] = 2e-4;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_OK);
  rps3_model_default(&m);
  m.platform.inertia[0] = m.platform.inertia[3] = m.platform.inertia[5] = 1.0;
  m.platform.inertia[1] = 2.0; /* products too large */
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_PLATFORM_BODY_INERTIA);
  rps3_model_default(&m);
  m.leg[2].cylinder.com[1] = (double)NAN;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_LEG3_CYLINDER_COM);
  assert_int_equal(chk.comp, 1);
  rps3_model_default(&m);
  m.leg[0].prismatic.coulomb = -1.0;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_LEG1_PRISMATIC_COULOMB);
  /* the paper parameters do not hold general bodies or prismatic
     friction */
  {
    double pi[RPS3_NPAPER];
    rps3_model_default(&m);
    m.bodies = RPS3_BODIES_GENERAL;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_paper_params(&m, pi, &chk), RPS3_EINVAL);
    assert_non_null(strstr(chk.msg, "general bodies"));
    rps3_model_default(&m);
    m.opt.effects |= RPS3_EFF_PRISMATIC_FRICTION;
    m.leg[2].prismatic.coulomb = 0.1;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_paper_params(&m, pi, &chk), RPS3_EINVAL);
    assert_non_null(strstr(chk.msg, "prismatic friction"));
  }
  rps3_model_default(&m);
  m.bodies = 2;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_F_BODIES);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(paper_is_a_special_case),
      cmocka_unit_test(general_bodies_two_formulations),
      cmocka_unit_test(regressor_std_equals_forces),
      cmocka_unit_test(refuses_unreal_bodies),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
