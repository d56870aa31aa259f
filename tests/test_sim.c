/* test_sim.c - simulation and control: the open-loop round trip of the
   inverse dynamics' forces, the energy balance, closed-loop tracking by
   the three controllers, measurement noise, and hard cases that must end
   in a clean status. */
#include <stdlib.h>

#include "control.h" /* white-box: a controller's workspaces, a bogus kind */
#include "testutil.h"
#include "bench/user_law.h"

/* the paper's helix, scaled to model_entropy()'s platform (r* < r/2) */
static void helix_entropy(rps3_traj *tr) {
  rps3_traj_default(tr);
  tr->helix.radius = 0.0031;
  tr->helix.z0 = 0.2713;
}

/* a fast sine: a turn of alpha per second, beta and z_c at 2 and 3 Hz */
static void fast_sine(rps3_traj *tr) {
  memset(tr, 0, sizeof(*tr));
  tr->kind = RPS3_TRAJ_SINE;
  tr->sine.mean[0] = 0.31;
  tr->sine.amp[0] = 1.03;
  tr->sine.freq[0] = 1.07;
  tr->sine.mean[1] = 0.21;
  tr->sine.amp[1] = 0.083;
  tr->sine.freq[1] = 2.03;
  tr->sine.phase[1] = 0.4;
  tr->sine.mean[2] = 0.27;
  tr->sine.amp[2] = 0.029;
  tr->sine.freq[2] = 3.01;
  tr->sine.duration = 2.0;
}

/* start s on the trajectory at t */
static void start_on(rps3_sim *s, const rps3_model *m, const rps3_traj *tr,
                     double t) {
  double pose[3], dpose[3];
  assert_int_equal(rps3_traj_eval(m, tr, t, pose, dpose, NULL), RPS3_OK);
  if (rps3_sim_start(s, t, pose, dpose) != RPS3_OK)
    fail_msg("start at t = %g: %s", t, rps3_sim_data(s)->err.msg);
}

/* largest |l - l_d| [m] at t, l_d by the closed form from the pose */
static double length_error(const rps3_model *m, const rps3_traj *tr,
                           rps3_data *w, const double y[3], double t) {
  double e = 0.0;
  int i;
  assert_int_equal(rps3_traj_eval(m, tr, t, w->pose, NULL, NULL), RPS3_OK);
  assert_int_equal(rps3_ik(m, w), RPS3_OK);
  for (i = 0; i < 3; i++) e = fmax(e, fabs(y[i] - w->l[i]));
  return e;
}

/*
 * Round trip, window by window.  Under the inverse dynamics' forces the
 * plant is open-loop unstable (it grows errors ~10x per 0.2 s on these
 * paths, measured: the platform on three force-controlled links is an
 * inverted pendulum), so a whole-path comparison would measure the
 * instability, not the integration.  Each window starts on the trajectory
 * and runs 0.05 s open loop (amplification < e^0.6); the error at its end
 * is the integrator's: rk8pd with epsabs = epsrel = 1e-10 must give
 * |l - l_d| <= 1e-9 m (ten times the tolerance, for the error of the
 * window's ~20 steps and the amplification), for every effect
 * combination with inertia, on the helix and the fast sine, with pin
 * friction at its exact sign.
 */
static void round_trip(const rps3_traj *tr, int eff, double *worst) {
  rps3_model m;
  rps3_sim_options o;
  rps3_sim *s;
  rps3_ctrl *c;
  rps3_data *w;
  rps3_check chk;
  const double win = 0.05;
  int k;
  model_entropy(&m);
  m.opt.effects = eff;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_sim_options_default(&o);
  o.integrator = RPS3_INT_RK8PD;
  o.epsabs = o.epsrel = 1e-10;
  if (rps3_sim_alloc(&m, &o, &s, &chk) != RPS3_OK)
    fail_msg("%s", chk.msg);
  if (rps3_ctrl_alloc(RPS3_CTRL_OPEN_LOOP, 0, 0, &m, tr, &c, &chk) != RPS3_OK)
    fail_msg("%s", chk.msg);
  assert_int_equal(rps3_data_alloc(&m, &w), RPS3_OK);
  {
    rps3_controller ctl = {rps3_ctrl_update, c, 0.0, 0u, NULL};
    double T = rps3_traj_duration(tr);
    for (k = 0; k < 6; k++) {
      double t0 = (T - win) * (0.037 + 0.19 * k), e;
      start_on(s, &m, tr, t0);
      if (rps3_sim_advance(s, &ctl, t0 + win) != RPS3_OK)
        fail_msg("effects %d, t0 = %g: %s", eff, t0, rps3_sim_data(s)->err.msg);
      e = length_error(&m, tr, w, rps3_sim_now(s)->y, t0 + win);
      if (e > *worst) *worst = e;
      if (!(e <= 1e-9))
        fail_msg("effects %d, window at %g s: |l - l_d| = %.3g m", eff, t0, e);
    }
  }
  rps3_data_free(w);
  rps3_ctrl_free(c);
  rps3_sim_free(s);
}

static void round_trip_every_effect(void **state) {
  rps3_traj helix, sine;
  double wh = 0.0, ws = 0.0;
  int eff;
  (void)state;
  helix_entropy(&helix);
  fast_sine(&sine);
  for (eff = 1; eff <= RPS3_EFF_ALL; eff++) {
    if (!(eff & (RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA |
                 RPS3_EFF_PAYLOAD)))
      continue;
    round_trip(&helix, eff, &wh);
    round_trip(&sine, eff, &ws);
  }
  print_message("round trip, rk8pd 1e-10, 0.05 s windows: worst |l - l_d| "
                "%.3g m (helix), %.3g m (fast sine)\n", wh, ws);
}

/* RK4 converges at its order: halving h divides the window's error by
   ~16 (between 8 and 32 allows for the higher-order terms) */
static void rk4_converges_at_order_4(void **state) {
  rps3_model m;
  rps3_traj tr;
  double e[2];
  int k;
  (void)state;
  model_entropy(&m);
  m.friction.vreg = 0.02; /* smooth, so that the order shows */
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  fast_sine(&tr);
  for (k = 0; k < 2; k++) {
    rps3_sim_options o;
    rps3_sim *s;
    rps3_ctrl *c;
    rps3_data *w;
    rps3_sim_options_default(&o);
    o.h = k ? 2e-3 : 4e-3;
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_OPEN_LOOP, 0, 0, &m, &tr, &c, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &w), RPS3_OK);
    {
      rps3_controller ctl = {rps3_ctrl_update, c, 0.0, 0u, NULL};
      start_on(s, &m, &tr, 0.3);
      assert_int_equal(rps3_sim_advance(s, &ctl, 0.5), RPS3_OK);
      e[k] = length_error(&m, &tr, w, rps3_sim_now(s)->y, 0.5);
    }
    rps3_data_free(w);
    rps3_ctrl_free(c);
    rps3_sim_free(s);
  }
  print_message("rk4 errors %.3g m (h = 4 ms), %.3g m (2 ms): ratio %.1f\n",
                e[0], e[1], e[0] / e[1]);
  assert_true(e[0] / e[1] > 8.0 && e[0] / e[1] < 32.0);
}

/* a force law that is zero: free motion */
static int zero_force(void *state, double t, const double l[3],
                      const double dl[3], double F[3]) {
  (void)state;
  (void)t;
  (void)l;
  (void)dl;
  F[0] = F[1] = F[2] = 0.0;
  return RPS3_OK;
}

/*
 * Energy.  Free motion (F = 0, no friction) keeps T + P; with friction and
 * a PD controller at 1 kHz the work of the forces and of the friction
 * equals the change of T + P.  Each control period (step) and the whole
 * run are checked: the residual is the integration error of the
 * quadratures and of the state, bounded by ~epsrel times the energy
 * exchanged (1e-10 here, checked at 1e-8 of the scale).
 */
