/*
 * test_sim_bodies.c - the simulation and the controllers of a general
 * plant (RPS3_BODIES_GENERAL: random bodies, friction in every joint): the
 * energy balance with an adaptive and a fixed-step integrator (RK4 at its
 * order), computed torque with the plant's model tracking the helix, and
 * no allocation after set-up.  The forward dynamics of the general bodies
 * themselves are tests/test_fd_bodies.c.
 */
#include "testutil.h"

#include "bodies_random.h"

/* the paper's helix scaled to model_entropy()'s platform (r* < r/2) */
static void helix_entropy(rps3_traj *tr) {
  rps3_traj_default(tr);
  tr->helix.radius = 0.0031;
  tr->helix.z0 = 0.2713;
}

/* start s on the trajectory at t */
static void start_on(rps3_sim *s, const rps3_model *m, const rps3_traj *tr,
                     double t) {
  double pose[3], dpose[3];
  assert_int_equal(rps3_traj_eval(m, tr, t, pose, dpose, NULL), RPS3_OK);
  if (rps3_sim_start(s, t, pose, dpose) != RPS3_OK)
    fail_msg("start at t = %g: %s", t, rps3_sim_data(s)->err.msg);
}

/*
 * random_general's friction made smooth enough for a simulation at 1 kHz:
 * its regularised Coulomb laws (pins 0.01 rad/s, prismatic joints 1e-3
 * m/s) are slopes of up to 500 N s/m on ~0.1 kg, time constants of
 * 0.2 ms that a fixed 1 ms step cannot follow (RK4 is then near its
 * stability limit, the balance off by 1e-6 of the energy a step,
 * measured); 0.5 rad/s and 0.05 m/s keep them above 5 ms.
 */
