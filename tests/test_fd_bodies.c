/*
 * test_fd_bodies.c - the forward dynamics, the energy and the simulation
 * of the general bodies (RPS3_BODIES_GENERAL): Mq l'' + hq = F inverts the
 * inverse dynamics of both formulations on random bodies with friction in
 * every joint, Mq is the inverse dynamics' columns (symmetric, positive
 * definite, 2T = l'^T Mq l' with T of rps3_energy), the paper's bodies
 * written as general ones give the paper path's answer, d(T + P)/dt is
 * the power put in, and a controller's model at a general plant's kept
 * state forms its own Mq and hq.  The simulation of a general plant is
 * tests/test_sim_bodies.c.
 */
#include <stdlib.h>

#include "testutil.h"

#include "bodies_random.h"
#include "fwddyn.h" /* the state part, as the simulation and controllers */

/* a random point of a random smooth trajectory through rps3_inverse */
static void random_state(const rps3_model *m, rps3_data *d, uint64_t *s) {
  rps3_traj tr;
  double t;
  traj_random(&tr, s);
  t = rnd_uniform(s, 0.0, tr.sine.duration);
  assert_int_equal(rps3_traj_eval(m, &tr, t, d->pose, d->dpose, d->ddpose),
                   RPS3_OK);
  if (rps3_inverse(m, d) != RPS3_OK) fail_msg("inverse: %s", d->err.msg);
}

/* the forward data starts on the inverse data's assembly mode */
static void load_state(rps3_data *f, const rps3_data *inv) {
  rps3_data_reset(f);
  memcpy(f->l, inv->l, sizeof(f->l));
  memcpy(f->dl, inv->dl, sizeof(f->dl));
  memcpy(f->F, inv->F, sizeof(f->F));
  memcpy(f->theta, inv->theta, sizeof(f->theta));
  f->have_theta = 1;
}

static double vmax(const double v[3]) {
  return fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
}

/* the largest |Mq_ij|: the scale of Mq's rounding */
static double mmax(double M[3][3]) {
  return fmax(vmax(M[0]), fmax(vmax(M[1]), vmax(M[2])));
}

/*
 * For every effect set with inertia, both formulations of the inverse
 * dynamics and random general bodies (friction in every joint): the
 * forces of a random motion give back its link accelerations, theta and
 * the platform's accelerations.  The residual Mq l''_ref + hq - F_ref is
 * backward error (TOL_PHYS); the accelerations are forward error, F_ref
 * and hq agreeing to ~1e-14 relative amplified by up to cond(Mq), hence
 * TOL_PHYS + 1e-14 cond(Mq) (test_fwddyn.c's reasoning); a missing or
 * wrong load term shows at >= 1e-3.
 */
