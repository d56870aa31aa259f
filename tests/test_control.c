/*
 * test_control.c - the shipped controllers.  Their desired motion is the
 * trajectory's, whatever the effects of the controller's own model: a
 * model that selects no dynamic effect (gravity alone) computes no rates
 * for its forces, and the controller must still track the desired link
 * rates.  The oracle is the trajectory's link rates by rps3_ik and
 * rps3_velocity of a separate model; with kp = 0, kd = 1 and a measured
 * rate of zero, PD's force is the desired rate itself.
 */
#include "testutil.h"

/* the controller's last desired length and rate i (rps3_ctrl_last) */
static double ctrl_l_des(const rps3_ctrl *c, int i) {
  double l[3];
  assert_int_equal(rps3_ctrl_last(c, NULL, l, NULL, NULL), RPS3_OK);
  return l[i];
}
static double ctrl_dl_des(const rps3_ctrl *c, int i) {
  double dl[3];
  assert_int_equal(rps3_ctrl_last(c, NULL, NULL, dl, NULL), RPS3_OK);
  return dl[i];
}

static void pd_tracks_the_desired_rates(void **state) {
  const int effects[3] = {RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY,
                          RPS3_EFF_DEFAULT, RPS3_EFF_PLATFORM_GRAVITY};
  int e, fo, k, i;
  (void)state;
  for (e = 0; e < 3; e++)
    for (fo = 0; fo < 2; fo++) {
      rps3_model cm, om;
      rps3_data *od = NULL;
      rps3_ctrl *c = NULL;
      rps3_traj tr;
      rps3_traj_default(&tr);
      rps3_model_default(&cm);
      cm.opt.effects = effects[e];
      /* fo: the runner's controllers, F alone (the leanest pass); else
         every output but the certificate (no rates for a static model) */
      cm.opt.outputs = fo ? RPS3_OUT_FORCES : RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
      assert_int_equal(rps3_model_init(&cm, NULL), RPS3_OK);
      rps3_model_default(&om);
      assert_int_equal(rps3_model_init(&om, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&om, &od), RPS3_OK);
      assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_PD, 0.0, 1.0, &cm, &tr, &c, NULL),
                       RPS3_OK);
      for (k = 0; k <= 20; k++) {
        double t = 0.5 * k, F[3], zero[3] = {0, 0, 0};
        assert_int_equal(rps3_traj_eval(&om, &tr, t, od->pose, od->dpose,
                                        od->ddpose),
                         RPS3_OK);
        assert_int_equal(rps3_ik(&om, od), RPS3_OK);
        assert_int_equal(rps3_velocity(&om, od), RPS3_OK);
        /* measured: on the desired lengths, at rest */
        assert_int_equal(rps3_ctrl_update(c, t, od->l, zero, F), RPS3_OK);
        for (i = 0; i < 3; i++)
          /* the same rates by another route: to rounding of m/s values
             of ~0.1 (1e-15 seen) */
          CHECK_REL(F[i], od->dl[i], 1e-12, 1.0,
                    "effects %#x F alone %d t %g: F%d = kd dl_des", effects[e],
                    fo, t, i);
      }
      rps3_ctrl_free(c);
      rps3_data_free(od);
    }
}

/*
 * Every controller logs the desired lengths and rates of its trajectory,
 * open loop too, whatever its model's effects (a static model computes no
 * rates for its forces): l_des and dl_des against rps3_ik and
 * rps3_velocity of a separate full model, to rounding.
 */
