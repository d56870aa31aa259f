/* test_invdyn.c - inverse dynamics (21)-(24), (34): energy rate, Lagrange =
   Newton-Euler, separability of effects, a static closed form, errors. */
#include "testutil.h"

static void run_point(const rps3_model *m, rps3_data *d, const rps3_traj *tr,
                      double t) {
  assert_int_equal(rps3_traj_eval(m, tr, t, d->pose, d->dpose, d->ddpose),
                   RPS3_OK);
  if (rps3_inverse(m, d) != RPS3_OK)
    fail_msg("t = %g: %s", t, d->err.msg);
}

static double fscale(const rps3_data *d) {
  return fabs(d->F[0]) + fabs(d->F[1]) + fabs(d->F[2]);
}

/*
 * Along a trajectory: the energy-rate residual is zero, and the two
 * formulations agree, for method-independent data.
 */
static void check_trajectory(const rps3_model *base, const rps3_traj *tr,
                             int samples) {
  rps3_model ml = *base, mn = *base;
  rps3_data *dl, *dn;
  int k, i, e;
  ml.opt.method = RPS3_LAGRANGE;
  mn.opt.method = RPS3_NEWTON_EULER;
  assert_int_equal(rps3_model_init(&ml, NULL), RPS3_OK);
  assert_int_equal(rps3_model_init(&mn, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&ml, &dl), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&mn, &dn), RPS3_OK);
  for (k = 0; k <= samples; k++) {
    double t = rps3_traj_duration(tr) * k / samples, s;
    run_point(&ml, dl, tr, t);
    run_point(&mn, dn, tr, t);
    assert_true(dl->has_lambda && !dn->has_lambda);
    CHECK_REL(dl->energy_residual, 0.0, TOL_PHYS, dl->energy_scale,
              "Lagrange energy residual at t = %g", t);
    CHECK_REL(dn->energy_residual, 0.0, TOL_PHYS, dn->energy_scale,
              "Newton-Euler energy residual at t = %g", t);
    s = fscale(dl);
    for (i = 0; i < 3; i++) {
      double sum = 0.0;
      CHECK_REL(dn->F[i], dl->F[i], TOL_PHYS, s, "F%d L vs NE at t = %g", i, t);
      for (e = 0; e < RPS3_NEFFECT; e++) {
        CHECK_REL(dn->F_effect[e][i], dl->F_effect[e][i], TOL_PHYS, s,
                  "%s share L vs NE", rps3_effect_name(e));
        sum += dl->F_effect[e][i];
        if (!(base->opt.effects & (1 << e)))
          assert_true(dl->F_effect[e][i] == 0.0);
      }
      CHECK_REL(sum, dl->F[i], TOL_EXACT, s, "shares sum to F");
    }
  }
  rps3_data_free(dl);
  rps3_data_free(dn);
}

static void paper_trajectory(void **state) {
  rps3_model m;
  rps3_traj tr;
  (void)state;
  rps3_model_default(&m);
  rps3_traj_default(&tr);
  check_trajectory(&m, &tr, 400);
  m.opt.effects = RPS3_EFF_ALL;
  m.payload.mass = 0.05;
  m.payload.com[2] = 0.02;
  m.payload.inertia[0] = m.payload.inertia[1] = 2e-5;
  m.payload.inertia[2] = 3e-5;
  m.friction.viscous = 0.01;
  check_trajectory(&m, &tr, 400);
}

static void random_trajectories(void **state) {
  rps3_model m;
  rps3_traj tr;
  uint64_t seed = 60221;
  int n;
  (void)state;
  model_entropy(&m);
  for (n = 0; n < 12; n++) {
    traj_random(&tr, &seed);
    check_trajectory(&m, &tr, 60);
  }
}

