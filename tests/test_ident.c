/*
 * test_ident.c - the regressor (src/ident.c) against the library's own
 * forces, and the estimators (src/ident_fit.c) on synthetic data with
 * known parameters.
 */
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_linalg.h>

#include "testutil.h"

/* Y pi against rps3_inverse's F: the same loads and solve, summed in
   another order (the columns, then the parameters' products): rounding
   of ~20 terms times the lambda system's condition number (< 1e3 on
   these states), ~1e-13 of the terms' scale; 1e-10 is the required
   agreement */
#define TOL_REGRESSOR 1e-10
#define NSTATE 10000

/* a model with every effect, the payload's centre of mass on platform
   axis `axis` (off the axes it has products of inertia the paper
   parameters do not hold) */
static void ident_model(rps3_model *m, int method, int axis, double vreg) {
  int k;
  model_entropy(m);
  for (k = 0; k < 3; k++)
    if (k != axis) m->payload.com[k] = 0.0;
  m->friction.vreg = vreg;
  m->opt.method = (rps3_method)method;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

static void random_state(rps3_data *d, uint64_t *s) {
  d->pose[0] = rnd_uniform(s, -PI, PI);
  d->pose[1] = rnd_uniform(s, 0.05, 0.45);
  d->pose[2] = rnd_uniform(s, 0.18, 0.40);
  d->dpose[0] = rnd_uniform(s, -2.0, 2.0);
  d->dpose[1] = rnd_uniform(s, -0.6, 0.6);
  d->dpose[2] = rnd_uniform(s, -0.2, 0.2);
  d->ddpose[0] = rnd_uniform(s, -8.0, 8.0);
  d->ddpose[1] = rnd_uniform(s, -3.0, 3.0);
  d->ddpose[2] = rnd_uniform(s, -1.0, 1.0);
}

/* Y pi = F at NSTATE random states, for a method and a theta route */
static void regressor_vs_forces(int method, int route) {
  rps3_model m;
  rps3_data *d, *d2;
  uint64_t s = 0x1d3e7ull + (uint64_t)(2 * method + route);
  double pi[RPS3_NPAPER], worst = 0.0;
  int i, r, k, nok = 0;
  ident_model(&m, method, method == 0 ? 2 : 0, route ? 0.0 : 0.05);
  m.opt.theta = (rps3_theta_route)route;
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d2), RPS3_OK);
  assert_int_equal(rps3_paper_params(&m, pi, NULL), RPS3_OK);
  for (i = 0; i < NSTATE; i++) {
    double Y[3][RPS3_NPAPER];
    int st1, st2;
    random_state(d, &s);
    copy_motion(d2, d);
    st1 = rps3_inverse(&m, d);
    st2 = rps3_regressor(&m, d2, Y);
    assert_int_equal(st1, st2);
    if (st1 != RPS3_OK) continue;
    nok++;
    for (r = 0; r < 3; r++) {
      double f = 0.0, scale = 0.0, e;
      for (k = 0; k < RPS3_NPAPER; k++) {
        f += Y[r][k] * pi[k];
        scale += fabs(Y[r][k] * pi[k]);
      }
      e = fabs(f - d->F[r]) / scale;
      if (e > worst) worst = e;
      CHECK_REL(f, d->F[r], TOL_REGRESSOR, scale,
                "method %d route %d state %d row %d", method, route, i, r);
    }
  }
  /* the states are inside the workspace: nearly all of them count */
  assert_true(nok > NSTATE * 9 / 10);
  print_message(
      "method %d route %d: %d states, worst |Y pi - F| / scale "
      "%.2g\n",
      method, route, nok, worst);
  rps3_data_free(d);
  rps3_data_free(d2);
}

static void test_regressor_lagrange(void **state) {
  (void)state;
  regressor_vs_forces(RPS3_LAGRANGE, RPS3_THETA_CLOSED_FORM);
  regressor_vs_forces(RPS3_LAGRANGE, RPS3_THETA_MULTIROOT);
}

static void test_regressor_newton_euler(void **state) {
  (void)state;
  regressor_vs_forces(RPS3_NEWTON_EULER, RPS3_THETA_CLOSED_FORM);
}

/* each column is the force of its parameter alone: a model with only that
   parameter nonzero (and its effect) has F = Y[:, k] pi_k; and columns of
   effects not selected are zero */
static void test_regressor_columns(void **state) {
  rps3_model m, one;
  rps3_data *d, *d1;
  uint64_t s = 77;
  double Y[3][RPS3_NPAPER], pi[RPS3_NPAPER];
  int r, k;
  (void)state;
  ident_model(&m, RPS3_LAGRANGE, 1, 0.0);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d1), RPS3_OK);
  random_state(d, &s);
  copy_motion(d1, d);
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  assert_int_equal(rps3_regressor(&m, d, Y), RPS3_OK);
  /* no force of the earlier call is left */
  assert_true(isnan(d->F[0]) && isnan(d->F_effect[2][1]) &&
              isnan(d->lambda[2]));
  /* pin friction alone */
  one = m;
  one.opt.effects = RPS3_EFF_PIN_FRICTION;
  assert_int_equal(rps3_model_init(&one, NULL), RPS3_OK);
  assert_int_equal(rps3_inverse(&one, d1), RPS3_OK);
  assert_int_equal(rps3_paper_params(&one, pi, NULL), RPS3_OK);
  for (r = 0; r < 3; r++)
    CHECK_REL(Y[r][10] * pi[10] + Y[r][11] * pi[11], d1->F[r], TOL_EXACT, 1e-3,
              "friction row %d", r);
  /* gravity only: the dynamic columns are zero, the others agree */
  {
    double Yg[3][RPS3_NPAPER];
    one = m;
    one.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
    assert_int_equal(rps3_model_init(&one, NULL), RPS3_OK);
    copy_motion(d1, d);
    assert_int_equal(rps3_regressor(&one, d1, Yg), RPS3_OK);
    for (r = 0; r < 3; r++)
      for (k = 2; k < RPS3_NPAPER; k++) assert_true(Yg[r][k] == 0.0);
    for (r = 0; r < 3; r++) {
      assert_true(Yg[r][1] == Y[r][1]);
      assert_true(Yg[r][0] != Y[r][0]); /* inertia left out of M's */
    }
  }
  rps3_data_free(d);
  rps3_data_free(d1);
}

/* the batch is the loop of rps3_regressor, bit for bit; a failed point is
   NaN, named in the message, and the others computed */