static void smooth_friction(rps3_model *m) {
  int i;
  for (i = 0; i < 3; i++) {
    m->leg[i].pin.vreg = 0.5;
    m->leg[i].prismatic.vreg = 0.05;
  }
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
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
 * A simulated general plant (every effect, friction in every joint,
 * smooth_friction) keeps its energy balance: the work of the actuators
 * plus the friction's equals the change of T + P (the simulation's
 * energy_residual, T and P of rps3_energy, which shares nothing with Mq),
 * over 0.1 s of free motion then 0.1 s of PD + gravity with the plant's
 * model at 1 kHz.  Adaptive rkf45 at epsabs = epsrel = 1e-10: 1e-8 of the
 * energy, as test_sim.c's energy_balance.  RK4 at a fixed step h: the
 * residual is its global error, O(h^4) (1e-8 of the energy at h = 1 ms,
 * measured; checked at 1e-6 each period), and halving h divides it by
 * ~16 (17.5 measured; 8 to 32 allows for the higher-order terms, as
 * test_sim.c's rk4_converges_at_order_4): a balance that held by accident
 * would not converge.  The gains are moderate (kp = 200 on pistons of
 * ~0.03 kg: h omega ~ 0.1) so that h = 1 ms is in RK4's asymptotic range.
 */
static double energy_run(rps3_integrator integ, double h, double tol) {
  uint64_t seed = 0x5e1a11ull;
  rps3_model m;
  rps3_traj tr;
  rps3_sim_options o;
  rps3_sim *s;
  rps3_ctrl *c;
  const rps3_sim_report *now;
  rps3_controller free_motion = {zero_force, NULL, 0.0, 0u, NULL}, pd;
  double scale, res;
  int k;
  random_general(&m, &seed, RPS3_LAGRANGE);
  smooth_friction(&m);
  helix_entropy(&tr);
  rps3_sim_options_default(&o);
  o.integrator = integ;
  o.h = h;
  o.epsabs = o.epsrel = 1e-10;
  assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
  assert_int_equal(
      rps3_ctrl_alloc(RPS3_CTRL_PD_GRAVITY, 200.0, 15.0, &m, &tr, &c, NULL),
      RPS3_OK);
  pd = rps3_ctrl_bind(c, 1000.0);
  start_on(s, &m, &tr, 0.0);
  now = rps3_sim_now(s);
  scale = fabs(now->T) + fabs(now->P);
  for (k = 1; k <= 200; k++) {
    if (rps3_sim_advance(s, k <= 100 ? &free_motion : &pd, 1e-3 * k) !=
        RPS3_OK)
      fail_msg("%s, t = %g: %s", rps3_integrator_name(integ), 1e-3 * k,
               rps3_sim_data(s)->err.msg);
    CHECK_REL(now->energy_residual, 0.0, tol, scale, "%s, h %g, t = %g",
              rps3_integrator_name(integ), h, 1e-3 * k);
  }
  print_message("general plant, %s (h %g): energy residual %.3g J, W_F %.4g "
                "J, W_f %.4g J, T + P %.4g J\n",
                rps3_integrator_name(integ), h, now->energy_residual,
                now->y[6], now->y[7], now->T + now->P);
  /* the friction took energy, and the bodies moved */
  assert_true(now->y[7] < 0.0);
  assert_true(fabs(now->T + now->P - now->E0) > 1e-3 * scale);
  res = now->energy_residual;
  rps3_ctrl_free(c);
  rps3_sim_free(s);
  return res;
}

static void simulation_keeps_energy_balance(void **state) {
  double r1, r2;
  (void)state;
  energy_run(RPS3_INT_RKF45, 1e-3, 1e-8);
  r1 = energy_run(RPS3_INT_RK4, 1e-3, 1e-6);
  r2 = energy_run(RPS3_INT_RK4, 5e-4, 1e-6);
  print_message("rk4 residual ratio h / (h/2): %.1f\n", r1 / r2);
  assert_true(fabs(r1 / r2) > 8.0 && fabs(r1 / r2) < 32.0);
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

/* computed torque of model cm on the general plant along tr at 1 kHz (RK4
   at the control rate), the largest |l - l_d| at the ticks */
static double track(const rps3_model *plant, const rps3_model *cm,
                    const rps3_traj *tr) {
  rps3_sim_options o;
  rps3_sim *s;
  rps3_ctrl *c;
  rps3_data *w;
  double e = 0.0;
  int k, n = (int)(rps3_traj_duration(tr) * 1000.0 + 0.5);
  rps3_sim_options_default(&o);
  assert_int_equal(rps3_sim_alloc(plant, &o, &s, NULL), RPS3_OK);
  assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0, cm,
                                   tr, &c, NULL),
                   RPS3_OK);
  assert_int_equal(rps3_data_alloc(plant, &w), RPS3_OK);
  {
    rps3_controller ctl = rps3_ctrl_bind(c, 1000.0);
    start_on(s, plant, tr, 0.0);
    for (k = 1; k <= n; k++) {
      if (rps3_sim_advance(s, &ctl, 1e-3 * k) != RPS3_OK)
        fail_msg("t = %g: %s", 1e-3 * k, rps3_sim_data(s)->err.msg);
      e = fmax(e, length_error(plant, tr, w, rps3_sim_now(s)->y, 1e-3 * k));
    }
  }
  rps3_data_free(w);
  rps3_ctrl_free(c);
  rps3_sim_free(s);
  return e;
}

/*
 * Computed torque on a general plant (random bodies, friction in every
 * joint) along the helix: with the plant's own model it tracks to within
 * the zero-order hold's discretisation (as test_sim.c's Table II plant,
 * < 1e-5 m); with the paper's bodies of the same geometry as its model
 * (the legs' pistons and the platform's offsets left out) the error is
 * orders of magnitude larger.
 */
