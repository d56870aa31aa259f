/*
 * test_batch.c - the batch entry points against the per-point loop they
 * stand for: every output bitwise equal (memcmp of the doubles) to what the
 * stage function leaves in a second workspace driven point by point, for
 * both formulations, the closed-form and the warm multiroot theta, with
 * failing points mixed in (recorded, NaN outputs, the others computed).
 * These are the configurations the vectorised kernel does not serve (all
 * six effects, Newton-Euler, multiroot); its own agreement with the loop
 * is tests/test_batch_kernel.c.  Then the call-level errors, which compute
 * nothing.
 */
#include <float.h>
#include <stdlib.h>

#include "testutil.h"

#define N 1500

/* a batch's arrays, component-major, on the heap of the test */
typedef struct {
  double pose[3 * N], dpose[3 * N], ddpose[3 * N], lin[3 * N], guess[3 * N];
  int status[N], warn[N], niter[N];
  double opose[3 * N], l[3 * N], theta[3 * N], F[3 * N];
  double F_effect[RPS3_NEFFECT * 3 * N], lambda[3 * N], cond[N], eres[N];
  double trans[N], dl[3 * N], ddl[3 * N], cpos[3 * N], escale[N], sres[N];
} arrays;

#define AT(a, c, i) ((a)[(size_t)(c) * N + (size_t)(i)])

/* bitwise equality of two doubles (NaN == NaN of the same bits) */
#define ASSERT_SAME(got, want, ...)                                           \
  do {                                                                        \
    double g_ = (got), w_ = (want);                                           \
    if (memcmp(&g_, &w_, sizeof(double)) != 0) {                              \
      print_error("got %.17g want %.17g: ", g_, w_);                          \
      print_error(__VA_ARGS__);                                               \
      print_error("\n");                                                      \
      fail();                                                                 \
    }                                                                         \
  } while (0)

/* the points: a random smooth trajectory, with some unreachable (below the
   base) and some non-finite poses among them; returns how many are bad */
static int make_points(const rps3_model *m, arrays *a, uint64_t seed) {
  rps3_traj tr;
  double p[3], dp[3], ddp[3];
  int i, c, bad = 0;
  traj_random(&tr, &seed);
  for (i = 0; i < N; i++) {
    double t = tr.sine.duration * (double)i / (double)(N - 1);
    assert_int_equal(rps3_traj_eval(m, &tr, t, p, dp, ddp), RPS3_OK);
    if (i % 97 == 13) { p[2] = -0.0371; bad++; }      /* unreachable */
    else if (i % 211 == 5) { p[1] = (double)NAN; bad++; } /* not finite */
    for (c = 0; c < 3; c++) {
      AT(a->pose, c, i) = p[c];
      AT(a->dpose, c, i) = dp[c];
      AT(a->ddpose, c, i) = ddp[c];
    }
  }
  return bad;
}

static rps3_batch_out outputs(arrays *a) {
  rps3_batch_out out;
  memset(&out, 0, sizeof(out));
  out.status = a->status;
  out.warn = a->warn;
  out.niter = a->niter;
  out.pose = a->opose;
  out.l = a->l;
  out.theta = a->theta;
  out.F = a->F;
  out.F_effect = a->F_effect;
  out.lambda = a->lambda;
  out.cond = a->cond;
  out.energy_residual = a->eres;
  out.transmission = a->trans;
  out.dl = a->dl;
  out.ddl = a->ddl;
  out.c = a->cpos;
  out.energy_scale = a->escale;
  out.solve_resid = a->sres;
  return out;
}