static void test_regressor_batch(void **state) {
  enum { N = 57 };
  rps3_model m;
  rps3_data *d, *d1;
  double pose[3 * N], dpose[3 * N], ddpose[3 * N], *Y, theta[3 * N];
  int status[N], i, c, k;
  uint64_t s = 5;
  rps3_batch_in in;
  rps3_batch_out out;
  (void)state;
  ident_model(&m, RPS3_LAGRANGE, 0, 0.01);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d1), RPS3_OK);
  for (i = 0; i < N; i++) {
    random_state(d, &s);
    for (c = 0; c < 3; c++) {
      pose[c * N + i] = d->pose[c];
      dpose[c * N + i] = d->dpose[c];
      ddpose[c * N + i] = d->ddpose[c];
    }
  }
  pose[2 * N + 13] = -0.3; /* below the base: unreachable */
  Y = malloc(sizeof(double) * 3 * RPS3_NPAPER * N);
  assert_non_null(Y);
  memset(&in, 0, sizeof(in));
  memset(&out, 0, sizeof(out));
  in.n = N;
  in.pose = pose;
  in.dpose = dpose;
  in.ddpose = ddpose;
  out.status = status;
  out.theta = theta;
  assert_int_equal(rps3_regressor_batch(&m, d, &in, Y, &out), RPS3_OK);
  assert_int_equal(out.nfail, 1);
  assert_int_equal(out.first_fail, 13);
  assert_int_equal(status[13], RPS3_EREACH);
  assert_non_null(strstr(d->err.msg, "point 13: "));
  for (i = 0; i < N; i++) {
    double Yp[3][RPS3_NPAPER];
    int st;
    for (c = 0; c < 3; c++) {
      d1->pose[c] = pose[c * N + i];
      d1->dpose[c] = dpose[c * N + i];
      d1->ddpose[c] = ddpose[c * N + i];
    }
    st = rps3_regressor(&m, d1, Yp);
    assert_int_equal(st, status[i]);
    for (c = 0; c < 3; c++)
      for (k = 0; k < RPS3_NPAPER; k++) {
        double b = Y[(c * RPS3_NPAPER + k) * N + i];
        if (st == RPS3_OK)
          assert_memory_equal(&b, &Yp[c][k], sizeof(double));
        else
          assert_true(isnan(b) && isnan(Yp[c][k]));
      }
  }
  /* invalid calls compute nothing */
  assert_int_equal(rps3_regressor_batch(&m, d, &in, NULL, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "Y"));
  in.dpose = NULL;
  assert_int_equal(rps3_regressor_batch(&m, d, &in, Y, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "dpose"));
  free(Y);
  rps3_data_free(d);
  rps3_data_free(d1);
}

static void test_regressor_errors(void **state) {
  rps3_model m;
  rps3_data *d;
  double Y[3][RPS3_NPAPER], pi[RPS3_NPAPER];
  rps3_check chk;
  (void)state;
  ident_model(&m, RPS3_LAGRANGE, 2, 0.0);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_regressor(NULL, d, Y), RPS3_EINVAL);
  assert_int_equal(rps3_regressor(&m, NULL, Y), RPS3_EINVAL);
  assert_int_equal(rps3_regressor(&m, d, NULL), RPS3_EINVAL);
  d->pose[0] = 0.3;
  d->pose[1] = 0.2;
  d->pose[2] = (double)NAN;
  assert_int_equal(rps3_regressor(&m, d, Y), RPS3_EINVAL);
  assert_true(isnan(Y[1][4]));
  /* the names and units of the Python package's PAPER_NAMES */
  assert_string_equal(rps3_paper_name(2), "Ipin");
  assert_string_equal(rps3_paper_name(11), "pin.fc");
  assert_string_equal(rps3_paper_unit(7), "kg m^2");
  assert_null(rps3_paper_name(12));
  assert_null(rps3_paper_unit(-1));
  /* a payload off the platform axes is refused by name */
  m.payload.com[0] = 0.01;
  m.payload.com[2] = 0.02;
  assert_int_equal(rps3_paper_params(&m, pi, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "payload.com"));
  rps3_data_free(d);
}

/* ------------------------------------------------------------ estimators */

/* an exciting motion: three sines per pose coordinate (0.1-1 Hz) about a
   mid-workspace pose, as tests/ident_oracle.py's exciting(), sampled
   every dt; the regressor's rows of columns cols[0..p) stacked sample by
   sample (row 3 s + actuator), and the forces of pi through them */
typedef struct {
  size_t n, p;
  double *Y, *F, *F0;
} stack;

static void stack_free(stack *st) {
  free(st->Y);
  free(st->F);
  free(st->F0);
}

static void make_stack(const rps3_model *m, size_t ns, double dt, double scale,
                       uint64_t seed, const int *cols, size_t p, stack *st) {
  static const double amp[3][3] = {
      {1.2, 0.6, 0.3}, {0.12, 0.06, 0.04}, {0.04, 0.02, 0.01}};
  double mean[3], fr[3][3], ph[3][3], pi[RPS3_NPAPER];
  uint64_t s = seed;
  rps3_data *d;
  size_t i, j;
  int c, h, r;
  mean[0] = rnd_uniform(&s, -1.0, 1.0);
  mean[1] = 0.25;
  mean[2] = 0.29;
  for (c = 0; c < 3; c++)
    for (h = 0; h < 3; h++) {
      fr[c][h] = rnd_uniform(&s, 0.1, 1.0);
      ph[c][h] = rnd_uniform(&s, -PI, PI);
    }
  rps3_paper_params(m, pi, NULL);
  assert_int_equal(rps3_data_alloc(m, &d), RPS3_OK);
  st->n = 3 * ns;
  st->p = p;
  st->Y = malloc(sizeof(double) * st->n * p);
  st->F = malloc(sizeof(double) * st->n);
  st->F0 = malloc(sizeof(double) * st->n);
  assert_true(st->Y && st->F && st->F0);
  for (i = 0; i < ns; i++) {
    double t = (double)i * dt, Y[3][RPS3_NPAPER];
    for (c = 0; c < 3; c++) {
      d->pose[c] = mean[c];
      d->dpose[c] = d->ddpose[c] = 0.0;
      for (h = 0; h < 3; h++) {
        double w = 2.0 * PI * fr[c][h], a = amp[c][h] * scale;
        d->pose[c] += a * sin(w * t + ph[c][h]);
        d->dpose[c] += a * w * cos(w * t + ph[c][h]);
        d->ddpose[c] -= a * w * w * sin(w * t + ph[c][h]);
      }
    }
    assert_int_equal(rps3_regressor(m, d, Y), RPS3_OK);
    for (r = 0; r < 3; r++) {
      double f = 0.0;
      for (j = 0; j < p; j++) {
        st->Y[(3 * i + (size_t)r) * p + j] = Y[r][cols[j]];
        f += Y[r][cols[j]] * pi[cols[j]];
      }
      st->F[3 * i + (size_t)r] = st->F0[3 * i + (size_t)r] = f;
    }
  }
  rps3_data_free(d);
}