static void computed_torque_tracks(void **state) {
  uint64_t seed = 0x7ac4ull;
  rps3_model plant, paper;
  rps3_traj tr;
  double e_own, e_paper;
  (void)state;
  random_general(&plant, &seed, RPS3_LAGRANGE);
  smooth_friction(&plant);
  model_entropy(&paper);
  paper.opt.effects = plant.opt.effects;
  assert_int_equal(rps3_model_init(&paper, NULL), RPS3_OK);
  helix_entropy(&tr);
  e_own = track(&plant, &plant, &tr);
  e_paper = track(&plant, &paper, &tr);
  print_message("general plant, helix at 1 kHz: computed torque %.3g m (its "
                "own model), %.3g m (paper bodies)\n",
                e_own, e_paper);
  assert_true(e_own < 1e-5);
  assert_true(e_paper > 100.0 * e_own);
}

#ifndef RPS3_SANITIZE
#include "alloc_count.h" /* not with ASan's allocator */

/* the general path allocates nothing either: rps3_fwddyn, rps3_energy and
   a closed-loop simulation (RK4 and rkf45, a controller with another
   general model, which forms its own Mq and hq at the plant's kept state)
   between the allocations of rps3_sim_alloc and rps3_ctrl_alloc */
static void allocates_nothing(void **state) {
  static const rps3_integrator integ[2] = {RPS3_INT_RK4, RPS3_INT_RKF45};
  uint64_t seed = 0xa110cull;
  rps3_model m, cm;
  rps3_data *inv, *d;
  rps3_traj tr;
  int k, j, ok = 0;
  (void)state;
  random_general(&m, &seed, RPS3_LAGRANGE);
  smooth_friction(&m);
  random_general(&cm, &seed, RPS3_LAGRANGE);
  smooth_friction(&cm);
  assert_int_equal(rps3_data_alloc(&m, &inv), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  helix_entropy(&tr);
  assert_int_equal(
      rps3_traj_eval(&m, &tr, 1.3, inv->pose, inv->dpose, inv->ddpose),
      RPS3_OK);
  assert_int_equal(rps3_inverse(&m, inv), RPS3_OK);
  count_start();
  for (j = 0; j < 100; j++) {
    rps3_data_reset(d);
    memcpy(d->l, inv->l, sizeof(d->l));
    memcpy(d->dl, inv->dl, sizeof(d->dl));
    memcpy(d->F, inv->F, sizeof(d->F));
    memcpy(d->theta, inv->theta, sizeof(d->theta));
    d->have_theta = 1;
    d->dl[j % 3] *= 1.0 + 0.01 * j;
    if (rps3_fwddyn(&m, d) == RPS3_OK &&
        rps3_energy(&m, d, NULL, NULL, NULL) == RPS3_OK)
      ok++;
  }
  count_stop();
  assert_int_equal(ok, 100);
  assert_int_equal(n_alloc, 0);
  assert_int_equal(n_free, 0);
  rps3_data_free(inv);
  rps3_data_free(d);
  for (k = 0; k < 2; k++) {
    rps3_sim_options o;
    rps3_sim *s = NULL;
    rps3_ctrl *c = NULL;
    double pose[3], dpose[3];
    int st = RPS3_OK;
    rps3_sim_options_default(&o);
    o.integrator = integ[k];
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0,
                                     &cm, &tr, &c, NULL),
                     RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, 0.0, pose, dpose, NULL),
                     RPS3_OK);
    count_start();
    {
      rps3_controller ctl = rps3_ctrl_bind(c, 1000.0);
      if (rps3_sim_start(s, 0.0, pose, dpose) != RPS3_OK) st = -100;
      for (j = 1; j <= 100 && st == RPS3_OK; j++)
        st = rps3_sim_advance(s, &ctl, 1e-3 * j);
    }
    count_stop();
    if (st != RPS3_OK) fail_msg("%s", rps3_sim_data(s)->err.msg);
    assert_int_equal(n_alloc, 0);
    assert_int_equal(n_free, 0);
    rps3_ctrl_free(c);
    rps3_sim_free(s);
  }
}
#endif

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(simulation_keeps_energy_balance),
      cmocka_unit_test(computed_torque_tracks),
#ifndef RPS3_SANITIZE
      cmocka_unit_test(allocates_nothing),
#endif
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
