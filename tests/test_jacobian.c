/*
 * test_jacobian.c - every analytic Jacobian of the library against finite
 * differences of a function the test writes itself from the model's inputs
 * (R, rho, the pin angles 0, 2pi/3, 4pi/3), never from a field the library
 * derived:
 *   - d f / d theta of (8)-(10) that the theta solve hands to GSL (fk.c);
 *   - d f / d l and d f / d theta of f_k = |b_i - b_j|^2 - 3 r^2 (ik.c),
 *     which the lambda system and the joint-rate route solve with;
 *   - the rate maps of velocity.c: (alpha', beta', z') -> (l', theta', vc,
 *     omega) and one order higher, against differences of the test's own
 *     inverse kinematics along the pose.
 *
 * The differences are the 5-point stencil (f(-2h) - 8 f(-h) + 8 f(h) -
 * f(2h)) / 12h: truncation h^4 |f^(5)| / 30, rounding ~ eps |f| / h.  With
 * h = 1e-3 (radians, or units of R) on functions whose terms are O(1-10)
 * that is ~1e-13 + ~2e-12, so TOL_JAC = 1e-9 relative to the Jacobian's
 * scale holds with three digits of margin, while a Jacobian entry off by
 * 0.1 % fails by six.
 */
#include "internal.h"
#include "testutil.h"

#define TOL_JAC 1e-9
#define H_JAC 1e-3

/* the test's own geometry, from the inputs only */
typedef struct {
  double R, r;
  double pin[3][3], u[3][3], ax[3][3], body[3][3];
} geom;

static void geom_make(geom *g, double R, double rho) {
  int i;
  g->R = R;
  g->r = rho * R;
  for (i = 0; i < 3; i++) {
    double psi = 2.0 * PI * i / 3.0, cp = cos(psi), sp = sin(psi);
    g->u[i][0] = cp;
    g->u[i][1] = sp;
    g->u[i][2] = 0.0;
    g->pin[i][0] = R * cp;
    g->pin[i][1] = R * sp;
    g->pin[i][2] = 0.0;
    g->ax[i][0] = -sp;
    g->ax[i][1] = cp;
    g->ax[i][2] = 0.0;
    g->body[i][0] = g->r * cp;
    g->body[i][1] = g->r * sp;
    g->body[i][2] = 0.0;
  }
}

/* ball joint i from its link: pin + l (-cos theta u + sin theta e_z) */
static void ball(const geom *g, int i, double l, double th, double b[3]) {
  int k;
  for (k = 0; k < 3; k++) b[k] = g->pin[i][k] - l * cos(th) * g->u[i][k];
  b[2] += l * sin(th);
}

/* f_k = |b_i - b_j|^2 - 3 r^2 for the pairs (1,2), (2,3), (3,1) [m^2] */
static void closure(const geom *g, const double l[3], const double th[3],
                    double f[3]) {
  int k, q;
  for (k = 0; k < 3; k++) {
    int i = k, j = (k + 1) % 3;
    double bi[3], bj[3], s = 0.0;
    ball(g, i, l[i], th[i], bi);
    ball(g, j, l[j], th[j], bj);
    for (q = 0; q < 3; q++) s += (bi[q] - bj[q]) * (bi[q] - bj[q]);
    f[k] = s - 3.0 * g->r * g->r;
  }
}

/* 5-point central difference of a 3-vector function along one coordinate */
static void diff5(double out[3], const double fm2[3], const double fm1[3],
                  const double fp1[3], const double fp2[3], double h) {
  int k;
  for (k = 0; k < 3; k++)
    out[k] = (fm2[k] - 8.0 * fm1[k] + 8.0 * fp1[k] - fp2[k]) / (12.0 * h);
}

static double maxabs33(const double J[3][3]) {
  double s = 0.0;
  int i, k;
  for (i = 0; i < 3; i++)
    for (k = 0; k < 3; k++)
      if (fabs(J[i][k]) > s) s = fabs(J[i][k]);
  return s;
}