static void inverts_inverse_dynamics(void **state) {
  uint64_t s = 0x6e4e4a1b0d1e5ull;
  int eff, meth, n, i, q;
  (void)state;
  for (meth = 0; meth < 2; meth++)
    for (eff = 1; eff <= RPS3_EFF_ALL; eff++) {
      rps3_model m;
      rps3_data *inv, *fd;
      if (!(eff & (RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA |
                   RPS3_EFF_PAYLOAD)))
        continue;
      random_general(&m, &s, meth ? RPS3_NEWTON_EULER : RPS3_LAGRANGE);
      m.opt.effects = eff;
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &inv), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &fd), RPS3_OK);
      for (n = 0; n < 6; n++) {
        double tol;
        random_state(&m, inv, &s);
        load_state(fd, inv);
        /* every other point the warm start is off, as an integrator's
           next stage: the solve has work to do */
        if (n % 2)
          for (i = 0; i < 3; i++) fd->theta[i] += 7.3e-4 * (i - 0.9);
        if (rps3_fwddyn(&m, fd) != RPS3_OK)
          fail_msg("effects %#x: %s", eff, fd->err.msg);
        tol = TOL_PHYS + 1e-14 * fd->Mcond;
        for (i = 0; i < 3; i++) {
          double r = fd->hq[i];
          CHECK_REL(fd->ddl[i], inv->ddl[i], tol, vmax(inv->ddl) + 1e-3,
                    "ddl%d effects %#x method %d", i, eff, meth);
          CHECK_REL(fd->theta[i], inv->theta[i], TOL_EXACT, 1.0, "theta%d", i);
          CHECK_REL(fd->ddtheta[i], inv->ddtheta[i], tol,
                    vmax(inv->ddtheta) + 1e-3, "ddtheta%d", i);
          CHECK_REL(fd->ac[i], inv->ac[i], tol, vmax(inv->ac) + 1e-3, "ac%d",
                    i);
          CHECK_REL(fd->domega[i], inv->domega[i], tol,
                    vmax(inv->domega) + 1e-3, "domega%d", i);
          for (q = 0; q < 3; q++) r += fd->Mq[i][q] * inv->ddl[q];
          CHECK_REL(r, inv->F[i], TOL_PHYS, vmax(inv->F) + 1e-6,
                    "Mq ddl + hq = F row %d effects %#x method %d", i, eff,
                    meth);
        }
        assert_true(fd->Mcond >= 1.0 && fd->Mcond < 1e9);
        assert_true((fd->stage & 7) == 7);
      }
      rps3_data_free(inv);
      rps3_data_free(fd);
    }
}

/* the Cholesky pivots of a symmetric A: all positive when it is positive
   definite (the smallest relative to its diagonal entry into *piv) */
static int cholesky_positive(const double A[3][3], double *piv) {
  double L[3][3] = {{0}}, d;
  int i, j, k;
  *piv = HUGE_VAL;
  for (j = 0; j < 3; j++) {
    d = A[j][j];
    for (k = 0; k < j; k++) d -= L[j][k] * L[j][k];
    if (!(d > 0.0)) return 0;
    *piv = fmin(*piv, d / A[j][j]);
    L[j][j] = sqrt(d);
    for (i = j + 1; i < 3; i++) {
      double x = A[i][j];
      for (k = 0; k < j; k++) x -= L[i][k] * L[j][k];
      L[i][j] = x / L[j][j];
    }
  }
  return 1;
}

/*
 * Mq column j is F(l'' = e_j) - F(l'' = 0) and hq is F(l'' = 0), both by
 * rps3_invdyn through the joint route, by each formulation (the
 * Newton-Euler one shares no load with the forward dynamics): Mq, formed
 * symmetric, is the columns to TOL_PHYS, so their own asymmetry is
 * rounding; it is positive definite (Cholesky pivots) and 2T = l'^T Mq l'
 * with T of rps3_energy, written from the bodies' motion (TOL_EXACT).
 */
