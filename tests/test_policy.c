/*
 * test_policy.c - the one singularity policy (src/policy.h): each measure
 * against its two thresholds, taken from the model's options, and the
 * same decision and message from every stage that measures one (the
 * inverse dynamics, the rate stages, the batch with and without its
 * kernel, the forward dynamics).  The expected messages are written out
 * here from the options, not read from the library.
 */
#include "testutil.h"

#include "policy.h"

/* options of high entropy, each threshold its own */
static void odd_limits(rps3_model *m) {
  rps3_model_default(m);
  m->opt.cond_warn = 2.385e5;
  m->opt.cond_max = 3.71e11;
  m->opt.trans_warn = 37.25;
  m->opt.trans_max = 4.13e6;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

/* one step of relative size 1e-12 above x: far above the rounding of
   the comparisons (exact), far below anything a test reads otherwise */
#define ABOVE(x) ((x) * (1.0 + 1e-12))

/* the message msg starts with the literal lit */
#define STARTS(msg, lit) (strncmp((msg), lit, sizeof(lit) - 1) == 0)

static void each_measure_at_its_thresholds(void **state) {
  static const struct {
    int measure, warn_bit;
    const char *what, *max_name;
  } meas[] = {
      {RPS3_SING_LAMBDA, RPS3_WARN_ILLCOND,
       "condition number of the lambda system (df/dtheta)^T", "cond_max"},
      {RPS3_SING_JT, 0, "condition number of df/dtheta", "cond_max"},
      {RPS3_SING_TRANS, RPS3_WARN_TRANS, "force transmission", "trans_max"},
      {RPS3_SING_MQ, 0, "condition number of Mq", "cond_max"},
  };
  rps3_model m;
  rps3_data *d;
  size_t k;
  (void)state;
  odd_limits(&m);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (k = 0; k < sizeof(meas) / sizeof(meas[0]); k++) {
    const int q = meas[k].measure;
    const int trans = q == RPS3_SING_TRANS;
    const double warn = !meas[k].warn_bit ? (trans ? m.opt.trans_max
                                                   : m.opt.cond_max)
                        : trans           ? m.opt.trans_warn
                                          : m.opt.cond_warn;
    const double max = trans ? m.opt.trans_max : m.opt.cond_max;
    const double bad[] = {ABOVE(max), HUGE_VAL, (double)NAN, -1.0};
    char want[sizeof(d->err.msg)];
    size_t b;
    /* silent up to the warning threshold */
    d->warn = 0;
    assert_int_equal(rps3_sing_check(&m, d, q, 0.0), RPS3_OK);
    assert_int_equal(rps3_sing_check(&m, d, q, 0.5 * warn), RPS3_OK);
    assert_int_equal(rps3_sing_check(&m, d, q, warn), RPS3_OK);
    assert_int_equal(d->warn, 0);
    /* the warning bit above it, the result kept up to the hard limit
       (a measure without a warning: the two are one) */
    if (meas[k].warn_bit) {
      assert_int_equal(rps3_sing_check(&m, d, q, ABOVE(warn)), RPS3_OK);
      assert_int_equal(d->warn, meas[k].warn_bit);
      d->warn = 0;
      assert_int_equal(rps3_sing_check(&m, d, q, max), RPS3_OK);
      assert_int_equal(d->warn, meas[k].warn_bit);
    }
    /* refused above it, and for what is no measure */
    for (b = 0; b < sizeof(bad) / sizeof(bad[0]); b++) {
      d->err.msg[0] = '\0';
      assert_int_equal(rps3_sing_check(&m, d, q, bad[b]), RPS3_ESING);
      assert_int_equal(d->err.code, RPS3_ESING);
      assert_true(STARTS(d->err.msg, "singular configuration: "));
      if (bad[b] == HUGE_VAL && !trans) {
        assert_non_null(strstr(d->err.msg, " is singular "));
        continue;
      }
      snprintf(want, sizeof(want), "singular configuration: %s %.3g above %s %.3g",
               meas[k].what, bad[b], meas[k].max_name, max);
      assert_true(strncmp(d->err.msg, want, strlen(want)) == 0);
    }
  }
  rps3_data_free(d);
}

/* the batch kernels keep a point only below the lower threshold of each
   measure, less their margin */
static void certificate_below_every_threshold(void **state) {
  rps3_model m;
  double c, t;
  (void)state;
  odd_limits(&m);
  rps3_sing_certify_limits(&m, 1e-6, &c, &t);
  assert_true(c == m.opt.cond_warn * (1.0 - 1e-6));
  assert_true(t == m.opt.trans_warn * (1.0 - 1e-6));
  /* warn = max: the hard limit is the lower one */
  m.opt.cond_warn = m.opt.cond_max = 7.5e3;
  m.opt.trans_warn = m.opt.trans_max = 12.5;
  rps3_sing_certify_limits(&m, 0.0, &c, &t);
  assert_true(c == 7.5e3 && t == 12.5);
}

/* a pose of the paper's platform, tilted, with rates */
static void set_pose(rps3_data *d) {
  d->pose[0] = 0.35;
  d->pose[1] = 0.27;
  d->pose[2] = 0.28;
  d->dpose[0] = 0.3;
  d->dpose[1] = -0.2;
  d->dpose[2] = 0.05;
  d->ddpose[0] = 0.1;
  d->ddpose[1] = 0.4;
  d->ddpose[2] = -0.3;
}

/*
 * The limits moved onto one point's own measures: rps3_inverse, the batch
 * (kernel and scalar path) and the joint-rate stage refuse it with the
 * policy's message, and keep it just above them with the warning bits.
 */
static void every_stage_the_same_decision(void **state) {
  rps3_model m;
  rps3_data *d, *e;
  double cond, trans, F[3], st_cond[1], st_trans[1];
  int status[1], warn[1], v;
  char want[sizeof(d->err.msg)];
  rps3_batch_in in;
  rps3_batch_out out;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &e), RPS3_OK);
  set_pose(d);
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  assert_int_equal(d->warn & (RPS3_WARN_ILLCOND | RPS3_WARN_TRANS), 0);
  cond = d->cond;
  trans = d->transmission;
  assert_true(cond > 1.0 && trans > 1.0);

  memset(&in, 0, sizeof(in));
  in.n = 1;
  in.pose = d->pose;
  in.dpose = d->dpose;
  in.ddpose = d->ddpose;
  memset(&out, 0, sizeof(out));
  out.status = status;
  out.warn = warn;
  out.F = F;
  out.cond = st_cond;
  out.transmission = st_trans;

  for (v = 0; v < 2; v++) {
    /* with and without the certificate: the kernel's two instances
       (theta and the energy rate, or the forces alone) */
    m.opt.outputs = v ? RPS3_OUT_ALL : RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
    /* the lambda system's condition number just above cond_max */
    m.opt.cond_warn = m.opt.cond_max = cond / ABOVE(1.0);
    m.opt.trans_warn = m.opt.trans_max = 1e8;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    snprintf(want, sizeof(want),
             "singular configuration: condition number of the lambda "
             "system (df/dtheta)^T %.3g above cond_max %.3g",
             cond, m.opt.cond_max);
    assert_int_equal(rps3_inverse(&m, d), RPS3_ESING);
    assert_string_equal(d->err.msg, want);
    assert_int_equal(rps3_inverse_batch(&m, e, &in, &out), RPS3_OK);
    assert_int_equal(status[0], RPS3_ESING);
    assert_non_null(strstr(e->err.msg, want));
    /* cond_max just above it: kept, with RPS3_WARN_ILLCOND */
    m.opt.cond_max = ABOVE(cond);
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
    assert_int_equal(d->warn & RPS3_WARN_ILLCOND, RPS3_WARN_ILLCOND);
    assert_int_equal(rps3_inverse_batch(&m, e, &in, &out), RPS3_OK);
    assert_int_equal(status[0], RPS3_OK);
    assert_int_equal(warn[0] & RPS3_WARN_ILLCOND, RPS3_WARN_ILLCOND);

    /* the transmission just above trans_max */
    m.opt.cond_warn = 1e6;
    m.opt.cond_max = 1e13;
    m.opt.trans_warn = m.opt.trans_max = trans / ABOVE(1.0);
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    snprintf(want, sizeof(want),
             "singular configuration: force transmission %.3g above "
             "trans_max %.3g: an actuator would carry that many times the "
             "load on the platform", trans, m.opt.trans_max);
    assert_int_equal(rps3_inverse(&m, d), RPS3_ESING);
    assert_string_equal(d->err.msg, want);
    assert_int_equal(rps3_inverse_batch(&m, e, &in, &out), RPS3_OK);
    assert_int_equal(status[0], RPS3_ESING);
    assert_non_null(strstr(e->err.msg, want));
    m.opt.trans_max = ABOVE(trans);
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
    assert_int_equal(d->warn & RPS3_WARN_TRANS, RPS3_WARN_TRANS);
    assert_int_equal(rps3_inverse_batch(&m, e, &in, &out), RPS3_OK);
    assert_int_equal(status[0], RPS3_OK);
    assert_int_equal(warn[0] & RPS3_WARN_TRANS, RPS3_WARN_TRANS);
  }
  m.opt.outputs = RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;

  /* the joint-rate stage: df/dtheta's condition number is the lambda
     system's transpose's, the same matrix; refused above cond_max */
  m.opt.trans_warn = 100.0;
  m.opt.trans_max = 1e8;
  m.opt.cond_warn = m.opt.cond_max = cond / 1.5;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  e->pose[0] = d->pose[0];
  e->pose[1] = d->pose[1];
  e->pose[2] = d->pose[2];
  assert_int_equal(rps3_ik(&m, e), RPS3_OK);
  e->dl[0] = 0.01;
  e->dl[1] = -0.02;
  e->dl[2] = 0.015;
  assert_int_equal(rps3_joint_velocity(&m, e), RPS3_ESING);
  assert_true(STARTS(e->err.msg, "singular configuration: condition "
                                  "number of df/dtheta "));
  assert_non_null(strstr(e->err.msg, "above cond_max"));
  rps3_data_free(d);
  rps3_data_free(e);
}