/* the estimators' view of the first p columns of st */
static void stack_data(const stack *st, size_t p, rps3_ident_data *dt) {
  memset(dt, 0, sizeof(*dt));
  dt->n = st->n;
  dt->p = p;
  dt->Y = st->Y;
  dt->F = st->F;
}

/* a standard normal deviate (Box-Muller) */
static double rnd_normal(uint64_t *s) {
  double u = rnd_uniform(s, 1e-300, 1.0), v = rnd_uniform(s, 0.0, 2.0 * PI);
  return sqrt(-2.0 * log(u)) * cos(v);
}

/* the paper model with friction and a payload on the platform's z axis */
static void truth_model(rps3_model *m, double coulomb) {
  rps3_model_default(m);
  m->M = 0.2381;
  m->m = 0.0917;
  m->link_Ic = 3.17e-4;
  m->payload.mass = 0.0713;
  m->payload.com[2] = 0.0411;
  m->payload.inertia[0] = 1.13e-4;
  m->payload.inertia[1] = 1.71e-4;
  m->payload.inertia[2] = 0.97e-4;
  m->friction.viscous = 0.0137;
  m->friction.coulomb = coulomb;
  m->friction.vreg = 0.01;
  m->opt.effects = RPS3_EFF_ALL;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

/* the paper set without the payload (M, md, Ipin, fv, fc), and with it
   (M left out: the payload's columns hold the disc) */
static const int SET_PLAIN[5] = {0, 1, 2, 10, 11};
static const int SET_PAYLOAD[11] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};

/* exact data: WLS returns the truth to rounding times the condition
   number (measured cond ~1e3 for the payload set: 1e-12 x 1e3 x 10) */
#define TOL_EXACT_FIT 1e-8

static void test_wls_exact(void **state) {
  rps3_model m;
  stack st;
  double pi[RPS3_NPAPER], th[11], ci[22], cov[121];
  rps3_ident_data dt;
  rps3_ident_result res;
  rps3_check chk;
  size_t j;
  (void)state;
  truth_model(&m, 0.0029);
  rps3_paper_params(&m, pi, NULL);
  make_stack(&m, 1000, 0.02, 1.0, 3, SET_PAYLOAD, 11, &st);
  stack_data(&st, 11, &dt);
  memset(&res, 0, sizeof(res));
  res.theta = th;
  res.ci = ci;
  res.cov = cov;
  assert_int_equal(rps3_ident_wls(&dt, NULL, &res, &chk), RPS3_OK);
  print_message("exact WLS: cond %.3g rank %lu\n", res.cond,
                (unsigned long)res.rank);
  for (j = 0; j < 11; j++)
    CHECK_REL(th[j], pi[SET_PAYLOAD[j]], TOL_EXACT_FIT, 1e-6, "parameter %s",
              rps3_paper_name(SET_PAYLOAD[j]));
  assert_int_equal(res.rank, 11);
  assert_int_equal(res.dof, st.n - 11);
  stack_free(&st);
}

/* noisy data, each actuator its own noise level: a Monte Carlo of the
   95 % intervals' coverage and of the two-pass weights' sigma */
#define MC_DRAWS 60
static void test_wls_monte_carlo(void **state) {
  static const double sig[3] = {0.02, 0.05, 0.01}; /* [N] */
  rps3_model m;
  stack st;
  double pi[RPS3_NPAPER], th[5], ci[10], cov[25], z2 = 0.0, sigm[3] = {0};
  rps3_ident_data dt;
  rps3_ident_result res;
  uint64_t s = 99;
  size_t j, r, cover = 0;
  int k;
  (void)state;
  truth_model(&m, 0.0029);
  rps3_paper_params(&m, pi, NULL);
  make_stack(&m, 1000, 0.02, 1.0, 11, SET_PLAIN, 5, &st);
  stack_data(&st, 5, &dt);
  memset(&res, 0, sizeof(res));
  res.theta = th;
  res.ci = ci;
  res.cov = cov;
  for (k = 0; k < MC_DRAWS; k++) {
    for (r = 0; r < st.n; r++) st.F[r] = st.F0[r] + sig[r % 3] * rnd_normal(&s);
    assert_int_equal(rps3_ident_wls(&dt, NULL, &res, NULL), RPS3_OK);
    for (j = 0; j < 5; j++) {
      double e = th[j] - pi[SET_PLAIN[j]];
      /* the intervals and the covariance are one estimate: half an
         interval is t(dof) sqrt(cov_jj), t from GSL's Student t */
      double half = 0.5 * (ci[2 * j + 1] - ci[2 * j]);
      double t = gsl_cdf_tdist_Pinv(0.975, (double)res.dof);
      CHECK_REL(half, t * sqrt(cov[j * 5 + j]), 1e-12, 0.0,
                "interval %lu against the covariance", (unsigned long)j);
      z2 += e * e / cov[j * 5 + j];
      cover +=
          ci[2 * j] <= pi[SET_PLAIN[j]] && pi[SET_PLAIN[j]] <= ci[2 * j + 1];
    }
    for (j = 0; j < 3; j++) sigm[j] += res.sigma[j] / MC_DRAWS;
  }
  z2 /= 5.0 * MC_DRAWS;
  print_message(
      "WLS Monte Carlo: coverage %.3f, mean z^2 %.3f, sigma %.4g "
      "%.4g %.4g\n",
      (double)cover / (5.0 * MC_DRAWS), z2, sigm[0], sigm[1], sigm[2]);
  /* 300 intervals: binomial sd of the coverage 1.3 %; z^2 a chi-square
     mean of 300 terms (sd 0.08) */
  assert_true((double)cover / (5.0 * MC_DRAWS) >= 0.90);
  assert_true(z2 > 0.7 && z2 < 1.3);
  /* sigma of 3000 residuals: 1.3 % sd each, 60 draws averaged */
  for (j = 0; j < 3; j++)
    CHECK_REL(sigm[j], sig[j], 0.01, 0.0, "sigma %lu", (unsigned long)j);
  stack_free(&st);
}

/* all twelve columns: M's is a combination of the payload's, so the rank
   is 11 and the message names them */