static void mass_matrix_is_the_loads_columns(void **state) {
  uint64_t s = 0xc01d5eedull;
  int n, meth, i, j;
  (void)state;
  for (meth = 0; meth < 2; meth++) {
    rps3_model m;
    rps3_data *inv, *fd, *u;
    random_general(&m, &s, meth ? RPS3_NEWTON_EULER : RPS3_LAGRANGE);
    assert_int_equal(rps3_data_alloc(&m, &inv), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &fd), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &u), RPS3_OK);
    for (n = 0; n < 30; n++) {
      double F0[3], Mcol[3][3], T, P, twoT = 0.0, sc, sf, piv;
      random_state(&m, inv, &s);
      load_state(fd, inv);
      assert_int_equal(rps3_fwddyn(&m, fd), RPS3_OK);
      for (j = -1; j < 3; j++) {
        load_state(u, inv);
        assert_int_equal(rps3_theta_solve(&m, u), RPS3_OK);
        assert_int_equal(rps3_joint_velocity(&m, u), RPS3_OK);
        for (i = 0; i < 3; i++) u->ddl[i] = (i == j) ? 1.0 : 0.0;
        assert_int_equal(rps3_joint_acceleration(&m, u), RPS3_OK);
        assert_int_equal(rps3_invdyn(&m, u), RPS3_OK);
        for (i = 0; i < 3; i++) {
          if (j < 0)
            F0[i] = u->F[i];
          else
            Mcol[i][j] = u->F[i] - F0[i];
        }
      }
      sc = mmax(fd->Mq);
      sf = vmax(F0);
      for (i = 0; i < 3; i++) {
        CHECK_REL(fd->hq[i], F0[i], TOL_PHYS, sf, "hq%d method %d", i, meth);
        for (j = 0; j < 3; j++) {
          /* a difference of two forces of size |hq| */
          CHECK_REL(fd->Mq[i][j], Mcol[i][j], TOL_PHYS, sc + sf,
                    "Mq[%d][%d] method %d", i, j, meth);
          assert_true(fd->Mq[i][j] == fd->Mq[j][i]);
          twoT += fd->dl[i] * fd->Mq[i][j] * fd->dl[j];
        }
      }
      assert_true(cholesky_positive((const double(*)[3])fd->Mq, &piv));
      assert_int_equal(rps3_energy(&m, fd, &T, &P, NULL), RPS3_OK);
      CHECK_REL(twoT, 2.0 * T, TOL_EXACT, 2.0 * T, "2T = dl' Mq dl");
    }
    rps3_data_free(inv);
    rps3_data_free(fd);
    rps3_data_free(u);
  }
}

/*
 * The paper's bodies written as general ones (the disc, point-mass links,
 * massless pistons, the same friction) give the paper path's Mq, hq, ddl
 * (Gram form and bias_force of src/loads.h) and energies, every effect
 * selected: two exact formulas, TOL_EXACT of each quantity's scale (the
 * accelerations' amplified by cond(Mq), measured below 1e3 here).
 */
static void paper_bodies_are_a_special_case(void **state) {
  uint64_t s = 0x9a9e4b0d1e5ull;
  rps3_model p, g;
  rps3_data *inv, *dp, *dg;
  int n, i, j;
  (void)state;
  model_entropy(&p);
  for (i = 0; i < 3; i++) {
    p.leg[i].prismatic.viscous = 0.31 + 0.07 * i;
    p.leg[i].prismatic.coulomb = 0.047;
    p.leg[i].prismatic.vreg = 1e-3;
  }
  p.friction.vreg = 0.01;
  paper_as_general(&p, &g);
  assert_int_equal(rps3_model_init(&p, NULL), RPS3_OK);
  assert_int_equal(rps3_model_init(&g, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&p, &inv), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&p, &dp), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&g, &dg), RPS3_OK);
  for (n = 0; n < 40; n++) {
    double Tp, Pp, Fp, Tg, Pg, Fg, sc, sh;
    random_state(&p, inv, &s);
    load_state(dp, inv);
    load_state(dg, inv);
    assert_int_equal(rps3_fwddyn(&p, dp), RPS3_OK);
    assert_int_equal(rps3_fwddyn(&g, dg), RPS3_OK);
    assert_true(dp->Mcond < 1e3);
    sc = mmax(dp->Mq);
    sh = vmax(dp->hq) + sc;
    for (i = 0; i < 3; i++) {
      CHECK_REL(dg->ddl[i], dp->ddl[i], TOL_EXACT, vmax(dp->ddl) + 1e-3,
                "ddl%d", i);
      CHECK_REL(dg->hq[i], dp->hq[i], TOL_EXACT, sh, "hq%d", i);
      for (j = 0; j < 3; j++)
        CHECK_REL(dg->Mq[i][j], dp->Mq[i][j], TOL_EXACT, sc, "Mq[%d][%d]", i,
                  j);
    }
    assert_int_equal(rps3_energy(&p, dp, &Tp, &Pp, &Fp), RPS3_OK);
    assert_int_equal(rps3_energy(&g, dg, &Tg, &Pg, &Fg), RPS3_OK);
    CHECK_REL(Tg, Tp, TOL_EXACT, fabs(Tp), "T");
    CHECK_REL(Pg, Pp, TOL_EXACT, fabs(Pp), "P");
    CHECK_REL(Fg, Fp, TOL_EXACT, fabs(Fp), "friction power");
  }
  rps3_data_free(inv);
  rps3_data_free(dp);
  rps3_data_free(dg);
}