static void energy_balance(void **state) {
  int integ, fr;
  (void)state;
  for (integ = 1; integ <= 2; integ++)
    for (fr = 0; fr < 2; fr++) {
      rps3_model m;
      rps3_traj tr;
      rps3_sim_options o;
      rps3_sim *s;
      rps3_ctrl *c;
      double scale, prev = 0.0, worst_step = 0.0;
      int k;
      model_entropy(&m);
      m.opt.effects =
          RPS3_EFF_ALL &
          ~(fr ? 0 : RPS3_EFF_PIN_FRICTION | RPS3_EFF_PRISMATIC_FRICTION);
      m.friction.vreg = 0.01;
      for (k = 0; k < 3; k++) {
        /* friction in the prismatic joints too: their power is lost */
        m.leg[k].prismatic.viscous = 0.21 + 0.03 * k;
        m.leg[k].prismatic.coulomb = 0.047;
        m.leg[k].prismatic.vreg = 1e-3;
      }
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      helix_entropy(&tr);
      rps3_sim_options_default(&o);
      o.integrator = (rps3_integrator)integ;
      o.epsabs = o.epsrel = 1e-10;
      assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
      assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_PD_GRAVITY, 800.0, 30.0, &m,
                                       &tr, &c, NULL), RPS3_OK);
      {
        rps3_controller free_motion = {zero_force, NULL, 0.0, 0u, NULL};
        rps3_controller pd = rps3_ctrl_bind(c, 1000.0);
        start_on(s, &m, &tr, 0.0);
        scale = fabs(rps3_sim_now(s)->T) + fabs(rps3_sim_now(s)->P);
        for (k = 1; k <= 200; k++) {
          /* 0.1 s free, then the controller catches it */
          const rps3_controller *ctl = (k <= 100) ? &free_motion : &pd;
          if (rps3_sim_advance(s, ctl, 1e-3 * k) != RPS3_OK)
            fail_msg("t = %g: %s", 1e-3 * k, rps3_sim_data(s)->err.msg);
          worst_step = fmax(worst_step, fabs(rps3_sim_now(s)->energy_residual - prev));
          prev = rps3_sim_now(s)->energy_residual;
          if (k == 100 && fr == 0)
            CHECK_REL(rps3_sim_now(s)->T + rps3_sim_now(s)->P, rps3_sim_now(s)->E0, 1e-8, scale,
                      "free motion keeps T + P (%s)",
                      rps3_integrator_name(integ));
        }
      }
      print_message("%s, friction %d: energy residual %.3g J over the run, "
                    "worst step %.3g J, W_F %.4g J, W_f %.4g J\n",
                    rps3_integrator_name(integ), fr, rps3_sim_now(s)->energy_residual,
                    worst_step, rps3_sim_now(s)->y[6], rps3_sim_now(s)->y[7]);
      CHECK_REL(rps3_sim_now(s)->energy_residual, 0.0, 1e-8, scale, "run");
      CHECK_REL(worst_step, 0.0, 1e-8, scale, "per step");
      if (fr) assert_true(rps3_sim_now(s)->y[7] < 0.0);
      rps3_ctrl_free(c);
      rps3_sim_free(s);
    }
}

/* one closed-loop run at 1 kHz, RK4 at the control rate; returns the
   largest |l - l_d| at the 1 ms samples and the status */
static int closed_loop(const rps3_model *plant, const rps3_model *cm,
                       const rps3_traj *tr, rps3_ctrl_kind kind, double kp,
                       double kd, const rps3_sim_options *o, double *emax,
                       rps3_sim **keep) {
  rps3_sim *s;
  rps3_ctrl *c;
  rps3_data *w;
  double T = rps3_traj_duration(tr);
  int k, n = (int)(T * 1000.0 + 0.5), st = RPS3_OK;
  assert_int_equal(rps3_sim_alloc(plant, o, &s, NULL), RPS3_OK);
  assert_int_equal(rps3_ctrl_alloc(kind, kp, kd, cm, tr, &c, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(plant, &w), RPS3_OK);
  *emax = 0.0;
  {
    rps3_controller ctl = rps3_ctrl_bind(c, 1000.0);
    start_on(s, plant, tr, 0.0);
    for (k = 1; k <= n; k++) {
      st = rps3_sim_advance(s, &ctl, 1e-3 * k);
      if (st != RPS3_OK) break;
      *emax = fmax(*emax, length_error(plant, tr, w, rps3_sim_now(s)->y, 1e-3 * k));
    }
  }
  rps3_data_free(w);
  rps3_ctrl_free(c);
  if (keep != NULL)
    *keep = s;
  else
    rps3_sim_free(s);
  return st;
}

/* the Table II plant (m/M = 0.5), and a model of it without link mass
   (the paper's case 1) */
static void plant_and_light(rps3_model *plant, rps3_model *light) {
  rps3_model_default(plant);
  assert_int_equal(rps3_model_init(plant, NULL), RPS3_OK);
  *light = *plant;
  light->m = 0.0;
  assert_int_equal(rps3_model_init(light, NULL), RPS3_OK);
}

/*
 * Closed loop on the paper's helix (Table II plant, m/M = 0.5): computed
 * torque with the exact model tracks to within its discretisation (ZOH at
 * 1 kHz); with a controller model that ignores link mass (the paper's case
 * 1) the error grows by orders of magnitude; PD + gravity beats PD.
 */
static void controllers_track_the_helix(void **state) {
  rps3_model plant, light;
  rps3_traj tr;
  rps3_sim_options o;
  double ect, ect_light, epd, epdg;
  (void)state;
  plant_and_light(&plant, &light);
  rps3_traj_default(&tr);
  rps3_sim_options_default(&o);
  assert_int_equal(closed_loop(&plant, &plant, &tr, RPS3_CTRL_COMPUTED_TORQUE,
                               400.0, 40.0, &o, &ect, NULL), RPS3_OK);
  assert_int_equal(closed_loop(&plant, &light, &tr, RPS3_CTRL_COMPUTED_TORQUE,
                               400.0, 40.0, &o, &ect_light, NULL), RPS3_OK);
  assert_int_equal(closed_loop(&plant, &plant, &tr, RPS3_CTRL_PD, 2000.0, 40.0,
                               &o, &epd, NULL), RPS3_OK);
  assert_int_equal(closed_loop(&plant, &plant, &tr, RPS3_CTRL_PD_GRAVITY,
                               2000.0, 40.0, &o, &epdg, NULL), RPS3_OK);
  print_message("helix, 1 kHz: computed torque %.3g m (exact model), %.3g m "
                "(model without link mass), PD %.3g m, PD + gravity %.3g m\n",
                ect, ect_light, epd, epdg);
  assert_true(ect < 1e-5);
  assert_true(ect_light > 100.0 * ect);
  assert_true(epdg < epd);
}

/* a computed-torque controller of model cm on tr, the gains of the bench */
static rps3_ctrl *computed_torque(const rps3_model *cm, const rps3_traj *tr) {
  rps3_ctrl *c;
  assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0, cm,
                                   tr, &c, NULL),
                   RPS3_OK);
  return c;
}

/*
 * One rps3_sim_advance over many control periods and one call a period
 * give the same run, bit for bit: the periods inside a call settle on a
 * lean state (no report), the call's end reports.  A call ending a
 * rounding sliver after a tick reports too (report_end).  And the
 * library's controller, lent the plant's state at its ticks (computed
 * torque with the plant's model, and with a model without link mass),
 * commands the forces it commands alone: a replay of its ticks outside
 * the simulation, where it solves its own theta, agrees to 1e-10.
 */