static void test_wls_rank_deficient(void **state) {
  static const int all[12] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  static const char *const names[12] = {
      "M",           "md",          "Ipin",        "payload.m",
      "payload.mcx", "payload.mcy", "payload.mcz", "payload.Ixx",
      "payload.Iyy", "payload.Izz", "pin.fv",      "pin.fc"};
  rps3_model m;
  stack st;
  double th[12];
  int flags[12];
  rps3_ident_data dt;
  rps3_ident_result res;
  rps3_check chk;
  (void)state;
  truth_model(&m, 0.0029);
  make_stack(&m, 300, 0.05, 1.0, 3, all, 12, &st);
  stack_data(&st, 12, &dt);
  dt.names = names;
  memset(&res, 0, sizeof(res));
  res.theta = th;
  res.unident = flags;
  assert_int_equal(rps3_ident_wls(&dt, NULL, &res, &chk), RPS3_ESING);
  print_message("%s\n", chk.msg);
  assert_int_equal(res.rank, 11);
  /* the null vector M - payload.m - r^2 (Ixx + Iyy + 2 Izz) / 4 has its
     weight on M and payload.m once the columns have unit norm */
  assert_true(flags[0] && flags[3]);
  assert_false(flags[1] || flags[2] || flags[10] || flags[11]);
  assert_non_null(strstr(chk.msg, "rank 11 < 12"));
  assert_non_null(strstr(chk.msg, " M "));
  assert_non_null(strstr(chk.msg, "payload.m"));
  assert_true(isnan(th[1]));
  /* bad arguments, each named */
  dt.names = NULL;
  dt.p = 0;
  assert_int_equal(rps3_ident_wls(&dt, NULL, &res, &chk), RPS3_EINVAL);
  dt.p = 12;
  st.F[7] = (double)NAN;
  assert_int_equal(rps3_ident_wls(&dt, NULL, &res, &chk), RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "data.F[7]"));
  stack_free(&st);
}

/* the consistent fit: on exact data it returns the truth but for the
   tie-break's pull (reg = 1e-9 of the normalised squared residual), which
   must stay far below what noise does: under 5 % of the standard
   deviation of the WLS estimate at 1 % noise (rps3.ident's criterion for
   its LMI fit); in a Monte Carlo of noisy data every fit is certified
   consistent */
#define TOL_CONSISTENT_BIAS 0.05
static void test_consistent(void **state) {
  rps3_model m;
  stack st;
  double pi[RPS3_NPAPER], th[11], body[20], eig[8], thw[11], cov[121];
  rps3_ident_data dt;
  rps3_ident_fit fit;
  rps3_ident_result res;
  const rps3_ident_layout *pl = rps3_ident_paper_layout();
  /* the paper layout on the payload set: columns renumbered */
  int col[2][10], kind[11], b, k;
  rps3_ident_layout lay;
  uint64_t s = 5;
  rps3_check chk;
  size_t j, r, nwls_bad = 0, nconv = 0;
  int st_c;
  (void)state;
  for (b = 0; b < 2; b++)
    for (k = 0; k < 10; k++) {
      int c = pl->col[b][k];
      col[b][k] = c < 0 ? -1 : c - 1; /* SET_PAYLOAD drops column 0 */
    }
  for (j = 0; j < 11; j++) kind[j] = pl->kind[SET_PAYLOAD[j]];
  lay.nbody = 2;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  truth_model(&m, 0.0);
  rps3_paper_params(&m, pi, NULL);
  make_stack(&m, 1000, 0.02, 0.3, 21, SET_PAYLOAD, 11, &st);
  stack_data(&st, 11, &dt);
  memset(&fit, 0, sizeof(fit));
  fit.theta = th;
  fit.body = body;
  fit.eig = eig;
  k = rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk);
  if (k != RPS3_OK) fail_msg("%s", chk.msg);
  print_message("consistent exact: %d iterations, cost %.3g\n", fit.niter,
                fit.cost);
  assert_true(fit.consistent);
  memset(&res, 0, sizeof(res));
  res.theta = thw;
  res.cov = cov;
  {
    double rms = 0.0;
    for (r = 0; r < st.n; r++) rms += st.F0[r] * st.F0[r] / (double)st.n;
    for (r = 0; r < st.n; r++)
      st.F[r] = st.F0[r] + 0.01 * sqrt(rms) * rnd_normal(&s);
    assert_int_equal(rps3_ident_wls(&dt, NULL, &res, NULL), RPS3_OK);
    for (j = 0; j < 11; j++) {
      double sd = sqrt(cov[j * 11 + j]);
      if (!(fabs(th[j] - pi[SET_PAYLOAD[j]]) <= TOL_CONSISTENT_BIAS * sd))
        fail_msg("parameter %s: %.6g, truth %.6g, WLS sd at 1 %% noise %.3g",
                 rps3_paper_name(SET_PAYLOAD[j]), th[j], pi[SET_PAYLOAD[j]],
                 sd);
    }
  }
  /* noisy: 20 draws, 1 % of the forces' RMS; every one converged and
     consistent, and WLS on the same data is not always (Coulomb 0 in
     truth: the optimum has it at 0, on the boundary, in about half) */
  res.cov = NULL;
  for (k = 0; k < 20; k++) {
    double rms = 0.0;
    for (r = 0; r < st.n; r++) rms += st.F0[r] * st.F0[r] / (double)st.n;
    for (r = 0; r < st.n; r++)
      st.F[r] = st.F0[r] + 0.01 * sqrt(rms) * rnd_normal(&s);
    st_c = rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk);
    if (st_c != RPS3_OK) fail_msg("draw %d: %s", k, chk.msg);
    nconv++;
    /* converged: the optimality measure within opt_tol (1e-6) of the cost
       (or at its 1e-14 floor) */
    assert_true(fit.gap <= 1e-6 * fit.cost + 1e-14);
    assert_true(fit.consistent);
    for (b = 0; b < 2; b++)
      assert_true(eig[4 * b] >= -1e-10 * fabs(eig[4 * b + 3]));
    assert_true(th[9] >= 0.0 && th[10] >= 0.0);
    /* the eigenvalues are the returned bodies' own: their sum is the
       trace of the pseudo-inertia [[tr(I)/2 1 - I, h], [h^T, m]],
       tr(I)/2 + m, from the standard parameters (m, h, Ixx, Ixy, Ixz,
       Iyy, Iyz, Izz) */
    for (b = 0; b < 2; b++) {
      const double *sb = body + 10 * b;
      double tr = 0.5 * (sb[4] + sb[7] + sb[9]) + sb[0];
      double es = eig[4 * b] + eig[4 * b + 1] + eig[4 * b + 2] + eig[4 * b + 3];
      CHECK_REL(es, tr, 1e-9, 0.0, "body %lu: eigenvalues against the trace",
                (unsigned long)b);
    }
    assert_int_equal(rps3_ident_wls(&dt, NULL, &res, NULL), RPS3_OK);
    nwls_bad += thw[10] < 0.0;
  }
  print_message(
      "WLS gave a negative Coulomb coefficient in %lu of 20; the "
      "consistent fit converged in %lu of 20, consistent in 20\n",
      (unsigned long)nwls_bad, (unsigned long)nconv);
  assert_true(nwls_bad > 0);
  assert_int_equal(nconv, 20);
  /* bad layouts, each named */
  col[1][3] = 1; /* column 1 is already the link's Ipin */
  assert_int_equal(rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk),
                   RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "layout.col[1][3]"));
  col[1][3] = 11;
  assert_int_equal(rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk),
                   RPS3_EINVAL);
  col[1][3] = 5;
  kind[4] = 3;
  assert_int_equal(rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk),
                   RPS3_EINVAL);
  assert_non_null(strstr(chk.msg, "layout.kind[4]"));
  kind[4] = 0;
  /* an iteration limit too small: not converged, said so */
  {
    rps3_ident_opts o;
    rps3_ident_opts_default(&o);
    o.max_iter = 1;
    assert_int_equal(rps3_ident_consistent(&dt, &lay, &o, &fit, &chk),
                     RPS3_ENOCONV);
    assert_true(fit.consistent); /* the start, checked */
    assert_non_null(strstr(chk.msg, "iterations"));
    assert_non_null(strstr(chk.msg, "optimality measure"));
    assert_true(fit.gap > o.opt_tol * fit.cost);
    /* a bad opt_tol, named */
    o.max_iter = 2000;
    o.opt_tol = -1.0;
    assert_int_equal(rps3_ident_consistent(&dt, &lay, &o, &fit, &chk),
                     RPS3_EINVAL);
    assert_non_null(strstr(chk.msg, "opt_tol"));
  }
  stack_free(&st);
}