/* the forward dynamics: the same policy on the same point, from the
   lengths (cond_max below the point's: the message names the condition
   number of df/dtheta); it has no transmission to measure */
static void forward_dynamics_the_same_decision(void **state) {
  rps3_model m;
  rps3_data *d, *f;
  double cond;
  int i;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &f), RPS3_OK);
  set_pose(d);
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  cond = d->cond;
  for (i = 0; i < 3; i++) {
    f->l[i] = d->l[i];
    f->theta[i] = d->theta[i];
    f->dl[i] = d->dl[i];
    f->F[i] = d->F[i];
  }
  f->have_theta = 1;
  assert_int_equal(rps3_fwddyn(&m, f), RPS3_OK);
  assert_int_equal(f->warn & (RPS3_WARN_ILLCOND | RPS3_WARN_TRANS), 0);

  m.opt.cond_warn = m.opt.cond_max = cond / 1.5;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_fwddyn(&m, f), RPS3_ESING);
  assert_true(STARTS(f->err.msg, "singular configuration: condition "
                                  "number of df/dtheta "));
  assert_non_null(strstr(f->err.msg, "above cond_max"));

  rps3_data_free(d);
  rps3_data_free(f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(each_measure_at_its_thresholds),
      cmocka_unit_test(certificate_below_every_threshold),
      cmocka_unit_test(every_stage_the_same_decision),
      cmocka_unit_test(forward_dynamics_the_same_decision),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