static void every_kind_logs_the_desired_motion(void **state) {
  int kind, e;
  (void)state;
  for (kind = 0; kind < RPS3_NCTRL; kind++)
    for (e = 0; e < 2; e++) {
      rps3_model cm, om;
      rps3_data *od = NULL;
      rps3_ctrl *c = NULL;
      rps3_traj tr;
      double F[3];
      int k, i;
      rps3_traj_default(&tr);
      rps3_model_default(&cm);
      cm.opt.effects = e ? RPS3_EFF_DEFAULT
                         : RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
      cm.opt.outputs &= ~RPS3_OUT_CERTIFY;
      assert_int_equal(rps3_model_init(&cm, NULL), RPS3_OK);
      rps3_model_default(&om);
      assert_int_equal(rps3_model_init(&om, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&om, &od), RPS3_OK);
      assert_int_equal(rps3_ctrl_alloc((rps3_ctrl_kind)kind, 100.0, 10.0,
                                       &cm, &tr, &c, NULL),
                       RPS3_OK);
      for (k = 0; k <= 10; k++) {
        double t = 0.97 * k;
        assert_int_equal(rps3_traj_eval(&om, &tr, t, od->pose, od->dpose,
                                        od->ddpose),
                         RPS3_OK);
        assert_int_equal(rps3_ik(&om, od), RPS3_OK);
        assert_int_equal(rps3_velocity(&om, od), RPS3_OK);
        assert_int_equal(rps3_ctrl_update(c, t, od->l, od->dl, F), RPS3_OK);
        for (i = 0; i < 3; i++) {
          /* lengths ~0.2 m and rates ~0.1 m/s by two routes: rounding */
          CHECK_REL(ctrl_l_des(c, i), od->l[i], 1e-12, 1.0,
                    "kind %d effects %d t %g: l_des%d", kind, e, t, i);
          CHECK_REL(ctrl_dl_des(c, i), od->dl[i], 1e-12, 1.0,
                    "kind %d effects %d t %g: dl_des%d", kind, e, t, i);
          assert_true(isfinite(F[i]));
        }
      }
      rps3_ctrl_free(c);
      rps3_data_free(od);
    }
}

/* the desired state of trajectory tr at t (rps3_ik and rps3_velocity of
   model m into od) and a measured state off it: l_i + dlen (i - c),
   dl_i - drate (i - c) */
static void off_trajectory(const rps3_model *m, const rps3_traj *tr,
                           double t, rps3_data *od, double dlen,
                           double drate, double c, double l[3],
                           double dl[3]) {
  int i;
  assert_int_equal(rps3_traj_eval(m, tr, t, od->pose, od->dpose, od->ddpose),
                   RPS3_OK);
  assert_int_equal(rps3_ik(m, od), RPS3_OK);
  assert_int_equal(rps3_velocity(m, od), RPS3_OK);
  for (i = 0; i < 3; i++) {
    l[i] = od->l[i] + dlen * (i - c);
    dl[i] = od->dl[i] - drate * (i - c);
  }
}

/*
 * A controller called again at the same time or at an earlier one (a
 * continuous controller inside an adaptive step, rate 0) has no motion to
 * predict its theta solve's start from: it starts from its last root.  Its
 * forces equal, to the theta solve's tolerance, those of a fresh
 * controller given the same call: PD + gravity and computed torque, on
 * measured states off the trajectory.
 */
static void repeated_and_earlier_times(void **state) {
  const rps3_ctrl_kind kinds[2] = {RPS3_CTRL_PD_GRAVITY,
                                   RPS3_CTRL_COMPUTED_TORQUE};
  const double times[6] = {1.0, 1.0, 0.999, 1.5, 1.5, 0.2};
  int q, k, i;
  (void)state;
  for (q = 0; q < 2; q++) {
    rps3_model cm;
    rps3_data *od = NULL;
    rps3_ctrl *c = NULL, *fresh = NULL;
    rps3_traj tr;
    rps3_traj_default(&tr);
    rps3_model_default(&cm);
    assert_int_equal(rps3_model_init(&cm, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&cm, &od), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc(kinds[q], 400.0, 40.0, &cm, &tr, &c, NULL),
                     RPS3_OK);
    for (k = 0; k < 6; k++) {
      double t = times[k], F[3], G[3], l[3], dl[3];
      /* a measured state 1 mm and 1 cm/s off the desired one */
      off_trajectory(&cm, &tr, t, od, 1e-3, 1e-2, 1.0, l, dl);
      assert_int_equal(rps3_ctrl_update(c, t, l, dl, F), RPS3_OK);
      assert_int_equal(rps3_ctrl_alloc(kinds[q], 400.0, 40.0, &cm, &tr,
                                       &fresh, NULL),
                       RPS3_OK);
      assert_int_equal(rps3_ctrl_update(fresh, t, l, dl, G), RPS3_OK);
      for (i = 0; i < 3; i++)
        /* theta to tol 1e-12 (units of R^2 in f): forces to ~1e-11 of
           their ~1-10 N scale */
        CHECK_REL(F[i], G[i], 1e-9, 1.0, "kind %d call %d (t %g): F%d",
                  (int)kinds[q], k, t, i);
      rps3_ctrl_free(fresh);
      fresh = NULL;
    }
    rps3_ctrl_free(c);
    rps3_data_free(od);
  }
}