/*
 * rps3_energy of the general bodies against the power balance, without
 * Mq: along a trajectory, d(T + P)/dt by central differences (h = 1e-5 s,
 * TOL_FD) is the actuators' power F . l' of rps3_invdyn plus the
 * friction's (pins and prismatic joints, regularised so that it is
 * smooth), which rps3_energy and rps3_invdyn's certificate agree on.
 */
static void energy_rate_is_the_power(void **state) {
  uint64_t s = 0xe1e7a7eull;
  rps3_model m;
  rps3_data *d;
  rps3_traj tr;
  const double h = 1e-5;
  int n, k;
  (void)state;
  random_general(&m, &s, RPS3_LAGRANGE);
  m.opt.outputs |= RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 20; n++) {
    double t, E[2], pw, fr, T, P;
    traj_random(&tr, &s);
    t = rnd_uniform(&s, 0.1, tr.sine.duration - 0.1);
    for (k = 0; k < 2; k++) {
      assert_int_equal(rps3_traj_eval(&m, &tr, t + (k ? h : -h), d->pose,
                                      d->dpose, d->ddpose),
                       RPS3_OK);
      assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
      assert_int_equal(rps3_energy(&m, d, &T, &P, NULL), RPS3_OK);
      E[k] = T + P;
    }
    assert_int_equal(rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose),
                     RPS3_OK);
    assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
    assert_int_equal(rps3_energy(&m, d, &T, &P, &fr), RPS3_OK);
    pw = d->F[0] * d->dl[0] + d->F[1] * d->dl[1] + d->F[2] * d->dl[2];
    CHECK_REL((E[1] - E[0]) / (2 * h), pw + fr, TOL_FD,
              fabs(pw) + fabs(fr) + d->energy_scale, "d(T+P)/dt at t = %g", t);
    CHECK_REL(fr, d->friction_power, TOL_EXACT, fabs(fr) + 1e-12,
              "friction power");
  }
  rps3_data_free(d);
}
/*
 * A controller's general model at a general plant's kept state
 * (rps3_fwddyn_state_shared: the plant's kinematics, the model's own Mq
 * and hq from the plane, positions NaN in its data) forms what its own
 * lean evaluation forms (theta from its own solve, 1e-10), for the
 * plant's model (its Mq, hq taken) and for other bodies and friction.
 */
