/*
 * test_control.c - the shipped controllers' desired motion is the
 * trajectory's, whatever the effects of the controller's own model: a
 * model that selects no dynamic effect (gravity alone) computes no rates
 * for its forces, and the controller must still track the desired link
 * rates.  The oracle is the trajectory's link rates by rps3_ik and
 * rps3_velocity of a separate model; with kp = 0, kd = 1 and a measured
 * rate of zero, PD's force is the desired rate itself.
 */
#include "testutil.h"

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
      cm.opt.forces_only = fo; /* the runner's controllers: forces_only */
      cm.opt.certify = 0;     /* no rates for a static model then */
      assert_int_equal(rps3_model_init(&cm, NULL, 0), RPS3_OK);
      rps3_model_default(&om);
      assert_int_equal(rps3_model_init(&om, NULL, 0), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&om, &od), RPS3_OK);
      assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_PD, 0.0, 1.0, &cm, &tr, &c,
                                       NULL, 0),
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
                    "effects %#x forces_only %d t %g: F%d = kd dl_des", effects[e],
                    fo, t, i);
      }
      rps3_ctrl_free(c);
      rps3_data_free(od);
    }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(pd_tracks_the_desired_rates),
  };
  gsl_set_error_handler_off();
  return cmocka_run_group_tests(tests, NULL, NULL);
}