/* random reachable configurations: a pose, its lengths and angles */
static int random_pose(const rps3_model *m, rps3_data *d, uint64_t *seed) {
  d->pose[0] = rnd_uniform(seed, -3.1, 3.1);
  d->pose[1] = rnd_uniform(seed, 0.02, 0.7);
  d->pose[2] = rnd_uniform(seed, 0.12, 0.45);
  return rps3_ik(m, d);
}

/* the theta solve's (8)-(10): f is the geometry, J is its derivative */
static void theta_solve_jacobian(void **state) {
  rps3_model m;
  rps3_data *d;
  geom g;
  uint64_t seed = 2385;
  int n, tried = 0, i, k, s;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  geom_make(&g, m.R, m.rho);
  for (n = 0; n < 300; n++) {
    double L[3], th[3], f[3], J[3][3], fg[3], l[3], sc;
    if (random_pose(&m, d, &seed) != RPS3_OK) continue;
    tried++;
    /* off the solution too: the solver evaluates J on its way there */
    for (i = 0; i < 3; i++) {
      L[i] = d->l[i] / m.R;
      l[i] = d->l[i];
      th[i] = d->theta[i] + rnd_uniform(&seed, -0.2, 0.2);
    }
    rps3_theta_constraints(L, m.rho, th, f, J);
    /* f is (8)-(10): the closure in units of R^2 */
    closure(&g, l, th, fg);
    for (k = 0; k < 3; k++)
      CHECK_REL(f[k], fg[k] / (m.R * m.R), TOL_EXACT, 1.0, "f%d pose %d", k, n);
    sc = maxabs33(M3C(J));
    for (i = 0; i < 3; i++) {
      double fs[4][3], col[3], t[3];
      static const double step[4] = {-2.0, -1.0, 1.0, 2.0};
      for (s = 0; s < 4; s++) {
        for (k = 0; k < 3; k++) t[k] = th[k];
        t[i] += step[s] * H_JAC;
        closure(&g, l, t, fs[s]);
        for (k = 0; k < 3; k++) fs[s][k] /= m.R * m.R;
      }
      diff5(col, fs[0], fs[1], fs[2], fs[3], H_JAC);
      for (k = 0; k < 3; k++)
        CHECK_REL(J[k][i], col[k], TOL_JAC, sc, "df%d/dtheta%d pose %d", k,
                  i, n);
    }
  }
  assert_true(tried > 200);
  rps3_data_free(d);
}

/* the two forms of src/cjac.h, the positions' (the lambda system, the
   batch kernel) and the links' planes' (the theta solve, the forward
   dynamics), are one Jacobian: entry by entry at the positions inverse
   kinematics leaves, and f = 0 there, to rounding of the entries' size */
static void cjac_forms_agree(void **state) {
  rps3_model m;
  rps3_data *d;
  uint64_t seed = 4127;
  int n, tried = 0, i, k;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (n = 0; n < 300; n++) {
    double Jl[3][3], Jt[3][3], h[3], Z[3], c[3], sn[3], sl, st;
    if (random_pose(&m, d, &seed) != RPS3_OK) continue;
    tried++;
    rps3_constraint_jacobian(d, Jl, Jt);
    sl = maxabs33(M3C(Jl));
    st = maxabs33(M3C(Jt));
    for (i = 0; i < 3; i++) {
      c[i] = cos(d->theta[i]);
      sn[i] = sin(d->theta[i]);
      h[i] = m.R - d->l[i] * c[i];
      Z[i] = d->l[i] * sn[i];
    }
    for (k = 0; k < 3; k++) {
      const int j = (k + 1) % 3;
      double al, bl;
      const rps3_plane_pair q = rps3_plane_pair_eval(
          h[k], h[j], Z[k], Z[j], d->l[k], d->l[j], c[k], sn[k], c[j], sn[j],
          3.0 * m.r * m.r);
      rps3_plane_pair_dl(&q, c[k], sn[k], c[j], sn[j], &al, &bl);
      CHECK_REL(q.f, 0.0, TOL_EXACT, m.R * m.R, "f%d pose %d", k, n);
      CHECK_REL(q.at, Jt[k][k], TOL_EXACT, st, "at%d pose %d", k, n);
      CHECK_REL(q.bt, Jt[k][j], TOL_EXACT, st, "bt%d pose %d", k, n);
      CHECK_REL(al, Jl[k][k], TOL_EXACT, sl, "al%d pose %d", k, n);
      CHECK_REL(bl, Jl[k][j], TOL_EXACT, sl, "bl%d pose %d", k, n);
    }
  }
  assert_true(tried > 200);
  rps3_data_free(d);
}

