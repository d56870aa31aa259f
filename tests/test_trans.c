/*
 * test_trans.c - the force transmission measure (rps3_data.transmission):
 * dimensionless, a bound on the holding force, blind to neither of the two
 * approaches where the condition number of df/dtheta says nothing (a level
 * platform lowered onto the base) or speaks too late (a tilted approach
 * to the singular surface), and its two limits opt.trans_warn/trans_max.
 */
#include "testutil.h"

#include "fwddyn.h" /* the forward dynamics' state, its limits */

static rps3_data *make(rps3_model *m, int effects, int method) {
  rps3_data *d = NULL;
  rps3_model_default(m);
  m->opt.effects = effects;
  m->opt.method = method;
  m->opt.outputs &= ~RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &d), RPS3_OK);
  return d;
}

static double fmax3(const double F[3]) {
  double a = fabs(F[0]), b = fabs(F[1]), c = fabs(F[2]);
  return a > b ? (a > c ? a : c) : (b > c ? b : c);
}

/*
 * A level platform lowered towards the base: the condition number of the
 * lambda system stays at exactly 3, but the holding force grows like
 * 1 / z_c.  The transmission follows the force: past trans_warn (100) the
 * point carries RPS3_WARN_TRANS, past trans_max (1e8) it is RPS3_ESING
 * with a message; at z_c = 1e-12 m it is refused (the forces would be 2e11 N).
 */
static void level_platform_lowered(void **state) {
  rps3_model m;
  rps3_data *d = make(&m, RPS3_EFF_PLATFORM_GRAVITY, RPS3_LAGRANGE);
  double z, W;
  int nok = 0, nwarn = 0, nsing = 0, last = -1;
  (void)state;
  W = m.M * m.g;
  for (z = 0.2713; z > 5e-13; z /= 3.7) {
    int st;
    d->pose[0] = 0.0;
    d->pose[1] = 0.0;
    d->pose[2] = z;
    st = rps3_inverse(&m, d);
    if (st == RPS3_OK) {
      /* the holding force stays under its bound: a platform weight W is
         the load (0, 0, W) with no moment */
      CHECK_REL(d->cond, 3.0, 1e-9, 1.0, "cond of a level platform");
      assert_true(fmax3(d->F) <= d->transmission * W * (1 + 1e-12));
      assert_int_equal((d->warn & RPS3_WARN_TRANS) != 0,
                       d->transmission > m.opt.trans_warn);
      /* warnings come in order: none, then warn; never back */
      assert_true(last <= ((d->warn & RPS3_WARN_TRANS) != 0));
      last = (d->warn & RPS3_WARN_TRANS) != 0;
      nok++;
      nwarn += last;
    } else {
      assert_int_equal(st, RPS3_ESING);
      assert_non_null(strstr(d->err.msg, "force transmission"));
      assert_true(d->transmission > m.opt.trans_max);
      assert_true(last == 1); /* warned before refused */
      nsing++;
    }
  }
  assert_true(nok > 3 && nwarn > 3 && nsing > 3);
  /* the pose at z_c -> 0: the platform in the base plane */
  d->pose[2] = 1e-12;
  assert_int_equal(rps3_inverse(&m, d), RPS3_ESING);
  rps3_data_free(d);
}

/*
 * A tilted approach to the singular surface (alpha = 0.3 rad, z_c = 0.2 m,
 * beta rising): the first RPS3_WARN_TRANS must come while the holding force
 * is still moderate (under 100 times the weight), long before
 * RPS3_WARN_ILLCOND (cond > 1e6), which came at 7.6e5 times it.
 */
static void tilted_approach_warns_early(void **state) {
  rps3_model m;
  rps3_data *d = make(&m, RPS3_EFF_PLATFORM_GRAVITY, RPS3_LAGRANGE);
  double lo = 0.5, hi = 1.0, bs, e, W, f_trans = -1.0, f_ill = -1.0;
  int k;
  (void)state;
  W = m.M * m.g;
  /* the singular surface along this line: bisection on the mode */
  d->pose[0] = 0.3;
  d->pose[2] = 0.2;
  for (k = 0; k < 80; k++) {
    d->pose[1] = 0.5 * (lo + hi);
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    if (d->mode == RPS3_MODE_LEVEL)
      lo = d->pose[1];
    else
      hi = d->pose[1];
  }
  bs = lo;
  for (e = 0.2; e > 1e-13; e *= 0.9) {
    d->pose[0] = 0.3;
    d->pose[1] = bs - e;
    d->pose[2] = 0.2;
    if (rps3_inverse(&m, d) != RPS3_OK) break;
    if (f_trans < 0 && (d->warn & RPS3_WARN_TRANS)) f_trans = fmax3(d->F) / W;
    if (f_ill < 0 && (d->warn & RPS3_WARN_ILLCOND)) f_ill = fmax3(d->F) / W;
  }
  print_message(
      "tilted approach: first transmission warning at %.3g x the "
      "weight, first condition warning at %.3g x\n",
      f_trans, f_ill);
  assert_true(f_trans > 0.0 && f_trans < 100.0);
  assert_true(f_ill < 0.0 || f_ill > 100.0 * f_trans);
  rps3_data_free(d);
}

