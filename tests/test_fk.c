/* test_fk.c - the theta solve of (8)-(10) (its warm Newton path, the
   multiroot route, the root predictor) and forward kinematics (11)-(20):
   round trips, every solver, warm starts, error codes. */
#include "internal.h"
#include "testutil.h"
#include "theta.h"

static int setup_model(rps3_model *m, rps3_solver s) {
  model_entropy(m);
  m->opt.solver = s;
  return rps3_model_init(m, NULL);
}

/* IK -> lengths -> FK closes on random reachable poses (cold starts) */
static void round_trip(void **state) {
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 91;
  int n, k, tried = 0;
  (void)state;
  assert_int_equal(setup_model(&m, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  m.opt.warm_start = 0;
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 400; n++) {
    double pose[3], c[3], T[4][4], T2[4][4];
    pose[0] = rnd_uniform(&seed, -3.1, 3.1);
    pose[1] = rnd_uniform(&seed, 0.01, 0.45);
    pose[2] = rnd_uniform(&seed, 0.15, 0.45);
    memcpy(d->pose, pose, sizeof pose);
    if (rps3_ik(&m, d) != RPS3_OK) continue;
    tried++;
    memcpy(c, d->c, sizeof c);
    rps3_transform(d, T);
    d->pose[0] = d->pose[1] = d->pose[2] = 0.0; /* FK must find them */
    assert_int_equal(rps3_fk(&m, d), RPS3_OK);
    /* theta is found to ~tol * cond; the pose inherits it */
    CHECK_REL(remainder(d->pose[0] - pose[0], 2 * PI), 0.0, 1e-9, 1.0, "alpha %d", n);
    CHECK_REL(d->pose[1], pose[1], 1e-9, 1.0, "beta %d", n);
    CHECK_REL(d->pose[2], pose[2], 1e-9, 1.0, "z %d", n);
    rps3_transform(d, T2);
    for (k = 0; k < 16; k++)
      CHECK_REL(T2[k / 4][k % 4], T[k / 4][k % 4], 1e-9, 1.0, "T[%d]", k);
    for (k = 0; k < 3; k++) CHECK_REL(d->c[k], c[k], 1e-9, m.R, "c");
    assert_true(d->solve_resid <= m.opt.tol);
    assert_true(d->solve_niter >= 1);
  }
  assert_true(tried > 300);
  rps3_data_free(d);
}

/* every solver converges to the closed-form theta (39) */
static void all_solvers_agree(void **state) {
  int s;
  (void)state;
  for (s = 0; s < RPS3_NSOLVER; s++) {
    rps3_model m;
    rps3_data *d;
    double th[3];
    int k;
    assert_int_equal(setup_model(&m, (rps3_solver)s), RPS3_OK);
    m.opt.warm_start = 0;
    m.opt.tol = 1e-13;
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    d->pose[0] = 0.7385;
    d->pose[1] = 0.2113;
    d->pose[2] = 0.3117;
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    memcpy(th, d->theta, sizeof th);
    if (rps3_theta_solve(&m, d) != RPS3_OK)
      fail_msg("solver %s: %s", rps3_solver_name(s), d->err.msg);
    for (k = 0; k < 3; k++)
      CHECK_REL(d->theta[k], th[k], 1e-11, 1.0, "%s theta%d",
                rps3_solver_name(s), k + 1);
    rps3_data_free(d);
  }
}

/* a pose held still: the warm start is the root, which every solver
   returns at once (0 iterations) with bit for bit the same positions */
static void held_pose_is_its_own_root(void **state) {
  int s;
  (void)state;
  for (s = 0; s < RPS3_NSOLVER; s++) {
    rps3_model m;
    rps3_data *d, first;
    assert_int_equal(setup_model(&m, (rps3_solver)s), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    d->pose[0] = 0.7385;
    d->pose[1] = 0.2113;
    d->pose[2] = 0.3117;
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    if (rps3_theta_solve(&m, d) != RPS3_OK)
      fail_msg("solver %s: %s", rps3_solver_name(s), d->err.msg);
    first = *d;
    assert_int_equal(rps3_theta_solve(&m, d), RPS3_OK);
    assert_int_equal(d->solve_niter, 0);
    assert_true(d->solve_resid == first.solve_resid);
    assert_true(memcmp(d->theta, first.theta, sizeof(d->theta)) == 0);
    assert_true(memcmp(d->b, first.b, sizeof(d->b)) == 0);
    assert_true(memcmp(d->rot, first.rot, sizeof(d->rot)) == 0);
    assert_true(memcmp(d->c, first.c, sizeof(d->c)) == 0);
    assert_true(d->mode == first.mode && d->warn == first.warn);
    rps3_data_free(d);
  }
}

/* a warm start from a nearby sample needs fewer iterations than cold */
static void warm_start_pays(void **state) {
  rps3_model m;
  rps3_data *d;
  int cold, warm;
  double l[3];
  (void)state;
  assert_int_equal(setup_model(&m, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = 1.1;
  d->pose[1] = 0.3;
  d->pose[2] = 0.29;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  d->pose[0] += 1e-3; /* next sample */
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  memcpy(l, d->l, sizeof l);
  d->theta[0] += 2e-3; /* previous solution, a little off */
  d->theta[1] -= 1e-3;
  assert_int_equal(rps3_theta_solve(&m, d), RPS3_OK);
  warm = d->solve_niter;
  d->have_theta = 0;
  memcpy(d->l, l, sizeof l);
  assert_int_equal(rps3_theta_solve(&m, d), RPS3_OK);
  cold = d->solve_niter;
  assert_true(warm < cold);
  rps3_data_free(d);
}

/*
 * rps3_inverse's multiroot route starts from the last root moved along the
 * lengths to second order (src/inverse.c): its start is off by O(h^3) for
 * a pose step h, where the last root itself (O(h)) and a tangent step
 * (O(h^2)) are not.  From an exact root (tol 1e-14), one step to a model
 * that takes any start within 1e-3: the start is the answer (no
 * iteration), and its distance from the closed form (39) falls by 8 when
 * h halves.  A pose held still keeps its root bit for bit (the step is
 * zero), and a jump beyond 0.01 rad is not predicted (the last root is
 * the start, and the tight model iterates).
 */
static void predicted_start_is_third_order(void **state) {
  const double p0[3] = {0.7, 0.25, 0.3}, v[3] = {1.0, 0.3, 0.05},
               a[3] = {2.0, -1.0, 0.1};
  rps3_model tight, loose;
  rps3_data *d, *ref;
  double err[3];
  int n, k;
  (void)state;
  assert_int_equal(setup_model(&tight, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  tight.opt.theta = RPS3_THETA_MULTIROOT;
  tight.opt.effects = RPS3_EFF_PLATFORM_GRAVITY;
  tight.opt.tol = 1e-14;
  loose = tight;
  loose.opt.tol = 1e-3;
  assert_int_equal(rps3_model_init(&tight, NULL), RPS3_OK);
  assert_int_equal(rps3_model_init(&loose, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&tight, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&tight, &ref), RPS3_OK);
  for (n = 0; n < 3; n++) {
    double h = 4e-3 / (double)(1 << n), e = 0.0;
    memcpy(d->pose, p0, sizeof p0);
    d->have_theta = 0;
    if (rps3_inverse(&tight, d) != RPS3_OK) fail_msg("%s", d->err.msg);
    for (k = 0; k < 3; k++) {
      d->pose[k] = p0[k] + v[k] * h + 0.5 * a[k] * h * h;
      ref->pose[k] = d->pose[k];
    }
    if (rps3_inverse(&loose, d) != RPS3_OK) fail_msg("%s", d->err.msg);
    assert_int_equal(d->solve_niter, 0);
    assert_int_equal(rps3_ik(&tight, ref), RPS3_OK);
    for (k = 0; k < 3; k++) e = fmax(e, fabs(d->theta[k] - ref->theta[k]));
    err[n] = e;
  }
  /* the start is good to 1e-8 rad at a 4 ms step of ~1 rad/s, far below
     the tolerance it was accepted at and far above rounding */
  assert_true(err[0] < 1e-6 && err[2] > 1e-13);
  for (n = 1; n < 3; n++) {
    double r = err[n - 1] / err[n];
    if (!(r > 6.0 && r < 10.0))
      fail_msg("start error %.3g -> %.3g as h halves: ratio %.3g, not ~8",
               err[n - 1], err[n], r);
  }

  /* held: the start is the last root, bit for bit */
  {
    double th[3];
    memcpy(th, d->theta, sizeof th);
    assert_int_equal(rps3_inverse(&loose, d), RPS3_OK);
    assert_int_equal(d->solve_niter, 0);
    assert_true(memcmp(th, d->theta, sizeof th) == 0);
  }
  /* a jump of 0.05 rad in alpha: no prediction, the tight solve
     iterates from the last root and lands on the closed form */
  for (k = 0; k < 3; k++) ref->pose[k] = d->pose[k];
  d->pose[0] += 0.05;
  ref->pose[0] = d->pose[0];
  assert_int_equal(rps3_inverse(&tight, d), RPS3_OK);
  assert_true(d->solve_niter >= 2);
  assert_int_equal(rps3_ik(&tight, ref), RPS3_OK);
  for (k = 0; k < 3; k++)
    CHECK_REL(d->theta[k], ref->theta[k], 1e-12, 1.0, "theta%d", k);
  rps3_data_free(d);
  rps3_data_free(ref);
}

static void error_codes(void **state) {
  rps3_model m;
  rps3_data *d;
  double th[3];
  int k;
  (void)state;
  assert_int_equal(setup_model(&m, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  m.opt.max_iter = 1;
  m.opt.warm_start = 1;
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = -2.2;
  d->pose[1] = 0.4;
  d->pose[2] = 0.27;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  memcpy(th, d->theta, sizeof th);

  /* one iteration from the cold guess is not enough */
  d->have_theta = 0;
  assert_int_equal(rps3_theta_solve(&m, d), RPS3_ENOCONV);
  assert_non_null(strstr(d->err.msg, "iterations"));
  assert_int_equal(d->solve_niter, 1);

  /* the mirror image below the base satisfies (8)-(10) exactly: the solver
     stops there at once and the branch check must refuse it */
  for (k = 0; k < 3; k++) d->theta[k] = -th[k];
  d->have_theta = 1;
  assert_int_equal(rps3_theta_solve(&m, d), RPS3_EBRANCH);
  assert_non_null(strstr(d->err.msg, "outside (0, pi)"));
  assert_int_equal(d->stage, 0);

  /* bad lengths */
  d->l[1] = -0.3;
  assert_int_equal(rps3_theta_solve(&m, d), RPS3_EINVAL);
  d->l[1] = (double)NAN;
  assert_int_equal(rps3_theta_guess(&m, d), RPS3_EINVAL);
  /* a workspace serves only the solver it was built for */
  {
    rps3_model other = m;
    other.opt.solver = RPS3_SOLVER_NEWTON;
    assert_int_equal(rps3_model_init(&other, NULL), RPS3_OK);
    d->l[1] = 0.3;
    assert_int_equal(rps3_theta_solve(&other, d), RPS3_EINVAL);
    assert_non_null(strstr(d->err.msg, "allocated for solver hybridsj"));
  }
  d->l[1] = 1e200; /* finite, but (8)-(10) overflow */
  d->have_theta = 0;
  assert_int_equal(rps3_theta_solve(&m, d), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "do not evaluate"));
  rps3_data_free(d);
}

/* the ball joints after a solve are (12)-(14) of the theta it returns,
   bitwise: the solve reuses the cos and sin of its last evaluation when
   that was at the root, and computes them when it was not (a rejected
   last trial step, or a root folded by whole turns into (0, pi)) */
static void positions_of_the_root(void **state) {
  int s;
  (void)state;
  for (s = 0; s < RPS3_NSOLVER; s++) {
    rps3_model m;
    rps3_data *d;
    int n, i, k;
    assert_int_equal(setup_model(&m, (rps3_solver)s), RPS3_OK);
    m.opt.warm_start = 1;
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    for (n = 0; n < 60; n++) {
      d->pose[0] = 0.3 + 0.01 * n;
      d->pose[1] = 0.2 + 0.002 * n;
      d->pose[2] = 0.3;
      assert_int_equal(rps3_ik(&m, d), RPS3_OK);
      /* every tenth start a whole turn away: the root is folded back */
      if (n % 10 == 5)
        for (i = 0; i < 3; i++) d->theta[i] += 2.0 * PI;
      d->have_theta = (n > 0);
      if (rps3_theta_solve(&m, d) != RPS3_OK)
        fail_msg("solver %s, point %d: %s", rps3_solver_name(s), n,
                 d->err.msg);
      for (i = 0; i < 3; i++) {
        double c = cos(d->theta[i]), sn = sin(d->theta[i]), phi[3];
        assert_true(d->theta[i] > 0.0 && d->theta[i] < PI);
        phi[0] = -c * m.radial[i][0];
        phi[1] = -c * m.radial[i][1];
        phi[2] = sn;
        for (k = 0; k < 3; k++) {
          assert_true(d->phi[i][k] == phi[k]);
          if (d->b[i][k] != m.pin[i][k] + d->l[i] * phi[k])
            fail_msg("solver %s, point %d: b%d[%d] %.17g, (12)-(14) of "
                     "theta %.17g", rps3_solver_name(s), n, i + 1, k,
                     d->b[i][k], m.pin[i][k] + d->l[i] * phi[k]);
        }
      }
    }
    rps3_data_free(d);
  }
}

/* the closure of model m at lengths l in metres (R = m.R) or in units of
   R (R = 1), theta th */
static rps3_closure closure_at(const rps3_model *m, const double l[3],
                               const double th[3], int metres) {
  rps3_closure q;
  int i;
  q.R = metres ? m->R : 1.0;
  q.r3 = metres ? 3.0 * m->r * m->r : 3.0 * m->rho * m->rho;
  for (i = 0; i < 3; i++) {
    q.l[i] = metres ? l[i] : l[i] / m->R;
    q.th[i] = th[i];
  }
  return q;
}

/*
 * The warm Newton path of the theta solve (rps3_theta_newton, the one the
 * multiroot route and the forward dynamics share) converges
 * quadratically: from 2e-3 rad off the closed form (39), three steps at
 * most (2e-3 -> ~4e-6 -> ~2e-11 -> rounding), to the closed form, in
 * metres and in units of R alike.  A start 0.3 rad off is no warm start
 * (the first correction passes RPS3_THETA_WARM_MAX): the path gives up,
 * and rps3_theta_solve takes the multiroot route from there to the same
 * root.
 */
static void warm_newton_path(void **state) {
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 517;
  int n, tried = 0, i;
  (void)state;
  assert_int_equal(setup_model(&m, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 200; n++) {
    double th[3], start[3];
    int u;
    d->pose[0] = rnd_uniform(&seed, -3.1, 3.1);
    d->pose[1] = rnd_uniform(&seed, 0.01, 0.45);
    d->pose[2] = rnd_uniform(&seed, 0.15, 0.45);
    if (rps3_inverse(&m, d) != RPS3_OK || !(d->cond < 1e3)) continue;
    tried++;
    memcpy(th, d->theta, sizeof th);
    for (i = 0; i < 3; i++) start[i] = th[i] + rnd_uniform(&seed, -2e-3, 2e-3);
    for (u = 0; u < 2; u++) {
      rps3_closure q = closure_at(&m, d->l, start, u);
      int niter = -1, exact = -1;
      double resid = -1.0;
      if (rps3_theta_newton(&m, &q, 0, d->mode, &niter, &resid, &exact) != 0)
        fail_msg("pose %d (%s): the warm Newton path did not converge", n,
                 u ? "metres" : "units of R");
      assert_true(niter >= 1 && niter <= 3);
      assert_true(resid <= m.opt.tol);
      assert_int_equal(exact, 0); /* series-stepped trig */
      for (i = 0; i < 3; i++) {
        CHECK_REL(q.th[i], th[i], TOL_EXACT, 1.0, "pose %d theta%d", n, i);
        CHECK_REL(q.c[i], cos(q.th[i]), TOL_EXACT, 1.0, "cos theta%d", i);
        CHECK_REL(q.s[i], sin(q.th[i]), TOL_EXACT, 1.0, "sin theta%d", i);
      }
    }
  }
  assert_true(tried > 100);

  /* far: Newton gives up, the multiroot route finds the root */
  d->pose[0] = 0.7385;
  d->pose[1] = 0.2113;
  d->pose[2] = 0.3117;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  {
    double th[3], start[3];
    rps3_closure q;
    int niter, exact;
    double resid;
    memcpy(th, d->theta, sizeof th);
    for (i = 0; i < 3; i++) start[i] = th[i] + (i == 1 ? -0.3 : 0.3);
    q = closure_at(&m, d->l, start, 1);
    assert_int_equal(rps3_theta_newton(&m, &q, 0, RPS3_MODE_ANY, &niter,
                                       &resid, &exact),
                     -1);
    memcpy(d->theta, start, sizeof start);
    d->have_theta = 1;
    if (rps3_theta_solve(&m, d) != RPS3_OK) fail_msg("%s", d->err.msg);
    assert_true(d->solve_niter >= 2);
    for (i = 0; i < 3; i++)
      CHECK_REL(d->theta[i], th[i], 1e-10, 1.0, "multiroot theta%d", i);
  }
  rps3_data_free(d);
}

/*
 * Near the singular surface the other assembly mode's root lies within a
 * warm step: on sine_edge (rps3-study's trajectory that passes within a
 * condition number of 4e2 of the surface) the two roots at t = 0.997 s
 * are 8e-3 rad apart.  The warm Newton path keeps the start's mode: from
 * the other mode's root itself it refuses for the start's mode and takes
 * it for RPS3_MODE_ANY; and every warm-started multiroot solve along the
 * trajectory's near-singular stretch is the pose's own root (EMODE, the
 * check against the closed form (39), would say otherwise).
 */
static void warm_newton_keeps_the_mode(void **state) {
  const rps3_sine edge = {
      {0.0, 0.6, 0.28}, {RPS3_PI, 0.2, 0.03}, {1.0, 2.3, 1.7}, {0, 0, 0}, 2.0};
  rps3_model m;
  rps3_data *d;
  rps3_traj tr;
  double th[3], other[3];
  int k, i, niter, exact, mode;
  double resid;
  (void)state;
  rps3_model_default(&m);
  m.opt.theta = RPS3_THETA_MULTIROOT;
  m.opt.tol = 1e-14;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  memset(&tr, 0, sizeof tr);
  tr.kind = RPS3_TRAJ_SINE;
  tr.sine = edge;
  /* the pose's root and the other mode's, at t = 0.997 s */
  assert_int_equal(rps3_traj_eval(&m, &tr, 0.997, d->pose, NULL, NULL),
                   RPS3_OK);
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  memcpy(th, d->theta, sizeof th);
  mode = d->mode;
  assert_int_equal(mode, RPS3_MODE_LEVEL);
  d->theta[0] = 0.7930;
  d->theta[1] = 1.1923;
  d->theta[2] = 1.2036;
  d->have_theta = 1;
  if (rps3_theta_solve(&m, d) != RPS3_OK) fail_msg("%s", d->err.msg);
  assert_int_equal(d->mode, RPS3_MODE_OTHER);
  memcpy(other, d->theta, sizeof other);
  assert_true(fabs(other[0] - th[0]) > 1e-3);
  {
    rps3_closure q = closure_at(&m, d->l, other, 1);
    assert_int_equal(
        rps3_theta_newton(&m, &q, 0, mode, &niter, &resid, &exact), -1);
    q = closure_at(&m, d->l, other, 1);
    assert_int_equal(rps3_theta_newton(&m, &q, 0, RPS3_MODE_ANY, &niter,
                                       &resid, &exact),
                     0);
    for (i = 0; i < 3; i++) CHECK_REL(q.th[i], other[i], 1e-12, 1.0, "theta%d", i);
  }
  /* warm along the stretch: every root the pose's own */
  rps3_data_reset(d);
  for (k = 480; k < 520; k++) {
    double t = 2.0 * (k + 0.5) / 1000.0;
    assert_int_equal(rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose),
                     RPS3_OK);
    if (rps3_inverse(&m, d) != RPS3_OK)
      fail_msg("t = %g s: %s", t, d->err.msg);
  }
  rps3_data_free(d);
}

/*
 * The root predictor (rps3_theta_predict in the links' planes, fed by
 * rps3_root_predict with the chord's own second derivative) against the
 * formula it replaced, written from the positions: theta' = -(df/dtheta)^-1
 * (df/dl) dl from the constraint Jacobian of the ball joints
 * (rps3_constraint_jacobian), theta'' from the velocity products of
 * |b_i - b_j|^2 (rps3_constraint_acc_rhs), start theta + theta' +
 * theta''/2.  The two agree to rounding; the second-order term alone is
 * ~1e-6 rad here, so a wrong coefficient shows.
 */
static void predictor_positions_oracle(void **state) {
  const double p0[3] = {0.7, 0.25, 0.3}, v[3] = {1.0, 0.3, 0.05};
  rps3_model m;
  rps3_data *d, *e;
  int n, i, k;
  (void)state;
  assert_int_equal(setup_model(&m, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  m.opt.theta = RPS3_THETA_MULTIROOT;
  m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &e), RPS3_OK);
  for (n = 0; n < 4; n++) {
    const double h = 4e-3 / (double)(1 << n);
    double Jl[3][3], Jt[3][3], Ji[3][3], D[3][3], dl[3], u[3], x[3],
        kn[3][3], want[3], det, second = 0.0;
    memcpy(d->pose, p0, sizeof p0);
    d->have_theta = 0;
    if (rps3_inverse(&m, d) != RPS3_OK) fail_msg("%s", d->err.msg);
    /* the oracle at the root d holds */
    rps3_constraint_jacobian(d, Jl, Jt);
    det = Jt[0][0] * (Jt[1][1] * Jt[2][2] - Jt[1][2] * Jt[2][1]) -
          Jt[0][1] * (Jt[1][0] * Jt[2][2] - Jt[1][2] * Jt[2][0]) +
          Jt[0][2] * (Jt[1][0] * Jt[2][1] - Jt[1][1] * Jt[2][0]);
    for (i = 0; i < 3; i++)
      for (k = 0; k < 3; k++) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, k1 = (k + 1) % 3,
                  k2 = (k + 2) % 3;
        Ji[k][i] = (Jt[i1][k1] * Jt[i2][k2] - Jt[i1][k2] * Jt[i2][k1]) / det;
      }
    for (i = 0; i < 3; i++)
      for (k = 0; k < 3; k++) D[i][k] = d->b[i][k] - d->b[(i + 1) % 3][k];
    for (k = 0; k < 3; k++) e->pose[k] = p0[k] + v[k] * h;
    assert_int_equal(rps3_ik(&m, e), RPS3_OK);
    for (i = 0; i < 3; i++) dl[i] = e->l[i] - d->l[i];
    for (i = 0; i < 3; i++) {
      x[i] = 0.0;
      for (k = 0; k < 3; k++) x[i] += Jl[i][k] * dl[k];
    }
    for (i = 0; i < 3; i++)
      u[i] = -(Ji[i][0] * x[0] + Ji[i][1] * x[1] + Ji[i][2] * x[2]);
    rps3_constraint_acc_rhs(M3C(D), M3C(d->phi), M3C(d->dphi), d->l, dl, u,
                            NULL, kn, x);
    for (i = 0; i < 3; i++) {
      const double dd = Ji[i][0] * x[0] + Ji[i][1] * x[1] + Ji[i][2] * x[2];
      want[i] = d->theta[i] + u[i] + 0.5 * dd;
      second = fmax(second, fabs(0.5 * dd));
    }
    /* the library's, from the root it kept */
    memcpy(d->l, e->l, sizeof(d->l));
    rps3_root_predict(d, 1e-2);
    for (i = 0; i < 3; i++)
      CHECK_REL(d->theta[i], want[i], TOL_EXACT, 1.0, "h %g theta%d", h, i);
    if (n == 0) assert_true(second > 1e-7);
  }
  rps3_data_free(d);
  rps3_data_free(e);
}

/* beta = 0: alpha is a free gauge; FK says so and stays finite */
static void level_platform(void **state) {
  rps3_model m;
  rps3_data *d;
  (void)state;
  assert_int_equal(setup_model(&m, RPS3_SOLVER_HYBRIDSJ), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = 0.9;
  d->pose[1] = 0.0;
  d->pose[2] = 0.3;
  assert_int_equal(rps3_ik(&m, d), RPS3_OK);
  assert_int_equal(rps3_fk(&m, d), RPS3_OK);
  assert_true(d->warn & RPS3_WARN_ALPHA);
  assert_true(d->pose[0] == 0.0);
  assert_true(d->pose[1] >= 0.0 && d->pose[1] < 1e-7);
  CHECK_REL(d->pose[2], 0.3, 1e-12, 1.0, "z");
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip),
      cmocka_unit_test(all_solvers_agree),
      cmocka_unit_test(warm_start_pays),
      cmocka_unit_test(held_pose_is_its_own_root),
      cmocka_unit_test(predicted_start_is_third_order),
      cmocka_unit_test(warm_newton_path),
      cmocka_unit_test(warm_newton_keeps_the_mode),
      cmocka_unit_test(predictor_positions_oracle),
      cmocka_unit_test(error_codes),
      cmocka_unit_test(level_platform),
      cmocka_unit_test(positions_of_the_root),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