static void one_call_or_one_per_period(void **state) {
  rps3_model plant, light;
  rps3_traj tr;
  rps3_sim *a, *b;
  rps3_ctrl *ca, *cb, *cr;
  int k, i, v, n = 300;
  (void)state;
  plant_and_light(&plant, &light);
  rps3_traj_default(&tr);
  for (v = 0; v < 2; v++) {
    const rps3_model *cm = v ? &light : &plant;
    rps3_controller ctl_a, ctl_b;
    assert_int_equal(rps3_sim_alloc(&plant, NULL, &a, NULL), RPS3_OK);
    assert_int_equal(rps3_sim_alloc(&plant, NULL, &b, NULL), RPS3_OK);
    ca = computed_torque(cm, &tr);
    cb = computed_torque(cm, &tr);
    ctl_a = rps3_ctrl_bind(ca, 1000.0);
    ctl_b = ctl_a;
    ctl_b.state = cb;
    start_on(a, &plant, &tr, 0.0);
    /* the ends at k / 1000, the ticks' own times: 1e-3 * k differs from
       them by rounding, and would change the last step of each call */
    for (k = 1; k <= n; k++)
      assert_int_equal(rps3_sim_advance(a, &ctl_a, k / 1000.0), RPS3_OK);
    for (k = 0; k < 2; k++) {
      /* one call to n / 1000; then, on a fresh run, one call that ends a
         rounding sliver past it: one more tick there, no step, and the
         state reported after a lean settle */
      const double end = n / 1000.0 + (k ? 1e-13 : 0.0);
      if (k) { /* a fresh controller too */
        rps3_ctrl_free(cb);
        cb = computed_torque(cm, &tr);
        ctl_b.state = cb;
      }
      start_on(b, &plant, &tr, 0.0);
      assert_int_equal(rps3_sim_advance(b, &ctl_b, end), RPS3_OK);
      for (i = 0; i < 8; i++) assert_true(rps3_sim_now(a)->y[i] == rps3_sim_now(b)->y[i]);
      for (i = 0; i < 3; i++) {
        assert_true(rps3_sim_data(a)->pose[i] == rps3_sim_data(b)->pose[i]);
        assert_true(rps3_sim_data(a)->dpose[i] == rps3_sim_data(b)->dpose[i]);
        assert_true(rps3_sim_data(a)->ddl[i] == rps3_sim_data(b)->ddl[i] || k);
        assert_true(rps3_sim_data(a)->b[i][2] == rps3_sim_data(b)->b[i][2]);
        assert_true(isfinite(rps3_sim_data(b)->pose[i]) && isfinite(rps3_sim_data(b)->ddtheta[i]));
      }
      assert_true(rps3_sim_now(a)->T == rps3_sim_now(b)->T && rps3_sim_now(a)->P == rps3_sim_now(b)->P);
      assert_true(rps3_sim_now(a)->energy_residual == rps3_sim_now(b)->energy_residual);
      assert_int_equal(rps3_sim_now(a)->nticks + k, rps3_sim_now(b)->nticks);
      assert_int_equal(rps3_sim_data(b)->stage & RPS3_STAGE_POS, RPS3_STAGE_POS);
      if (!k) assert_int_equal(rps3_sim_now(a)->nevals, rps3_sim_now(b)->nevals);
    }

    /* the ticks of a run, replayed outside a simulation.  The lent state
       was taken at every tick after the first: the shared path leaves the
       measured data's theta solve untouched (solve_niter stays -1) */
    rps3_sim_free(a);
    rps3_ctrl_free(ca);
    assert_int_equal(rps3_sim_alloc(&plant, NULL, &a, NULL), RPS3_OK);
    ca = computed_torque(cm, &tr);
    cr = computed_torque(cm, &tr);
    ctl_a.state = ca;
    start_on(a, &plant, &tr, 0.0);
    for (k = 1; k <= 200; k++) {
      double F[3];
      ca->meas->solve_niter = -1;
      assert_int_equal(rps3_sim_advance(a, &ctl_a, 1e-3 * k), RPS3_OK);
      if (k > 1) assert_int_equal(ca->meas->solve_niter, -1);
      assert_int_equal(rps3_ctrl_update(cr, ca->t, rps3_sim_now(a)->l_meas, rps3_sim_now(a)->dl_meas, F),
                       RPS3_OK);
      assert_true(cr->meas->solve_niter >= 0);
      for (i = 0; i < 3; i++)
        CHECK_REL(F[i], rps3_sim_now(a)->F_cmd[i], 1e-10, 1.0, "model %d tick %d F%d", v, k,
                  i);
    }
    rps3_sim_free(a);
    rps3_sim_free(b);
    rps3_ctrl_free(ca);
    rps3_ctrl_free(cb);
    rps3_ctrl_free(cr);
  }
}

/* the library's computed torque, failing from t_fail on */
typedef struct {
  rps3_ctrl *c;
  double t_fail;
} failing;

static int failing_ct(void *state, double t, const double l[3],
                      const double dl[3], double F[3]) {
  failing *f = (failing *)state;
  if (t >= f->t_fail) return RPS3_ERANGE;
  return rps3_ctrl_update(f->c, t, l, dl, F);
}

/*
 * A run that stops inside a call reports the state it stopped at (rps3_sim_now(s)->t,
 * rps3_sim_now(s)->y: the last good one), not the end of an earlier call: the same as a
 * run that called every period up to there, to the solve's tolerance; the
 * status and message stay the failure's.  The controller fails at its
 * tick at 0.5 s, after a first call to 0.1 s and inside a second to 1 s.
 */
static void report_where_the_run_stopped(void **state) {
  rps3_model plant, light;
  rps3_traj tr;
  rps3_sim *a, *b;
  failing fa, fb;
  rps3_controller ca, cb;
  int k, i;
  (void)state;
  plant_and_light(&plant, &light);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_sim_alloc(&plant, NULL, &a, NULL), RPS3_OK);
  assert_int_equal(rps3_sim_alloc(&plant, NULL, &b, NULL), RPS3_OK);
  fa.c = computed_torque(&plant, &tr);
  fb.c = computed_torque(&plant, &tr);
  fa.t_fail = fb.t_fail = 0.5;
  memset(&ca, 0, sizeof(ca));
  memset(&cb, 0, sizeof(cb));
  ca.fn = cb.fn = failing_ct;
  ca.state = &fa;
  cb.state = &fb;
  ca.rate = cb.rate = 1000.0;
  start_on(a, &plant, &tr, 0.0);
  start_on(b, &plant, &tr, 0.0);
  for (k = 1; k <= 500; k++)
    assert_int_equal(rps3_sim_advance(a, &ca, k / 1000.0), RPS3_OK);
  assert_int_equal(rps3_sim_advance(b, &cb, 0.1), RPS3_OK);
  assert_int_equal(rps3_sim_advance(b, &cb, 1.0), RPS3_ERANGE);
  assert_true(rps3_sim_now(b)->t == 0.5 && rps3_sim_now(b)->failed_at == 0.5);
  assert_int_equal(rps3_sim_now(b)->status, RPS3_ERANGE);
  assert_non_null(strstr(rps3_sim_data(b)->err.msg, "controller returned"));
  for (i = 0; i < 6; i++) assert_true(rps3_sim_now(a)->y[i] == rps3_sim_now(b)->y[i]);
  for (i = 0; i < 3; i++) {
    CHECK_REL(rps3_sim_data(b)->pose[i], rps3_sim_data(a)->pose[i], 1e-12, 1.0, "pose%d", i);
    CHECK_REL(rps3_sim_data(b)->dpose[i], rps3_sim_data(a)->dpose[i], 1e-10, 1.0, "dpose%d", i);
    CHECK_REL(rps3_sim_data(b)->c[i], rps3_sim_data(a)->c[i], 1e-12, 1.0, "c%d", i);
  }
  CHECK_REL(rps3_sim_now(b)->T, rps3_sim_now(a)->T, 1e-10, 1.0, "T");
  CHECK_REL(rps3_sim_now(b)->P, rps3_sim_now(a)->P, 1e-12, 1.0, "P");
  CHECK_REL(rps3_sim_now(b)->energy_residual, rps3_sim_now(a)->energy_residual, 1e-9, 1e-12,
            "energy residual");
  /* the stopped run answers with its status, and stays where it was */
  assert_int_equal(rps3_sim_advance(b, &cb, 2.0), RPS3_ERANGE);
  assert_true(rps3_sim_now(b)->t == 0.5);
  rps3_sim_free(a);
  rps3_sim_free(b);
  rps3_ctrl_free(fa.c);
  rps3_ctrl_free(fb.c);
}

/* the noise generator: reproducible by seed, of the requested spread, and
   quantisation puts measurements on the grid */
typedef struct {
  const rps3_sim *s;
  rps3_ctrl *c;
  double sum, sum2;
  long n;
  int on_grid;
  double q;
} probe;