/*
 * The laws apply their model's inverse dynamics at the measured state:
 * PD + gravity's weight term is rps3_invdyn at rest, computed torque's
 * force is rps3_invdyn with the commanded l'' = l''_des + kp e + kd e'.
 * The oracle runs the stages on the measured lengths (rps3_theta_solve,
 * rps3_joint_velocity, rps3_joint_acceleration, rps3_invdyn) by either
 * formulation, Newton-Euler sharing nothing with the controller's
 * joint-space Mq l'' + hq; every third effect set and all six, payload and
 * friction included.  The ticks run at 1 kHz over two stretches, so that
 * the controller's predicted starts and their moved trigonometry are what
 * is tested (a sign error in either moves theta by ~1e-4 rad): its theta
 * against the oracle's root, both solved to 1e-12 in f (1e-10 rad), and
 * the forces to 1e-10 of their scale (the two routes agree to ~1e-13).
 */
static void laws_are_the_model_inverse_dynamics(void **state) {
  const rps3_ctrl_kind kinds[2] = {RPS3_CTRL_PD_GRAVITY,
                                   RPS3_CTRL_COMPUTED_TORQUE};
  const double kp = 400.0, kd = 40.0, t0[2] = {0.5, 6.2};
  int q, e, meth, k, i;
  (void)state;
  for (q = 0; q < 2; q++)
    for (meth = 0; meth < 2; meth++)
      for (e = 0; e <= 21; e++) {
        const int eff = e < 21 ? 1 + 3 * e : RPS3_EFF_ALL;
        rps3_model cm;
        rps3_data *od = NULL;
        rps3_ctrl *c = NULL;
        rps3_traj tr;
        rps3_traj_default(&tr);
        rps3_model_default(&cm);
        cm.opt.effects = eff;
        cm.opt.method = meth ? RPS3_NEWTON_EULER : RPS3_LAGRANGE;
        cm.payload.mass = 0.05;
        cm.payload.com[0] = 0.01;
        cm.payload.com[1] = -0.02;
        cm.payload.com[2] = 0.03;
        cm.payload.inertia[0] = 2e-5;
        cm.payload.inertia[1] = 3e-5;
        cm.payload.inertia[2] = 4e-5;
        cm.friction.viscous = 0.01;
        cm.friction.coulomb = 0.005;
        cm.friction.vreg = 1e-3;
        assert_int_equal(rps3_model_init(&cm, NULL), RPS3_OK);
        assert_int_equal(rps3_data_alloc(&cm, &od), RPS3_OK);
        assert_int_equal(rps3_ctrl_alloc(kinds[q], kp, kd, &cm, &tr, &c, NULL),
                         RPS3_OK);
        for (k = 0; k < 80; k++) {
          double t = t0[k / 40] + 1e-3 * (k % 40), F[3], l[3], dl[3], a[3],
                 scale = 1.0;
          /* a measured state 2 mm and 3 cm/s off the desired one */
          off_trajectory(&cm, &tr, t, od, 2e-3, 3e-2, 0.7, l, dl);
          assert_int_equal(rps3_ctrl_update(c, t, l, dl, F), RPS3_OK);
          /* the oracle at the measured state, warm from the desired theta */
          for (i = 0; i < 3; i++) {
            double er = ctrl_l_des(c, i) - l[i], de = ctrl_dl_des(c, i) - dl[i];
            a[i] = (kinds[q] == RPS3_CTRL_COMPUTED_TORQUE)
                       ? rps3_ctrl_desired(c)->ddl[i] + kp * er + kd * de
                       : 0.0;
            od->l[i] = l[i];
          }
          od->have_theta = 1;
          assert_int_equal(rps3_theta_solve(&cm, od), RPS3_OK);
          for (i = 0; i < 3; i++) {
            od->dl[i] = (kinds[q] == RPS3_CTRL_COMPUTED_TORQUE) ? dl[i] : 0.0;
            od->ddl[i] = a[i];
          }
          assert_int_equal(rps3_joint_velocity(&cm, od), RPS3_OK);
          assert_int_equal(rps3_joint_acceleration(&cm, od), RPS3_OK);
          assert_int_equal(rps3_invdyn(&cm, od), RPS3_OK);
          for (i = 0; i < 3; i++) scale = fmax(scale, fabs(od->F[i]));
          for (i = 0; i < 3; i++) {
            double want = od->F[i];
            if (kinds[q] == RPS3_CTRL_PD_GRAVITY)
              want += kp * (ctrl_l_des(c, i) - l[i]) + kd * (ctrl_dl_des(c, i) - dl[i]);
            CHECK_REL(F[i], want, 1e-10, scale,
                      "kind %d effects %#x method %d t %g: F%d", (int)kinds[q],
                      eff, meth, t, i);
            CHECK_REL(rps3_ctrl_measured(c)->theta[i], od->theta[i], 1e-10, 1.0,
                      "kind %d effects %#x t %g: theta%d", (int)kinds[q], eff,
                      t, i);
          }
        }
        rps3_ctrl_free(c);
        rps3_data_free(od);
      }
}