/* a run with one effect gives that effect's share of the all-effects run */
static void effects_separate(void **state) {
  rps3_model all, one;
  rps3_data *da, *d1;
  rps3_traj tr;
  uint64_t seed = 8812;
  int e, k, i;
  (void)state;
  model_entropy(&all);
  assert_int_equal(rps3_model_init(&all, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&all, &da), RPS3_OK);
  traj_random(&tr, &seed);
  for (e = 0; e < RPS3_NEFFECT; e++) {
    one = all;
    one.opt.effects = 1 << e;
    assert_int_equal(rps3_model_init(&one, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&one, &d1), RPS3_OK);
    for (k = 0; k <= 20; k++) {
      double t = 0.1 * k;
      run_point(&all, da, &tr, t);
      run_point(&one, d1, &tr, t);
      /* and each effect alone satisfies its own energy balance */
      CHECK_REL(d1->energy_residual, 0.0, TOL_PHYS, d1->energy_scale,
                "%s alone: energy", rps3_effect_name(e));
      for (i = 0; i < 3; i++)
        CHECK_REL(d1->F[i], da->F_effect[e][i], TOL_EXACT, fscale(da),
                  "%s alone vs share", rps3_effect_name(e));
    }
    rps3_data_free(d1);
  }
  rps3_data_free(da);
}

/*
 * Every subset of opt.outputs, both methods and both theta routes, on
 * random trajectories of the high-entropy model: a result whose bit is set
 * equals the default's (every output) to rounding (TOL_EXACT of the
 * forces' scale: the summed solve without shares), a result whose bit is
 * not set is NaN, and status and warn are the default's.  At the singular
 * pose (the lambda system's zero determinant) every subset is RPS3_ESING,
 * and a lowered trans_warn warns whatever the bits (the transmission check
 * is decided without RPS3_OUT_TRANSMISSION too).
 */
static void outputs_each_bit(void **state) {
  rps3_model full, sub;
  rps3_data *df, *ds;
  rps3_traj tr;
  uint64_t seed = 9131;
  int method, route, bits, k, i, e;
  (void)state;
  for (method = 0; method < 2; method++)
    for (route = 0; route < 2; route++)
      for (bits = 0; bits <= RPS3_OUT_ALL; bits++) {
        model_entropy(&full);
        full.opt.method = (rps3_method)method;
        full.opt.theta = (rps3_theta_route)route;
        sub = full;
        sub.opt.outputs = bits;
        assert_int_equal(rps3_model_init(&full, NULL), RPS3_OK);
        assert_int_equal(rps3_model_init(&sub, NULL), RPS3_OK);
        assert_int_equal(rps3_data_alloc(&full, &df), RPS3_OK);
        assert_int_equal(rps3_data_alloc(&sub, &ds), RPS3_OK);
        traj_random(&tr, &seed);
        for (k = 0; k <= 10; k++) {
          double t = 0.2 * k, fs;
          run_point(&full, df, &tr, t);
          run_point(&sub, ds, &tr, t);
          assert_int_equal(ds->warn, df->warn);
          fs = fscale(df);
          assert_true(ds->cond == ds->cond);
          CHECK_REL(ds->cond, df->cond, TOL_EXACT * df->cond, 1.0, "cond");
          for (i = 0; i < 3; i++) {
            if (bits & RPS3_OUT_FORCES)
              CHECK_REL(ds->F[i], df->F[i], TOL_EXACT, fs, "F%d bits %#x", i,
                        bits);
            else
              assert_true(isnan(ds->F[i]));
            for (e = 0; e < RPS3_NEFFECT; e++)
              if (bits & RPS3_OUT_EFFECTS)
                assert_true(ds->F_effect[e][i] == df->F_effect[e][i]);
              else
                assert_true(isnan(ds->F_effect[e][i]));
            if ((bits & RPS3_OUT_LAMBDA) && method == RPS3_LAGRANGE)
              CHECK_REL(ds->lambda[i], df->lambda[i], TOL_EXACT,
                        fabs(df->lambda[0]) + fabs(df->lambda[1]) +
                            fabs(df->lambda[2]) + 1e-300,
                        "lambda%d", i);
            else
              assert_true(isnan(ds->lambda[i]) && !ds->has_lambda);
            if ((bits & RPS3_OUT_THETA) || route == RPS3_THETA_MULTIROOT)
              assert_true(ds->theta[i] == df->theta[i]);
            else
              assert_true(isnan(ds->theta[i]));
          }
          if (bits & RPS3_OUT_TRANSMISSION)
            CHECK_REL(ds->transmission, df->transmission, TOL_EXACT,
                      df->transmission, "transmission");
          else
            assert_true(isnan(ds->transmission));
          if (bits & RPS3_OUT_CERTIFY)
            CHECK_REL(ds->energy_residual, df->energy_residual, TOL_EXACT,
                      df->energy_scale + 1e-300, "energy residual");
          else
            assert_true(isnan(ds->energy_residual) &&
                        isnan(ds->energy_scale) && isnan(ds->power));
        }
        rps3_data_free(df);
        rps3_data_free(ds);
      }
  /* the checks with every subset: the singular pose, a lowered trans_warn */
  for (bits = 0; bits <= RPS3_OUT_ALL; bits++)
    for (route = 0; route < 2; route++) {
      double bs;
      rps3_model_default(&sub);
      sub.opt.outputs = bits;
      sub.opt.theta = (rps3_theta_route)route;
      assert_int_equal(rps3_model_init(&sub, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&sub, &ds), RPS3_OK);
      bs = singular_beta(&sub, ds, 0.25, 0.6, 1.0);
      ds->pose[0] = 0.0;
      ds->pose[1] = bs;
      ds->pose[2] = 0.25;
      for (i = 0; i < 3; i++) ds->dpose[i] = ds->ddpose[i] = 0.0;
      if (route == RPS3_THETA_CLOSED_FORM)
        assert_int_equal(rps3_inverse(&sub, ds), RPS3_ESING);
      rps3_data_free(ds);
      /* a transmission of 2.4 above a warning threshold of 2 */
      sub.opt.trans_warn = 2.0;
      sub.opt.theta = RPS3_THETA_CLOSED_FORM;
      assert_int_equal(rps3_model_init(&sub, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&sub, &ds), RPS3_OK);
      ds->pose[0] = 0.3;
      ds->pose[1] = 0.0;
      ds->pose[2] = sub.R;
      assert_int_equal(rps3_inverse(&sub, ds), RPS3_OK);
      assert_true(ds->warn & RPS3_WARN_TRANS);
      /* and a trans_max below it: RPS3_ESING */
      sub.opt.trans_max = 2.1;
      assert_int_equal(rps3_model_init(&sub, NULL), RPS3_OK);
      assert_int_equal(rps3_inverse(&sub, ds), RPS3_ESING);
      rps3_data_free(ds);
    }
}