static int probing(void *state, double t, const double l[3],
                   const double dl[3], double F[3]) {
  probe *p = (probe *)state;
  int i;
  for (i = 0; i < 3; i++) {
    double e = l[i] - rps3_sim_now(p->s)->y[i];
    p->sum += e;
    p->sum2 += e * e;
    p->n++;
    if (p->q > 0 && fabs(l[i] / p->q - nearbyint(l[i] / p->q)) > 1e-6)
      p->on_grid = 0;
  }
  return rps3_ctrl_update(p->c, t, l, dl, F);
}

static void noise_and_quantisation(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_sim_options o;
  double y1[6];
  int run;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  for (run = 0; run < 4; run++) {
    rps3_sim *s;
    probe p;
    rps3_sim_options_default(&o);
    o.noise_l = 1.3e-5;
    o.noise_dl = 2.1e-4;
    o.seed = (run == 2) ? 977UL : 4211UL;
    if (run == 3) {
      o.noise_l = 0.0;
      o.quant_l = 1e-5;
    }
    memset(&p, 0, sizeof(p));
    p.on_grid = 1;
    p.q = o.quant_l;
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_PD_GRAVITY, 2000.0, 40.0, &m,
                                     &tr, &p.c, NULL), RPS3_OK);
    p.s = s;
    {
      rps3_controller ctl = {probing, &p, 1000.0, 0u, NULL};
      start_on(s, &m, &tr, 0.0);
      assert_int_equal(rps3_sim_advance(s, &ctl, 2.0), RPS3_OK);
    }
    if (run == 0) memcpy(y1, rps3_sim_now(s)->y, sizeof(y1));
    if (run == 1) assert_memory_equal(y1, rps3_sim_now(s)->y, sizeof(y1));
    if (run == 2) assert_true(memcmp(y1, rps3_sim_now(s)->y, sizeof(y1)) != 0);
    if (run < 3) {
      /* 6000 samples: the mean within 4 sigma / sqrt(n), the spread 5% */
      double mean = p.sum / (double)p.n;
      double sd = sqrt(p.sum2 / (double)p.n - mean * mean);
      assert_true(fabs(mean) < 4.0 * o.noise_l / sqrt((double)p.n));
      CHECK_REL(sd, o.noise_l, 0.05, o.noise_l, "noise spread");
    } else {
      assert_true(p.on_grid);
    }
    rps3_ctrl_free(p.c);
    rps3_sim_free(s);
  }
}

/* the singular surface, whatever the integrator: a platform left without
   forces falls onto it (at t ~ 0.22 s) and every integrator stops there
   with RPS3_ESING, its time and a message that names the measure that
   decided (the condition number of df/dtheta or of Mq against cond_max,
   Mq's positive definiteness, or the step's crossing of det df/dtheta =
   0), never the theta solve's or the integrator's own failure */
static void singular_surface_every_integrator(void **state) {
  rps3_model m;
  rps3_sim_options o;
  double t_first = (double)NAN;
  int it;
  (void)state;
  rps3_model_default(&m);
  m.opt.effects = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  for (it = 0; it < 5; it++) {
    rps3_controller ctl = {zero_force, NULL, 0.0, 0u, NULL};
    double pose[3] = {0.4, 0.15, 0.25}, dpose[3] = {0, 0, -0.1};
    const char *msg;
    rps3_sim *s;
    int st;
    rps3_sim_options_default(&o);
    o.integrator = (rps3_integrator)it;
    /* rk4imp's implicit iteration diverges on a step of 1 ms that ends
       1 ms before the surface, short of it: RPS3_ENOCONV (the step's end
       is regular by the criterion); at 0.25 ms it reaches the surface */
    if (o.integrator == RPS3_INT_RK4IMP) o.h = 2.5e-4;
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_sim_start(s, 0.0, pose, dpose), RPS3_OK);
    st = rps3_sim_advance(s, &ctl, 1.0);
    msg = rps3_sim_data(s)->err.msg;
    print_message("%s: status %d, failed_at %.6g s, message: %s\n",
                  rps3_integrator_name(it), st, rps3_sim_now(s)->failed_at, msg);
    assert_int_equal(st, RPS3_ESING);
    assert_int_equal(rps3_sim_data(s)->err.code, RPS3_ESING);
    assert_true(strncmp(msg, "singular configuration at t = ", 30) == 0);
    assert_true(strstr(msg, "condition number") != NULL ||
                strstr(msg, "not positive definite") != NULL ||
                strstr(msg, "det df/dtheta") != NULL);
    /* the same surface: the integrators stop within 1 ms of each other
       (rk4 at a step of 1 ms) */
    if (isnan(t_first)) t_first = rps3_sim_now(s)->failed_at;
    assert_true(fabs(rps3_sim_now(s)->failed_at - t_first) < 1e-3);
    assert_true(rps3_sim_now(s)->failed_at > 0.1 && rps3_sim_now(s)->failed_at < 0.5);
    rps3_sim_free(s);
  }
  /* rk4imp at a step of 1.5 ms: its iteration diverges a step before the
     surface with no evaluation failing; the step's end lies past it by
     the same criterion, and the message says so */
  {
    rps3_controller ctl = {zero_force, NULL, 0.0, 0u, NULL};
    double pose[3] = {0.4, 0.15, 0.25}, dpose[3] = {0, 0, -0.1};
    rps3_sim *s;
    rps3_sim_options_default(&o);
    o.integrator = RPS3_INT_RK4IMP;
    o.h = 1.5e-3;
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_sim_start(s, 0.0, pose, dpose), RPS3_OK);
    assert_int_equal(rps3_sim_advance(s, &ctl, 1.0), RPS3_ESING);
    print_message("rk4imp, h = 1.5 ms: %s\n", rps3_sim_data(s)->err.msg);
    assert_non_null(strstr(rps3_sim_data(s)->err.msg, "rk4imp stopped a step of"));
    assert_non_null(strstr(rps3_sim_data(s)->err.msg, "det df/dtheta"));
    assert_true(rps3_sim_now(s)->failed_at < t_first && rps3_sim_now(s)->failed_at > t_first - 2.0 * o.h);
    rps3_sim_free(s);
  }
}