/*
 * What rps3_invdyn reports of a configuration, the controllers report at
 * the measured state too: with opt.trans_warn or opt.cond_warn below the
 * state's force transmission or condition number, RPS3_WARN_TRANS or
 * RPS3_WARN_ILLCOND in rps3_ctrl_measured(c)->warn, as in the oracle's; with
 * opt.trans_max or opt.cond_max below them, RPS3_ESING from both; with
 * opt.mode asking for the other assembly mode, RPS3_EMODE from both.
 */
static void laws_keep_the_model_limits(void **state) {
  const rps3_ctrl_kind kinds[2] = {RPS3_CTRL_PD_GRAVITY,
                                   RPS3_CTRL_COMPUTED_TORQUE};
  int q, v, i;
  (void)state;
  for (q = 0; q < 2; q++)
    for (v = 0; v < 5; v++) {
      rps3_model base, cm;
      rps3_data *od = NULL;
      rps3_ctrl *c = NULL;
      rps3_traj tr;
      double t = 2.371, F[3], l[3], dl[3], T, cond;
      int want_st, want_warn, st;
      rps3_traj_default(&tr);
      rps3_model_default(&base);
      assert_int_equal(rps3_model_init(&base, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&base, &od), RPS3_OK);
      /* the oracle's transmission and condition number at the state */
      off_trajectory(&base, &tr, t, od, 2e-3, 3e-2, 0.7, l, dl);
      for (i = 0; i < 3; i++) od->l[i] = l[i];
      od->have_theta = 1;
      assert_int_equal(rps3_theta_solve(&base, od), RPS3_OK);
      for (i = 0; i < 3; i++) od->dl[i] = od->ddl[i] = 0.0;
      assert_int_equal(rps3_joint_velocity(&base, od), RPS3_OK);
      assert_int_equal(rps3_joint_acceleration(&base, od), RPS3_OK);
      assert_int_equal(rps3_invdyn(&base, od), RPS3_OK);
      T = od->transmission;
      cond = od->cond;
      cm = base;
      /* limits between 1 (the least a model takes) and the state's */
      assert_true(T > 1.0 && cond > 1.0);
      switch (v) {
      case 0: cm.opt.trans_warn = 0.5 * (1.0 + T); break;
      case 1:
        cm.opt.trans_warn = 1.0;
        cm.opt.trans_max = 0.5 * (1.0 + T);
        break;
      case 2: cm.opt.cond_warn = 0.5 * (1.0 + cond); break;
      case 3:
        cm.opt.cond_warn = 1.0;
        cm.opt.cond_max = 0.5 * (1.0 + cond);
        break;
      default: cm.opt.mode = RPS3_MODE_OTHER; break;
      }
      assert_int_equal(rps3_model_init(&cm, NULL), RPS3_OK);
      /* the oracle with these limits */
      rps3_data_reset(od);
      off_trajectory(&cm, &tr, t, od, 2e-3, 3e-2, 0.7, l, dl);
      for (i = 0; i < 3; i++) od->l[i] = l[i];
      od->have_theta = 1;
      /* the first stage that fails gives the oracle's status (the rate
         stages test df/dtheta against cond_max too) */
      want_st = rps3_theta_solve(&cm, od);
      for (i = 0; i < 3; i++) od->dl[i] = od->ddl[i] = 0.0;
      if (want_st == RPS3_OK) want_st = rps3_joint_velocity(&cm, od);
      if (want_st == RPS3_OK) want_st = rps3_joint_acceleration(&cm, od);
      if (want_st == RPS3_OK) want_st = rps3_invdyn(&cm, od);
      want_warn = od->warn & (RPS3_WARN_TRANS | RPS3_WARN_ILLCOND);
      assert_int_equal(want_st,
                       v == 1 || v == 3 ? RPS3_ESING
                                        : v == 4 ? RPS3_EMODE : RPS3_OK);
      assert_int_equal(rps3_ctrl_alloc(kinds[q], 400.0, 40.0, &cm, &tr, &c, NULL),
                       RPS3_OK);
      st = rps3_ctrl_update(c, t, l, dl, F);
      if (st != want_st)
        fail_msg("kind %d variant %d: status %d (%s), the oracle's %d",
                 (int)kinds[q], v, st, rps3_ctrl_measured(c)->err.msg, want_st);
      if (st == RPS3_OK)
        assert_int_equal(rps3_ctrl_measured(c)->warn & (RPS3_WARN_TRANS | RPS3_WARN_ILLCOND),
                         want_warn);
      assert_true(v != 0 || (want_warn & RPS3_WARN_TRANS));
      assert_true(v != 2 || (want_warn & RPS3_WARN_ILLCOND));
      rps3_ctrl_free(c);
      rps3_data_free(od);
    }
}