/*
 * outputs without RPS3_OUT_EFFECTS and RPS3_OUT_THETA (F, lambda and the
 * transmission) give the default's forces from the summed loads: the same F
 * to rounding (1e-15 of the forces' scale seen; TOL_EXACT), the same
 * lambda, cond and warnings, the shares NaN, and on the closed-form route
 * theta NaN.  Both methods, both theta routes, every
 * effect, high-entropy parameters along random trajectories.
 */
static void summed_forces_match(void **state) {
  rps3_model full, fo;
  rps3_data *df, *dfo;
  rps3_traj tr;
  uint64_t seed = 4471;
  int method, route, n, k, i, e;
  (void)state;
  for (method = 0; method < 2; method++)
    for (route = 0; route < 2; route++) {
      model_entropy(&full);
      full.opt.method = (rps3_method)method;
      full.opt.theta = (rps3_theta_route)route;
      full.opt.outputs &= ~RPS3_OUT_CERTIFY;
      fo = full;
      fo.opt.outputs = RPS3_OUT_FORCES | RPS3_OUT_LAMBDA | RPS3_OUT_TRANSMISSION;
      assert_int_equal(rps3_model_init(&full, NULL), RPS3_OK);
      assert_int_equal(rps3_model_init(&fo, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&full, &df), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&fo, &dfo), RPS3_OK);
      for (n = 0; n < 4; n++) {
        traj_random(&tr, &seed);
        for (k = 0; k <= 40; k++) {
          double t = 0.05 * k;
          run_point(&full, df, &tr, t);
          run_point(&fo, dfo, &tr, t);
          assert_true(dfo->cond == df->cond && dfo->warn == df->warn);
          for (i = 0; i < 3; i++) {
            CHECK_REL(dfo->F[i], df->F[i], TOL_EXACT, fscale(df),
                      "summed F%d (method %d, route %d)", i, method,
                      route);
            if (method == RPS3_LAGRANGE)
              CHECK_REL(dfo->lambda[i], df->lambda[i], TOL_EXACT,
                        fabs(df->lambda[0]) + fabs(df->lambda[1]) +
                            fabs(df->lambda[2]) + 1e-300,
                        "summed lambda%d", i);
            else /* Newton-Euler has no multipliers: NaN */
              assert_true(isnan(dfo->lambda[i]) && isnan(df->lambda[i]) &&
                          !dfo->has_lambda && !df->has_lambda);
            for (e = 0; e < RPS3_NEFFECT; e++)
              assert_true(isnan(dfo->F_effect[e][i]));
            if (route == RPS3_THETA_CLOSED_FORM)
              assert_true(isnan(dfo->theta[i]));
            else
              assert_true(dfo->theta[i] == df->theta[i]);
          }
        }
      }
      rps3_data_free(df);
      rps3_data_free(dfo);
    }
}

