/*
 * test_alloc_trajectory.c - after init, the library never allocates: a
 * malloc interposer counts every malloc, calloc, realloc, posix_memalign
 * and free of the process (GSL's included, since the executable's
 * definitions take precedence over glibc's for every shared object) while
 * 10^5-point trajectories run through rps3_inverse.
 *
 * Not in the sanitizer build: ASan brings its own allocator, which must not
 * be interposed; there the test is reported as skipped.
 */
#include "testutil.h"

#include <gsl/gsl_vector.h>

#ifdef RPS3_SANITIZE

static void skipped_under_sanitizers(void **state) {
  (void)state;
  print_message("the malloc interposer is not built with ASan (its own "
                "allocator); run build/tests/test_alloc_trajectory\n");
  skip();
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(skipped_under_sanitizers),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}

#else /* !RPS3_SANITIZE */

/* ------------------------------------------------------------ interposer */

#include "alloc_count.h"

/* ----------------------------------------------------------------- tests */

#define NPOINTS 100000

/* the counter sees the library's and GSL's allocations: without this the
   zero counts below would prove nothing */
static void interposer_sees_gsl_and_init(void **state) {
  rps3_model m;
  rps3_data *d = NULL;
  gsl_vector *v;
  (void)state;
  model_entropy(&m);
  m.opt.theta = RPS3_THETA_MULTIROOT;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);

  count_start();
  v = gsl_vector_alloc(7); /* inside libgsl.so */
  gsl_vector_free(v);
  count_stop();
  assert_true(n_alloc >= 1);
  assert_true(n_free >= 1);

  count_start();
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  count_stop();
  assert_true(n_alloc >= 2); /* the data, GSL's solver and vectors */
  count_start();
  rps3_data_free(d);
  count_stop();
  assert_true(n_free >= 2);
}

/* 10^5 points of the paper's helix through rps3_inverse, with route theta
   and method, all effects (effects 0) or the given ones; zero allocations
   and frees after init */