/* rps3_inverse_batch against rps3_inverse point by point */
static void inverse_like_loop(rps3_theta_route theta, rps3_method method,
                              int effects, int certify) {
  rps3_model m;
  rps3_data *db = NULL, *dl = NULL;
  arrays *a = calloc(1, sizeof(*a));
  rps3_batch_in in;
  rps3_batch_out out;
  int i, c, k, bad, nfail = 0, first = -1;
  assert_non_null(a);
  model_entropy(&m);
  m.opt.theta = theta;
  m.opt.method = method;
  m.opt.effects = effects;
  m.opt.outputs = (certify) ? (m.opt.outputs | RPS3_OUT_CERTIFY)
      : (m.opt.outputs & ~RPS3_OUT_CERTIFY);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &db), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &dl), RPS3_OK);
  bad = make_points(&m, a, 0x5eed0 + (uint64_t)(theta * 2 + method));

  memset(&in, 0, sizeof(in));
  in.n = N;
  in.pose = a->pose;
  in.dpose = a->dpose;
  in.ddpose = a->ddpose;
  out = outputs(a);
  assert_int_equal(rps3_inverse_batch(&m, db, &in, &out), RPS3_OK);

  for (i = 0; i < N; i++) {
    int s;
    for (c = 0; c < 3; c++) {
      dl->pose[c] = AT(a->pose, c, i);
      dl->dpose[c] = AT(a->dpose, c, i);
      dl->ddpose[c] = AT(a->ddpose, c, i);
    }
    s = rps3_inverse(&m, dl);
    assert_int_equal(a->status[i], s);
    if (s != RPS3_OK) {
      if (nfail++ == 0) first = i;
      for (c = 0; c < 3; c++) {
        assert_true(isnan(AT(a->F, c, i)));
        assert_true(isnan(AT(a->theta, c, i)));
      }
      assert_true(isnan(a->cond[i]) && isnan(a->trans[i]) &&
                  isnan(a->escale[i]) && isnan(a->sres[i]));
      for (c = 0; c < 3; c++)
        assert_true(isnan(AT(a->dl, c, i)) && isnan(AT(a->ddl, c, i)) &&
                    isnan(AT(a->cpos, c, i)));
      continue;
    }
    assert_int_equal(a->warn[i], dl->warn);
    assert_int_equal(a->niter[i], dl->solve_niter);
    for (c = 0; c < 3; c++) {
      ASSERT_SAME(AT(a->F, c, i), dl->F[c], "F[%d] of point %d", c, i);
      ASSERT_SAME(AT(a->l, c, i), dl->l[c], "l[%d] of point %d", c, i);
      ASSERT_SAME(AT(a->theta, c, i), dl->theta[c], "theta %d/%d", c, i);
      ASSERT_SAME(AT(a->lambda, c, i),
                  dl->has_lambda ? dl->lambda[c] : (double)NAN,
                  "lambda[%d] of point %d", c, i);
      for (k = 0; k < RPS3_NEFFECT; k++)
        ASSERT_SAME(AT(a->F_effect, 3 * k + c, i), dl->F_effect[k][c],
                    "F_effect[%d][%d] of point %d", k, c, i);
    }
    ASSERT_SAME(a->cond[i], dl->cond, "cond of point %d", i);
    ASSERT_SAME(a->eres[i], dl->energy_residual, "residual of point %d", i);
    ASSERT_SAME(a->trans[i], dl->transmission, "transmission of point %d", i);
    ASSERT_SAME(a->escale[i], dl->energy_scale, "scale of point %d", i);
    ASSERT_SAME(a->sres[i], dl->solve_resid, "solve_resid of point %d", i);
    for (c = 0; c < 3; c++) {
      int vel = (dl->stage & RPS3_STAGE_VEL) != 0;
      int acc = (dl->stage & RPS3_STAGE_ACC) != 0;
      ASSERT_SAME(AT(a->dl, c, i), vel ? dl->dl[c] : (double)NAN,
                  "dl[%d] of point %d", c, i);
      ASSERT_SAME(AT(a->ddl, c, i), acc ? dl->ddl[c] : (double)NAN,
                  "ddl[%d] of point %d", c, i);
      ASSERT_SAME(AT(a->cpos, c, i), dl->c[c], "c[%d] of point %d", c, i);
    }
  }
  /* the failures are those planted, and the first one is named */
  assert_int_equal(nfail, bad);
  assert_int_equal((int)out.nfail, bad);
  assert_int_equal((int)out.first_fail, first);
  {
    char want[32];
    snprintf(want, sizeof want, "point %d: ", first);
    assert_true(strncmp(db->err.msg, want, strlen(want)) == 0);
  }
  rps3_data_free(db);
  rps3_data_free(dl);
  free(a);
}

static void closed_form_lagrange(void **state) {
  (void)state;
  inverse_like_loop(RPS3_THETA_CLOSED_FORM, RPS3_LAGRANGE, RPS3_EFF_ALL, 1);
}