/* hard cases: each ends in a clean status with its time, or stays stable */
static void hard_cases(void **state) {
  rps3_model m, m0;
  rps3_traj tr;
  rps3_sim_options o;
  rps3_sim *s;
  double e;
  int st, k;
  (void)state;
  rps3_model_default(&m);
  m.opt.effects = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_sim_options_default(&o);

  /* towards the base: no forces, the platform falls onto the singular
     surface, which stops the run (RPS3_ESING), with finite states */
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
  {
    rps3_controller ctl = {zero_force, NULL, 0.0, 0u, NULL};
    double pose[3] = {0.4, 0.15, 0.25}, dpose[3] = {0, 0, -0.1};
    assert_int_equal(rps3_sim_start(s, 0.0, pose, dpose), RPS3_OK);
    st = rps3_sim_advance(s, &ctl, 3.0);
    print_message("falling platform: %s at t = %.4g s: %s\n",
                  rps3_strerror(st), rps3_sim_now(s)->failed_at, rps3_sim_data(s)->err.msg);
    assert_int_equal(st, RPS3_ESING);
    assert_true(rps3_sim_now(s)->failed_at > 0.0 && rps3_sim_now(s)->failed_at < 3.0);
    for (k = 0; k < 8; k++) assert_true(isfinite(rps3_sim_now(s)->y[k]));
    assert_int_equal(rps3_sim_advance(s, &ctl, 4.0), st); /* stays stopped */
  }
  rps3_sim_free(s);

  /* towards the singular surface: a path whose tilt passes beta* */
  {
    rps3_data *d;
    double bs;
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    bs = singular_beta(&m, d, 0.12, 0.3, 1.5);
    rps3_data_free(d);
    memset(&tr, 0, sizeof(tr));
    tr.kind = RPS3_TRAJ_SINE;
    tr.sine.mean[1] = bs - 0.2;
    tr.sine.amp[1] = 0.4;
    tr.sine.freq[1] = 0.25;
    tr.sine.phase[1] = -0.5 * PI;
    tr.sine.mean[2] = 0.12;
    tr.sine.duration = 2.0;
    st = closed_loop(&m, &m, &tr, RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0, &o,
                     &e, &s);
    print_message("towards beta* = %.4f: %s (t = %.4g s) %s; final beta "
                  "%.4f, tracking error %.3g m\n", bs, rps3_strerror(st),
                  rps3_sim_now(s)->failed_at, rps3_sim_data(s)->err.msg, rps3_sim_data(s)->pose[1], e);
    if (st == RPS3_OK) {
      /* stable: the plant cannot cross the singular surface (its mass
         matrix grows without bound there); it ends on its side, on its
         assembly mode, while the path ends at beta* + 0.2 */
      assert_true(rps3_sim_data(s)->pose[1] < bs);
      assert_int_equal(rps3_sim_data(s)->mode, rps3_sim_now(s)->mode);
    } else {
      assert_true(st == RPS3_ESING || st == RPS3_EBRANCH ||
                  st == RPS3_ENOCONV);
      assert_true(rps3_sim_now(s)->failed_at > 0.0 && rps3_sim_now(s)->failed_at < 2.0);
      assert_true(strlen(rps3_sim_data(s)->err.msg) > 0);
    }
    rps3_sim_free(s);
  }

  /* a controller that saturates: the actuators clip, the run ends clean */
  rps3_traj_default(&tr);
  o.fmax = 0.5;
  st = closed_loop(&m, &m, &tr, RPS3_CTRL_PD_GRAVITY, 2000.0, 40.0, &o, &e, &s);
  print_message("fmax 0.5 N: %s, %ld of %ld ticks saturated, error %.3g m\n",
                rps3_strerror(st), rps3_sim_now(s)->nsat, rps3_sim_now(s)->nticks, e);
  assert_true(rps3_sim_now(s)->nsat > 0);
  assert_true(st == RPS3_OK || rps3_sim_now(s)->failed_at > 0.0);
  rps3_sim_free(s);
  o.fmax = 0.0;

  /* zero link mass in the plant (the paper's case 1) */
  m0 = m;
  m0.m = 0.0;
  assert_int_equal(rps3_model_init(&m0, NULL), RPS3_OK);
  assert_int_equal(closed_loop(&m0, &m0, &tr, RPS3_CTRL_COMPUTED_TORQUE, 400.0,
                               40.0, &o, &e, NULL), RPS3_OK);
  assert_true(e < 1e-5);

  /* the stroke: a run that leaves [l_min, l_max] stops with EREACH */
  o.l_max = 0.3;
  st = closed_loop(&m, &m, &tr, RPS3_CTRL_PD, 20.0, 1.0, &o, &e, &s);
  assert_int_equal(st, RPS3_EREACH);
  assert_non_null(strstr(rps3_sim_data(s)->err.msg, "stroke"));
  rps3_sim_free(s);
}

/*
 * Stick-slip: a PD controller holds the platform still against Coulomb
 * friction at the pins (the links stick).  With exact sign the equations
 * are discontinuous at dtheta = 0; rkf45 must still finish (it may not
 * stall: max_steps bounds it), and the regularised law must need fewer
 * evaluations.  Both counts are printed: the measurement.
 */
static void stick_slip(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_sim_options o;
  long evals[2];
  int k;
  (void)state;
  rps3_traj_default(&tr);
  tr.helix.period = 0.5;
  tr.helix.blend = 0.125;
  for (k = 0; k < 2; k++) {
    rps3_sim *s;
    double e;
    int st;
    rps3_model_default(&m);
    m.opt.effects = RPS3_EFF_DEFAULT | RPS3_EFF_PIN_FRICTION;
    m.friction.coulomb = 0.05;
    m.friction.viscous = 0.002;
    m.friction.vreg = k ? 1e-3 : 0.0;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    rps3_sim_options_default(&o);
    o.integrator = RPS3_INT_RKF45;
    o.epsabs = o.epsrel = 1e-8;
    st = closed_loop(&m, &m, &tr, RPS3_CTRL_PD_GRAVITY, 3000.0, 20.0, &o, &e,
                     &s);
    evals[k] = rps3_sim_now(s)->nevals;
    print_message("stick-slip, %s: %s, %ld steps, %ld evaluations, error "
                  "%.3g m\n", k ? "tanh(dtheta / 1e-3)" : "exact sign",
                  rps3_strerror(st), rps3_sim_now(s)->nsteps, rps3_sim_now(s)->nevals, e);
    assert_int_equal(st, RPS3_OK);
    rps3_sim_free(s);
  }
  assert_true(evals[1] < evals[0]);
}

/* bad options and calls: messages naming the field, statuses */
static void errors(void **state) {
  rps3_model m;
  rps3_sim_options o;
  rps3_sim *s = NULL;
  rps3_check chk;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_sim_options_default(&o);
  o.h = -1e-3;
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "simulate.h = "));
  assert_null(s);
  rps3_sim_options_default(&o);
  o.integrator = RPS3_INT_RKF45;
  o.epsabs = o.epsrel = 0.0;
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "simulate.epsabs"));
  rps3_sim_options_default(&o);
  o.l_max = o.l_min;
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, &chk), RPS3_EINVAL);
  o.l_max = HUGE_VAL;
  o.noise_l = (double)NAN;
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "simulate.noise_l"));
  assert_int_equal(chk.field, -1);
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_EINVAL);
  assert_int_equal(rps3_sim_alloc(&m, NULL, &s, &chk), RPS3_OK);
  assert_string_equal(chk.msg, "");
  {
    rps3_controller ctl = {zero_force, NULL, -1.0, 0u, NULL};
    assert_int_equal(rps3_sim_advance(s, &ctl, 1.0), RPS3_ESTATE);
  }
  rps3_sim_free(s);
  rps3_sim_free(NULL);
  assert_string_equal(rps3_integrator_name(RPS3_INT_MSBDF), "msbdf");
  assert_int_equal(rps3_integrator_index("rk4imp"), RPS3_INT_RK4IMP);
  assert_int_equal(rps3_integrator_index("euler"), -1);
  assert_string_equal(rps3_ctrl_name(RPS3_CTRL_PD_GRAVITY), "pd_gravity");
  assert_int_equal(rps3_ctrl_index("computed_torque"),
                   RPS3_CTRL_COMPUTED_TORQUE);
  {
    rps3_traj tr;
    rps3_ctrl *c = NULL;
    rps3_traj_default(&tr);
    assert_int_equal(
        rps3_ctrl_alloc(RPS3_CTRL_PD, -1.0, 0.0, &m, &tr, &c, &chk),
        RPS3_EINVAL);
    assert_non_null(strstr(chk.msg, "simulate.kp"));
    assert_int_equal(chk.field, -1);
    /* the trajectory's refusal names its field by identifier */
    tr.helix.period = -1.0;
    assert_int_equal(
        rps3_ctrl_alloc(RPS3_CTRL_PD, 1.0, 0.0, &m, &tr, &c, &chk),
        RPS3_EINVAL);
    assert_int_equal(chk.field, RPS3_F_HELIX_PERIOD);
    assert_true(strncmp(chk.msg, "trajectory.period = ", 20) == 0);
    assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_PD, 1.0, 0.0, &m, &tr, &c, NULL),
                     RPS3_EINVAL);
    assert_null(c);
    /* a success clears chk */
    rps3_traj_default(&tr);
    assert_int_equal(
        rps3_ctrl_alloc(RPS3_CTRL_PD, 1.0, 0.0, &m, &tr, &c, &chk), RPS3_OK);
    assert_int_equal(chk.field, -1);
    assert_string_equal(chk.msg, "");
    rps3_ctrl_free(c);
  }
}

/*
 * Settings that would make a loop run for ever are refused before any
 * work, with the field and the limit (rps3_sim_check_rate, rps3.h): a
 * control rate of 1e9 or 1e300 Hz (a typo) against the step, a rate whose
 * ticks double precision cannot tell apart at the run's times, a fixed
 * step that would need more than max_steps steps a period; rps3_sim_advance
 * refuses the same at once (RPS3_EINVAL, the run intact), and a t_end
 * before the simulation's time.  Each limit is probed on both sides.
 */