static void shared_state_is_own_state(void **state) {
  uint64_t seed = 0x54a3edull;
  rps3_model pm, cm[2];
  rps3_data *ref, *pd, *cd, *od;
  rps3_fd_state *pk = calloc(1, sizeof(*pk)), *ck = calloc(1, sizeof(*ck)),
                *ok = calloc(1, sizeof(*ok));
  int n, v, i, j, st;
  (void)state;
  assert_non_null(pk);
  assert_non_null(ck);
  assert_non_null(ok);
  random_general(&pm, &seed, RPS3_LAGRANGE);
  pm.opt.effects &= ~RPS3_EFF_PAYLOAD; /* a payload is never shared */
  assert_int_equal(rps3_model_init(&pm, NULL), RPS3_OK);
  cm[0] = pm;
  random_general(&cm[1], &seed, RPS3_NEWTON_EULER);
  cm[1].opt.effects = pm.opt.effects;
  assert_int_equal(rps3_model_init(&cm[1], NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&pm, &ref), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&pm, &pd), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&pm, &cd), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&pm, &od), RPS3_OK);
  for (n = 0; n < 30; n++) {
    random_state(&pm, ref, &seed);
    memset(pk, 0, sizeof(*pk));
    load_state(pd, ref);
    if (rps3_fwddyn_state(&pm, pd, pk, RPS3_FD_LEAN | RPS3_FD_KEEP) != RPS3_OK)
      fail_msg("plant: %s", pd->err.msg);
    for (v = 0; v < 2; v++) {
      double fs;
      memset(ck, 0, sizeof(*ck));
      memset(ok, 0, sizeof(*ok));
      load_state(cd, ref);
      load_state(od, ref);
      assert_int_equal(rps3_fwddyn_state_shared(&cm[v], cd, ck, &pm, pk, &st),
                       1);
      if (st != RPS3_OK) fail_msg("shared: %s", cd->err.msg);
      if (rps3_fwddyn_state(&cm[v], od, ok, RPS3_FD_LEAN | RPS3_FD_NOFACTOR) !=
          RPS3_OK)
        fail_msg("own: %s", od->err.msg);
      fs = vmax(od->hq) + mmax(od->Mq);
      for (i = 0; i < 3; i++) {
        CHECK_REL(cd->hq[i], od->hq[i], 1e-10, fs, "n %d model %d hq%d", n, v,
                  i);
        for (j = 0; j < 3; j++)
          CHECK_REL(cd->Mq[i][j], od->Mq[i][j], 1e-10, fs,
                    "n %d model %d Mq%d%d", n, v, i, j);
      }
      assert_true(isnan(cd->b[1][2]) && isnan(cd->ddl[0]));
    }
  }
  rps3_data_free(ref);
  rps3_data_free(pd);
  rps3_data_free(cd);
  rps3_data_free(od);
  free(pk);
  free(ck);
  free(ok);
}

/* general bodies without a mass where an inertia effect is selected:
   RPS3_EINVAL with the message, no acceleration; rates whose squares
   overflow in the bodies' loads: a status, never a number */
static void no_inertia_refused(void **state) {
  uint64_t seed = 0x0a55ull;
  rps3_model m;
  rps3_data *d, *inv;
  int i, st;
  (void)state;
  random_general(&m, &seed, RPS3_LAGRANGE);
  assert_int_equal(rps3_data_alloc(&m, &inv), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  random_state(&m, inv, &seed);
  load_state(d, inv);
  for (i = 0; i < 3; i++) d->dl[i] *= 1e200;
  st = rps3_fwddyn(&m, d);
  assert_true(st == RPS3_ERANGE || st == RPS3_ESING);
  for (i = 0; i < 3; i++) assert_true(isnan(d->ddl[i]));
  /* the platform's inertia alone, of a massless platform */
  memset(&m.platform, 0, sizeof(m.platform));
  m.opt.effects = RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_PLATFORM_GRAVITY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  load_state(d, inv);
  assert_int_equal(rps3_fwddyn(&m, d), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "needs inertia"));
  for (i = 0; i < 3; i++) assert_true(isnan(d->ddl[i]));
  /* the legs' inertia, of massless legs */
  for (i = 0; i < 3; i++) {
    memset(&m.leg[i].cylinder, 0, sizeof(rps3_body));
    memset(&m.leg[i].piston, 0, sizeof(rps3_body));
  }
  m.opt.effects = RPS3_EFF_LINK_INERTIA | RPS3_EFF_LINK_GRAVITY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  load_state(d, inv);
  assert_int_equal(rps3_fwddyn(&m, d), RPS3_EINVAL);
  rps3_data_free(inv);
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(inverts_inverse_dynamics),
      cmocka_unit_test(mass_matrix_is_the_loads_columns),
      cmocka_unit_test(paper_bodies_are_a_special_case),
      cmocka_unit_test(energy_rate_is_the_power),
      cmocka_unit_test(shared_state_is_own_state),
      cmocka_unit_test(no_inertia_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