/*
 * reg 0 and a body the data do not see.  Its pseudo-inertia costs
 * nothing anywhere in the cone, so the fit's other parameters are those
 * of the fit without it and the optimality measure must stay finite: a
 * direction of no curvature (h = 0) with a dual violation at rounding
 * level would make the measure's decrease e^2 / (4 h) infinite and the
 * fit never converge.  Three bodies of that kind: none of its parameters
 * a column; its ten columns all zero in Y; and one seen only through a
 * sum (its m and Izz columns equal, a fresh column of the data's scale:
 * their difference's curvature is rounding).  Each converged within
 * opt_tol, consistent, its cost that of the fit without the body (within
 * twice opt_tol, both fits within opt_tol of one optimum) where the body
 * is not seen at all.
 */
#define NX_UNSEEN 10
static void test_consistent_unseen_reg0(void **state) {
  rps3_model m;
  stack st;
  const rps3_ident_layout *pl = rps3_ident_paper_layout();
  const size_t P0 = 11, P = P0 + NX_UNSEEN;
  int col[3][10], kind[11 + NX_UNSEEN], b, k, v;
  double th[11 + NX_UNSEEN], body[30], eig[12], cost0 = 0.0, rms = 0.0;
  double *Y;
  rps3_ident_layout lay;
  rps3_ident_data dt;
  rps3_ident_fit fit;
  rps3_ident_opts o;
  rps3_check chk;
  uint64_t s = 17;
  size_t j, r;
  (void)state;
  for (b = 0; b < 2; b++)
    for (k = 0; k < 10; k++)
      col[b][k] = pl->col[b][k] < 0 ? -1 : pl->col[b][k] - 1;
  for (j = 0; j < P; j++) kind[j] = j < P0 ? pl->kind[SET_PAYLOAD[j]] : 0;
  truth_model(&m, 0.0);
  make_stack(&m, 1000, 0.02, 0.3, 21, SET_PAYLOAD, P0, &st);
  for (r = 0; r < st.n; r++) rms += st.F0[r] * st.F0[r] / (double)st.n;
  for (r = 0; r < st.n; r++)
    st.F[r] = st.F0[r] + 0.01 * sqrt(rms) * rnd_normal(&s);
  Y = malloc(st.n * P * sizeof(double));
  assert_non_null(Y);
  rps3_ident_opts_default(&o);
  o.reg = 0.0;
  memset(&fit, 0, sizeof(fit));
  fit.theta = th;
  fit.body = body;
  fit.eig = eig;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  for (v = 0; v < 4; v++) {
    int st_c;
    /* 0: the fit without the body; 1: a body of no column; 2: its
       columns zero; 3: seen through m + Izz only */
    lay.nbody = v == 0 ? 2 : 3;
    for (k = 0; k < 10; k++)
      col[2][k] = v == 2 ? (int)P0 + k : -1;
    if (v == 3) {
      col[2][0] = (int)P0;
      col[2][9] = (int)P0 + 1;
    }
    memset(&dt, 0, sizeof(dt));
    dt.n = st.n;
    dt.p = v >= 2 ? (v == 2 ? P : P0 + 2) : P0;
    dt.F = st.F;
    dt.Y = Y;
    for (r = 0; r < st.n; r++) {
      double z = st.Y[r * P0] * rnd_uniform(&s, -1.0, 1.0);
      for (j = 0; j < dt.p; j++)
        Y[r * dt.p + j] = j < P0 ? st.Y[r * P0 + j] : v == 3 ? z : 0.0;
    }
    st_c = rps3_ident_consistent(&dt, &lay, &o, &fit, &chk);
    print_message("unseen body %d, reg 0: status %d, %d iterations, gap / "
                  "cost %.2g\n",
                  v, st_c, fit.niter, fit.gap / fit.cost);
    if (st_c != RPS3_OK) fail_msg("case %d: %s", v, chk.msg);
    assert_true(fit.consistent);
    assert_true(fit.gap <= o.opt_tol * fit.cost + 1e-14);
    for (b = 0; b < (int)lay.nbody; b++)
      assert_true(eig[4 * b] >= -o.eig_tol * fabs(eig[4 * b + 3]));
    if (v == 0) cost0 = fit.cost;
    if (v == 1 || v == 2)
      CHECK_REL(fit.cost, cost0, 2.0 * o.opt_tol, 0.0,
                "case %d: the cost against the fit without the body", v);
  }
  free(Y);
  stack_free(&st);
}

/* ------------------------------------------ a boundary optimum by KKT */

/* the standard parameters (m, mcx, mcy, mcz, Ixx, Ixy, Ixz, Iyy, Iyz,
   Izz) of a pseudo-inertia J = [[Sigma, h], [h^T, m]], I = tr(Sigma) 1 -
   Sigma (include/rps3.h), and the gradient g_k = <M, dJ/ds_k> of a
   function of J whose gradient in J is M */
