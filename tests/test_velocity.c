/* test_velocity.c - velocities and accelerations (25)-(33): the pose-rate
   route against central differences of positions, the link-rate route
   against the pose-rate route, and the paper's (31)-(33) against both. */
#include "testutil.h"

#include "internal.h" /* rps3_link_motion */

typedef struct {
  double l[3], theta[3], c[3], rot[3][3];
} positions;

static void positions_at(const rps3_model *m, rps3_data *d,
                         const rps3_traj *tr, double t, positions *p) {
  assert_int_equal(rps3_traj_eval(m, tr, t, d->pose, d->dpose, d->ddpose),
                   RPS3_OK);
  assert_int_equal(rps3_ik(m, d), RPS3_OK);
  memcpy(p->l, d->l, sizeof p->l);
  memcpy(p->theta, d->theta, sizeof p->theta);
  memcpy(p->c, d->c, sizeof p->c);
  memcpy(p->rot, d->rot, sizeof p->rot);
}

typedef struct {
  double dl[3], dtheta[3], vc[3], omega[3];
} rates;

static void rates_at(const rps3_model *m, rps3_data *d, const rps3_traj *tr,
                     double t, rates *r) {
  assert_int_equal(rps3_traj_eval(m, tr, t, d->pose, d->dpose, d->ddpose),
                   RPS3_OK);
  assert_int_equal(rps3_ik(m, d), RPS3_OK);
  assert_int_equal(rps3_velocity(m, d), RPS3_OK);
  memcpy(r->dl, d->dl, sizeof r->dl);
  memcpy(r->dtheta, d->dtheta, sizeof r->dtheta);
  memcpy(r->vc, d->vc, sizeof r->vc);
  memcpy(r->omega, d->omega, sizeof r->omega);
}

static double norm3(const double v[3]) {
  return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* pose-rate route = d/dt of positions, by central differences */
static void velocity_is_derivative(void **state) {
  rps3_model m;
  rps3_data *d;
  rps3_traj tr;
  uint64_t seed = 4471;
  const double h = 1e-5;
  int n, k, i;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 6; n++) {
    traj_random(&tr, &seed);
    for (k = 1; k < 10; k++) {
      double t = 0.2 * k, w[3], sl, st, sv, sw;
      positions p0, p1;
      rates r, r0, r1;
      positions_at(&m, d, &tr, t - h, &p0);
      positions_at(&m, d, &tr, t + h, &p1);
      rates_at(&m, d, &tr, t, &r);
      /* omega from rot' rot^T (skew part) */
      {
        double W[3][3];
        int a, b, c;
        for (a = 0; a < 3; a++)
          for (b = 0; b < 3; b++) {
            double s = 0;
            for (c = 0; c < 3; c++)
              s += (p1.rot[a][c] - p0.rot[a][c]) / (2 * h) * 0.5 *
                   (p1.rot[b][c] + p0.rot[b][c]);
            W[a][b] = s;
          }
        w[0] = 0.5 * (W[2][1] - W[1][2]);
        w[1] = 0.5 * (W[0][2] - W[2][0]);
        w[2] = 0.5 * (W[1][0] - W[0][1]);
      }
      sl = norm3(r.dl);
      st = norm3(r.dtheta);
      sv = norm3(r.vc);
      sw = norm3(r.omega);
      for (i = 0; i < 3; i++) {
        CHECK_REL(r.dl[i], (p1.l[i] - p0.l[i]) / (2 * h), TOL_FD, sl, "dl%d", i);
        CHECK_REL(r.dtheta[i], (p1.theta[i] - p0.theta[i]) / (2 * h), TOL_FD, st,
                  "dtheta%d", i);
        CHECK_REL(r.vc[i], (p1.c[i] - p0.c[i]) / (2 * h), TOL_FD, sv, "vc%d", i);
        CHECK_REL(r.omega[i], w[i], TOL_FD, sw, "omega%d", i);
      }
      /* accelerations = d/dt of the rates */
      rates_at(&m, d, &tr, t - h, &r0);
      rates_at(&m, d, &tr, t + h, &r1);
      assert_int_equal(rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose), 0);
      assert_int_equal(rps3_ik(&m, d), RPS3_OK);
      assert_int_equal(rps3_velocity(&m, d), RPS3_OK);
      assert_int_equal(rps3_acceleration(&m, d), RPS3_OK);
      sl = norm3(d->ddl);
      st = norm3(d->ddtheta);
      sv = norm3(d->ac);
      sw = norm3(d->domega);
      for (i = 0; i < 3; i++) {
        CHECK_REL(d->ddl[i], (r1.dl[i] - r0.dl[i]) / (2 * h), TOL_FD, sl, "ddl%d", i);
        CHECK_REL(d->ddtheta[i], (r1.dtheta[i] - r0.dtheta[i]) / (2 * h), TOL_FD,
                  st, "ddtheta%d", i);
        CHECK_REL(d->ac[i], (r1.vc[i] - r0.vc[i]) / (2 * h), TOL_FD, sv, "ac%d", i);
        CHECK_REL(d->domega[i], (r1.omega[i] - r0.omega[i]) / (2 * h), TOL_FD, sw,
                  "domega%d", i);
      }
    }
  }
  rps3_data_free(d);
}