/* dimensionless: the same at every size of mechanism, and the same under
   both formulations (it reads positions only) */
static void scale_and_method_invariant(void **state) {
  static const double s[4] = {1e-3, 0.37, 1.0, 85.0};
  rps3_model m;
  rps3_data *d;
  double ref = 0.0;
  int k, method;
  (void)state;
  for (method = 0; method < 2; method++)
    for (k = 0; k < 4; k++) {
      d = make(&m, RPS3_EFF_PLATFORM_GRAVITY, method);
      m.R *= s[k];
      m.d *= s[k];
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      d->pose[0] = 0.7311;
      d->pose[1] = 0.4127;
      d->pose[2] = 0.9173 * m.R;
      assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
      if (ref == 0.0) ref = d->transmission;
      CHECK_REL(d->transmission, ref, 1e-12, 0.0, "scale %g method %d", s[k],
                method);
      rps3_data_free(d);
    }
  assert_true(ref > 1.0 && ref < 100.0);
}

/* the bound holds for any wrench: random poses, a load made of the
   platform weight plus an off-centre payload (force and moment) */
static void bound_on_holding_force(void **state) {
  rps3_model m;
  rps3_data *d = make(&m, RPS3_EFF_PAYLOAD, RPS3_NEWTON_EULER);
  uint64_t seed = 99;
  int n, ok = 0;
  (void)state;
  m.payload.mass = 0.3137;
  m.payload.com[0] = 0.0411;
  m.payload.com[1] = -0.0271;
  m.payload.com[2] = 0.0317;
  m.payload.inertia[0] = m.payload.inertia[1] = m.payload.inertia[2] = 1e-4;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  for (n = 0; n < 2000; n++) {
    double f, nm, load;
    int i;
    d->pose[0] = rnd_uniform(&seed, -PI, PI);
    d->pose[1] = rnd_uniform(&seed, 0.0, 0.6);
    d->pose[2] = rnd_uniform(&seed, 0.3, 2.5) * m.R;
    if (rps3_inverse(&m, d) != RPS3_OK) continue;
    /* the static payload load: force m g e_z, moment (R p) x (m g e_z)
       with p the payload centre of mass in base axes */
    f = m.payload.mass * m.g;
    nm = 0.0;
    for (i = 0; i < 2; i++) {
      double pc = 0.0;
      int k;
      for (k = 0; k < 3; k++) pc += d->rot[i][k] * m.payload.com[k];
      if (fabs(pc * f) > nm) nm = fabs(pc * f);
    }
    load = f > nm / m.R ? f : nm / m.R;
    assert_true(fmax3(d->F) <= d->transmission * load * (1 + 1e-12));
    ok++;
  }
  assert_true(ok > 1000);
  rps3_data_free(d);
}

/*
 * The oracle of the measure, from the model's inputs (R, rho) and the pose
 * only: ball joints from rot = Rz(alpha) Ry(beta) Rz(-alpha) and the centre
 * from the pin planes (each ball joint in the vertical plane of its pin),
 * link directions from the pins, pin axes tangential.  A wrench w = (f, n)
 * on the platform (moment about the centre) is held by F_i phi_i + tau_i
 * axis_i at the ball joints; B = the F rows of the inverse of that 6 x 6
 * statics, T = max_i sum_j |B_ij| s_j with s = (1, 1, 1, R, R, R).
 * Writes B (3 x 6); returns T.
 */