/* the outputs of rps3_invdyn, bit for bit */
static int same_dynamics(const rps3_data *a, const rps3_data *b) {
  return memcmp(a->F, b->F, sizeof(a->F)) == 0 &&
         memcmp(a->F_effect, b->F_effect, sizeof(a->F_effect)) == 0 &&
         memcmp(a->lambda, b->lambda, sizeof(a->lambda)) == 0 &&
         memcmp(&a->cond, &b->cond, sizeof(double)) == 0 &&
         memcmp(&a->transmission, &b->transmission, sizeof(double)) == 0 &&
         memcmp(&a->energy_residual, &b->energy_residual, sizeof(double)) ==
             0 &&
         a->warn == b->warn;
}

/*
 * rps3_inverse builds the constraint Jacobian once a point and hands it to
 * its later stages; the theta solve reuses the trig of its last
 * evaluation.  Neither may ever be stale: (a) rps3_invdyn called again on
 * the data rps3_inverse left (building its own Jacobian from the
 * positions) gives its outputs bit for bit; (b) a caller that moves the
 * positions between calls (here by rps3_ik and the rate stages of another
 * point) gets that point's forces, those of a fresh workspace; (c) a warm
 * start from a theta the caller changed (by one ulp) solves as a fresh
 * workspace started there: the multiroot route's predicted start is taken
 * only from the root it kept, while d->theta is that root bit for bit
 * (from the unchanged root the two solves agree to the tolerance).  Both
 * routes and methods, certificate on, high-entropy parameters along
 * random trajectories.
 */