/* link-rate route (constraint Jacobian) = pose-rate route, and (31)-(33) */
static void joint_route_agrees(void **state) {
  rps3_model m;
  rps3_data *a, *b;
  rps3_traj tr;
  uint64_t seed = 1213;
  int n, k, i;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &a), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &b), RPS3_OK);
  for (n = 0; n < 10; n++) {
    traj_random(&tr, &seed);
    for (k = 0; k <= 20; k++) {
      double t = 0.1 * k, wb[3], wbody[3], s;
      assert_int_equal(rps3_traj_eval(&m, &tr, t, a->pose, a->dpose, a->ddpose), 0);
      assert_int_equal(rps3_ik(&m, a), RPS3_OK);
      assert_int_equal(rps3_velocity(&m, a), RPS3_OK);
      assert_int_equal(rps3_acceleration(&m, a), RPS3_OK);
      /* b sees only the link lengths and their rates, as a controller does */
      memcpy(b->pose, a->pose, sizeof a->pose);
      assert_int_equal(rps3_ik(&m, b), RPS3_OK);
      memcpy(b->dl, a->dl, sizeof a->dl);
      memcpy(b->ddl, a->ddl, sizeof a->ddl);
      assert_int_equal(rps3_joint_velocity(&m, b), RPS3_OK);
      assert_int_equal(rps3_joint_acceleration(&m, b), RPS3_OK);
      s = norm3(a->dtheta) + norm3(a->omega);
      for (i = 0; i < 3; i++) {
        CHECK_REL(b->dtheta[i], a->dtheta[i], TOL_EXACT, s, "dtheta");
        CHECK_REL(b->vc[i], a->vc[i], TOL_EXACT, norm3(a->vc), "vc");
        CHECK_REL(b->omega[i], a->omega[i], TOL_EXACT, s, "omega");
        CHECK_REL(b->dpose[i], a->dpose[i], TOL_EXACT, norm3(a->dpose) / a->pose[1],
                  "dpose%d", i);
        CHECK_REL(b->ddtheta[i], a->ddtheta[i], TOL_EXACT, norm3(a->ddtheta), "ddtheta");
        CHECK_REL(b->ac[i], a->ac[i], TOL_EXACT, norm3(a->ac), "ac");
        CHECK_REL(b->domega[i], a->domega[i], TOL_EXACT, norm3(a->domega), "domega");
      }
      /* (31)-(33) give the body components of omega */
      rps3_omega_paper(&m, a, wb);
      for (i = 0; i < 3; i++)
        wbody[i] = a->rot[0][i] * a->omega[0] + a->rot[1][i] * a->omega[1] +
                   a->rot[2][i] * a->omega[2];
      for (i = 0; i < 3; i++)
        CHECK_REL(wb[i], wbody[i], TOL_EXACT, norm3(wbody), "(31)-(33) omega_%d", i);
    }
  }
  rps3_data_free(a);
  rps3_data_free(b);
}