/* the constraint Jacobian in metres of the lambda system and the joint
   route, at the positions inverse kinematics leaves in the data */
static void constraint_jacobian(void **state) {
  rps3_model m;
  rps3_data *d;
  geom g;
  uint64_t seed = 7713;
  int n, tried = 0, i, k, s;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  geom_make(&g, m.R, m.rho);
  for (n = 0; n < 300; n++) {
    double Jl[3][3], Jt[3][3], sl, st;
    if (random_pose(&m, d, &seed) != RPS3_OK) continue;
    tried++;
    rps3_constraint_jacobian(d, Jl, Jt);
    sl = maxabs33(M3C(Jl));
    st = maxabs33(M3C(Jt));
    for (i = 0; i < 3; i++) {
      double fl[4][3], ft[4][3], cl[3], ct[3], l[3], th[3];
      static const double step[4] = {-2.0, -1.0, 1.0, 2.0};
      for (s = 0; s < 4; s++) {
        for (k = 0; k < 3; k++) {
          l[k] = d->l[k];
          th[k] = d->theta[k];
        }
        l[i] += step[s] * H_JAC * m.R;
        closure(&g, l, th, fl[s]);
        l[i] = d->l[i];
        th[i] += step[s] * H_JAC;
        closure(&g, l, th, ft[s]);
      }
      diff5(cl, fl[0], fl[1], fl[2], fl[3], H_JAC * m.R);
      diff5(ct, ft[0], ft[1], ft[2], ft[3], H_JAC);
      for (k = 0; k < 3; k++) {
        CHECK_REL(Jl[k][i], cl[k], TOL_JAC, sl, "df%d/dl%d pose %d", k, i, n);
        CHECK_REL(Jt[k][i], ct[k], TOL_JAC, st, "df%d/dtheta%d pose %d", k, i,
                  n);
      }
    }
  }
  assert_true(tried > 200);
  rps3_data_free(d);
}

/* the test's inverse kinematics: Rz(a) Ry(b) Rz(-a), the centre on the
   three pin planes, b_i = c + rot r_i; l, theta (39) and the frame */
typedef struct {
  double l[3], th[3], c[3], rot[3][3];
} ikres;

static void ik_own(const geom *g, const double pose[3], ikres *o) {
  double a = pose[0], b = pose[1], ca = cos(a), sa = sin(a), cb = cos(b),
         sb = sin(b);
  double Rz[3][3] = {{ca, -sa, 0}, {sa, ca, 0}, {0, 0, 1}};
  double Ry[3][3] = {{cb, 0, sb}, {0, 1, 0}, {-sb, 0, cb}};
  double Rzm[3][3] = {{ca, sa, 0}, {-sa, ca, 0}, {0, 0, 1}};
  double T[3][3];
  int i, j, k;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      T[i][j] = 0.0;
      for (k = 0; k < 3; k++) T[i][j] += Rz[i][k] * Ry[k][j];
    }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      o->rot[i][j] = 0.0;
      for (k = 0; k < 3; k++) o->rot[i][j] += T[i][k] * Rzm[k][j];
    }
  /* each ball joint stays in its pin's vertical plane: with rot fixed this
     is linear in (x_c, y_c); solved here for pins 1 and 2 */
  {
    double w[3][3], A[2][2], rhs[2], det;
    for (i = 0; i < 3; i++)
      for (k = 0; k < 3; k++)
        w[i][k] = o->rot[k][0] * g->body[i][0] + o->rot[k][1] * g->body[i][1];
    for (i = 0; i < 2; i++) {
      /* (c + w_i) . ax_i = 0: the plane through the Z axis and pin i */
      A[i][0] = g->ax[i][0];
      A[i][1] = g->ax[i][1];
      rhs[i] = -(w[i][0] * g->ax[i][0] + w[i][1] * g->ax[i][1]);
    }
    det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    o->c[0] = (rhs[0] * A[1][1] - A[0][1] * rhs[1]) / det;
    o->c[1] = (A[0][0] * rhs[1] - rhs[0] * A[1][0]) / det;
    o->c[2] = pose[2];
    for (i = 0; i < 3; i++) {
      double v[3];
      for (k = 0; k < 3; k++) v[k] = o->c[k] + w[i][k] - g->pin[i][k];
      o->l[i] = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      o->th[i] = atan2(v[2], -(v[0] * g->u[i][0] + v[1] * g->u[i][1]));
    }
  }
}