/*
 * A sensor glitch: a measured length or rate NaN or infinite, or the time
 * not finite.  Every kind refuses it with RPS3_EINVAL and a message in
 * meas->err naming the input, before any law forms a force; a force that
 * overflows from finite inputs (gains near the largest double) is
 * RPS3_ERANGE; no kind returns RPS3_OK with a force not finite.  And the
 * controller works again on the next good measurement.
 */
static void non_finite_measurements(void **state) {
  const double bad[3] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
  int kind;
  (void)state;
  for (kind = 0; kind < RPS3_NCTRL; kind++) {
    rps3_model m;
    rps3_data *d = NULL;
    rps3_ctrl *c = NULL, *big = NULL;
    rps3_traj tr;
    double F[3], l[3], dl[3];
    int b, i, which, st;
    rps3_traj_default(&tr);
    rps3_model_default(&m);
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc((rps3_ctrl_kind)kind, 100.0, 10.0, &m,
                                     &tr, &c, NULL),
                     RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, 1.0, d->pose, d->dpose, NULL),
                     RPS3_OK);
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    assert_int_equal(rps3_velocity(&m, d), RPS3_OK);
    for (which = 0; which < 6; which++)
      for (b = 0; b < 3; b++) {
        char want[16];
        for (i = 0; i < 3; i++) {
          l[i] = d->l[i];
          dl[i] = d->dl[i];
        }
        if (which < 3) l[which] = bad[b];
        else dl[which - 3] = bad[b];
        F[0] = F[1] = F[2] = 0.0;
        st = rps3_ctrl_update(c, 1.0, l, dl, F);
        if (st != RPS3_EINVAL)
          fail_msg("kind %d, input %d = %g: status %d, F (%g, %g, %g)", kind,
                   which, bad[b], st, F[0], F[1], F[2]);
        snprintf(want, sizeof want, "measured %s%d", which < 3 ? "l" : "dl",
                 which % 3 + 1);
        if (strstr(rps3_ctrl_measured(c)->err.msg, want) == NULL)
          fail_msg("kind %d: '%s' does not name %s", kind, rps3_ctrl_measured(c)->err.msg,
                   want);
      }
    assert_int_equal(rps3_ctrl_update(c, (double)NAN, d->l, d->dl, F),
                     RPS3_EINVAL);
    assert_non_null(strstr(rps3_ctrl_measured(c)->err.msg, "time t"));
    /* an infinite time too, not only NaN */
    assert_int_equal(rps3_ctrl_update(c, (double)INFINITY, d->l, d->dl, F),
                     RPS3_EINVAL);
    assert_non_null(strstr(rps3_ctrl_measured(c)->err.msg, "time t"));
    /* the next good measurement: a finite force */
    assert_int_equal(rps3_ctrl_update(c, 1.0, d->l, d->dl, F), RPS3_OK);
    assert_true(isfinite(F[0]) && isfinite(F[1]) && isfinite(F[2]));
    /* finite inputs, gains that overflow the force: never OK with it */
    if (kind != RPS3_CTRL_OPEN_LOOP) {
      assert_int_equal(rps3_ctrl_alloc((rps3_ctrl_kind)kind, 1e308, 1e308,
                                       &m, &tr, &big, NULL),
                       RPS3_OK);
      for (i = 0; i < 3; i++) {
        l[i] = d->l[i] - 10.0;
        dl[i] = d->dl[i] - 10.0;
      }
      st = rps3_ctrl_update(big, 1.0, l, dl, F);
      assert_true(st != RPS3_OK);
      if (kind == RPS3_CTRL_PD) { /* the others' model refuses l first */
        assert_int_equal(st, RPS3_ERANGE);
        assert_non_null(strstr(rps3_ctrl_measured(big)->err.msg, "not finite"));
      }
      rps3_ctrl_free(big);
    }
    rps3_ctrl_free(c);
    rps3_data_free(d);
  }
}