static void bounded_calls(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_sim_options o;
  rps3_sim *s;
  rps3_check chk;
  double y0[8];
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  rps3_sim_options_default(NULL); /* does nothing, does not crash */
  rps3_sim_options_default(&o);
#define RATE(rate_, tmax_, st_, field_)                                       \
  do {                                                                        \
    snprintf(chk.msg, sizeof chk.msg, "stale");                               \
    assert_int_equal(rps3_sim_check_rate(&o, (rate_), (tmax_), &chk), (st_)); \
    if ((st_) == RPS3_OK && chk.msg[0] != '\0')                               \
      fail_msg("rate %g, t_max %g: OK left \"%s\"", (double)(rate_),         \
               (double)(tmax_), chk.msg);                                     \
    if ((st_) != RPS3_OK && strstr(chk.msg, (field_)) != chk.msg)             \
      fail_msg("rate %g, t_max %g: %s", (double)(rate_), (double)(tmax_),   \
               chk.msg);                                                      \
    assert_int_equal(chk.field, -1);                                          \
    assert_int_equal(rps3_sim_check_rate(&o, (rate_), (tmax_), NULL), (st_)); \
  } while (0)
  /* the step: at most RPS3_SIM_RATE_H_MAX periods a step h = 1 ms */
  RATE(1000.0, 10.0, RPS3_OK, "");
  RATE(0.0, 1e300, RPS3_OK, ""); /* continuous: max_steps bounds it */
  RATE(0.5e6, 10.0, RPS3_OK, "");
  RATE(2e6, 10.0, RPS3_EINVAL, "simulate.rate = ");
  RATE(1e9, 10.0, RPS3_EINVAL, "simulate.rate = ");
  RATE(1e300, 10.0, RPS3_EINVAL, "simulate.rate = ");
  RATE(HUGE_VAL, 10.0, RPS3_EINVAL, "simulate.rate = ");
  RATE((double)NAN, 10.0, RPS3_EINVAL, "simulate.rate = ");
  RATE(-1.0, 10.0, RPS3_EINVAL, "simulate.rate = ");
  /* the time: at most RPS3_SIM_MAX_PERIODS periods up to t_max */
  RATE(1000.0, 0.5e5, RPS3_OK, "");
  RATE(1000.0, 2e5, RPS3_EINVAL, "simulate.rate = ");
  RATE(1000.0, 1e300, RPS3_EINVAL, "simulate.rate = ");
  RATE(1000.0, (double)NAN, RPS3_EINVAL, "t_max = ");
  /* rk4's steps a period against max_steps: h 1e-8 at 1 Hz is 1e8 */
  o.h = 1e-8;
  o.hmin = 1e-12;
  RATE(1.0, 10.0, RPS3_EINVAL, "simulate.h = ");
  o.max_steps = 50000000L; /* half the 1e8 steps: still refused */
  RATE(1.0, 10.0, RPS3_EINVAL, "simulate.h = ");
  o.max_steps = 200000000L;
  RATE(1.0, 10.0, RPS3_OK, "");
  rps3_sim_options_default(&o);
  o.integrator = RPS3_INT_RKF45; /* adaptive: its own nmax bounds it */
  o.h = 1e-8;
  RATE(1.0, 10.0, RPS3_OK, "");
  /* its h is a first guess: the period is measured against hmin */
  o.h = 1.0;
  RATE(1e4, 10.0, RPS3_OK, "");
  RATE(1e16, 1e-9, RPS3_EINVAL, "simulate.rate = ");
  assert_non_null(strstr(chk.msg, "hmin"));
  rps3_sim_options_default(&o);
  o.h = (double)NAN; /* the options' own check first */
  RATE(1000.0, 10.0, RPS3_EINVAL, "simulate.h = ");
#undef RATE

  /* NULL pointers and unchecked structs: RPS3_EINVAL as rps3.h says */
  {
    const double p0[3] = {0.5, 0.1, 0.3};
    double F[3];
    rps3_ctrl bogus;
    assert_int_equal(rps3_sim_start(NULL, 0.0, p0, p0), RPS3_EINVAL);
    assert_int_equal(rps3_sim_advance(NULL, NULL, 1.0), RPS3_EINVAL);
    assert_int_equal(rps3_ctrl_update(NULL, 0.0, p0, p0, F), RPS3_EINVAL);
    memset(&bogus, 0, sizeof bogus);
    bogus.kind = (rps3_ctrl_kind)9;
    assert_int_equal(rps3_ctrl_update(&bogus, 0.0, p0, p0, F), RPS3_EINVAL);
    bogus.kind = RPS3_CTRL_PD; /* never allocated: no workspaces */
    assert_int_equal(rps3_ctrl_update(&bogus, 0.0, p0, p0, F), RPS3_EINVAL);
  }

  /* rps3_sim_advance: refused at once, nothing moves, the run goes on */
  assert_int_equal(rps3_sim_alloc(&m, NULL, &s, NULL), RPS3_OK);
  start_on(s, &m, &tr, 0.0);
  assert_int_equal(rps3_sim_advance(
                       s, &(rps3_controller){zero_force, NULL, 1000.0, 0u, NULL}, 0.01),
                   RPS3_OK);
  memcpy(y0, rps3_sim_now(s)->y, sizeof y0);
  {
    const double bad_rate[3] = {1e9, 1e300, (double)INFINITY};
    int k;
    for (k = 0; k < 3; k++) {
      rps3_controller c = {zero_force, NULL, bad_rate[k], 0u, NULL};
      assert_int_equal(rps3_sim_advance(s, &c, 1.0), RPS3_EINVAL);
      assert_non_null(strstr(rps3_sim_data(s)->err.msg, "simulate.rate = "));
    }
  }
  {
    rps3_controller c = {zero_force, NULL, 1000.0, 0u, NULL};
    assert_int_equal(rps3_sim_advance(s, &c, 1e300), RPS3_EINVAL);
    assert_non_null(strstr(rps3_sim_data(s)->err.msg, "control periods a run"));
    assert_int_equal(rps3_sim_advance(s, &c, 0.005), RPS3_EINVAL);
    assert_non_null(strstr(rps3_sim_data(s)->err.msg, "is before the simulation's time"));
    assert_int_equal(rps3_sim_advance(s, &c, (double)NAN), RPS3_EINVAL);
    assert_int_equal(rps3_sim_advance(s, NULL, 1.0), RPS3_EINVAL);
    assert_int_equal(rps3_sim_advance(
                         s, &(rps3_controller){NULL, NULL, 1000.0, 0u, NULL}, 1.0),
                     RPS3_EINVAL);
    assert_true(rps3_sim_now(s)->t == 0.01 && memcmp(y0, rps3_sim_now(s)->y, sizeof y0) == 0);
    assert_int_equal(rps3_sim_now(s)->status, RPS3_OK);
    assert_int_equal(rps3_sim_advance(s, &c, 0.01), RPS3_OK); /* t_end = t */
    assert_true(rps3_sim_now(s)->t == 0.01);
    assert_int_equal(rps3_sim_advance(s, &c, 0.02), RPS3_OK);
    assert_true(rps3_sim_now(s)->t == 0.02);
  }
  {
    /* a continuous controller to a far t_end: max_steps ends the call */
    rps3_controller c = {zero_force, NULL, 0.0, 0u, NULL};
    assert_int_equal(rps3_sim_advance(s, &c, 1e300), RPS3_ENOCONV);
  }
  rps3_sim_free(s);
}

/* the implicit integrators run the same round trip (stiff friction is what
   they are for; here they must agree with the explicit ones) */