/* one 5-point derivative along dir of everything ik_own returns */
static void ik_rate(const geom *g, const double pose[3], const double dir[3],
                    double h, ikres *o) {
  ikres r[4];
  static const double step[4] = {-2.0, -1.0, 1.0, 2.0};
  double *out = (double *)o, *in[4];
  size_t n = sizeof(ikres) / sizeof(double), j;
  int s, k;
  for (s = 0; s < 4; s++) {
    double p[3];
    for (k = 0; k < 3; k++) p[k] = pose[k] + step[s] * h * dir[k];
    ik_own(g, p, &r[s]);
    in[s] = (double *)&r[s];
  }
  for (j = 0; j < n; j++)
    out[j] = (in[0][j] - 8.0 * in[1][j] + 8.0 * in[2][j] - in[3][j]) /
             (12.0 * h);
}

static double norm3(const double v[3]) {
  return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* omega from rot' rot^T */
static void omega_of(const double rot[3][3], const double drot[3][3],
                     double w[3]) {
  double W[3][3];
  int a, b, c;
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) {
      W[a][b] = 0.0;
      for (c = 0; c < 3; c++) W[a][b] += drot[a][c] * rot[b][c];
    }
  w[0] = 0.5 * (W[2][1] - W[1][2]);
  w[1] = 0.5 * (W[0][2] - W[2][0]);
  w[2] = 0.5 * (W[1][0] - W[0][1]);
}

/* velocity.c's rate map: (l', theta', vc, omega) = d/dt of the test's own
   inverse kinematics along the pose rates, for random states */