static double oracle_transmission(double R, double rho, const double q[3],
                                  double B[3][6]) {
  double rot[3][3], Rz[3][3], Ry[3][3], c[3], b[3][3], A[6][6], Ai[6][6];
  double psi, cp[3], sp[3], T = 0.0, a1, a2, r = rho * R;
  int i, j, k;
  for (i = 0; i < 3; i++) {
    psi = 2.0 * PI * i / 3.0;
    cp[i] = cos(psi);
    sp[i] = sin(psi);
  }
  memset(Rz, 0, sizeof Rz);
  memset(Ry, 0, sizeof Ry);
  Rz[0][0] = Rz[1][1] = cos(q[0]);
  Rz[1][0] = sin(q[0]);
  Rz[0][1] = -Rz[1][0];
  Rz[2][2] = 1.0;
  Ry[0][0] = Ry[2][2] = cos(q[1]);
  Ry[0][2] = sin(q[1]);
  Ry[2][0] = -Ry[0][2];
  Ry[1][1] = 1.0;
  for (i = 0; i < 3; i++) /* Rz Ry Rz^T */
    for (j = 0; j < 3; j++) {
      rot[i][j] = 0.0;
      for (k = 0; k < 3; k++) {
        int l;
        for (l = 0; l < 3; l++) rot[i][j] += Rz[i][k] * Ry[k][l] * Rz[j][l];
      }
    }
  /* ball joint i relative to the centre: w_i = r rot (cos, sin, 0); the
     pin planes (c + w_i) . (-sin psi_i, cos psi_i, 0) = 0, i = 0, 1 */
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++)
      b[i][k] = r * (rot[k][0] * cp[i] + rot[k][1] * sp[i]);
  a1 = sp[0] * b[0][0] - cp[0] * b[0][1];
  a2 = sp[1] * b[1][0] - cp[1] * b[1][1];
  c[0] = (cp[1] * a1 - cp[0] * a2) / (cp[0] * sp[1] - sp[0] * cp[1]);
  c[1] = (sp[1] * a1 - sp[0] * a2) / (cp[0] * sp[1] - sp[0] * cp[1]);
  c[2] = q[2];
  assert_true(fabs(-sp[0] * c[0] + cp[0] * c[1] - a1) < 1e-12 * R);
  /* columns: link force phi_i and pin-axis force axis_i at rho_i = w_i */
  for (i = 0; i < 3; i++) {
    double phi[3], ax[3] = {-sp[i], cp[i], 0.0}, len = 0.0;
    double P[3] = {R * cp[i], R * sp[i], 0.0};
    for (k = 0; k < 3; k++) {
      phi[k] = c[k] + b[i][k] - P[k];
      len += phi[k] * phi[k];
    }
    for (k = 0; k < 3; k++) phi[k] /= sqrt(len);
    for (k = 0; k < 3; k++) {
      A[k][i] = phi[k];
      A[k][3 + i] = ax[k];
    }
    A[3][i] = b[i][1] * phi[2] - b[i][2] * phi[1];
    A[4][i] = b[i][2] * phi[0] - b[i][0] * phi[2];
    A[5][i] = b[i][0] * phi[1] - b[i][1] * phi[0];
    A[3][3 + i] = b[i][1] * ax[2] - b[i][2] * ax[1];
    A[4][3 + i] = b[i][2] * ax[0] - b[i][0] * ax[2];
    A[5][3 + i] = b[i][0] * ax[1] - b[i][1] * ax[0];
  }
  /* inverse by Gauss-Jordan with partial pivoting */
  for (i = 0; i < 6; i++)
    for (j = 0; j < 6; j++) Ai[i][j] = (i == j);
  for (k = 0; k < 6; k++) {
    int piv = k;
    for (i = k + 1; i < 6; i++)
      if (fabs(A[i][k]) > fabs(A[piv][k])) piv = i;
    for (j = 0; j < 6; j++) {
      double t = A[k][j];
      A[k][j] = A[piv][j];
      A[piv][j] = t;
      t = Ai[k][j];
      Ai[k][j] = Ai[piv][j];
      Ai[piv][j] = t;
    }
    for (i = 0; i < 6; i++) {
      double f = A[i][k] / A[k][k];
      if (i == k) continue;
      for (j = 0; j < 6; j++) {
        A[i][j] -= f * A[k][j];
        Ai[i][j] -= f * Ai[k][j];
      }
    }
  }
  for (i = 0; i < 3; i++) {
    double s = 0.0;
    for (j = 0; j < 6; j++) {
      B[i][j] = Ai[i][j] / A[i][i];
      s += fabs(B[i][j]) * (j < 3 ? 1.0 : R);
    }
    if (s > T) T = s;
  }
  return T;
}

/*
 * The measure equals its oracle from the inputs (TOL_EXACT: both invert a
 * well-conditioned 6 x 6 system, rounding only), over random poses of a
 * high-entropy geometry; and the oracle's B is the mechanism's statics:
 * a massless mechanism holding an off-centre payload at rest needs
 * F = +-B (f, n) for the payload's weight f and its moment n about the
 * centre, the sign the same everywhere (the library gets F from the
 * lambda system of (23), another formulation).
 */