static void closed_form_newton_euler(void **state) {
  (void)state;
  inverse_like_loop(RPS3_THETA_CLOSED_FORM, RPS3_NEWTON_EULER, RPS3_EFF_ALL,
                    1);
}

static void multiroot_lagrange(void **state) {
  (void)state;
  inverse_like_loop(RPS3_THETA_MULTIROOT, RPS3_LAGRANGE, RPS3_EFF_DEFAULT, 0);
}

/* a static selection without the certificate reads no rates: NULL rates
   are accepted, and the forces are the loop's with zero rates (the
   kernel's selection: to its tolerance, 8 eps cond of the force scale,
   tests/test_batch_kernel.c) */
static void static_without_rates(void **state) {
  rps3_model m;
  rps3_data *db = NULL, *dl = NULL;
  arrays *a = calloc(1, sizeof(*a));
  rps3_batch_in in;
  rps3_batch_out out;
  int i, c;
  (void)state;
  assert_non_null(a);
  model_entropy(&m);
  m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
  m.opt.outputs &= ~RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &db), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &dl), RPS3_OK);
  make_points(&m, a, 0xab5);
  memset(&in, 0, sizeof(in));
  in.n = N;
  in.pose = a->pose;
  out = outputs(a);
  assert_int_equal(rps3_inverse_batch(&m, db, &in, &out), RPS3_OK);
  for (i = 0; i < N; i++) {
    for (c = 0; c < 3; c++) dl->pose[c] = AT(a->pose, c, i);
    assert_int_equal(a->status[i], rps3_inverse(&m, dl));
    for (c = 0; c < 3 && a->status[i] == RPS3_OK; c++)
      CHECK_REL(AT(a->F, c, i), dl->F[c], 8.0 * DBL_EPSILON * dl->cond,
                fabs(dl->F_effect[0][c]) + fabs(dl->F_effect[1][c]),
                "F[%d] of point %d", c, i);
  }
  rps3_data_free(db);
  rps3_data_free(dl);
  free(a);
}

/* rps3_ik_batch against rps3_ik; rps3_fk_batch against rps3_fk, warm from
   the previous point and from an explicit guess, and the round trip */
static void ik_and_fk_like_loop(void **state) {
  rps3_model m, warm;
  rps3_data *db = NULL, *dl = NULL;
  arrays *a = calloc(1, sizeof(*a));
  rps3_batch_in in;
  rps3_batch_out out;
  int i, c, pass, bad;
  (void)state;
  assert_non_null(a);
  model_entropy(&m);
  m.opt.warm_start = 0; /* so that a guess must override the model */
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  warm = m;
  warm.opt.warm_start = 1;
  assert_int_equal(rps3_data_alloc(&m, &db), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &dl), RPS3_OK);
  bad = make_points(&m, a, 0x1c);

  memset(&in, 0, sizeof(in));
  in.n = N;
  in.pose = a->pose;
  out = outputs(a);
  assert_int_equal(rps3_ik_batch(&m, db, &in, &out), RPS3_OK);
  assert_int_equal((int)out.nfail, bad);
  for (i = 0; i < N; i++) {
    for (c = 0; c < 3; c++) dl->pose[c] = AT(a->pose, c, i);
    assert_int_equal(a->status[i], rps3_ik(&m, dl));
    for (c = 0; c < 3 && a->status[i] == RPS3_OK; c++) {
      ASSERT_SAME(AT(a->l, c, i), dl->l[c], "l[%d] of point %d", c, i);
      ASSERT_SAME(AT(a->theta, c, i), dl->theta[c], "theta %d/%d", c, i);
    }
  }

  /* the lengths (failed points keep their NaN: fk must record them too),
     and as guess the exact theta nudged by a high-entropy offset */
  for (i = 0; i < 3 * N; i++) {
    a->lin[i] = a->l[i];
    a->guess[i] = a->theta[i] + 0.0173 * (i % 3 == 1 ? -1.0 : 1.0);
  }
  for (pass = 0; pass < 2; pass++) {
    const rps3_model *ref = pass == 0 ? &m : &warm;
    memset(&in, 0, sizeof(in));
    in.n = N;
    in.l = a->lin;
    in.guess = pass == 0 ? NULL : a->guess;
    out = outputs(a);
    rps3_data_reset(db);
    rps3_data_reset(dl);
    assert_int_equal(rps3_fk_batch(&m, db, &in, &out), RPS3_OK);
    assert_int_equal((int)out.nfail, bad);
    for (i = 0; i < N; i++) {
      int s;
      for (c = 0; c < 3; c++) {
        dl->l[c] = AT(a->lin, c, i);
        if (pass == 1) dl->theta[c] = AT(a->guess, c, i);
      }
      if (pass == 1) dl->have_theta = 1;
      s = rps3_fk(ref, dl);
      if (isnan(AT(a->lin, 0, i))) {
        assert_int_equal(a->status[i], RPS3_EINVAL);
        continue;
      }
      assert_int_equal(a->status[i], s);
      assert_int_equal(s, RPS3_OK);
      assert_int_equal(a->niter[i], dl->solve_niter);
      for (c = 0; c < 3; c++) {
        ASSERT_SAME(AT(a->opose, c, i), dl->pose[c], "pose %d/%d", c, i);
        ASSERT_SAME(AT(a->theta, c, i), dl->theta[c], "theta %d/%d", c, i);
        /* round trip: ik then fk gives the pose back.  The theta solve
           stops at |f| <= opt.tol = 1e-12 (dimensionless), which moves the
           pose by up to cond(df/dtheta) ~ 100 times that: 1e-10 (seen:
           2.4e-12) */
        CHECK_REL(AT(a->opose, c, i), AT(a->pose, c, i), 1e-10, 1.0,
                  "round trip pose[%d] of point %d", c, i);
      }
    }
  }
  /* a non-finite guess is that point's error, not a silent cold start */
  a->guess[5] = (double)NAN;
  in.guess = a->guess;
  assert_int_equal(rps3_fk_batch(&m, db, &in, &out), RPS3_OK);
  assert_int_equal(a->status[5], RPS3_EINVAL);
  assert_true(isnan(AT(a->opose, 0, 5)));
  rps3_data_free(db);
  rps3_data_free(dl);
  free(a);
}