static void shared_jacobian_never_stale(void **state) {
  rps3_model m, mc;
  rps3_data *d, *e, *g;
  struct rps3_solver_state *es;
  rps3_traj tr;
  uint64_t seed = 9127;
  int method, route, n, k;
  (void)state;
  for (method = 0; method < 2; method++)
    for (route = 0; route < 2; route++) {
      model_entropy(&m);
      m.opt.method = (rps3_method)method;
      m.opt.theta = (rps3_theta_route)route;
      m.opt.outputs |= RPS3_OUT_CERTIFY;
      mc = m;
      mc.opt.theta = RPS3_THETA_CLOSED_FORM;
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      assert_int_equal(rps3_model_init(&mc, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &e), RPS3_OK);
      es = e->solver;
      for (n = 0; n < 3; n++) {
        traj_random(&tr, &seed);
        for (k = 0; k <= 40; k++) {
          run_point(&m, d, &tr, 0.05 * k);
          /* (a) */
          *e = *d;
          e->solver = es;
          assert_int_equal(rps3_invdyn(&m, e), RPS3_OK);
          assert_true(same_dynamics(d, e));
          /* (c): three times in four one component of the start is
             moved by one ulp; g, a fresh workspace, starts where d does */
          if (route == RPS3_THETA_MULTIROOT && k < 40) {
            assert_int_equal(rps3_data_alloc(&m, &g), RPS3_OK);
            if (k % 4 != 0)
              d->theta[k % 4 - 1] = nextafter(d->theta[k % 4 - 1], 4.0);
            memcpy(g->theta, d->theta, sizeof(d->theta));
            g->have_theta = 1;
            g->mode = d->mode;
            run_point(&m, d, &tr, 0.05 * (k + 1));
            run_point(&m, g, &tr, 0.05 * (k + 1));
            if (k % 4 != 0) {
              assert_true(same_dynamics(d, g));
              assert_true(memcmp(d->theta, g->theta, sizeof(d->theta)) == 0);
            } else {
              /* d's start is its kept root moved along the lengths, g's
                 the root itself: two roots within tol = 1e-12 (|theta
                 difference| up to 6e-13 rad, F's 1.1e-12 of its scale
                 measured; 100 times that allowed) */
              int i;
              for (i = 0; i < 3; i++) {
                CHECK_REL(d->theta[i], g->theta[i], 1e-10, 1.0, "theta%d", i);
                CHECK_REL(d->F[i], g->F[i], 1e-10, fscale(g), "F%d", i);
              }
            }
            rps3_data_free(g);
          }
        }
        /* (b): d at t = 0.3, then moved to t = 0.6 by the public stages */
        run_point(&m, d, &tr, 0.3);
        assert_int_equal(rps3_traj_eval(&m, &tr, 0.6, d->pose, d->dpose,
                                        d->ddpose), RPS3_OK);
        assert_int_equal(rps3_ik(&m, d), RPS3_OK);
        assert_int_equal(rps3_velocity(&m, d), RPS3_OK);
        assert_int_equal(rps3_acceleration(&m, d), RPS3_OK);
        assert_int_equal(rps3_invdyn(&m, d), RPS3_OK);
        rps3_data_reset(e);
        run_point(&mc, e, &tr, 0.6);
        assert_true(same_dynamics(d, e));
      }
      rps3_data_free(d);
      rps3_data_free(e);
    }
}

/*
 * Static symmetric pose, beta = 0, no motion.  By symmetry each ball joint
 * carries M g / 3 upwards and no tangential force; link i's moment balance
 * about its pin fixes the ball force component along dphi, s = -m g d
 * cos(theta) / l; the vertical balance F sin(theta) + s cos(theta) = M g/3
 * then gives F = (M g / 3 + m g d cos^2(theta) / l) / sin(theta), with
 * l^2 = (R - r)^2 + z^2 and cos(theta) = (R - r) / l.  Virtual work gives the
 * same: 3 F dl = M g dz + 3 m g d cos(theta) dtheta.  A payload at the
 * centre adds m_p g / (3 sin(theta)).
 */
static void static_closed_form(void **state) {
  int method, certify;
  (void)state;
  for (method = 0; method < 2; method++)
    for (certify = 0; certify < 2; certify++) {
      rps3_model m;
      rps3_data *d;
      double z = 0.2713, l, ct, st, F, Fp;
      int i;
      model_entropy(&m);
      memset(m.payload.com, 0, sizeof m.payload.com);
      m.opt.method = (rps3_method)method;
      m.opt.outputs = (certify) ? (m.opt.outputs | RPS3_OUT_CERTIFY)
      : (m.opt.outputs & ~RPS3_OUT_CERTIFY);
      m.opt.effects = RPS3_EFF_ALL; /* inertia and friction vanish at rest */
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
      d->pose[0] = 0.917; /* any alpha: a gauge at beta = 0 */
      d->pose[1] = 0.0;
      d->pose[2] = z;
      assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
      l = sqrt((m.R - m.r) * (m.R - m.r) + z * z);
      ct = (m.R - m.r) / l;
      st = z / l;
      F = (m.M * m.g / 3.0 + m.m * m.g * m.d * ct * ct / l) / st;
      Fp = m.payload.mass * m.g / (3.0 * st);
      for (i = 0; i < 3; i++) {
        CHECK_REL(d->l[i], l, TOL_EXACT, 0.0, "l");
        CHECK_REL(d->F[i], F + Fp, TOL_EXACT, 0.0, "F%d method %d", i, method);
        CHECK_REL(d->F_effect[4][i], Fp, TOL_EXACT, 0.0, "payload share");
        CHECK_REL(d->F_effect[2][i], 0.0, TOL_EXACT, F, "no inertia at rest");
        CHECK_REL(d->F_effect[5][i], 0.0, 0.0, 1.0, "no friction at rest");
      }
      rps3_data_free(d);
    }
}