static void stage_and_input_errors(void **state) {
  rps3_model m;
  rps3_data *d;
  double bs;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_velocity(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_joint_velocity(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_acceleration(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_joint_acceleration(&m, d), RPS3_ESTATE);
  d->pose[0] = 0.3;
  d->pose[1] = 0.2;
  d->pose[2] = 0.3;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  assert_int_equal(rps3_acceleration(&m, d), RPS3_ESTATE);
  d->dpose[1] = (double)INFINITY;
  assert_int_equal(rps3_velocity(&m, d), RPS3_EINVAL);
  d->dl[2] = (double)NAN;
  assert_int_equal(rps3_joint_velocity(&m, d), RPS3_EINVAL);
  d->dpose[1] = 0.1;
  assert_int_equal(rps3_velocity(&m, d), RPS3_OK);
  d->ddpose[0] = (double)NAN;
  assert_int_equal(rps3_acceleration(&m, d), RPS3_EINVAL);
  d->dl[2] = 0.01;
  assert_int_equal(rps3_joint_velocity(&m, d), RPS3_OK);
  d->ddl[0] = (double)NAN;
  assert_int_equal(rps3_joint_acceleration(&m, d), RPS3_EINVAL);
  /* link 1 in the platform plane: theta-dot is not determined by l-dot */
  bs = singular_beta(&m, d, 0.25, 0.6, 1.0);
  assert_true(isfinite(bs));
  d->dl[0] = d->dl[1] = d->dl[2] = 0.01;
  assert_int_equal(rps3_joint_velocity(&m, d), RPS3_ESING);
  assert_non_null(strstr(d->err.msg, "condition number"));
  rps3_data_free(d);
}

/*
 * rps3_link_motion, the controllers' desired motion: l, l', l'' from the
 * derivatives of l^2 = |b - P|^2, against the stages' route (the link
 * directions and theta: l' = phi . b', l'' = phi . b'' + l theta'^2) on
 * random motions, to 1e-12 of the scale (both exact; rounding ~1e-15,
 * amplified by the 1/l of the accelerations), and its refusals.
 */
static void link_motion_is_the_stages(void **state) {
  rps3_model m;
  rps3_data *a, *b;
  uint64_t seed = 0x11e7;
  int n, i;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &a), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &b), RPS3_OK);
  for (n = 0; n < 500; n++) {
    rps3_traj tr;
    double t, sv = 0.0, sa = 0.0;
    traj_random(&tr, &seed);
    t = rnd_uniform(&seed, 0.0, tr.sine.duration);
    assert_int_equal(rps3_traj_eval(&m, &tr, t, a->pose, a->dpose, a->ddpose),
                     RPS3_OK);
    memcpy(b->pose, a->pose, sizeof(a->pose));
    memcpy(b->dpose, a->dpose, sizeof(a->dpose));
    memcpy(b->ddpose, a->ddpose, sizeof(a->ddpose));
    assert_int_equal(rps3_ik(&m, a), RPS3_OK);
    assert_int_equal(rps3_velocity(&m, a), RPS3_OK);
    assert_int_equal(rps3_acceleration(&m, a), RPS3_OK);
    assert_int_equal(rps3_link_motion(&m, b, n % 5 != 0), RPS3_OK);
    for (i = 0; i < 3; i++) {
      sv = fmax(sv, fabs(a->dl[i]));
      sa = fmax(sa, fabs(a->ddl[i]));
    }
    for (i = 0; i < 3; i++) {
      CHECK_REL(b->l[i], a->l[i], 1e-14, 1.0, "n %d l%d", n, i);
      CHECK_REL(b->dl[i], a->dl[i], 1e-12, sv + 1e-3, "n %d dl%d", n, i);
      if (n % 5 != 0)
        CHECK_REL(b->ddl[i], a->ddl[i], 1e-12, sa + sv * sv + 1e-3,
                  "n %d ddl%d", n, i);
    }
    assert_int_equal(b->stage, 0); /* no theta, no directions */
  }
  /* out of reach: the platform below the base; not finite */
  b->pose[0] = 0.1;
  b->pose[1] = 0.2;
  b->pose[2] = -0.3;
  assert_int_equal(rps3_link_motion(&m, b, 1), RPS3_EREACH);
  assert_non_null(strstr(b->err.msg, "height"));
  b->pose[2] = 0.3;
  b->ddpose[1] = (double)NAN;
  assert_int_equal(rps3_link_motion(&m, b, 1), RPS3_EINVAL);
  assert_int_equal(rps3_link_motion(&m, b, 0), RPS3_OK);
  b->dpose[0] = HUGE_VAL;
  assert_int_equal(rps3_link_motion(&m, b, 0), RPS3_EINVAL);
  rps3_data_free(a);
  rps3_data_free(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(velocity_is_derivative),
      cmocka_unit_test(joint_route_agrees),
      cmocka_unit_test(stage_and_input_errors),
      cmocka_unit_test(link_motion_is_the_stages),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