static void implicit_integrators(void **state) {
  rps3_model m;
  rps3_traj tr;
  int integ;
  (void)state;
  model_entropy(&m);
  m.friction.vreg = 1e-3;
  m.friction.coulomb = 0.02;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  fast_sine(&tr);
  for (integ = RPS3_INT_MSBDF; integ <= RPS3_INT_RK4IMP; integ++) {
    rps3_sim_options o;
    rps3_sim *s;
    rps3_ctrl *c;
    rps3_data *w;
    double e;
    rps3_sim_options_default(&o);
    o.integrator = (rps3_integrator)integ;
    o.epsabs = o.epsrel = 1e-10;
    o.h = 1e-4;
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_OPEN_LOOP, 0, 0, &m, &tr, &c, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &w), RPS3_OK);
    {
      rps3_controller ctl = {rps3_ctrl_update, c, 0.0, 0u, NULL};
      start_on(s, &m, &tr, 0.7);
      if (rps3_sim_advance(s, &ctl, 0.75) != RPS3_OK)
        fail_msg("%s: %s", rps3_integrator_name(integ), rps3_sim_data(s)->err.msg);
      e = length_error(&m, &tr, w, rps3_sim_now(s)->y, 0.75);
    }
    print_message("%s: |l - l_d| %.3g m after 0.05 s, %ld steps, %ld "
                  "evaluations\n", rps3_integrator_name(integ), e, rps3_sim_now(s)->nsteps,
                  rps3_sim_now(s)->nevals);
    assert_true(e < 1e-8);
    rps3_data_free(w);
    rps3_ctrl_free(c);
    rps3_sim_free(s);
  }
}

/*
 * A pure relative tolerance (epsabs = 0) is refused for every adaptive
 * integrator: GSL's error level epsabs + epsrel |y_i| is 0 where a state
 * component is 0 (the work integrals start there), and msbdf then raises
 * "errlev <= zero" through GSL's error handler, which this program leaves
 * at its default (abort).  Were it accepted, the run below would show it.
 */
static void pure_relative_tolerance_refused(void **state) {
  static const rps3_integrator adaptive[] = {RPS3_INT_MSBDF, RPS3_INT_RKF45,
                                             RPS3_INT_RK8PD};
  rps3_model m;
  rps3_traj tr;
  size_t k;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  fast_sine(&tr);
  for (k = 0; k < sizeof adaptive / sizeof adaptive[0]; k++) {
    rps3_sim_options o;
    rps3_sim *s = NULL;
    rps3_check chk;
    int st;
    rps3_sim_options_default(&o);
    o.integrator = adaptive[k];
    o.epsabs = 0.0;
    o.epsrel = 2.385e-7;
    st = rps3_sim_alloc(&m, &o, &s, &chk);
    if (st == RPS3_OK) {
      rps3_ctrl *c;
      assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_OPEN_LOOP, 0, 0, &m, &tr,
                                       &c, NULL), RPS3_OK);
      {
        rps3_controller ctl = {rps3_ctrl_update, c, 0.0, 0u, NULL};
        start_on(s, &m, &tr, 0.0);
        (void)rps3_sim_advance(s, &ctl, 0.05);
      }
      rps3_ctrl_free(c);
      rps3_sim_free(s);
      fail_msg("%s with epsabs = 0 accepted",
               rps3_integrator_name(o.integrator));
    }
    assert_int_equal(st, RPS3_EINVAL);
    assert_null(s);
    assert_non_null(strstr(chk.msg, "simulate.epsabs = 0"));
  }
}


/* ------------------------------------------- the plant's state offered */

/*
 * Computed torque written by a user (tests/bench/user_law.h, public API
 * alone) that declares RPS3_CTRL_USES_PLANT and takes the offered Mq and hq
 * gives the run of the library's computed torque (rps3_ctrl_bind) to
 * TOL_EXACT (bit for bit but for the rounding of F = Mq a + hq: the same
 * operations in another order).  It is offered the plant's state at every
 * tick, the first too;
 * the same law solving its own model (rps3_fwddyn) gives the same run to
 * the theta solve's tolerance.
 */