static void run_trajectory(rps3_theta_route theta, rps3_method method,
                           int warm, int effects, int outputs) {
  rps3_model m;
  rps3_data *d = NULL;
  rps3_traj tr;
  double T, fsum = 0.0;
  long p, failures = 0, niter = 0;
  model_entropy(&m);
  m.opt.theta = theta;
  m.opt.method = method;
  m.opt.warm_start = warm;
  m.opt.solver = RPS3_SOLVER_HYBRIDSJ;
  if (effects) m.opt.effects = effects;
  m.opt.outputs = outputs;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  /* the helix of Table II scaled to this model's platform (r* < r/2) */
  tr.helix.radius = 0.0031;
  tr.helix.z0 = 0.2713;
  assert_int_equal(rps3_traj_check(&m, &tr, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  T = rps3_traj_duration(&tr);

  count_start();
  for (p = 0; p < NPOINTS; p++) {
    double t = T * (double)p / (double)(NPOINTS - 1);
    if (rps3_traj_eval(&m, &tr, t, d->pose, d->dpose, d->ddpose) != RPS3_OK ||
        rps3_inverse(&m, d) != RPS3_OK)
      failures++;
    fsum += d->F[0] + d->F[1] + d->F[2];
    niter += d->solve_niter;
  }
  count_stop();

  print_message("%s, %s, %s: %d points, %ld failures, %ld theta-solve "
                "iterations, %ld allocations, %ld frees\n",
                theta == RPS3_THETA_MULTIROOT ? "multiroot hybridsj"
                                              : "closed form",
                warm ? "warm" : "cold",
                method == RPS3_LAGRANGE ? "Lagrange" : "Newton-Euler", NPOINTS,
                failures, niter, n_alloc, n_free);
  assert_int_equal(failures, 0);
  assert_true(isfinite(fsum));
  if (theta == RPS3_THETA_MULTIROOT) assert_true(niter > 0);
  assert_int_equal(n_alloc, 0);
  assert_int_equal(n_free, 0);
  rps3_data_free(d);
}

static void closed_form_lagrange(void **state) {
  (void)state;
  run_trajectory(RPS3_THETA_CLOSED_FORM, RPS3_LAGRANGE, 1, 0, RPS3_OUT_ALL);
}

/* the paper's effects: rps3_inverse runs the one-point kernel, with every
   output, on the controller's path and in the lean pass */
static void closed_form_kernel(void **state) {
  (void)state;
  run_trajectory(RPS3_THETA_CLOSED_FORM, RPS3_LAGRANGE, 1, RPS3_EFF_DEFAULT,
                 RPS3_OUT_ALL);
  run_trajectory(RPS3_THETA_CLOSED_FORM, RPS3_LAGRANGE, 1, RPS3_EFF_DEFAULT,
                 RPS3_OUT_FORCES | RPS3_OUT_TRANSMISSION);
  run_trajectory(RPS3_THETA_CLOSED_FORM, RPS3_LAGRANGE, 1, RPS3_EFF_DEFAULT,
                 RPS3_OUT_FORCES);
}

static void closed_form_newton_euler(void **state) {
  (void)state;
  run_trajectory(RPS3_THETA_CLOSED_FORM, RPS3_NEWTON_EULER, 1, 0, RPS3_OUT_ALL);
}

static void warm_multiroot_lagrange(void **state) {
  (void)state;
  run_trajectory(RPS3_THETA_MULTIROOT, RPS3_LAGRANGE, 1, 0, RPS3_OUT_ALL);
}

static void warm_multiroot_newton_euler(void **state) {
  (void)state;
  run_trajectory(RPS3_THETA_MULTIROOT, RPS3_NEWTON_EULER, 1, 0, RPS3_OUT_ALL);
}

static void cold_multiroot_lagrange(void **state) {
  (void)state;
  run_trajectory(RPS3_THETA_MULTIROOT, RPS3_LAGRANGE, 0, 0, RPS3_OUT_ALL);
}

/* a table of the pose and a path of shape table: the spline's slopes
   (rps3_table_spline, on the caller's scratch), the unwrap of the centre's
   angle, and 10^4 points through rps3_inverse allocate nothing */
#define NROWS 401
/* C99 does not convert double (*)[3] to const double (*)[3] implicitly */
#define ROWS3(A) ((const double(*)[3])(A))
static void table_kinds(void **state) {
  static double time[NROWS], pose[NROWS][3], rate[NROWS][3], work[NROWS];
  static double centre[NROWS][3], crate[NROWS][3], psi[NROWS];
  rps3_model m;
  rps3_data *d = NULL;
  rps3_traj tr[2];
  long p, failures = 0;
  int i, j;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (i = 0; i < NROWS; i++) {
    double t = 4.0 * i / (NROWS - 1), a = 0.7 + 1.9 * t;
    time[i] = t;
    pose[i][0] = 0.3 * sin(1.3 * t);
    pose[i][1] = 0.08 + 0.02 * cos(0.7 * t);
    pose[i][2] = 0.3 + 0.01 * sin(t);
    centre[i][0] = 0.011 + 0.027 * cos(a);
    centre[i][1] = 0.004 + 0.027 * sin(a);
    centre[i][2] = 0.3;
  }
  count_start();
  assert_int_equal(rps3_table_spline(NROWS, time, ROWS3(pose), rate, work),
                   RPS3_OK);
  assert_int_equal(rps3_table_spline(NROWS, time, ROWS3(centre), crate, work),
                   RPS3_OK);
  assert_int_equal(rps3_table_unwrap(NROWS, ROWS3(centre), psi), RPS3_OK);
  count_stop();
  assert_int_equal(n_alloc, 0);
  for (j = 0; j < 2; j++) {
    rps3_table *tb = j ? &tr[j].path.table : &tr[j].table;
    rps3_traj_default(&tr[j]);
    tr[j].kind = j ? RPS3_TRAJ_PATH : RPS3_TRAJ_TABLE;
    tr[j].path.shape = RPS3_PATH_TABLE;
    tr[j].path.table_psi = psi;
    tb->n = NROWS;
    tb->time = time;
    tb->value = ROWS3(j ? centre : pose);
    tb->rate = ROWS3(j ? crate : rate);
    assert_int_equal(rps3_traj_check(&m, &tr[j], NULL), RPS3_OK);
  }
  count_start();
  for (p = 0; p < 10000; p++) {
    const rps3_traj *t = &tr[p % 2];
    double at = 4.0 * (double)p / 9999.0;
    if (rps3_traj_eval(&m, t, at, d->pose, d->dpose, d->ddpose) != RPS3_OK ||
        rps3_inverse(&m, d) != RPS3_OK)
      failures++;
  }
  count_stop();
  print_message("tables: 10000 points, %ld failures, %ld allocations, %ld "
                "frees\n", failures, n_alloc, n_free);
  assert_int_equal(failures, 0);
  assert_int_equal(n_alloc, 0);
  assert_int_equal(n_free, 0);
  rps3_data_free(d);
}

/* the other stages (forward dynamics included) and the error paths
   (RPS3_ERROR formats its message into the data) do not allocate either */
static void stages_and_errors(void **state) {
  rps3_model m;
  rps3_data *d = NULL;
  long p, ok = 0, errors = 0;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);

  count_start();
  for (p = 0; p < 2000; p++) {
    double s = (double)p / 2000.0;
    rps3_data_reset(d);
    d->pose[0] = -2.9 + 5.7 * s;
    d->pose[1] = 0.05 + 0.3 * s;
    d->pose[2] = 0.21 + 0.1 * s;
    d->dpose[0] = 0.71;
    d->dpose[1] = -0.23;
    d->dpose[2] = 0.037;
    d->ddpose[0] = -1.3;
    d->ddpose[1] = 0.47;
    d->ddpose[2] = 0.11;
    if (rps3_ik(&m, d) == RPS3_OK && rps3_velocity(&m, d) == RPS3_OK &&
        rps3_acceleration(&m, d) == RPS3_OK && rps3_invdyn(&m, d) == RPS3_OK &&
        rps3_joint_velocity(&m, d) == RPS3_OK &&
        rps3_joint_acceleration(&m, d) == RPS3_OK && rps3_fk(&m, d) == RPS3_OK &&
        rps3_fwddyn(&m, d) == RPS3_OK &&
        rps3_energy(&m, d, NULL, NULL, NULL) == RPS3_OK)
      ok++;
    /* errors: unreachable pose, non-finite input, stage out of order */
    d->pose[2] = -0.3;
    if (rps3_ik(&m, d) == RPS3_EREACH) errors++;
    d->pose[2] = (double)NAN;
    if (rps3_ik(&m, d) == RPS3_EINVAL) errors++;
    rps3_data_reset(d);
    if (rps3_invdyn(&m, d) == RPS3_ESTATE) errors++;
    d->l[0] = d->l[1] = d->l[2] = 1e200;
    if (rps3_theta_solve(&m, d) != RPS3_OK) errors++;
  }
  count_stop();
  print_message("stages: %ld points ok, %ld errors raised, %ld allocations\n",
                ok, errors, n_alloc);
  assert_int_equal(ok, 2000);
  assert_int_equal(errors, 4 * 2000);
  assert_int_equal(n_alloc, 0);
  assert_int_equal(n_free, 0);
  rps3_data_free(d);
}

/* the batch entry points, with failing points among them (the message of
   the first one is rewritten in place) */
#define NBATCH 2000
static void batches(void **state) {
  static double pose[3 * NBATCH], rates[3 * NBATCH], l[3 * NBATCH],
      theta[3 * NBATCH], F[3 * NBATCH], Fe[RPS3_NEFFECT * 3 * NBATCH];
  static int status[NBATCH];
  rps3_model m;
  rps3_data *d = NULL;
  rps3_batch_in in;
  rps3_batch_out out;
  size_t i, nfail[3];
  (void)state;
  model_entropy(&m);
  m.opt.theta = RPS3_THETA_MULTIROOT;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (i = 0; i < NBATCH; i++) {
    double s = (double)i / NBATCH;
    pose[i] = -2.9 + 5.7 * s;
    pose[NBATCH + i] = 0.05 + 0.3 * s;
    pose[2 * NBATCH + i] = i % 50 == 7 ? -0.1 : 0.21 + 0.1 * s;
  }
  for (i = 0; i < 3 * NBATCH; i++) rates[i] = 0.31 - 0.0001 * (double)i;
  memset(&in, 0, sizeof(in));
  memset(&out, 0, sizeof(out));
  in.n = NBATCH;
  in.pose = pose;
  in.dpose = rates;
  in.ddpose = rates;
  out.status = status;
  out.l = l;
  out.theta = theta;
  out.F = F;
  out.F_effect = Fe;

  count_start();
  assert_int_equal(rps3_inverse_batch(&m, d, &in, &out), RPS3_OK);
  nfail[0] = out.nfail;
  assert_int_equal(rps3_ik_batch(&m, d, &in, &out), RPS3_OK);
  nfail[1] = out.nfail;
  in.l = l;
  in.guess = theta;
  assert_int_equal(rps3_fk_batch(&m, d, &in, &out), RPS3_OK);
  nfail[2] = out.nfail;
  count_stop();
  print_message("batches: %d points, %lu/%lu/%lu failed, %ld allocations\n",
                NBATCH, (unsigned long)nfail[0], (unsigned long)nfail[1],
                (unsigned long)nfail[2], n_alloc);
  assert_int_equal((int)nfail[0], NBATCH / 50);
  assert_int_equal((int)nfail[2], NBATCH / 50);
  assert_int_equal(n_alloc, 0);
  assert_int_equal(n_free, 0);
  rps3_data_free(d);
}

/* a closed-loop simulation allocates only in rps3_sim_alloc and
   rps3_ctrl_alloc: start, advance, the controller and GSL's explicit
   steppers allocate nothing; GSL's implicit ones do */
static void simulation_loop(void **state) {
  static const rps3_integrator integ[4] = {RPS3_INT_RK4, RPS3_INT_RK8PD,
                                           RPS3_INT_MSBDF, RPS3_INT_RK4IMP};
  rps3_model m;
  rps3_traj tr;
  int k, j;
  (void)state;
  model_entropy(&m);
  m.friction.vreg = 1e-3;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  rps3_traj_default(&tr);
  tr.helix.radius = 0.0031;
  tr.helix.z0 = 0.2713;
  for (k = 0; k < 4; k++) {
    rps3_sim_options o;
    rps3_sim *s = NULL;
    rps3_ctrl *c = NULL;
    double pose[3], dpose[3];
    int st = RPS3_OK;
    rps3_sim_options_default(&o);
    o.integrator = integ[k];
    o.noise_l = 1e-6;
    o.h = (integ[k] == RPS3_INT_RK4IMP) ? 5e-4 : 1e-3;
    assert_int_equal(rps3_sim_alloc(&m, &o, &s, NULL), RPS3_OK);
    assert_int_equal(rps3_ctrl_alloc(RPS3_CTRL_COMPUTED_TORQUE, 400.0, 40.0,
                                     &m, &tr, &c, NULL), RPS3_OK);
    assert_int_equal(rps3_traj_eval(&m, &tr, 0.0, pose, dpose, NULL), RPS3_OK);
    count_start();
    {
      rps3_controller ctl = rps3_ctrl_bind(c, 1000.0);
      if (rps3_sim_start(s, 0.0, pose, dpose) != RPS3_OK) st = -100;
      for (j = 1; j <= 200 && st == RPS3_OK; j++)
        st = rps3_sim_advance(s, &ctl, 1e-3 * j);
    }
    count_stop();
    print_message("simulation, %s: %ld steps, %ld evaluations, %ld "
                  "allocations, %ld frees\n", rps3_integrator_name(integ[k]),
                  rps3_sim_now(s)->nsteps, rps3_sim_now(s)->nevals, n_alloc, n_free);
    assert_int_equal(st, RPS3_OK);
    /* GSL 2.7's implicit steppers allocate in their steps (documented in
       rps3.h); the count shows the interposer sees GSL's steppers */
    if (integ[k] == RPS3_INT_MSBDF || integ[k] == RPS3_INT_RK4IMP) {
      assert_true(n_alloc > 0);
    } else {
      assert_int_equal(n_alloc, 0);
      assert_int_equal(n_free, 0);
    }
    rps3_ctrl_free(c);
    rps3_sim_free(s);
  }
}

/* the design section after rps3_design_ws_alloc: a grid with every output,
   an empty workspace, a bad design, a task that passes and one that
   leaves the workspace allocate nothing */
static void design_evaluations(void **state) {
  static int flags[1000];
  static double l[3000], th[3000], ball[3000], c[3000], v[8][1000];
  rps3_design ds;
  rps3_design_ws *w = NULL;
  rps3_design_grid gr;
  rps3_design_summary sum;
  rps3_design_task task;
  rps3_design_out out;
  rps3_traj tr;
  int st[5];
  (void)state;
  out.flags = flags;
  out.l = l;
  out.theta = th;
  out.ball = ball;
  out.c = c;
  out.clearance = v[0];
  out.lti = v[1];
  out.oti = v[2];
  out.cti = v[3];
  out.cond_h = v[4];
  out.transmission = v[5];
  out.spin = v[6];
  rps3_design_default(&ds);
  ds.link_radius = 0.01;
  rps3_design_grid_default(&ds, &gr);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_design_ws_alloc(&w), RPS3_OK);
  count_start();
  st[0] = rps3_design_eval_grid(w, &ds, NULL, &gr, &out, &sum);
  st[1] = rps3_design_task_eval(w, &ds, NULL, &tr, 2001, 1, &task);
  ds.l_max = 0.34;
  st[2] = rps3_design_task_eval(w, &ds, NULL, &tr, 2001, 0, &task);
  ds.l_min = 5.0;
  ds.l_max = 6.0;
  st[3] = rps3_design_eval_grid(w, &ds, NULL, &gr, &out, &sum);
  ds.rho = -1.0;
  st[4] = rps3_design_eval_grid(w, &ds, NULL, &gr, &out, &sum);
  count_stop();
  print_message("design: %ld allocations, %ld frees\n", n_alloc, n_free);
  assert_int_equal(st[0], RPS3_OK);
  assert_int_equal(st[1], RPS3_OK);
  assert_int_equal(st[2], RPS3_EREACH);
  assert_int_equal(st[3], RPS3_EEMPTY);
  assert_int_equal(st[4], RPS3_EINVAL);
  assert_int_equal(n_alloc, 0);
  assert_int_equal(n_free, 0);
  rps3_design_ws_free(w);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(design_evaluations),
      cmocka_unit_test(batches),
      cmocka_unit_test(simulation_loop),
      cmocka_unit_test(interposer_sees_gsl_and_init),
      cmocka_unit_test(closed_form_lagrange),
      cmocka_unit_test(closed_form_kernel),
      cmocka_unit_test(closed_form_newton_euler),
      cmocka_unit_test(warm_multiroot_lagrange),
      cmocka_unit_test(warm_multiroot_newton_euler),
      cmocka_unit_test(cold_multiroot_lagrange),
      cmocka_unit_test(stages_and_errors),
      cmocka_unit_test(table_kinds),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}

#endif /* RPS3_SANITIZE */