static void transmission_from_inputs(void **state) {
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 4471;
  int n, ok = 0, sign = 0;
  (void)state;
  model_entropy(&m);
  m.M = m.m = m.link_Ic = 0.0;
  m.opt.effects = RPS3_EFF_PAYLOAD;
  m.opt.outputs &= ~RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 2000; n++) {
    double B[3][6], w[6], rp[3], T, res[2] = {0.0, 0.0}, scale = 0.0;
    int i, j, k;
    d->pose[0] = rnd_uniform(&seed, -PI, PI);
    d->pose[1] = rnd_uniform(&seed, 0.0, 0.7);
    d->pose[2] = rnd_uniform(&seed, 0.2, 2.5) * m.R;
    for (k = 0; k < 3; k++) d->dpose[k] = d->ddpose[k] = 0.0;
    if (rps3_inverse(&m, d) != RPS3_OK) continue;
    T = oracle_transmission(m.R, m.rho, d->pose, B);
    CHECK_REL(d->transmission, T, TOL_EXACT, 0.0, "pose %d", n);
    /* the payload's weight and its moment about the centre */
    for (k = 0; k < 3; k++)
      rp[k] = d->rot[k][0] * m.payload.com[0] +
              d->rot[k][1] * m.payload.com[1] + d->rot[k][2] * m.payload.com[2];
    w[0] = w[1] = 0.0;
    w[2] = -m.payload.mass * m.g;
    w[3] = rp[1] * w[2];
    w[4] = -rp[0] * w[2];
    w[5] = 0.0;
    for (i = 0; i < 3; i++) {
      double f = 0.0;
      for (j = 0; j < 6; j++) f += B[i][j] * w[j];
      res[0] += fabs(d->F[i] - f);
      res[1] += fabs(d->F[i] + f);
      scale += fabs(f);
    }
    k = res[0] < res[1] ? 1 : -1;
    if (sign == 0) sign = k;
    assert_int_equal(k, sign);
    CHECK_REL(res[0] < res[1] ? res[0] : res[1], 0.0, TOL_EXACT, scale,
              "static payload load at pose %d", n);
    ok++;
  }
  assert_true(ok > 1000);
  rps3_data_free(d);
}

/*
 * The forward dynamics' limits (src/fwddyn_plane.h, invdyn_limits) are
 * rps3_inverse's: the transmission from the twist columns Jc, Jw the
 * dynamics forms in the links' planes (from l, cos theta, sin theta, no
 * positions), and the condition number from its inverse of df/dtheta,
 * equal the stages' (from the positions, src/invdyn.c) over random poses
 * and rates of a high-entropy geometry.  TOL_PHYS: the state solves theta
 * again, to opt.tol, from the inverse's root.
 */
static void forward_dynamics_limits(void **state) {
  rps3_model m;
  rps3_data *d, *f;
  rps3_fd_state k;
  uint64_t seed = 0x7a3c1;
  int n, i, ok = 0;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &f), RPS3_OK);
  for (n = 0; n < 500; n++) {
    d->pose[0] = rnd_uniform(&seed, -PI, PI);
    d->pose[1] = rnd_uniform(&seed, 0.0, 0.7);
    d->pose[2] = rnd_uniform(&seed, 0.2, 2.5) * m.R;
    for (i = 0; i < 3; i++) {
      d->dpose[i] = rnd_uniform(&seed, -1.0, 1.0);
      d->ddpose[i] = rnd_uniform(&seed, -1.0, 1.0);
    }
    if (rps3_inverse(&m, d) != RPS3_OK) continue;
    rps3_data_reset(f);
    memcpy(f->l, d->l, sizeof(f->l));
    memcpy(f->dl, d->dl, sizeof(f->dl));
    memcpy(f->theta, d->theta, sizeof(f->theta));
    f->have_theta = 1;
    memset(&k, 0, sizeof(k));
    if (rps3_fwddyn_state(&m, f, &k, RPS3_FD_LEAN | RPS3_FD_NOFACTOR) !=
        RPS3_OK)
      fail_msg("pose %d: forward dynamics: %s", n, f->err.msg);
    CHECK_REL(f->transmission, d->transmission, TOL_PHYS, 0.0,
              "transmission at pose %d", n);
    CHECK_REL(f->cond, d->cond, TOL_PHYS, 0.0, "cond at pose %d", n);
    ok++;
  }
  assert_true(ok > 250);
  rps3_data_free(d);
  rps3_data_free(f);
}

/* the limits are options: validated, and trans_max >= trans_warn */
static void limits_are_options(void **state) {
  rps3_model m;
  rps3_check chk;
  (void)state;
  rps3_model_default(&m);
  assert_true(m.opt.trans_warn == 100.0 && m.opt.trans_max == 1e8);
  m.opt.trans_warn = 0.0;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_true(strncmp(chk.msg, "opt.trans_warn = ", 17) == 0);
  rps3_model_default(&m);
  m.opt.trans_max = 50.0;
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);
  assert_true(strncmp(chk.msg, "opt.trans_max = ", 16) == 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(level_platform_lowered),
      cmocka_unit_test(tilted_approach_warns_early),
      cmocka_unit_test(scale_and_method_invariant),
      cmocka_unit_test(bound_on_holding_force),
      cmocka_unit_test(transmission_from_inputs),
      cmocka_unit_test(forward_dynamics_limits),
      cmocka_unit_test(limits_are_options),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