static void user_law_with_plant_is_library_law(void **state) {
  rps3_model plant;
  rps3_traj tr;
  rps3_sim *a, *b, *c;
  rps3_ctrl *ct;
  user_law ub, uc;
  rps3_controller la, lb, lc;
  int k, i, n = 1500;
  (void)state;
  rps3_model_default(&plant);
  assert_int_equal(rps3_model_init(&plant, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_sim_alloc(&plant, NULL, &a, NULL), RPS3_OK);
  assert_int_equal(rps3_sim_alloc(&plant, NULL, &b, NULL), RPS3_OK);
  assert_int_equal(rps3_sim_alloc(&plant, NULL, &c, NULL), RPS3_OK);
  ct = computed_torque(&plant, &tr);
  assert_int_equal(user_law_init(&ub, &plant, &tr, 400.0, 40.0, 1), RPS3_OK);
  assert_int_equal(user_law_init(&uc, &plant, &tr, 400.0, 40.0, 0), RPS3_OK);
  la = rps3_ctrl_bind(ct, 1000.0);
  assert_true(la.caps == RPS3_CTRL_USES_PLANT && la.fn_plant != NULL &&
              la.fn == rps3_ctrl_update && la.state == ct);
  lb = user_law_controller(&ub, 1000.0);
  lc = user_law_controller(&uc, 1000.0);
  start_on(a, &plant, &tr, 0.0);
  start_on(b, &plant, &tr, 0.0);
  start_on(c, &plant, &tr, 0.0);
  for (k = 1; k <= n; k++) {
    assert_int_equal(rps3_sim_advance(a, &la, k / 1000.0), RPS3_OK);
    assert_int_equal(rps3_sim_advance(b, &lb, k / 1000.0), RPS3_OK);
    if (k % 10 == 0 || k == 1) {
      for (i = 0; i < 3; i++)
        CHECK_REL(rps3_sim_now(b)->F_cmd[i], rps3_sim_now(a)->F_cmd[i], TOL_EXACT, 1.0, "t %d F%d", k, i);
      for (i = 0; i < 6; i++)
        CHECK_REL(rps3_sim_now(b)->y[i], rps3_sim_now(a)->y[i], TOL_EXACT, 1e-3, "t %d y%d", k, i);
    }
  }
  /* one call over the run: the fallback of the law, its own solve */
  assert_int_equal(rps3_sim_advance(c, &lc, n / 1000.0), RPS3_OK);
  for (i = 0; i < 6; i++)
    CHECK_REL(rps3_sim_now(c)->y[i], rps3_sim_now(a)->y[i], TOL_PHYS, 1e-3, "own solve y%d", i);
  assert_int_equal(ub.offered, rps3_sim_now(b)->nticks);
  assert_int_equal(ub.solved, 0);
  assert_int_equal(uc.offered, 0);
  assert_int_equal(uc.solved, rps3_sim_now(c)->nticks);
  assert_int_equal(rps3_sim_now(a)->nevals, rps3_sim_now(b)->nevals);
  rps3_sim_free(a);
  rps3_sim_free(b);
  rps3_sim_free(c);
  rps3_ctrl_free(ct);
  user_law_free(&ub);
  user_law_free(&uc);
}

/* a law with RPS3_CTRL_USES_PLANT that checks the offered state against
   an independent evaluation, rps3_fwddyn of the plant's model at the
   tick's (l, dl), and drives the plant with the library's law */
typedef struct {
  const rps3_sim *s;
  rps3_ctrl *c;
  rps3_data *w;   /* the independent evaluation, warm from the last tick */
  long calls, offered;
} plant_probe;

static int probe_plant(void *state, double t, const double l[3],
                       const double dl[3], const rps3_plant_state *plant,
                       double F[3]) {
  plant_probe *p = (plant_probe *)state;
  rps3_data *w = p->w;
  int i, j;
  p->calls++;
  if (plant != NULL) {
    p->offered++;
    assert_ptr_equal(plant->model, rps3_sim_plant(p->s));
    assert_true(plant->t == t && t == rps3_sim_now(p->s)->t);
    for (i = 0; i < 3; i++) {
      /* the measurement is the plant's state, bit for bit */
      assert_true(plant->l[i] == l[i] && plant->dl[i] == dl[i]);
      assert_true(l[i] == rps3_sim_now(p->s)->y[i] && dl[i] == rps3_sim_now(p->s)->y[3 + i]);
      w->l[i] = l[i];
      w->dl[i] = dl[i];
      w->F[i] = 0.0;
    }
    if (rps3_fwddyn(plant->model, w) != RPS3_OK)
      fail_msg("t %g: %s", t, w->err.msg);
    assert_int_equal(plant->mode, w->mode);
    assert_int_equal(plant->mode, rps3_sim_now(p->s)->mode);
    for (i = 0; i < 3; i++) {
      /* two theta solves to their tolerance */
      CHECK_REL(plant->theta[i], w->theta[i], TOL_PHYS, 1.0, "t %g th%d", t,
                i);
      CHECK_REL(plant->dtheta[i], w->dtheta[i], TOL_PHYS, 1.0,
                "t %g dth%d", t, i);
      CHECK_REL(plant->hq[i], w->hq[i], TOL_PHYS, 1.0, "t %g hq%d", t, i);
      for (j = 0; j < 3; j++)
        CHECK_REL(plant->Mq[3 * i + j], w->Mq[i][j], TOL_PHYS, 1e-3,
                  "t %g Mq%d%d", t, i, j);
    }
  }
  return rps3_ctrl_update_plant(p->c, t, l, dl, plant, F);
}

/* the plant with every effect but the payload (friction in hq) */
static void plant_every_effect(rps3_model *m) {
  rps3_model_default(m);
  m->opt.effects = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD;
  m->friction.viscous = 0.01;
  m->friction.coulomb = 0.005;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

/*
 * The offered state is the plant's at the tick: theta, its rates, Mq, hq
 * and the mode agree with rps3_fwddyn of the plant's model at the tick's
 * (l, dl), for the paper's effects and for every effect with friction.
 * It is offered at every tick of an exact measurement, and NULL (the
 * law still called, fn_plant) with noise on the lengths or the rates, with
 * quantisation, and for a continuous law.
 */
static void plant_state_is_the_plant(void **state) {
  rps3_model plant;
  rps3_traj tr;
  int v;
  (void)state;
  rps3_traj_default(&tr);
  for (v = 0; v < 6; v++) {
    rps3_sim_options o;
    rps3_sim *s;
    plant_probe p;
    rps3_controller ctl = {NULL, NULL, 1000.0, RPS3_CTRL_USES_PLANT,
                           probe_plant};
    if (v == 1)
      plant_every_effect(&plant);
    else {
      rps3_model_default(&plant);
      assert_int_equal(rps3_model_init(&plant, NULL), RPS3_OK);
    }
    rps3_sim_options_default(&o);
    if (v == 2) o.noise_l = 1e-9;
    if (v == 3) o.noise_dl = 1e-9;
    if (v == 4) o.quant_l = 1e-12;
    if (v == 5) ctl.rate = 0.0;
    memset(&p, 0, sizeof(p));
    assert_int_equal(rps3_sim_alloc(&plant, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&plant, &p.w), RPS3_OK);
    p.s = s;
    p.c = computed_torque(&plant, &tr);
    ctl.state = &p;
    start_on(s, &plant, &tr, 0.0);
    assert_int_equal(rps3_sim_advance(s, &ctl, 0.05), RPS3_OK);
    assert_int_equal(rps3_sim_advance(s, &ctl, 0.3), RPS3_OK);
    assert_true(p.calls > 0);
    if (v < 2) {
      assert_int_equal(rps3_sim_now(s)->nticks, 300);
      assert_int_equal(p.offered, rps3_sim_now(s)->nticks);
    } else {
      assert_int_equal(p.offered, 0);
    }
    rps3_sim_free(s);
    rps3_data_free(p.w);
    rps3_ctrl_free(p.c);
  }
}

/* a law that counts its calls; and a plant-state form that must not be
   called for a controller without the capability */
static int counting_law(void *state, double t, const double l[3],
                        const double dl[3], double F[3]) {
  long *n = (long *)state;
  (void)t;
  (void)l;
  (void)dl;
  (*n)++;
  F[0] = F[1] = F[2] = 0.0;
  return RPS3_OK;
}

static int never_law(void *state, double t, const double l[3],
                     const double dl[3], const rps3_plant_state *plant,
                     double F[3]) {
  (void)state;
  (void)t;
  (void)l;
  (void)dl;
  (void)plant;
  (void)F;
  fail_msg("fn_plant called without RPS3_CTRL_USES_PLANT");
  return RPS3_EINVAL;
}

#if defined(__GNUC__)
/* the initialiser of existing code names the first three members: C
   zero-initialises the rest, which -Wextra points out */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
static rps3_controller three_member_form(long *n) {
  rps3_controller c = {counting_law, NULL, 1000.0};
  c.state = n;
  return c;
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

/*
 * A controller without the capability gets the five-argument call: the
 * three-member initialiser of existing code (caps 0, fn_plant NULL), and a
 * fn_plant without the caps bit, which is not called.  Unknown caps bits,
 * and the capability without fn_plant, are refused.
 */
static void law_without_capability(void **state) {
  rps3_model m;
  rps3_traj tr;
  rps3_sim *s;
  long n = 0;
  rps3_controller c;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_sim_alloc(&m, NULL, &s, NULL), RPS3_OK);
  c = three_member_form(&n);
  assert_true(c.caps == 0 && c.fn_plant == NULL);
  start_on(s, &m, &tr, 0.0);
  assert_int_equal(rps3_sim_advance(s, &c, 0.01), RPS3_OK);
  assert_int_equal(n, 10);
  c.fn_plant = never_law;
  assert_int_equal(rps3_sim_advance(s, &c, 0.02), RPS3_OK);
  assert_int_equal(n, 20);
  c.caps = 2u; /* no such capability */
  assert_int_equal(rps3_sim_advance(s, &c, 0.03), RPS3_EINVAL);
  assert_non_null(strstr(rps3_sim_data(s)->err.msg, "caps"));
  c.caps = RPS3_CTRL_USES_PLANT;
  c.fn_plant = NULL;
  assert_int_equal(rps3_sim_advance(s, &c, 0.03), RPS3_EINVAL);
  assert_int_equal(n, 20);
  assert_true(rps3_sim_now(s)->t == 0.02);
  rps3_sim_free(s);
}

/* the opaque simulation's accessors: its report, workspace, plant and
   options; NULL for no simulation */
static void accessors_of_the_opaque_simulation(void **state) {
  rps3_model plant;
  rps3_sim_options o;
  rps3_sim *s = NULL;
  const double pose[3] = {0.3, 0.2, 0.25}, zero[3] = {0.0, 0.0, 0.0};
  (void)state;
  rps3_model_default(&plant);
  assert_int_equal(rps3_model_init(&plant, NULL), RPS3_OK);
  rps3_sim_options_default(&o);
  o.h = 5e-4;
  assert_int_equal(rps3_sim_alloc(&plant, &o, &s, NULL), RPS3_OK);
  assert_int_equal(rps3_sim_start(s, 0.125, pose, zero), RPS3_OK);
  assert_true(rps3_sim_now(s)->t == 0.125);
  assert_int_equal(rps3_sim_now(s)->status, RPS3_OK);
  assert_true(isnan(rps3_sim_now(s)->failed_at));
  assert_true(rps3_sim_data(s)->pose[2] == 0.25);
  assert_true(rps3_sim_now(s)->y[0] == rps3_sim_data(s)->l[0]);
  assert_true(rps3_sim_plant(s)->R == plant.R && rps3_sim_plant(s) != &plant);
  assert_true(rps3_sim_opts(s)->h == 5e-4);
  assert_null(rps3_sim_now(NULL));
  assert_null(rps3_sim_data(NULL));
  assert_null(rps3_sim_plant(NULL));
  assert_null(rps3_sim_opts(NULL));
  rps3_sim_free(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(accessors_of_the_opaque_simulation),
      cmocka_unit_test(round_trip_every_effect),
      cmocka_unit_test(rk4_converges_at_order_4),
      cmocka_unit_test(energy_balance),
      cmocka_unit_test(controllers_track_the_helix),
      cmocka_unit_test(one_call_or_one_per_period),
      cmocka_unit_test(report_where_the_run_stopped),
      cmocka_unit_test(noise_and_quantisation),
      cmocka_unit_test(hard_cases),
      cmocka_unit_test(singular_surface_every_integrator),
      cmocka_unit_test(stick_slip),
      cmocka_unit_test(errors),
      cmocka_unit_test(bounded_calls),
      cmocka_unit_test(implicit_integrators),
      cmocka_unit_test(pure_relative_tolerance_refused),

      cmocka_unit_test(user_law_with_plant_is_library_law),
      cmocka_unit_test(plant_state_is_the_plant),
      cmocka_unit_test(law_without_capability),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