static void velocity_map(void **state) {
  rps3_model m;
  rps3_data *d;
  geom g;
  uint64_t seed = 5119;
  int n, tried = 0, i;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  geom_make(&g, m.R, m.rho);
  for (n = 0; n < 200; n++) {
    ikres r0, rd;
    double dp[3], w[3], pp[3], dw[3], sl, st, sv, sw;
    double Rd[3][3];
    if (random_pose(&m, d, &seed) != RPS3_OK) continue;
    for (i = 0; i < 3; i++) {
      dp[i] = rnd_uniform(&seed, -2.0, 2.0) * (i == 2 ? 0.1 : 1.0);
      d->dpose[i] = dp[i];
      d->ddpose[i] = 0.0;
    }
    if (rps3_velocity(&m, d) != RPS3_OK) fail_msg("%s", d->err.msg);
    tried++;
    /* first derivatives: along dpose (time derivative at fixed rates) */
    ik_own(&g, d->pose, &r0);
    ik_rate(&g, d->pose, dp, H_JAC, &rd);
    memcpy(Rd, rd.rot, sizeof Rd);
    omega_of(M3C(r0.rot), M3C(Rd), w);
    sl = norm3(rd.l);
    st = norm3(rd.th);
    sv = norm3(rd.c);
    sw = norm3(w);
    for (i = 0; i < 3; i++) {
      CHECK_REL(d->dl[i], rd.l[i], TOL_JAC, sl, "dl%d pose %d", i, n);
      CHECK_REL(d->dtheta[i], rd.th[i], TOL_JAC, st, "dtheta%d pose %d", i, n);
      CHECK_REL(d->vc[i], rd.c[i], TOL_JAC, sv, "vc%d pose %d", i, n);
      CHECK_REL(d->omega[i], w[i], TOL_JAC, sw, "omega%d pose %d", i, n);
    }
    /* second order, with a pose acceleration too: the rates at pose + s
       dpose with rates dpose + s ddpose, differenced in s (5 points) */
    {
      double ddp[3], acc_l[3], acc_t[3], acc_c[3], f[4][12];
      static const double step[4] = {-2.0, -1.0, 1.0, 2.0};
      const double h = H_JAC;
      int s, k;
      for (i = 0; i < 3; i++) {
        ddp[i] = rnd_uniform(&seed, -3.0, 3.0) * (i == 2 ? 0.1 : 1.0);
        d->ddpose[i] = ddp[i];
      }
      if (rps3_acceleration(&m, d) != RPS3_OK) fail_msg("%s", d->err.msg);
      for (s = 0; s < 4; s++) {
        ikres a0, ad;
        double dps[3], ww[3];
        /* the pose along its own second-order path p + s p' + s^2/2 p'' */
        for (k = 0; k < 3; k++) {
          double sh = step[s] * h;
          pp[k] = d->pose[k] + sh * dp[k] + 0.5 * sh * sh * ddp[k];
          dps[k] = dp[k] + sh * ddp[k];
        }
        ik_own(&g, pp, &a0);
        ik_rate(&g, pp, dps, 1e-4, &ad);
        omega_of(M3C(a0.rot), M3C(ad.rot), ww);
        for (k = 0; k < 3; k++) {
          f[s][k] = ad.l[k];
          f[s][3 + k] = ad.th[k];
          f[s][6 + k] = ad.c[k];
          f[s][9 + k] = ww[k];
        }
      }
      for (k = 0; k < 3; k++) {
        acc_l[k] = (f[0][k] - 8 * f[1][k] + 8 * f[2][k] - f[3][k]) / (12 * h);
        acc_t[k] = (f[0][3 + k] - 8 * f[1][3 + k] + 8 * f[2][3 + k] -
                    f[3][3 + k]) / (12 * h);
        acc_c[k] = (f[0][6 + k] - 8 * f[1][6 + k] + 8 * f[2][6 + k] -
                    f[3][6 + k]) / (12 * h);
        dw[k] = (f[0][9 + k] - 8 * f[1][9 + k] + 8 * f[2][9 + k] -
                 f[3][9 + k]) / (12 * h);
      }
      /* nested differences: the inner step 1e-4 leaves ~1e-11 of rounding
         in each rate, which the outer 1/(12 h) stencil amplifies to
         ~1e-8 of the acceleration's scale; TOL_FD (1e-7) is the bound here,
         a wrong term shows at 1e-3 */
      sl = norm3(acc_l);
      st = norm3(acc_t);
      sv = norm3(acc_c);
      sw = norm3(dw);
      for (i = 0; i < 3; i++) {
        CHECK_REL(d->ddl[i], acc_l[i], TOL_FD, sl, "ddl%d pose %d", i, n);
        CHECK_REL(d->ddtheta[i], acc_t[i], TOL_FD, st, "ddtheta%d pose %d", i,
                  n);
        CHECK_REL(d->ac[i], acc_c[i], TOL_FD, sv, "ac%d pose %d", i, n);
        CHECK_REL(d->domega[i], dw[i], TOL_FD, sw, "domega%d pose %d", i, n);
      }
    }
  }
  assert_true(tried > 100);
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(theta_solve_jacobian),
      cmocka_unit_test(constraint_jacobian),
      cmocka_unit_test(cjac_forms_agree),
      cmocka_unit_test(velocity_map),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