/* invalid calls compute nothing and say why */
static void call_errors(void **state) {
  rps3_model m, raw;
  rps3_data *d = NULL;
  double pose[3] = {0.37, 0.11, 0.27}, rates[3] = {0.1, 0.2, 0.3};
  int status[1] = {12345};
  rps3_batch_in in;
  rps3_batch_out out;
  (void)state;
  model_entropy(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  memset(&in, 0, sizeof(in));
  memset(&out, 0, sizeof(out));
  in.n = 1;
  in.pose = pose;
  in.dpose = rates;
  in.ddpose = rates;
  out.status = status;

  assert_int_equal(rps3_inverse_batch(&m, NULL, &in, &out), RPS3_EINVAL);
  assert_int_equal(rps3_inverse_batch(&m, d, NULL, &out), RPS3_EINVAL);
  assert_int_equal(rps3_inverse_batch(&m, d, &in, NULL), RPS3_EINVAL);
  raw = m;
  raw.valid = 0;
  assert_int_equal(rps3_inverse_batch(&raw, d, &in, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "not initialised"));
  /* rates needed (all effects) but absent */
  in.ddpose = NULL;
  assert_int_equal(rps3_inverse_batch(&m, d, &in, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "ddpose"));
  in.ddpose = rates;
  out.status = NULL;
  assert_int_equal(rps3_ik_batch(&m, d, &in, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "status"));
  out.status = status;
  assert_int_equal(rps3_fk_batch(&m, d, &in, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "in.l"));
  in.n = (size_t)-1 / 2;
  assert_int_equal(rps3_inverse_batch(&m, d, &in, &out), RPS3_EINVAL);
  assert_non_null(strstr(d->err.msg, "too large"));
  assert_int_equal(status[0], 12345); /* nothing computed */

  /* an empty batch is a valid call */
  in.n = 0;
  in.pose = NULL;
  assert_int_equal(rps3_inverse_batch(&m, d, &in, &out), RPS3_OK);
  assert_int_equal((int)out.nfail, 0);
  assert_int_equal((int)out.first_fail, 0);
  rps3_data_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(closed_form_lagrange),
      cmocka_unit_test(closed_form_newton_euler),
      cmocka_unit_test(multiroot_lagrange),
      cmocka_unit_test(static_without_rates),
      cmocka_unit_test(ik_and_fk_like_loop),
      cmocka_unit_test(call_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