/* the opaque controller's accessors: NaN before the first tick, the
   tick's values after it (the desired workspace's own), NULL and
   RPS3_EINVAL for no controller */
static void accessors_of_the_opaque_controller(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_ctrl *c = NULL;
  const rps3_data *des;
  double t, l[3], dl[3], ff[3], F[3];
  int i;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_OPEN_LOOP, 0.0, 0.0, &m, &tr, &c, NULL),
                   RPS3_OK);
  assert_int_equal(rps3_ctrl_last(c, &t, l, dl, ff), RPS3_OK);
  assert_true(isnan(t));
  for (i = 0; i < 3; i++)
    assert_true(isnan(l[i]) && isnan(dl[i]) && isnan(ff[i]));
  des = rps3_ctrl_desired(c);
  assert_non_null(des);
  assert_non_null(rps3_ctrl_measured(c));
  assert_int_equal(rps3_ctrl_update(c, 0.37, l, l, F), RPS3_EINVAL); /* NaN */
  for (i = 0; i < 3; i++) l[i] = dl[i] = 0.25;
  assert_int_equal(rps3_ctrl_update(c, 0.37, l, dl, F), RPS3_OK);
  assert_int_equal(rps3_ctrl_last(c, &t, l, dl, ff), RPS3_OK);
  assert_true(t == 0.37);
  for (i = 0; i < 3; i++) {
    assert_true(l[i] == des->l[i] && dl[i] == des->dl[i]);
    assert_true(ff[i] == F[i]); /* the open loop applies F_ff */
  }
  assert_int_equal(rps3_ctrl_last(NULL, &t, l, NULL, NULL), RPS3_EINVAL);
  assert_true(isnan(t) && isnan(l[0]));
  assert_null(rps3_ctrl_desired(NULL));
  assert_null(rps3_ctrl_measured(NULL));
  rps3_ctrl_free(c);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(pd_tracks_the_desired_rates),
      cmocka_unit_test(accessors_of_the_opaque_controller),
      cmocka_unit_test(every_kind_logs_the_desired_motion),
      cmocka_unit_test(repeated_and_earlier_times),
      cmocka_unit_test(laws_are_the_model_inverse_dynamics),
      cmocka_unit_test(laws_keep_the_model_limits),
      cmocka_unit_test(non_finite_measurements),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