static void std_of_J(const double J[4][4], double *s) {
  /* from the definition: m = J_44, m c = J_{1:3,4}, I = tr(Sigma) 1 -
     Sigma, in the order m, mcx, mcy, mcz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz */
  static const int row[6] = {0, 0, 0, 1, 1, 2}, col[6] = {0, 1, 2, 1, 2, 2};
  const double tr = J[0][0] + J[1][1] + J[2][2];
  int k;
  s[0] = J[3][3];
  for (k = 0; k < 3; k++) s[1 + k] = J[k][3];
  for (k = 0; k < 6; k++)
    s[4 + k] = (row[k] == col[k] ? tr : 0.0) - J[row[k]][col[k]];
}
static void grad_in_std(const double M[4][4], double *g) {
  g[0] = M[3][3];
  g[1] = 2.0 * M[0][3];
  g[2] = 2.0 * M[1][3];
  g[3] = 2.0 * M[2][3];
  g[4] = 0.5 * (-M[0][0] + M[1][1] + M[2][2]);
  g[5] = -2.0 * M[0][1];
  g[6] = -2.0 * M[0][2];
  g[7] = 0.5 * (M[0][0] - M[1][1] + M[2][2]);
  g[8] = -2.0 * M[1][2];
  g[9] = 0.5 * (M[0][0] + M[1][1] - M[2][2]);
}

/* the objective of rps3_ident_consistent from the rows: |F - Y pi|^2 /
   |F|^2 + reg sum_b tr J_b, the bodies' 10 parameters in pi's first 10
   nb columns */
static double kkt_objective(const double *Y, const double *F, size_t n,
                            size_t p, size_t nb, const double *pi, double reg) {
  double rss = 0.0, ff = 0.0, tr = 0.0;
  size_t r, j, b;
  for (r = 0; r < n; r++) {
    double e = F[r];
    for (j = 0; j < p; j++) e -= Y[r * p + j] * pi[j];
    rss += e * e;
    ff += F[r] * F[r];
  }
  for (b = 0; b < nb; b++) {
    const double *s = pi + 10 * b;
    tr += s[0] + 0.5 * (s[4] + s[7] + s[9]);
  }
  return rss / ff + reg * tr;
}

/*
 * Data built so that the optimum is known and lies on the boundary of the
 * cone: J_0 of rank 3, J_1 of rank 2, a >= 0 column at 0 with a positive
 * gradient, another >= 0 column and a free one inside.  With the gradient
 * the KKT conditions ask for (G_b = gamma times the projector on J_b's
 * null space, positive semidefinite with G_b J_b = 0; g_j > 0 at the
 * column at 0, 0 elsewhere) the residual r = Y (Y^T Y)^-1 w with w = g
 * |F|^2 / 2 gives exactly that gradient at pi*, and a part of F
 * orthogonal to Y's columns sets |F|^2 without changing it.  Y has full
 * column rank, so pi* is the only optimum.  Required: the C fit's
 * objective within TOL_KKT_OBJ of pi*'s (relative; opt_tol's 1e-6),
 * |Y (theta - pi*)|^2 / |F|^2 at most twice that excess (strict
 * convexity in Y pi), the column at 0 and the null-space eigenvalues
 * back at 0 to the same order.
 */
#define TOL_KKT_OBJ 1e-6
static void test_consistent_boundary_kkt(void **state) {
  enum { N = 400, P = 23, NB = 2 };
  static const double lam[NB][4] = {{0.0, 0.0213, 0.0371, 0.1937},
                                    {0.0, 0.0, 0.0587, 0.1429}};
  static const double gam[NB][4] = {{0.0347, 0.0, 0.0, 0.0},
                                    {0.0291, 0.0533, 0.0, 0.0}};
  static const double gcol[3] = {0.0173, 0.0, 0.0}; /* columns 20..22 */
  static const double picol[3] = {0.0, 0.0419, -0.0277};
  double *Y = malloc(sizeof(double) * N * P), *F = malloc(sizeof(double) * N);
  double *q = malloc(sizeof(double) * N), pi[P], g[P], w[P], th[P],
         body[10 * NB], eig[4 * NB], S, f0 = 0.0, qq = 0.0, phi_s, phi_c,
         dev = 0.0, ff = 0.0;
  const double reg = 1e-9;
  gsl_matrix *A = gsl_matrix_alloc(P, P);
  gsl_vector *x = gsl_vector_alloc(P), *bv = gsl_vector_alloc(P);
  int col[NB][10], kind[P], st, b, i, k, l;
  size_t r, j;
  uint64_t s = 17;
  rps3_ident_layout lay;
  rps3_ident_data dt;
  rps3_ident_fit fit;
  rps3_check chk;
  (void)state;
  assert_non_null(Y);
  assert_non_null(F);
  assert_non_null(q);
  for (r = 0; r < N; r++)
    for (j = 0; j < P; j++)
      Y[r * P + j] = rnd_normal(&s) * (0.37 + 0.11 * (double)(j % 7));
  /* each body: a random orthonormal basis Q (Gram-Schmidt), J* = Q diag
     lam Q^T, G* = Q diag gam Q^T */
  for (b = 0; b < NB; b++) {
    double Q[4][4], J[4][4], M[4][4];
    for (k = 0; k < 4; k++) {
      for (i = 0; i < 4; i++) Q[i][k] = rnd_normal(&s);
      for (l = 0; l < k; l++) {
        double d = 0.0;
        for (i = 0; i < 4; i++) d += Q[i][k] * Q[i][l];
        for (i = 0; i < 4; i++) Q[i][k] -= d * Q[i][l];
      }
      {
        double nn = 0.0;
        for (i = 0; i < 4; i++) nn += Q[i][k] * Q[i][k];
        for (i = 0; i < 4; i++) Q[i][k] /= sqrt(nn);
      }
    }
    for (i = 0; i < 4; i++)
      for (l = 0; l < 4; l++) {
        J[i][l] = M[i][l] = 0.0;
        for (k = 0; k < 4; k++) {
          J[i][l] += Q[i][k] * lam[b][k] * Q[l][k];
          M[i][l] += Q[i][k] * gam[b][k] * Q[l][k];
        }
      }
    /* the residual's share of G is G* minus the trace term's reg 1 */
    for (i = 0; i < 4; i++) M[i][i] -= reg;
    std_of_J((const double(*)[4])J, pi + 10 * b);
    grad_in_std((const double(*)[4])M, g + 10 * b);
    for (k = 0; k < 10; k++) col[b][k] = 10 * b + k;
  }
  for (k = 0; k < 3; k++) {
    pi[20 + k] = picol[k];
    g[20 + k] = gcol[k];
  }
  for (j = 0; j < P; j++) kind[j] = j == 20 || j == 21;
  /* |F|^2 = S: r = Y A^-1 w, w = g S / 2, F = Y pi* - r + q, q orthogonal
     to Y's columns */
  for (r = 0; r < N; r++) {
    double e = 0.0;
    for (j = 0; j < P; j++) e += Y[r * P + j] * pi[j];
    f0 += e * e;
  }
  S = 4.0 * f0;
  for (i = 0; i < P; i++)
    for (l = 0; l < P; l++) {
      double a = 0.0;
      for (r = 0; r < N; r++) a += Y[r * P + (size_t)i] * Y[r * P + (size_t)l];
      gsl_matrix_set(A, (size_t)i, (size_t)l, a);
    }
  assert_int_equal(gsl_linalg_cholesky_decomp1(A), GSL_SUCCESS);
  for (j = 0; j < P; j++) gsl_vector_set(bv, j, w[j] = 0.5 * g[j] * S);
  gsl_linalg_cholesky_solve(A, bv, x);
  for (r = 0; r < N; r++) {
    double e = 0.0;
    for (j = 0; j < P; j++) e += Y[r * P + j] * (pi[j] - gsl_vector_get(x, j));
    F[r] = e;
    q[r] = rnd_normal(&s);
  }
  /* q minus its projection on Y's columns */
  for (j = 0; j < P; j++) {
    double a = 0.0;
    for (r = 0; r < N; r++) a += Y[r * P + j] * q[r];
    gsl_vector_set(bv, j, a);
  }
  gsl_linalg_cholesky_solve(A, bv, x);
  for (r = 0; r < N; r++) {
    for (j = 0; j < P; j++) q[r] -= Y[r * P + j] * gsl_vector_get(x, j);
    qq += q[r] * q[r];
    ff += F[r] * F[r];
  }
  assert_true(ff < S);
  for (r = 0; r < N; r++) F[r] += q[r] * sqrt((S - ff) / qq);
  memset(&dt, 0, sizeof(dt));
  dt.n = N;
  dt.p = P;
  dt.Y = Y;
  dt.F = F;
  lay.nbody = NB;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  memset(&fit, 0, sizeof(fit));
  fit.theta = th;
  fit.body = body;
  fit.eig = eig;
  st = rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk);
  if (st != RPS3_OK) fail_msg("%s", chk.msg);
  phi_s = kkt_objective(Y, F, N, P, NB, pi, reg);
  phi_c = kkt_objective(Y, F, N, P, NB, th, reg);
  for (r = 0; r < N; r++) {
    double e = 0.0;
    for (j = 0; j < P; j++) e += Y[r * P + j] * (th[j] - pi[j]);
    dev += e * e / S;
  }
  print_message(
      "boundary by KKT: %d iterations, objective C / optimum - 1 = "
      "%.2e, |Y dpi|^2 / |F|^2 %.2e, column at 0: %.2e, "
      "null eigenvalues %.2e %.2e %.2e\n",
      fit.niter, phi_c / phi_s - 1.0, dev, th[20], eig[0], eig[4], eig[5]);
  assert_true(fabs(phi_c - phi_s) <= TOL_KKT_OBJ * phi_s);
  assert_true(dev <= 2.0 * TOL_KKT_OBJ * phi_s);
  assert_true(fit.consistent);
  /* at the boundary: the column at 0 and the eigenvalues of the null
     spaces (ascending: one of body 0, two of body 1) are small against
     the bodies' largest */
  assert_true(th[20] >= 0.0 && th[20] <= sqrt(TOL_KKT_OBJ) * picol[1]);
  assert_true(fabs(eig[0]) <= sqrt(TOL_KKT_OBJ) * eig[3]);
  assert_true(fabs(eig[4]) <= sqrt(TOL_KKT_OBJ) * eig[7]);
  assert_true(fabs(eig[5]) <= sqrt(TOL_KKT_OBJ) * eig[7]);
  gsl_matrix_free(A);
  gsl_vector_free(x);
  gsl_vector_free(bv);
  free(Y);
  free(F);
  free(q);
}