/* a static scene computes no rates: rps3_invdyn runs on positions alone */
static void static_scene_needs_no_rates(void **state) {
  rps3_model m;
  rps3_data *d;
  (void)state;
  rps3_model_default(&m);
  m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
  m.opt.outputs &= ~RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_invdyn(&m, d), RPS3_ESTATE);
  d->pose[0] = 0.4;
  d->pose[1] = 0.2;
  d->pose[2] = 0.3;
  d->dpose[0] = (double)NAN; /* never read */
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  assert_int_equal(d->stage & (RPS3_STAGE_VEL | RPS3_STAGE_ACC), 0);
  assert_true(isfinite(d->F[0]) && d->F[0] > 0);
  /* a dynamic scene refuses to run on positions alone */
  m.opt.effects = RPS3_EFF_DEFAULT;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  assert_int_equal(rps3_invdyn(&m, d), RPS3_ESTATE);
  assert_non_null(strstr(d->err.msg, "velocities"));
  rps3_data_free(d);
}

/* towards link 1 lying in the platform plane: cond grows, a warning is
   raised past cond_warn, and the singular pose itself is an error */
static void singular_configuration(void **state) {
  rps3_model m;
  rps3_data *d;
  double bs, prev = 0.0, delta;
  int i;
  (void)state;
  rps3_model_default(&m);
  /* this test is about the condition number: the transmission limit,
     tested on its own, is moved out of the way */
  m.opt.trans_max = 1e300;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  bs = singular_beta(&m, d, 0.25, 0.6, 1.0);
  assert_true(isfinite(bs));
  for (delta = 1e-1; delta > 1e-9; delta /= 10) {
    d->pose[0] = 0.0;
    d->pose[1] = bs - delta;
    d->pose[2] = 0.25;
    d->dpose[0] = 0.1;
    d->dpose[1] = d->dpose[2] = d->ddpose[0] = d->ddpose[1] = d->ddpose[2] = 0;
    assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
    assert_true(d->cond > prev); /* grows monotonically, ~1/delta */
    prev = d->cond;
    for (i = 0; i < 3; i++) assert_true(isfinite(d->F[i]));
    assert_int_equal((d->warn & RPS3_WARN_ILLCOND) != 0, d->cond > m.opt.cond_warn);
  }
  assert_true(d->warn & RPS3_WARN_ILLCOND);
  d->pose[1] = bs;
  assert_int_equal(rps3_inverse(&m, d), RPS3_ESING);
  assert_non_null(strstr(d->err.msg, "condition number"));
  assert_int_equal(d->stage & RPS3_STAGE_DYN, 0);
  rps3_data_free(d);
}

/* Coulomb friction: sign(0) = 0, and it opposes theta-dot */
static void friction_opposes_motion(void **state) {
  rps3_model m;
  rps3_data *d;
  int i;
  (void)state;
  rps3_model_default(&m);
  m.opt.effects = RPS3_EFF_PIN_FRICTION;
  m.friction.coulomb = 0.0371;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = 0.3;
  d->pose[1] = 0.15;
  d->pose[2] = 0.31;
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  for (i = 0; i < 3; i++) assert_true(d->F[i] == 0.0);
  d->dpose[2] = 0.05; /* rising: the actuators must also beat friction */
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  assert_true(d->friction_power < 0.0);
  assert_true(d->power > 0.0);
  CHECK_REL(d->power, -d->friction_power, TOL_EXACT, 0.0, "power balance");
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(paper_trajectory),
      cmocka_unit_test(random_trajectories),
      cmocka_unit_test(effects_separate),
      cmocka_unit_test(summed_forces_match),
      cmocka_unit_test(outputs_each_bit),
      cmocka_unit_test(shared_jacobian_never_stale),
      cmocka_unit_test(static_closed_form),
      cmocka_unit_test(static_scene_needs_no_rates),
      cmocka_unit_test(singular_configuration),
      cmocka_unit_test(friction_opposes_motion),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