/*
 * The general model's 76 parameters (the seven bodies' standard ones and
 * the pins' friction) of the paper's bodies written as general ones: the
 * links rods (a pseudo-inertia of rank 2), the pistons massless (0), the
 * pins' Coulomb coefficient 0, so the optimum lies on the boundary of the
 * consistent set, where the plain Cholesky stage alone crawls along a
 * face (here: not converged in 2,000 iterations) and the barrier stage
 * takes tens.  2 s of a sine trajectory at 1 kHz, 1 % noise.  Required:
 * converged within opt_tol, consistent, within GENERAL_MAX_ITER
 * iterations (measured 99 in all), and its objective (from the rows) at
 * most the truth's, a consistent point the optimum cannot be above.
 */
#define GENERAL_MAX_ITER 150
#define GENERAL_P 76
static void test_consistent_general_boundary(void **state) {
  rps3_model m;
  rps3_data *d;
  rps3_traj tr;
  rps3_ident_layout lay;
  rps3_ident_data dt;
  rps3_ident_fit fit;
  rps3_check chk;
  const size_t npt = 2000, n = 3 * npt;
  double *Y = malloc(n * GENERAL_P * sizeof(double));
  double *F = malloc(n * sizeof(double)), pi[RPS3_NSTD], th[GENERAL_P],
         body[10 * RPS3_NBODY], eig[4 * RPS3_NBODY], truth[GENERAL_P],
         rms = 0.0, phi_t, phi_c;
  int col[RPS3_NBODY][10], kind[GENERAL_P], b, k, st_c;
  uint64_t s = 29;
  size_t i, j, r;
  (void)state;
  assert_non_null(Y);
  assert_non_null(F);
  truth_model(&m, 0.0);
  assert_int_equal(rps3_std_params(&m, pi), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  traj_random(&tr, &s);
  /* columns: the bodies' 70, then the pins' 6 (standard 76..81) */
  for (j = 0; j < GENERAL_P; j++) {
    truth[j] = pi[j < 70 ? j : j + 6];
    kind[j] = j < 70 ? RPS3_IDENT_FREE : RPS3_IDENT_NONNEG;
  }
  for (i = 0; i < npt; i++) {
    double Ys[3][RPS3_NSTD];
    assert_int_equal(rps3_traj_eval(&m, &tr, 1e-3 * (double)i, d->pose,
                                     d->dpose, d->ddpose),
                     RPS3_OK);
    assert_int_equal(rps3_regressor_std(&m, d, Ys), RPS3_OK);
    for (r = 0; r < 3; r++) {
      double f = 0.0;
      for (j = 0; j < GENERAL_P; j++) {
        Y[(3 * i + r) * GENERAL_P + j] = Ys[r][j < 70 ? j : j + 6];
        f += Ys[r][j < 70 ? j : j + 6] * truth[j];
      }
      F[3 * i + r] = f;
      rms += f * f / (double)n;
    }
  }
  for (r = 0; r < n; r++) F[r] += 0.01 * sqrt(rms) * rnd_normal(&s);
  for (b = 0; b < RPS3_NBODY; b++)
    for (k = 0; k < 10; k++) col[b][k] = 10 * b + k;
  lay.nbody = RPS3_NBODY;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  memset(&dt, 0, sizeof(dt));
  dt.n = n;
  dt.p = GENERAL_P;
  dt.Y = Y;
  dt.F = F;
  memset(&fit, 0, sizeof(fit));
  fit.theta = th;
  fit.body = body;
  fit.eig = eig;
  st_c = rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk);
  phi_t = kkt_objective(Y, F, n, GENERAL_P, RPS3_NBODY, truth, 1e-9);
  phi_c = kkt_objective(Y, F, n, GENERAL_P, RPS3_NBODY, th, 1e-9);
  print_message("general boundary: %d iterations, gap / cost %.2g, "
                "objective C / truth's - 1 = %.3g\n",
                fit.niter, fit.gap / fit.cost, phi_c / phi_t - 1.0);
  if (st_c != RPS3_OK) fail_msg("%s", chk.msg);
  assert_true(fit.consistent);
  assert_true(fit.gap <= 1e-6 * fit.cost + 1e-14);
  assert_true(fit.niter <= GENERAL_MAX_ITER);
  assert_true(phi_c <= phi_t);
  for (b = 0; b < RPS3_NBODY; b++)
    assert_true(eig[4 * b] >= -1e-10 * fabs(eig[4 * b + 3]));
  for (j = 70; j < GENERAL_P; j++) assert_true(th[j] >= 0.0);
  rps3_data_free(d);
  free(Y);
  free(F);
}

/* the sizes of the targets, timed (reported, not asserted) */
static void test_timing(void **state) {
  rps3_model m;
  stack st;
  double th[11], body[20];
  rps3_ident_data dt;
  rps3_ident_result res;
  rps3_ident_fit fit;
  struct timespec t0, t1, t2;
  const rps3_ident_layout *pl = rps3_ident_paper_layout();
  int col[2][10], kind[11], b, k;
  rps3_ident_layout lay;
  size_t j;
  (void)state;
  for (b = 0; b < 2; b++)
    for (k = 0; k < 10; k++)
      col[b][k] = pl->col[b][k] < 0 ? -1 : pl->col[b][k] - 1;
  for (j = 0; j < 11; j++) kind[j] = pl->kind[SET_PAYLOAD[j]];
  lay.nbody = 2;
  lay.col = (const int(*)[10])col;
  lay.kind = kind;
  truth_model(&m, 0.0029);
  make_stack(&m, 10000, 0.005, 1.0, 8, SET_PAYLOAD, 11, &st);
  stack_data(&st, 11, &dt);
  memset(&res, 0, sizeof(res));
  res.theta = th;
  memset(&fit, 0, sizeof(fit));
  fit.theta = th;
  fit.body = body;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  assert_int_equal(rps3_ident_wls(&dt, NULL, &res, NULL), RPS3_OK);
  clock_gettime(CLOCK_MONOTONIC, &t1);
  {
    rps3_check chk;
    int st_c = rps3_ident_consistent(&dt, &lay, NULL, &fit, &chk);
    if (st_c != RPS3_OK) fail_msg("%s", chk.msg);
  }
  clock_gettime(CLOCK_MONOTONIC, &t2);
  print_message(
      "timing: WLS of %lu rows x 11 %.3f s (target 0.5 s), "
      "consistent fit %.3f s (target 1 s, %d iterations)\n",
      (unsigned long)st.n,
      (double)(t1.tv_sec - t0.tv_sec) +
          1e-9 * (double)(t1.tv_nsec - t0.tv_nsec),
      (double)(t2.tv_sec - t1.tv_sec) +
          1e-9 * (double)(t2.tv_nsec - t1.tv_nsec),
      fit.niter);
  stack_free(&st);
}

/* ------------------------------------------------ no allocation per point */

#ifndef RPS3_SANITIZE
#include "alloc_count.h"

/* the regressor, point by point (both theta routes) and in a batch,
   allocates nothing; the estimators do (the counter sees them) */
static void test_regressor_allocates_nothing(void **state) {
  enum { N = 2000 };
  rps3_model m;
  rps3_data *d;
  double Y[3][RPS3_NPAPER], *Yb, pose[3 * N], dpose[3 * N], ddpose[3 * N];
  int status[N], route, i, c;
  uint64_t s = 3;
  rps3_batch_in in;
  rps3_batch_out out;
  stack st;
  double th[5];
  rps3_ident_data dt;
  rps3_ident_result res;
  (void)state;
  for (route = 0; route < 2; route++) {
    ident_model(&m, RPS3_LAGRANGE, 2, 0.01);
    m.opt.theta = (rps3_theta_route)route;
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    count_start();
    for (i = 0; i < N; i++) {
      random_state(d, &s);
      rps3_regressor(&m, d, Y);
    }
    count_stop();
    assert_int_equal(n_alloc, 0);
    rps3_data_free(d);
  }
  for (i = 0; i < N; i++) {
    rps3_data tmp;
    random_state(&tmp, &s);
    for (c = 0; c < 3; c++) {
      pose[c * N + i] = tmp.pose[c];
      dpose[c * N + i] = tmp.dpose[c];
      ddpose[c * N + i] = tmp.ddpose[c];
    }
  }
  Yb = malloc(sizeof(double) * 3 * RPS3_NPAPER * N);
  assert_non_null(Yb);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  memset(&in, 0, sizeof(in));
  memset(&out, 0, sizeof(out));
  in.n = N;
  in.pose = pose;
  in.dpose = dpose;
  in.ddpose = ddpose;
  out.status = status;
  count_start();
  assert_int_equal(rps3_regressor_batch(&m, d, &in, Yb, &out), RPS3_OK);
  count_stop();
  assert_int_equal(n_alloc, 0);
  free(Yb);
  rps3_data_free(d);
  /* the counter works: WLS allocates its GSL workspaces */
  truth_model(&m, 0.0029);
  make_stack(&m, 100, 0.05, 1.0, 3, SET_PLAIN, 5, &st);
  stack_data(&st, 5, &dt);
  memset(&res, 0, sizeof(res));
  res.theta = th;
  count_start();
  assert_int_equal(rps3_ident_wls(&dt, NULL, &res, NULL), RPS3_OK);
  count_stop();
  assert_true(n_alloc > 0);
  stack_free(&st);
}
#endif

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_regressor_lagrange),
      cmocka_unit_test(test_regressor_newton_euler),
      cmocka_unit_test(test_regressor_columns),
      cmocka_unit_test(test_regressor_batch),
      cmocka_unit_test(test_regressor_errors),
      cmocka_unit_test(test_wls_exact),
      cmocka_unit_test(test_wls_monte_carlo),
      cmocka_unit_test(test_wls_rank_deficient),
      cmocka_unit_test(test_consistent),
      cmocka_unit_test(test_consistent_unseen_reg0),
      cmocka_unit_test(test_consistent_boundary_kkt),
      cmocka_unit_test(test_consistent_general_boundary),
      cmocka_unit_test(test_timing),
#ifndef RPS3_SANITIZE
      cmocka_unit_test(test_regressor_allocates_nothing),
#endif
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
